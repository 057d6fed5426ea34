/* bench/probes_bench.c - light field probes: bake time, and the error of the
 * indirect diffuse light (RMSE and relative MSE over hit pixels against a
 * path-traced reference) against bake and render time, with the path
 * tracer's own error at matching time. Needs only libvulkan and libc.
 *
 *   probes_bench [--cpu] [--device N|NAME] bake SCENE.{svo,vox} [GX,GY,GZ RES SPP]
 *       bakes a GX*GY*GZ grid (default 8,8,8 = 512 probes) at RES (128) with
 *       SPP (64) paths per texel, 1 bounce; prints the time and where it went
 *       (vx_probe_bake_stats). --batch N: probes per GPU batch; --host-filter: the GPU bake filters on 16 host
 *       threads (the reference path) instead of on the GPU; --runs N: N bakes
 *       in the process (the first compiles the pipelines); --out FILE: writes
 *       the last bake's .probes (timed).
 *   probes_bench [--cpu] [--device N|NAME] [options] error SCENE WxH REF_SPP [spacing:res:spp ...]
 *       reference: path-traced indirect at REF_SPP; then the path tracer at
 *       1, 4, 16, .. --pt-spp (64) spp, and for each bake configuration probe
 *       GI at 1, 4 and 16 samples per pixel and the light field at 1, 4, ..
 *       --lf-spp (16) rays per pixel.
 *       --camera/--up/--fov place the camera (default: frame the scene),
 *       --bounds the probe grid (default: the scene bounds).
 * Default: the GPU (bake and render); --cpu: the CPU reference paths.
 * Meshes: convert first, e.g. `vox2svo rtxgi_cornell.glb cornell.svo --res 256`. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench/bench_load.h"
#include "probes/probes.h"
#include "tools/common/tool.h" /* vx_tool_parse_vec */

static bool use_cpu;
static unsigned lf_spp_max = 16; /* --lf-spp N: light field renders at 1, 4, ... up to N rays per pixel */
static unsigned pt_spp_max = 64; /* --pt-spp N: path tracer at 1, 4, ... up to N */
static vx_render_camera camera;  /* --camera EX,EY,EZ,TX,TY,TZ [--up X,Y,Z] [--fov DEG] */
static bool bounds_set;          /* --bounds X0,Y0,Z0,X1,Y1,Z1: the probe grid's box */
static double bounds[6];
static double light_dir[3];      /* --light X,Y,Z: towards the sun (default: the bake's) */

static bool host_filter;         /* --host-filter: the GPU bake filters on host threads (the reference) */
static const char* out_path;     /* --out FILE: write the bake's .probes (timed) */
static unsigned bake_runs = 1;
static unsigned bake_batch;      /* --batch N: probes per GPU batch (0: the bake's choice) */   /* --runs N: bake N times in the process (the first compiles the pipelines) */

static vx_gpu* gpu;
static vx_render_scene* rs;


static vx_result bake(const vx_svo_scene* s, const vx_probe_bake_desc* d, vx_probe_set* ps, vx_error* err) {
    return use_cpu ? vx_probe_bake(s, d, ps, err) : vx_probe_bake_gpu(rs, s, d, ps, err);
}
/* GPU renders: the median GPU time of three runs (the first also warms the
 * pipeline up); the CPU paths run once (wall clock). */
static vx_result render(const vx_svo_scene* s, const vx_probe_set* ps, const vx_probe_render_desc* d,
                        vx_render_image* img, vx_error* err) {
    if (use_cpu) return vx_probe_render(s, ps, d, img, err);
    double t[3];
    for (int i = 0; i < 3; i++) {
        if (i) vx_render_image_free(img);
        vx_result r = vx_probe_render_gpu(rs, s, ps, d, img, err);
        if (r) return r;
        t[i] = img->gpu_seconds;
    }
    double lo = fmin(t[0], fmin(t[1], t[2])), hi = fmax(t[0], fmax(t[1], t[2]));
    img->gpu_seconds = t[0] + t[1] + t[2] - lo - hi;
    return VX_OK;
}

static void err_of(const vx_render_image* a, const vx_render_image* ref, double* rmse, double* rel) {
    double se = 0, rs2 = 0;
    size_t n = 0;
    for (size_t i = 0; i < (size_t)a->width * a->height; i++) {
        if (ref->pixels[4 * i + 3] == 0) continue;
        for (int c = 0; c < 3; c++) {
            double d = a->pixels[4 * i + c] - ref->pixels[4 * i + c];
            se += d * d, rs2 += ref->pixels[4 * i + c] * ref->pixels[4 * i + c];
        }
        n += 3;
    }
    *rmse = n ? sqrt(se / n) : 0;
    *rel = rs2 > 0 ? se / rs2 : 0;
}

static int usage(void) {
    fprintf(stderr, "usage: probes_bench [--cpu] [--device N|NAME] [--host-filter] [--batch N] [--runs N] [--out FILE]\n"
                    "                    bake SCENE [GX,GY,GZ RES SPP]\n"
                    "       probes_bench [--cpu] [--device N|NAME] [--lf-spp N] [--pt-spp N] [--camera E,T [--up U]\n"
                    "                    [--fov DEG]] [--light X,Y,Z] [--bounds X0,Y0,Z0,X1,Y1,Z1] error SCENE WxH REF_SPP "
                    "[spacing:res:spp ...]\n");
    return 2;
}

int main(int argc, char** argv) {
    const char* device = NULL;
    int i = 1;
    for (; i < argc && argv[i][0] == '-'; i++) {
        if (!strcmp(argv[i], "--cpu")) use_cpu = true;
        else if (!strcmp(argv[i], "--device") && i + 1 < argc) device = argv[++i];
        else if (!strcmp(argv[i], "--host-filter")) host_filter = true;
        else if (!strcmp(argv[i], "--out") && i + 1 < argc) out_path = argv[++i];
        else if (!strcmp(argv[i], "--batch") && i + 1 < argc) bake_batch = (unsigned)atoi(argv[++i]);
        else if (!strcmp(argv[i], "--runs") && i + 1 < argc) {
            bake_runs = (unsigned)atoi(argv[++i]);
            if (bake_runs < 1 || bake_runs > 100) return fprintf(stderr, "--runs: 1..100\n"), 2;
        }
        else if (!strcmp(argv[i], "--lf-spp") && i + 1 < argc) lf_spp_max = (unsigned)atoi(argv[++i]);
        else if (!strcmp(argv[i], "--pt-spp") && i + 1 < argc) pt_spp_max = (unsigned)atoi(argv[++i]);
        else if (!strcmp(argv[i], "--camera") && i + 1 < argc) {
            double v[6];
            if (!vx_tool_parse_vec(argv[++i], v, 6)) return usage();
            camera.set = true;
            memcpy(camera.eye, v, 24), memcpy(camera.target, v + 3, 24);
        } else if (!strcmp(argv[i], "--up") && i + 1 < argc) {
            if (!vx_tool_parse_vec(argv[++i], camera.up, 3)) return usage();
        } else if (!strcmp(argv[i], "--fov") && i + 1 < argc) {
            if (!vx_tool_parse_vec(argv[++i], &camera.fov, 1)) return usage();
        } else if (!strcmp(argv[i], "--light") && i + 1 < argc) {
            if (!vx_tool_parse_vec(argv[++i], light_dir, 3)) return usage();
        } else if (!strcmp(argv[i], "--bounds") && i + 1 < argc) {
            if (!vx_tool_parse_vec(argv[++i], bounds, 6)) return usage();
            bounds_set = true;
        }
        else return usage();
    }
    if (argc - i < 2) return usage();
    const char* cmd = argv[i], *path = argv[i + 1];
    i += 2;
    vx_error err = {0};
    vx_svo_scene s;
    double tp0 = vx_time_now();
    if (bench_load(path, &s, &err)) return fprintf(stderr, "%s: %s\n", path, err.msg), 1;
    double tp1 = vx_time_now(), tp2 = tp1, tp3 = tp1;
    if (!use_cpu) {
        if (vx_gpu_create(&(vx_gpu_desc){.device = device}, &gpu, &err)) {
            fprintf(stderr, "GPU: %s (--cpu for the CPU paths)\n", err.msg);
            return 1;
        }
        tp2 = vx_time_now();
        if (vx_render_scene_create(gpu, &s, &rs, &err)) {
            fprintf(stderr, "GPU: %s (--cpu for the CPU paths)\n", err.msg);
            return 1;
        }
        tp3 = vx_time_now();
        printf("device: %s\n", vx_gpu_device_name(gpu));
    } else {
        printf("device: CPU (2 threads)\n");
    }
    int rc = 0;
    if (!strcmp(cmd, "bake")) {
        vx_probe_bake_desc d = {.grid = {8, 8, 8}, .res = 128, .spp = 64, .bounces = 1, .threads = use_cpu ? 2 : 16};
        if (argc - i >= 3) {
            if (sscanf(argv[i], "%u,%u,%u", &d.grid[0], &d.grid[1], &d.grid[2]) != 3) return usage();
            d.res = (uint32_t)atoi(argv[i + 1]), d.spp = (uint32_t)atoi(argv[i + 2]);
        }
        vx_probe_bake_stats bs;
        d.host_filter = host_filter, d.stats = &bs, d.batch = bake_batch;
        printf("load %.3f s, Vulkan init %.3f s, scene upload %.3f s; filtering on the %s\n", tp1 - tp0, tp2 - tp1,
               tp3 - tp2, use_cpu ? "CPU" : (host_filter ? "host (16 threads)" : "GPU"));
        printf("| run | bake s | place s | setup s | loop s | batches | GPU trace s | GPU filter s | GPU copy s | wait s | "
               "download s | host filter s | MB down | GPU busy |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
        for (unsigned run = 0; run < bake_runs && !rc; run++) {
            vx_probe_set ps;
            memset(&bs, 0, sizeof bs);
            double t0 = vx_time_now();
            if (bake(&s, &d, &ps, &err)) return fprintf(stderr, "bake: %s\n", err.msg), 1;
            double t = vx_time_now() - t0;
            printf("| %u | %.3f | %.3f | %.3f | %.3f | %u | %.3f | %.3f | %.3f | %.3f | %.3f | %.3f | %.1f | %.0f%% |\n", run, t,
                   bs.place, bs.setup, bs.loop, bs.batches, bs.gpu_trace, bs.gpu_filter, bs.gpu_copy, bs.wait, bs.download,
                   bs.host_filter, bs.bytes_down / 1e6, 100 * bs.busy);
            if (run + 1 == bake_runs) {
                printf("| scene | probes | res | spp | bounces | bake s | s per probe |\n|---|---|---|---|---|---|---|\n");
                printf("| %s | %u | %u | %u | %u | %.3f | %.5f |\n", path, ps.probe_count, ps.res, ps.spp, ps.bounces, t,
                       t / ps.probe_count);
                if (out_path) {
                    double tw = vx_time_now();
                    if (vx_probe_write_file(NULL, &ps, out_path, &err)) fprintf(stderr, "%s: %s\n", out_path, err.msg), rc = 1;
                    else printf("wrote %s in %.3f s\n", out_path, vx_time_now() - tw);
                }
                printf("process so far %.3f s\n", vx_time_now() - tp0);
            }
            vx_probe_set_free(&ps);
        }
    } else if (!strcmp(cmd, "error") && argc - i >= 2) {
        unsigned w, h, ref_spp = (unsigned)atoi(argv[i + 1]);
        if (sscanf(argv[i], "%ux%u", &w, &h) != 2) return usage();
        vx_render_desc base = {.width = w, .height = h, .camera = camera};
        memcpy(base.light_dir, light_dir, 24); /* the path tracer's sun without probes */
        vx_render_image ref = {0};
        vx_probe_render_desc rd = {.base = &base, .mode = VX_PROBE_RENDER_PT_INDIRECT, .spp = ref_spp, .seed = 999,
                                   .threads = 2};
        if (render(&s, NULL, &rd, &ref, &err)) return fprintf(stderr, "reference: %s\n", err.msg), 1;
        printf("| scene | method | probes | res | spp | bake s | render s | RMSE | relMSE |\n"
               "|---|---|---|---|---|---|---|---|---|\n");
        printf("| %s | pathtrace ref | - | - | %u | - | %.3f | 0 | 0 |\n", path, ref_spp, ref.gpu_seconds);
        for (unsigned spp = 1; spp <= pt_spp_max && spp < ref_spp; spp *= 4) {
            vx_render_image pt = {0};
            rd.spp = spp, rd.seed = 7;
            if (render(&s, NULL, &rd, &pt, &err)) return fprintf(stderr, "pathtrace: %s\n", err.msg), 1;
            double rmse, rel;
            err_of(&pt, &ref, &rmse, &rel);
            printf("| %s | pathtrace | - | - | %u | - | %.3g | %.3g | %.3g |\n", path, spp, pt.gpu_seconds, rmse, rel);
            vx_render_image_free(&pt);
        }
        for (int k = i + 2; k < argc && !rc; k++) {
            double sp;
            unsigned res, spp;
            if (sscanf(argv[k], "%lf:%u:%u", &sp, &res, &spp) != 3) return usage();
            vx_probe_set ps;
            double t0 = vx_time_now();
            vx_probe_bake_desc bd = {.spacing = sp, .res = res, .spp = spp, .threads = use_cpu ? 2 : 16,
                                     .bounds_set = bounds_set};
            memcpy(bd.bounds_lo, bounds, 24), memcpy(bd.bounds_hi, bounds + 3, 24);
            memcpy(bd.light_dir, light_dir, 24);
            if (bake(&s, &bd, &ps, &err)) {
                fprintf(stderr, "bake: %s\n", err.msg);
                rc = 1;
                break;
            }
            double tb = vx_time_now() - t0;
            /* probe GI at 1 (the pixel centre), 4 and 16 jittered samples per pixel: the
             * reference is anti-aliased, so at one sample the silhouettes count as error */
            for (unsigned gspp = 1; gspp <= 16 && !rc; gspp *= 4) {
                vx_render_image gi = {0};
                vx_probe_render_desc gd = {.base = &base, .mode = VX_PROBE_RENDER_INDIRECT, .spp = gspp, .seed = 7,
                                           .threads = 2};
                if (render(&s, &ps, &gd, &gi, &err)) {
                    fprintf(stderr, "gi: %s\n", err.msg);
                    rc = 1;
                } else {
                    double rmse, rel;
                    err_of(&gi, &ref, &rmse, &rel);
                    printf("| %s | gi %u spp | %u | %u | %u | %.2f | %.3g | %.3g | %.3g |\n", path, gspp, ps.probe_count,
                           res, spp, tb, gi.gpu_seconds, rmse, rel);
                }
                vx_render_image_free(&gi);
            }
            for (unsigned lspp = 1; lspp <= lf_spp_max && !rc; lspp *= 4) {
                vx_render_image lf = {0};
                vx_probe_render_stats st = {0};
                vx_probe_render_desc ld = {.base = &base, .mode = VX_PROBE_RENDER_LF_INDIRECT, .spp = lspp, .seed = 7,
                                           .threads = 2, .stats = &st};
                if (render(&s, &ps, &ld, &lf, &err)) {
                    fprintf(stderr, "lightfield: %s\n", err.msg);
                    rc = 1;
                } else {
                    double rmse, rel;
                    err_of(&lf, &ref, &rmse, &rel);
                    printf("| %s | lightfield %u spp | %u | %u | %u | %.2f | %.3g | %.3g | %.3g |", path, lspp,
                           ps.probe_count, res, spp, tb, lf.gpu_seconds, rmse, rel);
                    if (st.rays)
                        printf(" fallback %.1f%%, %.2f probes/ray", 100.0 * st.fallbacks / st.rays,
                               (double)st.probe_traces / st.rays);
                    printf("\n");
                }
                vx_render_image_free(&lf);
            }
            vx_probe_set_free(&ps);
        }
        vx_render_image_free(&ref);
    } else {
        rc = usage();
    }
    vx_render_scene_destroy(rs);
    vx_gpu_destroy(gpu);
    vx_svo_scene_free(&s);
    return rc;
}
