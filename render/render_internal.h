/* render/render_internal.h - shared between the render/ sources (not public). */
#ifndef VX_RENDER_INTERNAL_H
#define VX_RENDER_INTERNAL_H

#include <vulkan/vulkan.h>

#include "render/render.h"

/* ---- camera and frame set-up, shared by the GPU and the CPU paths ----------------- */

/* Rays are generated relative to a reference point R near the scene (so the
 * GPU's floats keep the scene's precision even when the eye is far away):
 *   perspective:  P(u,v) = t_start * (u*rx + v*uy)   d = normalize(fwd + u*rx + v*uy)
 *                 depth = t_start * |fwd + u*rx + v*uy| + s
 *   orthographic: P(u,v) = u*rx + v*uy               d = fwd
 *                 depth = t_start + s
 * where s is the distance along d from P, u,v in [-1,1] (v up) and
 * R = eye + t_start * fwd lies before all scene geometry. */
typedef struct vx__frame {
    uint32_t width, height, spp;
    vx_render_mode mode;
    bool ortho;
    double ref[3];             /* R in world space */
    double fwd[3], rx[3], uy[3];
    double t_start;
    double light[3];           /* unit, towards the light */
    double ambient;
    double pixel_angle;        /* LOD cone: world footprint per unit distance */
    double pixel_size;         /* orthographic footprint */
    double lod_pixels;
    bool lod;
} vx__frame;

/* World bounds of the drawn instances' model boxes (zero when none). */
void vx__scene_world_bounds(const vx_svo_scene* s, double lo[3], double hi[3]);
/* Resolves defaults and the camera into a frame. */
vx_result vx__frame_setup(const double lo[3], const double hi[3], const vx_render_desc* desc, vx__frame* f,
                          vx_error* err);
/* Sub-pixel offset of sample i in [-0.5, 0.5)^2 (sample 0 is the centre). */
void vx__sample_offset(uint32_t i, double* ox, double* oy);
/* World (3x4) of instance i: world_from_grid * xform. */
void vx__instance_world(const vx_svo_scene* s, const vx_svo_instance* in, double w[12]);
void vx__affine_apply(const double m[12], const double p[3], double out[3]);
/* Inverse of a 3x4 affine map; false if singular. */
bool vx__affine_inverse(const double m[12], double out[12]);
/* Colour of an instance id for VX_RENDER_INSTANCE; heat map for iterations. */
void vx__instance_color(uint32_t id, float rgb[3]);
void vx__heat_color(uint32_t iterations, float rgb[3]);
/* Checks models and instances for the tracer's limits (depth, invertible). */
vx_result vx__check_scene(const vx_svo_scene* s, vx_error* err);
/* Whether instance i is drawn (not hidden, nor in a hidden layer, model not empty). */
bool vx__instance_drawn(const vx_svo_scene* s, uint32_t i);
/* RGBA8 of attribute record a of model m (palette looked up; white without attributes). */
uint32_t vx__attr_color(const vx_svo_scene* s, const vx_svo_model* m, uint32_t a);
/* World AABB of an instance's model box [0,size]. */
void vx__instance_bounds(const vx_svo_scene* s, const vx_svo_instance* in, double lo[3], double hi[3]);

#define VX__SKY_R 0.62f
#define VX__SKY_G 0.75f
#define VX__SKY_B 0.92f

/* ---- Vulkan ------------------------------------------------------------------------ */

#define VX_GPU_MAX_BINDINGS 16
#define VX_GPU_MAX_PIPELINES 32

typedef struct vx__buffer {
    VkBuffer buf;
    VkDeviceMemory mem;
    VkDeviceSize size;
    void* map;           /* persistently mapped when host visible */
    bool host_visible;
} vx__buffer;

typedef struct vx_gpu_compute_pipeline_desc {
    const uint32_t* spirv;
    size_t spirv_size;           /* bytes */
    const char* entry;           /* NULL == "main" */
    uint32_t push_constant_size;
    uint32_t binding_count;
    VkDescriptorType bindings[VX_GPU_MAX_BINDINGS];
    uint32_t spec_count;
    uint32_t spec[8];            /* 32-bit specialisation constants, ids 0.. */
    const char* label;
} vx_gpu_compute_pipeline_desc;

typedef struct vx__pipeline {
    uint64_t key;
    VkDescriptorSetLayout dsl;
    VkPipelineLayout layout;
    VkPipeline pipe;
} vx__pipeline;

struct vx_gpu {
    vx_allocator alloc;
    const vx_logger* logger;
    bool external;
    bool validate;
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
    uint32_t validation_errors;
    uint32_t pipeline_count;
    vx__pipeline pipelines[VX_GPU_MAX_PIPELINES];
};

const char* vx__vk_str(VkResult r);
vx_result vx__vk_fail(vx_error* err, VkResult r, const char* what);
#define VX__VK(call, what)                                          \
    do {                                                            \
        VkResult vx__r = (call);                                    \
        if (vx__r != VK_SUCCESS) return vx__vk_fail(err, vx__r, what); \
    } while (0)

void vx__gpu_name(vx_gpu* g, VkObjectType type, uint64_t handle, const char* label);

/* gpu_memory.c: device-local when possible; host-visible ones stay mapped. */
vx_result vx__buffer_create(vx_gpu* g, VkDeviceSize size, VkBufferUsageFlags usage, bool host_visible,
                            const char* label, vx__buffer* out, vx_error* err);
void vx__buffer_destroy(vx_gpu* g, vx__buffer* b);
/* Copies data into a buffer (through a staging buffer if not mapped). */
vx_result vx__buffer_upload(vx_gpu* g, vx__buffer* b, const void* data, VkDeviceSize size, vx_error* err);
vx_result vx__buffer_download(vx_gpu* g, vx__buffer* b, void* data, VkDeviceSize size, vx_error* err);

/* gpu_pipeline.c: created once per distinct key and cached in the vx_gpu. */
vx_result vx__pipeline_get(vx_gpu* g, uint64_t key, const vx_gpu_compute_pipeline_desc* desc, vx__pipeline** out,
                           vx_error* err);
void vx__pipelines_destroy(vx_gpu* g);
/* Embedded SPIR-V. */
const uint32_t* vx__spirv_trace(size_t* bytes);
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
    const char* label;
} vx__dispatch_desc;
/* Records, submits and waits; *seconds is the median GPU time per repeat
 * from timestamps (wall time if the queue has no timestamps). */
vx_result vx__dispatch(vx_gpu* g, const vx__dispatch_desc* d, double* seconds, vx_error* err);

/* ---- GPU data layout (must match shaders/trace.comp) -------------------------------- */

typedef struct vx__gpu_model {
    uint32_t node_off, color_off, depth, root;
    uint32_t root_attr, flags, pad0, pad1;
} vx__gpu_model;
enum { VX__MODEL_HAS_COLOR = 1u };

typedef struct vx__gpu_inst {
    float r[3][4];  /* model-from-world rows (world relative to the frame reference) */
    uint32_t model;
    float cell;     /* world size of one cell (largest column norm of M) */
    uint32_t id;    /* scene instance index */
    float pad;
} vx__gpu_inst;

typedef struct vx__gpu_frame {
    float fwd[4];    /* w: t_start */
    float rx[4];     /* w: ortho */
    float uy[4];     /* w: lod footprint per unit distance */
    float light[4];  /* w: ambient */
    float misc[4];   /* x: lod footprint at distance 0, y: lod pixels */
    uint32_t dims[4];   /* width, height, spp, instance count */
    uint32_t dims2[4];  /* x: dense grid nx, y: ny, z: nz, w: 0 */
    float grid_lo[4];   /* dense grid lower corner relative to R, w: cell size */
    /* precise variant only (std140 dvec4 at offset 128): the camera in double */
    double pfwd[4];     /* w: t_start */
    double prx[4];
    double puy[4];
} vx__gpu_frame;

/* Precise variant only (binding 9): the instances' model-from-world rows in
 * double, world relative to the frame reference. */
typedef struct vx__gpu_inst_precise {
    double r[3][4];
} vx__gpu_inst_precise;

enum { VX__SPEC_MODE = 0, VX__SPEC_HAS_COLOR, VX__SPEC_USE_BVH, VX__SPEC_LOD, VX__SPEC_HITS, VX__SPEC_COUNT };

/* ---- benchmark entry points (render_scene.c) ---------------------------------------- */

/* Runs the trace `repeat` times in one submission; *seconds is the median. */
vx_result vx__render_dispatch(vx_render_scene* rs, const vx_render_desc* desc, bool want_hits, uint32_t repeat,
                              vx__frame* f, double* seconds, vx_error* err);
/* Tests and benchmarks: 1 forces the float64 variant (fails at the next frame
 * without shaderFloat64), 0 forces the float one, -1 restores the choice by
 * model depth (VX_RENDER_PRECISE_DEPTH). */
void vx__render_scene_force_precise(vx_render_scene* rs, int precise);
/* Dense occupancy grid of the scene (identity world_from_grid) for the baseline. */
vx_result vx__dense_prepare(vx_render_scene* rs, const vx_svo_scene* s, uint64_t max_cells, vx_error* err);
vx_result vx__dense_dispatch(vx_render_scene* rs, const vx_render_desc* desc, uint32_t repeat, double* seconds,
                             float* depth_out, vx_error* err);

/* ---- other GPU passes over a scene (probes/probe_gpu.c) ------------------------------ */

/* shaders/probe.comp: the light field probes' bake and GI passes (float variant). */
const uint32_t* vx__spirv_probe(size_t* bytes);
vx_gpu* vx__render_scene_gpu(vx_render_scene* rs);
/* Writes the per-frame tables and the frame block for f (f->ref is the origin
 * of the shader's float coordinates; the camera matters only to camera rays)
 * and returns the scene's bindings 0-6 (frame, nodes, colors, models,
 * instances, BVH nodes, BVH items) and the trace spec constants. Float
 * variant only: VX_ERR_UNSUPPORTED for scenes that need float64. */
vx_result vx__render_scene_bind(vx_render_scene* rs, const vx__frame* f, vx__buffer* bufs[7],
                                uint32_t spec[VX__SPEC_COUNT], vx_error* err);
/* Palette index (0: none) of every entry of the colors buffer, in its order
 * (the models' attribute records one model after another); *out freed with
 * vx_free(alloc, ...). */
vx_result vx__scene_attr_palette(const vx_svo_scene* s, const vx_allocator* alloc, uint8_t** out, size_t* n,
                                 vx_error* err);

/* ---- CPU reference internals used by the benchmark's dense baseline ----------------- */

/* Calls fn for every filled model cell (via vx_svo_decode_model) placed in
 * grid space with floor(M (v + 1/2) + t). */
typedef void (*vx__grid_cell_fn)(void* user, int64_t x, int64_t y, int64_t z);
vx_result vx__scene_grid_cells(const vx_svo_scene* s, vx__grid_cell_fn fn, void* user, vx_error* err);

#endif
