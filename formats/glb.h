/* formats/glb.h - writes triangle meshes and a node list as a binary glTF
 * 2.0 file (.glb), through Debian's tinygltf (formats/glb_tinygltf.cpp).
 *
 * Everything goes into one buffer (the GLB's BIN chunk): per mesh one
 * primitive of triangles with POSITION (with its min/max), NORMAL and
 * COLOR_0 (linear RGBA, unsigned 16-bit normalized) where given, and 32-bit
 * indices (without NORMAL, glTF viewers compute flat normals). Materials:
 * with material_count 0, one opaque material "voxel" (white base colour,
 * roughness 1, metallic 0) that the vertex colours multiply, drawing every
 * mesh as one primitive (the output of a zero-initialised scene is the same
 * bytes as before materials existed). With materials, each is written as
 * given (vx_glb_material), and a mesh with primitives is drawn as those
 * index ranges, each with its material; the vertex attributes are shared by
 * the mesh's primitives. Extensions are declared in extensionsUsed where a
 * material needs them: KHR_materials_emissive_strength (strength > 1),
 * KHR_materials_transmission (transmission > 0), KHR_materials_ior (with
 * transmission, ior != 1.5). Nodes are all roots of the one scene; a node's
 * matrix is column-major, as glTF stores it.
 *
 * Lights (vx_glb_light): with light_count > 0, KHR_lights_punctual's light
 * list (declared in extensionsUsed) and after the scene's nodes one root
 * node per light placing it (the node's name is the light's). A scene
 * without lights writes neither (the same bytes as before lights existed).
 *
 * Scene extras (scene_extras): glTF has no ratified sky or environment, so
 * voxkit's sky goes into scenes[0].extras as its own record, as the lights'
 * records go into their extras.
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

/* A metallic-roughness material. Factors are glTF's: base_color linear
 * RGBA, emissive linear RGB in [0, 1] times emissive_strength (written as
 * KHR_materials_emissive_strength only when > 1: brighter emission is the
 * factor at its largest channel 1 and the rest in the strength). */
typedef struct vx_glb_material {
    const char* name;         /* may be NULL */
    float base_color[4];
    float metallic, roughness;
    float emissive[3];
    float emissive_strength;  /* <= 1: none (the factor alone) */
    float transmission;       /* KHR_materials_transmission when > 0 */
    float ior;                /* KHR_materials_ior with transmission, when != 1.5 (0: 1.5) */
} vx_glb_material;

/* A range of a mesh's indices drawn with one material. */
typedef struct vx_glb_primitive {
    size_t index_first, index_count; /* multiples of 3, count at least 3 */
    uint32_t material;               /* index into the scene's materials */
} vx_glb_primitive;

typedef struct vx_glb_mesh {
    const char* name;       /* may be NULL */
    size_t vertex_count;    /* at least 1 */
    const float* pos;       /* 3 per vertex */
    const float* normal;    /* 3 per vertex, or NULL */
    const uint16_t* color;  /* 4 per vertex (linear RGBA, 65535 = 1), or NULL */
    size_t index_count;     /* a multiple of 3, at least 3 */
    const uint32_t* index;  /* triangles, counter-clockwise seen from the front */
    uint32_t primitive_count; /* 0: one primitive of all indices with material 0 */
    const vx_glb_primitive* primitives;
} vx_glb_mesh;

typedef struct vx_glb_node {
    const char* name;       /* may be NULL */
    int32_t mesh;           /* index into meshes, or -1 for none */
    double matrix[16];      /* column-major 4x4 (last row 0 0 0 1) */
} vx_glb_node;

/* KHR_lights_punctual's types. */
typedef enum vx_glb_light_type {
    VX_GLB_LIGHT_DIRECTIONAL = 0,
    VX_GLB_LIGHT_POINT,
    VX_GLB_LIGHT_SPOT,
    VX_GLB_LIGHT_TYPE_COUNT
} vx_glb_light_type;

/* A KHR_lights_punctual light, in the extension's terms (the writer checks
 * them and refuses others with VX_ERR_INVALID_ARG naming the light):
 *  color       linear RGB, each in [0, 1] (the schema's range)
 *  intensity   >= 0: candela (point, spot) or lux (directional)
 *  range       point, spot: > 0 a cut-off distance, 0 none (not written)
 *  inner_cone, outer_cone  spot: radians, 0 <= inner < outer <= pi/2
 *  matrix      the node that places it (column-major, as vx_glb_node's);
 *              the light sits at its origin and shines down its -Z axis
 *  extras      NULL, or a JSON object (text) written as the light's
 *              "extras" (svo_info keeps voxkit's own record of the light
 *              there); anything else is VX_ERR_INVALID_ARG
 * Values the type does not use are not written. */
typedef struct vx_glb_light {
    const char* name;       /* the light's and its node's, may be NULL */
    vx_glb_light_type type;
    double color[3];
    double intensity;
    double range;
    double inner_cone, outer_cone;
    double matrix[16];
    const char* extras;
} vx_glb_light;

typedef struct vx_glb_scene {
    uint32_t mesh_count;
    const vx_glb_mesh* meshes;
    uint32_t node_count;
    const vx_glb_node* nodes;
    const char* generator;  /* asset.generator, may be NULL */
    uint32_t material_count; /* 0: the one default material (above) */
    const vx_glb_material* materials;
    uint32_t light_count;   /* 0: no KHR_lights_punctual */
    const vx_glb_light* lights;
    /* NULL, or a JSON object (text) written as the scene's "extras"
     * (scenes[0]; svo_info keeps voxkit's record of the sky there); anything
     * else is VX_ERR_INVALID_ARG. NULL writes the same bytes as before the
     * field existed. */
    const char* scene_extras;
} vx_glb_scene;

/* desc may be NULL (svo/core.h); its allocator serves the temporary file's
 * name only (tinygltf builds the document with operator new). */
vx_result vx_glb_write_file(const vx_write_desc* desc, const vx_glb_scene* s, const char* path, vx_error* err);

#ifdef __cplusplus
}
#endif
#endif /* VX_GLB_H */
