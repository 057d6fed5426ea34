/* render/gpu.h - the GPU layer under the tracer, shared by render/ and the
 * modules that add GPU passes over a scene (probes/, later GI methods):
 * the device (struct vx_gpu), buffers, cached compute pipelines with
 * specialisation constants, recorded dispatches with timestamps, and the
 * scene's bindings 0-6 for a frame (vx__render_scene_bind). Shaders that
 * trace the scene include render/shaders/trace_common.glsl and declare
 * bindings 0-6 as it does. Names keep the vx__ prefix: this is the toolkit's
 * own layer, documented for modules, not part of the user API (render.h).
 *
 * Typical use by a module's pass:
 *   vx_gpu* g = vx__render_scene_gpu(rs);
 *   vx__buffer out; vx__buffer_create(g, bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, false, "mine", &out, err);
 *   vx__buffer* scene[7]; uint32_t spec[VX__SPEC_COUNT];
 *   vx__render_scene_bind(rs, &frame, scene, spec, err);   // frame from vx__frame_setup (trace.h)
 *   vx__pipeline* p; vx__pipeline_get(g, key, &(vx_gpu_compute_pipeline_desc){...}, &p, err);
 *   vx__dispatch(g, &(vx__dispatch_desc){.pipeline = p, ...}, &seconds, err);
 *   vx__buffer_download(g, &out, host, bytes, err); vx__buffer_destroy(g, &out); */
#ifndef VX_RENDER_GPU_H
#define VX_RENDER_GPU_H

#include <vulkan/vulkan.h>

#include "render/trace.h"

/* ---- Vulkan ------------------------------------------------------------------------ */

#define VX_GPU_MAX_BINDINGS 27

typedef struct vx__buffer {
    VkBuffer buf;
    VkDeviceMemory mem;
    VkDeviceSize size;
    void* map;           /* persistently mapped when host visible */
    bool host_visible;
    /* a 3D image instead (vx__image3d_create; buf is then VK_NULL_HANDLE):
     * bound as VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER (trilinear, zero
     * outside) or VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, always in the general layout */
    VkImage image;
    VkImageView view;
    VkSampler sampler;
} vx__buffer;

/* The specialisation constant id that create_pipeline gives every pipeline: vx_gpu.nodes_file (a VkBool32). Vulkan
 * ignores a map entry whose id the module does not declare, so shaders that do not read the node buffer need
 * nothing; the ids a pipeline's desc sets (0..) stay below it. */
#define VX__SPEC_NODES_FILE 100u

typedef struct vx_gpu_compute_pipeline_desc {
    const uint32_t* spirv;
    size_t spirv_size;           /* bytes */
    const char* entry;           /* NULL == "main" */
    uint32_t push_constant_size;
    uint32_t binding_count;
    VkDescriptorType bindings[VX_GPU_MAX_BINDINGS];
    uint32_t spec_count;
    uint32_t spec[16];           /* 32-bit specialisation constants, ids 0.. */
    const char* label;
} vx_gpu_compute_pipeline_desc;

typedef struct vx__pipeline {
    uint64_t key;
    uint32_t binding_count;
    VkDescriptorType bindings[VX_GPU_MAX_BINDINGS]; /* as created: vx__dispatch writes descriptors of these types */
    VkDescriptorSetLayout dsl;
    VkPipelineLayout layout;
    VkPipeline pipe;
} vx__pipeline;

/* The pipeline cache's storage: blocks that are only appended, so that an
 * entry never moves (gpu_pipeline.c). */
enum { VX__PIPELINE_BLOCK = 32 };
typedef struct vx__pipeline_block {
    struct vx__pipeline_block* next;
    uint32_t count;
    vx__pipeline p[VX__PIPELINE_BLOCK];
} vx__pipeline_block;

struct vx_gpu {
    vx_allocator alloc;
    const vx_logger* logger;
    bool external;
    bool validate;
    /* VX_GPU_MEMORY_LOG=1: every allocation's memory type, flags and heap logged ("gpu.memory"), to compare
     * where two ways of building one scene put its buffers (docs/PERFORMANCE.md, issue 18, branch load2) */
    bool memory_log;
    VkInstance instance;
    VkDebugUtilsMessengerEXT messenger;
    PFN_vkSetDebugUtilsObjectNameEXT set_name;
    PFN_vkCmdBeginDebugUtilsLabelEXT begin_label;
    PFN_vkCmdEndDebugUtilsLabelEXT end_label;
    VkPhysicalDevice phys;
    VkPhysicalDeviceProperties props;
    VkPhysicalDeviceMemoryProperties memprops;
    VkDevice device;
    uint32_t queue_family;
    VkQueue queue;
    VkCommandPool cmd_pool;
    VkCommandBuffer cmd;
    VkFence fence;
    VkQueryPool timestamps;
    bool has_timestamps;
    bool has_float64; /* shaderFloat64 enabled: the precise trace variant can run */
    bool has_storage_write; /* shaderStorageImageWriteWithoutFormat enabled: vx_display writes images itself */
    /* The form of the plain layout's node descriptors in the GPU's node buffer (issue 21), decided once when the
     * device is made: false on GPUs, the GPU form (render_internal.h's vx__desc_gpu: on the H200 2-7% more primary
     * rays on models of 10 levels or less, 2-3% fewer on deeper ones, whose kernel turns each loaded descriptor
     * back, FILE_FORM); true on CPU devices, the file's (lavapipe traces 0.55-0.75 of the rate with the GPU form's
     * loop). VX_GPU_NODE_FORM=file|gpu overrides (ctest's *_gpu_form entries run the GPU form on lavapipe);
     * docs/PERFORMANCE.md, issue 21's fifteenth and sixteenth sittings. Every pipeline gets it as specialisation
     * constant VX__SPEC_NODES_FILE (gpu_pipeline.c; trace_common.glsl's NODES_FILE), and render_scene.c uploads
     * the nodes in it. */
    bool nodes_file;
    /* Each pipeline's module specialised on the host before the driver sees it (render/spirv_opt.h: lavapipe makes
     * the merged frame kernel in 0.05 s instead of 2.5 s): decided once when the device is made, true on CPU
     * devices where the build has the specialiser; VX_GPU_SPECIALISE=0|1 overrides (1: on any device with the
     * specialiser; test_pipeline_cache compares the two on every kernel). */
    bool specialise;
    uint32_t validation_errors;
    /* a display that holds recorded frames to submit several at once
     * (vx_display_set_queue): submits them; called before any other
     * submission or wait for the queue (vx__gpu_submit_held), so that work
     * recorded after them runs after them and a wait covers them */
    void (*held_submit)(void* user);
    void* held_user;
    /* the pipelines made (vx__pipeline_get): kept, and in place, until vx_gpu_destroy */
    uint32_t pipeline_count;
    vx__pipeline_block* pipelines;
    /* pipelines being made ahead on threads of their own (vx__pipeline_ahead), until a get takes them */
    struct vx__pipeline_pending* pending;
};

const char* vx__vk_str(VkResult r);
vx_result vx__vk_fail(vx_error* err, VkResult r, const char* what);
#define VX__VK(call, what)                                          \
    do {                                                            \
        VkResult vx__r = (call);                                    \
        if (vx__r != VK_SUCCESS) return vx__vk_fail(err, vx__r, what); \
    } while (0)

void vx__gpu_name(vx_gpu* g, VkObjectType type, uint64_t handle, const char* label);
/* Submits the frames a display holds (above); before vkQueueWaitIdle and other submissions. */
void vx__gpu_submit_held(vx_gpu* g);

/* VX_GPU_MEMORY_LOG: the device's heaps and memory types, logged ("gpu.memory"). */
void vx__gpu_log_memory_types(vx_gpu* g);
/* gpu_memory.c: device-local when possible; host-visible ones stay mapped. */
vx_result vx__buffer_create(vx_gpu* g, VkDeviceSize size, VkBufferUsageFlags usage, bool host_visible,
                            const char* label, vx__buffer* out, vx_error* err);
void vx__buffer_destroy(vx_gpu* g, vx__buffer* b);
/* A device-local storage buffer of at least size bytes: b is kept when it is
 * large enough, else replaced (its contents are not kept). */
vx_result vx__buffer_ensure(vx_gpu* g, vx__buffer* b, VkDeviceSize size, const char* label, vx_error* err);
/* A device-local 3D image of RGBA16F texels, cleared to zero, in the general
 * layout (sampled and stored), with a linear sampler whose outside is
 * transparent black; destroyed by vx__buffer_destroy. */
vx_result vx__image3d_create(vx_gpu* g, const uint32_t extent[3], const char* label, vx__buffer* out, vx_error* err);
/* Copies data into a buffer (through a staging buffer if not mapped). */
vx_result vx__buffer_upload(vx_gpu* g, vx__buffer* b, const void* data, VkDeviceSize size, vx_error* err);
/* The same at a byte offset into the buffer (offset + size within it). */
vx_result vx__buffer_upload_at(vx_gpu* g, vx__buffer* b, VkDeviceSize offset, const void* data, VkDeviceSize size,
                               vx_error* err);
vx_result vx__buffer_download(vx_gpu* g, vx__buffer* b, void* data, VkDeviceSize size, vx_error* err);
/* The same from a byte offset into the buffer (offset + size within it). */
vx_result vx__buffer_download_at(vx_gpu* g, vx__buffer* b, VkDeviceSize offset, void* data, VkDeviceSize size,
                                 vx_error* err);

/* gpu_pipeline.c: created once per distinct key and cached in the vx_gpu
 * until vx_gpu_destroy, never evicted nor moved: a vx__pipeline* stays valid
 * and the same pipeline for the device's life, so that frames, pass lists,
 * GI methods, the probe bake and command buffers recorded and not yet
 * submitted may hold one across other vx__pipeline_get calls. (The cache
 * used to evict its oldest entry past 128 and move the rest: what they held
 * was destroyed or became another pipeline, issue 18.) The keys are the
 * callers' (a shader and its constants); a process makes a bounded set of
 * variants (59 for a scene in both layouts with every GI method). */
vx_result vx__pipeline_get(vx_gpu* g, uint64_t key, const vx_gpu_compute_pipeline_desc* desc, vx__pipeline** out,
                           vx_error* err);
/* A pipeline's key from the shader's own seed (a constant per shader and form) and the first n of the
 * specialisation constants it is built with: one hash for every caller, so that two callers' keys for the same
 * shader and constants agree and a constant left out of the key is a visible choice (n), not a copied loop. */
static inline uint64_t vx__spec_key(uint64_t seed, const uint32_t* spec, uint32_t n) {
    for (uint32_t i = 0; i < n; i++) seed = seed * 131 + spec[i];
    return seed;
}
/* Starts making the pipeline of key on a thread of its own; the vx__pipeline_get of the same key waits for
 * it and takes it into the cache (its error, if any, is that get's). The driver compiles the SPIR-V in
 * vkCreateComputePipelines, and on a machine whose shader cache is empty the compiles take 0.05-0.9 s each
 * (the probe bake's four on an H200, docs/PERFORMANCE.md section 5): made ahead they overlap each other and
 * the caller's work instead of adding up. desc is copied; its SPIR-V and label must stay valid until the get
 * (or vx_gpu_destroy). Returns false where nothing was started: the key is made or pending already, or no
 * thread could be started (the get then makes it). Only the vx_gpu's own thread calls this and the get. */
bool vx__pipeline_ahead(vx_gpu* g, uint64_t key, const vx_gpu_compute_pipeline_desc* desc);
/* Where the pipeline of key is: VX__PIPE_NONE (neither made nor made ahead), VX__PIPE_PENDING (its thread
 * still at work), VX__PIPE_READY (made, or its thread done: the get returns at once; it may have failed, the
 * get says). Lets a caller take whichever of two equivalent pipelines the driver finishes first (the probe
 * bake's kernels: one a hit of the driver's cache where the other is compiled). */
enum { VX__PIPE_NONE, VX__PIPE_PENDING, VX__PIPE_READY };
int vx__pipeline_state(vx_gpu* g, uint64_t key);
void vx__pipelines_destroy(vx_gpu* g);
/* Embedded SPIR-V. */
const uint32_t* vx__spirv_trace(size_t* bytes);
/* The primary rays' beam pass (run before trace.comp, same bindings). */
const uint32_t* vx__spirv_beam(size_t* bytes);
const uint32_t* vx__spirv_dense(size_t* bytes);
/* trace.comp built with -DPRECISE (float64 traversal; needs has_float64). */
const uint32_t* vx__spirv_trace_precise(size_t* bytes);

/* gpu_dispatch.c */
vx_result vx__cmd_begin(vx_gpu* g, vx_error* err);
vx_result vx__cmd_submit_wait(vx_gpu* g, vx_error* err);

typedef struct vx__dispatch_desc {
    vx__pipeline* pipeline;
    uint32_t buffer_count;
    vx__buffer* buffers[VX_GPU_MAX_BINDINGS];
    uint32_t groups[3];
    uint32_t repeat;            /* 0 == 1: timed dispatches in one submission */
    const void* push;           /* push constants (push_size bytes; the pipeline's push_constant_size) */
    uint32_t push_size;
    const char* label;
    /* Optional first stage of every repeat (timed with it): pre_pipeline over
     * pre_groups, the same buffers (its layout declares the same bindings),
     * no push constants; a barrier orders its writes before the main stage. */
    vx__pipeline* pre_pipeline;
    uint32_t pre_groups[3];
    /* Optional last stage of every repeat (timed with it): post_pipeline over
     * post_groups, no barrier before it (it must write what the main stage
     * does not touch). Its layout must be compatible with the main
     * pipeline's (the same bindings and push constants: Vulkan's "compatible
     * for set 0"), whose descriptor set and push constants it uses. */
    vx__pipeline* post_pipeline;
    uint32_t post_groups[3];
} vx__dispatch_desc;
/* Records, submits and waits; *seconds is the median GPU time per repeat
 * from timestamps (wall time if the queue has no timestamps). */
vx_result vx__dispatch(vx_gpu* g, const vx__dispatch_desc* d, double* seconds, vx_error* err);

/* A sequence of dispatches in one command buffer, submitted and waited on
 * once (a pass of several steps pays one submission and one wait, where
 * vx__dispatch pays one each: photons/photons.c's pass had 2.4 ms of them on
 * the H200). Every recorded command is followed by a barrier that makes its
 * writes (shader or copy) visible to the later dispatches, copies, indirect
 * group counts and host reads. Timestamps: one before the first command and
 * one after each dispatch, so seconds[k] is the GPU time from the end of the
 * command before dispatch k (barrier included) to its end; they add up to the
 * sequence's GPU time. Without timestamps each is the wall time of the whole
 * submission over the count. Dispatches use d->pipeline, buffers, groups,
 * push and label (not repeat nor pre_pipeline). */
enum { VX__SEQ_MAX = 24 };
typedef struct vx__seq {
    VkDescriptorPool pool;
    uint32_t count;               /* dispatches recorded */
    uint32_t commands;            /* dispatches and copies recorded */
    double seconds[VX__SEQ_MAX];  /* after vx__seq_submit: GPU seconds of dispatch k */
    /* Set before recording a dispatch that the next one may run beside (it
     * does not read what this one writes): no barrier and no timestamp
     * after it, so the GPU fills the end of one with the other; its time
     * counts in the next one's (its seconds 0). Cleared by the dispatch. */
    bool beside;
    uint32_t query[VX__SEQ_MAX];  /* the timestamp after dispatch k (0: none) */
    uint32_t queries;
} vx__seq;
/* Begins the command buffer (g->cmd: nothing else may record until the
 * sequence is submitted or abandoned). */
vx_result vx__seq_begin(vx_gpu* g, vx__seq* s, vx_error* err);
/* Records a dispatch; with indirect (created with
 * VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT), its VkDispatchIndirectCommand at
 * offset gives the group counts (written by an earlier dispatch of the
 * sequence; zero groups: the dispatch does nothing) and d->groups is unused. */
vx_result vx__seq_dispatch(vx_gpu* g, vx__seq* s, const vx__dispatch_desc* d, const vx__buffer* indirect,
                           VkDeviceSize offset, vx_error* err);
/* Records a copy of size bytes between buffers (e.g. a count a dispatch
 * wrote, into a parameter block later dispatches read). */
void vx__seq_copy(vx_gpu* g, vx__seq* s, const vx__buffer* src, VkDeviceSize src_offset, const vx__buffer* dst,
                  VkDeviceSize dst_offset, VkDeviceSize size);
/* Records a fill of size bytes (a multiple of 4) of dst at offset with word. */
void vx__seq_fill(vx_gpu* g, vx__seq* s, const vx__buffer* dst, VkDeviceSize offset, VkDeviceSize size, uint32_t word);
/* Ends, submits, waits, reads the timestamps and frees the sequence's
 * descriptor pool (also on failure). */
vx_result vx__seq_submit(vx_gpu* g, vx__seq* s, vx_error* err);
/* After a failure between begin and submit: ends the command buffer
 * unsubmitted and frees the pool. */
void vx__seq_abandon(vx_gpu* g, vx__seq* s);

/* Specialisation constants of trace_common.glsl (ids 0-4); a pass's own start at 5. */
enum { VX__SPEC_MODE = 0, VX__SPEC_HAS_COLOR, VX__SPEC_USE_BVH, VX__SPEC_LOD, VX__SPEC_HITS, VX__SPEC_COUNT };
/* trace_common.glsl's DEEP (id 8: vx__render_scene_deep), FAR (id 9, default
 * true) and COMPACT (id 10): a pass whose scene is in the compact layout sets
 * COMPACT to vx__render_scene_compact(rs) (its spec_count then covers ids 8
 * and 9 too). */
enum { VX__SPEC_DEEP_ID = 8, VX__SPEC_FAR_ID = 9, VX__SPEC_COMPACT_ID = 10, VX__SPEC_TRACE_IDS = 11 };

/* ---- other GPU passes over a scene (probes/probe_gpu.c) ------------------------------ */

vx_gpu* vx__render_scene_gpu(vx_render_scene* rs);
/* The trace kernel's FAR constant (some model of the scene may hold a far
 * pointer, so the kernel tests the far bit per push): for other passes' kernels
 * (probes/probe_gpu.c), tests and benchmarks. */
bool vx__render_scene_far(const vx_render_scene* rs);
/* The trace kernel's DEEP constant (VX__SPEC_DEEP_ID) for the float variant:
 * 1 where a model is deeper than VX_RENDER_EXACT_DEPTH (exact hit distances),
 * 2 where one is deeper than VX_RENDER_REBASE_DEPTH (the rebased walk too),
 * else 0. Every kernel that traces the scene sets it: left at 0, a model of
 * 9-16 levels is walked with the shallow loop (its hits then disagree with
 * trace.comp's and the CPU reference's: issue 18, gdeep). */
uint32_t vx__render_scene_deep(const vx_render_scene* rs);
/* Whether the scene's bindings 1-3 (vx__render_scene_bind) are the compact
 * layout's (render/compact.h): kernels that trace it set trace_common.glsl's
 * COMPACT constant (VX__SPEC_COMPACT_ID). A paged compact scene is refused
 * by the bind (only vx_render_frame follows its pages). */
bool vx__render_scene_compact(const vx_render_scene* rs);
/* trace_common.glsl's COMPACT_FORM constant (id VX__SPEC_COMPACT_ID): 0 plain, 1 compact, 2 compact with
 * the brick dictionary (render/compact.h VX_COMPACT_BRICKS_DICT; its index words' path compiled in). */
uint32_t vx__render_scene_compact_form(const vx_render_scene* rs);
/* trace_common.glsl's ids 8-10 of a kernel that traces rs (spec has at least
 * VX__SPEC_TRACE_IDS entries): DEEP from the scene, FAR the shaders' default
 * (true), COMPACT the layout's form. One place for the passes, cones and
 * photons, so that no kernel is left walking deep models with the shallow
 * loop (issue 18, gdeep). */
static inline void vx__render_scene_trace_ids(const vx_render_scene* rs, uint32_t* spec) {
    spec[VX__SPEC_DEEP_ID] = vx__render_scene_deep(rs);
    spec[VX__SPEC_FAR_ID] = 1;
    spec[VX__SPEC_COMPACT_ID] = vx__render_scene_compact_form(rs);
}
/* The grid walk (render/grid.h, render/shaders/grid_walk.glsl) for a float
 * kernel that traces frame f and includes it (trace.comp; the pass kernels
 * through pass_grid.glsl): its GRID constant (id 13), 0 where no model walks
 * a grid (none built, the scene's switch off, f a LOD frame), and *buf the
 * grids' buffer to bind (NULL with 0). One rule for all those kernels. */
uint32_t vx__render_scene_grid_spec(vx_render_scene* rs, const vx__frame* f, vx__buffer** buf);
/* The directional light's conservative depth map (render/shadow_map.c) for
 * another pass's shadow rays towards a directional light: a kernel includes
 * render/shaders/smap_lookup.glsl (SMAP_BINDING: its first of three
 * bindings, constant 11 SMAP) and ends a shadow ray's walk at smap_tmax(...)
 * (or skips it): the same hits, fewer steps. The map holds the scene's
 * instances as drawn now (call it again after they move). */
typedef struct vx__sun_map {
    vx__buffer *map, *nodes, *insts_buf; /* the three bindings, in order; map NULL: no map (trace unclipped) */
    float origin[4];  /* smap_tmax's org: xyz the map's origin relative to ref, w the margin */
    uint32_t side;    /* smap_tmax's side */
    uint32_t insts;   /* smap_tmax's ninst */
} vx__sun_map;
/* Fills *out for the unit direction light (towards the light, the floats the
 * kernel's dot products use) and the kernel's reference point ref: the map
 * built on first use (the scene's node list too: the plain layout's words
 * read back), kept while the light and instances stay. max_side: the most
 * texels a side where the scene's side is its default and no list is made
 * yet (0: 2048, vx_render_frame's; the probe bake asks 4096: 256 MiB). No map (out->map
 * NULL, VX_OK) in the compact layout, the float64 variant, a scene made with
 * shadow_map_side 1 or edited by vx_render_scene_update_model, or too many
 * nodes. The buffers stay valid until the next call, frame or edit. */
vx_result vx__render_scene_sun_map(vx_render_scene* rs, const float light[3], const double ref[3], uint32_t max_side,
                                   vx__sun_map* out, vx_error* err);
/* The same for a pass of frame f (its light, f->light), before
 * vx__render_scene_bind(_cmd) for f: vx_render_frame's rule (a map is built
 * at a frame whose light the frame before had; allow false: none, as
 * vx_render_desc.no_shadow_map), none with LOD (a coarse hit's cube is larger
 * than the listed nodes). The frame block that bind writes then carries
 * smap_tmax's org (grid_lo) and side and ninst (dims2.x, dims2.y); out gives
 * the buffers (origin is not filled). */
vx_result vx__render_scene_sun_map_frame(vx_render_scene* rs, const vx__frame* f, bool allow, vx__sun_map* out,
                                         vx_error* err);
/* Writes the per-frame tables and the frame block for f (f->ref is the origin
 * of the shader's float coordinates; the camera matters only to camera rays)
 * and returns the scene's bindings 0-6 (frame, nodes, colors, models,
 * instances, BVH nodes, BVH items) and the trace spec constants. Float
 * variant only: VX_ERR_UNSUPPORTED for scenes that need float64. */
vx_result vx__render_scene_bind(vx_render_scene* rs, const vx__frame* f, vx__buffer* bufs[7],
                                uint32_t spec[VX__SPEC_COUNT], vx_error* err);
/* The same without the layout check (bindings 1-3 are then the plain
 * layout's, empty in a compact scene): for render/compact_gpu.c, which binds
 * only the frame, instances and BVH. */
vx_result vx__render_scene_tables(vx_render_scene* rs, const vx__frame* f, vx__buffer* bufs[7],
                                  uint32_t spec[VX__SPEC_COUNT], vx_error* err);
/* The same for a frame recorded into `cmd` (a VkCommandBuffer in the
 * recording state on the scene's queue) that other frames may precede on the
 * queue, still running: the tables and the frame block are written by
 * commands in cmd (vkCmdUpdateBuffer, between barriers), not by the host, so
 * each frame reads its own. Until the device has done these frames, the
 * host-side writers (vx__render_scene_bind, a frame of vx_render_frame, model
 * updates) wait for the queue to go idle first. */
vx_result vx__render_scene_bind_cmd(vx_render_scene* rs, const vx__frame* f, void* cmd, vx__buffer* bufs[7],
                                    uint32_t spec[VX__SPEC_COUNT], vx_error* err);
/* Material id (vx_svo_attr_material: the record's VX_ATTR_MATERIAL value,
 * else its palette index, else 0) of every entry of the colors buffer, in
 * its order (the models' attribute records one model after another); the
 * per-record tables of the passes and GI methods (emission, materials) are
 * built from these ids and the scene's vx_svo_material_table. *out freed
 * with vx_free(alloc, ...). */
vx_result vx__scene_attr_material(const vx_svo_scene* s, const vx_allocator* alloc, uint16_t** out, size_t* n,
                                  vx_error* err);
/* The same for the tables a pass indexes by the hit's Hit.attr. A compact
 * scene's kernels give there (compact_attr.glsl ca_table_index):
 * - where the layout was built with the models' material ids (a model has
 *   a material channel and some material of the scene is not plain
 *   diffuse: render_internal.h vx__compact_gpu_materials), the record's
 *   material id, so the tables are per id: entry i = i where some record of
 *   the scene has id i, else 0; *n the largest id + 1, at least 256;
 * - else the palette index (0 for RGBA records, as vx__scene_attr_material's
 *   entries of them without a material channel), so the tables are per
 *   palette index: *out 256 entries, entry i = i where some record has
 *   palette index i, else 0; *n 256 (the indices from the layout's build,
 *   vx_compact_scene.palette_used: s may be a reader's graph without the
 *   models' arrays). Where such a layout has no ids and s needs them (built
 *   from a model reader, or s's materials made non-diffuse after the
 *   layout was built) the tables could not give the plain layout's image:
 *   VX_ERR_UNSUPPORTED (the frame renderer keeps rendering the colour
 *   model, which reads no material, and refuses radiometric frames,
 *   render/pipeline.c mat_unkeyed).
 * The plain layout: vx__scene_attr_material(s). */
vx_result vx__render_scene_attr_material(const vx_render_scene* rs, const vx_svo_scene* s, const vx_allocator* alloc,
                                         uint16_t** out, size_t* n, vx_error* err);
/* pipeline.c: the buffer holding the last frame's image (RGBA32F,
 * rows top first, *w x *h), NULL before the first frame (render/display.c). */
struct vx_frame_renderer;
vx__buffer* vx__frame_renderer_image(const struct vx_frame_renderer* fr, uint32_t* w, uint32_t* h);
/* pipeline.c: vx_frame_record whose last pass also writes the display bytes
 * (shaders/display_out.glsl) into `view` (a storage view of an iw x ih image
 * in the GENERAL layout, which the caller transitions before and after),
 * with the device overlay laid over (NULL: none): the conversion fused into
 * the frame (render/display.c, vx_display_record_frame). */
typedef struct vx__display_target {
    VkImageView view;
    uint32_t iw, ih;
    const vx__buffer* overlay;
    bool bgra;
} vx__display_target;
struct vx_frame_desc;
struct vx_frame_result;
vx_result vx__frame_record_display(struct vx_frame_renderer* fr, const struct vx_frame_desc* desc, VkCommandBuffer cmd,
                                   uint32_t slot, const vx__display_target* t, struct vx_frame_result* out, vx_error* err);
/* A frame recorded with vx__render_scene_bind_cmd that will not be submitted:
 * the scene forgets the tables it recorded there (the next frame writes its
 * own whatever they are). */
void vx__render_scene_forget_tables(vx_render_scene* rs);
/* pipeline.c: light l in the std430 layout of passes_common.glsl's Light (24
 * floats), position relative to ref; cutoff: the irradiance where a light
 * without a range ends (vx_frame_desc.light_cutoff, resolved). For passes
 * that call light_eval (cones/). */
void vx__light_pack(const vx_light* l, const double ref[3], double cutoff, float out[24]);
/* A sky for render/shaders/sky.glsl (sky_eval's four vec4, in order zen,
 * hor, gnd, map): VX_SKY_DEFAULT or sky NULL: the uniform radiance
 * `uniform`; constant, gradient and map as vx_sky_radiance (a map without
 * texels is black, as there). Shared by the path tracer (probes/) and the
 * pass pipeline, so both read one packing. */
void vx__sky_pack(const vx_sky* sky, const vx_sky_texels* map, const double uniform[3], float out[16]);
/* The pass shaders' sky buffer (passes_common.glsl binding "Sky"): the
 * packing above, the table of the sky's irradiance E(n) / pi over normals
 * (render/pipeline.c), the map's texels; b is grown as needed. */
vx_result vx__sky_buffer(vx_gpu* g, const vx_sky* sky, const vx_sky_texels* map, const double uniform[3], vx__buffer* b,
                         vx_error* err);

#endif
