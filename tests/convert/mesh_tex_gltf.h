/* tests/convert/mesh_tex_gltf.h - a generated glTF for the per-cell
 * metallic-roughness and emission tests (mesh_scene_test, mesh_gpu_test):
 * a flat 16 x 16 quad (z = 0, two triangles split along x = y) whose
 * TEXCOORD_0 is (x, y) / 16 and TEXCOORD_1 is (1 - x / 16, y / 16), with an
 * 8 x 8 metallicRoughnessTexture (TEXCOORD_0, clamped sampler) and an 8 x 8
 * emissiveTexture (TEXCOORD_1, repeat) given as RGBA bytes, written as
 * stored-deflate PNGs in data URIs. The test's own encoders: nothing of the
 * reader's is used to make the file. */
#ifndef VX_TESTS_MESH_TEX_GLTF_H
#define VX_TESTS_MESH_TEX_GLTF_H

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "formats/gltf.h"

#define TEXG_N 8 /* texels a side */

static uint32_t texg_crc(uint32_t c, const uint8_t* p, size_t n) {
    c = ~c;
    for (size_t i = 0; i < n; i++) {
        c ^= p[i];
        for (int k = 0; k < 8; k++) c = (c >> 1) ^ (0xEDB88320u & (0u - (c & 1u)));
    }
    return ~c;
}

static size_t texg_be32(uint8_t* o, uint32_t v) {
    o[0] = (uint8_t)(v >> 24), o[1] = (uint8_t)(v >> 16), o[2] = (uint8_t)(v >> 8), o[3] = (uint8_t)v;
    return 4;
}

/* A PNG of TEXG_N^2 RGBA texels (rows top to bottom) into o (room for 1024 bytes). */
static size_t texg_png(const uint8_t* rgba, uint8_t* o) {
    static const uint8_t sig[8] = {137, 80, 78, 71, 13, 10, 26, 10};
    size_t n = 0;
    memcpy(o, sig, 8), n = 8;
    uint8_t ihdr[17] = {'I', 'H', 'D', 'R'};
    texg_be32(ihdr + 4, TEXG_N), texg_be32(ihdr + 8, TEXG_N);
    ihdr[12] = 8, ihdr[13] = 6; /* 8 bits, RGBA */
    n += texg_be32(o + n, 13);
    memcpy(o + n, ihdr, 17), n += 17;
    n += texg_be32(o + n, texg_crc(0, ihdr, 17));
    /* zlib: one stored block of the filtered rows (filter 0) */
    uint8_t raw[TEXG_N * (1 + 4 * TEXG_N)];
    size_t rn = 0;
    for (int y = 0; y < TEXG_N; y++) {
        raw[rn++] = 0;
        memcpy(raw + rn, rgba + 4 * TEXG_N * y, 4 * TEXG_N), rn += 4 * TEXG_N;
    }
    uint8_t idat[4 + 2 + 5 + sizeof raw + 4] = {'I', 'D', 'A', 'T', 0x78, 0x01, 1};
    size_t in = 7;
    idat[in++] = (uint8_t)rn, idat[in++] = (uint8_t)(rn >> 8), idat[in++] = (uint8_t)~rn, idat[in++] = (uint8_t)(~rn >> 8);
    memcpy(idat + in, raw, rn), in += rn;
    uint32_t a = 1, b = 0;
    for (size_t i = 0; i < rn; i++) a = (a + raw[i]) % 65521, b = (b + a) % 65521;
    in += texg_be32(idat + in, b << 16 | a);
    n += texg_be32(o + n, (uint32_t)(in - 4));
    memcpy(o + n, idat, in), n += in;
    n += texg_be32(o + n, texg_crc(0, idat, in));
    uint8_t iend[4] = {'I', 'E', 'N', 'D'};
    n += texg_be32(o + n, 0);
    memcpy(o + n, iend, 4), n += 4;
    n += texg_be32(o + n, texg_crc(0, iend, 4));
    return n;
}

static size_t texg_b64(const uint8_t* p, size_t n, char* o) {
    static const char* t = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    size_t k = 0;
    for (size_t i = 0; i < n; i += 3) {
        uint32_t v = (uint32_t)p[i] << 16 | (i + 1 < n ? (uint32_t)p[i + 1] << 8 : 0) | (i + 2 < n ? p[i + 2] : 0);
        o[k++] = t[v >> 18 & 63], o[k++] = t[v >> 12 & 63];
        o[k++] = i + 1 < n ? t[v >> 6 & 63] : '=';
        o[k++] = i + 2 < n ? t[v & 63] : '=';
    }
    o[k] = 0;
    return k;
}

/* The quad's corners (triangle A: (0,0) (16,0) (16,16); B: (0,0) (16,16) (0,16)). */
static const float texg_xy[12] = {0, 0, 16, 0, 16, 16, 0, 0, 16, 16, 0, 16};

/* The glTF text (malloc'd): material JSON `mat` (its textures 0: metallic-
 * roughness, 1: emissive), textures from mr and em (RGBA, TEXG_N^2 each). */
static char* texg_gltf(const char* mat, const uint8_t* mr, const uint8_t* em) {
    float buf[6 * 3 + 6 * 2 + 6 * 2];
    for (int v = 0; v < 6; v++) {
        float x = texg_xy[2 * v], y = texg_xy[2 * v + 1];
        buf[3 * v] = x, buf[3 * v + 1] = y, buf[3 * v + 2] = 0;
        buf[18 + 2 * v] = x / 16, buf[18 + 2 * v + 1] = y / 16;
        buf[30 + 2 * v] = 1 - x / 16, buf[30 + 2 * v + 1] = y / 16;
    }
    uint8_t png[2][1024];
    size_t pn[2] = {texg_png(mr, png[0]), texg_png(em, png[1])};
    char* b64[3];
    for (int k = 0; k < 3; k++) b64[k] = (char*)malloc(2048);
    texg_b64((const uint8_t*)buf, sizeof buf, b64[0]);
    texg_b64(png[0], pn[0], b64[1]);
    texg_b64(png[1], pn[1], b64[2]);
    size_t cap = 16384 + strlen(mat);
    char* j = (char*)malloc(cap);
    snprintf(j, cap,
             "{\"asset\":{\"version\":\"2.0\"},\"extensionsUsed\":[\"KHR_materials_emissive_strength\"],\"scene\":0,"
             "\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{\"mesh\":0}],"
             "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0,\"TEXCOORD_0\":1,\"TEXCOORD_1\":2},"
             "\"material\":0}]}],\"materials\":[%s],"
             "\"samplers\":[{\"wrapS\":33071,\"wrapT\":33071},{}],"
             "\"textures\":[{\"source\":0,\"sampler\":0},{\"source\":1,\"sampler\":1}],"
             "\"images\":[{\"uri\":\"data:image/png;base64,%s\"},{\"uri\":\"data:image/png;base64,%s\"}],"
             "\"buffers\":[{\"byteLength\":%zu,\"uri\":\"data:application/octet-stream;base64,%s\"}],"
             "\"bufferViews\":[{\"buffer\":0,\"byteOffset\":0,\"byteLength\":72},{\"buffer\":0,\"byteOffset\":72,"
             "\"byteLength\":48},{\"buffer\":0,\"byteOffset\":120,\"byteLength\":48}],"
             "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":6,\"type\":\"VEC3\",\"min\":[0,0,0],"
             "\"max\":[16,16,0]},{\"bufferView\":1,\"componentType\":5126,\"count\":6,\"type\":\"VEC2\"},"
             "{\"bufferView\":2,\"componentType\":5126,\"count\":6,\"type\":\"VEC2\"}]}",
             mat, b64[1], b64[2], sizeof buf, b64[0]);
    for (int k = 0; k < 3; k++) free(b64[k]);
    return j;
}

/* The glTF of texg_gltf read into m (vx_gltf_read, defaults). */
static vx_result texg_read(const char* mat, const uint8_t* mr, const uint8_t* em, vx_gltf_mesh* m, vx_error* err) {
    char* j = texg_gltf(mat, mr, em);
    vx_result r = vx_gltf_read(NULL, j, strlen(j), NULL, m, err);
    free(j);
    return r;
}

/* The split textures: metallic-roughness left half (x < 4) metal (B 255)
 * with G 102, right half B 0 with G 255; emissive orange (255 128 0) in the
 * quarter x < 4, y >= 4 (rows top to bottom: image rows 0..3 are v < 0.5),
 * black elsewhere. */
static void texg_split(uint8_t mr[4 * TEXG_N * TEXG_N], uint8_t em[4 * TEXG_N * TEXG_N]) {
    for (int y = 0; y < TEXG_N; y++)
        for (int x = 0; x < TEXG_N; x++) {
            uint8_t* p = mr + 4 * (y * TEXG_N + x);
            p[0] = 0, p[1] = x < 4 ? 102 : 255, p[2] = x < 4 ? 255 : 0, p[3] = 255;
            uint8_t* e = em + 4 * (y * TEXG_N + x);
            bool lit = x < 4 && y >= 4;
            e[0] = lit ? 255 : 0, e[1] = lit ? 128 : 0, e[2] = 0, e[3] = 255;
        }
}

static const char* kTexgSplitMat =
    "{\"pbrMetallicRoughness\":{\"metallicFactor\":0.8,\"roughnessFactor\":0.5,"
    "\"metallicRoughnessTexture\":{\"index\":0}},\"emissiveFactor\":[1,1,1],"
    "\"emissiveTexture\":{\"index\":1,\"texCoord\":1},"
    "\"extensions\":{\"KHR_materials_emissive_strength\":{\"emissiveStrength\":2}}}";

/* Emissive textures of two hues (mesh_scene_test's test_emissive_hue,
 * mesh_gpu_test): in the top half (image rows 0..3, the quad's cells y < 8)
 * red (255 0 0) in columns 0..3 (TEXCOORD_1's u < 0.5: cells x > 8) and
 * orange (255 128 0) in columns 4..7; in the bottom half `full` in columns
 * 0..3 and at half (its channels above 0 at 128) in columns 4..7. A cell whose
 * bilinear footprint stays in one quarter (x and y in 1..6 or 9..14: no
 * border, no wrap) sees that quarter's texel alone. */
static void texg_hue(const uint8_t full[3], uint8_t em[4 * TEXG_N * TEXG_N]) {
    for (int y = 0; y < TEXG_N; y++)
        for (int x = 0; x < TEXG_N; x++) {
            uint8_t* e = em + 4 * (y * TEXG_N + x);
            bool left = x < 4;
            for (int c = 0; c < 3; c++) {
                uint8_t top = c == 0 ? 255 : c == 1 && !left ? 128 : 0;
                uint8_t bottom = left ? full[c] : full[c] ? 128 : 0;
                e[c] = y < 4 ? top : bottom;
            }
            e[3] = 255;
        }
}

/* A material that emits through its texture alone (metallic 0, white base
 * colour): factor `factor` ("R,G,B") x strength 3. */
#define TEXG_HUE_MAT(factor)                                                                                    \
    "{\"pbrMetallicRoughness\":{\"metallicFactor\":0},\"emissiveFactor\":[" factor "],"                          \
    "\"emissiveTexture\":{\"index\":1,\"texCoord\":1},"                                                         \
    "\"extensions\":{\"KHR_materials_emissive_strength\":{\"emissiveStrength\":3}}}"

#endif
