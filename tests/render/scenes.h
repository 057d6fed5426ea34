/* tests/render/scenes.h - small scenes built in code for the render tests. */
#ifndef VX_TEST_RENDER_SCENES_H
#define VX_TEST_RENDER_SCENES_H
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "render/render.h"
#include "svo/svo.h"

/* deterministic PRNG */
static uint32_t ts_rng(uint32_t* s) {
    *s ^= *s << 13;
    *s ^= *s >> 17;
    *s ^= *s << 5;
    return *s;
}

/* Builds a model from n cells (xyz triples) with palette indices; far: the
 * builder's far limit (vx_svo_testing.far_limit; 0: the default). */
static vx_result ts_model_far(vx_svo_model* m, const uint32_t size[3], const uint32_t* xyz, const uint8_t* pal, size_t n, uint32_t far) {
    uint64_t* keys = malloc((n ? n : 1) * sizeof *keys);
    if (!keys) return VX_ERR_NOMEM;
    for (size_t i = 0; i < n; i++) keys[i] = vx_svo_morton(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]);
    vx_svo_voxels v = {.size = {size[0], size[1], size[2]}, .count = n, .keys = keys, .attrs = pal ? VX_ATTR_PALETTE : 0,
                       .palette = pal};
    vx_error err = {0};
    vx_result r = vx_svo_build_model(&(vx_svo_build_desc){.testing.far_limit = far}, &v, m, NULL, &err);
    if (r) fprintf(stderr, "build: %s\n", err.msg);
    free(keys);
    return r;
}
static vx_result ts_model(vx_svo_model* m, const uint32_t size[3], const uint32_t* xyz, const uint8_t* pal, size_t n) {
    return ts_model_far(m, size, xyz, pal, n, 0);
}

/* Random model: each cell of size^3 filled with probability pct/100 (far: as ts_model_far's). */
static vx_result ts_random_model_far(vx_svo_model* m, uint32_t sx, uint32_t sy, uint32_t sz, uint32_t pct, uint32_t seed, uint32_t far) {
    size_t cap = (size_t)sx * sy * sz, n = 0;
    uint32_t* xyz = malloc(cap * 12);
    uint8_t* pal = malloc(cap);
    if (!xyz || !pal) return VX_ERR_NOMEM;
    for (uint32_t z = 0; z < sz; z++)
        for (uint32_t y = 0; y < sy; y++)
            for (uint32_t x = 0; x < sx; x++)
                if (ts_rng(&seed) % 100 < pct) {
                    xyz[3 * n] = x, xyz[3 * n + 1] = y, xyz[3 * n + 2] = z;
                    pal[n++] = (uint8_t)(1 + ts_rng(&seed) % 255);
                }
    uint32_t size[3] = {sx, sy, sz};
    vx_result r = ts_model_far(m, size, xyz, pal, n, far);
    free(xyz);
    free(pal);
    return r;
}
static vx_result ts_random_model(vx_svo_model* m, uint32_t sx, uint32_t sy, uint32_t sz, uint32_t pct, uint32_t seed) {
    return ts_random_model_far(m, sx, sy, sz, pct, seed, 0);
}

/* The compact layout's field seams (render/compact.h): a 32^3 palette
 * model whose every 4^3 brick lacks one cell, at a place that varies, so
 * every level-3 node has 8 bricks of 63 cells and every level-4 node 4,032
 * cells (the largest counts the index words and the level-4 ranks hold). */
static inline vx_result ts_seam_model(vx_svo_model* m) {
    uint32_t size[3] = {32, 32, 32}, *xyz = malloc(32768 * 12);
    uint8_t* pal = malloc(32768);
    size_t n = 0;
    if (!xyz || !pal) {
        free(xyz), free(pal);
        return VX_ERR_NOMEM;
    }
    for (uint32_t z = 0; z < 32; z++)
        for (uint32_t y = 0; y < 32; y++)
            for (uint32_t x = 0; x < 32; x++) {
                uint32_t hole = (x / 4 * 7 + y / 4 * 13 + z / 4 * 29) % 64;
                if ((uint32_t)vx_svo_morton(x % 4, y % 4, z % 4) == hole) continue;
                xyz[3 * n] = x, xyz[3 * n + 1] = y, xyz[3 * n + 2] = z;
                pal[n++] = (uint8_t)(1 + (x + 3 * y + 5 * z) % 250);
            }
    vx_result r = ts_model(m, size, xyz, pal, n);
    free(xyz), free(pal);
    return r;
}

static void ts_palette(vx_svo_scene* s) {
    s->has_palette = true;
    uint32_t seed = 99;
    for (int i = 1; i < 256; i++) s->palette[i] = (ts_rng(&seed) & 0xFFFFFFu) | 0xFF000000u;
}

/* A scene owning copies of the given models (moved in) and instances. */
static void ts_scene(vx_svo_scene* s, vx_svo_model* models, uint32_t nm, const vx_svo_instance* inst, uint32_t ni) {
    vx_svo_scene_init(s, NULL);
    ts_palette(s);
    s->models = calloc(nm ? nm : 1, sizeof *s->models);
    s->instances = calloc(ni ? ni : 1, sizeof *s->instances);
    if (nm) memcpy(s->models, models, nm * sizeof *models);
    if (ni) memcpy(s->instances, inst, ni * sizeof *inst);
    s->model_count = nm;
    s->instance_count = ni;
    for (uint32_t i = 0; i < ni; i++) s->instances[i].layer = UINT32_MAX;
    vx_svo_scene_update_bounds(s);
}

static vx_svo_instance ts_inst(uint32_t model, const double m9[9], double tx, double ty, double tz) {
    vx_svo_instance in;
    memset(&in, 0, sizeof in);
    in.model = model;
    in.layer = UINT32_MAX;
    static const double id[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    if (!m9) m9 = id;
    for (int r = 0; r < 3; r++) {
        for (int c = 0; c < 3; c++) in.xform[4 * r + c] = m9[3 * r + c];
    }
    in.xform[3] = tx, in.xform[7] = ty, in.xform[11] = tz;
    return in;
}

/* The world point of model point m under instance in (world = M m + t). */
static inline void ts_inst_point(const vx_svo_instance* in, const double m[3], double w[3]) {
    for (int k = 0; k < 3; k++) {
        w[k] = in->xform[4 * k + 3];
        for (int c = 0; c < 3; c++) w[k] += in->xform[4 * k + c] * m[c];
    }
}

/* A scene whose only instance (untransformed) is one model `side` cells on a
 * side (a power of two) holding the n cells xyz (palette indices pal): the
 * deep-model tests' (test_render_gpu, test_passes). *depth: its levels. */
static inline vx_result ts_cube_scene(vx_svo_scene* s, uint32_t side, const uint32_t* xyz, const uint8_t* pal, size_t n,
                                      uint32_t* depth) {
    vx_svo_model m;
    vx_result r = ts_model(&m, (uint32_t[3]){side, side, side}, xyz, pal, n);
    if (r) return r;
    *depth = m.depth;
    vx_svo_instance in = ts_inst(0, NULL, 0, 0, 0);
    ts_scene(s, &m, 1, &in, 1);
    return VX_OK;
}
#endif
