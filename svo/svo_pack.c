/* svo/svo_pack.c - the NODE section: node words and attribute records of all
 * models, entropy-coded (docs/FORMAT.md section 3.4).
 *
 * A model built by vx_svo_build_model is stored structurally: its DAG in
 * depth-first order (valid masks, leaf masks, "new child" or a back-reference
 * to a completed node, the records of leaf children); pointers, far slots,
 * attribute indices and representative records are not stored, the reader
 * recomputes them with the builder's own layout (vx__svo_unpack). The writer
 * checks that the reconstruction gives the model back word for word and
 * otherwise stores the words and records themselves ("raw" form). All symbols
 * go through one adaptive binary range coder (the LZMA scheme: 11-bit
 * probabilities, shift 5), which on the small trees of typical .vox models
 * beats deflate clearly because it has no tables to transmit. Large models
 * (2^20 words or more) take the split form of version 5 instead: the same
 * symbols in zstd byte streams that decode on every thread (svo_split.c),
 * with attributes also the runs stream of version 6 (the layout's run
 * lookups only where a run is found again). */
#define _POSIX_C_SOURCE 200809L
#include <pthread.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <zlib.h>
#include <zstd.h>
#ifdef VX_HAVE_LIBDEFLATE
#include <libdeflate.h>
#endif

#include "svo/svo_internal.h"

#define STRUCT_ATTRS (VX_ATTR_PALETTE | VX_ATTR_RGBA8 | VX_ATTR_MATERIAL)
/* Sane maximum of words and of records per byte of NODE (the coder can
 * spend less than a bit per word on repetitive input, not 1/4096 of one). */
#define PACK_RATIO_MAX 4096u

/* ---- range coder ------------------------------------------------------------------------- */

typedef uint16_t prob;
#define PROB_INIT 1024u

typedef struct pk {
    bool enc;
    vx_buf* out;  /* encoder: the coded bytes */
    vx_buf* side; /* encoder: raw side bytes of 4-byte values */
    const uint8_t* raw; /* decoder: the side bytes */
    size_t raw_n, raw_pos;
    uint64_t low;
    uint32_t range;
    uint8_t cache;
    uint64_t cache_size;
    const uint8_t* p; /* decoder */
    size_t n, pos;
    uint32_t code;
    bool over;
    /* context models */
    prob form[4];
    prob valid[4][256];
    prob leaf[4][8];
    prob ref[4];
    prob dlen[32], dbit[32];
    prob eq[5][2];
    prob val[5][4][256];
    prob word[4][256];
    uint32_t prev[5];
    unsigned preveq[5];
} pk;

static void pk_init_models(pk* k) {
    prob* first = &k->form[0];
    prob* end = &k->word[3][255] + 1;
    for (prob* q = first; q < end; q++) *q = PROB_INIT;
    memset(k->prev, 0, sizeof k->prev);
    memset(k->preveq, 0, sizeof k->preveq);
}

static void shift_low(pk* k) {
    if ((uint32_t)k->low < 0xFF000000u || (k->low >> 32) != 0) {
        uint8_t carry = (uint8_t)(k->low >> 32), t = k->cache;
        do {
            vx_buf_u8(k->out, (uint8_t)(t + carry));
            t = 0xFF;
        } while (--k->cache_size != 0);
        k->cache = (uint8_t)(k->low >> 24);
    }
    k->cache_size++;
    k->low = (k->low & 0x00FFFFFFu) << 8;
}

static uint8_t next_byte(pk* k) {
    if (k->pos < k->n) return k->p[k->pos++];
    k->over = true; /* zeros past the end; the caller reports it */
    k->pos++;
    return 0;
}

/* Codes bit b (encoder) or returns the decoded bit (decoder; b ignored).
 * The coder's functions take `enc` as a constant and are inlined into one
 * encoder and one decoder per symbol (sym), which choose once per symbol, not
 * once per bit: the decoder spent a third of a read in bit(). */
static inline __attribute__((always_inline)) unsigned bit_x(pk* k, prob* p, unsigned b, const bool enc) {
    uint32_t bound = (k->range >> 11) * *p;
    if (enc) {
        if (!b) {
            k->range = bound;
            *p = (prob)(*p + ((2048u - *p) >> 5));
        } else {
            k->low += bound;
            k->range -= bound;
            *p = (prob)(*p - (*p >> 5));
        }
        while (k->range < (1u << 24)) {
            k->range <<= 8;
            shift_low(k);
        }
        return b;
    }
    if (k->code < bound) {
        k->range = bound;
        *p = (prob)(*p + ((2048u - *p) >> 5));
        b = 0;
    } else {
        k->code -= bound;
        k->range -= bound;
        *p = (prob)(*p - (*p >> 5));
        b = 1;
    }
    while (k->range < (1u << 24)) {
        k->range <<= 8;
        k->code = (k->code << 8) | next_byte(k);
    }
    return b;
}

static inline __attribute__((always_inline)) uint32_t tree8_x(pk* k, prob* t, uint32_t v, const bool enc) {
    unsigned m = 1;
    for (int i = 7; i >= 0; i--) m = (m << 1) | bit_x(k, &t[m], (v >> i) & 1u, enc);
    return m - 256;
}
static uint32_t plain_bits(pk* k, unsigned nb, uint32_t v) {
    const bool enc = k->enc;
    uint32_t out = 0;
    for (int i = (int)nb - 1; i >= 0; i--) {
        prob p = PROB_INIT;
        out = (out << 1) | bit_x(k, &p, (v >> i) & 1u, enc);
    }
    return out;
}

/* RGBA colours, normals and densities vary too much for the byte trees to
 * gain much (texture colours shrank by a few percent) while coding them bit
 * by bit was most of the writer's time; their differing values are stored
 * as plain bytes in the model's side stream. */
static inline __attribute__((always_inline)) uint32_t raw_u32_x(pk* k, uint32_t v, const bool enc) {
    if (enc) {
        uint8_t b[4] = {(uint8_t)v, (uint8_t)(v >> 8), (uint8_t)(v >> 16), (uint8_t)(v >> 24)};
        vx_buf_append(k->side, b, 4);
        return v;
    }
    if (k->raw_n - k->raw_pos < 4) {
        k->over = true;
        k->raw_pos = k->raw_n;
        return 0;
    }
    const uint8_t* b = k->raw + k->raw_pos;
    k->raw_pos += 4;
    return (uint32_t)b[0] | (uint32_t)b[1] << 8 | (uint32_t)b[2] << 16 | (uint32_t)b[3] << 24;
}

static unsigned level_class(unsigned level) { return level >= 4 ? 3 : level - 1; }
static const unsigned CH_BYTES[5] = {1, 4, 4, 2, 4};

/* One symbol (FORMAT.md 3.4): codes *v or decodes into it. */
static inline __attribute__((always_inline)) void sym_x(pk* k, unsigned kind, unsigned ctx, uint32_t* v, const bool enc) {
    switch (kind) {
    case VX__SYM_VALID: *v = tree8_x(k, k->valid[level_class(ctx)], *v, enc); break;
    case VX__SYM_LEAF: {
        unsigned lc = level_class(ctx & 0xFFu), valid = ctx >> 8;
        uint32_t out = 0;
        for (unsigned o = 0; o < 8; o++)
            if (valid >> o & 1u) out |= bit_x(k, &k->leaf[lc][o], (*v >> o) & 1u, enc) << o;
        *v = out;
        break;
    }
    case VX__SYM_REF: {
        uint32_t r = *v;
        if (!bit_x(k, &k->ref[level_class(ctx)], r != 0, enc)) {
            *v = 0;
            break;
        }
        unsigned want = enc ? 32u - (unsigned)__builtin_clz(r) : 0, nb = 1;
        while (nb < 32 && bit_x(k, &k->dlen[nb], nb < want, enc)) nb++;
        uint32_t out = 1;
        for (int j = (int)nb - 2; j >= 0; j--) out = (out << 1) | bit_x(k, &k->dbit[j], (r >> j) & 1u, enc);
        *v = out;
        break;
    }
    default: { /* VALUE: ctx is the channel */
        unsigned c = ctx;
        unsigned same = bit_x(k, &k->eq[c][k->preveq[c]], *v == k->prev[c], enc);
        uint32_t out = k->prev[c];
        if (!same && CH_BYTES[c] == 4) {
            out = raw_u32_x(k, *v, enc);
        } else if (!same) {
            out = 0;
            for (unsigned j = 0; j < CH_BYTES[c]; j++) out |= tree8_x(k, k->val[c][j], (*v >> (8 * j)) & 0xFFu, enc) << (8 * j);
        }
        k->preveq[c] = same;
        k->prev[c] = out;
        *v = out;
    }
    }
}

/* The encoder's twin of dec_bit: range and low in locals for a symbol, the
 * update by masks (the bit is as unpredictable to the coder's branch). */
typedef struct rce {
    uint64_t low;
    uint32_t range;
} rce;

static inline __attribute__((always_inline)) void enc_bit(pk* k, rce* r, prob* pp, unsigned b) {
    uint32_t p = *pp, bound = (r->range >> 11) * p, mask = 0u - (b & 1u);
    r->low += bound & mask;
    r->range = bound + ((r->range - 2 * bound) & mask);
    *pp = (prob)(p + (((2048u - p) >> 5) & ~mask) - ((p >> 5) & mask));
    while (r->range < (1u << 24)) {
        r->range <<= 8;
        k->low = r->low;
        shift_low(k);
        r->low = k->low;
    }
}

static inline __attribute__((always_inline)) void enc_tree8(pk* k, rce* r, prob* t, uint32_t v) {
    unsigned m = 1;
    for (int i = 7; i >= 0; i--) {
        unsigned b = (v >> i) & 1u;
        enc_bit(k, r, &t[m], b);
        m = (m << 1) | b;
    }
}

/* sym_x's encoder (the same grammar, FORMAT.md 3.4) on rce. */
static void sym_enc(pk* k, unsigned kind, unsigned ctx, uint32_t* v) {
    rce r = {k->low, k->range};
    switch (kind) {
    case VX__SYM_VALID: enc_tree8(k, &r, k->valid[level_class(ctx)], *v); break;
    case VX__SYM_LEAF: {
        unsigned lc = level_class(ctx & 0xFFu), valid = ctx >> 8;
        uint32_t out = 0;
        for (unsigned o = 0; o < 8; o++)
            if (valid >> o & 1u) {
                unsigned b = (*v >> o) & 1u;
                enc_bit(k, &r, &k->leaf[lc][o], b);
                out |= b << o;
            }
        *v = out;
        break;
    }
    case VX__SYM_REF: {
        uint32_t rf = *v;
        enc_bit(k, &r, &k->ref[level_class(ctx)], rf != 0);
        if (rf == 0) break;
        unsigned want = 32u - (unsigned)__builtin_clz(rf), nb = 1;
        while (nb < 32) {
            unsigned more = nb < want;
            enc_bit(k, &r, &k->dlen[nb], more);
            if (!more) break;
            nb++;
        }
        for (int j = (int)nb - 2; j >= 0; j--) enc_bit(k, &r, &k->dbit[j], (rf >> j) & 1u);
        break;
    }
    default: { /* VALUE: ctx is the channel */
        unsigned c = ctx, same = *v == k->prev[c];
        uint32_t out = *v;
        enc_bit(k, &r, &k->eq[c][k->preveq[c]], same);
        if (same) {
            out = k->prev[c];
        } else if (CH_BYTES[c] == 4) {
            raw_u32_x(k, out, true);
        } else {
            for (unsigned j = 0; j < CH_BYTES[c]; j++) enc_tree8(k, &r, k->val[c][j], (out >> (8 * j)) & 0xFFu);
            out &= CH_BYTES[c] == 1 ? 0xFFu : 0xFFFFu; /* what the decoder gets */
        }
        k->preveq[c] = same;
        k->prev[c] = out;
        *v = out;
    }
    }
    k->low = r.low;
    k->range = r.range;
}
/* The decoder's state in locals for one symbol (registers: through pk the
 * compiler stored range and code back after every bit). */
typedef struct rcd {
    uint32_t range, code;
    const uint8_t* p;
    size_t n, pos;
    bool over;
} rcd;

/* bit_x's decoder, with selects where it branches: the bits of masks and
 * distances are close to random, so that branch was mispredicted about
 * every other bit. One normalisation step is enough: p stays in 31..2017
 * (the updates' fixed points), so a bit leaves the range >= 2^24 * 31 /
 * 2048 > 2^16 and one shift brings it back above 2^24. */
static inline __attribute__((always_inline)) unsigned dec_bit(rcd* r, prob* pp) {
    uint32_t p = *pp, bound = (r->range >> 11) * p;
    unsigned b = r->code >= bound;
    uint32_t mask = 0u - b; /* all ones for a 1 */
    r->code -= bound & mask;
    r->range = bound + ((r->range - 2 * bound) & mask); /* (mod 2^32) range - bound for a 1 */
    *pp = (prob)(p + (((2048u - p) >> 5) & ~mask) - ((p >> 5) & mask));
    if (r->range < (1u << 24)) {
        r->range <<= 8;
        r->code = r->code << 8 | (r->pos < r->n ? r->p[r->pos] : (r->over = true, 0u)); /* next_byte */
        r->pos++;
    }
    return b;
}

static inline __attribute__((always_inline)) uint32_t dec_tree8(rcd* r, prob* t) {
    unsigned m = 1;
    for (int i = 0; i < 8; i++) m = (m << 1) | dec_bit(r, &t[m]);
    return m - 256;
}

/* sym_x's decoder (the same grammar, FORMAT.md 3.4) on rcd. */
static void sym_dec(pk* k, unsigned kind, unsigned ctx, uint32_t* v) {
    rcd r = {k->range, k->code, k->p, k->n, k->pos, false};
    switch (kind) {
    case VX__SYM_VALID: *v = dec_tree8(&r, k->valid[level_class(ctx)]); break;
    case VX__SYM_LEAF: {
        unsigned lc = level_class(ctx & 0xFFu), valid = ctx >> 8;
        uint32_t out = 0;
        for (unsigned o = 0; o < 8; o++)
            if (valid >> o & 1u) out |= dec_bit(&r, &k->leaf[lc][o]) << o;
        *v = out;
        break;
    }
    case VX__SYM_REF: {
        if (!dec_bit(&r, &k->ref[level_class(ctx)])) {
            *v = 0;
            break;
        }
        unsigned nb = 1;
        while (nb < 32 && dec_bit(&r, &k->dlen[nb])) nb++;
        uint32_t out = 1;
        for (int j = (int)nb - 2; j >= 0; j--) out = (out << 1) | dec_bit(&r, &k->dbit[j]);
        *v = out;
        break;
    }
    default: { /* VALUE: ctx is the channel */
        unsigned c = ctx;
        unsigned same = dec_bit(&r, &k->eq[c][k->preveq[c]]);
        uint32_t out = k->prev[c];
        if (!same && CH_BYTES[c] == 4) {
            out = raw_u32_x(k, 0, false);
        } else if (!same) {
            out = 0;
            for (unsigned j = 0; j < CH_BYTES[c]; j++) out |= dec_tree8(&r, k->val[c][j]) << (8 * j);
        }
        k->preveq[c] = same;
        k->prev[c] = out;
        *v = out;
    }
    }
    k->range = r.range;
    k->code = r.code;
    k->pos = r.pos;
    if (r.over) k->over = true; /* (raw_u32_x may have set it too) */
}
static void sym(pk* k, unsigned kind, unsigned ctx, uint32_t* v) {
    if (k->enc) sym_enc(k, kind, ctx, v);
    else sym_dec(k, kind, ctx, v);
}
static unsigned bit(pk* k, prob* p, unsigned b) { return k->enc ? bit_x(k, p, b, true) : bit_x(k, p, b, false); }

static uint32_t word_sym(pk* k, uint32_t w) {
    uint32_t out = 0;
    for (unsigned j = 0; j < 4; j++)
        out |= (k->enc ? tree8_x(k, k->word[j], (w >> (8 * j)) & 0xFFu, true) : tree8_x(k, k->word[j], 0, false)) << (8 * j);
    return out;
}

static uint32_t rec_get(const vx_svo_model* m, unsigned c, uint32_t r) {
    switch (c) {
    case 0: return m->palette[r];
    case 1: return m->rgba[r];
    case 2: return m->normal[r];
    case 3: return m->material[r];
    default: {
        union { float f; uint32_t u; } x = {m->density[r]};
        return x.u;
    }
    }
}

/* ---- writer: the depth-first symbols of a model -------------------------------------------------- */

typedef struct ext {
    const vx_svo_model* m;
    const vx_allocator* A;
    bool dag, oom;
    uint32_t* v;     /* the symbols, with the kind and context the reader will ask each with */
    uint8_t* kind;
    uint32_t* ctx;
    size_t n, cap, capk, capc;
    /* A completed node is known by (block, masks). The first node seen with
     * a block is kept in fb/fm, indexed by the block's word position (one
     * access, no probing: most of the writer's time went to the hash's cache
     * misses); nodes without a block and a second node with another mask on
     * the same block go to the hash. */
    uint32_t* fb; /* block -> completion index + 1 (0: none yet) */
    uint16_t* fm; /* its masks */
    uint64_t* hk; /* (block << 16 | masks) + 1 -> completion index */
    uint32_t* hv;
    size_t hcap, hused, hmax; /* hmax: the most slots (2 a word); the table starts small and doubles */
    uint32_t ndone;
    unsigned tries; /* try_struct calls so far */
    bool bad;       /* the words are not a valid tree (only a model that was not validated: a trusted check) */
    vx__svo_split_sink* sink; /* when set, the symbols go straight into the split streams (not into v, kind, ctx) */
    /* The split form's runs stream (FORMAT.md 3.7, version 6): each completed
     * node's run as the words place it, new where its record index a is nid
     * (the records the layout has appended so far), else found; put during
     * the walk as the new run's length (1..8) or RUN_FOUND, with the bit of a
     * found run's start set in tgt, then made 0, 1 (new and found later) or
     * 2 by runs_fix; into the sink, or into rv when there is none. */
    bool runs;
    uint32_t nid;
    uint64_t* tgt; /* attr_count bits */
    uint8_t* rv;
    size_t nrv, caprv;
} ext;

enum { RUN_FOUND = 0x10 };

/* The runs stream's final bytes from the walk's (above): a new run is 1 when
 * a later run is found at its start, else 0; a found one 2. */
static void runs_fix(uint8_t* r, size_t n, const uint64_t* tgt) {
    uint64_t nid = 0;
    for (size_t i = 0; i < n; i++) {
        if (r[i] == RUN_FOUND) {
            r[i] = 2;
            continue;
        }
        uint8_t len = r[i];
        r[i] = (uint8_t)(tgt[nid >> 6] >> (nid & 63u) & 1u);
        nid += len;
    }
}

static void ext_push(ext* x, unsigned kind, uint32_t ctx, uint32_t v) {
    if (x->sink) { /* a reference as the index of the node it names (FORMAT.md 3.7) */
        vx__svo_split_put(x->sink, kind, ctx, kind == VX__SYM_REF && v ? x->ndone - v + 1 : v);
        x->n++;
        return;
    }
    if (x->n < x->cap && x->n < x->capk && x->n < x->capc) { /* the common case without a call (vx_grow) per symbol */
        x->kind[x->n] = (uint8_t)kind;
        x->ctx[x->n] = ctx;
        x->v[x->n++] = v;
        return;
    }
    if (x->oom) return;
    if (!vx_grow(x->A, (void**)&x->v, &x->cap, x->n + 1, sizeof *x->v) ||
        !vx_grow(x->A, (void**)&x->kind, &x->capk, x->n + 1, sizeof *x->kind) ||
        !vx_grow(x->A, (void**)&x->ctx, &x->capc, x->n + 1, sizeof *x->ctx)) {
        x->oom = true;
        return;
    }
    x->kind[x->n] = (uint8_t)kind;
    x->ctx[x->n] = ctx;
    x->v[x->n++] = v;
}

/* The block of descriptor i (UINT32_MAX: none), or false where the words
 * cannot be a valid tree (a pointer out of range): the walk below is safe on
 * any words, so a writer may take a model it did not validate (its check
 * current, vx__svo_trusted_models) and a model that is not valid after all
 * gives symbols that do not read back, never a crash. */
static bool block_at(const vx_svo_model* m, uint32_t i, uint32_t* out) {
    uint32_t d = m->nodes[i], nn = vx__popc8(vx_svo_desc_valid(d) & ~vx_svo_desc_leaf(d)), na = m->attrs ? 1u : 0u;
    *out = UINT32_MAX;
    if (nn + na == 0) return true;
    uint32_t p = vx_svo_desc_ptr(d);
    if (p > i) return false;
    uint32_t b = vx_svo_desc_far(d) ? m->nodes[i - p] : i - p;
    if (b > m->node_count || nn + na > m->node_count - b) return false;
    *out = b;
    return true;
}
static uint64_t key_with(const vx_svo_model* m, uint32_t i, uint32_t b) { return ((uint64_t)b << 16 | (m->nodes[i] & 0xFFFFu)) + 1; }
static size_t key_slot(const ext* x, uint64_t key) {
    uint64_t h = key * 0x9E3779B97F4A7C15ull;
    size_t j = (size_t)(h >> 20) & (x->hcap - 1);
    while (x->hk[j] && x->hk[j] != key) j = (j + 1) & (x->hcap - 1);
    return j;
}

/* The completion index of the node equal to descriptor i (block b), or UINT32_MAX. */
static uint32_t ext_find(const ext* x, uint32_t i, uint32_t b) {
    uint32_t mk = x->m->nodes[i] & 0xFFFFu;
    if (b != UINT32_MAX) {
        if (!x->fb[b]) return UINT32_MAX;
        if (x->fm[b] == mk) return x->fb[b] - 1;
    }
    size_t j = key_slot(x, key_with(x->m, i, b));
    return x->hk[j] ? x->hv[j] : UINT32_MAX;
}

/* The hash at twice its slots, its entries moved (through key_slot, the one
 * placement); false (x->oom) without memory. */
static bool ext_grow(ext* x) {
    size_t cap = x->hcap * 2, old_cap = x->hcap;
    uint64_t *hk = (uint64_t*)vx_calloc(x->A, cap, sizeof *hk), *old_k = x->hk;
    uint32_t *hv = (uint32_t*)vx_calloc(x->A, cap, sizeof *hv), *old_v = x->hv;
    if (!hk || !hv) {
        vx_free(x->A, hk);
        vx_free(x->A, hv);
        x->oom = true;
        return false;
    }
    x->hk = hk, x->hv = hv, x->hcap = cap;
    for (size_t j = 0; j < old_cap; j++) {
        if (!old_k[j]) continue;
        size_t k = key_slot(x, old_k[j]);
        hk[k] = old_k[j];
        hv[k] = old_v[j];
    }
    vx_free(x->A, old_k);
    vx_free(x->A, old_v);
    return true;
}

/* Records descriptor i (block b) as completed node `done` unless an equal one is. */
static void ext_add(ext* x, uint32_t i, uint32_t b, uint32_t done) {
    uint32_t mk = x->m->nodes[i] & 0xFFFFu;
    if (b != UINT32_MAX) {
        if (!x->fb[b]) {
            x->fb[b] = done + 1;
            x->fm[b] = (uint16_t)mk;
            return;
        }
        if (x->fm[b] == mk) return;
    }
    size_t j = key_slot(x, key_with(x->m, i, b));
    if (!x->hk[j]) {
        if (x->hused + 1 > x->hcap / 2) {
            if (x->hcap >= x->hmax) { /* (only an invalid model completes more nodes than words) */
                x->bad = true;
                return;
            }
            if (!ext_grow(x)) return;
            j = key_slot(x, key_with(x->m, i, b));
        }
        x->hk[j] = key_with(x->m, i, b);
        x->hv[j] = done;
        x->hused++;
    }
}

/* The values of channel c of records a .. a + n - 1 (a node's leaf
 * children, in order) into the split sink, as ext_push would put them one
 * by one: a loop per channel where a put (and rec_get's switch) per child
 * and channel was. */
static void ext_values(ext* x, unsigned c, uint32_t a, unsigned n) {
    const vx_svo_model* m = x->m;
    vx__svo_split_sink* k = x->sink;
    if (k->capval[c] - k->nval[c] < n) { /* (no room: the put grows the array) */
        for (unsigned r = 0; r < n; r++) ext_push(x, VX__SYM_VALUE, c, rec_get(m, c, a + r));
        return;
    }
    uint32_t* q = k->val[c] + k->nval[c];
    switch (c) {
    case 0:
        for (unsigned r = 0; r < n; r++) q[r] = m->palette[a + r];
        break;
    case 1: memcpy(q, m->rgba + a, n * sizeof *q); break;
    case 2: memcpy(q, m->normal + a, n * sizeof *q); break;
    case 3:
        for (unsigned r = 0; r < n; r++) q[r] = m->material[a + r];
        break;
    default:
        for (unsigned r = 0; r < n; r++) q[r] = rec_get(m, c, a + r);
    }
    k->nval[c] += n;
    x->n += n;
}

/* A valid tree (or x->bad set): each node at most once with the DAG (and a
 * tree's nodes once without it), so no more completed nodes than words. */
static void ext_visit(ext* x, uint32_t i, unsigned level) {
    const vx_svo_model* m = x->m;
    uint32_t b;
    if (x->bad || level < 1 || i >= m->node_count || x->ndone >= m->node_count || !block_at(m, i, &b)) {
        x->bad = true;
        return;
    }
    uint32_t d = m->nodes[i], valid = vx_svo_desc_valid(d), leaf = vx_svo_desc_leaf(d);
    uint32_t nn = vx__popc8(valid & ~leaf), a = m->attrs ? m->nodes[b + nn] : 0, k = 0, rank = 0;
    if (!valid || (leaf & ~valid) || (level == 1 && leaf != valid) ||
        (m->attrs && (a > m->attr_count || vx__popc8(valid) > m->attr_count - a))) {
        x->bad = true;
        return;
    }
    ext_push(x, VX__SYM_VALID, level, valid);
    if (level > 1) ext_push(x, VX__SYM_LEAF, level | valid << 8, leaf);
    if (x->dag && nn > 1) {
        /* the non-leaf children's entries (fb, fm: a completed twin) and
         * blocks fetched together: each is a miss to memory, which the loop
         * below took one child at a time (a hint: nothing is read here but
         * the parent's block, which block_at checks) */
        for (uint32_t j = 0; j < nn; j++) {
            uint32_t cb;
            if (!block_at(m, b + j, &cb) || cb == UINT32_MAX) continue;
            __builtin_prefetch(&x->fb[cb]);
            __builtin_prefetch(&x->fm[cb]);
            __builtin_prefetch(&m->nodes[cb]);
        }
    }
    /* every child a leaf (every node at level 1, most of a model's): each
     * channel's values at once, where the sink keeps a stream per channel
     * (without it the symbols are interleaved, child by child) */
    if (x->sink && leaf == valid)
        for (unsigned c = 0; c < 5; c++)
            if (m->attrs >> c & 1u) ext_values(x, c, a, vx__popc8(valid));
    for (unsigned o = 0; o < 8 && !x->bad && !(x->sink && leaf == valid); o++) {
        if (!(valid >> o & 1u)) continue;
        if (leaf >> o & 1u) {
            for (unsigned c = 0; c < 5; c++)
                if (m->attrs >> c & 1u) ext_push(x, VX__SYM_VALUE, c, rec_get(m, c, a + rank));
        } else {
            uint32_t ci = b + k++, cb;
            if (!block_at(m, ci, &cb)) {
                x->bad = true;
                return;
            }
            uint32_t done = x->dag ? ext_find(x, ci, cb) : UINT32_MAX;
            if (done != UINT32_MAX) {
                ext_push(x, VX__SYM_REF, level, x->ndone - done);
            } else {
                ext_push(x, VX__SYM_REF, level, 0);
                ext_visit(x, ci, level - 1);
            }
        }
        rank++;
    }
    if (x->bad) return;
    if (x->runs) {
        /* (a <= attr_count - popcount(valid): checked above) */
        uint8_t r = a == x->nid ? (uint8_t)vx__popc8(valid) : (uint8_t)RUN_FOUND;
        if (a == x->nid) x->nid += vx__popc8(valid);
        else x->tgt[a >> 6] |= 1ull << (a & 63u);
        if (x->sink) vx__svo_split_put(x->sink, VX__SYM_RUN, 0, r);
        else if (x->nrv < x->caprv || vx_grow(x->A, (void**)&x->rv, &x->caprv, x->nrv + 1, sizeof *x->rv)) x->rv[x->nrv++] = r;
        else x->oom = true;
    }
    if (x->dag) ext_add(x, i, b, x->ndone);
    x->ndone++;
}

/* Symbols from an array (the writer's check). The encoder codes each with
 * the kind and context the writer's walk gave it (possibly while the check
 * runs), so the check requires the reader to ask for exactly those. */
typedef struct arr_src {
    const uint32_t* v;
    size_t n, pos;
    const uint8_t* kind;
    const uint32_t* ctx;
} arr_src;
static bool arr_next(void* user, unsigned kind, unsigned ctx, uint32_t* v, vx_error* err) {
    arr_src* s = (arr_src*)user;
    if (s->pos >= s->n) return vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "svo pack: symbols exhausted"), false;
    if (s->kind[s->pos] != kind || s->ctx[s->pos] != ctx)
        return vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "svo pack: symbol %zu asked as another kind", s->pos), false;
    *v = s->v[s->pos++];
    return true;
}

static bool model_same(const vx_svo_model* a, const vx_svo_model* b) {
    if (a->node_count != b->node_count || a->root != b->root || a->root_attr != b->root_attr || a->attr_count != b->attr_count)
        return false;
    if (a->node_count && memcmp(a->nodes, b->nodes, (size_t)a->node_count * 4) != 0) return false;
    size_t n = a->attr_count;
    if ((a->attrs & VX_ATTR_PALETTE) && n && memcmp(a->palette, b->palette, n) != 0) return false;
    if ((a->attrs & VX_ATTR_RGBA8) && n && memcmp(a->rgba, b->rgba, n * 4) != 0) return false;
    if ((a->attrs & VX_ATTR_MATERIAL) && n && memcmp(a->material, b->material, n * 2) != 0) return false;
    return true;
}

/* The model's coded bytes (FORMAT.md 3.4): the form bits, then the
 * structural symbols of src or the raw words and records; k fresh. */
static void code_stream(pk* k, const vx_svo_model* m, bool structural, bool dag, uint32_t limit, const arr_src* src) {
    bit(k, &k->form[0], structural);
    if (structural) {
        bit(k, &k->form[1], dag);
        if (bit(k, &k->form[2], limit != VX__SVO_PTR_MAX)) plain_bits(k, 15, limit);
        for (size_t i = 0; i < src->n; i++) {
            uint32_t v = src->v[i];
            sym_enc(k, src->kind[i], src->ctx[i], &v);
        }
    } else {
        for (uint32_t i = 0; i < m->node_count; i++) word_sym(k, m->nodes[i]);
        for (uint32_t r = 0; r < m->attr_count; r++)
            for (unsigned c = 0; c < 5; c++)
                if (m->attrs >> c & 1u) {
                    uint32_t v = rec_get(m, c, r);
                    sym(k, VX__SYM_VALUE, c, &v);
                }
    }
    for (int i = 0; i < 5; i++) shift_low(k);
}

/* A coder with its own output and side buffers. */
typedef struct coder {
    pk* k;
    vx_buf coded, side;
    /* the structural stream coded on another thread while the writer's
     * check runs (its result is used only when the check passes) */
    const vx_svo_model* m;
    const arr_src* src;
    bool dag;
    uint32_t limit;
    pthread_t th;
    bool started;
} coder;

static bool coder_init(coder* c, const vx_allocator* A) {
    memset(c, 0, sizeof *c);
    c->k = (pk*)vx_calloc(A, 1, sizeof *c->k);
    if (!c->k) return false;
    c->coded.alloc = c->side.alloc = A;
    pk_init_models(c->k);
    c->k->enc = true;
    c->k->out = &c->coded;
    c->k->side = &c->side;
    c->k->range = 0xFFFFFFFFu;
    c->k->cache_size = 1;
    return true;
}
static void coder_free(coder* c, const vx_allocator* A) {
    vx_buf_free(&c->coded);
    vx_buf_free(&c->side);
    vx_free(A, c->k);
    c->k = NULL;
}
static void* coder_main(void* arg) {
    coder* c = (coder*)arg;
    code_stream(c->k, c->m, true, c->dag, c->limit, c->src);
    return NULL;
}

/* Tries the structural form with one (dag, limit) setting; on success the
 * symbols with their kinds and contexts are left in x / src. An allocation
 * failure returns false with x->oom set. */
/* spec: when given, the symbols are coded on another thread while the check
 * runs (started only; the caller joins spec->th when spec->started). lay:
 * the check's layout threads (vx__svo_unpack_desc.layout_threads). */
static bool try_struct(const vx_svo_model* m, const vx_allocator* A, bool dag, uint32_t limit, ext* x, arr_src* src,
                       coder* spec, unsigned lay) {
    x->n = 0;
    x->ndone = 0;
    x->dag = dag;
    x->oom = false;
    x->bad = false;
    x->nid = 0;
    x->nrv = 0;
    if (x->runs && x->tgt) memset(x->tgt, 0, ((size_t)m->attr_count / 64 + 1) * 8);
    /* fresh tables are zero (calloc); only a second try clears what it used */
    if (x->tries++) {
        memset(x->fb, 0, (size_t)m->node_count * sizeof *x->fb);
        if (x->hused) memset(x->hk, 0, x->hcap * sizeof *x->hk);
        x->hused = 0;
    }
    ext_visit(x, m->root, m->depth);
    if (x->oom || x->bad) return false;
    src->v = x->v;
    src->kind = x->kind;
    src->ctx = x->ctx;
    src->n = x->n;
    src->pos = 0;
    if (spec && coder_init(spec, A)) {
        spec->m = m;
        spec->src = src;
        spec->dag = dag;
        spec->limit = limit;
        spec->started = pthread_create(&spec->th, NULL, coder_main, spec) == 0;
    }
    vx__svo_src s = {arr_next, src, NULL};
    vx__svo_unpack_desc ud = {.depth = m->depth, .attrs = m->attrs, .dag = dag, .limit = limit, .max_words = m->node_count, .alloc = A,
                              .layout_threads = lay};
    vx_svo_model r;
    memset(&r, 0, sizeof r);
    r.attrs = m->attrs;
    vx_error e;
    vx_result ur = vx__svo_unpack(&ud, &s, &r, &e);
    if (ur == VX_ERR_NOMEM) x->oom = true;
    bool ok = ur == VX_OK && src->pos == src->n && model_same(&r, m);
    vx_svo_model_free(A, &r);
    return ok;
}

/* ---- per-model streams and threads ------------------------------------------------------------- */

/* Each model is one independent coded stream (fresh contexts), so models
 * pack and unpack in parallel; NODE is, per model, a LEB128 byte length and
 * the stream. Threads are only used for large scenes: small ones stay on the
 * caller's thread, which keeps allocation order (and the OOM tests) exact.
 * The bytes never depend on the thread count. */
static unsigned pack_threads(const vx_svo_scene* s, unsigned want, const vx_svo_testing* t) { return vx__svo_threads(s, want, t); }
#define run_jobs vx_run_jobs

static bool put_var(vx_buf* b, uint64_t v) {
    do {
        uint8_t c = (uint8_t)(v & 0x7Fu);
        v >>= 7;
        if (!vx_buf_u8(b, (uint8_t)(c | (v ? 0x80u : 0u)))) return false;
    } while (v);
    return true;
}

int vx__svo_chunk_mode(const vx_write_desc* desc) {
    if (!desc) return VX__CHUNK_ZSTD;
    return desc->svo_chunk_stored ? VX__CHUNK_STORED
           : desc->svo_chunk_fast ? VX__CHUNK_FAST
           : desc->svo_chunk_deflate ? VX__CHUNK_DEFLATE
                                     : VX__CHUNK_ZSTD;
}

uint32_t vx__svo_crc32(uint32_t crc, const void* data, size_t n) {
#ifdef VX_HAVE_LIBDEFLATE
    return libdeflate_crc32(crc, data, n); /* carry-less multiply where the CPU has it: several GB/s */
#else
    return vx_crc32(crc, data, n);
#endif
}

/* ---- the chunked form (format version 3, docs/FORMAT.md 3.6) --------------------------------------
 * A large model's words and records as they are in memory, in chunks of
 * about CHUNK_RAW bytes, each raw DEFLATE on its own. The structural form is
 * several times smaller, but its reader re-runs the builder's layout (run
 * table, record interning, far slots) in one sequential pass and its writer
 * proves the form by rebuilding the model: 15-25 CPU seconds for the 4096^3
 * helmet. Chunks need neither, map straight onto the arrays and code and
 * decode on every core, even within one model. */
#define CHUNK_RAW ((uint64_t)4 << 20)
/* Inflated bytes per deflated byte that a chunk may declare: deflate never
 * exceeds 1032:1, so this bounds what a reader allocates by the file's size. */
#define CHUNK_RATIO_MAX 2048u
/* Codec bytes of the tagged chunks (format version 4, FORMAT.md 3.6): each
 * chunk's first byte. zstd over the transformed bytes: on the H200 host's
 * cores (GPU-made 4096^3 helmet, docs/PERFORMANCE.md ".svo I/O, seventh
 * step") level 1 codes in 0.53 of DEFLATE level 1's CPU time into 0.997 of
 * its bytes (its records come out larger), level 2 in 0.63 into 0.957,
 * level 3 in 0.75 into 0.926; level 2 keeps the 2-core write under 3 s
 * (2.1-2.8 s), the helmet and the benchmark terrain smaller than DEFLATE
 * (0.957, 0.968; terrains of 25 M voxels and less 0.3-0.6% larger). A chunk that
 * zstd would shrink past CHUNK_RATIO_MAX (long runs of one value) is
 * DEFLATEd instead, so the reader's bound on allocations holds for every
 * codec. */
enum { CHUNK_CODEC_DEFLATE = 0, CHUNK_CODEC_ZSTD = 1, CHUNK_CODEC_ZSTD_PLAIN = 2 };
#define CHUNK_ZSTD_LEVEL 2
/* The writer's choice between CHUNK_CODEC_ZSTD and _PLAIN for a chunk of
 * colour or normal records: SAMPLE_WINDOWS windows of SAMPLE_RECORDS
 * records spread over the chunk, coded both ways (about 1.5% of the
 * chunk's coding). Differences suit the helmet's shaded colours (0.36 of
 * the bytes against 0.48), the values as they are suit the terrain's few
 * exact colours (0.34 against 0.45): a whole scene's records go one way, and
 * the samples picked the smaller coding of each chunk of both. */
#define SAMPLE_WINDOWS 4u
#define SAMPLE_RECORDS 2048u
#define SAMPLE_LEVEL 1 /* the samples' zstd level: the cheapest, the same choice in the measured scenes */

static uint32_t rec_bytes(uint32_t attrs) {
    uint32_t n = 0;
    for (unsigned c = 0; c < 5; c++)
        if (attrs >> c & 1u) n += CH_BYTES[c];
    return n;
}

bool vx__svo_model_chunked(const vx_svo_model* m, uint32_t min_words) {
    if (min_words == 0) return false; /* the default: the compact form */
    return m->root < m->node_count && m->node_count >= min_words;
}

/* The pieces of a chunk's inflated bytes: its words, then each channel's
 * records (FORMAT.md 3.6); n[k] = 0 for a channel the model does not have. */
static void chunk_pieces(const vx_svo_model* m, uint32_t w0, uint32_t nw, uint32_t r0, uint32_t nr, uint8_t* p[6], size_t n[6]) {
    void* arrs[5] = {m->palette, m->rgba, m->normal, m->material, m->density};
    p[0] = (uint8_t*)(m->nodes + w0);
    n[0] = (size_t)nw * 4;
    for (unsigned c = 0; c < 5; c++) {
        bool has = m->attrs >> c & 1u;
        p[1 + c] = has && nr ? (uint8_t*)arrs[c] + (size_t)r0 * CH_BYTES[c] : NULL;
        n[1 + c] = has ? (size_t)nr * CH_BYTES[c] : 0;
    }
}

/* Byte order of the pieces in memory: the file is little-endian. */
static void swap_piece(uint8_t* p, size_t n, unsigned width) {
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_BIG_ENDIAN__
    for (size_t i = 0; i + width <= n; i += width)
        for (unsigned a = 0, b = width - 1; a < b; a++, b--) {
            uint8_t t = p[i + a];
            p[i + a] = p[i + b];
            p[i + b] = t;
        }
#else
    (void)p, (void)n, (void)width;
#endif
}
static const unsigned PIECE_WIDTH[6] = {4, 1, 4, 4, 2, 4};

typedef struct chunk_job {
    const vx_svo_model* m;
    const vx_allocator* A;
    uint32_t count, wcount; /* chunks; the first wcount hold words only, the others records only */
    int level, wlevel; /* deflate level of record chunks and of word chunks: 1, or 0 (stored blocks) */
    bool tagged;       /* VX__CHUNK_ZSTD: each chunk a codec byte, then zstd (or DEFLATE) */
    uint8_t** out; /* writer: each chunk's deflated bytes */
    size_t* out_n;
    bool* ok;
} chunk_job;

static uint32_t chunk_at(uint32_t total, uint32_t i, uint32_t count) { return (uint32_t)((uint64_t)total * i / count); }
/* The words [w0, w1) and records [r0, r1) of the writer's chunk i: the
 * words in wcount chunks, then the records in the rest, so that a chunk is
 * one piece (or one per channel) that codes and inflates in place, without
 * gathering the pieces into a buffer (FORMAT.md 3.6 leaves the split free). */
static void chunk_range(const chunk_job* j, uint32_t i, uint32_t* w0, uint32_t* w1, uint32_t* r0, uint32_t* r1) {
    const vx_svo_model* m = j->m;
    if (i < j->wcount) {
        *w0 = chunk_at(m->node_count, i, j->wcount), *w1 = chunk_at(m->node_count, i + 1, j->wcount);
        *r0 = *r1 = 0;
    } else {
        uint32_t rc = j->count - j->wcount, k = i - j->wcount;
        *w0 = *w1 = m->node_count;
        *r0 = chunk_at(m->attr_count, k, rc), *r1 = chunk_at(m->attr_count, k + 1, rc);
    }
}

/* DEFLATEs chunk i behind `pre` bytes left free (the codec byte of a
 * tagged chunk), at the job's level. */
static void deflate_chunk_at(chunk_job* j, uint32_t i, size_t pre) {
    const vx_svo_model* m = j->m;
    uint32_t w0, w1, r0, r1;
    chunk_range(j, i, &w0, &w1, &r0, &r1);
    const int level = i < j->wcount ? j->wlevel : j->level;
    uint8_t* p[6];
    size_t n[6], raw = 0;
    chunk_pieces(m, w0, w1 - w0, r0, r1 - r0, p, n);
    for (int k = 0; k < 6; k++) raw += n[k];
    j->ok[i] = false;
#if defined(VX_HAVE_LIBDEFLATE) && !(defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_BIG_ENDIAN__)
    if (level > 0) {
        /* libdeflate codes one contiguous buffer: a chunk of several pieces
         * (words, then each channel's records) is gathered first (a copy of
         * 4 MB, against some 20 ms of coding) */
        int np = 0, one = 0;
        for (int k = 0; k < 6; k++)
            if (n[k]) np++, one = k;
        uint8_t* buf = np > 1 ? (uint8_t*)vx_alloc(j->A, raw) : NULL;
        const uint8_t* src = np > 1 ? buf : p[one];
        if (np > 1 && buf)
            for (size_t k = 0, at = 0; k < 6; at += n[k], k++)
                if (n[k]) memcpy(buf + at, p[k], n[k]);
        struct libdeflate_compressor* c = (np < 2 || buf) ? libdeflate_alloc_compressor(level) : NULL;
        size_t cap = c ? libdeflate_deflate_compress_bound(c, raw) : 0;
        uint8_t* out = c ? (uint8_t*)vx_alloc(j->A, cap + pre) : NULL;
        size_t got = out ? libdeflate_deflate_compress(c, src, raw, out + pre, cap) : 0;
        if (c) libdeflate_free_compressor(c);
        vx_free(j->A, buf);
        if (!got) {
            vx_free(j->A, out);
            return;
        }
        j->out[i] = out;
        j->out_n[i] = got + pre;
        j->ok[i] = true;
        return;
    }
#endif
    z_stream z;
    memset(&z, 0, sizeof z);
    if (deflateInit2(&z, level, Z_DEFLATED, -15, 8, Z_DEFAULT_STRATEGY) != Z_OK) return;
    size_t cap = (size_t)deflateBound(&z, (uLong)raw);
    uint8_t* out = (uint8_t*)vx_alloc(j->A, cap + pre);
    uint8_t* tmp = NULL;
    bool ok = out != NULL;
    z.next_out = out ? out + pre : NULL;
    z.avail_out = (uInt)cap;
    int last = 5;
    while (last > 0 && n[last] == 0) last--;
    for (int k = 0; ok && k <= last; k++) {
        const uint8_t* src = p[k];
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_BIG_ENDIAN__
        vx_free(j->A, tmp);
        tmp = n[k] ? (uint8_t*)vx_alloc(j->A, n[k]) : NULL;
        if (n[k] && !tmp) {
            ok = false;
            break;
        }
        if (n[k]) memcpy(tmp, p[k], n[k]), swap_piece(tmp, n[k], PIECE_WIDTH[k]), src = tmp;
#endif
        z.next_in = (Bytef*)(uintptr_t)src;
        z.avail_in = (uInt)n[k];
        int zr = deflate(&z, k == last ? Z_FINISH : Z_NO_FLUSH);
        ok = k == last ? zr == Z_STREAM_END : zr == Z_OK || zr == Z_BUF_ERROR;
        ok = ok && z.avail_in == 0;
    }
    deflateEnd(&z);
    vx_free(j->A, tmp);
    if (!ok) {
        vx_free(j->A, out);
        return;
    }
    j->out[i] = out;
    j->out_n[i] = pre + (size_t)(cap - z.avail_out);
    j->ok[i] = true;
}

/* The bytes that a tagged chunk's zstd frame holds (FORMAT.md 3.6): the
 * words as four byte planes (byte 0 of every word, then byte 1, ...), and
 * each 4-byte RGBA8 or normal record as the bytewise difference (mod 256)
 * from the record before it in the chunk; the other channels as they are.
 * The planes gather the words' masks and pointer bytes into runs that code
 * better and faster than the interleaved words; neighbouring records (in
 * traversal order) have similar colours. Values are taken apart
 * arithmetically, so the bytes do not depend on the machine's byte order. */
static void chunk_transform(uint8_t* dst, uint8_t* const p[6], const size_t n[6], bool delta) {
    size_t nw = n[0] / 4;
    const uint32_t* w = (const uint32_t*)(const void*)p[0];
    for (size_t i = 0; i < nw; i++) {
        uint32_t v = w[i];
        dst[i] = (uint8_t)v, dst[nw + i] = (uint8_t)(v >> 8), dst[2 * nw + i] = (uint8_t)(v >> 16), dst[3 * nw + i] = (uint8_t)(v >> 24);
    }
    dst += n[0];
    for (int k = 1; k < 6; k++) {
        if (!n[k]) continue;
        if (delta && (k == 2 || k == 3)) { /* RGBA8, normal */
            const uint32_t* r = (const uint32_t*)(const void*)p[k];
            uint32_t prev = 0;
            for (size_t i = 0; i < n[k] / 4; i++) {
                uint32_t v = r[i];
                for (unsigned b = 0; b < 4; b++) dst[4 * i + b] = (uint8_t)((v >> 8 * b) - (prev >> 8 * b));
                prev = v;
            }
        } else {
            memcpy(dst, p[k], n[k]);
            swap_piece(dst, n[k], PIECE_WIDTH[k]);
        }
        dst += n[k];
    }
}

/* chunk_transform's inverse: src (the frame's bytes) into the arrays. */
static void chunk_untransform(uint8_t* const p[6], const size_t n[6], const uint8_t* src, bool delta) {
    size_t nw = n[0] / 4;
    uint32_t* w = (uint32_t*)(void*)p[0];
    for (size_t i = 0; i < nw; i++)
        w[i] = src[i] | (uint32_t)src[nw + i] << 8 | (uint32_t)src[2 * nw + i] << 16 | (uint32_t)src[3 * nw + i] << 24;
    src += n[0];
    for (int k = 1; k < 6; k++) {
        if (!n[k]) continue;
        if (delta && (k == 2 || k == 3)) {
            uint32_t* r = (uint32_t*)(void*)p[k];
            uint8_t a0 = 0, a1 = 0, a2 = 0, a3 = 0;
            for (size_t i = 0; i < n[k] / 4; i++) {
                a0 = (uint8_t)(a0 + src[4 * i]), a1 = (uint8_t)(a1 + src[4 * i + 1]);
                a2 = (uint8_t)(a2 + src[4 * i + 2]), a3 = (uint8_t)(a3 + src[4 * i + 3]);
                r[i] = a0 | (uint32_t)a1 << 8 | (uint32_t)a2 << 16 | (uint32_t)a3 << 24;
            }
        } else {
            memcpy(p[k], src, n[k]);
            swap_piece(p[k], n[k], PIECE_WIDTH[k]);
        }
        src += n[k];
    }
}

/* Whether the chunk's colour or normal records (the first of the two it
 * has) code smaller as differences than as they are, by samples (see
 * SAMPLE_WINDOWS); true when it has neither. tmp: scratch of at least
 * ZSTD_compressBound(4 SAMPLE_RECORDS) bytes (the chunk's output buffer). */
static bool sample_delta(ZSTD_CCtx* cc, uint8_t* const p[6], const size_t n[6], uint8_t* tmp, size_t tmp_n) {
    const int k = n[2] ? 2 : n[3] ? 3 : 0;
    const size_t recs = k ? n[k] / 4 : 0;
    if (!k || recs < 2 || tmp_n < ZSTD_compressBound(4 * SAMPLE_RECORDS)) return true;
    const size_t w = recs < SAMPLE_RECORDS ? recs : SAMPLE_RECORDS;
    const uint32_t* r = (const uint32_t*)(const void*)p[k];
    uint8_t plain[4 * SAMPLE_RECORDS], diff[4 * SAMPLE_RECORDS];
    size_t zp = 0, zd = 0;
    for (unsigned s = 0; s < SAMPLE_WINDOWS; s++) {
        size_t at = (recs - w) * s / (SAMPLE_WINDOWS - 1);
        uint32_t prev = 0;
        for (size_t i = 0; i < w; i++) {
            uint32_t v = r[at + i];
            for (unsigned b = 0; b < 4; b++) {
                plain[4 * i + b] = (uint8_t)(v >> 8 * b);
                diff[4 * i + b] = (uint8_t)((v >> 8 * b) - (prev >> 8 * b));
            }
            prev = v;
        }
        size_t a = ZSTD_compressCCtx(cc, tmp, tmp_n, plain, 4 * w, SAMPLE_LEVEL);
        size_t b = ZSTD_compressCCtx(cc, tmp, tmp_n, diff, 4 * w, SAMPLE_LEVEL);
        if (ZSTD_isError(a) || ZSTD_isError(b)) return true;
        zp += a, zd += b;
    }
    return zd <= zp;
}

/* Chunk i: DEFLATE (version 3), or a tagged chunk (version 4): the codec
 * byte, then a zstd frame of the transformed bytes with their size in its
 * header, or DEFLATE where zstd would pass CHUNK_RATIO_MAX. */
static void code_chunk(void* ctx, unsigned thread, uint32_t i) {
    (void)thread;
    chunk_job* j = (chunk_job*)ctx;
    if (!j->tagged) {
        deflate_chunk_at(j, i, 0);
        return;
    }
    uint32_t w0, w1, r0, r1;
    chunk_range(j, i, &w0, &w1, &r0, &r1);
    uint8_t* p[6];
    size_t n[6], raw = 0;
    chunk_pieces(j->m, w0, w1 - w0, r0, r1 - r0, p, n);
    for (int k = 0; k < 6; k++) raw += n[k];
    j->ok[i] = false;
    uint8_t* buf = (uint8_t*)vx_alloc(j->A, raw ? raw : 1);
    size_t cap = ZSTD_compressBound(raw) + 1;
    uint8_t* out = buf ? (uint8_t*)vx_alloc(j->A, cap) : NULL;
    ZSTD_CCtx* cc = out ? ZSTD_createCCtx() : NULL;
    size_t got = 0;
    bool delta = true;
    if (cc) {
        delta = sample_delta(cc, p, n, out + 1, cap - 1);
        chunk_transform(buf, p, n, delta);
        got = ZSTD_compressCCtx(cc, out + 1, cap - 1, buf, raw, CHUNK_ZSTD_LEVEL);
    }
    ZSTD_freeCCtx(cc);
    vx_free(j->A, buf);
    if (!cc || ZSTD_isError(got)) {
        vx_free(j->A, out);
        return;
    }
    if (raw > (uint64_t)CHUNK_RATIO_MAX * (got + 1)) { /* past the reader's bound: DEFLATE never is */
        vx_free(j->A, out);
        deflate_chunk_at(j, i, 1);
        if (j->ok[i]) j->out[i][0] = CHUNK_CODEC_DEFLATE;
        return;
    }
    out[0] = delta ? CHUNK_CODEC_ZSTD : CHUNK_CODEC_ZSTD_PLAIN;
    j->out[i] = out;
    j->out_n[i] = got + 1;
    j->ok[i] = true;
}

static bool maybe_flush(vx_buf* out, const vx__svo_sink* sink);

/* The chunks of model m in mode (VX__CHUNK_*): counts and levels, and the
 * arrays for their coded bytes; false when out of memory. */
static bool chunk_setup(chunk_job* j, const vx_svo_model* m, const vx_allocator* A, int mode) {
    const int level = mode == VX__CHUNK_STORED ? 0 : 1, wlevel = mode == VX__CHUNK_DEFLATE || mode == VX__CHUNK_ZSTD ? 1 : 0;
    uint64_t wraw = (uint64_t)m->node_count * 4, rraw = (uint64_t)m->attr_count * rec_bytes(m->attrs);
    uint64_t wc = (wraw + CHUNK_RAW - 1) / CHUNK_RAW, rc = (rraw + CHUNK_RAW - 1) / CHUNK_RAW;
    if (wc < 1) wc = 1;
    if (wc > m->node_count) wc = m->node_count; /* at least one word per word chunk */
    if (rc > m->attr_count) rc = m->attr_count;
    uint64_t count = wc + rc;
    *j = (chunk_job){m, A, (uint32_t)count, (uint32_t)wc, level, wlevel, mode == VX__CHUNK_ZSTD, NULL, NULL, NULL};
    j->out = (uint8_t**)vx_calloc(A, count, sizeof *j->out);
    j->out_n = (size_t*)vx_calloc(A, count, sizeof *j->out_n);
    j->ok = (bool*)vx_calloc(A, count, sizeof *j->ok);
    return j->out && j->out_n && j->ok;
}

static void chunk_free(chunk_job* j) {
    for (uint32_t i = 0; j->out && i < j->count; i++) vx_free(j->A, j->out[i]);
    vx_free(j->A, j->out);
    vx_free(j->A, j->out_n);
    vx_free(j->A, j->ok);
    j->out = NULL, j->out_n = NULL, j->ok = NULL;
}

/* A coded model's stream: the chunk count, per chunk its words, records
 * and deflated bytes, then the chunks, each freed once written. with_len:
 * the stream's length (varint) first, as the NODE section has it. With a
 * sink, each chunk goes to it as it is (out flushed first, to keep the
 * order): the stream is never gathered or copied whole (three copies of
 * the helmet's 322 MB and their fresh memory were a tenth of its write). */
static bool chunk_emit(chunk_job* j, bool with_len, vx_buf* out, const vx__svo_sink* sink) {
    vx_buf tab = {.alloc = j->A};
    bool ok = put_var(&tab, j->count);
    uint64_t total = 0;
    for (uint32_t i = 0; ok && i < j->count; i++) {
        uint32_t w0, w1, r0, r1;
        chunk_range(j, i, &w0, &w1, &r0, &r1);
        ok = j->ok[i] && put_var(&tab, w1 - w0) && put_var(&tab, r1 - r0) && put_var(&tab, j->out_n[i]);
        total += j->out_n[i];
    }
    ok = ok && !tab.failed && (!with_len || put_var(out, tab.size + total)) && vx_buf_append(out, tab.data, tab.size);
    vx_buf_free(&tab);
    for (uint32_t i = 0; ok && i < j->count; i++) {
        if (sink) {
            /* the chunk as a buffer of its own: flush() only reads and empties it */
            vx_buf piece = {.data = j->out[i], .size = j->out_n[i], .cap = j->out_n[i], .alloc = j->A};
            ok = (out->size == 0 || sink->flush(sink->user, out)) && sink->flush(sink->user, &piece);
        } else {
            ok = vx_buf_append(out, j->out[i], j->out_n[i]);
        }
        vx_free(j->A, j->out[i]);
        j->out[i] = NULL;
    }
    return ok && !out->failed;
}

/* A chunked model's stream (chunk_emit) coded on up to `threads` threads. */
static bool pack_chunked(const vx_svo_model* m, const vx_allocator* A, int mode, unsigned threads, bool with_len, vx_buf* out,
                         const vx__svo_sink* sink) {
    chunk_job j;
    bool ok = chunk_setup(&j, m, A, mode);
    if (ok) {
        if (threads > j.count) threads = j.count;
        if (threads <= 1)
            for (uint32_t i = 0; i < j.count; i++) code_chunk(&j, 0, i);
        else
            run_jobs(threads, j.count, code_chunk, &j);
        ok = chunk_emit(&j, with_len, out, sink);
    }
    chunk_free(&j);
    return ok && !out->failed;
}

/* Consecutive chunked models coded as one list of chunks on every thread,
 * each model written (chunk_emit) as soon as all its chunks are coded, by
 * whichever thread finishes its last one, while the others code on: no
 * thread waits for a model's slowest chunk or for its write, and the
 * write (the page-cache copy, a tenth of the helmet's CPU time) runs beside
 * the coding. A chunk of model k is not started before model k - WINDOW is
 * written, so at most WINDOW + 1 models' coded chunks are held. */
#define PIPE_WINDOW 2u
typedef struct chunk_pipe {
    chunk_job* jobs;  /* per model */
    uint32_t* first;  /* per model: its first chunk's index in the list; [n] the total */
    _Atomic uint32_t* done; /* per model: chunks coded */
    uint32_t n;
    vx_buf* out;
    const vx__svo_sink* sink;
    pthread_mutex_t lock;
    pthread_cond_t moved; /* `next` advanced, or the write failed */
    uint32_t next;        /* the model to write next */
    bool writing, failed;
} chunk_pipe;

/* Writes the models whose chunks are all coded, in order, unless another
 * thread is at it (it then writes them: it checks again after each). */
static void pipe_write(chunk_pipe* p) {
    pthread_mutex_lock(&p->lock);
    if (p->writing) {
        pthread_mutex_unlock(&p->lock);
        return;
    }
    p->writing = true;
    while (!p->failed && p->next < p->n && atomic_load(&p->done[p->next]) == p->jobs[p->next].count) {
        uint32_t k = p->next;
        pthread_mutex_unlock(&p->lock);
        bool ok = chunk_emit(&p->jobs[k], true, p->out, p->sink) && maybe_flush(p->out, p->sink);
        chunk_free(&p->jobs[k]);
        pthread_mutex_lock(&p->lock);
        p->failed = p->failed || !ok;
        p->next = k + 1;
        pthread_cond_broadcast(&p->moved);
    }
    p->writing = false;
    pthread_mutex_unlock(&p->lock);
}

static void pipe_job(void* ctx, unsigned thread, uint32_t i) {
    chunk_pipe* p = (chunk_pipe*)ctx;
    uint32_t k = 0;
    while (p->first[k + 1] <= i) k++;
    /* the window: wait for model k - WINDOW to be written, writing it here
     * when its chunks are done and no other thread is writing */
    pthread_mutex_lock(&p->lock);
    while (!p->failed && k >= p->next + PIPE_WINDOW) {
        if (!p->writing && atomic_load(&p->done[p->next]) == p->jobs[p->next].count) {
            pthread_mutex_unlock(&p->lock);
            pipe_write(p);
            pthread_mutex_lock(&p->lock);
            continue;
        }
        pthread_cond_wait(&p->moved, &p->lock); /* the writer broadcasts each model written */
    }
    const bool failed = p->failed;
    pthread_mutex_unlock(&p->lock);
    if (!failed) code_chunk(&p->jobs[k], thread, i - p->first[k]);
    atomic_fetch_add(&p->done[k], 1);
    pipe_write(p);
}

static bool pack_chunked_run(vx_buf* out, const vx_svo_model* models, uint32_t n, const vx_allocator* A, int mode, unsigned threads,
                             const vx__svo_sink* sink) {
    chunk_pipe p = {.n = n, .out = out, .sink = sink};
    p.jobs = (chunk_job*)vx_calloc(A, n, sizeof *p.jobs);
    p.first = (uint32_t*)vx_calloc(A, (size_t)n + 1, sizeof *p.first);
    p.done = (_Atomic uint32_t*)vx_calloc(A, n, sizeof *p.done);
    bool ok = p.jobs && p.first && p.done;
    uint64_t total = 0;
    for (uint32_t k = 0; ok && k < n; k++) {
        ok = chunk_setup(&p.jobs[k], &models[k], A, mode);
        p.first[k] = (uint32_t)total;
        total += p.jobs[k].count;
        ok = ok && total <= UINT32_MAX;
        atomic_init(&p.done[k], 0);
    }
    if (ok) {
        p.first[n] = (uint32_t)total;
        pthread_mutex_init(&p.lock, NULL);
        pthread_cond_init(&p.moved, NULL);
        if (threads <= 1) /* in order: each model is written as its last chunk is done */
            for (uint32_t i = 0; i < total; i++) pipe_job(&p, 0, i);
        else
            run_jobs(threads, (uint32_t)total, pipe_job, &p);
        pipe_write(&p); /* nothing is left unless a write failed */
        ok = !p.failed && p.next == n;
        pthread_cond_destroy(&p.moved);
        pthread_mutex_destroy(&p.lock);
    }
    for (uint32_t k = 0; p.jobs && k < n; k++) chunk_free(&p.jobs[k]);
    vx_free(A, p.jobs);
    vx_free(A, p.first);
    vx_free(A, (void*)p.done);
    return ok && !out->failed;
}

/* Codes one model into its own stream: the chunked form when `chunked`
 * (VX__CHUNK_ZSTD: tagged chunks, VX__CHUNK_DEFLATE: level 1,
 * VX__CHUNK_STORED: stored blocks; on up to
 * `threads` threads), else the structural or raw form; there, with
 * `threads` >= 2 and a model of at least vx__svo_parallel_words(hooks) words, the
 * symbols of the first setting tried are coded on a second thread while the
 * check rebuilds the model, whose layout follows its decoding on the
 * threads left. The bytes never depend on `threads`. */
bool vx__svo_model_split(const vx_svo_model* m, uint32_t chunk_min, uint32_t split_min) {
    return split_min && !vx__svo_model_chunked(m, chunk_min) && m->root < m->node_count && !(m->attrs & ~(uint32_t)STRUCT_ATTRS) &&
           m->node_count >= split_min;
}

bool vx__svo_pack_model(const vx_svo_model* m, const vx_allocator* A, int chunked, unsigned threads, const vx_svo_testing* hooks, bool trusted,
                        vx_buf* out) {
    const bool split = chunked == VX__CHUNK_SPLIT;
    if (chunked && !split) return pack_chunked(m, A, chunked, threads, false, out, NULL);
    coder cd, spec;
    bool spec_ok = false;
    memset(&spec, 0, sizeof spec);
    if (!coder_init(&cd, A)) return false;
    bool ok = true;
    ext x;
    memset(&x, 0, sizeof x);
    x.A = A;
    arr_src src;
    memset(&src, 0, sizeof src);
    bool structural = false, dag = false;
    uint32_t limit = VX__SVO_PTR_MAX;
    bool par = threads >= 2 && m->node_count >= vx__svo_parallel_words(hooks);
    unsigned lay = par ? (threads - 2 > 2 ? 2 : threads - 2) : 0;
    if (!vx__svo_unchecked(hooks) && m->root < m->node_count && !(m->attrs & ~(uint32_t)STRUCT_ATTRS)) {
        x.m = m;
        size_t need = 16;
        while (need < 2 * (size_t)m->node_count) need *= 2;
        /* The hash is for the few nodes without a block of their own or with
         * a second mask on one (the 4096^3 helmet's largest model: 57 K of 9.6
         * M words), so it starts at 1 K slots and doubles up to 2 a word, where
         * it held all of them from the start: 384 MB cleared and then touched
         * at random, a third of the split write's page faults (models of some
         * 10^5 words grow it: the tests' round trips) */
        x.hmax = need;
        if (need > ((size_t)1 << 10)) need = (size_t)1 << 10;
        x.hk = (uint64_t*)vx_calloc(A, need, sizeof *x.hk);
        x.hv = (uint32_t*)vx_calloc(A, need, sizeof *x.hv);
        x.fb = (uint32_t*)vx_calloc(A, m->node_count, sizeof *x.fb);
        x.fm = (uint16_t*)vx_calloc(A, m->node_count, sizeof *x.fm);
        x.hcap = need;
        /* the runs stream's found starts (split models with attributes) */
        if (split && m->attrs) x.tgt = (uint64_t*)vx_calloc(A, (size_t)m->attr_count / 64 + 1, 8);
        ok = x.hk && x.hv && x.fb && x.fm && (x.tgt || !(split && m->attrs));
        /* a model the reader rebuilt from the structural form, its digest
         * current: its symbols with the reader's settings give it back, so
         * the rebuild that proves the form is skipped (a model changed behind
         * an equal digest, odds of 2^-32, codes to what does not read back
         * as it, or raw where its words are not a tree: x.bad) */
        /* only the settings the tries below take first (the DAG, no far
         * limit: the builder's default), so that the bytes do not depend on
         * whether the check is current: a model read with other settings
         * might also come back with earlier ones, which the tries would pick */
        uint32_t st = m->check.structural, st_lim = st & 0xFFFFu;
        if (ok && trusted && st == (1u << 16 | VX__SVO_PTR_MAX)) {
            x.n = x.ndone = x.nid = 0;
            x.nrv = 0;
            x.dag = dag = (st >> 16 & 1u) != 0;
            limit = st_lim;
            x.tries++;
            /* the split form: straight into its streams, one walk */
            x.runs = split && m->attrs && dag && vx__svo_split_runs(hooks);
            if (split && !(x.sink = vx__svo_split_sink_new(m->attrs, x.runs, A))) ok = false;
            if (split && ok) vx__svo_split_sink_reserve(x.sink, m->attr_count); /* (the values: about one a record) */
            if (ok) ext_visit(&x, m->root, m->depth);
            if (x.oom) ok = false;
            structural = ok && !x.bad;
            if (x.sink && ok && structural) {
                size_t at = out->size, nr;
                uint8_t* rb = vx__svo_split_sink_runs(x.sink, &nr);
                if (rb) runs_fix(rb, nr, x.tgt);
                ok = vx_buf_u8(out, 1) && vx__svo_split_sink_code(x.sink, dag, limit, threads, out);
                uint64_t cap = ((uint64_t)(out->size - at) + 16) * PACK_RATIO_MAX;
                vx__svo_split_sink_free(x.sink);
                x.sink = NULL;
                if (!ok || (m->node_count <= cap && m->attr_count <= cap)) goto done;
                out->size = at; /* above the reader's limit (unpack_split): the walk again, into form 0 */
                x.n = x.ndone = x.nid = 0;
                x.runs = false;
                x.tries++;
                memset(x.fb, 0, (size_t)m->node_count * sizeof *x.fb);
                if (x.hused) memset(x.hk, 0, x.hcap * sizeof *x.hk);
                x.hused = 0;
                ext_visit(&x, m->root, m->depth);
                if (x.oom) ok = false;
                structural = ok && !x.bad;
            }
            vx__svo_split_sink_free(x.sink);
            x.sink = NULL;
            src.v = x.v, src.kind = x.kind, src.ctx = x.ctx, src.n = x.n, src.pos = 0;
        }
        /* the builder's settings are not stored in the model: try them */
        uint32_t lims[2] = {VX__SVO_PTR_MAX, vx__svo_far_limit(hooks)};
        for (int t = 0; ok && t < 4 && !structural; t++) {
            dag = t < 2;
            limit = lims[t & 1];
            if ((t & 1) && (limit == VX__SVO_PTR_MAX || limit < 1 || limit > VX__SVO_PTR_MAX)) continue;
            x.runs = split && m->attrs && dag && vx__svo_split_runs(hooks);
            structural = try_struct(m, A, dag, limit, &x, &src, t == 0 && par && !split ? &spec : NULL, lay);
            if (spec.started) {
                pthread_join(spec.th, NULL);
                spec.started = false;
                spec_ok = structural && !spec.coded.failed && !spec.side.failed;
            }
            /* out of memory is an error, not "this form does not fit": falling
             * back to the raw form would give other bytes for the same scene */
            if (x.oom) ok = false;
        }
    }
    if (split && ok) { /* the form byte; the split streams, or the stream of 3.4 */
        size_t at = out->size;
        ok = vx_buf_u8(out, structural ? 1 : 0);
        if (ok && structural) {
            if (x.runs && x.nrv == x.ndone) runs_fix(x.rv, x.nrv, x.tgt);
            ok = vx__svo_split_encode(x.v, x.kind, x.ctx, x.n, x.runs && x.nrv == x.ndone ? x.rv : NULL, m->attrs, m->depth, dag, limit,
                                      threads, A, out);
            /* a reader refuses more than PACK_RATIO_MAX words or records per
             * byte (unpack_split): a model that codes smaller takes form 0 */
            uint64_t cap = ((uint64_t)(out->size - at) + 16) * PACK_RATIO_MAX;
            if (!ok || (m->node_count <= cap && m->attr_count <= cap)) goto done;
            out->size = at;
            ok = vx_buf_u8(out, 0);
        }
    }
    coder* use = &cd;
    if (ok && spec_ok) use = &spec;
    else if (ok) code_stream(cd.k, m, structural, dag, limit, &src);
    if (ok) {
        /* the model's stream: side length, [deflated side length, deflated
         * side bytes], coded bytes. Deflate level 1: most of zlib's gain on
         * colour data at a small fraction of the range coder's time. */
        ok = put_var(out, use->side.size);
        if (ok && use->side.size) {
            uLongf zn = compressBound((uLong)use->side.size);
            uint8_t* z = use->side.size == (uLong)use->side.size ? (uint8_t*)vx_alloc(A, zn) : NULL;
            ok = z && compress2(z, &zn, use->side.data, (uLong)use->side.size, 1) == Z_OK && put_var(out, zn) &&
                 vx_buf_append(out, z, zn);
            vx_free(A, z);
        }
        ok = ok && vx_buf_append(out, use->coded.data, use->coded.size);
    }
    ok = ok && !use->coded.failed && !use->side.failed;
done:
    coder_free(&cd, A);
    if (spec.k) coder_free(&spec, A);
    vx_free(A, x.v);
    vx_free(A, x.rv);
    vx_free(A, x.tgt);
    vx_free(A, x.hk);
    vx_free(A, x.hv);
    vx_free(A, x.fb);
    vx_free(A, x.fm);
    vx_free(A, x.kind);
    vx_free(A, x.ctx);
    return ok && !out->failed;
}

typedef struct pack_jobs {
    const vx_svo_scene* s;
    const vx_allocator* A;
    vx_buf* bufs;
    bool* ok;
    uint32_t chunk_min, split_min;
    const uint8_t* trusted; /* the scene's (index first + i) */
    uint32_t first;
    const vx_svo_testing* t;
    const uint32_t* order; /* job k codes model order[k] of the batch */
} pack_jobs;

static void pack_job(void* ctx, unsigned thread, uint32_t k) {
    (void)thread;
    pack_jobs* j = (pack_jobs*)ctx;
    uint32_t i = j->order[k];
    const vx_svo_model* m = &j->s->models[i];
    j->ok[i] = vx__svo_pack_model(m, j->A, vx__svo_model_split(m, j->chunk_min, j->split_min) ? VX__CHUNK_SPLIT : VX__CHUNK_NONE, 1, j->t,
                                  j->trusted && j->trusted[j->first + i], &j->bufs[i]);
}

/* A writer's chance to move what is in `out` elsewhere (to disk) between
 * model streams, once it holds sink->flush_bytes (16 MB). */
static bool maybe_flush(vx_buf* out, const vx__svo_sink* sink) {
    if (!sink || out->size < sink->flush_bytes) return !out->failed;
    return !out->failed && sink->flush(sink->user, out);
}

/* One model's stream in the structural or raw form with its length,
 * straight into the output (chunked models: pack_chunked_run). */
static bool pack_one(vx_buf* out, const vx_svo_model* m, const vx_allocator* A, unsigned cpus, const vx_svo_testing* t, int mode, bool trusted,
                     const vx__svo_sink* sink) {
    vx_buf one = {0};
    one.alloc = A;
    bool ok = vx__svo_pack_model(m, A, mode, cpus, t, trusted, &one) && put_var(out, one.size) && vx_buf_append(out, one.data, one.size);
    vx_buf_free(&one);
    return ok && maybe_flush(out, sink);
}

/* The number of consecutive chunked models from model `first` on. */
static uint32_t chunked_run(const vx_svo_scene* s, uint32_t first, uint32_t chunk_min) {
    uint32_t n = 0;
    while (first + n < s->model_count && vx__svo_model_chunked(&s->models[first + n], chunk_min)) n++;
    return n;
}

bool vx__svo_pack_write(vx_buf* out, const vx_svo_scene* s, const vx_allocator* A, unsigned want, const vx_svo_testing* t,
                        uint32_t chunk_min, int chunk_mode, uint32_t split_min, const uint8_t* trusted, const vx__svo_sink* sink) {
    if (s->model_count == 0) return true;
    const int mode = chunk_mode ? chunk_mode : VX__CHUNK_ZSTD;
    unsigned threads = pack_threads(s, want, t), cpus = vx__svo_cpus(want);
    if (threads == 1) { /* one stream at a time, straight into the output */
        for (uint32_t mi = 0, n; mi < s->model_count; mi += n) {
            n = chunked_run(s, mi, chunk_min);
            if (n ? !pack_chunked_run(out, s->models + mi, n, A, mode, cpus, sink)
                  : !pack_one(out, &s->models[mi], A, cpus, t,
                              vx__svo_model_split(&s->models[mi], chunk_min, split_min) ? VX__CHUNK_SPLIT : VX__CHUNK_NONE,
                              trusted && trusted[mi], sink))
                return false;
            if (!n) n = 1;
        }
        return !out->failed;
    }
    /* models in batches of a few per thread: each batch's streams are appended
     * in order and freed before the next, so the extra memory is a batch's
     * output, not the whole file's. A chunked model is a batch of its own,
     * its chunks coded on every thread. */
    uint32_t batch = threads * 2;
    vx_buf* bufs = (vx_buf*)vx_calloc(A, batch, sizeof *bufs);
    bool* oks = (bool*)vx_calloc(A, batch, sizeof *oks);
    uint32_t* order = (uint32_t*)vx_calloc(A, batch, sizeof *order);
    bool ok = bufs && oks && order;
    for (uint32_t first = 0, n = 0; ok && first < s->model_count; first += n) {
        if ((n = chunked_run(s, first, chunk_min)) > 0) {
            ok = pack_chunked_run(out, s->models + first, n, A, mode, cpus, sink);
            continue;
        }
        for (n = 1; n < batch && first + n < s->model_count && !vx__svo_model_chunked(&s->models[first + n], chunk_min);) n++;
        vx_svo_scene part = *s; /* the batch's models, as a scene of their own */
        part.models = s->models + first;
        part.model_count = n;
        for (uint32_t i = 0; i < n; i++) {
            memset(&bufs[i], 0, sizeof bufs[i]);
            bufs[i].alloc = A;
        }
        /* the batch's models largest first (ties in model order), so that
         * its threads finish together: in model order a large model taken
         * last kept one thread busy alone (the 4096^3 helmet's models 6 and
         * 7); each stream still goes out in model order */
        for (uint32_t i = 0; i < n; i++) {
            uint32_t k = i;
            for (; k > 0 && part.models[order[k - 1]].node_count < part.models[i].node_count; k--) order[k] = order[k - 1];
            order[k] = i;
        }
        pack_jobs j = {&part, A, bufs, oks, chunk_min, split_min, trusted, first, t, order};
        run_jobs(threads < n ? threads : n, n, pack_job, &j);
        for (uint32_t i = 0; i < n; i++) {
            ok = ok && oks[i] && put_var(out, bufs[i].size) && vx_buf_append(out, bufs[i].data, bufs[i].size);
            vx_buf_free(&bufs[i]);
            ok = ok && maybe_flush(out, sink);
        }
    }
    vx_free(A, bufs);
    vx_free(A, oks);
    vx_free(A, order);
    return ok && !out->failed;
}

static unsigned var_len(uint64_t v) {
    unsigned n = 1;
    while (v >>= 7) n++;
    return n;
}

uint64_t vx__svo_pack_estimate(const vx_svo_scene* s, uint32_t chunk_min, int chunk_mode, uint32_t split_min) {
    const int mode = chunk_mode ? chunk_mode : VX__CHUNK_ZSTD;
    uint64_t total = 0;
    for (uint32_t i = 0; i < s->model_count; i++) {
        const vx_svo_model* m = &s->models[i];
        uint64_t words = (uint64_t)m->node_count * 4, recs = (uint64_t)m->attr_count * rec_bytes(m->attrs), est;
        /* typical ratios (docs/PERFORMANCE.md, issue 18): deflate level 1
         * about halves words and records, the structural form keeps about a
         * quarter; stored chunks are the raw bytes plus their tables */
        if (vx__svo_model_split(m, chunk_min, split_min)) est = (words + recs) / 3 + 64;
        else if (!vx__svo_model_chunked(m, chunk_min)) est = (words + recs) / 4 + 8;
        else if (mode == VX__CHUNK_STORED) est = words + recs + (words + recs) / 8192 + 16;
        else if (mode == VX__CHUNK_FAST) est = words + recs / 2 + 16;
        else est = (words + recs) / 2 + 16;
        total += var_len(est) + est;
    }
    return total;
}

/* ---- reader ---------------------------------------------------------------------------------- */

typedef struct rc_src {
    pk* k;
    uint64_t base;
} rc_src;
static bool rc_next(void* user, unsigned kind, unsigned ctx, uint32_t* v, vx_error* err) {
    rc_src* s = (rc_src*)user;
    if (s->k->over) {
        uint64_t at = s->base + s->k->n;
        return vx_fail(err, VX_ERR_TRUNCATED, at, "svo: section NODE at byte %llu: the coded stream ends before the trees do",
                       (unsigned long long)at),
               false;
    }
    *v = 0;
    sym_dec(s->k, kind, ctx, v);
    return true;
}

/* The structural symbols decoded on a thread of their own ahead of the
 * reconstruction (vx__svo_unpack, whose layout follows it in turn): the
 * range decoder walks the grammar of FORMAT.md 3.4 by itself (it needs only
 * the masks, the references and the declared word count) and hands the
 * values over in blocks, so that decoding, building the pool and laying it
 * out run at once. It asks for exactly the symbols the reconstruction asks
 * for and stops where that would stop (a zero mask, more descriptors than
 * declared words, a reference past the completed nodes, the stream used up),
 * after the same symbol, so the errors and the decoder's position are the
 * one-thread ones. */
/* The consumer sleeps until PIPE_WAKE more symbols are there (a fraction of
 * a millisecond of decoding), so that on two cores the threads take turns in
 * slices. */
enum { PIPE_BLOCK = 1 << 16, PIPE_PUBLISH = 4096, PIPE_WAKE = 1 << 14 };
typedef struct sym_pipe {
    pk* k;
    const vx_allocator* A;
    uint32_t depth, attrs;
    uint64_t max_words;
    uint32_t** blocks; /* allocated at the bound (never moved); each block freed by the consumer past it */
    size_t nblocks;
    vx__svo_gate pub;   /* symbols published; closed when the producer stops */
    atomic_bool stop;   /* the consumer has stopped: the producer may quit */
    bool truncated;     /* the producer stopped where the stream ran out (set before the close) */
    bool nomem;
    size_t n;           /* producer: symbols written */
    uint64_t words, ndone;
    uint8_t* ht;        /* producer: each completed node's height (max_words + 1 of them) */
    size_t pos, avail;  /* consumer: symbols taken, published as far as it knows */
    uint64_t base;
    pthread_t th;
} sym_pipe;

static bool pipe_emit(sym_pipe* q, uint32_t v) {
    size_t b = q->n / PIPE_BLOCK;
    if (q->n % PIPE_BLOCK == 0) {
        if (b >= q->nblocks || !(q->blocks[b] = (uint32_t*)vx_alloc(q->A, PIPE_BLOCK * sizeof(uint32_t)))) return q->nomem = true, false;
    }
    q->blocks[b][q->n % PIPE_BLOCK] = v;
    if (++q->n % PIPE_PUBLISH == 0) {
        vx__svo_gate_publish(&q->pub, q->n);
        if (atomic_load_explicit(&q->stop, memory_order_relaxed)) return false;
    }
    return true;
}

/* Decodes one symbol into the pipe; false where the one-thread reader
 * would stop before it (the stream used up) or the pipe cannot take it. */
static bool pipe_sym(sym_pipe* q, unsigned kind, unsigned ctx, uint32_t* v) {
    if (q->k->over) return q->truncated = true, false;
    *v = 0;
    sym_dec(q->k, kind, ctx, v);
    return pipe_emit(q, *v);
}

/* h: the node's height (vx__svo_unpack refuses a back-reference to a node
 * of more levels than are left below it: unp_visit). */
static bool pipe_walk(sym_pipe* q, unsigned level, unsigned* h) {
    uint32_t valid, leaf, ref, v;
    unsigned ch;
    *h = 1;
    if (!pipe_sym(q, VX__SYM_VALID, level, &valid) || valid == 0) return false;
    if (level == 1) leaf = valid;
    else if (!pipe_sym(q, VX__SYM_LEAF, level | valid << 8, &leaf)) return false;
    for (unsigned o = 0; o < 8; o++) {
        if (!(valid >> o & 1u)) continue;
        if (leaf >> o & 1u) {
            for (unsigned c = 0; c < 5; c++)
                if (q->attrs >> c & 1u && !pipe_sym(q, VX__SYM_VALUE, c, &v)) return false;
        } else {
            if (++q->words >= q->max_words) return false;
            if (!pipe_sym(q, VX__SYM_REF, level, &ref)) return false;
            if (ref == 0 ? !pipe_walk(q, level - 1, &ch) : ref > q->ndone) return false;
            if (ref && (ch = q->ht[q->ndone - ref]) > level - 1) return false;
            if (ch + 1 > *h) *h = ch + 1;
        }
    }
    q->ht[q->ndone++] = (uint8_t)*h; /* ndone <= max_words: allocated at that */
    return true;
}

static void* pipe_main(void* arg) {
    sym_pipe* q = (sym_pipe*)arg;
    unsigned h;
    pipe_walk(q, q->depth, &h);
    vx__svo_gate_close(&q->pub, q->n);
    return NULL;
}

static bool pipe_next(void* user, unsigned kind, unsigned ctx, uint32_t* v, vx_error* err) {
    (void)kind, (void)ctx;
    sym_pipe* q = (sym_pipe*)user;
    if (q->pos >= q->avail) {
        q->avail = vx__svo_gate_wait(&q->pub, q->pos, PIPE_WAKE);
        if (q->avail <= q->pos) { /* the decoder has stopped before this symbol */
            if (q->truncated) {
                uint64_t at = q->base + q->k->n;
                return vx_fail(err, VX_ERR_TRUNCATED, at, "svo: section NODE at byte %llu: the coded stream ends before the trees do",
                               (unsigned long long)at),
                       false;
            }
            return vx_fail(err, q->nomem ? VX_ERR_NOMEM : VX_ERR_BAD_FORMAT, VX_NO_OFFSET,
                           q->nomem ? "svo: out of memory" : "svo: section NODE: the coded symbols end early"),
                   false;
        }
    }
    size_t b = q->pos / PIPE_BLOCK;
    *v = q->blocks[b][q->pos % PIPE_BLOCK];
    if (++q->pos % PIPE_BLOCK == 0) {
        vx_free(q->A, q->blocks[b]);
        q->blocks[b] = NULL;
    }
    return true;
}

static bool set_rec(vx_svo_model* m, unsigned c, uint32_t r, uint32_t v) {
    switch (c) {
    case 0: m->palette[r] = (uint8_t)v; return v <= 0xFFu;
    case 1: m->rgba[r] = v; return true;
    case 2: m->normal[r] = v; return true;
    case 3: m->material[r] = (uint16_t)v; return v <= 0xFFFFu;
    default: {
        union { uint32_t u; float f; } x = {v};
        m->density[r] = x.f;
        return true;
    }
    }
}

/* The raw form: words and records as they are. The arrays grow with what
 * was decoded, so a declared count larger than the data allocates nothing. */
static vx_result read_raw(pk* k, vx_svo_model* m, const vx_allocator* A, uint64_t base, uint32_t mi, vx_error* err) {
    size_t cap = 0;
    uint32_t* w = NULL;
    for (uint32_t i = 0; i < m->node_count; i++) {
        if (k->over) {
            vx_free(A, w);
            return vx_fail(err, VX_ERR_TRUNCATED, base + k->n, "svo: section NODE at byte %llu: model %u: the coded stream ends after %u of %u words",
                           (unsigned long long)(base + k->n), mi, i, m->node_count);
        }
        if (!vx_grow(A, (void**)&w, &cap, (size_t)i + 1, 4)) {
            vx_free(A, w);
            return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "svo: out of memory");
        }
        w[i] = word_sym(k, 0);
    }
    m->nodes = w ? w : (uint32_t*)vx_calloc(A, 1, 4);
    if (!m->nodes) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "svo: out of memory");
    uint32_t n = m->attr_count;
    size_t ccap = 0;
    for (uint32_t r = 0; r <= n; r++) {
        if (m->attrs && (r == n || r == ccap)) { /* grow every channel together, doubling */
            size_t nc = r == n ? (n ? n : 1) : (ccap ? ccap * 2 : 64);
            if (nc > n) nc = n ? n : 1;
            void** arrs[5] = {(void**)&m->palette, (void**)&m->rgba, (void**)&m->normal, (void**)&m->material, (void**)&m->density};
            for (unsigned c = 0; c < 5; c++) {
                if (!(m->attrs >> c & 1u)) continue;
                void* p = vx_calloc(A, nc, CH_BYTES[c]);
                if (!p) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "svo: out of memory");
                if (*arrs[c]) memcpy(p, *arrs[c], (size_t)r * (c == 0 ? 1 : c == 3 ? 2 : 4));
                vx_free(A, *arrs[c]);
                *arrs[c] = p;
            }
            ccap = nc;
        }
        if (r == n) break;
        if (k->over)
            return vx_fail(err, VX_ERR_TRUNCATED, base + k->n, "svo: section NODE at byte %llu: model %u: the coded stream ends after %u of %u records",
                           (unsigned long long)(base + k->n), mi, r, n);
        for (unsigned c = 0; c < 5; c++) {
            if (!(m->attrs >> c & 1u)) continue;
            uint32_t v = 0;
            sym(k, VX__SYM_VALUE, c, &v);
            if (!set_rec(m, c, r, v))
                return vx_fail(err, VX_ERR_BAD_FORMAT, base + k->pos, "svo: section NODE near byte %llu: model %u: record %u value out of range",
                               (unsigned long long)(base + k->pos), mi, r);
        }
    }
    return VX_OK;
}

/* tree, rebuilt (both or neither NULL): a model rebuilt from the structural
 * form gets its tree's extent in *tree and *rebuilt = VX__SVO_SKIP_REBUILT
 * (the validation then checks its head only: vx__svo_check_rebuilt). */
/* The declared counts, which size the reconstruction's arrays, bounded by
 * the model's coded bytes (the stream's n and its side stream's side_n): at
 * most PACK_RATIO_MAX words and records per byte (3.4); the writers keep to it. */
static vx_result check_declared(size_t n, size_t side_n, uint64_t base, const vx_svo_model* m, uint32_t mi, vx_error* err) {
    uint64_t cap = ((uint64_t)n + side_n + 16) * PACK_RATIO_MAX;
    if (m->node_count > cap || m->attr_count > cap)
        return vx_fail(err, VX_ERR_LIMIT, base,
                       "svo: section NODE at byte %llu: model %u declares %u words and %u records, more than %u per byte of its %zu-byte stream",
                       (unsigned long long)base, mi, m->node_count, m->attr_count, PACK_RATIO_MAX, n);
    return VX_OK;
}

static vx_result unpack_coded(const uint8_t* p, size_t n, uint64_t base, const uint8_t* side, size_t side_n, vx_svo_model* m,
                              uint32_t mi, const vx_allocator* A, unsigned lay, vx__svo_extent* tree, uint8_t* rebuilt, vx_error* err);

/* Decodes model mi from its stream p[0..n) (base: the stream's file offset). */
static vx_result unpack_model(const uint8_t* p, size_t n, uint64_t base, vx_svo_model* m, uint32_t mi, const vx_allocator* A,
                              unsigned lay, vx__svo_extent* tree, uint8_t* rebuilt, vx_error* err) {
    /* side bytes first: their length, then (if any) the deflated length and
     * the deflated bytes. Both lengths are checked before anything is
     * allocated: the side holds at most 4 bytes per declared record and
     * 4-byte channel (RGBA8, normal, density). */
    uint64_t side_n = 0, z_n = 0;
    size_t hdr = 0;
    for (int which = 0; which < 2; which++) {
        uint64_t* dst = which ? &z_n : &side_n;
        if (which && side_n == 0) break;
        for (unsigned shift = 0;; shift += 7) {
            if (hdr >= n || shift > 35)
                return vx_fail(err, VX_ERR_BAD_FORMAT, base, "svo: section NODE at byte %llu: model %u: side length %s",
                               (unsigned long long)base, mi, hdr >= n ? "cut off" : "too long");
            uint8_t c = p[hdr++];
            *dst |= (uint64_t)(c & 0x7Fu) << shift;
            if (!(c & 0x80u)) break;
        }
    }
    /* one 4-byte value per record and channel (raw form) or per leaf child of
     * each node (structural form: at most 8 per declared word; with the DAG's
     * shared record runs these can outnumber the records) */
    uint64_t side_max = 4u * vx__popc8(m->attrs & (VX_ATTR_RGBA8 | VX_ATTR_NORMAL | VX_ATTR_DENSITY)) *
                        ((uint64_t)m->attr_count + 8u * (uint64_t)m->node_count);
    if (side_n > side_max || z_n > n - hdr)
        return vx_fail(err, side_n > side_max ? VX_ERR_BAD_FORMAT : VX_ERR_TRUNCATED, base,
                       "svo: section NODE at byte %llu: model %u: %llu side bytes (%llu deflated) for %u records, %zu bytes left",
                       (unsigned long long)base, mi, (unsigned long long)side_n, (unsigned long long)z_n, m->attr_count, n - hdr);
    uint8_t* side = NULL;
    if (side_n) {
        side = (uint8_t*)vx_alloc(A, (size_t)side_n);
        if (!side) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "svo: out of memory");
        uLongf got = (uLongf)side_n;
        if (uncompress(side, &got, p + hdr, (uLong)z_n) != Z_OK || got != side_n) {
            vx_free(A, side);
            return vx_fail(err, VX_ERR_BAD_FORMAT, base + hdr, "svo: section NODE at byte %llu: model %u: side bytes do not inflate to %llu bytes",
                           (unsigned long long)(base + hdr), mi, (unsigned long long)side_n);
        }
    }
    p += hdr + (size_t)z_n;
    base += hdr + z_n;
    n -= hdr + (size_t)z_n;
    vx_result r = unpack_coded(p, n, base, side, (size_t)side_n, m, mi, A, lay, tree, rebuilt, err);
    vx_free(A, side);
    return r;
}

static vx_result unpack_coded(const uint8_t* p, size_t n, uint64_t base, const uint8_t* side, size_t side_n, vx_svo_model* m,
                              uint32_t mi, const vx_allocator* A, unsigned lay, vx__svo_extent* tree, uint8_t* rebuilt, vx_error* err) {
    vx_result r0 = check_declared(n, side_n, base, m, mi, err);
    if (r0 != VX_OK) return r0;
    if (n < 5 || p[0] != 0)
        return vx_fail(err, VX_ERR_BAD_FORMAT, base, "svo: section NODE at byte %llu: model %u: not a coded stream (%s)",
                       (unsigned long long)base, mi, n < 5 ? "shorter than 5 bytes" : "first byte not 0");
    pk* k = (pk*)vx_calloc(A, 1, sizeof *k);
    if (!k) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "svo: out of memory");
    pk_init_models(k);
    k->p = p;
    k->n = n;
    k->raw = side;
    k->raw_n = side_n;
    k->range = 0xFFFFFFFFu;
    for (int i = 0; i < 5; i++) k->code = (k->code << 8) | next_byte(k);
    vx_result r = VX_OK;
    uint64_t at = base + k->pos;
    if (!bit(k, &k->form[0], 0)) {
        r = read_raw(k, m, A, base, mi, err);
    } else {
        bool dag = bit(k, &k->form[1], 0);
        uint32_t limit = VX__SVO_PTR_MAX;
        if (bit(k, &k->form[2], 0)) limit = plain_bits(k, 15, 0);
        if (m->root >= m->node_count || (m->attrs & ~(uint32_t)STRUCT_ATTRS) || limit == 0 || m->depth < 1 ||
            m->depth > VX_SVO_MAX_DEPTH) {
            r = vx_fail(err, VX_ERR_BAD_FORMAT, at,
                        "svo: section NODE near byte %llu: model %u: the structural form needs a root node, depth 1..21, channels palette/rgba/material only and a far limit >= 1",
                        (unsigned long long)at, mi);
        } else {
            vx_svo_model want = *m;
            rc_src rs = {k, base};
            vx__svo_src src = {rc_next, &rs, NULL};
            vx__svo_unpack_desc ud = {.depth = m->depth, .attrs = m->attrs, .dag = dag, .limit = limit, .max_words = m->node_count, .alloc = A,
                                      .layout_threads = lay, .tree = rebuilt ? tree : NULL};
            /* with threads to spare, the symbols are decoded ahead on one */
            sym_pipe* q = NULL;
            bool piped = false;
            if (lay && (q = (sym_pipe*)vx_calloc(A, 1, sizeof *q))) { /* lay: 0 under vx__svo_parallel_words (lay_for) */
                q->k = k;
                q->A = A;
                q->depth = m->depth;
                q->attrs = m->attrs;
                q->max_words = m->node_count;
                q->base = base;
                q->nblocks = (size_t)((26u * ((uint64_t)m->node_count + 1)) / PIPE_BLOCK + 2);
                q->blocks = (uint32_t**)vx_calloc(A, q->nblocks, sizeof *q->blocks);
                vx__svo_gate_init(&q->pub, 0);
                atomic_init(&q->stop, false);
                q->ht = (uint8_t*)vx_alloc(A, (size_t)m->node_count + 1);
                piped = q->blocks && q->ht && pthread_create(&q->th, NULL, pipe_main, q) == 0;
                if (piped) {
                    src.next = pipe_next;
                    src.user = q;
                }
            }
            r = vx__svo_unpack(&ud, &src, m, err);
            if (piped) {
                atomic_store_explicit(&q->stop, true, memory_order_relaxed);
                pthread_join(q->th, NULL);
            }
            if (q) {
                vx__svo_gate_destroy(&q->pub);
                vx_free(A, q->ht);
                for (size_t i = 0; q->blocks && i < q->nblocks; i++) vx_free(A, q->blocks[i]);
                vx_free(A, q->blocks);
                vx_free(A, q);
            }
            if (r != VX_OK) {
                if (r == VX_ERR_INVALID_ARG) r = VX_ERR_BAD_FORMAT;
                if (err) err->code = r;
                char pre[96];
                snprintf(pre, sizeof pre, "model %u (NODE near byte %llu)", mi, (unsigned long long)(base + (k->pos < n ? k->pos : n)));
                vx_error_prefix(err, pre);
            } else if (m->node_count != want.node_count || m->root != want.root || m->attr_count != want.attr_count ||
                       m->root_attr != want.root_attr) {
                r = vx_fail(err, VX_ERR_BAD_FORMAT, at,
                            "svo: section NODE near byte %llu: model %u rebuilds to %u words (root %u) and %u records (root %u), SCNE declares %u (root %u) and %u (root %u)",
                            (unsigned long long)at, mi, m->node_count, m->root, m->attr_count, m->root_attr, want.node_count, want.root,
                            want.attr_count, want.root_attr);
            } else {
                m->check.structural = (dag ? 1u << 16 : 0u) | limit; /* for a writer (vx__svo_pack_model's trusted) */
                if (rebuilt) *rebuilt = VX__SVO_SKIP_REBUILT;
            }
        }
    }
    if (r == VX_OK && (k->over || k->pos != n))
        r = vx_fail(err, k->over ? VX_ERR_TRUNCATED : VX_ERR_BAD_FORMAT, base + (k->over ? n : k->pos),
                    k->over ? "svo: section NODE: model %u: the coded stream or its side bytes are truncated (%zu bytes, more needed)"
                            : "svo: section NODE: model %u: %zu bytes, the coded stream ends earlier",
                    mi, n);
    if (r == VX_OK && k->raw_pos != k->raw_n)
        r = vx_fail(err, VX_ERR_BAD_FORMAT, base, "svo: section NODE: model %u: %zu side bytes left over", mi, k->raw_n - k->raw_pos);
    vx_free(A, k);
    return r;
}

/* A model's stream in the split form (FORMAT.md 3.7): the form byte, then
 * the split streams (decoded on up to `cpus` threads) feeding the
 * reconstruction, or the stream of 3.4. */
/* runs_ok: the file's version has the runs stream (6 and later) */
/* sc: the decoding thread's kept buffers (vx__svo_scratch), or NULL */
static vx_result unpack_split(const uint8_t* p, size_t n, uint64_t base, vx_svo_model* m, uint32_t mi, const vx_allocator* A, unsigned cpus,
                              unsigned lay, bool runs_ok, vx__svo_extent* tree, uint8_t* rebuilt, vx__svo_scratch* sc, vx_error* err) {
    if (n < 1 || p[0] > 1)
        return vx_fail(err, VX_ERR_BAD_FORMAT, base, "svo: section NODE at byte %llu: model %u: split form byte %s", (unsigned long long)base, mi,
                       n < 1 ? "missing" : "not 0 or 1");
    if (p[0] == 0) return unpack_model(p + 1, n - 1, base + 1, m, mi, A, lay, tree, rebuilt, err);
    if (m->root >= m->node_count || (m->attrs & ~(uint32_t)STRUCT_ATTRS) || m->depth < 1 || m->depth > VX_SVO_MAX_DEPTH)
        return vx_fail(err, VX_ERR_BAD_FORMAT, base,
                       "svo: section NODE at byte %llu: model %u: the structural form needs a root node, depth 1..21 and channels palette/rgba/material only",
                       (unsigned long long)base, mi);
    /* as in 3.4: the declared counts (which size the reconstruction's
     * arrays) bounded by the stream's bytes; the writer keeps to it */
    vx_result r0 = check_declared(n, 0, base, m, mi, err);
    if (r0 != VX_OK) return r0;
    vx__svo_split* d;
    bool dag;
    uint32_t limit;
    vx_result r = vx__svo_split_open(p + 1, n - 1, base + 1, m, mi, cpus, runs_ok, A, sc, &d, &dag, &limit, err);
    if (r != VX_OK) return r;
    vx_svo_model want = *m;
    vx__svo_src src = vx__svo_split_src(d);
    vx__svo_unpack_desc ud = {.depth = m->depth, .attrs = m->attrs, .dag = dag, .limit = limit, .max_words = m->node_count, .alloc = A,
                              .layout_threads = lay, .tree = rebuilt ? tree : NULL, .ref_index = true};
    ud.const_attrs = vx__svo_split_constants(d, m->attrs, &ud.const_rec);
    ud.runs = vx__svo_split_runs_stream(d, &ud.runs_n);
    ud.scratch = cpus <= 1 ? sc : NULL; /* (one thread: the scratch has no lock) */
    ud.max_records = m->attr_count ? m->attr_count : 1; /* (the words and records at the declared sizes) */
    r = vx__svo_unpack(&ud, &src, m, err);
    if (r != VX_OK) {
        if (r == VX_ERR_INVALID_ARG) r = VX_ERR_BAD_FORMAT;
        if (err) err->code = r;
        char pre[96];
        snprintf(pre, sizeof pre, "model %u (NODE split stream at byte %llu)", mi, (unsigned long long)base);
        vx_error_prefix(err, pre);
    } else if (m->node_count != want.node_count || m->root != want.root || m->attr_count != want.attr_count || m->root_attr != want.root_attr) {
        r = vx_fail(err, VX_ERR_BAD_FORMAT, base,
                    "svo: section NODE at byte %llu: model %u rebuilds to %u words (root %u) and %u records (root %u), SCNE declares %u (root %u) and %u (root %u)",
                    (unsigned long long)base, mi, m->node_count, m->root, m->attr_count, m->root_attr, want.node_count, want.root, want.attr_count,
                    want.root_attr);
    } else if ((r = vx__svo_split_done(d, err)) == VX_OK) {
        m->check.structural = (dag ? 1u << 16 : 0u) | limit; /* for a writer (vx__svo_pack_model's trusted) */
        if (rebuilt) *rebuilt = VX__SVO_SKIP_REBUILT;
    }
    vx__svo_split_free(d);
    return r;
}

/* ---- reader of the chunked form (FORMAT.md 3.6) ---------------------------------------------------- */

typedef struct chunk_ent {
    uint32_t w0, nw, r0, nr;
    size_t off, zn; /* the chunk's deflated bytes: p[off, off + zn) */
} chunk_ent;

typedef struct inflate_job {
    vx_svo_model* m;
    const uint8_t* p;
    uint64_t base;
    uint32_t mi;
    const chunk_ent* ch;
    vx_result* res;
    vx_error* errs;
    const vx_allocator* A;
    bool tagged; /* each chunk starts with its codec byte (format version 4) */
} inflate_job;

const char* vx__zstd_frame_problem(const uint8_t* src, size_t zn, size_t want) {
    unsigned long long declared = ZSTD_getFrameContentSize(src, zn);
    size_t frame = ZSTD_findFrameCompressedSize(src, zn);
    return declared == ZSTD_CONTENTSIZE_ERROR     ? "not a zstd frame"
           : declared == ZSTD_CONTENTSIZE_UNKNOWN ? "the frame does not declare its size"
           : declared != want                     ? "the frame declares another size"
           : ZSTD_isError(frame)                  ? "the frame is cut off or corrupt"
           : frame != zn                          ? "bytes left over after the frame"
                                                  : NULL;
}

/* A tagged chunk's zstd frame: exactly one frame filling the chunk, whose
 * header declares exactly the chunk's bytes (checked before decoding, and
 * the decoder is bounded by them), into a scratch buffer (at most
 * CHUNK_RATIO_MAX per coded byte, by the table's check) and back into the
 * arrays through the transform's inverse. */
static void unzstd_chunk(inflate_job* j, uint32_t i, const uint8_t* src, size_t zn, uint8_t* const p[6], const size_t n[6], size_t want,
                         bool delta) {
    const uint64_t at = j->base + j->ch[i].off;
    const char* why = vx__zstd_frame_problem(src, zn, want);
    if (why) {
        j->res[i] = vx_fail(&j->errs[i], VX_ERR_BAD_FORMAT, at,
                            "svo: section NODE at byte %llu: model %u: chunk %u (%zu bytes, zstd) does not decode to exactly %zu bytes (%s)",
                            (unsigned long long)at, j->mi, i, zn, want, why);
        return;
    }
    uint8_t* buf = (uint8_t*)vx_alloc(j->A, want ? want : 1);
    ZSTD_DCtx* d = buf ? ZSTD_createDCtx() : NULL;
    if (!d) {
        vx_free(j->A, buf);
        j->res[i] = vx_fail(&j->errs[i], VX_ERR_NOMEM, VX_NO_OFFSET, "svo: out of memory");
        return;
    }
    size_t got = ZSTD_decompressDCtx(d, buf, want, src, zn);
    ZSTD_freeDCtx(d);
    if (ZSTD_isError(got) || got != want) {
        j->res[i] = vx_fail(&j->errs[i], VX_ERR_BAD_FORMAT, at,
                            "svo: section NODE at byte %llu: model %u: chunk %u (%zu bytes, zstd) does not decode to exactly %zu bytes (%s)",
                            (unsigned long long)at, j->mi, i, zn, want, ZSTD_isError(got) ? ZSTD_getErrorName(got) : "too short");
    } else {
        chunk_untransform(p, n, buf, delta);
        j->res[i] = VX_OK;
    }
    vx_free(j->A, buf);
}

static void inflate_chunk(void* ctx, unsigned thread, uint32_t i) {
    (void)thread;
    inflate_job* j = (inflate_job*)ctx;
    const chunk_ent* c = &j->ch[i];
    uint8_t* p[6];
    size_t n[6];
    chunk_pieces(j->m, c->w0, c->nw, c->r0, c->nr, p, n);
    uint64_t at = j->base + c->off;
    const uint8_t* src = j->p + c->off;
    size_t zn = c->zn;
    if (j->tagged) { /* zn >= 1 by the table's check */
        const uint8_t codec = *src++;
        zn--;
        if (codec == CHUNK_CODEC_ZSTD || codec == CHUNK_CODEC_ZSTD_PLAIN) {
            size_t want = 0;
            for (int k = 0; k < 6; k++) want += n[k];
            unzstd_chunk(j, i, src, zn, p, n, want, codec == CHUNK_CODEC_ZSTD);
            return;
        }
        if (codec != CHUNK_CODEC_DEFLATE) {
            j->res[i] = vx_fail(&j->errs[i], VX_ERR_BAD_FORMAT, at, "svo: section NODE at byte %llu: model %u: chunk %u has unknown codec %u",
                                (unsigned long long)at, j->mi, i, codec);
            return;
        }
    }
#if defined(VX_HAVE_LIBDEFLATE) && !(defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_BIG_ENDIAN__)
    {
        /* libdeflate inflates into one buffer: a chunk of one piece in
         * place, one of several into a scratch buffer (bounded by the table's
         * check, at most CHUNK_RATIO_MAX per deflated byte) copied out */
        size_t want = 0;
        int np = 0, one = 0;
        for (int k = 0; k < 6; k++)
            if (n[k]) want += n[k], np++, one = k;
        uint8_t* buf = np > 1 ? (uint8_t*)vx_alloc(j->A, want) : p[one];
        struct libdeflate_decompressor* d = buf ? libdeflate_alloc_decompressor() : NULL;
        if (!d) {
            if (np > 1) vx_free(j->A, buf);
            j->res[i] = vx_fail(&j->errs[i], VX_ERR_NOMEM, VX_NO_OFFSET, "svo: out of memory");
            return;
        }
        size_t in_n = 0, out_n = 0;
        enum libdeflate_result lr = libdeflate_deflate_decompress_ex(d, src, zn, buf, want, &in_n, &out_n);
        libdeflate_free_decompressor(d);
        const char* why = lr == LIBDEFLATE_SUCCESS && out_n < want ? "too short"
                          : lr == LIBDEFLATE_SUCCESS && in_n != zn ? "bytes left over"
                          : lr != LIBDEFLATE_SUCCESS                  ? "corrupt"
                                                                      : NULL;
        if (!why && np > 1)
            for (size_t k = 0, o = 0; k < 6; o += n[k], k++)
                if (n[k]) memcpy(p[k], buf + o, n[k]);
        if (np > 1) vx_free(j->A, buf);
        j->res[i] = !why ? VX_OK
                         : vx_fail(&j->errs[i], VX_ERR_BAD_FORMAT, at,
                                   "svo: section NODE at byte %llu: model %u: chunk %u (%zu bytes) does not inflate to exactly %zu bytes (%s)",
                                   (unsigned long long)at, j->mi, i, zn, want, why);
        return;
    }
#endif
    z_stream z;
    memset(&z, 0, sizeof z);
    if (inflateInit2(&z, -15) != Z_OK) {
        j->res[i] = vx_fail(&j->errs[i], VX_ERR_NOMEM, VX_NO_OFFSET, "svo: out of memory");
        return;
    }
    z.next_in = (Bytef*)(uintptr_t)src;
    z.avail_in = (uInt)zn;
    int zr = Z_OK;
    size_t got = 0, want = 0;
    for (int k = 0; k < 6; k++) want += n[k];
    for (int k = 0; k < 6 && zr == Z_OK; k++) {
        if (!n[k]) continue;
        z.next_out = p[k];
        z.avail_out = (uInt)n[k];
        while (zr == Z_OK && z.avail_out) zr = inflate(&z, Z_NO_FLUSH);
        got += n[k] - z.avail_out;
        swap_piece(p[k], n[k], PIECE_WIDTH[k]);
    }
    if (zr == Z_OK) { /* everything filled: the stream must end here, with no byte left */
        uint8_t extra;
        z.next_out = &extra;
        z.avail_out = 1;
        zr = inflate(&z, Z_NO_FLUSH);
        if (z.avail_out == 0) zr = Z_DATA_ERROR;
    }
    bool ok = zr == Z_STREAM_END && got == want && z.avail_in == 0;
    inflateEnd(&z);
    j->res[i] = ok ? VX_OK
                   : vx_fail(&j->errs[i], VX_ERR_BAD_FORMAT, at,
                             "svo: section NODE at byte %llu: model %u: chunk %u (%zu bytes) does not inflate to exactly %zu bytes (%s)",
                             (unsigned long long)at, j->mi, i, zn, want,
                             zr == Z_MEM_ERROR ? "out of memory" : zr == Z_STREAM_END && got < want ? "too short" : zr == Z_STREAM_END ? "bytes left over" : "corrupt");
    if (zr == Z_MEM_ERROR) j->res[i] = VX_ERR_NOMEM, j->errs[i].code = VX_ERR_NOMEM;
}

static bool rd_leb(const uint8_t* p, size_t n, size_t* pos, uint64_t max, uint64_t* out) {
    uint64_t v = 0;
    for (unsigned shift = 0; shift < 64; shift += 7) {
        if (*pos >= n) return false;
        uint8_t c = p[(*pos)++];
        if (shift == 63 && (c & 0x7Eu)) return false;
        v |= (uint64_t)(c & 0x7Fu) << shift;
        if (!(c & 0x80u)) {
            *out = v;
            return v <= max;
        }
    }
    return false;
}

/* Decodes chunked model mi from its stream p[0..n) into arrays of the
 * declared size: the table is checked first (counts summing to the declared
 * words and records, each chunk's inflated size at most CHUNK_RATIO_MAX per
 * deflated byte, the deflated bytes exactly the rest of the stream), so
 * every allocation is bounded by the stream's length. */
static vx_result unpack_chunked(const uint8_t* p, size_t n, uint64_t base, vx_svo_model* m, uint32_t mi, const vx_allocator* A,
                                unsigned threads, bool tagged, vx_svo_chunk_stats* stats, vx_error* err) {
    size_t pos = 0;
    uint64_t count = 0;
    /* an entry is at least 3 bytes and a chunk at least 1 */
    if (!rd_leb(p, n, &pos, n / 4, &count) || count == 0)
        return vx_fail(err, VX_ERR_BAD_FORMAT, base, "svo: section NODE at byte %llu: model %u: chunk count %s", (unsigned long long)base,
                       mi, count == 0 && pos <= n ? "is 0 or cut off" : "exceeds the stream's bytes");
    chunk_ent* ch = (chunk_ent*)vx_calloc(A, (size_t)count, sizeof *ch);
    if (!ch) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "svo: out of memory");
    vx_result r = VX_OK;
    uint64_t sw = 0, sr = 0, sz = 0, rb = rec_bytes(m->attrs);
    for (uint64_t i = 0; r == VX_OK && i < count; i++) {
        size_t at = pos;
        uint64_t nw, nr, zn;
        if (!rd_leb(p, n, &pos, UINT32_MAX, &nw) || !rd_leb(p, n, &pos, UINT32_MAX, &nr) || !rd_leb(p, n, &pos, n, &zn)) {
            r = vx_fail(err, VX_ERR_BAD_FORMAT, base + at, "svo: section NODE at byte %llu: model %u: chunk %llu's entry is cut off or out of range",
                        (unsigned long long)(base + at), mi, (unsigned long long)i);
            break;
        }
        if (nw > (uint64_t)m->node_count - sw || nr > (uint64_t)m->attr_count - sr) {
            r = vx_fail(err, VX_ERR_BAD_FORMAT, base + at,
                        "svo: section NODE at byte %llu: model %u: chunk %llu goes past the declared %u words or %u records",
                        (unsigned long long)(base + at), mi, (unsigned long long)i, m->node_count, m->attr_count);
            break;
        }
        uint64_t raw = nw * 4 + nr * rb;
        if (zn == 0 || raw > (uint64_t)CHUNK_RATIO_MAX * zn) {
            r = vx_fail(err, zn == 0 ? VX_ERR_BAD_FORMAT : VX_ERR_LIMIT, base + at,
                        "svo: section NODE at byte %llu: model %u: chunk %llu declares %llu bytes from %llu deflated (at most %u per byte)",
                        (unsigned long long)(base + at), mi, (unsigned long long)i, (unsigned long long)raw, (unsigned long long)zn,
                        CHUNK_RATIO_MAX);
            break;
        }
        ch[i] = (chunk_ent){(uint32_t)sw, (uint32_t)nw, (uint32_t)sr, (uint32_t)nr, (size_t)sz, (size_t)zn};
        sw += nw;
        sr += nr;
        sz += zn;
        if (sz > n) {
            r = vx_fail(err, VX_ERR_TRUNCATED, base + at, "svo: section NODE at byte %llu: model %u: chunks of %llu bytes, the stream has %zu",
                        (unsigned long long)(base + at), mi, (unsigned long long)sz, n);
            break;
        }
    }
    if (r == VX_OK && (sw != m->node_count || sr != m->attr_count || sz != n - pos))
        r = vx_fail(err, VX_ERR_BAD_FORMAT, base,
                    "svo: section NODE at byte %llu: model %u: chunks hold %llu words, %llu records and %llu bytes; SCNE declares %u words and %u records, the stream has %zu bytes after the table",
                    (unsigned long long)base, mi, (unsigned long long)sw, (unsigned long long)sr, (unsigned long long)sz, m->node_count,
                    m->attr_count, n - pos);
    if (r == VX_OK) { /* every size is bounded by the stream now */
        m->nodes = (uint32_t*)vx_alloc(A, (size_t)m->node_count * 4);
        void** arrs[5] = {(void**)&m->palette, (void**)&m->rgba, (void**)&m->normal, (void**)&m->material, (void**)&m->density};
        bool ok = m->nodes != NULL;
        vx__svo_advise_huge(m->nodes, (size_t)m->node_count * 4);
        for (unsigned c = 0; ok && c < 5; c++)
            if (m->attrs >> c & 1u) {
                ok = (*arrs[c] = vx_alloc(A, (size_t)(m->attr_count ? m->attr_count : 1) * CH_BYTES[c])) != NULL;
                vx__svo_advise_huge(*arrs[c], (size_t)m->attr_count * CH_BYTES[c]);
            }
        if (!ok) r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "svo: out of memory");
    }
    if (r == VX_OK) {
        for (uint64_t i = 0; i < count; i++) ch[i].off += pos;
        if (stats) { /* each chunk has at least its codec byte (zn >= 1) */
            stats->models++;
            stats->coded_bytes += n - pos;
            stats->raw_bytes += (uint64_t)m->node_count * 4 + (uint64_t)m->attr_count * rb;
            for (uint64_t i = 0; i < count; i++) {
                const uint8_t codec = tagged ? p[ch[i].off] : CHUNK_CODEC_DEFLATE;
                if (codec == CHUNK_CODEC_ZSTD) stats->zstd++;
                else if (codec == CHUNK_CODEC_ZSTD_PLAIN) stats->zstd_plain++;
                else if (codec == CHUNK_CODEC_DEFLATE) stats->deflate++;
            }
        }
        vx_result* res = (vx_result*)vx_calloc(A, (size_t)count, sizeof *res);
        vx_error* errs = (vx_error*)vx_calloc(A, (size_t)count, sizeof *errs);
        if (!res || !errs) r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "svo: out of memory");
        else {
            inflate_job j = {m, p, base, mi, ch, res, errs, A, tagged};
            if (threads > count) threads = (unsigned)count;
            if (threads <= 1)
                for (uint32_t i = 0; i < count && res[i ? i - 1 : 0] == VX_OK; i++) inflate_chunk(&j, 0, i);
            else
                run_jobs(threads, (uint32_t)count, inflate_chunk, &j);
            for (uint32_t i = 0; r == VX_OK && i < count; i++)
                if (res[i] != VX_OK) {
                    r = res[i];
                    if (err) *err = errs[i];
                }
        }
        vx_free(A, res);
        vx_free(A, errs);
    }
    vx_free(A, ch);
    return r;
}

typedef struct unpack_jobs {
    vx_svo_scene* s;
    const uint8_t* p;
    uint64_t base;
    const size_t* off;
    const size_t* len;
    const vx_allocator* A;
    vx_result* res;
    vx_error* errs;
    const uint8_t* chunked; /* per model, or NULL */
    unsigned lay;           /* layout threads per model (vx__svo_unpack_desc.layout_threads) */
    vx__svo_extent* ext;    /* with rebuilt: see vx__svo_pack_read */
    uint8_t* rebuilt;
    const uint32_t* order; /* job k decodes model order[k] (largest first), or NULL: model k */
    const vx_svo_testing* t;
    vx__svo_scratch* sc; /* one per thread (NULL: none) */
} unpack_jobs;

/* Threads the layout of each structural model may follow its decoding on,
 * 0 when the models decoding on `threads` of `cpus` leave no core: with a
 * core to spare, the symbols are decoded on one thread, the pool built on
 * the caller's and the layout's two stages follow on two more. Four threads
 * on two cores beat fewer (H200 host, two cores, the 100 M-voxel terrain:
 * 5.13 s against 5.41 with one layout thread, 6.09 without the decoding
 * thread; docs/PERFORMANCE.md, ".svo I/O, eighth step"). */
static unsigned layout_threads(const vx_svo_scene* s, unsigned threads, unsigned cpus) {
    (void)s;
    return cpus > threads ? 2 : 0;
}
/* The layout threads model m takes of lay: none under vx__svo_parallel_words(t)
 * node words (declared), where the threads cost more than they save. */
static unsigned lay_for(const vx_svo_model* m, unsigned lay, const vx_svo_testing* t) {
    return m->node_count >= vx__svo_parallel_words(t) ? lay : 0;
}

static void unpack_job(void* ctx, unsigned thread, uint32_t k) {
    unpack_jobs* j = (unpack_jobs*)ctx;
    uint32_t i = j->order ? j->order[k] : k;
    if (j->chunked && (j->chunked[i] == 1 || j->chunked[i] == 2)) return; /* decoded afterwards, on every thread */
    if (j->chunked && j->chunked[i] >= 3)
        j->res[i] = unpack_split(j->p + j->off[i], j->len[i], j->base + j->off[i], &j->s->models[i], i, j->A, 1,
                                 lay_for(&j->s->models[i], j->lay, j->t), j->chunked[i] == 4,
                                 j->rebuilt ? &j->ext[i] : NULL, j->rebuilt ? &j->rebuilt[i] : NULL, j->sc ? &j->sc[thread] : NULL, &j->errs[i]);
    else
        j->res[i] = unpack_model(j->p + j->off[i], j->len[i], j->base + j->off[i], &j->s->models[i], i, j->A,
                                 lay_for(&j->s->models[i], j->lay, j->t),
                                 j->rebuilt ? &j->ext[i] : NULL, j->rebuilt ? &j->rebuilt[i] : NULL, &j->errs[i]);
}

/* The models by declared node words, largest first (ties in file order):
 * the order the reader's jobs take them in, so that the last job to start
 * is a small one and the threads end together (the 4096^3 helmet's eight
 * models of 3.3-9.6 M words on two threads, counting time by words: in file
 * order one thread idles while the other does 5.4 M words of the last
 * model, largest first 0.2 M; docs/PERFORMANCE.md issue 18, eleventh step).
 * Which thread decodes
 * a model never changes its result, and errors are taken in model order. */
static int cmp_words_desc(const void* a, const void* b) {
    const uint64_t x = *(const uint64_t*)a, y = *(const uint64_t*)b;
    return x < y ? -1 : x > y;
}
static uint32_t* largest_first(const vx_svo_scene* s, const vx_allocator* A) {
    uint64_t* key = (uint64_t*)vx_calloc(A, s->model_count, sizeof *key);
    uint32_t* order = key ? (uint32_t*)vx_calloc(A, s->model_count, sizeof *order) : NULL;
    if (!order) {
        vx_free(A, key);
        return NULL;
    }
    /* (2^32 - 1 - words) << 32 | index: ascending = most words first, then file order */
    for (uint32_t i = 0; i < s->model_count; i++) key[i] = (uint64_t)(0xFFFFFFFFu - s->models[i].node_count) << 32 | i;
    qsort(key, s->model_count, sizeof *key, cmp_words_desc);
    for (uint32_t i = 0; i < s->model_count; i++) order[i] = (uint32_t)key[i];
    vx_free(A, key);
    return order;
}

vx_result vx__svo_pack_read(const uint8_t* p, size_t n, uint64_t base, vx_svo_scene* s, const uint8_t* chunked, const vx_allocator* A,
                            unsigned want, const vx_svo_testing* t, vx_svo_chunk_stats* stats, vx__svo_extent* ext, uint8_t* rebuilt,
                            vx_error* err) {
    if (!ext) rebuilt = NULL;
    if (s->model_count == 0) {
        if (n) return vx_fail(err, VX_ERR_BAD_FORMAT, base, "svo: section NODE has %zu bytes but there are no models", n);
        return VX_OK;
    }
    /* the stream table first: every length is checked before anything is decoded */
    size_t* off = (size_t*)vx_calloc(A, s->model_count, sizeof *off);
    size_t* len = (size_t*)vx_calloc(A, s->model_count, sizeof *len);
    if (!off || !len) {
        vx_free(A, off);
        vx_free(A, len);
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "svo: out of memory");
    }
    vx_result r = VX_OK;
    size_t pos = 0;
    for (uint32_t mi = 0; r == VX_OK && mi < s->model_count; mi++) {
        uint64_t v = 0;
        unsigned shift = 0;
        size_t at = pos;
        for (;;) {
            if (pos >= n) {
                r = vx_fail(err, VX_ERR_TRUNCATED, base + at, "svo: section NODE at byte %llu: model %u: stream length cut off",
                            (unsigned long long)(base + at), mi);
                break;
            }
            uint8_t c = p[pos++];
            if (shift == 63 && (c & 0x7Eu)) {
                r = vx_fail(err, VX_ERR_BAD_FORMAT, base + at, "svo: section NODE at byte %llu: model %u: stream length overflows",
                            (unsigned long long)(base + at), mi);
                break;
            }
            v |= (uint64_t)(c & 0x7Fu) << shift;
            if (!(c & 0x80u)) break;
            shift += 7;
            if (shift > 63) {
                r = vx_fail(err, VX_ERR_BAD_FORMAT, base + at, "svo: section NODE at byte %llu: model %u: stream length is not a varint",
                            (unsigned long long)(base + at), mi);
                break;
            }
        }
        if (r != VX_OK) break;
        if (v > n - pos) {
            r = vx_fail(err, VX_ERR_TRUNCATED, base + at, "svo: section NODE at byte %llu: model %u: stream of %llu bytes, %zu left",
                        (unsigned long long)(base + at), mi, (unsigned long long)v, n - pos);
            break;
        }
        off[mi] = pos;
        len[mi] = (size_t)v;
        pos += (size_t)v;
    }
    if (r == VX_OK && pos != n)
        r = vx_fail(err, VX_ERR_BAD_FORMAT, base + pos, "svo: section NODE: %zu bytes after the last model's stream", n - pos);
    if (r == VX_OK) {
        unsigned threads = pack_threads(s, want, t), cpus = vx__svo_cpus(want), lay = layout_threads(s, threads, cpus);
        if (threads == 1) {
            for (uint32_t mi = 0; r == VX_OK && mi < s->model_count; mi++)
                r = chunked && chunked[mi] >= 3
                        ? unpack_split(p + off[mi], len[mi], base + off[mi], &s->models[mi], mi, A, cpus, lay_for(&s->models[mi], lay, t), chunked[mi] == 4,
                                       rebuilt ? &ext[mi] : NULL,
                                       rebuilt ? &rebuilt[mi] : NULL, NULL, err)
                    : chunked && chunked[mi] ? unpack_chunked(p + off[mi], len[mi], base + off[mi], &s->models[mi], mi, A, cpus, chunked[mi] == 2, stats, err)
                                           : unpack_model(p + off[mi], len[mi], base + off[mi], &s->models[mi], mi, A, lay_for(&s->models[mi], lay, t),
                                                          rebuilt ? &ext[mi] : NULL, rebuilt ? &rebuilt[mi] : NULL, err);
        } else {
            vx_result* res = (vx_result*)vx_calloc(A, s->model_count, sizeof *res);
            vx_error* errs = (vx_error*)vx_calloc(A, s->model_count, sizeof *errs);
            uint32_t* order = largest_first(s, A); /* NULL (out of memory): file order, the same result */
            /* each thread's kept buffers (NULL without memory: none kept, the same result) */
            vx__svo_scratch* sc = (vx__svo_scratch*)vx_calloc(A, threads, sizeof *sc);
            for (unsigned i = 0; sc && t && t->scratch_any && i < threads; i++) sc[i].min = 1;
            if (!res || !errs) r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "svo: out of memory");
            else {
                unpack_jobs j = {s, p, base, off, len, A, res, errs, chunked, lay, ext, rebuilt, order, t, sc};
                run_jobs(threads, s->model_count, unpack_job, &j);
                for (unsigned i = 0; sc && i < threads; i++) vx__svo_scratch_free(&sc[i], A);
                for (uint32_t mi = 0; chunked && mi < s->model_count; mi++)
                    if (chunked[mi] == 1 || chunked[mi] == 2) res[mi] = unpack_chunked(p + off[mi], len[mi], base + off[mi], &s->models[mi], mi, A, cpus, chunked[mi] == 2, stats, &errs[mi]);
                for (uint32_t mi = 0; r == VX_OK && mi < s->model_count; mi++)
                    if (res[mi] != VX_OK) {
                        r = res[mi];
                        if (err) *err = errs[mi];
                    }
            }
            vx_free(A, res);
            vx_free(A, errs);
            vx_free(A, order);
            vx_free(A, sc);
        }
    }
    vx_free(A, off);
    vx_free(A, len);
    return r;
}

vx_result vx__svo_unpack_one(const uint8_t* p, size_t n, uint64_t base, vx_svo_model* m, uint32_t mi, uint8_t chunked,
                             const vx_allocator* A, unsigned threads, const vx_svo_testing* t, vx__svo_extent* ext, uint8_t* rebuilt,
                             vx_error* err) {
    if (chunked >= 3) /* the split form: its streams on the threads, the layout's two stages where there are cores */
        return unpack_split(p, n, base, m, mi, A, threads ? threads : 1, lay_for(m, threads > 2 ? 2 : 0, t), chunked == 4, ext, rebuilt, NULL, err);
    if (chunked) return unpack_chunked(p, n, base, m, mi, A, threads ? threads : 1, chunked == 2, NULL, err);
    /* the layout's two stages beside the decoding where this call has the cores (layout_threads) */
    return unpack_model(p, n, base, m, mi, A, lay_for(m, threads > 2 ? 2 : 0, t), ext, rebuilt, err);
}
