/* bench/lights_bench.c - many lights in the direct pass (render/pipeline.h,
 * "Many lights"): brute force, tiled and clustered culling at several light
 * counts, with the cull pass's and the direct pass's GPU times. Needs only
 * libvulkan and libc.
 *
 *   lights_bench [--device N|NAME] [--runs N] [--size WxH] [--counts N,N,...]
 *                [--shadows N] [--range F] [--dry] SCENE.{vox,svo}
 *
 * The view is passes_bench's close-up (bench/bench_view.h); its hit share is
 * printed. N point lights sit just in front of surfaces the view sees (a
 * quarter of their range, at most 3% of the depth, before N random hit
 * pixels), so that every light lights something. Their range shrinks as 1/sqrt(N) (range = F (--range, default
 * 0.05) times the scene diagonal at 1,000 lights): the lights per pixel stay
 * about constant, as in a scene that gains lights by gaining area, not by
 * stacking them; the table states the mean number of lights in range of a
 * hit pixel (counted on the CPU over 2,000 hit pixels). --dry prints only
 * that count.
 * Intensity = range^2 / 20 (irradiance 0.2 at half the range), colours
 * random. Each row: the median over --runs frames (3 for brute force above
 * 10,000 lights) after a warm-up frame, passes separate (so that the direct
 * pass has its own time), shadows for the --shadows strongest lights per
 * pixel (default: the pipeline's default) and without shadows. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench/bench_load.h"
#include "bench/bench_stats.h"
#include "bench/bench_view.h"
#include "render/pipeline.h"

static double row_ms(const vx_frame_result* r, const char* name) {
    for (uint32_t q = 0; q < r->timing_count; q++)
        if (!strcmp(r->timings[q].name, name)) return r->timings[q].ms;
    return 0;
}

int main(int argc, char** argv) {
    const char* device = NULL;
    int runs = 9, shadows = 0;
    double range_f = 0.05;
    bool dry = false;
    uint32_t W = 1920, H = 1080;
    uint32_t counts[16] = {10, 32, 100, 1000, 25000, 100000}, ncounts = 6;
    int a = 1;
    for (; a < argc && argv[a][0] == '-'; a++) {
        if (!strcmp(argv[a], "--device") && a + 1 < argc) device = argv[++a];
        else if (!strcmp(argv[a], "--runs") && a + 1 < argc) runs = atoi(argv[++a]);
        else if (!strcmp(argv[a], "--shadows") && a + 1 < argc) shadows = atoi(argv[++a]);
        else if (!strcmp(argv[a], "--range") && a + 1 < argc) range_f = atof(argv[++a]);
        else if (!strcmp(argv[a], "--dry")) dry = true;
        else if (!strcmp(argv[a], "--size") && a + 1 < argc) {
            if (sscanf(argv[++a], "%ux%u", &W, &H) != 2) return 2;
        } else if (!strcmp(argv[a], "--counts") && a + 1 < argc) {
            ncounts = 0;
            for (char* p = argv[++a]; *p && ncounts < 16;) {
                char* e;
                unsigned long v = strtoul(p, &e, 10);
                if (e == p || !v || v > 10000000) return 2;
                counts[ncounts++] = (uint32_t)v;
                p = *e == ',' ? e + 1 : e;
            }
        } else {
            break;
        }
    }
    if (runs < 1 || runs > 1000 || !(range_f > 0) || shadows < 0 || shadows > VX_SHADOW_LIGHTS_MAX || a + 1 != argc) {
        fprintf(stderr, "usage: lights_bench [--device N|NAME] [--runs 1..1000] [--size WxH] [--counts N,N,...] "
                        "[--shadows 0..%d] [--range F] [--dry] SCENE\n",
                VX_SHADOW_LIGHTS_MAX);
        return 2;
    }
    vx_error err = {0};
    vx_gpu* gpu;
    if (vx_gpu_create(&(vx_gpu_desc){.device = device}, &gpu, &err)) {
        fprintf(stderr, "lights_bench: %s\n", err.msg);
        return 1;
    }
    vx_svo_scene s;
    vx_render_scene* rs = NULL;
    vx_frame_renderer* fr = NULL;
    if (bench_load(argv[a], &s, &err)) {
        fprintf(stderr, "lights_bench: %s\n", err.msg);
        vx_gpu_destroy(gpu);
        return 1;
    }
    if (vx_render_scene_create(gpu, &s, &rs, &err) || vx_frame_renderer_create(rs, &s, &fr, &err)) {
        fprintf(stderr, "lights_bench: %s: %s\n", argv[a], err.msg);
        vx_render_scene_destroy(rs);
        vx_svo_scene_free(&s);
        vx_gpu_destroy(gpu);
        return 1;
    }
    double lo[3], hi[3], diag = 0;
    vx_svo_scene_world_bounds(&s, lo, hi);
    for (int k = 0; k < 3; k++) diag += (hi[k] - lo[k]) * (hi[k] - lo[k]);
    diag = sqrt(diag);
    vx_render_desc base = {.width = W, .height = H};
    bench_closeup(lo, hi, &base);
    /* the view's hits: where the lights go */
    vx_frame_desc fd = vx_frame_desc_defaults();
    fd.base = base;
    fd.want_ids = true;
    vx_frame_result res;
    int status = 0;
    if (vx_frame_render(fr, &fd, &res, &err)) {
        fprintf(stderr, "lights_bench: %s\n", err.msg);
        status = 1;
    }
    size_t npx = (size_t)W * H, nhit = 0;
    uint32_t* hit_px = status ? NULL : malloc(npx * sizeof *hit_px);
    float* hit_t = status ? NULL : malloc(npx * sizeof *hit_t);
    for (size_t i = 0; hit_px && hit_t && i < npx; i++)
        if (res.image.hits[i].instance != VX_RENDER_NO_HIT) hit_px[nhit] = (uint32_t)i, hit_t[nhit++] = res.image.hits[i].t;
    if (!status) vx_render_image_free(&res.image);
    vx__frame f;
    vx__frame_setup(lo, hi, &base, &f, NULL);
    printf("# lights_bench on %s, %ux%u, %s close-up (%.1f%% of pixels hit), median of %d frames after a warm-up\n",
           vx_gpu_device_name(gpu), W, H, argv[a], 100.0 * nhit / npx, runs);
    printf("# point lights just before random hit pixels (range / 4, at most 3%% of the depth), range = %g * diagonal (%.1f) * sqrt(1000 / N), "
           "intensity = range^2 / 20; passes separate; shadows: the %d strongest lights per pixel\n\n",
           range_f, diag, shadows ? shadows : VX_SHADOW_LIGHTS_DEFAULT);
    printf("| lights | lights in range of a hit pixel | culling | list entries | cull ms | direct ms | cull + direct ms | direct ms, no shadows | "
           "cull + direct, no shadows | frame ms |\n| ---: | ---: | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n");
    double* t = calloc((size_t)runs * 4, sizeof *t);
    vx_pass_list L;
    vx_pass_list_parse("gbuffer,direct", &L, &err);
    /* the world point of hit pixel h */
#define HIT_POINT(h, out)                                                                                       \
    do {                                                                                                        \
        uint32_t px_ = hit_px[h] % W, py_ = hit_px[h] / W;                                                      \
        double u_ = ((px_ + 0.5) / W) * 2 - 1, v_ = 1 - ((py_ + 0.5) / H) * 2, d_[3], dl_ = 0;                  \
        for (int k_ = 0; k_ < 3; k_++) d_[k_] = f.fwd[k_] + u_ * f.rx[k_] + v_ * f.uy[k_], dl_ += d_[k_] * d_[k_]; \
        dl_ = sqrt(dl_);                                                                                        \
        for (int k_ = 0; k_ < 3; k_++) (out)[k_] = f.ref[k_] - f.fwd[k_] * f.t_start + d_[k_] / dl_ * hit_t[h]; \
    } while (0)
    for (uint32_t c = 0; c < ncounts && !status && nhit && t; c++) {
        uint32_t n = counts[c];
        vx_light* ls = calloc(n, sizeof *ls);
        if (!ls) break;
        uint32_t rng = 12345;
        double range = range_f * diag * sqrt(1000.0 / n);
        for (uint32_t i = 0; i < n; i++) {
            rng = rng * 1664525u + 1013904223u;
            size_t h = (size_t)(((uint64_t)(rng >> 4) * nhit) >> 28);
            double p[3], eye[3];
            HIT_POINT(h, p);
            double back = fmin(0.03, 0.25 * range / hit_t[h]); /* off the surface, well within the range */
            ls[i].type = VX_LIGHT_POINT;
            for (int k = 0; k < 3; k++) {
                eye[k] = f.ref[k] - f.fwd[k] * f.t_start;
                ls[i].position[k] = eye[k] + (p[k] - eye[k]) * (1 - back);
                rng = rng * 1664525u + 1013904223u;
                ls[i].color[k] = 0.3 + 0.7 * ((rng >> 8) / 16777216.0);
            }
            ls[i].intensity = range * range / 20;
            ls[i].range = range;
        }
        /* lights in range of a hit pixel, the mean over 2,000 of them */
        double in_range = 0;
        for (int j = 0; j < 2000; j++) {
            double p[3];
            size_t h = (size_t)(((uint64_t)j * 2654435761u) % nhit);
            HIT_POINT(h, p);
            for (uint32_t i = 0; i < n; i++) {
                double dx = ls[i].position[0] - p[0], dy = ls[i].position[1] - p[1], dz = ls[i].position[2] - p[2];
                in_range += dx * dx + dy * dy + dz * dz < range * range;
            }
        }
        in_range /= 2000;
        if (dry) {
            printf("| %u | %.1f | | | | | | | | |\n", n, in_range);
            free(ls);
            continue;
        }        for (int m = VX_LIGHT_CULLING_BRUTE; m <= VX_LIGHT_CULLING_CLUSTERED && !status; m++) {
            int nr = m == VX_LIGHT_CULLING_BRUTE && n > 10000 ? (runs < 3 ? runs : 3) : runs;
            double med[2][3], frame = 0;
            uint64_t entries = 0;
            for (int sh = 0; sh < 2 && !status; sh++) {
                fd = vx_frame_desc_defaults();
                fd.base = base;
                fd.base.spp = 1;
                fd.passes = &L;
                fd.no_readback = true;
                fd.separate_passes = true;
                fd.lights = ls, fd.light_count = n;
                fd.light_culling = (vx_light_culling)m;
                fd.shadow_lights = sh ? -1 : shadows;
                for (int k = 0; k < 1 + nr; k++) {
                    if (vx_frame_render(fr, &fd, &res, &err)) {
                        fprintf(stderr, "lights_bench: %u lights, %s: %s\n", n,
                                vx_light_culling_name((vx_light_culling)m), err.msg);
                        status = 1;
                        break;
                    }
                    if (k >= 1) {
                        t[k - 1] = row_ms(&res, "cull");
                        t[runs + k - 1] = row_ms(&res, "direct");
                        t[2 * runs + k - 1] = row_ms(&res, "cull") + row_ms(&res, "direct");
                        t[3 * runs + k - 1] = res.frame_ms;
                    }
                    entries = res.light_entries;
                    vx_render_image_free(&res.image);
                }
                if (status) break;
                for (int q = 0; q < 3; q++) med[sh][q] = bench_median(t + q * runs, nr);
                if (!sh) frame = bench_median(t + 3 * runs, nr);
            }
            if (status) break;
            printf("| %u | %.1f | %s | %llu | %.3f | %.3f | %.3f | %.3f | %.3f | %.3f |\n", n, in_range,
                   vx_light_culling_name((vx_light_culling)m), (unsigned long long)entries, med[0][0], med[0][1],
                   med[0][2], med[1][1], med[1][2], frame);
            fflush(stdout);
        }
        free(ls);
    }
    free(t);
    free(hit_px);
    free(hit_t);
    vx_frame_renderer_destroy(fr);
    vx_render_scene_destroy(rs);
    vx_svo_scene_free(&s);
    vx_gpu_destroy(gpu);
    return status;
}
