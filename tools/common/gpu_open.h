/* tools/common/gpu_open.h - opening a Vulkan device and binding a scene to
 * it on a thread of its own (svo_bake, svo_render under mpirun), so that the
 * driver's start-up (instance, device, the scene's upload: 0.3-0.6 s on the
 * GPU hosts, more with two ranks starting together) overlaps the tool's other
 * start-up work (MPI_Init, probe placement) instead of adding to it. */
#ifndef VX_TOOL_GPU_OPEN_H
#define VX_TOOL_GPU_OPEN_H

#include <pthread.h>
#include <stdbool.h>

#include "render/render.h"

typedef struct vx_tool_gpu_open {
    /* private: set by vx_tool_gpu_open_start, read after vx_tool_gpu_open_wait */
    pthread_t thread;
    bool started;
    char device[64]; /* a copy of desc.device */
    vx_gpu_desc desc;
    const vx_svo_scene* scene;
    vx_gpu* gpu;
    vx_render_scene* rs;
    vx_result r;
    vx_error err;
    const char* failed; /* "device" or "scene": which step failed */
    double seconds;     /* the thread's time */
    double device_s;    /* of it vx_gpu_create's (instance, device); the rest binds the scene */
} vx_tool_gpu_open;

/* Starts opening the device of desc (desc->device is copied; the logger and
 * allocator must outlive the wait) and binding scene to it (NULL: no scene).
 * The scene must stay unchanged until the wait. Without a thread (none could
 * be started) the open happens in the wait. */
void vx_tool_gpu_open_start(vx_tool_gpu_open* o, const vx_gpu_desc* desc, const vx_svo_scene* scene);

/* Waits for the open; on success hands over the device and the scene (the
 * caller destroys them), else returns the error in *err with *failed naming
 * the step ("device" or "scene") and has destroyed what was made. */
vx_result vx_tool_gpu_open_wait(vx_tool_gpu_open* o, vx_gpu** gpu, vx_render_scene** rs, const char** failed,
                                vx_error* err);

#endif
