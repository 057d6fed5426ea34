/* render/node_order.c - treelet order of a model's node words (node_order.h). */
#include "render/node_order.h"

#include "svo/svo_internal.h" /* VX__SVO_PTR_MAX */

/* Blocks are keyed by their first word in the file; key n (one past the
 * words) is the root descriptor alone, a block of one descriptor and no
 * attribute word, so that a root that is also some block's start stays
 * apart. */
typedef struct ord {
    const uint32_t* w;
    uint32_t n, root;
    bool attrs;
    uint8_t *len, *inner; /* per key: block words (0: not reached) and descriptors among them */
    uint32_t* indeg;      /* per key: references from reached blocks not placed yet */
    uint32_t *seq, nseq;  /* keys in placement order (top-down) */
    uint8_t* tstart;      /* per seq entry: it starts a treelet */
    uint32_t *queue, qcap, qtop; /* the treelets' queues, one above another */
    uint32_t budget;
    bool bad;
} ord;

static uint32_t key_start(const ord* o, uint32_t b) { return b < o->n ? b : o->root; }

/* The block of descriptor word wi (key, words *len, descriptors *inner), or
 * false where it has none; o->bad where its pointer breaks the format. */
static bool child_block(ord* o, uint32_t wi, uint32_t* key, uint32_t* len, uint32_t* inner) {
    uint32_t d = o->w[wi];
    uint32_t valid = vx_svo_desc_valid(d), leaf = vx_svo_desc_leaf(d);
    uint32_t ni = (uint32_t)__builtin_popcount(valid & ~leaf);
    uint32_t l = ni + (o->attrs && valid ? 1u : 0u);
    if (!l) return false;
    uint32_t p = vx_svo_desc_ptr(d);
    if (p == 0 || p > wi) return o->bad = true, false;
    uint32_t c = wi - p;
    if (vx_svo_desc_far(d)) c = o->w[c];
    /* the whole block before the descriptor: pointers go backwards, so the
     * walk below ends (no cycle) */
    if (c >= wi || wi - c < l) return o->bad = true, false;
    *key = c, *len = l, *inner = ni;
    return true;
}

/* Places the treelet rooted at block b (all its parents placed): blocks
 * breadth-first while they fit the budget, then a treelet per block left in
 * the queue. A block enters a queue when its last parent is placed. */
static void treelet(ord* o, uint32_t b, unsigned depth) {
    /* a chain deeper than the tracer's 23 levels is no octree (and would
     * take the stack) */
    if (depth > 64 || o->qcap - o->qtop < 9 * (o->budget + 1)) {
        o->bad = true;
        return;
    }
    uint32_t* q = o->queue + o->qtop;
    uint32_t head = 0, tail = 0, used = 0;
    q[tail++] = b;
    o->tstart[o->nseq] = 1;
    while (head < tail) {
        uint32_t x = q[head];
        if (used && used + o->len[x] > o->budget) break;
        head++;
        o->seq[o->nseq++] = x;
        used += o->len[x];
        uint32_t s = key_start(o, x);
        for (uint32_t k = 0; k < o->inner[x]; k++) {
            uint32_t c, l, ni;
            if (child_block(o, s + k, &c, &l, &ni) && --o->indeg[c] == 0) q[tail++] = c;
        }
    }
    o->qtop += tail;
    for (uint32_t i = head; i < tail && !o->bad; i++) treelet(o, q[i], depth + 1);
    o->qtop -= tail;
}

bool vx__node_order(const vx_svo_model* m, const vx__node_order_desc* desc, const vx_allocator* alloc, uint32_t** out,
                    uint32_t* out_count, uint32_t* out_root) {
    *out = NULL;
    if (!m->nodes || m->root >= m->node_count || m->node_count >= UINT32_MAX) return false;
    uint32_t budget = desc && desc->words ? desc->words : 32;
    if (budget > 4096) budget = 4096;
    uint32_t align = desc && desc->align ? desc->align : 0;
    if (align > 4096) align = 4096;
    /* at least 16: a far slot sits within 16 words of its descriptor */
    uint32_t limit = desc && desc->limit && desc->limit < VX__SVO_PTR_MAX ? desc->limit : VX__SVO_PTR_MAX;
    if (limit < 16) limit = 16;
    ord o = {.w = m->nodes, .n = m->node_count, .root = m->root, .attrs = m->attrs != 0, .budget = budget};
    size_t keys = (size_t)o.n + 1;
    o.len = vx_calloc(alloc, keys, 2);
    o.indeg = vx_calloc(alloc, keys, 4);
    o.seq = vx_calloc(alloc, keys, 4);
    o.tstart = vx_calloc(alloc, keys, 1);
    uint8_t* nfa = vx_calloc(alloc, keys, 1); /* per seq entry: its far slots */
    uint32_t* pos = vx_calloc(alloc, keys, 4);
    uint8_t* far = vx_calloc(alloc, o.n, 1); /* per descriptor word: its block through a far slot */
    o.qcap = 65 * 9 * (budget + 1);
    o.queue = vx_calloc(alloc, o.qcap, 4);
    uint32_t* stack = o.seq; /* the discovery's stack, before seq is filled */
    uint32_t* words = NULL;
    bool ok = false;
    if (!o.len || !o.indeg || !o.seq || !o.tstart || !nfa || !pos || !far || !o.queue) goto done;
    o.inner = o.len + keys;

    /* the blocks reached from the root, their lengths and references */
    uint32_t sp = 0;
    o.len[o.n] = 1, o.inner[o.n] = 1, o.indeg[o.n] = 1;
    stack[sp++] = o.n;
    while (sp && !o.bad) {
        uint32_t b = stack[--sp], s = key_start(&o, b);
        if ((uint64_t)s + o.len[b] > o.n) {
            o.bad = true;
            break;
        }
        for (uint32_t k = 0; k < o.inner[b]; k++) {
            uint32_t c, l, ni;
            if (!child_block(&o, s + k, &c, &l, &ni)) continue;
            if (!o.len[c]) {
                o.len[c] = (uint8_t)l, o.inner[c] = (uint8_t)ni;
                stack[sp++] = c; /* each key once: at most n + 1 */
            } else if (o.len[c] != l || o.inner[c] != ni) {
                o.bad = true;
            }
            o.indeg[c]++;
        }
    }
    if (o.bad) goto done;
    o.indeg[o.n] = 0;
    treelet(&o, o.n, 0);
    if (o.bad) goto done;

    /* positions: top-down, a block then its far slots; the words are then
     * written in reverse block order (a block's own words in place), so a
     * block's far slots sit right before it and its children before it.
     * Each far slot moves the blocks below, so the far marks grow to a
     * fixpoint (they only grow: at most one round per descriptor). */
    uint64_t total = 0;
    for (bool more = true; more;) {
        more = false;
        total = 0;
        for (uint32_t i = 0; i < o.nseq; i++) {
            uint32_t b = o.seq[i], s = key_start(&o, b), nf = 0;
            for (uint32_t k = 0; k < o.inner[b]; k++) nf += far[s + k];
            nfa[i] = (uint8_t)nf;
        }
        for (uint32_t i = 0; i < o.nseq; i++) {
            uint32_t b = o.seq[i];
            if (align && o.tstart[i]) {
                /* a treelet that fits a line but would cross one starts
                 * the next (the words' end is aligned below, so lines of
                 * the top-down positions are lines of the final ones) */
                uint64_t size = 0;
                for (uint32_t j = i; j < o.nseq && (j == i || !o.tstart[j]) && size <= align; j++)
                    size += o.len[o.seq[j]] + nfa[j];
                if (size <= align && total % align + size > align) total += align - total % align;
            }
            pos[b] = (uint32_t)total;
            total += o.len[b] + nfa[i];
            if (total > UINT32_MAX - 4096) goto done;
        }
        if (align && total % align) total += align - total % align;
        for (uint32_t i = 0; i < o.nseq; i++) {
            uint32_t b = o.seq[i], s = key_start(&o, b);
            uint64_t fb = total - pos[b] - o.len[b]; /* the block's final index */
            for (uint32_t k = 0; k < o.inner[b]; k++) {
                uint32_t c, l, ni;
                if (far[s + k] || !child_block(&o, s + k, &c, &l, &ni)) continue;
                if (fb + k - (total - pos[c] - o.len[c]) > limit) far[s + k] = 1, more = true;
            }
        }
    }
    words = vx_calloc(alloc, total ? total : 1, 4); /* alignment's gaps: zero words no pointer reaches */
    if (!words) goto done;
    for (uint32_t i = 0; i < o.nseq; i++) {
        uint32_t b = o.seq[i], s = key_start(&o, b);
        uint32_t fb = (uint32_t)(total - pos[b] - o.len[b]), fs = fb;
        for (uint32_t k = 0; k < o.inner[b]; k++) fs -= far[s + k];
        for (uint32_t k = 0, j = 0; k < o.len[b]; k++) {
            uint32_t d = o.w[s + k], c, l, ni;
            if (k >= o.inner[b]) {
                words[fb + k] = d; /* the attribute word: records keep their indices */
                continue;
            }
            uint32_t valid = vx_svo_desc_valid(d), leaf = vx_svo_desc_leaf(d);
            if (!child_block(&o, s + k, &c, &l, &ni)) {
                words[fb + k] = vx_svo_desc_make(0, false, valid, leaf);
                continue;
            }
            uint32_t cf = (uint32_t)(total - pos[c] - o.len[c]);
            if (far[s + k]) {
                words[fs + j] = cf;
                words[fb + k] = vx_svo_desc_make(fb + k - (fs + j), true, valid, leaf);
                j++;
            } else {
                words[fb + k] = vx_svo_desc_make(fb + k - cf, false, valid, leaf);
            }
        }
    }
    *out = words, *out_count = (uint32_t)total, *out_root = (uint32_t)(total - 1);
    words = NULL;
    ok = true;
done:
    vx_free(alloc, words);
    vx_free(alloc, o.len);
    vx_free(alloc, o.indeg);
    vx_free(alloc, o.seq);
    vx_free(alloc, o.tstart);
    vx_free(alloc, nfa);
    vx_free(alloc, pos);
    vx_free(alloc, far);
    vx_free(alloc, o.queue);
    return ok;
}
