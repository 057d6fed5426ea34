/* convert/export_glb.c - vx_conv_svo_to_glb_file (convert/export.h):
 * decode each model, greedy-mesh its surface (formats/voxmesh.h), write with
 * formats/glb.h.
 *
 * Materials: a cell's material id is vx_svo_attr_material (its
 * VX_ATTR_MATERIAL value, else its palette index). Ids whose MATL record
 * resolves to something other than a plain diffuse (metal, glass, or any
 * type with emission > 0) get a glTF material each; every other cell draws
 * with the default material 0 (white, roughness 1, metallic 0), and a scene
 * with no such id is written exactly as before materials were exported.
 * The mesher keeps the ids apart (a quad covers one id) and each mesh has
 * one primitive per material, its quads sorted by material. Base colour
 * stays white: the vertex colours carry the colour. */
#include "convert/export.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "formats/glb.h"
#include "formats/voxmesh.h"
#include "convert/export_internal.h"

typedef struct mesh_data {
    float* pos;
    vx_glb_primitive* prims; /* .material: table index + 1 (0 default) until the glTF indices are known */
    uint32_t prim_count;
    uint16_t* color;
    uint32_t* index;
    size_t vertices, indices;
    char name[32];
} mesh_data;

static double now(void) {
    struct timespec t;
    timespec_get(&t, TIME_UTC);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* Whether a resolved record gets a glTF material of its own (metal, glass,
 * or any emission); the rest draw with the default. */
static bool exported(const vx_material* m) { return m->type != VX_MATERIAL_DIFFUSE || m->emission > 0; }

/* Sorting quads by material, the mesher's order kept within one (the
 * output must not depend on qsort's handling of equal keys). */
typedef struct quad_ref {
    uint32_t material;
    size_t at;
} quad_ref;
static int quad_ref_cmp(const void* a, const void* b) {
    const quad_ref *p = a, *q = b;
    if (p->material != q->material) return p->material < q->material ? -1 : 1;
    return (p->at > q->at) - (p->at < q->at);
}

/* With materials (quads' material = table index + 1, 0 the default): the
 * quads sorted by material and md->prims one index range per material. */
static vx_result sort_by_material(const vx_allocator* A, vx_voxmesh* vm, mesh_data* md, vx_error* err) {
    size_t nq = vm->quad_count;
    quad_ref* ref = (quad_ref*)vx_calloc(A, nq, sizeof(quad_ref));
    vx_voxmesh_quad* sorted = (vx_voxmesh_quad*)vx_calloc(A, nq, sizeof(vx_voxmesh_quad));
    if (!ref || !sorted) {
        vx_free(A, ref);
        vx_free(A, sorted);
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %zu quads", nq);
    }
    for (size_t q = 0; q < nq; q++) ref[q] = (quad_ref){vm->quads[q].material, q};
    qsort(ref, nq, sizeof *ref, quad_ref_cmp);
    uint32_t n = 0;
    for (size_t q = 0; q < nq; q++) {
        sorted[q] = vm->quads[ref[q].at];
        n += q == 0 || ref[q].material != ref[q - 1].material;
    }
    vx_free(A, ref);
    memcpy(vm->quads, sorted, nq * sizeof *sorted);
    vx_free(A, sorted);
    md->prims = (vx_glb_primitive*)vx_calloc(A, n, sizeof(vx_glb_primitive));
    if (!md->prims) return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %u primitives", n);
    for (size_t q = 0; q < nq; q++) {
        if (q == 0 || vm->quads[q].material != vm->quads[q - 1].material)
            md->prims[md->prim_count++] = (vx_glb_primitive){.index_first = 6 * q, .material = vm->quads[q].material};
        md->prims[md->prim_count - 1].index_count += 6;
    }
    return VX_OK;
}

/* The quads as triangles: 4 corners each, counter-clockwise from outside (no
 * normals: glTF viewers compute flat ones, which these are). */
static vx_result quads_to_mesh(const vx_allocator* A, const vx_voxmesh* vm, const uint16_t lin[256], mesh_data* md,
                               vx_error* err) {
    size_t nq = vm->quad_count;
    md->vertices = 4 * nq;
    md->indices = 6 * nq;
    md->pos = (float*)vx_calloc(A, md->vertices, 3 * sizeof(float));
    md->color = (uint16_t*)vx_calloc(A, md->vertices, 4 * sizeof(uint16_t));
    md->index = (uint32_t*)vx_calloc(A, md->indices, sizeof(uint32_t));
    if (!md->pos || !md->color || !md->index)
        return vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %zu quads", nq);
    for (size_t q = 0; q < nq; q++) {
        const vx_voxmesh_quad* Q = &vm->quads[q];
        uint32_t a = Q->axis, ua = (a + 1) % 3, va = (a + 2) % 3;
        const uint32_t uv[4][2] = {{Q->u0, Q->v0}, {Q->u1, Q->v0}, {Q->u1, Q->v1}, {Q->u0, Q->v1}};
        uint16_t rgba[4] = {lin[Q->rgba & 0xFF], lin[(Q->rgba >> 8) & 0xFF], lin[(Q->rgba >> 16) & 0xFF],
                            (uint16_t)((Q->rgba >> 24) * 257u)};
        for (int k = 0; k < 4; k++) {
            size_t v = 4 * q + (size_t)k;
            md->pos[3 * v + a] = (float)Q->plane;
            md->pos[3 * v + ua] = (float)uv[k][0];
            md->pos[3 * v + va] = (float)uv[k][1];
            memcpy(md->color + 4 * v, rgba, sizeof rgba);
        }
        static const uint32_t front[6] = {0, 1, 2, 0, 2, 3}, back[6] = {0, 2, 1, 0, 3, 2};
        for (int k = 0; k < 6; k++) md->index[6 * q + (size_t)k] = (uint32_t)(4 * q) + (Q->positive ? front : back)[k];
    }
    return VX_OK;
}

vx_result vx_conv_svo_to_glb_file(const vx_conv_export_desc* xd, const vx_svo_scene* s, const char* path,
                                  vx_conv_glb_stats* stats, vx_error* err) {
    if (!s || !path) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "glb export: NULL argument");
    const vx_write_desc* desc = xd ? xd->write : NULL;
    bool all = xd && xd->all;
    const vx_allocator* A = desc ? desc->alloc : NULL;
    double lind[256];
    vx__export_srgb_to_linear(lind);
    uint16_t lin[256]; /* sRGB byte -> linear, 65535 = 1 */
    for (int i = 0; i < 256; i++) lin[i] = (uint16_t)lround(65535.0 * lind[i]);
    vx_conv_glb_stats st = {0};
    vx_svo_material_table tab = {0};
    vx_glb_material* gmat = NULL;
    uint32_t* cell_mat = NULL; /* per cell of the model at hand: table index + 1, 0 default */
    size_t cell_mat_cap = 0;
    double* emit_sum = NULL;   /* per table entry: linear RGB sum and cell count of its cells */
    int32_t* gl_index = NULL;  /* per table entry + 1: glTF material index, -1 unused */
    char(*mat_names)[24] = NULL;
    vx_result r = vx_svo_material_table_make(s, A, &tab, err);
    if (r) return r;
    bool materials = false; /* some table entry is more than a plain diffuse */
    for (uint32_t k = 0; k < tab.count; k++)
        materials |= exported(&tab.mats[k]);
    mesh_data* md = (mesh_data*)vx_calloc(A, s->model_count ? s->model_count : 1, sizeof(mesh_data));
    int32_t* mesh_of = (int32_t*)vx_calloc(A, s->model_count ? s->model_count : 1, sizeof(int32_t));
    vx_glb_mesh* meshes = (vx_glb_mesh*)vx_calloc(A, s->model_count ? s->model_count : 1, sizeof(vx_glb_mesh));
    vx_glb_node* nodes = (vx_glb_node*)vx_calloc(A, s->instance_count ? s->instance_count : 1, sizeof(vx_glb_node));
    char(*names)[80] = vx_calloc(A, s->instance_count ? s->instance_count : 1, 80);
    if (materials) {
        emit_sum = (double*)vx_calloc(A, tab.count, 4 * sizeof(double));
        gl_index = (int32_t*)vx_calloc(A, (size_t)tab.count + 1, sizeof(int32_t));
        gmat = (vx_glb_material*)vx_calloc(A, (size_t)tab.count + 1, sizeof(vx_glb_material));
        mat_names = vx_calloc(A, (size_t)tab.count + 1, sizeof *mat_names);
    }
    if (!md || !mesh_of || !meshes || !nodes || !names || (materials && (!emit_sum || !gl_index || !gmat || !mat_names))) {
        r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory");
        goto done;
    }
    double t0 = now();
    for (uint32_t i = 0; i < s->model_count; i++) mesh_of[i] = -2; /* -2: no node shows it */
    for (uint32_t i = 0; i < s->instance_count; i++)
        if (s->instances[i].model < s->model_count && (all || vx_svo_instance_visible(s, i)))
            mesh_of[s->instances[i].model] = -1;
    for (uint32_t i = 0; i < s->model_count; i++) {
        if (mesh_of[i] == -2) continue; /* a mesh no node uses (glTF validators flag it) */
        vx__export_cells c = {0};
        r = vx__export_cells_decode(A, s, i, &c, err);
        vx_voxmesh vm = {0};
        bool any = false; /* a cell of this model with a non-default material */
        if (r == VX_OK && materials && c.n) {
            if (!vx_grow(A, (void**)&cell_mat, &cell_mat_cap, c.n, sizeof(uint32_t)))
                r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "out of memory for %zu cells", c.n);
            for (size_t k = 0; r == VX_OK && k < c.n; k++) {
                const vx_material* mt =
                    vx_svo_material_table_find(&tab, vx_svo_attr_material(&s->models[i], c.attr[k]));
                uint32_t t = mt && exported(mt)
                                 ? (uint32_t)(mt - tab.mats) + 1
                                 : 0;
                cell_mat[k] = t;
                if (!t) continue;
                any = true;
                /* the mean linear colour of an id's cells: its emission colour
                 * where the record has none (MagicaVoxel: colour x _emit) */
                double* e = emit_sum + 4 * (t - 1);
                for (int ch = 0; ch < 3; ch++) e[ch] += lind[c.rgba[k] >> (8 * ch) & 0xFF];
                e[3] += 1;
            }
        }
        if (r == VX_OK) r = vx_voxmesh_build_material(A, c.xyz, c.rgba, any ? cell_mat : NULL, c.n, &vm, err);
        vx__export_cells_free(&c);
        if (r == VX_OK && vm.quad_count) {
            mesh_data* d = &md[st.meshes];
            if (any) r = sort_by_material(A, &vm, d, err);
            if (r == VX_OK) r = quads_to_mesh(A, &vm, lin, d, err);
            snprintf(d->name, sizeof d->name, "model %u", i);
            meshes[st.meshes] = (vx_glb_mesh){.name = d->name,
                                              .vertex_count = d->vertices,
                                              .pos = d->pos,
                                              .color = d->color,
                                              .index_count = d->indices,
                                              .index = d->index,
                                              .primitive_count = d->prim_count,
                                              .primitives = d->prims};
            mesh_of[i] = (int32_t)st.meshes++;
            st.quads += vm.quad_count;
            st.faces += vm.faces;
        }
        vx_voxmesh_free(&vm);
        if (r) goto done;
    }
    st.seconds_mesh = now() - t0;
    for (uint32_t i = 0; i < s->instance_count; i++) {
        const vx_svo_instance* in = &s->instances[i];
        if (in->model >= s->model_count || !(all || vx_svo_instance_visible(s, i))) continue;
        vx_glb_node* n = &nodes[st.nodes];
        double w[12];
        vx_svo_instance_world(s, in, w);
        /* voxkit's +Z up to glTF's +Y up: (x, y, z) -> (x, z, -y), the inverse
         * of the glTF import's turn (convert/mesh.h) */
        for (int col = 0; col < 4; col++) {
            n->matrix[col * 4 + 0] = w[col];
            n->matrix[col * 4 + 1] = w[8 + col];
            n->matrix[col * 4 + 2] = -w[4 + col];
        }
        n->matrix[15] = 1.0;
        n->mesh = mesh_of[in->model];
        if (in->name[0]) snprintf(names[st.nodes], 80, "%s", in->name);
        else snprintf(names[st.nodes], 80, "instance %u", i);
        n->name = names[st.nodes];
        st.nodes++;
    }
    uint32_t gcount = 0;
    if (materials) {
        /* glTF material 0 is the default; then one per table entry some
         * primitive uses, in id order */
        gmat[gcount++] = (vx_glb_material){
            .name = "voxel", .base_color = {1, 1, 1, 1}, .metallic = 0, .roughness = 1};
        for (uint32_t k = 0; k <= tab.count; k++) gl_index[k] = k ? -1 : 0;
        for (uint32_t m = 0; m < st.meshes; m++)
            for (uint32_t p = 0; p < md[m].prim_count; p++)
                if (md[m].prims[p].material) gl_index[md[m].prims[p].material] = 1;
        for (uint32_t k = 1; k <= tab.count; k++) {
            if (gl_index[k] < 0) continue;
            const vx_material* mt = &tab.mats[k - 1];
            gl_index[k] = (int32_t)gcount;
            vx_glb_material* g = &gmat[gcount++];
            snprintf(mat_names[gcount - 1], sizeof mat_names[0], "material %u", tab.ids[k - 1]);
            *g = (vx_glb_material){
                .name = mat_names[gcount - 1], .base_color = {1, 1, 1, 1}, .roughness = (float)mt->roughness};
            if (mt->type == VX_MATERIAL_METAL) g->metallic = (float)mt->metalness;
            if (mt->type == VX_MATERIAL_GLASS) {
                g->transmission = (float)mt->transmission;
                g->ior = (float)mt->ior;
            }
            if (mt->emission > 0) {
                /* glTF's emission does not multiply the base colour: the
                 * record's emission colour x strength, or where it has none
                 * (MagicaVoxel's rule, the voxel's colour x strength) the mean
                 * linear colour of the id's cells, exact for .vox scenes where
                 * a palette index is one colour and one material */
                const double* ec = mt->emission_color;
                double mean[3], e[3], big = 0;
                const double* sum = emit_sum + 4 * (k - 1);
                for (int ch = 0; ch < 3; ch++) mean[ch] = sum[3] > 0 ? sum[ch] / sum[3] : 1.0;
                bool own = ec[0] > 0 || ec[1] > 0 || ec[2] > 0;
                for (int ch = 0; ch < 3; ch++) {
                    e[ch] = (own ? ec[ch] : mean[ch]) * mt->emission;
                    if (e[ch] > big) big = e[ch];
                }
                /* the factor at most 1, the rest in the strength */
                double scale = big > 1 ? big : 1;
                for (int ch = 0; ch < 3; ch++) g->emissive[ch] = (float)(e[ch] / scale);
                if (big > 1) g->emissive_strength = (float)big;
            }
        }
        for (uint32_t m = 0; m < st.meshes; m++)
            for (uint32_t p = 0; p < md[m].prim_count; p++)
                md[m].prims[p].material = (uint32_t)gl_index[md[m].prims[p].material];
    }
    vx_glb_scene gs = {.mesh_count = st.meshes,
                       .material_count = gcount,
                       .materials = gmat,
                       .meshes = meshes,
                       .node_count = st.nodes,
                       .nodes = nodes,
                       .generator = "voxkit " VX_VERSION_STRING};
    st.materials = gcount;
    r = vx_glb_write_file(desc, &gs, path, err);
    if (r == VX_OK && stats) *stats = st;
done:
    if (md)
        for (uint32_t i = 0; i < s->model_count; i++) {
            vx_free(A, md[i].pos);
            vx_free(A, md[i].color);
            vx_free(A, md[i].index);
            vx_free(A, md[i].prims);
        }
    vx_free(A, cell_mat);
    vx_free(A, emit_sum);
    vx_free(A, gl_index);
    vx_free(A, gmat);
    vx_free(A, mat_names);
    vx_svo_material_table_free(&tab);
    vx_free(A, md);
    vx_free(A, mesh_of);
    vx_free(A, meshes);
    vx_free(A, nodes);
    vx_free(A, names);
    return r;
}
