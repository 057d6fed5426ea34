/* tests/probes/test_material_key.c - a record's material is keyed by its
 * material id (svo/svo.h vx_svo_attr_material: the VX_ATTR_MATERIAL value,
 * else the palette index), in every renderer. The same room built twice:
 * a palette model whose indices carry metal, glass and emissive MATL
 * records, and an RGBA8 model with the same colours and a material channel
 * naming materials with the same dictionaries under other ids (two above
 * 255, one the largest, 65535). The two scenes have the same cells and the
 * same attribute records in the same order (palette index -> (colour, id) is
 * one to one), so every renderer must give the same floats: the CPU path
 * tracer, the GPU path tracer, the pass pipeline (gbuffer,direct with a frame
 * light: the emission), gi=cones and gi=photons. That the RGBA scene's materials are
 * seen at all is checked against the RGBA scene without its MATL records
 * (the images must differ): keyed by palette index, as before the fix, both
 * render diffuse and dark alike. The compact layout, which carries the
 * records' material ids where the RGBA scene's channel names metal, glass and
 * emission, must give each frame of the plain layout. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cones/cones.h"
#include "photons/photons.h"
#include "probes/probes.h"
#include "render/pipeline.h"
#include "tests/gpu_test.h"
#include "tests/probes/probe_scenes.h"
#include "tests/test.h"

static vx_gpu* gpu;
static const char* gpu_skip;

enum { N = 12, ID_METAL = 300, ID_GLASS = 4, ID_EMIT = 65535, ID_WALL = 5 };

static const char* const glass_kv[] = {"_type", "_glass", "_ri", "1.5", "_rough", "0"};
static const char* const metal_kv[] = {"_type", "_metal", "_metal", "1", "_rough", "0.3"};
static const char* const emit_kv[] = {"_type", "_emit", "_emit", "2"};

/* palette index -> colour and material id of the RGBA twin (3 metal, 4 glass, 5 a diffuse wall, 9 the lamp) */
static uint32_t colour_of(uint8_t p) {
    return p == 3 ? 0xFF80A0C0u : p == 4 ? 0xFFE0F0FFu : p == 5 ? 0xFF4080E0u : 0xFFFFFFFFu;
}
static uint16_t id_of(uint8_t p) { return p == 3 ? ID_METAL : p == 4 ? ID_GLASS : p == 5 ? ID_WALL : ID_EMIT; }

static void palette_room(vx_svo_scene* s) {
    cells_scene(s, N, glass_room_cell);
    const uint8_t used[] = {3, 4, 5, 9};
    for (size_t i = 0; i < sizeof used; i++) s->palette[used[i]] = colour_of(used[i]);
    add_material(s, 4, glass_kv, 3);
    add_material(s, 3, metal_kv, 3);
    add_material(s, 9, emit_kv, 2);
}

/* The same cells as an RGBA8 model with a material channel; with_materials: its MATL records (else none). The
 * palette stays ts_scene's random one: no record reads it. */
static void rgba_room(vx_svo_scene* s, bool with_materials) {
    size_t cap = (size_t)N * N * N, k = 0;
    uint64_t* keys = malloc(cap * sizeof *keys);
    uint32_t* rgba = malloc(cap * sizeof *rgba);
    uint16_t* mat = malloc(cap * sizeof *mat);
    for (uint32_t z = 0; z < N; z++)
        for (uint32_t y = 0; y < N; y++)
            for (uint32_t x = 0; x < N; x++) {
                uint8_t c = glass_room_cell(x, y, z, N);
                if (!c) continue;
                keys[k] = vx_svo_morton(x, y, z), rgba[k] = colour_of(c), mat[k++] = id_of(c);
            }
    vx_svo_voxels v = {.size = {N, N, N}, .count = k, .keys = keys, .attrs = VX_ATTR_RGBA8 | VX_ATTR_MATERIAL,
                       .rgba = rgba, .material = mat};
    vx_svo_model m;
    vx_error err = {0};
    vx_result r = vx_svo_build_model(&(vx_svo_build_desc){0}, &v, &m, NULL, &err);
    if (r) fprintf(stderr, "build: %s\n", err.msg);
    free(keys), free(rgba), free(mat);
    vx_svo_instance in = ts_inst(0, NULL, 0, 0, 0);
    ts_scene(s, &m, 1, &in, 1);
    if (with_materials) {
        add_material(s, ID_GLASS, glass_kv, 3);
        add_material(s, ID_METAL, metal_kv, 3);
        add_material(s, ID_EMIT, emit_kv, 2);
    }
}

/* Floats of b that differ from a (bit for bit), 4 per pixel; a size mismatch counts all. */
static size_t differ(const vx_render_image* a, const vx_render_image* b) {
    size_t n = (size_t)a->width * a->height, d = 0;
    if (a->width != b->width || a->height != b->height || !a->pixels || !b->pixels) return 4 * n + 1;
    for (size_t i = 0; i < 4 * n; i++) d += memcmp(&a->pixels[i], &b->pixels[i], 4) != 0;
    return d;
}

static double sum_rgb(const vx_render_image* a) {
    double m = 0;
    for (size_t i = 0; a->pixels && i < (size_t)a->width * a->height; i++)
        m += a->pixels[4 * i] + a->pixels[4 * i + 1] + a->pixels[4 * i + 2];
    return m;
}

/* the three scenes: the palette room, its RGBA twin, the twin without MATL records */
typedef struct rooms {
    vx_svo_scene s[3];
} rooms;
static const char* const room_name[3] = {"palette", "rgba+material", "rgba, no MATL"};

static void rooms_make(rooms* r) {
    palette_room(&r->s[0]);
    rgba_room(&r->s[1], true);
    rgba_room(&r->s[2], false);
}
static void rooms_free(rooms* r) {
    for (int i = 0; i < 3; i++) vx_svo_scene_free(&r->s[i]);
}

/* im[0..2] of the three scenes: [1] must equal [0] and differ from [2]. (Not "brighter than [2]": metal seen
 * directly reflects the dim sky where the diffuse floor took the light, so a sum can go either way.) */
static void check_images(const char* what, vx_render_image im[3]) {
    size_t same = differ(&im[0], &im[1]), unlit = differ(&im[1], &im[2]);
    printf("  %-34s palette vs rgba+material: %zu floats differ; rgba+material vs no MATL: %zu differ "
           "(sums %.3f %.3f %.3f)\n", what, same, unlit, sum_rgb(&im[0]), sum_rgb(&im[1]), sum_rgb(&im[2]));
    CHECKF(same == 0, "%s: the RGBA scene with a material channel renders %zu floats unlike the palette scene", what,
           same);
    CHECKF(unlit > 0, "%s: the RGBA scene's materials are not seen (the same image without its MATL records)", what);
}

/* ---- the CPU reference's hit ------------------------------------------------------------- */

static void test_cpu_hit_material(void) {
    rooms R;
    rooms_make(&R);
    /* straight down onto the lamp (cells 8..9, 8..9, 0..2), the metal floor and the glass block */
    const double at[3][2] = {{9, 9}, {1.5, 10.5}, {4.5, 4.5}};
    const uint32_t want[3][2] = {{9, ID_EMIT}, {3, ID_METAL}, {4, ID_GLASS}};
    for (int sc = 0; sc < 2; sc++) {
        vx_render_caster* c = NULL;
        vx_error err = {0};
        REQUIRE(vx_render_caster_create(&R.s[sc], NULL, &c, &err) == VX_OK);
        for (int i = 0; i < 3; i++) {
            double o[3] = {at[i][0], at[i][1], N + 5.0}, d[3] = {0, 0, -1};
            vx_render_ray_hit h = {0};
            bool hit = vx_render_cast(c, o, d, 1e9, false, &h);
            CHECKF(hit && h.material == want[i][sc], "%s: ray %d: hit %d, material %u, want %u", room_name[sc], i,
                   (int)hit, h.material, want[i][sc]);
            CHECKF(hit && h.palette == (sc ? 0u : want[i][0]), "%s: ray %d: palette %u", room_name[sc], i, h.palette);
        }
        vx_render_caster_destroy(c);
    }
    rooms_free(&R);
}

/* ---- the path tracers -------------------------------------------------------------------- */

static void test_pathtrace_cpu(void) {
    rooms R;
    rooms_make(&R);
    double sky[3] = {0.1, 0.1, 0.1};
    vx_probe_set ps = light_only(0, sky, 3);
    vx_render_desc base = {.width = 24, .height = 18};
    vx_probe_render_desc d = {.base = &base, .mode = VX_PROBE_RENDER_PATHTRACE, .spp = 8, .seed = 3, .threads = 2};
    vx_render_image im[3] = {{0}};
    for (int i = 0; i < 3; i++) {
        vx_error err = {0};
        CHECKF(vx_probe_render(&R.s[i], &ps, &d, &im[i], &err) == VX_OK, "%s: CPU path tracer: %s", room_name[i],
               err.msg);
    }
    check_images("CPU path tracer", im);
    for (int i = 0; i < 3; i++) vx_render_image_free(&im[i]);
    rooms_free(&R);
}

static void test_pathtrace_gpu(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    rooms R;
    rooms_make(&R);
    double sky[3] = {0.1, 0.1, 0.1};
    vx_probe_set ps = light_only(0, sky, 3);
    vx_render_desc base = {.width = 24, .height = 18};
    vx_probe_render_desc d = {.base = &base, .mode = VX_PROBE_RENDER_PATHTRACE, .spp = 8, .seed = 3};
    vx_render_image im[3] = {{0}};
    for (int i = 0; i < 3; i++) {
        vx_error err = {0};
        vx_render_scene* rs = NULL;
        vx_result r = vx_render_scene_create(gpu, &R.s[i], &rs, &err);
        if (!r) r = vx_probe_render_gpu(rs, &R.s[i], &ps, &d, &im[i], &err);
        CHECKF(r == VX_OK, "%s: GPU path tracer: %s", room_name[i], err.msg);
        vx_render_scene_destroy(rs);
    }
    check_images("GPU path tracer", im);
    for (int i = 0; i < 3; i++) vx_render_image_free(&im[i]);
    rooms_free(&R);
}

/* ---- the pass pipeline and the GI methods ------------------------------------------------ */

/* Without a gi method the pass pipeline shows emission in its radiometric model only, the one frame lights
 * select (render/pipeline.c): the direct frame gets a point light above the room. */
static bool frame(vx_frame_renderer* fr, const char* list, const vx_gi_method* gm, vx_render_image* out) {
    static const vx_light point = {.type = VX_LIGHT_POINT, .position = {6, 6, 10}, .color = {1, 1, 1}, .intensity = 30};
    vx_pass_list L;
    vx_error err = {0};
    vx_frame_desc d = vx_frame_desc_defaults();
    d.base = (vx_render_desc){.width = 32, .height = 24};
    if (!gm) d.lights = &point, d.light_count = 1;
    vx_frame_result res;
    vx_result r = vx_pass_list_parse(list, &L, &err);
    d.passes = &L, d.gi = gm;
    if (!r) r = vx_frame_render(fr, &d, &res, &err);
    if (r) fprintf(stderr, "  '%s': %s\n", list, err.msg);
    else *out = res.image;
    return r == VX_OK;
}

static void test_passes(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    rooms R;
    rooms_make(&R);
    enum { DIRECT, CONES, PHOTONS, KINDS };
    static const char* const lists[KINDS] = {"gbuffer,direct (lit)", "gbuffer,direct,gi=cones", "gbuffer,direct,gi=photons"};
    vx_render_image im[KINDS][3] = {{{0}}};
    for (int i = 0; i < 3; i++) {
        vx_error err = {0};
        vx_render_scene* rs = NULL;
        vx_frame_renderer* fr = NULL;
        vx_result r = vx_render_scene_create(gpu, &R.s[i], &rs, &err);
        if (!r) r = vx_frame_renderer_create(rs, &R.s[i], &fr, &err);
        CHECKF(r == VX_OK, "%s: frame renderer: %s", room_name[i], err.msg);
        if (!r) {
            CHECKF(frame(fr, "gbuffer,direct", NULL, &im[DIRECT][i]), "%s: %s", room_name[i], lists[DIRECT]);
            vx_gi_method gm;
            vx_cone_gi* cg = NULL;
            if (vx_cone_gi_create(rs, &R.s[i], &(vx_cone_desc){.res = 32}, &gm, &cg, &err) == VX_OK)
                CHECKF(frame(fr, lists[CONES], &gm, &im[CONES][i]), "%s: %s", room_name[i], lists[CONES]);
            else CHECKF(false, "%s: gi=cones: %s", room_name[i], err.msg);
            vx_cone_gi_destroy(cg);
            vx_photon_gi* pg = NULL;
            vx_photon_desc phd = {.photons = 1 << 14, .seed = 9};
            if (vx_photon_gi_create(rs, &R.s[i], NULL, &phd, &gm, &pg, &err) == VX_OK)
                CHECKF(frame(fr, lists[PHOTONS], &gm, &im[PHOTONS][i]), "%s: %s", room_name[i], lists[PHOTONS]);
            else CHECKF(false, "%s: gi=photons: %s", room_name[i], err.msg);
            vx_photon_gi_destroy(pg);
        }
        vx_frame_renderer_destroy(fr);
        vx_render_scene_destroy(rs);
    }
    for (int k = 0; k < KINDS; k++) {
        check_images(lists[k], im[k]);
        for (int i = 0; i < 3; i++) vx_render_image_free(&im[k][i]);
    }
    CHECKF(vx_gpu_validation_errors(gpu) == 0, "%u validation errors", vx_gpu_validation_errors(gpu));
    rooms_free(&R);
}

/* ---- the compact layout ------------------------------------------------------------------ */

/* A frame of each kind the compact layout's passes render (the colour model, the direct pass with a light,
 * gi=cones, gi=photons; the GPU path tracer) of scene s in render scene rs into im[0..KINDS). */
enum { C_COLOUR, C_DIRECT, C_CONES, C_PHOTONS, C_PATH, C_KINDS };
static const char* const c_name[C_KINDS] = {"colour model", "gbuffer,direct (lit)", "gbuffer,direct,gi=cones",
                                            "gbuffer,direct,gi=photons", "GPU path tracer"};

static void all_frames(vx_render_scene* rs, const vx_svo_scene* s, const char* what, vx_render_image im[C_KINDS]) {
    vx_error err = {0};
    vx_frame_renderer* fr = NULL;
    vx_result r = vx_frame_renderer_create(rs, s, &fr, &err);
    CHECKF(r == VX_OK, "%s: frame renderer: %s", what, err.msg);
    if (!r) {
        vx_pass_list L;
        vx_frame_desc d = vx_frame_desc_defaults();
        d.base = (vx_render_desc){.width = 32, .height = 24};
        vx_frame_result res;
        vx_result cr = vx_pass_list_parse("gbuffer,direct", &L, &err);
        d.passes = &L;
        if (!cr) cr = vx_frame_render(fr, &d, &res, &err);
        CHECKF(cr == VX_OK, "%s: %s: %s", what, c_name[C_COLOUR], err.msg);
        if (!cr) im[C_COLOUR] = res.image;
        CHECKF(frame(fr, "gbuffer,direct", NULL, &im[C_DIRECT]), "%s: %s", what, c_name[C_DIRECT]);
        vx_gi_method gm;
        vx_cone_gi* cg = NULL;
        if (vx_cone_gi_create(rs, s, &(vx_cone_desc){.res = 32}, &gm, &cg, &err) == VX_OK)
            CHECKF(frame(fr, c_name[C_CONES], &gm, &im[C_CONES]), "%s: %s", what, c_name[C_CONES]);
        else CHECKF(false, "%s: gi=cones: %s", what, err.msg);
        vx_cone_gi_destroy(cg);
        vx_photon_gi* pg = NULL;
        vx_photon_desc phd = {.photons = 1 << 14, .seed = 9};
        if (vx_photon_gi_create(rs, s, NULL, &phd, &gm, &pg, &err) == VX_OK)
            CHECKF(frame(fr, c_name[C_PHOTONS], &gm, &im[C_PHOTONS]), "%s: %s", what, c_name[C_PHOTONS]);
        else CHECKF(false, "%s: gi=photons: %s", what, err.msg);
        vx_photon_gi_destroy(pg);
    }
    vx_frame_renderer_destroy(fr);
    double sky[3] = {0.1, 0.1, 0.1};
    vx_probe_set ps = light_only(0, sky, 3);
    vx_render_desc base = {.width = 24, .height = 18};
    vx_probe_render_desc pd = {.base = &base, .mode = VX_PROBE_RENDER_PATHTRACE, .spp = 8, .seed = 3};
    CHECKF(vx_probe_render_gpu(rs, s, &ps, &pd, &im[C_PATH], &err) == VX_OK, "%s: GPU path tracer: %s", what,
           err.msg);
}

/* The compact layout carries each record's material id where a model names non-diffuse materials through its
 * material channel (render/compact_gpu.c): over the three rooms, every frame of the compact layout (the colour
 * model, the lit direct pass, gi=cones, gi=photons, the GPU path tracer) is the plain layout's, float for
 * float; the ids are built for the RGBA room with MATL records only (the palette room keys its materials by
 * palette index, the room without MATL records has no material to name: no bytes, no buffer). The RGBA room's
 * compact frames must also differ from those of its twin without MATL records (its materials seen). */
static void test_compact_materials(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    rooms R;
    rooms_make(&R);
    vx_render_scene_desc cd = {.layout = VX_RENDER_LAYOUT_COMPACT, .memory_budget = 1ull << 40};
    vx_render_image im[2][3][C_KINDS] = {{{{0}}}}; /* [compact, plain][room][kind] */
    for (int i = 0; i < 3; i++) {
        vx_error err = {0};
        vx_render_scene *rs = NULL, *ps = NULL;
        REQUIRE(vx_render_scene_create_ex(gpu, &R.s[i], &cd, &rs, &err) == VX_OK);
        /* the plain layout's octree walk, which the compact kernels mirror float for float (no grids) */
        REQUIRE(vx_render_scene_create_ex(gpu, &R.s[i], &(vx_render_scene_desc){.grid_budget = VX_RENDER_NO_GRID}, &ps,
                                          &err) == VX_OK);
        vx_render_layout_info li;
        vx_render_scene_layout(rs, &li);
        printf("  compact %-16s material ids: %llu bytes (%llu cells; layout %llu bytes)\n", room_name[i],
               (unsigned long long)li.material_bytes, (unsigned long long)li.voxels, (unsigned long long)li.bytes);
        CHECKF(li.layout == VX_RENDER_LAYOUT_COMPACT, "%s: not the compact layout", room_name[i]);
        CHECKF(i == 1 ? li.material_bytes > 0 : li.material_bytes == 0, "%s: %llu bytes of material ids",
               room_name[i], (unsigned long long)li.material_bytes);
        all_frames(rs, &R.s[i], room_name[i], im[0][i]);
        all_frames(ps, &R.s[i], room_name[i], im[1][i]);
        vx_render_scene_destroy(rs), vx_render_scene_destroy(ps);
    }
    for (int k = 0; k < C_KINDS; k++) {
        size_t d[3], unlit = differ(&im[0][1][k], &im[0][2][k]);
        for (int i = 0; i < 3; i++) d[i] = differ(&im[1][i][k], &im[0][i][k]);
        printf("  %-28s compact vs plain: %zu %zu %zu floats differ (palette, rgba+material, no MATL); "
               "compact rgba+material vs no MATL: %zu\n", c_name[k], d[0], d[1], d[2], unlit);
        for (int i = 0; i < 3; i++)
            CHECKF(d[i] == 0, "%s, %s: the compact layout's frame differs from the plain layout's in %zu floats",
                   room_name[i], c_name[k], d[i]);
        if (k != C_COLOUR) /* (the colour model reads no material) */
            CHECKF(unlit > 0, "%s: the compact RGBA room's materials are not seen", c_name[k]);
    }
    for (int l = 0; l < 2; l++)
        for (int i = 0; i < 3; i++)
            for (int k = 0; k < C_KINDS; k++) vx_render_image_free(&im[l][i][k]);
    CHECKF(vx_gpu_validation_errors(gpu) == 0, "%u validation errors", vx_gpu_validation_errors(gpu));
    rooms_free(&R);
}

/* ---- the emission's own colour (_emit_color, glTF's emissiveFactor) -------------------------- */

/* Mean of channel c over the image. */
static double mean_ch(const vx_render_image* a, int c) {
    double m = 0;
    size_t n = (size_t)a->width * a->height;
    for (size_t i = 0; a->pixels && i < n; i++) m += a->pixels[4 * i + c];
    return n ? m / n : 0;
}

/* The palette room's white lamp (emission 2) against the same lamp with the emission colour (1, 0.5, 0.25):
 * light is carried per channel, so every renderer's red is the white lamp's (the same paths, the same red
 * emission), its green and blue are less, and the lamp seen directly differs by the emissions' difference,
 * (0, 1, 1.5), where the voxel's colour would have given none. */
static void test_emission_color(void) {
    static const char* const own_kv[] = {"_type", "_emit", "_emit", "2", "_emit_color", "1 0.5 0.25"};
    vx_svo_scene s[2];
    palette_room(&s[0]);
    palette_room(&s[1]);
    for (uint32_t i = 0; i < s[1].material_count; i++)
        if (s[1].materials[i].id == 9) s[1].materials[i].id = 1000; /* a later record of id 9 would not win */
    add_material(&s[1], 9, own_kv, 3);
    REQUIRE(vx_svo_scene_material(&s[1], 9).emission_color[1] == 0.5);
    enum { CPU_PT, GPU_PT, DIRECT, CONES, PHOTONS, KINDS };
    static const char* const name[KINDS] = {"CPU path tracer", "GPU path tracer", "gbuffer,direct (lit)",
                                            "gbuffer,direct,gi=cones", "gbuffer,direct,gi=photons"};
    vx_render_image im[KINDS][2] = {{{0}}};
    double sky[3] = {0.1, 0.1, 0.1};
    vx_probe_set ps = light_only(0, sky, 3);
    vx_render_desc base = {.width = 24, .height = 18};
    vx_probe_render_desc pd = {.base = &base, .mode = VX_PROBE_RENDER_PATHTRACE, .spp = 8, .seed = 3, .threads = 2};
    int kinds = gpu_skip ? 1 : KINDS;
    for (int i = 0; i < 2; i++) {
        vx_error err = {0};
        CHECKF(vx_probe_render(&s[i], &ps, &pd, &im[CPU_PT][i], &err) == VX_OK, "CPU path tracer: %s", err.msg);
        if (gpu_skip) continue;
        vx_render_scene* rs = NULL;
        vx_frame_renderer* fr = NULL;
        vx_result r = vx_render_scene_create(gpu, &s[i], &rs, &err);
        if (!r) CHECKF(vx_probe_render_gpu(rs, &s[i], &ps, &pd, &im[GPU_PT][i], &err) == VX_OK, "GPU path tracer: %s", err.msg);
        if (!r) r = vx_frame_renderer_create(rs, &s[i], &fr, &err);
        CHECKF(r == VX_OK, "frame renderer: %s", err.msg);
        if (!r) {
            CHECK(frame(fr, "gbuffer,direct", NULL, &im[DIRECT][i]));
            vx_gi_method gm;
            vx_cone_gi* cg = NULL;
            if (vx_cone_gi_create(rs, &s[i], &(vx_cone_desc){.res = 32}, &gm, &cg, &err) == VX_OK)
                CHECK(frame(fr, "gbuffer,direct,gi=cones", &gm, &im[CONES][i]));
            else CHECKF(false, "gi=cones: %s", err.msg);
            vx_cone_gi_destroy(cg);
            vx_photon_gi* pg = NULL;
            vx_photon_desc phd = {.photons = 1 << 14, .seed = 9};
            if (vx_photon_gi_create(rs, &s[i], NULL, &phd, &gm, &pg, &err) == VX_OK)
                CHECK(frame(fr, "gbuffer,direct,gi=photons", &gm, &im[PHOTONS][i]));
            else CHECKF(false, "gi=photons: %s", err.msg);
            vx_photon_gi_destroy(pg);
        }
        vx_frame_renderer_destroy(fr);
        vx_render_scene_destroy(rs);
    }
    for (int k = 0; k < kinds; k++) {
        const vx_render_image *w = &im[k][0], *o = &im[k][1];
        if (!w->pixels || !o->pixels || w->width != o->width || w->height != o->height) {
            CHECKF(false, "%s: no image", name[k]);
            continue;
        }
        double mw[3], mo[3];
        for (int c = 0; c < 3; c++) mw[c] = mean_ch(w, c), mo[c] = mean_ch(o, c);
        /* the brightest red pixel of the coloured lamp's image: the lamp seen directly */
        size_t n = (size_t)o->width * o->height, at = 0;
        for (size_t i = 1; i < n; i++)
            if (o->pixels[4 * i] > o->pixels[4 * at]) at = i;
        const float* px = &o->pixels[4 * at];
        const float* pw = &w->pixels[4 * at];
        printf("  %-26s mean RGB white lamp %.4f %.4f %.4f, coloured %.4f %.4f %.4f; brightest %.3f %.3f %.3f (white "
               "lamp there %.3f %.3f %.3f)\n", name[k], mw[0], mw[1], mw[2], mo[0], mo[1], mo[2], px[0], px[1], px[2],
               pw[0], pw[1], pw[2]);
        /* photons: the sources are picked by power, so the coloured lamp sends fewer photons (noise in red) */
        double tol = k == PHOTONS ? 0.02 : 2e-3;
        CHECKF(fabs(mo[0] / mw[0] - 1) < tol, "%s: red %.5f against the white lamp's %.5f", name[k], mo[0], mw[0]);
        CHECKF(mw[1] - mo[1] > 0.005 && mw[2] - mo[2] > mw[1] - mo[1], "%s: green %.5f, blue %.5f against %.5f, %.5f",
               name[k], mo[1], mo[2], mw[1], mw[2]);
        /* there the emission differs by (2, 2, 2) - (2, 1, 0.5); the rest of the light is the same */
        CHECKF(px[0] > 1.5 && fabs(pw[0] - px[0]) < 0.05 && fabs(pw[1] - px[1] - 1) < 0.05 &&
                   fabs(pw[2] - px[2] - 1.5) < 0.05,
               "%s: the lamp seen directly is %.3f %.3f %.3f, white %.3f %.3f %.3f", name[k], px[0], px[1], px[2],
               pw[0], pw[1], pw[2]);
        for (int i = 0; i < 2; i++) vx_render_image_free(&im[k][i]);
    }
    if (!gpu_skip) CHECKF(vx_gpu_validation_errors(gpu) == 0, "%u validation errors", vx_gpu_validation_errors(gpu));
    vx_svo_scene_free(&s[0]), vx_svo_scene_free(&s[1]);
}

int main(void) {
    int logged = 0;
    vx_logger lg = {.func = vx_test_validation_log, .user_data = &logged};
    gpu_skip = vx_test_gpu_open((vx_gpu_desc){.logger = &lg}, true, &gpu);
    (void)box_scene, (void)room_scene, (void)ts_random_model; /* the shared headers' other scenes */
    RUN(test_cpu_hit_material);
    RUN(test_pathtrace_cpu);
    RUN(test_pathtrace_gpu);
    RUN(test_passes);
    RUN(test_compact_materials);
    RUN(test_emission_color);
    vx_gpu_destroy(gpu);
    return vx_test_finish();
}
