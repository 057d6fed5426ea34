/* tools/svo_info/glb.c - svo_info --to-glb (see glb.h): decode each model,
 * greedy-mesh its surface (formats/voxmesh.h), write with formats/glb.h. */
#include "tools/svo_info/glb.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "formats/glb.h"
#include "formats/voxmesh.h"
#include "tools/svo_info/cells.h"

typedef struct mesh_data {
    float* pos;
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

vx_result svo_info_to_glb(const vx_write_desc* desc, const vx_svo_scene* s, bool all, const char* path,
                          svo_glb_stats* stats, vx_error* err) {
    const vx_allocator* A = desc ? desc->alloc : NULL;
    double lind[256];
    svo_srgb_to_linear(lind);
    uint16_t lin[256]; /* sRGB byte -> linear, 65535 = 1 */
    for (int i = 0; i < 256; i++) lin[i] = (uint16_t)lround(65535.0 * lind[i]);
    svo_glb_stats st = {0};
    vx_result r = VX_OK;
    mesh_data* md = (mesh_data*)vx_calloc(A, s->model_count ? s->model_count : 1, sizeof(mesh_data));
    int32_t* mesh_of = (int32_t*)vx_calloc(A, s->model_count ? s->model_count : 1, sizeof(int32_t));
    vx_glb_mesh* meshes = (vx_glb_mesh*)vx_calloc(A, s->model_count ? s->model_count : 1, sizeof(vx_glb_mesh));
    vx_glb_node* nodes = (vx_glb_node*)vx_calloc(A, s->instance_count ? s->instance_count : 1, sizeof(vx_glb_node));
    char(*names)[80] = vx_calloc(A, s->instance_count ? s->instance_count : 1, 80);
    if (!md || !mesh_of || !meshes || !nodes || !names) {
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
        svo_cells c = {0};
        r = svo_cells_decode(A, s, i, &c, err);
        vx_voxmesh vm = {0};
        if (r == VX_OK) r = vx_voxmesh_build(A, c.xyz, c.rgba, c.n, &vm, err);
        svo_cells_free(&c);
        if (r == VX_OK && vm.quad_count) {
            mesh_data* d = &md[st.meshes];
            r = quads_to_mesh(A, &vm, lin, d, err);
            snprintf(d->name, sizeof d->name, "model %u", i);
            meshes[st.meshes] = (vx_glb_mesh){.name = d->name,
                                              .vertex_count = d->vertices,
                                              .pos = d->pos,
                                              .color = d->color,
                                              .index_count = d->indices,
                                              .index = d->index};
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
    vx_glb_scene gs = {.mesh_count = st.meshes,
                       .meshes = meshes,
                       .node_count = st.nodes,
                       .nodes = nodes,
                       .generator = "voxkit svo_info " VX_VERSION_STRING};
    r = vx_glb_write_file(desc, &gs, path, err);
    if (r == VX_OK && stats) *stats = st;
done:
    if (md)
        for (uint32_t i = 0; i < s->model_count; i++) {
            vx_free(A, md[i].pos);
            vx_free(A, md[i].color);
            vx_free(A, md[i].index);
        }
    vx_free(A, md);
    vx_free(A, mesh_of);
    vx_free(A, meshes);
    vx_free(A, nodes);
    vx_free(A, names);
    return r;
}
