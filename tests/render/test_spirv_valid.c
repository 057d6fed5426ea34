/* tests/render/test_spirv_valid.c - every SPIR-V module the build embeds
 * passes the SPIR-V validator (spirv-val, Debian's spirv-tools) for the
 * environment glslangValidator compiles the kernels for. Twice a kernel
 * variant that glslang compiled was invalid (a `const bool` of `||` over
 * specialisation constants became an OpSpecConstantOp on an id that does not
 * dominate its uses: docs/PERFORMANCE.md, branches lean4 and ray8); lavapipe
 * ran it anyway, the NVIDIA driver crashed or failed the pipeline on the H200
 * and device time was lost. This test catches that on the dev machine.
 *
 * The modules are the embedded headers themselves (glslangValidator --vn
 * output, `0x...` words between the braces), listed by
 * tests/render/spirv_valid.cmake from the sources of every target, so a kernel
 * added anywhere is checked without editing this file. Each is written to a
 * temporary .spv and validated; the test fails naming each invalid module and
 * the validator's message, and skips when spirv-val is absent. With
 * arguments it checks those files instead (headers or .spv binaries), e.g. a
 * variant's kernel before it goes into a GPU payload.
 *
 * What this does not see: a module valid as compiled but invalid once
 * specialised (photons' zero-length array, docs/PERFORMANCE.md); spirv-val
 * checks the default values of the specialisation constants only. */
#define _POSIX_C_SOURCE 200809L /* popen, mkdtemp */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "tests/test.h"

#include "spirv_modules.h" /* VX_SPIRV_VAL, VX_SPIRV_ENV, VX_SPIRV_MODULES (tests/render/spirv_valid.cmake) */

static const char* const modules[] = {VX_SPIRV_MODULES NULL};
static int g_argc;
static char** g_argv;

/* The whole file, NUL-terminated, or NULL. */
static char* read_all(const char* path, size_t* len) {
    FILE* f = fopen(path, "rb");
    if (!f) return NULL;
    size_t cap = 1 << 16, n = 0;
    char* buf = malloc(cap);
    while (buf) {
        n += fread(buf + n, 1, cap - n - 1, f);
        if (n < cap - 1) break;
        char* nb = cap > (SIZE_MAX >> 2) ? NULL : realloc(buf, cap * 2);
        if (!nb) free(buf);
        buf = nb, cap *= 2;
    }
    if (ferror(f) && buf) free(buf), buf = NULL;
    fclose(f);
    if (buf) buf[n] = 0, *len = n;
    return buf;
}

/* The words of an embedded header (the hex literals between its first `{`
 * and the `}` after it) into a little-endian byte image in out; 0 and a
 * reason when the text is not such an array. */
static int header_words(const char* text, uint8_t** out, size_t* bytes, const char** why) {
    const char* p = strchr(text, '{');
    const char* end = p ? strchr(p, '}') : NULL;
    if (!p || !end) return *why = "no array between braces", 0;
    size_t cap = (size_t)(end - p) / 3 + 4, n = 0; /* each word takes at least "0x0," */
    uint8_t* b = malloc(cap * 4);
    if (!b) return *why = "out of memory", 0;
    for (p++; p < end;) {
        if (p[0] == '0' && (p[1] == 'x' || p[1] == 'X')) {
            char* q;
            unsigned long v = strtoul(p, &q, 16);
            if (q <= p + 2 || q > end || v > 0xFFFFFFFFul || n == cap) return free(b), *why = "bad word", 0;
            for (int k = 0; k < 4; k++) b[4 * n + k] = (uint8_t)(v >> (8 * k));
            n++, p = q;
        } else if (p[0] == ',' || p[0] == ' ' || p[0] == '\t' || p[0] == '\n' || p[0] == '\r') {
            p++;
        } else {
            return free(b), *why = "not a list of hex words", 0;
        }
    }
    if (n < 5 || b[0] != 0x03 || b[1] != 0x02 || b[2] != 0x23 || b[3] != 0x07)
        return free(b), *why = "no SPIR-V header (magic 0x07230203)", 0;
    *out = b, *bytes = 4 * n;
    return 1;
}

/* Validates one module (an embedded header, or a .spv file as it is); 1 when
 * valid, else 0 with the reason (the validator's output) printed. */
static int validate(const char* path, const char* tmpdir) {
    size_t len = 0;
    char* text = read_all(path, &len);
    if (!text) {
        fprintf(stderr, "  %s: cannot read (listed by the build but not built?)\n", path);
        return 0;
    }
    size_t plen = strlen(path);
    int is_header = plen > 2 && !strcmp(path + plen - 2, ".h");
    char spv[4096];
    const char* file = path;
    if (is_header) {
        uint8_t* bytes = NULL;
        size_t nb = 0;
        const char* why = "";
        int ok = header_words(text, &bytes, &nb, &why);
        free(text);
        if (!ok) {
            fprintf(stderr, "  %s: not an embedded SPIR-V module: %s\n", path, why);
            return 0;
        }
        snprintf(spv, sizeof spv, "%s/module.spv", tmpdir);
        FILE* f = fopen(spv, "wb");
        int wrote = f && fwrite(bytes, 1, nb, f) == nb;
        if (f && fclose(f)) wrote = 0;
        free(bytes);
        if (!wrote) {
            fprintf(stderr, "  %s: cannot write %s\n", path, spv);
            return 0;
        }
        file = spv;
    } else {
        free(text);
    }
    /* the paths come from the build tree and the command line; quoted for the shell, a quote in them refused */
    if (strchr(file, '\'')) {
        fprintf(stderr, "  %s: a quote in the path\n", path);
        return 0;
    }
    char cmd[8192];
    snprintf(cmd, sizeof cmd, "'%s' --target-env %s '%s' 2>&1", VX_SPIRV_VAL, VX_SPIRV_ENV, file);
    FILE* p = popen(cmd, "r");
    if (!p) {
        fprintf(stderr, "  %s: cannot run %s\n", path, VX_SPIRV_VAL);
        return 0;
    }
    char msg[4096];
    size_t m = fread(msg, 1, sizeof msg - 1, p);
    msg[m] = 0;
    while (fread(cmd, 1, sizeof cmd, p) > 0) {} /* the rest of a long message: read so the validator can exit */
    int st = pclose(p);
    if (file == spv) remove(spv);
    if (st == -1 || !WIFEXITED(st) || WEXITSTATUS(st) != 0) {
        fprintf(stderr, "  INVALID %s (spirv-val --target-env %s, status %d):\n%s\n", path, VX_SPIRV_ENV,
                st == -1 || !WIFEXITED(st) ? -1 : WEXITSTATUS(st), msg);
        return 0;
    }
    return 1;
}

static void test_modules_valid(void) {
    if (!*VX_SPIRV_VAL || access(VX_SPIRV_VAL, X_OK) != 0)
        SKIP("spirv-val not found when the build was configured (Debian 12: spirv-tools; scripts/install-deps.sh)");
    const char* base = getenv("TMPDIR");
    char tmpdir[4096];
    snprintf(tmpdir, sizeof tmpdir, "%s/vx_spirv_valid_XXXXXX", base && *base ? base : "/tmp");
    REQUIRE(mkdtemp(tmpdir));
    int n = 0, bad = 0;
    if (g_argc > 1) {
        for (int i = 1; i < g_argc; i++) n++, bad += !validate(g_argv[i], tmpdir);
    } else {
        for (const char* const* m = modules; *m; m++) n++, bad += !validate(*m, tmpdir);
    }
    rmdir(tmpdir);
    fprintf(stderr, "  %d modules, %d invalid\n", n, bad);
    CHECKF(n > 0, "no module to check");
    CHECKF(bad == 0, "%d of %d SPIR-V modules invalid (named above)", bad, n);
}

/* The parser itself: a header's words come out little-endian, and text that
 * is not such an array is refused, not read past. */
static void test_header_parse(void) {
    uint8_t* b = NULL;
    size_t nb = 0;
    const char* why = "";
    REQUIRE(header_words("const uint32_t a[] = {\n\t0x07230203,0x00010300,0x0008000b,0x1,0xFFFFFFFF\n};", &b, &nb, &why));
    CHECK(nb == 20);
    CHECK(b[0] == 0x03 && b[3] == 0x07 && b[4] == 0x00 && b[6] == 0x01 && b[12] == 0x01 && b[19] == 0xFF);
    free(b);
    CHECK(!header_words("const uint32_t a[] = {0x07230203,0x1};", &b, &nb, &why));        /* too short */
    CHECK(!header_words("const uint32_t a[] = {0x12345678,0,0,0,0};", &b, &nb, &why));    /* no magic */
    CHECK(!header_words("{0x07230203,0x1,0x2,0x3,0x4,foo}", &b, &nb, &why));              /* junk */
    CHECK(!header_words("{0x07230203,0x1,0x2,0x3,0x1FFFFFFFF}", &b, &nb, &why));          /* over 32 bits */
    CHECK(!header_words("{0x07230203,0x1,0x2,0x3,0x4", &b, &nb, &why));                   /* unclosed */
    CHECK(!header_words("", &b, &nb, &why));
}

int main(int argc, char** argv) {
    g_argc = argc, g_argv = argv;
    RUN(test_header_parse);
    RUN(test_modules_valid);
    return vx_test_finish();
}
