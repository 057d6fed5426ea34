/* tests/svo/test_svo_edit.c - incremental edits (svo/edit.h) against a dense
 * brute-force grid and against vx_svo_build_model of the same cells: after
 * random brush writes (set, clear, recolour, growth) the edited model holds
 * exactly the grid's cells and values, its tree (masks and every coarse
 * record, in depth-first order) equals the from-scratch build's, undo by
 * header gives the earlier cells back, compaction gives the builder's words,
 * and the model survives a .svo round trip. */
#include <math.h>
#include <stdint.h>

#include "svo/edit.h"
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
static uint32_t rnd_below(uint32_t n) { return (uint32_t)(rnd() % n); }

/* ---- the dense reference ---------------------------------------------------------------- */

#define GMAX 80u /* the grid the model may grow into */

typedef struct grid {
    uint32_t size[3];
    bool* set;
    vx_svo_cell* v;
} grid;

static size_t gi(uint32_t x, uint32_t y, uint32_t z) { return ((size_t)z * GMAX + y) * GMAX + x; }

static grid grid_new(void) {
    grid g = {{0, 0, 0}, calloc((size_t)GMAX * GMAX * GMAX, 1), calloc((size_t)GMAX * GMAX * GMAX, sizeof(vx_svo_cell))};
    return g;
}
static grid grid_copy(const grid* s) {
    grid g = grid_new();
    memcpy(g.size, s->size, sizeof g.size);
    memcpy(g.set, s->set, (size_t)GMAX * GMAX * GMAX);
    memcpy(g.v, s->v, (size_t)GMAX * GMAX * GMAX * sizeof(vx_svo_cell));
    return g;
}
static void grid_free(grid* g) {
    free(g->set);
    free(g->v);
}

/* A value with only the channels in attrs (what the model reads back). */
/* Cells equal member by member (the struct has padding, which a copy need not
 * keep: memcmp failed under -O1). The density's bits, so that -0 and NaN count. */
static bool same_cell(const vx_svo_cell* a, const vx_svo_cell* b) {
    return a->palette == b->palette && a->rgba == b->rgba && a->normal == b->normal && a->material == b->material &&
           !memcmp(&a->density, &b->density, sizeof a->density);
}

static vx_svo_cell cell_value(uint32_t attrs, uint32_t pick) {
    vx_svo_cell c = {0};
    /* few distinct values, so that collapse and sharing happen */
    if (attrs & VX_ATTR_PALETTE) c.palette = (uint8_t)(1 + pick % 4);
    if (attrs & VX_ATTR_RGBA8) c.rgba = 0xFF000000u | (pick % 3) * 0x00405060u;
    if (attrs & VX_ATTR_NORMAL) {
        float n[3] = {(float)(pick % 2), 1.0f, (float)(pick % 3) - 1.0f};
        c.normal = vx__oct_encode(n);
    }
    if (attrs & VX_ATTR_MATERIAL) c.material = (uint16_t)(pick % 2);
    if (attrs & VX_ATTR_DENSITY) c.density = 0.25f * (float)(1 + pick % 3);
    return c;
}

/* far: the builder's far limit (vx_svo_testing.far_limit; 0: the default) */
static vx_result build_from_grid(const grid* g, uint32_t attrs, uint32_t far, vx_svo_model* out) {
    size_t n = 0, cap = (size_t)GMAX * GMAX * GMAX;
    uint64_t* keys = malloc(cap * 8);
    uint8_t* pal = malloc(cap);
    uint32_t *rgba = malloc(cap * 4), *nrm = malloc(cap * 4);
    uint16_t* mat = malloc(cap * 2);
    float* den = malloc(cap * 4);
    for (uint32_t z = 0; z < g->size[2]; z++)
        for (uint32_t y = 0; y < g->size[1]; y++)
            for (uint32_t x = 0; x < g->size[0]; x++) {
                size_t i = gi(x, y, z);
                if (!g->set[i]) continue;
                keys[n] = vx_svo_morton(x, y, z);
                pal[n] = g->v[i].palette, rgba[n] = g->v[i].rgba, nrm[n] = g->v[i].normal;
                mat[n] = g->v[i].material, den[n] = g->v[i].density;
                n++;
            }
    vx_svo_voxels v = {.count = n, .keys = keys, .attrs = attrs};
    memcpy(v.size, g->size, sizeof v.size);
    if (attrs & VX_ATTR_PALETTE) v.palette = pal;
    if (attrs & VX_ATTR_RGBA8) v.rgba = rgba;
    if (attrs & VX_ATTR_NORMAL) v.normal = nrm;
    if (attrs & VX_ATTR_MATERIAL) v.material = mat;
    if (attrs & VX_ATTR_DENSITY) v.density = den;
    vx_error err;
    vx_result r = vx_svo_build_model(&(vx_svo_build_desc){.testing.far_limit = far}, &v, out, NULL, &err);
    free(keys), free(pal), free(rgba), free(nrm), free(mat), free(den);
    return r;
}

/* ---- comparisons -------------------------------------------------------------------------- */

typedef struct cmp_ctx {
    const grid* g;
    const vx_svo_model* m;
    size_t n, bad;
} cmp_ctx;

static bool cmp_cb(void* user, uint32_t x, uint32_t y, uint32_t z, uint32_t attr) {
    cmp_ctx* c = user;
    c->n++;
    if (x >= c->g->size[0] || y >= c->g->size[1] || z >= c->g->size[2] || !c->g->set[gi(x, y, z)]) {
        c->bad++;
        return true;
    }
    const vx_svo_cell* v = &c->g->v[gi(x, y, z)];
    const vx_svo_model* m = c->m;
    if ((m->palette && m->palette[attr] != v->palette) || (m->rgba && m->rgba[attr] != v->rgba) ||
        (m->normal && m->normal[attr] != v->normal) || (m->material && m->material[attr] != v->material) ||
        (m->density && m->density[attr] != v->density))
        c->bad++;
    return true;
}

/* Every cell of m equals the grid, and the grid has no other cell. */
static void check_cells(const vx_svo_model* m, const grid* g) {
    vx_error err;
    CHECKF(vx_svo_validate_edited_model(m, &err) == VX_OK, "%s", err.msg);
    CHECK(m->size[0] == g->size[0] && m->size[1] == g->size[1] && m->size[2] == g->size[2]);
    size_t want = 0;
    for (uint32_t z = 0; z < g->size[2]; z++)
        for (uint32_t y = 0; y < g->size[1]; y++)
            for (uint32_t x = 0; x < g->size[0]; x++) want += g->set[gi(x, y, z)];
    cmp_ctx c = {g, m, 0, 0};
    CHECK(vx_svo_decode_model(m, cmp_cb, &c, &err) == VX_OK);
    CHECKF(c.n == want && c.bad == 0 && m->voxel_count == want, "decoded %zu cells (%zu wrong), grid %zu, voxel_count %llu",
           c.n, c.bad, want, (unsigned long long)m->voxel_count);
}

/* The tree as a sequence: per node in depth-first order its masks and the
 * records of its valid children (all channels), the root's record first. */
typedef struct seq {
    uint32_t* v;
    size_t n, cap;
} seq;
static void put(seq* s, uint32_t x) {
    if (s->n == s->cap) s->v = realloc(s->v, (s->cap = s->cap ? 2 * s->cap : 1024) * 4);
    s->v[s->n++] = x;
}
static void put_rec(seq* s, const vx_svo_model* m, uint32_t a) {
    if (!m->attrs) return;
    put(s, m->palette ? m->palette[a] : 0);
    put(s, m->rgba ? m->rgba[a] : 0);
    put(s, m->normal ? m->normal[a] : 0);
    put(s, m->material ? m->material[a] : 0);
    uint32_t d = 0;
    if (m->density) memcpy(&d, &m->density[a], 4);
    put(s, d);
}
static void walk(seq* s, const vx_svo_model* m, uint32_t pos) {
    uint32_t d = m->nodes[pos], valid = vx_svo_desc_valid(d), leaf = vx_svo_desc_leaf(d);
    put(s, d & 0xFFFFu);
    if (!(valid & ~leaf) && !m->attrs) return;
    uint32_t p = vx_svo_desc_ptr(d), blk = vx_svo_desc_far(d) ? m->nodes[pos - p] : pos - p;
    uint32_t nn = vx__popc8(valid & ~leaf), a = m->attrs ? m->nodes[blk + nn] : 0, j = 0, r = 0;
    for (unsigned o = 0; o < 8; o++) {
        if (!(valid >> o & 1u)) continue;
        put_rec(s, m, a + r++);
        if (!(leaf >> o & 1u)) walk(s, m, blk + j++);
    }
}
static seq tree_seq(const vx_svo_model* m) {
    seq s = {0};
    put(&s, m->root == VX_SVO_ROOT_EMPTY ? 0 : m->root == VX_SVO_ROOT_LEAF ? 1 : 2);
    put(&s, m->depth);
    if (m->root != VX_SVO_ROOT_EMPTY) put_rec(&s, m, m->root_attr);
    if (m->root < VX_SVO_ROOT_LEAF) walk(&s, m, m->root);
    return s;
}

static void check_same_tree(const vx_svo_model* m, const grid* g) {
    vx_svo_model b = {0};
    REQUIRE(build_from_grid(g, m->attrs, 0, &b) == VX_OK);
    seq x = tree_seq(m), y = tree_seq(&b);
    size_t diff = x.n == y.n ? 0 : SIZE_MAX;
    for (size_t i = 0; diff == 0 && i < x.n; i++)
        if (x.v[i] != y.v[i]) diff = i + 1;
    CHECKF(diff == 0, "tree differs from the from-scratch build (%zu vs %zu entries, first difference at %zu)", x.n, y.n,
           diff == SIZE_MAX ? 0 : diff - 1);
    free(x.v), free(y.v);
    vx_svo_model_free(NULL, &b);
}

/* ---- edits ------------------------------------------------------------------------------ */

/* A random brush: a box or ball of set / clear / recolour writes, sometimes
 * beyond the size (growth). Applied to the grid and returned as writes. */
static size_t brush(grid* g, uint32_t attrs, vx_svo_editor* e, vx_svo_cell_write* w, uint32_t reach) {
    int op = (int)rnd_below(3); /* 0 set, 1 clear, 2 recolour (set where set) */
    uint32_t r = rnd_below(4), c[3];
    for (int k = 0; k < 3; k++) c[k] = rnd_below(reach);
    bool ball = rnd() & 1;
    uint32_t pick = rnd_below(6);
    size_t n = 0;
    for (int64_t dz = -(int64_t)r; dz <= r; dz++)
        for (int64_t dy = -(int64_t)r; dy <= r; dy++)
            for (int64_t dx = -(int64_t)r; dx <= r; dx++) {
                if (ball && dx * dx + dy * dy + dz * dz > (int64_t)r * r) continue;
                int64_t p[3] = {c[0] + dx, c[1] + dy, c[2] + dz};
                if (p[0] < 0 || p[1] < 0 || p[2] < 0 || p[0] >= GMAX || p[1] >= GMAX || p[2] >= GMAX) continue;
                uint32_t x = (uint32_t)p[0], y = (uint32_t)p[1], z = (uint32_t)p[2];
                size_t i = gi(x, y, z);
                bool inside = x < g->size[0] && y < g->size[1] && z < g->size[2];
                vx_svo_cell_write q = {.x = x, .y = y, .z = z};
                if (op == 0) {
                    q.set = true;
                    q.value = cell_value(attrs, pick + (uint32_t)(dx & 1));
                } else if (op == 1) {
                    if (!inside && (rnd() & 1)) continue; /* clears outside too, sometimes */
                } else {
                    vx_svo_cell old;
                    bool was = vx_svo_editor_get(e, x, y, z, &old);
                    CHECK(was == (inside && g->set[i]));
                    if (!was) continue;
                    if (was) CHECK(same_cell(&old, &g->v[i]));
                    q.set = true;
                    q.value = old;
                    if (attrs & VX_ATTR_PALETTE) q.value.palette = cell_value(attrs, pick).palette;
                    if (attrs & VX_ATTR_RGBA8) q.value.rgba = cell_value(attrs, pick).rgba;
                }
                w[n++] = q;
            }
    /* the grid: writes in order, the last one wins */
    for (size_t k = 0; k < n; k++) {
        size_t i = gi(w[k].x, w[k].y, w[k].z);
        if (w[k].set) {
            g->set[i] = true;
            g->v[i] = w[k].value;
            if (w[k].x >= g->size[0]) g->size[0] = w[k].x + 1;
            if (w[k].y >= g->size[1]) g->size[1] = w[k].y + 1;
            if (w[k].z >= g->size[2]) g->size[2] = w[k].z + 1;
        } else {
            g->set[i] = false;
        }
    }
    return n;
}

/* vx_svo_editor_get_box of a random box (reaching past the model at times)
 * against the grid. */
static void check_box(const vx_svo_editor* e, const grid* g) {
    uint32_t lo[3], hi[3], d[3];
    for (int k = 0; k < 3; k++) {
        lo[k] = rnd_below(GMAX - 1);
        hi[k] = lo[k] + rnd_below(24);
        if (hi[k] >= GMAX) hi[k] = GMAX - 1;
        d[k] = hi[k] - lo[k] + 1;
    }
    size_t n = (size_t)d[0] * d[1] * d[2], bad = 0;
    bool* set = malloc(n);
    vx_svo_cell* v = malloc(n * sizeof *v);
    REQUIRE(set && v && vx_svo_editor_get_box(e, lo, hi, set, v, NULL) == VX_OK);
    for (uint32_t z = 0; z < d[2]; z++)
        for (uint32_t y = 0; y < d[1]; y++)
            for (uint32_t x = 0; x < d[0]; x++) {
                size_t i = ((size_t)z * d[1] + y) * d[0] + x, j = gi(lo[0] + x, lo[1] + y, lo[2] + z);
                bool want = g->set[j] && lo[0] + x < g->size[0] && lo[1] + y < g->size[1] && lo[2] + z < g->size[2];
                bad += set[i] != want || (want && !same_cell(&v[i], &g->v[j]));
            }
    CHECKF(bad == 0, "box %u..%u x %u..%u x %u..%u: %zu cells differ", lo[0], hi[0], lo[1], hi[1], lo[2], hi[2], bad);
    free(set), free(v);
}

/* A blocky start: a few filled boxes of few values, so collapsed leaves and
 * shared subtrees exist. */
static void fill_start(grid* g, uint32_t attrs, uint32_t sx, uint32_t sy, uint32_t sz) {
    g->size[0] = sx, g->size[1] = sy, g->size[2] = sz;
    for (int b = 0; b < 6; b++) {
        uint32_t lo[3], hi[3];
        for (int k = 0; k < 3; k++) {
            lo[k] = rnd_below(g->size[k]);
            hi[k] = lo[k] + 1 + rnd_below(12);
            if (hi[k] > g->size[k]) hi[k] = g->size[k];
        }
        vx_svo_cell v = cell_value(attrs, (uint32_t)b);
        for (uint32_t z = lo[2]; z < hi[2]; z++)
            for (uint32_t y = lo[1]; y < hi[1]; y++)
                for (uint32_t x = lo[0]; x < hi[0]; x++) g->set[gi(x, y, z)] = true, g->v[gi(x, y, z)] = v;
    }
}

/* far_limit: the builder's and the editor's (vx_svo_testing.far_limit) */
static void run_edits(uint32_t attrs, bool no_dag, uint32_t far_limit, int rounds) {
    grid g = grid_new();
    fill_start(&g, attrs, 20 + rnd_below(12), 17, 24);
    vx_svo_model m = {0};
    REQUIRE(build_from_grid(&g, attrs, far_limit, &m) == VX_OK);
    vx_svo_editor* e = NULL;
    vx_error err;
    REQUIRE(vx_svo_editor_create(&(vx_svo_editor_desc){.no_dag = no_dag, .testing.far_limit = far_limit}, &m, &e, &err) == VX_OK);
    vx_svo_cell_write* w = malloc(9 * 9 * 9 * sizeof *w);
    uint64_t shared = 0, far_new = 0;
    for (int it = 0; it < rounds; it++) {
        grid before = grid_copy(&g);
        vx_svo_model_header h0 = vx_svo_model_header_get(&m);
        size_t n = brush(&g, attrs, e, w, it < rounds / 2 ? 36 : GMAX - 4);
        vx_svo_edit_stats st;
        if (vx_svo_editor_apply(e, w, n, &st, &err) != VX_OK) {
            CHECKF(false, "apply: %s", err.msg);
            grid_free(&before);
            break;
        }
        shared += st.blocks_shared;
        CHECK(st.words_from >= h0.node_count && (m.node_count == 0 || m.node_count == st.words_from + st.words_added));
        for (uint32_t i = st.words_from; i < m.node_count; i++) far_new += vx_svo_desc_far(m.nodes[i]) && vx_svo_desc_valid(m.nodes[i]);
        check_cells(&m, &g);
        if (it % 4 == 0) check_box(e, &g);
        if (it % 8 == 0 || it == rounds - 1) check_same_tree(&m, &g);
        if (it % 5 == 0) { /* undo by header, check, redo */
            vx_svo_model_header h1 = vx_svo_model_header_get(&m);
            vx_svo_model_header_set(&m, &h0);
            check_cells(&m, &before);
            vx_svo_model_header_set(&m, &h1);
            check_cells(&m, &g);
        }
        grid_free(&before);
        if (vx_t_cur_failed) break;
    }
    if (!no_dag) CHECK(shared > 0); /* unchanged neighbours of the paths are found again */
    /* a low limit reaches the editor: the words it appends hold far slots */
    if (far_limit < VX__SVO_PTR_MAX) CHECKF(far_new > 0, "far limit %u: no far descriptor among the edits' words", far_limit);
    /* compaction gives the builder's words and records exactly (its own
     * build: the default far limit) */
    vx_svo_model c = {0}, b = {0};
    CHECK(vx_svo_model_compact(NULL, &m, &c, &err) == VX_OK);
    CHECK(build_from_grid(&g, attrs, 0, &b) == VX_OK);
    CHECK(c.node_count == b.node_count && c.attr_count == b.attr_count && c.root == b.root && c.root_attr == b.root_attr);
    CHECK(c.node_count == b.node_count && (!b.node_count || !memcmp(c.nodes, b.nodes, (size_t)b.node_count * 4)));
    CHECK(!b.rgba || !memcmp(c.rgba, b.rgba, (size_t)b.attr_count * 4));
    CHECK(!b.palette || !memcmp(c.palette, b.palette, b.attr_count));
    /* the desc reaches the compaction's build: with the edits' far limit its words are the builder's with
     * that limit (far slots where the default has none) */
    if (far_limit < VX__SVO_PTR_MAX) {
        vx_svo_model cf = {0}, bf = {0};
        CHECK(vx_svo_model_compact(&(vx_svo_build_desc){.testing.far_limit = far_limit}, &m, &cf, &err) == VX_OK);
        CHECK(build_from_grid(&g, attrs, far_limit, &bf) == VX_OK);
        CHECKF(cf.node_count == bf.node_count && cf.root == bf.root &&
                   (!bf.node_count || !memcmp(cf.nodes, bf.nodes, (size_t)bf.node_count * 4)),
               "far limit %u: the compaction's words are not the builder's", far_limit);
        CHECKF(cf.node_count != c.node_count || (c.node_count && memcmp(cf.nodes, c.nodes, (size_t)c.node_count * 4)),
               "far limit %u: the compaction's words are the default limit's", far_limit);
        vx_svo_model_free(NULL, &cf);
        vx_svo_model_free(NULL, &bf);
    }
    /* the compacted model is a valid file whose cells are the grid's */
    vx_svo_scene s;
    vx_svo_scene_init(&s, NULL);
    s.model_count = 1;
    s.models = &c;
    s.instance_count = 1;
    vx_svo_instance in = {.xform = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0}, .layer = UINT32_MAX};
    s.instances = &in;
    if (attrs & VX_ATTR_PALETTE) {
        s.has_palette = true;
        for (int i = 1; i < 256; i++) s.palette[i] = 0xFF000000u | (uint32_t)i;
    }
    uint8_t* data = NULL;
    size_t size = 0;
    CHECKF(vx_svo_write(&s, NULL, &data, &size, &err) == VX_OK, "%s", err.msg);
    vx_svo_scene back;
    if (data && vx_svo_read(&(vx_svo_read_desc){0}, data, size, &back, &err) == VX_OK) {
        check_cells(&back.models[0], &g);
        vx_svo_scene_free(&back);
    } else {
        CHECKF(false, "read back: %s", err.msg);
    }
    vx_free(NULL, data);
    vx_svo_model_free(NULL, &c);
    vx_svo_model_free(NULL, &b);
    vx_svo_editor_destroy(e);
    vx_svo_model_free(NULL, &m);
    free(w);
    grid_free(&g);
}

static void test_edit_palette(void) { run_edits(VX_ATTR_PALETTE, false, VX__SVO_PTR_MAX, 120); }
static void test_edit_all_channels(void) { run_edits(VX_ATTR_ALL & ~VX_ATTR_PALETTE, false, VX__SVO_PTR_MAX, 80); }
static void test_edit_geometry_only(void) { run_edits(0, false, VX__SVO_PTR_MAX, 80); }
static void test_edit_far_pointers(void) { run_edits(VX_ATTR_RGBA8, false, 40, 80); }
static void test_edit_no_dag(void) { run_edits(VX_ATTR_PALETTE | VX_ATTR_MATERIAL, true, VX__SVO_PTR_MAX, 60); }

/* Emptying a model and filling a whole cube (a root leaf), growth from one
 * cell, and a write out of range that changes nothing. */
static void test_edit_edges(void) {
    grid g = grid_new();
    g.size[0] = g.size[1] = g.size[2] = 1;
    g.set[gi(0, 0, 0)] = true;
    g.v[gi(0, 0, 0)] = cell_value(VX_ATTR_RGBA8, 1);
    vx_svo_model m = {0};
    REQUIRE(build_from_grid(&g, VX_ATTR_RGBA8, 0, &m) == VX_OK);
    REQUIRE(m.root == VX_SVO_ROOT_LEAF && m.depth == 0);
    vx_svo_editor* e = NULL;
    vx_error err;
    REQUIRE(vx_svo_editor_create(NULL, &m, &e, &err) == VX_OK);
    /* fill the 4^3 cube in one value: the root becomes one leaf */
    vx_svo_cell_write w[64];
    size_t n = 0;
    for (uint32_t z = 0; z < 4; z++)
        for (uint32_t y = 0; y < 4; y++)
            for (uint32_t x = 0; x < 4; x++) {
                w[n] = (vx_svo_cell_write){.x = x, .y = y, .z = z, .set = true, .value = cell_value(VX_ATTR_RGBA8, 1)};
                g.set[gi(x, y, z)] = true, g.v[gi(x, y, z)] = w[n].value;
                n++;
            }
    g.size[0] = g.size[1] = g.size[2] = 4;
    CHECK(vx_svo_editor_apply(e, w, n, NULL, &err) == VX_OK);
    CHECK(m.root == VX_SVO_ROOT_LEAF && m.depth == 2 && m.node_count == 0);
    check_cells(&m, &g);
    check_same_tree(&m, &g);
    /* out of range: refused, nothing changes */
    vx_svo_model_header h = vx_svo_model_header_get(&m);
    vx_svo_cell_write far = {.x = 1u << 21, .set = true};
    CHECK(vx_svo_editor_apply(e, &far, 1, NULL, &err) == VX_ERR_LIMIT);
    vx_svo_model_header h2 = vx_svo_model_header_get(&m);
    CHECK(!memcmp(&h, &h2, sizeof h));
    /* clear everything: empty, then one cell again */
    for (size_t i = 0; i < n; i++) w[i].set = false, g.set[gi(w[i].x, w[i].y, w[i].z)] = false;
    CHECK(vx_svo_editor_apply(e, w, n, NULL, &err) == VX_OK);
    CHECK(m.root == VX_SVO_ROOT_EMPTY && m.voxel_count == 0 && m.node_count == 0);
    check_cells(&m, &g);
    w[0] = (vx_svo_cell_write){.x = 3, .y = 0, .z = 2, .set = true, .value = cell_value(VX_ATTR_RGBA8, 2)};
    g.set[gi(3, 0, 2)] = true, g.v[gi(3, 0, 2)] = w[0].value;
    CHECK(vx_svo_editor_apply(e, w, 1, NULL, &err) == VX_OK);
    check_cells(&m, &g);
    check_same_tree(&m, &g);
    /* the words of the emptied model were not reused: the first header is intact */
    vx_svo_model_header h3 = vx_svo_model_header_get(&m);
    vx_svo_model_header_set(&m, &h);
    CHECK(m.root == VX_SVO_ROOT_LEAF && m.voxel_count == 64);
    vx_svo_model_header_set(&m, &h3);
    vx_svo_editor_destroy(e);
    vx_svo_model_free(NULL, &m);
    grid_free(&g);
}

int main(void) {
    RUN(test_edit_palette);
    RUN(test_edit_all_channels);
    RUN(test_edit_geometry_only);
    RUN(test_edit_far_pointers);
    RUN(test_edit_no_dag);
    RUN(test_edit_edges);
    return vx_test_finish();
}
