/* tests/render/test_compact_page.c - the paged compact layout (render/compact.h
 * "pages", render/compact_page.c, the paged half of render/compact_gpu.c and
 * trace_compact.comp; issue 18: scenes bigger than GPU memory), on lavapipe.
 *
 * A pool of a quarter of the pages' bytes. A fly-through renders without
 * error; in every frame each coarse pixel (VX_RENDER_HIT_COARSE) lies in the
 * cube of a page that is not resident (vx_compact_page_at from the top on
 * the host), and each other pixel that hits is a set cell of the full layout
 * (vx_compact_lookup) with that cell's colour (vx_compact_rgba): the pages'
 * own attribute regions decode to the scene's colours. With the camera
 * still at a close-up, the frames converge (no request left) to the image of
 * the whole layout uploaded (vx_compact_gpu_create) and to trace.comp's,
 * pixel for pixel (instance, cell, t bits, colour). All resident pages
 * evicted and loaded again (next fit: elsewhere in the pool) give that image
 * again. A view that needs more pages than the pool holds says so (pages
 * refused, bytes over) and draws the rest coarse. Scenes: generated palette
 * and RGBA models with rotated instances at page levels 3 and 4, and a
 * height field of 11 levels (the two-frame walk) at page level 6, 9 (the
 * default: the rebase level, VX_RENDER_FRAME_LEVELS) and 10. The plain scenes ask for no grids: the compact
 * kernels mirror the octree walk's t bits, the grid walk takes t from its own planes (render.h grid_budget). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "render/compact.h"
#include "tests/gpu_test.h"
#include "tests/render/page_scenes.h"
#include "tests/render/scenes.h"
#include "tests/test.h"

static vx_gpu* gpu;
static const char* gpu_skip;

/* A frame's pixels against the layout on the host: coarse ones in pages not
 * resident, the others set cells with their colours. Returns coarse pixels. */
static uint32_t check_frame(const vx_svo_scene* s, const vx_compact_scene* c, vx_compact_gpu* cg,
                            const vx_render_image* img, const char* name, int frame) {
    const vx_compact_paged* p = vx_compact_gpu_paged(cg);
    uint32_t coarse = 0, bad = 0;
    for (size_t i = 0; i < (size_t)img->width * img->height; i++) {
        const vx_render_hit* h = &img->hits[i];
        if (h->instance == VX_RENDER_NO_HIT) {
            if (h->flags && bad++ < 3) fprintf(stderr, "  %s frame %d pixel %zu: no hit, flags %u\n", name, frame, i, h->flags);
            continue;
        }
        if (h->instance >= s->instance_count) {
            if (bad++ < 3) fprintf(stderr, "  %s frame %d pixel %zu: instance %u\n", name, frame, i, h->instance);
            continue;
        }
        uint32_t m = s->instances[h->instance].model;
        if (h->flags & VX_RENDER_HIT_COARSE) {
            coarse++;
            uint32_t pg = vx_compact_page_at(p, m, h->cell[0], h->cell[1], h->cell[2]);
            if ((pg == UINT32_MAX || vx_compact_gpu_page_slot(cg, pg) >= 0) && bad++ < 3)
                fprintf(stderr, "  %s frame %d pixel %zu: coarse at cell (%u %u %u) of model %u: page %d, slot %lld\n",
                        name, frame, i, h->cell[0], h->cell[1], h->cell[2], m, (int)pg,
                        pg == UINT32_MAX ? -2ll : (long long)vx_compact_gpu_page_slot(cg, pg));
            continue;
        }
        uint32_t idx;
        bool set = vx_compact_lookup(c, m, h->cell[0], h->cell[1], h->cell[2], &idx);
        bool ok = set;
        if (set && c->models[m].attr_kind != VX_COMPACT_ATTR_NONE) {
            uint32_t rgba = vx_compact_rgba(c, m, (uint32_t)idx);
            for (int k = 0; k < 3; k++)
                ok = ok && fabsf(img->pixels[4 * i + k] - (float)((rgba >> (8 * k)) & 0xFFu) / 255.0f) < 1e-6f;
        }
        if (!ok && bad++ < 3)
            fprintf(stderr, "  %s frame %d pixel %zu: cell (%u %u %u) of model %u: set %d, rgb %.4f %.4f %.4f\n", name,
                    frame, i, h->cell[0], h->cell[1], h->cell[2], m, set, img->pixels[4 * i], img->pixels[4 * i + 1],
                    img->pixels[4 * i + 2]);
    }
    CHECKF(bad == 0, "%s frame %d: %u pixels wrong (coarse outside a page not resident, or a cell not set or "
                     "of another colour)",
           name, frame, bad);
    return coarse;
}

static void run(const vx_svo_scene* s, uint32_t page_level, uint32_t pool_div, const char* name) {
    vx_error err = {0};
    vx_render_scene* rs = NULL;
    vx_compact_scene c;
    vx_compact_paged p;
    vx_compact_gpu *full = NULL, *cg = NULL;
    REQUIRE(vx_render_scene_create_ex(gpu, s, &(vx_render_scene_desc){.layout = VX_RENDER_LAYOUT_PLAIN, .grid_budget = VX_RENDER_NO_GRID}, &rs, &err) ==
            VX_OK);
    REQUIRE(vx_compact_build(NULL, s, &c, &err) == VX_OK);
    REQUIRE(vx_compact_gpu_create(rs, s, &c, &full, &err) == VX_OK);
    vx_result r = vx_compact_page_build(&c, page_level, NULL, &p, &err);
    CHECKF(r == VX_OK, "%s: %s", name, err.msg);
    if (r) goto out;
    uint64_t page_bytes = 4 * p.data_words, cells = 0;
    uint32_t npages = p.page_count;
    for (uint32_t k = 0; k < p.page_count; k++) cells += p.pages[k].cells;
    CHECKF(npages >= (pool_div > 1 ? 8u : 2u), "%s: %u pages", name, npages);
    /* (pool_div 1: room for every page, units rounded up) */
    uint64_t pool = pool_div == 1 ? 2 * page_bytes : page_bytes / pool_div;
    if (pool < 4ull * p.max_page_words) pool = 4ull * p.max_page_words;
    printf("  %s, page level %u: %u pages (%llu cells of %u in the first model's), %.1f KB of pages, top %.1f KB, "
           "pool %.1f KB\n",
           name, page_level, npages, (unsigned long long)cells, c.models[0].voxels, page_bytes / 1e3, p.top_words * 4e-3,
           pool / 1e3);
    r = vx_compact_gpu_create_paged(rs, s, &p, pool, &cg, &err);
    CHECKF(r == VX_OK, "%s: %s", name, err.msg);
    if (r) goto out;
    double lo[3], hi[3];
    vx_svo_scene_world_bounds(s, lo, hi);
    /* the fly-through: overviews and close-ups around the scene */
    uint32_t coarse_total = 0, refused_total = 0, loaded_total = 0, evicted_total = 0;
    for (int f = 0; f < 16; f++) {
        vx_render_desc d = tp_view(lo, hi, f / 16.0, f % 4 != 0);
        vx_render_image img = {0};
        r = vx_compact_gpu_frame(cg, &d, &img, &err);
        CHECKF(r == VX_OK, "%s frame %d: %s", name, f, err.msg);
        if (r) break;
        coarse_total += check_frame(s, &c, cg, &img, name, f);
        vx_compact_page_stats st;
        vx_compact_gpu_page_stats(cg, &st);
        CHECK(st.used_bytes <= st.pool_bytes && st.pool_bytes <= pool && st.resident <= st.pages);
        refused_total += st.refused, loaded_total += st.loaded, evicted_total += st.evicted;
        vx_render_image_free(&img);
    }
    printf("    fly-through: %u coarse pixels, %u loads, %u evictions, %u refusals\n", coarse_total, loaded_total,
           evicted_total, refused_total);
    CHECKF(coarse_total > 0 && loaded_total > 0, "%s: the fly-through loaded nothing", name);
    /* still: a close-up converges to the whole layout's image and trace.comp's */
    vx_render_desc d = tp_view(lo, hi, 0.3, true);
    d.width = 48, d.height = 32, d.camera.fov = 16;
    vx_render_image ref = {0}, ref2 = {0}, img = {0};
    REQUIRE(vx_compact_gpu_frame(full, &d, &ref, &err) == VX_OK);
    REQUIRE(vx_render_frame(rs, &d, &ref2, &err) == VX_OK);
    for (int round = 0; round < 2 && !r; round++) {
        int f = 0;
        vx_compact_page_stats st = {0};
        for (; f < 24; f++) {
            vx_render_image_free(&img);
            if ((r = vx_compact_gpu_frame(cg, &d, &img, &err))) break;
            check_frame(s, &c, cg, &img, name, 100 + f);
            vx_compact_gpu_page_stats(cg, &st);
            if (st.coarse == 0 && st.loaded == 0) break;
        }
        CHECKF(r == VX_OK, "%s: %s", name, err.msg);
        CHECKF(st.coarse == 0 && st.refused == 0, "%s round %d: after %d frames still %u pages coarse, %u refused", name,
               round, f, st.coarse, st.refused);
        uint32_t w1 = tp_differ(&ref, &img, "whole layout", "paged"), w2 = tp_differ(&ref2, &img, "trace.comp", "paged");
        CHECKF(w1 == 0 && w2 == 0, "%s round %d: %u and %u of %u pixels differ from the whole layout's and trace.comp's",
               name, round, w1, w2, d.width * d.height);
        printf("    still close-up, round %d: converged in %d frames, %u pages resident\n", round, f + 1, st.resident);
        if (round == 0) {
            /* every resident page out; loaded again, next fit puts them elsewhere */
            int64_t* before = calloc(npages, 8);
            REQUIRE(before);
            for (uint32_t k = 0; k < npages; k++) before[k] = vx_compact_gpu_page_slot(cg, k);
            for (uint32_t k = 0; k < npages; k++)
                if (before[k] >= 0) REQUIRE(vx_compact_gpu_page_evict(cg, k, &err) == VX_OK);
            vx_render_image first = {0};
            REQUIRE(vx_compact_gpu_frame(cg, &d, &first, &err) == VX_OK);
            CHECKF(check_frame(s, &c, cg, &first, name, 200) > 0, "%s: evicted pages drawn without coarse pixels", name);
            vx_render_image_free(&first);
            /* the next round's frames load them again; compare where they went */
            vx_render_image_free(&img);
            REQUIRE(vx_compact_gpu_frame(cg, &d, &img, &err) == VX_OK);
            uint32_t moved = 0, back = 0;
            for (uint32_t k = 0; k < npages; k++)
                if (before[k] >= 0 && vx_compact_gpu_page_slot(cg, k) >= 0)
                    back++, moved += vx_compact_gpu_page_slot(cg, k) != before[k];
            CHECKF(back > 0 && moved > 0, "%s: %u pages back, %u of them elsewhere", name, back, moved);
            printf("    evicted all, loaded again: %u pages back, %u elsewhere\n", back, moved);
            free(before);
        }
    }
    vx_render_image_free(&img);
    vx_render_image_free(&ref);
    vx_render_image_free(&ref2);
    /* an overview that needs more than the pool: it says so */
    {
        vx_render_desc o = tp_view(lo, hi, 0.0, false);
        vx_compact_page_stats st = {0};
        uint32_t refused = 0;
        for (int f = 0; f < 6 && !r; f++) {
            vx_render_image im = {0};
            r = vx_compact_gpu_frame(cg, &o, &im, &err);
            if (!r) check_frame(s, &c, cg, &im, name, 300 + f);
            vx_render_image_free(&im);
            vx_compact_gpu_page_stats(cg, &st);
            refused += st.refused;
        }
        printf("    overview: %u pages coarse, %u refused over 6 frames (%.1f KB over), %u resident\n", st.coarse, refused,
               st.refused_bytes / 1e3, st.resident);
    }
    CHECKF(vx_gpu_validation_errors(gpu) == 0, "%s: %u validation errors", name, vx_gpu_validation_errors(gpu));
out:
    vx_compact_gpu_destroy(cg);
    vx_compact_gpu_destroy(full);
    vx_compact_paged_free(&p);
    vx_compact_free(&c);
    vx_render_scene_destroy(rs);
}

/* The renderer's own choice: AUTO under a budget below the compact layout's
 * bytes pages it (vx_render_layout_info says so); vx_render_frame's frames
 * converge to the plain layout's image where the view's pages fit. */
static void test_render_scene(void) {
    if (gpu_skip) SKIP(gpu_skip);
    vx_svo_model m;
    REQUIRE(tp_shell_model(&m, 64, 3) == VX_OK);
    vx_svo_instance in[2] = {ts_inst(0, NULL, 0, 0, 0), ts_inst(0, NULL, 70, 0, 0)};
    vx_svo_scene s;
    ts_scene(&s, &m, 1, in, 2);
    vx_error err = {0};
    vx_render_scene *rp = NULL, *rc = NULL, *rg = NULL;
    REQUIRE(vx_render_scene_create_ex(gpu, &s, &(vx_render_scene_desc){.layout = VX_RENDER_LAYOUT_PLAIN, .grid_budget = VX_RENDER_NO_GRID}, &rp, &err) ==
            VX_OK);
    REQUIRE(vx_render_scene_create_ex(gpu, &s, &(vx_render_scene_desc){.layout = VX_RENDER_LAYOUT_COMPACT}, &rc, &err) ==
            VX_OK);
    vx_render_layout_info lc, lg;
    vx_render_scene_layout(rc, &lc);
    CHECK(lc.layout == VX_RENDER_LAYOUT_COMPACT && lc.pages == 0 && lc.compact_bytes > 0);
    uint64_t budget = lc.compact_bytes * 3 / 4;
    vx_result r = vx_render_scene_create_ex(gpu, &s, &(vx_render_scene_desc){.memory_budget = budget, .page_level = 4, .grid_budget = VX_RENDER_NO_GRID},
                                            &rg, &err);
    CHECKF(r == VX_OK, "paged: %s", err.msg);
    if (!r) {
        vx_render_scene_layout(rg, &lg);
        CHECKF(lg.layout == VX_RENDER_LAYOUT_COMPACT && lg.pages > 8 && lg.page_level == 4 && lg.bytes <= budget,
               "layout %s, %u pages at level %u, %llu bytes of a budget of %llu", vx_render_layout_name(lg.layout),
               lg.pages, lg.page_level, (unsigned long long)lg.bytes, (unsigned long long)budget);
        /* a view of part of one shell */
        vx_render_desc d = {.width = 64, .height = 48, .mode = VX_RENDER_ALBEDO, .want_hits = true,
                            .camera = {.set = true, .fov = 30, .eye = {20, 28, -30}, .target = {32, 32, 32}}};
        vx_render_image a = {0}, b = {0};
        REQUIRE(vx_render_frame(rp, &d, &a, &err) == VX_OK);
        vx_render_page_stats st = {0};
        int f = 0;
        for (; f < 16; f++) {
            vx_render_image_free(&b);
            REQUIRE(vx_render_frame(rg, &d, &b, &err) == VX_OK);
            vx_render_scene_page_stats(rg, &st);
            if (f == 0) CHECKF(st.coarse > 0 && st.resident == 0, "first frame: %u coarse, %u resident", st.coarse,
                               st.resident);
            if (!st.coarse) break;
        }
        CHECKF(st.coarse == 0 && st.frames == (uint64_t)f + 1 && st.pages == lg.pages, "after %d frames %u pages coarse",
               f + 1, st.coarse);
        CHECK(tp_differ(&a, &b, "plain layout", "paged") == 0);
        printf("  render scene, budget %llu of the compact layout's %llu bytes: %u pages, converged in %d frames\n",
               (unsigned long long)budget, (unsigned long long)lc.compact_bytes, lg.pages, f + 1);
        vx_render_image_free(&a);
        vx_render_image_free(&b);
        /* a budget below the top and the largest page: the whole compact layout, over it */
        vx_render_scene* rt = NULL;
        vx_render_layout_info lt;
        REQUIRE(vx_render_scene_create_ex(gpu, &s, &(vx_render_scene_desc){.memory_budget = 64, .page_level = 4, .grid_budget = VX_RENDER_NO_GRID}, &rt,
                                          &err) == VX_OK);
        vx_render_scene_layout(rt, &lt);
        CHECK(lt.layout == VX_RENDER_LAYOUT_COMPACT && lt.pages == 0 && lt.bytes > lt.budget);
        vx_render_scene_destroy(rt);
    }
    vx_render_scene_destroy(rg);
    vx_render_scene_destroy(rc);
    vx_render_scene_destroy(rp);
    vx_svo_scene_free(&s);
}

static void test_generated(void) {
    if (gpu_skip) SKIP(gpu_skip);
    vx_svo_model m[3];
    REQUIRE(tp_shell_model(&m[0], 64, 3) == VX_OK);
    REQUIRE(ts_random_model(&m[1], 48, 40, 44, 30, 2) == VX_OK);
    REQUIRE(ts_random_model(&m[2], 20, 20, 20, 50, 5) == VX_OK);
    static const double rot[9] = {0.36, -0.48, 0.8, 0.8, 0.6, 0, -0.48, 0.64, 0.6};
    vx_svo_instance in[5] = {ts_inst(0, NULL, 0, 0, 0), ts_inst(1, rot, 90, 10, 0), ts_inst(0, rot, -80, 20, 40),
                             ts_inst(2, NULL, 10, 80, -30), ts_inst(1, NULL, 30, -70, 20)};
    vx_svo_scene s;
    ts_scene(&s, m, 3, in, 5);
    run(&s, 4, 4, "shell and random models, 5 instances");
    run(&s, 3, 4, "shell and random models, 5 instances");
    vx_svo_scene_free(&s);
}

/* A height field of 11 levels (the two-frame walk), RGBA. */
static void test_deep(void) {
    if (gpu_skip) SKIP(gpu_skip);
    uint32_t sx = 1100, sz = 256, sy = 48, seed = 9;
    size_t n = 0;
    uint64_t* keys = malloc((size_t)sx * sz * 2 * 8);
    uint32_t* rgba = malloc((size_t)sx * sz * 2 * 4);
    REQUIRE(keys && rgba);
    for (uint32_t z = 0; z < sz; z++)
        for (uint32_t x = 0; x < sx; x++) {
            uint32_t y = (uint32_t)((sy - 2) * (0.5 + 0.3 * sin(x * 0.02) * cos(z * 0.07))) + ts_rng(&seed) % 2;
            for (uint32_t k = 0; k < 2; k++) {
                keys[n] = vx_svo_morton(x, y + k, z);
                rgba[n++] = 0xFF000000u | ((x >> 2) & 0xFFu) | ((z & 0xFFu) << 8) | ((y * 5 & 0xFFu) << 16);
            }
        }
    vx_svo_model m;
    vx_error err = {0};
    vx_svo_voxels v = {.size = {sx, sy, sz}, .count = n, .keys = keys, .attrs = VX_ATTR_RGBA8, .rgba = rgba};
    REQUIRE(vx_svo_build_model(NULL, &v, &m, NULL, &err) == VX_OK);
    free(keys);
    free(rgba);
    REQUIRE(m.depth == 11);
    vx_svo_instance in[2] = {ts_inst(0, NULL, 0, 0, 0), ts_inst(0, NULL, 0, 0, 300)};
    vx_svo_scene s;
    ts_scene(&s, &m, 1, in, 2);
    run(&s, 6, 4, "height field of 11 levels");
    /* pages at the rebase level (the default page level, VX_RENDER_FRAME_LEVELS) and above it: a pool for all of them */
    run(&s, VX_RENDER_FRAME_LEVELS, 1, "height field of 11 levels");
    run(&s, 10, 1, "height field of 11 levels");
    vx_svo_scene_free(&s);
}

int main(void) {
    gpu_skip = vx_test_gpu_open((vx_gpu_desc){0}, true, &gpu);
    RUN(test_generated);
    RUN(test_deep);
    RUN(test_render_scene);
    vx_gpu_destroy(gpu);
    return vx_test_finish();
}
