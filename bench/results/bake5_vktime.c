/* bake5_vktime: where a process's host time goes in its Vulkan and file calls (issue 21, branch bake5; a bench
 * helper, not part of the toolkit). An LD_PRELOAD library: each wrapped call (the Vulkan calls that can take
 * time: instance, device, memory, buffers, pipelines, submissions, waits, teardown; and fsync, rename, fclose)
 * is timed (CLOCK_MONOTONIC) and passed on (dlsym RTLD_NEXT). At exit (or _exit, which svo_bake ends with)
 * it prints to stderr, times in ms since the library's load (the process's start, before main()):
 *   vkt: loaded at realtime S, main() at MS, printed at MS    (__libc_start_main, wrapped, stands for main())
 *   vkt: fn NAME calls N total MS max MS          for every wrapped function called
 *   vkt: at MS tid T NAME MS                      every call of 0.5 ms or more, in order of their end
 * Build: cc -O2 -shared -fPIC bake5_vktime.c -o vktime.so -ldl
 * Use:   LD_PRELOAD=$PWD/vktime.so svo_bake ... */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/syscall.h>
#include <time.h>
#include <unistd.h>
#include <vulkan/vulkan.h>

static double now(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

enum { MAXFN = 64, MAXEV = 4096 };
typedef struct fnstat {
    const char* name;
    _Atomic long calls;
    _Atomic long long ns, max_ns;
} fnstat;
typedef struct event {
    double end, sec;
    long tid;
    const char* name;
} event;

static double t_load, t_main, rt_load;
static fnstat fns[MAXFN];
static _Atomic int nfn;
static event evs[MAXEV];
static _Atomic int nev;
static pthread_mutex_t fn_lock = PTHREAD_MUTEX_INITIALIZER;
static _Atomic int printed;

__attribute__((constructor)) static void vkt_load(void) {
    struct timespec ts;
    clock_gettime(CLOCK_REALTIME, &ts);
    t_load = now();
    rt_load = (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static fnstat* stat_of(const char* name) {
    int n = atomic_load(&nfn);
    for (int i = 0; i < n; i++)
        if (fns[i].name == name) return &fns[i];
    pthread_mutex_lock(&fn_lock);
    n = atomic_load(&nfn);
    for (int i = 0; i < n; i++)
        if (fns[i].name == name) {
            pthread_mutex_unlock(&fn_lock);
            return &fns[i];
        }
    fnstat* f = n < MAXFN ? &fns[n] : NULL;
    if (f) f->name = name, atomic_store(&nfn, n + 1);
    pthread_mutex_unlock(&fn_lock);
    return f;
}

static void record(const char* name, double t0) {
    double t1 = now(), s = t1 - t0;
    fnstat* f = stat_of(name);
    if (f) {
        long long ns = (long long)(s * 1e9);
        atomic_fetch_add(&f->calls, 1);
        atomic_fetch_add(&f->ns, ns);
        long long m = atomic_load(&f->max_ns);
        while (ns > m && !atomic_compare_exchange_weak(&f->max_ns, &m, ns)) {
        }
    }
    if (s >= 0.0005) {
        int i = atomic_fetch_add(&nev, 1);
        if (i < MAXEV) evs[i] = (event){t1 - t_load, s, (long)syscall(SYS_gettid), name};
    }
}

static void vkt_print(void) {
    if (atomic_exchange(&printed, 1)) return;
    double t = now() - t_load;
    int n = atomic_load(&nfn);
    for (int i = 0; i < n; i++)
        fprintf(stderr, "vkt: fn %s calls %ld total %.3f max %.3f\n", fns[i].name, atomic_load(&fns[i].calls),
                atomic_load(&fns[i].ns) * 1e-6, atomic_load(&fns[i].max_ns) * 1e-6);
    int m = atomic_load(&nev);
    for (int i = 0; i < m && i < MAXEV; i++)
        fprintf(stderr, "vkt: at %.3f tid %ld %s %.3f\n", evs[i].end * 1e3, evs[i].tid, evs[i].name, evs[i].sec * 1e3);
    fprintf(stderr, "vkt: loaded at realtime %.6f, main() at %.3f ms, printed at %.3f ms since the load\n", rt_load,
            (t_main - t_load) * 1e3, t * 1e3);
}

__attribute__((destructor)) static void vkt_unload(void) { vkt_print(); }

#define NEXT(fn) static __typeof__(fn)* real; if (!real) real = (__typeof__(fn)*)dlsym(RTLD_NEXT, #fn)
#define WRAP(ret, fn, params, args)                                                                                    \
    ret fn params {                                                                                                    \
        NEXT(fn);                                                                                                      \
        double t0 = now();                                                                                             \
        ret r = real args;                                                                                             \
        record(#fn, t0);                                                                                               \
        return r;                                                                                                      \
    }
#define WRAPV(fn, params, args)                                                                                        \
    void fn params {                                                                                                   \
        NEXT(fn);                                                                                                      \
        double t0 = now();                                                                                             \
        real args;                                                                                                     \
        record(#fn, t0);                                                                                               \
    }

WRAP(VkResult, vkCreateInstance, (const VkInstanceCreateInfo* a, const VkAllocationCallbacks* b, VkInstance* c), (a, b, c))
WRAP(VkResult, vkEnumerateInstanceExtensionProperties, (const char* a, uint32_t* b, VkExtensionProperties* c), (a, b, c))
WRAP(VkResult, vkEnumerateInstanceLayerProperties, (uint32_t* a, VkLayerProperties* b), (a, b))
WRAP(VkResult, vkEnumeratePhysicalDevices, (VkInstance a, uint32_t* b, VkPhysicalDevice* c), (a, b, c))
WRAP(VkResult, vkCreateDevice, (VkPhysicalDevice a, const VkDeviceCreateInfo* b, const VkAllocationCallbacks* c, VkDevice* d), (a, b, c, d))
WRAP(VkResult, vkAllocateMemory, (VkDevice a, const VkMemoryAllocateInfo* b, const VkAllocationCallbacks* c, VkDeviceMemory* d), (a, b, c, d))
WRAPV(vkFreeMemory, (VkDevice a, VkDeviceMemory b, const VkAllocationCallbacks* c), (a, b, c))
WRAP(VkResult, vkMapMemory, (VkDevice a, VkDeviceMemory b, VkDeviceSize c, VkDeviceSize d, VkMemoryMapFlags e, void** f), (a, b, c, d, e, f))
WRAP(VkResult, vkCreateBuffer, (VkDevice a, const VkBufferCreateInfo* b, const VkAllocationCallbacks* c, VkBuffer* d), (a, b, c, d))
WRAPV(vkDestroyBuffer, (VkDevice a, VkBuffer b, const VkAllocationCallbacks* c), (a, b, c))
WRAP(VkResult, vkBindBufferMemory, (VkDevice a, VkBuffer b, VkDeviceMemory c, VkDeviceSize d), (a, b, c, d))
WRAP(VkResult, vkCreateShaderModule, (VkDevice a, const VkShaderModuleCreateInfo* b, const VkAllocationCallbacks* c, VkShaderModule* d), (a, b, c, d))
WRAP(VkResult, vkCreateComputePipelines, (VkDevice a, VkPipelineCache b, uint32_t c, const VkComputePipelineCreateInfo* d, const VkAllocationCallbacks* e, VkPipeline* f), (a, b, c, d, e, f))
WRAPV(vkDestroyPipeline, (VkDevice a, VkPipeline b, const VkAllocationCallbacks* c), (a, b, c))
WRAP(VkResult, vkCreateDescriptorPool, (VkDevice a, const VkDescriptorPoolCreateInfo* b, const VkAllocationCallbacks* c, VkDescriptorPool* d), (a, b, c, d))
WRAP(VkResult, vkCreateCommandPool, (VkDevice a, const VkCommandPoolCreateInfo* b, const VkAllocationCallbacks* c, VkCommandPool* d), (a, b, c, d))
WRAP(VkResult, vkCreateQueryPool, (VkDevice a, const VkQueryPoolCreateInfo* b, const VkAllocationCallbacks* c, VkQueryPool* d), (a, b, c, d))
WRAP(VkResult, vkCreateImage, (VkDevice a, const VkImageCreateInfo* b, const VkAllocationCallbacks* c, VkImage* d), (a, b, c, d))
WRAP(VkResult, vkQueueSubmit, (VkQueue a, uint32_t b, const VkSubmitInfo* c, VkFence d), (a, b, c, d))
WRAP(VkResult, vkWaitForFences, (VkDevice a, uint32_t b, const VkFence* c, VkBool32 d, uint64_t e), (a, b, c, d, e))
WRAP(VkResult, vkQueueWaitIdle, (VkQueue a), (a))
WRAP(VkResult, vkDeviceWaitIdle, (VkDevice a), (a))
WRAP(VkResult, vkGetQueryPoolResults, (VkDevice a, VkQueryPool b, uint32_t c, uint32_t d, size_t e, void* f, VkDeviceSize g, VkQueryResultFlags h), (a, b, c, d, e, f, g, h))
WRAPV(vkDestroyDevice, (VkDevice a, const VkAllocationCallbacks* b), (a, b))
WRAPV(vkDestroyInstance, (VkInstance a, const VkAllocationCallbacks* b), (a, b))
WRAP(int, fsync, (int a), (a))
WRAP(int, rename, (const char* a, const char* b), (a, b))
WRAP(int, fclose, (FILE * a), (a))
WRAP(int, pthread_join, (pthread_t a, void** b), (a, b))

/* main()'s start: glibc's _start calls __libc_start_main through the dynamic linker */
typedef int (*main_fn)(int, char**, char**);
int __libc_start_main(main_fn m, int argc, char** argv, void (*init)(void), void (*fini)(void), void (*rtld_fini)(void),
                      void* stack_end) {
    __typeof__(__libc_start_main)* real = (__typeof__(__libc_start_main)*)dlsym(RTLD_NEXT, "__libc_start_main");
    t_main = now();
    return real(m, argc, argv, init, fini, rtld_fini, stack_end);
}

void _exit(int status) {
    static __typeof__(_exit)* real;
    if (!real) real = (__typeof__(_exit)*)dlsym(RTLD_NEXT, "_exit");
    vkt_print();
    real(status);
    __builtin_unreachable();
}
