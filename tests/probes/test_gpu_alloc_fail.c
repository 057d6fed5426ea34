/* tests/probes/test_gpu_alloc_fail.c - allocation-failure injection on the
 * GPU side (tests/reliability/test_alloc_fail.c does the host's readers,
 * writers and converters). The device is made with a test allocator
 * (vx_gpu_desc.alloc: what the render scene, the frame renderer, the GI
 * methods and the probe renderer allocate on the host goes through it), and
 * each operation runs with the k-th allocation failing and every later one,
 * k = 1, 2, ... until it runs without a failure: every failing run must
 * return an error, crash nowhere and leave no block allocated; the run that
 * goes through must give the image of a run with the plain allocator.
 * Operations: a render scene and vx_render_frame; the pass pipeline with
 * lights, ao, aa and tonemap; and with gi=pathtrace, gi=cones and
 * gi=photons; the GPU probe renderer. */
#include <dlfcn.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cones/cones.h"
#include "photons/photons.h"
#include "tests/fail_alloc.h"
#include "tests/probes/probe_scenes.h"
#include "tests/test.h"

static vx_gpu* gpu;
static tfail fa; /* the device's allocator's state: set per run */

enum { W = 16, H = 12 };

typedef enum { OP_FRAME, OP_PASSES, OP_GI_PATHTRACE, OP_GI_CONES, OP_GI_PHOTONS, OP_PROBE_RENDER, OP_COUNT } op;
static const char* const op_names[OP_COUNT] = {"render scene + frame", "passes with lights, ao, aa, tonemap",
                                               "passes with gi=pathtrace", "passes with gi=cones",
                                               "passes with gi=photons", "probe renderer (pathtrace)"};

/* One run of operation o on scene s; its image into *img (its pixels NULL where it failed). */
static vx_result run(op o, const vx_svo_scene* s, vx_render_image* img, vx_error* err) {
    memset(img, 0, sizeof *img);
    vx_render_scene* rs = NULL;
    vx_frame_renderer* fr = NULL;
    vx_cone_gi* cg = NULL;
    vx_photon_gi* ph = NULL;
    vx_probe_gi* pg = NULL;
    vx_gi_method gm;
    double black[3] = {0, 0, 0};
    vx_probe_set light = light_only(1, black, 1);
    vx_light L = {.type = VX_LIGHT_POINT, .position = {6, 6, 8}, .color = {1, 1, 1}, .intensity = 30};
    vx_render_desc base = {.width = W, .height = H};
    vx_result r = vx_render_scene_create(gpu, s, &rs, err);
    if (!r && o == OP_FRAME) r = vx_render_frame(rs, &base, img, err);
    if (!r && o == OP_PROBE_RENDER) {
        vx_probe_render_desc rd = {.base = &base, .mode = VX_PROBE_RENDER_PATHTRACE, .spp = 2, .seed = 3};
        r = vx_probe_render_gpu(rs, s, &light, &rd, img, err);
    }
    if (!r && o != OP_FRAME && o != OP_PROBE_RENDER) {
        const char* list = "gbuffer,direct,ao,aa,tonemap";
        r = vx_frame_renderer_create(rs, s, &fr, err);
        if (!r && o == OP_GI_PATHTRACE) {
            list = "gbuffer,direct,gi=pathtrace";
            r = vx_probe_gi_create(rs, s, &light, "pathtrace", &(vx_probe_render_desc){.spp = 1, .seed = 3}, &gm, &pg, err);
        } else if (!r && o == OP_GI_CONES) {
            list = "gbuffer,direct,gi=cones";
            r = vx_cone_gi_create(rs, s, &(vx_cone_desc){.res = 16}, &gm, &cg, err);
        } else if (!r && o == OP_GI_PHOTONS) {
            list = "gbuffer,direct,gi=photons";
            r = vx_photon_gi_create(rs, s, &light, &(vx_photon_desc){.photons = 1 << 10, .seed = 9}, &gm, &ph, err);
        }
        vx_pass_list pl;
        if (!r) r = vx_pass_list_parse(list, &pl, err);
        if (!r) {
            vx_frame_desc d = vx_frame_desc_defaults();
            d.base = base;
            d.passes = &pl;
            if (o == OP_PASSES) d.lights = &L, d.light_count = 1;
            else d.gi = &gm;
            vx_frame_result res;
            r = vx_frame_render(fr, &d, &res, err);
            if (!r) *img = res.image;
        }
    }
    vx_photon_gi_destroy(ph);
    vx_cone_gi_destroy(cg);
    vx_probe_gi_destroy(pg);
    vx_frame_renderer_destroy(fr);
    vx_render_scene_destroy(rs);
    return r;
}

static void test_gpu_operations(void) {
    if (!gpu) SKIP("no Vulkan device");
    vx_svo_scene s;
    glass_room_scene(&s); /* metal, glass, emission: every material path */
    for (int o = 0; o < OP_COUNT; o++) {
        vx_error err = {0};
        vx_render_image want;
        fa = (tfail){0};
        vx_result r = run((op)o, &s, &want, &err);
        if (r) {
            CHECKF(false, "%s: %s", op_names[o], err.msg);
            continue;
        }
        long k = 1, errors = 0;
        bool done = false;
        for (; k < 3000 && !done; k++) {
            fa = (tfail){.fail_at = k, .persistent = true};
            vx_render_image img;
            r = run((op)o, &s, &img, &err);
            bool failed = fa.failed;
            if (r == VX_OK) {
                CHECKF(!failed, "%s: allocation %ld failed and the run went on as if not", op_names[o], k);
                done = true;
                size_t n = (size_t)W * H * 4;
                CHECKF(img.pixels && !memcmp(img.pixels, want.pixels, n * sizeof *img.pixels),
                       "%s: the image after the failures differs", op_names[o]);
                vx_render_image_free(&img); /* (through the device's allocator: before the count below) */
            }
            long live = fa.live;
            fa = (tfail){0};
            if (r != VX_OK) {
                errors++;
                CHECKF(img.pixels == NULL, "%s: allocation %ld failing left an image", op_names[o], k);
            }
            CHECKF(live == 0, "%s: allocation %ld failing left %ld blocks", op_names[o], k, live);
        }
        fprintf(stderr, "  %-36s %ld allocation failures, each an error, then the same image\n", op_names[o], errors);
        CHECKF(done, "%s: still failing after %ld runs", op_names[o], k - 1);
        vx_render_image_free(&want);
    }
    vx_svo_scene_free(&s);
}

int main(void) {
    (void)ts_random_model, (void)room_scene, (void)box_scene;
    dlopen("libvulkan_lvp.so", RTLD_NOW | RTLD_NODELETE); /* see test_probes_gpu.c */
    vx_error err = {0};
    vx_allocator a = {.alloc = tfail_alloc, .free = tfail_free, .user_data = &fa};
    if (vx_gpu_create(&(vx_gpu_desc){.alloc = &a}, &gpu, &err)) {
        fprintf(stderr, "no Vulkan device (%s): skipped\n", err.msg);
        gpu = NULL;
    }
    RUN(test_gpu_operations);
    fa = (tfail){0};
    if (gpu) vx_gpu_destroy(gpu);
    return vx_test_finish();
}
