/* render/instance_ray.h - a ray against one drawn instance, where the CPU
 * caster (render/cpu_trace.c: vx_render_cpu, vx_render_cast) starts its walk:
 * the instance's model-from-world map, the ray in model space, the span of
 * the ray inside the model's box and the cell it starts in.
 *
 * Why a header of its own: probes/'s placement from the compact layout
 * (vx_probe_place_compact) answers the caster's question "does a probe at q
 * start inside a filled cell" without the caster's table of every leaf
 * (about 60 bytes a cell), and must answer it bit for bit as the caster does
 * (the same probes as vx_probe_place: tests/probes/test_probe_place_reader.c).
 * Both call these functions (and so does the compact layout's CPU walk,
 * render/compact_trace.c), so the arithmetic cannot drift apart: the inverse
 * map, the slab test with its guarded reciprocal, and the sign rule that puts
 * a start point on a cell boundary into the cell the ray moves into (without
 * it in the placement alone 85 of test_probe_place_reader's 18,620 probes
 * differed; without it in vx__cell_of, for both, 48 do: the caster steps out
 * of the wrong cell at t = 0 into the right one, the placement does not).
 *
 * Use:
 *   vx__inst_map* maps = <s->instance_count entries>; uint32_t n;
 *   vx__inst_maps(s, maps, &n, err);              // the drawn instances
 *   vx__inst_ray(&maps[i], o, d, om, dm);          // world ray -> model space
 *   vx__box_entry e;
 *   if (vx__box_enter(model->size, om, dm, t0, t1, &e)) ... e.cell ...
 *   (or vx__box_span, then vx__box_cell: the same two steps apart)
 *
 * Double precision, the operations in one order (ISO C17, no contraction:
 * the build sets no -march and no -ffast-math). Names keep the vx__ prefix
 * (render/trace.h): the toolkit's own layer, not a user API. Needs no
 * Vulkan (library vx_trace). */
#ifndef VX_RENDER_INSTANCE_RAY_H
#define VX_RENDER_INSTANCE_RAY_H

#include <math.h>
#include <stdbool.h>
#include <stdint.h>

#include "svo/svo.h"

#ifdef __cplusplus
extern "C" {
#endif

/* One drawn instance as the caster holds it. */
typedef struct vx__inst_map {
    double inv[12]; /* model from world: 3x4 affine rows, the inverse of vx_svo_instance_world */
    double cell;    /* a model cell's largest world extent (column norm of the world map), rounded to float */
    uint32_t model; /* the instance's model */
    uint32_t id;    /* the instance's index in s->instances */
} vx__inst_map;

/* The drawn instances of s (vx_svo_instance_drawn), in scene order, into
 * out[0 .. *n); out has room for s->instance_count entries. The scene is
 * checked first as the tracer checks it (render/trace.h vx__check_scene:
 * every instance's model index, the drawn models' depth and root, invertible
 * maps), so a map is never read uninitialised; on an error *n is 0. */
vx_result vx__inst_maps(const vx_svo_scene* s, vx__inst_map* out, uint32_t* n, vx_error* err);

/* The world ray o + t d in the instance's model space: om = inv o,
 * dm = inv's linear part d (t is the same along both). Inline, as the rest
 * below: the placement asks it of every drawn instance at up to 729 places a
 * probe, the caster of every instance a ray. */
static inline void vx__inst_ray(const vx__inst_map* in, const double o[3], const double d[3], double om[3],
                                double dm[3]) {
    for (int r = 0; r < 3; r++) {
        const double* row = &in->inv[4 * r];
        om[r] = row[0] * o[0] + row[1] * o[1] + row[2] * o[2] + row[3];
        dm[r] = row[0] * d[0] + row[1] * d[1] + row[2] * d[2];
    }
}

/* The cell holding coordinate p of a ray with component d there: floor(p),
 * but a p exactly on a boundary counts to the lower cell where d is negative
 * (the cell the ray moves into). The CPU walk's steps use it too
 * (vx__grid_step_out). */
static inline int64_t vx__cell_of(double p, double d) {
    double f = floor(p);
    if (p == f && signbit(d)) f -= 1;
    return (int64_t)f;
}

/* 1 / d, or +-1e300 (d's sign) where |d| < 1e-300. */
static inline double vx__inv_safe(double d) { return fabs(d) < 1e-300 ? (signbit(d) ? -1e300 : 1e300) : 1.0 / d; }

/* Where a model-space ray o + t d, t in [t0, t1], starts in the box
 * [0, size[0]] x [0, size[1]] x [0, size[2]]: vx__box_enter below. */
typedef struct vx__box_entry {
    double te, tx;   /* the span inside the box: t0 <= te < tx <= t1 */
    int64_t cell[3]; /* the cell at te, inside the box (clamped) */
    bool amb;        /* the start is ambiguous to a float walk: on a cell boundary at t0, or entering through an
                      * edge or corner (two or more entry planes at te) */
} vx__box_entry;

/* The span of the ray in the box, [t0, t1] clipped: *te, *tx; false where it
 * is empty (te >= tx). A component of d below 1e-300 in magnitude has the
 * reciprocal +-1e300 (its sign kept), so the slab test needs no case for rays
 * parallel to a face. */
static inline bool vx__box_span(const uint32_t size[3], const double o[3], const double d[3], double t0, double t1,
                                double* te, double* tx) {
    double e = t0, x = t1;
    for (int k = 0; k < 3; k++) {
        double inv = vx__inv_safe(d[k]);
        double a = (0 - o[k]) * inv, b = ((double)size[k] - o[k]) * inv;
        e = fmax(e, fmin(a, b));
        x = fmin(x, fmax(a, b));
    }
    *te = e, *tx = x;
    return e < x;
}

/* The cell the ray is in at te (vx__box_span's): floor of the point per
 * axis, except that a coordinate exactly on a boundary counts to the lower
 * cell where the ray's component is negative (the cell it moves into); where
 * te > t0 the ray enters through a face and that axis's cell is the face's
 * (0 or size - 1) exactly; clamped to the box. amb (may be NULL: not
 * computed) as vx__box_entry's. */
static inline void vx__box_cell(const uint32_t size[3], const double o[3], const double d[3], double t0, double te,
                                int64_t cell[3], bool* amb) {
    int entry_ties = 0;
    bool on_boundary = false;
    for (int k = 0; k < 3; k++) {
        double pk = o[k] + d[k] * te;
        if (amb && te <= t0 && fabs(pk - nearbyint(pk)) <= 1e-9 * fmax(1, fabs(pk))) on_boundary = true;
        int64_t c = vx__cell_of(pk, d[k]);
        if (te > t0) { /* entering through a face: the entry axis is exact */
            double inv = vx__inv_safe(d[k]);
            double a = (0 - o[k]) * inv, b = ((double)size[k] - o[k]) * inv;
            if (fmin(a, b) == te) c = signbit(d[k]) ? (int64_t)size[k] - 1 : 0, entry_ties++;
        }
        if (c < 0) c = 0;
        if (c >= (int64_t)size[k]) c = (int64_t)size[k] - 1;
        cell[k] = c;
    }
    if (amb) *amb = on_boundary || entry_ties > 1;
}

/* Both: fills *e and returns true when the span is not empty. The CPU
 * caster's and the compact layout's walks start here; the placement asks
 * the span first and the cell only where the span starts at t0. */
static inline bool vx__box_enter(const uint32_t size[3], const double o[3], const double d[3], double t0,
                                 double t1, vx__box_entry* e) {
    if (!vx__box_span(size, o, d, t0, t1, &e->te, &e->tx)) return false;
    vx__box_cell(size, o, d, t0, e->te, e->cell, &e->amb);
    return true;
}

#ifdef __cplusplus
}
#endif

#endif
