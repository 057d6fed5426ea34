/* tests/render/test_compact_load.c - the compact layout built model by model
 * from a file (vx_compact_build_reader over svo/svo.h's model reader, issue
 * 18): the same words as vx_compact_build of the scene read whole, on one
 * thread and several, both merges, both brick forms, the attributes in one
 * array and in regions; the reader's models equal the whole read's; a
 * damaged model in the middle fails the build with an error naming the
 * file and the model, nothing left (ASan in CI); a damaged NODE checksum
 * fails it at the end. Generated scenes of many models, written structural
 * and chunked, the corpus .vox scenes and, with the mesh converter, the
 * DamagedHelmet in regions. CPU only. */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "render/compact.h"
#include "svo/svo.h"
#include "tests/render/scenes.h"
#include "tests/test.h"
#include "tests/test_vox.h"
#ifdef VX_TEST_HAVE_MESH
#include "convert/mesh.h"
#endif

static char g_dir[64];

static void file_path(char* out, size_t n, const char* name) { snprintf(out, n, "%s/%s.svo", g_dir, name); }

static bool model_equal(const vx_svo_model* a, const vx_svo_model* b) {
    if (memcmp(a->size, b->size, sizeof a->size) || a->depth != b->depth || a->root != b->root ||
        a->root_attr != b->root_attr || a->attrs != b->attrs || a->voxel_count != b->voxel_count ||
        a->node_count != b->node_count || a->attr_count != b->attr_count)
        return false;
    if (a->node_count && memcmp(a->nodes, b->nodes, a->node_count * 4u)) return false;
    size_t n = a->attr_count;
    if (!a->palette != !b->palette || !a->rgba != !b->rgba) return false;
    if (a->palette && memcmp(a->palette, b->palette, n)) return false;
    if (a->rgba && memcmp(a->rgba, b->rgba, n * 4)) return false;
    return !memcmp(&a->check, &b->check, sizeof a->check);
}

/* The reader's models, one at a time, against the whole read's; its graph's
 * checks and (after finish) bounds against the whole read's. */
static void check_reader(const char* path, const vx_svo_scene* whole, const char* name) {
    vx_error err = {0};
    vx_svo_model_reader* rd = NULL;
    REQUIRE(vx_svo_reader_open(NULL, path, &rd, &err) == VX_OK);
    const vx_svo_scene* g = vx_svo_reader_scene(rd);
    CHECKF(g->model_count == whole->model_count && g->instance_count == whole->instance_count &&
               !memcmp(g->instances, whole->instances, whole->instance_count * sizeof *whole->instances) &&
               !memcmp(g->palette, whole->palette, sizeof g->palette),
           "%s: the graph differs", name);
    uint32_t bad = 0, seen = 0;
    for (;;) {
        uint32_t i = 0;
        vx_svo_model m;
        REQUIRE(vx_svo_reader_next(rd, &i, &m, &err) == VX_OK);
        if (i == g->model_count) break;
        CHECKF(i == seen, "%s: model %u handed over as %u", name, seen, i);
        seen++;
        bad += !model_equal(&m, &whole->models[i]);
        /* the check's box is the cells' box the renderer's instance boxes take */
        uint32_t lo[3], hi[3];
        vx_svo_model_cell_box(&m, lo, hi);
        if (m.voxel_count) bad += memcmp(lo, g->models[i].check.min, sizeof lo) || memcmp(hi, g->models[i].check.max, sizeof hi);
        vx_svo_model_free(NULL, &m);
    }
    CHECKF(!bad && seen == whole->model_count, "%s: %u of %u models differ", name, bad, seen);
    REQUIRE(vx_svo_reader_finish(rd, &err) == VX_OK);
    CHECKF(!memcmp(g->bounds_min, whole->bounds_min, sizeof g->bounds_min) &&
               !memcmp(g->bounds_max, whole->bounds_max, sizeof g->bounds_max),
           "%s: bounds differ", name);
    vx_svo_reader_close(rd);
}

static void check_same(const vx_compact_scene* c, const vx_compact_scene* one, const char* name, const char* how) {
    CHECKF(c->model_count == one->model_count && !memcmp(c->models, one->models, (size_t)one->model_count * sizeof *one->models),
           "%s, %s: models differ", name, how);
    CHECKF(c->slot_count == one->slot_count && c->brick_count == one->brick_count && c->geom_words == one->geom_words &&
               (!one->geom_words || !memcmp(c->geom, one->geom, (size_t)one->geom_words * 4)),
           "%s, %s: geometry differs (%u / %u words)", name, how, c->geom_words, one->geom_words);
    CHECKF(c->attr_words == one->attr_words && (!one->attr_words || !memcmp(c->attr, one->attr, (size_t)one->attr_words * 4)),
           "%s, %s: attributes differ (%u / %u words)", name, how, c->attr_words, one->attr_words);
    CHECKF(c->stats.nodes == one->stats.nodes && c->stats.blocks == one->stats.blocks &&
               c->stats.uniform == one->stats.uniform && c->stats.shared == one->stats.shared &&
               !memcmp(c->stats.level_slots, one->stats.level_slots, sizeof one->stats.level_slots),
           "%s, %s: counts differ", name, how);
    CHECK(!memcmp(c->palette, one->palette, sizeof c->palette));
    CHECKF(!memcmp(c->palette_used, one->palette_used, sizeof c->palette_used), "%s, %s: palette indices in use differ",
           name, how);
}

/* The palette indices the scene's records use (as render/gpu.h's vx__render_scene_attr_material lists them for a compact scene), and 0:
 * what the layout's build found (palette_used, which the passes' tables take for a compact scene). */
static void check_used(const vx_compact_scene* c, const vx_svo_scene* s, const char* name, const char* how) {
    uint32_t used[8] = {1};
    for (uint32_t i = 0; i < s->model_count; i++) {
        const vx_svo_model* m = &s->models[i];
        if (m->attrs && (m->attrs & VX_ATTR_PALETTE) && m->palette)
            for (uint32_t a = 0; a < m->attr_count; a++) used[m->palette[a] / 32] |= 1u << (m->palette[a] % 32);
    }
    CHECKF(!memcmp(c->palette_used, used, sizeof used), "%s, %s: palette indices in use are not the records'", name, how);
}

/* A second and third pass over the file (vx_svo_reader_rewind), as AUTO's
 * brick dictionary takes them (render_scene.c): the dictionary's geometry
 * built with the first layout's attributes moved over (desc.attrs_from) is
 * word for word vx_compact_build's dictionary of the scene read whole; the
 * attributes move back and forth (vx_compact_move_attrs); a layout without
 * attributes left, or joined ones, gives none (refused, nothing moved). */
static void check_passes(const char* path, const vx_svo_scene* whole, const char* name) {
    vx_error err = {0};
    vx_compact_scene one_i, one_d, c, c2, c3;
    REQUIRE(vx_compact_build(&(vx_compact_desc){.threads = 1}, whole, &one_i, &err) == VX_OK);
    REQUIRE(vx_compact_build(&(vx_compact_desc){.threads = 1, .bricks = VX_COMPACT_BRICKS_DICT}, whole, &one_d, &err) == VX_OK);
    vx_svo_model_reader* rd = NULL;
    REQUIRE(vx_svo_reader_open(NULL, path, &rd, &err) == VX_OK);
    REQUIRE(vx_compact_build_reader(&(vx_compact_desc){.threads = 2, .attr_regions = true}, rd, &c, &err) == VX_OK);
    CHECKF(vx_svo_reader_rewind(rd, &err) == VX_OK, "%s: %s", name, err.msg);
    vx_compact_desc dd = {.threads = 3, .bricks = VX_COMPACT_BRICKS_DICT, .attr_regions = true, .attrs_from = &c};
    vx_result r = vx_compact_build_reader(&dd, rd, &c2, &err);
    CHECKF(r == VX_OK, "%s, second pass: %s", name, err.msg);
    if (r == VX_OK) {
        CHECKF(c.attr_words == 0 && !c.attr_region && c2.attr_words == one_d.attr_words, "%s: %u attribute words left, %u moved",
               name, c.attr_words, c2.attr_words);
        CHECK(vx_compact_move_attrs(&c, &c2, &err) == VX_OK && c.attr_words == one_i.attr_words && !c2.attr_words);
        CHECK(vx_compact_move_attrs(&c, &c2, &err) == (one_i.attr_words ? VX_ERR_INVALID_ARG : VX_OK));
        CHECK(vx_compact_move_attrs(&c2, &c, &err) == VX_OK && c2.attr_words == one_d.attr_words && !c.attr_words);
        CHECK(vx_compact_join_attrs(&c2, &err) == VX_OK);
        check_same(&c2, &one_d, name, "the dictionary from a second pass, the attributes moved");
        CHECKF(c.geom_words == one_i.geom_words && (!one_i.geom_words || !memcmp(c.geom, one_i.geom, (size_t)one_i.geom_words * 4)),
               "%s: the first pass's geometry", name);
        /* a third pass, attrs_from without attributes (moved away) or joined: refused */
        CHECK(vx_svo_reader_rewind(rd, &err) == VX_OK);
        dd.attrs_from = one_i.attr_words ? &c : &c2;
        if (!one_i.attr_words) CHECK(vx_compact_join_attrs(&c2, &err) == VX_OK);
        r = vx_compact_build_reader(&dd, rd, &c3, &err);
        CHECKF(r == (one_i.attr_words || c2.attr ? VX_ERR_INVALID_ARG : VX_OK), "%s, third pass: %d %s", name, (int)r, err.msg);
        if (r == VX_OK) vx_compact_free(&c3);
        vx_compact_free(&c2);
    }
    CHECK(vx_compact_build(&(vx_compact_desc){.attrs_from = &c}, whole, &c3, &err) == VX_ERR_INVALID_ARG); /* not from a reader */
    vx_compact_free(&c);
    vx_svo_reader_close(rd);
    vx_compact_free(&one_i);
    vx_compact_free(&one_d);
}

/* vx_compact_build_reader of the file against vx_compact_build of the scene
 * read whole, on every thread count and merge. */
static void check_file(const char* path, const char* name) {
    vx_error err = {0};
    vx_svo_scene whole;
    REQUIRE(vx_svo_read_file(NULL, path, &whole, &err) == VX_OK);
    check_reader(path, &whole, name);
    static const struct {
        uint32_t threads, merge, bricks;
        bool regions;
    } v[] = {{1, 0, 0, false},
             {2, VX_COMPACT_MERGE_ORDERED, 0, false},
             {3, VX_COMPACT_MERGE_ORDERED, 0, true},
             {3, VX_COMPACT_MERGE_ALL, 0, false},
             {7, VX_COMPACT_MERGE_ALL, 0, true},
             {1, 0, VX_COMPACT_BRICKS_DICT, false},
             {3, 0, VX_COMPACT_BRICKS_DICT, true}};
    for (size_t k = 0; k < sizeof v / sizeof v[0]; k++) {
        char how[96];
        snprintf(how, sizeof how, "%u threads, merge %u, bricks %u%s", v[k].threads, v[k].merge, v[k].bricks,
                 v[k].regions ? ", regions" : "");
        vx_compact_desc d = {.threads = v[k].threads, .merge = v[k].merge, .bricks = v[k].bricks, .attr_regions = v[k].regions};
        vx_compact_scene one, c;
        vx_compact_desc d1 = {.threads = 1, .bricks = v[k].bricks};
        REQUIRE(vx_compact_build(&d1, &whole, &one, &err) == VX_OK);
        check_used(&one, &whole, name, how);
        vx_svo_model_reader* rd = NULL;
        REQUIRE(vx_svo_reader_open(&(vx_svo_read_desc){.threads = 2}, path, &rd, &err) == VX_OK);
        vx_result r = vx_compact_build_reader(&d, rd, &c, &err);
        CHECKF(r == VX_OK, "%s, %s: %s", name, how, err.msg);
        if (r == VX_OK) {
            CHECKF(!v[k].regions || whole.model_count < 2 || !one.attr_words || (c.attr_region && !c.attr),
                   "%s, %s: not in regions", name, how);
            REQUIRE(vx_compact_join_attrs(&c, &err) == VX_OK);
            check_same(&c, &one, name, how);
            vx_compact_free(&c);
        }
        vx_svo_reader_close(rd);
        vx_compact_free(&one);
    }
    check_passes(path, &whole, name);
    vx_svo_scene_free(&whole);
}

/* Many models: palette ones of several sizes and fills (an empty one, full
 * ones whose trees collapse), RGBA ones, instances of each. */
static void make_many(vx_svo_scene* s, uint32_t nm) {
    vx_svo_model* m = calloc(nm, sizeof *m);
    vx_svo_instance* in = calloc(nm, sizeof *in);
    for (uint32_t i = 0; i < nm; i++) {
        uint32_t side = 4 + (i * 7) % 29, pct = i == 5 ? 0 : i % 9 == 3 ? 100 : 5 + (i * 13) % 60;
        REQUIRE(ts_random_model(&m[i], side, side - i % 3, side, pct, 17 + i) == VX_OK);
        if (i % 4 == 1 && m[i].attr_count) { /* RGBA records instead of the palette */
            m[i].rgba = malloc((size_t)m[i].attr_count * 4);
            for (uint32_t a = 0; a < m[i].attr_count; a++) m[i].rgba[a] = 0xFF000000u | (m[i].palette[a] * 0x010305u);
            free(m[i].palette);
            m[i].palette = NULL;
            m[i].attrs = VX_ATTR_RGBA8;
        }
        in[i] = ts_inst(i, NULL, 40.0 * (i % 8), 40.0 * (i / 8), 0);
    }
    ts_scene(s, m, nm, in, nm);
    free(m);
    free(in);
}

static void test_generated(void) {
    vx_svo_scene s;
    make_many(&s, 40);
    vx_error err = {0};
    char path[128];
    file_path(path, sizeof path, "many");
    REQUIRE(vx_svo_write_file(NULL, &s, path, &err) == VX_OK);
    check_file(path, "40 models, structural");
    /* the chunked form (format version 4): each model's chunks decoded on its share of the threads */
    file_path(path, sizeof path, "many_chunked");
    REQUIRE(vx_svo_write_file(&(vx_write_desc){.svo_chunk_words = 16}, &s, path, &err) == VX_OK);
    check_file(path, "40 models, chunked");
    vx_svo_scene_free(&s);
    /* one model, and none */
    make_many(&s, 1);
    file_path(path, sizeof path, "one");
    REQUIRE(vx_svo_write_file(NULL, &s, path, &err) == VX_OK);
    check_file(path, "one model");
    vx_svo_scene_free(&s);
    vx_svo_scene_init(&s, NULL);
    file_path(path, sizeof path, "none");
    REQUIRE(vx_svo_write_file(NULL, &s, path, &err) == VX_OK);
    check_file(path, "no model");
    vx_svo_scene_free(&s);
}

/* A model in the middle that fails the reader's validation (its declared
 * voxel count one off, written unchecked), and a NODE section whose bytes
 * no longer match its checksum: the build fails with the file (and the
 * model) named, nothing built, no leak; the reader refuses more. */
static void test_damaged(void) {
    vx_svo_scene s;
    make_many(&s, 12);
    s.models[6].voxel_count++;
    vx_error err = {0};
    char path[128];
    file_path(path, sizeof path, "damaged");
    vx_result wr = vx_svo_write_file(&(vx_write_desc){.testing.unchecked = true}, &s, path, &err);
    REQUIRE(wr == VX_OK);
    s.models[6].voxel_count--;
    static const uint32_t threads[] = {1, 3, 3, 8};
    for (int k = 0; k < 4; k++) {
        vx_svo_model_reader* rd = NULL;
        REQUIRE(vx_svo_reader_open(NULL, path, &rd, &err) == VX_OK);
        vx_compact_scene c;
        memset(&c, 0x5A, sizeof c);
        vx_compact_desc d = {.threads = threads[k], .merge = k == 2 ? VX_COMPACT_MERGE_ALL : VX_COMPACT_MERGE_ORDERED};
        vx_result r = vx_compact_build_reader(&d, rd, &c, &err);
        CHECKF(r == VX_ERR_BAD_FORMAT && strstr(err.msg, path) && strstr(err.msg, "model 6") && strstr(err.msg, "voxel_count"),
               "%u threads: %d %s", threads[k], (int)r, err.msg);
        uint32_t i;
        vx_svo_model m;
        CHECK(vx_svo_reader_next(rd, &i, &m, &err) != VX_OK && m.nodes == NULL);
        CHECK(vx_svo_reader_finish(rd, &err) != VX_OK);
        vx_svo_reader_close(rd);
    }
    /* the whole read says the same */
    vx_svo_scene w;
    CHECK(vx_svo_read_file(NULL, path, &w, &err) == VX_ERR_BAD_FORMAT && strstr(err.msg, "model 6"));
    /* a byte of NODE changed: the model that holds it fails, or the checksum at the end */
    file_path(path, sizeof path, "flipped");
    REQUIRE(vx_svo_write_file(NULL, &s, path, &err) == VX_OK);
    FILE* f = fopen(path, "r+b");
    REQUIRE(f);
    vx_svo_file_info info;
    fseek(f, 0, SEEK_END);
    long size = ftell(f);
    REQUIRE(fseek(f, 0, SEEK_SET) == 0);
    uint8_t* all = malloc((size_t)size);
    REQUIRE(fread(all, 1, (size_t)size, f) == (size_t)size);
    REQUIRE(vx_svo_probe(all, (size_t)size, &info, &err) == VX_OK);
    uint64_t at = 0;
    for (uint32_t k = 0; k < info.section_count; k++)
        if (!strcmp(info.sections[k].tag, "NODE")) at = info.sections[k].offset + info.sections[k].size - 1;
    REQUIRE(at > 0);
    all[at] ^= 0x01u; /* the last model's last byte */
    REQUIRE(fseek(f, 0, SEEK_SET) == 0 && fwrite(all, 1, (size_t)size, f) == (size_t)size);
    fclose(f);
    free(all);
    for (uint32_t t = 1; t <= 3; t += 2) {
        vx_svo_model_reader* rd = NULL;
        REQUIRE(vx_svo_reader_open(NULL, path, &rd, &err) == VX_OK);
        vx_compact_scene c;
        vx_result r = vx_compact_build_reader(&(vx_compact_desc){.threads = t}, rd, &c, &err);
        CHECKF(r != VX_OK && strstr(err.msg, path) && (strstr(err.msg, "CRC") || strstr(err.msg, "model 11")), "%d %s", (int)r,
               err.msg);
        vx_svo_reader_close(rd);
    }
    /* the reader of a file that is not there */
    vx_svo_model_reader* rd = NULL;
    file_path(path, sizeof path, "absent");
    CHECK(vx_svo_reader_open(NULL, path, &rd, &err) != VX_OK && rd == NULL && strstr(err.msg, "absent"));
    vx_svo_scene_free(&s);
}

static void test_corpus(void) {
    static const char* files[] = {"eph_chr_knight.vox", "eph_monu1.vox", "eph_teapot.vox", "ogt_test_groups.vox",
                                  "ogt_test_multiple_model_scene.vox"};
    int done = 0;
    for (size_t i = 0; i < sizeof files / sizeof files[0]; i++) {
        vx_svo_scene s;
        vx_test_vox st = vx_test_vox_scene(files[i], &s);
        if (st == VX_TEST_VOX_ABSENT) continue;
        done++;
        CHECKF(st == VX_TEST_VOX_OK, "%s: not loaded", files[i]);
        if (st != VX_TEST_VOX_OK) continue;
        vx_error err = {0};
        char path[128];
        file_path(path, sizeof path, "corpus");
        REQUIRE(vx_svo_write_file(NULL, &s, path, &err) == VX_OK);
        check_file(path, files[i]);
        vx_svo_scene_free(&s);
    }
    if (!done) SKIP("no corpus .vox files");
}

/* The helmet in regions of 64 (the 65536^3 conversion's model grid, scaled
 * down): many RGBA models whose surfaces share blocks across models. */
static void test_corpus_mesh(void) {
#ifdef VX_TEST_HAVE_MESH
    const char* src = vx_test_corpus("gltf/khronos_DamagedHelmet.glb");
    if (!src) SKIP("no DamagedHelmet.glb");
    vx_svo_scene s;
    vx_error err = {0};
    vx_conv_mesh_desc d = {.res = 384, .region = 64};
    REQUIRE(vx_conv_mesh_file(&d, src, &s, NULL, &err) == VX_OK);
    CHECKF(s.model_count > 20, "DamagedHelmet at 384 in regions of 64: %u models", s.model_count);
    char path[128];
    file_path(path, sizeof path, "helmet");
    REQUIRE(vx_svo_write_file(NULL, &s, path, &err) == VX_OK);
    check_file(path, "DamagedHelmet at 384, regions of 64");
    vx_svo_scene_free(&s);
#else
    SKIP("built without the mesh converter");
#endif
}

int main(void) {
    snprintf(g_dir, sizeof g_dir, "/tmp/vx_compact_loadXXXXXX");
    if (!mkdtemp(g_dir)) return 1;
    RUN(test_generated);
    RUN(test_damaged);
    RUN(test_corpus);
    RUN(test_corpus_mesh);
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf %s", g_dir);
    if (system(cmd) != 0) fprintf(stderr, "could not remove %s\n", g_dir);
    return vx_test_finish();
}
