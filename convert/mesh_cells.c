/* convert/mesh_cells.c - the voxelizer as a flat cell list (tests, small grids). */
#include <pthread.h>
#include <string.h>

#include "convert/mesh_internal.h"

/* ---- flat cell list ------------------------------------------------------------- */

typedef struct cells_sink {
    const vx_allocator* alloc;
    uint32_t* xyz;
    uint32_t* rgba;
    size_t count, cap, rcap;
    bool want_rgba;
    pthread_mutex_t lock;
} cells_sink;

static vx_result cells_add_locked(cells_sink* s, const vx__mesh_region* r, vx_error* err) {
    size_t need, need3;
    if (!vx_add_size(s->count, r->count, &need) || !vx_mul_size(need, 3, &need3) ||
        !vx_grow(s->alloc, (void**)&s->xyz, &s->cap, need3, 4) ||
        (s->want_rgba && r->rgba && !vx_grow(s->alloc, (void**)&s->rgba, &s->rcap, need, 4)))
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "%zu cells", need);
    for (size_t i = 0; i < r->count; i++) {
        uint32_t x, y, z;
        vx_svo_demorton(r->keys[i], &x, &y, &z);
        uint32_t* o = s->xyz + 3 * (s->count + i);
        o[0] = r->origin[0] + x;
        o[1] = r->origin[1] + y;
        o[2] = r->origin[2] + z;
        if (s->want_rgba && r->rgba) s->rgba[s->count + i] = r->rgba[i];
    }
    s->count = need;
    return VX_OK;
}

static vx_result cells_add(void* user, const vx__mesh_region* r, vx_error* err) {
    cells_sink* s = (cells_sink*)user;
    pthread_mutex_lock(&s->lock);
    vx_result res = cells_add_locked(s, r, err);
    pthread_mutex_unlock(&s->lock);
    return res;
}

vx_result vx_conv_mesh_cells(const vx_conv_mesh_desc* desc_in, const vx_gltf_mesh* mesh, vx_conv_mesh_grid* out_grid,
                             uint32_t** out_xyz, uint32_t** out_rgba, size_t* out_count, vx_error* err) {
    vx_conv_mesh_desc desc = desc_in ? *desc_in : (vx_conv_mesh_desc){0};
    if (!mesh || !out_xyz || !out_count)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "mesh cells: NULL argument");
    vx_conv_mesh_grid grid;
    vx_result r = vx_conv_mesh_grid_make(mesh->pos, mesh->tri_count, desc.res, &grid, err);
    if (r) return r;
    uint32_t attrs = vx__mesh_attrs(&desc, mesh) & (out_rgba ? VX_ATTR_RGBA8 : 0u);
    cells_sink s = {desc.alloc, NULL, NULL, 0, 0, 0, out_rgba != NULL, PTHREAD_MUTEX_INITIALIZER};
    r = desc.backend ? desc.backend->voxelize(desc.backend->self, &desc, mesh, &grid, attrs, 0, 1, false, cells_add, &s, err)
                     : vx__mesh_voxelize(&desc, mesh, &grid, attrs, 0, 1, cells_add, &s, err);
    pthread_mutex_destroy(&s.lock);
    if (r) {
        vx_free(desc.alloc, s.xyz);
        vx_free(desc.alloc, s.rgba);
        return r;
    }
    if (out_grid) *out_grid = grid;
    *out_xyz = s.xyz;
    *out_count = s.count;
    if (out_rgba) *out_rgba = s.rgba;
    else vx_free(desc.alloc, s.rgba);
    return VX_OK;
}

