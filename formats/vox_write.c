/* formats/vox_write.c - MagicaVoxel .vox writer.
 *
 * Layout (version 150, what MagicaVoxel itself writes):
 *   MAIN { SIZE XYZI (per model), nTRN 0 -> nGRP 1 -> (nTRN 2k+2 -> nSHP 2k+3
 *   per instance), LAYR (per layer), RGBA (if has_rgba), IMAP (if has_imap),
 *   MATL (per material) }
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

/* Whether instance i's nTRN has a frame at f. */
static bool trn_key(const vx_vox_scene* s, uint32_t i, uint32_t f, uint32_t frames) {
    if (f == 0 || (i == 0 && f == frames - 1)) return true;
    const vx_vox_instance *a = frame_of(s, i, f), *p = frame_of(s, i, f - 1);
    return memcmp(a->rot, p->rot, sizeof a->rot) != 0 || memcmp(a->t, p->t, sizeof a->t) != 0;
}
static bool shp_key(const vx_vox_scene* s, uint32_t i, uint32_t f) {
    return f == 0 || frame_of(s, i, f)->model != frame_of(s, i, f - 1)->model;
}

static void put_graph(vx_buf* b, const vx_vox_scene* s) {
    static const char* const no_str[1] = {""};
    /* root transform -> group of every instance */
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
    vx_buf_u32le(b, s->instance_count);
    for (uint32_t i = 0; i < s->instance_count; i++) vx_buf_u32le(b, 2 + 2 * i);
    end_chunk(b, at);

    bool anim = animated(s);
    uint32_t frames = anim ? s->frame_count : 1;
    for (uint32_t i = 0; i < s->instance_count; i++) {
        const vx_vox_instance* in = frame_of(s, i, 0);
        const char* keys[2];
        const char* vals[2];
        int n = 0;
        if (in->name[0]) keys[n] = "_name", vals[n++] = in->name;
        if (in->hidden) keys[n] = "_hidden", vals[n++] = "1";
        at = begin_chunk(b, "nTRN");
        vx_buf_u32le(b, 2 + 2 * i);
        put_dict(b, n, keys, vals);
        vx_buf_u32le(b, 3 + 2 * i);
        vx_buf_u32le(b, UINT32_MAX);
        vx_buf_u32le(b, (uint32_t)in->layer);
        uint32_t nk = 0;
        for (uint32_t f = 0; f < frames; f++) nk += trn_key(s, i, f, frames);
        vx_buf_u32le(b, nk);
        for (uint32_t f = 0; f < frames; f++) {
            if (!trn_key(s, i, f, frames)) continue;
            const vx_vox_instance* fi = frame_of(s, i, f);
            uint8_t rb = 0;
            vx_vox_rot_to_byte(fi->rot, &rb); /* validated */
            char rs[8], ts[48], fs[16];
            snprintf(rs, sizeof rs, "%u", (unsigned)rb);
            snprintf(ts, sizeof ts, "%d %d %d", fi->t[0], fi->t[1], fi->t[2]);
            snprintf(fs, sizeof fs, "%u", f);
            const char* fk[3] = {"_r", "_t", "_f"};
            const char* fv[3] = {rs, ts, fs};
            put_dict(b, anim ? 3 : 2, fk, fv);
        }
        end_chunk(b, at);

        at = begin_chunk(b, "nSHP");
        vx_buf_u32le(b, 3 + 2 * i);
        put_dict(b, 0, no_str, no_str);
        nk = 0;
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
    /* two int32 node ids per instance after the root and its group */
    if (s->instance_count > ((uint32_t)INT32_MAX - 3) / 2)
        return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "vx_vox_write: %u instances exceed the node id range",
                       s->instance_count);
    vx_buf b = {.alloc = alloc};
    vx_buf_append(&b, "VOX ", 4);
    vx_buf_u32le(&b, 150);
    size_t main_at = begin_chunk(&b, "MAIN");
    put_models(&b, s);
    put_graph(&b, s);
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
