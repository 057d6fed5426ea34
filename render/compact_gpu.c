/* render/compact_gpu.c - the compact layout on the GPU (render/compact.h,
 * issue 18): its geometry DAG, attribute blocks and model table uploaded
 * beside a render scene, traced by shaders/trace_compact.comp with the
 * render scene's frame block, instance table and BVH (bindings 0, 4-6 of
 * vx__render_scene_tables), so both kernels see the same instances and rays. */
#include <stdlib.h>
#include <string.h>

#include "render/compact.h"
#include "render/render_internal.h"
#include "trace_compact.comp.h"

/* shaders/trace_compact.comp's CModel */
typedef struct cmodel_gpu {
    uint32_t root, depth, flags, box, attr_base, block_log2, kind, rank_base, rebase, page_up, pool_base, unit_log2;
    uint32_t tab_word, tab_k; /* the model's start table (below): its first word in attr, its level (0: none) */
    uint32_t value; /* flags & 4 (a model whose cells all hold one value, the whole layout): its colour */
    uint32_t rec3;  /* the whole layout: level-3 slot s's record is geometry slot rec3 + s (0: none; below) */
} cmodel_gpu;
/* a scene of one instance: its model's record in the frame block too (dispatch) */
_Static_assert(sizeof(cmodel_gpu) <= sizeof(((vx__gpu_frame*)0)->cmodel0), "cmodel_gpu vs the frame block's cmodel0");

/* The paged layout's state on the host (vx_compact_gpu_create_paged). */
typedef struct paging {
    vx_compact_paged p;
    uint32_t words_base;  /* the pool's first word in the buffer (the top's words before it) */
    uint32_t unit;        /* slots per pool unit */
    uint32_t units;       /* pool units */
    uint32_t cursor;      /* next-fit start */
    uint32_t* owner;      /* per unit: page + 1, 0 free */
    uint64_t* busy;       /* per unit a bit: owned (owner != 0), for pool_find's word-at-a-time scan */
    int64_t* slot;        /* per page: its pool slot P, -1 not resident */
    uint64_t* last_used;  /* per page: the last frame a ray entered it */
    uint32_t* pending;    /* pages the last frame requested */
    uint32_t npending;
    uint32_t* state;      /* the state buffer's words as uploaded before a frame */
    uint32_t state_words, list_off, req_off, rep_off, use_off, bitmap_words, use_words;
    uint32_t* evict_patch; /* pages whose top slot must say "not resident" at the next service */
    uint32_t nevict;
    uint32_t* moved;       /* resident pages the service moved (loaded again from the host elsewhere) */
    uint32_t nmoved;
    uint64_t* moved_bit;   /* per page a bit: in moved[] (the list's membership without a search) */
    int64_t* moved_from;   /* per page in moved[]: its slot before the service moved it (its words on the GPU) */
    struct victim { uint64_t used; uint32_t page; } * victims; /* scratch: the service's eviction candidates */
    uint32_t free_units;
    vx_compact_page_stats st;
    vx_compact_page_cache* cache; /* the file source (p.reader): images cut from the file, a host cache */
    uint32_t** dst;               /* scratch: where each load's image goes in the staging buffer */
} paging;

struct vx_compact_gpu {
    vx_render_scene* rs;
    vx_gpu* gpu;
    vx__buffer geom, attr, models, palette, pixels, hits, pstate, stage;
    vx__buffer pass_models; /* the palette, then the CModels: trace_common.glsl's binding 3 (COMPACT) */
    /* the attribute words beyond one storage buffer's range: parts 1.. of
     * 2^attr_shift words each (attr is part 0; attr_shift 0: attr holds them all) */
    vx__buffer attr_hi[VX_COMPACT_ATTR_PARTS - 1];
    uint32_t attr_shift, attr_parts;
    double lo[3], hi[3];
    uint32_t deep;
    uint32_t dict; /* the kernel's DICT constant: the layout has its brick dictionary */
    uint64_t table_bytes; /* the start tables' (in attr) */
    uint64_t record_bytes; /* the level-3 records' (after the geometry words) */
    bool records;          /* some model has them (CModel.rec3): the kernel's RECORDS constant */
    uint64_t uniform_entries; /* of their entries, TAB_UNIFORM ones */
    uint32_t uniform_models; /* of the models, those of one value (CModel flag 4) */
    uint64_t bytes;
    paging* pg; /* NULL: the whole layout is resident (geom and attr) */
    cmodel_gpu* cm; /* the models' records as uploaded (cm_count of them; NULL when paged): the frame block's cmodel0 */
    uint32_t cm_count;
    /* per model (path_count of them): its listed top for the primary rays'
     * starts below the root (vx__render_scene_paths; top NULL: none), owned */
    vx__path_model* paths;
    uint32_t path_count;
    uint32_t start_min; /* the fewest pushes a start skips (vx__compact_gpu_start_min; 0: START_MIN) */
    /* the whole layout's geometry words (the first of geom's) and slots, for a read-back (vx__compact_gpu_geometry) */
    uint32_t geom_words, slot_count, brick_count;
    /* the models' material ids (material_regions below): mat_used a bit per
     * id some record of the scene has (NULL: none built), mat_max the
     * largest; mat_missing: they were needed and could not be read */
    uint32_t* mat_used;
    uint32_t mat_max;
    bool mat_missing;
    uint64_t mat_bytes;
};

/* A start below the root skips at least this many pushes: on the H200 one
 * push saved (eph_monu1's close-up) cost 1.7% of the albedo rays/s and 6%
 * in the depth mode, two (the terrain's) gained 0.3% and 1.6%, four (the
 * helmet's, eph_menger's) 6% and 20% (docs/PERFORMANCE.md issue 18,
 * fourteenth step) */
#define START_MIN 2u

/* The kernel's DEEP constant, trace.comp's rule (vx__render_model_deep, render_scene.c): the greatest level of
 * the scene's models. */
static uint32_t deep_constant(const vx_svo_scene* s) {
    uint32_t deep = 0, rebase;
    for (uint32_t i = 0; i < s->model_count; i++) {
        uint32_t level = vx__render_model_deep(&s->models[i], &rebase);
        if (level > deep) deep = level;
    }
    return deep;
}

static void paging_free(vx_gpu* g, paging* pg) {
    if (!pg) return;
    vx_compact_page_cache_destroy(pg->cache);
    vx_compact_paged_free(&pg->p);
    vx_free(&g->alloc, pg->dst);
    vx_free(&g->alloc, pg->owner);
    vx_free(&g->alloc, pg->slot);
    vx_free(&g->alloc, pg->last_used);
    vx_free(&g->alloc, pg->pending);
    vx_free(&g->alloc, pg->state);
    vx_free(&g->alloc, pg->evict_patch);
    vx_free(&g->alloc, pg->moved);
    vx_free(&g->alloc, pg->moved_bit);
    vx_free(&g->alloc, pg->moved_from);
    vx_free(&g->alloc, pg->victims);
    vx_free(&g->alloc, pg->busy);
    vx_free(&g->alloc, pg);
}

void vx_compact_gpu_destroy(vx_compact_gpu* cg) {
    if (!cg) return;
    vx__buffer* b[9] = {&cg->geom,   &cg->attr, &cg->models, &cg->palette,    &cg->pixels,
                        &cg->hits,   &cg->pstate, &cg->stage, &cg->pass_models};
    for (int i = 0; i < 9; i++) vx__buffer_destroy(cg->gpu, b[i]);
    for (int i = 0; i < VX_COMPACT_ATTR_PARTS - 1; i++) vx__buffer_destroy(cg->gpu, &cg->attr_hi[i]);
    paging_free(cg->gpu, cg->pg);
    vx_free(&cg->gpu->alloc, cg->cm);
    vx_free(&cg->gpu->alloc, cg->mat_used);
    for (uint32_t i = 0; cg->paths && i < cg->path_count; i++) vx_free(&cg->gpu->alloc, (void*)cg->paths[i].top);
    vx_free(&cg->gpu->alloc, cg->paths);
    vx_free(&cg->gpu->alloc, cg);
}

/* The geometry slots for vx__top_list: a node of level >= 3 (a slot whose
 * word 0 holds the descriptor in its low 16 bits) and its children's block
 * (word 1), checked against the slots there are */
typedef struct slot_words {
    const uint32_t* geom;
    uint32_t slots;
} slot_words;

static uint32_t slot_desc(const void* ctx, uint32_t word) { return ((const slot_words*)ctx)->geom[2ull * word] & 0xFFFFu; }

static bool slot_block(const void* ctx, uint32_t word, uint32_t desc, uint32_t k, uint32_t* blk) {
    (void)desc;
    const slot_words* sw = ctx;
    uint32_t b = sw->geom[2ull * word + 1];
    if (b >= sw->slots || k > sw->slots - b) return false;
    *blk = b;
    return true;
}

/* The models' listed tops (cg->paths) from slots [0, slots) of geom: the
 * primary rays' starts below the root (trace_compact.comp PATH_START), at
 * nodes of level >= 3 (the kernel's walk reloads a start node's slot as
 * the walk's pop does: a descriptor there, bricks have none), and, paged,
 * at the page level's parent or above (a push into a page is the walk's:
 * its request and use bits). A list that cannot be made is none (the rays
 * start at the root). */
static void path_lists(vx_compact_gpu* cg, const cmodel_gpu* cm, const vx_compact_model* models, uint32_t count,
                       const uint32_t* geom, uint32_t slots) {
    cg->paths = vx_calloc(&cg->gpu->alloc, count ? count : 1, sizeof *cg->paths);
    if (!cg->paths) return;
    cg->path_count = count;
    slot_words sw = {.geom = geom, .slots = slots};
    for (uint32_t i = 0; i < count; i++) {
        uint32_t min_level = cm[i].page_up > 3 ? cm[i].page_up : 3, n;
        cg->paths[i] = (vx__path_model){.box = cm[i].box, .rebase = cm[i].rebase, .min_level = min_level,
                                        .min_dq = START_MIN};
        if (models[i].root >= slots || models[i].depth <= min_level) continue;
        vx__top_src src = {.ctx = &sw,
                           .desc = slot_desc,
                           .block = slot_block,
                           .max_depth = models[i].depth - min_level,
                           .max_nodes = vx__top_cap(count)};
        cg->paths[i].top = vx__top_list(&cg->gpu->alloc, &src, models[i].root, &n);
    }
}

static vx_result upload(vx_gpu* g, vx__buffer* b, const void* data, uint64_t bytes, const char* label, vx_error* err) {
    vx_result r = vx__buffer_create(g, bytes ? bytes : 16, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, false, label, b, err);
    if (!r && bytes) r = vx__buffer_upload(g, b, data, bytes, err);
    return r;
}

/* Words [at, at + n) of the attribute words, which lie in parts of 2^shift
 * words (shift 0: one part). */
static vx_result upload_attr(vx_compact_gpu* cg, uint64_t at, const uint32_t* src, uint64_t n, vx_error* err) {
    while (n) {
        uint64_t part = cg->attr_shift ? at >> cg->attr_shift : 0, o = at - (part << cg->attr_shift);
        uint64_t k = cg->attr_shift ? (1ull << cg->attr_shift) - o : n;
        if (k > n) k = n;
        vx__buffer* b = part ? &cg->attr_hi[part - 1] : &cg->attr;
        vx_result r = vx__buffer_upload_at(cg->gpu, b, o * 4, src, k * 4, err);
        if (r) return r;
        at += k, src += k, n -= k;
    }
    return VX_OK;
}

/* The attributes in per-model regions (vx_compact_desc.attr_regions,
 * consecutive in model order) gathered into uploads of up to 16 Mi words:
 * one upload (a staging buffer and a submission) per model took thousands
 * of them for a 65536^3 scene of 5,000 models. */
static vx_result upload_regions(vx_compact_gpu* cg, const vx_compact_scene* c, const vx_allocator* a, vx_error* err) {
    const uint64_t cap = (uint64_t)1 << 24;
    uint64_t first = 0, n = 0;
    uint32_t* buf = NULL;
    vx_result r = VX_OK;
    for (uint32_t i = 0; !r && i <= c->model_count; i++) {
        const uint32_t* w = i < c->model_count ? c->attr_region[i] : NULL;
        uint64_t k = w ? c->models[i].attr_words : 0, at = w ? c->models[i].attr_base : 0;
        if (n && (i == c->model_count || (w && (at != first + n || n + k > cap)))) { /* flush */
            r = upload_attr(cg, first, buf, n, err);
            n = 0;
        }
        if (r || !w || !k) continue;
        if (k > cap) { /* a region larger than the gathering: as it is */
            r = upload_attr(cg, at, w, k, err);
            continue;
        }
        if (!buf && !(buf = vx_alloc(a, (size_t)cap * 4)))
            r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for the attributes' upload");
        if (r) continue;
        if (!n) first = at;
        memcpy(buf + n, w, (size_t)k * 4);
        n += k;
    }
    vx_free(a, buf);
    return r;
}

/* The attribute words' parts for a storage buffer range of `range` bytes:
 * one where they fit, else parts of the largest power of two of words that
 * fits (trace_compact.comp ATTR_SHIFT). */
static vx_result attr_parts(uint64_t words, uint64_t range, uint32_t* shift, uint32_t* parts, vx_error* err) {
    *shift = 0, *parts = 1;
    if (words * 4 <= range) return VX_OK;
    uint32_t sh = 2;
    while (sh < 31 && (4ull << (sh + 1)) <= range) sh++;
    uint64_t n = (words + (1ull << sh) - 1) >> sh;
    if (n > VX_COMPACT_ATTR_PARTS || (4ull << sh) > range)
        return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET,
                       "compact layout: %llu attribute bytes need %llu storage buffers of the device's %llu-byte range "
                       "(at most %d)",
                       (unsigned long long)(words * 4), (unsigned long long)n, (unsigned long long)range,
                       VX_COMPACT_ATTR_PARTS);
    *shift = sh, *parts = (uint32_t)n;
    return VX_OK;
}

/* The start table of a coloured model (CModel.tab_word, tab_k): the cell's
 * attribute index is a descent from the root summing the cells before each
 * level's child (compact_attr.glsl cell_index); the table holds, for every
 * cube of level K (2^K cells a side) of the model, the slot of its node and
 * the cells before it, so that the descent starts at level K: two loads
 * instead of depth - K levels (the descent was most of the colour's cost:
 * docs/PERFORMANCE.md issue 18, eighth step). Dense, 2 words a cube,
 * (2^(depth - K))^3 cubes, K the lowest level whose table stays under the
 * scene's budget. The whole layout only (the paged one has none).
 * Entries: (slot, cells before); (TAB_FULL, index of the cube's first
 * cell) for a cube inside a full leaf cube; (TAB_FULL, 0) where empty
 * (never read: a hit's cube has cells); (TAB_UNIFORM | the palette index
 * of a palette model, the colour) for a cube whose cells all hold one
 * value (tab_uniform): its colour needs neither the descent nor the
 * decode, nor the palette. */
#define TAB_FULL 0xFFFFFFFFu
#define TAB_UNIFORM 0xFFFFFE00u /* | the palette index (palette models; slots never come near) */
#define TAB_EMPTY 0xFFFFFFFDu /* while the table is filled only */

typedef struct tab_fill {
    const vx_compact_scene* c;
    uint32_t* t; /* 2 words an entry */
    uint32_t K, D; /* level, log2 of the entries a side */
} tab_fill;

static void tab_set(const tab_fill* f, uint32_t x, uint32_t y, uint32_t z, uint32_t w0, uint32_t w1) {
    size_t e = ((size_t)(x >> f->K) | ((size_t)(y >> f->K) << f->D) | ((size_t)(z >> f->K) << (2 * f->D)));
    f->t[2 * e] = w0, f->t[2 * e + 1] = w1;
}

/* Node n of level L > K at cell (x, y, z), base cells before it. */
static void tab_node(const tab_fill* f, uint32_t n, uint32_t L, uint64_t base, uint32_t x, uint32_t y, uint32_t z) {
    const uint32_t* sl = f->c->geom + 2 * (size_t)n;
    uint32_t valid = (sl[0] >> 8) & 0xFFu, leaf = sl[0] & 0xFFu, inner = valid & ~leaf, s = L - 1;
    for (uint32_t o = 0; o < 8; o++) {
        if (!((valid >> o) & 1u)) continue;
        uint32_t below = (1u << o) - 1u, k = __builtin_popcount(inner & below);
        uint32_t cx = x + ((o & 1u) << s), cy = y + (((o >> 1) & 1u) << s), cz = z + (((o >> 2) & 1u) << s);
        uint64_t b = base + ((uint64_t)__builtin_popcount(leaf & below) << (3 * s)) +
                     vx__compact_inner_before(f->c, L, sl[1], k);
        if ((leaf >> o) & 1u) {
            /* a full cube of level s >= K: each of its level-K cubes from its first cell's index */
            uint32_t side = 1u << s, step = 1u << f->K;
            for (uint32_t qz = 0; qz < side; qz += step)
                for (uint32_t qy = 0; qy < side; qy += step)
                    for (uint32_t qx = 0; qx < side; qx += step)
                        tab_set(f, cx + qx, cy + qy, cz + qz, TAB_FULL, (uint32_t)(b + vx_svo_morton(qx, qy, qz)));
        } else if (s == f->K) {
            tab_set(f, cx, cy, cz, vx__compact_child(f->c, L, sl[1], k), (uint32_t)b);
        } else {
            tab_node(f, vx__compact_child(f->c, L, sl[1], k), s, b, cx, cy, cz);
        }
    }
}

/* Whether the attribute indices [b, e) of model mi all hold one stored
 * value, *v: every block they touch of one value (code 0, the encoder's
 * form for a block of one distinct value) and the same one. Blocks of
 * other codes count as not uniform (a cube then keeps its descent). */
static bool attr_uniform(const vx_compact_scene* c, uint32_t mi, uint64_t b, uint64_t e, uint32_t* v) {
    const vx_compact_model* m = &c->models[mi];
    const uint32_t* w = c->attr ? c->attr + m->attr_base : c->attr_region ? c->attr_region[mi] : NULL;
    if (!w || !m->block || e > m->voxels || b >= e) return false;
    uint32_t mask = m->attr_kind == VX_COMPACT_ATTR_PALETTE ? 0xFFu : 0xFFFFFFFFu;
    for (uint64_t blk = b / m->block; blk <= (e - 1) / m->block; blk++) {
        uint32_t g = w[blk / VX_COMPACT_GROUP];
        uint32_t h = w[(g & 0x7FFFFFFFu) + (g >> 31 ? 0 : blk % VX_COMPACT_GROUP)];
        if ((h & 31u) != 0) return false;
        uint32_t x = w[h >> 5] & mask;
        if (blk == b / m->block) *v = x;
        else if (x != *v) return false;
    }
    return true;
}

/* The entries of model mi's table (level K, D bits a side) whose cells
 * hold one value: counted (*filled: the entries that are not empty), and
 * with mark made TAB_UNIFORM. */
static uint64_t tab_uniform(const vx_compact_scene* c, uint32_t mi, uint32_t* t, uint32_t K, uint32_t D, bool mark,
                            uint64_t* filled) {
    uint64_t marked = 0;
    size_t n = (size_t)1 << (3 * D);
    for (size_t e = 0; e < n; e++) {
        uint32_t w0 = t[2 * e], v = 0;
        if (w0 == TAB_EMPTY) continue;
        ++*filled;
        uint64_t cells = 1ull << (3 * K);
        if (w0 != TAB_FULL) {
            const uint32_t* sl = c->geom + 2 * (size_t)w0;
            uint32_t valid = (sl[0] >> 8) & 0xFFu, leaf = sl[0] & 0xFFu;
            cells = ((uint64_t)__builtin_popcount(leaf) << (3 * (K - 1))) +
                    vx__compact_inner_before(c, K, sl[1], (uint32_t)__builtin_popcount(valid & ~leaf));
        }
        if (attr_uniform(c, mi, t[2 * e + 1], t[2 * e + 1] + cells, &v)) {
            marked++;
            bool pal = c->models[mi].attr_kind == VX_COMPACT_ATTR_PALETTE;
            if (mark) t[2 * e] = TAB_UNIFORM | (pal ? v : 0u), t[2 * e + 1] = pal ? c->palette[v] : v;
        }
    }
    return marked;
}

/* The table's level for a model of depth D within an entry budget (0: none). */
static uint32_t tab_level(uint32_t depth, uint64_t budget) {
    for (uint32_t K = 3; K < depth && K <= 10; K++)
        if (3 * (depth - K) <= 30 && (1ull << (3 * (depth - K))) <= budget) return K;
    return 0;
}

/* The level-3 records and the colour from the walk's path (below) in the
 * scenes whose kernel is DEEP 1 (models of 9 and 10 levels): on the H200 the
 * DEEP 0 kernels lost 1-3% of their albedo rays/s with the path's capture
 * (eph_monu1, eph_menger), and the DEEP 2 kernels (rebased) have none
 * (docs/PERFORMANCE.md issue 18, branch ck11). */
static bool records_on(uint32_t deep) { return deep == 1; }
/* The start tables' smallest budget (entries, shared by the coloured models):
 * with the records, 2^18 entries (2 MB; the helmet at 512: a table of level
 * 3, whose path loads the entry and the record only, no level-4 slots),
 * else 4096 (docs/PERFORMANCE.md issue 18, branch ck11) */
#define TAB_FLOOR(records) ((records) ? (1u << 18) : 4096u)

/* ---- material ids -------------------------------------------------------------------
 * The compact records hold a palette index or a colour; a model that names its
 * materials through a material channel (VX_ATTR_MATERIAL) needs its records'
 * ids beside them where they matter (vx__scene_material_ids_matter): each
 * such model's ids, one per cell in the same Morton order (so the attribute
 * index the walk sums finds both), coded as its colours are
 * (vx__compact_encode, RGBA width, the model's block: a region of one
 * material costs a header word per VX_COMPACT_GROUP blocks), placed after the
 * start tables in the attribute words; the passes' CModel of such a model
 * gets flag 8 and the region's word in pool_base (the whole layout has no
 * pool: compact_attr.glsl ca_table_index). The passes' Hit.attr is then the
 * material id of every record (a palette model's palette index, else 0,
 * where a model has no channel: vx_svo_attr_material's rule), and their
 * tables are per material id (vx__compact_gpu_materials). */
#define CM_MATERIAL 8u /* CModel flag: material ids at pool_base (the passes' records) */

typedef struct mat_cells {
    const vx_svo_model* m;
    uint32_t* vals;
    uint32_t n, cap;
} mat_cells;

static bool mat_cell(void* user, uint32_t x, uint32_t y, uint32_t z, uint32_t attr) {
    (void)x, (void)y, (void)z;
    mat_cells* q = user;
    if (q->n >= q->cap || attr >= q->m->attr_count) return false;
    q->vals[q->n++] = vx_svo_attr_material(q->m, attr);
    return true;
}

/* Whether model sm's arrays are at hand (a scene from a model reader is its graph without them). */
static bool model_arrays(const vx_svo_model* sm) {
    return sm->root == VX_SVO_ROOT_EMPTY || (sm->attr_count && (sm->root == VX_SVO_ROOT_LEAF || sm->nodes));
}

/* Which models get material ids (want[i]) and the ids in use (cg->mat_used,
 * mat_max), or cg->mat_missing where some model with the channel has no
 * arrays (then none). */
static vx_result material_plan(vx_compact_gpu* cg, const vx_svo_scene* s, const vx_compact_scene* c,
                               const cmodel_gpu* cm, bool* want, vx_error* err) {
    for (uint32_t i = 0; i < s->model_count; i++) {
        const vx_svo_model* sm = &s->models[i];
        want[i] = (sm->attrs & VX_ATTR_MATERIAL) && (cm[i].flags & 1u) && c->models[i].voxels;
        if (want[i] && (!model_arrays(sm) || !sm->material)) cg->mat_missing = true;
    }
    if (cg->mat_missing) {
        memset(want, 0, s->model_count * sizeof *want);
        return VX_OK;
    }
    if (!(cg->mat_used = vx_calloc(&cg->gpu->alloc, 65536 / 32, sizeof *cg->mat_used)))
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory");
    /* every record's id, as vx__scene_attr_material lists them for the plain layout */
    for (uint32_t i = 0; i < s->model_count; i++) {
        const vx_svo_model* sm = &s->models[i];
        if (!model_arrays(sm)) { /* no channel: its palette indices as the layout's build found them */
            for (uint32_t k = 0; k < 8; k++) cg->mat_used[k] |= c->palette_used[k];
            continue;
        }
        for (uint32_t a = 0; a < sm->attr_count; a++) {
            uint32_t id = vx_svo_attr_material(sm, a) & 0xFFFFu;
            cg->mat_used[id >> 5] |= 1u << (id & 31);
        }
    }
    cg->mat_used[0] |= 1u; /* id 0: what a record without a palette index or channel has */
    for (uint32_t id = 0; id < 65536; id++)
        if (cg->mat_used[id >> 5] & (1u << (id & 31))) cg->mat_max = id;
    return VX_OK;
}

/* The material id regions of the models want[] names, concatenated into
 * *words (*nwords of them) from attribute word `first`; base[i] each one's
 * first word. */
static vx_result material_regions(const vx_svo_scene* s, const vx_compact_scene* c, const bool* want, uint64_t first,
                                  const vx_allocator* a, uint32_t* base, uint32_t** words, uint64_t* nwords,
                                  vx_error* err) {
    *words = NULL, *nwords = 0;
    size_t cap = 0;
    vx_result r = VX_OK;
    for (uint32_t i = 0; i < s->model_count && !r; i++) {
        if (!want[i]) continue;
        const vx_compact_model* m = &c->models[i];
        mat_cells q = {.m = &s->models[i], .cap = m->voxels};
        uint32_t* w = NULL, nw = 0;
        if (!(q.vals = vx_alloc(a, (size_t)m->voxels * 4))) {
            r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %u material ids", m->voxels);
            break;
        }
        r = vx_svo_decode_model(q.m, mat_cell, &q, err);
        if (!r && q.n != m->voxels)
            r = vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "model %u: %u material ids for %u cells", i, q.n,
                        m->voxels);
        if (!r) r = vx__compact_encode(a, m->block, VX_COMPACT_ATTR_RGBA, q.vals, q.n, NULL, &w, &nw, err);
        vx_free(a, q.vals);
        if (!r && first + *nwords + nw > 0xFFFFFFFFull)
            r = vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "compact layout: more than 2^32 attribute words with the material ids");
        if (!r && !vx_grow(a, (void**)words, &cap, (size_t)(*nwords + nw), 4))
            r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %u material id words", nw);
        if (!r) {
            base[i] = (uint32_t)(first + *nwords);
            memcpy(*words + *nwords, w, (size_t)nw * 4);
            *nwords += nw;
        }
        vx_free(a, w);
    }
    if (r) {
        vx_free(a, *words);
        *words = NULL, *nwords = 0;
    }
    return r;
}

vx_result vx__compact_gpu_materials(const vx_compact_gpu* cg, const vx_allocator* alloc, uint16_t** out, size_t* n,
                                    bool* missing, vx_error* err) {
    *out = NULL, *n = 0;
    if (missing) *missing = cg && cg->mat_missing;
    if (!cg || !cg->mat_used) return VX_OK;
    size_t k = cg->mat_max < 256 ? 256 : (size_t)cg->mat_max + 1;
    uint16_t* p = vx_calloc(alloc, k, sizeof *p);
    if (!p) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory");
    for (size_t i = 0; i < k; i++) p[i] = cg->mat_used[i >> 5] & (1u << (i & 31)) ? (uint16_t)i : 0;
    *out = p, *n = k;
    return VX_OK;
}

uint64_t vx__compact_gpu_material_bytes(const vx_compact_gpu* cg) { return cg ? cg->mat_bytes : 0; }

vx_result vx_compact_gpu_create(vx_render_scene* rs, const vx_svo_scene* s, const vx_compact_scene* c,
                                vx_compact_gpu** out, vx_error* err) {
    if (!rs || !s || !c || !out) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    if (c->model_count != s->model_count)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "the compact scene has %u models, the scene %u",
                       c->model_count, s->model_count);
    uint32_t deep = deep_constant(s);
    bool records = records_on(deep);
    vx_gpu* g = vx__render_scene_gpu(rs);
    vx_compact_gpu* cg = vx_calloc(&g->alloc, 1, sizeof *cg);
    if (!cg) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory");
    cg->rs = rs, cg->gpu = g, cg->deep = deep, cg->dict = c->brick_dict;
    vx_svo_scene_world_bounds(s, cg->lo, cg->hi);
    size_t mcount = s->model_count ? s->model_count : 1;
    cmodel_gpu* cm = vx_calloc(&g->alloc, mcount, sizeof *cm);
    if (!cm) {
        vx_free(&g->alloc, cg);
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory");
    }
    for (uint32_t i = 0; i < s->model_count; i++) {
        const vx_compact_model* m = &c->models[i];
        const vx_svo_model* sm = &s->models[i];
        uint32_t flags = m->attr_kind != VX_COMPACT_ATTR_NONE ? 1u : 0u;
        uint32_t rebase;
        if (vx__render_model_deep(sm, &rebase)) flags |= 2u;
        cm[i] = (cmodel_gpu){.root = m->root, .depth = m->depth, .flags = flags, .box = vx__render_model_box(sm),
                             .attr_base = m->attr_base, .block_log2 = m->block ? (uint32_t)__builtin_ctz(m->block) : 0,
                             .kind = m->attr_kind, .rank_base = 2 * c->slot_count - c->brick_count,
                             .rebase = rebase};
    }
    /* the models' material ids where the scene needs them (above) */
    bool* want = vx_calloc(&g->alloc, mcount, sizeof *want);
    uint32_t* mbase = vx_calloc(&g->alloc, mcount, sizeof *mbase);
    vx_result r = want && mbase ? VX_OK : vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory");
    if (!r && vx__scene_material_ids_matter(s)) r = material_plan(cg, s, c, cm, want, err);
    /* the start tables after the attribute words: a scene budget of one
     * entry (2 words) per 16 words of the layout, at least TAB_FLOOR (32 KB,
     * 2 MB with the records), shared by the coloured models (the table of
     * the next level down is 8 times larger: at most an eighth more bytes
     * beyond the floor; docs/PERFORMANCE.md issue 18, eighth step) */
    uint64_t ncol = 0, tab_words = 0;
    for (uint32_t i = 0; i < s->model_count; i++) ncol += (cm[i].flags & 1u) && c->models[i].root < VX_SVO_ROOT_LEAF;
    uint64_t budget = ((uint64_t)c->geom_words + c->attr_words) / 16;
    if (budget < TAB_FLOOR(records)) budget = TAB_FLOOR(records);
    if (ncol) budget /= ncol;
    for (uint32_t i = 0; i < s->model_count; i++) {
        if (!(cm[i].flags & 1u) || c->models[i].root >= VX_SVO_ROOT_LEAF) continue;
        uint32_t K = tab_level(c->models[i].depth, budget);
        if (!K || c->attr_words + tab_words + (2ull << (3 * (c->models[i].depth - K))) > 0xFFFFFFFFull) continue;
        cm[i].tab_k = K, cm[i].tab_word = (uint32_t)(c->attr_words + tab_words);
        tab_words += 2ull << (3 * (c->models[i].depth - K));
    }
    /* the tables after the attribute words in one buffer (the passes' binding 2),
     * uploaded apart so that the host holds no second copy of the words */
    uint32_t* tw = !r && tab_words ? vx_alloc(&g->alloc, (size_t)tab_words * 4) : NULL;
    if (!r && !tw && tab_words) r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory");
    if (!r && tw) {
        for (size_t w = 0; w < tab_words; w++) tw[w] = w % 2 ? 0u : TAB_EMPTY;
        for (uint32_t i = 0; i < s->model_count; i++)
            if (cm[i].tab_k) {
                tab_fill f = {.c = c, .t = tw + (cm[i].tab_word - c->attr_words), .K = cm[i].tab_k,
                              .D = c->models[i].depth - cm[i].tab_k};
                tab_node(&f, c->models[i].root, c->models[i].depth, 0, 0, 0, 0);
            }
        /* The uniform cubes where at least a quarter of the scene's filled
         * entries are: each kernel that reads the tables then tests for them
         * (trace_compact.comp's UNIFORM constant), which cost 0.5-1.5% of the
         * H200's albedo rays/s on the helmet and the terrain (2-8% of their
         * entries uniform), and gave 7-13% on eph_menger (all of them;
         * docs/PERFORMANCE.md issue 18, twelfth step) */
        /* (not in a model with material ids: a uniform entry gives the colour
         * instead of the cell's attribute index, which its id needs) */
        uint64_t filled = 0, marked = 0;
        for (uint32_t i = 0; i < s->model_count; i++)
            if (cm[i].tab_k && !want[i])
                marked += tab_uniform(c, i, tw + (cm[i].tab_word - c->attr_words), cm[i].tab_k,
                                      c->models[i].depth - cm[i].tab_k, false, &filled);
        bool mark = marked > 0 && 4 * marked >= filled;
        for (uint32_t i = 0; i < s->model_count && mark; i++)
            if (cm[i].tab_k && !want[i])
                cg->uniform_entries += tab_uniform(c, i, tw + (cm[i].tab_word - c->attr_words), cm[i].tab_k,
                                                   c->models[i].depth - cm[i].tab_k, true, &filled);
        for (size_t w = 0; w < tab_words; w += 2)
            if (tw[w] == TAB_EMPTY) tw[w] = TAB_FULL;
    }
    /* A model whose cells all hold one value (every attribute block of one
     * value, the same one; eph_menger): flag 4 and the colour in the record,
     * so that its hits need no cell, no table entry and no decode, 0.89 ->
     * 0.99 of trace.comp's albedo rays/s on eph_menger's close-up on the H200
     * (docs/PERFORMANCE.md issue 18, thirteenth step). The tables stay (the
     * passes' kernels read them). */
    for (uint32_t i = 0; i < s->model_count; i++) {
        uint32_t v = 0;
        if (!(cm[i].flags & 1u) || c->models[i].root >= VX_SVO_ROOT_LEAF || !attr_uniform(c, i, 0, c->models[i].voxels, &v))
            continue;
        cm[i].flags |= 4u;
        cm[i].value = c->models[i].attr_kind == VX_COMPACT_ATTR_PALETTE ? c->palette[v] : v;
        cg->uniform_models++;
    }
    uint32_t* mw = NULL;
    uint64_t mat_words = 0;
    if (!r && cg->mat_used)
        r = material_regions(s, c, want, (uint64_t)c->attr_words + tab_words, &g->alloc, mbase, &mw, &mat_words, err);
    uint64_t range = vx__render_scene_buffer_range(rs), aw = (uint64_t)c->attr_words + tab_words + mat_words;
    if (!r && (uint64_t)c->geom_words * 4 > range)
        r = vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET,
                    "compact layout: %llu geometry bytes exceed the device's storage buffer range (%llu bytes)",
                    (unsigned long long)c->geom_words * 4, (unsigned long long)range);
    if (!r) r = attr_parts(aw, range, &cg->attr_shift, &cg->attr_parts, err);
    /* The level-3 records after the geometry words (vx__compact_level3_records):
     * with the hit's level-3 and level-4 ancestors from the walk, a coloured
     * model's hit inside a brick finds its attribute index in loads that do
     * not wait on each other (compact_attr.glsl cell_index_path) instead of
     * the descent's chain below the start table; 8 bytes a level-3 slot
     * (docs/PERFORMANCE.md issue 18, branch ck11). Models with a start
     * table of level 3 or more and colours of more than one value, in scenes
     * whose kernel is DEEP 1 (records_on). */
    uint32_t* rec = NULL, rec_first = 0, rec_count = 0;
    uint64_t gw = ((uint64_t)c->geom_words + 1) & ~1ull;
    if (!r && records) r = vx__compact_level3_records(c, &g->alloc, &rec, &rec_first, &rec_count, err);
    if (!r && rec_count && (gw + 2ull * rec_count) * 4 > range) rec_count = 0; /* no room: the descent */
    for (uint32_t i = 0; i < s->model_count && rec_count; i++)
        if ((cm[i].flags & 5u) == 1u && cm[i].tab_k >= 3 && c->models[i].depth >= 4) {
            cm[i].rec3 = (uint32_t)(gw / 2 - rec_first);
            cg->records = true;
        }
    uint32_t* geo = !r && rec_count ? vx_alloc(&g->alloc, (size_t)(gw + 2ull * rec_count) * 4) : NULL;
    if (!r && rec_count && !geo) r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory");
    if (geo) {
        memcpy(geo, c->geom, (size_t)c->geom_words * 4);
        if (gw > c->geom_words) geo[c->geom_words] = 0;
        memcpy(geo + gw, rec, (size_t)rec_count * 8);
    }
    vx_free(&g->alloc, rec);
    cg->record_bytes = geo ? 8ull * rec_count : 0;
    if (!r) r = upload(g, &cg->geom, geo ? geo : c->geom, geo ? (gw + 2ull * rec_count) * 4 : (uint64_t)c->geom_words * 4,
                       "compact geometry", err);
    vx_free(&g->alloc, geo);
    for (uint32_t k = 0; !r && k < cg->attr_parts; k++) {
        uint64_t first = (uint64_t)k << cg->attr_shift, n = cg->attr_shift ? 1ull << cg->attr_shift : aw;
        if (n > aw - first) n = aw - first;
        r = vx__buffer_create(g, n ? n * 4 : 16, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, false, "compact attributes",
                              k ? &cg->attr_hi[k - 1] : &cg->attr, err);
    }
    if (!r && c->attr) r = upload_attr(cg, 0, c->attr, c->attr_words, err);
    if (!r && c->attr_region) r = upload_regions(cg, c, &g->alloc, err);
    if (!r) r = upload_attr(cg, c->attr_words, tw, tab_words, err);
    if (!r && mat_words) r = upload_attr(cg, (uint64_t)c->attr_words + tab_words, mw, mat_words, err);
    vx_free(&g->alloc, tw);
    vx_free(&g->alloc, mw);
    if (!r) r = upload(g, &cg->models, cm, mcount * sizeof *cm, "compact models", err);
    if (!r) r = upload(g, &cg->palette, c->palette, sizeof c->palette, "compact palette", err);
    /* the passes' binding 3 (trace_common.glsl CModels): the palette first, so that
     * the shader finds it without the model count */
    uint8_t* pm = r ? NULL : vx_alloc(&g->alloc, sizeof c->palette + mcount * sizeof *cm);
    if (!r && !pm) r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory");
    if (!r) {
        memcpy(pm, c->palette, sizeof c->palette);
        memcpy(pm + sizeof c->palette, cm, mcount * sizeof *cm);
        for (uint32_t i = 0; i < s->model_count; i++)
            if (want[i]) { /* (trace_compact.comp's records keep pool_base 0: it reads no material) */
                cmodel_gpu* p = (cmodel_gpu*)(pm + sizeof c->palette) + i;
                p->flags |= CM_MATERIAL, p->pool_base = mbase[i];
            }
        r = upload(g, &cg->pass_models, pm, sizeof c->palette + mcount * sizeof *cm, "compact pass models", err);
    }
    vx_free(&g->alloc, pm);
    vx_free(&g->alloc, want);
    vx_free(&g->alloc, mbase);
    cg->cm = cm, cg->cm_count = (uint32_t)mcount;
    cg->geom_words = c->geom_words, cg->slot_count = c->slot_count, cg->brick_count = c->brick_count;
    if (!r) path_lists(cg, cm, c->models, s->model_count, c->geom, c->slot_count);
    if (r) {
        vx_compact_gpu_destroy(cg);
        return r;
    }
    cg->table_bytes = tab_words * 4;
    cg->mat_bytes = mat_words * 4;
    cg->bytes = (uint64_t)c->geom_words * 4 + cg->record_bytes + ((uint64_t)c->attr_words + tab_words) * 4 + mcount * sizeof(cmodel_gpu) +
                2 * sizeof c->palette + mcount * sizeof(cmodel_gpu) + cg->mat_bytes;
    *out = cg;
    return VX_OK;
}

uint64_t vx_compact_gpu_bytes(const vx_compact_gpu* cg) { return cg ? cg->bytes : 0; }

void vx__compact_gpu_start_min(vx_compact_gpu* cg, uint32_t pushes) {
    if (cg) cg->start_min = pushes;
}

uint64_t vx__compact_gpu_table_bytes(const vx_compact_gpu* cg) { return cg ? cg->table_bytes : 0; }
uint64_t vx__compact_gpu_record_bytes(const vx_compact_gpu* cg) { return cg ? cg->record_bytes : 0; }
uint64_t vx__compact_gpu_uniform_entries(const vx_compact_gpu* cg) { return cg ? cg->uniform_entries : 0; }

uint32_t vx__compact_gpu_attr_parts(const vx_compact_gpu* cg) { return cg ? cg->attr_parts : 0; }

vx_result vx__compact_gpu_geometry(vx_compact_gpu* cg, vx_compact_scene* out, vx_error* err) {
    if (!cg || !out) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    memset(out, 0, sizeof *out);
    if (cg->pg) return vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET, "the paged layout's geometry is not all resident");
    out->alloc = cg->gpu->alloc;
    out->model_count = cg->cm_count;
    out->models = vx_calloc(&out->alloc, cg->cm_count ? cg->cm_count : 1, sizeof *out->models);
    out->geom = vx_alloc(&out->alloc, (size_t)(cg->geom_words ? cg->geom_words : 1) * 4);
    vx_result r = out->models && out->geom ? VX_OK : vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory");
    if (!r && cg->geom_words) r = vx__buffer_download(cg->gpu, &cg->geom, out->geom, (VkDeviceSize)cg->geom_words * 4, err);
    if (r) {
        vx_compact_free(out);
        return r;
    }
    for (uint32_t i = 0; i < cg->cm_count; i++) out->models[i].root = cg->cm[i].root, out->models[i].depth = cg->cm[i].depth;
    out->geom_words = cg->geom_words, out->slot_count = cg->slot_count, out->brick_count = cg->brick_count;
    out->brick_dict = cg->dict != 0;
    return VX_OK;
}

bool vx__compact_gpu_bind(vx_compact_gpu* cg, vx__buffer* bufs[7]) {
    if (!cg || cg->pg || cg->attr_parts > 1) return false;
    bufs[1] = &cg->geom, bufs[2] = &cg->attr, bufs[3] = &cg->pass_models;
    return true;
}

/* ---- pages ------------------------------------------------------------------------- */

static uint32_t page_units(const paging* pg, uint32_t page) {
    uint64_t slots = (pg->p.pages[page].words + 1) / 2;
    return (uint32_t)((slots + pg->unit - 1) / pg->unit);
}

/* Marks units [u0, u0 + n) owned by page + 1 (page UINT32_MAX: free), in
 * owner and in the busy bits. */
static void units_set(paging* pg, uint32_t u0, uint32_t n, uint32_t page) {
    for (uint32_t u = u0; u < u0 + n; u++) {
        pg->owner[u] = page + 1;
        if (page == UINT32_MAX) pg->busy[u >> 6] &= ~(1ull << (u & 63));
        else pg->busy[u >> 6] |= 1ull << (u & 63);
    }
}

/* Next-fit over the pool's units: the first run of n free units from the
 * cursor on (so a page loaded again after its eviction lands elsewhere while
 * there is room); UINT32_MAX when none. The busy bits are read a word at a
 * time: a unit at a time, a service that loaded hundreds of pages into a
 * pool of 10^5-10^6 units scanned it once a page (0.2-0.6 s of a frame's
 * service on the H200, docs/PERFORMANCE.md "Paging from files"). */
static uint32_t pool_find(const paging* pg, uint32_t n) {
    for (uint32_t pass = 0; pass < 2; pass++) {
        uint32_t lo = pass ? 0 : pg->cursor, hi = pass ? pg->cursor : pg->units;
        uint32_t run = 0; /* free units just before u */
        for (uint32_t u = lo; u < hi;) {
            uint32_t avail = 64 - (u & 63);
            if (avail > hi - u) avail = hi - u;
            uint64_t w = pg->busy[u >> 6] >> (u & 63);
            if (avail < 64) w &= (1ull << avail) - 1;
            uint32_t z = w ? (uint32_t)__builtin_ctzll(w) : avail; /* free units from u on, in this word */
            if (run + z >= n) return u - run;
            if (!w) {
                run += avail, u += avail;
                continue;
            }
            uint64_t b = ~(w >> z); /* the busy run from u + z: its length is b's trailing zeros */
            run = 0;
            u += z + (b ? (uint32_t)__builtin_ctzll(b) : 64 - z);
        }
        if (pass == 0 && pg->cursor == 0) break;
    }
    return UINT32_MAX;
}

/* Slides the resident pages to the pool's start, in their order (free space
 * in holes smaller than a request is otherwise lost: pages differ in size).
 * A moved page is loaded again from the host copy at its new place; pages
 * loaded in this service (last_used == frame) are uploaded after it anyway. */
static void pool_compact(paging* pg, uint64_t frame) {
    uint32_t at = 0;
    for (uint32_t u = 0; u < pg->units;) {
        if (!pg->owner[u]) {
            u++;
            continue;
        }
        uint32_t page = pg->owner[u] - 1, n = page_units(pg, page);
        if (u != at) {
            uint32_t from = at + n > u ? at + n : u;
            units_set(pg, at, n, page);
            units_set(pg, from, u + n - from, UINT32_MAX);
            bool listed = pg->last_used[page] == frame || ((pg->moved_bit[page >> 6] >> (page & 63)) & 1u);
            if (!listed) { /* where its words are on the GPU until the service's upload */
                pg->moved[pg->nmoved++] = page;
                pg->moved_bit[page >> 6] |= 1ull << (page & 63);
                pg->moved_from[page] = pg->slot[page];
            }
            pg->slot[page] = (int64_t)pg->words_base / 2 + (int64_t)at * pg->unit;
        }
        at += n;
        u += n;
    }
    pg->cursor = at < pg->units ? at : 0;
}

static void page_drop(paging* pg, uint32_t page) {
    uint32_t u0 = (uint32_t)((pg->slot[page] - pg->words_base / 2) / pg->unit), n = page_units(pg, page);
    units_set(pg, u0, n, UINT32_MAX);
    pg->free_units += n;
    pg->slot[page] = -1;
    pg->st.resident--;
    pg->st.used_bytes -= 8ull * n * pg->unit;
    pg->evict_patch[pg->nevict++] = page;
}

int64_t vx_compact_gpu_page_slot(const vx_compact_gpu* cg, uint32_t page) {
    if (!cg || !cg->pg || page >= cg->pg->p.page_count) return -1;
    return cg->pg->slot[page];
}

vx_result vx_compact_gpu_page_evict(vx_compact_gpu* cg, uint32_t page, vx_error* err) {
    if (!cg || !cg->pg || page >= cg->pg->p.page_count)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "no page %u", page);
    if (cg->pg->slot[page] >= 0) page_drop(cg->pg, page);
    return VX_OK;
}

void vx_compact_gpu_page_stats(const vx_compact_gpu* cg, vx_compact_page_stats* out) {
    if (!out) return;
    memset(out, 0, sizeof *out);
    if (!cg || !cg->pg) return;
    *out = cg->pg->st;
    if (cg->pg->cache) {
        vx_compact_cache_stats cs;
        vx_compact_page_cache_stats(cg->pg->cache, &cs);
        out->from_file = true;
        out->host_budget = cs.budget, out->host_bytes = cs.bytes, out->host_peak_bytes = cs.peak_bytes;
        out->host_hits = cs.hits, out->file_pages = cs.file_pages, out->file_models = cs.models;
        out->host_evictions = cs.evictions, out->file_prefetched = cs.prefetched;
    }
}

const vx_compact_paged* vx_compact_gpu_paged(const vx_compact_gpu* cg) { return cg && cg->pg ? &cg->pg->p : NULL; }

/* Relocates page p's image w to pool slot P (the walk reads absolute
 * slots: word 1 of its header and of its nodes of levels >= 3 with
 * children), or undoes that (undo). */
static void page_relocate(uint32_t* w, const vx_compact_page* p, uint32_t P, bool undo) {
    uint32_t a = 2 * P, b = P, c = P + 2;
    if (undo) a = 0u - a, b = 0u - b, c = 0u - c;
    w[0] += a, w[1] += b;
    for (uint32_t j = 0; j < p->n3; j++) {
        uint32_t d = w[4 + 2 * j];
        if (((d >> 8) & ~d) & 0xFFu) w[4 + 2 * j + 1] += c;
    }
}

/* The images of the file source's pages that the service moved (pages[0 ..
 * n), each into dst[i]): read back from where they are in the pool (one
 * download of the span that holds them) and their relocation undone. From
 * the host they came from the cache or, evicted there, were cut from the
 * file again: with a host cache of 6 MB a frame of 511 loads cut 1,663
 * pages on the H200 (docs/PERFORMANCE.md "Paging from files"). */
static vx_result moved_from_pool(vx_compact_gpu* cg, const uint32_t* pages, uint32_t* const* dst, uint32_t n, vx_error* err) {
    paging* pg = cg->pg;
    uint64_t lo = UINT64_MAX, hi = 0;
    for (uint32_t i = 0; i < n; i++) {
        uint64_t w0 = 2 * (uint64_t)pg->moved_from[pages[i]], w1 = w0 + pg->p.pages[pages[i]].words;
        if (w0 < lo) lo = w0;
        if (w1 > hi) hi = w1;
    }
    uint32_t* span = vx_alloc(&cg->gpu->alloc, (size_t)(hi - lo) * 4);
    if (!span) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %llu bytes of moved pages", 4ull * (hi - lo));
    vx_result r = vx__buffer_download_at(cg->gpu, &cg->geom, lo * 4, span, (hi - lo) * 4, err);
    for (uint32_t i = 0; !r && i < n; i++) {
        const vx_compact_page* p = &pg->p.pages[pages[i]];
        memcpy(dst[i], span + (2 * (uint64_t)pg->moved_from[pages[i]] - lo), (size_t)p->words * 4);
        page_relocate(dst[i], p, (uint32_t)pg->moved_from[pages[i]], true);
    }
    pg->st.moved_from_pool += r ? 0 : n;
    vx_free(&cg->gpu->alloc, span);
    return r;
}

/* least recently entered first, ties by page (the order of the scan it replaced) */
static int cmp_victim(const void* a, const void* b) {
    const struct victim *x = a, *y = b;
    if (x->used != y->used) return x->used < y->used ? -1 : 1;
    return (x->page > y->page) - (x->page < y->page);
}

/* Between frames: loads the pages the last frame requested (evicting pages
 * the last frame did not enter, least recently entered first), marks the
 * evicted ones not resident in the top, and clears the frame's request and
 * use words: one staging buffer, one submission. */
static vx_result page_service(vx_compact_gpu* cg, vx_error* err) {
    paging* pg = cg->pg;
    vx_gpu* g = cg->gpu;
    uint64_t frame = pg->st.frames + 1; /* the frame about to be traced */
    pg->st.loaded = pg->st.evicted = pg->st.refused = pg->st.moved = 0;
    pg->st.refused_bytes = 0;
    uint32_t nload = 0;
    uint32_t* load = pg->pending; /* loaded pages are compacted to the front */
    /* the eviction candidates: resident pages the last frame did not enter,
     * least recently entered first (ties by page), sorted once: a scan of
     * every page for each page evicted made the services that swap
     * thousands of pages quadratic (pages loaded now are entered "now" and
     * never candidates, so the order stays valid through the service) */
    uint32_t nvict = 0, next_victim = 0;
    for (uint32_t k = 0; k < pg->p.page_count; k++)
        if (pg->slot[k] >= 0 && pg->last_used[k] + 1 < frame)
            pg->victims[nvict++] = (struct victim){.used = pg->last_used[k], .page = k};
    qsort(pg->victims, nvict, sizeof *pg->victims, cmp_victim);
    /* which pages load, and which go for them: a page evicts (least recently
     * entered first) while fewer units are free than it needs, and is refused
     * when no candidate is left; where the free units lie plays no part in
     * that, so the pages are placed after (below) */
    for (uint32_t i = 0; i < pg->npending; i++) {
        uint32_t page = pg->pending[i];
        if (page >= pg->p.page_count || pg->slot[page] >= 0) continue;
        uint32_t n = page_units(pg, page);
        while (pg->free_units < n) {
            while (next_victim < nvict && pg->slot[pg->victims[next_victim].page] < 0) next_victim++;
            if (next_victim == nvict) break;
            page_drop(pg, pg->victims[next_victim++].page);
            pg->st.evicted++;
        }
        if (pg->free_units < n) {
            pg->st.refused++;
            pg->st.refused_bytes += 4ull * pg->p.pages[page].words;
            continue;
        }
        pg->free_units -= n; /* its units, placed below */
        pg->last_used[page] = frame;
        pg->st.resident++;
        pg->st.used_bytes += 8ull * n * pg->unit;
        load[nload++] = page;
    }
    /* placed in turn, next fit; where the free units lie only in holes too
     * small, the pages slide together once and the rest fit after them (a
     * compaction per page, each a pass over the pool moving every page
     * after its first hole, cost 100-250 ms of the H200's frames that
     * loaded 150-500 pages) */
    uint32_t placed = 0;
    for (uint32_t i = 0; i < nload; i++) {
        uint32_t page = load[i], n = page_units(pg, page), u = pool_find(pg, n);
        if (u == UINT32_MAX) {
            pool_compact(pg, frame);
            u = pool_find(pg, n);
        }
        if (u == UINT32_MAX) { /* cannot happen (the free units hold it after the compaction): refused */
            pg->free_units += n;
            pg->st.resident--;
            pg->st.used_bytes -= 8ull * n * pg->unit;
            pg->st.refused++;
            pg->st.refused_bytes += 4ull * pg->p.pages[page].words;
            continue;
        }
        units_set(pg, u, n, page);
        pg->cursor = u + n < pg->units ? u + n : 0;
        pg->slot[page] = (int64_t)pg->words_base / 2 + (int64_t)u * pg->unit;
        load[placed++] = page;
    }
    nload = placed;
    pg->st.loaded = nload;
    pg->npending = 0;
    /* staging: the state words, the loaded images (relocated), the top's patched words */
    /* the moved pages go up as loads too (after this service's, so that
     * they are found in one list) */
    for (uint32_t i = 0; i < pg->nmoved; i++) {
        uint32_t page = pg->moved[i];
        pg->moved_bit[page >> 6] &= ~(1ull << (page & 63));
        if (pg->slot[page] >= 0) load[nload++] = page;
    }
    pg->nmoved = 0;
    pg->st.moved = nload - pg->st.loaded;
    uint64_t words = pg->state_words;
    for (uint32_t i = 0; i < nload; i++) words += pg->p.pages[load[i]].words;
    words += (uint64_t)nload + pg->nevict;
    vx_result r = VX_OK;
    if (!cg->stage.buf || cg->stage.size < words * 4) {
        vx__buffer_destroy(g, &cg->stage);
        r = vx__buffer_create(g, words * 4, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, true, "compact pages staging",
                              &cg->stage, err);
    }
    if (r) return r;
    uint32_t* st = cg->stage.map;
    uint32_t ncopy = 2 + nload + nload + pg->nevict, nc = 0;
    VkBufferCopy* cp = vx_alloc(&g->alloc, (size_t)ncopy * sizeof *cp);
    if (!cp) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %u copies", ncopy);
    uint64_t at = 0;
    memcpy(st, pg->state, (size_t)pg->state_words * 4);
    cp[nc++] = (VkBufferCopy){.srcOffset = 0, .dstOffset = 0, .size = (VkDeviceSize)pg->state_words * 4};
    at += pg->state_words;
    /* the images: from the layout's copy, or the file source (its cache, or cut from the file) */
    for (uint32_t i = 0, a = at; i < nload; i++) {
        const vx_compact_page* p = &pg->p.pages[load[i]];
        pg->dst[i] = st + a;
        if (!pg->cache) memcpy(st + a, pg->p.data + p->offset, (size_t)p->words * 4);
        a += p->words;
    }
    /* the file source's moved pages from the pool itself (loads [st.loaded, nload)) */
    uint32_t nget = pg->cache ? pg->st.loaded : nload;
    if (pg->cache && nload > nget) r = moved_from_pool(cg, load + nget, pg->dst + nget, nload - nget, err);
    if (!r && pg->cache && nget) r = vx_compact_page_cache_get(pg->cache, load, nget, pg->dst, err);
    if (r) {
        /* nothing went up: this service's pages (and those it moved) are not
         * resident after all; the next service marks them so in the top
         * before any ray enters them, and the next frame asks for them again */
        for (uint32_t i = 0; i < nload; i++) {
            page_drop(pg, load[i]);
            if (i < pg->st.loaded) pg->nevict--; /* loaded now: the top still says so (no patch to write) */
        }
        pg->st.loaded = 0;
        vx_free(&g->alloc, cp);
        return r;
    }
    for (uint32_t i = 0; i < nload; i++) {
        const vx_compact_page* p = &pg->p.pages[load[i]];
        uint32_t P = (uint32_t)pg->slot[load[i]];
        page_relocate(st + at, p, P, false);
        cp[nc++] = (VkBufferCopy){.srcOffset = at * 4, .dstOffset = (VkDeviceSize)P * 8, .size = (VkDeviceSize)p->words * 4};
        at += p->words;
    }
    for (uint32_t i = 0; i < nload + pg->nevict; i++) {
        uint32_t page = i < nload ? load[i] : pg->evict_patch[i - nload];
        /* an evicted page loaded again in this service: its load's word alone */
        if (i >= nload && pg->slot[page] >= 0) continue;
        st[at] = pg->slot[page] >= 0 ? (uint32_t)pg->slot[page] + 2 : 0x80000000u | page;
        cp[nc++] = (VkBufferCopy){.srcOffset = at * 4,
                                  .dstOffset = (2 * (VkDeviceSize)pg->p.pages[page].top_slot + 1) * 4, .size = 4};
        at++;
    }
    pg->nevict = 0;
    vx__seq s;
    if ((r = vx__seq_begin(g, &s, err))) {
        vx_free(&g->alloc, cp);
        return r;
    }
    /* the pool's and the top's words (no two regions overlap), then the
     * state words, whose copy's barrier orders all of them before the trace */
    if (nc > 1) vkCmdCopyBuffer(g->cmd, cg->stage.buf, cg->geom.buf, nc - 1, cp + 1);
    vx__seq_copy(g, &s, &cg->stage, 0, &cg->pstate, 0, cp[0].size);
    vx_free(&g->alloc, cp);
    return vx__seq_submit(g, &s, err);
}

static int cmp_u32(const void* a, const void* b) {
    uint32_t x = *(const uint32_t*)a, y = *(const uint32_t*)b;
    return (x > y) - (x < y);
}

/* After a frame: the pages it requested (drawn coarse) and those it entered
 * (by their first pool unit). */
static vx_result page_readback(vx_compact_gpu* cg, vx_error* err) {
    paging* pg = cg->pg;
    uint32_t n = pg->state_words;
    uint32_t* w = vx_alloc(&cg->gpu->alloc, (size_t)n * 4);
    if (!w) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory");
    vx_result r = vx__buffer_download(cg->gpu, &cg->pstate, w, (VkDeviceSize)n * 4, err);
    if (!r) {
        uint64_t frame = ++pg->st.frames;
        uint32_t count = w[0] < pg->p.page_count ? w[0] : pg->p.page_count;
        memcpy(pg->pending, w + pg->list_off, (size_t)count * 4);
        /* the list is in the order the GPU's threads appended to it, which
         * varies from run to run; where the pool cannot take every request,
         * the pages filled would vary with it (and the image): by page */
        qsort(pg->pending, count, 4, cmp_u32);
        pg->npending = count;
        pg->st.coarse = count;
        for (uint32_t u = 0; u < pg->units; u++)
            if (((w[pg->use_off + u / 32] >> (u % 32)) & 1u) && pg->owner[u]) pg->last_used[pg->owner[u] - 1] = frame;
    }
    vx_free(&cg->gpu->alloc, w);
    return r;
}

vx_result vx_compact_gpu_create_paged(vx_render_scene* rs, const vx_svo_scene* s, vx_compact_paged* p,
                                      uint64_t pool_bytes, vx_compact_gpu** out, vx_error* err) {
    return vx_compact_gpu_create_paged_ex(rs, s, p, pool_bytes, 0, out, err);
}

vx_result vx_compact_gpu_create_paged_ex(vx_render_scene* rs, const vx_svo_scene* s, vx_compact_paged* p,
                                         uint64_t pool_bytes, uint64_t host_budget, vx_compact_gpu** out, vx_error* err) {
    if (!rs || !s || !p || !out) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    if (!p->data && p->page_count && !p->reader)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "the paged layout has neither its page images nor a reader");
    if (p->model_count != s->model_count)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "the paged layout has %u models, the scene %u",
                       p->model_count, s->model_count);
    vx_gpu* g = vx__render_scene_gpu(rs);
    if (pool_bytes < 4ull * p->max_page_words)
        return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET,
                       "a page pool of %llu bytes cannot hold the largest page (%llu bytes): a larger budget or a "
                       "lower page level",
                       (unsigned long long)pool_bytes, 4ull * p->max_page_words);
    uint64_t max_words = (uint64_t)1 << 32; /* slots indexed by 31 bits, words by 32 */
    if (pool_bytes / 4 + p->top_words >= max_words) pool_bytes = (max_words - 16 - p->top_words) * 4;
    paging* pg = vx_calloc(&g->alloc, 1, sizeof *pg);
    if (!pg) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory");
    pg->p = *p;
    memset(p, 0, sizeof *p);
    uint32_t P = pg->p.page_count, W = (P + 31) / 32;
    /* units: small against pages (the waste at a page's end is half a unit
     * on average), at most 2^20 of them (a request's search is linear) */
    uint64_t maxslots = (pg->p.max_page_words + 1) / 2, pool_slots = pool_bytes / 8;
    pg->unit = 2;
    while (pg->unit < (pool_slots >> 20) || pg->unit * 1024ull < maxslots) pg->unit *= 2;
    pg->units = (uint32_t)(pool_bytes / 8 / pg->unit);
    pg->free_units = pg->units;
    pg->words_base = pg->p.top_words;
    pg->list_off = 1, pg->req_off = 1 + P, pg->rep_off = 1 + P + W, pg->use_off = 1 + 2 * P + W;
    pg->bitmap_words = W;
    pg->use_words = (pg->units + 31) / 32;
    pg->state_words = pg->use_off + (pg->use_words ? pg->use_words : 1);
    pg->owner = vx_calloc(&g->alloc, pg->units ? pg->units : 1, 4);
    pg->slot = vx_alloc(&g->alloc, (size_t)(P ? P : 1) * 8);
    pg->last_used = vx_calloc(&g->alloc, P ? P : 1, 8);
    pg->pending = vx_alloc(&g->alloc, (size_t)(P ? P : 1) * 4);
    pg->evict_patch = vx_alloc(&g->alloc, (size_t)(P ? P : 1) * 4);
    pg->moved = vx_alloc(&g->alloc, (size_t)(P ? P : 1) * 4);
    pg->moved_bit = vx_calloc(&g->alloc, (P + 63) / 64 + 1, 8);
    pg->moved_from = vx_alloc(&g->alloc, (size_t)(P ? P : 1) * 8);
    pg->victims = vx_alloc(&g->alloc, (size_t)(P ? P : 1) * sizeof *pg->victims);
    pg->busy = vx_calloc(&g->alloc, (pg->units + 63) / 64 + 1, 8);
    pg->dst = vx_alloc(&g->alloc, (size_t)(P ? P : 1) * sizeof *pg->dst);
    pg->state = vx_calloc(&g->alloc, pg->state_words, 4);
    vx_error cerr = {0};
    if (!pg->p.data && pg->p.reader && vx_compact_page_cache_create(&pg->p, host_budget, &g->alloc, &pg->cache, &cerr)) {
        paging_free(g, pg);
        if (err) *err = cerr;
        return cerr.code;
    }
    if (!pg->owner || !pg->slot || !pg->last_used || !pg->pending || !pg->evict_patch || !pg->moved || !pg->state || !pg->dst ||
        !pg->moved_bit || !pg->moved_from || !pg->victims || !pg->busy) {
        paging_free(g, pg);
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %u pages", P);
    }
    for (uint32_t k = 0; k < P; k++) {
        pg->slot[k] = -1;
        pg->state[pg->rep_off + k] = pg->p.pages[k].rgba;
    }
    uint32_t deep = deep_constant(s);
    vx_compact_gpu* cg = vx_calloc(&g->alloc, 1, sizeof *cg);
    cmodel_gpu* cm = vx_calloc(&g->alloc, s->model_count ? s->model_count : 1, sizeof *cm);
    if (!cg || !cm) {
        vx_free(&g->alloc, cg);
        vx_free(&g->alloc, cm);
        paging_free(g, pg);
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory");
    }
    cg->rs = rs, cg->gpu = g, cg->deep = deep, cg->pg = pg;
    vx_svo_scene_world_bounds(s, cg->lo, cg->hi);
    for (uint32_t i = 0; i < s->model_count; i++) {
        const vx_compact_model* m = &pg->p.models[i];
        const vx_svo_model* sm = &s->models[i];
        uint32_t flags = m->attr_kind != VX_COMPACT_ATTR_NONE ? 1u : 0u;
        uint32_t rebase;
        if (vx__render_model_deep(sm, &rebase)) flags |= 2u;
        bool paged = m->root < VX_SVO_ROOT_LEAF && m->depth > pg->p.page_level;
        cm[i] = (cmodel_gpu){.root = m->root, .depth = m->depth, .flags = flags, .box = vx__render_model_box(sm),
                             .attr_base = m->attr_base, .block_log2 = m->block ? (uint32_t)__builtin_ctz(m->block) : 0,
                             .kind = m->attr_kind, .rank_base = 2 * pg->p.top_slots,
                             .rebase = rebase,
                             .page_up = paged ? pg->p.page_level + 1 : 0,
                             .pool_base = pg->words_base / 2,
                             .unit_log2 = (uint32_t)__builtin_ctz(pg->unit)};
    }
    uint64_t pool_words = (uint64_t)pg->units * pg->unit * 2;
    uint64_t total = 4 * ((uint64_t)pg->p.top_words + pool_words);
    vx_result r = vx__buffer_create(g, total, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, false, "compact top and pages",
                                    &cg->geom, err);
    /* the top, its pages' words "not resident" as built */
    if (!r && pg->p.top_words) r = vx__buffer_upload(g, &cg->geom, pg->p.top, 4ull * pg->p.top_words, err);
    if (!r) r = upload(g, &cg->models, cm, (s->model_count ? s->model_count : 1) * sizeof *cm, "compact models", err);
    if (!r) r = upload(g, &cg->palette, pg->p.palette, sizeof pg->p.palette, "compact palette", err);
    if (!r) r = upload(g, &cg->pstate, pg->state, 4ull * pg->state_words, "compact pages", err);
    /* the top's slots as built: above the page level they never change (the page roots' word 1 does, below) */
    if (!r) path_lists(cg, cm, pg->p.models, s->model_count, pg->p.top, pg->p.top_slots);
    vx_free(&g->alloc, cm);
    if (r) {
        vx_compact_gpu_destroy(cg);
        return r;
    }
    pg->st.pages = P;
    pg->st.pool_bytes = pool_words * 4;
    pg->st.top_bytes = 4ull * pg->p.top_words + s->model_count * sizeof(cmodel_gpu) + sizeof pg->p.palette +
                       4ull * pg->state_words;
    cg->bytes = pg->st.top_bytes + pg->st.pool_bytes;
    *out = cg;
    return VX_OK;
}

/* trace_compact.comp's bindings: 0-10, then the attribute parts past the first from TC_ATTR_HI */
enum { TC_ATTR_HI = 11, TC_BINDINGS = TC_ATTR_HI + VX_COMPACT_ATTR_PARTS - 1 };

static vx_result dispatch(vx_compact_gpu* cg, const vx_render_desc* desc, bool want_hits, uint32_t repeat, vx__frame* f,
                          double* seconds, vx_error* err) {
    vx_gpu* g = cg->gpu;
    vx_result r = vx__frame_setup(cg->lo, cg->hi, desc, f, err);
    if (r) return r;
    if ((r = vx__gpu_float_range(cg->lo, cg->hi, err))) return r;
    vx__buffer* scene[7];
    uint32_t sp[VX__SPEC_COUNT];
    if ((r = vx__render_scene_tables(cg->rs, f, scene, sp, err))) return r;
    /* a scene of one instance (the kernel's USE_BVH off), the whole layout:
     * the kernel reads the instance's model's record from the frame block
     * (trace_compact.comp model_at; the instance's is there already) */
    vx__gpu_frame* gf = scene[0]->map;
    if (!sp[VX__SPEC_USE_BVH] && cg->cm && gf->inst0.model < cg->cm_count)
        memcpy(gf->cmodel0, &cg->cm[gf->inst0.model], sizeof *cg->cm);
    /* and the primary rays' starts below the root (trace_compact.comp
     * PATH_START), the kernel without them where no tile has one: the
     * start's code alone (the overviews: their rays enter the model box)
     * cost 1.3-2% of the albedo rays/s and 4-4.5% in the depth mode on the
     * H200 (docs/PERFORMANCE.md issue 18, fourteenth step) */
    bool path = !sp[VX__SPEC_USE_BVH] && vx__render_scene_path_on(cg->rs) && gf->inst0.model < cg->path_count &&
                cg->paths[gf->inst0.model].top;
    vx__path_model pm = path ? cg->paths[gf->inst0.model] : (vx__path_model){0};
    if (cg->start_min) pm.min_dq = cg->start_min;
    path = vx__render_scene_paths(cg->rs, f, path ? &pm : NULL, gf) > 0;
    VkDeviceSize npx = (VkDeviceSize)f->width * f->height;
    if ((r = vx__buffer_ensure(g, &cg->pixels, npx * 16, "compact pixels", err))) return r;
    if ((r = vx__buffer_ensure(g, &cg->hits, want_hits ? npx * 32 : 16, "compact hits", err))) return r;
    /* paged: the top and the pool are one buffer, bound as both the slots and the attribute words */
    uint32_t pages = cg->pg ? cg->pg->p.page_count : 0;
    /* The screen cull, as vx__render_dispatch's: the trace pass covers the pixels whose rays can meet the scene's
     * box, a second pass (the same kernel, MISS_PASS) writes the others' misses without a ray. Not when paged: a
     * page not resident is hit as its whole cube, which may reach past the cells' box. */
    uint32_t groups[3], miss_groups[3];
    uint64_t traced;
    bool miss = vx__frame_cull(f, cg->lo, cg->hi, !cg->pg, ((vx__gpu_frame*)scene[0]->map)->rect, groups, miss_groups,
                               &traced);
    /* 11: the miss pass */
    /* 6: one sample a pixel; 7: some start-table entry or some model is of one value (the kernel tests for them);
     * 12: the starts below the root */
    uint32_t spec[13] = {(uint32_t)f->mode, sp[VX__SPEC_HAS_COLOR], sp[VX__SPEC_USE_BVH], cg->records, want_hits, cg->dict,
                         f->spp <= 1, cg->uniform_entries > 0 || cg->uniform_models > 0, cg->deep, pages, cg->attr_shift, 0,
                         path};
    uint64_t key = vx__spec_key(0xC0AC7000u, spec, 13);
    vx_gpu_compute_pipeline_desc pd = {.spirv = vx__trace_compact_spv_arr, .spirv_size = sizeof vx__trace_compact_spv_arr,
                                       .binding_count = TC_BINDINGS, .spec_count = 13, .label = "trace compact"};
    pd.bindings[0] = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
    for (uint32_t i = 1; i < TC_BINDINGS; i++) pd.bindings[i] = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    memcpy(pd.spec, spec, sizeof spec);
    vx__pipeline* p;
    if ((r = vx__pipeline_get(g, key, &pd, &p, err))) return r;
    vx__pipeline* post = NULL;
    if (miss) {
        vx_gpu_compute_pipeline_desc md = pd;
        md.spec[11] = 1, md.label = "trace compact (misses)";
        md.spec[12] = 0; /* the miss pass traces no ray */
        uint64_t mkey = vx__spec_key(0xC0AC7000u, md.spec, 13);
        if ((r = vx__pipeline_get(g, mkey, &md, &post, err))) return r;
    }
    if (!cg->pstate.buf && (r = vx__buffer_create(g, 16, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, false, "compact pages",
                                                  &cg->pstate, err)))
        return r;
    vx__dispatch_desc dd = {.pipeline = p,
                            .buffer_count = TC_BINDINGS,
                            .buffers = {scene[0], &cg->geom, cg->pg ? &cg->geom : &cg->attr, &cg->models, scene[4],
                                        scene[5], scene[6], &cg->pixels, &cg->hits, &cg->palette, &cg->pstate},
                            .groups = {groups[0], groups[1], groups[2]},
                            .repeat = repeat,
                            .label = "trace compact",
                            .post_pipeline = post,
                            .post_groups = {miss_groups[0], miss_groups[1], miss_groups[2]}};
    /* the attribute parts past the first (bound to part 0 where there are none: never read) */
    for (uint32_t k = 1; k < VX_COMPACT_ATTR_PARTS; k++)
        dd.buffers[TC_ATTR_HI + k - 1] = k < cg->attr_parts ? &cg->attr_hi[k - 1] : dd.buffers[2];
    return vx__dispatch(g, &dd, seconds, err);
}

vx_result vx_compact_gpu_frame(vx_compact_gpu* cg, const vx_render_desc* desc, vx_render_image* out, vx_error* err) {
    if (!cg || !out) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    bool want_hits = desc && desc->want_hits;
    vx__frame f;
    double sec = 0;
    vx_result r = cg->pg ? page_service(cg, err) : VX_OK;
    if (!r) r = dispatch(cg, desc, want_hits, 1, &f, &sec, err);
    if (!r && cg->pg) r = page_readback(cg, err);
    if (r) return r;
    /* the file source: the requested pages the host cache lacks cut from
     * the file on threads while the image is read back and the caller works
     * between frames; the next service takes them from there */
    if (cg->pg && cg->pg->cache) vx_compact_page_cache_prefetch(cg->pg->cache, cg->pg->pending, cg->pg->npending);
    vx_render_image img = {.width = f.width, .height = f.height, .mode = f.mode, .alloc = &cg->gpu->alloc};
    if ((r = vx__image_read(cg->gpu, &cg->pixels, false, want_hits ? &cg->hits : NULL, &img, err))) return r;
    img.gpu_seconds = sec;
    img.rays = (uint64_t)f.width * f.height * f.spp;
    *out = img;
    return VX_OK;
}

vx_result vx_compact_gpu_time(vx_compact_gpu* cg, const vx_render_desc* desc, uint32_t repeat, double* seconds,
                              vx_error* err) {
    if (!cg || !seconds) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    vx__frame f;
    return dispatch(cg, desc, false, repeat ? repeat : 1, &f, seconds, err);
}
