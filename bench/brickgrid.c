/* bench/brickgrid.c - the grid hierarchy prototype's build (from the
 * scene's cells) and its dispatch; see bench/brickgrid.h.
 *
 * The layout is the tracer's (render/grid.h: bricks of 512 bits, nodes of
 * 8^3 entries, a dense root, empty entries holding their Chebyshev distance),
 * here over the whole scene's cells in one cube, root at most 128 wide by
 * default. Buffer: an 8-word header (top, R, the occupied cells' box [lo,
 * hi) in cells), then the grid. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bench/brickgrid.h"
#include "render/grid.h"
#include "brickgrid.comp.h"

enum { HEADER = 8 };

typedef struct brick_ctx {
    bench_brick* m;
    vx__grid_bricks b;
    uint64_t lo[3], hi[3];
    double x[12];
    uint64_t off[3]; /* block_cb's offset in bricks */
    bool nomem;
} brick_ctx;

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
    uint32_t* w = vx__grid_brick_at(&c->b, (uint32_t)b[0], (uint32_t)b[1], (uint32_t)b[2]);
    if (!w) return c->nomem = true, false;
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
    uint32_t* w = vx__grid_brick_at(&c->b, (uint32_t)b[0], (uint32_t)b[1], (uint32_t)b[2]);
    if (!w) return c->nomem = true, false;
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

vx_result bench_brick_create(vx_gpu* gpu, const vx_svo_scene* s, uint32_t max_depth, uint32_t root_log, bench_brick* m,
                             vx_error* err) {
    memset(m, 0, sizeof *m);
    m->gpu = gpu;
    double t0 = vx_time_now();
    bench_cube(s, 3, m->lo, &m->depth);
    if (m->depth > max_depth || m->depth > 20)
        return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "brick grid: a cube 2^%u cells wide is over the limit 2^%u",
                       m->depth, max_depth < 20 ? max_depth : 20);
    uint32_t top = vx__grid_top(m->depth, root_log);
    if (top > 3)
        return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "brick grid: a cube 2^%u cells wide needs %u levels, at most 3",
                       m->depth, top);
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
    m->bricks = c.b.bits.n / 16;
    /* the buffer: header, then the grid (render/grid.h: root, bricks, each level's nodes bottom up) */
    vx__grid_words out = {0};
    if (!r && !vx__grid_words_grow(NULL, &out, HEADER)) r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "brick grid: out of memory");
    if (!r) {
        memset(out.w, 0, HEADER * 4);
        out.w[0] = top, out.w[1] = 1u << (m->depth - 3 * top);
        for (int k = 0; k < 3; k++)
            out.w[2 + k] = m->cells ? (uint32_t)c.lo[k] : 0, out.w[5 + k] = m->cells ? (uint32_t)c.hi[k] : 0;
        out.n = HEADER;
        r = vx__grid_layout(&c.b, m->depth, top, NULL, 0, &out, err);
    }
    if (!r) {
        m->words = out.n;
        /* the kernel reads the header's values from its Frame block (a uniform, not a load per ray) */
        memcpy(m->k.extra, out.w, sizeof m->k.extra);
    }
    vx__grid_bricks_free(&c.b);
    m->build_seconds = vx_time_now() - t0;
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
