/* bench/voxmesh_bench.c - greedy meshing of a whole .svo scene
 * (formats/voxmesh.h, what svo_info --to-glb meshes), issue 19's goal: the
 * 4096^3 DamagedHelmet in under 5 s on 2 cores.
 *
 *   voxmesh_bench SCENE.svo [--runs N]
 *
 * Per run: every model decoded into cell arrays (vx_svo_decode_model, Morton
 * order) and meshed; prints the decode and mesh seconds (median of N runs),
 * the exposed faces (the quads of a naive mesh, one per face) and the greedy
 * quads. */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bench/bench_stats.h"
#include "formats/voxmesh.h"
#include "svo/svo.h"

/* CPU seconds of the whole process (all threads): on a loaded machine the
 * wall clock says little, the CPU time still says what the work costs. */
static double cpu_now(void) {
    struct timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

typedef struct cells {
    const vx_svo_scene* s;
    const vx_svo_model* m;
    uint32_t *xyz, *rgba;
    size_t n;
} cells;

static bool add_cell(void* user, uint32_t x, uint32_t y, uint32_t z, uint32_t attr) {
    cells* c = (cells*)user;
    c->xyz[3 * c->n] = x, c->xyz[3 * c->n + 1] = y, c->xyz[3 * c->n + 2] = z;
    c->rgba[c->n++] = vx_svo_attr_rgba(c->s, c->m, attr);
    return true;
}

int main(int argc, char** argv) {
    if (argc < 2 || !strcmp(argv[1], "--help") || !strcmp(argv[1], "-h")) {
        printf("usage: voxmesh_bench SCENE.svo [--runs N]\n"
               "  decodes and greedy-meshes every model of SCENE (median of N runs, default 3)\n");
        return argc < 2;
    }
    int runs = 3;
    for (int i = 2; i < argc; i++) {
        if (!strcmp(argv[i], "--runs") && i + 1 < argc) runs = atoi(argv[++i]);
        else {
            fprintf(stderr, "voxmesh_bench: unknown option %s\n", argv[i]);
            return 1;
        }
    }
    if (runs < 1 || runs > 1000) {
        fprintf(stderr, "voxmesh_bench: --runs must be 1..1000\n");
        return 1;
    }
    vx_svo_scene s;
    vx_error err = {0};
    if (vx_svo_read_file(NULL, argv[1], &s, &err) != VX_OK) {
        fprintf(stderr, "voxmesh_bench: %s: %s\n", argv[1], err.msg);
        return 1;
    }
    uint64_t cells_total = 0;
    for (uint32_t i = 0; i < s.model_count; i++) cells_total += s.models[i].voxel_count;
    double* td = calloc((size_t)runs, sizeof(double));
    double* tm = calloc((size_t)runs, sizeof(double));
    double* tc = calloc((size_t)runs, sizeof(double));
    uint64_t faces = 0, quads = 0;
    for (int r = 0; r < runs; r++) {
        faces = quads = 0;
        for (uint32_t i = 0; i < s.model_count; i++) {
            const vx_svo_model* m = &s.models[i];
            cells c = {.s = &s, .m = m};
            c.xyz = malloc(3 * sizeof(uint32_t) * (m->voxel_count ? m->voxel_count : 1));
            c.rgba = malloc(sizeof(uint32_t) * (m->voxel_count ? m->voxel_count : 1));
            if (!c.xyz || !c.rgba) {
                fprintf(stderr, "voxmesh_bench: out of memory for %llu cells\n", (unsigned long long)m->voxel_count);
                return 1;
            }
            double t0 = vx_time_now();
            if (vx_svo_decode_model(m, add_cell, &c, &err) != VX_OK) {
                fprintf(stderr, "voxmesh_bench: model %u: %s\n", i, err.msg);
                return 1;
            }
            double t1 = vx_time_now(), c1 = cpu_now();
            vx_voxmesh vm;
            if (vx_voxmesh_build(NULL, c.xyz, c.rgba, c.n, &vm, &err) != VX_OK) {
                fprintf(stderr, "voxmesh_bench: model %u: %s\n", i, err.msg);
                return 1;
            }
            double t2 = vx_time_now(), c2 = cpu_now();
            tc[r] += c2 - c1;
            td[r] += t1 - t0;
            tm[r] += t2 - t1;
            faces += vm.faces;
            quads += vm.quad_count;
            vx_voxmesh_free(&vm);
            free(c.xyz);
            free(c.rgba);
        }
        fprintf(stderr, "run %d: decode %.3f s, mesh %.3f s (%.3f CPU s)\n", r + 1, td[r], tm[r], tc[r]);
    }
    double d = bench_median(td, runs), mm = bench_median(tm, runs), mc = bench_median(tc, runs);
    printf("%s: %u models, %llu cells: decode %.3f s, mesh %.3f s (%.3f CPU s), total %.3f s (median of %d); "
           "%llu exposed faces (naive quads), %llu greedy quads, %.2f faces per quad\n",
           argv[1], s.model_count, (unsigned long long)cells_total, d, mm, mc, d + mm, runs, (unsigned long long)faces,
           (unsigned long long)quads, quads ? (double)faces / (double)quads : 0.0);
    free(td);
    free(tm);
    free(tc);
    vx_svo_scene_free(&s);
    return 0;
}
