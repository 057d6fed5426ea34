/* probes/lightfield.c - rays traced through the probes' light field
 * (McGuire et al. 2017): a ray is walked through one probe's distance map in
 * the map's own texel space.
 *
 * Inside one octant of the probe's frame the octahedral map is a central
 * projection (q -> q.xy / |q|_1, |q|_1 linear in q while the signs are
 * fixed) followed by an affine fold, so the image of a ray is a straight
 * segment per octant: at most four, split where the ray crosses the probe's
 * coordinate planes. Each segment is walked with a 2D DDA over the R/16
 * minimum-distance map first; a coarse texel whose minimum distance is
 * beyond the ray's farthest point in it (with a margin for surfaces seen at
 * a slant) is skipped whole, and only the others are walked at full
 * resolution.
 *
 * Each texel's stored distance and normal give the plane of the surface the
 * probe saw through it (exact for voxel faces). Inside the texel's view cone
 * the ray is: in front of that plane, free space; crossing it from the front
 * near the point the probe saw, a hit, whose radiance is that texel's; behind
 * it (beyond its uncertainty), or farther from the probe than the plane
 * reaches anywhere in the cone (an edge or corner inside the texel), past a
 * surface the probe sees: this probe cannot answer, and the next continues
 * from there. The normal also keeps a ray from "hitting" the surface it
 * leaves (it crosses that plane from behind). The maximum cone half-angle of
 * an octahedral texel is 4.25 / R (measured over R = 16..128). */
#include <math.h>
#include <string.h>

#include "probes/probes_internal.h"

/* Octahedral map coordinate of q for a fixed octant s (signs +-1): a point on
 * the octant's boundary planes gets the same value as from either side. */
static bool enc_octant(const double q[3], const double s[3], double uv[2]) {
    double l1 = s[0] * q[0] + s[1] * q[1] + s[2] * q[2];
    if (!(l1 > 0)) return false;
    double px = q[0] / l1, py = q[1] / l1;
    if (s[2] < 0) {
        double ux = (1 - s[1] * py) * s[0], uy = (1 - s[0] * px) * s[1];
        px = ux, py = uy;
    }
    uv[0] = px, uv[1] = py;
    return true;
}

/* The t of the ray point q0 + t d that the probe sees in direction w (the
 * two lines are coplanar by construction: w comes from the ray's image). */
static double t_of_dir(const double q0[3], const double d[3], const double w[3], double fallback) {
    double cqw[3] = {q0[1] * w[2] - q0[2] * w[1], q0[2] * w[0] - q0[0] * w[2], q0[0] * w[1] - q0[1] * w[0]};
    double cdw[3] = {d[1] * w[2] - d[2] * w[1], d[2] * w[0] - d[0] * w[2], d[0] * w[1] - d[1] * w[0]};
    double den = cdw[0] * cdw[0] + cdw[1] * cdw[1] + cdw[2] * cdw[2];
    if (!(den > 0)) return fallback;
    return -(cqw[0] * cdw[0] + cqw[1] * cdw[1] + cqw[2] * cdw[2]) / den;
}

static double radius(const double q0[3], const double d[3], double t) {
    double x = q0[0] + t * d[0], y = q0[1] + t * d[1], z = q0[2] + t * d[2];
    return sqrt(x * x + y * y + z * z);
}

/* Is the ray point at t within `near` of the point P + D w the probe saw? */
static bool near_seen(const double q0[3], const double d[3], double t, double D, const double w[3], double near) {
    double e = 0;
    for (int k = 0; k < 3; k++) {
        double x = q0[k] + t * d[k] - D * w[k];
        e += x * x;
    }
    return e <= near * near;
}

/* 2D DDA over unit cells along A + a (B - A), a in [0, 1]. */
typedef struct dda {
    int ix, iy, sx, sy;
    double nx, ny, dx, dy; /* a of the next x / y boundary, a per cell */
} dda;

static void dda_init(dda* g, const double A[2], const double B[2], double a0, int m) {
    double ex = B[0] - A[0], ey = B[1] - A[1];
    double px = A[0] + a0 * ex, py = A[1] + a0 * ey;
    g->sx = ex > 0 ? 1 : (ex < 0 ? -1 : 0);
    g->sy = ey > 0 ? 1 : (ey < 0 ? -1 : 0);
    double fx = floor(px), fy = floor(py);
    /* on a boundary, start in the cell the segment goes into */
    if (fx == px && g->sx < 0) fx -= 1;
    if (fy == py && g->sy < 0) fy -= 1;
    fx = !(fx >= 0) ? 0 : (fx > m - 1 ? m - 1 : fx); /* NaN too: the cast below must stay in range */
    fy = !(fy >= 0) ? 0 : (fy > m - 1 ? m - 1 : fy);
    g->ix = (int)fx, g->iy = (int)fy;
    g->dx = g->sx ? 1.0 / fabs(ex) : INFINITY;
    g->dy = g->sy ? 1.0 / fabs(ey) : INFINITY;
    g->nx = g->sx ? ((fx + (g->sx > 0)) - A[0]) / ex : INFINITY;
    g->ny = g->sy ? ((fy + (g->sy > 0)) - A[1]) / ey : INFINITY;
}

/* a where the current cell ends; then steps into the next cell. */
static double dda_step(dda* g) {
    if (g->nx < g->ny) {
        double a = g->nx;
        g->ix += g->sx, g->nx += g->dx;
        return a;
    }
    double a = g->ny;
    g->iy += g->sy, g->ny += g->dy;
    return a;
}

typedef struct walk {
    const vx_probe_set* ps;
    const uint16_t* dist;
    const uint32_t* nrm;
    const double* q0;
    const double* d;
    double tol_rel; /* plane uncertainty per unit distance: a texel's footprint */
    bool first;     /* no texel visited yet: a start behind a surface is not a hit */
    vx__lf_counts* cnt;
} walk;

/* One fine texel over ray parameters [t0, t1]: 0 free, 1 hit, 2 unknown.
 * The texel's stored distance and normal give the plane of the surface the
 * probe sees through it (exact for voxel faces); the ray is classified by
 * its side of that plane inside the texel's view cone: in front throughout,
 * free; crossing it from the front, a hit; already behind it on entry, a hit
 * if only by the plane's uncertainty (a continuous surface), else it went
 * behind a silhouette and this probe cannot tell. */
static int texel_test(walk* W, int fx, int fy, double t0, double t1, double* t_hit) {
    uint32_t n = W->ps->res;
    size_t at = (size_t)(fy + 1) * (n + 2) + (size_t)fx + 1;
    W->cnt->texels++;
    bool first = W->first;
    W->first = false;
    uint16_t code = W->dist[at];
    if (code == VX_PROBE_DIST_MISS) return 0; /* (a normal code 0 is +z, not a miss) */
    double D = code * W->ps->dist_step;
    double w[3], N[3];
    vx_probe_texel_dir(n, (uint32_t)fx, (uint32_t)fy, w);
    vx_probe_oct_unpack16(W->nrm[at], N);
    /* signed distance of the ray point (relative to the probe) to the plane */
    const double *q0 = W->q0, *d = W->d;
    double c0 = (q0[0] - D * w[0]) * N[0] + (q0[1] - D * w[1]) * N[1] + (q0[2] - D * w[2]) * N[2];
    double sd = d[0] * N[0] + d[1] * N[1] + d[2] * N[2];
    double s0 = c0 + t0 * sd, s1 = c0 + t1 * sd;
    /* the plane's own uncertainty: distance quantisation, normal packing */
    double thick = 2 * W->ps->dist_step + D * W->tol_rel;
    if (D <= thick) return 2; /* the probe sits on this surface: it sees nothing here */
    /* A hit must lie near the point the probe actually saw, within about
     * one texel's footprint: the plane of a face seen at a grazing angle
     * reaches far beyond the face inside the cone. */
    double near = thick + D * 4.25 / n;
    if (s0 >= 0 && s1 < 0) {
        /* crosses the plane from the front inside the cone */
        double th = t0 + (t1 - t0) * (s0 / (s0 - s1));
        if (!near_seen(q0, d, th, D, w, near)) return 2;
        *t_hit = th;
        return 1;
    }
    if (s0 < -thick) return 2; /* behind a surface the probe sees */
    if (s0 < 0 && sd < 0) {
        /* entered just behind it: a continuous surface, unless at the start */
        if (first || !near_seen(q0, d, t0, D, w, near)) return 2;
        *t_hit = t0;
        return 1;
    }
    /* In front of the plane (or leaving it). One plane per texel is wrong
     * where the cone holds an edge or a corner: a ray farther from the probe
     * than the plane reaches anywhere in the cone has passed some other
     * surface. */
    double cosw = fabs(w[0] * N[0] + w[1] * N[1] + w[2] * N[2]);
    double ang = acos(fmin(cosw, 1.0)) + 4.25 / n;
    if (ang < 1.5) {
        double dmax = D * cosw / cos(ang);
        if (fmax(radius(q0, d, t0), radius(q0, d, t1)) > dmax + thick) return 2;
    }
    return 0;
}

vx__lf_status vx__lf_trace_probe(const vx_probe_set* ps, uint32_t pi, const double o[3], const double d[3],
                                 double* t_io, double t_end, uint32_t* texel, vx__lf_counts* cnt) {
    vx__lf_counts dummy = {0};
    if (!cnt) cnt = &dummy;
    cnt->probe_traces++;
    uint32_t n = ps->res, lr = ps->low_res, k = pi - ps->first;
    const vx_probe* pr = &ps->probes[pi];
    double q0[3] = {o[0] - pr->pos[0], o[1] - pr->pos[1], o[2] - pr->pos[2]};
    walk W = {.ps = ps, .dist = ps->distance + vx__bsq(n) * k, .nrm = ps->normal + vx__bsq(n) * k, .q0 = q0, .d = d,
              .tol_rel = 1.0 / n, .first = true, .cnt = cnt};
    const uint16_t* low = ps->low + vx__bsq(lr) * k;
    double t0 = *t_io;
    /* the octant segments */
    double ts[5];
    int nt = 0;
    ts[nt++] = t0;
    for (int a = 0; a < 3; a++) {
        if (d[a] == 0) continue;
        double tb = -q0[a] / d[a];
        if (tb > t0 && tb < t_end) ts[nt++] = tb;
    }
    for (int i = 1; i < nt; i++)
        for (int j = i; j > 0 && ts[j] < ts[j - 1]; j--) {
            double x = ts[j];
            ts[j] = ts[j - 1], ts[j - 1] = x;
        }
    ts[nt++] = t_end;
    double fine_per_coarse = (double)n / lr;
    for (int sgi = 0; sgi + 1 < nt; sgi++) {
        double ta = ts[sgi], tb = ts[sgi + 1];
        if (!(tb > ta)) continue;
        double tm = 0.5 * (ta + tb), s[3];
        for (int a = 0; a < 3; a++) s[a] = q0[a] + tm * d[a] < 0 ? -1 : 1;
        double qa[3], qb[3], ua[2], ub[2];
        for (int a = 0; a < 3; a++) qa[a] = q0[a] + ta * d[a], qb[a] = q0[a] + tb * d[a];
        /* an end at the probe's centre (a ray through it, or from it) has no
         * direction: the image is that of a point just inside the segment */
        if (!enc_octant(qa, s, ua)) {
            double e = fmin(1e-6, 0.5 * (tb - ta));
            for (int a = 0; a < 3; a++) qa[a] = q0[a] + (ta + e) * d[a];
        }
        if (!enc_octant(qb, s, ub)) {
            double e = fmin(1e-6, 0.5 * (tb - ta));
            for (int a = 0; a < 3; a++) qb[a] = q0[a] + (tb - e) * d[a];
        }
        if (!enc_octant(qa, s, ua) || !enc_octant(qb, s, ub) || !isfinite(ua[0] + ua[1] + ub[0] + ub[1])) {
            *t_io = ta; /* too short for the precision, or beyond it (a file's extreme values) */
            return VX__LF_UNKNOWN;
        }
        /* coarse texel coordinates (fine = coarse * n / lr) */
        double A[2] = {(ua[0] + 1) * 0.5 * lr, (ua[1] + 1) * 0.5 * lr};
        double B[2] = {(ub[0] + 1) * 0.5 * lr, (ub[1] + 1) * 0.5 * lr};
        double Af[2] = {A[0] * fine_per_coarse, A[1] * fine_per_coarse};
        double Bf[2] = {B[0] * fine_per_coarse, B[1] * fine_per_coarse};
        /* a of the segment -> t (exact at the ends) */
        double ex = Bf[0] - Af[0], ey = Bf[1] - Af[1];
        bool radial = fabs(ex) + fabs(ey) < 1e-9;
        dda gc;
        dda_init(&gc, A, B, 0, (int)lr);
        double ac0 = 0;
        double tc0 = ta;
        while (ac0 < 1) {
            /* a step can land one cell past the map's edge (the segment ends
             * on it up to rounding): stay on the map, as the GPU walk does */
            int cx = gc.ix < 0 ? 0 : (gc.ix > (int)lr - 1 ? (int)lr - 1 : gc.ix);
            int cy = gc.iy < 0 ? 0 : (gc.iy > (int)lr - 1 ? (int)lr - 1 : gc.iy);
            double ac1 = radial ? 1 : fmin(dda_step(&gc), 1);
            double tc1 = tb;
            if (ac1 < 1) {
                double uv[2] = {(Af[0] + ac1 * ex) / n * 2 - 1, (Af[1] + ac1 * ey) / n * 2 - 1}, w[3];
                vx_probe_oct_decode(uv, w);
                tc1 = fmin(fmax(t_of_dir(q0, d, w, tc0), tc0), tb);
            }
            uint16_t lc = low[(size_t)(cy + 1) * (lr + 2) + (size_t)cx + 1];
            double dmin = lc == VX_PROBE_DIST_MISS ? INFINITY : lc * ps->dist_step;
            double rmax = fmax(radius(q0, d, tc0), radius(q0, d, tc1));
            /* centre distances bound a texel's surface only up to its slope:
             * skip with a margin of a few texels' footprint */
            if (!W.first && rmax < dmin * (1 - 8.0 / n)) {
                cnt->coarse_skips++;
            } else {
                /* the fine texels of this coarse texel along [ac0, ac1] */
                dda gf;
                dda_init(&gf, Af, Bf, ac0, (int)n);
                double af0 = ac0, tf0 = tc0;
                int lo_x = cx * (int)(n / lr), lo_y = cy * (int)(n / lr), hi_x = lo_x + (int)(n / lr) - 1,
                    hi_y = lo_y + (int)(n / lr) - 1;
                while (af0 < ac1) {
                    int fx = gf.ix < lo_x ? lo_x : (gf.ix > hi_x ? hi_x : gf.ix);
                    int fy = gf.iy < lo_y ? lo_y : (gf.iy > hi_y ? hi_y : gf.iy);
                    double af1 = radial ? ac1 : fmin(dda_step(&gf), ac1);
                    double tf1 = tc1;
                    if (af1 < ac1) {
                        double uv[2] = {(Af[0] + af1 * ex) / n * 2 - 1, (Af[1] + af1 * ey) / n * 2 - 1}, w[3];
                        vx_probe_oct_decode(uv, w);
                        tf1 = fmin(fmax(t_of_dir(q0, d, w, tf0), tf0), tc1);
                    }
                    double th;
                    int r = texel_test(&W, fx, fy, tf0, tf1, &th);
                    if (r == 1) {
                        *t_io = th;
                        *texel = (uint32_t)(fy + 1) * (n + 2) + (uint32_t)fx + 1;
                        return VX__LF_HIT;
                    }
                    if (r == 2) {
                        *t_io = tf0;
                        return VX__LF_UNKNOWN;
                    }
                    af0 = af1, tf0 = tf1;
                    if (radial) break;
                }
            }
            ac0 = ac1, tc0 = tc1;
            if (radial) break;
        }
    }
    *t_io = t_end;
    return VX__LF_MISS;
}

/* Leaving the box [lo, hi] (slabs); 0 if o is outside and the ray misses. */
static double exit_t(const double lo[3], const double hi[3], const double o[3], const double d[3]) {
    double t_near = 0, t_far = INFINITY;
    for (int k = 0; k < 3; k++) {
        if (d[k] == 0) {
            if (o[k] < lo[k] || o[k] > hi[k]) return 0;
            continue;
        }
        double a = (lo[k] - o[k]) / d[k], b = (hi[k] - o[k]) / d[k];
        if (a > b) {
            double x = a;
            a = b, b = x;
        }
        t_near = fmax(t_near, a), t_far = fmin(t_far, b);
    }
    return t_far >= t_near ? t_far : 0;
}

void vx__lf_radiance(const vx__lf* lf, const double o[3], const double d[3], double out[3], vx__lf_counts* cnt) {
    const vx_probe_set* ps = lf->ps;
    cnt->rays++;
    double t_end = exit_t(lf->lo, lf->hi, o, d);
    /* the eight probes around o, nearest first */
    uint32_t cand[8];
    double cd[8];
    int nc = 0;
    int64_t base[3];
    double alpha[3];
    vx__probe_cage(ps, o, base, alpha);
    for (int c = 0; c < 8; c++) {
        int64_t idx[3];
        bool skip = false;
        for (int k = 0; k < 3; k++) {
            idx[k] = base[k] + ((c >> k) & 1);
            if (idx[k] >= (int64_t)ps->grid[k]) skip = true;
        }
        if (skip) continue;
        uint32_t pi = (uint32_t)((size_t)idx[0] + ps->grid[0] * ((size_t)idx[1] + ps->grid[1] * (size_t)idx[2]));
        if (ps->probes[pi].state == VX_PROBE_DISABLED) continue;
        double r = 0;
        for (int k = 0; k < 3; k++) r += (ps->probes[pi].pos[k] - o[k]) * (ps->probes[pi].pos[k] - o[k]);
        int j = nc++;
        for (; j > 0 && cd[j - 1] > r; j--) cand[j] = cand[j - 1], cd[j] = cd[j - 1];
        cand[j] = pi, cd[j] = r;
    }
    double t = 0;
    for (int c = 0; c < nc && t_end > 0; c++) {
        uint32_t texel = 0;
        vx__lf_status st = vx__lf_trace_probe(ps, cand[c], o, d, &t, t_end, &texel, cnt);
        if (st == VX__LF_HIT) {
            const uint16_t* rad = ps->radiance + vx__bsq(ps->res) * 3 * (cand[c] - ps->first);
            for (int k = 0; k < 3; k++) out[k] = vx_probe_half_to_float(rad[3 * (size_t)texel + k]);
            cnt->hits++;
            return;
        }
        if (st == VX__LF_MISS) {
            memcpy(out, lf->L->sky, 3 * sizeof(double));
            cnt->misses++;
            return;
        }
    }
    if (!(t_end > 0)) {
        memcpy(out, lf->L->sky, 3 * sizeof(double));
        cnt->misses++;
        return;
    }
    /* no probe could answer: the octree tracer, shaded with the probes' irradiance */
    cnt->fallbacks++;
    vx_render_ray_hit h;
    if (!vx_render_cast(lf->L->caster, o, d, INFINITY, false, &h)) {
        memcpy(out, lf->L->sky, 3 * sizeof(double));
        return;
    }
    vx__surface sf;
    vx__surface_of(lf->L, o, d, &h, &sf);
    double dl[3], e[3];
    vx__direct(lf->L, &sf, dl);
    vx_probe_irradiance(ps, sf.p, sf.n, e);
    for (int k = 0; k < 3; k++) out[k] = sf.emit[k] + dl[k] + sf.albedo[k] / 3.14159265358979323846 * e[k];
}
