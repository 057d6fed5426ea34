/* bench/render_bench.c - rays per second of the octree tracer (primary and
 * shadow rays) against a dense-grid 3D-DDA baseline over the same voxels.
 *
 *   render_bench [--device N|NAME] [--sizes 1920x1080,1280x720] [--runs N]
 *                [--generate] [--deep] [--variant auto|float|precise]
 *                FILE.{svo,vox}...
 *
 * Times are GPU timestamps: one warm-up, then the median of --runs
 * dispatches. --generate adds procedural terrains 1024 (fits the dense
 * baseline) and 4096 cells wide; --deep the 1024 terrain placed in a model
 * 2^20 cells wide (20 levels: the float64 trace variant), seen by a camera
 * that frames the terrain. --variant forces the float or the float64
 * variant of the trace shader (auto: chosen by model depth).
 * Output: one table row per scene, size and kind. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench/bench_load.h"
#include "render/render_internal.h"


/* Terrain over 4096 x 4096 cells: columns of 8x8 cells whose top two
 * 8^3 tiles are filled (level-3 tiles, so the builder never expands them),
 * heights from a few sines up to ~3000 cells, plus 2048 single-cell
 * "pebbles" on top: extent 4096^3, depth 12. */
static int generate(vx_svo_scene* s, uint32_t extent, uint32_t deep_offset, vx_error* err) {
    const uint32_t cols = extent / 8;
    const double hs = extent / 4096.0;
    size_t cap = (size_t)cols * cols * 2 + 4096, n = 0;
    uint64_t* keys = malloc(cap * 8);
    uint8_t* level = malloc(cap);
    uint8_t* pal = malloc(cap);
    if (!keys || !level || !pal) return 1;
    for (uint32_t y = 0; y < cols; y++)
        for (uint32_t x = 0; x < cols; x++) {
            double h = hs * (1400 + 700 * sin(x * 0.021 / hs) * cos(y * 0.017 / hs) + 500 * sin((x + 2 * y) * 0.0061 / hs) +
                            150 * sin(x * 0.11 / hs + y * 0.07 / hs));
            uint32_t top = (uint32_t)(h / 8);
            for (uint32_t k = 0; k < 2 && top >= k; k++) {
                keys[n] = vx_svo_morton(deep_offset + x * 8, deep_offset + y * 8, deep_offset + (top - k) * 8);
                level[n] = 3;
                pal[n++] = (uint8_t)(1 + (top % 200));
            }
        }
    uint32_t seed = 1;
    for (int i = 0; i < 2048; i++) {
        seed = seed * 1664525u + 1013904223u;
        uint32_t x = (seed >> 8) % extent;
        seed = seed * 1664525u + 1013904223u;
        uint32_t y = (seed >> 8) % extent;
        keys[n] = vx_svo_morton(deep_offset + x, deep_offset + y, deep_offset + extent - 96 + i % 64);
        level[n] = 0;
        pal[n++] = 250;
    }
    uint32_t side = deep_offset ? 1u << 20 : extent;
    vx_svo_voxels v = {.size = {side, side, side}, .count = n, .keys = keys, .level = level, .attrs = VX_ATTR_PALETTE,
                       .palette = pal};
    vx_svo_scene_init(s, NULL);
    s->models = calloc(1, sizeof *s->models);
    s->instances = calloc(1, sizeof *s->instances);
    if (!s->models || !s->instances) return 1;
    vx_result r = vx_svo_build_model(NULL, &v, &s->models[0], NULL, err);
    free(keys), free(level), free(pal);
    if (r) return 1;
    s->model_count = 1;
    s->instance_count = 1;
    s->instances[0].xform[0] = s->instances[0].xform[5] = s->instances[0].xform[10] = 1;
    s->instances[0].layer = UINT32_MAX;
    s->has_palette = true;
    for (int i = 1; i < 256; i++) s->palette[i] = 0xFF000000u | (uint32_t)(i * 0x010203);
    vx_svo_scene_update_bounds(s);
    return 0;
}

int main(int argc, char** argv) {
    const char* device = NULL;
    const char* sizes = "1920x1080,1280x720";
    uint32_t runs = 5;
    bool gen = false, deep = false;
    int variant = -1;
    const char* files[64];
    int nf = 0;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--device") && i + 1 < argc) device = argv[++i];
        else if (!strcmp(argv[i], "--sizes") && i + 1 < argc) sizes = argv[++i];
        else if (!strcmp(argv[i], "--runs") && i + 1 < argc) runs = (uint32_t)atoi(argv[++i]);
        else if (!strcmp(argv[i], "--generate")) gen = true;
        else if (!strcmp(argv[i], "--deep")) deep = true;
        else if (!strcmp(argv[i], "--variant") && i + 1 < argc) {
            i++;
            variant = !strcmp(argv[i], "float") ? 0 : !strcmp(argv[i], "precise") ? 1 : -1;
        }
        else if (argv[i][0] == '-') {
            fprintf(stderr, "usage: %s [--device N|NAME] [--sizes WxH,...] [--runs N] [--generate] [--deep] "
                            "[--variant auto|float|precise] FILE...\n", argv[0]);
            return 2;
        } else if (nf < 64) files[nf++] = argv[i];
    }
    if (runs < 1 || runs > 31) runs = 5;
    vx_error err = {0};
    vx_gpu* gpu;
    if (vx_gpu_create(&(vx_gpu_desc){.device = device}, &gpu, &err)) {
        fprintf(stderr, "render_bench: %s\n", err.msg);
        return 1;
    }
    printf("device: %s\n", vx_gpu_device_name(gpu));
    printf("%-24s %-10s %10s %12s %12s %12s %8s\n", "scene", "size", "voxels", "primary", "shadow", "dense", "oct/den");
    printf("%-24s %-10s %10s %12s %12s %12s %8s\n", "", "", "", "Mrays/s", "Mpix/s", "Mrays/s", "");
    int total = nf + (gen ? 2 : 0) + (deep ? 1 : 0);
    for (int k = 0; k < total; k++) {
        vx_svo_scene s;
        const char* name;
        double t0 = vx_time_now();
        if (k < nf) {
            name = strrchr(files[k], '/') ? strrchr(files[k], '/') + 1 : files[k];
            if (bench_load(files[k], &s, &err)) {
                fprintf(stderr, "render_bench: %s: %s\n", files[k], err.msg);
                continue;
            }
        } else {
            bool is_deep = deep && k == total - 1;
            uint32_t extent = is_deep || k == nf ? 1024 : 4096;
            name = is_deep ? "terrain1024 in 2^20" : extent == 1024 ? "terrain1024 (generated)" : "terrain4096 (generated)";
            if (generate(&s, extent, is_deep ? (1u << 19) + 12344 : 0, &err)) {
                fprintf(stderr, "render_bench: generate: %s\n", err.msg);
                continue;
            }
        }
        double t_load = vx_time_now() - t0;
        uint64_t voxels = 0;
        for (uint32_t i = 0; i < s.instance_count; i++) voxels += s.models[s.instances[i].model].voxel_count;
        vx_render_scene* rs;
        if (vx_render_scene_create(gpu, &s, &rs, &err)) {
            fprintf(stderr, "render_bench: %s: %s\n", name, err.msg);
            vx_svo_scene_free(&s);
            continue;
        }
        vx__render_scene_force_precise(rs, variant);
        /* the deep terrain: frame its 1024^3 box as the default camera frames a scene */
        bool deep_cam = deep && k == total - 1;
        bool dense = !deep_cam && vx__dense_prepare(rs, &s, UINT64_C(1) << 30, &err) == VX_OK;
        const char* p = sizes;
        while (*p) {
            unsigned w, h;
            if (sscanf(p, "%ux%u", &w, &h) != 2) break;
            vx_render_desc d = {.width = w, .height = h, .mode = VX_RENDER_DEPTH};
            if (deep_cam) {
                double c0 = (1u << 19) + 12344 + 512.0;
                d.camera.set = true;
                d.camera.target[0] = d.camera.target[1] = c0, d.camera.target[2] = c0 - 200;
                d.camera.eye[0] = c0 - 1100, d.camera.eye[1] = c0 - 1500, d.camera.eye[2] = c0 + 1300;
            }
            vx__frame f;
            double sp = 0, ss = 0, sd = 0;
            vx_result r = vx__render_dispatch(rs, &d, false, 1, &f, &sp, &err); /* warm-up */
            if (!r) r = vx__render_dispatch(rs, &d, false, runs, &f, &sp, &err);
            d.mode = VX_RENDER_COLOR;
            if (!r) r = vx__render_dispatch(rs, &d, false, 1, &f, &ss, &err);
            if (!r) r = vx__render_dispatch(rs, &d, false, runs, &f, &ss, &err);
            d.mode = VX_RENDER_DEPTH;
            if (!r && dense) {
                r = vx__dense_dispatch(rs, &d, 1, &sd, NULL, &err);
                if (!r) r = vx__dense_dispatch(rs, &d, runs, &sd, NULL, &err);
            }
            if (r) {
                fprintf(stderr, "render_bench: %s: %s\n", name, err.msg);
                break;
            }
            double px = (double)w * h;
            char sz[32], dn[32], ratio[32];
            snprintf(sz, sizeof sz, "%ux%u", w, h);
            snprintf(dn, sizeof dn, "%.2f", dense ? px / sd * 1e-6 : 0.0);
            snprintf(ratio, sizeof ratio, "%.2f", dense ? sd / sp : 0.0);
            printf("%-24.24s %-10s %10llu %12.2f %12.2f %12s %8s%s\n", name, sz, (unsigned long long)voxels,
                   px / sp * 1e-6, px / ss * 1e-6, dense ? dn : "-", dense ? ratio : "-",
                   vx_render_scene_precise(rs) ? "  (float64)" : "");
            fflush(stdout);
            p = strchr(p, ',');
            if (!p) break;
            p++;
        }
        fprintf(stderr, "  (%s: load %.2f s, bvh %.3f ms)\n", name, t_load, vx_render_scene_bvh_seconds(rs) * 1e3);
        vx_render_scene_destroy(rs);
        vx_svo_scene_free(&s);
    }
    vx_gpu_destroy(gpu);
    return 0;
}
