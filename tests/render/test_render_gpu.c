/* tests/render/test_render_gpu.c - the Vulkan tracer against the CPU
 * reference: corpus scenes, extreme rays and transforms, scenes far from
 * the origin, instanced vs baked.
 * Runs with the validation layer when it is installed and fails on any
 * validation error. Skips (with a message) when there is no Vulkan device. */
#define _POSIX_C_SOURCE 200809L /* setenv, unsetenv, strdup: test_stack_levels */
#include <dlfcn.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "render/gpu.h" /* vx__render_scene_far */
#include "render/pipeline.h"
#include "render/testing.h" /* vx__render_scene_force_precise */
#include "svo/edit.h"
#include "tests/render/scenes.h"
#include "tests/test.h"
#include "tests/test_vox.h"
#include "tests/gpu_test.h"

static vx_gpu* gpu;
static const char* gpu_skip;

static void log_cb(void* user, vx_log_level level, const char* id, const char* msg) {
    (void)user;
    if (level >= VX_LOG_WARN) fprintf(stderr, "  [%s] %s\n", id, msg);
}
static vx_logger logger = {log_cb, NULL};

/* Same instance and same cell, or (exact ties at edges and corners, which
 * float and double may break differently) a touching cell at the same t. */
typedef struct cmp_result {
    size_t pixels, exact, tie, bad, depth_bad, hits, ambiguous;
} cmp_result;

/* g_strict is the issue's rule as is: same instance, same cell and depth
 * within 1e-4 relative, no "touching cell" ties; the only pixels let off are
 * those the reference flags ambiguous (the ray starts on a boundary or
 * crosses a lattice edge or corner within 1e-9 relative: no unique answer).
 * g_force: -1 lets the scene pick the float/float64 variant, 0/1 forces one. */
static double g_min_share = 0.9999, g_max_ambiguous = 0.125;
static bool g_strict;
/* check_scene: 0 or 1, whether the grid walk's kernel must read the empty entries' octant extents (GRID_OCT,
 * grid_walk.glsl: some grid's root at least 64 wide, render/grid.h VX__GRID_OCT_ROOT_LOG); -1 not checked */
static int g_want_oct = -1;
static int g_force = -1;

static cmp_result compare(const char* name, const vx_render_image* g, const vx_render_image* c) {
    cmp_result r = {0};
    size_t n = (size_t)g->width * g->height;
    int printed = 0;
    for (size_t i = 0; i < n; i++) {
        const vx_render_hit *a = &g->hits[i], *b = &c->hits[i];
        r.pixels++;
        bool ok = false, exact = false;
        if (a->instance == b->instance) {
            if (a->instance == VX_RENDER_NO_HIT) {
                ok = exact = true;
            } else {
                r.hits++;
                exact = a->cell[0] == b->cell[0] && a->cell[1] == b->cell[1] && a->cell[2] == b->cell[2];
                double tol = 1e-4 * fmax(fabs(b->t), 1e-3);
                bool t_ok = fabs((double)a->t - b->t) <= tol;
                bool touch = true;
                for (int k = 0; k < 3; k++) touch &= abs((int)a->cell[k] - (int)b->cell[k]) <= 1;
                ok = g_strict ? exact && t_ok : exact || (touch && t_ok);
                if (exact && !t_ok) r.depth_bad++;
            }
        } else if (a->instance != VX_RENDER_NO_HIT && b->instance != VX_RENDER_NO_HIT) {
            /* coplanar faces of two instances: either is right */
            ok = !g_strict && fabs((double)a->t - b->t) <= 1e-4 * fmax(fabs(b->t), 1e-3);
        }
        if (!ok && (b->flags & VX_RENDER_HIT_AMBIGUOUS)) {
            r.ambiguous++;
            continue;
        }
        if (exact) r.exact++;
        else if (ok) r.tie++;
        else r.bad++;
        if (!ok && printed < 8 && g_force != 0) {
            printed++;
            fprintf(stderr, "  %s pixel %zu,%zu: gpu inst %d cell %u,%u,%u t %.7g | cpu inst %d cell %u,%u,%u t %.7g\n",
                    name, i % g->width, i / g->width, (int)a->instance, a->cell[0], a->cell[1], a->cell[2], a->t,
                    (int)b->instance, b->cell[0], b->cell[1], b->cell[2], b->t);
        }
    }
    printf("%-28s %6zu px %6zu hits: %zu exact, %zu ties, %zu ambiguous, %zu mismatched, %zu depth off\n", name,
           r.pixels, r.hits, r.exact, r.tie, r.ambiguous, r.bad, r.depth_bad);
    /* a depth frame's image (trace.comp writes depth and coverage, vx_render_frame widens them): each pixel its
     * hit's t in r, g and b and 1 in a, a miss +inf and 0, the same bits as the hit records' t */
    size_t wide = 0;
    for (size_t i = 0; g->mode == VX_RENDER_DEPTH && g->pixels && i < n; i++) {
        bool hit = g->hits[i].instance != VX_RENDER_NO_HIT;
        float t = hit ? g->hits[i].t : INFINITY, want[4] = {t, t, t, hit ? 1.0f : 0.0f};
        wide += memcmp(&g->pixels[4 * i], want, 16) != 0;
    }
    CHECKF(!wide, "%s: %zu depth pixels are not their hits' (t, t, t, 1) or a miss's (inf, inf, inf, 0)", name, wide);
    return r;
}

/* The beam pass (vx_render_desc.beam) moves only where the primary walk
 * starts: with blocks of 8 and of 3 pixels (ragged edges) the frame must
 * hold the same instance, cell and depth bits as gi (beam off, the
 * default). Float variant only (the float64 one has no beam pass). */
static void check_beam(const char* name, vx_render_scene* rs, vx_render_desc d, const vx_render_image* gi) {
    if (vx_render_scene_precise(rs) || d.lod) return;
    static const uint32_t beams[] = {8, 3};
    for (size_t b = 0; b < sizeof beams / sizeof beams[0]; b++) {
        d.beam = beams[b];
        vx_render_image bi = {0};
        vx_error err = {0};
        vx_result r = vx_render_frame(rs, &d, &bi, &err);
        CHECKF(r == VX_OK, "%s beam %u: %s", name, beams[b], err.msg);
        size_t n = (size_t)gi->width * gi->height, diff = 0;
        for (size_t i = 0; !r && i < n; i++) {
            const vx_render_hit *a = &gi->hits[i], *c = &bi.hits[i];
            bool same = a->instance == c->instance && !memcmp(a->cell, c->cell, sizeof a->cell) &&
                        !memcmp(&a->t, &c->t, sizeof a->t) && !memcmp(&gi->pixels[4 * i], &bi.pixels[4 * i], 16);
            if (!same && diff++ < 4)
                fprintf(stderr, "  %s beam %u pixel %zu,%zu: inst %d cell %u,%u,%u t %.9g | no beam inst %d cell %u,%u,%u t %.9g\n",
                        name, beams[b], i % gi->width, i / gi->width, (int)c->instance, c->cell[0], c->cell[1],
                        c->cell[2], c->t, (int)a->instance, a->cell[0], a->cell[1], a->cell[2], a->t);
        }
        CHECKF(diff == 0, "%s: %zu pixels differ between beam %u and none", name, diff, beams[b]);
        vx_render_image_free(&bi);
    }
}

/* Distance in float steps between two finite floats of one sign (a large
 * value where they are not comparable that way). */
static uint32_t ulps_apart(float a, float b) {
    uint32_t ua, ub;
    memcpy(&ua, &a, 4);
    memcpy(&ub, &b, 4);
    if (!isfinite(a) || !isfinite(b) || (ua >> 31) != (ub >> 31)) return ua == ub ? 0u : UINT32_MAX;
    return ua > ub ? ua - ub : ub - ua;
}

/* The depth frame without hits (trace.comp's lean walk where it applies:
 * one instance, GPU form, issue 21's twentieth sitting) must hold the hits
 * frame's pixels: the same hit or miss everywhere and the same depth, from a
 * loop without the iteration guard, the ray-end test at a push and hh. The
 * depth within 4 float steps, not bit for bit: the two frames are different
 * kernels (WRITE_HITS), and on the H200 the NVIDIA compiler contracts their
 * walks' arithmetic differently (stop 50's merged check: 2-23 pixels of a
 * scene 1 step apart; bit for bit on lavapipe). A wrong walk (a wrong
 * scale_exp2: 31-42 pixels a scene on lavapipe) misses a cell or hits
 * another face, far more than 4 steps. */
static void check_lean(const char* name, vx_render_scene* rs, vx_render_desc d, const vx_render_image* gi) {
    d.want_hits = false;
    vx_render_image li = {0};
    vx_error err = {0};
    vx_result r = vx_render_frame(rs, &d, &li, &err);
    CHECKF(r == VX_OK, "%s without hits: %s", name, err.msg);
    size_t n = (size_t)gi->width * gi->height, diff = 0;
    for (size_t i = 0; !r && i < n; i++) {
        const float *a = &gi->pixels[4 * i], *b = &li.pixels[4 * i];
        if (a[3] == b[3] && ulps_apart(a[0], b[0]) <= 4u && b[1] == b[0] && b[2] == b[0]) continue;
        if (diff++ < 4)
            fprintf(stderr, "  %s pixel %zu,%zu: t %.9g (%g) without hits, %.9g (%g) with\n", name, i % gi->width,
                    i / gi->width, li.pixels[4 * i], li.pixels[4 * i + 3], gi->pixels[4 * i], gi->pixels[4 * i + 3]);
    }
    CHECKF(diff == 0, "%s: %zu depth pixels differ without hits", name, diff);
    vx_render_image_free(&li);
}

/* Pixels of two images of one size whose values differ (any of the four floats; NaN equals NaN). By value, not
 * by bits: a zero's sign is the compiler's to choose (SPIR-V without SignedZeroInfNanPreserve): on lavapipe the
 * normal frame of two kernels that found the same hits (instance, cell, depth, entry face) gave -0 in one and +0
 * in the other for a zero component of 267-929 normals (stop 78, the level-2 grids through the BVH). */
static size_t pixels_differ(const vx_render_image* a, const vx_render_image* b) {
    size_t n = (size_t)a->width * a->height, diff = 0;
    for (size_t i = 0; i < 4 * n; i += 4) {
        bool same = true;
        for (int k = 0; k < 4; k++) {
            float x = a->pixels[i + k], y = b->pixels[i + k];
            same = same && (x == y || (isnan(x) && isnan(y)));
        }
        diff += !same;
    }
    return diff;
}

/* The lean walk in the kernels of the colour modes (trace.comp's colour, albedo and normal kernels, primary and
 * shadow rays; the pass pipeline's G-buffer, merged with the direct pass and apart; issue 21, branch lean2): each
 * frame without hits or ids (the lean walk, where it applies: one instance, GPU form) against the same frame with
 * them (WRITE_HITS: main's walk, with the iteration guard, the ray-end test at a push and hh, the camera ray held
 * across the walk rather than formed again), value for value. Equal on CPU devices (lavapipe: the same
 * arithmetic); on GPUs at most 1% of the pixels apart, as check_lean allows (the two are different kernels and
 * the NVIDIA compiler may contract their walks differently: a depth a float step apart moves a shadow ray's
 * start). A wrong walk (a wrong scale_exp2) misses cells and gives other faces and shadows. */
static void check_lean_colour(const char* name, vx_render_scene* rs, const vx_svo_scene* s, vx_render_desc d) {
    static const vx_render_mode modes[] = {VX_RENDER_COLOR, VX_RENDER_ALBEDO, VX_RENDER_NORMAL};
    static const char* const mname[] = {"colour", "albedo", "normal", "passes", "separate passes"};
    size_t n = (size_t)d.width * d.height, allowed = vx_gpu_is_cpu(gpu) ? 0 : n / 100;
    vx_frame_renderer* fr = NULL;
    vx_error err = {0};
    vx_result r = vx_render_scene_precise(rs) ? VX_OK : vx_frame_renderer_create(rs, s, &fr, &err);
    CHECKF(r == VX_OK, "%s: frame renderer: %s", name, err.msg);
    /* the pass pipeline traces in float only (the float64 variant's scenes: the modes alone) */
    int nm = vx_render_scene_precise(rs) ? 3 : 5;
    for (int m = 0; m < nm && !r; m++) {
        vx_render_image img[2] = {{0}, {0}};
        for (int hits = 0; hits < 2 && !r; hits++) {
            d.want_hits = hits;
            if (m < 3) {
                d.mode = modes[m];
                r = vx_render_frame(rs, &d, &img[hits], &err);
            } else {
                vx_frame_desc fd = vx_frame_desc_defaults();
                fd.base = d;
                fd.base.mode = VX_RENDER_COLOR;
                fd.base.want_hits = false;
                fd.want_ids = hits;
                fd.separate_passes = m == 4;
                vx_frame_result res = {0};
                r = vx_frame_render(fr, &fd, &res, &err);
                img[hits] = res.image;
            }
            CHECKF(r == VX_OK, "%s %s: %s", name, mname[m], err.msg);
        }
        if (!r) {
            size_t diff = pixels_differ(&img[0], &img[1]);
            CHECKF(diff <= allowed, "%s: %zu %s pixels differ without hits (%zu allowed)", name, diff, mname[m], allowed);
        }
        vx_render_image_free(&img[0]);
        vx_render_image_free(&img[1]);
    }
    vx_frame_renderer_destroy(fr);
}

/* The albedo frame of walk wname (d's view) against the CPU reference's, ca: wherever both hit the same cell of
 * the same instance, the same 8-bit colour (the hit's attribute record: the grid walk finds it from its brick's
 * record word, render/grid.h vx__grid_brick_record; the octree walk by its own descent): each channel within half
 * a step of 1/255 (on the H200 the kernel's c / 255.0 came out an ulp from the CPU's division in double on most
 * pixels, on both walks; two records' colours a step apart are told apart). */
static void check_albedo(const char* wname, vx_render_scene* rs, vx_render_desc d, const vx_render_image* ca) {
    d.mode = VX_RENDER_ALBEDO;
    d.want_hits = true;
    vx_render_image ga = {0};
    vx_error err = {0};
    vx_result r = vx_render_frame(rs, &d, &ga, &err);
    CHECKF(r == VX_OK, "%s albedo: %s", wname, err.msg);
    size_t n = (size_t)d.width * d.height, same = 0, differ = 0;
    for (size_t i = 0; !r && i < n; i++) {
        const vx_render_hit *a = &ga.hits[i], *b = &ca->hits[i];
        if (a->instance == VX_RENDER_NO_HIT || a->instance != b->instance || memcmp(a->cell, b->cell, sizeof a->cell))
            continue;
        same++;
        bool near = true;
        for (int k = 0; k < 3; k++) near &= fabsf(ga.pixels[4 * i + k] - ca->pixels[4 * i + k]) < 0.5f / 255.0f;
        if (!near && differ++ < 4)
            fprintf(stderr, "  %s albedo pixel %zu: %g %g %g, the reference's %g %g %g\n", wname, i, ga.pixels[4 * i],
                    ga.pixels[4 * i + 1], ga.pixels[4 * i + 2], ca->pixels[4 * i], ca->pixels[4 * i + 1],
                    ca->pixels[4 * i + 2]);
    }
    CHECKF(!r && differ == 0, "%s: %zu of %zu hit pixels' albedo differ from the reference's", wname, differ, same);
    vx_render_image_free(&ga);
}

/* Renders s on both paths and checks the 99.99% rule. min_hits guards
 * against a camera that sees nothing. With g_force == 0 (the float variant
 * forced, for comparison) it only reports. */
static cmp_result check_scene(const char* name_in, const vx_svo_scene* s, vx_render_desc d, size_t min_hits) {
    char name[96];
    snprintf(name, sizeof name, "%s%s", g_force == 1 ? "[f64] " : "", name_in);
    d.want_hits = true;
    if (!d.width) d.width = 48, d.height = 40;
    vx_error err = {0};
    vx_render_scene* rs = NULL;
    vx_render_image gi = {0}, ci = {0};
    cmp_result c = {0};
    /* the grids asked for (the default on every device) */
    vx_render_scene_desc sd = {.grid_budget = VX_RENDER_GRID_BUDGET};
    vx_result r = vx_render_scene_create_ex(gpu, s, &sd, &rs, &err);
    CHECKF(r == VX_OK, "%s: %s", name, err.msg);
    if (!r && g_force < 0) {
        /* the variant follows the deepest drawn model */
        uint32_t deepest = 0;
        for (uint32_t i = 0; i < s->instance_count; i++)
            if (s->models[s->instances[i].model].depth > deepest) deepest = s->models[s->instances[i].model].depth;
        CHECKF(vx_render_scene_precise(rs) == (deepest > VX_RENDER_PRECISE_DEPTH), "%s: variant for depth %u", name,
               deepest);
    }
    if (!r) vx__render_scene_force_precise(rs, g_force);
    vx_result rc = vx_render_cpu(s, &d, NULL, &ci, &err);
    CHECKF(rc == VX_OK, "%s: %s", name, err.msg);
    /* the models with a grid (render/grid.h) walk it by default: then the octree walk too (grid off), each
     * against the reference */
    vx_render_layout_info li = {0};
    if (!r) vx_render_scene_layout(rs, &li);
    bool grids = !r && li.grid_models && !vx_render_scene_precise(rs) && !d.lod;
    /* a converter's regions walked as one grid by default (render_scene.c grid_union): then each region's grid
     * under the BVH too */
    bool uni = grids && vx__render_scene_grid_union(rs, -1) > 0;
    if (grids && g_want_oct >= 0) {
        vx__frame f = {0};
        vx__buffer* gb = NULL;
        uint32_t spec = vx__render_scene_grid_spec(rs, &f, &gb);
        CHECKF(((spec & 64u) != 0) == (g_want_oct == 1), "%s: GRID %u, want GRID_OCT %d", name, spec, g_want_oct);
    }
    /* with grids: each walk's albedo against the reference's (check_albedo) */
    vx_render_image ca = {0};
    if (grids && !rc) {
        vx_render_desc da = d;
        da.mode = VX_RENDER_ALBEDO, da.want_hits = true;
        vx_result ra = vx_render_cpu(s, &da, NULL, &ca, &err);
        CHECKF(ra == VX_OK, "%s: albedo reference: %s", name, err.msg);
    }
    for (int walk = 0; walk < (grids ? 2 + uni : 1) && !r; walk++) {
        char wname[112];
        snprintf(wname, sizeof wname, "%s%s", name,
                 !grids ? "" : walk == 2 ? " [regions apart]" : walk ? " [octree]" : uni ? " [union grid]" : " [grid]");
        vx__render_scene_grid(rs, walk == 1 ? 0 : -1);
        vx__render_scene_grid_union(rs, walk == 2 ? 0 : -1);
        vx_render_image_free(&gi);
        r = vx_render_frame(rs, &d, &gi, &err);
        CHECKF(r == VX_OK, "%s: %s", wname, err.msg);
        cmp_result cw = {0};
        if (!r && !rc) cw = compare(wname, &gi, &ci);
        if (!walk) c = cw;
        /* the beam pass (octree walk only) against the frame without it; each walk without hits against the
         * same walk with them; the colour modes (and the passes, octree walks) once, on the default walk */
        bool octree = !grids || walk == 1;
        if (!r && octree) check_beam(name, rs, d, &gi);
        if (!r && ca.pixels) check_albedo(wname, rs, d, &ca);
        if (!r && d.mode == VX_RENDER_DEPTH) check_lean(wname, rs, d, &gi);
        if (!r && !walk && d.mode == VX_RENDER_DEPTH && g_force != 1) check_lean_colour(name, rs, s, d);
        if (!r && !rc && g_force != 0) {
            CHECKF(cw.hits >= min_hits, "%s: %zu hits, expected at least %zu", wname, cw.hits, min_hits);
            CHECKF((double)(cw.exact + cw.tie) >= g_min_share * (cw.pixels - cw.ambiguous), "%s: %zu of %zu pixels differ",
                   wname, cw.bad, cw.pixels);
            CHECKF(cw.depth_bad <= (1 - g_min_share) * cw.pixels, "%s: %zu depths off by more than 1e-4", wname,
                   cw.depth_bad);
            /* exact edge/corner ties may go either way, but only on a small share */
            CHECKF(cw.ambiguous <= g_max_ambiguous * cw.pixels, "%s: %zu ambiguous pixels", wname, cw.ambiguous);
        }
    }
    if (!r) vx__render_scene_grid(rs, -1), vx__render_scene_grid_union(rs, -1);
    vx_render_image_free(&gi);
    vx_render_image_free(&ci);
    vx_render_image_free(&ca);
    vx_render_scene_destroy(rs);
    CHECK(vx_gpu_validation_errors(gpu) == 0);
    return c;
}

static vx_render_desc cam(double ex, double ey, double ez, double tx, double ty, double tz) {
    vx_render_desc d = {.mode = VX_RENDER_DEPTH};
    d.camera.set = true;
    d.camera.eye[0] = ex, d.camera.eye[1] = ey, d.camera.eye[2] = ez;
    d.camera.target[0] = tx, d.camera.target[1] = ty, d.camera.target[2] = tz;
    return d;
}

static void test_corpus(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    static const char* files[] = {"eph_chr_knight.vox", "eph_dragon.vox", "eph_teapot.vox", "eph_menger.vox",
                                  "eph_monu1.vox", "ogt_test_groups.vox", "ogt_test_multiple_model_scene.vox",
                                  "ogt_doom.vox", "ogt_chr_knight.vox"};
    int done = 0;
    for (size_t i = 0; i < sizeof files / sizeof files[0]; i++) {
        vx_svo_scene s;
        vx_test_vox st = vx_test_vox_scene(files[i], &s);
        if (st == VX_TEST_VOX_ABSENT) {
            fprintf(stderr, "  vox/%s: not available\n", files[i]);
            continue;
        }
        done++; /* found: a file that fails to load fails the test, not skips it */
        CHECKF(st == VX_TEST_VOX_OK, "%s: not loaded", files[i]);
        if (st != VX_TEST_VOX_OK) continue;
        g_want_oct = 0; /* the corpus's roots are 16-32 wide: main's walk, the extents not read */
        check_scene(files[i], &s, (vx_render_desc){.mode = VX_RENDER_DEPTH, .width = 64, .height = 48}, 100);
        g_want_oct = -1;
        /* another view, orthographic from above */
        vx_render_desc d = {.mode = VX_RENDER_DEPTH, .width = 40, .height = 40};
        d.camera.ortho = true;
        d.camera.fov = 30;
        char nm[96];
        snprintf(nm, sizeof nm, "%s (ortho)", files[i]);
        check_scene(nm, &s, d, 80);
        vx_svo_scene_free(&s);
    }
    if (!done) SKIP("corpus not available");
}

/* A random 12^3 model at the origin: the canvas of most extreme cases. */
static void random_scene(vx_svo_scene* s, const double* m9, double tx, double ty, double tz, uint32_t pct) {
    vx_svo_model m;
    ts_random_model(&m, 12, 12, 12, pct, 4242);
    vx_svo_instance in = ts_inst(0, m9, tx, ty, tz);
    ts_scene(s, &m, 1, &in, 1);
}

/* An orthographic depth view along an axis, px pixels over px units (exact pixel centres), from eye[axis] = from
 * towards to: the eye line is the axis itself (the scene moves instead, onto the pixel centres), so that
 * target - eye is exactly +0 or -0 (neg_zero; -0 - +0 = -0) across it. */
static vx_render_desc axis_camera(int axis, double from, double to, bool neg_zero, uint32_t px) {
    vx_render_desc d = {.mode = VX_RENDER_DEPTH, .width = px, .height = px};
    d.camera.set = true, d.camera.ortho = true, d.camera.ortho_height = px;
    double z = neg_zero ? -0.0 : 0.0, e[3] = {0, 0, 0}, t[3] = {z, z, z};
    e[axis] = from, t[axis] = to;
    memcpy(d.camera.eye, e, sizeof e);
    memcpy(d.camera.target, t, sizeof t);
    d.camera.up[(axis + 1) % 3] = 1;
    return d;
}

static void check_normals(const char* name, vx_render_scene* rs, const vx_svo_scene* s, vx_render_desc d);

/* Axis-parallel rays with pixel centres on cell edges and centres (+0 and -0 components) against the CPU
 * reference (check_scene), and each view's world normals against the reference's on the grid walk and the octree
 * walk (check_normals): a ray along a cell edge that enters its cell across the box's face ties the parallel
 * axis's entry time (-0) with the face's; the grid walk took the parallel axis (the x face's normal on straight-
 * down rays at x = 7.0: test_sky's top face 0.485 off), stop 87. */
static void test_axis_rays_on_edges(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    vx_svo_scene s;
    random_scene(&s, NULL, 0, 0, 0, 35);
    /* 16 pixels over 16 units: pixel centres on integer coordinates (cell
     * edges) or on half-integers (cell centres); directions with exact +0
     * and -0 components */
    const double offs[2] = {6.0, 6.5};
    for (int o = 0; o < 2; o++)
        for (int z = 0; z < 2; z++)
            for (int axis = 0; axis < 3; axis++) {
                vx_render_desc d = axis_camera(axis, 40, -3, z, 16);
                for (int k = 0; k < 3; k++) s.instances[0].xform[3 + 4 * k] = k == axis ? 0 : -offs[o];
                char nm[64];
                snprintf(nm, sizeof nm, "axis %d %s %s", axis, o ? "centres" : "edges", z ? "-0" : "+0");
                check_scene(nm, &s, d, 20);
                vx_render_scene* rs = NULL;
                vx_error err = {0};
                REQUIRE(vx_render_scene_create_ex(gpu, &s, &(vx_render_scene_desc){.grid_budget = VX_RENDER_GRID_BUDGET},
                                                  &rs, &err) == VX_OK);
                CHECKF(vx__render_scene_grid_models(rs) == 1, "%s: no grid", nm);
                check_normals(nm, rs, &s, d);
                vx__render_scene_grid(rs, 0);
                snprintf(nm, sizeof nm, "axis %d %s %s [octree]", axis, o ? "centres" : "edges", z ? "-0" : "+0");
                check_normals(nm, rs, &s, d);
                vx_render_scene_destroy(rs);
            }
    vx_svo_scene_free(&s);
}

static void test_diagonal_edges_corners(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    vx_svo_scene s;
    random_scene(&s, NULL, 0, 0, 0, 20);
    /* odd sizes put the centre pixel on the eye line, through lattice corners;
     * those rays graze cell corners, which float and double resolve apart,
     * so the centre column and row may differ in a few pixels */
    g_min_share = 0.99;
    const double dirs[][3] = {{1, 1, 1}, {1, 1, 0}, {-1, 2, 0}, {1, -1, 1}, {2, 1, 1}, {-1, -1, -1}};
    for (size_t i = 0; i < sizeof dirs / sizeof dirs[0]; i++) {
        vx_render_desc d = {.mode = VX_RENDER_DEPTH, .width = 33, .height = 33};
        d.camera.set = true, d.camera.ortho = true, d.camera.ortho_height = 16;
        for (int k = 0; k < 3; k++) d.camera.eye[k] = 6 + 20 * dirs[i][k], d.camera.target[k] = 6;
        char nm[64];
        snprintf(nm, sizeof nm, "diagonal %.0f,%.0f,%.0f", dirs[i][0], dirs[i][1], dirs[i][2]);
        check_scene(nm, &s, d, 50);
    }
    g_min_share = 0.9999;
    vx_svo_scene_free(&s);
}

static void test_ray_origins(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    vx_svo_scene s;
    random_scene(&s, NULL, 0, 0, 0, 30);
    /* find a filled cell and an empty one through the reference */
    vx_render_desc d;
    d = cam(5.5, 5.5, 5.5, 9, 1, 3); /* centre of a cell: inside a voxel or in empty space */
    check_scene("origin at a cell centre", &s, d, 0);
    d = cam(5.0, 5.5, 5.5, 9, 1, 3); /* on a face */
    check_scene("origin on a face", &s, d, 0);
    d = cam(5.0, 5.0, 5.0, -3, 9, 1); /* on a corner: every ray is an exact tie */
    g_max_ambiguous = 1;
    check_scene("origin on a corner", &s, d, 0);
    g_max_ambiguous = 0.125;
    d = cam(7.3, 2.2, 11.9, 1, 9, 1); /* inside the bounds */
    check_scene("origin inside the bounds", &s, d, 50);
    d = cam(6 + 5.7e5, 6 - 5.7e5, 6 + 5.7e5, 6, 6, 6); /* 1e6 away, narrow view */
    d.camera.fov = 0.0012;
    check_scene("origin 1e6 away", &s, d, 200);
    d = cam(6 + 5.7e5, 6 - 5.7e5, 6 + 5.7e5, 6, 6, 6);
    d.camera.ortho = true, d.camera.ortho_height = 20;
    check_scene("origin 1e6 away (ortho)", &s, d, 200);
    vx_svo_scene_free(&s);
}

/* The eye inside filled cells (a full block, then 90% filled): the rays
 * start in or next to solid cells, which the beam pass must not skip.
 * (Perspective only: an orthographic view starts its rays on a plane
 * before the scene's bounds.) */
static void test_eye_inside(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    static const uint32_t pct[] = {100, 90};
    for (int i = 0; i < 2; i++) {
        vx_svo_scene s;
        random_scene(&s, NULL, 0, 0, 0, pct[i]);
        char nm[64];
        snprintf(nm, sizeof nm, "eye inside, %u%% filled", pct[i]);
        vx_render_desc d = cam(5.5, 6.25, 5.75, 9, 1, 3);
        check_scene(nm, &s, d, 1000);
        vx_svo_scene_free(&s);
    }
}

static void test_grazing(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    /* a 12x12x4 slab: rays along its top face (z = 4 exactly) */
    uint32_t* xyz = malloc(12 * 12 * 4 * 12);
    size_t n = 0;
    for (uint32_t z = 0; z < 4; z++)
        for (uint32_t y = 0; y < 12; y++)
            for (uint32_t x = 0; x < 12; x++)
                if (z < 3 || (x * 7 + y * 3) % 5 == 0) xyz[3 * n] = x, xyz[3 * n + 1] = y, xyz[3 * n + 2] = z, n++;
    vx_svo_model m;
    REQUIRE(ts_model(&m, (uint32_t[3]){12, 12, 4}, xyz, NULL, n) == VX_OK);
    free(xyz);
    vx_svo_instance in = ts_inst(0, NULL, 0, 0, 0);
    vx_svo_scene s;
    ts_scene(&s, &m, 1, &in, 1);
    vx_render_desc d = {.mode = VX_RENDER_DEPTH, .width = 24, .height = 24};
    d.camera.set = true, d.camera.ortho = true, d.camera.ortho_height = 6;
    d.camera.eye[0] = -10, d.camera.eye[1] = 6, d.camera.eye[2] = 3;
    d.camera.target[0] = 0, d.camera.target[1] = 6, d.camera.target[2] = 3;
    check_scene("grazing along faces", &s, d, 100);
    d.camera.target[2] = 3 - 1e-4; /* almost parallel */
    check_scene("grazing, tilted 1e-5", &s, d, 100);
    d = cam(-8, 6.01, 4.001, 20, 6.2, 3.999);
    check_scene("grazing perspective", &s, d, 10);
    vx_svo_scene_free(&s);
}

/* A model 2^depth cells on a side holding, in each of three places (near
 * the origin, near the far corner, mid-cube off the float grid), a
 * checkerboard 3x3x3 and a random 6x6x6 block beside it; base[] gets the
 * places' corners. */
static void deep_scene(uint32_t depth, vx_svo_scene* s, uint32_t base[3][3]) {
    uint32_t side = 1u << depth;
    const uint32_t b[3][3] = {{5, 7, 9}, {side - 40, side - 30, side - 20}, {side / 2 - 1, side / 3, 100}};
    memcpy(base, b, sizeof b);
    uint32_t xyz[3 * (14 + 216) * 3];
    uint8_t pal[3 * (14 + 216)];
    size_t n = 0;
    uint32_t seed = 99;
    for (int c = 0; c < 3; c++) {
        for (uint32_t z = 0; z < 3; z++)
            for (uint32_t y = 0; y < 3; y++)
                for (uint32_t x = 0; x < 3; x++)
                    if ((x + y + z) % 2 == 0) {
                        xyz[3 * n] = base[c][0] + x, xyz[3 * n + 1] = base[c][1] + y, xyz[3 * n + 2] = base[c][2] + z;
                        pal[n] = (uint8_t)(2 + n % 200);
                        n++;
                    }
        for (uint32_t z = 0; z < 6; z++)
            for (uint32_t y = 0; y < 6; y++)
                for (uint32_t x = 0; x < 6; x++)
                    if (ts_rng(&seed) % 100 < 30) {
                        xyz[3 * n] = base[c][0] + 5 + x, xyz[3 * n + 1] = base[c][1] + y;
                        xyz[3 * n + 2] = base[c][2] + z;
                        pal[n] = (uint8_t)(2 + n % 200);
                        n++;
                    }
    }
    uint32_t levels = 0;
    REQUIRE(ts_cube_scene(s, side, xyz, pal, n, &levels) == VX_OK);
    CHECK(levels == depth);
}

/* Four views of place c (corner base): two close-ups (pixels ~1/3 and ~1/10
 * of a cell) with eyes off the float grid, so that the instance offset
 * rounds; one from outside the model, 1.2 * 2^depth away, a narrow cone
 * across 2^depth cells of empty space; an orthographic diagonal. */
static void deep_views(const uint32_t base[3], uint32_t side, uint32_t w, uint32_t h, vx_render_desc views[4]) {
    double tx = base[0] + 5.0, ty = base[1] + 3.0, tz = base[2] + 3.0;
    views[0] = cam(tx + 7.31, ty - 9.17, tz + 6.53, tx, ty, tz);
    views[1] = cam(tx - 2.13, ty - 3.71, tz + 2.9, tx, ty, tz); /* pixels ~1/10 cell */
    double far = 1.2 * side;
    views[2] = cam(tx - 0.48 * far, ty - 0.6 * far, tz + 0.64 * far, tx, ty, tz);
    views[2].camera.fov = 12.0 / far * 57.3;
    views[3] = cam(tx + 30.7, ty + 20.3, tz - 10.1, tx, ty, tz);
    views[3].camera.ortho = true, views[3].camera.ortho_height = 12;
    for (int v = 0; v < 4; v++) views[v].width = w, views[v].height = h;
}

/* Octrees 17, 20 and 21 levels deep (above VX_RENDER_PRECISE_DEPTH: the
 * float64 variant) under the strict rule, on deep_views(). The float
 * variant is rendered too, for the record (per view printed, not asserted;
 * over all views at most 2% of the pixels off the reference). */
static void test_deep_octrees(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    const uint32_t depths[] = {17, 20, 21};
    size_t fl_bad = 0, fl_px = 0, pr_bad = 0, pr_px = 0;
    for (size_t di = 0; di < sizeof depths / sizeof depths[0]; di++) {
        uint32_t depth = depths[di];
        vx_svo_scene s;
        uint32_t base[3][3];
        deep_scene(depth, &s, base);
        vx_error err = {0};
        vx_render_scene* rs = NULL;
        CHECK(vx_render_scene_create(gpu, &s, &rs, &err) == VX_OK);
        CHECK(vx_render_scene_precise(rs));
        vx_render_scene_destroy(rs);
        for (int c = 0; c < 3; c++) {
            vx_render_desc views[4];
            deep_views(base[c], 1u << depth, 48, 40, views);
            for (int v = 0; v < 4; v++) {
                char nm[64];
                snprintf(nm, sizeof nm, "depth %u place %d view %d", depth, c, v);
                g_strict = true;
                g_max_ambiguous = 0.01;
                cmp_result r = check_scene(nm, &s, views[v], 60);
                pr_bad += r.bad, pr_px += r.pixels;
                g_force = 0; /* the float variant, for the record */
                snprintf(nm, sizeof nm, "  (float) depth %u %d/%d", depth, c, v);
                r = check_scene(nm, &s, views[v], 0);
                fl_bad += r.bad, fl_px += r.pixels;
                g_force = -1;
                g_strict = false;
                g_max_ambiguous = 0.125;
            }
        }
        vx_svo_scene_free(&s);
    }
    printf("deep octrees, strict rule: float64 variant %zu of %zu pixels differ, float variant %zu of %zu\n", pr_bad,
           pr_px, fl_bad, fl_px);
    /* The float variant past its depth misses single cells (0.5% of these pixels on lavapipe and the H200, the far
     * views most), not whole views: a walk that loses its stack does (25% with the rebased walk's ladder of
     * selects sized for 16 levels, issue 21's eighteenth sitting) */
    CHECKF(fl_bad <= fl_px / 50, "float variant: %zu of %zu pixels differ from the reference", fl_bad, fl_px);
}

/* The float variant up to VX_RENDER_PRECISE_DEPTH (issue 18, "exact at every
 * depth"): octrees 10 (exact t, one frame), 12, 14 and 16 levels deep (two
 * frames), the views of deep_views() at 128x96, under the strict rule (same
 * cell, depth within 1e-4). On the close-ups (views 0, 1 and 3) at most 0.01%
 * of the pixels of each depth may differ from the CPU reference; with the
 * plain float walk 0.0045%, 0.024%, 0.14% and 0.61% differed in cell and
 * 0.7-39% in depth. The far view
 * (a narrow cone across 2^depth cells) keeps the float camera's error, a
 * direction off by a few 2^-24 over 2^depth cells (0.03-0.6% of its pixels
 * at 12-16): bounded at 1%, for the record. */
static void test_deep_float(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    const uint32_t depths[] = {10, 12, 14, 16};
    for (size_t di = 0; di < sizeof depths / sizeof depths[0]; di++) {
        uint32_t depth = depths[di];
        vx_svo_scene s;
        uint32_t base[3][3];
        deep_scene(depth, &s, base);
        size_t bad = 0, px = 0, cells = 0, far_bad = 0, far_px = 0, hits = 0, amb = 0;
        for (int c = 0; c < 3; c++) {
            vx_render_desc views[4];
            deep_views(base[c], 1u << depth, 128, 96, views);
            for (int v = 0; v < 4; v++) {
                char nm[64];
                snprintf(nm, sizeof nm, "float depth %u place %d view %d", depth, c, v);
                /* the share is asserted over the depth's close-ups below; one
                 * view alone (12288 pixels) may hold a pixel or two */
                g_strict = true;
                g_min_share = v == 2 ? 0.99 : 0.999;
                g_max_ambiguous = 0.01;
                cmp_result r = check_scene(nm, &s, views[v], 200);
                g_strict = false;
                g_min_share = 0.9999;
                g_max_ambiguous = 0.125;
                hits += r.hits, amb += r.ambiguous;
                if (v == 2) {
                    far_bad += r.bad + r.depth_bad, far_px += r.pixels;
                } else {
                    bad += r.bad + r.depth_bad, px += r.pixels, cells += r.bad;
                }
            }
        }
        printf("deep float, depth %u: close-ups %zu of %zu pixels differ (%.4f%%; %zu in cell, %zu in depth only), "
               "far view %zu of %zu (%.4f%%); %zu hits, %zu ambiguous\n",
               depth, bad, px, 100.0 * bad / px, cells, bad - cells, far_bad, far_px, 100.0 * far_bad / far_px, hits,
               amb);
        CHECKF((double)bad <= 1e-4 * px, "depth %u: %zu of %zu close-up pixels differ (%.4f%%)", depth, bad, px,
               100.0 * bad / px);
        CHECKF((double)far_bad <= 1e-2 * far_px, "depth %u: %zu of %zu far view pixels differ", depth, far_bad, far_px);
        vx_svo_scene_free(&s);
    }
}

/* A device without shaderFloat64 must refuse deep models at load (and a
 * forced float64 frame) with a message, not crash or trace them in float. */
static void test_deep_without_float64(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    uint32_t one[3] = {1000, 2000, 3000};
    uint8_t pal = 9;
    vx_svo_model m;
    REQUIRE(ts_model(&m, (uint32_t[3]){1u << 17, 4096, 4096}, one, &pal, 1) == VX_OK);
    vx_svo_instance in = ts_inst(0, NULL, 0, 0, 0);
    vx_svo_scene s;
    ts_scene(&s, &m, 1, &in, 1);
    bool had = gpu->has_float64;
    gpu->has_float64 = false; /* as on a device that lacks it */
    vx_error err = {0};
    vx_render_scene* rs = NULL;
    CHECK(vx_render_scene_create(gpu, &s, &rs, &err) == VX_ERR_UNSUPPORTED);
    CHECKF(strstr(err.msg, "17 octree levels") && strstr(err.msg, "float64"), "message: %s", err.msg);
    CHECK(rs == NULL);
    vx_svo_scene_free(&s);
    random_scene(&s, NULL, 0, 0, 0, 30);
    CHECK(vx_render_scene_create(gpu, &s, &rs, &err) == VX_OK);
    CHECK(!vx_render_scene_precise(rs));
    vx__render_scene_force_precise(rs, 1);
    vx_render_image img = {0};
    CHECK(vx_render_frame(rs, &(vx_render_desc){.width = 8, .height = 8}, &img, &err) == VX_ERR_UNSUPPORTED);
    gpu->has_float64 = had;
    vx_render_image_free(&img);
    vx_render_scene_destroy(rs);
    vx_svo_scene_free(&s);
}

/* The float64 variant on the ordinary extreme cases (transforms, BVH,
 * origins, edges, colour modes): deep models may share a scene with these. */
static void test_transforms(void);
static void test_many_instances(void);

/* Far descriptors reachable from node i (the tree walked, DAG blocks once per path). */
static uint32_t far_descs(const vx_svo_model* m, uint32_t i) {
    uint32_t d = m->nodes[i], n = vx_svo_desc_far(d);
    uint32_t blk = vx_svo_desc_far(d) ? m->nodes[i - vx_svo_desc_ptr(d)] : i - vx_svo_desc_ptr(d);
    uint32_t inner = vx_svo_desc_valid(d) & ~vx_svo_desc_leaf(d);
    for (uint32_t k = 0; inner; inner &= inner - 1, k++) n += far_descs(m, blk + k);
    return n;
}

/* The GPU frame of rs (depth with hits) against the CPU reference's: the
 * rule of check_scene, for a render scene the caller made or updated. */
static void check_frame(const char* name, vx_render_scene* rs, const vx_svo_scene* s, vx_render_desc d) {
    d.want_hits = true;
    vx_render_image gi = {0}, ci = {0};
    vx_error err = {0};
    vx_result r = vx_render_frame(rs, &d, &gi, &err);
    CHECKF(r == VX_OK, "%s: %s", name, err.msg);
    vx_result rc = vx_render_cpu(s, &d, NULL, &ci, &err);
    CHECKF(rc == VX_OK, "%s: %s", name, err.msg);
    if (!r && !rc) {
        cmp_result c = compare(name, &gi, &ci);
        CHECKF(c.hits >= 100, "%s: %zu hits", name, c.hits);
        CHECKF((double)(c.exact + c.tie) >= g_min_share * (c.pixels - c.ambiguous), "%s: %zu of %zu pixels differ",
               name, c.bad, c.pixels);
        CHECKF(c.depth_bad <= (1 - g_min_share) * c.pixels, "%s: %zu depths off by more than 1e-4", name, c.depth_bad);
    }
    vx_render_image_free(&gi);
    vx_render_image_free(&ci);
}

/* Far pointers (issue 21): the trace kernel tests a descriptor's far bit
 * only where some model may hold a far pointer (its FAR constant,
 * render_scene.c). A model built with the far limit lowered to 3 (far
 * pointers throughout a small tree) must turn FAR on and trace the CPU
 * reference's cells, in colour too (the hit's attribute record goes
 * through the far slot); the same cells built as usual (a small model has
 * none) leave it off; and a scene made without far pointers turns it on when
 * an edit appends some (vx_render_scene_update_model) and traces the
 * reference's cells after. */
static void test_far_pointers(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    vx_render_desc views[2] = {cam(-9, -14, 30, 10, 8, 11), cam(40, 31, -6, 10, 8, 11)};
    views[0].width = views[1].width = 64, views[0].height = views[1].height = 48;
    for (int lim = 0; lim < 2; lim++) {
        vx_svo_model m;
        vx_result br = ts_random_model_far(&m, 20, 17, 23, 35, 777, lim ? 3 : 0);
        REQUIRE(br == VX_OK);
        uint32_t nfar = far_descs(&m, m.root);
        CHECKF(lim ? nfar > 20 : nfar == 0, "far limit %s: %u far descriptors", lim ? "3" : "default", nfar);
        vx_svo_scene s;
        vx_svo_instance in = ts_inst(0, NULL, 0, 0, 0);
        ts_scene(&s, &m, 1, &in, 1);
        vx_render_scene* rs = NULL;
        vx_error err = {0};
        REQUIRE(vx_render_scene_create(gpu, &s, &rs, &err) == VX_OK);
        CHECKF(vx__render_scene_far(rs) == (lim == 1), "far limit %s: FAR %d", lim ? "3" : "default",
               vx__render_scene_far(rs));
        for (int v = 0; v < 2; v++) {
            char nm[64];
            snprintf(nm, sizeof nm, "far pointers %s view %d", lim ? "throughout" : "none", v);
            check_frame(nm, rs, &s, views[v]);
        }
        if (lim) {
            /* colour: the hit's attribute record through a far block */
            vx_render_desc d = views[0];
            d.mode = VX_RENDER_ALBEDO;
            vx_render_image gi = {0}, ci = {0};
            REQUIRE(vx_render_frame(rs, &d, &gi, &err) == VX_OK);
            REQUIRE(vx_render_cpu(&s, &d, NULL, &ci, &err) == VX_OK);
            size_t n = (size_t)d.width * d.height, off = 0;
            for (size_t i = 0; i < 4 * n; i++) off += fabsf(gi.pixels[i] - ci.pixels[i]) > 1e-5f;
            CHECKF(off <= n / 1000, "far pointers: %zu albedo channels differ from the CPU reference", off);
            vx_render_image_free(&gi);
            vx_render_image_free(&ci);
        } else {
            /* an edit with the far limit at 3 appends far pointers: FAR turns on */
            vx_svo_editor* e = NULL;
            vx_result er = vx_svo_editor_create(&(vx_svo_editor_desc){.testing.far_limit = 3}, &s.models[0], &e, &err);
            REQUIRE(er == VX_OK);
            static vx_svo_cell_write w[7 * 7 * 7];
            size_t nw = 0;
            for (uint32_t z = 4; z < 11; z++)
                for (uint32_t y = 3; y < 10; y++)
                    for (uint32_t x = 5; x < 12; x++)
                        w[nw++] = (vx_svo_cell_write){.x = x, .y = y, .z = z, .set = (x + y + z) % 3 != 0,
                                                      .value = {.palette = (uint8_t)(1 + (x * 7 + z) % 200)}};
            vx_svo_edit_stats st;
            REQUIRE(vx_svo_editor_apply(e, w, nw, &st, &err) == VX_OK);
            vx_svo_editor_destroy(e);
            CHECKF(far_descs(&s.models[0], s.models[0].root) > 0, "the edit appended no far pointer");
            REQUIRE(vx_render_scene_update_model(rs, &s, 0, st.words_from, st.records_from, &err) == VX_OK);
            CHECK(vx__render_scene_far(rs));
            for (int v = 0; v < 2; v++) {
                char nm[64];
                snprintf(nm, sizeof nm, "far pointers after an edit, view %d", v);
                check_frame(nm, rs, &s, views[v]);
            }
        }
        vx_render_scene_destroy(rs);
        vx_svo_scene_free(&s);
    }
    CHECK(vx_gpu_validation_errors(gpu) == 0);
}
/* Two frames of rs for d (hits wanted), with the primary rays' start on the
 * frame's octree path (trace.comp) and with every walk from the root: the
 * pixels and hits (instance, cell, depth bits) must be the same; *fewer
 * counts the frame when the path's iterations are fewer. */
static size_t path_frames(const char* name, vx_render_scene* rs, vx_render_desc d, size_t* fewer, double* saved) {
    vx_render_image a[2] = {{0}};
    vx_error err = {0};
    d.want_hits = true;
    for (int p = 0; p < 2; p++) {
        vx__render_scene_trace_path(rs, 1 - p); /* on even where a CPU device's default is off */
        CHECKF(vx_render_frame(rs, &d, &a[p], &err) == VX_OK, "%s: %s", name, err.msg);
    }
    vx__render_scene_trace_path(rs, -1);
    size_t n = (size_t)d.width * d.height, diff = 0;
    double it[2] = {0, 0};
    for (size_t i = 0; a[0].hits && a[1].hits && i < n; i++) {
        const vx_render_hit *x = &a[0].hits[i], *y = &a[1].hits[i];
        bool same = x->instance == y->instance && !memcmp(x->cell, y->cell, sizeof x->cell) &&
                    !memcmp(&x->t, &y->t, sizeof x->t) && !memcmp(&a[0].pixels[4 * i], &a[1].pixels[4 * i], 16);
        if (!same && diff < 3)
            printf("  %s pixel %zu,%zu: path inst %d cell %u,%u,%u t %.9g | root inst %d cell %u,%u,%u t %.9g\n", name,
                   i % d.width, i / d.width, (int)x->instance, x->cell[0], x->cell[1], x->cell[2], x->t, (int)y->instance,
                   y->cell[0], y->cell[1], y->cell[2], y->t);
        diff += !same;
        it[0] += x->iterations, it[1] += y->iterations;
    }
    if (!a[0].hits || !a[1].hits) diff = n;
    *fewer += it[0] < it[1];
    *saved += (it[1] - it[0]) / (double)n;
    vx_render_image_free(&a[0]);
    vx_render_image_free(&a[1]);
    return diff;
}

/* The primary rays' starts below the root (one instance: render_scene.c
 * frame_paths, the start in trace_model): frames from eyes inside a sparse 64^3 model with
 * solid blocks, at random points, on node planes (multiples of 4 to 32
 * cells, the model's mid-planes) and 1e-4 cells beside them, and from
 * outside the model box (none there), perspective and orthographic, in
 * depth and colour (shadow rays from the root), with far pointers
 * throughout and without, rotated and mirrored, must equal the walk from
 * the root; the starts must save iterations from most random eyes inside;
 * after an edit the path follows
 * the model's new words (a stale list fails). */
static void test_path_start(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    static const double rot[9] = {0, 0, -1, 1, 0, 0, 0, -1, 0};
    size_t frames = 0, fewer = 0, differ = 0, rand_frames = 0, rand_fewer = 0, outside_frames = 0, outside_fewer = 0;
    double saved = 0;
    for (int lim = 0; lim < 2; lim++) {
        /* solid blocks of 2-9 cells and 1% scattered cells in 64^3 */
        size_t cap = 64 * 64 * 64, n = 0;
        uint32_t* xyz = malloc(cap * 12);
        uint8_t* pal = malloc(cap);
        uint8_t* used = calloc(cap, 1);
        REQUIRE(xyz && pal && used);
        uint32_t seed = 1234 + (uint32_t)lim;
        for (int b = 0; b < 40; b++) {
            uint32_t o[3], e[3];
            for (int k = 0; k < 3; k++) e[k] = 2 + ts_rng(&seed) % 8, o[k] = ts_rng(&seed) % (64 - e[k]);
            for (uint32_t z = o[2]; z < o[2] + e[2]; z++)
                for (uint32_t y = o[1]; y < o[1] + e[1]; y++)
                    for (uint32_t x = o[0]; x < o[0] + e[0]; x++) used[(z * 64 + y) * 64 + x] = 1;
        }
        for (size_t i = 0; i < cap; i++) used[i] |= ts_rng(&seed) % 100 == 0;
        for (uint32_t i = 0; i < cap; i++)
            if (used[i]) xyz[3 * n] = i % 64, xyz[3 * n + 1] = i / 64 % 64, xyz[3 * n + 2] = i / 4096, pal[n++] = (uint8_t)(1 + i % 250);
        for (int tf = 0; tf < 2; tf++) {
            vx_svo_model mc;
            vx_result br = ts_model_far(&mc, (uint32_t[3]){64, 64, 64}, xyz, pal, n, lim ? 3 : 0);
            REQUIRE(br == VX_OK);
            CHECKF(lim ? far_descs(&mc, mc.root) > 20 : far_descs(&mc, mc.root) == 0, "far limit %s: %u far descriptors",
                   lim ? "3" : "default", far_descs(&mc, mc.root));
            vx_svo_scene s;
            vx_svo_instance in = ts_inst(0, tf ? rot : NULL, tf ? 3 : 0, tf ? -4 : 0, tf ? 7 : 0);
            ts_scene(&s, &mc, 1, &in, 1);
            vx_render_scene* rs = NULL;
            vx_error err = {0};
            REQUIRE(vx_render_scene_create(gpu, &s, &rs, &err) == VX_OK);
            vx__render_scene_grid(rs, 0); /* the starts serve the octree walk (the grid walk has none) */
            for (int v = 0; v < 24; v++) {
                /* the eye in model cells: random, on planes, beside them */
                double e[3];
                for (int k = 0; k < 3; k++) {
                    uint32_t r = ts_rng(&seed);
                    int kind = v % 4;
                    double plane = (double)((1u << (2 + r % 4)) * (1 + (r >> 4) % 3));
                    if (plane >= 64) plane = 32;
                    e[k] = kind == 0 ? 1 + (r % 6200) / 100.0 : kind == 1 ? plane : kind == 2 ? plane + 1e-4 : plane - 1e-4;
                    if (v == 23) e[k] = 32; /* the model's centre: every mid-plane */
                    if (v == 20) e[k] = 32 + (k == 0 ? 1e-3 : -2e-3); /* 1 and 2 times the margin beside them */
                    if (used[((uint32_t)e[2] * 64 + (uint32_t)e[1]) * 64 + (uint32_t)e[0]] && k == 2) e[k] += 0.5;
                }
                double dir[3], dl = 0;
                for (int k = 0; k < 3; k++) dir[k] = (double)(ts_rng(&seed) % 2001) - 1000, dl += dir[k] * dir[k];
                dl = sqrt(dl);
                vx_render_desc d = {.width = 40, .height = 30, .mode = v % 3 == 2 ? VX_RENDER_COLOR : VX_RENDER_DEPTH};
                d.camera.set = true, d.camera.fov = 70;
                for (int k = 0; k < 3; k++) {
                    double w = e[k];
                    if (tf) {
                        /* world = rot * model + t (the instance's map) */
                        w = in.xform[4 * k + 3];
                        for (int c = 0; c < 3; c++) w += in.xform[4 * k + c] * e[c];
                    }
                    d.camera.eye[k] = w, d.camera.target[k] = w + dir[k] / dl * 10;
                }
                char nm[96];
                snprintf(nm, sizeof nm, "path start, far %s, %s, view %d", lim ? "throughout" : "none",
                         tf ? "rotated" : "identity", v);
                size_t f0 = fewer;
                differ += path_frames(nm, rs, d, &fewer, &saved);
                frames++;
                if (v % 4 == 0 && v != 20) rand_frames++, rand_fewer += fewer > f0;
            }
            for (int v = 0; v < 8; v++) {
                /* from outside the model box (no starts there), perspective and orthographic, near and far */
                double dir[3], dl = 0;
                for (int k = 0; k < 3; k++) dir[k] = (double)(ts_rng(&seed) % 2001) - 1000, dl += dir[k] * dir[k];
                dl = sqrt(dl);
                vx_render_desc d = {.width = 64, .height = 48, .mode = v % 2 ? VX_RENDER_COLOR : VX_RENDER_DEPTH};
                d.camera.set = true, d.camera.ortho = v >= 6, d.camera.ortho_height = 40;
                double c[3] = {32, 32, 32}, dist = v % 3 == 0 ? 60 : 140;
                for (int k = 0; k < 3; k++) {
                    double w = c[k], e = c[k] + dir[k] / dl * dist;
                    if (tf) {
                        w = e = in.xform[4 * k + 3];
                        for (int j = 0; j < 3; j++) w += in.xform[4 * k + j] * c[j], e += in.xform[4 * k + j] * (c[j] + dir[j] / dl * dist);
                    }
                    d.camera.eye[k] = e, d.camera.target[k] = w;
                }
                char nm[96];
                snprintf(nm, sizeof nm, "path start, far %s, %s, outside %d", lim ? "throughout" : "none",
                         tf ? "rotated" : "identity", v);
                size_t f0 = fewer;
                differ += path_frames(nm, rs, d, &fewer, &saved);
                frames++;
                outside_frames++, outside_fewer += fewer > f0;
            }
            if (!tf) {
                /* an edit: a solid block around the model's centre and cells removed; the path follows */
                vx_svo_editor* ed = NULL;
                REQUIRE(vx_svo_editor_create(&(vx_svo_editor_desc){0}, &s.models[0], &ed, &err) == VX_OK);
                static vx_svo_cell_write w[12 * 12 * 12];
                size_t nw = 0;
                for (uint32_t z = 26; z < 38; z++)
                    for (uint32_t y = 26; y < 38; y++)
                        for (uint32_t x = 26; x < 38; x++)
                            w[nw++] = (vx_svo_cell_write){.x = x, .y = y, .z = z, .set = x < 30 || (x + y + z) % 4 == 0,
                                                          .value = {.palette = (uint8_t)(1 + x % 200)}};
                vx_svo_edit_stats st;
                REQUIRE(vx_svo_editor_apply(ed, w, nw, &st, &err) == VX_OK);
                vx_svo_editor_destroy(ed);
                REQUIRE(vx_render_scene_update_model(rs, &s, 0, st.words_from, st.records_from, &err) == VX_OK);
                static const double eyes[4][3] = {{31.5, 33.25, 34.5}, {37.9, 26.1, 30.5}, {32, 32, 32}, {20.5, 40.5, 33.5}};
                for (int v = 0; v < 4; v++) {
                    vx_render_desc d = cam(eyes[v][0], eyes[v][1], eyes[v][2], 64 - eyes[v][1], eyes[v][0], 5.0 + v);
                    d.width = 40, d.height = 30;
                    char nm[96];
                    snprintf(nm, sizeof nm, "path start after an edit, far %s, view %d", lim ? "throughout" : "none", v);
                    differ += path_frames(nm, rs, d, &fewer, &saved);
                    frames++;
                    /* and the CPU reference's cells; view 2's eye sits on the
                     * model's central node planes, where the H200's float walk
                     * (from the root as from the path, the same pixels above)
                     * took a neighbour's cell in 2 of 1,124 unambiguous pixels
                     * (stop 45): that view gets the share of the deep views'
                     * view 2 (test_deep_float), 1% of a 40x30 frame */
                    g_min_share = v == 2 ? 0.99 : 0.9999;
                    check_frame(nm, rs, &s, d);
                    g_min_share = 0.9999;
                }
            }
            vx_render_scene_destroy(rs);
            vx_svo_scene_free(&s);
        }
        free(xyz), free(pal), free(used);
    }
    printf("path start: %zu frames, %zu with fewer iterations (%zu of %zu from random eyes inside, %zu of %zu from "
           "outside), %.2f iterations a ray saved on average, %zu pixels differ\n",
           frames, fewer, rand_fewer, rand_frames, outside_fewer, outside_frames, saved / (double)frames, differ);
    CHECK(differ == 0);
    /* eyes on node planes or within 2^-16 of the cube (0.001 cells) of one walk from the root */
    CHECK(rand_fewer * 4 >= rand_frames * 3);
    /* from outside: no start where rays enter the model box (frame_paths: their lanes would start at different nodes) */
    CHECK(outside_fewer == 0);
    CHECK(vx_gpu_validation_errors(gpu) == 0);
}

/* The primary rays' start below a rebased model's frame level (issue 21,
 * rbstart): where node X lies at depth k = depth - VX_RENDER_FRAME_LEVELS or
 * below, trace_model starts the ray in the frame of X's depth-k ancestor N
 * (the switch into N's frame before the walk's loop, then on at X). Octrees
 * 11 to 16 levels deep (deep_scene: two frames) seen from eyes a few cells
 * from each place's blocks (X several levels below k), on the planes of the
 * root's, N's and X's cubes and 1e-4 cells beside them, in depth and colour,
 * the instance rotated and not: every
 * pixel's instance, cell, depth bits and colour must be those of the walk
 * from the root (path_frames), and most frames from off the planes must
 * take fewer iterations. */
static void test_path_start_deep(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    static const double rot[9] = {0, 0, -1, 1, 0, 0, 0, -1, 0};
    const uint32_t depths[] = {11, 12, 14, 16};
    size_t frames = 0, fewer = 0, differ = 0, off_frames = 0, off_fewer = 0;
    double saved = 0;
    for (size_t di = 0; di < sizeof depths / sizeof depths[0]; di++) {
        uint32_t depth = depths[di], side = 1u << depth, nside = 1u << VX_RENDER_FRAME_LEVELS;
        vx_svo_scene s;
        uint32_t base[3][3];
        deep_scene(depth, &s, base);
        for (int tf = 0; tf < 2; tf++) {
            /* the rotated instance at 12 and 16 levels only (CI time, docs/TESTING.md stop 60): the frame
             * switch's rotation is the same code at every depth */
            if (tf && depth != 12 && depth != 16) continue;
            vx_svo_instance in = ts_inst(0, tf ? rot : NULL, tf ? 3 : 0, tf ? -4 : 0, tf ? 7 : 0);
            s.instances[0] = in;
            vx_svo_scene_update_bounds(&s);
            vx_render_scene* rs = NULL;
            vx_error err = {0};
            REQUIRE(vx_render_scene_create(gpu, &s, &rs, &err) == VX_OK);
            vx__render_scene_grid(rs, 0); /* the starts serve the octree walk (the grid walk has none) */
            for (int c = 0; c < 3; c++) {
                double t[3] = {base[c][0] + 5.0, base[c][1] + 3.0, base[c][2] + 3.0};
                for (int v = 0; v < 8; v++) {
                    /* the eye in model cells: off the planes (0, 1), on the root's mid-plane x (2), on N's planes
                     * (3, 4: the multiple of nside nearest the blocks on x, y), 1e-4 beside them (5), on X's
                     * planes (6: multiples of 8 cells; 7: 1e-4 beside them) */
                    double e[3] = {t[0] + 7.31, t[1] - 9.17, t[2] + 6.53};
                    if (v == 1) e[0] = t[0] - 2.13, e[1] = t[1] - 3.71, e[2] = t[2] + 2.9;
                    if (v == 2) e[0] = side / 2;
                    for (int k = 0; k < 2 && (v == 3 || v == 4 || v == 5); k++)
                        if (v != 3 + k || v == 5) {
                            double pl = floor(t[k] / nside + 0.5) * nside;
                            if (pl <= 0) pl = nside;
                            e[k] = pl + (v == 5 ? 1e-4 : 0);
                        }
                    if (v >= 6)
                        for (int k = 0; k < 3; k++) e[k] = floor(e[k] / 8 + 0.5) * 8 + (v == 7 ? 1e-4 : 0);
                    vx_render_desc d = {.width = 40, .height = 30, .mode = v % 2 ? VX_RENDER_COLOR : VX_RENDER_DEPTH};
                    d.camera.set = true, d.camera.fov = 70;
                    ts_inst_point(&in, e, d.camera.eye);
                    ts_inst_point(&in, t, d.camera.target);
                    char nm[96];
                    snprintf(nm, sizeof nm, "deep path start, depth %u, %s, place %d view %d", depth,
                             tf ? "rotated" : "identity", c, v);
                    size_t f0 = fewer;
                    differ += path_frames(nm, rs, d, &fewer, &saved);
                    frames++;
                    if (v < 2) off_frames++, off_fewer += fewer > f0;
                }
            }
            vx_render_scene_destroy(rs);
        }
        vx_svo_scene_free(&s);
    }
    printf("deep path start: %zu frames, %zu with fewer iterations (%zu of %zu from eyes off the planes), %.2f "
           "iterations a ray saved on average, %zu pixels differ\n",
           frames, fewer, off_fewer, off_frames, saved / (double)frames, differ);
    CHECK(differ == 0);
    CHECK(off_fewer * 4 >= off_frames * 3);
    CHECK(vx_gpu_validation_errors(gpu) == 0);
}

static void test_modes(void);
static void test_precise_variant(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    if (!gpu->has_float64) SKIP("%s has no shaderFloat64", vx_gpu_device_name(gpu));
    g_force = 1;
    test_axis_rays_on_edges();
    test_ray_origins();
    test_grazing();
    test_transforms();
    test_many_instances();
    test_modes();
    g_force = -1;
}

static void test_transforms(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    struct {
        const char* name;
        double m[9];
        double t[3];
    } cases[] = {
        {"translated 1e5", {1, 0, 0, 0, 1, 0, 0, 0, 1}, {1e5, -1e5, 1e5}},
        {"scaled 1e-3", {1e-3, 0, 0, 0, 1e-3, 0, 0, 0, 1e-3}, {0.5, 0.25, 0}},
        {"scaled 1e3", {1e3, 0, 0, 0, 1e3, 0, 0, 0, 1e3}, {-2e3, 0, 5e3}},
        {"mirrored x", {-1, 0, 0, 0, 1, 0, 0, 0, 1}, {12, 0, 0}},
        {"rotated and mirrored", {0, 0, -1, 1, 0, 0, 0, -1, 0}, {3, -4, 7}},
        {"non-uniform scale + shear", {2, 0.5, 0, 0, 0.5, 0, 0.25, 0, 3}, {1, 2, 3}},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        vx_svo_scene s;
        random_scene(&s, cases[i].m, cases[i].t[0], cases[i].t[1], cases[i].t[2], 25);
        check_scene(cases[i].name, &s, (vx_render_desc){.mode = VX_RENDER_DEPTH, .width = 48, .height = 40}, 200);
        vx_svo_scene_free(&s);
    }
}

/* The GPU tracer's float range (render/trace.h, vx__gpu_float_range): a
 * scene scaled by 1e15 or 1e-15 traces as the CPU reference does, and so
 * does one of cells 2^30 wide translated to 1e20 (past 2^56: refused until
 * the limit took the kernels' coordinates relative to the frame's reference
 * point into account); scaled by 1e25 or 1e-25, or of unit cells translated
 * to 1e25 (a double there cannot tell its corners apart), the frame is
 * VX_ERR_LIMIT with a message naming the range, not an empty image (1e25: no
 * pixel hit where the reference hit 30%; 1e-20: depths off), while the CPU
 * reference still traces it. */
static void test_float_range(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    static const struct {
        double scale, t;
        bool ok;
    } cases[] = {{1e15, 0, true}, {1e-15, 0, true}, {0x1p30, 1e20, true}, {1e25, 0, false}, {1, 1e25, false},
                 {1e-25, 0, false}};
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        double k = cases[i].scale, m[9] = {k, 0, 0, 0, k, 0, 0, 0, k};
        vx_svo_scene s;
        random_scene(&s, m, cases[i].t, 0, 0, 25);
        vx_render_desc d = {.mode = VX_RENDER_DEPTH, .width = 32, .height = 24};
        char name[64];
        snprintf(name, sizeof name, "scaled %g, at %g", k, cases[i].t);
        if (cases[i].ok) {
            check_scene(name, &s, d, 100);
        } else {
            vx_render_scene* rs = NULL;
            vx_render_image gi = {0}, ci = {0};
            vx_error err = {0};
            vx_result r = vx_render_scene_create(gpu, &s, &rs, &err);
            if (!r) r = vx_render_frame(rs, &d, &gi, &err);
            CHECKF(r == VX_ERR_LIMIT && strstr(err.msg, "float range"), "%s: result %d (%s)", name, (int)r, err.msg);
            vx_error cerr = {0};
            CHECKF(vx_render_cpu(&s, &d, NULL, &ci, &cerr) == VX_OK, "%s: CPU reference %s", name, cerr.msg);
            size_t hits = 0;
            for (size_t p = 0; ci.pixels && p < (size_t)d.width * d.height; p++) hits += isfinite(ci.pixels[4 * p]);
            CHECKF(hits > 0, "%s: the CPU reference hit nothing", name);
            vx_render_image_free(&gi);
            vx_render_image_free(&ci);
            vx_render_scene_destroy(rs);
        }
        vx_svo_scene_free(&s);
    }
}

/* Far from the origin (docs/TESTING.md, "far from the origin"): small
 * voxels (1/64 of a unit) placed 6e6 from 0, where a float is 0.5 apart (32
 * voxels), by the scene's world map and by three instances (one plain, one
 * turned, one mirrored). The kernels work relative to the frame's reference
 * point (vx__frame), whose differences the host takes in double, so (a) the
 * close-ups match the double-precision CPU reference as near the origin do
 * and (b) the frame is the one of the same scene at 0 seen from a camera
 * moved alike: the same instance, cell and depth bits on every pixel, in
 * vx_render_frame's depth and colour modes (the sun's depth map, shadow
 * rays) and through the pass pipeline (gbuffer, direct with a point light
 * placed alike, ao). Rows, boxes, lights or the map's frame taken from
 * world coordinates rounded to float would move the surfaces by up to 16
 * voxels (the rows made from R rounded to float: 591 to all 1,536 pixels of
 * a view off). */
static void far_scene(vx_svo_scene* s, double tx, double ty, double tz) {
    vx_svo_model m[2];
    memset(m, 0, sizeof m);
    ts_random_model(&m[0], 24, 20, 16, 30, 17);
    ts_random_model(&m[1], 9, 9, 9, 60, 18);
    static const double rot[9] = {0, -1, 0, 1, 0, 0, 0, 0, 1}, mir[9] = {-1, 0, 0, 0, 1, 0, 0, 0, 1};
    vx_svo_instance in[3] = {ts_inst(0, NULL, 0, 0, 0), ts_inst(1, rot, 34, 4, 2), ts_inst(1, mir, -3, 22, 5)};
    ts_scene(s, m, 2, in, 3);
    memset(s->world_from_grid, 0, sizeof s->world_from_grid);
    const double k = 1.0 / 64;
    s->world_from_grid[0] = s->world_from_grid[5] = s->world_from_grid[10] = k;
    s->world_from_grid[3] = tx, s->world_from_grid[7] = ty, s->world_from_grid[11] = tz;
    vx_svo_scene_update_bounds(s);
}

static void test_far_origin(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    const double T[3] = {6e6, -6000001, 2097152}; /* float steps 0.5, 0.5, 0.25 */
    vx_svo_scene far, near;
    far_scene(&far, T[0], T[1], T[2]);
    far_scene(&near, 0, 0, 0);
    /* world units: the scene spans about 0.7 x 0.5 x 0.4 near 0; the views' points multiples of 1/64, but the
     * inside eye's, half a cell off a corner (on the corner of cell 20,16,8 the H200 started in that cell at t 0
     * where the CPU reference did not: an ambiguous start, not a far-origin property) */
    static const double views[4][6] = {{-0.25, -0.375, 0.5, 0.3125, 0.25, 0.125},  /* oblique */
                                       {0.125, 0.1875, 0.34375, 0.25, 0.3125, 0},  /* close-up, just above */
                                       {0.75, 0.125, 0.1875, 0.25, 0.1875, 0.125},  /* close-up, from the side */
                                       {0.3203125, 0.2578125, 0.1328125, 0.5, 0.0625, 0.0625}}; /* eye inside the bounds */
    vx_render_scene *rf = NULL, *rn = NULL;
    vx_frame_renderer *ff = NULL, *fn = NULL;
    vx_error err = {0};
    REQUIRE(vx_render_scene_create(gpu, &far, &rf, &err) == VX_OK);
    REQUIRE(vx_render_scene_create(gpu, &near, &rn, &err) == VX_OK);
    REQUIRE(vx_frame_renderer_create(rf, &far, &ff, &err) == VX_OK);
    REQUIRE(vx_frame_renderer_create(rn, &near, &fn, &err) == VX_OK);
    vx_pass_list L;
    REQUIRE(vx_pass_list_parse("gbuffer,direct,ao", &L, &err) == VX_OK);
    for (int v = 0; v < 4; v++) {
        char nm[64];
        const double* c = views[v];
        vx_render_desc dn = cam(c[0], c[1], c[2], c[3], c[4], c[5]);
        vx_render_desc df = cam(c[0] + T[0], c[1] + T[1], c[2] + T[2], c[3] + T[0], c[4] + T[1], c[5] + T[2]);
        dn.width = df.width = 48, dn.height = df.height = 32;
        snprintf(nm, sizeof nm, "far view %d", v);
        check_scene(nm, &far, df, 200);
        for (int mode = 0; mode < 2; mode++) {
            dn.mode = df.mode = mode ? VX_RENDER_COLOR : VX_RENDER_DEPTH;
            dn.want_hits = df.want_hits = true;
            vx_render_image a = {0}, b = {0};
            REQUIRE(vx_render_frame(rf, &df, &a, &err) == VX_OK);
            REQUIRE(vx_render_frame(rn, &dn, &b, &err) == VX_OK);
            size_t n = (size_t)a.width * a.height, hit = 0, differ = 0, px = 0;
            for (size_t i = 0; i < n; i++) {
                const vx_render_hit *x = &a.hits[i], *y = &b.hits[i];
                hit += y->instance != VX_RENDER_NO_HIT;
                differ += x->instance != y->instance || memcmp(x->cell, y->cell, sizeof x->cell) ||
                          memcmp(&x->t, &y->t, sizeof x->t);
                px += memcmp(&a.pixels[4 * i], &b.pixels[4 * i], 16) != 0;
            }
            printf("  %-26s %s: %zu of %zu pixels hit; %zu hit records and %zu pixels differ from the scene at 0\n",
                   nm, mode ? "colour" : "depth", hit, n, differ, px);
            CHECKF(hit >= 200 && differ == 0 && px == 0,
                   "%s %s: %zu hits; %zu hit records and %zu pixels differ from the scene at 0", nm,
                   mode ? "colour" : "depth", hit, differ, px);
            vx_render_image_free(&a);
            vx_render_image_free(&b);
        }
        /* the pass pipeline, a point light placed alike */
        vx_light ln = {.type = VX_LIGHT_POINT, .position = {0.25, 0.5, 0.75}, .color = {1, 1, 1}, .intensity = 0.5};
        vx_light lf = ln;
        for (int k = 0; k < 3; k++) lf.position[k] += T[k];
        vx_frame_desc pn = vx_frame_desc_defaults(), pf;
        pn.base = dn, pn.base.mode = VX_RENDER_COLOR, pn.base.spp = 2, pn.passes = &L, pn.ao_rays = 4, pn.want_ids = true;
        pn.lights = &ln, pn.light_count = 1;
        pf = pn, pf.base = df, pf.base.mode = VX_RENDER_COLOR, pf.base.spp = 2, pf.lights = &lf;
        vx_frame_result a, b;
        REQUIRE(vx_frame_render(ff, &pf, &a, &err) == VX_OK);
        REQUIRE(vx_frame_render(fn, &pn, &b, &err) == VX_OK);
        size_t n = (size_t)a.image.width * a.image.height, px = 0, ids = 0;
        for (size_t i = 0; i < n; i++) {
            px += memcmp(&a.image.pixels[4 * i], &b.image.pixels[4 * i], 16) != 0;
            /* the ids: instance, depth, flags and a hit's cell; the loop's iteration count is a statistic (the
             * BVH's boxes are world floats rounded outward, looser far out) and a miss's cell is not defined
             * (on the H200 the misses' cells differed from the scene at 0 in 790 pixels, everything else equal) */
            const vx_render_hit *x = a.image.hits ? &a.image.hits[i] : NULL, *y = b.image.hits ? &b.image.hits[i] : NULL;
            bool d = x && y &&
                     (x->instance != y->instance ||
                      (y->instance != VX_RENDER_NO_HIT && memcmp(x->cell, y->cell, sizeof x->cell)) ||
                      memcmp(&x->t, &y->t, sizeof x->t) || x->flags != y->flags);
            if (d && ++ids <= 3)
                printf("    pixel %zu: far inst %u cell %u,%u,%u t %.9g flags %x | at 0 inst %u cell %u,%u,%u t %.9g flags %x\n",
                       i, x->instance, x->cell[0], x->cell[1], x->cell[2], x->t, x->flags, y->instance, y->cell[0],
                       y->cell[1], y->cell[2], y->t, y->flags);
        }
        printf("  %-26s passes gbuffer,direct,ao: %zu pixels, %zu ids differ from the scene at 0\n", nm, px, ids);
        CHECKF(px == 0 && ids == 0 && a.image.hits, "%s passes: %zu pixels, %zu ids differ from the scene at 0", nm, px,
               ids);
        vx_render_image_free(&a.image);
        vx_render_image_free(&b.image);
    }
    vx_frame_renderer_destroy(ff);
    vx_frame_renderer_destroy(fn);
    vx_render_scene_destroy(rf);
    vx_render_scene_destroy(rn);
    vx_svo_scene_free(&far);
    vx_svo_scene_free(&near);
}

/* The walk's stack at every level it holds (issue 21, seventeenth and
 * eighteenth sittings): on devices with the file's node form (vx_gpu.nodes_file:
 * CPU devices) trace.comp keeps the walk's stack as selects over the indices
 * that the scene's models can push (TRACE_STACK_SELECTS in
 * shaders/trace_common.glsl): models of depth <= VX_RENDER_EXACT_DEPTH (8;
 * DEEP 0), <= VX_RENDER_REBASE_DEPTH (10; DEEP 1), and the rebased walk's
 * (DEEP 2) up to VX_RENDER_MAX_DEPTH (21: past VX_RENDER_PRECISE_DEPTH the
 * float variant, forced here; the scene's own is the float64 one). The GPU
 * form's kernels keep the array. Sparse random cells over cubes 7 to 21 levels
 * deep (half of them in a cluster, so that rays pop to every level), seen
 * from outside and from inside, on this device and on a second one made with
 * the other node form: the same instance, cell and depth bits on every pixel,
 * and up to 16 levels the CPU reference's cells on all but a few (the float
 * walk's rare misses at a cell's edge, 1 pixel in 4 of these views with either
 * form). A ladder one level short fails the first check (depth 8, 10 or 21);
 * the DEEP 2 ladder sized for 16 levels failed it at 17 to 21 (3-1189 of
 * 6912 pixels a view on lavapipe). */
static void test_stack_levels(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    /* the other form's device (VX_GPU_NODE_FORM is read when a device is made) */
    const char* prev = getenv("VX_GPU_NODE_FORM");
    char* keep = prev ? strdup(prev) : NULL;
    setenv("VX_GPU_NODE_FORM", gpu->nodes_file ? "gpu" : "file", 1);
    vx_gpu* other = NULL;
    const char* skip2 = vx_test_gpu_open((vx_gpu_desc){.logger = &logger}, false, &other);
    if (keep) setenv("VX_GPU_NODE_FORM", keep, 1);
    else unsetenv("VX_GPU_NODE_FORM");
    free(keep);
    REQUIRE(!skip2 && other);
    CHECK(other->nodes_file != gpu->nodes_file);
    for (uint32_t depth = 7; depth <= VX_RENDER_MAX_DEPTH; depth++) {
        uint32_t side = 1u << depth, seed = 4242 + depth, n = 0;
        enum { N = 40000 };
        static uint32_t xyz[3 * (N + 2)];
        static uint8_t pal[N + 2];
        /* the cells in a box of side c <= 1024 at the cube's centre (deeper cubes: two more cells at opposite
         * corners give the model its depth), half of them in a cluster of side c / 8 at its centre (deep paths
         * close together), half anywhere in it */
        uint32_t c = side < 1024 ? side : 1024, blo = side / 2 - c / 2;
        for (uint32_t i = 0; i < N; i++) {
            uint32_t span = i % 2 ? c : c / 8, lo = blo + (i % 2 ? 0 : c / 2 - c / 16);
            for (int k = 0; k < 3; k++) xyz[3 * n + k] = lo + ts_rng(&seed) % span;
            pal[n++] = (uint8_t)(1 + ts_rng(&seed) % 200);
        }
        if (c < side) {
            for (int k = 0; k < 3; k++) xyz[3 * n + k] = 0, xyz[3 * n + 3 + k] = side - 1;
            pal[n] = pal[n + 1] = 7, n += 2;
        }
        uint32_t size[3] = {side, side, side};
        vx_svo_model m;
        REQUIRE(ts_model(&m, size, xyz, pal, n) == VX_OK);
        CHECKF(m.depth == depth, "stack levels: model depth %u, expected %u", m.depth, depth);
        vx_svo_scene s;
        vx_svo_instance in = ts_inst(0, NULL, 0, 0, 0);
        ts_scene(&s, &m, 1, &in, 1);
        vx_render_scene *rs = NULL, *rs2 = NULL;
        vx_error err = {0};
        REQUIRE(vx_render_scene_create(gpu, &s, &rs, &err) == VX_OK);
        REQUIRE(vx_render_scene_create(other, &s, &rs2, &err) == VX_OK);
        /* past VX_RENDER_PRECISE_DEPTH the float variant, forced (the
         * scene's own is the float64 one, whose walk has no ladder) */
        bool forced = depth > VX_RENDER_PRECISE_DEPTH;
        if (forced) vx__render_scene_force_precise(rs, 0), vx__render_scene_force_precise(rs2, 0);
        double f = c, o = blo, mid = o + 0.5 * f; /* the views of the box of cells */
        vx_render_desc views[3] = {cam(o - 0.4 * f, o - 0.7 * f, o + 1.3 * f, mid, mid, mid),
                                   cam(mid + 3, mid - 2, mid + 1, o + 0.1 * f, o + 0.9 * f, o + 0.2 * f),
                                   cam(o + 0.3 * f, o + 0.2 * f, o + 0.45 * f, o + f, o + 0.8 * f, o + 0.6 * f)};
        for (int v = 0; v < 3; v++) {
            char nm[64];
            snprintf(nm, sizeof nm, "stack levels: depth %u view %d", depth, v);
            vx_render_desc d = views[v];
            d.width = 96, d.height = 72, d.want_hits = true;
            vx_render_image a = {0}, b = {0}, ci = {0};
            REQUIRE(vx_render_frame(rs, &d, &a, &err) == VX_OK);
            REQUIRE(vx_render_frame(rs2, &d, &b, &err) == VX_OK);
            REQUIRE(vx_render_cpu(&s, &d, NULL, &ci, &err) == VX_OK);
            size_t npx = (size_t)d.width * d.height, differ = 0;
            for (size_t i = 0; i < npx; i++)
                differ += a.hits[i].instance != b.hits[i].instance || memcmp(a.hits[i].cell, b.hits[i].cell, 12) ||
                          memcmp(&a.hits[i].t, &b.hits[i].t, sizeof a.hits[i].t);
            CHECKF(differ == 0, "%s: %zu of %zu pixels differ between the node forms", nm, differ, npx);
            cmp_result r = compare(nm, &a, &ci);
            CHECKF(r.hits >= 100, "%s: %zu hits", nm, r.hits);
            /* the forced float variant past its depth keeps the float camera's error (a point 2^(depth - 1) cells out
             * rounds to 2^(depth - 24) of a cell): the reference's cells for the record there */
            CHECKF(forced || (r.bad <= 2 && r.depth_bad <= 2), "%s: %zu pixels differ from the CPU reference, %zu depths",
                   nm, r.bad, r.depth_bad);
            vx_render_image_free(&a);
            vx_render_image_free(&b);
            vx_render_image_free(&ci);
        }
        vx_render_scene_destroy(rs);
        vx_render_scene_destroy(rs2);
        vx_svo_scene_free(&s);
    }
    vx_gpu_destroy(other);
}

/* The grid walk over models whose roots are at different levels in one kernel (GRID's constant is the greatest
 * root level; render/grid.h vx__grid_top): a 2^12 model (root level 2: its coarse cells' entries looked up
 * through a node) beside a small one (root level 1: the root holds the bricks), placed as is, rotated and
 * mirrored, seen from inside the big cube's cluster and from outside, each walk against the CPU reference.
 * Then the 2^12 model alone (GRID_EXACT: every root at level 2, the level a constant; one instance: its grid's
 * address and box from the frame block, TRACE_GRID_UBO) and with a mirrored copy (GRID_EXACT through the BVH). */
static void test_grid_mixed_roots(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    enum { N = 6000 };
    static uint32_t xyz[3 * (N + 2)];
    static uint8_t pal[N + 2];
    uint32_t seed = 77, n = 0, side = 1u << 12, lo = 1000;
    /* a cluster of cells 96 wide (sparse bricks, empty level-1 cells and empty level-2 entries between them)
     * and the two corners that give the model its depth */
    for (uint32_t i = 0; i < N; i++) {
        for (int k = 0; k < 3; k++) xyz[3 * n + k] = lo + ts_rng(&seed) % (i % 3 ? 96 : 24) * (i % 3 ? 1 : 4);
        pal[n++] = (uint8_t)(1 + ts_rng(&seed) % 200);
    }
    for (int k = 0; k < 3; k++) xyz[3 * n + k] = 0, xyz[3 * n + 3 + k] = side - 1;
    pal[n] = pal[n + 1] = 9, n += 2;
    uint32_t size[3] = {side, side, side};
    vx_svo_model m[2];
    memset(m, 0, sizeof m);
    REQUIRE(ts_model(&m[0], size, xyz, pal, n) == VX_OK);
    REQUIRE(ts_random_model(&m[1], 20, 14, 9, 40, 78) == VX_OK);
    CHECK(m[0].depth == 12 && m[1].depth <= 10);
    static const double rot[9] = {0, -1, 0, 1, 0, 0, 0, 0, 1}, mir[9] = {1, 0, 0, 0, -1, 0, 0, 0, 1};
    vx_svo_instance in[4] = {ts_inst(0, NULL, 0, 0, 0), ts_inst(1, NULL, lo + 100, lo + 20, lo + 30),
                             ts_inst(1, rot, lo + 40, lo + 110, lo + 60), ts_inst(1, mir, lo - 30, lo + 50, lo + 10)};
    vx_svo_scene s;
    ts_scene(&s, m, 2, in, 4);
    double c = lo + 48;
    vx_render_desc views[3] = {cam(lo - 150, lo - 120, lo + 200, c, c, c), cam(c, c + 7, c - 5, lo, lo + 90, lo + 20),
                               cam(lo + 300, lo + 40, lo - 90, lo + 20, lo + 60, lo + 40)};
    for (int v = 0; v < 3; v++) {
        views[v].width = 64, views[v].height = 48;
        char nm[64];
        snprintf(nm, sizeof nm, "mixed root levels, view %d", v);
        g_want_oct = 1; /* the 2^12 model's root is 64 wide: both models walked with the octant extents */
        check_scene(nm, &s, views[v], 200);
        g_want_oct = -1;
    }
    vx_svo_scene_free(&s);
    for (int copies = 1; copies <= 2; copies++) {
        vx_svo_model big;
        REQUIRE(ts_model(&big, size, xyz, pal, n) == VX_OK);
        /* the copy's cluster beside the first's, not over it (a tie between two instances' cells may go either
         * way between the kernels with and without hits, check_lean_colour) */
        vx_svo_instance bi[2] = {ts_inst(0, NULL, 0, 0, 0), ts_inst(0, mir, 0, 2 * lo + 200, 0)};
        ts_scene(&s, &big, 1, bi, (uint32_t)copies);
        for (int v = 0; v < 3; v++) {
            char nm[64];
            snprintf(nm, sizeof nm, "root level 2 only, %d instance%s, view %d", copies, copies > 1 ? "s" : "", v);
            g_want_oct = 1;
            check_scene(nm, &s, views[v], 200);
            g_want_oct = -1;
        }
        vx_svo_scene_free(&s);
    }
}

/* A grid over its cells' box's cube, not its model's (render/grid.h vx__grid_cube, grid_walk.glsl GRID_CUBE, stop
 * 85): a 2^10 model whose cells lie in a slab 73 x 5 x 62 far from cell 0, with a solid 8^3 block of one record, and
 * a 2^9 model whose cells are a 9^3 group at 290, 17, 250 (its cube 2^4 from 288, 16, 248); the first alone (one
 * instance: the frame block's box) and both with a turned and a mirrored copy (the BVH: the headers' boxes), each
 * walk against the CPU reference, and the grids' memory: a 16^3 root at most, where the model's cube would take a
 * 128^3 one (8 MiB). */
static void grid_cube_models(vx_svo_model m[2]) {
    enum { N = 3000 };
    static uint32_t xyz[3 * (N + 512)];
    static uint8_t pal[N + 512];
    uint32_t seed = 85, n = 0;
    memset(m, 0, 2 * sizeof *m);
    for (uint32_t i = 0; i < N; i++, n++) {
        uint32_t r = ts_rng(&seed);
        xyz[3 * n] = 403 + r % 73, xyz[3 * n + 1] = 130 + (r >> 8) % 5, xyz[3 * n + 2] = 250 + (r >> 12) % 62;
        pal[n] = (uint8_t)(1 + (r >> 20) % 200);
    }
    for (uint32_t j = 0; j < 512; j++, n++)
        xyz[3 * n] = 440 + (j & 7), xyz[3 * n + 1] = 128 + ((j >> 3) & 7), xyz[3 * n + 2] = 296 + (j >> 6), pal[n] = 9;
    REQUIRE(ts_model(&m[0], (uint32_t[3]){1000, 1000, 1000}, xyz, pal, n) == VX_OK);
    n = 0;
    for (uint32_t i = 0; i < 400; i++, n++) {
        uint32_t r = ts_rng(&seed);
        xyz[3 * n] = 290 + r % 9, xyz[3 * n + 1] = 17 + (r >> 8) % 9, xyz[3 * n + 2] = 250 + (r >> 16) % 9;
        pal[n] = (uint8_t)(1 + (r >> 24) % 200);
    }
    REQUIRE(ts_model(&m[1], (uint32_t[3]){300, 300, 300}, xyz, pal, n) == VX_OK);
    CHECK(m[0].depth == 10 && m[1].depth == 9);
}

static void test_grid_cube(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    static const double rot[9] = {0, -1, 0, 1, 0, 0, 0, 0, 1}, mir[9] = {1, 0, 0, 0, -1, 0, 0, 0, 1};
    /* the group's copies beside the slab (x 403-476, y 130-135, z 250-312) and a mirrored slab above it */
    vx_svo_instance in[4] = {ts_inst(0, NULL, 0, 0, 0), ts_inst(1, NULL, 130, 118, 10),
                             ts_inst(1, rot, 470, -160, 20), ts_inst(0, mir, 0, 300, 0)};
    for (int many = 0; many <= 1; many++) {
        vx_svo_model m[2];
        grid_cube_models(m);
        vx_svo_scene s;
        ts_scene(&s, m, 2, in, many ? 4 : 1);
        /* the grids' memory (the scene's layout): the slab's cube 2^7 (a 16^3 root), the group's 2^4 */
        vx_render_scene* rs = NULL;
        vx_error err = {0};
        vx_render_scene_desc sd = {.grid_budget = VX_RENDER_GRID_BUDGET};
        CHECKF(vx_render_scene_create_ex(gpu, &s, &sd, &rs, &err) == VX_OK, "%s", err.msg);
        if (rs) {
            vx_render_layout_info li = {0};
            vx_render_scene_layout(rs, &li);
            CHECKF(li.grid_models == 2 && li.grid_bytes < 256 * 1024, "%u grids, %llu bytes", li.grid_models,
                   (unsigned long long)li.grid_bytes);
            vx_render_scene_destroy(rs);
        }
        /* from above, oblique, and a close-up of the block's edge */
        vx_render_desc views[3] = {cam(441, 230, 282, 440, 132, 280), cam(370, 175, 215, 440, 132, 280),
                                   cam(436.5, 150, 292.5, 441, 130, 299)};
        for (int v = 0; v < 3; v++) {
            views[v].width = 64, views[v].height = 48;
            char nm[64];
            snprintf(nm, sizeof nm, "grid cube, %s, view %d", many ? "4 instances" : "1 instance", v);
            check_scene(nm, &s, views[v], 200);
        }
        vx_svo_scene_free(&s);
    }
}

/* The grid walk's empty 2^3 blocks (grid_walk.glsl: a fine step whose cell's aligned 2^3 block is empty leaves the
 * block in one step, through the planes the cell by cell walk would cross): a sparse 24^3 model (3% of its cells:
 * most blocks of its bricks empty, occupied ones beside them), seen along each axis with pixel centres on cell
 * edges (even ones are block edges, odd ones inside blocks) and on cell centres, directions with +0 and -0
 * components, and along diagonals, as is and mirrored in x and z (the mirrored walk's blocks: stored index xor 7);
 * each walk against the CPU reference. */
static void test_grid_sparse_blocks(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    static const double mir[9] = {-1, 0, 0, 0, 1, 0, 0, 0, -1};
    for (int mirrored = 0; mirrored < 2; mirrored++) {
        vx_svo_model m;
        REQUIRE(ts_random_model(&m, 24, 24, 24, 3, 4343) == VX_OK);
        /* the mirrored copy covers the same [0, 24]^3 */
        vx_svo_instance in = mirrored ? ts_inst(0, mir, 24, 0, 24) : ts_inst(0, NULL, 0, 0, 0);
        vx_svo_scene s;
        ts_scene(&s, &m, 1, &in, 1);
        const double offs[2] = {12.5, 12.0}; /* pixel centres on cell edges, on cell centres */
        for (int o = 0; o < 2; o++)
            for (int z = 0; z < 2; z++)
                for (int axis = 0; axis < 3; axis++) {
                    /* 32 pixels over 32 units: exact pixel centres (a width that is not a power of two makes
                     * them inexact, rays a float step off the planes, which float and double resolve apart) */
                    vx_render_desc d = axis_camera(axis, z ? -60 : 60, z ? 3 : -3, z, 32);
                    double base[3] = {mirrored ? 24 : 0, 0, mirrored ? 24 : 0};
                    for (int k = 0; k < 3; k++) s.instances[0].xform[3 + 4 * k] = base[k] - (k == axis ? 12 : offs[o]);
                    char nm[80];
                    snprintf(nm, sizeof nm, "sparse blocks%s, axis %d%s %s", mirrored ? " mirrored" : "", axis,
                             z ? " negative" : "", o ? "centres" : "edges");
                    check_scene(nm, &s, d, 100);
                }
        for (int k = 0; k < 3; k++) s.instances[0].xform[3 + 4 * k] = k == 1 ? 0 : (mirrored ? 24 : 0);
        /* diagonals: rays through block corners and edges; float and double may resolve those ties apart */
        g_min_share = 0.99;
        const double dirs[][3] = {{1, 1, 1}, {2, 1, 0}, {-1, 2, 1}, {1, -2, -3}};
        for (size_t i = 0; i < sizeof dirs / sizeof dirs[0]; i++) {
            vx_render_desc d = {.mode = VX_RENDER_DEPTH, .width = 41, .height = 41};
            d.camera.set = true, d.camera.ortho = true, d.camera.ortho_height = 40;
            for (int k = 0; k < 3; k++) d.camera.eye[k] = 12 + 50 * dirs[i][k], d.camera.target[k] = 12;
            char nm[80];
            snprintf(nm, sizeof nm, "sparse blocks%s, diagonal %.0f,%.0f,%.0f", mirrored ? " mirrored" : "",
                     dirs[i][0], dirs[i][1], dirs[i][2]);
            check_scene(nm, &s, d, 300);
        }
        g_min_share = 0.9999;
        vx_svo_scene_free(&s);
    }
}

/* The instances scene s's union grid holds (vx__render_scene_grid_union), UINT32_MAX where the scene is not
 * made; the scene made with grids (as on an NVIDIA device) kept in *keep (not NULL) or destroyed. */
static uint32_t union_insts(const vx_svo_scene* s, vx_render_scene** keep) {
    vx_render_scene_desc sd = {.grid_budget = VX_RENDER_GRID_BUDGET};
    vx_render_scene* rs = NULL;
    vx_error err = {0};
    vx_result r = vx_render_scene_create_ex(gpu, s, &sd, &rs, &err);
    CHECKF(r == VX_OK, "the scene with grids: %s", err.msg);
    uint32_t n = r ? UINT32_MAX : vx__render_scene_grid_union(rs, -1);
    if (keep) *keep = rs;
    else vx_render_scene_destroy(rs);
    return n;
}

/* The union grid of a converter's regions (render_scene.c grid_union): instances translated by whole bricks, each
 * in an aligned cube of its own (one model twice, one empty, a region of 8^3 cells beside ones of 16^3), with a
 * common linear part (as is; mirrored and scaled), walked as one grid by trace.comp's kernel of one instance and a
 * hit mapped back to its instance and model cell: each view (perspective, axis views whose pixel centres lie on the
 * regions' shared faces) against the CPU reference, and against each region walked apart (check_scene's walks).
 * Scenes that are not regions (offsets within a brick, overlapping cubes) build none; a moved instance walks the
 * BVH (the union no longer holds) and moved back the union again; an edited model drops it. */
static void test_grid_union(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    static const double mir[9] = {-0.5, 0, 0, 0, 0.5, 0, 0, 0, 0.5};
    for (int lin = 0; lin < 2; lin++) {
        vx_svo_model m[5];
        memset(m, 0, sizeof m);
        REQUIRE(ts_random_model(&m[0], 16, 16, 16, 12, 901) == VX_OK);
        REQUIRE(ts_random_model(&m[1], 16, 11, 16, 20, 902) == VX_OK);
        REQUIRE(ts_random_model(&m[2], 13, 16, 9, 8, 903) == VX_OK);
        REQUIRE(ts_model(&m[3], (uint32_t[3]){16, 16, 16}, NULL, NULL, 0) == VX_OK);
        REQUIRE(ts_random_model(&m[4], 8, 8, 8, 30, 904) == VX_OK);
        const double* lm = lin ? mir : NULL;
        double sc = lin ? 0.5 : 1, sx = lin ? -0.5 : 1; /* world units a cell (x: its sign) */
        /* region origins in cells (whole 16-cubes, the 8^3 region in the upper half of one) */
        static const int org[6][3] = {{0, 0, 0}, {16, 0, 0}, {0, 16, 0}, {16, 16, 0}, {0, 0, 16}, {40, 16, 16}};
        static const uint32_t mod[6] = {0, 1, 2, 0, 3, 4};
        vx_svo_instance in[6];
        for (int i = 0; i < 6; i++)
            in[i] = ts_inst(mod[i], lm, 3 + sx * org[i][0], -2 + sc * org[i][1], 1 + sc * org[i][2]);
        vx_svo_scene s;
        ts_scene(&s, m, 5, in, 6);
        vx_render_scene* rs = NULL;
        vx_error err = {0};
        uint32_t held = union_insts(&s, &rs);
        REQUIRE(rs);
        CHECKF(held == 5, "regions%s: the union holds %u instances, expected 5", lin ? " mirrored" : "", held);
        double lo[3], hi[3], c[3];
        vx_svo_scene_world_bounds(&s, lo, hi);
        for (int k = 0; k < 3; k++) c[k] = (lo[k] + hi[k]) / 2;
        vx_render_desc views[3] = {cam(c[0] - 50 * sc, c[1] - 35 * sc, c[2] + 60 * sc, c[0], c[1], c[2]),
                                   cam(c[0] + 9 * sc, c[1] + 4 * sc, c[2] + 3 * sc, lo[0], c[1], lo[2]),
                                   cam(hi[0] + 30 * sc, lo[1] - 20 * sc, hi[2] + 10 * sc, c[0], c[1], c[2])};
        char nm[96];
        for (int v = 0; v < 3; v++) {
            views[v].width = 64, views[v].height = 48;
            snprintf(nm, sizeof nm, "regions%s, view %d", lin ? " mirrored" : "", v);
            check_scene(nm, &s, views[v], 200);
        }
        /* along each axis, pixel centres on cell edges and on the regions' shared faces (16 cells from the
         * origin), 16 pixels over 16 cells (a power of two: exact centres, as test_grid_sparse_blocks): the
         * window ends 8 cells short of the union's outer faces (a ray in the plane of an instance box's outer
         * face is outside the BVH's box test or inside by the sign of a zero, on the walks without the union
         * too: not this test's subject). Not mirrored and scaled: there the instances' float maps put a ray in a
         * face's plane a rounding off it, and the walks without the union missed 10 of 256 pixels of the z
         * view where the reference hit the far region's face (found here, not mended) */
        for (int axis = 0; axis < 3 && !lin; axis++) {
            vx_render_desc d = {.mode = VX_RENDER_DEPTH, .width = 16, .height = 16};
            d.camera.set = true, d.camera.ortho = true, d.camera.ortho_height = 16 * sc;
            for (int k = 0; k < 3; k++) {
                /* half a cell off a region face: the pixel centres on cell edges, one on the face */
                double e = k == axis ? (axis == 1 ? hi[k] + 40 : lo[k] - 40)
                                     : (k == 0 ? 3 + sx * 16 : k == 1 ? -2 + sc * 16 : 1 + sc * 16) + 0.5 * sc;
                d.camera.eye[k] = e, d.camera.target[k] = k == axis ? c[k] : e;
            }
            d.camera.up[(axis + 1) % 3] = 1;
            snprintf(nm, sizeof nm, "regions%s, axis %d on faces", lin ? " mirrored" : "", axis);
            check_scene(nm, &s, d, 60);
        }
        /* an animation's frame that moves a region by whole regions: the union no longer holds (the BVH walk),
         * then frame 0 again (the union) */
        REQUIRE(vx_svo_scene_alloc_frames(&s, 2, &err) == VX_OK);
        s.frame_instances[1].xform[11] += 16 * sc; /* frame 1, instance 1 */
        vx_render_desc d = views[0];
        d.want_hits = true;
        static const uint32_t order[] = {1, 0};
        for (int k = 0; k < 2; k++) {
            vx_svo_scene v;
            REQUIRE(vx_svo_scene_frame(&s, order[k], &v));
            CHECKF(vx_render_scene_set_frame(rs, &s, order[k], &err) == VX_OK, "frame %u: %s", order[k], err.msg);
            vx_render_image gi = {0}, ci = {0};
            CHECK(vx_render_frame(rs, &d, &gi, &err) == VX_OK);
            CHECK(vx_render_cpu(&v, &d, NULL, &ci, &err) == VX_OK);
            snprintf(nm, sizeof nm, "regions%s, frame %u", lin ? " mirrored" : "", order[k]);
            cmp_result cr = compare(nm, &gi, &ci);
            CHECKF((double)(cr.exact + cr.tie) >= g_min_share * (cr.pixels - cr.ambiguous),
                   "%s: %zu of %zu pixels differ", nm, cr.bad, cr.pixels);
            CHECKF(cr.hits > 150, "%s: %zu hits", nm, cr.hits);
            vx_render_image_free(&gi), vx_render_image_free(&ci);
        }
        /* an edit of a region's model drops the union */
        CHECK(vx_render_scene_update_model(rs, &s, 1, 0, 0, &err) == VX_OK);
        CHECK(vx__render_scene_grid_union(rs, -1) == 0);
        vx_render_scene_destroy(rs);
        vx_svo_scene_free(&s);
    }
    /* deep regions: two of 1024 cells (10 levels, exact: the scene's kernels DEEP 1) whose union is 2048 wide
     * (11 levels: its walk needs the hi/lo origin, DEEP 2, which the union's dispatch compiles in); clusters of
     * cells on both sides of the shared face, seen across it */
    {
        enum { N = 3000 };
        static uint32_t xyz[2][3 * N];
        static uint8_t pal[N];
        uint32_t seed = 31;
        vx_svo_model m[2];
        for (int k = 0; k < 2; k++) {
            for (uint32_t i = 0; i < N; i++) {
                xyz[k][3 * i] = k ? ts_rng(&seed) % 40 : 1023 - ts_rng(&seed) % 40;
                xyz[k][3 * i + 1] = 500 + ts_rng(&seed) % 40, xyz[k][3 * i + 2] = 500 + ts_rng(&seed) % 40;
                pal[i] = (uint8_t)(1 + ts_rng(&seed) % 200);
            }
            REQUIRE(ts_model(&m[k], (uint32_t[3]){1024, 1024, 1024}, xyz[k], pal, N) == VX_OK);
        }
        vx_svo_instance in[2] = {ts_inst(0, NULL, 0, 0, 0), ts_inst(1, NULL, 1024, 0, 0)};
        vx_svo_scene s;
        ts_scene(&s, m, 2, in, 2);
        CHECK(union_insts(&s, NULL) == 2);
        vx_render_desc views[2] = {cam(1024 - 60, 480, 600, 1024, 520, 520), cam(1024 + 15, 560, 470, 1000, 510, 530)};
        for (int v = 0; v < 2; v++) {
            views[v].width = 64, views[v].height = 48;
            char nm[64];
            snprintf(nm, sizeof nm, "deep regions, view %d", v);
            check_scene(nm, &s, views[v], 400);
        }
        vx_svo_scene_free(&s);
    }
    /* not regions: an offset within a brick; two instances' cubes overlapping */
    for (int bad = 0; bad < 2; bad++) {
        vx_svo_model m[2];
        REQUIRE(ts_random_model(&m[0], 16, 16, 16, 12, 911) == VX_OK);
        REQUIRE(ts_random_model(&m[1], 16, 16, 16, 12, 912) == VX_OK);
        vx_svo_instance in[2] = {ts_inst(0, NULL, 0, 0, 0), ts_inst(1, NULL, bad ? 8 : 20, 0, 0)};
        vx_svo_scene s;
        ts_scene(&s, m, 2, in, 2);
        /* within a brick: the union of turned instances (test_grid_union_turned; a CPU device's only) holds both;
         * overlapping cubes whose cells meet: none */
        uint32_t want = bad || !vx_gpu_is_cpu(gpu) ? 0 : 2, got = union_insts(&s, NULL);
        CHECKF(got == want, "%s: the union holds %u instances, expected %u", bad ? "overlapping cubes" : "offset within a brick",
               got, want);
        check_scene(bad ? "overlapping cubes" : "offset within a brick", &s, cam(-30, -40, 50, 16, 8, 8), 100);
        vx_svo_scene_free(&s);
    }
}

/* Each hit pixel's world normal (VX_RENDER_NORMAL) on rs as it walks against the CPU reference's where both hit the
 * same instance and cell: a turned instance's hit axis and side mapped back from the union's frame. */
static void check_normals(const char* name, vx_render_scene* rs, const vx_svo_scene* s, vx_render_desc d) {
    d.mode = VX_RENDER_NORMAL, d.want_hits = true;
    vx_render_image g = {0}, c = {0};
    vx_error err = {0};
    CHECKF(vx_render_frame(rs, &d, &g, &err) == VX_OK, "%s normals: %s", name, err.msg);
    CHECKF(vx_render_cpu(s, &d, NULL, &c, &err) == VX_OK, "%s normals reference: %s", name, err.msg);
    size_t n = (size_t)d.width * d.height, same = 0, differ = 0;
    for (size_t i = 0; g.hits && c.hits && i < n; i++) {
        const vx_render_hit *a = &g.hits[i], *b = &c.hits[i];
        if (a->instance == VX_RENDER_NO_HIT || a->instance != b->instance || memcmp(a->cell, b->cell, sizeof a->cell) ||
            (b->flags & VX_RENDER_HIT_AMBIGUOUS))
            continue;
        same++;
        bool near = true;
        for (int k = 0; k < 3; k++) near &= fabsf(g.pixels[4 * i + k] - c.pixels[4 * i + k]) < 1e-4f;
        if (!near && differ++ < 4)
            fprintf(stderr, "  %s normal pixel %zu: %g %g %g, the reference's %g %g %g\n", name, i, g.pixels[4 * i],
                    g.pixels[4 * i + 1], g.pixels[4 * i + 2], c.pixels[4 * i], c.pixels[4 * i + 1], c.pixels[4 * i + 2]);
    }
    CHECKF(same > 50 && differ == 0, "%s: %zu of %zu hit pixels' normals differ from the reference's", name, differ,
           same);
    vx_render_image_free(&g), vx_render_image_free(&c);
}

/* The union of turned instances (render_scene.c prepare_union_turned): models turned about each axis and mirrored,
 * at cell offsets within bricks (bricks holding cells of two or three instances: the owner lists), one model drawn
 * twice, one empty, as is and in a scaled and mirrored world (every instance's map times a common one); each view
 * against the CPU reference and against the BVH's walk (check_scene), its normals against the reference's, axis
 * views with pixel centres on cell edges. Two instances that hold the same cell build none. Built on a CPU device
 * only; a GPU runs the same views under the BVH. */
static void test_grid_union_turned(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    static const double rots[6][9] = {{1, 0, 0, 0, 1, 0, 0, 0, 1},  {0, -1, 0, 1, 0, 0, 0, 0, 1},
                                      {1, 0, 0, 0, 0, -1, 0, 1, 0}, {0, 0, 1, 0, 1, 0, -1, 0, 0},
                                      {-1, 0, 0, 0, 1, 0, 0, 0, 1}, {0, 1, 0, 1, 0, 0, 0, 0, -1}};
    static const double common[9] = {-0.5, 0, 0, 0, 0, 0.5, 0, 0.5, 0}; /* scaled, mirrored, y and z swapped */
    for (int lin = 0; lin < 2; lin++) {
        vx_svo_model m[4];
        memset(m, 0, sizeof m);
        REQUIRE(ts_random_model(&m[0], 5, 6, 7, 55, 921) == VX_OK);
        REQUIRE(ts_random_model(&m[1], 6, 5, 4, 60, 922) == VX_OK);
        REQUIRE(ts_random_model(&m[2], 7, 7, 3, 50, 923) == VX_OK);
        REQUIRE(ts_model(&m[3], (uint32_t[3]){6, 6, 6}, NULL, NULL, 0) == VX_OK);
        /* 3 rows of 4 boxes, each against the one before it in x, the rows 7 cells apart in y (every turned box at
         * most 7 wide), off the bricks by 1-3 cells: most bricks hold cells of two or more instances (the owner
         * lists) */
        enum { NI = 12 };
        vx_svo_instance in[NI];
        int x = 1;
        for (int i = 0; i < NI; i++) {
            const double* r = rots[i % 6];
            const uint32_t mi = (uint32_t)(i % 4), *sz = m[mi].size;
            double mm[9], t[3];
            if (i % 4 == 0) x = 1 + i / 4;
            int org[3] = {x, 2 + 7 * (i / 4), 1 + i % 3};
            x += (int)(fabs(r[0]) * sz[0] + fabs(r[1]) * sz[1] + fabs(r[2]) * sz[2]); /* its extent in x */
            /* a turned box at its origin: its cells at [org, org + size) turned about the box's corner; the
             * rotation's negative axes moved back by the model's size */
            for (int a = 0; a < 3; a++) {
                t[a] = org[a];
                for (int c = 0; c < 3; c++) t[a] += r[3 * a + c] < 0 ? (double)sz[c] : 0;
            }
            memcpy(mm, r, sizeof mm);
            if (lin) { /* world = common (r p + t) */
                double cm[9], ct[3];
                for (int a = 0; a < 3; a++) {
                    ct[a] = 0;
                    for (int c = 0; c < 3; c++) {
                        cm[3 * a + c] = 0;
                        for (int k = 0; k < 3; k++) cm[3 * a + c] += common[3 * a + k] * r[3 * k + c];
                        ct[a] += common[3 * a + c] * t[c];
                    }
                }
                memcpy(mm, cm, sizeof mm), memcpy(t, ct, sizeof t);
            }
            in[i] = ts_inst(mi, mm, t[0], t[1], t[2]);
        }
        vx_svo_scene s;
        ts_scene(&s, m, 4, in, NI);
        vx_render_scene* rs = NULL;
        uint32_t held = union_insts(&s, &rs);
        REQUIRE(rs);
        /* a GPU keeps the BVH for turned instances (render_scene.c prepare_grids): the same views, no union */
        uint32_t want = vx_gpu_is_cpu(gpu) ? 9 : 0;
        CHECKF(held == want, "turned%s: the union holds %u instances, expected %u", lin ? " scaled" : "", held, want);
        double lo[3], hi[3], c[3], sc = lin ? 0.5 : 1;
        vx_svo_scene_world_bounds(&s, lo, hi);
        for (int k = 0; k < 3; k++) c[k] = (lo[k] + hi[k]) / 2;
        vx_render_desc views[3] = {cam(c[0] - 12 * sc, c[1] - 18 * sc, c[2] + 24 * sc, c[0], c[1], c[2]),
                                   cam(lo[0] - 4 * sc, c[1] + 2 * sc, c[2] + 1 * sc, hi[0], c[1], c[2]),
                                   cam(c[0] + 10 * sc, hi[1] + 12 * sc, lo[2] - 8 * sc, c[0], c[1], c[2])};
        char nm[96];
        /* strict: a hit on another instance's cell at the same t (check_scene's tie between coplanar instances)
         * would hide a wrong owner */
        g_strict = true;
        for (int v = 0; v < 3; v++) {
            views[v].width = 64, views[v].height = 48;
            snprintf(nm, sizeof nm, "turned%s, view %d", lin ? " scaled" : "", v);
            check_scene(nm, &s, views[v], 200);
            check_normals(nm, rs, &s, views[v]);
        }
        g_strict = false;
        /* along each axis, 32 pixels over 32 world units: pixel centres on cell edges (as is) */
        for (int axis = 0; axis < 3 && !lin; axis++) {
            vx_render_desc d = {.mode = VX_RENDER_DEPTH, .width = 32, .height = 32};
            d.camera.set = true, d.camera.ortho = true, d.camera.ortho_height = 32;
            for (int k = 0; k < 3; k++) {
                double e = k == axis ? lo[k] - 40 : floor(c[k]);
                d.camera.eye[k] = e, d.camera.target[k] = k == axis ? c[k] : e;
            }
            d.camera.up[(axis + 1) % 3] = 1;
            snprintf(nm, sizeof nm, "turned, axis %d on cell edges", axis);
            check_scene(nm, &s, d, 40);
        }
        vx_render_scene_destroy(rs);
        vx_svo_scene_free(&s);
    }
    /* one model twice at the same place, turned: their cells meet, no union */
    {
        vx_svo_model m;
        REQUIRE(ts_random_model(&m, 8, 8, 8, 50, 931) == VX_OK);
        vx_svo_instance in[2] = {ts_inst(0, NULL, 0, 0, 0), ts_inst(0, rots[1], 8, 0, 0)};
        vx_svo_scene s;
        ts_scene(&s, &m, 1, in, 2);
        CHECKF(union_insts(&s, NULL) == 0, "turned instances whose cells meet: a union was built");
        check_scene("turned instances whose cells meet", &s, cam(-20, -25, 30, 4, 4, 4), 100);
        vx_svo_scene_free(&s);
    }
}

static void test_empty_and_single(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    vx_svo_scene s;
    ts_scene(&s, NULL, 0, NULL, 0);
    check_scene("empty scene", &s, (vx_render_desc){.mode = VX_RENDER_DEPTH, .width = 16, .height = 16}, 0);
    vx_svo_scene_free(&s);
    vx_svo_model m;
    REQUIRE(ts_model(&m, (uint32_t[3]){4, 4, 4}, NULL, NULL, 0) == VX_OK);
    vx_svo_instance in = ts_inst(0, NULL, 0, 0, 0);
    ts_scene(&s, &m, 1, &in, 1);
    check_scene("empty model", &s, (vx_render_desc){.mode = VX_RENDER_DEPTH, .width = 16, .height = 16}, 0);
    vx_svo_scene_free(&s);
    uint32_t one[3] = {0, 0, 0};
    uint8_t pal = 7;
    REQUIRE(ts_model(&m, (uint32_t[3]){1, 1, 1}, one, &pal, 1) == VX_OK);
    ts_scene(&s, &m, 1, &in, 1);
    check_scene("single voxel", &s, (vx_render_desc){.mode = VX_RENDER_DEPTH, .width = 24, .height = 24}, 100);
    vx_svo_scene_free(&s);
}

/* Many instances through the BVH, some sharing a model. */
static void test_many_instances(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    vx_svo_model m[2];
    REQUIRE(ts_random_model(&m[0], 5, 6, 7, 40, 11) == VX_OK);
    REQUIRE(ts_random_model(&m[1], 9, 3, 4, 50, 12) == VX_OK);
    vx_svo_instance in[60];
    uint32_t seed = 5;
    static const double rots[4][9] = {{1, 0, 0, 0, 1, 0, 0, 0, 1}, {0, -1, 0, 1, 0, 0, 0, 0, 1},
                                      {-1, 0, 0, 0, 1, 0, 0, 0, 1}, {0, 0, 1, 0, 1, 0, -1, 0, 0}};
    for (int i = 0; i < 60; i++)
        in[i] = ts_inst(i % 2, rots[i % 4], (double)(ts_rng(&seed) % 40), (double)(ts_rng(&seed) % 40),
                        (double)(ts_rng(&seed) % 10));
    vx_svo_scene s;
    ts_scene(&s, m, 2, in, 60);
    check_scene("60 instances (bvh)", &s, (vx_render_desc){.mode = VX_RENDER_DEPTH, .width = 64, .height = 48}, 400);
    vx_svo_scene_free(&s);
}

/* An animation on the GPU: one scene (the models uploaded once), its
 * frames switched in a scrambled order with vx_render_scene_set_frame; each
 * frame against the CPU reference of that frame alone (its view). */
static void test_frames(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    vx_svo_model m[2];
    REQUIRE(ts_random_model(&m[0], 5, 6, 7, 40, 21) == VX_OK);
    REQUIRE(ts_random_model(&m[1], 9, 3, 4, 50, 22) == VX_OK);
    static const double id[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}, turn[9] = {0, -1, 0, 1, 0, 0, 0, 0, 1};
    vx_svo_instance in[12];
    for (int i = 0; i < 12; i++) in[i] = ts_inst(i % 2, id, (double)(i % 4) * 10, (double)(i / 4) * 10, 0);
    vx_svo_scene s;
    ts_scene(&s, m, 2, in, 12);
    vx_error err = {0};
    REQUIRE(vx_svo_scene_alloc_frames(&s, 4, &err) == VX_OK);
    vx_svo_instance* f1 = s.frame_instances;
    for (int i = 0; i < 12; i++) {
        f1[i].xform[11] += 3;                                  /* frame 1: everything up 3 cells */
        if (i % 3 == 0) f1[12 + i].flags = VX_SVO_INSTANCE_HIDDEN; /* frame 2: a third hidden */
        f1[24 + i].model = 1 - f1[24 + i].model;              /* frame 3: models swapped, */
        if (i < 4) memcpy(&f1[24 + i].xform[0], turn, 3 * sizeof(double)), memcpy(&f1[24 + i].xform[4], turn + 3, 3 * sizeof(double)),
                   memcpy(&f1[24 + i].xform[8], turn + 6, 3 * sizeof(double)); /* and four turned */
    }
    vx_render_desc d = cam(20, -40, 35, 15, 10, 2);
    d.width = 64, d.height = 48, d.want_hits = true;
    vx_render_scene* rs = NULL;
    REQUIRE(vx_render_scene_create(gpu, &s, &rs, &err) == VX_OK);
    static const uint32_t order[] = {2, 0, 3, 1, 3};
    size_t hits[4] = {0};
    for (size_t k = 0; k < sizeof order / sizeof order[0]; k++) {
        uint32_t f = order[k];
        vx_svo_scene v;
        REQUIRE(vx_svo_scene_frame(&s, f, &v));
        CHECKF(vx_render_scene_set_frame(rs, &s, f, &err) == VX_OK, "frame %u: %s", f, err.msg);
        vx_render_image gi = {0}, ci = {0};
        CHECK(vx_render_frame(rs, &d, &gi, &err) == VX_OK);
        CHECK(vx_render_cpu(&v, &d, NULL, &ci, &err) == VX_OK);
        char name[32];
        snprintf(name, sizeof name, "frame %u", f);
        cmp_result c = compare(name, &gi, &ci);
        CHECKF((double)(c.exact + c.tie) >= g_min_share * (c.pixels - c.ambiguous), "%s: %zu of %zu pixels differ", name, c.bad,
               c.pixels);
        CHECKF(c.hits > 200, "%s: %zu hits", name, c.hits);
        hits[f] = c.hits;
        vx_render_image_free(&gi), vx_render_image_free(&ci);
    }
    CHECK(hits[2] < hits[0]); /* hidden instances are not drawn */
    CHECK(vx_render_scene_set_frame(rs, &s, 4, &err) == VX_ERR_INVALID_ARG && strstr(err.msg, "no frame 4"));
    vx_svo_scene other = s;
    other.model_count = 1;
    CHECK(vx_render_scene_set_frame(rs, &other, 1, &err) == VX_ERR_INVALID_ARG && strstr(err.msg, "made with 2"));
    vx_render_scene_destroy(rs);
    CHECK(vx_gpu_validation_errors(gpu) == 0);
    vx_svo_scene_free(&s);
}

/* Rotated and mirrored instances against the same voxels baked into one model. */
static void test_instanced_vs_baked(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    vx_svo_model src;
    REQUIRE(ts_random_model(&src, 6, 5, 4, 45, 77) == VX_OK);
    static const double rots[5][9] = {{1, 0, 0, 0, 1, 0, 0, 0, 1},  {0, -1, 0, 1, 0, 0, 0, 0, 1},
                                      {-1, 0, 0, 0, 1, 0, 0, 0, 1}, {0, 0, 1, 0, -1, 0, 1, 0, 0},
                                      {0, 1, 0, 0, 0, -1, -1, 0, 0}};
    const double ts[5][3] = {{0, 0, 0}, {14, 2, 1}, {20, 9, 0}, {3, 12, 2}, {9, 18, 7}};
    /* bake: every cell v of every instance lands at floor(M (v + 1/2) + t) */
    typedef struct { uint32_t n; uint32_t xyz[6 * 5 * 4 * 5 * 3]; uint8_t pal[6 * 5 * 4 * 5]; } bake_t;
    static bake_t bk;
    bk.n = 0;
    struct dc { bake_t* b; const double* m; const double* t; const uint8_t* pal; } ctx;
    bool cb(void* u, uint32_t x, uint32_t y, uint32_t z, uint32_t a);
    vx_svo_instance in[5];
    for (int i = 0; i < 5; i++) {
        in[i] = ts_inst(0, rots[i], ts[i][0], ts[i][1], ts[i][2]);
        ctx = (struct dc){&bk, rots[i], ts[i], src.palette};
        vx_error err = {0};
        REQUIRE(vx_svo_decode_model(&src, cb, &ctx, &err) == VX_OK);
    }
    int32_t lo[3] = {1 << 30, 1 << 30, 1 << 30}, hi[3] = {-(1 << 30), -(1 << 30), -(1 << 30)};
    for (uint32_t i = 0; i < bk.n; i++)
        for (int k = 0; k < 3; k++) {
            int32_t v = (int32_t)bk.xyz[3 * i + k];
            if (v < lo[k]) lo[k] = v;
            if (v > hi[k]) hi[k] = v;
        }
    for (uint32_t i = 0; i < bk.n; i++)
        for (int k = 0; k < 3; k++) bk.xyz[3 * i + k] = (uint32_t)((int32_t)bk.xyz[3 * i + k] - lo[k]);
    vx_svo_model baked;
    uint32_t bsize[3] = {(uint32_t)(hi[0] - lo[0] + 1), (uint32_t)(hi[1] - lo[1] + 1), (uint32_t)(hi[2] - lo[2] + 1)};
    REQUIRE(ts_model(&baked, bsize, bk.xyz, bk.pal, bk.n) == VX_OK);
    vx_svo_scene si, sb;
    ts_scene(&si, &src, 1, in, 5);
    vx_svo_instance bin = ts_inst(0, NULL, lo[0], lo[1], lo[2]);
    ts_scene(&sb, &baked, 1, &bin, 1);
    vx_error err = {0};
    vx_render_scene *ri = NULL, *rb = NULL;
    REQUIRE(vx_render_scene_create(gpu, &si, &ri, &err) == VX_OK);
    REQUIRE(vx_render_scene_create(gpu, &sb, &rb, &err) == VX_OK);
    for (int mode = 0; mode < 2; mode++) {
        vx_render_desc d = {.mode = mode ? VX_RENDER_DEPTH : VX_RENDER_COLOR, .width = 64, .height = 48};
        vx_render_image a = {0}, b = {0};
        CHECK(vx_render_frame(ri, &d, &a, &err) == VX_OK);
        CHECK(vx_render_frame(rb, &d, &b, &err) == VX_OK);
        size_t n = (size_t)d.width * d.height, diff = 0, hits = 0;
        for (size_t i = 0; a.pixels && b.pixels && i < n; i++) {
            bool same = true;
            for (int k = 0; k < 4; k++) {
                float x = a.pixels[4 * i + k], y = b.pixels[4 * i + k];
                if (mode) same &= (isinf(x) && isinf(y)) || fabsf(x - y) <= 1e-4f * fabsf(y);
                else same &= fabsf(x - y) <= 1.0f / 255;
            }
            if (b.pixels[4 * i + 3] > 0) hits++;
            if (!same) {
                if (diff < 5)
                    fprintf(stderr, "  baked %s pixel %zu: %g %g %g | %g %g %g\n", mode ? "depth" : "color", i,
                            a.pixels[4 * i], a.pixels[4 * i + 1], a.pixels[4 * i + 2], b.pixels[4 * i],
                            b.pixels[4 * i + 1], b.pixels[4 * i + 2]);
                diff++;
            }
        }
        printf("instanced vs baked (%s): %zu pixels, %zu hits, %zu differ\n", mode ? "depth" : "color", n, hits, diff);
        CHECK(hits > 300);
        CHECK((double)diff <= 1e-4 * n);
        vx_render_image_free(&a);
        vx_render_image_free(&b);
    }
    vx_render_scene_destroy(ri);
    vx_render_scene_destroy(rb);
    vx_svo_scene_free(&si);
    vx_svo_scene_free(&sb);
    CHECK(vx_gpu_validation_errors(gpu) == 0);
}

bool cb(void* u, uint32_t x, uint32_t y, uint32_t z, uint32_t a) {
    struct dc { struct { uint32_t n; uint32_t xyz[6 * 5 * 4 * 5 * 3]; uint8_t pal[6 * 5 * 4 * 5]; }* b; const double* m; const double* t; const uint8_t* pal; }* c = u;
    double p[3] = {x + 0.5, y + 0.5, z + 0.5};
    for (int r = 0; r < 3; r++) {
        double g = c->m[3 * r] * p[0] + c->m[3 * r + 1] * p[1] + c->m[3 * r + 2] * p[2] + c->t[r];
        c->b->xyz[3 * c->b->n + r] = (uint32_t)(int32_t)floor(g);
    }
    c->b->pal[c->b->n] = c->pal[a];
    c->b->n++;
    return true;
}

/* Colour modes and LOD run, agree with the reference where they must. */
static void test_modes(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    vx_svo_scene s;
    random_scene(&s, NULL, 0, 0, 0, 30);
    vx_error err = {0};
    vx_render_scene* rs = NULL;
    REQUIRE(vx_render_scene_create(gpu, &s, &rs, &err) == VX_OK);
    vx__render_scene_force_precise(rs, g_force);
    for (int mode = 0; mode < VX_RENDER_MODE_NUM; mode++) {
        if (mode == VX_RENDER_ITERATIONS) continue; /* step counts differ by design */
        vx_render_desc d = {.mode = (vx_render_mode)mode, .width = 32, .height = 24};
        vx_render_image g = {0}, c = {0};
        CHECK(vx_render_frame(rs, &d, &g, &err) == VX_OK);
        CHECK(vx_render_cpu(&s, &d, NULL, &c, &err) == VX_OK);
        size_t n = 32 * 24, diff = 0;
        for (size_t i = 0; g.pixels && c.pixels && i < 4 * n; i++) {
            float x = g.pixels[i], y = c.pixels[i];
            if (!((isinf(x) && isinf(y)) || fabsf(x - y) <= 2e-3f * fmaxf(1, fabsf(y)))) diff++;
        }
        printf("mode %-10s: %zu of %zu values differ\n", vx_render_mode_name((vx_render_mode)mode), diff, 4 * n);
        CHECK(diff <= 4 * n / 200); /* shadow acne at edges may differ in a few */
        vx_render_image_free(&g);
        vx_render_image_free(&c);
    }
    /* LOD: every pixel hit with lod must also be hit without (coarse nodes
     * only cover more), and nothing crashes at large thresholds */
    vx_render_desc d = {.mode = VX_RENDER_DEPTH, .width = 32, .height = 24, .lod = true, .lod_pixels = 8};
    vx_render_image a = {0}, b = {0};
    CHECK(vx_render_frame(rs, &d, &a, &err) == VX_OK);
    d.lod = false;
    CHECK(vx_render_frame(rs, &d, &b, &err) == VX_OK);
    size_t lost = 0;
    for (size_t i = 0; a.pixels && b.pixels && i < 32 * 24; i++)
        if (b.pixels[4 * i + 3] > 0 && !(a.pixels[4 * i + 3] > 0)) lost++;
    CHECK(lost == 0);
    vx_render_image_free(&a);
    vx_render_image_free(&b);
    vx_render_scene_destroy(rs);
    vx_svo_scene_free(&s);
    CHECK(vx_gpu_validation_errors(gpu) == 0);
}

/* The screen cull (trace.comp traces the pixels whose rays can meet the
 * scene's box, a second pass writes the others' misses): the same bits as
 * without it, pixels and hit records, in every mode, for cameras far, near,
 * inside, looking away and orthographic, one instance and several (the BVH; a grid of 30 instances, whose
 * primary rays start the BVH walk at their screen tile's node), in depth, colour (shadow rays) and
 * iterations (a miss's count), two samples a pixel too. */
static void test_screen_cull(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    vx_svo_model m[2];
    REQUIRE(ts_random_model(&m[0], 9, 7, 5, 35, 21) == VX_OK);
    REQUIRE(ts_random_model(&m[1], 4, 6, 3, 50, 22) == VX_OK);
    static const double rot[9] = {0.6, -0.8, 0, 0.8, 0.6, 0, 0, 0, 1};
    vx_svo_instance in[3] = {ts_inst(0, rot, 3, 1, 0), ts_inst(1, NULL, -9, 4, 2), ts_inst(1, rot, 6, -8, -3)};
    /* scene 2: a grid of 30 instances, whose BVH's tiles start below the root (vx__frame_tiles) */
    vx_svo_instance grid[30];
    for (int i = 0; i < 30; i++)
        grid[i] = ts_inst(i % 2, i % 3 ? NULL : rot, 12.0 * (i % 5), 10.0 * ((i / 5) % 3), 9.0 * (i / 15));
    vx_svo_scene sc[3];
    vx_svo_model m1, mg[2];
    REQUIRE(ts_random_model(&m1, 9, 7, 5, 35, 21) == VX_OK);
    REQUIRE(ts_random_model(&mg[0], 9, 7, 5, 35, 21) == VX_OK);
    REQUIRE(ts_random_model(&mg[1], 4, 6, 3, 50, 22) == VX_OK);
    ts_scene(&sc[0], &m1, 1, in, 1);
    ts_scene(&sc[1], m, 2, in, 3);
    ts_scene(&sc[2], mg, 2, grid, 30);
    uint32_t seed = 77;
    size_t frames = 0, culled = 0, differ = 0;
    for (int si = 0; si < 3; si++) {
        vx_error err = {0};
        vx_render_scene* rs = NULL;
        REQUIRE(vx_render_scene_create(gpu, &sc[si], &rs, &err) == VX_OK);
        double lo[3], hi[3], ctr[3], rad = 0;
        vx_svo_scene_world_bounds(&sc[si], lo, hi);
        for (int k = 0; k < 3; k++) ctr[k] = 0.5 * (lo[k] + hi[k]), rad += 0.25 * (hi[k] - lo[k]) * (hi[k] - lo[k]);
        rad = sqrt(rad);
        for (int view = 0; view < 6; view++) {
            int kind = view % 5; /* far, near, inside, away, orthographic */
            double dist = rad * (kind == 1 ? 1.3 : kind == 2 ? 0.1 : 2.5 + view);
            double dir[3], dl = 0;
            for (int k = 0; k < 3; k++) dir[k] = (double)(ts_rng(&seed) % 2001) - 1000, dl += dir[k] * dir[k];
            dl = sqrt(dl);
            vx_render_desc d = {.width = 61, .height = 43, .want_hits = true};
            d.camera.set = true, d.camera.ortho = kind == 4, d.camera.ortho_height = 1.5 * rad;
            for (int k = 0; k < 3; k++) {
                d.camera.eye[k] = ctr[k] + dir[k] / dl * dist;
                d.camera.target[k] = kind == 3 ? 2 * d.camera.eye[k] - ctr[k] : ctr[k] + 0.3 * rad * (k == view % 3);
            }
            /* depth, colour (shadow rays), iterations (a miss's count), and depth with two samples a pixel */
            static const vx_render_mode modes[4] = {VX_RENDER_DEPTH, VX_RENDER_COLOR, VX_RENDER_ITERATIONS, VX_RENDER_DEPTH};
            for (int mi = 0; mi < 4; mi++) {
                if (mi == 3 && view != 5) continue;
                d.mode = modes[mi];
                d.spp = mi == 3 ? 2 : 1;
                /* a first colour frame with a light builds the sun's depth map for the next ones (whose shadow
                 * records then differ): one frame before the three */
                vx_render_image a[2] = {{0}};
                vx__render_scene_trace_variant(rs, 0);
                CHECK(vx_render_frame(rs, &d, &a[0], &err) == VX_OK);
                vx_render_image_free(&a[0]);
                for (int c = 0; c < 2; c++) {
                    vx__render_scene_trace_variant(rs, c);
                    CHECK(vx_render_frame(rs, &d, &a[c], &err) == VX_OK);
                }
                uint64_t tp;
                culled += vx__render_scene_traced(rs, &tp);
                frames++;
                size_t n = (size_t)d.width * d.height;
                for (int c = 1; c < 2; c++) {
                    if (!a[0].pixels || !a[c].pixels || !a[0].hits || !a[c].hits) {
                        differ++;
                        continue;
                    }
                    size_t dp = 0, dh = 0;
                    for (size_t i = 0; i < n; i++) {
                        dp += memcmp(&a[0].pixels[4 * i], &a[c].pixels[4 * i], 4 * sizeof(float)) != 0;
                        const vx_render_hit *x = &a[0].hits[i], *y = &a[c].hits[i];
                        dh += memcmp(x, y, sizeof *x) != 0;
                    }
                    if (dp || dh)
                        printf("screen cull %d: scene %d view %d mode %s: %zu pixels and %zu hits differ\n", c, si, view,
                               vx_render_mode_name(d.mode), dp, dh);
                    differ += dp + dh;
                }
                for (int c = 0; c < 2; c++) vx_render_image_free(&a[c]);
            }
        }
        vx__render_scene_trace_variant(rs, -1);
        vx_render_scene_destroy(rs);
    }
    printf("screen cull: %zu frames, %zu culled, %zu values differ\n", frames, culled, differ);
    CHECK(differ == 0);
    CHECK(culled * 2 >= frames); /* the far, away and orthographic views cull */
    vx_svo_scene_free(&sc[0]);
    vx_svo_scene_free(&sc[1]);
    vx_svo_scene_free(&sc[2]);
    CHECK(vx_gpu_validation_errors(gpu) == 0);
}

int main(void) {
    /* The loader unloads the driver and layer at vkDestroyInstance; pinning
     * them keeps their frames symbolised, so tests/render/lsan.supp can name
     * exactly these libraries (their internal caches are never freed). */
    /* validation on when the layer is installed */
    gpu_skip = vx_test_gpu_open((vx_gpu_desc){.logger = &logger}, true, &gpu);
    RUN(test_empty_and_single);
    RUN(test_grid_mixed_roots);
    RUN(test_grid_cube);
    RUN(test_grid_sparse_blocks);
    RUN(test_grid_union);
    RUN(test_grid_union_turned);
    RUN(test_axis_rays_on_edges);
    RUN(test_diagonal_edges_corners);
    RUN(test_ray_origins);
    RUN(test_eye_inside);
    RUN(test_grazing);
    RUN(test_transforms);
    RUN(test_float_range);
    RUN(test_far_origin);
    RUN(test_deep_octrees);
    RUN(test_deep_float);
    RUN(test_deep_without_float64);
    RUN(test_precise_variant);
    RUN(test_many_instances);
    RUN(test_far_pointers);
    RUN(test_stack_levels);
    RUN(test_instanced_vs_baked);
    RUN(test_frames);
    RUN(test_modes);
    RUN(test_screen_cull);
    RUN(test_path_start);
    RUN(test_path_start_deep);
    RUN(test_corpus);
    if (gpu) {
        CHECKF(vx_gpu_validation_errors(gpu) == 0, "%u validation errors", vx_gpu_validation_errors(gpu));
        vx_gpu_destroy(gpu);
    }
    return vx_test_finish();
}
