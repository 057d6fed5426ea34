/* svo/svo_light.c - lights and materials as scene data: validation of a
 * light and the typed reading of a material dictionary (svo.h). */
#define _XOPEN_SOURCE 700 /* realpath (vx_sky_rebase); implies _POSIX_C_SOURCE 200809L */
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "svo/svo.h"

static double len3(const double v[3]) { return sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }

vx_result vx_light_validate(const vx_light* l, uint32_t i, vx_error* err) {
    if (!l) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "light %u: NULL", i);
    if ((unsigned)l->type >= VX_LIGHT_TYPE_COUNT)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "light %u: unknown type %u", i, (unsigned)l->type);
    if (l->flags & ~(uint32_t)VX_LIGHT_FROM_VOXELS)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "light %u: unknown flags 0x%x", i, l->flags);
    double v[20] = {l->position[0], l->position[1], l->position[2], l->direction[0], l->direction[1],
                    l->direction[2], l->color[0],    l->color[1],    l->color[2],    l->intensity,
                    l->range,        l->inner_cone,  l->outer_cone,  l->radius,      l->angular_diameter,
                    l->tangent[0],   l->tangent[1],  l->tangent[2],  l->size[0],     l->size[1]};
    for (int k = 0; k < 20; k++)
        if (!isfinite(v[k]) || fabs(v[k]) > 1e30)
            return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "light %u: a value is not finite", i);
    if (l->intensity < 0 || l->color[0] < 0 || l->color[1] < 0 || l->color[2] < 0 || l->range < 0)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "light %u: negative intensity, colour or range", i);
    if (l->radius < 0 || l->angular_diameter < 0 || l->size[0] < 0 || l->size[1] < 0)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "light %u: negative radius, angle or size", i);
    if (l->angular_diameter >= 3.141592653589793)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "light %u: angular diameter must be below pi", i);
    for (int k = 0; k < 3; k++) /* shaders hold colour * intensity in a float */
        if (l->color[k] * l->intensity > 1e30)
            return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "light %u: colour times intensity above 1e30", i);
    bool directed = l->type == VX_LIGHT_DIRECTIONAL || l->type == VX_LIGHT_SPOT || l->type == VX_LIGHT_RECT;
    double dl = len3(l->direction);
    if (directed && !(dl > 0)) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "light %u: zero direction", i);
    if (l->type == VX_LIGHT_SPOT &&
        !(l->inner_cone >= 0 && l->inner_cone <= l->outer_cone && l->outer_cone <= 1.5707963267948966))
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET,
                       "light %u: spot cones must satisfy 0 <= inner <= outer <= pi/2 (radians)", i);
    if (l->type == VX_LIGHT_RECT) {
        double tl = len3(l->tangent);
        double c[3] = {l->direction[1] * l->tangent[2] - l->direction[2] * l->tangent[1],
                       l->direction[2] * l->tangent[0] - l->direction[0] * l->tangent[2],
                       l->direction[0] * l->tangent[1] - l->direction[1] * l->tangent[0]};
        if (!(tl > 0) || !(len3(c) > 1e-6 * tl * dl))
            return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET,
                           "light %u: a rect light needs a tangent not parallel to its normal", i);
    }
    return VX_OK;
}

static bool zero_bits(const double* v, int n) {
    for (int k = 0; k < n; k++)
        if (v[k] != 0 || signbit(v[k])) return false;
    return true;
}

vx_result vx_sky_validate(const vx_sky* k, vx_error* err) {
    if (!k) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "sky: NULL");
    if ((unsigned)k->type >= VX_SKY_TYPE_COUNT)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "sky: unknown type %u", (unsigned)k->type);
    double c[9] = {k->color[0],   k->color[1],   k->color[2],  k->horizon[0], k->horizon[1],
                   k->horizon[2], k->ground[0],  k->ground[1], k->ground[2]};
    for (int i = 0; i < 9; i++)
        if (!(c[i] >= 0 && c[i] <= 1e30))
            return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "sky: a colour is negative or not finite");
    if (!(k->intensity >= 0 && k->intensity <= 1e30) || !isfinite(k->rotation) || fabs(k->rotation) > 1e6)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "sky: intensity below 0 or not finite, or a rotation that is not finite");
    size_t plen = strnlen(k->path, sizeof k->path);
    if (plen == sizeof k->path)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "sky: the path is not NUL-terminated");
    /* one form per sky: what the type does not use is zero, so a write of a
     * sky read back gives the same bytes */
    int used = k->type == VX_SKY_DEFAULT ? 0 : k->type == VX_SKY_CONSTANT ? 3 : k->type == VX_SKY_GRADIENT ? 9 : 0;
    bool env = k->type == VX_SKY_ENVMAP;
    if (!zero_bits(c + used, 9 - used) || (!env && (!zero_bits(&k->intensity, 1) || !zero_bits(&k->rotation, 1))))
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "sky: a value the sky type does not use is not zero");
    if (env ? plen == 0 : plen != 0)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, env ? "sky: an environment map needs a path" : "sky: only an environment map has a path");
    return VX_OK;
}

void vx_sky_radiance(const vx_sky* k, const vx_sky_texels* map, const double d[3], double out[3]) {
    static const double pi = 3.14159265358979323846;
    out[0] = out[1] = out[2] = 0;
    if (!k) return;
    switch (k->type) {
        case VX_SKY_CONSTANT:
            for (int i = 0; i < 3; i++) out[i] = k->color[i];
            break;
        case VX_SKY_GRADIENT:
            if (d[2] >= 0) { /* +0 and -0 alike: the horizon colour */
                double t = fmin(d[2], 1.0);
                for (int i = 0; i < 3; i++) out[i] = k->horizon[i] + (k->color[i] - k->horizon[i]) * t;
            } else {
                for (int i = 0; i < 3; i++) out[i] = k->ground[i];
            }
            break;
        case VX_SKY_ENVMAP: {
            if (!map || !map->rgb || !map->width || !map->height) break;
            /* azimuth from +x towards +y, turned by -rotation (the map turns by +rotation), in turns */
            double u = (atan2(d[1], d[0]) - k->rotation) / (2 * pi);
            u -= floor(u);
            double v = acos(fmax(-1.0, fmin(1.0, d[2]))) / pi;
            if (!(u >= 0 && v >= 0)) break; /* NaN direction: black */
            uint32_t x = (uint32_t)fmin(u * map->width, map->width - 1.0);
            uint32_t y = (uint32_t)fmin(v * map->height, map->height - 1.0);
            const float* t = map->rgb + 3 * ((size_t)y * map->width + x);
            for (int i = 0; i < 3; i++) out[i] = t[i] * k->intensity;
            break;
        }
        default: break;
    }
}

bool vx_sky_path(const vx_sky* k, const char* svo_path, char* out, size_t n) {
    if (!out || n == 0) return false;
    out[0] = 0;
    if (!k || k->type != VX_SKY_ENVMAP || !k->path[0]) return false;
    size_t dir = 0; /* the folder part of svo_path, with its slash */
    if (k->path[0] != '/' && svo_path) {
        const char* slash = strrchr(svo_path, '/');
        dir = slash ? (size_t)(slash - svo_path) + 1 : 0;
    }
    size_t pl = strnlen(k->path, sizeof k->path);
    if (dir + pl + 1 > n || pl == sizeof k->path) return false;
    if (dir) memcpy(out, svo_path, dir);
    memcpy(out + dir, k->path, pl);
    out[dir + pl] = 0;
    return true;
}

/* The folder file lies in ("." where it names none), as realpath gives it. */
static vx_result real_folder(const char* file, char out[PATH_MAX], vx_error* err) {
    char dir[PATH_MAX];
    const char* slash = file ? strrchr(file, '/') : NULL;
    size_t n = slash ? (size_t)(slash - file) : 1;
    if (slash && n == 0) n = 1; /* "/x": the root */
    if (n >= sizeof dir) return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "sky: the folder of '%.80s...' is too long", file);
    memcpy(dir, slash ? file : ".", n);
    dir[n] = 0;
    if (!realpath(dir, out))
        return vx_fail(err, VX_ERR_IO, VX_NO_OFFSET, "sky: the folder '%.120s' cannot be resolved: %s", dir, strerror(errno));
    return VX_OK;
}

vx_result vx_sky_rebase(vx_sky* k, const char* from_file, const char* to_file, vx_error* err) {
    if (!k) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "sky: NULL");
    if (k->type != VX_SKY_ENVMAP || !k->path[0] || k->path[0] == '/') return VX_OK;
    char from[PATH_MAX], to[PATH_MAX];
    vx_result r = real_folder(from_file, from, err);
    if (!r) r = real_folder(to_file, to, err);
    if (r) return r;
    if (strcmp(from, to) == 0) return VX_OK;
    /* The image's path from the root, T = from + path: `from` is canonical
     * (no ".", "..", symlinks, doubled or trailing slash but the root's), so
     * the path's leading "./" and "../" can be taken off it as text (a
     * canonical folder's ".." is its parent). Then the folders T shares
     * with `to`, component by component as text (equal names under one
     * folder are one entry), one ".." per folder of `to` below those, and
     * the rest of T: no file system walk, and no component of the path
     * itself resolved (the renderer opens it; it may not exist yet). */
    const char* p = k->path;
    size_t fl = strlen(from);
    for (;;) {
        if (p[0] == '.' && p[1] == '/') {
            p += 2;
        } else if (p[0] == '.' && p[1] == '.' && p[2] == '/' && fl > 1) {
            while (fl > 1 && from[fl - 1] != '/') fl--;
            if (fl > 1) fl--;
            from[fl] = 0;
            p += 3;
        } else {
            break;
        }
    }
    char T[PATH_MAX + VX_SKY_PATH_MAX + 2];
    snprintf(T, sizeof T, "%s%s%s", from, fl > 1 ? "/" : "", p);
    size_t i = 0;
    while (T[i] && T[i] == to[i]) i++;
    size_t c = i; /* the shared folders' text ends at a component boundary */
    if (!((T[i] == 0 || T[i] == '/') && (to[i] == 0 || to[i] == '/')))
        while (c > 0 && T[c - 1] != '/') c--;
    const char *rest_to = to + c, *rest_t = T + c;
    while (*rest_to == '/') rest_to++;
    while (*rest_t == '/') rest_t++;
    char out[VX_SKY_PATH_MAX + 1] = {0}; /* zero after the text: the record's bytes do not depend on the stack */
    size_t at = 0;
    bool fits = true;
    for (const char* q = rest_to; *q && fits; q++)
        if (q == rest_to || q[-1] == '/') {
            fits = at + 3 <= VX_SKY_PATH_MAX;
            if (fits) memcpy(out + at, "../", 3), at += 3;
        }
    size_t n = strlen(rest_t);
    if (!fits || n == 0 || n > VX_SKY_PATH_MAX - at)
        return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET,
                       "sky: the environment map '%.60s' seen from '%.60s' needs a path over %u bytes (VX_SKY_PATH_MAX)",
                       k->path, to, VX_SKY_PATH_MAX);
    memcpy(out + at, rest_t, n);
    memcpy(k->path, out, sizeof k->path);
    return VX_OK;
}

vx_material vx_material_default(vx_material_type type) {
    vx_material m = {.type = type, .roughness = 0.1, .metalness = 0, .specular = 0.5, .ior = 1.5};
    if (type == VX_MATERIAL_DIFFUSE || type == VX_MATERIAL_EMIT) m.roughness = 1;
    if (type == VX_MATERIAL_METAL) m.metalness = 1;
    if (type == VX_MATERIAL_GLASS) m.transmission = 1;
    return m;
}

/* A number from the dictionary, or `def` when absent or not a finite number;
 * clamped to [lo, hi]. */
static double num(const vx_svo_material* m, const char* key, double def, double lo, double hi) {
    const char* s = vx_svo_material_get(m, key);
    if (!s || !*s) return def;
    char* end;
    double v = strtod(s, &end);
    if (end == s || !isfinite(v)) return def;
    return v < lo ? lo : v > hi ? hi : v;
}

vx_material vx_svo_material_resolve(const vx_svo_material* m) {
    if (!m) return vx_material_default(VX_MATERIAL_DIFFUSE);
    const char* t = vx_svo_material_get(m, "_type");
    vx_material_type type = VX_MATERIAL_DIFFUSE;
    if (t && !strcmp(t, "_metal")) type = VX_MATERIAL_METAL;
    else if (t && !strcmp(t, "_glass")) type = VX_MATERIAL_GLASS;
    else if (t && !strcmp(t, "_emit")) type = VX_MATERIAL_EMIT;
    vx_material r = vx_material_default(type);
    r.roughness = num(m, "_rough", r.roughness, 0, 1);
    r.metalness = num(m, "_metal", r.metalness, 0, 1);
    r.specular = num(m, "_spec", r.specular, 0, 1);
    double ri = num(m, "_ri", 0, 1, 4);
    r.ior = ri >= 1 && vx_svo_material_get(m, "_ri") ? ri : 1 + num(m, "_ior", r.ior - 1, 0, 3);
    r.transmission = num(m, "_trans", r.transmission, 0, 1);
    double e = num(m, "_emit", 0, 0, 1e30), f = num(m, "_flux", 0, 0, 16);
    r.emission = e * pow(2.0, f);
    /* voxkit's own emission colour: three finite numbers >= 0, else the voxel's colour */
    const char* ec = vx_svo_material_get(m, "_emit_color");
    if (ec) {
        double c[3];
        char* end = (char*)ec;
        bool ok = true;
        for (int k = 0; k < 3 && ok; k++) {
            const char* at = end;
            c[k] = strtod(at, &end);
            ok = end != at && isfinite(c[k]) && c[k] >= 0;
        }
        while (ok && *end == ' ') end++;
        if (ok && !*end)
            for (int k = 0; k < 3; k++) r.emission_color[k] = c[k] > 1e30 ? 1e30 : c[k];
    }
    if (type == VX_MATERIAL_EMIT && !(r.emission > 0)) r.type = VX_MATERIAL_DIFFUSE;
    return r;
}

vx_material vx_svo_scene_material(const vx_svo_scene* scene, uint32_t id) {
    for (uint32_t i = 0; scene && i < scene->material_count; i++)
        if (scene->materials[i].id == id) return vx_svo_material_resolve(&scene->materials[i]);
    return vx_material_default(VX_MATERIAL_DIFFUSE);
}

uint32_t vx_svo_attr_material(const vx_svo_model* m, uint32_t attr) {
    if (!m || attr >= m->attr_count) return 0;
    if ((m->attrs & VX_ATTR_MATERIAL) && m->material) return m->material[attr];
    if ((m->attrs & VX_ATTR_PALETTE) && m->palette) return m->palette[attr];
    return 0;
}

typedef struct mat_key {
    uint32_t id, at; /* at: the record's place in the scene, so that the first record of an id wins */
} mat_key;
static int mat_key_cmp(const void* a, const void* b) {
    const mat_key *x = a, *y = b;
    if (x->id != y->id) return x->id < y->id ? -1 : 1;
    return x->at < y->at ? -1 : x->at > y->at;
}

vx_result vx_svo_material_table_make(const vx_svo_scene* scene, const vx_allocator* alloc, vx_svo_material_table* out,
                                     vx_error* err) {
    if (!scene || !out) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    vx_svo_material_table t = {.alloc = alloc};
    uint32_t n = scene->material_count;
    if (n) {
        mat_key* k = vx_calloc(alloc, n, sizeof *k);
        t.ids = vx_calloc(alloc, n, sizeof *t.ids);
        t.mats = vx_calloc(alloc, n, sizeof *t.mats);
        if (!k || !t.ids || !t.mats) {
            vx_free(alloc, k);
            vx_svo_material_table_free(&t);
            return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %u materials", n);
        }
        for (uint32_t i = 0; i < n; i++) k[i] = (mat_key){scene->materials[i].id, i};
        qsort(k, n, sizeof *k, mat_key_cmp);
        for (uint32_t i = 0; i < n; i++) {
            if (t.count && t.ids[t.count - 1] == k[i].id) continue; /* a later record of the same id */
            vx_material m = vx_svo_material_resolve(&scene->materials[k[i].at]);
            t.ids[t.count] = k[i].id, t.mats[t.count++] = m;
            t.emissive |= m.emission > 0;
            t.specular |= m.type == VX_MATERIAL_METAL || m.type == VX_MATERIAL_GLASS;
        }
        vx_free(alloc, k);
    }
    *out = t;
    return VX_OK;
}

const vx_material* vx_svo_material_table_find(const vx_svo_material_table* t, uint32_t id) {
    uint32_t lo = 0, hi = t ? t->count : 0;
    while (lo < hi) {
        uint32_t mid = lo + (hi - lo) / 2;
        if (t->ids[mid] < id) lo = mid + 1;
        else hi = mid;
    }
    return t && lo < t->count && t->ids[lo] == id ? &t->mats[lo] : NULL;
}

double vx_svo_material_table_emission(const vx_svo_material_table* t, uint32_t id) {
    const vx_material* m = vx_svo_material_table_find(t, id);
    return m ? m->emission : 0;
}

vx_result vx_svo_material_table_emission_records(const vx_svo_material_table* t, const uint16_t* ids, size_t n,
                                                 const vx_allocator* alloc, float** out, size_t* count, vx_error* err) {
    size_t ne = t && t->emissive ? n : 0;
    float* e = vx_calloc(alloc, ne ? 4 * ne : 4, sizeof(float));
    if (!e) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %zu emission records", ne);
    for (size_t i = 0; i < ne; i++) vx_material_emitted_terms(vx_svo_material_table_find(t, ids[i]), e + 4 * i);
    *out = e, *count = ne;
    return VX_OK;
}

static bool own_emission_color(const vx_material* m) {
    return m->emission_color[0] > 0 || m->emission_color[1] > 0 || m->emission_color[2] > 0;
}

void vx_material_emitted(const vx_material* m, const double rgb[3], double out[3]) {
    bool own = own_emission_color(m);
    for (int k = 0; k < 3; k++) out[k] = (own ? m->emission_color[k] : rgb[k]) * m->emission;
}

void vx_material_emitted_terms(const vx_material* m, float k[4]) {
    k[0] = k[1] = k[2] = k[3] = 0;
    if (!m || !(m->emission > 0)) return;
    if (own_emission_color(m))
        for (int c = 0; c < 3; c++) k[c] = (float)fmin(m->emission_color[c] * m->emission, 1e30);
    else
        k[3] = (float)m->emission; /* as the multiplier alone was handed to the GPU */
}

void vx_svo_material_table_free(vx_svo_material_table* t) {
    if (!t) return;
    vx_free(t->alloc, t->ids);
    vx_free(t->alloc, t->mats);
    t->ids = NULL, t->mats = NULL, t->count = 0, t->emissive = t->specular = false;
}
