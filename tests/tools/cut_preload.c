/* tests/tools/cut_preload.c - an LD_PRELOAD module for test_tools_cut: a file
 * cut short by "another process" while a tool reads it, at a chosen point of
 * the read, without any hook in the tools or the library.
 *
 * The library reads .svo files with pread into its own buffers (svo/svo_io.c:
 * fsrc_read) and vx_file_read (svo_info) with fread (whose own reads are
 * glibc-internal calls no preload sees), so the moment of a cut is a pread or
 * an fread. This module wraps pread, pread64, read and fread: the first call
 * on the file named by VX_CUT_PATH whose offset (read, fread: the file
 * position) is at least VX_CUT_FROM first truncates that file to VX_CUT_TO
 * bytes, then reads as the call asked; later calls pass through. It is the same as a process
 * that shortens the file between the tool's open (size taken) and that read,
 * deterministically. VX_CUT_FROM = 0 cuts at the first read of the file (a
 * whole read); the NODE section's offset cuts when the model reader takes its
 * first model's stream (the header, the table and the other sections were
 * read at open). With VX_CUT_AGAIN=1 the cut waits for the first such call
 * at an offset that an earlier call on the file already read from: a byte
 * range read a second time, as svo_render --host-budget reads a page's
 * model again after the first pass (a cut mid-run, after the pass).
 *
 * Why a preload and not a hook: the library's on_open hook (vx_svo_read_desc)
 * serves its own tests; a tool-level hook would need an environment variable
 * read by the tools (a test-only path in every tool) and a file cut by a
 * child process at a random time tests nothing reliably. The once-only flag
 * below is this test module's state, not the library's or a tool's. */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <limits.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/types.h>
#include <unistd.h>

typedef ssize_t (*pread_fn)(int, void*, size_t, off_t);
typedef ssize_t (*read_fn)(int, void*, size_t);
typedef size_t (*fread_fn)(void*, size_t, size_t, FILE*);

static bool cut_done; /* one cut per process */
/* VX_CUT_AGAIN: the offsets the file's reads started at (a test's small
 * files: a fixed table, further offsets not remembered) */
static off_t seen[4096];
static unsigned nseen;

/* Whether fd is the file VX_CUT_PATH names (compared by its resolved path). */
static bool is_target(int fd, const char** path) {
    const char* want = getenv("VX_CUT_PATH");
    if (!want || !*want) return false;
    char link[64], have[PATH_MAX], real[PATH_MAX];
    snprintf(link, sizeof link, "/proc/self/fd/%d", fd);
    ssize_t n = readlink(link, have, sizeof have - 1);
    if (n <= 0) return false;
    have[n] = 0;
    if (!realpath(want, real)) return false;
    *path = want;
    return strcmp(have, real) == 0;
}

static void maybe_cut(int fd, off_t off) {
    const char* path = NULL;
    if (cut_done || !is_target(fd, &path)) return;
    const char* from = getenv("VX_CUT_FROM");
    const char* to = getenv("VX_CUT_TO");
    if (!to || (long long)off < (from ? atoll(from) : 0)) return;
    const char* again = getenv("VX_CUT_AGAIN");
    if (again && *again == '1') {
        bool before = false;
        for (unsigned i = 0; i < nseen && !before; i++) before = seen[i] == off;
        if (!before) {
            if (nseen < sizeof seen / sizeof seen[0]) seen[nseen++] = off;
            return;
        }
    }
    cut_done = true;
    if (truncate(path, (off_t)atoll(to)) != 0) _exit(99); /* the test sees a status no tool uses */
}

ssize_t pread(int fd, void* buf, size_t n, off_t off) {
    static pread_fn real_pread;
    if (!real_pread) real_pread = (pread_fn)dlsym(RTLD_NEXT, "pread");
    maybe_cut(fd, off);
    return real_pread(fd, buf, n, off);
}

ssize_t pread64(int fd, void* buf, size_t n, off_t off) {
    static pread_fn real_pread64;
    if (!real_pread64) real_pread64 = (pread_fn)dlsym(RTLD_NEXT, "pread64");
    maybe_cut(fd, off);
    return real_pread64(fd, buf, n, off);
}

ssize_t read(int fd, void* buf, size_t n) {
    static read_fn real_read;
    if (!real_read) real_read = (read_fn)dlsym(RTLD_NEXT, "read");
    if (!cut_done && getenv("VX_CUT_PATH")) {
        off_t at = lseek(fd, 0, SEEK_CUR); /* -1 on pipes and sockets: never the target */
        if (at >= 0) maybe_cut(fd, at);
    }
    return real_read(fd, buf, n);
}

size_t fread(void* buf, size_t size, size_t n, FILE* f) {
    static fread_fn real_fread;
    if (!real_fread) real_fread = (fread_fn)dlsym(RTLD_NEXT, "fread");
    if (!cut_done && getenv("VX_CUT_PATH")) {
        long at = ftell(f); /* before stdio buffers anything past it: the tools' first fread of the file */
        if (at >= 0) maybe_cut(fileno(f), (off_t)at);
    }
    return real_fread(buf, size, n, f);
}
