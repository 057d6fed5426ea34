/* convert/export_cells.c (see export_internal.h) */
#include "convert/export_internal.h"

#include <math.h>
#include <string.h>

typedef struct grow {
    const vx_svo_scene* s;
    const vx_svo_model* m;
    vx__export_cells c;
    size_t cap_xyz, cap_rgba, cap_attr;
    bool nomem;
} grow;

static bool add_cell(void* user, uint32_t x, uint32_t y, uint32_t z, uint32_t attr) {
    grow* g = (grow*)user;
    vx__export_cells* c = &g->c;
    if (!vx_grow(c->alloc, (void**)&c->xyz, &g->cap_xyz, 3 * (c->n + 1), sizeof(uint32_t)) ||
        !vx_grow(c->alloc, (void**)&c->rgba, &g->cap_rgba, c->n + 1, sizeof(uint32_t)) ||
        !vx_grow(c->alloc, (void**)&c->attr, &g->cap_attr, c->n + 1, sizeof(uint32_t))) {
        g->nomem = true;
        return false;
    }
    c->xyz[3 * c->n] = x, c->xyz[3 * c->n + 1] = y, c->xyz[3 * c->n + 2] = z;
    c->attr[c->n] = attr;
    c->rgba[c->n++] = vx_svo_attr_rgba(g->s, g->m, attr);
    return true;
}

vx_result vx__export_cells_decode(const vx_allocator* a, const vx_svo_scene* s, uint32_t m, vx__export_cells* out, vx_error* err) {
    grow g = {.s = s, .m = &s->models[m], .c = {.alloc = a}};
    /* room for every cell up front (vx_svo_read checked voxel_count against
     * the tree), so that the per-cell growth checks never copy */
    uint64_t hint = g.m->voxel_count < ((uint64_t)1 << 31) ? g.m->voxel_count : 0;
    if (hint && (!vx_grow(a, (void**)&g.c.xyz, &g.cap_xyz, 3 * (size_t)hint, sizeof(uint32_t)) ||
                 !vx_grow(a, (void**)&g.c.rgba, &g.cap_rgba, (size_t)hint, sizeof(uint32_t)) ||
                 !vx_grow(a, (void**)&g.c.attr, &g.cap_attr, (size_t)hint, sizeof(uint32_t)))) {
        vx__export_cells_free(&g.c);
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "model %u: out of memory for its %llu voxels", m,
                       (unsigned long long)hint);
    }
    vx_result r = vx_svo_decode_model(g.m, add_cell, &g, err);
    if (g.nomem) r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "model %u: out of memory for its voxels", m);
    if (r != VX_OK) {
        vx__export_cells_free(&g.c);
        return r;
    }
    *out = g.c;
    return VX_OK;
}

void vx__export_cells_free(vx__export_cells* c) {
    vx_free(c->alloc, c->xyz);
    vx_free(c->alloc, c->rgba);
    vx_free(c->alloc, c->attr);
    memset(c, 0, sizeof *c);
}

void vx__export_srgb_to_linear(double lin[256]) {
    for (int i = 0; i < 256; i++) {
        double c = i / 255.0;
        lin[i] = c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4);
    }
}
