/* render/compact.c - the compact GPU layout (render/compact.h): the geometry
 * DAG rebuilt from each model's Laine-Karras tree without its attribute
 * indices and hash-consed over the whole scene, and the attributes in
 * Morton order, block-coded with per-block palettes. */
#define _POSIX_C_SOURCE 200809L /* nanosleep */
#include "render/compact.h"

#include <pthread.h>
#include <stdatomic.h>
#include <string.h>
#include <time.h>

#define ATTR_OFF_MAX (1u << 27) /* payload offsets have 27 bits */

static uint32_t popc(uint32_t m) { return (uint32_t)__builtin_popcount(m); }

/* Bits [pos, pos + n) of a little-end-first bit stream, n in 1..32. The
 * caller sizes streams so that a straddling read stays inside. */
static uint32_t get_bits(const uint32_t* w, uint64_t pos, uint32_t n) {
    uint64_t i = pos >> 5;
    uint32_t s = (uint32_t)(pos & 31u);
    uint32_t v = w[i] >> s;
    if (s + n > 32) v |= w[i + 1] << (32 - s);
    return n == 32 ? v : v & ((1u << n) - 1u);
}
static void put_bits(uint32_t* w, uint64_t pos, uint32_t v, uint32_t n) {
    uint64_t i = pos >> 5;
    uint32_t s = (uint32_t)(pos & 31u);
    w[i] |= v << s;
    if (s + n > 32) w[i + 1] |= v >> (32 - s);
}

static uint64_t hash_words(const uint32_t* w, uint32_t n) {
    uint64_t h = 0x9E3779B97F4A7C15ull ^ n;
    for (uint32_t i = 0; i < n; i++) {
        h ^= w[i];
        h *= 0xBF58476D1CE4E5B9ull;
        h ^= h >> 31;
    }
    return h;
}

/* An open-addressing set of word sequences stored in a growable array (the
 * scene's geometry, or one model's attribute payloads): entries are start
 * indices, a sequence's length is len_of(ctx, data, start). */
typedef uint32_t (*len_fn)(const void* ctx, const uint32_t* data, uint32_t start);
typedef struct wordset {
    uint32_t* tab; /* UINT32_MAX: empty */
    size_t cap, n; /* cap a power of two */
    len_fn len_of;
    const void* ctx;
} wordset;


static vx_result set_grow(const vx_allocator* a, wordset* s, const uint32_t* data, vx_error* err) {
    size_t cap = s->cap ? s->cap * 2 : 1024;
    uint32_t* t = vx_calloc(a, cap, 4);
    if (!t) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for a %zu-entry hash table", cap);
    memset(t, 0xFF, cap * 4);
    for (size_t i = 0; i < s->cap; i++) {
        uint32_t e = s->tab[i];
        if (e == UINT32_MAX) continue;
        size_t j = (size_t)hash_words(data + e, s->len_of(s->ctx, data, e)) & (cap - 1);
        while (t[j] != UINT32_MAX) j = (j + 1) & (cap - 1);
        t[j] = e;
    }
    vx_free(a, s->tab);
    s->tab = t;
    s->cap = cap;
    return VX_OK;
}

/* Finds w[0..n) in the set over *data, or appends it to *data (growing it)
 * and inserts it; *at gets its start, *found whether it was there. */
static vx_result set_intern(const vx_allocator* a, wordset* s, uint32_t** data, size_t* cap, uint32_t* used,
                            const uint32_t* w, uint32_t n, uint32_t limit, uint32_t* at, bool* found,
                            vx_error* err) {
    vx_result r;
    if (2 * (s->n + 1) > s->cap && (r = set_grow(a, s, *data, err))) return r;
    uint64_t h = hash_words(w, n);
    size_t j = (size_t)h & (s->cap - 1);
    for (; s->tab[j] != UINT32_MAX; j = (j + 1) & (s->cap - 1)) {
        const uint32_t* e = *data + s->tab[j];
        if (s->len_of(s->ctx, *data, s->tab[j]) == n && !memcmp(e, w, (size_t)n * 4)) {
            *at = s->tab[j];
            *found = true;
            return VX_OK;
        }
    }
    if (n > limit || *used > limit - n)
        return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "compact layout: more than %u words", limit);
    if (!vx_grow(a, (void**)data, cap, (size_t)*used + n, 4))
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %u words", *used + n);
    memcpy(*data + *used, w, (size_t)n * 4);
    s->tab[j] = *used;
    s->n++;
    *at = *used;
    *used += n;
    *found = false;
    return VX_OK;
}

typedef struct builder {
    const vx_allocator* a;
    vx_error* err;
    uint32_t* slot;  /* 2 words per slot */
    uint32_t* rank;  /* one per slot */
    uint16_t* meta;  /* at a block's first slot: its length | level << 4 */
    size_t slot_cap, rank_cap, meta_cap;
    uint32_t n;      /* slots used */
    uint32_t* tab;   /* open addressing over block starts, UINT32_MAX: empty */
    size_t tab_cap, tab_n;
    /* per model: a source descriptor's slot words, cells and level (0: not built) */
    uint32_t* memo;
    uint32_t* memo_count;
    uint8_t* memo_level;
    vx_compact_stats* st;
    /* the brick dictionary: distinct 64-bit masks, found by an open-addressing table of their ids */
    uint64_t* dict;
    size_t dict_cap;
    uint32_t dict_n;
    uint32_t* dtab; /* UINT32_MAX: empty */
    size_t dtab_cap;
    uint32_t max_bricks;
    bool use_dict; /* VX_COMPACT_BRICKS_DICT */
} builder;

static uint64_t mask_hash(uint64_t m) {
    m ^= m >> 33;
    m *= 0xFF51AFD7ED558CCDull;
    m ^= m >> 29;
    return m;
}

/* The dictionary id of brick mask m, found or appended. */
static vx_result dict_intern(builder* b, uint64_t m, uint32_t* id) {
    if (2 * ((size_t)b->dict_n + 1) > b->dtab_cap) {
        size_t cap = b->dtab_cap ? b->dtab_cap * 2 : 1024;
        uint32_t* t = vx_alloc(b->a, cap * 4);
        if (!t) return vx_fail(b->err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for a %zu-entry hash table", cap);
        memset(t, 0xFF, cap * 4);
        for (uint32_t i = 0; i < b->dict_n; i++) {
            size_t j = (size_t)mask_hash(b->dict[i]) & (cap - 1);
            while (t[j] != UINT32_MAX) j = (j + 1) & (cap - 1);
            t[j] = i;
        }
        vx_free(b->a, b->dtab);
        b->dtab = t;
        b->dtab_cap = cap;
    }
    size_t j = (size_t)mask_hash(m) & (b->dtab_cap - 1);
    for (; b->dtab[j] != UINT32_MAX; j = (j + 1) & (b->dtab_cap - 1))
        if (b->dict[b->dtab[j]] == m) {
            *id = b->dtab[j];
            return VX_OK;
        }
    if (b->dict_n >= b->max_bricks)
        return vx_fail(b->err, VX_ERR_LIMIT, VX_NO_OFFSET, "compact layout: more than %u distinct bricks",
                       b->max_bricks);
    if (!vx_grow(b->a, (void**)&b->dict, &b->dict_cap, (size_t)b->dict_n + 1, 8))
        return vx_fail(b->err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %u bricks", b->dict_n + 1);
    b->dict[b->dict_n] = m;
    b->dtab[j] = b->dict_n;
    *id = b->dict_n++;
    return VX_OK;
}

static uint64_t block_hash(const uint32_t* w, uint32_t k, uint32_t level) {
    return hash_words(w, 2 * k) ^ ((uint64_t)level * 0xD6E8FEB86659FD93ull);
}

/* The block of k slots w (children of one node, level `level`, ranks rk)
 * in the geometry, found or appended; *at its first slot. Blocks are keyed by
 * level too: the same words at another level have other cell counts. */
static vx_result block_intern_h(builder* b, const uint32_t* w, const uint32_t* rk, uint32_t k, uint32_t level,
                                uint64_t hash, uint32_t* at) {
    if (2 * (b->tab_n + 1) > b->tab_cap) {
        size_t cap = b->tab_cap ? b->tab_cap * 2 : 1024;
        uint32_t* t = vx_calloc(b->a, cap, 4);
        if (!t) return vx_fail(b->err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for a %zu-entry hash table", cap);
        memset(t, 0xFF, cap * 4);
        for (size_t i = 0; i < b->tab_cap; i++) {
            uint32_t e = b->tab[i];
            if (e == UINT32_MAX) continue;
            size_t j = (size_t)block_hash(b->slot + 2 * (size_t)e, b->meta[e] & 15u, b->meta[e] >> 4) & (cap - 1);
            while (t[j] != UINT32_MAX) j = (j + 1) & (cap - 1);
            t[j] = e;
        }
        vx_free(b->a, b->tab);
        b->tab = t;
        b->tab_cap = cap;
    }
    uint16_t key = (uint16_t)(k | level << 4);
    size_t j = (size_t)hash & (b->tab_cap - 1);
    for (; b->tab[j] != UINT32_MAX; j = (j + 1) & (b->tab_cap - 1)) {
        uint32_t e = b->tab[j];
        if (b->meta[e] == key && !memcmp(b->slot + 2 * (size_t)e, w, (size_t)k * 8)) {
            *at = e;
            return VX_OK;
        }
    }
    if (b->n > VX_COMPACT_MAX_SLOTS - k)
        return vx_fail(b->err, VX_ERR_LIMIT, VX_NO_OFFSET, "compact layout: more than %u geometry slots",
                       VX_COMPACT_MAX_SLOTS);
    size_t need = (size_t)b->n + k;
    if (!vx_grow(b->a, (void**)&b->slot, &b->slot_cap, 2 * need, 4) ||
        !vx_grow(b->a, (void**)&b->rank, &b->rank_cap, need, 4) ||
        !vx_grow(b->a, (void**)&b->meta, &b->meta_cap, need, 2))
        return vx_fail(b->err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %zu geometry slots", need);
    memcpy(b->slot + 2 * (size_t)b->n, w, (size_t)k * 8);
    memcpy(b->rank + b->n, rk, (size_t)k * 4);
    memset(b->meta + b->n, 0, (size_t)k * 2);
    b->meta[b->n] = key;
    b->tab[j] = b->n;
    b->tab_n++;
    *at = b->n;
    b->n += k;
    b->st->nodes += k;
    b->st->level_slots[level] += k;
    b->st->level_blocks[level]++;
    return VX_OK;
}
static vx_result block_intern(builder* b, const uint32_t* w, const uint32_t* rk, uint32_t k, uint32_t level,
                              uint32_t* at) {
    return block_intern_h(b, w, rk, k, level, block_hash(w, k, level), at);
}

/* The slot words (*x, *y) of source descriptor w at level L (its children are
 * cubes of 2^(L-1) cells) and the cells below it. Level 1 or 2: the 64-bit
 * mask of its cells by Morton code (a level-2 node and its level-1 children
 * in one slot). Level >= 3: the trace descriptor and its children's block. */
static vx_result build_node(builder* b, const vx_svo_model* m, uint32_t w, uint32_t L, uint32_t* x, uint32_t* y,
                            uint64_t* out_count) {
    if (b->memo_level[w] == L) {
        *x = b->memo[2 * (size_t)w], *y = b->memo[2 * (size_t)w + 1];
        *out_count = b->memo_count[w];
        return VX_OK;
    }
    if (L < 1 || L > VX_SVO_MAX_DEPTH)
        return vx_fail(b->err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "descriptor %u at level %u", w, L);
    uint32_t d = m->nodes[w], valid = vx_svo_desc_valid(d), leaf = vx_svo_desc_leaf(d), p = vx_svo_desc_ptr(d);
    uint32_t inner = valid & ~leaf;
    uint32_t block = 0;
    if (inner) {
        if (p < 1 || p > w) return vx_fail(b->err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "descriptor %u: pointer %u", w, p);
        block = vx_svo_desc_far(d) ? m->nodes[w - p] : w - p;
        if (block >= w || popc(inner) > w - block)
            return vx_fail(b->err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "descriptor %u: children at %u", w, block);
        if (L == 1) return vx_fail(b->err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "descriptor %u: children below cells", w);
    }
    uint64_t total = 0;
    if (L <= 2) {
        uint64_t mask = 0;
        for (uint32_t o = 0, k = 0; o < 8; o++) {
            if (!((valid >> o) & 1u)) continue;
            uint64_t child = L == 1 || ((leaf >> o) & 1u) ? 0xFFu : vx_svo_desc_valid(m->nodes[block + k++]);
            mask |= L == 1 ? 1ull << o : child << (8 * o);
        }
        *x = (uint32_t)mask, *y = (uint32_t)(mask >> 32);
        total = (uint64_t)__builtin_popcountll(mask);
    } else {
        uint32_t words[16], ranks[8], np = 0;
        uint64_t cube = 1ull << (3 * (L - 1)), inner_cells = 0;
        for (uint32_t o = 0; o < 8; o++) {
            if (!((valid >> o) & 1u)) continue;
            if ((leaf >> o) & 1u) {
                total += cube;
                continue;
            }
            uint64_t cnt = 0;
            vx_result r = build_node(b, m, block + np, L - 1, &words[2 * np], &words[2 * np + 1], &cnt);
            if (r) return r;
            if (inner_cells > UINT32_MAX) break; /* reported below */
            inner_cells += cnt;
            total += cnt;
            ranks[np++] = (uint32_t)inner_cells;
        }
        if (total > UINT32_MAX)
            return vx_fail(b->err, VX_ERR_LIMIT, VX_NO_OFFSET,
                           "compact layout: a subtree of %llu cells (attribute indices have 32 bits)",
                           (unsigned long long)total);
        uint32_t at = 0;
        /* the children's block (compact.h): levels 3-4 carry the cells up to
         * them in word 0; with the dictionary, bricks become their index
         * words with that count */
        bool index_words = L == 3 && b->use_dict;
        for (uint32_t j = 0; j < np && L - 1 <= 4; j++) {
            if (L - 1 >= 3) {
                words[2 * j] |= ranks[j] << 16;
                continue;
            }
            if (!index_words) break;
            uint32_t before = j ? ranks[j - 1] : 0, id;
            if (ranks[j] == before)
                return vx_fail(b->err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "descriptor %u: an empty brick", w);
            vx_result r = dict_intern(b, words[2 * j] | (uint64_t)words[2 * j + 1] << 32, &id);
            if (r) return r;
            words[2 * j] = id | (ranks[j] - 1u) << VX_COMPACT_BRICK_BITS, words[2 * j + 1] = 0;
        }
        if (np) {
            vx_result r = block_intern(b, words, ranks, np, L - 1, &at);
            if (r) return r;
        }
        *x = (valid << 8) | leaf | (index_words && np ? VX_COMPACT_INDEXED : 0u), *y = at;
    }
    b->memo[2 * (size_t)w] = *x, b->memo[2 * (size_t)w + 1] = *y;
    b->memo_count[w] = (uint32_t)total;
    b->memo_level[w] = (uint8_t)L;
    *out_count = total;
    return VX_OK;
}

/* ---- attributes ---------------------------------------------------------------------- */

typedef struct attr_enc {
    const vx_allocator* a;
    vx_error* err;
    vx_compact_stats* st;
    const vx_svo_model* m;
    uint32_t kind, B, width;
    uint32_t* vals; /* B values of the current block */
    uint32_t n;
    uint32_t* hdr; /* block headers of the model */
    uint32_t nblocks, next_block;
    uint32_t* data; /* payloads (offsets from the region start = nblocks + index) */
    size_t data_cap;
    uint32_t data_n;
    wordset payloads;
    uint32_t* lens;  /* payload length by data index, for the payload set */
    size_t lens_cap;
    uint32_t* scratch; /* one payload being made */
    uint32_t* dkey;    /* distinct-value hash (2B slots), valid where dstamp == stamp */
    uint32_t* didx;
    uint32_t* dstamp;
    uint32_t stamp;
    vx_result fail;
    uint64_t cells;
} attr_enc;

/* payload lengths by start (a payload's code alone does not give it) */
static uint32_t payload_len_of(const void* ctx, const uint32_t* data, uint32_t start) {
    (void)data;
    return (*(uint32_t* const*)ctx)[start];
}

/* RGBA8 -> (R - G + 128, G, B - G + 128, A) mod 256 when dec (exact: recorrelate undoes it) */
static uint32_t decorrelate(uint32_t v, uint32_t dec) {
    if (!dec) return v;
    uint32_t r = v & 0xFFu, g = (v >> 8) & 0xFFu, b = (v >> 16) & 0xFFu;
    return (v & 0xFF00FF00u) | ((r - g + 128) & 0xFFu) | (((b - g + 128) & 0xFFu) << 16);
}
static uint32_t recorrelate(uint32_t v, uint32_t dec) {
    if (!dec) return v;
    uint32_t r = v & 0xFFu, g = (v >> 8) & 0xFFu, b = (v >> 16) & 0xFFu;
    return (v & 0xFF00FF00u) | ((r + g - 128) & 0xFFu) | (((b + g - 128) & 0xFFu) << 16);
}

static uint32_t ceil_log2(uint32_t k) {
    uint32_t b = 0;
    while ((1u << b) < k) b++;
    return b;
}

static vx_result flush_block(attr_enc* e) {
    uint32_t B = e->B, width = e->width, k = 0;
    if (++e->stamp == 0) {
        memset(e->dstamp, 0, (size_t)2 * B * 4);
        e->stamp = 1;
    }
    uint32_t* pal = e->scratch + 2 * B; /* distinct values in order of appearance */
    uint32_t* idx = e->scratch + 3 * B;
    for (uint32_t i = 0; i < e->n; i++) {
        uint32_t v = e->vals[i];
        size_t j = (size_t)((v * 0x9E3779B1u) >> 7) & (2 * B - 1);
        while (e->dstamp[j] == e->stamp && e->dkey[j] != v) j = (j + 1) & (2 * B - 1);
        if (e->dstamp[j] != e->stamp) {
            e->dstamp[j] = e->stamp;
            e->dkey[j] = v;
            e->didx[j] = k;
            pal[k++] = v;
        }
        idx[i] = e->didx[j];
    }
    uint32_t bits = ceil_log2(k), iw = (uint32_t)(((uint64_t)B * bits + 31) / 32), pw = (k * width + 31) / 32;
    uint32_t raw_words = (e->n * width + 31) / 32, code, len;
    /* deltas (RGBA only): each channel's minimum and the residuals' bit
     * widths, of the colours as they are or decorrelated (R - G, G, B - G: a
     * texture's shading moves the three together), whichever is smaller */
    uint32_t lo = 0, wsum = UINT32_MAX, wcode = 0, delta_words = UINT32_MAX;
    for (uint32_t dec = 0; width == 32 && bits && dec < 2; dec++) {
        uint32_t l = 0, ws = 0, wc = dec << 16;
        for (uint32_t c = 0; c < 4; c++) {
            uint32_t mn = 255, mx = 0;
            for (uint32_t i = 0; i < k; i++) {
                uint32_t v = (decorrelate(pal[i], dec) >> (8 * c)) & 0xFFu;
                mn = v < mn ? v : mn;
                mx = v > mx ? v : mx;
            }
            uint32_t w = ceil_log2(mx - mn + 1);
            l |= mn << (8 * c);
            wc |= w << (4 * c);
            ws += w;
        }
        if (ws < wsum) lo = l, wsum = ws, wcode = wc;
    }
    if (wsum != UINT32_MAX) delta_words = 2 + (uint32_t)(((uint64_t)B * wsum + 31) / 32);
    uint32_t* out = e->scratch;
    memset(out, 0, (size_t)2 * B * 4);
    if (bits && delta_words < iw + pw && delta_words < raw_words) {
        code = VX_COMPACT_DELTA;
        len = delta_words;
        out[0] = lo;
        out[1] = wcode;
        for (uint32_t i = 0; i < e->n; i++) {
            uint64_t pos = (uint64_t)i * wsum;
            for (uint32_t c = 0; c < 4; c++) {
                uint32_t w = (wcode >> (4 * c)) & 15u;
                uint32_t v = (decorrelate(e->vals[i], wcode >> 16) >> (8 * c)) & 0xFFu;
                if (w) put_bits(out + 2, pos, v - ((lo >> (8 * c)) & 0xFFu), w);
                pos += w;
            }
        }
        e->st->delta++;
    } else if (bits && raw_words <= iw + pw) {
        code = VX_COMPACT_RAW;
        len = raw_words;
        for (uint32_t i = 0; i < e->n; i++) put_bits(out, (uint64_t)i * width, e->vals[i], width);
        e->st->raw++;
    } else {
        code = bits;
        len = iw + pw;
        for (uint32_t i = 0; bits && i < e->n; i++) put_bits(out, (uint64_t)i * bits, idx[i], bits);
        for (uint32_t i = 0; i < k; i++) put_bits(out + iw, (uint64_t)i * width, pal[i], width);
        e->st->uniform += k == 1;
    }
    e->st->blocks++;
    e->st->distinct_sum += k;
    /* the payload set reads lengths by data index: reserve this one's slot first */
    if (!vx_grow(e->a, (void**)&e->lens, &e->lens_cap, (size_t)e->data_n + len, 4))
        return vx_fail(e->err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for attribute payloads");
    e->lens[e->data_n] = len;
    uint32_t at = 0;
    bool found = false;
    vx_result r = set_intern(e->a, &e->payloads, &e->data, &e->data_cap, &e->data_n, out, len, ATTR_OFF_MAX - 1,
                             &at, &found, e->err);
    if (r) return r;
    e->st->shared += found;
    e->hdr[e->next_block++] = (at << 5) | code; /* made relative to the region when it is laid out */
    e->n = 0;
    return VX_OK;
}

static bool enc_value(attr_enc* e, uint32_t v) {
    e->vals[e->n++] = v;
    e->cells++;
    if (e->n == e->B && (e->fail = flush_block(e))) return false;
    return true;
}

static bool enc_cell(void* user, uint32_t x, uint32_t y, uint32_t z, uint32_t attr) {
    (void)x, (void)y, (void)z;
    attr_enc* e = user;
    if (attr >= e->m->attr_count) {
        e->fail = vx_fail(e->err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "attribute index %u of %u records", attr,
                          e->m->attr_count);
        return false;
    }
    return enc_value(e, e->kind == VX_COMPACT_ATTR_RGBA ? e->m->rgba[attr] : e->m->palette[attr]);
}

/* Blocks [first, end) of group g, and whether they all have one header. */
static bool group_same(const uint32_t* hdr, uint32_t nblocks, uint32_t g, uint32_t* first, uint32_t* end) {
    *first = g * VX_COMPACT_GROUP;
    *end = nblocks - *first > VX_COMPACT_GROUP ? *first + VX_COMPACT_GROUP : nblocks;
    for (uint32_t i = *first + 1; i < *end; i++)
        if (hdr[i] != hdr[*first]) return false;
    return true;
}

/* Appends model m's attribute region to the scene's array: its cells'
 * values in Morton order, or, with vals, cm->voxels values given (a page's,
 * render/compact_page.c; m is then unused). */
static vx_result build_attrs(const vx_compact_desc* d, uint32_t B, const vx_svo_model* m, const uint32_t* vals,
                             vx_compact_model* cm, vx_compact_scene* c, size_t* attr_cap, vx_error* err) {
    cm->block = B;
    attr_enc e = {.a = d->alloc, .err = err, .st = &c->stats, .m = m, .kind = cm->attr_kind, .B = B,
                  .width = cm->attr_kind == VX_COMPACT_ATTR_PALETTE ? 8 : 32};
    e.payloads.len_of = payload_len_of;
    e.payloads.ctx = &e.lens; /* lens moves as it grows */
    e.nblocks = (uint32_t)(((uint64_t)cm->voxels + B - 1) / B);
    e.vals = vx_calloc(e.a, B, 4);
    e.scratch = vx_calloc(e.a, 4 * (size_t)B, 4);
    e.dkey = vx_calloc(e.a, 2 * (size_t)B, 4);
    e.didx = vx_calloc(e.a, 2 * (size_t)B, 4);
    e.dstamp = vx_calloc(e.a, 2 * (size_t)B, 4);
    e.hdr = vx_calloc(e.a, e.nblocks ? e.nblocks : 1, 4);
    vx_result r = VX_OK;
    if (!e.vals || !e.scratch || !e.dkey || !e.didx || !e.dstamp || !e.hdr) {
        r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %u attribute blocks", e.nblocks);
        goto done;
    }
    if (e.nblocks >= ATTR_OFF_MAX) {
        r = vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "compact layout: %u attribute blocks (at most %u)", e.nblocks,
                    ATTR_OFF_MAX - 1);
        goto done;
    }
    if (vals) {
        for (uint32_t i = 0; i < cm->voxels && enc_value(&e, vals[i]); i++) {}
    } else {
        r = vx_svo_decode_model(m, enc_cell, &e, err);
    }
    if (!r) r = e.fail;
    if (!r && e.n) r = flush_block(&e);
    if (r) goto done;
    if (e.cells != cm->voxels || e.next_block != e.nblocks) {
        r = vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "model decodes to %llu cells, its tree counts %u",
                    (unsigned long long)e.cells, cm->voxels);
        goto done;
    }
    /* groups of VX_COMPACT_GROUP blocks with one header word stand for all of it */
    uint32_t ngroups = (e.nblocks + VX_COMPACT_GROUP - 1) / VX_COMPACT_GROUP, nh = 0;
    for (uint32_t g = 0; g < ngroups; g++) {
        uint32_t first, end;
        bool same = group_same(e.hdr, e.nblocks, g, &first, &end);
        nh += same ? 1 : end - first;
        c->stats.uniform_groups += same;
    }
    uint64_t words = (uint64_t)ngroups + nh + e.data_n;
    if (words >= ATTR_OFF_MAX) {
        r = vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET,
                    "compact layout: a model's attributes need %llu words (at most %u)",
                    (unsigned long long)words, ATTR_OFF_MAX - 1);
        goto done;
    }
    if (words > UINT32_MAX - (uint64_t)c->attr_words) {
        r = vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "compact layout: more than 2^32 attribute words");
        goto done;
    }
    if (!vx_grow(d->alloc, (void**)&c->attr, attr_cap, (size_t)(c->attr_words + words), 4)) {
        r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %llu attribute words",
                    (unsigned long long)words);
        goto done;
    }
    cm->attr_base = c->attr_words;
    cm->attr_words = (uint32_t)words;
    uint32_t* region = c->attr + c->attr_words;
    uint32_t shift = (ngroups + nh) << 5; /* payloads follow the groups and the headers */
    for (uint32_t g = 0, h = ngroups; g < ngroups; g++) {
        uint32_t first, end;
        bool same = group_same(e.hdr, e.nblocks, g, &first, &end);
        region[g] = h | (same ? 1u << 31 : 0);
        for (uint32_t i = first; i < (same ? first + 1 : end); i++) region[h++] = e.hdr[i] + shift;
    }
    if (e.data_n) memcpy(region + ngroups + nh, e.data, (size_t)e.data_n * 4);
    c->attr_words += (uint32_t)words;
done:
    vx_free(e.a, e.vals);
    vx_free(e.a, e.scratch);
    vx_free(e.a, e.dkey);
    vx_free(e.a, e.didx);
    vx_free(e.a, e.dstamp);
    vx_free(e.a, e.hdr);
    vx_free(e.a, e.data);
    vx_free(e.a, e.lens);
    vx_free(e.a, e.payloads.tab);
    return r;
}

/* ---- scene --------------------------------------------------------------------------- */

vx_compact_desc vx_compact_desc_defaults(void) { return (vx_compact_desc){.block = 0, .max_bricks = VX_COMPACT_MAX_BRICKS}; }

/* The automatic block size: VX_COMPACT_BLOCK, or VX_COMPACT_BLOCK_UNIFORM
 * where at least half of the blocks of 64 hold one value and the larger
 * blocks take fewer words (a terrain whose colour changes every 8^3 tile pays
 * a header per 64 cells otherwise). */
static vx_result build_attrs_auto(const vx_compact_desc* d, const vx_svo_model* m, vx_compact_model* cm,
                                  vx_compact_scene* c, size_t* attr_cap, vx_error* err) {
    if (d->block) return build_attrs(d, d->block, m, NULL, cm, c, attr_cap, err);
    vx_compact_stats st0 = c->stats;
    uint32_t w0 = c->attr_words;
    vx_result r = build_attrs(d, VX_COMPACT_BLOCK, m, NULL, cm, c, attr_cap, err);
    if (r || 2 * (c->stats.uniform - st0.uniform) < c->stats.blocks - st0.blocks) return r;
    uint32_t w64 = c->attr_words - w0;
    c->stats = st0;
    c->attr_words = w0;
    if ((r = build_attrs(d, VX_COMPACT_BLOCK_UNIFORM, m, NULL, cm, c, attr_cap, err))) return r;
    if (c->attr_words - w0 < w64) return VX_OK;
    c->stats = st0;
    c->attr_words = w0;
    return build_attrs(d, VX_COMPACT_BLOCK, m, NULL, cm, c, attr_cap, err);
}

/* The attribute regions of the models, built apart on several threads
 * (each model's region depends on that model alone) and appended in model
 * order: the bytes of one thread. A large scene's colours were most of the
 * build's time on one thread (DamagedHelmet at 32768^3: 1,244 models;
 * docs/PERFORMANCE.md issue 18, "the helmet at 32768^3 on one H200"). */
typedef struct attr_jobs {
    const vx_compact_desc* d;
    const vx_svo_scene* s;
    vx_compact_scene* c;
    vx_compact_scene* part; /* per model: its region alone (attr, attr_words, stats) */
    vx_result* res;
    vx_error* errs;
} attr_jobs;

static void attr_job(void* ctx, unsigned thread, uint32_t i) {
    (void)thread;
    attr_jobs* j = ctx;
    vx_compact_model* cm = &j->c->models[i];
    if (cm->attr_kind == VX_COMPACT_ATTR_NONE || !cm->voxels) return;
    size_t cap = 0;
    j->part[i].alloc = j->c->alloc;
    j->res[i] = build_attrs_auto(j->d, &j->s->models[i], cm, &j->part[i], &cap, &j->errs[i]);
}

/* Threads for the attributes of a scene of `cells` cells in n models: one
 * where small (the allocation order stays that of one thread), else one
 * per CPU (at most VX_MAX_THREADS). */
static unsigned attr_threads(uint64_t cells, uint32_t n) {
    if (n < 2 || cells < ((uint64_t)1 << 22)) return 1;
    unsigned t = vx_cpu_count(VX_MAX_THREADS);
    return t < n ? t : n;
}

/* The models' attribute regions (j->part, built apart) given their bases in
 * model order, moved into c's per-model regions or copied into its one
 * array; the first failure in model order is the error. */
static vx_result place_attrs(const vx_compact_desc* d, vx_compact_scene* c, attr_jobs* jp, vx_error* err) {
    attr_jobs j = *jp;
    uint32_t n = c->model_count;
    vx_result r = VX_OK;
    uint64_t total = 0;
    for (uint32_t i = 0; i < n && !r; i++) {
        if (j.res[i]) {
            r = j.res[i];
            if (err) *err = j.errs[i];
        }
        total += j.part[i].attr_words;
    }
    if (!r && total > UINT32_MAX)
        r = vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "compact layout: %llu attribute words (more than 2^32 - 1)",
                    (unsigned long long)total);
    if (!r && total && d->attr_regions && !(c->attr_region = vx_calloc(d->alloc, n, sizeof *c->attr_region)))
        r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %u models' attributes", n);
    if (!r && total && !d->attr_regions && !(c->attr = vx_alloc(d->alloc, (size_t)total * 4)))
        r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %llu attribute words",
                    (unsigned long long)total);
    for (uint32_t i = 0; i < n && !r; i++) {
        vx_compact_scene* p = &j.part[i];
        vx_compact_model* cm = &c->models[i];
        if (cm->attr_kind == VX_COMPACT_ATTR_NONE || !cm->voxels) continue;
        cm->attr_base = c->attr_words;
        if (c->attr_region) { /* the region as it was built (its capacity's unwritten tail is not resident) */
            c->attr_region[i] = p->attr;
            p->attr = NULL;
        } else if (p->attr_words) {
            memcpy(c->attr + c->attr_words, p->attr, (size_t)p->attr_words * 4);
        }
        c->attr_words += p->attr_words;
        vx_compact_stats* st = &c->stats;
        st->blocks += p->stats.blocks, st->uniform += p->stats.uniform, st->raw += p->stats.raw;
        st->delta += p->stats.delta, st->uniform_groups += p->stats.uniform_groups, st->shared += p->stats.shared;
        st->distinct_sum += p->stats.distinct_sum;
    }
    return r;
}

/* desc->attrs_from: its attribute regions moved into c (whose geometry was
 * just built from the same models), after checking that every model's kind
 * and cells agree, so nothing moves unless all of it can. */
static vx_result take_attrs(vx_compact_scene* c, vx_compact_scene* from, vx_error* err) {
    uint32_t n = c->model_count;
    if (from->model_count != n || (from->attr_words && !from->attr_region) || from->attr)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET,
                       "compact layout: attrs_from is not a layout of these %u models with its attributes in regions", n);
    if (memcmp(&c->alloc, &from->alloc, sizeof c->alloc) != 0) /* the regions are freed with the new owner's */
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "compact layout: attrs_from has another allocator");
    for (uint32_t i = 0; i < n; i++) {
        const vx_compact_model *a = &c->models[i], *b = &from->models[i];
        bool has = a->attr_kind != VX_COMPACT_ATTR_NONE && a->voxels;
        if (a->attr_kind != b->attr_kind || (has && a->voxels != b->voxels) ||
            (has && (!b->attr_words || !from->attr_region || !from->attr_region[i]))) /* none left (moved before) */
            return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET,
                           "compact layout: attrs_from's model %u (kind %u, %u cells) is not this one's (kind %u, %u cells)",
                           i, b->attr_kind, b->voxels, a->attr_kind, a->voxels);
    }
    if (from->attr_words && !(c->attr_region = vx_calloc(&c->alloc, n ? n : 1, sizeof *c->attr_region)))
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %u models' attributes", n);
    for (uint32_t i = 0; i < n; i++) {
        vx_compact_model *a = &c->models[i], *b = &from->models[i];
        a->attr_base = b->attr_base, a->attr_words = b->attr_words, a->block = b->block;
        if (c->attr_region) c->attr_region[i] = from->attr_region[i];
        if (from->attr_region) from->attr_region[i] = NULL;
        b->attr_words = 0;
    }
    c->attr_words = from->attr_words;
    from->attr_words = 0;
    vx_free(&from->alloc, from->attr_region); /* its pointers moved */
    from->attr_region = NULL;
    vx_compact_stats *st = &c->stats, *fs = &from->stats;
    st->blocks = fs->blocks, st->uniform = fs->uniform, st->raw = fs->raw, st->delta = fs->delta;
    st->uniform_groups = fs->uniform_groups, st->shared = fs->shared, st->distinct_sum = fs->distinct_sum;
    return VX_OK;
}

vx_result vx_compact_move_attrs(vx_compact_scene* to, vx_compact_scene* from, vx_error* err) {
    if (!to || !from || to == from) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    if (to->attr_region || to->attr || to->attr_words)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "compact layout: the layout has attributes of its own");
    return take_attrs(to, from, err);
}

static vx_result build_all_attrs(const vx_compact_desc* d, const vx_svo_scene* s, vx_compact_scene* c,
                                 vx_error* err) {
    uint32_t n = c->model_count;
    uint64_t cells = 0;
    for (uint32_t i = 0; i < n; i++) cells += c->models[i].attr_kind != VX_COMPACT_ATTR_NONE ? c->models[i].voxels : 0;
    if (!cells) return VX_OK;
    attr_jobs j = {.d = d, .s = s, .c = c};
    j.part = vx_calloc(d->alloc, n, sizeof *j.part);
    j.res = vx_calloc(d->alloc, n, sizeof *j.res);
    j.errs = vx_calloc(d->alloc, n, sizeof *j.errs);
    vx_result r = VX_OK;
    if (!j.part || !j.res || !j.errs) {
        r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %u models' attributes", n);
        goto done;
    }
    vx_run_jobs(attr_threads(cells, n), n, attr_job, &j);
    r = place_attrs(d, c, &j, err);
done:
    for (uint32_t i = 0; j.part && i < n; i++) vx_free(d->alloc, j.part[i].attr);
    vx_free(d->alloc, j.part);
    vx_free(d->alloc, j.res);
    vx_free(d->alloc, j.errs);
    return r;
}

/* A build from a model reader (vx_compact_build_reader): the models come
 * from the reader in turn, on whichever build thread is free; each model's
 * attribute region is built beside its geometry while the model is in hand
 * (the attributes depend on the model alone), then the model is freed. So
 * the host holds the layout being built plus the models in hand (one per
 * build thread) and, with several threads, the local DAGs not yet merged. */
typedef struct stream {
    vx_svo_model_reader* rd;
    const vx_allocator* ma; /* the models' (the reader's) allocator */
    const vx_compact_desc* d;
    attr_jobs aj;           /* part, res, errs by model */
    _Atomic uint32_t taken; /* models asked of the reader */
    _Atomic int failed;     /* the reader failed: nothing more is taken */
    pthread_mutex_t lock;
    vx_result r; /* the reader's failure (under lock: the first) */
    vx_error err;
} stream;

/* The next model from the reader into *m, its index in *i; false when none
 * is left or the reader failed (recorded in q). */
static bool stream_take(stream* q, uint32_t n, uint32_t* i, vx_svo_model* m) {
    if (atomic_load(&q->failed) || atomic_fetch_add(&q->taken, 1) >= n) return false;
    vx_error e = {0};
    vx_result r = vx_svo_reader_next(q->rd, i, m, &e);
    if (!r && *i < n) return true;
    if (!r) r = vx_fail(&e, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "compact layout: the model reader had taken models before the build");
    pthread_mutex_lock(&q->lock);
    if (!q->r) q->r = r, q->err = e;
    pthread_mutex_unlock(&q->lock);
    atomic_store(&q->failed, 1);
    return false;
}

/* Model i's attribute region while the model is in hand: cm its geometry's
 * record (kind), cells its cells (as build_all_attrs after the geometry). */
static void stream_attrs(stream* q, const vx_svo_model* m, uint32_t i, vx_compact_model* cm, uint64_t cells) {
    if (cm->attr_kind == VX_COMPACT_ATTR_NONE || !cells || cells > UINT32_MAX) return;
    cm->voxels = (uint32_t)cells;
    if (q->d->attrs_from) return; /* moved from the earlier layout by take_attrs */
    size_t cap = 0;
    q->aj.part[i].alloc = q->aj.c->alloc;
    q->aj.res[i] = build_attrs_auto(q->d, m, cm, &q->aj.part[i], &cap, &q->aj.errs[i]);
}

vx_result vx_compact_join_attrs(vx_compact_scene* c, vx_error* err) {
    if (!c) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    if (!c->attr_region) return VX_OK;
    uint32_t* a = c->attr_words ? vx_alloc(&c->alloc, (size_t)c->attr_words * 4) : NULL;
    if (c->attr_words && !a)
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %u attribute words", c->attr_words);
    for (uint32_t i = 0; i < c->model_count; i++) {
        const vx_compact_model* m = &c->models[i];
        if (c->attr_region[i]) memcpy(a + m->attr_base, c->attr_region[i], (size_t)m->attr_words * 4);
        vx_free(&c->alloc, c->attr_region[i]); /* freed as it goes: the peak is the words once and a region */
    }
    vx_free(&c->alloc, c->attr_region);
    c->attr_region = NULL;
    c->attr = a;
    return VX_OK;
}

void vx_compact_free(vx_compact_scene* c) {
    if (!c) return;
    vx_allocator a = c->alloc;
    vx_free(&a, c->models);
    vx_free(&a, c->geom);
    vx_free(&a, c->attr);
    for (uint32_t i = 0; c->attr_region && i < c->model_count; i++) vx_free(&a, c->attr_region[i]);
    vx_free(&a, c->attr_region);
    memset(c, 0, sizeof *c);
}

/* The geometry array of c from the builder's blocks (compact.h): the brick
 * dictionary, the slots of levels >= 5, those of level 4, of level 3, the bricks in
 * their blocks, the ranks of levels >= 5, then the blocks of brick index
 * words (two builder words each, one here). Pointers to blocks and the
 * models' roots are renumbered. */
static vx_result assemble(builder* b, vx_compact_scene* c, vx_error* err) {
    uint32_t n = b->n, D = b->dict_n;
    uint64_t n5 = 0, n4 = 0, n3 = 0, n2 = 0;
    for (uint32_t e = 0; e < n; e++) {
        if (!b->meta[e]) continue;
        uint32_t len = b->meta[e] & 15u, level = b->meta[e] >> 4;
        if (level >= 5) n5 += len;
        else if (level == 4) n4 += len;
        else if (level == 3) n3 += len;
        else n2 += len;
    }
    uint64_t n34 = n4 + n3;
    uint64_t nbr = b->use_dict ? 0 : n2, ni = b->use_dict ? n2 : 0;
    uint64_t slots = D + n5 + n34 + nbr, words = 2 * slots + n5 + ni;
    words += words & 1u;
    if (slots > VX_COMPACT_MAX_SLOTS || words > UINT32_MAX)
        return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "compact layout: %llu geometry words",
                       (unsigned long long)words);
    c->slot_count = (uint32_t)slots;
    c->brick_count = D;
    c->stats.offset_words = n5;
    c->stats.bricks = D;
    c->stats.brick_refs = n2;
    c->geom_words = (uint32_t)words;
    if (!words) return VX_OK;
    uint32_t* map = vx_calloc(b->a, n ? n : 1, 4);
    uint32_t* g = vx_calloc(b->a, words, 4);
    if (!map || !g) {
        vx_free(b->a, map);
        vx_free(b->a, g);
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %llu geometry words",
                       (unsigned long long)words);
    }
    /* level 4 before level 3: the level-3 slots together, so that their
     * records (vx__compact_level3_records) take 8 bytes each and no more */
    uint32_t at5 = D, at4 = D + (uint32_t)n5, at3 = at4 + (uint32_t)n4;
    uint32_t at2 = b->use_dict ? (uint32_t)(2 * slots + n5) : at4 + (uint32_t)n34;
    for (uint32_t e = 0; e < n;) {
        uint32_t len = b->meta[e] & 15u, level = b->meta[e] >> 4;
        for (uint32_t k = 0; k < len; k++) map[e + k] = level >= 5 ? at5++ : level == 4 ? at4++ : level == 3 ? at3++ : at2++;
        e += len;
    }
    for (uint32_t i = 0; i < D; i++) g[2 * (size_t)i] = (uint32_t)b->dict[i], g[2 * (size_t)i + 1] = (uint32_t)(b->dict[i] >> 32);
    uint32_t* rank = g + 2 * slots - D; /* the rank of slot s (level >= 5) is word 2 slots - D + s */
    for (uint32_t e = 0; e < n;) {
        uint32_t len = b->meta[e] & 15u, level = b->meta[e] >> 4;
        for (uint32_t k = 0; k < len; k++) {
            uint32_t s = map[e + k], x = b->slot[2 * (size_t)(e + k)], y = b->slot[2 * (size_t)(e + k) + 1];
            if (level < 3 && b->use_dict) {
                g[s] = x; /* a brick's index word */
                continue;
            }
            /* a node of level >= 3 with non-leaf children points at their block */
            if (level >= 3 && (((x >> 8) & ~x) & 0xFFu)) y = map[y];
            g[2 * (size_t)s] = x, g[2 * (size_t)s + 1] = y;
            if (level >= 5) rank[s] = b->rank[e + k];
        }
        e += len;
    }
    for (uint32_t i = 0; i < c->model_count; i++)
        if (c->models[i].root < VX_SVO_ROOT_LEAF && (c->models[i].depth >= 3 || !b->use_dict))
            c->models[i].root = map[c->models[i].root];
    vx_free(b->a, map);
    vx_free(b->a, b->slot);
    b->slot = NULL;
    c->geom = g;
    return VX_OK;
}

/* ---- the geometry of the models -------------------------------------------------- */

/* The palette indices model m's attribute records use into c->palette_used
 * (the records vx__scene_attr_material lists by palette index: a model with the palette kind
 * and its array); several build threads at once, hence the atomic or. */
static void note_palette(vx_compact_scene* c, const vx_svo_model* m) {
    if (!m->attrs || !(m->attrs & VX_ATTR_PALETTE) || !m->palette) return;
    uint32_t used[8] = {0};
    for (uint32_t a = 0; a < m->attr_count; a++) used[m->palette[a] >> 5] |= 1u << (m->palette[a] & 31);
    for (int k = 0; k < 8; k++)
        if (used[k]) __atomic_fetch_or(&c->palette_used[k], used[k], __ATOMIC_RELAXED);
}

/* Model i's geometry into builder b: its nodes' blocks interned, cm->root its
 * root's block (or dictionary brick), *cells its cells. */
static vx_result build_model_geom(builder* b, const vx_svo_model* m, uint32_t i, vx_compact_model* cm,
                                  uint64_t* cells, vx_error* err) {
    cm->depth = m->depth;
    cm->root = m->root;
    cm->attr_kind = (m->attrs & VX_ATTR_RGBA8) && m->rgba         ? VX_COMPACT_ATTR_RGBA
                    : (m->attrs & VX_ATTR_PALETTE) && m->palette ? VX_COMPACT_ATTR_PALETTE
                                                                  : VX_COMPACT_ATTR_NONE;
    *cells = 0;
    if (m->root == VX_SVO_ROOT_LEAF) {
        *cells = m->depth > 10 ? UINT64_MAX : 1ull << (3 * m->depth);
        return VX_OK;
    }
    if (m->root == VX_SVO_ROOT_EMPTY) return VX_OK;
    if (m->root >= m->node_count)
        return vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "model %u: root %u of %u words", i, m->root,
                       m->node_count);
    b->memo = vx_calloc(b->a, m->node_count, 8);
    b->memo_count = vx_calloc(b->a, m->node_count, 4);
    b->memo_level = vx_calloc(b->a, m->node_count, 1);
    uint32_t rw[2], zero = 0;
    vx_result r;
    if (!b->memo || !b->memo_count || !b->memo_level)
        r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %u words", m->node_count);
    else
        r = build_node(b, m, m->root, m->depth, &rw[0], &rw[1], cells);
    /* the root: a block of one slot at the model's level */
    if (!r && m->depth <= 2 && b->use_dict) r = dict_intern(b, rw[0] | (uint64_t)rw[1] << 32, &cm->root);
    else if (!r) r = block_intern(b, rw, &zero, 1, m->depth, &cm->root);
    vx_free(b->a, b->memo);
    vx_free(b->a, b->memo_count);
    vx_free(b->a, b->memo_level);
    b->memo = NULL, b->memo_count = NULL, b->memo_level = NULL;
    if (r) vx_error_prefix(err, "compact layout");
    return r;
}

static vx_result model_cells(vx_compact_model* cm, uint64_t cells, uint32_t i, vx_error* err) {
    if (cells > UINT32_MAX) return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "model %u: more than 2^32 - 1 cells", i);
    cm->voxels = (uint32_t)cells;
    return VX_OK;
}

/* Threads for the geometry: one where small (the allocation order, and so
 * the OOM tests, stay those of one thread), else desc->threads or one per
 * CPU, at most the models. */
static unsigned geom_threads(const vx_compact_desc* d, const vx_svo_scene* s) {
    uint64_t words = 0;
    for (uint32_t i = 0; i < s->model_count; i++) words += s->models[i].node_count;
    if (s->model_count < 2 || d->threads == 1 || (!d->threads && words < ((uint64_t)1 << 20))) return 1;
    unsigned t = d->threads ? d->threads : vx_cpu_count(VX_MAX_THREADS);
    if (t > VX_MAX_THREADS) t = VX_MAX_THREADS;
    return t < s->model_count ? t : s->model_count;
}

/* The geometry on several threads. Each model's blocks are built alone, in a
 * builder of its own (its local DAG: blocks in the order one thread would
 * first meet them, pointers to local blocks, bricks by local dictionary
 * ids), then merged into the scene's builder in model order, which interns
 * each local block with its pointers and brick ids made the scene's. That
 * is the order of first appearance of the one-thread build, so the layout
 * is the same bytes: a block new to the scene is appended where one thread
 * would have appended it (its first use in its model, after every earlier
 * model's blocks), and distinct local blocks stay distinct (their words
 * differ, or by induction the blocks they point at). Most of the work (the
 * walk of every node word, the memo, the hashing of repeats within a model)
 * is in the models' own builds; the merge hashes each model's distinct
 * blocks once. Whichever thread finds the next model built merges it (one
 * at a time); builds run at most `window` models ahead of the merge, which
 * bounds the local DAGs held. */
typedef struct geom_local {
    builder b;
    vx_compact_stats st; /* the local builder's (discarded: the merge counts) */
    vx_compact_model cm; /* root: a local block or brick id */
    uint64_t cells;
    vx_result r;
    vx_error err;
} geom_local;

typedef struct geom_jobs {
    const vx_svo_scene* s;
    vx_compact_scene* c;
    builder* g;
    geom_local* loc; /* by model */
    _Atomic uint8_t* built;
    _Atomic uint32_t next;   /* the next model to build */
    _Atomic uint32_t merged; /* models merged */
    _Atomic int merging;     /* a thread is merging */
    _Atomic int stop;        /* a failure: the rest is skipped */
    uint32_t window;
    vx_result r; /* the first failure in model order */
    vx_error* err;
    stream* q; /* the models from a reader, or NULL */
} geom_jobs;

static void local_free(geom_local* l) {
    vx_free(l->b.a, l->b.slot);
    vx_free(l->b.a, l->b.rank);
    vx_free(l->b.a, l->b.meta);
    vx_free(l->b.a, l->b.tab);
    vx_free(l->b.a, l->b.dict);
    vx_free(l->b.a, l->b.dtab);
    memset(&l->b, 0, sizeof l->b);
}

/* The scene's words of local block e (pointers and brick ids remapped):
 * false where a child's block is not merged yet (bmap UINT32_MAX). */
static bool merged_words(const builder* g, const builder* b, const uint32_t* dmap, const uint32_t* bmap, uint32_t e,
                         uint32_t* w) {
    uint32_t len = b->meta[e] & 15u, level = b->meta[e] >> 4;
    for (uint32_t k = 0; k < len; k++) {
        uint32_t x = b->slot[2 * (size_t)(e + k)], y = b->slot[2 * (size_t)(e + k) + 1];
        if (level >= 3 && (((x >> 8) & ~x) & 0xFFu)) { /* its children's block */
            if ((y = bmap[y]) == UINT32_MAX) return false;
        } else if (level == 2 && g->use_dict) { /* a brick index word */
            x = dmap[x & (VX_COMPACT_MAX_BRICKS - 1u)] | (x & ~(VX_COMPACT_MAX_BRICKS - 1u));
        }
        w[2 * k] = x, w[2 * k + 1] = y;
    }
    return true;
}

/* Interns model i's local DAG into the scene's builder g. The scene's
 * table is far larger than the caches, so each probe is a miss and then
 * another for the entry's words: blocks whose words are known ahead (all
 * whose children are merged: the bricks' blocks, most of them) have their
 * table entry prefetched PF blocks ahead and the entry's words PF / 2
 * ahead. */
#ifndef PF
#define PF 16u /* blocks ahead; -DPF=1: no prefetch (bench A/B) */
#endif
/* One slot of merge_model's ring: the block at *ahead (its start in *e),
 * its hash in *h where its words are known now (*known), its table entry
 * prefetched; *ahead moves to the next block. */
static void ring_take(const builder* g, const builder* b, const uint32_t* dmap, const uint32_t* bmap, bool ok,
                      uint32_t* ahead, uint32_t* e, uint64_t* h, bool* known) {
    uint32_t w[16];
    *e = *ahead;
    *known = false;
    if (*ahead >= b->n) return;
    if (ok && merged_words(g, b, dmap, bmap, *ahead, w)) {
        *h = block_hash(w, b->meta[*ahead] & 15u, b->meta[*ahead] >> 4);
        *known = true;
        if (g->tab_cap) __builtin_prefetch(&g->tab[*h & (g->tab_cap - 1)]);
    }
    *ahead += b->meta[*ahead] & 15u;
}

static vx_result merge_model(builder* g, geom_local* l, vx_compact_model* cm, uint32_t i, vx_error* err) {
    builder* b = &l->b;
    *cm = l->cm;
    if (cm->root >= VX_SVO_ROOT_LEAF) return model_cells(cm, l->cells, i, err);
    uint32_t* dmap = vx_alloc(g->a, ((size_t)b->dict_n + 1) * 4);
    uint32_t* bmap = vx_alloc(g->a, ((size_t)b->n + 1) * 4);
    vx_result r = VX_OK;
    if (!dmap || !bmap) r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for model %u's blocks", i);
    for (uint32_t k = 0; !r && k < b->dict_n; k++) r = dict_intern(g, b->dict[k], &dmap[k]);
    if (!r) memset(bmap, 0xFF, ((size_t)b->n + 1) * 4);
    /* a ring of the next blocks: start, hash where known ahead */
    uint32_t ring_e[PF], w[16];
    uint64_t ring_h[PF];
    bool ring_k[PF];
    uint32_t ahead = 0; /* the first block start not yet in the ring */
    for (uint32_t q = 0; q < PF; q++) ring_take(g, b, dmap, bmap, !r, &ahead, &ring_e[q], &ring_h[q], &ring_k[q]);
    for (uint32_t q = 0; !r && ring_e[q % PF] < b->n; q++) {
        uint32_t slot = q % PF, e = ring_e[slot], len = b->meta[e] & 15u, level = b->meta[e] >> 4;
        /* the entry PF / 2 blocks ahead: its table slot is in the cache by now, prefetch its words */
        uint32_t mid = (q + PF / 2) % PF;
        if (ring_k[mid] && g->tab_cap) {
            uint32_t t = g->tab[ring_h[mid] & (g->tab_cap - 1)];
            if (t != UINT32_MAX) {
                __builtin_prefetch(g->slot + 2 * (size_t)t);
                __builtin_prefetch(g->meta + t);
            }
        }
        if (!merged_words(g, b, dmap, bmap, e, w)) {
            r = vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "model %u: a block before its children", i);
            break;
        }
        uint64_t h = ring_k[slot] ? ring_h[slot] : block_hash(w, len, level);
        r = block_intern_h(g, w, b->rank + e, len, level, h, &bmap[e]);
        /* refill the slot with the block PF ahead */
        ring_take(g, b, dmap, bmap, !r, &ahead, &ring_e[slot], &ring_h[slot], &ring_k[slot]);
    }
    if (!r) cm->root = cm->depth <= 2 && g->use_dict ? dmap[cm->root] : bmap[cm->root];
    if (r) vx_error_prefix(err, "compact layout");
    vx_free(g->a, dmap);
    vx_free(g->a, bmap);
    if (!r) r = model_cells(cm, l->cells, i, err);
    return r;
}

/* Merges the models built in order, while this thread holds the merge. */
static void merge_ready(geom_jobs* j) {
    for (;;) {
        int expect = 0;
        if (!atomic_compare_exchange_strong(&j->merging, &expect, 1)) return;
        uint32_t m = atomic_load(&j->merged), n = j->s->model_count;
        while (m < n && atomic_load(&j->built[m]) && !atomic_load(&j->stop)) {
            geom_local* l = &j->loc[m];
            vx_result r = l->r;
            if (r) {
                if (j->err) *j->err = l->err;
            } else {
                double t0 = vx_time_now();
                r = merge_model(j->g, l, &j->c->models[m], m, j->err);
                j->c->stats.geom_merge_seconds += vx_time_now() - t0;
            }
            local_free(l);
            if (r) {
                j->r = r;
                atomic_store(&j->stop, 1);
            }
            atomic_store(&j->merged, ++m);
        }
        atomic_store(&j->merging, 0);
        /* a model built while this thread was finishing is merged by it now */
        if (m >= n || atomic_load(&j->stop) || !atomic_load(&j->built[m])) return;
    }
}

/* geom_worker's build of model i, with the model m in hand. */
static void geom_build_one(geom_jobs* j, uint32_t i, const vx_svo_model* m) {
    geom_local* l = &j->loc[i];
    l->b = (builder){.a = j->g->a, .err = &l->err, .st = &l->st, .max_bricks = j->g->max_bricks,
                     .use_dict = j->g->use_dict};
    l->r = build_model_geom(&l->b, m, i, &l->cm, &l->cells, &l->err);
    note_palette(j->c, m);
    if (j->q && !l->r) stream_attrs(j->q, m, i, &l->cm, l->cells);
    /* the hash tables are not needed by the merge */
    vx_free(l->b.a, l->b.tab);
    vx_free(l->b.a, l->b.dtab);
    l->b.tab = NULL, l->b.dtab = NULL;
    atomic_store(&j->built[i], 1);
}

static void* geom_worker(void* arg) {
    geom_jobs* j = arg;
    uint32_t n = j->s->model_count;
    while (j->q) { /* from a reader: the models in the reader's order, as far ahead of the merge as the window */
        if (atomic_load(&j->stop)) return NULL;
        uint32_t t = atomic_load(&j->q->taken), i;
        if (t >= n) break;
        if (t >= atomic_load(&j->merged) + j->window) {
            merge_ready(j);
            if (t >= atomic_load(&j->merged) + j->window) nanosleep(&(struct timespec){0, 50000}, NULL);
            continue;
        }
        vx_svo_model m;
        if (!stream_take(j->q, n, &i, &m)) {
            if (atomic_load(&j->q->failed)) atomic_store(&j->stop, 1);
            break;
        }
        geom_build_one(j, i, &m);
        vx_svo_model_free(j->q->ma, &m);
        merge_ready(j);
    }
    for (; !j->q;) {
        if (atomic_load(&j->stop)) return NULL;
        uint32_t i = atomic_load(&j->next);
        if (i >= n) break;
        if (i >= atomic_load(&j->merged) + j->window) { /* too far ahead: merge, or wait for the merge */
            merge_ready(j);
            if (i >= atomic_load(&j->merged) + j->window) nanosleep(&(struct timespec){0, 50000}, NULL);
            continue;
        }
        if (!atomic_compare_exchange_weak(&j->next, &i, i + 1)) continue;
        geom_build_one(j, i, &j->s->models[i]);
        merge_ready(j);
    }
    /* nothing left to build: merge until every model is (another thread may be holding the merge) */
    while (atomic_load(&j->merged) < n && !atomic_load(&j->stop)) {
        merge_ready(j);
        if (atomic_load(&j->merged) < n) nanosleep(&(struct timespec){0, 50000}, NULL);
    }
    return NULL;
}

/* ---- the merge on all threads (bricks in their blocks) ------------------------------
 * The merge above runs on one thread at a time and was most of the
 * geometry's time on many threads (DamagedHelmet at 16384^3 on 32 threads:
 * merge 4.2 of 4.5 s). Here every model's local DAG is built first, then:
 *   1. level by level, from the bricks' blocks up, every local block is
 *      interned in one concurrent table under its canonical words (its
 *      children's pointers replaced by their table entries), the entry
 *      keeping the least key (model << 32 | local start, plus one) of the blocks
 *      equal to it: the block the one-thread build appends;
 *   2. the blocks that hold their entry's key are counted per model, the
 *      counts summed in model order, and each such block is placed where
 *      the one-thread build places it (after the earlier models' new
 *      blocks, in its model's local order), its entry then holding that
 *      place; 3. their words are written with the children's places.
 * So the layout is the same bytes (test_compact). Every level's pass and
 * every step runs over the models on all threads. The brick dictionary
 * (its ids also by first appearance) keeps the merge above. */
#define PM_EMPTY 0u /* keys are stored plus one, so that a zeroed table (calloc: untouched pages) is empty */

typedef struct pmerge {
    const vx_svo_scene* s;
    vx_compact_scene* c;
    builder* g;
    geom_local* loc;
    uint32_t** canon;  /* per model: by local block start, its table entry */
    uint8_t** first;   /* per model: by local block start, 1 where it is its entry's first block */
    uint32_t** order;  /* per model: its block starts by level (counting sort), lvl[i][L] the first of level L */
    uint32_t (*lvl)[34];
    _Atomic uint64_t* tab; /* keys, then (step 2 on) places */
    size_t cap;
    uint32_t level;
    uint64_t* count;       /* per model: slots of its first blocks */
    uint64_t* base;        /* per model: the place of its first such slot */
    uint64_t (*lslots)[33], (*lblocks)[33];
    vx_result* res;
    vx_error* errs;
    stream* q; /* the models from a reader, or NULL */
} pmerge;

/* The canonical words of model m's local block e (children as table entries). */
static void pm_words(const pmerge* p, uint32_t m, uint32_t e, uint32_t* w) {
    const builder* b = &p->loc[m].b;
    uint32_t len = b->meta[e] & 15u, level = b->meta[e] >> 4;
    for (uint32_t k = 0; k < len; k++) {
        uint32_t x = b->slot[2 * (size_t)(e + k)], y = b->slot[2 * (size_t)(e + k) + 1];
        if (level >= 3 && (((x >> 8) & ~x) & 0xFFu)) y = p->canon[m][y];
        w[2 * k] = x, w[2 * k + 1] = y;
    }
}

static void pm_level_job(void* ctx, unsigned thread, uint32_t i) {
    (void)thread;
    pmerge* p = ctx;
    const builder* b = &p->loc[i].b;
    uint32_t L = p->level, w[16], v[16];
    for (uint32_t q = p->lvl[i][L]; q < p->lvl[i][L + 1]; q++) {
        uint32_t e = p->order[i][q], len = b->meta[e] & 15u;
        pm_words(p, i, e, w);
        uint64_t key = ((uint64_t)i << 32 | e) + 1;
        size_t j = (size_t)block_hash(w, len, L) & (p->cap - 1);
        for (;;) {
            uint64_t k = atomic_load_explicit(&p->tab[j], memory_order_acquire);
            if (k == PM_EMPTY) {
                if (atomic_compare_exchange_strong(&p->tab[j], &k, key)) break;
                if (k == PM_EMPTY) continue;
            }
            uint32_t m = (uint32_t)((k - 1) >> 32), f = (uint32_t)(k - 1);
            if (p->loc[m].b.meta[f] == b->meta[e]) {
                pm_words(p, m, f, v);
                if (!memcmp(v, w, (size_t)len * 8)) { /* equal: keep the least key */
                    while (key < k && !atomic_compare_exchange_weak(&p->tab[j], &k, key)) {}
                    break;
                }
            }
            j = (j + 1) & (p->cap - 1);
        }
        p->canon[i][e] = (uint32_t)j;
    }
}

/* the order of model i's blocks by level, its canon and first arrays */
static void pm_prep_job(void* ctx, unsigned thread, uint32_t i) {
    (void)thread;
    pmerge* p = ctx;
    const builder* b = &p->loc[i].b;
    const vx_allocator* a = p->g->a;
    uint32_t nb = 0, cnt[34] = {0};
    for (uint32_t e = 0; e < b->n; e += b->meta[e] & 15u) cnt[(b->meta[e] >> 4) + 1]++, nb++;
    p->canon[i] = vx_alloc(a, ((size_t)b->n + 1) * 4);
    p->first[i] = vx_calloc(a, (size_t)b->n + 1, 1);
    p->order[i] = vx_alloc(a, ((size_t)nb + 1) * 4);
    if (!p->canon[i] || !p->first[i] || !p->order[i]) {
        p->res[i] = vx_fail(&p->errs[i], VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for model %u's blocks", i);
        return;
    }
    for (uint32_t L = 1; L < 34; L++) cnt[L] += cnt[L - 1];
    memcpy(p->lvl[i], cnt, sizeof cnt);
    for (uint32_t e = 0; e < b->n; e += b->meta[e] & 15u) p->order[i][cnt[b->meta[e] >> 4]++] = e;
}

/* step 2a: model i's first blocks, counted */
static void pm_count_job(void* ctx, unsigned thread, uint32_t i) {
    (void)thread;
    pmerge* p = ctx;
    const builder* b = &p->loc[i].b;
    uint64_t n = 0;
    for (uint32_t e = 0; e < b->n; e += b->meta[e] & 15u) {
        uint32_t len = b->meta[e] & 15u, level = b->meta[e] >> 4;
        if (atomic_load_explicit(&p->tab[p->canon[i][e]], memory_order_relaxed) != ((uint64_t)i << 32 | e) + 1) continue;
        p->first[i][e] = 1;
        n += len;
        p->lslots[i][level] += len;
        p->lblocks[i][level]++;
    }
    p->count[i] = n;
}

/* step 2b: their places into their entries */
static void pm_place_job(void* ctx, unsigned thread, uint32_t i) {
    (void)thread;
    pmerge* p = ctx;
    const builder* b = &p->loc[i].b;
    uint64_t at = p->base[i];
    for (uint32_t e = 0; e < b->n; e += b->meta[e] & 15u)
        if (p->first[i][e]) {
            atomic_store_explicit(&p->tab[p->canon[i][e]], at, memory_order_relaxed);
            at += b->meta[e] & 15u;
        }
}

/* step 3: their words, ranks and metas at their places; the root's place */
static void pm_write_job(void* ctx, unsigned thread, uint32_t i) {
    (void)thread;
    pmerge* p = ctx;
    const builder* b = &p->loc[i].b;
    builder* g = p->g;
    for (uint32_t e = 0; e < b->n; e += b->meta[e] & 15u) {
        if (!p->first[i][e]) continue;
        uint32_t len = b->meta[e] & 15u, level = b->meta[e] >> 4;
        size_t at = (size_t)atomic_load_explicit(&p->tab[p->canon[i][e]], memory_order_relaxed);
        for (uint32_t k = 0; k < len; k++) {
            uint32_t x = b->slot[2 * (size_t)(e + k)], y = b->slot[2 * (size_t)(e + k) + 1];
            if (level >= 3 && (((x >> 8) & ~x) & 0xFFu))
                y = (uint32_t)atomic_load_explicit(&p->tab[p->canon[i][y]], memory_order_relaxed);
            g->slot[2 * (at + k)] = x, g->slot[2 * (at + k) + 1] = y;
        }
        memcpy(g->rank + at, b->rank + e, (size_t)len * 4);
        memcpy(g->meta + at, b->meta + e, (size_t)len * 2);
    }
    vx_compact_model* cm = &p->c->models[i];
    if (cm->root < VX_SVO_ROOT_LEAF)
        cm->root = (uint32_t)atomic_load_explicit(&p->tab[p->canon[i][cm->root]], memory_order_relaxed);
}

static void pm_build_job(void* ctx, unsigned thread, uint32_t i) {
    (void)thread;
    pmerge* p = ctx;
    vx_svo_model m;
    /* from a reader: whichever model comes next (one per job), its attributes beside */
    if (p->q && !stream_take(p->q, p->s->model_count, &i, &m)) return;
    geom_local* l = &p->loc[i];
    l->b = (builder){.a = p->g->a, .err = &l->err, .st = &l->st, .max_bricks = p->g->max_bricks};
    l->r = build_model_geom(&l->b, p->q ? &m : &p->s->models[i], i, &l->cm, &l->cells, &l->err);
    note_palette(p->c, p->q ? &m : &p->s->models[i]);
    if (p->q && !l->r) stream_attrs(p->q, &m, i, &l->cm, l->cells);
    if (p->q) vx_svo_model_free(p->q->ma, &m);
    vx_free(l->b.a, l->b.tab); /* the local hash table: not needed by the merge */
    l->b.tab = NULL;
}

static vx_result build_geom_all(const vx_compact_desc* d, const vx_svo_scene* s, vx_compact_scene* c, builder* g,
                                unsigned threads, stream* q, vx_error* err) {
    uint32_t n = s->model_count;
    const vx_allocator* a = d->alloc;
    pmerge p = {.s = s, .c = c, .g = g, .q = q};
    p.loc = vx_calloc(a, n, sizeof *p.loc);
    p.canon = vx_calloc(a, n, sizeof *p.canon);
    p.first = vx_calloc(a, n, sizeof *p.first);
    p.order = vx_calloc(a, n, sizeof *p.order);
    p.lvl = vx_calloc(a, n, sizeof *p.lvl);
    p.count = vx_calloc(a, n, sizeof *p.count);
    p.base = vx_calloc(a, n, sizeof *p.base);
    p.lslots = vx_calloc(a, n, sizeof *p.lslots);
    p.lblocks = vx_calloc(a, n, sizeof *p.lblocks);
    p.res = vx_calloc(a, n, sizeof *p.res);
    p.errs = vx_calloc(a, n, sizeof *p.errs);
    vx_result r = VX_OK;
    if (!p.loc || !p.canon || !p.first || !p.order || !p.lvl || !p.count || !p.base || !p.lslots || !p.lblocks ||
        !p.res || !p.errs)
        r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %u models' geometry", n);
    if (!r) vx_run_jobs(threads, n, pm_build_job, &p);
    if (!r && q && q->r) {
        r = q->r;
        if (err) *err = q->err;
    }
    double t_merge = vx_time_now();
    uint64_t blocks = 0;
    uint32_t top = 0;
    for (uint32_t i = 0; !r && i < n; i++) { /* the first failure in model order, as one thread reports it */
        if ((r = p.loc[i].r)) {
            if (err) *err = p.loc[i].err;
            break;
        }
        c->models[i] = p.loc[i].cm;
        if ((r = model_cells(&c->models[i], p.loc[i].cells, i, err))) break;
        for (uint32_t e = 0; e < p.loc[i].b.n; e += p.loc[i].b.meta[e] & 15u) {
            blocks++;
            if ((p.loc[i].b.meta[e] >> 4) > top) top = p.loc[i].b.meta[e] >> 4;
        }
    }
    if (!r) vx_run_jobs(threads, n, pm_prep_job, &p);
    for (uint32_t i = 0; !r && i < n; i++)
        if ((r = p.res[i]) && err) *err = p.errs[i];
    if (!r) {
        p.cap = 1024;
        while (p.cap < 2 * blocks) p.cap *= 2;
        if (p.cap > ((size_t)1 << 32) || !(p.tab = vx_calloc(a, p.cap, sizeof *p.tab)))
            r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for a %zu-entry block table", p.cap);
    }
    if (!r) {
        for (p.level = 1; p.level <= top; p.level++) vx_run_jobs(threads, n, pm_level_job, &p);
        vx_run_jobs(threads, n, pm_count_job, &p);
        uint64_t total = 0;
        for (uint32_t i = 0; i < n; i++) {
            p.base[i] = total;
            total += p.count[i];
            for (uint32_t L = 0; L < 33; L++) {
                c->stats.nodes += p.lslots[i][L];
                c->stats.level_slots[L] += p.lslots[i][L];
                c->stats.level_blocks[L] += p.lblocks[i][L];
            }
        }
        if (total > VX_COMPACT_MAX_SLOTS)
            r = vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "compact layout: more than %u geometry slots",
                        VX_COMPACT_MAX_SLOTS);
        if (!r && (!vx_grow(a, (void**)&g->slot, &g->slot_cap, 2 * (size_t)total + 2, 4) ||
                   !vx_grow(a, (void**)&g->rank, &g->rank_cap, (size_t)total + 1, 4) ||
                   !vx_grow(a, (void**)&g->meta, &g->meta_cap, (size_t)total + 1, 2)))
            r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %llu geometry slots",
                        (unsigned long long)total);
        if (!r) {
            vx_run_jobs(threads, n, pm_place_job, &p);
            vx_run_jobs(threads, n, pm_write_job, &p);
            g->n = (uint32_t)total;
        }
    }
    for (uint32_t i = 0; p.loc && i < n; i++) {
        local_free(&p.loc[i]);
        if (p.canon) vx_free(a, p.canon[i]);
        if (p.first) vx_free(a, p.first[i]);
        if (p.order) vx_free(a, p.order[i]);
    }
    vx_free(a, (void*)p.tab);
    vx_free(a, p.loc), vx_free(a, p.canon), vx_free(a, p.first), vx_free(a, p.order), vx_free(a, p.lvl);
    vx_free(a, p.count), vx_free(a, p.base), vx_free(a, p.lslots), vx_free(a, p.lblocks);
    vx_free(a, p.res), vx_free(a, p.errs);
    c->stats.geom_merge_seconds = vx_time_now() - t_merge;
    return r;
}

static vx_result build_geom_parallel(const vx_compact_desc* d, const vx_svo_scene* s, vx_compact_scene* c, builder* g,
                                     unsigned threads, stream* q, vx_error* err) {
    uint32_t n = s->model_count;
    geom_jobs j = {.s = s, .c = c, .g = g, .window = 2 * threads, .err = err, .q = q};
    j.loc = vx_calloc(d->alloc, n, sizeof *j.loc);
    j.built = vx_calloc(d->alloc, n, sizeof *j.built);
    if (!j.loc || !j.built) {
        vx_free(d->alloc, j.loc);
        vx_free(d->alloc, (void*)j.built);
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %u models' geometry", n);
    }
    vx_run_threads(threads, geom_worker, &j);
    for (uint32_t i = 0; i < n; i++) local_free(&j.loc[i]); /* those built past a failure */
    vx_free(d->alloc, j.loc);
    vx_free(d->alloc, (void*)j.built);
    if (!j.r && q && q->r) { /* the reader's failure (a merge's is reported first) */
        j.r = q->r;
        if (err) *err = q->err;
    }
    return j.r;
}

/* vx_compact_build of s, or with rd, of the reader's models (s its graph). */
static vx_result build_core(const vx_compact_desc* desc_in, const vx_svo_scene* s, vx_svo_model_reader* rd,
                            const vx_allocator* model_alloc, vx_compact_scene* out, vx_error* err) {
    vx_compact_desc d = vx_compact_desc_defaults();
    if (desc_in) {
        d.alloc = desc_in->alloc;
        if (desc_in->block) d.block = desc_in->block;
        if (desc_in->max_bricks && desc_in->max_bricks < VX_COMPACT_MAX_BRICKS) d.max_bricks = desc_in->max_bricks;
        d.bricks = desc_in->bricks;
        d.threads = desc_in->threads;
        d.merge = desc_in->merge;
        d.attr_regions = desc_in->attr_regions;
        d.attrs_from = desc_in->attrs_from;
    }
    if (d.attrs_from && (!rd || !d.attr_regions))
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET,
                       "compact layout: attrs_from is for a build from a model reader with attr_regions");
    if (d.merge > VX_COMPACT_MERGE_ALL)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "compact merge %u: not a VX_COMPACT_MERGE_* value", d.merge);
    if (d.bricks != VX_COMPACT_BRICKS_INLINE && d.bricks != VX_COMPACT_BRICKS_DICT)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "compact bricks %u: not a VX_COMPACT_BRICKS_* value",
                       d.bricks);
    if (d.block && (d.block < 8 || d.block > 1024 || (d.block & (d.block - 1))))
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "compact block %u: not a power of two in 8..1024",
                       d.block);
    vx_compact_scene c = {.model_count = s->model_count};
    if (d.alloc) c.alloc = *d.alloc;
    d.alloc = &c.alloc;
    memcpy(c.palette, s->palette, sizeof c.palette);
    c.palette_used[0] = 1; /* index 0: what a record without a palette index reads */
    builder b = {.a = d.alloc, .err = err, .st = &c.stats, .max_bricks = d.max_bricks,
                 .use_dict = d.bricks == VX_COMPACT_BRICKS_DICT};
    c.brick_dict = b.use_dict;
    vx_result r = VX_OK;
    c.models = vx_calloc(d.alloc, s->model_count ? s->model_count : 1, sizeof *c.models);
    if (!c.models) r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %u models", s->model_count);
    unsigned threads = geom_threads(&d, s);
    double tg = vx_time_now();
    /* the merge on all threads does about twice the one thread's work in all
     * (the canonical words of both blocks at each probe, the passes); with
     * few threads the merge in model order beside the builds is faster */
    bool all = d.merge == VX_COMPACT_MERGE_ALL || (d.merge == VX_COMPACT_MERGE_AUTO && threads >= VX_COMPACT_MERGE_ALL_THREADS);
    stream q = {.rd = rd, .ma = model_alloc, .d = &d, .aj = {.d = &d, .s = s, .c = &c}};
    uint32_t n = s->model_count;
    if (rd) {
        pthread_mutex_init(&q.lock, NULL);
        q.aj.part = vx_calloc(d.alloc, n ? n : 1, sizeof *q.aj.part);
        q.aj.res = vx_calloc(d.alloc, n ? n : 1, sizeof *q.aj.res);
        q.aj.errs = vx_calloc(d.alloc, n ? n : 1, sizeof *q.aj.errs);
        if (!r && (!q.aj.part || !q.aj.res || !q.aj.errs))
            r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %u models' attributes", n);
    }
    if (!r && threads > 1)
        r = b.use_dict || !all ? build_geom_parallel(&d, s, &c, &b, threads, rd ? &q : NULL, err)
                               : build_geom_all(&d, s, &c, &b, threads, rd ? &q : NULL, err);
    for (uint32_t k = 0; !r && threads <= 1 && k < n; k++) {
        uint32_t i = k;
        vx_svo_model m;
        if (rd && !stream_take(&q, n, &i, &m)) {
            r = q.r;
            if (err) *err = q.err;
            break;
        }
        vx_compact_model* cm = &c.models[i];
        uint64_t cells = 0;
        r = build_model_geom(&b, rd ? &m : &s->models[i], i, cm, &cells, err);
        note_palette(&c, rd ? &m : &s->models[i]);
        if (!r) r = model_cells(cm, cells, i, err);
        if (!r && rd) stream_attrs(&q, &m, i, cm, cells);
        if (rd) vx_svo_model_free(model_alloc, &m);
    }
    /* the file's last checks (the NODE checksum) before the layout is made of its models */
    if (!r && rd) r = vx_svo_reader_finish(rd, err);
    c.stats.geom_seconds = vx_time_now() - tg;
    c.stats.geom_threads = threads > 1 ? threads : 1;
    vx_free(d.alloc, b.tab);
    b.tab = NULL;
    vx_free(d.alloc, b.dtab);
    b.dtab = NULL;
    if (!r) r = assemble(&b, &c, err);
    double ta = vx_time_now();
    if (!r && rd && d.attrs_from) r = take_attrs(&c, d.attrs_from, err); /* built by an earlier pass */
    else if (!r && rd) r = place_attrs(&d, &c, &q.aj, err); /* built beside the geometry */
    else if (!r) r = build_all_attrs(&d, s, &c, err);
    c.stats.attr_seconds = vx_time_now() - ta;
    if (rd) {
        for (uint32_t i = 0; q.aj.part && i < n; i++) vx_free(d.alloc, q.aj.part[i].attr);
        vx_free(d.alloc, q.aj.part);
        vx_free(d.alloc, q.aj.res);
        vx_free(d.alloc, q.aj.errs);
        pthread_mutex_destroy(&q.lock);
    }
    vx_free(d.alloc, b.dict);
    vx_free(d.alloc, b.meta);
    vx_free(d.alloc, b.rank);
    vx_free(d.alloc, b.slot);
    if (r) {
        vx_compact_free(&c);
        return r;
    }
    *out = c;
    return VX_OK;
}

vx_result vx_compact_build(const vx_compact_desc* desc, const vx_svo_scene* s, vx_compact_scene* out, vx_error* err) {
    if (!s || !out) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    return build_core(desc, s, NULL, NULL, out, err);
}

vx_result vx_compact_build_reader(const vx_compact_desc* desc, vx_svo_model_reader* rd, vx_compact_scene* out,
                                  vx_error* err) {
    if (!rd || !out) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    const vx_svo_scene* s = vx_svo_reader_scene(rd);
    return build_core(desc, s, rd, s->alloc, out, err); /* the models come in the graph's allocator */
}

/* ---- lookup (the CPU form of the shader's walk) -------------------------------------- */

uint32_t vx__compact_inner_before(const vx_compact_scene* c, uint32_t L, uint32_t blk, uint32_t k) {
    if (!k) return 0;
    if (L >= 6) return c->geom[2 * (size_t)c->slot_count - c->brick_count + blk + k - 1];
    if (L >= 4) return (c->geom[2 * (size_t)(blk + k - 1)] >> 16) & (L == 4 ? 0x7FFFu : 0xFFFFu);
    if (c->brick_dict) return (c->geom[blk + k - 1] >> VX_COMPACT_BRICK_BITS) + 1u;
    uint32_t n = 0; /* bricks in their block: the popcounts of those before */
    for (uint32_t i = 0; i < k; i++)
        n += popc(c->geom[2 * (size_t)(blk + i)]) + popc(c->geom[2 * (size_t)(blk + i) + 1]);
    return n;
}

/* The levels of the slots of levels >= 3 below node n of level L (lev[s],
 * 0 unseen): each once, the DAG's shared blocks too. */
static void mark_levels(const vx_compact_scene* c, uint8_t* lev, uint32_t n, uint32_t L) {
    if (L < 3 || n >= c->slot_count || lev[n]) return;
    lev[n] = (uint8_t)L;
    const uint32_t* sl = c->geom + 2 * (size_t)n;
    uint32_t inner = (sl[0] >> 8) & ~sl[0] & 0xFFu;
    if (L == 3) return;
    for (uint32_t k = 0; k < popc(inner); k++) mark_levels(c, lev, vx__compact_child(c, L, sl[1], k), L - 1);
}

vx_result vx__compact_level3_records(const vx_compact_scene* c, const vx_allocator* alloc, uint32_t** words,
                                     uint32_t* first, uint32_t* count, vx_error* err) {
    *words = NULL, *first = 0, *count = 0;
    if (!c->slot_count) return VX_OK;
    uint8_t* lev = vx_calloc(alloc, c->slot_count, 1);
    if (!lev) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %u slot levels", c->slot_count);
    for (uint32_t i = 0; i < c->model_count; i++)
        if (c->models[i].root < VX_SVO_ROOT_LEAF && c->models[i].depth >= 3)
            mark_levels(c, lev, c->models[i].root, c->models[i].depth);
    uint32_t lo = UINT32_MAX, hi = 0;
    for (uint32_t s = 0; s < c->slot_count; s++)
        if (lev[s] == 3) lo = s < lo ? s : lo, hi = s + 1;
    vx_result r = VX_OK;
    uint32_t* w = hi ? vx_calloc(alloc, 2 * (size_t)(hi - lo), 4) : NULL;
    if (hi && !w) r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %u level-3 records", hi - lo);
    for (uint32_t s = lo; w && s < hi; s++) {
        if (lev[s] != 3) continue;
        const uint32_t* sl = c->geom + 2 * (size_t)s;
        uint32_t leaf = sl[0] & 0xFFu, inner = (sl[0] >> 8) & ~leaf & 0xFFu;
        uint64_t v = 0;
        for (uint32_t o = 1; o < 8; o++) {
            uint32_t below = (1u << o) - 1u;
            uint64_t b = ((uint64_t)popc(leaf & below) << 6) + vx__compact_inner_before(c, 3, sl[1], popc(inner & below));
            v |= b << (9 * (o - 1));
        }
        w[2 * (size_t)(s - lo)] = (uint32_t)v, w[2 * (size_t)(s - lo) + 1] = (uint32_t)(v >> 32);
    }
    vx_free(alloc, lev);
    if (r) return r;
    *words = w, *first = hi ? lo : 0, *count = hi ? hi - lo : 0;
    return VX_OK;
}

uint32_t vx__compact_child(const vx_compact_scene* c, uint32_t L, uint32_t blk, uint32_t k) {
    return L == 3 && c->brick_dict ? c->geom[blk + k] & (VX_COMPACT_MAX_BRICKS - 1u) : blk + k;
}

bool vx_compact_lookup(const vx_compact_scene* c, uint32_t mi, uint32_t x, uint32_t y, uint32_t z, uint32_t* index) {
    if (!c || mi >= c->model_count) return false;
    const vx_compact_model* m = &c->models[mi];
    uint32_t L = m->depth;
    if (m->root == VX_SVO_ROOT_EMPTY || (L < 32 && (x >> L || y >> L || z >> L))) return false;
    if (m->root == VX_SVO_ROOT_LEAF) {
        *index = (uint32_t)vx_svo_morton(x, y, z);
        return true;
    }
    uint32_t n = m->root;
    uint64_t base = 0;
    for (; L >= 1; L--) {
        const uint32_t* sl = c->geom + 2 * (size_t)n;
        if (L <= 2) {
            uint32_t r = (1u << L) - 1u, bit = (uint32_t)vx_svo_morton(x & r, y & r, z & r);
            uint64_t mask = sl[0] | (uint64_t)sl[1] << 32;
            if (!((mask >> bit) & 1u)) return false;
            *index = (uint32_t)(base + (uint64_t)__builtin_popcountll(mask & ((1ull << bit) - 1u)));
            return true;
        }
        uint32_t valid = (sl[0] >> 8) & 0xFFu, leaf = sl[0] & 0xFFu, inner = valid & ~leaf;
        uint32_t s = L - 1, o = ((x >> s) & 1u) | (((y >> s) & 1u) << 1) | (((z >> s) & 1u) << 2);
        if (!((valid >> o) & 1u)) return false;
        uint32_t below = (1u << o) - 1u, k = popc(inner & below);
        base += ((uint64_t)popc(leaf & below) << (3 * s)) + vx__compact_inner_before(c, L, sl[1], k);
        if ((leaf >> o) & 1u) {
            uint32_t mask = (1u << s) - 1u;
            *index = (uint32_t)(base + vx_svo_morton(x & mask, y & mask, z & mask));
            return true;
        }
        n = vx__compact_child(c, L, sl[1], k);
    }
    return false;
}

static uint32_t wcode_sum(uint32_t wcode) {
    return (wcode & 15u) + ((wcode >> 4) & 15u) + ((wcode >> 8) & 15u) + ((wcode >> 12) & 15u);
}

vx_result vx__compact_encode(const vx_allocator* alloc, uint32_t block, uint32_t kind, const uint32_t* vals, uint32_t n,
                             vx_compact_stats* st, uint32_t** words, uint32_t* nwords, vx_error* err) {
    vx_compact_scene c = {0};
    vx_compact_model cm = {.voxels = n, .attr_kind = kind};
    vx_compact_desc d = {.alloc = alloc};
    size_t cap = 0;
    *words = NULL, *nwords = 0;
    if (!n) return VX_OK;
    vx_result r = build_attrs(&d, block, NULL, vals, &cm, &c, &cap, err);
    if (st) {
        st->blocks += c.stats.blocks, st->uniform += c.stats.uniform, st->raw += c.stats.raw;
        st->delta += c.stats.delta, st->uniform_groups += c.stats.uniform_groups, st->shared += c.stats.shared;
        st->distinct_sum += c.stats.distinct_sum;
    }
    if (r) {
        vx_free(alloc, c.attr);
        return r;
    }
    *words = c.attr, *nwords = c.attr_words;
    return VX_OK;
}

uint32_t vx_compact_rgba(const vx_compact_scene* c, uint32_t mi, uint32_t i) {
    if (!c || mi >= c->model_count) return 0xFFFFFFFFu;
    const vx_compact_model* m = &c->models[mi];
    if (m->attr_kind == VX_COMPACT_ATTR_NONE || i >= m->voxels) return 0xFFFFFFFFu;
    uint32_t v = vx__compact_value(c, mi, i);
    return m->attr_kind == VX_COMPACT_ATTR_PALETTE ? c->palette[v & 0xFFu] : v;
}

uint32_t vx__compact_value(const vx_compact_scene* c, uint32_t mi, uint32_t i) {
    const vx_compact_model* m = &c->models[mi];
    if (m->attr_kind == VX_COMPACT_ATTR_NONE || i >= m->voxels) return 0xFFFFFFFFu;
    uint32_t B = m->block, width = m->attr_kind == VX_COMPACT_ATTR_PALETTE ? 8 : 32;
    uint32_t blk = i / B, g = c->attr[m->attr_base + blk / VX_COMPACT_GROUP];
    uint32_t h = c->attr[m->attr_base + (g & 0x7FFFFFFFu) + (g >> 31 ? 0 : blk % VX_COMPACT_GROUP)];
    uint32_t code = h & 31u, j = i % B;
    const uint32_t* p = c->attr + m->attr_base + (h >> 5);
    uint32_t v;
    if (code == VX_COMPACT_RAW) {
        v = get_bits(p, (uint64_t)j * width, width);
    } else if (code == VX_COMPACT_DELTA) {
        uint32_t wcode = p[1], pos = 0;
        v = 0;
        for (uint32_t c = 0; c < 4; c++) {
            uint32_t w = (wcode >> (4 * c)) & 15u, base = (p[0] >> (8 * c)) & 0xFFu;
            uint32_t r = w ? get_bits(p + 2, (uint64_t)j * (wcode_sum(wcode)) + pos, w) : 0;
            v |= ((base + r) & 0xFFu) << (8 * c);
            pos += w;
        }
        v = recorrelate(v, (wcode >> 16) & 1u);
    } else {
        uint32_t k = code ? get_bits(p, (uint64_t)j * code, code) : 0;
        v = get_bits(p + ((uint64_t)B * code + 31) / 32, (uint64_t)k * width, width);
    }
    return v;
}
