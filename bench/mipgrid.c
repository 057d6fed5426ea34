/* bench/mipgrid.c - the occupancy pyramid prototype's build (from the
 * scene's cells) and its dispatch; see bench/mipgrid.h. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bench/mipgrid.h"
#include "mipgrid.comp.h"

/* First word of level l in a cube 2^d cells wide, coarse levels first after
 * a 32-word header: the three levels of one brick (l >= d - 2) take two
 * words each, level l < d - 2 takes 2 * 8^(d - l - 2) (mipgrid.comp computes
 * the same). */
static uint64_t level_base(uint32_t d, uint32_t l) {
    int k = (int)d - (int)l - 2;
    if (k <= 0) return (uint64_t)(36 + 2 * k);
    return 36 + ((UINT64_C(2) << 3 * k) - 2) / 7;
}

static uint64_t level_words(uint32_t d, uint32_t l) {
    int k = (int)d - (int)l - 2;
    return k <= 0 ? 2 : UINT64_C(2) << 3 * k;
}

/* Word and bit of cell q (level-l coordinates) */
static uint64_t cell_word(uint32_t d, uint32_t l, const uint64_t q[3], uint32_t* bit) {
    int k = (int)d - (int)l - 2;
    uint32_t bl = k > 0 ? (uint32_t)k : 0;
    uint64_t b = (((q[2] >> 2) << bl | (q[1] >> 2)) << bl) | (q[0] >> 2);
    uint32_t i = (uint32_t)((q[0] & 3) | (q[1] & 3) << 2 | (q[2] & 3) << 4);
    *bit = i & 31;
    return level_base(d, l) + 2 * b + (i >> 5);
}

typedef struct mip_ctx {
    bench_mip* m;
    uint32_t* w;
    double x[12];
} mip_ctx;

static bool cell_cb(void* user, uint32_t x, uint32_t y, uint32_t z, uint32_t attr) {
    (void)attr;
    mip_ctx* c = user;
    double p[3] = {x + 0.5, y + 0.5, z + 0.5}, q[3];
    vx__affine_apply(c->x, p, q);
    uint64_t g[3];
    for (int k = 0; k < 3; k++) {
        int64_t v = (int64_t)floor(q[k]) - c->m->lo[k];
        if (v < 0 || v >= ((int64_t)1 << c->m->depth)) return true;
        g[k] = (uint64_t)v;
    }
    uint32_t bit;
    uint64_t wi = cell_word(c->m->depth, 0, g, &bit);
    if (!(c->w[wi] >> bit & 1)) c->m->cells++;
    c->w[wi] |= UINT32_C(1) << bit;
    return true;
}

vx_result bench_mip_create(vx_gpu* gpu, const vx_svo_scene* s, uint32_t max_depth, bench_mip* m, vx_error* err) {
    memset(m, 0, sizeof *m);
    m->gpu = gpu;
    double t0 = vx_time_now();
    bench_cube(s, 1, m->lo, &m->depth);
    if (m->depth > max_depth || m->depth > 11)
        return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "occupancy pyramid: a cube 2^%u cells wide is over the limit 2^%u",
                       m->depth, max_depth < 11 ? max_depth : 11);
    uint32_t D = m->depth;
    m->words = level_base(D, 0) + level_words(D, 0);
    uint32_t* w = calloc(m->words, 4);
    if (!w) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "occupancy pyramid: out of memory");
    for (uint32_t l = 0; l <= D && l < 32; l++) w[l] = (uint32_t)level_base(D, l); /* header: for readers */
    vx_result r = VX_OK;
    for (uint32_t i = 0; i < s->instance_count && !r; i++) {
        if (!vx_svo_instance_drawn(s, i)) continue;
        mip_ctx c = {.m = m, .w = w};
        const vx_svo_model* md = &s->models[s->instances[i].model];
        vx_svo_instance_world(s, &s->instances[i], c.x);
        r = vx_svo_decode_model(md, cell_cb, &c, err);
    }
    /* each level from the one below: a cell is occupied where any of its eight children is */
    for (uint32_t l = 1; l <= D && !r; l++) {
        uint64_t n = (uint64_t)1 << (D - l + 1), base = level_base(D, l - 1), nw = level_words(D, l - 1);
        int k = (int)D - (int)(l - 1) - 2;
        uint32_t bl = k > 0 ? (uint32_t)k : 0;
        for (uint64_t wi = 0; wi < nw; wi++) {
            uint32_t v = w[base + wi];
            while (v) {
                uint32_t b = (uint32_t)__builtin_ctz(v);
                v &= v - 1;
                uint32_t i = (uint32_t)(wi & 1) * 32 + b;
                uint64_t br = wi >> 1, mask = ((uint64_t)1 << bl) - 1;
                uint64_t q[3] = {((br & mask) << 2) | (i & 3), (((br >> bl) & mask) << 2) | (i >> 2 & 3),
                                 ((br >> 2 * bl) << 2) | (i >> 4 & 3)};
                if (q[0] >= n || q[1] >= n || q[2] >= n) continue;
                for (int a = 0; a < 3; a++) q[a] >>= 1;
                uint32_t pb;
                uint64_t pw = cell_word(D, l, q, &pb);
                w[pw] |= UINT32_C(1) << pb;
            }
        }
    }
    m->build_seconds = vx_time_now() - t0;
    if (!r)
        r = vx__buffer_create(gpu, (VkDeviceSize)m->words * 4, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, false,
                              "mip bits", &m->buf, err);
    if (!r) r = vx__buffer_upload(gpu, &m->buf, w, (VkDeviceSize)m->words * 4, err);
    free(w);
    if (r) bench_mip_destroy(m);
    return r;
}

void bench_mip_destroy(bench_mip* m) {
    if (!m || !m->gpu) return;
    bench_kernel_destroy(m->gpu, &m->k);
    vx__buffer_destroy(m->gpu, &m->buf);
    memset(m, 0, sizeof *m);
}

uint64_t bench_mip_bytes(const bench_mip* m) { return m->words * 4; }

vx_result bench_mip_frame(bench_mip* m, uint32_t variant, const vx_svo_scene* s, const vx_render_desc* desc,
                          uint32_t repeat, double* seconds, float* depth, uint32_t* steps, vx_error* err) {
    vx_gpu_compute_pipeline_desc pd = {.spirv = vx__mipgrid_spv_arr, .spirv_size = sizeof vx__mipgrid_spv_arr,
                                       .binding_count = 3, .spec_count = 1, .spec = {variant}, .label = "mipgrid"};
    pd.bindings[0] = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
    pd.bindings[1] = pd.bindings[2] = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    return bench_kernel_frame(m->gpu, &m->k, &pd, UINT64_C(0x319C0000) + variant, &m->buf, s, desc, m->lo,
                              (double)((int64_t)1 << m->depth), m->depth, 0, repeat, seconds, depth, steps, err);
}
