/* render/pipeline.c - a frame as an ordered list of passes (render/pipeline.h):
 * pass-list parsing, the per-scene buffers, recording every pass of every
 * sample into one command buffer with a timestamp pair around each dispatch
 * (split only where a gi method submits its own work), and the readback. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "render/pipeline.h"
#include "render/render_internal.h"

#include "ao.comp.h"
#include "cull.comp.h"
#include "direct.comp.h"
#include "frame.comp.h"
#include "frame_display.comp.h"
#include "gbuffer.comp.h"
#include "post.comp.h"
#include "post_display.comp.h"
#include "resolve.comp.h"
#include "resolve_display.comp.h"

/* ---- pass lists ---------------------------------------------------------------------- */

static const char* const pass_names[VX_PASS_KIND_COUNT] = {"gbuffer", "dof", "direct", "gi", "ao", "aa", "tonemap"};
/* Order rank of each pass: a list must not decrease (direct, gi, ao share one). */
static const int pass_rank[VX_PASS_KIND_COUNT] = {0, 1, 2, 2, 2, 3, 4};

const char* vx_pass_name(vx_pass_kind k) { return (unsigned)k < VX_PASS_KIND_COUNT ? pass_names[k] : "?"; }

bool vx_pass_list_has(const vx_pass_list* l, vx_pass_kind k) {
    for (uint32_t i = 0; l && i < l->count; i++)
        if (l->kinds[i] == k) return true;
    return false;
}

vx_result vx_pass_list_parse(const char* s, vx_pass_list* out, vx_error* err) {
    if (!s || !out) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    vx_pass_list l = {0};
    snprintf(l.gi, sizeof l.gi, "none");
    const char* p = s;
    while (*p) {
        const char* e = strchr(p, ',');
        size_t n = e ? (size_t)(e - p) : strlen(p);
        char item[64];
        if (n == 0) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "empty pass name in '%s'", s);
        if (n >= sizeof item) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "pass name too long in '%s'", s);
        memcpy(item, p, n);
        item[n] = 0;
        char* arg = strchr(item, '=');
        if (arg) *arg++ = 0;
        int k = -1;
        for (int i = 0; i < VX_PASS_KIND_COUNT; i++)
            if (!strcmp(item, pass_names[i])) k = i;
        if (k < 0) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "unknown pass '%s'", item);
        if (k == VX_PASS_GI) {
            if (!arg || !*arg)
                return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "pass 'gi' needs a method: gi=NAME");
            if (strlen(arg) >= sizeof l.gi)
                return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "gi method name too long");
            snprintf(l.gi, sizeof l.gi, "%s", arg);
        } else if (arg) {
            return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "pass '%s' takes no '=' argument", item);
        }
        if (vx_pass_list_has(&l, (vx_pass_kind)k))
            return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "pass '%s' appears twice", item);
        if (l.count && pass_rank[l.kinds[l.count - 1]] > pass_rank[k])
            return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "pass '%s' is misplaced: it must come before '%s'",
                           item, pass_names[l.kinds[l.count - 1]]);
        if (k != VX_PASS_GBUFFER && !vx_pass_list_has(&l, VX_PASS_GBUFFER))
            return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "pass '%s' needs 'gbuffer' before it", item);
        l.kinds[l.count++] = (vx_pass_kind)k;
        p += n;
        if (*p == ',') p++;
    }
    if (!strcmp(l.gi, "none") && vx_pass_list_has(&l, VX_PASS_GI)) { /* gi=none: no pass at all */
        uint32_t j = 0;
        for (uint32_t i = 0; i < l.count; i++)
            if (l.kinds[i] != VX_PASS_GI) l.kinds[j++] = l.kinds[i];
        l.count = j;
    }
    *out = l;
    return VX_OK;
}

void vx_pass_list_format(const vx_pass_list* l, char* buf, size_t size) {
    if (!size) return;
    buf[0] = 0;
    size_t at = 0;
    for (uint32_t i = 0; l && i < l->count && at < size; i++) {
        int n = l->kinds[i] == VX_PASS_GI ? snprintf(buf + at, size - at, "%sgi=%s", i ? "," : "", l->gi)
                                          : snprintf(buf + at, size - at, "%s%s", i ? "," : "", pass_names[l->kinds[i]]);
        if (n < 0) break;
        at += (size_t)n;
    }
}

static const char* const show_names[VX_SHOW_COUNT] = {"final", "albedo", "normal",   "depth",   "direct",
                                                       "gi",    "ao",     "instance", "material"};

const char* vx_show_name(vx_show s) { return (unsigned)s < VX_SHOW_COUNT ? show_names[s] : "?"; }

bool vx_show_parse(const char* s, vx_show* out) {
    for (int i = 0; s && i < VX_SHOW_COUNT; i++)
        if (!strcmp(s, show_names[i])) {
            *out = (vx_show)i;
            return true;
        }
    return false;
}

vx_frame_desc vx_frame_desc_defaults(void) {
    vx_frame_desc d = {0};
    d.base = vx_render_desc_defaults();
    d.ao_rays = 4;
    d.edge_threshold = 0.1;
    d.sky[0] = 0.31, d.sky[1] = 0.375, d.sky[2] = 0.46; /* the probe bake's sky (probes.h) */
    d.shadow_lights = VX_SHADOW_LIGHTS_DEFAULT; /* light_cutoff stays 0: it follows the exposure */
    return d;
}

static const char* const culling_names[VX_LIGHT_CULLING_COUNT] = {"auto", "brute", "tiled", "clustered"};

const char* vx_light_culling_name(vx_light_culling c) {
    return (unsigned)c < VX_LIGHT_CULLING_COUNT ? culling_names[c] : "?";
}

bool vx_light_culling_parse(const char* s, vx_light_culling* out) {
    for (int i = 0; s && i < VX_LIGHT_CULLING_COUNT; i++)
        if (!strcmp(s, culling_names[i])) {
            *out = (vx_light_culling)i;
            return true;
        }
    return false;
}

/* ---- the renderer -------------------------------------------------------------------- */

enum { B_GB0, B_GB1, B_GB2, B_DIRECT, B_AO, B_GI, B_ACC, B_EMIT, B_OUT2, B_LIGHTS, B_CULL, B_LIDX, B_SKY, B_MAT, B_COUNT };
/* 0-19 the passes' (passes_common.glsl), 20-22 the sun's depth map (smap_lookup.glsl: the direct pass's sun
 * rays), 23 the records' materials (pass_bodies.glsl MAT_BINDING: metal seen directly), 24 the models' grids
 * (pass_grid.glsl: the grid walk), then a display variant's 25 and 26 (display_out.glsl) */
#define NBIND 25
_Static_assert(NBIND + 2 <= VX_GPU_MAX_BINDINGS, "pass shaders use 27 bindings");
/* the side of the GGX albedo table after the material records (pass_bodies.glsl MAT_ENV_N) */
#define MAT_ENV_N 32
/* the specialisation constants: the tracer's ids 0-10, then 11 SMAP (smap_lookup.glsl), 12 unused (trace.comp's
 * miss pass), 13 GRID (grid_walk.glsl: the kernels that trace, pass_grid.glsl) */
enum { PASS_SPEC_SMAP = VX__SPEC_TRACE_IDS, PASS_SPEC_GRID = VX__SPEC_TRACE_IDS + 2, PASS_SPECS };

/* The light grid (render/pipeline.h, shaders/passes_common.glsl). */
enum { CLUSTER_TILE = 32, CLUSTER_SLICES = 32, TILED_TILE = 16 /* = cull.comp's depth step: 256 pixels a tile */ };

/* std430 layout of a light in passes_common.glsl */
typedef struct gpu_light {
    float a[4], b[4], c[4], d[4], e[4], f[4];
} gpu_light;

static double dot3(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/* The reach R of a light (pipeline.h): range, or where its irradiance falls
 * to `cutoff`; 0 for directional lights (everywhere) and dark lights. */
static double light_reach(const vx_light* l, double cutoff) {
    double m = fmax(l->color[0], fmax(l->color[1], l->color[2])) * l->intensity;
    if (l->type == VX_LIGHT_DIRECTIONAL || !(m > 0)) return 0;
    if ((l->type == VX_LIGHT_POINT || l->type == VX_LIGHT_SPOT) && l->range > 0) return l->range;
    if (l->type == VX_LIGHT_SPHERE) return fmax(l->radius * sqrt(3.141592653589793 * m / cutoff), l->radius * 1.001);
    if (l->type == VX_LIGHT_RECT) {
        double area = l->size[0] * l->size[1];
        return 0.5 * hypot(l->size[0], l->size[1]) + sqrt(m * area / cutoff);
    }
    return sqrt(m / cutoff);
}

static void pack_light(const vx_light* l, const double ref[3], double cutoff, gpu_light* o) {
    memset(o, 0, sizeof *o);
    for (int k = 0; k < 3; k++) o->a[k] = (float)(l->position[k] - ref[k]);
    o->a[3] = (float)l->type;
    double dl = sqrt(dot3(l->direction, l->direction)), n[3] = {0, 0, 0};
    for (int k = 0; k < 3; k++) n[k] = dl > 0 ? l->direction[k] / dl : 0;
    for (int k = 0; k < 3; k++) o->b[k] = (float)n[k];
    o->b[3] = (float)light_reach(l, cutoff);
    for (int k = 0; k < 3; k++) o->c[k] = (float)(l->color[k] * l->intensity);
    if (l->type == VX_LIGHT_DIRECTIONAL) {
        double h = 0.5 * l->angular_diameter, s = sin(0.5 * h);
        o->c[3] = (float)(2 * s * s); /* 1 - cos h without the cancellation */
    } else if (l->type != VX_LIGHT_RECT) {
        o->c[3] = (float)l->radius;
    }
    /* glTF's spot falloff: clamp(cos * scale + offset)^2, scale over at least 0.001 */
    double ci = cos(l->inner_cone), co = cos(l->outer_cone);
    double scale = 1.0 / fmax(0.001, ci - co);
    o->d[0] = (float)scale, o->d[1] = (float)(-co * scale);
    o->d[2] = (l->flags & VX_LIGHT_FROM_VOXELS) ? 1.f : 0.f; /* emissive surfaces inside it are its own voxels */
    if (l->type == VX_LIGHT_RECT) { /* edges: the tangent made orthogonal to the normal, then n x t */
        double t[3], tn = dot3(l->tangent, n), tl, v[3];
        for (int k = 0; k < 3; k++) t[k] = l->tangent[k] - tn * n[k];
        tl = sqrt(dot3(t, t));
        for (int k = 0; k < 3; k++) t[k] /= tl;
        v[0] = n[1] * t[2] - n[2] * t[1], v[1] = n[2] * t[0] - n[0] * t[2], v[2] = n[0] * t[1] - n[1] * t[0];
        for (int k = 0; k < 3; k++) {
            o->e[k] = (float)(t[k] * 0.5 * l->size[0]);
            o->f[k] = (float)(v[k] * 0.5 * l->size[1]);
        }
    }
}

void vx__light_pack(const vx_light* l, const double ref[3], double cutoff, float out[24]) {
    gpu_light g;
    _Static_assert(sizeof g == 24 * sizeof(float), "gpu_light is 24 floats");
    pack_light(l, ref, cutoff, &g);
    memcpy(out, &g, sizeof g);
}

void vx__sky_pack(const vx_sky* k, const vx_sky_texels* map, const double uniform[3], float out[16]) {
    memset(out, 0, 16 * sizeof *out);
    vx_sky_type t = k ? k->type : VX_SKY_DEFAULT;
    bool texels = map && map->rgb && map->width && map->height;
    for (int i = 0; i < 3; i++) {
        out[i] = (float)(t == VX_SKY_DEFAULT ? uniform[i] : t == VX_SKY_ENVMAP ? 0 : k->color[i]);
        out[4 + i] = t == VX_SKY_GRADIENT ? (float)k->horizon[i] : 0.f;
        out[8 + i] = t == VX_SKY_GRADIENT ? (float)k->ground[i] : 0.f;
    }
    out[7] = t == VX_SKY_GRADIENT ? 1.f : t == VX_SKY_ENVMAP && texels ? 2.f : 0.f;
    if (t == VX_SKY_ENVMAP && texels) {
        out[11] = (float)k->intensity;
        out[12] = (float)k->rotation, out[13] = (float)map->width, out[14] = (float)map->height;
    }
}

/* The sky's light on a surface for the frame's sky term: E(n) / pi (the
 * radiance a white diffuse surface of normal n reflects, unoccluded) on a
 * grid of normals, SKY_IRR_W azimuths times SKY_IRR_H polar angles from +z
 * to -z (poles included), read bilinearly by passes_common.glsl. The sky is
 * integrated over a grid of at most SKY_GRID_W x SKY_GRID_H cells of equal
 * azimuth and polar steps (a map's texels averaged into them, weighted by
 * solid angle), each cell at its centre's cosine. */
enum { SKY_IRR_W = 32, SKY_IRR_H = 17, SKY_GRID_W = 128, SKY_GRID_H = 64 };
#define SKY_ENV_AT (16 + 3 * SKY_IRR_W * SKY_IRR_H) /* floats before the map's texels (passes_common.glsl) */

static vx_result sky_table(const vx_gpu* g, const vx_sky* k, const vx_sky_texels* map, const double uniform[3],
                           float* out, vx_error* err) {
    static const double pi = 3.14159265358979323846;
    vx_sky_type t = k ? k->type : VX_SKY_DEFAULT;
    bool is_map = t == VX_SKY_ENVMAP && map && map->rgb && map->width && map->height;
    uint32_t gw = is_map && map->width < SKY_GRID_W ? map->width : SKY_GRID_W;
    uint32_t gh = is_map && map->height < SKY_GRID_H ? map->height : SKY_GRID_H;
    double* L = vx_calloc(&g->alloc, (size_t)gw * gh, 4 * sizeof(double)); /* rgb, weight */
    if (!L) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for the sky's irradiance table");
    double rot = is_map ? k->rotation : 0;
    if (is_map) {
        for (uint32_t y = 0; y < map->height; y++) {
            double w = sin((y + 0.5) * pi / map->height); /* a texel's solid angle, up to a constant */
            for (uint32_t x = 0; x < map->width; x++) {
                double* c = L + 4 * ((size_t)(y * (uint64_t)gh / map->height) * gw + x * (uint64_t)gw / map->width);
                const float* p = map->rgb + 3 * ((size_t)y * map->width + x);
                for (int i = 0; i < 3; i++) c[i] += w * p[i] * k->intensity;
                c[3] += w;
            }
        }
        for (size_t c = 0; c < (size_t)gw * gh; c++)
            for (int i = 0; i < 3; i++) L[4 * c + i] = L[4 * c + 3] > 0 ? L[4 * c + i] / L[4 * c + 3] : 0;
    } else {
        for (uint32_t y = 0; y < gh; y++)
            for (uint32_t x = 0; x < gw; x++) {
                double th = (y + 0.5) * pi / gh, ph = (x + 0.5) * 2 * pi / gw, v[3];
                double d[3] = {sin(th) * cos(ph), sin(th) * sin(ph), cos(th)};
                if (t == VX_SKY_DEFAULT) memcpy(v, uniform, sizeof v);
                else vx_sky_radiance(k, map, d, v);
                memcpy(L + 4 * ((size_t)y * gw + x), v, sizeof v);
            }
    }
    /* divided by the grid's own integral of the clamped cosine (pi up to
     * the quadrature's error), so that a constant sky gives its radiance */
    for (uint32_t ny = 0; ny < SKY_IRR_H; ny++)
        for (uint32_t nx = 0; nx < SKY_IRR_W; nx++) {
            double nth = ny * pi / (SKY_IRR_H - 1), nph = nx * 2 * pi / SKY_IRR_W;
            double n[3] = {sin(nth) * cos(nph), sin(nth) * sin(nph), cos(nth)}, e[3] = {0, 0, 0}, kern = 0;
            for (uint32_t y = 0; y < gh; y++) {
                double th0 = y * pi / gh, th1 = (y + 1) * pi / gh, th = (y + 0.5) * pi / gh;
                double omega = (cos(th0) - cos(th1)) * 2 * pi / gw;
                for (uint32_t x = 0; x < gw; x++) {
                    double ph = rot + (x + 0.5) * 2 * pi / gw;
                    double c = n[0] * sin(th) * cos(ph) + n[1] * sin(th) * sin(ph) + n[2] * cos(th);
                    if (c <= 0) continue;
                    const double* l = L + 4 * ((size_t)y * gw + x);
                    for (int i = 0; i < 3; i++) e[i] += l[i] * c * omega;
                    kern += c * omega;
                }
            }
            for (int i = 0; i < 3; i++) out[3 * (ny * SKY_IRR_W + nx) + i] = (float)(kern > 0 ? e[i] / kern : 0);
        }
    vx_free(&g->alloc, L);
    return VX_OK;
}

vx_result vx__sky_buffer(vx_gpu* g, const vx_sky* k, const vx_sky_texels* map, const double uniform[3], vx__buffer* b,
                         vx_error* err) {
    bool texels = k && k->type == VX_SKY_ENVMAP && map && map->rgb;
    size_t ntex = texels ? (size_t)map->width * map->height * 3 : 0, nf = SKY_ENV_AT + (ntex ? ntex : 1);
    float* buf = vx_calloc(&g->alloc, nf, sizeof(float));
    if (!buf) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for the sky (%zu floats)", nf);
    vx__sky_pack(k, texels ? map : NULL, uniform, buf);
    vx_result r = sky_table(g, k, texels ? map : NULL, uniform, buf + 16, err);
    if (!r && ntex) memcpy(buf + SKY_ENV_AT, map->rgb, ntex * sizeof(float));
    if (!r) r = vx__buffer_ensure(g, b, nf * sizeof(float), "sky", err);
    if (!r) r = vx__buffer_upload(g, b, buf, nf * sizeof(float), err);
    vx_free(&g->alloc, buf);
    return r;
}

typedef struct push_block {
    float f0[4]; /* lens radius, focus, ao radius, 2^exposure */
    float f1[4]; /* sun, edge threshold */
    float f2[4]; /* sky */
    uint32_t u0[4]; /* sample, samples, ao rays, seed */
    uint32_t u1[4]; /* first ao ray of the dispatch, ao rays in it, lights, directional lights */
    float f3[4];    /* light grid: depth origin, near, (slices - 1) / ln(far / near), list capacity (bits) */
    uint32_t u2[4]; /* light grid: tiles across, down, slices, tile pixels */
    uint32_t u3[4]; /* the display image of the last pass (display_out.glsl): B,G,R,A, overlay, width, height */
} push_block;
_Static_assert(sizeof(push_block) <= 128, "Vulkan guarantees 128 bytes of push constants");

typedef enum shader_id { SH_GBUFFER, SH_DIRECT, SH_AO, SH_RESOLVE, SH_POST, SH_FRAME, SH_CULL, SH_COUNT } shader_id;

#define MAX_TIMED 8192 /* dispatches with timestamps in one submission */

/* A recorded frame (vx_frame_record) of one slot: its descriptor set's pool
 * and timestamps, kept until the slot is recorded again, and what
 * vx_frame_record_result makes of them once the device has run it. */
typedef struct frame_slot {
    VkDescriptorPool pool;
    VkQueryPool qp;
    uint32_t qcap;
    bool recorded;
    uint32_t nq, nd;
    vx_frame_result res; /* rows and counts; the times come from the queries */
    int row_of[MAX_TIMED];
} frame_slot;

struct vx_frame_renderer {
    vx_render_scene* rs;
    vx_gpu* g;
    double lo[3], hi[3];
    double max_cell; /* largest world cell over the drawn instances */
    vx__buffer b[B_COUNT];
    size_t cap_px;         /* pixels the image buffers hold */
    float* scene_emit;     /* the emission's terms per attribute record (4 floats, vx_material_emitted_terms) from the
                            * scene's materials (lights without gi) */
    /* the compact layout cannot key this scene's records by material id
     * (vx__render_scene_attr_material refused: a layout built from a model
     * reader has no material ids): the colour model needs no materials and
     * renders; a radiometric frame refuses (mat_error) */
    bool mat_unkeyed;
    vx_error mat_error;
    size_t scene_emit_count;
    size_t emit_count;     /* records in b[B_EMIT] */
    const float* emit_src; /* what b[B_EMIT] was filled from */
    /* metal and glass seen directly: per attribute record (1 metal / 0, roughness, metalness, specular) or
     * glass (2, roughness, ior, transmission), then the GGX albedo table (pass_bodies.glsl MAT_BINDING); NULL
     * when no record is metal or glass */
    float* scene_mat;
    size_t scene_mat_count; /* records */
    bool scene_metal, scene_glass; /* some record is metal / glass that transmits */
    bool mat_valid;         /* b[B_MAT] holds scene_mat */
    bool sky_valid;        /* b[B_SKY] holds sky_key's sky (sky.glsl's parameters, the table, the texels) */
    vx_sky sky_key;
    vx_sky_texels sky_map_key;
    VkQueryPool qp;
    uint32_t qcap;
    uint32_t lidx_cap; /* light list entries b[B_LIDX] holds */
    int last_out;          /* the buffer holding the last frame's image (-1: none yet) */
    uint32_t last_w, last_h;
    frame_slot* slots[VX_FRAME_SLOTS]; /* vx_frame_record's, made on first use */
    bool recorded; /* frames were recorded: wait for the queue before changing what they read */
};

vx__buffer* vx__frame_renderer_image(const vx_frame_renderer* fr, uint32_t* w, uint32_t* h) {
    if (!fr || fr->last_out < 0) return NULL;
    *w = fr->last_w, *h = fr->last_h;
    return (vx__buffer*)&fr->b[fr->last_out];
}

vx_result vx_frame_renderer_create(vx_render_scene* rs, const vx_svo_scene* scene, vx_frame_renderer** out,
                                   vx_error* err) {
    if (!rs || !scene || !out) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    vx_gpu* g = vx__render_scene_gpu(rs);
    vx_frame_renderer* fr = vx_calloc(&g->alloc, 1, sizeof *fr);
    if (!fr) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory");
    fr->rs = rs, fr->g = g;
    fr->last_out = -1;
    vx_result r = vx_frame_renderer_update_scene(fr, scene, err);
    if (r) {
        vx_frame_renderer_destroy(fr);
        return r;
    }
    *out = fr;
    return VX_OK;
}

/* One record's entry of material id `id`: (1 metal / 0, roughness, metalness, specular), or for glass that
 * transmits (2, roughness, ior, transmission). */
static void mat_record(const vx_svo_material_table* t, uint32_t id, float out[4]) {
    const vx_material* f = vx_svo_material_table_find(t, id);
    vx_material mt = f ? *f : vx_material_default(VX_MATERIAL_DIFFUSE);
    out[0] = mt.type == VX_MATERIAL_METAL ? 1.0f : 0.0f;
    out[1] = (float)mt.roughness, out[2] = (float)mt.metalness, out[3] = (float)mt.specular;
    if (mt.type == VX_MATERIAL_GLASS && mt.transmission > 0) /* the path tracer's glass (probes/pathtrace.c bsdf_of) */
        out[0] = 2.0f, out[2] = (float)mt.ior, out[3] = (float)fmin(mt.transmission, 1.0);
}

/* Metal and glass seen directly: each attribute record's material for the direct pass and resolve
 * (pass_bodies.glsl MAT_BINDING), then the GGX lobe's albedo table, when some record is metal or glass that
 * transmits; none otherwise (the frames then bind a placeholder and keep their SPIR-V path). Host-side, uploaded by the next frame that uses it.
 * ids: the records' material ids (vx__render_scene_attr_material), t the scene's materials by id. */
static vx_result scene_materials(vx_frame_renderer* fr, const vx_svo_material_table* t, const uint16_t* ids, size_t n,
                                 vx_error* err) {
    vx_gpu* g = fr->g;
    bool metal = false, glass = false;
    for (size_t i = 0; t->specular && i < n && !(metal && glass); i++) {
        const vx_material* f = vx_svo_material_table_find(t, ids[i]);
        metal |= f && f->type == VX_MATERIAL_METAL;
        glass |= f && f->type == VX_MATERIAL_GLASS && f->transmission > 0;
    }
    fr->scene_metal = metal, fr->scene_glass = glass;
    float* m = NULL;
    if (metal || glass) {
        if (n > (SIZE_MAX / 16) - MAT_ENV_N * MAT_ENV_N)
            return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "%zu attribute records", n);
        if (!(m = vx_calloc(&g->alloc, n + MAT_ENV_N * MAT_ENV_N, 4 * sizeof(float))))
            return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %zu material records", n);
        for (size_t i = 0; i < n; i++) mat_record(t, ids[i], m + 4 * i);
        vx_ggx_albedo_table(MAT_ENV_N, m + 4 * n);
        if (fr->scene_mat && fr->scene_mat_count == n && !memcmp(fr->scene_mat, m, (n + MAT_ENV_N * MAT_ENV_N) * 16)) {
            vx_free(&g->alloc, m); /* what the GPU holds stays */
            return VX_OK;
        }
    }
    vx_free(&g->alloc, fr->scene_mat);
    fr->scene_mat = m, fr->scene_mat_count = m ? n : 0;
    fr->mat_valid = false;
    return VX_OK;
}

/* The scene facts: the bounds (the default framing, dof's aperture, the
 * light grid's depths), the largest cell (ao's radius), and the emission of
 * each attribute record (the order of the scene's colour buffer), as the gi
 * methods give it: the radiometric model without a gi pass shows it, and
 * the direct pass knows emissive surfaces by it. Host-side only: the
 * emission goes to the GPU with the next frame that uses it, and only when
 * it changed (a frame in flight may still read the old). */
vx_result vx_frame_renderer_update_scene(vx_frame_renderer* fr, const vx_svo_scene* scene, vx_error* err) {
    if (!fr || !scene) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    vx_gpu* g = fr->g;
    vx_svo_scene_world_bounds(scene, fr->lo, fr->hi);
    fr->max_cell = 0;
    for (uint32_t i = 0; i < scene->instance_count; i++) {
        if (!vx_svo_instance_drawn(scene, i)) continue;
        double w[12];
        vx_svo_instance_world(scene, &scene->instances[i], w);
        for (int c = 0; c < 3; c++) {
            double n = sqrt(w[c] * w[c] + w[4 + c] * w[4 + c] + w[8 + c] * w[8 + c]);
            if (n > fr->max_cell) fr->max_cell = n;
        }
    }
    uint16_t* pal = NULL; /* material ids per record */
    size_t n = 0;
    float* e = NULL;
    vx_svo_material_table t = {0};
    vx_result r = vx__render_scene_attr_material(fr->rs, scene, &g->alloc, &pal, &n, &fr->mat_error);
    fr->mat_unkeyed = r == VX_ERR_UNSUPPORTED && vx__render_scene_compact(fr->rs);
    if (fr->mat_unkeyed) r = VX_OK, n = 0; /* no records' materials: no emission, no metal (the colour model) */
    else if (r && err) *err = fr->mat_error;
    if (!r && !fr->mat_unkeyed) r = vx_svo_material_table_make(scene, &g->alloc, &t, err);
    size_t ne = 0; /* a scene without emission: no records (no emission buffer, EMIT_KNOWN off) */
    if (!r) r = vx_svo_material_table_emission_records(&t, pal, n, &g->alloc, &e, &ne, err);
    if (!r) {
        bool same = fr->scene_emit && fr->scene_emit_count == ne && !memcmp(fr->scene_emit, e, 4 * ne * sizeof *e);
        if (same) {
            vx_free(&g->alloc, e); /* what the GPU holds stays */
        } else {
            vx_free(&g->alloc, fr->scene_emit);
            fr->scene_emit = e, fr->scene_emit_count = ne;
            fr->emit_src = NULL; /* uploaded again at the next frame that uses it */
        }
    }
    if (!r) r = scene_materials(fr, &t, pal, n, err);
    vx_free(&g->alloc, pal);
    vx_svo_material_table_free(&t);
    return r;
}

void vx_frame_renderer_destroy(vx_frame_renderer* fr) {
    if (!fr) return;
    if (fr->recorded) vkQueueWaitIdle(fr->g->queue);
    for (int i = 0; i < VX_FRAME_SLOTS; i++) {
        frame_slot* sl = fr->slots[i];
        if (!sl) continue;
        if (sl->pool) vkDestroyDescriptorPool(fr->g->device, sl->pool, NULL);
        if (sl->qp) vkDestroyQueryPool(fr->g->device, sl->qp, NULL);
        vx_free(&fr->g->alloc, sl);
    }
    vx_free(&fr->g->alloc, fr->scene_emit);
    vx_free(&fr->g->alloc, fr->scene_mat);
    for (int i = 0; i < B_COUNT; i++) vx__buffer_destroy(fr->g, &fr->b[i]);
    if (fr->qp) vkDestroyQueryPool(fr->g->device, fr->qp, NULL);
    vx_allocator a = fr->g->alloc;
    vx_free(&a, fr);
}

/* Before the host replaces or rewrites a buffer that recorded frames may
 * still read (a new size, the emission or sky tables changed). */
static void settle(vx_frame_renderer* fr) {
    if (!fr->recorded) return;
    vx__gpu_submit_held(fr->g); /* frames a display holds read these buffers too */
    vkQueueWaitIdle(fr->g->queue);
    fr->recorded = false;
}

static vx_result ensure(vx_frame_renderer* fr, int which, VkDeviceSize size, const char* label, vx_error* err) {
    if (!(fr->b[which].buf && fr->b[which].size >= size)) settle(fr);
    return vx__buffer_ensure(fr->g, &fr->b[which], size, label, err);
}

/* display: the variant that also writes the display image (frame, resolve,
 * post: DISPLAY_OUT), with the overlay and the image as bindings 20 and 21. */
static vx_result get_pipeline(vx_gpu* g, shader_id sh, const uint32_t spec[PASS_SPECS], bool display,
                              vx__pipeline** out, vx_error* err) {
    static const char* const labels[SH_COUNT] = {"gbuffer", "direct", "ao", "resolve", "post", "frame", "cull"};
    vx_gpu_compute_pipeline_desc pd = {.binding_count = NBIND,
                                       .spec_count = PASS_SPECS,
                                       .push_constant_size = sizeof(push_block),
                                       .label = labels[sh]};
    display = display && (sh == SH_RESOLVE || sh == SH_FRAME || sh == SH_POST);
    switch (sh) {
    case SH_GBUFFER: pd.spirv = vx__gbuffer_spv_arr, pd.spirv_size = sizeof vx__gbuffer_spv_arr; break;
    case SH_DIRECT: pd.spirv = vx__direct_spv_arr, pd.spirv_size = sizeof vx__direct_spv_arr; break;
    case SH_AO: pd.spirv = vx__ao_spv_arr, pd.spirv_size = sizeof vx__ao_spv_arr; break;
    case SH_RESOLVE:
        pd.spirv = display ? vx__resolve_display_spv_arr : vx__resolve_spv_arr;
        pd.spirv_size = display ? sizeof vx__resolve_display_spv_arr : sizeof vx__resolve_spv_arr;
        break;
    case SH_FRAME:
        pd.spirv = display ? vx__frame_display_spv_arr : vx__frame_spv_arr;
        pd.spirv_size = display ? sizeof vx__frame_display_spv_arr : sizeof vx__frame_spv_arr;
        break;
    case SH_CULL: pd.spirv = vx__cull_spv_arr, pd.spirv_size = sizeof vx__cull_spv_arr; break;
    default:
        pd.spirv = display ? vx__post_display_spv_arr : vx__post_spv_arr;
        pd.spirv_size = display ? sizeof vx__post_display_spv_arr : sizeof vx__post_spv_arr;
        break;
    }
    pd.bindings[0] = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
    for (uint32_t i = 1; i < NBIND; i++) pd.bindings[i] = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    if (display) {
        pd.binding_count = NBIND + 2;
        pd.bindings[NBIND] = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
        pd.bindings[NBIND + 1] = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
        pd.label = sh == SH_POST ? "post (display)" : sh == SH_FRAME ? "frame (display)" : "resolve (display)";
    }
    memcpy(pd.spec, spec, PASS_SPECS * sizeof spec[0]);
    uint64_t key = vx__spec_key(0x9A55000ull + (uint64_t)sh + (display ? 0x100u : 0u), spec, PASS_SPECS);
    return vx__pipeline_get(g, key, &pd, out, err);
}

/* One recorded dispatch: which timing row it adds to. */
typedef struct rec {
    vx_frame_renderer* fr;
    VkDescriptorSet set;
    VkDescriptorSet dset; /* the last pass's when it writes the display image (its variant's bindings) */
    uint32_t groups[2];
    VkCommandBuffer cb; /* the gpu's own, or the caller's (slot) */
    frame_slot* slot;   /* vx_frame_record: recorded into the caller's command buffer, not submitted */
    VkQueryPool qp;
    uint32_t qcap;
    uint32_t nq;       /* timestamps written in this submission */
    int row_of[MAX_TIMED];  /* timing row of dispatch k of this submission */
    uint32_t nd;
    bool recording;
    bool untimed; /* a recorded frame without timestamps (vx_frame_desc.no_timestamps) */
    bool open_end; /* no barrier after the next dispatch (the frame's last, writing only its display image) */
    vx_frame_result* res;
    double first_ts_ms; /* unused when no timestamps */
} rec;

static int timing_row(vx_frame_result* res, const char* name) {
    for (uint32_t i = 0; i < res->timing_count; i++)
        if (!strcmp(res->timings[i].name, name)) return (int)i;
    res->timings[res->timing_count] = (vx_pass_timing){.name = name};
    return (int)res->timing_count++;
}

static vx_result rec_begin(rec* R, vx_error* err) {
    if (!R->slot) {
        vx_result r = vx__cmd_begin(R->fr->g, err);
        if (r) return r;
        R->cb = R->fr->g->cmd;
    }
    R->nq = 0, R->nd = 0, R->recording = true;
    if (R->fr->g->has_timestamps && !R->untimed) vkCmdResetQueryPool(R->cb, R->qp, 0, R->qcap);
    return VX_OK;
}

/* Records one dispatch of groups[0] x groups[1] workgroups (NULL: the image's 8 x 8 tiles). */
static void rec_dispatch_n(rec* R, vx__pipeline* p, const push_block* pc, const char* row, const uint32_t* groups) {
    vx_gpu* g = R->fr->g;
    VkCommandBuffer cb = R->cb;
    vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_COMPUTE, p->pipe);
    vkCmdBindDescriptorSets(cb, VK_PIPELINE_BIND_POINT_COMPUTE, p->layout, 0, 1, &R->set, 0, NULL);
    vkCmdPushConstants(cb, p->layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof *pc, pc);
    bool ts = g->has_timestamps && !R->untimed && R->nq + 2 <= R->qcap && R->nd < MAX_TIMED;
    if (ts) vkCmdWriteTimestamp(cb, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, R->qp, R->nq);
    if (!groups) groups = R->groups;
    vkCmdDispatch(cb, groups[0], groups[1], 1);
    if (ts) vkCmdWriteTimestamp(cb, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, R->qp, R->nq + 1);
    if (!R->open_end) {
        VkMemoryBarrier mb = {.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER,
                              .srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT,
                              .dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT |
                                               VK_ACCESS_TRANSFER_READ_BIT | VK_ACCESS_HOST_READ_BIT};
        vkCmdPipelineBarrier(cb, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                             VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT | VK_PIPELINE_STAGE_HOST_BIT,
                             0, 1, &mb, 0, NULL, 0, NULL);
    }
    int rowi = timing_row(R->res, row);
    R->res->timings[rowi].dispatches++;
    if (ts) {
        R->row_of[R->nd++] = rowi;
        R->nq += 2;
    }
}

static void rec_dispatch(rec* R, vx__pipeline* p, const push_block* pc, const char* row) {
    rec_dispatch_n(R, p, pc, row, NULL);
}

/* The same with the last pass's set when `display` (its display variant). */
static void rec_dispatch_d(rec* R, vx__pipeline* p, const push_block* pc, const char* row, bool display) {
    VkDescriptorSet keep = R->set;
    if (display) R->set = R->dset;
    rec_dispatch_n(R, p, pc, row, NULL);
    R->set = keep;
}

/* Adds nq timestamps of qp (dispatch k timed by 2k, 2k + 1 for row
 * row_of[k]) to the rows and the frame time of res. */
static vx_result add_times(vx_gpu* g, VkQueryPool qp, uint32_t nq, uint32_t nd, const int* row_of, bool wait,
                           vx_frame_result* res, vx_error* err) {
    uint64_t* ts = vx_alloc(&g->alloc, (size_t)nq * 8);
    if (!ts) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for timestamps");
    VkResult vr = vkGetQueryPoolResults(g->device, qp, 0, nq, (size_t)nq * 8, ts, 8,
                                        VK_QUERY_RESULT_64_BIT | (wait ? VK_QUERY_RESULT_WAIT_BIT : 0));
    if (vr != VK_SUCCESS) {
        vx_free(&g->alloc, ts);
        if (vr == VK_NOT_READY)
            return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "the recorded frame has not run yet (wait for its submission)");
        return vx__vk_fail(err, vr, "vkGetQueryPoolResults");
    }
    double per = g->props.limits.timestampPeriod * 1e-6; /* ms per tick */
    for (uint32_t k = 0; k < nd; k++) res->timings[row_of[k]].ms += (double)(ts[2 * k + 1] - ts[2 * k]) * per;
    res->frame_ms += (double)(ts[nq - 1] - ts[0]) * per;
    vx_free(&g->alloc, ts);
    return VX_OK;
}

/* Submits, waits and adds the timestamps to the rows and the frame time.
 * A recorded frame (R->slot) is the caller's to submit: the slot keeps what
 * vx_frame_record_result needs. */
static vx_result rec_submit(rec* R, vx_error* err) {
    if (!R->recording) return VX_OK;
    R->recording = false;
    vx_gpu* g = R->fr->g;
    if (R->slot) {
        R->slot->nq = g->has_timestamps ? R->nq : 0, R->slot->nd = R->nd;
        memcpy(R->slot->row_of, R->row_of, (size_t)R->nd * sizeof R->row_of[0]);
        return VX_OK;
    }
    double t0 = vx_time_now();
    vx_result r = vx__cmd_submit_wait(g, err);
    if (r) return r;
    double wall = vx_time_now() - t0;
    if (!g->has_timestamps || R->nq == 0) {
        R->res->frame_ms += wall * 1e3;
        return VX_OK;
    }
    return add_times(g, R->qp, R->nq, R->nd, R->row_of, true, R->res, err);
}

/* The culling dispatches (shaders/cull.comp): clear, (tiled) tile depths,
 * count, scan, fill, all in the timing row "cull". */
static void rec_cull(rec* R, vx__pipeline* const p[5], const push_block* pc, uint64_t cells, uint32_t lights,
                     const uint32_t tiles[2]) {
    /* 8 lights a workgroup (32 invocations each), over rows of at most 65535 workgroups */
    uint32_t wgs = (lights + 7) / 8, rows = (wgs + 65534) / 65535;
    uint32_t clear[2] = {(uint32_t)((cells + 255) / 256), 1}, one[2] = {1, 1};
    uint32_t per_light[2] = {(wgs + rows - 1) / rows, rows};
    rec_dispatch_n(R, p[0], pc, "cull", clear);
    if (p[1]) rec_dispatch_n(R, p[1], pc, "cull", tiles);
    rec_dispatch_n(R, p[2], pc, "cull", per_light);
    rec_dispatch_n(R, p[3], pc, "cull", one);
    rec_dispatch_n(R, p[4], pc, "cull", per_light);
}

static bool any_emission(const float* e, size_t n) { /* n records of 4 terms */
    for (size_t i = 0; e && i < 4 * n; i++)
        if (e[i] > 0) return true;
    return false;
}

/* The culling of a frame with nl lights, ndir of them directional: only for
 * lights with a reach. */
static vx_light_culling pick_culling(const vx_frame_desc* desc, bool has_direct, uint32_t nl, uint32_t ndir) {
    if (nl <= ndir || !has_direct) return VX_LIGHT_CULLING_BRUTE;
    vx_light_culling cull = desc->light_culling;
    if (cull == VX_LIGHT_CULLING_AUTO)
        cull = nl - ndir <= VX_LIGHT_CULLING_AUTO_MAX ? VX_LIGHT_CULLING_BRUTE : VX_LIGHT_CULLING_TILED;
    return cull;
}

/* A frame: submitted and waited for (slot NULL), or recorded into the
 * caller's command buffer cb for slot (vx_frame_record); with dt (recorded
 * frames only) its last pass also writes the display image. */
static vx_result frame_run(vx_frame_renderer* fr, const vx_frame_desc* desc, vx_frame_result* out, frame_slot* slot,
                           VkCommandBuffer cb, const vx__display_target* dt, vx_error* err) {
    memset(out, 0, sizeof *out);
    vx_gpu* g = fr->g;
    if (!slot) settle(fr); /* recorded frames read the buffers this frame writes from the host */
    vx_pass_list deflist;
    vx_result r = VX_OK;
    const vx_pass_list* L = desc->passes;
    if (!L) {
        if ((r = vx_pass_list_parse(VX_PASS_LIST_DEFAULT, &deflist, err))) return r;
        L = &deflist;
    }
    if ((unsigned)desc->show >= VX_SHOW_COUNT) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "unknown show image");
    bool has_gb = vx_pass_list_has(L, VX_PASS_GBUFFER), has_direct = vx_pass_list_has(L, VX_PASS_DIRECT);
    bool has_gi = vx_pass_list_has(L, VX_PASS_GI), has_ao = vx_pass_list_has(L, VX_PASS_AO);
    bool has_dof = vx_pass_list_has(L, VX_PASS_DOF), has_aa = vx_pass_list_has(L, VX_PASS_AA);
    bool has_tm = vx_pass_list_has(L, VX_PASS_TONEMAP);
    const vx_gi_method* gm = desc->gi;
    if (has_gi && (!gm || !gm->render))
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "pass gi=%s has no method registered", L->gi);
    if (has_gi && gm->name && strcmp(gm->name, L->gi))
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "pass gi=%s but the method given is '%s'", L->gi,
                       gm->name);
    if (has_gi && has_direct && gm->includes_direct)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET,
                       "gi=%s brings the direct light itself (cone shadows): leave direct out of the pass list", L->gi);
    if (vx_render_scene_precise(fr->rs))
        return vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET,
                       "the pass pipeline traces in float; this scene has models deeper than %u levels",
                       VX_RENDER_PRECISE_DEPTH);
    vx_render_desc base = desc->base;
    base.mode = VX_RENDER_COLOR;
    base.want_hits = false;
    if (has_gi)
        for (int k = 0; k < 3; k++) base.light_dir[k] = gm->light_dir[k];
    if (!base.spp) base.spp = has_aa || has_dof ? 8 : 1;
    vx__frame f;
    if ((r = vx__frame_setup(fr->lo, fr->hi, &base, &f, err))) return r;
    if ((r = vx__gpu_float_range(fr->lo, fr->hi, err))) return r;
    bool ids = desc->want_ids;
    uint32_t nl = desc->light_count;
    if (slot && (ids || !desc->no_readback || has_gi))
        return vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET,
                       "a recorded frame is not read back (no_readback, no want_ids) and has no gi pass (gi=%s submits "
                       "its own work)",
                       has_gi ? L->gi : "none");
    if (nl && !desc->lights) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "%u lights but no array", nl);
    if (nl && has_gi && (gm->light_count != nl || gm->lights != desc->lights))
        return vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET,
                       "lights with a gi pass: the gi method (gi=%s) was not made with the frame's lights", L->gi);
    if (nl > (1u << 24)) return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "%u lights: at most 2^24", nl);
    uint32_t ndir = 0;
    for (uint32_t i = 0; i < nl; i++) {
        if ((r = vx_light_validate(&desc->lights[i], i, err))) return r;
        ndir += desc->lights[i].type == VX_LIGHT_DIRECTIONAL;
    }
    if ((unsigned)desc->light_culling >= VX_LIGHT_CULLING_COUNT)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "unknown light culling %d", (int)desc->light_culling);
    if (desc->shadow_lights < -1 || desc->shadow_lights > VX_SHADOW_LIGHTS_MAX)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "shadow_lights %d: -1 (none), 0 (default) or up to %d",
                       (int)desc->shadow_lights, VX_SHADOW_LIGHTS_MAX);
    if (!(desc->light_cutoff >= 0) || !isfinite(desc->light_cutoff) || !isfinite(desc->exposure))
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "light_cutoff and exposure must be finite, cutoff >= 0");
    double cutoff = desc->light_cutoff > 0 ? desc->light_cutoff : 3.141592653589793 / 1024 * exp2(-desc->exposure);
    if (!(cutoff > 0) || !isfinite(cutoff))
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "exposure %g leaves no light cut-off", desc->exposure);
    vx_light_culling cull = pick_culling(desc, has_direct, nl, ndir);
    bool tiled = cull == VX_LIGHT_CULLING_TILED, culled = cull != VX_LIGHT_CULLING_BRUTE;
    if (slot && culled)
        return vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET,
                       "a recorded frame has no light culling (%u lights with a reach: the grid's size is read back); "
                       "light_culling brute",
                       nl - ndir);
    uint32_t shadows = desc->shadow_lights < 0 ? 0
                       : desc->shadow_lights == 0 ? VX_SHADOW_LIGHTS_DEFAULT
                                                  : (uint32_t)desc->shadow_lights;
    if (shadows > nl) shadows = nl; /* no more slots than lights */
    bool phys = has_gi || nl > 0;
    if (phys && fr->mat_unkeyed) { /* the radiometric model would show these records' materials as diffuse */
        if (err) *err = fr->mat_error;
        return fr->mat_error.code ? fr->mat_error.code : VX_ERR_UNSUPPORTED;
    }
    bool sky = nl > 0 && !has_gi; /* the radiometric model without gi: the sky times ao (a gi pass brings the sky) */
    /* emission: the gi method's records, or without gi the scene's (the
     * radiometric model only: the colour model has none) */
    const float* emit_tab = has_gi ? gm->emit_attr : fr->scene_emit;
    size_t emit_n = has_gi ? gm->emit_count : fr->scene_emit_count;
    bool emit = phys && any_emission(emit_tab, emit_n);
    /* metal seen directly: the radiometric model's direct light and sky term with the records' BRDF */
    bool metal = phys && fr->scene_metal && (has_direct || sky);
    /* glass seen directly: the direct pass gives its radiance (without that pass glass is shaded as diffuse) */
    bool glass = phys && fr->scene_glass && has_direct;
    size_t npx = (size_t)f.width * f.height;
    VkDeviceSize px = (VkDeviceSize)npx;
    /* image buffers; absent passes get a 16-byte placeholder */
    if ((r = ensure(fr, B_GB0, px * 16, "gbuffer 0", err)) || (r = ensure(fr, B_GB1, px * 16, "gbuffer 1", err)) ||
        (r = ensure(fr, B_GB2, ids ? px * 32 : 16, "gbuffer ids", err)) ||
        (r = ensure(fr, B_DIRECT, has_direct ? px * 16 : 16, "direct", err)) ||
        (r = ensure(fr, B_AO, has_ao ? px * 4 : 16, "ao", err)) ||
        (r = ensure(fr, B_GI, has_gi ? px * 16 : 16, "gi", err)) || (r = ensure(fr, B_ACC, px * 16, "accumulation", err)) ||
        (r = ensure(fr, B_OUT2, has_aa ? px * 16 : 16, "post", err)) ||
        (r = ensure(fr, B_LIGHTS, nl ? (VkDeviceSize)nl * sizeof(gpu_light) : 16, "lights", err)))
        return r;
    /* the light grid: its cells, the scene's view depth range for the slices */
    uint32_t tile = tiled ? TILED_TILE : CLUSTER_TILE;
    uint32_t gx = (f.width + tile - 1) / tile, gy = (f.height + tile - 1) / tile, gz = tiled ? 1 : CLUSTER_SLICES;
    uint64_t cells = culled ? (uint64_t)gx * gy * gz : 0;
    if (culled) {
        uint64_t want = (uint64_t)(nl - ndir) * 8 + cells;
        if (want > (1u << 30)) want = 1u << 30;
        if (fr->lidx_cap < want) {
            if ((r = ensure(fr, B_LIDX, want * 4, "light lists", err))) return r;
            fr->lidx_cap = (uint32_t)want;
        }
    }
    if ((r = ensure(fr, B_CULL, culled ? (4 + cells * (tiled ? 4 : 2)) * 4 : 16, "light grid", err)) ||
        (!culled && (r = ensure(fr, B_LIDX, 16, "light lists", err))))
        return r;
    if (emit && (fr->emit_src != emit_tab || fr->emit_count != emit_n)) {
        settle(fr);
        vx__buffer_destroy(g, &fr->b[B_EMIT]);
        fr->emit_src = NULL, fr->emit_count = 0;
        if ((r = vx__buffer_create(g, emit_n * 16, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, false, "emission",
                                   &fr->b[B_EMIT], err)) ||
            (r = vx__buffer_upload(g, &fr->b[B_EMIT], emit_tab, emit_n * 16, err)))
            return r;
        fr->emit_src = emit_tab, fr->emit_count = emit_n;
    } else if (!fr->b[B_EMIT].buf && (r = ensure(fr, B_EMIT, 16, "emission", err))) {
        return r;
    }
    if ((metal || glass) && !fr->mat_valid) {
        settle(fr);
        vx__buffer_destroy(g, &fr->b[B_MAT]);
        VkDeviceSize size = (VkDeviceSize)(fr->scene_mat_count + MAT_ENV_N * MAT_ENV_N) * 16;
        if ((r = vx__buffer_create(g, size, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, false, "materials", &fr->b[B_MAT], err)) ||
            (r = vx__buffer_upload(g, &fr->b[B_MAT], fr->scene_mat, size, err)))
            return r;
        fr->mat_valid = true;
    } else if (!fr->b[B_MAT].buf && (r = ensure(fr, B_MAT, 16, "materials", err))) {
        return r;
    }
    /* the sky by direction (background, the sky term): the gi method's, else
     * the frame's; a constant one is the uniform radiance of the push constants */
    const vx_sky* sk = has_gi ? gm->sky_dir : desc->sky_dir;
    const vx_sky_texels* sm = has_gi ? gm->sky_map : desc->sky_map;
    double sky_uniform[3];
    for (int k = 0; k < 3; k++) sky_uniform[k] = has_gi ? gm->sky[k] : desc->sky[k];
    if (sk && sk->type == VX_SKY_CONSTANT) memcpy(sky_uniform, sk->color, sizeof sky_uniform);
    bool sky_dir = phys && sk && (sk->type == VX_SKY_GRADIENT || sk->type == VX_SKY_ENVMAP);
    if (sk && (r = vx_sky_validate(sk, err))) return r;
    if (sky_dir && sk->type == VX_SKY_ENVMAP &&
        (!sm || !sm->rgb || !sm->width || !sm->height || sm->width > 65536 || sm->height > 65536))
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "sky: the environment map '%s' has no texels", sk->path);
    if (sky_dir) {
        vx_sky_texels mk = sk->type == VX_SKY_ENVMAP ? *sm : (vx_sky_texels){0};
        if (!fr->sky_valid || memcmp(&fr->sky_key, sk, sizeof *sk) || memcmp(&fr->sky_map_key, &mk, sizeof mk)) {
            settle(fr);
            fr->sky_valid = false;
            if ((r = vx__sky_buffer(g, sk, &mk, sky_uniform, &fr->b[B_SKY], err))) return r;
            fr->sky_key = *sk, fr->sky_map_key = mk, fr->sky_valid = true;
        }
    } else if (!fr->b[B_SKY].buf && (r = ensure(fr, B_SKY, 16, "sky", err))) {
        return r;
    }
    /* the sun's depth map for the direct pass's sun rays (vx_render_frame's rule: built at a frame whose light
     * the frame before had): the colour model's sun, or gi's; the frame block written by the bind below
     * carries its frame */
    vx__sun_map sun_map = {0};
    bool sun_rays = has_direct && (!phys || (has_gi && (gm->sun[0] > 0 || gm->sun[1] > 0 || gm->sun[2] > 0)));
    if (sun_rays && (r = vx__render_scene_sun_map_frame(fr->rs, &f, !desc->base.no_shadow_map, &sun_map, err)))
        return r;
    out->shadow_map = sun_map.map != NULL;
    vx__buffer* scene_bufs[7];
    uint32_t tspec[VX__SPEC_COUNT];
    r = slot ? vx__render_scene_bind_cmd(fr->rs, &f, cb, scene_bufs, tspec, err)
             : vx__render_scene_bind(fr->rs, &f, scene_bufs, tspec, err);
    if (r) return r;
    tspec[VX__SPEC_HITS] = ids;
    if (nl) {
        gpu_light* gl = vx_alloc(&g->alloc, (size_t)nl * sizeof *gl);
        if (!gl) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %u lights", nl);
        /* directional lights first: the shaders take the first ndir at every pixel */
        uint32_t at_dir = 0, at_pos = ndir;
        for (uint32_t i = 0; i < nl; i++) {
            bool dir = desc->lights[i].type == VX_LIGHT_DIRECTIONAL;
            pack_light(&desc->lights[i], f.ref, cutoff, &gl[dir ? at_dir++ : at_pos++]);
        }
        if (slot) {
            /* in the command buffer, as the scene's tables: frames before this one may still read the lights */
            VkMemoryBarrier mb = {.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER, .dstAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT};
            vkCmdPipelineBarrier(cb, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 1, &mb, 0, NULL,
                                 0, NULL);
            VkDeviceSize size = (VkDeviceSize)nl * sizeof *gl;
            for (VkDeviceSize at = 0; at < size; at += 65536)
                vkCmdUpdateBuffer(cb, fr->b[B_LIGHTS].buf, at, size - at < 65536 ? size - at : 65536, (uint8_t*)gl + at);
            mb = (VkMemoryBarrier){.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER,
                                   .srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT,
                                   .dstAccessMask = VK_ACCESS_SHADER_READ_BIT};
            vkCmdPipelineBarrier(cb, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0, 1, &mb, 0, NULL,
                                 0, NULL);
        } else {
            r = vx__buffer_upload(g, &fr->b[B_LIGHTS], gl, (VkDeviceSize)nl * sizeof *gl, err);
        }
        vx_free(&g->alloc, gl);
        if (r) return r;
    }
    /* timestamps: two per dispatch of the largest submission */
    uint32_t ao_rays = desc->ao_rays ? desc->ao_rays : 4;
    uint32_t per_sample = 1 + has_direct + (has_ao ? (vx_gpu_is_cpu(g) ? (ao_rays + 15) / 16 : 1) : 0) + 1 + 5 * tiled;
    uint64_t want_q = 2ull * ((uint64_t)f.spp * per_sample + 2 + 4 * culled);
    if (want_q > 16384) want_q = 16384; /* later dispatches run untimed: rows and frame then cover the first 8192 */
    VkQueryPool* qp = slot ? &slot->qp : &fr->qp;
    uint32_t* qcap = slot ? &slot->qcap : &fr->qcap;
    if (g->has_timestamps && *qcap < want_q) {
        if (*qp) vkDestroyQueryPool(g->device, *qp, NULL);
        *qp = VK_NULL_HANDLE, *qcap = 0;
        VkQueryPoolCreateInfo qi = {.sType = VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO,
                                    .queryType = VK_QUERY_TYPE_TIMESTAMP,
                                    .queryCount = (uint32_t)want_q};
        VX__VK(vkCreateQueryPool(g->device, &qi, NULL, qp), "vkCreateQueryPool");
        *qcap = (uint32_t)want_q;
    }
    /* pipelines */
    uint32_t spec[PASS_SPECS] = {0};
    memcpy(spec, tspec, sizeof tspec);
    vx__render_scene_trace_ids(fr->rs, spec);
    /* the grid walk (grid_walk.glsl) in the kernels that trace: trace.comp's rule for this frame */
    vx__buffer* grid_buf = NULL;
    uint32_t grid = vx__render_scene_grid_spec(fr->rs, &f, &grid_buf);
    spec[PASS_SPEC_GRID] = grid;
    vx__pipeline *p_gb, *p_direct = NULL, *p_ao = NULL, *p_resolve = NULL, *p_aa = NULL, *p_tm = NULL, *p_merged = NULL;
    /* gbuffer, direct and resolve merge into one dispatch when nothing needs
     * their images in between (no ao, no gi, no intermediate shown) */
    uint32_t ao_n = desc->ao_rays ? desc->ao_rays : 4;
    bool merge = has_gb && !has_gi && (!has_ao || !vx_gpu_is_cpu(g) || ao_n <= 16) && desc->show == VX_SHOW_FINAL &&
                 !desc->separate_passes;
    const char* merged_name = has_direct ? (has_ao ? "gbuffer+direct+ao+resolve" : "gbuffer+direct+resolve")
                                         : (has_ao ? "gbuffer+ao+resolve" : "gbuffer+resolve");
    bool final = desc->show == VX_SHOW_FINAL;
    bool run_aa = has_aa && final, run_tm = has_tm && final;
    merge = merge && !tiled; /* tiled culling reads the G-buffer's depths before the direct pass */
    /* the last pass, which writes the display image with dt: tonemap, else aa, else the merged kernel or resolve */
    bool d_tm = dt && run_tm, d_aa = dt && run_aa && !run_tm, d_last = dt && !run_aa && !run_tm;
    uint32_t light_spec = (uint32_t)(cull == VX_LIGHT_CULLING_TILED ? 1 : cull == VX_LIGHT_CULLING_CLUSTERED ? 2 : 0) |
                          shadows << 2 | (emit ? 1u << 8 : 0u) | (metal ? 1u << 9 : 0u) |
                          (glass ? 1u << 10 : 0u) | (glass && sky ? 1u << 11 : 0u) | (glass && has_gi ? 1u << 12 : 0u);
    vx__pipeline* p_cull[5] = {NULL};
    spec[7] = 0;
    spec[5] = has_dof && !f.ortho, spec[6] = 0;
    /* The G-buffer's pipeline also gives the frame's descriptor set its layout, so it is made for a merged frame
     * too; the direct, AO and resolve kernels only where they run on their own: a merged frame dispatches the frame
     * kernel alone, and on lavapipe the direct kernel's compile was half of a default svo_render (1.8 of 3.7 s). */
    if ((r = get_pipeline(g, SH_GBUFFER, spec, false, &p_gb, err))) return r;
    spec[5] = 0, spec[6] = phys, spec[7] = light_spec;
    spec[PASS_SPEC_SMAP] = sun_map.map != NULL; /* SMAP: the direct pass and the merged kernel only */
    if (has_direct && !merge && (r = get_pipeline(g, SH_DIRECT, spec, false, &p_direct, err))) return r;
    spec[PASS_SPEC_SMAP] = 0;
    spec[6] = 0, spec[7] = 0;
    if (has_ao && !merge && (r = get_pipeline(g, SH_AO, spec, false, &p_ao, err))) return r;
    spec[PASS_SPEC_GRID] = 0; /* the kernels below do not trace: one pipeline whatever the grids */
    spec[5] = (has_direct ? 1u : 0u) | (has_gi ? 2u : 0u) | (has_ao ? 4u : 0u) | (emit ? 8u : 0u) |
              (phys ? 16u : 0u) | (sky ? 32u : 0u) | (metal ? 64u : 0u) | (glass ? 128u : 0u);
    spec[6] = (uint32_t)desc->show;
    if (!merge && (r = get_pipeline(g, SH_RESOLVE, spec, d_last, &p_resolve, err))) return r;
    if (merge) {
        uint32_t ms[PASS_SPECS];
        memcpy(ms, spec, sizeof ms);
        ms[PASS_SPEC_SMAP] = has_direct && sun_map.map != NULL;
        ms[PASS_SPEC_GRID] = grid;
        ms[5] = (has_direct ? 1u : 0u) | (has_ao ? 4u : 0u) | (emit ? 8u : 0u) | (phys ? 16u : 0u) | (sky ? 32u : 0u) |
                (metal ? 64u : 0u) | (glass ? 128u : 0u);
        ms[6] = has_dof && !f.ortho;
        ms[7] = light_spec;
        if ((r = get_pipeline(g, SH_FRAME, ms, d_last, &p_merged, err))) return r;
    }
    spec[5] = 0, spec[6] = 0;
    if (run_aa && (r = get_pipeline(g, SH_POST, spec, d_aa, &p_aa, err))) return r;
    spec[5] = 1, spec[6] = run_aa;
    if (run_tm && (r = get_pipeline(g, SH_POST, spec, d_tm, &p_tm, err))) return r;
    for (uint32_t step = 0; culled && step < 5; step++) {
        if (step == 1 && !tiled) continue;
        spec[5] = step, spec[6] = tiled;
        if ((r = get_pipeline(g, SH_CULL, spec, false, &p_cull[step], err))) return r;
    }
    /* push constants */
    push_block pc = {0};
    double eye[3], target[3], diag = 0;
    for (int k = 0; k < 3; k++) {
        eye[k] = f.ref[k] - f.fwd[k] * f.t_start;
        target[k] = base.camera.set ? base.camera.target[k] : 0.5 * (fr->lo[k] + fr->hi[k]);
        diag += (fr->hi[k] - fr->lo[k]) * (fr->hi[k] - fr->lo[k]);
    }
    double focus = desc->focus;
    if (!(focus > 0)) {
        focus = 0;
        for (int k = 0; k < 3; k++) focus += (target[k] - eye[k]) * f.fwd[k];
        if (!(focus > 0)) focus = f.t_start;
    }
    pc.f0[0] = (float)(desc->aperture > 0 ? desc->aperture : 0.01 * sqrt(diag));
    pc.f0[1] = (float)focus;
    pc.f0[2] = (float)(desc->ao_radius > 0 ? desc->ao_radius : 4 * (fr->max_cell > 0 ? fr->max_cell : 1));
    pc.f0[3] = (float)exp2(desc->exposure);
    pc.f1[3] = (float)(desc->edge_threshold > 0 ? desc->edge_threshold : 0.1);
    if (has_gi)
        for (int k = 0; k < 3; k++) pc.f1[k] = (float)gm->sun[k], pc.f2[k] = (float)sky_uniform[k];
    else if (sky)
        for (int k = 0; k < 3; k++) pc.f2[k] = (float)sky_uniform[k]; /* no sun: the lights are explicit */
    pc.f2[3] = sky_dir ? 1.f : 0.f; /* the sky by direction from b[B_SKY] */
    pc.u1[2] = nl, pc.u1[3] = ndir;
    if (culled) {
        /* depth slices over the view depths of the scene box (from the eye
         * plane; orthographic: from just before the box) */
        double zlo = INFINITY, zhi = -INFINITY;
        for (int c = 0; c < 8; c++) {
            double v[3] = {(c & 1 ? fr->hi : fr->lo)[0], (c & 2 ? fr->hi : fr->lo)[1], (c & 4 ? fr->hi : fr->lo)[2]};
            double z = 0;
            for (int k = 0; k < 3; k++) z += (v[k] - eye[k]) * f.fwd[k];
            zlo = fmin(zlo, z), zhi = fmax(zhi, z);
        }
        double zb = f.ortho ? zlo - 0.05 * (zhi - zlo) - 1e-6 * fmax(1, fabs(zlo)) : 0;
        double far = zhi - zb, near = fmax(zlo - zb, 1e-3 * far);
        if (!(near > 0)) near = 1e-6, far = fmax(far, 1e-3);
        if (!(far > 2 * near)) far = 2 * near;
        pc.f3[0] = (float)zb, pc.f3[1] = (float)near;
        pc.f3[2] = (float)((gz > 1 ? gz - 1 : 1) / log(far / near));
        pc.u2[0] = gx, pc.u2[1] = gy, pc.u2[2] = gz, pc.u2[3] = tile;
    }
    pc.u0[1] = f.spp;
    pc.u0[2] = desc->ao_rays ? desc->ao_rays : 4;
    pc.u0[3] = (uint32_t)(desc->seed ^ (desc->seed >> 32));
    if (dt) pc.u3[0] = dt->bgra, pc.u3[1] = dt->overlay != NULL, pc.u3[2] = dt->iw, pc.u3[3] = dt->ih;
    /* AO rays per dispatch: all of them on a GPU; on a CPU device few enough
     * that llvmpipe's 65535-iteration loop guard cannot cut a short-ray walk */
    uint32_t ao_chunk = vx_gpu_is_cpu(g) ? 16 : pc.u0[2];
    /* descriptor set */
    /* a recorded frame's pool also holds the set of a last pass that writes the display image */
    VkDescriptorPoolSize sizes[3] = {{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, slot ? 2 * NBIND : NBIND},
                                     {VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, slot ? 2 : 1},
                                     {VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1}};
    VkDescriptorPoolCreateInfo pci = {.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO,
                                      .maxSets = slot ? 2 : 1, .poolSizeCount = slot ? 3 : 2, .pPoolSizes = sizes};
    /* a recorded frame's set lives in its slot's pool until the slot is recorded again */
    VkDescriptorPool pool = slot ? slot->pool : VK_NULL_HANDLE;
    if (!pool) VX__VK(vkCreateDescriptorPool(g->device, &pci, NULL, &pool), "vkCreateDescriptorPool");
    if (slot) slot->pool = pool, vkResetDescriptorPool(g->device, pool, 0);
    rec* R = vx_calloc(&g->alloc, 1, sizeof *R);
    if (!R) {
        if (!slot) vkDestroyDescriptorPool(g->device, pool, NULL);
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory");
    }
    R->fr = fr, R->res = out;
    R->slot = slot, R->cb = cb, R->qp = *qp, R->qcap = *qcap;
    R->untimed = slot && desc->no_timestamps; /* a waited frame is always timed (its result says how long) */
    R->groups[0] = (f.width + 7) / 8, R->groups[1] = (f.height + 7) / 8;
    VkDescriptorSetAllocateInfo ai = {.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO,
                                      .descriptorPool = pool, .descriptorSetCount = 1, .pSetLayouts = &p_gb->dsl};
    VkResult vr = vkAllocateDescriptorSets(g->device, &ai, &R->set);
    vx__pipeline* p_disp = d_tm ? p_tm : d_aa ? p_aa : d_last ? (merge ? p_merged : p_resolve) : NULL;
    if (vr == VK_SUCCESS && p_disp) {
        ai.pSetLayouts = &p_disp->dsl;
        vr = vkAllocateDescriptorSets(g->device, &ai, &R->dset);
    }
    if (vr != VK_SUCCESS) {
        r = vx__vk_fail(err, vr, "vkAllocateDescriptorSets");
        goto done;
    }
    const uint32_t tile_groups[2] = {gx, gy};
    for (int attempt = 0;; attempt++) {
        memcpy(&pc.f3[3], &fr->lidx_cap, 4);
        {
            vx__buffer* all[NBIND] = {scene_bufs[0], scene_bufs[1], scene_bufs[2], scene_bufs[3], scene_bufs[4],
                                      scene_bufs[5], scene_bufs[6], &fr->b[B_GB0], &fr->b[B_GB1], &fr->b[B_GB2],
                                      &fr->b[B_DIRECT], &fr->b[B_AO], &fr->b[B_GI], &fr->b[B_ACC], &fr->b[B_EMIT],
                                      &fr->b[B_OUT2], &fr->b[B_LIGHTS], &fr->b[B_CULL], &fr->b[B_LIDX],
                                      &fr->b[B_SKY],
                                      /* the sun's map, else placeholders */
                                      sun_map.map ? sun_map.map : &fr->b[B_SKY],
                                      sun_map.map ? sun_map.nodes : &fr->b[B_SKY],
                                      sun_map.map ? sun_map.insts_buf : &fr->b[B_SKY], &fr->b[B_MAT],
                                      /* the grids, else a placeholder */
                                      grid_buf ? grid_buf : &fr->b[B_SKY]};
            VkDescriptorBufferInfo infos[NBIND];
            VkWriteDescriptorSet w[NBIND];
            for (uint32_t i = 0; i < NBIND; i++) {
                infos[i] = (VkDescriptorBufferInfo){.buffer = all[i]->buf, .range = VK_WHOLE_SIZE};
                w[i] = (VkWriteDescriptorSet){.sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET,
                                              .dstSet = R->set,
                                              .dstBinding = i,
                                              .descriptorCount = 1,
                                              .descriptorType =
                                                  i == 0 ? VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER : VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                                              .pBufferInfo = &infos[i]};
            }
            vkUpdateDescriptorSets(g->device, NBIND, w, 0, NULL);
            if (p_disp) {
                /* the same buffers, then the overlay (a placeholder without one) and the display image */
                VkWriteDescriptorSet wd[NBIND + 2];
                VkDescriptorBufferInfo ob = {.buffer = dt->overlay ? dt->overlay->buf : fr->b[B_OUT2].buf,
                                             .range = VK_WHOLE_SIZE};
                VkDescriptorImageInfo ii = {.imageView = dt->view, .imageLayout = VK_IMAGE_LAYOUT_GENERAL};
                for (uint32_t i = 0; i < NBIND; i++) wd[i] = w[i], wd[i].dstSet = R->dset;
                wd[NBIND] = w[1], wd[NBIND].dstSet = R->dset, wd[NBIND].dstBinding = NBIND, wd[NBIND].pBufferInfo = &ob;
                wd[NBIND + 1] = (VkWriteDescriptorSet){.sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET,
                                                       .dstSet = R->dset,
                                                       .dstBinding = NBIND + 1,
                                                       .descriptorCount = 1,
                                                       .descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,
                                                       .pImageInfo = &ii};
                vkUpdateDescriptorSets(g->device, NBIND + 2, wd, 0, NULL);
            }
        }
        if ((r = rec_begin(R, err))) goto done;
        pc.u0[0] = 0;
        if (culled && !tiled) rec_cull(R, p_cull, &pc, cells, nl - ndir, NULL); /* once: the grid is the camera's */
        vx_render_desc gi_frame = base;
        gi_frame.spp = 1;
        for (uint32_t s = 0; s < f.spp; s++) {
            pc.u0[0] = s;
            if (merge) {
                /* A recorded frame of one sample whose merged kernel writes only the display image (no buffer)
                 * ends without a barrier after it: the next frame's dispatch may start while this one's last
                 * tiles run (on an H200 the drain and launch between frames was a tenth of a 0.08 ms frame).
                 * What reads or overwrites its results brings its own barrier: the display's image barrier,
                 * a table or light update (compute -> transfer), the overlay copy, the host's fence wait. */
                R->open_end = slot && d_last && f.spp == 1 && !ids;
                rec_dispatch_d(R, p_merged, &pc, merged_name, d_last);
                R->open_end = false;
                continue;
            }
            if (has_gb) {
                rec_dispatch(R, p_gb, &pc, "gbuffer");
            } else {
                /* no gbuffer: every pixel is a miss (the background) */
                vkCmdFillBuffer(R->cb, fr->b[B_GB1].buf, 0, VK_WHOLE_SIZE, 0xFFFFFFFFu);
                VkMemoryBarrier mb = {.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER,
                                      .srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT,
                                      .dstAccessMask = VK_ACCESS_SHADER_READ_BIT};
                vkCmdPipelineBarrier(R->cb, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0, 1, &mb,
                                     0, NULL, 0, NULL);
            }
            if (tiled) rec_cull(R, p_cull, &pc, cells, nl - ndir, tile_groups); /* this sample's depths */
            if (has_direct) rec_dispatch(R, p_direct, &pc, "direct");
            for (uint32_t k = 0; has_ao && k < pc.u0[2]; k += ao_chunk) {
                pc.u1[0] = k, pc.u1[1] = pc.u0[2] - k < ao_chunk ? pc.u0[2] - k : ao_chunk;
                rec_dispatch(R, p_ao, &pc, "ao");
            }
            if (has_gi) {
                /* the method records and submits its own work */
                if ((r = rec_submit(R, err))) goto done;
                vx_gi_io io = {.frame = &gi_frame, .sample = s, .out = &fr->b[B_GI]};
                double sec = 0;
                if ((r = gm->render(gm->user, &io, &sec, err))) goto done;
                int row = timing_row(out, "gi");
                out->timings[row].ms += sec * 1e3;
                out->timings[row].dispatches++;
                out->frame_ms += sec * 1e3;
                /* the method rewrote the shared frame block for its own frame */
                if ((r = vx__render_scene_bind(fr->rs, &f, scene_bufs, tspec, err))) goto done;
                if ((r = rec_begin(R, err))) goto done;
            }
            rec_dispatch_d(R, p_resolve, &pc, "resolve", d_last);
        }
        if (run_aa) rec_dispatch_d(R, p_aa, &pc, "aa", d_aa);
        if (run_tm) rec_dispatch_d(R, p_tm, &pc, "tonemap", d_tm);
        if ((r = rec_submit(R, err))) goto done;
        if (culled) {
            uint32_t head[4];
            if ((r = vx__buffer_download(g, &fr->b[B_CULL], head, sizeof head, err))) goto done;
            if (head[1] > fr->lidx_cap && attempt == 0) {
                /* the lists overflowed: grow them to what the frame needs and render it again */
                uint64_t want = (uint64_t)head[1] + head[1] / 4;
                if (want > (1u << 30)) want = 1u << 30;
                if ((r = ensure(fr, B_LIDX, want * 4, "light lists", err))) goto done;
                fr->lidx_cap = (uint32_t)want;
                memset(out, 0, sizeof *out); /* timings of the lost frame */
                out->shadow_map = sun_map.map != NULL;
                continue;
            }
            if (head[1] > fr->lidx_cap) {
                r = vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "light lists need %u entries, more than %u", head[1],
                            fr->lidx_cap);
                goto done;
            }
            out->light_entries = head[0];
        }
        {
            vx_render_image img = {.width = f.width, .height = f.height, .mode = VX_RENDER_COLOR, .alloc = &g->alloc};
            bool read = ids || !desc->no_readback; /* no_readback: the image stays on the GPU */
            if (read && (r = vx__image_read(g, &fr->b[run_aa ? B_OUT2 : B_ACC], false, ids ? &fr->b[B_GB2] : NULL, &img, err)))
                goto done;
            img.gpu_seconds = out->frame_ms * 1e-3;
            img.rays = (uint64_t)npx * f.spp;
            out->image = img;
            fr->last_out = run_aa ? B_OUT2 : B_ACC;
            if (d_last && f.spp == 1) fr->last_out = -1; /* the last pass wrote the display bytes only */
            fr->last_w = f.width, fr->last_h = f.height;
        }
        break;
    }
    if (nl) out->light_culling = cull;
    if (slot) {
        slot->res = *out, slot->recorded = true;
        fr->recorded = true;
    }
done:
    if (R->recording && !slot) vkEndCommandBuffer(g->cmd);
    R->recording = false;
    vx_free(&g->alloc, R);
    if (!slot) vkDestroyDescriptorPool(g->device, pool, NULL);
    return r;
}

vx_result vx_frame_render(vx_frame_renderer* fr, const vx_frame_desc* desc, vx_frame_result* out, vx_error* err) {
    if (!fr || !desc || !out) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    return frame_run(fr, desc, out, NULL, VK_NULL_HANDLE, NULL, err);
}

static vx_result record(vx_frame_renderer* fr, const vx_frame_desc* desc, void* cmd, uint32_t slot,
                        const vx__display_target* dt, vx_frame_result* out, vx_error* err) {
    if (!fr || !desc || !cmd || !out) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    if (slot >= VX_FRAME_SLOTS)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "slot %u: a renderer has %d", slot, VX_FRAME_SLOTS);
    if (!fr->slots[slot] && !(fr->slots[slot] = vx_calloc(&fr->g->alloc, 1, sizeof(frame_slot))))
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory");
    frame_slot* sl = fr->slots[slot];
    sl->recorded = false;
    vx_result r = frame_run(fr, desc, out, sl, (VkCommandBuffer)cmd, dt, err);
    /* the caller drops the command buffer: the scene's tables recorded there are not written */
    if (r) vx__render_scene_forget_tables(fr->rs);
    return r;
}

vx_result vx_frame_record(vx_frame_renderer* fr, const vx_frame_desc* desc, void* cmd, uint32_t slot,
                          vx_frame_result* out, vx_error* err) {
    return record(fr, desc, cmd, slot, NULL, out, err);
}

vx_result vx__frame_record_display(vx_frame_renderer* fr, const vx_frame_desc* desc, VkCommandBuffer cmd, uint32_t slot,
                                   const vx__display_target* t, vx_frame_result* out, vx_error* err) {
    if (!t || !t->view) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "no display image");
    return record(fr, desc, cmd, slot, t, out, err);
}

vx_result vx_frame_recordable(const vx_frame_desc* desc, vx_error* err) {
    if (!desc) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    vx_pass_list deflist;
    const vx_pass_list* L = desc->passes;
    if (!L) {
        vx_result r = vx_pass_list_parse(VX_PASS_LIST_DEFAULT, &deflist, err);
        if (r) return r;
        L = &deflist;
    }
    if (desc->want_ids || !desc->no_readback || vx_pass_list_has(L, VX_PASS_GI))
        return vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET, "a recorded frame is not read back and has no gi pass");
    uint32_t ndir = 0;
    for (uint32_t i = 0; desc->lights && i < desc->light_count; i++) ndir += desc->lights[i].type == VX_LIGHT_DIRECTIONAL;
    if (pick_culling(desc, vx_pass_list_has(L, VX_PASS_DIRECT), desc->light_count, ndir) != VX_LIGHT_CULLING_BRUTE)
        return vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET, "a recorded frame has no light culling");
    return VX_OK;
}

void vx_frame_record_cancel(vx_frame_renderer* fr) {
    if (fr) vx__render_scene_forget_tables(fr->rs);
}

vx_result vx_frame_record_result(vx_frame_renderer* fr, uint32_t slot, vx_frame_result* out, vx_error* err) {
    if (!fr || !out) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    frame_slot* sl = slot < VX_FRAME_SLOTS ? fr->slots[slot] : NULL;
    if (!sl || !sl->recorded) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "slot %u holds no recorded frame", slot);
    *out = sl->res;
    if (!sl->nq) return VX_OK; /* no timestamps on this queue */
    vx_result r = add_times(fr->g, sl->qp, sl->nq, sl->nd, sl->row_of, false, out, err);
    if (!r) out->image.gpu_seconds = out->frame_ms * 1e-3;
    return r;
}

/* The GGX lobe's directional albedo as f0 A + B (the path tracer's lobe:
 * probes/shaders/path_common.glsl bsdf_eval, Schlick's Fresnel f0 + (1 - f0)
 * (1 - wi.h)^5, Smith height-correlated masking), for n view cosines x
 * n roughnesses at cell centres (render/pipeline.h): 32 x 32 stratified VNDF samples each, of
 * weight F G2 / G1(wo) (Heitz 2018: f cos / pdf of a visible normal). */
static double ggx_lambda(double a2, double z) {
    double z2 = z * z;
    if (z2 >= 1) return 0;
    if (!(z2 > 0)) return 1e30;
    return 0.5 * (-1 + sqrt(1 + a2 * (1 - z2) / z2));
}
void vx_ggx_albedo_table(uint32_t n, float* out) {
    enum { S = 32 };
    for (uint32_t j = 0; j < n; j++)
        for (uint32_t i = 0; i < n; i++) {
            double nv = (i + 0.5) / n, rough = (j + 0.5) / n;
            double alpha = fmax(rough * rough, 1e-3), a2 = alpha * alpha;
            double wo[3] = {sqrt(1 - nv * nv), 0, nv};
            double A = 0, B = 0, lo = ggx_lambda(a2, nv);
            /* the visible normals' frame (Heitz 2018, "Sampling the GGX Distribution of Visible Normals") */
            double vh[3] = {alpha * wo[0], alpha * wo[1], wo[2]}, lv = sqrt(vh[0] * vh[0] + vh[1] * vh[1] + vh[2] * vh[2]);
            for (int k = 0; k < 3; k++) vh[k] /= lv;
            double l2 = vh[0] * vh[0] + vh[1] * vh[1];
            double t1[3] = {1, 0, 0};
            if (l2 > 0) t1[0] = -vh[1] / sqrt(l2), t1[1] = vh[0] / sqrt(l2), t1[2] = 0;
            double t2[3] = {vh[1] * t1[2] - vh[2] * t1[1], vh[2] * t1[0] - vh[0] * t1[2], vh[0] * t1[1] - vh[1] * t1[0]};
            for (int a = 0; a < S; a++)
                for (int b = 0; b < S; b++) {
                    double u1 = (a + 0.5) / S, u2 = (b + 0.5) / S;
                    double r = sqrt(u1), phi = 2 * 3.14159265358979323846 * u2;
                    double p1 = r * cos(phi), p2 = r * sin(phi), sh = 0.5 * (1 + vh[2]);
                    p2 = (1 - sh) * sqrt(fmax(0, 1 - p1 * p1)) + sh * p2;
                    double p3 = sqrt(fmax(0, 1 - p1 * p1 - p2 * p2)), nh[3];
                    for (int k = 0; k < 3; k++) nh[k] = p1 * t1[k] + p2 * t2[k] + p3 * vh[k];
                    double m[3] = {alpha * nh[0], alpha * nh[1], fmax(0, nh[2])};
                    double lm = sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
                    if (!(lm > 0)) continue;
                    for (int k = 0; k < 3; k++) m[k] /= lm;
                    double c = wo[0] * m[0] + wo[1] * m[1] + wo[2] * m[2];
                    double wiz = 2 * c * m[2] - wo[2];
                    if (c <= 0 || wiz <= 0) continue;
                    double li = ggx_lambda(a2, wiz), w = (1 + lo) / (1 + lo + li);
                    double s5 = pow(1 - c, 5); /* wi.h = wo.h */
                    A += (1 - s5) * w, B += s5 * w;
                }
            float* o = out + 4 * (j * n + i);
            o[0] = (float)(A / (S * S)), o[1] = (float)(B / (S * S)), o[2] = o[3] = 0;
        }
}

