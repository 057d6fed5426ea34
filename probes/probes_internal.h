/* probes/probes_internal.h - shared between the probes/ sources (not public):
 * the probe grid, the bake's tables and the light field tracing. The lighting
 * model they share with other modules is probes/light.h. */
#ifndef VX_PROBES_INTERNAL_H
#define VX_PROBES_INTERNAL_H

#include <math.h>

#include "probes/light.h"
#include "probes/probes.h"
#include "render/trace.h"

/* The grid cell of the 8 probes around world point p (clamped to the grid):
 * probe (base + (c & 1, c >> 1 & 1, c >> 2 & 1)) for c in 0..7, skipping
 * indices past the grid's end; alpha: trilinear weights along each axis. */
static inline void vx__probe_cage(const vx_probe_set* ps, const double p[3], int64_t base[3], double alpha[3]) {
    for (int k = 0; k < 3; k++) {
        double g = (p[k] - ps->origin[k]) / ps->spacing[k];
        double top = (double)ps->grid[k] - 1;
        g = g < 0 ? 0 : (g > top ? top : g);
        double f = fmin(floor(g), fmax(top - 1, 0));
        base[k] = (int64_t)f;
        alpha[k] = top > 0 ? g - f : 0;
    }
}

/* Probe map sizes in texels (with borders) and the per-probe block size. */
static inline size_t vx__bsq(uint32_t n) { return (size_t)(n + 2) * (n + 2); }

/* ---- bake pieces shared by the CPU and the GPU baker (bake.c) -------------------- */

typedef struct vx__tables {
    uint32_t res;
    double* dir;   /* res^2 texel centre directions */
    double* omega; /* res^2 solid angles */
    double irr_dir[VX_PROBE_IRR_RES * VX_PROBE_IRR_RES][3];
    double mom_dir[VX_PROBE_DIST_RES * VX_PROBE_DIST_RES][3];
    const vx_allocator* alloc;
} vx__tables;

bool vx__tables_make(vx__tables* T, uint32_t res, const vx_allocator* alloc); /* false: out of memory (free anyway) */
void vx__tables_free(vx__tables* T);
/* Grows the data arrays to hold n probes from ps->first, the new ones zeroed, or left as they come where
 * the caller writes every byte of them before ps->count covers them (zero false: the GPU bake's maps; zeroing
 * its 105 MB for 512 probes at R=128 touched every page, 0.06 s of the goal bake on an H200). */
bool vx__probe_grow(vx_probe_set* ps, uint32_t n, bool zero);
/* Completes slot k of ps whose interior distance and normal codes are set:
 * L is the interior radiance (res^2 RGB, row-major), D the decoded distances
 * (dist_max for misses). Writes the radiance halfs, the borders, the
 * low-resolution minimum map, the irradiance and the distance moments. */
void vx__probe_finish(vx_probe_set* ps, const vx__tables* T, uint32_t k, const double* L, const double* D);
/* ---- the bake's driver (bake.c), one for the CPU and the GPU bakes ------------------ */

/* The first probe a bake of ps up to end starts at (*begin: after the probes
 * baked so far); VX_ERR_INVALID_ARG naming the range where end lies outside. */
vx_result vx__probe_bake_begin(const vx_probe_set* ps, uint32_t end, uint32_t* begin, vx_error* err);
/* The light a placed set records (its resolved light_dir, sun and sky: a sun
 * or sky of zero stays zero), for a bake that continues the set; c may be
 * NULL (the GPU bakes). L can be freed (vx__light_free) on failure too. */
vx_result vx__probe_set_light(vx__light* L, const vx_render_caster* c, const vx_svo_scene* s, const vx_probe_set* ps,
                              vx_error* err);
/* A device's part of a bake: bakes [ps->first + ps->count, end) of a placed
 * set (vx_probe_bake_more on the CPU, vx_probe_bake_more_gpu with device the
 * vx_render_scene). */
typedef vx_result (*vx__probe_bake_range)(void* device, const vx_svo_scene* scene, const vx_probe_bake_desc* desc,
                                          vx_probe_set* ps, uint32_t end, vx_error* err);
/* vx_probe_bake and vx_probe_bake_gpu: places the probes (vx_probe_place),
 * bakes the desc's range with bake, records the placement's wall time in
 * desc->stats->place; *out the set, untouched on failure. Why one driver:
 * the two bakes differ only in the range's device part, and written twice
 * they had drifted (only the GPU's reported the placement). */
vx_result vx__probe_bake_placed(const vx_svo_scene* scene, const vx_probe_bake_desc* desc, vx__probe_bake_range bake,
                                void* device, vx_probe_set* out, vx_error* err);
/* Distance code of a hit at world distance t. */
static inline uint16_t vx__dist_code(const vx_probe_set* ps, double t) {
    double q = nearbyint(t / ps->dist_step);
    return (uint16_t)(q > VX_PROBE_DIST_MISS - 1 ? VX_PROBE_DIST_MISS - 1 : q);
}

/* ---- light field tracing (lightfield.c) ------------------------------------------ */

typedef enum { VX__LF_HIT, VX__LF_MISS, VX__LF_UNKNOWN } vx__lf_status;

typedef struct vx__lf_counts {
    uint64_t rays, probe_traces, texels, coarse_skips, hits, misses, fallbacks;
} vx__lf_counts;

/* Walks o + t d, t in [*t_io, t_end], through probe pi's distance map (the
 * probe must be in ps's range). HIT: *t_io the hit, *texel its bordered
 * texel index; MISS: free up to t_end; UNKNOWN: free (as far as this probe
 * can tell) up to *t_io, where the ray went behind a surface it sees. */
vx__lf_status vx__lf_trace_probe(const vx_probe_set* ps, uint32_t pi, const double o[3], const double d[3],
                                 double* t_io, double t_end, uint32_t* texel, vx__lf_counts* cnt);

typedef struct vx__lf {
    const vx__light* L;
    const vx_probe_set* ps; /* complete */
    double lo[3], hi[3];    /* world bounds of the scene: a ray that leaves them sees the sky */
} vx__lf;

/* Radiance arriving at o from unit direction d through the light field: the
 * 8 probes around o, nearest first, each continuing where the last could not
 * answer; then the octree tracer, the hit shaded with direct light and the
 * probes' irradiance. */
void vx__lf_radiance(const vx__lf* lf, const double o[3], const double d[3], double out[3], vx__lf_counts* cnt);

#endif
