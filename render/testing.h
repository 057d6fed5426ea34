/* render/testing.h - the tracer's switches for the toolkit's benchmarks and
 * tests (bench/, tests/render, tests/view): not user API, not installed.
 *
 * Why a header of its own: bench/render_bench, passes_bench, compact_bench
 * and view_bench, and the tests that compare the tracer's variants, need to
 * time one trace dispatch, force a variant (the float64 kernel, the screen
 * cull, the primary rays' start below the root, the instance rows from the
 * host or the GPU), swap in another trace kernel (the ESVO baseline's
 * comparison) or run the dense grid baseline. These switches used to sit in
 * render/render_internal.h beside the trace shaders' data layout, so every
 * benchmark reached into the module's private header; here they are the
 * module's documented face for measuring it. Each takes a scene from
 * vx_render_scene_create (render/render.h) and changes only that scene;
 * a value of -1 restores the default wherever one is listed. Names keep the
 * vx__ prefix, as render/gpu.h: the toolkit's own layer. No Vulkan type
 * appears here (render/gpu.h has the GPU layer itself). */
#ifndef VX_RENDER_TESTING_H
#define VX_RENDER_TESTING_H

#include "render/trace.h"

/* Runs the trace `repeat` times in one submission; *seconds is the median. */
vx_result vx__render_dispatch(vx_render_scene* rs, const vx_render_desc* desc, bool want_hits, uint32_t repeat,
                              vx__frame* f, double* seconds, vx_error* err);
/* Tests and benchmarks: 1 forces the float64 variant (fails at the next frame
 * without shaderFloat64), 0 forces the float one, -1 restores the choice by
 * model depth (VX_RENDER_PRECISE_DEPTH). */
void vx__render_scene_force_precise(vx_render_scene* rs, int precise);
/* Tests and benchmarks: 0 makes recorded frames write the instance rows
 * from the host (render_scene.c frame_tables), 1 has the GPU compute them
 * (shaders/inst_rows.comp; needs float64 shaders, else the host's), -1
 * restores the default (the GPU's where the device has float64). */
void vx__render_scene_rows_on_gpu(vx_render_scene* rs, int on);
/* Benchmarks: the float variant's trace kernel from other SPIR-V words (a
 * variant of shaders/trace.comp with the same bindings and constants; NULL
 * restores the built-in one), and likewise the beam pass's (shaders/beam.comp);
 * tag (nonzero) tells their pipelines apart. The words must outlive their use. */
void vx__render_scene_trace_kernel(vx_render_scene* rs, const uint32_t* spirv, size_t bytes, const uint32_t* beam_spirv,
                                   size_t beam_bytes, uint32_t tag);
/* Benchmarks and tests: the screen cull (-1 the default: on for the
 * built-in kernel, off for another; 0 off, 1 on), for the kernel set by
 * vx__render_scene_trace_kernel. */
void vx__render_scene_trace_variant(vx_render_scene* rs, int cull);
/* Benchmarks and tests: the primary rays' starts below the root
 * (trace.comp and trace_compact.comp, scenes of one instance; -1 the
 * default: on for GPUs, off for CPU devices; 0 off: every walk from the
 * root; 1 on). */
void vx__render_scene_trace_path(vx_render_scene* rs, int path);
/* Benchmarks and tests: the grid walk (vx_render_scene_desc.grid_budget)
 * for the models that have a grid (-1 the default, on; 0 off: every model
 * walks its octree; 1 on). */
void vx__render_scene_grid(vx_render_scene* rs, int on);
/* Tests: the models whose grid the walk takes now (grid_at; after
 * vx_render_scene_update_model, those whose grids were made again). */
uint32_t vx__render_scene_grid_models(const vx_render_scene* rs);
/* Benchmarks and tests: the union grid over a converter's regions
 * (render_scene.c grid_union: trace.comp's kernel of one instance walks it
 * instead of each region's grid under the BVH; -1 the default, on where it
 * holds; 0 off; 1 on). Returns the instances it holds (0: none built). */
uint32_t vx__render_scene_grid_union(vx_render_scene* rs, int on);
/* Benchmarks: the last frame's traced pixels (the rest written as misses);
 * false where it traced the whole image (no cull). */
bool vx__render_scene_traced(const vx_render_scene* rs, uint64_t* pixels);
/* Benchmarks and tests: lists the shadow map's nodes again for a map of
 * side texels (1: no map); s is the scene the GPU scene was made from. */
vx_result vx__render_scene_smap_side(vx_render_scene* rs, const vx_svo_scene* s, uint32_t side, vx_error* err);
/* Dense occupancy grid of the scene (identity world_from_grid) for the baseline. */
vx_result vx__dense_prepare(vx_render_scene* rs, const vx_svo_scene* s, uint64_t max_cells, vx_error* err);
vx_result vx__dense_dispatch(vx_render_scene* rs, const vx_render_desc* desc, uint32_t repeat, double* seconds,
                             float* depth_out, vx_error* err);

#endif
