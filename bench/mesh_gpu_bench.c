/* bench/mesh_gpu_bench.c - the mesh voxelizer on the GPU against the CPU
 * path, in one run: MESH.glb at each resolution, the CPU conversion
 * (vx_conv_mesh, every core) and the GPU one (vx_conv_mesh with the GPU
 * backend: voxelization and octree build on the GPU, --build below), medians
 * of timed runs after a warm-up, the stages (wall and GPU timestamps), the
 * scene's assembly, and whether the two .svo
 * files are equal byte for byte (the check of mesh_gpu_test, here on the
 * bench's device and resolutions).
 *
 *   mesh_gpu_bench MESH.glb [--res N]... [--runs N] [--cpu-runs N] [--warmups N] [--device D] [--cells] [--digest] [--solid]
 *
 * --digest: prints a 64-bit FNV-1a digest of the GPU path's scene (each
 * model's size, root, node words and attribute arrays, each instance's
 * transform): two builds of the same bytes print the same digest, without
 * writing a file (at 4096^3 the CPU path and the writer take minutes).
 * --warmups N: untimed runs first (default 1).
 * --cells: the GPU runs voxelize into a flat cell list (vx_conv_mesh_cells,
 * colours only) instead of building the octrees: the voxelizer's own time
 * at resolutions where the CPU builds would take most of a run.
 * --build gpu|cpu|check: who builds the octrees (vx_conv_mesh_gpu_set_build;
 * default gpu: the node words on the GPU (pools, representatives, attribute
 * runs, blocks), the CPU fills the records; gpu-pools: the CPU lays the
 * blocks out).
 * --solid: both paths fill the inside (the GPU path: the GPU voxelizes the
 * surface, the CPU votes, fills and builds, convert/mesh_gpu.h). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench/bench_stats.h"
#include "convert/mesh_gpu.h"
#include "render/render.h"

#define MAXRUNS 32

static uint64_t fnv(uint64_t h, const void* p, size_t n) {
    const unsigned char* c = (const unsigned char*)p;
    for (size_t i = 0; i < n; i++) h = (h ^ c[i]) * 0x100000001B3ull;
    return h;
}
static uint64_t scene_digest(const vx_svo_scene* s) {
    uint64_t h = 0xCBF29CE484222325ull;
    for (uint32_t i = 0; i < s->model_count; i++) {
        const vx_svo_model* m = &s->models[i];
        size_t na = m->attr_count;
        h = fnv(h, m->size, sizeof m->size);
        h = fnv(h, &m->root, sizeof m->root);
        h = fnv(h, &m->root_attr, sizeof m->root_attr);
        h = fnv(h, &m->attrs, sizeof m->attrs);
        h = fnv(h, m->nodes, (size_t)m->node_count * 4);
        if (m->palette) h = fnv(h, m->palette, na);
        if (m->rgba) h = fnv(h, m->rgba, na * 4);
        if (m->normal) h = fnv(h, m->normal, na * 4);
        if (m->material) h = fnv(h, m->material, na * 2);
        if (m->density) h = fnv(h, m->density, na * 4);
    }
    for (uint32_t i = 0; i < s->instance_count; i++) h = fnv(h, s->instances[i].xform, sizeof s->instances[i].xform);
    return h;
}

static size_t svo_bytes(const vx_svo_scene* s, uint8_t** out) {
    size_t n = 0;
    vx_error err = {0};
    if (vx_svo_write(s, NULL, out, &n, &err)) {
        fprintf(stderr, "write: %s\n", err.msg);
        *out = NULL;
        return 0;
    }
    return n;
}

int main(int argc, char** argv) {
    const char* path = NULL;
    const char* device = NULL;
    uint32_t res[8], nres = 0;
    int runs = 5, cpu_runs = 3, warmups = 1;
    bool cells_only = false, digest = false, solid = false;
    vx_conv_mesh_gpu_build build = VX_CONV_MESH_GPU_BUILD_GPU;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--res") && i + 1 < argc && nres < 8) res[nres++] = (uint32_t)atoi(argv[++i]);
        else if (!strcmp(argv[i], "--runs") && i + 1 < argc) runs = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--cpu-runs") && i + 1 < argc) cpu_runs = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--device") && i + 1 < argc) device = argv[++i];
        else if (!strcmp(argv[i], "--cells")) cells_only = true;
        else if (!strcmp(argv[i], "--digest")) digest = true;
        else if (!strcmp(argv[i], "--solid")) solid = true;
        else if (!strcmp(argv[i], "--warmups") && i + 1 < argc) warmups = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--build") && i + 1 < argc) {
            const char* b = argv[++i];
            if (!strcmp(b, "gpu")) build = VX_CONV_MESH_GPU_BUILD_GPU;
            else if (!strcmp(b, "cpu")) build = VX_CONV_MESH_GPU_BUILD_CPU;
            else if (!strcmp(b, "check")) build = VX_CONV_MESH_GPU_BUILD_CHECK;
            else if (!strcmp(b, "gpu-pools")) build = VX_CONV_MESH_GPU_BUILD_GPU_POOLS;
            else path = NULL, argc = 0; /* usage */
        }
        else path = argv[i];
    }
    if (!path) {
        fprintf(stderr, "usage: mesh_gpu_bench MESH.glb [--res N]... [--runs N] [--cpu-runs N] [--warmups N] [--device D] "
                        "[--cells] [--digest] [--solid] [--build gpu|gpu-pools|cpu|check]\n");
        return 2;
    }
    if (!nres) res[nres++] = 1024;
    if (runs < 1) runs = 1;
    if (runs > MAXRUNS) runs = MAXRUNS;
    if (cpu_runs > MAXRUNS) cpu_runs = MAXRUNS;
    vx_error err = {0};
    vx_gpu* gpu = NULL;
    vx_conv_mesh_gpu* mg = NULL;
    if (vx_gpu_create(&(vx_gpu_desc){.device = device}, &gpu, &err) || vx_conv_mesh_gpu_create(gpu, NULL, &mg, &err)) {
        fprintf(stderr, "GPU: %s\n", err.msg);
        return 1;
    }
    printf("device: %s\n", vx_gpu_device_name(gpu));
    vx_conv_mesh_gpu_set_build(mg, build);
    vx_gltf_mesh mesh;
    double t0 = vx_time_now();
    if (vx_conv_mesh_read(NULL, path, &mesh, &err)) {
        fprintf(stderr, "%s: %s\n", path, err.msg);
        return 1;
    }
    printf("%s: %zu triangles, read in %.3f s\n", path, mesh.tri_count, vx_time_now() - t0);
    int fail = 0;
    for (uint32_t ri = 0; ri < nres; ri++) {
        vx_conv_mesh_desc d = {.res = res[ri], .solid = solid};
        double cpu[MAXRUNS], gpu_t[MAXRUNS], st[10][MAXRUNS], asm_t[MAXRUNS], bg[8][MAXRUNS], vg[5][MAXRUNS];
        vx_svo_scene ref, got;
        memset(&ref, 0, sizeof ref);
        memset(&got, 0, sizeof got);
        vx_conv_stats cs = {0};
        for (int k = 0; k < cpu_runs; k++) {
            if (k) vx_svo_scene_free(&ref);
            t0 = vx_time_now();
            if (vx_conv_mesh(&d, &mesh, &ref, &cs, &err)) {
                fprintf(stderr, "CPU at %u: %s\n", res[ri], err.msg);
                return 1;
            }
            cpu[k] = vx_time_now() - t0;
        }
        d.backend = vx_conv_mesh_gpu_backend(mg);
        vx_conv_mesh_gpu_stats gs;
        for (int k = -warmups; k < runs; k++) { /* runs < 0: warm-up (buffers grown, pipelines made) */
            if (k >= 0 || got.model_count) vx_svo_scene_free(&got);
            t0 = vx_time_now();
            if (cells_only) {
                uint32_t *xyz = NULL, *rgba = NULL;
                size_t n = 0;
                if (vx_conv_mesh_cells(&d, &mesh, NULL, &xyz, &rgba, &n, &err)) {
                    fprintf(stderr, "GPU cells at %u: %s\n", res[ri], err.msg);
                    return 1;
                }
                free(xyz);
                free(rgba);
            } else { /* vx_conv_mesh's two steps, the assembly (scene, bounds) timed apart */
                vx_conv_mesh_part* parts = NULL;
                size_t np = 0;
                vx_result rr = vx_conv_mesh_share(&d, &mesh, 0, 1, &parts, &np, NULL, &err);
                double ta = vx_time_now();
                if (!rr) rr = vx_conv_mesh_assemble(&d, &mesh, parts, np, &got, NULL, &err);
                vx_conv_mesh_parts_free(NULL, parts, np);
                if (k >= 0) asm_t[k] = vx_time_now() - ta;
                if (rr) {
                    fprintf(stderr, "GPU at %u: %s\n", res[ri], err.msg);
                    return 1;
                }
            }
            double t = vx_time_now() - t0;
            vx_conv_mesh_gpu_last_stats(mg, &gs);
            if (k < 0) continue;
            gpu_t[k] = t;
            double v[10] = {gs.bin, gs.upload, gs.count, gs.emit, gs.sort, gs.reduce, gs.download, gs.sink, gs.intern, gs.build};
            for (int q = 0; q < 10; q++) st[q][k] = v[q];
            for (int q = 0; q < 8; q++) bg[q][k] = gs.build_gpu[q];
            for (int q = 0; q < 5; q++) vg[q][k] = gs.vox_gpu[q];
        }
        uint8_t *a = NULL, *b = NULL;
        bool compare = cpu_runs > 0 && !cells_only;
        size_t na = compare ? svo_bytes(&ref, &a) : 0, nb = compare ? svo_bytes(&got, &b) : 0;
        int equal = compare && na == nb && na && !memcmp(a, b, na);
        if (compare && !equal) fail = 1;
        double med[10];
        for (int q = 0; q < 10; q++) med[q] = bench_median(st[q], runs);
        double gpu_vox = med[1] + med[2] + med[3] + med[4] + med[5] + med[6];
        double cpu_med = cpu_runs > 0 ? bench_median(cpu, cpu_runs) : 0, gpu_med = bench_median(gpu_t, runs);
        printf("res %u: %llu pairs, %llu pieces, %llu cells, %u sort passes\n", res[ri], (unsigned long long)gs.pairs,
               (unsigned long long)gs.records, (unsigned long long)gs.cells, gs.sort_passes);
        printf("  CPU path (vx_conv_mesh, all cores): median %.1f ms of %d (voxelize %.1f + build %.1f ms, last run)\n",
               cpu_med * 1e3, cpu_runs, cs.seconds_voxelize * 1e3, cs.seconds_build * 1e3);
        printf("  GPU path: median %.1f ms of %d = bin (CPU) %.1f + upload %.1f + count %.1f + emit %.1f + sort %.1f + "
               "reduce %.1f + tuples interned %.1f + download %.1f + octree pools (GPU) %.1f + %s %.1f ms\n",
               gpu_med * 1e3, runs, med[0] * 1e3, med[1] * 1e3, med[2] * 1e3, med[3] * 1e3, med[4] * 1e3,
               med[5] * 1e3, med[8] * 1e3, med[6] * 1e3, med[9] * 1e3,
               cells_only ? "cell list (CPU)" : build == VX_CONV_MESH_GPU_BUILD_CPU ? "octree builds (CPU)" : "records and layout left (CPU)",
               med[7] * 1e3);
        {
            double v[5];
            for (int q = 0; q < 5; q++) v[q] = bench_median(vg[q], runs);
            printf("  voxelizer, GPU timestamps (medians): count (with the uploads' copies) %.2f, emit %.2f, sort %.2f, reduce "
                   "%.2f, tuples interned %.2f ms\n",
                   v[0] * 1e3, v[1] * 1e3, v[2] * 1e3, v[3] * 1e3, v[4] * 1e3);
        }
        if (!cells_only && build != VX_CONV_MESH_GPU_BUILD_CPU) {
            double b[8], sum = 0;
            for (int q = 0; q < 8; q++) sum += b[q] = bench_median(bg[q], runs);
            printf("  octree build, GPU timestamps (medians): levels %.2f + sharing %.2f + representatives %.2f + order sort %.2f "
                   "+ pool words %.2f + attribute runs %.2f + blocks %.2f (%u iterations) + copy down %.2f = %.2f ms of %.2f ms wall\n",
                   b[0] * 1e3, b[1] * 1e3, b[2] * 1e3, b[3] * 1e3, b[4] * 1e3, b[5] * 1e3, b[7] * 1e3, gs.layout_iterations,
                   b[6] * 1e3, sum * 1e3, med[9] * 1e3);
        }
        if (!cells_only)
            printf("  outside the stages: %.1f ms, of which the scene's assembly (models' bounds) %.1f ms\n",
                   (gpu_med - med[0] - gpu_vox - med[7] - med[8] - med[9]) * 1e3, bench_median(asm_t, runs) * 1e3);
        printf("  octree build (--build %s): %llu parents made on the GPU over %u levels, %llu distinct nodes, %llu pool "
               "words, %llu new representative tuples, %llu attribute records and %llu node words laid out%s\n",
               build == VX_CONV_MESH_GPU_BUILD_GPU         ? "gpu"
               : build == VX_CONV_MESH_GPU_BUILD_GPU_POOLS ? "gpu-pools"
               : build == VX_CONV_MESH_GPU_BUILD_CPU       ? "cpu"
                                                           : "check",
               (unsigned long long)gs.node_slots, gs.levels, (unsigned long long)gs.nodes, (unsigned long long)gs.pool_words,
               (unsigned long long)gs.rep_tuples, (unsigned long long)gs.run_records, (unsigned long long)gs.laid_words,
               gs.build_fallback ? "; FELL BACK to the CPU builders" : "");
        printf("  tuples interned for the builders: %llu distinct (per region) of %llu cells, %u sort passes\n",
               (unsigned long long)gs.tuples, (unsigned long long)gs.cells, gs.intern_passes);
        printf("  GPU voxelization alone (upload .. download, without the interning): %.1f ms; with the CPU binning "
               "%.1f ms\n", gpu_vox * 1e3, (gpu_vox + med[0]) * 1e3);
        if (digest && !cells_only)
            printf("  digest of the GPU path's scene: %016llx (%u models)\n", (unsigned long long)scene_digest(&got),
                   got.model_count);
        if (compare)
            printf("  .svo CPU %zu bytes, GPU %zu bytes: %s; speed-up of the whole conversion %.2fx\n", na, nb,
                   equal ? "EQUAL" : "DIFFERENT", cpu_med / gpu_med);
        free(a);
        free(b);
        vx_svo_scene_free(&ref);
        vx_svo_scene_free(&got);
        fflush(stdout);
    }
    vx_gltf_mesh_free(&mesh);
    vx_conv_mesh_gpu_destroy(mg);
    vx_gpu_destroy(gpu);
    return fail;
}
