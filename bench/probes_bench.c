/* bench/probes_bench.c - error of probe GI's indirect diffuse light (RMSE and
 * relative MSE over hit pixels against a path-traced reference) against bake
 * and render time, and the path tracer's own error at matching time.
 *   probes_bench SCENE.svo WxH REF_SPP [spacing:res:spp ...] */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "probes/probes.h"

static void err_of(const vx_render_image* a, const vx_render_image* ref, double* rmse, double* rel) {
    double se = 0, rs = 0;
    size_t n = 0;
    for (size_t i = 0; i < (size_t)a->width * a->height; i++) {
        if (ref->pixels[4 * i + 3] == 0) continue;
        for (int c = 0; c < 3; c++) {
            double d = a->pixels[4 * i + c] - ref->pixels[4 * i + c];
            se += d * d, rs += ref->pixels[4 * i + c] * ref->pixels[4 * i + c];
        }
        n += 3;
    }
    *rmse = n ? sqrt(se / n) : 0;
    *rel = rs > 0 ? se / rs : 0;
}

int main(int argc, char** argv) {
    if (argc < 4) {
        fprintf(stderr, "usage: probes_bench SCENE.svo WxH REF_SPP [spacing:res:spp ...]\n");
        return 2;
    }
    vx_error err = {0};
    vx_svo_scene s;
    if (vx_svo_read_file(NULL, argv[1], &s, &err)) return fprintf(stderr, "%s\n", err.msg), 1;
    unsigned w, h, ref_spp = (unsigned)atoi(argv[3]);
    if (sscanf(argv[2], "%ux%u", &w, &h) != 2) return 2;
    vx_render_desc base = {.width = w, .height = h};
    vx_render_image ref = {0};
    if (vx_probe_render(&s, NULL, &(vx_probe_render_desc){.base = &base, .mode = VX_PROBE_RENDER_PT_INDIRECT, .spp = ref_spp, .seed = 999, .threads = 2}, &ref, &err))
        return fprintf(stderr, "%s\n", err.msg), 1;
    printf("| scene | method | probes | res | spp | bake s | render s | RMSE | relMSE |\n|---|---|---|---|---|---|---|---|---|\n");
    printf("| %s | pathtrace ref | - | - | %u | - | %.2f | 0 | 0 |\n", argv[1], ref_spp, ref.gpu_seconds);
    for (unsigned spp = 1; spp <= 16; spp *= 4) {
        vx_render_image pt = {0};
        vx_probe_render(&s, NULL, &(vx_probe_render_desc){.base = &base, .mode = VX_PROBE_RENDER_PT_INDIRECT, .spp = spp, .seed = 7, .threads = 2}, &pt, &err);
        double rmse, rel;
        err_of(&pt, &ref, &rmse, &rel);
        printf("| %s | pathtrace | - | - | %u | - | %.3f | %.4f | %.4f |\n", argv[1], spp, pt.gpu_seconds, rmse, rel);
        vx_render_image_free(&pt);
    }
    for (int i = 4; i < argc; i++) {
        double sp;
        unsigned res, spp;
        if (sscanf(argv[i], "%lf:%u:%u", &sp, &res, &spp) != 3) return 2;
        vx_probe_set ps;
        double t0 = vx_time_now();
        if (vx_probe_bake(&s, &(vx_probe_bake_desc){.spacing = sp, .res = res, .spp = spp, .threads = 2}, &ps, &err))
            return fprintf(stderr, "%s\n", err.msg), 1;
        double tb = vx_time_now() - t0;
        vx_render_image gi = {0};
        vx_probe_render(&s, &ps, &(vx_probe_render_desc){.base = &base, .mode = VX_PROBE_RENDER_INDIRECT, .threads = 2}, &gi, &err);
        double rmse, rel;
        err_of(&gi, &ref, &rmse, &rel);
        printf("| %s | gi | %u | %u | %u | %.2f | %.3f | %.4f | %.4f |\n", argv[1], ps.probe_count, res, spp, tb,
               gi.gpu_seconds, rmse, rel);
        vx_render_image_free(&gi);
        vx_probe_set_free(&ps);
    }
    vx_render_image_free(&ref);
    vx_svo_scene_free(&s);
    return 0;
}
