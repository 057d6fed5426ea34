/* bench/brickgrid.c - the grid hierarchy prototype's build (from the
 * scene's cells) and its dispatch; see bench/brickgrid.h.
 *
 * Levels: a level-k cell is 8^k cells wide. Level 0 are the cells; a
 * level-1 cell is a brick (16 words, bit x + 8 y + 64 z its cell (x, y, z));
 * a node (512 words, entry x + 8 y + 64 z) holds the 8^3 level-(k-1) cells
 * of one level-k cell; the root is a dense R^3 grid of level-`top` cells, R
 * = 2^depth / 8^top at most 128 (8 MiB). An entry below 2^31 is the word address of
 * its cell's node or brick; 2^31 | d marks an empty cell whose nearest
 * occupied cell of the same level is d cells away in the Chebyshev metric,
 * within its node (nodes) or the root grid (root), so every cell there
 * within d - 1 of it is empty. Buffer: an 8-word header (top, R, the
 * occupied cells' box [lo, hi) in cells), the root, the bricks, the nodes. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bench/brickgrid.h"
#include "brickgrid.comp.h"

enum { HEADER = 8, ROOT_LOG = 7, DIST_CAP = 0xFFFF }; /* ROOT_LOG: the root at most 2^7 = 128 wide by default */
#define EMPTY UINT32_C(0x80000000)

/* Growing word arrays and a hash from a cell's packed coordinates to an index. */
typedef struct words {
    uint32_t* w;
    uint64_t n, cap;
} words;

static bool words_grow(words* a, uint64_t add) {
    if (a->n + add <= a->cap) return true;
    uint64_t c = a->cap ? a->cap : 4096;
    while (c < a->n + add) c *= 2;
    uint32_t* w = realloc(a->w, c * 4);
    if (!w) return false;
    a->w = w, a->cap = c;
    return true;
}

typedef struct cell_map {
    uint64_t* key; /* packed coordinates + 1 (0: free) */
    uint32_t* val;
    uint64_t cap, n;
} cell_map;

static uint64_t pack(const uint64_t c[3]) { return c[0] | c[1] << 20 | c[2] << 40; }

static uint64_t slot_of(const cell_map* m, uint64_t k) {
    uint64_t h = (k * UINT64_C(0x9E3779B97F4A7C15)) >> 17, i = h & (m->cap - 1);
    while (m->key[i] && m->key[i] != k + 1) i = (i + 1) & (m->cap - 1);
    return i;
}

/* The index of cell k, *added true when new (given index next). */
static bool map_get(cell_map* m, uint64_t k, uint32_t next, uint32_t* out, bool* added) {
    if (2 * (m->n + 1) > m->cap) {
        cell_map g = {.cap = m->cap ? 2 * m->cap : 4096};
        g.key = calloc(g.cap, sizeof *g.key), g.val = malloc(g.cap * sizeof *g.val);
        if (!g.key || !g.val) return free(g.key), free(g.val), false;
        for (uint64_t i = 0; i < m->cap; i++)
            if (m->key[i]) {
                uint64_t j = slot_of(&g, m->key[i] - 1);
                g.key[j] = m->key[i], g.val[j] = m->val[i];
            }
        g.n = m->n;
        free(m->key), free(m->val);
        *m = g;
    }
    uint64_t i = slot_of(m, k);
    *added = !m->key[i];
    if (*added) m->key[i] = k + 1, m->val[i] = next, m->n++;
    *out = m->val[i];
    return true;
}

typedef struct brick_ctx {
    bench_brick* m;
    cell_map map;   /* brick coordinates -> brick index */
    words bricks;   /* 16 words each */
    words coords;   /* each brick's coordinates, 3 words */
    uint64_t lo[3], hi[3];
    double x[12];
    uint64_t off[3]; /* block_cb's offset in bricks */
    bool nomem;
} brick_ctx;

/* The brick at brick coordinates b (added empty if new); NULL out of memory. */
static uint32_t* brick_at(brick_ctx* c, const uint64_t b[3]) {
    uint32_t bi;
    bool added;
    if (!map_get(&c->map, pack(b), (uint32_t)c->m->bricks, &bi, &added)) return c->nomem = true, NULL;
    if (added) {
        if (!words_grow(&c->bricks, 16) || !words_grow(&c->coords, 3)) return c->nomem = true, NULL;
        memset(c->bricks.w + c->bricks.n, 0, 64);
        c->bricks.n += 16, c->m->bricks++;
        for (int k = 0; k < 3; k++) c->coords.w[c->coords.n++] = (uint32_t)b[k];
    }
    return &c->bricks.w[(uint64_t)bi * 16];
}

static void grow_box(brick_ctx* c, const uint64_t g[3]) {
    for (int k = 0; k < 3; k++) {
        if (g[k] < c->lo[k]) c->lo[k] = g[k];
        if (g[k] + 1 > c->hi[k]) c->hi[k] = g[k] + 1;
    }
}

static bool cell_cb(void* user, uint32_t x, uint32_t y, uint32_t z, uint32_t attr) {
    (void)attr;
    brick_ctx* c = user;
    bench_brick* m = c->m;
    double p[3] = {x + 0.5, y + 0.5, z + 0.5}, q[3];
    vx__affine_apply(c->x, p, q);
    uint64_t g[3], b[3];
    for (int k = 0; k < 3; k++) {
        int64_t v = (int64_t)floor(q[k]) - m->lo[k];
        if (v < 0 || v >= ((int64_t)1 << m->depth)) return true;
        g[k] = (uint64_t)v, b[k] = g[k] >> 3;
    }
    grow_box(c, g);
    uint32_t* w = brick_at(c, b);
    if (!w) return false;
    uint32_t i = (uint32_t)((g[0] & 7) | (g[1] & 7) << 3 | (g[2] & 7) << 6);
    if (!(w[i >> 5] >> (i & 31) & 1)) m->cells++;
    w[i >> 5] |= UINT32_C(1) << (i & 31);
    return true;
}

/* An instance whose grid maps to the cube by a translation of whole bricks
 * (vx_svo_decode_blocks' blocks are the cube's bricks): its blocks, offset
 * by off bricks, ORed in (instances may share a brick). */
static bool block_cb(void* user, uint32_t bx, uint32_t by, uint32_t bz, const uint32_t bits[16]) {
    brick_ctx* c = user;
    uint64_t b[3] = {bx + c->off[0], by + c->off[1], bz + c->off[2]};
    for (int k = 0; k < 3; k++)
        if (b[k] >= ((uint64_t)1 << (c->m->depth - 3))) return true; /* outside the cube: not drawn (as cell_cb) */
    uint32_t* w = brick_at(c, b);
    if (!w) return false;
    for (int j = 0; j < 16; j++) {
        uint32_t add = bits[j] & ~w[j];
        c->m->cells += (uint64_t)__builtin_popcount(add);
        w[j] |= bits[j];
        for (uint32_t v = bits[j]; v; v &= v - 1) { /* the box: only a block's first and last cells could move it, */
            uint32_t i = (uint32_t)j * 32 + (uint32_t)__builtin_ctz(v); /* but a block is at most 512 cells */
            uint64_t g[3] = {8 * b[0] + (i & 7), 8 * b[1] + (i >> 3 & 7), 8 * b[2] + (i >> 6)};
            grow_box(c, g);
        }
    }
    return true;
}

/* Whether world-from-grid x is a translation by whole bricks from the cube's
 * corner lo: off = (translation - lo) / 8 then. */
static bool brick_aligned(const double x[12], const int64_t lo[3], uint64_t off[3]) {
    static const double id[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    for (int r = 0; r < 3; r++)
        for (int k = 0; k < 3; k++)
            if (x[4 * r + k] != id[3 * r + k]) return false;
    for (int k = 0; k < 3; k++) {
        double t = x[4 * k + 3] - (double)lo[k];
        if (t != floor(t) || t < 0 || fmod(t, 8) != 0) return false;
        off[k] = (uint64_t)t / 8;
    }
    return true;
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

vx_result bench_brick_create(vx_gpu* gpu, const vx_svo_scene* s, uint32_t max_depth, uint32_t root_log, bench_brick* m,
                             vx_error* err) {
    memset(m, 0, sizeof *m);
    m->gpu = gpu;
    double t0 = vx_time_now();
    bench_cube(s, 3, m->lo, &m->depth);
    if (m->depth > max_depth || m->depth > 20)
        return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "brick grid: a cube 2^%u cells wide is over the limit 2^%u",
                       m->depth, max_depth < 20 ? max_depth : 20);
    uint32_t top = 1;
    if (!root_log) root_log = ROOT_LOG;
    while ((m->depth - 3 * top) > root_log && m->depth > 3 * (top + 1)) top++; /* R = 2^(depth - 3 top) at most 2^root_log */
    if (top > 3)
        return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "brick grid: a cube 2^%u cells wide needs %u levels, at most 3",
                       m->depth, top);
    uint64_t R = (uint64_t)1 << (m->depth - 3 * top), R3 = R * R * R;
    m->top = top;
    brick_ctx c = {.m = m, .lo = {UINT64_MAX, UINT64_MAX, UINT64_MAX}};
    vx_result r = VX_OK;
    for (uint32_t i = 0; i < s->instance_count && !r; i++) {
        if (!vx_svo_instance_drawn(s, i)) continue;
        vx_svo_instance_world(s, &s->instances[i], c.x);
        const vx_svo_model* md = &s->models[s->instances[i].model];
        /* whole bricks where the instance allows (a terrain's 2^28 cells as 2^19 blocks), else cell by cell */
        r = brick_aligned(c.x, m->lo, c.off) ? vx_svo_decode_blocks(md, block_cb, &c, err)
                                               : vx_svo_decode_model(md, cell_cb, &c, err);
        if (c.nomem) r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "brick grid: out of memory");
    }
    /* the buffer: header, root, bricks, then each level's nodes bottom up */
    words out = {0};
    uint32_t* queue = malloc((R3 > 512 ? R3 : 512) * 4);
    if (!r && (!queue || !words_grow(&out, HEADER + R3 + c.bricks.n)))
        r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "brick grid: out of memory");
    if (!r && out.w) {
        memset(out.w, 0, HEADER * 4);
        out.w[0] = top, out.w[1] = (uint32_t)R;
        for (int k = 0; k < 3; k++)
            out.w[2 + k] = m->cells ? (uint32_t)c.lo[k] : 0, out.w[5 + k] = m->cells ? (uint32_t)c.hi[k] : 0;
        for (uint64_t i = 0; i < R3; i++) out.w[HEADER + i] = EMPTY;
        memcpy(out.w + HEADER + R3, c.bricks.w, c.bricks.n * 4);
        out.n = HEADER + R3 + c.bricks.n;
    }
    /* the cells of the level being placed: coordinates (3 words) and address */
    words cc = c.coords, ca = {0};
    c.coords = (words){0};
    if (!r && !words_grow(&ca, m->bricks)) r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "brick grid: out of memory");
    for (uint64_t i = 0; !r && i < m->bricks; i++) ca.w[ca.n++] = (uint32_t)(HEADER + R3 + 16 * i);
    for (uint32_t lv = 1; lv < top && !r; lv++) {
        /* nodes of level lv + 1 cells, each the 8^3 level-lv cells below it */
        cell_map pm = {0};
        words pc = {0}, pa = {0};
        for (uint64_t i = 0; i < ca.n && !r; i++) {
            uint64_t p[3] = {cc.w[3 * i] >> 3, cc.w[3 * i + 1] >> 3, cc.w[3 * i + 2] >> 3};
            uint32_t ni;
            bool added;
            if (!map_get(&pm, pack(p), (uint32_t)pa.n, &ni, &added) ||
                (added && (!words_grow(&out, 512) || !words_grow(&pc, 3) || !words_grow(&pa, 1)))) {
                r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "brick grid: out of memory");
                break;
            }
            if (added) {
                if (out.n + 512 >= EMPTY) {
                    r = vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "brick grid: over 2^31 words");
                    break;
                }
                for (int k = 0; k < 3; k++) pc.w[pc.n++] = (uint32_t)p[k];
                pa.w[pa.n++] = (uint32_t)out.n;
                for (int e = 0; e < 512; e++) out.w[out.n + e] = EMPTY;
                out.n += 512;
            }
            uint32_t e = (cc.w[3 * i] & 7) | (cc.w[3 * i + 1] & 7) << 3 | (cc.w[3 * i + 2] & 7) << 6;
            out.w[pa.w[ni] + e] = ca.w[i];
        }
        for (uint64_t i = 0; i < pa.n && !r; i++) fill_distances(out.w + pa.w[i], 8, queue);
        free(pm.key), free(pm.val), free(cc.w), free(ca.w);
        cc = pc, ca = pa;
    }
    if (!r) {
        R3 = R * R * R;
        for (uint64_t i = 0; i < ca.n; i++)
            out.w[HEADER + ((uint64_t)cc.w[3 * i + 2] * R + cc.w[3 * i + 1]) * R + cc.w[3 * i]] = ca.w[i];
        fill_distances(out.w + HEADER, R, queue);
        m->words = out.n;
        /* the kernel reads the header's values from its Frame block (a uniform, not a load per ray) */
        memcpy(m->k.extra, out.w, sizeof m->k.extra);
    }
    free(cc.w), free(ca.w), free(queue), free(c.map.key), free(c.map.val), free(c.bricks.w), free(c.coords.w);
    m->build_seconds = vx_time_now() - t0;
    if (!r && out.n >= EMPTY) r = vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "brick grid: over 2^31 words");
    if (!r)
        r = vx__buffer_create(gpu, (VkDeviceSize)m->words * 4, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, false,
                              "brick grid", &m->buf, err);
    if (!r) r = vx__buffer_upload(gpu, &m->buf, out.w, (VkDeviceSize)m->words * 4, err);
    free(out.w);
    if (r) bench_brick_destroy(m);
    return r;
}

void bench_brick_destroy(bench_brick* m) {
    if (!m || !m->gpu) return;
    bench_kernel_destroy(m->gpu, &m->k);
    vx__buffer_destroy(m->gpu, &m->buf);
    memset(m, 0, sizeof *m);
}

uint64_t bench_brick_bytes(const bench_brick* m) { return m->words * 4; }

/* The pixels [x0, x1) x [y0, y1) whose rays can meet the occupied cells'
 * box (the kernel's Frame words 8-11): the box's corners projected through
 * the camera, 2 pixels of margin; the whole frame where a corner is not in
 * front of the eye. The rays outside it write a miss without being made:
 * most of an overview's pixels. */
static void screen_rect(const bench_brick* m, const vx__frame* f, uint32_t rect[4]) {
    rect[0] = 0, rect[1] = 0, rect[2] = f->width, rect[3] = f->height;
    double fmin[2] = {1e300, 1e300}, fmax[2] = {-1e300, -1e300};
    double ff = 0, rr = 0, uu = 0;
    for (int k = 0; k < 3; k++) ff += f->fwd[k] * f->fwd[k], rr += f->rx[k] * f->rx[k], uu += f->uy[k] * f->uy[k];
    for (int c = 0; c < 8; c++) {
        double y[3], s = 0, u = 0, v = 0;
        for (int k = 0; k < 3; k++) {
            uint32_t cell = (c >> k & 1) ? m->k.extra[5 + k] : m->k.extra[2 + k];
            y[k] = (double)(m->lo[k] + (int64_t)cell) - f->ref[k];
            if (!f->ortho) y[k] += f->t_start * f->fwd[k]; /* from the eye, -t_start fwd from the reference */
            s += y[k] * f->fwd[k] / ff, u += y[k] * f->rx[k] / rr, v += y[k] * f->uy[k] / uu;
        }
        if (!f->ortho) {
            if (!(s > 1e-9)) return;
            u /= s, v /= s;
        }
        double x = (u + 1) / 2 * f->width - 0.5, yp = (1 - v) / 2 * f->height - 0.5;
        fmin[0] = fmin[0] < x ? fmin[0] : x, fmax[0] = fmax[0] > x ? fmax[0] : x;
        fmin[1] = fmin[1] < yp ? fmin[1] : yp, fmax[1] = fmax[1] > yp ? fmax[1] : yp;
    }
    double n[2] = {f->width, f->height};
    for (int a = 0; a < 2; a++) {
        double lo = floor(fmin[a]) - 2, hi = ceil(fmax[a]) + 3;
        rect[a] = lo <= 0 ? 0 : lo >= n[a] ? (uint32_t)n[a] : (uint32_t)lo;
        rect[2 + a] = hi <= 0 ? 0 : hi >= n[a] ? (uint32_t)n[a] : (uint32_t)hi;
    }
}

vx_result bench_brick_frame(bench_brick* m, uint32_t variant, const vx_svo_scene* s, const vx_render_desc* desc,
                            uint32_t repeat, double* seconds, float* depth, uint32_t* steps, vx_error* err) {
    double blo[3], bhi[3];
    vx_svo_scene_world_bounds(s, blo, bhi);
    vx__frame f;
    vx_result r = vx__frame_setup(blo, bhi, desc, &f, err);
    if (r) return r;
    screen_rect(m, &f, m->k.extra + 8);
    vx_gpu_compute_pipeline_desc pd = {.spirv = vx__brickgrid_spv_arr, .spirv_size = sizeof vx__brickgrid_spv_arr,
                                       .binding_count = 3, .spec_count = 3, .spec = {1, m->top, variant},
                                       .label = "brickgrid"};
    pd.bindings[0] = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
    pd.bindings[1] = pd.bindings[2] = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    return bench_kernel_frame(m->gpu, &m->k, &pd, UINT64_C(0x31B00000) + 16 * m->top + variant, &m->buf, s, desc, m->lo,
                              (double)((int64_t)1 << m->depth), m->depth, 0, repeat, seconds, depth, steps, err);
}
