/* bench/brickgrid.h - a prototype for issue 21 in bench/render_bench: the
 * scene's cells as a hierarchy of grids, traced by a hierarchical DDA
 * (bench/shaders/brickgrid.comp) on the same primary rays as voxkit's tracer
 * and the ESVO baseline. Every level is 8 times coarser than the one below:
 * 8^3-cell bricks of 512 bits, nodes of 8^3 entries above them, a dense
 * root grid at most 128 wide on top (bench/brickgrid.c has the layout). An
 * empty entry holds its Chebyshev distance to the nearest occupied entry, so
 * a ray leaves the whole empty cube around it in one step. It measures what
 * the octree walk's per-step cost buys: the dense DDA baseline
 * (render_bench's GrayDn column) traces the .vox close-ups 1.2-1.9x faster
 * than ESVO with a step of a few instructions, but walks every empty cell;
 * this keeps the DDA's step and skips empty space by distance. Occupancy
 * only (no colours). Needs an identity world_from_grid, like the ESVO
 * baseline. */
#ifndef VX_BENCH_BRICKGRID_H
#define VX_BENCH_BRICKGRID_H
#include "bench/esvo.h"

enum { BENCH_BRICK_VARIANTS = 2 };

typedef struct bench_brick {
    vx_gpu* gpu;
    uint32_t depth; /* the cube is 2^depth cells wide (at least 8), from ESVO's corner */
    uint32_t top;   /* the root grid's level: its cells are 8^top cells wide */
    int64_t lo[3];
    uint64_t words, cells, bricks;
    vx__buffer buf;
    bench_kernel k;
    double build_seconds;
} bench_brick;

/* Builds the grid of every drawn instance's cells and uploads it. Fails with
 * VX_ERR_LIMIT for cubes wider than 2^max_depth cells. root_log: the root
 * grid at most 2^root_log wide (0: 7, 128 cells of 8^top). */
vx_result bench_brick_create(vx_gpu* gpu, const vx_svo_scene* s, uint32_t max_depth, uint32_t root_log, bench_brick* m,
                             vx_error* err);
void bench_brick_destroy(bench_brick* m);
/* Bytes of the grid on the GPU. */
uint64_t bench_brick_bytes(const bench_brick* m);
/* As bench_esvo_frame; variant: the kernel's FCOORD (0: a brick's cell
 * planes from the integer cell each step, 1: kept as floats); SKIP is 1
 * (the empty cube of the entry's distance a step; 0, one cell a step, was
 * measured at stop 75: bench/results/p75_h200_brick_v4.txt). */
vx_result bench_brick_frame(bench_brick* m, uint32_t variant, const vx_svo_scene* s, const vx_render_desc* desc,
                            uint32_t repeat, double* seconds, float* depth, uint32_t* steps, vx_error* err);
#endif
