/* svo/svo_internal.h - declarations shared by the svo_*.c files (not public). */
#ifndef VX_SVO_INTERNAL_H
#define VX_SVO_INTERNAL_H

#include "svo/svo.h"
#include "svo/svo_interned.h"

#include <pthread.h>

/* Largest relative child pointer the encoding allows (15 bits): the
 * builder's, the editor's and the writer's far limit unless a test lowers it
 * (vx_svo_testing.far_limit) so that far pointers appear in small trees. */
#define VX__SVO_PTR_MAX 0x7FFFu
/* Node words from which a scene's models are handled on threads, and a
 * model's layout follows its decoding on threads (2^20). */
#define VX__SVO_PARALLEL_WORDS ((uint64_t)1 << 20)
/* NODE bytes a streamed write holds before it flushes them (16 MB). */
#define VX__SVO_FLUSH_BYTES ((size_t)16 << 20)
/* Node words from which writers store a model in the split form (2^20). */
#define VX__SPLIT_WORDS (1u << 20)

/* The test hooks of a desc (vx_svo_testing, svo/core.h) with the defaults
 * applied: the one place the defaults are written. t NULL: the defaults. */
static inline uint32_t vx__svo_far_limit(const vx_svo_testing* t) {
    return t && t->far_limit >= 1 && t->far_limit <= VX__SVO_PTR_MAX ? t->far_limit : VX__SVO_PTR_MAX;
}
static inline uint64_t vx__svo_parallel_words(const vx_svo_testing* t) {
    return t && t->parallel_always ? 0 : VX__SVO_PARALLEL_WORDS;
}
static inline size_t vx__svo_flush_bytes(const vx_svo_testing* t) {
    return t && t->flush_bytes ? t->flush_bytes : VX__SVO_FLUSH_BYTES;
}
static inline uint32_t vx__svo_split_words(const vx_svo_testing* t) {
    return t && t->split_words ? t->split_words : VX__SPLIT_WORDS;
}
static inline bool vx__svo_split_runs(const vx_svo_testing* t) { return !(t && t->split_no_runs); }
static inline bool vx__svo_unchecked(const vx_svo_testing* t) { return t && t->unchecked; }
/* A write desc's hooks (NULL for a NULL desc), and its split threshold:
 * 0 (never) with vx_write_desc.svo_range_coded, else vx__svo_split_words. */
static inline const vx_svo_testing* vx__svo_write_testing(const vx_write_desc* d) { return d ? &d->testing : NULL; }
static inline uint32_t vx__svo_split_min(const vx_write_desc* d) {
    return d && d->svo_range_coded ? 0 : vx__svo_split_words(vx__svo_write_testing(d));
}

/* Bit count of an 8-bit mask. A SWAR sum rather than __builtin_popcount:
 * without -mpopcnt (the x86-64 baseline Debian builds for) the builtin
 * becomes a libgcc call, measured at 2.5% of a whole mesh conversion. */
static inline uint32_t vx__popc8(uint32_t m) {
    m &= 0xFFu;
    m = m - ((m >> 1) & 0x55u);
    m = (m & 0x33u) + ((m >> 2) & 0x33u);
    return (m + (m >> 4)) & 0x0Fu;
}
/* The same for 32 bits (the validator's level masks). */
static inline uint32_t vx__popc32(uint32_t m) {
    m = m - ((m >> 1) & 0x55555555u);
    m = (m & 0x33333333u) + ((m >> 2) & 0x33333333u);
    return (((m + (m >> 4)) & 0x0F0F0F0Fu) * 0x01010101u) >> 24;
}

/* Occupied extent of a model, from its tree without expanding leaves or
 * shared subtrees: cells, and min (inclusive) / max (exclusive) corner. */
typedef struct vx__svo_extent {
    uint64_t cells;
    uint32_t min[3], max[3];
} vx__svo_extent;

/* Validates m (as vx_svo_validate_model) and, when ext is non-NULL, returns
 * its occupied extent. */
vx_result vx__svo_analyze(const vx_svo_model* m, vx__svo_extent* ext, vx_error* err);
/* The same with unreferenced_ok: words that no descriptor reaches are
 * allowed (an edited model's superseded copies, svo/edit.h); everything
 * reachable is checked as strictly. Files never hold such words. */
vx_result vx__svo_analyze_opt(const vx_svo_model* m, vx__svo_extent* ext, bool unreferenced_ok, vx_error* err);
/* The same on up to `threads` threads within the model (models of 2^20
 * words or more: the ascending pass level by level); the result and the
 * error are the one-thread ones. */
vx_result vx__svo_analyze_mt(const vx_svo_model* m, vx__svo_extent* ext, bool unreferenced_ok, unsigned threads, vx_error* err);

/* Threads worth using for per-model work on s (1 for small scenes: under
 * vx__svo_parallel_words(t) node words or one model); want: the caller's
 * limit (a desc's threads field: 0 = one per CPU, up to 16); t: the desc's
 * test hooks (may be NULL). */
unsigned vx__svo_threads(const vx_svo_scene* s, unsigned want, const vx_svo_testing* t);
/* The CPUs to use for want (0: one per online CPU, capped at 16). */
unsigned vx__svo_cpus(unsigned want);
/* Asks the kernel for 2 MB pages behind the whole 2 MB units of p[0, n)
 * (Linux, transparent huge pages in "madvise" mode; nothing elsewhere), for
 * arrays of tens of MB or more that are filled once and then read at random:
 * the validation's per-word arrays and a read model's words. With 4 KB pages
 * their first touch (a fault per page) and the TLB misses of the random
 * lookups were a large part of a chunked read (docs/PERFORMANCE.md, issue
 * 18). Call it before the memory is first touched. */
void vx__svo_advise_huge(void* p, size_t n);

/* A count one thread advances (a stage's progress: pool words appended,
 * symbols decoded, words laid out) and one other thread waits on, asleep
 * (a condition variable) rather than polling: the stages of a read share
 * two cores with each other, and a poller's wake-ups are CPU the others
 * lose (docs/PERFORMANCE.md, issue 18, ninth step). The producer publishes
 * at most every `step` units (its stores and the waiter's wake-ups in
 * batches) and closes the gate with its final count. */
typedef struct vx__svo_gate {
    _Atomic size_t val;  /* published count */
    _Atomic size_t want; /* the waiter sleeps until val >= want (0: nobody waits) */
    bool closed;         /* under lock: val is final */
    size_t step, next;   /* the producer's: publish from `next` on */
    pthread_mutex_t lock;
    pthread_cond_t cond;
} vx__svo_gate;
void vx__svo_gate_init(vx__svo_gate* g, size_t step);
void vx__svo_gate_destroy(vx__svo_gate* g);
/* Producer: the first v units are complete (v never decreases). */
void vx__svo_gate_publish(vx__svo_gate* g, size_t v);
/* Producer: v is final; wakes the waiter for good. */
void vx__svo_gate_close(vx__svo_gate* g, size_t v);
/* Waiter: the published count once it exceeds `have` (at once when it
 * does; else asleep until it reaches have + more, or the gate is closed).
 * A result <= have means closed with nothing more. */
size_t vx__svo_gate_wait(vx__svo_gate* g, size_t have, size_t more);

/* The validation of a model the reader rebuilt from the structural form
 * (FORMAT.md 3.4, 3.5), whose reconstruction computed the extent of its tree
 * (tree, at the model's depth): rules 1, 2 and 5 of FORMAT.md 3.1 (the head,
 * the root, the cells inside the size and their count); rules 3 and 4 hold
 * by construction (vx__svo_unpack says why), so the words are not walked.
 * ext (may be tree) receives the extent. */
vx_result vx__svo_check_rebuilt(const vx_svo_model* m, const vx__svo_extent* tree, vx__svo_extent* ext, vx_error* err);

/* vx_svo_validate_scene that also returns each model's extent (ext has
 * model_count entries, or is NULL), so a writer analyses every model once. */
vx_result vx__svo_validate_scene_ext(const vx_svo_scene* s, vx__svo_extent* ext, unsigned threads, vx_error* err);
/* The same without the models' trees (models false): only the scene's own
 * rules, for a writer whose models were coded elsewhere (vx_svo_write_file_coded);
 * or without those marked in skip (may be NULL): VX__SVO_SKIP_TRUSTED, models
 * whose vx_svo_model.check the writer found current (their ext entries
 * untouched); VX__SVO_SKIP_REBUILT, models the reader rebuilt, whose ext
 * entries hold their trees' extents (vx__svo_check_rebuilt). */
enum { VX__SVO_SKIP_TRUSTED = 1, VX__SVO_SKIP_REBUILT = 2 };
vx_result vx__svo_validate_scene_opt(const vx_svo_scene* s, vx__svo_extent* ext, unsigned threads, const vx_svo_testing* t, bool models,
                                     const uint8_t* skip, vx_error* err);
/* Sets each model's vx_svo_model.check from its extent (the reader, after
 * validating the scene): the digests on up to `threads` threads. */
void vx__svo_set_checks(vx_svo_scene* s, const vx__svo_extent* ext, unsigned threads, const vx_svo_testing* t);
/* The models the writer need not validate (skip[i] = 1, ext[i] from the
 * check): stored chunked (chunk_min, vx_write_desc.svo_chunk_words) or
 * rebuilt by the reader from the structural form (check.structural), and
 * their check's digest current. alloc: the writer's (a failed allocation
 * leaves every model to the validation). */
void vx__svo_trusted_models(const vx_svo_scene* s, const vx_allocator* alloc, uint32_t chunk_min, unsigned threads, const vx_svo_testing* t,
                            uint8_t* skip, vx__svo_extent* ext);
/* Scene bounds from extents already known (known may be NULL: analyse). */
void vx__svo_scene_bounds_ext(const vx_svo_scene* s, const vx__svo_extent* known, double bmin[3], double bmax[3]);

/* The bounds vx_svo_scene_update_bounds would store, without modifying s
 * (the file writer omits bounds that equal them; the reader recomputes). */
void vx__svo_scene_bounds(const vx_svo_scene* s, double bmin[3], double bmax[3]);

/* Octahedral normal helpers (2 x snorm16, x in the low half). */
void vx__oct_decode(uint32_t v, float n[3]);
uint32_t vx__oct_encode(const float n[3]);

/* ---- structural packing of the NODE section (svo_pack.c; the reconstruction
 * shares the builder's layout code in svo_build.c) --------------------------- */

/* Symbols of a model's structure, in depth-first order (docs/FORMAT.md 3.4). */
enum { VX__SYM_VALID, VX__SYM_LEAF, VX__SYM_REF, VX__SYM_VALUE, VX__SYM_RUN };

/* Where vx__svo_unpack takes its symbols from. ctx: the level for VALID and
 * REF, level | valid << 8 for LEAF, the channel bit index for VALUE. Returns
 * false (with err set) when the source cannot deliver. */
/* The split form's decoded streams (svo_split.c) as the reconstruction reads
 * them without a call per symbol: stream s holds n[s] bytes at data[s], read
 * up to pos[s]; a channel's stream vcount[s] values, each its bytes in order,
 * least significant first (the decoder interleaves the file's planes); cs[c]
 * the stream of channel c. The decoder's own state: where the direct read
 * cannot take a symbol as it is (a stream's end, a leaf mask outside its
 * valid mask, a reference of more than one byte) it calls next, which reads
 * at the same position and gives the same symbol or the error. */
typedef struct vx__svo_split_cur {
    const uint8_t* data[15]; /* VX__SPLIT_MAX */
    size_t n[15], pos[15], vcount[15];
    uint8_t cs[5];
} vx__svo_split_cur;

typedef struct vx__svo_src {
    bool (*next)(void* user, unsigned kind, unsigned ctx, uint32_t* v, vx_error* err);
    void* user;
    vx__svo_split_cur* cur; /* the split form's streams (NULL: next only) */
} vx__svo_src;

typedef struct vx__svo_unpack_desc {
    uint32_t depth, attrs; /* attrs: a subset of PALETTE | RGBA8 | MATERIAL */
    bool dag;              /* the model was built with DAG sharing (runs of records shared) */
    uint32_t limit;        /* largest near pointer, 1..VX__SVO_PTR_MAX */
    uint64_t max_words;    /* declared node_count: the symbols may not describe more */
    const vx_allocator* alloc;
    /* Threads the layout may follow the decoding on (0: none, it runs
     * afterwards; 1: one; 2: the records' runs and the blocks apart); the
     * callers give 0 for models under vx__svo_parallel_words words. The
     * result never depends on it. */
    unsigned layout_threads;
    /* When non-NULL: receives the extent of the rebuilt tree at the depth,
     * and every back-reference is checked to name a node that fits below
     * its level (the reader's check instead of the validation's walk:
     * vx__svo_check_rebuilt; the proof is in svo_build.c before xt_node). */
    vx__svo_extent* tree;
    /* REF symbols are 0 (a new node) or 1 + the completion index of the node
     * named (the split form, FORMAT.md 3.7) instead of a distance back. */
    bool ref_index;
    /* Channels whose every leaf value is const_rec's (the split form's
     * decoded streams say so, vx__svo_split_constants): with at most one
     * channel left varying, records are that channel's values (no record
     * table), the others filled in; the result is the same. */
    uint32_t const_attrs;
    vx__svo_rec const_rec;
    /* The split form's runs stream (FORMAT.md 3.7, version 6; NULL: none):
     * one byte per node in completion order, how the layout treats its
     * attribute run (0 appended, 1 appended and stored, 2 found among the
     * stored runs), so that the run table holds and looks up only the runs
     * that are found again (run_take, svo_build.c). */
    const uint8_t* runs;
    size_t runs_n;
    /* The decoding thread's kept buffers (vx__svo_scratch), or NULL: with the
     * split streams the completed-node list is taken from it at its size
     * (one node a valid mask: the valid streams' bytes) and given back. */
    struct vx__svo_scratch* scratch;
    /* The declared attr_count (the split form's caller sets it, with
     * max_words): the words and the records' ids are taken at the declared
     * sizes up front, as 2 MB pages (vx__svo_advise_huge), instead of grown
     * by doubling (a valid stream fills them exactly; any other is an error
     * and grows them as before). 0: grown. The result never depends on it. */
    uint64_t max_records;
} vx__svo_unpack_desc;

/* Rebuilds a model's node words and records from its depth-first symbols by
 * running the builder's own layout, so that a model built by
 * vx_svo_build_model comes back word for word. Fills out->nodes, node_count,
 * root, root_attr, attr_count and the record arrays (attrs, size, depth and
 * voxel_count are left to the caller). */
vx_result vx__svo_unpack(const vx__svo_unpack_desc* d, const vx__svo_src* src, vx_svo_model* out, vx_error* err);

/* NODE section payload for all models of s (validated), and its inverse,
 * which fills the words and records of s's models from their declared
 * counts (node_count, attr_count, root, root_attr as read from SCNE). */
/* Where a writer can send what it has produced so far: flush() consumes
 * out->data[0, out->size) and empties it (out->size = 0); false on failure. */
typedef struct vx__svo_sink {
    bool (*flush)(void* user, vx_buf* out);
    void* user;
    size_t flush_bytes; /* vx__svo_pack_write flushes between model streams from this many bytes on
                           (vx__svo_flush_bytes: 16 MB; tests lower it to flush after every model) */
} vx__svo_sink;
/* Appends the NODE section to out; with a sink, out is flushed between model
 * streams whenever it holds sink->flush_bytes or more (sink NULL: all in
 * memory). */
/* One model's stream of the NODE section (without its length varint): the
 * model alone decides its bytes. m must be valid. */
/* chunked: 0 the structural or raw form, VX__CHUNK_DEFLATE, VX__CHUNK_STORED or
 * VX__CHUNK_FAST (words stored, records deflated) the chunked form of
 * version 3, VX__CHUNK_ZSTD the tagged chunks of version 4 (zstd) */
enum { VX__CHUNK_NONE = 0, VX__CHUNK_DEFLATE = 1, VX__CHUNK_STORED = 2, VX__CHUNK_FAST = 3, VX__CHUNK_ZSTD = 4,
       VX__CHUNK_SPLIT = 5 /* not chunked: the split form's stream (a form byte first, FORMAT.md 3.7) */ };
/* The chunked mode a write desc asks for (VX__CHUNK_ZSTD for NULL). */
int vx__svo_chunk_mode(const vx_write_desc* desc);
/* trusted: m's check is current (vx__svo_trusted_models): a model the reader
 * rebuilt from the structural form is coded in it with the check's settings
 * and without the rebuild that proves the form. hooks: the write desc's test
 * hooks (may be NULL): far_limit, parallel_always, split_no_runs, unchecked. */
bool vx__svo_pack_model(const vx_svo_model* m, const vx_allocator* A, int chunked, unsigned threads, const vx_svo_testing* hooks, bool trusted,
                        vx_buf* out);
/* Whether a writer with vx_write_desc.svo_chunk_words = min_words stores m in
 * the chunked form (FORMAT.md 3.6): a model with a root descriptor and at
 * least min_words words (0: never). */
bool vx__svo_model_chunked(const vx_svo_model* m, uint32_t min_words);
/* split_min: vx__svo_model_split's; trusted (model_count entries, or NULL):
 * the models whose check vx__svo_trusted_models found current */
bool vx__svo_pack_write(vx_buf* out, const vx_svo_scene* s, const vx_allocator* A, unsigned threads, const vx_svo_testing* t,
                        uint32_t chunk_min, int chunk_mode, uint32_t split_min, const uint8_t* trusted, const vx__svo_sink* sink);
/* A guess of the bytes vx__svo_pack_write appends for s (without coding
 * anything): the file writer places NODE behind a header that holds its
 * size as a varint, and only that varint's length must come out right for
 * NODE to stay where it was written (svo_io.c write_file). */
uint64_t vx__svo_pack_estimate(const vx_svo_scene* s, uint32_t chunk_min, int chunk_mode, uint32_t split_min);
/* chunked: per model, nonzero when SCNE marks its stream chunked: 1 the
 * DEFLATE chunks of version 3, 2 the tagged chunks of version 4, 3 the
 * split form of version 5, or 4 the split form in a file of version 6 or
 * later (its runs stream allowed) (NULL: none). */
/* ext, rebuilt (model_count entries each, or NULL): a model rebuilt from
 * the structural form gets rebuilt[i] = VX__SVO_SKIP_REBUILT and its tree's
 * extent in ext[i] (others: untouched), for the validation to check its
 * head only (vx__svo_validate_scene_opt). */
/* t: the read desc's test hooks (parallel_always; may be NULL). */
vx_result vx__svo_pack_read(const uint8_t* p, size_t n, uint64_t base, vx_svo_scene* s, const uint8_t* chunked, const vx_allocator* A,
                            unsigned threads, const vx_svo_testing* t, vx_svo_chunk_stats* stats, vx__svo_extent* ext, uint8_t* rebuilt,
                            vx_error* err);

/* What is wrong with src[0..zn) as the one zstd frame of a chunk or stream
 * that must decode to exactly `want` bytes (checked before decoding, so the
 * decoder is bounded by it), or NULL; svo_pack.c, used by svo_split.c too. */
const char* vx__zstd_frame_problem(const uint8_t* src, size_t zn, size_t want);

/* The split structural form (svo_split.c, FORMAT.md 3.7, version 5): the
 * symbols of 3.4 in byte streams by kind and level class, each a zstd frame
 * or stored. A model's SPLIT stream starts with a form byte: 0 the stream of
 * 3.4 follows (a model the structural form cannot give back), 1 the split
 * streams. Writers use it for models of VX__SPLIT_WORDS words or more unless
 * vx_write_desc.svo_range_coded is set. */
/* streams: 10 fixed (masks, references) and one per channel; zstd level 3:
 * level 6 codes the benchmark terrain into 0.93 of the bytes but writes it
 * 1.25-1.4x slower (docs/PERFORMANCE.md, ".svo I/O, tenth step") */
/* zstd levels: the structural streams at 3; the value planes (differences)
 * at 1, which codes them smaller and faster than 3 (the 4096^3 helmet's file
 * 0.974x, its write 0.81x the CPU; the terrain's file 1.001x: docs/PERFORMANCE.md,
 * ".svo I/O, fifteenth step") */
enum { VX__SPLIT_FIXED = 10, VX__SPLIT_MAX = 15, VX__SPLIT_LEVEL = 3, VX__SPLIT_VALUE_LEVEL = 1 };
/* The split form's flags byte: bit 2 (format version 6) says the runs stream
 * follows the channels' streams: each node's attribute run as the layout
 * placed it (vx__svo_unpack_desc.runs). Writers add it to every split model
 * with attributes and the DAG. */
enum { VX__SPLIT_RUNS = 4 };
/* (Tests write version 5's split form, without the runs stream, with
 * vx_svo_testing.split_no_runs, and small models in the split form with
 * vx_svo_testing.split_words.) */
/* v, kind, ctx: the symbols of a model of `depth` levels (as the writer's
 * walk gives them, references as distances); appends the bytes after the
 * form byte to out. */
/* runs: the runs stream's values in completion order (one per node; NULL:
 * no runs stream, version 5's form). */
bool vx__svo_split_encode(const uint32_t* v, const uint8_t* kind, const uint32_t* ctx, size_t n, const uint8_t* runs, uint32_t attrs,
                          unsigned depth, bool dag, uint32_t limit, unsigned threads, const vx_allocator* A, vx_buf* out);
/* The same from a walk that puts the symbols one by one (the trusted write:
 * no symbol arrays): REF as 0 or 1 + the node's completion index. */
/* The streams as they are filled: bytes for masks and references, each
 * channel's values as they come (put in byte planes when coded). Here, not
 * in svo_split.c, so that the walk's put is inline: a call per symbol was a
 * twentieth of the 4096^3 helmet's write. */
typedef struct vx__svo_split_sink {
    const vx_allocator* A;
    uint8_t cs[5];
    unsigned k;
    bool oom, runs; /* runs: p[VX__SPLIT_FIXED] is the runs stream (stream k - 1) */
    uint8_t* p[VX__SPLIT_FIXED + 1];
    size_t n[VX__SPLIT_FIXED + 1], cap[VX__SPLIT_FIXED + 1];
    uint32_t* val[5];
    size_t nval[5], capval[5];
} vx__svo_split_sink;
/* runs: the sink has the runs stream (put as VX__SYM_RUN, ctx 0). */
vx__svo_split_sink* vx__svo_split_sink_new(uint32_t attrs, bool runs, const vx_allocator* A);
/* Room for `values` values in each channel's array up front (a hint: the
 * puts grow it past that as before; nothing where it cannot be had). */
void vx__svo_split_sink_reserve(vx__svo_split_sink* k, size_t values);
/* The put where its stream has no room (grows it; k->oom without memory). */
void vx__svo_split_put_slow(vx__svo_split_sink* k, unsigned kind, unsigned ctx, uint32_t v);
static inline void vx__svo_split_put(vx__svo_split_sink* k, unsigned kind, unsigned ctx, uint32_t v) {
    if (kind == VX__SYM_VALUE) {
        if (k->nval[ctx] < k->capval[ctx]) {
            k->val[ctx][k->nval[ctx]++] = v;
            return;
        }
    } else {
        /* the stream (svo_split.c stream_of): VALID 0..3, LEAF 4..6, REF 7..9 by level class, RUN the last */
        unsigned lv = kind == VX__SYM_LEAF ? (ctx & 0xFFu) : ctx;
        unsigned c = lv >= 4 ? 3u : lv - 1u;
        unsigned s = kind == VX__SYM_RUN ? (unsigned)VX__SPLIT_FIXED : kind == VX__SYM_VALID ? c : kind == VX__SYM_LEAF ? 3 + c : 6 + c;
        if (k->n[s] + 5 <= k->cap[s]) {
            uint8_t* q = k->p[s] + k->n[s];
            if (kind == VX__SYM_REF) { /* LEB128 */
                do {
                    uint8_t b = (uint8_t)(v & 0x7Fu);
                    v >>= 7;
                    *q++ = (uint8_t)(b | (v ? 0x80u : 0u));
                } while (v);
            } else {
                *q++ = (uint8_t)v;
            }
            k->n[s] = (size_t)(q - k->p[s]);
            return;
        }
    }
    vx__svo_split_put_slow(k, kind, ctx, v);
}
/* The runs stream's bytes put so far (the writer rewrites them in place
 * before coding), NULL without one. */
uint8_t* vx__svo_split_sink_runs(vx__svo_split_sink* k, size_t* n);
/* Codes the streams put so far (false: out of memory); the sink stays the caller's to free. */
bool vx__svo_split_sink_code(vx__svo_split_sink* k, bool dag, uint32_t limit, unsigned threads, vx_buf* out);
void vx__svo_split_sink_free(vx__svo_split_sink* k);
/* Large buffers kept between the models one thread of a read decodes in
 * turn (vx_run_jobs' per-thread state): a model's decoded streams (the
 * 4096^3 helmet's: tens of MB each) are freed when it is read, and the
 * next model's, asked for moments later, came back from the kernel as
 * fresh pages to fault in and clear (a third of the read's page faults).
 * A buffer is handed out again only to the thread that freed it; every
 * byte of it is written before it is read (zstd's output, the values,
 * the copies), so nothing depends on its old bytes. Zero-initialised:
 * empty; vx__svo_scratch_free gives everything back. */
enum { VX__SCRATCH_SLOTS = 16, VX__SCRATCH_MIN = 1 << 20 };
typedef struct vx__svo_scratch {
    void* p[VX__SCRATCH_SLOTS];
    size_t cap[VX__SCRATCH_SLOTS];
    size_t min; /* the smallest buffer kept (0: VX__SCRATCH_MIN; vx_svo_testing.scratch_any: 1) */
} vx__svo_scratch;
/* A buffer of at least n bytes (the smallest kept one that fits, else
 * vx_alloc; *cap its size), NULL without memory. sc may be NULL. */
void* vx__svo_scratch_get(vx__svo_scratch* sc, const vx_allocator* A, size_t n, size_t* cap);
/* Keeps p (cap bytes; from vx__svo_scratch_get or vx_alloc) for a later get,
 * or frees it (sc NULL, small, or no slot free: the smallest kept one
 * smaller than p makes room). */
void vx__svo_scratch_put(vx__svo_scratch* sc, const vx_allocator* A, void* p, size_t cap);
void vx__svo_scratch_free(vx__svo_scratch* sc, const vx_allocator* A);
typedef struct vx__svo_split vx__svo_split;
/* Parses the streams after the form byte (p[0..n), base: its file offset),
 * checks every length against m's declared node_count and decodes them on
 * up to `threads` threads. */
/* runs_ok: the file's version has the runs stream (6 and later; the flags'
 * bit is refused in older files). */
/* sc: buffers kept between models (used where threads is 1), or NULL. */
vx_result vx__svo_split_open(const uint8_t* p, size_t n, uint64_t base, const vx_svo_model* m, uint32_t mi, unsigned threads, bool runs_ok,
                             const vx_allocator* A, vx__svo_scratch* sc, vx__svo_split** out, bool* dag, uint32_t* limit, vx_error* err);
vx__svo_src vx__svo_split_src(vx__svo_split* d);
/* The decoded runs stream (NULL, 0: the model has none). */
const uint8_t* vx__svo_split_runs_stream(const vx__svo_split* d, size_t* n);
/* The channels of attrs whose decoded values are all one value (a stream of
 * at least one value), and those values in *cst (others zero): the
 * reconstruction then runs direct on the one channel left (vx__svo_unpack_desc.const_attrs). */
uint32_t vx__svo_split_constants(const vx__svo_split* d, uint32_t attrs, vx__svo_rec* cst);
/* After the reconstruction: every stream used up exactly. */
vx_result vx__svo_split_done(vx__svo_split* d, vx_error* err);
void vx__svo_split_free(vx__svo_split* d);
/* Whether a writer stores m in the split form: not chunked, a root
 * descriptor, structural channels only, at least split_min words (0: never). */
bool vx__svo_model_split(const vx_svo_model* m, uint32_t chunk_min, uint32_t split_min);

/* One model of the NODE section: model mi's stream p[0, n) (base: its file
 * offset) decoded into m (its declared fields set, as read_scne sets them),
 * chunked as SCNE marks it (0, 1, 2, or 3 the split form and 4 the same in a file of version 6 or later, as read_scne sets it), on up to
 * `threads` threads within the model; ext and rebuilt as vx__svo_pack_read's
 * for this model (both or neither). The model is not validated here. */
vx_result vx__svo_unpack_one(const uint8_t* p, size_t n, uint64_t base, vx_svo_model* m, uint32_t mi, uint8_t chunked,
                             const vx_allocator* A, unsigned threads, const vx_svo_testing* t, vx__svo_extent* ext, uint8_t* rebuilt,
                             vx_error* err);
/* vx_crc32 (the same CRC-32), by libdeflate where the build has it: the
 * sections' checksums are one thread's pass over the whole file, about
 * 0.2 s for the 311 MB helmet with slicing-by-8. */
uint32_t vx__svo_crc32(uint32_t crc, const void* data, size_t n);

#endif
