/* bench/bench_view.h - the close-up view the pass and light benchmarks
 * measure: a quarter of the default framing's eye distance, the same
 * direction, aimed a little below the scene's centre. */
#ifndef VX_BENCH_VIEW_H
#define VX_BENCH_VIEW_H
#include <math.h>

#include "render/trace.h"

static inline void bench_closeup(const double lo[3], const double hi[3], vx_render_desc* base) {
    vx__frame f;
    vx__frame_setup(lo, hi, base, &f, NULL);
    double c[3], d = 0;
    for (int k = 0; k < 3; k++) c[k] = 0.5 * (lo[k] + hi[k]);
    for (int k = 0; k < 3; k++) {
        double e = f.ref[k] - f.fwd[k] * f.t_start;
        d += (e - c[k]) * (e - c[k]);
    }
    d = sqrt(d);
    base->camera.set = true;
    for (int k = 0; k < 3; k++) {
        base->camera.target[k] = c[k] - 0.08 * (hi[2] - lo[2]) * (k == 2);
        base->camera.eye[k] = c[k] - f.fwd[k] * d * 0.25;
    }
}
#endif
