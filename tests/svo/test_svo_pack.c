/* tests/svo/test_svo_pack.c - the coded NODE section (FORMAT.md 3.4): models
 * built with every option come back word for word and record for record
 * through the structural form, the raw form covers the rest, and corrupt or
 * truncated coded streams are rejected. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "svo/svo.h"
#include "svo/svo_internal.h"
#include "tests/test.h"

static uint64_t rs = 0x2545F4914F6CDD1Dull;
static uint64_t rnd(void) {
    rs ^= rs << 13;
    rs ^= rs >> 7;
    rs ^= rs << 17;
    return rs;
}

/* Random boxes (so that collapse and sharing happen) plus scattered cells;
 * with tiles some boxes are given as aligned 2^L cubes. far: the builder's
 * far limit (vx_svo_testing.far_limit; 0: the default). */
static bool build(vx_svo_model* m, uint32_t S, uint32_t attrs, bool collapse, bool dag, bool tiles, uint32_t far) {
    size_t cap = 200000, n = 0;
    uint64_t* k = (uint64_t*)malloc(cap * 8);
    uint8_t* lv = (uint8_t*)calloc(cap, 1);
    uint8_t* p = (uint8_t*)malloc(cap);
    uint32_t* c = (uint32_t*)malloc(cap * 4);
    uint16_t* mt = (uint16_t*)malloc(cap * 2);
    uint32_t* nr = (uint32_t*)malloc(cap * 4);
    float* de = (float*)malloc(cap * 4);
    for (int b = 0; b < 6 && n < cap; b++) {
        uint32_t x0 = (uint32_t)(rnd() % S), y0 = (uint32_t)(rnd() % S), z0 = (uint32_t)(rnd() % S), e = 1 + (uint32_t)(rnd() % 9);
        uint8_t col = (uint8_t)(1 + rnd() % 3);
        for (uint32_t z = z0; z < z0 + e && z < S; z++)
            for (uint32_t y = y0; y < y0 + e && y < S; y++)
                for (uint32_t x = x0; x < x0 + e && x < S && n < cap; x++, n++) {
                    k[n] = vx_svo_morton(x, y, z);
                    p[n] = (uint8_t)(rnd() % 8 ? col : 1 + rnd() % 200);
                    c[n] = p[n] * 0x01030507u;
                    mt[n] = (uint16_t)(p[n] % 3);
                    nr[n] = (uint32_t)rnd() & 0x7FFF7FFFu;
                    de[n] = (float)(p[n] % 7) / 4.0f;
                }
    }
    for (int i = 0; i < 300 && n < cap; i++, n++) {
        k[n] = vx_svo_morton((uint32_t)(rnd() % S), (uint32_t)(rnd() % S), (uint32_t)(rnd() % S));
        p[n] = (uint8_t)(1 + rnd() % 255);
        c[n] = (uint32_t)rnd();
        mt[n] = (uint16_t)rnd();
        nr[n] = (uint32_t)rnd() & 0x7FFF7FFFu;
        de[n] = (float)(rnd() % 100) / 8.0f;
    }
    if (tiles) { /* a few aligned cubes far from the rest: tiles may not overlap cells */
        n = 0;
        for (uint32_t t = 0; t < 4; t++) {
            k[n] = vx_svo_morton(t * 8 % S, (t * 8 / S) * 8, 0);
            lv[n] = 3;
            p[n] = (uint8_t)(1 + t), c[n] = 0xFF0000FFu + t, mt[n] = (uint16_t)t, nr[n] = t, de[n] = (float)t;
            n++;
        }
        for (uint32_t i = 0; i < 50; i++, n++) {
            k[n] = vx_svo_morton((uint32_t)(rnd() % S), (uint32_t)(rnd() % S), 8 + (uint32_t)(rnd() % (S - 8)));
            p[n] = (uint8_t)(1 + rnd() % 9), c[n] = (uint32_t)rnd(), mt[n] = 1, nr[n] = 0, de[n] = 1;
        }
    }
    vx_svo_voxels in = {.size = {S, S, S}, .count = n, .keys = k, .level = tiles ? lv : NULL, .attrs = attrs};
    if (attrs & VX_ATTR_PALETTE) in.palette = p;
    if (attrs & VX_ATTR_RGBA8) in.rgba = c;
    if (attrs & VX_ATTR_NORMAL) in.normal = nr;
    if (attrs & VX_ATTR_MATERIAL) in.material = mt;
    if (attrs & VX_ATTR_DENSITY) in.density = de;
    vx_svo_build_desc d = {.no_collapse = !collapse, .no_dag = !dag, .testing.far_limit = far};
    vx_error e;
    bool ok = vx_svo_build_model(&d, &in, m, NULL, &e) == VX_OK;
    if (!ok) fprintf(stderr, "build: %s\n", e.msg);
    free(k), free(lv), free(p), free(c), free(mt), free(nr), free(de);
    return ok;
}

static bool same_model(const vx_svo_model* a, const vx_svo_model* b) {
    if (a->node_count != b->node_count || a->root != b->root || a->root_attr != b->root_attr || a->attr_count != b->attr_count ||
        a->attrs != b->attrs || a->voxel_count != b->voxel_count || a->depth != b->depth)
        return false;
    if (a->node_count && memcmp(a->nodes, b->nodes, (size_t)a->node_count * 4)) return false;
    size_t n = a->attr_count;
    if (a->palette && memcmp(a->palette, b->palette, n)) return false;
    if (a->rgba && memcmp(a->rgba, b->rgba, n * 4)) return false;
    if (a->normal && memcmp(a->normal, b->normal, n * 4)) return false;
    if (a->material && memcmp(a->material, b->material, n * 2)) return false;
    if (a->density && memcmp(a->density, b->density, n * 4)) return false;
    return true;
}

static void one_model_scene(vx_svo_scene* s) {
    vx_svo_scene_init(s, NULL);
    s->model_count = 1;
    s->models = (vx_svo_model*)calloc(1, sizeof *s->models);
    s->instance_count = 1;
    s->instances = (vx_svo_instance*)calloc(1, sizeof *s->instances);
    s->instances[0].xform[0] = s->instances[0].xform[5] = s->instances[0].xform[10] = 1;
    s->instances[0].layer = UINT32_MAX;
    s->has_palette = true;
    for (int i = 0; i < 256; i++) s->palette[i] = 0xFF000000u | (uint32_t)i * 0x010203u;
}

/* write -> read -> compare -> write again (byte identity); returns the size,
 * and in *raw the size of the same scene stored in the raw form. far: the
 * writers' far limit (the one the model was built with, or 0: the default). */
static size_t round_trip(vx_svo_scene* s, uint32_t far, size_t* raw) {
    vx_svo_scene_update_bounds(s);
    uint8_t *d = NULL, *d2 = NULL;
    size_t n = 0, n2 = 0;
    vx_error e;
    const vx_write_desc wd = {.testing.far_limit = far};
    if (vx_svo_write_ex(&wd, s, &d, &n, &e) != VX_OK) {
        CHECKF(false, "write: %s", e.msg);
        return 0;
    }
    vx_svo_scene r;
    if (vx_svo_read(NULL, d, n, &r, &e) != VX_OK) {
        CHECKF(false, "read: %s", e.msg);
        free(d);
        return 0;
    }
    for (uint32_t i = 0; i < s->model_count; i++) CHECKF(same_model(&s->models[i], &r.models[i]), "model %u differs", i);
    CHECK(vx_svo_write_ex(&wd, &r, &d2, &n2, &e) == VX_OK && n2 == n && memcmp(d, d2, n) == 0);
    vx_svo_scene_free(&r);
    free(d2);
    free(d);
    CHECK(vx_svo_write_ex(&(vx_write_desc){.testing = {.far_limit = far, .unchecked = true}}, s, &d, raw, &e) == VX_OK);
    free(d);
    return n;
}

static void test_structural_round_trip(void) {
    const uint32_t attrs[] = {0, VX_ATTR_PALETTE, VX_ATTR_RGBA8, VX_ATTR_MATERIAL, VX_ATTR_PALETTE | VX_ATTR_MATERIAL,
                              VX_ATTR_PALETTE | VX_ATTR_RGBA8 | VX_ATTR_MATERIAL};
    for (size_t a = 0; a < sizeof attrs / sizeof attrs[0]; a++)
        for (int opt = 0; opt < 4; opt++) {
            vx_svo_scene s;
            one_model_scene(&s);
            REQUIRE(build(&s.models[0], 40 + (uint32_t)a * 7, attrs[a], opt & 1, opt & 2, false, 0));
            size_t raw = 0, n = round_trip(&s, 0, &raw);
            /* the structural form was taken: far smaller than the raw words */
            CHECKF(n && n * 4 < raw * 3, "attrs 0x%x opt %d: %zu bytes, raw %zu", attrs[a], opt, n, raw);
            vx_svo_scene_free(&s);
        }
}

static void test_far_pointers(void) {
    /* forced low limit: far slots in a small tree, still structural */
    for (int dag = 0; dag < 2; dag++) {
        vx_svo_scene s;
        one_model_scene(&s);
        REQUIRE(build(&s.models[0], 64, VX_ATTR_PALETTE, true, dag, false, 3));
        uint32_t far = 0;
        for (uint32_t i = 0; i < s.models[0].node_count; i++) far += (s.models[0].nodes[i] & 0xFFFFu) && vx_svo_desc_far(s.models[0].nodes[i]);
        CHECK(far > 0);
        size_t raw = 0, n = round_trip(&s, 3, &raw);
        CHECKF(n && n * 4 < raw * 3, "far dag %d: %zu bytes, raw %zu", dag, n, raw);
        /* written with the default limit in force the model still comes back (raw form) */
        n = round_trip(&s, 0, &raw);
        CHECK(n > 0);
        vx_svo_scene_free(&s);
    }
    /* real far pointers: a tree with more than 32767 words after its first block */
    vx_svo_scene s;
    one_model_scene(&s);
    size_t cnt = 60000;
    uint64_t* k = (uint64_t*)malloc(cnt * 8);
    uint8_t* p = (uint8_t*)malloc(cnt);
    for (size_t i = 0; i < cnt; i++) {
        k[i] = vx_svo_morton((uint32_t)(rnd() % 512), (uint32_t)(rnd() % 512), (uint32_t)(rnd() % 512));
        p[i] = (uint8_t)(1 + rnd() % 4);
    }
    vx_svo_voxels in = {.size = {512, 512, 512}, .count = cnt, .keys = k, .attrs = VX_ATTR_PALETTE, .palette = p};
    vx_svo_build_stats st;
    vx_error e;
    REQUIRE(vx_svo_build_model(NULL, &in, &s.models[0], &st, &e) == VX_OK);
    free(k), free(p);
    CHECK(st.far_pointers > 0);
    size_t raw = 0, n = round_trip(&s, 0, &raw);
    CHECKF(n && n * 4 < raw * 3, "real far: %zu bytes, raw %zu", n, raw);
    vx_svo_scene_free(&s);
}

static void test_tiles_and_float_channels(void) {
    vx_svo_scene s;
    one_model_scene(&s);
    REQUIRE(build(&s.models[0], 32, VX_ATTR_PALETTE | VX_ATTR_RGBA8, true, true, true, 0));
    size_t raw = 0, n = round_trip(&s, 0, &raw);
    CHECK(n && n * 4 < raw * 3);
    vx_svo_scene_free(&s);
    /* normals and densities: the raw form (representatives use floats) */
    one_model_scene(&s);
    REQUIRE(build(&s.models[0], 24, VX_ATTR_ALL, true, true, false, 0));
    CHECK(round_trip(&s, 0, &raw) > 0);
    vx_svo_scene_free(&s);
}

/* Symbols handed straight to the reconstruction: each breaks one rule. */
typedef struct arr {
    const uint32_t* v;
    size_t n, pos;
} arr;
static bool arr_next(void* u, unsigned kind, unsigned ctx, uint32_t* v, vx_error* err) {
    (void)kind, (void)ctx;
    arr* a = (arr*)u;
    if (a->pos >= a->n) return vx_fail(err, VX_ERR_TRUNCATED, VX_NO_OFFSET, "symbols exhausted"), false;
    *v = a->v[a->pos++];
    return true;
}
static void test_bad_symbols(void) {
    /* depth 2, no attributes: root valid, leaf, then per non-leaf child a ref */
    static const uint32_t ok[] = {0x03, 0x00, 0, 0x01, 1};                 /* child 0 new, child 1 = back-ref to it */
    static const uint32_t backref[] = {0x03, 0x00, 0, 0x01, 2};            /* only one node precedes */
    static const uint32_t first_ref[] = {0x01, 0x00, 1};                   /* back-reference with nothing before */
    static const uint32_t empty[] = {0x00};                                /* valid mask 0 */
    static const uint32_t notsub[] = {0x01, 0x02};                         /* leaf not within valid */
    static const uint32_t trunc[] = {0x03, 0x00, 0};                       /* ends inside the tree */
    struct {
        const uint32_t* v;
        size_t n;
        uint64_t words;
        const char* msg;
    } cases[] = {
        {ok, 5, 3, NULL},
        {backref, 5, 3, "back-reference"},
        {first_ref, 3, 3, "back-reference"},
        {empty, 1, 3, "valid mask"},
        {notsub, 2, 3, "subset"},
        {trunc, 3, 3, "exhausted"},
        {ok, 5, 2, "declared words"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        arr a = {cases[i].v, cases[i].n, 0};
        vx__svo_src src = {arr_next, &a, NULL};
        vx__svo_unpack_desc d = {.depth = 2, .attrs = 0, .dag = true, .limit = VX__SVO_PTR_MAX, .max_words = cases[i].words};
        vx_svo_model m;
        memset(&m, 0, sizeof m);
        vx_error e;
        memset(&e, 0, sizeof e);
        vx_result r = vx__svo_unpack(&d, &src, &m, &e);
        if (!cases[i].msg) {
            CHECKF(r == VX_OK && m.node_count == 3 && m.root == 2, "case %zu: %s", i, e.msg);
            m.size[0] = m.size[1] = m.size[2] = 4;
            m.depth = 2;
            m.voxel_count = 2;
            CHECKF(vx_svo_validate_model(&m, &e) == VX_OK, "case %zu: %s", i, e.msg);
        } else {
            CHECKF(r != VX_OK && strstr(e.msg, cases[i].msg), "case %zu: %s", i, r ? e.msg : "accepted");
        }
        vx_svo_model_free(NULL, &m);
    }
}

/* The reconstruction's own checks that stand in for the validation's walk
 * (vx__svo_check_rebuilt): a back-reference to a node with more levels than
 * are left below it is refused, one to a node of fewer levels (as the
 * builder shares them) is not, and the extent it computes is the
 * validator's. Depth 3, no attributes. */
static void test_rebuilt_levels(void) {
    /* root: octants 0 and 1; A (level 2) holds L (level 1, one cell) */
    static const uint32_t deep[] = {0x03, 0x00, 0, 0x01, 0x00, 0, 0x01, 0, 0x01, 0x00, 1}; /* B (level 2) -> A: 2 levels at level 1 */
    static const uint32_t low[] = {0x03, 0x00, 0, 0x01, 0x00, 0, 0x01, 2};                 /* octant 1 -> L at level 2 */
    static const uint32_t same[] = {0x03, 0x00, 0, 0x01, 0x00, 0, 0x01, 1};                /* octant 1 -> A at level 2 */
    struct {
        const uint32_t* v;
        size_t n;
        uint64_t cells;
        uint32_t mx[3];
    } cases[] = {{deep, 11, 0, {0, 0, 0}}, {low, 8, 9, {6, 2, 2}}, {same, 8, 2, {5, 1, 1}}};
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        arr a = {cases[i].v, cases[i].n, 0};
        vx__svo_src src = {arr_next, &a, NULL};
        vx__svo_extent tree;
        memset(&tree, 0, sizeof tree);
        vx__svo_unpack_desc d = {.depth = 3, .dag = true, .limit = VX__SVO_PTR_MAX, .max_words = 16, .tree = &tree};
        vx_svo_model m;
        memset(&m, 0, sizeof m);
        vx_error e;
        memset(&e, 0, sizeof e);
        vx_result r = vx__svo_unpack(&d, &src, &m, &e);
        if (!cases[i].cells) {
            CHECKF(r != VX_OK && strstr(e.msg, "names a node of 2 levels"), "case %zu: %s", i, r ? e.msg : "accepted");
            vx_svo_model_free(NULL, &m);
            continue;
        }
        CHECKF(r == VX_OK, "case %zu: %s", i, e.msg);
        m.size[0] = m.size[1] = m.size[2] = 8;
        m.depth = 3;
        m.voxel_count = cases[i].cells;
        vx__svo_extent full;
        CHECKF(r == VX_OK && vx__svo_analyze(&m, &full, &e) == VX_OK, "case %zu: %s", i, e.msg);
        CHECKF(tree.cells == cases[i].cells && full.cells == tree.cells && !memcmp(full.min, tree.min, sizeof tree.min) &&
                   !memcmp(full.max, tree.max, sizeof tree.max) && !memcmp(tree.max, cases[i].mx, sizeof tree.max),
               "case %zu: the rebuilt extent %llu (%u %u %u)-(%u %u %u), the validator's %llu", i, (unsigned long long)tree.cells,
               tree.min[0], tree.min[1], tree.min[2], tree.max[0], tree.max[1], tree.max[2], (unsigned long long)full.cells);
        /* the size and the cell count are still checked against the head */
        vx__svo_extent got;
        CHECK(vx__svo_check_rebuilt(&m, &tree, &got, &e) == VX_OK && got.cells == tree.cells);
        m.voxel_count++;
        CHECK(vx__svo_check_rebuilt(&m, &tree, &got, &e) == VX_ERR_BAD_FORMAT && strstr(e.msg, "voxel_count"));
        m.voxel_count--;
        m.size[0] = tree.max[0] - 1;
        CHECK(vx__svo_check_rebuilt(&m, &tree, &got, &e) == VX_ERR_BAD_FORMAT && strstr(e.msg, "outside the size"));
        vx_svo_model_free(NULL, &m);
    }
}

/* Every model a read accepts passes the full validation (FORMAT.md 3.1) and
 * its extent (the scene's computed bounds, the model's check) is the
 * validator's, whatever the bytes: the reader no longer walks rebuilt
 * models (vx__svo_check_rebuilt). Bit flips anywhere in NODE and SCNE, the
 * checksums skipped, on one thread and on three (the decoding thread); par:
 * the threaded paths for small models too (vx_svo_testing.parallel_always). */
static int validate_read(const uint8_t* d, size_t n, unsigned threads, bool par, int* rebuilt_refusals) {
    vx_svo_scene r;
    vx_error e;
    memset(&e, 0, sizeof e);
    const vx_svo_read_desc rd = {.threads = threads, .skip_checksums = true, .testing.parallel_always = par};
    if (vx_svo_read(&rd, d, n, &r, &e) != VX_OK) {
        if (strstr(e.msg, "names a node of")) ++*rebuilt_refusals;
        return 0;
    }
    for (uint32_t i = 0; i < r.model_count; i++) {
        vx__svo_extent full;
        vx_result v = vx__svo_analyze(&r.models[i], &full, &e);
        CHECKF(v == VX_OK, "a model read from damaged bytes fails the validation: %s", e.msg);
        if (v == VX_OK)
            CHECKF(!memcmp(full.min, r.models[i].check.min, sizeof full.min) && !memcmp(full.max, r.models[i].check.max, sizeof full.max),
                   "model %u: the read's extent is not the validator's", i);
    }
    vx_svo_scene_free(&r);
    return 1;
}

static void test_rebuilt_checks(void) {
    const uint32_t attrs[] = {0, VX_ATTR_PALETTE, VX_ATTR_RGBA8 | VX_ATTR_MATERIAL};
    int reads = 0, accepted = 0, refusals = 0;
    for (size_t a = 0; a < sizeof attrs / sizeof attrs[0]; a++)
        for (int opt = 0; opt < 3; opt++) {
            const uint32_t far = opt == 2 ? 5 : 0;
            vx_svo_scene s;
            one_model_scene(&s);
            REQUIRE(build(&s.models[0], 40 + (uint32_t)a * 7, attrs[a], true, opt != 1, false, far));
            vx_svo_scene_update_bounds(&s);
            vx_error e;
            uint8_t* one = NULL;
            size_t n1 = 0;
            REQUIRE(vx_svo_write_ex(&(vx_write_desc){.threads = 1, .testing.far_limit = far}, &s, &one, &n1, &e) == VX_OK);
            vx_svo_file_info fi;
            REQUIRE(vx_svo_probe(one, n1, &fi, &e) == VX_OK);
            uint8_t* bad = (uint8_t*)malloc(n1);
            for (uint32_t k = 0; k < fi.section_count; k++) {
                if (strcmp(fi.sections[k].tag, "NODE") && strcmp(fi.sections[k].tag, "SCNE")) continue;
                uint64_t at = fi.sections[k].offset, sz = fi.sections[k].size;
                for (int i = 0; i < 150; i++) {
                    memcpy(bad, one, n1);
                    for (int f = 0; f <= i % 3; f++) bad[at + rnd() % sz] ^= (uint8_t)(1u << (rnd() % 8));
                    accepted += validate_read(bad, n1, i & 1 ? 3 : 1, i & 1, &refusals);
                    reads++;
                }
            }
            /* a stream cut short (the file too: NODE is last but for the table) */
            for (size_t cut = 1; cut < 40 && cut < n1; cut += 3) accepted += validate_read(one, n1 - cut, 1, false, &refusals), reads++;
            free(bad);
            free(one);
            vx_svo_scene_free(&s);
        }
    fprintf(stderr, "  %d damaged reads, %d accepted (each validated), %d refused by the level check\n", reads, accepted, refusals);
    CHECK(refusals > 0 && accepted > 0 && accepted < reads);
}

/* The coded stream of a real scene, truncated, extended and bit-flipped. */
static void test_corrupt_stream(void) {
    vx_svo_scene s;
    one_model_scene(&s);
    REQUIRE(build(&s.models[0], 48, VX_ATTR_PALETTE, true, true, false, 0));
    vx_svo_scene_update_bounds(&s);
    uint8_t* d;
    size_t n;
    vx_error e;
    REQUIRE(vx_svo_write(&s, NULL, &d, &n, &e) == VX_OK);
    vx_svo_file_info info;
    REQUIRE(vx_svo_probe(d, n, &info, &e) == VX_OK);
    REQUIRE(info.section_count >= 2 && strcmp(info.sections[1].tag, "NODE") == 0);
    const uint8_t* node = d + info.sections[1].offset;
    size_t nsz = (size_t)info.sections[1].size;
    uint8_t* buf = (uint8_t*)malloc(nsz + 8);
    /* the declared counts as the reader has them after SCNE */
    vx_svo_scene t;
    vx_svo_scene_init(&t, NULL);
    t.model_count = 1;
    t.models = (vx_svo_model*)calloc(1, sizeof *t.models);
    int rejected = 0, tried = 0;
    for (int mode = 0; mode < 3; mode++) {
        int reps = mode == 2 ? 400 : 6;
        for (int i = 1; i <= reps; i++) {
            size_t len = nsz;
            memcpy(buf, node, nsz);
            if (mode == 0) len = nsz - (size_t)i;      /* truncated */
            else if (mode == 1) buf[len++] = (uint8_t)i; /* trailing bytes */
            else buf[rnd() % nsz] ^= (uint8_t)(1u << (rnd() % 8));
            vx_svo_model* m = &t.models[0];
            vx_svo_model_free(NULL, m);
            *m = s.models[0];
            m->nodes = NULL, m->palette = NULL;
            memset(&e, 0, sizeof e);
            vx_result r = vx__svo_pack_read(buf, len, 1000, &t, NULL, NULL, 0, NULL, NULL, NULL, NULL, &e);
            tried++;
            if (r != VX_OK) {
                rejected++;
                CHECKF(strstr(e.msg, "NODE") != NULL, "mode %d: %s", mode, e.msg);
            } else if (mode < 2) {
                CHECKF(false, "mode %d case %d accepted", mode, i);
            } else if (vx_svo_validate_model(m, &e) == VX_OK) {
                /* a flip that still decodes must at least give a valid tree */
            }
        }
    }
    CHECK(rejected > tried / 2);
    vx_svo_scene_free(&t);
    free(buf);
    free(d);
    vx_svo_scene_free(&s);
}

/* Several models handled by threads must give the same bytes as one thread,
 * and read back to the same models (threads, serial or parallel, never change
 * the file). The threshold is lowered so small models take the threaded path. */
static void test_parallel_models(void) {
    vx_svo_scene s;
    one_model_scene(&s);
    free(s.models);
    s.model_count = 5;
    s.models = (vx_svo_model*)calloc(5, sizeof *s.models);
    static const uint32_t attrs[5] = {VX_ATTR_PALETTE, VX_ATTR_RGBA8, 0, VX_ATTR_PALETTE | VX_ATTR_MATERIAL, VX_ATTR_NORMAL};
    for (uint32_t i = 0; i < 5; i++) REQUIRE(build(&s.models[i], 32u << (i % 3), attrs[i], true, true, false, 0));
    vx_svo_scene_update_bounds(&s);
    uint8_t *serial = NULL, *parallel = NULL;
    size_t ns = 0, np = 0;
    vx_error e;
    REQUIRE(vx_svo_write(&s, NULL, &serial, &ns, &e) == VX_OK);
    const vx_svo_testing par = {.parallel_always = true};
    CHECK(vx__svo_threads(&s, 2, NULL) == 1 && vx__svo_threads(&s, 2, &par) == 2); /* 5 small models: one thread unless forced */
    CHECK(vx_svo_write_ex(&(vx_write_desc){.testing = par}, &s, &parallel, &np, &e) == VX_OK);
    CHECK(np == ns && parallel && memcmp(serial, parallel, ns) == 0);
    vx_svo_scene r;
    vx_result rr = vx_svo_read(&(vx_svo_read_desc){.testing = par}, serial, ns, &r, &e);
    CHECKF(rr == VX_OK, "parallel read: %s", e.msg);
    if (rr == VX_OK) {
        for (uint32_t i = 0; i < 5; i++) CHECKF(same_model(&s.models[i], &r.models[i]), "model %u differs after a parallel read", i);
        vx_svo_scene_free(&r);
    }
    /* a stream length off by one (the first byte of NODE) breaks the stream
     * table: rejected whatever thread decodes what */
    vx_svo_file_info fi;
    REQUIRE(vx_svo_probe(serial, ns, &fi, &e) == VX_OK);
    uint64_t node_at = 0;
    for (uint32_t i = 0; i < fi.section_count; i++)
        if (!strcmp(fi.sections[i].tag, "NODE")) node_at = fi.sections[i].offset;
    REQUIRE(node_at > 0);
    serial[node_at] ^= 1u; /* the lowest bit of the length, continuation bit kept */
    rr = vx_svo_read(&(vx_svo_read_desc){.skip_checksums = true, .testing = par}, serial, ns, &r, &e);
    CHECK(rr != VX_OK);
    if (rr == VX_OK) vx_svo_scene_free(&r);
    else fprintf(stderr, "  corrupted stream, parallel read: %s\n", e.msg);
    free(serial);
    free(parallel);
    vx_svo_scene_free(&s);
}

/* One large model has its layout follow the decoding on other threads, and
 * the writer codes its symbols while its check rebuilds the model (forced on
 * here by lowering the threshold): the bytes and the models read must be
 * those of one thread, for every channel set, with and without the DAG and
 * far slots, and a damaged stream must give the same result (code and
 * message) on one thread and on several. */
static void test_layout_threads(void) {
    const uint32_t attrs[] = {0, VX_ATTR_PALETTE, VX_ATTR_RGBA8, VX_ATTR_PALETTE | VX_ATTR_RGBA8 | VX_ATTR_MATERIAL};
    int flips_rejected = 0, flips = 0;
    /* the threaded paths forced on for these small models, in every write and read but the first write */
    const vx_svo_testing par = {.parallel_always = true};
    for (size_t a = 0; a < sizeof attrs / sizeof attrs[0]; a++)
        for (int opt = 0; opt < 6; opt++) {
            const uint32_t far = opt >= 4 ? 5 : 0;
            vx_svo_scene s;
            one_model_scene(&s);
            REQUIRE(build(&s.models[0], 60 + (uint32_t)a * 5, attrs[a], true, (opt & 1) != 0, (opt & 2) != 0 && attrs[a] != 0, far));
            vx_svo_scene_update_bounds(&s);
            vx_error e;
            uint8_t* one = NULL;
            size_t n1 = 0;
            REQUIRE(vx_svo_write_ex(&(vx_write_desc){.threads = 1, .testing.far_limit = far}, &s, &one, &n1, &e) == VX_OK);
            for (unsigned t = 2; t <= 4; t++) {
                uint8_t* d = NULL;
                size_t n = 0;
                REQUIRE(vx_svo_write_ex(&(vx_write_desc){.threads = t, .testing = {.far_limit = far, .parallel_always = true}}, &s, &d, &n, &e) ==
                        VX_OK);
                CHECKF(n == n1 && !memcmp(d, one, n1), "attrs 0x%x opt %d, %u threads: other bytes", attrs[a], opt, t);
                vx_svo_scene r;
                vx_result rr = vx_svo_read(&(vx_svo_read_desc){.threads = t, .testing = par}, one, n1, &r, &e);
                CHECKF(rr == VX_OK, "attrs 0x%x opt %d, %u threads: %s", attrs[a], opt, t, e.msg);
                if (rr == VX_OK) {
                    CHECKF(same_model(&s.models[0], &r.models[0]), "attrs 0x%x opt %d, %u threads: model differs", attrs[a], opt, t);
                    vx_svo_scene_free(&r);
                }
                free(d);
            }
            /* bit flips in NODE (checksums skipped): one thread and three agree */
            vx_svo_file_info fi;
            REQUIRE(vx_svo_probe(one, n1, &fi, &e) == VX_OK);
            uint64_t at = 0, sz = 0;
            for (uint32_t i = 0; i < fi.section_count; i++)
                if (!strcmp(fi.sections[i].tag, "NODE")) at = fi.sections[i].offset, sz = fi.sections[i].size;
            REQUIRE(sz > 8);
            uint8_t* bad = (uint8_t*)malloc(n1);
            for (int i = 0; i < 12; i++) {
                memcpy(bad, one, n1);
                bad[at + 2 + rnd() % (sz - 2)] ^= (uint8_t)(1u << (rnd() % 8));
                vx_svo_scene r1, r3;
                vx_error e1, e3;
                memset(&e1, 0, sizeof e1);
                memset(&e3, 0, sizeof e3);
                vx_result a1 = vx_svo_read(&(vx_svo_read_desc){.threads = 1, .skip_checksums = true, .testing = par}, bad, n1, &r1, &e1);
                vx_result a3 = vx_svo_read(&(vx_svo_read_desc){.threads = 3, .skip_checksums = true, .testing = par}, bad, n1, &r3, &e3);
                flips++;
                CHECKF(a1 == a3, "flip %d: %d vs %d", i, (int)a1, (int)a3);
                if (a1 != VX_OK && a3 != VX_OK) {
                    flips_rejected++;
                    CHECKF(!strcmp(e1.msg, e3.msg), "flip %d: '%s' vs '%s'", i, e1.msg, e3.msg);
                }
                if (a1 == VX_OK && a3 == VX_OK) CHECK(same_model(&r1.models[0], &r3.models[0]));
                if (a1 == VX_OK) vx_svo_scene_free(&r1);
                if (a3 == VX_OK) vx_svo_scene_free(&r3);
            }
            free(bad);
            /* the stream cut short or with bytes after it (the stream length
             * adjusted: NODE's first varint): the same result on 1 and 3 threads */
            vx_svo_scene t;
            vx_svo_scene_init(&t, NULL);
            t.model_count = 1;
            t.models = (vx_svo_model*)calloc(1, sizeof *t.models);
            uint8_t* buf = (uint8_t*)malloc(sz + 16);
            for (int cut = -6; cut <= 2; cut++) {
                if (cut == 0) continue;
                size_t hdr = 0;
                uint64_t len = 0;
                for (unsigned sh = 0;; sh += 7) {
                    uint8_t c = one[at + hdr++];
                    len |= (uint64_t)(c & 0x7Fu) << sh;
                    if (!(c & 0x80u)) break;
                }
                uint64_t nl = len + (uint64_t)(int64_t)cut;
                size_t w = 0;
                do {
                    buf[w] = (uint8_t)(nl & 0x7Fu);
                    nl >>= 7;
                    if (nl) buf[w] |= 0x80u;
                    w++;
                } while (nl);
                size_t body = (size_t)(cut < 0 ? len - (uint64_t)(-cut) : len);
                memcpy(buf + w, one + at + hdr, body);
                for (int j = 0; j < cut; j++) buf[w + body + (size_t)j] = (uint8_t)(0x11 * (j + 1));
                size_t total = w + body + (size_t)(cut > 0 ? cut : 0);
                vx_result res[2];
                char msg[2][sizeof e.msg];
                for (int th = 0; th < 2; th++) {
                    vx_svo_model* mm = &t.models[0];
                    vx_svo_model_free(NULL, mm);
                    *mm = s.models[0];
                    mm->nodes = NULL, mm->palette = NULL, mm->rgba = NULL, mm->material = NULL;
                    memset(&e, 0, sizeof e);
                    res[th] = vx__svo_pack_read(buf, total, 1000, &t, NULL, NULL, th ? 3 : 1, &par, NULL, NULL, NULL, &e);
                    snprintf(msg[th], sizeof msg[th], "%s", e.msg);
                }
                CHECKF(res[0] != VX_OK && res[0] == res[1] && !strcmp(msg[0], msg[1]), "attrs 0x%x opt %d cut %d: %d '%s' vs %d '%s'",
                       attrs[a], opt, cut, (int)res[0], msg[0], (int)res[1], msg[1]);
            }
            free(buf);
            vx_svo_scene_free(&t);
            free(one);
            vx_svo_scene_free(&s);
        }
    CHECK(flips_rejected > 0 && flips_rejected <= flips);
}

int main(void) {
    RUN(test_structural_round_trip);
    RUN(test_far_pointers);
    RUN(test_tiles_and_float_channels);
    RUN(test_bad_symbols);
    RUN(test_rebuilt_levels);
    RUN(test_rebuilt_checks);
    RUN(test_corrupt_stream);
    RUN(test_parallel_models);
    RUN(test_layout_threads);
    return vx_test_finish();
}
