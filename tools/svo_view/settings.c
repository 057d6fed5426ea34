/* tools/svo_view/settings.c - GI options and material fields as text (see settings.h). */
#include "tools/svo_view/settings.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tools/common/tool.h" /* vx_tool_parse_vec: R,G,B as svo_render's colours */

static bool num(const char* s, double* out) {
    char* end;
    if (!s || !*s) return false;
    double v = strtod(s, &end);
    if (*end || !isfinite(v)) return false;
    *out = v;
    return true;
}

/* svo_render's parse_uint: decimal, at most 1,000,000 */
static bool whole(const char* s, uint32_t* out) {
    char* end;
    if (!s || !*s || *s == '-' || *s == '+') return false;
    unsigned long v = strtoul(s, &end, 10);
    if (end == s || *end || v > 1000000) return false;
    *out = (uint32_t)v;
    return true;
}

static bool onoff(const char* s, bool* out) {
    if (!s) return false;
    if (!strcmp(s, "on")) return *out = true, true;
    if (!strcmp(s, "off")) return *out = false, true;
    return false;
}

#define FAIL(...) return snprintf(why, why_size, __VA_ARGS__), false

bool sv_gi_option(sv_gi_settings* g, const char* name, const char* value, char* why, size_t why_size) {
    sv_gi_settings t = *g;
    uint32_t u = 0;
    double d = 0;
    bool b = false;
    if (!name || !value) FAIL("an option and a value");
    if (!strcmp(name, "bounces")) {
        if (!whole(value, &u) || !u || u > 64) FAIL("bad bounces '%s' (1..64)", value);
        t.bounces = u;
    } else if (!strcmp(name, "seed")) {
        if (!whole(value, &u)) FAIL("bad seed '%s'", value);
        t.seed = u;
    } else if (!strcmp(name, "spp") || !strcmp(name, "passes-count")) {
        if (!whole(value, &u) || !u || u > 1024) FAIL("bad %s '%s' (1..1024)", name, value);
        t.spp = u;
    } else if (!strcmp(name, "ao-rays")) {
        if (!whole(value, &u) || !u || u > 4096) FAIL("bad ao rays '%s' (1..4096)", value);
        t.ao_rays = u;
    } else if (!strcmp(name, "ao-radius")) {
        if (!num(value, &d) || !(d > 0 && d < 1e30)) FAIL("bad ao radius '%s'", value);
        t.ao_radius = d;
    } else if (!strcmp(name, "photons")) {
        if (!whole(value, &u) || !u || u > (1u << 26)) FAIL("bad photon count '%s' (1..2^26)", value);
        t.photon.photons = u;
    } else if (!strcmp(name, "final-gather")) {
        if (!whole(value, &u) || u > 1024) FAIL("bad final gather rays '%s' (0..1024)", value);
        t.photon.final_gather = u;
    } else if (!strcmp(name, "radius")) {
        if (!num(value, &d) || !(d > 0)) FAIL("bad photon radius '%s' (world units, above 0)", value);
        t.photon.radius = d;
    } else if (!strcmp(name, "cone-res")) {
        if (!whole(value, &u) || u < 2 || u > VX_CONE_RES_MAX) FAIL("bad cone resolution '%s' (2..%u)", value, VX_CONE_RES_MAX);
        t.cone.res = u;
    } else if (!strcmp(name, "cones")) {
        if (!whole(value, &u) || !u || u > VX_CONE_CONES_MAX) FAIL("bad cone count '%s' (1..%u)", value, VX_CONE_CONES_MAX);
        t.cone.cones = u;
    } else if (!strcmp(name, "cone-aperture")) {
        if (!num(value, &d) || !(d > 0 && d < 89)) FAIL("bad cone aperture '%s' (degrees, above 0 and below 89)", value);
        t.cone.aperture = d;
    } else if (!strcmp(name, "cone-bounces")) {
        if (!whole(value, &u) || !u || u > 4) FAIL("bad cone bounces '%s' (1..4)", value);
        t.cone.bounces = u;
    } else if (!strcmp(name, "cone-sun-angle")) {
        if (!num(value, &d) || !(d > 0 && d < 30)) FAIL("bad sun angle '%s' (degrees, above 0 and below 30)", value);
        t.cone.sun_angle = d;
    } else if (!strcmp(name, "cone-isotropic") || !strcmp(name, "cone-ao") || !strcmp(name, "cone-half") ||
               !strcmp(name, "cone-shadows") || !strcmp(name, "cone-no-specular")) {
        if (!onoff(value, &b)) FAIL("%s takes on or off, not '%s'", name, value);
        if (!strcmp(name, "cone-isotropic")) t.cone.isotropic = b;
        else if (!strcmp(name, "cone-ao")) t.cone.output = b ? VX_CONE_OUTPUT_AO : VX_CONE_OUTPUT_RADIANCE;
        else if (!strcmp(name, "cone-half")) t.cone.half_res = b;
        else if (!strcmp(name, "cone-shadows")) t.cone.shadows = b;
        else t.cone.no_specular = b;
    } else {
        FAIL("unknown option '%s' (bounces, seed, spp, ao-rays, ao-radius, photons, final-gather, radius, cone-res, cones, "
             "cone-aperture, cone-bounces, cone-sun-angle, cone-isotropic, cone-ao, cone-half, cone-shadows, "
             "cone-no-specular)", name);
    }
    *g = t;
    return true;
}

size_t sv_gi_options_format(const sv_gi_settings* g, char* out, size_t out_size) {
    size_t at = 0;
    char t[64];
#define PUT(...)                                                                           \
    do {                                                                                   \
        int k = snprintf(t, sizeof t, __VA_ARGS__);                                        \
        for (int i = 0; i < k && at + 1 < out_size; i++) out[at++] = t[i];                \
    } while (0)
    if (g->bounces) PUT(" --bounces %u", g->bounces);
    if (g->seed) PUT(" --seed %u", g->seed);
    if (g->spp) PUT(" --spp %u", g->spp);
    if (g->ao_rays) PUT(" --ao-rays %u", g->ao_rays);
    if (g->ao_radius > 0) PUT(" --ao-radius %.17g", g->ao_radius);
    if (g->photon.photons) PUT(" --photons %u", g->photon.photons);
    if (g->photon.final_gather) PUT(" --final-gather %u", g->photon.final_gather);
    if (g->photon.radius > 0) PUT(" --radius %.17g", g->photon.radius);
    if (g->cone.res) PUT(" --cone-res %u", g->cone.res);
    if (g->cone.cones) PUT(" --cones %u", g->cone.cones);
    if (g->cone.aperture > 0) PUT(" --cone-aperture %.17g", g->cone.aperture);
    if (g->cone.bounces) PUT(" --cone-bounces %u", g->cone.bounces);
    if (g->cone.sun_angle > 0) PUT(" --cone-sun-angle %.17g", g->cone.sun_angle);
    if (g->cone.isotropic) PUT(" --cone-isotropic");
    if (g->cone.output == VX_CONE_OUTPUT_AO) PUT(" --cone-ao");
    if (g->cone.half_res) PUT(" --cone-half");
    if (g->cone.shadows) PUT(" --cone-shadows");
    if (g->cone.no_specular) PUT(" --cone-no-specular");
#undef PUT
    if (out_size) out[at < out_size ? at : out_size - 1] = 0;
    return at;
}

bool sv_material_field(const char* field, const char* value, const char* keys[2], char values[2][SV_MATERIAL_VALUE],
                       uint32_t* n, char* why, size_t why_size) {
    double d = 0;
    *n = 1;
    if (!field || !value) FAIL("a field and a value");
    if (!strcmp(field, "type")) {
        static const char* const types[4] = {"diffuse", "metal", "glass", "emit"};
        int k = -1;
        for (int i = 0; i < 4; i++)
            if (!strcmp(value, types[i])) k = i;
        if (k < 0) FAIL("bad material type '%s' (diffuse, metal, glass, emit)", value);
        keys[0] = "_type";
        snprintf(values[0], SV_MATERIAL_VALUE, "_%s", types[k]);
        return true;
    }
    if (!strcmp(field, "emit_color")) { /* R,G,B as svo_render's colours, or none (the voxel's colour) */
        double c[3] = {0, 0, 0};
        bool ok = !strcmp(value, "none") ||
                  (vx_tool_parse_vec(value, c, 3) && c[0] >= 0 && c[1] >= 0 && c[2] >= 0 && c[0] <= 1e30 && c[1] <= 1e30 &&
                   c[2] <= 1e30);
        if (!ok) FAIL("bad material emit_color '%s' (R,G,B each 0..1e30, or none)", value);
        keys[0] = "_emit_color";
        snprintf(values[0], SV_MATERIAL_VALUE, "%.9g %.9g %.9g", c[0], c[1], c[2]);
        return true;
    }
    static const struct {
        const char* field;
        const char* key;
        double lo, hi;
    } f[] = {{"rough", "_rough", 0, 1}, {"metal", "_metal", 0, 1}, {"spec", "_spec", 0, 1}, {"trans", "_trans", 0, 1},
             {"ior", "_ri", 1, 4},      {"emit", "_emit", 0, 1e30}, {"flux", "_flux", 0, 16}};
    for (size_t i = 0; i < sizeof f / sizeof f[0]; i++) {
        if (strcmp(field, f[i].field)) continue;
        if (!num(value, &d) || d < f[i].lo || d > f[i].hi)
            FAIL("bad material %s '%s' (%g..%g)", field, value, f[i].lo, f[i].hi);
        keys[0] = f[i].key;
        snprintf(values[0], SV_MATERIAL_VALUE, "%.9g", d);
        if (!strcmp(field, "ior")) { /* MagicaVoxel's _ior is the index - 1; _ri (the index) wins on reading */
            keys[1] = "_ior";
            snprintf(values[1], SV_MATERIAL_VALUE, "%.9g", d - 1);
            *n = 2;
        }
        return true;
    }
    FAIL("unknown material field '%s' (type, rough, metal, spec, trans, ior, emit, flux, emit_color)", field);
}
