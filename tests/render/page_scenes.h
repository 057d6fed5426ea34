/* tests/render/page_scenes.h - set-up shared by the paging tests
 * (test_compact_page: pages from memory, test_compact_page_file: pages
 * read from the .svo file): a sphere-shell model with RGBA colours, the
 * views that circle a scene's box, and two frames compared pixel by pixel.
 * Written once here so that both tests page the same scenes under the same
 * views (they were copies of each other). */
#ifndef VX_TEST_RENDER_PAGE_SCENES_H
#define VX_TEST_RENDER_PAGE_SCENES_H
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "render/render.h"
#include "svo/svo.h"
#include "tests/render/scenes.h"

/* The pixels of b that differ from a: instance, colour and hit flags, and
 * where a hits, the cell and t bits; the first three printed (what: the
 * comparison, other: b's name). */
static uint32_t tp_differ(const vx_render_image* a, const vx_render_image* b, const char* what, const char* other) {
    uint32_t wrong = 0;
    for (size_t i = 0; i < (size_t)a->width * a->height; i++) {
        const vx_render_hit *x = &a->hits[i], *y = &b->hits[i];
        bool same = x->instance == y->instance && !memcmp(&a->pixels[4 * i], &b->pixels[4 * i], 16) &&
                    x->flags == y->flags;
        if (x->instance != VX_RENDER_NO_HIT)
            same = same && !memcmp(x->cell, y->cell, sizeof x->cell) && !memcmp(&x->t, &y->t, sizeof x->t);
        if (!same && wrong++ < 3)
            fprintf(stderr, "  %s pixel %zu: instance %u cell (%u %u %u) rgb %.4f flags %u; %s %u (%u %u %u) rgb %.4f flags %u\n",
                    what, i, x->instance, x->cell[0], x->cell[1], x->cell[2], a->pixels[4 * i], x->flags, other,
                    y->instance, y->cell[0], y->cell[1], y->cell[2], b->pixels[4 * i], y->flags);
    }
    return wrong;
}

/* A 96x64 albedo frame with hits of the box lo..hi: u in [0, 1) goes once
 * round it; close: from inside the box's margin towards a point near its
 * middle (pages of one region), else the whole box from outside. */
static vx_render_desc tp_view(const double lo[3], const double hi[3], double u, bool close) {
    vx_render_desc d = {.width = 96, .height = 64, .mode = VX_RENDER_ALBEDO, .want_hits = true};
    d.camera.set = true;
    d.camera.fov = close ? 40 : 60;
    for (int k = 0; k < 3; k++) {
        double mid = 0.5 * (lo[k] + hi[k]), ext = hi[k] - lo[k];
        double a = 6.2831853 * u + k;
        d.camera.target[k] = mid + (close ? 0.1 * ext * cos(a) : 0.0);
        d.camera.eye[k] = mid + (close ? 0.35 : 1.2) * ext * (k == 1 ? 0.6 : cos(a + 1.3 * k));
    }
    return d;
}

/* A sphere shell with RGBA colours (gradients and noise: delta blocks). */
static vx_result tp_shell_model(vx_svo_model* m, uint32_t n3, uint32_t seed) {
    size_t n = 0, cap = (size_t)n3 * n3 * n3;
    uint64_t* keys = malloc(cap * 8);
    uint32_t* rgba = malloc(cap * 4);
    vx_result r = VX_ERR_NOMEM;
    if (keys && rgba) {
        double c = n3 / 2.0, r0 = n3 * 0.45, r1 = n3 * 0.35;
        for (uint32_t z = 0; z < n3; z++)
            for (uint32_t y = 0; y < n3; y++)
                for (uint32_t x = 0; x < n3; x++) {
                    double q = (x - c) * (x - c) + (y - c) * (y - c) + (z - c) * (z - c);
                    if (q < r0 * r0 && q > r1 * r1 && ts_rng(&seed) % 5) {
                        keys[n] = vx_svo_morton(x, y, z);
                        rgba[n++] = 0xFF000000u | (x * 4 & 0xFFu) | ((y * 4 & 0xFFu) << 8) | ((z * 4 & 0xFFu) << 16) |
                                    (ts_rng(&seed) & 0x070707u);
                    }
                }
        vx_error err = {0};
        vx_svo_voxels v = {.size = {n3, n3, n3}, .count = n, .keys = keys, .attrs = VX_ATTR_RGBA8, .rgba = rgba};
        r = vx_svo_build_model(NULL, &v, m, NULL, &err);
    }
    free(keys);
    free(rgba);
    return r;
}

#endif
