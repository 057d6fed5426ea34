/* convert/mesh_gpu.h - the mesh voxelizer (convert/mesh.h) on a Vulkan
 * device: the same cells, colours, normals and materials as the CPU
 * voxelizer, bit for bit (tests/convert/mesh_gpu_test.c checks it on the
 * corpus), the octree then built from them by the CPU builder as before.
 *
 *   vx_gpu* gpu; vx_gpu_create(&(vx_gpu_desc){0}, &gpu, &err);      // render/render.h
 *   vx_conv_mesh_gpu* mg; vx_conv_mesh_gpu_create(gpu, NULL, &mg, &err);
 *   vx_conv_mesh(&(vx_conv_mesh_desc){ .res = 1024, .backend = vx_conv_mesh_gpu_backend(mg) }, &mesh, &s, &st, &err);
 *   vx_conv_mesh_gpu_destroy(mg); vx_gpu_destroy(gpu);
 *
 * How (convert/mesh_gpu.c): the CPU bins triangles into 64^3 bricks as its
 * own voxelizer does (vx__mesh_bin); the GPU then runs one thread per
 * (brick, triangle) pair with the CPU's clipping in the same double
 * arithmetic (shaders/meshvox.comp: counts, a prefix sum, records of each
 * (cell, triangle) piece; where a glTF material samples its metallic-
 * roughness or emissive texture per cell, the piece's weighted metallic,
 * roughness and emission too), a stable radix sort of the records by cell
 * (shaders/gpusort.comp), and one thread per cell summing its pieces in
 * triangle order with the CPU's float additions (shaders/meshreduce.comp;
 * the material id from those averages as the CPU's cell_material makes it),
 * then the cells' attribute tuples interned per region (shaders/meshintern.comp:
 * a radix sort by (region, tuple), one id per run), so that each region's
 * octree builder hashes its distinct tuples once (vx__svo_build_interned)
 * instead of every cell's; then each region's octree built level by level
 * (shaders/meshbuild.comp: uniform collapse, subtrees shared through a hash
 * table of their contents, checked against the canonical copy, pool
 * positions in the CPU builder's order) and only its node pool downloaded:
 * the CPU builder then computes the representatives and lays the blocks
 * out (vx__svo_build_interned with a pool). The cells come back in Morton
 * order, region by region, with their tuple ids, to the sink.
 *
 * The binning runs on the CPU's cores (triangle ranges in parallel, the
 * pairs the one-thread loop's), the images copied for the upload meanwhile,
 * and the octree's levels go to the GPU in three submissions (their counts
 * stay on the device; the first two levels' are read back).
 *
 * desc.solid is a hybrid: the GPU voxelizes the surface as above; the CPU
 * computes the parity votes (in the binning, as its own voxelizer does) and
 * fills each 64^3 brick from the GPU's surface cells with the CPU
 * voxelizer's own code (vx__mesh_fill_brick: interior cells and their
 * attributes), and the CPU builders build the octrees from those cells
 * (no GPU build: the interior is most of a solid's cells). The file is the
 * CPU path's byte for byte (mesh_gpu_test, test_vox2svo_gpu).
 *
 * Needs shaderFloat64 (NVIDIA, lavapipe); without it the voxelizer fails
 * with VX_ERR_UNSUPPORTED (the CPU one does both).
 * The object keeps its device buffers between calls (grown as needed); it
 * is not for several threads at once. */
#ifndef VX_CONVERT_MESH_GPU_H
#define VX_CONVERT_MESH_GPU_H

#include <stddef.h>
#include <stdint.h>

#include "convert/mesh.h"

#ifdef __cplusplus
extern "C" {
#endif

struct vx_gpu;
typedef struct vx_conv_mesh_gpu vx_conv_mesh_gpu;

/* Wall seconds of the last voxelization's stages (each a submission waited
 * for), and its sizes. */
typedef struct vx_conv_mesh_gpu_stats {
    double bin;      /* CPU: grid coordinates and brick pairs (vx__mesh_bin) */
    double upload;   /* triangles, pairs, materials, textures */
    double count;    /* cells per pair and their prefix sum */
    double emit;     /* the records, their radix sort by cell, the per-cell sums: one submission */
    double sort;     /* 0 (in emit; vox_gpu splits it) */
    double reduce;   /* 0 (in emit) */
    double intern;   /* the cells' attribute tuples interned per region for the builders */
    double download; /* the cells */
    double build;    /* the octrees' node pools built on the GPU (meshbuild.comp), downloaded */
    double sink;     /* CPU: regions handed to the sink (the octree builds) */
    uint64_t pairs, records, cells, tuples; /* tuples: distinct per region, summed (0: not interned) */
    uint32_t sort_passes, intern_passes;
    uint64_t node_slots, nodes, pool_words; /* the GPU build: parents made, distinct nodes, words downloaded */
    uint64_t rep_tuples; /* representatives' tuples that no cell has (interned on the GPU) */
    uint64_t run_records; /* the block layout's attribute records, laid out on the GPU (0: by the CPU) */
    uint64_t laid_words;  /* the models' node words laid out on the GPU (0: the CPU laid the blocks out) */
    /* the models' attribute records filled on the GPU and copied by the
     * builders (0: the builders looked each record's tuple up) */
    uint64_t filled_records;
    uint32_t layout_iterations; /* the GPU's block layout iterations (until one changed nothing) */
    /* GPU seconds of the build's steps (timestamps; 0 without them), within
     * build's wall time: [0] the levels (parents, collapse, hashes), [1]
     * sharing (hash table, the check), [2] representatives interned, [3]
     * the sort into pool order, [4] pool positions and words, [5] attribute
     * runs, [6] the copy for the download, [7] the blocks. */
    double build_gpu[8];
    /* and of the voxelizer's: [0] count (with the uploads' copies), [1]
     * emit, [2] sort, [3] reduce, [4] the tuples interned */
    double vox_gpu[5];
    uint32_t levels;
    /* The GPU build was asked for but the CPU builders built the trees
     * (a hash collision found, or the node buffers too small); 0: not. */
    uint32_t build_fallback;
    /* 1: some glTF material samples its metallic-roughness or emissive
     * texture per cell, and the shaders sampled them (the records carry the
     * weighted values, the reduce makes each cell's material id); 0: none. */
    uint32_t sampled_materials;
} vx_conv_mesh_gpu_stats;

/* Who builds the octrees from the cells. */
typedef enum vx_conv_mesh_gpu_build {
    VX_CONV_MESH_GPU_BUILD_GPU = 0, /* the GPU (node pools, meshbuild.comp); the CPU lays them out */
    VX_CONV_MESH_GPU_BUILD_CPU,     /* the CPU builders from the interned tuples */
    VX_CONV_MESH_GPU_BUILD_CHECK,   /* both: each region's CPU builder fails unless the GPU's pool is its own */
    VX_CONV_MESH_GPU_BUILD_GPU_POOLS /* the GPU without the blocks: the CPU lays them out (for comparisons) */
} vx_conv_mesh_gpu_build;

/* gpu is borrowed: it must outlive the object. alloc may be NULL (malloc). */
vx_result vx_conv_mesh_gpu_create(struct vx_gpu* gpu, const vx_allocator* alloc, vx_conv_mesh_gpu** out,
                                  vx_error* err);
/* For vx_conv_mesh_desc.backend (valid while mg lives). */
const struct vx_conv_mesh_backend* vx_conv_mesh_gpu_backend(vx_conv_mesh_gpu* mg);
void vx_conv_mesh_gpu_last_stats(const vx_conv_mesh_gpu* mg, vx_conv_mesh_gpu_stats* out);
/* Default VX_CONV_MESH_GPU_BUILD_GPU; the file is the same either way. */
void vx_conv_mesh_gpu_set_build(vx_conv_mesh_gpu* mg, vx_conv_mesh_gpu_build mode);
/* For tests of the GPU build's hash tables: collisions forced. FEW_SLOTS
 * starts every table probe in one of 8 slots (long probe chains; the
 * result is exact and stays on the GPU); FEW_LABELS keeps 4 bits of the
 * structural hash, so different subtrees hash alike: the GPU's check finds
 * them and the CPU builders build (vx_conv_mesh_gpu_stats.build_fallback).
 * The file is the same either way. */
typedef enum vx_conv_mesh_gpu_hash {
    VX_CONV_MESH_GPU_HASH_FULL = 0, /* the default */
    VX_CONV_MESH_GPU_HASH_FEW_SLOTS,
    VX_CONV_MESH_GPU_HASH_FEW_LABELS
} vx_conv_mesh_gpu_hash;
void vx_conv_mesh_gpu_set_hash(vx_conv_mesh_gpu* mg, vx_conv_mesh_gpu_hash hash);
void vx_conv_mesh_gpu_destroy(vx_conv_mesh_gpu* mg);

#ifdef __cplusplus
}
#endif
#endif /* VX_CONVERT_MESH_GPU_H */
