/* convert/mesh.c - glTF mesh -> svo scene: one model per non-empty region
 * of the brick voxelizer (convert/mesh_voxelize.c), placed by integer
 * translations in grid space. */
#include <pthread.h>
#include <stdio.h>
#include <string.h>

#include "convert/mesh_internal.h"

/* ---- scene ------------------------------------------------------------------------ */

/* Regions arrive from several threads in any order: each built model goes
 * to the slot of its region index, and the scene is assembled in index
 * order afterwards, so the output does not depend on thread timing. */
typedef struct scene_sink {
    const vx_conv_mesh_desc* desc;
    pthread_mutex_t lock;
    vx_svo_model* slot;
    uint32_t (*origin)[3];
    bool* used;
    size_t slots;
    vx_conv_stats* st;
} scene_sink;

static vx_result scene_add(void* user, const vx__mesh_region* r, vx_error* err) {
    scene_sink* k = (scene_sink*)user;
    const vx_allocator* a = k->desc->alloc;
    pthread_mutex_lock(&k->lock);
    if (!k->slot) {
        k->slot = (vx_svo_model*)vx_calloc(a, r->region_count, sizeof *k->slot);
        k->origin = (uint32_t(*)[3])vx_calloc(a, r->region_count, sizeof *k->origin);
        k->used = (bool*)vx_calloc(a, r->region_count, sizeof *k->used);
        k->slots = r->region_count;
    }
    bool ok = k->slot && k->origin && k->used && r->index < k->slots;
    pthread_mutex_unlock(&k->lock);
    if (!ok) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "scene of %zu regions", r->region_count);
    vx_svo_voxels in;
    memset(&in, 0, sizeof in);
    memcpy(in.size, r->size, sizeof in.size);
    in.count = r->count;
    in.keys = r->keys;
    in.attrs = r->attrs;
    in.rgba = r->rgba;
    in.normal = r->normal;
    vx_svo_build_desc bd = k->desc->build;
    if (!bd.alloc) bd.alloc = a;
    bd.progress.func = NULL; /* progress comes from the voxelizer (this may run on any thread) */
    vx_svo_model m;
    memset(&m, 0, sizeof m);
    vx_svo_build_stats bs;
    memset(&bs, 0, sizeof bs);
    double t0 = vx_time_now();
    vx_result res = vx_svo_build_model(&bd, &in, &m, &bs, err);
    double dt = vx_time_now() - t0;
    if (res) {
        char where[64];
        snprintf(where, sizeof where, "region at %u %u %u", r->origin[0], r->origin[1], r->origin[2]);
        vx_error_prefix(err, where);
        return res;
    }
    pthread_mutex_lock(&k->lock);
    k->st->seconds_build += dt;
    vx_svo_build_stats* sum = &k->st->build;
    sum->input_voxels += bs.input_voxels;
    sum->voxels += bs.voxels;
    sum->desc_plain += bs.desc_plain;
    sum->desc_collapsed += bs.desc_collapsed;
    sum->desc_dag += bs.desc_dag;
    sum->far_pointers += bs.far_pointers;
    sum->attr_records += bs.attr_records;
    sum->bytes += bs.bytes;
    k->slot[r->index] = m;
    memcpy(k->origin[r->index], r->origin, sizeof k->origin[0]);
    k->used[r->index] = true;
    pthread_mutex_unlock(&k->lock);
    return VX_OK;
}

static void sink_free(scene_sink* k) {
    const vx_allocator* a = k->desc->alloc;
    for (size_t i = 0; k->slot && i < k->slots; i++)
        if (k->used[i]) vx_svo_model_free(a, &k->slot[i]);
    vx_free(a, k->slot);
    vx_free(a, k->origin);
    vx_free(a, k->used);
    pthread_mutex_destroy(&k->lock);
}

/* Moves the built models into the scene, in region order. */
static vx_result sink_assemble(scene_sink* k, vx_svo_scene* s, vx_error* err) {
    const vx_allocator* a = k->desc->alloc;
    size_t n = 0;
    for (size_t i = 0; i < k->slots; i++) n += k->used[i];
    if (n > UINT32_MAX) return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "%zu models", n);
    s->models = (vx_svo_model*)vx_calloc(a, n ? n : 1, sizeof *s->models);
    s->instances = (vx_svo_instance*)vx_calloc(a, n ? n : 1, sizeof *s->instances);
    if (!s->models || !s->instances) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "scene of %zu models", n);
    for (size_t i = 0; i < k->slots; i++) {
        if (!k->used[i]) continue;
        uint32_t mi = s->model_count;
        s->models[mi] = k->slot[i];
        k->used[i] = false;
        vx_svo_instance* inst = &s->instances[mi];
        inst->xform[0] = inst->xform[5] = inst->xform[10] = 1.0;
        inst->xform[3] = k->origin[i][0];
        inst->xform[7] = k->origin[i][1];
        inst->xform[11] = k->origin[i][2];
        inst->model = mi;
        inst->layer = UINT32_MAX;
        snprintf(inst->name, sizeof inst->name, "region %u %u %u", k->origin[i][0], k->origin[i][1], k->origin[i][2]);
        s->model_count++;
        s->instance_count++;
    }
    return VX_OK;
}

vx_result vx_conv_mesh(const vx_conv_mesh_desc* desc_in, const vx_gltf_mesh* mesh, vx_svo_scene* out,
                       vx_conv_stats* stats, vx_error* err) {
    vx_conv_mesh_desc desc = desc_in ? *desc_in : (vx_conv_mesh_desc){0};
    if (!mesh || !out) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "mesh: NULL argument");
    vx_conv_stats st;
    memset(&st, 0, sizeof st);
    double t0 = vx_time_now();
    vx_conv_mesh_grid grid;
    vx_result r = vx_conv_mesh_grid_make(mesh->pos, mesh->tri_count, desc.res, &grid, err);
    if (r) return r;
    vx_svo_scene s;
    vx_svo_scene_init(&s, desc.alloc);
    scene_sink k;
    memset(&k, 0, sizeof k);
    k.desc = &desc;
    k.st = &st;
    pthread_mutex_init(&k.lock, NULL);
    r = vx__mesh_voxelize(&desc, mesh, &grid, vx__mesh_attrs(&desc, mesh), scene_add, &k, err);
    if (!r) r = sink_assemble(&k, &s, err);
    sink_free(&k);
    if (r) {
        vx_svo_scene_free(&s);
        return r;
    }
    memset(s.world_from_grid, 0, sizeof s.world_from_grid);
    for (int a = 0; a < 3; a++) {
        s.world_from_grid[a * 4 + a] = grid.h;
        s.world_from_grid[a * 4 + 3] = grid.min[a];
    }
    vx_svo_scene_update_bounds(&s);
    st.models = s.model_count;
    st.instances = s.instance_count;
    st.seconds_voxelize = vx_time_now() - t0 - st.seconds_build;
    st.peak_bytes = vx_peak_rss();
    if (stats) {
        st.seconds_read = stats->seconds_read;
        *stats = st;
    }
    *out = s;
    return VX_OK;
}

vx_result vx_conv_mesh_file(const vx_conv_mesh_desc* desc_in, const char* path, vx_svo_scene* out,
                            vx_conv_stats* stats, vx_error* err) {
    vx_conv_mesh_desc desc = desc_in ? *desc_in : (vx_conv_mesh_desc){0};
    if (!path || !out) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "mesh: NULL argument");
    vx_gltf_read_desc rd;
    memset(&rd, 0, sizeof rd);
    rd.alloc = desc.alloc;
    rd.logger = desc.logger;
    rd.scene_set = desc.scene_set;
    rd.scene = desc.scene;
    rd.no_images = desc.no_color;
    double t0 = vx_time_now();
    vx_gltf_mesh m;
    vx_result r = vx_gltf_read_file(&rd, path, &m, err);
    if (r) return r;
    vx_conv_stats st;
    memset(&st, 0, sizeof st);
    st.seconds_read = vx_time_now() - t0;
    r = vx_conv_mesh(&desc, &m, out, &st, err);
    vx_gltf_mesh_free(&m);
    if (r == VX_OK && stats) *stats = st;
    return r;
}
