/* tests/glb/test_glb_lights.c - svo_info --to-glb writes the scene's lights
 * (convert/export_glb.c, formats/glb.h) and voxkit reads them back
 * (formats/gltf.h's extras.voxkit_light, convert/mesh.c).
 *  - read back: a scene with a light of each of the five types (and the
 *    cases that need voxkit's record: a sun's angular diameter, a point
 *    radius, equal spot cones, a colour over 1), written and read with our
 *    .svo writer and reader, exported and read with our glTF reader: every
 *    field after the turn to glTF's +Y up; read as other readers see it
 *    (punctual_only), the sphere and rect approximations' intensities
 *    (L pi r^2, L A) and the nudged cones; a light of emissive voxels is
 *    not written.
 *  - round trips: that scene -> .glb -> vox2svo's conversion gives the same
 *    vx_light records, and a glTF file with KHR_lights_punctual lights (and
 *    voxkit's sphere and rect records) -> .svo -> .glb -> .svo gives the
 *    first .svo's records again; directions to 1e-15 (a unit vector is
 *    normalized once more on the way), every other value exact.
 *  - a scene without lights (or with only lights of emissive voxels) writes
 *    no KHR_lights_punctual and the same bytes.
 *  - bad records in extras.voxkit_light are errors naming the light; one of
 *    another type is ignored with a warning; the writer refuses values the
 *    extension forbids. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "convert/convert.h"
#include "convert/mesh.h"
#include "formats/glb.h"
#include "formats/gltf.h"
#include "svo/svo.h"
#include "tests/glb/box_gltf.h"
#include "tests/test.h"
#include "convert/export.h"

static const double PI = 3.141592653589793;

/* voxkit's lights, +Z up (svo/svo.h's units): one of each type, then the
 * cases only voxkit's extras record keeps */
static const vx_light LIGHTS[] = {
    {.type = VX_LIGHT_DIRECTIONAL, .direction = {0.3, -0.4, 0.866}, .color = {1, 0.9, 0.8}, .intensity = 3,
     .angular_diameter = 0.0093},
    {.type = VX_LIGHT_POINT, .position = {1.5, -2.25, 3}, .color = {0.2, 0.4, 1}, .intensity = 50, .range = 20,
     .radius = 0.1},
    {.type = VX_LIGHT_SPOT, .position = {4, 5, 6}, .direction = {0, 0.6, -0.8}, .color = {1, 1, 1}, .intensity = 100,
     .inner_cone = 0.2, .outer_cone = 0.6},
    {.type = VX_LIGHT_SPHERE, .position = {2, 1, 4}, .color = {1, 0.5, 0.25}, .intensity = 40, .radius = 0.25},
    {.type = VX_LIGHT_RECT, .position = {0, 3, 5}, .direction = {0, 0, -2}, .tangent = {1, 0, 0.3}, .size = {2, 0.5},
     .color = {0.9, 0.9, 1}, .intensity = 10},
    {.type = VX_LIGHT_POINT, .position = {-1, -1, 2}, .color = {2, 1, 0.5}, .intensity = 7},
    {.type = VX_LIGHT_SPOT, .position = {3, 0, 2}, .direction = {1, 0, 0}, .color = {1, 1, 1}, .intensity = 5,
     .inner_cone = 0.5, .outer_cone = 0.5, .radius = 0.05},
    {.type = VX_LIGHT_DIRECTIONAL, .direction = {0, 0, 1}, .color = {1, 1, 1}, .intensity = 1},
};
enum { NLIGHTS = sizeof LIGHTS / sizeof LIGHTS[0] };
/* those whose punctual light differs (vx_conv_glb_light_approx): 0 1 3 4 6 */
static const bool APPROX[NLIGHTS] = {true, true, false, true, true, false, true, false};
/* those that need extras.voxkit_light (5: the colour over 1) */
static const bool EXTRAS[NLIGHTS] = {true, true, false, true, true, true, true, false};

/* ---- helpers ---------------------------------------------------------------------- */

static void tmp_path(char* buf, size_t n, const char* tag, const char* ext) {
    const char* d = getenv("TMPDIR");
    snprintf(buf, n, "%s/test_glb_lights_%ld_%s.%s", d && *d ? d : "/tmp", (long)getpid(), tag, ext);
}

static void to_gltf(const double v[3], double o[3]) { o[0] = v[0], o[1] = v[2], o[2] = -v[1]; }
static double dot3(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
static void unit(const double v[3], double o[3]) {
    double l = sqrt(dot3(v, v));
    for (int k = 0; k < 3; k++) o[k] = v[k] / l;
}
/* t made orthogonal to unit n, then unit (the renderer's rect edges) */
static void across(const double t[3], const double n[3], double o[3]) {
    double tn = dot3(t, n), x[3];
    for (int k = 0; k < 3; k++) x[k] = t[k] - tn * n[k];
    unit(x, o);
}
static bool same3(const double a[3], const double b[3], double tol) {
    for (int k = 0; k < 3; k++)
        if (!(fabs(a[k] - b[k]) <= tol)) return false;
    return true;
}
static bool exact3(const double a[3], const double b[3]) { return a[0] == b[0] && a[1] == b[1] && a[2] == b[2]; }


/* A .gltf (text, the buffer a data URI): node 0 a box 0..4 on each axis (12
 * triangles), then `nodes` (JSON text, the nodes 1.. placing `lights`); both
 * NULL: the box alone. malloc'ed. */
static char* gltf_text(const char* lights, const char* nodes) {
    char b64[BOX_GLTF_B64];
    box_gltf_positions(b64);
    size_t n = strlen(b64) + (lights ? strlen(lights) : 0) + (nodes ? strlen(nodes) : 0) + 1024;
    char* s = malloc(n);
    if (!s) return NULL;
    int at = snprintf(s, n,
                      "{\"asset\":{\"version\":\"2.0\"},"
                      "\"buffers\":[{\"byteLength\":%zu,\"uri\":\"data:application/octet-stream;base64,%s\"}],"
                      "\"bufferViews\":[{\"buffer\":0,\"byteLength\":%zu}],"
                      "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":36,\"type\":\"VEC3\","
                      "\"min\":[0,0,0],\"max\":[4,4,4]}],"
                      "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0}}]}],",
                      (size_t)BOX_GLTF_BYTES, b64, (size_t)BOX_GLTF_BYTES);
    if (lights)
        at += snprintf(s + at, n - (size_t)at,
                       "\"extensionsUsed\":[\"KHR_lights_punctual\"],"
                       "\"extensions\":{\"KHR_lights_punctual\":{\"lights\":[%s]}},"
                       "\"nodes\":[{\"mesh\":0},%s],",
                       lights, nodes);
    else
        at += snprintf(s + at, n - (size_t)at, "\"nodes\":[{\"mesh\":0}],");
    int count = 1;
    for (const char* p = nodes; p && (p = strstr(p, "KHR_lights_punctual")); p++) count++;
    at += snprintf(s + at, n - (size_t)at, "\"scenes\":[{\"nodes\":[0");
    for (int i = 1; i < count; i++) at += snprintf(s + at, n - (size_t)at, ",%d", i);
    snprintf(s + at, n - (size_t)at, "]}],\"scene\":0}");
    return s;
}

/* vox2svo's conversion of a glTF file (at 8 cells a side) */
static vx_result convert(const char* path, vx_svo_scene* out) {
    vx_error err = {0};
    vx_result r = vx_conv_mesh_file(&(vx_conv_mesh_desc){.res = 8}, path, out, NULL, &err);
    if (r) fprintf(stderr, "  convert %s: %s\n", path, err.msg);
    return r;
}

/* s through our .svo writer and reader */
static vx_result svo_trip(const vx_svo_scene* s, vx_svo_scene* out) {
    char path[512];
    tmp_path(path, sizeof path, "trip", "svo");
    vx_error err = {0};
    vx_result r = vx_svo_write_file(NULL, s, path, &err);
    if (!r) r = vx_svo_read_file(NULL, path, out, &err);
    remove(path);
    if (r) fprintf(stderr, "  svo: %s\n", err.msg);
    return r;
}

/* The box with LIGHTS, through the .svo writer and reader. */
static vx_result lit_scene(vx_svo_scene* out) {
    char path[512];
    tmp_path(path, sizeof path, "box", "gltf");
    char* text = gltf_text(NULL, NULL);
    if (!text || !write_text(path, text)) {
        free(text);
        return VX_ERR_IO;
    }
    free(text);
    vx_svo_scene s;
    vx_result r = convert(path, &s);
    remove(path);
    if (r) return r;
    s.lights = vx_calloc(s.alloc, NLIGHTS, sizeof *s.lights);
    if (!s.lights) {
        vx_svo_scene_free(&s);
        return VX_ERR_NOMEM;
    }
    memcpy(s.lights, LIGHTS, sizeof LIGHTS);
    s.light_count = NLIGHTS;
    r = svo_trip(&s, out);
    vx_svo_scene_free(&s);
    return r;
}

static vx_result export_glb(const vx_svo_scene* s, const char* path, vx_conv_glb_stats* st) {
    vx_error err = {0};
    vx_result r = vx_conv_svo_to_glb_file(NULL, s, path, st, &err);
    if (r) fprintf(stderr, "  export: %s\n", err.msg);
    return r;
}

/* Two records the same light: directions and tangents as the renderer
 * reads them (unit; a rect's tangent orthogonal to its normal) to 1e-15,
 * every other field exact; want's values its type does not use are 0. */
static bool same_light(const vx_light* got, const vx_light* want, char* why, size_t n) {
    double dg[3] = {0, 0, 0}, dw[3] = {0, 0, 0}, tg[3] = {0, 0, 0}, tw[3] = {0, 0, 0};
    bool dir = want->type != VX_LIGHT_POINT && want->type != VX_LIGHT_SPHERE;
    if (dir) unit(got->direction, dg), unit(want->direction, dw);
    if (want->type == VX_LIGHT_RECT) across(got->tangent, dg, tg), across(want->tangent, dw, tw);
    const char* bad = got->type != want->type                         ? "type"
                      : !exact3(got->position, want->position)         ? "position"
                      : !same3(dg, dw, 1e-15)                          ? "direction"
                      : !exact3(got->color, want->color)               ? "colour"
                      : got->intensity != want->intensity              ? "intensity"
                      : got->range != want->range                      ? "range"
                      : got->inner_cone != want->inner_cone            ? "inner cone"
                      : got->outer_cone != want->outer_cone            ? "outer cone"
                      : got->radius != want->radius                    ? "radius"
                      : got->angular_diameter != want->angular_diameter ? "angular diameter"
                      : !same3(tg, tw, 1e-15)                          ? "tangent"
                      : got->size[0] != want->size[0] || got->size[1] != want->size[1] ? "size"
                      : got->flags != want->flags                      ? "flags"
                                                                       : NULL;
    if (bad)
        snprintf(why, n, "%s: type %d/%d position %.17g %.17g %.17g / %.17g %.17g %.17g intensity %.17g/%.17g", bad,
                 (int)got->type, (int)want->type, got->position[0], got->position[1], got->position[2],
                 want->position[0], want->position[1], want->position[2], got->intensity, want->intensity);
    return !bad;
}

/* ---- tests ------------------------------------------------------------------------ */

/* The export read back with our glTF reader: voxkit's records exactly, and
 * the punctual lights other readers see. */
static void test_lights_read_back(void) {
    vx_svo_scene s;
    REQUIRE(lit_scene(&s) == VX_OK);
    REQUIRE(s.light_count == NLIGHTS);
    /* a light of emissive voxels (never in a file) is not written */
    vx_light with_voxels[NLIGHTS + 1];
    memcpy(with_voxels, s.lights, sizeof LIGHTS);
    with_voxels[NLIGHTS] = (vx_light){.type = VX_LIGHT_SPHERE, .color = {1, 1, 1}, .intensity = 1, .radius = 1,
                                      .flags = VX_LIGHT_FROM_VOXELS};
    vx_svo_scene v = s;
    v.lights = with_voxels;
    v.light_count = NLIGHTS + 1;
    char path[512];
    tmp_path(path, sizeof path, "read", "glb");
    vx_conv_glb_stats st;
    vx_result r = export_glb(&v, path, &st);
    vx_svo_scene_free(&s);
    REQUIRE(r == VX_OK);
    CHECKF(st.lights == NLIGHTS, "%u lights written", st.lights);
    uint32_t approx = 0;
    for (int i = 0; i < NLIGHTS; i++) {
        approx += APPROX[i];
        CHECKF((vx_conv_glb_light_approx(&LIGHTS[i]) != NULL) == APPROX[i], "light %d: approximated?", i);
    }
    CHECKF(st.lights_approximated == approx, "%u approximated, %u expected", st.lights_approximated, approx);
    vx_gltf_mesh ex, pu;
    vx_error err = {0};
    r = vx_gltf_read_file(NULL, path, &ex, &err);
    if (r) fprintf(stderr, "  read: %s\n", err.msg);
    vx_result r2 = vx_gltf_read_file(&(vx_gltf_read_desc){.punctual_only = true}, path, &pu, &err);
    if (r2) fprintf(stderr, "  read (punctual only): %s\n", err.msg);
    remove(path);
    if (!r && r2) vx_gltf_mesh_free(&ex);
    if (r && !r2) vx_gltf_mesh_free(&pu);
    REQUIRE(r == VX_OK && r2 == VX_OK);
    CHECK(ex.tri_count > 0);
    REQUIRE(ex.light_count == NLIGHTS && pu.light_count == NLIGHTS);
    static const uint32_t gtype[VX_LIGHT_TYPE_COUNT] = {VX_GLTF_LIGHT_DIRECTIONAL, VX_GLTF_LIGHT_POINT,
                                                        VX_GLTF_LIGHT_SPOT, VX_GLTF_LIGHT_SPHERE, VX_GLTF_LIGHT_RECT};
    static const uint32_t ptype[VX_LIGHT_TYPE_COUNT] = {VX_GLTF_LIGHT_DIRECTIONAL, VX_GLTF_LIGHT_POINT,
                                                        VX_GLTF_LIGHT_SPOT, VX_GLTF_LIGHT_POINT, VX_GLTF_LIGHT_SPOT};
    for (int i = 0; i < NLIGHTS; i++) {
        const vx_light* l = &LIGHTS[i];
        const vx_gltf_light *e = &ex.lights[i], *p = &pu.lights[i];
        char name[24];
        snprintf(name, sizeof name, "light %d", i);
        CHECKF(!strcmp(e->name, name) && !strcmp(p->name, name), "light %d named '%s'", i, e->name);
        /* where it is and where it shines, in glTF's +Y-up world */
        double pos[3], d[3] = {0, 0, 0}, back[3] = {-l->direction[0], -l->direction[1], -l->direction[2]}, t[3];
        to_gltf(l->position, pos);
        if (l->type == VX_LIGHT_DIRECTIONAL) to_gltf(back, t), unit(t, d);
        else if (l->type == VX_LIGHT_SPOT || l->type == VX_LIGHT_RECT) to_gltf(l->direction, t), unit(t, d);
        CHECKF(exact3(e->position, pos) && exact3(p->position, pos), "light %d at %g %g %g, expected %g %g %g", i,
               e->position[0], e->position[1], e->position[2], pos[0], pos[1], pos[2]);
        if (l->type != VX_LIGHT_POINT && l->type != VX_LIGHT_SPHERE)
            CHECKF(same3(e->direction, d, 1e-15) && same3(p->direction, d, 1e-15),
                   "light %d shines along %g %g %g, expected %g %g %g", i, e->direction[0], e->direction[1],
                   e->direction[2], d[0], d[1], d[2]);
        /* voxkit's record: exact */
        CHECKF(e->type == gtype[l->type] && e->voxkit == EXTRAS[i], "light %d: type %u (voxkit %d)", i, e->type,
               (int)e->voxkit);
        CHECKF(exact3(e->color, l->color) && e->intensity == l->intensity, "light %d: colour %g %g %g x %g", i,
               e->color[0], e->color[1], e->color[2], e->intensity);
        bool cones = l->type != VX_LIGHT_SPOT || (e->inner_cone == l->inner_cone && e->outer_cone == l->outer_cone);
        CHECKF(cones, "light %d: cones %.17g %.17g", i, e->inner_cone, e->outer_cone);
        CHECKF(e->radius == (l->type == VX_LIGHT_RECT ? 0 : l->radius) && e->angular_diameter == l->angular_diameter,
               "light %d: radius %g, angular diameter %g", i, e->radius, e->angular_diameter);
        CHECKF(e->range == (l->type == VX_LIGHT_POINT || l->type == VX_LIGHT_SPOT ? l->range : 0), "light %d: range %g",
               i, e->range);
        if (l->type == VX_LIGHT_RECT) {
            double tg[3], tw[3];
            to_gltf(l->tangent, t);
            across(t, d, tw);
            memcpy(tg, e->tangent, sizeof tg);
            CHECKF(same3(tg, tw, 1e-15) && e->size[0] == l->size[0] && e->size[1] == l->size[1],
                   "rect: tangent %g %g %g (expected %g %g %g), size %g %g", tg[0], tg[1], tg[2], tw[0], tw[1], tw[2],
                   e->size[0], e->size[1]);
        }
        /* what other readers see: KHR_lights_punctual alone */
        double big = fmax(l->color[0], fmax(l->color[1], l->color[2])), scale = big > 1 ? big : 1, want = l->intensity;
        if (l->type == VX_LIGHT_SPHERE) want = l->intensity * PI * l->radius * l->radius; /* L pi r^2 */
        if (l->type == VX_LIGHT_RECT) want = l->intensity * l->size[0] * l->size[1];     /* L A */
        want *= scale;
        CHECKF(p->type == ptype[l->type] && !p->voxkit && p->radius == 0 && p->angular_diameter == 0,
               "light %d: punctual type %u", i, p->type);
        CHECKF(fabs(p->intensity - want) <= 1e-12 * want, "light %d: punctual intensity %.17g, expected %.17g", i,
               p->intensity, want);
        for (int k = 0; k < 3; k++)
            CHECKF(p->color[k] == l->color[k] / scale && p->color[k] <= 1, "light %d: punctual colour %g", i, p->color[k]);
        if (l->type == VX_LIGHT_RECT)
            CHECKF(p->inner_cone == 0 && p->outer_cone == PI / 2, "rect: cones %g %g", p->inner_cone, p->outer_cone);
        if (l->type == VX_LIGHT_SPOT && l->inner_cone < l->outer_cone)
            CHECKF(p->inner_cone == l->inner_cone && p->outer_cone == l->outer_cone, "spot %d: cones %g %g", i,
                   p->inner_cone, p->outer_cone);
        if (l->type == VX_LIGHT_SPOT && l->inner_cone == l->outer_cone) /* nudged: glTF needs inner < outer */
            CHECKF(p->inner_cone < p->outer_cone && p->outer_cone == l->outer_cone &&
                       p->inner_cone >= l->outer_cone * (1 - 1e-5),
                   "spot %d: cones %.17g %.17g", i, p->inner_cone, p->outer_cone);
        if (l->type == VX_LIGHT_POINT || l->type == VX_LIGHT_SPOT)
            CHECKF(p->range == l->range, "light %d: punctual range %g", i, p->range);
    }
    vx_gltf_mesh_free(&ex);
    vx_gltf_mesh_free(&pu);
}

/* .svo -> .glb -> vox2svo's conversion: the same records */
static void test_lights_svo_round_trip(void) {
    vx_svo_scene s, back;
    REQUIRE(lit_scene(&s) == VX_OK);
    char path[512];
    tmp_path(path, sizeof path, "svotrip", "glb");
    vx_result r = export_glb(&s, path, NULL);
    if (!r) r = convert(path, &back);
    remove(path);
    if (r) vx_svo_scene_free(&s);
    REQUIRE(r == VX_OK);
    CHECKF(back.light_count == NLIGHTS, "%u lights back", back.light_count);
    for (uint32_t i = 0; i < back.light_count && i < NLIGHTS; i++) {
        char why[256];
        CHECKF(same_light(&back.lights[i], &s.lights[i], why, sizeof why), "light %u: %s", i, why);
    }
    vx_svo_scene_free(&back);
    vx_svo_scene_free(&s);
}

/* A glTF file's KHR_lights_punctual lights (and voxkit's sphere and rect
 * records) -> vox2svo -> svo_info --to-glb -> vox2svo: the records of the
 * first conversion come back. */
static const char GLTF_LIGHTS[] =
    "{\"type\":\"directional\",\"color\":[1,0.9,0.8],\"intensity\":3},"
    "{\"type\":\"point\",\"name\":\"bulb\",\"color\":[0.2,0.4,1],\"intensity\":50,\"range\":20},"
    "{\"type\":\"spot\",\"intensity\":100,\"spot\":{\"innerConeAngle\":0.2,\"outerConeAngle\":0.6}},"
    "{\"type\":\"point\",\"intensity\":7.85,\"color\":[1,0.5,0.25],"
    "\"extras\":{\"voxkit_light\":{\"type\":\"sphere\",\"radiance\":40,\"radius\":0.25}}},"
    "{\"type\":\"spot\",\"intensity\":10,\"spot\":{\"innerConeAngle\":0,\"outerConeAngle\":1.5707963267948966},"
    "\"extras\":{\"voxkit_light\":{\"type\":\"rect\",\"radiance\":10,\"size\":[2,0.5]}}}";
static const char GLTF_NODES[] =
    "{\"rotation\":[-0.3826834,0,0,0.9238795],\"extensions\":{\"KHR_lights_punctual\":{\"light\":0}}},"
    "{\"translation\":[0.5,2,0.25],\"extensions\":{\"KHR_lights_punctual\":{\"light\":1}}},"
    "{\"translation\":[1,3,-2],\"rotation\":[0.2,0.1,0.3,0.927],\"extensions\":{\"KHR_lights_punctual\":{\"light\":2}}},"
    "{\"translation\":[2,4,-1],\"extensions\":{\"KHR_lights_punctual\":{\"light\":3}}},"
    "{\"translation\":[0,5,-3],\"rotation\":[-0.7071068,0,0,0.7071068],\"extensions\":{\"KHR_lights_punctual\":{\"light\":4}}}";

static void test_lights_gltf_round_trip(void) {
    char src[512], mid[512];
    tmp_path(src, sizeof src, "src", "gltf");
    tmp_path(mid, sizeof mid, "mid", "glb");
    char* text = gltf_text(GLTF_LIGHTS, GLTF_NODES);
    REQUIRE(text);
    bool ok = write_text(src, text);
    free(text);
    REQUIRE(ok);
    vx_svo_scene a0, a, b;
    vx_result r = convert(src, &a0);
    remove(src);
    REQUIRE(r == VX_OK);
    r = svo_trip(&a0, &a); /* vox2svo writes the .svo; svo_info reads it */
    vx_svo_scene_free(&a0);
    REQUIRE(r == VX_OK);
    REQUIRE(a.light_count == 5);
    /* the first conversion: glTF's values, turned +Z up: (x, y, z) -> (x, -z, y) */
    static const vx_light_type types[5] = {VX_LIGHT_DIRECTIONAL, VX_LIGHT_POINT, VX_LIGHT_SPOT, VX_LIGHT_SPHERE,
                                           VX_LIGHT_RECT};
    for (int i = 0; i < 5; i++) CHECKF(a.lights[i].type == types[i], "light %d: type %d", i, (int)a.lights[i].type);
    CHECK(exact3(a.lights[1].position, ((double[3]){0.5, -0.25, 2})) && a.lights[1].range == 20 &&
          a.lights[1].intensity == 50);
    CHECK(a.lights[2].inner_cone == 0.2 && a.lights[2].outer_cone == 0.6 && a.lights[2].intensity == 100);
    CHECK(exact3(a.lights[3].position, ((double[3]){2, 1, 4})) && a.lights[3].radius == 0.25 &&
          a.lights[3].intensity == 40 && exact3(a.lights[3].color, ((double[3]){1, 0.5, 0.25})));
    /* the rect: node 5 turned -90 degrees about glTF's X, its -Z (glTF's -Y, down) is voxkit's -Z; its +X stays +X */
    CHECK(exact3(a.lights[4].position, ((double[3]){0, 3, 5})) && a.lights[4].size[0] == 2 &&
          a.lights[4].size[1] == 0.5 && a.lights[4].intensity == 10);
    CHECK(same3(a.lights[4].direction, ((double[3]){0, 0, -1}), 1e-6) &&
          same3(a.lights[4].tangent, ((double[3]){1, 0, 0}), 1e-6));
    /* the sun shines along the node's -Z turned 45 degrees down; vx_light's direction points back up to it */
    CHECK(same3(a.lights[0].direction, ((double[3]){0, -0.7071068, 0.7071068}), 1e-6));
    r = export_glb(&a, mid, NULL);
    if (!r) r = convert(mid, &b);
    remove(mid);
    if (r) vx_svo_scene_free(&a);
    REQUIRE(r == VX_OK);
    CHECKF(b.light_count == a.light_count, "%u lights back of %u", b.light_count, a.light_count);
    for (uint32_t i = 0; i < b.light_count && i < a.light_count; i++) {
        char why[256];
        CHECKF(same_light(&b.lights[i], &a.lights[i], why, sizeof why), "light %u: %s", i, why);
    }
    vx_svo_scene_free(&b);
    vx_svo_scene_free(&a);
}

/* Without lights (or with only those of emissive voxels, never written) the
 * export is what it was before lights were exported: no
 * KHR_lights_punctual, no light nodes, and both the same bytes. */
static void test_no_lights_as_before(void) {
    vx_svo_scene s;
    REQUIRE(lit_scene(&s) == VX_OK);
    vx_light voxels = {.type = VX_LIGHT_SPHERE, .color = {1, 1, 1}, .intensity = 1, .radius = 1,
                       .flags = VX_LIGHT_FROM_VOXELS};
    vx_svo_scene v[3] = {s, s, s};
    v[0].light_count = 0, v[0].lights = NULL;
    v[1].light_count = 1, v[1].lights = &voxels;
    uint8_t* bytes[3] = {NULL, NULL, NULL};
    size_t size[3] = {0, 0, 0};
    for (int k = 0; k < 3; k++) {
        char path[512];
        char tag[24];
        snprintf(tag, sizeof tag, "none%d", k);
        tmp_path(path, sizeof path, tag, "glb");
        if (export_glb(&v[k], path, NULL) == VX_OK) bytes[k] = (uint8_t*)vx_test_slurp(path, &size[k]);
        remove(path);
    }
    vx_svo_scene_free(&s);
    if (bytes[0] && bytes[1] && bytes[2]) {
        CHECK(size[0] == size[1] && memcmp(bytes[0], bytes[1], size[0]) == 0);
        const char* json = (const char*)bytes[0] + 20;
        CHECK(!strstr(json, "KHR_lights_punctual") && !strstr(json, "extensionsUsed") && !strstr(json, "\"light"));
        /* the same scene with its lights: the lights and their nodes added, the geometry's bytes (the BIN chunk) the same */
        const char* lit = (const char*)bytes[2] + 20;
        CHECK(strstr(lit, "\"extensionsUsed\":[\"KHR_lights_punctual\"]") && strstr(lit, "\"voxkit_light\""));
        uint32_t j0, j2;
        memcpy(&j0, bytes[0] + 12, 4);
        memcpy(&j2, bytes[2] + 12, 4);
        CHECK(size[0] - j0 == size[2] - j2 && memcmp(bytes[0] + 20 + j0, bytes[2] + 20 + j2, size[0] - 20 - j0) == 0);
    } else {
        CHECK(!"the three exports");
    }
    for (int k = 0; k < 3; k++) free(bytes[k]);
}

/* ---- bad input ---------------------------------------------------------------------- */

typedef struct warned {
    int count;
    char id[64], msg[256];
} warned;
static void on_log(void* user, vx_log_level level, const char* id, const char* msg) {
    warned* w = user;
    if (level != VX_LOG_WARN) return;
    w->count++;
    snprintf(w->id, sizeof w->id, "%s", id);
    snprintf(w->msg, sizeof w->msg, "%s", msg);
}

/* one light (JSON) on node 1 at the origin, read from memory */
static vx_result read_one(const char* light, const char* node_extra, vx_gltf_mesh* m, vx_error* err, warned* w) {
    char nodes[512];
    snprintf(nodes, sizeof nodes, "{%s\"extensions\":{\"KHR_lights_punctual\":{\"light\":0}}}",
             node_extra ? node_extra : "");
    char* text = gltf_text(light, nodes);
    if (!text) return VX_ERR_NOMEM;
    vx_logger lg = {on_log, w};
    vx_result r = vx_gltf_read(&(vx_gltf_read_desc){.logger = &lg}, text, strlen(text), NULL, m, err);
    free(text);
    return r;
}

/* tinygltf needs a spot light's "spot" */
#define SPOT "\"spot\":{\"outerConeAngle\":0.5},"

static void test_bad_extras(void) {
    static const char* const bad[][2] = {
        {"{\"type\":\"point\",\"extras\":{\"voxkit_light\":{\"type\":\"sphere\",\"radius\":-1,\"radiance\":1}}}",
         "\"radius\""},
        {"{\"type\":\"point\",\"extras\":{\"voxkit_light\":{\"type\":\"sphere\",\"radius\":\"big\",\"radiance\":1}}}",
         "\"radius\""},
        {"{\"type\":\"point\",\"extras\":{\"voxkit_light\":{\"type\":\"sphere\",\"radius\":1}}}", "\"radiance\""},
        {"{\"type\":\"spot\"," SPOT "\"extras\":{\"voxkit_light\":{\"type\":\"rect\",\"radiance\":1,\"size\":[1]}}}", "\"size\""},
        {"{\"type\":\"spot\"," SPOT "\"extras\":{\"voxkit_light\":{\"type\":\"rect\",\"radiance\":1}}}", "\"size\""},
        {"{\"type\":\"directional\",\"extras\":{\"voxkit_light\":{\"type\":\"directional\",\"angular_diameter\":4}}}",
         "\"angular_diameter\""},
        {"{\"type\":\"spot\"," SPOT "\"extras\":{\"voxkit_light\":{\"type\":\"spot\",\"inner_cone\":0.5,\"outer_cone\":0.4}}}",
         "cones"},
        {"{\"type\":\"point\",\"extras\":{\"voxkit_light\":{\"type\":\"point\",\"color\":[1,-1,1]}}}", "\"color\""},
        {"{\"type\":\"point\",\"extras\":{\"voxkit_light\":\"sphere\"}}", "voxkit_light"},
        {"{\"type\":\"point\",\"extras\":{\"voxkit_light\":{\"radius\":1}}}", "voxkit_light"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        vx_gltf_mesh m;
        vx_error err = {0};
        warned w = {0};
        vx_result r = read_one(bad[i][0], NULL, &m, &err, &w);
        if (r == VX_OK) vx_gltf_mesh_free(&m);
        CHECKF(r == VX_ERR_BAD_FORMAT && strstr(err.msg, "light 0") && strstr(err.msg, bad[i][1]),
               "case %zu: result %d '%s'", i, (int)r, err.msg);
    }
    /* a rect whose node has no +X axis: no tangent */
    {
        vx_gltf_mesh m;
        vx_error err = {0};
        warned w = {0};
        vx_result r = read_one("{\"type\":\"spot\"," SPOT "\"extras\":{\"voxkit_light\":{\"type\":\"rect\",\"radiance\":1,"
                               "\"size\":[1,1]}}}",
                               "\"scale\":[0,1,1],", &m, &err, &w);
        if (r == VX_OK) vx_gltf_mesh_free(&m);
        CHECKF(r == VX_ERR_BAD_FORMAT && strstr(err.msg, "tangent"), "rect without +X: %d '%s'", (int)r, err.msg);
    }
    /* a record of another type than the light (retyped in an editor), or of
     * a type this reader does not know: the punctual light, with a warning */
    static const char* const other[] = {
        "{\"type\":\"spot\",\"intensity\":2," SPOT "\"extras\":{\"voxkit_light\":{\"type\":\"sphere\",\"radius\":1,\"radiance\":5}}}",
        "{\"type\":\"spot\",\"intensity\":2," SPOT "\"extras\":{\"voxkit_light\":{\"type\":\"disc\",\"radius\":1}}}",
    };
    for (int i = 0; i < 2; i++) {
        vx_gltf_mesh m;
        vx_error err = {0};
        warned w = {0};
        vx_result r = read_one(other[i], NULL, &m, &err, &w);
        CHECKF(r == VX_OK, "other %d: %s", i, err.msg);
        if (r) continue;
        CHECK(m.light_count == 1 && m.lights[0].type == VX_GLTF_LIGHT_SPOT && !m.lights[0].voxkit &&
              m.lights[0].intensity == 2 && m.lights[0].radius == 0);
        CHECKF(w.count == 1 && !strcmp(w.id, "gltf.light_extras") && strstr(w.msg, "light 0"), "warning %d %s: %s",
               w.count, w.id, w.msg);
        vx_gltf_mesh_free(&m);
    }
    /* extras without voxkit_light, and unknown members, are not ours to judge */
    {
        vx_gltf_mesh m;
        vx_error err = {0};
        warned w = {0};
        vx_result r = read_one("{\"type\":\"point\",\"intensity\":3,\"extras\":{\"owner\":\"someone\","
                               "\"voxkit_light\":{\"type\":\"point\",\"radius\":0.5,\"future\":[1,2]}}}",
                               NULL, &m, &err, &w);
        CHECKF(r == VX_OK, "%s", err.msg);
        if (!r) {
            CHECK(m.lights[0].voxkit && m.lights[0].radius == 0.5 && m.lights[0].intensity == 3 && w.count == 0);
            vx_gltf_mesh_free(&m);
        }
    }
}

/* The writer refuses what KHR_lights_punctual forbids, naming the light. */
static void test_writer_refuses(void) {
    const vx_glb_light ok = {.name = "lamp", .type = VX_GLB_LIGHT_SPOT, .color = {1, 1, 1}, .intensity = 1,
                             .inner_cone = 0.1, .outer_cone = 0.2, .matrix = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}};
    vx_glb_light bad[5] = {ok, ok, ok, ok, ok};
    bad[0].color[1] = 1.5;                     /* the schema's [0, 1] */
    bad[1].inner_cone = bad[1].outer_cone;     /* inner < outer */
    bad[2].intensity = -1;
    bad[3].extras = "[1, 2]";                  /* extras must be an object */
    bad[4].extras = "{\"voxkit_light\": ";     /* and JSON */
    char path[512];
    tmp_path(path, sizeof path, "refuse", "glb");
    for (int i = 0; i < 5; i++) {
        vx_glb_scene gs = {.light_count = 1, .lights = &bad[i]};
        vx_error err = {0};
        vx_result r = vx_glb_write_file(NULL, &gs, path, &err);
        CHECKF(r == VX_ERR_INVALID_ARG && strstr(err.msg, "lamp"), "case %d: %d '%s'", i, (int)r, err.msg);
        CHECK(access(path, F_OK) != 0);
    }
    vx_glb_scene gs = {.light_count = 1, .lights = &ok};
    vx_error err = {0};
    CHECKF(vx_glb_write_file(NULL, &gs, path, &err) == VX_OK, "%s", err.msg);
    remove(path);
}

int main(void) {
    RUN(test_lights_read_back);
    RUN(test_lights_svo_round_trip);
    RUN(test_lights_gltf_round_trip);
    RUN(test_no_lights_as_before);
    RUN(test_bad_extras);
    RUN(test_writer_refuses);
    return vx_test_finish();
}
