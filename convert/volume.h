/* convert/volume.h - OpenVDB grids (.vdb) -> svo scene.
 *
 * Usage: vx_conv_vdb_file(&(vx_conv_vdb_desc){0}, "in.vdb", &scene, &stats,
 * &err) -> vx_svo_write_file(NULL, &scene, ...) -> vx_svo_scene_free(&scene).
 *
 * Grid space is OpenVDB index space: grid cell (i, j, k) is voxel (i, j, k),
 * so `svo_info --dump` prints index coordinates (which may be negative).
 * OpenVDB centres voxel ijk on the integer point ijk while our cell g spans
 * [g, g+1], so world_from_grid = M * (g - 1/2) + t for the grid's linear
 * transform (M, t); non-linear (frustum) transforms are refused with
 * VX_ERR_UNSUPPORTED.
 *
 * Which cells are set (value v read through the tree: inactive voxels and
 * tiles count with their stored value, the unstored region with the
 * background):
 *  - fog volumes and other non-level-set grids: active voxels and active
 *    tiles with v >= threshold when threshold_set, else with v > 0;
 *  - level sets (class GRID_LEVEL_SET), default: the surface shell, i.e.
 *    the active voxels with v < 0 that have at least one of their six face
 *    neighbours with v >= 0 (the boundary cells of the --solid interior, so
 *    the shell renders like the solid and has no gaps);
 *  - solid (any class): every stored voxel and tile, active or not, with
 *    v < 0 (level-set interiors are mostly inactive tiles).
 * Tiles become collapsed subtrees through vx_svo_voxels.level, never
 * voxel by voxel.
 *
 * Attributes: density (VX_ATTR_DENSITY) stores the grid value as a float.
 * color_grid names a vec3 grid sampled at each set cell (its background
 * where it stores nothing); components are taken as linear values, clamped
 * to [0, 1] and encoded with the sRGB transfer function into RGBA8 (alpha
 * 255), the encoding used by palettes and glTF textures. A tile whose colour
 * varies is subdivided only as far as the colour grid requires.
 *
 * Splitting: index space is cut into regions of 2^D cells per axis,
 * D = min(max_model_depth, build.max_depth) (each 0 == VX_SVO_MAX_DEPTH),
 * counted from the grid's lowest set cell rounded down to a multiple of its
 * largest tile (so a grid around the origin is not cut there). Every
 * non-empty region becomes one model (origin snapped down to its own largest
 * tile, size tight around its cells) with one instance translated by that
 * integer origin. Tiles larger than 2^D are cut into 2^D tiles first.
 */
#ifndef VX_CONVERT_VOLUME_H
#define VX_CONVERT_VOLUME_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "convert/convert.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct vx_conv_vdb_desc {
    vx_svo_build_desc build;
    const vx_allocator* alloc;   /* NULL: malloc/free (the scene's arrays too) */
    const vx_logger* logger;     /* optional warnings */
    const char* grid;            /* NULL: the first float or double grid; a name several grids
                                    share selects the first, "NAME[N]" the N-th repeat (from 0),
                                    OpenVDB's io::File convention; the same for color_grid */
    bool solid;                  /* cells with value < 0 (level-set interior) */
    bool threshold_set;          /* use threshold below (fog volumes) */
    double threshold;            /* cells with value >= threshold */
    bool density;                /* keep the value as VX_ATTR_DENSITY */
    const char* color_grid;      /* NULL: no colours; else a vec3 grid's name */
    uint32_t max_model_depth;    /* 0 == VX_SVO_MAX_DEPTH; lower in tests to force splitting */
    uint64_t max_cells;          /* 0 == no limit; else VX_ERR_LIMIT past this many cells and tiles
                                    (a tile counts once; for untrusted input such as fuzzing) */
    uint32_t brick_depth;        /* 0: regions as above; else regions are the cubes of 2^brick_depth
                                    cells at multiples of 2^brick_depth (fixed places: sequences) */
} vx_conv_vdb_desc;

/* Reads path (whole file into memory) and converts it. On failure *out is
 * untouched and err names the problem (OpenVDB's message for bad files). */
vx_result vx_conv_vdb_file(const vx_conv_vdb_desc* desc, const char* path, vx_svo_scene* out,
                           vx_conv_stats* stats, vx_error* err);

/* A sequence of .vdb files (one frame each, the same options for every
 * frame) as one animated scene. Each frame is cut into bricks of
 * 2^brick_depth cells at fixed places (default VX_CONV_VDB_SEQUENCE_BRICK_DEPTH),
 * one model per non-empty brick; a brick model equal to one stored before
 * (vx_svo_model_equal: a part that did not change) is stored once. Each
 * brick some frame fills is one instance, hidden in the frames where the
 * brick is empty. Every frame must have frame 0's grid transform. Frame f is
 * paths[f]; errors name the frame and its file. */
#define VX_CONV_VDB_SEQUENCE_BRICK_DEPTH 5u
vx_result vx_conv_vdb_sequence(const vx_conv_vdb_desc* desc, const char* const* paths, uint32_t count, vx_svo_scene* out,
                               vx_conv_stats* stats, vx_error* err);

/* The same from a .vdb file held in memory (borrowed). */
vx_result vx_conv_vdb_memory(const vx_conv_vdb_desc* desc, const void* data, size_t size, vx_svo_scene* out,
                             vx_conv_stats* stats, vx_error* err);

#ifdef __cplusplus
}
#endif
#endif /* VX_CONVERT_VOLUME_H */
