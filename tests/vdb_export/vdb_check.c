/* vdb_check FILE.vdb FILE.svo: reads an svo_info --to-vdb output back through
 * the OpenVDB shim (formats/vdb.h) and prints each active voxel of every
 * "density" / "NAME/density" grid as 'x y z r g b' in the .svo's grid cells
 * (voxel centre -> world by the grid's transform -> grid cell by the inverse
 * of the scene's world_from_grid), colours from the matching "color" grid
 * encoded back to sRGB bytes (255 255 255 without one), for comparison with
 * `svo_info --dump`. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "formats/vdb.h"
#include "svo/svo.h"

typedef struct ctx {
    vx_vdb_file* f;
    int32_t color; /* grid index or -1 */
    const double* itw;
    double inv[12]; /* grid_from_world */
    uint64_t voxels;
    int bad;
} ctx;

static int srgb8(double l) {
    double c = l <= 0.0031308 ? 12.92 * l : 1.055 * pow(l, 1 / 2.4) - 0.055;
    return (int)lround(255.0 * (c < 0 ? 0 : c > 1 ? 1 : c));
}

static bool visit(void* user, const int32_t o[3], uint32_t log2dim, bool active, const double v[3]) {
    ctx* c = (ctx*)user;
    (void)v;
    if (!active) return true;
    if (log2dim) { /* the writer sets voxels only */
        c->bad = 1;
        return false;
    }
    double p[3], g[3];
    for (int r = 0; r < 3; r++)
        p[r] = c->itw[r * 4] * o[0] + c->itw[r * 4 + 1] * o[1] + c->itw[r * 4 + 2] * o[2] + c->itw[r * 4 + 3];
    for (int r = 0; r < 3; r++)
        g[r] = floor(c->inv[r * 4] * p[0] + c->inv[r * 4 + 1] * p[1] + c->inv[r * 4 + 2] * p[2] + c->inv[r * 4 + 3]);
    int rgb[3] = {255, 255, 255};
    if (c->color >= 0) {
        double col[3];
        bool on;
        uint32_t l2;
        if (!vx_vdb_probe(c->f, (uint32_t)c->color, o, col, &on, &l2) || !on) c->bad = 2;
        for (int k = 0; k < 3; k++) rgb[k] = srgb8(col[k]);
    }
    printf("%.0f %.0f %.0f %d %d %d\n", g[0], g[1], g[2], rgb[0], rgb[1], rgb[2]);
    c->voxels++;
    return true;
}

/* inverse of a 3x4 affine map */
static bool invert(const double m[12], double out[12]) {
    double a = m[0], b = m[1], c = m[2], d = m[4], e = m[5], f = m[6], g = m[8], h = m[9], i = m[10];
    double det = a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g);
    if (!(fabs(det) > 0)) return false;
    double L[9] = {(e * i - f * h) / det, (c * h - b * i) / det, (b * f - c * e) / det,
                   (f * g - d * i) / det, (a * i - c * g) / det, (c * d - a * f) / det,
                   (d * h - e * g) / det, (b * g - a * h) / det, (a * e - b * d) / det};
    for (int r = 0; r < 3; r++) {
        for (int k = 0; k < 3; k++) out[r * 4 + k] = L[r * 3 + k];
        out[r * 4 + 3] = -(L[r * 3] * m[3] + L[r * 3 + 1] * m[7] + L[r * 3 + 2] * m[11]);
    }
    return true;
}

int main(int argc, char** argv) {
    if (argc != 3) {
        fprintf(stderr, "usage: vdb_check FILE.vdb FILE.svo\n");
        return 2;
    }
    vx_error err = {0};
    vx_svo_scene s;
    uint8_t* data = NULL;
    size_t size = 0;
    vx_vdb_file* f = NULL;
    if (vx_svo_read_file(NULL, argv[2], &s, &err) || vx_file_read(argv[1], NULL, 0, &data, &size, &err) ||
        vx_vdb_read(data, size, &f, &err)) {
        fprintf(stderr, "vdb_check: %s\n", err.msg);
        return 1;
    }
    ctx c = {.f = f};
    if (!invert(s.world_from_grid, c.inv)) {
        fprintf(stderr, "vdb_check: world_from_grid is singular\n");
        return 1;
    }
    uint32_t n = vx_vdb_grid_count(f), density_grids = 0;
    vx_vdb_grid_info gi, ci;
    for (uint32_t i = 0; i < n && !c.bad; i++) {
        if (vx_vdb_grid_get_info(f, i, &gi, &err)) return fprintf(stderr, "vdb_check: %s\n", err.msg), 1;
        size_t len = strlen(gi.name);
        if (len < 7 || strcmp(gi.name + len - 7, "density") || (len > 7 && gi.name[len - 8] != '/')) continue;
        if (gi.value_type != VX_VDB_TYPE_FLOAT || gi.grid_class != VX_VDB_CLASS_FOG_VOLUME || !gi.linear) {
            fprintf(stderr, "vdb_check: grid '%s' is not a linear float fog volume\n", gi.name);
            return 1;
        }
        density_grids++;
        char want[160];
        snprintf(want, sizeof want, "%.*scolor", (int)(len - 7), gi.name);
        c.color = -1;
        for (uint32_t k = 0; k < n; k++)
            if (!vx_vdb_grid_get_info(f, k, &ci, &err) && !strcmp(ci.name, want)) {
                if (ci.value_type != VX_VDB_TYPE_VEC3F || memcmp(ci.index_to_world, gi.index_to_world, sizeof ci.index_to_world)) {
                    fprintf(stderr, "vdb_check: grid '%s' is not a vec3f grid with its density's transform\n", want);
                    return 1;
                }
                c.color = (int32_t)k;
            }
        c.itw = gi.index_to_world;
        uint64_t before = c.voxels;
        if (vx_vdb_iterate(f, i, VX_VDB_ITER_ACTIVE, visit, &c, &err))
            return fprintf(stderr, "vdb_check: %s\n", err.msg), 1;
        if (c.voxels - before != gi.active_voxels) {
            fprintf(stderr, "vdb_check: grid '%s': %llu voxels visited, OpenVDB counts %llu\n", gi.name,
                    (unsigned long long)(c.voxels - before), (unsigned long long)gi.active_voxels);
            return 1;
        }
    }
    if (c.bad) fprintf(stderr, "vdb_check: %s\n", c.bad == 1 ? "a tile where voxels were written" : "a density voxel without colour");
    fprintf(stderr, "vdb_check: %u density grids, %llu voxels\n", density_grids, (unsigned long long)c.voxels);
    vx_vdb_file_free(f);
    free(data);
    vx_svo_scene_free(&s);
    return c.bad ? 1 : 0;
}
