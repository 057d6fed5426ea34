/* convert/mesh.c - glTF mesh -> svo scene: one model per non-empty region
 * of the brick voxelizer (convert/mesh_voxelize.c), placed by integer
 * translations in grid space; a share of the regions as parts, and the
 * scene assembled from all parts (the same path for one process and for
 * vox2svo under mpirun). */
#include <stdlib.h>
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <string.h>

#include "convert/mesh_internal.h"

/* ---- parts: one model per region ------------------------------------------------------ */

/* Regions arrive from several threads in any order: each built model is
 * appended as a part with its region index, and the parts are put in index
 * order afterwards, so the output does not depend on thread timing. */
typedef struct part_sink {
    const vx_conv_mesh_desc* desc;
    pthread_mutex_t lock;
    vx_conv_mesh_part* parts;
    size_t count, cap;
} part_sink;

/* The distinct material ids of a model's records, ascending (NULL and 0
 * when it stores none but 0). */
static vx_result used_materials(const vx_svo_model* m, const vx_allocator* a, uint16_t** out, uint32_t* count,
                                vx_error* err) {
    *out = NULL;
    *count = 0;
    if (!(m->attrs & VX_ATTR_MATERIAL) || !m->material) return VX_OK;
    uint64_t* seen = (uint64_t*)vx_calloc(a, 65536 / 64, sizeof *seen);
    if (!seen) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "material ids");
    uint32_t n = 0;
    for (uint32_t i = 0; i < m->attr_count; i++) {
        uint16_t id = m->material[i];
        if (id && !(seen[id >> 6] & (1ull << (id & 63)))) seen[id >> 6] |= 1ull << (id & 63), n++;
    }
    uint16_t* ids = n ? (uint16_t*)vx_alloc(a, (size_t)n * sizeof *ids) : NULL;
    if (n && !ids) {
        vx_free(a, seen);
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "%u material ids", n);
    }
    uint32_t k = 0;
    for (uint32_t w = 0; w < 65536 / 64; w++)
        for (uint64_t b = seen[w]; b; b &= b - 1) ids[k++] = (uint16_t)(w * 64 + (uint32_t)__builtin_ctzll(b));
    vx_free(a, seen);
    *out = ids;
    *count = n;
    return VX_OK;
}

static vx_result part_add(void* user, const vx__mesh_region* r, vx_error* err) {
    part_sink* k = (part_sink*)user;
    const vx_allocator* a = k->desc->alloc;
    vx_svo_voxels in;
    memset(&in, 0, sizeof in);
    memcpy(in.size, r->size, sizeof in.size);
    in.count = r->count;
    in.keys = r->keys;
    in.attrs = r->attrs;
    in.rgba = r->rgba;
    in.normal = r->normal;
    in.material = r->material;
    vx_svo_build_desc bd = k->desc->build;
    if (!bd.alloc) bd.alloc = a;
    bd.progress.func = NULL; /* progress comes from the voxelizer (this may run on any thread) */
    vx_conv_mesh_part p;
    memset(&p, 0, sizeof p);
    p.index = r->index;
    memcpy(p.origin, r->origin, sizeof p.origin);
    p.has_box = r->has_box;
    memcpy(p.box_min, r->box_min, sizeof p.box_min);
    memcpy(p.box_max, r->box_max, sizeof p.box_max);
    double t0 = vx_time_now();
    vx_result res;
    if (r->interned.rec || r->interned.pool) { /* the tuples come interned (or the tree built): the arrays stay out */
        in.rgba = in.normal = NULL;
        in.material = NULL;
        res = vx__svo_build_interned(&bd, &in, &r->interned, &p.model, &p.build, err);
    } else {
        res = vx_svo_build_model(&bd, &in, &p.model, &p.build, err);
    }
    p.seconds_build = vx_time_now() - t0;
    if (res) {
        char where[64];
        snprintf(where, sizeof where, "region at %u %u %u", r->origin[0], r->origin[1], r->origin[2]);
        vx_error_prefix(err, where);
        return res;
    }
    if ((res = used_materials(&p.model, a, &p.material_ids, &p.material_id_count, err))) {
        vx_svo_model_free(a, &p.model);
        return res;
    }
    pthread_mutex_lock(&k->lock);
    bool ok = vx_grow(a, (void**)&k->parts, &k->cap, k->count + 1, sizeof *k->parts);
    if (ok) k->parts[k->count++] = p;
    pthread_mutex_unlock(&k->lock);
    if (!ok) {
        vx_svo_model_free(a, &p.model);
        vx_free(a, p.material_ids);
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "%zu models", k->count + 1);
    }
    return VX_OK;
}

static int part_cmp(const void* pa, const void* pb) {
    const vx_conv_mesh_part *a = (const vx_conv_mesh_part*)pa, *b = (const vx_conv_mesh_part*)pb;
    return a->index < b->index ? -1 : a->index > b->index;
}

void vx_conv_mesh_parts_free(const vx_allocator* a, vx_conv_mesh_part* parts, size_t count) {
    for (size_t i = 0; parts && i < count; i++) {
        vx_svo_model_free(a, &parts[i].model);
        vx_free(a, parts[i].material_ids);
    }
    vx_free(a, parts);
}

/* Sums the parts' build statistics and times into st. */
static void parts_stats(const vx_conv_mesh_part* parts, size_t count, vx_conv_stats* st) {
    for (size_t i = 0; i < count; i++) {
        const vx_svo_build_stats* bs = &parts[i].build;
        vx_svo_build_stats* sum = &st->build;
        sum->input_voxels += bs->input_voxels;
        sum->voxels += bs->voxels;
        sum->desc_plain += bs->desc_plain;
        sum->desc_collapsed += bs->desc_collapsed;
        sum->desc_dag += bs->desc_dag;
        sum->far_pointers += bs->far_pointers;
        sum->attr_records += bs->attr_records;
        sum->bytes += bs->bytes;
        st->seconds_build += parts[i].seconds_build;
    }
}

vx_result vx_conv_mesh_share(const vx_conv_mesh_desc* desc_in, const vx_gltf_mesh* mesh, uint32_t share,
                             uint32_t shares, vx_conv_mesh_part** out, size_t* out_count, vx_conv_stats* stats,
                             vx_error* err) {
    vx_conv_mesh_desc desc = desc_in ? *desc_in : (vx_conv_mesh_desc){0};
    if (!mesh || !out || !out_count) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "mesh: NULL argument");
    *out = NULL;
    *out_count = 0;
    double t0 = vx_time_now();
    vx_conv_mesh_grid grid;
    vx_result r = vx_conv_mesh_grid_make(mesh->pos, mesh->tri_count, desc.res, &grid, err);
    if (r) return r;
    part_sink k;
    memset(&k, 0, sizeof k);
    k.desc = &desc;
    pthread_mutex_init(&k.lock, NULL);
    if (desc.backend)
        r = desc.backend->voxelize(desc.backend->self, &desc, mesh, &grid, vx__mesh_attrs(&desc, mesh), share, shares, true,
                                   part_add, &k, err);
    else
        r = vx__mesh_voxelize(&desc, mesh, &grid, vx__mesh_attrs(&desc, mesh), share, shares, part_add, &k, err);
    pthread_mutex_destroy(&k.lock);
    if (r) {
        vx_conv_mesh_parts_free(desc.alloc, k.parts, k.count);
        return r;
    }
    if (k.count > 1) qsort(k.parts, k.count, sizeof *k.parts, part_cmp);
    if (stats) {
        vx_conv_stats st;
        memset(&st, 0, sizeof st);
        parts_stats(k.parts, k.count, &st);
        st.models = st.instances = (uint32_t)(k.count < UINT32_MAX ? k.count : UINT32_MAX);
        st.seconds_voxelize = vx_time_now() - t0 - st.seconds_build;
        st.peak_bytes = vx_peak_rss();
        st.seconds_read = stats->seconds_read;
        *stats = st;
    }
    *out = k.parts;
    *out_count = k.count;
    return VX_OK;
}

/* Moves the parts' models into the scene, in region order. */
static vx_result parts_to_scene(vx_conv_mesh_part* parts, size_t n, vx_svo_scene* s, const vx_allocator* a,
                                vx_error* err) {
    if (n > UINT32_MAX) return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "%zu models", n);
    s->models = (vx_svo_model*)vx_calloc(a, n ? n : 1, sizeof *s->models);
    s->instances = (vx_svo_instance*)vx_calloc(a, n ? n : 1, sizeof *s->instances);
    if (!s->models || !s->instances) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "scene of %zu models", n);
    for (size_t i = 0; i < n; i++) {
        uint32_t mi = s->model_count;
        s->models[mi] = parts[i].model;
        memset(&parts[i].model, 0, sizeof parts[i].model);
        vx_svo_instance* inst = &s->instances[mi];
        const uint32_t* o = parts[i].origin;
        inst->xform[0] = inst->xform[5] = inst->xform[10] = 1.0;
        inst->xform[3] = o[0];
        inst->xform[7] = o[1];
        inst->xform[11] = o[2];
        inst->model = mi;
        inst->layer = UINT32_MAX;
        snprintf(inst->name, sizeof inst->name, "region %u %u %u", o[0], o[1], o[2]);
        s->model_count++;
        s->instance_count++;
    }
    return VX_OK;
}

/* Appends "key\0value\0" to a dictionary buffer of cap bytes. */
static void dict_put_text(char* d, size_t cap, uint32_t* len, const char* key, const char* val) {
    size_t kl = strlen(key) + 1, vl = strlen(val) + 1;
    if (*len + kl + vl > cap) return;
    memcpy(d + *len, key, kl);
    memcpy(d + *len + kl, val, vl);
    *len += (uint32_t)(kl + vl);
}

static void dict_put(char* d, size_t cap, uint32_t* len, const char* key, double v) {
    char val[32];
    snprintf(val, sizeof val, "%.9g", v);
    dict_put_text(d, cap, len, key, val);
}

/* glTF materials as MATL records with MagicaVoxel keys (svo.h,
 * vx_svo_material_resolve), ids as the voxels' VX_ATTR_MATERIAL values say
 * (mesh_internal.h, vx__mesh_mats): one per special material that samples
 * nothing (whether or not a cell names it, as before per-cell materials),
 * and one per id of a material sampled per cell that some part's cells name:
 *   transmission > 0: _type _glass, _trans, _rough, _ior = ior - 1
 *   else metallic > 0: _type _metal, _metal, _rough, _ior = ior - 1
 *   else: _type _emit (when emissive) or _diffuse, _rough
 *   emissive: _emit = the largest channel of the emission, and _emit_color
 *   its hue (the emission / _emit: glTF's emission does not depend on the
 *   base colour, so MagicaVoxel's rule, the voxel's colour as the hue, would
 *   tint a lamp with its base colour). Where an emissive texture varies the
 *   emission per cell, the emission is the record's quantized channels
 *   (vx__mesh_mats_record: each channel has its own levels), so the
 *   texel's hue survives to the level's precision. */
static vx_result add_materials(const vx_gltf_mesh* mesh, const vx_conv_mesh_part* parts, size_t count, vx_svo_scene* s,
                               const vx_allocator* a, vx_error* err) {
    vx__mesh_mats p;
    vx_result r = vx__mesh_mats_make(mesh, a, &p, err);
    if (r) return r;
    /* the ids: every fixed one, and the sampled ones the parts use */
    uint64_t* want = (uint64_t*)vx_calloc(a, 65536 / 64, sizeof *want);
    if (!want) {
        vx__mesh_mats_free(a, &p);
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "material ids");
    }
    uint32_t n = 0;
    for (uint32_t i = 0; i < p.count; i++) {
        uint32_t id = p.m[i].sample ? 0 : vx__mesh_mats_id(&p, i, 0, 0, 0);
        if (id && !(want[id >> 6] & (1ull << (id & 63)))) want[id >> 6] |= 1ull << (id & 63), n++;
    }
    for (size_t k = 0; p.sampled && k < count; k++)
        for (uint32_t j = 0; j < parts[k].material_id_count; j++) {
            uint32_t id = parts[k].material_ids[j], mi;
            float v[4], emission[3];
            if (!(want[id >> 6] & (1ull << (id & 63))) && vx__mesh_mats_record(&p, id, &mi, v, emission))
                want[id >> 6] |= 1ull << (id & 63), n++;
        }
    s->materials = n ? (vx_svo_material*)vx_calloc(a, n, sizeof *s->materials) : NULL;
    if (n && !s->materials) r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "%u materials", n);
    for (uint32_t w = 0; !r && w < 65536 / 64; w++)
        for (uint64_t bits = want[w]; bits && !r; bits &= bits - 1) {
            uint32_t id = w * 64 + (uint32_t)__builtin_ctzll(bits), i;
            float v[4], emission[3];
            if (!vx__mesh_mats_record(&p, id, &i, v, emission)) continue;
            const vx_gltf_material* g = &mesh->materials[i];
            char d[256];
            uint32_t len = 0;
            double e = v[2];
            bool glass = v[3] > 0, metal = !glass && v[0] > 0;
            const char* type = glass ? "_glass" : metal ? "_metal" : e > 0 ? "_emit" : "_diffuse";
            size_t tl = strlen("_type") + 1, vl = strlen(type) + 1;
            memcpy(d, "_type", tl), memcpy(d + tl, type, vl), len = (uint32_t)(tl + vl);
            if (glass) dict_put(d, sizeof d, &len, "_trans", v[3]);
            if (metal) dict_put(d, sizeof d, &len, "_metal", v[0]);
            dict_put(d, sizeof d, &len, "_rough", v[1]);
            if (glass || metal) dict_put(d, sizeof d, &len, "_ior", g->ior - 1.0);
            if (e > 0) dict_put(d, sizeof d, &len, "_emit", e);
            /* the emission's own colour (glTF: emission = emissiveFactor x emissiveTexture, not the base colour),
             * its largest channel 1: the factor's hue, or where a texture varies it per cell the record's
             * quantized channels' (so radiance = the cell's quantized emission) */
            if (e > 0) {
                char rgb[64];
                snprintf(rgb, sizeof rgb, "%.9g %.9g %.9g", emission[0] / v[2], emission[1] / v[2], emission[2] / v[2]);
                dict_put_text(d, sizeof d, &len, "_emit_color", rgb);
            }
            vx_svo_material* m = &s->materials[s->material_count];
            m->id = id;
            m->dict = (char*)vx_alloc(a, len);
            if (!m->dict) {
                r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "material %u", i);
                break;
            }
            memcpy(m->dict, d, len);
            m->dict_size = len;
            s->material_count++;
        }
    vx_free(a, want);
    vx__mesh_mats_free(a, &p);
    return r;
}

/* KHR_lights_punctual lights as scene lights: the mesh's world frame is the
 * scene's world frame (world_from_grid maps grid cells back to it;
 * vx_conv_mesh_file turned both +Z up), so positions and directions carry
 * over; a directional light's vx_light
 * direction points towards the light, the opposite of glTF's. voxkit's own
 * record in a light's extras (formats/gltf.h: svo_info --to-glb's sphere and
 * rect lights, radii, a sun's angular diameter) comes back as it was
 * written; values a type does not use stay 0. */
static vx_result add_lights(const vx_gltf_mesh* mesh, vx_svo_scene* s, const vx_allocator* a, vx_error* err) {
    if (!mesh->light_count) return VX_OK;
    s->lights = (vx_light*)vx_calloc(a, mesh->light_count, sizeof *s->lights);
    if (!s->lights) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "%u lights", mesh->light_count);
    for (uint32_t i = 0; i < mesh->light_count; i++) {
        const vx_gltf_light* g = &mesh->lights[i];
        vx_light* l = &s->lights[i];
        static const vx_light_type types[5] = {VX_LIGHT_DIRECTIONAL, VX_LIGHT_POINT, VX_LIGHT_SPOT, VX_LIGHT_SPHERE,
                                               VX_LIGHT_RECT};
        l->type = g->type < 5 ? types[g->type] : VX_LIGHT_POINT;
        bool dir = l->type == VX_LIGHT_DIRECTIONAL, aimed = l->type == VX_LIGHT_SPOT || l->type == VX_LIGHT_RECT;
        for (int k = 0; k < 3; k++) {
            l->position[k] = dir ? 0 : g->position[k];
            l->direction[k] = dir ? -g->direction[k] : aimed ? g->direction[k] : 0;
            l->color[k] = g->color[k];
            if (l->type == VX_LIGHT_RECT) l->tangent[k] = g->tangent[k];
        }
        l->intensity = g->intensity;
        l->range = l->type == VX_LIGHT_POINT || l->type == VX_LIGHT_SPOT ? g->range : 0;
        if (l->type == VX_LIGHT_SPOT) l->inner_cone = g->inner_cone, l->outer_cone = g->outer_cone;
        if (l->type == VX_LIGHT_POINT || l->type == VX_LIGHT_SPOT || l->type == VX_LIGHT_SPHERE) l->radius = g->radius;
        if (dir) l->angular_diameter = g->angular_diameter;
        if (l->type == VX_LIGHT_RECT) l->size[0] = g->size[0], l->size[1] = g->size[1];
        s->light_count = i + 1;
        vx_result r = vx_light_validate(l, i, err);
        if (r) {
            char p[96];
            snprintf(p, sizeof p, "glTF light %u ('%s') on node %u", g->index, g->name, g->node);
            vx_error_prefix(err, p);
            if (err) err->code = VX_ERR_BAD_FORMAT;
            return VX_ERR_BAD_FORMAT;
        }
    }
    return VX_OK;
}

vx_result vx_conv_mesh_assemble(const vx_conv_mesh_desc* desc_in, const vx_gltf_mesh* mesh, vx_conv_mesh_part* parts,
                                size_t count, vx_svo_scene* out, vx_conv_stats* stats, vx_error* err) {
    vx_conv_mesh_desc desc = desc_in ? *desc_in : (vx_conv_mesh_desc){0};
    if (!mesh || !out || (!parts && count)) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "mesh: NULL argument");
    if (count > 1) qsort(parts, count, sizeof *parts, part_cmp);
    for (size_t i = 1; i < count; i++)
        if (parts[i].index == parts[i - 1].index)
            return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "region %zu given twice", parts[i].index);
    vx_conv_mesh_grid grid;
    vx_result r = vx_conv_mesh_grid_make(mesh->pos, mesh->tri_count, desc.res, &grid, err);
    if (r) return r;
    vx_conv_stats st;
    memset(&st, 0, sizeof st);
    parts_stats(parts, count, &st);
    vx_svo_scene s;
    vx_svo_scene_init(&s, desc.alloc);
    r = parts_to_scene(parts, count, &s, desc.alloc, err);
    if (!r) r = add_materials(mesh, parts, count, &s, desc.alloc, err);
    if (!r) r = add_lights(mesh, &s, desc.alloc, err);
    /* voxkit's own record (formats/gltf.h: extras.voxkit_sky), already
     * checked by the reader and already in voxkit's frame (+Z up): unlike
     * the positions and lights it is not turned, with or without y_up (a
     * gradient's zenith and a map's axis are +Z in vx_sky's model) */
    if (!r) s.sky = mesh->sky;
    if (r) {
        vx_svo_scene_free(&s);
        return r;
    }
    memset(s.world_from_grid, 0, sizeof s.world_from_grid);
    for (int a = 0; a < 3; a++) {
        s.world_from_grid[a * 4 + a] = grid.h;
        s.world_from_grid[a * 4 + 3] = grid.min[a] + mesh->origin[a]; /* pos is relative to origin */
    }
    /* every model's box known (the GPU build): no pass over the models */
    bool boxes = count > 0;
    for (size_t i = 0; i < count; i++) boxes = boxes && parts[i].has_box;
    vx_svo_model_coded* info = boxes ? (vx_svo_model_coded*)vx_calloc(desc.alloc, count, sizeof *info) : NULL;
    if (info) {
        for (size_t i = 0; i < count; i++) {
            info[i].cells = s.models[i].voxel_count ? s.models[i].voxel_count : 1;
            memcpy(info[i].min, parts[i].box_min, sizeof info[i].min);
            memcpy(info[i].max, parts[i].box_max, sizeof info[i].max);
        }
        vx_svo_scene_update_bounds_coded(&s, info);
        vx_free(desc.alloc, info);
    } else {
        vx_svo_scene_update_bounds(&s);
    }
    st.models = s.model_count;
    st.instances = s.instance_count;
    st.peak_bytes = vx_peak_rss();
    if (stats) {
        st.seconds_read = stats->seconds_read;
        st.seconds_voxelize = stats->seconds_voxelize;
        *stats = st;
    }
    *out = s;
    return VX_OK;
}

vx_result vx_conv_mesh(const vx_conv_mesh_desc* desc, const vx_gltf_mesh* mesh, vx_svo_scene* out,
                       vx_conv_stats* stats, vx_error* err) {
    if (!mesh || !out) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "mesh: NULL argument");
    const vx_allocator* a = desc ? desc->alloc : NULL;
    double t0 = vx_time_now();
    vx_conv_mesh_part* parts = NULL;
    size_t n = 0;
    vx_result r = vx_conv_mesh_share(desc, mesh, 0, 1, &parts, &n, NULL, err);
    if (r) return r;
    vx_conv_stats st;
    memset(&st, 0, sizeof st);
    r = vx_conv_mesh_assemble(desc, mesh, parts, n, out, &st, err);
    vx_conv_mesh_parts_free(a, parts, n);
    if (r) return r;
    st.seconds_voxelize = vx_time_now() - t0 - st.seconds_build;
    if (stats) {
        st.seconds_read = stats->seconds_read;
        *stats = st;
    }
    return VX_OK;
}

vx_conv_mesh_desc vx_conv_mesh_desc_from_file(const vx_conv_file_desc* d) {
    vx_conv_file_desc f = d ? *d : (vx_conv_file_desc){0}; /* res 0 means 256 in both */
    return (vx_conv_mesh_desc){.build = f.build, .alloc = f.alloc, .logger = f.logger, .res = f.res,
                               .scene_set = f.scene_set, .scene = f.scene, .solid = f.solid, .normals = f.normals,
                               .no_color = f.no_color, .threads = f.threads, .region = f.region, .y_up = f.y_up,
                               .backend = f.mesh_backend};
}

vx_result vx_conv_mesh_read(const vx_conv_mesh_desc* desc_in, const char* path, vx_gltf_mesh* out, vx_error* err) {
    vx_conv_mesh_desc desc = desc_in ? *desc_in : (vx_conv_mesh_desc){0};
    if (!path || !out) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "mesh: NULL argument");
    vx_gltf_read_desc rd;
    memset(&rd, 0, sizeof rd);
    rd.alloc = desc.alloc;
    rd.logger = desc.logger;
    rd.scene_set = desc.scene_set;
    rd.scene = desc.scene;
    rd.no_images = desc.no_color;
    vx_gltf_mesh m;
    vx_result r = vx_gltf_read_file(&rd, path, &m, err);
    if (r) return r;
    if (m.tri_count == 0) {
        /* say why there is nothing to voxelize (a glTF may hold meshes that no node of its scene places, as
         * glTF-Validator's samples do, or only points and lines) rather than the voxelizer's bare "no triangles" */
        char sc[48] = "the file's root nodes (it has no scene)";
        bool one = m.scene != UINT32_MAX; /* a scene places, root nodes place */
        if (one) snprintf(sc, sizeof sc, "scene %u", m.scene);
        uint32_t inst = m.instance_count;
        vx_gltf_mesh_free(&m);
        if (inst == 0)
            return vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "no triangles to voxelize: %s place%s no mesh", sc,
                           one ? "s" : "");
        return vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET,
                       "no triangles to voxelize: %s place%s %u mesh instance%s, none with triangle primitives "
                       "(points and lines are not voxelized)",
                       sc, one ? "s" : "", inst, inst == 1 ? "" : "s");
    }
    /* m.sky is voxkit's record in voxkit's frame already: never turned */
    if (!desc.y_up) { /* glTF's +Y up to voxkit's +Z up: (x, y, z) -> (x, -z, y) */
        for (size_t v = 0; v < 3 * m.tri_count; v++) {
            float* p = m.pos + 3 * v;
            float y = p[1];
            p[1] = -p[2];
            p[2] = y;
        }
        double oy = m.origin[1];
        m.origin[1] = -m.origin[2];
        m.origin[2] = oy;
        for (uint32_t i = 0; i < m.light_count; i++) {
            double* v[3] = {m.lights[i].position, m.lights[i].direction, m.lights[i].tangent};
            for (int k = 0; k < 3; k++) {
                double y = v[k][1];
                v[k][1] = -v[k][2];
                v[k][2] = y;
            }
        }
    }
    *out = m;
    return VX_OK;
}

vx_result vx_conv_mesh_file(const vx_conv_mesh_desc* desc, const char* path, vx_svo_scene* out,
                            vx_conv_stats* stats, vx_error* err) {
    if (!path || !out) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "mesh: NULL argument");
    double t0 = vx_time_now();
    vx_gltf_mesh m;
    vx_result r = vx_conv_mesh_read(desc, path, &m, err);
    if (r) return r;
    vx_conv_stats st;
    memset(&st, 0, sizeof st);
    st.seconds_read = vx_time_now() - t0;
    r = vx_conv_mesh(desc, &m, out, &st, err);
    vx_gltf_mesh_free(&m);
    if (r == VX_OK && stats) *stats = st;
    return r;
}
