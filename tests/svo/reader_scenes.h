/* tests/svo/reader_scenes.h - set-up shared by the model reader's tests
 * (test_svo_reader_model: random access, test_svo_reader_rewind: the second
 * pass): generated scenes of random cells, a file read whole, and a file
 * changed in place that keeps its length (one model's colour moved), which
 * both tests write over a file the reader has open. They were copies of
 * each other. The tests' folder is made and removed by tr_dir_make and
 * tr_dir_remove. */
#ifndef VX_TEST_SVO_READER_SCENES_H
#define VX_TEST_SVO_READER_SCENES_H
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "svo/svo.h"
#include "tests/test.h"

/* deterministic PRNG */
static uint32_t tr_rng(uint32_t* s) {
    *s ^= *s << 13;
    *s ^= *s >> 17;
    *s ^= *s << 5;
    return *s;
}

/* A generated scene: models of random cells (30% of a cube of side
 * 5 + (i * 7) % 23; the last one of side 60 with large_last, which the
 * chunked and split forms take with small thresholds), palette indices or,
 * with rgba, RGBA colours; each model's one instance spacing apart along x.
 * Model bump's attribute at (bump UINT32_MAX: none) one palette index (one
 * colour step) further: the same cells, other colours. */
typedef struct tr_scene_desc {
    uint32_t models;
    bool rgba, large_last;
    double spacing;
    uint32_t bump, at;
} tr_scene_desc;

static void tr_make_scene(vx_svo_scene* s, const tr_scene_desc* d) {
    uint32_t nm = d->models;
    vx_svo_scene_init(s, NULL);
    s->models = calloc(nm, sizeof *s->models);
    s->instances = calloc(nm, sizeof *s->instances);
    REQUIRE(s->models && s->instances);
    s->model_count = s->instance_count = nm;
    for (uint32_t k = 0; k < 256; k++) s->palette[k] = 0xFF000000u | (k * 0x010305u);
    s->has_palette = !d->rgba;
    for (uint32_t i = 0; i < nm; i++) {
        uint32_t side = 5 + (i * 7) % 23, seed = 77 + i, n = 0;
        if (d->large_last && i == nm - 1) side = 60;
        size_t cap = (size_t)side * side * side;
        uint64_t* keys = malloc(cap * sizeof *keys);
        uint8_t* pal = malloc(cap);
        uint32_t* col = malloc(cap * 4);
        REQUIRE(keys && pal && col);
        for (uint32_t z = 0; z < side; z++)
            for (uint32_t y = 0; y < side; y++)
                for (uint32_t x = 0; x < side; x++)
                    if (tr_rng(&seed) % 100 < 30) {
                        keys[n] = vx_svo_morton(x, y, z);
                        pal[n] = (uint8_t)(1 + tr_rng(&seed) % 200);
                        col[n] = 0xFF000000u | (tr_rng(&seed) & 0x00F0F0F0u);
                        if (i == d->bump && n == d->at) pal[n]++, col[n] ^= 0x10u;
                        n++;
                    }
        vx_svo_voxels v = {.size = {side, side, side}, .count = n, .keys = keys};
        if (d->rgba) v.attrs = VX_ATTR_RGBA8, v.rgba = col;
        else v.attrs = VX_ATTR_PALETTE, v.palette = pal;
        vx_error err = {0};
        if (vx_svo_build_model(NULL, &v, &s->models[i], NULL, &err)) fprintf(stderr, "build: %s\n", err.msg);
        free(keys);
        free(pal);
        free(col);
        vx_svo_instance* in = &s->instances[i];
        memset(in, 0, sizeof *in);
        in->model = i;
        in->layer = UINT32_MAX;
        in->xform[0] = in->xform[5] = in->xform[10] = 1;
        in->xform[3] = d->spacing * i;
    }
    vx_svo_scene_update_bounds(s);
}

/* A whole file (NULL when it cannot be read); *n its bytes. */
static uint8_t* tr_slurp(const char* path, size_t* n) {
    FILE* f = fopen(path, "rb");
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    *n = (size_t)ftell(f);
    fseek(f, 0, SEEK_SET);
    uint8_t* b = malloc(*n ? *n : 1);
    if (b && fread(b, 1, *n, f) != *n) free(b), b = NULL;
    fclose(f);
    return b;
}

/* Writes d's scene (d->bump ignored) to path_a, and the first variant with
 * model bump's colour moved (d->at = 0, 1, ...) whose file has the same
 * length and other bytes to path_b: *fa, *fb their bytes (REQUIRE: such a
 * variant exists). A file written over a's in place then changes model
 * bump only, its stream's length and offset kept. */
static void tr_changed_files(const tr_scene_desc* d, uint32_t bump, const char* path_a, const char* path_b, vx_svo_scene* a,
                             uint8_t** fa, size_t* na, uint8_t** fb, size_t* nb) {
    vx_error err = {0};
    *fa = *fb = NULL;
    tr_scene_desc da = *d;
    da.bump = UINT32_MAX;
    tr_make_scene(a, &da);
    REQUIRE(vx_svo_write_file(NULL, a, path_a, &err) == VX_OK);
    *fa = tr_slurp(path_a, na);
    REQUIRE(*fa);
    for (uint32_t at = 0; at < a->models[bump].voxel_count && !*fb; at++) {
        vx_svo_scene b;
        tr_scene_desc db = *d;
        db.bump = bump, db.at = at;
        tr_make_scene(&b, &db);
        REQUIRE(vx_svo_write_file(NULL, &b, path_b, &err) == VX_OK);
        vx_svo_scene_free(&b);
        *fb = tr_slurp(path_b, nb);
        if (*fb && (*nb != *na || !memcmp(*fa, *fb, *na))) free(*fb), *fb = NULL;
    }
    REQUIRE(*fb);
}

/* The tests' folder: /tmp/vx_<tag>XXXXXX made (false: not made), and removed with what it holds. */
static bool tr_dir_make(char dir[64], const char* tag) {
    snprintf(dir, 64, "/tmp/vx_%sXXXXXX", tag);
    return mkdtemp(dir) != NULL;
}

static void tr_dir_remove(const char* dir) {
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    if (system(cmd) != 0) fprintf(stderr, "could not remove %s\n", dir);
}

#endif
