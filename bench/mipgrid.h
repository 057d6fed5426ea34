/* bench/mipgrid.h - a prototype for issue 21 in bench/render_bench: the
 * scene's cells as a pointerless occupancy pyramid (level 0 one bit per
 * cell, level l one bit per 2^l-cell cube, each level in 4x4x4-bit bricks of
 * two 32-bit words, coarse levels first), traced by bench/shaders/mipgrid.comp
 * on the same primary rays as voxkit's tracer and the ESVO baseline. It
 * measures what an octree walk costs when a cell's address is computed from
 * its coordinates (no child pointers, no stack: a pop is a shift) and whether
 * a probe of the finest cell at the entry point of an occupied node (possible
 * only where addresses are computed) takes fewer steps than descending level
 * by level. Dense: 8/7 bits per cell of the cube, so only for cubes up to
 * 2^11 cells wide. Needs an identity world_from_grid, like the ESVO baseline. */
#ifndef VX_BENCH_MIPGRID_H
#define VX_BENCH_MIPGRID_H
#include "bench/esvo.h"

enum { BENCH_MIP_VARIANTS = 3 };

typedef struct bench_mip {
    vx_gpu* gpu;
    uint32_t depth; /* the cube is 2^depth cells wide, as ESVO's */
    int64_t lo[3];
    uint64_t words, cells;
    vx__buffer buf;
    bench_kernel k;
    double build_seconds;
} bench_mip;

/* Builds the pyramid of every drawn instance's cells and uploads it. Fails
 * with VX_ERR_LIMIT for cubes wider than 2^max_depth cells. */
vx_result bench_mip_create(vx_gpu* gpu, const vx_svo_scene* s, uint32_t max_depth, bench_mip* m, vx_error* err);
void bench_mip_destroy(bench_mip* m);
/* Bytes of the pyramid on the GPU. */
uint64_t bench_mip_bytes(const bench_mip* m);
/* As bench_esvo_frame; variant: the kernel's PROBE (0: descend level by
 * level; 1: on entering an occupied node first test the finest cell at the
 * entry point, a hit ends the ray; 2: as 1 from nodes at most 8 cells wide). */
vx_result bench_mip_frame(bench_mip* m, uint32_t variant, const vx_svo_scene* s, const vx_render_desc* desc,
                          uint32_t repeat, double* seconds, float* depth, uint32_t* steps, vx_error* err);
#endif
