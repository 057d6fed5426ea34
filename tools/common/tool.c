/* tools/common/tool.c */
#define _POSIX_C_SOURCE 200809L
#include "tools/common/tool.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdatomic.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

const char* vx_tool_name = "voxkit";

void vx_tool_init(int argc, char** argv) {
    if (argc > 0 && argv[0]) {
        const char* s = strrchr(argv[0], '/');
        vx_tool_name = s ? s + 1 : argv[0];
    }
}

/* "file: " before a message, or nothing where there is no file or the
 * message names it first already (the library's file functions prefix
 * their own errors with the path: a tool that passes it too would print
 * it twice) */
bool vx_tool_names_file(const char* file, const char* msg) {
    size_t n = file ? strlen(file) : 0;
    return n && msg && strncmp(msg, file, n) == 0 && msg[n] == ':';
}

static const char* file_sep(const char* file, const char* msg, const char** sep) {
    bool named = !file || !*file || vx_tool_names_file(file, msg);
    *sep = named ? "" : ": ";
    return named ? "" : file;
}

int vx_tool_error(const char* file, const vx_error* err) {
    const char* msg = err ? err->msg : "error";
    const char* sep;
    const char* f = file_sep(file, msg, &sep);
    if (err && err->offset != VX_NO_OFFSET && !strstr(err->msg, "byte"))
        fprintf(stderr, "%s: %s%s%s (at byte %llu)\n", vx_tool_name, f, sep, msg, (unsigned long long)err->offset);
    else
        fprintf(stderr, "%s: %s%s%s\n", vx_tool_name, f, sep, msg);
    return 1;
}

int vx_tool_error_budget(const char* file, const vx_error* err, const vx_budget* b) {
    if (!b || !b->refused) return vx_tool_error(file, err);
    fprintf(stderr, "%s: %s%sneeds more than --max-memory %s (a block of %s refused): %s\n", vx_tool_name,
            file ? file : "", file ? ": " : "", vx_tool_bytes(b->limit), vx_tool_bytes(b->refused),
            err ? err->msg : "error");
    return 1;
}

/* "tool: <message>" and a newline on stderr */
static void error_line(const char* fmt, va_list ap) {
    fprintf(stderr, "%s: ", vx_tool_name);
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
}

int vx_tool_errorf(const char* fmt, ...) {
    va_list ap;
    va_start(ap, fmt);
    error_line(fmt, ap);
    va_end(ap);
    return 1;
}

_Noreturn void vx_tool_usage_error(void (*usage)(int status), const char* fmt, ...) {
    va_list ap;
    va_start(ap, fmt);
    error_line(fmt, ap);
    va_end(ap);
    usage(2);
    exit(2); /* usage() does not return; this keeps the contract if it ever did */
}

const char* vx_tool_arg(int argc, char** argv, int* i, void (*usage)(int status)) {
    if (*i + 1 >= argc) vx_tool_usage_error(usage, "option %s needs an argument", argv[*i]);
    return argv[++*i];
}

/* ---- progress bar ---------------------------------------------------------- */

/* The bar's state: the library reports progress from one thread at a time
 * (the caller's, or a worker under the library's lock: probes/bake.c), but
 * the logger (log_func) may run on another (a device opened on a thread of
 * its own, gpu_open.c) and ends the bar too: atomics, so that no access is
 * a data race (at worst the bar is drawn once more). */
static _Atomic double bar_last;
static atomic_bool bar_shown;

static bool bar_func(void* user, const char* stage, uint64_t done, uint64_t total) {
    (void)user;
    double now = vx_time_now();
    if (done < total && now - atomic_load(&bar_last) < 0.1) return true;
    atomic_store(&bar_last, now);
    double f = total ? (double)done / (double)total : 1.0;
    if (f > 1) f = 1;
    int w = 30, fill = (int)(f * w);
    char bar[40];
    for (int i = 0; i < w; i++) bar[i] = i < fill ? '=' : (i == fill ? '>' : ' ');
    bar[w] = 0;
    fprintf(stderr, "\r%s: [%s] %3d%% %-24.24s", vx_tool_name, bar, (int)(f * 100), stage ? stage : "");
    fflush(stderr);
    atomic_store(&bar_shown, true);
    return true;
}

vx_progress vx_tool_progress(bool quiet) {
    vx_progress p = {0};
    if (!quiet && isatty(STDERR_FILENO)) p.func = bar_func;
    atomic_store(&bar_last, 0.0);
    return p;
}

void vx_tool_progress_done(void) {
    if (atomic_exchange(&bar_shown, false)) fprintf(stderr, "\r%*s\r", 80, "");
}

/* ---- formatting ------------------------------------------------------------- */

/* the formatters' buffers are per thread: a progress function may format
 * on a worker thread while the main thread formats too */
const char* vx_tool_num(uint64_t v) {
    static _Thread_local char slots[4][32];
    static _Thread_local unsigned next;
    char* out = slots[next++ & 3];
    char tmp[32];
    int n = snprintf(tmp, sizeof tmp, "%llu", (unsigned long long)v);
    int j = 0;
    for (int i = 0; i < n; i++) {
        out[j++] = tmp[i];
        int left = n - 1 - i;
        if (left > 0 && left % 3 == 0) out[j++] = ',';
    }
    out[j] = 0;
    return out;
}

const char* vx_tool_bytes(uint64_t v) {
    static _Thread_local char slots[4][32];
    static _Thread_local unsigned next;
    char* out = slots[next++ & 3];
    if (v < 1024) snprintf(out, 32, "%llu B", (unsigned long long)v);
    else if (v < 1024 * 1024) snprintf(out, 32, "%.1f KiB", v / 1024.0);
    else if (v < 1024ull * 1024 * 1024) snprintf(out, 32, "%.1f MiB", v / 1048576.0);
    else snprintf(out, 32, "%.2f GiB", v / 1073741824.0);
    return out;
}

bool vx_tool_parse_bytes(const char* s, uint64_t* out) {
    if (!s || !isdigit((unsigned char)*s)) return false;
    char* end;
    errno = 0;
    unsigned long long v = strtoull(s, &end, 10);
    if (errno) return false;
    int shift = 0;
    if (*end) {
        const char* units = "KMGT";
        const char* u = strchr(units, toupper((unsigned char)*end));
        if (!u || end[1]) return false;
        shift = 10 * (int)(u - units + 1);
    }
    if (v > (UINT64_C(1) << 62) >> shift) return false;
    *out = (uint64_t)v << shift;
    return true;
}

bool vx_tool_parse_u32(const char* s, uint32_t* out) {
    if (!s || !isdigit((unsigned char)*s)) return false;
    errno = 0;
    char* end;
    unsigned long long v = strtoull(s, &end, 10);
    if (errno || *end || v > UINT32_MAX) return false;
    *out = (uint32_t)v;
    return true;
}

bool vx_tool_parse_double(const char* s, double* out) {
    if (!s || !*s) return false;
    errno = 0;
    char* end;
    double v = strtod(s, &end);
    if (errno || *end || !isfinite(v)) return false;
    *out = v;
    return true;
}

bool vx_tool_parse_vec(const char* s, double* v, int n) { return vx_parse_doubles(s, v, n); }

static void log_func(void* user, vx_log_level level, const char* id, const char* msg) {
    bool verbose = user != NULL;
    if (level == VX_LOG_INFO && !verbose) return;
    vx_tool_progress_done();
    fprintf(stderr, "%s: %s: %s [%s]\n", vx_tool_name, level == VX_LOG_WARN ? "warning" : "info", msg, id);
}

vx_logger vx_tool_logger(bool verbose) {
    vx_logger l = {log_func, verbose ? (void*)1 : NULL};
    return l;
}

const char* vx_tool_ext(const char* path) {
    static _Thread_local char ext[16];
    const char* slash = strrchr(path, '/');
    const char* dot = strrchr(path, '.');
    if (!dot || (slash && dot < slash)) return "";
    size_t i = 0;
    for (dot++; *dot && i + 1 < sizeof ext; dot++) ext[i++] = (char)tolower((unsigned char)*dot);
    ext[i] = 0;
    return ext;
}

bool vx_tool_gi_method_known(const char* name) {
    static const char* const known[] = {"probes", "lightfield", "pathtrace", "photons", "cones"};
    for (size_t i = 0; i < sizeof known / sizeof known[0]; i++)
        if (!strcmp(name, known[i])) return true;
    return false;
}

bool vx_tool_gi_method_needs_probes(const char* name) { return !strcmp(name, "probes") || !strcmp(name, "lightfield"); }
