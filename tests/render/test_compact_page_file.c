/* tests/render/test_compact_page_file.c - paging from files (issue 18: the
 * file source, render/compact_page.c vx_compact_page_build_reader and the
 * host cache; render/compact_gpu.c's service through it), on lavapipe.
 *
 * The scene is written to a file (range-coded and split NODE forms). From
 * a model reader, the paged layout's page table equals the one cut from the
 * whole layout in memory (each page's model, cube, cells, size and mean
 * colour), and every page image the host cache hands out, cut from its
 * model read again from the file, equals the in-memory cut's word for word,
 * also after the cache's byte budget evicted it and it was cut again. On
 * the GPU, a fly-through with the file source (a host budget of a third of
 * the pages' bytes, a pool of a quarter) renders the in-memory pager's
 * frames pixel for pixel (instance, cell, t bits, colour, flags) and the
 * same page counts frame by frame; at a still close-up both converge to
 * the whole layout's image; all resident pages evicted come back (from the
 * cache or the file) to the same image. Through the render scene
 * (vx_render_scene_create_reader with host_budget): the frames of
 * create_ex's in-memory pager under the same budget, frame by frame; a file
 * cut short mid-run fails the next frame that needs a page from it
 * (VX_ERR_TRUNCATED naming the file), again on the next frame, never a
 * crash, and the scene is destroyed cleanly. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "render/compact.h"
#include "tests/gpu_test.h"
#include "tests/render/page_scenes.h"
#include "tests/render/scenes.h"
#include "tests/test.h"

static vx_gpu* gpu;
static const char* gpu_skip;
static char g_dir[64];

/* Four models (an RGBA shell, random palette models, one small enough to
 * stay in the top at level 4), five instances, two rotated. */
static void make_scene(vx_svo_scene* s) {
    vx_svo_model m[4];
    REQUIRE(tp_shell_model(&m[0], 64, 3) == VX_OK);
    REQUIRE(ts_random_model(&m[1], 48, 40, 44, 30, 2) == VX_OK);
    REQUIRE(ts_random_model(&m[2], 20, 20, 20, 50, 5) == VX_OK);
    REQUIRE(ts_random_model(&m[3], 12, 9, 14, 40, 8) == VX_OK);
    static const double rot[9] = {0.36, -0.48, 0.8, 0.8, 0.6, 0, -0.48, 0.64, 0.6};
    vx_svo_instance in[6] = {ts_inst(0, NULL, 0, 0, 0),       ts_inst(1, rot, 90, 10, 0),  ts_inst(0, rot, -80, 20, 40),
                             ts_inst(2, NULL, 10, 80, -30), ts_inst(1, NULL, 30, -70, 20), ts_inst(3, NULL, -40, -40, -40)};
    ts_scene(s, m, 4, in, 6);
}

static bool same_page(const vx_compact_page* a, const vx_compact_page* b) {
    return a->model == b->model && !memcmp(a->cube, b->cube, sizeof a->cube) && a->first == b->first && a->cells == b->cells &&
           a->rgba == b->rgba && a->slots == b->slots && a->n3 == b->n3 && a->words == b->words;
}

/* The scene of make_scene written to g_dir/name (the default form) */
static bool scene_file(vx_svo_scene* s, const char* name, char path[128]) {
    make_scene(s);
    snprintf(path, 128, "%s/%s", g_dir, name);
    vx_error err = {0};
    vx_result r = vx_svo_write_file(NULL, s, path, &err);
    CHECKF(r == VX_OK, "%s: %s", path, err.msg);
    return r == VX_OK;
}

/* A frame of the in-memory pager cm and of the file source cf (what names
 * it): the pixels that differ and whether the page counts do (added to
 * *wrong, *stats_differ); their stats in sa, sb; cf's image kept in *b
 * where b is not NULL. */
static vx_result frame_pair(vx_compact_gpu* cm, vx_compact_gpu* cf, const vx_render_desc* d, const char* what, uint32_t* wrong,
                            uint32_t* stats_differ, vx_compact_page_stats* sa, vx_compact_page_stats* sb, vx_render_image* b) {
    vx_error err = {0};
    vx_render_image x = {0}, y = {0};
    vx_result r = vx_compact_gpu_frame(cm, d, &x, &err);
    if (!r) r = vx_compact_gpu_frame(cf, d, &y, &err);
    CHECKF(r == VX_OK, "%s: %s", what, err.msg);
    if (!r) {
        *wrong += tp_differ(&x, &y, what, "file");
        vx_compact_gpu_page_stats(cm, sa);
        vx_compact_gpu_page_stats(cf, sb);
        *stats_differ += sa->coarse != sb->coarse || sa->loaded != sb->loaded || sa->evicted != sb->evicted ||
                         sa->resident != sb->resident || sa->refused != sb->refused || sa->used_bytes != sb->used_bytes;
    }
    vx_render_image_free(&x);
    if (b && !r) *b = y;
    else vx_render_image_free(&y);
    return r;
}

/* The file source's table and images against the in-memory cut, on the CPU. */
static void check_images(const vx_svo_scene* s, const char* path, uint32_t lp, const char* what) {
    vx_error err = {0};
    vx_compact_scene c;
    vx_compact_paged pm, pf;
    REQUIRE(vx_compact_build(NULL, s, &c, &err) == VX_OK);
    REQUIRE(vx_compact_page_build(&c, lp, NULL, &pm, &err) == VX_OK);
    vx_svo_model_reader* rd = NULL;
    REQUIRE(vx_svo_reader_open(NULL, path, &rd, &err) == VX_OK);
    vx_result r = vx_compact_page_build_reader(&(vx_compact_page_desc){.page_level = lp}, rd, &pf, &err);
    CHECKF(r == VX_OK, "%s: %s", what, err.msg);
    if (r) goto out;
    CHECK(pf.data == NULL && pf.reader == rd && pf.max_page_words == pm.max_page_words && pf.model_count == pm.model_count);
    CHECKF(pf.page_count == pm.page_count && pm.page_count > 8, "%s: %u pages from the file, %u in memory", what,
           pf.page_count, pm.page_count);
    uint32_t bad = 0;
    for (uint32_t k = 0; k < pm.page_count && k < pf.page_count; k++) bad += !same_page(&pm.pages[k], &pf.pages[k]);
    for (uint32_t i = 0; i < pm.model_count; i++) {
        const vx_compact_model *a = &pm.models[i], *b = &pf.models[i];
        bad += a->depth != b->depth || a->voxels != b->voxels || a->attr_kind != b->attr_kind || a->block != b->block ||
               a->attr_words != b->attr_words;
    }
    CHECKF(bad == 0, "%s: %u pages or models differ from the in-memory cut", what, bad);
    CHECK(!memcmp(pf.palette_used, c.palette_used, sizeof c.palette_used));
    /* the models cut on one thread and on three: the same top and table (the parts merged in model order) */
    for (uint32_t t = 1; t <= 3; t += 2) {
        vx_svo_model_reader* r2 = NULL;
        vx_compact_paged pt;
        REQUIRE(vx_svo_reader_open(NULL, path, &r2, &err) == VX_OK);
        REQUIRE(vx_compact_page_build_reader(&(vx_compact_page_desc){.page_level = lp, .threads = t}, r2, &pt, &err) == VX_OK);
        uint32_t pd = 0;
        for (uint32_t k = 0; k < pf.page_count && k < pt.page_count; k++)
            pd += !same_page(&pt.pages[k], &pf.pages[k]) || pt.pages[k].top_slot != pf.pages[k].top_slot;
        CHECKF(pt.top_words == pf.top_words && !memcmp(pt.top, pf.top, 4ull * pf.top_words) && pt.page_count == pf.page_count &&
                   !pd && !memcmp(pt.models, pf.models, pf.model_count * sizeof *pf.models),
               "%s: the top cut on %u threads differs (%u of %u words, %u pages)", what, t, pt.top_words, pf.top_words, pd);
        vx_compact_paged_free(&pt);
        vx_svo_reader_close(r2);
    }
    /* the images through a cache of a third of their bytes: shuffled, in batches, twice */
    uint64_t bytes = 4 * pm.data_words;
    vx_compact_page_cache* pc = NULL;
    REQUIRE(vx_compact_page_cache_create(&pf, bytes / 3, NULL, &pc, &err) == VX_OK);
    uint32_t n = pm.page_count, seed = 5;
    uint32_t* order = malloc(2 * n * sizeof *order);
    uint32_t** dst = malloc(2 * n * sizeof *dst);
    REQUIRE(order && dst);
    for (uint32_t k = 0; k < 2 * n; k++) order[k] = k % n;
    for (uint32_t k = 2 * n; k > 1; k--) {
        uint32_t j = ts_rng(&seed) % k, t = order[k - 1];
        order[k - 1] = order[j], order[j] = t;
    }
    uint32_t wrong = 0;
    for (uint32_t at = 0; at < 2 * n && !r;) {
        uint32_t batch = 1 + ts_rng(&seed) % 7;
        if (batch > 2 * n - at) batch = 2 * n - at;
        /* a page once per batch (as the service asks) */
        uint32_t nb = 0;
        for (uint32_t i = 0; i < batch; i++) {
            bool dup = false;
            for (uint32_t j = 0; j < nb; j++) dup = dup || order[at + j] == order[at + i];
            if (!dup) order[at + nb++] = order[at + i];
        }
        for (uint32_t i = 0; i < nb; i++) dst[i] = calloc(pm.pages[order[at + i]].words, 4);
        r = vx_compact_page_cache_get(pc, order + at, nb, dst, &err);
        CHECKF(r == VX_OK, "%s: %s", what, err.msg);
        for (uint32_t i = 0; i < nb; i++) {
            const vx_compact_page* pg = &pm.pages[order[at + i]];
            if (!r && memcmp(dst[i], pm.data + pg->offset, 4ull * pg->words) && wrong++ < 3)
                fprintf(stderr, "  %s: page %u's image differs from the in-memory cut's\n", what, order[at + i]);
            free(dst[i]);
        }
        at += batch;
    }
    vx_compact_cache_stats cs;
    vx_compact_page_cache_stats(pc, &cs);
    CHECKF(wrong == 0, "%s: %u images differ", what, wrong);
    CHECKF(cs.evictions > 0 && cs.hits > 0 && cs.file_pages > n && cs.peak_bytes <= bytes / 3 && cs.models > 0,
           "%s: cache %llu hits, %llu cut from the file (%llu models), %llu evictions, peak %llu of %llu", what,
           (unsigned long long)cs.hits, (unsigned long long)cs.file_pages, (unsigned long long)cs.models,
           (unsigned long long)cs.evictions, (unsigned long long)cs.peak_bytes, (unsigned long long)(bytes / 3));
    printf("  %s, level %u: %u pages (%.1f KB), top %.1f KB (in memory %.1f KB); cache of %.1f KB: %llu hits, %llu "
           "cut from the file (%llu model reads), %llu evictions\n",
           what, lp, n, bytes / 1e3, pf.top_words * 4e-3, pm.top_words * 4e-3, bytes / 3e3, (unsigned long long)cs.hits,
           (unsigned long long)cs.file_pages, (unsigned long long)cs.models, (unsigned long long)cs.evictions);
    /* a page past the table: refused */
    uint32_t none = n, *d0 = dst[0];
    CHECK(vx_compact_page_cache_get(pc, &none, 1, &d0, &err) == VX_ERR_INVALID_ARG);
    free(order);
    free(dst);
    vx_compact_page_cache_destroy(pc);
    vx_compact_paged_free(&pf);
out:
    vx_svo_reader_close(rd);
    vx_compact_paged_free(&pm);
    vx_compact_free(&c);
}

static void test_images(void) {
    vx_svo_scene s;
    make_scene(&s);
    static const struct {
        const char* name;
        vx_write_desc d;
    } forms[] = {{"range-coded", {0}}, {"split", {.testing.split_words = 1}}};
    for (size_t f = 0; f < 2; f++) {
        char path[128];
        snprintf(path, sizeof path, "%s/img%zu.svo", g_dir, f);
        vx_error err = {0};
        REQUIRE(vx_svo_write_file(&forms[f].d, &s, path, &err) == VX_OK);
        check_images(&s, path, 4, forms[f].name);
        check_images(&s, path, 3, forms[f].name);
    }
    vx_svo_scene_free(&s);
}

/* The in-memory pager and the file source side by side on the GPU. */
static void test_fly(void) {
    if (gpu_skip) SKIP(gpu_skip);
    vx_svo_scene s;
    char path[128];
    if (!scene_file(&s, "fly.svo", path)) return;
    vx_error err = {0};
    const uint32_t lp = 4;
    vx_render_scene* rs = NULL;
    vx_compact_scene c;
    vx_compact_paged pm, pf;
    vx_compact_gpu *full = NULL, *cm = NULL, *cf = NULL;
    REQUIRE(vx_render_scene_create_ex(gpu, &s, &(vx_render_scene_desc){.layout = VX_RENDER_LAYOUT_PLAIN}, &rs, &err) ==
            VX_OK);
    REQUIRE(vx_compact_build(NULL, &s, &c, &err) == VX_OK);
    REQUIRE(vx_compact_gpu_create(rs, &s, &c, &full, &err) == VX_OK);
    REQUIRE(vx_compact_page_build(&c, lp, NULL, &pm, &err) == VX_OK);
    vx_svo_model_reader* rd = NULL;
    REQUIRE(vx_svo_reader_open(NULL, path, &rd, &err) == VX_OK);
    REQUIRE(vx_compact_page_build_reader(&(vx_compact_page_desc){.page_level = lp}, rd, &pf, &err) == VX_OK);
    uint64_t page_bytes = 4 * pm.data_words, pool = page_bytes / 4, host = page_bytes / 3;
    uint32_t npages = pm.page_count;
    if (pool < 4ull * pm.max_page_words) pool = 4ull * pm.max_page_words;
    REQUIRE(vx_compact_gpu_create_paged(rs, &s, &pm, pool, &cm, &err) == VX_OK);
    REQUIRE(vx_compact_gpu_create_paged_ex(rs, vx_svo_reader_scene(rd), &pf, pool, host, &cf, &err) == VX_OK);
    double lo[3], hi[3];
    vx_svo_scene_world_bounds(&s, lo, hi);
    uint32_t wrong = 0, stats_differ = 0, coarse = 0;
    vx_result r = VX_OK;
    for (int f = 0; f < 16 && !r; f++) {
        vx_render_desc d = tp_view(lo, hi, f / 16.0, f % 4 != 0);
        char what[32];
        snprintf(what, sizeof what, "frame %d", f);
        vx_compact_page_stats sa, sb;
        r = frame_pair(cm, cf, &d, what, &wrong, &stats_differ, &sa, &sb, NULL);
        if (!r) {
            coarse += sb.coarse;
            CHECK(!sa.from_file && sb.from_file && sb.host_bytes <= host && sb.host_peak_bytes <= host);
        }
    }
    vx_compact_page_stats sf;
    vx_compact_gpu_page_stats(cf, &sf);
    CHECKF(wrong == 0 && stats_differ == 0, "fly-through: %u pixels and %u frames' page counts differ from the in-memory pager's",
           wrong, stats_differ);
    /* and pages the service slid together, read back from the pool (branch page2) */
    CHECKF(coarse > 0 && sf.host_evictions > 0 && sf.file_pages > 0 && sf.moved_from_pool > 0,
           "fly-through: %u coarse, %llu host evictions, %llu cut, %llu moved", coarse, (unsigned long long)sf.host_evictions,
           (unsigned long long)sf.file_pages, (unsigned long long)sf.moved_from_pool);
    printf("  fly-through, %u pages (%.1f KB), pool %.1f KB, host cache %.1f KB: %llu pages cut from the file (%llu model "
           "reads), %llu from the cache, %llu evicted from it, peak %.1f KB; %llu moved pages read back from the pool\n",
           npages, page_bytes / 1e3, pool / 1e3, host / 1e3, (unsigned long long)sf.file_pages,
           (unsigned long long)sf.file_models, (unsigned long long)sf.host_hits, (unsigned long long)sf.host_evictions,
           sf.host_peak_bytes / 1e3, (unsigned long long)sf.moved_from_pool);
    /* still: both converge to the whole layout's image; then every resident page out, back to the same image */
    vx_render_desc d = tp_view(lo, hi, 0.3, true);
    d.width = 48, d.height = 32, d.camera.fov = 16;
    vx_render_image ref = {0}, img = {0};
    REQUIRE(vx_compact_gpu_frame(full, &d, &ref, &err) == VX_OK);
    for (int round = 0; round < 2 && !r; round++) {
        vx_compact_page_stats st = {0};
        int f = 0;
        for (; f < 24; f++) {
            vx_render_image_free(&img);
            if ((r = vx_compact_gpu_frame(cf, &d, &img, &err))) break;
            vx_compact_gpu_page_stats(cf, &st);
            if (st.coarse == 0 && st.loaded == 0) break;
        }
        CHECKF(r == VX_OK, "%s", err.msg);
        uint32_t w = tp_differ(&ref, &img, "whole layout", "file");
        CHECKF(st.coarse == 0 && w == 0, "round %d: after %d frames %u coarse, %u pixels differ from the whole layout's", round,
               f + 1, st.coarse, w);
        printf("  still close-up, round %d: converged in %d frames, %u resident; %llu cut from the file, %llu from the cache\n",
               round, f + 1, st.resident, (unsigned long long)st.file_pages, (unsigned long long)st.host_hits);
        if (round == 0)
            for (uint32_t k = 0; k < npages; k++)
                if (vx_compact_gpu_page_slot(cf, k) >= 0) REQUIRE(vx_compact_gpu_page_evict(cf, k, &err) == VX_OK);
    }
    vx_render_image_free(&img);
    vx_render_image_free(&ref);
    CHECKF(vx_gpu_validation_errors(gpu) == 0, "%u validation errors", vx_gpu_validation_errors(gpu));
    vx_compact_gpu_destroy(cf);
    vx_compact_gpu_destroy(cm);
    vx_compact_gpu_destroy(full);
    vx_compact_paged_free(&pm);
    vx_compact_paged_free(&pf);
    vx_svo_reader_close(rd);
    vx_compact_free(&c);
    vx_render_scene_destroy(rs);
    vx_svo_scene_free(&s);
}

/* Through the render scene: create_reader with host_budget against
 * create_ex's in-memory pager under the same budget; then the file cut. */
static void test_render_scene(void) {
    if (gpu_skip) SKIP(gpu_skip);
    vx_svo_scene s;
    char path[128];
    if (!scene_file(&s, "rs.svo", path)) return;
    vx_error err = {0};
    vx_render_scene *rc = NULL, *rm = NULL, *rf = NULL;
    REQUIRE(vx_render_scene_create_ex(gpu, &s, &(vx_render_scene_desc){.layout = VX_RENDER_LAYOUT_COMPACT}, &rc, &err) ==
            VX_OK);
    vx_render_layout_info lc, lm, lf;
    vx_render_scene_layout(rc, &lc);
    uint64_t budget = lc.compact_bytes / 2;
    vx_render_scene_desc dm = {.memory_budget = budget, .page_level = 4, .compact_bricks = VX_RENDER_BRICKS_INLINE};
    REQUIRE(vx_render_scene_create_ex(gpu, &s, &dm, &rm, &err) == VX_OK);
    vx_svo_model_reader* rd = NULL;
    REQUIRE(vx_svo_reader_open(NULL, path, &rd, &err) == VX_OK);
    vx_render_scene_desc df = dm;
    df.host_budget = 16000;
    vx_result r = vx_render_scene_create_reader(gpu, rd, &df, &rf, &err);
    CHECKF(r == VX_OK, "file source: %s", err.msg);
    if (r) goto out;
    vx_render_scene_layout(rm, &lm);
    vx_render_scene_layout(rf, &lf);
    CHECKF(lm.pages > 8 && lf.pages == lm.pages && lf.page_level == 4 && lf.compact_bytes >= lc.compact_bytes &&
               lf.bytes <= budget,
           "pages %u / %u, level %u, %llu bytes of %llu", lm.pages, lf.pages, lf.page_level, (unsigned long long)lf.bytes,
           (unsigned long long)budget);
    double lo[3], hi[3];
    vx_svo_scene_world_bounds(&s, lo, hi);
    uint32_t wrong = 0;
    vx_render_page_stats sm = {0}, sf = {0};
    for (int f = 0; f < 12 && !r; f++) {
        vx_render_desc d = tp_view(lo, hi, f / 12.0, f % 3 != 0);
        vx_render_image a = {0}, b = {0};
        r = vx_render_frame(rm, &d, &a, &err);
        if (!r) r = vx_render_frame(rf, &d, &b, &err);
        CHECKF(r == VX_OK, "frame %d: %s", f, err.msg);
        if (!r) {
            char what[32];
            snprintf(what, sizeof what, "render scene frame %d", f);
            wrong += tp_differ(&a, &b, what, "file");
            vx_render_scene_page_stats(rm, &sm);
            vx_render_scene_page_stats(rf, &sf);
            CHECK(sm.coarse == sf.coarse && sm.resident == sf.resident && sf.from_file && !sm.from_file);
        }
        vx_render_image_free(&a);
        vx_render_image_free(&b);
    }
    CHECKF(wrong == 0, "%u pixels differ from create_ex's pager", wrong);
    printf("  render scene, budget %.1f KB, host %.1f KB: %u pages; %llu cut from the file, %llu from the cache, host peak "
           "%.1f KB\n",
           budget / 1e3, df.host_budget / 1e3, lf.pages, (unsigned long long)sf.file_pages, (unsigned long long)sf.host_hits,
           sf.host_peak_bytes / 1e3);
    /* the file cut short mid-run: the next frame that needs a page from it fails naming the file, and again */
    {
        struct stat st;
        REQUIRE(stat(path, &st) == 0 && truncate(path, 64) == 0);
        int failed = 0;
        for (int f = 0; f < 24 && failed < 2; f++) {
            vx_render_desc d = tp_view(lo, hi, 0.05 + f / 24.0, f % 2);
            vx_render_image b = {0};
            vx_result fr = vx_render_frame(rf, &d, &b, &err);
            if (fr) {
                CHECKF(fr == VX_ERR_TRUNCATED && strstr(err.msg, path) && strstr(err.msg, "cut short"), "%d: %s", (int)fr,
                       err.msg);
                failed++;
            }
            vx_render_image_free(&b);
        }
        CHECKF(failed == 2, "the cut file failed %d frames", failed);
    }
out:
    vx_render_scene_destroy(rf);
    vx_svo_reader_close(rd);
    vx_render_scene_destroy(rm);
    vx_render_scene_destroy(rc);
    vx_svo_scene_free(&s);
}

/* The parallel cuts (issue 18, branch page2): the host cache cuts the models
 * of one request on several threads and cuts the pages a frame requested
 * ahead, on a thread of its own, while the caller works between frames. On
 * the CPU: every page of the scene asked for in one call, on 1 and 4
 * threads, from a cache of a fifth of their bytes, equals the in-memory cut;
 * pages cut ahead (half of them, then asked for with the other half, with
 * pages never cut ahead and pages past the table refused) equal it too, and
 * a cut ahead that the next call does not use is dropped. On the GPU: a
 * close-up whose first service loads every page it needs at once, through
 * a pool smaller than the frame needs (refusals every frame), renders the
 * in-memory pager's frames pixel for pixel and page count for page count,
 * and with a pool that holds them converges to the whole layout's image. */
static void test_parallel(void) {
    vx_svo_scene s;
    char path[128];
    if (!scene_file(&s, "par.svo", path)) return;
    vx_error err = {0};
    const uint32_t lp = 3;
    vx_compact_scene c;
    vx_compact_paged pm;
    REQUIRE(vx_compact_build(NULL, &s, &c, &err) == VX_OK);
    REQUIRE(vx_compact_page_build(&c, lp, NULL, &pm, &err) == VX_OK);
    uint32_t n = pm.page_count;
    uint64_t bytes = 4 * pm.data_words;
    CHECKF(n > 200, "%u pages", n);
    uint32_t* all = malloc(2 * n * sizeof *all); /* a request of up to n / 2 pages cut ahead and n others */
    uint32_t** dst = malloc(2 * n * sizeof *dst);
    REQUIRE(all && dst);
    for (uint32_t t = 1; t <= 4; t += 3) {
        vx_svo_model_reader* rd = NULL;
        vx_compact_paged pf;
        REQUIRE(vx_svo_reader_open(NULL, path, &rd, &err) == VX_OK);
        REQUIRE(vx_compact_page_build_reader(&(vx_compact_page_desc){.page_level = lp, .threads = t}, rd, &pf, &err) == VX_OK);
        CHECK(pf.threads == t && pf.page_count == n);
        vx_compact_page_cache* pc = NULL;
        REQUIRE(vx_compact_page_cache_create(&pf, bytes / 5, NULL, &pc, &err) == VX_OK);
        /* every page at once, in reverse order (the cache sorts them by model) */
        for (uint32_t k = 0; k < n; k++) all[k] = n - 1 - k, dst[k] = calloc(pm.pages[n - 1 - k].words, 4);
        vx_result r = vx_compact_page_cache_get(pc, all, n, dst, &err);
        CHECKF(r == VX_OK, "%u threads: %s", t, err.msg);
        uint32_t wrong = 0;
        for (uint32_t k = 0; k < n; k++) {
            const vx_compact_page* pg = &pm.pages[all[k]];
            wrong += r || memcmp(dst[k], pm.data + pg->offset, 4ull * pg->words) != 0;
            free(dst[k]);
        }
        CHECKF(wrong == 0, "%u threads, all %u pages at once: %u images differ", t, n, wrong);
        /* cut ahead: the odd pages; then asked for all of them (the odd ones from the cuts ahead, or the
         * cache), twice (the second time the cache holds some) */
        uint32_t h = 0, seed = 11 + t;
        for (uint32_t k = 1; k < n; k += 2) all[h++] = k;
        for (int round = 0; round < 2 && !r; round++) {
            vx_compact_page_cache_prefetch(pc, all, h);
            uint32_t m = 0;
            for (uint32_t k = 0; k < n; k++)
                if (ts_rng(&seed) % 3) all[h + m++] = k; /* a page may come twice in one call: once ahead, once not */
            for (uint32_t k = 0; k < h + m; k++) dst[k] = calloc(pm.pages[all[k]].words, 4);
            r = vx_compact_page_cache_get(pc, all, h + m, dst, &err);
            CHECKF(r == VX_OK, "%u threads, round %d: %s", t, round, err.msg);
            wrong = 0;
            for (uint32_t k = 0; k < h + m; k++) {
                const vx_compact_page* pg = &pm.pages[all[k]];
                wrong += r || memcmp(dst[k], pm.data + pg->offset, 4ull * pg->words) != 0;
                free(dst[k]);
            }
            CHECKF(wrong == 0, "%u threads, round %d: %u of %u images differ", t, round, wrong, h + m);
        }
        /* a cut ahead left unused (the next call asks for other pages, or none), a page past the table */
        vx_compact_page_cache_prefetch(pc, all, h);
        uint32_t none = n, *d0 = NULL;
        CHECK(vx_compact_page_cache_get(pc, &none, 1, &d0, &err) == VX_ERR_INVALID_ARG);
        vx_compact_page_cache_prefetch(pc, all, h);
        vx_compact_cache_stats cs;
        vx_compact_page_cache_stats(pc, &cs);
        CHECKF(cs.prefetched > 0 && cs.evictions > 0 && cs.peak_bytes <= bytes / 5,
               "%u threads: %llu cut ahead and used, %llu evictions, peak %llu of %llu", t, (unsigned long long)cs.prefetched,
               (unsigned long long)cs.evictions, (unsigned long long)cs.peak_bytes, (unsigned long long)(bytes / 5));
        printf("  parallel cuts, %u threads: %u pages (%.1f KB); %llu cut from the file (%llu model reads), %llu of them "
               "ahead, %llu from the cache\n",
               t, n, bytes / 1e3, (unsigned long long)cs.file_pages, (unsigned long long)cs.models,
               (unsigned long long)cs.prefetched, (unsigned long long)cs.hits);
        vx_compact_page_cache_destroy(pc); /* with a cut ahead still running: joined */
        vx_compact_paged_free(&pf);
        vx_svo_reader_close(rd);
    }
    free(all);
    free(dst);
    if (gpu_skip) {
        vx_compact_paged_free(&pm);
        vx_compact_free(&c);
        vx_svo_scene_free(&s);
        SKIP(gpu_skip);
    }
    /* on the GPU: a close-up needing many pages at once */
    vx_render_scene* rs = NULL;
    vx_compact_gpu* full = NULL;
    REQUIRE(vx_render_scene_create_ex(gpu, &s, &(vx_render_scene_desc){.layout = VX_RENDER_LAYOUT_PLAIN}, &rs, &err) ==
            VX_OK);
    REQUIRE(vx_compact_gpu_create(rs, &s, &c, &full, &err) == VX_OK);
    double lo[3], hi[3];
    vx_svo_scene_world_bounds(&s, lo, hi);
    vx_render_desc d = tp_view(lo, hi, 0.6, true);
    d.width = 128, d.height = 96;
    vx_render_image ref = {0};
    REQUIRE(vx_compact_gpu_frame(full, &d, &ref, &err) == VX_OK);
    for (int big = 0; big < 2; big++) {
        vx_compact_paged pmc, pf;
        REQUIRE(vx_compact_page_build(&c, lp, NULL, &pmc, &err) == VX_OK);
        vx_svo_model_reader* rd = NULL;
        REQUIRE(vx_svo_reader_open(NULL, path, &rd, &err) == VX_OK);
        REQUIRE(vx_compact_page_build_reader(&(vx_compact_page_desc){.page_level = lp, .threads = 4}, rd, &pf, &err) == VX_OK);
        /* small: an eighth of the pages' bytes (less than the view needs); big: all of them */
        uint64_t pool = big ? bytes + bytes / 4 : bytes / 8;
        if (pool < 4ull * pmc.max_page_words) pool = 4ull * pmc.max_page_words;
        vx_compact_gpu *cm = NULL, *cf = NULL;
        REQUIRE(vx_compact_gpu_create_paged(rs, &s, &pmc, pool, &cm, &err) == VX_OK);
        REQUIRE(vx_compact_gpu_create_paged_ex(rs, vx_svo_reader_scene(rd), &pf, pool, bytes / 6, &cf, &err) == VX_OK);
        uint32_t wrong = 0, stats_differ = 0, most = 0, refused = 0, f = 0;
        vx_compact_page_stats sa = {0}, sb = {0};
        vx_render_image b = {0};
        vx_result r = VX_OK;
        for (; f < 24 && !r; f++) {
            char what[64];
            snprintf(what, sizeof what, "parallel, pool %llu, frame %u", (unsigned long long)pool, f);
            vx_render_image_free(&b);
            r = frame_pair(cm, cf, &d, what, &wrong, &stats_differ, &sa, &sb, &b);
            if (!r) {
                if (sb.loaded > most) most = sb.loaded;
                refused += sb.refused;
            }
            if (f > 2 && sb.loaded == 0) break; /* steady: nothing more fits, or all resident */
        }
        CHECKF(wrong == 0 && stats_differ == 0, "pool %llu: %u pixels and %u frames' page counts differ from the in-memory pager's",
               (unsigned long long)pool, wrong, stats_differ);
        CHECKF(most > 40, "pool %llu: at most %u pages loaded in one service", (unsigned long long)pool, most);
        if (big) {
            uint32_t w = r ? 1 : tp_differ(&ref, &b, "whole layout", "file");
            CHECKF(sb.coarse == 0 && refused == 0 && w == 0, "converged: %u coarse, %u refused, %u pixels differ", sb.coarse,
                   refused, w);
        } else {
            CHECKF(refused > 0 && sb.coarse > 0, "pool %llu: %u refused, %u coarse (the view should need more than the pool)",
                   (unsigned long long)pool, refused, sb.coarse);
        }
        printf("  parallel, pool %.1f KB: %u frames, up to %u pages loaded in one service, %u refused in all, %u coarse at "
               "the end; %llu cut from the file (%llu model reads), %llu of them ahead\n",
               pool / 1e3, f + 1, most, refused, sb.coarse, (unsigned long long)sb.file_pages, (unsigned long long)sb.file_models,
               (unsigned long long)sb.file_prefetched);
        vx_render_image_free(&b);
        vx_compact_gpu_destroy(cf);
        vx_compact_gpu_destroy(cm);
        vx_compact_paged_free(&pf);
        vx_compact_paged_free(&pmc);
        vx_svo_reader_close(rd);
    }
    CHECKF(vx_gpu_validation_errors(gpu) == 0, "%u validation errors", vx_gpu_validation_errors(gpu));
    vx_render_image_free(&ref);
    vx_compact_gpu_destroy(full);
    vx_render_scene_destroy(rs);
    vx_compact_paged_free(&pm);
    vx_compact_free(&c);
    vx_svo_scene_free(&s);
}

int main(void) {
    snprintf(g_dir, sizeof g_dir, "/tmp/vx_pagefileXXXXXX");
    if (!mkdtemp(g_dir)) return 1;
    gpu_skip = vx_test_gpu_open((vx_gpu_desc){0}, true, &gpu);
    RUN(test_images);
    RUN(test_fly);
    RUN(test_render_scene);
    RUN(test_parallel);
    vx_gpu_destroy(gpu);
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf %s", g_dir);
    if (system(cmd) != 0) fprintf(stderr, "could not remove %s\n", g_dir);
    return vx_test_finish();
}
