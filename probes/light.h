/* probes/light.h - the lighting model of voxkit's GI methods, shared by the
 * probe bake and the path tracer (probes/) and by the GI modules that trace
 * the same light (photons/): random streams independent of threads, the
 * light of a frame (sun, sky, the frame's lights, emissive voxels, the
 * scene's materials), surfaces and direct light, the path tracer's
 * radiance, the materials as the shaders read them, and the render set-up
 * that a probe render or a GI pass resolves before it traces (vx__prender).
 * Names keep the vx__ prefix, as render/gpu.h: the toolkit's own layer,
 * documented for modules, not part of the user API (probes.h).
 *
 * Typical use by a GI module:
 *   vx__prender P;
 *   vx__prender_setup(scene, NULL, false, &(vx_probe_render_desc){...}, &P, err);
 *   ... P.L (the light), P.lo / P.hi (the scene's bounds) ...
 *   vx__pack_materials(&P.L, ids, n, mats);   // for the shaders' mats[]
 *   vx__prender_free(&P); */
#ifndef VX_PROBES_LIGHT_H
#define VX_PROBES_LIGHT_H

#include <math.h>

#include "probes/probes.h"
#include "render/trace.h"

/* ---- random numbers: one stream per (seed, a, b, c), independent of threads ---- */

typedef struct vx__rng {
    uint64_t s;
} vx__rng;

static inline uint64_t vx__mix64(uint64_t z) {
    z += 0x9E3779B97F4A7C15ULL;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31);
}
static inline vx__rng vx__rng_make(uint64_t seed, uint64_t a, uint64_t b, uint64_t c) {
    vx__rng r = {vx__mix64(vx__mix64(vx__mix64(vx__mix64(seed) ^ a) ^ b) ^ c)};
    return r;
}
/* uniform in [0, 1) with 53 bits */
static inline double vx__rng_next(vx__rng* r) {
    r->s += 0x9E3779B97F4A7C15ULL;
    uint64_t z = r->s;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    z ^= z >> 31;
    return (double)(z >> 11) * 0x1.0p-53;
}

/* ---- the lighting model shared by the baker and the renderer -------------------- */

/* An emissive voxel as a light for next-event estimation: a parallelepiped
 * corner + a u + b v + c w (u, v, w in [0,1]: the instance's cell axes),
 * emitting radiance `rad` from its faces; `area` its surface area. */
typedef struct vx__emitter {
    double corner[3], axis[3][3];
    double rad[3];
    double area;
} vx__emitter;

typedef struct vx__light {
    const vx_render_caster* caster;
    const vx_svo_scene* scene;
    double light_dir[3]; /* unit */
    double sun[3];       /* irradiance on a surface facing the light */
    double sky[3];       /* radiance (a uniform sky) */
    /* sky by direction (vx__sky) when sky_dir.type is not VX_SKY_DEFAULT:
     * the path tracer's (vx_probe_render_desc.sky, texels borrowed) */
    vx_sky sky_dir;
    vx_sky_texels sky_map;
    /* the scene's materials by material id (vx_svo_attr_material: the
     * material channel, else the palette index; ids up to 65535, so a
     * sorted table, not one entry per id): vx__light_material and
     * vx_material_emitted look them up */
    vx_svo_material_table mt;
    vx_material diffuse;  /* what an id without a material reads */
    bool materials;       /* some material is metal or glass */
    const vx_light* lights; /* the frame's lights (sampled at every vertex) */
    uint32_t light_count;
    bool voxel_lights; /* some light stands for emissive voxels (VX_LIGHT_FROM_VOXELS) */
    /* model-from-world maps of the scene's instances (12 per instance), for
     * walks through glass voxels; NULL without glass */
    double* inst_inv;
    /* emissive voxels sampled by power: cdf[i] = power of 0..i / em_power */
    vx__emitter* em;
    double* em_cdf;
    uint32_t em_count;
    double em_power; /* sum of luminance(rad) * area: the area density of a point on any emitter is lum(rad) / em_power */
    const vx_allocator* alloc;
} vx__light;

/* Fills the materials and emission from the scene's MATL records
 * (vx_svo_scene_material) and resolves defaults. Owns memory: release with
 * vx__light_free. */
vx_result vx__light_init(vx__light* L, const vx_render_caster* c, const vx_svo_scene* s, const double light_dir[3],
                         const double sun[3], bool no_sun, const double sky[3], bool black_sky, vx_error* err);
/* Adds the frame's lights (borrowed; validated here) and, with emitters, the
 * scene's emissive voxels as lights for next-event estimation. */
vx_result vx__light_add(vx__light* L, const vx_light* lights, uint32_t n, bool emitters, vx_error* err);
void vx__light_free(vx__light* L);
/* The material of material id `id` (the default diffuse where the scene has none). */
static inline const vx_material* vx__light_material(const vx__light* L, uint32_t id) {
    const vx_material* m = vx_svo_material_table_find(&L->mt, id);
    return m ? m : &L->diffuse;
}
/* The emitted radiance of a voxel (attribute `attr` of model m): its colour,
 * or its material's emission colour, times its material's emission
 * (vx_material_emitted, by vx_svo_attr_material); false, rad untouched, where the voxel
 * does not emit. The one rule for the path tracer's emitter table and the
 * photons' emitting faces. */
bool vx__light_voxel_radiance(const vx__light* L, const vx_svo_scene* s, const vx_svo_model* m, uint32_t attr,
                              double rad[3]);
/* Sky radiance towards unit d: L->sky, or L->sky_dir by direction. */
void vx__sky(const vx__light* L, const double d[3], double out[3]);

typedef struct vx__surface {
    double p[3];   /* hit point, offset off the surface along the normal */
    double n[3];
    double albedo[3];
    double emit[3];
    uint32_t material; /* material id (vx_render_ray_hit.material) */
    double cell; /* world size of the hit instance's cells */
} vx__surface;

/* Resolves a hit into a surface; o, d the ray. */
void vx__surface_of(const vx__light* L, const double o[3], const double d[3], const vx_render_ray_hit* h,
                    vx__surface* s);
/* Directional light reflected by a surface (albedo/pi * sun * n.l * visibility). */
void vx__direct(const vx__light* L, const vx__surface* s, double out[3]);
/* The same with BRDF f in place of albedo/pi (f * sun * n.l * visibility; metal: vx__metal_of). */
void vx__direct_f(const vx__light* L, const vx__surface* s, const double f[3], double out[3]);
/* Radiance arriving at o from direction d (the path tracer, pathtrace.c):
 * the first surface's emission and direct light plus up to `bounces` further
 * diffuse or glossy bounces (glass events do not count, nor the path's first
 * VX__METAL_CHAIN metal events: a metal record's specular lobe, whatever its
 * roughness, as the probe modes' chain; pathtrace.c says why),
 * next-event estimation of every light with multiple importance sampling,
 * Russian roulette after VX__RR_DEPTH bounces. indirect: leave out the first
 * surface's emission and its light from the sun and the frame's lights
 * (what the pass pipeline's direct pass delivers; from the emissive voxels
 * too when a light stands for them), and the background of a primary miss;
 * where that surface is glass and its glass lobe is drawn, all the path
 * finds through and off the glass counts (the direct pass gives only the
 * glass's Lambert share: render/pipeline.h). Returns whether the ray hit a voxel. */
bool vx__path(const vx__light* L, const double o[3], const double d[3], uint32_t bounces, bool indirect, vx__rng* rng,
              double out[3]);
#define VX__RR_DEPTH 3
/* Glass at the camera's first surface s (met by the ray ro + t rd, hit h) in
 * the probe modes (render_gi.c): s's lobe drawn as the path tracer does;
 * where it is the glass lobe, the path tracer's events through the glass
 * (its Fresnel choice, the colour at entry, the walk) up to the first surface
 * that is not glass, thr the path's weight. Returns -1: the Lambert lobe,
 * nothing changed; 0: the path left the scene along rd (thr 0 where it was
 * absorbed or given up); 1: s (and h, ro, rd) is that surface; 2: s is an
 * opaque voxel met from inside the glass (no light is sampled there). */
int vx__glass_lobe(const vx__light* L, double ro[3], double rd[3], vx_render_ray_hit* h, vx__surface* s, vx__rng* rng,
                   double thr[3]);
/* Metal at a surface s met along unit d in the probe modes (render_gi.c): false where s's material is not
 * metal. kd: its Lambert lobe's weight (what takes the probes' light where a diffuse surface's albedo
 * does); fl: its BRDF f(-d, light_dir), Lambert and GGX lobes (vx__direct_f's f). Draws no number. */
bool vx__metal_of(const vx__light* L, const vx__surface* s, const double d[3], double kd[3], double fl[3]);
/* A direction wi of metal surface s's specular lobe alone (met along d), by the path tracer's sampler
 * (visible normals; three numbers), and its weight w = f_spec cos / pdf_spec (F G2 / G1): an unbiased
 * estimate of the light the lobe reflects is w times the radiance arriving along wi. false: no
 * direction (below the horizon). */
bool vx__metal_spec(const vx__light* L, const vx__surface* s, const double d[3], vx__rng* rng, double wi[3],
                    double w[3]);
/* The most metal events of one camera sample's chain in the probe modes (render_gi.c render_pixel; probe.comp
 * render()'s METAL_CHAIN, the same number), and the most metal events a path tracer's path (vx__path, probe.comp
 * path(): the bake's paths and the reference's) follows without spending a bounce on them, so that the
 * reference counts what the probe modes count: the first metal's lobe, a metal it meets, that one's lobe, ... A
 * constant, not the render's bounce count: the GPU keeps each metal surface of the chain in arrays of a size
 * fixed when the kernel is compiled (they are shaded after the event loop, so that the kernel inlines the
 * shading once), and the probes' light at the chain's end stands for the rest of the path whatever the count
 * (with the default count, 2, a mirror facing a metal wall would stop at 0.49x the converged path tracer).
 * 4: that mirror and wall (test_metal_gi's test_lobe_meets_metal, gi, 64-256 samples) give in red 0.08, 0.12,
 * 0.131, 0.139, 0.140 with chains of 2, 3, 4, 6, 8 against the path tracer's 0.164 at 10 bounces: past 4 the
 * weight F^k left is small. A metal met past the chain is shaded by its own BRDF and kd, with no lobe. The path
 * tracer's cap is the same 4: the paths' free events anywhere on the path (not only from the camera), so that
 * the probes' light, baked by the same paths, stands for the rest of a chain as the reference's paths go on;
 * with it the reference at the default 2 bounces gives that mirror 0.98x of its 10-bounce light (0.36x before). */
#define VX__METAL_CHAIN 4
/* Cosine-weighted direction around unit n. */
void vx__cosine_dir(const double n[3], double u1, double u2, double d[3]);

/* ---- the render set-up ----------------------------------------------------------- */

/* What a probe render resolves before it traces, the same on the CPU
 * (render_gi.c) and the GPU (probe_gpu.c): the checked desc, the frame, the
 * light (the probes', or the bake defaults; L.caster left NULL), samples
 * and bounces. */
typedef struct vx__prender {
    vx_probe_render_desc d;
    vx__frame f;
    double lo[3], hi[3]; /* world bounds of the scene */
    vx__light L;
    uint32_t spp, bounces;
    bool uses_probes, lightfield;
} vx__prender;

/* complete: ps holds every probe (the probe modes need that). */
vx_result vx__prender_setup(const vx_svo_scene* s, const vx_probe_set* ps, bool complete,
                            const vx_probe_render_desc* desc, vx__prender* out, vx_error* err);
/* Rows the desc renders (desc->rows), of height. */
uint32_t vx__prender_rows(const vx_probe_render_desc* desc, uint32_t height);
void vx__prender_free(vx__prender* P);

/* The materials of the colors[] entries whose material ids are ids[0..n)
 * as path_common.glsl reads them (mats[]): 8 floats each, (type: 0 diffuse,
 * 1 metal, 2 glass; GGX alpha; metalness; specular), (ior, transmission, 0, 0).
 * probe_gpu.c and photons/ upload them. */
void vx__pack_materials(const vx__light* L, const uint16_t* ids, size_t n, float* out);

#endif
