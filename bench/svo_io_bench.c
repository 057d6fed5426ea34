/* bench/svo_io_bench.c - .svo read and write speed (issue 18: file I/O at
 * disk speed). Reads FILE.svo once into memory, then times, for each thread
 * count given, the parse of the in-memory bytes (vx_svo_read), the whole
 * read from the file (vx_svo_read_file), the coding into memory
 * (vx_svo_write) and the whole write of a file (vx_svo_write_file: scratch,
 * copy, fsync, rename). Wall time and process CPU time, medians of --runs;
 * every write is compared with the first (the bytes may not depend on the
 * thread count).
 *
 * With --chunked the writes use the chunked NODE form (FORMAT.md 3.6,
 * vx_write_desc.svo_chunk_words = VX_SVO_CHUNK_WORDS), and the reads time
 * that form too: a file older than version 3 is first written chunked (to
 * DIR) and the reads time those bytes, so it needs no separate conversion.
 * --stored: the same with the chunks stored, not deflated
 * (vx_write_desc.svo_chunk_stored; the input is always re-coded).
 * --fast: the same with the word chunks stored, the record chunks deflated
 * (vx_write_desc.svo_chunk_fast).
 * --deflate: the chunks DEFLATEd at level 1 (format version 3,
 * vx_write_desc.svo_chunk_deflate) instead of zstd (version 4, the default).
 * --convert OUT.svo only writes the chunked copy of FILE (in the form the
 * flags above choose) and exits; --write-as OUT.svo the same in the form the
 * flags give without --chunked too (the default: large models in the split
 * form of version 5, with attributes its runs stream of version 6).
 * --compare OTHER.svo only reads FILE and OTHER (vx_svo_read_file each) and
 * compares their models word for word and record for record (exit 0 when
 * every model is equal, 3 when one differs): the same scene in two forms.
 * With --threads N, --convert's, --write-as' and --compare's reads run on
 * N threads (else every CPU): N 1 takes the reader's one-thread path (the
 * layout fused into the reconstruction), so two processes' chunked copies
 * (cmp) compare the paths' words and records across binaries.
 * --range: the writes (and --write-as) keep large structural models in the
 * range-coded form of versions 1 and 2 (vx_write_desc.svo_range_coded).
 * --no-checks: the writes get the scene without the reader's checks
 * (vx_svo_model.check cleared), so they validate every model as the write of
 * a scene just built does (vox2svo).
 *
 * --pin CPUS (e.g. 0,1): the timed steps run on those CPUs only (the
 * process is pinned after the untimed read that gives a write its scene, so
 * that read takes every core: on two cores it took as long as the timed
 * steps of the 4096^3 helmet; `taskset -c 0,1` pins the whole process).
 *
 * Usage: svo_io_bench FILE.svo [--runs N] [--threads 1,2] [--out DIR] [--only read|write|readfile|writefile] [--chunked] [--no-checks] [--pin CPUS]
 * (readfile / writefile: only vx_svo_read_file / vx_svo_write_file) */
#define _GNU_SOURCE /* sched_setaffinity */
#include <sched.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <unistd.h>

#include "bench_stats.h"
#include "svo/svo.h"

static double cpu_now(void) {
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    return (double)ru.ru_utime.tv_sec + (double)ru.ru_stime.tv_sec + 1e-6 * (double)(ru.ru_utime.tv_usec + ru.ru_stime.tv_usec);
}

/* the rusage of a timed step, so that two machines' runs can be told apart by
 * where the time went (user or kernel, page faults, switches) */
typedef struct {
    double user, sys;
    long minflt, majflt, nvcsw, nivcsw;
} ru_snap;

static ru_snap ru_now(void) {
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    return (ru_snap){(double)ru.ru_utime.tv_sec + 1e-6 * (double)ru.ru_utime.tv_usec, (double)ru.ru_stime.tv_sec + 1e-6 * (double)ru.ru_stime.tv_usec,
                     ru.ru_minflt, ru.ru_majflt, ru.ru_nvcsw, ru.ru_nivcsw};
}

static void ru_print(const char* step, int run, ru_snap a) {
    ru_snap b = ru_now();
    printf("  run %d, %s rusage: user %.3f s, sys %.3f s, minor faults %ld, major %ld, switches %ld voluntary %ld involuntary\n", run, step,
           b.user - a.user, b.sys - a.sys, b.minflt - a.minflt, b.majflt - a.majflt, b.nvcsw - a.nvcsw, b.nivcsw - a.nivcsw);
}

static void die(const char* what, const vx_error* e) {
    fprintf(stderr, "svo_io_bench: %s: %s\n", what, e->msg);
    exit(1);
}

static void print_counts(const char* path, size_t size, const vx_svo_scene* sc) {
    uint64_t words = 0, recs = 0, vox = 0;
    for (uint32_t i = 0; i < sc->model_count; i++) {
        words += sc->models[i].node_count;
        recs += sc->models[i].attr_count;
        vox += sc->models[i].voxel_count;
    }
    printf("file %s: %zu bytes, %u models, %llu voxels, %llu node words, %llu records\n", path, size, sc->model_count,
           (unsigned long long)vox, (unsigned long long)words, (unsigned long long)recs);
    fflush(stdout);
}

/* --compare: every model of a equal to b's, words and records */
static int compare_files(const char* pa, const char* pb, unsigned threads) {
    vx_svo_scene a, b;
    vx_error e;
    vx_svo_read_desc rd = {.threads = threads};
    double t0 = vx_time_now();
    if (vx_svo_read_file(&rd, pa, &a, &e) != VX_OK) die(pa, &e);
    double t1 = vx_time_now();
    if (vx_svo_read_file(&rd, pb, &b, &e) != VX_OK) die(pb, &e);
    double t2 = vx_time_now();
    printf("compare: read %s in %.2f s, %s in %.2f s\n", pa, t1 - t0, pb, t2 - t1);
    int bad = a.model_count != b.model_count;
    for (uint32_t i = 0; i < a.model_count && !bad; i++) {
        const vx_svo_model *x = &a.models[i], *y = &b.models[i];
        size_t n = x->attr_count;
        const char* why = x->node_count != y->node_count || x->root != y->root || x->root_attr != y->root_attr || x->attr_count != y->attr_count ||
                                  x->attrs != y->attrs || x->voxel_count != y->voxel_count
                              ? "counts"
                          : x->node_count && memcmp(x->nodes, y->nodes, (size_t)x->node_count * 4) ? "words"
                          : n && x->palette && memcmp(x->palette, y->palette, n) ? "palette"
                          : n && x->rgba && memcmp(x->rgba, y->rgba, n * 4) ? "rgba8"
                          : n && x->normal && memcmp(x->normal, y->normal, n * 4) ? "normals"
                          : n && x->material && memcmp(x->material, y->material, n * 2) ? "material"
                          : n && x->density && memcmp(x->density, y->density, n * 4) ? "density"
                                                                                      : NULL;
        if (why) printf("compare: model %u differs (%s)\n", i, why), bad = 1;
    }
    if (!bad) printf("compare: all %u models equal (words and records)\n", a.model_count);
    vx_svo_scene_free(&a);
    vx_svo_scene_free(&b);
    return bad ? 3 : 0;
}

int main(int argc, char** argv) {
    const char* path = NULL;
    const char* out_dir = "/tmp";
    const char* only = "";
    bool chunked = false, stored = false, fast = false, deflate = false, no_checks = false;
    const char* convert = NULL;
    const char* compare = NULL;
    bool write_as = false, range = false; /* --write-as: --convert in the form the options give; --range: svo_range_coded */
    int runs = 3;
    const char* pin = NULL; /* --pin: CPUs of the timed steps */
    unsigned threads[8] = {1, 2};
    int nt = 2;
    bool threads_given = false; /* --threads: also the threads of --convert's and --compare's reads (default: every CPU) */
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--runs") && i + 1 < argc) runs = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--out") && i + 1 < argc) out_dir = argv[++i];
        else if (!strcmp(argv[i], "--only") && i + 1 < argc) only = argv[++i];
        else if (!strcmp(argv[i], "--chunked")) chunked = true;
        else if (!strcmp(argv[i], "--stored")) chunked = stored = true;
        else if (!strcmp(argv[i], "--fast")) chunked = fast = true;
        else if (!strcmp(argv[i], "--deflate")) chunked = deflate = true;
        else if (!strcmp(argv[i], "--no-checks")) no_checks = true;
        else if (!strcmp(argv[i], "--convert") && i + 1 < argc) convert = argv[++i];
        else if (!strcmp(argv[i], "--write-as") && i + 1 < argc) convert = argv[++i], write_as = true;
        else if (!strcmp(argv[i], "--range")) range = true;
        else if (!strcmp(argv[i], "--compare") && i + 1 < argc) compare = argv[++i];
        else if (!strcmp(argv[i], "--pin") && i + 1 < argc) pin = argv[++i];
        else if (!strcmp(argv[i], "--threads") && i + 1 < argc) {
            nt = 0;
            threads_given = true;
            for (char* s = argv[++i]; *s && nt < 8;) {
                threads[nt++] = (unsigned)strtoul(s, &s, 10);
                if (*s == ',') s++;
            }
        } else if (argv[i][0] != '-' && !path) path = argv[i];
        else {
            fprintf(stderr, "usage: svo_io_bench FILE.svo [--runs N] [--threads 1,2] [--out DIR] [--only read|write|readfile|writefile] [--chunked | --stored | --fast | --deflate] [--range] [--no-checks] [--pin CPUS] [--convert OUT.svo | --write-as OUT.svo | --compare OTHER.svo]\n");
            return 2;
        }
    }
    if (!path || runs < 1 || runs > 99) {
        fprintf(stderr, "usage: svo_io_bench FILE.svo [--runs N] [--threads 1,2] [--out DIR] [--only read|write|readfile|writefile] [--chunked | --stored | --fast | --deflate] [--range] [--no-checks] [--pin CPUS] [--convert OUT.svo | --write-as OUT.svo | --compare OTHER.svo]\n");
        return 2;
    }
    vx_error err;
    if (compare) return compare_files(path, compare, threads_given ? threads[0] : 0);
    uint8_t* data = NULL;
    size_t size = 0;
    if (vx_file_read(path, NULL, UINT64_MAX, &data, &size, &err) != VX_OK) die(path, &err);
    const uint32_t chunk_words = chunked ? VX_SVO_CHUNK_WORDS : 0;
    /* a file of version 3 (byte 8, u16) has its large models chunked already */
    const bool do_read = strcmp(only, "write") && strcmp(only, "writefile"), do_write = strcmp(only, "read") && strcmp(only, "readfile");
    /* only timed reads need the input in the form written (writes code the scene in memory) */
    bool recode = do_read && (stored || fast || deflate || (chunked && !(size >= 10 && (data[8] | data[9] << 8) >= 3)));
    /* the scene in memory is only needed to write: with --only read the
     * first timed read gives the counts (on two cores an untimed read of the
     * 4096^3 helmet took as long as the timed ones) */
    /* --only readfile / writefile: only the whole-file step of the two */
    const bool file_only = !strcmp(only, "readfile") || !strcmp(only, "writefile");
    bool lazy = !do_write && !recode && !convert;
    vx_svo_scene sc;
    memset(&sc, 0, sizeof sc);
    if (!lazy) {
        vx_svo_read_desc rd = {.threads = threads_given ? threads[0] : 0};
        if (vx_svo_read(&rd, data, size, &sc, &err) != VX_OK) die(path, &err);
        print_counts(path, size, &sc);
    }
    if (convert) {
        /* --convert: only write the chunked copy (every thread), for later --chunked runs */
        double t0 = vx_time_now();
        vx_write_desc cd = {.svo_chunk_words = write_as ? chunk_words : VX_SVO_CHUNK_WORDS, .svo_chunk_stored = stored, .svo_chunk_fast = fast,
                            .svo_chunk_deflate = deflate, .svo_range_coded = range};
        if (vx_svo_write_file(&cd, &sc, convert, &err) != VX_OK) die(convert, &err);
        printf("wrote %s in the %s form in %.2f s\n", convert, cd.svo_chunk_words ? "chunked" : range ? "range-coded" : "default", vx_time_now() - t0);
        vx_svo_scene_free(&sc);
        vx_free(NULL, data);
        return 0;
    }
    char out_path[4096], in_path[4096];
    snprintf(out_path, sizeof out_path, "%s/svo_io_bench.%ld.svo", out_dir, (long)getpid());
    snprintf(in_path, sizeof in_path, "%s/svo_io_bench.%ld.in.svo", out_dir, (long)getpid());
    if (recode) {
        /* the reads time the chunked form: write it once (all threads) and read those bytes */
        double t0 = vx_time_now();
        if (vx_svo_write_file(&(vx_write_desc){.svo_chunk_words = chunk_words, .svo_chunk_stored = stored, .svo_chunk_fast = fast,
                                                 .svo_chunk_deflate = deflate},
                              &sc,
                              in_path, &err) != VX_OK)
            die(in_path, &err);
        vx_free(NULL, data);
        data = NULL;
        if (vx_file_read(in_path, NULL, UINT64_MAX, &data, &size, &err) != VX_OK) die(in_path, &err);
        vx_svo_scene_free(&sc);
        if (vx_svo_read(NULL, data, size, &sc, &err) != VX_OK) die(in_path, &err);
        path = in_path;
        printf("chunked copy %s: %zu bytes (written in %.2f s)\n", in_path, size, vx_time_now() - t0);
        fflush(stdout);
    }
    for (uint32_t i = 0; no_checks && i < sc.model_count; i++) memset(&sc.models[i].check, 0, sizeof sc.models[i].check);
    if (pin) { /* threads started from here on inherit the set (the library starts its own per call) */
        cpu_set_t set;
        CPU_ZERO(&set);
        unsigned n = 0;
        for (char* s = (char*)pin; *s;) {
            char* e;
            unsigned long c = strtoul(s, &e, 10);
            if (e == s || c >= CPU_SETSIZE) {
                fprintf(stderr, "svo_io_bench: --pin %s: a list of CPU numbers (0,1)\n", pin);
                return 2;
            }
            CPU_SET((int)c, &set);
            n++;
            s = *e == ',' ? e + 1 : e;
        }
        if (sched_setaffinity(0, sizeof set, &set) != 0) {
            perror("svo_io_bench: --pin");
            return 1;
        }
        printf("timed steps pinned to %u CPUs (%s)\n", n, pin);
    }
    uint8_t* first = NULL;
    size_t first_n = 0;
    printf("%-8s %-28s %10s %10s %10s\n", "threads", "step", "wall s", "cpu s", "MB/s");
    for (int ti = 0; ti < nt; ti++) {
        double w[4][99], c[4][99];
        for (int k = 0; k < runs; k++) {
            double t0, c0;
            if (do_read) {
                vx_svo_read_desc rd = {.threads = threads[ti]};
                vx_svo_scene b;
                w[0][k] = c[0][k] = 0;
                if (!file_only) {
                    t0 = vx_time_now(), c0 = cpu_now();
                    if (vx_svo_read(&rd, data, size, &b, &err) != VX_OK) die("read", &err);
                    w[0][k] = vx_time_now() - t0, c[0][k] = cpu_now() - c0;
                    vx_svo_scene_free(&b);
                }
                ru_snap r0 = ru_now();
                t0 = vx_time_now(), c0 = cpu_now();
                if (vx_svo_read_file(&rd, path, &b, &err) != VX_OK) die("read file", &err);
                w[1][k] = vx_time_now() - t0, c[1][k] = cpu_now() - c0;
                ru_print("read file", k, r0);
                if (lazy && ti == 0 && k == 0) print_counts(path, size, &b);
                vx_svo_scene_free(&b);
                /* each run as it ends too (a run cut short by a timeout still reports) */
                printf("  run %d, %u threads: read (memory) %.3f s wall %.3f s CPU, read file %.3f s wall %.3f s CPU\n", k,
                       threads[ti], w[0][k], c[0][k], w[1][k], c[1][k]);
                fflush(stdout);
            }
            if (do_write) {
                vx_write_desc wd = {.threads = threads[ti], .svo_chunk_words = chunk_words, .svo_chunk_stored = stored, .svo_chunk_fast = fast,
                                    .svo_chunk_deflate = deflate, .svo_range_coded = range};
                w[2][k] = c[2][k] = 0;
                if (!file_only) {
                    uint8_t* o = NULL;
                    size_t on = 0;
                    t0 = vx_time_now(), c0 = cpu_now();
                    if (vx_svo_write_ex(&wd, &sc, &o, &on, &err) != VX_OK) die("write", &err);
                    w[2][k] = vx_time_now() - t0, c[2][k] = cpu_now() - c0;
                    if (!first) first = o, first_n = on;
                    else {
                        if (on != first_n || memcmp(o, first, on)) {
                            fprintf(stderr, "svo_io_bench: the bytes differ with %u threads\n", threads[ti]);
                            return 1;
                        }
                        vx_free(NULL, o);
                    }
                }
                ru_snap r0 = ru_now();
                t0 = vx_time_now(), c0 = cpu_now();
                if (vx_svo_write_file(&wd, &sc, out_path, &err) != VX_OK) die(out_path, &err);
                w[3][k] = vx_time_now() - t0, c[3][k] = cpu_now() - c0;
                ru_print("write file", k, r0);
                printf("  run %d, %u threads: write (memory) %.3f s wall %.3f s CPU, write file %.3f s wall %.3f s CPU\n", k,
                       threads[ti], w[2][k], c[2][k], w[3][k], c[3][k]);
                fflush(stdout);
            }
        }
        static const char* names[4] = {"read (memory)", "read file", "write (memory)", "write file (with fsync)"};
        for (int st = 0; st < 4; st++) {
            if ((st < 2 && !do_read) || (st >= 2 && !do_write) || (file_only && st % 2 == 0)) continue;
            double wm = bench_median(w[st], runs), cm = bench_median(c[st], runs);
            printf("%-8u %-28s %10.3f %10.3f %10.1f\n", threads[ti], names[st], wm, cm, (double)size / wm / 1e6);
        }
        fflush(stdout);
    }
    if (first) printf("written: %zu bytes%s\n", first_n, first_n == size ? ", the input's size" : "");
    if (first && first_n == size) printf("written bytes %s the input file\n", memcmp(first, data, size) ? "differ from" : "equal");
    remove(out_path);
    if (recode) remove(in_path);
    vx_free(NULL, first);
    vx_svo_scene_free(&sc);
    vx_free(NULL, data);
    return 0;
}
