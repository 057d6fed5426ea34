/* bench/tree64.c - the 64-tree prototype's build (from the scene's cells)
 * and its dispatch; see bench/tree64.h. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bench/tree64.h"
#include "tree64.comp.h"

#define T64_MAX_NODES (UINT64_C(1) << 28)
#define T64_MAX_OCT 21 /* octree levels a 63-bit Morton key holds */

typedef struct key_list {
    uint64_t* k;
    size_t n, cap;
    int64_t lo[3];
    int64_t side;
    bool nomem;
} key_list;

/* Spreads the low 21 bits of v to every third bit. */
static uint64_t spread3(uint64_t v) {
    v &= 0x1FFFFF;
    v = (v | v << 32) & UINT64_C(0x1F00000000FFFF);
    v = (v | v << 16) & UINT64_C(0x1F0000FF0000FF);
    v = (v | v << 8) & UINT64_C(0x100F00F00F00F00F);
    v = (v | v << 4) & UINT64_C(0x10C30C30C30C30C3);
    v = (v | v << 2) & UINT64_C(0x1249249249249249);
    return v;
}

static void key_cb(void* user, int64_t x, int64_t y, int64_t z) {
    key_list* l = user;
    x -= l->lo[0], y -= l->lo[1], z -= l->lo[2];
    if (x < 0 || y < 0 || z < 0 || x >= l->side || y >= l->side || z >= l->side || l->nomem) return;
    if (l->n == l->cap) {
        size_t cap = l->cap ? l->cap * 2 : 1u << 16;
        uint64_t* p = realloc(l->k, cap * sizeof *p);
        if (!p) {
            l->nomem = true;
            return;
        }
        l->k = p, l->cap = cap;
    }
    l->k[l->n++] = spread3((uint64_t)x) | spread3((uint64_t)y) << 1 | spread3((uint64_t)z) << 2;
}

static int cmp_u64(const void* a, const void* b) {
    uint64_t x = *(const uint64_t*)a, y = *(const uint64_t*)b;
    return x < y ? -1 : x > y;
}

/* Bit of a 64-tree child from its 6 Morton bits (two octree levels, the
 * upper level's xyz in bits 3-5): x + 4 y + 16 z. */
static uint32_t child_bit(uint32_t d) {
    uint32_t x = ((d >> 3) & 1) * 2 + (d & 1), y = ((d >> 4) & 1) * 2 + ((d >> 1) & 1),
             z = ((d >> 5) & 1) * 2 + ((d >> 2) & 1);
    return x + 4 * y + 16 * z;
}

typedef struct open_node {
    uint64_t mask;
    uint32_t child[64][4];
} open_node;

typedef struct builder {
    uint32_t* nodes; /* 4 words per node */
    uint64_t count, cap;
    uint32_t* table; /* block start + 1 (0: free) */
    uint8_t* table_n;
    uint64_t table_cap, table_used;
    bool fail;
} builder;

static uint64_t hash_words(const uint32_t* w, size_t n) {
    uint64_t h = UINT64_C(1469598103934665603);
    for (size_t i = 0; i < n; i++) h = (h ^ w[i]) * UINT64_C(1099511628211);
    return h ^ (h >> 29);
}

static bool table_grow(builder* b) {
    uint64_t cap = b->table_cap ? b->table_cap * 2 : 1u << 16;
    uint32_t* t = calloc(cap, sizeof *t);
    uint8_t* tn = calloc(cap, 1);
    if (!t || !tn) {
        free(t), free(tn);
        return false;
    }
    for (uint64_t i = 0; i < b->table_cap; i++) {
        if (!b->table[i]) continue;
        uint32_t s = b->table[i] - 1, n = b->table_n[i];
        uint64_t j = hash_words(b->nodes + 4 * (uint64_t)s, 4 * (size_t)n) & (cap - 1);
        while (t[j]) j = (j + 1) & (cap - 1);
        t[j] = b->table[i], tn[j] = (uint8_t)n;
    }
    free(b->table), free(b->table_n);
    b->table = t, b->table_n = tn, b->table_cap = cap;
    return true;
}

/* The index of a block of n nodes equal to blk (n*4 words), appended unless
 * an identical block is stored already. */
static uint32_t intern(builder* b, const uint32_t* blk, uint32_t n) {
    if (b->fail) return 0;
    if ((b->table_used + 1) * 2 > b->table_cap && !table_grow(b)) {
        b->fail = true;
        return 0;
    }
    uint64_t j = hash_words(blk, 4 * (size_t)n) & (b->table_cap - 1);
    for (; b->table[j]; j = (j + 1) & (b->table_cap - 1))
        if (b->table_n[j] == n && !memcmp(b->nodes + 4 * (uint64_t)(b->table[j] - 1), blk, 16 * (size_t)n))
            return b->table[j] - 1;
    if (b->count + n > T64_MAX_NODES) {
        b->fail = true;
        return 0;
    }
    if (b->count + n > b->cap) {
        uint64_t cap = b->cap ? b->cap * 2 : 1u << 16;
        uint32_t* p = realloc(b->nodes, cap * 16);
        if (!p) {
            b->fail = true;
            return 0;
        }
        b->nodes = p, b->cap = cap;
    }
    uint32_t s = (uint32_t)b->count;
    memcpy(b->nodes + 4 * b->count, blk, 16 * (size_t)n);
    b->count += n;
    b->table[j] = s + 1, b->table_n[j] = (uint8_t)n; /* n == 64 fits: 1..64 */
    b->table_used++;
    return s;
}

/* Node words of open node o (leaf level: the cells' mask only). */
static void close_node(builder* b, open_node* o, bool leaf_level, uint32_t out[4]) {
    out[0] = (uint32_t)o->mask, out[1] = (uint32_t)(o->mask >> 32), out[2] = 0, out[3] = 0;
    if (!leaf_level) {
        uint32_t blk[64 * 4], n = 0;
        for (uint32_t i = 0; i < 64; i++)
            if (o->mask >> i & 1) memcpy(blk + 4 * n++, o->child[i], 16);
        out[2] = intern(b, blk, n);
    }
    o->mask = 0;
}

vx_result bench_tree64_create(vx_gpu* gpu, const vx_svo_scene* s, bench_tree64* t, vx_error* err) {
    memset(t, 0, sizeof *t);
    t->gpu = gpu;
    t->root = UINT32_MAX;
    double t0 = vx_time_now();
    bench_cube(s, 1, t->lo, &t->clip_depth);
    t->levels = (t->clip_depth + 1) / 2;
    if (2 * t->levels > T64_MAX_OCT)
        return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "64-tree: %u octree levels exceed %u", 2 * t->levels,
                       T64_MAX_OCT);
    key_list kl = {.side = (int64_t)1 << t->clip_depth};
    memcpy(kl.lo, t->lo, sizeof kl.lo);
    vx_result r = vx__scene_grid_cells(s, key_cb, &kl, err);
    if (!r && kl.nomem) r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "64-tree: out of memory for the cells");
    if (r) {
        free(kl.k);
        return r;
    }
    /* one model's cells come in Morton order; several instances do not */
    bool sorted = true;
    for (size_t i = 1; i < kl.n && sorted; i++) sorted = kl.k[i - 1] < kl.k[i];
    if (!sorted) {
        qsort(kl.k, kl.n, sizeof *kl.k, cmp_u64);
        size_t m = 0;
        for (size_t i = 0; i < kl.n; i++)
            if (!m || kl.k[i] != kl.k[m - 1]) kl.k[m++] = kl.k[i];
        kl.n = m;
    }
    t->cells = kl.n;
    uint32_t L = t->levels;
    builder b = {0};
    open_node* open = calloc(L, sizeof *open);
    if (!open) b.fail = true;
    for (size_t i = 0; i < kl.n && !b.fail; i++) {
        uint64_t k = kl.k[i];
        if (i > 0) {
            uint64_t p = kl.k[i - 1];
            /* close the nodes (bottom up) that p's and k's paths no longer share */
            uint32_t l = 1;
            while (l < L && (k >> 6 * (L - l)) == (p >> 6 * (L - l))) l++;
            for (uint32_t j = L - 1; j >= l && j > 0; j--) {
                uint32_t bit = child_bit((uint32_t)(p >> 6 * (L - j)) & 63);
                close_node(&b, &open[j], j == L - 1, open[j - 1].child[bit]);
                open[j - 1].mask |= UINT64_C(1) << bit;
            }
        }
        open[L - 1].mask |= UINT64_C(1) << child_bit((uint32_t)k & 63);
    }
    if (kl.n && !b.fail) {
        uint64_t p = kl.k[kl.n - 1];
        for (uint32_t j = L - 1; j > 0; j--) {
            uint32_t bit = child_bit((uint32_t)(p >> 6 * (L - j)) & 63);
            close_node(&b, &open[j], j == L - 1, open[j - 1].child[bit]);
            open[j - 1].mask |= UINT64_C(1) << bit;
        }
        uint32_t root[4];
        close_node(&b, &open[0], L == 1, root);
        t->root = intern(&b, root, 1);
    }
    free(open);
    free(kl.k);
    free(b.table), free(b.table_n);
    if (b.fail) r = vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "64-tree: more than 2^28 nodes (or out of memory)");
    t->node_count = b.count;
    t->build_seconds = vx_time_now() - t0;
    if (!r && !b.count) { /* an empty scene: one node so that the buffer exists */
        static const uint32_t zero[4] = {0};
        b.nodes = malloc(16);
        if (b.nodes) memcpy(b.nodes, zero, 16), b.count = 1;
        else r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory");
    }
    if (!r)
        r = vx__buffer_create(gpu, (VkDeviceSize)b.count * 16, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, false,
                              "tree64 nodes", &t->buf, err);
    if (!r) r = vx__buffer_upload(gpu, &t->buf, b.nodes, (VkDeviceSize)b.count * 16, err);
    free(b.nodes);
    if (r) bench_tree64_destroy(t);
    return r;
}

void bench_tree64_destroy(bench_tree64* t) {
    if (!t || !t->gpu) return;
    bench_kernel_destroy(t->gpu, &t->k);
    vx__buffer_destroy(t->gpu, &t->buf);
    memset(t, 0, sizeof *t);
}

uint64_t bench_tree64_bytes(const bench_tree64* t) { return t->node_count * 16; }

vx_result bench_tree64_frame(bench_tree64* t, uint32_t variant, const vx_svo_scene* s, const vx_render_desc* desc,
                             uint32_t repeat,
                             double* seconds, float* depth, uint32_t* steps, vx_error* err) {
    vx_gpu_compute_pipeline_desc pd = {.spirv = vx__tree64_spv_arr, .spirv_size = sizeof vx__tree64_spv_arr,
                                       .binding_count = 3, .spec_count = 1, .spec = {variant},
                                       .label = "tree64"};
    pd.bindings[0] = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
    pd.bindings[1] = pd.bindings[2] = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    /* box.w: the 64-tree's cube (4^levels); the rays are clipped to the ESVO cube */
    return bench_kernel_frame(t->gpu, &t->k, &pd, UINT64_C(0x7E6407E600) + variant, &t->buf, s, desc, t->lo,
                              (double)((int64_t)1 << 2 * t->levels), t->levels | t->clip_depth << 8, t->root,
                              repeat, seconds, depth, steps, err);
}
