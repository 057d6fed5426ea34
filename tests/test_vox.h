/* tests/test_vox.h - a corpus .vox file as an SVO scene, read and converted
 * with the defaults: the step the render and probe tests share (they link
 * vx_formats and vx_convert). */
#ifndef VX_TESTS_TEST_VOX_H
#define VX_TESTS_TEST_VOX_H
#include <math.h>
#include <stdio.h>

#include "convert/convert.h"
#include "formats/vox.h"
#include "tests/test.h"

typedef enum vx_test_vox { VX_TEST_VOX_OK, VX_TEST_VOX_ABSENT, VX_TEST_VOX_FAILED } vx_test_vox;

/* Corpus file vox/NAME into *out (free it with vx_svo_scene_free):
 * VX_TEST_VOX_OK; VX_TEST_VOX_ABSENT when the corpus does not have it (the
 * caller skips it); VX_TEST_VOX_FAILED when reading or converting failed
 * (the reason printed). *out is set only with VX_TEST_VOX_OK. */
static inline vx_test_vox vx_test_vox_scene(const char* name, vx_svo_scene* out) {
    char rel[256];
    snprintf(rel, sizeof rel, "vox/%s", name);
    const char* path = vx_test_corpus(rel);
    if (!path) return VX_TEST_VOX_ABSENT;
    vx_vox_scene vs;
    vx_error err = {0};
    vx_result r = vx_vox_read_file(NULL, path, &vs, &err);
    if (!r) {
        r = vx_conv_vox(NULL, &vs, out, NULL, &err);
        vx_vox_scene_free(&vs);
    }
    if (r) {
        fprintf(stderr, "  %s: %s\n", name, err.msg);
        return VX_TEST_VOX_FAILED;
    }
    return VX_TEST_VOX_OK;
}

/* The RGBA distance (0..510) of two RGBA8 colours: the colour error
 * vx_conv_vox_export_stats reports for a quantized .vox export. */
static inline double vx_test_rgba_dist(uint32_t a, uint32_t b) {
    double d2 = 0;
    for (int k = 0; k < 4; k++) {
        double d = (double)((a >> 8 * k) & 255) - (double)((b >> 8 * k) & 255);
        d2 += d * d;
    }
    return sqrt(d2);
}

#endif
