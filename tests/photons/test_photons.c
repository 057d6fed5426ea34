/* tests/photons/test_photons.c - photon mapping (photons/photons.h) on the
 * GPU (lavapipe without one), against independent values: the power every
 * light type emits (closed forms and a quadrature written here), a diffuse
 * furnace's analytic radiance, the path tracer's caustic under a glass
 * slab, and the progressive estimate's error falling with the passes. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "photons/photons.h"
#include "render/gpu.h" /* vx_gpu.messenger: the validation layer reports */
#include "tests/gpu_test.h"
#include "tests/probes/probe_scenes.h"
#include "tests/test.h"

static const double PI = 3.14159265358979323846;
static vx_gpu* gpu;


/* gray 0x80: the walls' albedo */
#define GRAY 0xFF808080u
static const double ALB = 128.0 / 255.0;

typedef struct run {
    vx_render_scene* rs;
    vx_photon_gi* pg;
    vx_gi_method gm;
} run;

static bool run_make(run* R, const vx_svo_scene* s, const vx_probe_set* light, const vx_photon_desc* d) {
    vx_error err = {0};
    memset(R, 0, sizeof *R);
    vx_result r = vx_render_scene_create(gpu, s, &R->rs, &err);
    if (!r) r = vx_photon_gi_create(R->rs, s, light, d, &R->gm, &R->pg, &err);
    if (r) fprintf(stderr, "  photons: %s\n", err.msg);
    return r == VX_OK;
}
static void run_free(run* R) {
    vx_photon_gi_destroy(R->pg);
    vx_render_scene_destroy(R->rs);
}

/* Stored power after one pass (first surface, all) and the pass's stats. */
static bool pass_power(run* R, double first[3], double all[3], vx_photon_stats* st) {
    vx_render_desc base = {.width = 4, .height = 4};
    vx_render_image im = {0};
    vx_error err = {0};
    vx_result r = vx_photon_render(R->pg, &base, 1, false, &im, &err);
    if (!r) r = vx_photon_power(R->pg, first, all, &err);
    if (r) fprintf(stderr, "  photons: %s\n", err.msg);
    vx_render_image_free(&im);
    vx_photon_last_stats(R->pg, st);
    return r == VX_OK;
}

/* The photons' image of scene s under light and d through view, the mean of `passes` passes (full: the
 * whole radiance, else the indirect light), the method made and freed here; st (may be NULL) gets the
 * last pass's stats. */
static bool photon_image(const vx_svo_scene* s, const vx_probe_set* light, const vx_photon_desc* d,
                         const vx_render_desc* view, uint32_t passes, bool full, vx_render_image* out, vx_photon_stats* st) {
    run R;
    if (!run_make(&R, s, light, d)) return false;
    vx_error err = {0};
    vx_result r = vx_photon_render(R.pg, view, passes, full, out, &err);
    if (r) fprintf(stderr, "  photons: %s\n", err.msg);
    if (st) vx_photon_last_stats(R.pg, st);
    run_free(&R);
    return r == VX_OK;
}

/* A w x h view straight down (ortho, 2 hh high) onto (cx, cy, 1) from height ez; +x right, +y up. */
static vx_render_desc view_down(uint32_t w, uint32_t h, double cx, double cy, double hh, double ez) {
    vx_render_desc v = {.width = w, .height = h};
    v.camera.set = true, v.camera.ortho = true, v.camera.ortho_height = 2 * hh;
    v.camera.eye[0] = cx, v.camera.eye[1] = cy, v.camera.eye[2] = ez;
    v.camera.target[0] = cx, v.camera.target[1] = cy, v.camera.target[2] = 1;
    v.camera.up[1] = 1;
    return v;
}

/* A spot light's power over colour * intensity: 2 pi times the integral of
 * the glTF falloff squared over cos theta, by Simpson's rule in theta. */
static double spot_power(double inner, double outer) {
    enum { N = 20000 };
    double ci = cos(inner), co = cos(outer), s = 0, h = outer / N;
    for (int i = 0; i <= N; i++) {
        double t = i * h, c = cos(t), f = (c - co) / (ci - co);
        f = f < 0 ? 0 : (f > 1 ? 1 : f);
        s += (i == 0 || i == N ? 1 : (i % 2 ? 4 : 2)) * f * f * sin(t);
    }
    return 2 * PI * s * h / 3;
}

/* Emission: inside a closed gray box every photon lands on a wall, so the
 * power stored at the photons' first surfaces is the lights' power; with
 * Russian roulette keeping the power of survivors, all stored power is the
 * geometric series power / (1 - albedo). */
static void test_emission_power(void) {
    if (!gpu) SKIP("no Vulkan device");
    vx_svo_scene s;
    box_scene(&s, 16, 1);
    s.palette[1] = GRAY;
    double black[3] = {0, 0, 0};
    vx_probe_set light = light_only(0, black, 1);
    const double col[3] = {1, 0.5, 0.25};
    vx_light L[4] = {
        {.type = VX_LIGHT_POINT, .position = {8, 8, 8}, .intensity = 2},
        {.type = VX_LIGHT_SPOT, .position = {8, 8, 12}, .direction = {0, 0, -1}, .intensity = 3, .inner_cone = 0.3,
         .outer_cone = 0.6},
        {.type = VX_LIGHT_SPHERE, .position = {8, 8, 8}, .intensity = 0.5, .radius = 1},
        {.type = VX_LIGHT_RECT, .position = {8, 8, 13}, .direction = {0, 0, -1}, .tangent = {1, 0, 0}, .intensity = 0.7,
         .size = {2, 3}},
    };
    double expect[4] = {4 * PI * 2, 3 * spot_power(0.3, 0.6), 0.5 * PI * 4 * PI, 0.7 * PI * 6};
    const char* names[4] = {"point", "spot", "sphere", "rect"};
    for (int i = 0; i < 4; i++) {
        memcpy(L[i].color, col, sizeof col);
        vx_photon_desc d = {.photons = 100000, .bounces = 100, .capacity = 1000000, .lights = &L[i], .light_count = 1};
        run R;
        REQUIRE(run_make(&R, &s, &light, &d));
        double first[3], all[3];
        vx_photon_stats st;
        REQUIRE(pass_power(&R, first, all, &st));
        CHECK(st.dropped == 0 && st.emitted == 100000);
        for (int k = 0; k < 3; k++) {
            double e = expect[i] * col[k];
            fprintf(stderr, "  %-6s ch %d: first %.5g all %.5g, expected %.5g and %.5g\n", names[i], k, first[k], all[k],
                    e, e / (1 - ALB));
            /* the spot's photons carry its falloff: statistical; the others' exact up to float sums */
            CHECK(fabs(first[k] / e - 1) < (i == 1 ? 0.01 : 1e-3));
            CHECK(fabs(all[k] * (1 - ALB) / e - 1) < 0.02);
        }
        run_free(&R);
    }
    vx_svo_scene_free(&s);
}

/* a 2 x 2 x 2 emissive block (palette 9) on the floor of a closed gray box */
static uint8_t block_cell(uint32_t x, uint32_t y, uint32_t z, uint32_t n) {
    if (!x || !y || !z || x == n - 1 || y == n - 1 || z == n - 1) return 1;
    return x >= 7 && x <= 8 && y >= 7 && y <= 8 && z <= 2 ? 9 : 0;
}
/* a floor slab in the open */
static uint8_t slab_cell(uint32_t x, uint32_t y, uint32_t z, uint32_t n) {
    (void)x, (void)y, (void)n;
    return z == 0 ? 1 : 0;
}

/* Emissive voxels emit from their visible faces only (the block's bottom
 * lies on the floor, its inner faces touch each other: 20 unit faces); the
 * sun's photons land on the slab's top (irradiance times area); the sky's on
 * every face of the slab (a uniform sky gives pi L on any face). */
static void test_emission_voxels_sun_sky(void) {
    if (!gpu) SKIP("no Vulkan device");
    vx_svo_scene s;
    cells_scene(&s, 16, block_cell);
    s.palette[1] = GRAY, s.palette[9] = GRAY;
    const char* kv[] = {"_type", "_emit", "_emit", "2"};
    add_material(&s, 9, kv, 2);
    double black[3] = {0, 0, 0}, sky[3] = {0.3, 0.2, 0.1};
    vx_probe_set light = light_only(0, black, 1);
    vx_photon_desc d = {.photons = 200000, .capacity = 2000000};
    run R;
    double first[3], all[3];
    vx_photon_stats st;
    REQUIRE(run_make(&R, &s, &light, &d));
    REQUIRE(pass_power(&R, first, all, &st));
    run_free(&R);
    vx_svo_scene_free(&s);
    for (int k = 0; k < 3; k++) {
        double e = PI * ALB * 2 * 20;
        fprintf(stderr, "  voxels: first %.5g expected %.5g\n", first[k], e);
        CHECK(fabs(first[k] / e - 1) < 0.02);
    }
    cells_scene(&s, 16, slab_cell);
    s.palette[1] = GRAY;
    for (int sun = 1; sun >= 0; sun--) {
        light = light_only(sun ? 2 : 0, sun ? black : sky, 1);
        REQUIRE(run_make(&R, &s, &light, &d));
        REQUIRE(pass_power(&R, first, all, &st));
        run_free(&R);
        for (int k = 0; k < 3; k++) {
            double e = sun ? 2 * 16 * 16 : PI * sky[k] * (2 * 16 * 16 + 4 * 16);
            fprintf(stderr, "  %s: first %.5g expected %.5g\n", sun ? "sun" : "sky", first[k], e);
            CHECK(fabs(first[k] / e - 1) < 0.02);
        }
    }
    vx_svo_scene_free(&s);
}

/* a 4 x 3 x 2 emissive block (palette 9) on the floor of a closed box */
static uint8_t block432_cell(uint32_t x, uint32_t y, uint32_t z, uint32_t n) {
    if (!x || !y || !z || x == n - 1 || y == n - 1 || z == n - 1) return 1;
    return x >= 6 && x <= 9 && y >= 6 && y <= 8 && z <= 2 ? 9 : 0;
}

/* Photons leave the exposed faces of emissive voxels only: a 4 x 3 x 2
 * block on the floor has 144 voxel faces of which 40 are exposed (the top,
 * 12, and the sides, 28; the bottom lies on the floor, the rest touch each
 * other). In a box of black walls every photon is stored once, where it
 * lands: so the photons stored equal the photons emitted (a photon sent from
 * a buried face, as before, is lost: 72% of them here), and the stored power
 * is the exposed area times the radiance times pi (each photon carries the
 * same power: exact but for the few below). */
static void test_emission_exposed_faces(void) {
    if (!gpu) SKIP("no Vulkan device");
    vx_svo_scene s;
    cells_scene(&s, 16, block432_cell);
    s.palette[1] = 0xFF000000u, s.palette[9] = GRAY;
    const char* kv[] = {"_type", "_emit", "_emit", "2"};
    add_material(&s, 9, kv, 2);
    double black[3] = {0, 0, 0};
    vx_probe_set light = light_only(0, black, 1);
    vx_photon_desc d = {.photons = 100000, .capacity = 1000000};
    run R;
    double first[3], all[3];
    vx_photon_stats st;
    REQUIRE(run_make(&R, &s, &light, &d));
    REQUIRE(pass_power(&R, first, all, &st));
    run_free(&R);
    vx_svo_scene_free(&s);
    fprintf(stderr, "  exposed faces: %llu photons emitted, %llu stored\n", (unsigned long long)st.emitted,
            (unsigned long long)st.stored);
    /* all but a few: a photon leaving a face's edge at a grazing angle that meets the neighbouring
     * surface within 0.002 cells is taken for one from a face against another model's voxel and
     * dropped (photon.comp emit; 16 of 100000 here) */
    CHECK(st.emitted == 100000 && st.stored <= st.emitted && st.stored >= 0.999 * st.emitted);
    for (int k = 0; k < 3; k++) {
        double e = PI * ALB * 2 * 40;
        fprintf(stderr, "  exposed faces: power %.6g, expected %.6g\n", first[k], e);
        CHECK(fabs(first[k] / e - 1) < 1e-3 && fabs(all[k] / e - 1) < 1e-3);
    }
}

/* two emissive blocks of unequal power in the two halves of a black box
 * parted by a wall at x = 8: A (palette 9) 2 x 2 x 2 at the left, B
 * (palette 10) 1 x 2 x 2 at the right */
static uint8_t two_blocks_cell(uint32_t x, uint32_t y, uint32_t z, uint32_t n) {
    if (!x || !y || !z || x == n - 1 || y == n - 1 || z == n - 1 || x == 8) return 1;
    if (y >= 7 && y <= 8 && z >= 7 && z <= 8) return x >= 3 && x <= 4 ? 9 : (x == 11 ? 10 : 0);
    return 0;
}

/* Photons pick the emitting faces by power (the alias table of photons.c):
 * the power stored in each half of the parted box is its block's, A's 24
 * faces of emission 1 against B's 16 of emission 3 (a power twice A's),
 * within 1.5% at 200k photons (the total alone cannot tell: every photon
 * carries the same power whichever face it leaves). */
static void test_emission_by_power(void) {
    if (!gpu) SKIP("no Vulkan device");
    vx_svo_scene s;
    cells_scene(&s, 16, two_blocks_cell);
    s.palette[1] = 0xFF000000u, s.palette[9] = GRAY, s.palette[10] = GRAY;
    const char* ka[] = {"_type", "_emit", "_emit", "1"};
    const char* kb[] = {"_type", "_emit", "_emit", "3"};
    add_material(&s, 9, ka, 2);
    add_material(&s, 10, kb, 2);
    double black[3] = {0, 0, 0};
    vx_probe_set light = light_only(0, black, 1);
    vx_photon_desc d = {.photons = 200000, .capacity = 1000000};
    run R;
    double first[3], all[3];
    vx_photon_stats st;
    REQUIRE(run_make(&R, &s, &light, &d));
    bool ok = pass_power(&R, first, all, &st);
    vx_photon_record* ph = NULL;
    size_t n = 0;
    vx_error err = {0};
    if (ok && vx_photon_stored(R.pg, &ph, &n, &err)) fprintf(stderr, "  photons: %s\n", err.msg), ok = false;
    run_free(&R);
    vx_svo_scene_free(&s);
    REQUIRE(ok);
    double side[2] = {0, 0};
    for (size_t i = 0; i < n; i++) side[ph[i].position[0] > 8.5] += ph[i].power[1];
    double ea = PI * ALB * 1 * 24, eb = PI * ALB * 3 * 16;
    fprintf(stderr, "  by power: left %.5g (expected %.5g), right %.5g (expected %.5g) of %zu photons\n", side[0], ea,
            side[1], eb, n);
    CHECK(n > 190000);
    CHECK(fabs(side[0] / ea - 1) < 0.015 && fabs(side[1] / eb - 1) < 0.015);
    vx_free(NULL, ph);
}

/* A gradient sky (zenith c, horizon h, ground g) by direction: the power
 * its photons leave at the slab's first surfaces is the closed form of its
 * irradiance on each face times the area: top pi (h + 2c) / 3, bottom pi g,
 * a side pi (g / 2 + h / 2 + (c - h) 2 / (3 pi)). */
static void test_sky_gradient_power(void) {
    if (!gpu) SKIP("no Vulkan device");
    vx_svo_scene s;
    cells_scene(&s, 16, slab_cell);
    s.palette[1] = GRAY;
    double black[3] = {0, 0, 0};
    vx_probe_set light = light_only(0, black, 1);
    vx_sky grad = {.type = VX_SKY_GRADIENT, .color = {0.2, 0.4, 1.0}, .horizon = {0.9, 0.8, 0.7}, .ground = {0.3, 0.2, 0.1}};
    vx_photon_desc d = {.photons = 400000, .capacity = 4000000, .sky_dir = &grad};
    run R;
    double first[3], all[3];
    vx_photon_stats st;
    REQUIRE(run_make(&R, &s, &light, &d));
    CHECK(R.gm.sky_dir && R.gm.sky_dir->type == VX_SKY_GRADIENT);
    REQUIRE(pass_power(&R, first, all, &st));
    run_free(&R);
    for (int k = 0; k < 3; k++) {
        double c = grad.color[k], h = grad.horizon[k], g = grad.ground[k];
        double e = 256 * PI * (h + 2 * c) / 3 + 256 * PI * g + 64 * PI * (g / 2 + h / 2 + (c - h) * 2 / (3 * PI));
        fprintf(stderr, "  gradient sky: first %.5g expected %.5g\n", first[k], e);
        CHECK(fabs(first[k] / e - 1) < 0.02);
    }
    vx_svo_scene_free(&s);
}

static double mean_rgb(const vx_render_image* im) {
    double m = 0;
    size_t n = (size_t)im->width * im->height;
    for (size_t i = 0; i < n; i++) m += im->pixels[4 * i] + im->pixels[4 * i + 1] + im->pixels[4 * i + 2];
    return m / (3.0 * n);
}

/* The diffuse furnace: a closed box whose walls (albedo a) all emit Le. The
 * radiance inside is Le / (1 - a) everywhere; the gi a wall sends (all but
 * its own emission) is a Le / (1 - a). Within 2% at 8 passes of 200k
 * photons (the walls' emission is not a direct-pass light, so every photon
 * counts). */
static void test_furnace(void) {
    if (!gpu) SKIP("no Vulkan device");
    vx_svo_scene s;
    box_scene(&s, 16, 1);
    s.palette[1] = GRAY;
    const char* kv[] = {"_type", "_emit", "_emit", "1"};
    add_material(&s, 1, kv, 2);
    double black[3] = {0, 0, 0};
    vx_probe_set light = light_only(0, black, 1);
    vx_photon_desc d = {.photons = 200000, .radius = 1, .alpha = 1, .bounces = 64, .capacity = 2000000};
    run R;
    REQUIRE(run_make(&R, &s, &light, &d));
    vx_render_desc base = {.width = 16, .height = 16};
    base.camera.set = true, base.camera.fov = 30;
    base.camera.eye[0] = 8, base.camera.eye[1] = 8, base.camera.eye[2] = 8;
    base.camera.target[0] = 8, base.camera.target[1] = 8, base.camera.target[2] = 1;
    base.camera.up[1] = 1;
    double Le = ALB * 1, expect = ALB * Le / (1 - ALB);
    for (int fg = 0; fg < 2; fg++) {
        /* and with a final gather: the walls' emission and photons one bounce further */
        if (fg) {
            run_free(&R);
            d.final_gather = 16, d.photons = 40000; /* llvmpipe's loop guard counts the gather's photons */
            REQUIRE(run_make(&R, &s, &light, &d));
        }
        vx_render_image im = {0};
        vx_error err = {0};
        vx_result r = vx_photon_render(R.pg, &base, fg ? 4 : 8, false, &im, &err);
        if (r) fprintf(stderr, "  %s\n", err.msg);
        REQUIRE(r == VX_OK);
        double m = mean_rgb(&im);
        fprintf(stderr, "  furnace%s: gi %.5f, analytic %.5f (%.2f%%)\n", fg ? " (final gather)" : "", m, expect,
                100 * (m / expect - 1));
        CHECK(fabs(m / expect - 1) < 0.02);
        vx_render_image_free(&im);
    }
    run_free(&R);
    vx_svo_scene_free(&s);
}

/* ---- a caustic: a glass slab (IOR 1.5) under a sphere light over a floor --------------- */

static uint8_t glass_cell(uint32_t x, uint32_t y, uint32_t z, uint32_t n) {
    (void)n;
    if (z == 0) return 1;
    if (z >= 4 && z <= 5 && x >= 4 && x < 12 && y >= 4 && y < 12) return 2;
    return 0;
}

static double rel_mse(const vx_render_image* a, const vx_render_image* ref) {
    double se = 0, r2 = 0;
    for (size_t i = 0; i < (size_t)ref->width * ref->height; i++)
        for (int c = 0; c < 3; c++) {
            double e = (double)a->pixels[4 * i + c] - ref->pixels[4 * i + c];
            se += e * e, r2 += (double)ref->pixels[4 * i + c] * ref->pixels[4 * i + c];
        }
    return r2 > 0 ? se / r2 : INFINITY;
}

static vx_svo_scene caustic;
static vx_light caustic_light = {.type = VX_LIGHT_SPHERE, .position = {8, 15, 10}, .color = {1, 1, 1},
                                 .intensity = 4, .radius = 2};
static vx_render_image caustic_ref, caustic_ref2; /* the path tracer, two seeds */
static vx_render_desc caustic_view;

static bool caustic_setup(void) {
    if (caustic_ref.pixels) return true;
    cells_scene(&caustic, 16, glass_cell);
    caustic.palette[1] = GRAY, caustic.palette[2] = 0xFFFFFFFFu;
    const char* kv[] = {"_type", "_glass", "_ri", "1.5", "_rough", "0"};
    add_material(&caustic, 2, kv, 3);
    /* straight down on the slab: every pixel sees the floor through the glass */
    caustic_view = view_down(24, 24, 8, 8, 3.5, 40);
    double black[3] = {0, 0, 0};
    vx_probe_set light = light_only(0, black, 6);
    vx_render_scene* rs = NULL;
    vx_error err = {0};
    vx_result r = vx_render_scene_create(gpu, &caustic, &rs, &err);
    for (int k = 0; k < 2 && !r; k++) {
        vx_probe_render_desc d = {.base = &caustic_view, .mode = VX_PROBE_RENDER_PT_INDIRECT, .spp = 2048,
                                  .seed = 11 + (uint64_t)k, .lights = &caustic_light, .light_count = 1,
                                  .pixel_centre = true};
        r = vx_probe_render_gpu(rs, &caustic, &light, &d, k ? &caustic_ref2 : &caustic_ref, &err);
    }
    vx_render_scene_destroy(rs);
    if (r) fprintf(stderr, "  path tracer: %s\n", err.msg);
    return r == VX_OK;
}

static bool caustic_photons(uint32_t photons, uint32_t passes, double radius, vx_render_image* out) {
    /* the slab's faces are flat: its caustic is smooth, one radius for both maps */
    double black[3] = {0, 0, 0};
    vx_probe_set light = light_only(0, black, 6);
    vx_photon_desc d = {.photons = photons, .radius = radius, .caustic_radius = radius, .lights = &caustic_light,
                        .light_count = 1};
    return photon_image(&caustic, &light, &d, &caustic_view, passes, false, out, NULL);
}

/* Through the slab the floor gets the light only by refraction: the path
 * tracer finds it with BSDF rays that cross the glass and meet the light,
 * the photons as caustic photons. The photon image matches the reference
 * (mean of two 2048-spp path-traced images, whose own noise adds about 0.01)
 * within a relMSE of 0.03; the
 * reference's own noise is printed (the relMSE between its two seeds). */
static void test_caustic(void) {
    if (!gpu) SKIP("no Vulkan device");
    REQUIRE(caustic_setup());
    vx_render_image im = {0};
    REQUIRE(caustic_photons(400000, 8, 0.6, &im));
    double noise = rel_mse(&caustic_ref2, &caustic_ref);
    vx_render_image ref = caustic_ref;
    size_t n = (size_t)ref.width * ref.height * 4;
    float* mean = malloc(n * sizeof(float));
    for (size_t i = 0; i < n; i++) mean[i] = 0.5f * (caustic_ref.pixels[i] + caustic_ref2.pixels[i]);
    ref.pixels = mean;
    double e = rel_mse(&im, &ref), mp = mean_rgb(&im), mr = mean_rgb(&ref);
    fprintf(stderr, "  caustic: mean photons %.5f path tracer %.5f; relMSE %.4f (reference seeds apart %.4f)\n", mp, mr,
            e, noise);
    CHECK(mr > 0.02); /* the caustic is there */
    CHECK(fabs(mp / mr - 1) < 0.05);
    CHECK(e < 0.03);
    free(mean);
    vx_render_image_free(&im);
}

/* Same seed, same image, bitwise: runs of the method made afresh (on
 * lavapipe, the CPU), with and without a final gather: twice with the same
 * settings, and once with another trace layout (workgroups of 128, four
 * photons per invocation; the default here is 64 and one), which stores the
 * same photons in another order: the gather's sums are exact (photons.h),
 * so the image is the same to the bit (with float sums in storage order, as
 * before, that third run differed here; the first two did not: lavapipe
 * stored the photons in the same order both times). Another seed gives
 * another image (the bytes compared do depend on the photons). */
static void test_reproducible(void) {
    if (!gpu) SKIP("no Vulkan device");
    REQUIRE(caustic_setup());
    double black[3] = {0, 0, 0};
    vx_probe_set light = light_only(0, black, 6);
    /* the sphere light and a spot whose falloff gives its photons unequal powers (photons of equal
     * power sum to the same float in any order) */
    vx_light L[2] = {caustic_light, {.type = VX_LIGHT_SPOT, .position = {8, 8, 12}, .direction = {0.1, 0, -1},
                                     .color = {1, 0.7, 0.4}, .intensity = 30, .inner_cone = 0.1, .outer_cone = 0.7}};
    for (int fg = 0; fg < 2; fg++) {
        vx_render_image im[4] = {{0}};
        for (int k = 0; k < 4; k++) {
            vx_photon_desc d = {.photons = 30000, .radius = 0.6, .seed = k == 3 ? 8 : 7, .final_gather = fg ? 4 : 0,
                                .lights = L, .light_count = 2};
            if (k == 2) d.workgroup = 128, d.batch = 4; /* the default at 30k photons: 64 and 1 */
            vx_photon_stats st;
            REQUIRE(photon_image(&caustic, &light, &d, &caustic_view, 3, false, &im[k], &st));
            CHECK(st.dropped == 0 && st.stored > 1000);
        }
        size_t bytes = (size_t)im[0].width * im[0].height * 16;
        size_t differ[2] = {0, 0};
        for (int j = 0; j < 2; j++)
            for (size_t i = 0; i < bytes / 4; i++) differ[j] += memcmp(&im[0].pixels[i], &im[1 + j].pixels[i], 4) != 0;
        double e = rel_mse(&im[3], &im[0]);
        fprintf(stderr, "  %s: %zu of %zu floats differ between two runs, %zu with another trace layout; "
                "another seed: relMSE %.4g\n", fg ? "final gather" : "direct", differ[0], bytes / 4, differ[1], e);
        CHECK(differ[0] == 0 && memcmp(im[0].pixels, im[1].pixels, bytes) == 0);
        CHECK(differ[1] == 0 && memcmp(im[0].pixels, im[2].pixels, bytes) == 0);
        CHECK(e > 1e-4 && mean_rgb(&im[0]) > 0.01);
        for (int k = 0; k < 4; k++) vx_render_image_free(&im[k]);
    }
}

/* A pass whose photons would store more than the capacity keeps photons 0..C-1 by index (photons.h
 * capacity), not those the GPU's atomic counter happened to give slots first: with half the stores'
 * room, runs with the default trace layout twice and with another layout (workgroups of 128, four
 * photons an invocation: lavapipe stores the photons in another order, and before this the photons
 * dropped differed with it) give the same image to the bit. The photons kept carry the whole
 * emission: the first surfaces' stored power matches the pass without a limit within 3% (before:
 * the dropped photons' power was lost, about half of it here), and it is no stand-in for an empty
 * pass: stored at most the capacity, at least the capacity less one photon's stores. */
static void test_overflow_reproducible(void) {
    if (!gpu) SKIP("no Vulkan device");
    REQUIRE(caustic_setup());
    double black[3] = {0, 0, 0};
    vx_probe_set light = light_only(0, black, 6);
    vx_photon_desc d = {.photons = 40000, .radius = 0.6, .seed = 5, .lights = &caustic_light, .light_count = 1};
    vx_render_image im[4] = {{0}};
    double first[4][3], all[4][3];
    vx_photon_stats st[4];
    for (int k = 0; k < 4; k++) {
        if (k == 1) d.capacity = (uint32_t)(st[0].stored / 2);
        d.workgroup = k == 3 ? 128 : 0, d.batch = k == 3 ? 4 : 0;
        run R;
        REQUIRE(run_make(&R, &caustic, &light, &d));
        vx_error err = {0};
        vx_result r = vx_photon_render(R.pg, &caustic_view, 2, false, &im[k], &err);
        if (!r) r = vx_photon_power(R.pg, first[k], all[k], &err);
        if (r) fprintf(stderr, "  photons: %s\n", err.msg);
        vx_photon_last_stats(R.pg, &st[k]);
        run_free(&R);
        REQUIRE(r == VX_OK);
    }
    size_t bytes = (size_t)im[0].width * im[0].height * 16, differ[2] = {0, 0};
    for (int j = 0; j < 2; j++)
        for (size_t i = 0; i < bytes / 4; i++) differ[j] += memcmp(&im[1].pixels[i], &im[2 + j].pixels[i], 4) != 0;
    double ratio = (first[1][0] + first[1][1] + first[1][2]) / (first[0][0] + first[0][1] + first[0][2]);
    fprintf(stderr, "  capacity %u: %llu of %llu photons traced, %llu stored; %zu of %zu floats differ between two runs, "
            "%zu with another trace layout; first-surface power %.4f of the pass without a limit (%llu stored)\n",
            d.capacity, (unsigned long long)st[1].emitted, (unsigned long long)d.photons, (unsigned long long)st[1].stored,
            differ[0], bytes / 4, differ[1], ratio, (unsigned long long)st[0].stored);
    CHECK(st[0].dropped == 0 && st[0].emitted == d.photons && st[0].stored > 2000);
    for (int k = 1; k < 4; k++) {
        CHECK(st[k].dropped > 0 && st[k].emitted + st[k].dropped == d.photons);
        CHECK(st[k].stored <= d.capacity && st[k].stored + 9 > d.capacity);
    }
    CHECK(differ[0] == 0 && memcmp(im[1].pixels, im[2].pixels, bytes) == 0);
    CHECK(differ[1] == 0 && memcmp(im[1].pixels, im[3].pixels, bytes) == 0);
    CHECK(fabs(ratio - 1) < 0.03);
    CHECK(mean_rgb(&im[1]) > 0.01);
    for (int k = 0; k < 4; k++) vx_render_image_free(&im[k]);
}

/* a closed gray box lit by an emissive 2 x 2 panel in its ceiling (palette 9), a glass slab (2) over the
 * floor and a metal block (3) in a corner */
static uint8_t fused_cell(uint32_t x, uint32_t y, uint32_t z, uint32_t n) {
    if (!x || !y || !z || x == n - 1 || y == n - 1 || z == n - 1)
        return z == n - 1 && x >= 7 && x <= 8 && y >= 7 && y <= 8 ? 9 : 1;
    if (z >= 5 && z <= 6 && x >= 4 && x < 12 && y >= 4 && y < 12) return 2;
    return x >= 2 && x <= 3 && y >= 2 && y <= 3 && z <= 3 ? 3 : 0;
}

/* the same with the metal block in palette 4 */
static uint8_t fused_half_cell(uint32_t x, uint32_t y, uint32_t z, uint32_t n) {
    uint8_t c = fused_cell(x, y, z, n);
    return c == 3 ? 4 : c;
}

/* Where the camera's paths need no photon (every sum a Lambert surface's, deferred to the density step),
 * they run in the trace's dispatch, their records after the photons (photons.c run_pass): the image is
 * the one the separate steps give, to the bit. A box lit by emissive voxels with glass and a metal block
 * (metalness 1: no diffuse lobe), the default layout (fused) against workgroups of 128 (which are not),
 * in a plain pass and in passes over the capacity (traced three times: the records must outlive the
 * photons stored after them). A metal of metalness 0.5 has a diffuse lobe whose sums run in the paths:
 * not fused. */
static void test_fused_paths(void) {
    if (!gpu) SKIP("no Vulkan device");
    vx_svo_scene s;
    cells_scene(&s, 16, fused_cell);
    s.palette[1] = GRAY, s.palette[2] = 0xFFFFFFFFu, s.palette[3] = 0xFFE0E0E0u, s.palette[9] = GRAY;
    const char* kg[] = {"_type", "_glass", "_ri", "1.5", "_rough", "0"};
    const char* km[] = {"_type", "_metal", "_metal", "1", "_rough", "0.2"};
    const char* ke[] = {"_type", "_emit", "_emit", "4"};
    add_material(&s, 2, kg, 3);
    add_material(&s, 3, km, 3);
    add_material(&s, 9, ke, 2);
    double black[3] = {0, 0, 0};
    vx_probe_set light = light_only(0, black, 1);
    vx_render_desc view = {.width = 24, .height = 24};
    view.camera.set = true, view.camera.fov = 70;
    view.camera.eye[0] = 8, view.camera.eye[1] = 1.5, view.camera.eye[2] = 11;
    view.camera.target[0] = 8, view.camera.target[1] = 9, view.camera.target[2] = 2;
    view.camera.up[2] = 1;
    size_t bytes = (size_t)view.width * view.height * 16;
    uint32_t capacity = 0;
    for (int over = 0; over < 2; over++) {
        vx_render_image im[2] = {{0}};
        vx_photon_stats st[2];
        for (int k = 0; k < 2; k++) {
            vx_photon_desc d = {.photons = 30000, .radius = 0.6, .seed = 9, .capacity = capacity};
            if (k) d.workgroup = 128, d.batch = 4;
            REQUIRE(photon_image(&s, &light, &d, &view, 2, false, &im[k], &st[k]));
        }
        size_t differ = 0;
        for (size_t i = 0; i < bytes / 4; i++) differ += memcmp(&im[0].pixels[i], &im[1].pixels[i], 4) != 0;
        fprintf(stderr, "  %s: fused %d and %d, %llu stored, %llu dropped; %zu of %zu floats differ; mean %.4f\n",
                over ? "over the capacity" : "plain", st[0].fused, st[1].fused, (unsigned long long)st[0].stored,
                (unsigned long long)st[0].dropped, differ, bytes / 4, mean_rgb(&im[0]));
        CHECK(st[0].fused && !st[1].fused);
        CHECK(over ? st[0].dropped > 0 && st[1].dropped == st[0].dropped : st[0].dropped == 0);
        CHECK(differ == 0 && memcmp(im[0].pixels, im[1].pixels, bytes) == 0);
        CHECK(mean_rgb(&im[0]) > 1e-3 && st[0].stored > 10000);
        capacity = (uint32_t)(st[0].stored / 2);
        for (int k = 0; k < 2; k++) vx_render_image_free(&im[k]);
    }
    vx_svo_scene_free(&s);
    cells_scene(&s, 16, fused_half_cell);
    s.palette[1] = GRAY, s.palette[2] = 0xFFFFFFFFu, s.palette[4] = 0xFFE0E0E0u, s.palette[9] = GRAY;
    const char* kh[] = {"_type", "_metal", "_metal", "0.5", "_rough", "0.2"};
    add_material(&s, 2, kg, 3);
    add_material(&s, 4, kh, 3);
    add_material(&s, 9, ke, 2);
    vx_render_image im = {0};
    vx_photon_stats st;
    vx_photon_desc d = {.photons = 30000, .radius = 0.6, .seed = 9};
    REQUIRE(photon_image(&s, &light, &d, &view, 1, false, &im, &st));
    fprintf(stderr, "  metalness 0.5: fused %d\n", st.fused);
    CHECK(!st.fused);
    vx_render_image_free(&im);
    vx_svo_scene_free(&s);
}

/* the slab with a wall along x = 12..13, 8 cells high: light from the point light bounces off it onto the
 * slab */
static uint8_t slab_wall_cell(uint32_t x, uint32_t y, uint32_t z, uint32_t n) {
    (void)y, (void)n;
    return z == 0 || (x >= 12 && x <= 13 && z <= 8) ? 1 : 0;
}

/* The GPU's gather against a brute-force estimate on the CPU over the same
 * photons (read back with vx_photon_stored): a gray slab lit by a point
 * light, seen straight down (ortho), where each pixel's value is
 * sum (albedo / pi) power / (pi r^2) over the photons within r of the
 * pixel's point on the slab's top whose normal is the top's. The GPU's
 * hashed grid, its 27-cell lookup and the normal test must find exactly
 * those photons: its value lies between the CPU's sums over radius
 * r (1 - 1e-4) and r (1 + 1e-4) (the pixel's point is recomputed here, a
 * photon on the circle's edge goes either way), and where the two agree it
 * equals them to float precision. Two cases: the slab alone in a full
 * image (every photon counts), and the slab with a wall beside it in an
 * image of the indirect light (the photons the point light brought to
 * their first surface, VX_PHOTON_DIRECT, do not count: the density step
 * leaves them out once for the whole tile where all of its pixels ask
 * that), the view kept more than r from the wall and the slab's edges
 * (where the kernel's area is not the disk); and the wall's face seen
 * head-on in a full image (its normal along x: the tile's box of cells
 * is 3 deep and 5 x 5 across, and its cells on the face take the box's
 * last slots, past the 64 the shared loop had before). Two more in full
 * images of the slab and the wall lit from above: straight down across
 * the wall's top (tiles whose points lie 8 apart in depth: boxes of more
 * than 128 cells, a slot each of the cells the pixels need) and along
 * (1, 0, -1) at the wall's foot (tiles with pixels of two normals: the
 * shared loop with each pixel's own tests), each pixel's sum over the
 * photons of its own face; pixels within r of an edge of their face are
 * not checked (so the other face's photons, which the normal test keeps
 * out, lie beyond r of every checked pixel: that test is not what this
 * case checks). */
enum { GATHER_FULL, GATHER_INDIRECT, GATHER_WALL, GATHER_STEP, GATHER_CORNER };
/* The point a pixel (x, y) of a view sees in gather_cpu_case and the face it lies on (0: a top, +z; 1: the
 * wall's face at x = 12, -x); false where the point is within r of its face's edge (the kernel's area is not
 * the disk there) or off the scene: such a pixel is not checked. */
static bool gather_point(int kind, double hh, double cx, int x, int y, int W, int H, double r, double p[3], int* face) {
    double hw = hh * W / H, u = ((x + 0.5) / W) * 2 - 1, vv = 1 - ((y + 0.5) / H) * 2, m = r * (1 + 1e-3);
    *face = 0;
    if (kind == GATHER_WALL) {
        p[0] = 12, p[1] = 8 - u * hw, p[2] = 5 + vv * hh, *face = 1;
        return true;
    }
    if (kind == GATHER_CORNER) {
        /* ortho along (1, 0, -1) / sqrt 2 from (2, 8, 11): right -y, up (1, 0, 1) / sqrt 2; the top z = 1
         * where the ray meets it at x < 12, the wall's face x = 12 above */
        double o[3] = {2 + vv * hh / sqrt(2), 8 - u * hw, 11 + vv * hh / sqrt(2)};
        double xt = o[0] + (o[2] - 1);
        if (xt < 12) {
            p[0] = xt, p[1] = o[1], p[2] = 1;
            return xt < 12 - m && xt > m && o[1] > m && o[1] < 16 - m;
        }
        p[0] = 12, p[1] = o[1], p[2] = o[2] - (12 - o[0]), *face = 1;
        return p[2] > 1 + m && p[2] < 9 - m && o[1] > m && o[1] < 16 - m;
    }
    p[0] = cx + u * hw, p[1] = 8 + vv * hh, p[2] = 1;
    if (kind == GATHER_STEP) { /* straight down across the wall's top (z = 9, x = 12..14) */
        if (p[0] >= 12 && p[0] < 14) p[2] = 9;
        bool edge = p[2] > 1 ? (p[0] < 12 + m || p[0] > 14 - m) : (p[0] > 12 - m && p[0] < 14 + m);
        return !edge && p[0] > m && p[0] < 16 - m && p[1] > m && p[1] < 16 - m;
    }
    return true;
}

static void gather_cpu_case(int kind) {
    bool indirect = kind == GATHER_INDIRECT, wall = kind == GATHER_WALL;
    bool general = kind == GATHER_STEP || kind == GATHER_CORNER;
    vx_svo_scene s;
    cells_scene(&s, 16, kind != GATHER_FULL ? slab_wall_cell : slab_cell);
    s.palette[1] = GRAY;
    double black[3] = {0, 0, 0};
    vx_probe_set light = light_only(0, black, 1);
    vx_light pl = {.type = VX_LIGHT_POINT, .position = {8, 8, 6}, .color = {1, 0.8, 0.6}, .intensity = 20};
    if (kind >= GATHER_STEP) pl.position[2] = 14; /* the wall's top lit too */
    const double r = 0.5;
    vx_photon_desc d = {.photons = kind >= GATHER_STEP ? 400000 : 200000, .radius = r, .caustic_radius = r, .lights = &pl,
                        .light_count = 1};
    run R;
    REQUIRE(run_make(&R, &s, &light, &d));
    enum { W = 24, H = 18 };
    /* three views: 9 cells wide (a tile of 8 x 8 pixels spans 6 radii: each pixel's own loop), 1.33 wide (a
     * tile spans 0.9 radii: the tile's shared loop, photon.comp tile_sum, over a box of at most 4 cells a
     * side) and 3.2 wide (2.1 radii: a box of 5 cells a side, the most the shared loop takes); the slab's
     * middle, or its part from x = 1.5 to 10.5 by the wall; the wall's face from z = 2 to 8 */
    enum { VIEWS = 3 };
    double heights[VIEWS] = {wall ? 6 : (indirect ? 6.75 : 9), 1, 2.4}, cxs[VIEWS] = {8, 8, 8};
    if (indirect) cxs[0] = cxs[1] = cxs[2] = 6;
    /* across the wall's top (a tile's points 8 apart in depth): boxes of 3 x 5 x 19 cells and more, a slot
     * each of the needed cells only (photon.comp tile_sum), or past 1024 cells the own loops; at the wall's
     * foot: tiles of two normals (the pixels' own normal tests in the shared loop) */
    if (kind == GATHER_STEP) heights[0] = 3, heights[1] = 8, heights[2] = 5, cxs[0] = 13, cxs[1] = 10, cxs[2] = 11;
    if (kind == GATHER_CORNER) heights[0] = 2, heights[1] = 6, heights[2] = 3;
    vx_render_image ims[VIEWS] = {{0}};
    vx_error err = {0};
    vx_photon_record* ph = NULL;
    size_t n = 0, direct = 0;
    vx_result res = VX_OK;
    for (int v = 0; v < VIEWS && !res; v++) {
        vx_render_desc view = view_down(W, H, cxs[v], 8, heights[v] / 2, 40);
        if (wall) { /* from -x towards the face at x = 12, up +z: right is -y */
            view.camera.eye[0] = -20, view.camera.eye[1] = 8, view.camera.eye[2] = 5;
            view.camera.target[0] = 12, view.camera.target[1] = 8, view.camera.target[2] = 5;
            view.camera.up[1] = 0, view.camera.up[2] = 1;
        }
        if (kind == GATHER_CORNER) { /* along (1, 0, -1): the corner line through (12, 8, 1) in the middle */
            view.camera.eye[0] = 2, view.camera.eye[1] = 8, view.camera.eye[2] = 11;
            view.camera.target[0] = 12, view.camera.target[1] = 8, view.camera.target[2] = 1;
            view.camera.up[1] = 0, view.camera.up[2] = 1;
        }
        res = vx_photon_render(R.pg, &view, 1, !indirect, &ims[v], &err);
    }
    if (!res) res = vx_photon_stored(R.pg, &ph, &n, &err);
    if (res) fprintf(stderr, "  photons: %s\n", err.msg);
    run_free(&R);
    vx_svo_scene_free(&s);
    REQUIRE(res == VX_OK);
    for (size_t i = 0; i < n; i++) direct += (ph[i].flags & VX_PHOTON_DIRECT) != 0;
    for (int v = 0; v < VIEWS; v++) {
        /* pixel centres on the top face (z = 1): right is +x, up +y; on the wall's face (x = 12): right -y, up +z */
        double hh = heights[v] / 2, hw = hh * W / H, f = ALB / PI / (PI * r * r);
        size_t outside = 0, agree = 0, hits = 0, checked = 0, faces[2] = {0};
        double worst = 0;
        (void)hw;
        for (int y = 0; y < H; y++)
            for (int x = 0; x < W; x++) {
                double p[3];
                int face;
                if (!gather_point(kind, hh, cxs[v], x, y, W, H, r, p, &face)) continue;
                checked++, faces[face]++;
                double lo[3] = {0}, hi[3] = {0};
                size_t nlo = 0, nhi = 0;
                for (size_t i = 0; i < n; i++) {
                    if ((face ? -ph[i].normal[0] : ph[i].normal[2]) < 0.9) continue; /* not the face (GPU: within 25 degrees) */
                    if (indirect && (ph[i].flags & VX_PHOTON_DIRECT)) continue;
                    double d2 = 0;
                    for (int k = 0; k < 3; k++) d2 += (ph[i].position[k] - p[k]) * (ph[i].position[k] - p[k]);
                    if (d2 > r * r * (1 + 2e-4)) continue;
                    bool in = d2 <= r * r * (1 - 2e-4);
                    for (int k = 0; k < 3; k++) {
                        hi[k] += f * ph[i].power[k];
                        if (in) lo[k] += f * ph[i].power[k];
                    }
                    nhi++, nlo += in;
                }
                hits += nlo;
                const float* g = ims[v].pixels + 4 * ((size_t)y * W + x);
                for (int k = 0; k < 3; k++) {
                    if (g[k] < lo[k] * (1 - 1e-5) - 1e-9 || g[k] > hi[k] * (1 + 1e-5) + 1e-9) outside++;
                    if (nlo == nhi && lo[k] > 0) worst = fmax(worst, fabs(g[k] / lo[k] - 1));
                }
                agree += nlo == nhi;
            }
        const char* what[] = {"full image", "indirect light by a wall", "the wall's face", "across the wall's top",
                              "the wall's foot"};
        fprintf(stderr, "  gather vs CPU, %s, view %.2f high: %zu photons (%zu direct), %.0f per pixel; %zu of %zu values "
                "outside the CPU's bracket; %zu of %zu pixels (%zu on a top, %zu on the face) without a photon on the "
                "circle's edge, there within %.2g\n",
                what[kind], heights[v], n, direct, (double)hits / (double)(checked ? checked : 1), outside, 3 * checked,
                agree, checked, faces[0], faces[1], worst);
        CHECK(n > 30000 && hits > (size_t)(indirect ? 10 : 50) * checked);
        CHECK(!indirect || (direct > n / 10 && direct < n)); /* both kinds on the slab: the test can tell them apart */
        CHECK(outside == 0);
        CHECK(agree > (v ? 0.7 : 0.8) * checked && worst < 1e-5); /* (more photons a pixel: more on the edge) */
        /* the views the cases are for: most pixels checked, both faces (or both depths) in the image */
        if (general) CHECK(checked > W * H / 3 && (kind == GATHER_STEP ? faces[0] > 0 : faces[0] > 20 && faces[1] > 20));
        vx_render_image_free(&ims[v]);
    }
    vx_free(NULL, ph);
}

static void test_gather_cpu(void) {
    if (!gpu) SKIP("no Vulkan device");
    gather_cpu_case(GATHER_FULL);
    gather_cpu_case(GATHER_INDIRECT);
    gather_cpu_case(GATHER_WALL);
    gather_cpu_case(GATHER_STEP);
    gather_cpu_case(GATHER_CORNER);
}

/* The estimate near a surface's edge: a slab's corner under a sun straight down (irradiance 2 on its
 * top, so radiance ALB / pi * 2 everywhere on it), seen straight down (ortho) in a full image. A pixel
 * within r of the slab's edge finds photons only on the slab's part of its disk; dividing by the disk
 * pi r^2 put it dark (about 0.79 of the radiance on a band r wide along a straight edge, less at the
 * corner: the light beyond the edge was lost, the caustic scene's 1.1% deficit), dividing by the
 * area of the slab's top within r (photon.comp kernel_factors) puts it right. Checks: the pixels
 * within r of the edges and those farther in, each group's mean within 3% of the radiance, and the
 * band's mean within 3% of the interior's. */
static void test_kernel_edge(void) {
    if (!gpu) SKIP("no Vulkan device");
    vx_svo_scene s;
    cells_scene(&s, 16, slab_cell);
    s.palette[1] = GRAY;
    double black[3] = {0, 0, 0};
    vx_probe_set light = light_only(2, black, 1);
    const double r = 1;
    vx_photon_desc d = {.photons = 300000, .radius = r, .caustic_radius = r, .seed = 3};
    enum { W = 32, H = 32 };
    const double cx = 2, cy = 2, hh = 3;
    vx_render_desc view = view_down(W, H, cx, cy, hh, 40);
    vx_render_image im = {0};
    bool ok = photon_image(&s, &light, &d, &view, 4, true, &im, NULL);
    vx_svo_scene_free(&s);
    REQUIRE(ok);
    double expect = ALB / PI * 2, sum[2] = {0, 0};
    size_t n[2] = {0, 0};
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            double u = ((x + 0.5) / W) * 2 - 1, v = 1 - ((y + 0.5) / H) * 2, px = cx + u * hh, py = cy + v * hh;
            if (px < 0.02 || py < 0.02) continue; /* off the slab (or on its rim) */
            int band = px < r || py < r;
            const float* g = im.pixels + 4 * ((size_t)y * W + x);
            sum[band] += (g[0] + g[1] + g[2]) / 3, n[band]++;
        }
    double in = sum[0] / n[0] / expect, edge = sum[1] / n[1] / expect;
    fprintf(stderr, "  slab under the sun: radiance within r of the edge %.4f of the analytic (%zu pixels), farther in "
            "%.4f (%zu)\n", edge, n[1], in, n[0]);
    CHECK(n[0] > 100 && n[1] > 100);
    CHECK(fabs(in - 1) < 0.03 && fabs(edge - 1) < 0.03 && fabs(edge / in - 1) < 0.03);
    vx_render_image_free(&im);
}

/* Two models side by side make one floor (two instances of an 8 x 16 slab): at their seam each model's
 * cells beyond it are empty, yet the other model's top continues the plane and holds photons; the area
 * counts it (photon.comp face_elsewhere: a short ray), so the seam is neither dark nor bright. Under a
 * sun straight down: the pixels within r of the seam within 3% of the radiance, as those farther off. */
static void test_kernel_seam(void) {
    if (!gpu) SKIP("no Vulkan device");
    uint32_t size[3] = {8, 16, 1}, *xyz = malloc(8 * 16 * 12);
    uint8_t* pal = malloc(8 * 16);
    size_t k = 0;
    for (uint32_t y = 0; y < 16; y++)
        for (uint32_t x = 0; x < 8; x++) xyz[3 * k] = x, xyz[3 * k + 1] = y, xyz[3 * k + 2] = 0, pal[k++] = 1;
    vx_svo_model m;
    REQUIRE(ts_model(&m, size, xyz, pal, k) == VX_OK);
    free(xyz);
    free(pal);
    vx_svo_instance in[2] = {ts_inst(0, NULL, 0, 0, 0), ts_inst(0, NULL, 8, 0, 0)};
    vx_svo_scene s;
    ts_scene(&s, &m, 1, in, 2);
    s.palette[1] = GRAY;
    double black[3] = {0, 0, 0};
    vx_probe_set light = light_only(2, black, 1);
    const double r = 1;
    vx_photon_desc d = {.photons = 300000, .radius = r, .caustic_radius = r, .seed = 4};
    enum { W = 32, H = 32 };
    const double cx = 8, cy = 8, hh = 3;
    vx_render_desc view = view_down(W, H, cx, cy, hh, 40);
    vx_render_image im = {0};
    bool ok = photon_image(&s, &light, &d, &view, 4, true, &im, NULL);
    vx_svo_scene_free(&s);
    REQUIRE(ok);
    double expect = ALB / PI * 2, sum[2] = {0, 0};
    size_t n[2] = {0, 0};
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            double u = ((x + 0.5) / W) * 2 - 1, px = cx + u * hh;
            int band = fabs(px - 8) < r;
            const float* g = im.pixels + 4 * ((size_t)y * W + x);
            sum[band] += (g[0] + g[1] + g[2]) / 3, n[band]++;
        }
    double off = sum[0] / n[0] / expect, seam = sum[1] / n[1] / expect;
    fprintf(stderr, "  two slabs under the sun: radiance within r of the seam %.4f of the analytic (%zu pixels), farther "
            "off %.4f (%zu)\n", seam, n[1], off, n[0]);
    CHECK(fabs(off - 1) < 0.03 && fabs(seam - 1) < 0.03);
    vx_render_image_free(&im);
}

/* The same at a concave edge: the furnace's box (walls of albedo a emitting Le: gi a Le / (1 - a) on
 * every wall), its floor's corner seen straight down. Within r of a wall the disk's part under the wall
 * holds none of the floor's photons (the wall's have another normal): 0.77 of the gi there before, 0.62
 * within r of both walls. Checks: the floor's interior within 2% of the analytic value, the band along
 * one wall within 3% of the interior (the corner's few pixels are printed). */
static void test_kernel_corner(void) {
    if (!gpu) SKIP("no Vulkan device");
    vx_svo_scene s;
    box_scene(&s, 16, 1);
    s.palette[1] = GRAY;
    const char* kv[] = {"_type", "_emit", "_emit", "1"};
    add_material(&s, 1, kv, 2);
    double black[3] = {0, 0, 0};
    vx_probe_set light = light_only(0, black, 1);
    vx_photon_desc d = {.photons = 400000, .radius = 1, .alpha = 1, .bounces = 64, .capacity = 4000000};
    enum { W = 32, H = 32 };
    const double cx = 4, cy = 4, hh = 3;
    vx_render_desc view = view_down(W, H, cx, cy, hh, 8);
    vx_render_image im = {0};
    bool ok = photon_image(&s, &light, &d, &view, 4, false, &im, NULL);
    vx_svo_scene_free(&s);
    REQUIRE(ok);
    double Le = ALB * 1, expect = ALB * Le / (1 - ALB), sum[3] = {0, 0, 0};
    size_t n[3] = {0, 0, 0};
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            double u = ((x + 0.5) / W) * 2 - 1, v = 1 - ((y + 0.5) / H) * 2, px = cx + u * hh, py = cy + v * hh;
            if (px < 1.02 || py < 1.02) continue;
            int band = (px < 2) + (py < 2);
            const float* g = im.pixels + 4 * ((size_t)y * W + x);
            sum[band] += (g[0] + g[1] + g[2]) / 3, n[band]++;
        }
    double in = sum[0] / n[0] / expect, one = sum[1] / n[1] / expect;
    fprintf(stderr, "  box corner: gi of the analytic: farther in %.4f (%zu pixels), within r of one wall %.4f (%zu), "
            "of both %.4f (%zu)\n", in, n[0], one, n[1], sum[2] / n[2] / expect, n[2]);
    CHECK(n[0] > 300 && n[1] > 100);
    CHECK(fabs(in - 1) < 0.02 && fabs(one / in - 1) < 0.03);
    vx_render_image_free(&im);
}

/* ---- a glossy surface: a rough metal voxel sphere in a lit gray room ------------------- */

static uint8_t metal_cell(uint32_t x, uint32_t y, uint32_t z, uint32_t n) {
    if (x == 0 || y == 0 || z == 0 || x == n - 1 || y == n - 1 || z == n - 1) return 1;
    double dx = x + 0.5 - 8, dy = y + 0.5 - 9, dz = z + 0.5 - 6;
    return dx * dx + dy * dy + dz * dz <= 16 ? 2 : 0;
}

/* A rough metal (GGX, roughness 0.2) voxel sphere in a closed gray room lit
 * by a sphere light, seen from inside the room; the indirect light on the
 * sphere is the lit room seen in it. A photon estimate there finds only the
 * photons on the facets of the pixel's orientation, which on the sphere's
 * staircase of faces cover part of the disk it divides by (cornell's metal
 * sphere came out dark): glossy surfaces follow their specular lobe by a
 * ray instead (photons.h). Over the pixels that see the sphere the mean
 * matches the path tracer's (two 1024-spp seeds) within 5%, and the whole
 * image within a relMSE of 0.03. Not matched (test_ggx_finite's scene, a
 * third of the path tracer's mean): a small light seen through two
 * reflections on the staircase, which the path tracer finds by next-event
 * estimation at the second and the photons take from the density of that
 * light's photons there (G_LIGHTS), as dark as before on a staircase. */
static void test_glossy(void) {
    if (!gpu) SKIP("no Vulkan device");
    vx_svo_scene s;
    cells_scene(&s, 16, metal_cell);
    s.palette[1] = GRAY, s.palette[2] = 0xFFE0E0E0u;
    const char* kv[] = {"_type", "_metal", "_metal", "1", "_rough", "0.2"};
    add_material(&s, 2, kv, 3);
    vx_light L = {.type = VX_LIGHT_SPHERE, .position = {3.5, 4, 12}, .color = {1, 1, 1}, .intensity = 11, .radius = 0.6};
    vx_render_desc view = {.width = 32, .height = 24};
    view.camera.set = true, view.camera.fov = 50;
    view.camera.eye[0] = 8.3, view.camera.eye[1] = 1.6, view.camera.eye[2] = 9.1;
    view.camera.target[0] = 8, view.camera.target[1] = 9, view.camera.target[2] = 6;
    view.camera.up[2] = 1;
    double black[3] = {0, 0, 0};
    vx_probe_set light = light_only(0, black, 6);
    vx_render_image ref[2] = {{0}}, im = {0}, sph = {0};
    vx_render_scene* rs = NULL;
    vx_error err = {0};
    vx_result r = vx_render_scene_create(gpu, &s, &rs, &err);
    for (int k = 0; k < 2 && !r; k++) {
        vx_probe_render_desc d = {.base = &view, .mode = VX_PROBE_RENDER_PT_INDIRECT, .spp = 1024,
                                  .seed = 21 + (uint64_t)k, .lights = &L, .light_count = 1, .pixel_centre = true};
        r = vx_probe_render_gpu(rs, &s, &light, &d, &ref[k], &err);
    }
    /* which pixels see the sphere: a render whose colour is the hit's palette entry */
    vx_render_desc pv = view;
    pv.mode = VX_RENDER_ALBEDO;
    if (!r) r = vx_render_frame(rs, &pv, &sph, &err);
    vx_render_scene_destroy(rs);
    if (r) fprintf(stderr, "  path tracer: %s\n", err.msg);
    REQUIRE(r == VX_OK);
    vx_photon_desc d = {.photons = 200000, .radius = 0.5, .lights = &L, .light_count = 1};
    bool ok = photon_image(&s, &light, &d, &view, 8, false, &im, NULL);
    vx_svo_scene_free(&s);
    REQUIRE(ok);
    double noise = rel_mse(&ref[1], &ref[0]);
    size_t n = (size_t)view.width * view.height, on = 0;
    for (size_t i = 0; i < 4 * n; i++) ref[0].pixels[i] = 0.5f * (ref[0].pixels[i] + ref[1].pixels[i]);
    double sp = 0, sr = 0;
    for (size_t i = 0; i < n; i++) {
        if (!(sph.pixels[4 * i] > 0.8f)) continue; /* the sphere's 0xE0 against the walls' 0x80 */
        for (int c = 0; c < 3; c++) sp += im.pixels[4 * i + c], sr += ref[0].pixels[4 * i + c];
        on++;
    }
    double e = rel_mse(&im, &ref[0]);
    fprintf(stderr, "  glossy: the sphere's %zu pixels, photons / path tracer %.4f; relMSE %.4f (reference seeds apart %.4f)\n",
            on, sp / sr, e, noise);
    CHECK(on > 100 && sr > 0.01 * on);
    CHECK(fabs(sp / sr - 1) < 0.05);
    CHECK(e < 0.03);
    vx_render_image_free(&im);
    vx_render_image_free(&sph);
    vx_render_image_free(&ref[0]);
    vx_render_image_free(&ref[1]);
}

/* A rough metal sphere over a floor seen straight from the side (ortho):
 * every pixel finite in the path tracer and the photons. The GGX Fresnel
 * term took pow(1 - dot(wi, h), 5), and where a reflection leaves a face
 * along its normal rounding puts the dot above 1: pow of a negative, NaN
 * (3 pixels of this image at 1024 spp on lavapipe before the clamp in
 * probes/shaders/path_common.glsl).
 * Then the light a glossy surface of voxel steps reflects from photons (the
 * G_LIGHTS sums, GGX per photon, over the faces of the point's orientation
 * within r): in the full image, on the sphere's pixels whose ray misses the
 * sphere light (the path tracer's camera rays end at it, the photons' pass
 * through it), the photons' mean is the path tracer's. The indirect image's
 * light here (two reflections on the steps) was noted dark: it is the same
 * sums at the second surface, a heavy-tailed estimate at these counts (four
 * seeds of 200k photons x 8 passes gave 0.34, 0.41, 0.94 and 2.73 of the
 * path tracer's, mean 1.10): most runs read dark, their mean does not
 * (docs/PERFORMANCE.md "Issue 13, seventh sitting"); the first surface's
 * sums, checked here, are less so. */
static uint8_t metal_floor_cell(uint32_t x, uint32_t y, uint32_t z, uint32_t n) {
    (void)n;
    if (z == 0) return 1;
    double dx = x + 0.5 - 8, dy = y + 0.5 - 8, dz = z + 0.5 - 6.5;
    return dx * dx + dy * dy + dz * dz <= 25 ? 2 : 0;
}
static void test_ggx_finite(void) {
    if (!gpu) SKIP("no Vulkan device");
    vx_svo_scene s;
    cells_scene(&s, 16, metal_floor_cell);
    s.palette[1] = GRAY, s.palette[2] = 0xFFE0E0E0u;
    const char* kv[] = {"_type", "_metal", "_metal", "1", "_rough", "0.2"};
    add_material(&s, 2, kv, 3);
    vx_light L = {.type = VX_LIGHT_SPHERE, .position = {3, 2, 9}, .color = {1, 1, 1}, .intensity = 6, .radius = 1.5};
    enum { W = 24, H = 24 };
    const double half = 5.5; /* the view's half height and width */
    vx_render_desc view = {.width = W, .height = H};
    view.camera.set = true, view.camera.ortho = true, view.camera.ortho_height = 2 * half;
    view.camera.eye[0] = 8, view.camera.eye[1] = -30, view.camera.eye[2] = 6.5;
    view.camera.target[0] = 8, view.camera.target[1] = 8, view.camera.target[2] = 6.5;
    view.camera.up[2] = 1;
    double black[3] = {0, 0, 0};
    vx_probe_set light = light_only(0, black, 6);
    vx_render_image im[2] = {{0}}, full[2] = {{0}}, alb = {0};
    vx_render_scene* rs = NULL;
    vx_error err = {0};
    vx_result r = vx_render_scene_create(gpu, &s, &rs, &err);
    vx_probe_render_desc d = {.base = &view, .mode = VX_PROBE_RENDER_PT_INDIRECT, .spp = 1024, .seed = 21,
                              .lights = &L, .light_count = 1, .pixel_centre = true};
    if (!r) r = vx_probe_render_gpu(rs, &s, &light, &d, &im[0], &err);
    d.mode = VX_PROBE_RENDER_PATHTRACE;
    if (!r) r = vx_probe_render_gpu(rs, &s, &light, &d, &full[0], &err);
    vx_render_desc pv = view; /* which pixels see the sphere: its palette entry's albedo */
    pv.mode = VX_RENDER_ALBEDO;
    if (!r) r = vx_render_frame(rs, &pv, &alb, &err);
    vx_render_scene_destroy(rs);
    if (r) fprintf(stderr, "  path tracer: %s\n", err.msg);
    vx_photon_desc pd = {.photons = 100000, .radius = 0.5, .lights = &L, .light_count = 1};
    if (!r && !photon_image(&s, &light, &pd, &view, 2, false, &im[1], NULL)) r = VX_ERR_GPU;
    /* capacity: the default 4 x photons makes a 204.8 MB photon buffer, past lavapipe's maxStorageBufferRange
     * (128 MiB: an invalid descriptor, which the validation layer reports) */
    vx_photon_desc pf = {.photons = 1600000, .capacity = 3200000, .radius = 0.25, .lights = &L, .light_count = 1,
                         .seed = 77};
    if (!r && !photon_image(&s, &light, &pf, &view, 8, true, &full[1], NULL)) r = VX_ERR_GPU;
    vx_svo_scene_free(&s);
    REQUIRE(r == VX_OK);
    size_t bad[2] = {0, 0};
    for (int k = 0; k < 2; k++)
        for (size_t i = 0; i < 4 * (size_t)view.width * view.height; i++)
            bad[k] += !isfinite(im[k].pixels[i]) + !isfinite(full[k].pixels[i]);
    /* the sphere's pixels (ortho: the ray through the pixel's centre at x, z) that miss the light */
    double sum[2] = {0, 0};
    size_t on = 0;
    for (int j = 0; j < H; j++)
        for (int i = 0; i < W; i++) {
            double x = 8 + half * (((i + 0.5) / W) * 2 - 1), z = 6.5 + half * (1 - ((j + 0.5) / H) * 2);
            size_t p = (size_t)j * W + i;
            bool behind = (x - L.position[0]) * (x - L.position[0]) + (z - L.position[2]) * (z - L.position[2]) <
                          (L.radius + 0.3) * (L.radius + 0.3);
            if (!(alb.pixels[4 * p] > 0.8f) || behind) continue; /* the sphere's 0xE0 against the floor's 0x80 */
            for (int k = 0; k < 2; k++)
                for (int c = 0; c < 3; c++) sum[k] += full[k].pixels[4 * p + c];
            on++;
        }
    fprintf(stderr, "  GGX straight from the side: %zu and %zu non-finite values (path tracer, photons); indirect means %.4f %.4f;"
            " full, the steps' %zu pixels that miss the light: photons / path tracer %.3f\n",
            bad[0], bad[1], mean_rgb(&im[0]), mean_rgb(&im[1]), on, sum[1] / sum[0]);
    CHECK(bad[0] == 0 && bad[1] == 0);
    CHECK(mean_rgb(&im[0]) > 1e-4 && mean_rgb(&im[1]) > 1e-4); /* lit */
    CHECK(on > 250 && sum[0] > 1e-3 * on);
    /* seeds 77-80: 1.21, 0.96, 0.95, 0.99 (a few pixels by the light carry most of the spread; the pixels'
     * median ratio is 0.86-0.92: per photon, GGX makes a heavy-tailed sum, most pixels read dark) */
    CHECK(sum[1] / sum[0] > 0.8 && sum[1] / sum[0] < 1.3);
    for (int k = 0; k < 2; k++) vx_render_image_free(&im[k]), vx_render_image_free(&full[k]);
    vx_render_image_free(&alb);
}

/* The progressive estimate: passes of few photons with a large first radius
 * (noisy and blurred); the error against the path tracer falls as passes
 * accumulate and the radius shrinks. */
static void test_progressive(void) {
    if (!gpu) SKIP("no Vulkan device");
    REQUIRE(caustic_setup());
    double e[3];
    uint32_t passes[3] = {1, 4, 16};
    for (int i = 0; i < 3; i++) {
        vx_render_image im = {0};
        REQUIRE(caustic_photons(20000, passes[i], 1.5, &im));
        e[i] = rel_mse(&im, &caustic_ref);
        fprintf(stderr, "  %2u passes: relMSE %.4f\n", passes[i], e[i]);
        vx_render_image_free(&im);
    }
    CHECK(e[1] < e[0] && e[2] < e[1]);
}

/* Last: the validation layer (where installed) saw no error in the tests
 * above, every photon step's pipeline among them: an invalid pipeline runs
 * on lavapipe all the same (photon.comp's t_wpre of length 0, 0ad1200). */
/* A capacity whose photon buffers pass the device's storage-buffer range (2^28 photons of 32 bytes:
 * 8 GiB, past any device's 32-bit range) is refused at creation with VX_ERR_LIMIT and a message that
 * names the range, not bound whole and left to the driver. */
static void test_capacity_range(void) {
    if (!gpu) SKIP("no Vulkan device");
    vx_svo_scene s;
    cells_scene(&s, 16, metal_floor_cell);
    double black[3] = {0, 0, 0};
    vx_probe_set light = light_only(0, black, 6);
    vx_photon_desc d = vx_photon_desc_defaults();
    d.photons = 1u << 16, d.capacity = 1u << 28;
    vx_render_scene* rs = NULL;
    vx_photon_gi* pg = NULL;
    vx_gi_method gm;
    vx_error err = {0};
    vx_result r = vx_render_scene_create(gpu, &s, &rs, &err);
    CHECKF(r == VX_OK, "scene: %s", err.msg);
    if (!r) {
        r = vx_photon_gi_create(rs, &s, &light, &d, &gm, &pg, &err);
        CHECKF(r == VX_ERR_LIMIT && strstr(err.msg, "storage-buffer range"), "capacity 2^28: result %d, '%s'", r,
               err.msg);
        CHECK(pg == NULL);
        vx_photon_gi_destroy(pg);
        /* the largest capacity that fits the range is accepted */
        d.capacity = (uint32_t)(gpu->props.limits.maxStorageBufferRange / 32 < (1u << 20)
                                    ? gpu->props.limits.maxStorageBufferRange / 32
                                    : (1u << 20));
        r = vx_photon_gi_create(rs, &s, &light, &d, &gm, &pg, &err);
        CHECKF(r == VX_OK, "capacity %u: %s", d.capacity, err.msg);
        vx_photon_gi_destroy(pg);
    }
    vx_render_scene_destroy(rs);
    vx_svo_scene_free(&s);
}

static void test_no_validation_errors(void) {
    if (!gpu) SKIP("no Vulkan device");
    if (!gpu->messenger) SKIP("no validation layer");
    CHECKF(vx_gpu_validation_errors(gpu) == 0, "%u validation errors", vx_gpu_validation_errors(gpu));
}

int main(void) {
    (void)ts_random_model, (void)room_scene;
    int logged = 0;
    vx_logger lg = {.func = vx_test_validation_log, .user_data = &logged};
    const char* skip = vx_test_gpu_open((vx_gpu_desc){.logger = &lg}, true, &gpu); /* pins lavapipe, see gpu_test.h */
    if (skip) fprintf(stderr, "%s\n", skip);
    RUN(test_emission_power);
    RUN(test_emission_voxels_sun_sky);
    RUN(test_emission_exposed_faces);
    RUN(test_emission_by_power);
    RUN(test_sky_gradient_power);
    RUN(test_furnace);
    RUN(test_caustic);
    RUN(test_glossy);
    RUN(test_ggx_finite);
    RUN(test_progressive);
    RUN(test_reproducible);
    RUN(test_overflow_reproducible);
    RUN(test_fused_paths);
    RUN(test_gather_cpu);
    RUN(test_kernel_edge);
    RUN(test_kernel_corner);
    RUN(test_kernel_seam);
    RUN(test_capacity_range);
    RUN(test_no_validation_errors);
    vx_render_image_free(&caustic_ref);
    vx_render_image_free(&caustic_ref2);
    if (caustic.models) vx_svo_scene_free(&caustic);
    if (gpu) vx_gpu_destroy(gpu);
    return vx_test_finish();
}
