/* lean2 (issue 21): bench_terrain 1024 written as a .svo for passes_bench and svo_render (not built by CMake):
 *   gcc -O2 -std=c17 -I. lean2_mkterrain.c build-gpu/svo/libvx_svo.a build-gpu/svo/libvx_core.a -lz -lzstd -ldeflate -lm -lpthread
 *   ./a.out 1024 terrain1024.svo */
#include "bench/bench_terrain.h"
#include <stdio.h>
int main(int argc, char** argv) {
    vx_svo_scene s; vx_error err = {0};
    if (argc < 3 || bench_terrain(&s, (uint32_t)atoi(argv[1]), 0, &err)) { fprintf(stderr, "fail %s\n", err.msg); return 1; }
    if (vx_svo_write_file(&(vx_write_desc){0}, &s, argv[2], &err)) { fprintf(stderr, "write %s\n", err.msg); return 1; }
    return 0;
}
