/* tests/render/test_compact_gpu.c - the compact layout's trace kernel
 * (shaders/trace_compact.comp, render/compact_gpu.c) against today's kernel
 * (trace.comp over the .svo node words, vx_render_frame) on the same render
 * scene: every pixel of several views must hold the same instance, cell, t
 * (its bits) and colour, in the albedo mode (the colour decoded from the
 * attribute blocks) and the shaded one (shadow rays through the DAG).
 * The same views from a render scene that chose the compact layout itself
 * (vx_render_scene_create_ex, AUTO under a budget below the plain layout's
 * bytes; also the depth mode at 2 spp) must equal trace.comp's too.
 * Scenes: generated palette and RGBA models (rotated and shifted instances,
 * a model 10 levels deep: the exact-t rule of trace.comp's DEEP 1 kernel;
 * models of 11 and 13 levels: its two-frame walk, DEEP 2),
 * the corpus .vox scenes and, with the mesh converter, DamagedHelmet at 128.
 * The plain scenes walk their octrees (grid_budget VX_RENDER_NO_GRID): the grid
 * walk (render/grid.h) finds the same cells but takes a hit's t from the cell's
 * entry planes, not from the walk's crossing times, so its bits may differ in the
 * last place (test_render_gpu checks it against the CPU reference). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "convert/convert.h"
#include "render/compact.h"
#include "render/render_internal.h" /* white-box: the frame block's start records (vx__gpu_frame, vx__render_scene_paths) */
#include "tests/gpu_test.h"
#include "tests/render/scenes.h"
#include "tests/test.h"
#include "tests/test_vox.h"
#ifdef VX_TEST_HAVE_MESH
#include "convert/mesh.h"
#endif

static vx_gpu* gpu;
static const char* gpu_skip;

/* The pixels of b that differ from a (instance, colour; cell and t bits where hit). */
static uint32_t differ(const vx_render_image* a, const vx_render_image* b, const char* name, const char* what, int view,
                       uint32_t* hits_out) {
    uint32_t wrong = 0, hits = 0;
    for (size_t i = 0; i < (size_t)a->width * a->height; i++) {
        const vx_render_hit *x = &a->hits[i], *y = &b->hits[i];
        bool same = x->instance == y->instance && !memcmp(&a->pixels[4 * i], &b->pixels[4 * i], 16);
        if (x->instance != VX_RENDER_NO_HIT) {
            hits++;
            same = same && !memcmp(x->cell, y->cell, sizeof x->cell) && !memcmp(&x->t, &y->t, sizeof x->t);
        }
        if (!same && wrong++ < 3)
            fprintf(stderr,
                    "  %s view %d pixel %zu: trace.comp instance %u cell (%u %u %u) t %.9g rgb %.4f %.4f %.4f;"
                    " %s %u (%u %u %u) t %.9g rgb %.4f %.4f %.4f\n",
                    name, view, i, x->instance, x->cell[0], x->cell[1], x->cell[2], x->t, a->pixels[4 * i],
                    a->pixels[4 * i + 1], a->pixels[4 * i + 2], what, y->instance, y->cell[0], y->cell[1], y->cell[2],
                    y->t, b->pixels[4 * i], b->pixels[4 * i + 1], b->pixels[4 * i + 2]);
    }
    if (hits_out) *hits_out = hits;
    return wrong;
}

/* Compares both kernels on views of s: trace.comp on a render scene forced
 * to the plain layout against trace_compact.comp beside it
 * (vx_compact_gpu_frame) and against the render scene that AUTO puts in the
 * compact layout under a budget below the plain layout's bytes (the
 * renderer's own choice, vx_render_frame); returns the pixels hit. */
static uint64_t compare(const vx_svo_scene* s, const char* name, uint32_t w, uint32_t h) {
    vx_error err = {0};
    vx_render_scene *rs = NULL, *rsc = NULL;
    vx_compact_scene c;
    vx_compact_gpu *cg = NULL, *cg2 = NULL; /* the render scene's brick form, the other one */
    vx_result r = vx_render_scene_create_ex(gpu, s, &(vx_render_scene_desc){.layout = VX_RENDER_LAYOUT_PLAIN, .grid_budget = VX_RENDER_NO_GRID}, &rs, &err);
    CHECKF(r == VX_OK, "%s: %s", name, err.msg);
    if (r) return 0;
    vx_render_layout_info lp, lc;
    vx_render_scene_layout(rs, &lp);
    CHECK(lp.layout == VX_RENDER_LAYOUT_PLAIN && lp.bytes == lp.plain_bytes && lp.plain_bytes > 0);
    {
        r = vx_render_scene_create_ex(gpu, s, &(vx_render_scene_desc){.memory_budget = lp.plain_bytes - 1}, &rsc, &err);
        CHECKF(r == VX_OK, "%s: compact render scene: %s", name, err.msg);
    }
    if (!r) {
        vx_render_scene_layout(rsc, &lc);
        if (lc.pages) {
            /* the compact layout exceeds that budget too, so AUTO paged it
             * (tests/render/test_compact_page.c): here the whole layout */
            CHECKF(lc.layout == VX_RENDER_LAYOUT_COMPACT && lc.compact_bytes > lc.budget && lc.bytes <= lc.budget,
                   "%s: paged, %llu bytes, the whole layout %llu", name, (unsigned long long)lc.bytes,
                   (unsigned long long)lc.compact_bytes);
            vx_render_scene_destroy(rsc);
            rsc = NULL;
            r = vx_render_scene_create_ex(gpu, s,
                                          &(vx_render_scene_desc){.layout = VX_RENDER_LAYOUT_COMPACT,
                                                                  .memory_budget = lc.compact_bytes},
                                          &rsc, &err);
            CHECKF(r == VX_OK, "%s: the whole compact layout: %s", name, err.msg);
            if (rsc) vx_render_scene_layout(rsc, &lc);
            lc.budget = lp.plain_bytes - 1; /* as asked of AUTO above */
        }
    }
    for (int k = 0; !r && k < 2; k++) {
        /* both brick forms (render/compact.h), the render scene's first */
        uint32_t bricks = (k == 0) == lc.brick_dict ? VX_COMPACT_BRICKS_DICT : VX_COMPACT_BRICKS_INLINE;
        r = vx_compact_build(&(vx_compact_desc){.bricks = bricks}, s, &c, &err);
        CHECKF(r == VX_OK, "%s: %s", name, err.msg);
        if (!r) {
            r = vx_compact_gpu_create(rs, s, &c, k ? &cg2 : &cg, &err);
            CHECKF(r == VX_OK, "%s: %s", name, err.msg);
            vx_compact_free(&c);
        }
    }
    if (!r) {
        CHECKF(lc.layout == VX_RENDER_LAYOUT_COMPACT && lc.pages == 0 && lc.bytes == vx_compact_gpu_bytes(cg) &&
                   lc.plain_bytes == lp.plain_bytes && lc.budget == lp.plain_bytes - 1 && lc.voxels == lp.voxels,
               "%s: layout %s, %llu bytes (compact %llu), plain %llu", name, vx_render_layout_name(lc.layout),
               (unsigned long long)lc.bytes, (unsigned long long)vx_compact_gpu_bytes(cg),
               (unsigned long long)lc.plain_bytes);
    }
    uint64_t hits_total = 0;
    double lo[3], hi[3];
    vx_svo_scene_world_bounds(s, lo, hi);
    for (int view = 0; !r && view < 5; view++) {
        vx_render_desc d = {.width = w, .height = h, .mode = view == 3 ? VX_RENDER_COLOR : VX_RENDER_ALBEDO,
                            .want_hits = true};
        if (view == 4) d.mode = VX_RENDER_DEPTH, d.spp = 2;
        if (view == 1) d.camera.ortho = true;
        if (view >= 2) {
            d.camera.set = true;
            d.camera.fov = 70;
            for (int k = 0; k < 3; k++) {
                double mid = 0.5 * (lo[k] + hi[k]), ext = hi[k] - lo[k];
                d.camera.target[k] = mid - 0.05 * ext;
                d.camera.eye[k] = mid + (k == 1 ? -0.3 : 0.2) * ext * (view == 3 ? 3 : 1);
            }
        }
        vx_render_image a = {0}, b = {0}, b2 = {0}, b3 = {0};
        vx_result r1 = vx_render_frame(rs, &d, &a, &err);
        CHECKF(r1 == VX_OK, "%s view %d: trace.comp: %s", name, view, err.msg);
        vx_result r2 = r1 ? r1 : vx_compact_gpu_frame(cg, &d, &b, &err);
        CHECKF(r2 == VX_OK, "%s view %d: trace_compact.comp: %s", name, view, err.msg);
        vx_result r3 = r2 ? r2 : vx_render_frame(rsc, &d, &b2, &err);
        CHECKF(r3 == VX_OK, "%s view %d: the compact render scene: %s", name, view, err.msg);
        if (!r3) r3 = vx_compact_gpu_frame(cg2, &d, &b3, &err);
        CHECKF(r3 == VX_OK, "%s view %d: the other brick form: %s", name, view, err.msg);
        if (!r3) {
            uint32_t hits = 0, wrong = differ(&a, &b, name, "compact", view, &hits);
            uint32_t wrong2 = differ(&a, &b2, name, "compact scene", view, NULL);
            uint32_t wrong3 = differ(&a, &b3, name, "compact, other bricks", view, NULL);
            CHECKF(wrong == 0 && wrong2 == 0 && wrong3 == 0, "%s view %d: %u, %u and %u of %u pixels differ", name, view,
                   wrong, wrong2, wrong3, w * h);
            printf("  %-34s view %d: %ux%u, %u pixels hit, %u / %u / %u differ\n", name, view, w, h, hits, wrong, wrong2,
                   wrong3);
            hits_total += hits;
        }
        if (!r3) {
            /* without hits: trace_compact.comp's walk without the iteration guard (as trace.comp's colour kernel) */
            vx_render_image c0 = {0}, c1 = {0};
            vx_render_desc dn = d;
            dn.want_hits = false;
            vx_result q = vx_render_frame(rs, &dn, &c0, &err);
            if (!q) q = vx_compact_gpu_frame(cg, &dn, &c1, &err);
            CHECKF(q == VX_OK, "%s view %d without hits: %s", name, view, err.msg);
            if (!q)
                CHECKF(!memcmp(c0.pixels, c1.pixels, (size_t)w * h * 16), "%s view %d without hits: the pixels differ", name,
                       view);
            vx_render_image_free(&c0);
            vx_render_image_free(&c1);
        }
        vx_render_image_free(&a);
        vx_render_image_free(&b);
        vx_render_image_free(&b2);
        vx_render_image_free(&b3);
    }
    if (rsc) {
        /* what only the plain layout serves is refused, with the reason */
        vx__frame f;
        double sec;
        vx_render_desc d = {.width = 8, .height = 8};
        CHECK(vx__render_dispatch(rsc, &d, false, 1, &f, &sec, &err) == VX_ERR_UNSUPPORTED && strstr(err.msg, "compact"));
        CHECK(vx_render_scene_update_model(rsc, s, 0, 0, 0, &err) == VX_ERR_UNSUPPORTED);
        d.lod = true;
        vx_render_image img = {0};
        CHECK(vx_render_frame(rsc, &d, &img, &err) == VX_ERR_UNSUPPORTED);
    }
    CHECKF(vx_gpu_validation_errors(gpu) == 0, "%s: %u validation errors", name, vx_gpu_validation_errors(gpu));
    vx_compact_gpu_destroy(cg);
    vx_compact_gpu_destroy(cg2);
    vx_render_scene_destroy(rsc);
    vx_render_scene_destroy(rs);
    return hits_total;
}

/* compare() on a scene of model `model` of s alone, one instance at the
 * origin (no BVH); the model stays owned by s */
static uint64_t compare_alone(const vx_svo_scene* s, uint32_t model, const char* name, uint32_t w, uint32_t h) {
    vx_svo_scene s1;
    vx_svo_model only = s->models[model];
    vx_svo_instance i1 = ts_inst(0, NULL, 0, 0, 0);
    ts_scene(&s1, &only, 1, &i1, 1);
    uint64_t hit = compare(&s1, name, w, h);
    s1.models[0] = (vx_svo_model){0};
    vx_svo_scene_free(&s1);
    return hit;
}

/* compare() on a scene of every model of s and one instance, of model
 * `model` (no BVH): the instance's model record is not model 0's (the
 * single-instance kernel reads it from the frame block); the models stay
 * owned by s */
static uint64_t compare_one_of(const vx_svo_scene* s, uint32_t model, const char* name, uint32_t w, uint32_t h) {
    vx_svo_scene s1;
    vx_svo_instance i1 = ts_inst(model, NULL, 0, 0, 0);
    ts_scene(&s1, s->models, s->model_count, &i1, 1);
    uint64_t hit = compare(&s1, name, w, h);
    for (uint32_t i = 0; i < s1.model_count; i++) s1.models[i] = (vx_svo_model){0};
    vx_svo_scene_free(&s1);
    return hit;
}

static void test_generated(void) {
    if (gpu_skip) SKIP(gpu_skip);
    /* palette: sparse, dense, nearly full; RGBA: gradients, noise, 8^3 tiles; one 10 levels deep */
    vx_svo_model m[6];
    REQUIRE(ts_random_model(&m[0], 37, 20, 9, 5, 1) == VX_OK);
    REQUIRE(ts_random_model(&m[1], 24, 24, 24, 50, 2) == VX_OK);
    REQUIRE(ts_random_model(&m[2], 16, 16, 16, 99, 3) == VX_OK);
    size_t n = 0, cap = 64 * 64 * 64;
    uint64_t* keys = malloc(cap * 8);
    uint32_t* rgba = malloc(cap * 4);
    uint8_t* level = calloc(cap, 1);
    REQUIRE(keys && rgba && level);
    uint32_t seed = 7;
    for (uint32_t z = 0; z < 64; z++)
        for (uint32_t y = 0; y < 64; y++)
            for (uint32_t x = 0; x < 64; x++)
                if ((x - 32) * (x - 32) + (y - 32) * (y - 32) + (z - 32) * (z - 32) < 900 && ts_rng(&seed) % 4) {
                    keys[n] = vx_svo_morton(x, y, z);
                    rgba[n++] = x < 40 ? 0xFF000000u | (x * 3) | ((y * 3) << 8) | ((z * 3) << 16) : ts_rng(&seed);
                }
    vx_error err = {0};
    vx_svo_voxels v = {.size = {64, 64, 64}, .count = n, .keys = keys, .attrs = VX_ATTR_RGBA8, .rgba = rgba};
    REQUIRE(vx_svo_build_model(NULL, &v, &m[3], NULL, &err) == VX_OK);
    n = 0;
    for (uint32_t z = 0; z < 64; z += 8)
        for (uint32_t y = 0; y < 64; y += 8)
            for (uint32_t x = 0; x < 64; x += 8)
                if (ts_rng(&seed) % 3 == 0) {
                    keys[n] = vx_svo_morton(x, y, z);
                    level[n] = ts_rng(&seed) % 2 ? 3 : 2;
                    rgba[n++] = 0xFF000000u | (ts_rng(&seed) % 3);
                }
    v = (vx_svo_voxels){.size = {64, 64, 64}, .count = n, .keys = keys, .level = level, .attrs = VX_ATTR_RGBA8, .rgba = rgba};
    REQUIRE(vx_svo_build_model(NULL, &v, &m[4], NULL, &err) == VX_OK);
    free(keys), free(rgba), free(level);
    REQUIRE(ts_random_model(&m[5], 600, 6, 530, 3, 4) == VX_OK);
    REQUIRE(m[5].depth == 10);
    static const double rot[9] = {0.36, -0.48, 0.8, 0.8, 0.6, 0, -0.48, 0.64, 0.6};
    vx_svo_instance in[8];
    for (uint32_t i = 0; i < 5; i++) in[i] = ts_inst(i, i % 2 ? rot : NULL, 80.0 * i, 10.0 * i, 0);
    in[5] = ts_inst(3, NULL, 100, 90, 40);
    in[6] = ts_inst(5, NULL, -100, -20, -300);
    in[7] = ts_inst(4, rot, 200, -60, 80);
    vx_svo_scene s;
    ts_scene(&s, m, 6, in, 8);
    CHECK(compare(&s, "generated (8 instances)", 160, 96) > 160 * 96 / 2);
    {
        /* the default (AUTO, three quarters of the device-local heap): plain for a scene this small */
        vx_render_scene* rs = NULL;
        vx_render_layout_info li;
        REQUIRE(vx_render_scene_create(gpu, &s, &rs, &err) == VX_OK);
        vx_render_scene_layout(rs, &li);
        CHECKF(li.layout == VX_RENDER_LAYOUT_PLAIN && li.budget > li.plain_bytes && li.bytes == li.plain_bytes,
               "layout %s, budget %llu, plain %llu", vx_render_layout_name(li.layout), (unsigned long long)li.budget,
               (unsigned long long)li.plain_bytes);
        vx_render_scene_destroy(rs);
    }
    /* one instance (no BVH): the deep model alone */
    CHECK(compare_alone(&s, 5, "10 levels deep, one instance", 160, 96) > 160 * 96 / 4);
    vx_svo_scene_free(&s);
}

/* s in a render scene forced to the plain layout (trace.comp) and in the
 * compact layout beside it (trace_compact.comp); false, with nothing left
 * behind, where either fails */
static bool plain_and_compact(const vx_svo_scene* s, vx_render_scene** rs, vx_compact_gpu** cg) {
    vx_error err = {0};
    vx_compact_scene c;
    *rs = NULL, *cg = NULL;
    vx_result r = vx_render_scene_create_ex(gpu, s, &(vx_render_scene_desc){.layout = VX_RENDER_LAYOUT_PLAIN, .grid_budget = VX_RENDER_NO_GRID}, rs, &err);
    if (!r && !(r = vx_compact_build(&(vx_compact_desc){0}, s, &c, &err))) {
        r = vx_compact_gpu_create(*rs, s, &c, cg, &err);
        vx_compact_free(&c);
    }
    CHECKF(r == VX_OK, "%s", err.msg);
    if (r) {
        vx_render_scene_destroy(*rs);
        *rs = NULL;
    }
    return r == VX_OK;
}

/* Cameras inside leaf cubes (the block of 16^3 cells at the model's corner
 * made of leaf cubes of 8^3 cells, each of its colour): every ray starts in
 * the cube it hits, whose cell is then the one holding the ray's start, not
 * one on the cube's entry face (trace_compact.comp's `te <= t0` after the
 * walk; untested before issue 18's lean5), so every pixel hits and must
 * hold trace.comp's cell, t and colour, albedo and shaded. */
static void test_inside_leaf(void) {
    if (gpu_skip) SKIP(gpu_skip);
    uint64_t keys[9];
    uint32_t rgba[9];
    uint8_t level[9];
    for (uint32_t i = 0; i < 8; i++) {
        keys[i] = vx_svo_morton(8 * (i & 1), 4 * (i & 2), 2 * (i & 4));
        level[i] = 3;
        rgba[i] = 0xFF000000u | (0x20u + 0x1Fu * i) | ((0xE0u - 0x1Bu * i) << 8) | ((0x11u * i) << 16);
    }
    keys[8] = vx_svo_morton(31, 31, 31), level[8] = 0, rgba[8] = 0xFF0000FFu; /* the model's box: 32 cells a side */
    vx_error err = {0};
    vx_svo_model m;
    vx_svo_voxels v = {.size = {32, 32, 32}, .count = 9, .keys = keys, .level = level, .attrs = VX_ATTR_RGBA8, .rgba = rgba};
    REQUIRE(vx_svo_build_model(NULL, &v, &m, NULL, &err) == VX_OK);
    vx_svo_instance in = ts_inst(0, NULL, 0, 0, 0);
    vx_svo_scene s;
    ts_scene(&s, &m, 1, &in, 1);
    vx_render_scene* rs;
    vx_compact_gpu* cg;
    REQUIRE(plain_and_compact(&s, &rs, &cg));
    double lo[3], hi[3];
    vx_svo_scene_world_bounds(&s, lo, hi);
    /* the eye (fractions of the box; the block is its first half) and the direction */
    static const double eye[4][3] = {{0.23, 0.31, 0.17}, {0.4, 0.12, 0.33}, {0.07, 0.45, 0.26}, {0.3, 0.3, 0.3}};
    static const double dir[4][3] = {{1, 0.2, 0.1}, {-0.3, 1, -0.2}, {0.1, -0.4, 1}, {-1, -0.7, -0.4}};
    for (int view = 0; cg && view < 8; view++) {
        const uint32_t w = 64, h = 48;
        vx_render_desc d = {.width = w, .height = h, .want_hits = true, .mode = view < 4 ? VX_RENDER_ALBEDO : VX_RENDER_COLOR};
        d.camera.set = true;
        d.camera.fov = 70;
        for (int k = 0; k < 3; k++) {
            d.camera.eye[k] = lo[k] + eye[view & 3][k] * (hi[k] - lo[k]);
            d.camera.target[k] = d.camera.eye[k] + dir[view & 3][k];
        }
        vx_render_image a = {0}, b = {0};
        vx_result r = vx_render_frame(rs, &d, &a, &err);
        if (!r) r = vx_compact_gpu_frame(cg, &d, &b, &err);
        CHECKF(r == VX_OK, "view %d: %s", view, err.msg);
        if (!r) {
            uint32_t hits = 0, wrong = differ(&a, &b, "inside a leaf cube", "compact", view, &hits);
            CHECKF(wrong == 0 && hits == w * h, "view %d: %u of %u pixels differ, %u hit", view, wrong, w * h, hits);
            printf("  inside a leaf cube view %d: %u pixels hit, %u differ\n", view, hits, wrong);
        }
        vx_render_image_free(&a);
        vx_render_image_free(&b);
    }
    CHECKF(vx_gpu_validation_errors(gpu) == 0, "%u validation errors", vx_gpu_validation_errors(gpu));
    vx_compact_gpu_destroy(cg);
    vx_render_scene_destroy(rs);
    vx_svo_scene_free(&s);
}

/* The compact layout's field seams (ts_seam_model: the largest counts of
 * the bricks' index words and of the level-4 ranks) in the kernel, beside
 * a rotated copy. */
static void test_seams(void) {
    if (gpu_skip) SKIP(gpu_skip);
    vx_svo_model m;
    REQUIRE(ts_seam_model(&m) == VX_OK);
    static const double rot[9] = {0.36, -0.48, 0.8, 0.8, 0.6, 0, -0.48, 0.64, 0.6};
    vx_svo_instance in[2] = {ts_inst(0, NULL, 0, 0, 0), ts_inst(0, rot, 40, 5, 0)};
    vx_svo_scene s;
    ts_scene(&s, &m, 1, in, 2);
    CHECK(compare(&s, "brick seams", 96, 64) > 96 * 64 / 8);
    vx_svo_scene_free(&s);
}

/* A height field of RGBA cells (a gradient with noise: delta blocks),
 * sx by sz cells, y = h(x, z) and the cell below it. */
static vx_result height_model(vx_svo_model* m, uint32_t sx, uint32_t sy, uint32_t sz, uint32_t seed) {
    size_t n = 0, cap = (size_t)sx * sz * 2;
    uint64_t* keys = malloc(cap * 8);
    uint32_t* rgba = malloc(cap * 4);
    vx_result r = VX_ERR_NOMEM;
    if (keys && rgba) {
        for (uint32_t z = 0; z < sz; z++)
            for (uint32_t x = 0; x < sx; x++) {
                uint32_t y = (uint32_t)((sy - 2) * (0.5 + 0.25 * sin(x * 0.013) * cos(z * 0.021))) + ts_rng(&seed) % 2;
                for (uint32_t k = 0; k < 2; k++) {
                    keys[n] = vx_svo_morton(x, y + k, z);
                    rgba[n++] = 0xFF000000u | ((x >> 3) & 0xFFu) | (((z >> 3) & 0xFFu) << 8) | ((y & 0xF0u) << 16) |
                                (ts_rng(&seed) & 0x030303u);
                }
            }
        vx_error err = {0};
        vx_svo_voxels v = {.size = {sx, sy, sz}, .count = n, .keys = keys, .attrs = VX_ATTR_RGBA8, .rgba = rgba};
        r = vx_svo_build_model(NULL, &v, m, NULL, &err);
    }
    free(keys);
    free(rgba);
    return r;
}

/* Models deeper than VX_RENDER_REBASE_DEPTH: trace.comp's DEEP 2 kernel
 * walks them in two frames (the lower one at depth - VX_RENDER_FRAME_LEVELS)
 * with the hi/lo origin; the compact kernel must give its cells, t bits and
 * colours on every pixel. Height fields of 11 and 13 levels (the second a
 * long band, so that rays cross many rebased nodes), instances rotated and
 * shifted off the origin. */
static void test_deep(void) {
    if (gpu_skip) SKIP(gpu_skip);
    vx_svo_model m[2];
    REQUIRE(height_model(&m[0], 1200, 64, 1100, 11) == VX_OK);
    REQUIRE(height_model(&m[1], 4200, 40, 160, 13) == VX_OK);
    REQUIRE(m[0].depth == 11 && m[1].depth == 13);
    static const double rot[9] = {0.36, -0.48, 0.8, 0.8, 0.6, 0, -0.48, 0.64, 0.6};
    vx_svo_instance in[3] = {ts_inst(0, NULL, 0, 0, 0), ts_inst(1, NULL, -1500, 30, 500),
                             ts_inst(0, rot, 200, 300, 100)};
    vx_svo_scene s;
    ts_scene(&s, m, 2, in, 3);
    CHECK(compare(&s, "11 and 13 levels deep", 160, 96) > 160 * 96 / 4);
    CHECK(compare_alone(&s, 1, "13 levels deep, one instance", 160, 96) > 160 * 96 / 8);
    vx_svo_scene_free(&s);
}

/* The start table (render/compact_gpu.c: the descent to a cell's colour
 * starts at the node of its level-K cube): a 128^3 model whose full leaf
 * cubes of levels 3 to 6 hold many level-K cubes each (the table's entries
 * inside a leaf: the index of their first cell), between cells of noise
 * colours; the same cells with few colours (blocks of distinct values),
 * one instance and a rotated one. */
static void test_start_table(void) {
    if (gpu_skip) SKIP(gpu_skip);
    size_t n = 0, cap = 40000;
    uint64_t* keys = malloc(cap * 8);
    uint32_t* rgba = malloc(cap * 4);
    uint8_t* level = calloc(cap, 1);
    REQUIRE(keys && rgba && level);
    uint32_t seed = 11;
    /* a 64^3 leaf (level 6) at the origin, 32^3 and 16^3 ones beside it, 8^3 ones on a grid */
    static const uint32_t cubes[][4] = {{0, 0, 0, 6}, {64, 0, 0, 5}, {96, 32, 0, 5}, {64, 64, 64, 4}, {112, 0, 96, 4}};
    for (size_t i = 0; i < sizeof cubes / sizeof cubes[0]; i++) {
        keys[n] = vx_svo_morton(cubes[i][0], cubes[i][1], cubes[i][2]);
        level[n] = (uint8_t)cubes[i][3];
        rgba[n++] = 0xFF000000u | ts_rng(&seed);
    }
    for (uint32_t z = 64; z < 128; z += 8)
        for (uint32_t x = 0; x < 64; x += 8)
            if (ts_rng(&seed) % 3 == 0) {
                keys[n] = vx_svo_morton(x, 96, z);
                level[n] = 3;
                rgba[n++] = 0xFF000000u | ts_rng(&seed);
            }
    while (n < 30000) {
        uint32_t x = ts_rng(&seed) % 128, y = 64 + ts_rng(&seed) % 64, z = ts_rng(&seed) % 64;
        keys[n] = vx_svo_morton(x, y, z);
        level[n] = 0;
        rgba[n++] = 0xFF000000u | (ts_rng(&seed) & 0x3F3F3Fu);
    }
    vx_error err = {0};
    vx_svo_model m[2];
    vx_svo_voxels v = {.size = {128, 128, 128}, .count = n, .keys = keys, .level = level, .attrs = VX_ATTR_RGBA8, .rgba = rgba};
    REQUIRE(vx_svo_build_model(NULL, &v, &m[0], NULL, &err) == VX_OK);
    for (size_t i = 0; i < n; i++) rgba[i] = 0xFF000000u | (ts_rng(&seed) % 9) * 0x1C1C1Cu; /* blocks of few values */
    REQUIRE(vx_svo_build_model(NULL, &v, &m[1], NULL, &err) == VX_OK);
    free(keys), free(rgba), free(level);
    REQUIRE(m[0].depth == 7);
    static const double rot[9] = {0.36, -0.48, 0.8, 0.8, 0.6, 0, -0.48, 0.64, 0.6};
    vx_svo_instance in[2] = {ts_inst(0, NULL, 0, 0, 0), ts_inst(1, rot, 160, 10, 0)};
    vx_svo_scene s;
    ts_scene(&s, m, 2, in, 2);
    CHECK(compare(&s, "start table, leaf cubes", 128, 96) > 128 * 96 / 4);
    CHECK(compare_alone(&s, 0, "start table, one instance", 128, 96) > 128 * 96 / 4);
    /* the two models share their geometry, not their colours */
    CHECK(compare_one_of(&s, 1, "start table, one instance of model 1", 128, 96) > 128 * 96 / 4);
    vx_svo_scene_free(&s);
}

/* Start-table entries whose level-K cube holds one value (compact_gpu.c
 * tab_uniform): the colour is the entry's value, with no descent or decode.
 * A 128^3 model (K = 3) of sparse cells, one colour for x < 48, another for
 * 48 <= x < 96 with a third sprinkled into some of its cubes (those keep the
 * descent), noise-coloured cells for x >= 96; as an RGBA model and as a
 * palette one. Every pixel must be trace.comp's, and entries must be marked
 * (the kernel tests for them where a quarter of the filled ones are), not
 * all. (test_start_table's models, of noise, have none marked.) */
static void test_uniform_cubes(void) {
    if (gpu_skip) SKIP(gpu_skip);
    size_t n = 0, cap = 1u << 17;
    uint64_t* keys = malloc(cap * 8);
    uint32_t* rgba = malloc(cap * 4);
    uint8_t* pal = malloc(cap);
    REQUIRE(keys && rgba && pal);
    uint32_t seed = 23;
    for (uint32_t z = 0; z < 128; z++)
        for (uint32_t y = 0; y < 128; y++)
            for (uint32_t x = 0; x < 128 && n < cap; x++) {
                if (ts_rng(&seed) % 100 >= 4) continue;
                keys[n] = vx_svo_morton(x, y, z);
                uint32_t r = ts_rng(&seed);
                uint8_t p = x < 48 ? 1 : x < 96 ? (r % 50 == 0 ? 3 : 2) : (uint8_t)(4 + r % 200);
                pal[n] = p;
                rgba[n++] = 0xFF000000u | (uint32_t)p * 0x010305u;
            }
    vx_error err = {0};
    vx_svo_model m[2];
    vx_svo_voxels v = {.size = {128, 128, 128}, .count = n, .keys = keys, .attrs = VX_ATTR_RGBA8, .rgba = rgba};
    REQUIRE(vx_svo_build_model(NULL, &v, &m[0], NULL, &err) == VX_OK);
    v.attrs = VX_ATTR_PALETTE, v.rgba = NULL, v.palette = pal;
    REQUIRE(vx_svo_build_model(NULL, &v, &m[1], NULL, &err) == VX_OK);
    free(keys), free(rgba), free(pal);
    REQUIRE(m[0].depth == 7 && m[1].depth == 7);
    static const double rot[9] = {0.36, -0.48, 0.8, 0.8, 0.6, 0, -0.48, 0.64, 0.6};
    vx_svo_instance in[2] = {ts_inst(0, NULL, 0, 0, 0), ts_inst(1, rot, 160, 10, 0)};
    vx_svo_scene s;
    ts_scene(&s, m, 2, in, 2);
    for (uint32_t k = 0; k < 2; k++) {
        /* the table of model k alone marks some entries, not all */
        vx_svo_scene s1;
        vx_svo_model only = s.models[k];
        vx_svo_instance i1 = ts_inst(0, NULL, 0, 0, 0);
        ts_scene(&s1, &only, 1, &i1, 1);
        vx_render_scene* rs;
        vx_compact_gpu* cg;
        REQUIRE(plain_and_compact(&s1, &rs, &cg));
        uint64_t marked = vx__compact_gpu_uniform_entries(cg), entries = vx__compact_gpu_table_bytes(cg) / 8;
        CHECKF(marked > entries / 4 && marked < entries, "model %u: %llu of %llu entries uniform", k,
               (unsigned long long)marked, (unsigned long long)entries);
        printf("  model %u: %llu of %llu start-table entries uniform\n", k, (unsigned long long)marked,
               (unsigned long long)entries);
        vx_compact_gpu_destroy(cg);
        vx_render_scene_destroy(rs);
        s1.models[0] = (vx_svo_model){0};
        vx_svo_scene_free(&s1);
    }
    CHECK(compare(&s, "uniform cubes", 128, 96) > 128 * 96 / 4);
    CHECK(compare_alone(&s, 0, "uniform cubes, one instance", 128, 96) > 128 * 96 / 4);
    CHECK(compare_alone(&s, 1, "uniform cubes, palette", 128, 96) > 128 * 96 / 4);
    vx_svo_scene_free(&s);
}

/* The attribute words past one storage buffer's range (the helmet at 32768^3 has about 6 GB against NVIDIA's
 * 4 GB): a render scene whose range (vx_render_scene_desc.max_buffer_range) is a fraction of them puts them in
 * several buffers and must render every view as the plain layout does; a range below the geometry is refused with
 * the reason, AUTO takes the compact layout where the plain one's words exceed the range, and the passes (one
 * attribute binding) refuse the split layout. */
static void test_attr_parts(void) {
    if (gpu_skip) SKIP(gpu_skip);
    vx_svo_model m[2];
    vx_svo_scene s;
    vx_error err = {0};
    uint32_t seed = 5;
    for (int k = 0; k < 2; k++) {
        size_t n = 0, cap = 24000;
        uint64_t* keys = malloc(cap * 8);
        uint32_t* rgba = malloc(cap * 4);
        REQUIRE(keys && rgba);
        for (; n < cap; n++) {
            uint32_t x = ts_rng(&seed) % 64, y = ts_rng(&seed) % 64, z = ts_rng(&seed) % 16;
            keys[n] = vx_svo_morton(x, y, z);
            rgba[n] = 0xFF000000u | (k ? ts_rng(&seed) : (ts_rng(&seed) % 7) * 0x242424u);
        }
        vx_svo_voxels v = {.size = {64, 64, 64}, .count = n, .keys = keys, .attrs = VX_ATTR_RGBA8, .rgba = rgba};
        REQUIRE(vx_svo_build_model(NULL, &v, &m[k], NULL, &err) == VX_OK);
        free(keys), free(rgba);
    }
    static const double rot[9] = {0.36, -0.48, 0.8, 0.8, 0.6, 0, -0.48, 0.64, 0.6};
    vx_svo_instance in[3] = {ts_inst(0, NULL, 0, 0, 0), ts_inst(1, rot, 70, 10, 0), ts_inst(0, rot, 20, 80, 30)};
    ts_scene(&s, m, 2, in, 3);
    vx_compact_scene c;
    REQUIRE(vx_compact_build(NULL, &s, &c, &err) == VX_OK);
    uint64_t geom = 4ull * c.geom_words, attr = 4ull * c.attr_words;
    vx_compact_free(&c);
    REQUIRE(attr > 4 * geom); /* so that a range of the geometry's bytes needs several attribute buffers */
    vx_render_scene *rs = NULL, *rsc = NULL;
    REQUIRE(vx_render_scene_create_ex(gpu, &s, &(vx_render_scene_desc){.layout = VX_RENDER_LAYOUT_PLAIN, .grid_budget = VX_RENDER_NO_GRID}, &rs, &err) ==
            VX_OK);
    /* ranges of about a fifth and a half of the attribute words (the tables come after them) */
    const uint64_t ranges[2] = {attr / 5 > geom ? attr / 5 : geom, attr / 2};
    for (int k = 0; k < 2; k++) {
        vx_result r = vx_render_scene_create_ex(
            gpu, &s, &(vx_render_scene_desc){.layout = VX_RENDER_LAYOUT_COMPACT, .max_buffer_range = ranges[k]}, &rsc,
            &err);
        CHECKF(r == VX_OK, "range %llu: %s", (unsigned long long)ranges[k], err.msg);
        if (r) continue;
        vx_render_layout_info li;
        vx_render_scene_layout(rsc, &li);
        CHECKF(li.layout == VX_RENDER_LAYOUT_COMPACT && li.attr_parts >= (k ? 2u : 5u) && li.attr_parts <= 8,
               "range %llu of %llu attribute bytes: %u parts", (unsigned long long)ranges[k], (unsigned long long)attr,
               li.attr_parts);
        for (int view = 0; view < 3; view++) {
            vx_render_desc d = {.width = 96, .height = 72, .want_hits = true,
                                .mode = view == 0 ? VX_RENDER_ALBEDO : view == 1 ? VX_RENDER_COLOR : VX_RENDER_DEPTH};
            {
                /* inside the instances' bounds, looking down at them: most pixels hit */
                d.camera.set = true;
                d.camera.fov = 70;
                double lo[3], hi[3];
                vx_svo_scene_world_bounds(&s, lo, hi);
                for (int q = 0; q < 3; q++) {
                    double mid = 0.5 * (lo[q] + hi[q]), ext = hi[q] - lo[q];
                    d.camera.target[q] = mid - (q == 2 ? 0.3 : 0.0) * ext;
                    d.camera.eye[q] = mid + (q == 2 ? 0.6 : q == 1 ? -0.1 : 0.05) * ext;
                }
            }
            vx_render_image a = {0}, b = {0};
            r = vx_render_frame(rs, &d, &a, &err);
            if (!r) r = vx_render_frame(rsc, &d, &b, &err);
            CHECKF(r == VX_OK, "view %d: %s", view, err.msg);
            uint32_t hits = 0;
            if (!r) {
                uint32_t wrong = differ(&a, &b, "attribute parts", "parts", view, &hits);
                CHECKF(wrong == 0 && hits > 96 * 72 / 10, "range %llu view %d: %u of %u pixels differ, %u hit",
                       (unsigned long long)ranges[k], view, wrong, 96 * 72, hits);
                printf("  attribute parts: %u buffers of at most %llu bytes, view %d: %u pixels hit, %u differ\n",
                       li.attr_parts, (unsigned long long)ranges[k], view, hits, wrong);
            }
            vx_render_image_free(&a);
            vx_render_image_free(&b);
        }
        /* the passes bind one attribute buffer: refused, with the reason */
        vx__frame f;
        vx__buffer* bufs[7];
        uint32_t spec[VX__SPEC_COUNT];
        double lo[3], hi[3];
        vx_svo_scene_world_bounds(&s, lo, hi);
        REQUIRE(vx__frame_setup(lo, hi, &(vx_render_desc){.width = 8, .height = 8}, &f, &err) == VX_OK);
        CHECK(vx__render_scene_bind(rsc, &f, bufs, spec, &err) == VX_ERR_UNSUPPORTED && strstr(err.msg, "storage buffers"));
        vx_render_scene_destroy(rsc);
        rsc = NULL;
    }
    /* a range below the geometry: refused with the reason, nothing left behind */
    CHECK(vx_render_scene_create_ex(gpu, &s,
                                    &(vx_render_scene_desc){.layout = VX_RENDER_LAYOUT_COMPACT, .max_buffer_range = geom - 4},
                                    &rsc, &err) == VX_ERR_LIMIT &&
          strstr(err.msg, "geometry") && !rsc);
    /* more parts than VX_COMPACT_ATTR_PARTS: refused */
    if (attr / geom > VX_COMPACT_ATTR_PARTS) {
        CHECK(vx_render_scene_create_ex(gpu, &s,
                                        &(vx_render_scene_desc){.layout = VX_RENDER_LAYOUT_COMPACT,
                                                                .max_buffer_range = attr / (VX_COMPACT_ATTR_PARTS + 2)},
                                        &rsc, &err) == VX_ERR_LIMIT &&
              strstr(err.msg, "storage buffers") && !rsc);
    }
    /* AUTO under the default budget: the plain layout, unless its words exceed the range */
    vx_render_layout_info lp;
    vx_render_scene_layout(rs, &lp);
    vx_result r = vx_render_scene_create_ex(gpu, &s, &(vx_render_scene_desc){.max_buffer_range = ranges[1]}, &rsc, &err);
    CHECKF(r == VX_OK, "AUTO: %s", err.msg);
    if (!r) {
        vx_render_layout_info la;
        vx_render_scene_layout(rsc, &la);
        CHECKF(lp.plain_bytes / 2 > ranges[1] && la.layout == VX_RENDER_LAYOUT_COMPACT && la.attr_parts >= 2,
               "AUTO with a range of %llu bytes (plain %llu): %s, %u parts", (unsigned long long)ranges[1],
               (unsigned long long)lp.plain_bytes, vx_render_layout_name(la.layout), la.attr_parts);
        vx_render_scene_destroy(rsc);
    }
    CHECK(lp.layout == VX_RENDER_LAYOUT_PLAIN && lp.attr_parts == 0);
    CHECKF(vx_gpu_validation_errors(gpu) == 0, "%u validation errors", vx_gpu_validation_errors(gpu));
    vx_render_scene_destroy(rs);
    vx_svo_scene_free(&s);
}

/* One frame of cg_on with the primary rays' starts below the root
 * (trace_compact.comp PATH_START) and one of cg_off with every walk from
 * the root (the same object for the whole layout; two paged objects that
 * take the same frames, whose pages then follow the same requests), hits
 * wanted: the pixels and hits (instance, cell, t bits, colour) must be the
 * same; with `plain` also trace.comp's (its starts on). *fewer counts the
 * frame when the start's iterations are fewer. Returns the pixels that
 * differ. */
static size_t cpath_frames(const char* name, vx_render_scene* rs, vx_compact_gpu* cg_on, vx_compact_gpu* cg_off,
                           bool plain, vx_render_desc d, size_t* fewer, double* saved) {
    vx_render_image a[3] = {{0}};
    vx_error err = {0};
    d.want_hits = true;
    for (int p = 0; p < 2; p++) {
        vx__render_scene_trace_path(rs, 1 - p); /* on even where a CPU device's default is off */
        CHECKF(vx_compact_gpu_frame(p ? cg_off : cg_on, &d, &a[p], &err) == VX_OK, "%s: %s", name, err.msg);
    }
    if (plain) {
        vx__render_scene_trace_path(rs, 1);
        CHECKF(vx_render_frame(rs, &d, &a[2], &err) == VX_OK, "%s: trace.comp: %s", name, err.msg);
    }
    vx__render_scene_trace_path(rs, -1);
    size_t n = (size_t)d.width * d.height, diff = 0;
    double it[2] = {0, 0};
    for (size_t i = 0; a[0].hits && a[1].hits && i < n; i++) {
        for (int q = 1; q < (plain ? 3 : 2); q++) {
            const vx_render_hit *x = &a[0].hits[i], *y = a[q].hits ? &a[q].hits[i] : x;
            bool same = a[q].hits && x->instance == y->instance && !memcmp(x->cell, y->cell, sizeof x->cell) &&
                        !memcmp(&x->t, &y->t, sizeof x->t) && !memcmp(&a[0].pixels[4 * i], &a[q].pixels[4 * i], 16);
            if (!same && diff < 3)
                printf("  %s pixel %zu,%zu: start inst %d cell %u,%u,%u t %.9g | %s inst %d cell %u,%u,%u t %.9g\n", name,
                       i % d.width, i / d.width, (int)x->instance, x->cell[0], x->cell[1], x->cell[2], x->t,
                       q == 1 ? "root" : "trace.comp", (int)y->instance, y->cell[0], y->cell[1], y->cell[2], y->t);
            diff += !same;
        }
        it[0] += a[0].hits[i].iterations, it[1] += a[1].hits[i].iterations;
    }
    if (!a[0].hits || !a[1].hits) diff = n;
    *fewer += it[0] < it[1];
    *saved += (it[1] - it[0]) / (double)n;
    for (int p = 0; p < 3; p++) vx_render_image_free(&a[p]);
    return diff;
}

/* A sparse model of side `side` (a power of two): solid blocks of 2 to
 * side/8 + 1 cells and 1% scattered cells; used[] (side^3) marks its cells. */
static vx_result block_model(vx_svo_model* m, uint32_t side, uint32_t seed, uint8_t* used) {
    size_t cap = (size_t)side * side * side, n = 0;
    uint32_t* xyz = malloc(cap * 12);
    uint8_t* pal = malloc(cap);
    vx_result r = VX_ERR_NOMEM;
    if (xyz && pal) {
        for (int b = 0; b < 40; b++) {
            uint32_t o[3], e[3];
            for (int k = 0; k < 3; k++) e[k] = 2 + ts_rng(&seed) % (side / 8), o[k] = ts_rng(&seed) % (side - e[k]);
            for (uint32_t z = o[2]; z < o[2] + e[2]; z++)
                for (uint32_t y = o[1]; y < o[1] + e[1]; y++)
                    for (uint32_t x = o[0]; x < o[0] + e[0]; x++) used[((size_t)z * side + y) * side + x] = 1;
        }
        for (size_t i = 0; i < cap; i++) used[i] |= ts_rng(&seed) % 100 == 0;
        for (size_t i = 0; i < cap; i++)
            if (used[i])
                xyz[3 * n] = (uint32_t)(i % side), xyz[3 * n + 1] = (uint32_t)(i / side % side),
                xyz[3 * n + 2] = (uint32_t)(i / side / side), pal[n++] = (uint8_t)(1 + i % 250);
        r = ts_model(m, (uint32_t[3]){side, side, side}, xyz, pal, n);
    }
    free(xyz), free(pal);
    return r;
}

/* The compact kernel's starts below the root (render_scene.c
 * vx__render_scene_paths over compact_gpu.c's listed tops, trace_model's
 * start in trace_compact.comp): frames from eyes inside sparse models of
 * 64^3 and 256^3 and height fields of 11 and 13 levels (trace.comp's DEEP 1
 * and DEEP 2: the exact t, the two-frame walk), at random points, on node
 * planes (multiples of 4 to 32 cells, the model's centre) and 1e-4 cells
 * beside them, and from outside the model box (no start there), in depth,
 * albedo and colour (shadow rays from the root), identity and rotated, in
 * both brick forms and paged (pages requested and loaded frame by frame),
 * must equal the walks from the root and trace.comp's frames; the starts
 * must save iterations from most random eyes inside. */
static void test_path_start(void) {
    if (gpu_skip) SKIP(gpu_skip);
    static const double rot[9] = {0, 0, -1, 1, 0, 0, 0, -1, 0};
    size_t frames = 0, fewer = 0, differ = 0, rand_frames = 0, rand_fewer = 0, outside_frames = 0, outside_fewer = 0;
    size_t paged_frames = 0, paged_fewer = 0;
    double saved = 0;
    for (int si = 0; si < 4; si++) {
        /* 0, 1: blocks in 64^3, 256^3; 2: 11 levels (DEEP 1); 3: 13 levels (DEEP 2); the deep ones first */
        int sc = (si + 2) % 4;
        uint32_t side = sc == 0 ? 64 : sc == 1 ? 256 : 0, seed = 4321 + (uint32_t)sc;
        uint8_t* used = side ? calloc((size_t)side * side * side, 1) : NULL;
        for (int tf = 0; tf < 2; tf++) {
            vx_svo_model m;
            vx_result br = side ? (used ? block_model(&m, side, 4321 + (uint32_t)sc, used) : VX_ERR_NOMEM)
                                : sc == 2 ? height_model(&m, 1200, 64, 1100, 11) : height_model(&m, 4200, 40, 160, 13);
            REQUIRE(br == VX_OK);
            uint32_t size[3] = {m.size[0], m.size[1], m.size[2]};
            vx_svo_scene s;
            vx_svo_instance in = ts_inst(0, tf ? rot : NULL, tf ? 3 : 0, tf ? -4 : 0, tf ? 7 : 0);
            ts_scene(&s, &m, 1, &in, 1);
            vx_render_scene* rs = NULL;
            vx_error err = {0};
            REQUIRE(vx_render_scene_create_ex(gpu, &s, &(vx_render_scene_desc){.layout = VX_RENDER_LAYOUT_PLAIN, .grid_budget = VX_RENDER_NO_GRID}, &rs,
                                              &err) == VX_OK);
            vx_compact_gpu* cg[2] = {NULL, NULL}; /* the brick forms: inline, the dictionary */
            for (int k = 0; k < 2; k++) {
                vx_compact_scene c;
                REQUIRE(vx_compact_build(&(vx_compact_desc){.bricks = k ? VX_COMPACT_BRICKS_DICT : VX_COMPACT_BRICKS_INLINE},
                                         &s, &c, &err) == VX_OK);
                REQUIRE(vx_compact_gpu_create(rs, &s, &c, &cg[k], &err) == VX_OK);
                vx_compact_free(&c);
            }
            /* paged (sc 0, 1 identity): two objects that take the same frames, level 3 pages, room for all */
            vx_compact_gpu* pg[2] = {NULL, NULL};
            if (side && !tf) {
                vx_compact_scene c;
                REQUIRE(vx_compact_build(NULL, &s, &c, &err) == VX_OK);
                for (int k = 0; k < 2; k++) {
                    vx_compact_paged p;
                    REQUIRE(vx_compact_page_build(&c, 3, NULL, &p, &err) == VX_OK);
                    uint64_t pool = 8 * p.data_words + 4ull * p.max_page_words;
                    REQUIRE(vx_compact_gpu_create_paged(rs, &s, &p, pool, &pg[k], &err) == VX_OK);
                }
                vx_compact_free(&c);
            }
            /* starts of any depth (the default takes those that skip 2 pushes or more) */
            for (int k = 0; k < 2; k++) vx__compact_gpu_start_min(cg[k], 1), vx__compact_gpu_start_min(pg[k], 1);
            /* 8 views inside (each of the four eye kinds twice, the last the centre) and 2 from outside: twice
             * that many took 529 s of this test in Release on 2 cores with a cold shader cache (stop 59) */
            int views = 8;
            for (int v = 0; v < views + 2; v++) {
                bool outside = v >= views;
                double e[3], t[3];
                vx_render_desc d = {.width = 40, .height = 30};
                /* one mode a model (colour on the 64^3 blocks and the 13 levels, albedo on the 256^3 blocks, depth on
                 * the 11 levels): the start is taken before the mode's shading, and each mode is a kernel of its own
                 * for lavapipe to compile for every model, layout and start setting (all three modes a model: 1,002 s
                 * of this test in Release on 2 cores with a cold shader cache, as CI's; docs/TESTING.md) */
                d.mode = sc == 1 ? VX_RENDER_ALBEDO : sc == 2 ? VX_RENDER_DEPTH : VX_RENDER_COLOR;
                d.camera.set = true, d.camera.fov = 70;
                double dir[3], dl = 0;
                for (int k = 0; k < 3; k++) dir[k] = (double)(ts_rng(&seed) % 2001) - 1000, dl += dir[k] * dir[k];
                dl = sqrt(dl);
                for (int k = 0; k < 3; k++) {
                    uint32_t r = ts_rng(&seed);
                    int kind = v % 4;
                    double plane = (double)((1u << (2 + r % 4)) * (1 + (r >> 4) % 3));
                    if (plane >= size[k]) plane = size[k] / 2;
                    e[k] = kind == 0 ? 1 + (r % ((size[k] - 2) * 100)) / 100.0
                           : kind == 1 ? plane
                           : kind == 2 ? plane + 1e-4
                                       : plane - 1e-4;
                    if (v == views - 1) e[k] = size[k] / 2; /* the centre: the model's mid-planes */
                    if (outside) e[k] = size[k] / 2 + dir[k] / dl * 1.5 * (size[0] + size[1] + size[2]);
                    t[k] = outside ? size[k] / 2 : e[k] + dir[k] / dl * 10;
                }
                if (!side && !outside) {
                    /* height fields (height_model): the eye 2-3 cells above the surface, inside the model box
                     * (the surface's highest cells are at 0.75 (size - 2)) */
                    double ys = (size[1] - 2) * (0.5 + 0.25 * sin(floor(e[0]) * 0.013) * cos(floor(e[2]) * 0.021));
                    e[1] = fmin(ys + 2 + (ts_rng(&seed) % 100) / 100.0, 0.74 * (size[1] - 2)), t[1] = e[1] - 6;
                }
                if (side && !outside) {
                    uint32_t c[3];
                    for (int k = 0; k < 3; k++) c[k] = (uint32_t)e[k] < side ? (uint32_t)e[k] : side - 1;
                    if (used[((size_t)c[2] * side + c[1]) * side + c[0]]) e[2] += 0.5; /* in a cell: still exact */
                }
                ts_inst_point(&in, e, d.camera.eye);
                ts_inst_point(&in, t, d.camera.target);
                for (int k = 0; k < 2; k++) {
                    char nm[128];
                    snprintf(nm, sizeof nm, "compact start, %s, %s, %s, view %d", side == 64 ? "64^3" : side ? "256^3" : sc == 2 ? "11 levels" : "13 levels",
                             tf ? "rotated" : "identity", k ? "dictionary" : "inline", v);
                    size_t f0 = fewer;
                    differ += cpath_frames(nm, rs, cg[k], cg[k], true, d, &fewer, &saved);
                    frames++;
                    if (outside) outside_frames++, outside_fewer += fewer > f0;
                    else if (v % 4 == 0 && v != views - 1) rand_frames++, rand_fewer += fewer > f0;
                }
                if (pg[0]) {
                    /* three frames each: pages requested, loaded, the whole image */
                    for (int fr = 0; fr < 3; fr++) {
                        char nm[128];
                        snprintf(nm, sizeof nm, "compact start, %s, paged, view %d frame %d", side == 64 ? "64^3" : "256^3", v, fr);
                        size_t f0 = fewer;
                        differ += cpath_frames(nm, rs, pg[0], pg[1], false, d, &fewer, &saved);
                        frames++, paged_frames++, paged_fewer += fewer > f0;
                    }
                }
            }
            printf("  compact start, %s, %s: %zu frames so far, %zu with fewer iterations, %zu pixels differ\n",
                   side == 64 ? "64^3" : side ? "256^3" : sc == 2 ? "11 levels" : "13 levels", tf ? "rotated" : "identity",
                   frames, fewer, differ);
            fflush(stdout);
            CHECKF(vx_gpu_validation_errors(gpu) == 0, "%u validation errors", vx_gpu_validation_errors(gpu));
            for (int k = 0; k < 2; k++) vx_compact_gpu_destroy(cg[k]), vx_compact_gpu_destroy(pg[k]);
            vx_render_scene_destroy(rs);
            vx_svo_scene_free(&s);
        }
        free(used);
    }
    printf("compact start: %zu frames, %zu with fewer iterations (%zu of %zu from random eyes inside, %zu of %zu from "
           "outside, %zu of %zu paged), %.2f iterations a ray saved on average, %zu pixels differ\n",
           frames, fewer, rand_fewer, rand_frames, outside_fewer, outside_frames, paged_fewer, paged_frames,
           saved / (double)frames, differ);
    CHECK(differ == 0);
    CHECK(rand_fewer * 4 >= rand_frames * 3);
    CHECK(outside_fewer == 0);
    CHECK(paged_fewer > 0);
}

/* The start records the host writes for the compact kernel
 * (vx__render_scene_paths over compact_gpu.c's lists), checked against the
 * geometry slots themselves after each frame (the frame block is mapped on
 * lavapipe): every record's chain is the descent from the model's root slot
 * through the octants of X's cube (each next slot the inner child of that
 * octant in its parent's block: geom word 1 plus the inner children below
 * it), X's level is 3 or more, its cube holds the eye, a record skips at
 * least the threshold's pushes (vx__compact_gpu_start_min: 1, the default
 * 2, or more than the model has: none), and a tile's record index is in
 * range. Sparse 256^3 blocks and the 11-level height field, both brick forms. */
static void test_path_records(void) {
    if (gpu_skip) SKIP(gpu_skip);
    size_t records = 0, checked_tiles = 0, bad = 0, deep1 = 0;
    for (int sc = 0; sc < 2; sc++) {
        uint8_t* used = sc == 0 ? calloc((size_t)256 * 256 * 256, 1) : NULL;
        vx_svo_model m;
        REQUIRE((sc == 0 ? (used ? block_model(&m, 256, 99, used) : VX_ERR_NOMEM) : height_model(&m, 1200, 64, 1100, 11)) ==
                VX_OK);
        uint32_t size[3] = {m.size[0], m.size[1], m.size[2]}, depth = m.depth;
        vx_svo_scene s;
        vx_svo_instance in = ts_inst(0, NULL, 0, 0, 0);
        ts_scene(&s, &m, 1, &in, 1);
        vx_error err = {0};
        vx_render_scene* rs = NULL;
        REQUIRE(vx_render_scene_create_ex(gpu, &s, &(vx_render_scene_desc){.layout = VX_RENDER_LAYOUT_PLAIN, .grid_budget = VX_RENDER_NO_GRID}, &rs, &err) ==
                VX_OK);
        double lo[3], hi[3];
        vx_svo_scene_world_bounds(&s, lo, hi);
        for (int k = 0; k < 2; k++) {
            vx_compact_scene c;
            REQUIRE(vx_compact_build(&(vx_compact_desc){.bricks = k ? VX_COMPACT_BRICKS_DICT : VX_COMPACT_BRICKS_INLINE}, &s,
                                     &c, &err) == VX_OK);
            vx_compact_gpu* cg = NULL;
            REQUIRE(vx_compact_gpu_create(rs, &s, &c, &cg, &err) == VX_OK);
            /* the frame block (binding 0, mapped on lavapipe) */
            vx__frame f;
            vx__buffer* bufs[7];
            uint32_t sp[VX__SPEC_COUNT];
            vx_render_desc d0 = {.width = 64, .height = 48};
            REQUIRE(vx__frame_setup(lo, hi, &d0, &f, &err) == VX_OK);
            REQUIRE(vx__render_scene_tables(rs, &f, bufs, sp, &err) == VX_OK);
            const vx__gpu_frame* gf = bufs[0]->map;
            if (!gf) {
                vx_compact_gpu_destroy(cg);
                vx_compact_free(&c);
                SKIP("the frame block is not host visible on %s", vx_gpu_device_name(gpu));
            }
            uint32_t seed = 77 + (uint32_t)k;
            for (int v = 0; v < 12; v++) {
                double e[3], dir[3], dl = 0;
                for (int a = 0; a < 3; a++) dir[a] = (double)(ts_rng(&seed) % 2001) - 1000, dl += dir[a] * dir[a];
                dl = sqrt(dl);
                for (int a = 0; a < 3; a++) e[a] = 1 + (ts_rng(&seed) % ((size[a] - 2) * 100)) / 100.0;
                if (sc == 1) e[1] = 0.74 * (size[1] - 2) - (ts_rng(&seed) % 100) / 100.0;
                vx_render_desc d = {.width = 64, .height = 48, .mode = VX_RENDER_DEPTH};
                d.camera.set = true, d.camera.fov = 70;
                for (int a = 0; a < 3; a++) d.camera.eye[a] = e[a], d.camera.target[a] = e[a] + dir[a] / dl * 10;
                for (uint32_t th = 1; th <= 3; th++) {
                    uint32_t min_dq = th == 3 ? depth : th; /* 3: more pushes than the model has */
                    vx__compact_gpu_start_min(cg, min_dq);
                    vx__render_scene_trace_path(rs, 1);
                    vx_render_image img = {0};
                    vx_result r = vx_compact_gpu_frame(cg, &d, &img, &err);
                    vx__render_scene_trace_path(rs, -1);
                    vx_render_image_free(&img);
                    CHECKF(r == VX_OK, "%s", err.msg);
                    if (r) continue;
                    uint32_t shift = gf->tile_info[0], tx = gf->tile_info[1];
                    uint32_t ty = (48 + (1u << shift) - 1) >> shift, maxrec = 0;
                    bool any = false;
                    for (uint32_t t = 0; t < tx * ty; t++) {
                        uint16_t ti = gf->tiles[t];
                        if (ti == VX__TILE_NONE) continue;
                        checked_tiles++, any = true;
                        if (ti >= VX__PATHS) {
                            bad++;
                            continue;
                        }
                        if (ti + 1u > maxrec) maxrec = ti + 1u;
                    }
                    if (th == 3) bad += any; /* no start skips more pushes than the model has levels below 3 */
                    for (uint32_t ri = 0; ri < maxrec; ri++) {
                        const vx__gpu_path* g = &gf->paths[ri];
                        uint32_t dx = g->info[0], ok = dx >= min_dq && dx >= 1 && dx + 3 <= depth && g->info[2] == 0;
                        ok = ok && g->nodes[0] == c.models[0].root && g->cube[3] == (float)ldexp(1.0, -(int)dx);
                        for (int a = 0; ok && a < 3; a++) {
                            /* the eye in the model cube's [1,2] units inside X's cube */
                            double q = 1 + e[a] / ldexp(1.0, (int)depth);
                            ok = q >= g->cube[a] && q <= g->cube[a] + g->cube[3];
                        }
                        for (uint32_t j = 0; ok && j < dx; j++) {
                            uint32_t node = g->nodes[j], next = j + 1 < dx ? g->nodes[j + 1] : g->info[1], oct = 0;
                            for (int a = 0; a < 3; a++)
                                oct |= (uint32_t)((int64_t)floor(((double)g->cube[a] - 1) * ldexp(1.0, (int)j + 1)) & 1) << a;
                            uint32_t w0 = c.geom[2 * (size_t)node], inner = (w0 >> 8) & ~w0 & 0xFFu;
                            ok = ((inner >> oct) & 1u) &&
                                 next == c.geom[2 * (size_t)node + 1] + (uint32_t)__builtin_popcount(inner & ((1u << oct) - 1u));
                        }
                        if (!ok && bad < 3)
                            printf("  record %u of view %d (threshold %u): depth %u, X %u, cube %g %g %g / %g\n", ri, v,
                                   min_dq, dx, g->info[1], g->cube[0], g->cube[1], g->cube[2], g->cube[3]);
                        bad += !ok;
                        records++;
                        deep1 += dx == 1;
                    }
                }
            }
            vx_compact_gpu_destroy(cg);
            vx_compact_free(&c);
        }
        vx_render_scene_destroy(rs);
        vx_svo_scene_free(&s);
        free(used);
    }
    printf("compact start records: %zu records of %zu tiles checked, %zu of one push, %zu wrong\n", records, checked_tiles,
           deep1, bad);
    CHECK(bad == 0);
    CHECK(records > 0 && deep1 > 0); /* the threshold 1 takes some of one push; 2 none (checked per record) */
}

static void test_corpus(void) {
    if (gpu_skip) SKIP(gpu_skip);
    static const char* files[] = {"eph_chr_knight.vox", "eph_dragon.vox", "eph_menger.vox",
                                  "eph_monu1.vox", "eph_teapot.vox", "ogt_chr_knight.vox",
                                  "ogt_doom.vox", "ogt_test_groups.vox", "ogt_test_multiple_model_scene.vox"};
    int done = 0;
    for (size_t i = 0; i < sizeof files / sizeof files[0]; i++) {
        vx_svo_scene s;
        vx_test_vox st = vx_test_vox_scene(files[i], &s);
        if (st == VX_TEST_VOX_ABSENT) continue;
        done++; /* found: a file that fails to load fails the test, not skips it */
        CHECKF(st == VX_TEST_VOX_OK, "%s: not loaded", files[i]);
        if (st != VX_TEST_VOX_OK) continue;
        CHECKF(compare(&s, files[i], 96, 72) > 96 * 72 / 10, "%s: too few pixels hit", files[i]);
        vx_svo_scene_free(&s);
    }
    if (!done) SKIP("no corpus .vox files");
}

static void test_corpus_mesh(void) {
    if (gpu_skip) SKIP(gpu_skip);
#ifdef VX_TEST_HAVE_MESH
    const char* path = vx_test_corpus("gltf/khronos_DamagedHelmet.glb");
    if (!path) SKIP("no DamagedHelmet.glb");
    vx_svo_scene s;
    vx_error err = {0};
    REQUIRE(vx_conv_mesh_file(&(vx_conv_mesh_desc){.res = 128}, path, &s, NULL, &err) == VX_OK);
    CHECK(compare(&s, "DamagedHelmet at 128", 128, 96) > 128 * 96 / 4);
    vx_svo_scene_free(&s);
#else
    SKIP("built without the mesh converter");
#endif
}

int main(void) {
    gpu_skip = vx_test_gpu_open((vx_gpu_desc){0}, true, &gpu);
    RUN(test_generated);
    RUN(test_seams);
    RUN(test_inside_leaf);
    RUN(test_deep);
    RUN(test_start_table);
    RUN(test_uniform_cubes);
    RUN(test_attr_parts);
    RUN(test_path_start);
    RUN(test_path_records);
    RUN(test_corpus);
    RUN(test_corpus_mesh);
    vx_gpu_destroy(gpu);
    return vx_test_finish();
}
