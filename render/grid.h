/* render/grid.h - the grid walk's layout (issue 21): a model's cells as a
 * hierarchy of grids that trace.comp walks by a hierarchical DDA
 * (render/shaders/grid_walk.glsl) instead of descending the octree. Shared by
 * render_scene.c (one grid per model, built at upload from the octree) and
 * bench/brickgrid.c (the prototype of stop 75: one grid of a whole scene).
 *
 * Levels: a level-k cell is 8^k cells wide. A level-1 cell is a brick: 16
 * words, bit x + 8 y + 64 z its cell (x, y, z). A node (512 words, entry x +
 * 8 y + 64 z) holds the 8^3 level-(k-1) cells of one level-k cell. The root
 * is a dense R^3 grid of level-`top` cells (x fastest), R = 2^depth / 8^top.
 * An entry below VX__GRID_EMPTY is the word address (in the buffer the grid
 * is placed in) of its cell's node or brick; VX__GRID_EMPTY | d marks an
 * empty cell whose nearest occupied cell of the same level is d cells away in
 * the Chebyshev metric, within its node (nodes) or the root, so every cell
 * there within d - 1 of it is empty: a ray leaves that whole cube in one
 * step; and per octant of directions how much further the empty cube from
 * it toward that octant reaches (VX__GRID_OCT_SHIFT below). Words: the
 * root, the bricks, then each level's nodes bottom up, then
 * (a model with attributes) one record word a brick, in the bricks' order
 * (vx__grid_brick_record: where a hit's octree descent for its attribute
 * record starts, so that it walks the last three levels, not all).
 *
 * Memory: 4 R^3 bytes of root, 64 bytes a brick (and 4 of its record word
 * where the model has attributes), 2 KiB a node (issue 21's terrain4096: 65
 * MiB at root level 2 with its records, against the octree's 2.3 MiB and the
 * ESVO baseline's 1176); render_scene.c keeps the grids within a budget. */
#ifndef VX_RENDER_GRID_H
#define VX_RENDER_GRID_H

#include "svo/svo.h"

#define VX__GRID_EMPTY UINT32_C(0x80000000)
/* An empty entry's word (stop 88): VX__GRID_EMPTY | d | the 8 octants' 3-bit extents from bit
 * VX__GRID_OCT_SHIFT, octant o's (bit a of o set: toward -a) at VX__GRID_OCT_SHIFT + 3 o. d (at most
 * VX__GRID_DIST_MASK: no occupied entry nearer, or none) is the Chebyshev distance above; d + e_o is the side
 * of the empty cube from the entry toward o (capped at d + 7; outside the node or root counts as empty), which
 * a ray whose direction lies in o leaves in one step. */
#define VX__GRID_DIST_MASK UINT32_C(0x7F)
/* The extents are made only in grids whose root is at least 2^VX__GRID_OCT_ROOT_LOG entries a side (their
 * nodes too); elsewhere they are 0, which is valid (the cube toward o is at least the distance's). The kernel
 * reads them only where some grid's root is that wide (render_scene.c grid_bits, grid_walk.glsl GRID_OCT): on
 * smaller roots they saved fewer steps than they cost (stop 88), and an edited small model's grid is made
 * again without them. */
enum { VX__GRID_OCT_SHIFT = 7, VX__GRID_OCT_ROOT_LOG = 6 };
/* Whether a grid of a 2^depth cube with its root at level top is wide enough to hold the extents (the one rule
 * for render/grid.c, which makes them, and render_scene.c, which sets the kernel's GRID_OCT). */
static inline bool vx__grid_octants(uint32_t depth, uint32_t top) {
    return depth >= 3 * top + VX__GRID_OCT_ROOT_LOG;
}
/* The default root: at most 2^7 = 128 cells of level `top` a side (8 MiB). */
enum { VX__GRID_ROOT_LOG = 7, VX__GRID_MAX_TOP = 3 };

/* A model's grid cube (stop 85): for a model of depth model_depth whose
 * cells lie in the box cb [lo, hi) (lo xyz, hi xyz exclusive: the grid
 * header's, render_scene.c), the smallest cube from org = lo rounded down to
 * whole bricks, 2^depth cells a side (depth >= 3), where that is smaller than
 * the model's; else the model's cube (org 0, depth max(model_depth, 3)).
 * Returns depth, org in cells (multiples of 8). A slab or a small group of
 * cells in a large model is laid out at its own size (vengi's cubictest, 73
 * cells in a 2^8 cube: a 2^4 cube, its root 2^3 words over 5 bricks, not a
 * 32^3 root of 128 KiB). grid_walk.glsl derives the same from the header's
 * box and the model's depth (grid_cube there) in kernels whose GRID has bit
 * 5; render_scene.c lays grids out so only in scenes where some grid would
 * outweigh its model's octree. */
static inline uint32_t vx__grid_cube(const uint32_t cb[6], uint32_t model_depth, uint32_t org[3]) {
    uint32_t ext = 8, depth = 3, md = model_depth < 3 ? 3 : model_depth;
    for (int k = 0; k < 3; k++) {
        org[k] = cb[k] & ~UINT32_C(7);
        if (cb[3 + k] > org[k] && cb[3 + k] - org[k] > ext) ext = cb[3 + k] - org[k];
    }
    while (depth < 31 && (UINT32_C(1) << depth) < ext) depth++;
    if (depth >= md) org[0] = org[1] = org[2] = 0, depth = md;
    return depth;
}

/* Growing 32-bit words (allocator a, NULL: malloc). */
typedef struct vx__grid_words {
    uint32_t* w;
    size_t n, cap;
} vx__grid_words;
bool vx__grid_words_grow(const vx_allocator* a, vx__grid_words* v, size_t add);

/* Bricks being collected: 16 words each, their brick coordinates (3 words
 * each), and a hash from coordinates to index (so that cells and blocks of
 * several sources OR into one brick). Zero-initialised is empty. */
typedef struct vx__grid_bricks {
    const vx_allocator* alloc;
    vx__grid_words bits, coords;
    uint64_t* key; /* packed coordinates + 1 (0: free) */
    uint32_t* val;
    size_t cap, count;
} vx__grid_bricks;
/* The 16 words of the brick at brick coordinates (bx, by, bz), each below
 * 2^20, added empty if new; NULL out of memory (the words may move at the
 * next call). */
uint32_t* vx__grid_brick_at(vx__grid_bricks* b, uint32_t bx, uint32_t by, uint32_t bz);
void vx__grid_bricks_free(vx__grid_bricks* b);

/* The root's level for a 2^depth cube whose root is at most 2^root_log wide
 * (0: VX__GRID_ROOT_LOG): the smallest top >= 1 with depth - 3 top <=
 * root_log (trace.comp's walk: grid_walk.glsl grid_top, the same rule for
 * root_log 0). */
uint32_t vx__grid_top(uint32_t depth, uint32_t root_log);

/* Appends the grid of bricks b (a 2^depth cube from cell org, org in whole
 * bricks' cells, NULL: 0; depth >= 3, top from vx__grid_top) to out, its
 * root first at word out->n; addresses are out's word indices plus base
 * (where out's word 0 will lie). VX_ERR_LIMIT where an address would reach
 * VX__GRID_EMPTY, VX_ERR_INVALID_ARG where a brick lies outside the cube,
 * VX_ERR_NOMEM. */
vx_result vx__grid_layout(vx__grid_bricks* b, uint32_t depth, uint32_t top, const uint32_t org[3], uint64_t base,
                          vx__grid_words* out, vx_error* err);

/* The bricks of a union grid that a model's grid points at rather than holds
 * (render_scene.c's union of a converter's regions): bricks as
 * vx__grid_bricks_add collected them, the model's at brick offset off, brick j
 * at word base + 16 j. */
typedef struct vx__grid_share {
    const vx__grid_bricks* bricks;
    uint64_t base;
    uint32_t off[3];
    uint32_t rec; /* the union's record key (vx__grid_model's *rec; 0: none) */
} vx__grid_share;

/* A brick's record word: for the brick at brick coordinates (bx, by, bz) of
 * model m (8 bx .. 8 bx + 7 its cells' x), the word index (in m->nodes, as
 * the renderer's node buffer holds them from the model's first word) of the
 * node whose cube is the brick (the root where depth <= 3), or
 * VX__GRID_RECORD_LEAF | a where a uniform leaf of 8^3 cells or more holds
 * the brick, a its attribute record; VX__GRID_RECORD_NONE where m has no
 * attributes, holds no cell there, or a value would not fit 31 bits.
 * grid_walk.glsl descends from it (model_cell_leaf_brick): the last three
 * levels to a hit cell's record instead of all. One descent; m valid. */
#define VX__GRID_RECORD_LEAF UINT32_C(0x80000000)
#define VX__GRID_RECORD_NONE UINT32_C(0xFFFFFFFF)
uint32_t vx__grid_brick_record(const vx_svo_model* m, uint32_t bx, uint32_t by, uint32_t bz);

/* The record words of bricks b (brick i at brick coordinates b->coords, minus
 * off: in the cells of model(user, i), which returns NULL for a brick whose
 * model has no attributes: word 0), appended to out; *rec the record key of
 * a grid whose brick 0 lies at word address brick0 (grid_walk.glsl: brick
 * word address w has its record at word *rec + (w >> 4); 0: no records,
 * where no brick has one or a value does not fit). VX_ERR_NOMEM. */
typedef const vx_svo_model* (*vx__grid_record_model_fn)(void* user, size_t brick, uint32_t off[3]);
vx_result vx__grid_records(const vx__grid_bricks* b, vx__grid_record_model_fn model, void* user, uint64_t base,
                           uint64_t brick0, vx__grid_words* out, uint32_t* rec, vx_error* err);

/* Appends model m's grid to out as vx__grid_layout does, its bricks from the
 * octree (vx_svo_decode_blocks), over the cube vx__grid_cube gives for its
 * cells' box cb (NULL: the model's cube from cell 0, max(depth, 3) levels;
 * cb must hold every cell of m), then (m with attributes) their record words
 * (vx__grid_records); *top its root's level (vx__grid_top of the cube's depth, 0),
 * *rec its record key (the grid header's word 3, grid_walk.glsl; 0: none). A
 * model of depth < 3 is walked in one brick (depth 3). With share (not NULL)
 * the grid is its levels above the bricks, its entries the union's brick
 * addresses (no brick written twice), its record key the union's;
 * VX_ERR_INVALID_ARG where a brick of the model is not the union's as is. m
 * must be valid. */
vx_result vx__grid_model(const vx_allocator* a, const vx_svo_model* m, const uint32_t cb[6], uint64_t base,
                         const vx__grid_share* share, vx__grid_words* out, uint32_t* top, uint32_t* rec, vx_error* err);

/* Adds model m's cells to b, each at its cell plus 8 off (off in bricks,
 * each sum below 2^20): the bricks of several models placed in one grid
 * (render_scene.c's union of a converter's regions). m must be valid. */
vx_result vx__grid_bricks_add(vx__grid_bricks* b, const vx_svo_model* m, const uint32_t off[3], vx_error* err);
#endif
