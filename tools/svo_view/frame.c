/* tools/svo_view/frame.c - one frame of the viewer (frame.h): the render
 * desc from the camera and the modes, the pass pipeline or the tracer, the
 * overlay (messages, probe grid, selection) and panels, screenshots and
 * grabs, and the presentation (the GPU path with frames in flight, or the
 * host's readback). */
#define _POSIX_C_SOURCE 200809L /* clock_gettime with CLOCK_THREAD_CPUTIME_ID */
#include <GLFW/glfw3.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <vulkan/vulkan.h> /* the shown image's layout before the panels' render pass */

#include "formats/image.h"
#include "render/trace.h"
#include "tools/common/tool.h"
#include "tools/svo_view/app.h"
#include "tools/svo_view/batch.h"
#include "tools/svo_view/camera.h"
#include "tools/svo_view/font.h"
#include "tools/svo_view/frame.h"
#include "tools/svo_view/panels.h"

/* This thread's CPU seconds (the panels' drawing cost, not disturbed by
 * other processes on a loaded machine); wall time where there is no such clock. */
static double thread_seconds(void) {
#ifdef CLOCK_THREAD_CPUTIME_ID
    struct timespec ts;
    if (!clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts)) return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
#endif
    return vx_time_now();
}

/* ---- frames -------------------------------------------------------------------------- */

static uint8_t to8(float v) {
    v = v < 0 ? 0 : (v > 1 ? 1 : v);
    return (uint8_t)lrintf(v * 255.0f);
}

/* Float pixels -> display bytes: colour modes exactly as svo_render's PNG;
 * normals as 0.5 n + 0.5; depth as grey, near = bright. */
static void convert(app* a, const vx_render_image* img, vf_canvas* cv) {
    size_t n = (size_t)img->width * img->height;
    float dmax = 0;
    if (img->mode == VX_RENDER_DEPTH)
        for (size_t i = 0; i < n; i++)
            if (isfinite(img->pixels[4 * i]) && img->pixels[4 * i] > dmax) dmax = img->pixels[4 * i];
    int r = cv->bgra ? 2 : 0, b = cv->bgra ? 0 : 2;
    for (size_t i = 0; i < n; i++) {
        const float* s = img->pixels + 4 * i;
        uint8_t* d = cv->pixels + 4 * i;
        float c[3] = {s[0], s[1], s[2]};
        if (img->mode == VX_RENDER_NORMAL) {
            for (int k = 0; k < 3; k++) c[k] = 0.5f * c[k] + 0.5f;
        } else if (img->mode == VX_RENDER_DEPTH) {
            float g = isfinite(s[0]) && dmax > 0 ? 1.0f - 0.8f * s[0] / dmax : 0.0f;
            c[0] = c[1] = c[2] = g;
        }
        d[r] = to8(c[0]);
        d[1] = to8(c[1]);
        d[b] = to8(c[2]);
        d[3] = 255;
    }
    (void)a;
}

/* Writes the tracer's image the way svo_render does. */
static vx_result save_image(const vx_render_image* img, const char* path, vx_error* err) {
    size_t npx = (size_t)img->width * img->height;
    bool exr = !strcmp(vx_tool_ext(path), "exr");
    vx_image_desc id = {.width = img->width, .height = img->height};
    void* buf = NULL;
    if (exr && img->mode == VX_RENDER_DEPTH) {
        float* p = malloc(npx * 4);
        for (size_t i = 0; p && i < npx; i++) p[i] = img->pixels[4 * i];
        buf = p, id.channels = 1, id.type = VX_IMAGE_F32;
    } else if (exr) {
        float* p = malloc(npx * 12);
        for (size_t i = 0; p && i < npx; i++) memcpy(p + 3 * i, img->pixels + 4 * i, 12);
        buf = p, id.channels = 3, id.type = VX_IMAGE_F32;
    } else {
        uint8_t* p = malloc(npx * 3);
        for (size_t i = 0; p && i < npx; i++) {
            const float* s = img->pixels + 4 * i;
            for (int k = 0; k < 3; k++) {
                float v = s[k];
                if (img->mode == VX_RENDER_NORMAL) v = 0.5f * v + 0.5f;
                p[3 * i + k] = to8(v);
            }
        }
        buf = p, id.channels = 3, id.type = VX_IMAGE_U8;
    }
    if (!buf) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory");
    id.pixels = buf;
    vx_result r = vx_image_write(path, &id, err);
    free(buf);
    return r;
}

/* Writes the displayed 8-bit frame (panels and overlay included) as PNG. */
static vx_result save_canvas(const vf_canvas* cv, const char* path, vx_error* err) {
    size_t npx = (size_t)cv->width * cv->height;
    uint8_t* p = malloc(npx * 3);
    if (!p) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory");
    int r = cv->bgra ? 2 : 0, b = cv->bgra ? 0 : 2;
    for (size_t i = 0; i < npx; i++) {
        p[3 * i] = cv->pixels[4 * i + r];
        p[3 * i + 1] = cv->pixels[4 * i + 1];
        p[3 * i + 2] = cv->pixels[4 * i + b];
    }
    vx_image_desc id = {.width = cv->width, .height = cv->height, .channels = 3, .type = VX_IMAGE_U8, .pixels = p};
    vx_result res = vx_image_write(path, &id, err);
    free(p);
    return res;
}

/* Projects a world point with the frame's camera (as the tracer sets it up). */
static bool project(const app* a, const double eye[3], const double f[3], uint32_t w, uint32_t h, const double p[3],
                    double* sx, double* sy) {
    double up[3] = {0, 0, 1}, r[3], u[3];
    r[0] = f[1] * up[2] - f[2] * up[1], r[1] = f[2] * up[0] - f[0] * up[2], r[2] = f[0] * up[1] - f[1] * up[0];
    double rl = sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
    if (!(rl > 0)) return false;
    for (int k = 0; k < 3; k++) r[k] /= rl;
    u[0] = r[1] * f[2] - r[2] * f[1], u[1] = r[2] * f[0] - r[0] * f[2], u[2] = r[0] * f[1] - r[1] * f[0];
    double v[3] = {p[0] - eye[0], p[1] - eye[1], p[2] - eye[2]};
    double z = v[0] * f[0] + v[1] * f[1] + v[2] * f[2];
    if (z < 1e-6) return false;
    double hh = tan(0.5 * a->o.fov * SV_PI / 180.0), aspect = (double)w / h;
    double x = (v[0] * r[0] + v[1] * r[1] + v[2] * r[2]) / (z * hh * aspect);
    double y = (v[0] * u[0] + v[1] * u[1] + v[2] * u[2]) / (z * hh);
    *sx = (x + 1) * 0.5 * w;
    *sy = (1 - y) * 0.5 * h;
    return true;
}

/* The probe grid (panel: show grid): each probe a square at its position,
 * green at its grid point, yellow moved out of a voxel, red disabled; the
 * probe whose maps the panel shows larger and white; baked probes filled. */
static void draw_probe_grid(app* a, vf_canvas* cv) {
    const vx_probe_set* ps = sv_probe_shown(a);
    if (!a->probe_grid || !ps) return;
    double f[3];
    sv_cam_fwd(a, f);
    for (uint32_t i = 0; i < ps->probe_count; i++) {
        double x, y;
        if (!project(a, a->eye, f, cv->width, cv->height, ps->probes[i].pos, &x, &y)) continue;
        uint32_t st = ps->probes[i].state;
        uint32_t c = i == a->probe_sel ? 0x00FFFFFFu : st == VX_PROBE_OK ? 0x0040E040u : st == VX_PROBE_MOVED ? 0x0030E0F0u
                                                                                                            : 0x002020F0u;
        int r = i == a->probe_sel ? 4 : 2;
        bool baked = i >= ps->first && i < ps->first + ps->count;
        if (baked) vf_fill_rect(cv, (int)x - r, (int)y - r, 2 * r + 1, 2 * r + 1, c, 255);
        else {
            vf_fill_rect(cv, (int)x - r, (int)y - r, 2 * r + 1, 1, c, 255);
            vf_fill_rect(cv, (int)x - r, (int)y + r, 2 * r + 1, 1, c, 255);
            vf_fill_rect(cv, (int)x - r, (int)y - r, 1, 2 * r + 1, c, 255);
            vf_fill_rect(cv, (int)x + r, (int)y - r, 1, 2 * r + 1, c, 255);
        }
    }
}

static void draw_selection(app* a, vf_canvas* cv) {
    if (a->sel == NO_SEL || a->sel >= a->scene.instance_count) return;
    double lo[3], hi[3], f[3];
    sv_world_box(a, a->sel, lo, hi);
    sv_cam_fwd(a, f);
    static const int edges[12][2] = {{0, 1}, {2, 3}, {4, 5}, {6, 7}, {0, 2}, {1, 3},
                                     {4, 6}, {5, 7}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
    for (int e = 0; e < 12; e++) {
        double p[2][3], s[2][2];
        bool ok = true;
        for (int j = 0; j < 2; j++) {
            int c = edges[e][j];
            p[j][0] = (c & 1) ? hi[0] : lo[0], p[j][1] = (c & 2) ? hi[1] : lo[1], p[j][2] = (c & 4) ? hi[2] : lo[2];
            ok &= project(a, a->eye, f, cv->width, cv->height, p[j], &s[j][0], &s[j][1]);
        }
        if (ok) vf_line(cv, s[0][0], s[0][1], s[1][0], s[1][1], 0x00FFB020u, 2);
    }
}

static void draw_overlay(app* a, vf_canvas* cv) {
    char line[512];
    int y = 6, sc = cv->height >= 900 ? 2 : 1, lh = 10 * sc;
    double sorted[64];
    uint32_t n = a->frame_n < 64 ? a->frame_n : 64;
    memcpy(sorted, a->frame_ms, n * sizeof *sorted);
    double med = 0;
    for (uint32_t i = 0; i < n; i++) med += sorted[i];
    med = n ? med / n : 0;
    uint64_t voxels = 0;
    uint32_t nd = 0;
    for (uint32_t i = 0; i < a->scene.instance_count; i++)
        if (vx_svo_instance_drawn(&a->scene, i)) nd++, voxels += a->scene.models[a->scene.instances[i].model].voxel_count;
    const char* lines[10];
    char buf[10][256];
    int nl = 0;
    snprintf(buf[nl], sizeof buf[0], "FPS %.1f  frame %.2f ms  trace %.2f ms  %.1f Mrays/s  edit+BVH %.2f ms",
             med > 0 ? 1000.0 / med : 0.0, med, a->trace_ms, a->rays_per_s * 1e-6, a->update_ms);
    lines[nl] = buf[nl], nl++;
    snprintf(buf[nl], sizeof buf[0], "device: %s%s", vx_gpu_device_name(a->gpu), vx_gpu_is_cpu(a->gpu) ? " (software)" : "");
    lines[nl] = buf[nl], nl++;
    snprintf(buf[nl], sizeof buf[0], "scene: %u models, %u instances (%u drawn), %s voxels, %u layers",
             a->scene.model_count, a->scene.instance_count, nd, vx_tool_num(voxels), a->scene.layer_count);
    lines[nl] = buf[nl], nl++;
    snprintf(buf[nl], sizeof buf[0], "mode: %s  camera: %s  vsync: %s  size %ux%u", sv_mode_name(a),
             a->orbit ? "orbit" : "fly", vp_vsync(a->p) ? "on" : "off", cv->width, cv->height);
    lines[nl] = buf[nl], nl++;
    if (a->timing_count && !a->gi && a->mode == VX_RENDER_COLOR) {
        int at = snprintf(buf[nl], sizeof buf[0], "passes (9 cycles):");
        for (uint32_t t = 0; t < a->timing_count && at > 0 && at < (int)sizeof buf[0]; t++)
            at += snprintf(buf[nl] + at, sizeof buf[0] - (size_t)at, " %s %.2f", a->timings[t].name, a->timings[t].ms);
        if (at > 0 && at < (int)sizeof buf[0]) snprintf(buf[nl] + at, sizeof buf[0] - (size_t)at, " ms  (GPU %.2f)", a->passes_ms);
        lines[nl] = buf[nl], nl++;
    }
    if (a->have_probes) {
        const vx_probe_set* ps = &a->probes;
        snprintf(buf[nl], sizeof buf[0], "probes: %ux%ux%u grid (%u probes, res %u, %u bounces)%s", ps->grid[0],
                 ps->grid[1], ps->grid[2], ps->probe_count, ps->res, ps->bounces, a->gi ? "" : "  7: gi  8: lightfield");
        lines[nl] = buf[nl], nl++;
    }
    if (a->sel != NO_SEL) {
        const vx_svo_instance* in = &a->scene.instances[a->sel];
        snprintf(buf[nl], sizeof buf[0], "selected: instance %u '%s' model %u at %g,%g,%g", a->sel, in->name, in->model,
                 in->xform[3], in->xform[7], in->xform[11]);
        lines[nl] = buf[nl], nl++;
    }
    if (a->op) {
        const char* what = a->op == 'g' ? "move" : a->op == 'r' ? "rotate" : a->op == 'm' ? "mirror" : "layer";
        if (a->op == 'l') snprintf(buf[nl], sizeof buf[0], "layer: press 0-9 to hide/show a layer");
        else if (a->op == 'g' && a->op_axis >= 0)
            snprintf(buf[nl], sizeof buf[0], "move along %c: %d voxels (arrows or mouse, Enter, Esc)", 'X' + a->op_axis,
                     a->grab_moved);
        else snprintf(buf[nl], sizeof buf[0], "%s: press X, Y or Z", what);
        lines[nl] = buf[nl], nl++;
    }
    int w = 0;
    for (int i = 0; i < nl; i++) w = fmax(w, (int)strlen(lines[i]));
    vf_fill_rect(cv, 0, 0, w * 6 * sc + 12, nl * lh + 8, 0, 150);
    for (int i = 0; i < nl; i++, y += lh) vf_text(cv, 6, y, sc, 0x00FFFFFFu, lines[i]);
    if (a->msg[0] && glfwGetTime() < a->msg_until) {
        snprintf(line, sizeof line, "%s", a->msg);
        int my = (int)cv->height - 2 * lh - 8;
        vf_fill_rect(cv, 0, my - 4, (int)strlen(line) * 6 * sc + 12, lh + 6, 0, 170);
        vf_text(cv, 6, my, sc, a->msg_error ? 0x004060FFu : 0x0060FF60u, line);
    }
}

/* The colour mode through the pass pipeline (a->passes): svo_render's
 * --passes frame for the same camera; per-pass times kept for the overlay. */
/* The file's sky for the passes, as svo_render uses it: constant and
 * gradient as stored, an environment map's texels read through OpenImageIO
 * (once per map); *sky NULL without one or when the map cannot be read (a
 * message says why, once). */
static void file_sky(app* a, const vx_sky** sky, const vx_sky_texels** map) {
    *sky = NULL, *map = NULL;
    const vx_sky* k = &a->scene.sky;
    if (k->type == VX_SKY_DEFAULT) return;
    if (k->type != VX_SKY_ENVMAP) {
        *sky = k;
        return;
    }
    char path[sizeof a->sky_file];
    if (!vx_sky_path(k, a->scene_file, path, sizeof path)) return;
    if (strcmp(path, a->sky_file)) {
        vx_free(NULL, a->sky_rgb);
        a->sky_rgb = NULL, a->sky_map = (vx_sky_texels){0};
        snprintf(a->sky_file, sizeof a->sky_file, "%s", path);
        uint32_t w = 0, h = 0, ch = 0;
        float* px = NULL;
        vx_error err = {0};
        if (vx_image_read(path, VX_IMAGE_F32, 0, &w, &h, &ch, (void**)&px, &err)) {
            sv_message(a, true, "the sky's environment map: %s", err.msg);
            return;
        }
        /* RGB per texel whatever the file has (grey: one channel; alpha dropped) */
        a->sky_rgb = vx_calloc(NULL, (size_t)w * h, 3 * sizeof(float));
        for (size_t i = 0; a->sky_rgb && i < (size_t)w * h; i++)
            for (uint32_t c = 0; c < 3; c++) a->sky_rgb[3 * i + c] = px[i * ch + (c < ch ? c : 0)];
        vx_free(NULL, px);
        if (!a->sky_rgb) {
            sv_message(a, true, "%s: out of memory for the sky's environment map", path);
            return;
        }
        a->sky_map = (vx_sky_texels){.rgb = a->sky_rgb, .width = w, .height = h};
    }
    if (a->sky_rgb) *sky = k, *map = &a->sky_map;
}

/* A frame's pass times: the overlay's and the statistics panel's numbers
 * and history. */
static void take_timings(app* a, const vx_frame_result* res) {
    memcpy(a->timings, res->timings, sizeof a->timings);
    a->timing_count = res->timing_count;
    a->passes_ms = res->frame_ms;
    /* the statistics panel's history; a different pass list starts it again */
    bool same = a->hist_layers == res->timing_count;
    for (uint32_t t = 0; same && t < res->timing_count; t++) same = a->hist_names[t] == res->timings[t].name ||
                                                                    !strcmp(a->hist_names[t], res->timings[t].name);
    if (!same) a->hist_n = 0, a->hist_layers = res->timing_count;
    for (uint32_t t = 0; t < res->timing_count; t++) a->hist_names[t] = res->timings[t].name;
    if (a->hist_n == SV_HISTORY) memmove(a->hist[0], a->hist[1], (SV_HISTORY - 1) * sizeof a->hist[0]);
    else a->hist_n++;
    for (uint32_t t = 0; t < res->timing_count; t++) a->hist[a->hist_n - 1][t] = (float)res->timings[t].ms;
}

/* The colour passes: rendered and waited for (cmd NULL), or recorded into
 * cmd for frame slot `slot` (frames in flight: the times come with the
 * slot's next frame, take_timings). */
/* The frame's description (the state the pass pipeline renders). */
static vx_result frame_desc(app* a, const vx_render_desc* d, bool on_gpu, vx_frame_desc* out, vx_error* err) {
    const vx_sky* sky;
    const vx_sky_texels* sky_map;
    file_sky(a, &sky, &sky_map);
    /* the gi methods are made with the file's lights (as in svo_render:
     * gi=pathtrace and gi=cones carry them, the probe methods give them to
     * the direct pass): made again when the lights changed */
    if ((a->pgi || a->cgi || a->phgi) && a->gi_light_serial != a->light_serial) sv_drop_gi(a);
    a->gi_light_serial = a->light_serial;
    bool made = a->pgi || a->cgi || a->phgi;
    if (vx_pass_list_has(&a->passes, VX_PASS_GI) && !made && !strcmp(a->passes.gi, "cones")) {
        /* the render panel's settings (svo_render's --cone-*), the file's lights and sky */
        vx_cone_desc cd = a->gis.cone;
        cd.sky_dir = sky, cd.sky_map = sky_map, cd.lights = a->scene.lights, cd.light_count = a->scene.light_count;
        vx_result r = vx_cone_gi_create(a->rs, &a->scene, &cd, &a->gm, &a->cgi, err);
        if (r) return r;
    } else if (vx_pass_list_has(&a->passes, VX_PASS_GI) && !made && !strcmp(a->passes.gi, "photons")) {
        /* svo_render's gi=photons with the render panel's settings (--photons, --radius, --final-gather, --seed;
         * zero: photons.h's defaults), the file's lights and sky */
        vx_photon_desc pd = a->gis.photon;
        pd.seed = a->gis.seed;
        pd.sky_dir = sky, pd.sky_map = sky_map, pd.lights = a->scene.lights, pd.light_count = a->scene.light_count;
        vx_result r = vx_photon_gi_create(a->rs, &a->scene, a->have_probes ? &a->probes : NULL, &pd, &a->gm, &a->phgi, err);
        if (r) return r;
    } else if (vx_pass_list_has(&a->passes, VX_PASS_GI) && !made) {
        vx_probe_render_desc pd = {.sky = sky, .sky_map = sky_map, .bounces = a->gis.bounces, .seed = a->gis.seed};
        pd.lights = a->scene.lights, pd.light_count = a->scene.light_count;
        vx_result r = vx_probe_gi_create(a->rs, &a->scene, a->have_probes ? &a->probes : NULL, a->passes.gi, &pd,
                                         &a->gm, &a->pgi, err);
        if (r) return r;
    }
    vx_frame_desc fd = vx_frame_desc_defaults();
    fd.base = *d;
    fd.base.mode = VX_RENDER_COLOR;
    fd.base.spp = a->gis.spp; /* 0: the pipeline's default (1, or 8 with aa or dof) */
    fd.seed = a->gis.seed;
    fd.ao_rays = a->gis.ao_rays, fd.ao_radius = a->gis.ao_radius;
    fd.passes = &a->passes;
    if (a->gis.cone.shadows && vx_pass_list_has(&a->passes, VX_PASS_GI) && !strcmp(a->passes.gi, "cones")) {
        /* cone shadows: the gi pass brings the direct light, so no direct pass (as svo_render drops it) */
        a->passes_run = a->passes;
        uint32_t k = 0;
        for (uint32_t j = 0; j < a->passes.count; j++)
            if (a->passes.kinds[j] != VX_PASS_DIRECT) a->passes_run.kinds[k++] = a->passes.kinds[j];
        a->passes_run.count = k;
        fd.passes = &a->passes_run;
    }
    fd.gi = a->pgi || a->cgi || a->phgi ? &a->gm : NULL;
    fd.want_ids = d->want_hits;
    fd.no_readback = on_gpu; /* the image stays on the GPU for vx_display */
    fd.exposure = a->exposure;
    /* the file's lights, as svo_render uses them by default (edited in the properties panel) */
    fd.lights = a->scene.lights;
    fd.light_count = a->scene.light_count;
    fd.sky_dir = sky, fd.sky_map = sky_map; /* and its sky */
    *out = fd;
    return VX_OK;
}

/* A frame submitted and waited for (frames in flight: present_in_flight). */
static vx_result render_passes(app* a, const vx_render_desc* d, bool on_gpu, vx_error* err) {
    vx_frame_desc fd;
    vx_frame_result res;
    vx_result r = frame_desc(a, d, on_gpu, &fd, err);
    if (r || (r = vx_frame_render(a->fr, &fd, &res, err))) return r;
    a->img = res.image;
    take_timings(a, &res);
    return VX_OK;
}

/* Frames in flight (render/display.h): the passes, the conversion with the
 * overlay and the copy into the swapchain image in one command buffer,
 * submitted and presented without waiting for it; vx_display_frame_begin
 * waits only for the frame VX_DISPLAY_FRAMES before, whose pass times the
 * statistics then show. Where the swapchain images are storage images the
 * frame's last pass writes the image itself (vx_display_record_frame: no
 * conversion pass), so the image is acquired before the passes are
 * recorded. VX_ERR_UNSUPPORTED, nothing submitted: a frame the recorder
 * refuses (lights that need a culling grid), which takes the waited path. */

static vx_result present_in_flight(app* a, const vx_render_desc* d, const vx_display_desc* dd, vx_error* err) {
    uint32_t slot;
    void* cmd;
    if (!a->o.batch) { /* --batch auto: the batch the measured frames ask for, the held frames presented first */
        uint32_t want = sv_batch_want(&a->batch, vp_vsync(a->p));
        if (want != a->batch.cur) {
            vx_result br = sv_batch_drain(a, err);
            if (!br) br = vx_display_set_queue(a->disp, want > 1 ? 2 * want : 0, want, false, err);
            if (br) return br;
            if (a->o.verbose)
                printf("%s: %u frames a submission from frame %llu (--batch auto)\n", vx_tool_name, want,
                       (unsigned long long)a->frames_recorded);
            sv_batch_set(&a->batch, want);
        }
    }
    vx_result r = vx_display_frame_begin(a->disp, &slot, &cmd, err);
    if (r) return r;
    vx_frame_result done;
    bool timed = !vx_frame_record_result(a->fr, slot, &done, NULL) && done.frame_ms > 0;
    sv_batch_frame(&a->batch, timed ? done.frame_ms : 0);
    if (timed) { /* a frame that was timed */
        take_timings(a, &done);
        a->trace_ms = done.image.gpu_seconds * 1e3;
        a->rays_per_s = done.image.gpu_seconds > 0 ? done.image.rays / done.image.gpu_seconds : 0;
    }
    vx_frame_desc fd;
    vp_image im;
    r = frame_desc(a, d, true, &fd, err);
    /* the passes' timestamps in one frame of 8, fewer for short frames (the statistics' times; each timed frame
     * costs an H200 a few microseconds more: batch.h) */
    fd.no_timestamps = !sv_batch_timed(&a->batch);
    vx_display_times dt;
    if (a->batch.max > 1 && vp_stale(a->p)) {
        /* a new swapchain next: the held frames submitted and their images presented before the old one goes */
        vx_result wr = vx_display_wait(a->disp, err);
        vx_display_frame_times(a->disp, &dt);
        if (!r && !wr) wr = vp_present_submitted(a->p, dt.frames_submitted, err);
        if (!r) r = wr;
    }
    vx_display_frame_times(a->disp, &dt);
    vp_set_frame_number(a->p, a->frames_recorded); /* the display numbers its frames as they are submitted */
    if (r || (r = vx_frame_recordable(&fd, err)) || (r = vp_acquire(a->p, slot, &im, err))) {
        vx_display_frame_cancel(a->disp);
        return r;
    }
    /* without an image (minimised, a new swapchain next frame) the passes still run, unseen */
    vx_frame_result res;
    bool fused = im.image && im.view;
    /* the panels drawn over the image after the last pass wrote it, in the same command buffer */
    bool panels = fused && a->panels_gpu_now;
    r = fused ? vx_display_record_frame(a->disp, a->fr, &fd, dd, im.image, im.view, im.width, im.height,
                                        panels ? VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL : im.layout, &res, err)
              : vx_frame_record(a->fr, &fd, cmd, slot, &res, err);
    char why[256];
    if (!r && panels && !sv_panels_gpu_record(a, cmd, slot, im.view, im.width, im.height, why, sizeof why))
        r = vx_fail(err, VX_ERR_GPU, VX_NO_OFFSET, "%s", why);
    if (r) {
        /* the acquired image is still presented (its semaphore waited for): cleared, in the slot's frame again */
        vx_frame_record_cancel(a->fr);
        vx_display_frame_cancel(a->disp);
        vx_error again;
        if (!im.image || vx_display_frame_begin(a->disp, &slot, &cmd, &again)) return r;
        vx_display_copy_to_image(cmd, 0, dd->width, dd->height, im.image, im.width, im.height, im.layout);
    } else if (im.image && !fused) {
        a->img = res.image;
        uint64_t bytes = 0;
        r = vx_display_record(a->disp, cmd, dd, &bytes, err);
        vx_display_copy_to_image(cmd, r ? 0 : bytes, dd->width, dd->height, im.image, im.width, im.height, im.layout);
    } else {
        a->img = res.image;
    }
    vx_result sr = vx_display_frame_submit(a->disp, im.acquired, im.rendered, err);
    if (!sr) a->frames_recorded++;
    if (!sr && im.image) sr = vp_present_acquired(a->p, err);
    if (!sr && a->batch.max > 1) { /* the frames submitted by now (this batch, or held ones an edit submitted) */
        vx_display_frame_times(a->disp, &dt);
        sr = vp_present_submitted(a->p, dt.frames_submitted, err);
    }
    return sr ? sr : r;
}

/* Before a frame that is not a frame in flight (a grab, another mode, the
 * host path): the frames a batch holds submitted and presented, so that the
 * images go to the screen in the order they were made. */
vx_result sv_batch_drain(app* a, vx_error* err) {
    if (a->batch.max <= 1 || !a->disp) return VX_OK;
    vx_result r = vx_display_wait(a->disp, err);
    vx_display_times dt;
    vx_display_frame_times(a->disp, &dt);
    vx_result pr = vp_present_submitted(a->p, dt.frames_submitted, err);
    return r ? r : pr;
}

/* Sets the pass list (script command `passes LIST`, key 9 cycles presets). */
bool sv_set_passes(app* a, const char* list) {
    vx_pass_list pl;
    vx_error err = {0};
    if (vx_pass_list_parse(list, &pl, &err)) {
        sv_message(a, true, "passes: %s", err.msg);
        return false;
    }
    if (vx_pass_list_has(&pl, VX_PASS_GI) && !vx_tool_gi_method_known(pl.gi)) {
        sv_message(a, true, "passes: unknown gi method '%s' (" VX_TOOL_GI_METHODS ")", pl.gi);
        return false;
    }
    if (vx_pass_list_has(&pl, VX_PASS_GI) && vx_tool_gi_method_needs_probes(pl.gi) && !a->have_probes) {
        sv_message(a, true, "gi=%s needs light field probes (--probes FILE, or the script command probes FILE)", pl.gi);
        return false;
    }
    sv_drop_gi(a);
    a->passes = pl;
    a->timing_count = 0;
    char t[160];
    vx_pass_list_format(&pl, t, sizeof t);
    sv_message(a, false, "passes %s", t[0] ? t : "(none)");
    return true;
}

/* The model cell a voxel click edits: for add the empty cell in front of the
 * hit face (the face the pixel's ray enters the hit cell through, found by
 * the slab test in model space with the tracer's own ray), else the hit cell;
 * with the face brush the hit cell and that face (*face, 0..5). */
static void click_target(const app* a, const vx_render_desc* d, uint32_t x, uint32_t y, const vx_render_hit* hit,
                         vvx_op op, int64_t out[3], uint8_t* face) {
    for (int k = 0; k < 3; k++) out[k] = hit->cell[k];
    bool want_face = a->brush.shape == VVX_FACE;
    if (op != VVX_ADD && !want_face) return;
    double lo[3], hi[3], wi[12], mi[12];
    vx_svo_scene_world_bounds(&a->scene, lo, hi);
    vx__frame f;
    const vx_svo_instance* in = vx_svo_scene_frame_instances(&a->scene, a->anim_frame) + hit->instance;
    if (vx__frame_setup(lo, hi, d, &f, NULL) || !vx__affine_inverse(a->scene.world_from_grid, wi) ||
        !vx__affine_inverse(in->xform, mi))
        return;
    double u = ((x + 0.5) / f.width) * 2 - 1, v = 1 - ((y + 0.5) / f.height) * 2, o[3], dir[3], og[3], dg[3], om[3], dm[3];
    for (int k = 0; k < 3; k++) {
        double off = u * f.rx[k] + v * f.uy[k];
        o[k] = f.ref[k] + (f.ortho ? off : f.t_start * off);
        dir[k] = f.ortho ? f.fwd[k] : f.fwd[k] + off;
    }
    vx__affine_apply(wi, o, og);
    vx__affine_apply(mi, og, om);
    for (int r = 0; r < 3; r++) dg[r] = wi[4 * r] * dir[0] + wi[4 * r + 1] * dir[1] + wi[4 * r + 2] * dir[2];
    for (int r = 0; r < 3; r++) dm[r] = mi[4 * r] * dg[0] + mi[4 * r + 1] * dg[1] + mi[4 * r + 2] * dg[2];
    int axis = -1;
    double best = -INFINITY;
    for (int k = 0; k < 3; k++) {
        if (dm[k] == 0) continue; /* parallel to the slab: never the entry face */
        double t1 = ((double)hit->cell[k] - om[k]) / dm[k], t2 = ((double)hit->cell[k] + 1 - om[k]) / dm[k];
        double tn = fmin(t1, t2);
        if (tn > best) best = tn, axis = k;
    }
    if (axis >= 0 && want_face) *face = (uint8_t)(2 * axis + (dm[axis] > 0 ? 0 : 1));
    else if (axis >= 0) out[axis] += dm[axis] > 0 ? -1 : 1;
}

/* Renders, converts, overlays and presents one frame. */
vx_result sv_frame(app* a, vx_error* err) {
    uint32_t w = a->o.width, h = a->o.height;
    if (!w) {
        vp_frame_size(a->p, &w, &h);
        if (!w || !h) return VX_OK;
    }
    double t0 = vx_time_now();
    vx_render_image_free(&a->img);
    vx_render_desc d = {.width = w, .height = h, .mode = a->mode, .camera = sv_camera_desc(a), .want_hits = a->pick_pending};
    vx_render_image pick_img = {0}; /* gi frames carry no hit records: a pick traces its own */
    if (a->rs && a->gi) {
        /* svo_render --mode gi|lightfield: its default spp, seed and bounces, the probes' light */
        vx_render_desc base = {.width = w, .height = h, .camera = d.camera};
        vx_probe_render_desc pd = {.base = &base, .mode = a->pmode};
        /* the probe maps stay on the GPU between frames (light field maps: up to
         * hundreds of MB) until the scene is rebuilt or other probes load */
        vx_result r = a->probes_gpu ? VX_OK : vx_probe_gpu_create(a->rs, &a->scene, &a->probes, &a->probes_gpu, err);
        if (!r) r = vx_probe_gpu_render(a->probes_gpu, &pd, &a->img, err);
        if (r && (a->o.screenshot || a->o.bench)) return r;
        if (r) {
            sv_message(a, true, "mode %s: %s", vx_probe_render_mode_name(a->pmode), err->msg);
            a->gi = false;
        } else if (a->pick_pending && (r = vx_render_frame(a->rs, &d, &pick_img, err))) {
            return r;
        }
    }
    bool passes = a->rs && !a->gi && a->mode == VX_RENDER_COLOR && a->fr && !vx_render_scene_precise(a->rs);
    /* the GPU path: the colour passes' image, unless this frame's pixels are wanted on the host */
    bool on_gpu = a->disp && passes && !a->pick_pending && !a->shot && !a->o.screenshot;
    /* frames in flight: all GPU-path frames but grabs (read back after a wait) */
    bool fly = on_gpu && !a->grab;
    if (passes && !fly) {
        vx_result r = render_passes(a, &d, on_gpu, err);
        if (r) return r;
    } else if (a->rs && !a->gi && !passes) {
        vx_result r = vx_render_frame(a->rs, &d, &a->img, err);
        if (r) return r;
    }
    if (a->rs && (a->img.pixels || (on_gpu && !fly))) {
        a->trace_ms = a->img.gpu_seconds * 1e3;
        a->rays_per_s = a->img.gpu_seconds > 0 ? a->img.rays / a->img.gpu_seconds : 0;
    }
    if (a->pick_pending) {
        a->pick_pending = false;
        uint32_t x = (uint32_t)a->pick_x, y = (uint32_t)a->pick_y;
        uint32_t hit = VX_RENDER_NO_HIT;
        const vx_render_hit* hits = pick_img.hits ? pick_img.hits : a->img.hits;
        vx_render_hit hr = {.instance = VX_RENDER_NO_HIT};
        if (hits && a->pick_x >= 0 && a->pick_y >= 0 && x < w && y < h) hr = hits[(size_t)y * w + x];
        hit = hr.instance;
        vx_render_image_free(&pick_img);
        if (a->pick_op >= 0) {
            /* a voxel click edits the hit instance's model (and selects it) */
            vvx_op op = (vvx_op)a->pick_op;
            a->pick_op = -1;
            if (hit == VX_RENDER_NO_HIT || hit >= a->scene.instance_count) {
                printf("%s: voxel %s at %u %u: nothing there\n", vx_tool_name, vvx_op_name(op), x, y);
            } else {
                int64_t c[3];
                click_target(a, &d, x, y, &hr, op, c, &a->brush.face);
                a->sel = hit;
                printf("%s: voxel %s at %u %u: instance %u cell %lld %lld %lld\n", vx_tool_name, vvx_op_name(op), x, y,
                       hit, (long long)c[0], (long long)c[1], (long long)c[2]);
                sv_voxels(a, op, c);
            }
        } else {
            a->sel = hit == VX_RENDER_NO_HIT ? NO_SEL : hit;
            if (hit == VX_RENDER_NO_HIT) printf("%s: pick %u %u: nothing\n", vx_tool_name, x, y);
            else printf("%s: pick %u %u: instance %u cell %u %u %u\n", vx_tool_name, x, y, hit, hr.cell[0], hr.cell[1], hr.cell[2]);
        }
    }
    if (a->shot && a->img.pixels) {
        vx_result r = save_image(&a->img, a->shot, err);
        if (r) sv_message(a, true, "%s: %s", a->shot, err->msg);
        else printf("%s: wrote %s (%ux%u, mode %s)\n", vx_tool_name, a->shot, w, h, sv_mode_name(a));
        if (r && a->o.screenshot) return r;
    }
    a->shot = NULL;
    size_t need = (size_t)w * h * 4;
    if (need > a->px8_cap) {
        free(a->px8);
        a->px8 = malloc(need);
        a->px8_cap = a->px8 ? need : 0;
        if (!a->px8) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for a %ux%u frame", w, h);
    }
    vf_canvas cv = {.pixels = a->px8, .width = w, .height = h, .bgra = vp_frame_bgra(a->p)};
    /* the panels on the GPU (frames in flight into storage and colour-attachment swapchain images): the overlay
     * then holds only what the CPU still draws (selection, probe grid), and none when nothing */
    bool panels_gpu_was = a->panels_gpu_now;
    a->panels_gpu_now = fly && a->panels_gpu && a->ui && a->panels && vp_colour(a->p);
    if (a->panels_gpu_now != panels_gpu_was) a->ui_dirty = true; /* the other way's panels to draw */
    bool draws = !a->o.screenshot &&
                 ((a->ui && a->panels && !a->panels_gpu_now) ||
                  (!a->o.bench && ((a->overlay && !(a->ui && a->panels)) || a->sel != NO_SEL || a->probe_grid)));
    bool panels_draw = a->ui && a->panels && !a->o.screenshot;
    a->frame_on_gpu = on_gpu;
    if (on_gpu) {
        /* the overlay (selection, panels, text) is drawn on the CPU into the
         * display's mapped buffer, again only when something may have changed
         * it: input, a script command, the camera, playback, a bake, a
         * message, a grab, or 250 ms passed (the statistics' numbers) */
        vf_canvas ov = cv;
        double now = vx_time_now(), cam[5] = {a->eye[0], a->eye[1], a->eye[2], a->yaw, a->pitch};
        bool redraw = (draws || panels_draw) &&
                      (a->ui_dirty || !a->ov_valid || a->ov_w != w || a->ov_h != h || a->grab || a->playing ||
                       a->bake.active || a->op || now - a->ov_time > 0.25 || now < a->msg_until + 0.1 ||
                       memcmp(cam, a->ov_cam, sizeof cam) || a->cam_default != a->ov_cam_default);
        if (redraw && draws && !(ov.pixels = vx_display_overlay(a->disp, w, h, err))) return VX_ERR_GPU;
        a->ov_valid = (draws || panels_draw) && (a->ov_valid || redraw);
        a->panels_ms = 0;
        if (redraw) {
            a->ui_dirty = false;
            a->ov_time = now, a->ov_w = w, a->ov_h = h, a->ov_cam_default = a->cam_default;
            memcpy(a->ov_cam, cam, sizeof cam);
            if (draws) {
                draw_probe_grid(a, &ov);
                draw_selection(a, &ov);
            }
            double tp = thread_seconds();
            if (a->ui && a->panels) sv_panels_draw(a, &ov); /* on the GPU: only the draw lists (ov unused) */
            else if (a->overlay) draw_overlay(a, &ov);
            a->panels_ms = a->ui && a->panels ? (thread_seconds() - tp) * 1e3 : 0;
        }
        vx_display_desc dd = {.fr = a->fr, .width = w, .height = h, .bgra = cv.bgra, .overlay = draws};
        vx_result r = VX_ERR_UNSUPPORTED;
        a->frame_in_flight = fly && (r = present_in_flight(a, &d, &dd, err)) != VX_ERR_UNSUPPORTED;
        if (a->frame_in_flight && r) return r;
        if (!a->frame_in_flight && a->panels_gpu_now) {
            /* a frame the recorder refused takes the waited path: the panels drawn on the CPU from now on */
            a->panels_gpu = a->panels_gpu_now = false;
            a->ui_dirty = true;
        }
        if (!a->frame_in_flight) {
            /* the waited path: a grab (read back after the wait), or a frame the recorder refused */
            if ((r = sv_batch_drain(a, err))) return r;
            if (fly) {
                if ((r = render_passes(a, &d, true, err))) return r;
                a->trace_ms = a->img.gpu_seconds * 1e3;
                a->rays_per_s = a->img.gpu_seconds > 0 ? a->img.rays / a->img.gpu_seconds : 0;
            }
            if ((r = vp_present_display(a->p, a->disp, &dd, a->grab ? a->px8 : NULL, err))) return r;
        }
    } else {
        vx_result r = sv_batch_drain(a, err);
        if (r) return r;
        a->ov_valid = false;
        if (a->img.pixels) convert(a, &a->img, &cv);
        else memset(a->px8, 0, need);
        if (draws) {
            draw_probe_grid(a, &cv);
            draw_selection(a, &cv);
            double tp = thread_seconds();
            if (a->ui && a->panels) sv_panels_draw(a, &cv);
            else if (a->overlay) draw_overlay(a, &cv);
            a->panels_ms = a->ui && a->panels ? (thread_seconds() - tp) * 1e3 : 0;
        }
    }
    if (a->grab) {
        vx_result r = save_canvas(&cv, a->grab, err);
        if (r) sv_message(a, true, "%s: %s", a->grab, err->msg);
        else printf("%s: wrote %s (%ux%u, the displayed frame%s)\n", vx_tool_name, a->grab, w, h,
                    on_gpu ? ", read back from the GPU path" : "");
        a->grab = NULL;
    }
    if (!on_gpu) {
        vx_result r = vp_present(a->p, a->px8, w, h, err);
        if (r) return r;
    }
    a->frame_ms[a->frame_n++ % 64] = (vx_time_now() - t0) * 1e3;
    return VX_OK;
}
