/* tests/render/test_render_smap.c - the directional light's depth map that
 * clips the colour mode's shadow rays (render/shadow_map.c, issue 21). The
 * map must change no pixel: every colour frame here is rendered with the
 * map (the default) and without (vx_render_desc.no_shadow_map) and must
 * hold the same pixel bits, with and without hits records, on
 *  - a sparse random model, a terrain (level-3 leaves, pebbles), and a scene
 *    of instances: identity, turned a quarter about z, mirrored in x (a
 *    negative determinant), turned by an odd angle about a skew axis and
 *    scaled, and a second model;
 *  - lights along each axis (either sign), with +0 and -0 components, the
 *    default light, a diagonal one and lights a hair off a face's plane
 *    (grazing the floor and a wall);
 *  - maps of 16, 61 and 2048 texels a side (texels much larger and smaller
 *    than a cell);
 *  - orthographic views from the light whose pixel centres lie on the
 *    map's texel edges (vx_render_shadow_map_info gives the texels), so
 *    that shadow rays start on texel edges and corners.
 * The frames with the map must have used it, agree with the CPU reference
 * as tests/render/test_render_gpu.c's colour modes do, and it must pay: on
 * the terrain's close-up the shadow rays take at most 0.6 of the loop
 * iterations they take without it (vx_render_hit.shadow). The pass
 * pipeline's direct pass (render/pipeline.h, merged into one kernel or
 * separate) clips the sun's rays by the same map: the same image bits with
 * and without (test_passes_direct). Runs on any Vulkan device (lavapipe in
 * CI). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "bench/bench_terrain.h"
#include "render/compact.h"
#include "render/pipeline.h"
#include "render/render.h"
#include "svo/svo.h"
#include "tests/render/scenes.h"
#include "tests/test.h"
#include "tests/gpu_test.h"

static vx_gpu* gpu;
static const char* gpu_skip;

typedef struct smap_stats {
    size_t frames, cast;
    double steps_on, steps_off; /* shadow loop iterations, summed */
} smap_stats;

/* Renders d (colour) with and without the map, with and without hits;
 * checks bits, the map's use and (cpu) the CPU reference. */
static void check_frame(const char* name, vx_render_scene* rs, const vx_svo_scene* s, vx_render_desc d, bool cpu,
                        smap_stats* st) {
    d.mode = VX_RENDER_COLOR;
    size_t n = (size_t)d.width * d.height;
    for (int hits = 1; hits >= 0; hits--) {
        d.want_hits = hits;
        vx_render_image a = {0}, b = {0};
        vx_error err = {0};
        d.no_shadow_map = true;
        vx_result r = vx_render_frame(rs, &d, &a, &err);
        CHECKF(r == VX_OK, "%s: %s", name, err.msg);
        vx_render_shadow_map_info info;
        vx_render_scene_shadow_map_info(rs, &info);
        CHECKF(!info.used, "%s: the map was used with no_shadow_map", name);
        d.no_shadow_map = false;
        r = r ? r : vx_render_frame(rs, &d, &b, &err);
        CHECKF(r == VX_OK, "%s: %s", name, err.msg);
        vx_render_scene_shadow_map_info(rs, &info);
        CHECKF(info.used && info.side > 0, "%s: the map was not used", name);
        if (r) {
            vx_render_image_free(&a);
            continue;
        }
        size_t diff = 0, cast = 0;
        for (size_t i = 0; i < n; i++) {
            if (memcmp(&a.pixels[4 * i], &b.pixels[4 * i], 16) && diff++ < 4)
                fprintf(stderr, "  %s pixel %zu,%zu: %.9g %.9g %.9g with the map, %.9g %.9g %.9g without\n", name,
                        i % d.width, i / d.width, b.pixels[4 * i], b.pixels[4 * i + 1], b.pixels[4 * i + 2],
                        a.pixels[4 * i], a.pixels[4 * i + 1], a.pixels[4 * i + 2]);
            if (!hits) continue;
            uint32_t ha = a.hits[i].shadow, hb = b.hits[i].shadow;
            /* the same pixels cast a shadow ray; their steps differ */
            CHECK((ha & VX_RENDER_SHADOW_CAST) == (hb & VX_RENDER_SHADOW_CAST));
            if (ha & VX_RENDER_SHADOW_CAST) {
                cast++;
                st->steps_off += ha & ~VX_RENDER_SHADOW_CAST;
                st->steps_on += hb & ~VX_RENDER_SHADOW_CAST;
            }
        }
        CHECKF(diff == 0, "%s%s: %zu of %zu pixels differ with the shadow map", name, hits ? " (hits)" : "", diff, n);
        if (hits) st->cast += cast, st->frames++;
        if (hits && cpu) {
            vx_render_image c = {0};
            vx_render_desc dc = d;
            dc.want_hits = false;
            CHECK(vx_render_cpu(s, &dc, NULL, &c, &err) == VX_OK);
            size_t off = 0;
            for (size_t i = 0; c.pixels && i < 4 * n; i++) {
                float x = b.pixels[i], y = c.pixels[i];
                if (!(fabsf(x - y) <= 2e-3f * fmaxf(1, fabsf(y)))) off++;
            }
            /* as test_render_gpu's colour modes: shadow acne at edges may differ in a few */
            CHECKF(off <= 4 * n / 200, "%s: %zu of %zu values differ from the CPU reference", name, off, 4 * n);
            vx_render_image_free(&c);
        }
        vx_render_image_free(&a);
        vx_render_image_free(&b);
    }
}

static vx_render_camera persp(double ex, double ey, double ez, double tx, double ty, double tz) {
    vx_render_camera c = {.set = true, .eye = {ex, ey, ez}, .target = {tx, ty, tz}, .up = {0, 0, 1}};
    return c;
}

/* Lights (towards the light): axes of either sign, signed zeros, the
 * default, a diagonal, grazing a z face and an x face. */
static const double lights[][3] = {
    {0.35, -0.45, 0.82}, {0, 0, 1}, {-0.0, 0.0, 1}, {0.0, -0.0, -1}, {1, -0.0, 0}, {-1, 0, 0},
    {0, 1, -0.0},        {1, 1, 1}, {1, 0.3, 1e-4}, {1e-4, -1, 0.4}, {-0.6, 0.5, 0.2},
};
#define NLIGHTS (sizeof lights / sizeof lights[0])

static void frames_with_map(vx_render_scene* rs, const double L[3], vx_render_image* img, vx_render_shadow_map_info* mi);

/* A node list made ahead from s's compact layout (render/compact.h: its geometry's nodes, full cubes of any
 * colours as one solid node) for a scene of side `side` on this device, taken by rs. */
static void take_compact_list(const char* name, const vx_svo_scene* s, uint32_t side, vx_render_scene* rs) {
    vx_compact_scene c;
    vx_error err = {0};
    vx_render_sun_nodes* nodes = NULL;
    /* the map of 61 texels from the brick dictionary's form (a level-3 node's bricks through index words) */
    vx_compact_desc cd = {.bricks = side == 61 ? VX_COMPACT_BRICKS_DICT : VX_COMPACT_BRICKS_INLINE};
    vx_result r = vx_compact_build(&cd, s, &c, &err);
    if (!r) {
        vx_render_sun_nodes_desc nd = {.shadow_map_side = side, .cpu_device = vx_gpu_is_cpu(gpu), .layout = &c};
        r = vx_render_sun_nodes_make(s, &nd, &nodes, &err);
        vx_compact_free(&c);
    }
    CHECKF(r == VX_OK, "%s: the compact layout's list: %s", name, err.msg);
    vx_render_scene_take_sun_nodes(rs, nodes);
}

/* Every light from the given cameras, maps of the given sides; compact: the node list from the scene's compact
 * layout (taken by the plain scene, whose trace.comp frames keep the one-cube rule with it). */
static void check_scene(const char* name, const vx_svo_scene* s, const vx_render_camera* cams, size_t ncam,
                        const uint32_t* sides, size_t nsides, bool cpu, bool compact, smap_stats* st) {
    for (size_t si = 0; si < nsides; si++) {
        vx_render_scene_desc sd = {.shadow_map_side = sides[si]};
        vx_render_scene* rs = NULL;
        vx_error err = {0};
        vx_result r = vx_render_scene_create_ex(gpu, s, &sd, &rs, &err);
        CHECKF(r == VX_OK, "%s: %s", name, err.msg);
        if (r) continue;
        if (compact) take_compact_list(name, s, sides[si], rs);
        for (size_t li = 0; li < NLIGHTS; li++)
            for (size_t c = 0; c < ncam; c++) {
                char nm[160];
                snprintf(nm, sizeof nm, "%s side %u light %zu view %zu", name, sides[si], li, c);
                vx_render_desc d = {.width = 61, .height = 43, .camera = cams[c]};
                memcpy(d.light_dir, lights[li], sizeof d.light_dir);
                check_frame(nm, rs, s, d, cpu && li < 3 && si == 0, st);
            }
        vx_render_shadow_map_info mi;
        vx_render_scene_shadow_map_info(rs, &mi);
        CHECKF(!compact || mi.ahead_seconds > 0, "%s side %u: the compact layout's list was not taken", name, sides[si]);
        vx_render_scene_destroy(rs);
    }
}

/* Orthographic views from the light whose pixel centres fall on the map's
 * texel corners (so their shadow rays start on texel edges, to rounding). */
static void check_texel_edges(const char* name, const vx_svo_scene* s, uint32_t side, smap_stats* st) {
    vx_render_scene_desc sd = {.shadow_map_side = side};
    vx_render_scene* rs = NULL;
    vx_error err = {0};
    vx_result r = vx_render_scene_create_ex(gpu, s, &sd, &rs, &err);
    CHECKF(r == VX_OK, "%s: %s", name, err.msg);
    if (r) return;
    static const size_t which[] = {0, 1, 2, 4, 7, 8};
    for (size_t w = 0; w < sizeof which / sizeof which[0]; w++) {
        vx_render_desc d = {.width = 64, .height = 64, .mode = VX_RENDER_COLOR};
        memcpy(d.light_dir, lights[which[w]], sizeof d.light_dir);
        vx_render_image img = {0};
        /* the second frame with this light builds its map */
        for (int k = 0; k < 2 && !r; k++) {
            r = vx_render_frame(rs, &d, &img, &err);
            vx_render_image_free(&img);
        }
        vx_render_shadow_map_info mi;
        vx_render_scene_shadow_map_info(rs, &mi);
        CHECKF(r == VX_OK && mi.used, "%s: no map (%s)", name, err.msg);
        if (r || !mi.used) continue;
        double L[3], l = 0;
        for (int k = 0; k < 3; k++) L[k] = lights[which[w]][k], l += L[k] * L[k];
        for (int k = 0; k < 3; k++) L[k] /= sqrt(l);
        /* pixels a texel apart, the view's centre half a texel past the
         * texel corner nearest the scene's middle: pixel centres (half a
         * pixel off the centre, the frame being even) on texel corners */
        double mu = floor(-mi.u0 / mi.texel) + 0.5, mv = floor(-mi.v0 / mi.texel) + 0.5;
        vx_render_camera c = {.set = true, .ortho = true, .ortho_height = d.height * mi.texel};
        for (int k = 0; k < 3; k++) {
            c.target[k] = mi.origin[k] + (mi.u0 + mu * mi.texel) * mi.axis_u[k] + (mi.v0 + mv * mi.texel) * mi.axis_v[k];
            c.eye[k] = c.target[k] + L[k] * 4 * d.height * mi.texel * side;
            c.up[k] = mi.axis_v[k];
        }
        d.camera = c;
        char nm[160];
        snprintf(nm, sizeof nm, "%s texel edges side %u light %zu", name, side, which[w]);
        check_frame(nm, rs, s, d, false, st);
    }
    vx_render_scene_destroy(rs);
}

static void test_random_model(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    vx_svo_model m;
    REQUIRE(ts_random_model(&m, 24, 20, 16, 30, 7) == VX_OK);
    vx_svo_instance in = ts_inst(0, NULL, 0, 0, 0);
    vx_svo_scene s;
    ts_scene(&s, &m, 1, &in, 1);
    vx_render_camera cams[2] = {{0}, persp(40, -30, 30, 12, 10, 8)};
    static const uint32_t sides[] = {0, 16, 61};
    smap_stats st = {0};
    check_scene("random", &s, cams, 2, sides, 3, true, false, &st);
    check_texel_edges("random", &s, 61, &st);
    printf("random model: %zu frames, %zu shadow rays, %.2f -> %.2f steps each\n", st.frames, st.cast,
           st.cast ? st.steps_off / st.cast : 0, st.cast ? st.steps_on / st.cast : 0);
    CHECK(st.cast > 1000);
    vx_svo_scene_free(&s);
}

/* Two models, six instances: identity, turned a quarter, mirrored, turned by an odd angle and scaled. */
static vx_result instance_scene(vx_svo_scene* s) {
    vx_svo_model m[2];
    vx_result r = ts_random_model(&m[0], 12, 10, 8, 45, 11);
    if (r) return r;
    /* a floor with pillars: faces the grazing lights skim */
    uint32_t xyz[3 * (40 * 40 + 4 * 12)];
    size_t n = 0;
    for (uint32_t y = 0; y < 40; y++)
        for (uint32_t x = 0; x < 40; x++) xyz[3 * n] = x, xyz[3 * n + 1] = y, xyz[3 * n + 2] = 0, n++;
    for (uint32_t p = 0; p < 4; p++)
        for (uint32_t z = 1; z <= 12; z++)
            xyz[3 * n] = 8 + 20 * (p & 1), xyz[3 * n + 1] = 8 + 20 * (p >> 1), xyz[3 * n + 2] = z, n++;
    if ((r = ts_model(&m[1], (const uint32_t[3]){40, 40, 13}, xyz, NULL, n))) {
        vx_svo_model_free(NULL, &m[0]);
        return r;
    }
    const double quarter[9] = {0, -1, 0, 1, 0, 0, 0, 0, 1};
    const double mirror[9] = {-1, 0, 0, 0, 1, 0, 0, 0, 1};
    /* 35 degrees about (1, 1, 1)/sqrt(3), scaled by 0.75 */
    double odd[9];
    {
        double a = 35 * 3.14159265358979 / 180, c = cos(a), si = sin(a), u = 1 / sqrt(3.0), t = 1 - c;
        double R[9] = {c + u * u * t,      u * u * t - u * si, u * u * t + u * si, u * u * t + u * si, c + u * u * t,
                       u * u * t - u * si, u * u * t - u * si, u * u * t + u * si, c + u * u * t};
        for (int i = 0; i < 9; i++) odd[i] = 0.75 * R[i];
    }
    vx_svo_instance in[6] = {ts_inst(1, NULL, -4, -4, -1), ts_inst(0, NULL, 2, 3, 1),     ts_inst(0, quarter, 30, 4, 1),
                             ts_inst(0, mirror, 20, 20, 1), ts_inst(0, odd, 6, 24, 6),      ts_inst(0, NULL, 14, 12, 14)};
    ts_scene(s, m, 2, in, 6);
    return VX_OK;
}

static void test_instances(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    vx_svo_scene s;
    REQUIRE(instance_scene(&s) == VX_OK);
    vx_render_camera cams[2] = {{0}, persp(50, -20, 30, 16, 16, 4)};
    static const uint32_t sides[] = {0, 16, 61};
    smap_stats st = {0};
    check_scene("instances", &s, cams, 2, sides, 3, true, false, &st);
    /* the node list from the compact layout (test_compact_list) */
    check_scene("instances, compact list", &s, cams, 1, sides, 3, true, true, &st);
    check_texel_edges("instances", &s, 61, &st);
    check_texel_edges("instances", &s, 16, &st);
    printf("instances: %zu frames, %zu shadow rays, %.2f -> %.2f steps each\n", st.frames, st.cast,
           st.cast ? st.steps_off / st.cast : 0, st.cast ? st.steps_on / st.cast : 0);
    CHECK(st.cast > 1000);
    vx_svo_scene_free(&s);
}

/* The node list from the compact layout (issue 18, branch smap3: what a scene built from a model reader lists,
 * svo_bake --load models), taken by a plain scene: the frames with the map the bits of those without, on the
 * instances (test_instances) and on a solid block of a colour per cell (full bricks: solid cubes of 4^3 cells in the compact
 * list), one whose every brick lacks a cell, models of depth 1 and 2 (a brick as the root), turned and mirrored;
 * the bricks in their blocks and in the dictionary (take_compact_list). */
static void test_compact_list(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    vx_svo_scene s;
    static const uint32_t sides[] = {0, 16, 61};
    smap_stats st = {0};
    vx_svo_model m[5];
    REQUIRE(ts_random_model(&m[0], 16, 16, 16, 100, 5) == VX_OK);
    REQUIRE(ts_seam_model(&m[4]) == VX_OK); /* every brick lacks one cell: none is a solid cube */
    REQUIRE(ts_random_model(&m[1], 2, 2, 2, 60, 9) == VX_OK);
    REQUIRE(ts_random_model(&m[2], 4, 4, 3, 55, 13) == VX_OK);
    REQUIRE(ts_random_model(&m[3], 14, 12, 10, 35, 17) == VX_OK);
    CHECK(m[1].depth == 1 && m[2].depth == 2);
    const double quarter[9] = {0, -1, 0, 1, 0, 0, 0, 0, 1}, mirror[9] = {-1, 0, 0, 0, 1, 0, 0, 0, 1};
    vx_svo_instance in[7] = {ts_inst(0, NULL, 0, 0, 0),       ts_inst(1, NULL, 4, 20, 2), ts_inst(2, quarter, 10, 22, 1),
                             ts_inst(2, mirror, 20, 18, 9),   ts_inst(3, NULL, 18, -2, 0), ts_inst(0, quarter, 40, 4, 6),
                             ts_inst(4, NULL, -34, 0, 0)};
    ts_scene(&s, m, 5, in, 7);
    vx_render_camera views[3] = {{0}, persp(60, -30, 40, 18, 10, 4), persp(-60, -40, 50, -18, 16, 16)};
    check_scene("blocks, compact list", &s, views, 3, sides, 3, true, true, &st);
    /* the block's full bricks are solid cubes of 4^3 cells in the compact list, 16^3 cells of other colours in
     * the plain one (a list at level 0 on a CPU device, 2 texels a cell; at level 1 or 2 on a GPU): fewer nodes,
     * the layout's list taken */
    vx_error err = {0};
    vx_render_scene *rp = NULL, *rc = NULL;
    vx_render_image img = {0};
    vx_render_shadow_map_info a = {0}, b = {0};
    const double L[3] = {0.35, -0.45, 0.82};
    REQUIRE(vx_render_scene_create(gpu, &s, &rp, &err) == VX_OK);
    REQUIRE(vx_render_scene_create(gpu, &s, &rc, &err) == VX_OK);
    take_compact_list("blocks", &s, 0, rc);
    frames_with_map(rp, L, &img, &a);
    frames_with_map(rc, L, &img, &b);
    printf("blocks: %u nodes listed from the plain models, %u from the compact layout\n", a.nodes, b.nodes);
    CHECK(a.used && b.used && b.ahead_seconds > 0 && b.nodes < a.nodes && a.side == b.side);
    vx_render_image_free(&img);
    vx_render_scene_destroy(rp);
    vx_render_scene_destroy(rc);
    /* bad arguments: a layout of other models */
    vx_compact_scene c;
    vx_svo_scene other;
    REQUIRE(instance_scene(&other) == VX_OK);
    REQUIRE(vx_compact_build(NULL, &other, &c, &err) == VX_OK);
    vx_render_sun_nodes* nodes = NULL;
    CHECK(vx_render_sun_nodes_make(&s, &(vx_render_sun_nodes_desc){.layout = &c}, &nodes, &err) == VX_ERR_INVALID_ARG);
    CHECK(nodes == NULL);
    vx_compact_free(&c);
    vx_svo_scene_free(&other);
    printf("compact lists: %zu frames, %zu shadow rays, %.2f -> %.2f steps each\n", st.frames, st.cast,
           st.cast ? st.steps_off / st.cast : 0, st.cast ? st.steps_on / st.cast : 0);
    vx_svo_scene_free(&s);
    CHECK(vx_gpu_validation_errors(gpu) == 0);
}

/* The terrain 256 cells wide: the bench's close-up case, where the map must pay. */
static void test_terrain(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    vx_svo_scene s;
    vx_error err = {0};
    REQUIRE(bench_terrain(&s, 256, 0, &err) == 0);
    vx_render_camera close[1] = {persp(100, 90, 230, 128, 128, 150)};
    vx_render_camera views[2] = {{0}, persp(-60, -90, 330, 128, 128, 120)};
    static const uint32_t def[] = {0}, sides[] = {16, 61};
    smap_stats st = {0};
    /* the default light only, the paying check */
    vx_render_scene* rs = NULL;
    REQUIRE(vx_render_scene_create(gpu, &s, &rs, &err) == VX_OK);
    vx_render_desc d = {.width = 96, .height = 64, .camera = close[0]};
    check_frame("terrain close-up", rs, &s, d, true, &st);
    vx_render_scene_destroy(rs);
    double off = st.cast ? st.steps_off / st.cast : 0, on = st.cast ? st.steps_on / st.cast : 0;
    printf("terrain close-up: %zu shadow rays, %.2f -> %.2f steps each\n", st.cast, off, on);
    CHECK(st.cast > 1000);
    CHECKF(on <= 0.6 * off, "the map saves too little: %.2f -> %.2f steps", off, on);
    check_scene("terrain", &s, close, 1, def, 1, false, false, &st);
    check_scene("terrain", &s, views, 2, sides, 2, false, false, &st);
    check_scene("terrain, compact list", &s, views, 1, sides, 2, false, true, &st);
    check_texel_edges("terrain", &s, 61, &st);
    vx_svo_scene_free(&s);
}

/* No map where it does not apply: LOD frames, other modes, a light new to the
 * frame (or changing every frame), a scene made without one. */
static void test_not_used(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    vx_svo_model m;
    REQUIRE(ts_random_model(&m, 16, 16, 16, 30, 3) == VX_OK);
    vx_svo_instance in = ts_inst(0, NULL, 0, 0, 0);
    vx_svo_scene s;
    ts_scene(&s, &m, 1, &in, 1);
    vx_error err = {0};
    vx_render_scene* rs = NULL;
    REQUIRE(vx_render_scene_create(gpu, &s, &rs, &err) == VX_OK);
    vx_render_shadow_map_info mi;
    vx_render_desc d = {.width = 32, .height = 24, .lod = true, .lod_pixels = 4};
    vx_render_image img = {0};
    CHECK(vx_render_frame(rs, &d, &img, &err) == VX_OK);
    vx_render_image_free(&img);
    vx_render_scene_shadow_map_info(rs, &mi);
    /* no list before the first build (a scene that never builds a map pays nothing) */
    CHECK(!mi.used && mi.builds == 0 && mi.side == 0 && mi.nodes == 0);
    d.lod = false, d.mode = VX_RENDER_DEPTH;
    CHECK(vx_render_frame(rs, &d, &img, &err) == VX_OK);
    vx_render_image_free(&img);
    vx_render_scene_shadow_map_info(rs, &mi);
    CHECK(!mi.used && mi.builds == 0);
    d.mode = VX_RENDER_COLOR;
    CHECK(vx_render_frame(rs, &d, &img, &err) == VX_OK); /* a light no frame had before: no map yet */
    vx_render_image_free(&img);
    vx_render_scene_shadow_map_info(rs, &mi);
    CHECK(!mi.used && mi.builds == 0);
    for (int k = 0; k < 2; k++) { /* the same light again: built once, then used as is */
        CHECK(vx_render_frame(rs, &d, &img, &err) == VX_OK);
        vx_render_image_free(&img);
        vx_render_scene_shadow_map_info(rs, &mi);
        CHECK(mi.used && mi.builds == 1 && mi.texel > 0);
        CHECK(mi.side >= 64 && mi.side <= 2048 && !(mi.side & (mi.side - 1)) && mi.nodes > 0);
    }
    /* a light that changes every frame: never a map */
    for (int k = 0; k < 3; k++) {
        d.light_dir[0] = 0.1 * k, d.light_dir[1] = 0.2, d.light_dir[2] = 1;
        CHECK(vx_render_frame(rs, &d, &img, &err) == VX_OK);
        vx_render_image_free(&img);
        vx_render_scene_shadow_map_info(rs, &mi);
        CHECK(!mi.used && mi.builds == 1);
    }
    vx_render_scene_destroy(rs);
    vx_render_scene_desc sd = {.shadow_map_side = 1};
    REQUIRE(vx_render_scene_create_ex(gpu, &s, &sd, &rs, &err) == VX_OK);
    CHECK(vx_render_frame(rs, &d, &img, &err) == VX_OK);
    vx_render_image_free(&img);
    vx_render_scene_shadow_map_info(rs, &mi);
    CHECK(!mi.used && mi.side == 0 && mi.nodes == 0);
    vx_render_scene_destroy(rs);
    vx_svo_scene_free(&s);
    CHECK(vx_gpu_validation_errors(gpu) == 0);
}

/* Two colour frames of rs with light L (the second builds and uses the map); the second's pixels into *img. */
static void frames_with_map(vx_render_scene* rs, const double L[3], vx_render_image* img, vx_render_shadow_map_info* mi) {
    vx_render_desc d = {.width = 48, .height = 32, .mode = VX_RENDER_COLOR, .light_dir = {L[0], L[1], L[2]}};
    d.camera = persp(50, -20, 30, 16, 16, 4);
    vx_error err = {0};
    for (int k = 0; k < 2; k++) {
        vx_render_image_free(img);
        CHECKF(vx_render_frame(rs, &d, img, &err) == VX_OK, "%s", err.msg);
    }
    vx_render_scene_shadow_map_info(rs, mi);
}

/* A node list made on the host ahead of the render scene (vx_render_sun_nodes_make, as svo_bake makes it while
 * its device opens): taken where it is the list the first build would make (the same side, nodes and image
 * bits as a scene that lists at the build), left where it is not (another device kind, largest side or
 * scene: the build lists as before); bad arguments fail without a crash. */
static void test_ahead(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    vx_svo_scene s, other;
    REQUIRE(instance_scene(&s) == VX_OK);
    vx_svo_model om;
    REQUIRE(ts_random_model(&om, 16, 16, 16, 30, 3) == VX_OK);
    vx_svo_instance oin = ts_inst(0, NULL, 0, 0, 0);
    ts_scene(&other, &om, 1, &oin, 1);
    const double L[3] = {0.35, -0.45, 0.82};
    vx_error err = {0};
    vx_render_scene* rs = NULL;
    vx_render_image ref = {0}, img = {0};
    vx_render_shadow_map_info a, b;
    REQUIRE(vx_render_scene_create(gpu, &s, &rs, &err) == VX_OK);
    frames_with_map(rs, L, &ref, &a);
    vx_render_scene_destroy(rs);
    CHECK(a.used && a.side > 0 && a.nodes > 0 && a.ahead_seconds == 0);
    bool cpu = vx_gpu_is_cpu(gpu);
    /* 0: the list this device's scene makes; 1: for the other kind of device; 2: for a larger side; 3: of
     * another scene */
    for (int k = 0; k < 4; k++) {
        vx_render_sun_nodes_desc nd = {.cpu_device = k == 1 ? !cpu : cpu, .max_side = k == 2 ? 4096 : 0};
        vx_render_sun_nodes* nodes = NULL;
        REQUIRE(vx_render_sun_nodes_make(k == 3 ? &other : &s, &nd, &nodes, &err) == VX_OK);
        REQUIRE(vx_render_scene_create(gpu, &s, &rs, &err) == VX_OK);
        vx_render_scene_take_sun_nodes(rs, nodes);
        frames_with_map(rs, L, &img, &b);
        CHECKF(b.used && b.side == a.side && b.nodes == a.nodes, "case %d: side %u nodes %u (listed at the build: %u, %u)",
               k, b.side, b.nodes, a.side, a.nodes);
        CHECKF(k == 0 ? b.ahead_seconds > 0 : b.ahead_seconds == 0, "case %d: the list made ahead %s", k,
               k == 0 ? "was not taken" : "was taken");
        CHECK(img.width == ref.width && img.height == ref.height &&
              !memcmp(img.pixels, ref.pixels, (size_t)ref.width * ref.height * 16));
        vx_render_scene_destroy(rs);
    }
    /* a scene that never builds a map frees what it took; NULL arguments */
    vx_render_sun_nodes* nodes = NULL;
    REQUIRE(vx_render_sun_nodes_make(&s, NULL, &nodes, &err) == VX_OK);
    REQUIRE(vx_render_scene_create(gpu, &s, &rs, &err) == VX_OK);
    vx_render_scene_take_sun_nodes(rs, nodes);
    vx_render_scene_destroy(rs);
    REQUIRE(vx_render_sun_nodes_make(&s, NULL, &nodes, &err) == VX_OK);
    vx_render_scene_take_sun_nodes(NULL, nodes);
    CHECK(vx_render_sun_nodes_make(NULL, NULL, &nodes, &err) == VX_ERR_INVALID_ARG);
    CHECK(vx_render_sun_nodes_make(&s, NULL, NULL, &err) == VX_ERR_INVALID_ARG);
    vx_render_sun_nodes_free(NULL);
    vx_render_image_free(&ref);
    vx_render_image_free(&img);
    vx_svo_scene_free(&s);
    vx_svo_scene_free(&other);
    CHECK(vx_gpu_validation_errors(gpu) == 0);
}

/* The pass pipeline's direct pass (the merged kernel, frame.comp, and the
 * separate direct.comp) with the sun's rays clipped by the map, against the
 * same frames with vx_render_desc.no_shadow_map: the same bits, for the
 * random model and the instances, several lights and map sides, in both
 * layouts; the frame after the first with a light uses the map
 * (vx_frame_result.shadow_map). */
static void test_passes_direct(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    vx_svo_model m[2];
    REQUIRE(ts_random_model(&m[0], 12, 10, 8, 45, 11) == VX_OK);
    REQUIRE(ts_random_model(&m[1], 40, 40, 2, 100, 3) == VX_OK);
    const double quarter[9] = {0, -1, 0, 1, 0, 0, 0, 0, 1}, mirror[9] = {-1, 0, 0, 0, 1, 0, 0, 0, 1};
    vx_svo_instance in[4] = {ts_inst(1, NULL, -4, -4, -2), ts_inst(0, NULL, 2, 3, 1), ts_inst(0, quarter, 30, 4, 1),
                             ts_inst(0, mirror, 20, 20, 1)};
    vx_svo_scene s;
    ts_scene(&s, m, 2, in, 4);
    static const size_t which[] = {0, 1, 3, 4, 8, 10};
    static const uint32_t sides[] = {0, 16};
    size_t frames = 0, used = 0;
    /* both layouts: a compact scene lists its map's nodes from its geometry read back (issue 18, branch smap3) */
    for (size_t si = 0; si < 4; si++) {
        bool compact = si >= 2;
        vx_render_scene_desc sd = {.shadow_map_side = sides[si % 2],
                                   .layout = compact ? VX_RENDER_LAYOUT_COMPACT : VX_RENDER_LAYOUT_PLAIN};
        vx_render_scene* rs = NULL;
        vx_frame_renderer* fr = NULL;
        vx_error err = {0};
        REQUIRE(vx_render_scene_create_ex(gpu, &s, &sd, &rs, &err) == VX_OK);
        REQUIRE(vx_frame_renderer_create(rs, &s, &fr, &err) == VX_OK);
        for (size_t w = 0; w < sizeof which / sizeof which[0]; w++)
            for (int sep = 0; sep < 2; sep++) {
                vx_frame_desc d = {.base = {.width = 48, .height = 36, .camera = persp(50, -20, 30, 16, 16, 4)},
                                   .separate_passes = sep != 0};
                memcpy(d.base.light_dir, lights[which[w]], sizeof d.base.light_dir);
                vx_frame_result a = {0}, b = {0};
                bool ok = true;
                for (int k = 0; k < 2 && ok; k++) { /* the second frame with this light builds and uses the map */
                    vx_render_image_free(&a.image);
                    ok = vx_frame_render(fr, &d, &a, &err) == VX_OK;
                }
                d.base.no_shadow_map = true;
                ok = ok && vx_frame_render(fr, &d, &b, &err) == VX_OK;
                CHECKF(ok, "passes: %s", err.msg);
                size_t n = (size_t)d.base.width * d.base.height * 4;
                bool same = ok && a.image.pixels && b.image.pixels && !memcmp(a.image.pixels, b.image.pixels, n * sizeof(float));
                CHECKF(same, "passes: %s side %u light %zu %s: the image differs with the map",
                       compact ? "compact" : "plain", sides[si % 2], which[w], sep ? "separate" : "merged");
                CHECK(!b.shadow_map);
                frames++, used += a.shadow_map;
                vx_render_image_free(&a.image);
                vx_render_image_free(&b.image);
            }
        vx_frame_renderer_destroy(fr);
        vx_render_scene_destroy(rs);
    }
    printf("passes: %zu frame pairs, %zu with the map\n", frames, used);
    CHECK(used == frames);
    vx_svo_scene_free(&s);
    CHECK(vx_gpu_validation_errors(gpu) == 0);
}

int main(void) {
    gpu_skip = vx_test_gpu_open((vx_gpu_desc){0}, true, &gpu);
    RUN(test_not_used);
    RUN(test_ahead);
    RUN(test_random_model);
    RUN(test_instances);
    RUN(test_terrain);
    RUN(test_compact_list);
    RUN(test_passes_direct);
    if (gpu) CHECK(vx_gpu_validation_errors(gpu) == 0);
    if (gpu) vx_gpu_destroy(gpu);
    return vx_test_finish();
}
