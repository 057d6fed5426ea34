/* tests/tools/test_gpu_only.c - a rank's driver narrowed to its GPU
 * (tools/common/gpu_only.c): with the nodes of a folder of our own in place
 * of /dev/nvidiaN, the kept node opens and the others are refused, whoever
 * calls open (this program, or zlib: a shared library bound to the
 * executable's exported open family, as the Vulkan driver is); files that are
 * not GPU nodes open as before, O_CREAT's mode arrives, and
 * vx_tool_mpi_gpu_all undoes it. Checked against stat/fstat of the files. */
#define _GNU_SOURCE
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

#include "../test.h"
#include "tools/common/mpi.h"

int vx__tool_gpu_only_at(const char* nodes_prefix, int local_rank);

static char dir[256];

static void path(char* out, const char* name) { snprintf(out, 300, "%s/%s", dir, name); }

static void touch(const char* name) {
    char p[300];
    path(p, name);
    FILE* f = fopen(p, "wb"); /* libc's own open: never refused */
    if (f) fputs(name, f), fclose(f);
}

/* opens name with open(); returns the errno of a failure, 0 when the
 * descriptor is the file stat names */
static int try_open(const char* name, int at) {
    char p[300];
    path(p, name);
    int fd = at ? openat(AT_FDCWD, p, O_RDONLY) : open(p, O_RDONLY);
    if (fd < 0) return errno;
    struct stat a, b;
    int same = fstat(fd, &a) == 0 && stat(p, &b) == 0 && a.st_ino == b.st_ino && a.st_dev == b.st_dev;
    close(fd);
    return same ? 0 : -1;
}

static void test_keeps_one_node(void) {
    touch("nvidia0"), touch("nvidia1"), touch("nvidia3"), touch("nvidiactl"), touch("nvidia1x");
    char prefix[300];
    path(prefix, "nvidia");
    /* nodes 0, 1, 3: local rank 4 gets the second (4 mod 3 = 1) */
    int keep = vx__tool_gpu_only_at(prefix, 4);
    CHECKF(keep == 1, "kept node %d", keep);
    CHECK(try_open("nvidia1", 0) == 0);
    CHECK(try_open("nvidia1", 1) == 0);
    CHECK(try_open("nvidia0", 0) == EPERM);
    CHECK(try_open("nvidia3", 1) == EPERM);
    CHECK(try_open("nvidiactl", 0) == 0); /* not a GPU node */
    CHECK(try_open("nvidia1x", 0) == 0);
    CHECK(try_open("nvidia2", 0) == EPERM);    /* another GPU's node, present or not */
    CHECK(try_open("nvidia-uvm", 0) == ENOENT); /* not a GPU node: the kernel's answer */
    /* a shared library's open binds to ours */
    char p[300];
    path(p, "nvidia3");
    errno = 0;
    gzFile z = gzopen(p, "rb");
    CHECKF(!z && errno == EPERM, "zlib opened a refused node (errno %d)", errno);
    if (z) gzclose(z);
    path(p, "nvidia1");
    z = gzopen(p, "rb");
    CHECK(z != NULL);
    if (z) {
        char buf[16] = {0};
        CHECK(gzread(z, buf, sizeof buf - 1) == 7 && !strcmp(buf, "nvidia1"));
        gzclose(z);
    }
    /* rank 0 keeps the first node */
    CHECK(vx__tool_gpu_only_at(prefix, 0) == 0);
    CHECK(try_open("nvidia0", 0) == 0 && try_open("nvidia1", 0) == EPERM);
    vx_tool_mpi_gpu_all();
    CHECK(try_open("nvidia0", 0) == 0 && try_open("nvidia1", 0) == 0 && try_open("nvidia3", 1) == 0);
}

static void test_nothing_to_leave_out(void) {
    char prefix[300];
    path(prefix, "solo");
    touch("solo0");
    CHECK(vx__tool_gpu_only_at(prefix, 0) == -1); /* one GPU: nothing refused */
    CHECK(try_open("solo0", 0) == 0);
    path(prefix, "nvidia");
    CHECK(vx__tool_gpu_only_at(prefix, -1) == -1); /* rank unknown */
    CHECK(try_open("nvidia3", 0) == 0);
}

static void test_create_mode(void) {
    char p[300];
    path(p, "nvidia0");
    CHECK(vx__tool_gpu_only_at(p, 0) == -1); /* no nodes named nvidia0N */
    mode_t old = umask(0);
    path(p, "made");
    int fd = open(p, O_CREAT | O_WRONLY | O_EXCL, 0640);
    CHECK(fd >= 0);
    if (fd >= 0) close(fd);
    struct stat s;
    CHECK(stat(p, &s) == 0 && (s.st_mode & 0777) == 0640);
    fd = openat(AT_FDCWD, p, O_CREAT | O_WRONLY | O_EXCL, 0600);
    CHECK(fd < 0 && errno == EEXIST);
    umask(old);
}

int main(void) {
    snprintf(dir, sizeof dir, "/tmp/vx_gpu_only_XXXXXX");
    if (!mkdtemp(dir)) return 1;
    RUN(test_keeps_one_node);
    RUN(test_nothing_to_leave_out);
    RUN(test_create_mode);
    const char* names[] = {"nvidia0", "nvidia1", "nvidia3", "nvidiactl", "nvidia1x", "solo0", "made"};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
        char p[300];
        path(p, names[i]);
        unlink(p);
    }
    rmdir(dir);
    return vx_test_finish();
}
