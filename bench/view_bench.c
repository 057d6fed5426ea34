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
 *        upload; bench/view_bench.sh compares it with the still scene)
 *        view_bench --stroke IN.svo|terrain256 [STROKES (default 30)] [RADIUS (default 4)]:
 *        svo_view's brush strokes (sphere, add/remove/paint in turn, centred on
 *        the surface of instance 0's model at random columns): the editor's
 *        apply (vvx_apply) and the GPU update (vx_render_scene_update_model),
 *        undo (header restored + update), against the path before (the model
 *        decoded and built again, the render scene made again) on the same
 *        strokes. terrain256: the tracer benchmarks' terrain at 256^3. Needs
 *        only libvulkan and libc (runs on the GPU machine). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "render/render.h"
#include "bench/bench_terrain.h"
#include "tools/svo_view/editor.h"
#include "tools/svo_view/voxels.h"

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

static int stroke_bench(const char* in, uint32_t strokes, uint32_t radius) {
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
    if (vx_gpu_create(NULL, &gpu, &err) || vx_render_scene_create(gpu, &s, &rs, &err) ||
        vx_render_scene_create(gpu, &s2, &rs2, &err))
        return fprintf(stderr, "%s\n", err.msg), 1;
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
        if (vx_render_scene_create(gpu, &s2, &rs2, &err)) return fprintf(stderr, "%s\n", err.msg), 1;
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

int main(int argc, char** argv) {
    if (argc >= 3 && !strcmp(argv[1], "--stroke"))
        return stroke_bench(argv[2], argc > 3 ? (uint32_t)strtoul(argv[3], NULL, 10) : 30,
                            argc > 4 ? (uint32_t)strtoul(argv[4], NULL, 10) : 4);
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
