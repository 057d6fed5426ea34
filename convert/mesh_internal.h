/* convert/mesh_internal.h - the brick voxelizer behind convert/mesh.h. */
#ifndef VX_CONVERT_MESH_INTERNAL_H
#define VX_CONVERT_MESH_INTERNAL_H

#include "convert/mesh.h"
#include "svo/svo_interned.h"

#define VX__MESH_BRICK_BITS 6u /* bricks of 64^3 cells */

/* One region's voxels, handed to the sink in Morton order. keys are
 * region-local Morton keys (x < size[0] ...); rgba / normal parallel to keys
 * when the attrs bit is set, else NULL. Borrowed for the call only. */
typedef struct vx__mesh_region {
    uint32_t origin[3], size[3];
    size_t index, region_count; /* which region of how many (Morton order) */
    size_t count;
    const uint64_t* keys;
    const uint32_t* rgba;
    const uint32_t* normal;
    const uint16_t* material; /* VX_ATTR_MATERIAL: vx__mesh_material_id of the cell's material */
    uint32_t attrs;
    /* The same tuples interned (interned.rec non-NULL; the GPU voxelizer):
     * the builder takes these (vx__svo_build_interned) instead of hashing
     * the arrays above, which stay for other sinks. */
    vx__svo_interned interned;
    /* The cells' box in the region (min inclusive, max exclusive) when the
     * voxelizer knows it (the GPU build): the scene's bounds then need no
     * pass over the model. */
    bool has_box;
    uint32_t box_min[3], box_max[3];
} vx__mesh_region;

/* A region handed to the sink, placed: zeroed, then its origin and size in
 * the grid (regions of R^3 cells, clipped at the grid's far faces) from its
 * Morton index, and which of how many it is. */
void vx__mesh_region_place(vx__mesh_region* reg, uint64_t region, uint32_t R, const uint32_t grid_size[3], size_t index,
                           size_t region_count);

/* ---- materials (convert/mesh_material.c) ----------------------------------------------
 *
 * The MATL records a mesh's cells can name (convert/mesh.h, "Materials"),
 * a function of the mesh alone, so that every process of a distributed run
 * and both voxelizers give the same ids. Per glTF material: its effective
 * factors (a texture channel that is uniform over its image folded in: the
 * same as the factor it equals) and which channels vary per cell
 * (VX__MESH_SAMPLE_*: a decoded texture that is not uniform, under a factor
 * above 0; roughness only where the material can need a record). A material
 * that samples nothing has one id, base, when it is special (metallic,
 * transmissive or emissive) and none (0, diffuse) otherwise: base = index + 1
 * when no material of the mesh samples (ids above 65535 are 0). One that
 * samples has a block of levels^k ids from base, k the channels it samples,
 * one per combination of quantized levels: id = base + (km * Lr + kr) * Le
 * + ke (L = levels for a sampled channel, else 1 with k = 0). A sampled
 * emission is n channels, not one: each of R, G, B whose factor emit[c] is
 * above 0 is quantized on its own, Le = levels^n and ke the levels' mixed-
 * radix number (R first, only those channels), so that a record keeps the
 * texel's hue (a red map under a white factor glows red, not white) at the
 * price of larger blocks (6^3 for a white factor). */
enum { VX__MESH_SAMPLE_METAL = 1, VX__MESH_SAMPLE_ROUGH = 2, VX__MESH_SAMPLE_EMIT = 4 };
#define VX__MESH_LEVELS 6u /* levels of a sampled channel (0, 1/5, ..., 1 of its factor); fewer when ids run out */

typedef struct vx__mesh_mat {
    float metal, rough, emit[3], trans; /* effective factors */
    float emit_max;                     /* the largest of emit */
    uint32_t base;                      /* first id (0: none) */
    uint32_t block;                     /* ids from base: levels^k (k counts an emission's channels), 1 when nothing is sampled */
    uint8_t sample;                     /* VX__MESH_SAMPLE_* */
    bool special;                       /* needs a record whatever its cells sample */
} vx__mesh_mat;

typedef struct vx__mesh_mats {
    uint32_t count;     /* = mesh->material_count */
    vx__mesh_mat* m;
    uint32_t levels;    /* of every sampled channel */
    bool sampled;       /* some material samples a channel per cell */
    bool any_special;   /* some triangle's material can need a record (VX_ATTR_MATERIAL) */
} vx__mesh_mats;

/* The plan of mesh's materials; VX_ERR_LIMIT when the ids of the materials
 * that sample do not fit in 65535 even at 2 levels. Free with
 * vx__mesh_mats_free. */
vx_result vx__mesh_mats_make(const vx_gltf_mesh* mesh, const vx_allocator* a, vx__mesh_mats* out, vx_error* err);
void vx__mesh_mats_free(const vx_allocator* a, vx__mesh_mats* p);
/* The id of a cell whose largest piece is of material mi (UINT32_MAX: none)
 * and whose area-weighted averages over its pieces are metal, rough and the
 * emission's RGB (ignored unless mi samples them); 0: diffuse. */
uint16_t vx__mesh_mats_id(const vx__mesh_mats* p, uint32_t mi, float metal, float rough, const float emit[3]);
/* What record id stands for: its glTF material and values (metal, rough,
 * emission scalar = the largest of emit_rgb, transmission) and its emission
 * (the factor, or where sampled the quantized levels of it); false when no
 * cell can name id. */
bool vx__mesh_mats_record(const vx__mesh_mats* p, uint32_t id, uint32_t* mi, float v[4], float emit_rgb[3]);

typedef vx_result (*vx__mesh_sink)(void* user, const vx__mesh_region* r, vx_error* err);

/* The attribute channels vx_conv_mesh stores for this mesh and desc. */
uint32_t vx__mesh_attrs(const vx_conv_mesh_desc* desc, const vx_gltf_mesh* mesh);

/* Voxelizes mesh on grid region by region (desc->region, resolved), calling
 * sink once per non-empty region of share `share` of `shares` (0 or 1
 * shares: every region; see vx_conv_mesh_share for the partition). The
 * sink may be called from several threads at once (for different regions,
 * in any order): it must order its results by index itself. */
vx_result vx__mesh_voxelize(const vx_conv_mesh_desc* desc, const vx_gltf_mesh* mesh, const vx_conv_mesh_grid* grid,
                            uint32_t attrs, uint32_t share, uint32_t shares, vx__mesh_sink sink, void* user,
                            vx_error* err);

/* The brick binning both voxelizers start from (the GPU one in
 * convert/mesh_gpu.c): grid coordinates (g[9t + 3v + a] = (pos - min) / h),
 * the (brick, triangle) pairs, brick Morton << 32 | triangle, sorted by
 * brick with triangles ascending within a brick, and the boundaries:
 * bstart[b] is brick b's first pair ([total_bricks] = pair_count), rstart[r]
 * region r's first brick ([region_count] = total_bricks); regions of R^3
 * cells, 2^rb bricks a side. With desc->solid the pairs include a filler
 * (triangle 0xFFFFFFFF) for every brick of the grid, so every brick is
 * listed, and vote holds the parity votes (vx__mesh_fill_brick). */
typedef struct vx__mesh_bins {
    double* g;
    uint64_t* pairs;
    size_t pair_count;
    size_t* bstart;
    size_t total_bricks;
    size_t* rstart;
    size_t region_count;
    uint32_t R;
    unsigned rb;
    uint64_t* vote[3]; /* desc->solid: parity per axis, bit x + n0 (y + n1 z); else NULL */
} vx__mesh_bins;
vx_result vx__mesh_bin(const vx_conv_mesh_desc* desc, const vx_gltf_mesh* mesh, const vx_conv_mesh_grid* grid,
                       vx__mesh_bins* out, vx_error* err);
void vx__mesh_bins_free(const vx_allocator* a, vx__mesh_bins* b);
/* desc->solid for a voxelizer that made the surface itself (the GPU one):
 * the CPU voxelizer's interior fill of the brick of Morton index bm, by the
 * same code (convert/mesh_voxelize.c). From the brick's n surface cells
 * (local Morton keys ascending, with their finished tuples where attrs:
 * NULL channels count as 0) and bins->vote, its cells with the interior
 * ones, in local Morton order, into the out arrays (room for 64^3 each; a
 * NULL channel is not written); returns their count. scratch:
 * vx__mesh_fill_scratch_size() bytes, one per thread. */
size_t vx__mesh_fill_scratch_size(void);
size_t vx__mesh_fill_brick(const vx__mesh_bins* bins, const vx_conv_mesh_grid* grid, uint64_t bm, uint32_t attrs,
                           const uint32_t* local, const uint32_t* rgba, const uint32_t* nrm, const uint32_t* mat, size_t n,
                           void* scratch, uint32_t* out_local, uint32_t* out_rgba, uint32_t* out_nrm, uint16_t* out_mat);
/* The colour tables of the CPU voxelizer (lin_to_srgb8, sample_texture),
 * for the GPU one: thr[256] (linear half-way points between sRGB codes),
 * guess[4097], lin[256] (sRGB code to linear), a255[256] (k / 255.0f). */
void vx__mesh_color_tables(float thr[256], uint32_t guess[4097], float lin[256], float a255[256]);

/* The regions of share `share` of `shares` (vx_conv_mesh_share's
 * partition, a function of the binning alone: rstart as in vx__mesh_bins):
 * *out (allocated, ascending region indices; every region for one share),
 * their count and their bricks. */
vx_result vx__mesh_share_regions(const size_t* rstart, size_t region_count, uint32_t share, uint32_t shares,
                                 const vx_allocator* a, size_t** out, size_t* count, size_t* bricks, vx_error* err);

/* A voxelizer other than vx__mesh_voxelize (convert/mesh_gpu.h), with its
 * contract (the regions of share `share` of `shares`, each once, as
 * vx__mesh_share_regions assigns them). */
struct vx_conv_mesh_backend {
    /* builds: the sink builds octrees (vx__svo_build_interned): a region
     * may come as its node pool and tuples (interned.pool) without its
     * cells (count set, keys NULL); else every region comes with its cells. */
    vx_result (*voxelize)(void* self, const vx_conv_mesh_desc* desc, const vx_gltf_mesh* mesh,
                          const vx_conv_mesh_grid* grid, uint32_t attrs, uint32_t share, uint32_t shares, bool builds,
                          vx__mesh_sink sink, void* user, vx_error* err);
    void* self;
};

#endif
