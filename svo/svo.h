/* svo/svo.h - sparse voxel octrees: build, minimize, read, write, decode.
 *
 * A scene is a set of models (one octree each) placed by instances. All
 * coordinates of a model are integer cells (x, y, z) in [0, size). A model's
 * octree covers the cube [0, 2^depth)^3 with 2^depth >= max(size).
 *
 * Octant numbering: child o of a node covers the half-cube whose offset is
 * (o & 1, (o >> 1) & 1, (o >> 2) & 1) times half the node size. Morton keys
 * interleave bits the same way: bit 3i is x_i, bit 3i+1 is y_i, bit 3i+2 is
 * z_i, so (key >> 3k) & 7 is the octant at level k (level 0 = single cells).
 *
 * The node array (Laine-Karras child descriptors), per model, 32-bit words:
 *   descriptor: bits 31..17 child pointer p (15 bits), bit 16 far flag,
 *               bits 15..8 valid mask, bits 7..0 leaf mask (leaf is a subset
 *               of valid). A leaf child is a single cell or a uniform full
 *               cube (collapsed subtree); leaves have no descriptor.
 *   children block of a descriptor at word i (present when it has a
 *   non-leaf child or the model has attributes):
 *       block = far ? nodes[i - p] : i - p            (p >= 1; pointers go
 *       backwards, so children always precede parents: no cycles possible)
 *       nodes[block + k], k < popcount(valid & ~leaf): descriptors of the
 *           non-leaf children in octant order;
 *       nodes[block + popcount(valid & ~leaf)]: the attribute index a, when
 *           the model has attributes: valid child o has attribute record
 *           a + popcount(valid & ((1 << o) - 1)).
 *   With the far flag, nodes[i - p] is a far slot holding the absolute word
 *   index of the block (a far pointer table entry stored just before the
 *   block that uses it). Identical subtrees share one block (a DAG).
 * docs/FORMAT.md specifies the file layout byte by byte.
 *
 * Usage: fill vx_svo_voxels per model -> vx_svo_build_model() -> put models
 * and instances into a vx_svo_scene -> vx_svo_write_file(); later
 * vx_svo_read_file() -> vx_svo_decode_model() -> vx_svo_scene_free().
 */
#ifndef VX_SVO_H
#define VX_SVO_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "svo/core.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The newest version this library reads (it reads 1..6). A writer stamps a
 * file with the lowest version that has all its sections: 2 only when it
 * holds a section introduced in version 2 (LGHT, FRMS), 3 or 4 only with a
 * model in the chunked form (DEFLATE chunks, or zstd-tagged ones), so files
 * without one keep the bytes of version 1 (docs/FORMAT.md 6). */
#define VX_SVO_FORMAT_VERSION 6u
#define VX_SVO_MAX_DEPTH 21u /* Morton keys are 63 bits; the tracer handles up to 23 */

/* Attribute channels (bitmask). Each model stores one record per attribute
 * index, with a value in every channel its mask names. */
enum {
    VX_ATTR_PALETTE = 1u << 0,  /* uint8_t index into the scene palette (1..255) */
    VX_ATTR_RGBA8 = 1u << 1,    /* uint32_t, R in bits 0..7, A in bits 24..31 */
    VX_ATTR_NORMAL = 1u << 2,   /* uint32_t octahedral normal: 2 x snorm16, x low */
    VX_ATTR_MATERIAL = 1u << 3, /* uint16_t material id */
    VX_ATTR_DENSITY = 1u << 4,  /* float scalar density */
    VX_ATTR_ALL = 0x1Fu
};

/* model.root values besides a word index into nodes */
#define VX_SVO_ROOT_EMPTY 0xFFFFFFFFu /* no voxels */
#define VX_SVO_ROOT_LEAF 0xFFFFFFFEu  /* the whole 2^depth cube is one leaf (root_attr) */

/* descriptor field access */
static inline uint32_t vx_svo_desc_ptr(uint32_t d) { return d >> 17; }
static inline bool vx_svo_desc_far(uint32_t d) { return (d >> 16) & 1u; }
static inline uint32_t vx_svo_desc_valid(uint32_t d) { return (d >> 8) & 0xFFu; }
static inline uint32_t vx_svo_desc_leaf(uint32_t d) { return d & 0xFFu; }
static inline uint32_t vx_svo_desc_make(uint32_t ptr, bool far, uint32_t valid, uint32_t leaf) {
    return (ptr << 17) | ((uint32_t)far << 16) | ((valid & 0xFFu) << 8) | (leaf & 0xFFu);
}

/* Morton keys: x in bits 3i, y in bits 3i + 1, z in bits 3i + 2 (21 bits
 * each), by parallel bit spreading rather than a loop over the bits: the
 * converters compute one per cell. vx__spread3 spreads the low 21 bits of v
 * to every third bit; vx__compact3 gathers bits 3i of n (its inverse). */
static inline uint64_t vx__spread3(uint32_t v) {
    uint64_t x = v & 0x1fffffu;
    x = (x | x << 32) & 0x1f00000000ffffull;
    x = (x | x << 16) & 0x1f0000ff0000ffull;
    x = (x | x << 8) & 0x100f00f00f00f00full;
    x = (x | x << 4) & 0x10c30c30c30c30c3ull;
    x = (x | x << 2) & 0x1249249249249249ull;
    return x;
}
static inline uint32_t vx__compact3(uint64_t n) {
    n &= 0x1249249249249249ull;
    n = (n ^ (n >> 2)) & 0x30c30c30c30c30c3ull;
    n = (n ^ (n >> 4)) & 0xf00f00f00f00f00full;
    n = (n ^ (n >> 8)) & 0x00ff0000ff0000ffull;
    n = (n ^ (n >> 16)) & 0x00ff00000000ffffull;
    n = (n ^ (n >> 32)) & 0x1fffffull;
    return (uint32_t)n;
}
static inline uint64_t vx_svo_morton(uint32_t x, uint32_t y, uint32_t z) {
    return vx__spread3(x) | (vx__spread3(y) << 1) | (vx__spread3(z) << 2);
}
static inline void vx_svo_demorton(uint64_t k, uint32_t* x, uint32_t* y, uint32_t* z) {
    *x = vx__compact3(k);
    *y = vx__compact3(k >> 1);
    *z = vx__compact3(k >> 2);
}

/* ---- in-memory scene ----------------------------------------------------------- */

/* What the reader found when it validated a model, or the builder knows of
 * the model it made (vx_svo_model.check). */
typedef struct vx_svo_model_check {
    uint32_t digest;         /* vx_svo_model_digest of the model then; 0: not known */
    uint32_t min[3], max[3]; /* the box of its cells, max exclusive */
    uint32_t structural;     /* nonzero: the reader rebuilt the model from the structural
                                form (docs/FORMAT.md 3.4, 3.7) with these settings, the DAG
                                in bit 16, the far limit in bits 0..15 (the builder: its
                                own model, built with the DAG and no far limit, is what that
                                rebuild gives); a writer that finds
                                the digest current codes one read with the DAG and no far
                                limit (the builder's default) in that form without validating
                                and rebuilding it again (docs/PERFORMANCE.md issue 18) */
} vx_svo_model_check;

typedef struct vx_svo_model {
    uint32_t size[3];     /* extent in cells, each 1..2^21 */
    uint32_t depth;       /* root cube is 2^depth cells; smallest with 2^depth >= max(size) */
    uint32_t root;        /* word index of the root descriptor, or VX_SVO_ROOT_EMPTY / _LEAF */
    uint32_t root_attr;   /* attribute record standing for the whole model (LOD) */
    uint32_t attrs;       /* VX_ATTR_* channels present (0: geometry only) */
    uint64_t voxel_count; /* cells set at the finest level */
    uint32_t node_count;  /* 32-bit words in nodes */
    uint32_t* nodes;
    uint32_t attr_count;  /* records in each channel array below */
    uint8_t* palette;     /* VX_ATTR_PALETTE */
    uint32_t* rgba;       /* VX_ATTR_RGBA8 */
    uint32_t* normal;     /* VX_ATTR_NORMAL */
    uint16_t* material;   /* VX_ATTR_MATERIAL */
    float* density;       /* VX_ATTR_DENSITY */
    /* Set by vx_svo_read and vx_svo_build_model (zero from every other
     * producer): the model's digest and cell box as validated (or valid by
     * construction). A writer that computes the same digest for a model it
     * stores in the chunked form, or in the structural form with the settings
     * of check.structural, takes the box from here instead of validating the
     * model again (about a third of a chunked write's time, most of a
     * structural one's; docs/PERFORMANCE.md, issue 18). Code that changes a model
     * need not clear it: the digest no longer matches, and the model is
     * validated as any other (a change that keeps a CRC-32 digest, odds of
     * 2^-32, can give a file that fails to read back; never a crash). */
    vx_svo_model_check check;
} vx_svo_model;

enum { VX_SVO_INSTANCE_HIDDEN = 1u << 0 };

typedef struct vx_svo_instance {
    /* Row-major 3x4 affine map from model cell space to grid space:
     * g = M * p + t with M = {xform[0..2]; xform[4..6]; xform[8..10]} and
     * t = {xform[3], xform[7], xform[11]}. Cell v of the model occupies
     * [v, v+1]^3 in model space; its grid cell is floor(M * (v + 1/2) + t). */
    double xform[12];
    uint32_t model;
    uint32_t layer; /* index into scene.layers, or UINT32_MAX for none */
    uint32_t flags; /* VX_SVO_INSTANCE_* */
    char name[64];  /* NUL-terminated, may be empty */
} vx_svo_instance;

enum { VX_SVO_LAYER_HIDDEN = 1u << 0 };

typedef struct vx_svo_layer {
    char name[64];
    uint32_t flags; /* VX_SVO_LAYER_* */
    uint32_t rgba;  /* display colour, 0 if none */
} vx_svo_layer;

/* A material record: an id (the palette index for .vox MATL) and a
 * dictionary stored as dict_size bytes of NUL-terminated strings
 * key0 value0 key1 value1 ... (MagicaVoxel keys such as "_type" "_emit"). */
typedef struct vx_svo_material {
    uint32_t id;
    uint32_t dict_size;
    char* dict;
} vx_svo_material;

/* ---- lights and materials (svo_light.c) ------------------------------------------- */

/* A light. Units follow glTF's KHR_lights_punctual where it has the type:
 *  directional: intensity = irradiance (lux) on a surface facing it;
 *               direction = towards the light; angular_diameter (radians,
 *               0 = a hard shadow; the sun is about 0.0093)
 *  point, spot: intensity = luminous intensity (candela, W/sr in our
 *               radiometric model): irradiance I cos(theta) / d^2;
 *               radius = the source's radius for soft shadows (0 = a point)
 *  spot:        direction = where it points; inner_cone <= outer_cone
 *               (radians from the axis, at most pi/2), glTF's smooth falloff
 *  sphere:      an emitting sphere of `radius` around position; intensity =
 *               its radiance (W/m^2/sr), the same from every point and angle
 *  rect:        an emitting rectangle centred at position, one-sided,
 *               emitting along `direction` (its normal); `tangent` is the
 *               first edge's direction, size[0] along it, size[1] along
 *               direction x tangent; intensity = radiance
 *  range:       point, spot: 0 for none, else glTF's window (1 - (d/range)^4)^2
 * Every type multiplies intensity by colour. Positions are world units.
 * flags: VX_LIGHT_FROM_VOXELS marks a light that stands for emissive voxels
 *  (vx_svo_emissive_lights); such lights are never stored in a file. */
typedef enum vx_light_type {
    VX_LIGHT_DIRECTIONAL = 0,
    VX_LIGHT_POINT,
    VX_LIGHT_SPOT,
    VX_LIGHT_SPHERE,
    VX_LIGHT_RECT,
    VX_LIGHT_TYPE_COUNT
} vx_light_type;
typedef struct vx_light {
    vx_light_type type;
    double position[3];
    double direction[3];
    double color[3];
    double intensity;
    double range;
    double inner_cone, outer_cone;
    double radius;
    double angular_diameter;
    double tangent[3];
    double size[2];
    uint32_t flags; /* VX_LIGHT_FROM_VOXELS */
} vx_light;

/* The light is an emissive-voxel cluster seen as a sphere light (it encloses
 * the voxels): a renderer that also shades the voxels' own emission (a path
 * tracer hitting them) must not count it twice, and a shadow ray towards it
 * ends at the sphere, not at its centre inside the voxels. */
enum { VX_LIGHT_FROM_VOXELS = 1u << 0 };

/* The sky: what a ray that leaves the scene sees, radiance (W/m^2/sr) by
 * direction. World +z is up (MagicaVoxel's axis, the renderer's default).
 *  VX_SKY_DEFAULT   the renderer's own sky (its --sky option); nothing stored
 *  VX_SKY_CONSTANT  `color` in every direction
 *  VX_SKY_GRADIENT  `color` at the zenith, `horizon` at z = 0, `ground` below:
 *                   above the horizon mix(horizon, color, dz) with dz the
 *                   direction's z, below it `ground` (a constant floor colour)
 *  VX_SKY_ENVMAP    an equirectangular (latitude-longitude) HDR image at
 *                   `path`, relative to the .svo file's folder (or absolute),
 *                   read by the renderer through formats/image.h; texel x/w is
 *                   the azimuth from +x towards +y, y/h the polar angle from +z;
 *                   radiance = texel * intensity, turned by `rotation` radians
 *                   about +z
 * The library stores and checks the path but never opens it (a file read
 * from an untrusted place names a path; the renderer decides). */
typedef enum vx_sky_type {
    VX_SKY_DEFAULT = 0,
    VX_SKY_CONSTANT,
    VX_SKY_GRADIENT,
    VX_SKY_ENVMAP,
    VX_SKY_TYPE_COUNT
} vx_sky_type;
#define VX_SKY_PATH_MAX 255u
typedef struct vx_sky {
    vx_sky_type type;
    double color[3];   /* constant: the radiance; gradient: the zenith */
    double horizon[3]; /* gradient */
    double ground[3];  /* gradient */
    double intensity;  /* envmap: multiplier of the texels */
    double rotation;   /* envmap: radians about +z */
    char path[VX_SKY_PATH_MAX + 1]; /* envmap: NUL-terminated, not empty */
} vx_sky;

/* Checks a light: finite values, intensity >= 0, a direction for directional,
 * spot and rect lights, cone angles in order, sizes >= 0 (rect: a tangent not
 * parallel to the normal); the error names the light's index. */
vx_result vx_light_validate(const vx_light* l, uint32_t index, vx_error* err);
/* The file an environment-map sky names, for a scene read from svo_path:
 * the sky's path when absolute, else joined to svo_path's folder. A
 * renderer reads it with formats/image.h (vx_image_read, VX_IMAGE_F32).
 * false (out = "") when the sky is no map or the result does not fit n. */
bool vx_sky_path(const vx_sky* sky, const char* svo_path, char* out, size_t n);
/* Moves an environment map's relative path from the folder of from_file to
 * the folder of to_file (NULL or no slash: the current directory), so that
 * the sky written next to to_file names the same image: "sky.exr" read
 * from a/s.svo and written to b/s.glb becomes "../a/sky.exr". The folders
 * are compared as realpath() gives them (both must exist: the one a file
 * was read from, the one a file goes to); where they are the same, the
 * path is absolute or the sky is no map, the sky is left as it is (the
 * record round-trips unchanged). VX_ERR_IO when a folder cannot be
 * resolved, VX_ERR_LIMIT when the new path is over VX_SKY_PATH_MAX bytes;
 * the sky is unchanged on failure. Used by svo_info --to-glb
 * (vx_conv_export_desc.svo_path) and vox2svo. */
vx_result vx_sky_rebase(vx_sky* sky, const char* from_file, const char* to_file, vx_error* err);
/* An environment map's texels as a renderer read them: RGB floats, row-major,
 * row 0 at the top (polar angle 0, +z), width * height * 3 values. */
typedef struct vx_sky_texels {
    const float* rgb;
    uint32_t width, height;
} vx_sky_texels;
/* The sky's radiance in unit direction d (the one definition the renderers
 * follow: the GPU path tracer's shader does the same in float). Constant:
 * color; gradient: as above; envmap: the texel the direction falls in
 * (nearest, no filtering) times intensity, black without texels (map NULL
 * or empty); VX_SKY_DEFAULT: black (the renderer's own sky applies). */
void vx_sky_radiance(const vx_sky* sky, const vx_sky_texels* map, const double d[3], double out[3]);
/* Checks a sky: known type, finite colours >= 0, envmap: intensity >= 0, a
 * finite rotation and a non-empty path of at most VX_SKY_PATH_MAX bytes;
 * fields the type does not use must be zero (one stored form per sky). */
vx_result vx_sky_validate(const vx_sky* sky, vx_error* err);
/* The sky as text: the --sky syntax of svo_render and vox2svo, which
 * Python's Scene.sky and svo_view's `sky` command also read and give:
 *   default                               VX_SKY_DEFAULT (nothing stored)
 *   R,G,B                                 VX_SKY_CONSTANT
 *   gradient:ZR,ZG,ZB:HR,HG,HB:GR,GG,GB   VX_SKY_GRADIENT (zenith, horizon, ground)
 *   map:FILE[:INTENSITY[:ROTATION]]       VX_SKY_ENVMAP, intensity 1 and rotation
 *                                         0 when left out; ROTATION in degrees
 * Numbers as strtod reads them (finite). FILE is kept as written (it cannot
 * hold ':'): a caller storing the sky in a file decides which folder it
 * starts from (vx_sky_rebase). The longest text vx_sky_format writes, with
 * its NUL, fits VX_SKY_SPEC_MAX bytes. */
#define VX_SKY_SPEC_MAX 320u
/* Parses spec into *out and checks it with vx_sky_validate: VX_ERR_INVALID_ARG
 * with the form that was expected, or the rule broken, in err->msg; *out is
 * VX_SKY_DEFAULT on failure. */
vx_result vx_sky_parse(const char* spec, vx_sky* out, vx_error* err);
/* Writes sky as the text vx_sky_parse reads back to the same record (the
 * shortest decimal that gives each double back; a rotation is written in
 * degrees, the one that gives the radians back where one does, else the
 * nearest), "default" for VX_SKY_DEFAULT. VX_ERR_INVALID_ARG when the sky
 * fails vx_sky_validate or its map's path holds ':' (the syntax cannot name
 * it), VX_ERR_LIMIT when the text does not fit n bytes; out is "" then. */
vx_result vx_sky_format(const vx_sky* sky, char* out, size_t n, vx_error* err);

/* A material resolved from a vx_svo_material dictionary (MagicaVoxel MATL
 * keys; the glTF importer writes the same keys):
 *  _type  "_diffuse" (default), "_metal", "_glass", "_emit" ("_blend" and
 *         "_media" are treated as diffuse)
 *  _rough roughness in [0,1] (GGX alpha = rough^2); default 0.1 metal/glass
 *  _metal metalness in [0,1] (metal: default 1)
 *  _spec  specular weight in [0,1] (default 0.5)
 *  _ior   MagicaVoxel stores the index of refraction minus 1 (0.3 = 1.3);
 *         _ri, when present, is the index itself. Default 1.5
 *  _trans transmission in [0,1] (glass: default 1)
 *  _emit, _flux  emission = colour * _emit * 2^_flux (MagicaVoxel), for
 *         any type that has _emit > 0
 *  _emit_color  voxkit's key: "R G B", the emitted light's own colour
 *         (linear, each in [0, 1e30]), which then replaces the voxel's
 *         colour in the emission (glTF's emissiveFactor: the glTF importer
 *         writes it with its largest channel 1); absent, unparsable or all
 *         zero: the voxel's colour, as MagicaVoxel
 * Out-of-range or unparsable values clamp to the range or fall back to the
 * default; resolving never fails. */
typedef enum vx_material_type {
    VX_MATERIAL_DIFFUSE = 0,
    VX_MATERIAL_METAL,
    VX_MATERIAL_GLASS,
    VX_MATERIAL_EMIT
} vx_material_type;
typedef struct vx_material {
    vx_material_type type;
    double roughness;
    double metalness;
    double specular;
    double ior;
    double transmission;
    double emission; /* multiplier of the emission colour; 0 = not emissive */
    double emission_color[3]; /* the emission colour (linear); all 0: the voxel's colour */
} vx_material;

/* The radiance a voxel of colour rgb (bytes / 255, as the renderers read it)
 * emits under m: m->emission times m's emission colour, or times rgb where m
 * has none. Every renderer's emission is this (the GPU tables take its
 * terms below). */
void vx_material_emitted(const vx_material* m, const double rgb[3], double out[3]);
/* The same as terms the GPU tables hold per record: radiance = rgb * k[3] +
 * (k[0], k[1], k[2]) (k[3] = emission and the rest 0 for the voxel's colour;
 * k[3] = 0 and the emission colour times the emission otherwise), so a
 * scene without emission colours gets rgb * emission, the same bits as a
 * multiplier alone. m NULL: all 0. */
void vx_material_emitted_terms(const vx_material* m, float k[4]);

typedef struct vx_svo_scene {
    uint32_t model_count;
    vx_svo_model* models;
    uint32_t instance_count;
    vx_svo_instance* instances;
    uint32_t layer_count;
    vx_svo_layer* layers;
    uint32_t material_count;
    vx_svo_material* materials;
    bool has_palette;
    uint32_t palette[256]; /* RGBA8 by palette index (.vox RGBA entry i-1); [0] unused */
    /* Row-major 3x4 map from grid space to world units (identity for .vox;
     * voxel size and origin for meshes and VDB grids). */
    double world_from_grid[12];
    /* Grid-space bounds of the visible instances' voxels, min inclusive,
     * max exclusive (all zero for an empty scene). */
    double bounds_min[3], bounds_max[3];
    /* Lights and sky (section LGHT, written only when there is a light or
     * sky.type != VX_SKY_DEFAULT). Lights derived from emissive voxels are
     * not stored here (vx_svo_emissive_lights derives them when rendering). */
    uint32_t light_count;
    vx_light* lights;
    vx_sky sky;
    /* Animation. A static scene has frame_count 0 or 1 and frame_instances
     * NULL. With frame_count >= 2, frame 0 is `instances` (code that knows
     * nothing of frames sees frame 0, and bounds are frame 0's) and frame
     * f >= 1 is the instance_count records at frame_instances +
     * (f - 1) * instance_count. Record i of every frame animates instance i:
     * its name and layer are instance i's; its model, transform and flags
     * (hidden) are the frame's. All frames share the models. Read a frame
     * through vx_svo_scene_frame() / vx_svo_scene_frame_instances(). */
    uint32_t frame_count;
    double frame_rate;                /* frames per second, 0 if not known */
    vx_svo_instance* frame_instances; /* (frame_count - 1) * instance_count records */
    const vx_allocator* alloc; /* what the arrays were allocated with: borrowed, it must outlive the
                                  scene (vx_svo_scene_free frees through it) */
} vx_svo_scene;

/* Frees every array of the scene and zeroes it. */
void vx_svo_scene_free(vx_svo_scene* scene);
void vx_svo_model_free(const vx_allocator* a, vx_svo_model* model);
/* Whether two models are the same octree word for word and record for
 * record (size, attributes, root, nodes and every channel), and a hash that
 * agrees with it: converters store a model that repeats (an unchanged part
 * of an animation) once. */
bool vx_svo_model_equal(const vx_svo_model* a, const vx_svo_model* b);
uint64_t vx_svo_model_hash(const vx_svo_model* m);
/* CRC-32 of the model's fields (size, depth, root, root_attr, attrs,
 * voxel_count, node_count, attr_count) and arrays (nodes, each channel it
 * has), never 0 (0 maps to 1); 0 when an array it needs is NULL. About
 * 17 GB/s (libdeflate's CRC): the 4096^3 helmet's 670 MB in 0.04 s. */
uint32_t vx_svo_model_digest(const vx_svo_model* m);
/* Sets world_from_grid to the identity. */
void vx_svo_scene_init(vx_svo_scene* scene, const vx_allocator* a);
/* Recomputes bounds_min/max from the instances (hidden ones excluded) using
 * each model's occupied extent: vx_svo_scene_update_bounds_ex(NULL, scene). */
void vx_svo_scene_update_bounds(vx_svo_scene* scene);
/* Options of vx_svo_scene_update_bounds_ex; NULL or zero-initialised: the
 * defaults. The bounds never depend on them. */
typedef struct vx_svo_bounds_desc {
    unsigned threads;       /* threads that find the models' extents (a pass over each tree) at once, for scenes
                               of two models or more and 2^20 node words or more: 0 = one per CPU (at most
                               VX_MAX_THREADS), 1 = the caller's thread only */
    vx_svo_testing testing; /* test hooks: parallel_always only (svo/core.h); leave zeroed */
} vx_svo_bounds_desc;
/* vx_svo_scene_update_bounds with options (desc may be NULL). Scratch
 * memory comes from scene->alloc; where it runs out the extents are found
 * on the caller's thread (the same bounds). */
void vx_svo_scene_update_bounds_ex(const vx_svo_bounds_desc* desc, vx_svo_scene* scene);
/* ---- scene facts shared by every module (svo_scene.c) ------------------------------ */

/* Whether instance i is shown: not hidden, not on a hidden layer, its model
 * index in range. */
bool vx_svo_instance_visible(const vx_svo_scene* scene, uint32_t i);
/* Whether instance i is drawn: visible and its model not empty. */
bool vx_svo_instance_drawn(const vx_svo_scene* scene, uint32_t i);
/* The instance's world map (3x4 row-major): world_from_grid * xform. */
void vx_svo_instance_world(const vx_svo_scene* scene, const vx_svo_instance* in, double w[12]);
/* The axis-aligned box around the box [in_lo, in_hi] mapped by the affine
 * map w (3x4 row-major): the least and greatest of its 8 corners' images. */
void vx_svo_box_map(const double w[12], const double in_lo[3], const double in_hi[3], double lo[3], double hi[3]);
/* World AABB of the instance's model box [0, size]. */
void vx_svo_instance_world_box(const vx_svo_scene* scene, const vx_svo_instance* in, double lo[3], double hi[3]);
/* World bounds of the drawn instances' model boxes (all zero when none is
 * drawn); computed from the instances, so stale stored bounds do not matter.
 * An animation: the union over its frames (a camera framing it holds still;
 * a frame's own bounds come from its view, vx_svo_scene_frame). */
void vx_svo_scene_world_bounds(const vx_svo_scene* scene, double lo[3], double hi[3]);
/* RGBA8 of attribute record a of model m: its colour, or the palette entry of
 * its index; opaque white without attributes or past the records. */
uint32_t vx_svo_attr_rgba(const vx_svo_scene* scene, const vx_svo_model* m, uint32_t a);

/* ---- animation frames (svo_scene.c) ------------------------------------------------ */

/* Number of frames: 1 for a static scene. */
uint32_t vx_svo_scene_frames(const vx_svo_scene* scene);
/* The instance_count records of frame f (scene->instances for frame 0 and
 * for a static scene); NULL when f >= vx_svo_scene_frames(scene). */
const vx_svo_instance* vx_svo_scene_frame_instances(const vx_svo_scene* scene, uint32_t f);
/* A view of frame f as a static scene: a shallow copy of *scene whose
 * instances are frame f's (frame_count 1, frame_instances NULL). Everything
 * stays owned by scene: use the view while scene lives and never free it.
 * Its bounds are the scene's (frame 0); vx_svo_scene_update_bounds(view)
 * computes the frame's. False (view untouched) when f is out of range. */
bool vx_svo_scene_frame(const vx_svo_scene* scene, uint32_t f, vx_svo_scene* view);
/* Makes the scene animated with frame_count frames (>= 2), every frame a copy
 * of `instances` (frames already there are freed). The records come from
 * scene->alloc; VX_ERR_LIMIT when they would exceed VX_SVO_FRAMES_MAX_BYTES. */
vx_result vx_svo_scene_alloc_frames(vx_svo_scene* scene, uint32_t frame_count, vx_error* err);
/* Bytes of frame records a scene may hold (the reader refuses files that
 * expand to more: a frame that changes nothing costs one byte on disk). */
#define VX_SVO_FRAMES_MAX_BYTES ((uint64_t)256 << 20)

/* Looks up a key in a material's dictionary; NULL if absent. */
const char* vx_svo_material_get(const vx_svo_material* m, const char* key);

/* The defaults for a type (no dictionary). */
vx_material vx_material_default(vx_material_type type);
/* m may be NULL (a diffuse material). */
vx_material vx_svo_material_resolve(const vx_svo_material* m);
/* The material of palette index / material id `id` in the scene (the record
 * whose id matches), diffuse when there is none. */
vx_material vx_svo_scene_material(const vx_svo_scene* scene, uint32_t id);

/* The material id of attribute record `attr` of model m: its
 * VX_ATTR_MATERIAL value where the model has that channel, else its palette
 * index (VX_ATTR_PALETTE), else 0 (also for attr past the model's records).
 * The one rule by which every renderer, the GI methods and the emissive
 * lights find a record's MATL material (an RGBA model from the glTF
 * importer names its materials through the channel, ids up to 65535). */
uint32_t vx_svo_attr_material(const vx_svo_model* m, uint32_t attr);

/* The scene's materials resolved once and sorted by id, for a lookup per
 * record or per hit (vx_svo_scene_material parses the dictionary at every
 * call). Ids may go up to 65535 and beyond, so the table holds one entry per
 * MATL record (the first record of an id, as vx_svo_scene_material), not
 * one per possible id. Zero-initialised: an empty table (every id diffuse).
 * emissive / specular: some entry has emission > 0 / is metal or glass. */
typedef struct vx_svo_material_table {
    uint32_t count;
    uint32_t* ids;     /* ascending, unique */
    vx_material* mats; /* mats[i]: material id ids[i] */
    bool emissive, specular;
    const vx_allocator* alloc;
} vx_svo_material_table;
/* *out gets the table of scene's materials (alloc NULL: malloc). */
vx_result vx_svo_material_table_make(const vx_svo_scene* scene, const vx_allocator* alloc, vx_svo_material_table* out,
                                     vx_error* err);
/* The material of id, NULL where the scene has none (diffuse, no emission). */
const vx_material* vx_svo_material_table_find(const vx_svo_material_table* t, uint32_t id);
/* Emission of id (vx_material.emission), 0 where it has no material. */
double vx_svo_material_table_emission(const vx_svo_material_table* t, uint32_t id);
/* The renderers' emission table of n attribute records whose material ids
 * are ids[i]: vx_material_emitted_terms of each record's material, 4 floats
 * a record, in *out (alloc NULL: malloc; freed with vx_free). Where no
 * material of t emits, *count = 0 and *out one zero record (a table can
 * always be bound; the kernels read no record past a table), else *count =
 * n. */
vx_result vx_svo_material_table_emission_records(const vx_svo_material_table* t, const uint16_t* ids, size_t n,
                                                 const vx_allocator* alloc, float** out, size_t* count, vx_error* err);
void vx_svo_material_table_free(vx_svo_material_table* t);

/* ---- emissive voxels as lights (svo_emissive.c) ----------------------------------- */

/* Emissive voxels (a material with emission > 0: MagicaVoxel _emit, the
 * glTF importer's emissive materials) as lights the direct pass and a path
 * tracer's light sampling can see. The material id of a cell is its
 * VX_ATTR_MATERIAL value, else its palette index; its radiance is
 * vx_material_emitted: its colour (bytes / 255, as the renderers read it),
 * or the material's emission colour where it has one, times the emission.
 *
 * One light per cluster, not per voxel: a lamp of 30 voxels is one light, so
 * the light count follows the number of lamps, not of voxels, and the many-
 * light passes stay cheap. A cluster is a component of face-connected
 * emissive cells of one model; a component wider than `block` cells
 * (default 2) on some axis is cut at the aligned blocks of that size, its
 * cells grouped by block: the cut keeps a long neon tube from becoming one
 * sphere at its middle, while a small lamp stays one light wherever it
 * sits. The default is the cut with the lowest error against the path
 * tracer on bench/emissive_bench's room (docs/PERFORMANCE.md section 11):
 * blocks of 2 beat one light per voxel (block 1) and larger blocks. Each cluster becomes, per drawn instance of its model, a
 * VX_LIGHT_SPHERE with VX_LIGHT_FROM_VOXELS set: centred on the cluster's
 * box, radius = half the box's diagonal (world units), and the radiance that
 * gives the sphere the power the cluster's exposed faces emit
 * (sum over faces whose neighbour cell is empty of pi L area, faces of the
 * model's boundary count as exposed), Ls = P / (4 pi^2 r^2). The sphere
 * encloses the voxels: a shadow ray towards it should end at its surface.
 * These lights are derived when rendering, never stored in the file (the
 * voxels are the data; stored copies would go stale when voxels change). */
typedef struct vx_svo_emissive_desc {
    const vx_allocator* alloc;
    uint32_t block;      /* cluster cut, cells per side, a power of two; 0 == 2 */
    uint64_t max_cells;  /* emissive cells per model; 0 == 2^24; more is VX_ERR_LIMIT */
    uint32_t max_lights; /* 0 == 2^22; more is VX_ERR_LIMIT */
} vx_svo_emissive_desc;
vx_svo_emissive_desc vx_svo_emissive_desc_defaults(void);
/* *out (free with vx_free(desc->alloc, ...)) gets *count lights in instance
 * order, each model's clusters in the Morton order of their first cell;
 * NULL and 0 when the scene has no emissive material or cell. */
vx_result vx_svo_emissive_lights(const vx_svo_scene* scene, const vx_svo_emissive_desc* desc, vx_light** out,
                                 uint32_t* count, vx_error* err);

/* ---- building ---------------------------------------------------------------------- */

/* The voxels of one model. keys[i] = vx_svo_morton(x, y, z) with x < size[0]
 * etc.; the channel arrays are parallel to keys, one per bit of attrs, and
 * must be NULL for channels not in attrs. Keys need not be sorted; when a key
 * appears several times the last occurrence wins (as in .vox files).
 * level (optional, NULL = all 0): entry i is a filled cube of 2^level[i]
 * cells whose minimum corner has Morton key keys[i] (aligned to 2^level);
 * such tiles become whole subtrees, never expanded cell by cell. Input is
 * borrowed and not modified. */
typedef struct vx_svo_voxels {
    uint32_t size[3];
    size_t count;
    const uint64_t* keys;
    const uint8_t* level;
    uint32_t attrs;
    const uint8_t* palette;
    const uint32_t* rgba;
    const uint32_t* normal;
    const uint16_t* material;
    const float* density;
} vx_svo_voxels;

/* Build options; zero-initialised means the defaults. */
typedef struct vx_svo_build_desc {
    bool no_collapse;   /* skip minimization step 1 (uniform full subtrees -> one leaf) */
    bool no_dag;        /* skip minimization step 2 (share identical subtrees) */
    uint32_t max_depth; /* 0 == VX_SVO_MAX_DEPTH */
    const vx_allocator* alloc;
    vx_progress progress;
    vx_svo_testing testing; /* test hooks: far_limit only (svo/core.h); leave zeroed */
} vx_svo_build_desc;

typedef struct vx_svo_build_stats {
    uint64_t input_voxels;      /* entries given (before duplicate removal) */
    uint64_t voxels;            /* distinct cells set */
    uint64_t desc_plain;        /* descriptors of the plain octree */
    uint64_t desc_collapsed;    /* after step 1 (equal to plain when skipped) */
    uint64_t desc_dag;          /* after step 2 (equal to collapsed when skipped) */
    uint64_t far_pointers;      /* far slots written */
    uint64_t attr_records;      /* attribute records stored */
    uint64_t bytes;             /* node words * 4 + attribute bytes */
} vx_svo_build_stats;

/* Builds one model's octree (collapse + DAG on by default). out is fully
 * owned by the caller (free with vx_svo_model_free(desc->alloc, out)).
 * stats may be NULL. An empty voxel set gives root = VX_SVO_ROOT_EMPTY. */
vx_result vx_svo_build_model(const vx_svo_build_desc* desc, const vx_svo_voxels* in, vx_svo_model* out,
                             vx_svo_build_stats* stats, vx_error* err);

/* Representative attribute rule for coarse levels (also used by tests):
 * palette and material: the most frequent value among the valid children,
 * ties to the smallest; rgba: the rounded mean of each channel; normal: the
 * renormalised mean; density: the mean. */

/* ---- decoding ------------------------------------------------------------------------- */

/* Called once per set cell, in Morton order; return false to stop early. */
typedef bool (*vx_svo_voxel_fn)(void* user, uint32_t x, uint32_t y, uint32_t z, uint32_t attr);

/* Visits every cell of the model (collapsed leaves are expanded), the exact
 * inverse of vx_svo_build_model. The model must be valid (as returned by
 * vx_svo_build_model or vx_svo_read). */
vx_result vx_svo_decode_model(const vx_svo_model* m, vx_svo_voxel_fn fn, void* user, vx_error* err);
/* Called once per 8^3-cell block that holds a set cell, block (bx, by, bz)
 * holding cells 8 bx .. 8 bx + 7 and so on, bits[i >> 5] >> (i & 31) & 1
 * the cell (x, y, z) of the block at i = x + 8 y + 64 z; in Morton order of
 * the blocks; return false to stop early. */
typedef bool (*vx_svo_block_fn)(void* user, uint32_t bx, uint32_t by, uint32_t bz, const uint32_t bits[16]);

/* Visits the model's cells as 8^3-cell occupancy blocks (the renderer's and
 * render_bench's grids, bench/brickgrid.h): the same cells as
 * vx_svo_decode_model (attributes aside), one call per occupied block, a
 * uniform leaf 8 or more cells wide given as its full blocks without
 * visiting its cells, shared subtrees visited once per place. The model
 * must be valid. */
vx_result vx_svo_decode_blocks(const vx_svo_model* m, vx_svo_block_fn fn, void* user, vx_error* err);
/* Whether cell (x, y, z) of a valid model is set: one descent from the root;
 * false outside the model's size. (The emissive lights' and the photons'
 * exposed faces: a face emits when the cell beyond it is empty.) */
bool vx_svo_model_cell_set(const vx_svo_model* m, uint32_t x, uint32_t y, uint32_t z);
/* The level of the leaf of a valid model that holds cell (x, y, z): 0 a
 * single cell, k a uniform block of 2^k cells a side (one attribute record)
 * at the cell's coordinates rounded down to a multiple of 2^k; UINT32_MAX
 * where the cell is empty or outside the model's size. One descent, as
 * vx_svo_model_cell_set. (The glass walks step over a uniform glass leaf at
 * once: probes/pathtrace.c glass_walk.) */
uint32_t vx_svo_model_cell_leaf(const vx_svo_model* m, uint32_t x, uint32_t y, uint32_t z);
/* The box of a valid model's set cells, lo inclusive, hi exclusive (all 0
 * for an empty model): a walk along each face from the root, about the
 * nodes that straddle the face (the renderer's instance boxes, issue 18). */
void vx_svo_model_cell_box(const vx_svo_model* m, uint32_t lo[3], uint32_t hi[3]);

/* RGBA8 colour of attribute record attr of model m (palette looked up;
 * opaque white for geometry-only models). */
uint32_t vx_svo_attr_color(const vx_svo_scene* s, const vx_svo_model* m, uint32_t attr);

/* Checks a model's structure: every pointer in range and strictly backward,
 * masks consistent, attribute indices in range, depth limits. */
vx_result vx_svo_validate_model(const vx_svo_model* m, vx_error* err);
/* Checks the whole scene (models, instance model ids, layers, transforms
 * finite; with frames, every frame's records the same way, their names and
 * layers equal to the instances they animate, a finite frame rate >= 0). */
vx_result vx_svo_validate_scene(const vx_svo_scene* s, vx_error* err);

/* ---- files ------------------------------------------------------------------------------ */

/* How the chunked models of a file were coded (docs/FORMAT.md 3.6), as
 * vx_svo_read found them (svo_info prints it). */
typedef struct vx_svo_chunk_stats {
    uint32_t models;       /* models in the chunked form */
    uint64_t deflate;      /* DEFLATE chunks: version 3's, or version 4's codec 0 */
    uint64_t zstd;         /* zstd chunks (version 4), records as differences */
    uint64_t zstd_plain;   /* zstd chunks (version 4), records as they are */
    uint64_t coded_bytes;  /* the chunks' bytes */
    uint64_t raw_bytes;    /* the words and records they hold */
} vx_svo_chunk_stats;

typedef struct vx_svo_read_desc {
    const vx_allocator* alloc;
    bool skip_checksums; /* default: every section's CRC-32 is verified */
    unsigned threads;    /* threads that decode, check and validate: 0 = one per CPU (at
                            most VX_MAX_THREADS), 1 = the caller's thread only. The scene read never
                            depends on it; small scenes always use the caller's thread. */
    vx_svo_chunk_stats* chunk_stats; /* NULL, or zeroed and filled by a read that gets as
                                        far as the NODE section */
    uint64_t max_file_bytes; /* vx_svo_read_file: a larger file is refused (VX_ERR_LIMIT);
                                0: any size the address space and memory hold (the
                                65536^3 helmet's file is about 28 GB; vx_file_read's
                                own default, 4 GiB, refused the 7 GB one at 32768^3) */
    /* vx_svo_read_file, vx_svo_reader_open: NULL, or called once the file is
     * open and its size taken, before any of its bytes is read (tests cut the
     * file short there; the read then fails naming the file). Files are read
     * with pread into the reader's own buffers, never mapped, so a file that
     * another process shortens during a read is an error (VX_ERR_TRUNCATED),
     * not a SIGBUS. */
    void (*on_open)(void* user, const char* path);
    void* on_open_user;
    vx_svo_testing testing; /* test hooks: parallel_always and scratch_any only (svo/core.h); leave zeroed */
} vx_svo_read_desc;

/* Parses and fully validates a .svo file held in memory. On success *out
 * owns copies of everything (the input buffer may be freed). */
vx_result vx_svo_read(const vx_svo_read_desc* desc, const void* data, size_t size, vx_svo_scene* out,
                      vx_error* err);
vx_result vx_svo_read_file(const vx_svo_read_desc* desc, const char* path, vx_svo_scene* out, vx_error* err);

/* ---- models one at a time ----------------------------------------------------------------
 * A file read without holding its scene: the scene graph first (instances,
 * layers, palette, materials, lights, frames, and every model's declared
 * fields: size, depth, attrs, counts, root), then the models in model order,
 * each decoded and validated as vx_svo_read validates it before it is handed
 * over and owned by the caller from then on. A consumer that builds its own
 * form of each model (render/compact.h's vx_compact_build_reader) holds that
 * form plus the models in hand instead of the whole scene (the 65536^3
 * helmet: 86 GiB read whole). Each model's stream is read (pread) when
 * its model is asked for and leaves the process's memory once decoded.
 *
 *   vx_svo_model_reader* rd; vx_svo_reader_open(NULL, path, &rd, &err);
 *   const vx_svo_scene* g = vx_svo_reader_scene(rd);      // no trees
 *   for (;;) { uint32_t i; vx_svo_model m;
 *              if (vx_svo_reader_next(rd, &i, &m, &err)) break;   // error
 *              if (i == g->model_count) break;                     // the end
 *              ... use model i ...; vx_svo_model_free(alloc, &m); }
 *   vx_svo_reader_finish(rd, &err);   // the NODE checksum, the bounds
 *   vx_svo_reader_close(rd);
 *
 * Errors name the file (and the model where one failed); after one, next
 * and finish fail. A scene is read only once finish succeeds: a model that
 * validated may still belong to a file whose NODE checksum (summed as the
 * models are taken) does not match, so a consumer discards what it built
 * from the models when finish fails. */
typedef struct vx_svo_model_reader vx_svo_model_reader;
/* Opens the file (a regular file), reads and checks the header, the
 * table, every section but NODE and their CRCs, parses the scene graph
 * and checks the scene's own rules. desc: alloc, skip_checksums,
 * max_file_bytes and threads (the CPUs the models' decoding shares) as
 * vx_svo_read's; chunk_stats is not filled. The reader copies *desc->alloc
 * (its user_data must outlive the reader and the models it hands over). */
vx_result vx_svo_reader_open(const vx_svo_read_desc* desc, const char* path, vx_svo_model_reader** out, vx_error* err);
/* The scene graph, owned by the reader: model i's arrays are NULL and its
 * counts the declared ones; its check (the cells' box and digest) is set
 * once model i was handed over; the bounds (where the file leaves them to
 * the reader) once finish succeeded. */
const vx_svo_scene* vx_svo_reader_scene(const vx_svo_model_reader* r);
/* The next model in model order: *index its index and *out the model (its
 * arrays allocated with desc->alloc; free them with vx_svo_model_free), or
 * *index = model_count and *out zeroed once every model has been taken.
 * Thread-safe: concurrent calls take the next models in order (the stream
 * table under a lock) and decode them at once, each on its share of the
 * CPUs. On failure *out is zeroed and nothing is held for the caller. */
vx_result vx_svo_reader_next(vx_svo_model_reader* r, uint32_t* index, vx_svo_model* out, vx_error* err);
/* After every model was handed over: the NODE section ends after the last
 * stream and its CRC matches, and the scene's computed bounds are set. */
vx_result vx_svo_reader_finish(vx_svo_model_reader* r, vx_error* err);
/* A second pass over the file (and a third ...), for a consumer that needs
 * the models again without holding them (the compact layout built again with
 * the brick dictionary: render/render.h, vx_render_scene_create_compact):
 * after finish succeeded, next hands the models over again from model 0,
 * each read from the file again (pread), decoded and validated, and finish
 * checks the NODE section again. A model that differs from the first pass's
 * (its digest or its cells' box: the file was changed between the passes)
 * fails next (VX_ERR_BAD_FORMAT, naming the file and the model). Refused
 * (VX_ERR_INVALID_ARG) before finish succeeded, after an error, or while a
 * call decodes. The graph (bounds, checks) stays the first pass's. */
vx_result vx_svo_reader_rewind(vx_svo_model_reader* r, vx_error* err);
/* Model `index` again, on its own (random access: a pager that decodes the
 * model of a page it needs, render/compact.h): after a pass that finish
 * accepted, its stream is read from the file again (pread of its bytes, at
 * the offset and length the first pass's walk of the stream table kept: 16
 * bytes a model), decoded and validated as next does, and handed over as
 * next hands it (*out owned by the caller). A model that differs from the
 * first pass's (digest or cells' box: the file changed in place) fails
 * (VX_ERR_BAD_FORMAT naming the file and the model), a file cut short fails
 * as a cut during a read (VX_ERR_TRUNCATED); neither stops the reader (each
 * call checks its own bytes; the NODE section's CRC is the first pass's).
 * Refused (VX_ERR_INVALID_ARG) before a pass that finish accepted, after an
 * error of next or finish, for an index past the models. Thread-safe, also
 * beside a later pass's next; concurrent calls share the CPUs as next's do. */
vx_result vx_svo_reader_model(vx_svo_model_reader* r, uint32_t index, vx_svo_model* out, vx_error* err);
/* The bounds of s (bounds_min, bounds_max), a scene of the reader's models
 * (its graph, a copy, or a view of one of its frames: vx_svo_scene_frame),
 * from s's instances and the cells' boxes of the models as the reader's pass
 * found them: what vx_svo_scene_update_bounds(s) computes from the trees of
 * the whole read (an animation's frame N > 0 read by the reader, which holds
 * no tree). Refused (VX_ERR_INVALID_ARG, s untouched) before a pass that
 * finish accepted and for a scene of another model count. Thread-safe, also
 * beside a later pass. */
vx_result vx_svo_reader_update_bounds(vx_svo_model_reader* r, vx_svo_scene* s, vx_error* err);
/* A copy of the graph as it is now (models without arrays, their checks and
 * the bounds as far as read), allocated with alloc and owned by the caller
 * (vx_svo_scene_free): for code that keeps the scene graph past the reader,
 * or fills the models in as they come (a whole scene from the reader). */
vx_result vx_svo_reader_copy_graph(const vx_svo_model_reader* r, const vx_allocator* alloc, vx_svo_scene* out, vx_error* err);
void vx_svo_reader_close(vx_svo_model_reader* r);

/* Serialises a scene (validated first). *out_data is freed with vx_free(alloc, ...). */
vx_result vx_svo_write(const vx_svo_scene* s, const vx_allocator* alloc, uint8_t** out_data, size_t* out_size,
                       vx_error* err);
/* The same with options (allocator, threads; desc may be NULL): the bytes
 * of vx_svo_write whatever desc->threads is. */
vx_result vx_svo_write_ex(const vx_write_desc* desc, const vx_svo_scene* s, uint8_t** out_data, size_t* out_size,
                          vx_error* err);
/* Writes the same bytes as vx_svo_write, streamed: the sections go to a
 * scratch file beside the output as they are made (never the whole file in
 * memory), then a temporary file gets the header and the sections and is
 * renamed into place. No partial output and no scratch file is left on
 * failure; errors name the path. desc may be NULL (svo/core.h). */
vx_result vx_svo_write_file(const vx_write_desc* desc, const vx_svo_scene* s, const char* path, vx_error* err);

/* ---- a file from models coded apart (vox2svo under mpirun) -------------------------------
 * A model's stream in the NODE section depends on that model alone, so the
 * processes that build models can code them (vx_svo_model_encode) and one
 * process writes the file from the streams in model order
 * (vx_svo_write_file_coded), holding one stream at a time instead of every
 * tree. The file is vx_svo_write_file's byte for byte. */
typedef struct vx_svo_model_coded {
    uint64_t stream_size;     /* bytes of the model's coded stream */
    uint64_t cells;           /* occupied cells (the tree's count: the model's voxel_count) */
    uint32_t min[3], max[3];  /* the occupied cells' box, min inclusive, max exclusive (all 0 when empty) */
    uint8_t palette_used[32]; /* bit i (byte i / 8, bit i % 8): some record has palette index i */
    bool chunked;             /* the stream is in the chunked form (FORMAT.md 3.6; by vx_write_desc.svo_chunk_words) */
    bool chunk_tagged;        /* chunked, with codec-tagged (zstd) chunks: format version 4 (not
                                 vx_write_desc.svo_chunk_deflate, _fast or _stored) */
    bool split;               /* the stream is in the split form (FORMAT.md 3.7, format version 5: a
                                 large structural model, unless vx_write_desc.svo_range_coded) */
} vx_svo_model_coded;

/* Validates m (as vx_svo_validate_model; not where its check is current, as
 * vx_svo_write does not: vx_svo_model.check) and codes it: *stream (free with
 * vx_free(desc->alloc, ...); desc may be NULL) gets info->stream_size bytes. */
vx_result vx_svo_model_encode(const vx_write_desc* desc, const vx_svo_model* m, vx_svo_model_coded* info, uint8_t** stream,
                              vx_error* err);

/* Where vx_svo_write_file_coded takes the streams: read(user, model, buf,
 * size) fills buf with model's stream (size = info[model].stream_size),
 * called once per model in model order; false fails the write (VX_ERR_IO). */
typedef struct vx_svo_stream_source {
    bool (*read)(void* user, uint32_t model, uint8_t* buf, uint64_t size);
    void* user;
} vx_svo_stream_source;

/* vx_svo_write_file for a scene whose trees are elsewhere: each model gives
 * only its fields (size, depth, attrs, node_count, root, voxel_count,
 * attr_count, root_attr; its arrays are not read and may be NULL), info[i]
 * is what vx_svo_model_encode returned for model i, src gives the streams.
 * The scene's rules are checked as vx_svo_validate_scene checks them, each
 * model's voxel_count against its info. Peak memory: the largest stream. */
vx_result vx_svo_write_file_coded(const vx_write_desc* desc, const vx_svo_scene* s, const vx_svo_model_coded* info,
                                  const vx_svo_stream_source* src, const char* path, vx_error* err);

/* vx_svo_scene_update_bounds from the models' coded extents (info[i] for
 * model i) instead of their trees. */
void vx_svo_scene_update_bounds_coded(vx_svo_scene* s, const vx_svo_model_coded* info);

/* Section table of a file, for svo_info. */
typedef struct vx_svo_section_info {
    char tag[5];      /* four ASCII characters */
    uint32_t flags;
    uint64_t offset, size;
    uint32_t crc;      /* as stored */
    bool crc_ok;       /* recomputed CRC matches */
    bool known;        /* this version understands the tag */
} vx_svo_section_info;

typedef struct vx_svo_file_info {
    uint32_t version;
    uint32_t section_count;
    vx_svo_section_info sections[64]; /* first 64 */
    uint64_t file_size;
} vx_svo_file_info;

/* Reads the header and section table only (checks bounds and CRCs). */
vx_result vx_svo_probe(const void* data, size_t size, vx_svo_file_info* out, vx_error* err);

#ifdef __cplusplus
}
#endif
#endif /* VX_SVO_H */
