/* render/render.h - Vulkan compute tracer and CPU reference for .svo scenes.
 *
 * A scene (svo/svo.h) is a set of per-model sparse voxel octrees placed by
 * affine instances. The GPU tracer walks a BVH over the instances' world
 * bounds (binned SAH, built on the CPU) and then each model's octree in the
 * manner of Laine & Karras (octant mirroring, the [1,2] cube, a stack of 23
 * levels), with the ray taken into model space by the inverse matrix. The CPU
 * reference (vx_render_cpu) traces the same rays in double precision with a
 * per-model 3D-DDA over the decoded voxels and a brute-force loop over the
 * instances; tests compare the two pixel by pixel.
 *
 * Usage:
 *   vx_gpu* gpu; vx_gpu_create(&(vx_gpu_desc){0}, &gpu, &err);
 *   vx_render_scene* rs; vx_render_scene_create(gpu, &scene, &rs, &err);
 *   vx_render_image img = {0};
 *   vx_render_frame(rs, &(vx_render_desc){ .width = 640, .height = 480 }, &img, &err);
 *   ... img.pixels ...; vx_render_image_free(&img);
 *   vx_render_scene_destroy(rs); vx_gpu_destroy(gpu);
 *
 * Conventions:
 *  - Rays live in world space: grid space mapped by scene.world_from_grid.
 *    Depth is the world distance along the unit ray direction from the eye
 *    (perspective) or from the image plane through the eye (orthographic), so
 *    t values compare across instances.
 *  - A ray whose origin lies inside a voxel hits it at t = 0. On a cell
 *    boundary a direction component of +0 counts as positive and -0 as
 *    negative (the ray is taken to be displaced infinitesimally that way).
 *    When a ray crosses an edge or a corner exactly, it steps into the
 *    diagonal cell (all tied axes at once).
 *  - The hit voxel is the model cell containing the hit point, inside the
 *    leaf that was hit (a collapsed leaf or, with lod, a coarse node).
 *  - Models deeper than VX_RENDER_MAX_DEPTH levels are refused at load.
 *  - Scenes with a model deeper than VX_RENDER_PRECISE_DEPTH levels are traced
 *    by a float64 variant of the shader (needs shaderFloat64; such scenes are
 *    refused at load on devices without it); all others by the float one.
 *  - This header does not include vulkan.h; a host application may pass
 *    its own VkInstance/VkPhysicalDevice/VkDevice/VkQueue as const void*.
 *  - The scene is borrowed only during vx_render_scene_create (everything
 *    is copied to GPU buffers and to host-side tables) and the updates
 *    (vx_render_scene_set_frame, vx_render_scene_update_model).
 */
#ifndef VX_RENDER_H
#define VX_RENDER_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "svo/svo.h"

#ifdef __cplusplus
extern "C" {
#endif

#define VX_RENDER_MAX_DEPTH 21u /* 23-bit mantissa of [1,2): finest cell = 4 ulps */

/* Deepest model traced by the float variant; scenes with a deeper model use
 * the float64 one. Float Laine-Karras keeps positions in the [1,2] cube, so
 * a depth-d cell is 2^(23-d) ulps and the ray's position is quantised to
 * ~2^(d-23) of a cell (more than the ray set-up's error). Measured on
 * lavapipe against the CPU reference with the strict rule (same cell, depth
 * within 1e-4 relative) on close-ups where a pixel is 1/10 to 1/3 of a cell
 * (tests/render/test_render_gpu.c, deep octrees): float mismatches 0% at
 * depth 8, 0.01% at 10, 0.04% at 12, 0.2% at 14, 0.7% at 16, 1.1% at 17,
 * 2.4% at 18, 5-9% at 20-21; float64 0% at every depth. 16 is the deepest
 * level at which the float error stays below 1/100 of a cell (a cell must
 * fill ~128 pixels before it spans one), so .vox scenes (<= 8 levels),
 * converted meshes and volumes and the 4096^3 benchmark terrain keep the
 * fast path: float64 costs ~25% on lavapipe and far more on GPUs with slow
 * float64. (These figures are the plain float walk's; models 9-16 levels
 * deep now take the exact and two-frame paths below, within 0.01%.) */
#define VX_RENDER_PRECISE_DEPTH 16u

/* Deep models on the float path (issue 18). The float walk in the model's
 * [1,2] cube keeps 23 - depth bits below a cell, and its crossing times
 * pos * coef - bias lose as many to cancellation; the ray set-up rounds the
 * origin to 2^-24 of the cube. Against the CPU reference under the strict
 * rule (same cell, depth within 1e-4 relative; tests/render/test_render_gpu.c,
 * test_deep_float) the plain walk's depths miss from 9 levels on (0.015% of
 * close-up pixels at 9, 0.7% at 10, 12% at 12) and its cells from 11 (0.013%
 * at 11, 0.024% at 12, 0.6% at 16). So:
 *  - models deeper than VX_RENDER_EXACT_DEPTH keep the ray origin as a hi/lo
 *    pair and take a hit's t from its cube's entry planes (exact differences),
 *    not from the walk;
 *  - models deeper than VX_RENDER_REBASE_DEPTH are also walked in two frames:
 *    when the walk descends into a node at depth depth - VX_RENDER_FRAME_LEVELS
 *    it moves the ray into that node's [1,2] cube (origin from the hi/lo pair),
 *    so that no frame spans more than VX_RENDER_FRAME_LEVELS levels; the upper
 *    frame keeps 23 - (depth - VX_RENDER_FRAME_LEVELS) bits at that depth.
 * The float path then matches the reference on at least 99.99% of the
 * close-up pixels up to VX_RENDER_PRECISE_DEPTH. Frames as deep as the
 * precision allows make the lower frame's nodes wide, so that rays move
 * between frames rarely (with depth/2 a grazing ray crossed dozens of them
 * on the 4096^3 terrain; at depth - 9 its close-up's rays rebase 1.21 times
 * and return 0.23 times each, its oblique's 2.2 and 1.9: on the H200 these
 * switches cost ~9% of the time and the two-frame code's fixed part ~13%,
 * against one frame, issue 21, deep3). A primary ray that trace.comp starts
 * below the root at a node X at depth k or deeper (the host's per-tile start)
 * begins in the frame of X's depth-k ancestor, its switch made before the
 * walk's loop (the close-up's switches from the loop 1.21 -> 0.21 a ray, its
 * steps 15.6 -> 11.6 with X a level deeper from a longer listed top, 7.5%
 * more rays/s on the H200; issue 21, rbstart). A return out of N into a
 * sibling that is an inner node goes straight to that sibling's switch, the
 * loop's step there taken outside the loop (the same decisions; 0.78 of the
 * oblique's 1.86 returns a ray, 1.4-2.6% more rays/s on terrain4096's views
 * on the H200; issue 21, late). Walking a few levels below k in the model
 * frame before switching (a late switch) cut the switches 4x but changed
 * pixels and lost speed: not kept (same).
 * Shallower models keep the plain
 * loop: the trace kernel's REBASE constant is off for scenes without a model deeper than
 * VX_RENDER_EXACT_DEPTH (shaders/trace_common.glsl, trace_model). Every
 * kernel that traces a scene takes the same DEEP constant
 * (vx__render_scene_deep, render/gpu.h): trace.comp, the pass pipeline's
 * (gbuffer, direct, ao, frame.comp), the probe bake's, photons' and cones'
 * (until issue 18's gdeep all but trace.comp ran the plain loop). */
#define VX_RENDER_EXACT_DEPTH 8u
#define VX_RENDER_REBASE_DEPTH 10u
#define VX_RENDER_FRAME_LEVELS 9u

/* ---- device ------------------------------------------------------------------------ */

typedef struct vx_gpu vx_gpu;

/* Device options; zero-initialised means the defaults.
 *  device:   NULL or "" picks a discrete GPU, then integrated, then any
 *            (lavapipe); "N" picks the N-th physical device; "gpu:K" the
 *            (K mod G)-th of the G devices that are GPUs (not CPU or other
 *            devices), in the order Vulkan lists them (the default pick where
 *            there is none): an MPI rank's GPU by its local rank without a
 *            second instance to count them; anything
 *            else picks the first device whose name contains it.
 *  validate: enables VK_LAYER_KHRONOS_validation (an error if it is not
 *            installed) and records every validation error; the environment
 *            variable VX_GPU_VALIDATION=1 does the same.
 *  logger:   receives validation messages ("gpu.validation") and notes.
 *  external: a host app's VkInstance, VkPhysicalDevice, VkDevice, VkQueue and
 *            queue family, used instead of creating them (not destroyed). */
typedef struct vx_gpu_desc {
    const char* device;
    bool validate;
    const vx_logger* logger;   /* kept by the device: must outlive it */
    const vx_allocator* alloc; /* copied into the device; its user_data must outlive the device */
    struct {
        const void* instance;
        const void* physical_device;
        const void* device;
        const void* queue;
        uint32_t queue_family;
        bool float64; /* the host enabled shaderFloat64 (needed for models deeper than VX_RENDER_PRECISE_DEPTH) */
        bool storage_write; /* the host enabled shaderStorageImageWriteWithoutFormat (render/display.h writes
                               B,G,R,A images itself; vx_gpu_make_device enables it where offered) */
    } external;
} vx_gpu_desc;

vx_result vx_gpu_create(const vx_gpu_desc* desc, vx_gpu** out, vx_error* err);
void vx_gpu_destroy(vx_gpu* gpu);
const char* vx_gpu_device_name(const vx_gpu* gpu);
bool vx_gpu_is_cpu(const vx_gpu* gpu); /* lavapipe or another CPU device */
/* Validation errors recorded since creation (0 without validation). */
uint32_t vx_gpu_validation_errors(const vx_gpu* gpu);
/* Picks a physical device and queue family of a Vulkan instance (a
 * VkInstance) the way vx_gpu_create does, for hosts that make their own
 * device (svo_view's window): `want` is an index or a part of the device
 * name (NULL or "": the best kind, discrete, integrated, virtual, then CPU);
 * the family has a compute queue (timestamps preferred) that
 * family_ok(user, physical device, family) accepts (NULL: any), e.g. one that
 * can present to a window; `needs` says what is required, for the error
 * message (NULL: "a compute queue"). *physical_device is a VkPhysicalDevice. */
vx_result vx_gpu_pick_device(const void* instance, const char* want,
                             bool (*family_ok)(void* user, const void* physical_device, uint32_t family), void* user,
                             const char* needs, const void** physical_device, uint32_t* family, vx_error* err);
/* Creates a VkDevice (*device) with one queue of `family` and the features
 * the tracer uses (shaderFloat64 where the device has it: *float64), plus
 * the given device extensions (a window's swapchain); the caller destroys it. */
vx_result vx_gpu_make_device(const void* physical_device, uint32_t family, const char* const* extensions,
                             uint32_t extension_count, const void** device, bool* float64, vx_error* err);
/* Lists physical devices: calls fn(user, index, name, type) for each, where
 * type is "discrete", "integrated", "virtual", "cpu" or "other". */
vx_result vx_gpu_list_devices(void (*fn)(void* user, uint32_t index, const char* name, const char* type),
                              void* user, vx_error* err);

/* ---- rendering --------------------------------------------------------------------- */

typedef enum vx_render_mode {
    VX_RENDER_COLOR = 0,  /* attribute colour, one directional light with hard shadows, sky ambient */
    VX_RENDER_ALBEDO,     /* attribute colour */
    VX_RENDER_NORMAL,     /* world-space geometric normal (float) */
    VX_RENDER_DEPTH,      /* ray t in world units, +inf for a miss (float) */
    VX_RENDER_INSTANCE,   /* a colour per instance id */
    VX_RENDER_ITERATIONS, /* heat map of traversal steps */
    VX_RENDER_MODE_NUM
} vx_render_mode;

/* Camera; all zero frames the scene bounds from a fixed direction.
 *  set:    use eye/target/up below (otherwise the default framing)
 *  up:     zero == (0, 0, 1) (MagicaVoxel's up axis)
 *  fov:    vertical field of view in degrees, 0 == 45
 *  ortho:  orthographic; ortho_height is the view height in world units,
 *          0 == frame the scene bounds */
typedef struct vx_render_camera {
    bool set;
    double eye[3], target[3], up[3];
    double fov;
    bool ortho;
    double ortho_height;
} vx_render_camera;

/* Frame options; zero-initialised means the defaults.
 *  width, height: 0 == 640 x 480 (at most 16384 each)
 *  spp:           samples per pixel, 0 == 1 (sample 0 is the pixel centre)
 *  lod:           stop descending where a voxel projects smaller than lod_pixels
 *                 pixels and use the coarse level's attribute (GPU only)
 *  lod_pixels:    0 == 1
 *  light_dir:     towards the light, zero == (0.35, -0.45, 0.82)
 *  ambient:       sky light share, 0 == 0.3
 *  want_hits:     also return per-pixel hit records (sample 0)
 *  beam:          vx_render_frame on a GPU: 0 or 1 == off (the default); N (2..64):
 *                 a first pass finds per block of N x N pixels where its rays
 *                 can first meet a non-empty node, and they start there (the
 *                 same cells and depths, fewer steps). It pays on sparse
 *                 scenes whose rays cross much empty space inside the octree
 *                 (8 is a good N there); elsewhere it costs more than it
 *                 saves (docs/PERFORMANCE.md, issue 21). Not used with lod
 *                 or by the float64 variant
 *  no_shadow_map: vx_render_frame on a GPU, VX_RENDER_COLOR: trace every
 *                 shadow ray to the scene's end. By default (false) each
 *                 shadow ray ends where the light's depth map says no
 *                 geometry lies further towards the light (the same image;
 *                 see vx_render_scene_shadow_map_info). Not used with lod,
 *                 by the float64 variant or by the compact layout */
typedef struct vx_render_desc {
    uint32_t width, height;
    vx_render_mode mode;
    uint32_t spp;
    vx_render_camera camera;
    bool lod;
    double lod_pixels;
    double light_dir[3];
    double ambient;
    bool want_hits;
    uint32_t beam;
    bool no_shadow_map;
} vx_render_desc;

/* What a zero-initialised desc means, field by field (the tools' --help
 * prints these): 640x480, 1 spp, fov 45, ambient 0.3, lod_pixels 1, light
 * (0.35, -0.45, 0.82); camera unset (frame the scene bounds). */
vx_render_desc vx_render_desc_defaults(void);

#define VX_RENDER_NO_HIT 0xFFFFFFFFu

/* What the centre ray of a pixel hit. instance is VX_RENDER_NO_HIT for a
 * miss; cell is the hit model cell; t the depth. */
typedef struct vx_render_hit {
    uint32_t instance;
    uint32_t cell[3];
    float t;
    uint32_t iterations;
    uint32_t flags; /* VX_RENDER_HIT_* */
    /* VX_RENDER_COLOR on a GPU (vx_render_frame): VX_RENDER_SHADOW_CAST when
     * the pixel cast a shadow ray, ORed with that ray's loop iterations
     * (0 where a shadow map showed it needs no walk); 0 elsewhere */
    uint32_t shadow;
} vx_render_hit;
#define VX_RENDER_SHADOW_CAST 0x80000000u

/* CPU reference only: the ray started exactly on a cell boundary or crossed
 * an edge or corner exactly before the hit; float tracing may break such a
 * tie differently (tests report these pixels separately). */
#define VX_RENDER_HIT_AMBIGUOUS 1u
/* Compact layout with pages (render/compact.h): the ray entered a page that
 * was not resident; the hit is that page's cube, drawn in its mean colour. */
#define VX_RENDER_HIT_COARSE 2u

/* Output of a frame. pixels: width*height*4 floats, RGBA, row 0 at the top
 * (colour modes in [0,1]; normal: xyz; depth: t in every channel); hits is
 * NULL unless want_hits. Free with vx_render_image_free. */
typedef struct vx_render_image {
    uint32_t width, height;
    vx_render_mode mode;
    float* pixels;
    vx_render_hit* hits;
    double gpu_seconds;    /* from timestamp queries (CPU: wall time) */
    uint64_t rays;         /* primary rays traced (width * height * spp) */
    const vx_allocator* alloc;
} vx_render_image;

void vx_render_image_free(vx_render_image* img);

/* The scene on the GPU. */
typedef struct vx_render_scene vx_render_scene;

/* An animated scene is created at frame 0 (its `instances`), with every
 * model of every frame on the GPU; the default camera frames all frames
 * (vx_svo_scene_world_bounds), so it holds still over a sequence. */
vx_result vx_render_scene_create(vx_gpu* gpu, const vx_svo_scene* scene, vx_render_scene** out, vx_error* err);
/* Shows frame `frame` of `scene`, the scene rs was created from: the
 * instances and their BVH are rebuilt, the models stay on the GPU (no
 * upload). Also takes instance edits (the records of any frame changed,
 * instances added or removed, the same models): the default camera's bounds
 * are taken again from every frame of `scene` (for an animation that was not
 * edited, the bounds it had). Waits for the device to be idle first, except
 * when the same number of instances is drawn (moves, turns, a frame of an
 * animation): then the tables are made again in place and the BVH keeps its
 * shape, its bounds refit bottom-up (vx_bvh_refit; built again when the refit
 * tree would cost twice the built one), on the host for frames the host
 * writes and on the GPU with each recorded frame (pipeline.h
 * vx_frame_record). The nearest hit does not depend on the tree, except
 * where two instances' surfaces coincide (equal depth): such ties may then
 * fall to the other instance than in a scene built from scratch. */
vx_result vx_render_scene_set_frame(vx_render_scene* rs, const vx_svo_scene* scene, uint32_t frame, vx_error* err);
void vx_render_scene_destroy(vx_render_scene* rs);

/* The layout a render scene keeps on the device (issue 18). The plain one is
 * the .svo node words plus a 4-byte colour record per leaf record: every
 * pass, the probes, GI, edits and the float64 variant read it. The compact
 * one (render/compact.h: a geometry DAG shared regardless of colour, exact
 * colours in coded blocks; DamagedHelmet at 4096^3 1.40 bytes per voxel
 * against 5.07) is traced by vx_render_frame (its modes, spp, shadow rays;
 * no LOD, and the beam pass is not used), at 0.62-0.94 of the plain kernel's
 * rays/s on the H200 (docs/PERFORMANCE.md), and by the passes, the probe
 * bake and the GI methods (trace_common.glsl's COMPACT kernels: the plain
 * layout's images), so it is chosen only where the plain layout does not
 * fit. Where the compact layout does not fit either, it is paged
 * (vx_render_page_stats below): the levels above the page level resident,
 * the pages below loaded as rays ask for them; only vx_render_frame traces
 * a paged scene. */
typedef enum vx_render_layout {
    VX_RENDER_LAYOUT_AUTO = 0, /* plain where its node words and records fit memory_budget, else compact */
    VX_RENDER_LAYOUT_PLAIN,
    VX_RENDER_LAYOUT_COMPACT,
} vx_render_layout;
typedef struct vx_render_scene_desc {
    vx_render_layout layout;
    /* bytes the plain layout's node words and records may take (AUTO);
     * 0: three quarters of the device's largest device-local heap. Where
     * the compact layout exceeds it too, the compact layout is paged and
     * this bounds the top and the page pool together */
    uint64_t memory_budget;
    /* the paged layout's page level (3..31; 0: VX_RENDER_FRAME_LEVELS, the
     * two-frame walk's lower frame: pages of 512^3 cells; lowered to three
     * below the deepest model's depth where that is shallower) */
    uint32_t page_level;
    /* the directional light's depth map (vx_render_scene_shadow_map_info):
     * texels a side, 0: by the scene (8 a cell, 2 on a CPU device; a power
     * of two in 64..2048); 1: no map (the node list is not made); others
     * are clamped to 16..16384 */
    uint32_t shadow_map_side;
    /* the compact layout's 4^3 bricks (render/compact.h): VX_RENDER_BRICKS_AUTO
     * (0) in their blocks, the brick dictionary where the layout exceeds the
     * budget and the dictionary's geometry is smaller (about 0.65x that of a large
     * surface scene; a second load per push into a brick, docs/PERFORMANCE.md
     * issue 18, seventh step); INLINE or DICT: that one */
    uint32_t compact_bricks;
    /* bytes one storage buffer binding may hold (0: the device's
     * maxStorageBufferRange; a smaller value applies where below it: tests
     * split a small scene as a large one is on any device). AUTO takes the
     * compact layout where the plain one's node words or records exceed it;
     * the compact attribute words beyond it go to up to VX_COMPACT_ATTR_PARTS
     * buffers (render/compact.h; then the single-shader frame only) */
    uint64_t max_buffer_range;
    /* vx_render_scene_create_compact: the caller made AUTO's brick choice
     * for its layout already (vx_render_compact_auto_bricks, before the
     * device existed), in file_passes passes over the file (for the layout's
     * report); false: create_compact makes it (a second pass over the file
     * there, after the device: a device idle through it lowers the H200's
     * clock, docs/PERFORMANCE.md issue 18, branches load2 and rdr2) */
    bool bricks_decided;
    uint32_t file_passes;
    /* vx_render_scene_create_reader (and _create_paged): 0, the compact
     * layout built whole from the reader (and paged from it in memory where
     * it exceeds memory_budget: the host holds every page image). > 0: the
     * file source: the compact layout (where it is the layout: asked for, or
     * AUTO's choice; a plain one is read whole as before) paged from the file
     * whatever its size,
     * the host holding the top and a cache of at most host_budget bytes of
     * page images (least recently used out first), each page cut from its
     * model read again from the file when a frame needs it and the cache does
     * not hold it (render/compact.h, vx_compact_page_build_reader); the reader
     * stays borrowed by the scene until vx_render_scene_destroy */
    uint64_t host_budget;
    /* the grid walk (issue 21; render/grid.h): vx_render_frame's trace walks
     * a model that has a grid by a hierarchical DDA over 8^3-cell bricks,
     * skipping empty space by distance, instead of descending its octree (the
     * same cells and hits). Grids are built from the plain layout's models of
     * at most VX_RENDER_GRID_DEPTH levels at creation, in model order while
     * their bytes stay within grid_budget: 0 VX_RENDER_GRID_BUDGET on every
     * device (on lavapipe too since issue 21's stop 87: there the grid walk
     * was at least 1.0x the ESVO baseline per CPU second on 17 of 21 bench
     * views, the octree walk on 16, terrain4096's close-up 1.4-1.7x against
     * 0.7x), VX_RENDER_NO_GRID none. An edited model's grid (vx_render_scene_update_model)
     * is made again where it took at most 1 MiB (a few ms a stroke); a larger
     * one is dropped and the model walks its octree. The pass pipeline's kernels that trace
     * (G-buffer, direct, AO, the merged frame: render/pipeline.h) take the
     * same walk by the same rule; probes and the GI methods' kernels walk the
     * octrees. */
    uint64_t grid_budget;
} vx_render_scene_desc;
#define VX_RENDER_GRID_BUDGET (UINT64_C(1) << 30)
#define VX_RENDER_NO_GRID UINT64_C(1)
#define VX_RENDER_GRID_DEPTH 13u
enum { VX_RENDER_BRICKS_AUTO = 0, VX_RENDER_BRICKS_INLINE = 1, VX_RENDER_BRICKS_DICT = 2 };
/* vx_render_scene_create with a layout choice (desc NULL: all defaults).
 * A compact scene refuses what only the plain layout serves
 * (vx_render_scene_update_model, LOD, models past VX_RENDER_PRECISE_DEPTH;
 * a paged one also the passes that bind the scene) with
 * VX_ERR_UNSUPPORTED. Where the models carry a material channel naming
 * materials other than plain diffuse, the compact layout keeps each
 * record's material id beside its colour (layout_info.material_bytes), so
 * the passes and GI methods render as the plain layout does; a compact
 * layout built from a model reader (vx_render_scene_create_compact, the
 * models' arrays not in hand) has none and refuses those passes and GI
 * methods of such a scene (docs/FORMAT.md 4.1);
 * AUTO falls back to the plain layout where the compact one cannot render
 * the scene. */
vx_result vx_render_scene_create_ex(vx_gpu* gpu, const vx_svo_scene* scene, const vx_render_scene_desc* desc,
                                    vx_render_scene** out, vx_error* err);
/* vx_render_scene_create_ex of the scene a model reader (svo/svo.h) gives,
 * that has handed over no model yet. With the compact layout (as AUTO picks
 * it from the models' declared counts, or asked for) the layout is built
 * model by model (vx_compact_build_reader): the host holds the layout and
 * the models in hand, not the scene (the 65536^3 helmet: 86 GiB read whole).
 * A compact layout over the memory budget is paged as create_ex pages it
 * (the pages are cut from the layout); with AUTO's bricks it is first built
 * again with the brick dictionary from a second pass over the file
 * (vx_svo_reader_rewind) and kept where its geometry is smaller, as
 * create_ex keeps it (the host then holds both layouts and the models in
 * hand, not the scene). The plain layout reads the scene whole first.
 * The reader is used up either way (finished on success); the graph
 * (vx_svo_reader_scene) then has its bounds and cells' boxes. */
vx_result vx_render_scene_create_reader(vx_gpu* gpu, vx_svo_model_reader* reader, const vx_render_scene_desc* desc,
                                        vx_render_scene** out, vx_error* err);
/* The second half of vx_render_scene_create_reader, for a caller that built
 * the compact layout from the reader itself (vx_compact_build_reader, with
 * attr_regions; before the device existed, say): the scene is in the
 * compact layout whatever desc->layout says, checked against desc's budget
 * as there (AUTO's bricks too: a layout c in blocks over the budget is built
 * again with the dictionary from a second pass over the reader's file, so
 * the reader must be the one c was built from, finished), and `c` is taken
 * (freed whatever the result). build_seconds goes to the layout's report. */
struct vx_compact_scene;
/* The layout vx_render_scene_create_ex (or _reader) takes for s on gpu: desc's,
 * or AUTO's choice from the models' declared counts (a reader's graph serves). */
vx_result vx_render_scene_choose_layout(vx_gpu* gpu, const vx_svo_scene* s, const vx_render_scene_desc* desc,
                                        vx_render_layout* out, vx_error* err);
vx_result vx_render_scene_create_compact(vx_gpu* gpu, vx_svo_model_reader* reader, struct vx_compact_scene* c,
                                         double build_seconds, const vx_render_scene_desc* desc,
                                         vx_render_scene** out, vx_error* err);
/* The file source (desc->host_budget): the paged layout's top and page table
 * from a fresh reader, one model at a time (vx_compact_page_build_reader at
 * the page level create_ex would take: desc's, lowered below the drawn
 * models' depth); the reader is finished and borrowed by *out. Then, after
 * the device exists, vx_render_scene_create_paged makes the render scene of
 * it (p is taken; the reader stays borrowed until the scene is destroyed):
 * the pool is memory_budget (or 3/4 of the device's largest local heap) less
 * the top, the host cache desc->host_budget bytes (0: none). A budget that
 * cannot hold the top and the largest page is refused (VX_ERR_LIMIT). */
struct vx_compact_paged;
vx_result vx_render_page_build_reader(vx_svo_model_reader* rd, const vx_render_scene_desc* desc, struct vx_compact_paged* out,
                                      vx_error* err);
vx_result vx_render_scene_create_paged(vx_gpu* gpu, vx_svo_model_reader* rd, struct vx_compact_paged* p,
                                       double build_seconds, const vx_render_scene_desc* desc, vx_render_scene** out,
                                       vx_error* err);
/* AUTO's brick choice for compact layout c built in blocks from reader rd
 * (vx_compact_build_reader, finished): where c exceeds budget (and desc's
 * bricks are AUTO), the layout built again with the brick dictionary from a
 * second pass over the file (vx_svo_reader_rewind; the attributes moved, not
 * built again) and kept where its geometry is smaller, as create_ex keeps it;
 * *passes (may be NULL) the passes made. For a caller that builds before it
 * makes the device (svo_render), then passes desc with bricks_decided to
 * vx_render_scene_create_compact. */
vx_result vx_render_compact_auto_bricks(vx_svo_model_reader* rd, const vx_render_scene_desc* desc, uint64_t budget,
                                        struct vx_compact_scene* c, uint32_t* passes, vx_error* err);
/* The memory budget AUTO compares with: desc's, else 3/4 of gpu's largest
 * device-local heap (0 without either). */
uint64_t vx_render_scene_budget(const vx_gpu* gpu, const vx_render_scene_desc* desc);
typedef struct vx_render_layout_info {
    vx_render_layout layout; /* PLAIN or COMPACT: the one in use */
    uint64_t bytes;          /* its scene buffers (node words and records, or the compact geometry and attributes) */
    uint64_t plain_bytes;    /* the plain layout's node words and records (4 bytes each), whichever is in use */
    uint64_t budget;         /* the budget AUTO compared plain_bytes with */
    uint64_t voxels;         /* cells set, summed over the models */
    uint32_t pages;          /* the compact layout paged: its pages (0: all of it resident) */
    uint32_t page_level;
    uint64_t compact_bytes;  /* the compact layout unpaged (0: not built) */
    bool brick_dict;         /* the compact layout with its brick dictionary */
    uint32_t file_passes;    /* built from a model reader: its passes over the file (2: AUTO's brick
                                dictionary built in a second pass); 0: from a scene in memory */
    /* the compact attribute words' storage buffers: 1, or more where they
     * exceed one buffer's range (then the passes refuse the scene, as a paged
     * one; vx_render_frame traces it); 0 for the plain or paged layout */
    uint32_t attr_parts;
    uint64_t geom_bytes;     /* of compact_bytes, the geometry (the rest: attributes) */
    /* of bytes, the compact layout's material ids: built only where a model
     * names its materials through a material channel and some material of
     * the scene is not plain diffuse (the passes' lit frames need each
     * record's material id then); 0 otherwise and for the plain layout */
    uint64_t material_bytes;
    double build_seconds;    /* the compact layout's build on the host (vx_compact_build) */
    double attr_seconds;     /* of which its attributes (on one thread per CPU) */
    double geom_seconds;     /* of which its geometry DAG, on geom_threads threads */
    uint32_t geom_threads;
    double upload_seconds;   /* its start tables and upload (vx_compact_gpu_create), or the pages' */
    uint64_t grid_bytes;     /* the grid walk's grids (vx_render_scene_desc.grid_budget), 0: none */
    uint32_t grid_models;    /* the models that have one */
    uint32_t grid_cubes;     /* of those, the grids over a cube smaller than their model's: the one of their
                                cells' box (render/grid.h vx__grid_cube), less memory on a slab or a small
                                group of cells in a large model */
    double grid_seconds;     /* their build on the host */
} vx_render_layout_info;
/* Paging (render/compact.h "pages"): each frame first loads the pages the
 * previous frame's rays requested, as many as the pool holds; rays that
 * enter a page not resident draw its cube in its mean colour
 * (VX_RENDER_HIT_COARSE) and request it, so a still camera converges in a
 * few frames where its pages fit. The state after the last frame: */
typedef struct vx_render_page_stats {
    uint32_t pages;        /* pages of the scene */
    uint32_t resident;     /* resident now */
    uint32_t coarse;       /* pages the last frame drew coarse (and requested) */
    uint32_t loaded;       /* loaded before the last frame */
    uint32_t evicted;      /* evicted before the last frame */
    uint32_t refused;      /* requested pages the pool could not take before the last frame */
    uint32_t moved;        /* resident pages slid elsewhere in the pool before the last frame (uploaded again) */
    uint64_t refused_bytes; /* their bytes (over the budget) */
    uint64_t top_bytes;    /* the resident top (slots, ranks, attributes, models, palette, page table) */
    uint64_t pool_bytes;   /* the pool */
    uint64_t used_bytes;   /* the pool's bytes held by resident pages */
    uint64_t frames;       /* frames traced */
    /* the file source (vx_render_scene_desc.host_budget): page images cut from
     * the file as frames need them, through a host cache (totals since the
     * scene was made) */
    bool from_file;
    uint64_t host_budget;     /* the cache's bound */
    uint64_t host_bytes;      /* images it holds now */
    uint64_t host_peak_bytes; /* the most it held */
    uint64_t host_hits;       /* loads served from it */
    uint64_t file_pages;      /* loads cut from the file */
    uint64_t file_models;     /* models read from the file for them */
    uint64_t host_evictions;  /* images the cache's bound pushed out */
    uint64_t file_prefetched; /* of file_pages, those cut ahead (after the frame that requested them) */
    uint64_t moved_from_pool; /* moved pages whose images were read back from the pool (not the cache or the file) */
} vx_render_page_stats;
/* Zeroes unless the scene is paged. */
void vx_render_scene_page_stats(const vx_render_scene* rs, vx_render_page_stats* out);
void vx_render_scene_layout(const vx_render_scene* rs, vx_render_layout_info* out);
const char* vx_render_layout_name(vx_render_layout layout);
/* Model `model` of `scene` (the scene rs was made from, the same model
 * count) changed in place by a vx_svo_editor (svo/edit.h), or an older or
 * newer header of such a model was restored (undo, redo): only what changed
 * goes to the GPU, not the model.
 *  - Node words [words_from, node_count) and attribute records
 *    [records_from, attr_count) are uploaded: an apply's
 *    vx_svo_edit_stats.words_from / records_from; a restored header gives
 *    UINT32_MAX (an editor never rewrites a word, so what rs holds stays
 *    valid). Words rs never received (a scene made while the model held
 *    fewer) are uploaded whatever words_from says, and so are words below
 *    words_from that hold descriptors no earlier root reached (the GPU
 *    holds reachable descriptors in its own form, render_internal.h's
 *    vx__desc_gpu). A descriptor the root reaches that points outside the
 *    model's words is VX_ERR_BAD_FORMAT.
 *  - The models share one buffer of node words and one of colours, made
 *    with headroom (1/16 plus 64 Ki entries); a model's appends go after
 *    its words when its region is the last one, else the region moves
 *    there first (a copy on the GPU, no upload); a buffer that has no room
 *    left is replaced by a larger one (a copy on the GPU).
 *  - The model's root, depth and offsets are rewritten; a new size, or a
 *    model that became empty or non-empty, rebuilds the instance tables and
 *    the BVH of the frame shown (as vx_render_scene_set_frame) and the
 *    default framing's bounds.
 *  - Colours come from the scene's palette as at creation: entries that
 *    kept records use must not have changed.
 * Waits for the device (one submission; none on devices whose buffers are
 * host visible, unless a region moves or grows). On failure the GPU scene
 * shows the model as before (a failed rebuild of the instance tables leaves
 * them as a failed vx_render_scene_set_frame does). */
vx_result vx_render_scene_update_model(vx_render_scene* rs, const vx_svo_scene* scene, uint32_t model,
                                       uint32_t words_from, uint32_t records_from, vx_error* err);
/* What went to the GPU since vx_render_scene_create: node words and colour
 * records uploaded (the models' at creation, then the appends
 * vx_render_scene_update_model uploads; a region moved or a buffer grown by
 * a GPU copy is not an upload), its calls, and the rebuilds of the instance
 * tables and BVH (vx_render_scene_set_frame, and update_model when a size
 * changed). Editors check with it that an edit uploaded what it should. */
typedef struct vx_render_scene_stats {
    uint64_t node_words_uploaded, records_uploaded;
    uint32_t model_updates, instance_rebuilds;
    /* of the rebuilds, those in place: the same number of instances drawn,
     * the BVH rebuilt on the CPU into the buffers it had, no buffer made and
     * no wait for the device (frames in flight keep running) */
    uint32_t instance_updates_in_place;
    /* of those, the ones that kept the BVH's shape: its bounds refit on the
     * host (vx_bvh_refit, for frames the host writes) and on the GPU with
     * each recorded frame's tables (vx_frame_record) instead of a build */
    uint32_t instance_refits;
    /* rows of the instance table and of the BVH's (its nodes, or the
     * refit's instance boxes) that recorded frames wrote to the GPU: only
     * those that changed since the last recorded frame (an instance moved
     * under a still camera: its row and box), all of them when the camera
     * moved (the rows are relative to it) */
    uint64_t table_rows_uploaded;
    /* grids of edited models made again by update_model (vx_render_scene_desc.grid_budget: the grid walk
     * kept after a stroke) */
    uint32_t grids_rebuilt;
} vx_render_scene_stats;
void vx_render_scene_get_stats(const vx_render_scene* rs, vx_render_scene_stats* out);
/* Whether the scene is traced by the float64 variant (a model deeper than
 * VX_RENDER_PRECISE_DEPTH). */
bool vx_render_scene_precise(const vx_render_scene* rs);
/* Seconds spent building the BVH at creation (or at the last instance update). */
double vx_render_scene_bvh_seconds(const vx_render_scene* rs);
/* The colour mode's shadow rays (one directional light) are parallel, so
 * each projects to one point of the light's orthographic view. The scene
 * keeps a conservative depth map of that view: per texel the largest
 * distance towards the light of any octree node (about a texel in size)
 * whose projection touches it, and a shadow ray's walk ends where it passes
 * that distance (or is skipped where it starts beyond it). The image is the
 * same as without (vx_render_desc.no_shadow_map). The nodes are listed at
 * the first build (float variant; from the node words on the GPU, or the
 * compact layout's geometry, read back: a scene that never builds a map has
 * no list and no buffer; a paged compact layout has none); the map is built on the
 * GPU at a colour frame whose light direction and instances the colour
 * frame before had too (a light or an animation that changes every frame
 * would pay a build, build_seconds, for one frame's shadow rays; such
 * frames trace them unclipped). After vx_render_scene_update_model the
 * scene has no map (shadow rays unclipped). */
typedef struct vx_render_shadow_map_info {
    uint32_t side;            /* texels a side; 0: the scene has no map (yet: none before the first build) */
    uint32_t nodes;           /* octree nodes listed */
    double list_seconds;      /* listing them (at the first build, with the words' read-back; where a list
                                 made ahead was taken: its buffer only) */
    double ahead_seconds;     /* the list made ahead on the host (vx_render_sun_nodes_make); 0: none taken */
    uint32_t builds;          /* maps built so far */
    double build_seconds;     /* the last build, wall time (uploads, submission) */
    double build_gpu_seconds; /* the last build's dispatches (timestamps) */
    bool used;                /* the last frame of vx_render_frame clipped its shadow rays by it */
    /* the last build's texels: world point x falls in texel
     * (floor((dot(x - origin, axis_u) - u0) / texel), likewise v), of side^2 */
    double origin[3], axis_u[3], axis_v[3];
    double u0, v0, texel;
} vx_render_shadow_map_info;
void vx_render_scene_shadow_map_info(const vx_render_scene* rs, vx_render_shadow_map_info* out);

/* The depth map's node list made on the host ahead of the render scene: a
 * tool that opens the device on a thread of its own (svo_bake) lists the
 * nodes while it waits for the device, instead of at the map's first build
 * after it (which reads the node words back from the GPU and lists them:
 * 0.009-0.015 s for the Cornell box on an H200 host). The scene takes the
 * list with vx_render_scene_take_sun_nodes; its first build uses it where it
 * is the list it would make (the same drawn instances, models, box, side
 * asked for, texels a cell and largest side), else lists as before. */
typedef struct vx_render_sun_nodes vx_render_sun_nodes;
typedef struct vx_render_sun_nodes_desc {
    const vx_allocator* alloc; /* NULL: malloc; must outlive the scene that takes the list */
    uint32_t shadow_map_side;  /* the render scene's vx_render_scene_desc.shadow_map_side */
    uint32_t max_side;         /* the build's largest side: 0 a frame's (2048), the probe bake's VX_PROBE_SUN_MAP_SIDE */
    bool cpu_device;           /* for a CPU device (2 texels a cell instead of 8) */
    /* NULL: the nodes of s's models (their trees); else this compact layout
     * of them (render/compact.h; its geometry read, s gives the instances
     * and box): a scene built from a model reader, which holds no trees
     * (svo_bake --load models), lists its nodes before the layout goes to
     * the GPU instead of reading the geometry back at the first build */
    const struct vx_compact_scene* layout;
} vx_render_sun_nodes_desc;
vx_result vx_render_sun_nodes_make(const vx_svo_scene* s, const vx_render_sun_nodes_desc* desc, vx_render_sun_nodes** out,
                                   vx_error* err);
/* rs owns n from here (NULL rs: n is freed). */
void vx_render_scene_take_sun_nodes(vx_render_scene* rs, vx_render_sun_nodes* n);
void vx_render_sun_nodes_free(vx_render_sun_nodes* n);

vx_result vx_render_frame(vx_render_scene* rs, const vx_render_desc* desc, vx_render_image* out, vx_error* err);
/* Runs desc's frame kernel back to back, in submissions of 8, for about
 * `seconds` of wall time (at least one submission; no image read back), for
 * benchmarks before they time frames: a GPU whose clock fell while it idled
 * (a long load after the device was made) stays slow through frames that
 * keep it busy a few percent of the time (the H200: 345 against 1980 MHz,
 * frames 4.7x slower; docs/PERFORMANCE.md, issue 18, branch load2).
 * *frame_ms (NULL: not asked): the last submission's median GPU ms. */
vx_result vx_render_scene_warm_up(vx_render_scene* rs, const vx_render_desc* desc, double seconds, double* frame_ms,
                                  vx_error* err);

/* The default framing (camera.set false) of the world box [lo, hi] under
 * desc's camera fov, ortho and up (desc NULL: the defaults): *out is desc's
 * camera with eye and target set, an orthographic view's ortho_height where
 * desc has none, and set true; a frame with it is the default frame of a
 * scene whose bounds are [lo, hi]. Renders frame vx_svo_scene_world_bounds
 * (an animation: the union over its frames, a camera that holds still), so a
 * tool that renders one frame's view (vx_svo_scene_frame: that frame's
 * bounds) keeps the animation's framing with this camera. */
void vx_render_camera_default(const double lo[3], const double hi[3], const vx_render_desc* desc, vx_render_camera* out);

/* The CPU reference: the same outputs in double precision (lod ignored). */
vx_result vx_render_cpu(const vx_svo_scene* scene, const vx_render_desc* desc, const vx_allocator* alloc,
                        vx_render_image* out, vx_error* err);

/* ---- CPU ray casting (the reference tracer's rays, for the probe baker) ----------- */

/* A scene prepared for single-ray queries in double precision with the CPU
 * reference's rules (a ray starting inside a voxel hits it at t = 0). The
 * scene is borrowed for the caster's lifetime. Casts are read-only and may
 * run from several threads at once. */
typedef struct vx_render_caster vx_render_caster;

typedef struct vx_render_ray_hit {
    double t;         /* world distance along the unit direction */
    double normal[3]; /* world geometric normal, facing the ray */
    double cell_size; /* world size of one cell of the hit instance */
    uint32_t instance;
    uint32_t cell[3];
    uint32_t rgba;    /* attribute colour (opaque white without attributes) */
    uint32_t palette; /* palette index, 0 if the model has none */
    uint32_t material; /* material id (vx_svo_attr_material): what MATL materials are keyed by */
} vx_render_ray_hit;

vx_result vx_render_caster_create(const vx_svo_scene* scene, const vx_allocator* alloc, vx_render_caster** out,
                                  vx_error* err);
void vx_render_caster_destroy(vx_render_caster* c);
/* First hit with t in [0, tmax) along the unit world direction d from o;
 * any: stop at the first hit found (shadow rays; hit->t etc. unspecified
 * then, but hit may be NULL). */
bool vx_render_cast(const vx_render_caster* c, const double o[3], const double d[3], double tmax, bool any,
                    vx_render_ray_hit* hit);
/* The same with the scene's instance skip_instance passed over
 * (VX_RENDER_NO_HIT: none): what lies inside that instance's voxels from a
 * point within one (the path tracer's walk through glass looks for another
 * instance's voxels inside the glass this way). */
bool vx_render_cast_skip(const vx_render_caster* c, const double o[3], const double d[3], double tmax, bool any,
                         uint32_t skip_instance, vx_render_ray_hit* hit);

/* Checks a frame desc (sizes, mode, camera finite); no GPU needed. */
vx_result vx_render_desc_validate(const vx_render_desc* desc, vx_error* err);

/* Name of a mode ("color", ...) and the reverse (false if unknown). */
const char* vx_render_mode_name(vx_render_mode m);
bool vx_render_mode_parse(const char* s, vx_render_mode* out);

/* ---- scene BVH (exposed for tests and benchmarks) ----------------------------------- */

typedef struct vx_bvh_node {
    float lo[3];
    uint32_t first; /* interior: index of the left child (right = first + 1); leaf: first item */
    float hi[3];
    uint32_t count; /* 0: interior; else item count of a leaf */
} vx_bvh_node;

typedef struct vx_bvh {
    uint32_t node_count;
    vx_bvh_node* nodes;
    uint32_t* items; /* item indices referenced by leaves */
    uint32_t item_count;
    const vx_allocator* alloc;
} vx_bvh;

/* Binned SAH build (16 bins, O(n log n)) over boxes lo[3*i..], hi[3*i..];
 * leaves hold at most 4 items. */
vx_result vx_bvh_build(const double* lo, const double* hi, uint32_t count, const vx_allocator* alloc, vx_bvh* out,
                       vx_error* err);
/* Refit: the same tree (nodes, items) over moved boxes of the same count,
 * each node's bounds recomputed bottom-up (children come after their parent,
 * so one pass from the last node), rounded outward to float as the build's.
 * Returns the tree's cost as the build measures it (the sum of the interior
 * nodes' surface areas over the root's, plus the leaves' item counts times
 * their areas over the root's), for callers that rebuild when a refit tree
 * has grown too costly; -1 on invalid boxes (nothing changed then). */
double vx_bvh_refit(vx_bvh* bvh, const double* lo, const double* hi, uint32_t count);
/* The same cost of a tree as it stands. */
double vx_bvh_cost(const vx_bvh* bvh);
/* The nodes in breadth-first order, level by level from the root: order[]
 * (node_count entries) and level_start[] (levels + 1 entries: level l is
 * order[level_start[l] .. level_start[l + 1])), for a refit on the GPU one
 * level at a time from the deepest; *levels receives the count. The arrays
 * are the caller's, level_start node_count + 1 entries at most. */
void vx_bvh_levels(const vx_bvh* bvh, uint32_t* order, uint32_t* level_start, uint32_t* levels);
void vx_bvh_free(vx_bvh* bvh);

#ifdef __cplusplus
}
#endif
#endif /* VX_RENDER_H */
