/* bench/view_bench.c - svo_view's edit path: one edit (move an instance by a
 * cell) plus the scene update after it, for N instances of a small model:
 * the render scene made again (BVH build, instance and model upload: what
 * the viewer did before), and the instance update it does now (instance
 * tables and BVH, vx_render_scene_set_frame); and a frame of that scene for
 * comparison.
 * Usage: view_bench [INSTANCES (default 10000)] [REPEAT (default 9)]
 *        view_bench --animate IN.svo OUT.svo FRAMES: OUT is IN as an animation
 *        of FRAMES frames, every instance one cell further along x each frame
 *        (models shared: playback in svo_view --bench switches frames with no
 *        upload; bench/view_bench.sh compares it with the still scene) */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "render/render.h"
#include "tools/svo_view/editor.h"

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

int main(int argc, char** argv) {
    if (argc == 5 && !strcmp(argv[1], "--animate")) return animate(argv[2], argv[3], (uint32_t)strtoul(argv[4], NULL, 10));
    uint32_t n = argc > 1 ? (uint32_t)strtoul(argv[1], NULL, 10) : 10000, rep = argc > 2 ? (uint32_t)strtoul(argv[2], NULL, 10) : 9;
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
    for (uint32_t k = 0; k < rep; k++) {
        double t0 = vx_time_now();
        if (ved_begin(&e, &err)) return 1;
        ved_move(&s, k % n, (int32_t[3]){1, 0, 0});
        if (vx_render_scene_set_frame(rs, &s, 0, &err)) return fprintf(stderr, "%s\n", err.msg), 1;
        inst[k] = (vx_time_now() - t0) * 1e3;
    }
    qsort(inst, rep, sizeof *inst, cmp);
    qsort(edit, rep, sizeof *edit, cmp);
    qsort(bvh, rep, sizeof *bvh, cmp);
    qsort(frame, rep, sizeof *frame, cmp);
    printf("view_bench: %u instances on %s: edit + scene update median %.3f ms (BVH build %.3f ms); "
           "640x480 frame (vx_render_frame wall) median %.3f ms\n",
           n, vx_gpu_device_name(gpu), edit[rep / 2], bvh[rep / 2], frame[rep / 2]);
    printf("view_bench: edit + instance update (instance tables and BVH, models stay on the GPU) median %.3f ms\n",
           inst[rep / 2]);
    free(edit), free(bvh), free(frame), free(inst);
    ved_free(&e);
    vx_render_scene_destroy(rs);
    vx_gpu_destroy(gpu);
    vx_svo_scene_free(&s);
    return 0;
}
