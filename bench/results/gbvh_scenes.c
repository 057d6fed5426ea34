/* gbvh (issue 21): the tests' scenes of several instances written as .svo files for passes_bench --check on the H200
 * (A against B, value for value): test_render_gpu's test_many_instances ("60 instances (bvh)") and test_passes'
 * generated scene (three instances, a rotation and a mirror), built as those tests build them (their seeds and
 * placements; tests/render/scenes.h). Not built by CMake:
 *   cc -O2 -std=c17 -I. bench/results/gbvh_scenes.c build/render/libvx_trace.a build/svo/libvx_svo.a \
 *      build/svo/libvx_core.a -lz -lzstd -ldeflate -lm -o build/gbvh_scenes && build/gbvh_scenes OUTDIR */
#include <stdio.h>

#include "tests/render/scenes.h"

static int write_scene(vx_svo_model* m, const vx_svo_instance* in, uint32_t n, const char* dir, const char* name) {
    vx_svo_scene s;
    ts_scene(&s, m, 2, in, n);
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    vx_error err = {0};
    int r = vx_svo_write_file(&(vx_write_desc){0}, &s, path, &err) != VX_OK;
    if (r) fprintf(stderr, "%s: %s\n", path, err.msg);
    vx_svo_scene_free(&s);
    return r;
}

int main(int argc, char** argv) {
    if (argc != 2) return 2;
    static const double rots[4][9] = {{1, 0, 0, 0, 1, 0, 0, 0, 1}, {0, -1, 0, 1, 0, 0, 0, 0, 1},
                                      {-1, 0, 0, 0, 1, 0, 0, 0, 1}, {0, 0, 1, 0, 1, 0, -1, 0, 0}};
    vx_svo_model m[2];
    vx_svo_instance in[60];
    uint32_t seed = 5;
    if (ts_random_model(&m[0], 5, 6, 7, 40, 11) || ts_random_model(&m[1], 9, 3, 4, 50, 12)) return 1;
    for (int i = 0; i < 60; i++) /* the test's expression (its arguments' order of evaluation too) */
        in[i] = ts_inst(i % 2, rots[i % 4], (double)(ts_rng(&seed) % 40), (double)(ts_rng(&seed) % 40),
                        (double)(ts_rng(&seed) % 10));
    int r = write_scene(m, in, 60, argv[1], "many60.svo");
    if (ts_random_model(&m[0], 24, 20, 16, 30, 7) || ts_random_model(&m[1], 9, 9, 9, 60, 8)) return 1;
    static const double mir[9] = {-1, 0, 0, 0, 1, 0, 0, 0, 1};
    in[0] = ts_inst(0, NULL, 0, 0, 0), in[1] = ts_inst(1, rots[1], 30, 4, 2), in[2] = ts_inst(1, mir, -12, 10, 5);
    return write_scene(m, in, 3, argv[1], "passes3.svo") || r;
}
