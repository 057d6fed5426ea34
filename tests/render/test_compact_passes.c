/* tests/render/test_compact_passes.c - the pass pipeline and the GI methods
 * over a scene in the compact layout (render/compact.h, issue 18): the
 * kernels that include trace_common.glsl walk the compact geometry when its
 * COMPACT constant is set (render_scene.c binds the compact buffers), so a
 * frame of gbuffer, direct and AO, and of each GI method (probes with a
 * probe set baked on the GPU, pathtrace, cones, photons), must give the
 * plain layout's image bit for bit, and the probe bake the same bytes.
 * Scenes: a generated one (palette and RGBA models, rotated instances, a
 * full-cube leaf model), a room with an emissive block, a glass block and a
 * metal floor (the per-record tables, per palette index in a compact scene),
 * and corpus .vox scenes (lavapipe in CI). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cones/cones.h"
#include "photons/photons.h"
#include "probes/probes.h"
#include "render/pipeline.h"
#include "render/gpu.h" /* vx__render_scene_compact */
#include "tests/gpu_test.h"
#include "tests/probes/probe_scenes.h"
#include "tests/render/scenes.h"
#include "tests/test.h"
#include "tests/test_vox.h"

static vx_gpu* gpu;
static const char* gpu_skip;


/* One render scene and its frame renderer in a given layout. */
typedef struct side {
    vx_render_scene* rs;
    vx_frame_renderer* fr;
} side;

static bool side_open(const vx_svo_scene* s, vx_render_layout layout, uint32_t bricks, side* o) {
    vx_error err = {0};
    memset(o, 0, sizeof *o);
    /* the whole compact layout: a budget no scene here reaches, so that it is not paged. No grids: the compact
     * kernels mirror the plain layout's octree walk float for float, and the grid walk (which the plain layout
     * takes by default, render.h grid_budget) reaches the same cells by other arithmetic, so ties may differ */
    vx_render_scene_desc d = {
        .layout = layout, .memory_budget = 1ull << 40, .compact_bricks = bricks, .grid_budget = VX_RENDER_NO_GRID};
    if (vx_render_scene_create_ex(gpu, s, &d, &o->rs, &err) || vx_frame_renderer_create(o->rs, s, &o->fr, &err)) {
        fprintf(stderr, "  create (%s): %s\n", vx_render_layout_name(layout), err.msg);
        vx_render_scene_destroy(o->rs);
        o->rs = NULL;
        return false;
    }
    return true;
}

static void side_close(side* o) {
    vx_frame_renderer_destroy(o->fr);
    vx_render_scene_destroy(o->rs);
}

/* merged: the passes merged where the pipeline can (frame.comp), else each its own dispatch so that every kernel
 * runs; *dispatches (if not NULL) the frame's timed dispatches */
static bool render_as(side* o, const char* list, const vx_gi_method* gm, const vx_frame_desc* t, vx_show show,
                      bool merged, vx_render_image* out, uint32_t* dispatches) {
    vx_pass_list L;
    vx_error err = {0};
    if (vx_pass_list_parse(list, &L, &err)) {
        fprintf(stderr, "  parse '%s': %s\n", list, err.msg);
        return false;
    }
    vx_frame_desc d = *t;
    d.passes = &L;
    d.gi = gm;
    d.show = show;
    d.separate_passes = !merged;
    vx_frame_result res;
    if (vx_frame_render(o->fr, &d, &res, &err)) {
        fprintf(stderr, "  render '%s': %s\n", list, err.msg);
        return false;
    }
    *out = res.image;
    if (dispatches) *dispatches = res.timing_count;
    return true;
}

static bool render(side* o, const char* list, const vx_gi_method* gm, const vx_frame_desc* t, vx_show show,
                   vx_render_image* out) {
    return render_as(o, list, gm, t, show, false, out, NULL);
}

/* The floats of b that differ from a; *hits the pixels a shows geometry on (alpha > 0). */
static size_t differ(const vx_render_image* a, const vx_render_image* b, size_t* hits) {
    size_t n = (size_t)a->width * a->height, diff = 0;
    *hits = 0;
    if (b->width != a->width || b->height != a->height) return 4 * n;
    for (size_t i = 0; i < n; i++) {
        *hits += a->pixels[4 * i + 3] > 0;
        for (int k = 0; k < 4; k++) diff += memcmp(&a->pixels[4 * i + k], &b->pixels[4 * i + k], 4) != 0;
    }
    return diff;
}

/* The first few pixels where b differs from a (same size), both values (named la and lb). */
static void list_pixels(const vx_render_image* a, const vx_render_image* b, const char* la, const char* lb) {
    int shown = 0;
    for (size_t i = 0; i < (size_t)a->width * a->height && shown < 4; i++) {
        const float *x = &a->pixels[4 * i], *y = &b->pixels[4 * i];
        if (!memcmp(x, y, 16)) continue;
        printf("      pixel (%zu, %zu): %s %.9g %.9g %.9g %.9g, %s %.9g %.9g %.9g %.9g\n", i % a->width, i / a->width, la,
               x[0], x[1], x[2], x[3], lb, y[0], y[1], y[2], y[3]);
        shown++;
    }
}

/* Where a frame differs between the layouts: each intermediate image (--show) of both, so that the pass whose
 * kernel makes the difference is named (the G-buffer's albedo, normal, depth and instance; direct; gi; ao), with
 * the first differing pixels. */
static void report(side* p, side* c, const char* list, const vx_gi_method* gp, const vx_gi_method* gc,
                   const vx_frame_desc* t) {
    for (int sh = VX_SHOW_ALBEDO; sh < VX_SHOW_COUNT; sh++) {
        if (sh == VX_SHOW_MATERIAL) continue; /* the record numbers are each layout's own (compact: palette indices) */
        vx_render_image a = {0}, b = {0};
        if (render(p, list, gp, t, (vx_show)sh, &a) && render(c, list, gc, t, (vx_show)sh, &b)) {
            size_t hits = 0, diff = differ(&a, &b, &hits);
            printf("    show %-9s %zu floats differ\n", vx_show_name((vx_show)sh), diff);
            if (diff && a.width == b.width && a.height == b.height) list_pixels(&a, &b, "plain", "compact");
        }
        vx_render_image_free(&a);
        vx_render_image_free(&b);
    }
}

static void compare_show(const char* name, const char* list, side* p, side* c, const vx_gi_method* gp,
                         const vx_gi_method* gc, const vx_frame_desc* t, vx_show show) {
    vx_render_image a = {0}, b = {0};
    bool ok = render(p, list, gp, t, show, &a) && render(c, list, gc, t, show, &b);
    CHECKF(ok, "%s '%s': rendered", name, list);
    if (ok) {
        size_t hits = 0, diff = differ(&a, &b, &hits);
        printf("  %-28s %-36s %ux%u: %zu pixels hit, %zu floats differ%s%s%s\n", name, list, a.width, a.height, hits,
               diff, t->light_count ? " (frame lights)" : "", show ? ", show " : "", show ? vx_show_name(show) : "");
        CHECKF(diff == 0, "%s '%s': %zu floats differ", name, list, diff);
        CHECKF(hits > 0, "%s '%s': nothing hit", name, list);
        if (diff && a.width == b.width && a.height == b.height) {
            list_pixels(&a, &b, "plain", "compact");
            if (show == VX_SHOW_FINAL) report(p, c, list, gp, gc, t);
        }
    }
    vx_render_image_free(&a);
    vx_render_image_free(&b);
}

static void compare(const char* name, const char* list, side* p, side* c, const vx_gi_method* gp,
                    const vx_gi_method* gc, const vx_frame_desc* t) {
    compare_show(name, list, p, c, gp, gc, t, VX_SHOW_FINAL);
}

/* The separate passes (gbuffer.comp, direct.comp, ao.comp, resolve.comp: each its own dispatch) against the merged
 * kernel (frame.comp: the same rays in one dispatch) in one layout: the same floats. They are different kernels,
 * so on NVIDIA each pipeline's walk would be contracted on its own where it could be (cmake/shaders.cmake), and a
 * shadow or AO ray's hit could flip between them. */
static void compare_merged(const char* name, const char* list, side* o, const vx_frame_desc* t) {
    vx_render_image a = {0}, b = {0};
    uint32_t na = 0, nb = 0;
    bool ok = render_as(o, list, NULL, t, VX_SHOW_FINAL, false, &a, &na) &&
              render_as(o, list, NULL, t, VX_SHOW_FINAL, true, &b, &nb);
    CHECKF(ok, "%s '%s': rendered separate and merged", name, list);
    if (ok) {
        size_t hits = 0, diff = differ(&a, &b, &hits);
        const char* layout = vx_render_layout_name(vx__render_scene_compact(o->rs) ? VX_RENDER_LAYOUT_COMPACT
                                                                                 : VX_RENDER_LAYOUT_PLAIN);
        printf("  %-28s %-36s %ux%u: %zu pixels hit, separate (%u dispatches) and merged (%u) %s: %zu floats differ%s\n",
               name, list, a.width, a.height, hits, na, nb, layout, diff, t->light_count ? " (frame lights)" : "");
        CHECKF(nb < na, "%s '%s': %u dispatches merged, %u separate: not merged", name, list, nb, na);
        CHECKF(diff == 0, "%s '%s' %s: separate and merged passes: %zu floats differ", name, list, layout, diff);
        CHECKF(hits > 0, "%s '%s': nothing hit", name, list);
        if (diff && a.width == b.width && a.height == b.height) list_pixels(&a, &b, "separate", "merged");
    }
    vx_render_image_free(&a);
    vx_render_image_free(&b);
}

/* The two layouts' radiance volumes, level by level: the same halfs (voxelize.comp's opacity, inject.comp's
 * radiance, filter.comp's levels above), so that a difference in the gi image is placed in the volume's kernels
 * or in cone.comp's own rays. */
static void compare_volumes(const char* name, const char* what, vx_cone_gi* a, vx_cone_gi* b) {
    vx_cone_info ia, ib;
    vx_cone_gi_info(a, &ia);
    vx_cone_gi_info(b, &ib);
    bool same_shape = ia.levels == ib.levels && ia.entries == ib.entries && !memcmp(ia.dims, ib.dims, sizeof ia.dims);
    CHECKF(same_shape, "%s %s: the volumes' shapes differ", name, what);
    CHECKF(ia.surface_voxels == ib.surface_voxels, "%s %s: %u and %u surface voxels", name, what, ia.surface_voxels,
           ib.surface_voxels);
    if (!same_shape) return;
    size_t rgb = 0, alpha = 0, level0 = 0;
    for (uint32_t l = 0; l < ia.levels; l++) {
        size_t n = (size_t)ia.dims[l][0] * ia.dims[l][1] * ia.dims[l][2] * ia.entries * 4;
        float *x = malloc(n * sizeof *x), *y = malloc(n * sizeof *y);
        vx_error err = {0};
        bool ok = x && y && !vx_cone_gi_read_level(a, l, x, n, &err) && !vx_cone_gi_read_level(b, l, y, n, &err);
        CHECKF(ok, "%s %s: level %u read: %s", name, what, l, err.msg);
        for (size_t i = 0; ok && i < n; i++)
            if (memcmp(&x[i], &y[i], sizeof *x)) (i % 4 == 3 ? alpha++ : rgb++), level0 += l == 0;
        free(x), free(y);
    }
    printf("  %-28s %-36s %u levels, %u surface voxels: %zu radiance and %zu opacity floats differ (%zu at level 0)\n",
           name, what, ia.levels, ia.surface_voxels, rgb, alpha, level0);
    CHECKF(rgb + alpha == 0, "%s %s: the volumes differ in %zu radiance and %zu opacity floats", name, what, rgb, alpha);
}

static bool probe_sets_equal(const vx_probe_set* a, const vx_probe_set* b) {
    if (a->res != b->res || a->low_res != b->low_res || a->count != b->count || a->probe_count != b->probe_count)
        return false;
    size_t n = a->count, r2 = (size_t)(a->res + 2) * (a->res + 2), l2 = (size_t)(a->low_res + 2) * (a->low_res + 2);
    return !memcmp(a->probes, b->probes, a->probe_count * sizeof *a->probes) &&
           !memcmp(a->radiance, b->radiance, n * r2 * 3 * 2) && !memcmp(a->normal, b->normal, n * r2 * 4) &&
           !memcmp(a->distance, b->distance, n * r2 * 2) && !memcmp(a->low, b->low, n * l2 * 2) &&
           !memcmp(a->irradiance, b->irradiance, n * 100 * 3 * 2) && !memcmp(a->moments, b->moments, n * 324 * 2 * 4);
}

/* The scene's frame lights: a point light above the scene's middle, a spot light from a corner. */
static void frame_lights(const vx_svo_scene* s, vx_light lights[2]) {
    double lo[3], hi[3];
    vx_svo_scene_world_bounds(s, lo, hi);
    lights[0] = (vx_light){.type = VX_LIGHT_POINT, .color = {1, 0.9, 0.8}};
    lights[1] = (vx_light){.type = VX_LIGHT_SPOT, .color = {0.5, 0.7, 1}, .inner_cone = 0.3, .outer_cone = 0.6};
    double ext = 0;
    for (int k = 0; k < 3; k++) {
        ext = fmax(ext, hi[k] - lo[k]);
        lights[0].position[k] = 0.5 * (lo[k] + hi[k]) + (k == 2 ? 0.3 * (hi[k] - lo[k]) : 0.0);
        lights[1].position[k] = k == 2 ? hi[k] : lo[k] + 0.1 * (hi[k] - lo[k]);
        lights[1].direction[k] = 0.5 * (lo[k] + hi[k]) - lights[1].position[k];
    }
    double dl = sqrt(lights[1].direction[0] * lights[1].direction[0] + lights[1].direction[1] * lights[1].direction[1] +
                     lights[1].direction[2] * lights[1].direction[2]);
    for (int k = 0; k < 3; k++) lights[1].direction[k] /= dl;
    lights[0].intensity = lights[1].intensity = 0.5 * ext * ext;
}

/* The frames of the passes: the G-buffer, direct and AO, frame lights, the separate passes against the merged
 * kernel, both layouts bit for bit. */
static void check_frames(const char* name, const vx_svo_scene* s, side* p, side* c, const vx_frame_desc* b) {
    vx_frame_desc base = *b;
    /* the G-buffer itself: the same hit (instance, face, colour) at the same depth on every pixel; the final
     * image hides a depth one float step apart where nothing reads the hit point (the H200's room: 5 pixels
     * with main's gbuffer.comp, whose walk the NVIDIA compiler contracted per layout) */
    static const vx_show gshows[] = {VX_SHOW_DEPTH, VX_SHOW_NORMAL, VX_SHOW_ALBEDO, VX_SHOW_INSTANCE};
    for (size_t k = 0; k < sizeof gshows / sizeof gshows[0]; k++)
        compare_show(name, "gbuffer", p, c, NULL, NULL, &base, gshows[k]);
    compare(name, "gbuffer,direct", p, c, NULL, NULL, &base);
    compare(name, "gbuffer,direct,ao", p, c, NULL, NULL, &base);
    vx_frame_desc two = base;
    two.base.spp = 2;
    compare(name, "gbuffer,direct,ao,aa,tonemap", p, c, NULL, NULL, &two);
    /* frame lights (their shadow rays) */
    vx_light lights[2];
    frame_lights(s, lights);
    vx_frame_desc lit = base;
    lit.lights = lights, lit.light_count = 2;
    compare(name, "gbuffer,direct", p, c, NULL, NULL, &lit);
    /* the separate passes against the merged kernel, each layout: the sun's shadow rays, the AO rays, the frame
     * lights' shadow rays */
    for (int k = 0; k < 2; k++) {
        side* o = k ? c : p;
        compare_merged(name, "gbuffer,direct", o, &base);
        compare_merged(name, "gbuffer,direct,ao", o, &base);
        compare_merged(name, "gbuffer,direct", o, &lit);
    }
}

/* The GI methods' frames that need no bake: gi=photons, gi=cones (its volume too), both layouts bit for bit. */
static void check_gi_frames(const char* name, const vx_svo_scene* s, side* p, side* c, const vx_frame_desc* b) {
    vx_frame_desc base = *b, lit = *b;
    vx_error err = {0};
    vx_light lights[2];
    frame_lights(s, lights);
    lit.lights = lights, lit.light_count = 2;
    /* gi=photons */
    {
        vx_gi_method gp, gc;
        vx_photon_gi *pp = NULL, *pc = NULL;
        vx_photon_desc phd = {.photons = 1 << 14, .seed = 9};
        vx_result q = vx_photon_gi_create(p->rs, s, NULL, &phd, &gp, &pp, &err);
        if (!q) q = vx_photon_gi_create(c->rs, s, NULL, &phd, &gc, &pc, &err);
        CHECKF(q == VX_OK, "%s: gi=photons: %s", name, err.msg);
        if (!q) compare(name, "gbuffer,direct,gi=photons", p, c, &gp, &gc, &base);
        vx_photon_gi_destroy(pp);
        vx_photon_gi_destroy(pc);
    }
    /* gi=cones: its voxelization, its light injection (shadow rays) and its gi pass (each pixel's primary ray)
     * trace the scene; the volumes compared level by level, then the frames. Then with frame lights injected
     * (their shadow rays) and the cone shadows (gbuffer,gi=cones: the gi image holds the direct light). */
    for (int k = 0; k < 2; k++) {
        vx_gi_method gp, gc;
        vx_cone_gi *cp = NULL, *cc = NULL;
        vx_cone_desc cd = {.res = 32};
        if (k == 1) cd.lights = lights, cd.light_count = 2, cd.shadows = true;
        vx_result q = vx_cone_gi_create(p->rs, s, &cd, &gp, &cp, &err);
        if (!q) q = vx_cone_gi_create(c->rs, s, &cd, &gc, &cc, &err);
        CHECKF(q == VX_OK, "%s: gi=cones: %s", name, err.msg);
        if (!q) {
            compare_volumes(name, k ? "cone volume (lights)" : "cone volume", cp, cc);
            compare(name, k ? "gbuffer,gi=cones" : "gbuffer,direct,gi=cones", p, c, &gp, &gc, k ? &lit : &base);
        }
        vx_cone_gi_destroy(cp);
        vx_cone_gi_destroy(cc);
    }
}

/* The probe bakes (the same bytes) and the GI methods that read them (gi=probes, gi=pathtrace). */
static void check_bakes(const char* name, const vx_svo_scene* s, side* p, side* c, const vx_frame_desc* b) {
    vx_frame_desc base = *b;
    vx_error err = {0};
    /* the probe bake: the same bytes from both layouts; a 3x3x3 grid at R=32 too, whose texel centre rays
     * meet solid cubes at their edges, where a cube of one colour (one leaf in the plain layout, cells in the
     * compact one) gave other cells, faces or distances before the bake's cell walk (probe.comp CELL_HITS:
     * eph_monu1's differed on lavapipe, the Cornell box's on the H200; issue 18, branch bakex); and the compact
     * layout's bake without its beam pass (probe_beam.comp's walk of the compact slots, issue 18 branch rdr4:
     * start distances that passed a cell would lose its hits); and without the sun's depth map, which the
     * compact scene lists from its geometry (issue 18, branch smap3: a bound below a cell would lose its shadow) */
    {
        vx_probe_bake_stats stc = {0};
        vx_probe_bake_desc be = {.grid = {3, 3, 3}, .res = 32, .spp = 1, .bounces = 1, .seed = 5};
        vx_probe_set ep = {0}, ec = {0}, en = {0}, es = {0};
        bool ok = vx_probe_bake_gpu(p->rs, s, &be, &ep, &err) == VX_OK;
        be.stats = &stc;
        ok = ok && vx_probe_bake_gpu(c->rs, s, &be, &ec, &err) == VX_OK;
        be.stats = NULL;
        be.no_beam = true;
        ok = ok && vx_probe_bake_gpu(c->rs, s, &be, &en, &err) == VX_OK;
        be.no_beam = false, be.no_shadow_map = true;
        ok = ok && vx_probe_bake_gpu(c->rs, s, &be, &es, &err) == VX_OK;
        CHECKF(ok, "%s: edge bake: %s", name, err.msg);
        if (ok) {
            bool same = probe_sets_equal(&ep, &ec), beam = probe_sets_equal(&ec, &en), map = probe_sets_equal(&ec, &es);
            printf("  %-28s probe bake (%u probes at %u, edge rays): %s; compact without its beam: %s, without its "
                   "sun map (%u texels): %s\n", name, ep.probe_count, ep.res, same ? "same bytes" : "DIFFER",
                   beam ? "same bytes" : "DIFFER", stc.sun_map_side, map ? "same bytes" : "DIFFER");
            CHECKF(same, "%s: the probe sets at R=32 differ", name);
            CHECKF(beam, "%s: the compact layout's bakes at R=32 with and without the beam differ", name);
            CHECKF(map, "%s: the compact layout's bakes at R=32 with and without the sun map differ", name);
            CHECKF(stc.sun_map_side > 0, "%s: the compact layout's bake had no sun map", name);
        }
        vx_probe_set_free(&ep), vx_probe_set_free(&ec), vx_probe_set_free(&en), vx_probe_set_free(&es);
    }
    vx_probe_bake_desc bd = {.grid = {2, 2, 2}, .res = 16, .spp = 2, .bounces = 1, .seed = 5};
    vx_probe_set psp = {0}, psc = {0};
    vx_result r1 = vx_probe_bake_gpu(p->rs, s, &bd, &psp, &err);
    CHECKF(r1 == VX_OK, "%s: plain bake: %s", name, err.msg);
    vx_result r2 = vx_probe_bake_gpu(c->rs, s, &bd, &psc, &err);
    CHECKF(r2 == VX_OK, "%s: compact bake: %s", name, err.msg);
    if (!r1 && !r2) {
        bool same = probe_sets_equal(&psp, &psc);
        printf("  %-28s probe bake (%u probes at %u): %s\n", name, psp.probe_count, psp.res, same ? "same bytes" : "DIFFER");
        CHECKF(same, "%s: the probe sets differ", name);
        /* gi=probes and gi=pathtrace (the probes' light) */
        static const char* const methods[] = {"probes", "pathtrace"};
        for (int k = 0; k < 2; k++) {
            vx_probe_render_desc pd = {.spp = 2, .bounces = 1, .seed = 3};
            vx_gi_method gp, gc;
            vx_probe_gi *pgp = NULL, *pgc = NULL;
            vx_result q = vx_probe_gi_create(p->rs, s, &psp, methods[k], &pd, &gp, &pgp, &err);
            if (!q) q = vx_probe_gi_create(c->rs, s, &psc, methods[k], &pd, &gc, &pgc, &err);
            CHECKF(q == VX_OK, "%s: gi=%s: %s", name, methods[k], err.msg);
            char list[64];
            snprintf(list, sizeof list, "gbuffer,direct,gi=%s", methods[k]);
            if (!q) compare(name, list, p, c, &gp, &gc, &base);
            vx_probe_gi_destroy(pgp);
            vx_probe_gi_destroy(pgc);
        }
    }
    vx_probe_set_free(&psp);
    vx_probe_set_free(&psc);
}

/* All scenes through the one device: its pipeline cache holds the pass, GI
 * and bake variants of both layouts of every scene, as a session that opens
 * several scenes does. Each scene's pass frames, GI frames and bakes are
 * separate tests (FRAMES, GI_FRAMES, BAKES), so that VX_TEST_ONLY picks one:
 * a fresh GPU machine compiles every pipeline cold.
 * bricks: the compact layout's brick form (VX_RENDER_BRICKS_INLINE or _DICT; the scenes take turns) */
enum { FRAMES = 1, BAKES = 2, GI_FRAMES = 4 };

static void check_scene(const char* name, const vx_svo_scene* s, uint32_t w, uint32_t h, uint32_t bricks, int parts) {
    side p, c;
    if (!side_open(s, VX_RENDER_LAYOUT_PLAIN, 0, &p)) {
        CHECKF(false, "%s: plain scene", name);
        return;
    }
    if (!side_open(s, VX_RENDER_LAYOUT_COMPACT, bricks, &c)) {
        CHECKF(false, "%s: compact scene", name);
        side_close(&p);
        return;
    }
    vx_render_layout_info li;
    vx_render_scene_layout(c.rs, &li);
    CHECKF(li.layout == VX_RENDER_LAYOUT_COMPACT && li.pages == 0 && vx__render_scene_compact(c.rs) &&
               !vx__render_scene_compact(p.rs) && li.brick_dict == (bricks == VX_RENDER_BRICKS_DICT),
           "%s: layout %s, %u pages, brick dictionary %d", name, vx_render_layout_name(li.layout), li.pages,
           (int)li.brick_dict);
    vx_frame_desc base = vx_frame_desc_defaults();
    base.base = (vx_render_desc){.width = w, .height = h};
    if (parts & FRAMES) check_frames(name, s, &p, &c, &base);
    if (parts & GI_FRAMES) check_gi_frames(name, s, &p, &c, &base);
    if (parts & BAKES) check_bakes(name, s, &p, &c, &base);
    CHECKF(vx_gpu_validation_errors(gpu) == 0, "%s: %u validation errors", name, vx_gpu_validation_errors(gpu));
    printf("  %-28s %u pipelines cached\n", name, gpu->pipeline_count);
    side_close(&c);
    side_close(&p);
}

static void generated_scenes(int parts) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    /* palette models (sparse, dense), an RGBA model with noise, a model of
     * full 8^3 leaf cubes (leaves above level 1) */
    vx_svo_model m[4];
    REQUIRE(ts_random_model(&m[0], 37, 20, 9, 5, 1) == VX_OK);
    REQUIRE(ts_random_model(&m[1], 24, 24, 24, 50, 2) == VX_OK);
    size_t n = 0, cap = 32 * 32 * 32;
    uint64_t* keys = malloc(cap * 8);
    uint32_t* rgba = malloc(cap * 4);
    uint8_t* level = calloc(cap, 1);
    REQUIRE(keys && rgba && level);
    uint32_t seed = 7;
    for (uint32_t z = 0; z < 32; z++)
        for (uint32_t y = 0; y < 32; y++)
            for (uint32_t x = 0; x < 32; x++)
                if ((x - 16) * (x - 16) + (y - 16) * (y - 16) + (z - 16) * (z - 16) < 200 && ts_rng(&seed) % 3) {
                    keys[n] = vx_svo_morton(x, y, z);
                    rgba[n++] = 0xFF000000u | (ts_rng(&seed) & 0xFFFFFFu);
                }
    vx_error err = {0};
    vx_svo_voxels v = {.size = {32, 32, 32}, .count = n, .keys = keys, .attrs = VX_ATTR_RGBA8, .rgba = rgba};
    REQUIRE(vx_svo_build_model(NULL, &v, &m[2], NULL, &err) == VX_OK);
    n = 0;
    for (uint32_t z = 0; z < 32; z += 8)
        for (uint32_t y = 0; y < 32; y += 8)
            for (uint32_t x = 0; x < 32; x += 8)
                if (ts_rng(&seed) % 3 == 0) {
                    keys[n] = vx_svo_morton(x, y, z);
                    level[n] = 3;
                    rgba[n++] = 0xFF000000u | (ts_rng(&seed) % 5) * 0x203040u;
                }
    v = (vx_svo_voxels){.size = {32, 32, 32}, .count = n, .keys = keys, .level = level, .attrs = VX_ATTR_RGBA8,
                        .rgba = rgba};
    REQUIRE(vx_svo_build_model(NULL, &v, &m[3], NULL, &err) == VX_OK);
    free(keys), free(rgba), free(level);
    static const double rot[9] = {0.36, -0.48, 0.8, 0.8, 0.6, 0, -0.48, 0.64, 0.6};
    vx_svo_instance in[5];
    for (uint32_t i = 0; i < 4; i++) in[i] = ts_inst(i, i % 2 ? rot : NULL, 40.0 * i, 6.0 * i, 0);
    in[4] = ts_inst(2, rot, 20, 30, 25);
    vx_svo_scene s;
    ts_scene(&s, m, 4, in, 5);
    check_scene("generated (5 instances)", &s, 64, 48, VX_RENDER_BRICKS_DICT, parts);
    vx_svo_scene_free(&s);
}

static void room_scenes(int parts) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    vx_svo_scene s;
    (void)box_scene, (void)room_scene; /* probe_scenes.h's other scenes (static there) */
    glass_room_scene(&s);
    check_scene("room (emissive, glass, metal)", &s, 48, 36, VX_RENDER_BRICKS_INLINE, parts);
    vx_svo_scene_free(&s);
}

static void corpus_scenes(int parts) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    static const char* files[] = {"eph_monu1.vox", "ogt_chr_knight.vox"};
    int done = 0;
    for (size_t i = 0; i < sizeof files / sizeof files[0]; i++) {
        vx_svo_scene s;
        vx_test_vox st = vx_test_vox_scene(files[i], &s);
        if (st == VX_TEST_VOX_ABSENT) continue;
        done++; /* found: a file that fails to load fails the test, not skips it */
        CHECKF(st == VX_TEST_VOX_OK, "%s: not loaded", files[i]);
        if (st != VX_TEST_VOX_OK) continue;
        check_scene(files[i], &s, 64, 48, i % 2 ? VX_RENDER_BRICKS_INLINE : VX_RENDER_BRICKS_DICT, parts);
        vx_svo_scene_free(&s);
    }
    if (!done) SKIP("no corpus .vox files");
}

/* (the names of the frame tests end in _frames: ctest's entry test_compact_passes runs VX_TEST_ONLY=_frames) */
static void test_generated_frames(void) { generated_scenes(FRAMES); }
static void test_generated_gi_frames(void) { generated_scenes(GI_FRAMES); }
static void test_generated_bakes(void) { generated_scenes(BAKES); }
static void test_room_frames(void) { room_scenes(FRAMES); }
static void test_room_gi_frames(void) { room_scenes(GI_FRAMES); }
static void test_room_bakes(void) { room_scenes(BAKES); }
static void test_corpus_frames(void) { corpus_scenes(FRAMES); }
static void test_corpus_gi_frames(void) { corpus_scenes(GI_FRAMES); }
static void test_corpus_bakes(void) { corpus_scenes(BAKES); }

int main(void) {
    int logged = 0;
    vx_logger lg = {.func = vx_test_validation_log, .user_data = &logged};
    gpu_skip = vx_test_gpu_open((vx_gpu_desc){.logger = &lg}, true, &gpu);
    RUN(test_generated_frames);
    RUN(test_generated_gi_frames);
    RUN(test_generated_bakes);
    RUN(test_room_frames);
    RUN(test_room_gi_frames);
    RUN(test_room_bakes);
    RUN(test_corpus_frames);
    RUN(test_corpus_gi_frames);
    RUN(test_corpus_bakes);
    vx_gpu_destroy(gpu);
    return vx_test_finish();
}
