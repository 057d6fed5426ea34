/* bench/svo_build_bench.c - builds a large generated scene (a noisy terrain
 * surface with height-banded colours) and prints input voxels/s, peak RSS
 * per input voxel, descriptors per minimization stage and bytes per voxel.
 *
 * Usage: svo_build_bench [-e EXTENT] [-t THICKNESS] [-geom] [-no-collapse] [-no-dag] [-o FILE.svo [-chunked]]
 *   -chunked: the file in the chunked NODE form (vx_write_desc.svo_chunk_words, FORMAT.md 3.6)
 *   default: -e 4096 -t 6 (about 100M voxels; -e 256 -t 3 is about 200k). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "svo/svo.h"

static uint32_t hash2(uint32_t x, uint32_t z, uint32_t seed) {
    uint32_t h = x * 0x8da6b343u ^ z * 0xd8163841u ^ seed * 0xcb1ab31fu;
    h ^= h >> 13;
    h *= 0x5bd1e995u;
    h ^= h >> 15;
    return h;
}
static float vnoise(float x, float z, uint32_t seed) {
    int xi = (int)floorf(x), zi = (int)floorf(z);
    float fx = x - (float)xi, fz = z - (float)zi;
    fx = fx * fx * (3 - 2 * fx);
    fz = fz * fz * (3 - 2 * fz);
    float a = (float)(hash2((uint32_t)xi, (uint32_t)zi, seed) & 0xFFFF) / 65535.0f;
    float b = (float)(hash2((uint32_t)xi + 1, (uint32_t)zi, seed) & 0xFFFF) / 65535.0f;
    float c = (float)(hash2((uint32_t)xi, (uint32_t)zi + 1, seed) & 0xFFFF) / 65535.0f;
    float d = (float)(hash2((uint32_t)xi + 1, (uint32_t)zi + 1, seed) & 0xFFFF) / 65535.0f;
    return (a + (b - a) * fx) + ((c + (d - c) * fx) - (a + (b - a) * fx)) * fz;
}

int main(int argc, char** argv) {
    uint32_t E = 4096, T = 6;
    bool geom = false;
    const char* out_path = NULL; /* -o FILE: also time writing and reading the .svo file */
    bool chunked = false;
    vx_svo_build_desc desc = {0};
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "-e") && i + 1 < argc) E = (uint32_t)atoi(argv[++i]);
        else if (!strcmp(argv[i], "-t") && i + 1 < argc) T = (uint32_t)atoi(argv[++i]);
        else if (!strcmp(argv[i], "-geom")) geom = true;
        else if (!strcmp(argv[i], "-no-collapse")) desc.no_collapse = true;
        else if (!strcmp(argv[i], "-no-dag")) desc.no_dag = true;
        else if (!strcmp(argv[i], "-o") && i + 1 < argc) out_path = argv[++i];
        else if (!strcmp(argv[i], "-chunked")) chunked = true;
        else {
            fprintf(stderr, "usage: %s [-e EXTENT] [-t THICKNESS] [-geom] [-no-collapse] [-no-dag] [-o FILE.svo [-chunked]]\n", argv[0]);
            return 2;
        }
    }
    if (E < 16 || E > (1u << 20) || T < 1 || T > E / 4) {
        fprintf(stderr, "svo_build_bench: extent 16..2^20 and thickness 1..extent/4\n");
        return 2;
    }
    uint32_t H = E / 4; /* terrain height range */
    size_t cap = (size_t)E * E * T, n = 0;
    uint64_t* keys = (uint64_t*)malloc(cap * sizeof *keys);
    uint32_t* rgba = geom ? NULL : (uint32_t*)malloc(cap * sizeof *rgba);
    if (!keys || (!geom && !rgba)) {
        fprintf(stderr, "svo_build_bench: out of memory for %zu voxels\n", cap);
        return 1;
    }
    static const uint32_t bands[6] = {0xFF3A6E1Fu, 0xFF2F8F3Fu, 0xFF4A6A8Au, 0xFF7A7A7Au, 0xFFB0B0B0u, 0xFFF0F0F0u};
    double tg = vx_time_now();
    /* scan order (x fastest): the builder has to sort */
    for (uint32_t z = 0; z < E; z++)
        for (uint32_t x = 0; x < E; x++) {
            float f = 0, amp = 0.5f, fr = 1.0f / 256.0f;
            for (int o = 0; o < 5; o++, amp *= 0.5f, fr *= 2.0f) f += amp * vnoise((float)x * fr * (E / 1024.0f > 1 ? 1024.0f / E * 4 : 4), (float)z * fr * 4, (uint32_t)o);
            uint32_t h = (uint32_t)(f * (float)(H - T - 1)) + T;
            uint32_t band = h * 6 / H;
            for (uint32_t y = h - T + 1; y <= h; y++) {
                keys[n] = vx_svo_morton(x, y, z);
                if (rgba) {
                    uint32_t c = bands[band > 5 ? 5 : band];
                    if (y < h) c = (c & 0xFF000000u) | ((c & 0x00FEFEFEu) >> 1); /* darker below the top */
                    rgba[n] = c;
                }
                n++;
            }
        }
    tg = vx_time_now() - tg;
    vx_svo_voxels in = {.size = {E, H, E}, .count = n, .keys = keys, .attrs = geom ? 0 : VX_ATTR_RGBA8, .rgba = rgba};
    vx_svo_model m;
    vx_svo_build_stats st;
    vx_error err;
    double t0 = vx_time_now();
    clock_t c0 = clock(); /* CPU time too: the machine is shared, wall time is noisy */
    vx_result r = vx_svo_build_model(&desc, &in, &m, &st, &err);
    double t = vx_time_now() - t0, tc = (double)(clock() - c0) / CLOCKS_PER_SEC;
    if (r != VX_OK) {
        fprintf(stderr, "svo_build_bench: %s\n", err.msg);
        return 1;
    }
    uint64_t rss = vx_peak_rss();
    printf("scene: terrain %ux%ux%u, thickness %u, %s, generated in %.2f s\n", E, H, E, T, geom ? "geometry only" : "RGBA8",
           tg);
    printf("input voxels:     %llu (%llu distinct)\n", (unsigned long long)st.input_voxels, (unsigned long long)st.voxels);
    printf("build time:       %.3f s wall = %.2f M input voxels/s; %.3f s CPU = %.2f M/s\n", t, (double)n / t / 1e6, tc,
           (double)n / tc / 1e6);
    printf("peak RSS:         %.1f MiB = %.2f bytes per input voxel (input arrays alone: %u)\n", (double)rss / 1048576.0,
           (double)rss / (double)n, geom ? 8 : 12);
    printf("descriptors:      plain %llu, collapsed %llu, dag %llu, far pointers %llu\n", (unsigned long long)st.desc_plain,
           (unsigned long long)st.desc_collapsed, (unsigned long long)st.desc_dag, (unsigned long long)st.far_pointers);
    printf("records:          %llu; node words %u\n", (unsigned long long)st.attr_records, m.node_count);
    printf("in memory:        %llu bytes = %.3f bytes per voxel\n", (unsigned long long)st.bytes, (double)st.bytes / (double)st.voxels);
    if (out_path) {
        /* the whole scene through the file: write (validate + code) and read back */
        vx_svo_scene sc;
        vx_svo_scene_init(&sc, NULL);
        vx_svo_instance inst = {.xform = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0}, .model = 0, .layer = UINT32_MAX};
        sc.model_count = 1;
        sc.models = &m;
        sc.instance_count = 1;
        sc.instances = &inst;
        vx_svo_scene_update_bounds(&sc);
        double w0 = vx_time_now();
        r = vx_svo_write_file(&(vx_write_desc){.svo_chunk_words = chunked ? VX_SVO_CHUNK_WORDS : 0}, &sc, out_path, &err);
        double tw = vx_time_now() - w0;
        if (r != VX_OK) {
            fprintf(stderr, "svo_build_bench: %s: %s\n", out_path, err.msg);
            return 1;
        }
        vx_svo_scene back;
        double r0 = vx_time_now();
        r = vx_svo_read_file(NULL, out_path, &back, &err);
        double tr = vx_time_now() - r0;
        if (r != VX_OK) {
            fprintf(stderr, "svo_build_bench: reading %s: %s\n", out_path, err.msg);
            return 1;
        }
        FILE* f = fopen(out_path, "rb");
        long fsz = 0;
        if (f) {
            fseek(f, 0, SEEK_END);
            fsz = ftell(f);
            fclose(f);
        }
        printf("file:             %ld bytes = %.3f bytes per voxel; write %.2f s, read %.2f s\n", fsz,
               (double)fsz / (double)st.voxels, tw, tr);
        vx_svo_scene_free(&back);
    }
    vx_svo_model_free(NULL, &m);
    free(keys);
    free(rgba);
    return 0;
}
