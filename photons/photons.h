/* photons/photons.h - photon mapping on the GPU as a GI method of the pass
 * pipeline (render/pipeline.h: gi=photons): global and caustic photon maps,
 * rebuilt every pass, progressive radius shrinking.
 *
 * Usage:
 *   vx_gi_method gm; vx_photon_gi* pg;
 *   vx_photon_gi_create(rs, &scene, NULL, &(vx_photon_desc){ .photons = 1 << 20 }, &gm, &pg, &err);
 *   frame_desc.gi = &gm;   ... vx_frame_render(...) ...   vx_photon_gi_destroy(pg);
 *
 * Light. The method's light is the probe renderer's (probes/probes.h): the
 * sun and sky of `light` (a probe set, possibly of no probes) or the bake
 * defaults, the emissive voxels (MATL _emit), and the desc's lights
 * (vx_light: directional, point, spot, sphere, rect; any replace the sun).
 * Photons leave every source with a probability proportional to its power
 * (luminance): the sun and directional lights, and the sky, through the disk
 * of the scene's bounding sphere seen from their direction; point and spot
 * lights from their position (a spot's cone weighted by its falloff, glTF's
 * range window applied at the first hit); sphere and rect lights and
 * emissive voxel faces from a uniform point with a cosine direction (only
 * the exposed faces of the emissive voxels, those whose neighbour cell in
 * their model is empty, picked by power: a buried face emits nothing). Each
 * photon carries its source's power / (probability * photons), so the sum of
 * the emitted power is the lights' power.
 *
 * Tracing (photons/shaders/photon.comp). Each photon walks the BVH and the
 * octrees with the path tracer's materials (probes/shaders/path_common.glsl:
 * Lambert, GGX metal, glass with refraction and Fresnel, the walk through a
 * glass voxel; an opaque voxel met from inside glass, as the floor under a
 * glass block, is a surface there). At every surface that is not glass it is stored (position,
 * incoming direction, normal, power), then scatters by the BSDF with Russian
 * roulette on its throughput (survivors keep about their power). A photon
 * whose path since the light went only through glass is a caustic photon
 * (the caustic map); all others form the global map. A photon that reached
 * its first surface straight from a light the direct pass shades (sun,
 * frame lights; emissive voxels only when a light stands for them) is
 * marked direct: the estimate at the camera's first surface leaves it out,
 * since the pipeline's direct pass delivers that light.
 *
 * Storage: a hashed uniform grid per map, cell = the map's gather radius,
 * rebuilt every pass (count per bucket, claim ranges, scatter; three
 * dispatches), over 2^k buckets, at least twice the photons stored in the
 * pass (at most twice the capacity). Hashed rather than dense: its memory follows the photon
 * count (2^k buckets, at least twice the photons' capacity), not the
 * scene's extent over the radius, which for a 0.01-diagonal radius would
 * be 10^6 cells of which most stay empty; collisions cost only tests of
 * photons that the distance check rejects. A gather reads the 27 cells
 * around the point (the 3^3 cells a sphere of radius r can touch) but those
 * whose box lies farther than r, a bucket two of them share once; cell = r
 * rather than 2r with 8 cells: those would cover twice the area of photons
 * to test on a surface (16 r^2 against about 8 r^2). The estimate runs in
 * two steps: the camera's paths, then the Lambert sums of each tile of
 * 8 x 8 pixels over the photons of the buckets the tile needs, read once
 * into shared memory, 4 lanes a pixel in images of few tiles (photon.comp
 * tile_sum).
 *
 * Estimate: at the camera's first surface that is neither glass nor glossy
 * (glass on the way is followed by Fresnel choice, as the path tracer does;
 * a glossy surface, metal or GGX, gives its diffuse lobe from the photons
 * and follows its specular lobe by one sampled ray per pass, Jensen's rule,
 * taking from photons there only the light such a ray cannot meet: the
 * direct pass's lights' photons, caustic photons of sun and frame lights),
 * the radiance towards the camera is sum f(wo, wi_p) Phi_p / A over the
 * photons of each map within its radius and of the surface's orientation
 * (normals within 25 degrees; on a Lambert surface f is one factor after
 * the sum), A the area of the faces of that orientation within r of the
 * point (pi r^2 on an unbroken plane; less where the surface ends within
 * r, a floor's edge or a wall's foot, whose photons were missing from the
 * disk: photon.comp kernel_factors; the plain disk where the radius passes
 * 6 cells or the model has no attributes; other models' faces in the
 * plane found by a short ray; the cells looked up as bits, one per cell, in
 * models of at most 512 cells a side, which the glass walk reads too);
 * caustics from the caustic map with its own,
 * smaller radius; indirect diffuse directly from the global map, or with
 * final_gather rays by a final gather for the light that bounced at least
 * once: BSDF-sampled rays from the first surface, each ending at the next
 * surface that is not glass with the whole photon estimate there (both
 * maps, direct photons too; glass on the way followed by Fresnel choice),
 * while the light straight from the sky and emissive voxels comes from the
 * photons at their first surface there (rays would have to find a small
 * bright emitter: noise); in a full image (vx_photon_render) those photons
 * include the ones the direct pass's lights brought. Each sum is exact
 * (64-bit fixed point per photon term), so its value does not depend on the
 * order the photons were stored in. What the estimate gives is the pipeline's gi: the indirect light
 * leaving the first surface (vx_probe_render PT_INDIRECT's quantity).
 * Sphere and rect lights seen by the camera through glass are left out
 * (the path tracer shows them), and a camera ray that meets a sphere or rect
 * light still gathers behind it (the path tracer stops there).
 *
 * Progressive: pass k (the pipeline's sample k) emits fresh photons with
 * radius r_k, r_k^2 = r_0^2 prod_{i=1..k} (i + alpha) / (i + 1) (Knaus and
 * Zwicker 2011, the memoryless form of stochastic progressive photon
 * mapping); the mean over the passes converges to the path tracer's answer:
 * its bias shrinks with the radius while the variance of the mean still
 * falls (alpha in (0, 1)).
 *
 * Storage per pass: 32 bytes per stored photon twice (stored, sorted), 8
 * bytes per bucket; 48 bytes a pixel for the estimate's second step, in
 * the stored photons' buffer once they are sorted, or after the photons
 * where the camera's paths run beside the trace (stats.fused: the
 * paths need no photon there, no final gather, no glossy surface with a
 * diffuse lobe, no light whose photons a glossy surface gathers; the
 * trace's workgroup 32 or 64); one bit per cell (two with glass) of the models
 * of at most 512 cells a side, 2^28 cells in all. A pass over the capacity
 * keeps the first photons by index (vx_photon_desc.capacity). */
#ifndef VX_PHOTONS_H
#define VX_PHOTONS_H

#include <stdbool.h>
#include <stdint.h>

#include "probes/probes.h"
#include "render/pipeline.h"
#include "render/render.h"
#include "svo/svo.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Options; zero-initialised means the defaults (vx_photon_desc_defaults).
 *  photons:        emitted per pass; 0: 2^20
 *  radius:         the global map's gather radius in the first pass, world
 *                  units; 0: the scene's bounding diagonal / 100
 *  caustic_radius: the caustic map's first radius; 0: radius / 4
 *  alpha:          radius shrinking per pass (above); 0: 2/3; 1 keeps it
 *  final_gather:   rays per pixel and pass of a final gather (0: none, the
 *                  global map's estimate at the first surface; at most 1024)
 *  bounces:        photons stored per path at most; 0: 8
 *  capacity:       stored photons per pass at most; 0: 4 x photons; at
 *                  least bounces + 1 (a photon's stores at most). A pass
 *                  whose photons would store more is traced twice again:
 *                  once counting each photon's stores, then with photons
 *                  0..C-1 alone, C the most whose stores fit, each carrying
 *                  1/C of the sources' power (stats.emitted C,
 *                  stats.dropped the others): the same photons whatever
 *                  order the GPU stores them in, and the estimate keeps its
 *                  expected value (the photons are independent draws);
 *                  such a pass costs three traces
 *  seed:           random streams (each pass its own); the same seed and
 *                  settings give the same image bitwise on a device (the
 *                  gather's sums are exact fixed-point, so the order the GPU
 *                  stores the photons in does not matter; over the
 *                  capacity, the photons kept go by index, above)
 *  workgroup:      invocations per workgroup of the trace, a power of two
 *                  32..1024; 0: 32 (a tuning knob: bench/photons_bench; on
 *                  the H200 the trace of the seed's Cornell setting took
 *                  2.6 ms at 32, 3.4 at 64: a workgroup of one SIMD group
 *                  frees its slot as soon as its photons end)
 *  batch:          photons each invocation of the trace traces in turn,
 *                  starting the next as soon as one ends (path regeneration:
 *                  a SIMD group's lanes stay busy while one photon of the
 *                  group bounces on); 0: 4, or 2 or 1 where 4 would leave
 *                  fewer than 2^17 invocations (small passes); at most 256
 *  light_dir:      towards the sun where `light` is NULL; zero: the bake default
 *  lights:         light_count lights (borrowed, validated; see above)
 *  sky_dir, sky_map: the sky by direction (svo/svo.h vx_sky, the file's;
 *                  as vx_probe_render_desc.sky): constant replaces the
 *                  uniform sky; gradient or environment map: sky photons
 *                  leave directions uniform on the sphere with power scaled
 *                  by the radiance towards them over the sky's mean (no
 *                  importance sampling: a small bright sun in a map is
 *                  noisy), the final gather's misses see it by direction,
 *                  and the pipeline's background shows it */
typedef struct vx_photon_desc {
    uint32_t photons;
    double radius;
    double caustic_radius;
    double alpha;
    uint32_t final_gather;
    uint32_t bounces;
    uint32_t capacity;
    uint64_t seed;
    uint32_t workgroup;
    uint32_t batch;
    double light_dir[3];
    const vx_light* lights;
    uint32_t light_count;
    const vx_sky* sky_dir;
    const vx_sky_texels* sky_map;
} vx_photon_desc;

/* The defaults (the one source; svo_render's --help prints them). Scene
 * dependent fields (radius, caustic_radius) stay 0. */
vx_photon_desc vx_photon_desc_defaults(void);

/* What the last pass did. */
typedef struct vx_photon_stats {
    uint32_t pass;
    uint64_t emitted;         /* photons traced (fewer than desc.photons when the stores passed the capacity) */
    uint64_t stored;          /* photons stored (both maps) */
    uint64_t dropped;         /* photons left out: their stores would have passed the capacity (see capacity) */
    double radius, caustic_radius; /* this pass's radii */
    double trace_ms, build_ms, gather_ms; /* GPU time: tracing, the grids' build (clear, count, alloc, scatter), the estimate */
    double paths_ms, density_ms; /* gather_ms's two steps: the camera's paths, the Lambert sums */
    double wall_ms;              /* host time of the whole pass: the GPU's, submissions, waits, downloads */
    bool fused;                  /* the camera's paths ran beside the trace, no barrier between (in trace_ms; paths_ms 0) */
} vx_photon_stats;

typedef struct vx_photon_gi vx_photon_gi;

/* Makes the method: fills *method (valid while *out lives) with the render
 * callback and the light the pipeline's direct pass must use (as
 * vx_probe_gi_create does); light may be NULL (the bake defaults). rs, scene,
 * light and desc->lights must outlive *out. */
vx_result vx_photon_gi_create(vx_render_scene* rs, const vx_svo_scene* scene, const vx_probe_set* light,
                              const vx_photon_desc* desc, vx_gi_method* method, vx_photon_gi** out, vx_error* err);
void vx_photon_gi_destroy(vx_photon_gi* pg);

/* Without the pipeline (tests, benchmarks): the mean of passes 0..passes-1
 * of the indirect light for the camera of base (pixel centres); with full,
 * the whole radiance instead: the first surface's emission and all photons
 * there (direct light too), the sky on a miss. out (RGBA float, alpha 1) is
 * freed with vx_render_image_free; its gpu_seconds is the sum of every
 * pass's GPU time. */
vx_result vx_photon_render(vx_photon_gi* pg, const vx_render_desc* base, uint32_t passes, bool full,
                           vx_render_image* out, vx_error* err);
void vx_photon_last_stats(const vx_photon_gi* pg, vx_photon_stats* out);

/* Downloads the last pass's stored photons and sums their power (RGB):
 * first: photons stored at the first surface of their path (no glass
 * before), all: every stored photon. For tests of energy conservation. */
vx_result vx_photon_power(vx_photon_gi* pg, double first[3], double all[3], vx_error* err);

/* A stored photon of the last pass, decoded (vx_photon_stored). */
enum { VX_PHOTON_CAUSTIC = 1, VX_PHOTON_DIRECT = 2, VX_PHOTON_FIRST = 4, VX_PHOTON_LIGHT = 8 };
typedef struct vx_photon_record {
    double position[3]; /* world */
    float power[3];
    float direction[3]; /* unit, towards where it came from (octahedral 2 x 16 bits) */
    float normal[3];    /* the surface's, unit (octahedral 2 x 16 bits) */
    uint32_t flags;     /* VX_PHOTON_*: caustic map; brought by a direct-pass light; first surface of its path;
                           a caustic photon from a light that camera rays cannot meet (not sky, not voxels) */
} vx_photon_record;

/* Downloads the last pass's stored photons (in the grid's order, which
 * changes from run to run): *out (free with vx_free(alloc, ...),
 * alloc the scene's allocator) gets *count records. For independent checks
 * of the gather (tests/photons: a brute-force estimate on the CPU). */
vx_result vx_photon_stored(vx_photon_gi* pg, vx_photon_record** out, size_t* count, vx_error* err);

#ifdef __cplusplus
}
#endif
#endif /* VX_PHOTONS_H */
