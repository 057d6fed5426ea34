/* probes/probes.h - light field probes: a grid of octahedral maps of what
 * each probe sees (radiance, surface normal, radial distance, after McGuire
 * et al. 2017) plus the filtered irradiance and distance moments diffuse GI
 * needs (DDGI, Majercik et al. 2019); baking, the .probes file, and a CPU
 * renderer that uses them.
 *
 * Usage:
 *   vx_probe_set ps; vx_probe_bake(&scene, &(vx_probe_bake_desc){ .res = 32 }, &ps, &err);
 *   vx_probe_write_file(NULL, &ps, "out.probes", &err);  ...  vx_probe_set_free(&ps);
 *   vx_probe_read_file(NULL, "out.probes", &ps, &err);
 *   vx_probe_render(&scene, &ps, &(vx_probe_render_desc){ .mode = VX_PROBE_RENDER_GI }, &img, &err);
 *
 * Octahedral maps: direction d maps to p = d.xy / (|x|+|y|+|z|), folded for
 * z < 0 to ((1-|p.y|) sign p.x, (1-|p.x|) sign p.y); p in [-1,1]^2. A map of
 * n x n texels has texel (i, j) centred exactly at
 * u = (2i + 1)/n - 1, v = (2j + 1)/n - 1 (i along u, row j along v). Maps are
 * stored with a one-texel border, (n+2)^2 texels, interior texel (i, j) at
 * (i+1, j+1); border texels repeat the texel across the fold, so the edge
 * u = 1 at v continues at u = 1 at -v and all four corners are the texel
 * diagonally opposite (see vx_probe_border_src). Bilinear filtering of a
 * bordered map never needs wrap logic.
 *
 * Lighting model (bake and renderer): albedo = the voxel's attribute colour
 * / 255; one directional light (irradiance sun[] on a surface facing it,
 * hard shadows); a uniform sky of radiance sky[] for rays that leave the
 * scene; materials from the scene's MATL records (vx_svo_scene_material):
 * emission albedo * _emit * 2^_flux, and in the path tracer metal (GGX) and
 * glass (dielectric, a glass voxel a solid block) besides diffuse; the
 * irradiance probes and the light field treat every surface as diffuse. An
 * opaque voxel against glass (a glass block standing on a floor, a voxel
 * set in glass) is a surface where a walk through the glass meets it: its
 * emission counts and the path bounces off it back into the glass; no light
 * is sampled there (a shadow ray from inside glass meets the glass), so the
 * light it gets comes through the glass by the path's own walks.
 * The path tracer (pathtrace.c, probe.comp) also takes the frame's lights
 * (vx_light: all types) and samples every light at every vertex with
 * multiple importance sampling, emissive voxels included (renderer), and
 * plays Russian roulette after 3 bounces. Radiance stored for a texel is the
 * light leaving the first surface hit towards the probe with `bounces`
 * further diffuse or glossy bounces (0: direct light and emission only;
 * mirror-like and glass events do not count).
 *
 * Distances are world units. Threads: a bake may use several threads; the
 * result does not depend on how many (every sample has its own random
 * stream keyed by seed, probe, texel and sample).
 */
#ifndef VX_PROBES_H
#define VX_PROBES_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "render/pipeline.h"
#include "render/render.h"
#include "svo/core.h"
#include "svo/svo.h"

#ifdef __cplusplus
extern "C" {
#endif

#define VX_PROBE_FORMAT_VERSION 1u
#define VX_PROBE_IRR_RES 8u    /* irradiance map interior texels per side */
#define VX_PROBE_DIST_RES 16u  /* distance moments map interior texels per side */
#define VX_PROBE_MAX_RES 1024u
#define VX_PROBE_MAX_PROBES (1u << 20)
#define VX_PROBE_DIST_MISS 0xFFFFu /* radial distance code of a ray that hit nothing */
/* the largest side in texels of the sun's depth map that the GPU bake and render build (render.h
 * vx_render_sun_nodes_desc.max_side, for a node list made ahead) */
#define VX_PROBE_SUN_MAP_SIDE 4096u

/* ---- octahedral mapping ------------------------------------------------------------- */

/* d need not be unit length (must be nonzero); uv in [-1,1]^2. */
void vx_probe_oct_encode(const double d[3], double uv[2]);
/* Unit direction of uv in [-1,1]^2. */
void vx_probe_oct_decode(const double uv[2], double d[3]);
/* 2 x snorm16 (u in the low half), rounded to nearest; and back to a unit vector.
 * Worst-case angular error: VX_PROBE_OCT16_MAX_ERROR radians. */
uint32_t vx_probe_oct_pack16(const double d[3]);
void vx_probe_oct_unpack16(uint32_t v, double d[3]);
/* Half a quantum (0.5/32767 per axis) moves the unnormalised octahedron
 * point by at most sqrt(6) times that, and |p| >= 1/sqrt(3): the angle
 * is at most sqrt(18) * 0.5/32767 (plus rounding). */
#define VX_PROBE_OCT16_MAX_ERROR (4.2426406871192851 * 0.5 / 32767.0 * 1.000001)
/* Centre direction of interior texel (i, j) of an n x n map. */
void vx_probe_texel_dir(uint32_t n, uint32_t i, uint32_t j, double d[3]);
/* Exact solid angle of interior texel (i, j) of an n x n map (n even). */
double vx_probe_texel_solid_angle(uint32_t n, uint32_t i, uint32_t j);
/* The interior texel (si, sj) that bordered texel (bi, bj) in [0, n+2)^2
 * repeats (interior texels give themselves). */
void vx_probe_border_src(uint32_t n, uint32_t bi, uint32_t bj, uint32_t* si, uint32_t* sj);

/* IEEE half floats (round to nearest even). */
uint16_t vx_probe_half(float f);
float vx_probe_half_to_float(uint16_t h);

/* ---- probe sets --------------------------------------------------------------------- */

enum {
    VX_PROBE_OK = 0,       /* at its grid point */
    VX_PROBE_MOVED = 1,    /* grid point inside a voxel: moved to the nearest free point within half a cell */
    VX_PROBE_DISABLED = 2  /* no free point within half a cell: no data, ignored by the renderer */
};

typedef struct vx_probe {
    double pos[3]; /* world */
    uint32_t state; /* VX_PROBE_* */
} vx_probe;

/* Everything a .probes file holds. Probe p (grid index x + nx*(y + ny*z))
 * has grid point origin + (x,y,z) * spacing. The per-probe arrays hold probes
 * first .. first+count-1 (a shard holds a part; a full set first = 0,
 * count = probe_count), each probe's maps contiguous:
 *   radiance:   (res+2)^2 * 3 halfs (RGB)
 *   normal:     (res+2)^2 oct 2 x snorm16 (0 where the ray missed, which is
 *               also +z: the distance code tells misses apart)
 *   distance:   (res+2)^2 u16, world distance = code * dist_step
 *               (VX_PROBE_DIST_MISS: nothing within dist_max)
 *   low:        (low_res+2)^2 u16, minimum of the res/low_res square block
 *   irradiance: (8+2)^2 * 3 halfs, E(n) = integral of L max(0, n.w) dw
 *   moments:    (16+2)^2 * 2 floats, mean and mean square of the distance
 *               (misses count as dist_max) with weight max(0, n.w)^50
 * Disabled probes' maps are all zero. */
typedef struct vx_probe_set {
    uint32_t res, low_res;           /* low_res = max(1, res / 16) */
    uint32_t grid[3];
    double origin[3], spacing[3];    /* world units */
    double dist_step;                /* world units per distance code */
    double dist_max;                 /* largest distance stored (VX_PROBE_DIST_MISS - 1) * dist_step */
    double dist_max_error;           /* maximum quantisation error = dist_step / 2 */
    /* bake parameters, recorded for reproducibility and for the renderer */
    uint32_t spp, bounces;
    uint64_t seed;
    double light_dir[3], sun[3], sky[3];
    uint32_t probe_count;
    vx_probe* probes;
    uint32_t first, count;
    uint16_t* radiance;
    uint32_t* normal;
    uint16_t* distance;
    uint16_t* low;
    uint16_t* irradiance;
    float* moments;
    const vx_allocator* alloc; /* the arrays': borrowed, it must outlive the set (vx_probe_set_free frees through it) */
} vx_probe_set;

void vx_probe_set_free(vx_probe_set* ps);

/* ---- baking ------------------------------------------------------------------------- */

/* Where a GPU bake's time went (vx_probe_bake_desc.stats; seconds). GPU
 * times come from timestamps; busy is the share of the batch loop's wall time
 * in which the GPU ran the bake's work (trace, filtering, copies). */
typedef struct vx_probe_bake_stats {
    double place;       /* placing the probes (vx_probe_bake and vx_probe_bake_gpu; wall) */
    double setup;       /* tables, buffers, uploads and pipelines before the first batch (wall) */
    double setup_ctx;   /* of setup: the lighting, the scene's bindings and the small uploads (wall) */
    double setup_pipes; /* of setup: the trace, beam and filter pipelines (wall; the driver's cache) */
    double setup_slots; /* of setup: the buffers of the two batch slots (trace output, filter scratch, maps,
                         * host-visible copies) and their descriptor sets (wall) */
    double sun_map;     /* of setup_ctx: the sun's depth map, its node list and build (wall; 0: none) */
    uint32_t sun_map_side; /* texels a side of the sun's depth map that clipped the sun rays (0: none) */
    uint32_t sun_map_nodes; /* its octree nodes (vx_render_shadow_map_info) */
    double sun_map_list;    /* of sun_map: listing them (wall; with a list made ahead its buffer only) */
    double sun_map_ahead;   /* the list made ahead (render.h vx_render_sun_nodes_make), not in sun_map; 0: none */
    double sun_map_gpu;     /* its build's dispatches (GPU) */
    double sun_map_build;   /* of sun_map: the build (wall: uploads, submission, wait; not the map's memory) */
    double grow;        /* growing the set's arrays for the range before the loop (wall) */
    double loop;        /* the batch loop, first submission to the last probe stored (wall) */
    double first_latency; /* of loop: the first batch's wait less its GPU time (its start's latency; wall) */
    double tail;        /* of loop: after the last batch's wait (its maps stored, the progress callback; wall) */
    double gpu_trace;   /* path tracing, all batches (GPU) */
    double gpu_filter;  /* filtering, quantisation and packing on the GPU (GPU) */
    double gpu_copy;    /* copies of results into host-visible memory (GPU) */
    double wait;        /* the host waiting for the GPU (wall) */
    double download;    /* copying results out of GPU memory (wall; staging copies included) */
    double host_filter; /* filtering or unpacking on the host (wall) */
    double busy;        /* (gpu_trace + gpu_filter + gpu_copy) / loop */
    uint64_t bytes_down; /* bytes read back from the GPU */
    uint32_t batches;
    bool one_walk;      /* the bake ran probe.comp's one-walk kernel (bake_one(); vx_probe_bake_desc.kernel) */
} vx_probe_bake_stats;

/* The GPU bake's kernel (vx_probe_bake_desc.kernel) */
typedef enum vx_probe_bake_kernel {
    VX_PROBE_KERNEL_AUTO = 0, /* the first the driver has ready, bake() where both are */
    VX_PROBE_KERNEL_INLINE,   /* probe.comp bake(): an inlined walk for each kind of ray */
    VX_PROBE_KERNEL_ONE_WALK  /* probe.comp bake_one() where the scene allows it, else bake() */
} vx_probe_bake_kernel;

/* Bake options; zero-initialised means the defaults.
 *  grid:       probes per axis, all zero == from spacing. Over the scene's
 *              bounds the grid is centred on them and its end probes lie a
 *              quarter cell (extent / n) beyond them, so that outer faces
 *              have probes on their side (n probes: extent * (2n + 1) /
 *              (2n (n - 1)) apart; one probe: the centre). With bounds_set:
 *              the cell centres of that grid over the given box
 *  spacing:    world distance between probes, 0 == (bounds diagonal) / 8;
 *              the grid is centred on the bounds and reaches at least a
 *              quarter spacing beyond them, so that outer faces have probes
 *              on their side
 *  bounds_set: use bounds_lo/hi (world) instead of the scene bounds
 *  res:        0 == 128 (even, 16..1024, a multiple of 16 for the low map
 *              to tile exactly)
 *  spp:        paths per radiance texel, 0 == 16
 *  bounces:    0 == 1, negative == 0 (direct light and emission only);
 *              metal and glass events spend none (vx_probe_render_desc)
 *  light_dir:  towards the light, zero == (0.35, -0.45, 0.82) (svo_render's)
 *  sun:        zero == (3, 3, 3); no_sun: no directional light
 *  sky:        zero == (0.62, 0.75, 0.92) * 0.5; black_sky: no sky light
 *  first, count: bake only probes first .. first+count-1 (count 0 == all
 *              from first); the set still describes the whole grid
 *  threads:    0 == 1
 *  progress:   called per finished probe (the GPU bake: after each batch, when
 *              the maps of the call's first `done` probes are in the set)
 *  batch:      GPU bake only: probes per batch, 0 == about 2^28 path
 *              segments (2^26 with host_filter); the bytes do not depend on it
 *  host_filter: GPU bake only: filter each batch's radiance and distances
 *              on `threads` host threads (vx__probe_finish, the CPU bake's
 *              code: the reference) instead of on the GPU
 *  stats:      optional out, where the time went: the GPU bake's; the CPU
 *              bake (vx_probe_bake) fills place only
 *  no_beam:    GPU bake only: the camera rays walk the octree from their probe
 *              rather than from their texel block's beam distance
 *              (probes/shaders/probe_beam.comp): the reference the beam is
 *              tested against (the same bytes); slower
 *  independent_bounce: GPU bake only: every sample's first-bounce direction
 *              from its own random numbers (the CPU bake's estimator) rather
 *              than stratified over the texel's samples (probe.comp STRAT:
 *              each direction still cosine-distributed, so the same mean, with
 *              less noise; a SIMD group's bounce rays leave in nearby
 *              directions, which the GPU traces faster)
 *  no_shadow_map: GPU bake only: the sun's shadow rays walk the whole ray
 *              rather than end where the sun's light-space depth map (render/
 *              shadow_map.c) shows nothing further towards the sun, or skip
 *              the walk where it decides them: the reference (the same bytes);
 *              slower
 *  kernel:     GPU bake only: which of probe.comp's two bake kernels runs;
 *              both give the same bytes. bake() gives each kind of ray (the
 *              texel's centre ray, the camera and bounce rays, the sun's) an
 *              inlined octree walk of its own: the faster one (H200, Cornell
 *              box: GPU trace 0.254 s against 0.359 s), which the driver
 *              compiles in 0.66-0.89 s where its shader cache is empty.
 *              bake_one() walks every ray at one place (only where the scene
 *              has no lights or sampled emitters and no metal or glass:
 *              probe.comp's LIGHTS and MATS off; else bake() runs): compiled
 *              in 0.3 s. VX_PROBE_KERNEL_AUTO (0) makes both at once and runs
 *              bake() where the driver has it ready (its cache) when
 *              bake_one() is, else bake_one(), bake() still being compiled
 *              (into the driver's cache: the next process's) */
typedef struct vx_probe_bake_desc {
    uint32_t grid[3];
    double spacing;
    bool bounds_set;
    double bounds_lo[3], bounds_hi[3];
    uint32_t res;
    uint32_t spp;
    int32_t bounces;
    uint64_t seed;
    double light_dir[3];
    double sun[3];
    bool no_sun;
    double sky[3];
    bool black_sky;
    uint32_t first, count;
    uint32_t threads;
    const vx_allocator* alloc;
    vx_progress progress;
    uint32_t batch;
    bool host_filter;
    vx_probe_bake_stats* stats;
    bool no_beam;
    bool independent_bounce;
    bool no_shadow_map;
    vx_probe_bake_kernel kernel;
} vx_probe_bake_desc;

/* What a zero field of a bake desc means (the one source of these defaults;
 * svo_bake's --help prints them): res 128, spp 16, 1 bounce, seed 0, light
 * (0.35, -0.45, 0.82), sun irradiance 3,3,3, sky radiance 0.31,0.375,0.46;
 * the grid from a spacing of the bounds' diagonal / 8. */
vx_probe_bake_desc vx_probe_bake_desc_defaults(void);

/* Places the grid and probes (moving or disabling the ones inside voxels)
 * without baking: *out has count = 0 and no maps. */
vx_result vx_probe_place(const vx_svo_scene* scene, const vx_probe_bake_desc* desc, vx_probe_set* out, vx_error* err);
/* vx_probe_place of the scene a model reader (svo/svo.h) gives, without
 * holding it: the same probes, bit for bit. The grid comes from the graph
 * (view: a frame of it, vx_svo_scene_frame of a copy of the graph; NULL: the
 * graph itself), whose instances and declared model sizes give the bounds;
 * the places a probe may move to that lie in a drawn instance's box are
 * decided in one pass over the models (each model's instances cast on the
 * CPU caster as a scene of their own), the others are free. rd must hand
 * over the models from the first (a fresh reader, or one rewound,
 * vx_svo_reader_rewind) and is finished by the call (its NODE checksum);
 * on failure the reader's error names the file and the model. The host
 * holds one model and its caster at a time, and a bit per probe place in
 * an instance's box. */
vx_result vx_probe_place_reader(vx_svo_model_reader* rd, const vx_svo_scene* view, const vx_probe_bake_desc* desc,
                                vx_probe_set* out, vx_error* err);
/* vx_probe_place of scene from its compact layout c (render/compact.h,
 * vx_compact_build or vx_compact_build_reader of that scene: the same models
 * in the same order), without the models' trees: the same probes, bit for
 * bit. scene may be a reader's graph (its declared fields, instances and
 * bounds; a frame's view of it); the test whether a probe place starts in a
 * cell is the CPU caster's (a cast that hits at t = 0) by its own arithmetic,
 * the cell looked up in c's geometry (vx_compact_lookup) instead of the
 * caster's table of every leaf (about 60 bytes a cell). So a caller that
 * built the layout from a model reader places the probes with no second pass
 * over the file and no caster (svo_bake --load models); the host holds c and
 * a model-from-world map per drawn instance. */
struct vx_compact_scene;
vx_result vx_probe_place_compact(const struct vx_compact_scene* c, const vx_svo_scene* scene,
                                 const vx_probe_bake_desc* desc, vx_probe_set* out, vx_error* err);
/* Places and bakes; *out owns everything (free with vx_probe_set_free). */
vx_result vx_probe_bake(const vx_svo_scene* scene, const vx_probe_bake_desc* desc, vx_probe_set* out, vx_error* err);
/* Bakes probes [ps->first + ps->count, end) into a set from vx_probe_place or
 * an earlier partial bake with the same desc (resuming), growing the arrays;
 * end <= first + count of the desc. */
vx_result vx_probe_bake_more(const vx_svo_scene* scene, const vx_probe_bake_desc* desc, vx_probe_set* ps,
                             uint32_t end, vx_error* err);

/* The same bake with the path tracing on the GPU (render/shaders/probe.comp,
 * float traversal) and the filtering too (desc->host_filter: on
 * desc->threads host threads; both give the same maps up to float rounding
 * of the sums: tests/probes/test_probes_gpu.c). rs must
 * be vx_render_scene_create(gpu, scene). Same seed, same bytes on one device
 * and driver; results do not depend on the batch size or sharding. The GPU
 * draws its own random numbers (pcg4d streams keyed by seed, probe, texel and
 * sample), so GPU and CPU bakes agree statistically, not bit for bit.
 * VX_ERR_UNSUPPORTED for scenes that need the float64 tracer. */
vx_result vx_probe_bake_gpu(vx_render_scene* rs, const vx_svo_scene* scene, const vx_probe_bake_desc* desc,
                            vx_probe_set* out, vx_error* err);
vx_result vx_probe_bake_more_gpu(vx_render_scene* rs, const vx_svo_scene* scene, const vx_probe_bake_desc* desc,
                                 vx_probe_set* ps, uint32_t end, vx_error* err);

/* A GPU bake kept across calls (the GPU filtering; not host_filter): the
 * context, the filter tables, the pipelines and the batch buffers are made
 * once, so a caller that bakes a grid in many ranges (svo_bake's MPI batches,
 * checkpoint steps) pays that set-up (about 45 ms on an H200 at R=128) once.
 * vx_probe_baker_create takes the bake's settings from desc and ps (a set
 * from vx_probe_place: its grid, light and the batch size for its whole
 * range); vx_probe_baker_run bakes [ps->first + ps->count, end) of ps as
 * vx_probe_bake_more_gpu does, for any ps of the same placement (the same
 * probes array, e.g. views of one placed set over other ranges), using only
 * desc's progress and stats (the first run's stats carry the create's time as
 * setup). The bytes are vx_probe_bake_more_gpu's. One thread at a time. */
typedef struct vx_probe_baker vx_probe_baker;
vx_result vx_probe_baker_create(vx_render_scene* rs, const vx_svo_scene* scene, const vx_probe_bake_desc* desc,
                                const vx_probe_set* ps, vx_probe_baker** out, vx_error* err);
vx_result vx_probe_baker_run(vx_probe_baker* b, const vx_probe_bake_desc* desc, vx_probe_set* ps, uint32_t end,
                             vx_error* err);
void vx_probe_baker_destroy(vx_probe_baker* b);

/* Joins parts with identical grids and parameters whose ranges tile
 * [0, probe_count) (in any order) into one full set. */
vx_result vx_probe_merge(const vx_probe_set* const* parts, uint32_t n, const vx_allocator* alloc, vx_probe_set* out,
                         vx_error* err);

/* ---- files -------------------------------------------------------------------------- */

typedef struct vx_probe_read_desc {
    const vx_allocator* alloc;
    uint32_t max_res;     /* 0 == VX_PROBE_MAX_RES */
    uint32_t max_probes;  /* 0 == VX_PROBE_MAX_PROBES */
} vx_probe_read_desc;

/* Serialises (docs/FORMAT.md, "## .probes"); *out freed with vx_free(alloc, ...). */
vx_result vx_probe_write(const vx_probe_set* ps, const vx_allocator* alloc, uint8_t** out, size_t* out_size,
                         vx_error* err);
/* The same through a temporary file renamed over path; desc may be NULL
 * (svo/core.h). */
vx_result vx_probe_write_file(const vx_write_desc* desc, const vx_probe_set* ps, const char* path, vx_error* err);
/* Bounded reader: every length and CRC checked; errors name the byte offset. */
/* A .probes file written while a bake fills the set (svo_bake: the file
 * goes to disk batch by batch while the GPU traces the next, instead of all
 * at the end): the same bytes as vx_probe_write_file of the set once probes
 * ps->first .. end - 1 are baked. vx_probe_stream_open writes the header and
 * GRID of the placed set ps (its first; its maps are not read) for the range
 * [ps->first, end) into a temporary file beside path; vx_probe_stream_put
 * appends the maps of the probes up to `upto` (exclusive; they must be in
 * the set passed, which holds the range from the same first) and starts their
 * disk writes; vx_probe_stream_commit patches DATA's CRC, syncs and renames
 * the file over path once every probe is in (or removes it and fails);
 * vx_probe_stream_abort removes it. Either of the last two ends the stream. */
typedef struct vx_probe_stream {
    vx_atomic_file file;
    const vx_allocator* alloc;
    uint32_t first, end, next; /* the range; the next probe to append */
    uint32_t crc;              /* DATA's CRC so far */
    uint64_t crc_at;           /* where it goes in the file */
    bool open;
} vx_probe_stream;
vx_result vx_probe_stream_open(vx_probe_stream* st, const vx_probe_set* ps, uint32_t end, const char* path,
                               const vx_allocator* alloc, vx_error* err);
vx_result vx_probe_stream_put(vx_probe_stream* st, const vx_probe_set* ps, uint32_t upto, vx_error* err);
vx_result vx_probe_stream_commit(vx_probe_stream* st, vx_error* err);
void vx_probe_stream_abort(vx_probe_stream* st);

vx_result vx_probe_read(const vx_probe_read_desc* desc, const void* data, size_t size, vx_probe_set* out,
                        vx_error* err);
vx_result vx_probe_read_file(const vx_probe_read_desc* desc, const char* path, vx_probe_set* out, vx_error* err);

/* ---- using the probes --------------------------------------------------------------- */

/* Irradiance at world point p with normal n (unit) from the 8 surrounding
 * probes: trilinear weights, Chebyshev visibility from the distance moments
 * and the normal weight (DDGI). The set must be complete. */
void vx_probe_irradiance(const vx_probe_set* ps, const double p[3], const double n[3], double out[3]);

typedef enum vx_probe_render_mode {
    VX_PROBE_RENDER_GI = 0,     /* direct + albedo/pi * probe irradiance */
    VX_PROBE_RENDER_PATHTRACE,  /* path-traced reference, same lights and materials */
    VX_PROBE_RENDER_INDIRECT,   /* albedo/pi * probe irradiance only (for error measurements) */
    VX_PROBE_RENDER_PT_INDIRECT, /* path-traced indirect diffuse only */
    VX_PROBE_RENDER_LIGHTFIELD,  /* direct + albedo * one bounce traced through the probes' distance maps */
    VX_PROBE_RENDER_LF_INDIRECT  /* that bounce only (for error measurements) */
} vx_probe_render_mode;
/* Glass at the camera's first surface (a record of type glass that transmits,
 * its lobe drawn by its transmission): in every mode the path tracer's events
 * through it (Fresnel, the walk, the tint) to the first surface that is not
 * glass, which gets the mode's whole shading (emission, direct light, the
 * probes' or the light field's light), or the sky where the path leaves; the
 * indirect modes give that lobe whole too, which the pass pipeline's gi pass
 * needs (render/pipeline.h). Metal and the Lambert share of glass are
 * shaded as diffuse by the probe and light field modes. */
#define VX_PROBE_RENDER_MODE_COUNT 6

/* What the light field modes did (filled when vx_probe_render_desc.stats is set). */
typedef struct vx_probe_render_stats {
    uint64_t rays;         /* indirect rays traced through the light field */
    uint64_t probe_traces; /* probe maps walked (a ray tries the next probe where one cannot answer) */
    uint64_t texels;       /* full-resolution texels tested */
    uint64_t coarse_skips; /* low-resolution texels skipped whole */
    uint64_t hits, misses; /* rays answered by a probe: a surface, or the sky */
    uint64_t fallbacks;    /* rays no probe could answer, traced in the octree */
    /* the GPU path tracer (pathtrace modes): texels a side of the sun's depth map that ended its sun rays
     * (render/gpu.h vx__render_scene_sun_map; 0: none; base->no_shadow_map: none; the same image) */
    uint32_t sun_map_side;
} vx_probe_render_stats;

/* Renderer options (CPU, double precision). The camera comes from base:
 * width, height, camera; base.spp and base.mode are ignored.
 *  spp:     paths per pixel for the path tracer, 0 == 16 (gi: 1)
 *  bounces: indirect bounces of the path tracer, 0 == probes' bounces + 1
 *           (or 2 without probes); a path's first 4 metal events (a metal
 *           material's specular lobe) and its glass events spend none, as
 *           in the probe modes and the bake; light, sun and sky: from the
 *           probes, or the bake defaults without probes
 *  seed:    path tracer (and light field ray) random seed
 *  lights:  light_count lights (borrowed, validated) for the path tracer
 *           modes; any replace the sun (as in the pass pipeline). In
 *           pathtrace-indirect the first surface's emission and its light
 *           from the sun and the lights are left out (the pass pipeline's
 *           direct pass delivers them)
 * Light field modes: spp indirect rays per pixel (0 == 16), each walked
 * through the distance maps of the 8 probes around its origin, nearest
 * first (each continuing where the last could not answer), radiance from the
 * texel hit; rays no probe answers are traced in the octree and shaded with
 * direct light plus the probes' irradiance. */
typedef struct vx_probe_render_desc {
    const vx_render_desc* base; /* NULL: defaults */
    vx_probe_render_mode mode;
    uint32_t spp;
    uint32_t bounces;
    uint64_t seed;
    uint32_t threads; /* 0 == 1 */
    vx_probe_render_stats* stats; /* optional out: light field counts */
    /* NULL: every row. Else `height` flags: only rows y with rows[y] != 0 are
     * rendered, the others stay 0 (the GPU dispatches only the rows listed).
     * A pixel's value depends only on the seed, the pixel and the sample,
     * never on which other pixels are rendered, so rows rendered apart
     * (mpirun svo_render) and put together equal one render bit for bit. */
    const uint8_t* rows;
    const vx_light* lights; /* the path tracer's lights (borrowed); any replace the sun */
    uint32_t light_count;
    bool pixel_centre; /* every sample through the pixel centre (no jitter): the gi pass's G-buffer rays */
    /* The path tracer's sky (borrowed; the path tracer modes only): NULL or
     * VX_SKY_DEFAULT: the uniform sky of the probes (or the bake default);
     * else this sky by direction (vx_sky_radiance), an environment map with
     * its texels in sky_map, which the caller reads (formats/image.h:
     * vx_sky_path, vx_image_read). Reached by BSDF rays (no sky sampling). */
    const vx_sky* sky;
    const vx_sky_texels* sky_map;
} vx_probe_render_desc;

/* Renders RGBA float radiance (alpha 1 on hits); probes may be NULL for
 * the path tracer modes. Free out with vx_render_image_free. */
vx_result vx_probe_render(const vx_svo_scene* scene, const vx_probe_set* probes, const vx_probe_render_desc* desc,
                          vx_render_image* out, vx_error* err);
/* The same on the GPU (float; threads ignored): image gpu_seconds from GPU
 * timestamps. Scenes without probes use the pathtrace modes only; the plain
 * trace pipeline (vx_render_frame) is untouched by the probe variants. */
vx_result vx_probe_render_gpu(vx_render_scene* rs, const vx_svo_scene* scene, const vx_probe_set* probes,
                              const vx_probe_render_desc* desc, vx_render_image* out, vx_error* err);
/* The probe maps kept on the GPU between frames (a viewer renders many
 * frames of one set: the light field maps alone can be hundreds of MB).
 * rs, scene and ps must outlive it; ps may be NULL or a part of a set (then
 * only the path tracer modes render, ps giving their light). Maps are
 * uploaded at the first frame that needs them (the light field maps only for
 * a light field frame). */
typedef struct vx_probe_gpu vx_probe_gpu;
vx_result vx_probe_gpu_create(vx_render_scene* rs, const vx_svo_scene* scene, const vx_probe_set* ps,
                              vx_probe_gpu** out, vx_error* err);
void vx_probe_gpu_destroy(vx_probe_gpu* pg);
/* vx_probe_render_gpu with the maps of pg. */
vx_result vx_probe_gpu_render(vx_probe_gpu* pg, const vx_probe_render_desc* desc, vx_render_image* out, vx_error* err);
/* The same image left on the GPU: written into `buffer` (a vx__buffer of
 * render/gpu.h holding at least width*height vec4) instead of read back;
 * *gpu_seconds: the render's and the copy's GPU time. */
vx_result vx_probe_gpu_render_into(vx_probe_gpu* pg, const vx_probe_render_desc* desc, void* buffer,
                                   double* gpu_seconds, vx_error* err);
/* The probe GI methods as the pass pipeline's gi pass (render/pipeline.h):
 * method "probes" (irradiance probes), "lightfield" (one bounce through the
 * distance maps) or "pathtrace" (path-traced indirect light; ps may be NULL,
 * or give the light). desc gives spp, bounces and seed (mode and base are
 * set per frame) and, for pathtrace, the frame's lights (desc->lights: the
 * method's lights, which the frame must then pass too). Fills *method
 * (valid while *out lives) with the render callback and the light the
 * pipeline's direct pass must use (the probes' sun, sky and direction,
 * emission per attribute record). The pipeline's direct pass shades a
 * metal first surface with its BRDF (render/pipeline.h) and glass as
 * diffuse: with glass there, gi=pathtrace adds only the light after the
 * first bounce. rs, scene and ps
 * must outlive *out. */
typedef struct vx_probe_gi vx_probe_gi;
vx_result vx_probe_gi_create(vx_render_scene* rs, const vx_svo_scene* scene, const vx_probe_set* ps, const char* method,
                             const vx_probe_render_desc* desc, vx_gi_method* method_out, vx_probe_gi** out,
                             vx_error* err);
void vx_probe_gi_destroy(vx_probe_gi* gi);
const char* vx_probe_render_mode_name(vx_probe_render_mode m);
/* Whether mode m reads the probes (gi and lightfield modes; not the path tracer). */
bool vx_probe_render_mode_uses_probes(vx_probe_render_mode m);
bool vx_probe_render_mode_parse(const char* s, vx_probe_render_mode* out);

#ifdef __cplusplus
}
#endif
#endif /* VX_PROBES_H */
