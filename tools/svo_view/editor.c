/* tools/svo_view/editor.c - scene edits with undo and redo (see editor.h). */
#include "tools/svo_view/editor.h"

#include <math.h>
#include <string.h>

static void materials_free(const vx_allocator* a, vx_svo_material* m, uint32_t n) {
    for (uint32_t i = 0; m && i < n; i++) vx_free(a, m[i].dict);
    vx_free(a, m);
}

static void snap_free(const vx_allocator* a, ved_snapshot* sn) {
    if (sn->has_materials) materials_free(a, sn->materials, sn->material_count);
    vx_free(a, sn->inst);
    vx_free(a, sn->frame_inst);
    vx_free(a, sn->layer_flags);
    vx_free(a, sn->lights);
    if (sn->has_model) vx_svo_model_free(a, &sn->model);
    memset(sn, 0, sizeof *sn);
}

/* Frame records beyond frame 0, as the scene holds them. */
static size_t frame_records(const vx_svo_scene* s) {
    return s->frame_count >= 2 && s->frame_instances ? (size_t)(s->frame_count - 1) * s->instance_count : 0;
}

static vx_result snap_take(const vx_svo_scene* s, ved_snapshot* out, vx_error* err) {
    ved_snapshot sn = {.inst_count = s->instance_count, .layer_count = s->layer_count,
                       .light_count = s->light_count, .sky = s->sky};
    size_t nf = frame_records(s);
    sn.inst = vx_calloc(s->alloc, s->instance_count ? s->instance_count : 1, sizeof *sn.inst);
    sn.frame_inst = nf ? vx_calloc(s->alloc, nf, sizeof *sn.frame_inst) : NULL;
    sn.layer_flags = vx_calloc(s->alloc, s->layer_count ? s->layer_count : 1, sizeof *sn.layer_flags);
    sn.lights = s->light_count ? vx_calloc(s->alloc, s->light_count, sizeof *sn.lights) : NULL;
    if (!sn.inst || !sn.layer_flags || (nf && !sn.frame_inst) || (s->light_count && !sn.lights)) {
        snap_free(s->alloc, &sn);
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for an undo step of %u instances",
                       s->instance_count);
    }
    if (s->instance_count) memcpy(sn.inst, s->instances, (size_t)s->instance_count * sizeof *sn.inst);
    if (nf) memcpy(sn.frame_inst, s->frame_instances, nf * sizeof *sn.frame_inst);
    if (s->light_count) memcpy(sn.lights, s->lights, (size_t)s->light_count * sizeof *sn.lights);
    sn.frame_count = nf ? s->frame_count : 0;
    for (uint32_t l = 0; l < s->layer_count; l++) sn.layer_flags[l] = s->layers[l].flags;
    *out = sn;
    return VX_OK;
}

/* Makes sn the scene's state; the scene's previous arrays go into sn. */
#define SWAP(T, a, b)                                                                                  \
    do {                                                                                               \
        T swap_ = (a);                                                                                 \
        (a) = (b), (b) = swap_;                                                                        \
    } while (0)
static void snap_swap(vx_svo_scene* s, ved_snapshot* sn) {
    SWAP(vx_svo_instance*, s->instances, sn->inst);
    SWAP(uint32_t, s->instance_count, sn->inst_count);
    SWAP(vx_svo_instance*, s->frame_instances, sn->frame_inst);
    SWAP(uint32_t, s->frame_count, sn->frame_count);
    SWAP(vx_light*, s->lights, sn->lights);
    SWAP(uint32_t, s->light_count, sn->light_count);
    SWAP(vx_sky, s->sky, sn->sky);
    if (sn->has_materials) {
        SWAP(vx_svo_material*, s->materials, sn->materials);
        SWAP(uint32_t, s->material_count, sn->material_count);
    }
    /* layers are never added or removed, only flagged */
    for (uint32_t l = 0; l < s->layer_count && l < sn->layer_count; l++) SWAP(uint32_t, s->layers[l].flags, sn->layer_flags[l]);
    /* models are never removed: the index stays valid */
    if (sn->has_model && sn->model_index < s->model_count) SWAP(vx_svo_model, s->models[sn->model_index], sn->model);
}
#undef SWAP

/* After snap_swap: a voxel step's header, or the editor of a model whose
 * arrays were swapped (made again at the next voxel edit). */
static void vox_swap(ved* e, ved_snapshot* sn) {
    vx_svo_scene* s = e->s;
    if (sn->has_header && sn->model_index < s->model_count) {
        vx_svo_model_header h = vx_svo_model_header_get(&s->models[sn->model_index]);
        vx_svo_model_header_set(&s->models[sn->model_index], &sn->header);
        sn->header = h;
    }
    if (sn->has_model && sn->model_index < e->vox_count) {
        ved_voxels* v = &e->vox[sn->model_index];
        vx_svo_editor_destroy(v->ed);
        v->ed = NULL;
        ved_arrays t = v->arrays;
        v->arrays = sn->model_arrays;
        sn->model_arrays = t;
    }
}

void ved_init(ved* e, vx_svo_scene* s) {
    memset(e, 0, sizeof *e);
    e->s = s;
    memset(e->pal_unused, 0xFF, sizeof e->pal_unused);
    e->pal_unused[0] &= ~1u; /* entry 0 is no colour */
    ved_palette_scan(e);
}

void ved_palette_scan(ved* e) {
    const vx_svo_scene* s = e->s;
    for (uint32_t m = 0; m < s->model_count; m++) {
        const vx_svo_model* md = &s->models[m];
        if (!(md->attrs & VX_ATTR_PALETTE) || !md->palette) continue;
        for (uint32_t r = 0; r < md->attr_count; r++) ved_palette_keep(e, md->palette[r]);
    }
}

void ved_palette_keep(ved* e, uint32_t i) {
    if (i < 256) e->pal_unused[i >> 5] &= ~(1u << (i & 31));
}

uint32_t ved_palette_take(ved* e, uint32_t rgba) {
    uint32_t* pal = e->s->palette;
    uint32_t at = 0;
    for (uint32_t i = 1; i < 256 && !at; i++)
        if (pal[i] == rgba) at = i;
    for (uint32_t i = 1; i < 256 && !at; i++)
        if (!pal[i]) at = i;
    for (uint32_t i = 1; i < 256 && !at; i++)
        if (e->pal_unused[i >> 5] & (1u << (i & 31))) at = i;
    if (at) {
        pal[at] = rgba; /* stored in the file once a cell uses it */
        ved_palette_keep(e, at);
    }
    return at;
}

void ved_free(ved* e) {
    for (uint32_t i = 0; i < e->undo_count; i++) snap_free(e->s->alloc, &e->undo[i]);
    for (uint32_t i = 0; i < e->redo_count; i++) snap_free(e->s->alloc, &e->redo[i]);
    e->undo_count = e->redo_count = 0;
    vx_free(e->s->alloc, e->undo);
    vx_free(e->s->alloc, e->redo);
    e->undo = e->redo = NULL;
    e->cap = 0;
    for (uint32_t i = 0; i < e->vox_count; i++) vx_svo_editor_destroy(e->vox[i].ed);
    vx_free(e->s->alloc, e->vox);
    e->vox = NULL;
    e->vox_count = 0;
}

uint64_t ved_snapshot_bytes(const ved_snapshot* sn) {
    uint64_t n = sizeof *sn + (uint64_t)sn->inst_count * sizeof(vx_svo_instance) +
                 (uint64_t)sn->layer_count * sizeof(uint32_t) + (uint64_t)sn->light_count * sizeof(vx_light);
    for (uint32_t i = 0; sn->has_materials && i < sn->material_count; i++)
        n += sizeof(vx_svo_material) + sn->materials[i].dict_size;
    if (sn->frame_inst && sn->frame_count >= 2) n += (uint64_t)(sn->frame_count - 1) * sn->inst_count * sizeof(vx_svo_instance);
    if (sn->has_model) {
        const vx_svo_model* m = &sn->model;
        uint64_t per = (m->palette ? 1 : 0) + (m->rgba ? 4 : 0) + (m->normal ? 4 : 0) + (m->material ? 2 : 0) +
                       (m->density ? 4 : 0);
        n += (uint64_t)m->node_count * 4 + (uint64_t)m->attr_count * per;
    }
    return n;
}

static void drop_oldest(ved* e) {
    snap_free(e->s->alloc, &e->undo[0]);
    memmove(e->undo, e->undo + 1, (size_t)(e->undo_count - 1) * sizeof e->undo[0]);
    e->undo_count--;
    e->dropped++;
}

vx_result ved_begin(ved* e, vx_error* err) {
    uint32_t limit = e->undo_limit ? e->undo_limit : VED_UNDO_STEPS_DEFAULT;
    uint64_t bytes = e->undo_bytes ? e->undo_bytes : VED_UNDO_BYTES_DEFAULT;
    if (e->undo_count >= e->cap && e->cap < limit) {
        /* both lists grow together: a redo entry was an undo entry */
        uint32_t nc = e->cap ? (e->cap > limit / 2 ? limit : e->cap * 2) : (limit < 16 ? limit : 16);
        ved_snapshot* u = vx_calloc(e->s->alloc, nc, sizeof *u);
        ved_snapshot* d = vx_calloc(e->s->alloc, nc, sizeof *d);
        if (!u || !d) {
            vx_free(e->s->alloc, u);
            vx_free(e->s->alloc, d);
            return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %u undo steps", nc);
        }
        if (e->undo_count) memcpy(u, e->undo, (size_t)e->undo_count * sizeof *u);
        if (e->redo_count) memcpy(d, e->redo, (size_t)e->redo_count * sizeof *d);
        vx_free(e->s->alloc, e->undo);
        vx_free(e->s->alloc, e->redo);
        e->undo = u, e->redo = d, e->cap = nc;
    }
    ved_snapshot sn;
    vx_result r = snap_take(e->s, &sn, err);
    if (r) return r;
    for (uint32_t i = 0; i < e->redo_count; i++) snap_free(e->s->alloc, &e->redo[i]);
    e->redo_count = 0;
    while (e->undo_count && e->undo_count >= (limit < e->cap ? limit : e->cap)) drop_oldest(e);
    e->undo[e->undo_count++] = sn;
    e->serial++;
    /* the byte bound: the oldest go first, the new step stays */
    uint64_t total = 0;
    for (uint32_t i = 0; i < e->undo_count; i++) total += ved_snapshot_bytes(&e->undo[i]);
    while (e->undo_count > 1 && total > bytes) {
        total -= ved_snapshot_bytes(&e->undo[0]);
        drop_oldest(e);
    }
    return VX_OK;
}

/* A deep copy of the scene's materials (NULL, 0 when it has none). */
static vx_result materials_copy(const vx_svo_scene* s, vx_svo_material** out, vx_error* err) {
    *out = NULL;
    if (!s->material_count) return VX_OK;
    vx_svo_material* m = vx_calloc(s->alloc, s->material_count, sizeof *m);
    for (uint32_t i = 0; m && i < s->material_count; i++) {
        m[i] = (vx_svo_material){.id = s->materials[i].id, .dict_size = s->materials[i].dict_size};
        if (!m[i].dict_size) continue;
        if (!(m[i].dict = vx_alloc(s->alloc, m[i].dict_size))) {
            materials_free(s->alloc, m, i);
            m = NULL;
            break;
        }
        memcpy(m[i].dict, s->materials[i].dict, m[i].dict_size);
    }
    if (!m) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for an undo step of %u materials",
                           s->material_count);
    *out = m;
    return VX_OK;
}

vx_result ved_begin_materials(ved* e, vx_error* err) {
    vx_svo_material* m;
    vx_result r = materials_copy(e->s, &m, err);
    if (r || (r = ved_begin(e, err))) {
        materials_free(e->s->alloc, m, e->s->material_count);
        return r;
    }
    ved_snapshot* sn = &e->undo[e->undo_count - 1];
    sn->has_materials = true, sn->materials = m, sn->material_count = e->s->material_count;
    return VX_OK;
}

vx_result ved_material_set(vx_svo_scene* s, uint32_t id, const char* key, const char* value, vx_error* err) {
    size_t kl = key ? strlen(key) : 0, vl = value ? strlen(value) : 0;
    if (!kl || kl > 63 || (value && (!vl || vl > 63)))
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "material %u: a key and value of 1 to 63 bytes", id);
    uint32_t at = s->material_count;
    for (uint32_t i = 0; i < s->material_count && at == s->material_count; i++)
        if (s->materials[i].id == id) at = i;
    if (at == s->material_count && !value) return VX_OK; /* nothing to remove */
    const vx_svo_material* old = at < s->material_count ? &s->materials[at] : NULL;
    /* the new dictionary: the old pairs but key's, then key's (kept in its place when it was there) */
    size_t cap = (old ? old->dict_size : 0) + kl + vl + 2;
    char* d = vx_alloc(s->alloc, cap);
    if (!d) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for material %u", id);
    size_t n = 0;
    bool put = false;
    const char* p = old ? old->dict : NULL;
    const char* end = old && old->dict ? old->dict + old->dict_size : NULL;
    while (p && p < end) {
        const char* k = p;
        const char* z = memchr(k, 0, (size_t)(end - k));
        if (!z || z + 1 >= end) break;
        const char* v = z + 1;
        const char* z2 = memchr(v, 0, (size_t)(end - v));
        if (!z2) break;
        p = z2 + 1;
        bool mine = !strcmp(k, key);
        if (mine && (put || !value)) continue;
        const char* nv = mine ? value : v;
        size_t a = (size_t)(z - k) + 1, b = strlen(nv) + 1;
        if (n + a + b > cap) break; /* cannot happen: the old pairs plus key's fit */
        memcpy(d + n, k, a), n += a;
        memcpy(d + n, nv, b), n += b;
        put |= mine;
    }
    if (value && !put) {
        memcpy(d + n, key, kl + 1), n += kl + 1;
        memcpy(d + n, value, vl + 1), n += vl + 1;
    }
    if (!old) {
        vx_svo_material* m = vx_calloc(s->alloc, (size_t)s->material_count + 1, sizeof *m);
        if (!m) {
            vx_free(s->alloc, d);
            return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for material %u", id);
        }
        if (s->material_count) memcpy(m, s->materials, (size_t)s->material_count * sizeof *m);
        vx_free(s->alloc, s->materials);
        s->materials = m;
        s->material_count++;
        s->materials[at] = (vx_svo_material){.id = id};
    }
    vx_free(s->alloc, s->materials[at].dict);
    s->materials[at].dict = n ? d : NULL;
    s->materials[at].dict_size = (uint32_t)n;
    if (!n) vx_free(s->alloc, d);
    return VX_OK;
}

bool ved_undo(ved* e, vx_error* err) {
    (void)err;
    if (!e->undo_count) return false;
    ved_snapshot sn = e->undo[--e->undo_count];
    e->serial++;
    snap_swap(e->s, &sn);
    vox_swap(e, &sn);
    e->redo[e->redo_count++] = sn;
    return true;
}

bool ved_redo(ved* e, vx_error* err) {
    (void)err;
    if (!e->redo_count) return false;
    ved_snapshot sn = e->redo[--e->redo_count];
    e->serial++;
    snap_swap(e->s, &sn);
    vox_swap(e, &sn);
    e->undo[e->undo_count++] = sn;
    return true;
}

vx_svo_instance* ved_record(vx_svo_scene* s, uint32_t f, uint32_t i) {
    return f == 0 ? &s->instances[i] : &s->frame_instances[(size_t)(f - 1) * s->instance_count + i];
}

void ved_instance_box(const vx_svo_scene* s, uint32_t f, uint32_t i, double lo[3], double hi[3]) {
    const vx_svo_instance* in = vx_svo_scene_frame_instances(s, f) + i;
    const vx_svo_model* m = &s->models[in->model];
    double zero[3] = {0, 0, 0}, size[3] = {m->size[0], m->size[1], m->size[2]};
    vx_svo_box_map(in->xform, zero, size, lo, hi);
}

void ved_pivot(const vx_svo_scene* s, uint32_t f, uint32_t i, int axis, bool rotate, double p[3]) {
    double lo[3], hi[3];
    ved_instance_box(s, f, i, lo, hi);
    for (int k = 0; k < 3; k++) p[k] = 0.5 * (lo[k] + hi[k]);
    int a = (axis + 1) % 3, b = (axis + 2) % 3, lo_ax = a < b ? a : b;
    /* a quarter turn maps cells to cells only when p_a + p_b is whole */
    double sum = p[a] + p[b];
    if (rotate && sum != floor(sum)) p[lo_ax] -= 0.5;
}

void ved_move(vx_svo_scene* s, uint32_t i, const int32_t d[3]) {
    for (uint32_t f = 0; f < vx_svo_scene_frames(s); f++)
        for (int k = 0; k < 3; k++) ved_record(s, f, i)->xform[4 * k + 3] += d[k];
}

void ved_hide(vx_svo_scene* s, uint32_t i, bool hide) {
    for (uint32_t f = 0; f < vx_svo_scene_frames(s); f++) {
        vx_svo_instance* in = ved_record(s, f, i);
        in->flags = hide ? in->flags | VX_SVO_INSTANCE_HIDDEN : in->flags & ~(uint32_t)VX_SVO_INSTANCE_HIDDEN;
    }
}

void ved_quarter_turn(int axis, int q, int32_t r[9]) {
    q = ((q % 4) + 4) % 4;
    int32_t one[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    memcpy(r, one, sizeof one);
    int a = (axis + 1) % 3, b = (axis + 2) % 3; /* the rotated plane, a -> b for a positive turn */
    for (int t = 0; t < q; t++) {
        /* new row a = -old row b, new row b = old row a (rows of R * prev) */
        for (int c = 0; c < 3; c++) {
            int32_t ra = r[3 * a + c], rb = r[3 * b + c];
            r[3 * a + c] = -rb;
            r[3 * b + c] = ra;
        }
    }
}

/* Applies x -> R (x - p) + p to one record: M' = R M, t' = R (t - p) + p. */
static void apply_linear(vx_svo_instance* in, const int32_t r[9], const double p[3]) {
    double m[12];
    memcpy(m, in->xform, sizeof m);
    double tp[3] = {m[3] - p[0], m[7] - p[1], m[11] - p[2]};
    for (int row = 0; row < 3; row++) {
        for (int col = 0; col < 3; col++)
            in->xform[4 * row + col] =
                r[3 * row] * m[col] + r[3 * row + 1] * m[4 + col] + r[3 * row + 2] * m[8 + col];
        in->xform[4 * row + 3] = r[3 * row] * tp[0] + r[3 * row + 1] * tp[1] + r[3 * row + 2] * tp[2] + p[row];
    }
}

void ved_rotate(vx_svo_scene* s, uint32_t f, uint32_t i, int axis, int quarter_turns) {
    int32_t r[9];
    double p[3];
    ved_quarter_turn(axis, quarter_turns, r);
    ved_pivot(s, f, i, axis, true, p);
    for (uint32_t g = 0; g < vx_svo_scene_frames(s); g++) apply_linear(ved_record(s, g, i), r, p);
}

void ved_mirror(vx_svo_scene* s, uint32_t f, uint32_t i, int axis) {
    int32_t r[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    double p[3];
    r[4 * axis] = -1;
    ved_pivot(s, f, i, axis, false, p);
    for (uint32_t g = 0; g < vx_svo_scene_frames(s); g++) apply_linear(ved_record(s, g, i), r, p);
}

/* Replaces the instance records of every frame with `add` more per frame:
 * record j of each frame comes from old record map[j] of that frame
 * (map[j] == UINT32_MAX: extra[j - first_extra] in every frame). */
static vx_result relayout(vx_svo_scene* s, uint32_t count, const uint32_t* map, const vx_svo_instance* extra,
                          uint32_t first_extra, vx_error* err) {
    uint32_t nf = vx_svo_scene_frames(s), n = s->instance_count;
    vx_svo_instance* inst = vx_calloc(s->alloc, count ? count : 1, sizeof *inst);
    vx_svo_instance* fi = nf >= 2 && count ? vx_calloc(s->alloc, (size_t)(nf - 1) * count, sizeof *fi) : NULL;
    if (!inst || (nf >= 2 && count && !fi)) {
        vx_free(s->alloc, inst);
        vx_free(s->alloc, fi);
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %u instances in %u frames", count, nf);
    }
    for (uint32_t f = 0; f < nf; f++) {
        const vx_svo_instance* src = vx_svo_scene_frame_instances(s, f);
        vx_svo_instance* dst = f == 0 ? inst : fi + (size_t)(f - 1) * count;
        for (uint32_t j = 0; j < count; j++) dst[j] = map[j] < n ? src[map[j]] : extra[j - first_extra];
    }
    vx_free(s->alloc, s->instances);
    vx_free(s->alloc, s->frame_instances);
    s->instances = inst;
    s->frame_instances = fi;
    s->instance_count = count;
    if (nf >= 2 && !count) s->frame_count = 0; /* no records left to animate */
    return VX_OK;
}

void ved_rename(vx_svo_scene* s, uint32_t i, const char* name) {
    for (uint32_t f = 0; f < vx_svo_scene_frames(s); f++) {
        vx_svo_instance* in = ved_record(s, f, i);
        memset(in->name, 0, sizeof in->name);
        strncpy(in->name, name, sizeof in->name - 1);
    }
}

void ved_set_layer(vx_svo_scene* s, uint32_t i, uint32_t layer) {
    for (uint32_t f = 0; f < vx_svo_scene_frames(s); f++) ved_record(s, f, i)->layer = layer;
}

void ved_set_model(vx_svo_scene* s, uint32_t i, uint32_t model) {
    for (uint32_t f = 0; f < vx_svo_scene_frames(s); f++) ved_record(s, f, i)->model = model;
}

vx_result ved_duplicate(vx_svo_scene* s, uint32_t i, uint32_t* out, vx_error* err) {
    uint32_t n = s->instance_count;
    if (n == UINT32_MAX) return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "too many instances");
    uint32_t* map = vx_calloc(s->alloc, (size_t)n + 1, sizeof *map);
    if (!map) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %u instances", n + 1);
    for (uint32_t j = 0; j < n; j++) map[j] = j;
    map[n] = i;
    vx_result r = relayout(s, n + 1, map, NULL, n + 1, err);
    vx_free(s->alloc, map);
    if (!r) *out = n;
    return r;
}

void ved_delete(vx_svo_scene* s, uint32_t i) {
    /* in place: record j of frame f moves to j - (j > i) of the new stride n - 1, never forward */
    uint32_t nf = vx_svo_scene_frames(s), n = s->instance_count;
    memmove(&s->instances[i], &s->instances[i + 1], (size_t)(n - i - 1) * sizeof s->instances[0]);
    if (nf >= 2) {
        vx_svo_instance* fi = s->frame_instances;
        size_t d = 0;
        for (size_t k = 0; k < (size_t)(nf - 1) * n; k++)
            if (k % n != i) fi[d++] = fi[k];
        if (n == 1) {
            vx_free(s->alloc, fi);
            s->frame_instances = NULL;
            s->frame_count = 0;
        }
    }
    s->instance_count--;
}

typedef struct recolor_ctx {
    uint64_t* keys;
    uint32_t* rgba;
    size_t n;
    const vx_svo_model* m;
    const uint32_t* palette;
} recolor_ctx;

static bool recolor_cb(void* user, uint32_t x, uint32_t y, uint32_t z, uint32_t attr) {
    recolor_ctx* c = user;
    c->keys[c->n] = vx_svo_morton(x, y, z);
    uint32_t p = attr < c->m->attr_count ? c->m->palette[attr] : 0;
    c->rgba[c->n] = c->palette[p];
    c->n++;
    return true;
}

/* Rebuilds a palette-coloured model with RGBA8 attributes (colours from the
 * palette it was made for); other channels are dropped. */
static vx_result recolor_model(const vx_allocator* a, vx_svo_model* m, const uint32_t palette[256], vx_error* err) {
    size_t n = (size_t)m->voxel_count;
    if ((uint64_t)n != m->voxel_count) return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "model too large");
    recolor_ctx c = {.m = m, .palette = palette};
    c.keys = vx_calloc(a, n ? n : 1, sizeof *c.keys);
    c.rgba = vx_calloc(a, n ? n : 1, sizeof *c.rgba);
    vx_result r = VX_OK;
    if (!c.keys || !c.rgba) r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory recolouring a model");
    if (!r) r = vx_svo_decode_model(m, recolor_cb, &c, err);
    vx_svo_model nm;
    if (!r) {
        vx_svo_voxels v = {.count = c.n, .keys = c.keys, .attrs = VX_ATTR_RGBA8, .rgba = c.rgba};
        memcpy(v.size, m->size, sizeof v.size);
        r = vx_svo_build_model(&(vx_svo_build_desc){.alloc = a}, &v, &nm, NULL, err);
    }
    if (!r) {
        vx_svo_model_free(a, m);
        *m = nm;
    }
    vx_free(a, c.keys);
    vx_free(a, c.rgba);
    return r;
}

vx_result ved_add_scene(vx_svo_scene* s, vx_svo_scene* o, const int32_t d[3], uint32_t* first, vx_error* err) {
    bool uses_palette = false, s_uses_palette = false;
    for (uint32_t i = 0; i < o->model_count; i++) uses_palette |= (o->models[i].attrs & VX_ATTR_PALETTE) != 0;
    for (uint32_t i = 0; i < s->model_count; i++) s_uses_palette |= (s->models[i].attrs & VX_ATTR_PALETTE) != 0;
    bool same_palette = s->has_palette && o->has_palette && !memcmp(s->palette, o->palette, sizeof s->palette);
    vx_result r;
    if (uses_palette && s_uses_palette && !same_palette) {
        for (uint32_t i = 0; i < o->model_count; i++)
            if ((o->models[i].attrs & VX_ATTR_PALETTE) &&
                (r = recolor_model(o->alloc, &o->models[i], o->palette, err)))
                return r;
    } else if (uses_palette && !s_uses_palette) {
        memcpy(s->palette, o->palette, sizeof s->palette);
        s->has_palette = true;
    }
    uint32_t mc = s->model_count, ic = s->instance_count;
    if (o->model_count > UINT32_MAX - mc || o->instance_count > UINT32_MAX - ic)
        return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "too many models or instances");
    uint32_t count = ic + o->instance_count;
    vx_svo_model* models = vx_calloc(s->alloc, (size_t)mc + o->model_count + 1, sizeof *models);
    uint32_t* map = vx_calloc(s->alloc, (size_t)count + 1, sizeof *map);
    vx_svo_instance* extra = vx_calloc(s->alloc, (size_t)o->instance_count + 1, sizeof *extra);
    if (!models || !map || !extra) {
        vx_free(s->alloc, models);
        vx_free(s->alloc, map);
        vx_free(s->alloc, extra);
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory adding %u models", o->model_count);
    }
    for (uint32_t j = 0; j < count; j++) map[j] = j < ic ? j : UINT32_MAX;
    /* the added file's frame 0, still in every frame of s */
    for (uint32_t i = 0; i < o->instance_count; i++) {
        vx_svo_instance in = o->instances[i];
        in.model += mc;
        in.layer = UINT32_MAX; /* the added file's layers are not merged */
        for (int k = 0; k < 3; k++) in.xform[4 * k + 3] += d[k];
        extra[i] = in;
    }
    r = relayout(s, count, map, extra, ic, err);
    vx_free(s->alloc, map);
    vx_free(s->alloc, extra);
    if (r) {
        vx_free(s->alloc, models);
        return r;
    }
    if (mc) memcpy(models, s->models, (size_t)mc * sizeof *models);
    if (o->model_count) memcpy(models + mc, o->models, (size_t)o->model_count * sizeof *models);
    vx_free(s->alloc, s->models);
    s->models = models;
    s->model_count = mc + o->model_count;
    /* the models now belong to s */
    vx_free(o->alloc, o->models);
    o->models = NULL;
    o->model_count = 0;
    *first = ic;
    return VX_OK;
}
