/* bench/passes_bench.c - the pass pipeline's cost (render/pipeline.h): per
 * pass GPU times and the frame time for several pass lists, and the
 * pipeline's overhead over the single trace shader (trace.comp's colour
 * mode) on the same rays. Needs only libvulkan and libc.
 *
 *   passes_bench [--device N|NAME] [--runs N] [--size WxH] [--layout plain|compact] [--quick] [--warmup S]
 *                [--gbuffer] [--octree] [--check DIR] SCENE[@CAMERA;...] ...
 *
 * --octree: every model on its octree walk (the grids, render/grid.h, which
 * the kernels that trace walk by default on GPUs, set aside): the grid walk's
 * gain in the passes is this process's times over a default one's.
 * --warmup S: before each row's frames, its frame back to back for S seconds
 * (default 0: only the 3 warm-up frames), so that every row runs at the
 * GPU's working clock (a process's first rows ran 3-5x slower on the H200).
 * --quick: only the lists "gbuffer" and "gbuffer,direct" (merged, with the
 * shadow map) and the shadow map check, no point lights (A/B runs on a
 * shared device).
 * --gbuffer: only the G-buffer's lists: "gbuffer" (merged with resolve:
 * frame.comp), "=gbuffer" (gbuffer.comp on its own) and "gbuffer,direct"
 * (frame.comp with the sun's shadow rays, svo_render's default), no shadow
 * map check, no point lights (A/B runs of the G-buffer's kernels); times
 * to 0.1 us (a change of 1-2% in a 0.05-0.15 ms pass is 1-3 us).
 * SCENE is a .vox or .svo file or terrain:EXTENT, the tracer benchmarks'
 * procedural terrain (bench/bench_terrain.h; render_bench --generate's
 * terrain1024 and terrain4096). @CAMERA;... (up to 8, each EX,EY,EZ,TX,TY,TZ
 * or "default", the default framing): the scene's views, in order, instead
 * of the two below (bench/results/gbvh_views.c prints render_bench's three
 * views in this form).
 * --check DIR: per view, the G-buffer's images (--show albedo, normal, depth,
 * instance, material: gbuffer.comp) and the frame's (gbuffer,direct merged:
 * frame.comp, and apart), read back and compared value for value with
 * DIR/pb_SCENE_VIEW_IMAGE.f32 where that file is there (a line "check ...: N
 * of M pixels differ"), else written there: a baseline's process writes, the
 * variant's compares. The hit's cell is not among them: with depth (its bits),
 * instance and face equal, the hit point and so its cell are.
 * --layout compact keeps each scene in the compact layout (render/compact.h,
 * issue 18: the passes' kernels then walk it, trace_common.glsl COMPACT);
 * the single shader's row is then trace_compact.comp (vx_render_frame).
 *
 * For each scene, two views: the default framing ("overview") and a close-up
 * from a quarter of the default distance ("close-up"); hit share stated per view. Times
 * are GPU timestamps, the median of --runs frames (default 15) after 3
 * warm-up frames; the single shader runs the same number of dispatches.
 * Then 1 to 512 point lights spread over the scene bounds, brute force, the
 * 16 strongest at each pixel with a shadow ray (VX_SHADOW_LIGHTS_MAX; up to
 * 16 lights that is every light: the direct pass's cost per light; many
 * lights with culling: lights_bench). The direct pass's sun rays are ended
 * by the scene's sun depth map (render/shadow_map.c) from the second frame
 * on; the rows marked "no shadow map" trace them whole, and per view the
 * merged and the separate passes' images with and without are compared bit
 * for bit. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench/bench_load.h"
#include "bench/bench_stats.h"
#include "bench/bench_terrain.h"
#include "bench/bench_view.h"
#include "render/pipeline.h"
#include "render/testing.h" /* vx__render_dispatch */


/* "=" marks a list run with separate_passes (each pass its own dispatch); "!" one run with
 * vx_render_desc.no_shadow_map (the direct pass's sun rays unclipped by the sun's depth map) */
static const char* const lists[] = {"gbuffer",        "gbuffer,direct",           "!gbuffer,direct", "=gbuffer,direct",
                                    "!=gbuffer,direct", "gbuffer,direct,tonemap", "=gbuffer,direct,tonemap",
                                    "gbuffer,direct,ao,tonemap", "=gbuffer,direct,ao", "gbuffer,direct,ao,aa,tonemap"};
#define NLISTS (sizeof lists / sizeof lists[0])
static const char* const gb_lists[] = {"gbuffer", "=gbuffer", "gbuffer,direct"}; /* --gbuffer */
#define MAX_CAMS 8

/* The views of "SCENE@CAMERA;..." (after the last '@'): their count, 0 without, -1 for a bad list. */
static int parse_cameras(const char* arg, vx_render_camera cams[MAX_CAMS]) {
    const char* at = strrchr(arg, '@');
    int n = 0;
    for (const char* p = at ? at + 1 : NULL; p; n++) {
        const char* end = strchr(p, ';');
        size_t len = end ? (size_t)(end - p) : strlen(p);
        char v[256], tail;
        if (n == MAX_CAMS || len >= sizeof v) return -1;
        memcpy(v, p, len), v[len] = 0;
        cams[n] = (vx_render_camera){0};
        double *e = cams[n].eye, *c = cams[n].target;
        bool framing = !strcmp(v, "default"); /* the default framing (the overview) */
        if (!framing && sscanf(v, "%lf,%lf,%lf,%lf,%lf,%lf%c", &e[0], &e[1], &e[2], &c[0], &c[1], &c[2], &tail) != 6)
            return -1;
        cams[n].set = !framing;
        p = end ? end + 1 : NULL;
    }
    return n;
}

/* --check: the view's G-buffer and frame images against (or written to) files in dir; 0 when every check ran. */
static int check_images(vx_frame_renderer* fr, const vx_render_desc* base, const char* dir, const char* scene,
                        int view) {
    static const vx_show shows[] = {VX_SHOW_ALBEDO, VX_SHOW_NORMAL, VX_SHOW_DEPTH, VX_SHOW_INSTANCE, VX_SHOW_MATERIAL,
                                    VX_SHOW_FINAL, VX_SHOW_FINAL};
    const char* sn = strrchr(scene, '/') ? strrchr(scene, '/') + 1 : scene;
    for (size_t k = 0; k < sizeof shows / sizeof shows[0]; k++) {
        bool frame = shows[k] == VX_SHOW_FINAL, sep = k == 6;
        vx_pass_list L;
        vx_error err = {0};
        vx_pass_list_parse(frame ? "gbuffer,direct" : "gbuffer", &L, &err);
        vx_frame_desc fd = vx_frame_desc_defaults();
        fd.base = *base;
        fd.base.spp = 1;
        fd.passes = &L;
        fd.show = shows[k];
        fd.separate_passes = sep;
        vx_frame_result res = {0};
        if (vx_frame_render(fr, &fd, &res, &err)) {
            fprintf(stderr, "passes_bench: check: %s\n", err.msg);
            return 1;
        }
        char what[32], path[2048];
        snprintf(what, sizeof what, "%s%s", frame ? "frame" : vx_show_name(shows[k]), sep ? "_separate" : "");
        snprintf(path, sizeof path, "%s/pb_%s_%d_%s.f32", dir, sn, view, what);
        size_t n = (size_t)res.image.width * res.image.height, bytes = n * 4 * sizeof(float);
        FILE* fp = fopen(path, "rb");
        int status = 0;
        if (fp) {
            float* ref = malloc(bytes ? bytes : 1);
            size_t got = ref ? fread(ref, 1, bytes, fp) : 0;
            bool whole = got == bytes && fgetc(fp) == EOF;
            size_t differ = 0;
            for (size_t i = 0; whole && i < n; i++)
                differ += memcmp(&ref[4 * i], &res.image.pixels[4 * i], 4 * sizeof(float)) != 0;
            if (whole) printf("check %s view %d %s: %zu of %zu pixels differ from %s\n", sn, view, what, differ, n, path);
            else printf("check %s view %d %s: %s is not an image of this size\n", sn, view, what, path), status = 1;
            free(ref);
            fclose(fp);
        } else if ((fp = fopen(path, "wb")) != NULL) {
            bool ok = fwrite(res.image.pixels, 1, bytes, fp) == bytes;
            ok = fclose(fp) == 0 && ok;
            printf("check %s view %d %s: %s %s\n", sn, view, what, ok ? "written to" : "FAILED to write", path);
            status = !ok;
        } else {
            printf("check %s view %d %s: cannot open %s\n", sn, view, what, path), status = 1;
        }
        vx_render_image_free(&res.image);
        if (status) return status;
    }
    return 0;
}

int main(int argc, char** argv) {
    const char* device = NULL;
    int runs = 15;
    uint32_t W = 1920, H = 1080;
    int first = 1;
    bool quick = false, gbuffer = false, octree = false;
    double warmup = 0;
    const char* check_dir = NULL;
    vx_render_scene_desc sd = {.layout = VX_RENDER_LAYOUT_PLAIN};
    for (; first < argc && argv[first][0] == '-'; first++) {
        if (!strcmp(argv[first], "--layout") && first + 1 < argc) {
            const char* l = argv[++first];
            if (!strcmp(l, "compact")) sd = (vx_render_scene_desc){.layout = VX_RENDER_LAYOUT_COMPACT, .memory_budget = 1ull << 40};
            else if (strcmp(l, "plain")) return 2;
            continue;
        }
        if (!strcmp(argv[first], "--quick")) quick = true;
        else if (!strcmp(argv[first], "--gbuffer")) gbuffer = true;
        else if (!strcmp(argv[first], "--octree")) octree = true;
        else if (!strcmp(argv[first], "--check") && first + 1 < argc) check_dir = argv[++first];
        else if (!strcmp(argv[first], "--warmup") && first + 1 < argc) {
            char* end;
            warmup = strtod(argv[++first], &end);
            if (*end || !(warmup >= 0 && warmup <= 60)) return 2;
        }
        else if (!strcmp(argv[first], "--device") && first + 1 < argc) device = argv[++first];
        else if (!strcmp(argv[first], "--runs") && first + 1 < argc) runs = atoi(argv[++first]);
        else if (!strcmp(argv[first], "--size") && first + 1 < argc) {
            if (sscanf(argv[++first], "%ux%u", &W, &H) != 2) return 2;
        } else {
            fprintf(stderr, "usage: passes_bench [--device N|NAME] [--runs N] [--size WxH] [--layout plain|compact] [--quick] [--warmup S]\n"
                            "                    [--gbuffer] [--octree] [--check DIR] SCENE[@CAMERA;...]...\n");
            return 2;
        }
    }
    if (runs < 1 || runs > 1000 || first >= argc) {
        fprintf(stderr, "usage: passes_bench [--device N|NAME] [--runs 1..1000] [--size WxH] [--layout plain|compact] [--quick] [--warmup S]\n"
                        "                    [--gbuffer] [--octree] [--check DIR] SCENE[@CAMERA;...]...\n");
        return 2;
    }
    vx_error err = {0};
    vx_gpu* gpu;
    if (vx_gpu_create(&(vx_gpu_desc){.device = device}, &gpu, &err)) {
        fprintf(stderr, "passes_bench: %s\n", err.msg);
        return 1;
    }
    printf("# passes_bench on %s, %ux%u, median of %d frames after 3 warm-up frames%s\n", vx_gpu_device_name(gpu), W, H,
           runs, octree ? ", every model on its octree walk (--octree)" : "");
    double* t = calloc((size_t)runs, sizeof *t);
    double* tp = calloc((size_t)runs * (VX_PASS_KIND_COUNT + 1), sizeof *tp);
    int status = 0;
    for (int a = first; a < argc; a++) {
        vx_svo_scene s;
        vx_render_camera cams[MAX_CAMS];
        int ncams = parse_cameras(argv[a], cams);
        char path[1024];
        snprintf(path, sizeof path, "%.*s", (int)(strrchr(argv[a], '@') ? strrchr(argv[a], '@') - argv[a] : 1023), argv[a]);
        unsigned extent = 0;
        char tail;
        bool terrain = sscanf(path, "terrain:%u%c", &extent, &tail) == 1;
        if (ncams < 0 || (terrain && (extent < 64 || extent > 16384 || (extent & (extent - 1))))) {
            fprintf(stderr, "passes_bench: %s: bad %s\n", argv[a], ncams < 0 ? "camera list" : "terrain (a power of two in 64..16384)");
            status = 1;
            continue;
        }
        if (terrain ? bench_terrain(&s, extent, 0, &err) != 0 : bench_load(path, &s, &err) != 0) {
            fprintf(stderr, "passes_bench: %s\n", err.msg);
            status = 1;
            continue;
        }
        vx_render_scene* rs = NULL;
        vx_frame_renderer* fr = NULL;
        if (vx_render_scene_create_ex(gpu, &s, &sd, &rs, &err) || vx_frame_renderer_create(rs, &s, &fr, &err)) {
            fprintf(stderr, "passes_bench: %s: %s\n", path, err.msg);
            vx_render_scene_destroy(rs);
            vx_svo_scene_free(&s);
            status = 1;
            continue;
        }
        if (octree) vx__render_scene_grid(rs, 0);
        vx_render_layout_info li;
        vx_render_scene_layout(rs, &li);
        if (!octree && li.grid_models)
            printf("# %s: grids of %u of %u models, %.2f MiB (the kernels that trace walk them)\n", path, li.grid_models,
                   s.model_count, li.grid_bytes / 1048576.0);
        double lo[3], hi[3];
        vx_svo_scene_world_bounds(&s, lo, hi);
        for (int view = 0; view < (ncams ? ncams : 2); view++) {
            vx_render_desc base = {.width = W, .height = H};
            if (ncams) base.camera = cams[view];
            else if (view == 1) bench_closeup(lo, hi, &base);
            /* hit share */
            vx_frame_desc fd = vx_frame_desc_defaults();
            fd.base = base;
            fd.want_ids = true;
            vx_frame_result res;
            if (vx_frame_render(fr, &fd, &res, &err)) {
                fprintf(stderr, "passes_bench: %s: %s\n", path, err.msg);
                status = 1;
                break;
            }
            size_t hits = 0, npx = (size_t)W * H;
            for (size_t i = 0; i < npx; i++) hits += res.image.hits[i].instance != VX_RENDER_NO_HIT;
            vx_render_image_free(&res.image);
            char vname[16];
            snprintf(vname, sizeof vname, "%s", ncams ? "camera " : view ? "close-up" : "overview");
            if (ncams) snprintf(vname + strlen(vname), sizeof vname - strlen(vname), "%d", view);
            printf("\n## %s, %s (%.1f%% of pixels hit)\n\n", path, vname, 100.0 * hits / npx);
            if (check_dir && check_images(fr, &base, check_dir, path, view)) {
                status = 1;
                break;
            }
            /* the single shader, colour mode */
            base.mode = VX_RENDER_COLOR;
            vx__frame f;
            double sec;
            bool compact = sd.layout == VX_RENDER_LAYOUT_COMPACT;
            for (double w0 = vx_time_now(); !compact && vx_time_now() - w0 < warmup;)
                if (vx__render_dispatch(rs, &base, false, 8, &f, &sec, &err)) break;
            for (int k = 0; k < 3 + runs; k++) {
                vx_result rr;
                if (compact) {
                    vx_render_image im = {0};
                    rr = vx_render_frame(rs, &base, &im, &err);
                    sec = im.gpu_seconds;
                    vx_render_image_free(&im);
                } else {
                    rr = vx__render_dispatch(rs, &base, false, 1, &f, &sec, &err);
                }
                if (rr) {
                    fprintf(stderr, "passes_bench: %s\n", err.msg);
                    status = 1;
                    break;
                }
                if (k >= 3) t[k - 3] = sec * 1e3;
            }
            double single = bench_median(t, runs);
            printf("| passes | frame ms | per pass ms | vs single shader |\n| --- | ---: | --- | ---: |\n");
            int dp = gbuffer ? 4 : 3; /* --gbuffer: 0.1 microseconds (its A/B steps are a few) */
            printf("| single shader (%s colour) | %.*f | | 1.00 |\n", compact ? "trace_compact.comp" : "trace.comp", dp, single);
            size_t nlists = gbuffer ? sizeof gb_lists / sizeof gb_lists[0] : quick ? 2 : NLISTS;
            for (size_t l = 0; l < nlists; l++) {
                const char* list = gbuffer ? gb_lists[l] : lists[l];
                vx_pass_list L;
                bool nomap = list[0] == '!';
                bool sep = list[nomap] == '=';
                vx_pass_list_parse(list + nomap + sep, &L, &err);
                fd = vx_frame_desc_defaults();
                fd.base = base;
                fd.base.spp = 1; /* aa: one sample, so the rows compare per-frame costs */
                fd.passes = &L;
                fd.no_readback = true;
                fd.separate_passes = sep;
                fd.base.no_shadow_map = nomap;
                bool mapped = false;
                const char* names[VX_PASS_KIND_COUNT + 1] = {0};
                uint32_t nn = 0;
                bool ok = true;
                for (double w0 = vx_time_now(); vx_time_now() - w0 < warmup;) {
                    if (vx_frame_render(fr, &fd, &res, &err)) break;
                    vx_render_image_free(&res.image);
                }
                for (int k = 0; k < 3 + runs && ok; k++) {
                    if (vx_frame_render(fr, &fd, &res, &err)) {
                        fprintf(stderr, "passes_bench: %s\n", err.msg);
                        ok = false;
                        status = 1;
                        break;
                    }
                    mapped = res.shadow_map;
                    if (k >= 3) {
                        t[k - 3] = res.frame_ms;
                        nn = res.timing_count;
                        for (uint32_t q = 0; q < nn; q++) {
                            names[q] = res.timings[q].name;
                            tp[q * runs + (k - 3)] = res.timings[q].ms;
                        }
                    }
                    vx_render_image_free(&res.image);
                }
                if (!ok) break;
                double fm = bench_median(t, runs);
                char per[256] = "";
                for (uint32_t q = 0; q < nn; q++)
                    snprintf(per + strlen(per), sizeof per - strlen(per), "%s%s %.*f", q ? ", " : "", names[q], dp,
                             bench_median(tp + q * runs, runs));
                printf("| %s%s%s | %.*f | %s | %.2f |\n", list + nomap + sep, sep ? " (separate passes)" : "",
                       nomap ? " (no shadow map)" : mapped ? " (shadow map)" : "", dp, fm, per, single > 0 ? fm / single : 0);
            }
            /* the sun map's exactness here: the images with and without, merged and separate */
            for (int sep = 0; sep < 2 && !status && !gbuffer; sep++) {
                vx_pass_list L;
                vx_pass_list_parse("gbuffer,direct", &L, &err);
                vx_frame_result ra = {0}, rb = {0};
                fd = vx_frame_desc_defaults();
                fd.base = base;
                fd.base.spp = 1;
                fd.passes = &L;
                fd.separate_passes = sep;
                bool ok = vx_frame_render(fr, &fd, &ra, &err) == VX_OK;
                fd.base.no_shadow_map = true;
                ok = ok && vx_frame_render(fr, &fd, &rb, &err) == VX_OK;
                size_t differ = 0, n = (size_t)W * H * 4;
                for (size_t i = 0; ok && i < n; i++) differ += memcmp(&ra.image.pixels[i], &rb.image.pixels[i], sizeof(float)) != 0;
                if (ok)
                    printf("shadow map check (gbuffer,direct%s): the map %s; %zu of %zu values differ from the frame without\n",
                           sep ? ", separate passes" : "", ra.shadow_map ? "used" : "NOT used", differ, n);
                else
                    fprintf(stderr, "passes_bench: %s\n", err.msg), status = 1;
                vx_render_image_free(&ra.image), vx_render_image_free(&rb.image);
            }
            /* brute-force point lights with ray-traced shadows: the direct pass loops over every
             * light (the baseline for issue 11's clustered culling) */
            if (quick || gbuffer) continue;
            printf("\n| point lights (brute force, 16 shadowed) | frame ms | direct ms | direct ms per light |\n"
                   "| ---: | ---: | ---: | ---: |\n");
            static const uint32_t counts[] = {1, 8, 64, 512};
            for (size_t c = 0; c < sizeof counts / sizeof counts[0] && !status; c++) {
                uint32_t nl = counts[c];
                vx_light* ls = calloc(nl, sizeof *ls);
                uint32_t rng = 12345;
                for (uint32_t i = 0; ls && i < nl; i++) {
                    ls[i].type = VX_LIGHT_POINT;
                    for (int k = 0; k < 3; k++) {
                        rng = rng * 1664525u + 1013904223u;
                        ls[i].position[k] = lo[k] + (hi[k] - lo[k]) * ((rng >> 8) / 16777216.0);
                    }
                    ls[i].color[0] = ls[i].color[1] = ls[i].color[2] = 1;
                    ls[i].intensity = 100.0 / nl;
                }
                vx_pass_list L;
                vx_pass_list_parse("gbuffer,direct", &L, &err);
                fd = vx_frame_desc_defaults();
                fd.base = base;
                fd.base.spp = 1;
                fd.passes = &L;
                fd.no_readback = true;
                fd.separate_passes = true;
                fd.lights = ls, fd.light_count = nl;
                fd.light_culling = VX_LIGHT_CULLING_BRUTE;
                fd.shadow_lights = VX_SHADOW_LIGHTS_MAX;
                double* td = tp; /* direct pass times */
                for (int k = 0; k < 3 + runs && ls; k++) {
                    if (vx_frame_render(fr, &fd, &res, &err)) {
                        fprintf(stderr, "passes_bench: %s\n", err.msg);
                        status = 1;
                        break;
                    }
                    if (k >= 3) {
                        t[k - 3] = res.frame_ms;
                        td[k - 3] = 0;
                        for (uint32_t q = 0; q < res.timing_count; q++)
                            if (!strcmp(res.timings[q].name, "direct")) td[k - 3] = res.timings[q].ms;
                    }
                    vx_render_image_free(&res.image);
                }
                free(ls);
                if (status) break;
                double fm = bench_median(t, runs), dm = bench_median(td, runs);
                printf("| %u | %.3f | %.3f | %.4f |\n", nl, fm, dm, dm / nl);
            }
        }
        vx_frame_renderer_destroy(fr);
        vx_render_scene_destroy(rs);
        vx_svo_scene_free(&s);
    }
    free(t);
    free(tp);
    vx_gpu_destroy(gpu);
    return status;
}
