/* probes/bake.c - probe placement and the CPU reference bake (double
 * precision path tracing on the CPU tracer's rays), filtering into the
 * irradiance and distance-moment maps, merging shards. */
#include <math.h>
#include <pthread.h>
#include <string.h>

#include "probes/probes_internal.h"
#include "render/compact.h"
#include "render/instance_ray.h"
#include "render/trace.h"

void vx_probe_set_free(vx_probe_set* ps) {
    if (!ps) return;
    const vx_allocator* a = ps->alloc;
    vx_free(a, ps->probes);
    vx_free(a, ps->radiance);
    vx_free(a, ps->normal);
    vx_free(a, ps->distance);
    vx_free(a, ps->low);
    vx_free(a, ps->irradiance);
    vx_free(a, ps->moments);
    memset(ps, 0, sizeof *ps);
}

/* ---- placement ---------------------------------------------------------------------- */

/* Whether a probe at p starts inside a cell: the caster's ray from p along the diagonal hits at t = 0
 * (compact_solid asks the same of the compact layout with this ray). */
static const double solid_dir[3] = {0.5773502691896258, 0.5773502691896258, 0.5773502691896258};
static const double solid_tmax = 1e-9;
static bool inside_solid(const vx_render_caster* c, const double p[3]) {
    vx_render_ray_hit h;
    return vx_render_cast(c, p, solid_dir, solid_tmax, false, &h) && h.t == 0;
}

typedef struct offs {
    double d2;
    int a, b, c;
} offs;

static int offs_cmp(const void* x, const void* y) {
    const offs *p = x, *q = y;
    if (p->d2 != q->d2) return p->d2 < q->d2 ? -1 : 1;
    if (p->a != q->a) return p->a - q->a;
    if (p->b != q->b) return p->b - q->b;
    return p->c - q->c;
}

#include <stdlib.h>

/* The grid of the placement: bounds, spacing, origin, the probes (at their
 * grid points, disabled) and the distance range; no model's cells are read
 * (the bounds are the drawn instances' model boxes). */
static vx_result place_grid(const vx_svo_scene* s, const vx_probe_bake_desc* d, vx_probe_set* ps, vx_error* err) {
    double lo[3], hi[3];
    if (d->bounds_set) {
        memcpy(lo, d->bounds_lo, sizeof lo);
        memcpy(hi, d->bounds_hi, sizeof hi);
    } else {
        vx_svo_scene_world_bounds(s, lo, hi);
    }
    double diag = 0;
    for (int k = 0; k < 3; k++) {
        if (!isfinite(lo[k]) || !isfinite(hi[k]) || !(hi[k] >= lo[k]))
            return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "bounds are empty or not finite");
        diag += (hi[k] - lo[k]) * (hi[k] - lo[k]);
    }
    diag = sqrt(diag);
    if (!(diag > 0)) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "scene bounds are empty: give bounds");
    bool grid_set = d->grid[0] || d->grid[1] || d->grid[2];
    if (grid_set && d->spacing) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "give a grid or a spacing, not both");
    double sp = d->spacing ? d->spacing : diag / 8;
    if (!(sp > 0) || !isfinite(sp)) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "spacing must be positive");
    uint64_t total = 1;
    for (int k = 0; k < 3; k++) {
        double ext = hi[k] - lo[k];
        if (grid_set) {
            if (!d->grid[k] || d->grid[k] > 4096)
                return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "grid axis %d: %u probes (1..4096)", k, d->grid[k]);
            ps->grid[k] = d->grid[k];
            /* Over the scene's bounds, the end probes lie a quarter cell
             * (extent / n) beyond them: at the cell centres (extent / n
             * apart, as before) every probe lay inside the scene's box, half a
             * cell in from its faces, so every surface facing out of the box
             * (the outer faces of a Menger sponge, of a closed Cornell box)
             * had no probe on its side: the Chebyshev test rejected the 8
             * behind it alike and the interpolation gave it their light, the
             * inside's (eph procedure_menger, --grid 4,4,3: indirect light
             * 0.43 of the path tracer's, 0.35 with 8,8,8, whose outer layer
             * is nearer the faces but still behind them; docs/TESTING.md,
             * "(C)"). A quarter cell rather than a spacing's quarter spacing
             * (extent / (n - 1.5) apart): with 2 probes an axis that would
             * put them half the extent out. Given bounds (bounds_set) are the
             * probe grid's box: its cell centres, as the caller placed them;
             * one probe: the centre. */
            uint32_t n = d->grid[k];
            if (!(ext > 0)) ps->spacing[k] = sp;
            else if (d->bounds_set || n == 1) ps->spacing[k] = ext / n;
            else ps->spacing[k] = ext * (2.0 * n + 1) / (2.0 * n * (n - 1));
        } else {
            /* The grid spans the bounds plus at least a quarter spacing on each
             * side, so the outermost probes lie outside the scene: with probes
             * only inside a closed shell (a converted mesh's one-voxel walls),
             * every outer face would interpolate the light of the inside, the
             * Chebyshev test rejecting all 8 probes alike (converted Cornell
             * box, spacing 0.45: relMSE 0.54 -> 0.009). */
            double n = ceil(ext / sp + 0.5) + 1;
            if (n > 4096) return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "spacing %g gives more than 4096 probes per axis", sp);
            ps->grid[k] = (uint32_t)n;
            ps->spacing[k] = sp;
        }
        /* centred on the bounds (an explicit grid: its cell centres) */
        ps->origin[k] = 0.5 * (lo[k] + hi[k]) - 0.5 * (ps->grid[k] - 1) * ps->spacing[k];
        total *= ps->grid[k];
    }
    if (total > VX_PROBE_MAX_PROBES)
        return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "%llu probes (at most %u)", (unsigned long long)total,
                       VX_PROBE_MAX_PROBES);
    ps->probe_count = (uint32_t)total;
    ps->probes = vx_calloc(ps->alloc, total, sizeof *ps->probes);
    if (!ps->probes) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory");
    /* The distances a probe can see stay within the bounds grown by the grid. */
    double ext2 = 0;
    for (int k = 0; k < 3; k++) {
        double a = fmin(lo[k], ps->origin[k] - ps->spacing[k]), b = fmax(hi[k], ps->origin[k] + ps->grid[k] * ps->spacing[k]);
        ext2 += (b - a) * (b - a);
    }
    ps->dist_step = sqrt(ext2) / (VX_PROBE_DIST_MISS - 1);
    ps->dist_max = ps->dist_step * (VX_PROBE_DIST_MISS - 1);
    ps->dist_max_error = ps->dist_step * 0.5;
    for (uint32_t z = 0; z < ps->grid[2]; z++)
        for (uint32_t y = 0; y < ps->grid[1]; y++)
            for (uint32_t x = 0; x < ps->grid[0]; x++) {
                vx_probe* p = &ps->probes[x + (size_t)ps->grid[0] * (y + (size_t)ps->grid[1] * z)];
                double g[3] = {ps->origin[0] + x * ps->spacing[0], ps->origin[1] + y * ps->spacing[1],
                               ps->origin[2] + z * ps->spacing[2]};
                p->state = VX_PROBE_DISABLED;
                memcpy(p->pos, g, sizeof g);
            }
    return VX_OK;
}

/* The places a probe may move to, nearest first: offsets of at most half a
 * cell per axis (H steps of spacing / 2H); returns their count. */
enum { PLACE_H = 4, PLACE_SIDE = 2 * PLACE_H + 1, PLACE_CANDS = PLACE_SIDE * PLACE_SIDE * PLACE_SIDE };
static int place_candidates(const vx_probe_set* ps, offs cand[PLACE_CANDS]) {
    int nc = 0;
    for (int a = -PLACE_H; a <= PLACE_H; a++)
        for (int b = -PLACE_H; b <= PLACE_H; b++)
            for (int cc = -PLACE_H; cc <= PLACE_H; cc++) {
                double x = a * ps->spacing[0], y = b * ps->spacing[1], z = cc * ps->spacing[2];
                cand[nc++] = (offs){x * x + y * y + z * z, a, b, cc};
            }
    qsort(cand, (size_t)nc, sizeof cand[0], offs_cmp);
    return nc;
}

/* Candidate i of the probe at grid point g. */
static void place_point(const vx_probe_set* ps, const double g[3], const offs* c, double q[3]) {
    q[0] = g[0] + c->a * ps->spacing[0] / (2 * PLACE_H);
    q[1] = g[1] + c->b * ps->spacing[1] / (2 * PLACE_H);
    q[2] = g[2] + c->c * ps->spacing[2] / (2 * PLACE_H);
}

/* Whether a probe at q would start inside a cell (the placement's test): the caster's inside_solid, or
 * compact_solid's answer from the compact layout. */
typedef bool (*solid_fn)(const void* user, const double q[3]);
static bool caster_solid(const void* user, const double q[3]) { return inside_solid(user, q); }

static vx_result place(const vx_svo_scene* s, const vx_probe_bake_desc* d, solid_fn solid, const void* user,
                       vx_probe_set* ps, vx_error* err) {
    vx_result r = place_grid(s, d, ps, err);
    if (r) return r;
    offs cand[PLACE_CANDS];
    int nc = place_candidates(ps, cand);
    for (uint32_t i = 0; i < ps->probe_count; i++) {
        vx_probe* p = &ps->probes[i];
        double g[3] = {p->pos[0], p->pos[1], p->pos[2]};
        for (int k = 0; k < nc; k++) {
            double q[3];
            place_point(ps, g, &cand[k], q);
            if (!solid(user, q)) {
                memcpy(p->pos, q, sizeof q);
                p->state = k == 0 ? VX_PROBE_OK : VX_PROBE_MOVED;
                break;
            }
        }
    }
    return VX_OK;
}

/* The light as the placement records it (the caster may be NULL: no cell is
 * read for it), into ps. */
static vx_result record_light(vx_probe_set* ps, const vx_render_caster* c, const vx_svo_scene* s, const vx_probe_bake_desc* d,
                              vx_error* err) {
    vx__light L;
    vx_result r = vx__light_init(&L, c, s, d->light_dir, d->sun, d->no_sun, d->sky, d->black_sky, err);
    vx__light_free(&L); /* only the resolved light is recorded here */
    if (r) return r;
    memcpy(ps->light_dir, L.light_dir, sizeof ps->light_dir);
    memcpy(ps->sun, L.sun, sizeof ps->sun);
    memcpy(ps->sky, L.sky, sizeof ps->sky);
    return VX_OK;
}

/* The placement's end: the desc's probe range checked against the set, the
 * set handed to *out (or freed with the error). */
static vx_result place_done(const vx_probe_bake_desc* d, vx_probe_set* ps, vx_probe_set* out, vx_error* err) {
    uint32_t first = d->first, end = d->count ? d->first + d->count : ps->probe_count;
    if (first > ps->probe_count || end > ps->probe_count || end < first) {
        uint32_t n = ps->probe_count;
        vx_probe_set_free(ps);
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "probe range %u..%u outside the %u probes", first, end, n);
    }
    ps->first = first;
    ps->count = 0;
    *out = *ps;
    return VX_OK;
}

/* ---- placement from a model reader --------------------------------------------------- */

static vx_result resolve(const vx_probe_bake_desc* d, vx_probe_set* ps, vx_error* err);

/* Whether q lies in the world box of a drawn instance of sub's model (the
 * box grown by a margin: a point on a face is the caster's to decide). */
static bool in_boxes(const double* boxes, uint32_t n, const double q[3]) {
    for (uint32_t i = 0; i < n; i++) {
        const double* b = boxes + 6 * i;
        if (q[0] >= b[0] && q[0] <= b[3] && q[1] >= b[1] && q[1] <= b[4] && q[2] >= b[2] && q[2] <= b[5]) return true;
    }
    return false;
}

/* World boxes of the drawn instances of g (model mi, or every model for
 * UINT32_MAX) into *out (6 doubles each), each grown by a margin. */
static vx_result drawn_boxes(const vx_svo_scene* g, uint32_t mi, const vx_allocator* a, double** out, uint32_t* n,
                             vx_error* err) {
    *n = 0;
    *out = vx_alloc(a, (g->instance_count ? g->instance_count : 1) * 6 * sizeof(double));
    if (!*out) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %u instance boxes", g->instance_count);
    for (uint32_t i = 0; i < g->instance_count; i++) {
        if (!vx_svo_instance_drawn(g, i) || (mi != UINT32_MAX && g->instances[i].model != mi)) continue;
        double lo[3], hi[3], w = 0;
        vx_svo_instance_world_box(g, &g->instances[i], lo, hi);
        for (int k = 0; k < 3; k++) w = fmax(w, hi[k] - lo[k]);
        double m = 1e-6 * w + 1e-9;
        double* b = *out + 6 * (*n)++;
        for (int k = 0; k < 3; k++) b[k] = lo[k] - m, b[3 + k] = hi[k] + m;
    }
    return VX_OK;
}

vx_result vx_probe_place_reader(vx_svo_model_reader* rd, const vx_svo_scene* view, const vx_probe_bake_desc* desc,
                                vx_probe_set* out, vx_error* err) {
    if (!rd || !out) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    const vx_svo_scene* g = view ? view : vx_svo_reader_scene(rd);
    vx_probe_bake_desc d = desc ? *desc : (vx_probe_bake_desc){0};
    vx_probe_set ps = {.alloc = d.alloc};
    vx_result r = resolve(&d, &ps, err);
    if (r) return r;
    if ((r = record_light(&ps, NULL, g, &d, err))) { /* as vx_probe_place records it, no cell read */
        vx_probe_set_free(&ps);
        return r;
    }
    if ((r = place_grid(g, &d, &ps, err))) {
        vx_probe_set_free(&ps);
        return r;
    }
    offs cand[PLACE_CANDS];
    int nc = place_candidates(&ps, cand);
    /* Each probe's candidates up to the first outside every drawn instance's
     * box (that one is free: no cast can start in a cell there): those are
     * the places the pass over the models decides, one bit each. */
    double* all = NULL;
    uint32_t nall = 0;
    uint64_t* first = vx_alloc(d.alloc, ((size_t)ps.probe_count + 1) * sizeof *first);
    uint8_t* solid = NULL;
    if (!first) r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory");
    if (!r) r = drawn_boxes(g, UINT32_MAX, d.alloc, &all, &nall, err);
    uint64_t bits = 0;
    for (uint32_t i = 0; !r && i < ps.probe_count; i++) {
        first[i] = bits;
        for (int k = 0; k < nc; k++) {
            double q[3];
            place_point(&ps, ps.probes[i].pos, &cand[k], q);
            bits++;
            if (!in_boxes(all, nall, q)) break;
        }
    }
    if (!r) first[ps.probe_count] = bits;
    if (!r && !(solid = vx_calloc(d.alloc, (size_t)(bits / 8 + 1), 1)))
        r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %llu probe places", (unsigned long long)bits);
    /* One pass over the models: each model with its drawn instances alone is
     * a scene for the CPU caster, whose casts decide its instances' cells as
     * the whole scene's caster decides them (a cast starting in a cell of any
     * instance hits at t = 0, the others do not change that). */
    for (;;) {
        if (r) break;
        uint32_t mi = 0;
        vx_svo_model m;
        if ((r = vx_svo_reader_next(rd, &mi, &m, err)) || mi >= g->model_count) break;
        double* boxes = NULL;
        uint32_t nb = 0;
        vx_svo_instance* inst = NULL;
        r = drawn_boxes(g, mi, d.alloc, &boxes, &nb, err);
        if (!r && nb && !(inst = vx_alloc(d.alloc, nb * sizeof *inst)))
            r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory");
        vx_render_caster* c = NULL;
        if (!r && nb) {
            uint32_t n = 0;
            for (uint32_t i = 0; i < g->instance_count; i++)
                if (vx_svo_instance_drawn(g, i) && g->instances[i].model == mi) inst[n] = g->instances[i], inst[n++].model = 0;
            vx_svo_scene sub = *g; /* its world map, layers and palette; this model and its instances */
            sub.models = &m, sub.model_count = 1;
            sub.instances = inst, sub.instance_count = n;
            sub.frame_count = 1, sub.frame_instances = NULL;
            r = vx_render_caster_create(&sub, d.alloc, &c, err);
            for (uint32_t i = 0; !r && i < ps.probe_count; i++)
                for (uint64_t b = first[i]; b < first[i + 1]; b++) {
                    if (solid[b / 8] & (1u << (b % 8))) continue;
                    double q[3];
                    place_point(&ps, ps.probes[i].pos, &cand[b - first[i]], q);
                    if (in_boxes(boxes, nb, q) && inside_solid(c, q)) solid[b / 8] |= (uint8_t)(1u << (b % 8));
                }
            vx_render_caster_destroy(c);
        }
        vx_free(d.alloc, inst);
        vx_free(d.alloc, boxes);
        vx_svo_model_free(vx_svo_reader_scene(rd)->alloc, &m);
    }
    if (!r) r = vx_svo_reader_finish(rd, err);
    for (uint32_t i = 0; !r && i < ps.probe_count; i++) {
        vx_probe* p = &ps.probes[i];
        for (uint64_t b = first[i]; b < first[i + 1]; b++) {
            if (solid[b / 8] & (1u << (b % 8))) continue;
            double q[3];
            place_point(&ps, p->pos, &cand[b - first[i]], q);
            memcpy(p->pos, q, sizeof q);
            p->state = b == first[i] ? VX_PROBE_OK : VX_PROBE_MOVED;
            break;
        }
    }
    vx_free(d.alloc, all);
    vx_free(d.alloc, first);
    vx_free(d.alloc, solid);
    if (r) {
        vx_probe_set_free(&ps);
        return r;
    }
    return place_done(&d, &ps, out, err);
}

vx_probe_bake_desc vx_probe_bake_desc_defaults(void) {
    return (vx_probe_bake_desc){.res = 128, .spp = 16, .bounces = 1, .light_dir = {0.35, -0.45, 0.82},
                                .sun = {3, 3, 3}, .sky = {0.31, 0.375, 0.46}};
}

static vx_result resolve(const vx_probe_bake_desc* d, vx_probe_set* ps, vx_error* err) {
    const vx_probe_bake_desc D = vx_probe_bake_desc_defaults();
    ps->res = d->res ? d->res : D.res;
    if (ps->res < 16 || ps->res > VX_PROBE_MAX_RES || ps->res % 16)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "res %u: must be a multiple of 16 in 16..%u", ps->res,
                       VX_PROBE_MAX_RES);
    ps->low_res = ps->res / 16;
    ps->spp = d->spp ? d->spp : D.spp;
    if (ps->spp > 65536) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "spp %u: at most 65536", ps->spp);
    ps->bounces = d->bounces == 0 ? (uint32_t)D.bounces : (d->bounces < 0 ? 0 : (uint32_t)d->bounces);
    if (ps->bounces > 64) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "bounces %u: at most 64", ps->bounces);
    ps->seed = d->seed;
    return VX_OK;
}

vx_result vx_probe_place(const vx_svo_scene* scene, const vx_probe_bake_desc* desc, vx_probe_set* out, vx_error* err) {
    if (!scene || !out) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    vx_probe_bake_desc d = desc ? *desc : (vx_probe_bake_desc){0};
    vx_probe_set ps = {.alloc = d.alloc};
    vx_result r = resolve(&d, &ps, err);
    if (r) return r;
    vx_render_caster* c = NULL;
    if ((r = vx_render_caster_create(scene, d.alloc, &c, err))) return r;
    r = record_light(&ps, c, scene, &d, err);
    if (!r) r = place(scene, &d, caster_solid, c, &ps, err);
    vx_render_caster_destroy(c);
    if (r) {
        vx_probe_set_free(&ps);
        return r;
    }
    return place_done(&d, &ps, out, err);
}

/* ---- placement from the compact layout ------------------------------------------------ */

/* The drawn instances as the CPU caster holds them (render/instance_ray.h). */
typedef struct cplace {
    const vx_compact_scene* c;
    const vx_svo_scene* s;
    uint32_t n;
    vx__inst_map* maps; /* per drawn instance */
} cplace;

/* inside_solid's answer without the caster: its cast (render/cpu_trace.c trace_scene, cm_trace) hits at
 * t = 0 exactly where, for some drawn instance, the ray's span in the model's box starts at t = 0 (q in
 * the box) and the cell it starts in is set: an empty start cell is left at t > 0, a later entry is at
 * t > 0. The instance maps, the span and the start cell are the caster's own functions
 * (render/instance_ray.h), the cell looked up in the layout's geometry (vx_compact_lookup) instead of the
 * caster's table of every leaf (about 60 bytes a cell: 6.3 GB for the 100 M-cell terrain). */
static bool compact_solid(const void* user, const double q[3]) {
    const cplace* P = user;
    for (uint32_t i = 0; i < P->n; i++) {
        const vx__inst_map* in = &P->maps[i];
        const vx_svo_model* m = &P->s->models[in->model];
        if (m->root == VX_SVO_ROOT_EMPTY) continue;
        double om[3], dm[3];
        vx__inst_ray(in, q, solid_dir, om, dm);
        double te, tx;
        if (!vx__box_span(m->size, om, dm, 0.0, solid_tmax, &te, &tx) || te > 0.0) continue;
        int64_t cell[3];
        vx__box_cell(m->size, om, dm, 0.0, te, cell, NULL); /* the caster's start cell; no ambiguity needed */
        uint32_t index;
        if (vx_compact_lookup(P->c, in->model, (uint32_t)cell[0], (uint32_t)cell[1], (uint32_t)cell[2], &index))
            return true;
    }
    return false;
}

vx_result vx_probe_place_compact(const vx_compact_scene* c, const vx_svo_scene* scene, const vx_probe_bake_desc* desc,
                                 vx_probe_set* out, vx_error* err) {
    if (!c || !scene || !out) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    if (c->model_count != scene->model_count)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "the compact layout has %u models, the scene %u",
                       c->model_count, scene->model_count);
    for (uint32_t i = 0; i < c->model_count; i++)
        if (c->models[i].depth != scene->models[i].depth)
            return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET,
                           "model %u: depth %u in the compact layout, %u in the scene (not its layout)", i,
                           c->models[i].depth, scene->models[i].depth);
    vx_probe_bake_desc d = desc ? *desc : (vx_probe_bake_desc){0};
    vx_probe_set ps = {.alloc = d.alloc};
    vx_result r = resolve(&d, &ps, err);
    if (r) return r;
    cplace P = {.c = c, .s = scene};
    P.maps = vx_calloc(d.alloc, scene->instance_count ? scene->instance_count : 1, sizeof *P.maps);
    if (!P.maps) r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %u instances", scene->instance_count);
    if (!r) r = vx__inst_maps(scene, P.maps, &P.n, err);
    if (!r) r = record_light(&ps, NULL, scene, &d, err);
    if (!r) r = place(scene, &d, compact_solid, &P, &ps, err);
    vx_free(d.alloc, P.maps);
    if (r) {
        vx_probe_set_free(&ps);
        return r;
    }
    return place_done(&d, &ps, out, err);
}

/* ---- baking --------------------------------------------------------------------------- */

/* per-probe element counts */
typedef struct sizes {
    size_t rad, nrm, dist, low, irr, mom;
} sizes;

static sizes sizes_of(const vx_probe_set* ps) {
    sizes z;
    z.rad = vx__bsq(ps->res) * 3;
    z.nrm = vx__bsq(ps->res);
    z.dist = vx__bsq(ps->res);
    z.low = vx__bsq(ps->low_res);
    z.irr = vx__bsq(VX_PROBE_IRR_RES) * 3;
    z.mom = vx__bsq(VX_PROBE_DIST_RES) * 2;
    return z;
}

/* Grows the data arrays to hold n probes (the new ones zeroed where zero is set; probes_internal.h). */
bool vx__probe_grow(vx_probe_set* ps, uint32_t n, bool zero) {
    sizes z = sizes_of(ps);
    void** arr[6] = {(void**)&ps->radiance, (void**)&ps->normal, (void**)&ps->distance,
                     (void**)&ps->low, (void**)&ps->irradiance, (void**)&ps->moments};
    size_t el[6] = {z.rad * 2, z.nrm * 4, z.dist * 2, z.low * 2, z.irr * 2, z.mom * 4};
    for (int i = 0; i < 6; i++) {
        size_t old, want;
        if (!vx_mul_size(el[i], ps->count, &old) || !vx_mul_size(el[i], n, &want)) return false;
        uint8_t* p = zero ? vx_calloc(ps->alloc, want ? want : 1, 1) : vx_alloc(ps->alloc, want ? want : 1);
        if (!p) return false;
        if (*arr[i] && old) memcpy(p, *arr[i], old < want ? old : want);
        vx_free(ps->alloc, *arr[i]);
        *arr[i] = p;
    }
    return true;
}

bool vx__tables_make(vx__tables* T, uint32_t res, const vx_allocator* alloc) {
    memset(T, 0, sizeof *T);
    T->res = res;
    T->alloc = alloc;
    size_t nt = (size_t)res * res;
    T->dir = vx_calloc(alloc, nt, 3 * sizeof(double));
    T->omega = vx_calloc(alloc, nt, sizeof(double));
    if (!T->dir || !T->omega) return false;
    for (uint32_t j = 0; j < res; j++)
        for (uint32_t i = 0; i < res; i++) {
            vx_probe_texel_dir(res, i, j, &T->dir[3 * ((size_t)j * res + i)]);
            T->omega[(size_t)j * res + i] = vx_probe_texel_solid_angle(res, i, j);
        }
    for (uint32_t q = 0; q < VX_PROBE_IRR_RES * VX_PROBE_IRR_RES; q++)
        vx_probe_texel_dir(VX_PROBE_IRR_RES, q % VX_PROBE_IRR_RES, q / VX_PROBE_IRR_RES, T->irr_dir[q]);
    for (uint32_t q = 0; q < VX_PROBE_DIST_RES * VX_PROBE_DIST_RES; q++)
        vx_probe_texel_dir(VX_PROBE_DIST_RES, q % VX_PROBE_DIST_RES, q / VX_PROBE_DIST_RES, T->mom_dir[q]);
    return true;
}

void vx__tables_free(vx__tables* T) {
    vx_free(T->alloc, T->dir);
    vx_free(T->alloc, T->omega);
    T->dir = T->omega = NULL;
}

typedef struct job {
    const vx_probe_set* ps;
    vx_probe_set* out;
    const vx__light* L;
    const vx__tables* T;
    uint32_t begin, end;
    uint32_t next; /* guarded by mu */
    uint32_t done;
    bool cancel, failed;
    pthread_mutex_t mu;
    const vx_progress* progress;
    const vx_allocator* alloc;
} job;

/* Copies each border texel of a bordered n x n map of `elem`-byte texels
 * from the interior texel it repeats (vx_probe_border_src). */
static void fill_border(void* map, uint32_t n, size_t elem) {
    uint8_t* m = (uint8_t*)map;
    for (uint32_t bj = 0; bj < n + 2; bj++)
        for (uint32_t bi = 0; bi < n + 2; bi++) {
            if (bi >= 1 && bi <= n && bj >= 1 && bj <= n) continue;
            uint32_t si, sj;
            vx_probe_border_src(n, bi, bj, &si, &sj);
            memcpy(m + ((size_t)bj * (n + 2) + bi) * elem, m + ((size_t)(sj + 1) * (n + 2) + si + 1) * elem, elem);
        }
}

#define MOMENT_POWER 50.0

/* Bakes one probe into slot k of out; scratch holds res^2 * 4 doubles. */
static void bake_probe(const job* J, uint32_t pi, uint32_t k, double* scratch) {
    const vx_probe_set* ps = J->ps;
    vx_probe_set* out = J->out;
    const vx__tables* T = J->T;
    const vx_probe* pr = &ps->probes[pi];
    sizes z = sizes_of(ps);
    uint32_t* nrm = out->normal + z.nrm * k;
    uint16_t* dist = out->distance + z.dist * k;
    if (pr->state == VX_PROBE_DISABLED) return; /* stays zero */
    uint32_t n = ps->res, nb = n + 2;
    double* L = scratch;          /* res^2 * 3 radiance */
    double* D = scratch + 3 * (size_t)n * n; /* res^2 decoded distances */
    for (uint32_t j = 0; j < n; j++)
        for (uint32_t i = 0; i < n; i++) {
            size_t t = (size_t)j * n + i;
            const double* d = &T->dir[3 * t];
            vx_render_ray_hit h;
            size_t b = (size_t)(j + 1) * nb + i + 1;
            if (vx_render_cast(J->L->caster, pr->pos, d, ps->dist_max, false, &h)) {
                double q = nearbyint(h.t / ps->dist_step);
                dist[b] = (uint16_t)(q > VX_PROBE_DIST_MISS - 1 ? VX_PROBE_DIST_MISS - 1 : q);
                nrm[b] = vx_probe_oct_pack16(h.normal);
                D[t] = dist[b] * ps->dist_step;
            } else {
                dist[b] = VX_PROBE_DIST_MISS;
                nrm[b] = 0;
                D[t] = ps->dist_max;
            }
            double acc[3] = {0, 0, 0};
            for (uint32_t s = 0; s < ps->spp; s++) {
                vx__rng rng = vx__rng_make(ps->seed, pi, t, s);
                /* jittered inside the texel (sample 0 too: the map is an average) */
                double uv[2] = {(2.0 * (i + vx__rng_next(&rng))) / n - 1, (2.0 * (j + vx__rng_next(&rng))) / n - 1};
                double dd[3], c[3];
                vx_probe_oct_decode(uv, dd);
                vx__path(J->L, pr->pos, dd, ps->bounces, false, &rng, c);
                for (int q = 0; q < 3; q++) acc[q] += c[q];
            }
            for (int q = 0; q < 3; q++) L[3 * t + q] = acc[q] / ps->spp;
        }
    vx__probe_finish(out, T, k, L, D);
}

void vx__probe_finish(vx_probe_set* out, const vx__tables* T, uint32_t k, const double* L, const double* D) {
    const vx_probe_set* ps = out;
    sizes z = sizes_of(ps);
    uint16_t* rad = out->radiance + z.rad * k;
    uint32_t* nrm = out->normal + z.nrm * k;
    uint16_t* dist = out->distance + z.dist * k;
    uint16_t* low = out->low + z.low * k;
    uint16_t* irr = out->irradiance + z.irr * k;
    float* mom = out->moments + z.mom * k;
    uint32_t n = ps->res, nb = n + 2;
    for (size_t t = 0; t < (size_t)n * n; t++) {
        size_t b = (t / n + 1) * nb + t % n + 1;
        for (int q = 0; q < 3; q++) rad[3 * b + q] = vx_probe_half((float)L[3 * t + q]);
    }
    fill_border(rad, n, 3 * sizeof *rad);
    fill_border(nrm, n, sizeof *nrm);
    fill_border(dist, n, sizeof *dist);
    /* low-resolution minimum distance: each texel the minimum over its block */
    uint32_t lr = ps->low_res, blk = n / lr;
    for (uint32_t lj = 0; lj < lr; lj++)
        for (uint32_t li = 0; li < lr; li++) {
            uint16_t m = 0xFFFF;
            for (uint32_t j = lj * blk; j < (lj + 1) * blk; j++)
                for (uint32_t i = li * blk; i < (li + 1) * blk; i++) {
                    uint16_t v = dist[(size_t)(j + 1) * nb + i + 1];
                    if (v < m) m = v;
                }
            low[(lj + 1) * (lr + 2) + li + 1] = m;
        }
    fill_border(low, lr, sizeof *low);
    /* cosine-convolved irradiance: E(n) = sum L(w) max(0, n.w) dw */
    for (uint32_t q = 0; q < VX_PROBE_IRR_RES * VX_PROBE_IRR_RES; q++) {
        const double* nn = T->irr_dir[q];
        double e[3] = {0, 0, 0};
        for (size_t t = 0; t < (size_t)n * n; t++) {
            const double* w = &T->dir[3 * t];
            double c = nn[0] * w[0] + nn[1] * w[1] + nn[2] * w[2];
            if (c <= 0) continue;
            c *= T->omega[t];
            e[0] += L[3 * t] * c, e[1] += L[3 * t + 1] * c, e[2] += L[3 * t + 2] * c;
        }
        uint32_t i = q % VX_PROBE_IRR_RES, j = q / VX_PROBE_IRR_RES;
        size_t b = (size_t)(j + 1) * (VX_PROBE_IRR_RES + 2) + i + 1;
        for (int c = 0; c < 3; c++) irr[3 * b + c] = vx_probe_half((float)e[c]);
    }
    fill_border(irr, VX_PROBE_IRR_RES, 3 * sizeof *irr);
    /* distance moments with a sharp cosine lobe (DDGI's power 50) */
    for (uint32_t q = 0; q < VX_PROBE_DIST_RES * VX_PROBE_DIST_RES; q++) {
        const double* nn = T->mom_dir[q];
        double m1 = 0, m2 = 0, ws = 0;
        for (size_t t = 0; t < (size_t)n * n; t++) {
            const double* w = &T->dir[3 * t];
            double c = nn[0] * w[0] + nn[1] * w[1] + nn[2] * w[2];
            if (c <= 0.75) continue; /* cos^50 < 6e-7 beyond: negligible */
            double wt = pow(c, MOMENT_POWER) * T->omega[t];
            m1 += wt * D[t], m2 += wt * D[t] * D[t], ws += wt;
        }
        uint32_t i = q % VX_PROBE_DIST_RES, j = q / VX_PROBE_DIST_RES;
        size_t b = (size_t)(j + 1) * (VX_PROBE_DIST_RES + 2) + i + 1;
        mom[2 * b] = (float)(ws > 0 ? m1 / ws : ps->dist_max);
        mom[2 * b + 1] = (float)(ws > 0 ? m2 / ws : ps->dist_max * ps->dist_max);
    }
    fill_border(mom, VX_PROBE_DIST_RES, 2 * sizeof *mom);
}

static void* worker(void* arg) {
    job* J = arg;
    size_t n = (size_t)J->ps->res * J->ps->res * 4;
    double* scratch = vx_alloc(J->alloc, n * sizeof(double));
    pthread_mutex_lock(&J->mu);
    if (!scratch) J->failed = true;
    while (!J->failed && !J->cancel && J->next < J->end) {
        uint32_t pi = J->next++;
        pthread_mutex_unlock(&J->mu);
        bake_probe(J, pi, pi - J->out->first, scratch);
        pthread_mutex_lock(&J->mu);
        J->done++;
        if (!vx_progress_report(J->progress, "bake", J->done, J->end - J->begin)) J->cancel = true;
    }
    pthread_mutex_unlock(&J->mu);
    vx_free(J->alloc, scratch);
    return NULL;
}

vx_result vx_probe_bake_more(const vx_svo_scene* scene, const vx_probe_bake_desc* desc, vx_probe_set* ps,
                             uint32_t end, vx_error* err) {
    if (!scene || !ps) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    vx_probe_bake_desc d = desc ? *desc : (vx_probe_bake_desc){0};
    uint32_t begin;
    vx_result r = vx__probe_bake_begin(ps, end, &begin, err);
    if (r || end == begin) return r;
    vx_render_caster* c = NULL;
    if ((r = vx_render_caster_create(scene, ps->alloc, &c, err))) return r;
    vx__light L;
    vx__tables T = {0};
    if ((r = vx__probe_set_light(&L, c, scene, ps, err))) goto done;
    if (!vx__tables_make(&T, ps->res, ps->alloc) || !vx__probe_grow(ps, end - ps->first, true)) {
        r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %u probes at res %u", end - ps->first, ps->res);
        goto done;
    }
    job J = {.ps = ps, .out = ps, .L = &L, .T = &T, .begin = begin, .end = end, .next = begin,
             .progress = &d.progress, .alloc = ps->alloc};
    pthread_mutex_init(&J.mu, NULL);
    vx_run_threads(d.threads, worker, &J);
    pthread_mutex_destroy(&J.mu);
    if (J.failed) {
        r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory");
    } else if (J.cancel) {
        r = vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "cancelled");
    }
    if (!r) {
        ps->count = end - ps->first;
    }
    /* on failure count stays: the probes baked so far are not recorded (the
     * arrays merely grew), so a resume redoes them */
done:
    vx__tables_free(&T);
    vx__light_free(&L);
    vx_render_caster_destroy(c);
    return r;
}

/* ---- the bake's driver -------------------------------------------------------------- */

vx_result vx__probe_bake_begin(const vx_probe_set* ps, uint32_t end, uint32_t* begin, vx_error* err) {
    *begin = ps->first + ps->count;
    if (end > ps->probe_count || end < *begin)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "bake end %u outside %u..%u", end, *begin,
                       ps->probe_count);
    return VX_OK;
}

vx_result vx__probe_set_light(vx__light* L, const vx_render_caster* c, const vx_svo_scene* s, const vx_probe_set* ps,
                              vx_error* err) {
    vx_result r = vx__light_init(L, c, s, ps->light_dir, ps->sun, false, ps->sky, false, err);
    /* the set's resolved values (vx__light_init takes a zero sun or sky for the default) */
    for (int k = 0; k < 3; k++) L->sun[k] = ps->sun[k], L->sky[k] = ps->sky[k];
    return r;
}

vx_result vx__probe_bake_placed(const vx_svo_scene* scene, const vx_probe_bake_desc* desc, vx__probe_bake_range bake,
                                void* device, vx_probe_set* out, vx_error* err) {
    vx_probe_set ps;
    double t0 = vx_time_now();
    vx_result r = vx_probe_place(scene, desc, &ps, err);
    if (r) return r;
    double placed = vx_time_now() - t0;
    uint32_t end = desc && desc->count ? desc->first + desc->count : ps.probe_count;
    if ((r = bake(device, scene, desc, &ps, end, err))) {
        vx_probe_set_free(&ps);
        return r;
    }
    if (desc && desc->stats) desc->stats->place = placed;
    *out = ps;
    return VX_OK;
}

static vx_result bake_range_cpu(void* device, const vx_svo_scene* scene, const vx_probe_bake_desc* desc,
                                vx_probe_set* ps, uint32_t end, vx_error* err) {
    (void)device;
    return vx_probe_bake_more(scene, desc, ps, end, err);
}

vx_result vx_probe_bake(const vx_svo_scene* scene, const vx_probe_bake_desc* desc, vx_probe_set* out, vx_error* err) {
    if (!scene || !out) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    return vx__probe_bake_placed(scene, desc, bake_range_cpu, NULL, out, err);
}

/* ---- merging ------------------------------------------------------------------------ */

static bool same_grid(const vx_probe_set* a, const vx_probe_set* b) {
    if (a->res != b->res || a->low_res != b->low_res || a->probe_count != b->probe_count || a->spp != b->spp ||
        a->bounces != b->bounces || a->seed != b->seed || a->dist_step != b->dist_step)
        return false;
    for (int k = 0; k < 3; k++)
        if (a->grid[k] != b->grid[k] || a->origin[k] != b->origin[k] || a->spacing[k] != b->spacing[k] ||
            a->light_dir[k] != b->light_dir[k] || a->sun[k] != b->sun[k] || a->sky[k] != b->sky[k])
            return false;
    return !memcmp(a->probes, b->probes, sizeof *a->probes * a->probe_count);
}

vx_result vx_probe_merge(const vx_probe_set* const* parts, uint32_t n, const vx_allocator* alloc, vx_probe_set* out,
                         vx_error* err) {
    if (!parts || !n || !out) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "nothing to merge");
    const vx_probe_set* a = parts[0];
    for (uint32_t i = 1; i < n; i++)
        if (!same_grid(a, parts[i]))
            return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "part %u: different grid or bake parameters than part 0", i);
    /* the ranges must tile [0, probe_count) exactly */
    uint32_t covered = 0;
    for (uint32_t at = 0; at < a->probe_count;) {
        uint32_t hit = UINT32_MAX;
        for (uint32_t i = 0; i < n; i++)
            if (parts[i]->first == at && parts[i]->count) hit = i;
        if (hit == UINT32_MAX) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "no part holds probe %u", at);
        at += parts[hit]->count;
        covered++;
    }
    uint32_t nonempty = 0;
    for (uint32_t i = 0; i < n; i++) nonempty += parts[i]->count != 0;
    if (covered != nonempty) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "parts overlap");
    vx_probe_set ps = *a;
    ps.alloc = alloc;
    ps.first = ps.count = 0;
    ps.radiance = NULL, ps.normal = NULL, ps.distance = NULL, ps.low = NULL, ps.irradiance = NULL, ps.moments = NULL;
    ps.probes = vx_calloc(alloc, a->probe_count, sizeof *ps.probes);
    if (!ps.probes || !vx__probe_grow(&ps, a->probe_count, true)) {
        vx_probe_set_free(&ps);
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory");
    }
    memcpy(ps.probes, a->probes, sizeof *ps.probes * a->probe_count);
    sizes z = sizes_of(&ps);
    for (uint32_t i = 0; i < n; i++) {
        const vx_probe_set* p = parts[i];
        size_t f = p->first, c = p->count;
        memcpy(ps.radiance + z.rad * f, p->radiance, z.rad * c * 2);
        memcpy(ps.normal + z.nrm * f, p->normal, z.nrm * c * 4);
        memcpy(ps.distance + z.dist * f, p->distance, z.dist * c * 2);
        memcpy(ps.low + z.low * f, p->low, z.low * c * 2);
        memcpy(ps.irradiance + z.irr * f, p->irradiance, z.irr * c * 2);
        memcpy(ps.moments + z.mom * f, p->moments, z.mom * c * 4);
    }
    ps.count = a->probe_count;
    *out = ps;
    return VX_OK;
}
