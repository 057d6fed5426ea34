/* tests/convert/mesh_scene_test.c - mesh -> svo scene: the decoded models,
 * placed by their instances, give exactly the voxelizer's cells and colours
 * (several regions -> several models); grid transform; corpus files. */
#define _POSIX_C_SOURCE 200809L /* mkdtemp */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "convert/mesh.h"
#include "tests/convert/mesh_tex_gltf.h"
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
    vx_gltf_material mats[2] = {{.base_color = {1, 0.5f, 0.25f, 1}, .image = -1, .roughness = 1, .ior = 1.5f},
                                {.base_color = {0.2f, 0.9f, 0.4f, 1}, .image = -1, .roughness = 1, .ior = 1.5f}};
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

/* ---- lights and materials from a glTF file written here ------------------------------- */

static void b64(const uint8_t* d, size_t n, char* out) { texg_b64(d, n, out); }

/* Four triangles side by side (triangle i covers x in [2i, 2i+1], y in
 * [0, 1], z = 0) with materials 0 metal, 1 glass, 2 emissive, 3 diffuse
 * (per `mats`), and the nodes and lights in `nodes_lights`. */
static char* light_gltf(const char* mats, const char* nodes, const char* lights) {
    float pos[36];
    for (int i = 0; i < 4; i++) {
        float v[9] = {2.f * i, 0, 0, 2.f * i + 1, 0, 0, 2.f * i, 1, 0};
        memcpy(pos + 9 * i, v, sizeof v);
    }
    char data[256];
    b64((const uint8_t*)pos, sizeof pos, data);
    size_t cap = 8192;
    char* j = (char*)malloc(cap);
    int n = snprintf(j, cap,
                     "{\"asset\":{\"version\":\"2.0\"},\"extensionsUsed\":[\"KHR_lights_punctual\"],\"scene\":0,"
                     "\"scenes\":[{\"nodes\":[0,3,4]}],\"nodes\":%s,"
                     "\"extensions\":{\"KHR_lights_punctual\":{\"lights\":%s}},"
                     "\"meshes\":[{\"primitives\":[",
                     nodes, lights);
    for (int i = 0; i < 4; i++)
        n += snprintf(j + n, cap - (size_t)n, "%s{\"attributes\":{\"POSITION\":%d},\"material\":%d}", i ? "," : "", i, i);
    n += snprintf(j + n, cap - (size_t)n, "]}],\"materials\":%s,\"buffers\":[{\"byteLength\":144,"
                  "\"uri\":\"data:application/octet-stream;base64,%s\"}],\"bufferViews\":[", mats, data);
    for (int i = 0; i < 4; i++)
        n += snprintf(j + n, cap - (size_t)n, "%s{\"buffer\":0,\"byteOffset\":%d,\"byteLength\":36}", i ? "," : "", 36 * i);
    n += snprintf(j + n, cap - (size_t)n, "],\"accessors\":[");
    for (int i = 0; i < 4; i++)
        n += snprintf(j + n, cap - (size_t)n,
                      "%s{\"bufferView\":%d,\"componentType\":5126,\"count\":3,\"type\":\"VEC3\",\"min\":[%d,0,0],"
                      "\"max\":[%d,1,0]}",
                      i ? "," : "", i, 2 * i, 2 * i + 1);
    snprintf(j + n, cap - (size_t)n, "]}");
    return j;
}

static const char* kMats =
    "[{\"pbrMetallicRoughness\":{\"metallicFactor\":1,\"roughnessFactor\":0.25}},"
    "{\"pbrMetallicRoughness\":{\"metallicFactor\":0,\"roughnessFactor\":0.5},"
    "\"extensions\":{\"KHR_materials_transmission\":{\"transmissionFactor\":0.75},\"KHR_materials_ior\":{\"ior\":1.25}}},"
    "{\"pbrMetallicRoughness\":{\"metallicFactor\":0},\"emissiveFactor\":[1,0.5,0],"
    "\"extensions\":{\"KHR_materials_emissive_strength\":{\"emissiveStrength\":4}}},"
    "{\"pbrMetallicRoughness\":{\"metallicFactor\":0}}]";
static const char* kMatsDiffuse =
    "[{\"pbrMetallicRoughness\":{\"metallicFactor\":0}},{\"pbrMetallicRoughness\":{\"metallicFactor\":0}},"
    "{\"pbrMetallicRoughness\":{\"metallicFactor\":0}},{\"pbrMetallicRoughness\":{\"metallicFactor\":0}}]";
/* node 0: the mesh, scaled by 2 and moved by (10, 0, 0), with child 1 (the
 * point light at (1, 2, 3): world (12, 4, 6)); node 3: the spot, turned 90
 * degrees about +x (its -z axis becomes +y); node 4: the sun, unturned
 * (shining along -z, so towards the light is +z); node 2 is not in the scene. */
static const char* kNodes =
    "[{\"mesh\":0,\"scale\":[2,2,2],\"translation\":[10,0,0],\"children\":[1]},"
    "{\"translation\":[1,2,3],\"extensions\":{\"KHR_lights_punctual\":{\"light\":0}}},"
    "{\"extensions\":{\"KHR_lights_punctual\":{\"light\":2}}},"
    "{\"translation\":[0,0,5],\"rotation\":[0.70710678118654752,0,0,0.70710678118654752],"
    "\"extensions\":{\"KHR_lights_punctual\":{\"light\":1}}},"
    "{\"extensions\":{\"KHR_lights_punctual\":{\"light\":2}}}]";
static const char* kLights =
    "[{\"type\":\"point\",\"name\":\"bulb\",\"color\":[1,0.5,0.25],\"intensity\":100,\"range\":10},"
    "{\"type\":\"spot\",\"intensity\":20,\"spot\":{\"innerConeAngle\":0.2,\"outerConeAngle\":0.5}},"
    "{\"type\":\"directional\",\"intensity\":3}]";

static bool near(double a, double b, double tol) { return fabs(a - b) <= tol; }

/* Decoded cells: triangle i covers world x in [10 + 4i, 12 + 4i] (scale 2,
 * moved by 10), so a cell's centre names its triangle and the material id
 * it must carry (i + 1 for the three special materials, 0 for diffuse). */
typedef struct mat_dec {
    const vx_svo_model* m;
    double w[12];
    size_t cells, wrong;
} mat_dec;
static bool mat_visit(void* user, uint32_t x, uint32_t y, uint32_t z, uint32_t attr) {
    mat_dec* d = (mat_dec*)user;
    double cx = d->w[0] * (x + 0.5) + d->w[1] * (y + 0.5) + d->w[2] * (z + 0.5) + d->w[3];
    int i = (int)floor((cx - 10) / 4);
    uint16_t want = i >= 0 && i < 3 ? (uint16_t)(i + 1) : 0;
    d->cells++;
    d->wrong += i < 0 || i > 3 || d->m->material[attr] != want;
    return true;
}

static void test_gltf_lights(void) {
    char* j = light_gltf(kMats, kNodes, kLights);
    vx_gltf_mesh m;
    vx_error err = {0};
    vx_result r = vx_gltf_read(NULL, j, strlen(j), NULL, &m, &err);
    if (r) fprintf(stderr, "%s\n", err.msg);
    REQUIRE(r == VX_OK);
    vx_svo_scene s;
    r = vx_conv_mesh(&(vx_conv_mesh_desc){.res = 28}, &m, &s, NULL, &err);
    if (r) fprintf(stderr, "%s\n", err.msg);
    REQUIRE(r == VX_OK);
    REQUIRE(s.light_count == 3);
    const vx_light* L = s.lights;
    CHECK(L[0].type == VX_LIGHT_POINT && L[0].position[0] == 12 && L[0].position[1] == 4 && L[0].position[2] == 6);
    CHECK(L[0].intensity == 100 && L[0].range == 10 && L[0].color[1] == 0.5 && L[0].color[2] == 0.25);
    CHECK(L[1].type == VX_LIGHT_SPOT && near(L[1].position[2], 5, 0) && near(L[1].direction[1], 1, 1e-12) &&
          near(L[1].direction[2], 0, 1e-12) && L[1].inner_cone == 0.2 && L[1].outer_cone == 0.5 && L[1].intensity == 20);
    CHECK(L[2].type == VX_LIGHT_DIRECTIONAL && L[2].direction[2] == 1 && L[2].intensity == 3 && L[2].color[0] == 1);
    /* the voxels sit in the same world frame: the mesh spans x in [10, 24] */
    double lo[3], hi[3];
    vx_svo_scene_world_bounds(&s, lo, hi);
    CHECK(near(lo[0], 10, 1e-9) && near(hi[0], 24, 1e-9));
    /* materials: records 1..3 for the special ones, none for the diffuse one */
    REQUIRE(s.material_count == 3);
    vx_material mt = vx_svo_scene_material(&s, 1), gl = vx_svo_scene_material(&s, 2), em = vx_svo_scene_material(&s, 3);
    CHECK(mt.type == VX_MATERIAL_METAL && mt.metalness == 1 && near(mt.roughness, 0.25, 1e-6));
    CHECK(gl.type == VX_MATERIAL_GLASS && near(gl.transmission, 0.75, 1e-6) && near(gl.ior, 1.25, 1e-6) &&
          near(gl.roughness, 0.5, 1e-6));
    CHECK(em.type == VX_MATERIAL_EMIT && near(em.emission, 4, 1e-6));
    /* glTF's emissive colour [1, 0.5, 0] x 4 is the emitted light whatever the base colour (_emit_color) */
    CHECK(em.emission_color[0] == 1 && em.emission_color[1] == 0.5 && em.emission_color[2] == 0);
    CHECK(mt.emission_color[0] == 0 && gl.emission_color[0] == 0); /* not emissive: no colour */
    CHECK(vx_svo_scene_material(&s, 4).type == VX_MATERIAL_DIFFUSE);
    /* every cell carries the id of its triangle's material (0 for the diffuse one) */
    size_t cells = 0, wrong = 0;
    for (uint32_t mi = 0; mi < s.model_count; mi++) {
        const vx_svo_model* md = &s.models[mi];
        CHECK(md->attrs & VX_ATTR_MATERIAL);
        for (uint32_t a = 0; a < md->attr_count; a++) wrong += md->material[a] > 3;
    }
    for (uint32_t ii = 0; ii < s.instance_count; ii++) {
        mat_dec d = {&s.models[s.instances[ii].model], {0}, 0, 0};
        vx_svo_instance_world(&s, &s.instances[ii], d.w);
        CHECK(vx_svo_decode_model(d.m, mat_visit, &d, &err) == VX_OK);
        cells += d.cells, wrong += d.wrong;
    }
    CHECK(cells > 0);
    CHECK(wrong == 0);
    /* the same scene with diffuse materials only: no channel, no records */
    vx_svo_scene_free(&s);
    vx_gltf_mesh_free(&m);
    free(j);
    j = light_gltf(kMatsDiffuse, kNodes, kLights);
    REQUIRE(vx_gltf_read(NULL, j, strlen(j), NULL, &m, &err) == VX_OK);
    REQUIRE(vx_conv_mesh(&(vx_conv_mesh_desc){.res = 28}, &m, &s, NULL, &err) == VX_OK);
    CHECK(s.material_count == 0 && s.light_count == 3);
    for (uint32_t mi = 0; mi < s.model_count; mi++) CHECK(!(s.models[mi].attrs & VX_ATTR_MATERIAL));
    vx_svo_scene_free(&s);
    vx_gltf_mesh_free(&m);
    free(j);
}

/* Bad lights are errors naming the light. */
static void test_gltf_bad_lights(void) {
    struct {
        const char* lights;
        const char* nodes;
        const char* want;
    } cases[] = {
        {"[{\"type\":\"point\",\"name\":\"bulb\",\"intensity\":-5},{\"type\":\"spot\",\"spot\":{}},{\"type\":\"directional\"}]", NULL,
         "light 0 ('bulb') on node 1: negative"},
        {"[{\"type\":\"point\"},{\"type\":\"spot\",\"spot\":{}},{\"type\":\"area\"}]", NULL, "light 2 on node 4: unknown type 'area'"},
        {"[{\"type\":\"point\"},{\"type\":\"spot\",\"spot\":{\"innerConeAngle\":0.6,\"outerConeAngle\":0.5}},"
         "{\"type\":\"directional\"}]",
         NULL, "light 1 on node 3: spot cones"},
        {"[{\"type\":\"point\",\"color\":[1,-1,1]},{\"type\":\"spot\",\"spot\":{}},{\"type\":\"directional\"}]", NULL, "light 0 on node 1: colour"},
        /* JSON has no NaN or infinity: a node chain whose world matrix overflows */
        {NULL,
         "[{\"mesh\":0},{\"translation\":[1e300,0,0],\"extensions\":{\"KHR_lights_punctual\":{\"light\":0}}},"
         "{},{\"scale\":[1e300,1e300,1e300],\"children\":[1]},{}]",
         "light 0 ('bulb') on node 1: the node puts it at a non-finite position"},
        {NULL,
         "[{\"mesh\":0,\"children\":[1]},{\"scale\":[1,1,0],\"extensions\":{\"KHR_lights_punctual\":{\"light\":2}}},"
         "{},{},{}]",
         "light 2 on node 1: the node's transform leaves it no direction"},
        {NULL, "[{\"mesh\":0},{},{},{\"extensions\":{\"KHR_lights_punctual\":{\"light\":7}}},{}]", "node 3"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        char* j = light_gltf(kMats, cases[i].nodes ? cases[i].nodes : kNodes, cases[i].lights ? cases[i].lights : kLights);
        vx_gltf_mesh m;
        vx_error err = {0};
        vx_result r = vx_gltf_read(NULL, j, strlen(j), NULL, &m, &err);
        CHECKF(r == VX_ERR_BAD_FORMAT && strstr(err.msg, cases[i].want), "case %zu: %s", i, r ? err.msg : "accepted");
        if (r == VX_OK) vx_gltf_mesh_free(&m);
        free(j);
    }
}

/* ---- per-cell metallic-roughness and emission (convert/mesh.h, "Materials") ---------- */

static double ref_srgb(double c) { return c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4); }
static int64_t ref_wrap(int64_t x, int64_t n, bool clamp) { return clamp ? (x < 0 ? 0 : x >= n ? n - 1 : x) : ((x % n) + n) % n; }
/* Bilinear sample of channel c of a TEXG_N^2 RGBA image at (u, v) (glTF: texel centres at (i + 0.5) / N). */
static double ref_sample(const uint8_t* im, double u, double v, int c, bool clamp, bool srgb) {
    double x = u * TEXG_N - 0.5, y = v * TEXG_N - 0.5, fx = floor(x), fy = floor(y), ax = x - fx, ay = y - fy, s = 0;
    for (int k = 0; k < 4; k++) {
        int64_t xi = ref_wrap((int64_t)fx + (k & 1), TEXG_N, clamp), yi = ref_wrap((int64_t)fy + (k >> 1), TEXG_N, clamp);
        double t = im[4 * (yi * TEXG_N + xi) + c] / 255.0;
        s += ((k & 1) ? ax : 1 - ax) * ((k >> 1) ? ay : 1 - ay) * (srgb ? ref_srgb(t) : t);
    }
    return s;
}
/* A record's key as a number, 0 when absent. */
static double mat_key(const vx_svo_scene* s, uint32_t id, const char* key) {
    for (uint32_t i = 0; i < s->material_count; i++)
        if (s->materials[i].id == id) {
            const char* v = vx_svo_material_get(&s->materials[i], key);
            return v ? strtod(v, NULL) : 0;
        }
    return -1; /* no record */
}
/* Level of q in [0, 1] over 6 levels; *tie when q * 5 is too near a half for float sums to agree. */
static int ref_level(double q, bool* tie) {
    double x = fmin(fmax(q, 0), 1) * 5;
    if (fabs(x - floor(x) - 0.5) < 1e-3) *tie = true;
    return (int)floor(x + 0.5);
}

typedef struct cell_ids {
    uint16_t id[16 * 16];
    bool set[16 * 16];
} cell_ids;
static bool ids_visit(void* user, uint32_t x, uint32_t y, uint32_t z, uint32_t attr) {
    void** u = (void**)user;
    cell_ids* c = (cell_ids*)u[0];
    const vx_svo_model* m = (const vx_svo_model*)u[1];
    if (x < 16 && y < 16 && z == 0) c->id[y * 16 + x] = (m->attrs & VX_ATTR_MATERIAL) ? m->material[attr] : 0, c->set[y * 16 + x] = true;
    return true;
}

/* The generated quad (tests/convert/mesh_tex_gltf.h): every cell's record
 * against a brute-force expectation: the texels sampled bilinearly at the
 * centroids of the cell's pieces (the whole cell off the diagonal, its two
 * halves on it), averaged by area, quantized to 6 levels of the factor,
 * each emission channel on its own (the record's _emit its largest,
 * _emit_color the channels over it). */
static void textured_materials(const char* mat, const char* label) {
    uint8_t mr[4 * TEXG_N * TEXG_N], em[4 * TEXG_N * TEXG_N];
    texg_split(mr, em);
    vx_gltf_mesh m;
    vx_error err = {0};
    vx_result r = texg_read(mat, mr, em, &m, &err);
    CHECKF(r == VX_OK, "%s", err.msg);
    if (r) return;
    vx_svo_scene s;
    r = vx_conv_mesh(&(vx_conv_mesh_desc){.res = 16}, &m, &s, NULL, &err);
    CHECKF(r == VX_OK, "%s", err.msg);
    if (r) {
        vx_gltf_mesh_free(&m);
        return;
    }
    REQUIRE(s.model_count == 1 && s.instances[0].xform[3] == 0 && s.instances[0].xform[7] == 0);
    cell_ids c;
    memset(&c, 0, sizeof c);
    void* u[2] = {&c, &s.models[0]};
    CHECK(vx_svo_decode_model(&s.models[0], ids_visit, u, &err) == VX_OK);
    size_t metal = 0, lit = 0, hued = 0, diffuse = 0, ties = 0, wrong = 0, levels_seen = 0;
    static bool seen[6 * 6 * 216];
    memset(seen, 0, sizeof seen);
    for (int y = 0; y < 16; y++)
        for (int x = 0; x < 16; x++) {
            double cx[2] = {x + 0.5, 0}, cy[2] = {y + 0.5, 0}, w[2] = {1, 0};
            int np = 1;
            if (x == y) np = 2, cx[0] = x + 2.0 / 3, cy[0] = y + 1.0 / 3, cx[1] = x + 1.0 / 3, cy[1] = y + 2.0 / 3, w[0] = w[1] = 0.5;
            double pm = 0, pr = 0, pe[3] = {0, 0, 0};
            for (int k = 0; k < np; k++) {
                double u0 = cx[k] / 16, v0 = cy[k] / 16, u1 = 1 - cx[k] / 16;
                pm += w[k] * 0.8 * ref_sample(mr, u0, v0, 2, true, false);
                pr += w[k] * 0.5 * ref_sample(mr, u0, v0, 1, true, false);
                for (int ch = 0; ch < 3; ch++) pe[ch] += w[k] * 2 * ref_sample(em, u1, v0, ch, false, true);
            }
            bool tie = false;
            int km = ref_level(pm / 0.8, &tie), kr = ref_level(pr / 0.5, &tie), ke[3], kmax = 0;
            for (int ch = 0; ch < 3; ch++) ke[ch] = ref_level(pe[ch] / 2, &tie), kmax = ke[ch] > kmax ? ke[ch] : kmax;
            if (!c.set[y * 16 + x]) {
                wrong++;
                continue;
            }
            if (tie) { ties++; continue; }
            uint16_t id = c.id[y * 16 + x];
            bool ok;
            if (km == 0 && kmax == 0) {
                ok = id == 0;
                diffuse++;
            } else {
                ok = id != 0 && fabs(mat_key(&s, id, "_metal") - 0.8 * km / 5) < 1e-6 &&
                     fabs(mat_key(&s, id, "_rough") - 0.5 * kr / 5) < 1e-6 && fabs(mat_key(&s, id, "_emit") - 2.0 * kmax / 5) < 1e-6;
                /* the emission's own colour: each channel's level over the largest's */
                vx_material mt = vx_svo_scene_material(&s, id);
                for (int ch = 0; ch < 3 && kmax; ch++) ok = ok && fabs(mt.emission_color[ch] - (double)ke[ch] / kmax) < 1e-6;
                metal += km > 0, lit += kmax > 0, hued += kmax > 0 && ke[1] < kmax;
                int k = (km * 6 + kr) * 216 + (ke[0] * 6 + ke[1]) * 6 + ke[2];
                if (!seen[k]) seen[k] = true, levels_seen++;
            }
            if (!ok) {
                if (wrong < 5)
                    fprintf(stderr, "  cell %d %d: id %u (_metal %g _rough %g _emit %g), expected levels %d %d %d %d %d\n", x, y,
                            id, mat_key(&s, id, "_metal"), mat_key(&s, id, "_rough"), mat_key(&s, id, "_emit"), km, kr, ke[0],
                            ke[1], ke[2]);
                wrong++;
            }
        }
    fprintf(stderr,
            "  %s: %zu metal, %zu emissive (%zu not grey), %zu diffuse cells, %zu combinations, %zu records, %zu ties skipped\n",
            label, metal, lit, hued, diffuse, levels_seen, (size_t)s.material_count, ties);
    CHECK(wrong == 0);
    CHECK(metal >= 64 && lit >= 32 && hued >= 16 && diffuse >= 32 && levels_seen >= 4 && ties < 16);
    CHECK(s.material_count == levels_seen); /* one record per combination the cells name */
    vx_svo_scene_free(&s);
    vx_gltf_mesh_free(&m);
}

/* Once as generated, once with the metallic-roughness image as the base
 * colour texture too (the same image, sampler and TEXCOORD_0): the
 * voxelizer then samples metallic-roughness over the colour's bilinear
 * footprint (hit_attr's shared texel_foot) while the emission (TEXCOORD_1)
 * takes its own; the records must be the brute force's either way. */
static void test_textured_materials(void) {
    textured_materials(kTexgSplitMat, "split textures");
    static const char* with_color =
        "{\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":0},\"metallicFactor\":0.8,\"roughnessFactor\":0.5,"
        "\"metallicRoughnessTexture\":{\"index\":0}},\"emissiveFactor\":[1,1,1],"
        "\"emissiveTexture\":{\"index\":1,\"texCoord\":1},"
        "\"extensions\":{\"KHR_materials_emissive_strength\":{\"emissiveStrength\":2}}}";
    textured_materials(with_color, "split textures, metallic-roughness also the base colour");
}

typedef struct hue_cells {
    const vx_svo_scene* s;
    const vx_svo_model* m;
    uint16_t id[16 * 16];
    double rgb[16 * 16][3];
    bool set[16 * 16];
} hue_cells;
static bool hue_visit(void* user, uint32_t x, uint32_t y, uint32_t z, uint32_t attr) {
    hue_cells* c = (hue_cells*)user;
    if (x >= 16 || y >= 16 || z != 0) return true;
    uint32_t col = vx_svo_attr_color(c->s, c->m, attr);
    for (int k = 0; k < 3; k++) c->rgb[y * 16 + x][k] = ((col >> (8 * k)) & 255) / 255.0;
    c->id[y * 16 + x] = (c->m->attrs & VX_ATTR_MATERIAL) ? c->m->material[attr] : 0;
    c->set[y * 16 + x] = true;
    return true;
}

/* An emissive texture's own hue per cell (convert/mesh.h, "Materials"): on
 * a white base colour, texg_hue's quarters under a white factor x 3 emit
 * red (3 0 0), orange (3 0.6 0: G's texel 128 is 0.216 linear, level 1 of
 * 5), blue (0 0 3) and half blue (0 0 0.6), not white (the voxel's colour,
 * MagicaVoxel's rule, which glowed white here before); under the factor
 * (1 0.5 0) x 3 only R and G are sampled (ids 1 + 6 kR + kG: a block of 6^2,
 * where sampling B as well would give 6^3) and nothing emits blue. */
static void test_emissive_hue(void) {
    static const struct {
        const char* mat;
        uint8_t full[3];    /* texg_hue's bottom colour */
        double want[4][3];  /* radiance in the quarters red, orange, full, half */
        int id[4];          /* their ids (0: diffuse) */
        int max_id;         /* base + block - 1 */
    } cases[] = {
        {TEXG_HUE_MAT("1,1,1"), {0, 0, 255}, {{3, 0, 0}, {3, 0.6, 0}, {0, 0, 3}, {0, 0, 0.6}},
         {1 + 5 * 36, 1 + 5 * 36 + 6, 1 + 5, 1 + 1}, 216},
        {TEXG_HUE_MAT("1,0.5,0"), {255, 255, 255}, {{3, 0, 0}, {3, 0.3, 0}, {3, 1.5, 0}, {0.6, 0.3, 0}},
         {1 + 5 * 6, 1 + 5 * 6 + 1, 1 + 5 * 6 + 5, 1 + 6 + 1}, 36},
    };
    for (size_t ci = 0; ci < sizeof cases / sizeof cases[0]; ci++) {
        uint8_t mr[4 * TEXG_N * TEXG_N], em[4 * TEXG_N * TEXG_N];
        memset(mr, 255, sizeof mr);
        texg_hue(cases[ci].full, em);
        vx_gltf_mesh m;
        vx_error err = {0};
        vx_svo_scene s;
        REQUIRE(texg_read(cases[ci].mat, mr, em, &m, &err) == VX_OK);
        vx_result r = vx_conv_mesh(&(vx_conv_mesh_desc){.res = 16}, &m, &s, NULL, &err);
        CHECKF(r == VX_OK, "%s", err.msg);
        if (r) {
            vx_gltf_mesh_free(&m);
            continue;
        }
        REQUIRE(s.model_count == 1 && s.instances[0].xform[3] == 0 && s.instances[0].xform[7] == 0);
        static hue_cells c;
        memset(&c, 0, sizeof c);
        c.s = &s, c.m = &s.models[0];
        CHECK(vx_svo_decode_model(c.m, hue_visit, &c, &err) == VX_OK);
        size_t cells = 0, wrong = 0, above = 0, blue = 0;
        for (int y = 0; y < 16; y++)
            for (int x = 0; x < 16; x++) {
                int i = y * 16 + x;
                if (!c.set[i]) {
                    wrong++;
                    continue;
                }
                above += c.id[i] > cases[ci].max_id;
                vx_material mt = vx_svo_scene_material(&s, c.id[i]);
                double e[3];
                vx_material_emitted(&mt, c.rgb[i], e);
                blue += e[2] > 0;
                bool in_x = (x >= 1 && x <= 6) || (x >= 9 && x <= 14), in_y = (y >= 1 && y <= 6) || (y >= 9 && y <= 14);
                if (!in_x || !in_y) continue; /* footprints across quarters or wrapped */
                int q = (y > 8 ? 2 : 0) + (x < 8 ? 1 : 0);
                const double* want = cases[ci].want[q];
                bool ok = c.id[i] == cases[ci].id[q] && c.rgb[i][0] == 1 && c.rgb[i][1] == 1 && c.rgb[i][2] == 1;
                for (int k = 0; k < 3; k++) ok = ok && fabs(e[k] - want[k]) < 1e-5;
                cells++;
                if (!ok && wrong++ < 5)
                    fprintf(stderr, "  case %zu cell %d %d: id %u emits %g %g %g (colour %g %g %g), expected id %d, %g %g %g\n", ci,
                            x, y, c.id[i], e[0], e[1], e[2], c.rgb[i][0], c.rgb[i][1], c.rgb[i][2], cases[ci].id[q], want[0],
                            want[1], want[2]);
            }
        fprintf(stderr, "  case %zu: %zu cells checked, %u records\n", ci, cells, s.material_count);
        CHECK(cells == 144 && wrong == 0);
        CHECKF(above == 0, "case %zu: %zu cells with ids past the material's block", ci, above);
        if (ci == 1) CHECKF(blue == 0, "%zu cells emit blue under a factor whose blue is 0", blue);
        /* every emitting record states its colour, its largest channel 1 */
        for (uint32_t k = 0; k < s.material_count; k++) {
            vx_material mt = vx_svo_material_resolve(&s.materials[k]);
            if (!(mt.emission > 0)) continue;
            double mx = fmax(mt.emission_color[0], fmax(mt.emission_color[1], mt.emission_color[2]));
            CHECKF(mx == 1, "record %u: emission colour %g %g %g", s.materials[k].id, mt.emission_color[0], mt.emission_color[1],
                   mt.emission_color[2]);
        }
        vx_svo_scene_free(&s);
        vx_gltf_mesh_free(&m);
    }
}

/* A material that samples its metallic-roughness texture but not its
 * emission (emissiveFactor (1 0.5 0.25) x 2, no emissive texture) keeps the
 * ids and records it had before emission was sampled per channel: the
 * records' dictionaries and the cells' ids against those of the converter
 * before that change (commit 8bec8ee), written out here. */
static void test_unsampled_emission_unchanged(void) {
    uint8_t mr[4 * TEXG_N * TEXG_N], em[4 * TEXG_N * TEXG_N];
    texg_split(mr, em);
    static const char* mat =
        "{\"pbrMetallicRoughness\":{\"metallicFactor\":0.8,\"roughnessFactor\":0.5,"
        "\"metallicRoughnessTexture\":{\"index\":0}},\"emissiveFactor\":[1,0.5,0.25],"
        "\"extensions\":{\"KHR_materials_emissive_strength\":{\"emissiveStrength\":2}}}";
    vx_gltf_mesh m;
    vx_error err = {0};
    vx_svo_scene s;
    REQUIRE(texg_read(mat, mr, em, &m, &err) == VX_OK);
    REQUIRE(vx_conv_mesh(&(vx_conv_mesh_desc){.res = 16}, &m, &s, NULL, &err) == VX_OK);
    /* the records as text: "id key=value ...;" in file order */
    char text[4096];
    size_t n = 0;
    for (uint32_t i = 0; i < s.material_count && n < sizeof text; i++) {
        const vx_svo_material* r = &s.materials[i];
        n += (size_t)snprintf(text + n, sizeof text - n, "%u", r->id);
        for (uint32_t o = 0; o < r->dict_size && n < sizeof text;) {
            const char* k = r->dict + o;
            const char* v = k + strlen(k) + 1;
            n += (size_t)snprintf(text + n, sizeof text - n, " %s=%s", k, v);
            o += (uint32_t)(strlen(k) + strlen(v) + 2);
        }
        if (n < sizeof text) n += (size_t)snprintf(text + n, sizeof text - n, ";");
    }
    /* the cells' ids, FNV-1a over the 16 x 16 grid (0 where no cell) */
    cell_ids c;
    memset(&c, 0, sizeof c);
    void* u[2] = {&c, &s.models[0]};
    CHECK(vx_svo_decode_model(&s.models[0], ids_visit, u, &err) == VX_OK);
    uint32_t h = 2166136261u;
    for (int i = 0; i < 16 * 16; i++) h = (h ^ c.id[i]) * 16777619u, h = (h ^ (uint32_t)(c.id[i] >> 8)) * 16777619u;
    static const char* want =
        "6 _type=_emit _rough=0.5 _emit=2 _emit_color=1 0.5 0.25;"
        "11 _type=_metal _metal=0.159999996 _rough=0.400000006 _ior=0.5 _emit=2 _emit_color=1 0.5 0.25;"
        "28 _type=_metal _metal=0.639999986 _rough=0.300000012 _ior=0.5 _emit=2 _emit_color=1 0.5 0.25;"
        "33 _type=_metal _metal=0.800000012 _rough=0.200000003 _ior=0.5 _emit=2 _emit_color=1 0.5 0.25;";
    CHECKF(strcmp(text, want) == 0, "records %s", text);
    CHECKF(h == 0xfd907745u, "ids %08x", h);
    vx_svo_scene_free(&s);
    vx_gltf_mesh_free(&m);
}

/* Uniform textures (every texel the same) give the file of the factors they
 * equal: metallic 0.8 x 1, roughness 0.5 x 0, emission (1 0.5 0.25) x 2 x 1. */
static void test_uniform_textures(void) {
    uint8_t mr[4 * TEXG_N * TEXG_N], em[4 * TEXG_N * TEXG_N];
    for (int i = 0; i < TEXG_N * TEXG_N; i++) {
        mr[4 * i] = 7, mr[4 * i + 1] = 0, mr[4 * i + 2] = 255, mr[4 * i + 3] = 255;
        em[4 * i] = em[4 * i + 1] = em[4 * i + 2] = em[4 * i + 3] = 255;
    }
    static const char* tex =
        "{\"pbrMetallicRoughness\":{\"metallicFactor\":0.8,\"roughnessFactor\":0.5,"
        "\"metallicRoughnessTexture\":{\"index\":0}},\"emissiveFactor\":[1,0.5,0.25],"
        "\"emissiveTexture\":{\"index\":1,\"texCoord\":1},"
        "\"extensions\":{\"KHR_materials_emissive_strength\":{\"emissiveStrength\":2}}}";
    static const char* fac =
        "{\"pbrMetallicRoughness\":{\"metallicFactor\":0.8,\"roughnessFactor\":0},\"emissiveFactor\":[1,0.5,0.25],"
        "\"extensions\":{\"KHR_materials_emissive_strength\":{\"emissiveStrength\":2}}}";
    uint8_t* bytes[2] = {NULL, NULL};
    size_t n[2] = {0, 0};
    for (int k = 0; k < 2; k++) {
        char* j = texg_gltf(k ? fac : tex, mr, em);
        vx_gltf_mesh m;
        vx_error err = {0};
        vx_svo_scene s;
        REQUIRE(vx_gltf_read(NULL, j, strlen(j), NULL, &m, &err) == VX_OK);
        free(j);
        REQUIRE(vx_conv_mesh(&(vx_conv_mesh_desc){.res = 16}, &m, &s, NULL, &err) == VX_OK);
        CHECK(s.material_count == 1 && mat_key(&s, 1, "_metal") > 0.79 && mat_key(&s, 1, "_emit") == 2);
        /* the emission's own colour, glTF's (the factor over its largest channel), not the base colour */
        vx_material mt = vx_svo_scene_material(&s, 1);
        CHECKF(mt.emission == 2 && mt.emission_color[0] == 1 && mt.emission_color[1] == 0.5 && mt.emission_color[2] == 0.25,
               "emission %g colour %g %g %g", mt.emission, mt.emission_color[0], mt.emission_color[1], mt.emission_color[2]);
        CHECK(vx_svo_write(&s, NULL, &bytes[k], &n[k], &err) == VX_OK);
        vx_svo_scene_free(&s);
        vx_gltf_mesh_free(&m);
    }
    CHECKF(n[0] == n[1] && n[0] > 0 && memcmp(bytes[0], bytes[1], n[0]) == 0, "%zu and %zu bytes", n[0], n[1]);
    free(bytes[0]);
    free(bytes[1]);
}

typedef struct helmet_cnt {
    const vx_svo_scene* s;
    const vx_svo_model* m;
    size_t cells, metal, lit;
    double emitted[3]; /* summed over the emissive cells: the record's emission colour x emission */
} helmet_cnt;
static bool helmet_visit(void* user, uint32_t x, uint32_t y, uint32_t z, uint32_t attr) {
    (void)x, (void)y, (void)z;
    helmet_cnt* k = (helmet_cnt*)user;
    uint16_t id = k->m->material[attr];
    k->cells++;
    if (id) {
        k->metal += mat_key(k->s, id, "_metal") > 0;
        k->lit += mat_key(k->s, id, "_emit") > 0;
        vx_material mt = vx_svo_scene_material(k->s, id);
        for (int c = 0; c < 3; c++) k->emitted[c] += mt.emission_color[c] * mt.emission;
    }
    return true;
}
static void helmet_count(const vx_svo_scene* s, const vx_svo_model* m, size_t* cells, size_t* metal, size_t* lit,
                         double emitted[3]) {
    helmet_cnt k = {s, m, 0, 0, 0, {0, 0, 0}};
    vx_error err = {0};
    CHECK(vx_svo_decode_model(m, helmet_visit, &k, &err) == VX_OK);
    *cells += k.cells, *metal += k.metal, *lit += k.lit;
    for (int c = 0; c < 3; c++) emitted[c] += k.emitted[c];
}

/* The corpus's DamagedHelmet: metal and emissive cells where its textures
 * say. Independently of the voxelizer: the share of the surface (triangle
 * area) whose texel at the triangle's centroid is metal (B > 127) or lit
 * (emissive > 0.25 linear) against the share of cells whose record is
 * metal or emits. */
static void test_helmet_materials(void) {
    const char* path = vx_test_corpus("gltf/khronos_DamagedHelmet.glb");
    if (!path) {
        fprintf(stderr, "  SKIP: corpus DamagedHelmet not found (VX_CORPUS_DIR)\n");
        return;
    }
    vx_gltf_mesh m;
    vx_error err = {0};
    vx_conv_mesh_desc d = {.res = 128};
    REQUIRE(vx_conv_mesh_read(&d, path, &m, &err) == VX_OK);
    REQUIRE(m.material_count >= 1 && m.materials[0].metal_rough.image >= 0 && m.materials[0].emissive_tex.image >= 0);
    double area = 0, area_metal = 0, area_lit = 0;
    for (size_t t = 0; t < m.tri_count; t++) {
        const float* p = m.pos + 9 * t;
        double e1[3], e2[3];
        for (int k = 0; k < 3; k++) e1[k] = p[3 + k] - p[k], e2[k] = p[6 + k] - p[k];
        double cx = e1[1] * e2[2] - e1[2] * e2[1], cy = e1[2] * e2[0] - e1[0] * e2[2], cz = e1[0] * e2[1] - e1[1] * e2[0];
        double a = 0.5 * sqrt(cx * cx + cy * cy + cz * cz);
        const vx_gltf_material* g = &m.materials[m.material[t]];
        const vx_gltf_image* ims[2] = {&m.images[g->metal_rough.image], &m.images[g->emissive_tex.image]};
        const float* uvs[2] = {m.uv_mr + 6 * t, m.uv_emissive + 6 * t};
        double val[2];
        for (int k = 0; k < 2; k++) { /* nearest texel at the centroid (repeat) */
            double u = (uvs[k][0] + uvs[k][2] + uvs[k][4]) / 3, v = (uvs[k][1] + uvs[k][3] + uvs[k][5]) / 3;
            int64_t xi = ref_wrap((int64_t)floor(u * ims[k]->width), ims[k]->width, false);
            int64_t yi = ref_wrap((int64_t)floor(v * ims[k]->height), ims[k]->height, false);
            const uint8_t* px = ims[k]->rgba + 4 * ((size_t)yi * ims[k]->width + (size_t)xi);
            val[k] = k == 0 ? px[2] / 255.0 : fmax(ref_srgb(px[0] / 255.0), fmax(ref_srgb(px[1] / 255.0), ref_srgb(px[2] / 255.0)));
        }
        area += a;
        area_metal += val[0] > 0.5 ? a : 0;
        area_lit += val[1] > 0.25 ? a : 0;
    }
    vx_svo_scene s;
    REQUIRE(vx_conv_mesh(&d, &m, &s, NULL, &err) == VX_OK);
    size_t cells = 0, metal = 0, lit = 0;
    double emitted[3] = {0, 0, 0};
    for (uint32_t i = 0; i < s.model_count; i++) {
        const vx_svo_model* md = &s.models[i];
        REQUIRE(md->attrs & VX_ATTR_MATERIAL);
        helmet_count(&s, md, &cells, &metal, &lit, emitted);
    }
    double fm = (double)metal / (double)cells, fl = (double)lit / (double)cells;
    fprintf(stderr, "  DamagedHelmet res 128: %u records, %zu cells, %zu metal (%.3f; surface %.3f), %zu emissive (%.3f; surface %.3f)\n",
            s.material_count, cells, metal, fm, area_metal / area, lit, fl, area_lit / area);
    CHECK(s.material_count > 1 && metal > 0 && lit > 0);
    CHECK(fabs(fm - area_metal / area) < 0.15 && fabs(fl - area_lit / area) < 0.1);
    /* its emissive map is not grey: every emitting record states its own colour (_emit_color, its largest
     * channel 1), and some are far from grey */
    uint32_t emitting = 0, coloured = 0, stated = 0;
    for (uint32_t i = 0; i < s.material_count; i++) {
        vx_material mt = vx_svo_material_resolve(&s.materials[i]);
        if (!(mt.emission > 0)) continue;
        const double* ec = mt.emission_color;
        double mx = fmax(ec[0], fmax(ec[1], ec[2])), mn = fmin(ec[0], fmin(ec[1], ec[2]));
        emitting++;
        stated += vx_svo_material_get(&s.materials[i], "_emit_color") && mx == 1;
        coloured += mx - mn > 0.25;
    }
    fprintf(stderr, "  DamagedHelmet res 128: %u emitting records, %u with a colour, %u of them far from grey; mean emission of "
            "its emissive cells %.3f %.3f %.3f\n", emitting, stated, coloured, emitted[0] / (double)(lit ? lit : 1),
            emitted[1] / (double)(lit ? lit : 1), emitted[2] / (double)(lit ? lit : 1));
    CHECK(emitting > 0 && stated == emitting && coloured > 0);
    /* and the scene is a valid file */
    uint8_t* bytes = NULL;
    size_t nb = 0;
    CHECK(vx_svo_validate_scene(&s, &err) == VX_OK && vx_svo_write(&s, NULL, &bytes, &nb, &err) == VX_OK);
    vx_svo_scene back;
    vx_result rb = vx_svo_read(NULL, bytes, nb, &back, &err);
    CHECKF(rb == VX_OK, "read back: %s", err.msg);
    if (rb == VX_OK) {
        CHECK(back.material_count == s.material_count && vx_svo_validate_scene(&back, &err) == VX_OK);
        vx_svo_scene_free(&back);
    }
    free(bytes);
    vx_svo_scene_free(&s);
    vx_gltf_mesh_free(&m);
}

/* A glTF with nothing to voxelize says why: meshes that no node of the scene
 * places (as many of glTF-Validator's samples: meshes, no scenes, no nodes),
 * a scene whose nodes place none, or mesh instances holding only points and
 * lines; before, each gave the voxelizer's bare "mesh has no triangles". */
static const char* kNoTriGltf =
    "{\"asset\":{\"version\":\"2.0\"},%s"
    "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0}%s}]}],"
    "\"buffers\":[{\"byteLength\":36,\"uri\":\"data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAA"
    "AAAAAAAAgD8AAAAA\"}],"
    "\"bufferViews\":[{\"buffer\":0,\"byteOffset\":0,\"byteLength\":36}],"
    "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":3,\"type\":\"VEC3\",\"min\":[0,0,0],"
    "\"max\":[1,1,0]}]}";

static void test_nothing_to_voxelize(void) {
    static const struct {
        const char *nodes, *prim, *want;
    } cases[] = {
        {"", "", "the file's root nodes (it has no scene) place no mesh"},
        {"\"scene\":0,\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{\"name\":\"empty\"}],", "",
         "scene 0 places no mesh"},
        {"\"scene\":0,\"scenes\":[{\"nodes\":[0,1]}],\"nodes\":[{\"mesh\":0},{\"mesh\":0}],", ",\"mode\":1",
         "scene 0 places 2 mesh instances, none with triangle primitives"},
        {"\"scene\":0,\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{\"mesh\":0}],", "", NULL}, /* one triangle: read */
    };
    char dir[] = "/tmp/vx_mesh_scene_test_XXXXXX";
    REQUIRE(mkdtemp(dir) != NULL);
    char path[64];
    snprintf(path, sizeof path, "%s/t.gltf", dir);
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        FILE* f = fopen(path, "wb");
        REQUIRE(f != NULL);
        fprintf(f, kNoTriGltf, cases[i].nodes, cases[i].prim);
        fclose(f);
        vx_gltf_mesh m;
        vx_error err = {0};
        vx_result r = vx_conv_mesh_read(NULL, path, &m, &err);
        if (!cases[i].want) {
            CHECKF(r == VX_OK && m.tri_count == 1, "case %zu: result %d (%s)", i, (int)r, err.msg);
            if (r == VX_OK) vx_gltf_mesh_free(&m);
            continue;
        }
        CHECKF(r == VX_ERR_BAD_FORMAT, "case %zu: result %d (%s)", i, (int)r, err.msg);
        CHECKF(strstr(err.msg, cases[i].want) != NULL, "case %zu: message: %s", i, err.msg);
        if (r == VX_OK) vx_gltf_mesh_free(&m);
        vx_svo_scene s;
        r = vx_conv_mesh_file(NULL, path, &s, NULL, &err); /* the whole conversion says the same */
        CHECKF(r == VX_ERR_BAD_FORMAT && strstr(err.msg, cases[i].want) != NULL, "case %zu: file: %d %s", i, (int)r,
               err.msg);
        if (r == VX_OK) vx_svo_scene_free(&s);
    }
    remove(path);
    rmdir(dir);
}

int main(void) {
    RUN(test_regions_match_cells);
    RUN(test_files);
    RUN(test_gltf_lights);
    RUN(test_gltf_bad_lights);
    RUN(test_textured_materials);
    RUN(test_emissive_hue);
    RUN(test_unsampled_emission_unchanged);
    RUN(test_uniform_textures);
    RUN(test_helmet_materials);
    RUN(test_nothing_to_voxelize);
    return vx_test_finish();
}
