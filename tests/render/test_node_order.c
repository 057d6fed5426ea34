/* tests/render/test_node_order.c - render/node_order.c (issue 21): a model's
 * node words in treelet order are the same octree (every cell and its
 * attribute record decode the same), in the format (pointers backwards, far
 * slots where a pointer does not fit), DAG-shared blocks placed once, a
 * child block nearer its parent than in the file; bad words are refused, never
 * read out of bounds. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "render/node_order.h"
#include "svo/svo_internal.h" /* vx__svo_far_limit */
#include "tests/render/scenes.h"
#include "tests/test.h"

typedef struct cells {
    uint32_t* v; /* x, y, z, attr per cell */
    size_t n, cap;
} cells;

static bool add_cell(void* user, uint32_t x, uint32_t y, uint32_t z, uint32_t attr) {
    cells* c = user;
    if (c->n == c->cap) {
        size_t cap = c->cap ? 2 * c->cap : 1024;
        uint32_t* v = realloc(c->v, cap * 16);
        if (!v) return false;
        c->v = v, c->cap = cap;
    }
    uint32_t* p = c->v + 4 * c->n++;
    p[0] = x, p[1] = y, p[2] = z, p[3] = attr;
    return true;
}

/* The far slots, inner descriptors and blocks of the words from root:
 * checks every pointer goes backwards and stays in range; counts the
 * descriptors whose child block starts within `near` words before them
 * (DAG blocks once per path). */
typedef struct walk {
    const uint32_t* w;
    uint32_t n;
    bool attrs, bad;
    uint64_t descs, near_count, far_count;
    uint64_t edges, line, sector; /* parent to child descriptor steps; in one 128-byte line, one 32-byte sector */
    uint32_t near;
} walk;

static void walk_desc(walk* k, uint32_t i, int depth) {
    if (k->bad || depth > 30) return;
    uint32_t d = k->w[i], valid = vx_svo_desc_valid(d), leaf = vx_svo_desc_leaf(d);
    uint32_t inner = valid & ~leaf, ni = (uint32_t)__builtin_popcount(inner);
    uint32_t len = ni + (k->attrs && valid ? 1u : 0u);
    if (!len) return;
    uint32_t p = vx_svo_desc_ptr(d);
    if (p == 0 || p > i) {
        k->bad = true;
        return;
    }
    uint32_t b = i - p;
    if (vx_svo_desc_far(d)) b = k->w[b], k->far_count++;
    if (b >= i || i - b < len) {
        k->bad = true;
        return;
    }
    k->descs++;
    k->near_count += i - b <= k->near;
    for (uint32_t c = 0; c < ni; c++) {
        k->edges++;
        k->line += i / 32 == (b + c) / 32;
        k->sector += i / 8 == (b + c) / 8;
        walk_desc(k, b + c, depth + 1);
    }
}

static walk walk_model(const uint32_t* w, uint32_t n, uint32_t root, bool attrs, uint32_t near) {
    walk k = {.w = w, .n = n, .attrs = attrs, .near = near};
    walk_desc(&k, root, 0);
    return k;
}

/* A model whose cells repeat with period 8 (and their colours with them):
 * most subtrees below the 8^3 level are shared (a DAG). */
static vx_result periodic_model(vx_svo_model* m, uint32_t side) {
    size_t cap = (size_t)side * side * side, n = 0;
    uint32_t* xyz = malloc(cap * 12);
    uint8_t* pal = malloc(cap);
    if (!xyz || !pal) return VX_ERR_NOMEM;
    for (uint32_t z = 0; z < side; z++)
        for (uint32_t y = 0; y < side; y++)
            for (uint32_t x = 0; x < side; x++) {
                uint32_t a = x & 7, b = y & 7, c = z & 7;
                /* a few distinct tiles: the tile's pattern depends on the tile's position mod 2 */
                uint32_t t = ((x >> 3) ^ (y >> 3) ^ (z >> 3)) & 1;
                if ((a * 3 + b * 5 + c * 7 + t) % 4 == 0 || (x < side / 3 && y < side / 2)) {
                    xyz[3 * n] = x, xyz[3 * n + 1] = y, xyz[3 * n + 2] = z;
                    pal[n++] = (uint8_t)(1 + (a + 2 * t) % 9);
                }
            }
    uint32_t size[3] = {side, side, side};
    vx_result r = ts_model(m, size, xyz, pal, n);
    free(xyz);
    free(pal);
    return r;
}

/* The model with the words in node order (the same record arrays). */
static vx_svo_model relaid(const vx_svo_model* m, uint32_t* words, uint32_t count, uint32_t root) {
    vx_svo_model r = *m;
    r.nodes = words, r.node_count = count, r.root = root;
    return r;
}

static void check_orders(const char* name, const vx_svo_model* m) {
    cells ref = {0};
    vx_error err = {0};
    REQUIRE(vx_svo_decode_model(m, add_cell, &ref, &err) == VX_OK);
    walk wf = walk_model(m->nodes, m->node_count, m->root, m->attrs != 0, 32);
    CHECKF(!wf.bad, "%s: the file's words are not the format", name);
    static const uint32_t sizes[] = {1, 8, 32, 128, 4096, 8, 32};
    printf("%-24s %8s %6s %6s %6s\n", name, "words", "near", "line", "sector");
    printf("%-24s %8u %5.1f%% %5.1f%% %5.1f%%\n", "  file", m->node_count, 100.0 * wf.near_count / (wf.descs ? wf.descs : 1),
           100.0 * wf.line / (wf.edges ? wf.edges : 1), 100.0 * wf.sector / (wf.edges ? wf.edges : 1));
    for (size_t si = 0; si < sizeof sizes / sizeof sizes[0]; si++)
        for (int lim = 0; lim < 2; lim++) {
            vx__node_order_desc od = {.words = sizes[si], .limit = lim ? 16 : 0, .align = si >= 5 ? sizes[si] : 0};
            uint32_t *w = NULL, count = 0, root = 0;
            bool ok = vx__node_order(m, &od, NULL, &w, &count, &root);
            CHECKF(ok, "%s: treelet %u limit %u: not reordered", name, od.words, od.limit);
            if (!ok) continue;
            vx_svo_model r = relaid(m, w, count, root);
            cells got = {0};
            REQUIRE(vx_svo_decode_model(&r, add_cell, &got, &err) == VX_OK);
            CHECKF(got.n == ref.n && !memcmp(got.v, ref.v, ref.n * 16),
                   "%s: treelet %u limit %u: %zu cells decoded against %zu, or other cells or records", name, od.words,
                   od.limit, got.n, ref.n);
            walk wr = walk_model(w, count, root, m->attrs != 0, 32);
            CHECKF(!wr.bad, "%s: treelet %u: a pointer out of the format", name, od.words);
            CHECKF(wr.descs == wf.descs, "%s: treelet %u: %llu descriptors with blocks against %llu", name, od.words,
                   (unsigned long long)wr.descs, (unsigned long long)wf.descs);
            /* no word twice (DAG blocks once); where no pointer needs a far
             * slot, no more words than the file */
            if (!lim && !wr.far_count && !od.align) CHECKF(count <= m->node_count, "%s: %u words against %u", name, count, m->node_count);
            if (lim) CHECKF(m->node_count < 64 || wr.far_count > 0, "%s: limit 16 and no far slot", name);
            /* the point of it: a block near its parent (within a 128-byte
             * line's 32 words) at least as often as in the file */
            if (!lim) {
                char lb[32];
                snprintf(lb, sizeof lb, "  treelet %u%s", od.words, od.align ? " aligned" : "");
                printf("%-24s %8u %5.1f%% %5.1f%% %5.1f%%\n", lb, count, 100.0 * wr.near_count / (wr.descs ? wr.descs : 1),
                       100.0 * wr.line / (wr.edges ? wr.edges : 1), 100.0 * wr.sector / (wr.edges ? wr.edges : 1));
            }
            free(got.v);
            free(w);
        }
    free(ref.v);
}

static void test_random_models(void) {
    static const uint32_t pct[] = {3, 35, 90};
    for (int i = 0; i < 3; i++) {
        vx_svo_model m;
        REQUIRE(ts_random_model(&m, 40, 33, 47, pct[i], 100 + i) == VX_OK);
        char nm[64];
        snprintf(nm, sizeof nm, "random %u%%", pct[i]);
        check_orders(nm, &m);
        vx_svo_model_free(NULL, &m);
    }
}

static void test_dag_model(void) {
    vx_svo_model m;
    REQUIRE(periodic_model(&m, 64) == VX_OK);
    check_orders("periodic (DAG)", &m);
    vx_svo_model_free(NULL, &m);
}

/* Geometry only (no attribute words: leaf-only nodes have no block). */
static void test_geometry_only(void) {
    vx_svo_model m;
    REQUIRE(ts_random_model(&m, 30, 30, 30, 20, 7) == VX_OK);
    /* the same cells without attributes */
    cells c = {0};
    vx_error err = {0};
    REQUIRE(vx_svo_decode_model(&m, add_cell, &c, &err) == VX_OK);
    uint64_t* keys = malloc((c.n ? c.n : 1) * sizeof *keys);
    REQUIRE(keys);
    for (size_t i = 0; i < c.n; i++) keys[i] = vx_svo_morton(c.v[4 * i], c.v[4 * i + 1], c.v[4 * i + 2]);
    vx_svo_voxels v = {.size = {30, 30, 30}, .count = c.n, .keys = keys};
    vx_svo_model g;
    REQUIRE(vx_svo_build_model(NULL, &v, &g, NULL, &err) == VX_OK);
    check_orders("geometry only", &g);
    vx_svo_model_free(NULL, &g);
    free(keys);
    free(c.v);
    vx_svo_model_free(NULL, &m);
}

/* A model built with far pointers throughout (the builder's limit at 3). */
static void test_file_far_pointers(void) {
    vx__svo_far_limit = 3;
    vx_svo_model m;
    vx_result r = ts_random_model(&m, 20, 17, 23, 35, 777);
    vx__svo_far_limit = VX__SVO_PTR_MAX;
    REQUIRE(r == VX_OK);
    check_orders("file with far pointers", &m);
    vx_svo_model_free(NULL, &m);
}

/* Words that are not the format: refused (false, *out NULL), never a crash
 * or an out-of-bounds read (ASan); random words too. */
static void test_bad_words(void) {
    vx_svo_model m;
    REQUIRE(ts_random_model(&m, 16, 16, 16, 30, 5) == VX_OK);
    uint32_t* keep = m.nodes;
    uint32_t* w = malloc((size_t)m.node_count * 4);
    REQUIRE(w);
    uint32_t *out = NULL, count = 0, root = 0;
    /* the root's pointer forward / to itself / a far slot pointing past the end */
    uint32_t d = keep[m.root];
    uint32_t cases[3] = {vx_svo_desc_make(0, false, vx_svo_desc_valid(d), vx_svo_desc_leaf(d)),
                         vx_svo_desc_make(m.root + 1 > 0x7FFF ? 0x7FFF : m.root + 1, false, vx_svo_desc_valid(d),
                                          vx_svo_desc_leaf(d)),
                         vx_svo_desc_make(1, true, vx_svo_desc_valid(d), vx_svo_desc_leaf(d))};
    for (int c = 0; c < 3; c++) {
        memcpy(w, keep, (size_t)m.node_count * 4);
        w[m.root] = cases[c];
        if (c == 2) w[m.root - 1] = m.root + 5;
        m.nodes = w;
        CHECKF(!vx__node_order(&m, NULL, NULL, &out, &count, &root) && !out, "bad root pointer %d accepted", c);
    }
    /* random words: refused or a tree that walks in bounds */
    uint32_t seed = 12345;
    int accepted = 0;
    for (int t = 0; t < 300; t++) {
        for (uint32_t i = 0; i < m.node_count; i++) {
            uint32_t x = ts_rng(&seed);
            /* mostly near pointers so that some trees go deep */
            w[i] = t % 3 ? vx_svo_desc_make(1 + x % 24, x & 0x10000u, x >> 8, x >> 24) : x;
        }
        m.nodes = w;
        m.root = ts_rng(&seed) % m.node_count;
        bool ok = vx__node_order(&m, &(vx__node_order_desc){.words = 1 + t % 40}, NULL, &out, &count, &root);
        if (ok) {
            accepted++;
            walk k = walk_model(out, count, root, m.attrs != 0, 32);
            CHECKF(!k.bad, "random words %d: the order's words break the format", t);
            free(out);
            out = NULL;
        } else {
            CHECK(out == NULL);
        }
    }
    printf("random words: %d of 300 accepted\n", accepted);
    /* no descriptor: an empty or leaf root, no words */
    m.nodes = keep;
    uint32_t r0 = m.root;
    m.root = VX_SVO_ROOT_EMPTY;
    CHECK(!vx__node_order(&m, NULL, NULL, &out, &count, &root) && !out);
    m.root = VX_SVO_ROOT_LEAF;
    CHECK(!vx__node_order(&m, NULL, NULL, &out, &count, &root) && !out);
    m.root = r0;
    free(w);
    vx_svo_model_free(NULL, &m);
}

int main(void) {
    (void)ts_scene, (void)ts_inst; /* scenes.h's scene helpers: this test needs models only */
    RUN(test_random_models);
    RUN(test_dag_model);
    RUN(test_geometry_only);
    RUN(test_file_far_pointers);
    RUN(test_bad_words);
    return vx_test_finish();
}
