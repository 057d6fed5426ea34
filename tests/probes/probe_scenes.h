/* tests/probes/probe_scenes.h - small scenes for the probe tests. */
#ifndef VX_TEST_PROBE_SCENES_H
#define VX_TEST_PROBE_SCENES_H
#include <stdio.h>

#include "probes/probes.h"
#include "render/pipeline.h"
#include "tests/render/scenes.h"

static inline size_t vx__bsq_test(uint32_t n) { return (size_t)(n + 2) * (n + 2); }

/* An n^3 model whose cell (x, y, z) has the palette index cell(x, y, z, n)
 * (0: empty), one instance at the origin. */
typedef uint8_t (*ps_cell_fn)(uint32_t x, uint32_t y, uint32_t z, uint32_t n);
static void cells_scene(vx_svo_scene* s, uint32_t n, ps_cell_fn cell) {
    size_t cap = (size_t)n * n * n, k = 0;
    uint32_t* xyz = malloc(cap * 12);
    uint8_t* pal = malloc(cap);
    for (uint32_t z = 0; z < n; z++)
        for (uint32_t y = 0; y < n; y++)
            for (uint32_t x = 0; x < n; x++) {
                uint8_t c = cell(x, y, z, n);
                if (!c) continue;
                xyz[3 * k] = x, xyz[3 * k + 1] = y, xyz[3 * k + 2] = z;
                pal[k++] = c;
            }
    vx_svo_model m;
    uint32_t size[3] = {n, n, n};
    ts_model(&m, size, xyz, pal, k);
    vx_svo_instance in = ts_inst(0, NULL, 0, 0, 0);
    ts_scene(s, &m, 1, &in, 1);
    free(xyz);
    free(pal);
}

static uint8_t box_palette;
static uint8_t box_cell(uint32_t x, uint32_t y, uint32_t z, uint32_t n) {
    return (!x || !y || !z || x == n - 1 || y == n - 1 || z == n - 1) ? box_palette : 0;
}

/* A closed n^3 box of voxels of palette c. */
static void box_scene(vx_svo_scene* s, uint32_t n, uint8_t c) {
    box_palette = c;
    cells_scene(s, n, box_cell);
}

/* floor (3), two walls (4), an emissive block (9) */
static uint8_t room_cell(uint32_t x, uint32_t y, uint32_t z, uint32_t n) {
    if (z == 0) return 3;
    if (x == 0 || y == n - 1) return 4;
    return (x >= 5 && x <= 6 && y >= 5 && y <= 6 && z <= 2) ? 9 : 0;
}

/* a metal floor (3), a wall (5), an emissive block (9) and a glass block of
 * 4^3 cells (4): the glass room of the compact passes and the pipeline cache
 * tests (inline: the other includers do not use it) */
static inline uint8_t glass_room_cell(uint32_t x, uint32_t y, uint32_t z, uint32_t n) {
    (void)n;
    if (z == 0) return 3;
    if (x == 0) return 5;
    if (x >= 8 && x <= 9 && y >= 8 && y <= 9 && z <= 2) return 9;
    return x >= 3 && x <= 6 && y >= 3 && y <= 6 && z <= 4 ? 4 : 0;
}

/* A small lit room: floor, two walls, an emissive block (palette 9). */
static void room_scene(vx_svo_scene* s) {
    cells_scene(s, 12, room_cell);
    s->palette[3] = 0xFF80A0C0u, s->palette[4] = 0xFF4080E0u, s->palette[9] = 0xFFFFFFFFu;
    static char dict[] = "_type\0_emit\0_emit\0" "0.5\0_flux\0" "1";
    s->materials = calloc(1, sizeof *s->materials);
    s->materials[0].id = 9;
    s->materials[0].dict_size = sizeof dict;
    s->materials[0].dict = malloc(sizeof dict);
    memcpy(s->materials[0].dict, dict, sizeof dict);
    s->material_count = 1;
}

/* Adds material record `id` with the dictionary "k0\0v0\0k1\0v1\0..." of n pairs. */
static inline void add_material(vx_svo_scene* s, uint32_t id, const char* const* kv, int n) {
    size_t size = 0;
    for (int i = 0; i < 2 * n; i++) size += strlen(kv[i]) + 1;
    s->materials = realloc(s->materials, (s->material_count + 1) * sizeof *s->materials);
    vx_svo_material* m = &s->materials[s->material_count++];
    memset(m, 0, sizeof *m);
    m->id = id;
    m->dict_size = (uint32_t)size;
    m->dict = malloc(size);
    size_t at = 0;
    for (int i = 0; i < 2 * n; i++) {
        memcpy(m->dict + at, kv[i], strlen(kv[i]) + 1);
        at += strlen(kv[i]) + 1;
    }
}

/* The glass room (glass_room_cell) with its materials: a metal floor, a glass
 * block of index 1.5, an emissive block (every material path of the passes). */
static inline void glass_room_scene(vx_svo_scene* s) {
    cells_scene(s, 12, glass_room_cell);
    s->palette[3] = 0xFF80A0C0u, s->palette[4] = 0xFFE0F0FFu, s->palette[5] = 0xFF4080E0u, s->palette[9] = 0xFFFFFFFFu;
    static const char* const glass[] = {"_type", "_glass", "_ri", "1.5", "_rough", "0"};
    static const char* const metal[] = {"_type", "_metal", "_metal", "1", "_rough", "0.3"};
    static const char* const emit[] = {"_type", "_emit", "_emit", "2"};
    add_material(s, 4, glass, 3);
    add_material(s, 3, metal, 3);
    add_material(s, 9, emit, 2);
}

/* A render description of w x h pixels seen from eye towards at. */
static inline vx_render_desc ps_view(uint32_t w, uint32_t h, const double eye[3], const double at[3]) {
    vx_render_desc d = {.width = w, .height = h};
    d.camera.set = true;
    memcpy(d.camera.eye, eye, 3 * sizeof *eye), memcpy(d.camera.target, at, 3 * sizeof *at);
    return d;
}

/* The mean colour of the central 12 x 10 pixels of an image (test_glass_gi, test_metal_gi: the pixels through
 * the pane, on the mirror). */
static inline void ps_centre_mean(const vx_render_image* im, double m[3]) {
    m[0] = m[1] = m[2] = 0;
    int n = 0;
    for (uint32_t y = im->height / 2 - 5; y < im->height / 2 + 5; y++)
        for (uint32_t x = im->width / 2 - 6; x < im->width / 2 + 6; x++, n++)
            for (int k = 0; k < 3; k++) m[k] += im->pixels[4 * ((size_t)y * im->width + x) + k];
    for (int k = 0; k < 3; k++) m[k] /= n;
}

/* The light of a render without a probe set: a set of no probes carries
 * sun, sky and bounces (probes.h: "ps giving their light"). */
static inline vx_probe_set light_only(double sun, const double sky[3], uint32_t bounces) {
    vx_probe_set ps = {0};
    ps.light_dir[2] = 1;
    for (int k = 0; k < 3; k++) ps.sun[k] = sun, ps.sky[k] = sky[k];
    ps.bounces = bounces - 1; /* the renderer's default bounces: the set's + 1 */
    return ps;
}

/* A set's .probes bytes (for byte-for-byte comparisons of bakes). */
static inline bool bytes_of(const vx_probe_set* ps, uint8_t** data, size_t* size) {
    vx_error err = {0};
    if (vx_probe_write(ps, NULL, data, size, &err)) {
        fprintf(stderr, "write: %s\n", err.msg);
        return false;
    }
    return true;
}

/* The pass pipeline's frame (gbuffer,direct) of s seen as base, with the n
 * lights L and a black sky (the glass tests' closed forms). */
static inline bool ps_pass_frame(vx_gpu* gpu, const vx_svo_scene* s, const vx_render_desc* base, const vx_light* L,
                                 uint32_t n, vx_render_image* out) {
    vx_error err = {0};
    vx_render_scene* rs = NULL;
    vx_frame_renderer* fr = NULL;
    vx_pass_list list;
    vx_result r = vx_pass_list_parse("gbuffer,direct", &list, &err);
    if (!r) r = vx_render_scene_create(gpu, s, &rs, &err);
    if (!r) r = vx_frame_renderer_create(rs, s, &fr, &err);
    vx_frame_result res = {0};
    if (!r) {
        vx_frame_desc fd = vx_frame_desc_defaults();
        fd.base = *base;
        fd.passes = &list;
        fd.lights = L, fd.light_count = n;
        fd.sky[0] = fd.sky[1] = fd.sky[2] = 0;
        r = vx_frame_render(fr, &fd, &res, &err);
    }
    if (r) fprintf(stderr, "  frame: %s\n", err.msg);
    vx_frame_renderer_destroy(fr);
    vx_render_scene_destroy(rs);
    *out = res.image;
    return r == VX_OK;
}

/* The path tracer's image of s seen as base (GPU with gpu_rs, else CPU; 2
 * threads, seed 5) at pixel centres: `bounces` diffuse or glossy bounces
 * (0: direct light and emission only), a constant sky of radiance sky_l, the
 * n lights L. */
static inline bool ps_pathtrace(const vx_svo_scene* s, vx_render_scene* gpu_rs, const vx_render_desc* base, uint32_t spp,
                                uint32_t bounces, double sky_l, const vx_light* L, uint32_t n, vx_render_image* out) {
    double sky[3] = {sky_l, sky_l, sky_l};
    vx_probe_set ps = light_only(0, sky, 1);
    ps.bounces = bounces ? bounces - 1 : UINT32_MAX; /* probes/render_gi.c: the set's + 1 (0 - 1 unsigned: none) */
    vx_probe_render_desc rd = {.base = base, .mode = VX_PROBE_RENDER_PATHTRACE, .spp = spp, .bounces = 0, .seed = 5,
                               .threads = 2, .lights = L, .light_count = n, .pixel_centre = true};
    vx_error err = {0};
    vx_result r = gpu_rs ? vx_probe_render_gpu(gpu_rs, s, &ps, &rd, out, &err) : vx_probe_render(s, &ps, &rd, out, &err);
    if (r) fprintf(stderr, "  path tracer: %s\n", err.msg);
    return r == VX_OK;
}

#endif
