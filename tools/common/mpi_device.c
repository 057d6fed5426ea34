/* tools/common/mpi_device.c - the device a rank opens (mpi.h); apart from
 * mpi.c so that a tool without Vulkan (vox2svo) links the MPI helpers
 * without the renderer. */
#include <stdio.h>
#include <string.h>

#include "render/render.h"
#include "tools/common/mpi.h"

typedef struct gpu_list {
    unsigned index[64];
    unsigned n;
} gpu_list;

static void list_fn(void* user, uint32_t index, const char* name, const char* type) {
    (void)name;
    gpu_list* l = user;
    if (strcmp(type, "cpu") && strcmp(type, "other") && l->n < 64) l->index[l->n++] = index;
}

const char* vx_tool_mpi_device(const vx_tool_mpi* m, const char* device, bool cpu, char buf[16]) {
    if (device || cpu) return device;
    gpu_list gl = {.n = 0};
    vx_error err = {0};
    if (vx_gpu_list_devices(list_fn, &gl, &err) || !gl.n) return NULL;
    snprintf(buf, 16, "%u", gl.index[(unsigned)m->local_rank % gl.n]);
    return buf;
}
