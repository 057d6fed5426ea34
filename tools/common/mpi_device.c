/* tools/common/mpi_device.c - the device a rank opens (mpi.h); apart from
 * mpi.c so that a tool without Vulkan (vox2svo) links the MPI helpers
 * without the renderer. The device is counted and picked by the instance
 * that opens it ("gpu:K"): listing the GPUs first took a second Vulkan
 * instance per rank. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tools/common/mpi.h"

const char* vx_tool_mpi_device(int local_rank, const char* device, bool cpu, char buf[16]) {
    if (device || cpu) return device;
    snprintf(buf, 16, "gpu:%d", local_rank > 0 ? local_rank : 0);
    return buf;
}

const char* vx_tool_mpi_device_narrowed(int local_rank, const char* device, bool cpu, char buf[16], int* node) {
    *node = -1;
    const char* all = getenv("VX_MPI_ALL_GPUS");
    if (!device && !cpu && local_rank >= 0 && !(all && !strcmp(all, "1")) &&
        (*node = vx_tool_mpi_gpu_only(local_rank)) >= 0) {
        snprintf(buf, 16, "gpu:0");
        return buf;
    }
    return vx_tool_mpi_device(local_rank, device, cpu, buf);
}
