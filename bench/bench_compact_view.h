/* bench/bench_compact_view.h - compact_bench's full-frame close-up (issue 18's speed views): fov 70, the eye at
 * the bounds' middle + (0.2, -0.3, 0.2) of their extent, aimed at the middle - 0.05 of it, so inside the bounds.
 * Needs only render/render.h, so today_bench builds with it in the tree of the day issue 18 was filed too. */
#ifndef VX_BENCH_COMPACT_VIEW_H
#define VX_BENCH_COMPACT_VIEW_H
#include "render/render.h"

static inline void bench_compact_closeup(const double lo[3], const double hi[3], vx_render_desc* d) {
    d->camera.set = true;
    d->camera.fov = 70;
    for (int k = 0; k < 3; k++) {
        double mid = 0.5 * (lo[k] + hi[k]), ext = hi[k] - lo[k];
        d->camera.target[k] = mid - 0.05 * ext;
        d->camera.eye[k] = mid + (k == 1 ? -0.3 : 0.2) * ext;
    }
}
#endif
