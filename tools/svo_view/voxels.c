/* tools/svo_view/voxels.c - brush edits of a model's cells (see voxels.h). */
#include "tools/svo_view/voxels.h"

#include <stdlib.h>
#include <string.h>

static const char* const op_names[VVX_OP_COUNT] = {"add", "remove", "paint"};
static const char* const shape_names[VVX_SHAPE_COUNT] = {"voxel", "box", "sphere", "face"};

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

static vx_result apply_rebuild(ved* e, uint32_t model, vvx_op op, const vvx_brush* b, const int64_t* cells, size_t nb,
                               const int64_t lo[3], const int64_t hi[3], uint64_t* changed, vx_error* err);

/* The per-model voxel state of e (voxels_of grows it to the scene's
 * models; editors made for a models array ved_add_scene has since replaced
 * are dropped). */
static ved_voxels* voxels_of(ved* e, uint32_t model, vx_error* err) {
    vx_svo_scene* s = e->s;
    if (e->vox_count < s->model_count) {
        ved_voxels* v = vx_calloc(s->alloc, s->model_count, sizeof *v);
        if (!v) {
            vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %u models' edit state", s->model_count);
            return NULL;
        }
        if (e->vox_count) memcpy(v, e->vox, (size_t)e->vox_count * sizeof *v);
        vx_free(s->alloc, e->vox);
        e->vox = v;
        e->vox_count = s->model_count;
    }
    for (uint32_t i = 0; i < e->vox_count; i++)
        if (e->vox[i].ed && e->vox[i].models != s->models) {
            vx_svo_editor_destroy(e->vox[i].ed);
            e->vox[i].ed = NULL;
        }
    return &e->vox[model];
}

/* The model's cell of smallest Morton key: the first valid octant at each
 * level (the builder's order, so its values are those the rebuild took
 * for an added cell with no set neighbour). False for an empty model. */
static bool first_cell(const vx_svo_model* m, vx_svo_cell* out) {
    memset(out, 0, sizeof *out);
    uint32_t a = m->root_attr;
    if (m->root == VX_SVO_ROOT_EMPTY) return false;
    if (m->root != VX_SVO_ROOT_LEAF) {
        uint32_t pos = m->root;
        for (;;) {
            uint32_t d = m->nodes[pos], valid = vx_svo_desc_valid(d), leaf = vx_svo_desc_leaf(d);
            uint32_t blk = vx_svo_desc_far(d) ? m->nodes[pos - vx_svo_desc_ptr(d)] : pos - vx_svo_desc_ptr(d);
            uint32_t o = 0;
            while (!(valid >> o & 1u)) o++;
            uint32_t nn = 0;
            for (uint32_t q = 0; q < 8; q++) nn += (valid & ~leaf) >> q & 1u;
            if (m->attrs) a = m->nodes[blk + nn]; /* the first valid child's record: index + 0 */
            if (leaf >> o & 1u) break;
            pos = blk; /* the first valid child is the block's first descriptor */
        }
    }
    if (m->attrs && a < m->attr_count) {
        if (m->palette) out->palette = m->palette[a];
        if (m->rgba) out->rgba = m->rgba[a];
        if (m->normal) out->normal = m->normal[a];
        if (m->material) out->material = m->material[a];
        if (m->density) out->density = m->density[a];
    }
    return true;
}

/* The model's voxel state with its editor (made at the model's first
 * incremental edit). */
static vx_result editor_of(ved* e, uint32_t model, ved_voxels** out, vx_error* err) {
    vx_svo_scene* s = e->s;
    ved_voxels* v = voxels_of(e, model, err);
    if (!v) return VX_ERR_NOMEM;
    if (!v->ed) {
        vx_svo_editor_desc dd = {.alloc = s->alloc, .words_in_use = v->arrays.words_in_use,
                                 .records_in_use = v->arrays.records_in_use};
        vx_result r = vx_svo_editor_create(&dd, &s->models[model], &v->ed, err);
        if (r) return r;
        v->models = s->models;
    }
    *out = v;
    return VX_OK;
}

/* Applies n writes through the model's editor as one undo step that keeps
 * the old header; *changed = n (0 on failure: the model is as before). */
static vx_result apply_writes(ved* e, uint32_t model, ved_voxels* v, const vx_svo_cell_write* w, size_t n,
                              uint64_t* changed, vx_error* err) {
    vx_svo_model* m = &e->s->models[model];
    if (changed) *changed = n;
    if (!n) return VX_OK;
    vx_svo_model_header before = vx_svo_model_header_get(m);
    vx_svo_edit_stats st;
    vx_result res = vx_svo_editor_apply(v->ed, w, n, &st, err);
    if (!res && (res = ved_begin(e, err))) vx_svo_model_header_set(m, &before); /* the appends stay unreferenced */
    if (res) {
        if (changed) *changed = 0;
        return res;
    }
    ved_snapshot* sn = &e->undo[e->undo_count - 1];
    sn->has_header = true;
    sn->model_index = model;
    sn->header = before;
    ved_arrays* ar = &v->arrays;
    if (!ar->edited) ar->edited = true, ar->pristine = before;
    uint32_t wend = st.words_from + st.words_added, rend = st.records_from + st.records_added;
    if (wend > ar->words_in_use) ar->words_in_use = wend;
    if (rend > ar->records_in_use) ar->records_in_use = rend;
    e->last = (ved_voxel_step){.incremental = true, .model = model, .words_from = st.words_from, .records_from = st.records_from};
    return VX_OK;
}

/* The face brush: the cells of the plane region connected to the hit cell
 * c (4-neighbours in the plane, within the radius) whose face toward n is
 * exposed (set, and the cell beyond it empty); add extrudes the region by
 * one layer (each new cell takes the values of the cell under it), remove
 * takes the region away, paint recolours it. */
static vx_result apply_face(ved* e, uint32_t model, vvx_op op, const vvx_brush* b, const int64_t c[3],
                            uint64_t* changed, vx_error* err) {
    vx_svo_scene* s = e->s;
    const vx_svo_model* m = &s->models[model];
    if (b->face > 5) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "bad face %u (0..5: -x +x -y +y -z +z)", b->face);
    for (int k = 0; k < 3; k++)
        if (c[k] < 0 || c[k] >= (int64_t)m->size[k]) return VX_OK; /* no cell there */
    ved_voxels* v = NULL;
    vx_result vr = editor_of(e, model, &v, err);
    if (vr) return vr;
    int ax = b->face / 2, a1 = (ax + 1) % 3, a2 = (ax + 2) % 3;
    int64_t d = b->face & 1 ? 1 : -1;
    int64_t R = b->radius ? b->radius : VVX_MAX_RADIUS, side = 2 * R + 1;
    /* set and exposed toward n */
#define FACE_AT(p, cell)                                                                                            \
    (vx_svo_editor_get(v->ed, (uint32_t)(p)[0], (uint32_t)(p)[1], (uint32_t)(p)[2], cell) &&                       \
     !((p)[ax] + d >= 0 && vx_svo_editor_get(v->ed, (uint32_t)((p)[0] + (ax == 0) * d),                            \
                                             (uint32_t)((p)[1] + (ax == 1) * d), (uint32_t)((p)[2] + (ax == 2) * d), NULL)))
    vx_svo_cell cur;
    if (!FACE_AT(c, &cur)) return VX_OK;
    if (op == VVX_ADD && c[ax] + d < 0)
        return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "the extrusion would reach below cell 0 of model %u", model);
    uint8_t* seen = calloc((size_t)(side * side), 1);
    int64_t* queue = malloc((size_t)(side * side) * 2 * sizeof *queue);
    vx_svo_cell_write* w = malloc((size_t)(side * side) * sizeof *w);
    if (!seen || !queue || !w) {
        free(seen), free(queue), free(w);
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for a face of radius %lld", (long long)R);
    }
    uint8_t pal = b->palette ? b->palette : 1;
    uint32_t rgba = b->rgba ? b->rgba : 0xFFFFFFFFu;
    bool has_pal = m->attrs & VX_ATTR_PALETTE, has_rgba = m->attrs & VX_ATTR_RGBA8;
    size_t qh = 0, qt = 0, n = 0;
    queue[0] = 0, queue[1] = 0, qt = 1;
    seen[(size_t)(R * side + R)] = 1;
    while (qh < qt) {
        int64_t du = queue[2 * qh], dv = queue[2 * qh + 1];
        qh++;
        int64_t p[3];
        p[ax] = c[ax], p[a1] = c[a1] + du, p[a2] = c[a2] + dv;
        if (!FACE_AT(p, &cur)) continue;
        vx_svo_cell_write* o = &w[n];
        *o = (vx_svo_cell_write){.x = (uint32_t)p[0], .y = (uint32_t)p[1], .z = (uint32_t)p[2], .set = op != VVX_REMOVE,
                                 .value = cur};
        if (op == VVX_ADD) {
            uint32_t* q = &o->x;
            q[ax] = (uint32_t)(p[ax] + d);
            n++;
        } else if (op == VVX_REMOVE) {
            n++;
        } else if ((has_pal && cur.palette != pal) || (has_rgba && cur.rgba != rgba)) {
            o->value.palette = pal, o->value.rgba = rgba;
            n++;
        }
        static const int nb4[4][2] = {{-1, 0}, {1, 0}, {0, -1}, {0, 1}};
        for (int q = 0; q < 4; q++) {
            int64_t u = du + nb4[q][0], vv = dv + nb4[q][1];
            if (u < -R || u > R || vv < -R || vv > R || c[a1] + u < 0 || c[a2] + vv < 0 ||
                c[a1] + u >= (int64_t)m->size[a1] || c[a2] + vv >= (int64_t)m->size[a2])
                continue;
            uint8_t* sv = &seen[(size_t)((vv + R) * side + (u + R))];
            if (*sv) continue;
            *sv = 1;
            queue[2 * qt] = u, queue[2 * qt + 1] = vv, qt++;
        }
    }
#undef FACE_AT
    vx_result res = apply_writes(e, model, v, w, n, changed, err);
    free(seen), free(queue), free(w);
    return res;
}

/* The edit through the model's vx_svo_editor: only the paths to the written
 * cells are made again (appended), the undo step keeps the old header. */
/* The brush's box of cells read at once (vx_svo_editor_get_box): set and
 * values of cell p at index ((p - lo) . (1, dx, dx dy)). */
typedef struct box_read {
    int64_t lo[3], hi[3];
    uint32_t d[3];
    bool* set;
    vx_svo_cell* v;
} box_read;

static bool box_get(const box_read* r, const int64_t p[3], vx_svo_cell* out) {
    for (int k = 0; k < 3; k++)
        if (p[k] < r->lo[k] || p[k] > r->hi[k]) return false;
    size_t i = ((size_t)(p[2] - r->lo[2]) * r->d[1] + (size_t)(p[1] - r->lo[1])) * r->d[0] + (size_t)(p[0] - r->lo[0]);
    if (r->set[i] && out) *out = r->v[i];
    return r->set[i];
}

static vx_result apply_incremental(ved* e, uint32_t model, vvx_op op, const vvx_brush* b, const int64_t* cells,
                                   size_t nb, const int64_t lo[3], const int64_t hi[3], uint64_t* changed, vx_error* err) {
    vx_svo_scene* s = e->s;
    ved_voxels* v = NULL;
    vx_result vr = editor_of(e, model, &v, err);
    if (vr) return vr;
    vx_svo_model* m = &s->models[model];
    /* the brush's box, and for add its face neighbours, read in one walk */
    box_read br;
    size_t bn = 1;
    uint32_t blo[3], bhi[3];
    for (int k = 0; k < 3; k++) {
        int64_t g = op == VVX_ADD ? 1 : 0;
        br.lo[k] = lo[k] - g < 0 ? 0 : lo[k] - g;
        br.hi[k] = hi[k] + g;
        br.d[k] = (uint32_t)(br.hi[k] - br.lo[k] + 1);
        blo[k] = (uint32_t)br.lo[k], bhi[k] = (uint32_t)br.hi[k];
        bn *= br.d[k];
    }
    br.set = malloc(bn);
    br.v = malloc(bn * sizeof *br.v);
    vx_svo_cell_write* w = malloc((nb ? nb : 1) * sizeof *w);
    if (!w || !br.set || !br.v) {
        free(w), free(br.set), free(br.v);
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %zu brush cells", nb);
    }
    if ((vr = vx_svo_editor_get_box(v->ed, blo, bhi, br.set, br.v, err))) {
        free(w), free(br.set), free(br.v);
        return vr;
    }
    uint8_t pal = b->palette ? b->palette : 1;
    uint32_t rgba = b->rgba ? b->rgba : 0xFFFFFFFFu;
    bool has_pal = m->attrs & VX_ATTR_PALETTE, has_rgba = m->attrs & VX_ATTR_RGBA8;
    bool have_first = false, first_set = false;
    vx_svo_cell first;
    size_t n = 0;
    for (size_t i = 0; i < nb; i++) {
        uint32_t x = (uint32_t)cells[3 * i], y = (uint32_t)cells[3 * i + 1], z = (uint32_t)cells[3 * i + 2];
        vx_svo_cell cur;
        bool set = box_get(&br, &cells[3 * i], &cur);
        vx_svo_cell_write* o = &w[n];
        *o = (vx_svo_cell_write){.x = x, .y = y, .z = z, .set = op != VVX_REMOVE};
        if (op == VVX_ADD) {
            if (set) continue;
            /* the other channels from the nearest set face neighbour (else the first cell) */
            static const int nbr[6][3] = {{-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}};
            vx_svo_cell src;
            bool found = false;
            for (int q = 0; q < 6 && !found; q++) {
                int64_t p[3] = {(int64_t)x + nbr[q][0], (int64_t)y + nbr[q][1], (int64_t)z + nbr[q][2]};
                found = box_get(&br, p, &src);
            }
            if (!found) {
                if (!have_first) first_set = first_cell(m, &first), have_first = true;
                src = first;
                if (!first_set) src = (vx_svo_cell){.density = 1.0f};
            }
            o->value = src;
        } else if (op == VVX_REMOVE) {
            if (!set) continue;
        } else {
            if (!set || ((!has_pal || cur.palette == pal) && (!has_rgba || cur.rgba == rgba))) continue;
            o->value = cur;
        }
        if (op != VVX_REMOVE) o->value.palette = pal, o->value.rgba = rgba;
        n++;
    }
    free(br.set), free(br.v);
    vx_result res = apply_writes(e, model, v, w, n, changed, err);
    free(w);
    return res;
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
    if (b->shape == VVX_FACE) return apply_face(e, model, op, b, c, changed, err);
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
    for (int k = 0; k < 3; k++)
        if (hi[k] - (lo[k] < 0 ? lo[k] : 0) + 1 > CELL_MAX) {
            free(cells);
            return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "model %u would be %lld cells long (at most %lld)", model,
                           (long long)(hi[k] - (lo[k] < 0 ? lo[k] : 0) + 1), (long long)CELL_MAX);
        }
    vx_result res;
    /* cells below 0 shift every key: the model is built again from its cells */
    if (lo[0] >= 0 && lo[1] >= 0 && lo[2] >= 0 && !e->vox_rebuild) res = apply_incremental(e, model, op, b, cells, nb, lo, hi, changed, err);
    else res = apply_rebuild(e, model, op, b, cells, nb, lo, hi, changed, err);
    free(cells);
    return res;
}

/* The edit by decoding the model's cells, applying the brush there and
 * building the octree again; the undo step parks the old octree. */
static vx_result apply_rebuild(ved* e, uint32_t model, vvx_op op, const vvx_brush* b, const int64_t* cells, size_t nb,
                               const int64_t lo[3], const int64_t hi[3], uint64_t* changed, vx_error* err) {
    vx_svo_scene* s = e->s;
    const vx_svo_model* m = &s->models[model];
    /* growth: below 0 the cells shift up; the size covers the brush */
    decoded d = {0};
    uint32_t size[3];
    for (int k = 0; k < 3; k++) {
        d.shift[k] = lo[k] < 0 ? -lo[k] : 0;
        int64_t top = hi[k] + d.shift[k] + 1, old = (int64_t)m->size[k] + d.shift[k];
        int64_t sz = top > old ? top : old;
        if (sz > CELL_MAX) {
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
        /* the parked arrays keep their words in use; the new ones have none past their words */
        ved_voxels* v = voxels_of(e, model, NULL);
        if (v) {
            vx_svo_editor_destroy(v->ed);
            v->ed = NULL;
            sn->model_arrays = v->arrays;
            memset(&v->arrays, 0, sizeof v->arrays);
        }
        e->last = (ved_voxel_step){.model = model};
    } else if (built) {
        vx_svo_model_free(s->alloc, &nm);
    }
    free(bkeys);
    free(d.v);
    free(o.keys), free(o.palette), free(o.rgba), free(o.normal), free(o.material), free(o.density);
    return res;
}

vx_result vvx_file_scene(const ved* e, vx_svo_scene* out, vx_error* err) {
    const vx_svo_scene* s = e->s;
    *out = *s;
    vx_svo_model* models = NULL;
    for (uint32_t i = 0; i < s->model_count && i < e->vox_count; i++) {
        const ved_arrays* ar = &e->vox[i].arrays;
        vx_svo_model_header h = vx_svo_model_header_get(&s->models[i]);
        if (!ar->edited || !memcmp(&h, &ar->pristine, sizeof h)) continue; /* the words as loaded or built */
        if (!models) {
            models = vx_calloc(s->alloc, s->model_count, sizeof *models);
            if (!models) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %u models", s->model_count);
            memcpy(models, s->models, (size_t)s->model_count * sizeof *models);
            out->models = models;
        }
        vx_result r = vx_svo_model_compact(&(vx_svo_build_desc){.alloc = s->alloc}, &s->models[i], &models[i], err);
        if (r) {
            models[i] = s->models[i];
            vvx_file_scene_free(e, out);
            *out = *s;
            return r;
        }
    }
    return VX_OK;
}

void vvx_file_scene_free(const ved* e, vx_svo_scene* out) {
    const vx_svo_scene* s = e->s;
    if (out->models == s->models) return;
    for (uint32_t i = 0; i < s->model_count; i++)
        if (out->models[i].nodes != s->models[i].nodes || out->models[i].palette != s->models[i].palette ||
            out->models[i].rgba != s->models[i].rgba)
            vx_svo_model_free(s->alloc, &out->models[i]);
    vx_free(s->alloc, out->models);
    out->models = s->models;
}
