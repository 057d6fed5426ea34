/* render/compact_page.c - the compact layout cut into pages (render/compact.h,
 * issue 18: scenes bigger than GPU memory): a resident top above the page
 * level and position-independent page images below it, each with its own
 * geometry blocks, ranks and attribute region, which render/compact_gpu.c
 * loads into a pool on demand. */
#include <string.h>

#include "render/compact.h"

static uint32_t popc(uint32_t m) { return (uint32_t)__builtin_popcount(m); }

typedef struct pbuild {
    const vx_compact_scene* c;
    vx_compact_paged* p;
    const vx_allocator* a;
    vx_error* err;
    uint32_t Lp;
    /* the top: slot pairs and a rank per slot */
    uint32_t* slot;
    uint32_t* rank;
    size_t slot_cap, rank_cap, page_cap;
    uint32_t n;
    /* blocks below the page level copied into the top once (models of at most Lp levels) */
    uint32_t* memo;
} pbuild;

static vx_result top_alloc(pbuild* b, uint32_t k, uint32_t* at) {
    if ((uint64_t)b->n + k > VX_COMPACT_MAX_SLOTS)
        return vx_fail(b->err, VX_ERR_LIMIT, VX_NO_OFFSET, "compact pages: more than %u top slots", VX_COMPACT_MAX_SLOTS);
    if (!vx_grow(b->a, (void**)&b->slot, &b->slot_cap, 2 * ((size_t)b->n + k), 4) ||
        !vx_grow(b->a, (void**)&b->rank, &b->rank_cap, (size_t)b->n + k, 4))
        return vx_fail(b->err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %u top slots", b->n + k);
    *at = b->n;
    memset(b->slot + 2 * (size_t)b->n, 0, 8 * (size_t)k);
    memset(b->rank + b->n, 0, 4 * (size_t)k);
    b->n += k;
    return VX_OK;
}

/* The rank of slot s of c at level L >= 3 (the cells of its block up to
 * it): a rank word at levels >= 5, bits 16..31 of its word 0 below. The
 * pages and the top keep the form before the ranks moved into word 0 and
 * the brick dictionary: a rank word per slot of level >= 3, descriptors of
 * 16 bits, bricks in their blocks (a page would need the whole dictionary
 * resident). */
static uint32_t orig_rank(const vx_compact_scene* c, uint32_t s, uint32_t L) {
    if (L >= 5) return c->geom[2 * (size_t)c->slot_count - c->brick_count + s];
    return (c->geom[2 * (size_t)s] >> 16) & (L == 3 ? 0x7FFFu : 0xFFFFu); /* level 3: bit 31 VX_COMPACT_INDEXED */
}
/* Word 0 of slot s of c at level L: the descriptor alone (or a brick's low word). */
static uint32_t orig_desc(const vx_compact_scene* c, uint32_t s, uint32_t L) {
    return L >= 3 ? c->geom[2 * (size_t)s] & 0xFFFFu : c->geom[2 * (size_t)s];
}

/* Copies the slot o of c (level L) into top slot t, and below it: a tree
 * down to the page level (paged models), pages there, shared blocks below
 * (models of at most Lp levels). origin and first: the node's cube and
 * first cell in model mi, cells its cells. */
static vx_result fill(pbuild* b, uint32_t mi, bool paged, uint32_t t, uint32_t o, uint32_t L, const uint32_t origin[3],
                      uint32_t first, uint32_t cells) {
    const vx_compact_scene* c = b->c;
    uint32_t desc = orig_desc(c, o, L), w1 = c->geom[2 * (size_t)o + 1];
    b->slot[2 * (size_t)t] = desc, b->slot[2 * (size_t)t + 1] = w1;
    if (L <= 2) return VX_OK; /* a brick: its mask */
    b->rank[t] = orig_rank(c, o, L);
    uint32_t valid = (desc >> 8) & 0xFFu, leaf = desc & 0xFFu, inner = valid & ~leaf, k = popc(inner);
    if (!k) return VX_OK;
    if (paged && L == b->Lp) {
        vx_compact_paged* p = b->p;
        if (p->page_count == 0x7FFFFFFFu)
            return vx_fail(b->err, VX_ERR_LIMIT, VX_NO_OFFSET, "compact pages: more than 2^31 - 1 pages");
        if (!vx_grow(b->a, (void**)&p->pages, &b->page_cap, (size_t)p->page_count + 1, sizeof *p->pages))
            return vx_fail(b->err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %u pages", p->page_count + 1);
        vx_compact_page* pg = &p->pages[p->page_count];
        *pg = (vx_compact_page){.model = mi, .top_slot = t, .cube = {origin[0], origin[1], origin[2]}, .first = first,
                                .cells = cells};
        /* a page's children block: word 1 of its original, kept here until the images are made */
        pg->offset = w1;
        b->slot[2 * (size_t)t + 1] = 0x80000000u | p->page_count++;
        return VX_OK;
    }
    if (!paged && b->memo[w1] != UINT32_MAX) {
        b->slot[2 * (size_t)t + 1] = b->memo[w1];
        return VX_OK;
    }
    uint32_t nb;
    vx_result r = top_alloc(b, k, &nb);
    if (r) return r;
    b->slot[2 * (size_t)t + 1] = nb;
    if (!paged) b->memo[w1] = nb;
    uint32_t s = L - 1, j = 0;
    for (uint32_t oc = 0; oc < 8; oc++) {
        if (!((inner >> oc) & 1u)) continue;
        uint32_t below = (1u << oc) - 1u;
        uint32_t before = vx__compact_inner_before(c, L, w1, j), upto = vx__compact_inner_before(c, L, w1, j + 1);
        uint32_t co[3] = {origin[0] + ((oc & 1u) << s), origin[1] + (((oc >> 1) & 1u) << s),
                          origin[2] + (((oc >> 2) & 1u) << s)};
        uint32_t cf = first + (s < 11 ? popc(leaf & below) << (3 * s) : 0) + before;
        if ((r = fill(b, mi, paged, nb + j, vx__compact_child(c, L, w1, j), L - 1, co, cf, upto - before))) return r;
        j++;
    }
    return VX_OK;
}

/* One page's image (compact.h): its blocks found from its children's block
 * (level Lp - 1), levels >= 3 first; stamp/local map blocks of c to local
 * slots for this page. */
typedef struct blk {
    uint32_t start, k, level;
} blk;

static vx_result page_image(pbuild* b, uint32_t pi, uint32_t* stamp, uint32_t* local, blk** list, size_t* list_cap,
                            uint32_t** img, size_t* img_cap, uint32_t** vals, size_t* vals_cap) {
    const vx_compact_scene* c = b->c;
    vx_compact_paged* p = b->p;
    vx_compact_page* pg = &p->pages[pi];
    uint32_t root_blk = (uint32_t)pg->offset;
    uint32_t rdesc = b->slot[2 * (size_t)pg->top_slot];
    uint32_t rk = popc(((rdesc >> 8) & ~rdesc) & 0xFFu);
    /* the blocks, depth first from the page root's */
    size_t nl = 0, head = 0;
    if (!vx_grow(b->a, (void**)list, list_cap, 1, sizeof **list))
        return vx_fail(b->err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for a page's blocks");
    (*list)[nl++] = (blk){root_blk, rk, b->Lp - 1};
    stamp[root_blk] = pi + 1;
    while (head < nl) {
        blk e = (*list)[head++];
        if (e.level < 3) continue;
        for (uint32_t j = 0; j < e.k; j++) {
            uint32_t d = orig_desc(c, e.start + j, e.level), w = c->geom[2 * (size_t)(e.start + j) + 1];
            uint32_t kk = popc(((d >> 8) & ~d) & 0xFFu);
            if (!kk || stamp[w] == pi + 1) continue;
            stamp[w] = pi + 1;
            if (!vx_grow(b->a, (void**)list, list_cap, nl + 1, sizeof **list))
                return vx_fail(b->err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for a page's blocks");
            (*list)[nl++] = (blk){w, kk, e.level - 1};
        }
    }
    uint32_t n = 0, n3 = 0;
    for (size_t i = 0; i < nl; i++)
        if ((*list)[i].level >= 3) local[(*list)[i].start] = n, n += (*list)[i].k;
    n3 = n;
    for (size_t i = 0; i < nl; i++)
        if ((*list)[i].level < 3) local[(*list)[i].start] = n, n += (*list)[i].k;
    /* attributes: the page's cells' values, coded from index 0 */
    const vx_compact_model* m = &c->models[pg->model];
    uint32_t* aw = NULL;
    uint32_t an = 0;
    uint64_t sum[4] = {0, 0, 0, 0};
    if (m->attr_kind != VX_COMPACT_ATTR_NONE) {
        if (!vx_grow(b->a, (void**)vals, vals_cap, pg->cells ? pg->cells : 1, 4))
            return vx_fail(b->err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %u page values", pg->cells);
        for (uint32_t i = 0; i < pg->cells; i++) {
            uint32_t v = vx__compact_value(c, pg->model, pg->first + i);
            (*vals)[i] = v;
            uint32_t rgba = m->attr_kind == VX_COMPACT_ATTR_PALETTE ? c->palette[v & 0xFFu] : v;
            for (int ch = 0; ch < 4; ch++) sum[ch] += (rgba >> (8 * ch)) & 0xFFu;
        }
        vx_result r = vx__compact_encode(b->a, m->block, m->attr_kind, *vals, pg->cells, NULL, &aw, &an, b->err);
        if (r) return r;
        uint32_t mean = 0;
        for (int ch = 0; ch < 4; ch++)
            mean |= (uint32_t)((sum[ch] + pg->cells / 2) / (pg->cells ? pg->cells : 1)) << (8 * ch);
        pg->rgba = mean;
    } else {
        pg->rgba = 0xFFFFFFFFu;
    }
    uint64_t R = 4 + 2 * (uint64_t)n, A = R + n3, words = A + an;
    words += words & 1u;
    if (words > 0x7FFFFFFFu) {
        vx_free(b->a, aw);
        return vx_fail(b->err, VX_ERR_LIMIT, VX_NO_OFFSET, "compact pages: page %u needs %llu words", pi,
                       (unsigned long long)words);
    }
    if (!vx_grow(b->a, (void**)img, img_cap, (size_t)words, 4)) {
        vx_free(b->a, aw);
        return vx_fail(b->err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for a page of %llu words",
                       (unsigned long long)words);
    }
    uint32_t* w = *img;
    memset(w, 0, (size_t)words * 4);
    w[0] = (uint32_t)A, w[1] = (uint32_t)R - 2, w[2] = pi;
    for (size_t i = 0; i < nl; i++) {
        blk e = (*list)[i];
        uint32_t at = local[e.start];
        for (uint32_t j = 0; j < e.k; j++) {
            /* a brick from the dictionary, by its index word */
            uint32_t o = e.level >= 3 ? e.start + j : vx__compact_child(c, 3, e.start, j);
            uint32_t d = orig_desc(c, o, e.level), y = c->geom[2 * (size_t)o + 1];
            if (e.level >= 3) {
                if (((d >> 8) & ~d) & 0xFFu) y = local[y];
                w[R + at + j] = orig_rank(c, o, e.level);
            }
            w[4 + 2 * (size_t)(at + j)] = d, w[4 + 2 * (size_t)(at + j) + 1] = y;
        }
    }
    if (an) memcpy(w + A, aw, (size_t)an * 4);
    vx_free(b->a, aw);
    pg->slots = n, pg->n3 = n3, pg->words = (uint32_t)words;
    return VX_OK;
}

void vx_compact_paged_free(vx_compact_paged* p) {
    if (!p) return;
    vx_allocator a = p->alloc;
    vx_free(&a, p->models);
    vx_free(&a, p->top);
    vx_free(&a, p->pages);
    vx_free(&a, p->data);
    memset(p, 0, sizeof *p);
}

vx_result vx_compact_page_build(const vx_compact_scene* c, uint32_t page_level, const vx_allocator* alloc,
                                vx_compact_paged* out, vx_error* err) {
    if (!c || !out) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    if (page_level < 3 || page_level > 31)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "page level %u: not in 3..31", page_level);
    vx_compact_paged p = {.page_level = page_level, .model_count = c->model_count};
    if (alloc) p.alloc = *alloc;
    memcpy(p.palette, c->palette, sizeof p.palette);
    pbuild b = {.c = c, .p = &p, .a = &p.alloc, .err = err, .Lp = page_level};
    vx_result r = VX_OK;
    uint32_t *stamp = NULL, *local = NULL, *img = NULL, *vals = NULL;
    blk* list = NULL;
    size_t list_cap = 0, img_cap = 0, vals_cap = 0, data_cap = 0, top_cap = 0;
    p.models = vx_calloc(b.a, c->model_count ? c->model_count : 1, sizeof *p.models);
    /* maps by block start: a slot, or the word of a block of brick index words */
    size_t starts = (size_t)c->geom_words + 1;
    b.memo = vx_alloc(b.a, starts * 4);
    if (!p.models || !b.memo) {
        r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for the pages' top");
        goto done;
    }
    memset(b.memo, 0xFF, starts * 4);
    for (uint32_t i = 0; !r && i < c->model_count; i++) {
        const vx_compact_model* m = &c->models[i];
        p.models[i] = *m;
        if (m->root >= VX_SVO_ROOT_LEAF) continue;
        uint32_t t, zero[3] = {0, 0, 0};
        if (!(r = top_alloc(&b, 1, &t))) r = fill(&b, i, m->depth > page_level, t, m->root, m->depth, zero, 0, m->voxels);
        p.models[i].root = t;
    }
    if (r) goto done;
    p.top_slots = b.n;
    /* the page images */
    stamp = vx_calloc(b.a, starts, 4);
    local = vx_alloc(b.a, starts * 4);
    if (!stamp || !local) {
        r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for the pages' maps");
        goto done;
    }
    for (uint32_t pi = 0; !r && pi < p.page_count; pi++) {
        if ((r = page_image(&b, pi, stamp, local, &list, &list_cap, &img, &img_cap, &vals, &vals_cap))) break;
        vx_compact_page* pg = &p.pages[pi];
        if (!vx_grow(b.a, (void**)&p.data, &data_cap, (size_t)(p.data_words + pg->words), 4)) {
            r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for the page images");
            break;
        }
        memcpy(p.data + p.data_words, img, (size_t)pg->words * 4);
        pg->offset = p.data_words;
        p.data_words += pg->words;
        if (pg->words > p.max_page_words) p.max_page_words = pg->words;
    }
    if (r) goto done;
    /* the top's words: slots, ranks, each model's attributes with its pages' cells as 0 */
    uint64_t tw = 3 * (uint64_t)p.top_slots;
    tw += tw & 1u;
    if (!vx_grow(b.a, (void**)&p.top, &top_cap, (size_t)(tw ? tw : 2), 4)) {
        r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for the top");
        goto done;
    }
    memset(p.top, 0, (size_t)tw * 4);
    if (p.top_slots) {
        memcpy(p.top, b.slot, 8 * (size_t)p.top_slots);
        memcpy(p.top + 2 * (size_t)p.top_slots, b.rank, 4 * (size_t)p.top_slots);
    }
    uint32_t next_page = 0;
    for (uint32_t i = 0; !r && i < c->model_count; i++) {
        const vx_compact_model* m = &c->models[i];
        vx_compact_model* pm = &p.models[i];
        pm->attr_base = (uint32_t)tw, pm->attr_words = 0;
        if (m->attr_kind == VX_COMPACT_ATTR_NONE || !m->voxels) continue;
        if (!vx_grow(b.a, (void**)&vals, &vals_cap, m->voxels, 4)) {
            r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %u values", m->voxels);
            break;
        }
        for (uint32_t v = 0; v < m->voxels; v++) vals[v] = vx__compact_value(c, i, v);
        /* pages were numbered model by model in index order */
        for (; next_page < p.page_count && p.pages[next_page].model == i; next_page++)
            memset(vals + p.pages[next_page].first, 0, (size_t)p.pages[next_page].cells * 4);
        uint32_t* aw = NULL;
        uint32_t an = 0;
        if ((r = vx__compact_encode(b.a, m->block, m->attr_kind, vals, m->voxels, NULL, &aw, &an, err))) break;
        if (tw + an > 0xFFFFFFF0u) {
            vx_free(b.a, aw);
            r = vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "compact pages: the top passes 2^32 words");
            break;
        }
        if (!vx_grow(b.a, (void**)&p.top, &top_cap, (size_t)(tw + an + 1), 4)) {
            vx_free(b.a, aw);
            r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for the top");
            break;
        }
        memcpy(p.top + tw, aw, (size_t)an * 4);
        vx_free(b.a, aw);
        pm->attr_words = an;
        tw += an;
    }
    if (r) goto done;
    if (tw & 1u) p.top[tw++] = 0;
    p.top_words = (uint32_t)tw;
done:
    vx_free(b.a, b.slot);
    vx_free(b.a, b.rank);
    vx_free(b.a, b.memo);
    vx_free(b.a, stamp);
    vx_free(b.a, local);
    vx_free(b.a, list);
    vx_free(b.a, img);
    vx_free(b.a, vals);
    if (r) {
        vx_compact_paged_free(&p);
        return r;
    }
    *out = p;
    return VX_OK;
}

uint32_t vx_compact_page_at(const vx_compact_paged* p, uint32_t mi, uint32_t x, uint32_t y, uint32_t z) {
    if (!p || mi >= p->model_count) return UINT32_MAX;
    const vx_compact_model* m = &p->models[mi];
    if (m->root >= VX_SVO_ROOT_LEAF || m->depth <= p->page_level) return UINT32_MAX;
    if (m->depth < 32 && (x >> m->depth || y >> m->depth || z >> m->depth)) return UINT32_MAX;
    uint32_t n = m->root;
    for (uint32_t L = m->depth; L > p->page_level; L--) {
        uint32_t d = p->top[2 * (size_t)n], valid = (d >> 8) & 0xFFu, inner = valid & ~d & 0xFFu;
        uint32_t s = L - 1, o = ((x >> s) & 1u) | (((y >> s) & 1u) << 1) | (((z >> s) & 1u) << 2);
        if (!((inner >> o) & 1u)) return UINT32_MAX;
        n = p->top[2 * (size_t)n + 1] + popc(inner & ((1u << o) - 1u));
    }
    uint32_t w1 = p->top[2 * (size_t)n + 1];
    return (w1 >> 31) ? w1 & 0x7FFFFFFFu : UINT32_MAX;
}
