/* bench/svo_regions.c - a generated scene of many grid-aligned region models
 * (issue 18, the frame time with many instances): the models that `mpirun
 * vox2svo` makes of a mesh (2048^3 regions, each placed by a translated
 * instance), at a size that a bench command can generate on the GPU machine.
 *
 * The shape is a closed sphere shell (the cells whose centre lies within 1.5
 * cells inside the radius, so no ray leaks through), 0.45 of the extent in
 * radius, with RGBA colours that change every 4 cells (a texture-like
 * pattern, so that the DAG shares little, as in a textured mesh). With
 * --region equal to --res the same cells are one model: the same geometry as
 * the regions, for the ratio "many instances against one model". As the
 * converter's regions, each region model has the region's full size (its
 * world box is the region cube), and regions with no cell are left out.
 *
 * Usage: svo_regions OUT.svo [--res N] [--region R] [--threads T]
 *   N, R powers of two, 64 <= R <= N <= 16384 (defaults: 1024, 64)
 * Prints the models, instances and cells. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "svo/core.h"
#include "svo/svo.h"

typedef struct gen {
    uint32_t res, region, grid; /* grid: regions per side */
    double cx, r_out, r_in;
    vx_svo_model* models; /* one slot per region, root VX_SVO_ROOT_EMPTY where empty */
    volatile int failed;
    vx_error err;
} gen;

static uint32_t cell_rgba(uint32_t x, uint32_t y, uint32_t z) {
    uint32_t h = (x >> 2) * 73856093u ^ (y >> 2) * 19349663u ^ (z >> 2) * 83492791u;
    h ^= h >> 13, h *= 0x5bd1e995u, h ^= h >> 15;
    return 0xFF000000u | (h & 0x3F3F3Fu) | 0x808080u;
}

/* z range [lo, hi) of the shell's cells in column (x, y) on one side of the
 * centre (side +1 above, -1 below); empty when lo >= hi */
static void shell_span(const gen* g, uint32_t x, uint32_t y, int side, int64_t* lo, int64_t* hi) {
    double dx = x + 0.5 - g->cx, dy = y + 0.5 - g->cx, s = dx * dx + dy * dy;
    *lo = *hi = 0;
    if (s >= g->r_out * g->r_out) return;
    double a = g->r_in * g->r_in > s ? sqrt(g->r_in * g->r_in - s) : 0; /* |dz| >= a */
    double b = sqrt(g->r_out * g->r_out - s);                          /* |dz| < b */
    /* cell z has centre dz = z + 0.5 - cx (never 0: cx is an integer) */
    if (side > 0)
        *lo = (int64_t)ceil(g->cx + a - 0.5), *hi = (int64_t)ceil(g->cx + b - 0.5);
    else
        *lo = (int64_t)floor(g->cx - b - 0.5) + 1, *hi = (int64_t)floor(g->cx - a - 0.5) + 1;
}

static void build_region(void* ctx, unsigned thread, uint32_t i) {
    (void)thread;
    gen* g = ctx;
    if (g->failed) return;
    uint32_t R = g->region, G = g->grid;
    uint32_t rx = i % G, ry = (i / G) % G, rz = i / G / G;
    size_t n = 0, cap = 0;
    uint64_t* keys = NULL;
    uint32_t* rgba = NULL;
    for (uint32_t y = ry * R; y < (ry + 1) * R; y++)
        for (uint32_t x = rx * R; x < (rx + 1) * R; x++)
            for (int side = -1; side <= 1; side += 2) {
                int64_t lo, hi;
                shell_span(g, x, y, side, &lo, &hi);
                if (lo < (int64_t)rz * R) lo = (int64_t)rz * R;
                if (hi > (int64_t)(rz + 1) * R) hi = (int64_t)(rz + 1) * R;
                for (int64_t z = lo; z < hi; z++) {
                    if (n == cap) {
                        cap = cap ? 2 * cap : 4096;
                        uint64_t* k2 = realloc(keys, cap * sizeof *keys);
                        uint32_t* c2 = realloc(rgba, cap * sizeof *rgba);
                        if (k2) keys = k2;
                        if (c2) rgba = c2;
                        if (!k2 || !c2) {
                            g->failed = 1;
                            free(keys), free(rgba);
                            return;
                        }
                    }
                    keys[n] = vx_svo_morton(x - rx * R, y - ry * R, (uint32_t)z - rz * R);
                    rgba[n++] = cell_rgba(x, y, (uint32_t)z);
                }
            }
    g->models[i].root = VX_SVO_ROOT_EMPTY;
    if (n) {
        vx_svo_voxels v = {.size = {R, R, R}, .count = n, .keys = keys, .attrs = VX_ATTR_RGBA8, .rgba = rgba};
        vx_error e = {0};
        if (vx_svo_build_model(NULL, &v, &g->models[i], NULL, &e)) {
            g->err = e;
            g->failed = 1;
        }
    }
    free(keys), free(rgba);
}

static int pow2_arg(const char* s, uint32_t* out) {
    char* end;
    unsigned long v = strtoul(s, &end, 10);
    if (*end || v < 64 || v > 16384 || (v & (v - 1))) return 0;
    *out = (uint32_t)v;
    return 1;
}

int main(int argc, char** argv) {
    const char* out = NULL;
    gen g = {.res = 1024, .region = 64};
    unsigned threads = 0;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--res") && i + 1 < argc) {
            if (!pow2_arg(argv[++i], &g.res)) return fprintf(stderr, "svo_regions: bad --res %s\n", argv[i]), 2;
        } else if (!strcmp(argv[i], "--region") && i + 1 < argc) {
            if (!pow2_arg(argv[++i], &g.region)) return fprintf(stderr, "svo_regions: bad --region %s\n", argv[i]), 2;
        } else if (!strcmp(argv[i], "--threads") && i + 1 < argc) threads = (unsigned)atoi(argv[++i]);
        else if (argv[i][0] != '-' && !out) out = argv[i];
        else return fprintf(stderr, "usage: svo_regions OUT.svo [--res N] [--region R] [--threads T]\n"), 2;
    }
    if (!out || g.region > g.res) return fprintf(stderr, "usage: svo_regions OUT.svo [--res N] [--region R <= N]\n"), 2;
    if (!threads) threads = vx_cpu_count(64);
    g.grid = g.res / g.region;
    g.cx = g.res * 0.5, g.r_out = g.res * 0.45, g.r_in = g.r_out - 1.5;
    uint32_t nreg = g.grid * g.grid * g.grid;
    g.models = calloc(nreg, sizeof *g.models);
    if (!g.models) return fprintf(stderr, "svo_regions: out of memory\n"), 1;
    vx_run_jobs(threads, nreg, build_region, &g);
    if (g.failed) return fprintf(stderr, "svo_regions: %s\n", g.err.msg[0] ? g.err.msg : "out of memory"), 1;
    vx_svo_scene s;
    vx_svo_scene_init(&s, NULL);
    s.models = calloc(nreg, sizeof *s.models);
    s.instances = calloc(nreg, sizeof *s.instances);
    if (!s.models || !s.instances) return fprintf(stderr, "svo_regions: out of memory\n"), 1;
    uint64_t cells = 0;
    for (uint32_t i = 0; i < nreg; i++) {
        if (g.models[i].root == VX_SVO_ROOT_EMPTY) continue;
        uint32_t k = s.model_count++;
        s.models[k] = g.models[i];
        cells += g.models[i].voxel_count;
        vx_svo_instance* in = &s.instances[s.instance_count++];
        in->xform[0] = in->xform[5] = in->xform[10] = 1;
        in->xform[3] = (double)(i % g.grid) * g.region;
        in->xform[7] = (double)((i / g.grid) % g.grid) * g.region;
        in->xform[11] = (double)(i / g.grid / g.grid) * g.region;
        in->model = k;
        in->layer = UINT32_MAX;
    }
    free(g.models);
    vx_svo_scene_update_bounds(&s);
    vx_error err = {0};
    if (vx_svo_write_file(NULL, &s, out, &err)) {
        fprintf(stderr, "svo_regions: %s\n", err.msg);
        vx_svo_scene_free(&s);
        return 1;
    }
    printf("svo_regions: %s: sphere shell at %u^3, regions of %u^3: %u models, %u instances, %llu cells\n", out, g.res,
           g.region, s.model_count, s.instance_count, (unsigned long long)cells);
    vx_svo_scene_free(&s);
    return 0;
}
