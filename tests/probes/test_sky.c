/* tests/probes/test_sky.c - the path tracer's sky by direction (issue 11):
 * gradient and environment-map skies (vx_probe_render_desc.sky) on the CPU
 * reference (probes/pathtrace.c) and the GPU (probes/shaders/probe.comp).
 *  - rays that leave the scene see the sky's definition (svo/svo.h), written
 *    out here from the documented mapping: gradient by the direction's z,
 *    the map's texel by azimuth and polar angle, turned by the rotation;
 *  - a scene lit by a gradient and by a map with a bright patch renders the
 *    same on the GPU as on the CPU within the noise;
 *  - a white furnace: a convex block of albedo 1 under an environment map of
 *    constant value c (written as an EXR and read back through OpenImageIO)
 *    is c at every pixel, and equals the same render under a constant sky.
 * The GPU parts skip without a Vulkan device. */
#define _DEFAULT_SOURCE /* mkdtemp */
#include <dlfcn.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "formats/image.h"
#include "probes/probes.h"
#include "render/pipeline.h"
#include "render/trace.h"
#include "tests/probes/probe_scenes.h"
#include "tests/test.h"

static const double PI = 3.14159265358979323846;
static vx_gpu* gpu;

static bool render(bool on_gpu, const vx_svo_scene* s, const vx_probe_set* ps, const vx_probe_render_desc* d,
                   vx_render_image* out) {
    vx_error err = {0};
    vx_result r;
    if (!on_gpu) {
        r = vx_probe_render(s, ps, d, out, &err);
    } else {
        vx_render_scene* rs = NULL;
        r = vx_render_scene_create(gpu, s, &rs, &err);
        if (!r) r = vx_probe_render_gpu(rs, s, ps, d, out, &err);
        vx_render_scene_destroy(rs);
    }
    if (r) fprintf(stderr, "  %s render: %s\n", on_gpu ? "GPU" : "CPU", err.msg);
    return r == VX_OK;
}

/* A block of palette 1 over x, y in [4, 12), z in [0, h) of a 16^3 model. */
static uint32_t block_h;
static uint8_t block_cell(uint32_t x, uint32_t y, uint32_t z, uint32_t n) {
    (void)n;
    return x >= 4 && x < 12 && y >= 4 && y < 12 && z < block_h ? 1 : 0;
}
/* The block, and for the lit scene a floor and a pillar (palette 2). */
static uint8_t lit_cell(uint32_t x, uint32_t y, uint32_t z, uint32_t n) {
    (void)n;
    if (z == 0) return 2;
    return x >= 6 && x < 9 && y >= 6 && y < 9 && z < 9 ? 1 : 0;
}

/* An orthographic camera whose rays all travel along unit dir. */
static vx_render_desc along(const double target[3], const double dir[3], uint32_t w, uint32_t h) {
    vx_render_desc d = {.width = w, .height = h};
    d.camera.set = true, d.camera.ortho = true, d.camera.ortho_height = 2;
    for (int k = 0; k < 3; k++) d.camera.eye[k] = target[k] - 40 * dir[k], d.camera.target[k] = target[k];
    d.camera.up[0] = fabs(dir[0]) > 0.9 ? 0 : 1, d.camera.up[1] = fabs(dir[0]) > 0.9 ? 1 : 0;
    return d;
}

static void unit(double d[3]) {
    double l = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    for (int k = 0; k < 3; k++) d[k] /= l;
}

/* Largest difference of any pixel's rgb from want, relative to max(want). */
static double worst(const vx_render_image* im, const double want[3]) {
    double m = fmax(want[0], fmax(want[1], want[2])), e = 0;
    for (size_t i = 0; i < (size_t)im->width * im->height; i++)
        for (int k = 0; k < 3; k++) {
            double v = im->pixels[4 * i + k];
            e = isfinite(v) ? fmax(e, fabs(v - want[k]) / m) : INFINITY;
        }
    return e;
}

/* ---- what a ray that leaves the scene sees -------------------------------------------- */

static void test_sky_seen_by_misses(void) {
    vx_svo_scene s;
    block_h = 2;
    cells_scene(&s, 16, block_cell);
    double black[3] = {0, 0, 0};
    vx_probe_set ps = light_only(0, black, 2);
    const double far[3] = {500, 500, 500}; /* the block stays out of view */
    /* gradient: zenith, horizon, ground */
    vx_sky grad = {.type = VX_SKY_GRADIENT, .color = {0.2, 0.4, 1.0}, .horizon = {0.9, 0.8, 0.7}, .ground = {0.3, 0.2, 0.1}};
    const double dirs[4][3] = {{0.8, 0.1, 0.5}, {-0.3, 0.6, -0.3}, {0, 0, 1}, {0.5, -0.7, 0.0}};
    for (int i = 0; i < 4; i++) {
        double d0[3] = {dirs[i][0], dirs[i][1], dirs[i][2]};
        unit(d0);
        double want[3];
        for (int k = 0; k < 3; k++)
            want[k] = d0[2] >= 0 ? grad.horizon[k] * (1 - d0[2]) + grad.color[k] * d0[2] : grad.ground[k];
        vx_render_desc base = along(far, d0, 6, 4);
        vx_probe_render_desc d = {.base = &base, .mode = VX_PROBE_RENDER_PATHTRACE, .spp = 2, .seed = 1, .sky = &grad};
        for (int g = 0; g < 2; g++) {
            if (g && !gpu) continue;
            vx_render_image im = {0};
            REQUIRE(render(g, &s, &ps, &d, &im));
            double e = worst(&im, want);
            CHECKF(e < (g ? 1e-5 : 1e-6), "gradient, direction (%.2f %.2f %.2f), %s: off by %.3g", d0[0], d0[1], d0[2],
                   g ? "GPU" : "CPU", e);
            vx_render_image_free(&im);
        }
    }
    /* an 8x4 map whose texel (x, y) is (x + 1, y + 1, 0.5), intensity 2,
     * turned by 0.3 rad: the direction at azimuth phi and polar angle theta
     * sees texel (floor(8 (phi - 0.3) / 2 pi) mod 8, floor(4 theta / pi)) */
    enum { W = 8, H = 4 };
    float tex[W * H * 3];
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) tex[3 * (y * W + x)] = x + 1.0f, tex[3 * (y * W + x) + 1] = y + 1.0f, tex[3 * (y * W + x) + 2] = 0.5f;
    vx_sky_texels map = {.rgb = tex, .width = W, .height = H};
    vx_sky env = {.type = VX_SKY_ENVMAP, .intensity = 2, .rotation = 0.3, .path = "map.exr"};
    /* texel centres and points well inside texels, both hemispheres, both
     * sides of the azimuth's wrap */
    const double at[5][2] = {{0.5, 0.5}, {6.3, 1.2}, {7.8, 2.9}, {2.2, 3.6}, {0.1, 1.7}};
    for (int i = 0; i < 5; i++) {
        double phi = 0.3 + at[i][0] * 2 * PI / W, theta = at[i][1] * PI / H;
        double d0[3] = {sin(theta) * cos(phi), sin(theta) * sin(phi), cos(theta)};
        int tx = (int)at[i][0], ty = (int)at[i][1];
        double want[3] = {2.0 * (tx + 1), 2.0 * (ty + 1), 1.0};
        vx_render_desc base = along(far, d0, 4, 4);
        base.camera.ortho_height = 1e-3; /* every pixel's ray along d0 from nearly one point */
        vx_probe_render_desc d = {.base = &base, .mode = VX_PROBE_RENDER_PATHTRACE, .spp = 1, .seed = 1, .sky = &env,
                                  .sky_map = &map};
        for (int g = 0; g < 2; g++) {
            if (g && !gpu) continue;
            vx_render_image im = {0};
            REQUIRE(render(g, &s, &ps, &d, &im));
            double e = worst(&im, want);
            CHECKF(e < 1e-6, "map texel (%d, %d), %s: off by %.3g (pixel 0: %g %g %g)", tx, ty, g ? "GPU" : "CPU", e,
                   im.pixels[0], im.pixels[1], im.pixels[2]);
            vx_render_image_free(&im);
        }
    }
    /* a map sky without texels is an error, not a black sky */
    vx_probe_render_desc d = {.mode = VX_PROBE_RENDER_PATHTRACE, .spp = 1, .sky = &env};
    vx_render_image im = {0};
    vx_error err = {0};
    CHECK(vx_probe_render(&s, &ps, &d, &im, &err) == VX_ERR_INVALID_ARG && strstr(err.msg, "map.exr"));
    vx_svo_scene_free(&s);
}

/* ---- a lit scene: GPU against the CPU reference ---------------------------------------- */

static void test_gpu_equals_cpu(void) {
    if (!gpu) SKIP("no Vulkan device");
    vx_svo_scene s;
    cells_scene(&s, 16, lit_cell);
    s.palette[1] = 0xFFC0C0C0u, s.palette[2] = 0xFF8060A0u;
    double black[3] = {0, 0, 0};
    vx_probe_set ps = light_only(0, black, 3);
    /* a map: dim blue sky, a bright patch (a sun of many texels) low in the west */
    enum { W = 64, H = 32 };
    float* tex = malloc(sizeof(float) * W * H * 3);
    REQUIRE(tex);
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            bool sun = x >= 28 && x < 38 && y >= 7 && y < 13;
            float* t = tex + 3 * (y * W + x);
            t[0] = sun ? 8.0f : 0.2f, t[1] = sun ? 7.0f : 0.3f, t[2] = sun ? 6.0f : (y < H / 2 ? 0.6f : 0.1f);
        }
    vx_sky_texels map = {.rgb = tex, .width = W, .height = H};
    vx_sky skies[2] = {{.type = VX_SKY_GRADIENT, .color = {0.3, 0.5, 1.2}, .horizon = {1.0, 0.9, 0.8}, .ground = {0.2, 0.15, 0.1}},
                       {.type = VX_SKY_ENVMAP, .intensity = 1.5, .rotation = -0.7, .path = "sun.exr"}};
    for (int k = 0; k < 2; k++) {
        vx_render_desc base = {.width = 24, .height = 16};
        vx_probe_render_desc d = {.base = &base, .mode = VX_PROBE_RENDER_PATHTRACE, .spp = 256, .seed = 1, .threads = 2,
                                  .sky = &skies[k], .sky_map = &map};
        vx_render_image c = {0}, g = {0}, c2 = {0}, g2 = {0};
        REQUIRE(render(false, &s, &ps, &d, &c) && render(true, &s, &ps, &d, &g));
        d.seed = 2;
        REQUIRE(render(false, &s, &ps, &d, &c2) && render(true, &s, &ps, &d, &g2));
        /* per pixel within 4 times the seeds' spread plus 3% (float geometry
         * at edges); the image means within 1% (as test_pathtrace's check) */
        size_t n = (size_t)24 * 16, ok = 0;
        double sc = 0, sg = 0;
        for (size_t i = 0; i < n; i++) {
            double a = 0, a2 = 0, b = 0, b2 = 0;
            for (int q = 0; q < 3; q++)
                a += c.pixels[4 * i + q], a2 += c2.pixels[4 * i + q], b += g.pixels[4 * i + q], b2 += g2.pixels[4 * i + q];
            double cm = 0.5 * (a + a2), gm = 0.5 * (b + b2), noise = 0.5 * (fabs(a - a2) + fabs(b - b2));
            ok += fabs(cm - gm) <= 4 * noise + 0.03 * cm + 1e-3;
            sc += cm, sg += gm;
        }
        fprintf(stderr, "  %s sky, 256 spp x 2 seeds: mean GPU/CPU %.4f, %zu/%zu pixels agree within noise\n",
                k ? "environment map" : "gradient", sg / sc, ok, n);
        CHECK(fabs(sg / sc - 1) < 0.01);
        CHECK(ok >= n * 95 / 100);
        vx_render_image_free(&c), vx_render_image_free(&g), vx_render_image_free(&c2), vx_render_image_free(&g2);
    }
    free(tex);
    vx_svo_scene_free(&s);
}

/* ---- white furnace under a constant map, read through OpenImageIO ---------------------- */

static void test_furnace_constant_map(void) {
    const double c = 0.6;
    enum { W = 32, H = 16 };
    float tex[W * H * 3];
    for (int i = 0; i < W * H * 3; i++) tex[i] = (float)c;
    char dir[] = "/tmp/vx_skyXXXXXX";
    REQUIRE(mkdtemp(dir));
    char path[64];
    snprintf(path, sizeof path, "%s/white.exr", dir);
    vx_error err = {0};
    REQUIRE(vx_image_write(path, &(vx_image_desc){.width = W, .height = H, .channels = 3, .type = VX_IMAGE_F32, .pixels = tex},
                           &err) == VX_OK);
    uint32_t w = 0, h = 0, ch = 0;
    float* px = NULL;
    REQUIRE(vx_image_read(path, VX_IMAGE_F32, 0, &w, &h, &ch, (void**)&px, &err) == VX_OK);
    remove(path);
    rmdir(dir);
    CHECK(w == W && h == H && ch >= 3);
    float* rgb = malloc(sizeof(float) * 3 * w * h);
    REQUIRE(rgb);
    for (size_t i = 0; i < (size_t)w * h; i++)
        for (int k = 0; k < 3; k++) rgb[3 * i + k] = px[i * ch + k];
    vx_free(NULL, px);
    vx_sky_texels map = {.rgb = rgb, .width = w, .height = h};
    vx_sky env = {.type = VX_SKY_ENVMAP, .intensity = 1, .path = "white.exr"};
    vx_sky flat = {.type = VX_SKY_CONSTANT, .color = {c, c, c}};

    /* a convex white block: every point on it sees only the sky, so with
     * albedo 1 every path returns c exactly (cosine sampling of Lambert) */
    vx_svo_scene s;
    block_h = 5;
    cells_scene(&s, 16, block_cell);
    s.palette[1] = 0xFFFFFFFFu;
    double black[3] = {0, 0, 0};
    vx_probe_set ps = light_only(0, black, 4);
    double to[3] = {-0.5, 0.7, -0.5}, centre[3] = {8, 8, 2.5};
    unit(to);
    vx_render_desc base = along(centre, to, 24, 16);
    base.camera.ortho_height = 14;
    const double want[3] = {c, c, c};
    for (int g = 0; g < 2; g++) {
        if (g && !gpu) continue;
        vx_probe_render_desc d = {.base = &base, .mode = VX_PROBE_RENDER_PATHTRACE, .spp = 16, .seed = 5, .threads = 2,
                                  .sky = &env, .sky_map = &map};
        vx_render_image a = {0}, b = {0};
        REQUIRE(render(g, &s, &ps, &d, &a));
        d.sky = &flat, d.sky_map = NULL;
        REQUIRE(render(g, &s, &ps, &d, &b));
        size_t hits = 0;
        for (size_t i = 0; i < (size_t)24 * 16; i++) hits += a.pixels[4 * i + 3] > 0;
        double ea = worst(&a, want), eb = worst(&b, want);
        fprintf(stderr, "  furnace on the %s: %zu of %d pixels on the block; off by %.2g (map), %.2g (constant sky)\n",
                g ? "GPU" : "CPU", hits, 24 * 16, ea, eb);
        CHECK(hits > 24 * 16 / 4);
        CHECK(ea < (g ? 1e-5 : 1e-6) && eb < (g ? 1e-5 : 1e-6));
        vx_render_image_free(&a), vx_render_image_free(&b);
    }
    free(rgb);
    vx_svo_scene_free(&s);
}

/* ---- the pass pipeline (render/pipeline.h: vx_frame_desc.sky_dir) ------------------------ */

/* A frame through the pass pipeline; lights: one point light of intensity 0
 * (the radiometric model without a gi pass needs a light; it adds nothing). */
static bool frame(const vx_svo_scene* s, const vx_frame_desc* fd0, const char* passes, vx_render_image* out) {
    vx_error err = {0};
    vx_render_scene* rs = NULL;
    vx_frame_renderer* fr = NULL;
    vx_pass_list list;
    static const vx_light dark = {.type = VX_LIGHT_POINT, .position = {-50, -50, 50}, .color = {1, 1, 1}};
    vx_frame_desc fd = *fd0;
    fd.passes = &list;
    if (!fd.gi) fd.lights = &dark, fd.light_count = 1;
    vx_frame_result res = {0};
    vx_result r = vx_pass_list_parse(passes, &list, &err);
    if (!r) r = vx_render_scene_create(gpu, s, &rs, &err);
    if (!r) r = vx_frame_renderer_create(rs, s, &fr, &err);
    if (!r) r = vx_frame_render(fr, &fd, &res, &err);
    if (r) fprintf(stderr, "  frame: %s\n", err.msg);
    vx_frame_renderer_destroy(fr);
    vx_render_scene_destroy(rs);
    *out = res.image;
    return r == VX_OK;
}

/* Miss pixels of the pass pipeline see vx_sky_radiance of their ray's
 * direction: a gradient and a map (texel centres and inner points, both
 * hemispheres, both sides of the azimuth's wrap), against the CPU function. */
static void test_pipeline_misses(void) {
    if (!gpu) SKIP("no Vulkan device");
    vx_svo_scene s;
    block_h = 2;
    cells_scene(&s, 16, block_cell);
    const double far[3] = {500, 500, 500};
    vx_sky grad = {.type = VX_SKY_GRADIENT, .color = {0.2, 0.4, 1.0}, .horizon = {0.9, 0.8, 0.7}, .ground = {0.3, 0.2, 0.1}};
    enum { W = 8, H = 4 };
    float tex[W * H * 3];
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) tex[3 * (y * W + x)] = x + 1.0f, tex[3 * (y * W + x) + 1] = y + 1.0f, tex[3 * (y * W + x) + 2] = 0.5f;
    vx_sky_texels map = {.rgb = tex, .width = W, .height = H};
    vx_sky env = {.type = VX_SKY_ENVMAP, .intensity = 2, .rotation = 0.3, .path = "map.exr"};
    const double dirs[4][3] = {{0.8, 0.1, 0.5}, {-0.3, 0.6, -0.3}, {0, 0, 1}, {0.5, -0.7, 0.0}};
    const double at[5][2] = {{0.5, 0.5}, {6.3, 1.2}, {7.8, 2.9}, {2.2, 3.6}, {0.1, 1.7}};
    for (int i = 0; i < 9; i++) {
        bool is_map = i >= 4;
        double d0[3];
        if (!is_map) {
            memcpy(d0, dirs[i], sizeof d0);
            unit(d0);
        } else {
            double phi = 0.3 + at[i - 4][0] * 2 * PI / W, theta = at[i - 4][1] * PI / H;
            d0[0] = sin(theta) * cos(phi), d0[1] = sin(theta) * sin(phi), d0[2] = cos(theta);
        }
        double want[3];
        vx_sky_radiance(is_map ? &env : &grad, &map, d0, want);
        vx_frame_desc fd = vx_frame_desc_defaults();
        fd.base = along(far, d0, 6, 4);
        fd.base.camera.ortho_height = 1e-3;
        fd.sky_dir = is_map ? &env : &grad, fd.sky_map = &map;
        for (int merged = 0; merged < 2; merged++) {
            fd.separate_passes = !merged;
            vx_render_image im = {0};
            REQUIRE(frame(&s, &fd, "gbuffer,direct", &im));
            double e = worst(&im, want);
            CHECKF(e < 1e-5, "%s, direction (%.2f %.2f %.2f)%s: off by %.3g (pixel 0: %g %g %g, want %g %g %g)",
                   is_map ? "map" : "gradient", d0[0], d0[1], d0[2], merged ? " merged" : "", e, im.pixels[0],
                   im.pixels[1], im.pixels[2], want[0], want[1], want[2]);
            vx_render_image_free(&im);
        }
    }
    vx_svo_scene_free(&s);
}

/* The sky's light on a surface. A gradient of zenith c, horizon h and ground
 * g lights a surface facing up with E / pi = (h + 2c) / 3 (the integral of
 * (h + (c - h) cos) cos over the hemisphere, over pi), a vertical one with
 * g / 2 + h / 2 + (c - h) 2 / (3 pi). The direct pass's sky term gives
 * albedo times that; gi=pathtrace under the gradient gives it by sampling
 * the sky, and agrees with the path tracer; misses behind the gi pass show
 * the method's gradient. */
static void test_pipeline_sky_light(void) {
    if (!gpu) SKIP("no Vulkan device");
    vx_svo_scene s;
    block_h = 5;
    cells_scene(&s, 16, block_cell);
    s.palette[1] = 0xFFC0C0C0u;
    const double alb = 192 / 255.0;
    vx_sky grad = {.type = VX_SKY_GRADIENT, .color = {0.2, 0.4, 1.0}, .horizon = {0.9, 0.8, 0.7}, .ground = {0.3, 0.2, 0.1}};
    const double down[3] = {0, 0, -1}, west[3] = {-1, 0, 0}, top[3] = {8, 8, 5}, side[3] = {12, 8, 2.5};
    double up_want[3], side_want[3];
    for (int k = 0; k < 3; k++) {
        up_want[k] = alb * (grad.horizon[k] + 2 * grad.color[k]) / 3;
        side_want[k] = alb * (grad.ground[k] / 2 + grad.horizon[k] / 2 + (grad.color[k] - grad.horizon[k]) * 2 / (3 * PI));
    }
    /* the direct pass's sky term, top and side faces */
    for (int f = 0; f < 2; f++) {
        vx_frame_desc fd = vx_frame_desc_defaults();
        fd.base = along(f ? side : top, f ? west : down, 8, 6);
        fd.base.camera.ortho_height = 4;
        fd.sky_dir = &grad;
        vx_render_image im = {0};
        REQUIRE(frame(&s, &fd, "gbuffer,direct", &im));
        double e = worst(&im, f ? side_want : up_want);
        fprintf(stderr, "  direct pass, sky term of a gradient on the %s face: off by %.2g of the closed form\n",
                f ? "side" : "top", e);
        CHECKF(e < 2e-3, "the %s face: off by %.3g (pixel 0: %g %g %g)", f ? "side" : "top", e, im.pixels[0], im.pixels[1],
               im.pixels[2]);
        vx_render_image_free(&im);
    }
    /* gi=pathtrace under the gradient: the top face, against the closed form
     * and the path tracer; then a frame half sky */
    double black[3] = {0, 0, 0};
    vx_probe_set ps = light_only(0, black, 2);
    vx_error err = {0};
    vx_render_scene* rs = NULL;
    REQUIRE(vx_render_scene_create(gpu, &s, &rs, &err) == VX_OK);
    vx_probe_render_desc pd = {.spp = 64, .bounces = 2, .seed = 3, .sky = &grad};
    vx_gi_method gm;
    vx_probe_gi* pgi = NULL;
    REQUIRE(vx_probe_gi_create(rs, &s, &ps, "pathtrace", &pd, &gm, &pgi, &err) == VX_OK);
    CHECK(gm.sky_dir && gm.sky_dir->type == VX_SKY_GRADIENT);
    vx_frame_desc fd = vx_frame_desc_defaults();
    fd.base = along(top, down, 16, 12);
    fd.base.camera.ortho_height = 4;
    fd.gi = &gm;
    vx_render_image im = {0}, ref = {0};
    REQUIRE(frame(&s, &fd, "gbuffer,direct,gi=pathtrace", &im));
    vx_render_desc base = fd.base;
    vx_probe_render_desc rd = {.base = &base, .mode = VX_PROBE_RENDER_PATHTRACE, .spp = 64, .bounces = 2, .seed = 4,
                               .sky = &grad, .pixel_centre = true};
    REQUIRE(vx_probe_render_gpu(rs, &s, &ps, &rd, &ref, &err) == VX_OK);
    double m[3] = {0, 0, 0}, mr[3] = {0, 0, 0};
    size_t n = (size_t)16 * 12;
    for (size_t i = 0; i < n; i++)
        for (int k = 0; k < 3; k++) m[k] += im.pixels[4 * i + k] / n, mr[k] += ref.pixels[4 * i + k] / n;
    double worst_rel = 0, worst_pt = 0;
    for (int k = 0; k < 3; k++)
        worst_rel = fmax(worst_rel, fabs(m[k] / up_want[k] - 1)), worst_pt = fmax(worst_pt, fabs(m[k] / mr[k] - 1));
    fprintf(stderr, "  gi=pathtrace under a gradient, top face: mean %.4f %.4f %.4f, closed form %.4f %.4f %.4f, "
            "path tracer %.4f %.4f %.4f\n", m[0], m[1], m[2], up_want[0], up_want[1], up_want[2], mr[0], mr[1], mr[2]);
    CHECKF(worst_rel < 0.01, "gi=pathtrace vs the closed form: off by %.3g", worst_rel);
    CHECKF(worst_pt < 0.01, "gi=pathtrace vs the path tracer: off by %.3g", worst_pt);
    vx_render_image_free(&im), vx_render_image_free(&ref);
    /* the misses behind the gi pass: the method's gradient */
    double d0[3] = {0.6, -0.2, 0.4}, want[3];
    unit(d0);
    vx_sky_radiance(&grad, NULL, d0, want);
    const double far[3] = {500, 500, 500};
    fd.base = along(far, d0, 6, 4);
    REQUIRE(frame(&s, &fd, "gbuffer,direct,gi=pathtrace", &im));
    double e = worst(&im, want);
    CHECKF(e < 1e-5, "misses with gi=pathtrace: off by %.3g", e);
    vx_render_image_free(&im);
    vx_probe_gi_destroy(pgi);
    vx_render_scene_destroy(rs);
    vx_svo_scene_free(&s);
}

/* A constant environment map is the constant sky in the pass pipeline:
 * misses and the sky term equal (and albedo times c on the block). */
static void test_pipeline_constant_map(void) {
    if (!gpu) SKIP("no Vulkan device");
    const double c = 0.6;
    enum { W = 32, H = 16 };
    float tex[W * H * 3];
    for (int i = 0; i < W * H * 3; i++) tex[i] = (float)c;
    vx_sky_texels map = {.rgb = tex, .width = W, .height = H};
    vx_sky env = {.type = VX_SKY_ENVMAP, .intensity = 1, .rotation = 1.1, .path = "white.exr"};
    vx_sky flat = {.type = VX_SKY_CONSTANT, .color = {c, c, c}};
    vx_svo_scene s;
    block_h = 5;
    cells_scene(&s, 16, block_cell);
    s.palette[1] = 0xFFFFFFFFu;
    double to[3] = {-0.5, 0.7, -0.5}, centre[3] = {8, 8, 2.5};
    unit(to);
    vx_frame_desc fd = vx_frame_desc_defaults();
    fd.base = along(centre, to, 24, 16);
    fd.base.camera.ortho_height = 14;
    fd.sky_dir = &env, fd.sky_map = &map;
    vx_render_image a = {0}, b = {0};
    REQUIRE(frame(&s, &fd, "gbuffer,direct", &a));
    fd.sky_dir = &flat, fd.sky_map = NULL;
    REQUIRE(frame(&s, &fd, "gbuffer,direct", &b));
    size_t hits = 0;
    for (size_t i = 0; i < (size_t)24 * 16; i++) hits += a.pixels[4 * i + 3] > 0;
    const double want[3] = {c, c, c};
    double ea = worst(&a, want), eb = worst(&b, want);
    fprintf(stderr, "  pass pipeline, constant map vs constant sky: %zu of %d pixels on the block; off by %.2g (map), "
            "%.2g (constant)\n", hits, 24 * 16, ea, eb);
    CHECK(hits > 24 * 16 / 4 && hits < 24 * 16);
    CHECK(ea < 1e-5 && eb < 1e-6);
    vx_render_image_free(&a), vx_render_image_free(&b);
    vx_svo_scene_free(&s);
}

int main(void) {
    (void)ts_random_model, (void)box_scene, (void)room_scene;
    dlopen("libvulkan_lvp.so", RTLD_NOW | RTLD_NODELETE); /* see test_probes_gpu.c */
    vx_error err = {0};
    if (vx_gpu_create(&(vx_gpu_desc){0}, &gpu, &err)) {
        fprintf(stderr, "no Vulkan device (%s): GPU comparisons skipped\n", err.msg);
        gpu = NULL;
    }
    RUN(test_sky_seen_by_misses);
    RUN(test_gpu_equals_cpu);
    RUN(test_furnace_constant_map);
    RUN(test_pipeline_misses);
    RUN(test_pipeline_sky_light);
    RUN(test_pipeline_constant_map);
    if (gpu) vx_gpu_destroy(gpu);
    return vx_test_finish();
}
