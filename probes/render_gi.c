/* probes/render_gi.c - the CPU renderer that uses the probes (diffuse GI
 * from the irradiance probes, DDGI style) and the path-traced reference
 * with the same lighting model. */
#include <math.h>
#include <pthread.h>
#include <string.h>

#include "probes/probes_internal.h"
#include "render/trace.h"

static const double pi = 3.14159265358979323846;

/* Bilinear sample of a bordered n x n map (ch channels) at direction d. */
static void sample_half(const uint16_t* map, uint32_t n, uint32_t ch, const double d[3], double* out) {
    double uv[2];
    vx_probe_oct_encode(d, uv);
    /* interior texel i is centred at (uv+1)/2*n = i + 0.5, stored at i + 1 */
    double x = (uv[0] + 1) * 0.5 * n + 0.5, y = (uv[1] + 1) * 0.5 * n + 0.5;
    double fx = floor(x), fy = floor(y);
    uint32_t x0 = (uint32_t)fx, y0 = (uint32_t)fy;
    if (x0 > n) x0 = n;
    if (y0 > n) y0 = n;
    double ax = x - x0, ay = y - y0;
    for (uint32_t c = 0; c < ch; c++) {
        double v00 = vx_probe_half_to_float(map[(y0 * (n + 2) + x0) * ch + c]);
        double v10 = vx_probe_half_to_float(map[(y0 * (n + 2) + x0 + 1) * ch + c]);
        double v01 = vx_probe_half_to_float(map[((y0 + 1) * (n + 2) + x0) * ch + c]);
        double v11 = vx_probe_half_to_float(map[((y0 + 1) * (n + 2) + x0 + 1) * ch + c]);
        out[c] = (v00 * (1 - ax) + v10 * ax) * (1 - ay) + (v01 * (1 - ax) + v11 * ax) * ay;
    }
}

static void sample_f32(const float* map, uint32_t n, uint32_t ch, const double d[3], double* out) {
    double uv[2];
    vx_probe_oct_encode(d, uv);
    double x = (uv[0] + 1) * 0.5 * n + 0.5, y = (uv[1] + 1) * 0.5 * n + 0.5;
    uint32_t x0 = (uint32_t)floor(x), y0 = (uint32_t)floor(y);
    if (x0 > n) x0 = n;
    if (y0 > n) y0 = n;
    double ax = x - x0, ay = y - y0;
    for (uint32_t c = 0; c < ch; c++) {
        double v00 = map[(y0 * (n + 2) + x0) * ch + c], v10 = map[(y0 * (n + 2) + x0 + 1) * ch + c];
        double v01 = map[((y0 + 1) * (n + 2) + x0) * ch + c], v11 = map[((y0 + 1) * (n + 2) + x0 + 1) * ch + c];
        out[c] = (v00 * (1 - ax) + v10 * ax) * (1 - ay) + (v01 * (1 - ax) + v11 * ax) * ay;
    }
}

/* DDGI irradiance with an explicit view direction for the surface bias
 * (vd: unit direction from the eye to p, may be NULL). */
static void irradiance_at(const vx_probe_set* ps, const double p_in[3], const double n[3], const double* vd,
                          double out[3]) {
    double smin = fmin(ps->spacing[0], fmin(ps->spacing[1], ps->spacing[2]));
    /* move the lookup off the surface so the probes' distance moments see it
     * in front of the nearest wall (DDGI's normal and view bias) */
    double p[3];
    for (int k = 0; k < 3; k++) p[k] = p_in[k] + (n[k] * 0.2 - (vd ? vd[k] : 0) * 0.1) * smin;
    int64_t base[3];
    double alpha[3];
    vx__probe_cage(ps, p, base, alpha);
    double sum[3] = {0, 0, 0}, wsum = 0;
    size_t ni = vx__bsq(VX_PROBE_IRR_RES) * 3, nm = vx__bsq(VX_PROBE_DIST_RES) * 2;
    for (int c = 0; c < 8; c++) {
        int64_t idx[3];
        double tri = 1;
        bool skip = false;
        for (int k = 0; k < 3; k++) {
            int o = (c >> k) & 1;
            idx[k] = base[k] + o;
            if (idx[k] >= (int64_t)ps->grid[k]) skip = true;
            tri *= o ? alpha[k] : 1 - alpha[k];
        }
        if (skip) continue;
        size_t pi = (size_t)idx[0] + ps->grid[0] * ((size_t)idx[1] + ps->grid[1] * (size_t)idx[2]);
        const vx_probe* pr = &ps->probes[pi];
        if (pr->state == VX_PROBE_DISABLED || pi < ps->first || pi >= (size_t)ps->first + ps->count) continue;
        size_t k = pi - ps->first;
        double to[3], r = 0;
        for (int q = 0; q < 3; q++) to[q] = pr->pos[q] - p[q], r += to[q] * to[q];
        r = sqrt(r);
        double dir[3] = {0, 0, 1};
        if (r > 0)
            for (int q = 0; q < 3; q++) dir[q] = to[q] / r;
        /* smooth backface weight */
        double wn = 0.5 * (dir[0] * n[0] + dir[1] * n[1] + dir[2] * n[2] + 1);
        double w = wn * wn + 0.2;
        /* Chebyshev visibility: is p farther from the probe than what it sees there? */
        double back[3] = {-dir[0], -dir[1], -dir[2]}, mom[2];
        sample_f32(ps->moments + nm * k, VX_PROBE_DIST_RES, 2, back, mom);
        if (r > mom[0]) {
            double var = fabs(mom[1] - mom[0] * mom[0]);
            double dd = r - mom[0];
            double cheb = var / (var + dd * dd);
            w *= fmax(cheb * cheb * cheb, 0.0);
        }
        w = fmax(w, 1e-6);
        /* crush tiny weights (DDGI): keeps light from leaking at low weights */
        if (w < 0.2) w = w * w * w / (0.2 * 0.2);
        w *= tri;
        double e[3];
        sample_half(ps->irradiance + ni * k, VX_PROBE_IRR_RES, 3, n, e);
        for (int q = 0; q < 3; q++) sum[q] += w * e[q];
        wsum += w;
    }
    for (int q = 0; q < 3; q++) out[q] = wsum > 0 ? sum[q] / wsum : 0;
}

void vx_probe_irradiance(const vx_probe_set* ps, const double p[3], const double n[3], double out[3]) {
    irradiance_at(ps, p, n, NULL, out);
}

const char* vx_probe_render_mode_name(vx_probe_render_mode m) {
    switch (m) {
    case VX_PROBE_RENDER_GI: return "gi";
    case VX_PROBE_RENDER_PATHTRACE: return "pathtrace";
    case VX_PROBE_RENDER_INDIRECT: return "gi-indirect";
    case VX_PROBE_RENDER_PT_INDIRECT: return "pathtrace-indirect";
    case VX_PROBE_RENDER_LIGHTFIELD: return "lightfield";
    case VX_PROBE_RENDER_LF_INDIRECT: return "lightfield-indirect";
    }
    return "?";
}

bool vx_probe_render_mode_parse(const char* s, vx_probe_render_mode* out) {
    for (int m = 0; m < VX_PROBE_RENDER_MODE_COUNT; m++)
        if (!strcmp(s, vx_probe_render_mode_name((vx_probe_render_mode)m))) {
            *out = (vx_probe_render_mode)m;
            return true;
        }
    return false;
}

typedef struct rjob {
    const vx__frame* f;
    const vx__light* L;
    const vx_probe_set* ps;
    vx_probe_render_mode mode;
    bool jitter;
    uint32_t spp, bounces;
    uint64_t seed;
    const vx__lf* lf;
    float* pixels;
    const uint8_t* rows; /* NULL: all */
    uint32_t next_row;
    vx__lf_counts counts;
    pthread_mutex_t mu;
} rjob;

static bool is_lf(vx_probe_render_mode m) { return m == VX_PROBE_RENDER_LIGHTFIELD || m == VX_PROBE_RENDER_LF_INDIRECT; }

bool vx_probe_render_mode_uses_probes(vx_probe_render_mode m) {
    return m == VX_PROBE_RENDER_GI || m == VX_PROBE_RENDER_INDIRECT || is_lf(m);
}

vx_result vx__prender_setup(const vx_svo_scene* s, const vx_probe_set* ps, bool complete,
                            const vx_probe_render_desc* desc, vx__prender* out, vx_error* err) {
    vx__prender* P = out;
    memset(P, 0, sizeof *P);
    P->d = desc ? *desc : (vx_probe_render_desc){0};
    vx_probe_render_mode m = P->d.mode;
    if ((unsigned)m >= VX_PROBE_RENDER_MODE_COUNT) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "unknown mode");
    P->uses_probes = vx_probe_render_mode_uses_probes(m);
    P->lightfield = is_lf(m);
    if (P->uses_probes && !complete)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "mode %s needs a complete probe set",
                       vx_probe_render_mode_name(m));
    vx_render_desc base = P->d.base ? *P->d.base : (vx_render_desc){0};
    base.mode = VX_RENDER_COLOR;
    base.spp = 1;
    base.lod = false;
    vx_svo_scene_world_bounds(s, P->lo, P->hi);
    vx_result r = vx__frame_setup(P->lo, P->hi, &base, &P->f, err);
    if (r) return r;
    if ((r = vx__light_init(&P->L, NULL, s, ps ? ps->light_dir : base.light_dir, NULL, false, NULL, false, err)))
        return r;
    if (ps)
        for (int k = 0; k < 3; k++) P->L.sun[k] = ps->sun[k], P->L.sky[k] = ps->sky[k];
    /* the frame's lights replace the sun (as in the pass pipeline) */
    if (P->d.light_count)
        for (int k = 0; k < 3; k++) P->L.sun[k] = 0;
    bool pt = m == VX_PROBE_RENDER_PATHTRACE || m == VX_PROBE_RENDER_PT_INDIRECT;
    if (pt && P->d.sky && P->d.sky->type != VX_SKY_DEFAULT) {
        const vx_sky* k = P->d.sky;
        const vx_sky_texels* t = P->d.sky_map;
        if ((r = vx_sky_validate(k, err))) {
            vx__light_free(&P->L);
            return r;
        }
        if (k->type == VX_SKY_ENVMAP &&
            (!t || !t->rgb || !t->width || !t->height || t->width > 65536 || t->height > 65536)) {
            vx__light_free(&P->L);
            return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "sky: the environment map '%s' has no texels", k->path);
        }
        if (k->type == VX_SKY_CONSTANT) memcpy(P->L.sky, k->color, sizeof P->L.sky); /* uniform: as before */
        else P->L.sky_dir = *k, P->L.sky_map = t ? *t : (vx_sky_texels){0};
    }
    if ((r = vx__light_add(&P->L, P->d.lights, P->d.light_count, pt, err))) {
        vx__light_free(&P->L);
        return r;
    }
    P->spp = P->d.spp ? P->d.spp : (P->uses_probes && !P->lightfield ? 1 : 16);
    P->bounces = P->d.bounces ? P->d.bounces : (ps ? ps->bounces + 1 : 2);
    return VX_OK;
}

uint32_t vx__prender_rows(const vx_probe_render_desc* d, uint32_t height) {
    if (!d->rows) return height;
    uint32_t n = 0;
    for (uint32_t y = 0; y < height; y++) n += d->rows[y] != 0;
    return n;
}

static bool has_direct(vx_probe_render_mode m) {
    return m == VX_PROBE_RENDER_GI || m == VX_PROBE_RENDER_PATHTRACE || m == VX_PROBE_RENDER_LIGHTFIELD;
}

void vx__prender_free(vx__prender* P) { vx__light_free(&P->L); }

static void render_pixel(const rjob* J, uint32_t x, uint32_t y, float* px, vx__lf_counts* cnt) {
    const vx__frame* f = J->f;
    double acc[4] = {0};
    for (uint32_t s = 0; s < J->spp; s++) {
        vx__rng rng = vx__rng_make(J->seed, 0x9000000000ull + y, x, s);
        double ox = 0, oy = 0;
        if (J->jitter) ox = vx__rng_next(&rng) - 0.5, oy = vx__rng_next(&rng) - 0.5;
        double u = ((x + 0.5 + ox) / f->width) * 2 - 1, v = 1 - ((y + 0.5 + oy) / f->height) * 2;
        double P[3], o[3], d[3];
        vx__frame_ray(f, u, v, P, o, d);
        double c[3] = {0, 0, 0};
        if (J->mode == VX_PROBE_RENDER_PATHTRACE || J->mode == VX_PROBE_RENDER_PT_INDIRECT) {
            acc[3] += vx__path(J->L, o, d, J->bounces, J->mode == VX_PROBE_RENDER_PT_INDIRECT, &rng, c);
            for (int k = 0; k < 3; k++) acc[k] += c[k];
            continue;
        }
        vx_render_ray_hit h;
        bool hit = vx_render_cast(J->L->caster, o, d, INFINITY, false, &h);
        if (!hit) {
            if (has_direct(J->mode)) memcpy(c, J->L->sky, sizeof c);
        } else {
            vx__surface sf;
            vx__surface_of(J->L, o, d, &h, &sf);
            bool full = has_direct(J->mode);
            if (full) for (int k = 0; k < 3; k++) c[k] += sf.emit[k];
            /* glass (its glass lobe): the surface the path tracer's events through it reach, shaded whole, in
             * the indirect modes too (the pass pipeline's direct pass gives only the glass's Lambert share:
             * render/pipeline.h); a path out of the scene brings the sky. */
            double thr[3] = {1, 1, 1};
            int at = J->L->materials ? vx__glass_lobe(J->L, o, d, &h, &sf, &rng, thr) : -1;
            bool whole = at > 0;
            /* Metal (the first metal surface met, directly or through glass; not from inside glass): its
             * specular lobe's one direction by the path tracer's sampler, and the surface met there (glass
             * events on the way) shaded whole times the sample's weight, in the indirect modes too (the pass
             * pipeline's direct pass gives only the metal's own lights); the sky on a miss. Each metal surface
             * of the chain itself: its direct light by the BRDF (the full modes; a metal after the first is
             * shaded whole), its Lambert lobe the probes' light times kd. A metal the lobe meets is one more
             * event of the chain, its own lobe followed in turn (stop 74: with one event, a mirror facing a
             * metal wall came out 0.22x the path tracer's), up to VX__METAL_CHAIN events (light.h says why that
             * number); a metal met past them, or from inside glass, is shaded by its own BRDF and kd (below).
             * The chain stops where its weight is zero. Both lobes are shaded in every sample, not one picked
             * as vx__path does: the Lambert lobe's light is a look-up without a ray, so a pick would only add
             * the choice's noise. The order of events and numbers is probe.comp render()'s: every lobe's
             * direction and the glass events after it, in the chain's order, then the metal surfaces' light
             * field samples in that order, then the last surface's. */
            enum { MC = VX__METAL_CHAIN };
            int nm = 0; /* the chain's metal events so far */
            vx__surface ms[MC];
            double m_d[MC][3], m_thr[MC][3], m_kd[MC][3], m_fl[MC][3];
            bool m_full[MC];
            while (nm < MC && (at == -1 || at == 1) && J->L->materials &&
                   vx__metal_of(J->L, &sf, d, m_kd[nm], m_fl[nm])) {
                m_full[nm] = full || whole, ms[nm] = sf;
                memcpy(m_d[nm], d, sizeof m_d[nm]), memcpy(m_thr[nm], thr, sizeof m_thr[nm]);
                nm++;
                if (whole)
                    for (int k = 0; k < 3; k++) c[k] += thr[k] * sf.emit[k];
                whole = true;
                double wi[3], w[3];
                if (!vx__metal_spec(J->L, &sf, d, &rng, wi, w)) {
                    at = 0, thr[0] = thr[1] = thr[2] = 0;
                    break;
                }
                for (int k = 0; k < 3; k++) thr[k] *= w[k];
                if (!(thr[0] > 0 || thr[1] > 0 || thr[2] > 0)) { /* (nothing more reaches the eye) */
                    at = 0, thr[0] = thr[1] = thr[2] = 0;
                    break;
                }
                memcpy(o, sf.p, sizeof o);
                memcpy(d, wi, sizeof d);
                if (!vx_render_cast(J->L->caster, o, d, INFINITY, false, &h)) {
                    at = 0;
                    break;
                }
                vx__surface_of(J->L, o, d, &h, &sf);
                double tg[3] = {1, 1, 1};
                at = vx__glass_lobe(J->L, o, d, &h, &sf, &rng, tg);
                for (int k = 0; k < 3; k++) thr[k] *= tg[k];
                if (at < 0) at = 1;
            }
            if (at == 0) {
                double sky[3];
                vx__sky(J->L, d, sky);
                for (int k = 0; k < 3; k++) c[k] += thr[k] * sky[k];
            }
            /* round r < nm the chain's r-th metal surface, round nm the surface reached (a scene without metal:
             * that round alone, as before the metal lobes) */
            for (int r = 0; r <= nm; r++) {
                bool m = r < nm;
                if (!m && at == 0) break;
                if (!m && whole) {
                    full = true;
                    for (int k = 0; k < 3; k++) c[k] += thr[k] * sf.emit[k];
                }
                const vx__surface* x = m ? &ms[r] : &sf;
                const double *xd = m ? m_d[r] : d, *tk = m ? m_thr[r] : thr, *wl = m ? m_kd[r] : sf.albedo;
                const double* fl = m ? m_fl[r] : NULL;
                /* a metal the chain reached past its last event, or from inside glass: its own BRDF towards the
                 * sun and its Lambert lobe's kd, no lobe (shaded as a diffuse surface, its whole colour lit by
                 * the sun, the demo island's statue came out 5-10x the path tracer's) */
                double s_kd[3], s_fl[3];
                bool xm = m || (nm > 0 && vx__metal_of(J->L, &sf, d, s_kd, s_fl));
                if (!m && xm) wl = s_kd, fl = s_fl;
                if ((m ? m_full[r] : full) && (m || at != 2)) { /* (no light is sampled inside glass) */
                    double dl[3];
                    if (xm) vx__direct_f(J->L, x, fl, dl);
                    else vx__direct(J->L, x, dl);
                    for (int k = 0; k < 3; k++) c[k] += tk[k] * dl[k];
                }
                if (xm && !(wl[0] > 0 || wl[1] > 0 || wl[2] > 0)) continue; /* (a pure metal: no Lambert lobe) */
                if (J->mode == VX_PROBE_RENDER_GI || J->mode == VX_PROBE_RENDER_INDIRECT) {
                    double e[3];
                    irradiance_at(J->ps, x->p, x->n, xd, e);
                    for (int k = 0; k < 3; k++) c[k] += tk[k] * wl[k] / pi * e[k];
                } else if (is_lf(J->mode)) {
                    double nd[3], li[3];
                    vx__cosine_dir(x->n, vx__rng_next(&rng), vx__rng_next(&rng), nd);
                    vx__lf_radiance(J->lf, x->p, nd, li, cnt);
                    for (int k = 0; k < 3; k++) c[k] += tk[k] * wl[k] * li[k];
                }
            }
            acc[3] += 1;
        }
        for (int k = 0; k < 3; k++) acc[k] += c[k];
    }
    for (int k = 0; k < 4; k++) px[k] = (float)(acc[k] / J->spp);
}

static void* rworker(void* arg) {
    rjob* J = arg;
    vx__lf_counts cnt = {0};
    for (;;) {
        pthread_mutex_lock(&J->mu);
        uint32_t y = J->next_row++;
        pthread_mutex_unlock(&J->mu);
        if (y >= J->f->height) break;
        if (J->rows && !J->rows[y]) continue;
        for (uint32_t x = 0; x < J->f->width; x++)
            render_pixel(J, x, y, &J->pixels[4 * ((size_t)y * J->f->width + x)], &cnt);
    }
    pthread_mutex_lock(&J->mu);
    J->counts.rays += cnt.rays, J->counts.probe_traces += cnt.probe_traces, J->counts.texels += cnt.texels;
    J->counts.coarse_skips += cnt.coarse_skips, J->counts.hits += cnt.hits, J->counts.misses += cnt.misses;
    J->counts.fallbacks += cnt.fallbacks;
    pthread_mutex_unlock(&J->mu);
    return NULL;
}

vx_result vx_probe_render(const vx_svo_scene* s, const vx_probe_set* ps, const vx_probe_render_desc* desc,
                          vx_render_image* out, vx_error* err) {
    if (!s || !out) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    vx__prender P;
    vx_result r = vx__prender_setup(s, ps, ps && ps->first == 0 && ps->count == ps->probe_count, desc, &P, err);
    if (r) return r;
    const vx_probe_render_desc d = P.d;
    const vx__frame f = P.f;
    vx_render_caster* c = NULL;
    if ((r = vx_render_caster_create(s, NULL, &c, err))) {
        vx__prender_free(&P);
        return r;
    }
    P.L.caster = c;
    vx__lf lf = {.L = &P.L, .ps = ps};
    memcpy(lf.lo, P.lo, sizeof lf.lo), memcpy(lf.hi, P.hi, sizeof lf.hi);
    rjob J = {.f = &f, .L = &P.L, .ps = ps, .lf = &lf, .mode = d.mode, .seed = d.seed, .spp = P.spp,
              .bounces = P.bounces, .rows = d.rows, .jitter = P.spp > 1 && !d.pixel_centre};
    vx_render_image img = {.width = f.width, .height = f.height, .mode = VX_RENDER_COLOR};
    img.pixels = vx_calloc(NULL, (size_t)f.width * f.height, 16);
    if (!img.pixels) {
        vx_render_caster_destroy(c);
        vx__prender_free(&P);
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for a %ux%u image", f.width, f.height);
    }
    J.pixels = img.pixels;
    double t0 = vx_time_now();
    pthread_mutex_init(&J.mu, NULL);
    vx_run_threads(d.threads, rworker, &J);
    pthread_mutex_destroy(&J.mu);
    img.gpu_seconds = vx_time_now() - t0;
    if (d.stats)
        *d.stats = (vx_probe_render_stats){.rays = J.counts.rays, .probe_traces = J.counts.probe_traces,
                                           .texels = J.counts.texels, .coarse_skips = J.counts.coarse_skips,
                                           .hits = J.counts.hits, .misses = J.counts.misses,
                                           .fallbacks = J.counts.fallbacks};
    img.rays = (uint64_t)f.width * vx__prender_rows(&d, f.height) * J.spp;
    vx_render_caster_destroy(c);
    vx__prender_free(&P);
    *out = img;
    return VX_OK;
}
