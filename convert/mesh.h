/* convert/mesh.h - triangle meshes (glTF 2.0) to voxels (conservative
 * surface voxelization, optionally solid) and on to an svo scene.
 *
 *   vx_svo_scene s;
 *   vx_conv_mesh_file(&(vx_conv_mesh_desc){ .res = 1024 }, "in.glb", &s, &stats, &err);
 *   vx_svo_write_file(NULL, &s, "out.svo", &err);
 *   vx_svo_scene_free(&s);
 *
 * The grid (vx_conv_mesh_grid_make):
 *   min = the mesh's world bounds' minimum (floats, exact in double). h =
 *   longest extent / res, rounded up to the next double when the division
 *   rounded down, so that res * h >= the extent exactly (a flat or
 *   point-like mesh with longest extent 0 gets h = 1). size[a] = the fewest
 *   cells n >= 1 with n * h >= extent_a, exactly (fma); the longest side
 *   gets exactly res cells. Grid coordinates of a world point p are
 *   g = (p - min) / h, computed in double. So the mesh lies within
 *   [0, size] on every axis, in exact arithmetic as well as in g: the
 *   mesh's min faces have g = 0 exactly, and its max faces are never an
 *   ulp beyond the last cell (they were, with h rounded down: a flat top on
 *   the max bound was voxelized although an exact test puts it outside).
 *   Inside the grid g is the double quotient itself (the specification,
 *   which the tests share): no float rounding of positions or of min.
 *
 * The cells are half-open: cell (i, j, k) is [i, i+1) x [j, j+1) x [k, k+1)
 * in g, except that the last cell along an axis (index size - 1) also
 * holds its max face, [size-1, size]. The cells partition the grid box, so
 * every point of a surface lies in exactly one cell. A cell is set iff
 * some triangle meets its box. Consequences, on purpose:
 *   - A face lying exactly on a cell boundary plane g = k sets one layer,
 *     the cells [k, k+1) on its + side, never both sides: a flat bottom on
 *     the grid's lower bound (or on any boundary) gives exactly one layer
 *     of cells, a flat top on the grid's max bound the last layer.
 *   - A cell that a surface only touches at its max face, edge or corner
 *     is not set (that point belongs to the neighbour), so no cell is set
 *     that does not hold part of the surface; a vertex on a corner shared
 *     by 8 cells sets one of them.
 *   - A face on an interior boundary with its solid below (a flat top at
 *     g = k) lands in the layer above it, k, like a bottom would. That is
 *     the price of a rule that does not depend on the winding.
 * Degenerate triangles (segments, points) set the cells they meet by the
 * same rule. NaN or infinite vertices are an error (VX_ERR_BAD_FORMAT).
 *
 * Solid (desc.solid): a cell whose centre is inside the mesh by a parity
 * count along at least two of the three axes (rays through cell centres) is
 * also set, so a small hole breaks at most one of the three votes. Grids of
 * more than 2^31 cells are refused (VX_ERR_LIMIT) in solid mode.
 *
 * Attributes: colour = baseColorFactor x baseColorTexture (bilinear, sampler
 * wrap modes, sRGB texels converted to linear) x vertex colour, evaluated at
 * the centroid of the part of each triangle inside the cell and averaged
 * in linear space, weighted by the area of that part (exact clipped area);
 * stored as sRGB RGBA8 (alpha linear). Normals (desc.normals): face
 * normals averaged the same way, oct-encoded. Colours are stored only when
 * the input has a material, a texture or vertex colours (and !no_color);
 * an input with none of them gives a geometry-only model. Interior cells of
 * a solid take the attribute of the nearest surface cell before them in
 * their x row within the same 64^3 brick (else the brick's first surface
 * cell, else opaque white / +z).
 *
 * Materials: glTF's metallic = metallicFactor x metallicRoughnessTexture B,
 * roughness = roughnessFactor x its G (linear texels), emission =
 * emissiveFactor x emissiveTexture RGB (sRGB texels, linear) x
 * KHR_materials_emissive_strength; each texture with its own texCoord set,
 * sampler wraps and KHR_texture_transform. They are sampled as the colour is
 * (bilinear, at the centroid of each triangle piece in the cell) and
 * averaged over the cell's pieces, weighted by area. A cell's material is
 * the glTF material of the triangle with the largest piece in the cell; its
 * MATL record, with MagicaVoxel keys, is that material's at the cell's
 * levels: a channel that varies per cell (a decoded texture that is not
 * uniform, under a factor above 0; roughness only where the material can be
 * metal, emissive or transmissive) is quantized to 6 levels of its factor
 * (0, 1/5, ..., 1: the average / factor rounded to the nearest; fewer,
 * 4, 3 or 2, when the ids would pass 65535, else VX_ERR_LIMIT; an emissive
 * texture's R, G and B are each a channel, those whose factor is above 0),
 * one record per (glTF material, levels) combination the cells name; a
 * texture uniform over its image counts as its factor (the file is the
 * equivalent factors' file). A material that varies nothing keeps one record, whether or not
 * cells name it. A cell that is neither metal (level 0) nor emissive nor
 * transmissive stores material 0 (diffuse, no record); a file without
 * metal, emissive or transmissive materials stores no material channel.
 * Ids (VX_ATTR_MATERIAL) are a function of the mesh alone: glTF material i
 * gets a block of 6^k ids, k the channels it varies (an emission's R, G
 * and B counted apart: 6^3 under a white factor; ids index + 1 when no
 * material varies any). The keys (convert/mesh.c, add_materials): _type
 * _glass with _trans, or _metal with _metal, or _emit / _diffuse; _rough;
 * _ior = IOR - 1; _emit = the largest channel of the emission and
 * _emit_color (voxkit's key, svo/svo.h) the emission over _emit, so the
 * emitted light is glTF's whatever the base colour, not MagicaVoxel's
 * colour x _emit. Where an emissive texture varies per cell, that emission
 * is the record's quantized channels, so the emissive texel's own hue is
 * kept (DamagedHelmet's lights over a grey base glow in their own colours)
 * to the levels' precision. A texture that is not decoded (desc.no_color,
 * an unreadable image) leaves metallic 0 or the emission out
 * (formats/gltf.h). The GPU voxelizer samples the textures too (the same
 * ids and file; convert/mesh_gpu.h).
 *
 * Lights: KHR_lights_punctual lights become scene lights (vx_light) in the
 * same world frame as the voxels (world_from_grid maps grid cells back to
 * world units: glTF's, turned +Z up as below); voxkit's own record in a
 * light's extras.voxkit_light (formats/gltf.h; what svo_info --to-glb
 * writes) gives the sphere and rect lights, radii and a sun's angular
 * diameter back; a light that vx_light_validate refuses is an error naming
 * it.
 *
 * Up axis: voxkit's world is +Z up (as MagicaVoxel's; svo_render's and
 * svo_view's default camera, the .vox export); glTF's is +Y up. So
 * vx_conv_mesh_file turns the file's positions, and its lights' positions,
 * directions and tangents, (x, y, z) into (x, -z, y), a rotation about +X by 90
 * degrees (exact in floats), before the grid is made: a model that stands on the glTF ground plane stands on ours, facing
 * the same way (glTF's +Z "front" becomes -Y). desc.y_up keeps the file's
 * axes instead. vx_conv_mesh and vx_conv_mesh_cells voxelize the positions
 * they are given as they are.
 *
 * Scale: the grid is voxelized in 64^3 bricks (triangles binned to bricks,
 * bricks spread over threads), so memory follows the surface, not the
 * volume. Each region of desc.region^3 cells becomes one model, placed
 * with an integer translation in grid space; world_from_grid = scale h,
 * translate min, so `svo_info --dump` prints grid indices.
 */
#ifndef VX_CONVERT_MESH_H
#define VX_CONVERT_MESH_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "convert/convert.h"
#include "convert/file.h"
#include "formats/gltf.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct vx_conv_mesh_desc {
    vx_svo_build_desc build;
    const vx_allocator* alloc;
    const vx_logger* logger;
    uint32_t res;      /* voxels along the longest side; 0 == 256; at most VX_CONV_MESH_RES_MAX */
    bool scene_set;    /* glTF scene `scene` instead of the default scene */
    uint32_t scene;
    bool solid;        /* also fill the inside */
    bool normals;      /* store VX_ATTR_NORMAL */
    bool no_color;     /* never store colours */
    uint32_t threads;  /* 0 == all cores */
    uint32_t region;   /* cells per side of one model, power of two >= 64; 0 == 2048 */
    bool y_up;         /* vx_conv_mesh_file: keep glTF's axes (+Y up); default: turned to +Z up */
    /* NULL == the CPU voxelizer; else another one, e.g. the GPU's
     * (convert/mesh_gpu.h), which gives the same cells and attributes.
     * Borrowed; only for one share (vx_conv_mesh, share 0 of 1). */
    const struct vx_conv_mesh_backend* backend;
} vx_conv_mesh_desc;

typedef struct vx_conv_mesh_grid {
    double min[3];    /* world position of grid point (0, 0, 0) */
    double h;         /* voxel size in world units */
    uint32_t size[3]; /* cells per axis */
} vx_conv_mesh_grid;

/* The grid of a triangle soup (pos: 9 floats per triangle, world space less the
 * mesh's origin, vx_gltf_mesh.origin; grid.min is in the same frame). */
vx_result vx_conv_mesh_grid_make(const float* pos, size_t tri_count, uint32_t res, vx_conv_mesh_grid* out,
                                 vx_error* err);

/* Voxelizes to a flat cell list (for tests and small grids): *out_xyz holds
 * 3 uint32 per set cell (grid indices), in no particular order; *out_rgba
 * (if out_rgba is non-NULL and colours apply) one sRGB RGBA8 per cell,
 * otherwise *out_rgba = NULL. Free with vx_free(desc->alloc, ...). */
vx_result vx_conv_mesh_cells(const vx_conv_mesh_desc* desc, const vx_gltf_mesh* mesh, vx_conv_mesh_grid* out_grid,
                             uint32_t** out_xyz, uint32_t** out_rgba, size_t* out_count, vx_error* err);

/* Voxelizes a loaded mesh into a scene (see the header comment). */
vx_result vx_conv_mesh(const vx_conv_mesh_desc* desc, const vx_gltf_mesh* mesh, vx_svo_scene* out,
                       vx_conv_stats* stats, vx_error* err);

/* Reads a .gltf / .glb (formats/gltf.h), turns it +Z up (unless desc.y_up)
 * and converts it. */
vx_result vx_conv_mesh_file(const vx_conv_mesh_desc* desc, const char* path, vx_svo_scene* out, vx_conv_stats* stats,
                            vx_error* err);
/* The reading half of vx_conv_mesh_file: the mesh, turned +Z up unless
 * desc.y_up. Free with vx_gltf_mesh_free. */
vx_result vx_conv_mesh_read(const vx_conv_mesh_desc* desc, const char* path, vx_gltf_mesh* out, vx_error* err);
/* The mesh options of vx_conv_file's desc (the one mapping vx_conv_file uses). */
vx_conv_mesh_desc vx_conv_mesh_desc_from_file(const vx_conv_file_desc* d);

/* ---- a conversion in shares (vox2svo under mpirun) -----------------------------------
 *
 * vx_conv_mesh is vx_conv_mesh_share(0 of 1) followed by
 * vx_conv_mesh_assemble; a distributed run gives each process one share of
 * the regions and assembles every share's parts in one place, so its scene
 * is the single process's, model for model and byte for byte when written.
 * The partition is a function of the mesh and desc alone (every process
 * bins the triangles itself and computes the same one): regions by their
 * number of surface bricks, the most first, each to the share with the
 * fewest bricks so far (ties to the lower share). A region is one model
 * (desc.region), built whole by the process that voxelizes it, so a share
 * needs the memory of its own regions only. */
typedef struct vx_conv_mesh_part {
    size_t index;              /* the region's index (regions in Morton order) */
    uint32_t origin[3];        /* grid cell of the model's cell (0, 0, 0) */
    vx_svo_model model;        /* owned by the part until vx_conv_mesh_assemble takes it */
    vx_svo_build_stats build;  /* of this model */
    double seconds_build;
    /* The model's occupied box (min inclusive, max exclusive) when the
     * voxelizer knew it (has_box; the GPU build): vx_conv_mesh_assemble then
     * takes the scene's bounds from the boxes instead of a pass over every
     * model. false (zero): unknown. */
    bool has_box;
    uint32_t box_min[3], box_max[3];
    /* The distinct VX_ATTR_MATERIAL ids the model's records hold, ascending
     * (allocated; freed with the part): vx_conv_mesh_assemble writes a MATL
     * record for each id of a material sampled per cell that some part
     * uses. A distributed run carries them with the part's fields. */
    uint16_t* material_ids;
    uint32_t material_id_count;
} vx_conv_mesh_part;

/* The non-empty regions of share `share` (< shares) as parts, in region
 * order; *out (free with vx_conv_mesh_parts_free(desc->alloc, ...)) may be
 * NULL with *count 0 when the share got no region. stats (may be NULL): this
 * share's models and times (seconds_read is kept). */
vx_result vx_conv_mesh_share(const vx_conv_mesh_desc* desc, const vx_gltf_mesh* mesh, uint32_t share,
                             uint32_t shares, vx_conv_mesh_part** out, size_t* count, vx_conv_stats* stats,
                             vx_error* err);
/* The scene of every share's parts (in any order; each region once): models
 * in region order with their instances, materials, lights, world_from_grid
 * and bounds, as vx_conv_mesh makes them. Takes the parts' models (their
 * model fields are zeroed); the array stays the caller's. stats (may be
 * NULL): the parts' sums; seconds_read and seconds_voxelize are kept. */
vx_result vx_conv_mesh_assemble(const vx_conv_mesh_desc* desc, const vx_gltf_mesh* mesh, vx_conv_mesh_part* parts,
                                size_t count, vx_svo_scene* out, vx_conv_stats* stats, vx_error* err);
/* Frees the models still held by parts and the array. */
void vx_conv_mesh_parts_free(const vx_allocator* a, vx_conv_mesh_part* parts, size_t count);

#ifdef __cplusplus
}
#endif
#endif /* VX_CONVERT_MESH_H */
