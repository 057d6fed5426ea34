/* bench/tree64.h - a prototype for issue 21 in bench/render_bench: the
 * scene's cells in a sparse 64-tree (each node 4x4x4 children: a 64-bit
 * child mask and the index of its children's block, the children stored
 * in mask order so that a child's index is the block plus a popcount;
 * identical blocks stored once, so identical subtrees are shared as in a
 * DAG), full depth (no collapsed leaves, geometry only: no colours), traced
 * by bench/shaders/tree64.comp on the same primary rays as voxkit's tracer
 * and the ESVO baseline. It measures whether half the levels (and a DDA over
 * each node's 4^3 cells, empty 2^3 groups skipped at once) take fewer steps
 * per ray and more rays per second than an octree. Needs an identity
 * world_from_grid, like the ESVO baseline. */
#ifndef VX_BENCH_TREE64_H
#define VX_BENCH_TREE64_H
#include "bench/esvo.h"

typedef struct bench_tree64 {
    vx_gpu* gpu;
    uint32_t levels;      /* 64-tree levels: the cube is 4^levels cells wide */
    uint32_t clip_depth;  /* rays are clipped to the ESVO cube, 2^clip_depth cells */
    uint32_t root;        /* node index of the root; UINT32_MAX: empty */
    int64_t lo[3];
    uint64_t node_count, cells;
    vx__buffer buf;
    bench_kernel k;
    double build_seconds;
} bench_tree64;

/* Builds the 64-tree of every drawn instance's cells and uploads it. Fails
 * with VX_ERR_LIMIT past 2^28 nodes or 21 octree levels. */
vx_result bench_tree64_create(vx_gpu* gpu, const vx_svo_scene* s, bench_tree64* t, vx_error* err);
void bench_tree64_destroy(bench_tree64* t);
/* Bytes of the tree on the GPU (16 per node). */
uint64_t bench_tree64_bytes(const bench_tree64* t);
/* As bench_esvo_frame; variant: the kernel's SKIP (0: empty cells one at a
 * time or as an empty 2^3 group, 1: one at a time; see tree64.comp). */
vx_result bench_tree64_frame(bench_tree64* t, uint32_t variant, const vx_svo_scene* s, const vx_render_desc* desc,
                             uint32_t repeat,
                             double* seconds, float* depth, uint32_t* steps, vx_error* err);
#endif
