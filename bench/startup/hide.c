/* bench/startup/hide.c - hide.so (LD_PRELOAD), an experiment (issue 23):
 * this process may open only one GPU's device node /dev/nvidiaN (N =
 * VX_GPU_ONLY, or the launcher's local rank mod the GPUs present); opening
 * another fails with VX_HIDE_ERRNO (EPERM default, or ENOENT). VX_HIDE_LOG=1
 * prints every /dev/nvidia* path opened. Does the NVIDIA Vulkan driver then
 * show and attach only that GPU? (The tools do the same in-process:
 * tools/common/gpu_only.c.) Built by hand:
 *   cc -O2 -shared -fPIC -o hide.so bench/startup/hide.c -ldl */
#define _GNU_SOURCE
#include <dirent.h>
#include <dlfcn.h>
#include <errno.h>
#include <fcntl.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
static int only = -2;
static int gpus(void) {
    int n = 0; char p[32]; struct stat s;
    for (int i = 0; i < 64; i++) { snprintf(p, sizeof p, "/dev/nvidia%d", i); if (stat(p, &s) == 0) n = i + 1; }
    return n;
}
static int blocked(const char* path) {
    if (!path || strncmp(path, "/dev/nvidia", 11)) return 0;
    if (getenv("VX_HIDE_LOG")) fprintf(stderr, "hide: open %s\n", path);
    const char* d = path + 11;
    if (*d < '0' || *d > '9') return 0;
    char* end; long n = strtol(d, &end, 10);
    if (*end) return 0;
    if (only == -2) {
        const char* e = getenv("VX_GPU_ONLY");
        const char* lr = getenv("OMPI_COMM_WORLD_LOCAL_RANK");
        int g = gpus();
        only = e ? atoi(e) : lr && g ? atoi(lr) % g : -1;
    }
    if (only < 0 || n == only) return 0;
    const char* en = getenv("VX_HIDE_ERRNO");
    errno = en && !strcmp(en, "ENOENT") ? ENOENT : EPERM;
    if (getenv("VX_HIDE_LOG")) fprintf(stderr, "hide: refused %s\n", path);
    return 1;
}
#define WRAP(name) \
    int name(const char* p, int fl, ...) { \
        static int (*real)(const char*, int, ...); if (!real) real = dlsym(RTLD_NEXT, #name); \
        mode_t m = 0; if (fl & (O_CREAT | O_TMPFILE)) { va_list ap; va_start(ap, fl); m = va_arg(ap, mode_t); va_end(ap); } \
        if (blocked(p)) return -1; return real(p, fl, m); }
WRAP(open)
WRAP(open64)
#define WRAPAT(name) \
    int name(int dfd, const char* p, int fl, ...) { \
        static int (*real)(int, const char*, int, ...); if (!real) real = dlsym(RTLD_NEXT, #name); \
        mode_t m = 0; if (fl & (O_CREAT | O_TMPFILE)) { va_list ap; va_start(ap, fl); m = va_arg(ap, mode_t); va_end(ap); } \
        if (blocked(p)) return -1; return real(dfd, p, fl, m); }
WRAPAT(openat)
WRAPAT(openat64)
int __open_2(const char* p, int fl) { static int (*real)(const char*, int); if (!real) real = dlsym(RTLD_NEXT, "__open_2"); if (blocked(p)) return -1; return real(p, fl); }
int __open64_2(const char* p, int fl) { static int (*real)(const char*, int); if (!real) real = dlsym(RTLD_NEXT, "__open64_2"); if (blocked(p)) return -1; return real(p, fl); }
