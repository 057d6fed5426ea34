/* svo/svo_decode.c - decoding, structural validation and the occupied extent
 * of a model, all without expanding shared subtrees or collapsed leaves
 * (except decoding, which is callback-driven and stoppable). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "svo/svo_internal.h"

enum { ROLE_NONE = 0, ROLE_DESC = 1, ROLE_ATTR = 2, ROLE_FAR = 3 };
static const char* role_name(uint8_t r) {
    return r == ROLE_DESC ? "a descriptor" : r == ROLE_ATTR ? "an attribute index" : "a far slot";
}

/* Resolves the children block of the descriptor at word w; false if the
 * pointer leaves the array (the caller reports). */
static bool block_of(const vx_svo_model* m, uint32_t w, uint32_t d, uint32_t* slot, uint32_t* block) {
    uint32_t p = vx_svo_desc_ptr(d);
    if (p < 1 || p > w) return false;
    if (vx_svo_desc_far(d)) {
        *slot = w - p;
        *block = m->nodes[w - p];
    } else {
        *slot = UINT32_MAX;
        *block = w - p;
    }
    return true;
}

typedef struct pair_ext {
    uint64_t cells;
    uint32_t mn[3], mx[3];
} pair_ext;

/* The validation's state of one word: the levels it is reached at as a
 * descriptor (bit l; l <= 21) and its role (bits 28-29) in one word, so
 * that marking a child is one cache miss (one atomic) and not two, and the
 * number of its first pair beside them for the ascending pass's lookups of
 * children (they were separate arrays, each lookup a miss of its own in a
 * shared DAG: docs/PERFORMANCE.md, issue 18). */
typedef struct wstate {
    uint32_t st, pidx;
} wstate;
#define ST_ROLE_SHIFT 28u
#define ST_ROLE_MASK (3u << ST_ROLE_SHIFT)
#define ST_LEVELS 0x003FFFFFu
static inline uint8_t st_role(uint32_t st) { return (uint8_t)(st >> ST_ROLE_SHIFT); }

static bool mark(wstate* ws, uint32_t w, uint8_t r, uint32_t from, vx_error* err, vx_result* res) {
    uint8_t cur = st_role(ws[w].st);
    if (cur != ROLE_NONE && cur != r) {
        *res = vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET,
                       "svo model: word %u is used as %s and, from the descriptor at word %u, as %s", w, role_name(cur),
                       from, role_name(r));
        return false;
    }
    ws[w].st |= (uint32_t)r << ST_ROLE_SHIFT;
    return true;
}

/* Pairs are kept for levels 2 and up only: a descriptor at level 1 has only
 * cells below it (the descending pass refuses others), so its extent is
 * its valid mask, which its level-2 parent reads from the children's block
 * it visits anyway. That saves the level-1 pairs (most of a model's
 * descriptors) and, for each level-2 pair, the lookups of its children's
 * level and pair words and pairs (cache misses in a shared DAG). */
#define PAIR_LEVELS (ST_LEVELS & ~3u) /* level bits that have a pair */
/* A pair is kept in one 16-byte slot up to level PAIR_SMALL_MAX (its cells
 * below 2^22, its corners 0..128 in bytes) and in two above (the full
 * pair_ext). Most pairs lie at levels 2-4, so the pairs take half the
 * memory of 32 bytes each (fresh memory the kernel zeroes), and the pairs
 * of a block's children, numbered next to each other, share cache lines. */
#define PAIR_SMALL_MAX 7u
#define PAIR_WIDE_LEVELS (ST_LEVELS & ~((2u << PAIR_SMALL_MAX) - 1u)) /* two slots each */
typedef struct pslot {
    uint32_t cells;
    uint8_t mn[3], mx[3], pad[6];
} pslot;
_Static_assert(sizeof(pslot) == 16 && sizeof(pair_ext) == 2 * sizeof(pslot), "a wide pair is two slots");
/* The first slot of w's pair at level l (a bit of PAIR_LEVELS in its state). */
static uint32_t pair_of(const wstate* ws, uint32_t w, uint32_t l) {
    uint32_t below = ws[w].st & ((1u << l) - 1u);
    return ws[w].pidx + vx__popc32(below & PAIR_LEVELS) + vx__popc32(below & PAIR_WIDE_LEVELS);
}
static void pair_load(const pslot* pe, uint32_t at, uint32_t l, pair_ext* e) {
    if (l > PAIR_SMALL_MAX) {
        memcpy(e, &pe[at], sizeof *e);
        return;
    }
    e->cells = pe[at].cells;
    for (int i = 0; i < 3; i++) e->mn[i] = pe[at].mn[i], e->mx[i] = pe[at].mx[i];
}
static void pair_store(pslot* pe, uint32_t at, uint32_t l, const pair_ext* e) {
    if (l > PAIR_SMALL_MAX) {
        memcpy(&pe[at], e, sizeof *e);
        return;
    }
    pslot v;
    memset(&v, 0, sizeof v);
    v.cells = (uint32_t)e->cells;
    for (int i = 0; i < 3; i++) v.mn[i] = (uint8_t)e->mn[i], v.mx[i] = (uint8_t)e->mx[i];
    pe[at] = v;
}
/* The extent of a level-1 descriptor d: its valid octants, one cell each. */
static void level1_ext(uint32_t d, pair_ext* e) {
    uint32_t v = vx_svo_desc_valid(d);
    static const uint8_t lo[3] = {0x55, 0x33, 0x0F}; /* octants with bit k clear */
    e->cells = vx__popc8(v);
    for (int k = 0; k < 3; k++) {
        e->mn[k] = (v & lo[k]) ? 0 : 1;
        e->mx[k] = (v & ~lo[k] & 0xFFu) ? 2 : 1;
    }
}

/* The occupied extent of descriptor w at level l >= 2 from its children's
 * pairs at level l - 1 (complete before: lower words, or the level below),
 * or their masks at level 1. */
static void pair_compute(const vx_svo_model* m, const wstate* ws, pslot* pe, uint32_t w, uint32_t l) {
    uint32_t d = m->nodes[w], valid = vx_svo_desc_valid(d), leaf = vx_svo_desc_leaf(d);
    uint32_t slot = 0, b = 0;
    if (valid & ~leaf) block_of(m, w, d, &slot, &b);
    pair_ext acc, *P = &acc;
    uint32_t half = 1u << (l - 1);
    P->cells = 0;
    P->mn[0] = P->mn[1] = P->mn[2] = UINT32_MAX;
    P->mx[0] = P->mx[1] = P->mx[2] = 0;
    uint32_t k = 0;
    for (uint32_t o = 0; o < 8; o++) {
        if (!(valid >> o & 1u)) continue;
        uint32_t off[3] = {(o & 1u) * half, (o >> 1 & 1u) * half, (o >> 2 & 1u) * half};
        uint64_t cells;
        uint32_t cmn[3], cmx[3];
        if (leaf >> o & 1u) {
            cells = (uint64_t)1 << (3 * (l - 1));
            for (int i = 0; i < 3; i++) cmn[i] = off[i], cmx[i] = off[i] + half;
        } else {
            uint32_t c = b + k++;
            pair_ext c1;
            const pair_ext* C = &c1;
            if (l == 2) level1_ext(m->nodes[c], &c1);
            else pair_load(pe, pair_of(ws, c, l - 1), l - 1, &c1); /* the child's pair for level l-1 */
            cells = C->cells;
            for (int i = 0; i < 3; i++) cmn[i] = off[i] + C->mn[i], cmx[i] = off[i] + C->mx[i];
        }
        P->cells += cells;
        for (int i = 0; i < 3; i++) {
            if (cmn[i] < P->mn[i]) P->mn[i] = cmn[i];
            if (cmx[i] > P->mx[i]) P->mx[i] = cmx[i];
        }
    }
    pair_store(pe, pair_of(ws, w, l), l, P);
}

/* How far ahead the validation's loops fetch the children they will read
 * (words of the descending pass, pairs of the ascending one). */
#define PREFETCH_AHEAD 16u

/* The children of descriptor w (a guess that is never wrong to make):
 * stage 0 their states, or a far pointer's slot; stage 1 (those fetched by
 * now) the first child's pairs, or a far block's states; for a level-2
 * pair the children's words. */
static void pair_prefetch(const vx_svo_model* m, const wstate* ws, const pslot* pe, uint32_t w, uint32_t l, int stage) {
    uint32_t d = m->nodes[w], p = vx_svo_desc_ptr(d);
    if (p < 1 || p > w || !(vx_svo_desc_valid(d) & ~vx_svo_desc_leaf(d))) return;
    uint32_t b = w - p;
    if (vx_svo_desc_far(d)) {
        if (stage == 0) {
            __builtin_prefetch(&m->nodes[b]);
            return;
        }
        if ((b = m->nodes[b]) >= w) return;
        stage = 0; /* the block's states now, its pairs too late to fetch */
    }
    if (l == 2) {
        if (stage == 0) __builtin_prefetch(&m->nodes[b]); /* the children's masks */
    } else if (stage == 0) {
        __builtin_prefetch(&ws[b]);
    } else {
        __builtin_prefetch(&pe[ws[b].pidx]);
    }
}

/* The block of the descriptor at word a, fetched ahead for the descending
 * passes (a guess: a may be no descriptor): stage 0 a near block's states
 * and words (the attribute word is read with the marks), or a far
 * pointer's slot; stage 1 (the slot fetched by then) a far block's. */
static void block_prefetch(const vx_svo_model* m, const wstate* ws, uint32_t a, int stage) {
    uint32_t d = m->nodes[a], p = vx_svo_desc_ptr(d);
    if (p < 1 || p > a) return;
    uint32_t b = a - p;
    if (vx_svo_desc_far(d)) {
        if (stage == 0) {
            __builtin_prefetch(&m->nodes[b]);
            return;
        }
        if ((b = m->nodes[b]) >= a) return;
    } else if (stage == 1) {
        return;
    }
    __builtin_prefetch(&ws[b], 1);
    __builtin_prefetch(&m->nodes[b]);
}

/* The ascending pass of one large model on several threads. A pair at level
 * l reads only pairs at level l - 1, so the pairs of one level are
 * independent: listed per level (in word order, which keeps the lookups
 * near each other), each level is split over the threads, the levels one
 * after the other. The result is the sequential pass's, pair for pair. The
 * lookups of children are cache misses (a shared DAG's children lie anywhere
 * below), so on a single large model this pass was most of a chunked read. */
#define LEVEL_PARALLEL_WORDS (1u << 20)
#define LEVEL_BLOCK 16384u
typedef struct level_job {
    const vx_svo_model* m;
    const wstate* ws;
    const uint32_t* list;
    pslot* pe;
    size_t n;
    uint32_t l;
} level_job;
static void level_run(void* ctx, unsigned thread, uint32_t i) {
    (void)thread;
    level_job* j = (level_job*)ctx;
    size_t a = (size_t)i * LEVEL_BLOCK, e = a + LEVEL_BLOCK < j->n ? a + LEVEL_BLOCK : j->n;
    for (size_t k = a; k < e; k++) {
        if (k + PREFETCH_AHEAD < e) pair_prefetch(j->m, j->ws, j->pe, j->list[k + PREFETCH_AHEAD], j->l, 0);
        if (k + PREFETCH_AHEAD / 2 < e) pair_prefetch(j->m, j->ws, j->pe, j->list[k + PREFETCH_AHEAD / 2], j->l, 1);
        pair_compute(j->m, j->ws, j->pe, j->list[k], j->l);
    }
}
/* false: no memory for the lists (the caller runs the sequential pass) */
/* per_level[l + 1]: the pairs at level l (the caller counted them) */
static bool pairs_by_level(const vx_svo_model* m, const wstate* ws, pslot* pe, size_t npairs, const size_t* per_level,
                           unsigned threads) {
    size_t start[VX_SVO_MAX_DEPTH + 2];
    uint32_t* list = (uint32_t*)vx_alloc(NULL, (npairs ? npairs : 1) * sizeof *list);
    if (!list) return false;
    vx__svo_advise_huge(list, npairs * sizeof *list);
    memcpy(start, per_level, sizeof start);
    for (uint32_t l = 1; l <= VX_SVO_MAX_DEPTH + 1; l++) start[l] += start[l - 1];
    size_t fill[VX_SVO_MAX_DEPTH + 1];
    memcpy(fill, start, sizeof fill);
    for (uint32_t w = 0; w < m->node_count; w++)
        if (st_role(ws[w].st) == ROLE_DESC)
            for (uint32_t lm = ws[w].st & PAIR_LEVELS; lm; lm &= lm - 1) list[fill[__builtin_ctz(lm)]++] = w;
    for (uint32_t l = 2; l <= VX_SVO_MAX_DEPTH; l++) {
        size_t n = start[l + 1] - start[l];
        if (!n) continue;
        level_job j = {m, ws, list + start[l], pe, n, l};
        vx_run_jobs(threads, (uint32_t)((n + LEVEL_BLOCK - 1) / LEVEL_BLOCK), level_run, &j);
    }
    vx_free(NULL, list);
    return true;
}

/* The descending pass of one large model on several threads, level by
 * level: the words reached at level l (the frontier) mark their children
 * at level l - 1, each (word, level) pair once (an atomic OR of the level
 * bit says who reached it first; that one lists it), roles by compare and
 * swap. The roles and levels it leaves are the sequential pass's (set-once
 * roles and ORed levels do not depend on the order), and it checks every
 * (word, level) pair the sequential pass checks; the first error found only
 * sets a flag, and the caller runs the sequential pass again, which finds
 * the same error as a one-thread read and reports it in its words. On the
 * terrain of docs/PERFORMANCE.md (one model of 33 M words) the sequential
 * pass was a fifth of a chunked read, and the only part left on one thread. */
#define DESCEND_FLUSH 1024u
typedef struct descend_job {
    const vx_svo_model* m;
    wstate* ws;
    const uint32_t* cur;
    uint32_t* next;
    size_t n;
    size_t next_n; /* atomic */
    uint32_t l;
    int failed; /* atomic */
} descend_job;

/* Sets w's role to r; false if it has another (of two threads setting
 * different roles at once the later one sees the earlier's bits) */
static bool mark_atomic(wstate* ws, uint32_t w, uint8_t r) {
    uint32_t cur = __atomic_load_n(&ws[w].st, __ATOMIC_RELAXED);
    if (st_role(cur) == r) return true;
    if (st_role(cur) != ROLE_NONE) return false;
    cur = __atomic_fetch_or(&ws[w].st, (uint32_t)r << ST_ROLE_SHIFT, __ATOMIC_RELAXED);
    return st_role(cur) == ROLE_NONE || st_role(cur) == r;
}

static void descend_flush(descend_job* j, const uint32_t* buf, uint32_t n) {
    size_t at = __atomic_fetch_add(&j->next_n, (size_t)n, __ATOMIC_RELAXED);
    memcpy(j->next + at, buf, n * sizeof *buf);
}

/* false: an error (any the sequential pass reports for this pair) */
static bool descend_word(descend_job* j, uint32_t w, uint32_t* buf, uint32_t* nb) {
    const vx_svo_model* m = j->m;
    uint32_t l = j->l, d = m->nodes[w], valid = vx_svo_desc_valid(d), leaf = vx_svo_desc_leaf(d);
    if (valid == 0 || (leaf & ~valid)) return false;
    uint32_t nn = vx__popc8(valid & ~leaf);
    if ((l == 1 && nn) || l == 0) return false;
    uint32_t blen = nn + (m->attrs ? 1u : 0u);
    if (blen == 0) return (d >> 16) == 0;
    uint32_t slot, b;
    if (!block_of(m, w, d, &slot, &b)) return false;
    if (slot != UINT32_MAX && !mark_atomic(j->ws, slot, ROLE_FAR)) return false;
    if ((uint64_t)b + blen > w) return false;
    const uint32_t want = (uint32_t)ROLE_DESC << ST_ROLE_SHIFT | 1u << (l - 1);
    for (uint32_t k = 0; k < nn; k++) {
        /* role and level in one atomic OR, after a load: a shared child
         * already marked at this level is only read */
        uint32_t cur = __atomic_load_n(&j->ws[b + k].st, __ATOMIC_RELAXED);
        if ((cur & (want | ST_ROLE_MASK)) == want) continue;
        cur = __atomic_fetch_or(&j->ws[b + k].st, want, __ATOMIC_RELAXED);
        if (st_role(cur) != ROLE_NONE && st_role(cur) != ROLE_DESC) return false;
        if (!(cur & want & ST_LEVELS)) {
            buf[(*nb)++] = b + k;
            if (*nb == DESCEND_FLUSH) descend_flush(j, buf, *nb), *nb = 0;
        }
    }
    if (m->attrs) {
        if (!mark_atomic(j->ws, b + nn, ROLE_ATTR)) return false;
        if ((uint64_t)m->nodes[b + nn] + vx__popc8(valid) > m->attr_count) return false;
    }
    return true;
}

static void descend_run(void* ctx, unsigned thread, uint32_t i) {
    (void)thread;
    descend_job* j = (descend_job*)ctx;
    if (__atomic_load_n(&j->failed, __ATOMIC_RELAXED)) return;
    size_t a = (size_t)i * LEVEL_BLOCK, e = a + LEVEL_BLOCK < j->n ? a + LEVEL_BLOCK : j->n;
    uint32_t buf[DESCEND_FLUSH], nb = 0;
    for (size_t k = a; k < e; k++) {
        /* the frontier's words lie anywhere: the word itself, then its block */
        if (k + 2 * PREFETCH_AHEAD < e) __builtin_prefetch(&j->m->nodes[j->cur[k + 2 * PREFETCH_AHEAD]]);
        if (k + PREFETCH_AHEAD < e) block_prefetch(j->m, j->ws, j->cur[k + PREFETCH_AHEAD], 0);
        if (k + PREFETCH_AHEAD / 2 < e) block_prefetch(j->m, j->ws, j->cur[k + PREFETCH_AHEAD / 2], 1);
        if (!descend_word(j, j->cur[k], buf, &nb)) {
            __atomic_store_n(&j->failed, 1, __ATOMIC_RELAXED);
            return;
        }
    }
    if (nb) descend_flush(j, buf, nb);
}

/* 1: done, 0: an error was found (the caller runs the sequential pass for
 * its message), -1: no memory for the frontiers (the same). ws holds the
 * root's marks. */
static int descend_by_level(const vx_svo_model* m, wstate* ws, unsigned threads) {
    size_t nw = m->node_count;
    uint32_t* cur = (uint32_t*)vx_alloc(NULL, nw * sizeof *cur);
    uint32_t* next = (uint32_t*)vx_alloc(NULL, nw * sizeof *next);
    vx__svo_advise_huge(cur, nw * sizeof *cur);
    vx__svo_advise_huge(next, nw * sizeof *next);
    int res = 1;
    if (!cur || !next) res = -1;
    size_t n = 1;
    if (cur) cur[0] = m->root;
    for (uint32_t l = m->depth; res == 1 && n && l >= 1; l--) {
        descend_job j = {m, ws, cur, next, n, 0, l, 0};
        vx_run_jobs(threads, (uint32_t)((n + LEVEL_BLOCK - 1) / LEVEL_BLOCK), descend_run, &j);
        if (j.failed) res = 0;
        uint32_t* t = cur;
        cur = next, next = t, n = j.next_n;
    }
    vx_free(NULL, cur);
    vx_free(NULL, next);
    return res;
}

vx_result vx__svo_analyze_opt(const vx_svo_model* m, vx__svo_extent* ext, bool unreferenced_ok, vx_error* err) {
    return vx__svo_analyze_mt(m, ext, unreferenced_ok, 1, err);
}

static vx_result analyze(const vx_svo_model* m, vx__svo_extent* ext, bool unreferenced_ok, unsigned threads, const vx__svo_extent* tree,
                         vx_error* err);
vx_result vx__svo_analyze_mt(const vx_svo_model* m, vx__svo_extent* ext, bool unreferenced_ok, unsigned threads, vx_error* err) {
    return analyze(m, ext, unreferenced_ok, threads, NULL, err);
}

vx_result vx__svo_check_rebuilt(const vx_svo_model* m, const vx__svo_extent* tree, vx__svo_extent* ext, vx_error* err) {
    return analyze(m, ext, false, 1, tree, err);
}

/* Rule 5 of FORMAT.md 3.1 on the root's extent: cells inside the size, as many as declared. */
static vx_result check_extent(const vx_svo_model* m, uint64_t cells, const uint32_t mn[3], const uint32_t mx[3], vx__svo_extent* ext,
                              vx_error* err) {
    if (mx[0] > m->size[0] || mx[1] > m->size[1] || mx[2] > m->size[2])
        return vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "svo model: cells reach (%u, %u, %u), outside the size %ux%ux%u", mx[0] - 1,
                       mx[1] - 1, mx[2] - 1, m->size[0], m->size[1], m->size[2]);
    if (cells != m->voxel_count)
        return vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "svo model: voxel_count %llu, the tree holds %llu",
                       (unsigned long long)m->voxel_count, (unsigned long long)cells);
    if (ext) {
        ext->cells = cells;
        memcpy(ext->min, mn, sizeof ext->min);
        memcpy(ext->max, mx, sizeof ext->max);
    }
    return VX_OK;
}

/* tree: the extent of m's tree as its reconstruction computed it (a model
 * the reader rebuilt from the structural form: vx__svo_check_rebuilt);
 * then only rules 1, 2 and 5 are checked here. */
static vx_result analyze(const vx_svo_model* m, vx__svo_extent* ext, bool unreferenced_ok, unsigned threads, const vx__svo_extent* tree,
                         vx_error* err) {
    if (!m) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "svo model: null");
    if (m->depth > VX_SVO_MAX_DEPTH)
        return vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "svo model: depth %u above %u", m->depth, VX_SVO_MAX_DEPTH);
    uint32_t mxs = 0;
    for (int i = 0; i < 3; i++) {
        if (m->size[i] < 1 || m->size[i] > (1u << VX_SVO_MAX_DEPTH))
            return vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "svo model: size[%d] = %u outside 1..2^21", i, m->size[i]);
        if (m->size[i] > mxs) mxs = m->size[i];
    }
    if ((1u << m->depth) < mxs || (m->depth > 0 && (1u << (m->depth - 1)) >= mxs))
        return vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "svo model: depth %u does not match size %ux%ux%u", m->depth,
                       m->size[0], m->size[1], m->size[2]);
    if (m->attrs & ~(uint32_t)VX_ATTR_ALL)
        return vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "svo model: unknown attribute bits 0x%x", m->attrs);
    if (!m->attrs && (m->attr_count || m->root_attr))
        return vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "svo model: %u attribute records without attribute channels",
                       m->attr_count);
    const void* ch[5] = {m->palette, m->rgba, m->normal, m->material, m->density};
    for (unsigned c = 0; c < 5; c++)
        if ((m->attrs >> c & 1u) && m->attr_count && !ch[c])
            return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "svo model: attribute channel %u has no array", c);
    if (m->node_count && !m->nodes) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "svo model: nodes is NULL");
    vx__svo_extent e;
    memset(&e, 0, sizeof e);
    if (m->root == VX_SVO_ROOT_EMPTY || m->root == VX_SVO_ROOT_LEAF) {
        if (m->node_count)
            return vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "svo model: root is %s but there are %u node words",
                           m->root == VX_SVO_ROOT_EMPTY ? "empty" : "one leaf", m->node_count);
        if (m->root == VX_SVO_ROOT_LEAF) {
            uint32_t side = 1u << m->depth;
            if (m->size[0] < side || m->size[1] < side || m->size[2] < side)
                return vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "svo model: root leaf cube of %u cells exceeds the size %ux%ux%u",
                               side, m->size[0], m->size[1], m->size[2]);
            if (m->attrs && m->root_attr >= m->attr_count)
                return vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "svo model: root attribute %u of %u records", m->root_attr,
                               m->attr_count);
            e.cells = (uint64_t)1 << (3 * m->depth);
            e.max[0] = e.max[1] = e.max[2] = side;
        }
        if (m->voxel_count != e.cells)
            return vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "svo model: voxel_count %llu, the tree holds %llu",
                           (unsigned long long)m->voxel_count, (unsigned long long)e.cells);
        if (ext) *ext = e;
        return VX_OK;
    }
    if (m->root >= m->node_count)
        return vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "svo model: root word %u of %u", m->root, m->node_count);
    if (m->depth == 0)
        return vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "svo model: depth 0 (one cell) cannot have a root descriptor");
    if (m->attrs && m->root_attr >= m->attr_count)
        return vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "svo model: root attribute %u of %u records", m->root_attr,
                       m->attr_count);
    if (tree) {
        vx__svo_extent t = *tree; /* ext may be tree */
        return check_extent(m, t.cells, t.min, t.max, ext, err);
    }

    size_t nw = m->node_count;
    /* calloc, not vx_calloc (malloc, then memset): a large block is fresh
     * pages, zero already and not yet touched, so the advice below gives
     * them 2 MB pages as the passes first touch them. The memset touched
     * every 4 KB page before the advice (the 4096^3 helmet: 60% of its
     * chunked read's page faults, 458 MB zeroed twice, the descending pass's
     * random lookups through 4 KB pages). The NULL allocator is malloc. */
    wstate* ws = (wstate*)calloc(nw ? nw : 1, sizeof *ws);
    vx__svo_advise_huge(ws, nw * sizeof *ws);
    pslot* pe = NULL;
    vx_result res = VX_OK;
    if (!ws) {
        res = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "svo model: cannot allocate validation state for %zu words", nw);
        goto out;
    }
    const uint32_t root_st = 1u << m->depth | (uint32_t)ROLE_DESC << ST_ROLE_SHIFT;
    ws[m->root].st = root_st;
    if (threads >= 2 && nw >= LEVEL_PARALLEL_WORDS) {
        int pr = descend_by_level(m, ws, threads);
        if (pr == 1) goto descended;
        /* an error (the sequential pass below reports it) or no memory: from the root's marks again */
        memset(ws, 0, nw * sizeof *ws);
        ws[m->root].st = root_st;
    }
    /* Pointers only go backwards, so a descending scan sees every parent of
     * a word before the word itself: each word is checked once, for every
     * level it is reached at, and shared blocks are never expanded. */
    for (uint32_t w = m->root + 1; w-- > 0;) {
        /* the children blocks of a shared DAG lie anywhere below: their role
         * and level words are cache misses, which this loop waited on one by
         * one (most of its time on the terrain); fetch a block some words
         * ahead (a guess: the word may be no descriptor, or a far one) */
        if (w >= PREFETCH_AHEAD && st_role(ws[w - PREFETCH_AHEAD].st) == ROLE_DESC)
            block_prefetch(m, ws, w - PREFETCH_AHEAD, 0);
        if (w >= PREFETCH_AHEAD / 2 && st_role(ws[w - PREFETCH_AHEAD / 2].st) == ROLE_DESC)
            block_prefetch(m, ws, w - PREFETCH_AHEAD / 2, 1);
        const uint32_t st = ws[w].st;
        if (st_role(st) != ROLE_DESC) continue;
        uint32_t d = m->nodes[w], valid = vx_svo_desc_valid(d), leaf = vx_svo_desc_leaf(d);
        if (valid == 0) {
            res = vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "svo model: descriptor at word %u has no children", w);
            goto out;
        }
        if (leaf & ~valid) {
            res = vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET,
                          "svo model: descriptor at word %u: leaf mask 0x%02x is not a subset of valid mask 0x%02x", w, leaf, valid);
            goto out;
        }
        uint32_t nn = vx__popc8(valid & ~leaf);
        if ((st & 2u) && nn) {
            res = vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET,
                          "svo model: descriptor at word %u is at level 1 but has non-leaf children (mask 0x%02x)", w, valid & ~leaf);
            goto out;
        }
        if (st & 1u) {
            res = vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "svo model: descriptor at word %u is below the finest level", w);
            goto out;
        }
        uint32_t blen = nn + (m->attrs ? 1u : 0u);
        if (blen == 0) {
            if (d >> 16) {
                res = vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET,
                              "svo model: descriptor at word %u has no children block but a pointer (0x%04x)", w, d >> 16);
                goto out;
            }
            continue;
        }
        uint32_t slot, b;
        if (!block_of(m, w, d, &slot, &b)) {
            res = vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET,
                          "svo model: descriptor at word %u: child pointer %u does not point backwards into the array", w,
                          vx_svo_desc_ptr(d));
            goto out;
        }
        if (slot != UINT32_MAX && !mark(ws, slot, ROLE_FAR, w, err, &res)) goto out;
        if ((uint64_t)b + blen > w) {
            res = vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET,
                          "svo model: descriptor at word %u: children block at word %u (%u words) does not lie before it", w, b,
                          blen);
            goto out;
        }
        for (uint32_t k = 0; k < nn; k++) {
            if (!mark(ws, b + k, ROLE_DESC, w, err, &res)) goto out;
            ws[b + k].st |= (st & ST_LEVELS) >> 1;
        }
        if (m->attrs) {
            if (!mark(ws, b + nn, ROLE_ATTR, w, err, &res)) goto out;
            uint32_t a = m->nodes[b + nn];
            if ((uint64_t)a + vx__popc8(valid) > m->attr_count) {
                res = vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET,
                              "svo model: descriptor at word %u: attribute records %u..%u beyond the %u records", w, a,
                              a + vx__popc8(valid) - 1, m->attr_count);
                goto out;
            }
        }
    }
descended:; /* (a declaration follows: C17 needs a statement after a label) */
    /* ascending: occupied extent of every (descriptor, level) pair; one pass
     * over the words checks that each was reached, numbers the pairs and
     * counts them per level (single passes over 33 M words matter on one
     * large model, docs/PERFORMANCE.md issue 18) */
    size_t npairs = 0, per_level[VX_SVO_MAX_DEPTH + 2] = {0};
    for (size_t w = 0; w < nw; w++) {
        ws[w].pidx = (uint32_t)npairs;
        uint8_t role = st_role(ws[w].st);
        if (role == ROLE_DESC) {
            uint32_t lm = ws[w].st & PAIR_LEVELS;
            npairs += (size_t)vx__popc32(lm) + vx__popc32(lm & PAIR_WIDE_LEVELS); /* slots */
            for (; lm; lm &= lm - 1) per_level[__builtin_ctz(lm) + 1]++;
        } else if (role == ROLE_NONE && !unreferenced_ok) {
            res = vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "svo model: word %zu of %zu is not reachable from the root", w, nw);
            goto out;
        }
        if (npairs > 0xFFFFFFF0u) {
            res = vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "svo model: too many shared levels to validate");
            goto out;
        }
    }
    pe = (pslot*)vx_alloc(NULL, (npairs ? npairs : 1) * sizeof *pe);
    vx__svo_advise_huge(pe, npairs * sizeof *pe);
    if (!pe) {
        res = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "svo model: cannot allocate validation state");
        goto out;
    }
    if (threads < 2 || nw < LEVEL_PARALLEL_WORDS || !pairs_by_level(m, ws, pe, npairs, per_level, threads)) {
        for (uint32_t w = 0; w < nw; w++) {
            /* the children of words some way ahead (their lowest level's) */
            for (int stage = 0; stage < 2; stage++) {
                uint32_t a = w + (stage ? PREFETCH_AHEAD / 2 : PREFETCH_AHEAD);
                uint32_t lm = a < nw && st_role(ws[a].st) == ROLE_DESC ? ws[a].st & PAIR_LEVELS : 0;
                if (lm) pair_prefetch(m, ws, pe, a, (uint32_t)__builtin_ctz(lm), stage);
            }
            if (st_role(ws[w].st) != ROLE_DESC) continue;
            for (uint32_t lm = ws[w].st & PAIR_LEVELS; lm; lm &= lm - 1) pair_compute(m, ws, pe, w, (uint32_t)__builtin_ctz(lm));
        }
    }
    {
        pair_ext r1;
        const pair_ext* R = &r1;
        if (m->depth == 1) level1_ext(m->nodes[m->root], &r1);
        else pair_load(pe, ws[m->root].pidx, m->depth, &r1);
        res = check_extent(m, R->cells, R->mn, R->mx, ext, err);
    }
out:
    vx_free(NULL, ws);
    vx_free(NULL, pe);
    return res;
}

vx_result vx__svo_analyze(const vx_svo_model* m, vx__svo_extent* ext, vx_error* err) {
    return vx__svo_analyze_opt(m, ext, false, err);
}

vx_result vx_svo_validate_model(const vx_svo_model* m, vx_error* err) { return vx__svo_analyze(m, NULL, err); }

static bool finite12(const double* v) {
    for (int i = 0; i < 12; i++)
        if (!isfinite(v[i])) return false;
    return true;
}
static bool has_nul(const char* s, size_t n) { return memchr(s, 0, n) != NULL; }

vx_result vx_svo_validate_scene(const vx_svo_scene* s, vx_error* err) { return vx__svo_validate_scene_ext(s, NULL, 0, err); }

/* One instance record (of the scene or of a frame: `where` is "" or "frame F "). */
static vx_result check_instance(const vx_svo_scene* s, const vx_svo_instance* in, uint32_t i, const char* where, vx_error* err) {
    if (in->model >= s->model_count)
        return vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "svo scene: %sinstance %u uses model %u of %u", where, i, in->model,
                       s->model_count);
    if (in->layer != UINT32_MAX && in->layer >= s->layer_count)
        return vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "svo scene: %sinstance %u is on layer %u of %u", where, i, in->layer,
                       s->layer_count);
    if (!finite12(in->xform))
        return vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "svo scene: %sinstance %u has a non-finite transform", where, i);
    if (in->flags & ~(uint32_t)VX_SVO_INSTANCE_HIDDEN)
        return vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "svo scene: %sinstance %u has unknown flags 0x%x", where, i, in->flags);
    if (!has_nul(in->name, sizeof in->name))
        return vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "svo scene: %sinstance %u name is not NUL-terminated", where, i);
    return VX_OK;
}

typedef struct analyze_jobs {
    const vx_svo_scene* s;
    vx__svo_extent* ext;
    const uint8_t* skip;
    vx_result* res;
    vx_error* errs;
} analyze_jobs;

static void analyze_job(void* ctx, unsigned thread, uint32_t i) {
    (void)thread;
    analyze_jobs* j = (analyze_jobs*)ctx;
    if (j->skip && j->skip[i] == VX__SVO_SKIP_REBUILT) j->res[i] = vx__svo_check_rebuilt(&j->s->models[i], &j->ext[i], &j->ext[i], &j->errs[i]);
    if (j->skip && j->skip[i]) return; /* res[i] stays VX_OK (0) */
    j->res[i] = vx__svo_analyze(&j->s->models[i], j->ext ? &j->ext[i] : NULL, &j->errs[i]);
}

/* Analyses every model but those marked in skip (may be NULL), in parallel
 * for large scenes; the first failing model in index order gives the error. */
static vx_result analyze_models(const vx_svo_scene* s, vx__svo_extent* ext, const uint8_t* skip, unsigned want, const vx_svo_testing* t,
                                uint32_t* bad, vx_error* err) {
    unsigned threads = vx__svo_threads(s, want, t);
    vx_result* res = threads > 1 ? (vx_result*)vx_calloc(s->alloc, s->model_count, sizeof *res) : NULL;
    vx_error* errs = threads > 1 ? (vx_error*)vx_calloc(s->alloc, s->model_count, sizeof *errs) : NULL;
    vx_result r = VX_OK;
    if (res && errs) {
        analyze_jobs j = {s, ext, skip, res, errs};
        vx_run_jobs(threads, s->model_count, analyze_job, &j);
        for (uint32_t i = 0; r == VX_OK && i < s->model_count; i++)
            if (res[i] != VX_OK) {
                r = res[i];
                *bad = i;
                if (err) *err = errs[i];
            }
    } else { /* one model at a time: a large one uses the threads within itself */
        unsigned cpus = vx__svo_cpus(want);
        for (uint32_t i = 0; r == VX_OK && i < s->model_count; i++)
            if (skip && skip[i] == VX__SVO_SKIP_REBUILT) {
                if ((r = vx__svo_check_rebuilt(&s->models[i], &ext[i], &ext[i], err)) != VX_OK) *bad = i;
            } else if ((!skip || !skip[i]) && (r = vx__svo_analyze_mt(&s->models[i], ext ? &ext[i] : NULL, false, cpus, err)) != VX_OK) {
                *bad = i;
            }
    }
    vx_free(s->alloc, res);
    vx_free(s->alloc, errs);
    return r;
}

/* Digests of a scene's models on the threads: the reader's checks, and the
 * writer's test of them. */
typedef struct digest_jobs {
    const vx_svo_scene* s;
    uint32_t* digest;
    const uint8_t* only; /* NULL: every model */
} digest_jobs;

static void digest_job(void* ctx, unsigned thread, uint32_t i) {
    (void)thread;
    digest_jobs* j = (digest_jobs*)ctx;
    j->digest[i] = !j->only || j->only[i] ? vx_svo_model_digest(&j->s->models[i]) : 0;
}

static void digests(const vx_svo_scene* s, const uint8_t* only, unsigned threads, const vx_svo_testing* t, uint32_t* out) {
    digest_jobs j = {s, out, only};
    vx_run_jobs(vx__svo_threads(s, threads, t), s->model_count, digest_job, &j);
}

void vx__svo_set_checks(vx_svo_scene* s, const vx__svo_extent* ext, unsigned threads, const vx_svo_testing* t) {
    uint32_t* d = s->model_count ? (uint32_t*)vx_calloc(s->alloc, s->model_count, sizeof *d) : NULL;
    if (!d) return; /* no checks: a later write validates */
    digests(s, NULL, threads, t, d);
    for (uint32_t i = 0; i < s->model_count; i++) {
        vx_svo_model_check* c = &s->models[i].check;
        c->digest = d[i];
        memcpy(c->min, ext[i].min, sizeof c->min);
        memcpy(c->max, ext[i].max, sizeof c->max);
    }
    vx_free(s->alloc, d);
}

void vx__svo_trusted_models(const vx_svo_scene* s, const vx_allocator* alloc, uint32_t chunk_min, unsigned threads, const vx_svo_testing* t,
                            uint8_t* skip, vx__svo_extent* ext) {
    uint32_t n = 0;
    for (uint32_t i = 0; i < s->model_count; i++) {
        const vx_svo_model* m = &s->models[i];
        /* chunked models, and those the structural coder takes with the
         * check's settings (its walk is safe on any words: ext_visit) */
        skip[i] = m->check.digest && (vx__svo_model_chunked(m, chunk_min) || m->check.structural);
        n += skip[i];
    }
    uint32_t* d = n ? (uint32_t*)vx_calloc(alloc, s->model_count, sizeof *d) : NULL;
    if (d) digests(s, skip, threads, t, d);
    for (uint32_t i = 0; i < s->model_count; i++) {
        const vx_svo_model* m = &s->models[i];
        skip[i] = skip[i] && d && d[i] == m->check.digest;
        if (!skip[i]) continue;
        ext[i].cells = m->voxel_count;
        memcpy(ext[i].min, m->check.min, sizeof ext[i].min);
        memcpy(ext[i].max, m->check.max, sizeof ext[i].max);
    }
    vx_free(alloc, d);
}

vx_result vx__svo_validate_scene_ext(const vx_svo_scene* s, vx__svo_extent* ext, unsigned threads, vx_error* err) {
    return vx__svo_validate_scene_opt(s, ext, threads, NULL, true, NULL, err);
}

vx_result vx__svo_validate_scene_opt(const vx_svo_scene* s, vx__svo_extent* ext, unsigned threads, const vx_svo_testing* t, bool models,
                                     const uint8_t* skip, vx_error* err) {
    if (!s) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "svo scene: null");
    if ((s->model_count && !s->models) || (s->instance_count && !s->instances) || (s->layer_count && !s->layers) ||
        (s->material_count && !s->materials) || (s->light_count && !s->lights))
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "svo scene: a non-empty array is NULL");
    uint32_t bad = 0;
    if (models) {
        vx_result r = analyze_models(s, ext, skip, threads, t, &bad, err);
        if (r != VX_OK) {
            char p[32];
            snprintf(p, sizeof p, "model %u", bad);
            vx_error_prefix(err, p);
            return r;
        }
    }
    for (uint32_t i = 0; i < s->instance_count; i++) {
        vx_result r = check_instance(s, &s->instances[i], i, "", err);
        if (r != VX_OK) return r;
    }
    if (s->frame_count > 1 || s->frame_instances) {
        if (s->frame_count < 2 || (s->instance_count && !s->frame_instances))
            return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "svo scene: %u frames with%s frame records", s->frame_count,
                           s->frame_instances ? "" : "out");
        if (!isfinite(s->frame_rate) || s->frame_rate < 0)
            return vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "svo scene: frame rate %g is not finite and >= 0", s->frame_rate);
        if ((uint64_t)(s->frame_count - 1) * s->instance_count > VX_SVO_FRAMES_MAX_BYTES / sizeof(vx_svo_instance))
            return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "svo scene: %u frames of %u instances exceed %llu bytes", s->frame_count,
                           s->instance_count, (unsigned long long)VX_SVO_FRAMES_MAX_BYTES);
        for (uint32_t f = 1; f < s->frame_count; f++) {
            char where[40];
            snprintf(where, sizeof where, "frame %u ", f);
            const vx_svo_instance* fr = s->frame_instances + (size_t)(f - 1) * s->instance_count;
            for (uint32_t i = 0; i < s->instance_count; i++) {
                vx_result r = check_instance(s, &fr[i], i, where, err);
                if (r != VX_OK) return r;
                /* the file stores a frame's model, transform and flags only */
                if (fr[i].layer != s->instances[i].layer || strcmp(fr[i].name, s->instances[i].name) != 0)
                    return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET,
                                   "svo scene: frame %u instance %u: name or layer differs from the instance it animates", f, i);
            }
        }
    }
    for (uint32_t i = 0; i < s->layer_count; i++) {
        if (!has_nul(s->layers[i].name, sizeof s->layers[i].name))
            return vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "svo scene: layer %u name is not NUL-terminated", i);
        if (s->layers[i].flags & ~(uint32_t)VX_SVO_LAYER_HIDDEN)
            return vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "svo scene: layer %u has unknown flags 0x%x", i,
                           s->layers[i].flags);
    }
    for (uint32_t i = 0; i < s->material_count; i++) {
        const vx_svo_material* mt = &s->materials[i];
        if (mt->dict_size == 0) continue;
        if (!mt->dict) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "svo scene: material %u dictionary is NULL", i);
        if (mt->dict[mt->dict_size - 1] != 0)
            return vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "svo scene: material %u dictionary does not end with NUL", i);
        uint32_t nul = 0;
        for (uint32_t k = 0; k < mt->dict_size; k++) nul += mt->dict[k] == 0;
        if (nul & 1u)
            return vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "svo scene: material %u dictionary has a key without a value", i);
    }
    for (uint32_t i = 0; i < s->light_count; i++) {
        vx_result r = vx_light_validate(&s->lights[i], i, err);
        if (r == VX_OK && s->lights[i].flags)
            r = vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET,
                        "light %u: flags 0x%x: lights derived from voxels are not scene data", i, s->lights[i].flags);
        if (r != VX_OK) return vx_error_prefix(err, "svo scene"), r;
    }
    {
        vx_result r = vx_sky_validate(&s->sky, err);
        if (r != VX_OK) return vx_error_prefix(err, "svo scene"), r;
    }
    if (!finite12(s->world_from_grid))
        return vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "svo scene: world_from_grid is not finite");
    for (int i = 0; i < 3; i++)
        if (!isfinite(s->bounds_min[i]) || !isfinite(s->bounds_max[i]) || s->bounds_min[i] > s->bounds_max[i])
            return vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "svo scene: bounds on axis %d are not finite or inverted", i);
    return VX_OK;
}

/* ---- decoding ---------------------------------------------------------------------------- */

typedef struct dec {
    const vx_svo_model* m;
    vx_svo_voxel_fn fn;
    void* user;
    bool stop;
    vx_error* err;
    vx_result res;
} dec;

static void emit_cube(dec* D, uint32_t x0, uint32_t y0, uint32_t z0, uint32_t lvl, uint32_t attr) {
    uint64_t n = (uint64_t)1 << (3 * lvl);
    for (uint64_t c = 0; c < n && !D->stop; c++)
        if (!D->fn(D->user, x0 + vx__compact3(c), y0 + vx__compact3(c >> 1), z0 + vx__compact3(c >> 2), attr)) D->stop = true;
}

/* Recursion depth is bounded by the model depth (<= 21). */
static void visit(dec* D, uint32_t w, uint32_t lvl, uint32_t x0, uint32_t y0, uint32_t z0) {
    const vx_svo_model* m = D->m;
    uint32_t d = m->nodes[w], valid = vx_svo_desc_valid(d), leaf = vx_svo_desc_leaf(d);
    uint32_t nn = vx__popc8(valid & ~leaf), blen = nn + (m->attrs ? 1u : 0u);
    uint32_t slot = 0, b = 0, a = 0;
    if (blen) {
        /* cheap guards so that an unvalidated model cannot read out of bounds */
        if (!block_of(m, w, d, &slot, &b) || (uint64_t)b + blen > w || lvl == 0 || (lvl == 1 && nn)) {
            D->res = vx_fail(D->err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "svo decode: bad descriptor at word %u", w);
            D->stop = true;
            return;
        }
        if (m->attrs) a = m->nodes[b + nn];
    }
    uint32_t half = 1u << (lvl - 1), k = 0;
    for (uint32_t o = 0; o < 8 && !D->stop; o++) {
        if (!(valid >> o & 1u)) continue;
        uint32_t x = x0 + (o & 1u) * half, y = y0 + (o >> 1 & 1u) * half, z = z0 + (o >> 2 & 1u) * half;
        if (leaf >> o & 1u) {
            uint32_t attr = m->attrs ? a + vx__popc8(valid & ((1u << o) - 1u)) : 0;
            emit_cube(D, x, y, z, lvl - 1, attr);
        } else {
            visit(D, b + k++, lvl - 1, x, y, z);
        }
    }
}

vx_result vx_svo_decode_model(const vx_svo_model* m, vx_svo_voxel_fn fn, void* user, vx_error* err) {
    if (!m || !fn) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "svo decode: null argument");
    if (m->depth > VX_SVO_MAX_DEPTH)
        return vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "svo decode: depth %u above %u", m->depth, VX_SVO_MAX_DEPTH);
    dec D = {m, fn, user, false, err, VX_OK};
    if (m->root == VX_SVO_ROOT_EMPTY) return VX_OK;
    if (m->root == VX_SVO_ROOT_LEAF) {
        emit_cube(&D, 0, 0, 0, m->depth, m->attrs ? m->root_attr : 0);
        return VX_OK;
    }
    if (m->root >= m->node_count || !m->nodes || m->depth == 0)
        return vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "svo decode: root word %u of %u", m->root, m->node_count);
    visit(&D, m->root, m->depth, 0, 0, 0);
    return D.res;
}

/* ---- blocks ---------------------------------------------------------------------------- */

typedef struct bdec {
    const vx_svo_model* m;
    vx_svo_block_fn fn;
    void* user;
    bool stop;
    vx_error* err;
    vx_result res;
    uint32_t bits[16]; /* the block being filled (levels below 3) */
    uint32_t full[16];
} bdec;

/* The cells of a cube of side 2^lvl (lvl <= 3) at (x0, y0, z0) within the
 * block, into its bits. */
static void bits_cube(bdec* B, uint32_t x0, uint32_t y0, uint32_t z0, uint32_t lvl) {
    uint32_t n = 1u << lvl;
    for (uint32_t z = z0; z < z0 + n; z++)
        for (uint32_t y = y0; y < y0 + n; y++)
            for (uint32_t x = x0; x < x0 + n; x++) {
                uint32_t i = x + 8 * y + 64 * z;
                B->bits[i >> 5] |= 1u << (i & 31);
            }
}

/* A descriptor's children block, with decode's guards (visit). */
static bool bdesc(bdec* B, uint32_t w, uint32_t lvl, uint32_t* d, uint32_t* b) {
    const vx_svo_model* m = B->m;
    *d = m->nodes[w];
    uint32_t valid = vx_svo_desc_valid(*d), leaf = vx_svo_desc_leaf(*d), nn = vx__popc8(valid & ~leaf), slot;
    uint32_t blen = nn + (m->attrs ? 1u : 0u);
    *b = 0;
    if (blen && (!block_of(m, w, *d, &slot, b) || (uint64_t)*b + blen > w || lvl == 0 || (lvl == 1 && nn))) {
        B->res = vx_fail(B->err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "svo decode: bad descriptor at word %u", w);
        B->stop = true;
        return false;
    }
    return true;
}

static void emit_block(bdec* B, uint32_t bx, uint32_t by, uint32_t bz, const uint32_t* bits) {
    if (!B->stop && !B->fn(B->user, bx, by, bz, bits)) B->stop = true;
}

/* A uniform cube of side 2^lvl (lvl >= 3) at block (bx, by, bz): its full
 * blocks, in Morton order. */
static void full_blocks(bdec* B, uint32_t bx, uint32_t by, uint32_t bz, uint32_t lvl) {
    uint64_t n = (uint64_t)1 << (3 * (lvl - 3));
    for (uint64_t c = 0; c < n && !B->stop; c++)
        emit_block(B, bx + vx__compact3(c), by + vx__compact3(c >> 1), bz + vx__compact3(c >> 2), B->full);
}

/* A node of side 2^lvl at cell (x0, y0, z0): above level 3 its uniform
 * leaves as full blocks and its children in turn, a child of side 8 into
 * a block of its own; at level 3 and below its cells into B->bits (the
 * caller clears and emits the block). Recursion bounded by the depth. */
static void blocks_node(bdec* B, uint32_t w, uint32_t lvl, uint32_t x0, uint32_t y0, uint32_t z0) {
    uint32_t d, b;
    if (!bdesc(B, w, lvl, &d, &b)) return;
    uint32_t valid = vx_svo_desc_valid(d), leaf = vx_svo_desc_leaf(d), half = 1u << (lvl - 1), k = 0;
    for (uint32_t o = 0; o < 8 && !B->stop; o++) {
        if (!(valid >> o & 1u)) continue;
        uint32_t x = x0 + (o & 1u) * half, y = y0 + (o >> 1 & 1u) * half, z = z0 + (o >> 2 & 1u) * half;
        if (leaf >> o & 1u) {
            if (lvl > 3) full_blocks(B, x >> 3, y >> 3, z >> 3, lvl - 1);
            else bits_cube(B, x & 7u, y & 7u, z & 7u, lvl - 1);
        } else if (lvl == 4) {
            memset(B->bits, 0, sizeof B->bits);
            blocks_node(B, b + k++, 3, x, y, z);
            emit_block(B, x >> 3, y >> 3, z >> 3, B->bits);
        } else {
            blocks_node(B, b + k++, lvl - 1, x, y, z);
        }
    }
}

vx_result vx_svo_decode_blocks(const vx_svo_model* m, vx_svo_block_fn fn, void* user, vx_error* err) {
    if (!m || !fn) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "svo decode: null argument");
    if (m->depth > VX_SVO_MAX_DEPTH)
        return vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "svo decode: depth %u above %u", m->depth, VX_SVO_MAX_DEPTH);
    bdec B = {.m = m, .fn = fn, .user = user, .err = err};
    memset(B.full, 0xFF, sizeof B.full);
    if (m->root == VX_SVO_ROOT_EMPTY) return VX_OK;
    if (m->root == VX_SVO_ROOT_LEAF) {
        if (m->depth >= 3) full_blocks(&B, 0, 0, 0, m->depth);
        else bits_cube(&B, 0, 0, 0, m->depth), emit_block(&B, 0, 0, 0, B.bits);
        return VX_OK;
    }
    if (m->root >= m->node_count || !m->nodes || m->depth == 0)
        return vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "svo decode: root word %u of %u", m->root, m->node_count);
    blocks_node(&B, m->root, m->depth, 0, 0, 0);
    if (m->depth <= 3) emit_block(&B, 0, 0, 0, B.bits); /* the whole model within one block */
    return B.res;
}

uint32_t vx_svo_attr_color(const vx_svo_scene* s, const vx_svo_model* m, uint32_t attr) {
    if (!m || attr >= m->attr_count) return 0xFFFFFFFFu;
    if ((m->attrs & VX_ATTR_RGBA8) && m->rgba) return m->rgba[attr];
    if ((m->attrs & VX_ATTR_PALETTE) && m->palette) return s ? s->palette[m->palette[attr]] : 0xFFFFFFFFu;
    return 0xFFFFFFFFu;
}
