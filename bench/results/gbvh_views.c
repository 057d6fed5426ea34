/* gbvh (issue 21): render_bench's three views (make_views: overview, oblique, close-up) of each scene printed as
 * passes_bench --camera arguments ("default" for the overview's default framing), so that the pass benchmark
 * measures the tracer benchmark's views. Not built by CMake: render_bench.c included with its main renamed,
 * linked with render_bench's other objects (build: the Release build dir with render_bench built):
 *   cc -O2 -std=c17 -I. -Ibuild/bench/spv bench/results/gbvh_views.c build/bench/CMakeFiles/render_bench.dir/esvo.c.o \
 *      build/bench/CMakeFiles/render_bench.dir/tree64.c.o build/render/libvx_render.a build/convert/libvx_convert.a \
 *      build/formats/libvx_formats.a build/svo/libvx_svo.a build/render/libvx_trace.a build/svo/libvx_svo.a \
 *      build/svo/libvx_core.a -lvulkan -lz -lzstd -ldeflate -lm -o build/gbvh_views
 *   build/gbvh_views SCENE.vox|terrain:EXTENT ... */
#define main render_bench_main
#include "bench/render_bench.c"
#undef main

int main(int argc, char** argv) {
    vx_error err = {0};
    vx_gpu* gpu;
    if (vx_gpu_create(&(vx_gpu_desc){0}, &gpu, &err)) return fprintf(stderr, "%s\n", err.msg), 1;
    int status = 0;
    for (int a = 1; a < argc; a++) {
        vx_svo_scene s;
        unsigned extent = 0;
        bool terrain = sscanf(argv[a], "terrain:%u", &extent) == 1;
        vx_render_scene* rs = NULL;
        vx_render_camera cams[3];
        bool loaded = !(terrain ? bench_terrain(&s, extent, 0, &err) : bench_load(argv[a], &s, &err));
        if (!loaded || vx_render_scene_create(gpu, &s, &rs, &err) || !make_views(rs, &s, cams)) {
            fprintf(stderr, "%s: no views %s\n", argv[a], err.msg);
            status = 1;
        } else {
            printf("%s:", argv[a]);
            for (int v = 0; v < 3; v++)
                if (!cams[v].set) printf(" default");
                else
                    printf(" %.9g,%.9g,%.9g,%.9g,%.9g,%.9g", cams[v].eye[0], cams[v].eye[1], cams[v].eye[2],
                           cams[v].target[0], cams[v].target[1], cams[v].target[2]);
            printf("\n");
        }
        vx_render_scene_destroy(rs);
        if (loaded) vx_svo_scene_free(&s);
    }
    vx_gpu_destroy(gpu);
    return status;
}
