/* convert/file.h - any supported input file to an svo scene, chosen by the
 * file's extension: .vox (convert/convert.h), .gltf/.glb (convert/mesh.h),
 * .vdb (convert/volume.h) and, when allowed, .svo (read as it is).
 *
 * One place for the dispatch and the options every reader of scenes takes:
 * vox2svo and svo_view (through tools/common/conv.h) and the Python module
 * (python/voxkit.c) call it. The glTF and OpenVDB converters are optional
 * modules: a build without them fails such files with VX_ERR_UNSUPPORTED.
 *
 *   vx_conv_file_desc d = vx_conv_file_defaults();   (or {0}: the same)
 *   d.res = 512;
 *   vx_conv_file(&d, "duck.glb", &scene, &stats, &err);
 */
#ifndef VX_CONVERT_FILE_H
#define VX_CONVERT_FILE_H

#include <stdbool.h>
#include <stdint.h>

#include "convert/convert.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The largest mesh resolution (vx_conv_file_desc.res, vx_conv_mesh_desc.res):
 * a grid of 2^16 cells along the longest side. */
#define VX_CONV_MESH_RES_MAX 65536u

/* Zero-initialised means the defaults (vx_conv_file_defaults). */
typedef struct vx_conv_file_desc {
    vx_svo_build_desc build;  /* every converter: no_collapse, no_dag, progress */
    const vx_allocator* alloc; /* every reader and converter, and the scene's arrays (NULL: malloc) */
    const vx_logger* logger;  /* warnings of the readers */
    bool allow_svo;           /* also read .svo files (default: an error) */
    /* .vox (formats/vox.h, convert/convert.h) */
    uint32_t frame;           /* with one_frame: that animation frame, default 0 */
    bool one_frame;           /* only `frame` (default: every frame of an animation, FRMS) */
    bool keep_hidden;         /* keep hidden nodes, groups and layers */
    bool keep_unused;         /* also store models no instance places */
    /* .gltf / .glb (convert/mesh.h) */
    uint32_t res;             /* voxels along the longest side, 0 == 256, at most VX_CONV_MESH_RES_MAX */
    bool scene_set;           /* glTF scene `scene` instead of the default one */
    uint32_t scene;
    bool normals;             /* store VX_ATTR_NORMAL */
    bool no_color;            /* never store colours */
    uint32_t threads;         /* 0 == all cores */
    uint32_t region;          /* cells per side of one model (convert/mesh.h), power of two >= 64; 0 == 2048 */
    bool y_up;                /* keep glTF's +Y up (default: turned to voxkit's +Z up) */
    const struct vx_conv_mesh_backend* mesh_backend; /* NULL: the CPU voxelizer (convert/mesh.h, backend) */
    /* .gltf / .glb and .vdb */
    bool solid;               /* fill the inside (meshes, level sets) */
    /* .vdb (convert/volume.h) */
    const char* grid;         /* NULL: the first float or double grid */
    bool threshold_set;       /* fog volumes: cells with value >= threshold */
    double threshold;
    bool density;             /* keep the value as VX_ATTR_DENSITY */
    const char* color_grid;   /* a vec3 grid's name for colours, NULL: none */
} vx_conv_file_desc;

/* The defaults, field by field (the tools' --help prints them): .vox frame
 * every frame (one_frame: frame 0) without hidden nodes or unused models; glTF at res 256, default scene,
 * surface only, colours, no normals, all cores; .vdb: first scalar grid, no
 * threshold, density or colours. */
vx_conv_file_desc vx_conv_file_defaults(void);

/* ".vox", ".gltf", ".glb", ".vdb" or ".svo" by the path's extension
 * (case-insensitive), NULL for anything else. */
const char* vx_conv_file_kind(const char* path);

/* Reads and converts path by its extension. stats (may be NULL) is filled on
 * success (.svo: zero but for seconds_read and peak_bytes). Errors say what
 * is wrong; the caller adds the path, as for every reader. */
vx_result vx_conv_file(const vx_conv_file_desc* desc, const char* path, vx_svo_scene* out, vx_conv_stats* stats,
                       vx_error* err);

#ifdef __cplusplus
}
#endif
#endif /* VX_CONVERT_FILE_H */
