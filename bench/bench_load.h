/* bench/bench_load.h - the scene a benchmark measures: a .vox converted
 * with the defaults, or a .svo read as it is. It needs only the formats,
 * convert and svo libraries, so the benchmarks run on a bare GPU machine. */
#ifndef VX_BENCH_LOAD_H
#define VX_BENCH_LOAD_H
#include <string.h>

#include "convert/convert.h"

static inline int bench_load(const char* path, vx_svo_scene* s, vx_error* err) {
    const char* ext = strrchr(path, '.');
    if (ext && !strcmp(ext, ".vox")) {
        vx_vox_scene vs;
        if (vx_vox_read_file(NULL, path, &vs, err)) return 1;
        vx_result r = vx_conv_vox(NULL, &vs, s, NULL, err);
        vx_vox_scene_free(&vs);
        return r != VX_OK;
    }
    return vx_svo_read_file(NULL, path, s, err) != VX_OK;
}
#endif
