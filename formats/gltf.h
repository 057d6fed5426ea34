/* formats/gltf.h - glTF 2.0 (.gltf / .glb) triangle meshes for voxelization.
 *
 * A thin C face over tinygltf (formats/gltf_tinygltf.cpp). It flattens a
 * scene into one triangle soup in world space: every mesh instance reached
 * from the scene's root nodes, with the node transforms applied; strips and
 * fans become triangles; indexed and non-indexed primitives; float and
 * normalized-integer (KHR_mesh_quantization) attributes. Points and lines
 * are skipped (logged). Skins and morph targets are ignored (bind pose).
 *
 *   vx_gltf_mesh m;
 *   vx_gltf_read_file(&(vx_gltf_read_desc){0}, "in.glb", &m, &err);
 *   ... m.pos[9 * t + 3 * v + axis] ...
 *   vx_gltf_mesh_free(&m);
 *
 * Errors: a malformed file (bad accessor or buffer-view ranges, bad
 * indices, node cycles, bad lights) is VX_ERR_BAD_FORMAT; a required extension that is
 * not implemented (KHR_draco_mesh_compression, EXT_meshopt_compression, ...)
 * is VX_ERR_UNSUPPORTED with the extension's name in the message; NaN or
 * infinite positions are VX_ERR_BAD_FORMAT. Everything returned is copied
 * into blocks from desc.alloc; the input is not kept.
 */
#ifndef VX_GLTF_H
#define VX_GLTF_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "svo/svo.h" /* vx_sky */

#ifdef __cplusplus
extern "C" {
#endif

/* Distance from 0 at which vx_gltf_mesh.origin moves off 0 (see there). */
#define VX_GLTF_ORIGIN_FAR 4096.0

/* Sampler wrap modes. */
enum { VX_GLTF_WRAP_REPEAT = 0, VX_GLTF_WRAP_CLAMP = 1, VX_GLTF_WRAP_MIRROR = 2 };

typedef struct vx_gltf_image {
    uint32_t width, height;
    uint8_t* rgba; /* width * height * 4 bytes, rows top to bottom, as stored (sRGB for colour) */
} vx_gltf_image;

/* A texture a material samples besides the base colour: its decoded image
 * (-1: none, or the texture could not be decoded: see vx_gltf_material)
 * and its sampler's wrap modes. Its texture coordinates (the texture
 * info's texCoord set and KHR_texture_transform) are vx_gltf_mesh's uv_mr /
 * uv_emissive. */
typedef struct vx_gltf_tex {
    int32_t image;
    uint8_t wrap_s, wrap_t; /* VX_GLTF_WRAP_* */
} vx_gltf_tex;

typedef struct vx_gltf_material {
    float base_color[4];    /* baseColorFactor (linear), default 1 1 1 1 */
    int32_t image;          /* baseColorTexture's decoded image, -1 if none */
    uint8_t wrap_s, wrap_t; /* VX_GLTF_WRAP_* */
    /* The rest of the metallic-roughness model, clamped to the ranges the
     * extensions give (non-finite values fall back to the default):
     * metallic, roughness: the factors (default 1 1). With a
     *   metallicRoughnessTexture that was decoded (metal_rough.image >= 0)
     *   the glTF values are metallic x texel B and roughness x texel G
     *   (linear, not sRGB); one that was not (desc.no_images, an unreadable
     *   image) leaves metallic 0: the texture says where the metal is, the
     *   factor alone would turn the whole material into metal.
     * emissive: emissiveFactor x KHR_materials_emissive_strength (linear
     *   radiance scale; default 0 0 0). With an emissiveTexture that was
     *   decoded (emissive_tex.image >= 0) the glTF value is emissive x the
     *   texel's RGB (sRGB-encoded, converted to linear); one that was not
     *   leaves 0 0 0 with the warning "gltf.emissive_texture" naming the
     *   material (the factor alone would light the whole material).
     * transmission: KHR_materials_transmission's factor (default 0)
     * ior: KHR_materials_ior (default 1.5, at least 1) */
    float metallic, roughness;
    float emissive[3];
    float transmission;
    float ior;
    vx_gltf_tex metal_rough; /* metallicRoughnessTexture */
    vx_gltf_tex emissive_tex; /* emissiveTexture */
} vx_gltf_material;

/* Light types: KHR_lights_punctual's three (the extension's strings), and
 * voxkit's sphere and rect, which only extras.voxkit_light gives (below). */
enum {
    VX_GLTF_LIGHT_DIRECTIONAL = 0,
    VX_GLTF_LIGHT_POINT = 1,
    VX_GLTF_LIGHT_SPOT = 2,
    VX_GLTF_LIGHT_SPHERE = 3,
    VX_GLTF_LIGHT_RECT = 4
};

/* A light placed by a node of the flattened scene (one per node that names
 * one), in world space: the node's world matrix applied to the origin and
 * to -Z, the direction the light points along (normalized). Properties are
 * the extension's, not scaled by the node (as the extension says).
 *
 * voxkit's record: svo_info --to-glb writes, where the punctual light is not
 * voxkit's light (a sphere or rect, a soft-shadow radius or angular
 * diameter, equal spot cones, a colour over 1), the exact values in the
 * light's "extras": {"voxkit_light": {"type": T, ...}} with T one of
 * "directional", "point", "spot" (the punctual type) or "sphere" (on a
 * point light), "rect" (on a spot), and the members
 *   "radiance"          sphere, rect (required): W/m^2/sr, the intensity
 *   "radius"            sphere (required), point, spot: world units
 *   "size": [w, h]      rect (required): edges along the node's +X (the
 *                       tangent) and along direction x tangent
 *   "angular_diameter"  directional: radians, below pi
 *   "inner_cone", "outer_cone"  spot: radians, 0 <= inner <= outer <= pi/2
 *   "color": [r, g, b]  the colour (>= 0) where a channel was over 1
 *   "intensity"         directional, point, spot: the exact intensity
 * Unless desc.punctual_only, the reader honours it: type, intensity,
 * colour, cones, radius, angular_diameter, size and tangent are then the
 * record's (voxkit = true). A member of the wrong type or out of range is
 * VX_ERR_BAD_FORMAT naming the light; other members are ignored. A record
 * of an unknown type, or one that does not match the punctual type (a
 * light retyped in an editor that kept the extras), is ignored with the
 * warning "gltf.light_extras": the punctual light stands. */
typedef struct vx_gltf_light {
    uint32_t type;         /* VX_GLTF_LIGHT_* */
    double position[3];
    double direction[3];   /* where it shines (directional, spot, rect: its normal) */
    double color[3];       /* linear, default 1 1 1 */
    double intensity;      /* candela (point, spot), lux (directional), radiance (sphere, rect); default 1 */
    double range;          /* point, spot; 0: none */
    double inner_cone, outer_cone; /* spot, radians: 0 <= inner < outer <= pi/2 (default 0, pi/4) */
    uint32_t index, node;  /* in KHR_lights_punctual.lights, and the node */
    char name[64];         /* truncated */
    /* voxkit's record only (0 otherwise): */
    bool voxkit;           /* the values above come from extras.voxkit_light */
    double radius;         /* sphere: its radius; point, spot: the source's (soft shadows) */
    double angular_diameter; /* directional: radians */
    double tangent[3];     /* rect: the node's +X axis (normalized), its first edge */
    double size[2];        /* rect: the edges along tangent and direction x tangent */
} vx_gltf_light;

/* Triangle soup of one scene. Per triangle t and corner v (0..2):
 *   pos[9t + 3v + a]   world-space position less origin (a = x, y, z)
 *   uv[6t + 2v + c]    the texture coordinates the triangle's material samples
 *                      its base colour with, its KHR_texture_transform applied
 *                      (0 0 where the primitive has none); NULL if no material
 *                      of the scene has a decoded base colour texture
 *   uv_mr, uv_emissive the same for the metallicRoughnessTexture and the
 *                      emissiveTexture (each its own texCoord set and
 *                      transform); NULL if no material has that texture
 *   color[12t + 4v + c] linear RGBA vertex colour COLOR_0 (1 1 1 1 where the
 *                      primitive has none); NULL if no primitive has COLOR_0
 *   material[t]        index into materials, or UINT32_MAX when the primitive
 *                      names none (the glTF default: white, no texture)
 * origin: pos is relative to it (world = origin + pos, in double): 0 0 0,
 *   except on an axis where the first vertex lies VX_GLTF_ORIGIN_FAR or more
 *   units from 0; there that vertex's coordinate rounded to a multiple of
 *   1024. A scene far from the origin (georeferenced: translations of 1e6)
 *   so keeps float precision (at 6e6 floats are 0.5 apart: a 3-unit model
 *   lost a fifth of its voxels); near the origin nothing changes. Where
 *   rounding moved positions by more than 2^-10 of the scene's extent
 *   before they reach pos (the file's float coordinates, 2^-24 of each;
 *   the double sum with a node's translation, 2^-52 of it: a small model
 *   translated to 1e30 collapses to a point), or every triangle lies at one
 *   point, the read succeeds with the warning "gltf.position_precision".
 * lights: KHR_lights_punctual lights of the scene's nodes, in visiting order.
 * A light with an unknown type, a negative or non-finite intensity, colour
 * or range, cone angles out of order, or a node that puts it at a
 * non-finite position or gives it no direction is VX_ERR_BAD_FORMAT, the
 * message naming the light ("light 2 ('lamp') on node 5: ...").
 * sky: glTF has no ratified sky, so svo_info --to-glb keeps voxkit's sky in
 * the scene's "extras": {"voxkit_sky": {"type": T, ...}} with T one of
 * "constant" ("color": [r, g, b]), "gradient" ("color" the zenith,
 * "horizon", "ground") or "envmap" ("path", "intensity", "rotation"), every
 * member the type uses required, others ignored. It is voxkit's record in
 * voxkit's frame (+Z up, svo/svo.h's vx_sky), not turned with the nodes;
 * an envmap's relative path starts from the glTF file's folder. Read from
 * the flattened scene's extras unless desc.punctual_only (a file read
 * without a scene has no sky); an unknown type, a missing member, a colour
 * that is not three numbers >= 0, a path that is empty, over
 * VX_SKY_PATH_MAX bytes or not a string, or a sky vx_sky_validate refuses
 * is VX_ERR_BAD_FORMAT naming it ("scene 0 extras voxkit_sky: ..."). */
typedef struct vx_gltf_mesh {
    size_t tri_count;
    float* pos;            /* relative to origin */
    float* uv;
    float* uv_mr;
    float* uv_emissive;
    float* color;
    uint32_t* material;
    uint32_t material_count;
    vx_gltf_material* materials;
    uint32_t image_count;
    vx_gltf_image* images; /* only images used as baseColorTexture, metallicRoughnessTexture or
                              emissiveTexture are decoded; others have rgba NULL */
    double origin[3];      /* world position of pos's 0 0 0 (see above) */
    uint32_t scene;        /* the scene that was flattened (UINT32_MAX: no scene, all root nodes) */
    uint32_t instance_count; /* mesh instances flattened */
    uint32_t light_count;
    vx_gltf_light* lights;
    vx_sky sky;            /* voxkit's record of the sky (below); VX_SKY_DEFAULT when absent */
    const vx_allocator* alloc;
} vx_gltf_mesh;

/* Options; zero means default. */
typedef struct vx_gltf_read_desc {
    const vx_allocator* alloc;
    const vx_logger* logger;
    bool scene_set;         /* use `scene` instead of the file's default scene */
    uint32_t scene;
    bool no_images;         /* do not decode textures (materials keep image = -1) */
    bool no_external;       /* refuse external files (buffers / images by URI) */
    uint64_t max_triangles; /* 0 == 2^28 */
    uint64_t max_image_pixels; /* per image, 0 == 2^26 */
    bool punctual_only;     /* ignore extras.voxkit_light and voxkit_sky: the file as other glTF readers see it */
} vx_gltf_read_desc;

/* Parses a .glb or .gltf held in memory. base_dir (may be NULL: no external
 * files) is where relative URIs are resolved. */
vx_result vx_gltf_read(const vx_gltf_read_desc* desc, const void* data, size_t size, const char* base_dir,
                       vx_gltf_mesh* out, vx_error* err);
/* Reads a file (external files resolved next to it unless no_external). */
vx_result vx_gltf_read_file(const vx_gltf_read_desc* desc, const char* path, vx_gltf_mesh* out, vx_error* err);
void vx_gltf_mesh_free(vx_gltf_mesh* m);

#ifdef __cplusplus
}
#endif
#endif /* VX_GLTF_H */
