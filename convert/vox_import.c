/* convert/vox_import.c - MagicaVoxel scene -> svo scene.
 *
 * One svo model per vox model that some instance places (instancing is
 * kept: shapes that share a model become instances of one octree; unused
 * models are left out unless keep_unused), palette indices as the only
 * attribute. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "convert/convert.h"

static int32_t vox_floor_half(uint32_t s) { return (int32_t)(s / 2); }

static vx_result build_model(const vx_conv_vox_desc* d, const vx_vox_model* vm, vx_svo_model* out,
                             vx_svo_build_stats* st, vx_error* err) {
    const vx_allocator* a = d->alloc;
    size_t n = vm->voxel_count;
    uint64_t* keys = (uint64_t*)vx_calloc(a, n ? n : 1, sizeof *keys);
    uint8_t* pal = (uint8_t*)vx_alloc(a, n ? n : 1);
    if (!keys || !pal) {
        vx_free(a, keys);
        vx_free(a, pal);
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "cannot allocate %zu voxels", n);
    }
    for (size_t i = 0; i < n; i++) {
        const uint8_t* v = vm->xyzi + 4 * i;
        keys[i] = vx_svo_morton(v[0], v[1], v[2]);
        pal[i] = v[3];
    }
    vx_svo_voxels in = {
        .size = {vm->size[0], vm->size[1], vm->size[2]},
        .count = n,
        .keys = keys,
        .attrs = n ? VX_ATTR_PALETTE : 0u,
        .palette = n ? pal : NULL,
    };
    vx_svo_build_desc bd = d->build;
    if (!bd.alloc) bd.alloc = a;
    vx_result r = vx_svo_build_model(&bd, &in, out, st, err);
    vx_free(a, keys);
    vx_free(a, pal);
    return r;
}

/* One vox instance as an svo instance (new_index: svo model of each vox model). */
static void convert_instance(const vx_vox_scene* in, const vx_vox_instance* vi, const uint32_t* new_index, vx_svo_instance* si) {
    const uint32_t* sz = in->models[vi->model].size;
    int32_t c[3] = {vox_floor_half(sz[0]), vox_floor_half(sz[1]), vox_floor_half(sz[2])};
    /* MagicaVoxel pivot: cell v lands at floor(R (v + 1/2 - c) + t), i.e.
     * the affine map p -> R p + (t - R c) applied to the cell centre. */
    for (int row = 0; row < 3; row++) {
        int64_t rc = 0;
        for (int col = 0; col < 3; col++) {
            si->xform[row * 4 + col] = (double)vi->rot[row * 3 + col];
            rc += (int64_t)vi->rot[row * 3 + col] * c[col];
        }
        si->xform[row * 4 + 3] = (double)((int64_t)vi->t[row] - rc);
    }
    si->model = new_index[vi->model];
    si->flags = vi->hidden ? VX_SVO_INSTANCE_HIDDEN : 0u;
    si->layer = UINT32_MAX;
    for (uint32_t l = 0; l < in->layer_count; l++)
        if (vi->layer >= 0 && in->layers[l].id == vi->layer) si->layer = l;
    snprintf(si->name, sizeof si->name, "%s", vi->name);
}

static void add_stats(vx_svo_build_stats* sum, const vx_svo_build_stats* s) {
    sum->input_voxels += s->input_voxels;
    sum->voxels += s->voxels;
    sum->desc_plain += s->desc_plain;
    sum->desc_collapsed += s->desc_collapsed;
    sum->desc_dag += s->desc_dag;
    sum->far_pointers += s->far_pointers;
    sum->attr_records += s->attr_records;
    sum->bytes += s->bytes;
}

vx_result vx_conv_vox(const vx_conv_vox_desc* desc, const vx_vox_scene* in, vx_svo_scene* out, vx_conv_stats* stats,
                      vx_error* err) {
    vx_conv_vox_desc d = desc ? *desc : (vx_conv_vox_desc){0};
    if (!in || !out) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "null argument");
    const vx_allocator* a = d.alloc;
    vx_conv_stats cs = {0};
    double t0 = vx_time_now();

    vx_svo_scene s;
    vx_svo_scene_init(&s, a);
    vx_result r = VX_OK;

    /* models some instance places; new_index[i]: svo model of vox model i */
    uint32_t* new_index = (uint32_t*)vx_calloc(a, in->model_count ? in->model_count : 1, sizeof *new_index);
    if (!new_index) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory");
    for (uint32_t i = 0; i < in->model_count; i++) new_index[i] = UINT32_MAX;
    /* an animation (frame_instances): every frame is stored, frame 0 as
     * the instances and the others as frames; a model is used when some
     * frame places it */
    bool anim = in->frame_count > 1 && in->frame_instances;
    uint32_t frames = anim ? in->frame_count : 1;
    const vx_vox_instance* all = anim ? in->frame_instances : in->instances;
    for (uint64_t i = 0; i < (uint64_t)frames * in->instance_count; i++) {
        uint32_t m = all[i].model;
        if (m >= in->model_count) {
            vx_free(a, new_index);
            return vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "frame %llu instance %llu uses model %u of %u",
                           (unsigned long long)(i / (in->instance_count ? in->instance_count : 1)),
                           (unsigned long long)(i % (in->instance_count ? in->instance_count : 1)), m, in->model_count);
        }
        new_index[m] = 0;
    }
    uint32_t kept = 0;
    for (uint32_t i = 0; i < in->model_count; i++) {
        if (new_index[i] == UINT32_MAX) cs.models_unused++;
        if (new_index[i] != UINT32_MAX || d.keep_unused) new_index[i] = kept++;
    }

    s.model_count = kept;
    s.models = (vx_svo_model*)vx_calloc(a, kept ? kept : 1, sizeof *s.models);
    s.instances = (vx_svo_instance*)vx_calloc(a, in->instance_count ? in->instance_count : 1, sizeof *s.instances);
    s.layers = (vx_svo_layer*)vx_calloc(a, in->layer_count ? in->layer_count : 1, sizeof *s.layers);
    s.materials = (vx_svo_material*)vx_calloc(a, in->material_count ? in->material_count : 1, sizeof *s.materials);
    if (!s.models || !s.instances || !s.layers || !s.materials) {
        s.model_count = 0;
        r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory");
        goto fail;
    }
    for (uint32_t i = 0; i < in->model_count; i++) {
        if (new_index[i] == UINT32_MAX) continue; /* left out */
        vx_svo_build_stats st = {0};
        r = build_model(&d, &in->models[i], &s.models[new_index[i]], &st, err);
        if (r != VX_OK) {
            char where[48];
            snprintf(where, sizeof where, "model %u", i);
            vx_error_prefix(err, where);
            goto fail;
        }
        add_stats(&cs.build, &st);
        if (in->models[i].voxel_count) s.has_palette = true;
    }
    memcpy(s.palette, in->palette, sizeof s.palette);
    s.palette[0] = 0;

    /* layers: vox layer ids are arbitrary ints, svo layers are indices */
    s.layer_count = in->layer_count;
    for (uint32_t i = 0; i < in->layer_count; i++) {
        const vx_vox_layer* l = &in->layers[i];
        snprintf(s.layers[i].name, sizeof s.layers[i].name, "%s", l->name);
        s.layers[i].flags = l->hidden ? VX_SVO_LAYER_HIDDEN : 0u;
        s.layers[i].rgba = l->rgba;
    }

    s.instance_count = in->instance_count;
    for (uint32_t i = 0; i < in->instance_count; i++) convert_instance(in, &all[i], new_index, &s.instances[i]);
    if (anim) {
        if ((r = vx_svo_scene_alloc_frames(&s, frames, err)) != VX_OK) goto fail;
        for (uint32_t f = 1; f < frames; f++)
            for (uint32_t i = 0; i < in->instance_count; i++)
                convert_instance(in, &all[(size_t)f * in->instance_count + i], new_index,
                                 &s.frame_instances[(size_t)(f - 1) * in->instance_count + i]);
    }

    /* MagicaVoxel files carry a material for each of the 256 palette
     * entries; only those some stored voxel uses describe the scene. */
    bool used[256] = {false};
    for (uint32_t i = 0; i < in->model_count; i++)
        if (new_index[i] != UINT32_MAX)
            for (uint32_t k = 0; k < in->models[i].voxel_count; k++) used[in->models[i].xyzi[4 * (size_t)k + 3]] = true;
    s.material_count = 0;
    for (uint32_t i = 0; i < in->material_count; i++) {
        const vx_vox_material* m = &in->materials[i];
        if (m->id > 255 || !used[m->id]) continue;
        vx_svo_material* sm = &s.materials[s.material_count];
        sm->id = m->id;
        sm->dict_size = m->dict_size;
        sm->dict = (char*)vx_alloc(a, m->dict_size ? m->dict_size : 1);
        if (!sm->dict) {
            r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory");
            goto fail;
        }
        if (m->dict_size) memcpy(sm->dict, m->dict, m->dict_size);
        s.material_count++;
    }

    vx_svo_scene_update_bounds(&s);
    cs.models = s.model_count;
    cs.instances = s.instance_count;
    cs.frames = vx_svo_scene_frames(&s);
    cs.seconds_build = vx_time_now() - t0;
    cs.peak_bytes = vx_peak_rss();
    vx_free(a, new_index);
    if (stats) *stats = cs;
    *out = s;
    return VX_OK;

fail:
    vx_free(a, new_index);
    vx_svo_scene_free(&s);
    return r;
}
