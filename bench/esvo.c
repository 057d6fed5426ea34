/* bench/esvo.c - the ESVO baseline's octree (built from the scene's cells)
 * and its dispatch; see bench/esvo.h. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bench/esvo.h"
#include "esvo.comp.h"

#define ESVO_VALID 0x80000000u
#define ESVO_LEAF 0x40000000u
#define ESVO_MAX_SLOTS (UINT64_C(1) << 30)

typedef struct kernel_frame {
    float fwd[4], rx[4], uy[4], box[4];
    uint32_t dims[4];
    uint32_t extra[12]; /* bench_kernel.extra */
} kernel_frame;

static uint32_t new_group(bench_esvo* e) {
    if (e->slot_count + 8 > ESVO_MAX_SLOTS) {
        e->too_big = true;
        return 0;
    }
    if (e->slot_count + 8 > e->cap) {
        size_t cap = e->cap ? e->cap * 2 : 1u << 16;
        uint32_t* p = realloc(e->slots, cap * 4);
        if (!p) {
            e->too_big = true;
            return 0;
        }
        e->slots = p, e->cap = cap;
    }
    uint32_t g = (uint32_t)e->slot_count;
    memset(e->slots + g, 0, 32);
    e->slot_count += 8;
    return g;
}

/* Inserts one cell (relative to e->lo) top-down; cells arrive in Morton
 * order per model, so the walk starts below the deepest level shared with
 * the previous cell. */
static void insert(bench_esvo* e, int64_t x, int64_t y, int64_t z, uint32_t rgb) {
    uint32_t D = e->depth;
    uint32_t start = 0;
    if (e->have_last) /* the groups of levels above the first differing octant are shared */
        while (start < D - 1) {
            uint32_t b = D - 1 - start;
            if (((x ^ e->last[0]) >> b) | ((y ^ e->last[1]) >> b) | ((z ^ e->last[2]) >> b)) break;
            start++;
        }
    for (uint32_t l = start; l < D && !e->too_big; l++) {
        uint32_t b = D - 1 - l;
        uint32_t oct = (uint32_t)(((x >> b) & 1) | (((y >> b) & 1) << 1) | (((z >> b) & 1) << 2));
        size_t si = (size_t)e->path[l] + oct;
        if (l == D - 1) {
            e->slots[si] = ESVO_VALID | ESVO_LEAF | (rgb & 0xFFFFFFu);
            break;
        }
        if (!(e->slots[si] & ESVO_VALID)) {
            uint32_t g = new_group(e);
            if (e->too_big) return;
            e->slots[si] = ESVO_VALID | g;
        }
        e->path[l + 1] = e->slots[si] & 0x3FFFFFFFu;
    }
    e->last[0] = x, e->last[1] = y, e->last[2] = z;
    e->have_last = true;
}

typedef struct cell_ctx {
    bench_esvo* e;
    const vx_svo_scene* s;
    const vx_svo_model* m;
    double w[12]; /* the instance's grid_from_model (not world: the octree's cells are grid cells) */
} cell_ctx;

static bool cell_cb(void* user, uint32_t x, uint32_t y, uint32_t z, uint32_t attr) {
    cell_ctx* c = user;
    double p[3] = {x + 0.5, y + 0.5, z + 0.5}, q[3];
    vx__affine_apply(c->w, p, q);
    int64_t g[3];
    for (int k = 0; k < 3; k++) {
        g[k] = (int64_t)floor(q[k]) - c->e->lo[k];
        if (g[k] < 0 || g[k] >= ((int64_t)1 << c->e->depth)) return true;
    }
    uint32_t rgb = c->m->attrs ? vx_svo_attr_rgba(c->s, c->m, attr) : 0xFFFFFFu;
    insert(c->e, g[0], g[1], g[2], rgb);
    return !c->e->too_big;
}

/* world_from_grid as a uniform scale k > 0 and a translation t (identity,
 * or a converted mesh's 2^-n and offset); false for any other map. */
static bool grid_scale(const vx_svo_scene* s, double* k, double t[3]) {
    const double* a = s->world_from_grid;
    if (!(a[0] > 0) || a[5] != a[0] || a[10] != a[0] || a[1] != 0 || a[2] != 0 || a[4] != 0 || a[6] != 0 ||
        a[8] != 0 || a[9] != 0)
        return false;
    *k = a[0], t[0] = a[3], t[1] = a[7], t[2] = a[11];
    return true;
}

/* bench_cube in grid cells: the scene's world bounds mapped back through
 * world_from_grid = k x + t (values within 1e-6 of a whole cell snapped to
 * it, so that the round trip does not move the cube by one). */
static void grid_cube(const vx_svo_scene* s, double k, const double t[3], uint32_t min_depth, int64_t lo[3],
                      uint32_t* depth) {
    double wlo[3], whi[3];
    vx_svo_scene_world_bounds(s, wlo, whi);
    int64_t ext = 1;
    for (int c = 0; c < 3; c++) {
        double g0 = (wlo[c] - t[c]) / k, g1 = (whi[c] - t[c]) / k;
        if (fabs(g0 - nearbyint(g0)) < 1e-6) g0 = nearbyint(g0);
        if (fabs(g1 - nearbyint(g1)) < 1e-6) g1 = nearbyint(g1);
        lo[c] = (int64_t)floor(g0);
        int64_t n = (int64_t)ceil(g1) - lo[c];
        if (n > ext) ext = n;
    }
    *depth = min_depth;
    while (((int64_t)1 << *depth) < ext) (*depth)++;
}

void bench_cube(const vx_svo_scene* s, uint32_t min_depth, int64_t lo[3], uint32_t* depth) {
    double wlo[3], whi[3];
    vx_svo_scene_world_bounds(s, wlo, whi);
    int64_t ext = 1;
    for (int k = 0; k < 3; k++) {
        lo[k] = (int64_t)floor(wlo[k]);
        int64_t n = (int64_t)ceil(whi[k]) - lo[k];
        if (n > ext) ext = n;
    }
    *depth = min_depth;
    while (((int64_t)1 << *depth) < ext) (*depth)++;
}

vx_result bench_esvo_create(vx_gpu* gpu, const vx_svo_scene* s, bench_esvo* e, vx_error* err) {
    memset(e, 0, sizeof *e);
    e->gpu = gpu;
    double t0 = vx_time_now();
    /* the octree holds the scene's grid cells (a converted mesh's world_from_grid
     * scales them by 2^-n: the world's unit cells would be 2^n grid cells each);
     * its cube goes to the kernel in world units (bench_esvo_frame) */
    double k, t[3];
    if (!grid_scale(s, &k, t))
        return vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET,
                       "ESVO baseline: world_from_grid is not a uniform scale and translation (--grid-world)");
    grid_cube(s, k, t, 1, e->lo, &e->depth);
    if (e->depth > 22)
        return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "ESVO baseline: %u levels exceed the float traversal's 22",
                       e->depth);
    new_group(e); /* the root's children */
    vx_result r = VX_OK;
    for (uint32_t i = 0; i < s->instance_count && !r && !e->too_big; i++) {
        if (!vx_svo_instance_drawn(s, i)) continue;
        cell_ctx c = {.e = e, .s = s, .m = &s->models[s->instances[i].model]};
        memcpy(c.w, s->instances[i].xform, sizeof c.w);
        e->have_last = false;
        r = vx_svo_decode_model(c.m, cell_cb, &c, err);
    }
    if (!r && e->too_big)
        r = vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "ESVO baseline: more than 2^30 slots (or out of memory)");
    e->build_seconds = vx_time_now() - t0;
    if (!r)
        r = vx__buffer_create(gpu, (VkDeviceSize)e->slot_count * 4, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, false,
                              "esvo slots", &e->buf, err);
    if (!r) r = vx__buffer_upload(gpu, &e->buf, e->slots, (VkDeviceSize)e->slot_count * 4, err);
    free(e->slots);
    e->slots = NULL;
    if (r) bench_esvo_destroy(e);
    return r;
}

void bench_esvo_destroy(bench_esvo* e) {
    if (!e || !e->gpu) return;
    bench_kernel_destroy(e->gpu, &e->k);
    vx__buffer_destroy(e->gpu, &e->buf);
    free(e->slots);
    memset(e, 0, sizeof *e);
}

uint64_t bench_esvo_bytes(const bench_esvo* e) { return (uint64_t)e->slot_count * 4; }

void bench_kernel_destroy(vx_gpu* g, bench_kernel* k) {
    if (!g) return;
    vkDeviceWaitIdle(g->device);
    vx__buffer_destroy(g, &k->out);
    vx__buffer_destroy(g, &k->frame);
}

/* bench_kernel_frame with the cube [lo, lo + side) in world units */
static vx_result kernel_frame_world(vx_gpu* g, bench_kernel* k, const vx_gpu_compute_pipeline_desc* pd,
                                    uint64_t key, vx__buffer* data, const vx_svo_scene* s,
                                    const vx_render_desc* desc, const double lo[3], double side, uint32_t p0,
                                    uint32_t p1, uint32_t repeat, double* seconds, float* depth, uint32_t* steps,
                                    vx_error* err) {
    double blo[3], bhi[3];
    vx_svo_scene_world_bounds(s, blo, bhi);
    vx__frame f;
    vx_result r = vx__frame_setup(blo, bhi, desc, &f, err);
    if (r) return r;
    if (!k->frame.buf) {
        r = vx__buffer_create(g, sizeof(kernel_frame), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, true, "bench frame",
                              &k->frame, err);
        if (!r && !k->frame.map) r = vx_fail(err, VX_ERR_GPU, VX_NO_OFFSET, "bench frame buffer is not host visible");
        if (r) return r;
    }
    VkDeviceSize npx = (VkDeviceSize)f.width * f.height;
    if (!k->out.buf || k->out.size < npx * 8) {
        vx__buffer_destroy(g, &k->out);
        if ((r = vx__buffer_create(g, npx * 8, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, false, "bench out", &k->out, err)))
            return r;
    }
    kernel_frame* ef = k->frame.map;
    memset(ef, 0, sizeof *ef);
    for (int c = 0; c < 3; c++) {
        ef->fwd[c] = (float)f.fwd[c];
        ef->rx[c] = (float)f.rx[c];
        ef->uy[c] = (float)f.uy[c];
        ef->box[c] = (float)(lo[c] - f.ref[c]);
    }
    ef->fwd[3] = (float)f.t_start;
    ef->rx[3] = f.ortho ? 1.0f : 0.0f;
    ef->box[3] = (float)side;
    ef->dims[0] = f.width, ef->dims[1] = f.height, ef->dims[2] = p0, ef->dims[3] = p1;
    memcpy(ef->extra, k->extra, sizeof ef->extra);
    vx__pipeline* p;
    if ((r = vx__pipeline_get(g, key, pd, &p, err))) return r;
    vx__dispatch_desc dd = {.pipeline = p,
                            .buffer_count = 3,
                            .buffers = {&k->frame, data, &k->out},
                            .groups = {(f.width + 7) / 8, (f.height + 7) / 8, 1},
                            .repeat = repeat,
                            .label = pd->label};
    if ((r = vx__dispatch(g, &dd, seconds, err))) return r;
    if (depth || steps) {
        uint32_t* tmp = malloc((size_t)npx * 8);
        if (!tmp) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory");
        r = vx__buffer_download(g, &k->out, tmp, npx * 8, err);
        for (size_t i = 0; !r && i < npx; i++) {
            if (depth) memcpy(&depth[i], &tmp[2 * i], 4);
            if (steps) steps[i] = tmp[2 * i + 1];
        }
        free(tmp);
    }
    return r;
}

vx_result bench_kernel_frame(vx_gpu* g, bench_kernel* k, const vx_gpu_compute_pipeline_desc* pd, uint64_t key,
                             vx__buffer* data, const vx_svo_scene* s, const vx_render_desc* desc,
                             const int64_t lo[3], double side, uint32_t p0, uint32_t p1, uint32_t repeat,
                             double* seconds, float* depth, uint32_t* steps, vx_error* err) {
    double wlo[3] = {(double)lo[0], (double)lo[1], (double)lo[2]};
    return kernel_frame_world(g, k, pd, key, data, s, desc, wlo, side, p0, p1, repeat, seconds, depth, steps, err);
}

vx_result bench_esvo_frame(bench_esvo* e, const vx_svo_scene* s, const vx_render_desc* desc, uint32_t repeat,
                           double* seconds, float* depth, uint32_t* steps, vx_error* err) {
    vx_gpu_compute_pipeline_desc pd = {.spirv = e->spv ? e->spv : vx__esvo_spv_arr,
                                       .spirv_size = e->spv ? e->spv_bytes : sizeof vx__esvo_spv_arr,
                                       .binding_count = 3, .label = "esvo"};
    pd.bindings[0] = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
    pd.bindings[1] = pd.bindings[2] = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    /* a variant kernel has a key of its own, from its words (the pipeline
     * cache is the device's; render_bench --esvo-kernels runs several) */
    uint64_t key = UINT64_C(0xE5F0E5F0);
    if (e->spv) {
        key = UINT64_C(1469598103934665603); /* FNV-1a */
        for (size_t i = 0; i < e->spv_bytes / 4; i++) key = (key ^ e->spv[i]) * UINT64_C(1099511628211);
        key |= UINT64_C(1) << 63;
    }
    /* the cube from grid cells to world units (identity: lo and 2^depth as they are) */
    double k, t[3], wlo[3];
    if (!grid_scale(s, &k, t))
        return vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET,
                       "ESVO baseline: world_from_grid is not a uniform scale and translation (--grid-world)");
    for (int c = 0; c < 3; c++) wlo[c] = k * (double)e->lo[c] + t[c];
    return kernel_frame_world(e->gpu, &e->k, &pd, key, &e->buf, s, desc, wlo, k * (double)((int64_t)1 << e->depth),
                              0, 0, repeat, seconds, depth, steps, err);
}
