/* render/render_scene.c - the scene on the GPU (prepare_* steps in
 * dependency order) and one frame: per-frame tables relative to the frame's
 * reference point, the trace dispatch and the readback. */
#include <math.h>
#include <string.h>

#include "render/compact.h"
#include "render/grid.h"
#include "render/render_internal.h"
#include "inst_rows.comp.h"
#include "refit.comp.h"

#include <stddef.h>

/* std140 places the precise variant's dvec4s at 32-byte multiples after the float block */
_Static_assert(offsetof(vx__gpu_frame, pfwd) == 128 && offsetof(vx__gpu_frame, inst0) == 224 &&
                   offsetof(vx__gpu_frame, model0) == 304 && offsetof(vx__gpu_frame, rect) == 336 &&
                   offsetof(vx__gpu_frame, tiles) == 368 && offsetof(vx__gpu_frame, cmodel0) == 2416 &&
                   2 * VX__TILES_X * VX__TILES_X == 2048 && offsetof(vx__gpu_frame, paths) == 2480 &&
                   sizeof(vx__gpu_path) == 128 && VX__PATHS == 64 && offsetof(vx__gpu_frame, gbox_lo) == 10672 &&
                   offsetof(vx__gpu_frame, grid0) == 10684 && offsetof(vx__gpu_frame, gbox_hi) == 10688 &&
                   offsetof(vx__gpu_frame, gunion) == 10700 &&
                   sizeof(vx__gpu_frame) == 10688 + 16,
               "vx__gpu_frame vs trace.comp");
_Static_assert(sizeof(vx__gpu_inst_precise) == 96, "vx__gpu_inst_precise vs trace.comp");

/* Where a model's node words (or colour records) live in the shared buffer:
 * [off, off + cap) words are its region, the first `have` of them hold its
 * words as last given (an edited model's appends go after them; see
 * vx_render_scene_update_model). */
typedef struct region {
    uint32_t off, cap, have;
} region;

/* One of the two buffers the models share (node words, colour records),
 * with headroom after the last region (the tail), the one a model's appends
 * grow into. */
typedef struct arena {
    uint32_t cap;  /* 4-byte units the buffer holds */
    uint32_t tail; /* the model whose region ends the used part (UINT32_MAX: none) */
} arena;

typedef struct inst_host {
    double inv[12]; /* model from world */
    double lo[3], hi[3]; /* world box */
    uint32_t model;
    uint32_t id;
    float cell;
} inst_host;

/* One grid over the cells of several instances (grid_walk.glsl's GRID_UNION), of two kinds:
 * - regions (prepare_union): every drawn instance's model-from-world map has the same linear part and
 *   translations that differ by whole bricks (8 cells), and each instance's cells lie in an aligned cube of
 *   2^shift cells of their own (a converter's regions: vox2svo's mesh regions, each a model at a whole
 *   region's offset); its bricks are shared with the models' own grids, a hit's cell mapped to its cube's
 *   instance and model cell;
 * - turned instances (prepare_union_turned): the maps differ by signed permutations and whole cells (a .vox
 *   scene's turned and mirrored models anywhere), no two instances holding the same cell; bricks of its own,
 *   a hit's instance from its brick's owner word.
 * trace.comp's kernel of one instance walks it without the BVH. The instances it was built for are kept: it
 * is used while they hold (a move or an animation's frame that changes them walks the BVH again; set_frame
 * compares them once, not each frame); an edit of a model drops it. */
typedef struct grid_union {
    uint32_t insts;      /* instances it holds (0: none built or dropped) */
    uint32_t addr;       /* its header's word in rs->grid (grid_walk.glsl's groot: the header, then the grid) */
    uint32_t table;      /* its table's word (regions: shift, nx, ny, nz, then per cube instance, cell offset xyz;
                          * turned instances: prepare_union_turned) */
    uint32_t depth, top; /* its cube of 2^depth cells and root level */
    uint32_t box[6];     /* its cells' box, hi exclusive */
    uint32_t flags;      /* its model record's (VX__MODEL_HAS_COLOR, VX__MODEL_EXACT) */
    uint32_t deep;       /* the DEEP constant its walk needs (vx__render_model_deep for its depth) */
    double inv[12];      /* its cells from world */
    uint32_t n;          /* rs->inst_count when built */
    inst_host* held;     /* rs->inst when built (n of them) */
    bool holds;          /* rs->inst is held (as built): set by prepare_union, set_frame */
    int on;              /* vx__render_scene_grid_union: -1 the default (on where it holds), 0 off, 1 on */
} grid_union;

/* An instance's rows relative to the world, as shaders/inst_rows.comp reads
 * them (the GPU computes the rows relative to the frame's reference point) */
typedef struct inst_src {
    double inv[12];
    double lo[3], hi[3];
    uint32_t model, id;
    float cell;
    uint32_t pad;
} inst_src;
_Static_assert(sizeof(inst_src) == 160, "inst_src vs inst_rows.comp");

/* The reference point block before the instance sources in a frame's tables (GPU rows). */
typedef struct rows_ref {
    double ref[3];
    double pad;
} rows_ref;

/* Per model, which words of its region hold a descriptor in the GPU form
 * (a bit per word; dform_walk below). On devices with gpu.h's nodes_file
 * the bits mark the same descriptors, which the GPU holds in the file's
 * form (the walk checks every model's pointers on every device). */
typedef struct dform {
    uint8_t* bits;
    size_t cap; /* bytes */
} dform;

struct vx_render_scene {
    uint32_t palette_used[8]; /* compact: the palette indices the records use (vx_compact_scene.palette_used) */
    vx_gpu* gpu;
    vx_allocator alloc;
    uint64_t buffer_range; /* bytes a storage buffer binding may hold (vx__render_scene_buffer_range) */
    uint32_t inst_count;
    uint32_t model_count; /* of the scene it was made from (vx_render_scene_set_frame checks it) */
    inst_host* inst;
    vx_bvh bvh;
    double bvh_seconds;
    bool has_color;
    uint32_t deep; /* the trace kernel's DEEP constant: 1 some model is exact, 2 some model is rebased */
    bool far;      /* the trace kernel's FAR constant: some model may hold a far pointer */
    bool precise;  /* float64 variant: a model deeper than VX_RENDER_PRECISE_DEPTH */
    int force_precise; /* -1: by depth; 0/1 forced (tests, benchmarks) */
    /* benchmarks: the float trace kernel from other SPIR-V (NULL: the built-in one) */
    const uint32_t* alt_spv;
    size_t alt_size;
    uint32_t alt_tag;
    const uint32_t* alt_beam; /* the beam pass's, likewise */
    size_t alt_beam_size;
    /* benchmarks and tests: the screen cull (-1: on unless alt_spv, 0 off, 1
     * on); vx__render_scene_trace_variant */
    int cull;
    int path; /* the starts below the root: -1 on for GPUs, off for CPU devices; 0 off, 1 on (vx__render_scene_trace_path) */
    uint64_t last_traced; /* the last frame's traced pixels */
    bool last_cull;       /* and whether they were not the whole image */
    uint32_t max_depth;
    double lo[3], hi[3];
    vx__buffer frame, nodes, colors, models, insts, pinsts, bvh_nodes, bvh_items, pixels, hits, dense_bits;
    vx__buffer beam; /* the beam pass's eye distance per pixel block */
    /* the grid walk (render/grid.h, trace.comp's GRID): words 0 .. model_count - 1 each model's grid address
     * (UINT32_MAX: none), then the grids, each after a 4-word header (its cells' box: lo.x | lo.y << 16,
     * lo.z | hi.x << 16, hi.y | hi.z << 16, 0; hi exclusive); grid_top the kernel's GRID: the greatest root level (0: no grid),
     * | 4 where every model that holds a cell has one (the octree walk compiled out), | 8 every root at the
     * greatest level (>= 2), | 32 some grid's cube is not its model's (vx__grid_cube: GRID_CUBE), | 64 some
     * grid's root is wide (GRID_OCT: grid_bits);
     * grid_on: vx__render_scene_grid (-1 the default: on where a grid was built) */
    vx__buffer grid;
    uint32_t* grid_at; /* host copy of the table's words 0 .. model_count - 1 (NULL: no grid) */
    /* per model, its grid's place in rs->grid: the header's word, the words there (header and grid) and its
     * root's level; kept after an edit drops the grid, whose rebuild (regrid) writes over it where it fits.
     * grid_end: the words of rs->grid in use (a rebuilt grid too large for its place goes there); grid_budget
     * the scene's (vx_render_scene_desc.grid_budget, bytes) */
    struct grid_slot {
        uint32_t addr, words, top;
    }* grid_slot;
    uint64_t grid_end, grid_budget;
    bool grid_cube; /* the grids were laid out over their cells' boxes' cubes (prepare_grids' pass 1: GRID_CUBE) */
    uint32_t grid_top;
    int grid_on;
    grid_union uni; /* one grid over a converter's regions (prepare_union), in rs->grid after the models' */
    /* the models' regions and table (vx_render_scene_update_model) */
    region* wreg; /* node words, per model */
    region* creg; /* colour records, per model */
    arena wa, ca;
    vx__gpu_model* gm;  /* host copy of the models buffer */
    vx__top_node** top; /* per model: the top of its octree (NULL: none; top_list) */
    uint32_t* top_count;
    dform* df;          /* per model: which of its region's words hold a descriptor in the GPU form (dform_walk) */
    uint32_t* msize;    /* per model: size[3], and whether it draws (root not empty) */
    uint32_t* mcells;   /* per model: its cells' box (vx_svo_model_cell_box), lo[3] and hi[3]: the instances' boxes */
    vx__buffer stage;   /* staging for updates where the buffers are not mapped */
    /* frames in flight (vx__render_scene_bind_cmd): their per-frame tables
     * were written by commands in their own command buffers; until settle()
     * the host neither writes the mapped tables nor changes what they read */
    bool recorded;
    bool items_dirty; /* the BVH's item order changed in place: bvh_items is written with the next frame's tables */
    /* the BVH refit on the GPU (shaders/refit.comp): recorded frames write
     * the instances' boxes relative to their reference point and refit the
     * nodes' bounds level by level, instead of every node's bounds from the
     * host. The tree's shape (first, count of each node) reaches the GPU
     * with a whole-node write: until one, shape_dirty. */
    uint32_t* bvh_order;   /* vx_bvh_levels: nodes level by level */
    uint32_t* bvh_level;   /* level starts in bvh_order */
    uint32_t bvh_levels;
    double bvh_cost;       /* the tree's cost when built (vx_bvh_cost): a refit tree twice as costly is built again */
    bool shape_dirty;
    bool order_dirty;      /* bvh_order changed in place: written with the next recorded frame's tables */
    vx__buffer inst_boxes, order_buf;
    VkDescriptorPool refit_pool;
    VkDescriptorSet refit_set;
    VkDescriptorSetLayout refit_dsl; /* the layout refit_set was made with */
    int tables_kind;       /* the last recorded tables' kind: 0 whole nodes, 1 refit, 2 refit with the rows on the GPU */
    /* the instances' rows on the GPU (shaders/inst_rows.comp): recorded frames
     * with the refit write the instances' rows relative to the world
     * (inst_src: only those that changed) and the frame's reference point;
     * the GPU computes the rows and boxes relative to it, so a camera move
     * writes no row. Where the device has float64 shaders. */
    vx__buffer inst_src;
    VkDescriptorSet rows_set;
    VkDescriptorSetLayout rows_dsl;
    int rows_gpu; /* -1: where the device has float64; 0/1 forced (vx__render_scene_rows_on_gpu) */
    uint32_t bvh_node_cap; /* nodes the bvh_nodes buffer holds (2n - 1 for n instances: any build fits) */
    void* scratch; /* host copy of the per-frame tables for those commands */
    size_t scratch_size;
    /* the tables the last recorded frame wrote (tables_size bytes, valid
     * while tables_known): a frame with the same (a still camera and scene)
     * records no update, the buffers hold them already */
    void* tables;
    size_t tables_size, tables_cap;
    bool tables_known;
    uint32_t shown;     /* the frame shown (vx_render_scene_set_frame) */
    vx_render_scene_stats stats;
    uint32_t dense_n[3];
    double dense_lo[3], dense_cell;
    /* the layout (vx_render_scene_create_ex): with COMPACT the nodes and
     * colors buffers are empty and compact traces the frames */
    vx_render_layout_info layout;
    vx_compact_gpu* compact;
    /* the directional light's depth map (shadow_map.c) and whether the last
     * frame used it */
    vx__smap smap;
    bool smap_used;
    /* the map's node list (SMAP_*); smap_side_req: the side asked for */
    enum {
        SMAP_LATER, /* made at the first build, from the node words (or compact geometry) read back */
        SMAP_MADE,  /* made (smap.side 0: no map possible) */
        SMAP_NEVER  /* shadow_map_side 1, the paged compact layout, float64, an edited model */
    } smap_state;
    uint32_t smap_side_req;
    /* a node list made on the host ahead (vx_render_scene_take_sun_nodes), for the first build where it fits */
    vx_render_sun_nodes* smap_pre;
    /* the light of the last colour frame since the instances last moved:
     * a map is built only for a light and instances two frames have had */
    bool smap_seen;
    float smap_seen_light[3];
};

/* Headroom after the models in the shared buffers, so that an edited
 * model's appended words usually fit without a new buffer: 1/16 more plus
 * 64 Ki entries (a brush stroke on a 256^3 model appends some thousands). */
static uint64_t with_headroom(uint64_t n, uint64_t limit) {
    uint64_t c = n + n / 16 + 65536;
    return c > limit ? (n > limit ? n : limit) : c;
}

/* Deep models on the float path (issue 18): models deeper than
 * VX_RENDER_EXACT_DEPTH get the hi/lo origin and a hit's t from its cube
 * (VX__MODEL_EXACT); those deeper than VX_RENDER_REBASE_DEPTH also the walk
 * in two frames, the lower one the frame of the nodes at depth
 * depth - VX_RENDER_FRAME_LEVELS (Model.rebase; as shallow as the frame's
 * precision allows, so that a ray moves between frames rarely). */
/* The DEEP constant a scene needs with model gm among its models. */
static uint32_t deep_level(uint32_t deep, const vx__gpu_model* gm) {
    uint32_t d = gm->rebase ? 2 : (gm->flags & VX__MODEL_EXACT) ? 1 : 0;
    return d > deep ? d : deep;
}

uint32_t vx__render_model_box(const vx_svo_model* m) {
    uint32_t sh = m->depth > 10 ? m->depth - 10 : 0, b = 0;
    for (int k = 0; k < 3; k++) {
        uint32_t q = m->size[k] ? ((m->size[k] - 1) >> sh) : 0; /* ceil(size / 2^sh) - 1 */
        b |= (q > 1023 ? 1023 : q) << (10 * k);
    }
    return b;
}

/* Far pointers (issue 21): the test of a descriptor's far bit on every push
 * cost 2-5% of the primary rays/s on the H200, so the trace kernel has it
 * only where some model may hold one (constant FAR). A model may when any of
 * its node words n[from, count) has bit 16 set: a descriptor's far bit, or a
 * far slot or attribute index of 2^16 or more (false positives, which only
 * keep the test). Models under 2^16 node words and records never have one. */
static bool words_may_far(const vx_svo_model* m, uint32_t from) {
    uint32_t acc = 0;
    for (uint32_t i = from; i < m->node_count; i++) acc |= m->nodes[i];
    return (acc >> 16) & 1u;
}

uint32_t vx__render_model_deep(const vx_svo_model* m, uint32_t* rebase) {
    *rebase = 0;
    if (m->root >= VX_SVO_ROOT_LEAF || m->depth <= VX_RENDER_EXACT_DEPTH) return 0;
    if (m->depth <= VX_RENDER_REBASE_DEPTH) return 1;
    *rebase = m->depth - VX_RENDER_FRAME_LEVELS;
    return 2;
}

static void deep_model(const vx_svo_model* m, vx__gpu_model* gm) {
    if (vx__render_model_deep(m, &gm->rebase)) gm->flags |= VX__MODEL_EXACT;
}

/* The GPU form of the plain layout's descriptors (issue 21). The node buffer
 * holds every descriptor a model's walk can reach with its low byte the
 * inner mask (valid and not leaf: the paper's non-leaf mask) where the file
 * has the leaf mask (vx__desc_gpu), so that trace_common.glsl's push finds a
 * child's valid bit, inner bit and the inner children below it from one
 * shift of the word. Other words (far slots, attribute indices, words no
 * descriptor reaches) are the file's. A model's dform has a bit per word of
 * its region: set where the GPU holds a descriptor in that form. A set bit's
 * descriptor has its whole subtree set (it was turned with them), so a walk
 * after an edit descends only into clear ones. */
static bool dform_get(const uint8_t* b, uint32_t i) { return (b[i >> 3] >> (i & 7)) & 1u; }
static void dform_set(uint8_t* b, uint32_t i) { b[i >> 3] |= (uint8_t)(1u << (i & 7)); }

/* Sets the bits (b, at least n of them) of the descriptors of words w[0, n)
 * that the walk from root (a descriptor of level depth) reaches through
 * descriptors whose bits were clear. *low: the lowest word whose bit it set
 * (n: none). dst (may be NULL; indexed as w): each of those words in the GPU
 * form. false where a reached descriptor's block lies outside [0, n) or
 * before word 0, or an inner child lies below level 1 (*bad: its word); the
 * bits set until then stay. About 3 ns a word on dev (terrain4096: 436,031
 * words in 1.3 ms). */
static bool dform_walk(const uint32_t* w, uint32_t n, uint32_t root, uint32_t depth, uint8_t* b, uint32_t* dst,
                       uint32_t* low, uint32_t* bad) {
    enum { CAP = 8 * (VX_RENDER_MAX_DEPTH + 2) };
    uint32_t sw[CAP], sl[CAP], sp = 0;
    *low = n;
    if (root >= n || dform_get(b, root)) return true;
    dform_set(b, root);
    *low = root;
    sw[sp] = root, sl[sp++] = depth;
    while (sp) {
        sp--;
        uint32_t at = sw[sp], lvl = sl[sp], d = w[at];
        if (dst) dst[at] = vx__desc_gpu(d);
        uint32_t inner = vx_svo_desc_valid(d) & ~vx_svo_desc_leaf(d), k = (uint32_t)__builtin_popcount(inner);
        if (!k) continue;
        *bad = at;
        uint32_t p = vx_svo_desc_ptr(d);
        if (lvl < 2 || p < 1 || p > at || sp + k > CAP) return false;
        uint32_t blk = at - p;
        if (vx_svo_desc_far(d)) blk = w[blk];
        if (blk >= n || k > n - blk) return false;
        for (uint32_t c = 0; c < k; c++) {
            uint32_t j = blk + c;
            if (dform_get(b, j)) continue;
            dform_set(b, j);
            if (j < *low) *low = j;
            sw[sp] = j, sl[sp++] = lvl - 1;
        }
    }
    return true;
}

/* dst[0, count) = the words src[from, from + count) as the GPU holds them
 * (those with their bits set in the GPU form; b NULL: the file's form, as
 * on devices with gpu.h's nodes_file). */
static void dform_put(uint32_t* dst, const uint32_t* src, uint32_t from, uint32_t count, const uint8_t* b) {
    if (!b) {
        if (count) memcpy(dst, src + from, (size_t)count * 4);
        return;
    }
    for (uint32_t i = 0; i < count; i++) {
        uint32_t x = src[from + i];
        dst[i] = dform_get(b, from + i) ? vx__desc_gpu(x) : x;
    }
}

/* The plain layout's words for vx__top_list: a node's word, its children's
 * block (svo/svo.h), checked against the model's n words */
typedef struct plain_words {
    const uint32_t* w;
    uint32_t n;
} plain_words;

static uint32_t plain_desc(const void* ctx, uint32_t word) { return ((const plain_words*)ctx)->w[word]; }

static bool plain_block(const void* ctx, uint32_t word, uint32_t desc, uint32_t k, uint32_t* blk) {
    const plain_words* pw = ctx;
    uint32_t p = vx_svo_desc_ptr(desc);
    if (p < 1 || p > word) return false;
    uint32_t b = word - p;
    if (vx_svo_desc_far(desc)) b = pw->w[b];
    if (b >= pw->n || k > pw->n - b) return false;
    *blk = b;
    return true;
}

vx__top_node* vx__top_list(const vx_allocator* alloc, const vx__top_src* src, uint32_t root, uint32_t* count) {
    *count = 0;
    uint32_t cap = src->max_nodes ? src->max_nodes : VX__TOP_NODES;
    vx__top_node* t = vx_alloc(alloc, cap * sizeof *t);
    if (!t) return NULL;
    uint32_t n = 1, level_end = 1, depth = 0;
    t[0] = (vx__top_node){.desc = src->desc(src->ctx, root), .word = root, .kids = VX__TOP_NONE};
    for (uint32_t i = 0; i < n; i++) {
        if (i == level_end) level_end = n, depth++;
        if (depth >= src->max_depth) break; /* its children would be past the deepest listed level */
        uint32_t d = t[i].desc, inner = vx_svo_desc_valid(d) & ~vx_svo_desc_leaf(d);
        uint32_t k = (uint32_t)__builtin_popcount(inner), blk;
        if (!k) continue;
        if (k > cap - n) break; /* the list ends: this and later entries keep VX__TOP_NONE */
        if (!src->block(src->ctx, t[i].word, d, k, &blk)) break;
        t[i].kids = n;
        for (uint32_t c = 0; c < k; c++)
            t[n++] = (vx__top_node){.desc = src->desc(src->ctx, blk + c), .word = blk + c, .kids = VX__TOP_NONE};
    }
    /* kept at its length (a scene holds a list per model) */
    vx__top_node* kept = vx_alloc(alloc, n * sizeof *kept);
    if (kept) {
        memcpy(kept, t, n * sizeof *kept);
        vx_free(alloc, t);
        t = kept;
    }
    *count = n;
    return t;
}

/* Lists the top of model mi's octree (vx__top_node) from its words w[0, n)
 * with root `root`, in place of the list it had. A list that cannot be
 * made (no memory, words out of their range) is none: the primary rays
 * then start at the root. */
static void top_list(vx_render_scene* rs, uint32_t mi, const uint32_t* w, uint32_t n, uint32_t root) {
    vx_free(&rs->alloc, rs->top[mi]);
    rs->top[mi] = NULL;
    rs->top_count[mi] = 0;
    if (!w || root >= n) return;
    plain_words pw = {.w = w, .n = n};
    vx__top_src src = {.ctx = &pw,
                       .desc = plain_desc,
                       .block = plain_block,
                       .max_depth = UINT32_MAX,
                       .max_nodes = vx__top_cap(rs->model_count)};
    rs->top[mi] = vx__top_list(&rs->alloc, &src, root, &rs->top_count[mi]);
}

/* The plain layout's node words and colour records of s. */
static void plain_size(const vx_svo_scene* s, uint64_t* words, uint64_t* colors) {
    *words = *colors = 0;
    for (uint32_t i = 0; i < s->model_count; i++) {
        *words += s->models[i].node_count;
        if (s->models[i].attrs) *colors += s->models[i].attr_count;
    }
}

/* The model table and, in the plain layout, the node words and colour
 * records (a compact scene's buffers stay empty: the compact layout holds
 * the scene, render/compact_gpu.c). */
static vx_result prepare_models(vx_render_scene* rs, const vx_svo_scene* s, bool plain, vx_error* err) {
    vx_gpu* g = rs->gpu;
    uint64_t words, colors;
    plain_size(s, &words, &colors);
    if (!plain) words = colors = 0;
    uint64_t limit = vx__render_scene_buffer_range(rs) / 4;
    if (words > limit || colors > limit)
        return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET,
                       "scene needs %llu node words and %llu colours; the device allows %llu per buffer",
                       (unsigned long long)words, (unsigned long long)colors, (unsigned long long)limit);
    size_t mcount = s->model_count ? s->model_count : 1;
    uint64_t wcap = with_headroom(words, limit), ccap = with_headroom(colors, limit);
    uint32_t* nw = vx_calloc(&rs->alloc, words ? words : 1, 4);
    uint32_t* cw = vx_calloc(&rs->alloc, colors ? colors : 1, 4);
    rs->gm = vx_calloc(&rs->alloc, mcount, sizeof *rs->gm);
    rs->wreg = vx_calloc(&rs->alloc, mcount, sizeof *rs->wreg);
    rs->creg = vx_calloc(&rs->alloc, mcount, sizeof *rs->creg);
    rs->msize = vx_calloc(&rs->alloc, mcount, 4 * sizeof *rs->msize);
    rs->mcells = vx_calloc(&rs->alloc, mcount, 6 * sizeof *rs->mcells);
    rs->top = vx_calloc(&rs->alloc, mcount, sizeof *rs->top);
    rs->top_count = vx_calloc(&rs->alloc, mcount, sizeof *rs->top_count);
    rs->df = vx_calloc(&rs->alloc, mcount, sizeof *rs->df);
    vx__gpu_model* gm = rs->gm;
    vx_result r = VX_OK;
    if (!nw || !cw || !gm || !rs->wreg || !rs->creg || !rs->msize || !rs->mcells || !rs->top || !rs->top_count ||
        !rs->df) {
        r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory staging %llu node words",
                    (unsigned long long)words);
        goto done;
    }
    uint32_t wo = 0, co = 0;
    for (uint32_t i = 0; i < s->model_count; i++) {
        const vx_svo_model* m = &s->models[i];
        if (m->node_count && !m->nodes) { /* a model reader's graph: the box its validation found (else the cube) */
            for (int k = 0; k < 3; k++) {
                rs->mcells[6 * i + k] = m->check.digest ? m->check.min[k] : 0;
                rs->mcells[6 * i + 3 + k] = m->check.digest ? m->check.max[k] : m->size[k];
            }
        } else {
            vx_svo_model_cell_box(m, &rs->mcells[6 * i], &rs->mcells[6 * i + 3]);
        }
        if (!plain) {
            /* what the instance tables and checks read of a model; no words */
            gm[i] = (vx__gpu_model){.depth = m->depth, .root = m->root, .root_attr = m->root_attr};
            if (m->attrs) rs->has_color = true;
            memcpy(&rs->msize[4 * i], m->size, 3 * sizeof m->size[0]);
            rs->msize[4 * i + 3] = m->root != VX_SVO_ROOT_EMPTY;
            continue;
        }
        if (m->node_count) {
            dform* f = &rs->df[i];
            f->cap = ((size_t)m->node_count + 7) / 8;
            if (!(f->bits = vx_calloc(&rs->alloc, f->cap, 1))) {
                r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for model %u's descriptor bits", i);
                goto done;
            }
            uint32_t low, bad = 0;
            memcpy(nw + wo, m->nodes, (size_t)m->node_count * 4);
            /* gpu.h's nodes_file (CPU devices): the file's form goes up as it is; the walk still checks the
             * model's pointers (about 3 ns a word), so that a scene is refused in either form alike */
            if (m->root < VX_SVO_ROOT_LEAF && !dform_walk(m->nodes, m->node_count, m->root, m->depth, f->bits,
                                                          rs->gpu->nodes_file ? NULL : nw + wo, &low, &bad)) {
                r = vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET,
                            "model %u: the descriptor at word %u points outside its %u node words or below level 1", i,
                            bad, m->node_count);
                goto done;
            }
        }
        top_list(rs, i, m->nodes, m->node_count, m->root);
        gm[i] = (vx__gpu_model){.node_off = wo, .color_off = co, .depth = m->depth, .root = m->root,
                                .root_attr = m->root_attr, .flags = m->attrs ? VX__MODEL_HAS_COLOR : 0};
        gm[i].box = vx__render_model_box(m);
        deep_model(m, &gm[i]);
        rs->deep = deep_level(rs->deep, &gm[i]);
        if (words_may_far(m, 0)) gm[i].flags |= VX__MODEL_FAR, rs->far = true;
        rs->wreg[i] = (region){.off = wo, .cap = m->node_count, .have = m->node_count};
        rs->creg[i] = (region){.off = co};
        if (m->attrs) {
            for (uint32_t a = 0; a < m->attr_count; a++) cw[co + a] = vx_svo_attr_rgba(s, m, a);
            rs->creg[i].cap = rs->creg[i].have = m->attr_count;
            co += m->attr_count;
            rs->has_color = true;
        }
        memcpy(&rs->msize[4 * i], m->size, 3 * sizeof m->size[0]);
        rs->msize[4 * i + 3] = m->root != VX_SVO_ROOT_EMPTY;
        wo += m->node_count;
    }
    rs->wa = (arena){.cap = (uint32_t)wcap, .tail = s->model_count ? s->model_count - 1 : UINT32_MAX};
    rs->ca = rs->wa;
    rs->ca.cap = (uint32_t)ccap;
    if (s->model_count) {
        region *lw = &rs->wreg[s->model_count - 1], *lc = &rs->creg[s->model_count - 1];
        lw->cap = (uint32_t)wcap - lw->off;
        lc->cap = (uint32_t)ccap - lc->off;
    }
    if ((r = vx__buffer_create(g, wcap * 4, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, false, "nodes", &rs->nodes, err)) ||
        (r = vx__buffer_upload(g, &rs->nodes, nw, words * 4, err)) ||
        (r = vx__buffer_create(g, ccap * 4, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, false, "colors", &rs->colors, err)) ||
        (r = vx__buffer_upload(g, &rs->colors, cw, colors * 4, err)) ||
        (r = vx__buffer_create(g, mcount * sizeof *gm, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, false, "models",
                               &rs->models, err)) ||
        (r = vx__buffer_upload(g, &rs->models, gm, s->model_count * sizeof *gm, err)))
        goto done;
    rs->stats.node_words_uploaded += words;
    rs->stats.records_uploaded += colors;
done:
    vx_free(&rs->alloc, nw);
    vx_free(&rs->alloc, cw);
    return r;
}

/* A grid's header's first three words (grid_walk.glsl: the cells' box it
 * clips rays to) from the model's cells' box cb (lo xyz, hi xyz exclusive,
 * each below 2^16: VX_RENDER_GRID_DEPTH). */
static void grid_header(const uint32_t cb[6], uint32_t w[3]) {
    w[0] = cb[0] | cb[1] << 16, w[1] = cb[2] | cb[3] << 16, w[2] = cb[4] | cb[5] << 16;
}

/* The smallest aligned power-of-two cube (at least a brick) that holds cells [lo, hi) of each axis, as a
 * shift. */
static uint32_t cube_shift(const uint64_t lo[3], const uint64_t hi[3]) {
    uint32_t sh = 3;
    for (int k = 0; k < 3; k++)
        while (sh < 40 && (lo[k] >> sh) != ((hi[k] - 1) >> sh)) sh++;
    return sh;
}

/* The union grid (grid_union) of the drawn instances, appended to out (the grid buffer's words) where the
 * scene is one: every drawn instance whose model holds a cell has a model-from-world map with the first's
 * linear part and a translation that differs from the first's by whole bricks, its cells in an aligned cube
 * of its own; the union at most VX_RENDER_GRID_DEPTH levels. Its walk is exact as a model of its depth is
 * (vx__render_model_deep: its kernel's DEEP at least uni.deep). Anything else leaves rs->uni empty (the
 * BVH); so does a layout that fails (memory, the budget). */
/* The union's bricks, kept for the models' grids, which point at them (vx__grid_model's share) rather than
 * hold copies: its bricks b (brick j at word base + 16 j) and per model the brick offset of its first
 * instance in the union (3 words; UINT32_MAX: none). */
typedef struct union_bricks {
    vx__grid_bricks b;
    uint64_t base;
    uint32_t* off;
    uint32_t rec; /* the union's record key (vx__grid_records; 0: none) */
} union_bricks;

/* The union's bricks' models for their record words (vx__grid_records): a brick's cube's instance in the
 * cube table (4 words a cube after its 4: instance, its cells' offset xyz). */
typedef struct union_rec {
    const uint32_t* table;
    const vx__grid_bricks* b;
    const vx_svo_scene* s;
    const inst_host* in;
} union_rec;

static const vx_svo_model* union_rec_model(void* user, size_t brick, uint32_t off[3]) {
    const union_rec* u = user;
    const uint32_t *c = &u->b->coords.w[3 * brick], *t = u->table;
    uint32_t sh = t[0] - 3; /* bricks to cubes */
    const uint32_t* e = &t[4 + 4 * (((size_t)(c[2] >> sh) * t[2] + (c[1] >> sh)) * t[1] + (c[0] >> sh))];
    if (e[0] == UINT32_MAX) return NULL;
    const vx_svo_model* m = &u->s->models[u->in[e[0]].model];
    for (int k = 0; k < 3; k++) off[k] = e[1 + k] >> 3;
    return m->attrs ? m : NULL;
}

static void prepare_union(vx_render_scene* rs, const vx_svo_scene* s, uint64_t budget, vx__grid_words* out,
                          union_bricks* ub) {
    uint32_t n = rs->inst_count, first = UINT32_MAX;
    if (n < 2) return;
    const inst_host* in = rs->inst;
    /* the instances' offsets from the first one's cells (whole bricks), as signed integers */
    int64_t* e = vx_calloc(&rs->alloc, 3 * (size_t)n, sizeof(int64_t));
    if (!e) return;
    bool ok = true, color = false;
    int64_t emin[3] = {0, 0, 0};
    for (uint32_t i = 0; ok && i < n; i++) {
        const vx_svo_model* m = &s->models[in[i].model];
        if (m->root == VX_SVO_ROOT_EMPTY) continue;
        if (m->depth > VX_RENDER_GRID_DEPTH || (m->node_count && !m->nodes)) ok = false;
        color |= (rs->gm[in[i].model].flags & VX__MODEL_HAS_COLOR) != 0;
        if (first == UINT32_MAX) first = i;
        const double* a = in[first].inv;
        for (int r = 0; ok && r < 3; r++) {
            for (int c = 0; c < 3; c++) ok &= in[i].inv[4 * r + c] == a[4 * r + c];
            /* a cell x of model i lies at x + (t_first - t_i) in the first's cells: whole bricks, to the
             * rounding of the maps' products (a converter's region origins in a scaled world: about 1e-14
             * cells apart from whole numbers; far below the float walk's 2^-24 of the union's cube) */
            double d = a[4 * r + 3] - in[i].inv[4 * r + 3], dr = rint(d);
            ok &= fabs(d) < 0x1p20 && fabs(d - dr) <= 1e-9 && fmod(dr, 8.0) == 0.0;
            if (ok) e[3 * i + r] = (int64_t)dr;
        }
        for (int k = 0; ok && k < 3; k++)
            if (first == i || e[3 * i + k] < emin[k]) emin[k] = e[3 * i + k];
    }
    if (!ok || first == UINT32_MAX) {
        vx_free(&rs->alloc, e);
        return;
    }
    /* the union's cells: the first's less emin, so that every model's cube starts at 0 or above */
    uint64_t ext[3] = {8, 8, 8}, blo[3] = {UINT64_MAX, UINT64_MAX, UINT64_MAX}, bhi[3] = {0, 0, 0};
    uint32_t shift = 3, held = 0;
    for (uint32_t i = 0; i < n; i++) {
        const vx_svo_model* m = &s->models[in[i].model];
        if (m->root == VX_SVO_ROOT_EMPTY) continue;
        const uint32_t* mc = &rs->mcells[6 * in[i].model];
        uint64_t lo[3], hi[3];
        for (int k = 0; k < 3; k++) {
            uint64_t off = (uint64_t)(e[3 * i + k] - emin[k]);
            lo[k] = off + mc[k], hi[k] = off + mc[3 + k];
            if (lo[k] < blo[k]) blo[k] = lo[k];
            if (hi[k] > bhi[k]) bhi[k] = hi[k];
            if (hi[k] > ext[k]) ext[k] = hi[k];
        }
        uint32_t sh = cube_shift(lo, hi);
        if (sh > shift) shift = sh;
        held++;
    }
    uint32_t depth = 3;
    while (depth < 40 && ((ext[0] - 1) >> depth || (ext[1] - 1) >> depth || (ext[2] - 1) >> depth)) depth++;
    /* its walk's precision: a model of its depth's (vx__render_model_deep) */
    uint32_t rebase, need = vx__render_model_deep(&(vx_svo_model){.depth = depth, .root = 0}, &rebase);
    uint64_t nc[3], cubes = 1;
    for (int k = 0; k < 3; k++) nc[k] = ((ext[k] - 1) >> shift) + 1, cubes *= nc[k];
    uint32_t* table = NULL;
    if (held < 2 || depth > VX_RENDER_GRID_DEPTH || cubes > (1u << 16) ||
        !(table = vx_alloc(&rs->alloc, (size_t)(4 + 4 * cubes) * 4))) {
        vx_free(&rs->alloc, e);
        return;
    }
    table[0] = shift, table[1] = (uint32_t)nc[0], table[2] = (uint32_t)nc[1], table[3] = (uint32_t)nc[2];
    memset(table + 4, 0xFF, (size_t)cubes * 16);
    /* each instance's cube (its cells in one: cube_shift <= shift), one instance a cube */
    for (uint32_t i = 0; ok && i < n; i++) {
        if (s->models[in[i].model].root == VX_SVO_ROOT_EMPTY) continue;
        const uint32_t* mc = &rs->mcells[6 * in[i].model];
        uint64_t c[3], off[3];
        for (int k = 0; k < 3; k++) off[k] = (uint64_t)(e[3 * i + k] - emin[k]), c[k] = (off[k] + mc[k]) >> shift;
        uint32_t* t = &table[4 + 4 * ((c[2] * nc[1] + c[1]) * nc[0] + c[0])];
        ok = t[0] == UINT32_MAX;
        t[0] = i, t[1] = (uint32_t)off[0], t[2] = (uint32_t)off[1], t[3] = (uint32_t)off[2];
    }
    /* the bricks of every model at its offset, laid out as one model's grid after its header */
    size_t before = out->n;
    vx__grid_bricks b = {.alloc = &rs->alloc};
    for (uint32_t i = 0; ok && i < n; i++) {
        const vx_svo_model* m = &s->models[in[i].model];
        if (m->root == VX_SVO_ROOT_EMPTY) continue;
        uint32_t off[3];
        for (int k = 0; k < 3; k++) off[k] = (uint32_t)((e[3 * i + k] - emin[k]) >> 3);
        vx_error ge = {0};
        ok = vx__grid_bricks_add(&b, m, off, &ge) == VX_OK;
    }
    /* (the union's grid covers its whole cube: its kernel's GRID has no GRID_CUBE) */
    uint32_t cb[6] = {(uint32_t)blo[0], (uint32_t)blo[1], (uint32_t)blo[2],
                      (uint32_t)bhi[0], (uint32_t)bhi[1], (uint32_t)bhi[2]};
    uint32_t top = vx__grid_top(depth, 0), addr = (uint32_t)out->n;
    vx_error ge = {0};
    ok = ok && vx__grid_words_grow(&rs->alloc, out, 4);
    if (ok) {
        grid_header(cb, &out->w[out->n]);
        out->w[out->n + 3] = 0;
        out->n += 4;
        memcpy(rs->uni.box, cb, sizeof cb);
    }
    ok = ok && vx__grid_layout(&b, depth, top, NULL, 0, out, &ge) == VX_OK;
    uint64_t R = (uint64_t)1 << (depth - 3 * top);
    uint32_t taddr = (uint32_t)out->n;
    ok = ok && vx__grid_words_grow(&rs->alloc, out, 4 + 4 * cubes) && (out->n + 4 + 4 * cubes) * 4 <= budget &&
         (rs->uni.held = vx_alloc(&rs->alloc, (size_t)n * sizeof *in));
    uint32_t rec = 0;
    if (ok) {
        memcpy(out->w + out->n, table, (size_t)(4 + 4 * cubes) * 4);
        out->n += 4 + 4 * cubes;
        /* the bricks' record words where a model has attributes (the hit's descent from its brick's node);
         * none where they do not fit (memory, the budget): the descent from the root */
        size_t at = out->n;
        union_rec ur = {table, &b, s, in};
        if (color && (vx__grid_records(&b, union_rec_model, &ur, 0, addr + 4 + R * R * R, out, &rec, &ge) ||
                      out->n * 4 > budget))
            out->n = at, rec = 0;
        out->w[addr + 3] = rec;
        memcpy(rs->uni.held, in, (size_t)n * sizeof *in);
        rs->uni.holds = true;
        memcpy(rs->uni.inv, in[first].inv, sizeof rs->uni.inv);
        for (int r = 0; r < 3; r++) rs->uni.inv[4 * r + 3] -= (double)emin[r]; /* exact: integers below 2^20 */
        rs->uni.insts = held, rs->uni.n = n, rs->uni.addr = addr, rs->uni.table = taddr;
        rs->uni.depth = depth, rs->uni.top = top, rs->uni.deep = need;
        rs->uni.flags = (color ? VX__MODEL_HAS_COLOR : 0u) | (need ? VX__MODEL_EXACT : 0u);
        /* the bricks for the models' grids: the first instance's offset of each model */
        if ((ub->off = vx_alloc(&rs->alloc, (size_t)s->model_count * 12))) {
            memset(ub->off, 0xFF, (size_t)s->model_count * 12);
            for (uint32_t i = 0; i < n; i++) {
                uint32_t* o = &ub->off[3 * in[i].model];
                if (s->models[in[i].model].root == VX_SVO_ROOT_EMPTY || o[0] != UINT32_MAX) continue;
                for (int k = 0; k < 3; k++) o[k] = (uint32_t)((e[3 * i + k] - emin[k]) >> 3);
            }
            ub->b = b, ub->base = addr + 4 + R * R * R, ub->rec = rec;
            b = (vx__grid_bricks){.alloc = &rs->alloc};
        }
    } else {
        out->n = before;
    }
    vx__grid_bricks_free(&b);
    vx_free(&rs->alloc, table);
    vx_free(&rs->alloc, e);
}

/* The union of turned instances (grid_union, its table's word 0 UNION_TURNED): where the regions' union does not
 * hold, every drawn instance whose model holds a cell maps the first one's cells to its own by a signed
 * permutation and whole cells (a .vox scene's turned and mirrored models at any cell offset: p = A u + b, A's
 * entries 0 or +-1, b whole), and no two instances hold the same cell, one grid is built over all their cells
 * (bricks of its own: the instances' cells need not fill bricks of their own). A hit's cell maps back through
 * its brick's owner word (render/shaders/grid_walk.glsl): the instance whose cells fill the brick, or
 * UNION_MIXED | the word address of 16-bit instance indices, one per set cell of the brick in bit order. The
 * table: word 0 UNION_TURNED, word 1 the owner words' key (brick word address w: key + (w >> 4)), then per
 * instance i at 4 + 4 i: i | per model axis c its union axis (2 bits at 16 + 2 c) and sign (bit 22 + c: -1),
 * then o_c: model cell p_c = s_c u_ax + o_c of union cell u. Its hits' records descend from the model's root
 * (header word 3: 0). Overlapping cells would need the walks' tie rule between instances: no union then. */
enum { UNION_TURNED = 0x80000000u, UNION_MIXED = 0x80000000u, UNION_TURNED_MAX = 0xFFFF };

typedef struct turn_map {
    int32_t q[3];  /* union cell u_r = s_c p_c + q_r, r = ax[c] */
    uint8_t ax[3]; /* per model axis c: its union axis */
    int8_t s[3];   /* and sign */
} turn_map;

typedef struct turn_ctx {
    vx__grid_bricks* b;
    const vx_allocator* a;
    const turn_map* map;
    uint32_t slot;
    uint32_t* owner; /* per brick: the instance that set its cells, or UNION_MIXED */
    size_t owner_cap;
    uint16_t* cells; /* pass 2: per mixed brick 512 instance indices (by its index in mixed) */
    const uint32_t* mixed;
    uint64_t count;
    bool clash, nomem;
} turn_ctx;

static bool turn_block(void* user, uint32_t bx, uint32_t by, uint32_t bz, const uint32_t bits[16]) {
    turn_ctx* c = user;
    const turn_map* t = c->map;
    const uint32_t bo[3] = {bx << 3, by << 3, bz << 3};
    for (uint32_t k = 0; k < 512; k++) {
        if (!(bits[k >> 5] >> (k & 31) & 1u)) continue;
        const uint32_t p[3] = {bo[0] + (k & 7), bo[1] + (k >> 3 & 7), bo[2] + (k >> 6)};
        uint32_t u[3];
        for (int m = 0; m < 3; m++) u[t->ax[m]] = (uint32_t)(t->s[m] * (int64_t)p[m] + t->q[t->ax[m]]);
        uint32_t i = (u[0] & 7) | (u[1] & 7) << 3 | (u[2] & 7) << 6;
        if (c->cells) { /* pass 2: the mixed bricks' cells */
            uint32_t* w = vx__grid_brick_at(c->b, u[0] >> 3, u[1] >> 3, u[2] >> 3);
            if (!w) return c->nomem = true, false;
            uint32_t j = c->mixed[(size_t)(w - c->b->bits.w) / 16];
            if (j != UINT32_MAX) c->cells[512 * (size_t)j + i] = (uint16_t)c->slot;
            continue;
        }
        if (++c->count > (UINT64_C(1) << 26)) return c->nomem = true, false; /* (seconds of this loop) */
        uint32_t* w = vx__grid_brick_at(c->b, u[0] >> 3, u[1] >> 3, u[2] >> 3);
        if (!w) return c->nomem = true, false;
        size_t j = (size_t)(w - c->b->bits.w) / 16;
        if (w[i >> 5] >> (i & 31) & 1u) return c->clash = true, false;
        w[i >> 5] |= 1u << (i & 31);
        if (j >= c->owner_cap) {
            void* o = c->owner;
            size_t cap = c->owner_cap;
            if (!vx_grow(c->a, &o, &c->owner_cap, j + 1, 4)) return c->nomem = true, false;
            c->owner = o;
            for (size_t z = cap; z < c->owner_cap; z++) c->owner[z] = UINT32_MAX;
        }
        if (c->owner[j] == UINT32_MAX) c->owner[j] = c->slot;
        else if (c->owner[j] != c->slot) c->owner[j] = UNION_MIXED;
    }
    return true;
}

/* The instances' maps from the first's cells (turn_map, table entries) for prepare_union_turned; false where
 * one is not a signed permutation and whole cells. */
static bool turn_maps(const vx_render_scene* rs, const vx_svo_scene* s, uint32_t first, turn_map* tm,
                      uint32_t* ent, int64_t emin[3], uint64_t ext[3], uint32_t box[6]) {
    const inst_host* in = rs->inst;
    const double* f = in[first].inv;
    /* the first's linear part inverted (its cells to world) */
    double L[9], det, I[9];
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++) L[3 * r + c] = f[4 * r + c];
    I[0] = L[4] * L[8] - L[5] * L[7], I[1] = L[2] * L[7] - L[1] * L[8], I[2] = L[1] * L[5] - L[2] * L[4];
    I[3] = L[5] * L[6] - L[3] * L[8], I[4] = L[0] * L[8] - L[2] * L[6], I[5] = L[2] * L[3] - L[0] * L[5];
    I[6] = L[3] * L[7] - L[4] * L[6], I[7] = L[1] * L[6] - L[0] * L[7], I[8] = L[0] * L[4] - L[1] * L[3];
    det = L[0] * I[0] + L[1] * I[3] + L[2] * I[6];
    if (!(fabs(det) > 1e-300)) return false;
    for (int k = 0; k < 9; k++) I[k] /= det;
    int64_t lo[3] = {INT64_MAX, INT64_MAX, INT64_MAX}, hi[3] = {INT64_MIN, INT64_MIN, INT64_MIN};
    for (uint32_t i = 0; i < rs->inst_count; i++) {
        if (s->models[in[i].model].root == VX_SVO_ROOT_EMPTY) continue;
        const double* g = in[i].inv;
        double A[9], b[3];
        uint32_t used = 0;
        for (int r = 0; r < 3; r++) {
            for (int c = 0; c < 3; c++)
                A[3 * r + c] = g[4 * r] * I[c] + g[4 * r + 1] * I[3 + c] + g[4 * r + 2] * I[6 + c];
            b[r] = g[4 * r + 3] - (A[3 * r] * f[3] + A[3 * r + 1] * f[7] + A[3 * r + 2] * f[11]);
        }
        turn_map* t = &tm[i];
        uint32_t code = 0;
        for (int c = 0; c < 3; c++) { /* model axis c: row c of A, one entry +-1 */
            int ax = -1;
            for (int r = 0; r < 3; r++) {
                double v = A[3 * c + r], rv = rint(v);
                if (fabs(v - rv) > 1e-9 || fabs(rv) > 1) return false;
                if (rv != 0) {
                    if (ax >= 0) return false;
                    ax = r, t->s[c] = (int8_t)rv;
                }
            }
            if (ax < 0 || used >> ax & 1u) return false;
            used |= 1u << ax, t->ax[c] = (uint8_t)ax;
            double rb = rint(b[c]);
            if (fabs(b[c] - rb) > 1e-9 || fabs(rb) > 0x1p20) return false;
            /* cell p_c = s u + b - [s < 0] (the cell [u, u + 1] of the union lands on [p, p + 1]) */
            int64_t bc = (int64_t)rb, neg = t->s[c] < 0;
            t->q[ax] = (int32_t)(t->s[c] * (neg - bc));
            const uint32_t* mc = &rs->mcells[6 * in[i].model];
            int64_t ulo = t->s[c] > 0 ? (int64_t)mc[c] - bc : bc - (int64_t)mc[3 + c];
            int64_t uhi = t->s[c] > 0 ? (int64_t)mc[3 + c] - bc : bc - (int64_t)mc[c];
            if (ulo < lo[ax]) lo[ax] = ulo;
            if (uhi > hi[ax]) hi[ax] = uhi;
            code |= (uint32_t)ax << (16 + 2 * c) | (uint32_t)neg << (22 + c);
        }
        ent[4 * i] = i | code;
    }
    for (int k = 0; k < 3; k++) {
        if (lo[k] < -(INT64_C(1) << 20) || hi[k] - lo[k] > (INT64_C(1) << 20)) return false;
        emin[k] = lo[k], ext[k] = (uint64_t)(hi[k] - lo[k]) < 8 ? 8 : (uint64_t)(hi[k] - lo[k]);
        box[k] = 0, box[3 + k] = (uint32_t)(hi[k] - lo[k]);
    }
    /* the maps in the union's cells (less emin): u = s p + q - emin, p = s u + o with o = s (emin - q) */
    for (uint32_t i = 0; i < rs->inst_count; i++) {
        if (s->models[in[i].model].root == VX_SVO_ROOT_EMPTY) continue;
        turn_map* t = &tm[i];
        for (int c = 0; c < 3; c++) {
            int ax = t->ax[c];
            ent[4 * i + 1 + c] = (uint32_t)(int32_t)(t->s[c] * (emin[ax] - (int64_t)t->q[ax]));
        }
        for (int r = 0; r < 3; r++) t->q[r] = (int32_t)(t->q[r] - emin[r]);
    }
    return true;
}

static void prepare_union_turned(vx_render_scene* rs, const vx_svo_scene* s, uint64_t budget, vx__grid_words* out) {
    uint32_t n = rs->inst_count, first = UINT32_MAX, held = 0;
    if (n < 2 || n > UNION_TURNED_MAX) return;
    const inst_host* in = rs->inst;
    bool color = false;
    for (uint32_t i = 0; i < n; i++) {
        const vx_svo_model* m = &s->models[in[i].model];
        if (m->root == VX_SVO_ROOT_EMPTY) continue;
        if (m->depth > VX_RENDER_GRID_DEPTH || (m->node_count && !m->nodes)) return;
        color |= (rs->gm[in[i].model].flags & VX__MODEL_HAS_COLOR) != 0;
        if (first == UINT32_MAX) first = i;
        held++;
    }
    if (held < 2) return;
    size_t nt = 4 + 4 * (size_t)n;
    turn_map* tm = vx_calloc(&rs->alloc, n, sizeof *tm);
    uint32_t* table = vx_calloc(&rs->alloc, nt, 4);
    int64_t emin[3];
    uint64_t ext[3];
    uint32_t box[6];
    vx__grid_bricks b = {.alloc = &rs->alloc};
    turn_ctx tc = {.b = &b, .a = &rs->alloc};
    uint32_t* mixed = NULL;
    bool ok = tm && table && turn_maps(rs, s, first, tm, table + 4, emin, ext, box);
    /* pass 1: every instance's cells into the bricks, each brick's owner; a cell set twice: no union */
    for (uint32_t i = 0; ok && i < n; i++) {
        const vx_svo_model* m = &s->models[in[i].model];
        if (m->root == VX_SVO_ROOT_EMPTY) continue;
        tc.map = &tm[i], tc.slot = i;
        vx_error ge = {0};
        ok = vx_svo_decode_blocks(m, turn_block, &tc, &ge) == VX_OK && !tc.clash && !tc.nomem;
    }
    size_t nb = b.bits.n / 16, nmix = 0;
    for (size_t j = 0; ok && j < nb; j++) nmix += tc.owner[j] == UNION_MIXED;
    /* pass 2: the mixed bricks' cells' instances */
    if (ok && nmix) {
        ok = (mixed = vx_alloc(&rs->alloc, nb * 4)) && (tc.cells = vx_calloc(&rs->alloc, nmix * 512, 2));
        for (size_t j = 0, k = 0; ok && j < nb; j++) mixed[j] = tc.owner[j] == UNION_MIXED ? (uint32_t)k++ : UINT32_MAX;
        tc.mixed = mixed;
        for (uint32_t i = 0; ok && i < n; i++) {
            const vx_svo_model* m = &s->models[in[i].model];
            if (m->root == VX_SVO_ROOT_EMPTY) continue;
            tc.map = &tm[i], tc.slot = i;
            vx_error ge = {0};
            ok = vx_svo_decode_blocks(m, turn_block, &tc, &ge) == VX_OK && !tc.nomem && b.bits.n / 16 == nb;
        }
    }
    uint32_t depth = 3;
    while (ok && depth < 40 && ((ext[0] - 1) >> depth || (ext[1] - 1) >> depth || (ext[2] - 1) >> depth)) depth++;
    ok = ok && depth <= VX_RENDER_GRID_DEPTH;
    uint32_t rebase, need = vx__render_model_deep(&(vx_svo_model){.depth = depth, .root = 0}, &rebase);
    size_t before = out->n;
    uint32_t top = vx__grid_top(depth, 0), addr = (uint32_t)out->n;
    vx_error ge = {0};
    ok = ok && vx__grid_words_grow(&rs->alloc, out, 4);
    if (ok) {
        grid_header(box, &out->w[out->n]);
        out->w[out->n + 3] = 0; /* no record words: a hit's record from its model's root */
        out->n += 4;
    }
    ok = ok && vx__grid_layout(&b, depth, top, NULL, 0, out, &ge) == VX_OK;
    uint64_t R = (uint64_t)1 << (depth - 3 * top), brick0 = addr + 4 + R * R * R;
    /* the table, the bricks' owner words, the mixed bricks' cell lists (16 bits a set cell) */
    uint32_t taddr = (uint32_t)out->n;
    size_t words = nt + nb;
    for (size_t j = 0; ok && j < nb; j++)
        if (tc.owner[j] == UNION_MIXED) {
            uint32_t set = 0;
            for (int k = 0; k < 16; k++) set += (uint32_t)__builtin_popcount(b.bits.w[16 * j + k]);
            words += (set + 1) / 2;
        }
    ok = ok && vx__grid_words_grow(&rs->alloc, out, words) && (out->n + words) * 4 <= budget &&
         out->n + words < UNION_MIXED && (rs->uni.held = vx_alloc(&rs->alloc, (size_t)n * sizeof *in));
    if (ok) {
        uint32_t* w = out->w + out->n;
        table[0] = UNION_TURNED, table[1] = (uint32_t)(taddr + nt - (brick0 >> 4));
        memcpy(w, table, nt * 4);
        uint32_t* own = w + nt;
        uint32_t list = (uint32_t)(taddr + nt + nb);
        for (size_t j = 0; j < nb; j++) {
            if (tc.owner[j] != UNION_MIXED) {
                own[j] = tc.owner[j];
                continue;
            }
            own[j] = UNION_MIXED | list;
            const uint32_t* bits = &b.bits.w[16 * j];
            const uint16_t* cs = &tc.cells[512 * (size_t)mixed[j]];
            uint32_t r = 0, *lw = out->w + list;
            for (uint32_t k = 0; k < 512; k++)
                if (bits[k >> 5] >> (k & 31) & 1u) {
                    if (!(r & 1)) lw[r >> 1] = 0;
                    lw[r >> 1] |= (uint32_t)cs[k] << (16 * (r & 1));
                    r++;
                }
            list += (r + 1) / 2;
        }
        out->n += words;
        memcpy(rs->uni.held, in, (size_t)n * sizeof *in);
        rs->uni.holds = true;
        memcpy(rs->uni.inv, in[first].inv, sizeof rs->uni.inv);
        for (int r = 0; r < 3; r++) rs->uni.inv[4 * r + 3] -= (double)emin[r]; /* exact: integers below 2^20 */
        memcpy(rs->uni.box, box, sizeof box);
        rs->uni.insts = held, rs->uni.n = n, rs->uni.addr = addr, rs->uni.table = taddr;
        rs->uni.depth = depth, rs->uni.top = top, rs->uni.deep = need;
        rs->uni.flags = (color ? VX__MODEL_HAS_COLOR : 0u) | (need ? VX__MODEL_EXACT : 0u);
    } else {
        out->n = before;
    }
    vx__grid_bricks_free(&b);
    vx_free(&rs->alloc, tc.owner);
    vx_free(&rs->alloc, tc.cells);
    vx_free(&rs->alloc, mixed);
    vx_free(&rs->alloc, table);
    vx_free(&rs->alloc, tm);
}

/* Whether the instances as they are now are those the union grid was built for (set_frame's check). */
static bool union_matches(const vx_render_scene* rs) {
    const grid_union* u = &rs->uni;
    if (!u->insts || u->n != rs->inst_count) return false;
    for (uint32_t i = 0; i < u->n; i++)
        if (memcmp(rs->inst[i].inv, u->held[i].inv, sizeof u->held[i].inv) || rs->inst[i].model != u->held[i].model)
            return false;
    return true;
}

/* Whether a frame walks the union grid. */
static bool union_holds(const vx_render_scene* rs) { return rs->uni.insts && rs->uni.holds && rs->uni.on != 0; }

/* The grid walk's grids (render/grid.h; trace.comp's grid_walk.glsl walks
 * them instead of the octrees): one per model of at most
 * VX_RENDER_GRID_DEPTH levels, built from its octree, in model order while
 * their words stay within the budget (desc->grid_budget) and one storage
 * buffer's range (on every device: lavapipe too since stop 87), and none for
 * the float64 variant's scenes. A model the grid cannot lay out keeps its octree walk. */
/* grid_walk.glsl's GRID from the grids the models have now (prepare_grids, regrid): the greatest root level,
 * GRID_ALL where every model that holds a cell has a grid, GRID_EXACT where every root is at that level and it is
 * 2 or more (at 1 the level is a constant already), GRID_CUBE as the grids were laid out (rs->grid_cube),
 * GRID_OCT where some grid's root is at least 2^VX__GRID_OCT_ROOT_LOG a side (render/grid.h: those grids hold
 * the octant extents; stop 88, H200: the terrains' roots of 64-128 1.14-1.35x their rays/s, the corpus's of 16-32
 * 0.92-1.00x), from its model's depth (a grid over its cells' cube may be narrower: its extents are 0 then) */
static void grid_bits(vx_render_scene* rs, const vx_svo_scene* s) {
    uint32_t made = 0, cells = 0, top = 0, low = UINT32_MAX;
    bool wide = false;
    for (uint32_t i = 0; i < rs->model_count; i++) {
        cells += s->models[i].root != VX_SVO_ROOT_EMPTY;
        if (rs->grid_at[i] == UINT32_MAX) continue;
        uint32_t t = rs->grid_slot[i].top, d = s->models[i].depth < 3 ? 3 : s->models[i].depth;
        made++;
        if (t > top) top = t;
        if (t < low) low = t;
        wide |= vx__grid_octants(d, t);
    }
    rs->grid_top = !made ? 0u
                         : top | (made == cells ? 4u : 0u) | (low == top && top >= 2 ? 8u : 0u) |
                               (rs->grid_cube ? 32u : 0u) | (wide ? 64u : 0u);
}

static vx_result prepare_grids(vx_render_scene* rs, const vx_svo_scene* s, const vx_render_scene_desc* desc,
                               vx_error* err) {
    uint64_t budget = desc && desc->grid_budget ? desc->grid_budget : VX_RENDER_GRID_BUDGET;
    if (budget == VX_RENDER_NO_GRID || rs->precise || !s->model_count) return VX_OK;
    if (budget > rs->buffer_range) budget = rs->buffer_range;
    double t0 = vx_time_now();
    vx__grid_words out = {0};
    if (!vx__grid_words_grow(&rs->alloc, &out, s->model_count))
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for the grid table");
    memset(out.w, 0xFF, (size_t)s->model_count * 4);
    out.n = s->model_count;
    struct grid_slot* slot = vx_calloc(&rs->alloc, s->model_count, sizeof *slot);
    if (!slot) {
        vx_free(&rs->alloc, out.w);
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for the grid table");
    }
    uint32_t made = 0;
    bool cube = false; /* some grid's cube is not its model's (vx__grid_cube): grid_walk.glsl's GRID_CUBE */
    uint32_t cubes = 0;
    /* the converter's regions as one grid first (trace.comp's kernel of one instance walks it), its bricks
     * shared with the regions' own grids (the pass kernels' and the BVH's walk) */
    union_bricks ub = {.b = {.alloc = &rs->alloc}};
    prepare_union(rs, s, budget, &out, &ub);
    /* Each grid over its model's cube (pass 0); where some grid would take more words than its model's
     * octree (nodes and records) and its cells' box's cube is smaller (render/grid.h vx__grid_cube: a slab or
     * a small group of cells in a large model, whose dense root is mostly empty), every grid is laid out
     * again over that cube where it is smaller (pass 1, GRID_CUBE: each walk then derives its cube, which
     * cost 1-5% of the rays/s on the H100 where it changed nothing, p85b; so not where no grid needs it) */
    /* on a CPU device, turned instances as one grid too (stop 84's patch, stop 87): lavapipe traced the
     * 104-instance scene's union 1.46-1.64x faster than its instances under the BVH (each instance box a ray
     * enters sets up a walk, costlier on a CPU's lanes); on the H100 it was 0.97-1.00x, so a GPU keeps the BVH */
    if (!rs->uni.insts && vx_gpu_is_cpu(rs->gpu)) prepare_union_turned(rs, s, budget, &out);
    size_t models_at = out.n;
    bool shrink = false;
    for (int pass = 0; pass < 2; pass++) {
        if (pass == 1) {
            if (!shrink) break;
            out.n = models_at;
            memset(out.w, 0xFF, (size_t)s->model_count * 4);
            memset(slot, 0, (size_t)s->model_count * sizeof *slot);
            made = cubes = 0;
        }
        for (uint32_t i = 0; i < s->model_count; i++) {
            const vx_svo_model* m = &s->models[i];
            if (m->root == VX_SVO_ROOT_EMPTY || m->depth > VX_RENDER_GRID_DEPTH || (m->node_count && !m->nodes))
                continue;
            size_t before = out.n;
            /* the header: the cells' box (grid_walk.glsl clips the ray to it, not to the model's extent: a slab
             * of cells in a large model's cube, ogt_doom's, walked 7x the steps of the prototype that clipped) */
            if (!vx__grid_words_grow(&rs->alloc, &out, 4)) continue;
            grid_header(&rs->mcells[6 * i], &out.w[out.n]);
            out.w[out.n + 3] = 0;
            out.n += 4;
            vx_error e = {0}; /* a model the layout refuses (memory, 2^31 words) keeps the octree walk */
            uint32_t t;
            vx__grid_share sh = {&ub.b, ub.base, {0, 0, 0}, ub.rec};
            bool shared = ub.off && ub.off[3 * i] != UINT32_MAX;
            if (shared) memcpy(sh.off, &ub.off[3 * i], sizeof sh.off);
            uint32_t rec;
            const uint32_t* cb = pass ? &rs->mcells[6 * i] : NULL;
            if (vx__grid_model(&rs->alloc, m, cb, 0, shared ? &sh : NULL, &out, &t, &rec, &e) ||
                (uint64_t)out.n * 4 > budget) {
                out.n = before;
                continue;
            }
            out.w[before + 3] = rec; /* the header's word 3: its bricks' record key (grid_walk.glsl) */
            uint32_t co[3], cd = vx__grid_cube(&rs->mcells[6 * i], m->depth, co);
            bool small = cd != (m->depth < 3 ? 3 : m->depth) || co[0] || co[1] || co[2];
            shrink |= small && out.n - before - 4 > (uint64_t)m->node_count + (m->attrs ? m->attr_count : 0);
            cube |= small && pass;
            cubes += small && pass;
            out.w[i] = (uint32_t)before;
            slot[i] = (struct grid_slot){(uint32_t)before, (uint32_t)(out.n - before), t};
            made++;
        }
    }
    vx__grid_bricks_free(&ub.b);
    vx_free(&rs->alloc, ub.off);
    vx_result r = VX_OK;
    if (made && !(rs->grid_at = vx_alloc(&rs->alloc, (size_t)s->model_count * 4)))
        r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for the grid table");
    if (made && !r && !(r = vx__buffer_create(rs->gpu, (VkDeviceSize)out.n * 4, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, false,
                                        "grid", &rs->grid, err)))
        r = vx__buffer_upload(rs->gpu, &rs->grid, out.w, (VkDeviceSize)out.n * 4, err);
    if (!r && made) {
        memcpy(rs->grid_at, out.w, (size_t)s->model_count * 4);
        rs->grid_slot = slot, slot = NULL;
        rs->grid_end = out.n, rs->grid_budget = budget, rs->grid_cube = cube;
        grid_bits(rs, s);
        rs->layout.grid_bytes = (uint64_t)out.n * 4;
        rs->layout.grid_models = made;
        rs->layout.grid_cubes = cubes;
        rs->layout.grid_seconds = vx_time_now() - t0;
    }
    if (!made || r) rs->uni.insts = 0; /* (no grid buffer) */
    vx_free(&rs->alloc, out.w);
    vx_free(&rs->alloc, slot);
    return r;
}

static uint32_t drawn_count(const vx_svo_scene* s) {
    uint32_t n = 0;
    for (uint32_t i = 0; i < s->instance_count; i++) n += vx_svo_instance_drawn(s, i);
    return n;
}

/* An instance's cell size in the world: its world-from-model map's longest column. */
static double instance_cell(const double w[12]) {
    double cell = 0;
    for (int c = 0; c < 3; c++) cell = fmax(cell, sqrt(w[c] * w[c] + w[4 + c] * w[4 + c] + w[8 + c] * w[8 + c]));
    return cell;
}

/* The drawn instances of s into inst (n of them) and their world boxes into
 * lo, hi (3 doubles each): the boxes of their models' cells (mcells, 6 words
 * a model), not of the models' extents. A region model of the converter is a
 * whole 2^k cube whose cells often fill a slab of it; the BVH then culls the
 * rays that cross only the cube's empty rest before any model walk (issue 18:
 * 1.3-1.7 fewer instances entered per ray on the sphere of 64^3 regions). */
static void fill_instances(const vx_svo_scene* s, const uint32_t* mcells, inst_host* inst, double* lo, double* hi) {
    uint32_t k = 0;
    for (uint32_t i = 0; i < s->instance_count; i++) {
        if (!vx_svo_instance_drawn(s, i)) continue;
        double w[12];
        vx_svo_instance_world(s, &s->instances[i], w);
        vx__affine_inverse(w, inst[k].inv); /* checked by vx__check_scene */
        inst[k].model = s->instances[i].model;
        inst[k].id = i;
        inst[k].cell = (float)instance_cell(w);
        const uint32_t* mc = &mcells[6 * s->instances[i].model];
        double clo[3] = {mc[0], mc[1], mc[2]}, chi[3] = {mc[3], mc[4], mc[5]};
        vx_svo_box_map(w, clo, chi, &lo[3 * k], &hi[3 * k]);
        memcpy(inst[k].lo, &lo[3 * k], sizeof inst[k].lo);
        memcpy(inst[k].hi, &hi[3 * k], sizeof inst[k].hi);
        k++;
    }
}

/* The BVH's levels (vx_bvh_levels) for the GPU refit, after a build. */
static vx_result bvh_levels(vx_render_scene* rs, vx_error* err) {
    vx_free(&rs->alloc, rs->bvh_order), rs->bvh_order = NULL;
    vx_free(&rs->alloc, rs->bvh_level), rs->bvh_level = NULL;
    rs->bvh_levels = 0;
    uint32_t nn = rs->bvh.node_count;
    if (!nn) return VX_OK;
    rs->bvh_order = vx_alloc(&rs->alloc, (size_t)nn * 4);
    rs->bvh_level = vx_alloc(&rs->alloc, ((size_t)nn + 1) * 4);
    if (!rs->bvh_order || !rs->bvh_level) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for the BVH's levels");
    vx_bvh_levels(&rs->bvh, rs->bvh_order, rs->bvh_level, &rs->bvh_levels);
    rs->bvh_cost = vx_bvh_cost(&rs->bvh);
    return VX_OK;
}

/* The host side of the instances: rs->inst (n drawn instances) and the BVH
 * over their world boxes (rs->bvh), built on the CPU. */
static vx_result instance_tables(vx_render_scene* rs, const vx_svo_scene* s, vx_error* err) {
    uint32_t n = drawn_count(s);
    /* the kernels' BVH stack packs a node's or leaf's first index with its
     * count in 32 bits (trace_common.glsl's BVH_ENTRY): indices below 2^29 */
    if (n > (1u << 27))
        return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "%u drawn instances: the GPU tracer takes at most %u", n, 1u << 27);
    rs->inst_count = n;
    rs->inst = vx_calloc(&rs->alloc, n ? n : 1, sizeof *rs->inst);
    double* lo = vx_calloc(&rs->alloc, 3 * (size_t)(n ? n : 1), sizeof(double));
    double* hi = vx_calloc(&rs->alloc, 3 * (size_t)(n ? n : 1), sizeof(double));
    vx_result r = VX_OK;
    if (!rs->inst || !lo || !hi) {
        r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %u instances", n);
        goto done;
    }
    fill_instances(s, rs->mcells, rs->inst, lo, hi);
    double t0 = vx_time_now();
    if (n > 1 && (r = vx_bvh_build(lo, hi, n, &rs->alloc, &rs->bvh, err))) goto done;
    rs->bvh_seconds = vx_time_now() - t0;
    r = bvh_levels(rs, err);
    rs->shape_dirty = true;
done:
    vx_free(&rs->alloc, lo);
    vx_free(&rs->alloc, hi);
    return r;
}

/* Instances moved (the same number drawn): rs->inst made again and the BVH
 * refit over the new boxes, its shape kept (no build: O(n), where the build
 * of 10,000 instances took 3.6 ms). VX_ERR_LIMIT, nothing changed: the
 * refit tree would cost more than twice the built one's (vx_bvh_cost):
 * build it again. */
static vx_result instance_refit(vx_render_scene* rs, const vx_svo_scene* s, vx_error* err) {
    uint32_t n = rs->inst_count;
    inst_host* inst = vx_calloc(&rs->alloc, n, sizeof *inst);
    double* lo = vx_calloc(&rs->alloc, 3 * (size_t)n, sizeof(double));
    double* hi = vx_calloc(&rs->alloc, 3 * (size_t)n, sizeof(double));
    vx_bvh fit = rs->bvh;
    fit.nodes = vx_alloc(&rs->alloc, (size_t)rs->bvh.node_count * sizeof *fit.nodes);
    vx_result r = VX_OK;
    if (!inst || !lo || !hi || !fit.nodes) {
        r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %u instances", n);
    } else {
        fill_instances(s, rs->mcells, inst, lo, hi);
        memcpy(fit.nodes, rs->bvh.nodes, (size_t)rs->bvh.node_count * sizeof *fit.nodes);
        double t0 = vx_time_now();
        double cost = vx_bvh_refit(&fit, lo, hi, n);
        if (!(cost >= 0) || cost > 2 * rs->bvh_cost) {
            r = vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "the refit BVH costs %g, built %g: build it again", cost,
                        rs->bvh_cost);
        } else {
            rs->bvh_seconds = vx_time_now() - t0;
            vx_free(&rs->alloc, rs->bvh.nodes);
            rs->bvh.nodes = fit.nodes, fit.nodes = NULL;
            vx_free(&rs->alloc, rs->inst);
            rs->inst = inst, inst = NULL;
        }
    }
    vx_free(&rs->alloc, fit.nodes);
    vx_free(&rs->alloc, inst);
    vx_free(&rs->alloc, lo);
    vx_free(&rs->alloc, hi);
    return r;
}

/* Every buffer prepare_instances makes, in one list so that a rebuild and the scene's destruction free the
 * same set (the refit's two and later the instance sources were leaked by a rebuild while the lists were
 * written twice; the validation layer names them at vkDestroyDevice). */
static void destroy_instance_buffers(vx_render_scene* rs) {
    vx__buffer* bufs[] = {&rs->frame,      &rs->bvh_items, &rs->bvh_nodes, &rs->insts,
                          &rs->pinsts,     &rs->inst_boxes, &rs->order_buf, &rs->inst_src};
    for (size_t i = 0; i < sizeof bufs / sizeof bufs[0]; i++) vx__buffer_destroy(rs->gpu, bufs[i]);
}

static vx_result prepare_instances(vx_render_scene* rs, const vx_svo_scene* s, vx_error* err) {
    vx_result r = instance_tables(rs, s, err);
    if (r) return r;
    uint32_t n = rs->inst_count;
    vx_gpu* g = rs->gpu;
    /* room for any BVH over n instances (a binary tree with non-empty leaves), so that an edit rebuilds it in place */
    rs->bvh_node_cap = n > 1 ? 2 * n - 1 : 1;
    if ((r = vx__buffer_create(g, (VkDeviceSize)(n ? n : 1) * sizeof(vx__gpu_inst), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                               true, "instances", &rs->insts, err)) ||
        (r = vx__buffer_create(g, (VkDeviceSize)rs->bvh_node_cap * sizeof(vx_bvh_node),
                               VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, true, "bvh nodes", &rs->bvh_nodes, err)) ||
        (r = vx__buffer_create(g, (VkDeviceSize)(rs->bvh.item_count ? rs->bvh.item_count : 1) * 4,
                               VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, false, "bvh items", &rs->bvh_items, err)) ||
        (r = vx__buffer_upload(g, &rs->bvh_items, rs->bvh.items, (VkDeviceSize)rs->bvh.item_count * 4, err)) ||
        (r = vx__buffer_create(g, (VkDeviceSize)(n ? n : 1) * sizeof(vx__gpu_inst_precise),
                               VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, true, "instances (double)", &rs->pinsts, err)) ||
        (r = vx__buffer_create(g, sizeof(vx__gpu_frame), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, true, "frame", &rs->frame,
                               err)) ||
        (r = vx__buffer_create(g, (VkDeviceSize)(n ? n : 1) * 32, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, false,
                               "instance boxes", &rs->inst_boxes, err)) ||
        (r = vx__buffer_create(g, (VkDeviceSize)(n ? n : 1) * sizeof(inst_src), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, false,
                               "instance sources", &rs->inst_src, err)) ||
        (r = vx__buffer_create(g, (VkDeviceSize)rs->bvh_node_cap * 4, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, false,
                               "bvh order", &rs->order_buf, err)) ||
        (rs->bvh_levels && (r = vx__buffer_upload(g, &rs->order_buf, rs->bvh_order, (VkDeviceSize)rs->bvh.node_count * 4,
                                                  err))))
        return r;
    /* the refit's set names the old buffers (no frame is in flight: the caller waited) */
    if (rs->refit_set) vkFreeDescriptorSets(g->device, rs->refit_pool, 1, &rs->refit_set), rs->refit_set = VK_NULL_HANDLE;
    if (rs->rows_set) vkFreeDescriptorSets(g->device, rs->refit_pool, 1, &rs->rows_set), rs->rows_set = VK_NULL_HANDLE;
    rs->order_dirty = false;
    rs->items_dirty = false;
    rs->tables_known = false; /* new buffers */
    if (!rs->insts.map || !rs->pinsts.map || !rs->bvh_nodes.map || !rs->frame.map)
        r = vx_fail(err, VX_ERR_GPU, VX_NO_OFFSET, "per-frame buffers are not host visible");
    return r;
}

/* The deepest model the scene draws, and whether this device can trace it. */
static vx_result drawn_depth(vx_gpu* gpu, const vx_svo_scene* s, uint32_t* out, vx_error* err) {
    uint32_t max_depth = 0, deep_model = 0;
    for (uint32_t i = 0; i < s->instance_count; i++) {
        if (!vx_svo_instance_drawn(s, i)) continue;
        uint32_t d = s->models[s->instances[i].model].depth;
        if (d > max_depth) max_depth = d, deep_model = s->instances[i].model;
    }
    if (max_depth > VX_RENDER_PRECISE_DEPTH && !gpu->has_float64)
        return vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET,
                       "model %u has %u octree levels; past %u the tracer needs float64 shaders, which %s lacks "
                       "(split the model into instances of at most %u levels)",
                       deep_model, max_depth, VX_RENDER_PRECISE_DEPTH, gpu->props.deviceName, VX_RENDER_PRECISE_DEPTH);
    *out = max_depth;
    return VX_OK;
}

const char* vx_render_layout_name(vx_render_layout layout) {
    return layout == VX_RENDER_LAYOUT_PLAIN ? "plain" : layout == VX_RENDER_LAYOUT_COMPACT ? "compact" : "auto";
}

/* AUTO's default budget: three quarters of the largest device-local heap
 * (the rest for frame buffers, pipelines and other work). */
static uint64_t default_budget(const vx_gpu* g) {
    uint64_t best = 0;
    for (uint32_t i = 0; i < g->memprops.memoryHeapCount; i++)
        if ((g->memprops.memoryHeaps[i].flags & VK_MEMORY_HEAP_DEVICE_LOCAL_BIT) && g->memprops.memoryHeaps[i].size > best)
            best = g->memprops.memoryHeaps[i].size;
    return best / 4 * 3;
}

/* The compact layout over the budget: paged at level lp, the pool the
 * budget less the top. Where the top and the largest page exceed the
 * budget too, *whole: the whole layout (over the budget, as the layout info
 * says; the device may still hold it). */
static vx_result create_paged(vx_render_scene* rs, const vx_svo_scene* s, const vx_compact_scene* c, uint32_t lp,
                              uint64_t budget, bool* whole, vx_error* err) {
    vx_compact_paged p;
    vx_result r = vx_compact_page_build(c, lp, &rs->alloc, &p, err);
    if (r) return r;
    uint64_t top = 4ull * p.top_words + 64ull * s->model_count + 1024 + 64 + 16ull * p.page_count;
    *whole = top >= budget || budget - top < 4ull * p.max_page_words;
    if (*whole) {
        vx_compact_paged_free(&p);
        return VX_OK;
    }
    rs->layout.pages = p.page_count;
    rs->layout.page_level = lp;
    /* (the pool's use bits, a bit per unit of at least 16 bytes, count in the top) */
    uint64_t pool = budget - top;
    r = vx_compact_gpu_create_paged(rs, s, &p, pool - pool / 128 - 8, &rs->compact, err);
    vx_compact_paged_free(&p); /* emptied when taken */
    return r;
}

void vx_render_scene_page_stats(const vx_render_scene* rs, vx_render_page_stats* out) {
    vx_compact_gpu_page_stats(rs ? rs->compact : NULL, out);
}

/* The shadow map's node list for the drawn instances (shadow_map.c): s's
 * models, or compact layout c's where c is not NULL. */
static vx_result smap_list(vx_render_scene* rs, const vx_svo_scene* s, const vx_compact_scene* c, uint32_t side,
                           uint32_t max_side, vx_error* err) {
    uint32_t n = rs->inst_count;
    uint32_t* model = vx_calloc(&rs->alloc, n ? n : 1, sizeof *model);
    float* cell = vx_calloc(&rs->alloc, n ? n : 1, sizeof *cell);
    vx_result r = VX_OK;
    if (!model || !cell) r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory");
    for (uint32_t i = 0; !r && i < n; i++) model[i] = rs->inst[i].model, cell[i] = rs->inst[i].cell;
    uint32_t per_cell = rs->gpu->props.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU ? VX__SMAP_PER_CELL_CPU : VX__SMAP_PER_CELL;
    if (!r) r = vx__smap_list(rs->gpu, &rs->alloc, s, c, model, cell, n, rs->lo, rs->hi, side, per_cell, max_side, &rs->smap, err);
    vx_free(&rs->alloc, model);
    vx_free(&rs->alloc, cell);
    return r;
}

vx_result vx__render_scene_smap_side(vx_render_scene* rs, const vx_svo_scene* s, uint32_t side, vx_error* err) {
    if (!rs || !s) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    vx__smap_free(rs->gpu, &rs->smap);
    rs->smap_state = SMAP_MADE;
    if (rs->compact || rs->precise || side == 1) return VX_OK;
    return smap_list(rs, s, NULL, side, 0, err);
}

/* A sun map's node list made on the host ahead of its render scene (render.h). */
struct vx_render_sun_nodes {
    const vx_allocator* alloc;
    vx__smap_pre* pre;
    uint32_t inst_count, model_count;
    uint32_t* model; /* the drawn instances' models and cells, as fill_instances has them */
    float* cell;
    double lo[3], hi[3];
    double seconds;
};

void vx_render_sun_nodes_free(vx_render_sun_nodes* n) {
    if (!n) return;
    vx__smap_pre_free(n->pre);
    vx_free(n->alloc, n->model);
    vx_free(n->alloc, n->cell);
    vx_free(n->alloc, n);
}

vx_result vx_render_sun_nodes_make(const vx_svo_scene* s, const vx_render_sun_nodes_desc* desc, vx_render_sun_nodes** out,
                                   vx_error* err) {
    if (!s || !out) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    *out = NULL;
    vx_render_sun_nodes_desc d = desc ? *desc : (vx_render_sun_nodes_desc){0};
    if (d.layout && d.layout->model_count != s->model_count)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "the compact layout has %u models, the scene %u",
                       d.layout->model_count, s->model_count);
    double t0 = vx_time_now();
    vx_render_sun_nodes* n = vx_calloc(d.alloc, 1, sizeof *n);
    if (!n) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory");
    n->alloc = d.alloc;
    uint32_t k = drawn_count(s);
    n->model = vx_calloc(d.alloc, k ? k : 1, sizeof *n->model);
    n->cell = vx_calloc(d.alloc, k ? k : 1, sizeof *n->cell);
    vx_result r = VX_OK;
    if (!n->model || !n->cell) r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory");
    for (uint32_t i = 0; !r && i < s->instance_count; i++) {
        if (!vx_svo_instance_drawn(s, i)) continue;
        double w[12];
        vx_svo_instance_world(s, &s->instances[i], w);
        n->model[n->inst_count] = s->instances[i].model;
        n->cell[n->inst_count++] = (float)instance_cell(w);
    }
    n->model_count = s->model_count;
    vx_svo_scene_world_bounds(s, n->lo, n->hi);
    if (!r)
        r = vx__smap_pre_make(d.alloc, s, d.layout, n->model, n->cell, n->inst_count, n->lo, n->hi, d.shadow_map_side,
                              d.cpu_device ? VX__SMAP_PER_CELL_CPU : VX__SMAP_PER_CELL, d.max_side, &n->pre, err);
    if (r) {
        vx_render_sun_nodes_free(n);
        return r;
    }
    n->seconds = vx_time_now() - t0;
    *out = n;
    return VX_OK;
}

void vx_render_scene_take_sun_nodes(vx_render_scene* rs, vx_render_sun_nodes* n) {
    if (!rs) {
        vx_render_sun_nodes_free(n);
        return;
    }
    vx_render_sun_nodes_free(rs->smap_pre);
    rs->smap_pre = n;
}

/* Whether the list made ahead is the one smap_list would make now. */
static bool smap_pre_fits(const vx_render_scene* rs, uint32_t per_cell, uint32_t max_side) {
    const vx_render_sun_nodes* n = rs->smap_pre;
    if (!n || !vx__smap_pre_fits(n->pre, rs->smap_side_req, per_cell, max_side) || n->inst_count != rs->inst_count ||
        n->model_count != rs->model_count || memcmp(n->lo, rs->lo, sizeof n->lo) || memcmp(n->hi, rs->hi, sizeof n->hi))
        return false;
    for (uint32_t i = 0; i < n->inst_count; i++)
        if (n->model[i] != rs->inst[i].model || n->cell[i] != rs->inst[i].cell) return false;
    return true;
}

/* The node list from the plain layout's words on the GPU (at the first build). */
static vx_result smap_list_gpu(vx_render_scene* rs, uint32_t max_side, vx_error* err) {
    rs->smap_state = SMAP_MADE;
    uint32_t per_cell = rs->gpu->props.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU ? VX__SMAP_PER_CELL_CPU : VX__SMAP_PER_CELL;
    if (smap_pre_fits(rs, per_cell, max_side)) {
        /* listed on the host while the device opened: only its buffer is left */
        double t0 = vx_time_now(), ahead = rs->smap_pre->seconds;
        vx_result r = vx__smap_pre_use(rs->gpu, rs->smap_pre->pre, &rs->smap, err);
        vx_render_sun_nodes_free(rs->smap_pre);
        rs->smap_pre = NULL;
        if (!r && rs->smap.side) rs->smap.list_seconds = vx_time_now() - t0, rs->smap.ahead_seconds = ahead;
        return r;
    }
    vx_render_sun_nodes_free(rs->smap_pre);
    rs->smap_pre = NULL;
    if (rs->compact) {
        /* the compact layout's geometry words: the same cells (smap_compact_state) */
        double t0 = vx_time_now();
        vx_compact_scene c;
        vx_result r = vx__compact_gpu_geometry(rs->compact, &c, err);
        if (!r) r = smap_list(rs, NULL, &c, rs->smap_side_req, max_side, err);
        vx_compact_free(&c);
        if (!r && rs->smap.side) rs->smap.list_seconds = vx_time_now() - t0;
        return r;
    }
    uint64_t words = 0;
    for (uint32_t i = 0; i < rs->model_count; i++)
        if (rs->wreg[i].have && (uint64_t)rs->wreg[i].off + rs->wreg[i].have > words) words = (uint64_t)rs->wreg[i].off + rs->wreg[i].have;
    double t0 = vx_time_now();
    uint32_t* w = vx_alloc(&rs->alloc, (size_t)(words ? words : 1) * 4);
    vx_svo_model* m = vx_calloc(&rs->alloc, rs->model_count ? rs->model_count : 1, sizeof *m);
    vx_result r = VX_OK;
    if (!w || !m) r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for the shadow map's nodes");
    if (!r && words) r = vx__buffer_download(rs->gpu, &rs->nodes, w, words * 4, err);
    for (uint32_t i = 0; !r && i < rs->model_count; i++) {
        /* what the listing reads of a model: its words, depth and root */
        m[i].nodes = w + rs->wreg[i].off;
        m[i].node_count = rs->wreg[i].have;
        /* the listing reads the file's form: the GPU form's descriptors back (vx__desc_gpu is its own inverse) */
        for (uint32_t j = 0; !rs->gpu->nodes_file && rs->df && rs->df[i].bits && j < rs->wreg[i].have; j++)
            if (dform_get(rs->df[i].bits, j)) w[rs->wreg[i].off + j] = vx__desc_gpu(w[rs->wreg[i].off + j]);
        m[i].depth = rs->gm[i].depth;
        m[i].root = rs->gm[i].root;
    }
    vx_svo_scene v = {.model_count = rs->model_count, .models = m};
    if (!r) r = smap_list(rs, &v, NULL, rs->smap_side_req, max_side, err);
    if (!r && rs->smap.side) rs->smap.list_seconds = vx_time_now() - t0;
    vx_free(&rs->alloc, w);
    vx_free(&rs->alloc, m);
    return r;
}

void vx_render_scene_shadow_map_info(const vx_render_scene* rs, vx_render_shadow_map_info* out) {
    if (!out) return;
    memset(out, 0, sizeof *out);
    if (!rs) return;
    out->side = rs->smap.side;
    out->nodes = rs->smap.node_count;
    out->list_seconds = rs->smap.list_seconds;
    out->ahead_seconds = rs->smap.ahead_seconds;
    out->builds = rs->smap.builds;
    out->build_seconds = rs->smap.build_seconds;
    out->build_gpu_seconds = rs->smap.build_gpu_seconds;
    out->used = rs->smap_used;
    for (int k = 0; k < 3; k++)
        out->origin[k] = rs->smap.origin[k], out->axis_u[k] = rs->smap.axis_u[k], out->axis_v[k] = rs->smap.axis_v[k];
    out->u0 = rs->smap.u0, out->v0 = rs->smap.v0, out->texel = rs->smap.texel;
}

vx_result vx_render_scene_create(vx_gpu* gpu, const vx_svo_scene* s, vx_render_scene** out, vx_error* err) {
    return vx_render_scene_create_ex(gpu, s, NULL, out, err);
}

/* The layout create_ex takes for s (AUTO decided), from the models' declared
 * counts and depths only (a model reader's graph serves). */
static vx_result choose_layout(vx_gpu* gpu, const vx_svo_scene* s, const vx_render_scene_desc* desc, vx_render_layout_info* out,
                               uint32_t* depth, uint64_t* range_out, vx_error* err) {
    vx_result r = vx__check_scene(s, err);
    uint32_t max_depth = 0;
    if (r || (r = drawn_depth(gpu, s, &max_depth, err))) return r;
    vx_render_layout_info li = {.layout = desc ? desc->layout : VX_RENDER_LAYOUT_AUTO,
                                .budget = vx_render_scene_budget(gpu, desc)};
    if (li.layout > VX_RENDER_LAYOUT_COMPACT)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "unknown render layout %d", (int)li.layout);
    uint64_t words, colors;
    plain_size(s, &words, &colors);
    li.plain_bytes = 4 * (words + colors);
    for (uint32_t i = 0; i < s->model_count; i++) li.voxels += s->models[i].voxel_count;
    /* the compact kernel is the float walk only */
    bool compact_ok = max_depth <= VX_RENDER_PRECISE_DEPTH;
    if (li.layout == VX_RENDER_LAYOUT_COMPACT && !compact_ok)
        return vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET,
                       "the compact layout traces models of at most %u levels; the scene has %u",
                       VX_RENDER_PRECISE_DEPTH, max_depth);
    /* the plain layout's node words and records each in one storage buffer: past the range it cannot
     * render at all (the helmet at 16384^3: 7.5 GB of words and records on a 4 GB range) */
    uint64_t range = gpu->props.limits.maxStorageBufferRange;
    if (desc && desc->max_buffer_range && desc->max_buffer_range < range) range = desc->max_buffer_range;
    bool plain_fits = 4 * words <= range && 4 * colors <= range;
    if (li.layout == VX_RENDER_LAYOUT_AUTO)
        li.layout = (li.plain_bytes > li.budget || !plain_fits) && compact_ok ? VX_RENDER_LAYOUT_COMPACT
                                                                              : VX_RENDER_LAYOUT_PLAIN;
    *out = li;
    *depth = max_depth;
    *range_out = range;
    return VX_OK;
}

static vx_render_scene* new_scene(vx_gpu* gpu, const vx_svo_scene* s, const vx_render_layout_info* li, uint64_t range,
                                  uint32_t max_depth) {
    vx_render_scene* rs = vx_calloc(&gpu->alloc, 1, sizeof *rs);
    if (!rs) return NULL;
    rs->gpu = gpu;
    rs->alloc = gpu->alloc;
    rs->buffer_range = range;
    rs->bvh.alloc = &rs->alloc;
    rs->max_depth = max_depth;
    rs->precise = max_depth > VX_RENDER_PRECISE_DEPTH;
    rs->force_precise = -1;
    rs->cull = -1;
    rs->path = -1;
    rs->grid_on = -1;
    rs->uni.on = -1;
    rs->rows_gpu = -1;
    rs->model_count = s->model_count;
    vx_svo_scene_world_bounds(s, rs->lo, rs->hi); /* every frame of an animation */
    rs->layout = *li;
    return rs;
}

/* A compact scene's sun map, as a plain one's, is listed at its first build,
 * from the geometry read back (smap_list_gpu) or a list made ahead from the
 * host's layout (vx_render_sun_nodes_desc.layout): the same cells, so the
 * same shadow rays' answers. A paged layout's geometry is not all on the
 * GPU: no map there. */
static void smap_compact_state(vx_render_scene* rs, const vx_render_scene_desc* desc) {
    rs->smap_side_req = desc ? desc->shadow_map_side : 0;
    rs->smap_state = rs->layout.pages || rs->smap_side_req == 1 ? SMAP_NEVER : SMAP_LATER;
}

/* What -v and vx_render_scene_layout report of a compact build that took
 * `seconds`: its stages' times, its form and its bytes. */
static void note_compact_build(vx_render_scene* rs, const vx_compact_scene* c, double seconds) {
    rs->layout.build_seconds = seconds;
    rs->layout.attr_seconds = c->stats.attr_seconds;
    rs->layout.geom_seconds = c->stats.geom_seconds;
    rs->layout.geom_threads = c->stats.geom_threads;
    rs->layout.brick_dict = c->brick_dict;
    rs->layout.compact_bytes = 4ull * c->geom_words + 4ull * c->attr_words;
    rs->layout.geom_bytes = 4ull * c->geom_words;
}

/* Compact layout c of scene s onto the GPU for rs (c is freed whatever the
 * result): paged below the page level where it exceeds the budget, whole
 * otherwise; one rule for create_ex and the reader's path. */
static vx_result upload_compact(vx_render_scene* rs, const vx_svo_scene* s, vx_compact_scene* c,
                                const vx_render_scene_desc* desc, uint64_t budget, uint32_t max_depth, vx_error* err) {
    double t1 = vx_time_now();
    uint32_t lp = desc && desc->page_level ? desc->page_level : VX_RENDER_FRAME_LEVELS;
    if (lp >= max_depth) lp = max_depth > 6 ? max_depth - 3 : 3;
    bool whole = true;
    vx_result r = VX_OK;
    memcpy(rs->palette_used, c->palette_used, sizeof rs->palette_used); /* the passes' tables (attr_palette) */
    if (rs->layout.compact_bytes > budget && lp < max_depth && !(r = vx_compact_join_attrs(c, err)))
        r = create_paged(rs, s, c, lp, budget, &whole, err);
    if (!r && whole) r = vx_compact_gpu_create(rs, s, c, &rs->compact, err);
    if (!r && whole) rs->layout.material_bytes = vx__compact_gpu_material_bytes(rs->compact);
    rs->layout.upload_seconds = vx_time_now() - t1;
    if (!whole) rs->layout.brick_dict = false; /* pages keep the bricks in their blocks */
    vx_compact_free(c);
    return r;
}

vx_result vx_render_scene_create_ex(vx_gpu* gpu, const vx_svo_scene* s, const vx_render_scene_desc* desc,
                                    vx_render_scene** out, vx_error* err) {
    if (!gpu || !s || !out) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    vx_render_layout_info li;
    uint32_t max_depth = 0;
    uint64_t range = 0;
    vx_result r = choose_layout(gpu, s, desc, &li, &max_depth, &range, err);
    if (r) return r;
    bool plain = li.layout == VX_RENDER_LAYOUT_PLAIN;
    vx_render_scene* rs = new_scene(gpu, s, &li, range, max_depth);
    if (!rs) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory");
    if ((r = prepare_models(rs, s, plain, err)) || (r = prepare_instances(rs, s, err)) ||
        (plain && (r = prepare_grids(rs, s, desc, err)))) {
        vx_render_scene_destroy(rs);
        return r;
    }
    if (plain) {
        rs->layout.bytes = li.plain_bytes;
        /* the shadow map's nodes are listed where a map is first built (most
         * scenes never build one: a pass without a directional light, depth
         * frames), from the words on the GPU: the scene does not keep the
         * models, and listing every scene took 1-31 ms and a buffer */
        rs->smap_side_req = desc ? desc->shadow_map_side : 0;
        rs->smap_state = rs->precise || rs->smap_side_req == 1 ? SMAP_NEVER : SMAP_LATER;
    } else {
        rs->smap_state = SMAP_NEVER;
        vx_compact_scene c;
        uint32_t bricks = desc ? desc->compact_bricks : VX_RENDER_BRICKS_AUTO;
        /* the attributes in their per-model regions: the upload takes them as they
         * are, no second host copy (the paged layout joins them first) */
        vx_compact_desc cd = {.alloc = &rs->alloc, .attr_regions = true,
                              .bricks = bricks == VX_RENDER_BRICKS_DICT ? VX_COMPACT_BRICKS_DICT : VX_COMPACT_BRICKS_INLINE};
        double t0 = vx_time_now();
        r = vx_compact_build(&cd, s, &c, err);
        if (!r && bricks == VX_RENDER_BRICKS_AUTO && 4ull * c.geom_words + 4ull * c.attr_words > li.budget) {
            /* over the budget: the brick dictionary's smaller geometry, where it is smaller */
            vx_compact_scene cdict = {0};
            vx_error derr = {0}; /* a dictionary past its limit: the layout in blocks stays */
            cd.bricks = VX_COMPACT_BRICKS_DICT;
            if (!vx_compact_build(&cd, s, &cdict, &derr) && cdict.geom_words < c.geom_words) {
                vx_compact_free(&c);
                c = cdict;
            } else {
                vx_compact_free(&cdict);
            }
        }
        if (!r) {
            note_compact_build(rs, &c, vx_time_now() - t0);
            r = upload_compact(rs, s, &c, desc, li.budget, max_depth, err);
        }
        if (r) {
            vx_render_scene_destroy(rs);
            return r;
        }
        smap_compact_state(rs, desc);
        rs->layout.bytes = vx_compact_gpu_bytes(rs->compact);
        rs->layout.attr_parts = vx__compact_gpu_attr_parts(rs->compact);
    }
    *out = rs;
    return VX_OK;
}

/* The reader's models into a copy of its graph: the whole scene, for the
 * plain layout (its node words are the models' own). */
static vx_result read_whole(vx_svo_model_reader* rd, const vx_allocator* a, vx_svo_scene* out, vx_error* err) {
    vx_result r = vx_svo_reader_copy_graph(rd, a, out, err);
    const vx_svo_scene* g = vx_svo_reader_scene(rd);
    for (;;) {
        uint32_t i = 0;
        vx_svo_model m;
        if (r || (r = vx_svo_reader_next(rd, &i, &m, err)) || i >= g->model_count) break;
        out->models[i] = m; /* in place of its declared fields (no arrays) */
    }
    if (!r) r = vx_svo_reader_finish(rd, err);
    if (!r) {
        memcpy(out->bounds_min, g->bounds_min, sizeof out->bounds_min);
        memcpy(out->bounds_max, g->bounds_max, sizeof out->bounds_max);
        for (uint32_t i = 0; i < g->model_count; i++) out->models[i].check = g->models[i].check;
    } else {
        vx_svo_scene_free(out);
    }
    return r;
}

/* AUTO's bricks for a layout c built from reader rd in blocks: over the
 * budget, the layout built again with the brick dictionary from a second pass
 * over the file (vx_svo_reader_rewind), kept where its geometry is smaller,
 * as create_ex keeps it. The host holds c, the second build's geometry (the
 * attributes move over from c: one copy) and its models in hand, not the scene. A dictionary past its limit keeps c (create_ex's
 * rule); any other failure of the second pass (the file cut or changed since
 * the first) is the caller's error. */
static vx_result auto_bricks_reader(vx_svo_model_reader* rd, const vx_render_scene_desc* desc, uint64_t budget,
                                    vx_compact_scene* c, uint32_t* passes, vx_error* err) {
    uint32_t bricks = desc ? desc->compact_bricks : VX_RENDER_BRICKS_AUTO;
    if (desc && desc->bricks_decided) return VX_OK; /* the caller made AUTO's choice (vx_render_compact_auto_bricks) */
    if (bricks != VX_RENDER_BRICKS_AUTO || c->brick_dict || 4ull * c->geom_words + 4ull * c->attr_words <= budget)
        return VX_OK;
    vx_result r = vx_svo_reader_rewind(rd, err);
    if (r) return r;
    *passes = 2;
    vx_compact_scene cdict = {0};
    /* the geometry only: the attributes (the same words in either form) move over from c, one copy on the host */
    bool move = !c->attr;
    vx_compact_desc cd = {.alloc = &c->alloc, .attr_regions = true, .bricks = VX_COMPACT_BRICKS_DICT, .attrs_from = move ? c : NULL};
    vx_error derr = {0};
    r = vx_compact_build_reader(&cd, rd, &cdict, &derr);
    if (r == VX_ERR_LIMIT) return VX_OK; /* the layout in blocks stays (nothing was moved) */
    if (r) {
        if (err) *err = derr;
        return r;
    }
    cdict.stats.geom_seconds += c->stats.geom_seconds; /* both passes' times, for -v */
    cdict.stats.attr_seconds += c->stats.attr_seconds;
    if (cdict.geom_words < c->geom_words) {
        vx_compact_free(c);
        *c = cdict;
        return VX_OK;
    }
    r = move ? vx_compact_move_attrs(c, &cdict, err) : VX_OK; /* the attributes back to the layout in blocks */
    vx_compact_free(&cdict);
    return r;
}

/* The render scene of compact layout c, built from reader rd whose graph is s
 * (c is freed whatever the result). AUTO's bricks as create_ex's: over the
 * budget, a second build with the brick dictionary from a second pass over
 * the file. Over the budget it is paged as create_ex pages it: the pages are
 * cut from the layout, not the models (the graph's declared fields and
 * cells' boxes are all they read of the models). */
static vx_result from_built(vx_gpu* gpu, vx_svo_model_reader* rd, const vx_svo_scene* s, const vx_render_scene_desc* desc,
                            const vx_render_layout_info* li, uint64_t range, uint32_t max_depth, vx_compact_scene* c,
                            double build_seconds, vx_render_scene** out, vx_error* err) {
    double t0 = vx_time_now();
    uint32_t passes = desc && desc->bricks_decided && desc->file_passes ? desc->file_passes : 1;
    vx_result r = auto_bricks_reader(rd, desc, li->budget, c, &passes, err);
    if (r) {
        vx_compact_free(c);
        return r;
    }
    if (passes > 1) build_seconds += vx_time_now() - t0; /* the second build's time too */
    double t1 = vx_time_now();
    vx_render_scene* rs = new_scene(gpu, s, li, range, max_depth);
    if (!rs) {
        vx_compact_free(c);
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory");
    }
    rs->smap_state = SMAP_NEVER;
    note_compact_build(rs, c, build_seconds);
    rs->layout.file_passes = passes;
    r = prepare_models(rs, s, false, err);
    if (!r) r = prepare_instances(rs, s, err);
    if (!r) r = upload_compact(rs, s, c, desc, li->budget, max_depth, err);
    else vx_compact_free(c);
    rs->layout.upload_seconds = vx_time_now() - t1; /* with the tables, as before */
    if (r) {
        vx_render_scene_destroy(rs);
        return r;
    }
    rs->layout.bytes = vx_compact_gpu_bytes(rs->compact);
    rs->layout.attr_parts = vx__compact_gpu_attr_parts(rs->compact);
    smap_compact_state(rs, desc);
    *out = rs;
    return VX_OK;
}

vx_result vx_render_scene_create_reader(vx_gpu* gpu, vx_svo_model_reader* rd, const vx_render_scene_desc* desc,
                                        vx_render_scene** out, vx_error* err) {
    if (!gpu || !rd || !out) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    const vx_svo_scene* s = vx_svo_reader_scene(rd);
    vx_render_layout_info li;
    uint32_t max_depth = 0;
    uint64_t range = 0;
    vx_result r = choose_layout(gpu, s, desc, &li, &max_depth, &range, err);
    if (r) return r;
    if (li.layout == VX_RENDER_LAYOUT_PLAIN) {
        vx_svo_scene whole;
        if ((r = read_whole(rd, &gpu->alloc, &whole, err))) return r;
        r = vx_render_scene_create_ex(gpu, &whole, desc, out, err);
        vx_svo_scene_free(&whole);
        return r;
    }
    if (desc && desc->host_budget) { /* the file source: the top and a cache of pages, not the layout */
        vx_compact_paged p;
        double t0 = vx_time_now();
        if ((r = vx_render_page_build_reader(rd, desc, &p, err))) return r;
        return vx_render_scene_create_paged(gpu, rd, &p, vx_time_now() - t0, desc, out, err);
    }
    /* the compact layout from the models in turn; the graph's bounds and cells' boxes are known after */
    vx_compact_scene c;
    uint32_t bricks = desc ? desc->compact_bricks : VX_RENDER_BRICKS_AUTO;
    vx_compact_desc cd = {.alloc = &gpu->alloc, .attr_regions = true,
                          .bricks = bricks == VX_RENDER_BRICKS_DICT ? VX_COMPACT_BRICKS_DICT : VX_COMPACT_BRICKS_INLINE};
    double t0 = vx_time_now();
    if ((r = vx_compact_build_reader(&cd, rd, &c, err))) return r;
    return from_built(gpu, rd, s, desc, &li, range, max_depth, &c, vx_time_now() - t0, out, err);
}

/* The page level upload_compact takes: desc's (or VX_RENDER_FRAME_LEVELS),
 * lowered below the drawn models' depth where that is shallower. */
static uint32_t page_level_for(const vx_svo_scene* s, const vx_render_scene_desc* desc) {
    uint32_t max_depth = 0;
    for (uint32_t i = 0; i < s->instance_count; i++) {
        if (!vx_svo_instance_drawn(s, i)) continue;
        uint32_t d = s->models[s->instances[i].model].depth;
        if (d > max_depth) max_depth = d;
    }
    uint32_t lp = desc && desc->page_level ? desc->page_level : VX_RENDER_FRAME_LEVELS;
    if (lp >= max_depth) lp = max_depth > 6 ? max_depth - 3 : 3;
    return lp;
}

vx_result vx_render_page_build_reader(vx_svo_model_reader* rd, const vx_render_scene_desc* desc, vx_compact_paged* out,
                                      vx_error* err) {
    if (!rd || !out) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    vx_compact_page_desc pd = {.page_level = page_level_for(vx_svo_reader_scene(rd), desc)};
    return vx_compact_page_build_reader(&pd, rd, out, err);
}

/* The file source's paged layout p onto the GPU for rs (p is taken): the
 * pool the budget less the top; unlike create_paged there is no whole
 * layout to fall back on where the top and the largest page exceed it. */
static vx_result upload_paged_file(vx_render_scene* rs, const vx_svo_scene* s, vx_compact_paged* p, uint64_t budget,
                                   uint64_t host_budget, vx_error* err) {
    uint64_t top = 4ull * p->top_words + 64ull * s->model_count + 1024 + 64 + 16ull * p->page_count;
    if (top >= budget || budget - top < 4ull * p->max_page_words + 4ull * (p->max_page_words / 64 + 16)) {
        vx_result r = vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET,
                              "the paged layout's top (%.3f MB) and its largest page (%.3f MB) do not fit the GPU budget "
                              "of %.3f MB: a larger budget or a lower page level",
                              top / 1e6, 4e-6 * p->max_page_words, budget / 1e6);
        vx_compact_paged_free(p);
        return r;
    }
    rs->layout.pages = p->page_count;
    rs->layout.page_level = p->page_level;
    rs->layout.compact_bytes = p->source_bytes;
    rs->layout.brick_dict = false;
    memcpy(rs->palette_used, p->palette_used, sizeof rs->palette_used);
    uint64_t pool = budget - top;
    vx_result r = vx_compact_gpu_create_paged_ex(rs, s, p, pool - pool / 128 - 8, host_budget, &rs->compact, err);
    vx_compact_paged_free(p); /* emptied when taken */
    return r;
}

/* The layout decision for a compact layout built from the reader (whole or paged): whatever AUTO would take is
 * compacted, so AUTO's depth limit and the budget's check apply; d is desc with the layout set to compact. */
static vx_result choose_compact(vx_gpu* gpu, const vx_svo_scene* s, const vx_render_scene_desc* desc,
                                vx_render_scene_desc* d, vx_render_layout_info* li, uint32_t* max_depth,
                                uint64_t* range, vx_error* err) {
    *d = desc ? *desc : (vx_render_scene_desc){0};
    d->layout = VX_RENDER_LAYOUT_COMPACT;
    return choose_layout(gpu, s, d, li, max_depth, range, err);
}

vx_result vx_render_scene_create_paged(vx_gpu* gpu, vx_svo_model_reader* rd, vx_compact_paged* p, double build_seconds,
                                       const vx_render_scene_desc* desc, vx_render_scene** out, vx_error* err) {
    if (!gpu || !rd || !p || !out) {
        if (p) vx_compact_paged_free(p);
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    }
    const vx_svo_scene* s = vx_svo_reader_scene(rd);
    vx_render_scene_desc d;
    vx_render_layout_info li;
    uint32_t max_depth = 0;
    uint64_t range = 0;
    vx_result r = choose_compact(gpu, s, desc, &d, &li, &max_depth, &range, err);
    if (!r && (p->reader != rd || p->model_count != s->model_count))
        r = vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "the paged layout was not built from this reader");
    if (r) {
        vx_compact_paged_free(p);
        return r;
    }
    double t1 = vx_time_now();
    vx_render_scene* rs = new_scene(gpu, s, &li, range, max_depth);
    if (!rs) {
        vx_compact_paged_free(p);
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory");
    }
    rs->smap_state = SMAP_NEVER;
    rs->layout.build_seconds = build_seconds;
    rs->layout.file_passes = 1;
    r = prepare_models(rs, s, false, err);
    if (!r) r = prepare_instances(rs, s, err);
    if (!r) r = upload_paged_file(rs, s, p, li.budget, d.host_budget, err);
    else vx_compact_paged_free(p);
    rs->layout.upload_seconds = vx_time_now() - t1;
    if (r) {
        vx_render_scene_destroy(rs);
        return r;
    }
    rs->layout.bytes = vx_compact_gpu_bytes(rs->compact);
    rs->layout.attr_parts = vx__compact_gpu_attr_parts(rs->compact);
    *out = rs;
    return VX_OK;
}

vx_result vx_render_compact_auto_bricks(vx_svo_model_reader* rd, const vx_render_scene_desc* desc, uint64_t budget,
                                        vx_compact_scene* c, uint32_t* passes, vx_error* err) {
    if (!rd || !c) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    uint32_t n = 1;
    vx_render_scene_desc d = desc ? *desc : (vx_render_scene_desc){0};
    d.bricks_decided = false;
    vx_result r = auto_bricks_reader(rd, &d, budget, c, &n, err);
    if (passes) *passes = n;
    return r;
}

uint64_t vx_render_scene_budget(const vx_gpu* gpu, const vx_render_scene_desc* desc) {
    return desc && desc->memory_budget ? desc->memory_budget : gpu ? default_budget(gpu) : 0;
}

vx_result vx_render_scene_choose_layout(vx_gpu* gpu, const vx_svo_scene* s, const vx_render_scene_desc* desc,
                                        vx_render_layout* out, vx_error* err) {
    if (!gpu || !s || !out) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    vx_render_layout_info li;
    uint32_t depth = 0;
    uint64_t range = 0;
    vx_result r = choose_layout(gpu, s, desc, &li, &depth, &range, err);
    if (!r) *out = li.layout;
    return r;
}

vx_result vx_render_scene_create_compact(vx_gpu* gpu, vx_svo_model_reader* rd, vx_compact_scene* c,
                                         double build_seconds, const vx_render_scene_desc* desc, vx_render_scene** out,
                                         vx_error* err) {
    if (!gpu || !rd || !c || !out) {
        if (c) vx_compact_free(c);
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    }
    const vx_svo_scene* s = vx_svo_reader_scene(rd);
    vx_render_scene_desc d;
    vx_render_layout_info li;
    uint32_t max_depth = 0;
    uint64_t range = 0;
    vx_result r = choose_compact(gpu, s, desc, &d, &li, &max_depth, &range, err);
    if (r) {
        vx_compact_free(c);
        return r;
    }
    return from_built(gpu, rd, s, &d, &li, range, max_depth, c, build_seconds, out, err);
}

void vx_render_scene_layout(const vx_render_scene* rs, vx_render_layout_info* out) {
    if (!out) return;
    memset(out, 0, sizeof *out);
    if (rs) *out = rs->layout;
}

/* The passes trace the whole compact layout (vx__render_scene_bind, trace_common.glsl COMPACT), not a paged one:
 * its pages move between frames, which only trace_compact.comp follows. */
static vx_result need_whole(const vx_render_scene* rs, vx_error* err) {
    if (rs->compact && rs->layout.attr_parts > 1)
        return vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET,
                       "the compact layout's attributes (%.1f MB) are in %u storage buffers (the device's range is "
                       "%.1f MB); only the single-shader frame (vx_render_frame) traces it",
                       rs->layout.compact_bytes / 1e6, rs->layout.attr_parts, rs->buffer_range / 1e6);
    if (!rs->compact || !rs->layout.pages) return VX_OK;
    return vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET,
                   "the scene is in the paged compact layout (%u pages: the compact layout's %.1f MB exceed the budget "
                   "of %.1f MB); only the single-shader frame (vx_render_frame) traces it",
                   rs->layout.pages, rs->layout.compact_bytes / 1e6, rs->layout.budget / 1e6);
}

/* Kernels that read the scene's node words or records directly (trace.comp's frames, LOD, model updates) cannot
 * trace a compact scene. */
static vx_result need_plain(const vx_render_scene* rs, vx_error* err) {
    if (!rs->compact) return VX_OK;
    return vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET,
                   "the scene is in the compact layout (its plain node words and records, %.1f MB, exceed the budget "
                   "of %.1f MB, or it was asked for): vx_render_frame and the passes trace it, not trace.comp, LOD "
                   "or model updates",
                   rs->layout.plain_bytes / 1e6, rs->layout.budget / 1e6);
}

void vx_render_scene_destroy(vx_render_scene* rs) {
    if (!rs) return;
    vx_gpu* g = rs->gpu;
    vx__gpu_submit_held(g);
    vkDeviceWaitIdle(g->device);
    vx_compact_gpu_destroy(rs->compact);
    vx__smap_free(g, &rs->smap);
    vx_render_sun_nodes_free(rs->smap_pre);
    destroy_instance_buffers(rs);
    vx__buffer* bufs[] = {&rs->beam,   &rs->dense_bits, &rs->hits,  &rs->pixels, &rs->models,
                          &rs->colors, &rs->nodes,      &rs->stage, &rs->grid};
    for (size_t i = 0; i < sizeof bufs / sizeof bufs[0]; i++) vx__buffer_destroy(g, bufs[i]);
    if (rs->refit_pool) vkDestroyDescriptorPool(g->device, rs->refit_pool, NULL);
    vx_bvh_free(&rs->bvh);
    vx_allocator a = rs->alloc;
    vx_free(&a, rs->inst);
    for (uint32_t i = 0; rs->top && i < rs->model_count; i++) vx_free(&a, rs->top[i]);
    vx_free(&a, rs->top);
    vx_free(&a, rs->grid_at);
    vx_free(&a, rs->grid_slot);
    vx_free(&a, rs->uni.held);
    vx_free(&a, rs->top_count);
    for (uint32_t i = 0; rs->df && i < rs->model_count; i++) vx_free(&a, rs->df[i].bits);
    vx_free(&a, rs->df);
    vx_free(&a, rs->gm);
    vx_free(&a, rs->wreg);
    vx_free(&a, rs->creg);
    vx_free(&a, rs->msize);
    vx_free(&a, rs->mcells);
    vx_free(&a, rs->scratch);
    vx_free(&a, rs->tables);
    vx_free(&a, rs->bvh_order);
    vx_free(&a, rs->bvh_level);
    vx_free(&a, rs);
}

/* Waits for recorded frames (vx__render_scene_bind_cmd) before the host
 * writes what they read: the mapped per-frame tables, the model records,
 * the buffers an update replaces. One queue does all of the scene's work. */
static void settle(vx_render_scene* rs) {
    if (!rs->recorded) return;
    vx__gpu_submit_held(rs->gpu); /* frames a display holds read these buffers too */
    vkQueueWaitIdle(rs->gpu->queue);
    rs->recorded = false;
}

/* The BVH's item order, when an in-place rebuild changed it (host writes:
 * no frame in flight reads it). */
static vx_result upload_items(vx_render_scene* rs, vx_error* err) {
    if (rs->order_dirty && rs->bvh_levels) {
        vx_result r = vx__buffer_upload(rs->gpu, &rs->order_buf, rs->bvh_order, (VkDeviceSize)rs->bvh.node_count * 4, err);
        if (r) return r;
    }
    rs->order_dirty = false;
    if (!rs->items_dirty) return VX_OK;
    rs->items_dirty = false;
    return vx__buffer_upload(rs->gpu, &rs->bvh_items, rs->bvh.items, (VkDeviceSize)rs->bvh.item_count * 4, err);
}

/* The models stay on the GPU; the instance tables and the BVH over them are
 * made again for the frame (host-side work proportional to the instances):
 * with `refit` the BVH keeps its shape where it can (vx_render_scene_set_frame:
 * moved instances), else it is built again (a model's new size: the
 * instances that overlap then tie as in a scene built from scratch, whose
 * tree is the same build's). */
static vx_result set_frame_tables(vx_render_scene* rs, const vx_svo_scene* s, uint32_t frame, bool refit,
                                 vx_error* err) {
    vx_svo_scene v;
    if (!rs || !s) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    if (!vx_svo_scene_frame(s, frame, &v))
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "no frame %u (the scene has %u)", frame, vx_svo_scene_frames(s));
    if (s->model_count != rs->model_count)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "frame %u: the scene has %u models, the GPU scene was made with %u",
                       frame, s->model_count, rs->model_count);
    uint32_t max_depth = 0;
    vx_result r = vx__check_scene(&v, err);
    if (r || (r = drawn_depth(rs->gpu, &v, &max_depth, err))) return r;
    vx_gpu* g = rs->gpu;
    /* the instances move: the map is built again once a frame after this one keeps them */
    rs->smap.valid = false;
    rs->smap_seen = false;
    if (drawn_count(&v) == rs->inst_count && rs->inst_count > 0 && rs->insts.buf) {
        /* the same number of instances drawn (moves, turns, a frame of an
         * animation): the tables and the BVH are made again on the host in
         * place of the old ones, no buffer changes and nothing waits for the
         * device. The instance tables and BVH nodes go to the GPU with every
         * frame's tables (relative to its camera) anyway; the BVH's item
         * order (n words) goes with the next frame's, or now when no frame
         * is in flight. A build over a few hundred instances takes well under
         * a millisecond (docs/PERFORMANCE.md, "Frames in flight"). */
        if (refit && rs->inst_count > 1 && rs->bvh.node_count && instance_refit(rs, &v, NULL) == VX_OK) {
            /* the BVH refit (its shape kept): the GPU refits its bounds with each recorded frame's tables */
            if (max_depth > rs->max_depth) rs->max_depth = max_depth;
            rs->precise = rs->max_depth > VX_RENDER_PRECISE_DEPTH;
            rs->shown = frame;
            rs->stats.instance_rebuilds++;
            rs->stats.instance_updates_in_place++;
            rs->stats.instance_refits++;
            vx_svo_scene_world_bounds(s, rs->lo, rs->hi);
            return VX_OK;
        }
        inst_host* old_inst = rs->inst;
        vx_bvh old_bvh = rs->bvh;
        memset(&rs->bvh, 0, sizeof rs->bvh);
        rs->bvh.alloc = &rs->alloc;
        rs->inst = NULL;
        if ((r = instance_tables(rs, &v, err)) || rs->bvh.node_count > rs->bvh_node_cap) {
            vx_free(&rs->alloc, rs->inst);
            vx_bvh_free(&rs->bvh);
            rs->inst = old_inst, rs->bvh = old_bvh, rs->inst_count = drawn_count(&v);
            vx_result lr = bvh_levels(rs, NULL); /* the old tree's */
            if (r || (r = lr)) return r;
        } else {
            vx_free(&rs->alloc, old_inst);
            vx_bvh_free(&old_bvh);
            if (max_depth > rs->max_depth) rs->max_depth = max_depth;
            rs->precise = rs->max_depth > VX_RENDER_PRECISE_DEPTH;
            rs->shown = frame;
            rs->stats.instance_rebuilds++;
            rs->stats.instance_updates_in_place++;
            vx_svo_scene_world_bounds(s, rs->lo, rs->hi);
            rs->items_dirty = true, rs->order_dirty = true;
            if (!rs->recorded) return upload_items(rs, err);
            return VX_OK;
        }
    }
    vx__gpu_submit_held(g);
    vkDeviceWaitIdle(g->device); /* the old tables may still be read */
    rs->recorded = false;
    destroy_instance_buffers(rs);
    vx_bvh_free(&rs->bvh);
    memset(&rs->bvh, 0, sizeof rs->bvh);
    rs->bvh.alloc = &rs->alloc;
    vx_free(&rs->alloc, rs->inst);
    rs->inst = NULL;
    rs->inst_count = 0;
    if (max_depth > rs->max_depth) rs->max_depth = max_depth;
    rs->precise = rs->max_depth > VX_RENDER_PRECISE_DEPTH;
    rs->shown = frame;
    rs->stats.instance_rebuilds++;
    /* the default framing: every frame's bounds, as at creation, of the scene as it is now (an instance edit moves them) */
    vx_svo_scene_world_bounds(s, rs->lo, rs->hi);
    return prepare_instances(rs, &v, err);
}

/* set_frame_tables, then whether the union grid holds for the instances it leaves (on an error too: it may
 * leave them changed) */
static vx_result set_frame(vx_render_scene* rs, const vx_svo_scene* s, uint32_t frame, bool refit, vx_error* err) {
    vx_result r = set_frame_tables(rs, s, frame, refit, err);
    if (rs) rs->uni.holds = union_matches(rs);
    return r;
}

vx_result vx_render_scene_set_frame(vx_render_scene* rs, const vx_svo_scene* s, uint32_t frame, vx_error* err) {
    return set_frame(rs, s, frame, true, err);
}

void vx_render_scene_get_stats(const vx_render_scene* rs, vx_render_scene_stats* out) {
    memset(out, 0, sizeof *out);
    if (rs) *out = rs->stats;
}

/* ---- incremental model updates (an editor's appends) ------------------------------------ */

/* Room for `need` units of model mi's region in arena a: where the region
 * goes (it moves behind the tail when it is not the tail and does not fit)
 * and the buffer's capacity after (more than a->cap: a new buffer). */
typedef struct room {
    uint32_t off;
    bool moved;
    uint64_t cap;
    uint32_t used; /* units of the old buffer a new one copies */
} room;

static vx_result plan_room(const arena* a, const region* reg, uint32_t mi, uint32_t need, uint32_t valid, uint64_t limit,
                           const char* what, room* p, vx_error* err) {
    const region* r = &reg[mi];
    const region* t = &reg[a->tail];
    *p = (room){.off = r->off, .cap = a->cap, .used = mi == a->tail ? r->off + valid : t->off + t->have};
    if (need <= r->cap) return VX_OK;
    if (mi != a->tail) p->moved = true, p->off = t->off + t->have;
    uint64_t end = (uint64_t)p->off + need;
    if (end > a->cap) {
        if (end > limit)
            return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "model %u needs %llu %s in the scene's buffer; the device allows %llu",
                           mi, (unsigned long long)end, what, (unsigned long long)limit);
        p->cap = with_headroom(end, limit);
    }
    return VX_OK;
}

/* Records the copies that make room: the old buffer's used part into the
 * new one, the region's valid units to its new place. */
static void record_room(vx_gpu* g, const vx__buffer* old, const vx__buffer* nb, const region* r, const room* p,
                        uint32_t valid) {
    const vx__buffer* dst = nb->buf ? nb : old;
    if (nb->buf && p->used) {
        VkBufferCopy c = {.srcOffset = 0, .dstOffset = 0, .size = (VkDeviceSize)p->used * 4};
        vkCmdCopyBuffer(g->cmd, old->buf, nb->buf, 1, &c);
    }
    if (p->moved && valid) {
        VkBufferCopy c = {.srcOffset = (VkDeviceSize)r->off * 4, .dstOffset = (VkDeviceSize)p->off * 4,
                          .size = (VkDeviceSize)valid * 4};
        vkCmdCopyBuffer(g->cmd, old->buf, dst->buf, 1, &c);
    }
}

/* After the update: the arena's bookkeeping for model mi's region. */
static void commit_room(arena* a, region* reg, uint32_t mi, const room* p, uint32_t have) {
    if (p->moved) {
        region* t = &reg[a->tail];
        t->cap = p->off - t->off; /* the old tail keeps what it holds */
        reg[mi].off = p->off;
        a->tail = mi;
    }
    a->cap = (uint32_t)p->cap;
    if (a->tail == mi) reg[mi].cap = a->cap - reg[mi].off;
    reg[mi].have = have;
}

/* rs->stage (the update's host-visible staging buffer) at least `bytes` long: made again, twice the size, where
 * shorter. Its contents are not kept. */
static vx_result stage_room(vx_render_scene* rs, VkDeviceSize bytes, vx_error* err) {
    if (bytes <= rs->stage.size) return VX_OK;
    vx__buffer_destroy(rs->gpu, &rs->stage);
    vx_result r = vx__buffer_create(rs->gpu, bytes * 2, 0, true, "update staging", &rs->stage, err);
    if (r) return r;
    if (!rs->stage.map) {
        vx__buffer_destroy(rs->gpu, &rs->stage);
        return vx_fail(err, VX_ERR_GPU, VX_NO_OFFSET, "staging buffer is not host visible");
    }
    return VX_OK;
}

/* An edited model's grid made again (vx_render_scene_update_model, after its words, its cells' box and the
 * instances), where the grid it had took at most REGRID_WORDS words: a stroke keeps the grid walk (on the H100
 * 1.3-3x the rays/s of the octree walk on the .vox scenes, issue 21) for one build of the grid. On dev (one
 * core, `view_bench --stroke FILE 30 4 on`) a stroke's update took 0.42 ms on eph_monu1 and 0.89 ms on
 * eph_dragon (0.05 MiB grids; 0.04-0.07 ms without grids) and 3.2 ms on the 256^3 terrain (0.38 MiB), so
 * about 9 ms at the limit. A larger grid stays dropped (the model walks its octree), as before this rule.
 * The same cube rule as prepare_grids; the grid goes where the old one was where it fits, else after the grids
 * in use (rs->grid grows; the old place stays unused), within the scene's grid budget. VX_OK without a
 * grid where the model has none now (empty, too deep, past the budget, out of host or device memory for it: the
 * octree walk, as prepare_grids leaves such a model); an error only where the GPU fails a copy or an upload.
 * *stale: the GPU's table word for mi still names the dropped grid; cleared where the new grid's is written. */
enum { REGRID_WORDS = 1u << 18 };
static vx_result regrid(vx_render_scene* rs, const vx_svo_scene* s, uint32_t mi, bool* stale, vx_error* err) {
    const vx_svo_model* m = &s->models[mi];
    struct grid_slot* sl = &rs->grid_slot[mi];
    if (!sl->words || sl->words > REGRID_WORDS || m->root == VX_SVO_ROOT_EMPTY || m->depth > VX_RENDER_GRID_DEPTH ||
        (m->node_count && !m->nodes))
        return VX_OK;
    const uint32_t* cb = &rs->mcells[6 * mi];
    vx__grid_words out = {0};
    uint32_t top = 0, rec = 0;
    uint64_t addr = sl->addr;
    bool placed = false, at_end = false;
    for (int k = 0; k < 2 && !placed; k++) {
        at_end = k == 1;
        if (at_end) addr = rs->grid_end;
        out.n = 0;
        vx_error e = {0};
        if (!vx__grid_words_grow(&rs->alloc, &out, 4)) break;
        grid_header(cb, out.w);
        out.n = 4;
        if (vx__grid_model(&rs->alloc, m, rs->grid_cube ? cb : NULL, addr, NULL, &out, &top, &rec, &e)) break;
        out.w[3] = rec; /* the header's word 3: its bricks' record key */
        placed = at_end ? (addr + out.n) * 4 <= rs->grid_budget : out.n <= sl->words;
    }
    vx_result r = VX_OK;
    vx_gpu* g = rs->gpu;
    /* a grid that outgrew its place gets a quarter more room at the end, for the next strokes' */
    uint64_t end = addr + out.n, room = at_end ? end + out.n / 4 + 64 : end;
    if (room * 4 > rs->grid_budget) room = end;
    vx__buffer nb = {0}; /* the grown buffer, where the grid does not fit the one in use */
    if (placed && room * 4 > rs->grid.size) {
        vx_error e = {0};
        if (vx__buffer_create(g, with_headroom(room, rs->grid_budget / 4) * 4, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, false,
                              "grid", &nb, &e))
            placed = false;
    }
    vx__buffer* gb = nb.buf ? &nb : &rs->grid;
    uint32_t a32 = (uint32_t)addr;
    VkDeviceSize bytes = (VkDeviceSize)out.n * 4;
    /* one submission (a device-local buffer): the words in use copied into a grown buffer, the grid's words from
     * the update's staging buffer and its table word. Before, three staged uploads (each a staging buffer made
     * and freed, a submission and a wait) took about 2 ms a stroke on the H100 (PERFORMANCE.md, stop 86) */
    bool staged = placed && (!gb->map || nb.buf);
    if (staged && !gb->map && (r = stage_room(rs, bytes, err))) placed = false;
    if (staged && placed && !(r = vx__cmd_begin(g, err))) {
        VkMemoryBarrier mb = {.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER,
                              .srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT,
                              .dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_TRANSFER_WRITE_BIT};
        if (nb.buf) {
            VkBufferCopy c = {.srcOffset = 0, .dstOffset = 0, .size = (VkDeviceSize)rs->grid_end * 4};
            if (c.size) vkCmdCopyBuffer(g->cmd, rs->grid.buf, nb.buf, 1, &c);
            VkMemoryBarrier tb = {.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER,
                                  .srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT,
                                  .dstAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT};
            vkCmdPipelineBarrier(g->cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 1, &tb, 0,
                                 NULL, 0, NULL);
        }
        if (!gb->map) {
            memcpy(rs->stage.map, out.w, bytes);
            VkBufferCopy c = {.srcOffset = 0, .dstOffset = (VkDeviceSize)addr * 4, .size = bytes};
            vkCmdCopyBuffer(g->cmd, rs->stage.buf, gb->buf, 1, &c);
            vkCmdUpdateBuffer(g->cmd, gb->buf, (VkDeviceSize)mi * 4, 4, &a32);
        }
        vkCmdPipelineBarrier(g->cmd, VK_PIPELINE_STAGE_TRANSFER_BIT,
                             VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 1, &mb, 0, NULL,
                             0, NULL);
        r = vx__cmd_submit_wait(g, err);
    }
    if (r) placed = false;
    if (placed && gb->map) { /* mapped (lavapipe, resizable BAR): written in place, no frame is in flight */
        memcpy((uint32_t*)gb->map + addr, out.w, bytes);
        memcpy((uint32_t*)gb->map + mi, &a32, 4);
    }
    if (placed && nb.buf) vx__buffer_destroy(g, &rs->grid), rs->grid = nb, nb = (vx__buffer){0};
    vx__buffer_destroy(g, &nb);
    if (placed) {
        rs->grid_at[mi] = a32;
        *stale = false; /* the GPU's table word is the new grid's */
        sl->addr = a32, sl->top = top;
        if (at_end) sl->words = (uint32_t)(room - addr), rs->grid_end = room;
        rs->layout.grid_bytes = rs->grid_end * 4;
        rs->stats.grids_rebuilt++;
    }
    vx_free(&rs->alloc, out.w);
    grid_bits(rs, s);
    return r;
}

/* vx_render_scene_update_model's work; *stale set where the model's grid was dropped on the host and the GPU's
 * table word still names it (written by the next submission: the update's, regrid's, else the caller's) */
static vx_result update_model(vx_render_scene* rs, const vx_svo_scene* s, uint32_t mi, uint32_t words_from,
                              uint32_t records_from, bool* stale, vx_error* err) {
    if (s->model_count != rs->model_count || mi >= s->model_count)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "model %u: the scene has %u models, the GPU scene was made with %u",
                       mi, s->model_count, rs->model_count);
    vx_result lr = need_plain(rs, err);
    if (lr) return lr;
    const vx_svo_model* m = &s->models[mi];
    vx_gpu* g = rs->gpu;
    if (m->depth > VX_RENDER_MAX_DEPTH)
        return vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET, "model %u has %u octree levels; the tracer supports at most %u",
                       mi, m->depth, VX_RENDER_MAX_DEPTH);
    if (m->root != VX_SVO_ROOT_LEAF && m->root != VX_SVO_ROOT_EMPTY && m->root >= m->node_count)
        return vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "model %u: root %u outside %u node words", mi, m->root,
                       m->node_count);
    if (m->node_count && !m->nodes)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "model %u: %u node words and no array", mi, m->node_count);
    settle(rs); /* the model record and the appended words' place may be read by a frame in flight */
    rs->uni.insts = 0; /* the union grid's bricks are the models' as made: the BVH from now on */
    if (rs->grid_at && rs->grid_at[mi] != UINT32_MAX) {
        /* the edited model walks its octree until its grid is made again at the end (regrid, where that is
         * cheap; else from now on): its old grid does not hold the new cells. Models without one need no upload */
        uint32_t none = UINT32_MAX;
        if (rs->grid.map) memcpy((uint32_t*)rs->grid.map + mi, &none, 4); /* settled: no frame reads it */
        else *stale = true;
        rs->grid_at[mi] = UINT32_MAX;
        rs->grid_top &= 3u | 32u | 64u; /* not every model has a grid now: the octree walk is compiled in (and
                                         * the root level taken from each grid's depth: its bits 2-3 off) */
    }
    /* the shadow map's node list is the models' as made: an edited scene has
     * no map (listing the nodes again would cost a stroke tens of ms on a
     * large model) */
    vx__smap_free(g, &rs->smap);
    vx_render_sun_nodes_free(rs->smap_pre);
    rs->smap_pre = NULL;
    rs->smap_state = SMAP_NEVER;
    vx_svo_scene v;
    if (!vx_svo_scene_frame(s, rs->shown, &v)) vx_svo_scene_frame(s, 0, &v);
    uint32_t depth = 0;
    vx_result r = vx__check_scene(&v, err);
    if (r || (r = drawn_depth(g, &v, &depth, err))) return r;
    uint64_t limit = g->props.limits.maxStorageBufferRange / 4;
    region *wr = &rs->wreg[mi], *cr = &rs->creg[mi];
    uint32_t nc = m->node_count, ac = m->attrs ? m->attr_count : 0;
    /* valid: units the GPU holds that stay; [valid, count) is uploaded */
    uint32_t wvalid = words_from < wr->have ? words_from : wr->have, cvalid = records_from < cr->have ? records_from : cr->have;
    /* the descriptors in the GPU form after the update (dform): the bits of
     * the words that stay, then those the walk from the new root reaches
     * through clear ones; a word that stays but is reached clear (a block
     * no earlier root reached, shared by an edit) is uploaded again */
    dform nf = {0};
    {
        nf.cap = ((size_t)(nc > wr->have ? nc : wr->have) + 7) / 8;
        if (!(nf.bits = vx_calloc(&rs->alloc, nf.cap ? nf.cap : 1, 1)))
            return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for model %u's descriptor bits", mi);
        const dform* of = &rs->df[mi];
        uint32_t keep = wvalid;
        if (of->bits) memcpy(nf.bits, of->bits, keep / 8 < of->cap ? keep / 8 : of->cap);
        for (uint32_t i = keep & ~7u; i < keep; i++)
            if (of->bits && dform_get(of->bits, i)) dform_set(nf.bits, i);
        uint32_t low, bad = 0;
        if (m->root < VX_SVO_ROOT_LEAF && !dform_walk(m->nodes, nc, m->root, m->depth, nf.bits, NULL, &low, &bad)) {
            vx_free(&rs->alloc, nf.bits);
            return vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET,
                           "model %u: the descriptor at word %u points outside its %u node words or below level 1", mi,
                           bad, nc);
        }
        /* the file's form (gpu.h's nodes_file): the words the GPU holds are the file's, none goes up again */
        if (low < wvalid && !g->nodes_file) wvalid = low;
    }
    const uint8_t* put_bits = g->nodes_file ? NULL : nf.bits; /* dform_put: NULL, the words as they are */
    uint32_t whave = nc > wvalid ? nc : wvalid, chave = ac > cvalid ? ac : cvalid;
    uint32_t wn = nc > wvalid ? nc - wvalid : 0, cn = ac > cvalid ? ac - cvalid : 0;
    room wp, cp;
    vx__buffer nwb = {0}, ncb = {0};
    uint32_t* col = NULL;
    if ((r = plan_room(&rs->wa, rs->wreg, mi, whave, wvalid, limit, "node words", &wp, err)) ||
        (r = plan_room(&rs->ca, rs->creg, mi, chave, cvalid, limit, "colours", &cp, err)))
        goto fail;
    if (wp.cap > rs->wa.cap &&
        (r = vx__buffer_create(g, wp.cap * 4, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, false, "nodes", &nwb, err)))
        return r;
    if (cp.cap > rs->ca.cap &&
        (r = vx__buffer_create(g, cp.cap * 4, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, false, "colors", &ncb, err)))
        goto fail;
    col = vx_alloc(&rs->alloc, (size_t)(cn ? cn : 1) * 4);
    if (!col) {
        r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %u colours", cn);
        goto fail;
    }
    for (uint32_t a = 0; a < cn; a++) col[a] = vx_svo_attr_rgba(s, m, cvalid + a);
    vx__buffer *wt = nwb.buf ? &nwb : &rs->nodes, *ct = ncb.buf ? &ncb : &rs->colors;
    /* staged where the target is not mapped (a discrete GPU's device-local memory) */
    VkDeviceSize wst = wt->map ? 0 : (VkDeviceSize)wn * 4, cst = ct->map ? 0 : (VkDeviceSize)cn * 4;
    if ((r = stage_room(rs, wst + cst, err))) goto fail;
    vx__gpu_model gm = rs->gm[mi];
    gm.node_off = wp.off, gm.color_off = cp.off, gm.depth = m->depth, gm.root = m->root, gm.root_attr = m->root_attr;
    /* the words below wvalid stay: the FAR bit is kept and ORed with the new ones' */
    gm.flags &= VX__MODEL_HAS_COLOR | VX__MODEL_FAR, gm.rebase = 0, gm.box = vx__render_model_box(m);
    if (words_may_far(m, wvalid)) gm.flags |= VX__MODEL_FAR;
    deep_model(m, &gm);
    bool cmd = nwb.buf || ncb.buf || wp.moved || cp.moved || wst || cst || !rs->models.map;
    if (cmd) {
        if (wst) dform_put(rs->stage.map, m->nodes, wvalid, wn, put_bits);
        if (cst) memcpy((uint8_t*)rs->stage.map + wst, col, cst);
        if ((r = vx__cmd_begin(g, err))) goto fail;
        record_room(g, &rs->nodes, &nwb, wr, &wp, wvalid);
        record_room(g, &rs->colors, &ncb, cr, &cp, cvalid);
        if (wst) {
            VkBufferCopy c = {.srcOffset = 0, .dstOffset = ((VkDeviceSize)wp.off + wvalid) * 4, .size = wst};
            vkCmdCopyBuffer(g->cmd, rs->stage.buf, wt->buf, 1, &c);
        }
        if (cst) {
            VkBufferCopy c = {.srcOffset = wst, .dstOffset = ((VkDeviceSize)cp.off + cvalid) * 4, .size = cst};
            vkCmdCopyBuffer(g->cmd, rs->stage.buf, ct->buf, 1, &c);
        }
        if (!rs->models.map) vkCmdUpdateBuffer(g->cmd, rs->models.buf, (VkDeviceSize)mi * sizeof gm, sizeof gm, &gm);
        const uint32_t none = UINT32_MAX;
        if (*stale) vkCmdUpdateBuffer(g->cmd, rs->grid.buf, (VkDeviceSize)mi * 4, 4, &none);
        VkMemoryBarrier mb = {.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER,
                              .srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT,
                              .dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_TRANSFER_READ_BIT};
        vkCmdPipelineBarrier(g->cmd, VK_PIPELINE_STAGE_TRANSFER_BIT,
                             VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 1, &mb, 0, NULL,
                             0, NULL);
        if ((r = vx__cmd_submit_wait(g, err))) goto fail;
        *stale = false;
    }
    /* mapped targets (lavapipe, resizable BAR): written in place */
    if (wn && !wst) dform_put((uint32_t*)wt->map + wp.off + wvalid, m->nodes, wvalid, wn, put_bits);
    if (cn && !cst) memcpy((uint32_t*)ct->map + cp.off + cvalid, col, (size_t)cn * 4);
    if (rs->models.map) memcpy((vx__gpu_model*)rs->models.map + mi, &gm, sizeof gm);
    vx_free(&rs->alloc, col);
    vx_free(&rs->alloc, rs->df[mi].bits);
    rs->df[mi] = nf;
    if (nwb.buf) vx__buffer_destroy(g, &rs->nodes), rs->nodes = nwb;
    if (ncb.buf) vx__buffer_destroy(g, &rs->colors), rs->colors = ncb;
    rs->stats.node_words_uploaded += wn;
    rs->stats.records_uploaded += cn;
    rs->stats.model_updates++;
    commit_room(&rs->wa, rs->wreg, mi, &wp, whave);
    commit_room(&rs->ca, rs->creg, mi, &cp, chave);
    rs->gm[mi] = gm;
    /* the words below wvalid stay on the GPU and in m->nodes (the caller's
     * model holds them all), so the list is made from m's words */
    top_list(rs, mi, m->nodes, nc, m->root);
    rs->deep = 0, rs->far = false;
    for (uint32_t i = 0; i < rs->model_count; i++)
        rs->deep = deep_level(rs->deep, &rs->gm[i]), rs->far |= (rs->gm[i].flags & VX__MODEL_FAR) != 0;
    if (depth > rs->max_depth) rs->max_depth = depth;
    rs->precise = rs->max_depth > VX_RENDER_PRECISE_DEPTH;
    /* a new size or an emptied (or no longer empty) model changes instance
     * boxes and which instances draw: the instance tables and the BVH */
    uint32_t* ms = &rs->msize[4 * mi];
    bool draws = m->root != VX_SVO_ROOT_EMPTY;
    /* and so do new cells outside the model's cells' box (the instances'
     * boxes); cells removed leave the box as it was (still around every cell) */
    uint32_t cb[6], *mc = &rs->mcells[6 * mi];
    vx_svo_model_cell_box(m, cb, cb + 3);
    bool grown = false;
    for (int k = 0; k < 3; k++) grown |= cb[k] < mc[k] || cb[3 + k] > mc[3 + k];
    if (ms[0] != m->size[0] || ms[1] != m->size[1] || ms[2] != m->size[2] || ms[3] != draws || (draws && grown)) {
        memcpy(ms, m->size, 3 * sizeof m->size[0]);
        memcpy(mc, cb, sizeof cb);
        ms[3] = draws;
        vx_svo_scene_world_bounds(s, rs->lo, rs->hi);
        uint32_t f = rs->shown < vx_svo_scene_frames(s) ? rs->shown : 0;
        if ((r = set_frame(rs, s, f, false, err))) return r;
    }
    /* its grid made again (dropped above) where that is cheap */
    if (rs->grid_at && (r = regrid(rs, s, mi, stale, err))) return r;
    return VX_OK;
fail:
    vx__buffer_destroy(g, &nwb);
    vx__buffer_destroy(g, &ncb);
    vx_free(&rs->alloc, col);
    vx_free(&rs->alloc, nf.bits);
    return r;
}

vx_result vx_render_scene_update_model(vx_render_scene* rs, const vx_svo_scene* s, uint32_t mi, uint32_t words_from,
                                       uint32_t records_from, vx_error* err) {
    if (!rs || !s) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    bool stale = false;
    vx_result r = update_model(rs, s, mi, words_from, records_from, &stale, err);
    /* the dropped grid's table word, where no submission wrote it (an error on the way, or no upload was needed
     * and no grid was made again): the model walks its octree */
    if (stale) {
        const uint32_t none = UINT32_MAX;
        vx_error e = {0};
        vx_result wr = vx__buffer_upload_at(rs->gpu, &rs->grid, (VkDeviceSize)mi * 4, &none, 4, r ? &e : err);
        if (!r) r = wr;
    }
    return r;
}

double vx_render_scene_bvh_seconds(const vx_render_scene* rs) { return rs ? rs->bvh_seconds : 0; }

static bool use_precise(const vx_render_scene* rs) { return rs->force_precise < 0 ? rs->precise : rs->force_precise > 0; }

bool vx_render_scene_precise(const vx_render_scene* rs) { return rs && use_precise(rs); }

bool vx__render_scene_far(const vx_render_scene* rs) { return rs && rs->far; }

uint32_t vx__render_scene_deep(const vx_render_scene* rs) { return rs && !use_precise(rs) ? rs->deep : 0; }

void vx__render_scene_trace_kernel(vx_render_scene* rs, const uint32_t* spirv, size_t bytes, const uint32_t* beam_spirv,
                                   size_t beam_bytes, uint32_t tag) {
    if (!rs) return;
    rs->alt_spv = spirv && bytes ? spirv : NULL, rs->alt_size = bytes, rs->alt_tag = tag;
    rs->alt_beam = beam_spirv && beam_bytes ? beam_spirv : NULL, rs->alt_beam_size = beam_bytes;
}

void vx__render_scene_trace_variant(vx_render_scene* rs, int cull) {
    if (!rs) return;
    rs->cull = cull < 0 ? -1 : cull > 0;
}

void vx__render_scene_trace_path(vx_render_scene* rs, int path) {
    if (rs) rs->path = path < 0 ? -1 : path > 0;
}

uint32_t vx__render_scene_grid_spec(vx_render_scene* rs, const vx__frame* f, vx__buffer** buf) {
    /* without LOD: a coarse hit is its node's cube, which the grids do not hold */
    uint32_t grid = rs && rs->grid_at && !f->lod && rs->grid_on != 0 ? rs->grid_top : 0;
    *buf = grid ? &rs->grid : NULL;
    return grid;
}

void vx__render_scene_grid(vx_render_scene* rs, int on) {
    if (rs) rs->grid_on = on < 0 ? -1 : on > 0;
}

uint32_t vx__render_scene_grid_models(const vx_render_scene* rs) {
    uint32_t n = 0;
    for (uint32_t i = 0; rs && rs->grid_at && i < rs->model_count; i++) n += rs->grid_at[i] != UINT32_MAX;
    return n;
}

uint32_t vx__render_scene_grid_union(vx_render_scene* rs, int on) {
    if (!rs) return 0;
    rs->uni.on = on < 0 ? -1 : on > 0;
    return rs->uni.insts;
}

/* Whether the trace kernel starts primary rays below the root (its
 * PATH_START constant): off on CPU devices by default, where lavapipe ran
 * the start's code masked for every ray, 0.45-0.65 of the rays per CPU
 * second (issue 21's fourteenth sitting) */
static bool path_on(const vx_render_scene* rs) {
    return rs->path < 0 ? !vx_gpu_is_cpu(rs->gpu) : rs->path > 0;
}

bool vx__render_scene_path_on(const vx_render_scene* rs) { return rs && path_on(rs); }

bool vx__render_scene_traced(const vx_render_scene* rs, uint64_t* pixels) {
    if (!rs || !rs->last_cull) return false;
    *pixels = rs->last_traced;
    return true;
}

void vx__render_scene_force_precise(vx_render_scene* rs, int precise) {
    if (rs) rs->force_precise = precise < 0 ? -1 : precise > 0;
}

/* Per-frame tables relative to the reference point R, computed in double,
 * into gi, pi (NULL: not written) and bn. */
static void frame_tables(const vx_render_scene* rs, const vx__frame* f, vx__gpu_inst* gi, vx__gpu_inst_precise* pi,
                         vx_bvh_node* bn) {
    for (uint32_t i = 0; i < rs->inst_count; i++) {
        const inst_host* h = &rs->inst[i];
        for (int r = 0; r < 3; r++) {
            const double* row = &h->inv[4 * r];
            double w = row[0] * f->ref[0] + row[1] * f->ref[1] + row[2] * f->ref[2] + row[3];
            for (int c = 0; c < 3; c++) gi[i].r[r][c] = (float)row[c];
            gi[i].r[r][3] = (float)w;
            gi[i].lo[r] = (float)(w - (double)(float)w);
            if (!pi) continue;
            for (int c = 0; c < 3; c++) pi[i].r[r][c] = row[c];
            pi[i].r[r][3] = w;
        }
        gi[i].model = h->model;
        gi[i].cell = h->cell;
        gi[i].id = h->id;
        gi[i].pad = 0;
        gi[i].lo[3] = 0;
    }
    for (uint32_t i = 0; bn && i < rs->bvh.node_count; i++) {
        const vx_bvh_node* s = &rs->bvh.nodes[i];
        bn[i] = *s;
        for (int k = 0; k < 3; k++) {
            double a = (double)s->lo[k] - f->ref[k], b = (double)s->hi[k] - f->ref[k];
            float fa = (float)a, fb = (float)b;
            if ((double)fa > a) fa = nextafterf(fa, -INFINITY);
            if ((double)fb < b) fb = nextafterf(fb, INFINITY);
            bn[i].lo[k] = fa, bn[i].hi[k] = fb;
        }
    }
}

void vx__render_scene_forget_tables(vx_render_scene* rs) {
    if (!rs) return;
    /* and the BVH's shape, which those tables may have carried (whole nodes): the next frame writes it */
    rs->tables_known = false;
    rs->shape_dirty = true;
}

static vx_result write_frame_tables(vx_render_scene* rs, const vx__frame* f, vx_error* err) {
    settle(rs);
    rs->tables_known = false; /* the host writes them (and the frame block after this) */
    frame_tables(rs, f, rs->insts.map, rs->pinsts.map, rs->bvh_nodes.map);
    rs->shape_dirty = false; /* whole nodes */
    return upload_items(rs, err);
}

/* The sun map's origin relative to a kernel's reference point ref (xyz) and
 * its margin (w): the kernel's coordinates are relative to ref, so its
 * rounding grows with the origin's distance from it (smap_lookup.glsl's org). */
static void smap_origin(const vx_render_scene* rs, const double ref[3], float org[4]) {
    double o2 = 0;
    for (int k = 0; k < 3; k++) {
        double d = rs->smap.origin[k] - ref[k];
        org[k] = (float)d;
        o2 += d * d;
    }
    org[3] = (float)(rs->smap.margin + ldexp(sqrt(o2), -13));
}

static void fill_gpu_frame(const vx_render_scene* rs, const vx__frame* f, vx__gpu_frame* gf) {
    memset(gf, 0, sizeof *gf);
    for (int k = 0; k < 3; k++) {
        gf->fwd[k] = (float)f->fwd[k];
        gf->rx[k] = (float)f->rx[k];
        gf->uy[k] = (float)f->uy[k];
        gf->light[k] = (float)f->light[k];
        gf->pfwd[k] = f->fwd[k];
        gf->prx[k] = f->rx[k];
        gf->puy[k] = f->uy[k];
    }
    gf->pfwd[3] = f->t_start;
    gf->fwd[3] = (float)f->t_start;
    gf->rx[3] = f->ortho ? 1.0f : 0.0f;
    /* LOD cone: footprint(t) = misc.x + uy.w * t (t from the reference plane) */
    if (f->ortho) {
        gf->misc[0] = (float)(f->pixel_size * f->lod_pixels);
        gf->uy[3] = 0;
    } else {
        gf->misc[0] = (float)(f->t_start * f->pixel_angle * f->lod_pixels);
        gf->uy[3] = (float)(f->pixel_angle * f->lod_pixels);
    }
    gf->misc[1] = (float)f->lod_pixels;
    gf->light[3] = (float)f->ambient;
    gf->dims[0] = f->width, gf->dims[1] = f->height, gf->dims[2] = f->spp, gf->dims[3] = rs->inst_count;
    /* the sun's depth map where the scene holds one for this light: its
     * origin relative to the reference, margin, side and instance entries
     * (smap_lookup.glsl's smap_tmax, trace.comp and the direct pass) */
    if (rs->smap.valid && !memcmp(gf->light, rs->smap.light, sizeof rs->smap.light)) {
        smap_origin(rs, f->ref, gf->grid_lo);
        gf->dims2[0] = rs->smap.side;
        gf->dims2[1] = rs->smap.insts_built;
    }
}

/* Whether a colour frame with f's light clips its shadow rays (*use; allow:
 * the frame asks for the map). The map is built for a light that the frame
 * before had too (with the same instances): a light or an animation that
 * changes every frame would pay a build per frame and gain one frame's
 * shadow rays (docs/PERFORMANCE.md, issue 21's eighth sitting). */
static vx_result smap_build(vx_render_scene* rs, const float lf[3], uint32_t max_side, vx_error* err);
static vx_result smap_ensure(vx_render_scene* rs, const vx__frame* f, bool allow, bool* use, vx_error* err) {
    float lf[3] = {(float)f->light[0], (float)f->light[1], (float)f->light[2]};
    bool again = rs->smap_seen && !memcmp(lf, rs->smap_seen_light, sizeof lf);
    rs->smap_seen = true;
    memcpy(rs->smap_seen_light, lf, sizeof lf);
    *use = false;
    if (!allow) return VX_OK;
    if (rs->smap.valid && !memcmp(lf, rs->smap.light, sizeof lf)) {
        *use = true;
        return VX_OK;
    }
    if (!again) return VX_OK;
    vx_result r = smap_build(rs, lf, 0, err);
    *use = !r && rs->smap.valid;
    return r;
}

/* Builds the map for light lf and the instances as they are (the node list
 * first where none is made yet). */
static vx_result smap_build(vx_render_scene* rs, const float lf[3], uint32_t max_side, vx_error* err) {
    settle(rs);
    vx_result r = VX_OK;
    if (rs->smap_state == SMAP_LATER && (r = smap_list_gpu(rs, max_side, err))) return r;
    if (!rs->smap.side) return VX_OK;
    uint32_t n = rs->inst_count;
    double(*world)[12] = vx_calloc(&rs->alloc, n ? n : 1, sizeof *world);
    uint32_t* model = vx_calloc(&rs->alloc, n ? n : 1, sizeof *model);
    if (!world || !model) r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory");
    for (uint32_t i = 0; !r && i < n; i++) {
        model[i] = rs->inst[i].model;
        vx__affine_inverse(rs->inst[i].inv, world[i]);
    }
    if (!r) r = vx__smap_build(rs->gpu, &rs->smap, lf, (const double(*)[12])world, model, n, rs->lo, rs->hi, err);
    vx_free(&rs->alloc, world);
    vx_free(&rs->alloc, model);
    return r;
}

/* Whether a map can still be built: its list is to be made, or made with a side. */
static bool smap_possible(const vx_render_scene* rs) {
    return rs->smap_state == SMAP_LATER || (rs->smap_state == SMAP_MADE && rs->smap.side);
}

/* The map's bindings, side and instance entries (not its origin) into *out. */
static void sun_map_out(vx_render_scene* rs, vx__sun_map* out) {
    out->side = rs->smap.side, out->insts = rs->smap.insts_built;
    out->map = &rs->smap.map, out->nodes = &rs->smap.nodes, out->insts_buf = &rs->smap.insts;
}

vx_result vx__render_scene_sun_map_frame(vx_render_scene* rs, const vx__frame* f, bool allow, vx__sun_map* out,
                                         vx_error* err) {
    if (!rs || !f || !out) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    memset(out, 0, sizeof *out);
    bool use = false;
    vx_result r = VX_OK;
    if (!use_precise(rs) && !f->lod && smap_possible(rs)) r = smap_ensure(rs, f, allow, &use, err);
    if (r || !use) return r;
    sun_map_out(rs, out);
    return VX_OK;
}

/* The single-instance kernels (USE_BVH off: trace.comp's float variant,
 * trace_compact.comp) read the instance's record, and trace.comp its
 * model's and its grid's, from the frame block rather than the buffers.
 * After fill_gpu_frame. */
static void fill_single_instance(vx_render_scene* rs) {
    if (rs->inst_count != 1) return;
    vx__gpu_frame* gf = rs->frame.map;
    gf->inst0 = *(const vx__gpu_inst*)rs->insts.map;
    uint32_t m = gf->inst0.model;
    if (m < rs->model_count) gf->model0 = rs->gm[m];
    /* its grid (none since an edit of its model: update_model clears grid_at) */
    gf->grid0 = UINT32_MAX;
    if (rs->grid_at && m < rs->model_count && rs->grid_at[m] != UINT32_MAX) {
        gf->grid0 = rs->grid_at[m];
        const uint32_t* cb = &rs->mcells[6 * m]; /* the header's box (grid_header), exact as floats (< 2^16) */
        for (int k = 0; k < 3; k++) gf->gbox_lo[k] = (float)cb[k], gf->gbox_hi[k] = (float)cb[3 + k];
    }
}

/* trace.comp's kernel of one instance over the union grid (grid_union): its instance and model records in
 * the frame block (the instance's rows relative to the frame's reference, as frame_tables makes them; model
 * UINT32_MAX, which inst_at and model_at read from the frame block, a hit's instance from insts), its grid
 * and cube table. After fill_gpu_frame. */
static void fill_union(vx_render_scene* rs, const vx__frame* f) {
    vx__gpu_frame* gf = rs->frame.map;
    const grid_union* u = &rs->uni;
    for (int r = 0; r < 3; r++) {
        const double* row = &u->inv[4 * r];
        double w = row[0] * f->ref[0] + row[1] * f->ref[1] + row[2] * f->ref[2] + row[3];
        for (int c = 0; c < 3; c++) gf->inst0.r[r][c] = (float)row[c];
        gf->inst0.r[r][3] = (float)w;
        gf->inst0.lo[r] = (float)(w - (double)(float)w);
    }
    gf->inst0.lo[3] = 0;
    gf->inst0.model = UINT32_MAX;
    gf->inst0.cell = rs->inst[0].cell;
    gf->inst0.id = UINT32_MAX;
    gf->inst0.pad = 0;
    memset(&gf->model0, 0, sizeof gf->model0);
    gf->model0.depth = u->depth;
    gf->model0.flags = u->flags;
    gf->grid0 = u->addr;
    for (int k = 0; k < 3; k++) gf->gbox_lo[k] = (float)u->box[k], gf->gbox_hi[k] = (float)u->box[3 + k];
    gf->gunion = u->table;
}

vx_result vx__render_scene_sun_map(vx_render_scene* rs, const float light[3], const double ref[3], uint32_t max_side,
                                   vx__sun_map* out, vx_error* err) {
    if (!rs || !light || !ref || !out) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    memset(out, 0, sizeof *out);
    if (!smap_possible(rs)) return VX_OK;
    if (!(rs->smap.valid && !memcmp(light, rs->smap.light, sizeof rs->smap.light))) {
        vx_result r = smap_build(rs, light, max_side, err);
        if (r) return r;
        /* a colour frame with this light finds the map made */
        rs->smap_seen = true;
        memcpy(rs->smap_seen_light, light, sizeof rs->smap_seen_light);
    }
    if (!rs->smap.valid) return VX_OK;
    smap_origin(rs, ref, out->origin);
    sun_map_out(rs, out);
    return VX_OK;
}

/* The model-space start of the ray through image point (x, y) (pixels,
 * edges included) of frame f in instance `in` (inv: model from world), as
 * trace.comp starts it: its origin, or its entry into the model box
 * [0, bhi] (*entry set); false where it misses the box. */
static bool ray_start(const vx__frame* f, const double inv[12], const double bhi[3], double x, double y, double p[3],
                      bool* entry) {
    double u = x / f->width * 2 - 1, v = 1 - y / f->height * 2, ow[3], dw[3], om[3], dm[3];
    for (int k = 0; k < 3; k++) {
        double off = u * f->rx[k] + v * f->uy[k];
        ow[k] = f->ref[k] + (f->ortho ? off : f->t_start * off);
        dw[k] = f->ortho ? f->fwd[k] : f->fwd[k] + off;
    }
    for (int r = 0; r < 3; r++) {
        om[r] = inv[4 * r] * ow[0] + inv[4 * r + 1] * ow[1] + inv[4 * r + 2] * ow[2] + inv[4 * r + 3];
        dm[r] = inv[4 * r] * dw[0] + inv[4 * r + 1] * dw[1] + inv[4 * r + 2] * dw[2];
    }
    double te = 0, tx = INFINITY;
    for (int k = 0; k < 3; k++) {
        if (dm[k] == 0) {
            if (!(om[k] >= 0 && om[k] <= bhi[k])) return false;
            continue;
        }
        double a = -om[k] / dm[k], b = (bhi[k] - om[k]) / dm[k];
        te = fmax(te, fmin(a, b)), tx = fmin(tx, fmax(a, b));
    }
    if (!(te < tx)) return false;
    for (int k = 0; k < 3; k++) p[k] = om[k] + dm[k] * te;
    *entry = te > 0;
    return true;
}

/* Starts below the root for the primary rays of a scene of one instance
 * (vx__gpu_frame.paths and tiles; trace.comp's trace_model). Per screen
 * tile (as vx__frame_tiles cuts the image) whose corner rays start at
 * their origins inside the model box (the eye of a perspective view inside
 * it: one point for the whole frame) the box of those starts is taken down
 * the model's listed top (vx__top_node) while it lies in one inner child: X,
 * the node where that stops. The kernel checks per ray that its start lies
 * well inside one of X's children (the walk from the root then descends to
 * X without an advance), so the box only proposes: a ray whose start lies
 * elsewhere walks from the root. X is no deeper than a rebased model's
 * frame level less one (the walk moves into that frame by a push of its
 * own) unless pm->in_frame (the kernel then starts the ray in that frame).
 * Distinct starts take records in order; past VX__PATHS a tile takes
 * the deepest record whose X holds its box, or none. Not for LOD or the
 * beam (their walks start otherwise) or the float64 variant. Tiles whose
 * rays enter the model box (oblique views, overviews) get none: their
 * rays' starts spread over X's children and, on the H200, the warps' lanes
 * that then start at different nodes lost 6-16% of the rays/s though they
 * took 4-27% fewer steps (issue 21's fourteenth sitting). */
uint32_t vx__render_scene_paths(const vx_render_scene* rs, const vx__frame* f, const vx__path_model* pm,
                                vx__gpu_frame* gf) {
    uint32_t W = f->width, H = f->height, s, tx, ty;
    vx__frame_tile_grid(f, &s, &tx, &ty);
    gf->tile_info[0] = s, gf->tile_info[1] = tx;
    for (uint32_t i = 0; i < VX__TILES_X * VX__TILES_X; i++) gf->tiles[i] = VX__TILE_NONE;
    if (rs->inst_count != 1 || f->lod || !pm || !path_on(rs) || !W || !H) return 0;
    const inst_host* in = &rs->inst[0];
    uint32_t mi = in->model;
    if (mi >= rs->model_count || !pm->top) return 0;
    const vx__gpu_model* m = &rs->gm[mi];
    if (m->root >= VX_SVO_ROOT_LEAF || m->depth < 2 || m->depth > VX_RENDER_MAX_DEPTH) return 0;
    const vx__top_node* t = pm->top;
    /* hm: twice the kernel's margin (2^-16 of the cube), so that the box's
     * rays pass its test despite their float rounding */
    double side = ldexp(1.0, (int)m->depth), hm = ldexp(side, -15), bhi[3];
    uint32_t bsh = m->depth > 10 ? m->depth - 10 : 0, box = pm->box, rebase = pm->rebase;
    for (int k = 0; k < 3; k++) bhi[k] = (double)((((box >> (10 * k)) & 1023u) + 1u) << bsh);
    uint32_t min_level = pm->min_level ? pm->min_level : 1, min_dq = pm->min_dq ? pm->min_dq : 1;
    if (m->depth <= min_level) return 0;
    uint32_t max_dq = m->depth - min_level;
    if (rebase && !pm->in_frame && rebase - 1 < max_dq) max_dq = rebase - 1;
    if (max_dq > 24) max_dq = 24;
    uint32_t npaths = 0;
    for (uint32_t y = 0; y < ty; y++)
        for (uint32_t x = 0; x < tx; x++) {
            double plo[3] = {INFINITY, INFINITY, INFINITY}, phi[3] = {-INFINITY, -INFINITY, -INFINITY}, p[3];
            bool all = true, entry = false;
            for (int c = 0; c < 4 && all; c++) {
                double cx = fmin((double)((x + (c & 1)) << s), W), cy = fmin((double)((y + (c >> 1)) << s), H);
                all = ray_start(f, in->inv, bhi, cx, cy, p, &entry) && !entry;
                for (int k = 0; all && k < 3; k++) plo[k] = fmin(plo[k], p[k]), phi[k] = fmax(phi[k], p[k]);
            }
            if (!all) continue;
            /* down the listed nodes while the box lies in one inner child:
             * X, the node where it stops (the box across its mid-planes, or
             * in a child that is empty, a leaf or not listed) */
            uint32_t chain[25], i = 0, d = 0;
            double lo[3] = {0, 0, 0}, size = side;
            for (;;) {
                chain[d] = t[i].word;
                double half = 0.5 * size;
                uint32_t oct = 0;
                bool straddle = false;
                for (int k = 0; k < 3; k++) {
                    double mid = lo[k] + half;
                    if (plo[k] >= mid + hm) oct |= 1u << k;
                    else if (!(phi[k] <= mid - hm)) straddle = true;
                }
                uint32_t dsc = t[i].desc, inner = vx_svo_desc_valid(dsc) & ~vx_svo_desc_leaf(dsc);
                if (straddle || d + 1 > max_dq || !((inner >> oct) & 1u) || t[i].kids == VX__TOP_NONE) break;
                i = t[i].kids + (uint32_t)__builtin_popcount(inner & ((1u << oct) - 1u));
                for (int k = 0; k < 3; k++) lo[k] += ((oct >> k) & 1u) ? half : 0;
                size = half, d++;
            }
            uint32_t dq = d;
            if (dq < min_dq) continue; /* X the root: nothing to skip; or fewer pushes than a start is worth */
            float cube[4];
            for (int k = 0; k < 3; k++) cube[k] = (float)(1.0 + lo[k] / side);
            cube[3] = (float)(size / side);
            uint32_t r = 0;
            while (r < npaths && !(gf->paths[r].info[0] == dq && gf->paths[r].info[1] == chain[dq] &&
                                   !memcmp(gf->paths[r].cube, cube, sizeof cube)))
                r++;
            if (r == npaths && npaths < VX__PATHS) {
                vx__gpu_path* g = &gf->paths[npaths++];
                memset(g, 0, sizeof *g);
                g->info[0] = dq, g->info[1] = chain[dq], g->info[2] = mi;
                memcpy(g->cube, cube, sizeof cube);
                memcpy(g->nodes, chain, dq * sizeof chain[0]);
            } else if (r == npaths) {
                /* the table is full: the deepest record whose X holds the box */
                uint32_t best = VX__TILE_NONE;
                for (uint32_t j = 0; j < npaths; j++) {
                    const float* kc = gf->paths[j].cube;
                    bool holds = true;
                    for (int k = 0; k < 3; k++) {
                        double a = (kc[k] - 1.0) * side, b = a + kc[3] * side;
                        holds = holds && plo[k] >= a + hm && phi[k] <= b - hm;
                    }
                    if (holds && (best == VX__TILE_NONE || kc[3] < gf->paths[best].cube[3])) best = j;
                }
                r = best;
            }
            gf->tiles[y * tx + x] = (uint16_t)r;
        }
    return npaths;
}

/* trace.comp's starts (vx__render_scene_paths) over the plain layout's
 * listed tops: X down to level 1 (any node of the words). Not for the beam
 * (its walks start where the beam pass says) or the float64 variant. */
static void frame_paths(const vx_render_scene* rs, const vx__frame* f, bool precise, uint32_t beam,
                        vx__gpu_frame* gf) {
    uint32_t mi = rs->inst_count == 1 ? rs->inst[0].model : UINT32_MAX;
    bool on = !precise && !beam && rs->top && mi < rs->model_count && rs->top[mi];
    vx__path_model pm = {0};
    if (on)
        pm = (vx__path_model){
            .top = rs->top[mi], .box = rs->gm[mi].box, .rebase = rs->gm[mi].rebase, .min_level = 1, .in_frame = true};
    (void)vx__render_scene_paths(rs, f, on ? &pm : NULL, gf);
}

vx_result vx__render_dispatch(vx_render_scene* rs, const vx_render_desc* desc, bool want_hits, uint32_t repeat,
                              vx__frame* f, double* seconds, vx_error* err) {
    vx_gpu* g = rs->gpu;
    vx_result r = need_plain(rs, err);
    if (r) return r;
    r = vx__frame_setup(rs->lo, rs->hi, desc, f, err);
    if (r) return r;
    if ((r = vx__gpu_float_range(rs->lo, rs->hi, err))) return r;
    VkDeviceSize npx = (VkDeviceSize)f->width * f->height;
    if ((r = vx__buffer_ensure(g, &rs->pixels, npx * 16, "pixels", err))) return r;
    if (want_hits && (r = vx__buffer_ensure(g, &rs->hits, npx * 32, "hits", err))) return r;
    if (!want_hits && (r = vx__buffer_ensure(g, &rs->hits, 16, "hits", err))) return r;
    bool precise = use_precise(rs);
    if (precise && !g->has_float64)
        return vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET, "the float64 trace variant needs shaderFloat64, which %s lacks",
                       g->props.deviceName);
    /* the shadow rays' depth map: colour mode, float variant, no LOD (a LOD
     * hit is a coarse node, larger than the listed ones) */
    bool smap = false;
    if (!precise && f->mode == VX_RENDER_COLOR && !f->lod && smap_possible(rs) &&
        (r = smap_ensure(rs, f, !(desc && desc->no_shadow_map), &smap, err)))
        return r;
    rs->smap_used = smap;
    if ((r = write_frame_tables(rs, f, err))) return r;
    fill_gpu_frame(rs, f, rs->frame.map); /* with the map's frame (grid_lo, dims2) where smap */
    fill_single_instance(rs);
    /* the grid walk (shaders/grid_walk.glsl): float variant, without LOD; the
     * kernel's GRID the grids' greatest root level. The beam pass and the
     * starts below the root serve the octree walk: off with it. */
    vx__buffer* grid_buf = NULL;
    uint32_t grid = !precise ? vx__render_scene_grid_spec(rs, f, &grid_buf) : 0;
    /* a converter's regions as one grid (grid_union): the kernel of one instance (USE_BVH off) walks it,
     * GRID's bit 4; every model's hit through it (bit 2), its root's level exact (bit 3) */
    bool uni = grid && union_holds(rs);
    if (uni) {
        fill_union(rs, f);
        grid = rs->uni.top | 4u | 16u | (rs->uni.top >= 2 ? 8u : 0u);
    }
    /* the beam pass: float variant, without LOD (see shaders/beam.comp) */
    uint32_t beam = !precise && !f->lod && f->beam > 1 && !grid ? f->beam : 0;
    if (rs->inst_count <= 1 && !grid) frame_paths(rs, f, precise, beam, rs->frame.map);
    uint32_t bw = beam ? (f->width + beam - 1) / beam : 0, bh = beam ? (f->height + beam - 1) / beam : 0;
    /* the float kernel declares the beam binding either way */
    if (!precise && (r = vx__buffer_ensure(g, &rs->beam, beam ? (VkDeviceSize)bw * bh * 4 : 16, "beam", err))) return r;
    /* The screen cull: the trace pass covers the pixels whose rays can meet
     * the scene's box, a second pass (the same kernel, MISS_PASS) writes the
     * others' misses without a ray. Not with LOD (a coarse hit is its node's
     * cube, which may reach past the cells' box) nor another kernel (a
     * benchmark's, which may not read the rectangle). */
    bool cull = rs->cull < 0 ? !rs->alt_spv : rs->cull > 0;
    uint32_t groups[3], miss_groups[3];
    bool miss = vx__frame_cull(f, rs->lo, rs->hi, cull && !f->lod, ((vx__gpu_frame*)rs->frame.map)->rect, groups,
                               miss_groups, &rs->last_traced);
    rs->last_cull = miss;
    if (cull && !f->lod && rs->inst_count > 1) {
        vx__gpu_frame* gf = rs->frame.map;
        vx__frame_tiles(f, &rs->bvh, gf->tiles, &gf->tile_info[0], &gf->tile_info[1]);
    }
    /* 6 one sample a pixel (id 6 is other kernels' too: passes, probes), 7 the starts below the root
     * (PATH_START; other kernels' 7 is theirs); 8 the float walk's DEEP,
     * 9 FAR, 10 COMPACT (off here), 11 the shadow map, 12 the screen cull's miss pass */
    uint32_t spec[14] = {(uint32_t)f->mode, rs->has_color, rs->inst_count > 1 && !uni, f->lod, want_hits, beam,
                         f->spp <= 1,
                         rs->inst_count <= 1 && path_on(rs) && !grid,
                         uni && rs->uni.deep > vx__render_scene_deep(rs) ? rs->uni.deep : vx__render_scene_deep(rs),
                         rs->far, 0, smap, 0, grid};
    uint64_t key = vx__spec_key(1 + precise, spec, 14);
    size_t spv_size;
    const uint32_t* spv = precise ? vx__spirv_trace_precise(&spv_size) : vx__spirv_trace(&spv_size);
    if (!precise && rs->alt_spv) spv = rs->alt_spv, spv_size = rs->alt_size, key = key * 131 + 0x5EED0000u + rs->alt_tag;
    /* bindings 0-8, 9 the float64 instances, 10 the beam, 11-13 the shadow map, its nodes and instances,
     * 14 the grids (a kernel of vx__render_scene_trace_kernel gets them too: one that does not declare 14 or
     * GRID, id 13, takes the octree walk as before) */
    uint32_t nb = precise ? 10 : 15;
    vx_gpu_compute_pipeline_desc pd = {.spirv = spv, .spirv_size = spv_size, .binding_count = nb,
                                       .spec_count = 14, .label = precise ? "trace (float64)" : "trace"};
    pd.bindings[0] = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
    for (uint32_t i = 1; i < nb; i++) pd.bindings[i] = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    memcpy(pd.spec, spec, sizeof spec);
    vx__pipeline *p, *pre = NULL;
    vx_gpu_compute_pipeline_desc bd = pd;
    /* the beam pass reads only the scene and the camera: one pipeline per
     * BVH use, block size and far-pointer test. Its key hashes every constant
     * it is built with: a key without FAR (issue 21) let a scene with far
     * pointers (terrain4096) reuse the pass built for one without, whose walk
     * then took wrong children (6,415 pixels of the overview changed). */
    uint64_t bkey = 0xBEA4000u;
    if (beam) {
        bd.spirv = vx__spirv_beam(&bd.spirv_size);
        if (rs->alt_beam) bd.spirv = rs->alt_beam, bd.spirv_size = rs->alt_beam_size, bkey += 0x100000u * (rs->alt_tag + 1);
        bd.label = "beam";
        bd.spec[VX__SPEC_MODE] = bd.spec[VX__SPEC_HAS_COLOR] = bd.spec[VX__SPEC_LOD] = bd.spec[VX__SPEC_HITS] = 0;
        bd.spec[6] = bd.spec[7] = 0; /* trace.comp's one-sample switch and starts */
        bkey = vx__spec_key(bkey, bd.spec, 10);
        if ((r = vx__pipeline_get(g, bkey, &bd, &pre, err))) return r;
    }
    if ((r = vx__pipeline_get(g, key, &pd, &p, err))) return r;
    vx__pipeline* post = NULL;
    if (miss) {
        vx_gpu_compute_pipeline_desc md = pd;
        md.spec[12] = 1, md.label = "trace (misses)";
        uint64_t mkey = vx__spec_key(1 + precise, md.spec, 14);
        if (!precise && rs->alt_spv) mkey = mkey * 131 + 0x5EED0000u + rs->alt_tag;
        if ((r = vx__pipeline_get(g, mkey, &md, &post, err))) return r;
    }
    vx__dispatch_desc dd = {.pipeline = p,
                            .buffer_count = nb,
                            .buffers = {&rs->frame, &rs->nodes, &rs->colors, &rs->models, &rs->insts, &rs->bvh_nodes,
                                        &rs->bvh_items, &rs->pixels, &rs->hits, &rs->pinsts, &rs->beam,
                                        smap ? &rs->smap.map : &rs->beam, smap ? &rs->smap.nodes : &rs->beam,
                                        smap ? &rs->smap.insts : &rs->beam, grid ? grid_buf : &rs->beam},
                            .groups = {groups[0], groups[1], groups[2]},
                            .repeat = repeat,
                            .label = "trace",
                            .pre_pipeline = pre,
                            .pre_groups = {(bw + 7) / 8, (bh + 7) / 8, 1},
                            .post_pipeline = post,
                            .post_groups = {miss_groups[0], miss_groups[1], miss_groups[2]}};
    return vx__dispatch(g, &dd, seconds, err);
}

vx_gpu* vx__render_scene_gpu(vx_render_scene* rs) { return rs ? rs->gpu : NULL; }

uint64_t vx__render_scene_buffer_range(const vx_render_scene* rs) { return rs ? rs->buffer_range : 0; }

vx_result vx__render_scene_bind(vx_render_scene* rs, const vx__frame* f, vx__buffer* bufs[7],
                                uint32_t spec[VX__SPEC_COUNT], vx_error* err) {
    vx_result r = need_whole(rs, err);
    if (!r) r = vx__render_scene_tables(rs, f, bufs, spec, err);
    if (!r && rs->compact) vx__compact_gpu_bind(rs->compact, bufs);
    return r;
}

bool vx__render_scene_compact(const vx_render_scene* rs) { return rs && rs->compact; }
uint32_t vx__render_scene_compact_form(const vx_render_scene* rs) {
    return !vx__render_scene_compact(rs) ? 0u : rs->layout.brick_dict ? 2u : 1u;
}

bool vx__scene_material_ids_matter(const vx_svo_scene* s) {
    bool channel = false, special = false;
    for (uint32_t i = 0; s && i < s->model_count && !channel; i++) channel = (s->models[i].attrs & VX_ATTR_MATERIAL) != 0;
    for (uint32_t i = 0; channel && i < s->material_count && !special; i++) {
        vx_material m = vx_svo_material_resolve(&s->materials[i]);
        special = m.emission > 0 || m.type == VX_MATERIAL_METAL || m.type == VX_MATERIAL_GLASS;
    }
    return special;
}

vx_result vx__render_scene_attr_material(const vx_render_scene* rs, const vx_svo_scene* s, const vx_allocator* alloc,
                                         uint16_t** out, size_t* n, vx_error* err) {
    if (!vx__render_scene_compact(rs)) return vx__scene_attr_material(s, alloc, out, n, err);
    /* a layout built with the models' material ids: the passes' Hit.attr is the material id (compact_gpu.c) */
    bool missing = false;
    vx_result r = vx__compact_gpu_materials(rs->compact, alloc, out, n, &missing, err);
    if (r || *out) return r;
    /* else the records are keyed by palette index: refuse where a material channel would name a material other
     * than plain diffuse (the plain layout's image would differ) and the layout has no ids for it */
    if (vx__scene_material_ids_matter(s))
        return vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET,
                       "the compact layout has no material ids for the models' material channel (%s): render it in "
                       "the plain layout, or without lights and gi",
                       missing           ? "built from a model reader, without the models' arrays"
                       : rs->layout.pages ? "the paged layout carries none"
                                          : "the scene's materials were all diffuse when the layout was built");
    /* per palette index; the indices no record uses are 0 (none), so that a table's "some record is ..." (metal,
     * emissive) is the plain layout's. The indices in use come from the layout's build (palette_used), not from
     * s's models: a scene built from a model reader is its graph here, without the models' arrays (svo_bake
     * --load models) */
    uint16_t* p = vx_calloc(alloc, 256, sizeof *p);
    if (!p) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory");
    for (uint32_t i = 0; i < 256; i++) p[i] = rs->palette_used[i >> 5] & (1u << (i & 31)) ? (uint16_t)i : 0;
    *out = p;
    *n = 256;
    return VX_OK;
}

vx_result vx__render_scene_tables(vx_render_scene* rs, const vx__frame* f, vx__buffer* bufs[7],
                                  uint32_t spec[VX__SPEC_COUNT], vx_error* err) {
    if (use_precise(rs))
        return vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET,
                       "the scene has models deeper than %u levels, which this GPU pass cannot trace (float only)",
                       VX_RENDER_PRECISE_DEPTH);
    vx_result r = write_frame_tables(rs, f, err);
    if (r) return r;
    fill_gpu_frame(rs, f, rs->frame.map);
    fill_single_instance(rs); /* trace_compact.comp reads inst0 too */
    vx__buffer* b[7] = {&rs->frame, &rs->nodes, &rs->colors, &rs->models, &rs->insts, &rs->bvh_nodes, &rs->bvh_items};
    memcpy(bufs, b, sizeof b);
    uint32_t sp[VX__SPEC_COUNT] = {(uint32_t)VX_RENDER_COLOR, rs->has_color, rs->inst_count > 1, 0, 0};
    memcpy(spec, sp, sizeof sp);
    return VX_OK;
}

/* vkCmdUpdateBuffer in its largest pieces (64 KiB). */
static void update_buffer(VkCommandBuffer cb, const vx__buffer* b, const void* data, VkDeviceSize size) {
    for (VkDeviceSize at = 0; at < size; at += 65536) {
        VkDeviceSize n = size - at < 65536 ? size - at : 65536;
        vkCmdUpdateBuffer(cb, b->buf, at, n, (const uint8_t*)data + at);
    }
}

/* The rows of `data` (count rows of `row` bytes) that differ from `last`
 * (the buffer's contents once the frames before run), in runs: rows a few
 * apart go in one update (a command each costs more than a few rows). More
 * than a quarter changed: the whole table in one go. Returns the rows sent. */
static uint64_t update_rows(VkCommandBuffer cb, const vx__buffer* b, const uint8_t* data, const uint8_t* last, size_t row,
                            size_t count) {
    size_t changed = 0;
    for (size_t i = 0; i < count; i++) changed += memcmp(data + i * row, last + i * row, row) != 0;
    if (changed * 4 > count) {
        update_buffer(cb, b, data, (VkDeviceSize)(row * count));
        return count;
    }
    uint64_t sent = 0;
    for (size_t i = 0; i < count;) {
        if (!memcmp(data + i * row, last + i * row, row)) {
            i++;
            continue;
        }
        size_t e = i + 1, gap = 0; /* the run ends after 4 equal rows in a row */
        for (size_t j = i + 1; j < count && gap < 4; j++) {
            if (memcmp(data + j * row, last + j * row, row)) e = j + 1, gap = 0;
            else gap++;
        }
        VkDeviceSize at = (VkDeviceSize)(i * row), n = (VkDeviceSize)((e - i) * row);
        for (VkDeviceSize k = 0; k < n; k += 65536)
            vkCmdUpdateBuffer(cb, b->buf, at + k, n - k < 65536 ? n - k : 65536, data + at + k);
        sent += e - i;
        i = e;
    }
    return sent;
}

/* The pool of the refit's set and the instance rows' set. */
static vx_result sets_pool(vx_render_scene* rs, vx_error* err) {
    if (rs->refit_pool) return VX_OK;
    VkDescriptorPoolSize size = {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 7};
    VkDescriptorPoolCreateInfo pci = {.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO,
                                      .flags = VK_DESCRIPTOR_POOL_CREATE_FREE_DESCRIPTOR_SET_BIT,
                                      .maxSets = 2, .poolSizeCount = 1, .pPoolSizes = &size};
    VX__VK(vkCreateDescriptorPool(rs->gpu->device, &pci, NULL, &rs->refit_pool), "vkCreateDescriptorPool");
    return VX_OK;
}

/* *set, p's set of n storage buffers b (from the scene's small pool), made
 * on first use; again only if p's layout is not *dsl's (the device's cache
 * keeps p as it is for its life, gpu.h). A set made for an earlier layout may
 * be in frames in flight: it is freed only after them. */
static vx_result storage_set(vx_render_scene* rs, const vx__pipeline* p, VkDescriptorSet* set,
                             VkDescriptorSetLayout* dsl, const vx__buffer* const* b, uint32_t n, vx_error* err) {
    if (*set && *dsl == p->dsl) return VX_OK;
    vx_gpu* g = rs->gpu;
    settle(rs);
    if (*set) vkFreeDescriptorSets(g->device, rs->refit_pool, 1, set), *set = VK_NULL_HANDLE;
    VkDescriptorSetAllocateInfo ai = {.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO,
                                      .descriptorPool = rs->refit_pool, .descriptorSetCount = 1,
                                      .pSetLayouts = &p->dsl};
    VX__VK(vkAllocateDescriptorSets(g->device, &ai, set), "vkAllocateDescriptorSets");
    *dsl = p->dsl;
    VkDescriptorBufferInfo bi[4];
    VkWriteDescriptorSet w[4];
    for (uint32_t i = 0; i < n; i++) {
        bi[i] = (VkDescriptorBufferInfo){.buffer = b[i]->buf, .range = VK_WHOLE_SIZE};
        w[i] = (VkWriteDescriptorSet){.sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET, .dstSet = *set,
                                      .dstBinding = i, .descriptorCount = 1,
                                      .descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, .pBufferInfo = &bi[i]};
    }
    vkUpdateDescriptorSets(g->device, n, w, 0, NULL);
    return VX_OK;
}

/* A compute pipeline over n storage buffers and its descriptor set (set,
 * dsl: the scene's fields that keep them; storage_set). */
static vx_result storage_pipeline(vx_render_scene* rs, const uint32_t* spirv, size_t spirv_size, uint32_t push, uint32_t key,
                                  const char* label, const vx__buffer* const* b, uint32_t n, VkDescriptorSet* set,
                                  VkDescriptorSetLayout* dsl, vx__pipeline** out, vx_error* err) {
    vx_gpu_compute_pipeline_desc pd = {
        .spirv = spirv, .spirv_size = spirv_size, .binding_count = n, .push_constant_size = push, .label = label};
    for (uint32_t i = 0; i < n; i++) pd.bindings[i] = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    vx__pipeline* p;
    vx_result r = vx__pipeline_get(rs->gpu, key, &pd, &p, err);
    if (r || (r = sets_pool(rs, err)) || (r = storage_set(rs, p, set, dsl, b, n, err))) return r;
    *out = p;
    return VX_OK;
}

/* The instance rows' pipeline and its set (sources, instance rows, boxes). */
static vx_result rows_pipeline(vx_render_scene* rs, vx__pipeline** out, vx_error* err) {
    const vx__buffer* b[3] = {&rs->inst_src, &rs->insts, &rs->inst_boxes};
    return storage_pipeline(rs, vx__inst_rows_spv_arr, sizeof vx__inst_rows_spv_arr, 32, 0x1057u, "instance rows", b, 3,
                            &rs->rows_set, &rs->rows_dsl, out, err);
}

/* The instances' rows relative to the world (inst_rows.comp's input). */
static void instance_sources(const vx_render_scene* rs, inst_src* out) {
    for (uint32_t i = 0; i < rs->inst_count; i++) {
        const inst_host* h = &rs->inst[i];
        inst_src* o = &out[i];
        memset(o, 0, sizeof *o);
        memcpy(o->inv, h->inv, sizeof o->inv);
        memcpy(o->lo, h->lo, sizeof o->lo);
        memcpy(o->hi, h->hi, sizeof o->hi);
        o->model = h->model, o->id = h->id, o->cell = h->cell;
    }
}

void vx__render_scene_rows_on_gpu(vx_render_scene* rs, int on) {
    if (rs) rs->rows_gpu = on < 0 ? -1 : on > 0;
}

/* The refit's pipeline and its set (bvh nodes, items, instance boxes, order). */
static vx_result refit_pipeline(vx_render_scene* rs, vx__pipeline** out, vx_error* err) {
    const vx__buffer* b[4] = {&rs->bvh_nodes, &rs->bvh_items, &rs->inst_boxes, &rs->order_buf};
    return storage_pipeline(rs, vx__refit_spv_arr, sizeof vx__refit_spv_arr, 8, 0x4EF17u, "bvh refit", b, 4,
                            &rs->refit_set, &rs->refit_dsl, out, err);
}

/* Each instance's world box relative to f's reference point, rounded outward
 * to float (lo, hi as vec4 pairs): the refit's leaves. */
static void instance_boxes(const vx_render_scene* rs, const vx__frame* f, float* out) {
    for (uint32_t i = 0; i < rs->inst_count; i++) {
        float* o = out + 8 * (size_t)i;
        for (int k = 0; k < 3; k++) {
            double a = rs->inst[i].lo[k] - f->ref[k], b = rs->inst[i].hi[k] - f->ref[k];
            float fa = (float)a, fb = (float)b;
            if ((double)fa > a) fa = nextafterf(fa, -INFINITY);
            if ((double)fb < b) fb = nextafterf(fb, INFINITY);
            o[k] = fa, o[4 + k] = fb;
        }
        o[3] = o[7] = 0;
    }
}

vx_result vx__render_scene_bind_cmd(vx_render_scene* rs, const vx__frame* f, void* cmd, vx__buffer* bufs[7],
                                    uint32_t spec[VX__SPEC_COUNT], vx_error* err) {
    vx_result lr = need_whole(rs, err);
    if (lr) return lr;
    if (use_precise(rs))
        return vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET,
                       "the scene has models deeper than %u levels, which this GPU pass cannot trace (float only)",
                       VX_RENDER_PRECISE_DEPTH);
    VkCommandBuffer cb = (VkCommandBuffer)cmd;
    /* the BVH's bounds: refit on the GPU from the instances' boxes once its shape is there; whole nodes else */
    vx__pipeline *rp = NULL, *wp = NULL;
    bool refit = rs->bvh.node_count && rs->bvh_levels && !rs->shape_dirty;
    /* the rows on the GPU: with the refit (the boxes come from them), where the device has float64 */
    bool gpu_rows = refit && rs->gpu->has_float64 && (rs->rows_gpu < 0 || rs->rows_gpu > 0);
    if (refit) {
        vx_result r = refit_pipeline(rs, &rp, err);
        if (!r && gpu_rows) r = rows_pipeline(rs, &wp, err);
        if (r) return r;
    }
    int kind = gpu_rows ? 2 : refit ? 1 : 0;
    /* the tables after the frame block: the instance rows (GPU rows: the reference point and the sources),
     * then the boxes (refit on the host's rows) or the BVH's nodes (none with GPU rows) */
    size_t ni = gpu_rows ? sizeof(rows_ref) + (size_t)rs->inst_count * sizeof(inst_src)
                         : (size_t)rs->inst_count * sizeof(vx__gpu_inst);
    size_t nb = gpu_rows ? 0 : refit ? (size_t)rs->inst_count * 32 : (size_t)rs->bvh.node_count * sizeof(vx_bvh_node);
    size_t need = sizeof(vx__gpu_frame) + ni + nb;
    if (need > rs->scratch_size) {
        void* p = vx_alloc(&rs->alloc, need);
        if (!p) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %zu bytes of frame tables", need);
        vx_free(&rs->alloc, rs->scratch);
        rs->scratch = p, rs->scratch_size = need;
    }
    uint8_t* at = rs->scratch;
    vx__gpu_frame* gf = (vx__gpu_frame*)at;
    vx__gpu_inst* gi = (vx__gpu_inst*)(at + sizeof *gf);
    if (gpu_rows) {
        rows_ref rr = {.ref = {f->ref[0], f->ref[1], f->ref[2]}};
        memcpy(gi, &rr, sizeof rr);
        instance_sources(rs, (inst_src*)(at + sizeof *gf + sizeof rr));
    } else if (refit) {
        frame_tables(rs, f, gi, NULL, NULL);
        instance_boxes(rs, f, (float*)(at + sizeof *gf + ni));
    } else {
        frame_tables(rs, f, gi, NULL, (vx_bvh_node*)(at + sizeof *gf + ni));
    }
    fill_gpu_frame(rs, f, gf);
    /* the same tables as the last recorded frame's: the buffers hold them (that frame's updates run before this
     * frame on the queue), so no update and no barrier before one */
    bool same = rs->tables_known && !rs->items_dirty && !rs->order_dirty && rs->tables_kind == kind &&
                rs->tables_size == need && !memcmp(rs->tables, rs->scratch, need);
    if (!same) {
        /* after the shader reads of frames before this one on the queue (an
         * execution dependency is enough for a write after reads), before this
         * frame's reads */
        VkMemoryBarrier before = {.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER, .dstAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT};
        vkCmdPipelineBarrier(cb, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                             VK_PIPELINE_STAGE_TRANSFER_BIT | (refit ? VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT : 0), 0, 1,
                             &before, 0, NULL, 0, NULL);
        /* with the last recorded frame's tables known and of the same kind, only the rows that changed (an
         * instance moved, the camera still: one row and its box, not all); else all */
        bool rows = rs->tables_known && rs->tables_kind == kind && rs->tables_size == need;
        const uint8_t* last = rs->tables;
        size_t nrow = refit ? 32 : sizeof(vx_bvh_node);
        bool run_rows = false; /* the GPU computes the rows (their sources or the reference point changed) */
        if (!rows || memcmp(last, gf, sizeof *gf)) update_buffer(cb, &rs->frame, gf, sizeof *gf);
        if (gpu_rows) {
            const uint8_t* src = at + sizeof *gf + sizeof(rows_ref);
            uint64_t sent = rows ? update_rows(cb, &rs->inst_src, src, last + sizeof *gf + sizeof(rows_ref),
                                               sizeof(inst_src), rs->inst_count)
                                 : (update_buffer(cb, &rs->inst_src, src, (VkDeviceSize)rs->inst_count * sizeof(inst_src)),
                                    rs->inst_count);
            rs->stats.table_rows_uploaded += sent;
            run_rows = !rows || sent || memcmp(last + sizeof *gf, at + sizeof *gf, sizeof(rows_ref));
        } else if (rows) {
            rs->stats.table_rows_uploaded +=
                update_rows(cb, &rs->insts, (const uint8_t*)gi, last + sizeof *gf, sizeof(vx__gpu_inst), rs->inst_count);
            rs->stats.table_rows_uploaded += update_rows(cb, refit ? &rs->inst_boxes : &rs->bvh_nodes,
                                                         at + sizeof *gf + ni, last + sizeof *gf + ni, nrow, nb / nrow);
        } else {
            update_buffer(cb, &rs->insts, gi, ni);
            update_buffer(cb, refit ? &rs->inst_boxes : &rs->bvh_nodes, at + sizeof *gf + ni, nb);
            rs->stats.table_rows_uploaded += rs->inst_count + nb / nrow;
        }
        if (rs->items_dirty) { /* an in-place instance update's item order (frames before this one read the old) */
            update_buffer(cb, &rs->bvh_items, rs->bvh.items, (VkDeviceSize)rs->bvh.item_count * 4);
            rs->items_dirty = false;
        }
        if (rs->order_dirty) { /* and its levels */
            update_buffer(cb, &rs->order_buf, rs->bvh_order, (VkDeviceSize)rs->bvh.node_count * 4);
            rs->order_dirty = false;
        }
        if (refit) {
            /* the levels from the deepest up, each after the one below */
            VkMemoryBarrier mb = {.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER,
                                  .srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT,
                                  .dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT};
            vkCmdPipelineBarrier(cb, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0, 1, &mb, 0,
                                 NULL, 0, NULL);
            if (run_rows) {
                /* the rows and boxes relative to this frame's reference point, before the refit reads the boxes */
                struct {
                    uint32_t count, pad;
                    double ref[3];
                } pc = {rs->inst_count, 0, {f->ref[0], f->ref[1], f->ref[2]}};
                _Static_assert(sizeof pc == 32, "inst_rows.comp's push constants");
                vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_COMPUTE, wp->pipe);
                vkCmdBindDescriptorSets(cb, VK_PIPELINE_BIND_POINT_COMPUTE, wp->layout, 0, 1, &rs->rows_set, 0, NULL);
                vkCmdPushConstants(cb, wp->layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof pc, &pc);
                vkCmdDispatch(cb, (rs->inst_count + 63) / 64, 1, 1);
                mb = (VkMemoryBarrier){.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER,
                                       .srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT,
                                       .dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT};
                vkCmdPipelineBarrier(cb, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0, 1,
                                     &mb, 0, NULL, 0, NULL);
            }
            vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_COMPUTE, rp->pipe);
            vkCmdBindDescriptorSets(cb, VK_PIPELINE_BIND_POINT_COMPUTE, rp->layout, 0, 1, &rs->refit_set, 0, NULL);
            for (uint32_t l = rs->bvh_levels; l-- > 0;) {
                uint32_t pc[2] = {rs->bvh_level[l], rs->bvh_level[l + 1] - rs->bvh_level[l]};
                vkCmdPushConstants(cb, rp->layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof pc, pc);
                vkCmdDispatch(cb, (pc[1] + 63) / 64, 1, 1);
                if (l) {
                    mb = (VkMemoryBarrier){.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER,
                                           .srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT,
                                           .dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT};
                    vkCmdPipelineBarrier(cb, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0,
                                         1, &mb, 0, NULL, 0, NULL);
                }
            }
        } else {
            rs->shape_dirty = false; /* whole nodes */
        }
        rs->tables_known = false;
        if (need > rs->tables_cap) {
            void* p = vx_alloc(&rs->alloc, need);
            if (p) vx_free(&rs->alloc, rs->tables), rs->tables = p, rs->tables_cap = need;
        }
        if (need <= rs->tables_cap) {
            memcpy(rs->tables, rs->scratch, need);
            rs->tables_size = need, rs->tables_known = true, rs->tables_kind = kind;
        }
    }
    /* the transfers before this frame's passes (table rows, an overlay copy recorded before this) and this
     * frame's refit dispatches before its reads. Earlier frames' shader writes need no wait here: a frame that
     * writes the shared images ends with a barrier after its last dispatch (render/pipeline.c), and one that
     * does not (its last pass writes only its own display image) may still run while this frame starts */
    VkMemoryBarrier after = {.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER,
                             .srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT | (same ? 0 : VK_ACCESS_SHADER_WRITE_BIT),
                             .dstAccessMask =
                                 VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_UNIFORM_READ_BIT};
    vkCmdPipelineBarrier(cb, VK_PIPELINE_STAGE_TRANSFER_BIT | (same ? 0 : VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT),
                         VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0, 1, &after, 0, NULL, 0, NULL);
    rs->recorded = true;
    vx__buffer* b[7] = {&rs->frame, &rs->nodes, &rs->colors, &rs->models, &rs->insts, &rs->bvh_nodes, &rs->bvh_items};
    memcpy(bufs, b, sizeof b);
    if (rs->compact) vx__compact_gpu_bind(rs->compact, bufs);
    uint32_t sp[VX__SPEC_COUNT] = {(uint32_t)VX_RENDER_COLOR, rs->has_color, rs->inst_count > 1, 0, 0};
    memcpy(spec, sp, sizeof sp);
    return VX_OK;
}

/* Must walk the models as prepare_models does. */
vx_result vx__scene_attr_material(const vx_svo_scene* s, const vx_allocator* alloc, uint16_t** out, size_t* n,
                                  vx_error* err) {
    size_t total = 0;
    for (uint32_t i = 0; i < s->model_count; i++)
        if (s->models[i].attrs) total += s->models[i].attr_count;
    uint16_t* p = vx_calloc(alloc, total ? total : 1, sizeof *p);
    if (!p) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %zu attribute records", total);
    size_t at = 0;
    for (uint32_t i = 0; i < s->model_count; i++) {
        const vx_svo_model* m = &s->models[i];
        if (!m->attrs) continue;
        for (uint32_t a = 0; a < m->attr_count; a++) p[at++] = (uint16_t)vx_svo_attr_material(m, a);
    }
    *out = p;
    *n = total;
    return VX_OK;
}

static void hits_unpack(const uint32_t* raw, size_t n, vx_render_hit* hits) {
    for (size_t i = 0; i < n; i++) {
        const uint32_t* w = raw + 8 * i;
        hits[i] = (vx_render_hit){.instance = w[0], .cell = {w[1], w[2], w[3]}, .iterations = w[5], .flags = w[6],
                                  .shadow = w[7]};
        memcpy(&hits[i].t, &w[4], 4);
    }
}

vx_result vx__image_read(vx_gpu* g, vx__buffer* pixels, bool depth2, vx__buffer* hits, vx_render_image* img,
                         vx_error* err) {
    size_t npx = (size_t)img->width * img->height;
    img->pixels = vx_alloc(img->alloc, npx * 16);
    uint32_t* raw = hits ? vx_alloc(img->alloc, npx * 32) : NULL;
    if (hits) img->hits = vx_alloc(img->alloc, npx * sizeof *img->hits);
    vx_result r = VX_OK;
    if (!img->pixels || (hits && (!raw || !img->hits)))
        r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for a %ux%u image", img->width, img->height);
    if (!r) r = vx__buffer_download(g, pixels, img->pixels, npx * (depth2 ? 8 : 16), err);
    /* widened in place from the last pixel down (pixel i's 4 floats start at or after its 2's) */
    for (size_t i = npx; !r && depth2 && i-- > 0;) {
        float t = img->pixels[2 * i], a = img->pixels[2 * i + 1];
        img->pixels[4 * i] = img->pixels[4 * i + 1] = img->pixels[4 * i + 2] = t, img->pixels[4 * i + 3] = a;
    }
    if (!r && hits) r = vx__buffer_download(g, hits, raw, npx * 32, err);
    if (!r && hits) hits_unpack(raw, npx, img->hits);
    vx_free(img->alloc, raw);
    if (r) vx_render_image_free(img);
    return r;
}

vx_result vx_render_frame(vx_render_scene* rs, const vx_render_desc* desc, vx_render_image* out, vx_error* err) {
    if (!rs || !out) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    if (rs->compact) {
        if (desc && desc->lod)
            return vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET, "the compact layout has no LOD (render without lod)");
        return vx_compact_gpu_frame(rs->compact, desc, out, err);
    }
    bool want_hits = desc && desc->want_hits;
    vx__frame f;
    double sec = 0;
    vx_result r = vx__render_dispatch(rs, desc, want_hits, 1, &f, &sec, err);
    if (r) return r;
    size_t npx = (size_t)f.width * f.height;
    vx_render_image img = {.width = f.width, .height = f.height, .mode = f.mode, .alloc = &rs->gpu->alloc};
    /* trace.comp's depth mode writes depth and coverage only */
    bool depth2 = f.mode == VX_RENDER_DEPTH;
    if ((r = vx__image_read(rs->gpu, &rs->pixels, depth2, want_hits ? &rs->hits : NULL, &img, err))) return r;
    img.gpu_seconds = sec;
    img.rays = (uint64_t)npx * f.spp;
    *out = img;
    return VX_OK;
}

vx_result vx_render_scene_warm_up(vx_render_scene* rs, const vx_render_desc* desc, double seconds, double* frame_ms,
                                  vx_error* err) {
    if (!rs) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    double t0 = vx_time_now(), sec = 0;
    vx_result r = VX_OK;
    do {
        vx__frame f;
        r = rs->compact ? vx_compact_gpu_time(rs->compact, desc, 8, &sec, err)
                        : vx__render_dispatch(rs, desc, false, 8, &f, &sec, err);
    } while (!r && vx_time_now() - t0 < seconds);
    if (frame_ms) *frame_ms = sec * 1e3;
    return r;
}

/* ---- dense-grid baseline (benchmark) ----------------------------------------------- */

typedef struct dense_ctx {
    uint32_t* bits;
    uint32_t n[3];
    int64_t lo[3];
} dense_ctx;

static void dense_set(void* user, int64_t x, int64_t y, int64_t z) {
    dense_ctx* c = user;
    int64_t p[3] = {x - c->lo[0], y - c->lo[1], z - c->lo[2]};
    for (int k = 0; k < 3; k++)
        if (p[k] < 0 || p[k] >= c->n[k]) return;
    uint64_t i = ((uint64_t)p[2] * c->n[1] + (uint64_t)p[1]) * c->n[0] + (uint64_t)p[0];
    c->bits[i >> 5] |= 1u << (i & 31);
}

/* Builds the occupancy bit grid of the scene's grid-space bounds; the scene
 * must have an identity world_from_grid. Fails with VX_ERR_LIMIT above
 * max_cells. */
vx_result vx__dense_prepare(vx_render_scene* rs, const vx_svo_scene* s, uint64_t max_cells, vx_error* err) {
    dense_ctx c = {0};
    uint64_t cells = 1;
    for (int k = 0; k < 3; k++) {
        c.lo[k] = (int64_t)floor(rs->lo[k]);
        int64_t hi = (int64_t)ceil(rs->hi[k]);
        if (hi <= c.lo[k]) hi = c.lo[k] + 1;
        if (hi - c.lo[k] > (1 << 20)) return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "scene too large for a dense grid");
        c.n[k] = (uint32_t)(hi - c.lo[k]);
        cells *= c.n[k];
    }
    if (cells > max_cells)
        return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "dense grid of %llu cells exceeds %llu",
                       (unsigned long long)cells, (unsigned long long)max_cells);
    size_t words = (size_t)((cells + 31) / 32);
    c.bits = vx_calloc(&rs->alloc, words, 4);
    if (!c.bits) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for a dense grid");
    vx_result r = vx__scene_grid_cells(s, dense_set, &c, err);
    if (!r) r = vx__buffer_create(rs->gpu, (VkDeviceSize)words * 4, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, false,
                                  "dense bits", &rs->dense_bits, err);
    if (!r) r = vx__buffer_upload(rs->gpu, &rs->dense_bits, c.bits, (VkDeviceSize)words * 4, err);
    vx_free(&rs->alloc, c.bits);
    if (r) return r;
    for (int k = 0; k < 3; k++) rs->dense_n[k] = c.n[k], rs->dense_lo[k] = (double)c.lo[k];
    rs->dense_cell = 1;
    return VX_OK;
}

/* Dense DDA primary rays (depth); the pixels buffer receives t. */
vx_result vx__dense_dispatch(vx_render_scene* rs, const vx_render_desc* desc, uint32_t repeat, double* seconds,
                             float* depth_out, vx_error* err) {
    vx_gpu* g = rs->gpu;
    vx__frame f;
    vx_result r = vx__frame_setup(rs->lo, rs->hi, desc, &f, err);
    if (r) return r;
    if (!rs->dense_bits.buf) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "dense grid not prepared");
    VkDeviceSize npx = (VkDeviceSize)f.width * f.height;
    if ((r = vx__buffer_ensure(g, &rs->pixels, npx * 16, "pixels", err))) return r;
    vx__gpu_frame* gf = rs->frame.map;
    rs->tables_known = false; /* the host writes the frame block */
    fill_gpu_frame(rs, &f, gf);
    for (int k = 0; k < 3; k++) {
        gf->dims2[k] = rs->dense_n[k];
        gf->grid_lo[k] = (float)(rs->dense_lo[k] - f.ref[k]);
    }
    gf->grid_lo[3] = (float)rs->dense_cell;
    size_t spv_size;
    const uint32_t* spv = vx__spirv_dense(&spv_size);
    vx_gpu_compute_pipeline_desc pd = {.spirv = spv, .spirv_size = spv_size, .binding_count = 3, .label = "dense"};
    pd.bindings[0] = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
    pd.bindings[1] = pd.bindings[2] = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    vx__pipeline* p;
    if ((r = vx__pipeline_get(g, 0xDE45Eu, &pd, &p, err))) return r;
    vx__dispatch_desc dd = {.pipeline = p,
                            .buffer_count = 3,
                            .buffers = {&rs->frame, &rs->dense_bits, &rs->pixels},
                            .groups = {(f.width + 7) / 8, (f.height + 7) / 8, 1},
                            .repeat = repeat,
                            .label = "dense"};
    if ((r = vx__dispatch(g, &dd, seconds, err))) return r;
    if (depth_out) {
        float* tmp = vx_alloc(&rs->alloc, (size_t)npx * 16);
        if (!tmp) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory");
        r = vx__buffer_download(g, &rs->pixels, tmp, npx * 16, err);
        for (size_t i = 0; !r && i < npx; i++) depth_out[i] = tmp[4 * i];
        vx_free(&rs->alloc, tmp);
    }
    return r;
}
