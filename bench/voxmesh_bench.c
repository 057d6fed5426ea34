/* bench/voxmesh_bench.c - greedy meshing of a whole .svo scene
 * (formats/voxmesh.h, what svo_info --to-glb meshes), issue 19's goal: the
 * 4096^3 DamagedHelmet in under 5 s on 2 cores.
 *
 *   voxmesh_bench SCENE.svo [--runs N]
 *
 * Per run: every model decoded into cell arrays (vx_svo_decode_model, Morton
 * order; models on all cores at once), then meshed one model after another
 * (each on all cores); prints the decode and mesh seconds (median of N runs),
 * the exposed faces (the quads of a naive mesh, one per face) and the greedy
 * quads. */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <stdatomic.h>
#include <time.h>
#include <unistd.h>

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

/* Models decoded by as many threads as there are cores, one model per job,
 * taken in turn. */
typedef struct decode_jobs {
    cells* c;
    uint32_t count;
    atomic_uint next;
    atomic_bool failed;
    vx_error err;
} decode_jobs;

static void* decode_worker(void* arg) {
    decode_jobs* j = (decode_jobs*)arg;
    for (;;) {
        uint32_t i = atomic_fetch_add(&j->next, 1);
        if (i >= j->count) return NULL;
        j->c[i].n = 0;
        vx_error e = {0};
        if (vx_svo_decode_model(j->c[i].m, add_cell, &j->c[i], &e) != VX_OK && !atomic_exchange(&j->failed, true))
            j->err = e;
    }
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
    cells* c = calloc(s.model_count ? s.model_count : 1, sizeof(cells));
    if (!c) return 1;
    for (uint32_t i = 0; i < s.model_count; i++) {
        const vx_svo_model* m = &s.models[i];
        c[i] = (cells){.s = &s, .m = m};
        c[i].xyz = malloc(3 * sizeof(uint32_t) * (m->voxel_count ? m->voxel_count : 1));
        c[i].rgba = malloc(sizeof(uint32_t) * (m->voxel_count ? m->voxel_count : 1));
        if (!c[i].xyz || !c[i].rgba) {
            fprintf(stderr, "voxmesh_bench: out of memory for %llu cells\n", (unsigned long long)m->voxel_count);
            return 1;
        }
    }
    for (int r = 0; r < runs; r++) {
        faces = quads = 0;
        /* decode: the models on every core at once */
        decode_jobs dj = {.c = c, .count = s.model_count};
        double t0 = vx_time_now();
        long cores = sysconf(_SC_NPROCESSORS_ONLN);
        vx_run_threads(cores < 1 ? 1u : (unsigned)cores < dj.count ? (unsigned)cores : dj.count, decode_worker, &dj);
        td[r] = vx_time_now() - t0;
        if (dj.failed) {
            fprintf(stderr, "voxmesh_bench: %s\n", dj.err.msg);
            return 1;
        }
        /* mesh: one model after another, each on every core */
        for (uint32_t i = 0; i < s.model_count; i++) {
            double t1 = vx_time_now(), c1 = cpu_now();
            vx_voxmesh vm;
            if (vx_voxmesh_build(NULL, c[i].xyz, c[i].rgba, c[i].n, &vm, &err) != VX_OK) {
                fprintf(stderr, "voxmesh_bench: model %u: %s\n", i, err.msg);
                return 1;
            }
            double t2 = vx_time_now(), c2 = cpu_now();
            tc[r] += c2 - c1;
            tm[r] += t2 - t1;
            faces += vm.faces;
            quads += vm.quad_count;
            vx_voxmesh_free(&vm);
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
    for (uint32_t i = 0; i < s.model_count; i++) {
        free(c[i].xyz);
        free(c[i].rgba);
    }
    free(c);
    vx_svo_scene_free(&s);
    return 0;
}
