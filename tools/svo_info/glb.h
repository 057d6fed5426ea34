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
    uint32_t lights;       /* KHR_lights_punctual lights written */
    uint32_t approximated; /* of them, those svo_info_glb_light_approx names */
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

/* Lights: every stored light (those of emissive voxels are never stored) as
 * a KHR_lights_punctual light on a root node named "light I" (I its index
 * in the scene), placed and aimed in glTF's +Y-up world units as the mesh
 * nodes are. Directional, point and spot carry over in glTF's units (which
 * are voxkit's); the two types glTF lacks become their nearest punctual
 * light: a sphere (radiance L, radius r) a point light of the same power
 * seen from afar, I = L pi r^2; a rect (one-sided, radiance L, area A) a spot
 * along its normal with outer cone pi/2, inner 0 and its on-axis intensity
 * I = L A. Where the punctual light is not voxkit's exact record (sphere,
 * rect, a point or spot radius, a sun's angular diameter, a spot whose
 * inner cone equals its outer, a colour channel over 1), the light's
 * extras hold "voxkit_light" with the exact values (docs/LIBRARY.md), which
 * formats/gltf.h reads back. */

/* Why light l's punctual form differs from the light, for other glTF
 * readers (a phrase such as "sphere light as a point light of the same
 * power"), or NULL when it is the light itself. */
const char* svo_info_glb_light_approx(const vx_light* l);

#endif
