/* tests/view/test_ui_gpu.c - svo_view's panels drawn on the GPU
 * (tools/svo_view/ui.h ui_gpu_record: Dear ImGui's Vulkan backend over the
 * frame the tracer's last pass wrote, in the same command buffer) against
 * two independent paths: the same frame without panels (every byte outside
 * the panels' windows must be the tracer's, and inside them the panels
 * must show), and the same draw lists rasterized on the CPU (ui_draw_cpu,
 * the viewer's own triangle rasterizer) over that frame (the panels' pixels
 * must agree up to the two rasterizers' sampling: the GPU filters the font
 * atlas linearly, the CPU takes the nearest texel). Then frames in flight,
 * each with panels, rotating the frame slots and the backend's buffers: the
 * last equals the single frame byte for byte. Under the validation layer
 * where installed (no message allowed). On lavapipe; skips without a
 * device or without storage images. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <vulkan/vulkan.h>

#include "render/display.h"
#include "render/gpu.h"
#include "render/pipeline.h"
#include "tests/gpu_test.h"
#include "tests/render/scenes.h"
#include "tests/test.h"
#include "tools/svo_view/ui.h"

static vx_gpu* gpu;
static const char* gpu_skip;

enum { W = 200, H = 150, FLIGHT = 7 };

/* The panels' windows (x, y, w, h): placed where the scene is, one partly off the frame's edge. */
static const float win[3][4] = {{6, 6, 84, 70}, {110, 60, 80, 64}, {150, 128, 70, 40}};

static void panels(ui* u) {
    ui_frame_begin(u, W, H, 1.0 / 60);
    if (ui_window_begin("Outliner", win[0][0], win[0][1], win[0][2], win[0][3])) {
        ui_text("instances 3");
        bool v = true;
        ui_checkbox("visible", &v);
        ui_button("Save");
    }
    ui_window_end();
    if (ui_window_begin("Stats", win[1][0], win[1][1], win[1][2], win[1][3])) {
        static const float bars[8] = {1, 2, 2, 1, 3, 1, 2, 2};
        static const uint32_t colours[2] = {0x3080F0u, 0x40C040u};
        ui_text("0.12 ms");
        ui_stacked_bars(bars, 4, 2, 2, colours, 2, 5, 20);
        ui_progress(0.4f, "bake");
    }
    ui_window_end();
    if (ui_window_begin("Edge", win[2][0], win[2][1], win[2][2], win[2][3])) ui_text("clipped");
    ui_window_end();
    ui_frame_end(u, NULL);
}

/* Whether pixel (x, y) is within `margin` pixels of a panel window. */
static bool near_panel(uint32_t x, uint32_t y, float margin) {
    for (int i = 0; i < 3; i++)
        if (x + 0.5f >= win[i][0] - margin && x + 0.5f < win[i][0] + win[i][2] + margin && y + 0.5f >= win[i][1] - margin &&
            y + 0.5f < win[i][1] + win[i][3] + margin)
            return true;
    return false;
}

/* One frame into img (fused: the last pass writes it), with the panels drawn over it or not, submitted; *slot its slot. */
static bool frame(vx_display* disp, vx_frame_renderer* fr, const vx_frame_desc* fd, ui* u, uint64_t img, bool with_panels,
                  uint32_t* slot) {
    vx_error err = {0};
    void* cmd;
    if (vx_display_frame_begin(disp, slot, &cmd, &err)) return fprintf(stderr, "%s\n", err.msg), false;
    vx_display_desc dd = {.fr = fr, .width = W, .height = H, .bgra = true};
    vx_frame_result res;
    int layout = with_panels ? VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL : VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
    if (vx_display_record_frame(disp, fr, fd, &dd, img, 0, W, H, layout, &res, &err)) {
        fprintf(stderr, "%s\n", err.msg);
        vx_display_frame_cancel(disp);
        return false;
    }
    char why[256];
    if (with_panels && !ui_gpu_record(u, cmd, *slot, vx_display_image_view(disp, img), W, H, why, sizeof why)) {
        fprintf(stderr, "%s\n", why);
        vx_display_frame_cancel(disp);
        return false;
    }
    return !vx_display_frame_submit(disp, 0, 0, &err);
}

static void test_panels_on_gpu(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    vx_svo_model m[2];
    memset(m, 0, sizeof m);
    REQUIRE(ts_random_model(&m[0], 24, 20, 16, 40, 3) == VX_OK);
    REQUIRE(ts_random_model(&m[1], 9, 9, 9, 60, 4) == VX_OK);
    vx_svo_instance in[2] = {ts_inst(0, NULL, 0, 0, 0), ts_inst(1, NULL, 26, 4, 2)};
    vx_svo_scene s;
    ts_scene(&s, m, 2, in, 2);
    vx_error err = {0};
    vx_render_scene* rs = NULL;
    vx_frame_renderer* fr = NULL;
    vx_display* disp = NULL;
    REQUIRE(vx_render_scene_create(gpu, &s, &rs, &err) == VX_OK);
    REQUIRE(vx_frame_renderer_create(rs, &s, &fr, &err) == VX_OK);
    REQUIRE(vx_display_create(gpu, &disp, &err) == VX_OK);
    if (!vx_display_image_storage(disp)) {
        vx_display_destroy(disp);
        vx_frame_renderer_destroy(fr);
        vx_render_scene_destroy(rs);
        vx_svo_scene_free(&s);
        SKIP("the device cannot write B,G,R,A storage images");
    }
    uint64_t img[VX_DISPLAY_FRAMES];
    for (int i = 0; i < VX_DISPLAY_FRAMES; i++) REQUIRE(vx_display_image_create(disp, W, H, &img[i], &err) == VX_OK);
    REQUIRE(vx_display_image_view(disp, img[0]) != 0);
    CHECK(vx_display_image_view(disp, 12345) == 0);
    ui* u = ui_create();
    REQUIRE(u);
    char why[256] = "";
    ui_gpu_desc gd = {.instance = gpu->instance, .phys = gpu->phys, .device = gpu->device, .queue = gpu->queue,
                      .queue_family = gpu->queue_family, .final_layout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                      .frames = VX_DISPLAY_FRAMES};
    CHECKF(ui_gpu_init(u, &gd, why, sizeof why), "%s", why);
    REQUIRE(ui_gpu_ready(u));
    CHECK(!ui_gpu_init(u, &gd, why, sizeof why)); /* made already */
    panels(u);
    panels(u); /* the second frame: the windows placed and sized as on every later one */

    double lo[3], hi[3], c[3], r = 0;
    vx_svo_scene_world_bounds(&s, lo, hi);
    for (int i = 0; i < 3; i++) c[i] = 0.5 * (lo[i] + hi[i]), r = fmax(r, hi[i] - lo[i]);
    vx_frame_desc fd = vx_frame_desc_defaults();
    fd.base.width = W, fd.base.height = H, fd.base.mode = VX_RENDER_COLOR;
    fd.base.camera = (vx_render_camera){.set = true, .eye = {c[0] + 0.9 * r, c[1] - 0.8 * r, c[2] + 0.5 * r},
                                        .target = {c[0], c[1], c[2]}, .up = {0, 0, 1}};
    fd.no_readback = true;
    size_t n = (size_t)W * H * 4;
    uint8_t *scene = malloc(n), *gpu_px = malloc(n), *cpu_px = malloc(n), *last = malloc(n);
    REQUIRE(scene && gpu_px && cpu_px && last);
    uint32_t slot;
    REQUIRE(frame(disp, fr, &fd, u, img[0], false, &slot));
    REQUIRE(vx_display_image_read(disp, img[0], W, H, scene, &err) == VX_OK);
    REQUIRE(frame(disp, fr, &fd, u, img[1], true, &slot));
    REQUIRE(vx_display_image_read(disp, img[1], W, H, gpu_px, &err) == VX_OK);
    /* the CPU's rasterizer over the scene's bytes: the same draw lists */
    memcpy(cpu_px, scene, n);
    vf_canvas cv = {.pixels = cpu_px, .width = W, .height = H, .bgra = true};
    ui_draw_cpu(u, &cv);

    size_t outside = 0, outside_bad = 0, inside = 0, shown = 0, cmp = 0, far = 0, hit = 0;
    double sum = 0;
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++) {
            size_t q = 4 * ((size_t)y * W + x);
            hit += scene[q] != scene[0] || scene[q + 1] != scene[1] || scene[q + 2] != scene[2];
            if (!near_panel(x, y, 2)) { /* the scene's pixels: the tracer's bytes, all four */
                outside++;
                outside_bad += memcmp(scene + q, gpu_px + q, 4) != 0;
                continue;
            }
            int dmax = 0;
            for (int k = 0; k < 3; k++) {
                int dg = abs((int)gpu_px[q + k] - (int)cpu_px[q + k]);
                sum += dg, dmax = dg > dmax ? dg : dmax;
            }
            cmp++;
            far += dmax > 32;
            if (near_panel(x, y, -2)) {
                inside++;
                shown += memcmp(scene + q, gpu_px + q, 3) != 0;
            }
        }
    double mean = cmp ? sum / (3.0 * cmp) : 0;
    printf("  scene pixels outside the panels: %zu, %zu differ; inside: %zu, %zu show the panels; against the CPU "
           "rasterizer: mean |diff| %.3f, %zu of %zu pixels off by more than 32\n",
           outside, outside_bad, inside, shown, mean, far, cmp);
    CHECKF(hit > n / 4 / 10, "the scene covers %zu pixels: too flat a test", hit);
    CHECKF(outside > n / 4 / 3 && outside_bad == 0, "%zu of %zu scene pixels changed", outside_bad, outside);
    CHECKF(shown > inside * 95 / 100, "the panels show in %zu of %zu pixels", shown, inside);
    /* the two rasterizers: the same triangles, colours and blend; text edges differ by the font's filtering */
    CHECKF(mean < 2.0, "mean |GPU - CPU| %.3f", mean);
    CHECKF(far < cmp / 50, "%zu of %zu pixels differ by more than 32", far, cmp);

    /* frames in flight, each with the panels: slots, framebuffers and the backend's buffers rotate */
    uint32_t last_slot = 0;
    for (int k = 0; k < FLIGHT; k++) {
        uint32_t sl, want = (uint32_t)(k + 2) % VX_DISPLAY_FRAMES; /* slots take turns: the image of the slot */
        REQUIRE(frame(disp, fr, &fd, u, img[want], true, &sl));
        CHECK(sl == want);
        last_slot = want;
    }
    REQUIRE(vx_display_image_read(disp, img[last_slot], W, H, last, &err) == VX_OK);
    size_t diff = 0;
    for (size_t q = 0; q < n; q++) diff += last[q] != gpu_px[q];
    printf("  %d frames in flight with the panels: the last differs from the single frame in %zu bytes\n", FLIGHT, diff);
    CHECKF(diff == 0, "%zu bytes differ", diff);

    REQUIRE(vx_display_wait(disp, &err) == VX_OK);
    ui_gpu_shutdown(u);
    CHECK(!ui_gpu_ready(u));
    ui_destroy(u);
    free(scene), free(gpu_px), free(cpu_px), free(last);
    vx_display_destroy(disp);
    vx_frame_renderer_destroy(fr);
    vx_render_scene_destroy(rs);
    vx_svo_scene_free(&s);
    CHECKF(vx_gpu_validation_errors(gpu) == 0, "%u validation errors", vx_gpu_validation_errors(gpu));
}

int main(void) {
    gpu_skip = vx_test_gpu_open((vx_gpu_desc){0}, true, &gpu);
    RUN(test_panels_on_gpu);
    vx_gpu_destroy(gpu);
    return vx_test_finish();
}
