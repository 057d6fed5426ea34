/* tests/svo/test_svo_reader_model.c - the model reader's random access
 * (vx_svo_reader_model, issue 18: paging from files): after a pass that
 * finish accepted, any model read again on its own equals the whole read's
 * model (node words, every attribute channel's records, root, counts, its
 * check), in a random order with repeats, on every corpus .vox scene and on
 * generated scenes written in each NODE form (range-coded, chunked, split),
 * also from two threads at once and beside a second pass; refused before
 * such a pass, for an index past the models and after an error; a file
 * changed in place after the pass fails the changed model naming the file
 * and the model (the others still read); a file cut short fails naming the
 * file as a cut during a read, never a crash. */
#define _POSIX_C_SOURCE 200809L
#include <fcntl.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "svo/svo.h"
#include "tests/svo/reader_scenes.h"
#include "tests/test.h"
#include "tests/test_vox.h"

static char g_dir[64];

/* a and b the same model: words, records of every channel, fields, check */
static bool same_model(const vx_svo_model* a, const vx_svo_model* b) {
    if (memcmp(a->size, b->size, sizeof a->size) || a->depth != b->depth || a->root != b->root ||
        a->root_attr != b->root_attr || a->attrs != b->attrs || a->voxel_count != b->voxel_count ||
        a->node_count != b->node_count || a->attr_count != b->attr_count)
        return false;
    if (a->node_count && memcmp(a->nodes, b->nodes, (size_t)a->node_count * 4)) return false;
    size_t n = a->attr_count;
    if ((a->palette != NULL) != (b->palette != NULL) || (a->palette && memcmp(a->palette, b->palette, n))) return false;
    if ((a->rgba != NULL) != (b->rgba != NULL) || (a->rgba && memcmp(a->rgba, b->rgba, n * 4))) return false;
    if ((a->normal != NULL) != (b->normal != NULL) || (a->normal && memcmp(a->normal, b->normal, n * 4))) return false;
    if ((a->material != NULL) != (b->material != NULL) || (a->material && memcmp(a->material, b->material, n * 2)))
        return false;
    if ((a->density != NULL) != (b->density != NULL) || (a->density && memcmp(a->density, b->density, n * 4))) return false;
    return a->check.digest == b->check.digest && !memcmp(a->check.min, b->check.min, sizeof a->check.min) &&
           !memcmp(a->check.max, b->check.max, sizeof a->check.max);
}

/* one pass of next over every model, then finish */
static vx_result pass(vx_svo_model_reader* rd, vx_error* err) {
    uint32_t nm = vx_svo_reader_scene(rd)->model_count;
    for (;;) {
        uint32_t i = 0;
        vx_svo_model m;
        vx_result r = vx_svo_reader_next(rd, &i, &m, err);
        if (r) return r;
        if (i == nm) break;
        vx_svo_model_free(NULL, &m);
    }
    return vx_svo_reader_finish(rd, err);
}

typedef struct job {
    vx_svo_model_reader* rd;
    const vx_svo_scene* whole;
    uint32_t seed, reads, bad;
} job;

/* reads models at random and compares each with the whole read's */
static void* reads_at_random(void* arg) {
    job* j = (job*)arg;
    uint32_t nm = j->whole->model_count;
    for (uint32_t k = 0; k < j->reads; k++) {
        uint32_t i = tr_rng(&j->seed) % nm;
        vx_svo_model m;
        vx_error err = {0};
        if (vx_svo_reader_model(j->rd, i, &m, &err) != VX_OK) {
            fprintf(stderr, "  model %u: %s\n", i, err.msg);
            j->bad++;
            continue;
        }
        if (!same_model(&m, &j->whole->models[i])) {
            fprintf(stderr, "  model %u differs from the whole read's\n", i);
            j->bad++;
        }
        vx_svo_model_free(NULL, &m);
    }
    return NULL;
}

/* Every model of the file at path read at random (each at least once, in a
 * shuffled order, then random ones on two threads and beside a second pass)
 * equals the whole read's. */
static void check_file(const char* path, const char* what) {
    vx_svo_scene whole;
    vx_error err = {0};
    REQUIRE(vx_svo_read_file(NULL, path, &whole, &err) == VX_OK);
    uint32_t nm = whole.model_count;
    vx_svo_model_reader* rd = NULL;
    REQUIRE(vx_svo_reader_open(&(vx_svo_read_desc){.threads = 2}, path, &rd, &err) == VX_OK);
    vx_svo_model m;
    /* before a pass that finish accepted: refused (before any model, and mid-pass) */
    CHECKF(vx_svo_reader_model(rd, 0, &m, &err) == VX_ERR_INVALID_ARG && strstr(err.msg, path), "%s: %s", what, err.msg);
    if (nm) {
        uint32_t i;
        REQUIRE(vx_svo_reader_next(rd, &i, &m, &err) == VX_OK && i == 0);
        vx_svo_model_free(NULL, &m);
        CHECK(vx_svo_reader_model(rd, 0, &m, &err) == VX_ERR_INVALID_ARG);
        vx_svo_reader_close(rd);
        REQUIRE(vx_svo_reader_open(&(vx_svo_read_desc){.threads = 2}, path, &rd, &err) == VX_OK);
    }
    CHECKF(pass(rd, &err) == VX_OK, "%s: %s", what, err.msg);
    /* each model once, shuffled */
    uint32_t* order = malloc((nm ? nm : 1) * sizeof *order);
    uint32_t seed = 12345u + nm, differ = 0, failed = 0;
    for (uint32_t k = 0; k < nm; k++) order[k] = k;
    for (uint32_t k = nm; k > 1; k--) {
        uint32_t j = tr_rng(&seed) % k, t = order[k - 1];
        order[k - 1] = order[j], order[j] = t;
    }
    for (uint32_t k = 0; k < nm; k++) {
        if (vx_svo_reader_model(rd, order[k], &m, &err) != VX_OK) {
            if (!failed++) fprintf(stderr, "  %s: model %u: %s\n", what, order[k], err.msg);
            continue;
        }
        if (!same_model(&m, &whole.models[order[k]])) differ++;
        vx_svo_model_free(NULL, &m);
    }
    CHECKF(!failed && !differ, "%s: %u of %u models failed, %u differ", what, failed, nm, differ);
    /* past the models: refused, and the reader goes on */
    CHECKF(vx_svo_reader_model(rd, nm, &m, &err) == VX_ERR_INVALID_ARG && strstr(err.msg, path), "%s", err.msg);
    CHECK(vx_svo_reader_model(rd, UINT32_MAX, &m, &err) == VX_ERR_INVALID_ARG);
    CHECK(vx_svo_reader_model(NULL, 0, &m, &err) == VX_ERR_INVALID_ARG);
    CHECK(vx_svo_reader_model(rd, 0, NULL, &err) == VX_ERR_INVALID_ARG);
    if (nm) {
        /* two threads at random at once, and a second pass beside them */
        CHECKF(vx_svo_reader_rewind(rd, &err) == VX_OK, "%s", err.msg);
        job jobs[2] = {{rd, &whole, 7u, 3 * nm + 4, 0}, {rd, &whole, 99u, 3 * nm + 4, 0}};
        pthread_t t[2];
        for (int k = 0; k < 2; k++) REQUIRE(pthread_create(&t[k], NULL, reads_at_random, &jobs[k]) == 0);
        vx_result pr = pass(rd, &err);
        for (int k = 0; k < 2; k++) pthread_join(t[k], NULL);
        CHECKF(pr == VX_OK, "%s: the second pass beside random reads: %s", what, err.msg);
        CHECKF(jobs[0].bad + jobs[1].bad == 0, "%s: %u random reads failed or differ", what, jobs[0].bad + jobs[1].bad);
    }
    free(order);
    vx_svo_reader_close(rd);
    vx_svo_scene_free(&whole);
}

static const struct {
    const char* name;
    vx_write_desc d;
} g_forms[] = {
    {"range-coded", {0}},
    {"chunked", {.svo_chunk_words = 16}},
    {"split", {.testing.split_words = 1}},
    {"split, mixed", {.svo_chunk_words = 4096, .testing.split_words = 16}},
};

static void test_generated(void) {
    for (int rgba = 0; rgba < 2; rgba++) {
        vx_svo_scene s;
        tr_make_scene(&s, &(tr_scene_desc){.models = 9, .rgba = rgba, .large_last = true, .spacing = 64, .bump = UINT32_MAX});
        for (size_t f = 0; f < sizeof g_forms / sizeof g_forms[0]; f++) {
            char path[128], what[64];
            snprintf(path, sizeof path, "%s/g%d_%zu.svo", g_dir, rgba, f);
            snprintf(what, sizeof what, "%s, %s", rgba ? "rgba" : "palette", g_forms[f].name);
            vx_error err = {0};
            REQUIRE(vx_svo_write_file(&g_forms[f].d, &s, path, &err) == VX_OK);
            check_file(path, what);
        }
        vx_svo_scene_free(&s);
    }
    /* no models */
    vx_svo_scene e;
    vx_svo_scene_init(&e, NULL);
    char path[128];
    snprintf(path, sizeof path, "%s/empty.svo", g_dir);
    vx_error err = {0};
    REQUIRE(vx_svo_write_file(NULL, &e, path, &err) == VX_OK);
    check_file(path, "no models");
}

static void test_corpus(void) {
    static const char* files[] = {"eph_chr_knight.vox", "eph_dragon.vox", "eph_menger.vox", "eph_monu1.vox",
                                  "eph_teapot.vox", "ogt_chr_knight.vox", "ogt_doom.vox", "ogt_test_groups.vox",
                                  "ogt_test_multiple_model_scene.vox"};
    int done = 0;
    for (size_t i = 0; i < sizeof files / sizeof files[0]; i++) {
        vx_svo_scene s;
        vx_test_vox st = vx_test_vox_scene(files[i], &s);
        if (st == VX_TEST_VOX_ABSENT) continue;
        done++;
        CHECKF(st == VX_TEST_VOX_OK, "%s: not loaded", files[i]);
        if (st != VX_TEST_VOX_OK) continue;
        /* as written by default, and every model in the split form */
        for (size_t f = 0; f < sizeof g_forms / sizeof g_forms[0]; f += 2) {
            char path[128], what[128];
            snprintf(path, sizeof path, "%s/corpus%zu.svo", g_dir, f);
            snprintf(what, sizeof what, "%s, %s", files[i], g_forms[f].name);
            vx_error err = {0};
            REQUIRE(vx_svo_write_file(&g_forms[f].d, &s, path, &err) == VX_OK);
            check_file(path, what);
        }
        vx_svo_scene_free(&s);
    }
    if (!done) SKIP("no corpus .vox files");
}

/* A file changed in place after the pass (model 3 with one colour moved, the
 * same length): model 3 fails naming the file and the model, the others
 * still read; the error does not stop the reader. Then cut short: the
 * models past the cut fail as a cut during a read, naming the file. */
static void test_changed_and_cut(void) {
    enum { NM = 6, BUMP = 3 };
    vx_svo_scene a;
    vx_error err = {0};
    char pa[128], pb[128];
    snprintf(pa, sizeof pa, "%s/a.svo", g_dir);
    snprintf(pb, sizeof pb, "%s/b.svo", g_dir);
    size_t na = 0, nb = 0;
    uint8_t *fa, *fb;
    tr_changed_files(&(tr_scene_desc){.models = NM, .large_last = true, .spacing = 64}, BUMP, pa, pb, &a, &fa, &na, &fb, &nb);
    REQUIRE(fa && fb);
    vx_svo_model_reader* rd = NULL;
    REQUIRE(vx_svo_reader_open(NULL, pa, &rd, &err) == VX_OK);
    REQUIRE(pass(rd, &err) == VX_OK);
    int fd = open(pa, O_WRONLY);
    REQUIRE(fd >= 0);
    CHECK(pwrite(fd, fb, nb, 0) == (ssize_t)nb);
    close(fd);
    vx_svo_model m;
    vx_result r = vx_svo_reader_model(rd, BUMP, &m, &err);
    CHECKF(r == VX_ERR_BAD_FORMAT && strstr(err.msg, pa) && strstr(err.msg, "model 3") && strstr(err.msg, "file changed"),
           "%d: %s", (int)r, err.msg);
    for (uint32_t i = 0; i < NM; i++) {
        if (i == BUMP) continue;
        CHECKF(vx_svo_reader_model(rd, i, &m, &err) == VX_OK, "model %u: %s", i, err.msg);
        CHECK(m.node_count == a.models[i].node_count && !memcmp(m.nodes, a.models[i].nodes, 4ull * m.node_count));
        vx_svo_model_free(NULL, &m);
    }
    /* cut to half: the last model's stream lies past the end */
    struct stat st;
    REQUIRE(stat(pa, &st) == 0 && truncate(pa, st.st_size / 2) == 0);
    r = vx_svo_reader_model(rd, NM - 1, &m, &err);
    CHECKF(r == VX_ERR_TRUNCATED && strstr(err.msg, pa) && strstr(err.msg, "model 5") && strstr(err.msg, "cut short"),
           "%d: %s", (int)r, err.msg);
    CHECK(m.nodes == NULL && m.node_count == 0);
    r = vx_svo_reader_model(rd, 0, &m, &err); /* before the cut: still there */
    CHECKF(r == VX_OK, "%s", err.msg);
    vx_svo_model_free(NULL, &m);
    vx_svo_reader_close(rd);
    /* a reader stopped by an error of next refuses random access too */
    REQUIRE(vx_svo_write_file(NULL, &a, pa, &err) == VX_OK);
    REQUIRE(vx_svo_reader_open(NULL, pa, &rd, &err) == VX_OK);
    REQUIRE(pass(rd, &err) == VX_OK);
    REQUIRE(vx_svo_reader_rewind(rd, &err) == VX_OK);
    REQUIRE(stat(pa, &st) == 0 && truncate(pa, 40) == 0);
    CHECK(pass(rd, &err) != VX_OK);
    r = vx_svo_reader_model(rd, 0, &m, &err);
    CHECKF(r == VX_ERR_INVALID_ARG && strstr(err.msg, "earlier error"), "%d: %s", (int)r, err.msg);
    vx_svo_reader_close(rd);
    free(fa);
    free(fb);
    vx_svo_scene_free(&a);
}

int main(void) {
    if (!tr_dir_make(g_dir, "rmodel")) return 1;
    RUN(test_generated);
    RUN(test_corpus);
    RUN(test_changed_and_cut);
    tr_dir_remove(g_dir);
    return vx_test_finish();
}
