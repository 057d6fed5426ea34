/* tests/test.h - a tiny test runner: CHECK records failures and goes on,
 * REQUIRE stops the current test; main() prints "N passed, N failed". */
#ifndef VX_TEST_H
#define VX_TEST_H
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

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

/* VX_TEST_ONLY=NAME[,NAME...] runs only the tests whose names hold one of
 * the NAMEs (while iterating on one part; ctest sets nothing) */
static inline int vx_t_selected(const char* fn) {
    const char* only = getenv("VX_TEST_ONLY");
    if (!only || !*only) return 1;
    char buf[256];
    snprintf(buf, sizeof buf, "%s", only);
    for (char* t = strtok(buf, ","); t; t = strtok(NULL, ","))
        if (strstr(fn, t)) return 1;
    return 0;
}

#define RUN(fn)                                                                  \
    do {                                                                         \
        if (!vx_t_selected(#fn)) break;                                          \
        vx_t_cur_failed = 0;                                                     \
        fprintf(stderr, "[ run  ] %s\n", #fn);                                   \
        fn();                                                                    \
        if (vx_t_cur_failed > 0) { vx_t_fail++; fprintf(stderr, "[ FAIL ] %s\n", #fn); } \
        else if (vx_t_cur_failed < 0) { vx_t_skip++; fprintf(stderr, "[ skip ] %s\n", #fn); } \
        else { vx_t_pass++; fprintf(stderr, "[  ok  ] %s\n", #fn); }              \
    } while (0)

/* Prints the closing line and gives main's return value. */
static inline int vx_test_finish(void) {
    printf("%d passed, %d failed, %d skipped\n", vx_t_pass, vx_t_fail, vx_t_skip);
    return vx_t_fail ? 1 : 0;
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
