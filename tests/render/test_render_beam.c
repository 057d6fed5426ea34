/* tests/render/test_render_beam.c - the beam pass (vx_render_desc.beam)
 * against the same frame without it. The pass finds per pixel block where
 * the block's rays can first meet a non-empty node; each primary ray then
 * starts its walk at that distance (render/shaders/beam.comp, trace_model
 * in trace_common.glsl). That may change no hit: every frame here must hold the same instance, cell and
 * depth bits (and pixel values) per pixel as without the beam, for blocks of
 * 2, 3, 4, 8, 16 and 64 pixels on frames whose sizes are not multiples of
 * the block (ragged edges):
 *  - axis-parallel rays: orthographic views along each axis with the pixel
 *    centres on cell edges and on the octree's mid-planes, and a
 *    perspective view whose block corners lie on the image centre (rays
 *    along an axis within a block);
 *  - rays grazing the conservative bound: views along a floor's top face
 *    (the eye at its height and a hair above and below), so that blocks
 *    straddle the face and their rays pass just by the widened boxes;
 *  - close-ups and oblique views of a terrain (blocks straddling the
 *    octree's mid-planes), the eye inside the terrain, a scene of several
 *    instances of one model and of other models under the BVH; the terrain
 *    1024 cells wide too (an exact model: the DEEP 1 walk).
 *  - far pointers: a model whose descriptors point to their children
 *    through far slots, traced after a scene without any on the same device
 *    (the beam pass's pipeline must be the one built with the far-pointer
 *    test: issue 21's terrain4096 overview took the other, 6,415 pixels
 *    changed).
 * And it must pay: with the eye inside the terrain the frame with the beam
 * takes at least 15% fewer loop iterations per ray. Runs on any Vulkan
 * device (lavapipe in CI). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "bench/bench_terrain.h"
#include "render/render.h"
#include "svo/svo.h"
#include "tests/render/scenes.h"
#include "render/gpu.h" /* vx__render_scene_far */
#include "render/testing.h" /* vx__render_scene_trace_path */
#include "tests/test.h"
#include "tests/gpu_test.h"

static vx_gpu* gpu;
static const char* gpu_skip;
/* the scenes without grids: the beam pass runs only where the models walk their octrees (with grids, the
 * default on every device, it is off: the grid walk skips empty space by distance itself) */
static const vx_render_scene_desc no_grid = {.grid_budget = VX_RENDER_NO_GRID};

typedef struct beam_stats {
    double iter_off, iter_on; /* mean loop iterations per pixel */
    size_t hits;
} beam_stats;

/* Renders d without and with each block size, checks that no pixel
 * changes; returns the iteration counts of the block size `probe`. */
static beam_stats check_view(const char* name, vx_render_scene* rs, vx_render_desc d, uint32_t probe) {
    static const uint32_t blocks[] = {2, 3, 4, 8, 16, 64};
    beam_stats st = {0};
    d.want_hits = true;
    d.beam = 0;
    vx_render_image ref = {0};
    vx_error err = {0};
    vx__render_scene_trace_path(rs, 1); /* the starts below the root, even where a CPU device's default is off */
    vx_result r = vx_render_frame(rs, &d, &ref, &err);
    CHECKF(r == VX_OK, "%s: %s", name, err.msg);
    if (r) return st;
    size_t n = (size_t)d.width * d.height;
    /* the walk from the root: the primary rays' start below it on the
     * frame's octree path (a frame without the beam) must change no pixel
     * either, and the beam's saving is counted against the root's walk */
    vx_render_image root = {0};
    vx__render_scene_trace_path(rs, 0);
    r = vx_render_frame(rs, &d, &root, &err);
    vx__render_scene_trace_path(rs, -1);
    CHECKF(r == VX_OK, "%s (walk from the root): %s", name, err.msg);
    size_t pdiff = 0;
    double piter = 0;
    for (size_t i = 0; !r && i < n; i++) {
        const vx_render_hit *a = &ref.hits[i], *c = &root.hits[i];
        pdiff += !(a->instance == c->instance && !memcmp(a->cell, c->cell, sizeof a->cell) &&
                   !memcmp(&a->t, &c->t, sizeof a->t) && !memcmp(&ref.pixels[4 * i], &root.pixels[4 * i], 16));
        st.iter_off += c->iterations;
        piter += a->iterations;
        if (ref.hits[i].instance == VX_RENDER_NO_HIT) continue;
        st.hits++;
    }
    vx_render_image_free(&root);
    st.iter_off /= (double)n;
    printf("%-34s the path's start: %zu of %zu pixels differ; %.2f iterations per ray (%.2f from the root)\n", name,
           pdiff, n, piter / (double)n, st.iter_off);
    CHECKF(pdiff == 0, "%s: %zu pixels differ between the path's start and the walk from the root", name, pdiff);
    for (size_t b = 0; b < sizeof blocks / sizeof blocks[0]; b++) {
        d.beam = blocks[b];
        vx_render_image bi = {0};
        r = vx_render_frame(rs, &d, &bi, &err);
        CHECKF(r == VX_OK, "%s beam %u: %s", name, blocks[b], err.msg);
        if (r) continue;
        size_t diff = 0;
        double iter = 0;
        for (size_t i = 0; i < n; i++) {
            const vx_render_hit *a = &ref.hits[i], *c = &bi.hits[i];
            bool same = a->instance == c->instance && !memcmp(a->cell, c->cell, sizeof a->cell) &&
                        !memcmp(&a->t, &c->t, sizeof a->t) && !memcmp(&ref.pixels[4 * i], &bi.pixels[4 * i], 16);
            if (!same && diff++ < 4)
                fprintf(stderr, "  %s beam %u pixel %zu,%zu: inst %d cell %u,%u,%u t %.9g | no beam inst %d cell %u,%u,%u t %.9g\n",
                        name, blocks[b], i % d.width, i / d.width, (int)c->instance, c->cell[0], c->cell[1], c->cell[2],
                        c->t, (int)a->instance, a->cell[0], a->cell[1], a->cell[2], a->t);
            iter += c->iterations;
        }
        printf("%-34s beam %2u: %zu of %zu pixels differ; %.2f iterations per ray (%.2f without)\n", name, blocks[b], diff,
               n, iter / (double)n, st.iter_off);
        CHECKF(diff == 0, "%s: %zu pixels differ between beam %u and none", name, diff, blocks[b]);
        if (blocks[b] == probe) st.iter_on = iter / (double)n;
        vx_render_image_free(&bi);
    }
    vx_render_image_free(&ref);
    CHECK(vx_gpu_validation_errors(gpu) == 0);
    return st;
}

static vx_render_desc persp(uint32_t w, uint32_t h, double ex, double ey, double ez, double tx, double ty, double tz) {
    vx_render_desc d = {.width = w, .height = h, .mode = VX_RENDER_COLOR};
    d.camera = (vx_render_camera){.set = true, .eye = {ex, ey, ez}, .target = {tx, ty, tz}, .fov = 50};
    return d;
}

/* Orthographic along an axis: pixels one cell apart, centres on cell edges. */
static vx_render_desc ortho_axis(uint32_t w, uint32_t h, int axis, double centre, double dist) {
    vx_render_desc d = {.width = w, .height = h, .mode = VX_RENDER_COLOR};
    vx_render_camera c = {.set = true, .ortho = true, .ortho_height = h};
    /* h even, w even: the centre pixel edges sit on `centre`; shift by half
     * a pixel so that pixel centres are on integer planes */
    for (int k = 0; k < 3; k++) c.eye[k] = c.target[k] = centre + 0.5;
    c.eye[axis] = centre + dist, c.target[axis] = centre;
    c.up[axis == 2 ? 1 : 2] = 1;
    d.camera = c;
    return d;
}

/* The terrain 256 cells wide (8 levels, the plain walk), or 1024 (10
 * levels: an exact model, the DEEP 1 kernel, which pushes without the exit
 * test). */
static void terrain_views(uint32_t extent) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    vx_svo_scene s;
    vx_error err = {0};
    CHECK(bench_terrain(&s, extent, 0, &err) == 0);
    vx_render_scene* rs = NULL;
    vx_result r = vx_render_scene_create_ex(gpu, &s, &no_grid, &rs, &err);
    CHECKF(r == VX_OK, "terrain: %s", err.msg);
    if (r) {
        vx_svo_scene_free(&s);
        return;
    }
    double k = extent / 256.0;
    check_view("terrain oblique", rs, persp(101, 67, -60 * k, -90 * k, 330 * k, 128 * k, 128 * k, 120 * k), 8);
    check_view("terrain close-up", rs, persp(96, 64, 100 * k, 90 * k, 230 * k, 128 * k, 128 * k, 150 * k), 8);
    /* straight down, perspective: block corners on the image centre */
    check_view("terrain down (perspective)", rs, persp(64, 48, 128 * k, 128 * k, 300 * k, 128 * k, 128 * k, 0), 8);
    if (extent != 256) {
        vx_render_scene_destroy(rs);
        vx_svo_scene_free(&s);
        return;
    }
    for (int axis = 0; axis < 3; axis++) {
        char name[64];
        snprintf(name, sizeof name, "terrain ortho along axis %d", axis);
        beam_stats st = check_view(name, rs, ortho_axis(70, 52, axis, 128, 400), 8);
        CHECKF(st.hits > 0.1 * 70 * 52, "%s: %zu hits", name, st.hits);
    }
    beam_stats in = check_view("terrain eye inside", rs, persp(48, 40, 40, 40, 20, 200, 200, 60), 8);
    CHECKF(in.iter_on < 0.85 * in.iter_off, "terrain eye inside: %.2f iterations per ray with the beam, %.2f without",
           in.iter_on, in.iter_off);
    vx_render_scene_destroy(rs);
    vx_svo_scene_free(&s);
}

/* A floor 64 x 64 x 4 cells with random pillars on it, seen along its top
 * face (z = 4) from its height and just above and below it. */
static void test_terrain(void) { terrain_views(256); }
static void test_terrain_exact(void) { terrain_views(1024); }

static void test_grazing(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    const uint32_t S = 64, F = 4;
    uint32_t* xyz = malloc((size_t)S * S * S * 12);
    uint8_t* pal = malloc((size_t)S * S * S);
    CHECK(xyz && pal);
    if (!xyz || !pal) {
        free(xyz), free(pal);
        return;
    }
    size_t n = 0;
    uint32_t seed = 7;
    for (uint32_t y = 0; y < S; y++)
        for (uint32_t x = 0; x < S; x++) {
            uint32_t top = F;
            if (ts_rng(&seed) % 40 == 0) top = F + 1 + ts_rng(&seed) % 20;
            for (uint32_t z = 0; z < top; z++) xyz[3 * n] = x, xyz[3 * n + 1] = y, xyz[3 * n + 2] = z, pal[n++] = 1 + (x ^ y) % 200;
        }
    vx_svo_model m;
    uint32_t size[3] = {S, S, S};
    vx_result r = ts_model(&m, size, xyz, pal, n);
    free(xyz), free(pal);
    CHECK(r == VX_OK);
    if (r) return;
    vx_svo_instance in = ts_inst(0, NULL, 0, 0, 0);
    vx_svo_scene s;
    ts_scene(&s, &m, 1, &in, 1);
    vx_render_scene* rs = NULL;
    vx_error err = {0};
    r = vx_render_scene_create_ex(gpu, &s, &no_grid, &rs, &err);
    CHECKF(r == VX_OK, "floor: %s", err.msg);
    static const double dz[] = {0, 1e-4, -1e-4, 0.5};
    for (size_t i = 0; !r && i < sizeof dz / sizeof dz[0]; i++) {
        char name[64];
        snprintf(name, sizeof name, "floor grazing, eye %+g", dz[i]);
        check_view(name, rs, persp(83, 61, -10, 31.5, F + dz[i], 70, 33.3, F + dz[i]), 8);
        snprintf(name, sizeof name, "floor grazing diagonal, eye %+g", dz[i]);
        check_view(name, rs, persp(64, 64, -5, -5, F + dz[i], 64, 64, F + dz[i]), 8);
    }
    vx_render_scene_destroy(rs);
    vx_svo_scene_free(&s);
}

/* Several instances of one model and two other models under the BVH. */
static void test_instances(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    vx_svo_model m[3];
    CHECK(ts_random_model(&m[0], 32, 32, 32, 30, 11) == VX_OK);
    CHECK(ts_random_model(&m[1], 16, 16, 16, 60, 12) == VX_OK);
    CHECK(ts_random_model(&m[2], 64, 8, 64, 20, 13) == VX_OK);
    static const double rot[9] = {0, -1, 0, 1, 0, 0, 0, 0, 1};
    vx_svo_instance in[6] = {ts_inst(0, NULL, 0, 0, 0),   ts_inst(0, NULL, 40, 0, 0),  ts_inst(0, rot, 40, 40, 8),
                             ts_inst(1, NULL, 10, 40, 0), ts_inst(2, NULL, -20, -20, -10), ts_inst(1, NULL, 33, 5, 20)};
    vx_svo_scene s;
    ts_scene(&s, m, 3, in, 6);
    vx_render_scene* rs = NULL;
    vx_error err = {0};
    vx_result r = vx_render_scene_create_ex(gpu, &s, &no_grid, &rs, &err);
    CHECKF(r == VX_OK, "instances: %s", err.msg);
    if (!r) {
        check_view("instances overview", rs, persp(90, 70, -60, -80, 90, 30, 30, 10), 8);
        check_view("instances close-up", rs, persp(64, 48, 20, -20, 40, 20, 20, 10), 8);
        check_view("instances ortho along z", rs, ortho_axis(80, 60, 2, 20, 200), 8);
    }
    vx_render_scene_destroy(rs);
    vx_svo_scene_free(&s);
}

/* The terrain 256 cells wide built twice on one device: first as usual (no
 * far pointers, FAR off), then with the far limit lowered to 3 (far pointers
 * throughout, FAR on). The second scene's beam pass must follow the far
 * slots: with the pass built for the first scene (FAR off) its walk takes
 * wrong children and the rays of some blocks start past their hits. */
static void test_far_pointers(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    for (int lim = 0; lim < 2; lim++) {
        vx_svo_scene s;
        vx_error err = {0};
        int br = bench_terrain_desc(&s, 256, 0, &(vx_svo_build_desc){.testing.far_limit = lim ? 3 : 0}, &err);
        REQUIRE(br == 0);
        vx_render_scene* rs = NULL;
        vx_result r = vx_render_scene_create_ex(gpu, &s, &no_grid, &rs, &err);
        CHECKF(r == VX_OK, "far pointers: %s", err.msg);
        CHECKF(r || vx__render_scene_far(rs) == (lim == 1), "far limit %s: FAR %d", lim ? "3" : "default",
               r ? -1 : (int)vx__render_scene_far(rs));
        if (!r) {
            const char* nm[2] = {"terrain, no far pointers", "terrain, far pointers throughout"};
            beam_stats in = check_view(nm[lim], rs, persp(48, 40, 40, 40, 20, 200, 200, 60), 8);
            CHECKF(in.iter_on < 0.85 * in.iter_off, "%s: %.2f iterations per ray with the beam, %.2f without", nm[lim],
                   in.iter_on, in.iter_off);
            check_view(nm[lim], rs, persp(96, 64, 100, 90, 230, 128, 128, 150), 8);
        }
        vx_render_scene_destroy(rs);
        vx_svo_scene_free(&s);
    }
}

int main(void) {
    gpu_skip = vx_test_gpu_open((vx_gpu_desc){0}, true, &gpu);
    RUN(test_terrain);
    RUN(test_terrain_exact);
    RUN(test_grazing);
    RUN(test_instances);
    RUN(test_far_pointers);
    if (gpu) vx_gpu_destroy(gpu);
    return vx_test_finish();
}
