/* tools/common/gpu_open.c - a device opened on its own thread (gpu_open.h). */
#define _POSIX_C_SOURCE 200809L /* clock_gettime */
#include "tools/common/gpu_open.h"

#include <stdio.h>
#include <string.h>
#include <time.h>

/* the wall clock: stamps that can be set against other processes' */
static double wall(void) {
    struct timespec t;
    clock_gettime(CLOCK_REALTIME, &t);
    return (double)t.tv_sec + (double)t.tv_nsec * 1e-9;
}

static void* open_thread(void* arg) {
    vx_tool_gpu_open* o = arg;
    o->at[0] = wall();
    double t = vx_time_now();
    o->r = vx_gpu_create(&o->desc, &o->gpu, &o->err);
    /* narrowed to one GPU: a failure, or a software device where the GPU was
     * left out, opens the fallback with every GPU in sight */
    if (o->widen && (o->r || vx_gpu_is_cpu(o->gpu))) {
        vx_gpu_destroy(o->gpu);
        o->gpu = NULL;
        o->widen();
        o->fell_back = true;
        o->desc.device = o->fallback[0] ? o->fallback : NULL;
        o->r = vx_gpu_create(&o->desc, &o->gpu, &o->err);
    }
    o->device_s = vx_time_now() - t;
    o->at[1] = wall();
    if (o->r) o->failed = "device";
    else if (o->scene && (o->r = vx_render_scene_create(o->gpu, o->scene, &o->rs, &o->err))) o->failed = "scene";
    o->seconds = vx_time_now() - t;
    o->at[2] = wall();
    return NULL;
}

void vx_tool_gpu_open_start(vx_tool_gpu_open* o, const vx_gpu_desc* desc, const vx_svo_scene* scene) {
    vx_tool_gpu_open_start_narrowed(o, desc, scene, NULL, NULL);
}

void vx_tool_gpu_open_start_narrowed(vx_tool_gpu_open* o, const vx_gpu_desc* desc, const vx_svo_scene* scene,
                                     const char* fallback, void (*widen)(void)) {
    memset(o, 0, sizeof *o);
    o->widen = widen;
    if (fallback) snprintf(o->fallback, sizeof o->fallback, "%s", fallback);
    o->desc = desc ? *desc : (vx_gpu_desc){0};
    if (o->desc.device) {
        snprintf(o->device, sizeof o->device, "%s", o->desc.device);
        o->desc.device = o->device;
    }
    o->scene = scene;
    o->started = pthread_create(&o->thread, NULL, open_thread, o) == 0;
}

vx_result vx_tool_gpu_open_wait(vx_tool_gpu_open* o, vx_gpu** gpu, vx_render_scene** rs, const char** failed,
                                vx_error* err) {
    if (o->started) pthread_join(o->thread, NULL);
    else open_thread(o);
    o->started = false;
    if (o->r) {
        vx_render_scene_destroy(o->rs);
        vx_gpu_destroy(o->gpu);
        o->rs = NULL, o->gpu = NULL;
        if (err) *err = o->err;
        if (failed) *failed = o->failed;
        return o->r;
    }
    *gpu = o->gpu;
    if (rs) *rs = o->rs;
    else vx_render_scene_destroy(o->rs);
    return VX_OK;
}

static void* bg_main(void* arg) {
    vx_tool_bg* b = arg;
    b->fn(b->arg);
    return NULL;
}

void vx_tool_bg_start(vx_tool_bg* b, void (*fn)(void* arg), void* arg) {
    b->fn = fn, b->arg = arg;
    b->started = pthread_create(&b->thread, NULL, bg_main, b) == 0;
    if (!b->started) fn(arg);
}

void vx_tool_bg_wait(vx_tool_bg* b) {
    if (b->started) pthread_join(b->thread, NULL);
    b->started = false;
}
