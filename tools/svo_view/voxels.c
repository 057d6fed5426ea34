/* tools/svo_view/voxels.c - brush edits of a model's cells (see voxels.h). */
#include "tools/svo_view/voxels.h"

#include <stdlib.h>
#include <string.h>

static const char* const op_names[VVX_OP_COUNT] = {"add", "remove", "paint"};
static const char* const shape_names[VVX_SHAPE_COUNT] = {"voxel", "box", "sphere"};

const char* vvx_op_name(vvx_op op) { return (unsigned)op < VVX_OP_COUNT ? op_names[op] : "?"; }
const char* vvx_shape_name(vvx_shape s) { return (unsigned)s < VVX_SHAPE_COUNT ? shape_names[s] : "?"; }
bool vvx_shape_parse(const char* s, vvx_shape* out) {
    for (int i = 0; i < VVX_SHAPE_COUNT; i++)
        if (!strcmp(s, shape_names[i])) {
            *out = (vvx_shape)i;
            return true;
        }
    return false;
}

/* A cell of the model after the edit's shift: its Morton key and attribute record. */
typedef struct kv {
    uint64_t key;
    uint32_t attr;
} kv;

typedef struct decoded {
    kv* v;
    size_t n;
    int64_t shift[3];
} decoded;

#define CELL_MAX ((int64_t)1 << VX_SVO_MAX_DEPTH)

static bool decode_cb(void* user, uint32_t x, uint32_t y, uint32_t z, uint32_t attr) {
    decoded* d = user;
    d->v[d->n].key = vx_svo_morton((uint32_t)(x + d->shift[0]), (uint32_t)(y + d->shift[1]), (uint32_t)(z + d->shift[2]));
    d->v[d->n].attr = attr;
    d->n++;
    return true;
}

static int cmp_kv(const void* x, const void* y) {
    uint64_t a = ((const kv*)x)->key, b = ((const kv*)y)->key;
    return (a > b) - (a < b);
}
static int cmp_u64(const void* x, const void* y) {
    uint64_t a = *(const uint64_t*)x, b = *(const uint64_t*)y;
    return (a > b) - (a < b);
}

static const kv* find(const decoded* d, uint64_t key) {
    size_t lo = 0, hi = d->n;
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        if (d->v[mid].key < key) lo = mid + 1;
        else hi = mid;
    }
    return lo < d->n && d->v[lo].key == key ? &d->v[lo] : NULL;
}

static bool in_keys(const uint64_t* k, size_t n, uint64_t key) {
    size_t lo = 0, hi = n;
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        if (k[mid] < key) lo = mid + 1;
        else hi = mid;
    }
    return lo < n && k[lo] == key;
}

/* The channels of the model's cells, parallel arrays the builder reads. */
typedef struct out_cells {
    uint64_t* keys;
    uint8_t* palette;
    uint32_t *rgba, *normal;
    uint16_t* material;
    float* density;
    size_t n;
} out_cells;

static void put(out_cells* o, const vx_svo_model* m, uint64_t key, const kv* rec, bool colour, const vvx_brush* b) {
    size_t i = o->n++;
    o->keys[i] = key;
    uint32_t a = rec && rec->attr < m->attr_count ? rec->attr : UINT32_MAX;
    if (o->palette) o->palette[i] = colour ? (b->palette ? b->palette : 1) : (a != UINT32_MAX ? m->palette[a] : 1);
    if (o->rgba) o->rgba[i] = colour ? (b->rgba ? b->rgba : 0xFFFFFFFFu) : (a != UINT32_MAX ? m->rgba[a] : 0xFFFFFFFFu);
    if (o->normal) o->normal[i] = a != UINT32_MAX ? m->normal[a] : 0;
    if (o->material) o->material[i] = a != UINT32_MAX ? m->material[a] : 0;
    if (o->density) o->density[i] = a != UINT32_MAX ? m->density[a] : 1.0f;
}

static bool same_colour(const vx_svo_model* m, uint32_t a, const vvx_brush* b) {
    if (a >= m->attr_count) return false;
    if ((m->attrs & VX_ATTR_PALETTE) && m->palette[a] != (b->palette ? b->palette : 1)) return false;
    if ((m->attrs & VX_ATTR_RGBA8) && m->rgba[a] != (b->rgba ? b->rgba : 0xFFFFFFFFu)) return false;
    return true;
}

vx_result vvx_apply(ved* e, uint32_t model, vvx_op op, const vvx_brush* b, const int64_t c[3], uint64_t* changed,
                    vx_error* err) {
    vx_svo_scene* s = e->s;
    if (changed) *changed = 0;
    if (model >= s->model_count) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "no model %u", model);
    if ((unsigned)op >= VVX_OP_COUNT || (unsigned)b->shape >= VVX_SHAPE_COUNT || b->radius > VVX_MAX_RADIUS)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "bad brush (radius at most %u)", VVX_MAX_RADIUS);
    const vx_svo_model* m = &s->models[model];
    if (op == VVX_PAINT && !(m->attrs & (VX_ATTR_PALETTE | VX_ATTR_RGBA8)))
        return vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET, "model %u has no colours to paint", model);
    for (int k = 0; k < 3; k++)
        if (c[k] < -CELL_MAX || c[k] > 2 * CELL_MAX)
            return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "cell %lld,%lld,%lld is too far from model %u",
                           (long long)c[0], (long long)c[1], (long long)c[2], model);
    /* the brush's cells */
    int64_t r = b->shape == VVX_VOXEL ? 0 : b->radius, side = 2 * r + 1;
    size_t cap = (size_t)(side * side * side);
    int64_t* cells = malloc(cap * 3 * sizeof *cells);
    if (!cells) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for a brush of radius %lld", (long long)r);
    size_t nb = 0;
    int64_t lo[3] = {INT64_MAX, INT64_MAX, INT64_MAX}, hi[3] = {INT64_MIN, INT64_MIN, INT64_MIN};
    for (int64_t dz = -r; dz <= r; dz++)
        for (int64_t dy = -r; dy <= r; dy++)
            for (int64_t dx = -r; dx <= r; dx++) {
                if (b->shape == VVX_SPHERE && dx * dx + dy * dy + dz * dz > r * r) continue;
                int64_t p[3] = {c[0] + dx, c[1] + dy, c[2] + dz};
                bool inside = true;
                for (int k = 0; k < 3; k++) inside &= p[k] >= 0 && p[k] < (int64_t)m->size[k];
                if (op != VVX_ADD && !inside) continue; /* nothing there to remove or paint */
                for (int k = 0; k < 3; k++) {
                    cells[3 * nb + k] = p[k];
                    lo[k] = p[k] < lo[k] ? p[k] : lo[k];
                    hi[k] = p[k] > hi[k] ? p[k] : hi[k];
                }
                nb++;
            }
    if (!nb) {
        free(cells);
        return VX_OK;
    }
    /* growth: below 0 the cells shift up; the size covers the brush */
    decoded d = {0};
    uint32_t size[3];
    for (int k = 0; k < 3; k++) {
        d.shift[k] = lo[k] < 0 ? -lo[k] : 0;
        int64_t top = hi[k] + d.shift[k] + 1, old = (int64_t)m->size[k] + d.shift[k];
        int64_t sz = top > old ? top : old;
        if (sz > CELL_MAX) {
            free(cells);
            return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "model %u would be %lld cells long (at most %lld)", model,
                           (long long)sz, (long long)CELL_MAX);
        }
        size[k] = (uint32_t)sz;
    }
    size_t nv = (size_t)m->voxel_count;
    vx_result res = VX_OK;
    uint64_t* bkeys = malloc(nb * sizeof *bkeys);
    d.v = malloc((nv ? nv : 1) * sizeof *d.v);
    out_cells o = {0};
    size_t ocap = nv + (op == VVX_ADD ? nb : 0);
    o.keys = malloc((ocap ? ocap : 1) * sizeof *o.keys);
    if (m->attrs & VX_ATTR_PALETTE) o.palette = malloc(ocap ? ocap : 1);
    if (m->attrs & VX_ATTR_RGBA8) o.rgba = malloc((ocap ? ocap : 1) * 4);
    if (m->attrs & VX_ATTR_NORMAL) o.normal = malloc((ocap ? ocap : 1) * 4);
    if (m->attrs & VX_ATTR_MATERIAL) o.material = malloc((ocap ? ocap : 1) * 2);
    if (m->attrs & VX_ATTR_DENSITY) o.density = malloc((ocap ? ocap : 1) * 4);
    if ((uint64_t)nv != m->voxel_count || !bkeys || !d.v || !o.keys || ((m->attrs & VX_ATTR_PALETTE) && !o.palette) ||
        ((m->attrs & VX_ATTR_RGBA8) && !o.rgba) || ((m->attrs & VX_ATTR_NORMAL) && !o.normal) ||
        ((m->attrs & VX_ATTR_MATERIAL) && !o.material) || ((m->attrs & VX_ATTR_DENSITY) && !o.density))
        res = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory editing model %u (%zu cells)", model, nv);
    if (!res) res = vx_svo_decode_model(m, decode_cb, &d, err);
    uint64_t n_changed = 0;
    if (!res) {
        for (size_t i = 0; i < nb; i++)
            bkeys[i] = vx_svo_morton((uint32_t)(cells[3 * i] + d.shift[0]), (uint32_t)(cells[3 * i + 1] + d.shift[1]),
                                     (uint32_t)(cells[3 * i + 2] + d.shift[2]));
        qsort(bkeys, nb, sizeof *bkeys, cmp_u64);
        qsort(d.v, d.n, sizeof *d.v, cmp_kv); /* Morton order of the shifted cells */
        for (size_t i = 0; i < d.n; i++) {
            bool hit = in_keys(bkeys, nb, d.v[i].key);
            if (hit && op == VVX_REMOVE) {
                n_changed++;
                continue;
            }
            bool paint = hit && op == VVX_PAINT;
            if (paint && !same_colour(m, d.v[i].attr, b)) n_changed++;
            put(&o, m, d.v[i].key, &d.v[i], paint, b);
        }
        if (op == VVX_ADD) {
            for (size_t i = 0; i < nb; i++) {
                if (i && bkeys[i] == bkeys[i - 1]) continue;
                if (find(&d, bkeys[i])) continue;
                /* the other channels from the nearest set face neighbour (else the first cell) */
                uint32_t x, y, z;
                vx_svo_demorton(bkeys[i], &x, &y, &z);
                const kv* src = NULL;
                static const int nbr[6][3] = {{-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}};
                for (int q = 0; q < 6 && !src; q++) {
                    int64_t p[3] = {(int64_t)x + nbr[q][0], (int64_t)y + nbr[q][1], (int64_t)z + nbr[q][2]};
                    if (p[0] < 0 || p[1] < 0 || p[2] < 0 || p[0] >= CELL_MAX || p[1] >= CELL_MAX || p[2] >= CELL_MAX)
                        continue;
                    src = find(&d, vx_svo_morton((uint32_t)p[0], (uint32_t)p[1], (uint32_t)p[2]));
                }
                if (!src && d.n) src = &d.v[0];
                put(&o, m, bkeys[i], src, true, b);
                n_changed++;
            }
        }
    }
    vx_svo_model nm = {0};
    bool built = false;
    if (!res && n_changed) {
        vx_svo_voxels v = {.count = o.n, .keys = o.keys, .attrs = m->attrs, .palette = o.palette, .rgba = o.rgba,
                           .normal = o.normal, .material = o.material, .density = o.density};
        memcpy(v.size, size, sizeof v.size);
        res = vx_svo_build_model(&(vx_svo_build_desc){.alloc = s->alloc}, &v, &nm, NULL, err);
        built = !res;
    }
    if (built) res = ved_begin(e, err);
    if (built && !res) {
        /* nothing moves in the world: every instance of the model steps back by M * shift */
        for (uint32_t f = 0; f < vx_svo_scene_frames(s); f++)
            for (uint32_t i = 0; i < s->instance_count; i++) {
                vx_svo_instance* in = ved_record(s, f, i);
                if (in->model != model) continue;
                for (int row = 0; row < 3; row++)
                    in->xform[4 * row + 3] -= in->xform[4 * row] * (double)d.shift[0] +
                                              in->xform[4 * row + 1] * (double)d.shift[1] +
                                              in->xform[4 * row + 2] * (double)d.shift[2];
            }
        ved_snapshot* sn = &e->undo[e->undo_count - 1];
        sn->has_model = true;
        sn->model_index = model;
        sn->model = s->models[model];
        s->models[model] = nm;
        if (changed) *changed = n_changed;
    } else if (built) {
        vx_svo_model_free(s->alloc, &nm);
    }
    free(cells);
    free(bkeys);
    free(d.v);
    free(o.keys), free(o.palette), free(o.rgba), free(o.normal), free(o.material), free(o.density);
    return res;
}
