/* tests/render/test_render_hits.c - the per-pixel hits frame (want_hits,
 * what svo_view's picking uses) on a deep terrain-like scene (the bench's
 * 4096^3 terrain, 12 levels) from oblique and grazing views: it returns in
 * under a second on a real GPU, and its hits agree with the depth frame
 * (same instance or miss, same t) and with the colour frame's hits, and the
 * beam pass (vx_render_desc.beam 8, over this scene's two-frame walk,
 * DEEP 2, and its far pointers) changes no hit: the depth+hits frame
 * with it holds the same instance, cell and t bits as without.
 * Issue 21: this frame hung on an NVIDIA H100 (it took 0.6 s on lavapipe).
 *
 *   test_render_hits [WxH] [--mode color|depth] [--no-hits] [--view N]
 *
 * Without arguments: 1920x1080 on a GPU, 192x108 on a CPU device (lavapipe).
 * The arguments run one frame only and print its time (for diagnosis on the
 * GPU machine). A frame that does not return within 60 s ends the process. */
#include <dlfcn.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "bench/bench_terrain.h"
#include "render/render.h"
#include "svo/core.h"
#include "tests/test.h"
#include "tests/gpu_test.h"

static vx_gpu* gpu;
static const char* gpu_skip;
static vx_svo_scene terrain;
static bool have_terrain;

static void on_alarm(int sig) {
    (void)sig;
    static const char msg[] = "test_render_hits: a frame did not return within 60 s (GPU hang)\n";
    ssize_t w = write(2, msg, sizeof msg - 1);
    (void)w;
    _exit(1);
}

/* Oblique from above a corner, low over the ground, and grazing along it. */
static vx_render_camera view(int i) {
    static const double v[][6] = {
        {-600, -900, 3600, 2048, 2048, 1400},
        {300, 200, 2700, 3200, 3000, 1500},
        {-200, 2048, 2300, 4096, 2048, 1900},
    };
    vx_render_camera c = {.set = true};
    for (int k = 0; k < 3; k++) c.eye[k] = v[i][k], c.target[k] = v[i][3 + k];
    return c;
}

static int frame(vx_render_scene* rs, uint32_t w, uint32_t h, vx_render_mode mode, bool hits, int vi,
                 vx_render_image* img, double* wall) {
    vx_error err = {0};
    /* mode | 0x100: with the beam pass (blocks of 8 pixels) */
    vx_render_desc d = {.width = w, .height = h, .mode = mode & 0xFF, .camera = view(vi), .want_hits = hits,
                        .beam = mode & 0x100 ? 8 : 0};
    alarm(60);
    double t0 = vx_time_now();
    vx_result r = vx_render_frame(rs, &d, img, &err);
    *wall = vx_time_now() - t0;
    alarm(0);
    if (r) fprintf(stderr, "frame: %s\n", err.msg);
    return r != VX_OK;
}

static bool prepare(void) {
    if (have_terrain) return true;
    vx_error err = {0};
    if (bench_terrain(&terrain, 4096, 0, &err)) {
        fprintf(stderr, "terrain: %s\n", err.msg);
        return false;
    }
    have_terrain = true;
    return true;
}

static void test_hits_frame(void) {
    if (gpu_skip) SKIP("%s", gpu_skip);
    REQUIRE(prepare());
    bool cpu = vx_gpu_is_cpu(gpu);
    uint32_t w = cpu ? 192 : 1920, h = cpu ? 108 : 1080;
    vx_error err = {0};
    vx_render_scene* rs = NULL;
    REQUIRE(vx_render_scene_create(gpu, &terrain, &rs, &err) == VX_OK);
    for (int vi = 0; vi < 3; vi++) {
        vx_render_image dep = {0}, col = {0}, dh = {0}, nb = {0};
        double t_dep = 0, t_col = 0, t_dh = 0, t_nb = 0;
        bool ok = !frame(rs, w, h, VX_RENDER_DEPTH, false, vi, &dep, &t_dep) &&
                  !frame(rs, w, h, VX_RENDER_COLOR, true, vi, &col, &t_col) &&
                  !frame(rs, w, h, VX_RENDER_DEPTH, true, vi, &dh, &t_dh) &&
                  !frame(rs, w, h, (vx_render_mode)(VX_RENDER_DEPTH | 0x100), true, vi, &nb, &t_nb);
        CHECKF(ok, "view %d: frames failed", vi);
        if (ok) {
            size_t n = (size_t)w * h, hit = 0, bad = 0, bad_col = 0, bad_beam = 0;
            for (size_t i = 0; i < n; i++) {
                float t = dep.pixels[4 * i];
                const vx_render_hit* a = &col.hits[i];
                bool miss = a->instance == VX_RENDER_NO_HIT;
                hit += !miss;
                if (miss ? isfinite(t) : !(fabsf(a->t - t) <= 1e-5f * fmaxf(t, 1.0f))) {
                    if (bad < 5)
                        fprintf(stderr, "  view %d pixel %zu,%zu: hits inst %d t %.7g, depth frame %.7g\n", vi, i % w,
                                i / w, (int)a->instance, a->t, t);
                    bad++;
                }
                /* the two specialisations may round t differently (contractions) */
                const vx_render_hit* b = &dh.hits[i];
                if (b->instance != a->instance ||
                    (!miss && (!(fabsf(b->t - a->t) <= 1e-5f * fmaxf(a->t, 1.0f)) || memcmp(b->cell, a->cell, sizeof a->cell))))
                    bad_col++;
                const vx_render_hit* c = &nb.hits[i];
                bad_beam += c->instance != b->instance || memcmp(c->cell, b->cell, sizeof c->cell) ||
                            memcmp(&c->t, &b->t, sizeof c->t);
            }
            printf("view %d %ux%u: %.1f%% hits; depth %.3f s, colour+hits %.3f s, depth+hits %.3f s (beam %.3f s) wall; "
                   "%zu pixels differ from depth, %zu between the two hits frames, %zu with the beam\n",
                   vi, w, h, 100.0 * hit / n, t_dep, t_col, t_dh, t_nb, bad, bad_col, bad_beam);
            CHECKF(hit > n / 4, "view %d: only %zu hits", vi, hit);
            CHECKF(bad <= n / 10000, "view %d: %zu pixels differ from the depth frame", vi, bad);
            CHECKF(bad_col <= n / 10000, "view %d: %zu pixels differ between the colour and depth hits", vi, bad_col);
            CHECKF(bad_beam == 0, "view %d: %zu pixels differ with the beam pass", vi, bad_beam);
            /* the frame includes the readback of 66 MB of hits at 1920x1080 */
            if (!cpu) CHECKF(t_col < 1.0 && t_dh < 1.0, "view %d: hits frames took %.2f s and %.2f s", vi, t_col, t_dh);
        }
        vx_render_image_free(&dep);
        vx_render_image_free(&col);
        vx_render_image_free(&dh);
        vx_render_image_free(&nb);
    }
    vx_render_scene_destroy(rs);
    CHECK(vx_gpu_validation_errors(gpu) == 0);
}

int main(int argc, char** argv) {
    signal(SIGALRM, on_alarm);
    uint32_t w = 0, h = 0;
    vx_render_mode mode = VX_RENDER_COLOR;
    bool hits = true;
    int vi = 0;
    for (int i = 1; i < argc; i++) {
        if (sscanf(argv[i], "%ux%u", &w, &h) == 2) continue;
        if (!strcmp(argv[i], "--mode") && i + 1 < argc) mode = !strcmp(argv[++i], "depth") ? VX_RENDER_DEPTH : VX_RENDER_COLOR;
        else if (!strcmp(argv[i], "--no-hits")) hits = false;
        else if (!strcmp(argv[i], "--view") && i + 1 < argc) vi = atoi(argv[++i]) % 3;
        else {
            fprintf(stderr, "usage: %s [WxH] [--mode color|depth] [--no-hits] [--view N]\n", argv[0]);
            return 2;
        }
    }
    /* validation on when the layer is installed */
    gpu_skip = vx_test_gpu_open((vx_gpu_desc){0}, true, &gpu);
    vx_error err = {0};
    if (w && h) {
        /* one frame, for diagnosis */
        if (gpu_skip || !prepare()) return 1;
        vx_render_scene* rs = NULL;
        if (vx_render_scene_create(gpu, &terrain, &rs, &err)) return 1;
        vx_render_image img = {0};
        double wall = 0;
        /* an 8x8 frame first: the pipeline's creation apart from the frame */
        int bad = frame(rs, 8, 8, mode, hits, vi, &img, &wall);
        printf("8x8 first frame (creates the pipeline): %.3f s wall\n", wall);
        fflush(stdout);
        vx_render_image_free(&img);
        if (!bad) bad = frame(rs, w, h, mode, hits, vi, &img, &wall);
        size_t nh = 0, maxit = 0, odd = 0;
        for (size_t i = 0; !bad && hits && i < (size_t)w * h; i++) {
            nh += img.hits[i].instance != VX_RENDER_NO_HIT;
            if (img.hits[i].iterations > 100000) {
                if (odd++ < 4)
                    printf("  pixel %zu,%zu: %u iterations (%08x)\n", i % w, i / w, img.hits[i].iterations,
                           img.hits[i].iterations);
                continue;
            }
            if (img.hits[i].iterations > maxit) maxit = img.hits[i].iterations;
        }
        if (odd) printf("  %zu pixels past the iteration guard\n", odd);
        printf("%ux%u %s%s view %d: %.3f s wall, %.4f s GPU, %zu hits, max iterations %zu\n", w, h,
               mode == VX_RENDER_DEPTH ? "depth" : "color", hits ? " +hits" : "", vi, wall, img.gpu_seconds, nh, maxit);
        vx_render_image_free(&img);
        vx_render_scene_destroy(rs);
        vx_svo_scene_free(&terrain);
        vx_gpu_destroy(gpu);
        return bad;
    }
    RUN(test_hits_frame);
    if (have_terrain) vx_svo_scene_free(&terrain);
    if (gpu) vx_gpu_destroy(gpu);
    return vx_test_finish();
}
