/* svo/core.h - shared foundations of voxkit: results, errors, allocation,
 * checked size arithmetic, a bounds-checked byte reader, CRC-32 and file I/O.
 *
 * Every fallible function in voxkit returns a vx_result and takes an optional
 * `vx_error* err` as its last argument. On failure err->msg holds one specific
 * line ("XYZI chunk at byte 1234: 4000 voxels declared, 812 bytes left") and
 * err->offset the byte offset in the input where the problem was found (or
 * VX_NO_OFFSET). Outputs come back through out_ pointers and are left
 * untouched on failure. Library code never prints and never exits.
 *
 * Allocation goes through vx_allocator; a zeroed allocator (or NULL) means
 * malloc/free. Whoever allocates provides the matching free.
 */
#ifndef VX_CORE_H
#define VX_CORE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define VX_VERSION_STRING "0.1.0"

/* ---- results and errors ------------------------------------------------ */

typedef enum vx_result {
    VX_OK = 0,
    VX_ERR_INVALID_ARG, /* caller passed something unusable */
    VX_ERR_TRUNCATED,   /* input ends before a declared length */
    VX_ERR_BAD_FORMAT,  /* input is malformed */
    VX_ERR_UNSUPPORTED, /* well-formed but uses a feature we do not support */
    VX_ERR_LIMIT,       /* input exceeds a configured limit (max_dim, ...) */
    VX_ERR_NOMEM,       /* allocation failed or a size overflowed */
    VX_ERR_IO,          /* file system error */
    VX_ERR_GPU,         /* Vulkan error */
    VX_RESULT_NUM
} vx_result;

#define VX_NO_OFFSET UINT64_MAX

typedef struct vx_error {
    vx_result code;
    uint64_t offset; /* byte offset in the input, VX_NO_OFFSET if none */
    char msg[192];
} vx_error;

const char* vx_result_str(vx_result r);

/* Fills err (if non-NULL) and returns code, so call sites read
 * `return vx_fail(err, VX_ERR_TRUNCATED, off, "XYZI: %u voxels", n);` */
vx_result vx_fail(vx_error* err, vx_result code, uint64_t offset, const char* fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 4, 5)))
#endif
    ;

/* Prefixes err->msg with "prefix: " (used to add context while unwinding). */
void vx_error_prefix(vx_error* err, const char* prefix);

/* ---- logging (warnings from library code) ------------------------------- */

typedef enum vx_log_level { VX_LOG_INFO = 0, VX_LOG_WARN = 1 } vx_log_level;

/* id is a stable message identifier such as "vox.voxel_outside_model". */
typedef struct vx_logger {
    void (*func)(void* user, vx_log_level level, const char* id, const char* msg);
    void* user_data;
} vx_logger;

void vx_log(const vx_logger* log, vx_log_level level, const char* id, const char* fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 4, 5)))
#endif
    ;

/* ---- progress ------------------------------------------------------------ */

/* Called from long operations with done <= total; returns false to cancel
 * (the operation then fails with VX_ERR_INVALID_ARG, "cancelled"). */
typedef struct vx_progress {
    bool (*func)(void* user, const char* stage, uint64_t done, uint64_t total);
    void* user_data;
} vx_progress;

bool vx_progress_report(const vx_progress* p, const char* stage, uint64_t done, uint64_t total);

/* ---- allocation ------------------------------------------------------------ */

/* Ownership: a call that only allocates and frees within itself (a reader,
 * a writer, a converter) uses its desc's allocator during the call. An
 * object or result that frees later (a scene's arrays, an editor, a GPU
 * scene, a probe set, an image) keeps the `const vx_allocator*` it was
 * given, borrowed, not a copy, unless its header says it copies the struct
 * (vx_gpu_desc.alloc, vx_svo_model_reader): the allocator, and its
 * user_data in either case, must outlive the object and everything it
 * allocated with it. */
typedef struct vx_allocator {
    void* (*alloc)(void* user, size_t size); /* NULL: malloc */
    void (*free)(void* user, void* ptr);     /* NULL: free */
    void* user_data;
} vx_allocator;

/* a may be NULL. vx_alloc(0) returns a valid unique pointer or NULL. */
void* vx_alloc(const vx_allocator* a, size_t size);
void* vx_calloc(const vx_allocator* a, size_t count, size_t size); /* overflow-checked, zeroed */
void vx_free(const vx_allocator* a, void* p);
/* Grows *p (count elements of size) to at least need elements; doubles. */
bool vx_grow(const vx_allocator* a, void** p, size_t* cap, size_t need, size_t size);

/* A memory budget (the tools' --max-memory): an allocator that refuses any
 * allocation that would take the bytes in use past `limit`, before asking
 * its parent (NULL: malloc). Give &b.allocator to readers, converters and
 * writers; a refused allocation makes them fail with VX_ERR_NOMEM, and
 * b.refused tells the caller that the budget, not the system, said no (the
 * tools then name the cap). Each block carries a 16-byte header with its
 * size; counters are updated atomically (readers allocate from threads).
 * The budget must outlive everything allocated from it. Memory that
 * third-party libraries allocate themselves (OpenVDB, tinygltf, OIIO) is not
 * counted. */
typedef struct vx_budget {
    vx_allocator allocator;
    const vx_allocator* parent;
    size_t limit;   /* 0: no limit */
    size_t used;    /* bytes in use, headers included */
    size_t peak;    /* most bytes in use */
    size_t refused; /* the first allocation refused (bytes), 0 if none */
} vx_budget;
void vx_budget_init(vx_budget* b, size_t limit, const vx_allocator* parent);

/* ---- checked size arithmetic ---------------------------------------------
 * Every size computed from untrusted input goes through these: a wrapped
 * product would turn into a small allocation followed by a large write. */

static inline bool vx_mul_size(size_t a, size_t b, size_t* out) {
#if defined(__GNUC__) || defined(__clang__)
    return !__builtin_mul_overflow(a, b, out);
#else
    if (b && a > SIZE_MAX / b) return false;
    *out = a * b;
    return true;
#endif
}
static inline bool vx_add_size(size_t a, size_t b, size_t* out) {
#if defined(__GNUC__) || defined(__clang__)
    return !__builtin_add_overflow(a, b, out);
#else
    if (a > SIZE_MAX - b) return false;
    *out = a + b;
    return true;
#endif
}
static inline bool vx_mul_u64(uint64_t a, uint64_t b, uint64_t* out) {
#if defined(__GNUC__) || defined(__clang__)
    return !__builtin_mul_overflow(a, b, out);
#else
    if (b && a > UINT64_MAX / b) return false;
    *out = a * b;
    return true;
#endif
}

/* ---- bounded little-endian reader ------------------------------------------
 * A failed read does not advance the cursor. Lengths are compared against the
 * bytes remaining in subtraction form, so no offset arithmetic can wrap. */

typedef struct vx_rd {
    const uint8_t* p;
    size_t size;
    size_t off;
    uint64_t base; /* absolute offset of p[0] in the file, for messages */
} vx_rd;

static inline vx_rd vx_rd_make(const void* p, size_t size) {
    vx_rd r = {(const uint8_t*)p, size, 0, 0};
    return r;
}
static inline size_t vx_rd_left(const vx_rd* r) { return r->size - r->off; }
static inline uint64_t vx_rd_pos(const vx_rd* r) { return r->base + r->off; }
static inline bool vx_rd_bytes(vx_rd* r, void* dst, size_t n) {
    if (n > r->size - r->off) return false;
    for (size_t i = 0; i < n; i++) ((uint8_t*)dst)[i] = r->p[r->off + i];
    r->off += n;
    return true;
}
static inline bool vx_rd_skip(vx_rd* r, size_t n) {
    if (n > r->size - r->off) return false;
    r->off += n;
    return true;
}
static inline bool vx_rd_u8(vx_rd* r, uint8_t* v) {
    if (r->size - r->off < 1) return false;
    *v = r->p[r->off++];
    return true;
}
static inline bool vx_rd_u16le(vx_rd* r, uint16_t* v) {
    if (r->size - r->off < 2) return false;
    const uint8_t* b = r->p + r->off;
    *v = (uint16_t)(b[0] | (b[1] << 8));
    r->off += 2;
    return true;
}
static inline bool vx_rd_u32le(vx_rd* r, uint32_t* v) {
    if (r->size - r->off < 4) return false;
    const uint8_t* b = r->p + r->off;
    *v = (uint32_t)b[0] | ((uint32_t)b[1] << 8) | ((uint32_t)b[2] << 16) | ((uint32_t)b[3] << 24);
    r->off += 4;
    return true;
}
static inline bool vx_rd_u64le(vx_rd* r, uint64_t* v) {
    uint32_t lo = 0, hi = 0;
    if (r->size - r->off < 8) return false;
    vx_rd_u32le(r, &lo);
    vx_rd_u32le(r, &hi);
    *v = (uint64_t)lo | ((uint64_t)hi << 32);
    return true;
}
static inline bool vx_rd_f32le(vx_rd* r, float* v) {
    uint32_t u = 0;
    if (!vx_rd_u32le(r, &u)) return false;
    union { uint32_t u; float f; } c = {u};
    *v = c.f;
    return true;
}
static inline bool vx_rd_f64le(vx_rd* r, double* v) {
    uint64_t u = 0;
    if (!vx_rd_u64le(r, &u)) return false;
    union { uint64_t u; double f; } c = {u};
    *v = c.f;
    return true;
}
/* A sub-reader over the next n bytes (advancing r past them), so a bad length
 * inside a chunk cannot escape the chunk. */
static inline bool vx_rd_sub(vx_rd* r, size_t n, vx_rd* sub) {
    if (n > r->size - r->off) return false;
    sub->p = r->p + r->off;
    sub->size = n;
    sub->off = 0;
    sub->base = r->base + r->off;
    r->off += n;
    return true;
}

/* ---- growable byte buffer (writers) ---------------------------------------- */

typedef struct vx_buf {
    uint8_t* data;
    size_t size, cap;
    const vx_allocator* alloc;
    bool failed; /* sticky: an append failed (out of memory) */
} vx_buf;

bool vx_buf_append(vx_buf* b, const void* data, size_t n);
bool vx_buf_u8(vx_buf* b, uint8_t v);
bool vx_buf_u16le(vx_buf* b, uint16_t v);
bool vx_buf_u32le(vx_buf* b, uint32_t v);
bool vx_buf_u64le(vx_buf* b, uint64_t v);
bool vx_buf_f32le(vx_buf* b, float v);
bool vx_buf_f64le(vx_buf* b, double v);
bool vx_buf_zeros(vx_buf* b, size_t n);
void vx_buf_put_u32le(uint8_t* dst, uint32_t v); /* patch in place */
void vx_buf_free(vx_buf* b);

/* ---- checksums ---------------------------------------------------------------- */

/* CRC-32 (ISO-HDLC / zlib: reflected polynomial 0xEDB88320, init and final
 * xor 0xFFFFFFFF). Pass crc = 0 to start; feed the result back to continue. */
uint32_t vx_crc32(uint32_t crc, const void* data, size_t n);

/* ---- files ------------------------------------------------------------------------ */

/* Reads a whole file into memory (freed with vx_free(a, *out_data)).
 * max_bytes 0 means 4 GiB. */
vx_result vx_file_read(const char* path, const vx_allocator* a, uint64_t max_bytes, uint8_t** out_data,
                       size_t* out_size, vx_error* err);

/* Test hooks of svo/ (as sokol's sg_desc.disable_validation): they let small
 * test scenes reach paths that real inputs reach only at scale (far
 * pointers, threads, streamed output, the split form) without a mutable
 * global. Zero-initialised: the library's own behaviour, which users keep.
 * Each desc that holds one (vx_write_desc, vx_svo_read_desc,
 * vx_svo_build_desc, vx_svo_editor_desc) reads only the fields named for it
 * here; the defaults are written once, in svo/svo_internal.h. */
typedef struct vx_svo_testing {
    uint32_t far_limit;   /* build, edit, .svo write: largest near child pointer laid out or tried (0: the 15-bit maximum, 32767) */
    bool parallel_always; /* .svo read and write: per-model and layout threads for models of any size (default: 2^20 words and more) */
    size_t flush_bytes;   /* vx_svo_write_file: NODE is flushed after a model once it holds this many bytes (0: 16 MB) */
    uint32_t split_words; /* .svo write: models of at least this many words take the split form (0: 2^20) */
    bool split_no_runs;   /* .svo write: the split form without its runs stream (format version 5's, for the old-file tests) */
    bool unchecked;       /* .svo write: no validation; words and records stored raw (tests write corrupt trees) */
    bool scratch_any;     /* .svo read: a thread keeps its models' decoded buffers of any size for its next model (default: 1 MB and more) */
} vx_svo_testing;

/* Options of the writers to a file (vx_svo_write_file, vx_vox_write_file,
 * vx_probe_write_file, vx_glb_write_file, vx_vdb_write_file). NULL or
 * zero-initialised: the defaults. */
typedef struct vx_write_desc {
    const vx_allocator* alloc; /* NULL: malloc/free. Every block the writer
                                  allocates itself (the temporary file's name,
                                  encoded sections, streaming buffers); not
                                  what stdio, zlib, tinygltf or OpenVDB
                                  allocate inside. Out of memory is
                                  VX_ERR_NOMEM with the output name untouched. */
    unsigned threads;          /* writers that code in parallel (.svo): 0 = one per
                                  CPU (at most VX_MAX_THREADS), 1 = the caller's thread only.
                                  The bytes never depend on it. */
    uint32_t svo_chunk_words;  /* .svo: models with at least this many node words
                                  are stored in the chunked form (docs/FORMAT.md
                                  3.6, format version 4: the words and records
                                  themselves in zstd-coded chunks that code and
                                  decode on every thread, 1.7-3.1x the bytes of the
                                  structural form: the 4096^3 helmet read in
                                  1.4-2.5 s and written in 2.4-2.5 s on two
                                  cores, against 5.5-8.7 s and 4.6-5.3 s,
                                  docs/PERFORMANCE.md issue 18, twelfth I/O
                                  step); 0 = never (the default: the compact
                                  structural forms for every model);
                                  VX_SVO_CHUNK_WORDS is the suggested value
                                  (`vox2svo --chunked`). */
    bool svo_chunk_stored;     /* .svo, chunked models: the chunks as DEFLATE's
                                  stored blocks (level 0) instead of level 1:
                                  the same format, every reader reads them;
                                  coding is a copy (deflate at level 1 is
                                  about 100 MB/s per core), at about twice
                                  the chunked form's bytes (docs/PERFORMANCE.md,
                                  issue 18). false: zstd chunks (the default; level 1 with svo_chunk_deflate). */
    bool svo_chunk_fast;       /* .svo, chunked models: the chunks of node words
                                  stored, those of records at level 1 (the
                                  same format, every reader reads them): the
                                  words deflate slowest (to about 55%), so
                                  this about halves the coding time for about
                                  a third more bytes than level 1 everywhere
                                  (docs/PERFORMANCE.md, issue 18).
                                  svo_chunk_stored wins if both are set. */
    bool svo_chunk_deflate;    /* .svo, chunked models: DEFLATE level 1 chunks
                                  (format version 3, what readers before
                                  version 4 read) instead of the default zstd
                                  chunks (version 4: zstd level 2 codes the
                                  4096^3 helmet in 0.6 of the time into 0.96
                                  of the bytes, docs/PERFORMANCE.md issue 18).
                                  svo_chunk_stored and svo_chunk_fast are
                                  version-3 forms too and win over it. */
    bool svo_range_coded;      /* .svo: models of 2^20 words or more that are not
                                  chunked in the range-coded form of versions
                                  1 and 2 (what older readers read) instead of
                                  the split form (docs/FORMAT.md 3.7, format
                                  version 5, with attributes its runs stream,
                                  version 6; the default: the same DAG in zstd
                                  byte streams that decode on every thread,
                                  several times faster to read and write for
                                  a few percent more bytes, docs/PERFORMANCE.md
                                  issue 18). */
    vx_svo_testing testing;    /* .svo: test hooks (all of vx_svo_testing's); leave zeroed */
} vx_write_desc;

/* Suggested vx_write_desc.svo_chunk_words (vox2svo --chunked): a model of
 * 2^20 words (4 MB) takes a second or more to rebuild from the structural
 * form. Not the default: the chunked form costs 2-3x the bytes, and files
 * that do not ask for it keep the compact form older readers know. */
#define VX_SVO_CHUNK_WORDS (1u << 20)

/* Writes data to path through a temporary file in the same folder that is
 * renamed over path only after everything was written and flushed, so a
 * failure never leaves a half-written output. a: as vx_write_desc.alloc. */
vx_result vx_file_write_atomic(const char* path, const vx_allocator* a, const void* data, size_t size,
                               vx_error* err);

/* The same written in pieces: vx_atomic_open creates the temporary file,
 * vx_atomic_write appends (a failure is remembered), vx_atomic_commit
 * flushes, syncs and renames it over path (or removes it and fails);
 * vx_atomic_abort removes it. Either of the last two ends the file. */
typedef struct vx_atomic_file {
    void* f; /* FILE* */
    char* tmp;
    const char* path;
    const vx_allocator* alloc; /* tmp's */
    int failed_errno;          /* 0 while every write succeeded */
} vx_atomic_file;
vx_result vx_atomic_open(vx_atomic_file* af, const char* path, const vx_allocator* a, vx_error* err);
bool vx_atomic_write(vx_atomic_file* af, const void* data, size_t n);
vx_result vx_atomic_commit(vx_atomic_file* af, vx_error* err);
void vx_atomic_abort(vx_atomic_file* af);

/* ---- threads -------------------------------------------------------------------------- */

#define VX_MAX_THREADS 64

/* Runs worker(arg) on `threads` threads at once, the caller's thread
 * included, and returns when all have returned. Workers take their work
 * from shared state in arg (so if a thread cannot be started the others
 * do its share); 0 means 1; more than VX_MAX_THREADS are capped. */
void vx_run_threads(unsigned threads, void* (*worker)(void* arg), void* arg);

/* Runs run(ctx, thread, i) once for every job i in [0, count) on up to
 * `threads` threads (vx_run_threads: the caller's thread included, 0 means
 * 1) and returns when every job has run. Jobs are handed out in increasing
 * order from one shared counter, so a thread that finishes early takes the
 * next; which thread runs which job depends on timing, so results must not.
 * thread (in [0, threads)) names the running thread for per-thread scratch
 * state; the caller's thread is 0 (the one to report progress from). To
 * stop early (a failure, a cancel), run checks a flag of its own in ctx and
 * returns at once: the jobs left are then handed out and skipped. */
void vx_run_jobs(unsigned threads, uint32_t count, void (*run)(void* ctx, unsigned thread, uint32_t i), void* ctx);

/* ---- misc ---------------------------------------------------------------------------- */

/* The online CPUs, at most max (0: no cap); at least 1. Where work spreads
 * over one thread per CPU (the .svo coder, the compact layout's attributes). */
unsigned vx_cpu_count(unsigned max);

/* Whether s is exactly n comma-separated finite numbers (strtod's syntax),
 * stored in v: the text form of vectors (a sky's colours, a tool's option). */
bool vx_parse_doubles(const char* s, double* v, int n);

/* Monotonic seconds, for statistics. */
double vx_time_now(void);
/* Peak resident memory of this process in bytes (0 if unknown). */
uint64_t vx_peak_rss(void);

#ifdef __cplusplus
}
#endif
#endif /* VX_CORE_H */
