/* tools/svo_info/glb.h - svo_info --to-glb: the scene as a binary glTF. */
#ifndef VX_SVO_INFO_GLB_H
#define VX_SVO_INFO_GLB_H

#include <stdbool.h>
#include <stdint.h>

#include "svo/svo.h"

typedef struct svo_glb_stats {
    uint32_t meshes, nodes;
    uint64_t quads; /* greedy quads written (two triangles each) */
    uint64_t faces; /* exposed voxel faces: the quads of a naive mesh */
    double seconds_mesh;
} svo_glb_stats;

/* One mesh per non-empty model that a written node shows (greedy-meshed surface, model cell units,
 * linear vertex colours decoded from the sRGB voxel colours, no normals:
 * viewers compute the flat ones),
 * one node per shown instance (every instance with all) whose matrix is
 * R * world_from_grid * xform, R turning voxkit's +Z up into glTF's +Y up:
 * (x, y, z) -> (x, z, -y), so a scene stands upright in glTF viewers and a
 * converted glTF file gets its own axes back. desc may be NULL; its
 * allocator serves every block made here (cells, quads, the mesh arrays) and
 * the temporary file's name. */
vx_result svo_info_to_glb(const vx_write_desc* desc, const vx_svo_scene* s, bool all, const char* path,
                          svo_glb_stats* stats, vx_error* err);

#endif
