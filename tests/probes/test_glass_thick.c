/* tests/probes/test_glass_thick.c - glass thicker than the old walk limits
 * (256 cells in the passes, 512 in the path tracers): a horizontal glass
 * slab 600 cells thick of one colour (the octree collapses it into a few
 * uniform leaves, which the walks step over whole), and one 300 cells thick
 * whose cells alternate between two colours of the same glass material (no
 * collapse: the walks go cell by cell, under the limit of
 * render/trace.h vx__glass_walk_steps), seen from far above through a
 * narrow view onto a diffuse floor below it, lit by a point light between
 * the floor and the slab (no shadow ray from the floor crosses the glass),
 * black sky. Each against
 *  - the closed form: the ray refracted through the slab's parallel faces,
 *    the floor's Lambert radiance albedo / pi E where it lands, times the
 *    entry cell's tint and (1 - F_in)(1 - F_out) (exact Fresnel), in double,
 *    for the pass pipeline's pixels (gbuffer,direct: per pixel, none below
 *    it, the light reflected inside the slab added, and by their mean);
 *  - the same for the CPU path tracer and the GPU path tracer (the mean over
 *    the pixels: their Fresnel choices are coins per interface).
 * Before the walks stepped over uniform leaves and had the one limit, every
 * one of these pixels was black but the path tracers' through the 300-cell
 * slab. Skips without a Vulkan device. */
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

enum { W = 32, H = 24, S = 48, X0 = 8, X1 = 40, G = 8 };
static const uint32_t FLOOR_RGBA = 0xFF4090D0u;
static const uint32_t TINT_RGBA[2] = {0xFFE0F0FFu, 0xFFD0E8F4u}; /* palette 2 and 3: the tint of the entry cell */
static const double LIGHT_POS[3] = {24, 24, 4}, LIGHT_I = 60, IOR = 1.5;

/* The slab: x, y in [X0, X1), z in [G, G + thick); the floor: cells z = 0. alternate: palette 2 + (x + y + z) % 2. */
static void thick_scene(vx_svo_scene* s, uint32_t thick, bool alternate) {
    size_t cap = (size_t)S * S + (size_t)(X1 - X0) * (X1 - X0) * thick, n = 0;
    uint32_t* xyz = malloc(cap * 12);
    uint8_t* pal = malloc(cap);
    REQUIRE(xyz && pal);
    for (uint32_t y = 0; y < S; y++)
        for (uint32_t x = 0; x < S; x++) xyz[3 * n] = x, xyz[3 * n + 1] = y, xyz[3 * n + 2] = 0, pal[n++] = 1;
    for (uint32_t z = G; z < G + thick; z++)
        for (uint32_t y = X0; y < X1; y++)
            for (uint32_t x = X0; x < X1; x++)
                xyz[3 * n] = x, xyz[3 * n + 1] = y, xyz[3 * n + 2] = z, pal[n++] = alternate ? 2 + (x + y + z) % 2 : 2;
    vx_svo_model m;
    uint32_t size[3] = {S, S, G + thick};
    REQUIRE(ts_model(&m, size, xyz, pal, n) == VX_OK);
    free(xyz), free(pal);
    vx_svo_instance in = ts_inst(0, NULL, 0, 0, 0);
    ts_scene(s, &m, 1, &in, 1);
    s->palette[1] = FLOOR_RGBA, s->palette[2] = TINT_RGBA[0], s->palette[3] = TINT_RGBA[1];
    const char* kv[] = {"_type", "_glass", "_trans", "1", "_ior", "0.5", "_rough", "0"};
    add_material(s, 2, kv, 4);
    add_material(s, 3, kv, 4);
}

/* From far above, a little off the vertical, a narrow view of the slab's top. */
static vx_render_desc camera(uint32_t thick) {
    vx_render_desc b = {.width = W, .height = H, .spp = 1};
    b.camera.set = true;
    b.camera.eye[0] = 24 + 9, b.camera.eye[1] = 24 + 15, b.camera.eye[2] = G + thick + 900.0;
    b.camera.target[0] = 24, b.camera.target[1] = 24, b.camera.target[2] = 1;
    b.camera.up[1] = 1, b.camera.fov = 1.6;
    return b;
}

static vx_light point_light(void) {
    vx_light L = {.type = VX_LIGHT_POINT, .color = {1, 1, 1}, .intensity = LIGHT_I, .range = 1000};
    memcpy(L.position, LIGHT_POS, sizeof L.position);
    return L;
}

/* The pass pipeline's frame (gbuffer,direct) with the point light and a black sky. */
static bool frame(const vx_svo_scene* s, uint32_t thick, vx_render_image* out) {
    vx_light L = point_light();
    vx_render_desc base = camera(thick);
    return ps_pass_frame(gpu, s, &base, &L, 1, out);
}

static bool inside(double v, double lo, double hi, double margin) { return v > lo + margin && v < hi - margin; }

/* Pixel (px, py)'s centre ray (render/render.h's pinhole): whether it enters
 * the slab's top (z = G + thick) and leaves by its bottom (z = G), both 0.5
 * from the slab's sides, entering 0.05 or more from a cell's edge (its tint
 * is known), to land on the floor (top z = 1) 0.25 inside it; then the
 * expected radiance: Lambert floor times the entry cell's tint and
 * (1 - F_in)(1 - F_out). */
static bool pixel_expect(uint32_t thick, bool alternate, uint32_t px, uint32_t py, double out[3]) {
    vx_render_desc b = camera(thick);
    const double* e = b.camera.eye;
    double d[3];
    cf_pixel_ray(&b, px, py, d);
    if (!(d[2] < 0)) return false;
    double top = G + (double)thick, t0 = (top - e[2]) / d[2], a[3];
    for (int k = 0; k < 3; k++) a[k] = e[k] + t0 * d[k];
    if (!inside(a[0], X0, X1, 0.5) || !inside(a[1], X0, X1, 0.5)) return false;
    double fx = a[0] - floor(a[0]), fy = a[1] - floor(a[1]);
    if (fx < 0.05 || fx > 0.95 || fy < 0.05 || fy > 0.95) return false;
    uint32_t cx = (uint32_t)a[0], cy = (uint32_t)a[1], cz = G + thick - 1;
    uint32_t tint = alternate ? TINT_RGBA[(cx + cy + cz) % 2] : TINT_RGBA[0];
    /* refract into the slab (normal +z), walk to z = G, refract out: d again */
    double c = -d[2], ei = 1 / IOR, k2 = 1 - ei * ei * (1 - c * c), n[3] = {0, 0, 1}, di[3];
    for (int k = 0; k < 3; k++) di[k] = ei * d[k] + (ei * c - sqrt(k2)) * n[k];
    double t1 = (G - a[2]) / di[2], q[3];
    for (int k = 0; k < 3; k++) q[k] = a[k] + t1 * di[k];
    if (!inside(q[0], X0, X1, 0.5) || !inside(q[1], X0, X1, 0.5)) return false;
    double thr = (1 - cf_fresnel(c, IOR)) * (1 - cf_fresnel(-di[2], 1 / IOR));
    double t = (1 - q[2]) / d[2], p[3];
    for (int k = 0; k < 3; k++) p[k] = q[k] + t * d[k];
    if (!inside(p[0], 0, S, 0.25) || !inside(p[1], 0, S, 0.25)) return false;
    double wi[3];
    for (int k = 0; k < 3; k++) wi[k] = LIGHT_POS[k] - p[k];
    double di2 = cf_dot3(wi, wi), dist = sqrt(di2), qq = (dist / 1000) * (dist / 1000);
    double E = LIGHT_I * (wi[2] / dist) / di2 * (1 - qq * qq) * (1 - qq * qq);
    for (int k = 0; k < 3; k++) {
        double fl = ((FLOOR_RGBA >> (8 * k)) & 255) / 255.0, tn = ((tint >> (8 * k)) & 255) / 255.0;
        out[k] = fl / PI * E * thr * tn;
    }
    return true;
}

/* The path tracer's render of s (GPU with gpu_rs, else CPU): pixel centres, direct light only. */
static bool pathtrace(const vx_svo_scene* s, uint32_t thick, vx_render_scene* gpu_rs, uint32_t spp,
                      vx_render_image* out) {
    vx_light L = point_light();
    vx_render_desc base = camera(thick);
    return ps_pathtrace(s, gpu_rs, &base, spp, 0, 0, &L, 1, out);
}

/* The slab of `thick` cells against the closed form: the passes per pixel,
 * the CPU and the GPU path tracers by the mean ratio over the same pixels,
 * 64 spp each. The ratio's spread is larger than the coins' binomial 0.4%
 * at 16 spp: the pixels' floor irradiance varies some tenfold under the
 * near point light, so few pixels weigh most. Measured on the 600-cell
 * slab at 16 spp over seeds 1-6: CPU 0.973-1.016, GPU 0.991-1.013; at 64
 * spp CPU 0.994-1.006 (mean 1.0001), at 256 spp 1.0003: no bias, so both
 * within 2% at 64 spp (5 of the CPU's standard deviations). */
static void check_slab(uint32_t thick, bool alternate) {
    if (!gpu) SKIP("no Vulkan device");
    vx_svo_scene s;
    thick_scene(&s, thick, alternate);
    fprintf(stderr, "  %u cells thick%s: %u octree nodes for %llu cells\n", thick, alternate ? ", alternating" : "",
            s.models[0].node_count, (unsigned long long)s.models[0].voxel_count);
    vx_render_image im = {0}, cpu = {0}, gpt = {0};
    REQUIRE(frame(&s, thick, &im));
    REQUIRE(pathtrace(&s, thick, NULL, 64, &cpu));
    vx_error err = {0};
    vx_render_scene* rs = NULL;
    REQUIRE(vx_render_scene_create(gpu, &s, &rs, &err) == VX_OK);
    REQUIRE(pathtrace(&s, thick, rs, 64, &gpt));
    vx_render_scene_destroy(rs);
    double below = 0, sum = 0, sum_px = 0, sum_cpu = 0, sum_gpu = 0;
    size_t n = 0;
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++) {
            double want[3];
            if (!pixel_expect(thick, alternate, x, y, want)) continue;
            size_t i = 4 * ((size_t)y * W + x);
            for (int k = 0; k < 3; k++) {
                below = fmax(below, (want[k] - im.pixels[i + k]) / want[k]);
                sum += want[k], sum_px += im.pixels[i + k], sum_cpu += cpu.pixels[i + k], sum_gpu += gpt.pixels[i + k];
            }
            n++;
        }
    fprintf(stderr, "  %zu pixels through the slab: passes at most %.2e below the closed form, mean ratio %.4f; "
            "CPU path tracer %.4f, GPU path tracer %.4f\n", n, below, sum_px / sum, sum_cpu / sum, sum_gpu / sum);
    CHECK(n > 250);
    /* The passes follow the light reflected inside the slab too (pass_bodies.glsl glass_lobe), which the closed
     * form leaves out: per pixel they may only add to it (a pixel whose twice-reflected ray lands on the floor
     * near the light, or leaves by a side face, up to some 10%), and the mean stays within 1% (measured 1.0012
     * on both slabs; before they followed that light, within 5e-3 per pixel both ways). */
    CHECKF(below < 5e-3, "passes: %.2e below the closed form", below);
    CHECKF(fabs(sum_px / sum - 1) < 0.01, "passes: mean ratio %.4f", sum_px / sum);
    CHECKF(fabs(sum_cpu / sum - 1) < 0.02, "CPU path tracer: mean ratio %.4f", sum_cpu / sum);
    CHECKF(fabs(sum_gpu / sum - 1) < 0.02, "GPU path tracer: mean ratio %.4f", sum_gpu / sum);
    vx_render_image_free(&im), vx_render_image_free(&cpu), vx_render_image_free(&gpt);
    vx_svo_scene_free(&s);
}

/* 600 cells of one glass: a few uniform leaves. */
static void test_thick_uniform_slab(void) { check_slab(600, false); }
/* 300 cells of alternating colours: no collapse, cell by cell. */
static void test_thick_alternating_slab(void) { check_slab(300, true); }

int main(void) {
    (void)ts_random_model, (void)room_scene, (void)box_scene, (void)cells_scene;
    dlopen("libvulkan_lvp.so", RTLD_NOW | RTLD_NODELETE); /* see test_probes_gpu.c */
    vx_error err = {0};
    if (vx_gpu_create(&(vx_gpu_desc){0}, &gpu, &err)) {
        fprintf(stderr, "no Vulkan device (%s): GPU comparisons skipped\n", err.msg);
        gpu = NULL;
    }
    RUN(test_thick_uniform_slab);
    RUN(test_thick_alternating_slab);
    if (gpu) vx_gpu_destroy(gpu);
    return vx_test_finish();
}
