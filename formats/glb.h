/* formats/glb.h - writes triangle meshes and a node list as a binary glTF
 * 2.0 file (.glb), through Debian's tinygltf (formats/glb_tinygltf.cpp).
 *
 * Everything goes into one buffer (the GLB's BIN chunk): per mesh one
 * primitive of triangles with POSITION (with its min/max), NORMAL and
 * COLOR_0 (linear RGBA, unsigned 16-bit normalized) where given, and 32-bit
 * indices (without NORMAL, glTF viewers compute flat normals), drawn with
 * one opaque material (white base colour, roughness 1, metallic 0) that
 * the vertex colours multiply. Nodes are all roots of the one scene; a
 * node's matrix is column-major, as glTF stores it.
 *
 * Errors: VX_ERR_LIMIT when the buffer would pass the GLB's 4 GiB, VX_ERR_IO
 * when the file cannot be written (nothing is left behind: the file is
 * streamed to a temporary name and renamed).
 */
#ifndef VX_GLB_H
#define VX_GLB_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "svo/core.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct vx_glb_mesh {
    const char* name;       /* may be NULL */
    size_t vertex_count;    /* at least 1 */
    const float* pos;       /* 3 per vertex */
    const float* normal;    /* 3 per vertex, or NULL */
    const uint16_t* color;  /* 4 per vertex (linear RGBA, 65535 = 1), or NULL */
    size_t index_count;     /* a multiple of 3, at least 3 */
    const uint32_t* index;  /* triangles, counter-clockwise seen from the front */
} vx_glb_mesh;

typedef struct vx_glb_node {
    const char* name;       /* may be NULL */
    int32_t mesh;           /* index into meshes, or -1 for none */
    double matrix[16];      /* column-major 4x4 (last row 0 0 0 1) */
} vx_glb_node;

typedef struct vx_glb_scene {
    uint32_t mesh_count;
    const vx_glb_mesh* meshes;
    uint32_t node_count;
    const vx_glb_node* nodes;
    const char* generator;  /* asset.generator, may be NULL */
} vx_glb_scene;

/* desc may be NULL (svo/core.h); its allocator serves the temporary file's
 * name only (tinygltf builds the document with operator new). */
vx_result vx_glb_write_file(const vx_write_desc* desc, const vx_glb_scene* s, const char* path, vx_error* err);

#ifdef __cplusplus
}
#endif
#endif /* VX_GLB_H */
