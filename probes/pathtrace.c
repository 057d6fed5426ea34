/* probes/pathtrace.c - the path tracer (CPU reference, double precision):
 * materials, light sampling and the path loop; probes/shaders/probe.comp
 * runs the same algorithm in float on the GPU.
 *
 * Materials (vx_material by material id, vx_svo_attr_material; colour = the voxel's colour):
 *  diffuse, emit  Lambert; emit adds colour * emission (any type may emit)
 *  metal          GGX microfacet, alpha = max(rough^2, 1e-3), Smith
 *                 height-correlated G2, Schlick Fresnel with
 *                 F0 = mix(0.08 specular, colour, metalness), plus a Lambert
 *                 lobe (1 - metalness)(1 - 0.08 specular) colour / pi;
 *                 the path picks the specular lobe with probability
 *                 ps = (1 + metalness) / 2 (visible normals, Heitz 2018),
 *                 else the Lambert lobe (cosine), and weighs the lobe drawn
 *                 alone (its f cos / (pick probability * pdf)): the
 *                 specular lobe's event is a metal event (below)
 *  glass          with probability `transmission` a dielectric (exact
 *                 Fresnel, IOR; rough glass: visible-normal GGX sampling,
 *                 alpha = rough^2, smooth below 1e-3), else Lambert. A glass
 *                 voxel is a solid block: a refracted ray walks cell by cell
 *                 through adjacent glass voxels and leaves through the first
 *                 face whose neighbour is empty; a path that reaches a face
 *                 shared with an opaque voxel ends there (the surface under
 *                 the glass is not shaded: a documented loss). Transmission into
 *                 the glass is tinted by the colour; IOR 1 is no interface.
 * Lights: the probes' sun (a delta) and sky (uniform, or the render's sky
 * by direction: gradient or environment map; reached by BSDF rays only), the frame's vx_lights and the emissive voxels. Point and spot
 * lights are deltas (glTF falloff; d^2 kept above (cell/100)^2); a
 * directional light with an angular diameter is a cone of radiance
 * E / (pi sin^2(diameter/2)), sampled uniformly in solid angle (below
 * CONE_MIN, 1e-6 rad, a delta: the cone's radiance would leave the GPU's
 * float range); sphere
 * lights by their subtended cone, rect lights by area, emissive voxels by
 * power (a voxel with probability lum(radiance) * area / total, a point
 * uniformly on its surface, so a point's area density is
 * lum(radiance) / total: no look-up of the voxel hit is needed for MIS).
 * Lights marked VX_LIGHT_FROM_VOXELS are left out: the emissive voxels they
 * stand for are sampled themselves. Every vertex with a non-delta BSDF
 * samples every light once (cost linear
 * in the light count: this is the reference, not the many-light renderer);
 * BSDF rays that reach an area light, a cone or an emissive voxel are
 * weighted against light sampling by the power heuristic. Light sampling
 * through glass is blocked (shadow rays stop at every voxel), so a light
 * seen through glass is found by BSDF rays with full weight, and delta
 * lights cast no caustics. Russian roulette from VX__RR_DEPTH bounces on.
 *
 * Bounces: a path ends after `bounces` diffuse or glossy bounces, but a
 * metal event, the specular lobe drawn at a metal record (whatever its
 * roughness), spends none, for the first VX__METAL_CHAIN of them on the
 * path (later ones count): the probe modes' camera chain follows that many
 * metal events without counting them either (render_gi.c, light.h), and the
 * reference those modes are judged against (the GI table's: the path tracer
 * at the probes' bounces + 1) must count what they count. Before, a mirror
 * facing a metal wall came out at 0.36x the converged light at the default
 * bounces (test_metal_gi). Where only the specular lobe goes on (bounces
 * spent, metal events left), light sampling weighs each lobe apart: the
 * specular lobe's against its own sampling, the Lambert lobe's whole (the
 * path ends if that lobe is drawn), so the estimate stays unbiased for the
 * light it defines; no roulette on the free events (at most
 * VX__METAL_CHAIN). The bake (bake.c) runs the same paths, so the probes'
 * light counts the same way. A scene without metal runs the code it ran
 * before (the same numbers, the same bytes). */
#include <math.h>
#include <string.h>

#include "probes/probes_internal.h"

static const double pi = 3.14159265358979323846;

static inline double dot3(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
static inline double lum3(const double c[3]) { return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]; }
static inline void norm3(double v[3]) {
    double l = sqrt(dot3(v, v));
    if (l > 0)
        for (int k = 0; k < 3; k++) v[k] /= l;
}
static inline double mis(double a, double b) { return a * a / (a * a + b * b); } /* power heuristic */

/* Orthonormal basis around unit n (Duff et al. 2017). */
static void basis(const double n[3], double t[3], double b[3]) {
    double sg = copysign(1.0, n[2]);
    double a = -1.0 / (sg + n[2]), c = n[0] * n[1] * a;
    t[0] = 1 + sg * n[0] * n[0] * a, t[1] = sg * c, t[2] = -sg * n[0];
    b[0] = c, b[1] = sg + n[1] * n[1] * a, b[2] = -n[1];
}

/* Unit vector within the cone of half-angle acos(cmax) around unit axis,
 * uniform in solid angle (pdf 1 / (2 pi (1 - cmax))); omc = 1 - cmax. */
static void cone_dir(const double axis[3], double omc, double u1, double u2, double d[3]) {
    double t[3], b[3];
    basis(axis, t, b);
    double z = 1 - u1 * omc, s = sqrt(fmax(0, 1 - z * z)), phi = 2 * pi * u2;
    for (int k = 0; k < 3; k++) d[k] = s * cos(phi) * t[k] + s * sin(phi) * b[k] + z * axis[k];
}

/* ---- GGX ---------------------------------------------------------------------------- */

static double ggx_d(double a2, double z) {
    double c = z * z * (a2 - 1) + 1;
    return a2 / (pi * c * c);
}
static double ggx_lambda(double a2, double z) {
    double z2 = z * z;
    if (z2 >= 1) return 0;
    if (!(z2 > 0)) return 1e30;
    return 0.5 * (-1 + sqrt(1 + a2 * (1 - z2) / z2));
}
/* A visible normal for local wo (z up, wo.z > 0), Heitz 2018. */
static void ggx_vndf(double alpha, const double wo[3], double u1, double u2, double m[3]) {
    double vh[3] = {alpha * wo[0], alpha * wo[1], wo[2]};
    norm3(vh);
    double l2 = vh[0] * vh[0] + vh[1] * vh[1];
    double t1[3] = {1, 0, 0};
    if (l2 > 0) t1[0] = -vh[1] / sqrt(l2), t1[1] = vh[0] / sqrt(l2), t1[2] = 0;
    double t2[3] = {vh[1] * t1[2] - vh[2] * t1[1], vh[2] * t1[0] - vh[0] * t1[2], vh[0] * t1[1] - vh[1] * t1[0]};
    double r = sqrt(u1), phi = 2 * pi * u2;
    double p1 = r * cos(phi), p2 = r * sin(phi), s = 0.5 * (1 + vh[2]);
    p2 = (1 - s) * sqrt(fmax(0, 1 - p1 * p1)) + s * p2;
    double pz = sqrt(fmax(0, 1 - p1 * p1 - p2 * p2));
    double nh[3];
    for (int k = 0; k < 3; k++) nh[k] = p1 * t1[k] + p2 * t2[k] + pz * vh[k];
    m[0] = alpha * nh[0], m[1] = alpha * nh[1], m[2] = fmax(0, nh[2]);
    norm3(m);
}

/* Unpolarised Fresnel reflectance at a dielectric interface; cosi > 0 on the
 * incident side, eta = n_transmitted / n_incident. */
static double fresnel_dielectric(double cosi, double eta) {
    double s2t = (1 - cosi * cosi) / (eta * eta);
    if (s2t >= 1) return 1;
    double ct = sqrt(1 - s2t);
    double rs = (cosi - eta * ct) / (cosi + eta * ct), rp = (eta * cosi - ct) / (eta * cosi + ct);
    return 0.5 * (rs * rs + rp * rp);
}

/* ---- the BSDF of a vertex --------------------------------------------------------- */

enum { B_LAMBERT, B_GLOSSY, B_GLASS };

typedef struct bsdf {
    int kind;
    double alb[3];
    double kd[3], f0[3]; /* glossy: Lambert weight, Fresnel at normal incidence */
    double alpha, a2, ps; /* glossy: probability of the specular lobe */
    double eta;
    double n[3], t[3], b[3]; /* shading frame */
} bsdf;

static void to_local(const bsdf* B, const double v[3], double o[3]) {
    o[0] = dot3(v, B->t), o[1] = dot3(v, B->b), o[2] = dot3(v, B->n);
}
static void to_world(const bsdf* B, const double v[3], double o[3]) {
    for (int k = 0; k < 3; k++) o[k] = v[0] * B->t[k] + v[1] * B->b[k] + v[2] * B->n[k];
}

/* The vertex's BSDF; glass that does not transmit this time is Lambert. */
static void bsdf_of(const vx__light* L, const vx__surface* s, vx__rng* rng, bsdf* B) {
    memset(B, 0, sizeof *B);
    const vx_material* m = vx__light_material(L, s->material);
    memcpy(B->alb, s->albedo, sizeof B->alb);
    memcpy(B->n, s->n, sizeof B->n);
    basis(B->n, B->t, B->b);
    B->kind = B_LAMBERT;
    if (m->type == VX_MATERIAL_METAL) {
        B->kind = B_GLOSSY;
        double mt = m->metalness, f0d = 0.08 * m->specular;
        for (int k = 0; k < 3; k++) B->kd[k] = (1 - mt) * (1 - f0d) * B->alb[k], B->f0[k] = (1 - mt) * f0d + mt * B->alb[k];
        B->alpha = fmax(m->roughness * m->roughness, 1e-3);
        B->a2 = B->alpha * B->alpha;
        B->ps = 0.5 * (1 + mt);
    } else if (m->type == VX_MATERIAL_GLASS && m->transmission > 0 &&
               (m->transmission >= 1 || vx__rng_next(rng) < m->transmission)) {
        B->kind = B_GLASS;
        B->alpha = m->roughness * m->roughness;
        B->a2 = B->alpha * B->alpha;
        B->eta = m->ior;
    }
}

/* f (per channel) and the solid-angle pdf of sampling wi, world directions. */
static void bsdf_eval(const bsdf* B, const double wo_w[3], const double wi_w[3], double f[3], double* pdf) {
    double wo[3], wi[3];
    to_local(B, wo_w, wo), to_local(B, wi_w, wi);
    f[0] = f[1] = f[2] = 0, *pdf = 0;
    if (wi[2] <= 0 || wo[2] <= 0) return;
    if (B->kind == B_LAMBERT) {
        for (int k = 0; k < 3; k++) f[k] = B->alb[k] / pi;
        *pdf = wi[2] / pi;
        return;
    }
    double h[3] = {wo[0] + wi[0], wo[1] + wi[1], wo[2] + wi[2]};
    norm3(h);
    double d = ggx_d(B->a2, h[2]), lo = ggx_lambda(B->a2, wo[2]), li = ggx_lambda(B->a2, wi[2]);
    double g2 = 1 / (1 + lo + li), c = fmax(0, dot3(wi, h)), s5 = pow(1 - c, 5);
    for (int k = 0; k < 3; k++) f[k] = B->kd[k] / pi + (B->f0[k] + (1 - B->f0[k]) * s5) * d * g2 / (4 * wo[2] * wi[2]);
    *pdf = B->ps * d / (1 + lo) / (4 * wo[2]) + (1 - B->ps) * wi[2] / pi;
}

/* The two lobes of a glossy vertex apart (vx__path's metal events follow the specular one): each lobe's f
 * and the solid-angle pdf of its own sampler (cosine; visible normals), not weighted by the lobe's pick. */
static void glossy_lobes(const bsdf* B, const double wo_w[3], const double wi_w[3], double fs[3], double* pss,
                         double fd[3], double* pdd) {
    double wo[3], wi[3];
    to_local(B, wo_w, wo), to_local(B, wi_w, wi);
    for (int k = 0; k < 3; k++) fs[k] = fd[k] = 0;
    *pss = *pdd = 0;
    if (wi[2] <= 0 || wo[2] <= 0) return;
    double h[3] = {wo[0] + wi[0], wo[1] + wi[1], wo[2] + wi[2]};
    norm3(h);
    double d = ggx_d(B->a2, h[2]), lo = ggx_lambda(B->a2, wo[2]), li = ggx_lambda(B->a2, wi[2]);
    double g2 = 1 / (1 + lo + li), c = fmax(0, dot3(wi, h)), s5 = pow(1 - c, 5);
    for (int k = 0; k < 3; k++) fs[k] = (B->f0[k] + (1 - B->f0[k]) * s5) * d * g2 / (4 * wo[2] * wi[2]);
    for (int k = 0; k < 3; k++) fd[k] = B->kd[k] / pi;
    *pss = d / (1 + lo) / (4 * wo[2]);
    *pdd = wi[2] / pi;
}

/* The direction of one lobe from u1, u2: the specular lobe's by visible
 * normals (false where wo is below the surface), else the Lambert lobe's
 * cosine; bsdf_sample and glossy_sample differ only in how they pick it. */
static bool lobe_dir(const bsdf* B, const double wo[3], bool spec, double u1, double u2, double wi_w[3]) {
    if (!spec) {
        vx__cosine_dir(B->n, u1, u2, wi_w);
        return true;
    }
    if (wo[2] <= 0) return false;
    double m[3], wi[3];
    ggx_vndf(B->alpha, wo, u1, u2, m);
    double c = dot3(wo, m);
    for (int k = 0; k < 3; k++) wi[k] = 2 * c * m[k] - wo[k];
    to_world(B, wi, wi_w);
    return true;
}

/* Samples wi for a Lambert or glossy vertex: weight = f cos / pdf. */
static bool bsdf_sample(const bsdf* B, const double wo_w[3], vx__rng* rng, double wi_w[3], double w[3], double* pdf) {
    double wo[3];
    to_local(B, wo_w, wo);
    double u0 = vx__rng_next(rng), u1 = vx__rng_next(rng), u2 = vx__rng_next(rng);
    if (!lobe_dir(B, wo, B->kind != B_LAMBERT && u0 < B->ps, u1, u2, wi_w)) return false;
    double f[3];
    bsdf_eval(B, wo_w, wi_w, f, pdf);
    double cs = dot3(wi_w, B->n);
    if (!(*pdf > 0) || cs <= 0) return false;
    for (int k = 0; k < 3; k++) w[k] = f[k] * cs / *pdf;
    return true;
}

/* Samples wi at a glossy vertex by one lobe, as vx__path needs it (a metal event is the specular lobe's,
 * and only that lobe may go on where the path's bounces are spent): the specular lobe with probability
 * ps (visible normals), else the Lambert lobe (cosine); the three numbers of bsdf_sample. w = the lobe's
 * own f cos / (ps_lobe pdf_lobe) and *pdf = ps_lobe pdf_lobe (the density the lights' MIS weighs
 * against), *spec the lobe drawn: per lobe an unbiased estimate of its share of the reflected light,
 * so the two sum to the whole BSDF's (no one-sample MIS between the lobes, which would mix the shares). */
static bool glossy_sample(const bsdf* B, const double wo_w[3], vx__rng* rng, double wi_w[3], double w[3],
                          double* pdf, bool* spec) {
    double wo[3];
    to_local(B, wo_w, wo);
    double u0 = vx__rng_next(rng), u1 = vx__rng_next(rng), u2 = vx__rng_next(rng);
    *spec = u0 < B->ps;
    if (!lobe_dir(B, wo, *spec, u1, u2, wi_w)) return false;
    double fs[3], fd[3], pss, pdd;
    glossy_lobes(B, wo_w, wi_w, fs, &pss, fd, &pdd);
    const double* f = *spec ? fs : fd;
    *pdf = *spec ? B->ps * pss : (1 - B->ps) * pdd;
    double cs = dot3(wi_w, B->n);
    if (!(*pdf > 0) || cs <= 0) return false;
    for (int k = 0; k < 3; k++) w[k] = f[k] * cs / *pdf;
    return true;
}

/* One event at a dielectric interface: n faces the incident side, wo (unit)
 * leaves the surface on that side, eta = n_other / n_this. */
static bool dielectric(const double n[3], const double wo_w[3], double eta, double alpha, vx__rng* rng,
                       double wi_w[3], bool* refracted, double* weight) {
    *weight = 1;
    if (fabs(eta - 1) < 1e-9) { /* index-matched: no interface */
        for (int k = 0; k < 3; k++) wi_w[k] = -wo_w[k];
        *refracted = true;
        return true;
    }
    bsdf F = {0};
    memcpy(F.n, n, sizeof F.n);
    basis(F.n, F.t, F.b);
    double wo[3], m[3] = {0, 0, 1}, wi[3];
    to_local(&F, wo_w, wo);
    if (wo[2] <= 0) return false;
    bool rough = alpha >= 1e-3;
    double u1 = vx__rng_next(rng), u2 = vx__rng_next(rng), u3 = vx__rng_next(rng);
    if (rough) ggx_vndf(alpha, wo, u1, u2, m);
    double c = dot3(wo, m);
    if (c <= 0) return false;
    double fr = fresnel_dielectric(c, eta);
    if (u3 < fr) {
        for (int k = 0; k < 3; k++) wi[k] = 2 * c * m[k] - wo[k];
        *refracted = false;
    } else {
        double e = 1 / eta, k2 = 1 - e * e * (1 - c * c);
        for (int k = 0; k < 3; k++) wi[k] = -e * wo[k] + (e * c - sqrt(fmax(0, k2))) * m[k];
        *refracted = true;
    }
    if (rough) {
        double a2 = alpha * alpha;
        if (*refracted ? wi[2] >= 0 : wi[2] <= 0) return false;
        double li = ggx_lambda(a2, fabs(wi[2])), lo = ggx_lambda(a2, wo[2]);
        /* visible-normal sampling with Fresnel selection: G2 / G1(wo) for
         * reflection, G1(wi) for transmission (separable on either side) */
        *weight = *refracted ? 1 / (1 + li) : (1 + lo) / (1 + lo + li);
    }
    norm3(wi);
    to_world(&F, wi, wi_w);
    return true;
}

/* Inside a glass voxel (cell `cell` of instance `inst`) at p, going along d:
 * walks through adjacent glass voxels to the face where the glass ends and
 * applies the interface there (internal reflections continue the walk).
 * Each step leaves the box of the octree leaf that holds the current cell:
 * a uniform glass block (collapsed) at once, else the one cell, so a thick
 * uniform body costs a handful of steps. The exits are measured along the
 * straight stretch from its start p (t: how far the walk is along it), so
 * where a stretch leaves the glass does not depend on the boxes it took on
 * the way (the GPU walks give the same bits in either scene layout, one of
 * which knows no collapsed leaves: path_common.glsl). WALK_ABSORBED: the walk
 * limit (render/trace.h vx__glass_walk_steps). WALK_OUT: o/d the ray that
 * left. WALK_STOP: the walk met an opaque voxel across a face of the glass
 * (a glass block on a floor, a voxel set in glass) or, in a scene of several
 * instances, another instance's voxel inside the glass box (a model placed
 * overlapping a glass one; found by a cast that passes over the glass
 * instance, which a ray from inside it would meet at once): *stop is that
 * voxel's surface, seen from inside the glass, and the glass cell the walk
 * was in, where a bounce off the surface walks on (vx__path). */
enum { WALK_ABSORBED, WALK_OUT, WALK_STOP };
typedef struct glass_stop {
    vx_render_ray_hit h;  /* the opaque voxel: normal facing into the glass, t = 0 at p */
    double p[3];          /* the point on the face between the glass and the voxel */
    uint32_t inst, cell[3]; /* the glass cell it was met from */
} glass_stop;
/* Whether a hit's material is glass that transmits (a walk goes on in it). */
static bool transmits(const vx__light* L, const vx_render_ray_hit* g) {
    const vx_material* m = vx__light_material(L, g->material);
    return m->type == VX_MATERIAL_GLASS && m->transmission > 0;
}

/* A walk's stop (WALK_STOP): the voxel of g met at p, from glass cell c of
 * instance inst. */
static int stop_at(glass_stop* stop, const vx_render_ray_hit* g, const double p[3], uint32_t inst, const uint32_t c[3]) {
    stop->h = *g;
    stop->h.t = 0;
    memcpy(stop->p, p, sizeof stop->p);
    stop->inst = inst, memcpy(stop->cell, c, sizeof stop->cell);
    return WALK_STOP;
}

static int glass_walk(const vx__light* L, uint32_t inst, const uint32_t cell[3], double csize, double ior, double alpha,
                      double p[3], double d[3], vx__rng* rng, double thr[3], double o[3], glass_stop* stop) {
    uint32_t c[3] = {cell[0], cell[1], cell[2]};
    const vx_svo_scene* S = L->scene;
    uint32_t limit = vx__glass_walk_steps(S->models[S->instances[inst].model].depth);
    double t = 0; /* along d from p */
    for (uint32_t step = 0; step < limit; step++) {
        const double* M = L->inst_inv + 12 * (size_t)inst;
        const vx_svo_model* mod = &S->models[S->instances[inst].model];
        /* the leaf's box: [lo, hi) on each axis, within the model's size */
        uint32_t lv = vx_svo_model_cell_leaf(mod, c[0], c[1], c[2]);
        double lo[3], hi[3];
        for (int a = 0; a < 3; a++) {
            uint32_t b = lv == UINT32_MAX ? c[a] : c[a] & ~((1u << lv) - 1u);
            uint32_t e = lv == UINT32_MAX ? c[a] + 1 : b + (1u << lv);
            lo[a] = b, hi[a] = e < mod->size[a] ? e : mod->size[a];
        }
        double om[3], dm[3];
        for (int r = 0; r < 3; r++) {
            om[r] = M[4 * r] * p[0] + M[4 * r + 1] * p[1] + M[4 * r + 2] * p[2] + M[4 * r + 3];
            dm[r] = M[4 * r] * d[0] + M[4 * r + 1] * d[1] + M[4 * r + 2] * d[2];
        }
        double te = INFINITY;
        int ax = -1;
        for (int a = 0; a < 3; a++) {
            if (dm[a] == 0) continue;
            double ta = ((dm[a] > 0 ? hi[a] : lo[a]) - om[a]) / dm[a];
            if (ta < te) te = ta, ax = a;
        }
        if (ax < 0 || !isfinite(te)) return WALK_ABSORBED;
        te = fmax(te, t);
        /* (a box of one cell: another instance there is met at its faces, below) */
        if (S->instance_count > 1 && lv != UINT32_MAX && lv > 0 && te > t) {
            double a[3] = {p[0] + d[0] * t, p[1] + d[1] * t, p[2] + d[2] * t};
            vx_render_ray_hit g;
            if (vx_render_cast_skip(L->caster, a, d, te - t, false, inst, &g) && !transmits(L, &g)) {
                double at[3] = {a[0] + d[0] * g.t, a[1] + d[1] * g.t, a[2] + d[2] * g.t};
                return stop_at(stop, &g, at, inst, c);
            }
        }
        double q[3], nf[3], eps = 1e-4 * csize;
        for (int k = 0; k < 3; k++) q[k] = p[k] + d[k] * te, nf[k] = (dm[ax] > 0 ? 1 : -1) * M[4 * ax + k];
        norm3(nf);
        /* the neighbour across the exit face: a ray starting inside a voxel hits it at 0 */
        double qi[3] = {q[0] + d[0] * eps, q[1] + d[1] * eps, q[2] + d[2] * eps};
        vx_render_ray_hit g;
        if (vx_render_cast(L->caster, qi, d, eps, false, &g)) {
            if (transmits(L, &g)) {
                inst = g.instance, c[0] = g.cell[0], c[1] = g.cell[1], c[2] = g.cell[2];
                t = te + eps;
                continue;
            }
            /* an opaque voxel against the glass: its face (the glass cell's), lit only through the glass */
            for (int k = 0; k < 3; k++) g.normal[k] = -nf[k];
            return stop_at(stop, &g, q, inst, c);
        }
        /* glass -> outside: the normal facing the inside */
        double nin[3] = {-nf[0], -nf[1], -nf[2]}, wo[3] = {-d[0], -d[1], -d[2]}, wi[3], w;
        bool refr;
        if (!dielectric(nin, wo, 1 / ior, alpha, rng, wi, &refr, &w)) return WALK_ABSORBED;
        for (int k = 0; k < 3; k++) thr[k] *= w;
        memcpy(d, wi, 3 * sizeof(double));
        if (refr) {
            for (int k = 0; k < 3; k++) o[k] = q[k] + nf[k] * eps;
            return WALK_OUT;
        }
        /* reflected inside: a new stretch from just inside the face */
        for (int k = 0; k < 3; k++) p[k] = q[k] - nf[k] * eps;
        t = 0;
    }
    return WALK_ABSORBED;
}

/* ---- lights ------------------------------------------------------------------------- */

static bool occluded(const vx__light* L, const double p[3], const double l[3], double tmax) {
    return vx_render_cast(L->caster, p, l, tmax, true, NULL);
}

/* The frame's sphere and rect lights along a ray, nearest before tmax:
 * its index, radiance and the solid-angle density light sampling gives the
 * direction from o. */
static int area_hit(const vx__light* L, const double o[3], const double d[3], double tmax, double le[3],
                    double* pdf) {
    int best = -1;
    for (uint32_t i = 0; i < L->light_count; i++) {
        const vx_light* l = &L->lights[i];
        double t = INFINITY, p = 0;
        if (l->flags & VX_LIGHT_FROM_VOXELS) continue; /* the voxels emit themselves */
        if (l->type == VX_LIGHT_SPHERE) {
            double v[3] = {l->position[0] - o[0], l->position[1] - o[1], l->position[2] - o[2]};
            double d2 = dot3(v, v), r2 = l->radius * l->radius, b = dot3(v, d);
            if (d2 <= r2 || b <= 0) continue; /* inside: not seen (see nee) */
            double disc = r2 - (d2 - b * b);
            if (disc < 0) continue;
            t = b - sqrt(disc);
            double s2 = r2 / d2, omc = s2 / (1 + sqrt(1 - s2));
            p = 1 / (2 * pi * omc);
        } else if (l->type == VX_LIGHT_RECT) {
            double n[3] = {l->direction[0], l->direction[1], l->direction[2]};
            norm3(n);
            double dn = dot3(d, n);
            if (dn >= 0) continue; /* one-sided */
            double v[3] = {l->position[0] - o[0], l->position[1] - o[1], l->position[2] - o[2]};
            t = dot3(v, n) / dn;
            if (!(t > 0)) continue;
            double t1[3] = {l->tangent[0], l->tangent[1], l->tangent[2]}, tn = dot3(t1, n);
            for (int k = 0; k < 3; k++) t1[k] -= tn * n[k];
            norm3(t1);
            double t2[3] = {n[1] * t1[2] - n[2] * t1[1], n[2] * t1[0] - n[0] * t1[2], n[0] * t1[1] - n[1] * t1[0]};
            double y[3] = {o[0] + d[0] * t - l->position[0], o[1] + d[1] * t - l->position[1],
                           o[2] + d[2] * t - l->position[2]};
            double area = l->size[0] * l->size[1];
            if (!(area > 0) || fabs(dot3(y, t1)) > 0.5 * l->size[0] || fabs(dot3(y, t2)) > 0.5 * l->size[1]) continue;
            p = t * t / (area * -dn);
        } else {
            continue;
        }
        if (t < tmax) {
            tmax = t, best = (int)i, *pdf = p;
            for (int k = 0; k < 3; k++) le[k] = l->color[k] * l->intensity;
        }
    }
    return best;
}

/* Below this angular diameter a directional light is a delta (its cone's
 * radiance E / (pi sin^2) would leave the float range on the GPU). */
#define CONE_MIN 1e-6

/* Radiance and cone (1 - cos of the half angle, sin^2 of it) of a directional
 * light with an angular diameter. */
static void cone_of(const vx_light* l, double axis[3], double* omc, double* s2, double le[3]) {
    memcpy(axis, l->direction, 3 * sizeof(double));
    norm3(axis);
    double h = 0.5 * l->angular_diameter, s = sin(h), q = sin(0.5 * h);
    *omc = 2 * q * q, *s2 = s * s; /* no cancellation for tiny angles */
    for (int k = 0; k < 3; k++) le[k] = l->color[k] * l->intensity / (pi * s * s);
}
/* Whether unit d lies in the cone (by the sine: exact for small angles). */
static bool in_cone(const double ax[3], double s2, const double d[3]) {
    double c[3] = {ax[1] * d[2] - ax[2] * d[1], ax[2] * d[0] - ax[0] * d[2], ax[0] * d[1] - ax[1] * d[0]};
    return dot3(ax, d) > 0 && dot3(c, c) < s2;
}

/* The BSDF towards a sampled light direction l and the weight of the
 * sample, so that f * w * radiance * cos estimates the light: the light's
 * pdf (0: a delta, weight 1) weighed by the power heuristic against the BSDF
 * sampling of each lobe that goes on from the vertex (vx__path: go_d the
 * Lambert lobe, or a Lambert vertex; go_s a glossy vertex's specular lobe),
 * whole (1 / pdf) for a lobe that ends the path there, or nothing where
 * end_zero (the emissive voxels: emission past the path's last vertex is
 * not counted). A glossy vertex's lobes are weighed apart (each with its
 * own pick probability times pdf, as glossy_sample draws them), folded into
 * f with w = 1; a Lambert vertex's as before. */
static void nee_f(const bsdf* B, const double wo[3], const double l[3], double pdf, bool go_d, bool go_s,
                  bool end_zero, double f[3], double* w) {
    double bp;
    if (B->kind != B_GLOSSY) {
        bsdf_eval(B, wo, l, f, &bp);
        if (end_zero) *w = go_d ? mis(pdf, bp) / pdf : 0;
        else *w = pdf > 0 ? (go_d ? mis(pdf, bp) / pdf : 1 / pdf) : 1;
        return;
    }
    double fs[3], fd[3], pss, pdd;
    glossy_lobes(B, wo, l, fs, &pss, fd, &pdd);
    double ws = 1, wd = 1;
    if (pdf > 0 || end_zero) {
        ws = go_s ? mis(pdf, B->ps * pss) / pdf : (end_zero ? 0 : 1 / pdf);
        wd = go_d ? mis(pdf, (1 - B->ps) * pdd) / pdf : (end_zero ? 0 : 1 / pdf);
    }
    for (int k = 0; k < 3; k++) f[k] = fs[k] * ws + fd[k] * wd;
    *w = 1;
}

/* Light arriving at a non-delta vertex by light sampling, through B towards
 * wo: every light once. go_d, go_s: which lobes go on from the vertex
 * (nee_f: the lights are weighed against those lobes' BSDF sampling, whole
 * for the others); skip_direct: leave out what the pass pipeline's direct
 * pass delivers (the sun and every frame light; the emissive voxels when a
 * light stands for them). */
static void nee(const vx__light* L, const vx__surface* s, const bsdf* B, const double wo[3], vx__rng* rng, bool go_d,
                bool go_s, bool skip_direct, double out[3]) {
    double f[3], bp, l[3];
    bool go = go_d || (B->kind == B_GLOSSY && go_s); /* some lobe goes on */
    out[0] = out[1] = out[2] = 0;
    if (!skip_direct && (L->sun[0] > 0 || L->sun[1] > 0 || L->sun[2] > 0) && dot3(s->n, L->light_dir) > 0 &&
        !occluded(L, s->p, L->light_dir, INFINITY)) {
        bsdf_eval(B, wo, L->light_dir, f, &bp);
        double cs = dot3(s->n, L->light_dir);
        for (int k = 0; k < 3; k++) out[k] += f[k] * L->sun[k] * cs;
    }
    for (uint32_t i = 0; i < L->light_count; i++) {
        const vx_light* li = &L->lights[i];
        if (li->flags & VX_LIGHT_FROM_VOXELS) continue;
        double e[3] = {li->color[0] * li->intensity, li->color[1] * li->intensity, li->color[2] * li->intensity};
        double pdf = 0, tmax = INFINITY, g = 1; /* pdf 0: a delta */
        if (skip_direct) continue;
        if (li->type == VX_LIGHT_DIRECTIONAL) {
            if (li->angular_diameter >= CONE_MIN) {
                double ax[3], omc, s2;
                cone_of(li, ax, &omc, &s2, e);
                cone_dir(ax, omc, vx__rng_next(rng), vx__rng_next(rng), l);
                pdf = 1 / (2 * pi * omc);
            } else {
                memcpy(l, li->direction, sizeof l);
                norm3(l);
            }
        } else if (li->type == VX_LIGHT_POINT || li->type == VX_LIGHT_SPOT) {
            double v[3] = {li->position[0] - s->p[0], li->position[1] - s->p[1], li->position[2] - s->p[2]};
            double d2 = dot3(v, v), dist = sqrt(d2), floor2 = 1e-4 * s->cell * s->cell;
            if (!(dist > 0)) continue; /* on the point itself: no direction, no light (finite) */
            for (int k = 0; k < 3; k++) l[k] = v[k] / dist;
            g = 1 / fmax(d2, floor2);
            if (li->range > 0) {
                double q = dist / li->range, w = fmax(0, 1 - q * q * q * q);
                g *= w * w;
            }
            if (li->type == VX_LIGHT_SPOT) {
                double ax[3] = {li->direction[0], li->direction[1], li->direction[2]};
                norm3(ax);
                double ci = cos(li->inner_cone), co = cos(li->outer_cone), sc = 1 / fmax(0.001, ci - co);
                double a = fmin(1, fmax(0, -dot3(l, ax) * sc - co * sc));
                g *= a * a;
            }
            tmax = dist * (1 - 1e-9);
        } else if (li->type == VX_LIGHT_SPHERE) {
            double v[3] = {li->position[0] - s->p[0], li->position[1] - s->p[1], li->position[2] - s->p[2]};
            double d2 = dot3(v, v), r2 = li->radius * li->radius;
            if (d2 <= r2 || !(r2 > 0)) continue; /* inside (or a point): the surface sees no sphere from outside */
            double dist = sqrt(d2), s2 = r2 / d2, omc = s2 / (1 + sqrt(1 - s2));
            for (int k = 0; k < 3; k++) v[k] /= dist;
            cone_dir(v, omc, vx__rng_next(rng), vx__rng_next(rng), l);
            pdf = 1 / (2 * pi * omc);
            double b = dist * dot3(v, l), disc = r2 - (d2 - b * b);
            tmax = (b - sqrt(fmax(0, disc))) * (1 - 1e-9);
        } else if (li->type == VX_LIGHT_RECT) {
            double n[3] = {li->direction[0], li->direction[1], li->direction[2]};
            norm3(n);
            double t1[3] = {li->tangent[0], li->tangent[1], li->tangent[2]}, tn = dot3(t1, n);
            for (int k = 0; k < 3; k++) t1[k] -= tn * n[k];
            norm3(t1);
            double t2[3] = {n[1] * t1[2] - n[2] * t1[1], n[2] * t1[0] - n[0] * t1[2], n[0] * t1[1] - n[1] * t1[0]};
            double area = li->size[0] * li->size[1];
            if (!(area > 0)) continue;
            double u = vx__rng_next(rng) - 0.5, w = vx__rng_next(rng) - 0.5, v[3];
            for (int k = 0; k < 3; k++)
                v[k] = li->position[k] + u * li->size[0] * t1[k] + w * li->size[1] * t2[k] - s->p[k];
            double d2 = dot3(v, v), dist = sqrt(d2);
            if (!(dist > 0)) continue;
            for (int k = 0; k < 3; k++) l[k] = v[k] / dist;
            double cl = -dot3(l, n);
            if (cl <= 0) continue;
            pdf = d2 / (area * cl);
            tmax = dist * (1 - 1e-9);
        } else {
            continue;
        }
        double cs = dot3(s->n, l);
        if (cs <= 0 || g <= 0 || !isfinite(g) || occluded(L, s->p, l, tmax)) continue;
        double w;
        nee_f(B, wo, l, pdf, go_d, go_s, false, f, &w);
        for (int k = 0; k < 3; k++) out[k] += f[k] * e[k] * g * cs * w;
    }
    if (L->em_count && go && !(skip_direct && L->voxel_lights)) {
        /* an emissive voxel by power, a point uniformly on its surface; not
         * at a path's last vertex, where emission counts only when a path
         * hits it (so `bounces` means what it meant before light sampling:
         * emission seen after that many bounces) */
        double u = vx__rng_next(rng);
        uint32_t lo = 0, hi = L->em_count - 1;
        while (lo < hi) {
            uint32_t mid = lo + (hi - lo) / 2;
            if (L->em_cdf[mid] <= u) lo = mid + 1;
            else hi = mid;
        }
        const vx__emitter* em = &L->em[lo];
        double fa[3];
        for (int a = 0; a < 3; a++) {
            const double *p = em->axis[(a + 1) % 3], *q = em->axis[(a + 2) % 3];
            double cx = p[1] * q[2] - p[2] * q[1], cy = p[2] * q[0] - p[0] * q[2], cz = p[0] * q[1] - p[1] * q[0];
            fa[a] = 2 * sqrt(cx * cx + cy * cy + cz * cz);
        }
        double pick = vx__rng_next(rng) * em->area;
        int a = pick < fa[0] ? 0 : (pick < fa[0] + fa[1] ? 1 : 2);
        int side = vx__rng_next(rng) < 0.5;
        double u1 = vx__rng_next(rng), u2 = vx__rng_next(rng), y[3], n[3];
        const double *ea = em->axis[a], *eb = em->axis[(a + 1) % 3], *ec = em->axis[(a + 2) % 3];
        for (int k = 0; k < 3; k++) y[k] = em->corner[k] + side * ea[k] + u1 * eb[k] + u2 * ec[k];
        n[0] = eb[1] * ec[2] - eb[2] * ec[1], n[1] = eb[2] * ec[0] - eb[0] * ec[2], n[2] = eb[0] * ec[1] - eb[1] * ec[0];
        norm3(n);
        if ((dot3(n, ea) > 0) != (side == 1))
            for (int k = 0; k < 3; k++) n[k] = -n[k];
        double v[3] = {y[0] - s->p[0], y[1] - s->p[1], y[2] - s->p[2]};
        double d2 = dot3(v, v), dist = sqrt(d2);
        if (dist > 0) {
            for (int k = 0; k < 3; k++) l[k] = v[k] / dist;
            double cy = -dot3(l, n), cs = dot3(s->n, l), cell = sqrt(dot3(ea, ea));
            if (cy > 0 && cs > 0 && !occluded(L, s->p, l, dist - 1e-3 * cell)) {
                double pdf = lum3(em->rad) / L->em_power * d2 / cy, w;
                nee_f(B, wo, l, pdf, go_d, go_s, true, f, &w);
                for (int k = 0; k < 3; k++) out[k] += f[k] * em->rad[k] * cs * w;
            }
        }
    }
}

/* ---- the path ------------------------------------------------------------------------ */

/* Where a walk through glass goes on: the glass cell, its cells' size, the
 * glass's index and roughness. */
typedef struct glass_at {
    uint32_t inst, cell[3];
    double csize, ior, alpha;
} glass_at;

/* A refraction into the glass of surface s (hit h, met along ro + t rd, its
 * BSDF B) towards wi: the colour at entry into thr, ro just inside the face,
 * rd = wi, and *g the cell the walk starts from (vx__path, vx__glass_lobe). */
static void glass_enter(const vx__light* L, const vx__surface* s, const vx_render_ray_hit* h, const bsdf* B,
                        const double wi[3], double ro[3], double rd[3], double thr[3], glass_at* g) {
    for (int k = 0; k < 3; k++) thr[k] *= B->alb[k];
    for (int k = 0; k < 3; k++) ro[k] = ro[k] + rd[k] * h->t - s->n[k] * 1e-6 * h->cell_size;
    memcpy(rd, wi, 3 * sizeof *rd);
    g->inst = h->instance, memcpy(g->cell, h->cell, sizeof g->cell);
    g->csize = h->cell_size, g->ior = vx__light_material(L, s->material)->ior, g->alpha = B->alpha;
}

bool vx__path(const vx__light* L, const double o[3], const double d[3], uint32_t bounces, bool indirect, vx__rng* rng,
              double out[3]) {
    double thr[3] = {1, 1, 1}, acc[3] = {0, 0, 0}, ro[3], rd[3];
    memcpy(ro, o, sizeof ro);
    memcpy(rd, d, sizeof rd);
    bool primary_hit = false;
    double prev_pdf = 0; /* the BSDF density of the last direction; 0: a delta or the camera (full weight) */
    uint32_t depth = 0;  /* diffuse and glossy bounces so far (metal events not counted) */
    uint32_t metal = 0;  /* metal events so far, up to VX__METAL_CHAIN (light.h) */
    int vertex = 0;      /* surfaces met, glass events included */
    /* Inside glass: the walk (glass_walk) the next event runs from ro along
     * rd, in glass cell g_cell of instance g_inst (after a refraction into
     * the glass, or a bounce off an opaque voxel met from inside it). */
    bool in_glass = false;
    glass_at g = {.ior = 1.5};
    for (int events = 0; events < 1024; events++) {
        vx_render_ray_hit h;
        bool hit, stopped = false; /* stopped: h is an opaque voxel's face met from inside glass, at ro */
        if (in_glass) {
            glass_stop st;
            double p[3] = {ro[0], ro[1], ro[2]};
            int wr = glass_walk(L, g.inst, g.cell, g.csize, g.ior, g.alpha, p, rd, rng, thr, ro, &st);
            /* no light is sampled inside glass (a shadow ray starting in a glass voxel meets it), so
             * what the path finds after a walk counts whole, as after a delta event */
            prev_pdf = 0;
            if (wr == WALK_ABSORBED) break;
            if (wr == WALK_STOP) {
                h = st.h, hit = stopped = true;
                memcpy(ro, st.p, sizeof ro);
                g.inst = st.inst, memcpy(g.cell, st.cell, sizeof g.cell);
            } else {
                in_glass = false;
                hit = vx_render_cast(L->caster, ro, rd, INFINITY, false, &h);
            }
        } else {
            hit = vx_render_cast(L->caster, ro, rd, INFINITY, false, &h);
        }
        double le[3], lp = 0;
        bool skip = indirect && vertex == 0; /* the camera's own ray: the pipeline shows the first surface */
        bool skip_lights = indirect && vertex <= 1; /* and the direct pass the lights on it */
        if (!stopped && L->light_count && area_hit(L, ro, rd, hit ? h.t : INFINITY, le, &lp) >= 0) {
            double w = prev_pdf > 0 ? mis(prev_pdf, lp) : 1;
            if (!skip_lights)
                for (int k = 0; k < 3; k++) acc[k] += thr[k] * le[k] * w;
            break;
        }
        if (!hit) {
            if (!skip) {
                double sky[3];
                vx__sky(L, rd, sky);
                for (int k = 0; k < 3; k++) acc[k] += thr[k] * sky[k];
            }
            /* the cones of directional lights (from the first surface: the direct pass's in indirect mode) */
            for (uint32_t i = 0; i < L->light_count && !(indirect && vertex <= 1); i++) {
                const vx_light* li = &L->lights[i];
                if (li->type != VX_LIGHT_DIRECTIONAL || !(li->angular_diameter >= CONE_MIN) ||
                    (li->flags & VX_LIGHT_FROM_VOXELS))
                    continue;
                double ax[3], omc, s2;
                cone_of(li, ax, &omc, &s2, le);
                if (!in_cone(ax, s2, rd)) continue;
                double w = prev_pdf > 0 ? mis(prev_pdf, 1 / (2 * pi * omc)) : 1;
                for (int k = 0; k < 3; k++) acc[k] += thr[k] * le[k] * w;
            }
            break;
        }
        if (vertex == 0) primary_hit = true;
        vx__surface s;
        vx__surface_of(L, ro, rd, &h, &s);
        if (!skip && !(skip_lights && L->voxel_lights) && (s.emit[0] > 0 || s.emit[1] > 0 || s.emit[2] > 0)) {
            double w = 1;
            if (prev_pdf > 0 && L->em_count) {
                double cy = fabs(dot3(rd, s.n));
                w = cy > 0 ? mis(prev_pdf, lum3(s.emit) / L->em_power * h.t * h.t / cy) : 0;
            }
            for (int k = 0; k < 3; k++) acc[k] += thr[k] * s.emit[k] * w;
        }
        vertex++;
        bsdf B;
        bsdf_of(L, &s, rng, &B);
        double wo[3] = {-rd[0], -rd[1], -rd[2]};
        if (B.kind == B_GLASS) {
            /* a delta (or rough) interface event: no light sampling, no bounce counted */
            double wi[3], w;
            bool refr;
            if (!dielectric(s.n, wo, B.eta, B.alpha, rng, wi, &refr, &w)) break;
            prev_pdf = 0;
            /* glass at the camera's first surface: the pipeline's direct pass gives only the glass's Lambert
             * share, so what the glass reflects and transmits is this path's whole (render/pipeline.h) */
            if (vertex == 1) indirect = false;
            for (int k = 0; k < 3; k++) thr[k] *= w;
            if (!refr) {
                memcpy(ro, s.p, sizeof ro);
                memcpy(rd, wi, sizeof rd);
                continue;
            }
            if (!L->inst_inv) break;
            glass_enter(L, &s, &h, &B, wi, ro, rd, thr, &g);
            in_glass = true; /* the walk runs at the next event */
            continue;
        }
        /* Which lobes go on: the Lambert lobe (and a Lambert vertex) while bounces are left; a metal's
         * specular lobe also while metal events are (light.h VX__METAL_CHAIN: a metal event, the specular
         * lobe of a metal record whatever its roughness, does not spend a bounce, as the probe modes'
         * chain of metal events does not) */
        bool glossy = B.kind == B_GLOSSY, go_d = depth < bounces, go_s = go_d || (glossy && metal < VX__METAL_CHAIN);
        if (!stopped) { /* inside glass no light is sampled (above) */
            double dl[3];
            nee(L, &s, &B, wo, rng, go_d, go_s, indirect && vertex == 1, dl);
            for (int k = 0; k < 3; k++) acc[k] += thr[k] * dl[k];
        }
        if (!go_s) break;
        double w[3];
        bool spec = false;
        if (glossy ? !glossy_sample(&B, wo, rng, rd, w, &prev_pdf, &spec) : !bsdf_sample(&B, wo, rng, rd, w, &prev_pdf))
            break;
        if (spec && metal < VX__METAL_CHAIN) {
            metal++; /* (a handful at most: no roulette) */
            for (int k = 0; k < 3; k++) thr[k] *= w[k];
        } else {
            if (!go_d) break; /* the Lambert lobe, drawn where only the specular one goes on (nee: whole) */
            for (int k = 0; k < 3; k++) thr[k] *= w[k];
            depth++;
            if (depth >= VX__RR_DEPTH) {
                double q = fmin(0.95, fmax(thr[0], fmax(thr[1], thr[2])));
                if (!(vx__rng_next(rng) < q)) break;
                for (int k = 0; k < 3; k++) thr[k] /= q;
            }
        }
        if (thr[0] == 0 && thr[1] == 0 && thr[2] == 0) break;
        memcpy(ro, s.p, sizeof ro);
        in_glass = stopped; /* a bounce off a voxel set in glass goes back into the glass */
    }
    memcpy(out, acc, sizeof acc);
    return primary_hit;
}

int vx__glass_lobe(const vx__light* L, double ro[3], double rd[3], vx_render_ray_hit* h, vx__surface* s, vx__rng* rng,
                   double thr[3]) {
    bsdf B;
    bsdf_of(L, s, rng, &B);
    if (B.kind != B_GLASS) return -1;
    thr[0] = thr[1] = thr[2] = 1;
    for (int events = 0; events < 64; events++) { /* vx__path's glass events, the walk at once */
        double wo[3] = {-rd[0], -rd[1], -rd[2]}, wi[3], w;
        bool refr;
        if (!dielectric(s->n, wo, B.eta, B.alpha, rng, wi, &refr, &w)) break;
        for (int k = 0; k < 3; k++) thr[k] *= w;
        if (!refr) {
            memcpy(ro, s->p, 3 * sizeof *ro);
            memcpy(rd, wi, sizeof wi);
        } else {
            if (!L->inst_inv) break;
            glass_at g;
            glass_enter(L, s, h, &B, wi, ro, rd, thr, &g);
            double p[3] = {ro[0], ro[1], ro[2]};
            glass_stop st;
            int wr = glass_walk(L, g.inst, g.cell, g.csize, g.ior, g.alpha, p, rd, rng, thr, ro, &st);
            if (wr == WALK_ABSORBED) break;
            if (wr == WALK_STOP) {
                *h = st.h;
                memcpy(ro, st.p, 3 * sizeof *ro);
                vx__surface_of(L, ro, rd, h, s);
                return 2;
            }
        }
        if (!vx_render_cast(L->caster, ro, rd, INFINITY, false, h)) return 0;
        vx__surface_of(L, ro, rd, h, s);
        bsdf_of(L, s, rng, &B);
        if (B.kind != B_GLASS) return 1;
    }
    thr[0] = thr[1] = thr[2] = 0;
    return 0;
}

bool vx__metal_of(const vx__light* L, const vx__surface* s, const double d[3], double kd[3], double fl[3]) {
    if (vx__light_material(L, s->material)->type != VX_MATERIAL_METAL) return false;
    bsdf B;
    bsdf_of(L, s, NULL, &B); /* (metal draws no number) */
    double wo[3] = {-d[0], -d[1], -d[2]}, pdf;
    memcpy(kd, B.kd, sizeof B.kd);
    bsdf_eval(&B, wo, L->light_dir, fl, &pdf);
    return true;
}

bool vx__metal_spec(const vx__light* L, const vx__surface* s, const double d[3], vx__rng* rng, double wi[3],
                    double w[3]) {
    bsdf B;
    bsdf_of(L, s, NULL, &B);
    /* the specular lobe alone: bsdf_sample's visible normals with probability 1 (its three numbers all
     * drawn, as probe.comp's), f the GGX term and the pdf the lobe's, so w = F G2 / G1(wo) */
    B.ps = 1;
    B.kd[0] = B.kd[1] = B.kd[2] = 0;
    double wo[3] = {-d[0], -d[1], -d[2]}, pdf;
    return bsdf_sample(&B, wo, rng, wi, w, &pdf);
}
