/* probes/light.c - the lighting model (see probes.h) shared by the baker and
 * the CPU renderer, on the CPU reference tracer's double-precision rays. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "probes/probes_internal.h"

static const double pi = 3.14159265358979323846;

void vx__light_init(vx__light* L, const vx_render_caster* c, const vx_svo_scene* s, const double light_dir[3],
                    const double sun[3], bool no_sun, const double sky[3], bool black_sky) {
    memset(L, 0, sizeof *L);
    L->caster = c;
    L->scene = s;
    const vx_probe_bake_desc D = vx_probe_bake_desc_defaults(); /* the light's defaults */
    double ld[3] = {D.light_dir[0], D.light_dir[1], D.light_dir[2]};
    if (light_dir && (light_dir[0] || light_dir[1] || light_dir[2])) memcpy(ld, light_dir, sizeof ld);
    double l = sqrt(ld[0] * ld[0] + ld[1] * ld[1] + ld[2] * ld[2]);
    for (int k = 0; k < 3; k++) L->light_dir[k] = ld[k] / l;
    for (int k = 0; k < 3; k++) {
        L->sun[k] = no_sun ? 0 : (sun && (sun[0] || sun[1] || sun[2]) ? sun[k] : D.sun[k]);
        L->sky[k] = black_sky ? 0 : (sky && (sky[0] || sky[1] || sky[2]) ? sky[k] : D.sky[k]);
    }
    for (uint32_t i = 0; s && i < s->material_count; i++) {
        const vx_svo_material* m = &s->materials[i];
        const char* type = vx_svo_material_get(m, "_type");
        if (m->id >= 256 || !type || strcmp(type, "_emit")) continue;
        const char* e = vx_svo_material_get(m, "_emit");
        const char* f = vx_svo_material_get(m, "_flux");
        double ev = e ? strtod(e, NULL) : 0, fv = f ? strtod(f, NULL) : 0;
        if (!isfinite(ev) || ev < 0) ev = 0;
        if (!isfinite(fv) || fv < 0) fv = 0;
        if (fv > 16) fv = 16;
        L->emit[m->id] = ev * pow(2.0, fv);
    }
}

void vx__surface_of(const vx__light* L, const double o[3], const double d[3], const vx_render_ray_hit* h,
                    vx__surface* s) {
    double pmax = 0;
    for (int k = 0; k < 3; k++) {
        s->p[k] = o[k] + d[k] * h->t;
        pmax = fmax(pmax, fabs(s->p[k]));
    }
    /* off the surface so the next ray does not start inside the hit voxel */
    double eps = h->cell_size * 1e-6 + pmax * 1e-12;
    for (int k = 0; k < 3; k++) s->n[k] = h->normal[k], s->p[k] += h->normal[k] * eps;
    uint32_t c = h->rgba;
    s->albedo[0] = (c & 0xFF) / 255.0, s->albedo[1] = ((c >> 8) & 0xFF) / 255.0, s->albedo[2] = ((c >> 16) & 0xFF) / 255.0;
    double e = h->palette < 256 ? L->emit[h->palette] : 0;
    for (int k = 0; k < 3; k++) s->emit[k] = s->albedo[k] * e;
}

void vx__direct(const vx__light* L, const vx__surface* s, double out[3]) {
    out[0] = out[1] = out[2] = 0;
    double ndl = s->n[0] * L->light_dir[0] + s->n[1] * L->light_dir[1] + s->n[2] * L->light_dir[2];
    if (ndl <= 0 || !(L->sun[0] > 0 || L->sun[1] > 0 || L->sun[2] > 0)) return;
    if (vx_render_cast(L->caster, s->p, L->light_dir, INFINITY, true, NULL)) return;
    for (int k = 0; k < 3; k++) out[k] = s->albedo[k] / pi * L->sun[k] * ndl;
}

void vx__cosine_dir(const double n[3], double u1, double u2, double d[3]) {
    /* Duff et al. 2017 branchless orthonormal basis */
    double sg = copysign(1.0, n[2]);
    double a = -1.0 / (sg + n[2]), b = n[0] * n[1] * a;
    double t[3] = {1 + sg * n[0] * n[0] * a, sg * b, -sg * n[0]};
    double bt[3] = {b, sg + n[1] * n[1] * a, -n[1]};
    double r = sqrt(u1), phi = 2 * pi * u2;
    double x = r * cos(phi), y = r * sin(phi), z = sqrt(fmax(0, 1 - u1));
    for (int k = 0; k < 3; k++) d[k] = x * t[k] + y * bt[k] + z * n[k];
}

void vx__path(const vx__light* L, const double o[3], const double d[3], uint32_t bounces, vx__rng* rng,
              double out[3]) {
    double thr[3] = {1, 1, 1}, acc[3] = {0, 0, 0};
    double ro[3], rd[3];
    memcpy(ro, o, sizeof ro);
    memcpy(rd, d, sizeof rd);
    for (uint32_t depth = 0;; depth++) {
        vx_render_ray_hit h;
        if (!vx_render_cast(L->caster, ro, rd, INFINITY, false, &h)) {
            for (int k = 0; k < 3; k++) acc[k] += thr[k] * L->sky[k];
            break;
        }
        vx__surface s;
        vx__surface_of(L, ro, rd, &h, &s);
        double dl[3];
        vx__direct(L, &s, dl);
        for (int k = 0; k < 3; k++) acc[k] += thr[k] * (s.emit[k] + dl[k]);
        if (depth >= bounces) break;
        double u1 = vx__rng_next(rng), u2 = vx__rng_next(rng);
        vx__cosine_dir(s.n, u1, u2, rd);
        memcpy(ro, s.p, sizeof ro);
        for (int k = 0; k < 3; k++) thr[k] *= s.albedo[k];
        if (thr[0] == 0 && thr[1] == 0 && thr[2] == 0) break;
    }
    memcpy(out, acc, sizeof acc);
}
