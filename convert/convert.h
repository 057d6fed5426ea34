/* convert/convert.h - inputs to voxels: every converter produces a
 * vx_svo_scene (models built with vx_svo_build_model, instances, palette,
 * materials) that vx_svo_write_file() stores.
 *
 *   .vox          vx_conv_vox()        (this header)
 *   .gltf / .glb  vx_conv_mesh_file()  (convert/mesh.h)
 *   .vdb          vx_conv_vdb_file()   (convert/volume.h)
 *
 * Conventions shared by all converters:
 *  - Options are *_desc structs, zero-initialised means the defaults; each
 *    embeds a vx_svo_build_desc `build` passed on to the octree builder.
 *  - Grid space: instances map model cells to integer grid cells; the
 *    scene's world_from_grid maps grid cells to world units (identity for
 *    .vox). `svo_info --dump` prints grid cells.
 *  - A model never needs more than VX_SVO_MAX_DEPTH levels: larger inputs
 *    are split into several models placed as instances.
 *  - stats (may be NULL) is filled on success.
 */
#ifndef VX_CONVERT_H
#define VX_CONVERT_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "formats/vox.h"
#include "svo/svo.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct vx_conv_stats {
    uint32_t models, instances;
    uint32_t frames;          /* animation frames stored (1 for a static scene) */
    uint32_t models_unused;   /* .vox: models no instance places (left out, or kept with keep_unused) */
    vx_svo_build_stats build; /* summed over all models */
    double seconds_read;      /* parsing the input file */
    double seconds_voxelize;  /* making voxels (meshes, grids) */
    double seconds_build;     /* octree construction */
    uint64_t peak_bytes;      /* peak resident memory of the process, 0 if unknown */
} vx_conv_stats;

/* .vox scene -> svo scene. An animation read with all_frames (frame_count
 * > 1 and frame_instances) becomes an animated svo scene: frame f of the svo
 * scene is frame f of the vox scene, frame 0 the instances. Each vox model
 * becomes one svo model (instancing kept); each vox instance an instance with M = R, t = t_vox - R floor(s/2)
 * (the MagicaVoxel pivot), so floor(M (v + 1/2) + t) is the MagicaVoxel
 * world cell. Models that no instance places (through the scene graph, for
 * the frames and hidden-node choice the reader made: other animation
 * frames, shapes under hidden nodes, models no shape names) are left out
 * and the others renumbered in their file order, unless keep_unused;
 * stats->models_unused counts them either way. The palette is stored only
 * when some stored voxel uses it; MATL records of the colours stored
 * voxels use become material records; layers are copied. */
typedef struct vx_conv_vox_desc {
    vx_svo_build_desc build;
    const vx_allocator* alloc;
    bool keep_unused; /* also store models no instance places (default: left out) */
} vx_conv_vox_desc;

vx_result vx_conv_vox(const vx_conv_vox_desc* desc, const vx_vox_scene* in, vx_svo_scene* out, vx_conv_stats* stats,
                      vx_error* err);

/* svo scene -> .vox scene, for svo_info --to-vox and export. An animation
 * becomes an animated .vox scene (frame_instances, written as keyframes;
 * its hidden flags must not change between frames). Needs integer
 * signed-permutation instance matrices, integer translations and at most
 * 255 colours: palette models keep their entries, RGBA8 colours take
 * entries of the same colour or ones no palette model uses (a scene may mix
 * both; a geometry-only model's cells are entry 1); otherwise
 * VX_ERR_UNSUPPORTED names what does not fit (more colours:
 * vx_conv_svo_to_vox_ex's quantize).
 * A model of at most 256 cells per side is one .vox model (model i of the
 * scene is .vox model i when all fit). A larger one is split into 256^3
 * tiles from its corner: each tile holding cells becomes a .vox model (a
 * piece, trimmed to its cells' extent; empty tiles are left out), shared
 * by the model's instances; each instance becomes a group (out->groups:
 * the instance's transform as an unsplit model's, pivot floor(size/2),
 * its name and hidden flag) of one shape per piece (identity rotation, the
 * translation that puts every cell where it was, the instance's name and
 * layer). Read back (vx_vox_read, vx_conv_vox), the pieces are instances
 * of their own, in the same world cells. A split model's instance must
 * show that model in every frame (VX_ERR_UNSUPPORTED otherwise); more than
 * VX_VOX_MAX_INSTANCES pieces or shapes are VX_ERR_LIMIT. */
vx_result vx_conv_svo_to_vox(const vx_svo_scene* in, const vx_allocator* alloc, vx_vox_scene* out, vx_error* err);

/* Export options; zero-initialised means vx_conv_svo_to_vox's behaviour. */
typedef struct vx_conv_vox_export_desc {
    const vx_allocator* alloc;
    /* More than 255 distinct colours (else VX_ERR_UNSUPPORTED naming the
     * count): the RGBA8 models' colours are cut (median cut over RGBA, each
     * colour weighted by its cells, deterministic) into the entries the
     * palette models leave free, and every colour takes its nearest entry in
     * use (RGBA distance, ties to the lowest index). Palette models keep
     * their entries; a scene of at most 255 colours is exported exactly,
     * quantize or not. */
    bool quantize;
} vx_conv_vox_export_desc;

/* Filled on VX_OK, and on the refusal of more than 255 colours without
 * quantize (VX_ERR_UNSUPPORTED with colors set), so that a front end can
 * name its own option; otherwise untouched. */
typedef struct vx_conv_vox_export_stats {
    uint32_t colors;   /* the scene's distinct colours, counted when more than 255 (else 0) */
    bool quantized;    /* colours were mapped (quantize and more than 255) */
    double max_error;  /* quantized: the largest RGBA distance (0..510) of a cell's colour to its entry */
    double mean_error; /* quantized: the mean over the RGBA8 models' cells */
} vx_conv_vox_export_stats;

/* vx_conv_svo_to_vox with options (desc may be NULL) and what quantizing
 * did (stats may be NULL). */
vx_result vx_conv_svo_to_vox_ex(const vx_conv_vox_export_desc* desc, const vx_svo_scene* in, vx_vox_scene* out,
                                vx_conv_vox_export_stats* stats, vx_error* err);

#ifdef __cplusplus
}
#endif
#endif /* VX_CONVERT_H */
