/* bench/esvo.h - the ESVO baseline of bench/render_bench: the scene's cells
 * in a plain full-depth octree (groups of eight 32-bit child slots: bit 31
 * valid, bit 30 leaf, bits 0-29 the children's group or the leaf's RGB),
 * traced by the loop of Laine and Karras 2010 in bench/shaders/esvo.comp on
 * the same primary rays as voxkit's tracer. The octree holds grid cells
 * (the instances' grid_from_model) and its cube is mapped to world units
 * through world_from_grid, which must be a uniform scale and a translation
 * (identity, or a converted mesh's 2^-n; else bench_esvo_create fails).
 * bench_cube and bench_kernel_frame, shared with the prototypes, still take
 * world cells = grid cells. */
#ifndef VX_BENCH_ESVO_H
#define VX_BENCH_ESVO_H
#include "render/gpu.h" /* vx__buffer, vx__pipeline_get, vx__dispatch */

/* The per-frame state of a baseline kernel: its Frame block (the camera,
 * the cube, two parameters) and its per-pixel output (depth bits, steps). */
typedef struct bench_kernel {
    vx__buffer frame, out;
    uint32_t extra[12]; /* the Frame block's three uvec4 after dims, for kernels that declare them */
} bench_kernel;

/* One frame of a baseline kernel laid out like bench/shaders/esvo.comp
 * (binding 0 the Frame block, 1 the kernel's data, 2 the output): desc's
 * camera and size, the cube [lo, lo + side) in grid cells (box.w = side),
 * dims.z and dims.w = p0 and p1; repeat timed dispatches (median in
 * *seconds); with depth/steps non-NULL the last run's per-pixel depth (+inf
 * for a miss) and steps (bit 31: the ray entered the cube). */
vx_result bench_kernel_frame(vx_gpu* g, bench_kernel* k, const vx_gpu_compute_pipeline_desc* pd, uint64_t key,
                             vx__buffer* data, const vx_svo_scene* s, const vx_render_desc* desc,
                             const int64_t lo[3], double side, uint32_t p0, uint32_t p1, uint32_t repeat,
                             double* seconds, float* depth, uint32_t* steps, vx_error* err);
void bench_kernel_destroy(vx_gpu* g, bench_kernel* k);

/* The baselines' cube: its corner lo (the floor of the scene's world
 * bounds) and the least depth >= min_depth with 2^depth cells covering the
 * bounds on every axis. */
void bench_cube(const vx_svo_scene* s, uint32_t min_depth, int64_t lo[3], uint32_t* depth);

typedef struct bench_esvo {
    vx_gpu* gpu;
    uint32_t* slots; /* host copy while building, freed after the upload */
    size_t slot_count, cap;
    uint32_t depth;
    int64_t lo[3];
    uint32_t path[24];
    int64_t last[3];
    bool have_last, too_big;
    vx__buffer buf;
    bench_kernel k;
    double build_seconds;
    /* the kernel's SPIR-V where not NULL (render_bench --esvo-kernel: a variant
     * of bench/shaders/esvo.comp with the same bindings; the caller owns it),
     * else the built-in esvo.comp */
    const uint32_t* spv;
    size_t spv_bytes;
} bench_esvo;

/* Builds the octree of every drawn instance's cells and uploads it. Fails
 * with VX_ERR_LIMIT past 2^30 slots. */
vx_result bench_esvo_create(vx_gpu* gpu, const vx_svo_scene* s, bench_esvo* e, vx_error* err);
void bench_esvo_destroy(bench_esvo* e);
/* Bytes of the octree on the GPU. */
uint64_t bench_esvo_bytes(const bench_esvo* e);
/* One frame of primary rays (desc's camera and size; mode ignored), repeat
 * timed dispatches (median in *seconds); with depth/steps non-NULL the
 * per-pixel depth (+inf for a miss) and steps (bit 31: the ray entered the
 * octree's cube) of the last run. */
vx_result bench_esvo_frame(bench_esvo* e, const vx_svo_scene* s, const vx_render_desc* desc, uint32_t repeat,
                           double* seconds, float* depth, uint32_t* steps, vx_error* err);
#endif
