/* tests/svo/test_svo_reader_rewind.c - the model reader's second pass
 * (vx_svo_reader_rewind, issue 18): after a pass that finish accepted, the
 * models come again from the file, the same models (digest, counts, cells'
 * box) in the same order, on the structural and the chunked forms, and
 * finish checks NODE again; a rewind before finish, mid-pass or after an
 * error is refused; a file cut between the passes fails the second pass
 * naming the file; a file changed in place between the passes (a model with
 * other colours, the same bytes long) fails naming the model. */
#define _POSIX_C_SOURCE 200809L
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "svo/svo.h"
#include "tests/svo/reader_scenes.h"
#include "tests/test.h"

static char g_dir[64];

typedef struct seen {
    uint32_t digest, min[3], max[3];
    uint64_t voxels, words;
} seen;

/* one pass: every model in order into got[], then finish */
static vx_result pass(vx_svo_model_reader* rd, seen* got, uint32_t nm, uint32_t* taken, vx_error* err) {
    *taken = 0;
    for (;;) {
        uint32_t i = 0;
        vx_svo_model m;
        vx_result r = vx_svo_reader_next(rd, &i, &m, err);
        if (r) return r;
        if (i == nm) break;
        if (i != *taken) {
            vx_svo_model_free(NULL, &m);
            return VX_ERR_INVALID_ARG;
        }
        const vx_svo_model_check* c = &vx_svo_reader_scene(rd)->models[i].check;
        got[i] = (seen){.digest = vx_svo_model_digest(&m), .voxels = m.voxel_count, .words = m.node_count};
        memcpy(got[i].min, c->min, sizeof got[i].min);
        memcpy(got[i].max, c->max, sizeof got[i].max);
        vx_svo_model_free(NULL, &m);
        (*taken)++;
    }
    return vx_svo_reader_finish(rd, err);
}

static void test_passes(void) {
    vx_svo_scene s;
    enum { NM = 12 };
    tr_make_scene(&s, &(tr_scene_desc){.models = NM, .spacing = 32, .bump = UINT32_MAX});
    vx_error err = {0};
    for (int form = 0; form < 2; form++) {
        char path[128];
        snprintf(path, sizeof path, "%s/p%d.svo", g_dir, form);
        REQUIRE(vx_svo_write_file(&(vx_write_desc){.svo_chunk_words = form ? 16 : 0}, &s, path, &err) == VX_OK);
        vx_svo_model_reader* rd = NULL;
        REQUIRE(vx_svo_reader_open(NULL, path, &rd, &err) == VX_OK);
        /* before a pass, and mid-pass: refused, and the reader goes on */
        CHECKF(vx_svo_reader_rewind(rd, &err) == VX_ERR_INVALID_ARG && strstr(err.msg, path), "%s", err.msg);
        uint32_t i;
        vx_svo_model m;
        REQUIRE(vx_svo_reader_next(rd, &i, &m, &err) == VX_OK && i == 0);
        vx_svo_model_free(NULL, &m);
        CHECK(vx_svo_reader_rewind(rd, &err) == VX_ERR_INVALID_ARG);
        vx_svo_reader_close(rd);
        seen first[NM], again[NM];
        uint32_t taken = 0;
        REQUIRE(vx_svo_reader_open(NULL, path, &rd, &err) == VX_OK);
        CHECKF(pass(rd, first, NM, &taken, &err) == VX_OK && taken == NM, "form %d: %s", form, err.msg);
        for (int p = 2; p <= 3; p++) {
            CHECKF(vx_svo_reader_rewind(rd, &err) == VX_OK, "%s", err.msg);
            memset(again, 0, sizeof again);
            CHECKF(pass(rd, again, NM, &taken, &err) == VX_OK && taken == NM, "form %d pass %d: %s", form, p, err.msg);
            CHECKF(memcmp(first, again, sizeof first) == 0, "form %d pass %d: other models", form, p);
        }
        for (uint32_t k = 0; k < NM; k++) CHECK(first[k].digest == vx_svo_model_digest(&s.models[k]) && first[k].voxels);
        /* cut between the passes: the second pass fails naming the file, then refuses more */
        CHECK(vx_svo_reader_rewind(rd, &err) == VX_OK);
        struct stat st;
        REQUIRE(stat(path, &st) == 0 && truncate(path, st.st_size / 2) == 0);
        vx_result r = pass(rd, again, NM, &taken, &err);
        CHECKF(r == VX_ERR_TRUNCATED && strstr(err.msg, path) && taken < NM, "form %d: %d %s", form, (int)r, err.msg);
        CHECK(vx_svo_reader_next(rd, &i, &m, &err) != VX_OK);
        CHECK(vx_svo_reader_finish(rd, &err) != VX_OK);
        CHECK(vx_svo_reader_rewind(rd, &err) == VX_ERR_INVALID_ARG);
        vx_svo_reader_close(rd);
    }
    vx_svo_scene_free(&s);
}

static void test_changed_between_passes(void) {
    enum { NM = 6, BUMP = 3 };
    vx_svo_scene a;
    vx_error err = {0};
    char pa[128], pb[128];
    snprintf(pa, sizeof pa, "%s/a.svo", g_dir);
    snprintf(pb, sizeof pb, "%s/b.svo", g_dir);
    size_t na = 0, nb = 0;
    uint8_t *fa, *fb;
    /* model 3 with one colour moved: the first such file of a's length (its other bytes shifted by nothing) */
    tr_changed_files(&(tr_scene_desc){.models = NM, .spacing = 32}, BUMP, pa, pb, &a, &fa, &na, &fb, &nb);
    REQUIRE(fa && fb);
    vx_svo_model_reader* rd = NULL;
    seen first[NM];
    uint32_t taken = 0;
    REQUIRE(vx_svo_reader_open(NULL, pa, &rd, &err) == VX_OK);
    REQUIRE(pass(rd, first, NM, &taken, &err) == VX_OK);
    /* b's bytes over a's, in place (the reader's open file sees them) */
    int fd = open(pa, O_WRONLY);
    REQUIRE(fd >= 0);
    CHECK(pwrite(fd, fb, nb, 0) == (ssize_t)nb);
    close(fd);
    CHECK(vx_svo_reader_rewind(rd, &err) == VX_OK);
    seen again[NM];
    vx_result r = pass(rd, again, NM, &taken, &err);
    CHECKF(r == VX_ERR_BAD_FORMAT && taken == BUMP && strstr(err.msg, pa) && strstr(err.msg, "model 3") &&
               strstr(err.msg, "changed between the passes"),
           "%d, %u taken: %s", (int)r, taken, err.msg);
    CHECK(memcmp(first, again, BUMP * sizeof *first) == 0);
    CHECK(vx_svo_reader_finish(rd, &err) != VX_OK);
    vx_svo_reader_close(rd);
    CHECK(vx_svo_reader_rewind(NULL, &err) == VX_ERR_INVALID_ARG);
    free(fa);
    free(fb);
    vx_svo_scene_free(&a);
}

int main(void) {
    if (!tr_dir_make(g_dir, "rewind")) return 1;
    RUN(test_passes);
    RUN(test_changed_between_passes);
    tr_dir_remove(g_dir);
    return vx_test_finish();
}
