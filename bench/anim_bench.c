/* bench/anim_bench.c - animations (issue 24), docs/PERFORMANCE.md "Animation".
 *
 *   anim_bench [--frames N] [--res R] [--runs K] [--dir DIR] [--brick D] [--keep]
 *
 * Writes N frames of a generated smoke plume at R^3 (OpenVDB fog volumes
 * through the shim, formats/vdb.h: a column of value noise that rises one
 * cell per frame, density kept) into DIR, then converts (1) each frame alone
 * (vx_conv_vdb_file, the same options, regions as vox2svo makes them) and
 * (2) the whole sequence into one animation (vx_conv_vdb_sequence), K times
 * each, interleaved so that a change of the machine's load hits both alike.
 * It prints the median voxel rate of both (voxels converted per second,
 * reading included) by wall-clock time and by the process's CPU time (the
 * conversions are single-threaded: on a shared machine the CPU time does
 * not count the waits for a core), their ratios, and the bytes of the animation against
 * the largest single frame. A second sequence, the same smoke standing still
 * while a small puff moves, shows what frames that share most voxels cost.
 * --keep leaves the frames (DIR/smoke_####.vdb, DIR/puff_####.vdb) for
 * `vox2svo 'DIR/smoke_####.vdb' OUT.svo`. */
#define _POSIX_C_SOURCE 200809L /* mkdtemp */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "bench/bench_stats.h"
#include "convert/volume.h"
#include "formats/vdb.h"
#include "svo/svo.h"

static double hash3(int x, int y, int z) {
    uint32_t h = (uint32_t)x * 73856093u ^ (uint32_t)y * 19349663u ^ (uint32_t)z * 83492791u;
    h ^= h >> 13, h *= 0x5bd1e995u, h ^= h >> 15;
    return (h & 0xFFFFFF) / (double)0xFFFFFF;
}

/* Trilinear value noise with an 8-cell lattice, in [0, 1]. */
static double noise(double x, double y, double z) {
    int X = (int)floor(x / 8), Y = (int)floor(y / 8), Z = (int)floor(z / 8);
    double fx = x / 8 - X, fy = y / 8 - Y, fz = z / 8 - Z, v = 0;
    for (int c = 0; c < 8; c++) {
        double w = ((c & 1) ? fx : 1 - fx) * ((c & 2) ? fy : 1 - fy) * ((c & 4) ? fz : 1 - fz);
        v += w * hash3(X + (c & 1), Y + (c >> 1 & 1), Z + (c >> 2 & 1));
    }
    return v;
}

typedef struct cells {
    int32_t* ijk;
    float* value;
    size_t n, cap_ijk, cap_v;
} cells;

static void add(cells* c, int x, int y, int z, float v) {
    if (!vx_grow(NULL, (void**)&c->ijk, &c->cap_ijk, 3 * (c->n + 1), sizeof *c->ijk) ||
        !vx_grow(NULL, (void**)&c->value, &c->cap_v, c->n + 1, sizeof *c->value)) {
        fprintf(stderr, "anim_bench: out of memory\n");
        exit(1);
    }
    c->ijk[3 * c->n] = x, c->ijk[3 * c->n + 1] = y, c->ijk[3 * c->n + 2] = z;
    c->value[c->n++] = v;
}

/* Frame f of the plume: density in a cylinder of radius res/3 around the
 * vertical axis, noise advected upwards by `rise` cells per frame; cells
 * below 0.45 are left out. puff >= 0: a ball of radius res/16 at height
 * puff as well (its cells given last: they take the value 1). */
static void smoke(int res, int f, int rise, int puff, const char* path) {
    cells c = {0};
    double mid = res / 2.0, r2 = (res / 3.0) * (res / 3.0);
    for (int z = 0; z < res; z++)
        for (int y = 0; y < res; y++)
            for (int x = 0; x < res; x++) {
                double dx = x - mid, dy = y - mid, d2 = dx * dx + dy * dy;
                if (d2 > r2) continue;
                double v = noise(x, y, z - (double)rise * f) * (1.0 - d2 / r2) * 1.6;
                if (v > 0.45) add(&c, x, y, z, (float)(round(v * 64) / 64));
            }
    if (puff >= 0) {
        int R = res / 16, px = res / 8;
        for (int z = puff - R; z <= puff + R; z++)
            for (int y = px - R; y <= px + R; y++)
                for (int x = px - R; x <= px + R; x++)
                    if ((x - px) * (x - px) + (y - px) * (y - px) + (z - puff) * (z - puff) <= R * R) add(&c, x, y, z, 1.0f);
    }
    vx_vdb_write_grid g = {.name = "density", .value_type = VX_VDB_TYPE_FLOAT, .grid_class = VX_VDB_CLASS_FOG_VOLUME,
                           .index_to_world = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0}, .share = -1, .count = c.n,
                           .ijk = c.ijk, .value = c.value};
    vx_error err = {0};
    if (vx_vdb_write_file(NULL, &g, 1, path, &err) != VX_OK) {
        fprintf(stderr, "anim_bench: %s: %s\n", path, err.msg);
        exit(1);
    }
    free(c.ijk);
    free(c.value);
}

static double cpu_now(void) {
    struct timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static size_t svo_bytes(const vx_svo_scene* s) {
    uint8_t* d = NULL;
    size_t n = 0;
    vx_error e = {0};
    if (vx_svo_write(s, NULL, &d, &n, &e) != VX_OK) {
        fprintf(stderr, "anim_bench: write: %s\n", e.msg);
        exit(1);
    }
    free(d);
    return n;
}

typedef struct opts {
    int frames, res, runs, brick;
    bool keep;
} opts;

static void run(const char* what, const char* dir, const opts* o, int rise, bool puff) {
    const int frames = o->frames, res = o->res;
    char** names = (char**)calloc((size_t)frames, sizeof *names);
    double* t_single = (double*)calloc((size_t)o->runs, sizeof(double));
    double* t_seq = (double*)calloc((size_t)o->runs, sizeof(double));
    double* c_single = (double*)calloc((size_t)o->runs, sizeof(double));
    double* c_seq = (double*)calloc((size_t)o->runs, sizeof(double));
    if (!names || !t_single || !t_seq || !c_single || !c_seq) exit(1);
    double tg = vx_time_now();
    for (int f = 0; f < frames; f++) {
        size_t len = strlen(dir) + strlen(what) + 16;
        names[f] = (char*)malloc(len);
        if (!names[f]) exit(1);
        snprintf(names[f], len, "%s/%s_%04d.vdb", dir, what, f);
        smoke(res, f, rise, puff ? res / 8 + f * res / (frames + 8) : -1, names[f]);
    }
    tg = vx_time_now() - tg;
    vx_conv_vdb_desc d = {0};
    d.density = true;
    vx_conv_vdb_desc ds = d; /* the sequence's: bricks */
    ds.brick_depth = (uint32_t)o->brick;
    vx_error err = {0};
    uint64_t v1 = 0, vs = 0, largest_vox = 0, stored = 0;
    size_t largest = 0, bytes = 0;
    uint32_t models = 0, instances = 0;
    for (int k = 0; k < o->runs; k++) {
        /* every frame alone */
        t_single[k] = c_single[k] = 0, v1 = 0;
        for (int f = 0; f < frames; f++) {
            vx_svo_scene s;
            vx_conv_stats st = {0};
            double t0 = vx_time_now(), c0 = cpu_now();
            if (vx_conv_vdb_file(&d, names[f], &s, &st, &err) != VX_OK) {
                fprintf(stderr, "anim_bench: %s: %s\n", names[f], err.msg);
                exit(1);
            }
            t_single[k] += vx_time_now() - t0;
            c_single[k] += cpu_now() - c0;
            v1 += st.build.voxels;
            if (k == 0) {
                size_t b = svo_bytes(&s);
                if (b > largest) largest = b, largest_vox = st.build.voxels;
            }
            vx_svo_scene_free(&s);
        }
        /* the sequence */
        vx_svo_scene s;
        vx_conv_stats st = {0};
        double t0 = vx_time_now(), c0 = cpu_now();
        if (vx_conv_vdb_sequence(&ds, (const char* const*)names, (uint32_t)frames, &s, &st, &err) != VX_OK) {
            fprintf(stderr, "anim_bench: sequence: %s\n", err.msg);
            exit(1);
        }
        t_seq[k] = vx_time_now() - t0;
        c_seq[k] = cpu_now() - c0;
        vs = st.build.voxels;
        if (k == 0) {
            bytes = svo_bytes(&s);
            for (uint32_t m = 0; m < s.model_count; m++) stored += s.models[m].voxel_count;
            models = s.model_count, instances = s.instance_count;
        }
        vx_svo_scene_free(&s);
    }
    double m1 = bench_median(t_single, o->runs), ms = bench_median(t_seq, o->runs);
    double r1 = (double)v1 / m1, rs = (double)vs / ms;
    double mc1 = bench_median(c_single, o->runs), mcs = bench_median(c_seq, o->runs);
    printf("%-6s %d frames at %d^3 (written in %.1f s), medians of %d runs\n", what, frames, res, tg, o->runs);
    printf("  single frames   %.2f M voxels/s (%llu voxels in %.2f s)\n", r1 * 1e-6, (unsigned long long)v1, m1);
    printf("  sequence        %.2f M voxels/s (%llu voxels in %.2f s) = %.0f%% of the single-frame rate\n", rs * 1e-6,
           (unsigned long long)vs, ms, 100.0 * rs / r1);
    printf("  by CPU time     single frames %.2f M voxels/s (%.2f s), sequence %.2f M voxels/s (%.2f s) = %.0f%%\n",
           (double)v1 / mc1 * 1e-6, mc1, (double)vs / mcs * 1e-6, mcs, 100.0 * mc1 / mcs * (double)vs / (double)v1);
    printf("  bytes           animation %zu, largest frame %zu (%llu voxels): %.2fx; %u models, %u instances, %llu voxels "
           "stored of %llu\n",
           bytes, largest, (unsigned long long)largest_vox, (double)bytes / (double)largest, models, instances,
           (unsigned long long)stored, (unsigned long long)vs);
    fflush(stdout);
    for (int f = 0; f < frames; f++) {
        if (!o->keep) remove(names[f]);
        free(names[f]);
    }
    free(names);
    free(t_single);
    free(t_seq);
    free(c_single);
    free(c_seq);
}

int main(int argc, char** argv) {
    opts o = {.frames = 100, .res = 256, .runs = 3, .brick = 0, .keep = false};
    const char* dir = "/tmp";
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--frames") && i + 1 < argc) o.frames = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--res") && i + 1 < argc) o.res = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--runs") && i + 1 < argc) o.runs = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--dir") && i + 1 < argc) dir = argv[++i];
        else if (!strcmp(argv[i], "--brick") && i + 1 < argc) o.brick = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--keep")) o.keep = true;
        else {
            fprintf(stderr,
                    "usage: %s [--frames N (100)] [--res R (256)] [--runs K (3)] [--dir DIR (/tmp)] [--brick D (%u)] "
                    "[--keep]\n",
                    argv[0], VX_CONV_VDB_SEQUENCE_BRICK_DEPTH);
            return 2;
        }
    }
    if (o.frames < 1 || o.res < 16 || o.runs < 1 || o.brick < 0 || o.brick > 21) {
        fprintf(stderr, "%s: need --frames >= 1, --res >= 16, --runs >= 1, --brick 0..21\n", argv[0]);
        return 2;
    }
    size_t len = strlen(dir) + 32;
    char* tmpl = (char*)malloc(len);
    if (!tmpl) return 1;
    snprintf(tmpl, len, "%s/anim_benchXXXXXX", dir);
    if (!mkdtemp(tmpl)) {
        perror(tmpl);
        return 1;
    }
    run("smoke", tmpl, &o, 1, false);
    run("puff", tmpl, &o, 0, true);
    if (o.keep) printf("frames kept in %s\n", tmpl);
    else rmdir(tmpl);
    free(tmpl);
    return 0;
}
