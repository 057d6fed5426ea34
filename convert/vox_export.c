/* convert/vox_export.c - svo scene -> MagicaVoxel scene (svo_info --to-vox).
 *
 * The inverse of vx_conv_vox for scenes of at most 255 colours (more: the
 * quantizer below, on request) whose instance matrices are signed
 * permutations with integer translations.
 * A model of at most 256 cells per side is one .vox model. A larger one is
 * split as MagicaVoxel exporters do: 256^3 tiles from its corner, each
 * tile that holds cells one .vox model (a piece, trimmed to its cells'
 * extent); each instance of it becomes a group whose transform places the
 * big model (rotation, mirror and translation as an unsplit model's, pivot
 * at floor(size/2)), with one shape per piece, translated within the group
 * so that every cell lands where it was. Instances of one big model share
 * its pieces. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "convert/convert.h"

/* ---- colours: a set of RGBA8 colours and the quantizer (more than 255) ----------------- */

/* Distinct RGBA8 colours with their cell counts and, once quantized, their
 * palette entries (open addressing, grown at half full). */
typedef struct colour_set {
    const vx_allocator* a;
    uint32_t* key;
    uint64_t* count;
    uint8_t* entry;
    uint8_t* used;
    size_t cap, n;
    bool nomem;
} colour_set;

static size_t colour_slot(const colour_set* s, uint32_t c) {
    uint32_t h = c;
    h ^= h >> 16, h *= 0x7feb352du, h ^= h >> 15, h *= 0x846ca68bu, h ^= h >> 16;
    size_t i = h & (s->cap - 1);
    while (s->used[i] && s->key[i] != c) i = (i + 1) & (s->cap - 1);
    return i;
}

static void colour_set_free(colour_set* s) {
    vx_free(s->a, s->key);
    vx_free(s->a, s->count);
    vx_free(s->a, s->entry);
    vx_free(s->a, s->used);
    s->key = NULL, s->count = NULL, s->entry = NULL, s->used = NULL;
    s->cap = s->n = 0;
}

static bool colour_set_grow(colour_set* s) {
    colour_set g = {.a = s->a, .cap = s->cap ? 2 * s->cap : 1024};
    g.key = (uint32_t*)vx_calloc(g.a, g.cap, sizeof *g.key);
    g.count = (uint64_t*)vx_calloc(g.a, g.cap, sizeof *g.count);
    g.entry = (uint8_t*)vx_calloc(g.a, g.cap, 1);
    g.used = (uint8_t*)vx_calloc(g.a, g.cap, 1);
    if (!g.key || !g.count || !g.entry || !g.used) {
        colour_set_free(&g);
        return false;
    }
    for (size_t i = 0; i < s->cap; i++) {
        if (!s->used[i]) continue;
        size_t j = colour_slot(&g, s->key[i]);
        g.used[j] = 1, g.key[j] = s->key[i], g.count[j] = s->count[i], g.entry[j] = s->entry[i];
    }
    g.n = s->n;
    colour_set_free(s);
    *s = g;
    return true;
}

static bool colour_add(colour_set* s, uint32_t c) {
    if (2 * (s->n + 1) > s->cap && !colour_set_grow(s)) return false;
    size_t i = colour_slot(s, c);
    if (!s->used[i]) s->used[i] = 1, s->key[i] = c, s->n++;
    s->count[i]++;
    return true;
}

typedef struct gather_ctx {
    const vx_svo_model* m;
    colour_set* set;
} gather_ctx;

static bool gather_cell(void* user, uint32_t x, uint32_t y, uint32_t z, uint32_t attr) {
    (void)x, (void)y, (void)z;
    gather_ctx* g = (gather_ctx*)user;
    if (colour_add(g->set, g->m->rgba[attr])) return true;
    g->set->nomem = true;
    return false;
}

static uint32_t channel(uint32_t rgba, int k) { return (rgba >> (8 * k)) & 0xFFu; }

static uint32_t colour_dist2(uint32_t a, uint32_t b) {
    uint32_t d2 = 0;
    for (int k = 0; k < 4; k++) {
        int32_t d = (int32_t)channel(a, k) - (int32_t)channel(b, k);
        d2 += (uint32_t)(d * d);
    }
    return d2;
}

/* Median cut: a colour, its cell count and its sort key (the channel cut, then the colour). */
typedef struct qcolour {
    uint64_t key;
    uint64_t w;
    uint32_t rgba;
} qcolour;

static int cmp_qcolour(const void* a, const void* b) {
    uint64_t x = ((const qcolour*)a)->key, y = ((const qcolour*)b)->key;
    return x < y ? -1 : x > y; /* distinct colours: a total order, the same result every run */
}

typedef struct qbox {
    size_t lo, hi;  /* q[lo, hi) */
    int axis;       /* its widest channel */
    uint32_t range; /* that channel's max - min */
    uint64_t w;     /* its cells */
} qbox;

static void box_measure(const qcolour* q, qbox* b) {
    uint32_t mn[4] = {255, 255, 255, 255}, mx[4] = {0, 0, 0, 0};
    b->w = 0;
    for (size_t i = b->lo; i < b->hi; i++) {
        b->w += q[i].w;
        for (int k = 0; k < 4; k++) {
            uint32_t c = channel(q[i].rgba, k);
            if (c < mn[k]) mn[k] = c;
            if (c > mx[k]) mx[k] = c;
        }
    }
    b->axis = 0, b->range = 0;
    for (int k = 0; k < 4; k++)
        if (mx[k] - mn[k] > b->range) b->axis = k, b->range = mx[k] - mn[k];
}

/* Up to `want` colours for q[0, n): boxes split at the weighted median of
 * their widest channel, the widest box first (of equally wide ones, the one
 * of most cells), until there are `want` boxes or none holds two colours;
 * each box gives its cell-weighted mean. */
static uint32_t median_cut(qcolour* q, size_t n, uint32_t want, qbox* box, uint32_t* out) {
    if (!n || !want) return 0;
    uint32_t nb = 1;
    box[0] = (qbox){0, n, 0, 0, 0};
    box_measure(q, &box[0]);
    while (nb < want) {
        uint32_t pick = UINT32_MAX;
        for (uint32_t i = 0; i < nb; i++)
            if (box[i].range > 0 &&
                (pick == UINT32_MAX || box[i].range > box[pick].range || (box[i].range == box[pick].range && box[i].w > box[pick].w)))
                pick = i;
        if (pick == UINT32_MAX) break;
        qbox* b = &box[pick];
        for (size_t i = b->lo; i < b->hi; i++) q[i].key = (uint64_t)channel(q[i].rgba, b->axis) << 32 | q[i].rgba;
        qsort(q + b->lo, b->hi - b->lo, sizeof *q, cmp_qcolour);
        uint64_t total = 0, acc = 0;
        for (size_t i = b->lo; i < b->hi; i++) total += q[i].w;
        size_t cut = b->lo + 1;
        for (size_t i = b->lo; i + 1 < b->hi; i++) {
            acc += q[i].w;
            cut = i + 1;
            if (2 * acc >= total) break;
        }
        box[nb] = (qbox){cut, b->hi, 0, 0, 0};
        b->hi = cut;
        box_measure(q, b);
        box_measure(q, &box[nb]);
        nb++;
    }
    for (uint32_t i = 0; i < nb; i++) {
        uint64_t sum[4] = {0, 0, 0, 0}, w = 0;
        for (size_t j = box[i].lo; j < box[i].hi; j++) {
            uint64_t cw = q[j].w ? q[j].w : 1;
            for (int k = 0; k < 4; k++) sum[k] += cw * channel(q[j].rgba, k);
            w += cw;
        }
        uint32_t c = 0;
        for (int k = 0; k < 4; k++) c |= (uint32_t)((sum[k] + w / 2) / w) << (8 * k);
        out[i] = c;
    }
    return nb;
}

/* What quantizing gave: the entries made (taken, pal as the export fills
 * them) and every colour's entry in set. */
typedef struct quantized {
    colour_set set;
    uint32_t pal[256];
    uint8_t taken[256];
} quantized;

/* The palette models' entries: base (the scene's palette, else the
 * default with white at 1), and which of them some palette model uses. */
static void fixed_entries(const vx_svo_scene* in, uint32_t base[256], uint32_t pal[256], uint8_t taken[256]) {
    if (in->has_palette) memcpy(base, in->palette, 256 * sizeof *base);
    else {
        memcpy(base, vx_vox_default_palette, 256 * sizeof *base);
        base[1] = 0xFFFFFFFFu; /* geometry only: white */
    }
    memset(pal, 0, 256 * sizeof *pal);
    memset(taken, 0, 256);
    for (uint32_t i = 0; i < in->model_count; i++) {
        const vx_svo_model* m = &in->models[i];
        /* geometry only: its cells are entry 1, which no RGBA8 colour may then take */
        if (!(m->attrs & (VX_ATTR_PALETTE | VX_ATTR_RGBA8)) && m->voxel_count) taken[1] = 1, pal[1] = base[1];
        if (!(m->attrs & VX_ATTR_PALETTE) || !m->palette) continue;
        for (uint32_t k = 0; k < m->attr_count; k++) {
            uint8_t e = m->palette[k] ? m->palette[k] : 1;
            taken[e] = 1, pal[e] = base[e];
        }
    }
}

typedef struct export_ctx {
    const vx_svo_scene* s;
    const vx_svo_model* m;
    uint8_t* xyzi;
    uint32_t n, cap;
    uint32_t* pal;  /* the palette made, by index: palette models' entries, then RGBA8 models' colours */
    uint8_t* taken; /* entries of pal in use (palette models' voxels, colours given) */
    bool too_many_colors;
    const colour_set* map; /* quantized: every RGBA8 colour's entry */
} export_ctx;

/* An RGBA8 colour's entry: quantized, the one the quantizer chose; else
 * one of that colour in use, else the first free (a scene may mix palette
 * and RGBA8 models: svo_view's add of a file with another palette). */
static uint8_t color_index(export_ctx* c, uint32_t rgba) {
    if (c->map) {
        size_t i = colour_slot(c->map, rgba);
        if (c->map->used[i]) return c->map->entry[i];
        c->too_many_colors = true; /* cannot happen: the same cells were gathered */
        return 1;
    }
    for (uint32_t i = 1; i < 256; i++)
        if (c->taken[i] && c->pal[i] == rgba) return (uint8_t)i;
    for (uint32_t i = 1; i < 256; i++)
        if (!c->taken[i]) {
            c->taken[i] = 1, c->pal[i] = rgba;
            return (uint8_t)i;
        }
    c->too_many_colors = true;
    return 1;
}

/* A voxel's colour index in the .vox palette. */
static uint8_t voxel_index(export_ctx* c, uint32_t attr) {
    if (c->m->attrs & VX_ATTR_PALETTE) return c->m->palette[attr] ? c->m->palette[attr] : 1;
    if (c->m->attrs & VX_ATTR_RGBA8) return color_index(c, c->m->rgba[attr]);
    return 1;
}

static bool collect(void* user, uint32_t x, uint32_t y, uint32_t z, uint32_t attr) {
    export_ctx* c = (export_ctx*)user;
    if (c->n == c->cap) return false; /* cannot happen: cap is the model's voxel count */
    uint8_t* v = c->xyzi + 4 * (size_t)c->n++;
    v[0] = (uint8_t)x;
    v[1] = (uint8_t)y;
    v[2] = (uint8_t)z;
    v[3] = voxel_index(c, attr);
    return true;
}

/* ---- a model over 256 cells a side, in pieces ------------------------------------------- */

#define VOX_SIDE 256u

/* One 256^3 tile of a big model that holds cells. */
typedef struct piece {
    uint64_t tile;  /* tz << 42 | ty << 21 | tx: tiles in z, y, x order */
    uint32_t lo[3]; /* the extent of its cells, in the model's cells */
    uint32_t hi[3];
    uint64_t count; /* its cells */
} piece;

typedef struct split_model {
    piece* p; /* sorted by tile */
    size_t n, cap;
    uint32_t first; /* .vox model of p[0]; p[k] is first + k */
} split_model;

static uint64_t tile_of(uint32_t x, uint32_t y, uint32_t z) {
    return (uint64_t)(z / VOX_SIDE) << 42 | (uint64_t)(y / VOX_SIDE) << 21 | (uint64_t)(x / VOX_SIDE);
}

typedef struct count_ctx {
    const vx_allocator* a;
    split_model* sm;
    bool nomem;
} count_ctx;

/* The first pass: the tiles and each one's count and extent. Cells come in
 * Morton order from the model's corner, so a 256-aligned tile's come in one
 * run; a tile met again (not expected) is merged after the sort. */
static bool count_cell(void* user, uint32_t x, uint32_t y, uint32_t z, uint32_t attr) {
    (void)attr;
    count_ctx* c = (count_ctx*)user;
    split_model* sm = c->sm;
    uint64_t t = tile_of(x, y, z);
    uint32_t v[3] = {x, y, z};
    if (!sm->n || sm->p[sm->n - 1].tile != t) {
        if (sm->n == sm->cap) {
            size_t cap = sm->cap ? 2 * sm->cap : 16;
            piece* p = (piece*)vx_calloc(c->a, cap, sizeof *p);
            if (!p) {
                c->nomem = true;
                return false;
            }
            if (sm->n) memcpy(p, sm->p, sm->n * sizeof *p);
            vx_free(c->a, sm->p);
            sm->p = p, sm->cap = cap;
        }
        piece* q = &sm->p[sm->n++];
        q->tile = t, q->count = 0;
        memcpy(q->lo, v, sizeof v);
        memcpy(q->hi, v, sizeof v);
    }
    piece* q = &sm->p[sm->n - 1];
    q->count++;
    for (int k = 0; k < 3; k++) {
        if (v[k] < q->lo[k]) q->lo[k] = v[k];
        if (v[k] > q->hi[k]) q->hi[k] = v[k];
    }
    return true;
}

static int cmp_piece(const void* a, const void* b) {
    uint64_t x = ((const piece*)a)->tile, y = ((const piece*)b)->tile;
    return x < y ? -1 : x > y;
}

/* Sorted by tile, a tile's runs merged into one piece. */
static void sort_pieces(split_model* sm) {
    if (sm->n > 1) qsort(sm->p, sm->n, sizeof *sm->p, cmp_piece);
    size_t o = 0;
    for (size_t i = 0; i < sm->n; i++) {
        piece* q = &sm->p[i];
        if (o && sm->p[o - 1].tile == q->tile) {
            piece* r = &sm->p[o - 1];
            r->count += q->count;
            for (int k = 0; k < 3; k++) {
                if (q->lo[k] < r->lo[k]) r->lo[k] = q->lo[k];
                if (q->hi[k] > r->hi[k]) r->hi[k] = q->hi[k];
            }
        } else {
            sm->p[o++] = *q;
        }
    }
    sm->n = o;
}

typedef struct fill_ctx {
    export_ctx e;
    const split_model* sm;
    vx_vox_model* models; /* the pieces' .vox models, models[k] for sm->p[k] */
    size_t last;          /* the piece of the last cell */
} fill_ctx;

/* The second pass: each cell into its piece, at its place in the piece. */
static bool fill_cell(void* user, uint32_t x, uint32_t y, uint32_t z, uint32_t attr) {
    fill_ctx* c = (fill_ctx*)user;
    uint64_t t = tile_of(x, y, z);
    const piece* p = c->sm->p;
    if (p[c->last].tile != t) {
        size_t lo = 0, hi = c->sm->n;
        while (lo < hi) {
            size_t mid = lo + (hi - lo) / 2;
            if (p[mid].tile < t) lo = mid + 1;
            else hi = mid;
        }
        if (lo == c->sm->n || p[lo].tile != t) return false; /* cannot happen: the first pass met every tile */
        c->last = lo;
    }
    const piece* q = &p[c->last];
    vx_vox_model* vm = &c->models[c->last];
    if (vm->voxel_count == q->count) return false; /* cannot happen: the first pass counted it */
    uint8_t* v = vm->xyzi + 4 * (size_t)vm->voxel_count++;
    v[0] = (uint8_t)(x - q->lo[0]);
    v[1] = (uint8_t)(y - q->lo[1]);
    v[2] = (uint8_t)(z - q->lo[2]);
    v[3] = voxel_index(&c->e, attr);
    return true;
}

static bool fits(const vx_svo_model* m) { return m->size[0] <= VOX_SIDE && m->size[1] <= VOX_SIDE && m->size[2] <= VOX_SIDE; }

static bool is_int(double v) { return isfinite(v) && v == floor(v) && fabs(v) < 2147483647.0; }

/* Instance i of frame f (si) as a .vox instance: the MagicaVoxel pivot undone,
 * whole-cell translations and signed permutations only. */
static vx_result export_instance(const vx_svo_scene* in, const vx_svo_instance* si, uint32_t i, uint32_t f, vx_vox_instance* vi,
                                 vx_error* err) {
    if (si->model >= in->model_count)
        return vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "frame %u instance %u: model %u out of range", f, i, si->model);
    const uint32_t* sz = in->models[si->model].size;
    double c[3] = {(double)(sz[0] / 2), (double)(sz[1] / 2), (double)(sz[2] / 2)};
    for (int row = 0; row < 3; row++) {
        double rc = 0;
        for (int col = 0; col < 3; col++) {
            double e = si->xform[row * 4 + col];
            if (e != 0.0 && e != 1.0 && e != -1.0)
                return vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET, "frame %u instance %u: matrix entry %g is not a .vox rotation", f,
                               i, e);
            vi->rot[row * 3 + col] = (int32_t)e;
            rc += e * c[col];
        }
        double t = si->xform[row * 4 + 3] + rc;
        if (!is_int(t))
            return vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET, "frame %u instance %u: translation %g is not a whole cell", f, i,
                           si->xform[row * 4 + 3]);
        vi->t[row] = (int32_t)t;
    }
    uint8_t b;
    if (!vx_vox_rot_to_byte(vi->rot, &b))
        return vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET, "frame %u instance %u: matrix is not a signed permutation", f, i);
    vi->model = si->model;
    vi->layer = si->layer < in->layer_count ? (int32_t)si->layer : -1;
    vi->hidden = (si->flags & VX_SVO_INSTANCE_HIDDEN) != 0;
    snprintf(vi->name, sizeof vi->name, "%s", si->name);
    return VX_OK;
}

/* The group a split model's instance becomes: the instance's transform,
 * name and hidden flag (the layer stays with the pieces, so that a hidden
 * layer hides them as their own layer and not as a node above them). */
static void group_of(const vx_vox_instance* vi, vx_vox_group* g) {
    memset(g, 0, sizeof *g);
    memcpy(g->rot, vi->rot, sizeof g->rot);
    memcpy(g->t, vi->t, sizeof g->t);
    g->layer = -1;
    g->hidden = vi->hidden;
    memcpy(g->name, vi->name, sizeof g->name);
}

/* The export; qz: the quantized colours (NULL: exact, *too_many set when
 * they do not fit). */
static vx_result export_scene(const vx_svo_scene* in, const vx_allocator* a, const quantized* qz, vx_vox_scene* out,
                              bool* too_many, vx_error* err) {
    vx_vox_scene v;
    memset(&v, 0, sizeof v);
    v.alloc = a;
    v.version = 150;
    vx_result r = VX_OK;
    bool uses_rgba = false, uses_palette = false;
    /* the palette models' entries first: RGBA8 colours take the others */
    uint32_t base[256], pal[256];
    uint8_t taken[256];
    fixed_entries(in, base, pal, taken);
    if (qz) memcpy(pal, qz->pal, sizeof pal), memcpy(taken, qz->taken, sizeof taken);

    /* the pieces of the models over 256 cells a side (first pass), and the
     * .vox models: sm[i].first .. + n for model i (n = 1 unless split) */
    uint32_t M = in->model_count;
    split_model* sm = (split_model*)vx_calloc(a, M ? M : 1, sizeof *sm);
    if (!sm) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory");
    uint64_t vox_models = 0;
    for (uint32_t i = 0; i < M; i++) {
        const vx_svo_model* m = &in->models[i];
        sm[i].first = (uint32_t)vox_models;
        if (fits(m)) {
            if (m->voxel_count > 256u * 256u * 256u) {
                r = vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "model %u claims %llu voxels", i,
                            (unsigned long long)m->voxel_count);
                goto fail;
            }
            vox_models++;
            continue;
        }
        count_ctx cc = {a, &sm[i], false};
        r = vx_svo_decode_model(m, count_cell, &cc, err);
        if (r == VX_OK && cc.nomem) r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "model %u: out of memory for its pieces", i);
        if (r != VX_OK) goto fail;
        sort_pieces(&sm[i]);
        vox_models += sm[i].n;
        if (vox_models > VX_VOX_MAX_INSTANCES) {
            r = vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET,
                        "model %u is %ux%ux%u: its pieces make more than %u .vox models", i, m->size[0], m->size[1],
                        m->size[2], VX_VOX_MAX_INSTANCES);
            goto fail;
        }
    }
    /* the shapes and groups the instances become (frame 0's models; the
     * others must not change a split model: one group per instance) */
    uint32_t frames = vx_svo_scene_frames(in), I = in->instance_count;
    uint64_t vox_instances = 0;
    uint32_t groups = 0;
    for (uint32_t f = 0; f < frames; f++) {
        const vx_svo_instance* fi = vx_svo_scene_frame_instances(in, f);
        const vx_svo_instance* f0 = vx_svo_scene_frame_instances(in, 0);
        for (uint32_t i = 0; i < I; i++) {
            uint32_t m = fi[i].model, m0 = f0[i].model;
            if (m >= M) {
                r = vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "frame %u instance %u: model %u out of range", f, i, m);
                goto fail;
            }
            if (f == 0) {
                bool split = !fits(&in->models[m]);
                vox_instances += split ? sm[m].n : 1;
                groups += split;
            } else if (m != m0 && (!fits(&in->models[m]) || !fits(&in->models[m0]))) {
                const vx_svo_model* big = fits(&in->models[m]) ? &in->models[m0] : &in->models[m];
                r = vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET,
                            "frame %u instance %u: model %u, frame 0 model %u; a model over 256 cells a side (%ux%ux%u) "
                            "is written as a group of pieces, which .vox cannot swap for another model between frames",
                            f, i, m, m0, big->size[0], big->size[1], big->size[2]);
                goto fail;
            }
        }
    }
    if (vox_instances > VX_VOX_MAX_INSTANCES) {
        r = vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET,
                    "%u instances of models split into 256^3 pieces place %llu shapes, more than the %u a .vox read takes", I,
                    (unsigned long long)vox_instances, VX_VOX_MAX_INSTANCES);
        goto fail;
    }

    v.models = (vx_vox_model*)vx_calloc(a, vox_models ? (size_t)vox_models : 1, sizeof *v.models);
    v.instances = (vx_vox_instance*)vx_calloc(a, vox_instances ? (size_t)vox_instances : 1, sizeof *v.instances);
    v.groups = (vx_vox_group*)vx_calloc(a, groups ? groups : 1, sizeof *v.groups);
    v.layers = (vx_vox_layer*)vx_calloc(a, in->layer_count ? in->layer_count : 1, sizeof *v.layers);
    v.materials = (vx_vox_material*)vx_calloc(a, in->material_count ? in->material_count : 1, sizeof *v.materials);
    if (!v.models || !v.instances || !v.groups || !v.layers || !v.materials) {
        r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory");
        goto fail;
    }
    v.model_count = (uint32_t)vox_models; /* each xyzi NULL until made: freed as made */
    for (uint32_t i = 0; i < M; i++) {
        const vx_svo_model* m = &in->models[i];
        export_ctx c = {in, m, NULL, 0, 0, pal, taken, false, qz ? &qz->set : NULL};
        if (fits(m)) {
            uint32_t n = (uint32_t)m->voxel_count;
            vx_vox_model* vm = &v.models[sm[i].first];
            memcpy(vm->size, m->size, sizeof vm->size);
            vm->xyzi = (uint8_t*)vx_calloc(a, n ? n : 1, 4);
            if (!vm->xyzi) {
                r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory");
                goto fail;
            }
            c.xyzi = vm->xyzi, c.cap = n;
            r = vx_svo_decode_model(m, collect, &c, err);
            vm->voxel_count = c.n;
        } else {
            for (size_t k = 0; k < sm[i].n; k++) {
                const piece* q = &sm[i].p[k];
                vx_vox_model* vm = &v.models[sm[i].first + k];
                for (int d = 0; d < 3; d++) vm->size[d] = q->hi[d] - q->lo[d] + 1;
                vm->xyzi = (uint8_t*)vx_calloc(a, (size_t)q->count, 4); /* 1 .. 256^3 */
                if (!vm->xyzi) {
                    r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "model %u: out of memory for piece %zu", i, k);
                    goto fail;
                }
            }
            fill_ctx fc = {c, &sm[i], &v.models[sm[i].first], 0};
            if (sm[i].n) r = vx_svo_decode_model(m, fill_cell, &fc, err);
            c.too_many_colors = fc.e.too_many_colors;
            for (size_t k = 0; r == VX_OK && k < sm[i].n; k++)
                if (v.models[sm[i].first + k].voxel_count != sm[i].p[k].count)
                    r = vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "model %u: decoded twice, gave other cells", i);
        }
        if (r != VX_OK) goto fail;
        if (c.too_many_colors) {
            *too_many = true;
            r = vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET, "more than 255 distinct colours do not fit a .vox palette");
            goto fail;
        }
        if (m->attrs & VX_ATTR_PALETTE) uses_palette = true;
        else if (m->attrs & VX_ATTR_RGBA8) uses_rgba = true;
    }
    /* RGBA8 only: the colours given, in the order met; with palette models
     * too, their entries and the colours given in the others */
    for (uint32_t i = 0; i < 256; i++) v.palette[i] = uses_rgba && !uses_palette ? pal[i] : taken[i] ? pal[i] : base[i];
    v.has_rgba = true;

    for (uint32_t i = 0; i < in->layer_count; i++) {
        v.layers[i].id = (int32_t)i;
        v.layers[i].hidden = (in->layers[i].flags & VX_SVO_LAYER_HIDDEN) != 0;
        v.layers[i].rgba = in->layers[i].rgba;
        snprintf(v.layers[i].name, sizeof v.layers[i].name, "%s", in->layers[i].name);
    }
    v.layer_count = in->layer_count;

    /* an animation: every frame (the writer stores them as keyframes) */
    uint32_t VI = (uint32_t)vox_instances;
    if (frames > 1) {
        v.frame_instances = (vx_vox_instance*)vx_calloc(a, (size_t)frames * VI + 1, sizeof *v.frame_instances);
        v.frame_groups = (vx_vox_group*)vx_calloc(a, (size_t)frames * groups + 1, sizeof *v.frame_groups);
        if (!v.frame_instances || !v.frame_groups) {
            r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %u frames", frames);
            goto fail;
        }
        v.frame_count = frames;
    }
    for (uint32_t f = 0; f < frames; f++) {
        const vx_svo_instance* fi = vx_svo_scene_frame_instances(in, f);
        vx_vox_instance* vf = frames > 1 ? &v.frame_instances[(size_t)f * VI] : v.instances;
        vx_vox_group* gf = frames > 1 ? &v.frame_groups[(size_t)f * groups] : v.groups;
        uint32_t o = 0, g = 0;
        for (uint32_t i = 0; i < I; i++) {
            vx_vox_instance vi;
            memset(&vi, 0, sizeof vi);
            if ((r = export_instance(in, &fi[i], i, f, &vi, err)) != VX_OK) goto fail;
            const split_model* q = &sm[fi[i].model];
            vi.model = q->first;
            if (fits(&in->models[fi[i].model])) {
                vf[o++] = vi;
                continue;
            }
            group_of(&vi, &gf[g++]);
            /* piece k: cell w at floor(R (w + 1/2 - floor(s_k/2) + t_k) + t), which is the
             * model's cell lo_k + w when t_k = lo_k + floor(s_k/2) - floor(size/2) */
            const uint32_t* S = in->models[fi[i].model].size;
            for (size_t k = 0; k < q->n; k++) {
                const piece* p = &q->p[k];
                vx_vox_instance* pi = &vf[o++];
                memset(pi, 0, sizeof *pi);
                pi->model = q->first + (uint32_t)k;
                pi->rot[0] = pi->rot[4] = pi->rot[8] = 1;
                for (int d = 0; d < 3; d++)
                    pi->t[d] = (int32_t)p->lo[d] + (int32_t)((p->hi[d] - p->lo[d] + 1) / 2) - (int32_t)(S[d] / 2);
                pi->layer = vi.layer;
                memcpy(pi->name, vi.name, sizeof pi->name);
                pi->group = g;
            }
        }
    }
    if (frames > 1) {
        if (VI) memcpy(v.instances, v.frame_instances, (size_t)VI * sizeof *v.instances);
        if (groups) memcpy(v.groups, v.frame_groups, (size_t)groups * sizeof *v.groups);
    }
    v.instance_count = VI;
    v.group_count = groups;

    for (uint32_t i = 0; i < in->material_count; i++) {
        const vx_svo_material* m = &in->materials[i];
        v.materials[i].id = m->id;
        v.materials[i].dict_size = m->dict_size;
        v.materials[i].dict = (char*)vx_alloc(a, m->dict_size ? m->dict_size : 1);
        v.material_count = i + 1;
        if (!v.materials[i].dict) {
            r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory");
            goto fail;
        }
        if (m->dict_size) memcpy(v.materials[i].dict, m->dict, m->dict_size);
    }
    v.has_scene_graph = true;
    for (uint32_t i = 0; i < M; i++) vx_free(a, sm[i].p);
    vx_free(a, sm);
    *out = v;
    return VX_OK;
fail:
    for (uint32_t i = 0; i < M; i++) vx_free(a, sm[i].p);
    vx_free(a, sm);
    vx_vox_scene_free(&v);
    return r;
}

/* More than 255 colours: the distinct colours counted (palette models'
 * entries in use, then the RGBA8 models' colours that are none of them);
 * with quantize, the RGBA8 colours cut into the entries the palette models
 * leave free and every one mapped to its nearest entry in use. */
static vx_result quantize(const vx_svo_scene* in, const vx_allocator* a, bool apply, quantized* qz,
                          vx_conv_vox_export_stats* st, vx_error* err) {
    uint32_t base[256];
    fixed_entries(in, base, qz->pal, qz->taken);
    qz->set.a = a;
    vx_result r = VX_OK;
    for (uint32_t i = 0; i < in->model_count && r == VX_OK; i++) {
        const vx_svo_model* m = &in->models[i];
        if ((m->attrs & VX_ATTR_PALETTE) || !(m->attrs & VX_ATTR_RGBA8)) continue; /* as voxel_index */
        gather_ctx g = {m, &qz->set};
        r = vx_svo_decode_model(m, gather_cell, &g, err);
        if (r == VX_OK && qz->set.nomem) r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for the colours");
    }
    if (r != VX_OK) return r;
    uint32_t fixed = 0;
    for (int e = 1; e < 256; e++) fixed += qz->taken[e];
    /* the RGBA8 colours no fixed entry holds */
    qcolour* q = (qcolour*)vx_calloc(a, qz->set.n + 1, sizeof *q);
    qbox* box = (qbox*)vx_calloc(a, 256, sizeof *box);
    if (!q || !box) {
        vx_free(a, q), vx_free(a, box);
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for the colours");
    }
    size_t n = 0;
    for (size_t i = 0; i < qz->set.cap; i++) {
        if (!qz->set.used[i]) continue;
        bool held = false;
        for (int e = 1; e < 256 && !held; e++) held = qz->taken[e] && qz->pal[e] == qz->set.key[i];
        if (!held) q[n++] = (qcolour){0, qz->set.count[i], qz->set.key[i]};
    }
    st->colors = fixed + (uint32_t)(n < UINT32_MAX - fixed ? n : UINT32_MAX - fixed);
    if (!apply) {
        vx_free(a, q), vx_free(a, box);
        return VX_OK;
    }
    /* set order depends on nothing but the colours: sorted, the cut is the same every run */
    for (size_t i = 0; i < n; i++) q[i].key = q[i].rgba;
    qsort(q, n, sizeof *q, cmp_qcolour);
    uint32_t made[256];
    uint32_t nm = median_cut(q, n, 255 - fixed, box, made);
    for (uint32_t e = 1, k = 0; e < 256 && k < nm; e++)
        if (!qz->taken[e]) qz->taken[e] = 1, qz->pal[e] = made[k++];
    vx_free(a, q), vx_free(a, box);
    /* every colour to its nearest entry in use (ties: the lowest index) */
    double sum = 0, max = 0;
    uint64_t cells = 0;
    for (size_t i = 0; i < qz->set.cap; i++) {
        if (!qz->set.used[i]) continue;
        uint32_t best = UINT32_MAX, be = 1;
        for (uint32_t e = 1; e < 256; e++) {
            if (!qz->taken[e]) continue;
            uint32_t d = colour_dist2(qz->set.key[i], qz->pal[e]);
            if (d < best) best = d, be = e;
        }
        qz->set.entry[i] = (uint8_t)be;
        double d = sqrt((double)best);
        if (d > max) max = d;
        sum += d * (double)qz->set.count[i];
        cells += qz->set.count[i];
    }
    st->quantized = true;
    st->max_error = max;
    st->mean_error = cells ? sum / (double)cells : 0.0;
    return VX_OK;
}

vx_result vx_conv_svo_to_vox_ex(const vx_conv_vox_export_desc* desc, const vx_svo_scene* in, vx_vox_scene* out,
                                vx_conv_vox_export_stats* stats, vx_error* err) {
    if (!in || !out) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "null argument");
    vx_conv_vox_export_desc d = desc ? *desc : (vx_conv_vox_export_desc){0};
    vx_conv_vox_export_stats st = {0};
    bool too_many = false;
    vx_result r = export_scene(in, d.alloc, NULL, out, &too_many, err);
    if (r == VX_OK || !too_many) {
        if (r == VX_OK && stats) *stats = st;
        return r;
    }
    quantized qz;
    memset(&qz, 0, sizeof qz);
    r = quantize(in, d.alloc, d.quantize, &qz, &st, err);
    bool refused = r == VX_OK && !d.quantize;
    if (refused)
        r = vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET,
                    "the scene has %u distinct colours, a .vox palette holds 255; export with quantize to map them to 255",
                    st.colors);
    if (r == VX_OK) r = export_scene(in, d.alloc, &qz, out, &too_many, err);
    colour_set_free(&qz.set);
    /* the refusal's count too: each front end names its own option for quantize */
    if ((r == VX_OK || refused) && stats) *stats = st;
    return r;
}

vx_result vx_conv_svo_to_vox(const vx_svo_scene* in, const vx_allocator* a, vx_vox_scene* out, vx_error* err) {
    return vx_conv_svo_to_vox_ex(&(vx_conv_vox_export_desc){.alloc = a}, in, out, NULL, err);
}
