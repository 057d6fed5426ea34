/* render/trace.h - the tracer's plain-C layer, shared by render/ and probes/:
 * camera and frame set-up, affine helpers, the colours of the debug modes,
 * scene checks and the CPU reference's grid walk. It needs no Vulkan (the
 * library vx_trace builds without it: bvh.c, cpu_trace.c, render_common.c).
 * Names keep the vx__ prefix: this is the toolkit's own layer under the
 * public render.h, documented for the modules built on it, not for users. */
#ifndef VX_RENDER_TRACE_H
#define VX_RENDER_TRACE_H

#include "render/render.h"

/* ---- the glass walks' step limit, one rule for every light transport path -------- */

/* A walk through glass (probes/pathtrace.c glass_walk, the GPU path tracer's
 * and the photons' probes/shaders/path_common.glsl glass_walk, the passes'
 * render/shaders/pass_bodies.glsl glass_pass_walk) steps from box to box: a
 * uniform glass leaf of the octree (a collapsed block) at once, else one
 * cell. It gives up (the light is absorbed: the path ends, the pass pixel
 * gets nothing through this body) after this many steps, counted from the
 * model of the instance where the walk starts (2^depth cells a side): 12
 * sides (a straight crossing of the model cube passes at most 3 sides of
 * cells; four of them, i.e. a few internal reflections), at least 512 (the
 * path tracer's limit before, so small models keep their paths). The
 * shaders write the same expression. */
#define VX__GLASS_WALK_MIN 512u
#define VX__GLASS_WALK_SIDES 12u
static inline uint32_t vx__glass_walk_steps(uint32_t depth) {
    uint32_t side = depth < 21 ? 1u << depth : 1u << 21;
    return side * VX__GLASS_WALK_SIDES > VX__GLASS_WALK_MIN ? side * VX__GLASS_WALK_SIDES : VX__GLASS_WALK_MIN;
}

/* ---- camera and frame set-up, shared by the GPU and the CPU paths ----------------- */

/* Rays are generated relative to a reference point R near the scene (so the
 * GPU's floats keep the scene's precision even when the eye is far away, or
 * the scene far from the world's origin):
 *   perspective:  P(u,v) = t_start * (u*rx + v*uy)   d = normalize(fwd + u*rx + v*uy)
 *                 depth = t_start * |fwd + u*rx + v*uy| + s
 *   orthographic: P(u,v) = u*rx + v*uy               d = fwd
 *                 depth = t_start + s
 * where s is the distance along d from P, u,v in [-1,1] (v up) and
 * R = eye + t_start * fwd lies before all scene geometry.
 * R is the GPU's frame origin: every kernel works in world coordinates
 * minus R, differences the host takes in double per frame, and no world
 * coordinate reaches a kernel as a float: the instances' model-from-world
 * rows (their translation row . R + t in double, a float hi/lo pair), the
 * BVH's and the instances' boxes (rounded outward), the sun depth map's
 * origin, the lights' positions (vx__light_pack), the dense grid, the probe
 * grid's origin and the probes' positions, the cone volume's origin, the
 * photons' sources (the photons read back are moved by R again), the beam
 * pass (the frame's constants). Depth is a distance and the hits are model
 * cells, so nothing a kernel writes back is a world position but the
 * photons. A scene 6e6 from 0 with cells of 1/64 (a float there is 0.5
 * apart) gives the bits of the same scene at 0 seen from a camera moved
 * alike, on every GPU path (test_render_gpu's and test_cones'
 * test_far_origin). What position still limits is the double:
 * vx__gpu_float_range. */
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
    uint32_t beam;             /* beam pass block side; 1: off */
} vx__frame;

/* Scene facts (drawn instances, their world maps and boxes, the world
 * bounds, attribute colours) are svo/ functions: vx_svo_instance_drawn etc. */
/* Resolves defaults and the camera into a frame. */
vx_result vx__frame_setup(const double lo[3], const double hi[3], const vx_render_desc* desc, vx__frame* f,
                          vx_error* err);
/* The GPU kernels' float range: VX_ERR_LIMIT, naming the bounds, for a
 * scene whose world bounds [lo, hi] have a largest side past 2^56 or under
 * 2^-56 (a model scaled by 1e25 traced as empty and one scaled by 1e-20 off
 * the CPU reference; 1e-18 to 1e20 traced as it did: the limits keep a
 * margin), or lie farther from 0 than 2^52 times that side (a double there
 * cannot tell the scene's corners apart: unit cells at 1e25). The bounds'
 * distance from 0 is no float limit itself: the kernels work relative to
 * the frame's reference point (vx__frame), so cells of 2^30 at 1e20 trace
 * as the CPU reference does (refused, as past 2^56 from 0, until stop 63;
 * test_render_gpu's test_float_range). Every GPU frame checks it
 * (trace.comp's, the compact layout's, the pass pipeline's, the probe
 * modes' and path tracer's) and so does the GPU bake. An empty scene (lo >
 * hi, or all 0) passes. The CPU reference (double) has no such limit. */
vx_result vx__gpu_float_range(const double lo[3], const double hi[3], vx_error* err);
/* The pixels whose rays can meet the box [lo, hi] (world space), as the
 * rectangle [rect[0], rect[2]) x [rect[1], rect[3]) (empty: all four 0): the
 * box's corners projected with f's camera, two pixels of margin on each side
 * (a sample's offset, the GPU's float rays), the whole image where the box
 * reaches the eye's plane and nothing where it lies behind that plane. A
 * pixel outside the rectangle misses: trace.comp traces only the rectangle. */
void vx__frame_rect(const vx__frame* f, const double lo[3], const double hi[3], uint32_t rect[4]);
/* The screen cull's dispatch shape, for trace.comp and trace_compact.comp:
 * rect as vx__frame_rect (cull) or the whole image, the trace pass's 8x8
 * groups over it, and the miss pass's (MISS_PASS: one invocation per pixel
 * outside the rectangle, 64 a group, at most 65535 groups in x; shaders/
 * screen_cull.glsl numbers them). Returns whether a miss pass is needed (the
 * rectangle is not the whole image); *traced the rectangle's pixels. */
bool vx__frame_cull(const vx__frame* f, const double lo[3], const double hi[3], bool cull, uint32_t rect[4],
                    uint32_t groups[3], uint32_t miss_groups[3], uint64_t* traced);
/* The BVH walk's start per screen tile (trace.comp's primary rays, scenes
 * of several instances): the image in tiles of 2^*shift pixels a side, at
 * most VX__TILES_X x VX__TILES_X of them (*nx a row, row-major), and per
 * tile the deepest BVH node whose subtree holds every leaf whose box the
 * tile's rays can meet (a node's box's rectangle as vx__frame_rect's, the
 * descent stopping where both children's rectangles meet the tile), or
 * VX__TILE_NONE where none can. A ray's walk from that node visits the same
 * leaves in the same order as from the root (the skipped subtrees' boxes
 * lie outside its pixel's rectangles), so its hit and steps are the same.
 * Nodes past 0xFFFE are not named (their parents start instead). */
#define VX__TILES_X 32
#define VX__TILE_NONE 0xFFFFu
void vx__frame_tiles(const vx__frame* f, const vx_bvh* bvh, uint16_t tiles[VX__TILES_X * VX__TILES_X],
                     uint32_t* shift, uint32_t* nx);
/* The screen tiles of frame f: 2^shift pixels a side (shift >= 3), nx x ny
 * of them, at most VX__TILES_X a side; vx__frame_tiles' grid and the
 * primary rays' starts below the root (render_scene.c). */
void vx__frame_tile_grid(const vx__frame* f, uint32_t* shift, uint32_t* nx, uint32_t* ny);
/* Sub-pixel offset of sample i in [-0.5, 0.5)^2 (sample 0 is the centre). */
void vx__sample_offset(uint32_t i, double* ox, double* oy);
/* The double-precision ray of image point (u, v) in [-1, 1]^2 (v up) by the
 * model above: P its start relative to R, o = R + P, d unit; returns the
 * depth of o along the ray (depth = the return value + s). The CPU reference
 * (vx_render_cpu), the compact layout's CPU walk and the probes' CPU renders
 * make their rays with it. */
double vx__frame_ray(const vx__frame* f, double u, double v, double P[3], double o[3], double d[3]);
void vx__affine_apply(const double m[12], const double p[3], double out[3]);
/* Inverse of a 3x4 affine map; false if singular. */
bool vx__affine_inverse(const double m[12], double out[12]);
/* Colour of an instance id for VX_RENDER_INSTANCE; heat map for iterations. */
void vx__instance_color(uint32_t id, float rgb[3]);
void vx__heat_color(uint32_t iterations, float rgb[3]);
/* Checks models and instances for the tracer's limits (depth, invertible). */
vx_result vx__check_scene(const vx_svo_scene* s, vx_error* err);

#define VX__SKY_R 0.62f
#define VX__SKY_G 0.75f
#define VX__SKY_B 0.92f

/* ---- CPU reference internals used by the benchmark's dense baseline ----------------- */

/* Calls fn for every filled model cell (via vx_svo_decode_model) placed in
 * grid space with floor(M (v + 1/2) + t). */
/* One step of the CPU reference's double-precision walk: from `cell`, inside an
 * empty block of side B (a power of two), to the first cell past that block along
 * o + t d. Ties between axes within 1e-9 (relative) set *amb (the pixel is then
 * ambiguous to the GPU's float walk); a step that leaves the model (`size`) or
 * reaches tx returns false. The reference and the compact layout's CPU walk share
 * it, so both step by the same rules. */
bool vx__grid_step_out(int64_t cell[3], int64_t B, const double o[3], const double d[3], double tx,
                       const uint32_t size[3], double* t, bool* amb);

typedef void (*vx__grid_cell_fn)(void* user, int64_t x, int64_t y, int64_t z);
vx_result vx__scene_grid_cells(const vx_svo_scene* s, vx__grid_cell_fn fn, void* user, vx_error* err);

#endif
