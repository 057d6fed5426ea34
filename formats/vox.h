/* formats/vox.h - MagicaVoxel .vox reader and writer.
 *
 * Reads versions 150 and 200: MAIN, PACK, SIZE, XYZI, RGBA, MATT, MATL, nTRN,
 * nGRP, nSHP, LAYR, IMAP, rOBJ, rCAM, NOTE, META; unknown chunks are skipped
 * by their declared sizes. Teardown's variant too: a model's voxels in a
 * TDCZ chunk after its SIZE (the sizes again, then a zlib stream of one
 * colour index per cell, x fastest, 0 empty; accepted once it has given
 * every cell, as Teardown leaves it unterminated; refused when its sizes
 * differ from SIZE's or it ends early), and an RGBA chunk of fewer than 256
 * entries (Teardown writes 255): indices it lacks keep the default colours.
 *
 * Data model (as MagicaVoxel shows the scene):
 *  - Models hold voxels as (x, y, z, i) bytes; z is up; i in 1..255 is the
 *    colour index, RGBA entry i-1 of the file (or the default palette).
 *    palette[i] below is already that colour, so palette[0] is unused.
 *  - The scene graph (nTRN -> nGRP/nSHP) is flattened into instances: one per
 *    shape reached from the root, with the rotations R and translations t of
 *    every transform node from the shape up to the root composed:
 *        world(p) = R_root(...(R_shape p + t_shape)...) + t_root
 *    A voxel at cell v of a model of size s lands in the world cell
 *        floor(R (v + 1/2 - floor(s/2)) + t)
 *    with the composed R (a signed permutation, mirrors included) and t.
 *    A group (or transform) that several transform nodes point at, as
 *    MagicaVoxel writes an instanced group, is placed once per path from the
 *    root: each shape under it gives one instance per copy (at most
 *    VX_VOX_MAX_INSTANCES, else VX_ERR_LIMIT); a cycle is an error.
 *  - Hidden transform nodes, groups and layers are left out unless
 *    keep_hidden is set. The instance then carries hidden = true when its
 *    transform, a node above it or the layer of a transform above it is
 *    hidden; a shape hidden by its own transform's layer only keeps hidden =
 *    false, the flag being that layer's (layers[]): it is shown when
 *    neither is set.
 *  - Animation: keyframe values (_f) on nTRN and model keys on nSHP are
 *    taken for `frame` (the last key at or before it; the first if none).
 *    The animation has frame_count frames: the largest _f key + 1, or, in a
 *    file without a scene graph, one frame per model (a PACK sequence).
 *    With all_frames the reader flattens every frame (frame_instances); the
 *    instance list is the same shapes in the same order in every frame, so
 *    record i of each frame is one shape over time.
 *  - Files without a scene graph show one model at the identity (model 0, or
 *    model `frame` for PACK animations), with the same pivot rule.
 *  - A model used by several shapes stays one model with several instances.
 *
 * Usage: vx_vox_read() -> use scene -> vx_vox_scene_free(). The scene owns
 * copies of everything; the input buffer is borrowed only during the call.
 * Ownership: every array (models, each models[i].xyzi, instances, layers,
 * materials, each materials[i].dict) is a separate block from scene->alloc,
 * so a scene assembled by other code (for the writer) is freed the same way.
 */
#ifndef VX_VOX_H
#define VX_VOX_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "svo/core.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct vx_vox_model {
    uint32_t size[3];     /* 1..max_dim each */
    uint32_t voxel_count;
    uint8_t* xyzi;        /* 4 bytes per voxel: x, y, z, colour index (1..255) */
} vx_vox_model;

/* Rotation/mirror as a row-major 3x3 matrix with entries -1, 0, 1 (one
 * non-zero per row and column). */
typedef struct vx_vox_instance {
    uint32_t model;
    int32_t rot[9];
    int32_t t[3];
    int32_t layer;    /* layer id, -1 for none */
    bool hidden;      /* only when keep_hidden was set; its own layer's flag is the layer's (above) */
    char name[64];    /* _name of the shape's transform node, may be empty */
    /* Writer only (the reader flattens groups and leaves 0): 0 for a shape
     * under the root group, g >= 1 for one under groups[g - 1], its rot
     * and t then relative to that group's transform. */
    uint32_t group;
} vx_vox_instance;

/* A group the writer puts under the root group (vx_conv_svo_to_vox's model
 * split into pieces): its transform node carries rot, t, name, layer and
 * the hidden flag; the instances whose group names it are its children.
 * Read back, its shapes come out as instances with the composed transform
 * (R_group R, R_group t + t_group), hidden when the group is. */
typedef struct vx_vox_group {
    int32_t rot[9];
    int32_t t[3];
    int32_t layer; /* -1 for none */
    bool hidden;
    char name[64];
} vx_vox_group;

typedef struct vx_vox_layer {
    int32_t id;
    bool hidden;
    char name[64];
    uint32_t rgba; /* _color, 0 if none */
} vx_vox_layer;

/* MATL (v200) and MATT (v150) both become a dictionary of NUL-terminated
 * strings key0 value0 key1 value1 ... (MATT is translated to MATL keys). */
typedef struct vx_vox_material {
    uint32_t id; /* palette index 0..255 */
    uint32_t dict_size;
    char* dict;
} vx_vox_material;

/* The scene graph as stored, kept for the writer and for inspection. */
typedef enum vx_vox_node_type { VX_VOX_NODE_TRN = 1, VX_VOX_NODE_GRP, VX_VOX_NODE_SHP } vx_vox_node_type;

typedef struct vx_vox_scene {
    uint32_t version;            /* 150, 200, ... as stored */
    uint32_t model_count;
    vx_vox_model* models;
    uint32_t instance_count;
    vx_vox_instance* instances;  /* flattened scene graph for the chosen frame */
    uint32_t layer_count;
    vx_vox_layer* layers;
    uint32_t material_count;
    vx_vox_material* materials;
    bool has_rgba;               /* false: palette is the default palette */
    uint32_t palette[256];       /* RGBA8 (R in low byte) by colour index; [0] unused */
    bool has_imap;
    uint8_t imap[256];
    bool has_scene_graph;
    uint32_t node_count;         /* nTRN + nGRP + nSHP chunks */
    uint32_t camera_count;       /* rCAM chunks */
    uint32_t note_count;         /* NOTE entries */
    uint32_t robj_count;         /* rOBJ chunks */
    uint32_t frame_count;        /* frames of the animation, 1 for a still scene */
    /* all_frames and frame_count > 1: frame_count * instance_count records,
     * frame f's at frame_instances + f * instance_count (else NULL) */
    vx_vox_instance* frame_instances;
    /* Writer only, the reader leaves them 0/NULL: groups under the root
     * (group_count records); an animation's frame f at frame_groups + f *
     * group_count (NULL: groups[] in every frame). A separate block from
     * alloc each, freed with the scene. */
    uint32_t group_count;
    vx_vox_group* groups;
    vx_vox_group* frame_groups;
    const vx_allocator* alloc;
} vx_vox_scene;

/* Read options; zero-initialised means the defaults. */
typedef struct vx_vox_read_desc {
    const vx_allocator* alloc;
    const vx_logger* logger;  /* warnings (skipped voxels, unknown chunks) */
    uint32_t frame;           /* animation frame, default 0 */
    bool all_frames;          /* also flatten every frame into frame_instances */
    bool keep_hidden;         /* keep hidden nodes, groups and layers */
    uint32_t max_dim;         /* 0 == 256: larger SIZE values are rejected */
    uint64_t max_voxels;      /* 0 == 1<<28 voxels in all models together */
} vx_vox_read_desc;

/* Most instances one frame's scene graph may place (shared groups multiply
 * them), else VX_ERR_LIMIT. */
#define VX_VOX_MAX_INSTANCES (1u << 20)

/* all_frames: at most this many frames, and frame records of at most
 * VX_VOX_FRAMES_MAX_BYTES (else VX_ERR_LIMIT: convert single frames). */
#define VX_VOX_MAX_FRAMES 65536u
#define VX_VOX_FRAMES_MAX_BYTES ((uint64_t)256 << 20)

vx_result vx_vox_read(const vx_vox_read_desc* desc, const void* data, size_t size, vx_vox_scene* out, vx_error* err);
vx_result vx_vox_read_file(const vx_vox_read_desc* desc, const char* path, vx_vox_scene* out, vx_error* err);
void vx_vox_scene_free(vx_vox_scene* scene);

/* The MagicaVoxel default palette (RGBA8 by colour index, [0] = 0). */
extern const uint32_t vx_vox_default_palette[256];

/* Rotation byte <-> matrix. Returns false for an invalid byte/matrix. */
bool vx_vox_rot_from_byte(uint8_t b, int32_t rot[9]);
bool vx_vox_rot_to_byte(const int32_t rot[9], uint8_t* out);

/* World cell of cell v of a model of size s under (rot, t):
 * floor(R (v + 1/2 - floor(s/2)) + t), computed exactly in integers. */
void vx_vox_place(const int32_t rot[9], const int32_t t[3], const uint32_t size[3], const uint32_t v[3],
                  int32_t out[3]);

/* Checks a scene before writing: sizes 1..256, voxel coordinates inside
 * their model, indices 1..255, instance model ids and rotations valid,
 * group indices in range, group rotations valid. */
vx_result vx_vox_validate(const vx_vox_scene* s, vx_error* err);

/* Writes version 150 with a scene graph (root nTRN -> nGRP -> one nTRN +
 * nSHP per instance, or per group an nTRN -> nGRP -> one nTRN + nSHP per
 * instance of the group, placed where the group's first instance comes;
 * groups without instances last), RGBA when has_rgba, LAYR and MATL
 * records. Node ids run 0, 1, 2, ... in the order the chunks are written. A single
 * model with one identity instance is written the same way. An animation
 * (frame_count > 1 and frame_instances; `instances` is then not used) is
 * written as keyframes (_f) on each instance's nTRN and nSHP, which the
 * reader reads back as the same frames; names, layers and hidden flags must
 * be the same in every frame (VX_ERR_UNSUPPORTED otherwise), and so must an
 * instance's group; a group's transform is keyed as an instance's. */
vx_result vx_vox_write(const vx_vox_scene* s, const vx_allocator* alloc, uint8_t** out_data, size_t* out_size,
                       vx_error* err);
/* The same through a temporary file renamed over path (svo/core.h
 * vx_file_write_atomic); desc may be NULL. */
vx_result vx_vox_write_file(const vx_write_desc* desc, const vx_vox_scene* s, const char* path, vx_error* err);

#ifdef __cplusplus
}
#endif
#endif /* VX_VOX_H */
