/* render/compact_page.c - the compact layout cut into pages (render/compact.h,
 * issue 18: scenes bigger than GPU memory): a resident top above the page
 * level and position-independent page images below it, each with its own
 * geometry blocks, ranks and attribute region, which render/compact_gpu.c
 * loads into a pool on demand. */
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "render/compact.h"

static uint32_t popc(uint32_t m) { return (uint32_t)__builtin_popcount(m); }

typedef struct blk {
    uint32_t start, k, level;
} blk;

typedef struct pbuild {
    const vx_compact_scene* c; /* the layout the models are cut from: the scene's, or one model's */
    uint32_t cm;               /* the model being cut: its index in c (the scene's index is the page's model) */
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
    /* the models' top attribute regions, back to back (placed after the slots and ranks at the end) */
    uint32_t* attr;
    size_t attr_cap;
    uint64_t attr_n;
    /* the images' scratch: per block start of c, a page's stamp and local slot */
    uint32_t *stamp, *local, *img, *vals;
    blk* list;
    size_t list_cap, img_cap, vals_cap, data_cap;
    bool keep_images; /* the images into p->data (else only their sizes and colours are kept) */
    uint8_t* lvl;     /* with track_levels: each top slot's level (a model's part relocated when merged) */
    size_t lvl_cap;
    bool track_levels;
} pbuild;

static vx_result top_alloc(pbuild* b, uint32_t k, uint32_t* at) {
    if ((uint64_t)b->n + k > VX_COMPACT_MAX_SLOTS)
        return vx_fail(b->err, VX_ERR_LIMIT, VX_NO_OFFSET, "compact pages: more than %u top slots", VX_COMPACT_MAX_SLOTS);
    if (!vx_grow(b->a, (void**)&b->slot, &b->slot_cap, 2 * ((size_t)b->n + k), 4) ||
        !vx_grow(b->a, (void**)&b->rank, &b->rank_cap, (size_t)b->n + k, 4) ||
        (b->track_levels && !vx_grow(b->a, (void**)&b->lvl, &b->lvl_cap, (size_t)b->n + k, 1)))
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
    if (b->track_levels) b->lvl[t] = (uint8_t)L;
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

/* One page's image (compact.h) into b->img: its blocks found from its
 * children's block (level Lp - 1), levels >= 3 first; b->stamp/local map
 * blocks of c to local slots for this page. */
static vx_result page_image(pbuild* b, uint32_t pi) {
    uint32_t *stamp = b->stamp, *local = b->local, **img = &b->img, **vals = &b->vals;
    blk** list = &b->list;
    size_t *list_cap = &b->list_cap, *img_cap = &b->img_cap, *vals_cap = &b->vals_cap;
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
    const vx_compact_model* m = &c->models[b->cm];
    uint32_t* aw = NULL;
    uint32_t an = 0;
    uint64_t sum[4] = {0, 0, 0, 0};
    if (m->attr_kind != VX_COMPACT_ATTR_NONE) {
        if (!vx_grow(b->a, (void**)vals, vals_cap, pg->cells ? pg->cells : 1, 4))
            return vx_fail(b->err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %u page values", pg->cells);
        for (uint32_t i = 0; i < pg->cells; i++) {
            uint32_t v = vx__compact_value(c, b->cm, pg->first + i);
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

/* The scratch of b for a layout c (its blocks' maps), model cm of it. */
static vx_result use_layout(pbuild* b, const vx_compact_scene* c, uint32_t cm) {
    size_t starts = (size_t)c->geom_words + 1;
    b->c = c, b->cm = cm;
    vx_free(b->a, b->memo);
    vx_free(b->a, b->stamp);
    vx_free(b->a, b->local);
    b->memo = vx_alloc(b->a, starts * 4);
    b->stamp = vx_calloc(b->a, starts, 4);
    b->local = vx_alloc(b->a, starts * 4);
    if (!b->memo || !b->stamp || !b->local)
        return vx_fail(b->err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for the pages' maps");
    memset(b->memo, 0xFF, starts * 4);
    return VX_OK;
}

/* Model b->cm of b->c as model mi of the paged layout: its top (a tree down
 * to the page level, pages numbered from the next one), its pages' images
 * (kept in p->data with keep_images; their sizes and colours in any case)
 * and its top attribute region (its values with its pages' cells as 0). */
static vx_result cut_model(pbuild* b, uint32_t mi, uint32_t out) {
    const vx_compact_scene* c = b->c;
    vx_compact_paged* p = b->p;
    const vx_compact_model* m = &c->models[b->cm];
    vx_compact_model* pm = &p->models[out]; /* the scene's model mi (out: its index in p->models) */
    *pm = *m;
    vx_result r = VX_OK;
    uint32_t first_page = p->page_count;
    if (m->root < VX_SVO_ROOT_LEAF) {
        uint32_t t, zero[3] = {0, 0, 0};
        if (!(r = top_alloc(b, 1, &t))) r = fill(b, mi, m->depth > b->Lp, t, m->root, m->depth, zero, 0, m->voxels);
        pm->root = t;
    }
    for (uint32_t pi = first_page; !r && pi < p->page_count; pi++) {
        if ((r = page_image(b, pi))) break;
        vx_compact_page* pg = &p->pages[pi];
        pg->offset = 0;
        if (pg->words > p->max_page_words) p->max_page_words = pg->words;
        if (!b->keep_images) continue;
        if (!vx_grow(b->a, (void**)&p->data, &b->data_cap, (size_t)(p->data_words + pg->words), 4)) {
            r = vx_fail(b->err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for the page images");
            break;
        }
        memcpy(p->data + p->data_words, b->img, (size_t)pg->words * 4);
        pg->offset = p->data_words;
        p->data_words += pg->words;
    }
    if (r) return r;
    /* the model's top attributes: at attr_base from the regions' start (placed after the slots at the end) */
    pm->attr_base = (uint32_t)b->attr_n, pm->attr_words = 0;
    if (m->attr_kind == VX_COMPACT_ATTR_NONE || !m->voxels) return VX_OK;
    if (!vx_grow(b->a, (void**)&b->vals, &b->vals_cap, m->voxels, 4))
        return vx_fail(b->err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %u values", m->voxels);
    for (uint32_t v = 0; v < m->voxels; v++) b->vals[v] = vx__compact_value(c, b->cm, v);
    for (uint32_t pi = first_page; pi < p->page_count; pi++)
        memset(b->vals + p->pages[pi].first, 0, (size_t)p->pages[pi].cells * 4);
    uint32_t* aw = NULL;
    uint32_t an = 0;
    if ((r = vx__compact_encode(b->a, m->block, m->attr_kind, b->vals, m->voxels, NULL, &aw, &an, b->err))) return r;
    if (b->attr_n + an > 0xFFFFFFF0u) {
        vx_free(b->a, aw);
        return vx_fail(b->err, VX_ERR_LIMIT, VX_NO_OFFSET, "compact pages: the top passes 2^32 words");
    }
    if (!vx_grow(b->a, (void**)&b->attr, &b->attr_cap, (size_t)(b->attr_n + an + 1), 4)) {
        vx_free(b->a, aw);
        return vx_fail(b->err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for the top");
    }
    memcpy(b->attr + b->attr_n, aw, (size_t)an * 4);
    vx_free(b->a, aw);
    pm->attr_words = an;
    b->attr_n += an;
    return VX_OK;
}

/* The top's words: slots, ranks, then the models' attribute regions. */
static vx_result finish_top(pbuild* b) {
    vx_compact_paged* p = b->p;
    p->top_slots = b->n;
    uint64_t tw = 3 * (uint64_t)p->top_slots;
    tw += tw & 1u;
    uint64_t total = tw + b->attr_n;
    total += total & 1u;
    if (total > 0xFFFFFFF0u) return vx_fail(b->err, VX_ERR_LIMIT, VX_NO_OFFSET, "compact pages: the top passes 2^32 words");
    p->top = vx_calloc(b->a, (size_t)(total ? total : 2), 4);
    if (!p->top) return vx_fail(b->err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for the top");
    if (p->top_slots) {
        memcpy(p->top, b->slot, 8 * (size_t)p->top_slots);
        memcpy(p->top + 2 * (size_t)p->top_slots, b->rank, 4 * (size_t)p->top_slots);
    }
    if (b->attr_n) memcpy(p->top + tw, b->attr, (size_t)b->attr_n * 4);
    for (uint32_t i = 0; i < p->model_count; i++) p->models[i].attr_base += (uint32_t)tw;
    p->top_words = (uint32_t)total;
    return VX_OK;
}

static void pbuild_free(pbuild* b) {
    vx_free(b->a, b->slot);
    vx_free(b->a, b->rank);
    vx_free(b->a, b->memo);
    vx_free(b->a, b->attr);
    vx_free(b->a, b->stamp);
    vx_free(b->a, b->local);
    vx_free(b->a, b->list);
    vx_free(b->a, b->img);
    vx_free(b->a, b->vals);
    vx_free(b->a, b->lvl);
}

vx_result vx_compact_page_build(const vx_compact_scene* c, uint32_t page_level, const vx_allocator* alloc,
                                vx_compact_paged* out, vx_error* err) {
    if (!c || !out) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    if (page_level < 3 || page_level > 31)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "page level %u: not in 3..31", page_level);
    vx_compact_paged p = {.page_level = page_level, .model_count = c->model_count};
    if (alloc) p.alloc = *alloc;
    memcpy(p.palette, c->palette, sizeof p.palette);
    memcpy(p.palette_used, c->palette_used, sizeof p.palette_used);
    p.source_bytes = 4ull * c->geom_words + 4ull * c->attr_words;
    pbuild b = {.p = &p, .a = &p.alloc, .err = err, .Lp = page_level, .keep_images = true};
    vx_result r = VX_OK;
    p.models = vx_calloc(b.a, c->model_count ? c->model_count : 1, sizeof *p.models);
    if (!p.models) r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for the pages' top");
    /* one map for the scene's blocks: the models of at most Lp levels share the top's blocks as they share c's */
    if (!r) r = use_layout(&b, c, 0);
    for (uint32_t i = 0; !r && i < c->model_count; i++) {
        b.cm = i;
        r = cut_model(&b, i, i);
    }
    if (!r) r = finish_top(&b);
    pbuild_free(&b);
    if (r) {
        vx_compact_paged_free(&p);
        return r;
    }
    *out = p;
    return VX_OK;
}

/* One model as a layout of its own (the page cuts of the file source): its
 * geometry DAG and attributes as vx_compact_build makes them for the scene
 * (a page's image depends on its subtree and cells alone, so the same words). */
static vx_result model_layout(const vx_svo_scene* graph, vx_svo_model* m, uint32_t block, const vx_allocator* a,
                              vx_compact_scene* out, vx_error* err) {
    vx_svo_scene one;
    memset(&one, 0, sizeof one);
    one.alloc = graph->alloc;
    memcpy(one.palette, graph->palette, sizeof one.palette);
    one.has_palette = graph->has_palette;
    one.models = m;
    one.model_count = 1;
    vx_compact_desc cd = {.alloc = a, .block = block, .threads = 1};
    return vx_compact_build(&cd, &one, out, err);
}

/* One model's part of the file source's top, cut on a worker thread: its
 * top slots (from 0, with their levels), pages (numbered from 0), top
 * attributes and record; merged in model order at the end. */
typedef struct mpart {
    uint32_t n;
    uint32_t *slot, *rank;
    uint8_t* lvl;
    vx_compact_paged p; /* pages, models[0] */
    uint32_t* attr;
    uint64_t attr_n;
    uint64_t source_bytes;
    uint32_t palette_used[8];
} mpart;

typedef struct rjob {
    vx_svo_model_reader* rd;
    const vx_svo_scene* g;
    const vx_allocator* a;
    uint32_t Lp, block;
    mpart* parts;
    pthread_mutex_t lock;
    bool failed;
    vx_error err;
} rjob;

static void part_free(const vx_allocator* a, mpart* m) {
    vx_free(a, m->slot);
    vx_free(a, m->rank);
    vx_free(a, m->lvl);
    vx_free(a, m->attr);
    vx_free(a, m->p.pages);
    vx_free(a, m->p.models);
    memset(m, 0, sizeof *m);
}

/* A worker: models from the reader in turn (its next is thread-safe), each
 * built as a layout of its own, cut into its part and dropped. */
static void reader_worker(void* ctx, unsigned thread, uint32_t job) {
    (void)thread, (void)job;
    rjob* j = (rjob*)ctx;
    for (;;) {
        pthread_mutex_lock(&j->lock);
        bool stop = j->failed;
        pthread_mutex_unlock(&j->lock);
        if (stop) return;
        vx_error err = {0};
        uint32_t i = 0;
        vx_svo_model m;
        vx_result r = vx_svo_reader_next(j->rd, &i, &m, &err);
        if (!r && i >= j->g->model_count) return;
        vx_compact_scene c1;
        memset(&c1, 0, sizeof c1);
        bool built = false;
        if (!r) {
            r = model_layout(j->g, &m, j->block, j->a, &c1, &err);
            vx_svo_model_free(j->g->alloc, &m);
            built = !r;
            if (r) {
                char what[32];
                snprintf(what, sizeof what, "model %u", i);
                vx_error_prefix(&err, what);
            }
        }
        mpart* part = r ? NULL : &j->parts[i];
        if (part) {
            part->p.alloc = j->a ? *j->a : (vx_allocator){0};
            part->p.page_level = j->Lp, part->p.model_count = 1;
            if (!(part->p.models = vx_calloc(j->a, 1, sizeof *part->p.models)))
                r = vx_fail(&err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for the pages' top");
            pbuild b = {.p = &part->p, .a = j->a, .err = &err, .Lp = j->Lp, .track_levels = true};
            if (!r && !(r = use_layout(&b, &c1, 0))) r = cut_model(&b, i, 0);
            part->n = b.n, part->slot = b.slot, part->rank = b.rank, part->lvl = b.lvl, part->attr = b.attr;
            part->attr_n = b.attr_n;
            b.slot = b.rank = b.attr = NULL, b.lvl = NULL;
            pbuild_free(&b);
            part->source_bytes = 4ull * c1.geom_words + 4ull * c1.attr_words;
            memcpy(part->palette_used, c1.palette_used, sizeof part->palette_used);
        }
        if (built) vx_compact_free(&c1);
        if (r) {
            pthread_mutex_lock(&j->lock);
            /* the first error, or the one that stopped the reader over "stopped at an earlier error" */
            if (!j->failed || (j->err.code == VX_ERR_INVALID_ARG && err.code != VX_ERR_INVALID_ARG)) j->err = err;
            j->failed = true;
            pthread_mutex_unlock(&j->lock);
            return;
        }
    }
}

/* The parts into one top, in model order: slot words 1 of nodes relocated by
 * the part's first slot, page numbers by its first page. */
static vx_result merge_parts(pbuild* b, mpart* parts, uint32_t count) {
    vx_compact_paged* p = b->p;
    size_t page_cap = 0;
    for (uint32_t i = 0; i < count; i++) {
        mpart* m = &parts[i];
        uint32_t base, pbase = p->page_count;
        if ((uint64_t)p->page_count + m->p.page_count > 0x7FFFFFFFu)
            return vx_fail(b->err, VX_ERR_LIMIT, VX_NO_OFFSET, "compact pages: more than 2^31 - 1 pages");
        vx_result r = m->n ? top_alloc(b, m->n, &base) : VX_OK;
        if (r) return r;
        if (!m->n) base = b->n;
        for (uint32_t s = 0; s < m->n; s++) {
            uint32_t d = m->slot[2 * (size_t)s], w = m->slot[2 * (size_t)s + 1];
            if (m->lvl[s] >= 3 && (w >> 31)) w = 0x80000000u | ((w & 0x7FFFFFFFu) + pbase);
            else if (m->lvl[s] >= 3 && (((d >> 8) & ~d) & 0xFFu)) w += base;
            b->slot[2 * ((size_t)base + s)] = d, b->slot[2 * ((size_t)base + s) + 1] = w;
            b->rank[base + s] = m->rank[s];
        }
        if (m->p.page_count) {
            if (!vx_grow(b->a, (void**)&p->pages, &page_cap, (size_t)p->page_count + m->p.page_count, sizeof *p->pages))
                return vx_fail(b->err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %u pages", p->page_count + m->p.page_count);
            for (uint32_t k = 0; k < m->p.page_count; k++) {
                vx_compact_page pg = m->p.pages[k];
                pg.top_slot += base;
                p->pages[p->page_count++] = pg;
            }
        }
        if (m->p.max_page_words > p->max_page_words) p->max_page_words = m->p.max_page_words;
        vx_compact_model pm = m->p.models[0];
        if (pm.root < VX_SVO_ROOT_LEAF) pm.root += base;
        pm.attr_base = (uint32_t)b->attr_n;
        if (b->attr_n + m->attr_n > 0xFFFFFFF0u) return vx_fail(b->err, VX_ERR_LIMIT, VX_NO_OFFSET, "compact pages: the top passes 2^32 words");
        if (m->attr_n) {
            if (!vx_grow(b->a, (void**)&b->attr, &b->attr_cap, (size_t)(b->attr_n + m->attr_n), 4))
                return vx_fail(b->err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for the top");
            memcpy(b->attr + b->attr_n, m->attr, (size_t)m->attr_n * 4);
            b->attr_n += m->attr_n;
        }
        p->models[i] = pm;
        p->source_bytes += m->source_bytes;
        for (int k = 0; k < 8; k++) p->palette_used[k] |= m->palette_used[k];
        part_free(b->a, m);
    }
    return VX_OK;
}

vx_result vx_compact_page_build_reader(const vx_compact_page_desc* desc, vx_svo_model_reader* rd, vx_compact_paged* out,
                                       vx_error* err) {
    if (!rd || !out) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    vx_compact_page_desc d = desc ? *desc : (vx_compact_page_desc){0};
    uint32_t Lp = d.page_level ? d.page_level : VX_RENDER_FRAME_LEVELS;
    if (Lp < 3 || Lp > 31) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "page level %u: not in 3..31", Lp);
    const vx_svo_scene* g = vx_svo_reader_scene(rd);
    vx_compact_paged p = {.page_level = Lp, .model_count = g->model_count, .reader = rd, .block = d.block,
                          .threads = d.threads};
    if (d.alloc) p.alloc = *d.alloc;
    memcpy(p.palette, g->palette, sizeof p.palette);
    p.palette_used[0] = 1;
    pbuild b = {.p = &p, .a = &p.alloc, .err = err, .Lp = Lp};
    vx_result r = VX_OK;
    p.models = vx_calloc(b.a, g->model_count ? g->model_count : 1, sizeof *p.models);
    rjob j = {.rd = rd, .g = g, .a = b.a, .Lp = Lp, .block = d.block};
    j.parts = vx_calloc(b.a, g->model_count ? g->model_count : 1, sizeof *j.parts);
    if (!p.models || !j.parts) r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for the pages' top");
    if (!r) {
        /* the models on up to one thread a CPU: each model's build and cut on one, its decode on the
         * reader's share of them (the parts in model order after: the page numbers of the sequential cut) */
        unsigned t = d.threads ? d.threads : vx_cpu_count(VX_MAX_THREADS);
        if (t > VX_MAX_THREADS) t = VX_MAX_THREADS;
        if (t > g->model_count) t = g->model_count ? g->model_count : 1;
        pthread_mutex_init(&j.lock, NULL);
        vx_run_jobs(t, t, reader_worker, &j);
        pthread_mutex_destroy(&j.lock);
        if (j.failed) {
            r = j.err.code ? j.err.code : VX_ERR_INVALID_ARG;
            if (err) *err = j.err;
        }
    }
    if (!r) r = vx_svo_reader_finish(rd, err);
    if (!r) r = merge_parts(&b, j.parts, g->model_count);
    if (!r) r = finish_top(&b);
    for (uint32_t i = 0; j.parts && i < g->model_count; i++) part_free(b.a, &j.parts[i]);
    vx_free(b.a, j.parts);
    pbuild_free(&b);
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

/* ---- the file source's host cache --------------------------------------------------- */

/* A batch of page cuts: pages[0 .. n) sorted by page (so by model: pages
 * are numbered model by model), each cut into dst[i]; a group per model,
 * the groups cut at once on up to `threads` threads (each group one model's
 * read, decode and layout build on one thread; the reader's random access
 * and the allocator are called from several). */
typedef struct cut_group {
    uint32_t model, at, n;
    vx_result r;
    vx_error err;
} cut_group;

typedef struct cut_batch {
    const vx_compact_page_cache* pc;
    uint32_t* pages;
    uint32_t** dst;
    uint32_t n, ngroups, cap, group_cap;
    cut_group* groups;
} cut_batch;

struct vx_compact_page_cache {
    const vx_compact_paged* p; /* borrowed: the top, the page table, the reader */
    vx_allocator alloc;
    const vx_allocator* a;
    uint64_t budget;
    unsigned threads;     /* models cut at once (p->threads; 0 there: one a CPU) */
    uint32_t* first_page; /* per model, its first page (pages are numbered model by model); model_count + 1 */
    uint32_t** img;       /* per page: its image while cached, else NULL */
    uint32_t *prev, *next; /* the cached pages, most recently used first (UINT32_MAX: none) */
    uint32_t head, tail;
    uint64_t* miss;       /* scratch: the requests not cached (page << 32 | request) */
    uint32_t miss_cap;
    cut_batch now;        /* the cuts of a _get (dst: the caller's) */
    /* the cuts ahead (_prefetch) on a thread of their own, joined by the next
     * _get or _prefetch (dst: images of their own) */
    cut_batch ahead;
    pthread_t thread;
    bool running;
    vx_compact_cache_stats st;
};

static void batch_free(const vx_allocator* a, cut_batch* b, bool own_images) {
    for (uint32_t i = 0; own_images && b->dst && i < b->n; i++) vx_free(a, b->dst[i]);
    vx_free(a, b->pages);
    vx_free(a, b->dst);
    vx_free(a, b->groups);
    memset(b, 0, sizeof *b);
}

static void prefetch_join(vx_compact_page_cache* pc) {
    if (!pc->running) return;
    pthread_join(pc->thread, NULL);
    pc->running = false;
    cut_batch* b = &pc->ahead;
    for (uint32_t g = 0; g < b->ngroups; g++) {
        const cut_group* cg = &b->groups[g];
        pc->st.models++; /* read, whether or not it cut */
        if (!cg->r) {
            pc->st.file_pages += cg->n;
            continue;
        }
        /* a group that failed has no images: its pages are cut again when asked for */
        for (uint32_t i = cg->at; i < cg->at + cg->n; i++) {
            vx_free(pc->a, b->dst[i]);
            b->dst[i] = NULL;
        }
    }
}

void vx_compact_page_cache_destroy(vx_compact_page_cache* pc) {
    if (!pc) return;
    const vx_allocator* a = pc->a;
    prefetch_join(pc);
    batch_free(a, &pc->ahead, true);
    batch_free(a, &pc->now, false);
    for (uint32_t k = 0; pc->img && k < pc->p->page_count; k++) vx_free(a, pc->img[k]);
    vx_free(a, pc->img);
    vx_free(a, pc->first_page);
    vx_free(a, pc->prev);
    vx_free(a, pc->next);
    vx_free(a, pc->miss);
    vx_allocator keep = pc->alloc;
    vx_free(&keep, pc);
}

vx_result vx_compact_page_cache_create(const vx_compact_paged* p, uint64_t budget, const vx_allocator* alloc,
                                       vx_compact_page_cache** out, vx_error* err) {
    if (!p || !out || !p->reader) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument (or no reader)");
    *out = NULL;
    vx_allocator al = {0};
    if (alloc) al = *alloc;
    vx_compact_page_cache* pc = vx_calloc(alloc, 1, sizeof *pc);
    if (!pc) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for the page cache");
    pc->alloc = al;
    pc->a = alloc ? &pc->alloc : NULL;
    pc->p = p;
    pc->budget = budget;
    pc->st.budget = budget;
    pc->threads = p->threads ? p->threads : vx_cpu_count(VX_MAX_THREADS);
    if (pc->threads > VX_MAX_THREADS) pc->threads = VX_MAX_THREADS;
    pc->head = pc->tail = UINT32_MAX;
    uint32_t P = p->page_count ? p->page_count : 1;
    pc->img = vx_calloc(pc->a, P, sizeof *pc->img);
    pc->prev = vx_alloc(pc->a, (size_t)P * 4);
    pc->next = vx_alloc(pc->a, (size_t)P * 4);
    pc->first_page = vx_alloc(pc->a, ((size_t)p->model_count + 1) * 4);
    if (!pc->img || !pc->prev || !pc->next || !pc->first_page) {
        vx_compact_page_cache_destroy(pc);
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for the page cache of %u pages", p->page_count);
    }
    for (uint32_t i = 0, k = 0; i <= p->model_count; i++) {
        while (k < p->page_count && p->pages[k].model < i) k++;
        pc->first_page[i] = k;
    }
    *out = pc;
    return VX_OK;
}

static int cmp_u64(const void* x, const void* y) {
    uint64_t a = *(const uint64_t*)x, b = *(const uint64_t*)y;
    return (a > b) - (a < b);
}

static void lru_unlink(vx_compact_page_cache* pc, uint32_t k) {
    uint32_t a = pc->prev[k], b = pc->next[k];
    if (a != UINT32_MAX) pc->next[a] = b;
    else pc->head = b;
    if (b != UINT32_MAX) pc->prev[b] = a;
    else pc->tail = a;
}

static void lru_front(vx_compact_page_cache* pc, uint32_t k) {
    pc->prev[k] = UINT32_MAX, pc->next[k] = pc->head;
    if (pc->head != UINT32_MAX) pc->prev[pc->head] = k;
    pc->head = k;
    if (pc->tail == UINT32_MAX) pc->tail = k;
}

/* Page k's image (words) into the cache, the least recently used pages out
 * until it fits; an image larger than the budget is not kept. */
static void cache_put(vx_compact_page_cache* pc, uint32_t k, const uint32_t* words) {
    uint64_t bytes = 4ull * pc->p->pages[k].words;
    if (pc->img[k] || bytes > pc->budget) return;
    while (pc->st.bytes + bytes > pc->budget && pc->tail != UINT32_MAX) {
        uint32_t old = pc->tail;
        lru_unlink(pc, old);
        vx_free(pc->a, pc->img[old]);
        pc->img[old] = NULL;
        pc->st.bytes -= 4ull * pc->p->pages[old].words;
        pc->st.evictions++;
    }
    uint32_t* c = vx_alloc(pc->a, (size_t)bytes);
    if (!c) return; /* a cache that cannot grow: the page comes from the file again next time */
    memcpy(c, words, (size_t)bytes);
    pc->img[k] = c;
    lru_front(pc, k);
    pc->st.bytes += bytes;
    if (pc->st.bytes > pc->st.peak_bytes) pc->st.peak_bytes = pc->st.bytes;
}

/* Pages pages[0 .. n) of model mi (each once or more, any order), cut into
 * dst[i] from the model read again from the file: the model's layout, its
 * top walked to number its pages as the first pass did, then the images of
 * the requested ones, checked against the page table. Reads pc, never
 * writes it (the cuts of a batch run on several threads). */
static vx_result cut_model_pages(const vx_compact_page_cache* pc, uint32_t mi, const uint32_t* pages, uint32_t* const* dst,
                                 uint32_t n, vx_error* err) {
    const vx_compact_paged* P = pc->p;
    const vx_svo_scene* g = vx_svo_reader_scene(P->reader);
    vx_svo_model m;
    vx_result r = vx_svo_reader_model(P->reader, mi, &m, err);
    if (r) return r;
    vx_compact_scene c1;
    r = model_layout(g, &m, P->block, pc->a, &c1, err);
    vx_svo_model_free(g->alloc, &m);
    if (r) return r;
    vx_compact_paged scratch = {.page_level = P->page_level, .model_count = 1};
    if (pc->a) scratch.alloc = *pc->a;
    pbuild b = {.p = &scratch, .a = &scratch.alloc, .err = err, .Lp = P->page_level};
    const vx_compact_model* cm = &c1.models[0];
    uint32_t t;
    if (!(r = use_layout(&b, &c1, 0)) && cm->root < VX_SVO_ROOT_LEAF && cm->depth > P->page_level &&
        !(r = top_alloc(&b, 1, &t))) {
        uint32_t zero[3] = {0, 0, 0};
        r = fill(&b, mi, true, t, cm->root, cm->depth, zero, 0, cm->voxels);
    }
    uint32_t base = pc->first_page[mi], have = pc->first_page[mi + 1] - base;
    if (!r && scratch.page_count != have)
        r = vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "model %u has %u pages, the first pass cut %u (the file changed)", mi,
                    scratch.page_count, have);
    for (uint32_t i = 0; !r && i < n; i++) {
        uint32_t k = pages[i], local = k - base;
        const vx_compact_page* was = &P->pages[k];
        if (k < base || local >= have) {
            r = vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "page %u is not a page of model %u", k, mi);
            break;
        }
        if ((r = page_image(&b, local))) break;
        const vx_compact_page* now = &scratch.pages[local];
        if (now->words != was->words || now->n3 != was->n3 || now->slots != was->slots || now->cells != was->cells ||
            now->first != was->first || now->rgba != was->rgba || memcmp(now->cube, was->cube, sizeof now->cube)) {
            r = vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "model %u: page %u is not the page the first pass cut (the file changed)",
                        mi, k);
            break;
        }
        b.img[2] = k; /* the scene's page number */
        memcpy(dst[i], b.img, 4ull * was->words);
    }
    pbuild_free(&b);
    vx_free(b.a, scratch.pages);
    vx_compact_free(&c1);
    return r;
}

/* Room in b for n cuts (and as many groups); its lists emptied. */
static bool batch_reserve(const vx_allocator* a, cut_batch* b, uint32_t n) {
    b->n = b->ngroups = 0;
    if (n <= b->cap) return true;
    vx_free(a, b->pages), vx_free(a, b->dst), vx_free(a, b->groups);
    b->cap = 0;
    b->pages = vx_alloc(a, (size_t)n * 4);
    b->dst = vx_calloc(a, n, sizeof *b->dst);
    b->groups = vx_alloc(a, (size_t)n * sizeof *b->groups);
    if (!b->pages || !b->dst || !b->groups) return false;
    b->cap = n;
    return true;
}

/* Appends page k's cut (into dst) to b, whose pages come in page order. */
static void batch_add(const vx_compact_page_cache* pc, cut_batch* b, uint32_t k, uint32_t* dst) {
    uint32_t mi = pc->p->pages[k].model;
    if (!b->ngroups || b->groups[b->ngroups - 1].model != mi)
        b->groups[b->ngroups++] = (cut_group){.model = mi, .at = b->n};
    b->groups[b->ngroups - 1].n++;
    b->pages[b->n] = k, b->dst[b->n++] = dst;
}

static void cut_worker(void* ctx, unsigned thread, uint32_t i) {
    (void)thread;
    cut_batch* b = ctx;
    cut_group* g = &b->groups[i];
    memset(&g->err, 0, sizeof g->err);
    g->r = cut_model_pages(b->pc, g->model, b->pages + g->at, b->dst + g->at, g->n, &g->err);
}

static void batch_run(cut_batch* b) {
    unsigned t = b->pc->threads < b->ngroups ? b->pc->threads : b->ngroups;
    vx_run_jobs(t ? t : 1, b->ngroups, cut_worker, b);
}

static void* prefetch_main(void* ctx) {
    batch_run(ctx);
    return NULL;
}

void vx_compact_page_cache_prefetch(vx_compact_page_cache* pc, const uint32_t* pages, uint32_t n) {
    if (!pc) return;
    prefetch_join(pc);
    batch_free(pc->a, &pc->ahead, true);
    if (!n || !pages || n > pc->p->page_count) return;
    uint32_t* k = vx_alloc(pc->a, (size_t)n * 4);
    if (!k) return;
    uint32_t m = 0;
    for (uint32_t i = 0; i < n; i++)
        if (pages[i] < pc->p->page_count && !pc->img[pages[i]]) k[m++] = pages[i];
    /* by page (so by model: a group a model), each page once */
    uint64_t* sorted = vx_alloc(pc->a, (size_t)(m ? m : 1) * 8);
    bool ok = sorted && batch_reserve(pc->a, &pc->ahead, m);
    for (uint32_t i = 0; ok && i < m; i++) sorted[i] = k[i];
    if (ok) qsort(sorted, m, 8, cmp_u64);
    for (uint32_t i = 0; ok && i < m; i++) {
        if (i && sorted[i] == sorted[i - 1]) continue;
        uint32_t* img = vx_alloc(pc->a, 4ull * pc->p->pages[sorted[i]].words);
        if (!img) {
            ok = false;
            break;
        }
        batch_add(pc, &pc->ahead, (uint32_t)sorted[i], img);
    }
    vx_free(pc->a, sorted);
    vx_free(pc->a, k);
    pc->ahead.pc = pc;
    if (ok && pc->ahead.ngroups && !pthread_create(&pc->thread, NULL, prefetch_main, &pc->ahead)) pc->running = true;
    else batch_free(pc->a, &pc->ahead, true);
}

/* The image of page k cut ahead, or NULL (not cut ahead, or its group
 * failed: prefetch_join dropped its images). */
static const uint32_t* ahead_image(const vx_compact_page_cache* pc, uint32_t k) {
    const cut_batch* b = &pc->ahead;
    uint32_t lo = 0, hi = b->n;
    while (lo < hi) {
        uint32_t mid = lo + (hi - lo) / 2;
        if (b->pages[mid] < k) lo = mid + 1;
        else hi = mid;
    }
    return lo < b->n && b->pages[lo] == k ? b->dst[lo] : NULL;
}

vx_result vx_compact_page_cache_get(vx_compact_page_cache* pc, const uint32_t* pages, uint32_t n, uint32_t* const* dst,
                                    vx_error* err) {
    if (!pc || (n && (!pages || !dst))) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    const vx_compact_paged* P = pc->p;
    prefetch_join(pc);
    vx_result r = VX_OK;
    if (n > pc->miss_cap) {
        vx_free(pc->a, pc->miss);
        pc->miss_cap = 0;
        if (!(pc->miss = vx_alloc(pc->a, (size_t)n * 8))) r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory");
        else pc->miss_cap = n;
    }
    if (!r && !batch_reserve(pc->a, &pc->now, n)) r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory");
    uint32_t nm = 0;
    for (uint32_t i = 0; !r && i < n; i++) {
        uint32_t k = pages[i];
        if (k >= P->page_count) {
            r = vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "no page %u", k);
        } else if (pc->img[k]) {
            memcpy(dst[i], pc->img[k], 4ull * P->pages[k].words);
            lru_unlink(pc, k);
            lru_front(pc, k);
            pc->st.hits++;
        } else {
            pc->miss[nm++] = (uint64_t)k << 32 | i;
        }
    }
    /* by page, so by model: each model read once for its requests; the
     * pages cut ahead copied, the others cut now, the models at once */
    if (!r) qsort(pc->miss, nm, 8, cmp_u64);
    pc->now.pc = pc;
    for (uint32_t j = 0; !r && j < nm; j++) {
        uint32_t k = (uint32_t)(pc->miss[j] >> 32), i = (uint32_t)pc->miss[j];
        const uint32_t* a = ahead_image(pc, k);
        if (a) {
            memcpy(dst[i], a, 4ull * P->pages[k].words);
            pc->st.prefetched++;
        } else {
            batch_add(pc, &pc->now, k, dst[i]);
        }
    }
    if (!r) batch_run(&pc->now);
    /* into the cache in page order (as one thread cutting model after model
     * would put them), up to the first model that failed */
    uint32_t g = 0, fail = UINT32_MAX;
    for (; !r && g < pc->now.ngroups; g++) {
        pc->st.models++;
        if (pc->now.groups[g].r && fail == UINT32_MAX) fail = g;
    }
    for (uint32_t j = 0, at = 0, gi = 0; !r && j < nm; j++) {
        uint32_t k = (uint32_t)(pc->miss[j] >> 32), i = (uint32_t)pc->miss[j];
        if (at < pc->now.n && pc->now.pages[at] == k && pc->now.dst[at] == dst[i]) {
            while (gi + 1 < pc->now.ngroups && pc->now.groups[gi + 1].at <= at) gi++;
            at++;
            if (fail != UINT32_MAX && gi >= fail) break;
            pc->st.file_pages++;
        }
        cache_put(pc, k, dst[i]);
    }
    if (!r && fail != UINT32_MAX) {
        r = pc->now.groups[fail].r;
        if (err) *err = pc->now.groups[fail].err;
    }
    batch_free(pc->a, &pc->ahead, true);
    return r;
}

void vx_compact_page_cache_stats(const vx_compact_page_cache* pc, vx_compact_cache_stats* out) {
    if (!out) return;
    memset(out, 0, sizeof *out);
    if (pc) *out = pc->st;
}
