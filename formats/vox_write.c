/* formats/vox_write.c - MagicaVoxel .vox writer.
 *
 * Layout (version 150, what MagicaVoxel itself writes):
 *   MAIN { SIZE XYZI (per model), nTRN 0 -> nGRP 1 -> (nTRN -> nSHP per
 *   instance, or nTRN -> nGRP -> (nTRN -> nSHP per instance of it) per
 *   group), LAYR (per layer), RGBA (if has_rgba), IMAP (if has_imap),
 *   MATL (per material) }; node ids 2, 3, ... in the order written.
 * Each instance carries its already composed rotation and translation, so
 * reading the file back gives the same instances whatever graph they came
 * from. An animation (frame_count > 1 with frame_instances) is written as
 * keyframes: each instance's nTRN gets a frame (_f) where its rotation or
 * translation changes and its nSHP a model key (_f) where its model
 * changes, frame 0 always; instance 0 also gets a key at the last frame so
 * that the reader finds the frame count again. */
#include <stdio.h>
#include <string.h>

#include "formats/vox.h"

/* Opens a chunk and returns where its header starts, for end_chunk. */
static size_t begin_chunk(vx_buf* b, const char id[4]) {
    size_t at = b->size;
    vx_buf_append(b, id, 4);
    vx_buf_u32le(b, 0);
    vx_buf_u32le(b, 0);
    return at;
}

static void end_chunk(vx_buf* b, size_t at) {
    if (b->failed) return;
    /* sizes above INT32_MAX are rejected once the whole file is written */
    size_t n = b->size - at - 12;
    vx_buf_put_u32le(b->data + at + 4, (uint32_t)(n > UINT32_MAX ? UINT32_MAX : n));
}

static void put_str(vx_buf* b, const char* s, size_t n) {
    vx_buf_u32le(b, (uint32_t)n);
    vx_buf_append(b, s, n);
}

static void put_cstr(vx_buf* b, const char* s) { put_str(b, s, strlen(s)); }

/* A DICT from parallel arrays of NUL-terminated keys and values. */
static void put_dict(vx_buf* b, int n, const char* const* keys, const char* const* vals) {
    vx_buf_u32le(b, (uint32_t)n);
    for (int i = 0; i < n; i++) {
        put_cstr(b, keys[i]);
        put_cstr(b, vals[i]);
    }
}

static void put_models(vx_buf* b, const vx_vox_scene* s) {
    for (uint32_t i = 0; i < s->model_count; i++) {
        const vx_vox_model* m = &s->models[i];
        size_t at = begin_chunk(b, "SIZE");
        for (int k = 0; k < 3; k++) vx_buf_u32le(b, m->size[k]);
        end_chunk(b, at);
        at = begin_chunk(b, "XYZI");
        vx_buf_u32le(b, m->voxel_count);
        vx_buf_append(b, m->xyzi, (size_t)m->voxel_count * 4);
        end_chunk(b, at);
    }
}

static bool animated(const vx_vox_scene* s) { return s->frame_count > 1 && s->frame_instances; }

/* Instance i in frame f (the instance itself in a still scene). */
static const vx_vox_instance* frame_of(const vx_vox_scene* s, uint32_t i, uint32_t f) {
    return animated(s) ? &s->frame_instances[(size_t)f * s->instance_count + i] : &s->instances[i];
}

/* Group g in frame f (groups[] when the animation gives no frame_groups). */
static const vx_vox_group* group_of(const vx_vox_scene* s, uint32_t g, uint32_t f) {
    return animated(s) && s->frame_groups ? &s->frame_groups[(size_t)f * s->group_count + g] : &s->groups[g];
}

/* The transform of an instance (group false) or a group in frame f. */
static void xf_of(const vx_vox_scene* s, bool group, uint32_t i, uint32_t f, const int32_t** rot, const int32_t** t) {
    if (group) {
        const vx_vox_group* g = group_of(s, i, f);
        *rot = g->rot, *t = g->t;
    } else {
        const vx_vox_instance* in = frame_of(s, i, f);
        *rot = in->rot, *t = in->t;
    }
}

/* Whether the nTRN has a frame at f (last: a key at the last frame too). */
static bool trn_key(const vx_vox_scene* s, bool group, uint32_t i, uint32_t f, uint32_t frames, bool last) {
    if (f == 0 || (last && f == frames - 1)) return true;
    const int32_t *ra, *ta, *rp, *tp;
    xf_of(s, group, i, f, &ra, &ta);
    xf_of(s, group, i, f - 1, &rp, &tp);
    return memcmp(ra, rp, 9 * sizeof *ra) != 0 || memcmp(ta, tp, 3 * sizeof *ta) != 0;
}
static bool shp_key(const vx_vox_scene* s, uint32_t i, uint32_t f) {
    return f == 0 || frame_of(s, i, f)->model != frame_of(s, i, f - 1)->model;
}

static void put_empty_dict(vx_buf* b) { vx_buf_u32le(b, 0); }

/* An instance's or a group's transform node (id) over its child node. */
static void put_trn(vx_buf* b, const vx_vox_scene* s, bool group, uint32_t i, uint32_t id, uint32_t child) {
    const char* name;
    bool hidden;
    int32_t layer;
    if (group) {
        const vx_vox_group* g = group_of(s, i, 0);
        name = g->name, hidden = g->hidden, layer = g->layer;
    } else {
        const vx_vox_instance* in = frame_of(s, i, 0);
        name = in->name, hidden = in->hidden, layer = in->layer;
    }
    const char* keys[2];
    const char* vals[2];
    int n = 0;
    if (name[0]) keys[n] = "_name", vals[n++] = name;
    if (hidden) keys[n] = "_hidden", vals[n++] = "1";
    size_t at = begin_chunk(b, "nTRN");
    vx_buf_u32le(b, id);
    put_dict(b, n, keys, vals);
    vx_buf_u32le(b, child);
    vx_buf_u32le(b, UINT32_MAX);
    vx_buf_u32le(b, (uint32_t)layer);
    bool anim = animated(s), last = !group && i == 0; /* instance 0 marks the frame count */
    uint32_t frames = anim ? s->frame_count : 1, nk = 0;
    for (uint32_t f = 0; f < frames; f++) nk += trn_key(s, group, i, f, frames, last);
    vx_buf_u32le(b, nk);
    for (uint32_t f = 0; f < frames; f++) {
        if (!trn_key(s, group, i, f, frames, last)) continue;
        const int32_t *rot, *t;
        xf_of(s, group, i, f, &rot, &t);
        uint8_t rb = 0;
        vx_vox_rot_to_byte(rot, &rb); /* validated */
        char rs[8], ts[48], fs[16];
        snprintf(rs, sizeof rs, "%u", (unsigned)rb);
        snprintf(ts, sizeof ts, "%d %d %d", t[0], t[1], t[2]);
        snprintf(fs, sizeof fs, "%u", f);
        const char* fk[3] = {"_r", "_t", "_f"};
        const char* fv[3] = {rs, ts, fs};
        put_dict(b, anim ? 3 : 2, fk, fv);
    }
    end_chunk(b, at);
}

static void put_shp(vx_buf* b, const vx_vox_scene* s, uint32_t i, uint32_t id) {
    bool anim = animated(s);
    uint32_t frames = anim ? s->frame_count : 1, nk = 0;
    size_t at = begin_chunk(b, "nSHP");
    vx_buf_u32le(b, id);
    put_empty_dict(b);
    for (uint32_t f = 0; f < frames; f++) nk += shp_key(s, i, f);
    vx_buf_u32le(b, nk);
    for (uint32_t f = 0; f < frames; f++) {
        if (!shp_key(s, i, f)) continue;
        vx_buf_u32le(b, frame_of(s, i, f)->model);
        char fs[16];
        snprintf(fs, sizeof fs, "%u", f);
        const char* mk[1] = {"_f"};
        const char* mv[1] = {fs};
        put_dict(b, anim ? 1 : 0, mk, mv);
    }
    end_chunk(b, at);
}

static void put_grp(vx_buf* b, uint32_t id, uint32_t first_kid, uint32_t kids) {
    size_t at = begin_chunk(b, "nGRP");
    vx_buf_u32le(b, id);
    put_empty_dict(b);
    vx_buf_u32le(b, kids);
    for (uint32_t k = 0; k < kids; k++) vx_buf_u32le(b, first_kid + 2 * k);
    end_chunk(b, at);
}

/* The root's children, in order: an instance of no group (item i), or a
 * group (item ~g) where its first instance comes, groups without instances
 * last; members: each group's instances in order (gstart[g] .. gstart[g+1]). */
typedef struct graph_plan {
    uint32_t* items;
    uint32_t item_count;
    uint32_t* gstart;
    uint32_t* members;
} graph_plan;

static bool plan_graph(const vx_vox_scene* s, const vx_allocator* a, graph_plan* p) {
    uint32_t I = s->instance_count, G = s->group_count;
    p->items = (uint32_t*)vx_alloc(a, ((size_t)I + G + 1) * sizeof *p->items);
    p->gstart = (uint32_t*)vx_calloc(a, (size_t)G + 2, sizeof *p->gstart);
    p->members = (uint32_t*)vx_alloc(a, ((size_t)I + 1) * sizeof *p->members);
    if (!p->items || !p->gstart || !p->members) return false;
    /* a counting sort (groups from 0 here): gstart[g + 1] counts group g's
     * instances, summed it is where group g + 1 starts; gstart[g] is then
     * group g's cursor, left at its end, and the shift by one puts the
     * starts back */
    for (uint32_t i = 0; i < I; i++)
        if (frame_of(s, i, 0)->group) p->gstart[frame_of(s, i, 0)->group]++; /* validated: <= G */
    for (uint32_t g = 1; g <= G; g++) p->gstart[g] += p->gstart[g - 1];
    for (uint32_t i = 0; i < I; i++) {
        uint32_t g = frame_of(s, i, 0)->group;
        if (g) p->members[p->gstart[g - 1]++] = i;
    }
    for (uint32_t g = G; g > 0; g--) p->gstart[g] = p->gstart[g - 1];
    p->gstart[0] = 0;
    p->item_count = 0;
    for (uint32_t i = 0; i < I; i++) {
        uint32_t g = frame_of(s, i, 0)->group;
        if (!g) p->items[p->item_count++] = i;
        else if (p->members[p->gstart[g - 1]] == i) p->items[p->item_count++] = ~(g - 1);
    }
    for (uint32_t g = 0; g < G; g++)
        if (p->gstart[g] == p->gstart[g + 1]) p->items[p->item_count++] = ~g;
    return true;
}

static void plan_free(const vx_allocator* a, graph_plan* p) {
    vx_free(a, p->items);
    vx_free(a, p->gstart);
    vx_free(a, p->members);
}

/* Node ids: 0 the root transform, 1 its group, then in the order written. */
static void put_graph(vx_buf* b, const vx_vox_scene* s, const graph_plan* p) {
    static const char* const no_str[1] = {""};
    size_t at = begin_chunk(b, "nTRN");
    vx_buf_u32le(b, 0);
    put_dict(b, 0, no_str, no_str);
    vx_buf_u32le(b, 1);
    vx_buf_u32le(b, UINT32_MAX); /* reserved: -1 */
    vx_buf_u32le(b, UINT32_MAX); /* no layer */
    vx_buf_u32le(b, 1);
    put_dict(b, 0, no_str, no_str);
    end_chunk(b, at);

    at = begin_chunk(b, "nGRP");
    vx_buf_u32le(b, 1);
    put_dict(b, 0, no_str, no_str);
    vx_buf_u32le(b, p->item_count);
    uint32_t id = 2;
    for (uint32_t k = 0; k < p->item_count; k++) {
        vx_buf_u32le(b, id);
        uint32_t it = p->items[k];
        id += 2;
        if (it >= s->instance_count) id += 2 * (p->gstart[~it + 1] - p->gstart[~it]);
    }
    end_chunk(b, at);

    id = 2;
    for (uint32_t k = 0; k < p->item_count; k++) {
        uint32_t it = p->items[k];
        if (it < s->instance_count) {
            put_trn(b, s, false, it, id, id + 1);
            put_shp(b, s, it, id + 1);
            id += 2;
            continue;
        }
        uint32_t g = ~it, n = p->gstart[g + 1] - p->gstart[g];
        put_trn(b, s, true, g, id, id + 1);
        put_grp(b, id + 1, id + 2, n);
        id += 2;
        for (uint32_t m = 0; m < n; m++, id += 2) {
            uint32_t i = p->members[p->gstart[g] + m];
            put_trn(b, s, false, i, id, id + 1);
            put_shp(b, s, i, id + 1);
        }
    }
}

static void put_layers(vx_buf* b, const vx_vox_scene* s) {
    for (uint32_t i = 0; i < s->layer_count; i++) {
        const vx_vox_layer* l = &s->layers[i];
        const char* keys[3];
        const char* vals[3];
        char color[16];
        int n = 0;
        if (l->name[0]) keys[n] = "_name", vals[n++] = l->name;
        if (l->hidden) keys[n] = "_hidden", vals[n++] = "1";
        if (l->rgba) {
            snprintf(color, sizeof color, "%u %u %u", (unsigned)(l->rgba & 0xff), (unsigned)((l->rgba >> 8) & 0xff),
                     (unsigned)((l->rgba >> 16) & 0xff));
            keys[n] = "_color", vals[n++] = color;
        }
        size_t at = begin_chunk(b, "LAYR");
        vx_buf_u32le(b, (uint32_t)l->id);
        put_dict(b, n, keys, vals);
        vx_buf_u32le(b, UINT32_MAX);
        end_chunk(b, at);
    }
}

static void put_materials(vx_buf* b, const vx_vox_scene* s) {
    for (uint32_t i = 0; i < s->material_count; i++) {
        const vx_vox_material* m = &s->materials[i];
        size_t at = begin_chunk(b, "MATL");
        vx_buf_u32le(b, m->id);
        /* validated: an even number of NUL-terminated strings */
        uint32_t strings = 0;
        for (uint32_t k = 0; k < m->dict_size; k++) strings += m->dict[k] == 0;
        vx_buf_u32le(b, strings / 2);
        for (uint32_t k = 0; k < m->dict_size;) {
            size_t len = strlen(m->dict + k);
            put_str(b, m->dict + k, len);
            k += (uint32_t)len + 1;
        }
        end_chunk(b, at);
    }
}

vx_result vx_vox_write(const vx_vox_scene* s, const vx_allocator* alloc, uint8_t** out_data, size_t* out_size,
                       vx_error* err) {
    if (!s || !out_data || !out_size) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "vx_vox_write: null argument");
    vx_result r = vx_vox_validate(s, err);
    if (r != VX_OK) return r;
    /* two int32 node ids per instance and per group after the root and its group */
    if ((uint64_t)s->instance_count + s->group_count > ((uint32_t)INT32_MAX - 3) / 2)
        return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "vx_vox_write: %u instances and %u groups exceed the node id range",
                       s->instance_count, s->group_count);
    graph_plan plan = {0};
    if (!plan_graph(s, alloc, &plan)) {
        plan_free(alloc, &plan);
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "vx_vox_write: out of memory");
    }
    vx_buf b = {.alloc = alloc};
    vx_buf_append(&b, "VOX ", 4);
    vx_buf_u32le(&b, 150);
    size_t main_at = begin_chunk(&b, "MAIN");
    put_models(&b, s);
    put_graph(&b, s, &plan);
    plan_free(alloc, &plan);
    put_layers(&b, s);
    if (s->has_rgba) {
        size_t at = begin_chunk(&b, "RGBA");
        for (int i = 1; i < 256; i++) vx_buf_u32le(&b, s->palette[i]);
        vx_buf_u32le(&b, 0);
        end_chunk(&b, at);
    }
    if (s->has_imap) {
        size_t at = begin_chunk(&b, "IMAP");
        vx_buf_append(&b, s->imap, 256);
        end_chunk(&b, at);
    }
    put_materials(&b, s);
    if (b.failed) {
        vx_buf_free(&b);
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "vx_vox_write: out of memory");
    }
    if (b.size - 20 > (size_t)INT32_MAX) {
        vx_buf_free(&b);
        return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "vx_vox_write: %zu bytes of chunks exceed the 2 GiB MAIN limit",
                       b.size - 20);
    }
    vx_buf_put_u32le(b.data + main_at + 8, (uint32_t)(b.size - main_at - 12));
    *out_data = b.data;
    *out_size = b.size;
    return VX_OK;
}

vx_result vx_vox_write_file(const vx_write_desc* desc, const vx_vox_scene* s, const char* path, vx_error* err) {
    if (!path) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "vx_vox_write_file: null path");
    const vx_allocator* a = desc ? desc->alloc : NULL;
    uint8_t* data;
    size_t size;
    vx_result r = vx_vox_write(s, a, &data, &size, err);
    if (r != VX_OK) return r;
    r = vx_file_write_atomic(path, a, data, size, err);
    vx_free(a, data);
    if (r != VX_OK) vx_error_prefix(err, path);
    return r;
}
