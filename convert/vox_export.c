/* convert/vox_export.c - svo scene -> MagicaVoxel scene (svo_info --to-vox).
 *
 * The inverse of vx_conv_vox for scenes that fit MagicaVoxel's limits:
 * models of at most 256 cells per side, 255 colours, instances whose
 * matrices are signed permutations with integer translations. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "convert/convert.h"

typedef struct export_ctx {
    const vx_svo_scene* s;
    const vx_svo_model* m;
    uint8_t* xyzi;
    uint32_t n, cap;
    uint32_t* pal;  /* the palette made, by index: palette models' entries, then RGBA8 models' colours */
    uint8_t* taken; /* entries of pal in use (palette models' voxels, colours given) */
    bool too_many_colors;
} export_ctx;

/* An RGBA8 colour's entry: one of that colour in use, else the first free
 * (a scene may mix palette and RGBA8 models: svo_view's add of a file
 * with another palette). */
static uint8_t color_index(export_ctx* c, uint32_t rgba) {
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

static bool collect(void* user, uint32_t x, uint32_t y, uint32_t z, uint32_t attr) {
    export_ctx* c = (export_ctx*)user;
    if (c->n == c->cap) return false; /* cannot happen: cap is the model's voxel count */
    uint8_t* v = c->xyzi + 4 * (size_t)c->n++;
    v[0] = (uint8_t)x;
    v[1] = (uint8_t)y;
    v[2] = (uint8_t)z;
    if (c->m->attrs & VX_ATTR_PALETTE) v[3] = c->m->palette[attr] ? c->m->palette[attr] : 1;
    else if (c->m->attrs & VX_ATTR_RGBA8) v[3] = color_index(c, c->m->rgba[attr]);
    else v[3] = 1;
    return true;
}

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

vx_result vx_conv_svo_to_vox(const vx_svo_scene* in, const vx_allocator* a, vx_vox_scene* out, vx_error* err) {
    if (!in || !out) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "null argument");
    vx_vox_scene v;
    memset(&v, 0, sizeof v);
    v.alloc = a;
    v.version = 150;
    vx_result r = VX_OK;
    bool uses_rgba = false, uses_palette = false;
    /* the palette models' entries first: RGBA8 colours take the others */
    uint32_t base[256], pal[256] = {0};
    uint8_t taken[256] = {0};
    if (in->has_palette) memcpy(base, in->palette, sizeof base);
    else {
        memcpy(base, vx_vox_default_palette, sizeof base);
        base[1] = 0xFFFFFFFFu; /* geometry only: white */
    }
    for (uint32_t i = 0; i < in->model_count; i++) {
        const vx_svo_model* m = &in->models[i];
        if (!(m->attrs & VX_ATTR_PALETTE) || !m->palette) continue;
        for (uint32_t k = 0; k < m->attr_count; k++) {
            uint8_t e = m->palette[k] ? m->palette[k] : 1;
            taken[e] = 1, pal[e] = base[e];
        }
    }

    v.models = (vx_vox_model*)vx_calloc(a, in->model_count ? in->model_count : 1, sizeof *v.models);
    v.instances = (vx_vox_instance*)vx_calloc(a, in->instance_count ? in->instance_count : 1, sizeof *v.instances);
    v.layers = (vx_vox_layer*)vx_calloc(a, in->layer_count ? in->layer_count : 1, sizeof *v.layers);
    v.materials = (vx_vox_material*)vx_calloc(a, in->material_count ? in->material_count : 1, sizeof *v.materials);
    if (!v.models || !v.instances || !v.layers || !v.materials) {
        r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory");
        goto fail;
    }
    for (uint32_t i = 0; i < in->model_count; i++) {
        const vx_svo_model* m = &in->models[i];
        if (m->size[0] > 256 || m->size[1] > 256 || m->size[2] > 256) {
            r = vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET,
                        "model %u is %ux%ux%u: .vox models are at most 256 cells per side", i, m->size[0], m->size[1],
                        m->size[2]);
            goto fail;
        }
        if (m->voxel_count > 256u * 256u * 256u) {
            r = vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "model %u claims %llu voxels", i,
                        (unsigned long long)m->voxel_count);
            goto fail;
        }
        uint32_t n = (uint32_t)m->voxel_count;
        v.models[i].size[0] = m->size[0];
        v.models[i].size[1] = m->size[1];
        v.models[i].size[2] = m->size[2];
        v.models[i].xyzi = (uint8_t*)vx_calloc(a, n ? n : 1, 4);
        v.model_count = i + 1;
        if (!v.models[i].xyzi) {
            r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory");
            goto fail;
        }
        export_ctx c = {in, m, v.models[i].xyzi, 0, n, pal, taken, false};
        r = vx_svo_decode_model(m, collect, &c, err);
        if (r != VX_OK) goto fail;
        if (c.too_many_colors) {
            r = vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET, "more than 255 distinct colours do not fit a .vox palette");
            goto fail;
        }
        v.models[i].voxel_count = c.n;
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
    uint32_t frames = vx_svo_scene_frames(in), I = in->instance_count;
    if (frames > 1) {
        v.frame_instances = (vx_vox_instance*)vx_calloc(a, (size_t)frames * I + 1, sizeof *v.frame_instances);
        if (!v.frame_instances) {
            r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %u frames", frames);
            goto fail;
        }
        v.frame_count = frames;
    }
    for (uint32_t f = 0; f < frames; f++) {
        const vx_svo_instance* fi = vx_svo_scene_frame_instances(in, f);
        for (uint32_t i = 0; i < I; i++) {
            vx_vox_instance* vi = frames > 1 ? &v.frame_instances[(size_t)f * I + i] : &v.instances[i];
            if ((r = export_instance(in, &fi[i], i, f, vi, err)) != VX_OK) goto fail;
        }
    }
    if (frames > 1 && I) memcpy(v.instances, v.frame_instances, (size_t)I * sizeof *v.instances);
    v.instance_count = in->instance_count;

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
    *out = v;
    return VX_OK;
fail:
    vx_vox_scene_free(&v);
    return r;
}
