/* tests/render/test_grid.c - the grid walk's layout (render/grid.h) read
 * back by a reader written here from the header's description, against the
 * octree (vx_svo_model_cell_set) for every cell of small models and for
 * sampled and set cells of large ones; every empty entry's distance checked
 * by brute force (no occupied entry nearer, one at that distance); the root
 * level rule against the shader's (grid_walk.glsl grid_top). CPU only. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tests/test.h"
#include "tests/render/scenes.h"
#include "render/grid.h"

/* The word address of the brick that holds cell (x, y, z) in the grid of w (word i at address base + i, its
 * root at word root); VX__GRID_EMPTY where none does. */
static uint32_t grid_brick(const uint32_t* w, uint64_t base, uint64_t root, uint32_t depth, uint32_t top, uint32_t x,
                           uint32_t y, uint32_t z) {
    uint32_t R = 1u << (depth - 3 * top);
    uint32_t sh = 3 * top;
    uint32_t e = w[root + ((uint64_t)(z >> sh) * R + (y >> sh)) * R + (x >> sh)];
    for (uint32_t lv = top; lv > 1; lv--) {
        if (e >= VX__GRID_EMPTY) return VX__GRID_EMPTY;
        sh -= 3;
        e = w[e - base + (((x >> sh) & 7) | ((y >> sh) & 7) << 3 | ((z >> sh) & 7) << 6)];
    }
    return e >= VX__GRID_EMPTY ? VX__GRID_EMPTY : e;
}

/* Whether cell (x, y, z) is set in the grid at word `base` of w (root at base). */
static bool grid_cell(const uint32_t* w, uint64_t base, uint64_t root, uint32_t depth, uint32_t top, uint32_t x,
                      uint32_t y, uint32_t z) {
    uint32_t e = grid_brick(w, base, root, depth, top, x, y, z);
    if (e >= VX__GRID_EMPTY) return false;
    uint32_t i = (x & 7) | (y & 7) << 3 | (z & 7) << 6;
    return w[e - base + (i >> 5)] >> (i & 31) & 1;
}

/* A hit cell's attribute record from its brick's record word rw, as grid_walk.glsl's model_cell_leaf_brick
 * finds it (render/grid.h: bit 31 a uniform leaf's record, else the node whose cube is the brick, from which
 * the last min(depth, 3) levels are descended as svo.h describes the nodes); UINT32_MAX where the cell is
 * empty there. */
static uint32_t record_from_brick(const vx_svo_model* m, uint32_t rw, uint32_t x, uint32_t y, uint32_t z) {
    if (rw & VX__GRID_RECORD_LEAF) return rw & ~VX__GRID_RECORD_LEAF;
    uint32_t i = rw;
    for (uint32_t l = (m->depth < 3 ? m->depth : 3); l-- > 0;) {
        uint32_t d = m->nodes[i], o = ((x >> l) & 1u) | ((y >> l) & 1u) << 1 | ((z >> l) & 1u) << 2;
        uint32_t valid = vx_svo_desc_valid(d), leaf = vx_svo_desc_leaf(d), below = (1u << o) - 1u;
        if (!(valid >> o & 1u)) return UINT32_MAX;
        uint32_t block = vx_svo_desc_far(d) ? m->nodes[i - vx_svo_desc_ptr(d)] : i - vx_svo_desc_ptr(d);
        if (leaf >> o & 1u)
            return m->nodes[block + (uint32_t)__builtin_popcount(valid & ~leaf)] + (uint32_t)__builtin_popcount(valid & below);
        i = block + (uint32_t)__builtin_popcount(valid & ~leaf & below);
    }
    return UINT32_MAX;
}

/* Every set cell's record (vx_svo_decode_model's attribute) against the one found from its brick's record
 * word in grid w (its record key rec: brick address e has its word at rec + (e >> 4)). */
typedef struct rec_check {
    const vx_svo_model* m;
    const uint32_t* w;
    uint64_t base, root;
    uint32_t depth, top, rec;
    size_t cells, wrong;
    const char* name;
    uint32_t org[3]; /* the grid's cube's corner (vx__grid_cube; 0: the model's) */
} rec_check;

static bool rec_cell(void* user, uint32_t x, uint32_t y, uint32_t z, uint32_t attr) {
    rec_check* c = user;
    uint32_t e = grid_brick(c->w, c->base, c->root, c->depth, c->top, x - c->org[0], y - c->org[1], z - c->org[2]);
    uint32_t got = UINT32_MAX;
    if (e < VX__GRID_EMPTY) got = record_from_brick(c->m, c->w[c->rec + (e >> 4) - c->base], x, y, z);
    c->cells++;
    if (got != attr && c->wrong++ < 4)
        fprintf(stderr, "  %s: cell %u,%u,%u record %u from its brick, %u decoded\n", c->name, x, y, z, got, attr);
    return true;
}

/* The occupied entries of an n^3 grid (x fastest) as a summed-volume table:
 * sv[(z * (n + 1) + y) * (n + 1) + x] counts those below (x, y, z). */
static uint32_t* summed_volume(const uint32_t* g, uint32_t n) {
    uint64_t m = n + 1;
    uint32_t* sv = calloc(m * m * m, 4);
    CHECK(sv != NULL);
    for (uint64_t z = 1; sv && z <= n; z++)
        for (uint64_t y = 1; y <= n; y++)
            for (uint64_t x = 1; x <= n; x++)
                sv[(z * m + y) * m + x] = (g[((z - 1) * n + y - 1) * n + x - 1] < VX__GRID_EMPTY) +
                                          sv[(z * m + y) * m + x - 1] + sv[(z * m + y - 1) * m + x] +
                                          sv[((z - 1) * m + y) * m + x] - sv[(z * m + y - 1) * m + x - 1] -
                                          sv[((z - 1) * m + y) * m + x - 1] - sv[((z - 1) * m + y - 1) * m + x] +
                                          sv[((z - 1) * m + y - 1) * m + x - 1];
    return sv;
}

/* The occupied entries in the box [lo, hi] (inclusive, clipped to the grid) */
static uint32_t occupied(const uint32_t* sv, uint32_t n, const int64_t lo[3], const int64_t hi[3]) {
    int64_t a[3], b[3], m = n + 1;
    for (int k = 0; k < 3; k++) {
        a[k] = lo[k] < 0 ? 0 : lo[k], b[k] = hi[k] >= (int64_t)n ? (int64_t)n - 1 : hi[k];
        if (a[k] > b[k]) return 0;
        b[k]++;
    }
#define SV(x, y, z) (int64_t) sv[((z)*m + (y)) * m + (x)]
    return (uint32_t)(SV(b[0], b[1], b[2]) - SV(a[0], b[1], b[2]) - SV(b[0], a[1], b[2]) - SV(b[0], b[1], a[2]) +
                      SV(a[0], a[1], b[2]) + SV(a[0], b[1], a[2]) + SV(b[0], a[1], a[2]) - SV(a[0], a[1], a[2]));
#undef SV
}

/* Every empty entry of an n^3 grid g (x fastest): no occupied entry within
 * Chebyshev distance d - 1, and one at d exactly (where any is occupied and
 * d is below the cap); and per octant o (bit a: toward -a) its extent e_o
 * (render/grid.h VX__GRID_OCT_SHIFT): where octants, the empty cube from the
 * entry toward o of side d + e_o is empty and, below the cap of 7, the one
 * of side d + e_o + 1 is not (outside the grid counts as empty); else 0.
 * Counted by a summed-volume table, not by the build's search and recurrence.
 * Returns the entries that fail. */
static size_t check_distances(const uint32_t* g, uint32_t n, bool octants) {
    size_t bad = 0;
    uint32_t* sv = summed_volume(g, n);
    if (!sv) return 1;
    bool any = sv[(uint64_t)(n + 1) * (n + 1) * (n + 1) - 1] > 0;
    for (uint32_t z = 0; z < n; z++)
        for (uint32_t y = 0; y < n; y++)
            for (uint32_t x = 0; x < n; x++) {
                uint32_t e = g[((uint64_t)z * n + y) * n + x];
                if (e < VX__GRID_EMPTY) continue;
                int64_t p[3] = {x, y, z}, lo[3], hi[3];
                uint32_t d = e & VX__GRID_DIST_MASK;
                bool ok = d >= 1;
                /* radius d - 1 empty; radius d holds one (below the cap) */
                for (int r = 0; r < 2 && ok; r++) {
                    int64_t rad = (int64_t)d - 1 + r;
                    for (int k = 0; k < 3; k++) lo[k] = p[k] - rad, hi[k] = p[k] + rad;
                    uint32_t c = occupied(sv, n, lo, hi);
                    ok = r == 0 ? c == 0 : (!any ? d == VX__GRID_DIST_MASK : (c > 0 || d == VX__GRID_DIST_MASK));
                }
                for (int o = 0; o < 8 && ok; o++) {
                    uint32_t eo = e >> (VX__GRID_OCT_SHIFT + 3 * o) & 7;
                    if (!octants) {
                        ok = eo == 0;
                        continue;
                    }
                    for (int r = 0; r < 2 && ok; r++) {
                        if (r == 1 && eo == 7) break;
                        int64_t side = (int64_t)d + eo + r;
                        for (int k = 0; k < 3; k++) {
                            bool negk = (o >> k) & 1;
                            lo[k] = negk ? p[k] - side + 1 : p[k], hi[k] = negk ? p[k] : p[k] + side - 1;
                        }
                        /* (a cube of side + 1 empty in the grid would have made the extent larger: outside
                         * the grid counts as empty, so its extent is 7 there) */
                        uint32_t c = occupied(sv, n, lo, hi);
                        ok = r == 0 ? c == 0 : c > 0;
                    }
                    if (!ok) fprintf(stderr, "  entry %u,%u,%u of %u^3: octant %d extent %u (distance %u)\n", x, y, z, n, o, eo, d);
                }
                if (!ok) {
                    if (bad < 4) fprintf(stderr, "  entry %u,%u,%u of %u^3: distance %u\n", x, y, z, n, d);
                    bad++;
                }
            }
    free(sv);
    return bad;
}

/* The grid of m at base 1000 (addresses offset, as in a buffer after other grids) read back. */
static void check_model(const char* name, const vx_svo_model* m, bool every_cell) {
    vx__grid_words out = {0};
    CHECK(vx__grid_words_grow(NULL, &out, 7));
    out.n = 7; /* words before the grid: its addresses count from the buffer's start */
    vx_error err = {0};
    uint32_t top, rec;
    vx_result r = vx__grid_model(NULL, m, NULL, 993, NULL, &out, &top, &rec, &err);
    CHECKF(r == VX_OK, "%s: %s", name, err.msg);
    if (r) return;
    /* the bricks' record words: a model with attributes has them, every set cell's record found from them */
    CHECKF((rec != 0) == (m->attrs != 0), "%s: record key %u with attributes %u", name, rec, m->attrs);
    size_t rec_cells = 0;
    if (rec) {
        rec_check rc = {m, out.w, 993, 7, m->depth < 3 ? 3 : m->depth, top, rec, 0, 0, name, {0, 0, 0}};
        CHECK(vx_svo_decode_model(m, rec_cell, &rc, &err) == VX_OK);
        CHECKF(rc.wrong == 0 && rc.cells > 0, "%s: %zu of %zu cells' records differ from the decoded", name, rc.wrong,
               rc.cells);
        rec_cells = rc.cells;
    }
    uint32_t depth = m->depth < 3 ? 3 : m->depth;
    CHECKF(top == vx__grid_top(depth, 0), "%s: root level %u", name, top);
    uint32_t R = 1u << (depth - 3 * top);
    const uint32_t* w = out.w;
    uint64_t base = 993, root = 7;
    size_t wrong = 0, cells = 0;
    uint32_t side = 1u << depth;
    if (every_cell) {
        for (uint32_t z = 0; z < side; z++)
            for (uint32_t y = 0; y < side; y++)
                for (uint32_t x = 0; x < side; x++) {
                    bool a = grid_cell(w, base, root, depth, top, x, y, z), b = vx_svo_model_cell_set(m, x, y, z);
                    cells += b;
                    if (a != b && wrong++ < 4) fprintf(stderr, "  %s: cell %u,%u,%u grid %d octree %d\n", name, x, y, z, a, b);
                }
    } else {
        uint32_t seed = 99;
        for (int i = 0; i < 200000; i++) {
            uint32_t x = ts_rng(&seed) % side, y = ts_rng(&seed) % side, z = ts_rng(&seed) % side;
            bool a = grid_cell(w, base, root, depth, top, x, y, z), b = vx_svo_model_cell_set(m, x, y, z);
            cells += b;
            if (a != b && wrong++ < 4) fprintf(stderr, "  %s: cell %u,%u,%u grid %d octree %d\n", name, x, y, z, a, b);
        }
    }
    CHECKF(wrong == 0, "%s: %zu cells differ", name, wrong);
    /* the distances and the octant extents (made where the root is wide: render/grid.h), the root and every node */
    bool wide = depth - 3 * top >= VX__GRID_OCT_ROOT_LOG;
    CHECKF(check_distances(w + root, R, wide) == 0, "%s: root distances", name);
    size_t nodes = 0, bad_nodes = 0;
    for (uint64_t i = 0; i < (uint64_t)R * R * R; i++) {
        uint32_t e = w[root + i];
        if (e >= VX__GRID_EMPTY || top < 2) continue;
        nodes++;
        bad_nodes += check_distances(w + (e - base), 8, wide) != 0;
    }
    CHECKF(bad_nodes == 0, "%s: %zu of %zu level-%u nodes with wrong distances", name, bad_nodes, nodes, top);
    printf("%-28s depth %2u top %u root %3u^3: %zu words, %zu cells checked set%s, %zu records from their bricks\n",
           name, m->depth, top, R, out.n, cells, every_cell ? " (every cell)" : " (sampled)", rec_cells);
    vx_free(NULL, out.w);
}

static void test_models(void) {
    static const uint32_t sizes[][4] = {{1, 1, 1, 100}, {3, 2, 4, 60}, {8, 8, 8, 30}, {12, 12, 12, 35},
                                        {17, 5, 9, 20}, {40, 3, 70, 3}, {64, 64, 64, 1}};
    for (size_t i = 0; i < sizeof sizes / sizeof sizes[0]; i++) {
        vx_svo_model m;
        CHECK(ts_random_model(&m, sizes[i][0], sizes[i][1], sizes[i][2], sizes[i][3], 7 + (uint32_t)i) == VX_OK);
        char nm[64];
        snprintf(nm, sizeof nm, "random %ux%ux%u %u%%", sizes[i][0], sizes[i][1], sizes[i][2], sizes[i][3]);
        check_model(nm, &m, true);
        vx_svo_model_free(NULL, &m);
    }
}

/* Root level 2 and 3 (depth 11 and 14): a few cells far apart and a solid
 * block (a uniform leaf: full bricks without cells), sampled plus every set
 * cell's neighbourhood through the random samples' misses. */
static void test_deep_levels(void) {
    /* (and 9 and 12: roots of 64 at levels 1 and 2, which hold the octant extents) */
    static const uint32_t depths[] = {9, 11, 12, 14};
    for (size_t di = 0; di < sizeof depths / sizeof depths[0]; di++) {
        uint32_t depth = depths[di];
        uint32_t n = 0, xyz[3 * 600];
        uint32_t seed = depth, side = (1u << depth) - 1;
        for (int i = 0; i < 88; i++, n++)
            for (int k = 0; k < 3; k++) xyz[3 * n + k] = ts_rng(&seed) % side;
        for (uint32_t z = 0; z < 8; z++) /* an 8^3 block at 64: one full brick */
            for (uint32_t y = 0; y < 8; y++)
                for (uint32_t x = 0; x < 8; x++, n++) xyz[3 * n] = 64 + x, xyz[3 * n + 1] = 64 + y, xyz[3 * n + 2] = 64 + z;
        uint32_t size[3] = {side + 1, side + 1, side + 1};
        vx_svo_model m;
        CHECK(ts_model(&m, size, xyz, NULL, n) == VX_OK);
        char nm[64];
        snprintf(nm, sizeof nm, "sparse 2^%u", depth);
        check_model(nm, &m, false);
        /* every set cell, and its 26 neighbours */
        vx__grid_words out = {0};
        vx_error err = {0};
        uint32_t top, rec;
        CHECK(vx__grid_model(NULL, &m, NULL, 0, NULL, &out, &top, &rec, &err) == VX_OK && rec == 0);
        size_t wrong = 0;
        for (uint32_t i = 0; i < n; i++)
            for (int dz = -1; dz <= 1; dz++)
                for (int dy = -1; dy <= 1; dy++)
                    for (int dx = -1; dx <= 1; dx++) {
                        int64_t x = (int64_t)xyz[3 * i] + dx, y = (int64_t)xyz[3 * i + 1] + dy, z = (int64_t)xyz[3 * i + 2] + dz;
                        if (x < 0 || y < 0 || z < 0 || x > side || y > side || z > side) continue;
                        bool a = grid_cell(out.w, 0, 0, depth, top, (uint32_t)x, (uint32_t)y, (uint32_t)z);
                        wrong += a != vx_svo_model_cell_set(&m, (uint32_t)x, (uint32_t)y, (uint32_t)z);
                    }
        CHECKF(wrong == 0, "%s: %zu cells near set ones differ", nm, wrong);
        vx_free(NULL, out.w);
        vx_svo_model_free(NULL, &m);
    }
}

/* The bricks' record words (vx__grid_brick_record) where the octree has uniform leaves of one record at the
 * brick's level and above it (a 16^3 and an 8^3 block) and below it (a 4^3 block), far pointers (the builder's far
 * limit 2: most blocks through a far slot), a whole model of one record (its root a leaf), a model of depth 2 (one
 * brick: its root is the brick's node) and a root at level 2 (depth 11): every set cell's record from its brick
 * against the decoded one (check_model). */
static void test_records(void) {
    for (uint32_t far = 0; far <= 2; far += 2) {
        uint32_t n = 0, seed = 5 + far, *xyz = malloc(64 * 64 * 64 * 12);
        uint8_t* pal = malloc(64 * 64 * 64);
        CHECK(xyz && pal);
        if (!xyz || !pal) return;
        for (uint32_t z = 0; z < 64; z++)
            for (uint32_t y = 0; y < 64; y++)
                for (uint32_t x = 0; x < 64; x++) {
                    bool a = x >= 16 && x < 32 && y >= 16 && y < 32 && z >= 16 && z < 32;
                    bool b = x >= 40 && x < 48 && y < 8 && z >= 8 && z < 16;
                    bool c = x >= 4 && x < 8 && y >= 4 && y < 8 && z >= 4 && z < 8;
                    uint32_t r = ts_rng(&seed);
                    if (!a && !b && !c && r % 100 >= 20) continue;
                    xyz[3 * n] = x, xyz[3 * n + 1] = y, xyz[3 * n + 2] = z;
                    pal[n++] = (uint8_t)(a ? 5 : b ? 9 : c ? 3 : 1 + (r >> 8) % 255);
                }
        vx_svo_model m;
        CHECK(ts_model_far(&m, (uint32_t[3]){64, 64, 64}, xyz, pal, n, far) == VX_OK);
        check_model(far ? "blocks of one record, far" : "blocks of one record", &m, true);
        vx_svo_model_free(NULL, &m);
        /* a whole 16^3 model of one record */
        n = 0;
        for (uint32_t i = 0; i < 16 * 16 * 16; i++, n++)
            xyz[3 * n] = i & 15, xyz[3 * n + 1] = (i >> 4) & 15, xyz[3 * n + 2] = i >> 8, pal[n] = 77;
        CHECK(ts_model_far(&m, (uint32_t[3]){16, 16, 16}, xyz, pal, n, far) == VX_OK);
        CHECK(m.root == VX_SVO_ROOT_LEAF);
        check_model("one record", &m, true);
        vx_svo_model_free(NULL, &m);
        /* depth 11 (root level 2), a few hundred cells and an 8^3 block of one record */
        n = 0;
        for (int i = 0; i < 300; i++, n++) {
            for (int k = 0; k < 3; k++) xyz[3 * n + k] = ts_rng(&seed) % 2048;
            pal[n] = (uint8_t)(1 + ts_rng(&seed) % 255);
        }
        for (uint32_t i = 0; i < 512; i++, n++)
            xyz[3 * n] = 1024 + (i & 7), xyz[3 * n + 1] = 8 + ((i >> 3) & 7), xyz[3 * n + 2] = 64 + (i >> 6), pal[n] = 12;
        CHECK(ts_model_far(&m, (uint32_t[3]){2048, 2048, 2048}, xyz, pal, n, far) == VX_OK);
        check_model("depth 11 with records", &m, false);
        vx_svo_model_free(NULL, &m);
        free(xyz);
        free(pal);
    }
    /* depth 2: the root is the brick's node */
    vx_svo_model m;
    CHECK(ts_random_model(&m, 3, 4, 2, 70, 3) == VX_OK && m.depth == 2);
    check_model("depth 2 with records", &m, true);
    vx_svo_model_free(NULL, &m);
}

/* The root level: render/grid.c's rule against grid_walk.glsl's table (depth
 * <= 10: 1, <= 13: 2, else 3), and the layout's refusals. */
static void test_top_rule(void) {
    for (uint32_t d = 3; d <= 16; d++) {
        uint32_t shader = d <= 10 ? 1 : d <= 13 ? 2 : 3;
        CHECKF(vx__grid_top(d, 0) == shader, "depth %u: top %u, the shader's %u", d, vx__grid_top(d, 0), shader);
        CHECKF((d - 3 * vx__grid_top(d, 0)) <= VX__GRID_ROOT_LOG, "depth %u: root over 128 wide", d);
    }
    CHECK(vx__grid_top(12, 9) == 1); /* render_bench --brick-root 9: terrain4096 in two levels */
    vx__grid_bricks b = {0};
    vx__grid_words out = {0};
    vx_error err = {0};
    CHECK(vx__grid_layout(&b, 2, 1, NULL, 0, &out, &err) == VX_ERR_LIMIT);
    CHECK(vx__grid_layout(&b, 12, 4, NULL, 0, &out, &err) == VX_ERR_LIMIT);
    CHECK(vx__grid_layout(&b, 12, 2, NULL, UINT64_C(0x7FFFFFF0), &out, &err) == VX_ERR_LIMIT); /* addresses past 2^31 */
    CHECK(out.n == 0);
    /* two sources ORed into one brick */
    uint32_t* w = vx__grid_brick_at(&b, 1, 2, 3);
    CHECK(w && (w[0] |= 1, true));
    w = vx__grid_brick_at(&b, 1, 2, 3);
    CHECK(w && w[0] == 1 && b.count == 1 && b.bits.n == 16);
    vx__grid_bricks_free(&b);
}

/* The grid over its cells' box's cube (vx__grid_cube, stop 85): the rule on boxes at the seams (a box that
 * ends on a brick's edge or one past it, a box of one cell, lo on a multiple of 8 and one below), then models
 * whose cells lie in a small box of a large cube (a slab, a small group far from cell 0, and one with a solid
 * 8^3 block of one record: a uniform leaf) laid out over that cube: every cell of the cube against the octree,
 * every set cell's record, the distances; and a brick outside the cube refused with nothing written. */
static void test_cube(void) {
    /* a model of depth 20 (every cube below smaller than its), then boxes whose cube is not smaller than their
     * model's: the model's cube from 0 */
    static const struct { uint32_t cb[6], org[3], depth; } rule[] = {
        {{0, 0, 0, 8, 8, 8}, {0, 0, 0}, 3},          {{0, 0, 0, 9, 1, 1}, {0, 0, 0}, 4},
        {{7, 7, 7, 8, 8, 8}, {0, 0, 0}, 3},          {{8, 8, 8, 9, 9, 9}, {8, 8, 8}, 3},
        {{7, 0, 0, 9, 1, 1}, {0, 0, 0}, 4},          {{15, 16, 17, 16, 17, 18}, {8, 16, 16}, 3},
        {{203, 100, 17, 231, 105, 41}, {200, 96, 16}, 5}, {{0, 0, 0, 1024, 3, 3}, {0, 0, 0}, 10},
        {{44, 62, 5, 50, 71, 10}, {40, 56, 0}, 4},   {{1, 2, 3, 4, 5, 6}, {0, 0, 0}, 3},
    };
    static const struct { uint32_t cb[6], model_depth; } same[] = {
        {{8, 56, 0, 113, 65, 116}, 7}, /* ogt_doom's: org 8,56,0 would give 2^7 too */
        {{0, 0, 0, 17, 5, 9}, 5},      {{3, 3, 3, 4, 4, 4}, 2}, {{8, 8, 8, 16, 16, 16}, 3}, {{9, 0, 0, 30, 1, 1}, 5},
    };
    for (size_t i = 0; i < sizeof same / sizeof same[0]; i++) {
        uint32_t org[3] = {1, 1, 1}, d = vx__grid_cube(same[i].cb, same[i].model_depth, org), md = same[i].model_depth;
        CHECKF(d == (md < 3 ? 3 : md) && !(org[0] | org[1] | org[2]), "box %zu: depth %u org %u,%u,%u, the model's %u",
               i, d, org[0], org[1], org[2], md);
    }
    for (size_t i = 0; i < sizeof rule / sizeof rule[0]; i++) {
        uint32_t org[3], d = vx__grid_cube(rule[i].cb, 20, org);
        CHECKF(d == rule[i].depth && !memcmp(org, rule[i].org, sizeof org), "box %zu: depth %u org %u,%u,%u", i, d,
               org[0], org[1], org[2]);
        for (int k = 0; k < 3; k++) /* the cube holds the box */
            CHECKF(org[k] <= rule[i].cb[k] && rule[i].cb[3 + k] - org[k] <= (1u << d), "box %zu axis %d", i, k);
    }
    for (int v = 0; v < 3; v++) {
        uint32_t n = 0, seed = 31 + (uint32_t)v, *xyz = malloc(3 * 4096 * 4);
        uint8_t* pal = malloc(4096);
        CHECK(xyz && pal);
        if (!xyz || !pal) return;
        for (int i = 0; i < 600; i++, n++) {
            /* v 0: a slab 40 x 2 x 60 at 150, 401, 77; v 1: a 9^3 group at 300, 17, 250; v 2: as v 1 and a block */
            uint32_t r = ts_rng(&seed);
            if (v == 0) xyz[3 * n] = 150 + r % 40, xyz[3 * n + 1] = 401 + (r >> 8) % 2, xyz[3 * n + 2] = 77 + (r >> 12) % 60;
            else xyz[3 * n] = 300 + r % 9, xyz[3 * n + 1] = 17 + (r >> 8) % 9, xyz[3 * n + 2] = 250 + (r >> 16) % 9;
            pal[n] = (uint8_t)(1 + (r >> 20) % 200);
        }
        if (v == 2)
            for (uint32_t j = 0; j < 512; j++, n++)
                xyz[3 * n] = 312 + (j & 7), xyz[3 * n + 1] = 24 + ((j >> 3) & 7), xyz[3 * n + 2] = 256 + (j >> 6), pal[n] = 9;
        vx_svo_model m;
        CHECK(ts_model_far(&m, (uint32_t[3]){500, 500, 500}, xyz, pal, n, 0) == VX_OK);
        char nm[64];
        snprintf(nm, sizeof nm, "%s in 2^%u", v == 0 ? "slab" : v == 1 ? "group" : "group and block", m.depth);
        uint32_t cb[6], org[3];
        vx_svo_model_cell_box(&m, cb, cb + 3);
        uint32_t depth = vx__grid_cube(cb, m.depth, org);
        vx__grid_words out = {0};
        CHECK(vx__grid_words_grow(NULL, &out, 5));
        out.n = 5;
        vx_error err = {0};
        uint32_t top, rec;
        vx_result r = vx__grid_model(NULL, &m, cb, 71, NULL, &out, &top, &rec, &err);
        CHECKF(r == VX_OK && rec != 0, "%s: %s", nm, err.msg);
        CHECKF(depth < m.depth && top == vx__grid_top(depth, 0), "%s: cube 2^%u, model 2^%u", nm, depth, m.depth);
        if (!r) {
            /* every cell of the cube */
            size_t wrong = 0, cells = 0;
            uint32_t side = 1u << depth;
            for (uint32_t z = 0; z < side; z++)
                for (uint32_t y = 0; y < side; y++)
                    for (uint32_t x = 0; x < side; x++) {
                        bool a = grid_cell(out.w, 71, 5, depth, top, x, y, z);
                        bool b = vx_svo_model_cell_set(&m, org[0] + x, org[1] + y, org[2] + z);
                        cells += b;
                        if (a != b && wrong++ < 4) fprintf(stderr, "  %s: cell %u,%u,%u grid %d octree %d\n", nm, x, y, z, a, b);
                    }
            CHECKF(wrong == 0 && cells > 0 && cells == m.voxel_count, "%s: %zu cells differ, %zu of %llu found", nm,
                   wrong, cells, (unsigned long long)m.voxel_count);
            uint32_t R = 1u << (depth - 3 * top);
            CHECKF(check_distances(out.w + 5, R, depth - 3 * top >= VX__GRID_OCT_ROOT_LOG) == 0, "%s: root distances", nm);
            rec_check rc = {&m, out.w, 71, 5, depth, top, rec, 0, 0, nm, {org[0], org[1], org[2]}};
            CHECK(vx_svo_decode_model(&m, rec_cell, &rc, &err) == VX_OK);
            CHECKF(rc.wrong == 0 && rc.cells == m.voxel_count, "%s: %zu of %zu cells' records differ", nm, rc.wrong,
                   rc.cells);
            printf("%-28s cube 2^%u at %u,%u,%u: %zu words (the model's cube: 2^%u)\n", nm, depth, org[0], org[1],
                   org[2], out.n - 5, m.depth);
        }
        /* a box that leaves a cell out: its brick outside the cube, refused, nothing appended */
        uint32_t small[6] = {cb[0], cb[1], cb[2], cb[0] + 1, cb[1] + 1, cb[2] + 1};
        size_t before = out.n;
        r = vx__grid_model(NULL, &m, small, 71, NULL, &out, &top, &rec, &err);
        CHECKF(r == VX_ERR_INVALID_ARG && out.n == before, "%s: a brick outside the cube: %d", nm, (int)r);
        vx_free(NULL, out.w);
        vx_svo_model_free(NULL, &m);
        free(xyz);
        free(pal);
    }
}

int main(void) {
    RUN(test_top_rule);
    RUN(test_cube);
    RUN(test_models);
    RUN(test_deep_levels);
    RUN(test_records);
    return vx_test_finish();
}
