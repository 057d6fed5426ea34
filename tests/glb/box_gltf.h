/* tests/glb/box_gltf.h - what the glTF tests' hand-written files share: a box
 * 0..4 on each axis (12 triangles, 36 float positions) as the base64 text of
 * a data URI, and writing a text file. Header-only, static: each test is its
 * own program. */
#ifndef VX_TEST_GLB_BOX_GLTF_H
#define VX_TEST_GLB_BOX_GLTF_H
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

/* Bytes of the box's positions (the buffer's and view's byteLength). */
enum { BOX_GLTF_BYTES = 36 * 3 * 4 };
/* Room for the base64 text of the box's positions, with its NUL. */
enum { BOX_GLTF_B64 = 4 * BOX_GLTF_BYTES / 3 + 8 };

static void box_gltf_base64(const uint8_t* p, size_t n, char* out) {
    static const char B64[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    for (size_t i = 0; i < n; i += 3) {
        uint32_t v = (uint32_t)p[i] << 16 | (i + 1 < n ? (uint32_t)p[i + 1] << 8 : 0) | (i + 2 < n ? p[i + 2] : 0);
        *out++ = B64[v >> 18 & 63];
        *out++ = B64[v >> 12 & 63];
        *out++ = i + 1 < n ? B64[v >> 6 & 63] : '=';
        *out++ = i + 2 < n ? B64[v & 63] : '=';
    }
    *out = 0;
}

/* The box's positions (float x, y, z per vertex, three per triangle,
 * counter-clockwise from outside) as base64 into out[BOX_GLTF_B64]. */
static void box_gltf_positions(char out[BOX_GLTF_B64]) {
    static const uint8_t tri[12][3] = {{0, 1, 3}, {0, 3, 2}, {4, 6, 7}, {4, 7, 5}, {0, 4, 5}, {0, 5, 1},
                                       {2, 3, 7}, {2, 7, 6}, {0, 2, 6}, {0, 6, 4}, {1, 5, 7}, {1, 7, 3}};
    float pos[36][3];
    for (int t = 0; t < 12; t++)
        for (int v = 0; v < 3; v++)
            for (int a = 0; a < 3; a++) pos[3 * t + v][a] = (tri[t][v] >> (2 - a) & 1) ? 4.f : 0.f;
    box_gltf_base64((const uint8_t*)pos, sizeof pos, out);
}

/* Writes text to path; false on any failure. */
static bool write_text(const char* path, const char* text) {
    FILE* f = fopen(path, "wb");
    if (!f) return false;
    bool ok = fwrite(text, 1, strlen(text), f) == strlen(text);
    return fclose(f) == 0 && ok;
}
#endif
