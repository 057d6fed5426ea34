/* svo/svo_edit.c - incremental, append-only edits of a built model (svo/edit.h).
 *
 * A node on a written path is expanded into its eight children (read from
 * its descriptor and block, or eight copies of a collapsed leaf, or eight
 * empty ones), the written children are made again recursively, and the node
 * is re-formed: empty, a collapsed leaf, or a new block appended after the
 * model's words (far slots, the non-leaf children's descriptors, the
 * attribute index), unless the index of blocks holds an equal one. */
#include <stdlib.h>
#include <string.h>

#include "svo/edit.h"
#include "svo/svo_internal.h"

#define NO_BLOCK 0xFFFFFFFFu
enum { K_EMPTY = 0, K_LEAF, K_NODE };

/* A child as the update sees it. hdr is the descriptor's low 16 bits
 * (valid << 8 | leaf); rec is a leaf's tuple or a node's representative. */
typedef struct cref {
    uint32_t kind, hdr, block;
    vx__svo_rec rec;
} cref;

/* A block's content, what makes two blocks interchangeable: the node's
 * masks, each non-leaf child's masks and block, each valid child's tuple. */
typedef struct bkey {
    uint32_t hdr, nn, nv;
    uint32_t c[16];
    vx__svo_rec recs[8];
} bkey;

/* A write after sorting: Morton key and the index of the write. */
typedef struct kw {
    uint64_t key;
    size_t i;
} kw;

struct vx_svo_editor {
    const vx_allocator* a;
    vx_svo_model* m;
    bool dag;
    uint32_t limit;               /* largest near pointer */
    size_t ncap, acap;            /* allocated words / records of m's arrays */
    uint32_t nend, aend;          /* words / records in use: appends go here (monotonic) */
    uint64_t* tab;                /* index: hdr << 32 | block, 0 = free slot */
    size_t tabcap, tabn;
    /* during one apply */
    const vx_svo_cell_write* w;
    const kw* kv;
    vx_svo_edit_stats st;
    int64_t dcells;
};

vx_svo_model_header vx_svo_model_header_get(const vx_svo_model* m) {
    vx_svo_model_header h = {.depth = m->depth, .root = m->root, .root_attr = m->root_attr, .node_count = m->node_count,
                             .attr_count = m->attr_count, .voxel_count = m->voxel_count};
    memcpy(h.size, m->size, sizeof h.size);
    return h;
}

void vx_svo_model_header_set(vx_svo_model* m, const vx_svo_model_header* h) {
    memcpy(m->size, h->size, sizeof m->size);
    m->depth = h->depth, m->root = h->root, m->root_attr = h->root_attr;
    m->node_count = h->node_count, m->attr_count = h->attr_count, m->voxel_count = h->voxel_count;
}

/* ---- reading the model ----------------------------------------------------------------- */

static bool has_block(const vx_svo_model* m, uint32_t hdr) { return ((hdr >> 8) & ~hdr & 0xFFu) || m->attrs; }

/* The block of the descriptor d stored at word pos. */
static uint32_t resolve(const vx_svo_model* m, uint32_t pos, uint32_t d) {
    if (!has_block(m, d & 0xFFFFu)) return NO_BLOCK;
    uint32_t p = vx_svo_desc_ptr(d);
    return vx_svo_desc_far(d) ? m->nodes[pos - p] : pos - p;
}

static void load_rec(const vx_svo_model* m, uint32_t a, vx__svo_rec* r) {
    memset(r, 0, sizeof *r);
    if (m->palette) r->palette = m->palette[a];
    if (m->rgba) r->rgba = m->rgba[a];
    if (m->normal) r->normal = m->normal[a];
    if (m->material) r->material = m->material[a];
    if (m->density) r->density = m->density[a];
}

static cref root_ref(const vx_svo_model* m) {
    cref r;
    memset(&r, 0, sizeof r);
    if (m->root == VX_SVO_ROOT_EMPTY) return r;
    if (m->attrs) load_rec(m, m->root_attr, &r.rec);
    if (m->root == VX_SVO_ROOT_LEAF) {
        r.kind = K_LEAF;
        return r;
    }
    uint32_t d = m->nodes[m->root];
    r.kind = K_NODE;
    r.hdr = d & 0xFFFFu;
    r.block = resolve(m, m->root, d);
    return r;
}

/* The eight children of n. */
static void expand(const vx_svo_model* m, const cref* n, cref ch[8]) {
    memset(ch, 0, 8 * sizeof *ch);
    if (n->kind == K_EMPTY) return;
    if (n->kind == K_LEAF) {
        for (int o = 0; o < 8; o++) ch[o].kind = K_LEAF, ch[o].rec = n->rec;
        return;
    }
    uint32_t valid = n->hdr >> 8, leaf = n->hdr & 0xFFu, nn = vx__popc8(valid & ~leaf);
    uint32_t a = m->attrs ? m->nodes[n->block + nn] : 0, j = 0, r = 0;
    for (unsigned o = 0; o < 8; o++) {
        if (!(valid >> o & 1u)) continue;
        if (m->attrs) load_rec(m, a + r, &ch[o].rec);
        r++;
        if (leaf >> o & 1u) {
            ch[o].kind = K_LEAF;
        } else {
            uint32_t pos = n->block + j++, d = m->nodes[pos];
            ch[o].kind = K_NODE;
            ch[o].hdr = d & 0xFFFFu;
            ch[o].block = resolve(m, pos, d);
        }
    }
}

/* The content of the stored block of a node with masks hdr. */
static void read_key(const vx_svo_model* m, uint32_t hdr, uint32_t block, bkey* k) {
    memset(k, 0, sizeof *k);
    uint32_t valid = hdr >> 8, leaf = hdr & 0xFFu;
    k->hdr = hdr;
    k->nn = vx__popc8(valid & ~leaf);
    k->nv = vx__popc8(valid);
    for (uint32_t j = 0; j < k->nn; j++) {
        uint32_t d = m->nodes[block + j];
        k->c[2 * j] = d & 0xFFFFu;
        k->c[2 * j + 1] = resolve(m, block + j, d);
    }
    if (m->attrs) {
        uint32_t a = m->nodes[block + k->nn];
        for (uint32_t r = 0; r < k->nv; r++) load_rec(m, a + r, &k->recs[r]);
    }
}

static uint64_t mix64(uint64_t h) {
    h ^= h >> 33;
    h *= 0xff51afd7ed558ccdull;
    h ^= h >> 33;
    h *= 0xc4ceb9fe1a85ec53ull;
    return h ^ (h >> 33);
}

static uint64_t key_hash(const bkey* k, uint32_t attrs) {
    uint64_t h = mix64(k->hdr + 0x9E3779B97F4A7C15ull);
    for (uint32_t j = 0; j < 2 * k->nn; j++) h = mix64(h ^ k->c[j]);
    if (attrs)
        for (uint32_t r = 0; r < k->nv; r++) {
            uint32_t w[4];
            memcpy(w, &k->recs[r], sizeof w);
            for (int q = 0; q < 4; q++) h = mix64(h ^ w[q]);
        }
    return h;
}

static bool key_eq(const bkey* x, const bkey* y, uint32_t attrs) {
    if (x->hdr != y->hdr || x->nn != y->nn || x->nv != y->nv) return false;
    if (memcmp(x->c, y->c, 2 * x->nn * sizeof x->c[0])) return false;
    return !attrs || !memcmp(x->recs, y->recs, x->nv * sizeof x->recs[0]);
}

/* ---- the index of blocks ----------------------------------------------------------------- */

/* The block of an entry equal to k, or NO_BLOCK; *slot = where k would go. */
static uint32_t index_find(const vx_svo_editor* e, const bkey* k, uint64_t h, size_t* slot) {
    size_t j = (size_t)h & (e->tabcap - 1);
    while (e->tab[j]) {
        uint32_t hdr = (uint32_t)(e->tab[j] >> 32), blk = (uint32_t)e->tab[j];
        if (hdr == k->hdr) {
            bkey o;
            read_key(e->m, hdr, blk, &o);
            if (key_eq(&o, k, e->m->attrs)) return blk;
        }
        j = (j + 1) & (e->tabcap - 1);
    }
    *slot = j;
    return NO_BLOCK;
}

static bool index_reserve(vx_svo_editor* e, size_t more) {
    if ((e->tabn + more) * 2 <= e->tabcap) return true;
    size_t ncap = e->tabcap ? e->tabcap : 1024;
    while ((e->tabn + more) * 2 > ncap) {
        if (ncap > SIZE_MAX / 16) return false;
        ncap *= 2;
    }
    uint64_t* t = (uint64_t*)vx_calloc(e->a, ncap, sizeof *t);
    if (!t) return false;
    for (size_t i = 0; i < e->tabcap; i++) {
        if (!e->tab[i]) continue;
        bkey k;
        read_key(e->m, (uint32_t)(e->tab[i] >> 32), (uint32_t)e->tab[i], &k);
        size_t j = (size_t)key_hash(&k, e->m->attrs) & (ncap - 1);
        while (t[j]) j = (j + 1) & (ncap - 1);
        t[j] = e->tab[i];
    }
    vx_free(e->a, e->tab);
    e->tab = t;
    e->tabcap = ncap;
    return true;
}

/* Every reachable block of the model, each once (a block found equal to an
 * indexed one has indexed children too: its subtree is skipped). */
static vx_result index_build(vx_svo_editor* e, vx_error* err) {
    const vx_svo_model* m = e->m;
    if (m->root == VX_SVO_ROOT_EMPTY || m->root == VX_SVO_ROOT_LEAF) return VX_OK;
    uint32_t* stack = NULL;
    size_t cap = 0, n = 0;
    vx_result r = VX_OK;
    if (!vx_grow(e->a, (void**)&stack, &cap, 64, sizeof *stack)) goto oom;
    stack[n++] = m->root;
    while (n) {
        uint32_t pos = stack[--n], d = m->nodes[pos], hdr = d & 0xFFFFu;
        if (!has_block(m, hdr)) continue;
        uint32_t blk = resolve(m, pos, d);
        bkey k;
        read_key(m, hdr, blk, &k);
        if (!index_reserve(e, 1)) goto oom;
        size_t slot = 0;
        uint64_t h = key_hash(&k, m->attrs);
        if (index_find(e, &k, h, &slot) != NO_BLOCK) continue;
        e->tab[slot] = (uint64_t)hdr << 32 | blk;
        e->tabn++;
        if (!vx_grow(e->a, (void**)&stack, &cap, n + k.nn, sizeof *stack)) goto oom;
        for (uint32_t j = 0; j < k.nn; j++) stack[n++] = blk + j;
    }
    vx_free(e->a, stack);
    return r;
oom:
    vx_free(e->a, stack);
    return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "svo edit: out of memory indexing %u node words", m->node_count);
}

vx_result vx_svo_validate_edited_model(const vx_svo_model* m, vx_error* err) {
    return vx__svo_analyze_opt(m, NULL, true, err);
}

/* ---- create / get ---------------------------------------------------------------------------- */

vx_result vx_svo_editor_create(const vx_svo_editor_desc* desc, vx_svo_model* m, vx_svo_editor** out, vx_error* err) {
    vx_svo_editor_desc d = desc ? *desc : (vx_svo_editor_desc){0};
    if (!m || !out) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "svo edit: NULL argument");
    *out = NULL;
    vx_result r = vx_svo_validate_edited_model(m, err);
    if (r) return r;
    vx_svo_editor* e = (vx_svo_editor*)vx_calloc(d.alloc, 1, sizeof *e);
    if (!e) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "svo edit: out of memory");
    e->a = d.alloc;
    e->m = m;
    e->dag = !d.no_dag;
    e->limit = vx__svo_far_limit(&d.testing);
    e->nend = d.words_in_use > m->node_count ? d.words_in_use : m->node_count;
    e->aend = d.records_in_use > m->attr_count ? d.records_in_use : m->attr_count;
    e->ncap = e->nend;
    e->acap = e->aend;
    if (e->dag && (r = index_build(e, err))) {
        vx_svo_editor_destroy(e);
        return r;
    }
    *out = e;
    return VX_OK;
}

void vx_svo_editor_destroy(vx_svo_editor* e) {
    if (!e) return;
    const vx_allocator* a = e->a;
    vx_free(a, e->tab);
    vx_free(a, e);
}

static void cell_to_rec(uint32_t attrs, const vx_svo_cell* c, vx__svo_rec* r) {
    memset(r, 0, sizeof *r);
    if (attrs & VX_ATTR_PALETTE) r->palette = c->palette;
    if (attrs & VX_ATTR_RGBA8) r->rgba = c->rgba;
    if (attrs & VX_ATTR_NORMAL) r->normal = c->normal;
    if (attrs & VX_ATTR_MATERIAL) r->material = c->material;
    if (attrs & VX_ATTR_DENSITY) r->density = c->density;
}

bool vx_svo_editor_get(const vx_svo_editor* e, uint32_t x, uint32_t y, uint32_t z, vx_svo_cell* out) {
    const vx_svo_model* m = e->m;
    if (out) memset(out, 0, sizeof *out);
    if (x >= m->size[0] || y >= m->size[1] || z >= m->size[2]) return false;
    uint64_t key = vx_svo_morton(x, y, z);
    cref n = root_ref(m), ch[8];
    for (uint32_t L = m->depth; L > 0 && n.kind == K_NODE; L--) {
        expand(m, &n, ch);
        n = ch[(key >> (3 * (L - 1))) & 7u];
    }
    if (n.kind == K_EMPTY) return false;
    if (out) {
        out->palette = n.rec.palette, out->rgba = n.rec.rgba, out->normal = n.rec.normal;
        out->material = n.rec.material, out->density = n.rec.density;
    }
    return true;
}

/* Fills the part of box [lo, hi] that node n (the cube of 2^L cells at o)
 * covers. */
static void get_box_node(const vx_svo_model* m, const cref* n, uint32_t L, const uint32_t o[3], const uint32_t lo[3],
                         const uint32_t hi[3], const uint32_t dim[3], bool* set, vx_svo_cell* out) {
    uint64_t side = (uint64_t)1 << L;
    for (int k = 0; k < 3; k++)
        if ((uint64_t)o[k] > hi[k] || (uint64_t)o[k] + side <= lo[k]) return;
    if (n->kind == K_EMPTY) return;
    if (n->kind == K_LEAF) {
        uint32_t a[3], b[3];
        for (int k = 0; k < 3; k++) {
            a[k] = o[k] > lo[k] ? o[k] : lo[k];
            uint64_t e = (uint64_t)o[k] + side - 1;
            b[k] = e < hi[k] ? (uint32_t)e : hi[k];
        }
        vx_svo_cell c;
        memset(&c, 0, sizeof c); /* padding too: callers may compare cells bytewise, as vx_svo_editor_get's */
        c.palette = n->rec.palette, c.rgba = n->rec.rgba, c.normal = n->rec.normal;
        c.material = n->rec.material, c.density = n->rec.density;
        for (uint32_t z = a[2]; z <= b[2]; z++)
            for (uint32_t y = a[1]; y <= b[1]; y++) {
                size_t i = ((size_t)(z - lo[2]) * dim[1] + (y - lo[1])) * dim[0] + (a[0] - lo[0]);
                for (uint32_t x = a[0]; x <= b[0]; x++, i++) {
                    set[i] = true;
                    if (out) out[i] = c;
                }
            }
        return;
    }
    cref ch[8];
    expand(m, n, ch);
    uint32_t h = (uint32_t)(side / 2);
    for (unsigned q = 0; q < 8; q++) {
        if (ch[q].kind == K_EMPTY) continue;
        uint32_t co[3] = {o[0] + (q & 1u) * h, o[1] + ((q >> 1) & 1u) * h, o[2] + ((q >> 2) & 1u) * h};
        get_box_node(m, &ch[q], L - 1, co, lo, hi, dim, set, out);
    }
}

vx_result vx_svo_editor_get_box(const vx_svo_editor* e, const uint32_t lo[3], const uint32_t hi[3], bool* set,
                                vx_svo_cell* out, vx_error* err) {
    if (!e || !lo || !hi || !set) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "svo edit: NULL argument");
    uint32_t dim[3];
    size_t n = 1;
    for (int k = 0; k < 3; k++) {
        if (hi[k] < lo[k]) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "svo edit: box axis %d is empty", k);
        dim[k] = hi[k] - lo[k] + 1;
        if (dim[k] == 0 || n > SIZE_MAX / sizeof *out / dim[k])
            return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "svo edit: box too large");
        n *= dim[k];
    }
    memset(set, 0, n * sizeof *set);
    if (out) memset(out, 0, n * sizeof *out);
    const vx_svo_model* m = e->m;
    cref root = root_ref(m);
    uint32_t o[3] = {0, 0, 0};
    get_box_node(m, &root, m->depth, o, lo, hi, dim, set, out); /* a valid model has no cell past its size */
    return VX_OK;
}

/* ---- apply ---------------------------------------------------------------------------------- */

/* Arrays were grown before the update (see apply): pushes cannot fail. */
static void push_word(vx_svo_editor* e, uint32_t v) { e->m->nodes[e->nend++] = v; }

static uint32_t push_recs(vx_svo_editor* e, const vx__svo_rec* r, uint32_t n) {
    vx_svo_model* m = e->m;
    uint32_t a = e->aend;
    for (uint32_t i = 0; i < n; i++) {
        if (m->palette) m->palette[a + i] = r[i].palette;
        if (m->rgba) m->rgba[a + i] = r[i].rgba;
        if (m->normal) m->normal[a + i] = r[i].normal;
        if (m->material) m->material[a + i] = r[i].material;
        if (m->density) m->density[a + i] = r[i].density;
    }
    e->aend += n;
    e->st.records_added += n;
    return a;
}

/* Appends the block of k (far slots first, as the builder places them). */
static uint32_t put_block(vx_svo_editor* e, const bkey* k) {
    uint32_t a = e->m->attrs ? push_recs(e, k->recs, k->nv) : 0;
    uint32_t cur = e->nend, nfar = 0;
    bool far[8] = {false};
    for (int it = 0; it < 10; it++) { /* each slot shifts the descriptors: a fixpoint */
        uint32_t cnt = 0;
        for (uint32_t j = 0; j < k->nn; j++) {
            uint32_t cb = k->c[2 * j + 1];
            far[j] = cb != NO_BLOCK && (cur + nfar + j) - cb > e->limit;
            cnt += far[j];
        }
        if (cnt == nfar) break;
        nfar = cnt;
    }
    for (uint32_t j = 0; j < k->nn; j++)
        if (far[j]) push_word(e, k->c[2 * j + 1]);
    uint32_t bstart = cur + nfar, fi = 0;
    for (uint32_t j = 0; j < k->nn; j++) {
        uint32_t pos = bstart + j, cb = k->c[2 * j + 1], h = k->c[2 * j], d;
        if (cb == NO_BLOCK) d = vx_svo_desc_make(0, false, h >> 8, h & 0xFFu);
        else if (far[j]) d = vx_svo_desc_make(pos - (cur + fi++), true, h >> 8, h & 0xFFu);
        else d = vx_svo_desc_make(pos - cb, false, h >> 8, h & 0xFFu);
        push_word(e, d);
    }
    if (e->m->attrs) push_word(e, a);
    e->st.blocks_made++;
    return bstart;
}

/* The node of children ch, re-minimized. */
static cref combine(vx_svo_editor* e, const cref ch[8]) {
    const vx_svo_model* m = e->m;
    cref out;
    memset(&out, 0, sizeof out);
    uint32_t valid = 0, leaf = 0;
    for (unsigned o = 0; o < 8; o++) {
        if (ch[o].kind != K_EMPTY) valid |= 1u << o;
        if (ch[o].kind == K_LEAF) leaf |= 1u << o;
    }
    if (!valid) return out;
    if (valid == 0xFFu && leaf == 0xFFu) { /* collapse: eight full leaves of one tuple */
        bool same = true;
        for (unsigned o = 1; o < 8; o++) same = same && !memcmp(&ch[o].rec, &ch[0].rec, sizeof ch[0].rec);
        if (same) {
            out.kind = K_LEAF;
            out.rec = ch[0].rec;
            return out;
        }
    }
    bkey k;
    memset(&k, 0, sizeof k);
    k.hdr = valid << 8 | leaf;
    const vx__svo_rec* rp[8];
    for (unsigned o = 0; o < 8; o++) {
        if (!(valid >> o & 1u)) continue;
        rp[k.nv] = &ch[o].rec;
        k.recs[k.nv++] = ch[o].rec;
        if (!(leaf >> o & 1u)) {
            k.c[2 * k.nn] = ch[o].hdr;
            k.c[2 * k.nn + 1] = ch[o].block;
            k.nn++;
        }
    }
    out.kind = K_NODE;
    out.hdr = k.hdr;
    if (m->attrs) vx__svo_rec_mean(m->attrs, rp, k.nv, &out.rec);
    if (!has_block(m, k.hdr)) {
        out.block = NO_BLOCK;
        return out;
    }
    if (e->dag) {
        size_t slot = 0;
        uint64_t h = key_hash(&k, m->attrs);
        uint32_t blk = index_find(e, &k, h, &slot);
        if (blk != NO_BLOCK) {
            e->st.blocks_shared++;
            out.block = blk;
            return out;
        }
        out.block = put_block(e, &k);
        e->tab[slot] = (uint64_t)k.hdr << 32 | out.block; /* reserved by apply */
        e->tabn++;
        return out;
    }
    out.block = put_block(e, &k);
    return out;
}

/* Node n covering 2^L cells with the writes kv[i0, i1) inside it. */
static cref update(vx_svo_editor* e, const cref* n, uint32_t L, size_t i0, size_t i1) {
    if (L == 0) { /* one cell, one write (duplicates were dropped) */
        const vx_svo_cell_write* w = &e->w[e->kv[i0].i];
        cref c;
        memset(&c, 0, sizeof c);
        if (w->set) {
            c.kind = K_LEAF;
            cell_to_rec(e->m->attrs, &w->value, &c.rec);
        }
        if (n->kind == K_EMPTY && c.kind != K_EMPTY) e->st.cells_added++, e->dcells++;
        if (n->kind != K_EMPTY && c.kind == K_EMPTY) e->st.cells_removed++, e->dcells--;
        if (n->kind != K_EMPTY && c.kind != K_EMPTY && memcmp(&n->rec, &c.rec, sizeof c.rec)) e->st.cells_changed++;
        return c;
    }
    cref ch[8];
    expand(e->m, n, ch);
    unsigned sh = 3 * (L - 1);
    for (size_t i = i0; i < i1;) {
        unsigned o = (unsigned)(e->kv[i].key >> sh) & 7u;
        size_t j = i + 1;
        while (j < i1 && ((unsigned)(e->kv[j].key >> sh) & 7u) == o) j++;
        ch[o] = update(e, &ch[o], L - 1, i, j);
        i = j;
    }
    return combine(e, ch);
}

static int cmp_kw(const void* x, const void* y) {
    const kw *a = (const kw*)x, *b = (const kw*)y;
    if (a->key != b->key) return a->key < b->key ? -1 : 1;
    return (a->i > b->i) - (a->i < b->i);
}

static uint32_t depth_for(const uint32_t size[3]) {
    uint32_t mx = size[0] > size[1] ? size[0] : size[1], d = 0;
    if (size[2] > mx) mx = size[2];
    while (((uint64_t)1 << d) < mx) d++;
    return d;
}

vx_result vx_svo_editor_apply(vx_svo_editor* e, const vx_svo_cell_write* w, size_t n, vx_svo_edit_stats* stats,
                              vx_error* err) {
    if (!e || (n && !w)) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "svo edit: NULL argument");
    vx_svo_model* m = e->m;
    memset(&e->st, 0, sizeof e->st);
    e->st.words_from = e->nend;
    e->st.records_from = e->aend;
    if (stats) *stats = e->st;
    const uint32_t cmax = 1u << VX_SVO_MAX_DEPTH;
    uint32_t size[3] = {m->size[0], m->size[1], m->size[2]};
    size_t nk = 0;
    for (size_t i = 0; i < n; i++) {
        if (w[i].x >= cmax || w[i].y >= cmax || w[i].z >= cmax)
            return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "svo edit: write %zu: cell (%u, %u, %u) beyond 2^%u cells a side",
                           i, w[i].x, w[i].y, w[i].z, VX_SVO_MAX_DEPTH);
        if (w[i].set) {
            uint32_t c[3] = {w[i].x, w[i].y, w[i].z};
            for (int k = 0; k < 3; k++)
                if (c[k] >= size[k]) size[k] = c[k] + 1;
        }
    }
    uint32_t depth = depth_for(size);
    kw* kv = n ? (kw*)vx_alloc(e->a, n * sizeof *kv) : NULL;
    if (n && !kv) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "svo edit: out of memory for %zu writes", n);
    for (size_t i = 0; i < n; i++) {
        /* a clear outside the (grown) model is nothing to do */
        if (!w[i].set && (w[i].x >= size[0] || w[i].y >= size[1] || w[i].z >= size[2])) continue;
        kv[nk].key = vx_svo_morton(w[i].x, w[i].y, w[i].z);
        kv[nk].i = i;
        nk++;
    }
    if (nk) qsort(kv, nk, sizeof *kv, cmp_kw);
    size_t u = 0; /* the last write of each cell */
    for (size_t i = 0; i < nk; i++) {
        if (u && kv[u - 1].key == kv[i].key) kv[u - 1] = kv[i];
        else kv[u++] = kv[i];
    }
    nk = u;
    /* nodes the update can make: the distinct key prefixes at each level, plus
     * the levels a deeper root adds; each appends at most 8 far slots, 8
     * descriptors and an index word, and 8 records */
    uint64_t touched = depth - m->depth + 1;
    for (uint32_t L = 1; L <= depth; L++) {
        unsigned sh = 3 * L;
        for (size_t i = 0; i < nk; i++) touched += !i || (kv[i].key >> sh) != (kv[i - 1].key >> sh);
    }
    uint64_t words = (uint64_t)e->nend + 17 * touched + 2, recs = (uint64_t)e->aend + 8 * touched + 1;
    if (words >= 0xFFFFFFF0u || recs >= 0xFFFFFFF0u) {
        vx_free(e->a, kv);
        return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "svo edit: the model would exceed 2^32 node words or records");
    }
    bool ok = vx_grow(e->a, (void**)&m->nodes, &e->ncap, (size_t)words, sizeof *m->nodes);
    size_t ac = e->acap;
    if (ok && m->attrs) {
        /* every channel to the same capacity (ac tracks the last one grown) */
        size_t c0 = e->acap;
        if (m->attrs & VX_ATTR_PALETTE) ac = c0, ok = ok && vx_grow(e->a, (void**)&m->palette, &ac, (size_t)recs, 1);
        if (m->attrs & VX_ATTR_RGBA8) ac = c0, ok = ok && vx_grow(e->a, (void**)&m->rgba, &ac, (size_t)recs, 4);
        if (m->attrs & VX_ATTR_NORMAL) ac = c0, ok = ok && vx_grow(e->a, (void**)&m->normal, &ac, (size_t)recs, 4);
        if (m->attrs & VX_ATTR_MATERIAL) ac = c0, ok = ok && vx_grow(e->a, (void**)&m->material, &ac, (size_t)recs, 2);
        if (m->attrs & VX_ATTR_DENSITY) ac = c0, ok = ok && vx_grow(e->a, (void**)&m->density, &ac, (size_t)recs, 4);
        /* a failure part-way leaves some channels at c0 and others larger:
         * keep c0, which every channel has */
        if (ok) e->acap = ac;
    }
    if (ok && e->dag) ok = index_reserve(e, (size_t)touched);
    if (!ok) {
        vx_free(e->a, kv);
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "svo edit: out of memory growing the model to %llu words",
                       (unsigned long long)words);
    }
    /* from here nothing can fail */
    e->w = w;
    e->kv = kv;
    e->dcells = 0;
    cref root = root_ref(m), ch[8];
    for (uint32_t L = m->depth; L < depth; L++) { /* a deeper root: the old one is its octant 0 */
        memset(ch, 0, sizeof ch);
        ch[0] = root;
        root = combine(e, ch);
    }
    if (nk) root = update(e, &root, depth, 0, nk);
    memcpy(m->size, size, sizeof size);
    m->depth = depth;
    m->voxel_count = (uint64_t)((int64_t)m->voxel_count + e->dcells);
    m->root_attr = 0;
    if (root.kind == K_EMPTY) {
        m->root = VX_SVO_ROOT_EMPTY;
        m->node_count = 0;
    } else if (root.kind == K_LEAF) {
        m->root = VX_SVO_ROOT_LEAF;
        m->node_count = 0;
        if (m->attrs) m->root_attr = push_recs(e, &root.rec, 1);
    } else {
        if (m->attrs) m->root_attr = push_recs(e, &root.rec, 1);
        uint32_t h = root.hdr;
        if (root.block == NO_BLOCK) {
            push_word(e, vx_svo_desc_make(0, false, h >> 8, h & 0xFFu));
        } else if (e->nend - root.block > e->limit) {
            push_word(e, root.block);
            push_word(e, vx_svo_desc_make(1, true, h >> 8, h & 0xFFu));
        } else {
            push_word(e, vx_svo_desc_make(e->nend - root.block, false, h >> 8, h & 0xFFu));
        }
        m->root = e->nend - 1;
        m->node_count = e->nend;
    }
    m->attr_count = m->attrs ? e->aend : 0;
    e->st.words_added = e->nend - e->st.words_from;
    if (stats) *stats = e->st;
    vx_free(e->a, kv);
    return VX_OK;
}

/* ---- compaction --------------------------------------------------------------------------------- */

typedef struct cells {
    const vx_svo_model* m;
    uint64_t* keys;
    uint8_t* palette;
    uint32_t *rgba, *normal;
    uint16_t* material;
    float* density;
    size_t n;
} cells;

static bool cell_cb(void* user, uint32_t x, uint32_t y, uint32_t z, uint32_t attr) {
    cells* c = (cells*)user;
    size_t i = c->n++;
    c->keys[i] = vx_svo_morton(x, y, z);
    if (c->palette) c->palette[i] = c->m->palette[attr];
    if (c->rgba) c->rgba[i] = c->m->rgba[attr];
    if (c->normal) c->normal[i] = c->m->normal[attr];
    if (c->material) c->material[i] = c->m->material[attr];
    if (c->density) c->density[i] = c->m->density[attr];
    return true;
}

vx_result vx_svo_model_compact(const vx_svo_build_desc* desc, const vx_svo_model* m, vx_svo_model* out,
                               vx_error* err) {
    if (!m || !out) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "svo compact: NULL argument");
    const vx_svo_build_desc bd = desc ? *desc : (vx_svo_build_desc){0};
    const vx_allocator* alloc = bd.alloc;
    memset(out, 0, sizeof *out);
    if (m->voxel_count > SIZE_MAX / 16)
        return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "svo compact: %llu cells", (unsigned long long)m->voxel_count);
    size_t n = (size_t)m->voxel_count, k = n ? n : 1;
    cells c = {.m = m};
    c.keys = (uint64_t*)vx_alloc(alloc, k * 8);
    if (m->attrs & VX_ATTR_PALETTE) c.palette = (uint8_t*)vx_alloc(alloc, k);
    if (m->attrs & VX_ATTR_RGBA8) c.rgba = (uint32_t*)vx_alloc(alloc, k * 4);
    if (m->attrs & VX_ATTR_NORMAL) c.normal = (uint32_t*)vx_alloc(alloc, k * 4);
    if (m->attrs & VX_ATTR_MATERIAL) c.material = (uint16_t*)vx_alloc(alloc, k * 2);
    if (m->attrs & VX_ATTR_DENSITY) c.density = (float*)vx_alloc(alloc, k * 4);
    vx_result r = VX_OK;
    if (!c.keys || ((m->attrs & VX_ATTR_PALETTE) && !c.palette) || ((m->attrs & VX_ATTR_RGBA8) && !c.rgba) ||
        ((m->attrs & VX_ATTR_NORMAL) && !c.normal) || ((m->attrs & VX_ATTR_MATERIAL) && !c.material) ||
        ((m->attrs & VX_ATTR_DENSITY) && !c.density))
        r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "svo compact: out of memory for %zu cells", n);
    if (!r) r = vx_svo_validate_edited_model(m, err); /* the decoder trusts its model; voxel_count bounds the cells */
    if (!r) r = vx_svo_decode_model(m, cell_cb, &c, err);
    if (!r) {
        vx_svo_voxels v = {.count = c.n, .keys = c.keys, .attrs = m->attrs, .palette = c.palette, .rgba = c.rgba,
                           .normal = c.normal, .material = c.material, .density = c.density};
        memcpy(v.size, m->size, sizeof v.size);
        r = vx_svo_build_model(&bd, &v, out, NULL, err);
    }
    vx_free(alloc, c.keys);
    vx_free(alloc, c.palette);
    vx_free(alloc, c.rgba);
    vx_free(alloc, c.normal);
    vx_free(alloc, c.material);
    vx_free(alloc, c.density);
    return r;
}
