/* convert/export.h - a scene out to other tools' formats: binary glTF (.glb)
 * and OpenVDB grids (.vdb). These are the exports of `svo_info --to-glb` and
 * `--to-vdb`, for programs (and the Python module) that hold a scene; the
 * .vox export is vx_conv_svo_to_vox (convert/convert.h).
 *
 * Both write what a scene shows: its instances that are visible (their own
 * flag and their layer's; every instance with `all`), each model decoded
 * once. For an animation pass the frame's view (vx_svo_scene_frame). Files
 * are written whole or not at all (a temporary name, then a rename). A build
 * without tinygltf (libtinygltf-dev) or OpenVDB (libopenvdb-dev) keeps the
 * function but it fails with VX_ERR_UNSUPPORTED saying so.
 */
#ifndef VX_CONV_EXPORT_H
#define VX_CONV_EXPORT_H

#include <stdbool.h>
#include <stdint.h>

#include "svo/svo.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Export options; zero-initialised means the defaults.
 *  write:       NULL, or the allocator (every block made here: decoded cells,
 *               meshes, grids, the temporary file's name) and write options
 *  all:         also hidden instances and instances on hidden layers
 *  vdb_models:  .vdb only: one grid pair per instance instead of the
 *               flattened scene (see vx_conv_svo_to_vdb_file)
 *  svo_path:    .glb only: the file the scene was read from, whose folder
 *               an environment-map sky's relative path starts from (below);
 *               NULL: unknown, the path is written as it is (as if the .glb
 *               lay beside the scene's file) */
typedef struct vx_conv_export_desc {
    const vx_write_desc* write;
    bool all;
    bool vdb_models;
    const char* svo_path;
} vx_conv_export_desc;

typedef struct vx_conv_glb_stats {
    uint32_t meshes, nodes;
    uint32_t materials;   /* glTF materials written (0: the one default) */
    uint32_t lights;      /* KHR_lights_punctual lights written */
    uint32_t lights_approximated; /* of those: sphere and rect lights, which glTF lacks */
    uint64_t quads;       /* greedy quads written (two triangles each) */
    uint64_t faces;       /* exposed voxel faces: the quads of a naive mesh */
    double seconds_mesh;
} vx_conv_glb_stats;

/* The scene as binary glTF 2.0: one mesh per non-empty model that a written
 * node shows (its greedy-meshed surface in model cells, linear vertex colours
 * decoded from the sRGB voxel colours, no normals: viewers compute the flat
 * ones), one node per written instance whose matrix is R * world_from_grid *
 * xform, R turning voxkit's +Z up into glTF's +Y up, (x, y, z) -> (x, z, -y),
 * so a scene stands upright in glTF viewers and a converted glTF file gets its
 * own axes back. Materials: each material id that resolves (vx_svo_material
 * keys, vx_material) to metal, glass or emission is a glTF material
 * (metallic-roughness; KHR_materials_transmission and KHR_materials_ior;
 * emissiveFactor with KHR_materials_emissive_strength), one primitive per
 * material in each mesh; every other cell draws with one white diffuse
 * material that the vertex colours multiply (a scene without such ids is
 * written as before materials were exported). stats may be NULL. */
vx_result vx_conv_svo_to_glb_file(const vx_conv_export_desc* desc, const vx_svo_scene* s, const char* path,
                                  vx_conv_glb_stats* stats, vx_error* err);

/* Lights in the .glb: every stored light (those of emissive voxels are never
 * stored) as a KHR_lights_punctual light on a root node named "light I" (I
 * its index in the scene), placed and aimed in glTF's +Y-up world units as
 * the mesh nodes are. Directional, point and spot carry over in glTF's units
 * (which are voxkit's); the two types glTF lacks become their nearest
 * punctual light: a sphere (radiance L, radius r) a point light of the same
 * power seen from afar, I = L pi r^2; a rect (one-sided, radiance L, area A)
 * a spot along its normal with outer cone pi/2, inner 0 and its on-axis
 * intensity I = L A. Where the punctual light is not voxkit's exact record
 * (sphere, rect, a point or spot radius, a sun's angular diameter, a spot
 * whose inner cone equals its outer, a colour channel over 1), the light's
 * extras hold "voxkit_light" with the exact values (docs/LIBRARY.md), which
 * formats/gltf.h reads back (vox2svo, voxkit.open).
 *
 * The sky in the .glb: glTF has no ratified sky or environment, so a sky
 * other than VX_SKY_DEFAULT goes into the scene's extras as voxkit's own
 * record, {"voxkit_sky": {"type": "constant" | "gradient" | "envmap", ...}}
 * with every field the type uses ("color", "horizon", "ground" as [r, g, b];
 * "path", "intensity", "rotation"; numbers to 17 digits, so they read back
 * as the same doubles), in voxkit's frame (+Z up, as vx_sky: the record is
 * voxkit's, not a glTF environment, and is not turned with the nodes).
 * formats/gltf.h reads it back (vx_gltf_mesh.sky). A DEFAULT sky writes no
 * scene extras (the same bytes as before). An environment map's relative
 * path is rewritten to start from the .glb's folder (vx_sky_rebase from
 * desc.svo_path's folder; unchanged where the two folders are the same or
 * svo_path is NULL),
 * rather than made absolute, so a .glb and its map moved together keep
 * working; VX_ERR_IO when a folder cannot be resolved, VX_ERR_LIMIT when
 * the rewritten path is over VX_SKY_PATH_MAX.
 *
 * Why light l's punctual form differs from the light, for other glTF
 * readers (a phrase such as "sphere light as a point light of the same
 * power"), or NULL when it is the light itself (and for a build without
 * tinygltf). */
const char* vx_conv_glb_light_approx(const vx_light* l);

typedef struct vx_conv_vdb_stats {
    uint32_t grids;  /* grids written (shared ones included) */
    uint64_t voxels; /* active voxels written (a shared tree counted once) */
    bool colors;     /* colour grids written */
} vx_conv_vdb_stats;

/* The scene as OpenVDB grids. Default: the flattened scene (the cells
 * `svo_info --dump` prints) as a fog volume "density" (1, or the model's
 * density attribute) and, when a written model has colours, a vec3 grid
 * "color" (linear RGB decoded from the sRGB voxel colours); index space =
 * grid cells, transform = world_from_grid (shifted half a cell: OpenVDB
 * centres voxel ijk on ijk); overlapping instances: the later one's value.
 * vdb_models: one grid pair "NAME/density", "NAME/color" per written
 * instance (NAME its name, or "instance I"), in model cells with the
 * instance's world map as the transform; instances of one model share its
 * tree (stored once). A cell outside OpenVDB's 32-bit index space is
 * VX_ERR_LIMIT. stats may be NULL. */
vx_result vx_conv_svo_to_vdb_file(const vx_conv_export_desc* desc, const vx_svo_scene* s, const char* path,
                                  vx_conv_vdb_stats* stats, vx_error* err);

#ifdef __cplusplus
}
#endif

#endif /* VX_CONV_EXPORT_H */
