/* bench/mesh_bench.c - mesh voxelization: conversion time, peak memory and
 * surface error against --res.
 *
 * Usage: mesh_bench FILE.glb RES [RES ...] [--normals] [--no-color] [--no-error]
 * Prints one line per resolution:
 *   file res voxels models seconds(read+voxelize+build) voxelize build peak_MiB mean_err max_err cube_miss
 * Surface error: N points sampled uniformly (by area) on the triangles; for
 * each, the distance (world units) to the centre of the nearest set cell,
 * searched among the 27 cells around it in the decoded scene (the cell
 * containing the point is always set by a conservative voxelization, so no
 * other cell can be nearer). cube_miss counts samples whose containing cell
 * is NOT set (must be 0). The conversion runs first, and the timing is taken
 * before the error pass allocates anything. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "convert/mesh.h"

typedef struct keys {
    uint64_t* k;
    size_t n, cap;
    const double* t;
} keys;

static bool collect(void* user, uint32_t x, uint32_t y, uint32_t z, uint32_t attr) {
    (void)attr;
    keys* s = (keys*)user;
    if (s->n == s->cap) {
        s->cap = s->cap ? 2 * s->cap : 1 << 20;
        s->k = (uint64_t*)realloc(s->k, s->cap * 8);
        if (!s->k) return false;
    }
    s->k[s->n++] = vx_svo_morton(x + (uint32_t)s->t[3], y + (uint32_t)s->t[7], z + (uint32_t)s->t[11]);
    return true;
}

static void radix(uint64_t* v, size_t n) {
    uint64_t* t = (uint64_t*)malloc(n * 8);
    uint64_t *s = v, *d = t;
    for (int sh = 0; sh < 64; sh += 16) {
        size_t* c = (size_t*)calloc(65536, sizeof *c);
        for (size_t i = 0; i < n; i++) c[(s[i] >> sh) & 0xFFFF]++;
        size_t sum = 0;
        for (int i = 0; i < 65536; i++) { size_t x = c[i]; c[i] = sum; sum += x; }
        for (size_t i = 0; i < n; i++) d[c[(s[i] >> sh) & 0xFFFF]++] = s[i];
        free(c);
        uint64_t* x = s; s = d; d = x;
    }
    free(t);
}

static bool has(const keys* s, int64_t x, int64_t y, int64_t z) {
    if (x < 0 || y < 0 || z < 0) return false;
    uint64_t k = vx_svo_morton((uint32_t)x, (uint32_t)y, (uint32_t)z);
    size_t lo = 0, hi = s->n;
    while (lo < hi) {
        size_t m = (lo + hi) / 2;
        if (s->k[m] < k) lo = m + 1;
        else hi = m;
    }
    return lo < s->n && s->k[lo] == k;
}

static uint64_t rs = 88172645463325252ull;
static double rnd(void) {
    rs ^= rs << 13; rs ^= rs >> 7; rs ^= rs << 17;
    return (double)(rs >> 11) / 9007199254740992.0;
}

int main(int argc, char** argv) {
    if (argc < 3) {
        fprintf(stderr, "usage: %s FILE RES [RES ...] [--normals] [--no-color] [--no-error]\n", argv[0]);
        return 2;
    }
    bool normals = false, no_color = false, no_error = false;
    for (int i = 2; i < argc; i++) {
        if (!strcmp(argv[i], "--normals")) normals = true;
        if (!strcmp(argv[i], "--no-color")) no_color = true;
        if (!strcmp(argv[i], "--no-error")) no_error = true;
    }
    const char* name = strrchr(argv[1], '/') ? strrchr(argv[1], '/') + 1 : argv[1];
    printf("# file res voxels models seconds voxelize build peak_MiB mean_err max_err cube_miss h\n");
    for (int i = 2; i < argc; i++) {
        if (argv[i][0] == '-') continue;
        uint32_t res = (uint32_t)atoi(argv[i]);
        vx_conv_mesh_desc d = {.res = res, .normals = normals, .no_color = no_color};
        vx_svo_scene s;
        vx_conv_stats st;
        vx_error err = {0};
        double t0 = vx_time_now();
        if (vx_conv_mesh_file(&d, argv[1], &s, &st, &err) != VX_OK) {
            fprintf(stderr, "%s: %s\n", argv[1], err.msg);
            return 1;
        }
        double secs = vx_time_now() - t0;
        uint64_t peak = vx_peak_rss();
        double mean = NAN, mx = NAN;
        size_t miss = 0;
        if (!no_error) {
            keys k = {0};
            for (uint32_t j = 0; j < s.instance_count; j++) {
                k.t = s.instances[j].xform;
                vx_svo_decode_model(&s.models[s.instances[j].model], collect, &k, NULL);
            }
            radix(k.k, k.n);
            vx_gltf_mesh m;
            vx_gltf_read_file(&(vx_gltf_read_desc){.no_images = true}, argv[1], &m, NULL);
            double h = s.world_from_grid[0], mn[3] = {s.world_from_grid[3], s.world_from_grid[7], s.world_from_grid[11]};
            /* area-weighted sampling: cumulative areas */
            double* cum = (double*)malloc(m.tri_count * sizeof *cum), tot = 0;
            for (size_t t = 0; t < m.tri_count; t++) {
                const float* p = m.pos + 9 * t;
                double e1[3], e2[3];
                for (int a = 0; a < 3; a++) { e1[a] = p[3 + a] - p[a]; e2[a] = p[6 + a] - p[a]; }
                double cx = e1[1] * e2[2] - e1[2] * e2[1], cy = e1[2] * e2[0] - e1[0] * e2[2], cz = e1[0] * e2[1] - e1[1] * e2[0];
                tot += 0.5 * sqrt(cx * cx + cy * cy + cz * cz);
                cum[t] = tot;
            }
            const int N = 200000;
            double sum = 0;
            mx = 0;
            for (int q = 0; q < N; q++) {
                double r = rnd() * tot;
                size_t lo = 0, hi = m.tri_count - 1;
                while (lo < hi) { size_t mid = (lo + hi) / 2; if (cum[mid] < r) lo = mid + 1; else hi = mid; }
                const float* p = m.pos + 9 * lo;
                double a = rnd(), b = rnd();
                if (a + b > 1) { a = 1 - a; b = 1 - b; }
                double g[3];
                for (int c = 0; c < 3; c++) g[c] = ((p[c] + a * (p[3 + c] - p[c]) + b * (p[6 + c] - p[c])) - mn[c]) / h;
                int64_t c0[3];
                for (int c = 0; c < 3; c++) {
                    c0[c] = (int64_t)floor(g[c]);
                    if (c0[c] >= (int64_t)(s.bounds_max[c])) c0[c] = (int64_t)s.bounds_max[c] - 1; /* max face */
                }
                if (!has(&k, c0[0], c0[1], c0[2])) miss++;
                double best = INFINITY;
                for (int dz = -1; dz <= 1; dz++)
                    for (int dy = -1; dy <= 1; dy++)
                        for (int dx = -1; dx <= 1; dx++) {
                            int64_t x = c0[0] + dx, y = c0[1] + dy, z = c0[2] + dz;
                            if (!has(&k, x, y, z)) continue;
                            double ex = x + 0.5 - g[0], ey = y + 0.5 - g[1], ez = z + 0.5 - g[2];
                            best = fmin(best, sqrt(ex * ex + ey * ey + ez * ez));
                        }
                best *= h;
                sum += best;
                mx = fmax(mx, best);
            }
            mean = sum / N;
            free(cum);
            free(k.k);
            vx_gltf_mesh_free(&m);
        }
        printf("%s %u %llu %u %.3f %.3f %.3f %.0f %.6g %.6g %zu %.6g\n", name, res,
               (unsigned long long)st.build.voxels, st.models, secs, st.seconds_voxelize,
               st.seconds_build, peak / 1048576.0, mean, mx, miss, s.world_from_grid[0]);
        fflush(stdout);
        vx_svo_scene_free(&s);
    }
    return 0;
}
