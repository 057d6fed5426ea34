/* tests/convert/mesh_scene_test.c - mesh -> svo scene: the decoded models,
 * placed by their instances, give exactly the voxelizer's cells and colours
 * (several regions -> several models); grid transform; corpus files. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "convert/mesh.h"
#include "tests/test.h"

typedef struct dec {
    const vx_svo_scene* s;
    const vx_svo_model* m;
    const double* t;
    uint32_t n[3];
    uint32_t* rgba; /* per grid cell, 0 = unset (colours are never 0: alpha 255) */
    size_t count, outside;
} dec;

static bool visit(void* user, uint32_t x, uint32_t y, uint32_t z, uint32_t attr) {
    dec* d = (dec*)user;
    uint32_t g[3] = {x + (uint32_t)d->t[3], y + (uint32_t)d->t[7], z + (uint32_t)d->t[11]};
    if (g[0] >= d->n[0] || g[1] >= d->n[1] || g[2] >= d->n[2]) { d->outside++; return true; }
    d->rgba[g[0] + (size_t)d->n[0] * (g[1] + (size_t)d->n[1] * g[2])] = vx_svo_attr_color(d->s, d->m, attr) | 1u;
    d->count++;
    return true;
}

static void check_same(const vx_gltf_mesh* m, vx_conv_mesh_desc desc, uint32_t want_models_min) {
    vx_svo_scene s;
    vx_error err = {0};
    REQUIRE(vx_conv_mesh(&desc, m, &s, NULL, &err) == VX_OK);
    CHECK(vx_svo_validate_scene(&s, &err) == VX_OK);
    CHECKF(s.model_count >= want_models_min, "%u models", s.model_count);
    uint32_t *xyz = NULL, *rgba = NULL;
    size_t count = 0;
    vx_conv_mesh_grid g;
    REQUIRE(vx_conv_mesh_cells(&desc, m, &g, &xyz, &rgba, &count, &err) == VX_OK);
    CHECK(fabs(s.world_from_grid[0] - g.h) == 0 && s.world_from_grid[3] == g.min[0] && s.world_from_grid[11] == g.min[2]);
    dec d = {&s, NULL, NULL, {g.size[0], g.size[1], g.size[2]}, NULL, 0, 0};
    d.rgba = (uint32_t*)calloc((size_t)g.size[0] * g.size[1] * g.size[2], 4);
    for (uint32_t i = 0; i < s.instance_count; i++) {
        d.m = &s.models[s.instances[i].model];
        d.t = s.instances[i].xform;
        CHECK(vx_svo_decode_model(d.m, visit, &d, NULL) == VX_OK);
    }
    CHECK(d.outside == 0);
    CHECKF(d.count == count, "decoded %zu, voxelizer %zu", d.count, count);
    size_t bad = 0;
    for (size_t i = 0; i < count; i++) {
        uint32_t c = d.rgba[xyz[3 * i] + (size_t)g.size[0] * (xyz[3 * i + 1] + (size_t)g.size[1] * xyz[3 * i + 2])];
        uint32_t want = (rgba ? rgba[i] : 0xFFFFFFFFu) | 1u;
        bad += c != want;
    }
    CHECKF(bad == 0, "%zu cells differ", bad);
    free(d.rgba);
    free(xyz);
    free(rgba);
    vx_svo_scene_free(&s);
}

static void test_regions_match_cells(void) {
    static float pos[9 * 200];
    uint64_t r = 12345;
    for (int i = 0; i < 9 * 200; i++) {
        r = r * 6364136223846793005ull + 1442695040888963407ull;
        pos[i] = (float)((r >> 11) % 100000) / 1000.0f;
    }
    for (int i = 0; i < 200; i++)
        for (int k = 3; k < 9; k++) pos[9 * i + k] = pos[9 * i + k % 3] + (float)((k * 7 + i) % 11) - 5.0f;
    uint32_t mat[200];
    float col[12 * 200];
    for (int i = 0; i < 200; i++) mat[i] = (uint32_t)(i % 2);
    for (int i = 0; i < 12 * 200; i++) col[i] = (float)((i * 37) % 100) / 100.0f;
    vx_gltf_material mats[2] = {{{1, 0.5f, 0.25f, 1}, -1, 0, 0}, {{0.2f, 0.9f, 0.4f, 1}, -1, 0, 0}};
    vx_gltf_mesh m;
    memset(&m, 0, sizeof m);
    m.tri_count = 200;
    m.pos = pos;
    m.material = mat;
    m.material_count = 2;
    m.materials = mats;
    m.color = col;
    check_same(&m, (vx_conv_mesh_desc){.res = 150, .region = 64}, 8);        /* regions in parallel */
    check_same(&m, (vx_conv_mesh_desc){.res = 150, .region = 128, .threads = 2}, 2); /* bricks in parallel */
    check_same(&m, (vx_conv_mesh_desc){.res = 40, .no_color = true}, 1);
}

static void test_files(void) {
    const char* p = vx_test_corpus("gltf/julian_Duck.glb");
    if (!p) SKIP("no corpus");
    vx_svo_scene s;
    vx_conv_stats st;
    vx_error err = {0};
    REQUIRE(vx_conv_mesh_file(&(vx_conv_mesh_desc){.res = 40, .normals = true}, p, &s, &st, &err) == VX_OK);
    CHECK(s.model_count == 1 && s.models[0].attrs == (VX_ATTR_RGBA8 | VX_ATTR_NORMAL));
    CHECK(st.build.voxels == s.models[0].voxel_count && st.build.voxels > 0);
    CHECK(s.bounds_max[0] <= 40 && s.bounds_max[1] <= 40 && s.bounds_max[2] <= 40);
    CHECK(s.bounds_max[0] == 40 || s.bounds_max[1] == 40 || s.bounds_max[2] == 40);
    /* the Duck is yellow: the mean colour has more red and green than blue */
    uint64_t sum[3] = {0, 0, 0};
    for (uint32_t i = 0; i < s.models[0].attr_count; i++)
        for (int c = 0; c < 3; c++) sum[c] += (s.models[0].rgba[i] >> (8 * c)) & 255;
    CHECK(sum[0] > sum[2] && sum[1] > sum[2]);
    vx_svo_scene_free(&s);
    REQUIRE(vx_conv_mesh_file(&(vx_conv_mesh_desc){.res = 24, .solid = true}, p, &s, &st, &err) == VX_OK);
    CHECK(vx_svo_validate_scene(&s, &err) == VX_OK);
    vx_svo_scene_free(&s);
    const char* draco = vx_test_corpus("gltf/aleph_Box.glb");
    if (draco) {
        CHECK(vx_conv_mesh_file(NULL, draco, &s, NULL, &err) == VX_ERR_UNSUPPORTED);
        CHECK(strstr(err.msg, "KHR_draco_mesh_compression") != NULL);
    }
}

int main(void) {
    RUN(test_regions_match_cells);
    RUN(test_files);
    return vx_test_finish();
}
