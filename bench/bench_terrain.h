/* bench/bench_terrain.h - the procedural terrain of the tracer benchmarks
 * (and of tests/render/test_render_hits.c): columns of 8x8 cells whose top
 * two 8^3 tiles are filled (level-3 tiles, so the builder never expands
 * them), heights from a few sines up to ~3/4 of the extent, plus 2048
 * single-cell "pebbles" near the top: extent^3, depth log2(extent). With
 * deep_offset the terrain sits at that cell offset in a model 2^20 cells
 * wide (20 levels: the float64 trace variant). Returns 0 on success.
 * bench_terrain_desc builds it with bd (NULL: the defaults; the tests lower
 * the far limit through bd->testing). */
#ifndef VX_BENCH_TERRAIN_H
#define VX_BENCH_TERRAIN_H
#include <math.h>
#include <stdlib.h>

#include "svo/svo.h"

static inline int bench_terrain_desc(vx_svo_scene* s, uint32_t extent, uint32_t deep_offset, const vx_svo_build_desc* bd, vx_error* err) {
    const uint32_t cols = extent / 8;
    const double hs = extent / 4096.0;
    size_t cap = (size_t)cols * cols * 2 + 4096, n = 0;
    uint64_t* keys = malloc(cap * 8);
    uint8_t* level = malloc(cap);
    uint8_t* pal = malloc(cap);
    vx_svo_scene_init(s, NULL);
    if (!keys || !level || !pal) {
        free(keys), free(level), free(pal);
        return 1;
    }
    for (uint32_t y = 0; y < cols; y++)
        for (uint32_t x = 0; x < cols; x++) {
            double h = hs * (1400 + 700 * sin(x * 0.021 / hs) * cos(y * 0.017 / hs) + 500 * sin((x + 2 * y) * 0.0061 / hs) +
                             150 * sin(x * 0.11 / hs + y * 0.07 / hs));
            uint32_t top = (uint32_t)(h / 8);
            for (uint32_t k = 0; k < 2 && top >= k; k++) {
                keys[n] = vx_svo_morton(deep_offset + x * 8, deep_offset + y * 8, deep_offset + (top - k) * 8);
                level[n] = 3;
                pal[n++] = (uint8_t)(1 + (top % 200));
            }
        }
    uint32_t seed = 1;
    for (int i = 0; i < 2048; i++) {
        seed = seed * 1664525u + 1013904223u;
        uint32_t x = (seed >> 8) % extent;
        seed = seed * 1664525u + 1013904223u;
        uint32_t y = (seed >> 8) % extent;
        keys[n] = vx_svo_morton(deep_offset + x, deep_offset + y, deep_offset + extent - 96 + i % 64);
        level[n] = 0;
        pal[n++] = 250;
    }
    uint32_t side = deep_offset ? 1u << 20 : extent;
    vx_svo_voxels v = {.size = {side, side, side}, .count = n, .keys = keys, .level = level, .attrs = VX_ATTR_PALETTE,
                       .palette = pal};
    s->models = calloc(1, sizeof *s->models);
    s->instances = calloc(1, sizeof *s->instances);
    if (!s->models || !s->instances) {
        free(keys), free(level), free(pal);
        vx_svo_scene_free(s);
        return 1;
    }
    vx_result r = vx_svo_build_model(bd, &v, &s->models[0], NULL, err);
    free(keys), free(level), free(pal);
    if (r) {
        vx_svo_scene_free(s);
        return 1;
    }
    s->model_count = 1;
    s->instance_count = 1;
    s->instances[0].xform[0] = s->instances[0].xform[5] = s->instances[0].xform[10] = 1;
    s->instances[0].layer = UINT32_MAX;
    s->has_palette = true;
    for (int i = 1; i < 256; i++) s->palette[i] = 0xFF000000u | (uint32_t)(i * 0x010203);
    vx_svo_scene_update_bounds(s);
    return 0;
}
static inline int bench_terrain(vx_svo_scene* s, uint32_t extent, uint32_t deep_offset, vx_error* err) {
    return bench_terrain_desc(s, extent, deep_offset, NULL, err);
}
#endif
