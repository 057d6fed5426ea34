/* svo/core.c - results, errors, allocation, buffers, CRC-32 and file I/O. */
#define _POSIX_C_SOURCE 200809L
#include "svo/core.h"

#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <limits.h>
#include <pthread.h>
#include <signal.h>
#include <stdarg.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

const char* vx_result_str(vx_result r) {
    switch (r) {
    case VX_OK: return "ok";
    case VX_ERR_INVALID_ARG: return "invalid argument";
    case VX_ERR_TRUNCATED: return "truncated input";
    case VX_ERR_BAD_FORMAT: return "malformed input";
    case VX_ERR_UNSUPPORTED: return "unsupported feature";
    case VX_ERR_LIMIT: return "limit exceeded";
    case VX_ERR_NOMEM: return "out of memory";
    case VX_ERR_IO: return "i/o error";
    case VX_ERR_GPU: return "gpu error";
    default: return "unknown error";
    }
}

vx_result vx_fail(vx_error* err, vx_result code, uint64_t offset, const char* fmt, ...) {
    if (err) {
        err->code = code;
        err->offset = offset;
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(err->msg, sizeof err->msg, fmt, ap);
        va_end(ap);
    }
    return code;
}

void vx_error_prefix(vx_error* err, const char* prefix) {
    if (!err || !prefix) return;
    /* build into a larger buffer, then cut to fit: context first, detail last */
    char tmp[2 * sizeof err->msg];
    snprintf(tmp, sizeof tmp, "%s: %s", prefix, err->msg);
    memcpy(err->msg, tmp, sizeof err->msg - 1);
    err->msg[sizeof err->msg - 1] = 0;
}

void vx_log(const vx_logger* log, vx_log_level level, const char* id, const char* fmt, ...) {
    if (!log || !log->func) return;
    char msg[1024]; /* validation layer messages run to several hundred characters */
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    log->func(log->user_data, level, id, msg);
}

bool vx_progress_report(const vx_progress* p, const char* stage, uint64_t done, uint64_t total) {
    if (!p || !p->func) return true;
    return p->func(p->user_data, stage, done, total);
}

void* vx_alloc(const vx_allocator* a, size_t size) {
    if (size == 0) size = 1;
    if (a && a->alloc) return a->alloc(a->user_data, size);
    return malloc(size);
}

void* vx_calloc(const vx_allocator* a, size_t count, size_t size) {
    size_t n;
    if (!vx_mul_size(count, size, &n)) return NULL;
    void* p = vx_alloc(a, n);
    if (p) memset(p, 0, n ? n : 1);
    return p;
}

void vx_free(const vx_allocator* a, void* p) {
    if (!p) return;
    if (a && a->free) a->free(a->user_data, p);
    else free(p);
}

enum { BUDGET_HEAD = 16 }; /* keeps the alignment of malloc's blocks */

static void* budget_alloc(void* user, size_t size) {
    vx_budget* b = user;
    size_t total;
    if (!vx_add_size(size, BUDGET_HEAD, &total)) return NULL;
    size_t used = __atomic_load_n(&b->used, __ATOMIC_RELAXED);
    do {
        if (b->limit && (total > b->limit || used > b->limit - total)) {
            size_t zero = 0;
            __atomic_compare_exchange_n(&b->refused, &zero, size, false, __ATOMIC_RELAXED, __ATOMIC_RELAXED);
            return NULL;
        }
    } while (!__atomic_compare_exchange_n(&b->used, &used, used + total, true, __ATOMIC_RELAXED, __ATOMIC_RELAXED));
    size_t now = used + total, peak = __atomic_load_n(&b->peak, __ATOMIC_RELAXED);
    while (now > peak && !__atomic_compare_exchange_n(&b->peak, &peak, now, true, __ATOMIC_RELAXED, __ATOMIC_RELAXED)) {
    }
    unsigned char* p = vx_alloc(b->parent, total);
    if (!p) {
        __atomic_fetch_sub(&b->used, total, __ATOMIC_RELAXED);
        return NULL;
    }
    memcpy(p, &total, sizeof total);
    return p + BUDGET_HEAD;
}

static void budget_free(void* user, void* ptr) {
    vx_budget* b = user;
    unsigned char* p = (unsigned char*)ptr - BUDGET_HEAD;
    size_t total;
    memcpy(&total, p, sizeof total);
    __atomic_fetch_sub(&b->used, total, __ATOMIC_RELAXED);
    vx_free(b->parent, p);
}

void vx_budget_init(vx_budget* b, size_t limit, const vx_allocator* parent) {
    memset(b, 0, sizeof *b);
    b->allocator = (vx_allocator){budget_alloc, budget_free, b};
    b->parent = parent;
    b->limit = limit;
}

bool vx_grow(const vx_allocator* a, void** p, size_t* cap, size_t need, size_t size) {
    if (need <= *cap) return true;
    size_t ncap = *cap ? *cap : 16;
    while (ncap < need) {
        if (ncap > SIZE_MAX / 2) return false;
        ncap *= 2;
    }
    size_t bytes, old;
    if (!vx_mul_size(ncap, size, &bytes)) return false;
    if (!a || (!a->alloc && !a->free)) {
        /* the default allocator: realloc can move a large block's pages
         * instead of copying them, so growing a file-sized buffer does not
         * briefly need twice its memory */
        void* np = realloc(*p, bytes);
        if (!np) return false;
        *p = np;
        *cap = ncap;
        return true;
    }
    void* np = vx_alloc(a, bytes);
    if (!np) return false;
    old = *cap * size; /* cannot overflow: it was allocated before */
    if (*p && old) memcpy(np, *p, old);
    vx_free(a, *p);
    *p = np;
    *cap = ncap;
    return true;
}

/* ---- buffers ---------------------------------------------------------------- */

bool vx_buf_append(vx_buf* b, const void* data, size_t n) {
    if (b->failed) return false;
    size_t need;
    if (!vx_add_size(b->size, n, &need) || !vx_grow(b->alloc, (void**)&b->data, &b->cap, need, 1)) {
        b->failed = true;
        return false;
    }
    if (n) memcpy(b->data + b->size, data, n);
    b->size = need;
    return true;
}
bool vx_buf_u8(vx_buf* b, uint8_t v) { return vx_buf_append(b, &v, 1); }
bool vx_buf_u16le(vx_buf* b, uint16_t v) {
    uint8_t t[2] = {(uint8_t)v, (uint8_t)(v >> 8)};
    return vx_buf_append(b, t, 2);
}
void vx_buf_put_u32le(uint8_t* d, uint32_t v) {
    d[0] = (uint8_t)v;
    d[1] = (uint8_t)(v >> 8);
    d[2] = (uint8_t)(v >> 16);
    d[3] = (uint8_t)(v >> 24);
}
bool vx_buf_u32le(vx_buf* b, uint32_t v) {
    uint8_t t[4];
    vx_buf_put_u32le(t, v);
    return vx_buf_append(b, t, 4);
}
bool vx_buf_u64le(vx_buf* b, uint64_t v) { return vx_buf_u32le(b, (uint32_t)v) && vx_buf_u32le(b, (uint32_t)(v >> 32)); }
bool vx_buf_f32le(vx_buf* b, float v) {
    union { float f; uint32_t u; } c = {v};
    return vx_buf_u32le(b, c.u);
}
bool vx_buf_f64le(vx_buf* b, double v) {
    union { double f; uint64_t u; } c = {v};
    return vx_buf_u64le(b, c.u);
}
bool vx_buf_zeros(vx_buf* b, size_t n) {
    static const uint8_t z[64];
    while (n) {
        size_t k = n < sizeof z ? n : sizeof z;
        if (!vx_buf_append(b, z, k)) return false;
        n -= k;
    }
    return true;
}
void vx_buf_free(vx_buf* b) {
    vx_free(b->alloc, b->data);
    b->data = NULL;
    b->size = b->cap = 0;
}

/* ---- CRC-32 -------------------------------------------------------------------- */

/* The slicing-by-8 tables, built once on first use. Written only by
 * crc_init, which pthread_once runs exactly once; POSIX lists pthread_once
 * among the calls that synchronize memory (XBD 4.12), so every thread that
 * returns from it sees the whole table, and nothing writes the table after:
 * no data race (a plain "ready" flag was one, however benign its writes). */
static uint32_t crc_table[8][256];
static pthread_once_t crc_once = PTHREAD_ONCE_INIT;

static void crc_init(void) {
    for (uint32_t i = 0; i < 256; i++) {
        uint32_t c = i;
        for (int k = 0; k < 8; k++) c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
        crc_table[0][i] = c;
    }
    for (uint32_t i = 0; i < 256; i++)
        for (int t = 1; t < 8; t++) crc_table[t][i] = (crc_table[t - 1][i] >> 8) ^ crc_table[0][crc_table[t - 1][i] & 0xFF];
}

uint32_t vx_crc32(uint32_t crc, const void* data, size_t n) {
    (void)pthread_once(&crc_once, crc_init); /* fails only for an invalid once object */
    const uint8_t* p = (const uint8_t*)data;
    uint32_t c = ~crc;
    /* slicing-by-8: sections of tens of MB are checksummed on every read */
    while (n >= 8) {
        uint32_t lo = c ^ ((uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24);
        uint32_t hi = (uint32_t)p[4] | (uint32_t)p[5] << 8 | (uint32_t)p[6] << 16 | (uint32_t)p[7] << 24;
        c = crc_table[7][lo & 0xFF] ^ crc_table[6][(lo >> 8) & 0xFF] ^ crc_table[5][(lo >> 16) & 0xFF] ^
            crc_table[4][lo >> 24] ^ crc_table[3][hi & 0xFF] ^ crc_table[2][(hi >> 8) & 0xFF] ^
            crc_table[1][(hi >> 16) & 0xFF] ^ crc_table[0][hi >> 24];
        p += 8;
        n -= 8;
    }
    while (n--) c = crc_table[0][(c ^ *p++) & 0xFF] ^ (c >> 8);
    return ~c;
}

/* ---- files ----------------------------------------------------------------------- */

vx_result vx_file_read(const char* path, const vx_allocator* a, uint64_t max_bytes, uint8_t** out_data,
                       size_t* out_size, vx_error* err) {
    if (!path || !out_data || !out_size) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "null argument");
    if (max_bytes == 0) max_bytes = (uint64_t)4 << 30;
    FILE* f = fopen(path, "rb");
    if (!f) return vx_fail(err, VX_ERR_IO, VX_NO_OFFSET, "cannot open: %s", strerror(errno));
    struct stat st;
    if (fstat(fileno(f), &st) != 0 || !S_ISREG(st.st_mode)) {
        fclose(f);
        return vx_fail(err, VX_ERR_IO, VX_NO_OFFSET, "not a regular file");
    }
    if ((uint64_t)st.st_size > max_bytes || (uint64_t)st.st_size > SIZE_MAX) {
        fclose(f);
        return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "file is %llu bytes, limit is %llu",
                       (unsigned long long)st.st_size, (unsigned long long)max_bytes);
    }
    size_t n = (size_t)st.st_size;
    uint8_t* d = (uint8_t*)vx_alloc(a, n);
    if (!d) {
        fclose(f);
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "cannot allocate %zu bytes", n);
    }
    size_t got = n ? fread(d, 1, n, f) : 0;
    int bad = ferror(f);
    fclose(f);
    if (got != n || bad) {
        vx_free(a, d);
        if (bad) return vx_fail(err, VX_ERR_IO, VX_NO_OFFSET, "read error");
        /* a short read without an error: another process cut the file after its size was taken */
        return vx_fail(err, VX_ERR_TRUNCATED, got, "the file ends at byte %zu, it had %zu bytes when opened (cut short while it was read)",
                       got, n);
    }
    *out_data = d;
    *out_size = n;
    return VX_OK;
}

/* A writer killed between creating its temporary file and the rename
 * (SIGKILL, a crash) leaves PATH.tmpPID (and PATH.tmpPID.sections from the
 * .svo writer) behind; nothing else would ever remove it. The next write of
 * PATH removes those whose process is gone: kill(pid, 0) fails with ESRCH.
 * A live writer's files are kept (also one in another PID namespace that
 * happens to match a live pid here); one whose pid is unknown here (another
 * host on a shared folder) would lose its temporary file and fail cleanly at
 * its rename, never leave a partial PATH. */
static void remove_stale_tmp(const char* path, const vx_allocator* a) {
    const char* slash = strrchr(path, '/');
    const char* base = slash ? slash + 1 : path;
    size_t dlen = slash ? (size_t)(slash - path) + 1 : 0, blen = strlen(base);
    /* out of memory: nothing is removed this time (the write goes on) */
    char* name = (char*)vx_alloc(a, dlen + 256 + 2);
    if (!name || !blen) {
        vx_free(a, name);
        return;
    }
    memcpy(name, path, dlen);
    name[dlen] = 0;
    DIR* d = opendir(dlen ? name : ".");
    struct dirent* e;
    while (d && (e = readdir(d))) {
        const char* n = e->d_name;
        if (strncmp(n, base, blen) != 0 || strncmp(n + blen, ".tmp", 4) != 0) continue;
        const char* p = n + blen + 4;
        char* end;
        if (*p < '0' || *p > '9') continue;
        long pid = strtol(p, &end, 10);
        if ((*end && strcmp(end, ".sections") != 0) || pid <= 0 || pid == (long)getpid()) continue;
        if (kill((pid_t)pid, 0) == 0 || errno != ESRCH || strlen(n) > 255) continue;
        memcpy(name + dlen, n, strlen(n) + 1);
        remove(name);
    }
    if (d) closedir(d);
    vx_free(a, name);
}

vx_result vx_atomic_open(vx_atomic_file* af, const char* path, const vx_allocator* a, vx_error* err) {
    memset(af, 0, sizeof *af);
    if (!path) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "null path");
    remove_stale_tmp(path, a);
    size_t plen = strlen(path);
    af->alloc = a;
    af->tmp = (char*)vx_alloc(a, plen + 32);
    if (!af->tmp) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory");
    snprintf(af->tmp, plen + 32, "%s.tmp%ld", path, (long)getpid());
    af->f = fopen(af->tmp, "wb");
    if (!af->f) {
        vx_result r = vx_fail(err, VX_ERR_IO, VX_NO_OFFSET, "cannot create %s: %s", af->tmp, strerror(errno));
        vx_free(a, af->tmp);
        af->tmp = NULL;
        return r;
    }
    af->path = path;
    return VX_OK;
}

bool vx_atomic_write(vx_atomic_file* af, const void* data, size_t n) {
    if (af->failed_errno) return false;
    if (n && fwrite(data, 1, n, (FILE*)af->f) != n) af->failed_errno = errno ? errno : EIO;
    return !af->failed_errno;
}

void vx_atomic_abort(vx_atomic_file* af) {
    if (af->f) fclose((FILE*)af->f);
    if (af->tmp) remove(af->tmp);
    vx_free(af->alloc, af->tmp);
    memset(af, 0, sizeof *af);
}

vx_result vx_atomic_commit(vx_atomic_file* af, vx_error* err) {
    FILE* f = (FILE*)af->f;
    int e = af->failed_errno;
    if (!e && fflush(f) != 0) e = errno;
    if (!e && fsync(fileno(f)) != 0 && errno != EINVAL && errno != EROFS) e = errno;
    af->f = NULL;
    if (fclose(f) != 0 && !e) e = errno;
    if (!e && rename(af->tmp, af->path) != 0) e = errno;
    if (e) {
        vx_atomic_abort(af);
        return vx_fail(err, VX_ERR_IO, VX_NO_OFFSET, "cannot write: %s", strerror(e));
    }
    vx_free(af->alloc, af->tmp);
    memset(af, 0, sizeof *af);
    return VX_OK;
}

vx_result vx_file_write_atomic(const char* path, const vx_allocator* a, const void* data, size_t size,
                               vx_error* err) {
    vx_atomic_file af;
    vx_result r = vx_atomic_open(&af, path, a, err);
    if (r) return r;
    vx_atomic_write(&af, data, size);
    return vx_atomic_commit(&af, err);
}

void vx_run_threads(unsigned threads, void* (*worker)(void* arg), void* arg) {
    if (threads > VX_MAX_THREADS) threads = VX_MAX_THREADS;
    pthread_t tid[VX_MAX_THREADS];
    unsigned started = 0;
    for (unsigned t = 1; t < threads; t++)
        if (pthread_create(&tid[started], NULL, worker, arg) == 0) started++;
    worker(arg);
    for (unsigned t = 0; t < started; t++) pthread_join(tid[t], NULL);
}

typedef struct job_set {
    void (*run)(void* ctx, unsigned thread, uint32_t i);
    void* ctx;
    uint32_t count;
    _Atomic uint32_t next; /* the next job */
} job_set;
typedef struct job_thread {
    job_set* set;
    unsigned thread;
} job_thread;

static void* job_worker(void* arg) {
    const job_thread* t = (const job_thread*)arg;
    job_set* j = t->set;
    for (;;) {
        uint32_t i = atomic_fetch_add(&j->next, 1);
        if (i >= j->count) return NULL;
        j->run(j->ctx, t->thread, i);
    }
}

void vx_run_jobs(unsigned threads, uint32_t count, void (*run)(void* ctx, unsigned thread, uint32_t i), void* ctx) {
    if (count == 0) return;
    if (threads > VX_MAX_THREADS) threads = VX_MAX_THREADS;
    if (threads > count) threads = count;
    if (threads == 0) threads = 1;
    job_set j = {run, ctx, count, 0};
    /* as vx_run_threads, but each thread knows its index (the caller's 0;
     * one that cannot be started leaves its index unused) */
    job_thread t[VX_MAX_THREADS];
    pthread_t tid[VX_MAX_THREADS];
    unsigned started = 0;
    for (unsigned k = 0; k < threads; k++) t[k] = (job_thread){&j, k};
    for (unsigned k = 1; k < threads; k++)
        if (pthread_create(&tid[started], NULL, job_worker, &t[k]) == 0) started++;
    job_worker(&t[0]);
    for (unsigned k = 0; k < started; k++) pthread_join(tid[k], NULL);
}

unsigned vx_cpu_count(unsigned max) {
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    unsigned c = n < 1 ? 1u : (unsigned long)n > UINT_MAX ? UINT_MAX : (unsigned)n;
    return max && c > max ? max : c;
}

double vx_time_now(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

uint64_t vx_peak_rss(void) {
    struct rusage ru;
    if (getrusage(RUSAGE_SELF, &ru) != 0) return 0;
    return (uint64_t)ru.ru_maxrss * 1024u; /* Linux reports KiB */
}

bool vx_parse_doubles(const char* s, double* v, int n) {
    for (int i = 0; i < n; i++) {
        char* end;
        errno = 0;
        v[i] = strtod(s, &end);
        if (end == s || errno || !isfinite(v[i])) return false;
        s = end;
        if (i < n - 1) {
            if (*s != ',') return false;
            s++;
        }
    }
    return *s == 0;
}
