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
    double at[3];       /* wall clock (CLOCK_REALTIME s): the thread's start, the device made, the scene bound */
    char fallback[64];  /* the device to try after widen() where the first failed ("" none) */
    void (*widen)(void);
    bool fell_back;     /* the fallback was tried */
} vx_tool_gpu_open;

/* Starts opening the device of desc (desc->device is copied; the logger and
 * allocator must outlive the wait) and binding scene to it (NULL: no scene).
 * The scene must stay unchanged until the wait. Without a thread (none could
 * be started) the open happens in the wait. */
void vx_tool_gpu_open_start(vx_tool_gpu_open* o, const vx_gpu_desc* desc, const vx_svo_scene* scene);

/* The same for a process whose driver was narrowed to one GPU
 * (vx_tool_mpi_gpu_only): where making the device fails, widen() undoes that
 * and the device `fallback` is opened instead (a driver that refuses to
 * start without every GPU costs a second start, not the job). */
void vx_tool_gpu_open_start_narrowed(vx_tool_gpu_open* o, const vx_gpu_desc* desc, const vx_svo_scene* scene,
                                     const char* fallback, void (*widen)(void));

/* Waits for the open; on success hands over the device and the scene (the
 * caller destroys them), else returns the error in *err with *failed naming
 * the step ("device" or "scene") and has destroyed what was made. */
vx_result vx_tool_gpu_open_wait(vx_tool_gpu_open* o, vx_gpu** gpu, vx_render_scene** rs, const char** failed,
                                vx_error* err);

/* Something slow at the end (closing a device: vkDestroyDevice and the
 * instance's end took 0.15-0.3 s a rank with four ranks starting together on
 * the 4-H200 host) run on a thread of its own while the tool gathers and
 * writes its output; vx_tool_bg_wait joins it (a no-op when none started).
 * Without a thread fn runs in the start. */
typedef struct vx_tool_bg {
    pthread_t thread;
    bool started;
    void (*fn)(void* arg);
    void* arg;
} vx_tool_bg;
void vx_tool_bg_start(vx_tool_bg* b, void (*fn)(void* arg), void* arg);
void vx_tool_bg_wait(vx_tool_bg* b);

#endif
