/* LD_PRELOAD shim: wall seconds spent in vkCreateComputePipelines (the driver's compile, or its cache's hit)
 * and in the waits for the device (vkWaitForFences, vkQueueWaitIdle, vkDeviceWaitIdle: on lavapipe the
 * dispatches run there), printed to stderr at exit; the pipelines' CPU time on the threads that made them too. Build: cc -O2 -shared -fPIC vk_time_shim.c -o shim.so -ldl */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <stdint.h>
#include <stdio.h>
#include <time.h>
#include <vulkan/vulkan.h>
static double now(void) { struct timespec t; clock_gettime(CLOCK_MONOTONIC, &t); return t.tv_sec + 1e-9 * t.tv_nsec; }
static double tcpu(void) { struct timespec t; clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t); return t.tv_sec + 1e-9 * t.tv_nsec; }
static double t_pipe, c_pipe, t_wait; static unsigned n_pipe, n_wait;
#define NEXT(name) static PFN_##name next; if (!next) next = (PFN_##name)dlsym(RTLD_NEXT, #name)
VKAPI_ATTR VkResult VKAPI_CALL vkCreateComputePipelines(VkDevice d, VkPipelineCache c, uint32_t n,
        const VkComputePipelineCreateInfo* ci, const VkAllocationCallbacks* a, VkPipeline* p) {
    NEXT(vkCreateComputePipelines);
    double t0 = now(), c0 = tcpu(); VkResult r = next(d, c, n, ci, a, p); t_pipe += now() - t0; c_pipe += tcpu() - c0; n_pipe += n; return r;
}
VKAPI_ATTR VkResult VKAPI_CALL vkWaitForFences(VkDevice d, uint32_t n, const VkFence* f, VkBool32 all, uint64_t to) {
    NEXT(vkWaitForFences);
    double t0 = now(); VkResult r = next(d, n, f, all, to); t_wait += now() - t0; n_wait++; return r;
}
VKAPI_ATTR VkResult VKAPI_CALL vkQueueWaitIdle(VkQueue q) {
    NEXT(vkQueueWaitIdle);
    double t0 = now(); VkResult r = next(q); t_wait += now() - t0; n_wait++; return r;
}
VKAPI_ATTR VkResult VKAPI_CALL vkDeviceWaitIdle(VkDevice d) {
    NEXT(vkDeviceWaitIdle);
    double t0 = now(); VkResult r = next(d); t_wait += now() - t0; n_wait++; return r;
}
__attribute__((destructor)) static void report(void) {
    fprintf(stderr, "vk_time_shim: pipelines %u in %.2f s (%.2f s CPU of the calling threads), waits %u in %.2f s\n", n_pipe, t_pipe, c_pipe, n_wait, t_wait);
}
