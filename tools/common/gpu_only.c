/* tools/common/gpu_only.c - a rank whose Vulkan driver sees only its own GPU
 * (mpi.h: vx_tool_mpi_gpu_only).
 *
 * Why: NVIDIA's driver opens the device node of every GPU of the host
 * (/dev/nvidiaN) and attaches it when an instance enumerates its physical
 * devices, whichever one the process then uses; the driver serialises those
 * attaches across processes, so on 4 H200 of one host one rank's Vulkan start
 * took 0.46 s alone and 1.03-1.25 s with four ranks starting together
 * (docs/PERFORMANCE.md section 10). The driver leaves out a GPU whose node it
 * cannot open (what a container given some of a host's GPUs relies on), and
 * the NVIDIA driver offers no setting that narrows the list. So, once a rank
 * has chosen its GPU, this process's open calls refuse the other GPUs' nodes
 * with EPERM.
 *
 * How: these definitions of the open family take precedence over libc's for
 * the whole process (the executable exports them: tools/common.cmake), so the
 * driver's own calls come here; every call not on a refused node goes to the
 * kernel unchanged (the openat system call, as libc would). Until
 * vx_tool_mpi_gpu_only is called nothing is refused. */
#define _GNU_SOURCE
#include <errno.h>
#include <fcntl.h>
#include <stdarg.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <unistd.h>

#include "tools/common/mpi.h"

/* the one GPU node this process may open; -1: every node (set before the
 * device thread starts, read by any thread); the nodes' names (a test's
 * folder in place of /dev, set with it) */
static atomic_int only = -1;
static char prefix[256] = "/dev/nvidia";
static size_t prefix_len = 11;

/* N of "/dev/nvidiaN", else -1 (nvidiactl, nvidia-uvm, other files) */
static int gpu_node(const char* path) {
    if (!path || strncmp(path, prefix, prefix_len)) return -1;
    const char* d = path + prefix_len;
    int n = 0;
    if (*d < '0' || *d > '9') return -1;
    for (; *d >= '0' && *d <= '9' && n < 1 << 20; d++) n = n * 10 + (*d - '0');
    return *d ? -1 : n;
}

static int refused(const char* path) {
    int keep = atomic_load(&only);
    if (keep < 0) return 0;
    int n = gpu_node(path);
    if (n < 0 || n == keep) return 0;
    errno = EPERM;
    return 1;
}

static int open_mode(int flags, va_list ap) {
    return (flags & O_CREAT) || (flags & O_TMPFILE) == O_TMPFILE ? va_arg(ap, int) : 0;
}

static int sys_openat(int dirfd, const char* path, int flags, int mode) {
    return (int)syscall(SYS_openat, dirfd, path, flags, mode);
}

int open(const char* path, int flags, ...) {
    va_list ap;
    va_start(ap, flags);
    int mode = open_mode(flags, ap);
    va_end(ap);
    return refused(path) ? -1 : sys_openat(AT_FDCWD, path, flags, mode);
}

int open64(const char* path, int flags, ...) {
    va_list ap;
    va_start(ap, flags);
    int mode = open_mode(flags, ap);
    va_end(ap);
    return refused(path) ? -1 : sys_openat(AT_FDCWD, path, flags, mode);
}

int openat(int dirfd, const char* path, int flags, ...) {
    va_list ap;
    va_start(ap, flags);
    int mode = open_mode(flags, ap);
    va_end(ap);
    return refused(path) ? -1 : sys_openat(dirfd, path, flags, mode);
}

int openat64(int dirfd, const char* path, int flags, ...) {
    va_list ap;
    va_start(ap, flags);
    int mode = open_mode(flags, ap);
    va_end(ap);
    return refused(path) ? -1 : sys_openat(dirfd, path, flags, mode);
}

/* what _FORTIFY_SOURCE builds call for open without a mode */
int __open_2(const char* path, int flags) { return refused(path) ? -1 : sys_openat(AT_FDCWD, path, flags, 0); }
int __open64_2(const char* path, int flags) { return refused(path) ? -1 : sys_openat(AT_FDCWD, path, flags, 0); }

/* vx_tool_mpi_gpu_only with the nodes named PREFIX N (tests: files in a
 * folder of their own); internal */
int vx__tool_gpu_only_at(const char* nodes_prefix, int local_rank);
int vx__tool_gpu_only_at(const char* nodes_prefix, int local_rank) {
    size_t n = strlen(nodes_prefix);
    if (local_rank < 0 || n >= sizeof prefix) return -1;
    /* the GPU nodes present, in order (N is the driver's minor number) */
    int nodes[64], count = 0;
    for (int i = 0; i < 64; i++) {
        char p[300];
        struct stat s;
        snprintf(p, sizeof p, "%s%d", nodes_prefix, i);
        if (stat(p, &s) == 0) nodes[count++] = i;
    }
    if (count < 2) return -1; /* nothing to leave out */
    int keep = nodes[local_rank % count];
    atomic_store(&only, -1);
    memcpy(prefix, nodes_prefix, n + 1);
    prefix_len = n;
    atomic_store(&only, keep);
    return keep;
}

int vx_tool_mpi_gpu_only(int local_rank) { return vx__tool_gpu_only_at("/dev/nvidia", local_rank); }

void vx_tool_mpi_gpu_all(void) { atomic_store(&only, -1); }
