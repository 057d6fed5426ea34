/* cones/cones.h - voxel cone tracing (issue 12) as a GI method of the pass
 * pipeline (render/pipeline.h: "gi=cones").
 *
 * What it keeps on the GPU, beside the scene's octrees, and only when a
 * scene asks for cone tracing (nothing is added to .svo files):
 *
 *   a pre-filtered radiance volume: a mip pyramid of voxels over the scene's
 *   world bounds, level 0 of `res` voxels along the longest side (cubic
 *   voxels of side s), each level halving the one below (ceil), up to one
 *   voxel. A voxel entry is premultiplied radiance (RGB) and opacity (A) as
 *   four halfs (8 bytes): six entries per voxel (anisotropic, the default:
 *   what a viewer on the +x, -x, +y, -y, +z, -z side sees), or one
 *   (isotropic).
 *
 * Why a world-space volume and not radiance per octree node. The octree is
 * a DAG: one subtree stands for every place (and every instance) where the
 * same geometry appears, while the light on those places differs. Radiance
 * per node would need one copy per path through the DAG (per (instance,
 * node) pair and, inside a model, per shared occurrence), i.e. undoing the
 * minimization. Geometry (what the octree shares) and light (what differs per
 * place) are therefore kept apart: the volume is rebuilt from the octrees by
 * tracing (voxelization below), so a shared subtree is lit separately wherever
 * it is placed, rotations and mirrors of instances included, and moving an
 * instance costs a voxelization, not a rebuild of any octree. The price is
 * a dense pyramid (8/7 of level 0): 130^3 is 20 MB isotropic, 120 MB
 * anisotropic, plus 480 bytes per voxel with geometry (the recorded
 * surfaces); res is capped at VX_CONE_RES_MAX.
 *
 * The three steps, all compute shaders over the tracer's scene bindings:
 *   voxelize (when instances move; vx_cone_gi_voxelize): each level-0 voxel
 *     is crossed by samples^2 axis-parallel rays from each of its six faces
 *     (octree rays, the tracer's traversal). The share that hits is the
 *     opacity seen from that side (projected coverage); the voxels with any
 *     hit are listed and, for each side, the visible surface is recorded:
 *     where the rays hit first, its normal, albedo and emission (a ray that
 *     starts inside a solid cell sees an interior: opaque, and given the
 *     voxel's mean surface radiance, so that a cone reading a slab's sides
 *     along its plane is not darkened).
 *   inject (when a light changes; vx_cone_gi_inject): each listed voxel's
 *     recorded surfaces are lit with the sun (one shadow ray; none when there
 *     are lights), every vx_light
 *     (one shadow ray each, exact irradiance as the direct pass) and their
 *     emission: radiance = emission + albedo / pi * irradiance. Isotropic:
 *     the voxel's radiance is the mean over its visible surfaces, its
 *     opacity the mean of the six sides'. With bounces > 1 the surfaces then
 *     also gather diffuse cones from the volume and are injected again.
 *   filter: level l+1 from level l on the GPU, one dispatch per level;
 *     isotropic: the mean of the 8 children; anisotropic: per side, the
 *     children composited front to back along that axis, then the mean of
 *     the 4 columns (what a viewer on that side sees through the block).
 *     After a voxelization every voxel of every level; after a light change
 *     only the voxels with geometry below them (lists per level built at
 *     voxelization: a parent once per occupancy bit), since every other
 *     voxel stays empty.
 *   atlas: the levels are copied into one 3D texture (RGBA16F; every level
 *     with a zero voxel around it, the entries stacked in z) that the cones
 *     sample with the hardware's trilinear filter: one fetch per entry read
 *     instead of eight buffer loads; after a light change only the occupied
 *     voxels are copied.
 *
 * Cone tracing (the gi pass, per pixel): the pixel's first surface (a
 * pixel-centre primary ray, as the G-buffer's) gathers `cones` diffuse cones
 * around its normal: directions cosine-distributed over the hemisphere
 * (a Fibonacci spiral, rotated per sample), equal weights, half angle
 * acos(1 - 1/cones) unless `aperture` is given (each cone then covers an equal
 * share of the hemisphere's solid angle). Along a cone the volume is read at
 * the level whose voxel matches the cone's diameter, trilinear in each of the
 * two nearest levels and linear between them (quadrilinear), anisotropic
 * entries weighted by the squared direction components; the opacity is
 * corrected for the step length and composited front to back; what a cone
 * does not hit sees the sky. Near-surface offset: the cone starts `offset`
 * level-0 voxels off the surface along its normal (default 1.5: the first
 * samples, of one voxel's diameter, then no longer touch the voxel holding
 * the surface) and the first sample is half a voxel further along the cone.
 * The gi image is albedo * sum(w_i L_i) (indirect radiance of a diffuse
 * surface); its alpha holds the cone ambient occlusion (the weighted share
 * of the cones' light that the volume does not block, within ao_distance),
 * and output = VX_CONE_OUTPUT_AO writes that share into RGB too (--show gi
 * then shows the AO).
 *
 * Light leaks: a wall thinner than a voxel at the level a cone reads is
 * partly transparent there (its opacity is averaged with the empty space
 * around it), so light behind it leaks through; anisotropic entries keep
 * the lit side's radiance off the dark side but not the opacity.
 * docs/PERFORMANCE.md "Cone tracing (issue 12)" measures it. */
#ifndef VX_CONES_H
#define VX_CONES_H

#include "render/pipeline.h"

#ifdef __cplusplus
extern "C" {
#endif

#define VX_CONE_RES_MAX 512
#define VX_CONE_CONES_MAX 32
#define VX_CONE_LEVELS_MAX 16

typedef enum vx_cone_output {
    VX_CONE_OUTPUT_RADIANCE = 0, /* the indirect radiance (alpha: AO) */
    VX_CONE_OUTPUT_AO            /* the cone AO in RGB and alpha */
} vx_cone_output;

/* Options; zero-initialised means the defaults (vx_cone_desc_defaults).
 *  res:         level-0 voxels along the scene's longest side (0: 128)
 *  samples:     rays per face side when voxelizing, samples^2 per face (0: 2; at most 8)
 *  isotropic:   one entry per voxel instead of six (anisotropic, the
 *               default: the tests' analytic cases and the path tracer's
 *               room are 2-3 times closer with six)
 *  cones:       diffuse cones per pixel (0: 6; at most VX_CONE_CONES_MAX)
 *  aperture:    cone half angle in degrees (0: acos(1 - 1/cones))
 *  offset:      near-surface offset in level-0 voxels (0: 1.5; below 64)
 *  step:        march step as a share of the cone's diameter (0: 0.5; 0.05 to 4)
 *  ao_distance: world distance within which the cone AO counts occlusion (0: unlimited)
 *  bounces:     diffuse bounces kept in the volume (0: 1: direct light only)
 *  light_dir, sun, sky: the light (0: the probe bake's defaults,
 *               vx_probe_bake_desc_defaults; no_sun / black_sky switch them off)
 *  sky_dir, sky_map: the sky by direction (svo/svo.h vx_sky, the file's;
 *               borrowed, the texels for as long as the method): constant
 *               replaces sky; gradient or environment map: what a cone
 *               leaves unoccluded sees the sky along its axis (a point
 *               sample of the cone), in the gi image and in the bounces
 *               kept in the volume; the method's sky_dir then gives the
 *               pipeline's background. NULL: the uniform sky
 *  lights:      frame lights injected too (borrowed; the frame must pass the same array);
 *               any replace the sun (as no_sun), as in the path tracer
 *  output:      what the gi image holds
 *  half_res:    the diffuse cones at one pixel of each 2 x 2 block, spread to
 *               the others on the same surface (normals within 18 degrees,
 *               within half a level-0 voxel of the pixel's tangent plane;
 *               a pixel with no such sample traces its own); the albedo, the
 *               specular cones and the cone shadows stay per pixel
 *  shadows:     cone soft shadows: the gi image also holds the direct light
 *               (the sun and every frame light, visibility from one cone
 *               towards each source as wide as the source), so the frame
 *               must have no direct pass (vx_gi_method.includes_direct)
 *  sun_angle:   the sun's angular diameter in degrees for the cone shadows
 *               (0: 0.53, the sun's; below 30)
 *  no_specular: metal records shaded as diffuse (the specular cones are
 *               otherwise traced wherever the scene has a metal record)
 *
 * Specular cones: where the scene has metal records (svo/svo.h vx_material),
 * the gi pass shades them as the path tracer's BSDF (probes/shaders/
 * path_common.glsl bsdf_of): f = kd / pi + GGX (alpha = roughness^2, Smith
 * masking, Schlick Fresnel with f0 from the metalness). The gi image there
 * is kd * sum w_i L_i (the diffuse cones) plus one cone along the mirror
 * direction, half angle atan(2 alpha) (2 alpha is tan(2 atan alpha) to first
 * order: twice the angle within which half of the GGX normals lie), at most
 * 45 degrees (and, as every cone, at most a third of its height above the
 * surface's tangent plane wide: past roughness 0.3 or so that limit, not the
 * roughness, sets the width), times the lobe's directional albedo f0 A + B for the view
 * angle (a table integrated on the CPU from the same lobe, so a constant
 * environment is exact up to its interpolation). The direct light of a
 * metal stays the direct pass's (diffuse) unless `shadows` is on, where it
 * is also diffuse: a specular highlight of the lights is not drawn. Glass
 * seen directly (render/pipeline.h): the gi image holds its glass lobe, the
 * direct pass's walk through the glass (render/shaders/pass_bodies.glsl
 * glass_lobe) with the cones' light added at the surface behind it, plus
 * the cones' light on its Lambert share (1 - transmission); in the volume a
 * glass voxel counts 1 - transmission of its opacity (the cones see through
 * a window). A scene without metal records has no specular path in the
 * shader, one without glass no glass path (specialised out). */
typedef struct vx_cone_desc {
    uint32_t res;
    uint32_t samples;
    bool isotropic;
    uint32_t cones;
    double aperture;
    double offset;
    double step;
    double ao_distance;
    uint32_t bounces;
    double light_dir[3], sun[3], sky[3];
    bool no_sun, black_sky;
    const vx_sky* sky_dir;
    const vx_sky_texels* sky_map;
    const vx_light* lights;
    uint32_t light_count;
    vx_cone_output output;
    bool half_res;
    bool shadows;
    double sun_angle;
    bool no_specular;
} vx_cone_desc;

vx_cone_desc vx_cone_desc_defaults(void);

/* The volume as built (for tests and tools). */
typedef struct vx_cone_info {
    uint32_t levels;
    uint32_t dims[VX_CONE_LEVELS_MAX][3];
    uint32_t entries;     /* 1 isotropic, 6 anisotropic */
    double origin[3];     /* world corner of voxel (0,0,0) at every level */
    double voxel;         /* level-0 voxel side, world units */
    uint32_t surface_voxels; /* level-0 voxels with geometry */
    uint32_t occupied_voxels; /* voxels of the levels above 0 with geometry below them (filtered after a light change) */
    bool specular;        /* the gi pass traces specular cones (some attribute record is metal) */
    uint64_t bytes;       /* GPU memory of the volume and its lists */
    double voxelize_ms, inject_ms, filter_ms; /* GPU time of the last of each step */
} vx_cone_info;

typedef struct vx_cone_gi vx_cone_gi;

/* Builds the volume (voxelize, inject, filter) for scene (the one rs was
 * made from; rs and scene must outlive *out) and fills *method (valid while
 * *out lives; name "cones") with the render callback and the light the
 * pipeline's direct pass must use. */
vx_result vx_cone_gi_create(vx_render_scene* rs, const vx_svo_scene* scene, const vx_cone_desc* desc,
                            vx_gi_method* method, vx_cone_gi** out, vx_error* err);
void vx_cone_gi_destroy(vx_cone_gi* cg);
/* After instances moved (vx_render_scene_set_frame): voxelize, inject and
 * filter again. */
vx_result vx_cone_gi_voxelize(vx_cone_gi* cg, vx_error* err);
/* After a light change: the new sun (light_dir, sun, sky of desc; the
 * geometry options are ignored, and the sky by direction stays the one the
 * method was made with) injected and filtered; method is updated. */
vx_result vx_cone_gi_inject(vx_cone_gi* cg, const vx_cone_desc* desc, vx_gi_method* method, vx_error* err);
void vx_cone_gi_info(const vx_cone_gi* cg, vx_cone_info* out);
/* Downloads level `level` as float RGBA, entries per voxel in x-fastest
 * order (dims[level] voxels, info.entries each): out holds
 * 4 * entries * voxels floats. */
vx_result vx_cone_gi_read_level(vx_cone_gi* cg, uint32_t level, float* out, size_t floats, vx_error* err);

#ifdef __cplusplus
}
#endif
#endif /* VX_CONES_H */
