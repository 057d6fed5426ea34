/* tests/fuzz/driver.c - replays a libFuzzer target without libFuzzer.
 *
 * Usage: NAME_replay [-n MUTATIONS] FILE|DIR ...
 * Each seed is fed as is, then MUTATIONS (default 2000) deterministic
 * mutants: byte flips, overwritten 32-bit words (sizes and counts set to
 * 0, 0xFFFFFFFF and near-size values), truncations and splices. Under the
 * sanitizer build this catches what a short fuzzing session would, with no
 * clang needed; real libFuzzer binaries are built with -DVX_FUZZ=ON. */
#define _DEFAULT_SOURCE
#include <dirent.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

static uint64_t rng_state = 0x9E3779B97F4A7C15ull;
static uint64_t rng(void) {
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return rng_state;
}

static long mutations = 2000;
static long runs;

static void run_one(const uint8_t* d, size_t n) {
    /* copy into an exact-size heap block so ASan sees any over-read */
    uint8_t* c = (uint8_t*)malloc(n ? n : 1);
    if (!c) return;
    if (n) memcpy(c, d, n);
    LLVMFuzzerTestOneInput(c, n);
    free(c);
    runs++;
}

static void fuzz_seed(const uint8_t* d, size_t n) {
    run_one(d, n);
    if (n == 0) return;
    uint8_t* m = (uint8_t*)malloc(n);
    if (!m) return;
    static const uint32_t words[] = {0u, 1u, 0x7FFFFFFFu, 0x80000000u, 0xFFFFFFFFu, 0xFFFFFFFEu, 256u, 257u, 65536u};
    for (long i = 0; i < mutations; i++) {
        memcpy(m, d, n);
        size_t len = n;
        int kind = (int)(rng() % 4);
        int edits = 1 + (int)(rng() % 4);
        for (int e = 0; e < edits; e++) {
            size_t at = (size_t)(rng() % n);
            if (kind == 0) m[at] ^= (uint8_t)(1u << (rng() % 8));
            else if (kind == 1 && at + 4 <= n) {
                uint32_t w = (rng() & 1) ? words[rng() % (sizeof words / sizeof words[0])] : (uint32_t)(n - at + (rng() % 9) - 4);
                memcpy(m + at, &w, 4);
            } else if (kind == 2) len = (size_t)(rng() % n);
            else m[at] = (uint8_t)rng();
        }
        run_one(m, len);
    }
    free(m);
}

static void do_file(const char* path) {
    FILE* f = fopen(path, "rb");
    if (!f) { fprintf(stderr, "cannot open %s\n", path); return; }
    fseek(f, 0, SEEK_END);
    long sz = ftell(f);
    fseek(f, 0, SEEK_SET);
    if (sz < 0 || sz > (64l << 20)) { fclose(f); return; }
    uint8_t* d = (uint8_t*)malloc((size_t)sz + 1);
    size_t got = d ? fread(d, 1, (size_t)sz, f) : 0;
    fclose(f);
    if (d && got == (size_t)sz) fuzz_seed(d, got);
    free(d);
}

static void do_path(const char* path) {
    struct stat st;
    if (stat(path, &st) != 0) { fprintf(stderr, "skipping missing seed %s\n", path); return; }
    if (!S_ISDIR(st.st_mode)) { do_file(path); return; }
    DIR* dir = opendir(path);
    if (!dir) return;
    struct dirent* e;
    while ((e = readdir(dir))) {
        if (e->d_name[0] == '.') continue;
        char buf[4096];
        snprintf(buf, sizeof buf, "%s/%s", path, e->d_name);
        do_path(buf);
    }
    closedir(dir);
}

int main(int argc, char** argv) {
    int i = 1;
    if (i + 1 < argc && strcmp(argv[i], "-n") == 0) { mutations = atol(argv[i + 1]); i += 2; }
    for (; i < argc; i++) do_path(argv[i]);
    run_one((const uint8_t*)"", 0);
    printf("replayed %ld inputs\n", runs);
    return 0;
}
