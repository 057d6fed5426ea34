/* render/grid.c - the grid walk's layout: bricks collected, then the levels
 * above them with their distances (render/grid.h). */
#include <string.h>

#include "render/grid.h"

enum { DIST_CAP = VX__GRID_DIST_MASK, OCT_MAX = 7 };
#define EMPTY VX__GRID_EMPTY

static uint32_t popc(uint32_t m) { return (uint32_t)__builtin_popcount(m); }

bool vx__grid_words_grow(const vx_allocator* a, vx__grid_words* v, size_t add) {
    if (add > SIZE_MAX - v->n) return false;
    void* p = v->w;
    if (!vx_grow(a, &p, &v->cap, v->n + add, 4)) return false;
    v->w = p;
    return true;
}

static uint64_t pack(uint64_t x, uint64_t y, uint64_t z) { return x | y << 20 | z << 40; }

static size_t slot_of(const uint64_t* key, size_t cap, uint64_t k) {
    size_t i = (size_t)((k * UINT64_C(0x9E3779B97F4A7C15)) >> 17) & (cap - 1);
    while (key[i] && key[i] != k + 1) i = (i + 1) & (cap - 1);
    return i;
}

/* The hash's value for key k, *added when new (given value next); false out of memory. */
static bool map_get(const vx_allocator* a, uint64_t** key, uint32_t** val, size_t* cap, size_t* n, uint64_t k,
                    uint32_t next, uint32_t* out, bool* added) {
    if (2 * (*n + 1) > *cap) {
        size_t nc = *cap ? 2 * *cap : 4096;
        uint64_t* nk = vx_calloc(a, nc, sizeof *nk);
        uint32_t* nv = vx_calloc(a, nc, sizeof *nv);
        if (!nk || !nv) return vx_free(a, nk), vx_free(a, nv), false;
        for (size_t i = 0; i < *cap; i++)
            if ((*key)[i]) {
                size_t j = slot_of(nk, nc, (*key)[i] - 1);
                nk[j] = (*key)[i], nv[j] = (*val)[i];
            }
        vx_free(a, *key), vx_free(a, *val);
        *key = nk, *val = nv, *cap = nc;
    }
    size_t i = slot_of(*key, *cap, k);
    *added = !(*key)[i];
    if (*added) (*key)[i] = k + 1, (*val)[i] = next, (*n)++;
    *out = (*val)[i];
    return true;
}

uint32_t* vx__grid_brick_at(vx__grid_bricks* b, uint32_t bx, uint32_t by, uint32_t bz) {
    /* room for a new brick first, so that a failure leaves no key without its brick */
    if (!vx__grid_words_grow(b->alloc, &b->bits, 16) || !vx__grid_words_grow(b->alloc, &b->coords, 3)) return NULL;
    uint32_t bi;
    bool added;
    if (!map_get(b->alloc, &b->key, &b->val, &b->cap, &b->count, pack(bx, by, bz), (uint32_t)(b->bits.n / 16), &bi,
                 &added))
        return NULL;
    if (added) {
        memset(b->bits.w + b->bits.n, 0, 64);
        b->bits.n += 16;
        b->coords.w[b->coords.n++] = bx, b->coords.w[b->coords.n++] = by, b->coords.w[b->coords.n++] = bz;
    }
    return &b->bits.w[(size_t)bi * 16];
}

void vx__grid_bricks_free(vx__grid_bricks* b) {
    vx_free(b->alloc, b->bits.w), vx_free(b->alloc, b->coords.w), vx_free(b->alloc, b->key), vx_free(b->alloc, b->val);
    *b = (vx__grid_bricks){.alloc = b->alloc};
}

uint32_t vx__grid_top(uint32_t depth, uint32_t root_log) {
    if (!root_log) root_log = VX__GRID_ROOT_LOG;
    uint32_t top = 1;
    while (depth > 3 * top + root_log && depth > 3 * (top + 1)) top++;
    return top;
}

/* The empty entries of an n^3 grid (x fastest) get EMPTY | their Chebyshev
 * distance to the nearest occupied entry (capped): a breadth-first search
 * over the 26 neighbours from all occupied entries at once (a step to any of
 * the 26 is one unit of the metric). queue: n^3 words. */
static void fill_distances(uint32_t* g, uint64_t n, uint32_t* queue) {
    uint64_t cnt = n * n * n, head = 0, tail = 0;
    for (uint64_t i = 0; i < cnt; i++)
        if (g[i] < EMPTY) queue[tail++] = (uint32_t)i;
        else g[i] = EMPTY | DIST_CAP;
    while (head < tail) {
        uint64_t i = queue[head++];
        int64_t x = (int64_t)(i % n), y = (int64_t)(i / n % n), z = (int64_t)(i / (n * n));
        uint32_t dn = (g[i] < EMPTY ? 0 : g[i] & DIST_CAP) + 1;
        if (dn >= DIST_CAP) continue;
        for (int dz = -1; dz <= 1; dz++)
            for (int dy = -1; dy <= 1; dy++)
                for (int dx = -1; dx <= 1; dx++) {
                    int64_t X = x + dx, Y = y + dy, Z = z + dz;
                    if (X < 0 || Y < 0 || Z < 0 || X >= (int64_t)n || Y >= (int64_t)n || Z >= (int64_t)n) continue;
                    uint64_t j = ((uint64_t)Z * n + (uint64_t)Y) * n + (uint64_t)X;
                    if (g[j] >= EMPTY && (g[j] & DIST_CAP) > dn) g[j] = EMPTY | dn, queue[tail++] = (uint32_t)j;
                }
    }
}

/* After fill_distances: each empty entry of the n^3 grid g also gets, per octant o of directions (bit a set:
 * toward -a), how much further than its distance d the empty cube from it toward o reaches (render/grid.h
 * VX__GRID_OCT_SHIFT): the largest k with every entry of [P, P + s (k - 1)] in the grid empty, less d, at most
 * 7. A ray leaves that cube, not only the cube around P (stop 88: beside a model's surface the cube around an
 * entry stops at the surface behind the ray as well). The largest cube by the usual recurrence over the octant's
 * 7 neighbours, k(P) = 1 + min k(P + s delta) (outside the grid: unbounded), an entry visited after those
 * neighbours. k: n^3 bytes of scratch. k >= d always (the Chebyshev cube of radius d - 1 holds P's octant cube
 * of side d). */
static void fill_octants(uint32_t* g, uint32_t n, uint8_t* k) {
    for (uint32_t o = 0; o < 8; o++) {
        int s[3] = {o & 1 ? -1 : 1, o & 2 ? -1 : 1, o & 4 ? -1 : 1};
        for (uint32_t zi = 0; zi < n; zi++)
            for (uint32_t yi = 0; yi < n; yi++)
                for (uint32_t xi = 0; xi < n; xi++) {
                    /* toward +a the neighbours are at higher a: visit a from the far end */
                    int64_t x = s[0] > 0 ? n - 1 - xi : xi, y = s[1] > 0 ? n - 1 - yi : yi,
                            z = s[2] > 0 ? n - 1 - zi : zi;
                    uint64_t i = ((uint64_t)z * n + (uint64_t)y) * n + (uint64_t)x;
                    if (g[i] < EMPTY) {
                        k[i] = 0;
                        continue;
                    }
                    unsigned m = 255;
                    for (int dl = 1; dl < 8; dl++) {
                        int64_t X = x + (dl & 1 ? s[0] : 0), Y = y + (dl & 2 ? s[1] : 0), Z = z + (dl & 4 ? s[2] : 0);
                        if (X < 0 || Y < 0 || Z < 0 || X >= (int64_t)n || Y >= (int64_t)n || Z >= (int64_t)n) continue;
                        unsigned v = k[((uint64_t)Z * n + (uint64_t)Y) * n + (uint64_t)X];
                        if (v < m) m = v;
                    }
                    k[i] = (uint8_t)(m < 255 ? m + 1 : 255);
                    uint32_t d = g[i] & DIST_CAP, e = k[i] > d ? k[i] - d : 0;
                    g[i] |= (e < OCT_MAX ? e : OCT_MAX) << (VX__GRID_OCT_SHIFT + 3 * o);
                }
    }
}

static void fill_empty(uint32_t* g, uint32_t n, uint32_t* queue, bool octants) {
    fill_distances(g, n, queue);
    if (octants) fill_octants(g, n, (uint8_t*)queue); /* (the queue's n^3 words are done with: n^3 bytes of them) */
}

static vx_result layout(vx__grid_bricks* b, uint32_t depth, uint32_t top, const uint32_t org[3], uint64_t base,
                        const uint32_t* at, vx__grid_words* out, vx_error* err);

vx_result vx__grid_layout(vx__grid_bricks* b, uint32_t depth, uint32_t top, const uint32_t org[3], uint64_t base,
                          vx__grid_words* out, vx_error* err) {
    return layout(b, depth, top, org, base, NULL, out, err);
}

/* vx__grid_layout; at (not NULL): brick i is at word address at[i] already (another grid's), not written. */
static vx_result layout(vx__grid_bricks* b, uint32_t depth, uint32_t top, const uint32_t org[3], uint64_t base,
                        const uint32_t* at, vx__grid_words* out, vx_error* err) {
    const vx_allocator* a = b->alloc;
    if (depth < 3 || top < 1 || top > VX__GRID_MAX_TOP || depth < 3 * top || depth - 3 * top > 10)
        return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "grid: no layout for a 2^%u cube with its root at level %u",
                       depth, top);
    uint64_t R = (uint64_t)1 << (depth - 3 * top), R3 = R * R * R;
    bool oct = vx__grid_octants(depth, top); /* the empty entries' octant extents (render/grid.h) */
    size_t root = out->n, nb = b->bits.n / 16;
    /* every address below EMPTY: root, bricks and at most one node per brick and level */
    if (base + root + R3 + 16 * (uint64_t)nb + 512 * (uint64_t)nb * (top - 1) >= EMPTY)
        return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "grid: %zu bricks and a %llu^3 root over 2^31 words", nb,
                       (unsigned long long)R);
    uint32_t* queue = vx_alloc(a, (R3 > 512 ? R3 : 512) * 4);
    vx__grid_words cc = {0}, ca = {0}; /* the cells of the level being placed: coordinates (3 words) and address */
    vx_result r = VX_OK;
    size_t own = at ? 0 : b->bits.n; /* the bricks' words written here */
    if (!queue || !vx__grid_words_grow(a, out, R3 + own) || !vx__grid_words_grow(a, &cc, b->coords.n) ||
        !vx__grid_words_grow(a, &ca, nb)) {
        r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "grid: out of memory for %zu bricks", nb);
        goto done;
    }
    for (uint64_t i = 0; i < R3; i++) out->w[root + i] = EMPTY;
    if (own) memcpy(out->w + root + R3, b->bits.w, own * 4);
    /* the bricks' coordinates in the cube from org (in bricks), each checked inside it: the root's index
     * below comes from them */
    uint32_t ob[3] = {org ? org[0] >> 3 : 0, org ? org[1] >> 3 : 0, org ? org[2] >> 3 : 0};
    uint64_t side = (uint64_t)1 << (depth - 3);
    for (size_t i = 0; i < b->coords.n; i++) {
        uint32_t c = b->coords.w[i], o = ob[i % 3];
        if (c < o || c - o >= side) {
            r = vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "grid: brick %u,%u,%u outside the 2^%u cube at %u,%u,%u",
                        b->coords.w[i - i % 3], b->coords.w[i - i % 3 + 1], b->coords.w[i - i % 3 + 2], depth,
                        8 * ob[0], 8 * ob[1], 8 * ob[2]);
            goto done;
        }
        cc.w[i] = c - o;
    }
    out->n = root + R3 + own;
    cc.n = b->coords.n;
    for (size_t i = 0; i < nb; i++) ca.w[ca.n++] = at ? at[i] : (uint32_t)(base + root + R3 + 16 * i);
    for (uint32_t lv = 1; lv < top && !r; lv++) {
        /* nodes of level lv + 1 cells, each the 8^3 level-lv cells below it */
        uint64_t* pk = NULL;
        uint32_t* pv = NULL;
        size_t pcap = 0, pn = 0;
        vx__grid_words pc = {0}, pa = {0};
        for (size_t i = 0; i < ca.n && !r; i++) {
            uint32_t ni;
            bool added;
            if (!map_get(a, &pk, &pv, &pcap, &pn, pack(cc.w[3 * i] >> 3, cc.w[3 * i + 1] >> 3, cc.w[3 * i + 2] >> 3),
                         (uint32_t)pa.n, &ni, &added) ||
                (added && (!vx__grid_words_grow(a, out, 512) || !vx__grid_words_grow(a, &pc, 3) ||
                           !vx__grid_words_grow(a, &pa, 1)))) {
                r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "grid: out of memory for level %u", lv + 1);
                break;
            }
            if (added) {
                for (int k = 0; k < 3; k++) pc.w[pc.n++] = cc.w[3 * i + k] >> 3;
                pa.w[pa.n++] = (uint32_t)(base + out->n);
                for (int e = 0; e < 512; e++) out->w[out->n + e] = EMPTY;
                out->n += 512;
            }
            uint32_t e = (cc.w[3 * i] & 7) | (cc.w[3 * i + 1] & 7) << 3 | (cc.w[3 * i + 2] & 7) << 6;
            out->w[pa.w[ni] - base + e] = ca.w[i];
        }
        for (size_t i = 0; i < pa.n && !r; i++) fill_empty(out->w + (pa.w[i] - base), 8, queue, oct);
        vx_free(a, pk), vx_free(a, pv), vx_free(a, cc.w), vx_free(a, ca.w);
        cc = pc, ca = pa;
    }
    if (!r) {
        for (size_t i = 0; i < ca.n; i++)
            out->w[root + ((uint64_t)cc.w[3 * i + 2] * R + cc.w[3 * i + 1]) * R + cc.w[3 * i]] = ca.w[i];
        fill_empty(out->w + root, (uint32_t)R, queue, oct);
    }
done:
    vx_free(a, cc.w), vx_free(a, ca.w), vx_free(a, queue);
    return r;
}

typedef struct model_ctx {
    vx__grid_bricks* b;
    bool nomem;
    uint32_t off[3]; /* in bricks */
} model_ctx;

static bool block_cb(void* user, uint32_t bx, uint32_t by, uint32_t bz, const uint32_t bits[16]) {
    model_ctx* c = user;
    uint32_t* w = vx__grid_brick_at(c->b, bx + c->off[0], by + c->off[1], bz + c->off[2]);
    if (!w) return c->nomem = true, false;
    for (int j = 0; j < 16; j++) w[j] |= bits[j];
    return true;
}

/* The index of b's brick at brick coordinates (bx, by, bz), UINT32_MAX none. */
static uint32_t brick_find(const vx__grid_bricks* b, uint32_t bx, uint32_t by, uint32_t bz) {
    if (!b->cap) return UINT32_MAX;
    size_t i = slot_of(b->key, b->cap, pack(bx, by, bz));
    return b->key[i] ? b->val[i] : UINT32_MAX;
}

uint32_t vx__grid_brick_record(const vx_svo_model* m, uint32_t bx, uint32_t by, uint32_t bz) {
    if (!m->attrs || m->root == VX_SVO_ROOT_EMPTY) return VX__GRID_RECORD_NONE;
    if (m->root == VX_SVO_ROOT_LEAF)
        return m->root_attr < VX__GRID_RECORD_LEAF ? VX__GRID_RECORD_LEAF | m->root_attr : VX__GRID_RECORD_NONE;
    /* down to the node of level 3 (its cube 8^3 cells: the brick), as vx_svo_model_cell_leaf descends */
    uint32_t i = m->root, x = bx << 3, y = by << 3, z = bz << 3;
    for (uint32_t l = m->depth; l-- > 3;) {
        if (i >= m->node_count) return VX__GRID_RECORD_NONE; /* not a valid tree: no crash */
        uint32_t d = m->nodes[i];
        uint32_t o = ((x >> l) & 1u) | ((y >> l) & 1u) << 1 | ((z >> l) & 1u) << 2;
        uint32_t valid = vx_svo_desc_valid(d), leaf = vx_svo_desc_leaf(d);
        uint32_t p = vx_svo_desc_ptr(d);
        if (!(valid >> o & 1u) || p > i) return VX__GRID_RECORD_NONE;
        uint32_t block = vx_svo_desc_far(d) ? m->nodes[i - p] : i - p;
        if (leaf >> o & 1u) {
            /* the block's attribute word after its inner children (svo.h), the leaf's record from it */
            uint64_t at = (uint64_t)block + popc(valid & ~leaf);
            if (at >= m->node_count) return VX__GRID_RECORD_NONE;
            uint64_t rec = (uint64_t)m->nodes[at] + popc(valid & ((1u << o) - 1u));
            return rec < VX__GRID_RECORD_LEAF ? VX__GRID_RECORD_LEAF | (uint32_t)rec : VX__GRID_RECORD_NONE;
        }
        i = block + popc(valid & ~leaf & ((1u << o) - 1u));
    }
    return i < VX__GRID_RECORD_LEAF ? i : VX__GRID_RECORD_NONE;
}

vx_result vx__grid_records(const vx__grid_bricks* b, vx__grid_record_model_fn model, void* user, uint64_t base,
                           uint64_t brick0, vx__grid_words* out, uint32_t* rec, vx_error* err) {
    size_t nb = b->bits.n / 16, at = out->n;
    *rec = 0;
    /* the key: the table's address less brick 0's >> 4 (brick j at brick0 + 16 j has its word at key + (w >> 4)),
     * never 0: the table lies past the bricks */
    uint64_t key = base + at - (brick0 >> 4);
    if (!nb || key >= EMPTY || base + at + nb >= EMPTY) return VX_OK;
    if (!vx__grid_words_grow(b->alloc, out, nb))
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "grid: out of memory for %zu bricks' records", nb);
    bool any = false;
    for (size_t i = 0; i < nb; i++) {
        uint32_t off[3] = {0, 0, 0}, w = 0;
        const vx_svo_model* m = model(user, i, off);
        if (m) {
            const uint32_t* c = &b->coords.w[3 * i];
            w = vx__grid_brick_record(m, c[0] - off[0], c[1] - off[1], c[2] - off[2]);
            if (w == VX__GRID_RECORD_NONE) return VX_OK; /* none at all: the descent from the root */
            any = true;
        }
        out->w[at + i] = w;
    }
    if (any) out->n = at + nb, *rec = (uint32_t)key;
    return VX_OK;
}

static const vx_svo_model* own_model(void* user, size_t brick, uint32_t off[3]) {
    (void)brick, (void)off;
    return user;
}

vx_result vx__grid_model(const vx_allocator* a, const vx_svo_model* m, const uint32_t cb[6], uint64_t base,
                         const vx__grid_share* share, vx__grid_words* out, uint32_t* top, uint32_t* rec, vx_error* err) {
    uint32_t org[3] = {0, 0, 0}, depth = m->depth < 3 ? 3 : m->depth;
    if (cb) depth = vx__grid_cube(cb, m->depth, org);
    *top = vx__grid_top(depth, 0);
    *rec = share ? share->rec : 0;
    size_t root = out->n;
    vx__grid_bricks b = {.alloc = a};
    vx_result r = vx__grid_bricks_add(&b, m, (const uint32_t[3]){0, 0, 0}, err);
    uint32_t* at = NULL; /* with share: each brick's address in the union's */
    size_t nb = b.bits.n / 16;
    if (!r && share && !(at = vx_alloc(a, (nb ? nb : 1) * 4)))
        r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "grid: out of memory for %zu bricks", nb);
    for (size_t i = 0; at && i < nb && !r; i++) {
        const uint32_t* bc = &b.coords.w[3 * i];
        const uint32_t* o = share->off;
        uint32_t j = brick_find(share->bricks, bc[0] + o[0], bc[1] + o[1], bc[2] + o[2]);
        /* the union's brick holds this model's cells and only them (its cube is the model's alone) */
        if (j == UINT32_MAX || memcmp(&share->bricks->bits.w[16 * (size_t)j], &b.bits.w[16 * i], 64))
            r = vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "grid: brick %u,%u,%u is not the union's", bc[0], bc[1],
                        bc[2]);
        else
            at[i] = (uint32_t)(share->base + 16 * (uint64_t)j);
    }
    if (!r) r = layout(&b, depth, *top, org, base, at, out, err);
    if (!r && !share && m->attrs) {
        uint64_t R = (uint64_t)1 << (depth - 3 * *top);
        r = vx__grid_records(&b, own_model, (void*)m, base, base + root + R * R * R, out, rec, err);
    }
    vx_free(a, at);
    vx__grid_bricks_free(&b);
    return r;
}

vx_result vx__grid_bricks_add(vx__grid_bricks* b, const vx_svo_model* m, const uint32_t off[3], vx_error* err) {
    model_ctx c = {b, false, {off[0], off[1], off[2]}};
    vx_result r = vx_svo_decode_blocks(m, block_cb, &c, err);
    if (!r && c.nomem) r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "grid: out of memory collecting bricks");
    return r;
}
