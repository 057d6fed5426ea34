/* tests/svo/test_svo_build.c - octree building, minimization, decoding and
 * validation against brute-force references (dense cell arrays). */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "svo/svo.h"
#include "svo/svo_internal.h"
#include "tests/test.h"

static uint64_t rs = 0x243F6A8885A308D3ull;
static uint64_t rnd(void) {
    rs ^= rs << 13;
    rs ^= rs >> 7;
    rs ^= rs << 17;
    return rs;
}

/* ---- decode collector ------------------------------------------------------------ */

typedef struct cell {
    uint32_t x, y, z, attr;
} cell;
typedef struct coll {
    cell* c;
    size_t n, cap, limit;
    bool order_ok;
    uint64_t last;
} coll;

static bool collect(void* user, uint32_t x, uint32_t y, uint32_t z, uint32_t attr) {
    coll* c = (coll*)user;
    uint64_t k = vx_svo_morton(x, y, z);
    if (c->n && k <= c->last) c->order_ok = false;
    c->last = k;
    if (c->n == c->cap) {
        c->cap = c->cap ? c->cap * 2 : 1024;
        c->c = (cell*)realloc(c->c, c->cap * sizeof(cell));
    }
    c->c[c->n++] = (cell){x, y, z, attr};
    return c->limit == 0 || c->n < c->limit;
}

static coll decode_all(const vx_svo_model* m) {
    coll c = {0};
    c.order_ok = true;
    vx_error e;
    CHECK(vx_svo_decode_model(m, collect, &c, &e) == VX_OK);
    return c;
}

/* ---- blocks against cells ------------------------------------------------------------- */

typedef struct blocks {
    coll cells; /* every set bit of every block, as cells */
    uint64_t blocks, last;
    bool order_ok, empty_block;
} blocks;

static bool block_cb(void* user, uint32_t bx, uint32_t by, uint32_t bz, const uint32_t bits[16]) {
    blocks* b = (blocks*)user;
    uint64_t k = vx_svo_morton(bx, by, bz);
    if (b->blocks && k <= b->last) b->order_ok = false;
    b->last = k, b->blocks++;
    bool any = false;
    for (uint32_t i = 0; i < 512; i++)
        if (bits[i >> 5] >> (i & 31) & 1u) {
            any = true;
            collect(&b->cells, 8 * bx + (i & 7), 8 * by + (i >> 3 & 7), 8 * bz + (i >> 6), 0);
        }
    if (!any) b->empty_block = true;
    return true;
}

static int cell_cmp(const void* a, const void* b) {
    const cell *p = a, *q = b;
    uint64_t x = vx_svo_morton(p->x, p->y, p->z), y = vx_svo_morton(q->x, q->y, q->z);
    return x < y ? -1 : x > y;
}

/* vx_svo_decode_blocks gives the cells vx_svo_decode_model gives, in
 * occupied blocks only, the blocks in Morton order. */
static void check_blocks(const vx_svo_model* m, const coll* want) {
    blocks b = {.order_ok = true};
    b.cells.order_ok = true;
    vx_error e;
    CHECK(vx_svo_decode_blocks(m, block_cb, &b, &e) == VX_OK);
    CHECK(b.order_ok);
    CHECK(!b.empty_block);
    CHECKF(b.cells.n == want->n, "blocks hold %zu cells, decode gives %zu", b.cells.n, want->n);
    if (b.cells.n == want->n && want->n) {
        cell* w = malloc(want->n * sizeof *w);
        memcpy(w, want->c, want->n * sizeof *w);
        qsort(w, want->n, sizeof *w, cell_cmp);
        qsort(b.cells.c, b.cells.n, sizeof *b.cells.c, cell_cmp);
        size_t bad = 0;
        for (size_t i = 0; i < want->n; i++)
            bad += w[i].x != b.cells.c[i].x || w[i].y != b.cells.c[i].y || w[i].z != b.cells.c[i].z;
        CHECKF(bad == 0, "%zu cells of the blocks differ from the decoded cells", bad);
        free(w);
    }
    free(b.cells.c);
}

/* Dense reference: value+1 per cell, 0 = empty. */
typedef struct dense {
    uint32_t sx, sy, sz;
    uint32_t* v;
} dense;
static dense dense_make(uint32_t sx, uint32_t sy, uint32_t sz) {
    dense d = {sx, sy, sz, (uint32_t*)calloc((size_t)sx * sy * sz, 4)};
    return d;
}
static uint32_t* dat(dense* d, uint32_t x, uint32_t y, uint32_t z) { return &d->v[((size_t)z * d->sy + y) * d->sx + x]; }

/* Decoded cells must equal the reference exactly; value(attr) maps a record
 * to the reference's value. */
static void check_equal(const vx_svo_model* m, dense* ref, uint32_t (*value)(const vx_svo_model*, uint32_t)) {
    coll c = decode_all(m);
    CHECK(c.order_ok);
    size_t want = 0;
    for (size_t i = 0; i < (size_t)ref->sx * ref->sy * ref->sz; i++) want += ref->v[i] != 0;
    CHECKF(c.n == want, "decoded %zu cells, reference has %zu", c.n, want);
    CHECK(m->voxel_count == want);
    size_t bad = 0;
    for (size_t i = 0; i < c.n; i++) {
        cell* q = &c.c[i];
        if (q->x >= ref->sx || q->y >= ref->sy || q->z >= ref->sz) { bad++; continue; }
        uint32_t r = *dat(ref, q->x, q->y, q->z);
        if (r == 0 || r - 1 != value(m, q->attr)) bad++;
    }
    CHECKF(bad == 0, "%zu decoded cells differ from the reference", bad);
    check_blocks(m, &c);
    free(c.c);
}

static uint32_t val_pal(const vx_svo_model* m, uint32_t a) { return a < m->attr_count ? m->palette[a] : 0xDEAD; }
static uint32_t val_rgba(const vx_svo_model* m, uint32_t a) { return a < m->attr_count ? m->rgba[a] : 0xDEAD; }

/* ---- tests ----------------------------------------------------------------------------- */

/* The Morton helpers against the definition, bit by bit. */
static void test_morton_helpers(void) {
    for (int i = 0; i < 20000; i++) {
        uint32_t x = (uint32_t)rnd() & 0x1FFFFF, y = (uint32_t)rnd() & 0x1FFFFF, z = (uint32_t)rnd() & 0x1FFFFF;
        uint64_t want = 0;
        for (unsigned bit = 0; bit < 21; bit++)
            want |= ((uint64_t)(x >> bit & 1u) << (3 * bit)) | ((uint64_t)(y >> bit & 1u) << (3 * bit + 1)) |
                    ((uint64_t)(z >> bit & 1u) << (3 * bit + 2));
        uint64_t k = vx_svo_morton(x, y, z);
        CHECK(k == want);
        uint32_t a, b, c;
        vx_svo_demorton(k, &a, &b, &c);
        CHECK(a == x && b == y && c == z);
        CHECK(vx__compact3(k) == x && vx__compact3(k >> 1) == y && vx__compact3(k >> 2) == z);
    }
}

static void test_empty(void) {
    vx_svo_voxels in = {.size = {16, 16, 16}};
    vx_svo_model m;
    vx_svo_build_stats st;
    vx_error e;
    REQUIRE(vx_svo_build_model(NULL, &in, &m, &st, &e) == VX_OK);
    CHECK(m.root == VX_SVO_ROOT_EMPTY && m.node_count == 0 && m.voxel_count == 0 && m.depth == 4);
    CHECK(vx_svo_validate_model(&m, &e) == VX_OK);
    coll c = decode_all(&m);
    CHECK(c.n == 0);
    free(c.c);
    vx_svo_model_free(NULL, &m);
}

static void test_one_voxel(void) {
    uint64_t k = vx_svo_morton(7, 2, 1);
    uint8_t pal = 5;
    vx_svo_voxels in = {.size = {10, 5, 3}, .count = 1, .keys = &k, .attrs = VX_ATTR_PALETTE, .palette = &pal};
    vx_svo_model m;
    vx_svo_build_stats st;
    vx_error e;
    REQUIRE(vx_svo_build_model(NULL, &in, &m, &st, &e) == VX_OK);
    CHECK(m.depth == 4 && m.voxel_count == 1 && st.voxels == 1);
    CHECK(st.desc_plain == 4 && st.desc_collapsed == 4 && st.desc_dag == 4);
    CHECK(vx_svo_validate_model(&m, &e) == VX_OK);
    coll c = decode_all(&m);
    REQUIRE(c.n == 1);
    CHECK(c.c[0].x == 7 && c.c[0].y == 2 && c.c[0].z == 1 && m.palette[c.c[0].attr] == 5);
    CHECK(m.palette[m.root_attr] == 5);
    vx_svo_scene s;
    vx_svo_scene_init(&s, NULL);
    s.palette[5] = 0xFF112233u;
    CHECK(vx_svo_attr_color(&s, &m, c.c[0].attr) == 0xFF112233u);
    free(c.c);
    vx_svo_model_free(NULL, &m);

    /* depth 0: a 1x1x1 model is one root leaf */
    uint64_t k0 = 0;
    vx_svo_voxels in0 = {.size = {1, 1, 1}, .count = 1, .keys = &k0};
    REQUIRE(vx_svo_build_model(NULL, &in0, &m, &st, &e) == VX_OK);
    CHECK(m.depth == 0 && m.root == VX_SVO_ROOT_LEAF && m.voxel_count == 1);
    CHECK(vx_svo_validate_model(&m, &e) == VX_OK);
    c = decode_all(&m);
    CHECK(c.n == 1);
    free(c.c);
    vx_svo_model_free(NULL, &m);
}

/* Streaming checks for the big cases (no cell list). */
typedef struct stream_chk {
    uint64_t n, bad;
    const vx_svo_model* m;
    int mode; /* 0: the i-th cell is demorton(i); 1: checkerboard */
} stream_chk;
static bool stream_cb(void* user, uint32_t x, uint32_t y, uint32_t z, uint32_t a) {
    stream_chk* c = (stream_chk*)user;
    if (c->mode == 0) {
        if (vx_svo_morton(x, y, z) != c->n) c->bad++;
    } else if (((x + y + z) & 1) || c->m->palette[a] != 1 + (x & 2)) {
        c->bad++;
    }
    c->n++;
    return true;
}

static void test_full_cube(void) {
    const uint32_t S = 256;
    size_t n = (size_t)S * S * S;
    uint64_t* keys = (uint64_t*)malloc(n * 8);
    uint8_t* pal = (uint8_t*)malloc(n);
    REQUIRE(keys && pal);
    size_t i = 0;
    for (uint32_t z = 0; z < S; z++)
        for (uint32_t y = 0; y < S; y++)
            for (uint32_t x = 0; x < S; x++) keys[i] = vx_svo_morton(x, y, z), pal[i++] = 9;
    vx_svo_voxels in = {.size = {S, S, S}, .count = n, .keys = keys};
    vx_svo_model m;
    vx_svo_build_stats st;
    vx_error e;
    REQUIRE(vx_svo_build_model(NULL, &in, &m, &st, &e) == VX_OK);
    CHECK(m.root == VX_SVO_ROOT_LEAF && m.node_count == 0 && st.desc_dag == 0 && st.desc_collapsed == 0);
    CHECK(st.desc_plain == (n - 1) / 7); /* 1 + 8 + ... + 8^7 internal nodes */
    CHECK(m.voxel_count == n);
    CHECK(vx_svo_validate_model(&m, &e) == VX_OK);
    /* decode: every cell once, in Morton order */
    stream_chk c = {0, 0, &m, 0};
    CHECK(vx_svo_decode_model(&m, stream_cb, &c, &e) == VX_OK);
    CHECK(c.n == n && c.bad == 0);
    vx_svo_model_free(NULL, &m);
    /* with a uniform palette (64^3 to keep the test short): still one leaf,
     * root_attr carries the colour */
    i = 0;
    for (uint32_t z = 0; z < 64; z++)
        for (uint32_t y = 0; y < 64; y++)
            for (uint32_t x = 0; x < 64; x++) keys[i++] = vx_svo_morton(x, y, z);
    in.size[0] = in.size[1] = in.size[2] = 64;
    in.count = i;
    in.attrs = VX_ATTR_PALETTE;
    in.palette = pal;
    REQUIRE(vx_svo_build_model(NULL, &in, &m, &st, &e) == VX_OK);
    CHECK(m.root == VX_SVO_ROOT_LEAF && m.attr_count == 1 && m.palette[m.root_attr] == 9);
    CHECK(vx_svo_validate_model(&m, &e) == VX_OK);
    vx_svo_model_free(NULL, &m);
    free(keys);
    free(pal);
}

static void test_checkerboard(void) {
    const uint32_t S = 256;
    size_t n = (size_t)S * S * S / 2, i = 0;
    uint64_t* keys = (uint64_t*)malloc(n * 8);
    uint8_t* pal = (uint8_t*)malloc(n);
    REQUIRE(keys && pal);
    for (uint32_t z = 0; z < S; z++)
        for (uint32_t y = 0; y < S; y++)
            for (uint32_t x = (y + z) & 1; x < S; x += 2) keys[i] = vx_svo_morton(x, y, z), pal[i++] = (uint8_t)(1 + (x & 2));
    REQUIRE(i == n);
    vx_svo_voxels in = {.size = {S, S, S}, .count = n, .keys = keys, .attrs = VX_ATTR_PALETTE, .palette = pal};
    vx_svo_model m;
    vx_svo_build_stats st;
    vx_error e;
    REQUIRE(vx_svo_build_model(NULL, &in, &m, &st, &e) == VX_OK);
    CHECK(m.voxel_count == n);
    CHECK(st.desc_plain == ((size_t)S * S * S - 1) / 7);
    CHECK(st.desc_collapsed == st.desc_plain); /* nothing is full */
    CHECKF(st.desc_dag < 64, "checkerboard DAG has %llu descriptors", (unsigned long long)st.desc_dag);
    CHECK(m.node_count < 256 && m.attr_count < 64);
    CHECK(vx_svo_validate_model(&m, &e) == VX_OK);
    /* every decoded cell is a black one with its colour, and the count is exact */
    stream_chk c = {0, 0, &m, 1};
    CHECK(vx_svo_decode_model(&m, stream_cb, &c, &e) == VX_OK);
    CHECK(c.n == n && c.bad == 0);
    vx_svo_model_free(NULL, &m);
    free(keys);
    free(pal);
}

/* Random sparse cells plus a few uniform boxes (so collapse happens), with
 * duplicates, in a non-cubic model; every minimization setting. */
/* vx_svo_model_cell_box against the decoded cells' box */
static void check_cell_box(const vx_svo_model* m) {
    coll c = decode_all(m);
    uint32_t lo[3] = {UINT32_MAX, UINT32_MAX, UINT32_MAX}, hi[3] = {0, 0, 0}, blo[3], bhi[3];
    for (size_t i = 0; i < c.n; i++) {
        uint32_t v[3] = {c.c[i].x, c.c[i].y, c.c[i].z};
        for (int k = 0; k < 3; k++) {
            if (v[k] < lo[k]) lo[k] = v[k];
            if (v[k] + 1 > hi[k]) hi[k] = v[k] + 1;
        }
    }
    if (!c.n) lo[0] = lo[1] = lo[2] = 0;
    vx_svo_model_cell_box(m, blo, bhi);
    for (int k = 0; k < 3; k++)
        CHECKF(blo[k] == lo[k] && bhi[k] == hi[k], "axis %d: box [%u, %u), cells [%u, %u)", k, blo[k], bhi[k], lo[k], hi[k]);
    free(c.c);
}

static void random_case(uint32_t sx, uint32_t sy, uint32_t sz, size_t n, bool rgba) {
    dense ref = dense_make(sx, sy, sz);
    size_t cap = n + 20000;
    uint64_t* keys = (uint64_t*)malloc(cap * 8);
    uint8_t* pal = (uint8_t*)malloc(cap);
    uint32_t* col = (uint32_t*)malloc(cap * 4);
    size_t cnt = 0;
    for (size_t i = 0; i < n; i++) {
        uint32_t x, y, z;
        if (cnt && rnd() % 10 == 0) { /* duplicate an earlier key with a new value */
            uint64_t k = keys[rnd() % cnt];
            x = vx__compact3(k), y = vx__compact3(k >> 1), z = vx__compact3(k >> 2);
        } else {
            x = (uint32_t)(rnd() % sx), y = (uint32_t)(rnd() % sy), z = (uint32_t)(rnd() % sz);
        }
        keys[cnt] = vx_svo_morton(x, y, z);
        pal[cnt] = (uint8_t)(1 + rnd() % 4);
        col[cnt] = (uint32_t)rnd() & 0xFF030303u;
        *dat(&ref, x, y, z) = 1 + (rgba ? col[cnt] : pal[cnt]);
        cnt++;
    }
    /* uniform boxes aligned to 4 */
    for (int b = 0; b < 3; b++) {
        uint32_t bx = (uint32_t)(rnd() % (sx / 4 + 1)) * 4, by = (uint32_t)(rnd() % (sy / 4 + 1)) * 4, bz = (uint32_t)(rnd() % (sz / 4 + 1)) * 4;
        for (uint32_t z = bz; z < bz + 4 && z < sz; z++)
            for (uint32_t y = by; y < by + 4 && y < sy; y++)
                for (uint32_t x = bx; x < bx + 4 && x < sx; x++) {
                    keys[cnt] = vx_svo_morton(x, y, z);
                    pal[cnt] = 7;
                    col[cnt] = 0xFF0000FFu;
                    *dat(&ref, x, y, z) = 1 + (rgba ? col[cnt] : pal[cnt]);
                    cnt++;
                }
    }
    vx_svo_voxels in = {.size = {sx, sy, sz}, .count = cnt, .keys = keys};
    if (rgba) in.attrs = VX_ATTR_RGBA8, in.rgba = col;
    else in.attrs = VX_ATTR_PALETTE, in.palette = pal;
    uint64_t words[4] = {0};
    for (int mode = 0; mode < 4; mode++) {
        vx_svo_build_desc d = {.no_collapse = mode & 1, .no_dag = (mode >> 1) & 1};
        vx_svo_model m;
        vx_svo_build_stats st;
        vx_error e;
        REQUIRE(vx_svo_build_model(&d, &in, &m, &st, &e) == VX_OK);
        CHECK(st.input_voxels == cnt);
        CHECK(vx_svo_validate_model(&m, &e) == VX_OK);
        check_equal(&m, &ref, rgba ? val_rgba : val_pal);
        check_cell_box(&m);
        CHECK(st.desc_collapsed <= st.desc_plain && st.desc_dag <= st.desc_collapsed);
        if (d.no_collapse) CHECK(st.desc_collapsed == st.desc_plain);
        if (d.no_dag) CHECK(st.desc_dag == st.desc_collapsed);
        words[mode] = m.node_count;
        vx_svo_model_free(NULL, &m);
    }
    CHECK(words[0] <= words[1] && words[0] <= words[3]);
    free(ref.v);
    free(keys);
    free(pal);
    free(col);
}

static void test_random_sparse(void) {
    random_case(37, 50, 23, 3000, false);
    random_case(64, 64, 64, 20000, true);
    random_case(5, 130, 9, 2000, false);
    random_case(3, 3, 3, 40, true);
}

static void test_tiles(void) {
    const uint32_t S = 64;
    dense ref = dense_make(S, S, S);
    uint64_t keys[64];
    uint8_t lv[64], pal[64];
    size_t n = 0;
    /* non-overlapping tiles of levels 1..4 and single cells */
    struct { uint32_t x, y, z, l; } t[] = {{0, 0, 0, 4}, {16, 0, 0, 3}, {32, 32, 32, 5}, {24, 8, 0, 2},
                                           {1, 17, 3, 0}, {2, 18, 4, 1}, {16, 16, 16, 0}, {63, 63, 0, 0}};
    for (size_t i = 0; i < sizeof t / sizeof t[0]; i++) {
        keys[n] = vx_svo_morton(t[i].x, t[i].y, t[i].z);
        lv[n] = (uint8_t)t[i].l;
        pal[n] = (uint8_t)(10 + i);
        uint32_t side = 1u << t[i].l;
        for (uint32_t z = 0; z < side; z++)
            for (uint32_t y = 0; y < side; y++)
                for (uint32_t x = 0; x < side; x++) *dat(&ref, t[i].x + x, t[i].y + y, t[i].z + z) = 1 + pal[n];
        n++;
    }
    /* a duplicate tile: the later one wins */
    keys[n] = vx_svo_morton(16, 0, 0), lv[n] = 3, pal[n] = 99;
    for (uint32_t z = 0; z < 8; z++)
        for (uint32_t y = 0; y < 8; y++)
            for (uint32_t x = 0; x < 8; x++) *dat(&ref, 16 + x, y, z) = 1 + 99;
    n++;
    vx_svo_voxels in = {.size = {S, S, S}, .count = n, .keys = keys, .level = lv, .attrs = VX_ATTR_PALETTE, .palette = pal};
    for (int mode = 0; mode < 4; mode++) {
        vx_svo_build_desc d = {.no_collapse = mode & 1, .no_dag = (mode >> 1) & 1};
        vx_svo_model m;
        vx_svo_build_stats st;
        vx_error e;
        REQUIRE(vx_svo_build_model(&d, &in, &m, &st, &e) == VX_OK);
        CHECK(vx_svo_validate_model(&m, &e) == VX_OK);
        check_equal(&m, &ref, val_pal);
        CHECK(m.node_count < 200); /* tiles are never expanded */
        vx_svo_model_free(NULL, &m);
    }
    /* a whole-model tile is the root leaf */
    uint64_t k0 = 0;
    uint8_t l6 = 6;
    vx_svo_voxels whole = {.size = {S, S, S}, .count = 1, .keys = &k0, .level = &l6};
    vx_svo_model m;
    vx_error e;
    REQUIRE(vx_svo_build_model(NULL, &whole, &m, NULL, &e) == VX_OK);
    CHECK(m.root == VX_SVO_ROOT_LEAF && m.voxel_count == (uint64_t)S * S * S);
    vx_svo_model_free(NULL, &m);
    /* bad tiles */
    uint64_t bk[2];
    uint8_t bl[2];
    vx_svo_voxels bad = {.size = {S, S, S}, .count = 1, .keys = bk, .level = bl};
    bk[0] = vx_svo_morton(4, 0, 0), bl[0] = 3; /* misaligned */
    CHECK(vx_svo_build_model(NULL, &bad, &m, NULL, &e) == VX_ERR_INVALID_ARG && strstr(e.msg, "aligned"));
    bk[0] = 0, bl[0] = 7; /* above depth */
    CHECK(vx_svo_build_model(NULL, &bad, &m, NULL, &e) == VX_ERR_INVALID_ARG && strstr(e.msg, "level"));
    vx_svo_voxels bad2 = {.size = {36, 64, 64}, .count = 1, .keys = bk, .level = bl};
    bk[0] = vx_svo_morton(32, 0, 0), bl[0] = 3; /* crosses size */
    CHECK(vx_svo_build_model(NULL, &bad2, &m, NULL, &e) == VX_ERR_INVALID_ARG && strstr(e.msg, "outside"));
    bad.count = 2;
    bk[0] = 0, bl[0] = 2, bk[1] = vx_svo_morton(1, 1, 1), bl[1] = 0; /* overlap */
    CHECK(vx_svo_build_model(NULL, &bad, &m, NULL, &e) == VX_ERR_INVALID_ARG && strstr(e.msg, "inside"));
    bk[1] = 0, bl[1] = 1; /* same corner, different size */
    CHECK(vx_svo_build_model(NULL, &bad, &m, NULL, &e) == VX_ERR_INVALID_ARG);
    free(ref.v);
}

static void test_bad_input(void) {
    vx_svo_model m;
    vx_error e;
    uint64_t k = vx_svo_morton(10, 0, 0);
    vx_svo_voxels in = {.size = {10, 10, 10}, .count = 1, .keys = &k};
    CHECK(vx_svo_build_model(NULL, &in, &m, NULL, &e) == VX_ERR_INVALID_ARG && strstr(e.msg, "outside"));
    k = 1ull << 63;
    CHECK(vx_svo_build_model(NULL, &in, &m, NULL, &e) == VX_ERR_INVALID_ARG);
    k = 0;
    in.attrs = VX_ATTR_RGBA8; /* array missing */
    CHECK(vx_svo_build_model(NULL, &in, &m, NULL, &e) == VX_ERR_INVALID_ARG);
    uint8_t p = 1;
    in.attrs = 0, in.palette = &p; /* array not named */
    CHECK(vx_svo_build_model(NULL, &in, &m, NULL, &e) == VX_ERR_INVALID_ARG);
    in.palette = NULL;
    in.size[0] = 0;
    CHECK(vx_svo_build_model(NULL, &in, &m, NULL, &e) == VX_ERR_INVALID_ARG);
    in.size[0] = 1000;
    CHECK(vx_svo_build_model(&(vx_svo_build_desc){.max_depth = 8}, &in, &m, NULL, &e) == VX_ERR_LIMIT);
    CHECK(vx_svo_build_model(&(vx_svo_build_desc){.max_depth = 22}, &in, &m, NULL, &e) == VX_ERR_INVALID_ARG);
    in.size[0] = 1u << 21; /* depth 21: keys use 63 bits, the wide sort path */
    uint64_t ks[3] = {vx_svo_morton((1u << 21) - 1, 9, 9), vx_svo_morton(3, 2, 1), vx_svo_morton((1u << 21) - 1, 9, 9)};
    uint8_t pl[3] = {1, 2, 3};
    vx_svo_voxels deep = {.size = {1u << 21, 10, 10}, .count = 3, .keys = ks, .attrs = VX_ATTR_PALETTE, .palette = pl};
    REQUIRE(vx_svo_build_model(NULL, &deep, &m, NULL, &e) == VX_OK);
    CHECK(m.depth == 21 && m.voxel_count == 2 && vx_svo_validate_model(&m, &e) == VX_OK);
    coll c = decode_all(&m);
    REQUIRE(c.n == 2);
    CHECK(c.c[0].x == 3 && m.palette[c.c[0].attr] == 2 && c.c[1].x == (1u << 21) - 1 && m.palette[c.c[1].attr] == 3);
    free(c.c);
    vx_svo_model_free(NULL, &m);
}

static void far_case(uint32_t limit) {
    const vx_svo_build_desc bd = {.testing.far_limit = limit};
    const uint32_t S = 48;
    dense ref = dense_make(S, S, S);
    size_t n = 4000;
    uint64_t* keys = (uint64_t*)malloc(n * 8);
    uint8_t* pal = (uint8_t*)malloc(n);
    for (size_t i = 0; i < n; i++) {
        uint32_t x = (uint32_t)(rnd() % S), y = (uint32_t)(rnd() % S), z = (uint32_t)(rnd() % S);
        keys[i] = vx_svo_morton(x, y, z);
        pal[i] = (uint8_t)(1 + rnd() % 3);
        *dat(&ref, x, y, z) = 1 + pal[i];
    }
    for (int attrs = 0; attrs < 2; attrs++) {
        vx_svo_voxels in = {.size = {S, S, S}, .count = n, .keys = keys};
        if (attrs) in.attrs = VX_ATTR_PALETTE, in.palette = pal;
        vx_svo_model m;
        vx_svo_build_stats st;
        vx_error e;
        REQUIRE(vx_svo_build_model(&bd, &in, &m, &st, &e) == VX_OK);
        CHECKF(st.far_pointers > 0, "limit %u: no far pointers", limit);
        CHECK(vx_svo_validate_model(&m, &e) == VX_OK);
        check_cell_box(&m);
        if (attrs) check_equal(&m, &ref, val_pal);
        else {
            coll c = decode_all(&m);
            size_t want = 0;
            for (size_t i = 0; i < (size_t)S * S * S; i++) want += ref.v[i] != 0;
            CHECK(c.n == want && c.order_ok);
            for (size_t i = 0; i < c.n; i++) CHECK(*dat(&ref, c.c[i].x, c.c[i].y, c.c[i].z) != 0);
            free(c.c);
        }
        vx_svo_model_free(NULL, &m);
    }
    free(ref.v);
    free(keys);
    free(pal);
}

static void test_far_forced(void) {
    far_case(1);
    far_case(3);
    far_case(40);
}

/* No test hook: a model whose node array is far longer than 2^15 words. */
static void test_far_real(void) {
    const uint32_t S = 1024;
    size_t n = 120000;
    uint64_t* keys = (uint64_t*)malloc(n * 8);
    uint32_t* col = (uint32_t*)malloc(n * 4);
    for (size_t i = 0; i < n; i++) {
        keys[i] = vx_svo_morton((uint32_t)(rnd() % S), (uint32_t)(rnd() % S), (uint32_t)(rnd() % S));
        col[i] = (uint32_t)rnd();
    }
    vx_svo_voxels in = {.size = {S, S, S}, .count = n, .keys = keys, .attrs = VX_ATTR_RGBA8, .rgba = col};
    vx_svo_model m;
    vx_svo_build_stats st;
    vx_error e;
    REQUIRE(vx_svo_build_model(NULL, &in, &m, &st, &e) == VX_OK);
    CHECK(m.node_count > 100000);
    CHECKF(st.far_pointers > 0, "%u words, no far pointers", m.node_count);
    CHECK(vx_svo_validate_model(&m, &e) == VX_OK);
    /* decode and compare as sorted key sets (dense is too big here) */
    coll c = decode_all(&m);
    CHECK(c.n == m.voxel_count && c.order_ok);
    size_t found = 0;
    for (size_t i = 0; i < n; i += 997) {
        uint32_t x = vx__compact3(keys[i]), y = vx__compact3(keys[i] >> 1), z = vx__compact3(keys[i] >> 2);
        size_t lo = 0, hi = c.n;
        while (lo < hi) {
            size_t mid = (lo + hi) / 2;
            if (vx_svo_morton(c.c[mid].x, c.c[mid].y, c.c[mid].z) < keys[i]) lo = mid + 1;
            else hi = mid;
        }
        /* the last duplicate of this key decides its colour */
        size_t last = i;
        for (size_t j = i + 1; j < n; j++)
            if (keys[j] == keys[i]) last = j;
        if (lo < c.n && c.c[lo].x == x && c.c[lo].y == y && c.c[lo].z == z && m.rgba[c.c[lo].attr] == col[last]) found++;
        else CHECK(0);
    }
    CHECK(found > 0);
    free(c.c);
    vx_svo_model_free(NULL, &m);
    free(keys);
    free(col);
}

/* One shape stamped many times at block-aligned spots shares its subtree. */
static void test_repeated(void) {
    const uint32_t S = 128, B = 16;
    dense ref = dense_make(S, S, S);
    size_t cap = 1u << 20, n = 0;
    uint64_t* keys = (uint64_t*)malloc(cap * 8);
    uint8_t* pal = (uint8_t*)malloc(cap);
    for (uint32_t bz = 0; bz < S; bz += 2 * B)
        for (uint32_t by = 0; by < S; by += B)
            for (uint32_t bx = 0; bx < S; bx += B)
                for (uint32_t z = 0; z < B; z++)
                    for (uint32_t y = 0; y < B; y++)
                        for (uint32_t x = 0; x < B; x++) {
                            float dx = x - 7.5f, dy = y - 7.5f, dz = z - 7.5f;
                            float r2 = dx * dx + dy * dy + dz * dz;
                            if (r2 > 49 || r2 < 30) continue;
                            keys[n] = vx_svo_morton(bx + x, by + y, bz + z);
                            pal[n] = (uint8_t)(1 + (z > 8) + (x > 8));
                            *dat(&ref, bx + x, by + y, bz + z) = 1 + pal[n];
                            n++;
                        }
    vx_svo_voxels in = {.size = {S, S, S}, .count = n, .keys = keys, .attrs = VX_ATTR_PALETTE, .palette = pal};
    vx_svo_model m, m1;
    vx_svo_build_stats st, st1;
    vx_error e;
    REQUIRE(vx_svo_build_model(NULL, &in, &m, &st, &e) == VX_OK);
    check_equal(&m, &ref, val_pal);
    /* one copy alone */
    size_t n1 = 0;
    for (size_t i = 0; i < n; i++)
        if (vx__compact3(keys[i]) < B && vx__compact3(keys[i] >> 1) < B && vx__compact3(keys[i] >> 2) < B) n1++;
    vx_svo_voxels one = {.size = {B, B, B}, .count = n1, .keys = keys, .attrs = VX_ATTR_PALETTE, .palette = pal};
    REQUIRE(vx_svo_build_model(NULL, &one, &m1, &st1, &e) == VX_OK);
    size_t copies = (S / B) * (S / B) * (S / (2 * B));
    CHECK(st.desc_collapsed >= copies * st1.desc_collapsed);
    /* shared: one copy's descriptors plus the few levels above the copies */
    CHECKF(st.desc_dag <= st1.desc_dag + 3 * 8 + 2, "dag %llu, one copy %llu", (unsigned long long)st.desc_dag,
           (unsigned long long)st1.desc_dag);
    CHECK(m.attr_count <= m1.attr_count + 3 * 8 + 8);
    vx_svo_model_free(NULL, &m);
    vx_svo_model_free(NULL, &m1);
    free(ref.v);
    free(keys);
    free(pal);
}

/* Reference representative attribute, recursively on a dense grid. */
typedef struct lodref {
    dense* d;
    bool rgba;
} lodref;
static bool ref_rep(lodref* L, uint32_t x0, uint32_t y0, uint32_t z0, uint32_t lvl, uint32_t* out) {
    if (lvl == 0) {
        if (x0 >= L->d->sx || y0 >= L->d->sy || z0 >= L->d->sz) return false;
        uint32_t v = *dat(L->d, x0, y0, z0);
        if (!v) return false;
        *out = v - 1;
        return true;
    }
    uint32_t vals[8], n = 0, h = 1u << (lvl - 1);
    for (uint32_t o = 0; o < 8; o++)
        if (ref_rep(L, x0 + (o & 1) * h, y0 + (o >> 1 & 1) * h, z0 + (o >> 2 & 1) * h, lvl - 1, &vals[n])) n++;
    if (!n) return false;
    if (L->rgba) {
        uint32_t r = 0;
        for (int c = 0; c < 4; c++) {
            uint32_t s = 0;
            for (uint32_t i = 0; i < n; i++) s += (vals[i] >> (8 * c)) & 255;
            r |= (uint32_t)floor((double)s / n + 0.5) << (8 * c);
        }
        *out = r;
    } else {
        uint32_t best = 0, bn = 0;
        for (uint32_t v = 0; v < 256; v++) {
            uint32_t k = 0;
            for (uint32_t i = 0; i < n; i++) k += vals[i] == v;
            if (k > bn) bn = k, best = v; /* ascending v: ties keep the smallest */
        }
        *out = best;
    }
    return true;
}

static void test_lod(void) {
    for (int rgba = 0; rgba < 2; rgba++)
        for (int trial = 0; trial < 20; trial++) {
            const uint32_t S = 8;
            dense ref = dense_make(S, S, S);
            uint64_t keys[200];
            uint8_t pal[200];
            uint32_t col[200];
            size_t n = 0;
            uint32_t A = rgba ? 0xFF2080F0u : 3, B = rgba ? 0x80FF1001u : 7;
            size_t want = 1 + rnd() % 150;
            for (size_t i = 0; i < want; i++) {
                uint32_t x = (uint32_t)(rnd() % S), y = (uint32_t)(rnd() % S), z = (uint32_t)(rnd() % S);
                uint32_t v = rnd() % 3 ? A : B;
                keys[n] = vx_svo_morton(x, y, z);
                pal[n] = (uint8_t)v;
                col[n] = v;
                *dat(&ref, x, y, z) = 1 + v;
                n++;
            }
            vx_svo_voxels in = {.size = {S, S, S}, .count = n, .keys = keys};
            if (rgba) in.attrs = VX_ATTR_RGBA8, in.rgba = col;
            else in.attrs = VX_ATTR_PALETTE, in.palette = pal;
            vx_svo_model m;
            vx_error e;
            REQUIRE(vx_svo_build_model(NULL, &in, &m, NULL, &e) == VX_OK);
            lodref L = {&ref, rgba != 0};
            uint32_t expect = 0;
            REQUIRE(ref_rep(&L, 0, 0, 0, 3, &expect));
            uint32_t got = rgba ? m.rgba[m.root_attr] : m.palette[m.root_attr];
            CHECKF(got == expect, "root_attr 0x%x, reference 0x%x", got, expect);
            vx_svo_model_free(NULL, &m);
            free(ref.v);
        }
}

static bool count_stop(void* user, uint32_t x, uint32_t y, uint32_t z, uint32_t a) {
    (void)x, (void)y, (void)z, (void)a;
    return --*(int*)user > 0;
}

static void test_decode_stop(void) {
    uint64_t k = 0;
    uint8_t l = 5;
    vx_svo_voxels in = {.size = {32, 32, 32}, .count = 1, .keys = &k, .level = &l};
    vx_svo_model m;
    vx_error e;
    REQUIRE(vx_svo_build_model(NULL, &in, &m, NULL, &e) == VX_OK);
    int left = 1000;
    CHECK(vx_svo_decode_model(&m, count_stop, &left, &e) == VX_OK && left == 0);
    vx_svo_model_free(NULL, &m);
}

static void test_other_channels(void) {
    const uint32_t S = 16;
    size_t n = 600;
    uint64_t keys[600];
    uint32_t nrm[600];
    uint16_t mat[600];
    float den[600];
    for (size_t i = 0; i < n; i++) {
        keys[i] = vx_svo_morton((uint32_t)(rnd() % S), (uint32_t)(rnd() % S), (uint32_t)(rnd() % S));
        float v[3] = {(float)(rnd() % 200) - 100.0f, (float)(rnd() % 200) - 100.0f, (float)(rnd() % 200) - 100.0f};
        nrm[i] = vx__oct_encode(v);
        mat[i] = (uint16_t)(rnd() % 3);
        den[i] = (float)(rnd() % 1000) * 0.25f;
    }
    vx_svo_voxels in = {.size = {S, S, S}, .count = n, .keys = keys, .attrs = VX_ATTR_NORMAL | VX_ATTR_MATERIAL | VX_ATTR_DENSITY,
                        .normal = nrm, .material = mat, .density = den};
    vx_svo_model m;
    vx_error e;
    REQUIRE(vx_svo_build_model(NULL, &in, &m, NULL, &e) == VX_OK);
    CHECK(vx_svo_validate_model(&m, &e) == VX_OK && m.palette == NULL && m.rgba == NULL);
    coll c = decode_all(&m);
    size_t bad = 0;
    for (size_t j = 0; j < c.n; j++) {
        uint64_t k = vx_svo_morton(c.c[j].x, c.c[j].y, c.c[j].z);
        size_t last = SIZE_MAX;
        for (size_t i = 0; i < n; i++)
            if (keys[i] == k) last = i;
        uint32_t a = c.c[j].attr;
        if (last == SIZE_MAX || m.normal[a] != nrm[last] || m.material[a] != mat[last] || m.density[a] != den[last]) bad++;
    }
    CHECK(bad == 0 && c.n == m.voxel_count);
    free(c.c);
    /* octahedral round trip stays close */
    for (int i = 0; i < 100; i++) {
        float v[3] = {(float)(rnd() % 200) - 100.0f, (float)(rnd() % 200) - 100.0f, (float)(rnd() % 200) - 99.5f}, w[3];
        float l = sqrtf(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        vx__oct_decode(vx__oct_encode(v), w);
        CHECK(fabsf(w[0] - v[0] / l) < 1e-3f && fabsf(w[1] - v[1] / l) < 1e-3f && fabsf(w[2] - v[2] / l) < 1e-3f);
    }
    vx_svo_model_free(NULL, &m);
    /* density mean at the root of two cells */
    uint64_t k2[2] = {vx_svo_morton(0, 0, 0), vx_svo_morton(1, 0, 0)};
    float d2[2] = {1.0f, 2.0f};
    vx_svo_voxels in2 = {.size = {2, 2, 2}, .count = 2, .keys = k2, .attrs = VX_ATTR_DENSITY, .density = d2};
    REQUIRE(vx_svo_build_model(NULL, &in2, &m, NULL, &e) == VX_OK);
    CHECK(m.density[m.root_attr] == 1.5f);
    vx_svo_model_free(NULL, &m);
}

/* vx__svo_build_interned (the tuples interned by the caller, as the GPU
 * voxelizer hands them) builds the same model, word for word, as
 * vx_svo_build_model over the expanded tuples: every channel mix (one
 * channel: the builder's direct values), shared tuples, uniform blocks that
 * collapse, shared subtrees, duplicates (the later wins), unsorted input,
 * forced far pointers; and it rejects equal tuples and ids out of range. */
typedef struct ient {
    uint64_t key;
    size_t order;
    uint32_t v;
} ient;
static int ient_cmp(const void* pa, const void* pb) {
    const ient *a = (const ient*)pa, *b = (const ient*)pb;
    if (a->key != b->key) return a->key < b->key ? -1 : 1;
    return a->order < b->order ? -1 : a->order > b->order;
}

static const vx__svo_rec* g_vals; /* for val_cmp */
static int val_cmp(const void* pa, const void* pb) {
    uint32_t a = *(const uint32_t*)pa, b = *(const uint32_t*)pb;
    int c = memcmp(&g_vals[a], &g_vals[b], sizeof *g_vals);
    return c ? c : (a < b ? -1 : a > b);
}

/* ---- a node pool made by brute force (the caller's build, vx__svo_interned.pool) ---------- */

/* Post-order recursion over the sorted unique cells, children in octant
 * order, equal nodes found through a table of their contents: the order
 * and ids the builder's streaming pass gives, made another way. */
typedef struct tpool {
    uint32_t* w;
    size_t n, cap;
    uint32_t* tab; /* node offset + 1 */
    size_t tcap;
    uint64_t plain, coll;
} tpool;

static size_t tp_slot(const tpool* p, const uint32_t* node, unsigned len) {
    uint64_t h = 0xCBF29CE484222325ull;
    for (unsigned i = 0; i < len; i++) h = (h ^ node[i]) * 0x100000001B3ull;
    size_t j = (size_t)(h ^ h >> 29) & (p->tcap - 1);
    while (p->tab[j]) {
        const uint32_t* q = p->w + p->tab[j] - 1;
        if (q[0] == node[0] && !memcmp(q + 3, node + 3, (len - 3) * 4)) break;
        j = (j + 1) & (p->tcap - 1);
    }
    return j;
}

static void tp_node(tpool* p, const uint64_t* k, const uint32_t* id, size_t lo, size_t hi, unsigned level, bool* leaf,
                    uint32_t* ref) {
    if (level == 0) {
        *leaf = true, *ref = id[lo];
        return;
    }
    uint32_t node[11], valid = 0, lmask = 0, kid[8];
    unsigned nk = 0;
    bool same = true;
    for (size_t a = lo; a < hi;) {
        unsigned o = (unsigned)(k[a] >> (3 * (level - 1)) & 7u);
        size_t b = a;
        while (b < hi && (unsigned)(k[b] >> (3 * (level - 1)) & 7u) == o) b++;
        bool cl;
        uint32_t cr;
        tp_node(p, k, id, a, b, level - 1, &cl, &cr);
        valid |= 1u << o;
        if (cl) lmask |= 1u << o;
        kid[nk] = cr;
        same = same && cl && cr == kid[0];
        nk++;
        a = b;
    }
    p->plain++;
    if (valid == 0xFFu && lmask == 0xFFu && same) {
        *leaf = true, *ref = kid[0];
        return;
    }
    p->coll++;
    node[0] = valid | lmask << 8, node[1] = 0, node[2] = 0;
    memcpy(node + 3, kid, nk * 4);
    size_t j = tp_slot(p, node, 3 + nk);
    *leaf = false;
    if (p->tab[j]) {
        *ref = p->tab[j] - 1;
        return;
    }
    REQUIRE(p->n + 3 + nk <= p->cap);
    memcpy(p->w + p->n, node, (3 + nk) * 4);
    *ref = (uint32_t)p->n;
    p->tab[j] = (uint32_t)p->n + 1;
    p->n += 3 + nk;
}

/* The caller's representatives and attribute runs (vx__svo_pool.reps,
 * .runs) made another way, in pool order: each node's representative by
 * vx__svo_rec_mean over its children's tuples, looked up in (or appended
 * to) a copy of the tuple table; its run (children's tuple ids) as the
 * layout's definition says, sequentially: a uniform run of n < 8 copies of
 * v takes the longest stored run of v with more copies (tried from 8 down),
 * else a stored equal run, else it is stored. Runs are found through a
 * table of (contents -> first record) over the stored runs only. */
typedef struct truns {
    vx__svo_rec* tab; /* the tuples, then the representatives' new ones */
    size_t ntab, captab;
    uint32_t* recs;
    size_t nrecs;
    uint64_t* key; /* run table: hash | 1, 0 empty */
    uint32_t *start, *len;
    size_t cap;
} truns;

static uint64_t tr_hash(const uint32_t* v, unsigned n) {
    uint64_t h = 0xCBF29CE484222325ull ^ n;
    for (unsigned i = 0; i < n; i++) h = (h ^ v[i]) * 0x100000001B3ull;
    return h | 1u;
}
/* The first record of a stored run equal to v[0..n), or UINT32_MAX. */
static uint32_t tr_find(const truns* t, const uint32_t* v, unsigned n) {
    uint64_t h = tr_hash(v, n);
    for (size_t j = (size_t)(h >> 7) & (t->cap - 1); t->key[j]; j = (j + 1) & (t->cap - 1))
        if (t->key[j] == h && t->len[j] == n && !memcmp(t->recs + t->start[j], v, n * 4)) return t->start[j];
    return UINT32_MAX;
}
static uint32_t tr_run(truns* t, const uint32_t* v, unsigned n) {
    bool uni = true;
    for (unsigned i = 1; i < n; i++) uni = uni && v[i] == v[0];
    if (uni && n < 8) {
        uint32_t w[8];
        for (unsigned i = 0; i < 8; i++) w[i] = v[0];
        for (unsigned L = 8; L > n; L--) {
            uint32_t st = tr_find(t, w, L);
            if (st != UINT32_MAX) return st;
        }
    }
    uint32_t st = tr_find(t, v, n);
    if (st != UINT32_MAX) return st;
    uint64_t h = tr_hash(v, n);
    size_t j = (size_t)(h >> 7) & (t->cap - 1);
    while (t->key[j]) j = (j + 1) & (t->cap - 1);
    t->key[j] = h, t->start[j] = (uint32_t)t->nrecs, t->len[j] = n;
    memcpy(t->recs + t->nrecs, v, n * 4);
    t->nrecs += n;
    return t->start[j];
}

/* Fills pool words [1] (representative ids) and [2] (run starts) of the
 * pool w[0..n) over tuples tab[0..ntab); t gets the extended table and the
 * records. */
static void tr_make(truns* t, uint32_t attrs, uint32_t* w, size_t n, const vx__svo_rec* tab, size_t ntab) {
    size_t nodes = n / 4 + 1;
    t->captab = ntab + nodes;
    t->tab = (vx__svo_rec*)calloc(t->captab, sizeof *t->tab);
    t->recs = (uint32_t*)calloc(8 * nodes, 4);
    t->cap = 1024;
    while (t->cap < 4 * nodes) t->cap *= 2;
    t->key = (uint64_t*)calloc(t->cap, 8);
    t->start = (uint32_t*)calloc(t->cap, 4);
    t->len = (uint32_t*)calloc(t->cap, 4);
    size_t tcap = 1024;
    while (tcap < 2 * t->captab) tcap *= 2;
    uint32_t* tt = (uint32_t*)calloc(tcap, 4); /* tuple table: id + 1 */
    REQUIRE(t->tab && t->recs && t->key && t->start && t->len && tt);
    memcpy(t->tab, tab, ntab * sizeof *tab);
    t->ntab = ntab;
    for (size_t i = 0; i < ntab; i++) {
        size_t j = (size_t)(tr_hash((const uint32_t*)&tab[i], 4) >> 7) & (tcap - 1);
        while (tt[j]) j = (j + 1) & (tcap - 1);
        tt[j] = (uint32_t)i + 1;
    }
    for (size_t off = 0; off < n;) {
        uint32_t valid = w[off] & 0xFFu, leaf = (w[off] >> 8) & 0xFFu, v[8];
        unsigned nk = 0;
        const vx__svo_rec* c[8];
        for (unsigned o = 0; o < 8; o++) {
            if (!(valid >> o & 1u)) continue;
            uint32_t ref = w[off + 3 + nk];
            v[nk] = (leaf >> o & 1u) ? ref : w[ref + 1];
            c[nk] = &t->tab[v[nk]];
            nk++;
        }
        vx__svo_rec r;
        vx__svo_rec_mean(attrs, c, nk, &r);
        size_t j = (size_t)(tr_hash((const uint32_t*)&r, 4) >> 7) & (tcap - 1);
        while (tt[j] && memcmp(&t->tab[tt[j] - 1], &r, sizeof r)) j = (j + 1) & (tcap - 1);
        if (!tt[j]) t->tab[t->ntab] = r, tt[j] = (uint32_t)++t->ntab;
        w[off + 1] = tt[j] - 1;
        w[off + 2] = tr_run(t, v, nk);
        off += 3 + nk;
    }
    free(tt);
}

static void tr_free(truns* t) { free(t->tab), free(t->recs), free(t->key), free(t->start), free(t->len); }

/* The pool path on the sorted, unique entries (the last of equal keys):
 * the model equals the builder's own, check_pool accepts the pool, and
 * broken pools are refused. */
static void pool_case(uint32_t attrs, uint32_t S, const uint64_t* keys, const uint32_t* ids, size_t n, const vx__svo_rec* tab,
                      size_t ntab, bool thread, uint32_t far) {
    const vx_svo_build_desc bd = {.testing.far_limit = far};
    uint64_t* uk = (uint64_t*)calloc(n + 1, 8);
    uint32_t* ui = (uint32_t*)calloc(n + 1, 4);
    REQUIRE(uk && ui);
    size_t m = 0;
    for (size_t i = 0; i < n; i++) {
        if (m && uk[m - 1] == keys[i]) m--;
        uk[m] = keys[i], ui[m] = ids[i], m++;
    }
    unsigned depth = 0;
    while ((1u << depth) < S) depth++;
    tpool p = {0};
    p.cap = 11 * m + 16;
    p.tcap = 1024;
    while (p.tcap < 4 * m) p.tcap *= 2;
    p.w = (uint32_t*)calloc(p.cap, 4);
    p.tab = (uint32_t*)calloc(p.tcap, 4);
    REQUIRE(p.w && p.tab && m);
    bool rl;
    uint32_t rr;
    tp_node(&p, uk, ui, 0, m, depth, &rl, &rr);
    vx__svo_pool pool = {.words = p.w, .count = p.n, .root = rr, .root_leaf = rl, .plain = p.plain, .collapsed = p.coll};
    vx_svo_voxels in = {.size = {S, S, S}, .count = m, .keys = uk, .attrs = attrs};
    vx__svo_interned pre = {ui, tab, ntab, thread, 1, NULL, false};
    vx_svo_model a, b;
    vx_svo_build_stats sa, sb;
    vx_error e;
    REQUIRE(vx__svo_build_interned(&bd, &in, &pre, &a, &sa, &e) == VX_OK);
    pre.pool = &pool;
    vx_result r = vx__svo_build_interned(&bd, &in, &pre, &b, &sb, &e);
    CHECKF(r == VX_OK, "pool, attrs 0x%x: %s", attrs, e.msg);
    if (r == VX_OK) {
        size_t na = a.attr_count;
        CHECKF(a.node_count == b.node_count && a.root == b.root && a.root_attr == b.root_attr && na == b.attr_count &&
                   !memcmp(a.nodes, b.nodes, (size_t)a.node_count * 4) && (!a.rgba || !memcmp(a.rgba, b.rgba, na * 4)) &&
                   (!a.palette || !memcmp(a.palette, b.palette, na)) && (!a.normal || !memcmp(a.normal, b.normal, na * 4)) &&
                   (!a.material || !memcmp(a.material, b.material, na * 2)) &&
                   (!a.density || !memcmp(a.density, b.density, na * 4)) && sa.desc_dag == sb.desc_dag &&
                   sa.desc_plain == sb.desc_plain && sa.desc_collapsed == sb.desc_collapsed && sa.voxels == sb.voxels,
               "pool, attrs 0x%x: %u/%u words, %u/%u records", attrs, a.node_count, b.node_count, a.attr_count, b.attr_count);
        vx_svo_model_free(NULL, &b);
    }
    pre.check_pool = true; /* the builder's own pool is the brute-force one */
    r = vx__svo_build_interned(&bd, &in, &pre, &b, NULL, &e);
    CHECKF(r == VX_OK, "check_pool, attrs 0x%x: %s", attrs, e.msg);
    if (r == VX_OK) vx_svo_model_free(NULL, &b);
    if (p.n >= 4 && !rl) {
        /* a leaf child's tuple changed: check_pool names it; taken, the model differs or it is refused */
        size_t off = 0;
        while (off < p.n && !((p.w[off] >> 8) & 0xFFu)) off += 3 + (size_t)__builtin_popcount(p.w[off] & 0xFFu);
        if (off < p.n && ntab > 1) {
            unsigned j = 0; /* the first leaf child's index among the valid children */
            uint32_t valid = p.w[off] & 0xFFu, leaf = p.w[off] >> 8;
            for (unsigned o = 0; o < 8 && !((leaf >> o) & 1u); o++) j += (valid >> o) & 1u;
            uint32_t keep = p.w[off + 3 + j];
            p.w[off + 3 + j] = (keep + 1) % (uint32_t)ntab;
            CHECK(vx__svo_build_interned(&bd, &in, &pre, &b, NULL, &e) == VX_ERR_INVALID_ARG && strstr(e.msg, "differs"));
            p.w[off + 3 + j] = keep;
        }
        pre.check_pool = false;
        uint32_t h0 = p.w[0];
        p.w[0] = 0;
        CHECK(vx__svo_build_interned(&bd, &in, &pre, &b, NULL, &e) == VX_ERR_INVALID_ARG && strstr(e.msg, "header"));
        p.w[0] = h0;
        /* the last node's first node child pointing at itself, or its leaf at a tuple beyond the table */
        size_t last = 0;
        for (size_t off2 = 0; off2 < p.n; off2 += 3 + (size_t)__builtin_popcount(p.w[off2] & 0xFFu)) last = off2;
        uint32_t keep = p.w[last + 3];
        uint32_t lv = p.w[last] & 0xFFu, first = lv & (~lv + 1u); /* its first valid child */
        bool leaf0 = ((p.w[last] >> 8) & first) != 0;
        p.w[last + 3] = leaf0 ? (uint32_t)ntab : (uint32_t)last;
        CHECK(vx__svo_build_interned(&bd, &in, &pre, &b, NULL, &e) == VX_ERR_INVALID_ARG &&
              strstr(e.msg, leaf0 ? "tuple" : "earlier node"));
        p.w[last + 3] = keep;
        pool.root = (uint32_t)p.n + 5;
        CHECK(vx__svo_build_interned(&bd, &in, &pre, &b, NULL, &e) == VX_ERR_INVALID_ARG && strstr(e.msg, "root"));
    }
    /* the representatives and attribute runs given too (as the GPU gives
     * them): the same model; a run that is not the node's children's refused */
    if (attrs && !rl && p.n) {
        pool.root = rr;
        truns t = {0};
        tr_make(&t, attrs, p.w, p.n, tab, ntab);
        vx__svo_pool pr = pool;
        pr.reps = pr.runs = true;
        pr.recs = t.recs, pr.nrecs = t.nrecs;
        vx__svo_interned pi = {ui, t.tab, t.ntab, thread, 3, &pr, false}; /* 3 threads: the large cases copy and convert in parallel */
        r = vx__svo_build_interned(&bd, &in, &pi, &b, NULL, &e);
        CHECKF(r == VX_OK, "runs given, attrs 0x%x: %s", attrs, e.msg);
        if (r == VX_OK) {
            size_t na = a.attr_count;
            CHECKF(a.node_count == b.node_count && a.root == b.root && a.root_attr == b.root_attr && na == b.attr_count &&
                       !memcmp(a.nodes, b.nodes, (size_t)a.node_count * 4) && (!a.rgba || !memcmp(a.rgba, b.rgba, na * 4)) &&
                       (!a.palette || !memcmp(a.palette, b.palette, na)) && (!a.normal || !memcmp(a.normal, b.normal, na * 4)) &&
                       (!a.material || !memcmp(a.material, b.material, na * 2)) &&
                       (!a.density || !memcmp(a.density, b.density, na * 4)),
                   "runs given, attrs 0x%x: %u/%u words, %u/%u records", attrs, a.node_count, b.node_count, a.attr_count,
                   b.attr_count);
            vx_svo_model_free(NULL, &b);
        }
        /* and the blocks laid out (here the builder's own words): the records
         * filled, the same model and counts; with check_pool a changed word is named */
        vx_svo_build_stats sl;
        pr.laid = a.nodes, pr.laid_count = a.node_count, pr.laid_far = sa.far_pointers, pr.laid_desc = sa.desc_dag;
        pr.root_rep = p.w[rr + 1];
        r = vx__svo_build_interned(&bd, &in, &pi, &b, &sl, &e);
        if (vx__svo_far_limit(&bd.testing) != VX__SVO_PTR_MAX) { /* forced far pointers: the caller's layout cannot have them */
            CHECK(r == VX_ERR_INVALID_ARG && strstr(e.msg, "near pointers"));
            r = VX_ERR_INVALID_ARG;
        } else {
            CHECKF(r == VX_OK, "laid out, attrs 0x%x: %s", attrs, e.msg);
        }
        if (r == VX_OK) {
            size_t na = a.attr_count;
            CHECKF(a.node_count == b.node_count && a.root == b.root && a.root_attr == b.root_attr && na == b.attr_count &&
                       !memcmp(a.nodes, b.nodes, (size_t)a.node_count * 4) && (!a.rgba || !memcmp(a.rgba, b.rgba, na * 4)) &&
                       (!a.palette || !memcmp(a.palette, b.palette, na)) && (!a.normal || !memcmp(a.normal, b.normal, na * 4)) &&
                       (!a.material || !memcmp(a.material, b.material, na * 2)) &&
                       (!a.density || !memcmp(a.density, b.density, na * 4)) && sl.desc_dag == sa.desc_dag &&
                       sl.far_pointers == sa.far_pointers && sl.bytes == sa.bytes,
                   "laid out, attrs 0x%x: %u/%u records", attrs, a.attr_count, b.attr_count);
            vx_svo_model_free(NULL, &b);
        }
        pi.check_pool = true;
        r = vx__svo_build_interned(&bd, &in, &pi, &b, NULL, &e);
        CHECKF(r == VX_OK, "laid out, checked, attrs 0x%x: %s", attrs, e.msg);
        if (r == VX_OK) vx_svo_model_free(NULL, &b);
        a.nodes[a.node_count / 2] ^= 1u << 17; /* a pointer one off */
        CHECK(vx__svo_build_interned(&bd, &in, &pi, &b, NULL, &e) == VX_ERR_INVALID_ARG && strstr(e.msg, "blocks differ"));
        a.nodes[a.node_count / 2] ^= 1u << 17;
        pi.check_pool = false;
        pr.laid = NULL;
        pi.check_pool = true; /* the builder's own layout's runs are these */
        r = vx__svo_build_interned(&bd, &in, &pi, &b, NULL, &e);
        CHECKF(r == VX_OK, "runs checked, attrs 0x%x: %s", attrs, e.msg);
        if (r == VX_OK) vx_svo_model_free(NULL, &b);
        pi.check_pool = false;
        /* the last node's run moved one record on: refused (its records are not its children's) */
        size_t last = 0;
        for (size_t off2 = 0; off2 < p.n; off2 += 3 + (size_t)__builtin_popcount(p.w[off2] & 0xFFu)) last = off2;
        uint32_t keep = p.w[last + 2];
        p.w[last + 2] = keep + 1 < t.nrecs ? keep + 1 : 0;
        bool moved_same = true; /* unless the records there happen to be the same ones */
        unsigned nk = (unsigned)__builtin_popcount(p.w[last] & 0xFFu);
        for (unsigned k = 0; k < nk; k++)
            moved_same = moved_same && p.w[last + 2] + k < t.nrecs && t.recs[p.w[last + 2] + k] == t.recs[keep + k];
        if (!moved_same)
            CHECK(vx__svo_build_interned(&bd, &in, &pi, &b, NULL, &e) == VX_ERR_INVALID_ARG && strstr(e.msg, "run at record"));
        p.w[last + 2] = keep;
        tr_free(&t);
    }
    vx_svo_model_free(NULL, &a);
    free(uk), free(ui), free(p.w), free(p.tab);
}

/* far: the builder's far limit (vx_svo_testing.far_limit; 0: the default) */
static void interned_case(uint32_t attrs, uint32_t S, size_t nblocks, size_t nrand, unsigned nvals, bool shuffle,
                          bool thread, unsigned threads, uint32_t far) {
    const vx_svo_build_desc bd = {.testing.far_limit = far};
    size_t cap = nblocks * 64 + nrand;
    uint64_t* keys = (uint64_t*)calloc(cap, 8);
    vx__svo_rec* full = (vx__svo_rec*)calloc(cap, sizeof *full);
    vx__svo_rec* vals = (vx__svo_rec*)calloc(nvals, sizeof *vals);
    uint8_t* pal = (uint8_t*)calloc(cap, 1);
    uint32_t *rgba = (uint32_t*)calloc(cap, 4), *nrm = (uint32_t*)calloc(cap, 4), *ids = (uint32_t*)calloc(cap, 4);
    uint16_t* mat = (uint16_t*)calloc(cap, 2);
    float* den = (float*)calloc(cap, 4);
    vx__svo_rec* tab = (vx__svo_rec*)calloc(cap, sizeof *tab);
    REQUIRE(keys && full && vals && pal && rgba && nrm && ids && mat && den && tab);
    for (unsigned v = 0; v < nvals; v++) {
        float f[3] = {(float)(rnd() % 200) - 100.0f, (float)(rnd() % 200) - 100.0f, (float)(rnd() % 200) - 99.5f};
        if (attrs & VX_ATTR_PALETTE) vals[v].palette = (uint8_t)(1 + rnd() % 255);
        if (attrs & VX_ATTR_RGBA8) vals[v].rgba = (uint32_t)rnd();
        if (attrs & VX_ATTR_NORMAL) vals[v].normal = vx__oct_encode(f);
        if (attrs & VX_ATTR_MATERIAL) vals[v].material = (uint16_t)(rnd() % 4);
        if (attrs & VX_ATTR_DENSITY) vals[v].density = (float)(rnd() % 64) * 0.5f;
    }
    /* entries as (key, input order, value index), sorted by key then order
     * unless shuffle (duplicates keep their order: the later wins) */
    ient* ent = (ient*)calloc(cap, sizeof *ent);
    uint32_t* canon = (uint32_t*)calloc(nvals, 4);
    uint32_t* tid = (uint32_t*)calloc(nvals, 4);
    REQUIRE(ent && canon && tid);
    size_t n = 0;
    for (size_t b = 0; b < nblocks; b++) { /* uniform 4^3 blocks: collapse, and shared subtrees */
        uint32_t x0 = (uint32_t)(rnd() % (S / 4)) * 4, y0 = (uint32_t)(rnd() % (S / 4)) * 4, z0 = (uint32_t)(rnd() % (S / 4)) * 4;
        unsigned v = (unsigned)(rnd() % nvals);
        for (uint32_t q = 0; q < 64; q++, n++)
            ent[n] = (ient){vx_svo_morton(x0 + (q & 3), y0 + (q >> 2 & 3), z0 + (q >> 4)), n, v};
    }
    for (size_t i = 0; i < nrand; i++, n++)
        ent[n] = (ient){vx_svo_morton((uint32_t)(rnd() % S), (uint32_t)(rnd() % S), (uint32_t)(rnd() % S)), n,
                        (uint32_t)(rnd() % nvals)};
    if (!shuffle) qsort(ent, n, sizeof *ent, ient_cmp);
    /* equal values (random ones may repeat) share one tuple id, numbered by first use */
    uint32_t* ord = (uint32_t*)calloc(nvals, 4);
    REQUIRE(ord);
    for (unsigned v = 0; v < nvals; v++) ord[v] = v, tid[v] = UINT32_MAX;
    g_vals = vals;
    qsort(ord, nvals, 4, val_cmp);
    for (unsigned q = 0; q < nvals; q++)
        canon[ord[q]] = q && !memcmp(&vals[ord[q]], &vals[ord[q - 1]], sizeof *vals) ? canon[ord[q - 1]] : ord[q];
    free(ord);
    size_t ntab = 0;
    for (size_t i = 0; i < n; i++) {
        uint32_t v = canon[ent[i].v];
        keys[i] = ent[i].key;
        full[i] = vals[v];
        pal[i] = full[i].palette, rgba[i] = full[i].rgba, nrm[i] = full[i].normal, mat[i] = full[i].material;
        den[i] = full[i].density;
        if (tid[v] == UINT32_MAX) tab[ntab] = vals[v], tid[v] = (uint32_t)ntab++;
        ids[i] = tid[v];
    }
    free(ent), free(canon), free(tid);
    vx_svo_voxels in = {.size = {S, S, S}, .count = n, .keys = keys, .attrs = attrs};
    in.palette = (attrs & VX_ATTR_PALETTE) ? pal : NULL;
    in.rgba = (attrs & VX_ATTR_RGBA8) ? rgba : NULL;
    in.normal = (attrs & VX_ATTR_NORMAL) ? nrm : NULL;
    in.material = (attrs & VX_ATTR_MATERIAL) ? mat : NULL;
    in.density = (attrs & VX_ATTR_DENSITY) ? den : NULL;
    vx_svo_model a, b;
    vx_svo_build_stats sa, sb;
    vx_error e;
    REQUIRE(vx_svo_build_model(&bd, &in, &a, &sa, &e) == VX_OK);
    vx_svo_voxels bare = in;
    bare.palette = NULL, bare.rgba = NULL, bare.normal = NULL, bare.material = NULL, bare.density = NULL;
    vx__svo_interned pre = {ids, tab, ntab, thread, threads, NULL, false};
    vx_result r = vx__svo_build_interned(&bd, &bare, &pre, &b, &sb, &e);
    CHECKF(r == VX_OK, "attrs 0x%x: %s", attrs, e.msg);
    if (r == VX_OK) {
        CHECKF(a.node_count == b.node_count && a.root == b.root && a.root_attr == b.root_attr && a.attr_count == b.attr_count &&
                   !memcmp(a.nodes, b.nodes, (size_t)a.node_count * 4) && sa.desc_dag == sb.desc_dag && sa.voxels == sb.voxels,
               "attrs 0x%x: %u/%u words, %u/%u records", attrs, a.node_count, b.node_count, a.attr_count, b.attr_count);
        size_t na = a.attr_count;
        CHECK(!a.palette == !b.palette && (!a.palette || !memcmp(a.palette, b.palette, na)));
        CHECK(!a.rgba == !b.rgba && (!a.rgba || !memcmp(a.rgba, b.rgba, na * 4)));
        CHECK(!a.normal == !b.normal && (!a.normal || !memcmp(a.normal, b.normal, na * 4)));
        CHECK(!a.material == !b.material && (!a.material || !memcmp(a.material, b.material, na * 2)));
        CHECK(!a.density == !b.density && (!a.density || !memcmp(a.density, b.density, na * 4)));
        CHECK(sa.desc_collapsed < sa.desc_plain || nblocks == 0); /* the blocks did collapse */
        vx_svo_model_free(NULL, &b);
    }
    if (!shuffle && n) pool_case(attrs, S, keys, ids, n, tab, ntab, thread, far);
    /* rejected: an id out of range, two equal tuples */
    if (n && ntab) {
        uint32_t keep = ids[n / 2];
        ids[n / 2] = (uint32_t)ntab;
        CHECK(vx__svo_build_interned(&bd, &bare, &pre, &b, NULL, &e) == VX_ERR_INVALID_ARG && strstr(e.msg, "tuple"));
        ids[n / 2] = keep;
        tab[ntab] = tab[0];
        pre.count = ntab + 1;
        CHECK(vx__svo_build_interned(&bd, &bare, &pre, &b, NULL, &e) == VX_ERR_INVALID_ARG && strstr(e.msg, "equal"));
    }
    vx_svo_model_free(NULL, &a);
    free(keys), free(full), free(vals), free(pal), free(rgba), free(nrm), free(ids), free(mat), free(den), free(tab);
}

static void test_interned(void) {
    const uint32_t mixes[] = {VX_ATTR_RGBA8, VX_ATTR_RGBA8 | VX_ATTR_MATERIAL, VX_ATTR_RGBA8 | VX_ATTR_NORMAL | VX_ATTR_MATERIAL,
                              VX_ATTR_PALETTE, VX_ATTR_MATERIAL, VX_ATTR_NORMAL | VX_ATTR_DENSITY};
    for (size_t i = 0; i < sizeof mixes / sizeof *mixes; i++) {
        interned_case(mixes[i], 32, 12, 900, 3, false, false, 0, 0);   /* few tuples: much sharing */
        interned_case(mixes[i], 64, 6, 2500, 400, false, false, 0, 0); /* many tuples */
        interned_case(mixes[i], 16, 4, 300, 2, true, false, 0, 0);     /* unsorted, duplicates */
    }
    interned_case(VX_ATTR_RGBA8 | VX_ATTR_MATERIAL, 64, 20, 3000, 50, false, false, 0, 40);
    /* the layout on a second thread (from 2^16 entries): the same words */
    interned_case(VX_ATTR_RGBA8 | VX_ATTR_MATERIAL, 128, 300, 90000, 60, false, true, 0, 0);
    interned_case(VX_ATTR_RGBA8, 256, 100, 120000, 5000, false, true, 0, 0);
    interned_case(VX_ATTR_RGBA8 | VX_ATTR_NORMAL, 128, 400, 80000, 30, false, true, 0, 200);
    /* many tuples (from 2^18) interned on 4 threads, with and without the layout thread */
    interned_case(VX_ATTR_RGBA8 | VX_ATTR_MATERIAL, 256, 200, 600000, 1000000, false, true, 4, 0);
    interned_case(VX_ATTR_RGBA8 | VX_ATTR_NORMAL | VX_ATTR_MATERIAL, 256, 50, 500000, 900000, false, false, 3, 0);
    uint64_t k = 0;
    vx_svo_voxels in = {.size = {4, 4, 4}, .count = 1, .keys = &k, .attrs = VX_ATTR_RGBA8};
    vx__svo_interned pre = {NULL, NULL, 0, false, 0, NULL, false};
    vx_svo_model m;
    vx_error e;
    CHECK(vx__svo_build_interned(NULL, &in, &pre, &m, NULL, &e) == VX_ERR_INVALID_ARG);
}

/* Hand-made broken models: each must be rejected with a specific message. */
static void test_validate_rejects(void) {
    /* a valid base: depth 2, root with one non-leaf child (all-leaf, level 1) */
    uint32_t nodes[8];
    vx_svo_model m;
    memset(&m, 0, sizeof m);
    m.size[0] = m.size[1] = m.size[2] = 4;
    m.depth = 2;
    m.nodes = nodes;
    m.voxel_count = 3;
    /* word 0: child descriptor (level 1): valid 0x07, leaf 0x07, no block */
    nodes[0] = vx_svo_desc_make(0, false, 0x07, 0x07);
    /* word 1: root: valid 0x01, leaf 0; block at word 0 */
    nodes[1] = vx_svo_desc_make(1, false, 0x01, 0x00);
    m.node_count = 2;
    m.root = 1;
    vx_error e;
    REQUIRE(vx_svo_validate_model(&m, &e) == VX_OK);
    coll c = decode_all(&m);
    CHECK(c.n == 3);
    free(c.c);
    struct {
        uint32_t w, v;
        const char* msg;
    } cases[] = {
        {1, vx_svo_desc_make(2, false, 0x01, 0x00), "backwards"},      /* out of range */
        {1, vx_svo_desc_make(0, false, 0x01, 0x00), "backwards"},      /* p = 0 */
        {0, vx_svo_desc_make(0, false, 0x07, 0x0F), "subset"},         /* leaf not in valid */
        {0, vx_svo_desc_make(0, false, 0x00, 0x00), "no children"},    /* empty */
        {0, vx_svo_desc_make(0, false, 0x07, 0x03), "level 1"},        /* non-leaf at level 1 */
        {1, vx_svo_desc_make(1, true, 0x01, 0x00), "before"},          /* far slot to a later word */
        {0, vx_svo_desc_make(1, false, 0x07, 0x07), "pointer"},        /* block where none is needed */
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        uint32_t save = nodes[cases[i].w];
        nodes[cases[i].w] = cases[i].v;
        vx_result r = vx_svo_validate_model(&m, &e);
        CHECKF(r == VX_ERR_BAD_FORMAT && strstr(e.msg, cases[i].msg), "case %zu: %s", i, r ? e.msg : "accepted");
        nodes[cases[i].w] = save;
    }
    /* self-referencing block (cycle): root points at a block containing itself */
    nodes[0] = vx_svo_desc_make(0, false, 0x07, 0x07);
    nodes[1] = vx_svo_desc_make(1, false, 0x03, 0x00); /* two non-leaf children: words 0 and 1 */
    CHECK(vx_svo_validate_model(&m, &e) == VX_ERR_BAD_FORMAT && strstr(e.msg, "before"));
    /* forward far slot */
    nodes[0] = 5; /* far slot to word 5 */
    nodes[1] = vx_svo_desc_make(1, true, 0x01, 0x00);
    CHECK(vx_svo_validate_model(&m, &e) == VX_ERR_BAD_FORMAT);
    /* unreachable word */
    nodes[0] = vx_svo_desc_make(0, false, 0x07, 0x07);
    nodes[1] = vx_svo_desc_make(1, false, 0x01, 0x00);
    nodes[2] = 0;
    m.node_count = 3;
    CHECK(vx_svo_validate_model(&m, &e) == VX_ERR_BAD_FORMAT && strstr(e.msg, "reachable"));
    m.node_count = 2;
    m.voxel_count = 4;
    CHECK(vx_svo_validate_model(&m, &e) == VX_ERR_BAD_FORMAT && strstr(e.msg, "voxel_count"));
    m.voxel_count = 3;
    m.size[0] = 1; /* depth no longer matches */
    CHECK(vx_svo_validate_model(&m, &e) == VX_ERR_BAD_FORMAT);
    m.size[0] = 3; /* cells at x up to 2 fit; a leaf at x = 3 would not */
    nodes[0] = vx_svo_desc_make(0, false, 0x03, 0x03);
    m.voxel_count = 2;
    CHECK(vx_svo_validate_model(&m, &e) == VX_OK);
    nodes[1] = vx_svo_desc_make(1, false, 0x02, 0x00); /* moves the cells to x = 2..3 */
    CHECK(vx_svo_validate_model(&m, &e) == VX_ERR_BAD_FORMAT && strstr(e.msg, "outside"));
    /* attribute index beyond the records */
    uint8_t pal[4] = {1, 2, 3, 4};
    uint32_t an[3] = {2, vx_svo_desc_make(1, false, 0x03, 0x03), 0};
    vx_svo_model ma;
    memset(&ma, 0, sizeof ma);
    ma.size[0] = ma.size[1] = ma.size[2] = 2;
    ma.depth = 1;
    ma.nodes = an;
    ma.node_count = 2;
    ma.root = 1;
    ma.attrs = VX_ATTR_PALETTE;
    ma.palette = pal;
    ma.attr_count = 4;
    ma.voxel_count = 2;
    CHECK(vx_svo_validate_model(&ma, &e) == VX_OK);
    an[0] = 3;
    CHECK(vx_svo_validate_model(&ma, &e) == VX_ERR_BAD_FORMAT && strstr(e.msg, "attribute"));
    an[0] = 0xFFFFFFFFu;
    CHECK(vx_svo_validate_model(&ma, &e) == VX_ERR_BAD_FORMAT);
    ma.depth = 22;
    CHECK(vx_svo_validate_model(&ma, &e) == VX_ERR_BAD_FORMAT);
}

/* The grid cells of the n cells keys[] of an instance's model (floor(M (v + 1/2) + t)), added to the box
 * [mn, mx): the scene bounds by brute force. */
static void grow_bounds(const vx_svo_instance* in, const uint64_t* keys, size_t n, double mn[3], double mx[3]) {
    for (size_t k = 0; k < n; k++) {
        double p[3] = {vx__compact3(keys[k]) + 0.5, vx__compact3(keys[k] >> 1) + 0.5, vx__compact3(keys[k] >> 2) + 0.5};
        const double* M = in->xform;
        for (int r = 0; r < 3; r++) {
            double g = floor(M[4 * r] * p[0] + M[4 * r + 1] * p[1] + M[4 * r + 2] * p[2] + M[4 * r + 3]);
            if (g < mn[r]) mn[r] = g;
            if (g + 1 > mx[r]) mx[r] = g + 1;
        }
    }
}

static void test_bounds_and_materials(void) {
    uint64_t keys[3] = {vx_svo_morton(2, 3, 4), vx_svo_morton(5, 3, 1), vx_svo_morton(3, 6, 2)};
    vx_svo_voxels in = {.size = {8, 8, 8}, .count = 3, .keys = keys};
    vx_svo_scene s;
    vx_svo_scene_init(&s, NULL);
    s.models = (vx_svo_model*)calloc(1, sizeof *s.models);
    s.model_count = 1;
    vx_error e;
    REQUIRE(vx_svo_build_model(NULL, &in, &s.models[0], NULL, &e) == VX_OK);
    s.instances = (vx_svo_instance*)calloc(3, sizeof *s.instances);
    s.instance_count = 3;
    /* a 90-degree rotation about z plus translation, a plain shift, and a hidden one far away */
    double rot[12] = {0, -1, 0, 10, 1, 0, 0, -4, 0, 0, 1, 0.25};
    double sh[12] = {1, 0, 0, 100, 0, 1, 0, 0, 0, 0, 1, 0};
    double far[12] = {1, 0, 0, 1e6, 0, 1, 0, 0, 0, 0, 1, 0};
    memcpy(s.instances[0].xform, rot, sizeof rot);
    memcpy(s.instances[1].xform, sh, sizeof sh);
    memcpy(s.instances[2].xform, far, sizeof far);
    s.instances[2].flags = VX_SVO_INSTANCE_HIDDEN;
    for (int i = 0; i < 3; i++) s.instances[i].layer = UINT32_MAX;
    vx_svo_scene_update_bounds(&s);
    /* brute force: every cell's grid cell */
    double mn[3] = {1e300, 1e300, 1e300}, mx[3] = {-1e300, -1e300, -1e300};
    for (int i = 0; i < 2; i++) grow_bounds(&s.instances[i], keys, 3, mn, mx);
    for (int r = 0; r < 3; r++) CHECKF(s.bounds_min[r] == mn[r] && s.bounds_max[r] == mx[r], "axis %d: %g..%g vs %g..%g", r,
                                       s.bounds_min[r], s.bounds_max[r], mn[r], mx[r]);
    CHECK(vx_svo_validate_scene(&s, &e) == VX_OK);
    s.instances[1].model = 1;
    CHECK(vx_svo_validate_scene(&s, &e) == VX_ERR_BAD_FORMAT && strstr(e.msg, "model"));
    s.instances[1].model = 0;
    s.instances[1].xform[3] = NAN;
    CHECK(vx_svo_validate_scene(&s, &e) == VX_ERR_BAD_FORMAT && strstr(e.msg, "finite"));
    s.instances[1].xform[3] = 0;
    s.instances[1].layer = 0;
    CHECK(vx_svo_validate_scene(&s, &e) == VX_ERR_BAD_FORMAT && strstr(e.msg, "layer"));
    s.instances[1].layer = UINT32_MAX;
    static const char dict[] = "_type\0_emit\0_emit\0" "0.5\0_rough\0\0";
    vx_svo_material mat = {3, sizeof dict, (char*)dict};
    CHECK(strcmp(vx_svo_material_get(&mat, "_type"), "_emit") == 0);
    CHECK(strcmp(vx_svo_material_get(&mat, "_emit"), "0.5") == 0);
    CHECK(strcmp(vx_svo_material_get(&mat, "_rough"), "") == 0);
    CHECK(vx_svo_material_get(&mat, "_ior") == NULL);
    vx_svo_scene_free(&s);
    CHECK(s.models == NULL && s.model_count == 0);
}

/* The cells' box of models whose cells fill a random part of their extent:
 * single cells and whole aligned blocks of 2^l cells (collapsed leaves at
 * levels 1-3 where the build collapses). */
/* vx_svo_scene_update_bounds_ex: the desc reaches the bounds (threads, testing.parallel_always) and the
 * bounds never depend on it. Observed through the scene's allocator: the models' extents found on threads
 * take one scratch block (every model's extent), on the caller's thread two (the extents met so far and
 * their states). */
typedef struct count_alloc {
    int blocks;
} count_alloc;
static void* counted_alloc(void* user, size_t n) {
    ((count_alloc*)user)->blocks++;
    return malloc(n ? n : 1);
}
static void counted_free(void* user, void* p) {
    (void)user;
    free(p);
}

static void test_bounds_desc(void) {
    uint64_t ka[2] = {vx_svo_morton(1, 2, 3), vx_svo_morton(6, 0, 7)}, kb[1] = {vx_svo_morton(0, 5, 2)};
    vx_svo_voxels va = {.size = {8, 8, 8}, .count = 2, .keys = ka}, vb = {.size = {8, 8, 8}, .count = 1, .keys = kb};
    count_alloc ca = {0};
    const vx_allocator A = {counted_alloc, counted_free, &ca};
    vx_svo_scene s;
    vx_svo_scene_init(&s, &A);
    s.models = (vx_svo_model*)calloc(2, sizeof *s.models);
    s.model_count = 2;
    vx_error e;
    REQUIRE(vx_svo_build_model(NULL, &va, &s.models[0], NULL, &e) == VX_OK);
    REQUIRE(vx_svo_build_model(NULL, &vb, &s.models[1], NULL, &e) == VX_OK);
    s.instances = (vx_svo_instance*)calloc(3, sizeof *s.instances);
    s.instance_count = 3;
    double rot[12] = {0, -1, 0, 10, 1, 0, 0, -4, 0, 0, 1, 0.25}, sh[12] = {1, 0, 0, -20, 0, 1, 0, 3, 0, 0, 1, 0};
    memcpy(s.instances[0].xform, rot, sizeof rot);
    memcpy(s.instances[1].xform, sh, sizeof sh);
    memcpy(s.instances[2].xform, sh, sizeof sh);
    s.instances[1].model = 1;
    s.instances[2].xform[3] = 500, s.instances[2].flags = VX_SVO_INSTANCE_HIDDEN;
    for (int i = 0; i < 3; i++) s.instances[i].layer = UINT32_MAX;
    /* brute force: every drawn cell's grid cell */
    double mn[3] = {1e300, 1e300, 1e300}, mx[3] = {-1e300, -1e300, -1e300};
    grow_bounds(&s.instances[0], ka, 2, mn, mx);
    grow_bounds(&s.instances[1], kb, 1, mn, mx);
    const struct {
        const char* what;
        vx_svo_bounds_desc d;
        bool null;
        int blocks;
    } cases[] = {
        {"NULL desc", {0}, true, 2},
        {"zeroed desc (two models, few words: one thread)", {0}, false, 2},
        {"parallel_always, 2 threads", {.threads = 2, .testing.parallel_always = true}, false, 1},
        {"parallel_always, one per CPU", {.testing.parallel_always = true}, false, vx_cpu_count(64) > 1 ? 1 : 2},
        {"parallel_always, 1 thread", {.threads = 1, .testing.parallel_always = true}, false, 2},
    };
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        memset(s.bounds_min, 0, sizeof s.bounds_min), memset(s.bounds_max, 0, sizeof s.bounds_max);
        ca.blocks = 0;
        vx_svo_scene_update_bounds_ex(cases[c].null ? NULL : &cases[c].d, &s);
        CHECKF(ca.blocks == cases[c].blocks, "%s: %d scratch blocks, expected %d", cases[c].what, ca.blocks,
               cases[c].blocks);
        for (int r = 0; r < 3; r++)
            CHECKF(s.bounds_min[r] == mn[r] && s.bounds_max[r] == mx[r], "%s, axis %d: %g..%g vs %g..%g",
                   cases[c].what, r, s.bounds_min[r], s.bounds_max[r], mn[r], mx[r]);
    }
    ca.blocks = 0;
    vx_svo_scene_update_bounds(&s); /* the plain call: the defaults */
    CHECK(ca.blocks == 2 && s.bounds_min[0] == mn[0] && s.bounds_max[2] == mx[2]);
    s.alloc = NULL;
    vx_svo_scene_free(&s);
}

static void test_cell_box(void) {
    for (int trial = 0; trial < 300; trial++) {
        uint32_t size[3], a[3], b[3];
        for (int k = 0; k < 3; k++) {
            size[k] = 1 + (uint32_t)(rnd() % 90);
            a[k] = (uint32_t)(rnd() % size[k]);
            b[k] = a[k] + 1 + (uint32_t)(rnd() % (size[k] - a[k]));
        }
        size_t n = trial % 7 == 0 ? 0 : 1 + rnd() % 300, cnt = 0, cap = n * 512 + 1;
        uint64_t* keys = (uint64_t*)malloc(cap * 8);
        for (size_t i = 0; i < n; i++) {
            uint32_t v[3], l = rnd() % 5 == 0 ? (uint32_t)(1 + rnd() % 3) : 0, w = 1u << l;
            bool fits = true;
            for (int k = 0; k < 3; k++) {
                v[k] = (a[k] + (uint32_t)(rnd() % (b[k] - a[k]))) & ~(w - 1u); /* aligned to the block */
                fits = fits && v[k] >= a[k] && v[k] + w <= b[k];
            }
            if (!fits) w = 1, v[0] = a[0] + (uint32_t)(rnd() % (b[0] - a[0])), v[1] = a[1], v[2] = b[2] - 1;
            for (uint32_t z = 0; z < w; z++)
                for (uint32_t y = 0; y < w; y++)
                    for (uint32_t x = 0; x < w; x++) keys[cnt++] = vx_svo_morton(v[0] + x, v[1] + y, v[2] + z);
        }
        vx_svo_voxels in = {.size = {size[0], size[1], size[2]}, .count = cnt, .keys = keys};
        vx_svo_build_desc d = {.no_collapse = trial & 1, .no_dag = (trial >> 1) & 1};
        vx_svo_model m;
        vx_error e;
        REQUIRE(vx_svo_build_model(&d, &in, &m, NULL, &e) == VX_OK);
        check_cell_box(&m);
        if (cnt) {
            uint32_t lo[3], hi[3];
            vx_svo_model_cell_box(&m, lo, hi);
            for (int k = 0; k < 3; k++) CHECK(lo[k] >= a[k] && hi[k] <= b[k] && lo[k] < hi[k]);
        }
        vx_svo_model_free(NULL, &m);
        free(keys);
    }
}

int main(void) {
    RUN(test_morton_helpers);
    RUN(test_empty);
    RUN(test_one_voxel);
    RUN(test_full_cube);
    RUN(test_checkerboard);
    RUN(test_random_sparse);
    RUN(test_cell_box);
    RUN(test_tiles);
    RUN(test_bad_input);
    RUN(test_far_forced);
    RUN(test_far_real);
    RUN(test_repeated);
    RUN(test_lod);
    RUN(test_decode_stop);
    RUN(test_other_channels);
    RUN(test_interned);
    RUN(test_validate_rejects);
    RUN(test_bounds_and_materials);
    RUN(test_bounds_desc);
    return vx_test_finish();
}
