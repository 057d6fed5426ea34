/* render/render_internal.h - shared between the render/ sources (not public):
 * the GPU data layout of the trace shaders, the shadow map, the primary rays'
 * starts below the root. The switches benchmarks and tests set are
 * render/testing.h.
 * The layers other modules use are render/trace.h (plain C) and
 * render/gpu.h (Vulkan). */
#ifndef VX_RENDER_INTERNAL_H
#define VX_RENDER_INTERNAL_H

#include "render/gpu.h"
#include "render/testing.h"

/* ---- GPU data layout (must match shaders/trace.comp) -------------------------------- */

typedef struct vx__gpu_model {
    uint32_t node_off, color_off, depth, root;
    uint32_t root_attr, flags;
    uint32_t rebase; /* depth of the nodes whose frame the float walk moves into (0: none; see VX_RENDER_REBASE_DEPTH) */
    /* the model's extent (size) in units of 2^max(depth - 10, 0) cells,
     * rounded up, minus one: 10 bits per axis, x lowest (the ray is clipped
     * to this box, tighter than the 2^depth cube) */
    uint32_t box;
} vx__gpu_model;
/* EXACT: the trace kernel keeps the ray origin as hi/lo and computes a hit's
 * t from its cube's entry planes (models deeper than VX_RENDER_EXACT_DEPTH) */
enum { VX__MODEL_HAS_COLOR = 1u, VX__MODEL_EXACT = 2u, VX__MODEL_FAR = 4u };
/* FAR (host side; the shaders ignore the bit): the model's node words may
 * hold a far pointer. The trace kernel's FAR constant (id 9) is the OR over
 * the scene's models. */
/* Deep models on the float path (issue 18; render/render.h, the rule of
 * VX_RENDER_EXACT_DEPTH): model m's level, 0 (an empty or leaf root, or at
 * most VX_RENDER_EXACT_DEPTH levels), 1 (deeper: the hi/lo origin and a hit's
 * t from its cube's entry planes, the EXACT flag of Model and CModel) or 2
 * (deeper than VX_RENDER_REBASE_DEPTH: also the walk in two frames); *rebase
 * is the depth of the lower frame's nodes at level 2 (depth -
 * VX_RENDER_FRAME_LEVELS: Model.rebase, CModel.rebase), else 0. The trace
 * kernels' DEEP constant (VX__SPEC_DEEP_ID) is the greatest level over the
 * scene's models in both layouts: render_scene.c's (vx__render_scene_deep)
 * and compact_gpu.c's (trace_compact.comp), one rule in render_scene.c. */
uint32_t vx__render_model_deep(const vx_svo_model* m, uint32_t* rebase);
/* Model.box and CModel.box (both layouts' trace kernels clip the ray to it):
 * model m's extent (size) in units of 2^max(depth - 10, 0) cells, rounded up
 * (so conservative), minus one, 10 bits per axis, x lowest. */
uint32_t vx__render_model_box(const vx_svo_model* m);
/* The GPU form of descriptor d in the plain layout's node buffer (issue 21;
 * trace_common.glsl's desc_gpu_form): the low byte the inner mask (valid and
 * not leaf) where the file has the leaf mask, bits 8-31 the file's. Its own
 * inverse on any descriptor (the leaf mask is a subset of the valid mask).
 * render_scene.c turns the descriptors a model's walk reaches; the other
 * words stay the file's. */
static inline uint32_t vx__desc_gpu(uint32_t d) { return (d & 0xFFFFFF00u) | ((d >> 8) & ~d & 0xFFu); }

typedef struct vx__gpu_inst {
    float r[3][4];  /* model-from-world rows (world relative to the frame reference) */
    uint32_t model;
    float cell;     /* world size of one cell (largest column norm of M) */
    uint32_t id;    /* scene instance index */
    float pad;
    float lo[4];    /* rounding errors of r[0..2][3] (the rebased walk of deep models keeps the origin in hi + lo) */
} vx__gpu_inst;

/* A start below the root for the primary rays of one screen tile
 * (trace.comp, one instance): rays whose walk starts well inside one of the
 * children of node X begin at X's loop top with that child next, X's
 * ancestors on the stack, instead of descending from the root. */
#define VX__PATHS 64
typedef struct vx__gpu_path {
    uint32_t info[4];   /* X's depth dx (>= 1), X's word (model-relative), the model, 0 */
    float cube[4];      /* X's corner in the model cube's [1,2] coordinates, its side */
    uint32_t nodes[24]; /* the words of X's ancestors (dx of them), the root first */
} vx__gpu_path;

typedef struct vx__gpu_frame {
    float fwd[4];    /* w: t_start */
    float rx[4];     /* w: ortho */
    float uy[4];     /* w: lod footprint per unit distance */
    float light[4];  /* w: ambient */
    float misc[4];   /* x: lod footprint at distance 0, y: lod pixels */
    uint32_t dims[4];   /* width, height, spp, instance count */
    uint32_t dims2[4];  /* x: dense grid nx, y: ny, z: nz, w: 0; else x, y: the sun map's side and instances */
    float grid_lo[4];   /* dense grid lower corner relative to R, w: cell size; else the sun map's origin, margin */
    /* precise variant only (std140 dvec4 at offset 128): the camera in double */
    double pfwd[4];     /* w: t_start */
    double prx[4];
    double puy[4];
    /* a scene of one instance (vx__render_dispatch; trace.comp's float
     * variant reads them instead of the insts and models buffers, whose
     * loads lavapipe runs lane by lane): instance 0's record and its model's */
    vx__gpu_inst inst0;
    vx__gpu_model model0;
    /* trace.comp and trace_compact.comp: the pixels [rect[0], rect[2]) x
     * [rect[1], rect[3]) that the trace pass covers; the rest miss
     * (vx__frame_cull) */
    uint32_t rect[4];
    /* trace.comp with several instances: the primary rays' BVH start per
     * screen tile (vx__frame_tiles): x the tiles' shift, y tiles a row;
     * all 0 (the root for every tile) where the host sets none */
    uint32_t tile_info[4];
    uint16_t tiles[VX__TILES_X * VX__TILES_X];
    /* trace_compact.comp with one instance and the whole layout resident:
     * that instance's model's CModel (compact_gpu.c cmodel_gpu, 14 words) */
    uint32_t cmodel0[16];
    /* trace.comp with one instance: starts below the root (tiles: per
     * screen tile the index of one, VX__TILE_NONE none; render_scene.c
     * frame_paths) */
    vx__gpu_path paths[VX__PATHS];
    /* trace.comp with one instance: its model's grid (grid_walk.glsl), so that a ray loads neither the grid
     * table's word nor the grid's header: gbox_lo, gbox_hi its cells' box (the header's, render_scene.c
     * grid_header) as floats, grid0 the grid's word address (UINT32_MAX: none, the octree walk); std140 packs
     * each vec3 with the word after it (trace_common.glsl's Frame block); gunion: where grid0 is the union
     * of a converter's regions (render_scene.c grid_union), its cube table's word address */
    float gbox_lo[3];
    uint32_t grid0;
    float gbox_hi[3];
    uint32_t gunion;
} vx__gpu_frame;

/* Precise variant only (binding 9): the instances' model-from-world rows in
 * double, world relative to the frame reference. */
typedef struct vx__gpu_inst_precise {
    double r[3][4];
} vx__gpu_inst_precise;


/* Reads a frame back into img (width, height and alloc set): the vec4 pixels
 * (depth2: a vec2 of depth and coverage each, trace.comp's depth mode, widened
 * to (depth, depth, depth, coverage)), and with hits the records of trace.comp
 * / the pipeline's gbuffer ids (two uvec4 per pixel: instance id, cell; depth
 * bits, iterations). On failure img holds nothing. */
vx_result vx__image_read(vx_gpu* g, vx__buffer* pixels, bool depth2, vx__buffer* hits, vx_render_image* img,
                         vx_error* err);

/* ---- the directional light's depth map (shadow_map.c, shaders/smap.comp) ----------- */

/* At most this many nodes in a scene's list (16 bytes each on the GPU):
 * past it the list takes coarser levels. */
#define VX__SMAP_MAX_NODES (4u << 20)
/* the most texels a side by default (vx_render_scene_desc.shadow_map_side 0),
 * and the texels a side of a cell: 8 on a GPU, 2 on a CPU device (lavapipe),
 * where a build over eph_menger's cells took 4.3 s with 8 (one 1920x1080
 * colour frame there: about 1 s) */
#define VX__SMAP_PER_CELL 8u
#define VX__SMAP_PER_CELL_CPU 2u
#define VX__SMAP_SIDE 2048u

typedef struct vx__smap {
    const vx_allocator* alloc;
    uint32_t side;          /* texels a side; 0: no map for this scene */
    uint32_t node_count, model_count;
    uint32_t* model_first;  /* model_count + 1 starts in the node list, then each model's level */
    double diag;            /* the scene box's diagonal when listed (the margin's scale) */
    vx__buffer nodes, insts, map;
    /* the last build: valid for `light` (the frame block's floats) */
    bool valid;
    float light[3];
    double origin[3];       /* O, world */
    double axis_u[3], axis_v[3], u0, v0, texel; /* the texels (vx_render_shadow_map_info) */
    double margin;          /* world units */
    double list_seconds;    /* the node list (at the first build: the words' read-back, the list, its buffer) */
    double ahead_seconds;   /* the list made on the host ahead (vx_render_sun_nodes_make), 0: none */
    double build_seconds, build_gpu_seconds; /* the last build, wall and GPU time */
    uint32_t builds;
    uint32_t insts_built;   /* entries in the insts buffer (the last build) */
} vx__smap;

const uint32_t* vx__spirv_smap(size_t* bytes);
/* Lists the nodes of s's models (at about one texel of a side-texel map
 * over the box lo, hi; inst_model and inst_cell: the drawn instances' models
 * and cell sizes) and makes the GPU buffers. c not NULL: the models are
 * compact layout c's (its geometry read, s unused; a compact scene's map
 * bounds the same cells). side 0: per_cell texels a side
 * of the finest cell, a power of two in 64..max_side (0: VX__SMAP_SIDE). With no map
 * possible (side 1, no instance, too many nodes) sm->side stays 0. */
struct vx_compact_scene;
vx_result vx__smap_list(vx_gpu* g, const vx_allocator* alloc, const vx_svo_scene* s, const struct vx_compact_scene* c,
                        const uint32_t* inst_model,
                        const float* inst_cell, uint32_t inst_count, const double lo[3], const double hi[3],
                        uint32_t side, uint32_t per_cell, uint32_t max_side, vx__smap* sm, vx_error* err);
/* The host's part of vx__smap_list made ahead, without a device (its
 * arguments as vx__smap_list's); vx__smap_pre_fits tells whether it is the
 * list vx__smap_list would make for side, per_cell and max_side (the scene's
 * instances, models and box the caller compares), vx__smap_pre_use makes
 * sm's GPU buffers from it (emptying it). */
typedef struct vx__smap_pre vx__smap_pre;
vx_result vx__smap_pre_make(const vx_allocator* alloc, const vx_svo_scene* s, const struct vx_compact_scene* c,
                            const uint32_t* inst_model,
                            const float* inst_cell, uint32_t inst_count, const double lo[3], const double hi[3],
                            uint32_t side, uint32_t per_cell, uint32_t max_side, vx__smap_pre** out, vx_error* err);
bool vx__smap_pre_fits(const vx__smap_pre* p, uint32_t side, uint32_t per_cell, uint32_t max_side);
vx_result vx__smap_pre_use(vx_gpu* g, vx__smap_pre* p, vx__smap* sm, vx_error* err);
void vx__smap_pre_free(vx__smap_pre* p);
/* Builds the map for the unit direction light (towards the light) and the
 * drawn instances' world-from-model maps; one submission. */
vx_result vx__smap_build(vx_gpu* g, vx__smap* sm, const float light[3], const double (*world)[12],
                         const uint32_t* inst_model, uint32_t inst_count, const double lo[3], const double hi[3],
                         vx_error* err);
void vx__smap_free(vx_gpu* g, vx__smap* sm);

/* ---- the primary rays' starts below the root (render_scene.c) ------------------------ */

/* The top of a model's octree on the host, for the primary rays' start
 * below the root (vx__render_scene_paths): its descriptors from the root
 * down, level by level, each inner child listed once per parent listed (a
 * DAG's shared block is listed again under each), with its word (the plain
 * layout's model-relative word, the compact layout's slot) and the entry of
 * its first inner child (the others follow in octant order; VX__TOP_NONE
 * where they are not listed). At most vx__top_src.max_nodes entries a model
 * (VX__TOP_NODES where 0): the start stops where the list does. */
typedef struct vx__top_node {
    uint32_t desc, word, kids;
} vx__top_node;
#define VX__TOP_NONE 0xFFFFFFFFu
#define VX__TOP_NODES 4096u
/* A scene of one model: its one list 4x as long, so that the primary rays of a
 * broad model start a level deeper (terrain4096's close-up in trace.comp: 11.6
 * steps a ray, not 12.6, issue 21 rbstart; the helmet's close-up in
 * trace_compact.comp likewise). Scenes of more models keep VX__TOP_NODES: the
 * host holds a list per model (a 65536^3 scene has thousands). */
#define VX__TOP_NODES_ONE (4u * VX__TOP_NODES)
/* vx__top_src.max_nodes for a model of a scene of model_count models (both layouts). */
static inline uint32_t vx__top_cap(uint32_t model_count) { return model_count == 1 ? VX__TOP_NODES_ONE : VX__TOP_NODES; }
/* What vx__top_list reads of a layout: desc(ctx, word) a node's descriptor
 * (valid mask in bits 8..15, leaf mask in bits 0..7, svo/svo.h's form);
 * block(ctx, word, desc, k, &blk) the word of the first of its k inner
 * children (child c at blk + c), false where the words do not hold them
 * (the list then ends); nodes deeper than max_depth (the root 0) are not
 * listed (the compact layout's bricks and pages have no descriptor word). */
typedef struct vx__top_src {
    const void* ctx;
    uint32_t (*desc)(const void* ctx, uint32_t word);
    bool (*block)(const void* ctx, uint32_t word, uint32_t desc, uint32_t k, uint32_t* blk);
    uint32_t max_depth;
    uint32_t max_nodes; /* the list's length limit; 0: VX__TOP_NODES */
} vx__top_src;
/* The list from node root (render_scene.c), *count its entries; NULL without memory. */
vx__top_node* vx__top_list(const vx_allocator* alloc, const vx__top_src* src, uint32_t root, uint32_t* count);
/* The starts of a scene of one instance: the list of its model (top), that
 * model's Model.box and rebase (trace.comp's), the shallowest level node X
 * may have (the compact layout: 3, the page level's parent if paged; 0 or
 * 1: any) and the fewest pushes a start must skip (X's depth; 0 or 1: any).
 * in_frame: X may lie at a rebased model's rebase depth k or below (trace.comp
 * starts such a ray in the frame of X's depth-k ancestor); false: X is at most
 * k - 1 deep (trace_compact.comp, whose walk moves into that frame by a push
 * of its own). */
typedef struct vx__path_model {
    const vx__top_node* top;
    uint32_t box, rebase, min_level, min_dq;
    bool in_frame;
} vx__path_model;
/* Writes the frame block's tile grid (tile_info, tiles) and start records
 * (paths) for f (render_scene.c): per screen tile the record of node X
 * where its primary rays start below the root, VX__TILE_NONE elsewhere;
 * none where the scene has several instances, for LOD, where pm is NULL
 * (the model of the scene's one instance) or the starts are off
 * (vx__render_scene_trace_path). Returns the records written (0: no tile
 * has a start). */
uint32_t vx__render_scene_paths(const vx_render_scene* rs, const vx__frame* f, const vx__path_model* pm,
                                vx__gpu_frame* gf);
/* Whether the trace kernels start primary rays below the root (their
 * PATH_START constants; vx__render_scene_trace_path). */
bool vx__render_scene_path_on(const vx_render_scene* rs);
/* compact_gpu.c: the whole compact layout's buffers for the COMPACT kernels
 * of trace_common.glsl, bindings 1-3 of bufs (geometry slots, attribute
 * words, the palette then the CModel records); false, bufs untouched, for a
 * paged layout or one with its attributes in parts (only trace_compact.comp
 * follows its pages and parts). */
struct vx_compact_gpu;
bool vx__compact_gpu_bind(struct vx_compact_gpu* cg, vx__buffer* bufs[7]);
/* Whether scene s needs each record's material id on the GPU to render as the
 * plain layout does: some model names its materials through a material
 * channel (VX_ATTR_MATERIAL) and some material of the scene is not plain
 * diffuse (emission, metal, glass). Else the palette index (or 0) keys the
 * same materials (render_scene.c). */
bool vx__scene_material_ids_matter(const vx_svo_scene* s);
/* compact_gpu.c: where the whole layout was built with the models' material
 * ids (vx__scene_material_ids_matter at vx_compact_gpu_create: each model with
 * a material channel has its ids encoded beside its colours, CModel flag 8 in
 * the passes' records, and the passes' Hit.attr is the material id), *out
 * the per-"record" table of vx__render_scene_attr_material indexed by that
 * Hit.attr: entry i = i where some record of the scene has material id i,
 * else 0, *n the largest such id + 1 (at least 256). Else *out NULL, *n 0
 * (the layout keys records by palette index). *missing: the ids were needed
 * but some model with the channel had no arrays to read them from (a scene
 * from a model reader, svo_bake --load models), so none were built. */
vx_result vx__compact_gpu_materials(const struct vx_compact_gpu* cg, const vx_allocator* alloc, uint16_t** out,
                                    size_t* n, bool* missing, vx_error* err);
/* Bytes of the material ids on the GPU (0: none built). */
uint64_t vx__compact_gpu_material_bytes(const struct vx_compact_gpu* cg);
/* The bytes one storage buffer binding may hold for rs: its desc's
 * max_buffer_range where set below the device's maxStorageBufferRange. */
uint64_t vx__render_scene_buffer_range(const vx_render_scene* rs);

#endif
