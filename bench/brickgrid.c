/* bench/brickgrid.c - the two-level grid prototype's build (from the scene's
 * cells) and its dispatch; see bench/brickgrid.h. Layout of the one buffer:
 * C^3 coarse words (C = 2^depth / 8, x fastest), then 16 words per brick.
 * A coarse word below 2^31 is its brick's index; 2^31 | d marks an empty
 * coarse cell whose nearest occupied coarse cell is d cells away in the
 * Chebyshev metric (every coarse cell within d - 1 of it is empty). A
 * brick's bit x + 8 y + 64 z is its cell (x, y, z). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bench/brickgrid.h"
#include "brickgrid.comp.h"

enum { DIST_CAP = 0xFFFF };

typedef struct brick_ctx {
    bench_brick* m;
    uint32_t* coarse; /* brick index + 1, 0: none yet */
    uint32_t* bricks; /* 16 words each */
    uint64_t cap;     /* bricks allocated */
    double x[12];
    bool nomem;
} brick_ctx;

static bool cell_cb(void* user, uint32_t x, uint32_t y, uint32_t z, uint32_t attr) {
    (void)attr;
    brick_ctx* c = user;
    bench_brick* m = c->m;
    double p[3] = {x + 0.5, y + 0.5, z + 0.5}, q[3];
    vx__affine_apply(c->x, p, q);
    uint64_t g[3];
    for (int k = 0; k < 3; k++) {
        int64_t v = (int64_t)floor(q[k]) - m->lo[k];
        if (v < 0 || v >= ((int64_t)1 << m->depth)) return true;
        g[k] = (uint64_t)v;
    }
    uint64_t C = (uint64_t)1 << (m->depth - 3);
    uint64_t ci = ((g[2] >> 3) * C + (g[1] >> 3)) * C + (g[0] >> 3);
    if (!c->coarse[ci]) {
        if (m->bricks == c->cap) {
            uint64_t n = c->cap ? 2 * c->cap : 1024;
            uint32_t* b = realloc(c->bricks, n * 64);
            if (!b) return c->nomem = true, false;
            memset(b + c->cap * 16, 0, (n - c->cap) * 64);
            c->bricks = b, c->cap = n;
        }
        c->coarse[ci] = (uint32_t)++m->bricks;
    }
    uint32_t i = (uint32_t)((g[0] & 7) | (g[1] & 7) << 3 | (g[2] & 7) << 6);
    uint32_t* w = &c->bricks[(uint64_t)(c->coarse[ci] - 1) * 16 + (i >> 5)];
    if (!(*w >> (i & 31) & 1)) m->cells++;
    *w |= UINT32_C(1) << (i & 31);
    return true;
}

/* Chebyshev distance of every coarse cell to the nearest occupied one: a
 * breadth-first search over the 26 neighbours from all occupied cells at
 * once (a step to any of the 26 is one unit of the metric). */
static bool coarse_distances(const uint32_t* coarse, uint64_t C, uint32_t* dist) {
    uint64_t n = C * C * C;
    uint32_t* queue = malloc(n * sizeof *queue);
    if (!queue) return false;
    uint64_t head = 0, tail = 0;
    for (uint64_t i = 0; i < n; i++) {
        dist[i] = coarse[i] ? 0 : DIST_CAP;
        if (coarse[i]) queue[tail++] = (uint32_t)i;
    }
    while (head < tail) {
        uint64_t i = queue[head++];
        int64_t x = (int64_t)(i % C), y = (int64_t)(i / C % C), z = (int64_t)(i / (C * C));
        uint32_t dn = dist[i] + 1;
        if (dn >= DIST_CAP) continue;
        for (int dz = -1; dz <= 1; dz++)
            for (int dy = -1; dy <= 1; dy++)
                for (int dx = -1; dx <= 1; dx++) {
                    int64_t X = x + dx, Y = y + dy, Z = z + dz;
                    if (X < 0 || Y < 0 || Z < 0 || X >= (int64_t)C || Y >= (int64_t)C || Z >= (int64_t)C) continue;
                    uint64_t j = ((uint64_t)Z * C + (uint64_t)Y) * C + (uint64_t)X;
                    if (dist[j] > dn) dist[j] = dn, queue[tail++] = (uint32_t)j;
                }
    }
    free(queue);
    return true;
}

vx_result bench_brick_create(vx_gpu* gpu, const vx_svo_scene* s, uint32_t max_depth, bench_brick* m, vx_error* err) {
    memset(m, 0, sizeof *m);
    m->gpu = gpu;
    double t0 = vx_time_now();
    double lo[3], hi[3];
    vx_svo_scene_world_bounds(s, lo, hi);
    int64_t ext = 1;
    for (int k = 0; k < 3; k++) {
        m->lo[k] = (int64_t)floor(lo[k]);
        int64_t n = (int64_t)ceil(hi[k]) - m->lo[k];
        if (n > ext) ext = n;
    }
    m->depth = 3;
    while (((int64_t)1 << m->depth) < ext) m->depth++;
    if (m->depth > max_depth || m->depth > 10)
        return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "brick grid: a cube 2^%u cells wide is over the limit 2^%u",
                       m->depth, max_depth < 10 ? max_depth : 10);
    uint64_t C = (uint64_t)1 << (m->depth - 3), n = C * C * C;
    brick_ctx c = {.m = m, .coarse = calloc(n, 4)};
    uint32_t* dist = malloc(n * 4);
    vx_result r = c.coarse && dist ? VX_OK : vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "brick grid: out of memory");
    for (uint32_t i = 0; i < s->instance_count && !r; i++) {
        if (!vx_svo_instance_drawn(s, i)) continue;
        vx_svo_instance_world(s, &s->instances[i], c.x);
        r = vx_svo_decode_model(&s->models[s->instances[i].model], cell_cb, &c, err);
        if (c.nomem) r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "brick grid: out of memory");
    }
    if (!r && !coarse_distances(c.coarse, C, dist))
        r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "brick grid: out of memory");
    uint32_t* w = NULL;
    if (!r) {
        m->words = n + m->bricks * 16;
        if (!(w = malloc(m->words * 4))) r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "brick grid: out of memory");
    }
    if (!r) {
        for (uint64_t i = 0; i < n; i++) w[i] = c.coarse[i] ? c.coarse[i] - 1 : UINT32_C(0x80000000) | dist[i];
        if (m->bricks) memcpy(w + n, c.bricks, m->bricks * 64);
    }
    free(c.coarse), free(c.bricks), free(dist);
    m->build_seconds = vx_time_now() - t0;
    if (!r)
        r = vx__buffer_create(gpu, (VkDeviceSize)m->words * 4, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, false,
                              "brick grid", &m->buf, err);
    if (!r) r = vx__buffer_upload(gpu, &m->buf, w, (VkDeviceSize)m->words * 4, err);
    free(w);
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

vx_result bench_brick_frame(bench_brick* m, uint32_t variant, const vx_svo_scene* s, const vx_render_desc* desc,
                            uint32_t repeat, double* seconds, float* depth, uint32_t* steps, vx_error* err) {
    vx_gpu_compute_pipeline_desc pd = {.spirv = vx__brickgrid_spv_arr, .spirv_size = sizeof vx__brickgrid_spv_arr,
                                       .binding_count = 3, .spec_count = 1, .spec = {variant}, .label = "brickgrid"};
    pd.bindings[0] = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
    pd.bindings[1] = pd.bindings[2] = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    return bench_kernel_frame(m->gpu, &m->k, &pd, UINT64_C(0x31B00000) + variant, &m->buf, s, desc, m->lo,
                              (double)((int64_t)1 << m->depth), m->depth, 0, repeat, seconds, depth, steps, err);
}
