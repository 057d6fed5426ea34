/* svo/svo_scene.c - scene lifetime, bounds and material lookup. */
#include <math.h>
#include <string.h>

#include "svo/svo_internal.h"

void vx_svo_model_free(const vx_allocator* a, vx_svo_model* m) {
    if (!m) return;
    vx_free(a, m->nodes);
    vx_free(a, m->palette);
    vx_free(a, m->rgba);
    vx_free(a, m->normal);
    vx_free(a, m->material);
    vx_free(a, m->density);
    memset(m, 0, sizeof *m);
}

static uint64_t fnv(uint64_t h, const void* p, size_t n) {
    const uint8_t* b = (const uint8_t*)p;
    for (size_t i = 0; i < n; i++) h = (h ^ b[i]) * 0x100000001b3ull;
    return h;
}

/* The channel arrays of a model with their element sizes, in VX_ATTR_* order. */
static void channels(const vx_svo_model* m, const void* ch[5], size_t el[5]) {
    ch[0] = m->palette, el[0] = 1;
    ch[1] = m->rgba, el[1] = 4;
    ch[2] = m->normal, el[2] = 4;
    ch[3] = m->material, el[3] = 2;
    ch[4] = m->density, el[4] = 4;
}

uint64_t vx_svo_model_hash(const vx_svo_model* m) {
    uint64_t h = 0xcbf29ce484222325ull;
    h = fnv(h, m->size, sizeof m->size);
    h = fnv(h, &m->root, sizeof m->root);
    h = fnv(h, &m->root_attr, sizeof m->root_attr);
    h = fnv(h, &m->attrs, sizeof m->attrs);
    h = fnv(h, &m->attr_count, sizeof m->attr_count);
    if (m->node_count && m->nodes) h = fnv(h, m->nodes, (size_t)m->node_count * 4);
    const void* ch[5];
    size_t el[5];
    channels(m, ch, el);
    for (int k = 0; k < 5; k++)
        if ((m->attrs >> k & 1u) && ch[k] && m->attr_count) h = fnv(h, ch[k], el[k] * m->attr_count);
    return h;
}

uint32_t vx_svo_model_digest(const vx_svo_model* m) {
    if (!m || (m->node_count && !m->nodes)) return 0;
    uint32_t f[12] = {m->size[0], m->size[1], m->size[2], m->depth, m->root, m->root_attr, m->attrs, (uint32_t)m->voxel_count,
                      (uint32_t)(m->voxel_count >> 32), m->node_count, m->attr_count, 0x53564F44u};
    /* in the host's byte order: a digest is only compared within a process */
    uint32_t crc = vx__svo_crc32(0, f, sizeof f);
    if (m->node_count) crc = vx__svo_crc32(crc, m->nodes, (size_t)m->node_count * 4);
    const void* ch[5];
    size_t el[5];
    channels(m, ch, el);
    for (int k = 0; k < 5; k++) {
        if (!(m->attrs >> k & 1u) || !m->attr_count) continue;
        if (!ch[k]) return 0;
        crc = vx__svo_crc32(crc, ch[k], el[k] * m->attr_count);
    }
    return crc ? crc : 1u;
}

bool vx_svo_model_equal(const vx_svo_model* a, const vx_svo_model* b) {
    if (memcmp(a->size, b->size, sizeof a->size) || a->depth != b->depth || a->root != b->root || a->root_attr != b->root_attr ||
        a->attrs != b->attrs || a->voxel_count != b->voxel_count || a->node_count != b->node_count || a->attr_count != b->attr_count)
        return false;
    if (a->node_count && memcmp(a->nodes, b->nodes, (size_t)a->node_count * 4)) return false;
    const void *ca[5], *cb[5];
    size_t el[5];
    channels(a, ca, el);
    channels(b, cb, el);
    for (int k = 0; k < 5; k++)
        if ((a->attrs >> k & 1u) && a->attr_count && (!ca[k] || !cb[k] || memcmp(ca[k], cb[k], el[k] * a->attr_count))) return false;
    return true;
}

void vx_svo_scene_init(vx_svo_scene* s, const vx_allocator* a) {
    if (!s) return;
    memset(s, 0, sizeof *s);
    s->alloc = a;
    s->world_from_grid[0] = s->world_from_grid[5] = s->world_from_grid[10] = 1.0;
}

void vx_svo_scene_free(vx_svo_scene* s) {
    if (!s) return;
    const vx_allocator* a = s->alloc;
    for (uint32_t i = 0; s->models && i < s->model_count; i++) vx_svo_model_free(a, &s->models[i]);
    for (uint32_t i = 0; s->materials && i < s->material_count; i++) vx_free(a, s->materials[i].dict);
    vx_free(a, s->models);
    vx_free(a, s->instances);
    vx_free(a, s->layers);
    vx_free(a, s->materials);
    vx_free(a, s->lights);
    vx_free(a, s->frame_instances);
    memset(s, 0, sizeof *s);
}

/* ---- animation frames ------------------------------------------------------------- */

uint32_t vx_svo_scene_frames(const vx_svo_scene* s) {
    return s && s->frame_count > 1 && (s->frame_instances || s->instance_count == 0) ? s->frame_count : 1;
}

const vx_svo_instance* vx_svo_scene_frame_instances(const vx_svo_scene* s, uint32_t f) {
    if (!s || f >= vx_svo_scene_frames(s)) return NULL;
    return f == 0 ? s->instances : s->frame_instances + (size_t)(f - 1) * s->instance_count;
}

bool vx_svo_scene_frame(const vx_svo_scene* s, uint32_t f, vx_svo_scene* view) {
    if (!s || !view || f >= vx_svo_scene_frames(s)) return false;
    *view = *s;
    view->instances = (vx_svo_instance*)vx_svo_scene_frame_instances(s, f);
    view->frame_count = 1;
    view->frame_instances = NULL;
    return true;
}

vx_result vx_svo_scene_alloc_frames(vx_svo_scene* s, uint32_t frame_count, vx_error* err) {
    if (!s || frame_count < 2 || (s->instance_count && !s->instances))
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "svo scene: frames: need a scene and at least 2 frames");
    uint64_t n = (uint64_t)(frame_count - 1) * s->instance_count;
    if (n > VX_SVO_FRAMES_MAX_BYTES / sizeof(vx_svo_instance))
        return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "svo scene: %u frames of %u instances need %llu bytes, the limit is %llu",
                       frame_count, s->instance_count, (unsigned long long)(n * sizeof(vx_svo_instance)),
                       (unsigned long long)VX_SVO_FRAMES_MAX_BYTES);
    vx_svo_instance* fi = (vx_svo_instance*)vx_calloc(s->alloc, n ? (size_t)n : 1, sizeof *fi);
    if (!fi) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "svo scene: out of memory for %u frames", frame_count);
    for (uint32_t f = 1; f < frame_count && s->instance_count; f++)
        memcpy(fi + (size_t)(f - 1) * s->instance_count, s->instances, (size_t)s->instance_count * sizeof *fi);
    vx_free(s->alloc, s->frame_instances);
    s->frame_instances = fi;
    s->frame_count = frame_count;
    return VX_OK;
}

/* Bounds are exact for each model's occupied box: the box's extreme cell
 * centres are among its 8 corner cells, the map is affine and floor is
 * monotone, so transforming those 8 centres gives the grid cells that bound
 * the instance. Instances that are hidden, or on a hidden layer, are left out.
 * Each model is analysed once (many instances may share it); without memory
 * for that cache it is analysed per instance, with the same result. */
static bool model_extent(const vx_svo_model* m, vx__svo_extent* e) {
    if (vx__svo_analyze_opt(m, e, true, NULL) != VX_OK) { /* an edited model counts by its cells */
        /* an invalid model: fall back to its declared size */
        if (m->root == VX_SVO_ROOT_EMPTY) return false;
        memset(e, 0, sizeof *e);
        e->cells = 1;
        for (int k = 0; k < 3; k++) e->max[k] = m->size[k];
    }
    return e->cells != 0;
}

typedef struct extent_jobs {
    const vx_svo_scene* s;
    vx__svo_extent* ext;
} extent_jobs;

static void extent_job(void* ctx, unsigned thread, uint32_t i) {
    (void)thread;
    extent_jobs* j = (extent_jobs*)ctx;
    if (!model_extent(&j->s->models[i], &j->ext[i])) memset(&j->ext[i], 0, sizeof j->ext[i]);
}

/* want, hooks: vx_svo_bounds_desc's threads and testing */
static void scene_bounds(const vx_svo_scene* s, unsigned want, const vx_svo_testing* hooks, double bmin[3],
                         double bmax[3]) {
    /* large scenes: every model's extent in parallel first (each is a full
     * pass over its tree), then the instances */
    unsigned threads = s->models ? vx__svo_threads(s, want, hooks) : 1;
    vx__svo_extent* ext = threads > 1 ? (vx__svo_extent*)vx_calloc(s->alloc, s->model_count, sizeof *ext) : NULL;
    if (ext) {
        extent_jobs j = {s, ext};
        vx_run_jobs(threads, s->model_count, extent_job, &j);
    }
    vx__svo_scene_bounds_ext(s, ext, bmin, bmax);
    vx_free(s->alloc, ext);
}

void vx__svo_scene_bounds(const vx_svo_scene* s, double bmin[3], double bmax[3]) {
    scene_bounds(s, 0, NULL, bmin, bmax);
}

void vx__svo_scene_bounds_ext(const vx_svo_scene* s, const vx__svo_extent* known, double bmin[3], double bmax[3]) {
    double mn[3] = {INFINITY, INFINITY, INFINITY}, mx[3] = {-INFINITY, -INFINITY, -INFINITY};
    bool any = false;
    vx__svo_extent* cache = NULL;
    uint8_t* state = NULL; /* 0 not analysed, 1 empty, 2 extent in cache */
    if (!known && s->models && s->model_count) {
        cache = (vx__svo_extent*)vx_calloc(s->alloc, s->model_count, sizeof *cache);
        state = (uint8_t*)vx_calloc(s->alloc, s->model_count, 1);
    }
    for (uint32_t i = 0; s->instances && i < s->instance_count; i++) {
        const vx_svo_instance* in = &s->instances[i];
        if (!s->models || !vx_svo_instance_visible(s, i)) continue;
        vx__svo_extent local, *e = &local;
        if (known) {
            local = known[in->model];
            if (local.cells == 0) continue;
        } else if (cache && state) {
            e = &cache[in->model];
            if (!state[in->model]) state[in->model] = model_extent(&s->models[in->model], e) ? 2 : 1;
            if (state[in->model] == 1) continue;
        } else if (!model_extent(&s->models[in->model], e)) {
            continue;
        }
        for (int c = 0; c < 8; c++) {
            double p[3];
            for (int k = 0; k < 3; k++) p[k] = ((c >> k) & 1 ? (double)e->max[k] - 1.0 : (double)e->min[k]) + 0.5;
            for (int r = 0; r < 3; r++) {
                const double* row = in->xform + 4 * r;
                double g = floor(row[0] * p[0] + row[1] * p[1] + row[2] * p[2] + row[3]);
                if (g < mn[r]) mn[r] = g;
                if (g + 1.0 > mx[r]) mx[r] = g + 1.0;
            }
        }
        any = true;
    }
    vx_free(s->alloc, cache);
    vx_free(s->alloc, state);
    for (int k = 0; k < 3; k++) {
        bmin[k] = any ? mn[k] : 0.0;
        bmax[k] = any ? mx[k] : 0.0;
    }
}

void vx_svo_scene_update_bounds_coded(vx_svo_scene* s, const vx_svo_model_coded* info) {
    if (!s || (s->model_count && !info)) return;
    vx__svo_extent* ext = s->model_count ? (vx__svo_extent*)vx_calloc(s->alloc, s->model_count, sizeof *ext) : NULL;
    if (s->model_count && !ext) return;
    for (uint32_t i = 0; i < s->model_count; i++) {
        ext[i].cells = info[i].cells;
        memcpy(ext[i].min, info[i].min, sizeof ext[i].min);
        memcpy(ext[i].max, info[i].max, sizeof ext[i].max);
    }
    vx__svo_scene_bounds_ext(s, ext, s->bounds_min, s->bounds_max);
    vx_free(s->alloc, ext);
}

void vx_svo_scene_update_bounds_ex(const vx_svo_bounds_desc* desc, vx_svo_scene* s) {
    if (!s) return;
    const vx_svo_bounds_desc d = desc ? *desc : (vx_svo_bounds_desc){0};
    scene_bounds(s, d.threads, &d.testing, s->bounds_min, s->bounds_max);
}

void vx_svo_scene_update_bounds(vx_svo_scene* s) { vx_svo_scene_update_bounds_ex(NULL, s); }

const char* vx_svo_material_get(const vx_svo_material* m, const char* key) {
    if (!m || !key || !m->dict || m->dict_size == 0) return NULL;
    const char* p = m->dict;
    const char* end = m->dict + m->dict_size;
    while (p < end) {
        const char* k = p;
        const char* z = memchr(k, 0, (size_t)(end - k));
        if (!z || z + 1 >= end) return NULL;
        const char* v = z + 1;
        const char* z2 = memchr(v, 0, (size_t)(end - v));
        if (!z2) return NULL;
        if (strcmp(k, key) == 0) return v;
        p = z2 + 1;
    }
    return NULL;
}

/* ---- scene facts --------------------------------------------------------------------- */

bool vx_svo_instance_visible(const vx_svo_scene* s, uint32_t i) {
    if (!s || i >= s->instance_count) return false;
    const vx_svo_instance* in = &s->instances[i];
    if (in->flags & VX_SVO_INSTANCE_HIDDEN) return false;
    if (in->layer < s->layer_count && s->layers && (s->layers[in->layer].flags & VX_SVO_LAYER_HIDDEN)) return false;
    return in->model < s->model_count;
}

bool vx_svo_instance_drawn(const vx_svo_scene* s, uint32_t i) {
    return vx_svo_instance_visible(s, i) && s->models[s->instances[i].model].root != VX_SVO_ROOT_EMPTY;
}

void vx_svo_instance_world(const vx_svo_scene* s, const vx_svo_instance* in, double w[12]) {
    const double* a = s->world_from_grid;
    const double* b = in->xform;
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 4; c++) {
            double v = a[4 * r + 0] * b[c] + a[4 * r + 1] * b[4 + c] + a[4 * r + 2] * b[8 + c];
            if (c == 3) v += a[4 * r + 3];
            w[4 * r + c] = v;
        }
}

void vx_svo_box_map(const double w[12], const double in_lo[3], const double in_hi[3], double lo[3], double hi[3]) {
    for (int k = 0; k < 3; k++) lo[k] = INFINITY, hi[k] = -INFINITY;
    for (int c = 0; c < 8; c++) {
        double p[3] = {(c & 1) ? in_hi[0] : in_lo[0], (c & 2) ? in_hi[1] : in_lo[1], (c & 4) ? in_hi[2] : in_lo[2]};
        for (int r = 0; r < 3; r++) {
            double q = w[4 * r] * p[0] + w[4 * r + 1] * p[1] + w[4 * r + 2] * p[2] + w[4 * r + 3];
            lo[r] = fmin(lo[r], q), hi[r] = fmax(hi[r], q);
        }
    }
}

void vx_svo_instance_world_box(const vx_svo_scene* s, const vx_svo_instance* in, double lo[3], double hi[3]) {
    const vx_svo_model* m = &s->models[in->model];
    double w[12], zero[3] = {0, 0, 0}, size[3] = {m->size[0], m->size[1], m->size[2]};
    vx_svo_instance_world(s, in, w);
    vx_svo_box_map(w, zero, size, lo, hi);
}

void vx_svo_scene_world_bounds(const vx_svo_scene* s, double lo[3], double hi[3]) {
    bool any = false;
    for (int k = 0; k < 3; k++) lo[k] = INFINITY, hi[k] = -INFINITY;
    for (uint32_t f = 0; f < vx_svo_scene_frames(s); f++) {
        vx_svo_scene v;
        vx_svo_scene_frame(s, f, &v);
        for (uint32_t i = 0; i < v.instance_count; i++) {
            if (!vx_svo_instance_drawn(&v, i)) continue;
            double a[3], b[3];
            vx_svo_instance_world_box(&v, &v.instances[i], a, b);
            for (int k = 0; k < 3; k++) lo[k] = fmin(lo[k], a[k]), hi[k] = fmax(hi[k], b[k]);
            any = true;
        }
    }
    if (!any)
        for (int k = 0; k < 3; k++) lo[k] = hi[k] = 0;
}

uint32_t vx_svo_attr_rgba(const vx_svo_scene* s, const vx_svo_model* m, uint32_t a) {
    if (a >= m->attr_count) return 0xFFFFFFFFu;
    if ((m->attrs & VX_ATTR_RGBA8) && m->rgba) return m->rgba[a];
    if ((m->attrs & VX_ATTR_PALETTE) && m->palette) return s->palette[m->palette[a]];
    return 0xFFFFFFFFu;
}
