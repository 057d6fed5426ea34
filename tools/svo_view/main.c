/* tools/svo_view/main.c - svo_view FILE [options]: an interactive viewer and
 * scene editor on the Vulkan tracer (GLFW window, swapchain, CPU overlay),
 * scriptable for headless runs under Xvfb. This file sets the viewer up, runs
 * its loop (input, animation, a bake's step, script commands, a frame) and
 * tears it down; app.h lists the other files. */
#include <GLFW/glfw3.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tools/common/tool.h"
#include "tools/svo_view/app.h"
#include "tools/svo_view/batch.h"
#include "tools/svo_view/camera.h"
#include "tools/svo_view/frame.h"
#include "tools/svo_view/input.h"
#include "tools/svo_view/panels.h"
#include "tools/svo_view/script.h"

/* ---- main ------------------------------------------------------------------------------- */

static int cmp_double(const void* x, const void* y) {
    double a = *(const double*)x, b = *(const double*)y;
    return (a > b) - (a < b);
}

static void log_cb(void* user, vx_log_level level, const char* id, const char* msg) {
    (void)user;
    if (level >= VX_LOG_WARN) fprintf(stderr, "%s: %s: %s\n", vx_tool_name, id, msg);
}

/* --bench N: per frame the wall time, the trace's GPU time, an animation's
 * frame switch, the panels' CPU time and the script's commands before it. */
typedef struct bench_times {
    double *frame, *trace, *frame_switch, *panels, *edit;
} bench_times;

static bool bench_times_make(bench_times* bt, uint32_t n) {
    *bt = (bench_times){0};
    if (!n) return true;
    bt->frame = calloc(n, sizeof *bt->frame);
    bt->trace = calloc(n, sizeof *bt->trace);
    bt->frame_switch = calloc(n, sizeof *bt->frame_switch);
    bt->panels = calloc(n, sizeof *bt->panels);
    bt->edit = calloc(n, sizeof *bt->edit);
    return bt->frame && bt->trace && bt->frame_switch && bt->panels && bt->edit;
}

static void bench_times_free(bench_times* bt) {
    free(bt->frame);
    free(bt->trace);
    free(bt->frame_switch);
    free(bt->panels);
    free(bt->edit);
}

/* --bench N: the medians of the frames' times. */
static void bench_report(const app* a, bench_times* bt, uint32_t frames) {
    double sum = 0; /* the mean too: with --batch the frames come in bursts, so the median is not the rate */
    for (uint32_t k = 0; k < frames; k++) sum += bt->frame[k];
    qsort(bt->frame, frames, sizeof *bt->frame, cmp_double);
    qsort(bt->trace, frames, sizeof *bt->trace, cmp_double);
    uint32_t fw = a->o.width, fh = a->o.height;
    if (!fw) vp_frame_size(a->p, &fw, &fh);
    printf("%s: %u frames %ux%u mode %s on %s: median frame %.3f ms (mean %.3f ms), median trace %.3f ms (GPU "
           "timestamps)\n",
           vx_tool_name, frames, fw, fh, sv_mode_name(a), vx_gpu_device_name(a->gpu), bt->frame[frames / 2], sum / frames,
           bt->trace[frames / 2]);
    qsort(bt->panels, frames, sizeof *bt->panels, cmp_double);
    qsort(bt->edit, frames, sizeof *bt->edit, cmp_double);
    printf("%s: panels %s (median %.3f ms of CPU time drawing them), present %s, script commands before a frame "
           "median %.3f ms (max %.3f ms)\n",
           vx_tool_name, a->ui && a->panels ? "on" : "off", bt->panels[frames / 2],
           a->frame_on_gpu ? "GPU" : "host readback", bt->edit[frames / 2], bt->edit[frames - 1]);
    if (vx_svo_scene_frames(&a->scene) > 1) {
        qsort(bt->frame_switch, frames, sizeof *bt->frame_switch, cmp_double);
        printf("%s: animation of %u frames played, one per bench frame: median frame switch %.3f ms "
               "(instance tables and BVH; no model upload)\n",
               vx_tool_name, vx_svo_scene_frames(&a->scene), bt->frame_switch[frames / 2]);
    }
}

/* At the loop's end: the frames a batch still holds go to the screen; with -v
 * what became of the frames in flight. */
static void drain_frames_in_flight(app* a) {
    vx_error derr = {0};
    if (sv_batch_drain(a, &derr)) fprintf(stderr, "%s: %s\n", vx_tool_name, derr.msg);
    vx_display_times dt;
    vx_display_frame_times(a->disp, &dt);
    vp_present_counts pc;
    vp_get_present_counts(a->p, &pc);
    if (a->o.verbose)
        printf("%s: frames in flight: %llu recorded, %llu submitted in %llu vkQueueSubmit calls, %llu presented "
               "(%llu out of order, %u still queued)\n",
               vx_tool_name, (unsigned long long)a->frames_recorded, (unsigned long long)dt.frames_submitted,
               (unsigned long long)dt.submits, (unsigned long long)pc.presented, (unsigned long long)pc.out_of_order,
               pc.queued);
}

/* The panels' part of a script (`ui key`, `ui click`): a key released a
 * frame after its press; a click at the widget's centre once the panels drew
 * it, pressed for one frame. */
static void scripted_panel_input(app* a) {
    if (a->ui_key_up) { /* `ui key K`: released a frame after the press */
        sv_panels_key(a, a->ui_key_up, false, 0);
        a->ui_key_up = 0;
        a->ui_dirty = true;
    }
    if (a->ui_finding) { /* `ui click LABEL`: at the widget's centre once the panels drew it */
        float r[4];
        a->ui_dirty = true;
        if (sv_panels_found(a, r)) {
            a->click_x = 0.5 * (r[0] + r[2]), a->click_y = 0.5 * (r[1] + r[3]);
            a->click_state = 2, a->ui_finding = 0;
        } else if (!--a->ui_finding) {
            fprintf(stderr, "%s: %s: ui click: no widget '%s' on the panels\n", vx_tool_name, a->o.script, a->ui_label);
            a->status = 1, a->quit = true;
        }
    }
    if (a->click_state == 1) { /* a scripted panel click: released one frame after the press */
        sv_panels_button(a, 0, false);
        if (a->ui_ctrl) sv_panels_key(a, GLFW_KEY_LEFT_CONTROL, false, 0), a->ui_ctrl = false;
        a->click_state = 0;
        a->ui_dirty = true;
    } else if (a->click_state == 2) {
        sv_panels_mouse(a, a->click_x, a->click_y);
        if (a->ui_ctrl) sv_panels_key(a, GLFW_KEY_LEFT_CONTROL, true, GLFW_MOD_CONTROL);
        sv_panels_button(a, 0, true);
        a->click_state = 1;
        a->ui_dirty = true;
    }
}

/* The script's commands before this frame: after a `wait` its frames, else
 * the commands up to the next one that needs a frame (pick, screenshot,
 * wait, grab, a panel click or key, a bake). */
static void script_commands(app* a) {
    if (a->wait) {
        a->wait--;
        return;
    }
    while (a->line_pos < a->line_count && !a->quit && !a->pick_pending && !a->shot && !a->wait && !a->grab &&
           !a->click_state && !a->ui_finding && !a->ui_key_up && !a->bake.active) {
        uint32_t ln = a->line_pos++;
        if (!sv_script_command(a, a->lines[ln], ln + 1)) {
            a->status = 1;
            a->quit = true;
        }
    }
}

static int run(app* a) {
    vx_error err = {0};
    double last = glfwGetTime(), last_play = last;
    bench_times bt;
    if (!bench_times_make(&bt, a->o.bench)) a->quit = true, a->status = 1;
    uint32_t frames = 0;
    GLFWwindow* w = vp_window(a->p);
    if (a->o.screenshot) a->shot = a->o.screenshot;
    while (!a->quit && !glfwWindowShouldClose(w)) {
        glfwPollEvents();
        double now = glfwGetTime();
        sv_fly(a, fmin(now - last, 0.25));
        last = now;
        scripted_panel_input(a);
        sv_play_step(a, fmin(now - last_play, 0.25));
        last_play = now;
        sv_probe_bake_step(a); /* a step of a running bake, between frames */
        double t_edit = vx_time_now();
        if (a->lines && !a->pick_pending && !a->click_state && !a->ui_finding && !a->ui_key_up && !a->bake.active) {
            script_commands(a);
            if (a->quit && !a->shot && !a->pick_pending && !a->grab && !a->click_state && !a->ui_finding && !a->ui_key_up)
                break;
        }
        double t0 = vx_time_now();
        if (a->o.bench && vx_svo_scene_frames(&a->scene) > 1) {
            /* an animation plays, one frame per bench frame: the frame switch is in the time */
            sv_set_frame(a, (a->anim_frame + 1) % vx_svo_scene_frames(&a->scene));
            bt.frame_switch[frames] = a->switch_ms;
        }
        vx_result r = sv_frame(a, &err);
        if (r) {
            fprintf(stderr, "%s: %s\n", vx_tool_name, err.msg);
            a->status = 1;
            break;
        }
        if (a->o.bench) {
            bt.frame[frames] = (vx_time_now() - t0) * 1e3;
            bt.trace[frames] = a->trace_ms;
            bt.panels[frames] = a->panels_ms;
            bt.edit[frames] = (t0 - t_edit) * 1e3; /* the script's commands before this frame (edits) */
            if (++frames == a->o.bench) break;
        }
        if (a->o.screenshot) break;
    }
    if (a->disp && a->frames_recorded) drain_frames_in_flight(a);
    if (a->o.bench && frames) bench_report(a, &bt, frames);
    bench_times_free(&bt);
    return a->status;
}

/* --present: the GPU path on devices that are not the CPU (auto), or as
 * asked; it needs vx_display (a compute pipeline on the window's device). */
static void choose_present(app* a) {
    const char* want = a->o.present ? a->o.present : "auto";
    bool cpu = vx_gpu_is_cpu(a->gpu);
    if (!strcmp(want, "host") || (!strcmp(want, "auto") && cpu)) {
        snprintf(a->present_note, sizeof a->present_note, "host readback (%s)",
                 !strcmp(want, "host") ? "--present host" : "a CPU device: its memory is the host's");
        return;
    }
    vx_error err = {0};
    if (vx_display_create(a->gpu, &a->disp, &err)) {
        snprintf(a->present_note, sizeof a->present_note, "host readback (the GPU path failed: %.100s)", err.msg);
        a->disp = NULL;
        return;
    }
    vx_display_set_timestamps(a->disp, false); /* the viewer reads the passes' times, not the display's */
    /* batches: twice their frames in flight, so that one batch runs while the next is recorded */
    if (a->batch.cur > 1 && vx_display_set_queue(a->disp, 2 * a->batch.cur, a->batch.cur, false, &err)) {
        snprintf(a->present_note, sizeof a->present_note, "host readback (the GPU path failed: %.100s)", err.msg);
        vx_display_destroy(a->disp);
        a->disp = NULL;
        return;
    }
    /* the panels drawn on the GPU where the swapchain images take the last pass's writes and a render pass */
    char why[256] = "", batch_text[96];
    if (a->o.batch) snprintf(batch_text, sizeof batch_text, "%u", a->batch.cur);
    else snprintf(batch_text, sizeof batch_text, "1 to %u (--batch auto: from the frame time, at most %g ms later; 1 with vsync)",
                  a->batch.max, a->batch.latency_ms);
    if (a->o.gpu_panels && a->ui && vp_colour(a->p)) a->panels_gpu = sv_panels_gpu_init(a, why, sizeof why);
    snprintf(a->present_note, sizeof a->present_note,
             "GPU: colour passes -> display conversion + overlay %s the swapchain image in one submission, %u "
             "frames in flight, %s a submission (%s); panels %s; grabs wait for theirs; other modes, picks, screenshots: "
             "host readback",
             vp_storage(a->p) ? "fused into the last pass, written into" : "-> a copy to",
             a->batch.cur > 1 ? 2 * a->batch.cur : VX_DISPLAY_FRAMES, batch_text,
             strcmp(want, "gpu") ? "auto" : "--present gpu",
             a->panels_gpu        ? "drawn on the GPU (ImGui's Vulkan backend) in that submission"
             : why[0]             ? why
             : !a->o.gpu_panels   ? "drawn on the CPU into the overlay (--gpu-panels: on the GPU)"
                                  : "drawn on the CPU into the overlay (the swapchain images are not storage and colour images)");
}

/* The viewer's state before the scene: the options, the memory budget, the
 * batches of frames in flight, nothing selected, the panels' defaults. */
static void app_init(app* a, options o) {
    a->o = o;
    a->batch = sv_batch_make(a->o.batch ? a->o.batch : VX_DISPLAY_SLOTS / 2, a->o.batch_latency);
    if (a->o.batch) a->batch.cur = a->o.batch; /* fixed: never changed */
    vx_budget_init(&a->budget, a->o.conv.max_memory, NULL);
    if (a->o.conv.max_memory) a->o.conv.alloc = &a->budget.allocator;
    a->sel = NO_SEL;
    a->sel_light = NO_SEL;
    a->light_step_for = a->mat_step_for = NO_SEL;
    a->mat_sel = 1; /* the properties panel's material: palette entry 1 */
    a->name_for = NO_SEL;
    a->pick_op = -1;
    a->bake_res_i = 1, a->bake_spp = 8, a->bake_grid = 4; /* the probe panel's bake: res 32, 8 spp, 4^3 probes */
    a->mode = a->o.mode;
    a->gi = a->o.gi;
    a->pmode = a->o.pmode;
    a->overlay = true;
    vx_pass_list_parse(a->o.passes, &a->passes, NULL); /* checked by sv_options_parse() */
}

/* Everything the viewer made, in reverse order; with --validate the count of
 * validation errors, which fails a run that had any. Returns the exit status. */
static int app_free(app* a, int status) {
    sv_panels_destroy(a);
    vx_display_destroy(a->disp);
    vx_render_image_free(&a->img);
    sv_drop_probes(a);
    sv_drop_passes(a);
    vx_render_scene_destroy(a->rs);
    uint32_t gpu_errors = vx_gpu_validation_errors(a->gpu);
    vx_gpu_destroy(a->gpu);
    /* the window's callbacks point at `a`; the presenter goes last */
    vp_destroy(a->p);
    if (a->o.validate) {
        /* the tracer runs on the window's device, so the window's messenger sees its errors too */
        uint32_t n = a->validation_errors + gpu_errors;
        fprintf(n ? stderr : stdout, "%s: %u Vulkan validation error%s\n", vx_tool_name, n, n == 1 ? "" : "s");
        if (n && !status) status = 1;
    }
    if (a->bake.active) vx_probe_set_free(&a->bake.ps);
    ved_free(&a->ed);
    vx_svo_scene_free(&a->scene);
    vx_free(NULL, a->sky_rgb);
    free(a->px8);
    if (a->lines) free(a->lines[0]), free(a->lines);
    return status;
}

int main(int argc, char** argv) {
    vx_tool_init(argc, argv);
    app a = {0};
    app_init(&a, sv_options_parse(argc, argv));
    if (a.o.verbose)
        printf("%s %s --mode %s --fov %g%s%s%s%s\n", vx_tool_name, a.o.in, sv_mode_name(&a), a.o.fov,
               a.o.screenshot ? " --screenshot " : "", a.o.screenshot ? a.o.screenshot : "",
               a.o.script ? " --script " : "", a.o.script ? a.o.script : "");
    if (a.o.script && sv_script_load(&a)) return 1;
    vx_error err = {0};
    double t0 = vx_time_now();
    if (sv_load_scene(&a.o, a.o.in, &a.scene, &err)) {
        if (a.lines) free(a.lines[0]), free(a.lines);
        return vx_tool_error_budget(a.o.in, &err, &a.budget);
    }
    snprintf(a.scene_file, sizeof a.scene_file, "%s", a.o.in);
    double t_load = vx_time_now() - t0;
    if (a.o.probes && sv_load_probes(&a, a.o.probes, &err)) {
        vx_svo_scene_free(&a.scene);
        if (a.lines) free(a.lines[0]), free(a.lines);
        return vx_tool_errorf("%s", err.msg); /* the message names the file */
    }
    ved_init(&a.ed, &a.scene);
    a.ed.undo_limit = a.o.undo_limit, a.ed.undo_bytes = a.o.undo_bytes;
    a.fps = a.o.fps > 0 ? a.o.fps : a.scene.frame_rate > 0 ? a.scene.frame_rate : SV_FPS_DEFAULT;
    int status = 1;
    char title[512];
    snprintf(title, sizeof title, "svo_view - %s", a.o.in);
    vx_logger logger = {log_cb, NULL};
    vx_gpu_desc gd = {.validate = a.o.validate, .logger = &logger};
    if (vp_create(&(vp_desc){.width = a.o.win_w, .height = a.o.win_h, .title = title, .device = a.o.device,
                             .validate = a.o.validate, .validation_errors = &a.validation_errors,
                             .logger = &logger, .vsync = a.o.vsync, .hidden = a.o.hidden,
                             .batch = a.batch.max},
                  &a.p, &err)) {
        vx_tool_error(a.o.in, &err);
        goto done;
    }
    vp_external(a.p, &gd);
    if (vx_gpu_create(&gd, &a.gpu, &err)) {
        vx_tool_error(a.o.in, &err);
        goto done;
    }
    sv_input_attach(&a, vp_window(a.p));
    if (!a.o.screenshot && !a.o.no_panels) a.panels = sv_panels_create(&a);
    choose_present(&a);
    sv_camera_default(&a);
    sv_rebuild(&a);
    if (!a.rs && (a.o.screenshot || a.o.bench)) goto done; /* the message names the problem */
    if (a.o.verbose) {
        printf("%s: %s: %u models, %u instances (load %.1f ms, scene upload %.1f ms) on %s\n", vx_tool_name, a.o.in,
               a.scene.model_count, a.scene.instance_count, t_load * 1e3, a.update_ms, vx_gpu_device_name(a.gpu));
        printf("%s: present: %s\n", vx_tool_name, a.present_note);
    }
    status = run(&a);
done:
    return app_free(&a, status);
}
