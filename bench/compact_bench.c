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
 * whose instance, cell, t or colour differ.
 *
 * --shader-stats (before --gpu) prints the driver's statistics of both
 * kernels (registers, spills, instructions) as they are created; each row
 * gives the mean traversal steps per ray of both (the hits' iterations).
 *
 * Usage: compact_bench [--blocks 0,16,64,...] (0: automatic, the default) [--shader-stats] [--gpu WxH] [--reps N]
 *                      [--terrain EXTENT] [FILE.vox|FILE.svo ...] */
#define _POSIX_C_SOURCE 200809L /* setenv */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench/bench_load.h"
#include "bench/bench_terrain.h"
#include "render/compact.h"
#ifdef VX_BENCH_HAVE_VULKAN
#include "bench/bench_stats.h"
#include "render/render_internal.h"

static void print_stats(void* user, vx_log_level level, const char* id, const char* msg) {
    (void)user, (void)level;
    if (!strcmp(id, "gpu.shader_stats")) printf("stats: %s\n", msg);
    fflush(stdout);
}

#define ROUNDS 5 /* timing rounds per view; medians */

/* Both kernels on s: one markdown row per view. */
static void gpu_rows(vx_gpu* g, const char* name, const vx_svo_scene* s, uint32_t W, uint32_t H, uint32_t reps) {
    const uint32_t nv = 1; /* compact kernels timed (kernel variants were timed this way, issue 18) */
    vx_error err = {0};
    vx_render_scene* rs = NULL;
    vx_compact_scene c;
    vx_compact_gpu* cg = NULL;
    if (vx_render_scene_create(g, s, &rs, &err)) {
        fprintf(stderr, "compact_bench: %s: %s\n", name, err.msg);
        return;
    }
    if (vx_compact_build(NULL, s, &c, &err) == VX_OK) {
        if (vx_compact_gpu_create(rs, s, &c, &cg, &err)) cg = NULL;
        vx_compact_free(&c);
    }
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
        if (view == 1) {
            d.camera.set = true;
            d.camera.fov = 70;
            for (int k = 0; k < 3; k++) {
                double mid = 0.5 * (lo[k] + hi[k]), ext = hi[k] - lo[k];
                d.camera.target[k] = mid - 0.05 * ext;
                d.camera.eye[k] = mid + (k == 1 ? -0.3 : 0.2) * ext;
            }
        }
        /* pixels whose instance or cell differ, colour, t bits, t by more than 1e-5 relative */
        uint64_t hits = 0, differ[8] = {0}, dcol[8] = {0}, dt[8] = {0}, dtbig[8] = {0}, ita = 0, itb = 0;
        for (uint32_t v = 0; v < nv; v++) {
            vx_render_image a = {0}, b = {0};
            if (vx_render_frame(rs, &d, &a, &err) || vx_compact_gpu_frame(cg, &d, &b, &err)) {
                fprintf(stderr, "compact_bench: %s: %s\n", name, err.msg);
            } else {
                hits = ita = itb = 0;
                for (size_t i = 0; i < (size_t)W * H; i++) {
                    const vx_render_hit *x = &a.hits[i], *y = &b.hits[i];
                    bool cell = x->instance == y->instance &&
                                (x->instance == VX_RENDER_NO_HIT || !memcmp(x->cell, y->cell, sizeof x->cell));
                    hits += x->instance != VX_RENDER_NO_HIT;
                    ita += x->iterations, itb += y->iterations;
                    differ[v] += !cell;
                    dcol[v] += cell && memcmp(&a.pixels[4 * i], &b.pixels[4 * i], 16) != 0;
                    dt[v] += cell && memcmp(&x->t, &y->t, 4) != 0;
                    dtbig[v] += cell && fabs((double)x->t - (double)y->t) > 1e-5 * fabs((double)x->t);
                }
            }
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
                if (vx_compact_gpu_time(cg, &d, reps, &tb[k - 1][round], &err)) {
                    fprintf(stderr, "compact_bench: %s: %s\n", name, err.msg);
                    tb[k - 1][round] = 0;
                }
            }
        }
        double ma = bench_median(ta, ROUNDS), rays = (double)W * H;
        /* the depth mode: the walk alone (no colour decode in either) */
        d.mode = VX_RENDER_DEPTH;
        double da3[ROUNDS], db3[ROUNDS];
        for (int round = 0; round < ROUNDS; round++) {
            bool first = round % 2 == 0;
            if (first && vx__render_dispatch(rs, &d, false, reps, &f, &da3[round], &err)) da3[round] = 0;
            if (vx_compact_gpu_time(cg, &d, reps, &db3[round], &err)) db3[round] = 0;
            if (!first && vx__render_dispatch(rs, &d, false, reps, &f, &da3[round], &err)) da3[round] = 0;
        }
        double da = bench_median(da3, ROUNDS), db = bench_median(db3, ROUNDS);
        for (uint32_t v = 0; v < nv; v++) {
            double mb = bench_median(tb[v], ROUNDS);
            printf("| %s | %s | %.3f ms = %.2f G rays/s | %.3f ms = %.2f G rays/s | **%.3f** | %.3f | %.1f / %.1f | %llu | "
                   "%llu / %llu / %llu / %llu | %.1f MB | %.1f MB |\n",
                   name, view ? "close-up" : "overview", 1e3 * ma, rays / ma / 1e9, 1e3 * mb,
                   rays / mb / 1e9, mb > 0 ? ma / mb : 0.0, db > 0 ? da / db : 0.0, (double)ita / rays, (double)itb / rays,
                   (unsigned long long)hits, (unsigned long long)differ[v], (unsigned long long)dcol[v],
                   (unsigned long long)dt[v], (unsigned long long)dtbig[v], 4.0 * (double)(words + colors) / 1e6,
                   (double)vx_compact_gpu_bytes(cg) / 1e6);
        }
        fflush(stdout);
    }
    vx_compact_gpu_destroy(cg);
    vx_render_scene_destroy(rs);
}
#endif

static void row(const char* name, const vx_svo_scene* s, uint32_t block, double load_s) {
    uint64_t voxels = 0, words = 0, colors = 0;
    for (uint32_t i = 0; i < s->model_count; i++) {
        voxels += s->models[i].voxel_count;
        words += s->models[i].node_count;
        if (s->models[i].attrs) colors += s->models[i].attr_count;
    }
    vx_compact_desc d = vx_compact_desc_defaults();
    d.block = block;
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
    if (block) snprintf(bs, sizeof bs, "%u", block);
    else snprintf(bs, sizeof bs, "auto (%u)", c.model_count ? c.models[big].block : 0);
    double blocks = st->blocks ? (double)st->blocks : 1;
    printf("| %s | %llu | %.1f MB = %.3f (%.3f + %.3f) | %s | %.1f MB = **%.3f** | %.3f | %.3f "
           "| %.1f%% / %.1f%% / %.1f%% / %.1f%% | %.2f | %.2f s (load %.2f s) |\n",
           name, (unsigned long long)voxels, today / 1e6, today / v, 4.0 * words / v, 4.0 * colors / v, bs,
           (geom + attr) / 1e6, (geom + attr) / v, geom / v, attr / v, 100.0 * st->uniform / blocks,
           100.0 * st->delta / blocks, 100.0 * st->raw / blocks, 100.0 * st->shared / blocks,
           st->distinct_sum / blocks, t, load_s);
    fflush(stdout);
    vx_compact_free(&c);
}

int main(int argc, char** argv) {
    uint32_t blocks[16] = {0}, nb = 1; /* 0: automatic per model */
    uint32_t gw = 0, gh = 0, reps = 20;
    bool stats = false;
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
                   "colour / t bits / t > 1e-5 | today's buffers | compact buffers |\n"
                   "| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n",
                   vx_gpu_device_name(gpu));
#else
            fprintf(stderr, "compact_bench: built without Vulkan\n");
            return 2;
#endif
            continue;
        }
        if (!strcmp(argv[i], "--shader-stats")) {
            /* before --gpu: the driver's statistics of each kernel as it is created */
            stats = !setenv("VX_GPU_SHADER_STATS", "1", 1);
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
            fprintf(stderr, "usage: %s [--blocks 0,16,64,...] [--terrain EXTENT] [FILE.vox|FILE.svo ...]\n", argv[0]);
            return 2;
        } else {
            if (bench_load(argv[i], &s, &err)) {
                fprintf(stderr, "compact_bench: %s: %s\n", argv[i], err.msg);
                return 1;
            }
            const char* b = strrchr(argv[i], '/');
            snprintf(name, sizeof name, "%s", b ? b + 1 : argv[i]);
        }
        double load = vx_time_now() - t0;
        if (!gw)
            for (uint32_t k = 0; k < nb; k++) row(name, &s, blocks[k], load);
#ifdef VX_BENCH_HAVE_VULKAN
        if (gw) gpu_rows(gpu, name, &s, gw, gh, reps);
#endif
        vx_svo_scene_free(&s);
    }
#ifdef VX_BENCH_HAVE_VULKAN
    vx_gpu_destroy(gpu);
#endif
    return 0;
}
