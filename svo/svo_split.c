/* svo/svo_split.c - the split structural form of a model's NODE stream
 * (docs/FORMAT.md 3.7, format version 5).
 *
 * The structural symbols of 3.4 (valid masks, leaf masks, references, the
 * values of leaf children) in separate byte streams, one per kind and level
 * class, each one zstd frame (or stored). The range coder of 3.4 spends
 * 40-50% of a structural read in one thread's bit-by-bit chain; here the
 * streams decode on every thread at zstd's speed and the reconstruction
 * (vx__svo_unpack) takes each symbol with a load from its stream. Splitting
 * by kind and level class keeps most of the contexts the range coder had:
 * masks of one level look alike, references and colours are runs. */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <string.h>
#include <zstd.h>

#include "svo/svo_internal.h"

static unsigned lclass(unsigned level) { return level >= 4 ? 3 : level - 1; }
static const unsigned CH_W[5] = {1, 4, 4, 2, 4}; /* bytes per value: palette, RGBA8, normal, material, density */

/* The stream a symbol goes to: VALID 0..3 (levels 1, 2, 3, 4+), LEAF 4..6
 * (levels 2, 3, 4+), REF 7..9 (the same), then one per channel of the model
 * in channel order. */
static unsigned stream_of(unsigned kind, unsigned ctx, const uint8_t chan_stream[5]) {
    switch (kind) {
    case VX__SYM_VALID: return lclass(ctx);
    case VX__SYM_LEAF: return 4 + lclass(ctx & 0xFFu) - 1;
    case VX__SYM_REF: return 7 + lclass(ctx) - 1;
    case VX__SYM_VALUE: return chan_stream[ctx];
    default: return ctx; /* VX__SYM_RUN: its stream's index, the last one */
    }
}

/* runs: the runs stream (version 6) after the channels' streams */
static unsigned stream_count(uint32_t attrs, bool runs, uint8_t chan_stream[5]) {
    unsigned k = VX__SPLIT_FIXED;
    for (unsigned c = 0; c < 5; c++) chan_stream[c] = (uint8_t)(attrs >> c & 1u ? k++ : 0);
    return k + (runs ? 1u : 0u);
}

static uint8_t* put_leb(uint8_t* p, uint64_t v) {
    do {
        uint8_t c = (uint8_t)(v & 0x7Fu);
        v >>= 7;
        *p++ = (uint8_t)(c | (v ? 0x80u : 0u));
    } while (v);
    return p;
}

/* RGBA8 and material values: each byte plane as differences (mod 256) from
 * the byte before it in the plane (the first from 0). Neighbouring leaves of
 * a shaded surface differ a little in each byte: as differences the helmet's
 * colours code to 0.77 of their bytes as they are, the terrain's few exact
 * colours to 1.001 (docs/PERFORMANCE.md, ".svo I/O, tenth step"). */
/* (the writer's side: planes_put, below) */
/* The reader's side: the planes p (differences) summed and interleaved into
 * out, value k's `width` bytes at width * k, least significant first, the
 * form the reconstruction reads (vx__svo_split_cur.data). One pass that
 * reads the planes in order and writes the values in order: the
 * reconstruction then reads one array in order where it read `width`
 * planes, a load from each a value (a sixth of the 4096^3 helmet's
 * unp_visit), and the pass replaces the planes' own summing pass. */
static void planes_values(uint8_t* restrict out, const uint8_t* restrict p, size_t count, unsigned width) {
    if (width == 4) {
        const uint8_t *p0 = p, *p1 = p + count, *p2 = p + 2 * count, *p3 = p + 3 * count;
        uint8_t a0 = 0, a1 = 0, a2 = 0, a3 = 0;
        for (size_t k = 0; k < count; k++) {
            a0 = (uint8_t)(a0 + p0[k]), a1 = (uint8_t)(a1 + p1[k]), a2 = (uint8_t)(a2 + p2[k]), a3 = (uint8_t)(a3 + p3[k]);
            uint32_t v = (uint32_t)a0 | (uint32_t)a1 << 8 | (uint32_t)a2 << 16 | (uint32_t)a3 << 24;
            memcpy(out + 4 * k, &v, 4);
        }
    } else { /* 2 (material) */
        const uint8_t *p0 = p, *p1 = p + count;
        uint8_t a0 = 0, a1 = 0;
        for (size_t k = 0; k < count; k++) {
            a0 = (uint8_t)(a0 + p0[k]), a1 = (uint8_t)(a1 + p1[k]);
            out[2 * k] = a0, out[2 * k + 1] = a1;
        }
    }
}

/* ---- writer ---------------------------------------------------------------------------------- */

/* Values into byte planes (byte b of value i at b * count + i), as
 * differences where a value has several bytes (each byte less the one before it), one
 * plane at a time: each pass reads the values in order and writes one
 * plane, which the compiler vectorises (a byte of (v[i] >> s) - (v[i-1] >> s)
 * is the difference of the bytes); the loop by value and then by byte, and
 * a pass of differences after it, were a twentieth of the 4096^3 helmet's write. */
static inline void planes_w(uint8_t* pl, const uint32_t* v, size_t cnt, const unsigned w) {
    for (unsigned b = 0; b < w; b++) {
        uint8_t* q = pl + (size_t)b * cnt;
        const unsigned sh = 8 * b;
        if (!cnt) break;
        q[0] = (uint8_t)(v[0] >> sh);
        if (w == 1)
            for (size_t i = 1; i < cnt; i++) q[i] = (uint8_t)v[i];
        else
            for (size_t i = 1; i < cnt; i++) q[i] = (uint8_t)((v[i] >> sh) - (v[i - 1] >> sh));
    }
}
static void planes_put(uint8_t* pl, const uint32_t* v, size_t cnt, unsigned w) {
    if (w == 4) planes_w(pl, v, cnt, 4);
    else if (w == 2) planes_w(pl, v, cnt, 2);
    else planes_w(pl, v, cnt, 1);
}

/* (the sink: svo_internal.h, where its put is inline) */

vx__svo_split_sink* vx__svo_split_sink_new(uint32_t attrs, bool runs, const vx_allocator* A) {
    vx__svo_split_sink* k = (vx__svo_split_sink*)vx_calloc(A, 1, sizeof *k);
    if (!k) return NULL;
    k->A = A;
    k->runs = runs;
    k->k = stream_count(attrs, runs, k->cs);
    return k;
}

void vx__svo_split_sink_reserve(vx__svo_split_sink* k, size_t values) {
    /* grown by doubling from nothing, each array was copied by realloc at
     * every step below glibc's mmap threshold (32 MB after a few large
     * frees) and faulted in a 4 KB page at a time: with the 4096^3 helmet's
     * write, most of its page faults. At the model's record count, advised
     * as 2 MB pages, untouched pages cost nothing. */
    for (unsigned c = 0; c < 5; c++) {
        if (!k->cs[c] || k->val[c] || !values || values > SIZE_MAX / sizeof *k->val[c]) continue;
        if ((k->val[c] = (uint32_t*)vx_alloc(k->A, values * sizeof *k->val[c])) == NULL) continue;
        k->capval[c] = values;
        vx__svo_advise_huge(k->val[c], values * sizeof *k->val[c]);
    }
}

void vx__svo_split_sink_free(vx__svo_split_sink* k) {
    if (!k) return;
    for (unsigned s = 0; s <= VX__SPLIT_FIXED; s++) vx_free(k->A, k->p[s]);
    for (unsigned c = 0; c < 5; c++) vx_free(k->A, k->val[c]);
    vx_free(k->A, k);
}

/* Room for 5 more bytes in stream s (the largest symbol, a reference). */
static bool sink_room(vx__svo_split_sink* k, unsigned s) {
    if (k->n[s] + 5 <= k->cap[s]) return true;
    if (!vx_grow(k->A, (void**)&k->p[s], &k->cap[s], k->n[s] + 5, 1)) return k->oom = true, false;
    vx__svo_advise_huge(k->p[s], k->cap[s]); /* the pages the growth adds: 2 MB ones (see put_slow) */
    return true;
}

void vx__svo_split_put_slow(vx__svo_split_sink* k, unsigned kind, unsigned ctx, uint32_t v) {
    if (kind == VX__SYM_VALUE) {
        if (k->nval[ctx] >= k->capval[ctx] &&
            !vx_grow(k->A, (void**)&k->val[ctx], &k->capval[ctx], k->nval[ctx] + 1, sizeof *k->val[ctx])) {
            k->oom = true;
            return;
        }
        /* the pages the growth adds (realloc moves a large block's pages and
         * keeps its advice), faulted in as 2 MB pages: the sink's arrays, a
         * 4 KB fault at a time, were most of the 4096^3 helmet's split
         * write's 390 K faults */
        vx__svo_advise_huge(k->val[ctx], k->capval[ctx] * sizeof *k->val[ctx]);
        k->val[ctx][k->nval[ctx]++] = v;
        return;
    }
    unsigned s = kind == VX__SYM_RUN ? VX__SPLIT_FIXED : stream_of(kind, ctx, k->cs); /* p[] index */
    if (!sink_room(k, s)) return;
    if (kind == VX__SYM_REF) k->n[s] = (size_t)(put_leb(k->p[s] + k->n[s], v) - k->p[s]);
    else k->p[s][k->n[s]++] = (uint8_t)v;
}

typedef struct enc_job {
    uint8_t* raw[VX__SPLIT_MAX];
    size_t n[VX__SPLIT_MAX];
    void* z[VX__SPLIT_MAX];
    size_t zn[VX__SPLIT_MAX]; /* 0: stored */
    int level[VX__SPLIT_MAX];
    const vx_allocator* A;
    bool oom;
} enc_job;

static void enc_stream(void* ctx, unsigned thread, uint32_t i) {
    (void)thread;
    enc_job* j = (enc_job*)ctx;
    j->zn[i] = 0;
    if (j->n[i] < 64) return; /* a frame's header costs more than it saves */
    size_t cap = ZSTD_compressBound(j->n[i]);
    void* z = vx_alloc(j->A, cap);
    ZSTD_CCtx* cc = z ? ZSTD_createCCtx() : NULL;
    if (!cc) {
        vx_free(j->A, z);
        j->oom = true;
        return;
    }
    /* the frame declares its size (the reader checks it before allocating);
     * no checksum: the section's CRC covers the stream */
    size_t got = ZSTD_isError(ZSTD_CCtx_setParameter(cc, ZSTD_c_compressionLevel, j->level[i])) ||
                         ZSTD_isError(ZSTD_CCtx_setParameter(cc, ZSTD_c_contentSizeFlag, 1))
                     ? (size_t)-1
                     : ZSTD_compress2(cc, z, cap, j->raw[i], j->n[i]);
    ZSTD_freeCCtx(cc);
    if (ZSTD_isError(got) || got >= j->n[i]) {
        vx_free(j->A, z);
        return;
    }
    j->z[i] = z;
    j->zn[i] = got;
}

bool vx__svo_split_sink_code(vx__svo_split_sink* k, bool dag, uint32_t limit, unsigned threads, vx_buf* out) {
    enc_job j;
    memset(&j, 0, sizeof j);
    j.A = k->A;
    for (unsigned s = 0; s < VX__SPLIT_MAX; s++) j.level[s] = VX__SPLIT_LEVEL;
    bool ok = !k->oom;
    for (unsigned s = 0; s < VX__SPLIT_FIXED; s++) j.raw[s] = k->p[s], j.n[s] = k->n[s];
    if (k->runs) j.raw[k->k - 1] = k->p[VX__SPLIT_FIXED], j.n[k->k - 1] = k->n[VX__SPLIT_FIXED];
    uint8_t* planes[5] = {NULL, NULL, NULL, NULL, NULL};
    for (unsigned c = 0; c < 5 && ok; c++) {
        if (!k->cs[c]) continue;
        /* byte b of value i at b * count + i */
        size_t cnt = k->nval[c];
        unsigned w = CH_W[c], s = k->cs[c];
        if (!(planes[c] = (uint8_t*)vx_alloc(k->A, cnt ? cnt * w : 1))) {
            ok = false;
            break;
        }
        vx__svo_advise_huge(planes[c], cnt * w); /* fresh, written whole */
        planes_put(planes[c], k->val[c], cnt, w);
        j.raw[s] = planes[c];
        j.n[s] = cnt * w;
        j.level[s] = VX__SPLIT_VALUE_LEVEL;
    }
    if (ok) {
        vx_run_jobs(threads ? threads : 1, k->k, enc_stream, &j);
        ok = !j.oom;
    }
    if (ok) {
        uint8_t head[16 + 20 * VX__SPLIT_MAX], *h = head;
        *h++ = (uint8_t)((dag ? 1u : 0u) | (limit != VX__SVO_PTR_MAX ? 2u : 0u) | (k->runs ? (unsigned)VX__SPLIT_RUNS : 0u));
        if (limit != VX__SVO_PTR_MAX) h = put_leb(h, limit);
        for (unsigned s = 0; s < k->k; s++) {
            h = put_leb(h, j.n[s]);
            h = put_leb(h, j.zn[s]);
        }
        ok = vx_buf_append(out, head, (size_t)(h - head));
        for (unsigned s = 0; s < k->k && ok; s++)
            ok = j.zn[s] ? vx_buf_append(out, j.z[s], j.zn[s]) : vx_buf_append(out, j.raw[s] ? j.raw[s] : (const uint8_t*)"", j.n[s]);
    }
    for (unsigned c = 0; c < 5; c++) vx_free(k->A, planes[c]);
    for (unsigned s = 0; s < VX__SPLIT_MAX; s++) vx_free(k->A, j.z[s]);
    return ok && !out->failed;
}

/* The symbols' walk (FORMAT.md 3.4's grammar) over a symbol array: a
 * reference becomes 1 + the completion index of the node it names. */
typedef struct walk {
    const uint32_t* v;
    const uint8_t* kind;
    const uint32_t* ctx;
    size_t n, i;
    uint32_t ndone;
    bool bad;
    vx__svo_split_sink* k;
    const uint8_t* runs; /* one per completed node, or NULL */
} walk;

static void walk_put(walk* w, size_t i) {
    uint32_t x = w->v[i];
    if (w->kind[i] == VX__SYM_REF && x) x = w->ndone - x + 1;
    vx__svo_split_put(w->k, w->kind[i], w->ctx[i], x);
}

/* The symbols come from the writer's own walk (ext_visit), so they follow
 * the grammar; w->bad guards the array's end regardless. */
static void walk_node(walk* w, unsigned level, unsigned nch) {
    if (w->i + (level > 1 ? 2 : 1) > w->n || w->bad || level < 1) {
        w->bad = true;
        return;
    }
    uint32_t valid = w->v[w->i], leaf = valid;
    walk_put(w, w->i++);
    if (level > 1) {
        leaf = w->v[w->i];
        walk_put(w, w->i++);
    }
    for (unsigned o = 0; o < 8 && !w->bad; o++) {
        if (!(valid >> o & 1u)) continue;
        if (leaf >> o & 1u) {
            if (w->i + nch > w->n) {
                w->bad = true;
                return;
            }
            for (unsigned c = 0; c < nch; c++) walk_put(w, w->i++);
        } else {
            if (w->i >= w->n || w->kind[w->i] != VX__SYM_REF || level < 2) {
                w->bad = true;
                return;
            }
            uint32_t r = w->v[w->i];
            walk_put(w, w->i++);
            if (r == 0) walk_node(w, level - 1, nch);
        }
    }
    if (w->runs && !w->bad) vx__svo_split_put(w->k, VX__SYM_RUN, 0, w->runs[w->ndone]);
    w->ndone++;
}

bool vx__svo_split_encode(const uint32_t* v, const uint8_t* kind, const uint32_t* ctx, size_t n, const uint8_t* runs, uint32_t attrs,
                          unsigned depth, bool dag, uint32_t limit, unsigned threads, const vx_allocator* A, vx_buf* out) {
    vx__svo_split_sink* k = vx__svo_split_sink_new(attrs, runs != NULL, A);
    if (!k) return false;
    walk w = {v, kind, ctx, n, 0, 0, false, k, runs};
    walk_node(&w, depth, (unsigned)__builtin_popcount(attrs));
    bool ok = !w.bad && w.i == n && vx__svo_split_sink_code(k, dag, limit, threads, out);
    vx__svo_split_sink_free(k);
    return ok;
}

/* ---- reader ---------------------------------------------------------------------------------- */

void* vx__svo_scratch_get(vx__svo_scratch* sc, const vx_allocator* A, size_t n, size_t* cap) {
    if (sc && n >= (sc->min ? sc->min : VX__SCRATCH_MIN)) {
        int best = -1;
        for (int i = 0; i < VX__SCRATCH_SLOTS; i++)
            if (sc->p[i] && sc->cap[i] >= n && (best < 0 || sc->cap[i] < sc->cap[best])) best = i;
        if (best >= 0) {
            void* p = sc->p[best];
            *cap = sc->cap[best];
            sc->p[best] = NULL;
            sc->cap[best] = 0;
            return p;
        }
    }
    *cap = n ? n : 1;
    void* p = vx_alloc(A, *cap);
    vx__svo_advise_huge(p, *cap); /* fresh: a decoded stream or the node list, written whole before it is read */
    return p;
}

void vx__svo_scratch_put(vx__svo_scratch* sc, const vx_allocator* A, void* p, size_t cap) {
    if (!p) return;
    if (sc && cap >= (sc->min ? sc->min : VX__SCRATCH_MIN)) {
        int slot = -1;
        for (int i = 0; i < VX__SCRATCH_SLOTS && slot < 0; i++)
            if (!sc->p[i]) slot = i;
        if (slot < 0) /* the smallest kept one, where it is smaller */
            for (int i = 0; i < VX__SCRATCH_SLOTS; i++)
                if (sc->cap[i] < cap && (slot < 0 || sc->cap[i] < sc->cap[slot])) slot = i;
        if (slot >= 0) {
            vx_free(A, sc->p[slot]);
            sc->p[slot] = p;
            sc->cap[slot] = cap;
            return;
        }
    }
    vx_free(A, p);
}

void vx__svo_scratch_free(vx__svo_scratch* sc, const vx_allocator* A) {
    if (!sc) return;
    for (int i = 0; i < VX__SCRATCH_SLOTS; i++) {
        vx_free(A, sc->p[i]);
        sc->p[i] = NULL;
        sc->cap[i] = 0;
    }
}

struct vx__svo_split {
    const vx_allocator* A;
    vx__svo_scratch* sc; /* buffers kept between models (one decoding thread only), or NULL */
    size_t owncap[VX__SPLIT_MAX];
    unsigned k;
    /* the decoded streams (data: own[s], or into the file where stored),
     * lengths, read positions, values per channel stream, the channels'
     * streams: what vx__svo_unpack reads through (vx__svo_src.cur) */
    vx__svo_split_cur c;
    uint8_t* own[VX__SPLIT_MAX]; /* decoded streams (NULL: stored, data points into the file) */
    uint8_t delta[VX__SPLIT_MAX]; /* a channel's value width when its planes hold differences (RGBA8, material), else 0 */
    uint64_t zoff[VX__SPLIT_MAX]; /* each stream's file offset */
    size_t zn[VX__SPLIT_MAX];
    const uint8_t* zsrc[VX__SPLIT_MAX];
    uint64_t base;
    uint32_t mi;
    bool runs; /* the last stream is the runs stream (flags bit VX__SPLIT_RUNS) */
    vx_result res[VX__SPLIT_MAX];
    vx_error errs[VX__SPLIT_MAX];
};

static const char* stream_name(unsigned s, char buf[48], const uint8_t cs[5]) {
    static const char* const CH[5] = {"palette", "rgba8", "normal", "material", "density"};
    snprintf(buf, 48, "runs"); /* the one stream past the channels' */
    if (s < 4) snprintf(buf, 48, "valid masks, level class %u", s);
    else if (s < 7) snprintf(buf, 48, "leaf masks, level class %u", s - 3);
    else if (s < 10) snprintf(buf, 48, "references, level class %u", s - 6);
    else
        for (unsigned c = 0; c < 5; c++)
            if (cs[c] == s) snprintf(buf, 48, "%s values", CH[c]);
    return buf;
}

static void dec_stream(void* ctx, unsigned thread, uint32_t s) {
    (void)thread;
    vx__svo_split* d = (vx__svo_split*)ctx;
    d->res[s] = VX_OK;
    if (!d->zn[s] && d->delta[s]) { /* stored differences: summed into values */
        if (!(d->own[s] = (uint8_t*)vx__svo_scratch_get(d->sc, d->A, d->c.n[s], &d->owncap[s]))) {
            d->res[s] = vx_fail(&d->errs[s], VX_ERR_NOMEM, VX_NO_OFFSET, "svo: out of memory");
            return;
        }
        planes_values(d->own[s], d->zsrc[s], d->c.vcount[s], d->delta[s]);
        d->c.data[s] = d->own[s];
        return;
    }
    if (!d->zn[s]) return;
    char nm[48];
    const uint8_t* src = d->zsrc[s];
    size_t zn = d->zn[s], want = d->c.n[s];
    const char* why = vx__zstd_frame_problem(src, zn, want);
    size_t got = 0;
    if (!why) {
        if (!(d->own[s] = (uint8_t*)vx__svo_scratch_get(d->sc, d->A, want, &d->owncap[s]))) {
            d->res[s] = vx_fail(&d->errs[s], VX_ERR_NOMEM, VX_NO_OFFSET, "svo: out of memory");
            return;
        }
        ZSTD_DCtx* z = ZSTD_createDCtx();
        if (!z) {
            d->res[s] = vx_fail(&d->errs[s], VX_ERR_NOMEM, VX_NO_OFFSET, "svo: out of memory");
            return;
        }
        got = ZSTD_decompressDCtx(z, d->own[s], want, src, zn);
        ZSTD_freeDCtx(z);
        if (ZSTD_isError(got)) why = ZSTD_getErrorName(got);
        else if (got != want) why = "too short";
    }
    if (why)
        d->res[s] = vx_fail(&d->errs[s], VX_ERR_BAD_FORMAT, d->zoff[s],
                            "svo: section NODE at byte %llu: model %u: stream %u (%s, %zu bytes, zstd) does not decode to exactly %zu bytes (%s)",
                            (unsigned long long)d->zoff[s], d->mi, s, stream_name(s, nm, d->c.cs), zn, want, why);
    else {
        if (d->delta[s]) { /* the planes into values: a buffer of their size, the planes freed */
            size_t vcap;
            uint8_t* v = (uint8_t*)vx__svo_scratch_get(d->sc, d->A, want, &vcap);
            if (!v) {
                d->res[s] = vx_fail(&d->errs[s], VX_ERR_NOMEM, VX_NO_OFFSET, "svo: out of memory");
                return;
            }
            planes_values(v, d->own[s], d->c.vcount[s], d->delta[s]);
            vx__svo_scratch_put(d->sc, d->A, d->own[s], d->owncap[s]);
            d->own[s] = v;
            d->owncap[s] = vcap;
        }
        d->c.data[s] = d->own[s];
    }
}

void vx__svo_split_free(vx__svo_split* d) {
    if (!d) return;
    for (unsigned s = 0; s < VX__SPLIT_MAX; s++) vx__svo_scratch_put(d->sc, d->A, d->own[s], d->owncap[s]);
    vx_free(d->A, d);
}

static bool rd_leb(const uint8_t* p, size_t n, size_t* pos, uint64_t max, uint64_t* out) {
    uint64_t v = 0;
    for (unsigned shift = 0; shift < 64; shift += 7) {
        if (*pos >= n) return false;
        uint8_t c = p[(*pos)++];
        v |= (uint64_t)(c & 0x7Fu) << shift;
        if (!(c & 0x80u)) {
            if (v > max || (c == 0 && shift)) return false; /* too large or not the shortest form */
            *out = v;
            return true;
        }
    }
    return false;
}

vx_result vx__svo_split_open(const uint8_t* p, size_t n, uint64_t base, const vx_svo_model* m, uint32_t mi, unsigned threads, bool runs_ok,
                             const vx_allocator* A, vx__svo_scratch* sc, vx__svo_split** out, bool* dag, uint32_t* limit, vx_error* err) {
    *out = NULL;
    /* the caller read the form byte (1) */
    size_t pos = 0;
    if (n < 1 || (p[0] & ~(3u | VX__SPLIT_RUNS)))
        return vx_fail(err, VX_ERR_BAD_FORMAT, base, "svo: section NODE at byte %llu: model %u: split form flags %s", (unsigned long long)base,
                       mi, n < 1 ? "cut off" : "with reserved bits set");
    if ((p[0] & VX__SPLIT_RUNS) && !runs_ok)
        return vx_fail(err, VX_ERR_BAD_FORMAT, base, "svo: section NODE at byte %llu: model %u: the split form's runs stream needs format version 6",
                       (unsigned long long)base, mi);
    *dag = p[0] & 1u;
    *limit = VX__SVO_PTR_MAX;
    pos = 1;
    uint64_t v;
    if ((p[0] & 2u) && (!rd_leb(p, n, &pos, VX__SVO_PTR_MAX, &v) || v == 0))
        return vx_fail(err, VX_ERR_BAD_FORMAT, base + 1, "svo: section NODE at byte %llu: model %u: the far limit is cut off or not in 1..%u",
                       (unsigned long long)(base + 1), mi, VX__SVO_PTR_MAX);
    if (p[0] & 2u) *limit = (uint32_t)v;
    vx__svo_split* d = (vx__svo_split*)vx_calloc(A, 1, sizeof *d);
    if (!d) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "svo: out of memory");
    d->A = A;
    d->sc = threads <= 1 ? sc : NULL; /* (the streams decode on one thread: the scratch has no lock) */
    d->base = base;
    d->mi = mi;
    d->runs = (p[0] & VX__SPLIT_RUNS) != 0;
    d->k = stream_count(m->attrs, d->runs, d->c.cs);
    /* every stream's decoded length is bounded by the declared words: a node
     * per word (its valid and leaf masks), a reference of at most 5 bytes per
     * word, a value per leaf child (8 per node) */
    const uint64_t W = (uint64_t)m->node_count + 1;
    vx_result r = VX_OK;
    char nm[48];
    for (unsigned s = 0; s < d->k && r == VX_OK; s++) {
        /* (the runs stream: a byte per node) */
        uint64_t max = s < 7 || (d->runs && s == d->k - 1) ? W : s < 10 ? 5 * W : 8 * W * 4, u, z;
        size_t at = pos;
        if (!rd_leb(p, n, &pos, max, &u) || !rd_leb(p, n, &pos, (uint64_t)n, &z)) {
            r = vx_fail(err, VX_ERR_BAD_FORMAT, base + at,
                        "svo: section NODE at byte %llu: model %u: stream %u (%s): its lengths are cut off, not the shortest varints or more than %llu bytes for %u words",
                        (unsigned long long)(base + at), mi, s, stream_name(s, nm, d->c.cs), (unsigned long long)max, m->node_count);
            break;
        }
        for (unsigned c = 0; c < 5; c++)
            if ((m->attrs >> c & 1u) && d->c.cs[c] == s) {
                if (u % CH_W[c] || u / CH_W[c] > 8 * W)
                    r = vx_fail(err, VX_ERR_BAD_FORMAT, base + at,
                                "svo: section NODE at byte %llu: model %u: stream %u (%s): %llu bytes, not a whole number of %u-byte values at most 8 per word",
                                (unsigned long long)(base + at), mi, s, stream_name(s, nm, d->c.cs), (unsigned long long)u, CH_W[c]);
                d->c.vcount[s] = (size_t)(u / CH_W[c]);
                d->delta[s] = (uint8_t)(CH_W[c] > 1 ? CH_W[c] : 0);
            }
        d->c.n[s] = (size_t)u;
        d->zn[s] = (size_t)z;
    }
    /* the bodies, back to back, end exactly at the end of the stream */
    for (unsigned s = 0; s < d->k && r == VX_OK; s++) {
        size_t len = d->zn[s] ? d->zn[s] : d->c.n[s];
        if (len > n - pos) {
            r = vx_fail(err, VX_ERR_TRUNCATED, base + pos, "svo: section NODE at byte %llu: model %u: stream %u (%s) of %zu bytes, %zu left",
                        (unsigned long long)(base + pos), mi, s, stream_name(s, nm, d->c.cs), len, n - pos);
            break;
        }
        d->zoff[s] = base + pos;
        d->zsrc[s] = p + pos;
        if (!d->zn[s]) d->c.data[s] = p + pos;
        pos += len;
    }
    if (r == VX_OK && pos != n)
        r = vx_fail(err, VX_ERR_BAD_FORMAT, base + pos, "svo: section NODE at byte %llu: model %u: %zu bytes after the last split stream",
                    (unsigned long long)(base + pos), mi, n - pos);
    if (r == VX_OK) {
        vx_run_jobs(threads ? threads : 1, d->k, dec_stream, d);
        for (unsigned s = 0; s < d->k && r == VX_OK; s++)
            if (d->res[s] != VX_OK) {
                r = d->res[s];
                if (err) *err = d->errs[s];
            }
    }
    if (r != VX_OK) {
        vx__svo_split_free(d);
        return r;
    }
    *out = d;
    return VX_OK;
}

uint32_t vx__svo_split_constants(const vx__svo_split* d, uint32_t attrs, vx__svo_rec* cst) {
    memset(cst, 0, sizeof *cst);
    uint32_t out = 0;
    for (unsigned c = 0; c < 5; c++) {
        unsigned s = d->c.cs[c];
        if (!(attrs >> c & 1u) || !s || !d->c.vcount[s] || !d->c.data[s]) continue;
        /* (values, not planes: the decoding interleaved them) every value the first */
        size_t w = CH_W[c], bytes = d->c.vcount[s] * w;
        const uint8_t* q = d->c.data[s];
        bool one = bytes <= w || (memcmp(q, q + bytes - w, w) == 0 && memcmp(q, q + w, bytes - w) == 0);
        if (!one) continue;
        uint32_t x = 0;
        for (unsigned i = 0; i < w; i++) x |= (uint32_t)q[i] << (8 * i);
        if (c == 0) cst->palette = (uint8_t)x;
        else if (c == 1) cst->rgba = x;
        else if (c == 2) cst->normal = x;
        else if (c == 3) cst->material = (uint16_t)x;
        else memcpy(&cst->density, &x, sizeof x);
        out |= 1u << c;
    }
    return out;
}

static bool ends(vx__svo_split* d, unsigned s, vx_error* err) {
    char nm[48];
    return vx_fail(err, VX_ERR_BAD_FORMAT, d->zoff[s], "svo: section NODE at byte %llu: model %u: stream %u (%s) ends before the trees do",
                   (unsigned long long)d->zoff[s], d->mi, s, stream_name(s, nm, d->c.cs)),
           false;
}

static bool split_next(void* user, unsigned kind, unsigned ctx, uint32_t* v, vx_error* err) {
    vx__svo_split* d = (vx__svo_split*)user;
    unsigned s = stream_of(kind, ctx, d->c.cs);
    size_t at = d->c.pos[s];
    const uint8_t* b = d->c.data[s];
    if (kind == VX__SYM_REF) { /* 0 or 1 + a node's completion index (vx__svo_unpack_desc.ref_index) */
        uint64_t r;
        size_t q = at;
        if (!rd_leb(b, d->c.n[s], &q, UINT32_MAX, &r)) {
            if (q >= d->c.n[s]) return ends(d, s, err);
            char nm[48];
            return vx_fail(err, VX_ERR_BAD_FORMAT, d->zoff[s],
                           "svo: section NODE at byte %llu: model %u: stream %u (%s), decoded byte %zu: not the shortest varint of at most 32 bits",
                           (unsigned long long)d->zoff[s], d->mi, s, stream_name(s, nm, d->c.cs), at),
                   false;
        }
        d->c.pos[s] = q;
        *v = (uint32_t)r;
        return true;
    }
    if (kind == VX__SYM_VALUE) {
        if (at >= d->c.vcount[s]) return ends(d, s, err);
        uint32_t x = 0;
        for (unsigned i = 0; i < CH_W[ctx]; i++) x |= (uint32_t)b[CH_W[ctx] * at + i] << (8 * i);
        d->c.pos[s] = at + 1;
        *v = x;
        return true;
    }
    if (at >= d->c.n[s]) return ends(d, s, err);
    *v = b[at];
    d->c.pos[s] = at + 1;
    if (kind == VX__SYM_LEAF && (*v & ~(ctx >> 8))) {
        char nm[48];
        return vx_fail(err, VX_ERR_BAD_FORMAT, d->zoff[s],
                       "svo: section NODE at byte %llu: model %u: stream %u (%s), decoded byte %zu: leaf mask 0x%02x outside the valid mask 0x%02x",
                       (unsigned long long)d->zoff[s], d->mi, s, stream_name(s, nm, d->c.cs), at, *v, ctx >> 8),
               false;
    }
    return true;
}

vx__svo_src vx__svo_split_src(vx__svo_split* d) { return (vx__svo_src){split_next, d, &d->c}; }

uint8_t* vx__svo_split_sink_runs(vx__svo_split_sink* k, size_t* n) {
    *n = k->runs ? k->n[VX__SPLIT_FIXED] : 0;
    return k->runs && !k->oom ? k->p[VX__SPLIT_FIXED] : NULL;
}

const uint8_t* vx__svo_split_runs_stream(const vx__svo_split* d, size_t* n) {
    *n = d->runs ? d->c.n[d->k - 1] : 0;
    return d->runs ? (d->c.data[d->k - 1] ? d->c.data[d->k - 1] : (const uint8_t*)"") : NULL;
}

vx_result vx__svo_split_done(vx__svo_split* d, vx_error* err) {
    char nm[48];
    /* (the runs stream is read by the layout, which checks its end: vx__svo_unpack) */
    for (unsigned s = 0; s < d->k - (d->runs ? 1u : 0u); s++) {
        size_t have = s >= VX__SPLIT_FIXED ? d->c.vcount[s] : d->c.n[s];
        if (d->c.pos[s] != have)
            return vx_fail(err, VX_ERR_BAD_FORMAT, d->zoff[s], "svo: section NODE at byte %llu: model %u: stream %u (%s): %zu of its %zu %s left over",
                           (unsigned long long)d->zoff[s], d->mi, s, stream_name(s, nm, d->c.cs), have - d->c.pos[s], have,
                           s >= VX__SPLIT_FIXED ? "values" : "bytes");
    }
    return VX_OK;
}
