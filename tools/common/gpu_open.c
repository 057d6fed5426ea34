/* tools/common/gpu_open.c - a device opened on its own thread (gpu_open.h). */
#include "tools/common/gpu_open.h"

#include <stdio.h>
#include <string.h>

static void* open_thread(void* arg) {
    vx_tool_gpu_open* o = arg;
    double t = vx_time_now();
    o->r = vx_gpu_create(&o->desc, &o->gpu, &o->err);
    o->device_s = vx_time_now() - t;
    if (o->r) o->failed = "device";
    else if (o->scene && (o->r = vx_render_scene_create(o->gpu, o->scene, &o->rs, &o->err))) o->failed = "scene";
    o->seconds = vx_time_now() - t;
    return NULL;
}

void vx_tool_gpu_open_start(vx_tool_gpu_open* o, const vx_gpu_desc* desc, const vx_svo_scene* scene) {
    memset(o, 0, sizeof *o);
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
