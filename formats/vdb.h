/* formats/vdb.h - OpenVDB grids through a small C shim (formats/vdb_openvdb.cpp).
 *
 * Usage: vx_vdb_read(bytes) -> vx_vdb_grid_count / vx_vdb_grid_get_info ->
 * vx_vdb_iterate (values and tiles) and vx_vdb_probe (random access) ->
 * vx_vdb_file_free(). Writing: vx_vdb_write_file (float and vec3f grids).
 *
 * Coordinates are OpenVDB index space: voxel (i, j, k) is centred on the
 * integer point (i, j, k); world = M * (i, j, k) + t for linear transforms.
 * Values are reported as doubles (float, half-saved-as-float and double
 * grids: one component; vec3 grids: three).
 *
 * Ownership: vx_vdb_read copies what it needs (the input may be freed after
 * the call). A vx_vdb_file is not thread-safe: probes go through cached
 * OpenVDB accessors held in it.
 *
 * Errors: every C++ exception thrown by OpenVDB (bad magic, unsupported
 * version, unregistered grid type, truncated stream, out of memory) is caught
 * and returned as a vx_result with OpenVDB's message; the offset is the byte
 * position of the stream when the exception was thrown. Nothing is printed.
 * Half-float grids saved by Houdini ("Tree_float_5_4_3_HalfFloat", file
 * version 222) load as float grids; a native half tree type is not
 * registered by this OpenVDB build and gives VX_ERR_UNSUPPORTED.
 */
#ifndef VX_VDB_H
#define VX_VDB_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "svo/core.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct vx_vdb_file vx_vdb_file;

typedef enum vx_vdb_value_type {
    VX_VDB_TYPE_OTHER = 0, /* a type we read but cannot iterate (int, bool, points, ...) */
    VX_VDB_TYPE_FLOAT,     /* includes grids saved as half floats */
    VX_VDB_TYPE_DOUBLE,
    VX_VDB_TYPE_VEC3F,
    VX_VDB_TYPE_VEC3D
} vx_vdb_value_type;

typedef enum vx_vdb_grid_class {
    VX_VDB_CLASS_UNKNOWN = 0,
    VX_VDB_CLASS_LEVEL_SET,
    VX_VDB_CLASS_FOG_VOLUME,
    VX_VDB_CLASS_STAGGERED
} vx_vdb_grid_class;

typedef struct vx_vdb_grid_info {
    char name[128];              /* truncated to 127 bytes */
    char type[64];               /* OpenVDB tree type, e.g. "Tree_float_5_4_3" */
    vx_vdb_value_type value_type;
    uint32_t components;         /* 1 for scalars, 3 for vec3, 0 for OTHER */
    vx_vdb_grid_class grid_class;
    bool saved_as_half;          /* the file stored the values as half floats */
    bool linear;                 /* the transform is affine (false: frustum etc.) */
    double index_to_world[12];   /* row-major 3x4, valid when linear */
    double voxel_size[3];        /* world size of voxel (0,0,0) */
    double background[3];
    uint64_t active_voxels;      /* OpenVDB's activeVoxelCount (tiles included) */
    uint64_t active_tiles;       /* active tiles at internal/root nodes */
    uint64_t leaf_count;
    bool empty;                  /* no active values: bbox below is meaningless */
    int32_t bbox_min[3], bbox_max[3]; /* active bounding box, inclusive */
} vx_vdb_grid_info;

/* Parses a .vdb file held in memory (all grids are loaded). */
vx_result vx_vdb_read(const void* data, size_t size, vx_vdb_file** out, vx_error* err);
void vx_vdb_file_free(vx_vdb_file* f);

uint32_t vx_vdb_grid_count(const vx_vdb_file* f);
vx_result vx_vdb_grid_get_info(const vx_vdb_file* f, uint32_t grid, vx_vdb_grid_info* out, vx_error* err);
/* The grid's whole name (vx_vdb_grid_info.name is cut at 127 bytes), owned by
 * f until vx_vdb_file_free; NULL when f is NULL or grid out of range. */
const char* vx_vdb_grid_name(const vx_vdb_file* f, uint32_t grid);

/* One stored value: a voxel (log2dim 0) or a tile covering the aligned cube
 * [origin, origin + 2^log2dim) in index space. value[] holds `components`
 * entries. Return false to stop (the iteration then returns VX_OK). */
typedef bool (*vx_vdb_value_fn)(void* user, const int32_t origin[3], uint32_t log2dim, bool active,
                                const double value[3]);

enum {
    VX_VDB_ITER_ACTIVE = 0, /* active voxels and active tiles */
    VX_VDB_ITER_ALL = 1     /* every stored voxel and tile, active or not (not the background outside the tree) */
};

/* Visits the grid's values (grids of type OTHER give VX_ERR_UNSUPPORTED). */
vx_result vx_vdb_iterate(vx_vdb_file* f, uint32_t grid, uint32_t mode, vx_vdb_value_fn fn, void* user,
                         vx_error* err);

/* Value at index point ijk (the background where nothing is stored), whether
 * it is active, and log2 of the edge of the aligned constant cube that holds
 * it: 0 for a leaf voxel, the tile size for tiles, the root child size for
 * the background outside the tree. Returns false (outputs untouched) when
 * grid is out of range or of type OTHER. */
bool vx_vdb_probe(vx_vdb_file* f, uint32_t grid, const int32_t ijk[3], double value[3], bool* active,
                  uint32_t* log2dim);

/* ---- writing ---------------------------------------------------------------------- */

/* One grid to write: active voxels at index points ijk with their values
 * (background 0, every other voxel inactive), OpenVDB's index-to-world map
 * (voxel ijk is centred on index_to_world * ijk), a name and a class. A
 * voxel given twice takes its last value. share >= 0 names an earlier grid
 * (share < 0 itself, same type) whose voxels this one has: the two grids
 * share one tree, which OpenVDB stores once (grid instancing); count, ijk
 * and value are then ignored. */
typedef struct vx_vdb_write_grid {
    const char* name;
    vx_vdb_value_type value_type; /* VX_VDB_TYPE_FLOAT or VX_VDB_TYPE_VEC3F */
    vx_vdb_grid_class grid_class;
    double index_to_world[12];    /* row-major 3x4, finite and invertible */
    int32_t share;                /* -1: voxels below */
    size_t count;
    const int32_t* ijk;           /* 3 per voxel */
    const float* value;           /* 1 (float) or 3 (vec3f) per voxel */
} vx_vdb_write_grid;

/* Writes the grids as one .vdb file (OpenVDB's stream format, its default
 * compression), through a temporary file renamed into place: a failure
 * leaves nothing behind. desc may be NULL (svo/core.h); its allocator serves
 * the temporary file's name only (OpenVDB builds the grids with operator new). */
vx_result vx_vdb_write_file(const vx_write_desc* desc, const vx_vdb_write_grid* grids, uint32_t count, const char* path,
                            vx_error* err);

#ifdef __cplusplus
}
#endif
#endif /* VX_VDB_H */
