/* convert/mesh_gpu.c - the mesh voxelizer on the GPU (convert/mesh_gpu.h). */
#include "convert/mesh_gpu.h"

#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "convert/mesh_internal.h"
#include "render/gpu.h"

#include "gpuscan.comp.h"
#include "gpusort.comp.h"
#include "meshreduce.comp.h"
#include "meshbuild.comp.h"
#include "meshintern.comp.h"
#include "meshvox.comp.h"

#define BRICK 64u

enum { B_G, B_PAIRS, B_BRICKS, B_COUNTS, B_KEYS, B_RECS, B_TRIMAT, B_MATS, B_IMAGES, B_TEXELS, B_UV, B_COL,
       B_TABLES, B_VALS, B_KEYS2, B_VALS2, B_HIST, B_POS, B_OKEYS, B_ORGBA, B_ONRM, B_OMAT, B_RTABLES, B_READ,
       B_UP, B_DOWN, B_SCAN0, B_SCAN1, B_SCAN2, B_SCAN3, B_REGION, B_IDS, B_UTAB, B_BINFO, B_RINFO, B_ROUT, B_ITA,
       B_ITB, B_START, B_NODES, B_TAB, B_MISC, B_POOL, B_RBASE, B_PDOWN, B_NREP, B_TTAB, B_RNEW, B_EXT, B_RTAB,
       B_RNODE, B_RIDS, B_RFIRST, B_LAY, B_ORD, B_WORDS, B_TEXUP, B_LVL, B_ARGBA, B_ANRM, B_AMAT,
       B_SMATS, B_UVMR, B_UVEM, B_RECX, B_PLANS, B_COUNT };
#define SCAN_LEVELS 4

#define BUILD_MODES 31 /* meshbuild.comp's modes: pipeline P_BUILD + mode */
enum { P_COUNT, P_EMIT, P_HIST, P_SCATTER, P_SCAN, P_ADD, P_FLAG, P_REDUCE, P_IKEY, P_INKEY, P_IFLAG, P_IOUT, P_BUILD,
       P_NUM = P_BUILD + BUILD_MODES };

#define TS_PAIRS 32
#define VX_CONV_MESH_GPU_NEAR_MAX 0x7FFFu /* the largest near pointer (svo/svo.h's descriptor: 15 bits) */
struct vx_conv_mesh_gpu {
    vx_gpu* g;
    const vx_allocator* alloc;
    struct vx_conv_mesh_backend backend;
    vx__pipeline* pipe[P_NUM];
    vx__buffer buf[B_COUNT];
    VkDescriptorPool pool;
    vx_conv_mesh_gpu_stats stats;
    vx_conv_mesh_gpu_build build;
    vx_conv_mesh_gpu_hash hash;
    /* GPU timestamps around the build's steps (stats.build_gpu): pairs
     * written in the open recording, read after its wait */
    VkQueryPool qp; /* VK_NULL_HANDLE: the queue has no timestamps */
    uint32_t nq;
    int qstep[TS_PAIRS];
    uint32_t build_attrs; /* meshbuild.comp's channels (1 rgba, 2 normal, 4 material; 0: no representatives) */
};

typedef struct meshvox_push {
    uint32_t pair_count, attrs, first, mode;
    int32_t size[4];
} meshvox_push;
typedef struct sort_push {
    uint32_t n, shift, ntiles;
} sort_push;
typedef struct intern_push {
    uint32_t n, attrs, perm;
} intern_push;
typedef struct build_push {
    uint32_t n, level, base, mask, attrs, smask, lmask;
} build_push;

/* ---- recording ----------------------------------------------------------------------- */

static vx_result rec_begin(vx_conv_mesh_gpu* m, vx_error* err) {
    VX__VK(vkResetDescriptorPool(m->g->device, m->pool, 0), "vkResetDescriptorPool");
    vx_result r = vx__cmd_begin(m->g, err);
    m->nq = 0;
    if (!r && m->qp) vkCmdResetQueryPool(m->g->cmd, m->qp, 0, 2 * TS_PAIRS);
    return r;
}

/* A timestamp before (ts_begin) and after (ts_end) the commands of build
 * step `step` recorded between them; steps beyond TS_PAIRS pairs a
 * recording go untimed. */
static void ts_end(vx_conv_mesh_gpu* m);
static void ts_begin(vx_conv_mesh_gpu* m, int step) {
    ts_end(m); /* a step still open ends here */
    if (!m->qp || m->nq >= 2 * TS_PAIRS) return;
    m->qstep[m->nq / 2] = step;
    vkCmdWriteTimestamp(m->g->cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, m->qp, m->nq++);
}
static void ts_end(vx_conv_mesh_gpu* m) {
    if (!m->qp || m->nq % 2 == 0) return;
    vkCmdWriteTimestamp(m->g->cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, m->qp, m->nq++);
}

/* Submits the recording, waits, and adds its timed steps to stats.build_gpu. */
static vx_result submit(vx_conv_mesh_gpu* m, vx_error* err) {
    vx_result r = vx__cmd_submit_wait(m->g, err);
    if (r || !m->nq) return r;
    uint64_t t[2 * TS_PAIRS];
    uint32_t n = m->nq & ~1u;
    m->nq = 0;
    if (!n || vkGetQueryPoolResults(m->g->device, m->qp, 0, n, sizeof t, t, 8, VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT) !=
                  VK_SUCCESS)
        return VX_OK; /* timings only */
    double period = (double)m->g->props.limits.timestampPeriod * 1e-9;
    for (uint32_t i = 0; i < n; i += 2) {
        int st = m->qstep[i / 2];
        double dt = (double)(t[i + 1] - t[i]) * period;
        if (st < 8) m->stats.build_gpu[st] += dt;
        else m->stats.vox_gpu[st - 8] += dt;
    }
    return VX_OK;
}

static void barrier(vx_gpu* g) {
    VkMemoryBarrier mb = {.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER,
                          .srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT,
                          .dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT |
                                           VK_ACCESS_TRANSFER_READ_BIT | VK_ACCESS_TRANSFER_WRITE_BIT |
                                           VK_ACCESS_HOST_READ_BIT};
    vkCmdPipelineBarrier(g->cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                         VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT | VK_PIPELINE_STAGE_HOST_BIT,
                         0, 1, &mb, 0, NULL, 0, NULL);
}

/* Records one dispatch of `groups` workgroups (spread over x and y: the
 * shaders number them y * x_count + x) over the buffers ids[n], then a
 * barrier. */
static vx_result stage(vx_conv_mesh_gpu* m, int pipe, const int* ids, uint32_t n, uint64_t groups, const void* push,
                       uint32_t push_size, vx_error* err) {
    vx_gpu* g = m->g;
    if (groups == 0) return VX_OK;
    vx__pipeline* p = m->pipe[pipe];
    VkDescriptorSetAllocateInfo ai = {.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO,
                                      .descriptorPool = m->pool,
                                      .descriptorSetCount = 1,
                                      .pSetLayouts = &p->dsl};
    VkDescriptorSet set;
    VX__VK(vkAllocateDescriptorSets(g->device, &ai, &set), "vkAllocateDescriptorSets");
    VkDescriptorBufferInfo infos[VX_GPU_MAX_BINDINGS];
    VkWriteDescriptorSet w[VX_GPU_MAX_BINDINGS];
    for (uint32_t i = 0; i < n; i++) {
        infos[i] = (VkDescriptorBufferInfo){.buffer = m->buf[ids[i]].buf, .offset = 0, .range = VK_WHOLE_SIZE};
        w[i] = (VkWriteDescriptorSet){.sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET,
                                      .dstSet = set,
                                      .dstBinding = i,
                                      .descriptorCount = 1,
                                      .descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                                      .pBufferInfo = &infos[i]};
    }
    vkUpdateDescriptorSets(g->device, n, w, 0, NULL);
    vkCmdBindPipeline(g->cmd, VK_PIPELINE_BIND_POINT_COMPUTE, p->pipe);
    vkCmdBindDescriptorSets(g->cmd, VK_PIPELINE_BIND_POINT_COMPUTE, p->layout, 0, 1, &set, 0, NULL);
    if (push_size) vkCmdPushConstants(g->cmd, p->layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, push_size, push);
    uint64_t gx = groups < 65535 ? groups : 65535, gy = (groups + gx - 1) / gx;
    if (gy > 65535) return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "GPU voxelizer: %llu workgroups", (unsigned long long)groups);
    vkCmdDispatch(g->cmd, (uint32_t)gx, (uint32_t)gy, 1);
    barrier(g);
    return VX_OK;
}

/* Exclusive prefix sums of buffer id's first n uints, in place (gpuscan.comp),
 * level by level through the scan buffers. */
static vx_result scan(vx_conv_mesh_gpu* m, int id, uint64_t n, int level, vx_error* err) {
    if (n > UINT32_MAX) return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "GPU voxelizer: scan of %llu", (unsigned long long)n);
    if (level >= SCAN_LEVELS) return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "GPU voxelizer: scan too deep");
    uint64_t blocks = (n + 2047) / 2048;
    int sums = B_SCAN0 + level;
    if (m->buf[sums].size < blocks * 4)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "GPU voxelizer: scan buffers not prepared");
    vx_result r;
    uint32_t push = (uint32_t)n;
    int ids[2] = {id, sums};
    if ((r = stage(m, P_SCAN, ids, 2, blocks, &push, 4, err))) return r;
    if (blocks <= 1) return VX_OK;
    if ((r = scan(m, sums, blocks, level + 1, err))) return r;
    return stage(m, P_ADD, ids, 2, blocks, &push, 4, err);
}

/* The scan buffers for n entries, made before recording (a buffer grown
 * while recorded commands use it would be destroyed under them). */
static vx_result scan_prepare(vx_conv_mesh_gpu* m, uint64_t n, vx_error* err) {
    for (int level = 0; level < SCAN_LEVELS; level++) {
        uint64_t blocks = (n + 2047) / 2048;
        vx_result r = vx__buffer_ensure(m->g, &m->buf[B_SCAN0 + level], blocks * 4 + 16, "meshgpu.scan", err);
        if (r) return r;
        if (blocks <= 1) break;
        n = blocks;
    }
    return VX_OK;
}

/* Records one pass of the stable radix sort (gpusort.comp) of n pairs by the
 * 4-bit digit at shift, from KEYS/VALS (*src 0) or KEYS2/VALS2 (1) into the
 * other pair; B_HIST and the scan buffers must hold ntiles * 16. */
static vx_result sort_pass(vx_conv_mesh_gpu* m, uint32_t n, uint32_t shift, uint64_t ntiles, int* src, vx_error* err) {
    sort_push sp = {n, shift, (uint32_t)ntiles};
    int ids[5] = {*src ? B_KEYS2 : B_KEYS, *src ? B_VALS2 : B_VALS, *src ? B_KEYS : B_KEYS2, *src ? B_VALS : B_VALS2, B_HIST};
    vx_result r;
    if ((r = stage(m, P_HIST, ids, 5, ntiles, &sp, sizeof sp, err))) return r;
    if ((r = scan(m, B_HIST, ntiles * 16, 0, err))) return r;
    if ((r = stage(m, P_SCATTER, ids, 5, ntiles, &sp, sizeof sp, err))) return r;
    *src ^= 1;
    return VX_OK;
}

/* Records a copy of the uint at index i of buffer id into the read buffer's slot. */
static void read_u32(vx_conv_mesh_gpu* m, int id, uint64_t i, uint32_t slot) {
    VkBufferCopy c = {.srcOffset = i * 4, .dstOffset = slot * 4, .size = 4};
    vkCmdCopyBuffer(m->g->cmd, m->buf[id].buf, m->buf[B_READ].buf, 1, &c);
    barrier(m->g);
}

static vx_result ensure(vx_conv_mesh_gpu* m, int id, uint64_t bytes, vx_error* err) {
    return vx__buffer_ensure(m->g, &m->buf[id], bytes < 16 ? 16 : bytes, "meshgpu", err);
}
/* A host-visible buffer (mapped; cached where the device has such memory,
 * so that reading the results back is a plain memory read), kept between
 * calls: the uploads and downloads go through two of them instead of a
 * staging buffer allocated per copy. */
static vx_result ensure_host(vx_conv_mesh_gpu* m, int id, uint64_t bytes, vx_error* err) {
    vx__buffer* b = &m->buf[id];
    if (b->buf && b->size >= bytes) return VX_OK;
    if (b->buf) vx__buffer_destroy(m->g, b);
    vx_result r = vx__buffer_create(m->g, bytes < 16 ? 16 : bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, true, "meshgpu.host", b, err);
    if (!r && !b->map) r = vx_fail(err, VX_ERR_GPU, VX_NO_OFFSET, "GPU voxelizer: no host-visible memory");
    return r;
}

typedef struct upload {
    int id;
    const void* data; /* NULL: the device buffer only (its bytes come another way) */
    uint64_t bytes, offset;
} upload;

/* Makes each upload's device buffer, copies the data into the upload
 * buffer and records the copies into the open command buffer. */
static vx_result put_all(vx_conv_mesh_gpu* m, upload* u, int n, vx_error* err) {
    uint64_t total = 0;
    vx_result r;
    for (int i = 0; i < n; i++) {
        if ((r = ensure(m, u[i].id, u[i].bytes, err))) return r;
        u[i].offset = total;
        total += (u[i].bytes + 15) & ~15ull;
    }
    if ((r = ensure_host(m, B_UP, total, err))) return r;
    for (int i = 0; i < n; i++)
        if (u[i].data && u[i].bytes)
            memcpy((uint8_t*)m->buf[B_UP].map + u[i].offset, u[i].data, u[i].bytes);
    return VX_OK;
}
static void put_record(vx_conv_mesh_gpu* m, const upload* u, int n) {
    for (int i = 0; i < n; i++) {
        if (!u[i].data || !u[i].bytes) continue;
        VkBufferCopy c = {.srcOffset = u[i].offset, .dstOffset = 0, .size = u[i].bytes};
        vkCmdCopyBuffer(m->g->cmd, m->buf[B_UP].buf, m->buf[u[i].id].buf, 1, &c);
    }
    barrier(m->g);
}

/* ---- regions to the sink ------------------------------------------------------------------- */

typedef struct region_job {
    const vx__mesh_bins* bins;
    const vx_conv_mesh_grid* grid;
    const uint64_t* brick_morton; /* per brick index */
    const uint32_t* okeys;        /* 2 per cell: (local | brick << 18, brick >> 14) */
    const uint32_t *rgba, *nrm, *mat;
    const size_t* cstart;         /* first cell of each region; [region_count] = cells */
    const uint32_t* ids;          /* per cell its tuple's global id (meshintern.comp), or NULL: not interned */
    const uint32_t* utab;         /* 4 per id: rgba, normal, material, region (ids in region order) */
    const size_t* ustart;         /* first id of each region; [region_count] = ids */
    const vx__svo_pool* pools;    /* per region its node pool built on the GPU, or NULL */
    const uint32_t* ext;          /* with pools: per region its representatives' new tuples, then [R + r] the first */
    const uint32_t* ext_tuples;   /* those tuples, 4 words each (rgba, normal, material, region) */
    bool check_pools;             /* the builders check the pools against their own */
    bool solid;                   /* desc->solid: the CPU's interior fill of each brick (vx__mesh_fill_brick) */
    bool layout_thread;           /* a core to spare per builder: its layout on a second thread */
    unsigned intern_threads;      /* threads per builder for its tuples (cores over builders) */
    unsigned copy_threads;        /* threads per builder copying filled records (pools[ri].filled) at most: all cores */
    const size_t* mine;           /* the regions of this share (vx__mesh_share_regions), ascending */
    size_t mine_count;
    uint32_t attrs;
    vx__mesh_sink sink;
    void* user;
    const vx_allocator* alloc;
    pthread_mutex_t lock;
    vx_result failed;
    vx_error first_err;
} region_job;

/* A region's tuples for its builder: the cells' (4 words each in the
 * download), then its representatives' new ones; in chunks, on several
 * threads for the large regions. */
typedef struct tab_fill {
    vx__svo_rec* tab;
    const uint32_t* cells; /* nc tuples */
    size_t nc;
    const uint32_t* news; /* nu - nc tuples */
    size_t nu;
} tab_fill;
enum { TAB_CHUNK = 1 << 15 };
static void tab_fill_chunk(void* ctx, unsigned thread, uint32_t c) {
    (void)thread;
    tab_fill* f = (tab_fill*)ctx;
    size_t lo = (size_t)c * TAB_CHUNK, hi = lo + TAB_CHUNK < f->nu ? lo + TAB_CHUNK : f->nu;
    for (size_t u = lo; u < hi; u++) {
        const uint32_t* t = u < f->nc ? f->cells + 4 * u : f->news + 4 * (u - f->nc);
        f->tab[u].rgba = t[0], f->tab[u].normal = t[1], f->tab[u].material = (uint16_t)t[2];
    }
}

/* desc->solid: region ri's bricks, each filled by the CPU voxelizer's code
 * from the GPU's surface cells (the votes from the binning), handed to the
 * sink as the CPU voxelizer hands them (no interned tuples: the builder
 * hashes them). */
static vx_result region_emit_solid(region_job* j, size_t ri, vx_error* err) {
    const vx__mesh_bins* b = j->bins;
    const vx_allocator* a = j->alloc;
    enum { CELLS = BRICK * BRICK * BRICK };
    size_t c = j->cstart[ri], cend = j->cstart[ri + 1], k = 0, kcap = 0, rcap = 0, ncap = 0, mcap = 0;
    uint64_t mask = (1ull << (3 * b->rb)) - 1;
    bool rgba = (j->attrs & VX_ATTR_RGBA8) != 0, nrm = (j->attrs & VX_ATTR_NORMAL) != 0, mat = (j->attrs & VX_ATTR_MATERIAL) != 0;
    uint64_t* keys = NULL;
    uint32_t *orgba = NULL, *onrm = NULL;
    uint16_t* omat = NULL;
    void* scratch = vx_alloc(a, vx__mesh_fill_scratch_size());
    uint32_t* loc = (uint32_t*)vx_alloc(a, 2 * (size_t)CELLS * 4); /* the surface's local keys, then the brick's */
    vx_result r = VX_OK;
    if (!scratch || !loc) r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "solid fill buffers");
    for (size_t bi = b->rstart[ri]; !r && bi < b->rstart[ri + 1]; bi++) {
        size_t s0 = c;
        while (c < cend && ((uint64_t)(j->okeys[2 * c] >> 18) | (uint64_t)j->okeys[2 * c + 1] << 14) == bi) {
            loc[c - s0] = j->okeys[2 * c] & 0x3FFFFu;
            c++;
        }
        if (!vx_grow(a, (void**)&keys, &kcap, k + CELLS, 8) || (rgba && !vx_grow(a, (void**)&orgba, &rcap, k + CELLS, 4)) ||
            (nrm && !vx_grow(a, (void**)&onrm, &ncap, k + CELLS, 4)) || (mat && !vx_grow(a, (void**)&omat, &mcap, k + CELLS, 2))) {
            r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "solid region of %zu voxels", k + CELLS);
            break;
        }
        uint32_t* out = loc + CELLS;
        size_t nb = vx__mesh_fill_brick(b, j->grid, j->brick_morton[bi], j->attrs, loc, rgba ? j->rgba + s0 : NULL,
                                        nrm ? j->nrm + s0 : NULL, mat ? j->mat + s0 : NULL, c - s0, scratch, out,
                                        rgba ? orgba + k : NULL, nrm ? onrm + k : NULL, mat ? omat + k : NULL);
        uint64_t bm = (j->brick_morton[bi] & mask) << 18;
        for (size_t i = 0; i < nb; i++) keys[k + i] = bm | out[i];
        k += nb;
    }
    if (!r && k) {
        vx__mesh_region reg;
        vx__mesh_region_place(&reg, j->brick_morton[b->rstart[ri]] >> (3 * b->rb), b->R, j->grid->size, ri, b->region_count);
        reg.count = k;
        reg.keys = keys;
        reg.rgba = orgba;
        reg.normal = onrm;
        reg.material = omat;
        reg.attrs = j->attrs;
        r = j->sink(j->user, &reg, err);
    }
    vx_free(a, scratch);
    vx_free(a, loc);
    vx_free(a, keys);
    vx_free(a, orgba);
    vx_free(a, onrm);
    vx_free(a, omat);
    return r;
}

static vx_result region_emit(region_job* j, size_t ri, vx_error* err) {
    if (j->solid) return region_emit_solid(j, ri, err);
    const vx__mesh_bins* b = j->bins;
    size_t c0 = j->cstart[ri], n = j->cstart[ri + 1] - c0;
    if (n == 0) return VX_OK;
    /* the cells (not downloaded when the GPU built the tree: the pool stands for them) */
    bool cells = j->okeys != NULL;
    uint64_t* keys = cells ? (uint64_t*)vx_alloc(j->alloc, n * 8) : NULL;
    uint16_t* mat = cells && (j->attrs & VX_ATTR_MATERIAL) ? (uint16_t*)vx_alloc(j->alloc, n * 2) : NULL;
    if ((cells && !keys) || (cells && (j->attrs & VX_ATTR_MATERIAL) && !mat)) {
        vx_free(j->alloc, keys);
        vx_free(j->alloc, mat);
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "region of %zu voxels", n);
    }
    uint64_t mask = (1ull << (3 * b->rb)) - 1;
    for (size_t i = 0; cells && i < n; i++) {
        const uint32_t* k = j->okeys + 2 * (c0 + i);
        uint64_t brick = (uint64_t)(k[0] >> 18) | (uint64_t)k[1] << 14;
        keys[i] = (j->brick_morton[brick] & mask) << 18 | (k[0] & 0x3FFFFu);
        if (mat) mat[i] = (uint16_t)j->mat[c0 + i];
    }
    /* the region's tuples and the cells' ids into them, for the builder */
    uint32_t* rec = NULL;
    vx__svo_rec* tab = NULL;
    /* the records filled on the GPU: the builder copies them and reads no tuple */
    bool filled = j->pools && j->pools[ri].filled && !j->check_pools;
    bool interned = j->utab != NULL && !filled;
    size_t u0 = j->utab ? j->ustart[ri] : 0, nc = j->utab ? j->ustart[ri + 1] - u0 : 0;
    size_t ne = j->pools && j->ext ? j->ext[ri] : 0, nu = nc + ne; /* the cells' tuples, then the representatives' new ones */
    if (interned) {
        rec = j->ids ? (uint32_t*)vx_alloc(j->alloc, n * 4) : NULL;
        tab = (vx__svo_rec*)vx_calloc(j->alloc, nu ? nu : 1, sizeof *tab);
        if ((j->ids && !rec) || !tab) {
            vx_free(j->alloc, keys), vx_free(j->alloc, mat), vx_free(j->alloc, rec), vx_free(j->alloc, tab);
            return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "region of %zu voxels", n);
        }
        const uint32_t* news = ne ? j->ext_tuples + 4 * (size_t)j->ext[j->bins->region_count + ri] : NULL;
        tab_fill tf = {tab, j->utab + 4 * u0, nc, news, nu};
        vx_run_jobs(nu >= ((size_t)1 << 17) ? j->intern_threads : 1, (uint32_t)((nu + TAB_CHUNK - 1) / TAB_CHUNK), tab_fill_chunk,
                    &tf);
        for (size_t i = 0; rec && i < n; i++) rec[i] = j->ids[c0 + i] - (uint32_t)u0;
    }
    vx__mesh_region reg;
    vx__mesh_region_place(&reg, j->brick_morton[b->rstart[ri]] >> (3 * b->rb), b->R, j->grid->size, ri,
                          b->region_count);
    reg.count = n;
    reg.keys = keys;
    reg.rgba = cells && (j->attrs & VX_ATTR_RGBA8) ? j->rgba + c0 : NULL;
    reg.normal = cells && (j->attrs & VX_ATTR_NORMAL) ? j->nrm + c0 : NULL;
    reg.material = mat;
    reg.attrs = j->attrs;
    unsigned threads = j->intern_threads;
    if (filled) { /* copies: a thread per 2^20 words copied, up to every core */
        const vx__svo_pool* p = &j->pools[ri];
        uint64_t want = (p->laid_count + 3 * (uint64_t)p->nrecs) >> 20;
        threads = want < threads ? threads : want > j->copy_threads ? j->copy_threads : (unsigned)want;
    }
    reg.interned = (vx__svo_interned){rec, tab, nu, j->layout_thread, threads, j->pools ? &j->pools[ri] : NULL, j->check_pools};
    if (j->pools && j->ext) { /* the cells' box, from the GPU build */
        const uint32_t* e = j->ext + 3 * j->bins->region_count + 6 * ri;
        reg.has_box = e[3] != 0;
        for (int k = 0; k < 3; k++) reg.box_min[k] = ~e[k], reg.box_max[k] = e[3 + k];
    }
    vx_result r = j->sink(j->user, &reg, err);
    vx_free(j->alloc, keys);
    vx_free(j->alloc, mat);
    vx_free(j->alloc, rec);
    vx_free(j->alloc, tab);
    return r;
}

/* Region mine[k] (vx_run_jobs); after a failure the rest are skipped. */
static void region_run(void* ctx, unsigned thread, uint32_t k) {
    (void)thread;
    region_job* j = (region_job*)ctx;
    pthread_mutex_lock(&j->lock);
    bool stop = j->failed != VX_OK;
    pthread_mutex_unlock(&j->lock);
    if (stop) return;
    vx_error e = {0};
    vx_result r = region_emit(j, j->mine[k], &e);
    if (r) {
        pthread_mutex_lock(&j->lock);
        if (!j->failed) j->failed = r, j->first_err = e;
        pthread_mutex_unlock(&j->lock);
    }
}

/* ---- the voxelizer ---------------------------------------------------------------------- */

static unsigned bits_for(uint64_t v) {
    unsigned b = 0;
    while (b < 64 && (v >> b)) b++;
    return b;
}

/* ---- the octrees on the GPU (meshbuild.comp) -------------------------------------------------- */

/* Binds the build's buffers; items: level l's children in ITA (src 0) or ITB. */
#define BUILD_BINDINGS 26
static void build_ids(int* ids, int src, int sorted) {
    static const int base[BUILD_BINDINGS] = {B_OKEYS, B_IDS,  B_BINFO, B_RINFO, B_ROUT, B_ITA,   B_ITB,   B_POS,  B_START,
                                             B_NODES, B_TAB,  B_MISC,  B_KEYS,  B_VALS, B_POOL,  B_RBASE, B_NREP, B_UTAB,
                                             B_TTAB,  B_RNEW, B_EXT,   B_RTAB,  B_RNODE, B_RIDS, B_RFIRST, B_LAY};
    memcpy(ids, base, sizeof base);
    if (src) ids[5] = B_ITB, ids[6] = B_ITA;
    if (sorted) ids[12] = B_KEYS2, ids[13] = B_VALS2;
}

static vx_result bstage(vx_conv_mesh_gpu* m, int mode, int src, int sorted, uint64_t n, uint32_t level, uint32_t base,
                        uint32_t mask, vx_error* err) {
    int ids[BUILD_BINDINGS];
    build_ids(ids, src, sorted);
    if ((mode >= 1 && mode <= 3) || mode == 27 || mode == 28) ids[25] = B_LVL; /* the level loop's counts (meshbuild.comp) */
    build_push bp = {(uint32_t)n, level, base, mask, m->build_attrs, UINT32_MAX, UINT32_MAX};
    if (m->hash == VX_CONV_MESH_GPU_HASH_FEW_SLOTS) bp.smask = 7; /* every probe starts in one of 8 slots */
    if (m->hash == VX_CONV_MESH_GPU_HASH_FEW_LABELS) bp.lmask = 15; /* 16 structural hashes: distinct subtrees alike */
    return stage(m, P_BUILD + mode, ids, BUILD_BINDINGS, (n + 255) / 256, &bp, sizeof bp, err);
}

/* The block layout's stages (modes 21-26): nodes in pool order from B_ORD,
 * the lone records' sort in KEYS/VALS (lsorted 0) or KEYS2/VALS2 (bound
 * as keys and start), the words into B_WORDS (bound as rids); limit: the
 * largest near pointer. */
static vx_result lstage(vx_conv_mesh_gpu* m, int mode, int lsorted, uint64_t n, uint32_t level, uint32_t limit, vx_error* err) {
    int ids[BUILD_BINDINGS];
    build_ids(ids, 0, 0);
    ids[8] = lsorted ? B_VALS2 : B_VALS;
    ids[12] = lsorted ? B_KEYS2 : B_KEYS;
    ids[13] = B_ORD;
    ids[23] = B_WORDS;
    build_push bp = {(uint32_t)n, level, 0, limit, m->build_attrs, UINT32_MAX, UINT32_MAX};
    return stage(m, P_BUILD + mode, ids, BUILD_BINDINGS, (n + 255) / 256, &bp, sizeof bp, err);
}

static void fill(vx_conv_mesh_gpu* m, int id, uint64_t bytes, uint32_t v) {
    vkCmdFillBuffer(m->g->cmd, m->buf[id].buf, 0, (bytes + 3) & ~3ull, v);
    barrier(m->g);
}

/* Builds every region's octree on the GPU from the C interned cells still
 * on the device (B_OKEYS, B_IDS) and downloads the node pools: *out gets
 * one vx__svo_pool per region (words in the pool download buffer), or
 * stays NULL when the CPU builders must build (a hash collision found by
 * the check, buffers beyond what one binding addresses, depths beyond
 * max_depth: the CPU builder reports those). */
static vx_result gpu_build(vx_conv_mesh_gpu* m, const vx__mesh_bins* bins, const vx_conv_mesh_grid* grid, const uint64_t* bm,
                           const uint32_t* breg, uint32_t C, const size_t* ustart, uint32_t U, uint32_t attrs,
                           uint32_t max_depth, const vx_allocator* a, vx__svo_pool** out, uint32_t** out_ext,
                           const uint32_t** out_tuples, vx_error* err) {
    vx_gpu* g = m->g;
    size_t NB = bins->total_bricks, R = bins->region_count;
    *out = NULL;
    *out_ext = NULL;
    /* the representatives too, for the mesh's channels (the tuples are interned: U of them) */
    m->build_attrs = U ? ((attrs & VX_ATTR_RGBA8) ? 1u : 0u) | ((attrs & VX_ATTR_NORMAL) ? 2u : 0u) |
                             ((attrs & VX_ATTR_MATERIAL) ? 4u : 0u)
                       : 0u;
    if (attrs & ~(uint32_t)(VX_ATTR_RGBA8 | VX_ATTR_NORMAL | VX_ATTR_MATERIAL)) m->build_attrs = 0;
    if (C == 0 || C >= (1u << 27)) return VX_OK; /* order = last cell << 5 | level in 32 bits */
    const uint64_t max_binding = 0xFFFFFFF0ull;     /* bytes one storage binding addresses */
    uint64_t cap = (uint64_t)C + 1024;             /* node slots: about C / 2 for a surface */
    if (cap * 64 > max_binding) cap = max_binding / 64;
    if ((uint64_t)C * 32 > max_binding) return VX_OK;
    uint32_t* binfo = (uint32_t*)vx_alloc(a, (NB ? NB : 1) * 16);
    uint32_t* rinfo = (uint32_t*)vx_alloc(a, (R ? R : 1) * 16);
    uint32_t* rdown = NULL;
    vx__svo_pool* pools = NULL;
    vx_result r = VX_OK;
    if (!binfo || !rinfo) {
        r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "GPU octree build: %zu bricks", NB);
        goto done;
    }
    uint32_t maxd = 0;
    uint64_t mask = (1ull << (3 * bins->rb)) - 1;
    for (size_t b = 0; b < NB; b++) {
        uint64_t k = bm[b] & mask;
        binfo[4 * b] = (uint32_t)k, binfo[4 * b + 1] = (uint32_t)(k >> 32), binfo[4 * b + 2] = breg[b], binfo[4 * b + 3] = 0;
    }
    for (size_t ri = 0; ri < R; ri++) {
        vx__mesh_region reg;
        vx__mesh_region_place(&reg, bm[bins->rstart[ri]] >> (3 * bins->rb), bins->R, grid->size, ri, R);
        uint32_t mx = reg.size[0] > reg.size[1] ? reg.size[0] : reg.size[1], d = 0;
        if (reg.size[2] > mx) mx = reg.size[2];
        while ((1u << d) < mx) d++;
        if (d > (max_depth ? max_depth : VX_SVO_MAX_DEPTH) || 3 * d > 63) goto done; /* the CPU builder says why */
        if (d > maxd) maxd = d;
        rinfo[4 * ri] = d, rinfo[4 * ri + 1] = (uint32_t)ustart[ri], rinfo[4 * ri + 3] = 0;
        rinfo[4 * ri + 2] = (uint32_t)(ustart[ri + 1] - ustart[ri]); /* the region's tuples: its new ones follow */
    }
    upload ups[2] = {{B_BINFO, binfo, (uint64_t)NB * 16, 0}, {B_RINFO, rinfo, (uint64_t)R * 16, 0}};
    if ((r = put_all(m, ups, 2, err)) || (r = ensure(m, B_ROUT, (uint64_t)R * 16, err)) ||
        (r = ensure(m, B_RBASE, (uint64_t)R * 4, err)) || (r = ensure(m, B_ITA, (uint64_t)C * 32, err)) ||
        (r = ensure(m, B_ITB, (uint64_t)C * 32, err)) || (r = ensure(m, B_POS, (cap + 1) * 4, err)) ||
        (r = ensure(m, B_START, (uint64_t)C * 4, err)) || (r = ensure(m, B_NODES, cap * 64, err)) ||
        (r = ensure(m, B_MISC, ((uint64_t)R * 11 + 4) * 4, err)) || (r = ensure(m, B_TAB, 16, err)) || (r = ensure(m, B_POOL, 16, err)) ||
        (r = ensure(m, B_KEYS2, 16, err)) || (r = ensure(m, B_VALS2, 16, err)) || (r = scan_prepare(m, cap + 1, err)) ||
        (r = ensure(m, B_NREP, m->build_attrs ? cap * 16 : 16, err)) || (r = ensure(m, B_UTAB, 16, err)) ||
        (r = ensure(m, B_TTAB, 16, err)) || (r = ensure(m, B_RNEW, ((uint64_t)R * 2 + 1) * 4, err)) ||
        (r = ensure(m, B_EXT, 16, err)) || (r = ensure(m, B_RTAB, 16, err)) || (r = ensure(m, B_RNODE, 16, err)) ||
        (r = ensure(m, B_RIDS, 16, err)) || (r = ensure(m, B_RFIRST, (uint64_t)R * 32, err)) || (r = ensure(m, B_LAY, 16, err)) ||
        (r = ensure(m, B_ORD, 16, err)) || (r = ensure(m, B_WORDS, 16, err)))
        goto done;

    /* level by level: the children of level l are the items, their parents
     * the next items. The counts stay on the device (meshbuild.comp's level
     * state) and each level is dispatched at a bound of its count (no more
     * than the level below, nor than the regions' nodes at that level); the
     * invocations beyond it return. The first two levels' parent counts are
     * read back (two round trips, where the host used to wait once a level):
     * those levels hold most of the items, and a bound of the cell count
     * there cost 0.4 ms of GPU time at 1024^3 and 9 ms at 4096^3 (H200);
     * every later level goes into one submission. */
    if ((r = ensure(m, B_LVL, 64, err))) goto done;
    int src = 0;
    if ((r = rec_begin(m, err))) goto done;
    put_record(m, ups, 2);
    fill(m, B_ROUT, (uint64_t)R * 16, 0);
    fill(m, B_RBASE, (uint64_t)R * 4, 0xFFFFFFFFu);
    fill(m, B_MISC, ((uint64_t)R * 11 + 4) * 4, 0);
    {
        uint32_t lv[8] = {C, 0, 0, 0, 0, 0, 0, 0};
        vkCmdUpdateBuffer(g->cmd, m->buf[B_LVL].buf, 0, sizeof lv, lv);
        barrier(g);
    }
    ts_begin(m, 0);
    if ((r = bstage(m, 0, 1, 0, C, 0, (uint32_t)R, 0, err))) goto done; /* src 1: writes ITA */
    uint64_t bound = C; /* the items of this level, at most */
    for (uint32_t level = 0; level <= maxd; level++) {
        uint64_t next = 0; /* the parents: the regions' nodes at level + 1, at most (none above the last level) */
        for (size_t ri = 0; level < maxd && ri < R && next < bound; ri++) {
            uint32_t d = rinfo[4 * ri], e = d > level + 1 ? d - (level + 1) : 0;
            next += 3 * e >= 40 ? bound : 1ull << (3 * e);
        }
        if (next > bound) next = bound;
        fill(m, B_POS, (bound + 1) * 4, 0);
        if ((r = bstage(m, 1, src, 0, bound, level, 0, 0, err)) || (r = scan(m, B_POS, bound + 1, 0, err)) ||
            (r = bstage(m, 2, src, 0, bound, level, 0, 0, err)) ||
            (r = bstage(m, 27, src, 0, 1, (uint32_t)next, 0, (uint32_t)(cap < UINT32_MAX ? cap : UINT32_MAX), err)))
            goto done;
        if (level == maxd) break;
        if (level < 2) { /* the parents' count itself */
            VkBufferCopy c = {.srcOffset = 8, .dstOffset = 0, .size = 8};
            vkCmdCopyBuffer(g->cmd, m->buf[B_LVL].buf, m->buf[B_READ].buf, 1, &c);
            barrier(g);
            ts_end(m);
            if ((r = submit(m, err))) goto done;
            uint32_t pf[2]; /* parents, failed */
            if ((r = vx__buffer_download(g, &m->buf[B_READ], pf, 8, err))) goto done;
            if (pf[1]) goto done; /* beyond the node buffer: the CPU builds */
            if ((r = rec_begin(m, err))) goto done;
            ts_begin(m, 0);
            next = pf[0];
            if (next == 0) break;
        }
        if ((r = bstage(m, 3, src, 0, next, level + 1, 0, 0, err)) || (r = bstage(m, 28, src, 0, 1, level, 0, 0, err)))
            goto done;
        bound = next;
        src ^= 1;
    }
    {
        VkBufferCopy c = {.srcOffset = 0, .dstOffset = 0, .size = 24};
        vkCmdCopyBuffer(g->cmd, m->buf[B_LVL].buf, m->buf[B_READ].buf, 1, &c);
        barrier(g);
    }
    ts_end(m);
    if ((r = submit(m, err))) goto done;
    uint32_t lvd[6]; /* items, base; parents, failed; levels */
    if ((r = vx__buffer_download(g, &m->buf[B_READ], lvd, 24, err))) goto done;
    if (lvd[3] || lvd[1] > cap) goto done; /* beyond the node buffer, or too deep: the CPU builds */
    uint64_t base = lvd[1];
    m->stats.levels = lvd[4];
    m->stats.node_slots = base;

    /* shared subtrees: one slot per (hash, region), the least order there
     * canonical, every node checked against its canonical node */
    uint64_t N = base, T = 1024;
    while (T < 2 * N) T *= 2;
    if (T * 8 > max_binding) goto done;
    if ((r = ensure(m, B_TAB, T * 8, err)) || (r = rec_begin(m, err))) goto done;
    ts_begin(m, 1);
    fill(m, B_TAB, T * 8, 0xFFFFFFFFu);
    fill(m, B_MISC, 16, 0);
    fill(m, B_POS, (N + 1) * 4, 0);
    if ((r = bstage(m, 4, 0, 0, N, 0, 0, (uint32_t)(T - 1), err)) || (r = bstage(m, 5, 0, 0, N, 0, 0, 0, err)) ||
        (r = bstage(m, 6, 0, 0, N, 0, 0, 0, err)) || (r = bstage(m, 7, 0, 0, N, 0, 0, 0, err)) ||
        (r = scan(m, B_POS, N + 1, 0, err)))
        goto done;
    read_u32(m, B_POS, N, 0);
    read_u32(m, B_MISC, 0, 1);
    ts_end(m);
    if ((r = submit(m, err))) goto done;
    uint32_t KM[2];
    if ((r = vx__buffer_download(g, &m->buf[B_READ], KM, 8, err))) goto done;
    uint32_t K = KM[0];
    if (KM[1] || K > N) goto done; /* two different subtrees hashed alike: the CPU builds */
    m->stats.nodes = K;

    /* canonical nodes in the builder's order (radix sort by order), pool positions, words */
    uint64_t W = 0, E = 0;
    uint64_t T2 = 1024; /* the tuple table: the cells' tuples and the representatives */
    while (T2 < 2 * ((uint64_t)U + K)) T2 *= 2;
    if (m->build_attrs && (T2 * 8 > max_binding || (uint64_t)U + N >= 0xFFFFFFF0u)) goto done;
    /* the attribute runs too (with the representatives): a table of the
     * nodes' runs, at most 8 records a node */
    uint64_t T3 = 1024;
    while (T3 < 2 * (uint64_t)K) T3 *= 2;
    bool runs = m->build_attrs && K && T3 * 8 <= max_binding && (uint64_t)K * 32 <= max_binding;
    /* and the blocks (the final node words), unless only the pools are asked for */
    bool blocks = runs && m->build != VX_CONV_MESH_GPU_BUILD_GPU_POOLS;
    /* and with the blocks the records' attributes themselves (MODE 30; the
     * material halves in the download are a uint16_t array on little-endian
     * hosts only) */
    const uint16_t one = 1;
    bool filled = blocks && *(const uint8_t*)&one == 1;
    uint32_t ba = m->build_attrs;
    int lsorted = 0;
    if (K) {
        uint64_t ntiles = ((uint64_t)K + 1023) / 1024;
        if ((uint64_t)K * 11 * 4 > max_binding) goto done;
        if ((r = ensure(m, B_KEYS, (uint64_t)K * 8, err)) || (r = ensure(m, B_VALS, (uint64_t)K * 4, err)) ||
            (r = ensure(m, B_KEYS2, (uint64_t)K * 8, err)) || (r = ensure(m, B_VALS2, (uint64_t)K * 4, err)) ||
            (r = ensure(m, B_HIST, ntiles * 16 * 4 + 4, err)) || (r = scan_prepare(m, ntiles * 16, err)) ||
            (r = ensure(m, B_POOL, (uint64_t)K * 11 * 4, err)) ||
            (m->build_attrs && ((r = ensure(m, B_TTAB, T2 * 8, err)) || (r = ensure(m, B_EXT, (uint64_t)K * 16, err)))) ||
            (runs && ((r = ensure(m, B_RTAB, T3 * 8, err)) || (r = ensure(m, B_RNODE, (uint64_t)K * 8, err)) ||
                      (r = ensure(m, B_RIDS, (uint64_t)K * 32, err)))) ||
            (blocks && ((r = ensure(m, B_LAY, (uint64_t)K * 8, err)) || (r = ensure(m, B_ORD, (uint64_t)K * 4, err)))) ||
            (filled && ((r = ensure(m, B_ARGBA, (ba & 1u) ? (uint64_t)K * 32 : 16, err)) ||
                        (r = ensure(m, B_ANRM, (ba & 2u) ? (uint64_t)K * 32 : 16, err)) ||
                        (r = ensure(m, B_AMAT, (ba & 4u) ? (uint64_t)K * 16 : 16, err)))) ||
            (r = rec_begin(m, err)))
            goto done;
        if (m->build_attrs) { /* the representatives' ids: the region's tuple where equal, else a new one */
            ts_begin(m, 2);
            fill(m, B_TTAB, T2 * 8, 0xFFFFFFFFu);
            fill(m, B_RNEW, ((uint64_t)R * 2 + 1) * 4, 0);
            uint32_t tm = (uint32_t)(T2 - 1);
            if ((r = bstage(m, 13, 0, 0, U, 0, U, tm, err)) || (r = bstage(m, 14, 0, 0, N, 0, U, tm, err)) ||
                (r = bstage(m, 15, 0, 0, N, 0, U, tm, err)) || (r = bstage(m, 16, 0, 0, 1, (uint32_t)R, U, tm, err)) ||
                (r = bstage(m, 17, 0, 0, N, (uint32_t)R, U, tm, err)))
                goto done;
            read_u32(m, B_RNEW, (uint64_t)R * 2, 1);
            ts_end(m);
        }
        ts_begin(m, 3);
        if ((r = bstage(m, 8, 0, 0, N, 0, 0, 0, err))) goto done;
        unsigned obits = bits_for(((uint64_t)C << 5) | 31);
        int sorted = 0;
        for (uint32_t pass = 0; 4 * pass < obits && K > 1; pass++)
            if ((r = sort_pass(m, K, 4 * pass, ntiles, &sorted, err))) goto done;
        ts_end(m);
        ts_begin(m, 4);
        fill(m, B_POS, ((uint64_t)K + 1) * 4, 0);
        if ((r = bstage(m, 9, 0, sorted, K, 0, 0, 0, err)) || (r = scan(m, B_POS, (uint64_t)K + 1, 0, err)) ||
            (r = bstage(m, 10, 0, sorted, K, 0, 0, 0, err)) || (r = bstage(m, 11, 0, sorted, K, 0, 0, 0, err)))
            goto done;
        read_u32(m, B_POS, K, 0);
        ts_end(m);
        if (runs) { /* the attribute runs: pool word 2 of each node its run's first record */
            ts_begin(m, 5);
            uint32_t rm = (uint32_t)(T3 - 1);
            fill(m, B_RTAB, T3 * 8, 0xFFFFFFFFu);
            fill(m, B_RFIRST, (uint64_t)R * 32, 0xFFFFFFFFu);
            if ((r = bstage(m, 18, 0, sorted, K, 0, 0, rm, err)) || (r = bstage(m, 19, 0, sorted, K, 0, 0, rm, err)) ||
                (r = scan(m, B_POS, (uint64_t)K + 1, 0, err)) || (r = bstage(m, 20, 0, sorted, K, 0, 0, rm, err)))
                goto done;
            if (filled) { /* the records' attributes while pos holds their starts */
                fill(m, B_AMAT, (ba & 4u) ? (uint64_t)K * 16 : 16, 0);
                int ids[BUILD_BINDINGS];
                build_ids(ids, 0, sorted);
                ids[5] = B_ARGBA, ids[6] = B_ANRM, ids[8] = B_AMAT;
                build_push bp = {(uint32_t)K, (uint32_t)R, 0, 0, ba, UINT32_MAX, UINT32_MAX};
                if ((r = stage(m, P_BUILD + 30, ids, BUILD_BINDINGS, ((uint64_t)K + 255) / 256, &bp, sizeof bp, err))) goto done;
            }
            read_u32(m, B_POS, K, 2);
            ts_end(m);
        }
        if (blocks) { /* the blocks' first guess; the lone records sorted by their run (stable: pool order kept) */
            ts_begin(m, 7);
            VkBufferCopy co = {.srcOffset = 0, .dstOffset = 0, .size = (uint64_t)K * 4};
            vkCmdCopyBuffer(g->cmd, m->buf[sorted ? B_VALS2 : B_VALS].buf, m->buf[B_ORD].buf, 1, &co);
            barrier(g);
            if ((r = lstage(m, 21, 0, K, 0, VX_CONV_MESH_GPU_NEAR_MAX, err))) goto done;
            for (uint32_t pass = 0; pass < 8 && K > 1; pass++)
                if ((r = sort_pass(m, K, 4 * pass, ntiles, &lsorted, err))) goto done;
            ts_end(m);
        }
    } else if ((r = rec_begin(m, err))) {
        goto done;
    }
    if ((r = bstage(m, 12, 0, 0, R, 0, 0, 0, err))) goto done;
    if ((r = submit(m, err))) goto done;
    uint64_t NR = 0; /* records of the stored runs */
    if (K) {
        uint32_t we[3];
        if ((r = vx__buffer_download(g, &m->buf[B_READ], we, 12, err))) goto done;
        W = we[0];
        E = m->build_attrs ? we[1] : 0;
        NR = runs ? we[2] : 0;
        if (E > K || NR > (uint64_t)K * 8) goto done;
    }
    m->stats.pool_words = W;
    m->stats.rep_tuples = E;
    /* the blocks: iterated until an iteration changes nothing (the
     * sequential layout's solution, meshbuild.comp); else the CPU lays
     * them out */
    uint64_t LW = 0; /* the laid-out blocks' words, all regions */
    if (blocks) {
        blocks = false;
        /* 8 iterations a submission (DamagedHelmet settles in 5 at 1024,
         * the 6th confirms); once one changes nothing the rest skip their
         * decisions (meshbuild.comp mode 29), so no round trip per few
         * iterations and little work past the fixpoint */
        for (uint32_t it = 0, chunk = 8; it < 64 && !blocks; it += chunk, chunk = 4) {
            if ((r = rec_begin(m, err))) goto done;
            ts_begin(m, 7);
            for (uint32_t k = 0; k < chunk; k++) {
                vkCmdFillBuffer(g->cmd, m->buf[B_MISC].buf, 4, 4, 0);
                barrier(g);
                if ((r = lstage(m, 23, lsorted, K, 0, VX_CONV_MESH_GPU_NEAR_MAX, err)) || (r = scan(m, B_POS, (uint64_t)K + 1, 0, err)) ||
                    (r = lstage(m, 24, lsorted, K, 0, VX_CONV_MESH_GPU_NEAR_MAX, err)) ||
                    (r = lstage(m, 25, lsorted, K, 0, VX_CONV_MESH_GPU_NEAR_MAX, err)) ||
                    (r = lstage(m, 29, lsorted, 1, 0, VX_CONV_MESH_GPU_NEAR_MAX, err)))
                    goto done;
            }
            read_u32(m, B_MISC, 2, 0);
            read_u32(m, B_POS, K, 1);
            read_u32(m, B_MISC, 3, 2);
            ts_end(m);
            if ((r = submit(m, err))) goto done;
            uint32_t cw[3];
            if ((r = vx__buffer_download(g, &m->buf[B_READ], cw, 12, err))) goto done;
            m->stats.layout_iterations = cw[2];
            if (cw[0]) blocks = true, LW = cw[1] + 2 * (uint64_t)R;
        }
        if (blocks && (LW * 4 > max_binding || (r = ensure(m, B_WORDS, LW * 4 + 16, err)))) {
            if (r) goto done;
            blocks = false;
        }
    }
    bool check = m->build == VX_CONV_MESH_GPU_BUILD_CHECK;
    bool pool_down = !blocks || check; /* the check compares the pools too */
    filled = filled && blocks;
    /* with the records' attributes the builders read no tuple: the runs'
     * tuple ids and the new tuples stay on the device (unless checked) */
    bool ids_down = !filled || check;
    uint64_t WD = pool_down ? W : 0, ED = ids_down ? E : 0, NRD = ids_down ? NR : 0, NF = filled ? NR : 0;
    uint64_t at_rout = WD * 4, at_rbase = at_rout + (uint64_t)R * 16, at_rnew = at_rbase + (uint64_t)R * 4,
             at_ext = at_rnew + (uint64_t)R * 8, at_cells = at_ext + ED * 16, at_rfirst = at_cells + (uint64_t)R * 28,
             at_rids = at_rfirst + (uint64_t)R * 32, at_laid = at_rids + NRD * 4, at_root = at_laid + LW * 4,
             at_argba = at_root + (filled ? (uint64_t)R * 16 : 0), at_anrm = at_argba + ((ba & 1u) ? NF * 4 : 0),
             at_amat = at_anrm + ((ba & 2u) ? NF * 4 : 0), total = at_amat + ((ba & 4u) ? (NF * 2 + 3) & ~3ull : 0);
    if ((r = ensure_host(m, B_PDOWN, total + 16, err)) || (r = rec_begin(m, err))) goto done;
    if (blocks) { /* the blocks' words, each region's root descriptor last */
        ts_begin(m, 7);
        if ((r = lstage(m, 22, lsorted, R, 0, VX_CONV_MESH_GPU_NEAR_MAX, err)) ||
            (r = lstage(m, 26, lsorted, K, 0, VX_CONV_MESH_GPU_NEAR_MAX, err)) ||
            (r = lstage(m, 22, lsorted, R, 1, VX_CONV_MESH_GPU_NEAR_MAX, err)))
            goto done;
    }
    ts_begin(m, 6);
    {
        VkBufferCopy cp = {.srcOffset = 0, .dstOffset = 0, .size = WD * 4};
        VkBufferCopy co = {.srcOffset = 0, .dstOffset = at_rout, .size = (uint64_t)R * 16};
        VkBufferCopy cb = {.srcOffset = 0, .dstOffset = at_rbase, .size = (uint64_t)R * 4};
        if (WD) vkCmdCopyBuffer(g->cmd, m->buf[B_POOL].buf, m->buf[B_PDOWN].buf, 1, &cp);
        if (blocks) {
            VkBufferCopy cl = {.srcOffset = 0, .dstOffset = at_laid, .size = LW * 4};
            vkCmdCopyBuffer(g->cmd, m->buf[B_WORDS].buf, m->buf[B_PDOWN].buf, 1, &cl);
        }
        vkCmdCopyBuffer(g->cmd, m->buf[B_ROUT].buf, m->buf[B_PDOWN].buf, 1, &co);
        vkCmdCopyBuffer(g->cmd, m->buf[B_RBASE].buf, m->buf[B_PDOWN].buf, 1, &cb);
        VkBufferCopy cc = {.srcOffset = 16, .dstOffset = at_cells, .size = (uint64_t)R * 28}; /* cells, boxes */
        vkCmdCopyBuffer(g->cmd, m->buf[B_MISC].buf, m->buf[B_PDOWN].buf, 1, &cc);
        if (m->build_attrs && K) {
            VkBufferCopy cn = {.srcOffset = 0, .dstOffset = at_rnew, .size = (uint64_t)R * 8};
            VkBufferCopy ce = {.srcOffset = 0, .dstOffset = at_ext, .size = ED * 16};
            vkCmdCopyBuffer(g->cmd, m->buf[B_RNEW].buf, m->buf[B_PDOWN].buf, 1, &cn);
            if (ED) vkCmdCopyBuffer(g->cmd, m->buf[B_EXT].buf, m->buf[B_PDOWN].buf, 1, &ce);
        }
        if (runs) {
            VkBufferCopy cf = {.srcOffset = 0, .dstOffset = at_rfirst, .size = (uint64_t)R * 32};
            VkBufferCopy ci = {.srcOffset = 0, .dstOffset = at_rids, .size = NRD * 4};
            vkCmdCopyBuffer(g->cmd, m->buf[B_RFIRST].buf, m->buf[B_PDOWN].buf, 1, &cf);
            if (NRD) vkCmdCopyBuffer(g->cmd, m->buf[B_RIDS].buf, m->buf[B_PDOWN].buf, 1, &ci);
        }
        if (filled) { /* the records' attributes, each region's root representative (MODE 30) */
            VkBufferCopy cr = {.srcOffset = ((uint64_t)R * 7 + 4) * 4, .dstOffset = at_root, .size = (uint64_t)R * 16};
            vkCmdCopyBuffer(g->cmd, m->buf[B_MISC].buf, m->buf[B_PDOWN].buf, 1, &cr);
            VkBufferCopy ca[3] = {{0, at_argba, NF * 4}, {0, at_anrm, NF * 4}, {0, at_amat, (NF * 2 + 3) & ~3ull}};
            int bufs[3] = {B_ARGBA, B_ANRM, B_AMAT};
            for (int q = 0; q < 3; q++)
                if ((ba >> q & 1u) && NF) vkCmdCopyBuffer(g->cmd, m->buf[bufs[q]].buf, m->buf[B_PDOWN].buf, 1, &ca[q]);
        }
        barrier(g);
    }
    ts_end(m);
    if ((r = submit(m, err))) goto done;
    {
        const uint8_t* hb = (const uint8_t*)m->buf[B_PDOWN].map;
        const uint32_t* words = (const uint32_t*)hb;
        rdown = (uint32_t*)vx_alloc(a, ((size_t)R * 5 + 1) * 4);
        /* per region: new tuples, first one, cells, then 6 per region: the cells' box (meshbuild.comp) */
        uint32_t* rext = (uint32_t*)vx_calloc(a, (size_t)R * 9 + 1, 4);
        if (!rext) {
            r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "GPU octree build: %zu regions", R);
            goto done;
        }
        if (m->build_attrs && K) memcpy(rext, hb + at_rnew, (size_t)R * 8);
        memcpy(rext + 2 * R, hb + at_cells, (size_t)R * 28);
        *out_ext = rext;
        *out_tuples = ED ? (const uint32_t*)(hb + at_ext) : NULL;
        pools = (vx__svo_pool*)vx_calloc(a, R ? R : 1, sizeof *pools);
        if (!rdown || !pools) {
            r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "GPU octree build: %zu regions", R);
            goto done;
        }
        memcpy(rdown, hb + at_rout, (size_t)R * 16);
        memcpy(rdown + 4 * R, hb + at_rbase, (size_t)R * 4);
        const uint32_t* rb = rdown + 4 * R;
        const uint32_t* rf = (const uint32_t*)(hb + at_rfirst); /* per region: 8 words (meshbuild.comp's rfirst) */
        uint64_t end = W, rend = NR;
        for (size_t ri = R; ri-- > 0;) { /* a region's words (and records) run to the next region's first */
            vx__svo_pool* p = &pools[ri];
            const uint32_t* ro = rdown + 4 * ri;
            p->root = ro[0], p->root_leaf = ro[1] != 0, p->plain = ro[2], p->collapsed = ro[3];
            p->reps = m->build_attrs != 0;
            if (rb[ri] == 0xFFFFFFFFu) continue; /* no node: the root is a leaf (or the region is empty) */
            if (rb[ri] > end) goto done;
            if (pool_down) p->words = words + rb[ri], p->count = (size_t)(end - rb[ri]);
            end = rb[ri];
            if (blocks) {
                const uint32_t* l = rf + 8 * ri + 4; /* first word, words, far pointers, descriptor words */
                if (l[1] == 0 || (uint64_t)l[0] + l[1] > LW) goto done;
                p->laid = (const uint32_t*)(hb + at_laid) + l[0];
                p->laid_count = l[1];
                p->laid_far = l[2];
                p->laid_desc = l[3];
                p->root_rep = rf[8 * ri + 3];
            }
            if (runs) {
                uint32_t r0 = rf[8 * ri + 1];
                if (r0 > rend) goto done;
                p->runs = true;
                p->recs = NRD ? (const uint32_t*)(hb + at_rids) + r0 : NULL;
                p->nrecs = (size_t)(rend - r0);
                rend = r0;
                if (filled) { /* the records as the model stores them; the root's representative */
                    const uint32_t* rr = (const uint32_t*)(hb + at_root) + 4 * ri;
                    p->attr_rgba = (ba & 1u) ? (const uint32_t*)(hb + at_argba) + r0 : NULL;
                    p->attr_normal = (ba & 2u) ? (const uint32_t*)(hb + at_anrm) + r0 : NULL;
                    p->attr_material = (ba & 4u) ? (const uint16_t*)(hb + at_amat) + r0 : NULL;
                    p->filled = true;
                    uint64_t first = rr[0] ? (uint64_t)(uint32_t)~rr[0] : UINT64_MAX; /* the least global record holding it */
                    if (rr[0] && (first < r0 || first >= r0 + p->nrecs)) goto done;
                    p->root_attr = rr[0] ? (uint32_t)(first - r0) : (uint32_t)p->nrecs;
                    p->root_tuple = (vx__svo_rec){rr[1], rr[2], 0.0f, (uint16_t)rr[3], 0, 0};
                }
            }
        }
        m->stats.run_records = NR;
        m->stats.laid_words = LW;
        m->stats.filled_records = NF;
        *out = pools;
        pools = NULL;
    }
done:
    vx_free(a, binfo);
    vx_free(a, rinfo);
    vx_free(a, rdown);
    vx_free(a, pools);
    return r;
}

/* Copies the voxelizer's results into the download buffer and points at
 * them there: the tuples (interned: each cell's id and each id's tuple),
 * and with cells the cells' keys and attributes (else those stay NULL). */
static vx_result download(vx_conv_mesh_gpu* m, uint32_t C, uint32_t U, uint32_t attrs, bool intern, bool cells,
                          const uint32_t** okeys, const uint32_t** orgba, const uint32_t** onrm, const uint32_t** omat,
                          const uint32_t** oids, const uint32_t** outab, vx_error* err) {
    vx_gpu* g = m->g;
    uint64_t c8 = cells ? (uint64_t)C * 8 : 0, c4 = cells ? (uint64_t)C * 4 : 0;
    uint64_t at_ids = c8 + 3 * c4, at_utab = at_ids + (intern ? c4 : 0), total = at_utab + (uint64_t)U * 16;
    vx_result r;
    if ((r = ensure_host(m, B_DOWN, total + 16, err)) || (r = rec_begin(m, err))) return r;
    if (cells) {
        VkBufferCopy ck = {.srcOffset = 0, .dstOffset = 0, .size = c8 ? c8 : 8};
        vkCmdCopyBuffer(g->cmd, m->buf[B_OKEYS].buf, m->buf[B_DOWN].buf, 1, &ck);
        int src_ids[3] = {B_ORGBA, B_ONRM, B_OMAT};
        uint32_t bits[3] = {VX_ATTR_RGBA8, VX_ATTR_NORMAL, VX_ATTR_MATERIAL};
        for (int q = 0; q < 3; q++)
            if ((attrs & bits[q]) && c4) {
                VkBufferCopy c = {.srcOffset = 0, .dstOffset = c8 + (uint64_t)q * c4, .size = c4};
                vkCmdCopyBuffer(g->cmd, m->buf[src_ids[q]].buf, m->buf[B_DOWN].buf, 1, &c);
            }
    }
    if (intern) {
        VkBufferCopy ci = {.srcOffset = 0, .dstOffset = at_ids, .size = c4};
        VkBufferCopy cu = {.srcOffset = 0, .dstOffset = at_utab, .size = (uint64_t)U * 16};
        if (c4) vkCmdCopyBuffer(g->cmd, m->buf[B_IDS].buf, m->buf[B_DOWN].buf, 1, &ci);
        vkCmdCopyBuffer(g->cmd, m->buf[B_UTAB].buf, m->buf[B_DOWN].buf, 1, &cu);
    }
    barrier(g);
    if ((r = submit(m, err))) return r;
    const uint8_t* base = (const uint8_t*)m->buf[B_DOWN].map;
    *okeys = *orgba = *onrm = *omat = *oids = *outab = NULL;
    if (cells) {
        *okeys = (const uint32_t*)base;
        *orgba = (const uint32_t*)(base + c8);
        *onrm = (const uint32_t*)(base + c8 + c4);
        *omat = (const uint32_t*)(base + c8 + 2 * c4);
        if (intern) *oids = (const uint32_t*)(base + at_ids);
    }
    if (intern) *outab = (const uint32_t*)(base + at_utab);
    return VX_OK;
}

/* The images' texels, one after the other, into the texel upload buffer:
 * on a thread of their own while the CPU bins the triangles (16 MB for
 * DamagedHelmet, 2-3 ms of copying that used to follow the binning). */
typedef struct texel_copy {
    const vx_gltf_mesh* mesh;
    uint8_t* at;
} texel_copy;
static void* texel_copy_main(void* arg) {
    const texel_copy* tc = (const texel_copy*)arg;
    uint8_t* at = tc->at;
    for (uint32_t i = 0; i < tc->mesh->image_count; i++) {
        const vx_gltf_image* im = &tc->mesh->images[i];
        if (!im->rgba) continue;
        size_t bytes = (size_t)im->width * im->height * 4;
        memcpy(at, im->rgba, bytes);
        at += bytes;
    }
    return NULL;
}

static vx_result gpu_voxelize(void* self, const vx_conv_mesh_desc* desc, const vx_gltf_mesh* mesh,
                              const vx_conv_mesh_grid* grid, uint32_t attrs, uint32_t share, uint32_t shares, bool builds,
                              vx__mesh_sink sink, void* user, vx_error* err) {
    vx_conv_mesh_gpu* m = (vx_conv_mesh_gpu*)self;
    vx_gpu* g = m->g;
    const vx_allocator* a = desc->alloc;
    memset(&m->stats, 0, sizeof m->stats);
    if (share >= (shares ? shares : 1)) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "share %u of %u", share, shares);
    /* the MATL ids; with materials that sample their metallic-roughness or
     * emissive textures per cell (plan.sampled) the records carry those
     * values and meshreduce.comp makes each cell's id from its averages */
    vx__mesh_mats plan;
    memset(&plan, 0, sizeof plan);
    if (attrs & VX_ATTR_MATERIAL) {
        vx_result pr = vx__mesh_mats_make(mesh, a, &plan, err);
        if (pr) return pr;
    }
    m->stats.sampled_materials = plan.sampled;
    double t0 = vx_time_now();
    bool tex = (attrs & VX_ATTR_RGBA8) != 0;
    bool texels = tex || plan.sampled; /* the shaders sample images */
    size_t texel_count = 0;
    for (uint32_t i = 0; i < mesh->image_count; i++)
        if (mesh->images[i].rgba) texel_count += (size_t)mesh->images[i].width * mesh->images[i].height;
    if (texel_count > UINT32_MAX) {
        vx__mesh_mats_free(a, &plan);
        return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "GPU voxelizer: %zu texels", texel_count);
    }
    texel_copy tc = {mesh, NULL};
    pthread_t tc_thread;
    bool tc_running = false;
    if (texels && texel_count) {
        vx_result tr = ensure_host(m, B_TEXUP, (uint64_t)texel_count * 4, err);
        if (tr) {
            vx__mesh_mats_free(a, &plan);
            return tr;
        }
        tc.at = (uint8_t*)m->buf[B_TEXUP].map;
        tc_running = pthread_create(&tc_thread, NULL, texel_copy_main, &tc) == 0;
        if (!tc_running) texel_copy_main(&tc);
    }
    vx__mesh_bins bins;
    memset(&bins, 0, sizeof bins);
    vx_result r = vx__mesh_bin(desc, mesh, grid, &bins, err);
    if (r) {
        if (tc_running) pthread_join(tc_thread, NULL);
        vx__mesh_mats_free(a, &plan);
        return r;
    }
    size_t P = bins.pair_count, NB = bins.total_bricks, T = mesh->tri_count;
    uint32_t* pairs2 = NULL;
    uint32_t* bricks = NULL;
    uint64_t* bm = NULL;
    uint32_t* trimat = NULL;
    const uint32_t *okeys = NULL, *orgba = NULL, *onrm = NULL, *omat = NULL; /* in the download buffer */
    size_t* cstart = NULL;
    size_t* ustart = NULL;
    const uint32_t *oids = NULL, *outab = NULL; /* interned tuples, in the download buffer */
    vx__svo_pool* pools = NULL; /* per region, built on the GPU (words in the pool download buffer) */
    uint32_t* ext = NULL;       /* per region the representatives' new tuples (gpu_build) */
    const uint32_t* ext_tuples = NULL;
    uint32_t* breg = NULL;
    size_t* mine = NULL;
    size_t mine_count = 0;
    float* mats = NULL;
    uint32_t* images = NULL;
    float* smats = NULL;  /* plan.sampled: meshvox.comp's SMat per material */
    float* plans = NULL;  /* plan.sampled: meshreduce.comp's Plan per material */
    if (P > UINT32_MAX / 64 - 1 || NB > (1ull << 40)) {
        r = vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "GPU voxelizer: %zu brick pairs", P);
        goto done;
    }
    pairs2 = (uint32_t*)vx_alloc(a, (P ? P : 1) * 8);
    bricks = (uint32_t*)vx_alloc(a, (NB ? NB : 1) * 16);
    bm = (uint64_t*)vx_alloc(a, (NB ? NB : 1) * 8);
    trimat = (uint32_t*)vx_alloc(a, (T ? T : 1) * 4);
    if (!pairs2 || !bricks || !bm || !trimat) {
        r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "GPU voxelizer: %zu pairs", P);
        goto done;
    }
    P = 0; /* the GPU's pairs: solid's fillers (bricks without a triangle) left out */
    for (size_t b = 0; b < NB; b++) {
        uint64_t mort = bins.pairs[bins.bstart[b]] >> 32;
        uint32_t x, y, z;
        vx_svo_demorton(mort, &x, &y, &z);
        bm[b] = mort;
        bricks[4 * b] = x * BRICK, bricks[4 * b + 1] = y * BRICK, bricks[4 * b + 2] = z * BRICK, bricks[4 * b + 3] = 0;
        for (size_t p = bins.bstart[b]; p < bins.bstart[b + 1]; p++) {
            uint32_t t = (uint32_t)(bins.pairs[p] & 0xFFFFFFFFu);
            if (t == 0xFFFFFFFFu) continue;
            pairs2[2 * P] = t;
            pairs2[2 * P + 1] = (uint32_t)b;
            P++;
        }
    }
    for (size_t t = 0; t < T; t++) trimat[t] = mesh->material ? mesh->material[t] : UINT32_MAX;
    /* materials: base colour, the image it samples (-1: none; as setup_tri_attrs decides), wraps, MATL id */
    uint32_t MC = mesh->material_count;
    mats = (float*)vx_calloc(a, MC ? MC : 1, 32);
    images = (uint32_t*)vx_calloc(a, mesh->image_count ? mesh->image_count : 1, 16);
    if (!mats || !images) {
        r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "GPU voxelizer: materials");
        goto done;
    }
    {
        size_t off = 0;
        for (uint32_t i = 0; i < mesh->image_count; i++) {
            const vx_gltf_image* im = &mesh->images[i];
            images[4 * i] = (uint32_t)off, images[4 * i + 1] = im->width, images[4 * i + 2] = im->height;
            if (!im->rgba) continue;
            off += (size_t)im->width * im->height;
        }
    }
    for (uint32_t i = 0; i < MC; i++) {
        const vx_gltf_material* mt = &mesh->materials[i];
        float* o = mats + 8 * i;
        memcpy(o, mt->base_color, 16);
        int32_t img = -1;
        if (mt->image >= 0 && (uint32_t)mt->image < mesh->image_count && mesh->images[mt->image].rgba && mesh->uv)
            img = mt->image;
        static const float no_emit[3] = {0, 0, 0};
        uint32_t u[4] = {(uint32_t)img, mt->wrap_s, mt->wrap_t, vx__mesh_mats_id(&plan, i, 0, 0, no_emit)};
        memcpy(o + 4, u, 16);
    }
    if (plan.sampled) { /* setup_tri_sampling's factors and textures per material; vx__mesh_mats_id's plan */
        smats = (float*)vx_calloc(a, MC ? MC : 1, 64);
        plans = (float*)vx_calloc(a, MC ? MC : 1, 48);
        if (!smats || !plans) {
            r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "GPU voxelizer: materials");
            goto done;
        }
        for (uint32_t i = 0; i < MC && i < plan.count; i++) {
            const vx__mesh_mat* p = &plan.m[i];
            const vx_gltf_material* mt = &mesh->materials[i];
            float* o = smats + 16 * i;
            o[0] = p->metal, o[1] = p->rough, o[2] = p->emit[0], o[3] = p->emit[1], o[4] = p->emit[2];
            bool mr = (p->sample & (VX__MESH_SAMPLE_METAL | VX__MESH_SAMPLE_ROUGH)) != 0, em = (p->sample & VX__MESH_SAMPLE_EMIT) != 0;
            int32_t u[8] = {p->sample,         mr ? mt->metal_rough.image : -1, mt->metal_rough.wrap_s, mt->metal_rough.wrap_t,
                            em ? mt->emissive_tex.image : -1, mt->emissive_tex.wrap_s, mt->emissive_tex.wrap_t, 0};
            memcpy(o + 8, u, 32);
            float* q = plans + 12 * i;
            q[0] = p->metal, q[1] = p->rough, q[2] = p->emit_max, q[3] = p->trans;
            uint32_t v[4] = {p->base, p->block, p->sample, p->special};
            memcpy(q + 4, v, 16);
            q[8] = p->emit[0], q[9] = p->emit[1], q[10] = p->emit[2]; /* the channels a sampled emission quantizes */
        }
    }
    struct {
        float lin[256], a255[256];
        uint32_t has_uv, has_color, mat_count, pad;
    } tables;
    struct {
        float thr[256];
        uint32_t guess[4097];
        uint32_t attrs, sampled, levels, mat_count;
    } rtables;
    vx__mesh_color_tables(rtables.thr, rtables.guess, tables.lin, tables.a255);
    tables.has_uv = mesh->uv != NULL;
    tables.has_color = mesh->color != NULL;
    tables.mat_count = MC;
    tables.pad = 0;
    rtables.attrs = attrs;
    rtables.sampled = plan.sampled;
    rtables.levels = plan.levels;
    rtables.mat_count = plan.sampled ? MC : 0;
    m->stats.bin = vx_time_now() - t0;
    m->stats.pairs = P;

    t0 = vx_time_now();
    upload ups[] = {{B_G, bins.g, (uint64_t)T * 72, 0},
                    {B_PAIRS, pairs2, (uint64_t)P * 8, 0},
                    {B_BRICKS, bricks, (uint64_t)NB * 16, 0},
                    {B_COUNTS, NULL, ((uint64_t)P * 64 + 2) * 4, 0},
                    {B_TRIMAT, trimat, (uint64_t)T * 4, 0},
                    {B_MATS, mats, (uint64_t)MC * 32, 0},
                    {B_IMAGES, images, (uint64_t)mesh->image_count * 16, 0},
                    {B_TEXELS, NULL, texels ? (uint64_t)texel_count * 4 : 0, 0}, /* from B_TEXUP */
                    {B_UV, tex ? mesh->uv : NULL, tex && mesh->uv ? (uint64_t)T * 24 : 0, 0},
                    {B_COL, tex ? mesh->color : NULL, tex && mesh->color ? (uint64_t)T * 48 : 0, 0},
                    {B_TABLES, &tables, sizeof tables, 0},
                    {B_RTABLES, &rtables, sizeof rtables, 0},
                    {B_SMATS, smats, plan.sampled ? (uint64_t)MC * 64 : 0, 0},
                    {B_PLANS, plans, plan.sampled ? (uint64_t)MC * 48 : 0, 0},
                    {B_UVMR, plan.sampled ? mesh->uv_mr : NULL, plan.sampled && mesh->uv_mr ? (uint64_t)T * 24 : 0, 0},
                    {B_UVEM, plan.sampled ? mesh->uv_emissive : NULL, plan.sampled && mesh->uv_emissive ? (uint64_t)T * 24 : 0, 0}};
    int nups = (int)(sizeof ups / sizeof ups[0]);
    if ((r = put_all(m, ups, nups, err))) goto done;
    m->stats.upload = vx_time_now() - t0; /* the copies themselves go with the count pass */

    /* count, prefix sum: counts[p] = pair p's first record, counts[P] = all */
    t0 = vx_time_now();
    meshvox_push mp = {(uint32_t)P, 0, 0, 0, {(int32_t)grid->size[0], (int32_t)grid->size[1], (int32_t)grid->size[2], 0}};
    mp.attrs = ((attrs & VX_ATTR_RGBA8) ? 1u : 0u) | ((attrs & VX_ATTR_NORMAL) ? 2u : 0u) |
               ((attrs & VX_ATTR_MATERIAL) ? 4u : 0u) | (plan.sampled ? 8u : 0u);
    static const int vox_ids[18] = {B_G,   B_PAIRS,  B_BRICKS, B_COUNTS, B_KEYS,  B_RECS, B_TRIMAT, B_MATS, B_IMAGES,
                                    B_TEXELS, B_UV, B_COL,    B_TABLES, B_VALS, B_SMATS, B_UVMR, B_UVEM,   B_RECX};
    if ((r = ensure(m, B_KEYS, 16, err)) || (r = ensure(m, B_RECS, 16, err)) || (r = ensure(m, B_VALS, 16, err)) ||
        (r = ensure(m, B_RECX, 16, err)))
        goto done;
    uint64_t slots = (uint64_t)P * 64; /* (pair, strip); two pairs a workgroup (meshvox.comp) */
    if ((r = scan_prepare(m, slots + 1, err)) || (r = rec_begin(m, err))) goto done;
    ts_begin(m, 8);
    if (tc_running) pthread_join(tc_thread, NULL), tc_running = false; /* the texels are in B_TEXUP */
    if (texels && texel_count) {
        VkBufferCopy ct = {.srcOffset = 0, .dstOffset = 0, .size = (uint64_t)texel_count * 4};
        vkCmdCopyBuffer(g->cmd, m->buf[B_TEXUP].buf, m->buf[B_TEXELS].buf, 1, &ct);
    }
    put_record(m, ups, nups);
    vkCmdFillBuffer(g->cmd, m->buf[B_COUNTS].buf, 0, (slots + 2) * 4, 0);
    barrier(g);
    if ((r = stage(m, P_COUNT, vox_ids, 18, (P + 1) / 2, &mp, sizeof mp, err))) goto done;
    if ((r = scan(m, B_COUNTS, slots + 1, 0, err))) goto done;
    read_u32(m, B_COUNTS, slots, 0);
    read_u32(m, B_COUNTS, slots + 1, 1);
    ts_end(m);
    if ((r = submit(m, err))) goto done;
    uint32_t NN[2];
    if ((r = vx__buffer_download(g, &m->buf[B_READ], NN, 8, err))) goto done;
    uint32_t N = NN[0];
    m->stats.count = vx_time_now() - t0;
    m->stats.records = N;
    if ((uint64_t)NN[1] * 256 > (uint64_t)UINT32_MAX - (1u << 20)) { /* the bound, not the wrapped sum */
        r = vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "GPU voxelizer: about %llu cell pieces, more than 2^32 (lower res)",
                    (unsigned long long)NN[1] * 256);
        goto done;
    }

    /* the records, their stable radix sort by (brick index, local Morton
     * key), one cell per run of keys: one submission (their wall time is
     * stats.emit's; the timestamps split it) */
    t0 = vx_time_now();
    unsigned key_bits = 18 + bits_for(NB ? NB - 1 : 0);
    uint32_t passes = (key_bits + 3) / 4;
    m->stats.sort_passes = passes;
    uint64_t ntiles = ((uint64_t)N + 1023) / 1024;
    if ((r = ensure(m, B_KEYS, (uint64_t)N * 8, err)) || (r = ensure(m, B_VALS, (uint64_t)N * 4, err)) ||
        (r = ensure(m, B_RECS, attrs ? (uint64_t)N * 48 : 16, err)) ||
        (r = ensure(m, B_RECX, plan.sampled ? (uint64_t)N * 8 : 16, err)) || (r = ensure(m, B_KEYS2, (uint64_t)N * 8, err)) ||
        (r = ensure(m, B_VALS2, (uint64_t)N * 4, err)) || (r = ensure(m, B_HIST, ntiles * 16 * 4 + 4, err)) ||
        (r = scan_prepare(m, ntiles * 16, err)) || (r = ensure(m, B_POS, ((uint64_t)N + 1) * 4, err)) ||
        (r = ensure(m, B_OKEYS, (uint64_t)N * 8, err)) || (r = ensure(m, B_ORGBA, (uint64_t)N * 4, err)) ||
        (r = ensure(m, B_ONRM, (uint64_t)N * 4, err)) || (r = ensure(m, B_OMAT, (uint64_t)N * 4, err)) ||
        (r = scan_prepare(m, (uint64_t)N + 1, err)))
        goto done;
    if ((r = rec_begin(m, err))) goto done;
    mp.mode = 1;
    ts_begin(m, 9);
    if ((r = stage(m, P_EMIT, vox_ids, 18, (P + 1) / 2, &mp, sizeof mp, err))) goto done;
    ts_end(m);
    int src = 0; /* 0: KEYS/VALS, 1: KEYS2/VALS2 */
    ts_begin(m, 10);
    for (uint32_t pass = 0; pass < passes && N > 1; pass++)
        if ((r = sort_pass(m, N, 4 * pass, ntiles, &src, err))) goto done;
    ts_end(m);
    {
        int ids[11] = {src ? B_KEYS2 : B_KEYS, src ? B_VALS2 : B_VALS, B_RECS, B_POS,    B_OKEYS, B_ORGBA,
                       B_ONRM,                B_OMAT,                B_RTABLES, B_PLANS, B_RECX};
        uint32_t n = N;
        ts_begin(m, 11);
        vkCmdFillBuffer(g->cmd, m->buf[B_POS].buf, 0, ((VkDeviceSize)N + 1) * 4, 0);
        barrier(g);
        if ((r = stage(m, P_FLAG, ids, 11, ((uint64_t)N + 255) / 256, &n, 4, err))) goto done;
        if ((r = scan(m, B_POS, (uint64_t)N + 1, 0, err))) goto done;
        if ((r = stage(m, P_REDUCE, ids, 11, ((uint64_t)N + 255) / 256, &n, 4, err))) goto done;
        read_u32(m, B_POS, N, 0);
        ts_end(m);
    }
    if ((r = submit(m, err))) goto done;
    uint32_t C;
    if ((r = vx__buffer_download(g, &m->buf[B_READ], &C, 4, err))) goto done;
    m->stats.emit = vx_time_now() - t0;
    m->stats.cells = C;

    /* the cells' tuples interned per region (meshintern.comp), so that the
     * builders hash each distinct tuple once instead of every cell's */
    t0 = vx_time_now();
    uint32_t U = 0;
    bool intern = attrs && C > 0 && bins.region_count <= 65536 && !desc->solid; /* solid: the CPU fills, the builders hash */
    if (intern) {
        breg = (uint32_t*)vx_alloc(a, (NB ? NB : 1) * 4);
        if (!breg) {
            r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "GPU voxelizer: %zu bricks", NB);
            goto done;
        }
        for (size_t ri = 0; ri < bins.region_count; ri++)
            for (size_t b = bins.rstart[ri]; b < bins.rstart[ri + 1]; b++) breg[b] = (uint32_t)ri;
        upload ur = {B_REGION, breg, (uint64_t)NB * 4, 0};
        uint64_t ntiles = ((uint64_t)C + 1023) / 1024;
        if ((r = put_all(m, &ur, 1, err)) || (r = ensure(m, B_IDS, (uint64_t)C * 4, err)) ||
            (r = ensure(m, B_UTAB, (uint64_t)C * 16, err)) || (r = ensure(m, B_HIST, ntiles * 16 * 4 + 4, err)) ||
            (r = scan_prepare(m, ntiles * 16, err)) || (r = scan_prepare(m, (uint64_t)C + 1, err)) || (r = rec_begin(m, err)))
            goto done;
        ts_begin(m, 12);
        put_record(m, &ur, 1);
        intern_push ip = {C, ((attrs & VX_ATTR_RGBA8) ? 1u : 0u) | ((attrs & VX_ATTR_NORMAL) ? 2u : 0u) |
                                 ((attrs & VX_ATTR_MATERIAL) ? 4u : 0u), 0};
        uint64_t groups = ((uint64_t)C + 255) / 256;
        int src = 0;
        int ids[10] = {B_KEYS, B_VALS, B_OKEYS, B_ORGBA, B_ONRM, B_OMAT, B_REGION, B_POS, B_IDS, B_UTAB};
        uint32_t shifts[16], ns = 0;
        if (attrs & VX_ATTR_NORMAL) { /* LSD: by normal first, the rest stably after */
            if ((r = stage(m, P_INKEY, ids, 10, groups, &ip, sizeof ip, err))) goto done;
            for (uint32_t q = 0; q < 8; q++)
                if ((r = sort_pass(m, C, 4 * q, ntiles, &src, err))) goto done;
            ip.perm = 1;
        }
        ids[0] = src ? B_KEYS2 : B_KEYS, ids[1] = src ? B_VALS2 : B_VALS;
        if ((r = stage(m, P_IKEY, ids, 10, groups, &ip, sizeof ip, err))) goto done;
        for (uint32_t q = 0; (attrs & VX_ATTR_RGBA8) && q < 8; q++) shifts[ns++] = 4 * q;
        for (uint32_t q = 0; (attrs & VX_ATTR_MATERIAL) && q < 4; q++) shifts[ns++] = 32 + 4 * q;
        for (uint32_t q = 0; 4 * q < bits_for(bins.region_count - 1); q++) shifts[ns++] = 48 + 4 * q;
        for (uint32_t q = 0; q < ns; q++)
            if ((r = sort_pass(m, C, shifts[q], ntiles, &src, err))) goto done;
        m->stats.intern_passes = ns + ((attrs & VX_ATTR_NORMAL) ? 8 : 0);
        ids[0] = src ? B_KEYS2 : B_KEYS, ids[1] = src ? B_VALS2 : B_VALS;
        vkCmdFillBuffer(g->cmd, m->buf[B_POS].buf, 0, ((VkDeviceSize)C + 1) * 4, 0);
        barrier(g);
        if ((r = stage(m, P_IFLAG, ids, 10, groups, &ip, sizeof ip, err))) goto done;
        if ((r = scan(m, B_POS, (uint64_t)C + 1, 0, err))) goto done;
        if ((r = stage(m, P_IOUT, ids, 10, groups, &ip, sizeof ip, err))) goto done;
        read_u32(m, B_POS, C, 0);
        ts_end(m);
        if ((r = submit(m, err))) goto done;
        if ((r = vx__buffer_download(g, &m->buf[B_READ], &U, 4, err))) goto done;
        if (U == 0 || U > C) {
            r = vx_fail(err, VX_ERR_GPU, VX_NO_OFFSET, "GPU voxelizer: %u distinct tuples of %u cells", U, C);
            goto done;
        }
    }
    m->stats.intern = vx_time_now() - t0;
    m->stats.tuples = U;

    t0 = vx_time_now();
    cstart = (size_t*)vx_alloc(a, (bins.region_count + 1) * sizeof *cstart);
    ustart = (size_t*)vx_alloc(a, (bins.region_count + 1) * sizeof *ustart);
    if (!cstart || !ustart) {
        r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "GPU voxelizer: %zu regions", bins.region_count);
        goto done;
    }
    /* the octrees on the GPU (below) when the sink builds them: then only
     * the tuples come back, not the cells (unless the builders check) */
    bool want_build = intern && m->build != VX_CONV_MESH_GPU_BUILD_CPU && !desc->build.no_collapse && !desc->build.no_dag;
    bool lean = want_build && builds && (m->build == VX_CONV_MESH_GPU_BUILD_GPU || m->build == VX_CONV_MESH_GPU_BUILD_GPU_POOLS);
    if ((r = download(m, C, U, attrs, intern, !lean, &okeys, &orgba, &onrm, &omat, &oids, &outab, err))) goto done;
    m->stats.download = vx_time_now() - t0;

    if (outab) { /* ids come in region order: each region's are a range */
        size_t u = 0;
        for (size_t ri = 0; ri < bins.region_count; ri++) {
            ustart[ri] = u;
            while (u < U && outab[4 * u + 3] <= ri) u++;
        }
        ustart[bins.region_count] = u;
    }
    /* the octrees on the GPU, down to their node pools */
    t0 = vx_time_now();
    if (want_build) {
        if ((r = gpu_build(m, &bins, grid, bm, breg, C, ustart, U, attrs, desc->build.max_depth, a, &pools, &ext, &ext_tuples,
                           err)))
            goto done;
        if (!pools) m->stats.build_fallback = 1;
    }
    if (lean && !pools) { /* the CPU builders build after all: they need the cells */
        double t1 = vx_time_now();
        if ((r = download(m, C, U, attrs, intern, true, &okeys, &orgba, &onrm, &omat, &oids, &outab, err))) goto done;
        m->stats.download += vx_time_now() - t1;
    }
    /* regions: cells are sorted by brick index, regions are runs of bricks */
    if (okeys) {
        size_t c = 0;
        for (size_t ri = 0; ri < bins.region_count; ri++) {
            cstart[ri] = c;
            uint64_t end_brick = bins.rstart[ri + 1];
            while (c < C && ((uint64_t)(okeys[2 * c] >> 18) | (uint64_t)okeys[2 * c + 1] << 14) < end_brick) c++;
        }
        cstart[bins.region_count] = c;
    } else { /* counted on the GPU */
        size_t c = 0;
        for (size_t ri = 0; ri < bins.region_count; ri++) cstart[ri] = c, c += ext[2 * bins.region_count + ri];
        cstart[bins.region_count] = c;
        if (c != C) {
            r = vx_fail(err, VX_ERR_GPU, VX_NO_OFFSET, "GPU octree build: %zu cells counted in regions of %u", c, C);
            goto done;
        }
    }
    m->stats.build = vx_time_now() - t0;
    t0 = vx_time_now();
    {
        /* under MPI each process builds its share's regions; the GPU voxelized
         * them all (a few percent of the conversion; the builds are the cost) */
        size_t mine_bricks;
        if ((r = vx__mesh_share_regions(bins.rstart, bins.region_count, share, shares, a, &mine, &mine_count, &mine_bricks,
                                        err)))
            goto done;
        region_job j = {&bins, grid, bm, okeys, orgba, onrm, omat, cstart, oids, outab, ustart, pools, ext, ext_tuples,
                        m->build == VX_CONV_MESH_GPU_BUILD_CHECK, desc->solid, false, 1, 1, mine, mine_count, attrs, sink, user, a,
                        PTHREAD_MUTEX_INITIALIZER, VX_OK, {0}};
        unsigned threads = desc->threads ? desc->threads : 0;
        if (threads == 0) {
            long nc = sysconf(_SC_NPROCESSORS_ONLN);
            threads = nc > 0 ? (unsigned)nc : 1;
        }
        unsigned cores = threads;
        if (threads > 64) threads = 64;
        if (threads > mine_count) threads = (unsigned)(mine_count ? mine_count : 1);
        /* fewer regions than cores (8 regions at 1024^3 and beyond): each
         * builder lays its blocks out on a second thread as it builds */
        j.layout_thread = 2 * threads <= cores;
        /* and interns its tuples (a 4096^3 region can hold 14 M) on its share of the cores */
        j.intern_threads = cores / threads;
        /* copies (filled records) are memory-bound and the regions unequal
         * (at 4096^3 the largest holds a fifth of the records): a large
         * region's builder may use every core (16 threads for each of 8
         * builders at 4096^3: the copies 59 ms, against 630 ms for the
         * lookups on 2 threads each); at 1024^3 the regions' few MB keep
         * their 2 (16 each cost 6 ms more in thread starts and faults) */
        j.copy_threads = cores;
        vx_run_jobs(threads, (uint32_t)mine_count, region_run, &j);
        pthread_mutex_destroy(&j.lock);
        if (j.failed) {
            r = j.failed;
            if (err) *err = j.first_err;
        }
    }
    m->stats.sink = vx_time_now() - t0;

done:
    vx__mesh_mats_free(a, &plan);
    if (tc_running) pthread_join(tc_thread, NULL);
    vx_free(a, pairs2);
    vx_free(a, bricks);
    vx_free(a, bm);
    vx_free(a, trimat);
    vx_free(a, mats);
    vx_free(a, images);
    vx_free(a, smats);
    vx_free(a, plans);
    vx_free(a, cstart);
    vx_free(a, ustart);
    vx_free(a, breg);
    vx_free(a, pools);
    vx_free(a, ext);
    vx_free(a, mine);
    vx__mesh_bins_free(a, &bins);
    return r;
}

/* ---- the object ---------------------------------------------------------------------- */

static vx_result make_pipe(vx_conv_mesh_gpu* m, int which, const uint32_t* spv, size_t bytes, uint32_t mode,
                           uint32_t bindings, uint32_t push, const char* label, vx_error* err) {
    vx_gpu_compute_pipeline_desc d;
    memset(&d, 0, sizeof d);
    d.spirv = spv;
    d.spirv_size = bytes;
    d.push_constant_size = push;
    d.binding_count = bindings;
    for (uint32_t i = 0; i < bindings; i++) d.bindings[i] = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    d.spec_count = 1;
    d.spec[0] = mode;
    d.label = label;
    return vx__pipeline_get(m->g, 0x6D76B000ull + (uint64_t)which, &d, &m->pipe[which], err);
}

vx_result vx_conv_mesh_gpu_create(struct vx_gpu* gpu, const vx_allocator* alloc, vx_conv_mesh_gpu** out,
                                  vx_error* err) {
    if (!gpu || !out) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "GPU voxelizer: NULL argument");
    if (!gpu->has_float64)
        return vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET,
                       "GPU voxelizer: the device has no shaderFloat64 (the CPU voxelizer's arithmetic is double)");
    vx_conv_mesh_gpu* m = (vx_conv_mesh_gpu*)vx_calloc(alloc, 1, sizeof *m);
    if (!m) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "GPU voxelizer");
    m->g = gpu;
    m->alloc = alloc;
    m->backend.voxelize = gpu_voxelize;
    m->backend.self = m;
    /* the voxelizer's and the interning's pipelines: one shader each, the mode a specialization constant */
    static const struct {
        int pipe;
        const uint32_t* spv;
        size_t bytes;
        uint32_t mode, bindings, push;
        const char* label;
    } pipes[] = {
        {P_COUNT, vx__meshvox_spv_arr, sizeof vx__meshvox_spv_arr, 0, 18, sizeof(meshvox_push), "meshgpu.count"},
        {P_EMIT, vx__meshvox_spv_arr, sizeof vx__meshvox_spv_arr, 1, 18, sizeof(meshvox_push), "meshgpu.emit"},
        {P_HIST, vx__gpusort_spv_arr, sizeof vx__gpusort_spv_arr, 0, 5, sizeof(sort_push), "meshgpu.hist"},
        {P_SCATTER, vx__gpusort_spv_arr, sizeof vx__gpusort_spv_arr, 1, 5, sizeof(sort_push), "meshgpu.scatter"},
        {P_SCAN, vx__gpuscan_spv_arr, sizeof vx__gpuscan_spv_arr, 0, 2, 4, "meshgpu.scan"},
        {P_ADD, vx__gpuscan_spv_arr, sizeof vx__gpuscan_spv_arr, 1, 2, 4, "meshgpu.add"},
        {P_FLAG, vx__meshreduce_spv_arr, sizeof vx__meshreduce_spv_arr, 0, 11, 4, "meshgpu.flag"},
        {P_REDUCE, vx__meshreduce_spv_arr, sizeof vx__meshreduce_spv_arr, 1, 11, 4, "meshgpu.reduce"},
        {P_IKEY, vx__meshintern_spv_arr, sizeof vx__meshintern_spv_arr, 0, 10, sizeof(intern_push), "meshgpu.ikey"},
        {P_INKEY, vx__meshintern_spv_arr, sizeof vx__meshintern_spv_arr, 3, 10, sizeof(intern_push), "meshgpu.inkey"},
        {P_IFLAG, vx__meshintern_spv_arr, sizeof vx__meshintern_spv_arr, 1, 10, sizeof(intern_push), "meshgpu.iflag"},
        {P_IOUT, vx__meshintern_spv_arr, sizeof vx__meshintern_spv_arr, 2, 10, sizeof(intern_push), "meshgpu.iout"},
    };
    vx_result r = vx__buffer_create(gpu, 32, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, true, "meshgpu.read", &m->buf[B_READ], err);
    for (size_t i = 0; !r && i < sizeof pipes / sizeof pipes[0]; i++)
        r = make_pipe(m, pipes[i].pipe, pipes[i].spv, pipes[i].bytes, pipes[i].mode, pipes[i].bindings, pipes[i].push,
                      pipes[i].label, err);
    if (r) {
        vx_conv_mesh_gpu_destroy(m);
        return r;
    }
    for (uint32_t mode = 0; mode < BUILD_MODES; mode++)
        if ((r = make_pipe(m, P_BUILD + (int)mode, vx__meshbuild_spv_arr, sizeof vx__meshbuild_spv_arr, mode, BUILD_BINDINGS,
                           sizeof(build_push), "meshgpu.build", err))) {
            vx_conv_mesh_gpu_destroy(m);
            return r;
        }
    if (gpu->has_timestamps) { /* the build's steps timed (stats.build_gpu); none: wall times only */
        VkQueryPoolCreateInfo qi = {.sType = VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO,
                                    .queryType = VK_QUERY_TYPE_TIMESTAMP,
                                    .queryCount = 2 * TS_PAIRS};
        if (vkCreateQueryPool(gpu->device, &qi, NULL, &m->qp) != VK_SUCCESS) m->qp = VK_NULL_HANDLE;
    }
    VkDescriptorPoolSize size = {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 512 * BUILD_BINDINGS};
    VkDescriptorPoolCreateInfo pci = {.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO,
                                      .maxSets = 512,
                                      .poolSizeCount = 1,
                                      .pPoolSizes = &size};
    VkResult vr = vkCreateDescriptorPool(gpu->device, &pci, NULL, &m->pool);
    if (vr != VK_SUCCESS) {
        vx_conv_mesh_gpu_destroy(m);
        return vx__vk_fail(err, vr, "vkCreateDescriptorPool");
    }
    *out = m;
    return VX_OK;
}

const struct vx_conv_mesh_backend* vx_conv_mesh_gpu_backend(vx_conv_mesh_gpu* mg) { return mg ? &mg->backend : NULL; }

void vx_conv_mesh_gpu_last_stats(const vx_conv_mesh_gpu* mg, vx_conv_mesh_gpu_stats* out) {
    if (mg && out) *out = mg->stats;
}

void vx_conv_mesh_gpu_set_build(vx_conv_mesh_gpu* mg, vx_conv_mesh_gpu_build mode) {
    if (mg) mg->build = mode;
}

void vx_conv_mesh_gpu_set_hash(vx_conv_mesh_gpu* mg, vx_conv_mesh_gpu_hash hash) {
    if (mg) mg->hash = hash;
}

void vx_conv_mesh_gpu_destroy(vx_conv_mesh_gpu* m) {
    if (!m) return;
    vkDeviceWaitIdle(m->g->device);
    for (int i = 0; i < B_COUNT; i++)
        if (m->buf[i].buf) vx__buffer_destroy(m->g, &m->buf[i]);
    if (m->pool) vkDestroyDescriptorPool(m->g->device, m->pool, NULL);
    if (m->qp) vkDestroyQueryPool(m->g->device, m->qp, NULL);
    vx_free(m->alloc, m);
}
