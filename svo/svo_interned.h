/* svo/svo_interned.h - the octree builder's entry for callers that have
 * already deduplicated their cells' attribute tuples (the GPU voxelizer,
 * convert/mesh_gpu.c, interns them on the device): the tuple record, the
 * coarse-level rule over tuples, and vx__svo_build_interned, which builds
 * the same model as vx_svo_build_model (svo.h) word for word while hashing
 * each distinct tuple once. Names keep the vx__ prefix, as render/gpu.h:
 * documented for the toolkit's modules, not part of the user API.
 *
 * Typical use:
 *   vx__svo_interned pre = {.rec = idx, .tab = tuples, .count = n};
 *   vx_svo_voxels in = {.size = {n, n, n}, .count = cells, .keys = keys, .attrs = attrs};  // channels NULL
 *   vx__svo_build_interned(&desc, &in, &pre, &model, &stats, err); */
#ifndef VX_SVO_INTERNED_H
#define VX_SVO_INTERNED_H

#include "svo/svo.h"

/* An attribute tuple, every channel (those a model lacks are zero); pad is
 * always zero so tuples compare with memcmp (the builder's records and the
 * incremental editor's, svo_edit.c). */
typedef struct vx__svo_rec {
    uint32_t rgba, normal;
    float density;
    uint16_t material;
    uint8_t palette, pad;
} vx__svo_rec;
_Static_assert(sizeof(vx__svo_rec) == 16, "vx__svo_rec layout");
/* The coarse-level rule of svo.h (vx_svo_build_model's representative) over
 * n (1..8) children's tuples; n equal tuples give that tuple exactly. */
void vx__svo_rec_mean(uint32_t attrs, const vx__svo_rec* const* c, unsigned n, vx__svo_rec* out);

/* The node pool of a tree built by the caller (the GPU,
 * convert/shaders/meshbuild.comp): the nodes the builder's streaming pass
 * appends, in its order, with its ids. A node at word offset off:
 * [0] valid | leaf << 8, [1] and [2] anything (the builder writes its
 * representative and block position there; see reps), [3 + j] child j over valid in
 * octant order: the tuple id of a leaf child, the offset of a node child
 * (an earlier node). Nodes follow each other without gaps. */
typedef struct vx__svo_pool {
    const uint32_t* words; /* read only (the builder copies the nodes) */
    size_t count;
    uint32_t root;   /* the root's offset, or its tuple id with root_leaf */
    bool root_leaf;
    uint64_t plain, collapsed; /* vx_svo_build_stats.desc_plain, desc_collapsed */
    /* Word [1] of each node is its representative's tuple id (the rule of
     * vx__svo_rec_mean, computed by the caller) and the tuples are all in
     * vx__svo_interned.tab, distinct: the builder then hashes nothing. */
    bool reps;
    /* With reps: the block layout's attribute runs laid out by the caller
     * as the layout does (each node's run of its children's tuple ids over
     * valid, shared as run_intern shares it, svo/svo_build.c): word [2] of
     * each node is its run's first record, recs the records (tuple ids,
     * nrecs of them). The builder then lays out only the blocks. */
    bool runs;
    const uint32_t* recs;
    size_t nrecs;
    /* With runs: the blocks laid out by the caller too, as the layout lays
     * them out (near pointers up to VX__SVO_PTR_MAX, far words, the reuse
     * window of lone records): laid holds the model's node words (root
     * descriptor last; laid_count of them, laid_far far pointers among them,
     * laid_desc descriptor words as vx_svo_build_stats.desc_dag counts
     * them), root_rep the root's representative (a tuple id). The builder
     * then only fills the records; words and count may be left out (NULL,
     * 0) unless check_pool, which also compares laid with its own words. */
    const uint32_t* laid;
    size_t laid_count;
    uint64_t laid_far, laid_desc;
    uint32_t root_rep;
    /* With laid: the model's attribute records filled by the caller too
     * (the GPU looks each record's tuple up, meshbuild.comp MODE 30): record
     * k of the runs as its tuple's channels, nrecs of each channel in the
     * model's attrs (attr_rgba, attr_normal, attr_material; read only: the
     * builder copies them, on vx__svo_interned.threads threads), root_attr
     * the first record equal to the root's representative, or nrecs when
     * none is (the builder then appends root_tuple, as its layout does).
     * The builder reads no tuple then (vx__svo_interned.rec, tab and recs
     * may be NULL, count anything); with check_pool it fails unless these
     * are its own model's records and root_attr. */
    bool filled;
    const uint32_t* attr_rgba;
    const uint32_t* attr_normal;
    const uint16_t* attr_material;
    uint32_t root_attr;
    vx__svo_rec root_tuple;
} vx__svo_pool;

/* Entries whose tuples the caller has already interned (the GPU voxelizer,
 * convert/mesh_gpu.c, dedups them on the device): entry i carries
 * tab[rec[i]]; tab holds count distinct tuples (channels outside attrs and
 * pad zero). */
typedef struct vx__svo_interned {
    const uint32_t* rec;
    const vx__svo_rec* tab;
    size_t count;
    /* Lay the node blocks out on a second thread while the tree is built
     * (for callers with a core to spare; the model is the same). */
    bool layout_thread;
    /* Threads that may intern tab (from 2^18 tuples) and copy the records
     * of a filled pool (from 2^17; 0 or 1: the caller's). */
    unsigned threads;
    /* The tree already built (NULL: the builder builds it). The builder
     * then computes the representatives (unless pool->reps) and lays the
     * blocks out; entries given are still checked (Morton keys strictly
     * increasing); with pool->reps they may be left out (keys and rec
     * NULL, count only). With
     * check_pool it builds the tree itself as well and fails (naming the
     * first node that differs, and its height) unless pool is its own pool
     * word for word, and with pool->runs unless the runs are its layout's:
     * the test of the caller's build. */
    const vx__svo_pool* pool;
    bool check_pool;
} vx__svo_interned;
/* vx_svo_build_model over such entries: in's channel arrays are NULL (the
 * tuples are pre), in->attrs != 0, no tiles (in->level NULL). The builder
 * interns tab once instead of hashing every entry's tuple; the model is the
 * one vx_svo_build_model builds from the expanded tuples, word for word. */
vx_result vx__svo_build_interned(const vx_svo_build_desc* desc, const vx_svo_voxels* in, const vx__svo_interned* pre,
                                 vx_svo_model* out, vx_svo_build_stats* stats, vx_error* err);

#endif
