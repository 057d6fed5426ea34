/* today_bench - issue 18's speed goal read as written: "primary-ray speed with the new layout within 10% of
 * today's", "today" being the day the issue was filed (as its 5.06 bytes per voxel and 18.1 s write are). This
 * program times trace.comp's albedo primary rays on compact_bench's two views (its default framing, and its
 * close-up: fov 70, eye at mid + (0.2, -0.3, 0.2) of the extent, target at mid - 0.05 of it), with the same
 * timing (0.5 s warm-up, then 5 rounds of --reps timestamped dispatches in one submission, medians). It
 * compiles against the tree of the day the issue was filed (00625c1, the commit before issue 18's first; one
 * include changed, below) and against today's main, so that one process of each on the same GPU gives "today's" rates beside
 * compact_bench's compact kernel (bench/results/today_gpu_run.sh). In main it is the target today_bench; in
 * 00625c1's tree a copy (with bench/bench_compact_view.h) and the same target added to bench/render.cmake by hand.
 * Usage: today_bench [--gpu WxH] [--reps N] [--terrain EXTENT] FILE.vox|FILE.svo ... */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench/bench_compact_view.h"
#include "bench/bench_load.h"
#include "bench/bench_stats.h"
#include "bench/bench_terrain.h"
/* In 00625c1's tree, before render/testing.h existed, the same two entry points (vx__render_dispatch, vx__frame) were
 * declared in render's private header: built there with this one include changed (`sed -i
 * 's|render/testing.h|render/render_internal.h|' bench/today_bench.c`; the measured binary chose it by __has_include). */
#include "render/testing.h"

static void rows(vx_gpu* gpu, const char* name, vx_svo_scene* s, uint32_t W, uint32_t H, uint32_t reps) {
    vx_error err = {0};
    vx_render_scene* rs;
    if (vx_render_scene_create(gpu, s, &rs, &err)) {
        fprintf(stderr, "today_bench: %s: %s\n", name, err.msg);
        return;
    }
    double lo[3], hi[3];
    vx_svo_scene_world_bounds(s, lo, hi);
    for (int view = 0; view < 2; view++) {
        vx_render_desc d = {.width = W, .height = H, .mode = VX_RENDER_ALBEDO, .want_hits = true};
        if (view == 1) bench_compact_closeup(lo, hi, &d);
        vx_render_image img = {0};
        uint64_t hits = 0;
        if (vx_render_frame(rs, &d, &img, &err)) {
            fprintf(stderr, "today_bench: %s: %s\n", name, err.msg);
            continue;
        }
        for (size_t i = 0; i < (size_t)W * H; i++) hits += img.hits[i].instance != UINT32_MAX;
        vx_render_image_free(&img);
        d.want_hits = false;
        vx__frame f;
        double warm = 0, t_w = vx_time_now(), t[5];
        while (vx_time_now() - t_w < 0.5)
            if (vx__render_dispatch(rs, &d, false, reps, &f, &warm, &err)) break;
        for (int r = 0; r < 5; r++)
            if (vx__render_dispatch(rs, &d, false, reps, &f, &t[r], &err)) t[r] = 0;
        double m = bench_median(t, 5);
        printf("| %s | %s | %.1f%% | %.3f ms | %.3f G rays/s |\n", name, view ? "close-up" : "overview",
               100.0 * (double)hits / ((double)W * H), 1e3 * m, m > 0 ? (double)W * H / m / 1e9 : 0.0);
        fflush(stdout);
    }
    vx_render_scene_destroy(rs);
}

int main(int argc, char** argv) {
    uint32_t W = 1920, H = 1080, reps = 30;
    vx_error err = {0};
    vx_gpu* gpu;
    if (vx_gpu_create(&(vx_gpu_desc){0}, &gpu, &err)) {
        fprintf(stderr, "today_bench: %s\n", err.msg);
        return 1;
    }
    printf("device: %s\n\n| scene | view | hit | trace.comp albedo | rays/s |\n| --- | --- | ---: | ---: | ---: |\n",
           vx_gpu_device_name(gpu));
    for (int i = 1; i < argc; i++) {
        vx_svo_scene s;
        char name[256];
        if (!strcmp(argv[i], "--gpu") && i + 1 < argc) {
            if (sscanf(argv[++i], "%ux%u", &W, &H) != 2 || !W || !H) return 2;
            continue;
        }
        if (!strcmp(argv[i], "--reps") && i + 1 < argc) {
            reps = (uint32_t)atoi(argv[++i]);
            if (!reps) return 2;
            continue;
        }
        if (!strcmp(argv[i], "--terrain") && i + 1 < argc) {
            uint32_t e = (uint32_t)atoi(argv[++i]);
            if (bench_terrain(&s, e, 0, &err)) {
                fprintf(stderr, "today_bench: terrain %u: %s\n", e, err.msg);
                return 1;
            }
            snprintf(name, sizeof name, "terrain %u", e);
        } else {
            if (bench_load(argv[i], &s, &err)) {
                fprintf(stderr, "today_bench: %s: %s\n", argv[i], err.msg);
                return 1;
            }
            const char* b = strrchr(argv[i], '/');
            snprintf(name, sizeof name, "%s", b ? b + 1 : argv[i]);
        }
        rows(gpu, name, &s, W, H, reps);
        vx_svo_scene_free(&s);
    }
    vx_gpu_destroy(gpu);
    return 0;
}
