/* bench/render_bench.c - rays per second of voxkit's octree tracer against
 * two baselines over the same cells and the same primary rays: an ESVO
 * octree (a plain full-depth octree traced by the loop of Laine and Karras
 * 2010, bench/esvo.c and bench/shaders/esvo.comp) and a dense-grid 3D-DDA
 * (scenes up to 2^30 cells).
 *
 *   render_bench [--device N|NAME] [--sizes 1920x1080,...] [--runs N]
 *                [--views overview,oblique,closeup,sky] [--warmup SECONDS]
 *                [--generate] [--deep] [--variant auto|float|precise]
 *                [--no-esvo] [--tree64] [--mip] [--brick] [--brick-root L] [--grid-world] [--shader-stats] [--beam N,...] [--mrays]
 *                [--cpu-time]
 *                FILE.{svo,vox}...
 *
 * Each scene is seen from three views: the default overview, an oblique view
 * from low over a corner, and a full-frame close-up (a surface point of the
 * oblique view seen from nearby, at least 98% of the pixels hit where
 * possible); --views sky adds the oblique view's eye looking away from the
 * scene (every ray misses: the kernels' per-ray fixed cost). Per view: the GPU first runs each kernel for --warmup seconds
 * (clocks up), then the median of --runs timestamped dispatches is taken.
 * Hit share, the share of rays that enter an octree (voxkit: at least one
 * traversal step; ESVO: the ray meets the octree's cube), steps per ray (loop
 * iterations of the traversal, the same count in both kernels) and the
 * per-pixel depth agreement come from one frame of each. --generate adds the
 * procedural terrains 1024 and 4096 cells wide (bench/bench_terrain.h);
 * --deep the 1024 terrain placed in a model 2^20 cells wide (the float64
 * variant; no ESVO row). Output: one table row per scene, view and size.
 * --shader-stats: the driver's statistics of every kernel the run creates
 * (VK_KHR_pipeline_executable_properties where the device has it: registers,
 * local memory, instructions; lines "stats: LABEL [spec ...] ..."), the pass
 * pipeline's frame.comp and gbuffer.comp included (one small frame each).
 * --octree: voxkit's rows again with every model on its octree walk (the
 * grid walk off, render/grid.h; rows end "[kernel octree walk]", "px differ"
 * then counts the pixels whose hits differ from the grid walk's). --grid: the
 * grids' budget asked for (VX_RENDER_GRID_BUDGET: since stop 87 the default on
 * every device, so the flag changes nothing; kept for old command lines). --regions:
 * voxkit's rows again with a converter's regions each walked under the BVH
 * (the union grid off, render_scene.c grid_union; rows end "[kernel regions
 * apart]").
 * --beam: voxkit's rows for each beam block size (vx_render_desc.beam; 0 or
 * 1: off, the default), one row each with the baselines timed once per
 * view; steps per ray count the primary walk only (not the beam pass), and
 * the depth agreement checks every beam size against ESVO; rows after a
 * view's first end "[N px differ from the first row, M in colour]": pixels
 * whose instance, cell or depth bits differ from the first row's (list 0
 * first: the beam pass must change no hit), and pixels of the colour frame
 * (primary and shadow rays) whose values differ (kernel variants too).
 * --tree64: also the 64-tree prototype (bench/tree64.h; with ESVO only), its
 * kernel variants 0 and 1 (tree64.comp's SKIP): steps per ray, rays/s,
 * steps/s, rays/s over ESVO's, depth agreement with ESVO, and its GPU MiB,
 * timed like ESVO (columns ...T64). --mip: also the occupancy pyramid
 * prototype (bench/mipgrid.h; with ESVO only, cubes up to 2^10 cells wide),
 * its kernel variants 0-2 (mipgrid.comp's PROBE) after each view's row, a
 * line "mip-variant" each: steps per ray, rays/s, steps/s, rays/s over
 * ESVO's and voxkit's, depth agreement with voxkit's hits, GPU MiB. --brick:
 * the same for the two-level grid prototype (bench/brickgrid.h, lines
 * "brick-variant", brickgrid.comp's FCOORD 0 and 1; --brick-root L: its root
 * grid at most 2^L wide, default 7). --grid-world: world_from_grid of every
 * file set to the identity (a converted mesh in cells, so that the baselines,
 * which need world cells = grid cells, apply). --kernels FILE.spv,...: voxkit's
 * rows again for each of up to 8 variants of the float trace kernel (SPIR-V
 * of a shaders/trace.comp variant with the same bindings, e.g. from
 * glslangValidator -V; the grids at binding 14 and GRID, id 13, as the
 * built-in kernel gets them: a variant that declares neither walks the
 * octrees; rows end "[kernel FILE]"), in the same process and
 * view, the baselines timed once: per-step experiments measured side by side;
 * an entry T.spv:B.spv also replaces the beam pass (shaders/beam.comp) by B,
 * :B.spv the beam pass only.
 * --cpu-time: also the process's CPU time per frame of voxkit's primary rays
 * and ESVO's (mean over the timed runs; columns McpuVX, McpuES: rays per CPU
 * second, and their ratio cVX/ES; McpuSh: pixels of primary + shadow rays per
 * CPU second): on lavapipe, whose worker threads run the
 * kernels, a comparison that other jobs on the machine disturb less than the
 * dispatch timestamps do.
 * --shadow-map off|0|N,...: voxkit's rows again for each shadow map setting
 * (vx_render_scene_shadow_map_info): off (vx_render_desc.no_shadow_map), 0
 * the scene's default, N a map of N texels a side; rows end "[shadow map
 * on|off|none]" and each row with a map is preceded by a line "shadow map:"
 * with its side, its nodes and its build time (the timed frames trace with
 * the map built, as with the BVH). The colour frame of every row is compared
 * with the first row's (list off first: the map must change no pixel).
 * --mrays: rays/s, steps/s and pixels/s in millions (columns M...) instead of
 * billions, for slow devices (lavapipe).
 * --esvo-kernel FILE.spv: the ESVO baseline's rows with this kernel instead of
 * bench/shaders/esvo.comp (a variant with the same bindings, e.g. from
 * glslangValidator -V; the depth agreement with voxkit checks it).
 * --esvo-kernels FILE.spv,...: up to 8 variants of the ESVO kernel timed after
 * the baseline in the same process and view, a line "esvo-variant" each: steps,
 * rays/s, its rate over the baseline's and its depth agreement with voxkit
 * (the per-step probes of both kernels side by side).
 * Every row ends "[warps: lane use VX / ES]": the loop's steps summed over the
 * lanes of each 32-lane warp (an 8x4 pixel tile of the kernels' 8x8 groups,
 * voxkit's grid from its traced rectangle's corner) over 32 times the warp's
 * largest, over all warps: the share of a warp's loop iterations its lanes
 * use (1 - the divergence's idle share). */
#define _POSIX_C_SOURCE 200809L /* setenv */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bench/bench_load.h"
#include "bench/bench_terrain.h"
#include "bench/esvo.h"
#include "bench/brickgrid.h"
#include "bench/mipgrid.h"
#include "bench/tree64.h"
#include "render/pipeline.h"
#include "render/gpu.h" /* vx__render_scene_far */
#include "render/testing.h"

typedef struct view_result {
    double hit, enter_vx, enter_es, steps_vx, steps_es, sec_vx, sec_es, sec_shadow, sec_dense, agree;
    /* the 64-tree prototype per kernel variant: steps, time, depth agreement with ESVO */
    double steps_t[2], sec_t[2], agree_t[2];
    double cpu_vx, cpu_es, cpu_sh; /* process CPU seconds per frame (--cpu-time); sh: primary + shadow */
    /* pixels whose instance, cell or depth bits differ from the first row
     * of the view (beam 0 first: the beam pass must change none); -1: none */
    long beam_diff;
    long color_diff; /* likewise, pixels of the colour frame (primary + shadow) whose values differ */
    double sh_share, sh_steps; /* pixels that cast a shadow ray, and its loop iterations (vx_render_hit.shadow) */
    double warp_vx, warp_es;   /* the warps' lane use (warp_use; -1: none) */
} view_result;

/* A view's first row: its hits and its colour frame, which every later
 * row (beam size, kernel variant) must reproduce bit for bit. */
typedef struct row_ref {
    vx_render_hit* hits;
    float* color;
} row_ref;

static double cpu_now(void) {
    struct timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* Lane use of the 32-lane warps of a dispatch of 8x8 groups over the pixels
 * [r[0], r[2]) x [r[1], r[3]) of a W-wide image (NVIDIA's warps are 32
 * consecutive invocations: rows 0-3 and 4-7 of a group): the steps of every
 * lane summed, over 32 times each warp's largest (lanes past the rectangle
 * count as idle). -1 where no warp steps. */
static double warp_use(const uint32_t* steps, uint32_t W, const uint32_t r[4]) {
    double sum = 0, cap = 0;
    for (uint32_t y0 = r[1]; y0 < r[3]; y0 += 4)
        for (uint32_t x0 = r[0]; x0 < r[2]; x0 += 8) {
            uint32_t mx = 0;
            for (uint32_t y = y0; y < y0 + 4 && y < r[3]; y++)
                for (uint32_t x = x0; x < x0 + 8 && x < r[2]; x++) {
                    uint32_t st = steps[(size_t)y * W + x] & 0x7FFFFFFFu;
                    sum += st;
                    if (st > mx) mx = st;
                }
            cap += 32.0 * mx;
        }
    return cap > 0 ? sum / cap : -1;
}

static void usage(FILE* out, const char* prog) {
    fprintf(out,
            "usage: %s [--device N|NAME] [--sizes WxH,...] [--runs N] [--views overview,oblique,closeup,sky]\n"
            "          [--warmup SECONDS] [--generate] [--deep] [--variant auto|float|precise] [--no-esvo]\n"
            "          [--tree64] [--mip] [--brick] [--brick-root L] [--grid-world] [--shader-stats] [--beam N,...] [--kernels F.spv,...] [--octree] [--regions] [--grid] [--mrays] [--cpu-time]\n"
            "          [--shadow-map off|0|N,...] [--esvo-kernel F.spv] [--esvo-kernels F.spv,...] FILE...\n"
            "defaults: --sizes 1920x1080 --runs 15 --views overview,oblique,closeup --warmup 0.5 --beam %u\n"
            "(--beam 0 or 1: no beam pass; up to 8 sizes)\n",
            prog, vx_render_desc_defaults().beam);
}

/* The words of a SPIR-V file (free with free), or NULL. */
static uint32_t* read_spirv(const char* path, size_t* bytes) {
    FILE* f = fopen(path, "rb");
    if (!f) return NULL;
    uint32_t* w = NULL;
    long n = fseek(f, 0, SEEK_END) ? -1 : ftell(f);
    if (n > 0 && n % 4 == 0 && !fseek(f, 0, SEEK_SET) && (w = malloc((size_t)n)) && fread(w, 1, (size_t)n, f) != (size_t)n)
        free(w), w = NULL;
    fclose(f);
    *bytes = w ? (size_t)n : 0;
    return w;
}

static void print_stats(void* user, vx_log_level level, const char* id, const char* msg) {
    (void)user, (void)level;
    if (!strcmp(id, "gpu.shader_stats")) printf("stats: %s\n", msg);
    fflush(stdout);
}

/* One small frame through the pass pipeline, merged (frame.comp) and as
 * separate passes (gbuffer.comp, direct.comp, resolve.comp), so that their
 * kernels are created (and their statistics logged). */
static vx_result pass_kernels(vx_render_scene* rs, const vx_svo_scene* s, vx_render_camera cam, vx_error* err) {
    vx_frame_renderer* fr = NULL;
    vx_result r = vx_frame_renderer_create(rs, s, &fr, err);
    for (int sep = 0; sep < 2 && !r; sep++) {
        vx_frame_desc fd = {.base = {.width = 64, .height = 64, .camera = cam}, .separate_passes = sep};
        vx_frame_result res = {0};
        r = vx_frame_render(fr, &fd, &res, err);
        vx_render_image_free(&res.image);
    }
    vx_frame_renderer_destroy(fr);
    return r;
}

/* Runs fn(repeat 32) until `seconds` of wall time have passed. */
static vx_result warm(vx_render_scene* rs, bench_esvo* es, bench_tree64* t6, uint32_t t6_variant,
                      const vx_svo_scene* s, const vx_render_desc* d, double seconds, vx_error* err) {
    double t0 = vx_time_now(), sec;
    vx__frame f;
    do {
        vx_result r = t6   ? bench_tree64_frame(t6, t6_variant, s, d, 32, &sec, NULL, NULL, err)
                      : es ? bench_esvo_frame(es, s, d, 32, &sec, NULL, NULL, err)
                           : vx__render_dispatch(rs, d, false, 32, &f, &sec, err);
        if (r) return r;
    } while (vx_time_now() - t0 < seconds);
    return VX_OK;
}

/* The world point that pixel (px, py) of frame f sees at depth t. */
static void pixel_point(const vx__frame* f, uint32_t px, uint32_t py, double t, double p[3], double dir[3]) {
    double u = ((px + 0.5) / f->width) * 2 - 1, v = 1 - ((py + 0.5) / f->height) * 2, l = 0;
    for (int k = 0; k < 3; k++) dir[k] = f->fwd[k] + u * f->rx[k] + v * f->uy[k], l += dir[k] * dir[k];
    l = sqrt(l);
    for (int k = 0; k < 3; k++) dir[k] /= l, p[k] = f->ref[k] - f->fwd[k] * f->t_start + dir[k] * t;
}

/* Share of pixels hit in a small probe frame of camera c; the frame's hits
 * go to *keep when it is not NULL (free with vx_render_image_free). */
static double probe_hits(vx_render_scene* rs, vx_render_camera c, vx_render_image* keep) {
    vx_render_desc d = {.width = 97, .height = 55, .mode = VX_RENDER_DEPTH, .camera = c, .want_hits = true};
    vx_render_image img = {0};
    vx_error err = {0};
    if (vx_render_frame(rs, &d, &img, &err)) return 0;
    size_t n = (size_t)img.width * img.height, h = 0;
    for (size_t i = 0; i < n; i++) h += img.hits[i].instance != VX_RENDER_NO_HIT;
    if (keep) *keep = img;
    else vx_render_image_free(&img);
    return (double)h / n;
}

/* Cameras of the three views (overview: the default framing). */
static bool make_views(vx_render_scene* rs, const vx_svo_scene* s, vx_render_camera cams[3]) {
    double lo[3], hi[3], c[3], rad = 0;
    vx_svo_scene_world_bounds(s, lo, hi);
    for (int k = 0; k < 3; k++) c[k] = 0.5 * (lo[k] + hi[k]), rad += (hi[k] - lo[k]) * (hi[k] - lo[k]);
    rad = 0.5 * sqrt(rad);
    memset(cams, 0, 3 * sizeof *cams);
    /* oblique: from low over the (-x, -y) corner, about 17 degrees up */
    double dir[3] = {-0.7, -0.6, 0.3}, l = sqrt(0.49 + 0.36 + 0.09);
    cams[1].set = true;
    for (int k = 0; k < 3; k++) cams[1].eye[k] = c[k] + dir[k] / l * 1.3 * rad, cams[1].target[k] = c[k];
    /* close-up: the hit nearest the centre of the oblique view, from nearby */
    vx_render_image img = {0};
    probe_hits(rs, cams[1], &img);
    if (!img.hits) return false;
    vx__frame f;
    vx_error err = {0};
    vx_render_desc d = {.width = img.width, .height = img.height, .camera = cams[1]};
    if (vx__frame_setup(lo, hi, &d, &f, &err)) {
        vx_render_image_free(&img);
        return false;
    }
    double best = INFINITY;
    uint32_t bx = 0, by = 0;
    for (uint32_t y = 0; y < img.height; y++)
        for (uint32_t x = 0; x < img.width; x++) {
            if (img.hits[y * img.width + x].instance == VX_RENDER_NO_HIT) continue;
            double dx = x - 0.5 * img.width, dy = y - 0.5 * img.height;
            if (dx * dx + dy * dy < best) best = dx * dx + dy * dy, bx = x, by = y;
        }
    if (!isfinite(best)) {
        vx_render_image_free(&img);
        return false;
    }
    double p[3], rd[3];
    pixel_point(&f, bx, by, img.hits[by * img.width + bx].t, p, rd);
    vx_render_image_free(&img);
    double best_share = -1;
    static const double dist[] = {0.25, 0.12, 0.06, 0.03, 0.015, 0.008};
    for (size_t i = 0; i < sizeof dist / sizeof dist[0]; i++) {
        vx_render_camera cc = {.set = true};
        double dd = fmax(dist[i] * rad, 6.0);
        for (int k = 0; k < 3; k++) cc.eye[k] = p[k] - rd[k] * dd, cc.target[k] = p[k];
        double share = probe_hits(rs, cc, NULL);
        if (share > best_share) best_share = share, cams[2] = cc;
        if (share >= 0.98) break;
    }
    return true;
}

/* Times voxkit's kernels for d; the baselines (ESVO, dense) only with
 * time_base (ESVO's depth frame is compared whenever es is set). */
static int run_view(vx_render_scene* rs, bench_esvo* es, bench_tree64* t6, uint32_t t6_variants,
                    const vx_svo_scene* s, vx_render_desc d, bool dense, bool time_base, uint32_t runs, double warmup,
                    row_ref* ref, view_result* out, vx_error* err) {
    view_result prev = *out;
    memset(out, 0, sizeof *out);
    if (!time_base)
        out->sec_es = prev.sec_es, out->sec_dense = prev.sec_dense,
        memcpy(out->sec_t, prev.sec_t, sizeof out->sec_t), memcpy(out->steps_t, prev.steps_t, sizeof out->steps_t),
        memcpy(out->agree_t, prev.agree_t, sizeof out->agree_t), out->cpu_es = prev.cpu_es;
    size_t npx = (size_t)d.width * d.height;
    /* one frame of each with per-pixel results */
    d.mode = VX_RENDER_DEPTH;
    d.want_hits = true;
    vx_render_image img = {0};
    if (vx_render_frame(rs, &d, &img, err)) return 1;
    float* edepth = es ? malloc(npx * sizeof *edepth) : NULL;
    uint32_t* esteps = es ? malloc(npx * sizeof *esteps) : NULL;
    double sec;
    if (es && (!edepth || !esteps || bench_esvo_frame(es, s, &d, 1, &sec, edepth, esteps, err))) {
        free(edepth), free(esteps);
        vx_render_image_free(&img);
        return 1;
    }
    for (uint32_t tv = 0; es && t6 && time_base && tv < t6_variants; tv++) {
        /* the 64-tree against ESVO's depth, the same test as voxkit's */
        float* tdepth = malloc(npx * sizeof *tdepth);
        uint32_t* tsteps = malloc(npx * sizeof *tsteps);
        if (!tdepth || !tsteps || bench_tree64_frame(t6, tv, s, &d, 1, &sec, tdepth, tsteps, err)) {
            free(tdepth), free(tsteps), free(edepth), free(esteps);
            vx_render_image_free(&img);
            return 1;
        }
        size_t ag = 0;
        double st = 0;
        for (size_t i = 0; i < npx; i++) {
            st += tsteps[i] & 0x7FFFFFFFu;
            bool ht = isfinite(tdepth[i]), he = isfinite(edepth[i]);
            if (ht == he && (!ht || fabs((double)tdepth[i] - edepth[i]) <= 1e-4 * fmax(fabs((double)edepth[i]), 1.0)))
                ag++;
        }
        out->steps_t[tv] = st / npx, out->agree_t[tv] = (double)ag / npx;
        free(tdepth), free(tsteps);
    }
    size_t hits = 0, ent_vx = 0, ent_es = 0, agree = 0;
    double st_vx = 0, st_es = 0;
    for (size_t i = 0; i < npx; i++) {
        const vx_render_hit* h = &img.hits[i];
        bool hv = h->instance != VX_RENDER_NO_HIT;
        hits += hv;
        ent_vx += h->iterations > 0;
        st_vx += h->iterations;
        if (!es) continue;
        ent_es += esteps[i] >> 31;
        st_es += esteps[i] & 0x7FFFFFFFu;
        bool he = isfinite(edepth[i]);
        if (hv == he && (!hv || fabs((double)h->t - edepth[i]) <= 1e-4 * fmax(fabs((double)h->t), 1.0))) agree++;
    }
    /* divergence: the warps' lane use of both kernels on these rays (voxkit's
     * grid starts at the screen cull's rectangle, ESVO's at pixel 0, 0) */
    out->warp_vx = out->warp_es = -1;
    uint32_t* vsteps = malloc(npx * sizeof *vsteps);
    if (vsteps) {
        for (size_t i = 0; i < npx; i++) vsteps[i] = img.hits[i].iterations;
        uint32_t rect[4] = {0, 0, d.width, d.height};
        uint64_t tp;
        double blo[3], bhi[3];
        vx__frame f0;
        vx_error e0 = {0};
        vx_svo_scene_world_bounds(s, blo, bhi);
        if (vx__render_scene_traced(rs, &tp) && !vx__frame_setup(blo, bhi, &d, &f0, &e0)) {
            vx__frame_rect(&f0, blo, bhi, rect);
            if ((uint64_t)(rect[2] - rect[0]) * (rect[3] - rect[1]) != tp) /* not the library's rectangle */
                rect[0] = rect[1] = 0, rect[2] = d.width, rect[3] = d.height, out->warp_vx = -2;
        }
        if (out->warp_vx != -2) out->warp_vx = warp_use(vsteps, d.width, rect);
        uint32_t full[4] = {0, 0, d.width, d.height};
        if (es) out->warp_es = warp_use(esteps, d.width, full);
        free(vsteps);
    }
    out->beam_diff = -1;
    if (ref->hits) {
        out->beam_diff = 0;
        for (size_t i = 0; i < npx; i++) {
            const vx_render_hit *a = &img.hits[i], *b = &ref->hits[i];
            out->beam_diff += a->instance != b->instance || memcmp(a->cell, b->cell, sizeof a->cell) ||
                              memcmp(&a->t, &b->t, sizeof a->t);
        }
        vx_render_image_free(&img);
    } else {
        ref->hits = malloc(npx * sizeof *ref->hits); /* the caller frees it */
        if (ref->hits) memcpy(ref->hits, img.hits, npx * sizeof *ref->hits);
        vx_render_image_free(&img);
    }
    /* the colour frame (primary and shadow rays) against the first row's,
     * after one that lets the scene build the shadow map (a light the frame
     * before had: vx_render_scene_shadow_map_info) */
    d.mode = VX_RENDER_COLOR;
    d.want_hits = false;
    if (vx_render_frame(rs, &d, &img, err)) {
        free(edepth), free(esteps);
        return 1;
    }
    vx_render_image_free(&img);
    if (vx_render_frame(rs, &d, &img, err)) {
        free(edepth), free(esteps);
        return 1;
    }
    out->color_diff = -1;
    if (ref->color) {
        out->color_diff = 0;
        for (size_t i = 0; i < npx; i++) out->color_diff += memcmp(&img.pixels[4 * i], &ref->color[4 * i], 16) != 0;
    } else {
        ref->color = malloc(npx * 16); /* the caller frees it */
        if (ref->color) memcpy(ref->color, img.pixels, npx * 16);
    }
    vx_render_image_free(&img);
    /* the shadow rays' share and steps (the colour frame with hits records) */
    d.want_hits = true;
    if (vx_render_frame(rs, &d, &img, err)) {
        free(edepth), free(esteps);
        return 1;
    }
    size_t ncast = 0;
    double sst = 0;
    for (size_t i = 0; i < npx; i++)
        if (img.hits[i].shadow & VX_RENDER_SHADOW_CAST) ncast++, sst += img.hits[i].shadow & ~VX_RENDER_SHADOW_CAST;
    out->sh_share = (double)ncast / npx, out->sh_steps = ncast ? sst / ncast : 0;
    vx_render_image_free(&img);
    d.want_hits = false;
    d.mode = VX_RENDER_DEPTH;
    free(edepth), free(esteps);
    out->hit = (double)hits / npx;
    out->enter_vx = (double)ent_vx / npx, out->steps_vx = st_vx / npx;
    out->enter_es = (double)ent_es / npx, out->steps_es = st_es / npx;
    out->agree = (double)agree / npx;
    d.want_hits = false;
    vx__frame f;
    /* voxkit primary rays (depth mode), then primary + shadow (colour mode) */
    if (vx__render_dispatch(rs, &d, false, 1, &f, &sec, err) || warm(rs, NULL, NULL, 0, s, &d, warmup, err))
        return 1;
    double c0 = cpu_now();
    if (vx__render_dispatch(rs, &d, false, runs, &f, &out->sec_vx, err)) return 1;
    out->cpu_vx = (cpu_now() - c0) / runs;
    if (es && time_base) {
        if (warm(NULL, es, NULL, 0, s, &d, warmup, err)) return 1;
        c0 = cpu_now();
        if (bench_esvo_frame(es, s, &d, runs, &out->sec_es, NULL, NULL, err)) return 1;
        out->cpu_es = (cpu_now() - c0) / runs;
    }
    for (uint32_t tv = 0; es && t6 && time_base && tv < t6_variants; tv++)
        if (warm(NULL, NULL, t6, tv, s, &d, warmup, err) ||
            bench_tree64_frame(t6, tv, s, &d, runs, &out->sec_t[tv], NULL, NULL, err))
            return 1;
    d.mode = VX_RENDER_COLOR;
    if (vx__render_dispatch(rs, &d, false, 1, &f, &sec, err)) return 1;
    c0 = cpu_now();
    if (vx__render_dispatch(rs, &d, false, runs, &f, &out->sec_shadow, err)) return 1;
    out->cpu_sh = (cpu_now() - c0) / runs;
    d.mode = VX_RENDER_DEPTH;
    if (dense && time_base && (vx__dense_dispatch(rs, &d, 1, &sec, NULL, err) ||
                  vx__dense_dispatch(rs, &d, runs, &out->sec_dense, NULL, err)))
        return 1;
    return 0;
}

/* A baseline variant's frame (depth, steps of each pixel) against voxkit's
 * hits: out[0] steps per ray, out[2] the share of pixels whose depth agrees
 * (as run_view's test; -1 without hits), out[3] its warps' lane use. */
static void variant_stats(const float* depth, const uint32_t* steps, uint32_t width, uint32_t height,
                          const vx_render_hit* vx_hits, double out[4]) {
    size_t npx = (size_t)width * height, agree = 0;
    double st = 0;
    for (size_t i = 0; i < npx; i++) {
        st += steps[i] & 0x7FFFFFFFu;
        bool hv = vx_hits && vx_hits[i].instance != VX_RENDER_NO_HIT, he = isfinite(depth[i]);
        if (vx_hits && hv == he && (!hv || fabs((double)vx_hits[i].t - depth[i]) <= 1e-4 * fmax(fabs((double)vx_hits[i].t), 1.0)))
            agree++;
    }
    uint32_t full[4] = {0, 0, width, height};
    out[0] = st / npx, out[2] = vx_hits ? (double)agree / npx : -1, out[3] = warp_use(steps, width, full);
}

/* An ESVO kernel variant (--esvo-kernels) on view d after the baseline:
 * out[0] steps per ray, [1] seconds per frame (median of runs), [2] the
 * share of pixels whose depth agrees with voxkit's hits (as run_view's
 * test), [3] its warps' lane use. The baseline's kernel is restored. */
static int esvo_variant(bench_esvo* es, const uint32_t* spv, size_t bytes, const vx_svo_scene* s, vx_render_desc d,
                        uint32_t runs, double warmup, const vx_render_hit* vx_hits, double out[4], vx_error* err) {
    size_t npx = (size_t)d.width * d.height;
    float* depth = malloc(npx * sizeof *depth);
    uint32_t* steps = malloc(npx * sizeof *steps);
    const uint32_t* spv0 = es->spv;
    size_t bytes0 = es->spv_bytes;
    es->spv = spv, es->spv_bytes = bytes;
    double sec;
    int fail = !depth || !steps || bench_esvo_frame(es, s, &d, 1, &sec, depth, steps, err) ||
               warm(NULL, es, NULL, 0, s, &d, warmup, err) || bench_esvo_frame(es, s, &d, runs, &out[1], NULL, NULL, err);
    es->spv = spv0, es->spv_bytes = bytes0;
    if (!fail) variant_stats(depth, steps, d.width, d.height, vx_hits, out);
    free(depth), free(steps);
    return fail;
}

/* One frame of a prototype kernel (--mip, --brick): as bench_mip_frame. */
typedef vx_result (*proto_frame_fn)(void* m, uint32_t variant, const vx_svo_scene* s, const vx_render_desc* desc,
                                    uint32_t repeat, double* seconds, float* depth, uint32_t* steps, vx_error* err);

static vx_result mip_frame(void* m, uint32_t v, const vx_svo_scene* s, const vx_render_desc* d, uint32_t repeat,
                           double* sec, float* depth, uint32_t* steps, vx_error* err) {
    return bench_mip_frame(m, v, s, d, repeat, sec, depth, steps, err);
}

static vx_result brick_frame(void* m, uint32_t v, const vx_svo_scene* s, const vx_render_desc* d, uint32_t repeat,
                             double* sec, float* depth, uint32_t* steps, vx_error* err) {
    return bench_brick_frame(m, v, s, d, repeat, sec, depth, steps, err);
}

/* A prototype (--mip, --brick) on view d, variant v: out as esvo_variant's. */
static int proto_variant(proto_frame_fn frame, void* m, uint32_t v, const vx_svo_scene* s, vx_render_desc d,
                         uint32_t runs, double warmup, const vx_render_hit* vx_hits, double out[4], vx_error* err) {
    size_t npx = (size_t)d.width * d.height;
    float* depth = malloc(npx * sizeof *depth);
    uint32_t* steps = malloc(npx * sizeof *steps);
    double sec, t0;
    int fail = !depth || !steps || frame(m, v, s, &d, 1, &sec, depth, steps, err);
    t0 = vx_time_now();
    while (!fail && vx_time_now() - t0 < warmup) fail = frame(m, v, s, &d, 32, &sec, NULL, NULL, err) != VX_OK;
    if (!fail) fail = frame(m, v, s, &d, runs, &out[1], NULL, NULL, err) != VX_OK;
    if (!fail) variant_stats(depth, steps, d.width, d.height, vx_hits, out);
    free(depth), free(steps);
    return fail;
}

int main(int argc, char** argv) {
    const char* device = NULL;
    const char* sizes = "1920x1080";
    const char* views = "overview,oblique,closeup";
    uint32_t beam_list[8] = {0};
    int nbeam = 1;
    uint32_t smap_list[8] = {0}; /* 0: the scene's default map; 1: off; N: a map of N texels a side */
    int nsmap = 1;
    const char* kname[9] = {NULL};
    uint32_t* kspv[9] = {NULL};
    size_t kbytes[9] = {0};
    uint32_t* bspv[9] = {NULL}; /* the beam pass's variants */
    size_t bbytes[9] = {0};
    int nkern = 1; /* 0: the built-in kernel */
    /* per kernel: the screen cull (-1: the library's) */
    int kcull[9] = {-1, -1, -1, -1, -1, -1, -1, -1, -1};
    int kpath[9] = {-1, -1, -1, -1, -1, -1, -1, -1, -1};
    int kgrid[9] = {-1, -1, -1, -1, -1, -1, -1, -1, -1}; /* the grid walk (-1: the library's) */
    int kunion[9] = {-1, -1, -1, -1, -1, -1, -1, -1, -1}; /* the union grid of regions (-1: the library's) */
    char klabel[9][96];
    uint32_t runs = 15;
    uint32_t brick_root = 0; /* --brick-root: bench_brick_create's root_log */
    double warmup = 0.5;
    uint32_t* esvo_spv = NULL; /* --esvo-kernel */
    size_t esvo_bytes = 0;
    uint32_t* ev_spv[8] = {NULL}; /* --esvo-kernels */
    size_t ev_bytes[8] = {0};
    const char* ev_name[8] = {NULL};
    int nev = 0;
    bool force_grid = false;
    bool gen = false, deep = false, use_esvo = true, use_tree64 = false, use_mip = false, use_brick = false, stats = false, mrays = false, cpu = false;
    uint32_t t6_variants = 2;
    bool grid_world = false;
    int variant = -1;
    const char* files[64];
    int nf = 0;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "-h") || !strcmp(argv[i], "--help")) {
            usage(stdout, argv[0]);
            return 0;
        } else if (!strcmp(argv[i], "--device") && i + 1 < argc) device = argv[++i];
        else if (!strcmp(argv[i], "--sizes") && i + 1 < argc) sizes = argv[++i];
        else if (!strcmp(argv[i], "--views") && i + 1 < argc) views = argv[++i];
        else if (!strcmp(argv[i], "--beam") && i + 1 < argc) {
            const char* bp = argv[++i];
            for (nbeam = 0; nbeam < 8;) {
                char* end;
                unsigned long n = strtoul(bp, &end, 10);
                if (end == bp || n > 64 || (*end && *end != ',')) {
                    fprintf(stderr, "render_bench: --beam wants up to 8 block sizes from 0 to 64, not '%s'\n", argv[i]);
                    return 2;
                }
                beam_list[nbeam++] = (uint32_t)n;
                if (!*end) break;
                bp = end + 1;
            }
        }
        else if (!strcmp(argv[i], "--shadow-map") && i + 1 < argc) {
            const char* bp = argv[++i];
            for (nsmap = 0; nsmap < 8;) {
                char* end = NULL;
                unsigned long n = 0;
                if (!strncmp(bp, "off", 3)) n = 1, end = (char*)bp + 3;
                else n = strtoul(bp, &end, 10);
                if (end == bp || (n > 1 && (n < 16 || n > 16384)) || (*end && *end != ',')) {
                    fprintf(stderr, "render_bench: --shadow-map wants up to 8 of off, 0 (default) or 16..16384, not '%s'\n",
                            argv[i]);
                    return 2;
                }
                smap_list[nsmap++] = (uint32_t)n;
                if (!*end) break;
                bp = end + 1;
            }
        }
        else if (!strcmp(argv[i], "--grid")) force_grid = true;
        else if (!strcmp(argv[i], "--octree")) {
            /* the built-in kernel again with every model on its octree walk (no grid walk) */
            if (nkern < 9) {
                snprintf(klabel[nkern], sizeof klabel[nkern], "octree walk");
                kgrid[nkern] = 0, kname[nkern] = klabel[nkern], nkern++;
            }
        }
        else if (!strcmp(argv[i], "--regions")) {
            /* the built-in kernel again with a converter's regions each walked under the BVH (no union grid) */
            if (nkern < 9) {
                snprintf(klabel[nkern], sizeof klabel[nkern], "regions apart");
                kunion[nkern] = 0, kname[nkern] = klabel[nkern], nkern++;
            }
        }
        else if (!strcmp(argv[i], "--kernels") && i + 1 < argc) {
            char* list = argv[++i];
            for (char* t = strtok(list, ","); t; t = strtok(NULL, ",")) {
                /* ENTRY@cM[pN]: the kernel with the screen cull M (0 off, 1 on) and
                 * the primary rays' starts below the root N (0 off, 1 on; without:
                 * the library's default, on for GPUs, off for CPU devices);
                 * @cM alone: the built-in kernel so; another kernel without it: off (main's trace.comp
                 * reads no rectangle) */
                if (nkern < 9) {
                    snprintf(klabel[nkern], sizeof klabel[nkern], "%s", t);
                    char* at = strchr(t, '@');
                    if (at) {
                        const char* q = at + 1;
                        bool ok = q[0] == 'c' && (q[1] == '0' || q[1] == '1');
                        unsigned cc = ok ? (unsigned)(q[1] - '0') : 0;
                        int pp = -1;
                        if (ok) q += 2;
                        if (ok && q[0] == 'p' && (q[1] == '0' || q[1] == '1')) pp = q[1] - '0', q += 2;
                        if (!ok || *q) {
                            fprintf(stderr, "render_bench: --kernels: '%s': want @c0 or @c1, optionally p0 or p1\n", at);
                            return 2;
                        }
                        kcull[nkern] = (int)cc;
                        kpath[nkern] = pp;
                        *at = 0;
                        if (!*t) {
                            kname[nkern] = klabel[nkern], nkern++;
                            continue;
                        }
                    } else {
                        kcull[nkern] = 0;
                    }
                }
                /* T.spv:B.spv: also the beam pass from B ("" for T: the built-in trace kernel) */
                char* colon = strchr(t, ':');
                if (colon && nkern < 9) {
                    *colon = 0;
                    if (!(bspv[nkern] = read_spirv(colon + 1, &bbytes[nkern]))) {
                        fprintf(stderr, "render_bench: --kernels: %s: cannot read a SPIR-V file\n", colon + 1);
                        return 2;
                    }
                    if (!*t) {
                        kname[nkern] = klabel[nkern], nkern++;
                        continue;
                    }
                }
                if (nkern == 9 || !(kspv[nkern] = read_spirv(t, &kbytes[nkern]))) {
                    fprintf(stderr, "render_bench: --kernels: %s: %s\n", t,
                            nkern == 9 ? "more than 8 kernels" : "cannot read a SPIR-V file");
                    return 2;
                }
                kname[nkern] = klabel[nkern], nkern++;
            }
        }
        else if (!strcmp(argv[i], "--runs") && i + 1 < argc) {
            char* end;
            errno = 0;
            unsigned long n = strtoul(argv[++i], &end, 10);
            if (errno || *end || end == argv[i] || n < 1 || n > 100000 || argv[i][0] == '-') {
                fprintf(stderr, "render_bench: --runs wants a count from 1 to 100000, not '%s'\n", argv[i]);
                return 2;
            }
            runs = (uint32_t)n;
        } else if (!strcmp(argv[i], "--warmup") && i + 1 < argc) {
            char* end;
            warmup = strtod(argv[++i], &end);
            if (*end || !(warmup >= 0 && warmup <= 60)) {
                fprintf(stderr, "render_bench: --warmup wants seconds from 0 to 60, not '%s'\n", argv[i]);
                return 2;
            }
        } else if (!strcmp(argv[i], "--generate")) gen = true;
        else if (!strcmp(argv[i], "--deep")) deep = true;
        else if (!strcmp(argv[i], "--no-esvo")) use_esvo = false;
        else if (!strcmp(argv[i], "--esvo-kernel") && i + 1 < argc) {
            esvo_spv = read_spirv(argv[++i], &esvo_bytes);
            if (!esvo_spv) {
                fprintf(stderr, "render_bench: --esvo-kernel: cannot read SPIR-V from '%s'\n", argv[i]);
                return 2;
            }
        }
        else if (!strcmp(argv[i], "--esvo-kernels") && i + 1 < argc) {
            for (char* t = strtok(argv[++i], ","); t; t = strtok(NULL, ",")) {
                if (nev == 8 || !(ev_spv[nev] = read_spirv(t, &ev_bytes[nev]))) {
                    fprintf(stderr, "render_bench: --esvo-kernels: %s: %s\n", t,
                            nev == 8 ? "more than 8 kernels" : "cannot read a SPIR-V file");
                    return 2;
                }
                ev_name[nev++] = t;
            }
        }
        else if (!strcmp(argv[i], "--mrays")) mrays = true;
        else if (!strcmp(argv[i], "--cpu-time")) cpu = true;
        else if (!strcmp(argv[i], "--tree64")) use_tree64 = true;
        else if (!strcmp(argv[i], "--mip")) use_mip = true;
        else if (!strcmp(argv[i], "--brick")) use_brick = true;
        else if (!strcmp(argv[i], "--brick-root") && i + 1 < argc) use_brick = true, brick_root = (uint32_t)atoi(argv[++i]);
        else if (!strcmp(argv[i], "--grid-world")) grid_world = true;
        else if (!strcmp(argv[i], "--shader-stats")) stats = true;
        else if (!strcmp(argv[i], "--variant") && i + 1 < argc) {
            i++;
            variant = !strcmp(argv[i], "float") ? 0 : !strcmp(argv[i], "precise") ? 1 : -1;
        } else if (argv[i][0] == '-') {
            fprintf(stderr, "render_bench: unknown option %s\n", argv[i]);
            usage(stderr, argv[0]);
            return 2;
        } else if (nf < 64) {
            files[nf++] = argv[i];
        } else { /* never drop a scene silently */
            fprintf(stderr, "render_bench: at most 64 scene files a run (%s and after left out: run them apart)\n", argv[i]);
            return 2;
        }
    }
    vx_error err = {0};
    vx_gpu* gpu;
    /* read by render/gpu_device.c and gpu_pipeline.c */
    if (stats && setenv("VX_GPU_SHADER_STATS", "1", 1)) stats = false;
    vx_logger logger = {.func = print_stats};
    if (vx_gpu_create(&(vx_gpu_desc){.device = device, .logger = stats ? &logger : NULL}, &gpu, &err)) {
        fprintf(stderr, "render_bench: %s\n", err.msg);
        return 1;
    }
    printf("device: %s; median of %u timestamped dispatches after %.2f s warm-up per kernel and view\n",
           vx_gpu_device_name(gpu), runs, warmup);
    /* rates in G (M with --mrays) per second */
    const double U = mrays ? 1e-6 : 1e-9;
    const char* u = mrays ? "M" : "G";
    char hd[7][16];
    static const char* const hn[7] = {"rayVX", "rayES", "stVX", "stES", "pixSh", "rayDn", "rayT64"};
    for (int k = 0; k < 7; k++) snprintf(hd[k], sizeof hd[k], "%s%s", u, hn[k]);
    printf("%-20s %-8s %-9s %4s %5s %5s %5s %6s %6s %7s %7s %7s %7s %6s %7s %7s %7s %9s %9s", "scene", "view", "size",
           "beam", "hit", "entVX", "entES", "stVX", "stES", hd[0], hd[1], hd[2], hd[3], "VX/ES", "depth=", hd[4],
           hd[5], "MiB VX", "MiB ES");
    for (uint32_t tv = 0; use_tree64 && tv < t6_variants; tv++)
        printf("  stT64.%u %s %sstT64 T64/ES T64dep=", tv, hd[6], u);
    if (use_tree64) printf(" %9s", "MiB T64");
    if (cpu) printf(" %5scpuVX %5scpuES cVX/ES %5scpuSh", u, u, u);
    printf("\n");
    fflush(stdout);
    int total = nf + (gen ? 2 : 0) + (deep ? 1 : 0);
    int failed = 0;
    for (int k = 0; k < total; k++) {
        vx_svo_scene s;
        const char* name;
        double t0 = vx_time_now();
        bool is_deep = false;
        if (k < nf) {
            name = strrchr(files[k], '/') ? strrchr(files[k], '/') + 1 : files[k];
            if (bench_load(files[k], &s, &err)) {
                fprintf(stderr, "render_bench: %s: %s\n", files[k], err.msg);
                failed = 1;
                continue;
            }
            if (grid_world) { /* world units = cells, so that the baselines see the scene's cells */
                static const double id[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
                memcpy(s.world_from_grid, id, sizeof id);
                vx_svo_scene_update_bounds(&s);
            }
        } else {
            is_deep = deep && k == total - 1;
            uint32_t extent = is_deep || k == nf ? 1024 : 4096;
            name = is_deep ? "terrain1024in2^20" : extent == 1024 ? "terrain1024" : "terrain4096";
            if (bench_terrain(&s, extent, is_deep ? (1u << 19) + 12344 : 0, &err)) {
                fprintf(stderr, "render_bench: generate: %s\n", err.msg);
                failed = 1;
                continue;
            }
        }
        double t_load = vx_time_now() - t0;
        vx_render_scene* rs;
        /* --grid: the grids' budget asked for (render.h grid_budget; the default on every device now) */
        vx_render_scene_desc sdesc = {.grid_budget = force_grid ? VX_RENDER_GRID_BUDGET : 0};
        if (vx_render_scene_create_ex(gpu, &s, &sdesc, &rs, &err)) {
            fprintf(stderr, "render_bench: %s: %s\n", name, err.msg);
            vx_svo_scene_free(&s);
            failed = 1;
            continue;
        }
        vx__render_scene_force_precise(rs, variant);
        uint64_t vx_bytes = 0;
        for (uint32_t i = 0; i < s.model_count; i++)
            vx_bytes += (uint64_t)s.models[i].node_count * 4 + (s.models[i].attrs ? (uint64_t)s.models[i].attr_count * 4 : 0);
        vx_render_layout_info rli;
        vx_render_scene_layout(rs, &rli);
        vx_bytes += rli.grid_bytes; /* the grid walk's grids (render/grid.h) */
        uint32_t uni = vx__render_scene_grid_union(rs, -1); /* (the library's default) */
        if (rli.grid_models)
            printf("grid: %s: %u of %u models%s%.0u%s, %.2f MiB, built in %.3f s%s%.0u%s\n", name, rli.grid_models,
                   s.model_count, uni ? " and the union grid of " : "", uni, uni ? " instances" : "",
                   rli.grid_bytes / 1048576.0, rli.grid_seconds, rli.grid_cubes ? " (" : "", rli.grid_cubes,
                   rli.grid_cubes ? " over their cells' cube)" : "");
        bool dense = !is_deep && vx__dense_prepare(rs, &s, UINT64_C(1) << 30, &err) == VX_OK;
        bench_esvo es = {0}, *esp = NULL;
        bench_tree64 t6 = {0}, *t6p = NULL;
        bench_mip mip = {0}, *mipp = NULL;
        bench_brick brk = {0}, *brkp = NULL;
        if (use_esvo && !is_deep && !vx_render_scene_precise(rs)) {
            if (bench_esvo_create(gpu, &s, &es, &err))
                fprintf(stderr, "render_bench: %s: no ESVO baseline: %s\n", name, err.msg);
            else
                esp = &es, es.spv = esvo_spv, es.spv_bytes = esvo_bytes;
            if (esp && use_tree64) {
                if (bench_tree64_create(gpu, &s, &t6, &err))
                    fprintf(stderr, "render_bench: %s: no 64-tree: %s\n", name, err.msg);
                else
                    t6p = &t6;
            }
            if (esp && use_mip) {
                if (bench_mip_create(gpu, &s, 10, &mip, &err))
                    fprintf(stderr, "render_bench: %s: no occupancy pyramid: %s\n", name, err.msg);
                else
                    mipp = &mip;
            }
            if (esp && use_brick) {
                if (bench_brick_create(gpu, &s, 12, brick_root, &brk, &err))
                    fprintf(stderr, "render_bench: %s: no brick grid: %s\n", name, err.msg);
                else
                    brkp = &brk;
            }
        }
        vx_render_camera cams[4] = {{0}};
        if (is_deep) {
            double c0 = (1u << 19) + 12344 + 512.0;
            cams[0].set = true;
            cams[0].target[0] = cams[0].target[1] = c0, cams[0].target[2] = c0 - 200;
            cams[0].eye[0] = c0 - 1100, cams[0].eye[1] = c0 - 1500, cams[0].eye[2] = c0 + 1300;
        }
        bool have_views = !is_deep && make_views(rs, &s, cams);
        if (have_views) {
            /* sky (only where --views names it): the oblique view's eye looking away from the
             * scene, every ray misses: the per-ray fixed cost of each kernel */
            cams[3] = cams[1];
            for (int k = 0; k < 3; k++) cams[3].target[k] = 2 * cams[1].eye[k] - cams[1].target[k];
        }
        static const char* vnames[4] = {"overview", "oblique", "closeup", "sky"};
        bool first_view = true;
        for (int v = 0; v < 4; v++) {
            if (!strstr(views, vnames[v]) || (v > 0 && !have_views)) continue;
            const char* p = sizes;
            while (*p) {
                unsigned w, h;
                if (sscanf(p, "%ux%u", &w, &h) != 2) break;
                view_result r = {0};
                row_ref ref = {0};
                uint32_t smap_side = 0; /* the scene's list now: 0 the default */
                for (int si = 0; si < nsmap; si++)
                for (int ki = 0; ki < nkern; ki++)
                for (int bi = 0; bi < nbeam; bi++) {
                    uint32_t beam = beam_list[bi];
                    vx_render_desc d = {.width = w, .height = h, .camera = cams[v], .beam = beam,
                                        .no_shadow_map = smap_list[si] == 1};
                    if (smap_list[si] != 1 && smap_list[si] != smap_side) {
                        if (vx__render_scene_smap_side(rs, &s, smap_list[si], &err)) {
                            fprintf(stderr, "render_bench: %s: shadow map: %s\n", name, err.msg);
                            failed = 1;
                            break;
                        }
                        smap_side = smap_list[si];
                    }
                    vx__render_scene_trace_kernel(rs, kspv[ki], kbytes[ki], bspv[ki], bbytes[ki], (uint32_t)ki);
                    vx__render_scene_trace_variant(rs, kcull[ki]);
                    vx__render_scene_trace_path(rs, kpath[ki]);
                    vx__render_scene_grid(rs, kgrid[ki]);
                    vx__render_scene_grid_union(rs, kunion[ki]);
                    /* the scene's first view warms for at least 1 s: after a long host-side
                     * build (ESVO of terrain4096, 12 s) its first timing measured 0.1-0.4 of
                     * the rest with 0.2-0.3 s (clocks down) */
                    double wu = first_view && ki == 0 && bi == 0 ? fmax(warmup, 1.0) : warmup;
                    if (run_view(rs, esp, t6p, t6_variants, &s, d, dense, bi == 0 && ki == 0 && si == 0, runs, wu, &ref, &r,
                                 &err)) {
                        fprintf(stderr, "render_bench: %s %s: %s\n", name, vnames[v], err.msg);
                        failed = 1;
                        break;
                    }
                    double px = (double)w * h;
                    char sz[32], ges[16], stes[16], gstes[16], ratio[16], agree[16], dn[16], mes[16], enes[16];
                    snprintf(sz, sizeof sz, "%ux%u", w, h);
                    snprintf(enes, sizeof enes, esp ? "%.0f%%" : "-", 100 * r.enter_es);
                    snprintf(stes, sizeof stes, esp ? "%.1f" : "-", r.steps_es);
                    snprintf(ges, sizeof ges, esp ? "%.2f" : "-", px / r.sec_es * U);
                    snprintf(gstes, sizeof gstes, esp ? "%.0f" : "-", px * r.steps_es / r.sec_es * U);
                    snprintf(ratio, sizeof ratio, esp ? "%.2f" : "-", r.sec_es / r.sec_vx);
                    snprintf(agree, sizeof agree, esp ? "%.3f%%" : "-", 100 * r.agree);
                    snprintf(dn, sizeof dn, dense ? "%.2f" : "-", px / r.sec_dense * U);
                    snprintf(mes, sizeof mes, esp ? "%.2f" : "-", bench_esvo_bytes(&es) / 1048576.0);
                    char t64[192] = "";
                    for (uint32_t tv = 0; t6p && tv < t6_variants; tv++) {
                        size_t at = strlen(t64);
                        snprintf(t64 + at, sizeof t64 - at, " %8.1f %7.2f %6.0f %6.2f %6.3f%%", r.steps_t[tv],
                                 px / r.sec_t[tv] * U, px * r.steps_t[tv] / r.sec_t[tv] * U,
                                 r.sec_es / r.sec_t[tv], 100 * r.agree_t[tv]);
                    }
                    if (t6p) {
                        size_t at = strlen(t64);
                        snprintf(t64 + at, sizeof t64 - at, " %9.2f", bench_tree64_bytes(&t6) / 1048576.0);
                    }
                    char cp[80] = "";
                    if (cpu)
                        snprintf(cp, sizeof cp, " %10.2f %10.2f %6.2f %10.2f", px / r.cpu_vx * U, esp ? px / r.cpu_es * U : 0.0,
                                 esp ? r.cpu_es / r.cpu_vx : 0.0, px / r.cpu_sh * U);
                    char kl[320] = "";
                    if (ki) snprintf(kl, sizeof kl, "  [kernel %s]", kname[ki]);
                    vx_render_shadow_map_info smi;
                    vx_render_scene_shadow_map_info(rs, &smi);
                    {
                        size_t at = strlen(kl);
                        snprintf(kl + at, sizeof kl - at, "  [shadow rays %.0f%%, %.1f steps]", 100 * r.sh_share, r.sh_steps);
                        uint64_t tp;
                        if (vx__render_scene_traced(rs, &tp)) {
                            at = strlen(kl);
                            snprintf(kl + at, sizeof kl - at, "  [traced %.1f%% of the pixels]", 100.0 * (double)tp / px);
                        }
                    }
                    {
                        size_t at = strlen(kl);
                        char wv[16], we[16];
                        snprintf(wv, sizeof wv, r.warp_vx >= 0 ? "%.1f%%" : "?", 100 * r.warp_vx);
                        snprintf(we, sizeof we, r.warp_es >= 0 ? "%.1f%%" : "-", 100 * r.warp_es);
                        snprintf(kl + at, sizeof kl - at, "  [warps: lane use VX %s / ES %s]", wv, we);
                    }
                    if (nsmap > 1 || smap_list[0]) {
                        size_t at = strlen(kl);
                        snprintf(kl + at, sizeof kl - at, "  [shadow map %s]",
                                 smi.used ? "on" : smap_list[si] == 1 ? "off" : "none");
                    }
                    if (smi.used)
                        printf("shadow map: %s %s: %u texels a side, %u nodes listed in %.3f s; build %.3f ms GPU, "
                               "%.3f ms wall (per light direction)\n",
                               name, vnames[v], smi.side, smi.nodes, smi.list_seconds, smi.build_gpu_seconds * 1e3,
                               smi.build_seconds * 1e3);
                    if (r.beam_diff >= 0) {
                        size_t at = strlen(kl);
                        snprintf(kl + at, sizeof kl - at, "  [%ld px differ from the first row, %ld in colour]", r.beam_diff,
                                 r.color_diff);
                    }
                    printf("%-20.20s %-8s %-9s %4u %4.0f%% %4.0f%% %5s %6.1f %6s %7.2f %7s %7.0f %7s %6s %7s %7.2f %7s %9.2f %9s%s%s%s%s\n",
                           name, vnames[v], sz, beam, 100 * r.hit, 100 * r.enter_vx, enes, r.steps_vx, stes,
                           px / r.sec_vx * U, ges, px * r.steps_vx / r.sec_vx * U, gstes, ratio, agree,
                           px / r.sec_shadow * U, dn, vx_bytes / 1048576.0, mes, t64, cp,
                           vx_render_scene_precise(rs) ? "  (float64)" : "", kl);
                    fflush(stdout);
                    /* the prototypes' rows (--mip, --brick): each variant after the view's row */
                    const struct {
                        void* m;
                        proto_frame_fn frame;
                        uint32_t variants;
                        const char *what, *row, *tag, *param;
                        double mib;
                    } protos[2] = {
                        {mipp, mip_frame, BENCH_MIP_VARIANTS, "occupancy pyramid", "mip-variant  ", "MIP", "probe",
                         mipp ? bench_mip_bytes(mipp) / 1048576.0 : 0},
                        {brkp, brick_frame, BENCH_BRICK_VARIANTS, "brick grid", "brick-variant  ", "BRK", "fcoord",
                         brkp ? bench_brick_bytes(brkp) / 1048576.0 : 0}};
                    for (int pi = 0; pi < 2 && !failed; pi++)
                        for (uint32_t pv = 0; protos[pi].m && ki == 0 && bi == 0 && si == 0 && pv < protos[pi].variants;
                             pv++) {
                            double ev[4];
                            if (proto_variant(protos[pi].frame, protos[pi].m, pv, &s, d, runs, warmup, ref.hits, ev, &err)) {
                                fprintf(stderr, "render_bench: %s %s: %s %u: %s\n", name, vnames[v], protos[pi].what, pv,
                                        err.msg);
                                failed = 1;
                                break;
                            }
                            printf("%s%-20.20s %-8s %-9s %6.1f %7.2f %7.0f %s/ES %.3f %s/VX %.3f depth= %.3f%%  "
                                   "[warps: lane use %.1f%%]  [%s %u, %.2f MiB]\n",
                                   protos[pi].row, name, vnames[v], sz, ev[0], px / ev[1] * U, px * ev[0] / ev[1] * U,
                                   protos[pi].tag, r.sec_es / ev[1], protos[pi].tag, r.sec_vx / ev[1], 100 * ev[2],
                                   100 * ev[3], protos[pi].param, pv, protos[pi].mib);
                            fflush(stdout);
                        }
                    for (int ei = 0; esp && ki == 0 && bi == 0 && si == 0 && ei < nev; ei++) {
                        double ev[4];
                        if (esvo_variant(esp, ev_spv[ei], ev_bytes[ei], &s, d, runs, warmup, ref.hits, ev, &err)) {
                            fprintf(stderr, "render_bench: %s %s: ESVO variant %s: %s\n", name, vnames[v], ev_name[ei], err.msg);
                            failed = 1;
                            break;
                        }
                        printf("esvo-variant %-20.20s %-8s %-9s %6.1f %7.2f %7.0f ES/base %.3f depth= %.3f%%  [warps: lane use %.1f%%]  "
                               "[%s]\n",
                               name, vnames[v], sz, ev[0], px / ev[1] * U, px * ev[0] / ev[1] * U, r.sec_es / ev[1],
                               100 * ev[2], 100 * ev[3], ev_name[ei]);
                        fflush(stdout);
                    }
                }
                free(ref.hits), free(ref.color);
                if (smap_side && vx__render_scene_smap_side(rs, &s, 0, &err)) failed = 1;
                first_view = false;
                vx__render_scene_trace_kernel(rs, NULL, 0, NULL, 0, 0);
                p = strchr(p, ',');
                if (!p) break;
                p++;
            }
        }
        if (stats && !vx_render_scene_precise(rs) && pass_kernels(rs, &s, cams[0], &err)) {
            fprintf(stderr, "render_bench: %s: passes: %s\n", name, err.msg);
            failed = 1;
        }
        uint64_t voxels = 0;
        for (uint32_t i = 0; i < s.instance_count; i++) voxels += s.models[s.instances[i].model].voxel_count;
        fprintf(stderr, "  (%s: %llu voxels, load %.2f s, ESVO build %.2f s, far pointer test %s)\n", name,
                (unsigned long long)voxels, t_load, esp ? es.build_seconds : 0.0, vx__render_scene_far(rs) ? "on" : "off");
        /* the MiB columns' bytes (small scenes round to 0.0x MiB): voxkit's nodes and records, its grids, ESVO's slots */
        fprintf(stderr, "  (%s: GPU bytes voxkit %llu (grids %llu) / ESVO %llu)\n", name, (unsigned long long)vx_bytes,
                (unsigned long long)rli.grid_bytes, esp ? (unsigned long long)bench_esvo_bytes(&es) : 0ull);
        if (t6p)
            fprintf(stderr, "  (%s: 64-tree %u levels, %llu cells, %llu nodes, build %.2f s)\n", name, t6.levels,
                    (unsigned long long)t6.cells, (unsigned long long)t6.node_count, t6.build_seconds);
        if (mipp)
            fprintf(stderr, "  (%s: occupancy pyramid 2^%u cells wide, %llu cells, build %.2f s)\n", name, mip.depth,
                    (unsigned long long)mip.cells, mip.build_seconds);
        if (brkp)
            fprintf(stderr, "  (%s: brick grid 2^%u cells wide, root level %u, %llu cells, %llu bricks, build %.2f s)\n", name, brk.depth, brk.top,
                    (unsigned long long)brk.cells, (unsigned long long)brk.bricks, brk.build_seconds);
        bench_brick_destroy(&brk);
        bench_mip_destroy(&mip);
        bench_tree64_destroy(&t6);
        bench_esvo_destroy(&es);
        vx_render_scene_destroy(rs);
        vx_svo_scene_free(&s);
    }
    vx_gpu_destroy(gpu);
    for (int ki = 1; ki < nkern; ki++) free(kspv[ki]), free(bspv[ki]);
    for (int ei = 0; ei < nev; ei++) free(ev_spv[ei]);
    free(esvo_spv);
    return failed;
}
