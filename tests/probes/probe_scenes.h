/* tests/probes/probe_scenes.h - small scenes for the probe tests. */
#ifndef VX_TEST_PROBE_SCENES_H
#define VX_TEST_PROBE_SCENES_H
#include <stdio.h>

#include "tests/render/scenes.h"

static inline size_t vx__bsq_test(uint32_t n) { return (size_t)(n + 2) * (n + 2); }

/* A closed n^3 box of voxels of palette c. */
static void box_scene(vx_svo_scene* s, uint32_t n, uint8_t c) {
    size_t cap = (size_t)n * n * n, k = 0;
    uint32_t* xyz = malloc(cap * 12);
    uint8_t* pal = malloc(cap);
    for (uint32_t z = 0; z < n; z++)
        for (uint32_t y = 0; y < n; y++)
            for (uint32_t x = 0; x < n; x++)
                if (!x || !y || !z || x == n - 1 || y == n - 1 || z == n - 1) {
                    xyz[3 * k] = x, xyz[3 * k + 1] = y, xyz[3 * k + 2] = z;
                    pal[k++] = c;
                }
    vx_svo_model m;
    uint32_t size[3] = {n, n, n};
    ts_model(&m, size, xyz, pal, k);
    vx_svo_instance in = ts_inst(0, NULL, 0, 0, 0);
    ts_scene(s, &m, 1, &in, 1);
    free(xyz);
    free(pal);
}

/* A small lit room: floor, two walls, an emissive block (palette 9). */
static void room_scene(vx_svo_scene* s) {
    uint32_t n = 12, cap = n * n * n, k = 0;
    uint32_t* xyz = malloc((size_t)cap * 12);
    uint8_t* pal = malloc(cap);
    for (uint32_t z = 0; z < n; z++)
        for (uint32_t y = 0; y < n; y++)
            for (uint32_t x = 0; x < n; x++) {
                uint8_t c = 0;
                if (z == 0) c = 3;
                else if (x == 0 || y == n - 1) c = 4;
                else if (x >= 5 && x <= 6 && y >= 5 && y <= 6 && z <= 2) c = 9;
                if (!c) continue;
                xyz[3 * k] = x, xyz[3 * k + 1] = y, xyz[3 * k + 2] = z;
                pal[k++] = c;
            }
    vx_svo_model m;
    uint32_t size[3] = {n, n, n};
    ts_model(&m, size, xyz, pal, k);
    vx_svo_instance in = ts_inst(0, NULL, 0, 0, 0);
    ts_scene(s, &m, 1, &in, 1);
    s->palette[3] = 0xFF80A0C0u, s->palette[4] = 0xFF4080E0u, s->palette[9] = 0xFFFFFFFFu;
    static char dict[] = "_type\0_emit\0_emit\0" "0.5\0_flux\0" "1";
    s->materials = calloc(1, sizeof *s->materials);
    s->materials[0].id = 9;
    s->materials[0].dict_size = sizeof dict;
    s->materials[0].dict = malloc(sizeof dict);
    memcpy(s->materials[0].dict, dict, sizeof dict);
    s->material_count = 1;
    free(xyz);
    free(pal);
}

#endif
