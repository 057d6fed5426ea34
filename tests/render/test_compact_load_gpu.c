/* tests/render/test_compact_load_gpu.c - the render scene from a model
 * reader (vx_render_scene_create_reader, issue 18): the compact layout built
 * model by model renders what vx_render_scene_create_ex of the scene read
 * whole renders (the same instance, cell and colour per pixel, several
 * views and modes), with the same layout sizes; AUTO's plain layout through
 * the reader too; a compact layout past the memory budget is paged as
 * create_ex pages it (the same frames, frame by frame, and page counts); a
 * damaged model names the file. The layout built from the
 * reader before the device (vx_render_scene_create_compact, as svo_render
 * --load models does) renders the same frames; vx_render_scene_choose_layout
 * answers what create_ex picks. AUTO's brick dictionary from a second pass
 * over the file (vx_svo_reader_rewind): create_ex's layout and frames. Lavapipe in CI. */
#define _POSIX_C_SOURCE 200809L
#include <dlfcn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "render/compact.h"
#include "render/render.h"
#include "svo/svo.h"
#include "tests/gpu_test.h"
#include "tests/render/scenes.h"
#include "tests/test.h"

static vx_gpu* gpu;
static const char* gpu_skip;
static char g_dir[64];

/* Region-like models: palette and RGBA, of several sizes and fills, each an instance on a grid. */
static void make_many(vx_svo_scene* s, uint32_t nm) {
    vx_svo_model* m = calloc(nm, sizeof *m);
    vx_svo_instance* in = calloc(nm, sizeof *in);
    for (uint32_t i = 0; i < nm; i++) {
        uint32_t side = 6 + (i * 5) % 19, pct = i % 7 == 3 ? 100 : 8 + (i * 11) % 50;
        REQUIRE(ts_random_model(&m[i], side, side, side - i % 2, pct, 31 + i) == VX_OK);
        if (i % 3 == 1 && m[i].attr_count) {
            m[i].rgba = malloc((size_t)m[i].attr_count * 4);
            for (uint32_t a = 0; a < m[i].attr_count; a++) m[i].rgba[a] = 0xFF000000u | (m[i].palette[a] * 0x030507u);
            free(m[i].palette);
            m[i].palette = NULL;
            m[i].attrs = VX_ATTR_RGBA8;
        }
        in[i] = ts_inst(i, NULL, 26.0 * (i % 5), 26.0 * (i / 5 % 5), 26.0 * (i / 25));
    }
    ts_scene(s, m, nm, in, nm);
    free(m);
    free(in);
}

static uint32_t differ(const vx_render_image* a, const vx_render_image* b, const char* what) {
    uint32_t bad = 0, n = a->width * a->height;
    if (a->width != b->width || a->height != b->height) return UINT32_MAX;
    for (uint32_t i = 0; i < n; i++)
        bad += a->pixels[i] != b->pixels[i] || a->hits[i].instance != b->hits[i].instance ||
               memcmp(a->hits[i].cell, b->hits[i].cell, sizeof a->hits[i].cell) != 0;
    if (bad) fprintf(stderr, "%s: %u of %u pixels differ\n", what, bad, n);
    return bad;
}


/* A paged (or over-budget whole) scene from the reader against create_ex's: the same layout report, and
 * frame after frame the same images and page counts until the view's pages are resident. */
static void paged_same_view(vx_render_scene* ra, vx_render_scene* rb, bool want_pages, const vx_render_camera* cam);
static void paged_same(vx_render_scene* ra, vx_render_scene* rb, bool want_pages) { paged_same_view(ra, rb, want_pages, NULL); }
static void paged_same_view(vx_render_scene* ra, vx_render_scene* rb, bool want_pages, const vx_render_camera* cam) {
    vx_render_layout_info la, lb;
    vx_render_scene_layout(ra, &la);
    vx_render_scene_layout(rb, &lb);
    CHECKF(la.layout == lb.layout && la.pages == lb.pages && la.page_level == lb.page_level && la.bytes == lb.bytes,
           "%u pages at %u, %llu bytes against %u at %u, %llu", la.pages, la.page_level, (unsigned long long)la.bytes,
           lb.pages, lb.page_level, (unsigned long long)lb.bytes);
    CHECKF(want_pages ? la.pages > 1 : la.pages == 0 && la.bytes > la.budget, "%u pages, %llu bytes of %llu", la.pages,
           (unsigned long long)la.bytes, (unsigned long long)la.budget);
    vx_render_desc d = {.width = 80, .height = 60, .mode = VX_RENDER_ALBEDO, .want_hits = true};
    if (cam) d.camera = *cam;
    vx_error err = {0};
    int f = 0;
    for (; f < 24; f++) {
        vx_render_image a = {0}, b = {0};
        REQUIRE(vx_render_frame(ra, &d, &a, &err) == VX_OK);
        REQUIRE(vx_render_frame(rb, &d, &b, &err) == VX_OK);
        vx_render_page_stats sa = {0}, sb = {0};
        vx_render_scene_page_stats(ra, &sa);
        vx_render_scene_page_stats(rb, &sb);
        CHECKF(differ(&a, &b, "paged from the reader") == 0 && sa.coarse == sb.coarse && sa.resident == sb.resident,
               "frame %d: %u coarse, %u resident against %u, %u", f, sa.coarse, sa.resident, sb.coarse, sb.resident);
        if (want_pages && f == 0) CHECKF(sa.coarse > 0, "first frame: %u pages coarse", sa.coarse);
        vx_render_image_free(&a), vx_render_image_free(&b);
        if (!sa.coarse) break;
    }
    CHECKF(f < 24, "still coarse after %d frames", f);
}

static void test_same_frames(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    vx_svo_scene s;
    make_many(&s, 60);
    vx_error err = {0};
    char path[128];
    snprintf(path, sizeof path, "%s/many.svo", g_dir);
    REQUIRE(vx_svo_write_file(NULL, &s, path, &err) == VX_OK);
    vx_svo_scene_free(&s);
    vx_svo_scene whole;
    REQUIRE(vx_svo_read_file(NULL, path, &whole, &err) == VX_OK);
    for (int layout = VX_RENDER_LAYOUT_AUTO; layout <= VX_RENDER_LAYOUT_COMPACT; layout += 2) {
        vx_render_scene_desc sd = {.layout = (vx_render_layout)layout};
        vx_render_scene *ra = NULL, *rb = NULL;
        vx_svo_model_reader* rd = NULL;
        REQUIRE(vx_render_scene_create_ex(gpu, &whole, &sd, &ra, &err) == VX_OK);
        REQUIRE(vx_svo_reader_open(NULL, path, &rd, &err) == VX_OK);
        vx_result r = vx_render_scene_create_reader(gpu, rd, &sd, &rb, &err);
        CHECKF(r == VX_OK, "layout %d: %s", layout, err.msg);
        vx_svo_reader_close(rd);
        if (r) {
            vx_render_scene_destroy(ra);
            continue;
        }
        vx_render_layout_info la, lb;
        vx_render_scene_layout(ra, &la);
        vx_render_scene_layout(rb, &lb);
        CHECKF(la.layout == lb.layout && la.bytes == lb.bytes && la.compact_bytes == lb.compact_bytes &&
                   la.geom_bytes == lb.geom_bytes && la.plain_bytes == lb.plain_bytes && la.voxels == lb.voxels,
               "layout %d: %s %llu bytes against %s %llu", layout, vx_render_layout_name(la.layout),
               (unsigned long long)la.bytes, vx_render_layout_name(lb.layout), (unsigned long long)lb.bytes);
        CHECK(layout != VX_RENDER_LAYOUT_COMPACT || lb.layout == VX_RENDER_LAYOUT_COMPACT);
        for (int view = 0; view < 3; view++) {
            vx_render_desc d = {.width = 96, .height = 72, .mode = view == 2 ? VX_RENDER_COLOR : VX_RENDER_ALBEDO,
                                .want_hits = true};
            if (view == 1) {
                d.camera.set = true;
                d.camera.fov = 60;
                double eye[3] = {-20, -30, 70}, target[3] = {60, 60, 10};
                memcpy(d.camera.eye, eye, sizeof eye);
                memcpy(d.camera.target, target, sizeof target);
            }
            vx_render_image a = {0}, b = {0};
            REQUIRE(vx_render_frame(ra, &d, &a, &err) == VX_OK);
            REQUIRE(vx_render_frame(rb, &d, &b, &err) == VX_OK);
            uint32_t hit = 0;
            for (uint32_t i = 0; i < a.width * a.height; i++) hit += a.hits[i].instance != VX_RENDER_NO_HIT;
            CHECKF(hit > a.width * a.height / 20, "view %d: %u pixels hit", view, hit);
            CHECKF(differ(&a, &b, "reader against whole") == 0, "layout %d view %d: the frames differ", layout, view);
            vx_render_image_free(&a);
            vx_render_image_free(&b);
        }
        vx_render_scene_destroy(ra);
        vx_render_scene_destroy(rb);
    }
    /* past the budget: paged as create_ex pages it (the pages are cut from the layout), or where the top and
     * the largest page exceed it, the whole layout over it */
    vx_render_scene* rc = NULL;
    REQUIRE(vx_render_scene_create_ex(gpu, &whole, &(vx_render_scene_desc){.layout = VX_RENDER_LAYOUT_COMPACT}, &rc,
                                      &err) == VX_OK);
    vx_render_layout_info lc;
    vx_render_scene_layout(rc, &lc);
    vx_render_scene_destroy(rc);
    uint64_t budgets[2] = {lc.compact_bytes * 3 / 4, 4096};
    for (int k = 0; k < 2; k++) {
        vx_render_scene_desc small = {.layout = VX_RENDER_LAYOUT_COMPACT, .memory_budget = budgets[k], .page_level = 3};
        vx_svo_model_reader* rd = NULL;
        vx_render_scene *ra = NULL, *rb = NULL;
        REQUIRE(vx_render_scene_create_ex(gpu, &whole, &small, &ra, &err) == VX_OK);
        REQUIRE(vx_svo_reader_open(NULL, path, &rd, &err) == VX_OK);
        vx_result r = vx_render_scene_create_reader(gpu, rd, &small, &rb, &err);
        CHECKF(r == VX_OK, "budget %llu: %s", (unsigned long long)budgets[k], err.msg);
        vx_svo_reader_close(rd);
        if (!r) paged_same(ra, rb, k == 0);
        vx_render_scene_destroy(ra);
        vx_render_scene_destroy(rb);
    }
    vx_svo_scene_free(&whole);
}

static void test_damaged(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    vx_svo_scene s;
    make_many(&s, 9);
    s.models[4].voxel_count += 3;
    vx_error err = {0};
    char path[128];
    snprintf(path, sizeof path, "%s/damaged.svo", g_dir);
    vx_result wr = vx_svo_write_file(&(vx_write_desc){.testing.unchecked = true}, &s, path, &err);
    REQUIRE(wr == VX_OK);
    vx_svo_scene_free(&s);
    for (int layout = VX_RENDER_LAYOUT_AUTO; layout <= VX_RENDER_LAYOUT_COMPACT; layout += 2) {
        vx_svo_model_reader* rd = NULL;
        vx_render_scene* rs = NULL;
        REQUIRE(vx_svo_reader_open(NULL, path, &rd, &err) == VX_OK);
        vx_result r = vx_render_scene_create_reader(gpu, rd, &(vx_render_scene_desc){.layout = (vx_render_layout)layout}, &rs, &err);
        CHECKF(r == VX_ERR_BAD_FORMAT && rs == NULL && strstr(err.msg, path) && strstr(err.msg, "model 4"), "layout %d: %d %s",
               layout, (int)r, err.msg);
        vx_svo_reader_close(rd);
    }
}


/* The compact layout built from a reader with no device in it (vx_compact_build_reader, what svo_render
 * --load models does before it makes the device: a device idle through the build ran the H200's frames
 * 4.7x slower), then handed to vx_render_scene_create_compact: the frames and sizes of create_ex's. The
 * layout choice create_ex makes, asked first (vx_render_scene_choose_layout). */
static void test_built_first(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    vx_svo_scene s;
    make_many(&s, 33);
    vx_error err = {0};
    char path[128];
    snprintf(path, sizeof path, "%s/first.svo", g_dir);
    REQUIRE(vx_svo_write_file(&(vx_write_desc){.svo_chunk_words = 64}, &s, path, &err) == VX_OK);
    vx_svo_scene_free(&s);
    vx_svo_scene whole;
    REQUIRE(vx_svo_read_file(NULL, path, &whole, &err) == VX_OK);
    /* the choice: as create_ex's, for each layout asked and a budget that makes AUTO compact */
    vx_render_scene_desc asks[4] = {{.layout = VX_RENDER_LAYOUT_AUTO}, {.layout = VX_RENDER_LAYOUT_PLAIN},
                                    {.layout = VX_RENDER_LAYOUT_COMPACT}, {.layout = VX_RENDER_LAYOUT_AUTO, .memory_budget = 2048}};
    for (int k = 0; k < 4; k++) {
        vx_svo_model_reader* rd = NULL;
        vx_render_scene* ra = NULL;
        vx_render_layout lay = (vx_render_layout)99;
        REQUIRE(vx_svo_reader_open(NULL, path, &rd, &err) == VX_OK);
        CHECKF(vx_render_scene_choose_layout(gpu, vx_svo_reader_scene(rd), &asks[k], &lay, &err) == VX_OK, "%s", err.msg);
        REQUIRE(vx_render_scene_create_ex(gpu, &whole, &asks[k], &ra, &err) == VX_OK);
        vx_render_layout_info la;
        vx_render_scene_layout(ra, &la);
        CHECKF(lay == la.layout, "ask %d: chose %s, create_ex %s", k, vx_render_layout_name(lay), vx_render_layout_name(la.layout));
        CHECK(k != 3 || lay == VX_RENDER_LAYOUT_COMPACT);
        vx_render_scene_destroy(ra);
        vx_svo_reader_close(rd);
    }
    vx_render_layout bad;
    CHECK(vx_render_scene_choose_layout(gpu, NULL, NULL, &bad, &err) == VX_ERR_INVALID_ARG);
    /* the layout built with no device, then the scene: create_ex's frames */
    vx_render_scene_desc sd = {.layout = VX_RENDER_LAYOUT_COMPACT};
    vx_svo_model_reader* rd = NULL;
    vx_render_scene *ra = NULL, *rb = NULL;
    vx_compact_scene c;
    REQUIRE(vx_svo_reader_open(NULL, path, &rd, &err) == VX_OK);
    REQUIRE(vx_compact_build_reader(&(vx_compact_desc){.attr_regions = true}, rd, &c, &err) == VX_OK);
    /* asked for AUTO (plain for this scene): the scene is still the compact layout it was given */
    vx_result r = vx_render_scene_create_compact(gpu, rd, &c, 0.5, &(vx_render_scene_desc){0}, &rb, &err);
    CHECKF(r == VX_OK, "%s", err.msg);
    vx_svo_reader_close(rd);
    REQUIRE(vx_render_scene_create_ex(gpu, &whole, &sd, &ra, &err) == VX_OK);
    if (!r) {
        vx_render_layout_info la, lb;
        vx_render_scene_layout(ra, &la);
        vx_render_scene_layout(rb, &lb);
        CHECK(lb.layout == VX_RENDER_LAYOUT_COMPACT && la.bytes == lb.bytes && la.compact_bytes == lb.compact_bytes &&
              la.geom_bytes == lb.geom_bytes && lb.build_seconds == 0.5);
        for (int view = 0; view < 2; view++) {
            vx_render_desc d = {.width = 80, .height = 64, .mode = view ? VX_RENDER_COLOR : VX_RENDER_ALBEDO, .want_hits = true};
            vx_render_image a = {0}, b = {0}, b2 = {0};
            REQUIRE(vx_render_frame(ra, &d, &a, &err) == VX_OK);
            REQUIRE(vx_render_frame(rb, &d, &b, &err) == VX_OK);
            CHECKF(differ(&a, &b, "built first against whole") == 0, "view %d: the frames differ", view);
            /* the warm-up runs the frame's kernel and leaves the frames as they were */
            double ms = -1;
            CHECKF(vx_render_scene_warm_up(rb, &d, 0, &ms, &err) == VX_OK && ms >= 0, "warm-up: %s", err.msg);
            REQUIRE(vx_render_frame(rb, &d, &b2, &err) == VX_OK);
            CHECK(differ(&b, &b2, "after the warm-up") == 0);
            vx_render_image_free(&a), vx_render_image_free(&b), vx_render_image_free(&b2);
        }
    }
    vx_render_scene_destroy(rb);
    /* past the budget: paged as create_ex's, from the layout built with no device */
    vx_render_layout_info lw;
    vx_render_scene_layout(ra, &lw);
    vx_render_scene_destroy(ra);
    ra = NULL;
    vx_render_scene_desc small = {.layout = VX_RENDER_LAYOUT_COMPACT, .memory_budget = lw.compact_bytes * 3 / 4,
                                  .page_level = 3};
    REQUIRE(vx_render_scene_create_ex(gpu, &whole, &small, &ra, &err) == VX_OK);
    REQUIRE(vx_svo_reader_open(NULL, path, &rd, &err) == VX_OK);
    REQUIRE(vx_compact_build_reader(&(vx_compact_desc){.attr_regions = true}, rd, &c, &err) == VX_OK);
    rb = NULL;
    r = vx_render_scene_create_compact(gpu, rd, &c, 0, &small, &rb, &err);
    CHECKF(r == VX_OK, "%s", err.msg);
    if (!r) paged_same(ra, rb, true);
    vx_render_scene_destroy(ra);
    vx_render_scene_destroy(rb);
    /* the reader is used up: a second build fails and leaves nothing (ASan: no leak) */
    REQUIRE(vx_compact_build_reader(&(vx_compact_desc){.attr_regions = true}, rd, &c, &err) != VX_OK);
    vx_svo_reader_close(rd);
    CHECK(vx_render_scene_create_compact(gpu, NULL, NULL, 0, NULL, &rb, &err) == VX_ERR_INVALID_ARG);
    vx_svo_scene_free(&whole);
}

/* Models whose 4^3 bricks repeat under parents that do not: each brick of a
 * 32^3 model is empty or one of three fixed patterns, chosen per brick by a
 * hash, so the DAG shares few subtrees above the bricks and the brick
 * dictionary (render/compact.h) holds three bricks for all of them. */
static void make_bricky(vx_svo_scene* s, uint32_t nm) {
    vx_svo_model* m = calloc(nm, sizeof *m);
    vx_svo_instance* in = calloc(nm, sizeof *in);
    uint32_t* xyz = malloc(32768 * 12);
    uint8_t* pal = malloc(32768);
    for (uint32_t i = 0; i < nm; i++) {
        size_t n = 0;
        for (uint32_t z = 0; z < 32; z++)
            for (uint32_t y = 0; y < 32; y++)
                for (uint32_t x = 0; x < 32; x++) {
                    uint32_t h = ((x >> 2) * 73856093u) ^ ((y >> 2) * 19349663u) ^ ((z >> 2) * 83492791u) ^ (i * 2654435761u);
                    uint32_t kind = (h >> 7) % 4, c = (x & 3) + 4 * (y & 3) + 16 * (z & 3);
                    bool set = kind == 1 ? c % 3 == 0 : kind == 2 ? (c * 37u) % 64 < 20 : kind == 3 ? (x & 3) == (y & 3) : false;
                    if (!set) continue;
                    xyz[3 * n] = x, xyz[3 * n + 1] = y, xyz[3 * n + 2] = z;
                    pal[n++] = (uint8_t)(1 + (x / 8 + y / 8 + z / 8 + i) % 9);
                }
        uint32_t size[3] = {32, 32, 32};
        REQUIRE(ts_model(&m[i], size, xyz, pal, n) == VX_OK);
        in[i] = ts_inst(i, NULL, 40.0 * (i % 3), 40.0 * (i / 3), 0);
    }
    ts_scene(s, m, nm, in, nm);
    free(m), free(in), free(xyz), free(pal);
}

/* AUTO's bricks from a reader (a second pass over the file, vx_svo_reader_rewind): over the budget the
 * layout is built again with the brick dictionary and kept where its geometry is smaller, as create_ex
 * keeps it from the scene read whole: the same layout report (dictionary, bytes, pages) and the same frames
 * through create_reader and through create_compact (the layout in blocks built before the device, as
 * svo_render builds it), whole where the dictionary fits the budget and paged where it does not (frames
 * converge as create_ex's). A file cut after the first pass fails the second, naming the file. */
static void test_auto_bricks(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    vx_svo_scene s;
    make_bricky(&s, 6);
    vx_error err = {0};
    char path[128];
    snprintf(path, sizeof path, "%s/bricky.svo", g_dir);
    REQUIRE(vx_svo_write_file(NULL, &s, path, &err) == VX_OK);
    vx_svo_scene_free(&s);
    vx_svo_scene whole;
    REQUIRE(vx_svo_read_file(NULL, path, &whole, &err) == VX_OK);
    vx_compact_scene ci, cdict;
    REQUIRE(vx_compact_build(&(vx_compact_desc){0}, &whole, &ci, &err) == VX_OK);
    REQUIRE(vx_compact_build(&(vx_compact_desc){.bricks = VX_COMPACT_BRICKS_DICT}, &whole, &cdict, &err) == VX_OK);
    uint64_t bi = 4ull * (ci.geom_words + ci.attr_words), bd = 4ull * (cdict.geom_words + cdict.attr_words);
    CHECKF(cdict.geom_words < ci.geom_words && bd < bi, "the dictionary: %u geometry words against %u", cdict.geom_words,
           ci.geom_words);
    vx_compact_free(&ci), vx_compact_free(&cdict);
    /* between the two: the dictionary whole; under both: paged; over both: the blocks (no second pass) */
    uint64_t budgets[3] = {(bi + bd) / 2, bd * 9 / 10, bi + 1};
    for (int k = 0; k < 3; k++) {
        vx_render_scene_desc sd = {.layout = VX_RENDER_LAYOUT_COMPACT, .memory_budget = budgets[k], .page_level = 4};
        vx_render_scene *ra = NULL, *rb = NULL, *rc = NULL;
        REQUIRE(vx_render_scene_create_ex(gpu, &whole, &sd, &ra, &err) == VX_OK);
        vx_svo_model_reader* rd = NULL;
        REQUIRE(vx_svo_reader_open(NULL, path, &rd, &err) == VX_OK);
        vx_result r = vx_render_scene_create_reader(gpu, rd, &sd, &rb, &err);
        CHECKF(r == VX_OK, "budget %llu: %s", (unsigned long long)budgets[k], err.msg);
        vx_svo_reader_close(rd);
        vx_compact_scene c;
        REQUIRE(vx_svo_reader_open(NULL, path, &rd, &err) == VX_OK);
        REQUIRE(vx_compact_build_reader(&(vx_compact_desc){.attr_regions = true}, rd, &c, &err) == VX_OK);
        vx_result r2 = vx_render_scene_create_compact(gpu, rd, &c, 0, &sd, &rc, &err);
        CHECKF(r2 == VX_OK, "budget %llu, built first: %s", (unsigned long long)budgets[k], err.msg);
        vx_svo_reader_close(rd);
        /* AUTO's choice made before the device (vx_render_compact_auto_bricks, as svo_render makes it), then
         * create_compact told so (bricks_decided): the same layout and frames, no third pass */
        vx_render_scene* rd3 = NULL;
        REQUIRE(vx_svo_reader_open(NULL, path, &rd, &err) == VX_OK);
        REQUIRE(vx_compact_build_reader(&(vx_compact_desc){.attr_regions = true}, rd, &c, &err) == VX_OK);
        uint32_t passes = 0;
        vx_result r3 = vx_render_compact_auto_bricks(rd, &sd, vx_render_scene_budget(gpu, &sd), &c, &passes, &err);
        CHECKF(r3 == VX_OK && passes == (k == 2 ? 1u : 2u), "budget %d, decided first: %u passes, %s", k, passes, err.msg);
        vx_render_scene_desc sdd = sd;
        sdd.bricks_decided = true, sdd.file_passes = passes;
        if (r3 == VX_OK) r3 = vx_render_scene_create_compact(gpu, rd, &c, 0, &sdd, &rd3, &err);
        else vx_compact_free(&c);
        CHECKF(r3 == VX_OK, "budget %d, decided first: %s", k, err.msg);
        vx_svo_reader_close(rd);
        vx_render_layout_info la, lb, lc, ld = {0};
        vx_render_scene_layout(ra, &la);
        vx_render_scene_layout(rb, &lb);
        vx_render_scene_layout(rc, &lc);
        vx_render_scene_layout(rd3, &ld);
        CHECKF(!r3 && ld.brick_dict == la.brick_dict && ld.compact_bytes == la.compact_bytes && ld.bytes == la.bytes &&
                   ld.pages == la.pages && ld.file_passes == passes,
               "budget %d, decided first: dictionary %d, %llu bytes, %u passes", k, (int)ld.brick_dict,
               (unsigned long long)ld.bytes, ld.file_passes);
        if (!r3 && k != 1) {
            vx_render_desc d = {.width = 80, .height = 60, .mode = VX_RENDER_ALBEDO, .want_hits = true};
            vx_render_image a = {0}, b = {0};
            REQUIRE(vx_render_frame(ra, &d, &a, &err) == VX_OK);
            REQUIRE(vx_render_frame(rd3, &d, &b, &err) == VX_OK);
            CHECKF(differ(&a, &b, "auto bricks, decided first") == 0, "budget %d: the frames differ", k);
            vx_render_image_free(&a), vx_render_image_free(&b);
        }
        vx_render_scene_destroy(rd3);
        CHECKF(la.brick_dict == (k == 0) && la.pages == (k == 1 ? la.pages : 0) && (k != 1 || la.pages > 1),
               "budget %d: create_ex's layout: dictionary %d, %u pages", k, (int)la.brick_dict, la.pages);
        CHECKF(!r && lb.brick_dict == la.brick_dict && lb.compact_bytes == la.compact_bytes && lb.geom_bytes == la.geom_bytes &&
                   lb.bytes == la.bytes && lb.pages == la.pages,
               "budget %d: from the reader: dictionary %d, %llu bytes, %u pages against %d, %llu, %u", k, (int)lb.brick_dict,
               (unsigned long long)lb.bytes, lb.pages, (int)la.brick_dict, (unsigned long long)la.bytes, la.pages);
        CHECKF(!r2 && lc.brick_dict == la.brick_dict && lc.compact_bytes == la.compact_bytes && lc.bytes == la.bytes &&
                   lc.pages == la.pages,
               "budget %d: built first: dictionary %d, %llu bytes against %d, %llu", k, (int)lc.brick_dict,
               (unsigned long long)lc.bytes, (int)la.brick_dict, (unsigned long long)la.bytes);
        CHECKF(lb.file_passes == (k == 2 ? 1u : 2u) && lc.file_passes == lb.file_passes, "budget %d: %u and %u passes", k,
               lb.file_passes, lc.file_passes);
        if (!r && !r2 && k == 1) {
            /* the pages keep their bricks in blocks: the pool holds the view of one model, not the scene */
            vx_render_camera cam = {.set = true, .fov = 30, .eye = {16, -30, 60}, .target = {16, 16, 0}};
            paged_same_view(ra, rb, true, &cam);
            vx_render_scene_destroy(ra);
            ra = NULL;
            REQUIRE(vx_render_scene_create_ex(gpu, &whole, &sd, &ra, &err) == VX_OK);
            paged_same_view(ra, rc, true, &cam);
        } else if (!r && !r2) {
            for (int view = 0; view < 2; view++) {
                vx_render_desc d = {.width = 80, .height = 60, .mode = view ? VX_RENDER_COLOR : VX_RENDER_ALBEDO,
                                    .want_hits = true};
                vx_render_image a = {0}, b = {0}, c2 = {0};
                REQUIRE(vx_render_frame(ra, &d, &a, &err) == VX_OK);
                REQUIRE(vx_render_frame(rb, &d, &b, &err) == VX_OK);
                REQUIRE(vx_render_frame(rc, &d, &c2, &err) == VX_OK);
                uint32_t hit = 0;
                for (uint32_t i = 0; i < a.width * a.height; i++) hit += a.hits[i].instance != VX_RENDER_NO_HIT;
                CHECKF(hit > a.width * a.height / 10, "view %d: %u pixels hit", view, hit);
                CHECKF(differ(&a, &b, "auto bricks, reader") == 0 && differ(&a, &c2, "auto bricks, built first") == 0,
                       "budget %d view %d: the frames differ", k, view);
                vx_render_image_free(&a), vx_render_image_free(&b), vx_render_image_free(&c2);
            }
        }
        vx_render_scene_destroy(ra);
        vx_render_scene_destroy(rb);
        vx_render_scene_destroy(rc);
    }
    /* the file cut after the first pass: the second fails, naming the file; nothing is left (ASan) */
    vx_svo_model_reader* rd = NULL;
    vx_compact_scene c;
    vx_render_scene* rs = NULL;
    REQUIRE(vx_svo_reader_open(NULL, path, &rd, &err) == VX_OK);
    REQUIRE(vx_compact_build_reader(&(vx_compact_desc){.attr_regions = true}, rd, &c, &err) == VX_OK);
    REQUIRE(truncate(path, 300) == 0);
    vx_render_scene_desc sd = {.layout = VX_RENDER_LAYOUT_COMPACT, .memory_budget = (bi + bd) / 2};
    vx_result r = vx_render_scene_create_compact(gpu, rd, &c, 0, &sd, &rs, &err);
    CHECKF(r == VX_ERR_TRUNCATED && !rs && strstr(err.msg, path), "%d: %s", (int)r, err.msg);
    vx_svo_reader_close(rd);
    vx_svo_scene_free(&whole);
}

/* VX_GPU_MEMORY_LOG=1: the device's memory types and each buffer's allocation reach the logger (how batch 1 of
 * branch load2 compared the two paths' buffers on the H200); without it, nothing. */
typedef struct mem_lines {
    uint32_t types, geometry, other;
} mem_lines;
static void mem_log(void* user, vx_log_level level, const char* id, const char* msg) {
    (void)level;
    mem_lines* m = user;
    if (strcmp(id, "gpu.memory") != 0) return;
    if (!strncmp(msg, "type ", 5)) m->types++;
    else if (strstr(msg, "'compact geometry'") && strstr(msg, ": type ") && strstr(msg, "heap ")) m->geometry++;
    else m->other++;
}

static void test_memory_log(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    vx_svo_scene s;
    make_many(&s, 5);
    for (int on = 0; on < 2; on++) {
        mem_lines m = {0};
        vx_logger lg = {mem_log, &m};
        if (on) setenv("VX_GPU_MEMORY_LOG", "1", 1);
        vx_gpu* g = NULL;
        vx_error err = {0};
        vx_result r = vx_gpu_create(&(vx_gpu_desc){.logger = &lg}, &g, &err);
        unsetenv("VX_GPU_MEMORY_LOG");
        REQUIRE(r == VX_OK);
        vx_render_scene* rs = NULL;
        REQUIRE(vx_render_scene_create_ex(g, &s, &(vx_render_scene_desc){.layout = VX_RENDER_LAYOUT_COMPACT}, &rs, &err) ==
                VX_OK);
        vx_render_scene_destroy(rs);
        vx_gpu_destroy(g);
        if (on) CHECKF(m.types >= 1 && m.geometry == 1 && m.other > 5, "%u types, %u geometry, %u others", m.types, m.geometry, m.other);
        else CHECKF(m.types + m.geometry + m.other == 0, "%u lines without the variable", m.types + m.geometry + m.other);
    }
    vx_svo_scene_free(&s);
}

int main(void) {
    snprintf(g_dir, sizeof g_dir, "/tmp/vx_load_gpuXXXXXX");
    if (!mkdtemp(g_dir)) return 1;
    gpu_skip = vx_test_gpu_open((vx_gpu_desc){0}, false, &gpu);
    RUN(test_same_frames);
    RUN(test_damaged);
    RUN(test_built_first);
    RUN(test_auto_bricks);
    RUN(test_memory_log);
    vx_gpu_destroy(gpu);
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf %s", g_dir);
    if (system(cmd) != 0) fprintf(stderr, "could not remove %s\n", g_dir);
    return vx_test_finish();
}
