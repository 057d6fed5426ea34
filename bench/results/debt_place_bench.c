/* The probe placement alone: vx_probe_place (the caster) and vx_probe_place_compact (the compact layout),
 * thread CPU seconds, median of N. Linked against main's libraries or the branch's. */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
#include "probes/probes.h"
#include "render/compact.h"
#include "svo/svo.h"
static double cpu(void) { struct timespec t; clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t); return t.tv_sec + 1e-9 * t.tv_nsec; }
static int cmpd(const void* a, const void* b) { double x = *(const double*)a, y = *(const double*)b; return x < y ? -1 : x > y; }
int main(int argc, char** argv) {
    if (argc < 6) return 2;
    vx_svo_scene s; vx_error err = {0};
    if (vx_svo_read_file(NULL, argv[1], &s, &err)) { fprintf(stderr, "%s\n", err.msg); return 1; }
    vx_probe_bake_desc d = {.grid = {atoi(argv[2]), atoi(argv[3]), atoi(argv[4])}, .res = 16};
    int n = atoi(argv[5]);
    vx_compact_scene c;
    if (vx_compact_build(NULL, &s, &c, &err)) { fprintf(stderr, "%s\n", err.msg); return 1; }
    double tw[64], tc[64]; unsigned long moved = 0;
    for (int i = 0; i < n && i < 64; i++) {
        vx_probe_set a = {0}, b = {0};
        double t0 = cpu();
        if (vx_probe_place(&s, &d, &a, &err)) return 1;
        double t1 = cpu();
        if (vx_probe_place_compact(&c, &s, &d, &b, &err)) return 1;
        double t2 = cpu();
        tw[i] = t1 - t0, tc[i] = t2 - t1;
        for (uint32_t k = 0; k < a.probe_count; k++) moved += a.probes[k].state != b.probes[k].state;
        vx_probe_set_free(&a), vx_probe_set_free(&b);
    }
    qsort(tw, n, sizeof *tw, cmpd), qsort(tc, n, sizeof *tc, cmpd);
    printf("%s grid %s,%s,%s: vx_probe_place %.4f s, vx_probe_place_compact %.4f s (medians of %d, thread CPU); states differing %lu\n",
           argv[1], argv[2], argv[3], argv[4], tw[n / 2], tc[n / 2], n, moved);
    vx_compact_free(&c); vx_svo_scene_free(&s);
    return 0;
}
