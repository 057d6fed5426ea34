/* tests/render/test_display.c - frames in flight (render/display.h,
 * vx_frame_record): frames recorded one command buffer each and submitted
 * without a wait, VX_DISPLAY_FRAMES in flight, into off-screen images, equal
 * byte for byte to the same frames rendered and converted one at a time with
 * a wait (vx_frame_render + vx_display_run), while the camera and the lights
 * change every frame (each frame must read its own tables), an instance
 * moves between two frames (the scene update waits for the frames in
 * flight), and the overlay is redrawn twice (the two overlays: one drawn
 * while frames in flight read the other). Frame 2 repeats frame 1's camera
 * (the scene's tables are not written again: the frame must still read
 * them), and before frame 8 a frame with frame 8's camera is recorded and
 * cancelled (its tables never written: frame 8 must write them). Three ways
 * to the image: the conversion into a buffer copied to it, the conversion
 * writing it, and the conversion fused into the frame's last pass
 * (vx_display_record_frame). Also: the pass times of a slot's frame once it
 * ran, and the refusals. On lavapipe; skips without a device. */
#include <dlfcn.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <vulkan/vulkan.h> /* image layouts for vx_display_copy_to_image */

#include "render/display.h"
#include "render/gpu.h" /* has_float64 */
#include "render/testing.h" /* vx__render_scene_rows_on_gpu */
#include "render/pipeline.h"
#include "tests/render/scenes.h"
#include "tests/gpu_test.h"
#include "tests/test.h"

static vx_gpu* gpu;
static const char* gpu_skip;

enum { K = 10, W = 64, H = 48 };

/* Frame k's camera (an orbit), lights (intensities change) and overlay pattern. */
static vx_frame_desc frame_k(const vx_svo_scene* s, uint32_t k, vx_light lights[2]) {
    double lo[3], hi[3], c[3], r = 0;
    vx_svo_scene_world_bounds(s, lo, hi);
    for (int i = 0; i < 3; i++) c[i] = 0.5 * (lo[i] + hi[i]), r = fmax(r, hi[i] - lo[i]);
    double a = 0.35 * (k == 2 ? 1 : k); /* frame 2: frame 1's camera */
    vx_frame_desc d = vx_frame_desc_defaults();
    d.base.width = W, d.base.height = H, d.base.mode = VX_RENDER_COLOR;
    d.base.camera = (vx_render_camera){.set = true,
                                       .eye = {c[0] + 1.6 * r * cos(a), c[1] + 1.6 * r * sin(a), c[2] + 0.7 * r},
                                       .target = {c[0], c[1], c[2]},
                                       .up = {0, 0, 1}};
    lights[0] = (vx_light){.type = VX_LIGHT_POINT, .position = {c[0], c[1], hi[2] + 4}, .color = {1, 0.9, 0.8},
                           .intensity = 400 + 60 * k};
    lights[1] = (vx_light){.type = VX_LIGHT_DIRECTIONAL, .direction = {0.3, -0.4, -0.85}, .color = {0.5, 0.6, 1},
                           .intensity = 1 + 0.2 * k};
    d.lights = lights, d.light_count = 2;
    d.no_readback = true;
    return d;
}

static int pattern_of(uint32_t k) { return k < 3 ? 0 : k < 7 ? 1 : 2; }

/* Pattern p: a translucent box (premultiplied), placed by p. */
static bool draw_pattern(vx_display* disp, int p) {
    uint8_t* ov = vx_display_overlay(disp, W, H, NULL);
    if (!ov) return false;
    for (uint32_t y = 4 + 6 * (uint32_t)p; y < 20 + 6 * (uint32_t)p; y++)
        for (uint32_t x = 8 * (uint32_t)p; x < 24 + 8 * (uint32_t)p; x++) {
            uint32_t v = 0xC0000000u | (uint32_t)(0x20 + 0x30 * p) << 16 | 0x1000u | 0x30u;
            memcpy(ov + 4 * ((size_t)y * W + x), &v, 4);
        }
    return true;
}

/* An instance edit: the BVH rebuilt in place (the same instances drawn), with no wait for the frames in flight. */
static void move_instance(vx_svo_scene* s, vx_render_scene* rs, double dx) {
    vx_render_scene_stats a, b;
    vx_render_scene_get_stats(rs, &a);
    s->instances[1].xform[3] += dx;
    vx_svo_scene_update_bounds(s);
    CHECK(vx_render_scene_set_frame(rs, s, 0, NULL) == VX_OK);
    vx_render_scene_get_stats(rs, &b);
    CHECK(b.instance_updates_in_place == a.instance_updates_in_place + 1);
}

/* How the frame gets into the off-screen image: the conversion into a buffer
 * copied to it, the conversion writing the image itself (a storage image),
 * or the frame's last pass writing it (the conversion fused). */
typedef enum way { WAY_COPY, WAY_IMAGE, WAY_FUSED } way;

/* Records frame k (desc d) into the frame begun in cmd, slot. */
static vx_result record_k(way w, vx_display* disp, vx_frame_renderer* fr, const vx_frame_desc* d, void* cmd, uint32_t slot,
                          uint64_t img, vx_frame_result* res, vx_error* err) {
    vx_display_desc dd = {.fr = fr, .width = W, .height = H, .bgra = true, .overlay = true};
    if (w == WAY_FUSED)
        return vx_display_record_frame(disp, fr, d, &dd, img, 0, W, H, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, res, err);
    uint64_t buf = 0;
    vx_result r = vx_frame_record(fr, d, cmd, slot, res, err);
    if (!r && w == WAY_IMAGE)
        r = vx_display_record_image(disp, cmd, &dd, img, 0, W, H, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, err);
    else if (!r)
        r = vx_display_record(disp, cmd, &dd, &buf, err);
    if (r) vx_frame_record_cancel(fr); /* the passes were recorded */
    if (!r && w == WAY_COPY) vx_display_copy_to_image(cmd, buf, W, H, img, W, H, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
    return r;
}

/* The scene, frame renderer and display every case below draws with (the
 * caller destroys them in the reverse order). */
static bool open_chain(const vx_svo_scene* s, vx_render_scene** rs, vx_frame_renderer** fr, vx_display** disp,
                       vx_error* err) {
    *rs = NULL;
    *fr = NULL;
    *disp = NULL;
    return vx_render_scene_create(gpu, s, rs, err) == VX_OK && vx_frame_renderer_create(*rs, s, fr, err) == VX_OK &&
           vx_display_create(gpu, disp, err) == VX_OK;
}

/* batch > 1: frames submitted `batch` at a time (vx_display_set_queue, `frames` in flight); the edit at frame 5
 * submits the held frames itself before it waits for the queue (vx_gpu.held_submit) */
static void in_flight_equals_waited(way wy, uint32_t frames, uint32_t batch, bool one) {
    bool to_image = wy != WAY_COPY;
    vx_svo_model m[2];
    memset(m, 0, sizeof m);
    REQUIRE(ts_random_model(&m[0], 24, 20, 16, 30, 7) == VX_OK);
    REQUIRE(ts_random_model(&m[1], 9, 9, 9, 60, 8) == VX_OK);
    static const double rot[9] = {0, -1, 0, 1, 0, 0, 0, 0, 1};
    vx_svo_instance in[3] = {ts_inst(0, NULL, 0, 0, 0), ts_inst(1, rot, 30, 4, 2), ts_inst(1, NULL, -12, 10, 5)};
    vx_svo_scene s;
    ts_scene(&s, m, 2, in, 3);
    vx_error err = {0};
    vx_render_scene* rs;
    vx_frame_renderer* fr;
    vx_display* disp;
    REQUIRE(open_chain(&s, &rs, &fr, &disp, &err));
    if (to_image && !vx_display_image_storage(disp)) {
        vx_display_destroy(disp);
        vx_frame_renderer_destroy(fr);
        vx_render_scene_destroy(rs);
        vx_svo_scene_free(&s);
        SKIP("the device cannot write B,G,R,A storage images");
    }
    uint64_t img[K];
    for (int k = 0; k < K; k++) REQUIRE(vx_display_image_create(disp, W, H, &img[k], &err) == VX_OK);
    REQUIRE(vx_display_set_queue(disp, frames, batch, one, &err) == VX_OK);
    /* the frames in flight */
    REQUIRE(draw_pattern(disp, 0));
    uint32_t slot_of[K];
    for (uint32_t k = 0; k < K; k++) {
        if (k == 5) move_instance(&s, rs, 7); /* an edit between frames: waits for those in flight */
        if (k == 3 || k == 7) REQUIRE(draw_pattern(disp, pattern_of(k)));
        vx_light lights[2];
        vx_frame_desc d = frame_k(&s, k, lights);
        uint32_t slot;
        void* cmd;
        vx_frame_result res;
        if (k == 8) {
            /* frame 8 recorded and dropped: its tables were never written */
            REQUIRE(vx_display_frame_begin(disp, &slot, &cmd, &err) == VX_OK);
            CHECK(record_k(wy, disp, fr, &d, cmd, slot, img[k], &res, &err) == VX_OK);
            if (wy != WAY_FUSED) vx_frame_record_cancel(fr);
            vx_display_frame_cancel(disp);
        }
        REQUIRE(vx_display_frame_begin(disp, &slot, &cmd, &err) == VX_OK);
        vx_result r = record_k(wy, disp, fr, &d, cmd, slot, img[k], &res, &err);
        if (r) {
            vx_display_frame_cancel(disp);
            CHECKF(false, "frame %u: %s", k, err.msg);
            break;
        }
        CHECK(res.image.pixels == NULL && res.frame_ms == 0);
        REQUIRE(vx_display_frame_submit(disp, 0, 0, &err) == VX_OK);
        slot_of[k] = slot;
    }
    /* the last frame's pass times: the rows of the waited frame, times present */
    REQUIRE(vx_display_wait(disp, &err) == VX_OK);
    vx_display_times dt;
    vx_display_frame_times(disp, &dt);
    CHECKF(dt.frames_done == K, "%llu frames done", (unsigned long long)dt.frames_done);
    vx_frame_result rec_res, ref_res;
    CHECK(vx_frame_record_result(fr, slot_of[K - 1], &rec_res, &err) == VX_OK);
    /* bytes of every frame against the waited path with the same state (moved instance for k >= 5) */
    uint8_t* got = malloc(W * H * 4);
    uint8_t* want = malloc(W * H * 4);
    REQUIRE(got && want);
    size_t bad_total = 0;
    for (int pass = 0; pass < 2; pass++) {
        if (pass == 1) move_instance(&s, rs, -7);
        for (uint32_t k = 0; k < K; k++) {
            if ((k >= 5) != (pass == 0)) continue;
            vx_light lights[2];
            vx_frame_desc d = frame_k(&s, k, lights);
            REQUIRE(draw_pattern(disp, pattern_of(k)));
            vx_display_desc dd = {.fr = fr, .width = W, .height = H, .bgra = true, .overlay = true};
            REQUIRE(vx_frame_render(fr, &d, &ref_res, &err) == VX_OK);
            REQUIRE(vx_display_run(disp, &dd, want, NULL, &err) == VX_OK);
            REQUIRE(vx_display_image_read(disp, img[k], W, H, got, &err) == VX_OK);
            size_t bad = 0, lit = 0;
            for (size_t q = 0; q < (size_t)W * H * 4; q++) bad += got[q] != want[q];
            for (size_t q = 0; q < (size_t)W * H; q++) lit += want[4 * q] != want[4 * q + 1];
            printf("  frame %u in flight (slot %u, overlay %d%s): %zu of %d bytes differ from the waited path\n", k,
                   slot_of[k], pattern_of(k), k >= 5 ? ", instance moved" : "", bad, W * H * 4);
            CHECKF(bad == 0, "frame %u: %zu bytes differ", k, bad);
            CHECKF(lit > 0, "frame %u: a flat image", k);
            bad_total += bad;
        }
    }
    /* the frames differ from one another (the test would not see a frame reading another's tables otherwise) */
    uint8_t* other = malloc(W * H * 4);
    REQUIRE(other);
    REQUIRE(vx_display_image_read(disp, img[0], W, H, got, &err) == VX_OK);
    REQUIRE(vx_display_image_read(disp, img[1], W, H, other, &err) == VX_OK);
    CHECK(memcmp(got, other, W * H * 4) != 0);
    /* the recorded frame's rows are the waited frame's (last reference: frame 4, same pass list) */
    CHECKF(rec_res.timing_count == ref_res.timing_count && rec_res.timing_count > 0, "rows %u vs %u",
           rec_res.timing_count, ref_res.timing_count);
    for (uint32_t t = 0; t < rec_res.timing_count && t < ref_res.timing_count; t++)
        CHECK(!strcmp(rec_res.timings[t].name, ref_res.timings[t].name));
    CHECK(rec_res.frame_ms >= 0 && rec_res.image.rays == (uint64_t)W * H);
    printf("  %d frames (%u in flight, %u a submission%s, %s): %zu bytes differ in all; last frame's passes %.3f ms (waited: %.3f ms), "
           "its command buffer %.3f ms on the device\n",
           K, frames ? frames : VX_DISPLAY_FRAMES, batch ? batch : 1, one ? " in one VkSubmitInfo" : "",
           wy == WAY_FUSED ? "fused into the last pass" : to_image ? "written into the image" : "copied to the image",
           bad_total, rec_res.frame_ms,
           ref_res.frame_ms, dt.gpu_ms);
    free(got), free(want), free(other);
    /* refusals: nothing is recorded, the frame is dropped */
    {
        uint32_t slot;
        void* cmd;
        REQUIRE(vx_display_frame_begin(disp, &slot, &cmd, &err) == VX_OK);
        vx_light lights[2];
        vx_frame_desc d = frame_k(&s, 0, lights);
        vx_frame_result res;
        d.want_ids = true;
        CHECK(vx_frame_record(fr, &d, cmd, slot, &res, &err) == VX_ERR_UNSUPPORTED);
        d.want_ids = false, d.no_readback = false;
        CHECK(vx_frame_record(fr, &d, cmd, slot, &res, &err) == VX_ERR_UNSUPPORTED);
        d.no_readback = true;
        CHECK(vx_frame_record(fr, &d, cmd, VX_FRAME_SLOTS, &res, &err) == VX_ERR_INVALID_ARG);
        CHECK(vx_frame_record_result(fr, slot, &res, &err) == VX_ERR_INVALID_ARG); /* the refused frame left nothing */
        CHECK(vx_display_frame_begin(disp, &slot, &cmd, &err) == VX_ERR_INVALID_ARG); /* one frame at a time */
        vx_display_frame_cancel(disp);
        CHECK(vx_display_frame_submit(disp, 0, 0, &err) == VX_ERR_INVALID_ARG);
    }
    vx_display_destroy(disp);
    vx_frame_renderer_destroy(fr);
    vx_render_scene_destroy(rs);
    vx_svo_scene_free(&s);
    /* with VX_GPU_VALIDATION=1 (and the layer's synchronization validation enabled) nothing was reported */
    CHECKF(vx_gpu_validation_errors(gpu) == 0, "%u validation errors", vx_gpu_validation_errors(gpu));
}

/* Instance moves with frames in flight: the BVH keeps its shape and is refit
 * (on the host for waited frames, on the GPU level by level for recorded
 * ones); every recorded frame equals the same frame of a render scene built
 * from scratch (an SAH build over the moved instances: another tree, the
 * same nearest hits), and so does the waited frame after the moves. Eight
 * steps over 48 instances in a grid, a few moved each step (one of them far,
 * so the refit boxes grow and overlap), the camera orbiting and then, from
 * step STILL on, still: those frames write only the rows of the instance
 * table and of the boxes that changed (vx_render_scene_stats
 * table_rows_uploaded), and must still equal the scenes built from scratch.
 * Twice: with the instance rows computed on the GPU from the rows relative
 * to the world (shaders/inst_rows.comp, where the device has float64: the
 * default), where the orbiting camera's frames write no row but the moved
 * instances' sources, and with the host's rows (frame_tables), where they
 * write every row and box; the scenes built from scratch render with the
 * host's rows (waited frames), so the GPU's rows must be the host's bit for
 * bit. */
enum { RN = 48, STEPS = 8, STILL = 5 };

/* Step k's camera: the orbit's, held from step STILL on. */
static uint32_t cam_of(uint32_t k) { return k < STILL ? k : STILL; }

static void refit_equals_scratch(bool rows_on_gpu) {
    vx_svo_model m[2];
    memset(m, 0, sizeof m);
    REQUIRE(ts_random_model(&m[0], 8, 7, 6, 40, 11) == VX_OK);
    REQUIRE(ts_random_model(&m[1], 5, 5, 9, 55, 12) == VX_OK);
    vx_svo_instance in[RN];
    /* 30 cells apart, moves of at most 2 cells a step (and one of 60 up, out of the grid): no two instances meet,
     * so the nearest hit never ties between instances (which a different tree could then break otherwise) */
    for (uint32_t i = 0; i < RN; i++) in[i] = ts_inst(i % 2, NULL, 30.0 * (i % 8), 30.0 * (i / 8 % 3), 30.0 * (i / 24));
    vx_svo_scene s;
    ts_scene(&s, m, 2, in, RN);
    vx_error err = {0};
    vx_render_scene* rs;
    vx_frame_renderer* fr;
    vx_display* disp;
    REQUIRE(open_chain(&s, &rs, &fr, &disp, &err));
    vx__render_scene_rows_on_gpu(rs, rows_on_gpu);
    uint64_t img[STEPS];
    for (int k = 0; k < STEPS; k++) REQUIRE(vx_display_image_create(disp, W, H, &img[k], &err) == VX_OK);
    double xf[STEPS][RN][3]; /* the translations at each step */
    uint32_t seed = 5;
    vx_render_scene_stats st0, st1, still0 = {0}, from2 = {0};
    vx_render_scene_get_stats(rs, &st0);
    REQUIRE(draw_pattern(disp, 0)); /* record_k lays the overlay over the frames */
    for (uint32_t k = 0; k < STEPS; k++) {
        if (k) {
            for (int j = 0; j < 4; j++) {
                seed = seed * 1664525u + 1013904223u;
                uint32_t i = (seed >> 8) % RN;
                bool far = j == 0 && k == 3;
                double d = far ? 60 : (double)((seed >> 20) % 5) - 2;
                s.instances[i].xform[3 + 4 * (far ? 2 : (int)((seed >> 4) % 3))] += d;
            }
            vx_svo_scene_update_bounds(&s);
            REQUIRE(vx_render_scene_set_frame(rs, &s, 0, &err) == VX_OK);
        }
        for (uint32_t i = 0; i < RN; i++)
            for (int c = 0; c < 3; c++) xf[k][i][c] = s.instances[i].xform[3 + 4 * c];
        vx_light lights[2];
        vx_frame_desc d = frame_k(&s, cam_of(k), lights);
        if (k == STILL + 1) vx_render_scene_get_stats(rs, &still0); /* the frames after the camera stopped */
        if (k == 2) vx_render_scene_get_stats(rs, &from2); /* after the first frames (whole tables, then the refit's) */
        uint32_t slot;
        void* cmd;
        vx_frame_result res;
        REQUIRE(vx_display_frame_begin(disp, &slot, &cmd, &err) == VX_OK);
        if (record_k(WAY_COPY, disp, fr, &d, cmd, slot, img[k], &res, &err)) {
            vx_display_frame_cancel(disp);
            CHECKF(false, "step %u: %s", k, err.msg);
            break;
        }
        REQUIRE(vx_display_frame_submit(disp, 0, 0, &err) == VX_OK);
    }
    REQUIRE(vx_display_wait(disp, &err) == VX_OK);
    vx_render_scene_get_stats(rs, &st1);
    uint32_t refits = st1.instance_refits - st0.instance_refits;
    CHECKF(refits >= STEPS - 2, "%u of %d moves refit the BVH", refits, STEPS - 1);
    /* the still camera's frames: a few moved instances' rows and boxes (4 moves a step, runs merged across at
     * most 3 unchanged rows: at most 13 rows of each table), not the 2 x 48 of a whole upload */
    uint64_t rows = st1.table_rows_uploaded - still0.table_rows_uploaded, steps = STEPS - STILL - 1;
    printf("  %llu table rows written by the %llu frames with a still camera (%llu for whole tables)\n",
           (unsigned long long)rows, (unsigned long long)steps, (unsigned long long)(steps * 2 * RN));
    CHECKF(rows > 0 && rows <= steps * 2 * 13, "%llu rows written", (unsigned long long)rows);
    uint64_t later = st1.table_rows_uploaded - from2.table_rows_uploaded;
    printf("  rows %s: %llu table rows written by frames 2-%d (the camera orbits up to %d)\n",
           rows_on_gpu ? "on the GPU" : "from the host", (unsigned long long)later, STEPS - 1, STILL);
    if (rows_on_gpu) /* the moved instances' sources (at most 13 a step): the camera writes none */
        CHECKF(later > 0 && later <= (uint64_t)(STEPS - 2) * 13, "the frames wrote %llu rows", (unsigned long long)later);
    else /* every row and box while the camera moves */
        CHECKF(later >= (uint64_t)(STILL - 2) * 2 * RN, "the orbiting camera's frames wrote %llu rows",
               (unsigned long long)later);
    /* each step against a scene built from scratch with that step's instances */
    uint8_t *got = malloc(W * H * 4), *want = malloc(W * H * 4);
    REQUIRE(got && want);
    size_t bad_total = 0;
    for (uint32_t k = 0; k < STEPS; k++) {
        for (uint32_t i = 0; i < RN; i++)
            for (int c = 0; c < 3; c++) s.instances[i].xform[3 + 4 * c] = xf[k][i][c];
        vx_svo_scene_update_bounds(&s);
        vx_render_scene* rs2 = NULL;
        vx_frame_renderer* fr2 = NULL;
        REQUIRE(vx_render_scene_create(gpu, &s, &rs2, &err) == VX_OK);
        REQUIRE(vx_frame_renderer_create(rs2, &s, &fr2, &err) == VX_OK);
        vx_light lights[2];
        vx_frame_desc d = frame_k(&s, cam_of(k), lights);
        vx_frame_result res;
        vx_display_desc dd = {.fr = fr2, .width = W, .height = H, .bgra = true, .overlay = true};
        REQUIRE(vx_frame_render(fr2, &d, &res, &err) == VX_OK);
        REQUIRE(vx_display_run(disp, &dd, want, NULL, &err) == VX_OK);
        REQUIRE(vx_display_image_read(disp, img[k], W, H, got, &err) == VX_OK);
        size_t bad = 0, hit = 0;
        for (size_t q = 0; q < (size_t)W * H * 4; q++) bad += got[q] != want[q];
        for (size_t q = 0; q < (size_t)W * H; q++) hit += memcmp(want + 4 * q, want, 4) != 0; /* not the corner's sky */
        if (k == STEPS - 1) {
            /* the waited frame of the moved scene (the host's refit tree) too */
            vx_display_desc d1 = dd;
            d1.fr = fr;
            REQUIRE(vx_frame_render(fr, &d, &res, &err) == VX_OK);
            REQUIRE(vx_display_run(disp, &d1, got, NULL, &err) == VX_OK);
            for (size_t q = 0; q < (size_t)W * H * 4; q++) bad += got[q] != want[q];
        }
        printf("  step %u: refit frame against a scene built from scratch: %zu bytes differ (%zu pixels not the sky's)\n",
               k, bad, hit);
        CHECKF(bad == 0, "step %u: %zu bytes differ", k, bad);
        CHECKF(hit > 0, "step %u: a flat image", k);
        bad_total += bad;
        vx_frame_renderer_destroy(fr2);
        vx_render_scene_destroy(rs2);
    }
    printf("  %d steps, %u refits: %zu bytes differ in all\n", STEPS, refits, bad_total);
    free(got), free(want);
    vx_display_destroy(disp);
    vx_frame_renderer_destroy(fr);
    vx_render_scene_destroy(rs);
    vx_svo_scene_free(&s);
    CHECKF(vx_gpu_validation_errors(gpu) == 0, "%u validation errors", vx_gpu_validation_errors(gpu));
}

static void test_refit_equals_scratch(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    refit_equals_scratch(false);
    if (!gpu->has_float64) SKIP("%s has no float64 shaders: the instance rows stay the host's", vx_gpu_device_name(gpu));
    refit_equals_scratch(true);
}

static void test_in_flight_equals_waited(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    in_flight_equals_waited(WAY_COPY, 0, 0, false);
}

static void test_in_flight_into_image(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    in_flight_equals_waited(WAY_IMAGE, 0, 0, false);
}

static void test_in_flight_fused(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    in_flight_equals_waited(WAY_FUSED, 0, 0, false);
}

/* Frames submitted several at a time (vx_display_set_queue): the same bytes, frame by frame. Batches of 3 of 6
 * in flight in one VkSubmitInfo (the dropped frame 8 and the overlay redrawn at 3 and 7 fall inside batches),
 * and of 2 of 3 (a batch wrapping round the slots), each frame its own VkSubmitInfo. */
static void test_in_flight_batched(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    in_flight_equals_waited(WAY_FUSED, 6, 3, true);
    in_flight_equals_waited(WAY_COPY, 3, 2, false);
}

/* Frames held for a batch (vx_display_set_queue) when a model is edited: the
 * edit's wait for the queue submits them first (vx_gpu.held_submit), so they
 * show the model as it was when they were recorded, and the frame after the
 * edit shows the new one. Without that the held frames would run after the
 * edit's writes (lavapipe writes the mapped buffers in place) and show the
 * new model. */
static void test_batched_model_edit(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    vx_svo_model m[2];
    memset(m, 0, sizeof m);
    REQUIRE(ts_random_model(&m[0], 16, 16, 12, 35, 21) == VX_OK);
    REQUIRE(ts_random_model(&m[1], 16, 16, 12, 35, 22) == VX_OK); /* the same size, other cells */
    vx_svo_instance in[1] = {ts_inst(0, NULL, 0, 0, 0)};
    vx_svo_scene s;
    ts_scene(&s, m, 1, in, 1);
    vx_error err = {0};
    vx_render_scene* rs;
    vx_frame_renderer* fr;
    vx_display* disp;
    REQUIRE(open_chain(&s, &rs, &fr, &disp, &err));
    uint64_t img[3];
    for (int k = 0; k < 3; k++) REQUIRE(vx_display_image_create(disp, W, H, &img[k], &err) == VX_OK);
    REQUIRE(draw_pattern(disp, 1));
    vx_light lights[2];
    vx_frame_desc d = frame_k(&s, 1, lights);
    vx_display_desc dd = {.fr = fr, .width = W, .height = H, .bgra = true, .overlay = true};
    uint8_t *before = malloc(W * H * 4), *after = malloc(W * H * 4), *got = malloc(W * H * 4);
    REQUIRE(before && after && got);
    vx_frame_result res;
    REQUIRE(vx_frame_render(fr, &d, &res, &err) == VX_OK);
    REQUIRE(vx_display_run(disp, &dd, before, NULL, &err) == VX_OK);
    REQUIRE(vx_display_set_queue(disp, 6, 3, false, &err) == VX_OK);
    way wy = vx_display_image_storage(disp) ? WAY_FUSED : WAY_COPY;
    for (int k = 0; k < 3; k++) {
        if (k == 2) { /* the edit: model 0's octree replaced by another's, every word uploaded again */
            vx_svo_model keep = s.models[0];
            s.models[0] = m[1], m[1] = keep;
            REQUIRE(vx_render_scene_update_model(rs, &s, 0, 0, 0, &err) == VX_OK);
        }
        uint32_t slot;
        void* cmd;
        REQUIRE(vx_display_frame_begin(disp, &slot, &cmd, &err) == VX_OK);
        REQUIRE(record_k(wy, disp, fr, &d, cmd, slot, img[k], &res, &err) == VX_OK);
        REQUIRE(vx_display_frame_submit(disp, 0, 0, &err) == VX_OK);
    }
    REQUIRE(vx_display_wait(disp, &err) == VX_OK);
    REQUIRE(vx_frame_render(fr, &d, &res, &err) == VX_OK);
    REQUIRE(vx_display_run(disp, &dd, after, NULL, &err) == VX_OK);
    size_t changed = 0;
    for (size_t q = 0; q < (size_t)W * H * 4; q++) changed += before[q] != after[q];
    CHECKF(changed > 0, "the edit changed no byte of the frame");
    for (int k = 0; k < 3; k++) {
        REQUIRE(vx_display_image_read(disp, img[k], W, H, got, &err) == VX_OK);
        const uint8_t* want = k < 2 ? before : after;
        size_t bad = 0;
        for (size_t q = 0; q < (size_t)W * H * 4; q++) bad += got[q] != want[q];
        printf("  held frame %d (%s the edit): %zu of %d bytes differ (the edit changed %zu)\n", k, k < 2 ? "before" : "after",
               bad, W * H * 4, changed);
        CHECKF(bad == 0, "frame %d: %zu bytes differ", k, bad);
    }
    free(before), free(after), free(got);
    vx_display_destroy(disp);
    vx_frame_renderer_destroy(fr);
    vx_render_scene_destroy(rs);
    vx_svo_model_free(NULL, &m[1]);
    vx_svo_scene_free(&s);
    CHECKF(vx_gpu_validation_errors(gpu) == 0, "%u validation errors", vx_gpu_validation_errors(gpu));
}

int main(void) {
    gpu_skip = vx_test_gpu_open((vx_gpu_desc){0}, false, &gpu);
    RUN(test_in_flight_equals_waited);
    RUN(test_in_flight_into_image);
    RUN(test_in_flight_fused);
    RUN(test_in_flight_batched);
    RUN(test_batched_model_edit);
    RUN(test_refit_equals_scratch);
    vx_gpu_destroy(gpu);
    return vx_test_finish();
}
