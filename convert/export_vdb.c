/* convert/export_vdb.c - vx_conv_svo_to_vdb_file (convert/export.h): the
 * scene's cells as OpenVDB grids, written through the OpenVDB shim
 * (formats/vdb.h). */
#include "convert/export.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "formats/vdb.h"
#include "convert/export_internal.h"

/* A density and a colour grid's voxels. */
typedef struct pair {
    int32_t* ijk;
    float* density;
    float* color;
    size_t n, cap_ijk, cap_d, cap_c;
    const vx_allocator* alloc;
} pair;

static void pair_free(pair* p) {
    vx_free(p->alloc, p->ijk);
    vx_free(p->alloc, p->density);
    vx_free(p->alloc, p->color);
    memset(p, 0, sizeof *p);
}

/* index_to_world for a map w of cells [v, v+1]: voxel ijk is centred on ijk. */
static void centred(const double w[12], double out[12]) {
    memcpy(out, w, 12 * sizeof(double));
    for (int r = 0; r < 3; r++) out[r * 4 + 3] += 0.5 * (w[r * 4] + w[r * 4 + 1] + w[r * 4 + 2]);
}

static bool has_colors(const vx_svo_model* m) { return (m->attrs & (VX_ATTR_PALETTE | VX_ATTR_RGBA8)) != 0; }

/* Appends model m's cells mapped by x (NULL: model cells) to p. */
static vx_result add_cells(const vx_svo_scene* s, uint32_t m, const vx__export_cells* c, const double* x, const double lin[256],
                           pair* p, vx_error* err) {
    const vx_svo_model* md = &s->models[m];
    if (!vx_grow(p->alloc, (void**)&p->ijk, &p->cap_ijk, 3 * (p->n + c->n), sizeof(int32_t)) ||
        !vx_grow(p->alloc, (void**)&p->density, &p->cap_d, p->n + c->n, sizeof(float)) ||
        !vx_grow(p->alloc, (void**)&p->color, &p->cap_c, 3 * (p->n + c->n), sizeof(float)))
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %zu voxels", p->n + c->n);
    for (size_t i = 0; i < c->n; i++, p->n++) {
        const uint32_t* v = c->xyz + 3 * i;
        for (int r = 0; r < 3; r++) {
            double g = x ? floor(x[r * 4] * (v[0] + 0.5) + x[r * 4 + 1] * (v[1] + 0.5) + x[r * 4 + 2] * (v[2] + 0.5) +
                                 x[r * 4 + 3])
                         : (double)v[r];
            if (!(g >= INT32_MIN && g <= INT32_MAX))
                return vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "model %u: a cell lies outside OpenVDB's 32-bit index space", m);
            p->ijk[3 * p->n + (size_t)r] = (int32_t)g;
        }
        uint32_t a = c->attr[i];
        p->density[p->n] = (md->attrs & VX_ATTR_DENSITY) && a < md->attr_count ? md->density[a] : 1.0f;
        for (int k = 0; k < 3; k++) p->color[3 * p->n + (size_t)k] = (float)lin[(c->rgba[i] >> (8 * k)) & 0xFF];
    }
    return VX_OK;
}

vx_result vx_conv_svo_to_vdb_file(const vx_conv_export_desc* xd, const vx_svo_scene* s, const char* path,
                                  vx_conv_vdb_stats* stats, vx_error* err) {
    if (!s || !path) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "vdb export: NULL argument");
    const vx_write_desc* desc = xd ? xd->write : NULL;
    bool all = xd && xd->all, models = xd && xd->vdb_models;
    const vx_allocator* A = desc ? desc->alloc : NULL;
    double lin[256];
    vx__export_srgb_to_linear(lin);
    vx_conv_vdb_stats st = {0};
    vx_result r = VX_OK;
    uint32_t mc = s->model_count ? s->model_count : 1, ic = s->instance_count ? s->instance_count : 1;
    vx__export_cells* cells = (vx__export_cells*)vx_calloc(A, mc, sizeof(vx__export_cells));
    bool* decoded = (bool*)vx_calloc(A, mc, sizeof(bool));
    int32_t* first = (int32_t*)vx_calloc(A, mc, sizeof(int32_t)); /* grid index of a model's density grid */
    pair* pairs = (pair*)vx_calloc(A, models ? mc : 1, sizeof(pair));
    vx_vdb_write_grid* grids = (vx_vdb_write_grid*)vx_calloc(A, 2 * (size_t)ic + 2, sizeof(vx_vdb_write_grid));
    char(*names)[2][96] = vx_calloc(A, ic, sizeof *names);
    if (!cells || !decoded || !first || !pairs || !grids || !names) {
        r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory");
        goto done;
    }
    for (uint32_t m = 0; m < (models ? mc : 1); m++) pairs[m].alloc = A;
    for (uint32_t i = 0; i < s->instance_count; i++) {
        const vx_svo_instance* in = &s->instances[i];
        if (in->model >= s->model_count || !(all || vx_svo_instance_visible(s, i))) continue;
        st.colors = st.colors || has_colors(&s->models[in->model]);
    }
    uint32_t g = 0;
    for (uint32_t i = 0; i < s->instance_count; i++) {
        const vx_svo_instance* in = &s->instances[i];
        uint32_t m = in->model;
        if (m >= s->model_count || !(all || vx_svo_instance_visible(s, i)) || !s->models[m].voxel_count) continue;
        if (!decoded[m]) {
            if ((r = vx__export_cells_decode(A, s, m, &cells[m], err)) != VX_OK) goto done;
            decoded[m] = true;
            if (models) { /* the model's own voxels, once */
                if ((r = add_cells(s, m, &cells[m], NULL, lin, &pairs[m], err)) != VX_OK) goto done;
                st.voxels += pairs[m].n;
            }
            first[m] = -1;
        }
        if (!models) {
            if ((r = add_cells(s, m, &cells[m], in->xform, lin, &pairs[0], err)) != VX_OK) goto done;
            continue;
        }
        double w[12];
        vx_svo_instance_world(s, in, w);
        char base[80];
        if (in->name[0]) snprintf(base, sizeof base, "%s", in->name);
        else snprintf(base, sizeof base, "instance %u", i);
        snprintf(names[i][0], sizeof names[i][0], "%s/density", base);
        snprintf(names[i][1], sizeof names[i][1], "%s/color", base);
        for (int k = 0; k < (st.colors ? 2 : 1); k++) {
            vx_vdb_write_grid* G = &grids[g];
            *G = (vx_vdb_write_grid){.name = names[i][k],
                                     .value_type = k ? VX_VDB_TYPE_VEC3F : VX_VDB_TYPE_FLOAT,
                                     .grid_class = k ? VX_VDB_CLASS_UNKNOWN : VX_VDB_CLASS_FOG_VOLUME,
                                     .share = first[m] < 0 ? -1 : first[m] + k,
                                     .count = pairs[m].n,
                                     .ijk = pairs[m].ijk,
                                     .value = k ? pairs[m].color : pairs[m].density};
            centred(w, G->index_to_world);
            g++;
        }
        if (first[m] < 0) first[m] = (int32_t)(g - (st.colors ? 2 : 1));
    }
    if (!models) {
        static const char* const flat[2] = {"density", "color"};
        for (int k = 0; k < (st.colors ? 2 : 1); k++) {
            grids[g] = (vx_vdb_write_grid){.name = flat[k],
                                           .value_type = k ? VX_VDB_TYPE_VEC3F : VX_VDB_TYPE_FLOAT,
                                           .grid_class = k ? VX_VDB_CLASS_UNKNOWN : VX_VDB_CLASS_FOG_VOLUME,
                                           .share = -1,
                                           .count = pairs[0].n,
                                           .ijk = pairs[0].ijk,
                                           .value = k ? pairs[0].color : pairs[0].density};
            centred(s->world_from_grid, grids[g].index_to_world);
            g++;
        }
        st.voxels = pairs[0].n;
    }
    st.grids = g;
    r = vx_vdb_write_file(desc, grids, g, path, err);
    if (r == VX_OK && stats) *stats = st;
done:
    for (uint32_t m = 0; cells && m < s->model_count; m++) vx__export_cells_free(&cells[m]);
    for (uint32_t m = 0; pairs && m < (models ? s->model_count : 1); m++) pair_free(&pairs[m]);
    vx_free(A, cells);
    vx_free(A, decoded);
    vx_free(A, first);
    vx_free(A, pairs);
    vx_free(A, grids);
    vx_free(A, names);
    return r;
}
