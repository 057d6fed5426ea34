/* tests/fuzz/make_svo_reader_seeds.c - writes svo_reader_fuzz's own seeds:
 * scenes of many small models (so that the fuzz target's two threads take
 * models at once and a damaged model sits between good ones), one file per
 * NODE form the reader decodes: the range-coded form (raw and structural
 * models), the chunked form (zstd and DEFLATE chunks, stored chunks) and the
 * split form (FORMAT.md 3.4, 3.6, 3.7).
 *
 *   make_svo_reader_seeds DIR     (tests/fuzz/svo_reader_seeds) */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "svo/svo.h"

static uint64_t rs = 0x2545F4914F6CDD1Dull;
static uint64_t rnd(void) {
    rs ^= rs << 13;
    rs ^= rs >> 7;
    rs ^= rs << 17;
    return rs;
}

/* n random cells in an S^3 model with attrs; a few runs of equal cells so
 * the DAG shares subtrees (the structural form's references). */
static int build(vx_svo_model* m, uint32_t S, size_t n, uint32_t attrs) {
    uint64_t* k = malloc(n * 8);
    uint8_t* p = malloc(n);
    uint32_t* c = malloc(n * 4);
    if (!k || !p || !c) return 0;
    for (size_t i = 0; i < n; i++) {
        uint32_t x = (uint32_t)(rnd() % S), y = (uint32_t)(rnd() % S), z = (uint32_t)(rnd() % S);
        if (i % 3 == 0) x &= ~3u, y &= ~3u; /* repeated bricks */
        k[i] = vx_svo_morton(x, y, z);
        p[i] = (uint8_t)(1 + rnd() % 5);
        c[i] = 0xFF000000u | (uint32_t)(rnd() % 4) * 0x404040u;
    }
    vx_svo_voxels in = {.size = {S, S, S}, .count = n, .keys = k, .attrs = attrs};
    if (attrs & VX_ATTR_PALETTE) in.palette = p;
    if (attrs & VX_ATTR_RGBA8) in.rgba = c;
    vx_error e;
    int ok = vx_svo_build_model(NULL, &in, m, NULL, &e) == VX_OK;
    if (!ok) fprintf(stderr, "build: %s\n", e.msg);
    free(k), free(p), free(c);
    return ok;
}

/* models models (palette, RGBA, geometry only in turn), one instance each on a row, one more hidden */
static int make_scene(vx_svo_scene* s, uint32_t models) {
    vx_svo_scene_init(s, NULL);
    s->models = calloc(models, sizeof *s->models);
    s->instances = calloc(models + 1, sizeof *s->instances);
    if (!s->models || !s->instances) return 0;
    s->model_count = models, s->instance_count = models + 1;
    for (uint32_t i = 0; i < models; i++) {
        uint32_t attrs = i % 3 == 0 ? VX_ATTR_PALETTE : i % 3 == 1 ? VX_ATTR_RGBA8 : 0;
        if (!build(&s->models[i], 8u << (i % 3), 6 + 5 * (i % 4), attrs)) return 0;
    }
    s->has_palette = true;
    for (int i = 0; i < 256; i++) s->palette[i] = 0xFF000000u | (uint32_t)i * 0x010305u;
    for (uint32_t i = 0; i <= models; i++) {
        vx_svo_instance* in = &s->instances[i];
        double id[12] = {1, 0, 0, 40.0 * i, 0, 1, 0, 0, 0, 0, 1, 0};
        memcpy(in->xform, id, sizeof id);
        in->model = i % models;
        in->layer = UINT32_MAX;
        in->flags = i == models ? VX_SVO_INSTANCE_HIDDEN : 0;
    }
    vx_svo_scene_update_bounds(s);
    return 1;
}

int main(int argc, char** argv) {
    if (argc != 2) return fprintf(stderr, "usage: make_svo_reader_seeds DIR\n"), 2;
    /* testing.split_words: the models of at least that many words in the
     * split form; split_no_runs: without its runs stream (version 5) */
    struct {
        const char* name;
        vx_write_desc w;
    } forms[] = {
        {"coded", {0}},
        {"chunked_zstd", {.svo_chunk_words = 1}},
        {"chunked_deflate", {.svo_chunk_words = 1, .svo_chunk_deflate = true}},
        {"chunked_stored", {.svo_chunk_words = 1, .svo_chunk_stored = true}},
        {"split", {.testing.split_words = 1}},
        {"split_mixed", {.svo_chunk_words = 64, .testing.split_words = 16}}, /* larger models chunked, middle ones split, small coded */
        {"split_v5", {.testing = {.split_words = 1, .split_no_runs = true}}},
    };
    for (size_t f = 0; f < sizeof forms / sizeof forms[0]; f++) {
        vx_svo_scene s;
        if (!make_scene(&s, 9)) return fprintf(stderr, "make_svo_reader_seeds: out of memory\n"), 1;
        char path[4096];
        snprintf(path, sizeof path, "%s/%s.svo", argv[1], forms[f].name);
        vx_error e;
        vx_result r = vx_svo_write_file(&forms[f].w, &s, path, &e);
        vx_svo_scene_free(&s);
        if (r != VX_OK) return fprintf(stderr, "%s: %s\n", path, e.msg), 1;
    }
    return 0;
}
