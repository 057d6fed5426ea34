/* tests/glb/test_glb_materials.c - svo_info --to-glb keeps the scene's MATL
 * materials (convert/export_glb.c, formats/glb.h). A .vox scene written with
 * our writer: a 12 x 2 x 2 bar of six 2^3 blocks, palette indices 1..6: a
 * _diffuse record, _metal, _glass, and three _emit (white and orange under
 * MagicaVoxel's colour x _emit rule, one with voxkit's _emit_color). The
 * diffuse, metal and glass blocks share one colour, so a mesher that merged
 * on colour alone would run their quads together. Read back with our glTF
 * reader (formats/gltf.h), every triangle's material must be its block's;
 * voxelized again (vx_conv_mesh_file at the scene's resolution) the records
 * must come back with the same types and values. A scene without MATL
 * records (or with only diffuse ones) exports the one default material, as
 * before materials were exported. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "convert/convert.h"
#include "convert/export.h"
#include "convert/mesh.h"
#include "formats/gltf.h"
#include "formats/vox.h"
#include "svo/svo.h"
#include "tests/test.h"

enum { BLOCKS = 6 };

/* A model's cells and their attribute records (vx_svo_decode_model). */
typedef struct cell_list {
    uint32_t* xyz;
    uint32_t* attr;
    size_t n, cap;
} cell_list;
static bool add_cell(void* user, uint32_t x, uint32_t y, uint32_t z, uint32_t attr) {
    cell_list* c = user;
    if (c->n == c->cap) {
        size_t cap = c->cap ? 2 * c->cap : 256;
        uint32_t* xyz = realloc(c->xyz, 3 * cap * sizeof *xyz);
        if (xyz) c->xyz = xyz;
        uint32_t* at = realloc(c->attr, cap * sizeof *at);
        if (at) c->attr = at;
        if (!xyz || !at) return false; /* the decode stops with an error */
        c->cap = cap;
    }
    c->xyz[3 * c->n] = x, c->xyz[3 * c->n + 1] = y, c->xyz[3 * c->n + 2] = z, c->attr[c->n++] = attr;
    return true;
}

/* palette index b + 1 per block b; R in the low byte */
static const uint32_t colour[BLOCKS] = {0xFF808080u, 0xFF808080u, 0xFF808080u,
                                        0xFFFFFFFFu, 0xFF2080FFu, 0xFF40C0A0u};
static const char* const dicts[BLOCKS][8] = {
    {"_type", "_diffuse", "_rough", "0.5"},
    {"_type", "_metal", "_metal", "0.7", "_rough", "0.3"},
    {"_type", "_glass", "_trans", "0.8", "_ior", "0.33", "_rough", "0.1"},
    {"_type", "_emit", "_emit", "3"},
    {"_type", "_emit", "_emit", "1.5"},
    {"_type", "_emit", "_emit", "2", "_emit_color", "1 0.5 0.25"},
};

static void set_dict(vx_vox_material* m, uint32_t id, const char* const* kv) {
    size_t n = 0;
    for (int k = 0; k < 8 && kv[k]; k++) n += strlen(kv[k]) + 1;
    m->id = id;
    m->dict_size = (uint32_t)n;
    m->dict = malloc(n + 1);
    n = 0;
    for (int k = 0; k < 8 && kv[k]; k++) {
        memcpy(m->dict + n, kv[k], strlen(kv[k]) + 1);
        n += strlen(kv[k]) + 1;
    }
}

/* The bar through .vox bytes and vx_conv_vox; materials: how many of the
 * blocks' records to write (0 none, 1 the diffuse one only, BLOCKS all). */
static vx_result bar_scene(int materials, vx_svo_scene* out) {
    vx_vox_scene s;
    memset(&s, 0, sizeof s);
    s.version = 150;
    s.model_count = 1;
    s.models = calloc(1, sizeof *s.models);
    s.instances = calloc(1, sizeof *s.instances);
    s.materials = calloc(BLOCKS, sizeof *s.materials);
    if (!s.models || !s.instances || !s.materials) return VX_ERR_NOMEM;
    vx_vox_model* vm = &s.models[0];
    vm->size[0] = 2 * BLOCKS, vm->size[1] = 2, vm->size[2] = 2;
    vm->xyzi = malloc(4 * 2 * BLOCKS * 4);
    if (!vm->xyzi) return VX_ERR_NOMEM;
    for (uint32_t z = 0; z < 2; z++)
        for (uint32_t y = 0; y < 2; y++)
            for (uint32_t x = 0; x < 2 * BLOCKS; x++) {
                uint8_t* v = vm->xyzi + 4 * (size_t)vm->voxel_count++;
                v[0] = (uint8_t)x, v[1] = (uint8_t)y, v[2] = (uint8_t)z, v[3] = (uint8_t)(x / 2 + 1);
            }
    s.has_rgba = true;
    memcpy(s.palette, vx_vox_default_palette, sizeof s.palette);
    for (int b = 0; b < BLOCKS; b++) s.palette[b + 1] = colour[b];
    for (int b = 0; b < materials; b++) set_dict(&s.materials[s.material_count++], (uint32_t)b + 1, dicts[b]);
    static const int32_t id[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    s.instances[0] = (vx_vox_instance){.model = 0, .layer = -1, .name = "bar"};
    memcpy(s.instances[0].rot, id, sizeof id);
    s.instance_count = 1;
    uint8_t* bytes = NULL;
    size_t n = 0;
    vx_error err = {0};
    vx_vox_scene back;
    vx_result r = vx_vox_write(&s, NULL, &bytes, &n, &err);
    vx_vox_scene_free(&s);
    if (!r) r = vx_vox_read(NULL, bytes, n, &back, &err);
    free(bytes);
    if (!r) {
        vx_conv_stats st;
        r = vx_conv_vox(&(vx_conv_vox_desc){0}, &back, out, &st, &err);
        vx_vox_scene_free(&back);
    }
    if (r) fprintf(stderr, "  bar_scene: %s\n", err.msg);
    return r;
}

static double srgb_to_linear(uint32_t byte) {
    double c = byte / 255.0;
    return c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4);
}

/* The emission block b's glTF material must carry: the record's emission
 * colour x strength, or (no _emit_color) its cells' linear colour x strength. */
static void expected_emission(int b, double e[3]) {
    static const double strength[BLOCKS] = {0, 0, 0, 3, 1.5, 2};
    static const double own[3] = {1, 0.5, 0.25};
    for (int c = 0; c < 3; c++)
        e[c] = strength[b] * (b == 5 ? own[c] : srgb_to_linear(colour[b] >> (8 * c) & 0xFF));
}

static bool near(double a, double b, double tol) { return fabs(a - b) <= tol * (1 + fabs(b)); }

static void tmp_path(char* buf, size_t n, const char* tag) {
    const char* d = getenv("TMPDIR");
    snprintf(buf, n, "%s/test_glb_materials_%ld_%s.glb", d && *d ? d : "/tmp", (long)getpid(), tag);
}

static vx_result export_glb(const vx_svo_scene* s, const char* path) {
    vx_error err = {0};
    vx_result r = vx_conv_svo_to_glb_file(NULL, s, path, NULL, &err);
    if (r) fprintf(stderr, "  export: %s\n", err.msg);
    return r;
}

static void test_materials_read_back(void) {
    vx_svo_scene s;
    REQUIRE(bar_scene(BLOCKS, &s) == VX_OK);
    char path[512];
    tmp_path(path, sizeof path, "mat");
    vx_result r = export_glb(&s, path);
    vx_svo_scene_free(&s);
    REQUIRE(r == VX_OK);
    vx_gltf_mesh gm;
    vx_error err = {0};
    r = vx_gltf_read_file(NULL, path, &gm, &err);
    remove(path);
    if (r) fprintf(stderr, "  read: %s\n", err.msg);
    REQUIRE(r == VX_OK);
    /* one default material and one per non-diffuse record */
    CHECKF(gm.material_count == BLOCKS, "%u materials", gm.material_count);
    float lo = INFINITY, hi = -INFINITY;
    for (size_t i = 0; i < 9 * gm.tri_count; i += 3) {
        if (gm.pos[i] < lo) lo = gm.pos[i];
        if (gm.pos[i] > hi) hi = gm.pos[i];
    }
    REQUIRE(gm.tri_count > 0 && hi > lo);
    size_t seen[BLOCKS] = {0}, bad = 0;
    for (size_t t = 0; t < gm.tri_count; t++) {
        double cx = (gm.pos[9 * t] + gm.pos[9 * t + 3] + gm.pos[9 * t + 6]) / 3;
        int b = (int)floor((cx - lo) / (hi - lo) * BLOCKS);
        b = b < 0 ? 0 : b >= BLOCKS ? BLOCKS - 1 : b;
        seen[b]++;
        REQUIRE(gm.material && gm.material[t] < gm.material_count);
        const vx_gltf_material* m = &gm.materials[gm.material[t]];
        double e[3] = {0, 0, 0};
        if (b >= 3) expected_emission(b, e);
        bool ok = near(m->emissive[0], e[0], 1e-5) && near(m->emissive[1], e[1], 1e-5) &&
                  near(m->emissive[2], e[2], 1e-5);
        switch (b) {
        case 0: /* a _diffuse record: the default material */
            ok = ok && m->metallic == 0 && m->roughness == 1 && m->transmission == 0 && m->ior == 1.5f;
            break;
        case 1: ok = ok && near(m->metallic, 0.7, 1e-6) && near(m->roughness, 0.3, 1e-6) && m->transmission == 0; break;
        case 2:
            ok = ok && m->metallic == 0 && near(m->transmission, 0.8, 1e-6) && near(m->ior, 1.33, 1e-6) &&
                 near(m->roughness, 0.1, 1e-6);
            break;
        default: ok = ok && m->metallic == 0 && m->transmission == 0; break;
        }
        for (int k = 0; k < 4; k++) ok = ok && m->base_color[k] == 1; /* the vertex colours carry the colour */
        if (!ok && bad++ < 6)
            fprintf(stderr,
                    "  triangle %zu (block %d): material %u metallic %g roughness %g emissive %g %g %g "
                    "transmission %g ior %g; emissive expected %g %g %g\n",
                    t, b, gm.material[t], m->metallic, m->roughness, m->emissive[0], m->emissive[1], m->emissive[2],
                    m->transmission, m->ior, e[0], e[1], e[2]);
    }
    CHECKF(bad == 0, "%zu triangles with another block's material", bad);
    for (int b = 0; b < BLOCKS; b++) CHECKF(seen[b] > 0, "no triangle in block %d", b);
    vx_gltf_mesh_free(&gm);
}

/* vox -> svo -> glb -> svo: the records come back with their types and values */
static void test_materials_round_trip(void) {
    vx_svo_scene s, back;
    REQUIRE(bar_scene(BLOCKS, &s) == VX_OK);
    char path[512];
    tmp_path(path, sizeof path, "trip");
    vx_result r = export_glb(&s, path);
    vx_error err = {0};
    if (!r) {
        r = vx_conv_mesh_file(&(vx_conv_mesh_desc){.res = 2 * BLOCKS}, path, &back, NULL, &err);
        if (r) fprintf(stderr, "  voxelize: %s\n", err.msg);
    }
    remove(path);
    if (r) vx_svo_scene_free(&s);
    REQUIRE(r == VX_OK);
    /* the diffuse block stores no record (convert/mesh.h): the other five do */
    CHECKF(back.material_count == BLOCKS - 1, "%u records back", back.material_count);
    bool used[64] = {false};
    for (int b = 1; b < BLOCKS; b++) {
        vx_material a = vx_svo_scene_material(&s, (uint32_t)b + 1);
        bool found = false;
        for (uint32_t i = 0; i < back.material_count && i < 64 && !found; i++) {
            if (used[i]) continue;
            vx_material m = vx_svo_material_resolve(&back.materials[i]);
            if (m.type != a.type) continue;
            bool ok = near(m.roughness, a.roughness, 1e-5);
            if (a.type == VX_MATERIAL_METAL) ok = ok && near(m.metalness, a.metalness, 1e-5);
            if (a.type == VX_MATERIAL_GLASS)
                ok = ok && near(m.transmission, a.transmission, 1e-5) && near(m.ior, a.ior, 1e-5);
            if (a.type == VX_MATERIAL_EMIT) {
                /* the light emitted: glTF's (expected_emission) is the
                 * importer's _emit x _emit_color */
                double e[3], any[3] = {0.5, 0.5, 0.5}, got[3];
                expected_emission(b, e);
                vx_material_emitted(&m, any, got);
                for (int c = 0; c < 3; c++) ok = ok && near(got[c], e[c], 1e-5);
            }
            if (ok) found = used[i] = true;
        }
        CHECKF(found, "block %d's material (type %d) did not come back", b, (int)a.type);
    }
    /* and the cells name them: every cell of the bar is back, each with its block's material type (and
     * emission: the two MagicaVoxel-rule emitters differ in it) */
    uint64_t cells = 0;
    size_t wrong = 0;
    for (uint32_t m = 0; m < back.model_count; m++) {
        cell_list c = {0};
        REQUIRE(vx_svo_decode_model(&back.models[m], add_cell, &c, &err) == VX_OK);
        cells += c.n;
        uint32_t lo = UINT32_MAX;
        for (size_t i = 0; i < c.n; i++) lo = c.xyz[3 * i] < lo ? c.xyz[3 * i] : lo;
        for (size_t i = 0; i < c.n; i++) {
            int b = (int)((c.xyz[3 * i] - lo) / 2);
            b = b >= BLOCKS ? BLOCKS - 1 : b;
            vx_material got = vx_svo_scene_material(&back, vx_svo_attr_material(&back.models[m], c.attr[i]));
            vx_material want = vx_svo_scene_material(&s, (uint32_t)b + 1);
            double e[3] = {0, 0, 0}, any[3] = {0.5, 0.5, 0.5}, ge[3];
            if (b >= 3) expected_emission(b, e);
            vx_material_emitted(&got, any, ge);
            bool ok = got.type == want.type && near(ge[0], e[0], 1e-5) && near(ge[1], e[1], 1e-5) &&
                      near(ge[2], e[2], 1e-5);
            if (!ok && wrong++ < 4)
                fprintf(stderr, "  cell %u %u %u (block %d): type %d, expected %d\n", c.xyz[3 * i], c.xyz[3 * i + 1],
                        c.xyz[3 * i + 2], b, (int)got.type, (int)want.type);
        }
        free(c.xyz), free(c.attr);
    }
    CHECKF(cells == 4 * 2 * BLOCKS, "%llu cells back", (unsigned long long)cells);
    CHECKF(wrong == 0, "%zu cells with another block's material", wrong);
    vx_svo_scene_free(&back);
    vx_svo_scene_free(&s);
}

/* Without MATL records, or with diffuse ones only, the document's material
 * list is the one default material (as before materials were exported),
 * and the two exports are the same bytes. */
static void test_no_materials_as_before(void) {
    char path[2][512];
    uint8_t* bytes[2] = {NULL, NULL};
    long size[2] = {0, 0};
    for (int k = 0; k < 2; k++) {
        vx_svo_scene s;
        REQUIRE(bar_scene(k, &s) == VX_OK);
        tmp_path(path[k], sizeof path[k], k ? "diffuse" : "none");
        vx_result r = export_glb(&s, path[k]);
        vx_svo_scene_free(&s);
        REQUIRE(r == VX_OK);
        FILE* f = fopen(path[k], "rb");
        REQUIRE(f);
        fseek(f, 0, SEEK_END);
        size[k] = ftell(f);
        fseek(f, 0, SEEK_SET);
        bytes[k] = malloc((size_t)size[k] + 1);
        size_t got = bytes[k] ? fread(bytes[k], 1, (size_t)size[k], f) : 0;
        fclose(f);
        remove(path[k]);
        REQUIRE(got == (size_t)size[k]);
        bytes[k][size[k]] = 0;
    }
    CHECK(size[0] == size[1] && memcmp(bytes[0], bytes[1], (size_t)size[0]) == 0);
    /* the JSON chunk (from byte 20) holds exactly the old material list, one primitive, no extensions */
    const char* json = (const char*)bytes[0] + 20;
    CHECK(strstr(json, "\"materials\":[{\"name\":\"voxel\",\"pbrMetallicRoughness\":{\"metallicFactor\":0.0}}]"));
    CHECK(!strstr(json, "extensionsUsed"));
    CHECK(!strstr(json, "\"material\":1"));
    free(bytes[0]);
    free(bytes[1]);
}

int main(void) {
    RUN(test_materials_read_back);
    RUN(test_materials_round_trip);
    RUN(test_no_materials_as_before);
    return vx_test_finish();
}
