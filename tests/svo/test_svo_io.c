/* tests/svo/test_svo_io.c - the .svo container: round trips, probing and
 * corrupted files (each rejected with a clear error, never a crash).
 * `svo_io --write-seeds DIR` writes the fuzz seed files. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdint.h>
#include <unistd.h>

#include "svo/svo.h"
#include "svo/svo_internal.h"
#include "tests/test.h"

static uint64_t rs = 0x9E3779B97F4A7C15ull;
static uint64_t rnd(void) {
    rs ^= rs << 13;
    rs ^= rs >> 7;
    rs ^= rs << 17;
    return rs;
}

static bool build(vx_svo_model* m, uint32_t S, size_t n, uint32_t attrs) {
    uint64_t* k = (uint64_t*)malloc(n * 8);
    uint8_t* p = (uint8_t*)malloc(n);
    uint32_t* c = (uint32_t*)malloc(n * 4);
    uint32_t* nr = (uint32_t*)malloc(n * 4);
    uint16_t* mt = (uint16_t*)malloc(n * 2);
    float* d = (float*)malloc(n * 4);
    for (size_t i = 0; i < n; i++) {
        k[i] = vx_svo_morton((uint32_t)(rnd() % S), (uint32_t)(rnd() % S), (uint32_t)(rnd() % S));
        p[i] = (uint8_t)(1 + rnd() % 5);
        c[i] = (uint32_t)rnd();
        nr[i] = (uint32_t)rnd() & 0x7FFF7FFFu;
        mt[i] = (uint16_t)(rnd() % 4);
        d[i] = (float)(rnd() % 100) / 8.0f;
    }
    vx_svo_voxels in = {.size = {S, S - 1, S}, .count = n, .keys = k, .attrs = attrs};
    if (attrs & VX_ATTR_PALETTE) in.palette = p;
    if (attrs & VX_ATTR_RGBA8) in.rgba = c;
    if (attrs & VX_ATTR_NORMAL) in.normal = nr;
    if (attrs & VX_ATTR_MATERIAL) in.material = mt;
    if (attrs & VX_ATTR_DENSITY) in.density = d;
    /* keys outside the smaller y extent are dropped */
    size_t w = 0;
    for (size_t i = 0; i < n; i++)
        if (vx__compact3(k[i] >> 1) < S - 1) {
            k[w] = k[i], p[w] = p[i], c[w] = c[i], nr[w] = nr[i], mt[w] = mt[i], d[w] = d[i];
            w++;
        }
    in.count = w;
    vx_error e;
    bool ok = vx_svo_build_model(NULL, &in, m, NULL, &e) == VX_OK;
    if (!ok) fprintf(stderr, "build: %s\n", e.msg);
    free(k), free(p), free(c), free(nr), free(mt), free(d);
    return ok;
}

/* A scene with three models (palette; all other channels; geometry only). */
static void make_scene(vx_svo_scene* s, size_t n) {
    vx_svo_scene_init(s, NULL);
    s->model_count = 3;
    s->models = (vx_svo_model*)calloc(3, sizeof *s->models);
    build(&s->models[0], 16, n, VX_ATTR_PALETTE);
    build(&s->models[1], 8, n / 2, VX_ATTR_RGBA8 | VX_ATTR_NORMAL | VX_ATTR_MATERIAL | VX_ATTR_DENSITY);
    build(&s->models[2], 32, n, 0);
    s->has_palette = true;
    for (int i = 0; i < 256; i++) s->palette[i] = 0xFF000000u | (uint32_t)i * 0x010203u;
    s->instance_count = 4;
    s->instances = (vx_svo_instance*)calloc(4, sizeof *s->instances);
    for (uint32_t i = 0; i < 4; i++) {
        vx_svo_instance* in = &s->instances[i];
        double id[12] = {1, 0, 0, 10.0 * i, 0, 1, 0, -3, 0, 0, 1, 0.5};
        memcpy(in->xform, id, sizeof id);
        in->model = i % 3;
        in->layer = i == 3 ? UINT32_MAX : i % 2;
        in->flags = i == 2 ? VX_SVO_INSTANCE_HIDDEN : 0;
        snprintf(in->name, sizeof in->name, "inst%u", i);
    }
    s->layer_count = 2;
    s->layers = (vx_svo_layer*)calloc(2, sizeof *s->layers);
    strcpy(s->layers[0].name, "ground");
    s->layers[1].flags = VX_SVO_LAYER_HIDDEN;
    s->layers[1].rgba = 0xFF00FF00u;
    s->material_count = 2;
    s->materials = (vx_svo_material*)calloc(2, sizeof *s->materials);
    static const char d0[] = "_type\0_metal\0_rough\0" "0.1";
    s->materials[0].id = 4;
    s->materials[0].dict_size = sizeof d0;
    s->materials[0].dict = (char*)malloc(sizeof d0);
    memcpy(s->materials[0].dict, d0, sizeof d0);
    s->materials[1].id = 9;
    s->world_from_grid[0] = s->world_from_grid[5] = s->world_from_grid[10] = 0.1;
    vx_svo_scene_update_bounds(s);
}

static bool model_equal(const vx_svo_model* a, const vx_svo_model* b) {
    if (memcmp(a->size, b->size, sizeof a->size) || a->depth != b->depth || a->root != b->root || a->root_attr != b->root_attr ||
        a->attrs != b->attrs || a->voxel_count != b->voxel_count || a->node_count != b->node_count || a->attr_count != b->attr_count)
        return false;
    if (a->node_count && memcmp(a->nodes, b->nodes, a->node_count * 4u)) return false;
    size_t n = a->attr_count;
    if (a->palette && memcmp(a->palette, b->palette, n)) return false;
    if (a->rgba && memcmp(a->rgba, b->rgba, n * 4)) return false;
    if (a->normal && memcmp(a->normal, b->normal, n * 4)) return false;
    if (a->material && memcmp(a->material, b->material, n * 2)) return false;
    if (a->density && memcmp(a->density, b->density, n * 4)) return false;
    return true;
}

/* Recomputes every CRC so that a patched file fails on structure, not CRC. */
static void fix_crcs(uint8_t* d, size_t size) {
    uint32_t count;
    memcpy(&count, d + 12, 4);
    uint64_t toff;
    memcpy(&toff, d + 16, 8);
    if (toff > size || count > (size - toff) / 32) { /* the test broke the table on purpose */
        uint32_t hc = vx_crc32(0, d, 28);
        memcpy(d + 28, &hc, 4);
        return;
    }
    for (uint32_t i = 0; i < count; i++) {
        uint8_t* e = d + toff + 32 * (size_t)i;
        uint64_t off, sz;
        memcpy(&off, e + 8, 8);
        memcpy(&sz, e + 16, 8);
        if (off <= size && sz <= size - off) {
            uint32_t c = vx_crc32(0, d + off, (size_t)sz);
            memcpy(e + 24, &c, 4);
        }
    }
    uint32_t tc = vx_crc32(0, d + toff, 32 * (size_t)count);
    memcpy(d + 24, &tc, 4);
    uint32_t hc = vx_crc32(0, d, 28);
    memcpy(d + 28, &hc, 4);
}

/* Offset of section tag in the file (0 if absent). */
static uint64_t sec_off(const uint8_t* d, const char* tag, uint64_t* size) {
    uint32_t count;
    memcpy(&count, d + 12, 4);
    for (uint32_t i = 0; i < count; i++) {
        const uint8_t* e = d + 32 + 32 * (size_t)i;
        if (memcmp(e, tag, 4) == 0) {
            uint64_t off;
            memcpy(&off, e + 8, 8);
            if (size) memcpy(size, e + 16, 8);
            return off;
        }
    }
    return 0;
}

static void test_round_trip(void) {
    vx_svo_scene s, r, r2;
    make_scene(&s, 1500);
    vx_error e;
    uint8_t *d1 = NULL, *d2 = NULL;
    size_t n1 = 0, n2 = 0;
    REQUIRE(vx_svo_write(&s, NULL, &d1, &n1, &e) == VX_OK);
    REQUIRE(vx_svo_read(NULL, d1, n1, &r, &e) == VX_OK);
    REQUIRE(r.model_count == 3 && r.instance_count == 4 && r.layer_count == 2 && r.material_count == 2);
    for (int i = 0; i < 3; i++) CHECK(model_equal(&s.models[i], &r.models[i]));
    CHECK(memcmp(s.instances, r.instances, 4 * sizeof *s.instances) == 0);
    CHECK(memcmp(s.layers, r.layers, 2 * sizeof *s.layers) == 0);
    CHECK(r.has_palette && memcmp(s.palette, r.palette, sizeof s.palette) == 0);
    CHECK(memcmp(s.world_from_grid, r.world_from_grid, sizeof s.world_from_grid) == 0);
    CHECK(memcmp(s.bounds_min, r.bounds_min, sizeof s.bounds_min) == 0 && memcmp(s.bounds_max, r.bounds_max, sizeof s.bounds_max) == 0);
    CHECK(r.materials[0].id == 4 && strcmp(vx_svo_material_get(&r.materials[0], "_rough"), "0.1") == 0);
    CHECK(r.materials[1].id == 9 && r.materials[1].dict_size == 0);
    REQUIRE(vx_svo_write(&r, NULL, &d2, &n2, &e) == VX_OK);
    CHECK(n1 == n2 && memcmp(d1, d2, n1) == 0);
    /* probe: every section known, CRCs fine */
    vx_svo_file_info info;
    REQUIRE(vx_svo_probe(d1, n1, &info, &e) == VX_OK);
    CHECK(info.version == VX_SVO_FORMAT_VERSION && info.section_count == 9 && info.file_size == n1);
    for (uint32_t i = 0; i < info.section_count; i++) CHECK(info.sections[i].known && info.sections[i].crc_ok && info.sections[i].offset % 8 == 0);
    /* file round trip through a temporary path */
    char path[] = "/tmp/vx_svo_testXXXXXX";
    int fd = mkstemp(path);
    REQUIRE(fd >= 0);
    close(fd);
    CHECK(vx_svo_write_file(&s, path, &e) == VX_OK);
    vx_svo_scene_free(&r);
    REQUIRE(vx_svo_read_file(NULL, path, &r2, &e) == VX_OK);
    CHECK(model_equal(&s.models[1], &r2.models[1]));
    vx_svo_scene_free(&r2);
    remove(path);
    CHECK(vx_svo_read_file(NULL, path, &r2, &e) == VX_ERR_IO);
    free(d1);
    free(d2);
    vx_svo_scene_free(&s);
}

static void test_geometry_only_sections(void) {
    vx_svo_scene s;
    vx_svo_scene_init(&s, NULL);
    s.model_count = 1;
    s.models = (vx_svo_model*)calloc(1, sizeof *s.models);
    REQUIRE(build(&s.models[0], 16, 300, 0));
    s.has_palette = true; /* unused palette: not written */
    vx_error e;
    uint8_t* d;
    size_t n;
    REQUIRE(vx_svo_write(&s, NULL, &d, &n, &e) == VX_OK);
    vx_svo_file_info info;
    REQUIRE(vx_svo_probe(d, n, &info, &e) == VX_OK);
    CHECK(info.section_count == 2 && strcmp(info.sections[0].tag, "SCNE") == 0 && strcmp(info.sections[1].tag, "NODE") == 0);
    vx_svo_scene r;
    REQUIRE(vx_svo_read(NULL, d, n, &r, &e) == VX_OK);
    CHECK(!r.has_palette && r.models[0].attrs == 0 && model_equal(&s.models[0], &r.models[0]));
    vx_svo_scene_free(&r);
    free(d);
    /* an invalid scene is not written */
    s.models[0].root = 12345678;
    d = NULL;
    CHECK(vx_svo_write(&s, NULL, &d, &n, &e) == VX_ERR_BAD_FORMAT && d == NULL && strstr(e.msg, "root"));
    s.models[0].root = VX_SVO_ROOT_EMPTY;
    vx_svo_scene_free(&s);
}

static void test_truncations(void) {
    vx_svo_scene s;
    make_scene(&s, 40);
    vx_error e;
    uint8_t* d;
    size_t n;
    REQUIRE(vx_svo_write(&s, NULL, &d, &n, &e) == VX_OK);
    size_t rejected = 0;
    for (size_t len = 0; len < n; len++) {
        uint8_t* c = (uint8_t*)malloc(len ? len : 1);
        memcpy(c, d, len);
        vx_svo_scene r;
        memset(&e, 0, sizeof e);
        vx_result res = vx_svo_read(NULL, c, len, &r, &e);
        if (res != VX_OK && e.msg[0]) rejected++;
        if (res == VX_OK) vx_svo_scene_free(&r);
        free(c);
    }
    CHECKF(rejected == n, "%zu of %zu truncations rejected", rejected, n);
    free(d);
    vx_svo_scene_free(&s);
}

static void test_flips(void) {
    vx_svo_scene s;
    make_scene(&s, 60);
    vx_error e;
    uint8_t* d;
    size_t n;
    REQUIRE(vx_svo_write(&s, NULL, &d, &n, &e) == VX_OK);
    uint8_t* c = (uint8_t*)malloc(n);
    size_t crc_rejects = 0, flips = 0;
    for (size_t at = 0; at < n; at += 1 + at / 64) {
        memcpy(c, d, n);
        c[at] ^= (uint8_t)(1u << (at % 8));
        vx_svo_scene r;
        vx_result res = vx_svo_read(NULL, c, n, &r, &e);
        flips++;
        if (res != VX_OK) crc_rejects++;
        else vx_svo_scene_free(&r);
        /* without checksums: structure decides; a pass must decode safely */
        res = vx_svo_read(&(vx_svo_read_desc){.skip_checksums = true}, c, n, &r, &e);
        if (res == VX_OK) {
            for (uint32_t i = 0; i < r.model_count; i++) CHECK(vx_svo_validate_model(&r.models[i], &e) == VX_OK);
            vx_svo_scene_free(&r);
        } else {
            CHECK(e.msg[0] != 0);
        }
    }
    /* a flip in padding bytes is the only thing a CRC cannot see */
    CHECKF(crc_rejects + 8 >= flips, "%zu of %zu flips rejected", crc_rejects, flips);
    free(c);
    free(d);
    vx_svo_scene_free(&s);
}

static void test_bad_crc_and_skip(void) {
    vx_svo_scene s;
    make_scene(&s, 50);
    vx_error e;
    uint8_t* d;
    size_t n;
    REQUIRE(vx_svo_write(&s, NULL, &d, &n, &e) == VX_OK);
    uint64_t po = sec_off(d, "PALT", NULL);
    REQUIRE(po);
    d[po + 4 * 7] ^= 0x55;
    vx_svo_scene r;
    CHECK(vx_svo_read(NULL, d, n, &r, &e) == VX_ERR_BAD_FORMAT && strstr(e.msg, "PALT") && strstr(e.msg, "CRC"));
    vx_svo_file_info info;
    REQUIRE(vx_svo_probe(d, n, &info, &e) == VX_OK);
    bool seen = false;
    for (uint32_t i = 0; i < info.section_count; i++)
        if (strcmp(info.sections[i].tag, "PALT") == 0) {
            seen = true;
            CHECK(!info.sections[i].crc_ok);
        }
    CHECK(seen);
    REQUIRE(vx_svo_read(&(vx_svo_read_desc){.skip_checksums = true}, d, n, &r, &e) == VX_OK);
    CHECK(r.palette[7] == (s.palette[7] ^ 0x55u));
    vx_svo_scene_free(&r);
    /* a node word flipped with skip_checksums: rejected by structure */
    d[po + 4 * 7] ^= 0x55;
    uint64_t no = sec_off(d, "NODE", NULL);
    uint32_t root = s.models[0].root;
    uint32_t w;
    memcpy(&w, d + no + 4 * (size_t)root, 4);
    w |= 0xFFFEu << 17; /* pointer far beyond the array start */
    memcpy(d + no + 4 * (size_t)root, &w, 4);
    CHECK(vx_svo_read(&(vx_svo_read_desc){.skip_checksums = true}, d, n, &r, &e) == VX_ERR_BAD_FORMAT &&
          strstr(e.msg, "structure"));
    free(d);
    vx_svo_scene_free(&s);
}

/* Patches one node word of model 0 and fixes the CRCs: structural rejects. */
static void test_corrupt_pointers(void) {
    vx_svo_scene s;
    vx_svo_scene_init(&s, NULL);
    s.model_count = 1;
    s.models = (vx_svo_model*)calloc(1, sizeof *s.models);
    REQUIRE(build(&s.models[0], 16, 200, VX_ATTR_PALETTE));
    s.has_palette = true;
    vx_error e;
    uint8_t* d;
    size_t n;
    REQUIRE(vx_svo_write(&s, NULL, &d, &n, &e) == VX_OK);
    const vx_svo_model* m = &s.models[0];
    uint64_t no = sec_off(d, "NODE", NULL);
    uint8_t* c = (uint8_t*)malloc(n);
    uint32_t root = m->root, rd = m->nodes[root];
    struct {
        uint32_t word, value;
        const char* msg;
    } cases[] = {
        {root, vx_svo_desc_make(0, false, vx_svo_desc_valid(rd), vx_svo_desc_leaf(rd)), "backwards"},
        {root, vx_svo_desc_make(root + 1, false, vx_svo_desc_valid(rd), vx_svo_desc_leaf(rd)), "backwards"},
        /* block that contains the descriptor itself: a cycle */
        {root, vx_svo_desc_make(1, false, vx_svo_desc_valid(rd), vx_svo_desc_leaf(rd)), "before"},
        /* far slot holding a forward index */
        {root - 1, root + 5, NULL},
        {root, vx_svo_desc_make(0x7FFF, true, vx_svo_desc_valid(rd), vx_svo_desc_leaf(rd)), "backwards"},
        {root, vx_svo_desc_make(vx_svo_desc_ptr(rd), false, 0x01, 0x02), "subset"},
        {root, 0, NULL},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        memcpy(c, d, n);
        if (cases[i].word == root - 1) {
            /* turn the root pointer into a far pointer to word root-1 */
            uint32_t f = vx_svo_desc_make(1, true, vx_svo_desc_valid(rd), vx_svo_desc_leaf(rd));
            memcpy(c + no + 4 * (size_t)root, &f, 4);
        }
        memcpy(c + no + 4 * (size_t)cases[i].word, &cases[i].value, 4);
        fix_crcs(c, n);
        vx_svo_scene r;
        vx_result res = vx_svo_read(NULL, c, n, &r, &e);
        CHECKF(res == VX_ERR_BAD_FORMAT && (!cases[i].msg || strstr(e.msg, cases[i].msg)), "case %zu: %s", i,
               res ? e.msg : "accepted");
        if (res == VX_OK) vx_svo_scene_free(&r);
    }
    free(c);
    free(d);
    vx_svo_scene_free(&s);
}

static void put32(uint8_t* p, uint32_t v) { memcpy(p, &v, 4); }
static void put64(uint8_t* p, uint64_t v) { memcpy(p, &v, 8); }

static void test_bad_counts(void) {
    vx_svo_scene s;
    make_scene(&s, 30);
    vx_error e;
    uint8_t* d;
    size_t n;
    REQUIRE(vx_svo_write(&s, NULL, &d, &n, &e) == VX_OK);
    uint8_t* c = (uint8_t*)malloc(n);
    uint64_t so = sec_off(d, "SCNE", NULL);
    struct {
        uint64_t at;
        int width;
        uint64_t v;
        vx_result want;
        const char* msg;
    } cases[] = {
        {so + 0, 4, 0xFFFFFFFFu, VX_ERR_BAD_FORMAT, "SCNE"},          /* model count */
        {so + 4, 4, 0x80000000u, VX_ERR_BAD_FORMAT, "SCNE"},          /* instance count */
        {so + 160 + 28, 4, 0xFFFFFFFFu, VX_ERR_BAD_FORMAT, "NODE"},   /* node_count */
        {so + 160 + 40, 8, ~0ull, VX_ERR_BAD_FORMAT, "NODE"},         /* node_first */
        {so + 160 + 48, 4, 0xFFFFFFFFu, VX_ERR_BAD_FORMAT, "APAL"},   /* attr_count */
        {so + 160 + 56, 8, ~0ull - 3, VX_ERR_BAD_FORMAT, "APAL"},     /* attr_first */
        {so + 160 + 24, 4, 0x100u, VX_ERR_BAD_FORMAT, "attribute"},   /* attrs */
        {so + 160 + 12, 4, 25u, VX_ERR_BAD_FORMAT, "depth"},          /* depth */
        {12, 4, 0xFFFFFFFFu, VX_ERR_LIMIT, "sections"},               /* section count */
        {16, 8, ~0ull - 7, VX_ERR_TRUNCATED, "table"},                 /* table offset */
        {32 + 16, 8, ~0ull, VX_ERR_TRUNCATED, "SCNE"},                /* section size */
        {32 + 8, 8, ~0ull - 7, VX_ERR_TRUNCATED, "SCNE"},             /* section offset */
        {32 + 8, 8, 33, VX_ERR_BAD_FORMAT, "aligned"},
        {8, 4, VX_SVO_FORMAT_VERSION + 1, VX_ERR_UNSUPPORTED, "version"},
        {0, 1, 'W', VX_ERR_BAD_FORMAT, "magic"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        memcpy(c, d, n);
        if (cases[i].width == 4) put32(c + cases[i].at, (uint32_t)cases[i].v);
        else if (cases[i].width == 8) put64(c + cases[i].at, cases[i].v);
        else c[cases[i].at] = (uint8_t)cases[i].v;
        fix_crcs(c, n);
        vx_svo_scene r;
        vx_result res = vx_svo_read(NULL, c, n, &r, &e);
        CHECKF(res == cases[i].want && strstr(e.msg, cases[i].msg), "case %zu: %d %s", i, res, res ? e.msg : "accepted");
        if (res == VX_OK) vx_svo_scene_free(&r);
    }
    /* a header CRC mismatch alone */
    memcpy(c, d, n);
    c[20] ^= 1;
    vx_svo_scene r;
    CHECK(vx_svo_read(NULL, c, n, &r, &e) == VX_ERR_BAD_FORMAT && strstr(e.msg, "header"));
    free(c);
    free(d);
    vx_svo_scene_free(&s);
}

/* Rebuilds a file with one more section at the end. */
static uint8_t* add_section(const uint8_t* d, size_t n, const char* tag, uint32_t flags, size_t* out_n) {
    uint32_t count;
    memcpy(&count, d + 12, 4);
    size_t at = (n + 32 + 7) & ~(size_t)7, nn = at + 13;
    uint8_t* o = (uint8_t*)calloc(1, nn);
    memcpy(o, d, 32);
    put32(o + 12, count + 1);
    for (uint32_t i = 0; i < count; i++) {
        memcpy(o + 32 + 32 * i, d + 32 + 32 * i, 32);
        uint64_t off;
        memcpy(&off, d + 32 + 32 * i + 8, 8);
        put64(o + 32 + 32 * i + 8, off + 32);
    }
    uint8_t* e = o + 32 + 32 * (size_t)count;
    memcpy(e, tag, 4);
    put32(e + 4, flags);
    put64(e + 8, at);
    put64(e + 16, 13);
    memcpy(o + 32 + 32 * ((size_t)count + 1), d + 32 + 32 * (size_t)count, n - 32 - 32 * (size_t)count);
    memcpy(o + at, "future data!!", 13);
    fix_crcs(o, nn);
    *out_n = nn;
    return o;
}

static void test_unknown_sections(void) {
    vx_svo_scene s;
    make_scene(&s, 30);
    vx_error e;
    uint8_t* d;
    size_t n, n2;
    REQUIRE(vx_svo_write(&s, NULL, &d, &n, &e) == VX_OK);
    uint8_t* o = add_section(d, n, "XTRA", 0, &n2);
    vx_svo_scene r;
    REQUIRE(vx_svo_read(NULL, o, n2, &r, &e) == VX_OK);
    CHECK(model_equal(&r.models[0], &s.models[0]));
    vx_svo_file_info info;
    CHECK(vx_svo_probe(o, n2, &info, &e) == VX_OK && !info.sections[info.section_count - 1].known);
    vx_svo_scene_free(&r);
    free(o);
    o = add_section(d, n, "XTRA", 1, &n2);
    CHECK(vx_svo_read(NULL, o, n2, &r, &e) == VX_ERR_UNSUPPORTED && strstr(e.msg, "XTRA"));
    free(o);
    o = add_section(d, n, "NODE", 0, &n2);
    CHECK(vx_svo_read(NULL, o, n2, &r, &e) == VX_ERR_BAD_FORMAT && strstr(e.msg, "twice"));
    free(o);
    free(d);
    vx_svo_scene_free(&s);
}

/* A real far-pointer model through the file. */
static void test_far_file(void) {
    vx__svo_far_limit = 2;
    vx_svo_scene s;
    make_scene(&s, 800);
    vx__svo_far_limit = VX__SVO_PTR_MAX;
    vx_error e;
    uint8_t* d;
    size_t n;
    REQUIRE(vx_svo_write(&s, NULL, &d, &n, &e) == VX_OK);
    vx_svo_scene r;
    REQUIRE(vx_svo_read(NULL, d, n, &r, &e) == VX_OK);
    for (int i = 0; i < 3; i++) CHECK(model_equal(&s.models[i], &r.models[i]));
    vx_svo_scene_free(&r);
    free(d);
    vx_svo_scene_free(&s);
}

static int write_seeds(const char* dir) {
    char path[4096];
    vx_error e;
    for (int k = 0; k < 4; k++) {
        vx_svo_scene s;
        if (k == 3) vx__svo_far_limit = 2;
        make_scene(&s, k == 0 ? 3 : (size_t)(20 * k));
        vx__svo_far_limit = VX__SVO_PTR_MAX;
        if (k == 1) { /* geometry only */
            for (uint32_t i = 0; i < 2; i++) vx_svo_model_free(NULL, &s.models[i]);
            s.model_count = 1;
            s.models[0] = s.models[2];
            memset(&s.models[2], 0, sizeof s.models[2]);
            for (uint32_t i = 0; i < s.instance_count; i++) s.instances[i].model = 0;
        }
        snprintf(path, sizeof path, "%s/seed%d.svo", dir, k);
        if (vx_svo_write_file(&s, path, &e) != VX_OK) {
            fprintf(stderr, "%s: %s\n", path, e.msg);
            return 1;
        }
        vx_svo_scene_free(&s);
    }
    return 0;
}

int main(int argc, char** argv) {
    if (argc == 3 && strcmp(argv[1], "--write-seeds") == 0) return write_seeds(argv[2]);
    RUN(test_round_trip);
    RUN(test_geometry_only_sections);
    RUN(test_truncations);
    RUN(test_flips);
    RUN(test_bad_crc_and_skip);
    RUN(test_corrupt_pointers);
    RUN(test_bad_counts);
    RUN(test_unknown_sections);
    RUN(test_far_file);
    return vx_test_finish();
}
