/* tests/probes/test_probe_place_reader.c - the probe placement from a model
 * reader (vx_probe_place_reader, issue 18: svo_bake over the reader): the
 * same probe set as vx_probe_place of the scene read whole, bit for bit
 * (grid, positions, states, light), on scenes where many probes start inside
 * cells (dense grids over solid and hollow models, rotated and scaled
 * instances, a hidden layer, an empty model, probes on cell faces), on a
 * fresh reader and a rewound one, the structural and the chunked form, a
 * frame's view of an animation; the reader is finished by it; a model that
 * fails names the file. The placement from the compact layout
 * (vx_probe_place_compact: built from the scene in blocks and with the brick
 * dictionary, and from a reader with its graph as the scene; a frame's view)
 * gives the same set too. CPU only. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "probes/probes.h"
#include "render/compact.h"
#include "svo/svo.h"
#include "tests/render/scenes.h"
#include "tests/test.h"

static char g_dir[64];

/* A solid block with a hollow, a random one, an empty one, a thin wall;
 * instances rotated, mirrored, scaled by the world map, one on a hidden
 * layer; the world 0.5 units a cell. */
static void make_scene(vx_svo_scene* s) {
    enum { NM = 4 };
    vx_svo_model m[NM];
    uint32_t* xyz = malloc(32768 * 12);
    uint8_t* pal = malloc(32768);
    size_t n = 0;
    for (uint32_t z = 0; z < 24; z++)
        for (uint32_t y = 0; y < 20; y++)
            for (uint32_t x = 0; x < 16; x++) {
                bool hollow = x > 4 && x < 11 && y > 4 && y < 15 && z > 4 && z < 19;
                if (hollow) continue;
                xyz[3 * n] = x, xyz[3 * n + 1] = y, xyz[3 * n + 2] = z;
                pal[n++] = (uint8_t)(1 + (x + y + z) % 7);
            }
    uint32_t s0[3] = {16, 20, 24};
    REQUIRE(ts_model(&m[0], s0, xyz, pal, n) == VX_OK);
    REQUIRE(ts_random_model(&m[1], 21, 17, 13, 45, 5) == VX_OK);
    uint32_t s2[3] = {8, 8, 8};
    REQUIRE(ts_model(&m[2], s2, NULL, NULL, 0) == VX_OK);
    n = 0;
    for (uint32_t z = 0; z < 30; z++)
        for (uint32_t y = 0; y < 30; y++) xyz[3 * n] = 1, xyz[3 * n + 1] = y, xyz[3 * n + 2] = z, pal[n++] = 3;
    uint32_t s3[3] = {3, 30, 30};
    REQUIRE(ts_model(&m[3], s3, xyz, pal, n) == VX_OK);
    free(xyz), free(pal);
    static const double rz[9] = {0, -1, 0, 1, 0, 0, 0, 0, 1}, mx[9] = {-1, 0, 0, 0, 1, 0, 0, 0, 1};
    vx_svo_instance in[7] = {ts_inst(0, NULL, 0, 0, 0),      ts_inst(0, rz, 40, 3, 0), ts_inst(1, NULL, 10, 30, 2),
                             ts_inst(1, mx, 60, 30, 0),      ts_inst(2, NULL, 5, 5, 5), ts_inst(3, NULL, 30, 0, 0),
                             ts_inst(1, NULL, 20, 10, 10)};
    ts_scene(s, m, NM, in, 7);
    s->layers = calloc(1, sizeof *s->layers);
    s->layer_count = 1;
    s->layers[0].flags = VX_SVO_LAYER_HIDDEN;
    s->instances[6].layer = 0; /* drawn by nobody: its cells hold no probe back */
    double w[12] = {0.5, 0, 0, 0.25, 0, 0.5, 0, -1, 0, 0, 0.5, 0.125}; /* half a unit a cell, offset */
    memcpy(s->world_from_grid, w, sizeof w);
    vx_svo_scene_update_bounds(s);
}

static bool same_set(const vx_probe_set* a, const vx_probe_set* b, const char* what) {
    bool ok = a->probe_count == b->probe_count && !memcmp(a->grid, b->grid, sizeof a->grid) &&
              !memcmp(a->origin, b->origin, sizeof a->origin) && !memcmp(a->spacing, b->spacing, sizeof a->spacing) &&
              a->dist_step == b->dist_step && a->dist_max == b->dist_max && a->first == b->first && a->count == b->count &&
              !memcmp(a->light_dir, b->light_dir, sizeof a->light_dir) && !memcmp(a->sun, b->sun, sizeof a->sun) &&
              !memcmp(a->sky, b->sky, sizeof a->sky) && a->res == b->res && a->spp == b->spp;
    uint32_t bad = 0;
    for (uint32_t i = 0; ok && i < a->probe_count; i++)
        bad += memcmp(a->probes[i].pos, b->probes[i].pos, sizeof a->probes[i].pos) != 0 || a->probes[i].state != b->probes[i].state;
    if (!ok || bad) fprintf(stderr, "%s: %s, %u of %u probes differ\n", what, ok ? "same grid" : "another grid", bad, a->probe_count);
    return ok && !bad;
}

static void count_states(const vx_probe_set* ps, uint32_t c[3]) {
    c[0] = c[1] = c[2] = 0;
    for (uint32_t i = 0; i < ps->probe_count; i++) c[ps->probes[i].state == VX_PROBE_OK ? 0 : ps->probes[i].state == VX_PROBE_MOVED ? 1 : 2]++;
}

static void test_same_placement(void) {
    vx_svo_scene s;
    make_scene(&s);
    vx_error err = {0};
    vx_probe_bake_desc descs[3] = {{.spacing = 1.5, .res = 16}, {.grid = {20, 14, 9}, .res = 16}, {.spacing = 0.9, .res = 16, .first = 10, .count = 40}};
    for (int form = 0; form < 2; form++) {
        char path[128];
        snprintf(path, sizeof path, "%s/place%d.svo", g_dir, form);
        REQUIRE(vx_svo_write_file(&(vx_write_desc){.svo_chunk_words = form ? 16 : 0}, &s, path, &err) == VX_OK);
        vx_svo_scene whole;
        REQUIRE(vx_svo_read_file(NULL, path, &whole, &err) == VX_OK);
        for (int k = 0; k < 3; k++) {
            vx_probe_set a = {0}, b = {0}, c = {0};
            REQUIRE(vx_probe_place(&whole, &descs[k], &a, &err) == VX_OK);
            uint32_t st[3];
            count_states(&a, st);
            /* the scene must move and disable probes for the comparison to mean anything */
            CHECKF(k == 2 || (st[1] > 10 && st[2] > 0 && st[0] > 10), "desc %d: %u ok, %u moved, %u disabled", k, st[0], st[1], st[2]);
            vx_svo_model_reader* rd = NULL;
            REQUIRE(vx_svo_reader_open(NULL, path, &rd, &err) == VX_OK);
            vx_result r = vx_probe_place_reader(rd, NULL, &descs[k], &b, &err);
            CHECKF(r == VX_OK, "form %d desc %d: %s", form, k, err.msg);
            if (!r) CHECK(same_set(&a, &b, "fresh reader"));
            /* finished by it: a rewind is accepted, and the second pass places the same */
            CHECKF(vx_svo_reader_rewind(rd, &err) == VX_OK, "%s", err.msg);
            r = vx_probe_place_reader(rd, NULL, &descs[k], &c, &err);
            CHECKF(r == VX_OK, "rewound, form %d desc %d: %s", form, k, err.msg);
            if (!r) CHECK(same_set(&a, &c, "rewound reader"));
            vx_svo_reader_close(rd);
            /* from the compact layout (vx_probe_place_compact): built from the scene read whole, in blocks and
             * with the brick dictionary, and from a reader with its graph as the scene (svo_bake --load models) */
            for (int bricks = 0; bricks < 2; bricks++) {
                vx_compact_scene cs;
                vx_compact_desc cd = {.bricks = bricks ? VX_COMPACT_BRICKS_DICT : VX_COMPACT_BRICKS_INLINE};
                REQUIRE(vx_compact_build(&cd, &whole, &cs, &err) == VX_OK);
                vx_probe_set e = {0};
                r = vx_probe_place_compact(&cs, &whole, &descs[k], &e, &err);
                CHECKF(r == VX_OK, "compact, form %d desc %d: %s", form, k, err.msg);
                if (!r) CHECK(same_set(&a, &e, bricks ? "compact layout (dictionary)" : "compact layout"));
                vx_probe_set_free(&e);
                vx_compact_free(&cs);
            }
            REQUIRE(vx_svo_reader_open(NULL, path, &rd, &err) == VX_OK);
            vx_compact_scene cr;
            REQUIRE(vx_compact_build_reader(&(vx_compact_desc){.attr_regions = true}, rd, &cr, &err) == VX_OK);
            vx_svo_scene graph;
            REQUIRE(vx_svo_reader_copy_graph(rd, NULL, &graph, &err) == VX_OK);
            vx_svo_reader_close(rd);
            vx_probe_set e = {0};
            r = vx_probe_place_compact(&cr, &graph, &descs[k], &e, &err);
            CHECKF(r == VX_OK, "compact from a reader, form %d desc %d: %s", form, k, err.msg);
            if (!r) CHECK(same_set(&a, &e, "compact layout from a reader, the graph"));
            vx_probe_set_free(&e);
            vx_compact_free(&cr);
            vx_svo_scene_free(&graph);
            vx_probe_set_free(&a), vx_probe_set_free(&b), vx_probe_set_free(&c);
        }
        vx_svo_scene_free(&whole);
    }
    vx_svo_scene_free(&s);
}

/* An animation: frame 1 moves the hollow block; the placement of frame 1's view matches. */
static void test_frame_view(void) {
    vx_svo_scene s;
    make_scene(&s);
    uint32_t ni = s.instance_count;
    s.frame_count = 2;
    s.frame_instances = malloc(ni * sizeof *s.frame_instances);
    memcpy(s.frame_instances, s.instances, ni * sizeof *s.instances);
    s.frame_instances[0].xform[3] += 7, s.frame_instances[0].xform[11] += 3;
    vx_error err = {0};
    char path[128];
    snprintf(path, sizeof path, "%s/anim.svo", g_dir);
    REQUIRE(vx_svo_write_file(NULL, &s, path, &err) == VX_OK);
    vx_svo_scene_free(&s);
    vx_svo_scene whole, fv;
    REQUIRE(vx_svo_read_file(NULL, path, &whole, &err) == VX_OK);
    REQUIRE(vx_svo_scene_frame(&whole, 1, &fv));
    vx_probe_bake_desc d = {.spacing = 1.25, .res = 16};
    vx_probe_set a = {0}, b = {0};
    REQUIRE(vx_probe_place(&fv, &d, &a, &err) == VX_OK);
    vx_svo_model_reader* rd = NULL;
    REQUIRE(vx_svo_reader_open(NULL, path, &rd, &err) == VX_OK);
    vx_svo_scene graph, gv;
    REQUIRE(vx_svo_reader_copy_graph(rd, NULL, &graph, &err) == VX_OK);
    REQUIRE(vx_svo_scene_frame(&graph, 1, &gv));
    vx_result r = vx_probe_place_reader(rd, &gv, &d, &b, &err);
    CHECKF(r == VX_OK, "%s", err.msg);
    if (!r) CHECK(same_set(&a, &b, "frame 1"));
    /* the compact layout's placement of frame 1's view */
    vx_compact_scene cs;
    REQUIRE(vx_compact_build(NULL, &whole, &cs, &err) == VX_OK);
    vx_probe_set e = {0};
    r = vx_probe_place_compact(&cs, &gv, &d, &e, &err);
    CHECKF(r == VX_OK, "%s", err.msg);
    if (!r) CHECK(same_set(&a, &e, "frame 1, compact layout"));
    vx_probe_set_free(&e);
    /* a layout of other models is refused */
    vx_svo_scene one = whole;
    one.model_count = 1, one.instance_count = 0, one.frame_count = 1, one.frame_instances = NULL;
    vx_compact_scene c1;
    REQUIRE(vx_compact_build(NULL, &one, &c1, &err) == VX_OK);
    r = vx_probe_place_compact(&c1, &gv, &d, &e, &err);
    CHECKF(r == VX_ERR_INVALID_ARG && strstr(err.msg, "models") && !e.probes, "%d: %s", (int)r, err.msg);
    CHECK(vx_probe_place_compact(NULL, &gv, &d, &e, &err) == VX_ERR_INVALID_ARG);
    vx_compact_free(&c1);
    vx_compact_free(&cs);
    vx_svo_reader_close(rd);
    vx_svo_scene_free(&graph);
    vx_probe_set_free(&a), vx_probe_set_free(&b);
    vx_svo_scene_free(&whole);
}

/* A file cut in its last model's stream: the placement fails naming the file, nothing is left (ASan). */
static void test_cut(void) {
    vx_svo_scene s;
    make_scene(&s);
    vx_error err = {0};
    char path[128];
    snprintf(path, sizeof path, "%s/cut.svo", g_dir);
    REQUIRE(vx_svo_write_file(NULL, &s, path, &err) == VX_OK);
    vx_svo_scene_free(&s);
    vx_svo_model_reader* rd = NULL;
    REQUIRE(vx_svo_reader_open(NULL, path, &rd, &err) == VX_OK);
    struct stat st;
    REQUIRE(stat(path, &st) == 0 && truncate(path, st.st_size / 2) == 0); /* inside NODE: its streams are read later */
    vx_probe_set b = {0};
    vx_result r = vx_probe_place_reader(rd, NULL, &(vx_probe_bake_desc){.spacing = 2, .res = 16}, &b, &err);
    CHECKF(r != VX_OK && strstr(err.msg, path) && b.probes == NULL, "%d: %s", (int)r, err.msg);
    vx_svo_reader_close(rd);
    CHECK(vx_probe_place_reader(NULL, NULL, NULL, &b, &err) == VX_ERR_INVALID_ARG);
}

/* Instances the caster refuses are refused by the compact layout's placement with the same code and
 * message (both read the instance maps through render/instance_ray.h): a singular map (its inverse would
 * be read uninitialised otherwise), a hidden instance naming a model past the scene's. */
static void test_refused_instances(void) {
    vx_svo_scene s;
    make_scene(&s);
    vx_error err = {0}, err2 = {0};
    vx_compact_scene cs;
    REQUIRE(vx_compact_build(NULL, &s, &cs, &err) == VX_OK);
    vx_probe_bake_desc d = {.spacing = 2, .res = 16};
    vx_probe_set a = {0}, e = {0};
    double keep[12];
    memcpy(keep, s.instances[1].xform, sizeof keep);
    for (int k = 0; k < 3; k++) s.instances[1].xform[4 * 2 + k] = 0; /* z row 0: flat */
    vx_result ra = vx_probe_place(&s, &d, &a, &err);
    vx_result re = vx_probe_place_compact(&cs, &s, &d, &e, &err2);
    CHECKF(ra == VX_ERR_UNSUPPORTED && re == ra && !strcmp(err.msg, err2.msg) && !e.probes, "%d %d: %s / %s",
           (int)ra, (int)re, err.msg, err2.msg);
    memcpy(s.instances[1].xform, keep, sizeof keep);
    s.instances[6].model = s.model_count; /* on the hidden layer: never drawn, still checked */
    ra = vx_probe_place(&s, &d, &a, &err);
    re = vx_probe_place_compact(&cs, &s, &d, &e, &err2);
    CHECKF(ra == VX_ERR_BAD_FORMAT && re == ra && !strcmp(err.msg, err2.msg) && !e.probes, "%d %d: %s / %s",
           (int)ra, (int)re, err.msg, err2.msg);
    s.instances[6].model = 1;
    REQUIRE(vx_probe_place(&s, &d, &a, &err) == VX_OK);
    REQUIRE(vx_probe_place_compact(&cs, &s, &d, &e, &err) == VX_OK);
    CHECK(same_set(&a, &e, "restored instances"));
    vx_probe_set_free(&a), vx_probe_set_free(&e);
    vx_compact_free(&cs);
    vx_svo_scene_free(&s);
}

int main(void) {
    snprintf(g_dir, sizeof g_dir, "/tmp/vx_placeXXXXXX");
    if (!mkdtemp(g_dir)) return 1;
    RUN(test_same_placement);
    RUN(test_frame_view);
    RUN(test_cut);
    RUN(test_refused_instances);
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf %s", g_dir);
    if (system(cmd) != 0) fprintf(stderr, "could not remove %s\n", g_dir);
    return vx_test_finish();
}
