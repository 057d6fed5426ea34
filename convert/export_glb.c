/* convert/export_glb.c - vx_conv_svo_to_glb_file (convert/export.h):
 * decode each model, greedy-mesh its surface (formats/voxmesh.h), write with
 * formats/glb.h.
 *
 * Materials: a cell's material id is vx_svo_attr_material (its
 * VX_ATTR_MATERIAL value, else its palette index). Ids whose MATL record
 * resolves to something other than a plain diffuse (metal, glass, or any
 * type with emission > 0) get a glTF material each; every other cell draws
 * with the default material 0 (white, roughness 1, metallic 0), and a scene
 * with no such id is written exactly as before materials were exported.
 * The mesher keeps the ids apart (a quad covers one id) and each mesh has
 * one primitive per material, its quads sorted by material. Base colour
 * stays white: the vertex colours carry the colour.
 *
 * Lights: the stored ones as KHR_lights_punctual lights on nodes of their
 * own (formats/glb.h and convert/export.h say how each type maps;
 * light_to_glb below).
 *
 * Sky: a sky other than DEFAULT as voxkit's record in the scene's extras
 * (sky_text below; convert/export.h). */
#include "convert/export.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "formats/glb.h"
#include "formats/voxmesh.h"
#include "convert/export_internal.h"

typedef struct mesh_data {
    float* pos;
    vx_glb_primitive* prims; /* .material: table index + 1 (0 default) until the glTF indices are known */
    uint32_t prim_count;
    uint16_t* color;
    uint32_t* index;
    size_t vertices, indices;
    char name[32];
} mesh_data;

static double now(void) {
    struct timespec t;
    timespec_get(&t, TIME_UTC);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* Whether a resolved record gets a glTF material of its own (metal, glass,
 * or any emission); the rest draw with the default. */
static bool exported(const vx_material* m) { return m->type != VX_MATERIAL_DIFFUSE || m->emission > 0; }

/* Sorting quads by material, the mesher's order kept within one (the
 * output must not depend on qsort's handling of equal keys). */
typedef struct quad_ref {
    uint32_t material;
    size_t at;
} quad_ref;
static int quad_ref_cmp(const void* a, const void* b) {
    const quad_ref *p = a, *q = b;
    if (p->material != q->material) return p->material < q->material ? -1 : 1;
    return (p->at > q->at) - (p->at < q->at);
}

/* With materials (quads' material = table index + 1, 0 the default): the
 * quads sorted by material and md->prims one index range per material. */
static vx_result sort_by_material(const vx_allocator* A, vx_voxmesh* vm, mesh_data* md, vx_error* err) {
    size_t nq = vm->quad_count;
    quad_ref* ref = (quad_ref*)vx_calloc(A, nq, sizeof(quad_ref));
    vx_voxmesh_quad* sorted = (vx_voxmesh_quad*)vx_calloc(A, nq, sizeof(vx_voxmesh_quad));
    if (!ref || !sorted) {
        vx_free(A, ref);
        vx_free(A, sorted);
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %zu quads", nq);
    }
    for (size_t q = 0; q < nq; q++) ref[q] = (quad_ref){vm->quads[q].material, q};
    qsort(ref, nq, sizeof *ref, quad_ref_cmp);
    uint32_t n = 0;
    for (size_t q = 0; q < nq; q++) {
        sorted[q] = vm->quads[ref[q].at];
        n += q == 0 || ref[q].material != ref[q - 1].material;
    }
    vx_free(A, ref);
    memcpy(vm->quads, sorted, nq * sizeof *sorted);
    vx_free(A, sorted);
    md->prims = (vx_glb_primitive*)vx_calloc(A, n, sizeof(vx_glb_primitive));
    if (!md->prims) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %u primitives", n);
    for (size_t q = 0; q < nq; q++) {
        if (q == 0 || vm->quads[q].material != vm->quads[q - 1].material)
            md->prims[md->prim_count++] = (vx_glb_primitive){.index_first = 6 * q, .material = vm->quads[q].material};
        md->prims[md->prim_count - 1].index_count += 6;
    }
    return VX_OK;
}

/* The quads as triangles: 4 corners each, counter-clockwise from outside (no
 * normals: glTF viewers compute flat ones, which these are). */
static vx_result quads_to_mesh(const vx_allocator* A, const vx_voxmesh* vm, const uint16_t lin[256], mesh_data* md,
                               vx_error* err) {
    size_t nq = vm->quad_count;
    md->vertices = 4 * nq;
    md->indices = 6 * nq;
    md->pos = (float*)vx_calloc(A, md->vertices, 3 * sizeof(float));
    md->color = (uint16_t*)vx_calloc(A, md->vertices, 4 * sizeof(uint16_t));
    md->index = (uint32_t*)vx_calloc(A, md->indices, sizeof(uint32_t));
    if (!md->pos || !md->color || !md->index)
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %zu quads", nq);
    for (size_t q = 0; q < nq; q++) {
        const vx_voxmesh_quad* Q = &vm->quads[q];
        uint32_t a = Q->axis, ua = (a + 1) % 3, va = (a + 2) % 3;
        const uint32_t uv[4][2] = {{Q->u0, Q->v0}, {Q->u1, Q->v0}, {Q->u1, Q->v1}, {Q->u0, Q->v1}};
        uint16_t rgba[4] = {lin[Q->rgba & 0xFF], lin[(Q->rgba >> 8) & 0xFF], lin[(Q->rgba >> 16) & 0xFF],
                            (uint16_t)((Q->rgba >> 24) * 257u)};
        for (int k = 0; k < 4; k++) {
            size_t v = 4 * q + (size_t)k;
            md->pos[3 * v + a] = (float)Q->plane;
            md->pos[3 * v + ua] = (float)uv[k][0];
            md->pos[3 * v + va] = (float)uv[k][1];
            memcpy(md->color + 4 * v, rgba, sizeof rgba);
        }
        static const uint32_t front[6] = {0, 1, 2, 0, 2, 3}, back[6] = {0, 2, 1, 0, 3, 2};
        for (int k = 0; k < 6; k++) md->index[6 * q + (size_t)k] = (uint32_t)(4 * q) + (Q->positive ? front : back)[k];
    }
    return VX_OK;
}

/* ---- lights ------------------------------------------------------------------------ */

static const char* const light_type_name[VX_LIGHT_TYPE_COUNT] = {"directional", "point", "spot", "sphere", "rect"};

/* voxkit's +Z up to glTF's +Y up, (x, y, z) -> (x, z, -y), as the mesh nodes */
static void to_gltf(const double v[3], double o[3]) {
    o[0] = v[0];
    o[1] = v[2];
    o[2] = -v[1];
}

static double dot3(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/* The node placing a light at p: with d (where it shines, any length) its -Z
 * along d and its +X along x_hint made orthogonal to d (NULL: the world axis
 * most across d), +Y completing a right-handed frame; without d the identity
 * rotation. A rotation, so glTF validators see a proper TRS matrix, and
 * reading -Z back gives d normalized. */
static void light_matrix(const double p[3], const double* d, const double* x_hint, double M[16]) {
    double x[3] = {1, 0, 0}, y[3] = {0, 1, 0}, z[3] = {0, 0, 1};
    if (d) {
        double dl = sqrt(dot3(d, d)), h[3] = {0, 0, 0};
        for (int k = 0; k < 3; k++) z[k] = -d[k] / dl;
        if (x_hint) {
            memcpy(h, x_hint, sizeof h);
        } else {
            int a = 0;
            for (int k = 1; k < 3; k++)
                if (fabs(z[k]) < fabs(z[a])) a = k;
            h[a] = 1;
        }
        double hz = dot3(h, z);
        for (int k = 0; k < 3; k++) x[k] = h[k] - hz * z[k];
        double xl = sqrt(dot3(x, x));
        for (int k = 0; k < 3; k++) x[k] /= xl;
        y[0] = z[1] * x[2] - z[2] * x[1];
        y[1] = z[2] * x[0] - z[0] * x[2];
        y[2] = z[0] * x[1] - z[1] * x[0];
    }
    memset(M, 0, 16 * sizeof *M);
    for (int k = 0; k < 3; k++) {
        M[k] = x[k];
        M[4 + k] = y[k];
        M[8 + k] = z[k];
        M[12 + k] = p[k];
    }
    M[15] = 1;
}

const char* vx_conv_glb_light_approx(const vx_light* l) {
    switch (l->type) {
    case VX_LIGHT_SPHERE: return "sphere light as a point light of the same power (I = L pi r^2)";
    case VX_LIGHT_RECT: return "rect light as a spot along its normal (outer cone 90 degrees, I = L A)";
    case VX_LIGHT_DIRECTIONAL:
        return l->angular_diameter > 0 ? "sun without its angular diameter (glTF's is a hard sun)" : NULL;
    case VX_LIGHT_SPOT:
        if (!(l->inner_cone < l->outer_cone)) return "spot with its inner cone nudged below the outer (glTF needs inner < outer)";
        return l->radius > 0 ? "spot without its radius (glTF's is a point source)" : NULL;
    case VX_LIGHT_POINT: return l->radius > 0 ? "point light without its radius (glTF's is a point source)" : NULL;
    default: return NULL;
    }
}

/* a light's node name and its extras' JSON text */
typedef struct light_text {
    char name[24];
    char extras[768];
} light_text;

/* A JSON text being appended to (a light's or the sky's extras): s holds cap
 * bytes and stays terminated; at is its length. A text that did not fit ends
 * cut at cap - 1 (the callers' field counts and %.17g's 24 characters rule
 * that out; the writer would refuse the cut text as JSON). */
typedef struct json_text {
    char* s;
    size_t cap, at;
} json_text;

static void put(json_text* j, const char* fmt, ...) __attribute__((format(printf, 2, 3)));
static void put(json_text* j, const char* fmt, ...) {
    if (j->at >= j->cap - 1) return;
    va_list ap;
    va_start(ap, fmt);
    int k = vsnprintf(j->s + j->at, j->cap - j->at, fmt, ap);
    va_end(ap);
    j->at = k < 0 ? j->cap - 1 : j->at + (size_t)k < j->cap - 1 ? j->at + (size_t)k : j->cap - 1;
}

/* Appends `,"key":v` (or an array of n values); %.17g reads back as the
 * same double, and -0 is written "-0.0" because JSON readers take "-0" for
 * the integer 0 (it would come back +0). */
static void put_num(json_text* j, const char* key, const double* v, int n) {
    put(j, ",\"%s\":%s", key, n > 1 ? "[" : "");
    for (int k = 0; k < n; k++) {
        if (v[k] == 0 && signbit(v[k])) put(j, "%s-0.0", k ? "," : "");
        else put(j, "%s%.17g", k ? "," : "", v[k]);
    }
    if (n > 1) put(j, "]");
}

/* Light l (a valid record, index i in the scene) as KHR_lights_punctual
 * (glb.h): g's strings point into t. */
static void light_to_glb(const vx_light* l, uint32_t i, vx_glb_light* g, light_text* t) {
    memset(g, 0, sizeof *g);
    snprintf(t->name, sizeof t->name, "light %u", i);
    g->name = t->name;
    json_text j = {t->extras, sizeof t->extras, 0};
    put(&j, "{\"voxkit_light\":{\"type\":\"%s\"", light_type_name[l->type]);
    bool extras = false; /* the punctual light is not the exact record */
    /* the extension's colour lies in [0, 1]: a brighter channel goes into
     * the intensity (every renderer multiplies the two), the exact values
     * into extras */
    double big = fmax(l->color[0], fmax(l->color[1], l->color[2])), scale = big > 1 ? big : 1;
    for (int k = 0; k < 3; k++) g->color[k] = l->color[k] / scale;
    double p[3], d[3], x[3], back[3] = {-l->direction[0], -l->direction[1], -l->direction[2]};
    to_gltf(l->position, p);
    g->intensity = l->intensity * scale;
    switch (l->type) {
    case VX_LIGHT_DIRECTIONAL: /* vx_light's direction points towards the light; glTF's light travels along -Z */
        g->type = VX_GLB_LIGHT_DIRECTIONAL;
        to_gltf(back, d);
        light_matrix(p, d, NULL, g->matrix);
        if (l->angular_diameter > 0) put_num(&j, "angular_diameter", &l->angular_diameter, 1), extras = true;
        break;
    case VX_LIGHT_POINT:
        g->type = VX_GLB_LIGHT_POINT;
        g->range = l->range;
        light_matrix(p, NULL, NULL, g->matrix);
        if (l->radius > 0) put_num(&j, "radius", &l->radius, 1), extras = true;
        break;
    case VX_LIGHT_SPOT:
        g->type = VX_GLB_LIGHT_SPOT;
        g->range = l->range;
        g->inner_cone = l->inner_cone, g->outer_cone = l->outer_cone;
        if (!(g->inner_cone < g->outer_cone)) {
            /* glTF needs inner < outer; voxkit allows them equal (a hard
             * edge). The inner cone goes a millionth of the outer below it
             * (both 0: the outer up to 1e-6 radians): voxkit's renderers
             * widen a falloff narrower than 0.001 in cosine to that anyway,
             * so the light looks the same. The exact cones go into extras. */
            if (g->outer_cone > 0) g->inner_cone = g->outer_cone * (1 - 1e-6);
            else g->outer_cone = 1e-6;
            put_num(&j, "inner_cone", &l->inner_cone, 1);
            put_num(&j, "outer_cone", &l->outer_cone, 1);
            extras = true;
        }
        to_gltf(l->direction, d);
        light_matrix(p, d, NULL, g->matrix);
        if (l->radius > 0) put_num(&j, "radius", &l->radius, 1), extras = true;
        break;
    case VX_LIGHT_SPHERE:
        /* seen from afar a sphere of radiance L and radius r is a point of
         * intensity L pi r^2 (its projected disc, every direction) */
        g->type = VX_GLB_LIGHT_POINT;
        g->intensity = l->intensity * 3.141592653589793 * l->radius * l->radius * scale;
        light_matrix(p, NULL, NULL, g->matrix);
        put_num(&j, "radiance", &l->intensity, 1);
        put_num(&j, "radius", &l->radius, 1);
        extras = true;
        break;
    case VX_LIGHT_RECT: {
        /* a one-sided Lambertian emitter of radiance L and area A: on its
         * axis intensity L A, falling off as cos theta to 0 at 90 degrees;
         * the spot's smooth falloff from 0 to pi/2 stands in for the cosine */
        g->type = VX_GLB_LIGHT_SPOT;
        g->intensity = l->intensity * l->size[0] * l->size[1] * scale;
        g->inner_cone = 0, g->outer_cone = 1.5707963267948966;
        to_gltf(l->direction, d);
        to_gltf(l->tangent, x);
        light_matrix(p, d, x, g->matrix); /* the node's +X: the first edge */
        put_num(&j, "radiance", &l->intensity, 1);
        put_num(&j, "size", l->size, 2);
        extras = true;
        break;
    }
    default: break;
    }
    if (scale > 1) {
        put_num(&j, "color", l->color, 3);
        if (l->type != VX_LIGHT_SPHERE && l->type != VX_LIGHT_RECT) put_num(&j, "intensity", &l->intensity, 1);
        extras = true;
    }
    put(&j, "}}");
    g->extras = extras ? t->extras : NULL;
}

/* ---- sky ---------------------------------------------------------------------------- */

/* Whether s is well-formed UTF-8 (JSON text must be; a Linux file name need
 * not be, and the writer's parser would refuse it without naming it). */
static bool utf8_ok(const unsigned char* s) {
    while (*s) {
        unsigned c = *s, n = c < 0x80 ? 0 : (c & 0xE0) == 0xC0 ? 1 : (c & 0xF0) == 0xE0 ? 2 : (c & 0xF8) == 0xF0 ? 3 : 4;
        if (n == 4 || (n == 1 && c < 0xC2)) return false;
        for (unsigned k = 1; k <= n; k++)
            if ((s[k] & 0xC0) != 0x80) return false;
        s += n + 1;
    }
    return true;
}

/* The scene's sky as the extras text {"voxkit_sky":{...}} (convert/export.h)
 * in t (cap bytes), or t = "" for the DEFAULT sky; sky is the one to write
 * (its path already rebased for the .glb's folder). */
static vx_result sky_text(const vx_sky* k, char* t, size_t cap, vx_error* err) {
    t[0] = 0;
    if (k->type == VX_SKY_DEFAULT) return VX_OK;
    static const char* const name[VX_SKY_TYPE_COUNT] = {"default", "constant", "gradient", "envmap"};
    json_text j = {t, cap, 0};
    put(&j, "{\"voxkit_sky\":{\"type\":\"%s\"", name[k->type]);
    if (k->type == VX_SKY_CONSTANT || k->type == VX_SKY_GRADIENT) put_num(&j, "color", k->color, 3);
    if (k->type == VX_SKY_GRADIENT) {
        put_num(&j, "horizon", k->horizon, 3);
        put_num(&j, "ground", k->ground, 3);
    }
    if (k->type == VX_SKY_ENVMAP) {
        if (!utf8_ok((const unsigned char*)k->path))
            return vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET,
                           "glb export: the sky's environment map path is not UTF-8 (glTF's JSON must be)");
        /* the path as a JSON string: quotes, backslashes and control bytes escaped */
        put(&j, ",\"path\":\"");
        for (const unsigned char* p = (const unsigned char*)k->path; *p; p++)
            put(&j, *p == '"' || *p == '\\' ? "\\%c" : *p < 0x20 ? "\\u%04x" : "%c", *p);
        put(&j, "\"");
        put_num(&j, "intensity", &k->intensity, 1);
        put_num(&j, "rotation", &k->rotation, 1);
    }
    put(&j, "}}");
    /* 9 numbers of at most 24 characters, or a path of 255 bytes escaped to
     * at most 6 each, fit the caller's buffer: this is a guard, not a limit */
    if (j.at >= cap - 1) return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "glb export: the sky's record does not fit %zu bytes", cap);
    return VX_OK;
}

vx_result vx_conv_svo_to_glb_file(const vx_conv_export_desc* xd, const vx_svo_scene* s, const char* path,
                                  vx_conv_glb_stats* stats, vx_error* err) {
    if (!s || !path) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "glb export: NULL argument");
    const vx_write_desc* desc = xd ? xd->write : NULL;
    bool all = xd && xd->all;
    /* the sky first: a bad one fails before the meshing's work */
    vx_sky sky = s->sky; /* its map's path rebased for the .glb's folder */
    char sky_json[2048];
    vx_result sr = vx_sky_validate(&sky, err);
    if (!sr && xd && xd->svo_path) sr = vx_sky_rebase(&sky, xd->svo_path, path, err);
    if (sr) return vx_error_prefix(err, "glb export"), sr;
    if ((sr = sky_text(&sky, sky_json, sizeof sky_json, err))) return sr;
    const vx_allocator* A = desc ? desc->alloc : NULL;
    double lind[256];
    vx__export_srgb_to_linear(lind);
    uint16_t lin[256]; /* sRGB byte -> linear, 65535 = 1 */
    for (int i = 0; i < 256; i++) lin[i] = (uint16_t)lround(65535.0 * lind[i]);
    vx_conv_glb_stats st = {0};
    vx_svo_material_table tab = {0};
    vx_glb_material* gmat = NULL;
    uint32_t* cell_mat = NULL; /* per cell of the model at hand: table index + 1, 0 default */
    size_t cell_mat_cap = 0;
    double* emit_sum = NULL;   /* per table entry: linear RGB sum and cell count of its cells */
    int32_t* gl_index = NULL;  /* per table entry + 1: glTF material index, -1 unused */
    char(*mat_names)[24] = NULL;
    vx_glb_light* glights = NULL;
    light_text* ltext = NULL;
    vx_result r = vx_svo_material_table_make(s, A, &tab, err);
    if (r) return r;
    bool materials = false; /* some table entry is more than a plain diffuse */
    for (uint32_t k = 0; k < tab.count; k++)
        materials |= exported(&tab.mats[k]);
    mesh_data* md = (mesh_data*)vx_calloc(A, s->model_count ? s->model_count : 1, sizeof(mesh_data));
    int32_t* mesh_of = (int32_t*)vx_calloc(A, s->model_count ? s->model_count : 1, sizeof(int32_t));
    vx_glb_mesh* meshes = (vx_glb_mesh*)vx_calloc(A, s->model_count ? s->model_count : 1, sizeof(vx_glb_mesh));
    vx_glb_node* nodes = (vx_glb_node*)vx_calloc(A, s->instance_count ? s->instance_count : 1, sizeof(vx_glb_node));
    char(*names)[80] = vx_calloc(A, s->instance_count ? s->instance_count : 1, 80);
    if (materials) {
        emit_sum = (double*)vx_calloc(A, tab.count, 4 * sizeof(double));
        gl_index = (int32_t*)vx_calloc(A, (size_t)tab.count + 1, sizeof(int32_t));
        gmat = (vx_glb_material*)vx_calloc(A, (size_t)tab.count + 1, sizeof(vx_glb_material));
        mat_names = vx_calloc(A, (size_t)tab.count + 1, sizeof *mat_names);
    }
    if (!md || !mesh_of || !meshes || !nodes || !names || (materials && (!emit_sum || !gl_index || !gmat || !mat_names))) {
        r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory");
        goto done;
    }
    double t0 = now();
    for (uint32_t i = 0; i < s->model_count; i++) mesh_of[i] = -2; /* -2: no node shows it */
    for (uint32_t i = 0; i < s->instance_count; i++)
        if (s->instances[i].model < s->model_count && (all || vx_svo_instance_visible(s, i)))
            mesh_of[s->instances[i].model] = -1;
    for (uint32_t i = 0; i < s->model_count; i++) {
        if (mesh_of[i] == -2) continue; /* a mesh no node uses (glTF validators flag it) */
        vx__export_cells c = {0};
        r = vx__export_cells_decode(A, s, i, &c, err);
        vx_voxmesh vm = {0};
        bool any = false; /* a cell of this model with a non-default material */
        if (r == VX_OK && materials && c.n) {
            if (!vx_grow(A, (void**)&cell_mat, &cell_mat_cap, c.n, sizeof(uint32_t)))
                r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %zu cells", c.n);
            for (size_t k = 0; r == VX_OK && k < c.n; k++) {
                const vx_material* mt =
                    vx_svo_material_table_find(&tab, vx_svo_attr_material(&s->models[i], c.attr[k]));
                uint32_t t = mt && exported(mt)
                                 ? (uint32_t)(mt - tab.mats) + 1
                                 : 0;
                cell_mat[k] = t;
                if (!t) continue;
                any = true;
                /* the mean linear colour of an id's cells: its emission colour
                 * where the record has none (MagicaVoxel: colour x _emit) */
                double* e = emit_sum + 4 * (t - 1);
                for (int ch = 0; ch < 3; ch++) e[ch] += lind[c.rgba[k] >> (8 * ch) & 0xFF];
                e[3] += 1;
            }
        }
        if (r == VX_OK) r = vx_voxmesh_build_material(A, c.xyz, c.rgba, any ? cell_mat : NULL, c.n, &vm, err);
        vx__export_cells_free(&c);
        if (r == VX_OK && vm.quad_count) {
            mesh_data* d = &md[st.meshes];
            if (any) r = sort_by_material(A, &vm, d, err);
            if (r == VX_OK) r = quads_to_mesh(A, &vm, lin, d, err);
            snprintf(d->name, sizeof d->name, "model %u", i);
            meshes[st.meshes] = (vx_glb_mesh){.name = d->name,
                                              .vertex_count = d->vertices,
                                              .pos = d->pos,
                                              .color = d->color,
                                              .index_count = d->indices,
                                              .index = d->index,
                                              .primitive_count = d->prim_count,
                                              .primitives = d->prims};
            mesh_of[i] = (int32_t)st.meshes++;
            st.quads += vm.quad_count;
            st.faces += vm.faces;
        }
        vx_voxmesh_free(&vm);
        if (r) goto done;
    }
    st.seconds_mesh = now() - t0;
    for (uint32_t i = 0; i < s->instance_count; i++) {
        const vx_svo_instance* in = &s->instances[i];
        if (in->model >= s->model_count || !(all || vx_svo_instance_visible(s, i))) continue;
        vx_glb_node* n = &nodes[st.nodes];
        double w[12];
        vx_svo_instance_world(s, in, w);
        /* voxkit's +Z up to glTF's +Y up: (x, y, z) -> (x, z, -y), the inverse
         * of the glTF import's turn (convert/mesh.h) */
        for (int col = 0; col < 4; col++) {
            n->matrix[col * 4 + 0] = w[col];
            n->matrix[col * 4 + 1] = w[8 + col];
            n->matrix[col * 4 + 2] = -w[4 + col];
        }
        n->matrix[15] = 1.0;
        n->mesh = mesh_of[in->model];
        if (in->name[0]) snprintf(names[st.nodes], 80, "%s", in->name);
        else snprintf(names[st.nodes], 80, "instance %u", i);
        n->name = names[st.nodes];
        st.nodes++;
    }
    uint32_t gcount = 0;
    if (materials) {
        /* glTF material 0 is the default; then one per table entry some
         * primitive uses, in id order */
        gmat[gcount++] = (vx_glb_material){
            .name = "voxel", .base_color = {1, 1, 1, 1}, .metallic = 0, .roughness = 1};
        for (uint32_t k = 0; k <= tab.count; k++) gl_index[k] = k ? -1 : 0;
        for (uint32_t m = 0; m < st.meshes; m++)
            for (uint32_t p = 0; p < md[m].prim_count; p++)
                if (md[m].prims[p].material) gl_index[md[m].prims[p].material] = 1;
        for (uint32_t k = 1; k <= tab.count; k++) {
            if (gl_index[k] < 0) continue;
            const vx_material* mt = &tab.mats[k - 1];
            gl_index[k] = (int32_t)gcount;
            vx_glb_material* g = &gmat[gcount++];
            snprintf(mat_names[gcount - 1], sizeof mat_names[0], "material %u", tab.ids[k - 1]);
            *g = (vx_glb_material){
                .name = mat_names[gcount - 1], .base_color = {1, 1, 1, 1}, .roughness = (float)mt->roughness};
            if (mt->type == VX_MATERIAL_METAL) g->metallic = (float)mt->metalness;
            if (mt->type == VX_MATERIAL_GLASS) {
                g->transmission = (float)mt->transmission;
                g->ior = (float)mt->ior;
            }
            if (mt->emission > 0) {
                /* glTF's emission does not multiply the base colour: the
                 * record's emission colour x strength, or where it has none
                 * (MagicaVoxel's rule, the voxel's colour x strength) the mean
                 * linear colour of the id's cells, exact for .vox scenes where
                 * a palette index is one colour and one material */
                const double* ec = mt->emission_color;
                double mean[3], e[3], big = 0;
                const double* sum = emit_sum + 4 * (k - 1);
                for (int ch = 0; ch < 3; ch++) mean[ch] = sum[3] > 0 ? sum[ch] / sum[3] : 1.0;
                bool own = ec[0] > 0 || ec[1] > 0 || ec[2] > 0;
                for (int ch = 0; ch < 3; ch++) {
                    e[ch] = (own ? ec[ch] : mean[ch]) * mt->emission;
                    if (e[ch] > big) big = e[ch];
                }
                /* the factor at most 1, the rest in the strength */
                double scale = big > 1 ? big : 1;
                for (int ch = 0; ch < 3; ch++) g->emissive[ch] = (float)(e[ch] / scale);
                if (big > 1) g->emissive_strength = (float)big;
            }
        }
        for (uint32_t m = 0; m < st.meshes; m++)
            for (uint32_t p = 0; p < md[m].prim_count; p++)
                md[m].prims[p].material = (uint32_t)gl_index[md[m].prims[p].material];
    }
    if (s->light_count) {
        glights = (vx_glb_light*)vx_calloc(A, s->light_count, sizeof *glights);
        ltext = (light_text*)vx_calloc(A, s->light_count, sizeof *ltext);
        if (!glights || !ltext) {
            r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %u lights", s->light_count);
            goto done;
        }
    }
    for (uint32_t i = 0; i < s->light_count; i++) {
        const vx_light* l = &s->lights[i];
        if (l->flags & VX_LIGHT_FROM_VOXELS) continue; /* the voxels' own emission is in the meshes' materials */
        if ((r = vx_light_validate(l, i, err))) goto done;
        light_to_glb(l, i, &glights[st.lights], &ltext[st.lights]);
        st.lights++;
        st.lights_approximated += vx_conv_glb_light_approx(l) != NULL;
    }
    vx_glb_scene gs = {.mesh_count = st.meshes,
                       .material_count = gcount,
                       .materials = gmat,
                       .meshes = meshes,
                       .node_count = st.nodes,
                       .nodes = nodes,
                       .light_count = st.lights,
                       .lights = glights,
                       .generator = "voxkit " VX_VERSION_STRING,
                       .scene_extras = sky_json[0] ? sky_json : NULL};
    st.materials = gcount;
    r = vx_glb_write_file(desc, &gs, path, err);
    if (r == VX_OK && stats) *stats = st;
done:
    if (md)
        for (uint32_t i = 0; i < s->model_count; i++) {
            vx_free(A, md[i].pos);
            vx_free(A, md[i].color);
            vx_free(A, md[i].index);
            vx_free(A, md[i].prims);
        }
    vx_free(A, cell_mat);
    vx_free(A, emit_sum);
    vx_free(A, gl_index);
    vx_free(A, gmat);
    vx_free(A, mat_names);
    vx_free(A, glights);
    vx_free(A, ltext);
    vx_svo_material_table_free(&tab);
    vx_free(A, md);
    vx_free(A, mesh_of);
    vx_free(A, meshes);
    vx_free(A, nodes);
    vx_free(A, names);
    return r;
}
