/* tests/probes/test_pathtrace.c - the path tracer with lights and materials
 * (probes/pathtrace.c, probes/shaders/probe.comp) against independent
 * values: the GGX white furnace against a quadrature of the single-scattering
 * albedo written here, an index-matched glass slab against the scene without
 * it, a closed emitting box against the geometric series, a point and a spot
 * light over a plane against I cos / r^2, a stiff emitter's convergence
 * against a high-spp reference, finite images for degenerate lights, and the
 * GPU against the CPU reference. The GPU parts skip without a Vulkan device. */
#include <dlfcn.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "probes/probes.h"
#include "render/trace.h"
#include "tests/probes/probe_scenes.h"
#include "tests/test.h"

static const double PI = 3.14159265358979323846;
static vx_gpu* gpu;

static bool render_cpu(const vx_svo_scene* s, const vx_probe_set* ps, const vx_probe_render_desc* d, vx_render_image* out) {
    vx_error err = {0};
    vx_result r = vx_probe_render(s, ps, d, out, &err);
    if (r) fprintf(stderr, "  CPU render: %s\n", err.msg);
    return r == VX_OK;
}

static bool render_gpu(const vx_svo_scene* s, const vx_probe_set* ps, const vx_probe_render_desc* d, vx_render_image* out) {
    vx_error err = {0};
    vx_render_scene* rs = NULL;
    vx_result r = vx_render_scene_create(gpu, s, &rs, &err);
    if (!r) r = vx_probe_render_gpu(rs, s, ps, d, out, &err);
    if (r) fprintf(stderr, "  GPU render: %s\n", err.msg);
    vx_render_scene_destroy(rs);
    return r == VX_OK;
}

static double mean_rgb(const vx_render_image* im) {
    double m = 0;
    size_t n = (size_t)im->width * im->height;
    for (size_t i = 0; i < n; i++) m += im->pixels[4 * i] + im->pixels[4 * i + 1] + im->pixels[4 * i + 2];
    return m / (3.0 * n);
}

/* Standard deviation of the image mean when every pixel estimates the same
 * value (a uniform scene): the spread of the pixels over sqrt(pixels). */
static double sigma_of_mean(const vx_render_image* im) {
    size_t n = (size_t)im->width * im->height;
    double m = mean_rgb(im), v = 0;
    for (size_t i = 0; i < n; i++) {
        double p = (im->pixels[4 * i] + im->pixels[4 * i + 1] + im->pixels[4 * i + 2]) / 3 - m;
        v += p * p;
    }
    return sqrt(v / (n - 1) / n);
}

static size_t non_finite(const vx_render_image* im) {
    size_t bad = 0;
    for (size_t i = 0; i < (size_t)im->width * im->height * 4; i++) bad += !isfinite(im->pixels[i]);
    return bad;
}

/* ---- scenes -------------------------------------------------------------------------- */

static uint32_t slab_n;
static uint8_t slab_cell(uint32_t x, uint32_t y, uint32_t z, uint32_t n) {
    (void)x, (void)y, (void)n;
    return z == 0 ? 1 : 0;
}
/* An n x n x 1 slab of palette 1 (top face at z = 1) in an n^3 model. */
static void slab_scene(vx_svo_scene* s, uint32_t n, uint32_t rgba) {
    slab_n = n;
    cells_scene(s, n, slab_cell);
    s->palette[1] = rgba;
}

/* An orthographic camera looking at target from direction (sin t, 0, cos t). */
static vx_render_desc ortho_view(const double target[3], double theta, double height, uint32_t w, uint32_t h) {
    vx_render_desc d = {.width = w, .height = h};
    d.camera.set = true, d.camera.ortho = true, d.camera.ortho_height = height;
    d.camera.eye[0] = target[0] + 40 * sin(theta), d.camera.eye[1] = target[1], d.camera.eye[2] = target[2] + 40 * cos(theta);
    memcpy(d.camera.target, target, sizeof d.camera.target);
    d.camera.up[1] = theta > 0 ? 0 : 1, d.camera.up[2] = theta > 0 ? 1 : 0;
    return d;
}

/* ---- the GGX white furnace ------------------------------------------------------------ */

/* Directional albedo of single-scattering GGX with F = 1 (height-correlated
 * Smith G2) for an outgoing direction at cos mu: integral of D G2 (wo.m) / mu
 * over the normals m, on a midpoint grid in the variables that make D cos
 * uniform (tan^2 = a^2 x / (1 - x)), written independently of the tracer. */
static double ggx_albedo(double alpha, double mu) {
    double a2 = alpha * alpha, wo[3] = {sqrt(1 - mu * mu), 0, mu};
    enum { NX = 2000, NP = 400 };
    double sum = 0;
    for (int i = 0; i < NX; i++) {
        double x = (i + 0.5) / NX, t2 = a2 * x / (1 - x), ct = 1 / sqrt(1 + t2), st = sqrt(1 - ct * ct);
        for (int j = 0; j < NP; j++) {
            double ph = 2 * PI * (j + 0.5) / NP, m[3] = {st * cos(ph), st * sin(ph), ct};
            double om = wo[0] * m[0] + wo[1] * m[1] + wo[2] * m[2];
            if (om <= 0) continue;
            double wiz = 2 * om * m[2] - wo[2];
            if (wiz <= 0) continue;
            double lam = 0.5 * (-1 + sqrt(1 + a2 * (1 - mu * mu) / (mu * mu)));
            double lami = 0.5 * (-1 + sqrt(1 + a2 * (1 - wiz * wiz) / (wiz * wiz)));
            /* samples of D cos: the integrand over D cos is G2 (wo.m) / (mu cos) */
            sum += 1 / (1 + lam + lami) * om / (mu * ct);
        }
    }
    return sum / ((double)NX * NP);
}

static void test_ggx_white_furnace(void) {
    const double roughs[2] = {0.5, 0.9}, thetas[2] = {30 * PI / 180, 70 * PI / 180};
    for (int ri = 0; ri < 2; ri++) {
        vx_svo_scene s;
        slab_scene(&s, 16, 0xFFFFFFFFu);
        char rough[32];
        snprintf(rough, sizeof rough, "%g", roughs[ri]);
        const char* kv[] = {"_type", "_metal", "_metal", "1", "_rough", rough};
        add_material(&s, 1, kv, 3);
        double sky[3] = {1, 1, 1};
        vx_probe_set ps = light_only(0, sky, 4);
        for (int ti = 0; ti < 2; ti++) {
            double target[3] = {8, 8, 1};
            vx_render_desc base = ortho_view(target, thetas[ti], 4, 8, 8);
            vx_probe_render_desc d = {.base = &base, .mode = VX_PROBE_RENDER_PATHTRACE, .spp = 1024, .seed = 3, .threads = 2};
            double expect = ggx_albedo(roughs[ri] * roughs[ri], cos(thetas[ti]));
            vx_render_image c = {0}, g = {0};
            REQUIRE(render_cpu(&s, &ps, &d, &c));
            double mc = mean_rgb(&c), mg = NAN, sc = sigma_of_mean(&c), sg = NAN;
            if (gpu && render_gpu(&s, &ps, &d, &g)) mg = mean_rgb(&g), sg = sigma_of_mean(&g);
            fprintf(stderr,
                    "  GGX rough %.2f at %2.0f deg: single-scattering albedo %.4f (loss %.1f%%); CPU %.4f +- %.4f, GPU %.4f +- %.4f\n",
                    roughs[ri], thetas[ti] * 180 / PI, expect, 100 * (1 - expect), mc, sc, mg, sg);
            /* within 4 sigma of the noise (plus 0.1% for the quadrature and float) */
            CHECK(fabs(mc - expect) < 4 * sc + 1e-3 * expect);
            if (gpu) CHECK(fabs(mg - expect) < 4 * sg + 1e-3 * expect);
            vx_render_image_free(&c), vx_render_image_free(&g);
        }
        vx_svo_scene_free(&s);
    }
    /* the quadrature sees the loss: rough grazing GGX keeps clearly less than 1 */
    CHECK(ggx_albedo(0.81, cos(70 * PI / 180)) < 0.9 && ggx_albedo(0.01, 0.9) > 0.99);
}

/* ---- the white furnace with facing metal ------------------------------------------------- */

/* A white floor (Lambert albedo 1) in a box of white mirrors (metal of metalness 1, colour white so F0 = 1,
 * roughness 0.05: GGX alpha 0.0025, whose single-scattering loss is under 1e-4), open above, under a directional
 * light whose cone is the whole upper hemisphere (angular diameter just under pi, intensity pi sin^2 of its half
 * angle: radiance 1 from every direction above the horizon), no sun, a black sky. A white furnace: every surface
 * reflects at most what it receives and nothing brings more than 1, so no pixel's expected radiance exceeds 1, and
 * with enough bounces every path leaves towards the light: 1 less the mirrors' tiny loss. The light is both
 * sampled at every vertex and met by the BSDF rays, weighed by multiple importance sampling, so the test sees
 * the weights at the mirrors (each lobe against its own pick and pdf) and at the vertex where the path's bounces
 * are spent but its metal events are not (the mirrors' specular lobe goes on: its light weighed, the Lambert
 * lobe's whole; probes/pathtrace.c vx__path, probe.comp path()): a weight counted twice would pass 1, one left out
 * would stay under it at 100 bounces (shallow paths cross the box many times: 20 bounces gave 0.95, 100 and 400
 * 0.9996 and 1.002 on the CPU, 0.991 and 0.995 on the GPU). The camera inside the box sees a mirror wall, the floor
 * and the light. CPU and GPU, the default bounces (2: with the metal events, paths of up to 6 events; 0.73) and 100. */
static uint8_t trough_cell(uint32_t x, uint32_t y, uint32_t z, uint32_t n) {
    if (z == 0) return 1;
    if (x == 0 || x == n - 1 || y == 0 || y == n - 1) return 2;
    return 0;
}

static void test_metal_white_furnace(void) {
    vx_svo_scene s;
    cells_scene(&s, 16, trough_cell);
    s.palette[1] = s.palette[2] = 0xFFFFFFFFu;
    const char* mirror[] = {"_type", "_metal", "_metal", "1", "_rough", "0.05"};
    add_material(&s, 2, mirror, 3);
    double h = 0.5 * 3.14159, black[3] = {0, 0, 0};
    vx_light hemi = {.type = VX_LIGHT_DIRECTIONAL, .direction = {0, 0, 1}, .color = {1, 1, 1},
                     .intensity = PI * sin(h) * sin(h), .angular_diameter = 2 * h};
    vx_render_desc base = {.width = 16, .height = 16};
    base.camera.set = true;
    base.camera.eye[0] = 12, base.camera.eye[1] = 8, base.camera.eye[2] = 9;
    base.camera.target[0] = 0, base.camera.target[1] = 8, base.camera.target[2] = 5;
    base.camera.up[2] = 1;
    base.camera.fov = 70;
    const uint32_t caps[2] = {2, 100};
    for (int ci = 0; ci < 2; ci++) {
        vx_probe_set ps = light_only(0, black, caps[ci]);
        vx_probe_render_desc d = {.base = &base, .mode = VX_PROBE_RENDER_PATHTRACE, .spp = 512, .seed = 4, .threads = 2,
                                  .lights = &hemi, .light_count = 1};
        vx_render_image c = {0}, g = {0};
        REQUIRE(render_cpu(&s, &ps, &d, &c));
        double mc = mean_rgb(&c), mg = NAN, sc = sigma_of_mean(&c), sg = NAN;
        if (gpu && render_gpu(&s, &ps, &d, &g)) mg = mean_rgb(&g), sg = sigma_of_mean(&g);
        fprintf(stderr, "  white furnace, facing mirrors, %u bounces: CPU %.4f +- %.4f, GPU %.4f +- %.4f\n", caps[ci], mc,
                sc, mg, sg);
        /* the pixels' spread bounds the mean's noise (they differ in mean too, so it is generous) */
        CHECKF(mc <= 1 + 4 * sc, "CPU %.4f over 1", mc);
        if (gpu) CHECKF(mg <= 1 + 4 * sg, "GPU %.4f over 1", mg);
        if (caps[ci] == 100) {
            CHECKF(mc > 0.98 - 4 * sc, "CPU %.4f: energy lost", mc);
            if (gpu) CHECKF(mg > 0.98 - 4 * sg, "GPU %.4f: energy lost", mg);
        }
        CHECK(non_finite(&c) == 0);
        vx_render_image_free(&c), vx_render_image_free(&g);
    }
    vx_svo_scene_free(&s);
}

/* ---- a partial metal where only its specular lobe goes on -------------------------------- */

/* The noise of the mean of two images' mean: the pixels' seed-to-seed differences (var of a pixel ~ d^2 / 2). */
static double noise_of_mean2(const vx_render_image* a, const vx_render_image* b) {
    size_t n = (size_t)a->width * a->height;
    double v = 0;
    for (size_t i = 0; i < n; i++) {
        double d = 0;
        for (int k = 0; k < 3; k++) d += (a->pixels[4 * i + k] - b->pixels[4 * i + k]) / 3;
        v += d * d / 2;
    }
    return sqrt(v) / n / sqrt(2.0);
}

/* A slab of half metal (metalness 0.5, roughness 0.3: a Lambert lobe and a specular one, each drawn apart) under a
 * sphere and a rect light, both large and near (the BSDF's densities are of the lights' size, so the weights
 * matter), black sky, no sun: nothing but the lights to see past the slab, so the image is the
 * slab's direct light whatever the bounces. At 0 bounces the camera's first surface has no bounce left but a
 * metal event: its specular lobe goes on (probes/pathtrace.c vx__path) and its light is weighed against that
 * lobe's sampling, while the Lambert lobe's is taken whole (a path that draws it ends); at 3 both lobes go on and
 * are weighed against their sampling. The two must give the same mean (within 4 sigma of the two-seed noise): a
 * lobe weighed against a sampling that does not go on would lose light, one taken whole where it also goes on
 * would count it twice. CPU and GPU, and the two alike at 3 bounces. */
static void test_partial_metal_spent_bounces(void) {
    vx_svo_scene s;
    slab_scene(&s, 16, 0xFF60A0E0u);
    const char* kv[] = {"_type", "_metal", "_metal", "0.5", "_rough", "0.3"};
    add_material(&s, 1, kv, 3);
    const vx_light lights[2] = {
        {.type = VX_LIGHT_SPHERE, .position = {4, 11, 4.5}, .color = {1, 0.9, 0.8}, .intensity = 3, .radius = 2.5},
        {.type = VX_LIGHT_RECT, .position = {10, 7, 3}, .direction = {-0.2, 0, -1}, .tangent = {0, 1, 0},
         .color = {0.7, 0.8, 1}, .intensity = 1, .size = {8, 10}}};
    double black[3] = {0, 0, 0}, target[3] = {8, 8, 1};
    vx_render_desc base = ortho_view(target, 35 * PI / 180, 12, 16, 16);
    double cpu3 = 0, cpu3s = 0;
    for (int dev = 0; dev < 2; dev++) {
        if (dev && !gpu) break;
        double m[2], sg[2];
        for (int bi = 0; bi < 2; bi++) {
            vx_probe_set ps = light_only(0, black, 1);
            ps.bounces = bi ? 2 : UINT32_MAX; /* the renderer's: the set's + 1, 3 or 0 */
            vx_probe_render_desc d = {.base = &base, .mode = VX_PROBE_RENDER_PATHTRACE, .spp = 512, .threads = 2,
                                      .lights = lights, .light_count = 2};
            vx_render_image a = {0}, b = {0};
            d.seed = 21;
            REQUIRE(dev ? render_gpu(&s, &ps, &d, &a) : render_cpu(&s, &ps, &d, &a));
            d.seed = 22;
            REQUIRE(dev ? render_gpu(&s, &ps, &d, &b) : render_cpu(&s, &ps, &d, &b));
            m[bi] = 0.5 * (mean_rgb(&a) + mean_rgb(&b)), sg[bi] = noise_of_mean2(&a, &b);
            vx_render_image_free(&a), vx_render_image_free(&b);
        }
        fprintf(stderr, "  half metal, %s: 0 bounces %.5f +- %.5f, 3 bounces %.5f +- %.5f\n", dev ? "GPU" : "CPU", m[0],
                sg[0], m[1], sg[1]);
        CHECK(m[0] > 0.01);
        CHECKF(fabs(m[0] - m[1]) < 4 * sqrt(sg[0] * sg[0] + sg[1] * sg[1]) + 1e-4 * m[1],
               "%s: 0 bounces %.5f against 3 bounces %.5f", dev ? "GPU" : "CPU", m[0], m[1]);
        if (!dev) cpu3 = m[1], cpu3s = sg[1];
        else /* and the devices alike (a lobe counted twice in both bounce settings shows here) */
            CHECKF(fabs(m[1] - cpu3) < 4 * sqrt(sg[1] * sg[1] + cpu3s * cpu3s) + 5e-3 * cpu3, "GPU %.5f against CPU %.5f",
                   m[1], cpu3);
    }
    vx_svo_scene_free(&s);
}

/* ---- glass of IOR 1 ------------------------------------------------------------------ */

static bool glass_on;
static uint8_t glass_cell(uint32_t x, uint32_t y, uint32_t z, uint32_t n) {
    (void)n;
    if (z == 0) return 1;
    if (glass_on && z >= 4 && z <= 5 && x >= 4 && x < 12 && y >= 4 && y < 12) return 2;
    return 0;
}

static void glass_scene(vx_svo_scene* s, bool with_glass, const char* ri, const char* rough) {
    glass_on = with_glass;
    cells_scene(s, 16, glass_cell);
    s->palette[1] = 0xFF808080u, s->palette[2] = 0xFFFFFFFFu;
    const char* kv[] = {"_type", "_glass", "_ri", ri, "_rough", rough};
    add_material(s, 2, kv, 3);
}

static void test_glass_ior1_invisible(void) {
    vx_light lights[1] = {{.type = VX_LIGHT_SPHERE, .position = {6, 9, 10}, .color = {1, 1, 1}, .intensity = 20,
                           .radius = 1.5}};
    double sky[3] = {0.3, 0.3, 0.3};
    vx_probe_set ps = light_only(0, sky, 3);
    double target[3] = {8, 8, 1};
    vx_render_desc base = ortho_view(target, 20 * PI / 180, 12, 16, 16);
    vx_probe_render_desc d = {.base = &base, .mode = VX_PROBE_RENDER_PATHTRACE, .spp = 256, .seed = 5, .threads = 2,
                              .lights = lights, .light_count = 1};
    /* IOR 1 smooth and rough: invisible; IOR 1.5: visible (the check can fail) */
    const char* roughs[3] = {"0", "0.4", "0.1"};
    const char* iors[3] = {"1", "1", "1.5"};
    for (int ri = 0; ri < 3; ri++) {
        vx_svo_scene with, without;
        glass_scene(&with, true, iors[ri], roughs[ri]);
        glass_scene(&without, false, iors[ri], roughs[ri]);
        for (int dev = 0; dev < (gpu ? 2 : 1); dev++) {
            bool (*rend)(const vx_svo_scene*, const vx_probe_set*, const vx_probe_render_desc*, vx_render_image*) =
                dev ? render_gpu : render_cpu;
            vx_render_image a = {0}, b = {0}, b2 = {0};
            d.seed = 4; /* independent of the others' streams */
            REQUIRE(rend(&with, &ps, &d, &a));
            d.seed = 5;
            REQUIRE(rend(&without, &ps, &d, &b));
            d.seed = 6;
            REQUIRE(rend(&without, &ps, &d, &b2));
            double se = 0, se0 = 0;
            size_t n = (size_t)16 * 16 * 4;
            for (size_t i = 0; i < n; i++) {
                if (i % 4 == 3) continue;
                se += (a.pixels[i] - b.pixels[i]) * (a.pixels[i] - b.pixels[i]);
                se0 += (b2.pixels[i] - b.pixels[i]) * (b2.pixels[i] - b.pixels[i]);
            }
            double ma = mean_rgb(&a), mb = mean_rgb(&b);
            fprintf(stderr, "  %s glass IOR %s rough %s: mean with/without %.4f, RMSE %.4f vs noise (other seed) %.4f\n",
                    dev ? "GPU" : "CPU", iors[ri], roughs[ri], ma / mb, sqrt(se / n), sqrt(se0 / n));
            if (ri < 2) {
                CHECK(fabs(ma / mb - 1) < 0.02);
                CHECK(sqrt(se / n) < 1.3 * sqrt(se0 / n));
            } else {
                CHECK(sqrt(se / n) > 2 * sqrt(se0 / n));
            }
            vx_render_image_free(&a), vx_render_image_free(&b), vx_render_image_free(&b2);
        }
        vx_svo_scene_free(&with), vx_svo_scene_free(&without);
    }
}

/* ---- the diffuse furnace: a closed emitting box ---------------------------------------- */

static void test_closed_box_series(void) {
    vx_svo_scene s;
    box_scene(&s, 8, 5);
    s.palette[5] = 0xFF808080u; /* albedo a = 128/255 */
    const char* kv[] = {"_type", "_emit", "_emit", "1"};
    add_material(&s, 5, kv, 2);
    double a = 128 / 255.0, sky[3] = {0, 0, 0};
    vx_render_desc base = {.width = 12, .height = 12};
    base.camera.set = true;
    base.camera.eye[0] = 4, base.camera.eye[1] = 4, base.camera.eye[2] = 4;
    base.camera.target[0] = 4, base.camera.target[1] = 0, base.camera.target[2] = 3;
    base.camera.up[2] = 1;
    base.camera.fov = 60;
    /* emission a (colour times 1) seen after k bounces: a^(k+1); a cap of b
     * bounces sums k = 0..b; Russian roulette keeps the infinite sum a / (1 - a) */
    const uint32_t caps[2] = {2, 1000};
    for (int ci = 0; ci < 2; ci++) {
        vx_probe_set ps = light_only(0, sky, caps[ci]);
        double expect = caps[ci] == 2 ? a + a * a + a * a * a : a / (1 - a);
        vx_probe_render_desc d = {.base = &base, .mode = VX_PROBE_RENDER_PATHTRACE, .spp = 256, .seed = 9, .threads = 2};
        vx_render_image c = {0}, g = {0};
        REQUIRE(render_cpu(&s, &ps, &d, &c));
        double mc = mean_rgb(&c), mg = NAN;
        if (gpu && render_gpu(&s, &ps, &d, &g)) mg = mean_rgb(&g);
        fprintf(stderr, "  closed box, albedo %.4f, %u bounces: expected %.4f, CPU %.4f, GPU %.4f\n", a, caps[ci],
                expect, mc, mg);
        CHECK(fabs(mc / expect - 1) < 0.01);
        if (gpu) CHECK(fabs(mg / expect - 1) < 0.01);
        vx_render_image_free(&c), vx_render_image_free(&g);
    }
    vx_svo_scene_free(&s);
}

/* ---- point and spot lights over a plane ----------------------------------------------- */

static void test_point_and_spot_over_plane(void) {
    vx_svo_scene s;
    slab_scene(&s, 32, 0xFF808080u);
    double a = 128 / 255.0, sky[3] = {0, 0, 0};
    vx_probe_set ps = light_only(0, sky, 2);
    double target[3] = {16, 16, 1};
    enum { W = 16 };
    vx_render_desc base = ortho_view(target, 0, 30, W, W);
    vx_light L[2] = {
        {.type = VX_LIGHT_POINT, .position = {13, 18, 7}, .color = {1, 0.5, 0.25}, .intensity = 100},
        {.type = VX_LIGHT_SPOT, .position = {16, 16, 9}, .direction = {0, 0, -1}, .color = {1, 1, 1}, .intensity = 300,
         .inner_cone = 0.2, .outer_cone = 0.5},
    };
    vx__frame f;
    vx_error err = {0};
    double lo[3], hi[3];
    vx_svo_scene_world_bounds(&s, lo, hi);
    REQUIRE(vx__frame_setup(lo, hi, &base, &f, &err) == VX_OK);
    for (int li = 0; li < 2; li++) {
        vx_probe_render_desc d = {.base = &base, .mode = VX_PROBE_RENDER_PATHTRACE, .spp = 1, .threads = 2,
                                  .lights = &L[li], .light_count = 1};
        for (int dev = 0; dev < (gpu ? 2 : 1); dev++) {
            vx_render_image im = {0};
            REQUIRE(dev ? render_gpu(&s, &ps, &d, &im) : render_cpu(&s, &ps, &d, &im));
            double worst = 0, peak = 0;
            size_t dark_ok = 0, dark = 0;
            for (size_t i = 0; i < (size_t)W * W * 4; i++) peak = fmax(peak, i % 4 == 3 ? 0 : im.pixels[i]);
            for (uint32_t y = 0; y < W; y++)
                for (uint32_t x = 0; x < W; x++) {
                    /* the pixel centre's ray meets the plane z = 1 */
                    double u = (x + 0.5) / W * 2 - 1, v = 1 - (y + 0.5) / W * 2, p[3];
                    for (int k = 0; k < 3; k++) p[k] = f.ref[k] + u * f.rx[k] + v * f.uy[k];
                    double t = (1 - p[2]) / f.fwd[2];
                    for (int k = 0; k < 3; k++) p[k] += f.fwd[k] * t;
                    double l[3], r2 = 0;
                    for (int k = 0; k < 3; k++) l[k] = L[li].position[k] - p[k], r2 += l[k] * l[k];
                    double r = sqrt(r2), ct = l[2] / r, g = L[li].intensity * ct / r2;
                    if (li == 1) {
                        double cd = -(-l[2] / r), ci = cos(L[li].inner_cone), co = cos(L[li].outer_cone);
                        double sp = fmin(1, fmax(0, (cd - co) / (ci - co)));
                        g *= sp * sp;
                    }
                    const float* px = &im.pixels[4 * ((size_t)y * W + x)];
                    for (int k = 0; k < 3; k++) {
                        double e = a / PI * g * L[li].color[k];
                        if (e == 0) {
                            dark++;
                            dark_ok += px[k] == 0;
                        } else {
                            /* float on the GPU: relative, and absolute near the spot's edge where the falloff is steep */
                            worst = fmax(worst, fabs(px[k] - e) / (e + (dev ? 0.05 * peak : 0)));
                        }
                    }
                }
            fprintf(stderr, "  %s %s light over a plane: worst relative error %.2g; %zu/%zu values outside the cone zero\n",
                    dev ? "GPU" : "CPU", li ? "spot" : "point", worst, dark_ok, dark);
            CHECK(worst < (dev ? 2e-3 : 1e-5)); /* the CPU's shading point sits 1e-6 cells off the plane */
            CHECK(dark_ok == dark);
            if (li == 1) CHECK(dark > 0);
            vx_render_image_free(&im);
        }
    }
    vx_svo_scene_free(&s);
}

/* ---- a stiff case: one voxel 10^4 times brighter than the rest --------------------------- */

static uint8_t stiff_cell(uint32_t x, uint32_t y, uint32_t z, uint32_t n) {
    if (x == 3 && y == 6 && z == 1) return 9;
    return box_cell(x, y, z, n);
}

static double rel_mse(const vx_render_image* a, const vx_render_image* ref) {
    double s = 0;
    size_t n = (size_t)a->width * a->height, m = 0;
    for (size_t i = 0; i < n; i++)
        for (int k = 0; k < 3; k++) {
            double r = ref->pixels[4 * i + k], e = a->pixels[4 * i + k] - r;
            s += e * e / (r * r + 1e-4), m++;
        }
    return s / m;
}

/* A closed 10^3 room of dim emissive walls (albedo 1/2, emission 0.01) and
 * one voxel emitting 100, seen from inside. */
static void stiff_scene(vx_svo_scene* s, vx_render_desc* base) {
    box_palette = 4;
    cells_scene(s, 10, stiff_cell);
    s->palette[4] = 0xFF808080u, s->palette[9] = 0xFFFFFFFFu;
    const char* dim[] = {"_type", "_emit", "_emit", "0.01"};
    const char* hot[] = {"_type", "_emit", "_emit", "100"};
    add_material(s, 4, dim, 2);
    add_material(s, 9, hot, 2);
    *base = (vx_render_desc){.width = 16, .height = 12};
    base->camera.set = true;
    base->camera.eye[0] = 8, base->camera.eye[1] = 2, base->camera.eye[2] = 7;
    base->camera.target[0] = 4, base->camera.target[1] = 7, base->camera.target[2] = 2;
    base->camera.up[2] = 1;
    base->camera.fov = 70;
}

static void test_stiff_emitter(void) {
    vx_svo_scene s;
    vx_render_desc base;
    stiff_scene(&s, &base);
    double sky[3] = {0, 0, 0};
    vx_probe_set ps = light_only(0, sky, 6);
    vx_probe_render_desc d = {.base = &base, .mode = VX_PROBE_RENDER_PATHTRACE, .spp = 8192, .seed = 100, .threads = 2};
    vx_render_image ref = {0};
    REQUIRE(render_cpu(&s, &ps, &d, &ref));
    const uint32_t spps[4] = {16, 64, 256, 1024};
    double e[4];
    for (int i = 0; i < 4; i++) {
        vx_render_image im = {0};
        d.spp = spps[i], d.seed = 200 + i;
        REQUIRE(render_cpu(&s, &ps, &d, &im));
        /* the reference's own error adds about relMSE(8192) */
        e[i] = rel_mse(&im, &ref);
        vx_render_image_free(&im);
    }
    fprintf(stderr, "  stiff emitter, relMSE x spp: %.3g %.3g %.3g %.3g at 16 64 256 1024 spp\n", e[0] * 16, e[1] * 64,
            e[2] * 256, e[3] * 1024);
    /* 1/spp: relMSE x spp about constant (the reference's own error adds 1/8
     * at 1024 spp; no firefly makes the low counts much worse or the high
     * counts stall) */
    double lo = INFINITY, hi = 0;
    for (int i = 0; i < 4; i++) lo = fmin(lo, e[i] * spps[i]), hi = fmax(hi, e[i] * spps[i]);
    CHECKF(hi < 1.6 * lo, "relMSE x spp from %.3g to %.3g", lo, hi);
    if (gpu) {
        vx_render_image g = {0};
        d.spp = 1024, d.seed = 300;
        REQUIRE(render_gpu(&s, &ps, &d, &g));
        double rg = rel_mse(&g, &ref);
        fprintf(stderr, "  GPU 1024 spp: relMSE %.3g (CPU %.3g), mean GPU/CPU reference %.4f\n", rg, e[3],
                mean_rgb(&g) / mean_rgb(&ref));
        CHECK(rg < 2 * e[3]);
        CHECK(fabs(mean_rgb(&g) / mean_rgb(&ref) - 1) < 0.02);
        vx_render_image_free(&g);
    }
    vx_render_image_free(&ref);
    vx_svo_scene_free(&s);
}

/* ---- degenerate lights give finite images ----------------------------------------------- */

static void test_degenerate_lights_finite(void) {
    vx_svo_scene s;
    room_scene(&s);
    const char* glass[] = {"_type", "_glass", "_ior", "0.5", "_rough", "0.2"};
    const char* metal[] = {"_type", "_metal", "_rough", "0"};
    add_material(&s, 3, metal, 2);
    add_material(&s, 4, glass, 3);
    vx_light L[] = {
        {.type = VX_LIGHT_POINT, .position = {5.5, 5.5, 1.5}, .color = {1, 1, 1}, .intensity = 50},  /* inside a voxel */
        {.type = VX_LIGHT_POINT, .position = {3, 4, 1}, .color = {1, 1, 1}, .intensity = 50},        /* on the floor */
        {.type = VX_LIGHT_SPOT, .position = {6, 6, 8}, .direction = {0, 0, -1}, .color = {1, 1, 1}, .intensity = 50},
        {.type = VX_LIGHT_SPHERE, .position = {5.5, 6.5, 0.5}, .color = {1, 1, 1}, .intensity = 5, .radius = 0.2},
        {.type = VX_LIGHT_SPHERE, .position = {8, 8, 1 + 1e-9}, .color = {1, 1, 1}, .intensity = 5, .radius = 0},
        {.type = VX_LIGHT_RECT, .position = {8, 3, 1}, .direction = {0, 0, 1}, .tangent = {1, 0, 0}, .color = {1, 1, 1},
         .intensity = 5, .size = {2, 0}},
        {.type = VX_LIGHT_RECT, .position = {8, 3, 1}, .direction = {0, 0, 1}, .tangent = {1, 0, 0}, .color = {1, 1, 1},
         .intensity = 5, .size = {2, 2}},
        {.type = VX_LIGHT_DIRECTIONAL, .direction = {0.2, 0.1, 1}, .color = {1, 1, 1}, .intensity = 2,
         .angular_diameter = 1e-7},
        {.type = VX_LIGHT_DIRECTIONAL, .direction = {-0.2, 0.1, 1}, .color = {1, 1, 1}, .intensity = 2,
         .angular_diameter = 2e-6},
        {.type = VX_LIGHT_SPOT, .position = {4, 4, 9}, .direction = {0, 0, -1}, .color = {1, 1, 1}, .intensity = 50,
         .inner_cone = 0, .outer_cone = 1e-9},
    };
    double sky[3] = {0.2, 0.2, 0.2};
    vx_probe_set ps = light_only(0, sky, 3);
    vx_render_desc base = {.width = 24, .height = 16};
    for (int dev = 0; dev < (gpu ? 2 : 1); dev++)
        for (int m = 0; m < 2; m++) {
            vx_probe_render_mode mode = m ? VX_PROBE_RENDER_PT_INDIRECT : VX_PROBE_RENDER_PATHTRACE;
            vx_probe_render_desc d = {.base = &base, .mode = mode, .spp = 16, .threads = 2, .lights = L,
                                      .light_count = sizeof L / sizeof L[0]};
            vx_render_image im = {0};
            REQUIRE(dev ? render_gpu(&s, &ps, &d, &im) : render_cpu(&s, &ps, &d, &im));
            size_t bad = non_finite(&im);
            CHECKF(bad == 0, "%s %s: %zu non-finite values", dev ? "GPU" : "CPU", vx_probe_render_mode_name(mode), bad);
            CHECK(mean_rgb(&im) > 0);
            vx_render_image_free(&im);
        }
    vx_svo_scene_free(&s);
}

/* ---- every material and light: GPU against CPU, convergence ---------------------------- */

static uint8_t all_cell(uint32_t x, uint32_t y, uint32_t z, uint32_t n) {
    if (z == 0) return 3;                                        /* floor: diffuse */
    if (x == 0 || y == n - 1) return 4;                          /* walls: rough metal */
    if (x >= 6 && x <= 8 && y >= 2 && y <= 4 && z <= 3) return 6; /* a glass block */
    if (x >= 2 && x <= 3 && y >= 6 && y <= 8 && z <= 2) return 7; /* a mirror block */
    if (x == 9 && y == 9 && z == 1) return 9;                    /* a lamp voxel */
    return 0;
}

static void all_scene(vx_svo_scene* s) {
    cells_scene(s, 12, all_cell);
    s->palette[3] = 0xFF90A0B0u, s->palette[4] = 0xFF60A0E0u, s->palette[6] = 0xFFE0FFF0u;
    s->palette[7] = 0xFFFFFFFFu, s->palette[9] = 0xFFA0E0FFu;
    const char* metal[] = {"_type", "_metal", "_rough", "0.4", "_metal", "0.7"};
    const char* glass[] = {"_type", "_glass", "_ior", "0.5", "_rough", "0.05"};
    const char* mirror[] = {"_type", "_metal", "_rough", "0.02"};
    const char* lamp[] = {"_type", "_emit", "_emit", "4", "_flux", "1"};
    add_material(s, 4, metal, 3);
    add_material(s, 6, glass, 3);
    add_material(s, 7, mirror, 2);
    add_material(s, 9, lamp, 3);
}

static const vx_light all_lights[] = {
    {.type = VX_LIGHT_DIRECTIONAL, .direction = {0.4, -0.5, 0.8}, .color = {1, 0.9, 0.8}, .intensity = 2,
     .angular_diameter = 0.3},
    {.type = VX_LIGHT_SPOT, .position = {9, 3, 9}, .direction = {-0.3, 0.2, -1}, .color = {1, 1, 1}, .intensity = 60,
     .inner_cone = 0.3, .outer_cone = 0.6},
    {.type = VX_LIGHT_SPHERE, .position = {4, 4, 7}, .color = {1, 0.8, 0.6}, .intensity = 6, .radius = 0.7},
    {.type = VX_LIGHT_RECT, .position = {7, 8, 10}, .direction = {0, 0, -1}, .tangent = {1, 0, 0}, .color = {0.6, 0.8, 1},
     .intensity = 4, .size = {3, 2}},
};

static void test_all_materials_gpu_vs_cpu(void) {
    if (!gpu) SKIP("no Vulkan device");
    vx_svo_scene s;
    all_scene(&s);
    double sky[3] = {0.2, 0.25, 0.3};
    vx_probe_set ps = light_only(0, sky, 4);
    vx_render_desc base = {.width = 24, .height = 16};
    vx_probe_render_desc d = {.base = &base, .mode = VX_PROBE_RENDER_PATHTRACE, .spp = 256, .seed = 1, .threads = 2,
                              .lights = all_lights, .light_count = sizeof all_lights / sizeof all_lights[0]};
    vx_render_image c = {0}, g = {0}, c2 = {0}, g2 = {0};
    REQUIRE(render_cpu(&s, &ps, &d, &c));
    REQUIRE(render_gpu(&s, &ps, &d, &g));
    d.seed = 2;
    REQUIRE(render_cpu(&s, &ps, &d, &c2));
    REQUIRE(render_gpu(&s, &ps, &d, &g2));
    /* per pixel: the two devices' means (two seeds each) within 4 times the
     * pixel's noise (the seeds' spread) plus 3% for float geometry at edges
     * and grazing shadow rays; the image means within 1% */
    size_t n = (size_t)24 * 16, ok = 0;
    for (size_t i = 0; i < n; i++) {
        double a = 0, a2 = 0, b = 0, b2 = 0;
        for (int k = 0; k < 3; k++)
            a += c.pixels[4 * i + k], a2 += c2.pixels[4 * i + k], b += g.pixels[4 * i + k], b2 += g2.pixels[4 * i + k];
        double cm = 0.5 * (a + a2), gm = 0.5 * (b + b2), noise = 0.5 * (fabs(a - a2) + fabs(b - b2));
        ok += fabs(cm - gm) <= 4 * noise + 0.03 * cm + 1e-3;
    }
    double ratio = (mean_rgb(&g) + mean_rgb(&g2)) / (mean_rgb(&c) + mean_rgb(&c2));
    fprintf(stderr, "  every material and light, 256 spp x 2 seeds: mean GPU/CPU %.4f, %zu/%zu pixels agree within noise\n",
            ratio, ok, n);
    CHECK(fabs(ratio - 1) < 0.01);
    CHECK(ok >= n * 95 / 100);
    vx_render_image_free(&c), vx_render_image_free(&g), vx_render_image_free(&c2), vx_render_image_free(&g2);
    vx_svo_scene_free(&s);
}

/* The goal: an image at N samples within 1% relMSE of the image at 4N, on
 * the test scenes: every material and light at N = 256; the stiff emitter
 * (relMSE x spp about 7: N = 1024); a glass slab of IOR 1.5 under a sphere
 * light (the floor under the glass sees the light only through BSDF rays
 * that cross the glass: N = 2048). */
static void test_converges_to_itself(void) {
    bool dev = gpu != NULL; /* the GPU when there is one: faster than the reference on lavapipe */
    for (int sc = 0; sc < 3; sc++) {
        vx_svo_scene s;
        vx_render_desc base = {.width = 24, .height = 16};
        double sky_all[3] = {0.2, 0.25, 0.3}, black[3] = {0, 0, 0}, grey[3] = {0.3, 0.3, 0.3};
        vx_light sphere = {.type = VX_LIGHT_SPHERE, .position = {6, 9, 10}, .color = {1, 1, 1}, .intensity = 20,
                           .radius = 1.5};
        vx_probe_render_desc d = {.base = &base, .mode = VX_PROBE_RENDER_PATHTRACE, .threads = 2};
        vx_probe_set ps;
        const char* name;
        const uint32_t spp[3] = {256, 1024, 2048};
        if (sc == 0) {
            all_scene(&s);
            ps = light_only(0, sky_all, 4);
            d.lights = all_lights, d.light_count = sizeof all_lights / sizeof all_lights[0];
            name = "every material and light";
        } else if (sc == 1) {
            stiff_scene(&s, &base);
            ps = light_only(0, black, 6);
            name = "stiff emitter";
        } else {
            glass_scene(&s, true, "1.5", "0.1");
            double target[3] = {8, 8, 1};
            base = ortho_view(target, 20 * PI / 180, 12, 16, 16);
            ps = light_only(0, grey, 3);
            d.lights = &sphere, d.light_count = 1;
            name = "glass IOR 1.5, sphere light";
        }
        vx_render_image a = {0}, b = {0};
        d.spp = 4 * spp[sc], d.seed = 11;
        REQUIRE(dev ? render_gpu(&s, &ps, &d, &b) : render_cpu(&s, &ps, &d, &b));
        d.spp = spp[sc], d.seed = 12;
        REQUIRE(dev ? render_gpu(&s, &ps, &d, &a) : render_cpu(&s, &ps, &d, &a));
        double e = rel_mse(&a, &b);
        fprintf(stderr, "  %s (%s): relMSE of %u spp against %u spp %.4f\n", name, dev ? "GPU" : "CPU", spp[sc],
                4 * spp[sc], e);
        CHECK(e < 0.01);
        vx_render_image_free(&a), vx_render_image_free(&b);
        vx_svo_scene_free(&s);
    }
}

/* The pass pipeline with lights and gi=pathtrace: direct pass + gi pass
 * estimate what the path tracer renders whole (pixel centres: spp 1 both);
 * a frame whose lights are not the method's is refused. metal: the floor
 * (palette 3) a rough metal, so the direct pass shades it with the metal
 * BRDF and the gi pass must continue its paths by that lobe too (the light
 * the walls and the lamp send to the floor and the floor on to the eye). */
static void pipeline_lights_with_pathtrace_gi(bool metal) {
    if (!gpu) SKIP("no Vulkan device");
    vx_svo_scene s;
    room_scene(&s);
    if (metal) {
        const char* kv[] = {"_type", "_metal", "_metal", "0.8", "_rough", "0.35", "_spec", "0.5"};
        add_material(&s, 3, kv, 4);
    }
    vx_error err = {0};
    vx_render_scene* rs = NULL;
    REQUIRE(vx_render_scene_create(gpu, &s, &rs, &err) == VX_OK);
    vx_frame_renderer* fr = NULL;
    REQUIRE(vx_frame_renderer_create(rs, &s, &fr, &err) == VX_OK);
    vx_light L[3] = {{.type = VX_LIGHT_POINT, .position = {8, 3, 6}, .color = {1, 0.9, 0.7}, .intensity = 40},
                     {.type = VX_LIGHT_SPOT, .position = {3, 8, 9}, .direction = {0.2, -0.1, -1}, .color = {0.6, 0.8, 1},
                      .intensity = 80, .inner_cone = 0.3, .outer_cone = 0.7},
                     {.type = VX_LIGHT_SPHERE, .position = {7, 7, 11}, .color = {1, 1, 1}, .intensity = 30, .radius = 0.3}};
    vx_probe_render_desc pd = {.spp = 256, .bounces = 3, .seed = 7, .lights = L, .light_count = 3};
    vx_gi_method gm;
    vx_probe_gi* pgi = NULL;
    REQUIRE(vx_probe_gi_create(rs, &s, NULL, "pathtrace", &pd, &gm, &pgi, &err) == VX_OK);
    vx_pass_list list;
    REQUIRE(vx_pass_list_parse("gbuffer,direct,gi=pathtrace", &list, &err) == VX_OK);
    vx_frame_desc fd = vx_frame_desc_defaults();
    fd.base.width = 24, fd.base.height = 16;
    fd.passes = &list;
    fd.gi = &gm;
    fd.lights = L, fd.light_count = 3;
    vx_frame_result res = {0};
    vx_result r = vx_frame_render(fr, &fd, &res, &err);
    if (r) fprintf(stderr, "  frame: %s\n", err.msg);
    REQUIRE(r == VX_OK);
    vx_render_desc base = fd.base;
    for (int k = 0; k < 3; k++) base.light_dir[k] = gm.light_dir[k];
    vx_probe_render_desc rd = pd;
    rd.base = &base, rd.mode = VX_PROBE_RENDER_PATHTRACE, rd.spp = 256, rd.seed = 8;
    rd.pixel_centre = true; /* as the G-buffer */
    vx_render_image ref = {0}, ref2 = {0};
    REQUIRE(vx_probe_render_gpu(rs, &s, NULL, &rd, &ref, &err) == VX_OK);
    rd.seed = 9;
    REQUIRE(vx_probe_render_gpu(rs, &s, NULL, &rd, &ref2, &err) == VX_OK);
    double se = 0, se0 = 0;
    size_t n = (size_t)24 * 16 * 4;
    for (size_t i = 0; i < n; i++) {
        if (i % 4 == 3) continue;
        se += (res.image.pixels[i] - ref.pixels[i]) * (res.image.pixels[i] - ref.pixels[i]);
        se0 += (ref2.pixels[i] - ref.pixels[i]) * (ref2.pixels[i] - ref.pixels[i]);
    }
    double ratio = mean_rgb(&res.image) / mean_rgb(&ref);
    fprintf(stderr, "  pipeline direct + gi=pathtrace vs the path tracer%s: mean %.4f, RMSE %.4f vs noise %.4f\n",
            metal ? " (metal floor)" : "", ratio, sqrt(se / n), sqrt(se0 / n));
    CHECK(fabs(ratio - 1) < 0.02);
    CHECK(sqrt(se / n) < 1.3 * sqrt(se0 / n));
    vx_light other[3];
    memcpy(other, L, sizeof other);
    fd.lights = other;
    vx_frame_result bad = {0};
    CHECK(vx_frame_render(fr, &fd, &bad, &err) == VX_ERR_UNSUPPORTED);
    vx_render_image_free(&bad.image);
    vx_render_image_free(&ref), vx_render_image_free(&ref2), vx_render_image_free(&res.image);
    vx_probe_gi_destroy(pgi);
    vx_frame_renderer_destroy(fr);
    vx_render_scene_destroy(rs);
    vx_svo_scene_free(&s);
}

static void test_pipeline_lights_with_pathtrace_gi(void) { pipeline_lights_with_pathtrace_gi(false); }
static void test_pipeline_metal_with_pathtrace_gi(void) { pipeline_lights_with_pathtrace_gi(true); }

/* Lamps of emissive voxels as lights (vx_svo_emissive_lights, svo_render
 * --voxel-lights): the pass pipeline (direct pass with the clusters' sphere
 * lights + gi=pathtrace) against the path tracer, which samples the voxels
 * themselves, on the lamps' own pixels (white albedo: only the lamp is
 * white). A lamp's face lies inside its cluster's sphere: lit by it on top of
 * its emission the lamp showed 15-20% brighter (docs/PERFORMANCE.md 11).
 * Without gi the lamp shows its emission too (the radiometric model). */
static void test_pipeline_lamp_pixels(void) {
    if (!gpu) SKIP("no Vulkan device");
    vx_svo_scene s;
    room_scene(&s);
    vx_error err = {0};
    vx_light* L = NULL;
    uint32_t nl = 0;
    REQUIRE(vx_svo_emissive_lights(&s, NULL, &L, &nl, &err) == VX_OK);
    REQUIRE(nl > 0);
    vx_render_scene* rs = NULL;
    REQUIRE(vx_render_scene_create(gpu, &s, &rs, &err) == VX_OK);
    vx_frame_renderer* fr = NULL;
    REQUIRE(vx_frame_renderer_create(rs, &s, &fr, &err) == VX_OK);
    double sky[3] = {0, 0, 0};
    vx_probe_set ps = light_only(0, sky, 3); /* no sun, no sky: the lamp alone */
    vx_probe_render_desc pd = {.spp = 64, .bounces = 3, .seed = 7, .lights = L, .light_count = nl};
    vx_gi_method gm;
    vx_probe_gi* pgi = NULL;
    REQUIRE(vx_probe_gi_create(rs, &s, &ps, "pathtrace", &pd, &gm, &pgi, &err) == VX_OK);
    vx_pass_list list, plain;
    REQUIRE(vx_pass_list_parse("gbuffer,direct,gi=pathtrace", &list, &err) == VX_OK);
    REQUIRE(vx_pass_list_parse("gbuffer,direct", &plain, &err) == VX_OK);
    vx_frame_desc fd = vx_frame_desc_defaults();
    fd.base.width = 32, fd.base.height = 24;
    fd.base.camera.set = true;
    fd.base.camera.eye[0] = 11, fd.base.camera.eye[1] = 1, fd.base.camera.eye[2] = 6;
    fd.base.camera.target[0] = 6, fd.base.camera.target[1] = 6, fd.base.camera.target[2] = 1.5;
    fd.base.camera.up[2] = 1, fd.base.camera.fov = 50;
    fd.passes = &list;
    fd.gi = &gm;
    fd.lights = L, fd.light_count = nl;
    vx_frame_result res = {0}, alb = {0}, dir = {0};
    REQUIRE(vx_frame_render(fr, &fd, &res, &err) == VX_OK);
    vx_frame_desc fa = fd;
    fa.show = VX_SHOW_ALBEDO;
    REQUIRE(vx_frame_render(fr, &fa, &alb, &err) == VX_OK);
    vx_frame_desc fp = fd;
    fp.passes = &plain, fp.gi = NULL;
    fp.sky[0] = fp.sky[1] = fp.sky[2] = 0; /* as the path tracer's */
    REQUIRE(vx_frame_render(fr, &fp, &dir, &err) == VX_OK);
    vx_render_desc base = fd.base;
    for (int k = 0; k < 3; k++) base.light_dir[k] = gm.light_dir[k];
    vx_probe_render_desc rd = pd;
    rd.base = &base, rd.mode = VX_PROBE_RENDER_PATHTRACE, rd.spp = 256, rd.seed = 8;
    rd.lights = NULL, rd.light_count = 0; /* the voxels themselves */
    rd.pixel_centre = true;
    vx_render_image ref = {0};
    REQUIRE(vx_probe_render_gpu(rs, &s, &ps, &rd, &ref, &err) == VX_OK);
    double lamp = 0, lamp_ref = 0, lamp_plain = 0;
    size_t nlamp = 0, npx = (size_t)fd.base.width * fd.base.height;
    for (size_t i = 0; i < npx; i++) {
        const float* a = alb.image.pixels + 4 * i;
        if (!(a[0] > 0.999f && a[1] > 0.999f && a[2] > 0.999f)) continue;
        for (int k = 0; k < 3; k++)
            lamp += res.image.pixels[4 * i + k], lamp_ref += ref.pixels[4 * i + k], lamp_plain += dir.image.pixels[4 * i + k];
        nlamp++;
    }
    double ratio = lamp / lamp_ref, ratio_plain = lamp_plain / lamp_ref;
    fprintf(stderr, "  lamp pixels (%zu, %u voxel lights): pipeline / path tracer %.4f, direct only %.4f\n", nlamp, nl,
            ratio, ratio_plain);
    CHECK(nlamp >= 20);
    CHECKF(fabs(ratio - 1) < 0.03, "the lamp's pixels: %.4f of the path tracer's", ratio);
    /* direct only: the emission (1 here) and no light from the lamp itself;
     * the path tracer adds what bounces back from the room */
    CHECKF(ratio_plain > 0.85 && ratio_plain <= 1.0 + 1e-3, "direct only: %.4f of the path tracer's", ratio_plain);
    vx_render_image_free(&ref);
    vx_render_image_free(&res.image), vx_render_image_free(&alb.image), vx_render_image_free(&dir.image);
    vx_probe_gi_destroy(pgi);
    vx_frame_renderer_destroy(fr);
    vx_render_scene_destroy(rs);
    vx_free(NULL, L);
    vx_svo_scene_free(&s);
}

int main(void) {
    (void)ts_random_model;
    dlopen("libvulkan_lvp.so", RTLD_NOW | RTLD_NODELETE); /* see test_probes_gpu.c */
    vx_error err = {0};
    if (vx_gpu_create(&(vx_gpu_desc){0}, &gpu, &err)) {
        fprintf(stderr, "no Vulkan device (%s): GPU comparisons skipped\n", err.msg);
        gpu = NULL;
    }
    RUN(test_ggx_white_furnace);
    RUN(test_metal_white_furnace);
    RUN(test_partial_metal_spent_bounces);
    RUN(test_glass_ior1_invisible);
    RUN(test_closed_box_series);
    RUN(test_point_and_spot_over_plane);
    RUN(test_stiff_emitter);
    RUN(test_degenerate_lights_finite);
    RUN(test_all_materials_gpu_vs_cpu);
    RUN(test_converges_to_itself);
    RUN(test_pipeline_lights_with_pathtrace_gi);
    RUN(test_pipeline_metal_with_pathtrace_gi);
    RUN(test_pipeline_lamp_pixels);
    if (gpu) vx_gpu_destroy(gpu);
    return vx_test_finish();
}
