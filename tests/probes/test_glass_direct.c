/* tests/probes/test_glass_direct.c - glass seen directly in the pass pipeline
 * (render/shaders/pass_bodies.glsl glass_pixel): a vertical glass slab, three
 * cells thick, between the camera and part of a diffuse floor lit by a point
 * light behind the slab (no shadow ray from the floor behind it crosses the
 * glass), black sky, the passes gbuffer,direct, against
 *  - the closed form: the ray refracted through the slab's parallel faces
 *    (direction unchanged, displaced), the floor's Lambert radiance albedo /
 *    pi E where it lands, times the tint and (1 - F_in)(1 - F_out) (the exact
 *    Fresnel, F_out = F_in for parallel faces), plus the share reflected
 *    twice inside the slab, computed here in double;
 *  - the CPU path tracer (pixel centres; its Fresnel choices converge over
 *    samples; no bounces: the pipeline's direct pass has none);
 *  - the floor seen beside the slab, the same pixels as a scene whose slab is
 *    diffuse (a scene without glass keeps its code path and values).
 * And what glass reflects (test_glass_reflection): a pool of water (a glass
 * slab in a basin) under a wall lit by point lights, seen at a low angle, and
 * a glass pane before a lit wall with a lit floor on the camera's side, the
 * passes without a gi pass against the path tracer at bounces 0 (direct
 * light and emission: its glass events are no bounces, so its paths go on
 * off the glass to the lit wall and floor). Before the direct pass followed
 * the reflected rays, a glass pixel's reflection was the sky's alone: the
 * pool's water 0.0000 against the path tracer's 0.0120.
 * Skips without a Vulkan device. */
#include <dlfcn.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "probes/probes.h"
#include "render/pipeline.h"
#include "tests/probes/closed_form.h"
#include "tests/probes/probe_scenes.h"
#include "tests/test.h"

static const double PI = 3.14159265358979323846;
static vx_gpu* gpu;

enum { W = 40, H = 30, N = 16 };
static const uint32_t FLOOR_RGBA = 0xFF4090D0u; /* R 0xD0, G 0x90, B 0x40 */
static const uint32_t GLASS_RGBA = 0xFFE0F0FFu; /* R 0xFF, G 0xF0, B 0xE0: the tint */
static const double LIGHT_POS[3] = {8, 15, 7}, LIGHT_I = 60, IOR = 1.5;
/* the slab: x in [X0, X1), y in [Y0, Y1), z in [1, Z1) (cells); the floor: cells z = 0 from y = Y0 on */
enum { X0 = 5, X1 = 11, Y0 = 4, Y1 = 7, Z1 = 7 };

static uint8_t slab_cell(uint32_t x, uint32_t y, uint32_t z, uint32_t n) {
    (void)n;
    if (z == 0) return y >= Y0 ? 1 : 0;
    return x >= X0 && x < X1 && y >= Y0 && y < Y1 && z < Z1 ? 2 : 0;
}

/* The floor and the slab; the slab glass (MATL _glass, _ior 0.5: MagicaVoxel's ior - 1) or diffuse. */
static void slab_scene(vx_svo_scene* s, bool glass) {
    cells_scene(s, N, slab_cell);
    s->palette[1] = FLOOR_RGBA, s->palette[2] = GLASS_RGBA;
    if (!glass) return;
    const char* kv[] = {"_type", "_glass", "_trans", "1", "_ior", "0.5", "_rough", "0"};
    add_material(s, 2, kv, 4);
}

static vx_render_desc camera(void) {
    vx_render_desc b = {.width = W, .height = H, .spp = 1};
    b.camera.set = true;
    b.camera.eye[0] = 8, b.camera.eye[1] = -4, b.camera.eye[2] = 10;
    b.camera.target[0] = 8, b.camera.target[1] = 9, b.camera.target[2] = 1;
    b.camera.up[2] = 1, b.camera.fov = 45;
    return b;
}

static vx_light point_light(void) {
    vx_light L = {.type = VX_LIGHT_POINT, .color = {1, 1, 1}, .intensity = LIGHT_I, .range = 1000};
    memcpy(L.position, LIGHT_POS, sizeof L.position);
    return L;
}

/* The pass pipeline's frame of s with list `passes`, the point light, a black sky. */
static bool frame(const vx_svo_scene* s, const char* passes, bool separate, vx_render_image* out) {
    vx_error err = {0};
    vx_render_scene* rs = NULL;
    vx_frame_renderer* fr = NULL;
    vx_pass_list list;
    vx_light L = point_light();
    vx_result r = vx_pass_list_parse(passes, &list, &err);
    if (!r) r = vx_render_scene_create(gpu, s, &rs, &err);
    if (!r) r = vx_frame_renderer_create(rs, s, &fr, &err);
    vx_frame_result res = {0};
    if (!r) {
        vx_frame_desc fd = vx_frame_desc_defaults();
        fd.base = camera();
        fd.passes = &list;
        fd.lights = &L, fd.light_count = 1;
        fd.sky[0] = fd.sky[1] = fd.sky[2] = 0;
        fd.separate_passes = separate;
        r = vx_frame_render(fr, &fd, &res, &err);
    }
    if (r) fprintf(stderr, "  frame: %s\n", err.msg);
    vx_frame_renderer_destroy(fr);
    vx_render_scene_destroy(rs);
    *out = res.image;
    return r == VX_OK;
}

/* The Lambert radiance albedo / pi E of the floor (top z = 1) where the ray
 * o + t d lands, 0.25 inside it and behind the slab; false elsewhere. */
static bool floor_light(const double o[3], const double d[3], double out[3]) {
    double t = (1 - o[2]) / d[2], p[3];
    for (int k = 0; k < 3; k++) p[k] = o[k] + t * d[k];
    if (!(p[0] > 0.25 && p[0] < N - 0.25 && p[1] > Y1 + 0.25 && p[1] < N - 0.25)) return false;
    double wi[3];
    for (int k = 0; k < 3; k++) wi[k] = LIGHT_POS[k] - p[k];
    double di2 = cf_dot3(wi, wi), dist = sqrt(di2), q = (dist / 1000) * (dist / 1000);
    double E = LIGHT_I * (wi[2] / dist) / di2 * (1 - q * q) * (1 - q * q);
    for (int k = 0; k < 3; k++) out[k] = ((FLOOR_RGBA >> (8 * k)) & 255) / 255.0 / PI * E;
    return true;
}

/* Pixel (px, py)'s centre ray (render/render.h's pinhole). Through the slab:
 * whether it enters by the front face y = Y0 and leaves by the back face
 * y = Y1 (both 0.2 from the face's edges) to land on the floor (top z = 1)
 * 0.25 inside it, and so does the share reflected twice inside (back face,
 * front face) that leaves by the back face further on; then the expected
 * radiance (Lambert floor times the tint and (1 - F)^2, plus that share's
 * with F^2 more), and F. Beside the slab (through == false): whether it
 * meets the floor 0.25 inside it without touching the slab's box, and the
 * floor's Lambert radiance. */
static bool pixel_expect(uint32_t px, uint32_t py, bool through, double out[3], double* F) {
    vx_render_desc b = camera();
    const double* e = b.camera.eye;
    double d[3];
    cf_pixel_ray(&b, px, py, d);
    double o[3] = {e[0], e[1], e[2]}, thr = 1, twice[3] = {0, 0, 0};
    *F = 0;
    if (!(d[2] < 0) || !(d[1] > 0)) return false;
    double t0 = (Y0 - o[1]) / d[1], a[3];
    for (int k = 0; k < 3; k++) a[k] = o[k] + t0 * d[k];
    bool front = a[0] > X0 - 0.2 && a[0] < X1 + 0.2 && a[2] > 1 - 0.2 && a[2] < Z1 + 0.2;
    if (through) {
        if (!(a[0] > X0 + 0.2 && a[0] < X1 - 0.2 && a[2] > 1.2 && a[2] < Z1 - 0.2)) return false;
        /* refract into the slab (normal -y), walk to y = Y1, refract out: d again */
        double c = d[1], eta = IOR, ei = 1 / eta, k2 = 1 - ei * ei * (1 - c * c), n[3] = {0, -1, 0}, di[3];
        for (int k = 0; k < 3; k++) di[k] = ei * d[k] + (ei * c - sqrt(k2)) * n[k];
        double t1 = (Y1 - a[1]) / di[1], q[3];
        for (int k = 0; k < 3; k++) q[k] = a[k] + t1 * di[k];
        if (!(q[0] > X0 + 0.2 && q[0] < X1 - 0.2 && q[2] > 1.2 && q[2] < Z1 - 0.2)) return false;
        double fi = cf_fresnel(c, eta), fo = cf_fresnel(di[1], 1 / eta); /* out: cos inside = di.y */
        *F = fi;
        thr = (1 - fi) * (1 - fo);
        memcpy(o, q, sizeof o);
        /* the share reflected at the back face and again at the front one leaves the back face parallel to the
         * first exit, two crossings further on (weight F_out^2 more; the next, F_out^4, some 3e-6, left out),
         * unless it goes down to the slab's bottom first, where it meets the floor under the glass (no light
         * there: its shadow rays meet the glass); near an edge the pixel is not taken */
        double q2[3], s2 = 2 * (Y1 - Y0) / di[1];
        for (int k = 0; k < 3; k++) q2[k] = q[k] + s2 * (k == 1 ? 0 : di[k]);
        if (!(q2[0] > X0 + 0.2 && q2[0] < X1 - 0.2 && q2[2] < Z1 - 0.2) || fabs(q2[2] - 1) < 0.2) return false;
        double e2[3];
        if (q2[2] > 1 && !floor_light(q2, d, e2)) return false;
        for (int k = 0; k < 3; k++) twice[k] = q2[2] > 1 ? thr * fo * fo * e2[k] : 0;
    } else if (front || (a[0] > X0 - 0.2 && a[0] < X1 + 0.2 && a[2] >= Z1)) {
        return false; /* the slab's box is in the way, or close */
    }
    double e1[3];
    if (!floor_light(o, d, e1)) return false;
    for (int k = 0; k < 3; k++) {
        double tint = through ? ((GLASS_RGBA >> (8 * k)) & 255) / 255.0 : 1;
        out[k] = (thr * e1[k] + twice[k]) * tint;
    }
    return true;
}

/* Through the slab against the closed form (merged and separate passes), and
 * the floor beside it against albedo / pi E. */
static void test_glass_closed_form(void) {
    if (!gpu) SKIP("no Vulkan device");
    vx_svo_scene s;
    slab_scene(&s, true);
    for (int sep = 0; sep < 2; sep++) {
        vx_render_image im = {0};
        REQUIRE(frame(&s, "gbuffer,direct", sep, &im));
        for (int through = 1; through >= 0; through--) {
            double worst = 0, fmin_ = 1, fmax_ = 0;
            size_t n = 0;
            for (uint32_t y = 0; y < H; y++)
                for (uint32_t x = 0; x < W; x++) {
                    double want[3], F;
                    if (!pixel_expect(x, y, through, want, &F)) continue;
                    const float* g = im.pixels + 4 * ((size_t)y * W + x);
                    for (int k = 0; k < 3; k++) worst = fmax(worst, fabs(g[k] - want[k]) / want[k]);
                    if (through) fmin_ = fmin(fmin_, F), fmax_ = fmax(fmax_, F);
                    n++;
                }
            fprintf(stderr, "  %s (%s): %zu pixels, worst relative error %.2e%s", through ? "through glass" : "beside it",
                    sep ? "separate" : "merged", n, worst, through ? "" : "\n");
            if (through) fprintf(stderr, ", F at entry %.4f .. %.4f\n", fmin_, fmax_);
            CHECK(n > (through ? 110u : 60u));
            /* the shading point 1e-3 cell above the floor (its light direction and distance): some 1e-4 */
            CHECKF(worst < 2e-3, "worst relative error %.2e", worst);
        }
        vx_render_image_free(&im);
    }
    vx_svo_scene_free(&s);
}

/* Through the slab against the CPU path tracer: the mean ratio over the
 * pixels the closed form takes (1 within 2%: the path tracer's Fresnel
 * choice is a coin per interface, so its pixel is 0 or the floor's light;
 * at spp 256 and some 130 pixels of p = (1 - F)^2 ~ 0.92 the mean's
 * standard error is some 0.2%; the pipeline follows the light reflected
 * inside the slab as the path tracer does). */
static void test_glass_vs_pathtracer(void) {
    if (!gpu) SKIP("no Vulkan device");
    vx_svo_scene s;
    slab_scene(&s, true);
    vx_render_image im = {0};
    REQUIRE(frame(&s, "gbuffer,direct", false, &im));
    double sky[3] = {0, 0, 0};
    vx_probe_set ps = light_only(0, sky, 1);
    ps.bounces = UINT32_MAX; /* probes/render_gi.c: bounces 0 takes the set's + 1, here 0 (unsigned): direct light only */
    vx_light L = point_light();
    vx_render_desc base = camera();
    vx_probe_render_desc rd = {.base = &base, .mode = VX_PROBE_RENDER_PATHTRACE, .spp = 256, .bounces = 0, .seed = 9,
                               .lights = &L, .light_count = 1, .pixel_centre = true};
    vx_render_image ref = {0};
    vx_error err = {0};
    vx_result r = vx_probe_render(&s, &ps, &rd, &ref, &err);
    if (r) fprintf(stderr, "  path tracer: %s\n", err.msg);
    REQUIRE(r == VX_OK);
    double sum = 0, sum_ref = 0, sum_b = 0, sum_bref = 0;
    size_t n = 0, nb = 0;
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++) {
            double want[3], F;
            size_t i = 4 * ((size_t)y * W + x);
            bool through = pixel_expect(x, y, true, want, &F);
            if (!through && !pixel_expect(x, y, false, want, &F)) continue;
            for (int k = 0; k < 3; k++) {
                if (through) sum += im.pixels[i + k], sum_ref += ref.pixels[i + k];
                else sum_b += im.pixels[i + k], sum_bref += ref.pixels[i + k];
            }
            through ? n++ : nb++;
        }
    fprintf(stderr, "  against the CPU path tracer: through glass %zu pixels, mean ratio %.5f; beside it %zu, %.5f\n", n,
            sum / sum_ref, nb, sum_b / sum_bref);
    CHECK(n > 110 && nb > 60);
    CHECKF(fabs(sum / sum_ref - 1) < 0.02, "mean ratio %.5f", sum / sum_ref);
    CHECKF(fabs(sum_b / sum_bref - 1) < 1e-3, "mean ratio beside %.5f", sum_b / sum_bref);
    vx_render_image_free(&ref), vx_render_image_free(&im);
    vx_svo_scene_free(&s);
}

/* A scene without glass (the slab diffuse) keeps its pixels: the floor
 * beside the slab as in the glass scene (whose SPIR-V path differs: a float
 * rounding apart at most), and the diffuse slab's pixels are not the glass's. */
static void test_glass_free_unchanged(void) {
    if (!gpu) SKIP("no Vulkan device");
    vx_svo_scene s, g;
    slab_scene(&s, false);
    slab_scene(&g, true);
    vx_render_image a = {0}, b = {0};
    REQUIRE(frame(&s, "gbuffer,direct", false, &a));
    REQUIRE(frame(&g, "gbuffer,direct", false, &b));
    double apart = 0, worst = 0;
    size_t n = 0, differ = 0;
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++) {
            double want[3], F;
            size_t i = 4 * ((size_t)y * W + x);
            if (pixel_expect(x, y, true, want, &F)) {
                differ += fabs(a.pixels[i] - b.pixels[i]) > 1e-3 * want[0];
                continue;
            }
            if (!pixel_expect(x, y, false, want, &F)) continue;
            for (int k = 0; k < 3; k++) {
                apart = fmax(apart, fabs(a.pixels[i + k] - b.pixels[i + k]) / want[k]);
                worst = fmax(worst, fabs(a.pixels[i + k] - want[k]) / want[k]);
            }
            n++;
        }
    fprintf(stderr, "  glass-free scene: %zu floor pixels, worst relative error against albedo / pi E %.2e, "
            "%.2e from the glass scene's; %zu slab pixels differ\n", n, worst, apart, differ);
    CHECK(n > 60);
    CHECKF(worst < 2e-3, "worst relative error %.2e", worst);
    CHECKF(apart < 1e-5, "apart %.2e", apart);
    CHECK(differ > 110);
    vx_render_image_free(&a), vx_render_image_free(&b);
    vx_svo_scene_free(&s), vx_svo_scene_free(&g);
}

/* test_glass_reflection's scenes (16^3 cells, palette 1 diffuse, 2 glass of index 1.5): 0, a pane two cells
 * thick before a wall, a floor under both; 1, a pool: water two cells deep in a basin, a wall behind it. */
static int refl_scene_kind;
static uint8_t refl_cell(uint32_t x, uint32_t y, uint32_t z, uint32_t n) {
    (void)n;
    if (refl_scene_kind == 0) {
        if (y == 13 || z == 0) return 1;
        return y >= 5 && y < 7 && x >= 3 && x < 13 && z >= 1 && z < 11 ? 2 : 0;
    }
    if ((y == 13 && z < 12) || z == 0) return 1;
    bool in = x >= 1 && x <= 14 && y >= 1 && y <= 12;
    if (in && z < 4 && (x == 1 || x == 14 || y == 1 || y == 12)) return 1; /* the basin's rim */
    return in && z >= 1 && z < 3 ? 2 : 0;
}

/* What glass reflects and transmits against the path tracer at bounces 0:
 * each scene lit by two point lights, one on either side of the glass (the
 * pane: between it and the wall, and over the floor before it; the pool: over
 * the water, and behind the camera), black sky, 48 x 36, the mean over the
 * pixels whose first surface is the glass (the albedo image tells them), the
 * path tracer at 1024 samples per pixel centre. Measured: the pane 1.0005,
 * the pool 0.9933 (before: 0.9895 and 0.0000: the reflection was the black
 * sky's). The pane within 0.5% (its reflection is 1.1% of its light; the
 * path tracer's transmission coins leave its mean some 0.03% of noise), the
 * pool within 3% (a reflection of F ~ 0.1 drawn by a coin: some 0.5%).
 * Rough glass is not checked here: the passes take the smooth directions
 * (at roughness 0.3 the pane measured 1.053, the pool 1.112). */
static void test_glass_reflection(void) {
    if (!gpu) SKIP("no Vulkan device");
    enum { RW = 48, RH = 36 };
    const double tol[2] = {0.005, 0.03};
    for (refl_scene_kind = 0; refl_scene_kind < 2; refl_scene_kind++) {
        bool pool = refl_scene_kind == 1;
        vx_svo_scene s;
        cells_scene(&s, N, refl_cell);
        s.palette[1] = FLOOR_RGBA, s.palette[2] = GLASS_RGBA;
        const char* kv[] = {"_type", "_glass", "_trans", "1", "_ior", "0.5", "_rough", "0"};
        add_material(&s, 2, kv, 4);
        vx_light L[2];
        for (int i = 0; i < 2; i++) {
            L[i] = (vx_light){.type = VX_LIGHT_POINT, .color = {1, 1, 1}, .intensity = 40, .range = 1000};
            L[i].position[0] = 8, L[i].position[2] = pool ? 10 : 8;
        }
        L[0].position[1] = pool ? 8 : 9, L[1].position[1] = pool ? -3 : 1;
        vx_render_desc base = ps_view(RW, RH, (double[3]){8, -6, pool ? 9 : 6}, (double[3]){8, 12, pool ? 1 : 5});
        vx_render_image im = {0}, alb = {0}, ref = {0};
        vx_error err = {0};
        vx_render_scene* rs = NULL;
        vx_frame_renderer* fr = NULL;
        vx_pass_list list;
        REQUIRE(vx_pass_list_parse("gbuffer,direct", &list, &err) == VX_OK);
        REQUIRE(vx_render_scene_create(gpu, &s, &rs, &err) == VX_OK);
        REQUIRE(vx_frame_renderer_create(rs, &s, &fr, &err) == VX_OK);
        for (int show = 0; show < 2; show++) {
            vx_frame_desc fd = vx_frame_desc_defaults();
            fd.base = base;
            fd.passes = &list;
            fd.lights = L, fd.light_count = 2;
            fd.sky[0] = fd.sky[1] = fd.sky[2] = 0;
            fd.show = show ? VX_SHOW_ALBEDO : VX_SHOW_FINAL;
            vx_frame_result res = {0};
            vx_result r = vx_frame_render(fr, &fd, &res, &err);
            if (r) fprintf(stderr, "  frame: %s\n", err.msg);
            REQUIRE(r == VX_OK);
            *(show ? &alb : &im) = res.image;
        }
        vx_frame_renderer_destroy(fr);
        vx_render_scene_destroy(rs);
        REQUIRE(ps_pathtrace(&s, NULL, &base, 1024, 0, 0, L, 2, &ref));
        double sum = 0, sum_ref = 0, sum_o = 0, sum_oref = 0;
        size_t n = 0;
        const float ga = ((GLASS_RGBA >> 8) & 255) / 255.0f, gb = ((GLASS_RGBA >> 16) & 255) / 255.0f;
        for (size_t i = 0; i < (size_t)RW * RH; i++) {
            const float* a = alb.pixels + 4 * i;
            bool glass = a[0] == 1.0f && fabsf(a[1] - ga) < 1e-4f && fabsf(a[2] - gb) < 1e-4f;
            for (int k = 0; k < 3; k++) {
                if (glass) sum += im.pixels[4 * i + k], sum_ref += ref.pixels[4 * i + k];
                else sum_o += im.pixels[4 * i + k], sum_oref += ref.pixels[4 * i + k];
            }
            n += glass;
        }
        fprintf(stderr, "  %s: %zu glass pixels, mean %.5f against the path tracer's %.5f: ratio %.4f; the others %.4f\n",
                pool ? "pool" : "pane", n, sum / (3.0 * n), sum_ref / (3.0 * n), sum / sum_ref, sum_o / sum_oref);
        CHECK(n > (pool ? 300u : 1000u));
        CHECKF(fabs(sum / sum_ref - 1) < tol[pool], "%s: mean ratio %.4f", pool ? "pool" : "pane", sum / sum_ref);
        CHECKF(fabs(sum_o / sum_oref - 1) < 0.01, "the other pixels: mean ratio %.4f", sum_o / sum_oref);
        vx_render_image_free(&im), vx_render_image_free(&alb), vx_render_image_free(&ref);
        vx_svo_scene_free(&s);
    }
}

int main(void) {
    (void)ts_random_model, (void)room_scene, (void)box_scene;
    dlopen("libvulkan_lvp.so", RTLD_NOW | RTLD_NODELETE); /* see test_probes_gpu.c */
    vx_error err = {0};
    if (vx_gpu_create(&(vx_gpu_desc){0}, &gpu, &err)) {
        fprintf(stderr, "no Vulkan device (%s): GPU comparisons skipped\n", err.msg);
        gpu = NULL;
    }
    RUN(test_glass_closed_form);
    RUN(test_glass_vs_pathtracer);
    RUN(test_glass_free_unchanged);
    RUN(test_glass_reflection);
    if (gpu) vx_gpu_destroy(gpu);
    return vx_test_finish();
}
