/* probes/light.c - the lighting model (see probes.h) shared by the baker and
 * the CPU renderer, on the CPU reference tracer's double-precision rays. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "probes/probes_internal.h"

static const double pi = 3.14159265358979323846;

vx_result vx__light_init(vx__light* L, const vx_render_caster* c, const vx_svo_scene* s, const double light_dir[3],
                         const double sun[3], bool no_sun, const double sky[3], bool black_sky, vx_error* err) {
    memset(L, 0, sizeof *L);
    L->caster = c;
    L->scene = s;
    L->alloc = s ? s->alloc : NULL;
    const vx_probe_bake_desc D = vx_probe_bake_desc_defaults(); /* the light's defaults */
    double ld[3] = {D.light_dir[0], D.light_dir[1], D.light_dir[2]};
    if (light_dir && (light_dir[0] || light_dir[1] || light_dir[2])) memcpy(ld, light_dir, sizeof ld);
    double l = sqrt(ld[0] * ld[0] + ld[1] * ld[1] + ld[2] * ld[2]);
    for (int k = 0; k < 3; k++) L->light_dir[k] = ld[k] / l;
    for (int k = 0; k < 3; k++) {
        L->sun[k] = no_sun ? 0 : (sun && (sun[0] || sun[1] || sun[2]) ? sun[k] : D.sun[k]);
        L->sky[k] = black_sky ? 0 : (sky && (sky[0] || sky[1] || sky[2]) ? sky[k] : D.sky[k]);
    }
    L->diffuse = vx_material_default(VX_MATERIAL_DIFFUSE);
    vx_result r = s ? vx_svo_material_table_make(s, L->alloc, &L->mt, err) : VX_OK;
    if (r) return r;
    bool glass = false;
    for (uint32_t i = 0; i < L->mt.count; i++)
        glass |= L->mt.mats[i].type == VX_MATERIAL_GLASS && L->mt.mats[i].transmission > 0;
    L->materials = L->mt.specular;
    if (glass && s->instance_count) {
        L->inst_inv = vx_calloc(L->alloc, s->instance_count, 12 * sizeof(double));
        if (!L->inst_inv) {
            vx__light_free(L); /* nothing held on failure */
            return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %u instance maps", s->instance_count);
        }
        for (uint32_t i = 0; i < s->instance_count; i++) {
            double w[12];
            vx_svo_instance_world(s, &s->instances[i], w);
            if (!vx__affine_inverse(w, L->inst_inv + 12 * i)) memset(L->inst_inv + 12 * i, 0, 12 * sizeof(double));
        }
    }
    return VX_OK;
}

bool vx__light_voxel_radiance(const vx__light* L, const vx_svo_scene* s, const vx_svo_model* m, uint32_t attr,
                              double rad[3]) {
    const vx_material* mt = vx__light_material(L, vx_svo_attr_material(m, attr));
    if (!(mt->emission > 0)) return false;
    uint32_t c = m->attrs ? vx_svo_attr_rgba(s, m, attr) : 0xFFFFFFFFu;
    double rgb[3];
    for (int k = 0; k < 3; k++) rgb[k] = ((c >> (8 * k)) & 0xFF) / 255.0;
    vx_material_emitted(mt, rgb, rad);
    return true;
}

typedef struct em_ctx {
    vx__light* L;
    const vx_svo_model* m;
    double w[12];
    size_t cap;
    bool nomem;
} em_ctx;

static bool em_voxel(void* user, uint32_t x, uint32_t y, uint32_t z, uint32_t attr) {
    em_ctx* E = user;
    vx__light* L = E->L;
    const vx_svo_model* m = E->m;
    double rad[3];
    if (!vx__light_voxel_radiance(L, L->scene, m, attr, rad)) return true;
    if (!(rad[0] > 0 || rad[1] > 0 || rad[2] > 0)) return true;
    if (!vx_grow(L->alloc, (void**)&L->em, &E->cap, (size_t)L->em_count + 1, sizeof *L->em)) {
        E->nomem = true;
        return false;
    }
    vx__emitter* e = &L->em[L->em_count++];
    double p[3] = {x, y, z};
    vx__affine_apply(E->w, p, e->corner);
    for (int a = 0; a < 3; a++)
        for (int k = 0; k < 3; k++) e->axis[a][k] = E->w[4 * k + a];
    double area = 0;
    for (int a = 0; a < 3; a++) {
        const double *u = e->axis[(a + 1) % 3], *v = e->axis[(a + 2) % 3];
        double cx = u[1] * v[2] - u[2] * v[1], cy = u[2] * v[0] - u[0] * v[2], cz = u[0] * v[1] - u[1] * v[0];
        area += 2 * sqrt(cx * cx + cy * cy + cz * cz);
    }
    memcpy(e->rad, rad, sizeof rad);
    e->area = area;
    return true;
}

vx_result vx__light_add(vx__light* L, const vx_light* lights, uint32_t n, bool emitters, vx_error* err) {
    if (n && !lights) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "%u lights but no array", n);
    for (uint32_t i = 0; i < n; i++) {
        vx_result r = vx_light_validate(&lights[i], i, err);
        if (r) return r;
    }
    L->lights = lights, L->light_count = n;
    for (uint32_t i = 0; i < n; i++) L->voxel_lights |= (lights[i].flags & VX_LIGHT_FROM_VOXELS) != 0;
    const vx_svo_scene* s = L->scene;
    if (!emitters || !L->mt.emissive || !s) return VX_OK;
    em_ctx E = {.L = L};
    for (uint32_t i = 0; i < s->instance_count && !E.nomem; i++) {
        if (!vx_svo_instance_drawn(s, i)) continue;
        E.m = &s->models[s->instances[i].model];
        vx_svo_instance_world(s, &s->instances[i], E.w);
        vx_result r = vx_svo_decode_model(E.m, em_voxel, &E, err);
        if (r && !E.nomem) return r;
    }
    if (E.nomem || (L->em_count && !(L->em_cdf = vx_alloc(L->alloc, L->em_count * sizeof(double)))))
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %u emissive voxels", L->em_count);
    double acc = 0;
    for (uint32_t i = 0; i < L->em_count; i++) {
        const double* c = L->em[i].rad;
        acc += (0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]) * L->em[i].area;
        L->em_cdf[i] = acc;
    }
    for (uint32_t i = 0; i < L->em_count; i++) L->em_cdf[i] /= acc;
    L->em_power = acc;
    if (!(acc > 0) || !isfinite(acc)) L->em_count = 0; /* nothing to sample (colours without luminance) */
    return VX_OK;
}

void vx__sky(const vx__light* L, const double d[3], double out[3]) {
    if (L->sky_dir.type == VX_SKY_DEFAULT) memcpy(out, L->sky, sizeof L->sky);
    else vx_sky_radiance(&L->sky_dir, &L->sky_map, d, out);
}

void vx__light_free(vx__light* L) {
    vx_free(L->alloc, L->inst_inv);
    vx_free(L->alloc, L->em);
    vx_free(L->alloc, L->em_cdf);
    vx_svo_material_table_free(&L->mt);
    L->inst_inv = NULL, L->em = NULL, L->em_cdf = NULL, L->em_count = 0;
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
    s->material = h->material;
    s->cell = h->cell_size;
    vx_material_emitted(vx__light_material(L, s->material), s->albedo, s->emit);
}

void vx__direct_f(const vx__light* L, const vx__surface* s, const double f[3], double out[3]) {
    out[0] = out[1] = out[2] = 0;
    double ndl = s->n[0] * L->light_dir[0] + s->n[1] * L->light_dir[1] + s->n[2] * L->light_dir[2];
    if (ndl <= 0 || !(L->sun[0] > 0 || L->sun[1] > 0 || L->sun[2] > 0)) return;
    if (vx_render_cast(L->caster, s->p, L->light_dir, INFINITY, true, NULL)) return;
    for (int k = 0; k < 3; k++) out[k] = f[k] * L->sun[k] * ndl;
}

void vx__direct(const vx__light* L, const vx__surface* s, double out[3]) {
    double f[3] = {s->albedo[0] / pi, s->albedo[1] / pi, s->albedo[2] / pi};
    vx__direct_f(L, s, f, out);
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
