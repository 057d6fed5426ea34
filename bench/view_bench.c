/* bench/view_bench.c - svo_view's edit path: one edit (move an instance by a
 * cell) plus the scene update after it, for N instances of a small model:
 * the render scene made again (BVH build, instance and model upload: what
 * the viewer did before), and the instance update it does now (instance
 * tables and BVH, vx_render_scene_set_frame); and a frame of that scene for
 * comparison.
 * Usage: view_bench [INSTANCES (default 10000)] [REPEAT (default 9)] [FRAMES (default 0)]:
 *        the instance edit (in place since frames in flight: the CPU BVH
 *        build and no wait) and, with FRAMES, FRAMES frames in flight at
 *        1920x1080 without and with an instance moved before every frame,
 *        and with the camera orbiting, the instance rows computed on the GPU
 *        (shaders/inst_rows.comp) and from the host (the table rows written)
 *        view_bench --animate IN.svo OUT.svo FRAMES: OUT is IN as an animation
 *        of FRAMES frames, every instance one cell further along x each frame
 *        (models shared: playback in svo_view --bench switches frames with no
 *        upload; bench/view_bench.sh compares it with the still scene)
 *        view_bench --stroke IN.svo|terrain256 [STROKES (default 30)] [RADIUS (default 4)] [GRID (on|off)]:
 *        svo_view's brush strokes (sphere, add/remove/paint in turn, centred on
 *        the surface of instance 0's model at random columns): the editor's
 *        apply (vvx_apply) and the GPU update (vx_render_scene_update_model),
 *        undo (header restored + update), against the path before (the model
 *        decoded and built again, the render scene made again) on the same
 *        strokes. terrain256: the tracer benchmarks' terrain at 256^3. GRID:
 *        the render scenes' grids asked for or none (default: built, on a CPU
 *        device too); with grids a stroke's update makes its
 *        model's grid again where it is small (render_scene.c regrid).
 *        view_bench --frame IN.svo [W H (default 1920 1080)] [FRAMES (default 30)] [PASSES]:
 *        svo_view's colour frame without a window, on each path, medians:
 *        the passes' GPU time (svo_render's trace time for the same passes,
 *        default gbuffer,direct, the file's lights); the host path (the frame read
 *        back, converted to 8 bits on the CPU as svo_view does); the GPU path
 *        (the image left on the GPU, vx_display's conversion with an overlay
 *        the size of svo_view's panel columns laid over it, a submission
 *        waited for: what svo_view records before its swapchain copy). The
 *        panels' CPU drawing is svo_view's, not here (svo_view --bench -v
 *        prints it).
 *        view_bench --loop IN.svo [W H (default 1920 1080)] [FRAMES (default 300)] [PASSES] [EX,EY,EZ,TX,TY,TZ]:
 *        frames in flight as svo_view's GPU path records them (render/display.h:
 *        passes, conversion with the overlay, copy into an image, one submission
 *        per frame, VX_DISPLAY_FRAMES in flight), into off-screen images that
 *        stand in for the swapchain's (no display here): the interval between
 *        frames on the CPU (what a user sees) and on the GPU (start timestamps),
 *        each frame's GPU time, against the passes' GPU time of frames submitted
 *        and waited for (svo_render's trace time); with no overlay, the overlay
 *        kept, and redrawn each frame; the last frame's bytes against the waited
 *        path's. Says whether the instance offers VK_EXT_headless_surface.
 *        view_bench --submit IN.svo [W H] [FRAMES] [PASSES] [EX,EY,EZ,TX,TY,TZ]:
 *        svo_view's frame (fused, overlay kept, no timestamps) with the queue
 *        set up in other ways (vx_display_set_queue: frames in flight, frames
 *        per vkQueueSubmit, one VkSubmitInfo): where the time between frames
 *        goes beyond the passes (a submission's fixed cost, or the CPU); also
 *        the waits that found the GPU behind, and an empty frame's floor; and
 *        what a command buffer boundary costs (4 frames' passes in 4 command
 *        buffers or in one, a vkQueueSubmit each 4).
 *        Needs only libvulkan and libc (runs on the GPU machine). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <vulkan/vulkan.h> /* --loop: the headless surface query, image layouts */

#include "render/display.h"
#include "render/gpu.h" /* --loop: timestamps between a frame's stages */
#include "render/pipeline.h"
#include "render/render.h"
#include "render/testing.h" /* vx__render_scene_rows_on_gpu */
#include "bench/bench_terrain.h"
#include "tools/svo_view/batch.h"
#include "tools/svo_view/editor.h"
#include "tools/svo_view/voxels.h"

#if VX_BENCH_GPU_PANELS
#include "tools/svo_view/ui.h"

/* Panels as svo_view lays them out (columns of 3/8 of the width left and
 * right) filled with text lines and a bar graph, drawn by Dear ImGui's
 * Vulkan backend over the frame (ui_gpu_record); the draw lists made once
 * and kept, as svo_view keeps them between redraws. NULL: no panels. */
static struct ui* panels_make(vx_gpu* g, uint32_t w, uint32_t h) {
    ui* u = ui_create();
    char why[256];
    ui_gpu_desc gd = {.instance = g->instance, .phys = g->phys, .device = g->device, .queue = g->queue,
                      .queue_family = g->queue_family, .final_layout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                      .frames = VX_DISPLAY_FRAMES};
    if (!u || !ui_gpu_init(u, &gd, why, sizeof why)) {
        fprintf(stderr, "view_bench: %s\n", u ? why : "out of memory");
        ui_destroy(u);
        return NULL;
    }
    float cw = (float)(w * 3 / 8);
    /* VX_BENCH_PANEL_SMALL: one 240 x 200 window instead (how the panels' cost grows with their pixels) */
    bool small = getenv("VX_BENCH_PANEL_SMALL") != NULL;
    static const float bars[64] = {1, 2, 2, 1, 3, 1, 2, 2, 1, 2, 2, 1, 3, 1, 2, 2, 1, 2, 2, 1, 3, 1,
                                   2, 2, 1, 2, 2, 1, 3, 1, 2, 2, 1, 2, 2, 1, 3, 1, 2, 2, 1, 2, 2};
    static const uint32_t colours[2] = {0x3080F0u, 0x40C040u};
    for (int f = 0; f < 2; f++) { /* the second frame: windows placed and sized as on every later one */
        ui_frame_begin(u, w, h, 1.0 / 60);
        for (int c = 0; c < (small ? 1 : 2); c++) {
            if (ui_window_begin(c ? "Properties" : "Outliner", c ? (float)w - cw : 0, 0, small ? 240 : cw,
                                small ? 200 : (float)h)) {
                for (int i = 0; i < 40; i++) ui_text("instance %d  model %d  layer %d  (%d, %d, %d)", i, i % 7, i % 3, i, -i, 2 * i);
                ui_stacked_bars(bars, 32, 2, 2, colours, 2, 5, 60);
                ui_progress(0.4f, "bake");
            }
            ui_window_end();
        }
        ui_frame_end(u, NULL);
    }
    return u;
}

static bool panels_record(struct ui* u, void* cmd, uint32_t slot, uint64_t view, uint32_t w, uint32_t h) {
    char why[256];
    if (ui_gpu_record(u, cmd, slot, view, w, h, why, sizeof why)) return true;
    fprintf(stderr, "view_bench: %s\n", why);
    return false;
}
#else
struct ui;
static struct ui* panels_make(vx_gpu* g, uint32_t w, uint32_t h) {
    (void)g, (void)w, (void)h;
    return NULL;
}
static bool panels_record(struct ui* u, void* cmd, uint32_t slot, uint64_t view, uint32_t w, uint32_t h) {
    (void)u, (void)cmd, (void)slot, (void)view, (void)w, (void)h;
    return false;
}
static void ui_destroy(struct ui* u) { (void)u; }
static void ui_gpu_shutdown(struct ui* u) { (void)u; }
#endif

static int cmp(const void* a, const void* b) {
    double x = *(const double*)a, y = *(const double*)b;
    return (x > y) - (x < y);
}

static int animate(const char* in, const char* out, uint32_t frames) {
    vx_svo_scene s;
    vx_error err = {0};
    if (frames < 2 || vx_svo_read_file(NULL, in, &s, &err)) return fprintf(stderr, "%s\n", frames < 2 ? "FRAMES >= 2" : err.msg), 1;
    if (vx_svo_scene_alloc_frames(&s, frames, &err)) return fprintf(stderr, "%s\n", err.msg), 1;
    for (uint32_t f = 1; f < frames; f++)
        for (uint32_t i = 0; i < s.instance_count; i++) s.frame_instances[(size_t)(f - 1) * s.instance_count + i].xform[3] += f;
    s.frame_rate = 24;
    vx_result r = vx_svo_write_file(NULL, &s, out, &err);
    if (r) fprintf(stderr, "%s\n", err.msg);
    vx_svo_scene_free(&s);
    return r ? 1 : 0;
}

/* ---- --stroke ---------------------------------------------------------------------------- */

typedef struct heights {
    uint32_t nx, ny;
    int32_t* h; /* highest set z per column, -1: none */
} heights;

static bool height_cb(void* user, uint32_t x, uint32_t y, uint32_t z, uint32_t attr) {
    (void)attr;
    heights* hm = user;
    int32_t* h = &hm->h[(size_t)y * hm->nx + x];
    if ((int32_t)z > *h) *h = (int32_t)z;
    return true;
}

static double median(double* v, uint32_t n) {
    qsort(v, n, sizeof *v, cmp);
    return n ? v[n / 2] : 0;
}

static int stroke_bench(const char* in, uint32_t strokes, uint32_t radius, const char* grid) {
    vx_svo_scene s, s2;
    vx_error err = {0};
    bool terrain = !strcmp(in, "terrain256");
    if (terrain ? bench_terrain(&s, 256, 0, &err) || bench_terrain(&s2, 256, 0, &err)
                : vx_svo_read_file(NULL, in, &s, &err) || vx_svo_read_file(NULL, in, &s2, &err))
        return fprintf(stderr, "%s: %s\n", in, err.msg[0] ? err.msg : "cannot make the scene"), 1;
    if (!s.instance_count) return fprintf(stderr, "%s: no instances\n", in), 1;
    uint32_t model = s.instances[0].model;
    const vx_svo_model* m = &s.models[model];
    heights hm = {m->size[0], m->size[1], malloc((size_t)m->size[0] * m->size[1] * sizeof(int32_t))};
    if (!hm.h) return 1;
    for (size_t i = 0; i < (size_t)hm.nx * hm.ny; i++) hm.h[i] = -1;
    if (vx_svo_decode_model(m, height_cb, &hm, &err)) return fprintf(stderr, "%s\n", err.msg), 1;
    /* the stroke centres: random columns that hold cells, on their top cell */
    int64_t(*c)[3] = calloc(strokes, sizeof *c);
    uint64_t rng = 0x9E3779B97F4A7C15ull;
    for (uint32_t k = 0; k < strokes;) {
        rng = rng * 6364136223846793005ull + 1442695040888963407ull;
        uint32_t x = (uint32_t)(rng >> 33) % hm.nx, y = (uint32_t)(rng >> 13) % hm.ny;
        int32_t z = hm.h[(size_t)y * hm.nx + x];
        if (z < (int32_t)radius) continue;
        c[k][0] = x, c[k][1] = y, c[k][2] = z;
        k++;
    }
    vx_gpu* gpu;
    vx_render_scene *rs = NULL, *rs2 = NULL;
    /* GRID: the render scenes' grids (the default: the budget on every device; "on": asked for;
     * "off": none), so that a stroke's update includes its grid's rebuild (render_scene.c regrid) */
    vx_render_scene_desc sd = {.grid_budget = !grid                   ? 0
                                              : !strcmp(grid, "on")  ? VX_RENDER_GRID_BUDGET
                                              : !strcmp(grid, "off") ? VX_RENDER_NO_GRID
                                                                     : UINT64_MAX};
    if (sd.grid_budget == UINT64_MAX) return fprintf(stderr, "--stroke: GRID is on or off, not %s\n", grid), 2;
    if (vx_gpu_create(NULL, &gpu, &err) || vx_render_scene_create_ex(gpu, &s, &sd, &rs, &err) ||
        vx_render_scene_create_ex(gpu, &s2, &sd, &rs2, &err))
        return fprintf(stderr, "%s\n", err.msg), 1;
    vx_render_layout_info li0;
    vx_render_scene_layout(rs, &li0);
    ved e, e2;
    ved_init(&e, &s);
    ved_init(&e2, &s2);
    e2.vox_rebuild = true;
    double *apply = calloc(strokes, sizeof(double)), *upd = calloc(strokes, sizeof(double)),
           *tot = calloc(strokes, sizeof(double)), *undo = calloc(strokes, sizeof(double));
    uint64_t cells = 0, words = 0;
    /* the first stroke makes the editor (indexes the model's blocks): timed apart */
    double t_first = 0;
    for (uint32_t k = 0; k < strokes; k++) {
        vvx_brush b = {.shape = VVX_SPHERE, .radius = radius, .palette = (uint8_t)(1 + k % 7), .rgba = 0xFF000000u | k * 0x00102030u};
        vvx_op op = (vvx_op)(k % 3);
        uint64_t n = 0;
        double t0 = vx_time_now();
        if (vvx_apply(&e, model, op, &b, c[k], &n, &err)) return fprintf(stderr, "%s\n", err.msg), 1;
        double t1 = vx_time_now();
        if (n && vx_render_scene_update_model(rs, &s, model, e.last.words_from, e.last.records_from, &err))
            return fprintf(stderr, "%s\n", err.msg), 1;
        double t2 = vx_time_now();
        if (k == 0) t_first = (t1 - t0) * 1e3;
        apply[k] = (t1 - t0) * 1e3, upd[k] = (t2 - t1) * 1e3, tot[k] = (t2 - t0) * 1e3;
        cells += n;
        words += s.models[model].node_count - e.last.words_from;
    }
    /* the edited scene's frames (its grid made again where small, else the octree walk) against a scene made
     * from the edited model (a fresh grid): 1920x1080 depth (primary rays: an edited scene has no sun map, so
     * its colour frames differ by the shadow rays), the default framing, GPU time, median of 7 */
    double fr[2][7] = {{0}};
    vx_render_scene* rs3 = NULL;
    if (vx_render_scene_create_ex(gpu, &s, &sd, &rs3, &err)) return fprintf(stderr, "%s\n", err.msg), 1;
    for (int w = 0; w < 2; w++)
        for (int k = 0; k < 8; k++) {
            vx_render_image img = {0};
            vx_render_desc d = {.width = 1920, .height = 1080, .mode = VX_RENDER_DEPTH};
            if (vx_render_frame(w ? rs3 : rs, &d, &img, &err)) return fprintf(stderr, "%s\n", err.msg), 1;
            if (k) fr[w][k - 1] = img.gpu_seconds * 1e3; /* the first: pipelines made */
            vx_render_image_free(&img);
        }
    vx_render_scene_destroy(rs3);
    char frames[256];
    snprintf(frames, sizeof frames, "  a depth frame after the strokes (1920x1080, median of 7, GPU): %.3f ms; a scene made from the edited model: %.3f ms\n",
           median(fr[0], 7), median(fr[1], 7));
    /* undo all the strokes: headers restored, nothing uploaded */
    for (uint32_t k = 0; k < strokes; k++) {
        double t0 = vx_time_now();
        if (!ved_undo(&e, NULL)) break;
        if (vx_render_scene_update_model(rs, &s, model, UINT32_MAX, UINT32_MAX, &err)) return fprintf(stderr, "%s\n", err.msg), 1;
        undo[k] = (vx_time_now() - t0) * 1e3;
    }
    /* before: decode + build, render scene made again (a few strokes) */
    uint32_t nb = strokes < 5 ? strokes : 5;
    double *rb = calloc(nb, sizeof(double)), *rc = calloc(nb, sizeof(double));
    for (uint32_t k = 0; k < nb; k++) {
        vvx_brush b = {.shape = VVX_SPHERE, .radius = radius, .palette = (uint8_t)(1 + k % 7), .rgba = 0xFF000000u | k * 0x00102030u};
        uint64_t n = 0;
        double t0 = vx_time_now();
        if (vvx_apply(&e2, model, (vvx_op)(k % 3), &b, c[k], &n, &err)) return fprintf(stderr, "%s\n", err.msg), 1;
        double t1 = vx_time_now();
        vx_render_scene_destroy(rs2);
        if (vx_render_scene_create_ex(gpu, &s2, &sd, &rs2, &err)) return fprintf(stderr, "%s\n", err.msg), 1;
        rb[k] = (t1 - t0) * 1e3, rc[k] = (vx_time_now() - t1) * 1e3;
    }
    printf("view_bench --stroke: %s model %u (%ux%ux%u, %llu voxels, %u node words) on %s, sphere radius %u, %u strokes "
           "(%llu cells changed, %llu words appended)\n",
           in, model, m->size[0], m->size[1], m->size[2], (unsigned long long)m->voxel_count, m->node_count,
           vx_gpu_device_name(gpu), radius, strokes, (unsigned long long)cells, (unsigned long long)words);
    printf("  incremental: stroke (apply + GPU update) median %.3f ms: editor apply %.3f ms, GPU update %.3f ms; "
           "first stroke's apply %.1f ms (makes the editor); undo (header + update) %.3f ms\n",
           median(tot, strokes), median(apply, strokes), median(upd, strokes), t_first, median(undo, strokes));
    printf("  before (decode + build, scene made again), %u strokes: median %.2f ms + %.2f ms\n", nb, median(rb, nb),
           median(rc, nb));
    fputs(frames, stdout);
    vx_render_scene_stats st;
    vx_render_scene_get_stats(rs, &st);
    vx_render_layout_info li;
    vx_render_scene_layout(rs, &li);
    printf("  grids: %u models at the start (%.3f MiB, built in %.4f s), %u made again by the strokes and undos "
           "(%.3f MiB of grid buffer at the end)\n",
           li0.grid_models, li0.grid_bytes / 1048576.0, li0.grid_seconds, st.grids_rebuilt, li.grid_bytes / 1048576.0);
    free(apply), free(upd), free(tot), free(undo), free(rb), free(rc), free(c), free(hm.h);
    ved_free(&e);
    ved_free(&e2);
    vx_render_scene_destroy(rs);
    vx_render_scene_destroy(rs2);
    vx_gpu_destroy(gpu);
    vx_svo_scene_free(&s);
    vx_svo_scene_free(&s2);
    return 0;
}

/* ---- --frame ---------------------------------------------------------------------------- */

static uint8_t to8(float v) {
    v = v < 0 ? 0 : (v > 1 ? 1 : v);
    return (uint8_t)lrintf(v * 255.0f);
}

/* The set-up both frame benches share: device, scene, frame renderer,
 * display, the pass list and a colour frame of w x h with the scene's lights
 * and sky. Prints the error and returns false on failure. */
static bool open_view(const vx_svo_scene* s, uint32_t w, uint32_t h, const char* passes, vx_gpu** g,
                      vx_render_scene** rs, vx_frame_renderer** fr, vx_display** disp, vx_pass_list* pl,
                      vx_frame_desc* fd) {
    vx_error err = {0};
    *rs = NULL, *fr = NULL, *disp = NULL;
    if (vx_gpu_create(NULL, g, &err) || vx_render_scene_create(*g, s, rs, &err) ||
        vx_frame_renderer_create(*rs, s, fr, &err) || vx_display_create(*g, disp, &err) ||
        vx_pass_list_parse(passes, pl, &err))
        return fprintf(stderr, "%s\n", err.msg), false;
    *fd = vx_frame_desc_defaults();
    fd->base.width = w, fd->base.height = h, fd->base.mode = VX_RENDER_COLOR;
    fd->passes = pl;
    fd->lights = s->lights, fd->light_count = s->light_count;
    fd->sky_dir = &s->sky;
    return true;
}

static int frame_bench(const char* in, uint32_t w, uint32_t h, uint32_t n, const char* passes) {
    vx_svo_scene s;
    vx_error err = {0};
    if (!w || !h || !n || n > 10000) return 2;
    if (vx_svo_read_file(NULL, in, &s, &err)) return fprintf(stderr, "%s: %s\n", in, err.msg), 1;
    vx_gpu* gpu;
    vx_render_scene* rs;
    vx_frame_renderer* fr;
    vx_display* disp;
    vx_pass_list pl;
    vx_frame_desc fd;
    if (!open_view(&s, w, h, passes, &gpu, &rs, &fr, &disp, &pl, &fd)) return 1;
    double *gpu_ms = calloc(n, sizeof(double)), *host = calloc(n, sizeof(double)), *gp = calloc(n, sizeof(double)),
           *gp_bare = calloc(n, sizeof(double)), *disp_ms = calloc(n, sizeof(double)), *trace_wall = calloc(n, sizeof(double)),
           *kept = calloc(n, sizeof(double));
    uint8_t* px8 = malloc((size_t)w * h * 4);
    uint8_t* back = malloc((size_t)w * h * 4);
    if (!gpu_ms || !host || !gp || !gp_bare || !disp_ms || !trace_wall || !kept || !px8 || !back) return 1;
    /* panel columns as svo_view lays them out: a third of the width, left and right, translucent */
    uint32_t lw = w * 3 / 8, rw = w * 3 / 8;
    for (uint32_t k = 0; k < n + 2; k++) { /* two warm-up frames */
        uint32_t i = k < 2 ? 0 : k - 2;
        /* host path: read back, convert */
        vx_frame_result res;
        fd.no_readback = false;
        double t0 = vx_time_now();
        if (vx_frame_render(fr, &fd, &res, &err)) return fprintf(stderr, "%s\n", err.msg), 1;
        const float* p = res.image.pixels;
        for (size_t q = 0; q < (size_t)w * h; q++) {
            px8[4 * q] = to8(p[4 * q]), px8[4 * q + 1] = to8(p[4 * q + 1]), px8[4 * q + 2] = to8(p[4 * q + 2]);
            px8[4 * q + 3] = 255;
        }
        double t1 = vx_time_now();
        vx_render_image_free(&res.image);
        /* GPU path, no overlay */
        fd.no_readback = true;
        double t2 = vx_time_now();
        if (vx_frame_render(fr, &fd, &res, &err)) return fprintf(stderr, "%s\n", err.msg), 1;
        double t3 = vx_time_now();
        vx_display_desc dd = {.fr = fr, .width = w, .height = h, .bgra = true};
        double ds = 0;
        if (vx_display_run(disp, &dd, NULL, &ds, &err)) return fprintf(stderr, "%s\n", err.msg), 1;
        double t4 = vx_time_now();
        /* GPU path with the overlay: zeroed and the panel columns filled (the drawing itself: svo_view's) */
        double t5 = vx_time_now();
        if (vx_frame_render(fr, &fd, &res, &err)) return fprintf(stderr, "%s\n", err.msg), 1;
        uint8_t* ov = vx_display_overlay(disp, w, h, &err);
        if (!ov) return fprintf(stderr, "%s\n", err.msg), 1;
        for (uint32_t y = 0; y < h; y++) {
            uint32_t* row = (uint32_t*)(ov + (size_t)y * w * 4);
            for (uint32_t x = 0; x < lw; x++) row[x] = 0xF0141414u;
            for (uint32_t x = w - rw; x < w; x++) row[x] = 0xF0141414u;
        }
        dd.overlay = true;
        if (vx_display_run(disp, &dd, k == n + 1 ? back : NULL, NULL, &err)) return fprintf(stderr, "%s\n", err.msg), 1;
        double t6 = vx_time_now();
        /* GPU path, the overlay kept from the last frame (svo_view redraws it on input or every 250 ms) */
        double t7 = vx_time_now();
        if (vx_frame_render(fr, &fd, &res, &err) || vx_display_run(disp, &dd, NULL, NULL, &err))
            return fprintf(stderr, "%s\n", err.msg), 1;
        double t8 = vx_time_now();
        if (k < 2) continue;
        kept[i] = (t8 - t7) * 1e3;
        gpu_ms[i] = res.frame_ms, host[i] = (t1 - t0) * 1e3, trace_wall[i] = (t3 - t2) * 1e3;
        gp_bare[i] = (t4 - t2) * 1e3, disp_ms[i] = ds * 1e3, gp[i] = (t6 - t5) * 1e3;
    }
    /* the GPU path's bytes between the panel columns are the host path's (B,G,R,A there) */
    size_t bad = 0;
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = lw; x < w - rw; x++) {
            const uint8_t *a = px8 + 4 * ((size_t)y * w + x), *b = back + 4 * ((size_t)y * w + x);
            bad += a[0] != b[2] || a[1] != b[1] || a[2] != b[0];
        }
    double mg = median(gpu_ms, n);
    printf("view_bench --frame %s %ux%u on %s, %u frames, passes %s, medians:\n", in, w, h, vx_gpu_device_name(gpu), n,
           passes);
    printf("  passes GPU time (svo_render's trace time for these passes) %.3f ms\n", mg);
    printf("  frame render, image left on the GPU (wall, submission + wait)  %.3f ms\n", median(trace_wall, n));
    printf("  host path: render + readback + 8-bit conversion on the CPU      %.3f ms (%.2fx the passes)\n",
           median(host, n), median(host, n) / mg);
    printf("  GPU path: render + display conversion (no overlay)              %.3f ms (%.2fx; conversion %.3f ms wall)\n",
           median(gp_bare, n), median(gp_bare, n) / mg, median(disp_ms, n));
    printf("  GPU path with the panels' overlay (zeroed + columns filled)     %.3f ms (%.2fx)\n", median(gp, n),
           median(gp, n) / mg);
    printf("  GPU path with the overlay kept from the last frame              %.3f ms (%.2fx)\n", median(kept, n),
           median(kept, n) / mg);
    printf("  GPU path bytes between the panels differing from the host path: %zu\n", bad);
    free(gpu_ms), free(host), free(gp), free(gp_bare), free(disp_ms), free(trace_wall), free(kept), free(px8), free(back);
    vx_display_destroy(disp);
    vx_frame_renderer_destroy(fr);
    vx_render_scene_destroy(rs);
    vx_gpu_destroy(gpu);
    vx_svo_scene_free(&s);
    return bad ? 1 : 0;
}

/* ---- --loop: frames in flight ------------------------------------------------------------ */

/* Whether the instance offers VK_EXT_headless_surface (a swapchain without a
 * window system), which a GPU machine without a display would need for a
 * real swapchain. */
static bool headless_offered(void) {
    uint32_t n = 0;
    if (vkEnumerateInstanceExtensionProperties(NULL, &n, NULL) != VK_SUCCESS || !n) return false;
    VkExtensionProperties* e = calloc(n, sizeof *e);
    bool found = false;
    if (e && vkEnumerateInstanceExtensionProperties(NULL, &n, e) == VK_SUCCESS)
        for (uint32_t i = 0; i < n; i++) {
            found |= !strcmp(e[i].extensionName, "VK_EXT_headless_surface");
            printf("%s%s", i ? " " : "view_bench --loop: instance extensions: ", e[i].extensionName);
        }
    printf("\n");
    free(e);
    return found;
}

/* The panel columns svo_view lays out: 3/8 of the width left and right, translucent. */
static void draw_columns(uint8_t* ov, uint32_t w, uint32_t h) {
    uint32_t lw = w * 3 / 8, rw = w * 3 / 8;
    for (uint32_t y = 0; y < h; y++) {
        uint32_t* row = (uint32_t*)(ov + (size_t)y * w * 4);
        for (uint32_t x = 0; x < lw; x++) row[x] = 0xF0141414u;
        for (uint32_t x = w - rw; x < w; x++) row[x] = 0xF0141414u;
    }
}

typedef struct loop_stats {
    double interval_med, interval_mean; /* CPU: between the returns of vx_display_frame_begin */
    double gpu_med, gpu_gap_med;        /* a frame's command buffer on the GPU; start to start */
    double passes_med;                  /* the passes' GPU time (vx_frame_record_result) */
    double cpu_record_med;              /* CPU: recording and submitting one frame */
    /* GPU: a frame's command buffer by stages (timestamps): from its start
     * to the passes' end (the scene tables' update included), the
     * conversion, the copy into the image, the rest to its end */
    double stage_med[4];
} loop_stats;

/* n frames in flight (after warm-up), each: the passes, the conversion with
 * the overlay (mode 0: none, 1: kept from before the loop, 2: redrawn every
 * frame), the copy into the slot's image, one submission; mode 3: the
 * passes alone (the floor: what the trace costs in flight); modes 4 and 5:
 * the conversion writes the image itself (no copy), without and with the
 * overlay kept; modes 6 and 7: the conversion fused into the last pass
 * (vx_display_record_frame), without and with the overlay kept; mode 8: an
 * empty frame (its command buffer holds only the timestamps: the floor of a
 * submission per frame); mode 9: mode 7 without this loop's own stage
 * timestamps (their query reset and three writes a frame), the frame
 * svo_view records. */
typedef bool (*before_fn)(void* user, uint32_t k);

/* mode 10: mode 9 without the overlay, the panels drawn on the GPU over the
 * image instead (ui_gpu_record, tools/svo_view/ui.h; `panels` its ui). */

static bool run_loop_panels(vx_gpu* g, vx_frame_renderer* fr, vx_display* disp, const uint64_t* img, vx_frame_desc* fd,
                            uint32_t w, uint32_t h, uint32_t n, int mode, before_fn before, void* user, struct ui* panels,
                            loop_stats* st) {
    vx_error err = {0};
    uint32_t warm = 20, total = n + warm;
    double *t = calloc(total + 1, sizeof(double)), *gpu = calloc(total, sizeof(double)), *gap = calloc(total, sizeof(double)),
           *pass = calloc(total, sizeof(double)), *rec = calloc(total, sizeof(double));
    double* stage[4];
    for (int i = 0; i < 4; i++) stage[i] = calloc(total, sizeof(double));
    uint32_t ng = 0, np = 0, ns = 0;
    /* three timestamps per slot: after the passes, the conversion, the copy */
    VkQueryPool qp = VK_NULL_HANDLE;
    bool stages = mode != 9 && mode != 10;
    bool gpu_panels = mode == 10 || mode == 11;
    /* mode 11: also no timestamps of the passes' and the display's own (svo_view's frame but one in 8); mode 12:
     * mode 9 (the CPU-drawn overlay kept) without them (svo_view's frame without --gpu-panels) */
    bool untimed = mode == 11 || mode == 12;
    if (mode == 12) mode = 7, stages = false;
    if (mode == 9) mode = 7;
    if (mode == 10 || mode == 11) mode = 6, stages = false;
    fd->no_timestamps = untimed;
    vx_display_set_timestamps(disp, !untimed);
    VkQueryPoolCreateInfo qi = {.sType = VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO, .queryType = VK_QUERY_TYPE_TIMESTAMP,
                                .queryCount = 3 * VX_DISPLAY_FRAMES};
    if (stages && g->has_timestamps && vkCreateQueryPool(g->device, &qi, NULL, &qp) != VK_SUCCESS) qp = VK_NULL_HANDLE;
    double per = g->props.limits.timestampPeriod * 1e-6;
    double last_start = -1;
    uint64_t last_done = 0;
    bool ok = t && gpu && gap && pass && rec;
    bool recorded[VX_DISPLAY_FRAMES] = {0};
    for (uint32_t k = 0; ok && k < total; k++) {
        uint32_t slot;
        void* cmd;
        if (vx_display_frame_begin(disp, &slot, &cmd, &err)) break;
        t[k] = vx_time_now();
        vx_display_times dt;
        vx_display_frame_times(disp, &dt);
        if (k > warm + VX_DISPLAY_FRAMES && dt.frames_done != last_done) {
            gpu[ng] = dt.gpu_ms;
            gap[ng++] = last_start >= 0 ? dt.gpu_start_ms - last_start : 0;
        }
        last_start = dt.gpu_start_ms, last_done = dt.frames_done;
        vx_frame_result res;
        if (mode != 8 && recorded[slot] && k > warm && !vx_frame_record_result(fr, slot, &res, &err) && res.frame_ms > 0)
            pass[np++] = res.frame_ms;
        uint64_t ts[3];
        if (qp && recorded[slot] && k > warm &&
            vkGetQueryPoolResults(g->device, qp, 3 * slot, 3, sizeof ts, ts, 8, VK_QUERY_RESULT_64_BIT) == VK_SUCCESS) {
            double at[5] = {dt.gpu_start_ms, ts[0] * per, ts[1] * per, ts[2] * per, dt.gpu_start_ms + dt.gpu_ms};
            for (int i = 0; i < 4; i++) stage[i][ns] = at[i + 1] - at[i];
            ns++;
        }
        if (qp) vkCmdResetQueryPool(cmd, qp, 3 * slot, 3);
        if (before && !before(user, k)) {
            vx_display_frame_cancel(disp);
            break;
        }
        if (mode == 2) {
            uint8_t* ov = vx_display_overlay(disp, w, h, &err);
            if (!ov) break;
            draw_columns(ov, w, h);
        }
        uint64_t buf = 0;
        vx_display_desc dd = {.fr = fr, .width = w, .height = h, .bgra = true,
                              .overlay = mode == 1 || mode == 2 || mode == 5 || mode == 7};
        bool to_image = mode == 4 || mode == 5, fused = mode == 6 || mode == 7;
        if (mode == 8) {
            /* nothing recorded */
        } else if (fused ? vx_display_record_frame(disp, fr, fd, &dd, img[slot], 0, w, h,
                                                   gpu_panels ? VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL
                                                              : VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                                                   &res, &err)
                         : vx_frame_record(fr, fd, cmd, slot, &res, &err)) {
            vx_display_frame_cancel(disp);
            break;
        }
        if (gpu_panels && !panels_record(panels, cmd, slot, vx_display_image_view(disp, img[slot]), w, h)) {
            vx_display_frame_cancel(disp);
            break;
        }
        if (qp) vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, qp, 3 * slot);
        if (to_image ? vx_display_record_image(disp, cmd, &dd, img[slot], 0, w, h, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, &err)
                     : mode != 3 && mode != 8 && !fused && vx_display_record(disp, cmd, &dd, &buf, &err)) {
            vx_frame_record_cancel(fr);
            vx_display_frame_cancel(disp);
            break;
        }
        if (qp) vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, qp, 3 * slot + 1);
        if (mode != 3 && mode != 8 && !to_image && !fused)
            vx_display_copy_to_image(cmd, buf, w, h, img[slot], w, h, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
        if (qp) vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, qp, 3 * slot + 2);
        if (vx_display_frame_submit(disp, 0, 0, &err)) break;
        recorded[slot] = true;
        rec[k] = (vx_time_now() - t[k]) * 1e3;
    }
    if (vx_display_wait(disp, &err) || err.msg[0]) {
        fprintf(stderr, "loop: %s\n", err.msg[0] ? err.msg : "failed");
        ok = false;
    }
    if (ok) {
        double* iv = calloc(n, sizeof(double));
        for (uint32_t k = 0; iv && k + 1 < n; k++) iv[k] = (t[warm + k + 1] - t[warm + k]) * 1e3;
        st->interval_med = iv ? median(iv, n - 1) : 0;
        st->interval_mean = (t[total - 1] - t[warm]) * 1e3 / (n - 1);
        free(iv);
        st->gpu_med = median(gpu, ng);
        st->gpu_gap_med = ng > 1 ? median(gap + 1, ng - 1) : 0;
        st->passes_med = median(pass, np);
        st->cpu_record_med = median(rec + warm, n);
        for (int i = 0; i < 4; i++) st->stage_med[i] = median(stage[i], ns);
    }
    if (qp) vkDestroyQueryPool(g->device, qp, NULL);
    fd->no_timestamps = false;
    vx_display_set_timestamps(disp, true);
    free(t), free(gpu), free(gap), free(pass), free(rec);
    for (int i = 0; i < 4; i++) free(stage[i]);
    return ok;
}

static bool run_loop(vx_gpu* g, vx_frame_renderer* fr, vx_display* disp, const uint64_t* img, vx_frame_desc* fd,
                     uint32_t w, uint32_t h, uint32_t n, int mode, before_fn before, void* user, loop_stats* st) {
    return run_loop_panels(g, fr, disp, img, fd, w, h, n, mode, before, user, NULL, st);
}

/* A camera flying round the scene (a user moving it): frame k's camera, so
 * that every frame's tables differ from the last. */
typedef struct orbit {
    vx_frame_desc* fd;
    double c[3], r;
} orbit;

static bool orbit_step(void* user, uint32_t k) {
    orbit* o = user;
    double a = 0.01 * k;
    o->fd->base.camera = (vx_render_camera){.set = true,
                                            .eye = {o->c[0] + 1.5 * o->r * cos(a), o->c[1] + 1.5 * o->r * sin(a),
                                                    o->c[2] + 0.6 * o->r},
                                            .target = {o->c[0], o->c[1], o->c[2]},
                                            .up = {0, 0, 1}};
    return true;
}

/* --camera EX,EY,EZ,TX,TY,TZ: svo_render --camera's view (its up: z, its field of view: the default) into *c; false
 * where malformed */
static bool camera_of(const char* s, vx_render_camera* c) {
    double v[6];
    if (sscanf(s, "%lf,%lf,%lf,%lf,%lf,%lf", &v[0], &v[1], &v[2], &v[3], &v[4], &v[5]) != 6) return false;
    *c = (vx_render_camera){.set = true, .eye = {v[0], v[1], v[2]}, .target = {v[3], v[4], v[5]}, .up = {0, 0, 1}};
    return true;
}

static int loop_bench(const char* in, uint32_t w, uint32_t h, uint32_t n, const char* passes, const char* camera) {
    vx_svo_scene s;
    vx_error err = {0};
    vx_render_camera cam = {0};
    if (!w || !h || n < 3 || n > 100000) return 2;
    if (camera && !camera_of(camera, &cam))
        return fprintf(stderr, "view_bench --loop: bad camera '%s' (EX,EY,EZ,TX,TY,TZ)\n", camera), 2;
    printf("view_bench --loop: the Vulkan instance %s VK_EXT_headless_surface\n",
           headless_offered() ? "offers" : "does not offer");
    if (vx_svo_read_file(NULL, in, &s, &err)) return fprintf(stderr, "%s: %s\n", in, err.msg), 1;
    vx_gpu* g;
    vx_render_scene* rs;
    vx_frame_renderer* fr;
    vx_display* disp;
    vx_pass_list pl;
    vx_frame_desc fd;
    if (!open_view(&s, w, h, passes, &g, &rs, &fr, &disp, &pl, &fd)) return 1;
    fd.no_readback = true;
    if (cam.set) fd.base.camera = cam;
    /* the swapchain's stand-in: an image per frame slot, as a swapchain has one per frame in flight */
    uint64_t img[VX_DISPLAY_FRAMES];
    for (int i = 0; i < VX_DISPLAY_FRAMES; i++)
        if (vx_display_image_create(disp, w, h, &img[i], &err)) return fprintf(stderr, "%s\n", err.msg), 1;
    /* the baseline: each frame submitted and waited for (vx_frame_render), its passes' GPU time */
    double *base = calloc(n, sizeof(double)), *base_wall = calloc(n, sizeof(double));
    uint8_t *want = malloc((size_t)w * h * 4), *got = malloc((size_t)w * h * 4);
    if (!base || !base_wall || !want || !got) return 1;
    for (uint32_t k = 0; k < n + 2; k++) {
        vx_frame_result res;
        double t0 = vx_time_now();
        if (vx_frame_render(fr, &fd, &res, &err)) return fprintf(stderr, "%s\n", err.msg), 1;
        if (k >= 2) base[k - 2] = res.frame_ms, base_wall[k - 2] = (vx_time_now() - t0) * 1e3;
    }
    double mb = median(base, n), mbw = median(base_wall, n);
    /* the panels' overlay, drawn once and kept (svo_view redraws it on input or every 250 ms) */
    uint8_t* ov = vx_display_overlay(disp, w, h, &err);
    if (!ov) return fprintf(stderr, "%s\n", err.msg), 1;
    draw_columns(ov, w, h);
    loop_stats none = {0}, kept = {0}, redrawn = {0}, bare = {0}, store = {0}, store_kept = {0}, fused = {0},
               fused_kept = {0}, empty = {0}, bare_fused = {0};
    if (!run_loop(g, fr, disp, img, &fd, w, h, n, 0, NULL, NULL, &none) ||
        !run_loop(g, fr, disp, img, &fd, w, h, n, 1, NULL, NULL, &kept))
        return 1;
    /* the last frame in flight (slot of frame n + warm - 1) against the same frame through the waited path */
    uint32_t last = (n + 20 - 1) % VX_DISPLAY_FRAMES;
    bool read = !vx_display_image_read(disp, img[last], w, h, got, &err);
    vx_frame_result res;
    vx_display_desc dd = {.fr = fr, .width = w, .height = h, .bgra = true, .overlay = true};
    if (vx_frame_render(fr, &fd, &res, &err) || vx_display_run(disp, &dd, want, NULL, &err))
        return fprintf(stderr, "%s\n", err.msg), 1;
    size_t bad = 0;
    for (size_t q = 0; read && q < (size_t)w * h * 4; q++) bad += want[q] != got[q];
    if (!run_loop(g, fr, disp, img, &fd, w, h, n, 2, NULL, NULL, &redrawn) ||
        !run_loop(g, fr, disp, img, &fd, w, h, n, 3, NULL, NULL, &bare))
        return 1;
    /* the conversion into the image itself, where the device can; the bytes checked as above */
    bool store_ok = vx_display_image_storage(disp);
    size_t store_bad = 0, fused_bad = 0;
    bool store_read = false, fused_read = false;
    if (store_ok) {
        /* the overlay drawn again (the redrawn loop left it another), then kept */
        uint8_t* ov2 = vx_display_overlay(disp, w, h, &err);
        if (!ov2) return fprintf(stderr, "%s\n", err.msg), 1;
        draw_columns(ov2, w, h);
        if (!run_loop(g, fr, disp, img, &fd, w, h, n, 4, NULL, NULL, &store) ||
            !run_loop(g, fr, disp, img, &fd, w, h, n, 5, NULL, NULL, &store_kept))
            return 1;
        store_read = !vx_display_image_read(disp, img[last], w, h, got, &err);
        for (size_t q = 0; store_read && q < (size_t)w * h * 4; q++) store_bad += want[q] != got[q];
        /* the conversion fused into the last pass; the bytes checked as above */
        memset(got, 0, (size_t)w * h * 4);
        if (!run_loop(g, fr, disp, img, &fd, w, h, n, 6, NULL, NULL, &fused) ||
            !run_loop(g, fr, disp, img, &fd, w, h, n, 7, NULL, NULL, &fused_kept))
            return 1;
        fused_read = !vx_display_image_read(disp, img[last], w, h, got, &err);
        for (size_t q = 0; fused_read && q < (size_t)w * h * 4; q++) fused_bad += want[q] != got[q];
    }
    if (!run_loop(g, fr, disp, img, &fd, w, h, n, 8, NULL, NULL, &empty) ||
        (store_ok && !run_loop(g, fr, disp, img, &fd, w, h, n, 9, NULL, NULL, &bare_fused)))
        return 1;
    /* the camera moving every frame (the tables written every frame), fused as svo_view records it, and the
     * trace time of such frames waited for */
    loop_stats flying = {0};
    double fly_trace = 0;
    if (store_ok) {
        double lo[3], hi[3];
        vx_svo_scene_world_bounds(&s, lo, hi);
        orbit o = {.fd = &fd};
        for (int k = 0; k < 3; k++) o.c[k] = 0.5 * (lo[k] + hi[k]), o.r = fmax(o.r, hi[k] - lo[k]);
        vx_render_camera keep = fd.base.camera;
        if (!run_loop(g, fr, disp, img, &fd, w, h, n, 9, orbit_step, &o, &flying)) return 1;
        double* ft = calloc(n, sizeof(double));
        if (!ft) return 1;
        for (uint32_t k = 0; k < n; k++) {
            vx_frame_result res;
            orbit_step(&o, k + 20);
            if (vx_frame_render(fr, &fd, &res, &err)) return fprintf(stderr, "%s\n", err.msg), 1;
            ft[k] = res.frame_ms;
        }
        fly_trace = median(ft, n);
        free(ft);
        fd.base.camera = keep;
    }
    /* the panels drawn on the GPU (Dear ImGui's Vulkan backend) over the fused frame, no overlay: svo_view's frame
     * with panels where they are drawn on the GPU; the scene's bytes outside the panel columns checked */
    loop_stats gpu_panels = {0}, gpu_panels_untimed = {0}, kept_untimed = {0};
    if (store_ok && !run_loop(g, fr, disp, img, &fd, w, h, n, 12, NULL, NULL, &kept_untimed)) return 1;
    struct ui* pu = store_ok ? panels_make(g, w, h) : NULL;
    size_t panels_bad = 0, panels_shown = 0, panels_in = 0;
    bool panels_read = false;
    uint8_t* plain = pu ? malloc((size_t)w * h * 4) : NULL; /* the waited path's frame without any overlay */
    vx_display_desc plain_dd = {.fr = fr, .width = w, .height = h, .bgra = true};
    if (pu && (!plain || vx_frame_render(fr, &fd, &res, &err) || vx_display_run(disp, &plain_dd, plain, NULL, &err)))
        return fprintf(stderr, "%s\n", err.msg), 1;
    if (pu) {
        if (!run_loop_panels(g, fr, disp, img, &fd, w, h, n, 11, NULL, NULL, pu, &gpu_panels_untimed) ||
            !run_loop_panels(g, fr, disp, img, &fd, w, h, n, 10, NULL, NULL, pu, &gpu_panels))
            return 1;
        panels_read = !vx_display_image_read(disp, img[last], w, h, got, &err);
        uint32_t lw = w * 3 / 8, rw = w * 3 / 8;
        for (uint32_t y = 0; panels_read && y < h; y++)
            for (uint32_t x = 0; x < w; x++) {
                size_t q = 4 * ((size_t)y * w + x);
                if (getenv("VX_BENCH_PANEL_SMALL")) { /* one window at the top left */
                    bool in = x < 242 && y < 202;
                    if (!in) panels_bad += memcmp(plain + q, got + q, 4) != 0;
                    else if (x < 238 && y < 198) panels_in++, panels_shown += memcmp(plain + q, got + q, 3) != 0;
                } else if (x >= lw + 2 && x + 2 < w - rw) panels_bad += memcmp(plain + q, got + q, 4) != 0;
                else if (x + 2 < lw || x >= w - rw + 2) panels_in++, panels_shown += memcmp(plain + q, got + q, 3) != 0;
            }
        vx_display_wait(disp, &err);
        ui_gpu_shutdown(pu);
        ui_destroy(pu);
    }
    free(plain);
    printf("view_bench --loop %s %ux%u on %s, %u frames (after 20), passes %s, %d frames in flight, off-screen images:\n", in,
           w, h, vx_gpu_device_name(g), n, passes, VX_DISPLAY_FRAMES);
    printf("  baseline, vx_frame_render submitted + waited: passes GPU %.4f ms, wall %.4f ms\n", mb, mbw);
    const char* names[14] = {"no overlay", "overlay kept", "overlay redrawn (CPU columns) each frame",
                             "passes alone (no conversion, no copy)", "written into the image, no overlay",
                             "written into the image, overlay kept", "fused into the last pass, no overlay",
                             "fused into the last pass, overlay kept", "empty (timestamps only: the floor)",
                             "fused, overlay kept, no stage timestamps", "the same, the camera moving every frame",
                             "fused, panels drawn on the GPU (ImGui Vulkan)",
                             "the same, no timestamps (svo_view --gpu-panels)",
                             "fused, overlay kept, no timestamps (svo_view)"};
    loop_stats* all[14] = {&none,       &kept,  &redrawn,    &bare,   &store,      &store_kept,         &fused,
                           &fused_kept, &empty, &bare_fused, &flying, &gpu_panels, &gpu_panels_untimed, &kept_untimed};
    int modes = pu ? 14 : 11;
    if (!store_ok) all[4] = all[8], names[4] = names[8], modes = 5;
    for (int m = 0; m < modes; m++)
        printf("  in flight, %-41s interval median %.4f mean %.4f ms (%.3fx the passes; %.0f frames/s), GPU per frame "
               "%.4f ms, GPU start-to-start %.4f ms (%.3fx), passes %.4f ms, CPU record+submit %.4f ms\n",
               names[m], all[m]->interval_med, all[m]->interval_mean, all[m]->interval_mean / mb,
               1e3 / all[m]->interval_mean, all[m]->gpu_med, all[m]->gpu_gap_med, all[m]->gpu_gap_med / mb,
               all[m]->passes_med, all[m]->cpu_record_med);
    for (int m = 0; m < modes; m++)
        printf("  GPU stages, %-41s start to passes' end %.4f, conversion %.4f, copy %.4f, to the end %.4f ms\n", names[m],
               all[m]->stage_med[0], all[m]->stage_med[1], all[m]->stage_med[2], all[m]->stage_med[3]);
    if (store_ok)
        printf("  the moving camera's frames submitted + waited: passes GPU %.4f ms (the trace of those views)\n",
               fly_trace);
    if (pu)
        printf("  panels drawn on the GPU, last frame: %s, %zu bytes between the columns differ from the waited path, "
               "%zu of %zu pixels in the columns show the panels\n",
               panels_read ? "read" : "NOT READ", panels_bad, panels_shown, panels_in);
    printf("  last frame in flight against the waited path (vx_frame_render + vx_display_run): %s, %zu bytes differ\n",
           read ? "read" : "NOT READ", bad);
    if (store_ok) {
        printf("  the same, written into the image: %s, %zu bytes differ\n", store_read ? "read" : "NOT READ", store_bad);
        printf("  the same, fused into the last pass: %s, %zu bytes differ\n", fused_read ? "read" : "NOT READ", fused_bad);
    }
    else
        printf("  the device cannot write B,G,R,A storage images: no conversion into the image\n");
    free(base), free(base_wall), free(want), free(got);
    vx_display_destroy(disp);
    vx_frame_renderer_destroy(fr);
    vx_render_scene_destroy(rs);
    vx_gpu_destroy(g);
    vx_svo_scene_free(&s);
    return read && !bad && (!store_ok || (store_read && !store_bad && fused_read && !fused_bad)) &&
                   (!pu || (panels_read && !panels_bad && panels_shown > panels_in / 2))
               ? 0
               : 1;
}

/* ---- --submit ------------------------------------------------------------------------------ */

typedef struct submit_cfg {
    uint32_t frames, batch;
    bool one, timed, empty;
    const char* name;
    bool automatic; /* svo_view's default, --batch auto (tools/svo_view/batch.h): the batch from the timed frames */
} submit_cfg;

/* What a command buffer boundary costs the queue: the passes of 4 frames
 * (no display write) recorded into 4 command buffers or into one, one
 * vkQueueSubmit of the 4, two such submissions in flight (slots 0-3, 4-7);
 * the interval between frames (wall time over the frames). */
static int cb_boundary(vx_gpu* g, vx_frame_renderer* fr, const vx_frame_desc* fd, uint32_t n, double mb) {
    VkCommandPool pool;
    VkCommandPoolCreateInfo pci = {.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO,
                                   .flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT,
                                   .queueFamilyIndex = g->queue_family};
    if (vkCreateCommandPool(g->device, &pci, NULL, &pool)) return 1;
    VkCommandBuffer cb[8];
    VkCommandBufferAllocateInfo ai = {.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO, .commandPool = pool,
                                      .level = VK_COMMAND_BUFFER_LEVEL_PRIMARY, .commandBufferCount = 8};
    VkFence fence[2];
    VkFenceCreateInfo fci = {.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    if (vkAllocateCommandBuffers(g->device, &ai, cb) || vkCreateFence(g->device, &fci, NULL, &fence[0]) ||
        vkCreateFence(g->device, &fci, NULL, &fence[1]))
        return 1;
    int rc = 0;
    for (int round = 0; round < 2 && !rc; round++)
        for (int one = 0; one < 2 && !rc; one++) {
            uint32_t groups = (n + 20) / 4;
            double t0 = 0;
            for (uint32_t k = 0; k < groups && !rc; k++) {
                uint32_t grp = k & 1;
                if (k == 5) t0 = vx_time_now(); /* after 20 frames */
                if (k >= 2) {
                    vkWaitForFences(g->device, 1, &fence[grp], VK_TRUE, UINT64_MAX);
                    vkResetFences(g->device, 1, &fence[grp]);
                }
                VkCommandBufferBeginInfo bi = {.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO,
                                               .flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT};
                for (uint32_t j = 0; j < 4 && !rc; j++) {
                    VkCommandBuffer c = cb[4 * grp + (one ? 0 : j)];
                    if (!one || !j) vkResetCommandBuffer(c, 0), vkBeginCommandBuffer(c, &bi);
                    vx_frame_result res;
                    vx_error err = {0};
                    if (vx_frame_record(fr, fd, c, 4 * grp + j, &res, &err)) fprintf(stderr, "%s\n", err.msg), rc = 1;
                    if (!one || j == 3) vkEndCommandBuffer(c);
                }
                VkSubmitInfo si = {.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO, .commandBufferCount = one ? 1 : 4,
                                   .pCommandBuffers = &cb[4 * grp]};
                if (!rc && vkQueueSubmit(g->queue, 1, &si, fence[grp])) rc = 1;
            }
            vkQueueWaitIdle(g->queue);
            double mean = (vx_time_now() - t0) * 1e3 / (double)(4 * (groups - 5));
            printf("  passes only, 4 frames a vkQueueSubmit in %-17s interval mean %.4f ms (%.3fx the passes)\n",
                   one ? "ONE command buffer" : "4 command buffers", mean, mean / mb);
        }
    vkDestroyFence(g->device, fence[0], NULL), vkDestroyFence(g->device, fence[1], NULL);
    vkDestroyCommandPool(g->device, pool, NULL);
    fflush(stdout);
    return rc;
}

static int submit_bench(const char* in, uint32_t w, uint32_t h, uint32_t n, const char* passes, const char* camera) {
    vx_svo_scene s;
    vx_error err = {0};
    vx_render_camera cam = {0};
    if (!w || !h || n < 10 || n > 100000) return 2;
    if (camera && !camera_of(camera, &cam))
        return fprintf(stderr, "view_bench --submit: bad camera '%s' (EX,EY,EZ,TX,TY,TZ)\n", camera), 2;
    if (vx_svo_read_file(NULL, in, &s, &err)) return fprintf(stderr, "%s: %s\n", in, err.msg), 1;
    vx_gpu* g;
    vx_render_scene* rs;
    vx_frame_renderer* fr;
    vx_display* disp;
    vx_pass_list pl;
    vx_frame_desc fd;
    if (!open_view(&s, w, h, passes, &g, &rs, &fr, &disp, &pl, &fd)) return 1;
    fd.no_readback = true;
    if (cam.set) fd.base.camera = cam;
    if (!vx_display_image_storage(disp)) return fprintf(stderr, "view_bench --submit: no storage images\n"), 1;
    uint64_t img[VX_DISPLAY_SLOTS];
    for (int i = 0; i < VX_DISPLAY_SLOTS; i++)
        if (vx_display_image_create(disp, w, h, &img[i], &err)) return fprintf(stderr, "%s\n", err.msg), 1;
    /* the baseline: frames submitted and waited for, their passes' GPU time; the bytes every config must give */
    double* base = calloc(n, sizeof(double));
    uint8_t *want = malloc((size_t)w * h * 4), *got = malloc((size_t)w * h * 4);
    if (!base || !want || !got) return 1;
    for (uint32_t k = 0; k < n + 2; k++) {
        vx_frame_result res;
        if (vx_frame_render(fr, &fd, &res, &err)) return fprintf(stderr, "%s\n", err.msg), 1;
        if (k >= 2) base[k - 2] = res.frame_ms;
    }
    double mb = median(base, n);
    uint8_t* ov = vx_display_overlay(disp, w, h, &err);
    if (!ov) return fprintf(stderr, "%s\n", err.msg), 1;
    draw_columns(ov, w, h);
    vx_display_desc dd = {.fr = fr, .width = w, .height = h, .bgra = true, .overlay = true};
    {
        vx_frame_result res;
        if (vx_frame_render(fr, &fd, &res, &err) || vx_display_run(disp, &dd, want, NULL, &err))
            return fprintf(stderr, "%s\n", err.msg), 1;
    }
    static const submit_cfg cfgs[] = {
        {3, 1, false, false, false, "svo_view's frame: 3 in flight, one submission a frame", false},
        {3, 1, false, true, false, "the same with the display's 2 timestamps (GPU times)", false},
        {6, 1, false, false, false, "6 in flight, one submission a frame", false},
        {8, 1, false, true, false, "8 in flight, one submission a frame, timed", false},
        {4, 2, false, false, false, "4 in flight, 2 frames a vkQueueSubmit (2 VkSubmitInfo)", false},
        {4, 2, true, false, false, "4 in flight, 2 frames a vkQueueSubmit (1 VkSubmitInfo)", false},
        {8, 4, false, false, false, "8 in flight, 4 frames a vkQueueSubmit (4 VkSubmitInfo)", false},
        {8, 4, true, false, false, "8 in flight, 4 frames a vkQueueSubmit (1 VkSubmitInfo)", false},
        {8, 4, true, true, false, "the same, timed", false},
        {8, 8, true, false, false, "8 in flight, 8 frames a vkQueueSubmit (1 VkSubmitInfo)", false},
        {3, 1, false, false, true, "empty frame, 3 in flight, untimed", false},
        {3, 1, false, true, true, "empty frame, 3 in flight, timed", false},
        {8, 1, false, false, true, "empty frame, 8 in flight, untimed", false},
        {8, 8, true, false, true, "empty frame, 8 a submission, untimed", false},
        {3, 1, false, false, false, "svo_view's frame again", false},
        {3, 1, false, false, false, "svo_view's default: --batch auto, its frames timed", true},
    };
    int nc = (int)(sizeof cfgs / sizeof cfgs[0]);
    printf("view_bench --submit %s %ux%u on %s, %u frames (after 20), passes %s%s%s: waited frames' passes %.4f ms\n", in, w, h,
           vx_gpu_device_name(g), n, passes, camera ? ", camera " : "", camera ? camera : "", mb);
    uint32_t warm = 20, total = n + warm;
    double *t = calloc(total + 1, sizeof(double)), *wb = calloc(total, sizeof(double)), *gpu = calloc(total, sizeof(double)),
           *gap = calloc(total, sizeof(double));
    if (!t || !wb || !gpu || !gap) return 1;
    int fail = 0;
    fd.no_timestamps = true;
    for (int c = 0; c < nc; c++) {
        const submit_cfg* q = &cfgs[c];
        if (vx_display_set_queue(disp, q->frames, q->batch, q->one, &err)) return fprintf(stderr, "%s\n", err.msg), 1;
        sv_batch pol = sv_batch_make(VX_DISPLAY_SLOTS / 2, 0);
        uint64_t switched_at = 0;
        vx_display_set_timestamps(disp, q->timed);
        vx_display_times d0;
        vx_display_frame_times(disp, &d0);
        uint32_t ng = 0, last_slot = 0;
        double last_start = -1;
        uint64_t last_done = d0.frames_done, waited0 = d0.begins_waited;
        for (uint32_t k = 0; k < total; k++) {
            uint32_t slot;
            void* cmd;
            double t0 = vx_time_now();
            if (k == warm + 1) vx_display_frame_times(disp, &d0), waited0 = d0.begins_waited;
            if (q->automatic) { /* as svo_view's present_in_flight: the batch changed between frames */
                uint32_t want = sv_batch_want(&pol, false);
                if (want != pol.cur) {
                    if (vx_display_set_queue(disp, want > 1 ? 2 * want : 0, want, false, &err))
                        return fprintf(stderr, "%s\n", err.msg), 1;
                    sv_batch_set(&pol, want);
                    switched_at = k;
                }
            }
            if (vx_display_frame_begin(disp, &slot, &cmd, &err)) return fprintf(stderr, "%s\n", err.msg), 1;
            if (q->automatic) {
                vx_frame_result done;
                bool timed = !vx_frame_record_result(fr, slot, &done, NULL) && done.frame_ms > 0;
                sv_batch_frame(&pol, timed ? done.frame_ms : 0);
                fd.no_timestamps = !sv_batch_timed(&pol); /* as svo_view: its statistics' pass times */
            }
            t[k] = vx_time_now();
            wb[k] = (t[k] - t0) * 1e3;
            vx_display_times dt;
            vx_display_frame_times(disp, &dt);
            if (q->timed && k > warm + q->frames && dt.frames_done != last_done) {
                gpu[ng] = dt.gpu_ms;
                gap[ng++] = last_start >= 0 ? dt.gpu_start_ms - last_start : 0;
            }
            last_start = dt.gpu_start_ms, last_done = dt.frames_done;
            vx_frame_result res;
            if (!q->empty && vx_display_record_frame(disp, fr, &fd, &dd, img[slot], 0, w, h, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                                                     &res, &err)) {
                vx_display_frame_cancel(disp);
                return fprintf(stderr, "%s\n", err.msg), 1;
            }
            if (vx_display_frame_submit(disp, 0, 0, &err)) return fprintf(stderr, "%s\n", err.msg), 1;
            last_slot = slot;
        }
        double t_end = vx_time_now();
        vx_display_times d1;
        vx_display_frame_times(disp, &d1);
        if (vx_display_wait(disp, &err)) return fprintf(stderr, "%s\n", err.msg), 1;
        double* iv = calloc(n, sizeof(double));
        if (!iv) return 1;
        for (uint32_t k = 0; k + 1 < n; k++) iv[k] = (t[warm + k + 1] - t[warm + k]) * 1e3;
        double mean = (t_end - t[warm]) * 1e3 / n;
        double ivm = median(iv, n - 1), wbm = median(wb + warm, n);
        free(iv);
        size_t bad = 0;
        bool read = false;
        if (!q->empty) {
            read = !vx_display_image_read(disp, img[last_slot], w, h, got, &err);
            for (size_t i = 0; read && i < (size_t)w * h * 4; i++) bad += want[i] != got[i];
            fail |= !read || bad;
        }
        printf("  %-58s interval mean %.4f median %.4f ms (%.3fx the passes), begin (wait) %.4f ms, "
               "waits finding the GPU busy %.0f%%",
               q->name, mean, ivm, mean / mb, wbm, 100.0 * (double)(d1.begins_waited - waited0) / (n - 1));
        if (q->timed) printf(", GPU a frame %.4f ms, start-to-start %.4f ms", median(gpu, ng), ng > 1 ? median(gap + 1, ng - 1) : 0);
        if (!q->empty) printf(", last frame %s, %zu bytes differ", read ? "read" : "NOT READ", bad);
        if (q->automatic) printf(", batch %u from frame %llu", pol.cur, (unsigned long long)switched_at);
        printf("\n");
        fflush(stdout);
    }
    vx_display_set_queue(disp, 0, 0, false, &err);
    fd.no_timestamps = true;
    if (cb_boundary(g, fr, &fd, n, mb)) fail = 1;
    free(t), free(wb), free(gpu), free(gap), free(base), free(want), free(got);
    vx_display_destroy(disp);
    vx_frame_renderer_destroy(fr);
    vx_render_scene_destroy(rs);
    vx_gpu_destroy(g);
    vx_svo_scene_free(&s);
    return fail;
}

/* Instance edits with frames in flight: an instance moved (an undo step, the
 * move, vx_render_scene_set_frame: in place) before every frame. */
typedef struct mover {
    vx_svo_scene* s;
    vx_render_scene* rs;
    ved* e;
} mover;

static bool move_one(void* user, uint32_t k) {
    mover* m = user;
    vx_error err = {0};
    if (ved_begin(m->e, &err)) return false;
    ved_move(m->s, k % m->s->instance_count, (int32_t[3]){(k / m->s->instance_count) % 2 ? -1 : 1, 0, 0});
    if (vx_render_scene_set_frame(m->rs, m->s, 0, &err)) return fprintf(stderr, "%s\n", err.msg), false;
    return true;
}

static bool inst_loop(vx_gpu* g, vx_render_scene* rs, vx_svo_scene* s, ved* e, uint32_t n, loop_stats* still,
                      loop_stats* moving, loop_stats orbiting[2]) {
    vx_error err = {0};
    uint32_t w = 1920, h = 1080;
    vx_frame_renderer* fr = NULL;
    vx_display* disp = NULL;
    if (vx_frame_renderer_create(rs, s, &fr, &err) || vx_display_create(g, &disp, &err))
        return fprintf(stderr, "%s\n", err.msg), false;
    uint64_t img[VX_DISPLAY_FRAMES];
    for (int i = 0; i < VX_DISPLAY_FRAMES; i++)
        if (vx_display_image_create(disp, w, h, &img[i], &err)) return fprintf(stderr, "%s\n", err.msg), false;
    vx_frame_desc fd = vx_frame_desc_defaults();
    fd.base.width = w, fd.base.height = h, fd.base.mode = VX_RENDER_COLOR;
    fd.no_readback = true;
    mover m = {s, rs, e};
    bool ok = run_loop(g, fr, disp, img, &fd, w, h, n, 0, NULL, NULL, still) &&
              run_loop(g, fr, disp, img, &fd, w, h, n, 0, move_one, &m, moving);
    /* the camera orbiting (every row relative to it changes each frame): the rows computed on the GPU from the
     * instances' rows relative to the world (the default where the device has float64), then from the host */
    double lo[3], hi[3];
    vx_svo_scene_world_bounds(s, lo, hi);
    orbit o = {&fd, {0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), 0.5 * (lo[2] + hi[2])}, 0.5 * (hi[0] - lo[0])};
    for (int k = 0; k < 2 && ok; k++) {
        vx__render_scene_rows_on_gpu(rs, k == 0 ? 1 : 0);
        ok = run_loop(g, fr, disp, img, &fd, w, h, n, 0, orbit_step, &o, &orbiting[k]);
    }
    vx__render_scene_rows_on_gpu(rs, -1);
    vx_display_destroy(disp);
    vx_frame_renderer_destroy(fr);
    return ok;
}

int main(int argc, char** argv) {
    if (argc >= 3 && !strcmp(argv[1], "--loop"))
        return loop_bench(argv[2], argc > 4 ? (uint32_t)strtoul(argv[3], NULL, 10) : 1920,
                          argc > 4 ? (uint32_t)strtoul(argv[4], NULL, 10) : 1080,
                          argc > 5 ? (uint32_t)strtoul(argv[5], NULL, 10) : 300, argc > 6 ? argv[6] : VX_PASS_LIST_DEFAULT,
                          argc > 7 ? argv[7] : NULL);
    if (argc >= 3 && !strcmp(argv[1], "--submit"))
        return submit_bench(argv[2], argc > 4 ? (uint32_t)strtoul(argv[3], NULL, 10) : 1920,
                            argc > 4 ? (uint32_t)strtoul(argv[4], NULL, 10) : 1080,
                            argc > 5 ? (uint32_t)strtoul(argv[5], NULL, 10) : 2000, argc > 6 ? argv[6] : VX_PASS_LIST_DEFAULT,
                            argc > 7 ? argv[7] : NULL);
    if (argc >= 3 && !strcmp(argv[1], "--stroke"))
        return stroke_bench(argv[2], argc > 3 ? (uint32_t)strtoul(argv[3], NULL, 10) : 30,
                            argc > 4 ? (uint32_t)strtoul(argv[4], NULL, 10) : 4, argc > 5 ? argv[5] : NULL);
    if (argc >= 3 && !strcmp(argv[1], "--frame"))
        return frame_bench(argv[2], argc > 4 ? (uint32_t)strtoul(argv[3], NULL, 10) : 1920,
                           argc > 4 ? (uint32_t)strtoul(argv[4], NULL, 10) : 1080,
                           argc > 5 ? (uint32_t)strtoul(argv[5], NULL, 10) : 30, argc > 6 ? argv[6] : VX_PASS_LIST_DEFAULT);
    if (argc == 5 && !strcmp(argv[1], "--animate")) return animate(argv[2], argv[3], (uint32_t)strtoul(argv[4], NULL, 10));
    uint32_t n = argc > 1 ? (uint32_t)strtoul(argv[1], NULL, 10) : 10000, rep = argc > 2 ? (uint32_t)strtoul(argv[2], NULL, 10) : 9;
    uint32_t flight = argc > 3 ? (uint32_t)strtoul(argv[3], NULL, 10) : 0;
    if (!n || !rep || rep > 1000) return 2;
    /* one 8^3 model with a sphere of cells, on a square grid of instances */
    uint64_t keys[512];
    size_t nk = 0;
    for (uint32_t z = 0; z < 8; z++)
        for (uint32_t y = 0; y < 8; y++)
            for (uint32_t x = 0; x < 8; x++) {
                double dx = x - 3.5, dy = y - 3.5, dz = z - 3.5;
                if (dx * dx + dy * dy + dz * dz < 16) keys[nk++] = vx_svo_morton(x, y, z);
            }
    vx_svo_scene s;
    vx_svo_scene_init(&s, NULL);
    vx_error err = {0};
    s.models = calloc(1, sizeof *s.models);
    s.instances = calloc(n, sizeof *s.instances);
    if (!s.models || !s.instances) return 1;
    s.model_count = 1;
    if (vx_svo_build_model(NULL, &(vx_svo_voxels){.size = {8, 8, 8}, .count = nk, .keys = keys}, &s.models[0], NULL, &err))
        return fprintf(stderr, "%s\n", err.msg), 1;
    uint32_t side = 1;
    while (side * side < n) side++;
    for (uint32_t i = 0; i < n; i++) {
        vx_svo_instance* in = &s.instances[i];
        in->xform[0] = in->xform[5] = in->xform[10] = 1;
        in->xform[3] = 10.0 * (i % side), in->xform[7] = 10.0 * (i / side);
        in->layer = UINT32_MAX;
    }
    s.instance_count = n;
    vx_svo_scene_update_bounds(&s);
    vx_gpu* gpu;
    vx_render_scene* rs = NULL;
    if (vx_gpu_create(NULL, &gpu, &err) || vx_render_scene_create(gpu, &s, &rs, &err))
        return fprintf(stderr, "%s\n", err.msg), 1;
    ved e;
    ved_init(&e, &s);
    double* edit = calloc(rep, sizeof *edit);
    double* bvh = calloc(rep, sizeof *bvh);
    double* frame = calloc(rep, sizeof *frame);
    for (uint32_t k = 0; k < rep; k++) {
        double t0 = vx_time_now();
        if (ved_begin(&e, &err)) return 1;
        ved_move(&s, k % n, (int32_t[3]){1, 0, 0});
        vx_render_scene_destroy(rs);
        if (vx_render_scene_create(gpu, &s, &rs, &err)) return fprintf(stderr, "%s\n", err.msg), 1;
        edit[k] = (vx_time_now() - t0) * 1e3;
        bvh[k] = vx_render_scene_bvh_seconds(rs) * 1e3;
        vx_render_image img = {0};
        double t1 = vx_time_now();
        if (vx_render_frame(rs, &(vx_render_desc){.width = 640, .height = 480}, &img, &err))
            return fprintf(stderr, "%s\n", err.msg), 1;
        frame[k] = (vx_time_now() - t1) * 1e3;
        vx_render_image_free(&img);
    }
    /* svo_view's path since instance edits keep the models: the instance
     * tables and BVH only (vx_render_scene_set_frame), no node upload */
    double* inst = calloc(rep, sizeof *inst);
    if (!inst) return 1;
    double* inst_bvh = calloc(rep, sizeof *inst_bvh);
    if (!inst_bvh) return 1;
    vx_render_scene_stats st0, st1;
    vx_render_scene_get_stats(rs, &st0);
    for (uint32_t k = 0; k < rep; k++) {
        double t0 = vx_time_now();
        if (ved_begin(&e, &err)) return 1;
        ved_move(&s, k % n, (int32_t[3]){1, 0, 0});
        if (vx_render_scene_set_frame(rs, &s, 0, &err)) return fprintf(stderr, "%s\n", err.msg), 1;
        inst[k] = (vx_time_now() - t0) * 1e3;
        inst_bvh[k] = vx_render_scene_bvh_seconds(rs) * 1e3;
    }
    vx_render_scene_get_stats(rs, &st1);
    loop_stats still = {0}, moving = {0}, orbiting[2] = {{0}};
    vx_render_scene_stats so0, so1;
    vx_render_scene_get_stats(rs, &so0);
    if (flight && !inst_loop(gpu, rs, &s, &e, flight, &still, &moving, orbiting)) return 1;
    vx_render_scene_get_stats(rs, &so1);
    qsort(inst, rep, sizeof *inst, cmp);
    qsort(edit, rep, sizeof *edit, cmp);
    qsort(bvh, rep, sizeof *bvh, cmp);
    qsort(frame, rep, sizeof *frame, cmp);
    printf("view_bench: %u instances on %s: edit + scene update median %.3f ms (BVH build %.3f ms); "
           "640x480 frame (vx_render_frame wall) median %.3f ms\n",
           n, vx_gpu_device_name(gpu), edit[rep / 2], bvh[rep / 2], frame[rep / 2]);
    qsort(inst_bvh, rep, sizeof *inst_bvh, cmp);
    printf("view_bench: edit + instance update (instance tables and BVH, models stay on the GPU) median %.3f ms "
           "(BVH build or refit on the CPU %.3f ms; %u of %u in place, %u of them refit: the GPU refits with each "
           "recorded frame)\n",
           inst[rep / 2], inst_bvh[rep / 2], st1.instance_updates_in_place - st0.instance_updates_in_place, rep,
           st1.instance_refits - st0.instance_refits);
    if (flight)
        printf("view_bench: frames in flight at 1920x1080, %u frames: interval median %.4f ms (GPU start-to-start %.4f ms, "
               "passes %.4f ms); with an instance moved before every frame (undo step + move + in-place update) %.4f ms "
               "(GPU %.4f ms, passes %.4f ms, CPU record+submit incl. the edit %.4f ms)\n",
               flight, still.interval_med, still.gpu_gap_med, still.passes_med, moving.interval_med, moving.gpu_gap_med,
               moving.passes_med, moving.cpu_record_med);
    if (flight)
        printf("view_bench: the camera orbiting, frames in flight: instance rows computed on the GPU interval median %.4f ms "
               "(GPU %.4f ms, CPU record+submit %.4f ms), from the host %.4f ms (GPU %.4f ms, CPU %.4f ms); table rows "
               "written by the frames in flight %llu\n",
               orbiting[0].interval_med, orbiting[0].gpu_gap_med, orbiting[0].cpu_record_med, orbiting[1].interval_med,
               orbiting[1].gpu_gap_med, orbiting[1].cpu_record_med,
               (unsigned long long)(so1.table_rows_uploaded - so0.table_rows_uploaded));
    free(edit), free(bvh), free(frame), free(inst), free(inst_bvh);
    ved_free(&e);
    vx_render_scene_destroy(rs);
    vx_gpu_destroy(gpu);
    vx_svo_scene_free(&s);
    return 0;
}
