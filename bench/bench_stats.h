/* bench/bench_stats.h - the median the benchmarks report (sorts v in place). */
#ifndef VX_BENCH_STATS_H
#define VX_BENCH_STATS_H
#include <stdlib.h>

static inline int bench_cmpd(const void* a, const void* b) {
    double x = *(const double*)a, y = *(const double*)b;
    return (x > y) - (x < y);
}
static inline double bench_median(double* v, int n) {
    qsort(v, (size_t)n, sizeof *v, bench_cmpd);
    return n ? v[n / 2] : 0;
}

#endif
