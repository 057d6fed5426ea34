/* bench/compact_bench.c - GPU bytes per voxel of the compact layout
 * (render/compact.h, issue 18) beside the layout the tracer uploads today
 * (render_scene.c: the .svo node words plus one 4-byte RGBA record per
 * attribute record), for .vox / .svo scenes and the tracer benchmarks'
 * terrain. One markdown row per scene and attribute block size.
 *
 * Usage: compact_bench [--blocks 0,16,64,...] (0: automatic, the default) [--terrain EXTENT] [FILE.vox|FILE.svo ...] */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench/bench_load.h"
#include "bench/bench_terrain.h"
#include "render/compact.h"

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
        for (uint32_t k = 0; k < nb; k++) row(name, &s, blocks[k], load);
        vx_svo_scene_free(&s);
    }
    return 0;
}
