/* bench/pathtrace_bench.c - the path tracer's rate (samples per second, GPU
 * timestamps) on one scene with what issue 11 added, switched on one at a
 * time: "diffuse" (the scene's MATL records and lights dropped: the
 * workload the diffuse-only path tracer had), "lights" (four vx_lights: a sun
 * with a 0.5 degree disc, a spot, a sphere and a rect light, placed from the
 * scene's bounds), "materials" (palette entries made metal, glass and
 * emissive: index % 6 == 1 metal rough 0.3, == 2 glass IOR 1.5 rough 0.05,
 * index % 16 == 3 emissive 4), and "all". Needs only libvulkan and libc.
 *
 *   pathtrace_bench SCENE.{svo,vox} WxH [--spp N (64)] [--bounces N (4)] [--runs N (3)]
 *
 * One row per configuration: median GPU ms of --runs renders, samples per
 * second (pixels x spp / s) and the image mean (so a broken configuration
 * shows). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench/bench_load.h"
#include "probes/probes.h"

static int cmp_d(const void* a, const void* b) {
    double x = *(const double*)a, y = *(const double*)b;
    return x < y ? -1 : x > y;
}

/* Material record `id` with a dictionary of n key/value pairs (the scene
 * owns it afterwards: vx_svo_scene_free frees it). */
static int add_material(vx_svo_scene* s, uint32_t id, const char* const* kv, int n) {
    size_t size = 0;
    for (int i = 0; i < 2 * n; i++) size += strlen(kv[i]) + 1;
    vx_svo_material* m = realloc(s->materials, (s->material_count + 1) * sizeof *m);
    if (!m) return 1;
    s->materials = m;
    char* dict = malloc(size);
    if (!dict) return 1;
    size_t at = 0;
    for (int i = 0; i < 2 * n; i++) memcpy(dict + at, kv[i], strlen(kv[i]) + 1), at += strlen(kv[i]) + 1;
    s->materials[s->material_count++] = (vx_svo_material){.id = id, .dict_size = (uint32_t)size, .dict = dict};
    return 0;
}

int main(int argc, char** argv) {
    if (argc < 3) {
        fprintf(stderr, "usage: %s SCENE.{svo,vox} WxH [--spp N] [--bounces N] [--runs N]\n", argv[0]);
        return 2;
    }
    uint32_t w = 0, h = 0, spp = 64, bounces = 4, runs = 3;
    if (sscanf(argv[2], "%ux%u", &w, &h) != 2 || !w || !h) {
        fprintf(stderr, "bad size '%s'\n", argv[2]);
        return 2;
    }
    for (int i = 3; i + 1 < argc; i += 2) {
        uint32_t v = (uint32_t)strtoul(argv[i + 1], NULL, 10);
        if (!strcmp(argv[i], "--spp")) spp = v;
        else if (!strcmp(argv[i], "--bounces")) bounces = v;
        else if (!strcmp(argv[i], "--runs")) runs = v;
        else {
            fprintf(stderr, "unknown option '%s'\n", argv[i]);
            return 2;
        }
    }
    if (!spp || !bounces || !runs || runs > 64) {
        fprintf(stderr, "--spp, --bounces and --runs must be positive (runs at most 64)\n");
        return 2;
    }
    vx_error err = {0};
    vx_svo_scene s;
    if (bench_load(argv[1], &s, &err)) {
        fprintf(stderr, "%s: %s\n", argv[1], err.msg);
        return 1;
    }
    vx_gpu* gpu = NULL;
    if (vx_gpu_create(&(vx_gpu_desc){0}, &gpu, &err)) {
        fprintf(stderr, "no Vulkan device: %s\n", err.msg);
        vx_svo_scene_free(&s);
        return 1;
    }
    double lo[3], hi[3], c[3], ext = 0;
    vx_svo_scene_world_bounds(&s, lo, hi);
    for (int k = 0; k < 3; k++) c[k] = 0.5 * (lo[k] + hi[k]), ext = fmax(ext, hi[k] - lo[k]);
    vx_light lights[4] = {
        {.type = VX_LIGHT_DIRECTIONAL, .direction = {0.35, -0.45, 0.82}, .color = {1, 0.95, 0.9}, .intensity = 3,
         .angular_diameter = 0.0093},
        {.type = VX_LIGHT_SPOT, .position = {c[0], c[1], hi[2] + 0.2 * ext}, .direction = {0.1, 0.1, -1}, .color = {1, 1, 1},
         .intensity = 0.5 * ext * ext, .inner_cone = 0.3, .outer_cone = 0.6},
        {.type = VX_LIGHT_SPHERE, .position = {lo[0] + 0.25 * ext, c[1], hi[2] + 0.1 * ext}, .color = {1, 0.8, 0.6},
         .intensity = 20, .radius = 0.05 * ext},
        {.type = VX_LIGHT_RECT, .position = {hi[0] - 0.25 * ext, c[1], hi[2] + 0.15 * ext}, .direction = {0, 0, -1},
         .tangent = {1, 0, 0}, .color = {0.6, 0.8, 1}, .intensity = 10, .size = {0.1 * ext, 0.1 * ext}},
    };
    /* the scene's own materials are kept aside for the diffuse and lights rows */
    uint32_t own_count = s.material_count;
    vx_svo_material* own = s.materials;
    vx_svo_scene m = s;
    m.materials = NULL, m.material_count = 0;
    int bad = 0;
    for (uint32_t i = 1; i < 256 && !bad; i++) {
        const char* metal[] = {"_type", "_metal", "_rough", "0.3"};
        const char* glass[] = {"_type", "_glass", "_ior", "0.5", "_rough", "0.05"};
        const char* lamp[] = {"_type", "_emit", "_emit", "4"};
        if (i % 16 == 3) bad = add_material(&m, i, lamp, 2);
        else if (i % 6 == 1) bad = add_material(&m, i, metal, 2);
        else if (i % 6 == 2) bad = add_material(&m, i, glass, 3);
    }
    printf("scene %s, %ux%u, %u spp, %u bounces, device %s\n", argv[1], w, h, spp, bounces, vx_gpu_device_name(gpu));
    printf("%-10s %12s %14s %10s\n", "config", "GPU ms", "samples/s", "mean");
    const char* names[4] = {"diffuse", "lights", "materials", "all"};
    int status = bad;
    for (int cfg = 0; cfg < 4 && !status; cfg++) {
        vx_svo_scene* sc = &s;
        s.materials = NULL, s.material_count = 0; /* diffuse: what the path tracer had before materials */
        if (cfg >= 2) sc = &m;
        vx_render_scene* rs = NULL;
        if (vx_render_scene_create(gpu, sc, &rs, &err)) {
            fprintf(stderr, "%s: %s\n", names[cfg], err.msg);
            status = 1;
            break;
        }
        /* without lights the sun's rays are ended by the sun's depth map (render/shadow_map.c): those
         * configurations also run without it (base.no_shadow_map), their last images compared bit for bit */
        float* keep = NULL;
        for (int nomap = 0; nomap < (cfg & 1 ? 1 : 2) && !status; nomap++) {
            vx_render_desc base = {.width = w, .height = h, .no_shadow_map = nomap != 0};
            vx_probe_render_stats rst = {0};
            vx_probe_render_desc d = {.base = &base, .mode = VX_PROBE_RENDER_PATHTRACE, .spp = spp, .bounces = bounces,
                                      .seed = 1, .lights = cfg & 1 ? lights : NULL, .light_count = cfg & 1 ? 4 : 0,
                                      .stats = &rst};
            double t[64], mean = 0;
            size_t differ = 0;
            for (uint32_t r = 0; r < runs && !status; r++) {
                vx_render_image img = {0};
                if (vx_probe_render_gpu(rs, sc, NULL, &d, &img, &err)) {
                    fprintf(stderr, "%s: %s\n", names[cfg], err.msg);
                    status = 1;
                    break;
                }
                t[r] = img.gpu_seconds;
                mean = 0;
                for (size_t i = 0; i < (size_t)w * h; i++) mean += img.pixels[4 * i] + img.pixels[4 * i + 1] + img.pixels[4 * i + 2];
                mean /= 3.0 * w * h;
                if (r + 1 == runs && !nomap && (keep = malloc((size_t)w * h * 16))) memcpy(keep, img.pixels, (size_t)w * h * 16);
                if (r + 1 == runs && nomap && keep)
                    for (size_t i = 0; i < (size_t)w * h * 4; i++) differ += memcmp(&keep[i], &img.pixels[i], 4) != 0;
                vx_render_image_free(&img);
            }
            if (status) break;
            qsort(t, runs, sizeof t[0], cmp_d);
            double med = t[runs / 2];
            printf("%-10s %12.2f %14.4g %10.4g", names[cfg], med * 1e3, (double)w * h * spp / med, mean);
            if (nomap) printf("  (no sun map: %zu of %zu values differ from the row above)\n", differ, (size_t)w * h * 4);
            else if (rst.sun_map_side) printf("  (sun map, %u texels a side)\n", rst.sun_map_side);
            else printf("\n");
        }
        free(keep);
        vx_render_scene_destroy(rs);
        if (status) break;
    }
    s.materials = own, s.material_count = own_count;
    vx_svo_scene_free(&s);
    for (uint32_t i = 0; i < m.material_count; i++) free(m.materials[i].dict);
    free(m.materials);
    vx_gpu_destroy(gpu);
    return status;
}
