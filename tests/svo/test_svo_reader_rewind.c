/* tests/svo/test_svo_reader_rewind.c - the model reader's second pass
 * (vx_svo_reader_rewind, issue 18): after a pass that finish accepted, the
 * models come again from the file, the same models (digest, counts, cells'
 * box) in the same order, on the structural and the chunked forms, and
 * finish checks NODE again; a rewind before finish, mid-pass or after an
 * error is refused; a file cut between the passes fails the second pass
 * naming the file; a file changed in place between the passes (a model with
 * other colours, the same bytes long) fails naming the model. And the
 * bounds of an animation's frames from the models' boxes of a pass
 * (vx_svo_reader_update_bounds). */
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

/* vx_svo_reader_update_bounds (issue 18, branch rdr4: svo_bake --load models --frame N): each frame of an
 * animation whose frames move, hide and turn instances gets, from the models' cells' boxes the reader's pass
 * found, the bounds vx_svo_scene_update_bounds gives the whole read's frame from the trees; refused before a
 * finished pass, and for a scene of other models. */
static void test_frame_bounds(void) {
    enum { NM = 5, NF = 4 };
    vx_svo_scene s;
    vx_error err = {0};
    tr_make_scene(&s, &(tr_scene_desc){.models = NM, .spacing = 32, .bump = UINT32_MAX});
    REQUIRE(vx_svo_scene_alloc_frames(&s, NF, &err) == VX_OK);
    for (uint32_t f = 1; f < NF; f++) {
        vx_svo_instance* in = (vx_svo_instance*)vx_svo_scene_frame_instances(&s, f);
        REQUIRE(in);
        in[NM - 1].xform[3] += 17.0 * f, in[NM - 1].xform[11] -= 5.0 * f; /* the last moves out and down */
        if (f == 2) in[0].flags |= VX_SVO_INSTANCE_HIDDEN; /* the first hidden: the box starts later */
        if (f == 3) {                                        /* model 2 a quarter turn about z, lifted */
            double* x = in[2].xform;
            x[0] = 0, x[1] = -1, x[4] = 1, x[5] = 0, x[11] = 40;
        }
    }
    char path[128];
    snprintf(path, sizeof path, "%s/frames.svo", g_dir);
    REQUIRE(vx_svo_write_file(NULL, &s, path, &err) == VX_OK);
    vx_svo_scene whole, graph;
    REQUIRE(vx_svo_read_file(NULL, path, &whole, &err) == VX_OK);
    vx_svo_model_reader* rd = NULL;
    REQUIRE(vx_svo_reader_open(NULL, path, &rd, &err) == VX_OK);
    REQUIRE(vx_svo_reader_copy_graph(rd, NULL, &graph, &err) == VX_OK);
    vx_svo_scene gv;
    REQUIRE(vx_svo_scene_frame(&graph, 1, &gv));
    CHECKF(vx_svo_reader_update_bounds(rd, &gv, &err) == VX_ERR_INVALID_ARG && strstr(err.msg, path), "%s", err.msg);
    seen got[NM];
    uint32_t taken = 0;
    REQUIRE(pass(rd, got, NM, &taken, &err) == VX_OK);
    double b0[6];
    for (uint32_t f = 0; f < NF; f++) {
        vx_svo_scene wv;
        REQUIRE(vx_svo_scene_frame(&whole, f, &wv) && vx_svo_scene_frame(&graph, f, &gv));
        vx_svo_scene_update_bounds(&wv);
        memset(gv.bounds_min, 0, sizeof gv.bounds_min), memset(gv.bounds_max, 0, sizeof gv.bounds_max);
        CHECKF(vx_svo_reader_update_bounds(rd, &gv, &err) == VX_OK, "%s", err.msg);
        bool same = !memcmp(wv.bounds_min, gv.bounds_min, sizeof gv.bounds_min) &&
                    !memcmp(wv.bounds_max, gv.bounds_max, sizeof gv.bounds_max);
        CHECKF(same, "frame %u: reader %g,%g,%g..%g,%g,%g, trees %g,%g,%g..%g,%g,%g", f, gv.bounds_min[0], gv.bounds_min[1],
               gv.bounds_min[2], gv.bounds_max[0], gv.bounds_max[1], gv.bounds_max[2], wv.bounds_min[0], wv.bounds_min[1],
               wv.bounds_min[2], wv.bounds_max[0], wv.bounds_max[1], wv.bounds_max[2]);
        double b[6] = {gv.bounds_min[0], gv.bounds_min[1], gv.bounds_min[2], gv.bounds_max[0], gv.bounds_max[1], gv.bounds_max[2]};
        if (f == 0) memcpy(b0, b, sizeof b0);
        else CHECKF(memcmp(b, b0, sizeof b0) != 0, "frame %u has frame 0's bounds (the test moves nothing)", f);
    }
    /* the graph itself (frame 0's instances) and a scene of other models */
    vx_svo_scene g0 = graph;
    CHECK(vx_svo_reader_update_bounds(rd, &g0, &err) == VX_OK && !memcmp(g0.bounds_max, b0 + 3, sizeof g0.bounds_max));
    g0.model_count = NM - 1;
    CHECKF(vx_svo_reader_update_bounds(rd, &g0, &err) == VX_ERR_INVALID_ARG && strstr(err.msg, "models"), "%s", err.msg);
    CHECK(vx_svo_reader_update_bounds(NULL, &g0, &err) == VX_ERR_INVALID_ARG);
    vx_svo_reader_close(rd);
    vx_svo_scene_free(&graph);
    vx_svo_scene_free(&whole);
    vx_svo_scene_free(&s);
}

int main(void) {
    if (!tr_dir_make(g_dir, "rewind")) return 1;
    RUN(test_passes);
    RUN(test_changed_between_passes);
    RUN(test_frame_bounds);
    tr_dir_remove(g_dir);
    return vx_test_finish();
}
