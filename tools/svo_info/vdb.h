/* tools/svo_info/vdb.h - svo_info --to-vdb: the scene as OpenVDB grids. */
#ifndef VX_SVO_INFO_VDB_H
#define VX_SVO_INFO_VDB_H

#include <stdbool.h>
#include <stdint.h>

#include "svo/svo.h"

typedef struct svo_vdb_stats {
    uint32_t grids;  /* grids written (shared ones included) */
    uint64_t voxels; /* active voxels written (a shared tree counted once) */
    bool colors;     /* colour grids written */
} svo_vdb_stats;

/* Default (models false): the flattened scene, the cells `svo_info --dump`
 * prints, as a fog volume "density" (1, or the model's density attribute)
 * and, when a shown model has colours, a vec3 grid "color" (linear RGB
 * decoded from the sRGB voxel colours); index space = grid cells, the
 * transform world_from_grid (shifted half a cell: OpenVDB centres voxel ijk
 * on ijk). Overlapping instances: the later one's value.
 * models: one grid pair "NAME/density", "NAME/color" per shown instance (NAME
 * its name, or "instance I"), in model cells with the instance's world map
 * as the transform; instances of one model share its tree (stored once).
 * desc may be NULL; its allocator serves every block made here (cells, the
 * grids' voxel arrays) and the temporary file's name. */
vx_result svo_info_to_vdb(const vx_write_desc* desc, const vx_svo_scene* s, bool all, bool models, const char* path,
                          svo_vdb_stats* stats, vx_error* err);

#endif
