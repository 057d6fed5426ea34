/* bench/compact_bench.c - GPU bytes per voxel of the compact layout
 * (render/compact.h, issue 18) beside the layout the tracer uploads today
 * (render_scene.c: the .svo node words plus one 4-byte RGBA record per
 * attribute record), for .vox / .svo scenes and the tracer benchmarks'
 * terrain. One markdown row per scene and attribute block size.
 *
 * With --gpu WxH (a build with Vulkan) it also traces each scene with both
 * kernels on the same render scene (trace.comp over the .svo words,
 * trace_compact.comp over the compact layout), albedo, the default framing
 * and a close-up from inside the bounds: rays/s from the median of --reps
 * timed dispatches per round, median of 5 rounds (the kernels' order rotated
 * each round, after 0.5 s of warm-up dispatches), and the pixels
 * whose instance, cell, t or colour differ (a frame with hits), and whose
 * colour differs in a frame without (the kernels that write no hits, as
 * the timed ones).
 *
 * --paged LP (before the files) also times the paged layout cut at page level LP
 * (render/compact.h "pages") with a pool for all its pages, after frames
 * until every page the view needs is resident: the cost of the paging
 * hooks in the kernel. --fly N with --budget MB (and --paged LP) instead flies
 * N frames around each scene with a pool of MB: per frame the wall time
 * (the service between frames, the trace, the read-back), the GPU time of the
 * trace, the pages drawn coarse, loaded, evicted and refused, the pool's use.
 *
 * --shader-stats (before --gpu) prints the driver's statistics of both
 * kernels (registers, spills, instructions) as they are created; each row
 * gives the mean traversal steps per ray of both (the hits' iterations).
 *
 * --geometry (before the files): the layout of the scenes with their
 * attributes left out, so that only the geometry DAG is built (it never
 * sees a colour, so its words are those of the full layout): the geometry
 * bytes of scenes whose attribute blocks would take too long to code
 * (the 16384^3 goal).
 *
 * --res N (before the files; a build with the glTF reader): meshes (.glb,
 * .gltf) are voxelized in the process at N along their longest side, with
 * no colours under --geometry (vx_conv_mesh_desc.no_color: the same cells),
 * on every core, or on the GPU with --mesh-gpu (a build with Vulkan): no
 * .svo file of a scene too large to write and read back within a run. The
 * conversion's time is printed before the row.
 *
 * --bricks inline|dict|both (before the files): the geometry's bricks in
 * their blocks (the default), in the brick dictionary, or the bytes rows of
 * both (--gpu rows: the first). --levels: after each bytes row, the
 * geometry's bytes by level and field, and what the same blocks take in
 * main's form before the seventh step (rank words at levels >= 3).
 *
 * Usage: compact_bench [--blocks 0,16,64,...] (0: automatic, the default) [--bricks inline|dict|both] [--levels]
 *                      [--shader-stats] [--gpu WxH] [--reps N]
 *                      [--geometry] [--res N [--mesh-gpu]] [--terrain EXTENT] [FILE.vox|FILE.svo|FILE.glb ...] */
#define _POSIX_C_SOURCE 200809L /* setenv */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench/bench_compact_view.h"
#include "bench/bench_load.h"
#include "bench/bench_terrain.h"
#include "render/compact.h"
#ifdef VX_BENCH_HAVE_MESH
#include "convert/mesh.h"
#endif
#ifdef VX_BENCH_HAVE_MESH_GPU
#include "convert/mesh_gpu.h"
#endif
#ifdef VX_BENCH_HAVE_VULKAN
#include "bench/bench_stats.h"
#include "render/testing.h"

static void print_stats(void* user, vx_log_level level, const char* id, const char* msg) {
    (void)user, (void)level;
    if (!strcmp(id, "gpu.shader_stats")) printf("stats: %s\n", msg);
    if (!strcmp(id, "gpu.validation")) printf("validation: %s\n", msg);
    fflush(stdout);
}

#define ROUNDS 5 /* timing rounds per view; medians */
/* --start-ab: also the whole layout's kernel with its primary rays' starts
 * below the root off (every walk from the root) and with starts of one push
 * too (vx__compact_gpu_start_min 1), in the same rounds: the start's own
 * effect beside trace.comp in one process (rows ", from the root", ", starts
 * from one push") */
static bool g_start_ab;
/* --start-on: the starts below the root on for both kernels even on a CPU
 * device (lavapipe, whose default is off): their steps per ray there */
static bool g_start_on;

/* Both kernels on s: one markdown row per view. */
/* The camera of frame f of n of a fly-through: around the scene's centre at
 * three distances, looking at points near it. */
static vx_render_desc fly_view(const double lo[3], const double hi[3], uint32_t W, uint32_t H, uint32_t f, uint32_t n) {
    vx_render_desc d = {.width = W, .height = H, .mode = VX_RENDER_ALBEDO};
    double u = (double)f / n, a = 6.2831853 * u, dist = 0.35 + 0.5 * (0.5 + 0.5 * cos(3 * a));
    d.camera.set = true;
    d.camera.fov = 60;
    for (int k = 0; k < 3; k++) {
        double mid = 0.5 * (lo[k] + hi[k]), ext = hi[k] - lo[k];
        d.camera.target[k] = mid + 0.1 * ext * sin(a + k);
        d.camera.eye[k] = mid + dist * ext * (k == 1 ? 0.4 : (k == 0 ? cos(a) : sin(a)));
    }
    return d;
}

static void fly_rows(vx_gpu* g, const char* name, const vx_svo_scene* s, uint32_t W, uint32_t H, uint32_t lp,
                     uint64_t budget, uint32_t frames) {
    vx_error err = {0};
    vx_render_scene* rs = NULL;
    vx_compact_scene c;
    vx_compact_paged p;
    vx_compact_gpu* cg = NULL;
    double t0 = vx_time_now();
    if (vx_render_scene_create_ex(g, s, &(vx_render_scene_desc){.layout = VX_RENDER_LAYOUT_PLAIN}, &rs, &err) ||
        vx_compact_build(NULL, s, &c, &err)) {
        fprintf(stderr, "compact_bench: %s: %s\n", name, err.msg);
        vx_render_scene_destroy(rs);
        return;
    }
    double t1 = vx_time_now();
    uint64_t whole = 4ull * c.geom_words + 4ull * c.attr_words;
    vx_result r = vx_compact_page_build(&c, lp, NULL, &p, &err);
    double t2 = vx_time_now();
    uint32_t npages = r ? 0 : p.page_count;
    uint64_t page_bytes = r ? 0 : 4 * p.data_words, top = r ? 0 : 4ull * p.top_words;
    if (!r) r = vx_compact_gpu_create_paged(rs, s, &p, budget, &cg, &err);
    vx_compact_paged_free(&p);
    if (r) {
        fprintf(stderr, "compact_bench: %s: %s\n", name, err.msg);
        vx_compact_free(&c);
        vx_render_scene_destroy(rs);
        return;
    }
    printf("\n%s: page level %u, %u pages, %.1f MB of pages, top %.2f MB, pool %.1f MB (whole compact layout %.1f MB); "
           "compact build %.2f s, pages cut %.2f s\n\n",
           name, lp, npages, page_bytes / 1e6, top / 1e6, budget / 1e6, whole / 1e6, t1 - t0, t2 - t1);
    printf("| frame | wall ms | trace GPU ms | pages coarse | loaded | evicted | refused (MB over) | resident | pool used MB |\n"
           "| ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n");
    double lo[3], hi[3];
    vx_svo_scene_world_bounds(s, lo, hi);
    double* wall = calloc(frames ? frames : 1, sizeof *wall);
    double* gpu_t = calloc(frames ? frames : 1, sizeof *gpu_t);
    for (uint32_t f = 0; wall && gpu_t && f < frames; f++) {
        vx_render_desc d = fly_view(lo, hi, W, H, f, frames);
        vx_render_image img = {0};
        double tf = vx_time_now();
        if (vx_compact_gpu_frame(cg, &d, &img, &err)) {
            fprintf(stderr, "compact_bench: %s frame %u: %s\n", name, f, err.msg);
            break;
        }
        wall[f] = vx_time_now() - tf, gpu_t[f] = img.gpu_seconds;
        vx_render_image_free(&img);
        vx_compact_page_stats st;
        vx_compact_gpu_page_stats(cg, &st);
        printf("| %u | %.2f | %.3f | %u | %u | %u | %u (%.1f) | %u | %.1f |\n", f, 1e3 * wall[f], 1e3 * gpu_t[f],
               st.coarse, st.loaded, st.evicted, st.refused, st.refused_bytes / 1e6, st.resident, st.used_bytes / 1e6);
    }
    if (wall && gpu_t && frames) printf("\nmedian wall %.2f ms, trace %.3f ms a frame\n", 1e3 * bench_median(wall, frames),
                                       1e3 * bench_median(gpu_t, frames));
    fflush(stdout);
    free(wall);
    free(gpu_t);
    vx_compact_free(&c);
    vx_compact_gpu_destroy(cg);
    vx_render_scene_destroy(rs);
}

/* The compact kernel's frame and timing: variant 0 as built, 1 its starts
 * below the root off (trace.comp's keep theirs), 2 starts from one push */
static vx_result compact_frame(vx_render_scene* rs, vx_compact_gpu* cg, int variant, const vx_render_desc* d,
                               vx_render_image* out, vx_error* err) {
    if (variant == 1) vx__render_scene_trace_path(rs, 0);
    if (variant == 2) vx__compact_gpu_start_min(cg, 1);
    vx_result r = vx_compact_gpu_frame(cg, d, out, err);
    vx__render_scene_trace_path(rs, g_start_on ? 1 : -1);
    vx__compact_gpu_start_min(cg, 0);
    return r;
}
static vx_result compact_time(vx_render_scene* rs, vx_compact_gpu* cg, int variant, const vx_render_desc* d, uint32_t reps,
                              double* seconds, vx_error* err) {
    if (variant == 1) vx__render_scene_trace_path(rs, 0);
    if (variant == 2) vx__compact_gpu_start_min(cg, 1);
    vx_result r = vx_compact_gpu_time(cg, d, reps, seconds, err);
    vx__render_scene_trace_path(rs, g_start_on ? 1 : -1);
    vx__compact_gpu_start_min(cg, 0);
    return r;
}

static void gpu_rows(vx_gpu* g, const char* name, const vx_svo_scene* s, uint32_t bricks, uint32_t W, uint32_t H, uint32_t reps,
                     uint32_t lp) {
    vx_error err = {0};
    vx_render_scene* rs = NULL;
    vx_compact_scene c;
    vx_compact_gpu* cg = NULL;
    vx_compact_gpu* cgp = NULL; /* the paged layout, every page it needs resident */
    if (vx_render_scene_create(g, s, &rs, &err)) {
        fprintf(stderr, "compact_bench: %s: %s\n", name, err.msg);
        return;
    }
    if (g_start_on) vx__render_scene_trace_path(rs, 1);
    if (vx_compact_build(&(vx_compact_desc){.bricks = bricks}, s, &c, &err) == VX_OK) {
        if (vx_compact_gpu_create(rs, s, &c, &cg, &err)) cg = NULL;
        vx_compact_paged p;
        if (cg && lp && vx_compact_page_build(&c, lp, NULL, &p, &err) == VX_OK) {
            if (vx_compact_gpu_create_paged(rs, s, &p, 8 * p.data_words + (64u << 20), &cgp, &err)) {
                fprintf(stderr, "compact_bench: %s: paged: %s\n", name, err.msg);
                cgp = NULL;
            }
            vx_compact_paged_free(&p);
        }
        vx_compact_free(&c);
    }
    const uint32_t nl = cgp ? 2 : 1; /* compact layouts: the whole layout, and paged */
    /* compact kernels timed: those, and with --start-ab the whole layout's
     * from the root (v == nl) and with starts from one push (v == nl + 1) */
    const uint32_t nv = nl + (g_start_ab ? 2u : 0u);
#define VARIANT(v) ((v) < nl ? 0 : (int)((v) - nl) + 1)
    if (!cg) {
        fprintf(stderr, "compact_bench: %s: %s\n", name, err.msg);
        vx_render_scene_destroy(rs);
        return;
    }
    uint64_t words = 0, colors = 0;
    for (uint32_t i = 0; i < s->model_count; i++) {
        words += s->models[i].node_count;
        if (s->models[i].attrs) colors += s->models[i].attr_count;
    }
    double lo[3], hi[3];
    vx_svo_scene_world_bounds(s, lo, hi);
    for (int view = 0; view < 2; view++) {
        vx_render_desc d = {.width = W, .height = H, .mode = VX_RENDER_ALBEDO, .want_hits = true};
        if (view == 1) bench_compact_closeup(lo, hi, &d);
        /* pixels whose instance or cell differ, colour, t bits, t by more than 1e-5 relative */
        uint64_t hits = 0, differ[8] = {0}, dcol[8] = {0}, dt[8] = {0}, dtbig[8] = {0}, ita = 0, dnh[8] = {0};
        uint64_t itv[8] = {0}; /* each compact kernel's steps */
        for (uint32_t v = 0; v < nv; v++) {
            vx_render_image a = {0}, b = {0};
            vx_compact_gpu* k = v == 1 && cgp ? cgp : cg;
            if (v == 1 && cgp) {
                /* frames until the view's pages are resident */
                for (int f = 0; f < 16; f++) {
                    vx_compact_page_stats st;
                    if (vx_compact_gpu_frame(k, &d, &b, &err)) break;
                    vx_render_image_free(&b);
                    vx_compact_gpu_page_stats(k, &st);
                    if (!st.coarse && !st.loaded) break;
                }
            }
            if (vx_render_frame(rs, &d, &a, &err) || compact_frame(rs, k, VARIANT(v), &d, &b, &err)) {
                fprintf(stderr, "compact_bench: %s: %s\n", name, err.msg);
            } else {
                hits = ita = 0;
                for (size_t i = 0; i < (size_t)W * H; i++) {
                    const vx_render_hit *x = &a.hits[i], *y = &b.hits[i];
                    bool cell = x->instance == y->instance &&
                                (x->instance == VX_RENDER_NO_HIT || !memcmp(x->cell, y->cell, sizeof x->cell));
                    hits += x->instance != VX_RENDER_NO_HIT;
                    ita += x->iterations, itv[v] += y->iterations;
                    differ[v] += !cell;
                    dcol[v] += cell && memcmp(&a.pixels[4 * i], &b.pixels[4 * i], 16) != 0;
                    dt[v] += cell && memcmp(&x->t, &y->t, 4) != 0;
                    dtbig[v] += cell && fabs((double)x->t - (double)y->t) > 1e-5 * fabs((double)x->t);
                }
            }
            vx_render_image_free(&a);
            vx_render_image_free(&b);
            /* the albedo pixels without hits (the kernels that write none) */
            vx_render_desc dn = d;
            dn.want_hits = false;
            if (!vx_render_frame(rs, &dn, &a, &err) && !compact_frame(rs, k, VARIANT(v), &dn, &b, &err))
                for (size_t i = 0; i < (size_t)W * H; i++) dnh[v] += memcmp(&a.pixels[4 * i], &b.pixels[4 * i], 16) != 0;
            else
                dnh[v] = UINT64_MAX;
            vx_render_image_free(&a);
            vx_render_image_free(&b);
        }
        d.want_hits = false;
        /* The GPU's clocks: a first batch of dispatches measured 1.3-1.5x
         * differences between kernels timed one after the other that the
         * order explained (H200, docs/PERFORMANCE.md), so the device is kept
         * busy for a while first and each round times the kernels in another
         * order (rotated). */
        vx__frame f;
        double warm = 0, t_w = vx_time_now();
        while (vx_time_now() - t_w < 0.5)
            if (vx__render_dispatch(rs, &d, false, reps, &f, &warm, &err)) break;
        double ta[ROUNDS], tb[8][ROUNDS];
        for (int round = 0; round < ROUNDS; round++) {
            for (uint32_t q = 0; q <= nv; q++) {
                uint32_t k = (q + (uint32_t)round) % (nv + 1); /* 0: trace.comp, v + 1: compact kernel v */
                if (k == 0) {
                    if (vx__render_dispatch(rs, &d, false, reps, &f, &ta[round], &err)) ta[round] = 0;
                    continue;
                }
                if (compact_time(rs, k == 2 && cgp ? cgp : cg, VARIANT(k - 1), &d, reps, &tb[k - 1][round], &err)) {
                    fprintf(stderr, "compact_bench: %s: %s\n", name, err.msg);
                    tb[k - 1][round] = 0;
                }
            }
        }
        double ma = bench_median(ta, ROUNDS), rays = (double)W * H;
        /* the depth mode: the walk alone (no colour decode in either) */
        d.mode = VX_RENDER_DEPTH;
        double da3[ROUNDS], db3[4][ROUNDS];
        for (int round = 0; round < ROUNDS; round++) {
            bool first = round % 2 == 0;
            if (first && vx__render_dispatch(rs, &d, false, reps, &f, &da3[round], &err)) da3[round] = 0;
            for (uint32_t v = 0; v < nv; v++)
                if (compact_time(rs, v == 1 && cgp ? cgp : cg, VARIANT(v), &d, reps, &db3[v][round], &err)) db3[v][round] = 0;
            if (!first && vx__render_dispatch(rs, &d, false, reps, &f, &da3[round], &err)) da3[round] = 0;
        }
        double da = bench_median(da3, ROUNDS);
        for (uint32_t v = 0; v < nv; v++) {
            double mb = bench_median(tb[v], ROUNDS), db = bench_median(db3[v], ROUNDS);
            printf("| %s | %s | %.3f ms = %.2f G rays/s | %.3f ms = %.2f G rays/s | **%.3f** | %.3f | %.1f / %.1f | %llu | "
                   "%llu / %llu / %llu / %llu | %.1f MB | %.1f MB | %.1f KB (%llu), %.1f KB | %llu |\n",
                   name, v == nl + 1 ? (view ? "close-up, starts from one push" : "overview, starts from one push")
                         : v == nl ? (view ? "close-up, from the root" : "overview, from the root")
                         : v ? (view ? "close-up, paged" : "overview, paged") : (view ? "close-up" : "overview"),
                   1e3 * ma, rays / ma / 1e9, 1e3 * mb,
                   rays / mb / 1e9, mb > 0 ? ma / mb : 0.0, db > 0 ? da / db : 0.0, (double)ita / rays, (double)itv[v] / rays,
                   (unsigned long long)hits, (unsigned long long)differ[v], (unsigned long long)dcol[v],
                   (unsigned long long)dt[v], (unsigned long long)dtbig[v], 4.0 * (double)(words + colors) / 1e6,
                   (double)vx_compact_gpu_bytes(v == 1 && cgp ? cgp : cg) / 1e6,
                   (double)vx__compact_gpu_table_bytes(v == 1 && cgp ? cgp : cg) / 1e3,
                   (unsigned long long)vx__compact_gpu_uniform_entries(v == 1 && cgp ? cgp : cg),
                   (double)vx__compact_gpu_record_bytes(v == 1 && cgp ? cgp : cg) / 1e3, (unsigned long long)dnh[v]);
        }
        fflush(stdout);
    }
    vx_compact_gpu_destroy(cg);
    vx_compact_gpu_destroy(cgp);
    vx_render_scene_destroy(rs);
}
#endif

/* The geometry's bytes by level and field (--levels, render/compact.h): per
 * level its blocks and slots (64 bits each, a rank word more at levels >= 5;
 * level 2: the bricks' index words), the brick dictionary; and what the
 * same blocks took before the dictionary (every slot of level >= 3 with a
 * rank word, every brick 8 bytes in its block). */
static void level_rows(const vx_compact_scene* c, double voxels) {
    const vx_compact_stats* st = &c->stats;
    printf("\n| level | blocks | slots | slots per block | slot bytes | rank bytes | bytes per voxel | share |\n"
           "| ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n");
    double all = 4.0 * c->geom_words, before = 0;
    for (int L = 32; L >= 1; L--) {
        uint64_t n = st->level_slots[L];
        if (!n) continue;
        double sb = L >= 3 || !c->brick_dict ? 8.0 * n : 4.0 * n, rb = L >= 5 ? 4.0 * n : 0;
        before += L >= 3 ? 12.0 * n : 8.0 * n;
        printf("| %d%s | %llu | %llu | %.2f | %.1f MB | %.1f MB | %.4f | %.1f%% |\n", L,
               L > 2 ? "" : c->brick_dict ? " (index words)" : " (bricks)",
               (unsigned long long)st->level_blocks[L], (unsigned long long)n, (double)n / st->level_blocks[L],
               sb / 1e6, rb / 1e6, (sb + rb) / voxels, 100.0 * (sb + rb) / all);
    }
    double db = 8.0 * st->bricks;
    if (c->brick_dict)
        printf("| dictionary | | %llu bricks | | %.1f MB | | %.4f | %.1f%% |\n", (unsigned long long)st->bricks, db / 1e6,
               db / voxels, 100.0 * db / all);
    printf("\ngeometry%s %.1f MB = %.4f bytes/voxel; the same blocks in main's form (ed89e10: rank words at levels >= 3, "
           "bricks in blocks): %.1f MB = %.4f\n\n", c->brick_dict ? " (brick dictionary)" : "", all / 1e6, all / voxels,
           before / 1e6, before / voxels);
}

static void row(const char* name, const vx_svo_scene* s, uint32_t block, uint32_t bricks, double load_s, bool levels) {
    uint64_t voxels = 0, words = 0, colors = 0;
    for (uint32_t i = 0; i < s->model_count; i++) {
        voxels += s->models[i].voxel_count;
        words += s->models[i].node_count;
        if (s->models[i].attrs) colors += s->models[i].attr_count;
    }
    vx_compact_desc d = vx_compact_desc_defaults();
    d.block = block;
    d.bricks = bricks;
    vx_compact_scene c;
    vx_error err = {0};
    double t0 = vx_time_now();
    if (vx_compact_build(&d, s, &c, &err)) {
        fprintf(stderr, "compact_bench: %s: %s\n", name, err.msg);
        return;
    }
    double t = vx_time_now() - t0, v = voxels ? (double)voxels : 1;
    bool pal = false;
    for (uint32_t i = 0; i < c.model_count; i++) pal |= c.models[i].attr_kind == VX_COMPACT_ATTR_PALETTE;
    double today = 4.0 * (double)(words + colors), geom = 4.0 * c.geom_words;
    double attr = 4.0 * c.attr_words + (pal ? 1024 : 0);
    const vx_compact_stats* st = &c.stats;
    char bs[32];
    uint32_t big = 0; /* automatic: the block of the largest model */
    for (uint32_t i = 1; i < c.model_count; i++)
        if (c.models[i].voxels > c.models[big].voxels) big = i;
    if (block) snprintf(bs, sizeof bs, "%u%s", block, c.brick_dict ? ", brick dictionary" : "");
    else snprintf(bs, sizeof bs, "auto (%u)%s", c.model_count ? c.models[big].block : 0, c.brick_dict ? ", brick dictionary" : "");
    double blocks = st->blocks ? (double)st->blocks : 1;
    printf("| %s | %llu | %.1f MB = %.3f (%.3f + %.3f) | %s | %.1f MB = **%.3f** | %.3f | %.3f "
           "| %.1f%% / %.1f%% / %.1f%% / %.1f%% | %.2f | %.2f s (load %.2f s) |\n",
           name, (unsigned long long)voxels, today / 1e6, today / v, 4.0 * words / v, 4.0 * colors / v, bs,
           (geom + attr) / 1e6, (geom + attr) / v, geom / v, attr / v, 100.0 * st->uniform / blocks,
           100.0 * st->delta / blocks, 100.0 * st->raw / blocks, 100.0 * st->shared / blocks,
           st->distinct_sum / blocks, t, load_s);
    fflush(stdout);
    if (levels) level_rows(&c, v);
    vx_compact_free(&c);
}

/* A mesh voxelized at res in the process (see --res above). */
static int mesh_scene(const char* path, uint32_t res, bool no_color, bool on_gpu, vx_svo_scene* s, vx_error* err) {
#ifdef VX_BENCH_HAVE_MESH
    vx_conv_mesh_desc d = {.res = res, .no_color = no_color};
    vx_gltf_mesh mesh;
    if (vx_conv_mesh_read(&d, path, &mesh, err)) return 1;
#ifdef VX_BENCH_HAVE_MESH_GPU
    vx_gpu* g = NULL;
    vx_conv_mesh_gpu* mg = NULL;
    if (on_gpu && (vx_gpu_create(&(vx_gpu_desc){0}, &g, err) || vx_conv_mesh_gpu_create(g, NULL, &mg, err))) {
        vx_gltf_mesh_free(&mesh);
        return 1;
    }
    if (mg) d.backend = vx_conv_mesh_gpu_backend(mg);
#else
    if (on_gpu) {
        vx_gltf_mesh_free(&mesh);
        return vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET, "--mesh-gpu: built without the GPU voxelizer"), 1;
    }
#endif
    double t0 = vx_time_now();
    vx_result r = vx_conv_mesh(&d, &mesh, s, NULL, err);
    double t = vx_time_now() - t0;
    vx_gltf_mesh_free(&mesh);
#ifdef VX_BENCH_HAVE_MESH_GPU
    vx_conv_mesh_gpu_destroy(mg);
    vx_gpu_destroy(g);
#endif
    if (r) return 1;
    uint64_t vox = 0, words = 0;
    for (uint32_t m = 0; m < s->model_count; m++) vox += s->models[m].voxel_count, words += s->models[m].node_count;
    printf("%s at %u: %llu voxels, %u models, %llu node words, converted in %.1f s (%s%s)\n", path, res, (unsigned long long)vox,
           s->model_count, (unsigned long long)words, t, on_gpu ? "GPU" : "CPU", no_color ? ", no colours" : "");
    fflush(stdout);
    return 0;
#else
    (void)path, (void)res, (void)no_color, (void)on_gpu, (void)s;
    return vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET, "meshes: built without the glTF reader"), 1;
#endif
}


/* --threads 1,N,... (before the files): the layout built with each
 * (with --regions, vx_compact_desc.attr_regions: the peak without the
 * attributes' joined copy; a count followed by o or a: the ordered merge
 * or the merge on all threads, vx_compact_desc.merge)
 * geometry thread count in turn, --reps rounds (ABAB), the median wall time
 * of the geometry DAG and of the whole build, and whether every count gives
 * the first count's bytes (render/compact.h: they must). */
static int cmp_double(const void* a, const void* b) {
    double x = *(const double*)a, y = *(const double*)b;
    return x < y ? -1 : x > y;
}
static void threads_rows(const char* name, const vx_svo_scene* s, const uint32_t* counts, const uint32_t* mrg,
                         uint32_t nc, uint32_t reps, bool regions) {
    double geom[8][64], all[8][64], merge[8][64];
    bool same[8] = {0};
    if (reps > 64) reps = 64;
    for (uint32_t k = 0; k < nc; k++) same[k] = true;
    vx_compact_scene first = {0};
    for (uint32_t r = 0; r < reps; r++)
        for (uint32_t k = 0; k < nc; k++) {
            vx_compact_desc d = vx_compact_desc_defaults();
            d.threads = counts[k];
            d.merge = mrg[k];
            d.attr_regions = regions; /* --regions: the attributes per model (no joined copy; the bytes not compared) */
            vx_compact_scene c;
            vx_error err = {0};
            double t0 = vx_time_now();
            if (vx_compact_build(&d, s, &c, &err)) {
                fprintf(stderr, "compact_bench: %s: %s\n", name, err.msg);
                vx_compact_free(&first);
                return;
            }
            all[k][r] = vx_time_now() - t0;
            geom[k][r] = c.stats.geom_seconds;
            merge[k][r] = c.stats.geom_merge_seconds;
            if (!first.models) {
                first = c;
                continue;
            }
            same[k] &= c.geom_words == first.geom_words && c.attr_words == first.attr_words &&
                       !memcmp(c.geom, first.geom, (size_t)c.geom_words * 4) &&
                       (regions || !memcmp(c.attr, first.attr, (size_t)c.attr_words * 4)) &&
                       !memcmp(c.models, first.models, (size_t)c.model_count * sizeof *c.models);
            vx_compact_free(&c);
        }
    for (uint32_t k = 0; k < nc; k++) {
        qsort(geom[k], reps, sizeof(double), cmp_double);
        qsort(all[k], reps, sizeof(double), cmp_double);
        qsort(merge[k], reps, sizeof(double), cmp_double);
        printf("threads %s: %u%s: geometry %.3f s (median of %u; merge %.3f s), build %.3f s, peak %.2f GiB, bytes %s\n",
               name, counts[k], mrg[k] == VX_COMPACT_MERGE_ORDERED ? " (ordered merge)" : mrg[k] ? " (merge on all)" : "",
               geom[k][reps / 2], reps, merge[k][reps / 2], all[k][reps / 2],
               vx_peak_rss() / 1073741824.0,
               same[k] ? "same as the first" : "DIFFER");
    }
    vx_compact_free(&first);
}

int main(int argc, char** argv) {
    uint32_t blocks[16] = {0}, nb = 1; /* 0: automatic per model */
    uint32_t bricks[2] = {VX_COMPACT_BRICKS_INLINE, VX_COMPACT_BRICKS_DICT}, nbricks = 1;
    uint32_t gw = 0, gh = 0, reps = 20, lp = 0, fly = 0;
    uint64_t budget = 0;
    bool stats = false, geometry_only = false, mesh_gpu = false, levels = false;
    uint32_t mesh_res = 0, tcounts[8], tmerge[8], ntc = 0;
    bool regions = false;
#ifdef VX_BENCH_HAVE_VULKAN
    vx_gpu* gpu = NULL;
    vx_logger logger = {.func = print_stats};
#endif
    printf("| scene | voxels | today: MB = bytes/voxel (nodes + colours) | block | compact: MB = bytes/voxel | "
           "geometry | attributes | blocks uniform / delta / raw / shared | distinct per block | build |\n");
    printf("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n");
    for (int i = 1; i < argc; i++) {
        vx_svo_scene s;
        vx_error err = {0};
        char name[256];
        double t0 = vx_time_now();
        if (!strcmp(argv[i], "--blocks") && i + 1 < argc) {
            nb = 0;
            for (char* p = argv[++i]; *p && nb < 16;) {
                blocks[nb++] = (uint32_t)strtoul(p, &p, 10);
                if (*p == ',') p++;
                else if (*p) break;
            }
            continue;
        }
        if (!strcmp(argv[i], "--gpu") && i + 1 < argc) {
            if (sscanf(argv[++i], "%ux%u", &gw, &gh) != 2 || !gw || !gh || gw > 16384 || gh > 16384) {
                fprintf(stderr, "compact_bench: --gpu WxH\n");
                return 2;
            }
#ifdef VX_BENCH_HAVE_VULKAN
            if (!gpu && vx_gpu_create(&(vx_gpu_desc){.logger = stats ? &logger : NULL}, &gpu, &err)) {
                fprintf(stderr, "compact_bench: %s\n", err.msg);
                return 1;
            }
            printf("device: %s\n\n| scene | view | trace.comp (albedo) | trace_compact.comp | compact / today | "
                   "the same, depth mode | steps per ray (today / compact) | pixels hit | differing: instance or cell / "
                   "colour / t bits / t > 1e-5 | today's buffers | compact buffers | of them start tables (entries of one value), "
                   "level-3 records | "
                   "pixels differing without hits |\n"
                   "| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n",
                   vx_gpu_device_name(gpu));
#else
            fprintf(stderr, "compact_bench: built without Vulkan\n");
            return 2;
#endif
            continue;
        }
        if (!strcmp(argv[i], "--res") && i + 1 < argc) {
            mesh_res = (uint32_t)strtoul(argv[++i], NULL, 10);
            continue;
        }
        if (!strcmp(argv[i], "--mesh-gpu")) {
            mesh_gpu = true;
            continue;
        }
        if (!strcmp(argv[i], "--threads") && i + 1 < argc) {
            for (char* p = argv[++i]; *p && ntc < 8;) {
                tcounts[ntc] = (uint32_t)strtoul(p, &p, 10);
                tmerge[ntc++] = *p == 'o' ? VX_COMPACT_MERGE_ORDERED : *p == 'a' ? VX_COMPACT_MERGE_ALL : 0;
                if (*p == 'o' || *p == 'a') p++;
                if (*p == ',') p++;
                else break;
            }
            if (reps == 20) reps = 3; /* the default is --gpu's */
            continue;
        }
        if (!strcmp(argv[i], "--regions")) {
            regions = true;
            continue;
        }
        if (!strcmp(argv[i], "--geometry")) {
            geometry_only = true;
            continue;
        }
        if (!strcmp(argv[i], "--bricks") && i + 1 < argc) {
            /* inline, dict, or both (bytes rows of each; --gpu rows the first) */
            const char* v = argv[++i];
            nbricks = strcmp(v, "both") ? 1 : 2;
            if (!strcmp(v, "dict")) bricks[0] = VX_COMPACT_BRICKS_DICT;
            else if (strcmp(v, "inline") && strcmp(v, "both")) {
                fprintf(stderr, "compact_bench: --bricks inline|dict|both\n");
                return 2;
            }
            continue;
        }
        if (!strcmp(argv[i], "--levels")) {
            levels = true;
            continue;
        }
        if (!strcmp(argv[i], "--start-on")) {
            g_start_on = true;
            continue;
        }
        if (!strcmp(argv[i], "--start-ab")) {
            g_start_ab = true;
            continue;
        }
        if (!strcmp(argv[i], "--shader-stats")) {
            /* before --gpu: the driver's statistics of each kernel as it is created */
            stats = !setenv("VX_GPU_SHADER_STATS", "1", 1);
            continue;
        }
        if (!strcmp(argv[i], "--paged") && i + 1 < argc) {
            lp = (uint32_t)strtoul(argv[++i], NULL, 10);
            continue;
        }
        if (!strcmp(argv[i], "--fly") && i + 1 < argc) {
            fly = (uint32_t)strtoul(argv[++i], NULL, 10);
            continue;
        }
        if (!strcmp(argv[i], "--budget") && i + 1 < argc) {
            budget = (uint64_t)(strtod(argv[++i], NULL) * 1e6);
            continue;
        }
        if (!strcmp(argv[i], "--reps") && i + 1 < argc) {
            reps = (uint32_t)strtoul(argv[++i], NULL, 10);
            if (!reps || reps > 1000) reps = 20;
            continue;
        }
        if (!strcmp(argv[i], "--terrain") && i + 1 < argc) {
            uint32_t e = (uint32_t)strtoul(argv[++i], NULL, 10);
            if (e < 64 || e > 16384 || (e & (e - 1))) {
                fprintf(stderr, "compact_bench: --terrain: a power of two in 64..16384\n");
                return 2;
            }
            if (bench_terrain(&s, e, 0, &err)) {
                fprintf(stderr, "compact_bench: terrain %u: %s\n", e, err.msg);
                return 1;
            }
            snprintf(name, sizeof name, "terrain %u", e);
        } else if (argv[i][0] == '-') {
            fprintf(stderr, "usage: %s [--blocks 0,16,64,...] [--geometry] [--terrain EXTENT] [FILE.vox|FILE.svo ...]\n", argv[0]);
            return 2;
        } else if (mesh_res && (strstr(argv[i], ".glb") || strstr(argv[i], ".gltf"))) {
            if (mesh_scene(argv[i], mesh_res, geometry_only, mesh_gpu, &s, &err)) {
                fprintf(stderr, "compact_bench: %s: %s\n", argv[i], err.msg);
                return 1;
            }
            const char* b = strrchr(argv[i], '/');
            snprintf(name, sizeof name, "%s at %u", b ? b + 1 : argv[i], mesh_res);
        } else {
            if (bench_load(argv[i], &s, &err)) {
                fprintf(stderr, "compact_bench: %s: %s\n", argv[i], err.msg);
                return 1;
            }
            const char* b = strrchr(argv[i], '/');
            snprintf(name, sizeof name, "%s", b ? b + 1 : argv[i]);
        }
        double load = vx_time_now() - t0;
        if (geometry_only)
            for (uint32_t m = 0; m < s.model_count; m++) s.models[m].attrs = 0; /* the records stay, unread */
        if (ntc) threads_rows(name, &s, tcounts, tmerge, ntc, reps, regions);
        else if (!gw)
            for (uint32_t k = 0; k < nb; k++)
                for (uint32_t j = 0; j < nbricks; j++) row(name, &s, blocks[k], bricks[j], load, levels);
#ifdef VX_BENCH_HAVE_VULKAN
        if (gw && fly && lp && budget) fly_rows(gpu, name, &s, gw, gh, lp, budget, fly);
        else if (gw) gpu_rows(gpu, name, &s, bricks[0], gw, gh, reps, lp);
#endif
        vx_svo_scene_free(&s);
    }
#ifdef VX_BENCH_HAVE_VULKAN
    vx_gpu_destroy(gpu);
#endif
    return 0;
}
