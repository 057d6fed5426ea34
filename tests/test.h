/* tests/test.h - a tiny test runner: CHECK records failures and goes on,
 * REQUIRE stops the current test; main() prints "N passed, N failed". */
#ifndef VX_TEST_H
#define VX_TEST_H
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static int vx_t_failed_checks;
static int vx_t_cur_failed;
static int vx_t_pass, vx_t_fail, vx_t_skip;

#define CHECK(cond)                                                              \
    do {                                                                         \
        if (!(cond)) {                                                           \
            fprintf(stderr, "%s:%d: CHECK failed: %s\n", __FILE__, __LINE__, #cond); \
            vx_t_failed_checks++;                                                \
            vx_t_cur_failed = 1;                                                 \
        }                                                                        \
    } while (0)
#define CHECKF(cond, ...)                                                        \
    do {                                                                         \
        if (!(cond)) {                                                           \
            fprintf(stderr, "%s:%d: CHECK failed: %s: ", __FILE__, __LINE__, #cond); \
            fprintf(stderr, __VA_ARGS__);                                        \
            fprintf(stderr, "\n");                                               \
            vx_t_failed_checks++;                                                \
            vx_t_cur_failed = 1;                                                 \
        }                                                                        \
    } while (0)
#define REQUIRE(cond)                                                            \
    do {                                                                         \
        if (!(cond)) {                                                           \
            fprintf(stderr, "%s:%d: REQUIRE failed: %s\n", __FILE__, __LINE__, #cond); \
            vx_t_cur_failed = 1;                                                 \
            return;                                                              \
        }                                                                        \
    } while (0)
/* Marks the current test skipped (with a reason) and returns. */
#define SKIP(...)                                                                \
    do {                                                                         \
        fprintf(stderr, "  skipped: ");                                          \
        fprintf(stderr, __VA_ARGS__);                                            \
        fprintf(stderr, "\n");                                                   \
        vx_t_cur_failed = -1;                                                    \
        return;                                                                  \
    } while (0)

/* 1 when fn's name holds one of the comma-separated NAMEs of list; a NAME
 * ending in '$' must be the whole name (test_path_start$ is not
 * test_path_start_deep). */
static inline int vx_t_listed(const char* fn, const char* list) {
    char buf[512];
    snprintf(buf, sizeof buf, "%s", list);
    for (char* t = strtok(buf, ","); t; t = strtok(NULL, ",")) {
        size_t n = strlen(t);
        if (n > 1 && t[n - 1] == '$') {
            t[n - 1] = 0;
            if (!strcmp(fn, t)) return 1;
        } else if (strstr(fn, t)) {
            return 1;
        }
    }
    return 0;
}

/* VX_TEST_ONLY=NAME[,NAME...] runs only the tests whose names hold one of
 * the NAMEs (while iterating on one part, and where ctest splits a binary
 * into entries); VX_TEST_SKIP=NAME[,NAME...] leaves those out (the sanitizer
 * build's trims, tests/CMakeLists.txt vx_sanitize_trim): 1 to run, 0 not
 * asked for, -1 left out by VX_TEST_SKIP (RUN says so). */
static inline int vx_t_selected(const char* fn) {
    const char* only = getenv("VX_TEST_ONLY");
    const char* skip = getenv("VX_TEST_SKIP");
    if (skip && *skip && vx_t_listed(fn, skip)) return -1;
    return !only || !*only || vx_t_listed(fn, only);
}

/* Seconds (C11 timespec_get: test.h comes after headers that may not ask for
 * POSIX): each test's line gives its time, so the suite's slow parts can be
 * found in a ctest log (CI has a time limit). */
static inline double vx_t_now(void) {
    struct timespec ts;
    if (timespec_get(&ts, TIME_UTC) != TIME_UTC) return 0.0;
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

#define RUN(fn)                                                                  \
    do {                                                                         \
        int vx_t_sel = vx_t_selected(#fn);                                       \
        if (vx_t_sel < 0) fprintf(stderr, "[ left ] %s (VX_TEST_SKIP)\n", #fn);   \
        if (vx_t_sel <= 0) break;                                                \
        vx_t_cur_failed = 0;                                                     \
        fprintf(stderr, "[ run  ] %s\n", #fn);                                   \
        double vx_t_t0 = vx_t_now();                                             \
        fn();                                                                    \
        double vx_t_s = vx_t_now() - vx_t_t0;                                    \
        if (vx_t_cur_failed > 0) { vx_t_fail++; fprintf(stderr, "[ FAIL ] %s (%.1f s)\n", #fn, vx_t_s); } \
        else if (vx_t_cur_failed < 0) { vx_t_skip++; fprintf(stderr, "[ skip ] %s (%.1f s)\n", #fn, vx_t_s); } \
        else { vx_t_pass++; fprintf(stderr, "[  ok  ] %s (%.1f s)\n", #fn, vx_t_s); } \
    } while (0)

/* Prints the closing line and gives main's return value. */
static inline int vx_test_finish(void) {
    printf("%d passed, %d failed, %d skipped\n", vx_t_pass, vx_t_fail, vx_t_skip);
    return vx_t_fail ? 1 : 0;
}

/* A file's bytes (free them) with a 0 after them, so that a text file is a
 * string; *n (may be NULL) their count. NULL when the file cannot be read. */
static inline char* vx_test_slurp(const char* path, size_t* n) {
    FILE* f = fopen(path, "rb");
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    long size = ftell(f);
    fseek(f, 0, SEEK_SET);
    char* b = size >= 0 ? (char*)malloc((size_t)size + 1) : NULL;
    if (b && fread(b, 1, (size_t)size, f) != (size_t)size) free(b), b = NULL;
    fclose(f);
    if (b) {
        b[size] = 0;
        if (n) *n = (size_t)size;
    }
    return b;
}

/* Path of a corpus file, or NULL (the test should SKIP) when absent. */
static inline const char* vx_test_corpus(const char* rel) {
    static char buf[4096];
    const char* dir = getenv("VX_CORPUS_DIR");
#ifdef VX_CORPUS_DIR_DEFAULT
    if (!dir) dir = VX_CORPUS_DIR_DEFAULT;
#endif
    if (!dir) return NULL;
    snprintf(buf, sizeof buf, "%s/%s", dir, rel);
    FILE* f = fopen(buf, "rb");
    if (!f) return NULL;
    fclose(f);
    return buf;
}
#endif
