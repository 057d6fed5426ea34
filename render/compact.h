/* render/compact.h - the compact GPU layout of a scene (issue 18): geometry as
 * one DAG shared regardless of attributes, attributes in a separate array
 * indexed by a voxel's rank in traversal (Morton) order.
 *
 * The layout today's tracer uploads (render_scene.c) is the .svo node array
 * plus one 4-byte RGBA record per leaf. Its DAG shares a subtree only when the
 * colours below agree too, so a textured mesh shares almost nothing (the
 * DamagedHelmet at 4096^3: 5.06 bytes per voxel). Here the geometry DAG never
 * sees a colour: subtrees that differ only in colour are one node, across
 * the models of the scene as well. A cell's colour is found by its index i,
 * the number of set cells before it in Morton order, which the traversal
 * sums on the way down from per-node child offsets.
 *
 * Geometry: slots of 64 bits (2 words, low first) in one array for the
 * scene; a node lives in its parent's block of children, so a push in the
 * walk reads the child's slot and nothing else (the node and the pointer to
 * its children arrive in one load, as in trace.comp's descriptors; a walk
 * that first read a pointer word, then the child's header, ran at 0.55-0.84
 * of trace.comp, docs/PERFORMANCE.md issue 18). With the brick dictionary
 * (VX_COMPACT_BRICKS_DICT) a push into a brick reads its index word first.
 *   level >= 3:  word 0 trace.comp's descriptor form, bits 8..15 valid mask,
 *                bits 0..7 leaf mask (a leaf child is one cell at level 1, a
 *                full cube of 8^(level-1) cells above), at levels 3-4 bits
 *                16..31 its rank (below; at most 8 * 8^4 cells, 8 * 8^3 at
 *                level 3 in bits 16..30); bit 31 at level 3
 *                VX_COMPACT_INDEXED (the scene has the dictionary and the
 *                node bricks); word 1 its children's block: the slot index
 *                of its non-leaf children in octant order, or the word index
 *                of their index words (VX_COMPACT_INDEXED); 0 without any
 *   level 1, 2:  a brick, the 64-bit mask of its cells by their Morton code
 *                within the node (bit 8 * o2 + o1: octant o2 of the node,
 *                octant o1 of that child); the index of a cell within it is
 *                the number of set bits below its own. A model of depth 1
 *                uses bits 0..7. In its block, or once in the dictionary.
 *   brick index word (VX_COMPACT_BRICKS_DICT: a level-3 node's block holds
 *                one per brick child): bits 0..22 the brick's slot
 *                (VX_COMPACT_BRICK_BITS; more than VX_COMPACT_MAX_BRICKS
 *                distinct bricks are refused), bits 23..31 the cells of the
 *                block's bricks up to and including it, less one.
 * A surface's 4^3 bricks repeat (DamagedHelmet at 16384: 15.5 M brick
 * children, 466 K distinct masks), so with the dictionary a brick costs a
 * word where it is used and 8 bytes once: 0.64x the geometry at 16384, but
 * a second dependent load per push into a brick (docs/PERFORMANCE.md, issue
 * 18, seventh step); scenes whose bricks do not repeat grow.
 * Order: the dictionary's brick_count slots (a model of depth <= 2 has its
 * brick there as root), the slots of levels >= 5, of level 4, of level 3, the
 * bricks' blocks (slot_count slots in all, words 0 .. 2 slot_count), the
 * rank words of the levels >= 5 slots (slot s at word 2 slot_count -
 * brick_count + s), then the blocks of index words. Blocks are hash-consed
 * by their words and level over the whole scene, so equal subtrees are
 * stored once whatever their colours. A model's root is a block of one
 * slot. The rank of a slot is the cells of its block's slots up to and
 * including it (a block's own property, so it is shared with it): a rank
 * word (levels >= 5), 16 bits of word 0 (levels 3-4), the index word's count
 * (indexed bricks); bricks in their block have none: the cells before brick
 * k of a block are the popcounts of bricks 0 .. k-1, in the cache line the
 * walk reads for brick k anyway. The index of a cell is the sum, over the
 * levels of its path, of the cells in the children before it:
 * popcount(leaf & below) cubes of 8^(level-1) and, when k = popcount(inner
 * & below) > 0, the rank of child k - 1 of the block; plus the Morton key of
 * the cell inside a full-cube leaf or its bit rank inside a brick.
 *
 * Attributes, per model, one value per cell in Morton order, cut into blocks
 * of the model's `block` values; each block has a header word and a payload that
 * identical blocks of the model share, coded in the smallest of three ways
 * (a textured mesh's exact colours: few distinct values per block, or few
 * bits of spread per channel, or neither). Blocks form groups of
 * VX_COMPACT_GROUP; a group whose blocks have one header keeps it once, so a
 * uniform region costs a word per group, not per block:
 *   attr[base + g]           group g = b / VX_COMPACT_GROUP: bits 0..30 word
 *                            offset q (from base) of its headers, bit 31 set
 *                            when the group has one header for all blocks
 *   attr[base + q (+ b % VX_COMPACT_GROUP without bit 31)]
 *                            header of block b: bits 0..4 code c, bits 5..31
 *                            payload word offset p (from base)
 *   c == 31 (raw):           the block's values packed at the value width
 *   c == 30 (delta, RGBA):   word 0 each channel's minimum (RGBA8), word 1
 *                            the residuals' bit widths w_ch (4 bits each, R
 *                            lowest, 0..8) and in bit 16 the flag d, then per
 *                            value its residuals (value - minimum) R, G, B, A
 *                            at w_R..w_A bits, value j at bit
 *                            j * (w_R + w_G + w_B + w_A). With d the channels
 *                            are (R - G + 128, G, B - G + 128, A) mod 256.
 *   c in 0..29 (palette):    block * c bits of indices (packed, little end
 *                            first, ceil(block * c / 32) words), then the
 *                            block's distinct values packed at the value width
 * Value width: 8 bits for palette models (the scene palette index; the
 * colour is palette[index]), 32 bits RGBA otherwise. Values are exact: a
 * model's colour of cell x is vx_svo_attr_rgba() of its record.
 *
 * Limits: a model of more than 2^32 - 1 cells, a scene of more than
 * VX_COMPACT_MAX_SLOTS slots, or a model whose attribute region passes 2^27
 * words (512 MiB), is refused with VX_ERR_LIMIT. */
#ifndef VX_COMPACT_H
#define VX_COMPACT_H

#include "render/render.h"
#include "svo/svo.h"

#ifdef __cplusplus
extern "C" {
#endif

#define VX_COMPACT_BLOCK 64u          /* attribute block, values (docs/PERFORMANCE.md issue 18) */
#define VX_COMPACT_BLOCK_UNIFORM 512u /* the block of models mostly of one colour per block */
#define VX_COMPACT_RAW 31u   /* block code: values stored as they are */
#define VX_COMPACT_DELTA 30u /* block code: RGBA as per-channel minimum plus residuals */
#define VX_COMPACT_GROUP 64u /* blocks per group word */
#define VX_COMPACT_MAX_SLOTS 0x3FFFFFFFu /* geometry slots (up to 3 words each with the ranks) */
#define VX_COMPACT_BRICK_BITS 23u        /* bits of a brick's dictionary index in its index word */
#define VX_COMPACT_INDEXED 0x80000000u   /* word 0 of a level-3 node: its block holds index words */
enum { VX_COMPACT_BRICKS_INLINE = 0, VX_COMPACT_BRICKS_DICT = 1 };
enum { VX_COMPACT_MERGE_AUTO = 0, VX_COMPACT_MERGE_ORDERED = 1, VX_COMPACT_MERGE_ALL = 2 };
#define VX_COMPACT_MERGE_ALL_THREADS 8u
#define VX_COMPACT_MAX_BRICKS (1u << VX_COMPACT_BRICK_BITS) /* distinct bricks of a scene */

typedef struct vx_compact_desc {
    const vx_allocator* alloc;
    /* values per attribute block, a power of two in 8..1024; 0: per model,
     * VX_COMPACT_BLOCK, or VX_COMPACT_BLOCK_UNIFORM where at least half of
     * the blocks of 64 hold one value and the larger blocks take fewer words */
    uint32_t block;
    /* distinct bricks a scene may have, 0: VX_COMPACT_MAX_BRICKS (what the
     * index word's bits hold); fewer refuses a scene past it as the bits'
     * limit would (tests: the refusal without 2^23 bricks) */
    uint32_t max_bricks;
    /* VX_COMPACT_BRICKS_INLINE (0): bricks in their blocks, a push into one
     * a single load; VX_COMPACT_BRICKS_DICT: the brick dictionary (about
     * 0.65x the geometry of a large surface scene, a second dependent load
     * per push into a brick: docs/PERFORMANCE.md issue 18, seventh step) */
    uint32_t bricks;
    /* threads for the geometry DAG, 0: one per CPU where the scene has at
     * least 2^20 node words and two models, else one; any count gives the
     * same bytes (each model's blocks are built apart, then merged in model
     * order: docs/PERFORMANCE.md issue 18, "65536^3") */
    uint32_t threads;
    /* how the models' blocks are merged on several threads (the same
     * bytes): VX_COMPACT_MERGE_AUTO (0) ALL from VX_COMPACT_MERGE_ALL_THREADS
     * threads on, else ORDERED; ORDERED: in model order on one thread at a
     * time beside the builds (the least work); ALL: level by level on
     * every thread (about twice the work, no serial part). The brick
     * dictionary always merges ORDERED. */
    uint32_t merge;
    /* the attributes left in one array per model (attr_region; attr NULL):
     * no second host copy of them (they are built apart on the threads),
     * for the upload (vx_compact_gpu_create takes either form);
     * vx_compact_join_attrs gives the one array the CPU walks read */
    bool attr_regions;
    /* vx_compact_build_reader with attr_regions: NULL, or a layout of the
     * same models built before (with attr_regions, the same block; the other
     * brick form, say) whose attribute regions are moved into this one
     * instead of being built again: the attributes do not depend on the
     * geometry's form, so a second pass over the file (vx_svo_reader_rewind,
     * AUTO's brick dictionary) builds the geometry only and the host never
     * holds two copies of them. Each model's kind and cells and the
     * allocator must match (else VX_ERR_INVALID_ARG, nothing moved); on success attrs_from keeps its
     * geometry and has no attributes left (attr_region NULL, attr_words 0). */
    struct vx_compact_scene* attrs_from;
} vx_compact_desc;
vx_compact_desc vx_compact_desc_defaults(void);

enum { VX_COMPACT_ATTR_NONE = 0, VX_COMPACT_ATTR_PALETTE = 1, VX_COMPACT_ATTR_RGBA = 2 };

typedef struct vx_compact_model {
    uint32_t root;      /* slot of the root node, or VX_SVO_ROOT_EMPTY / VX_SVO_ROOT_LEAF */
    uint32_t depth;     /* the source model's depth */
    uint32_t voxels;    /* cells set (attribute indices 0..voxels-1) */
    uint32_t attr_kind; /* VX_COMPACT_ATTR_*: NONE is opaque white */
    uint32_t attr_base; /* word index in attr of the model's first block header */
    uint32_t attr_words; /* words of the model's region (headers and payloads) */
    uint32_t block;      /* values per attribute block */
} vx_compact_model;

typedef struct vx_compact_stats {
    uint64_t nodes;         /* geometry nodes of the scene */
    uint64_t offset_words;  /* geometry words spent on ranks (one per slot of level >= 5) */
    uint64_t bricks;        /* distinct bricks (the dictionary) */
    uint64_t brick_refs;    /* brick index words */
    uint64_t blocks;        /* attribute blocks */
    uint64_t uniform;       /* blocks of one value (code 0) */
    uint64_t raw;           /* blocks stored raw */
    uint64_t delta;         /* blocks stored as deltas */
    uint64_t uniform_groups; /* groups whose blocks share one header */
    uint64_t shared;        /* blocks whose payload an earlier block of the model already had */
    uint64_t distinct_sum;  /* distinct values summed over blocks */
    uint64_t level_slots[33];  /* geometry slots by their node's level (bricks: 2, or 1 in a model of depth 1) */
    uint64_t level_blocks[33]; /* blocks by their slots' level */
    double attr_seconds;       /* wall time of the attributes' build (on several threads), of the whole build's */
    double geom_seconds;       /* wall time of the geometry DAG's build, of the whole build's */
    double geom_merge_seconds; /* of which the merge of the models' blocks in model order (on one thread at a time) */
    uint32_t geom_threads;     /* threads it ran on */
} vx_compact_stats;

typedef struct vx_compact_scene {
    uint32_t model_count;
    vx_compact_model* models;
    uint32_t slot_count;  /* geometry slots (the bricks of the dictionary first) */
    uint32_t brick_count; /* the dictionary's bricks: slots 0 .. brick_count - 1 (0 without it) */
    bool brick_dict;      /* built with VX_COMPACT_BRICKS_DICT */
    uint32_t geom_words;  /* 2 slot_count + the ranks + the brick index words, rounded up to even */
    uint32_t* geom;
    uint32_t attr_words;
    uint32_t* attr;          /* the attribute words (NULL while they are in attr_region) */
    uint32_t** attr_region;  /* vx_compact_desc.attr_regions: model i's words (models[i].attr_words of
                                them, at attr_base in attr's numbering), or NULL */
    uint32_t palette[256]; /* the scene palette (palette models' colours) */
    /* the palette indices the models' attribute records use (bit i of word
     * i / 32; index 0 always): what a pass needs of the records beside the
     * layout (which materials emit or are metal, probes/probe_gpu.c), found
     * while each model is in hand, so that a layout built from a model reader
     * answers it without the models (svo_bake --load models) */
    uint32_t palette_used[8];
    vx_compact_stats stats;
    vx_allocator alloc;
} vx_compact_scene;

/* Builds the layout of every model of s (all of them, drawn or not, as the
 * tracer uploads them). *out owns its arrays (vx_compact_free). s must be
 * valid (vx_svo_validate_scene). */
vx_result vx_compact_build(const vx_compact_desc* desc, const vx_svo_scene* s, vx_compact_scene* out, vx_error* err);
/* The same layout, byte for byte, from a model reader (svo/svo.h) that has
 * handed over no model yet: the models are taken from it in turn (on the
 * build's threads, each while another is read) and each is freed once its
 * geometry and attribute region are built, so the host holds the layout and
 * the models in hand (one per thread) instead of the scene; the reader is
 * finished (vx_svo_reader_finish) before the layout is made. On failure
 * (a model the reader refuses: the error names the file and the model)
 * nothing is left built; the reader cannot be used further. The scene must
 * be valid as vx_compact_build's (the reader validates every model). */
vx_result vx_compact_build_reader(const vx_compact_desc* desc, vx_svo_model_reader* rd, vx_compact_scene* out,
                                  vx_error* err);
void vx_compact_free(vx_compact_scene* c);
/* Moves the attribute regions of `from` into `to`, a layout of the same
 * models (each model's kind and cells checked; the same allocator) whose attributes have been
 * moved out or were never built (desc.attrs_from): how a second build of the
 * geometry takes or gives back the first one's attributes. `from` must hold
 * them in regions (attr_regions). Nothing moves on failure. */
vx_result vx_compact_move_attrs(vx_compact_scene* to, vx_compact_scene* from, vx_error* err);
/* Joins the per-model attribute regions (vx_compact_desc.attr_regions) into
 * attr, freeing each as it is copied; nothing to do without them. */
vx_result vx_compact_join_attrs(vx_compact_scene* c, vx_error* err);

/* Walks model m's geometry to cell (x, y, z): false when the cell is empty or
 * outside the model's cube, else true and *index its attribute index. */
bool vx_compact_lookup(const vx_compact_scene* c, uint32_t m, uint32_t x, uint32_t y, uint32_t z, uint32_t* index);
/* Internal (compact.c, compact_trace.c): the cells of the first k non-leaf
 * children of a level-L node whose children's block is blk. */
uint32_t vx__compact_inner_before(const vx_compact_scene* c, uint32_t L, uint32_t blk, uint32_t k);
/* Internal: the slot of child k (in block order) of a level-L node whose
 * children's block is blk (a brick's dictionary slot at level 3). */
uint32_t vx__compact_child(const vx_compact_scene* c, uint32_t L, uint32_t blk, uint32_t k);
/* Internal (compact.c, compact_gpu.c): the level-3 records, a GPU-side
 * index (docs/PERFORMANCE.md issue 18, branch ck11): for each level-3 slot s
 * reached from a model's root, words 2 (s - *first) and 2 (s - *first) + 1
 * hold the cells before each octant o = 1..7 of the node (its leaf cubes
 * and its non-leaf children's cells; at most 448, 9 bits at bit 9 (o - 1)
 * of the 64-bit pair), so that the trace kernel finds a hit's cells before
 * its brick in one load where the walk gives the level-3 node's slot.
 * *count records from slot *first (level-3 and level-4 slots lie together,
 * compact.h's order; the others' records are 0); *words NULL and *count 0
 * where no model has a level-3 node. Owned by the caller (alloc). */
vx_result vx__compact_level3_records(const vx_compact_scene* c, const vx_allocator* alloc, uint32_t** words,
                                     uint32_t* first, uint32_t* count, vx_error* err);
/* Decodes attribute index i of model m (its block's payload); opaque white
 * for a model without attributes or i past its cells. */
uint32_t vx_compact_rgba(const vx_compact_scene* c, uint32_t m, uint32_t i);

/* Internal (compact.c): the stored value of attribute index i of model m
 * (the palette index for palette models, RGBA otherwise); and n values
 * coded as one model's attribute region (compact.h's groups, headers and
 * payloads, offsets from its first word) in *words (freed with alloc). */
uint32_t vx__compact_value(const vx_compact_scene* c, uint32_t m, uint32_t i);
vx_result vx__compact_encode(const vx_allocator* alloc, uint32_t block, uint32_t kind, const uint32_t* vals, uint32_t n,
                             vx_compact_stats* st, uint32_t** words, uint32_t* nwords, vx_error* err);

/* ---- pages: scenes bigger than GPU memory (render/compact_page.c) -------------------
 * The layout cut at page level Lp (>= 3): the subtree below each node of
 * level Lp that has children of its own is a page, loaded into a pool on
 * the GPU when a ray needs it; the levels above Lp (the top) stay resident.
 * The top is a tree down to level Lp (each occurrence of a level-Lp node its
 * own slot, so a page is one place of one model and has one index range of
 * attributes; blocks shared between pages are stored in each, sharing inside
 * a page stays). A page root's slot keeps its descriptor; its word 1 is the
 * pool slot of the page's first block when resident, else bit 31 | page.
 * The top and the pages keep the geometry's form before the brick
 * dictionary (a page would need the whole dictionary resident): bricks in
 * their blocks as slots, descriptors of 16 bits, a rank word per slot of
 * level >= 3 (a brick's rank is the popcounts of the bricks before it).
 *
 * Top words: the top's slots (2 words each), then a rank word per slot
 * (word 2 top_slots + s, 0 for bricks), then each model's attribute region:
 * its values in Morton order with the cells of its pages replaced by 0 (a
 * page's range of indices codes as uniform blocks, a word per group).
 * A page image (words, position independent; loaded at an even word 2P):
 *   0: attribute region (word offset; + 2P when loaded)
 *   1: rank word base - 2 (+ P when loaded: the rank of slot s, s >= P + 2,
 *      of levels >= 3 is at word that + s)
 *   2: the page number, 3: 0
 *   4 ..: its slots (slot P + 2 + j: local slot j), those of levels >= 3
 *      first (n3 of them: their word 1 a local block index, + P + 2 when
 *      loaded), the page root's children's block at local slot 0
 *   then the n3 ranks, then the attribute region of the page's cells
 *   (indices from its first cell), rounded up to an even count of words. */
typedef struct vx_compact_page {
    uint32_t model;      /* the model */
    uint32_t top_slot;   /* its root's slot in the top */
    uint32_t cube[3];    /* its cube's first cell in the model (side 2^page_level) */
    uint32_t first;      /* the model's attribute index of its first cell */
    uint32_t cells;      /* its cells */
    uint32_t rgba;       /* the mean colour of its cells: what a frame draws while it is not resident */
    uint32_t slots, n3;  /* geometry slots of its image, of levels >= 3 */
    uint32_t words;      /* words of its image */
    uint64_t offset;     /* word offset of its image in data */
} vx_compact_page;

typedef struct vx_compact_paged {
    uint32_t page_level;
    uint32_t model_count;
    vx_compact_model* models; /* root: a top slot; attr_base: a top word */
    uint32_t top_slots;
    uint32_t top_words;
    uint32_t* top;
    uint32_t page_count;
    vx_compact_page* pages;
    uint64_t data_words;
    uint32_t* data; /* the page images; NULL with the file source (reader) */
    uint32_t max_page_words;
    uint32_t palette[256];
    uint32_t palette_used[8]; /* as vx_compact_scene's (the passes' tables) */
    uint64_t source_bytes;    /* the compact layout's bytes it was cut from (from a reader: the models'
                                 own layouts summed, no sharing between models) */
    /* the file source (vx_compact_page_build_reader): the reader the pages are
     * cut from again on demand (borrowed: it must outlive every user of this
     * layout), and the attribute block the models were built with */
    vx_svo_model_reader* reader;
    uint32_t block;
    uint32_t threads; /* vx_compact_page_desc.threads: the models the host cache cuts at once too (0: one a CPU) */
    vx_allocator alloc;
} vx_compact_paged;

/* Cuts c (vx_compact_build of a scene) at page_level (3..31; models of at
 * most page_level levels are all top). *out owns its arrays. */
vx_result vx_compact_page_build(const vx_compact_scene* c, uint32_t page_level, const vx_allocator* alloc,
                                vx_compact_paged* out, vx_error* err);
void vx_compact_paged_free(vx_compact_paged* p);

/* ---- pages from the file (the file source) -------------------------------------------
 * The paged layout without the whole compact layout or its page images on
 * the host: vx_compact_page_build_reader takes a fresh model reader's
 * models in turn, builds each model's compact layout on its own (the words
 * vx_compact_build gives its blocks: a page's image depends on its subtree
 * and cells only), cuts it into its top and pages and drops it, keeping the
 * top (each model's tree down to the page level and its top attributes) and
 * the page table (each page's model, cube, cells, size and mean colour), not
 * the images; the reader is finished and stays borrowed (p->reader). A page
 * image is then cut again when a frame needs it: the page's model read again
 * (vx_svo_reader_model), its layout built, its top walked to number its
 * pages, the requested pages' images made and checked against the table,
 * the model dropped. The images are vx_compact_page_build's word for word;
 * the top differs only where models of at most page_level levels would
 * share blocks across models (each model's top is its own). */
typedef struct vx_compact_page_desc {
    const vx_allocator* alloc;
    uint32_t page_level; /* 3..31; 0: VX_RENDER_FRAME_LEVELS */
    uint32_t block;      /* vx_compact_desc.block (0: per model) */
    uint32_t threads;    /* models cut at once (each on one thread; their decodes share the CPUs): 0 one per CPU */
} vx_compact_page_desc;
vx_result vx_compact_page_build_reader(const vx_compact_page_desc* desc, vx_svo_model_reader* rd, vx_compact_paged* out,
                                       vx_error* err);
/* A host cache of page images cut from the file, at most `budget` bytes of
 * them (least recently used out first; 0: none kept, every load from the
 * file). p (with its reader) is borrowed. _get writes the images of pages[0
 * .. n) (not relocated) to dst[i] (pages[i]'s words each): cached ones
 * copied, the others cut from their models, each model read once for its
 * pages of the call, up to p->threads models at once (one thread each: the
 * model's read, decode and layout build; 0: one a CPU), put into the cache
 * in page order whatever the threads' timing; errors (a file cut or changed
 * since the first pass) name the file and the first such model.
 * _prefetch starts cutting the pages of pages[0 .. n) the cache lacks on a
 * thread of its own (the same parallel cuts) and returns at once: the next
 * _get copies those it asks for from there instead of the file (the rest
 * are dropped; a cut that failed there is made again by _get, which reports
 * it). It overlaps a frame's cuts with what the caller does between its
 * frames (the service asks for the pages a frame requested right after its
 * read-back). One caller thread at a time per cache (the page service's);
 * the reader's random access and the allocator are called from several. */
typedef struct vx_compact_page_cache vx_compact_page_cache;
typedef struct vx_compact_cache_stats {
    uint64_t budget;      /* bytes the cache may hold */
    uint64_t bytes;       /* held now */
    uint64_t peak_bytes;  /* the most it held */
    uint64_t hits;        /* images copied from the cache (since it was made) */
    uint64_t file_pages;  /* images cut from the file */
    uint64_t models;      /* models read from the file for them */
    uint64_t evictions;   /* images the budget pushed out */
    uint64_t prefetched;  /* images _get took from the cuts made ahead (also in file_pages) */
} vx_compact_cache_stats;
vx_result vx_compact_page_cache_create(const vx_compact_paged* p, uint64_t budget, const vx_allocator* alloc,
                                       vx_compact_page_cache** out, vx_error* err);
vx_result vx_compact_page_cache_get(vx_compact_page_cache* pc, const uint32_t* pages, uint32_t n, uint32_t* const* dst,
                                    vx_error* err);
void vx_compact_page_cache_prefetch(vx_compact_page_cache* pc, const uint32_t* pages, uint32_t n);
void vx_compact_page_cache_stats(const vx_compact_page_cache* pc, vx_compact_cache_stats* out);
void vx_compact_page_cache_destroy(vx_compact_page_cache* pc);

/* The page whose cube holds cell (x, y, z) of model m, or UINT32_MAX (a cell
 * of the top: no page there). */
uint32_t vx_compact_page_at(const vx_compact_paged* p, uint32_t m, uint32_t x, uint32_t y, uint32_t z);

/* The CPU traversal of the layout: the centre ray of every pixel of the
 * frame desc gives (the CPU reference's camera, rays and rules, double
 * precision, a brute-force loop over the drawn instances of s), walked
 * through c's geometry DAG alone; the colour is decoded from the attribute
 * index the walk sums. c must be vx_compact_build(s). Only
 * VX_RENDER_ALBEDO (no shading) is supported; out->hits is always filled
 * (instance, cell, t, steps, the ambiguity flag): vx_render_cpu's for the
 * same desc, pixel for pixel, is what tests/render/test_compact.c asserts. */
vx_result vx_compact_render_cpu(const vx_compact_scene* c, const vx_svo_scene* s, const vx_render_desc* desc,
                                const vx_allocator* alloc, vx_render_image* out, vx_error* err);

/* ---- on the GPU (library vx_render, built with Vulkan) ------------------------------
 * The layout uploaded beside a render scene made from the same scene s
 * (vx_render_scene_create), traced by shaders/trace_compact.comp with the
 * render scene's instances, BVH and camera: the float walk of trace.comp
 * over the geometry DAG (its exact t and two-frame walk of deep models
 * included), the colour decoded at the hit; lod and beam are ignored. A
 * coloured model gets a start table (compact_gpu.c: its level-K cubes'
 * nodes and cells before, so that the colour's descent starts at level K),
 * at most an eighth of the layout's bytes beyond 32 KB. Where a model of s
 * names its materials through a material channel and some material of s is
 * not plain diffuse (what the passes' lit frames read per record), each such
 * model's material ids are coded as its colours are (one per cell in the
 * same Morton order, so the attribute index the walk sums finds both; RGBA
 * width, the model's block) after the start tables, and the passes' hits
 * give the material id (render/compact_gpu.c; none without such a channel,
 * and none where s's models have no arrays, a reader's graph). rs and c are
 * borrowed for the object's lifetime (c only during create). */
typedef struct vx_compact_gpu vx_compact_gpu;
vx_result vx_compact_gpu_create(vx_render_scene* rs, const vx_svo_scene* s, const vx_compact_scene* c,
                                vx_compact_gpu** out, vx_error* err);
void vx_compact_gpu_destroy(vx_compact_gpu* cg);
/* A frame, as vx_render_frame. */
vx_result vx_compact_gpu_frame(vx_compact_gpu* cg, const vx_render_desc* desc, vx_render_image* out, vx_error* err);
/* Benchmarks: repeat timed dispatches in one submission, *seconds the median. */
vx_result vx_compact_gpu_time(vx_compact_gpu* cg, const vx_render_desc* desc, uint32_t repeat, double* seconds,
                              vx_error* err);
/* Bytes of the GPU buffers of the layout (geometry, attributes and start tables, material ids, models, palette). */
uint64_t vx_compact_gpu_bytes(const vx_compact_gpu* cg);
/* Internal (benchmarks): the bytes of those that are start tables (render/compact_gpu.c). */
uint64_t vx__compact_gpu_table_bytes(const vx_compact_gpu* cg);
/* Internal: the level-3 records' bytes on the GPU (after the geometry words; 0: none) */
uint64_t vx__compact_gpu_record_bytes(const vx_compact_gpu* cg);
/* Internal (benchmarks, tests): the fewest pushes from the root a primary
 * ray's start below the root must skip (trace_compact.comp PATH_START;
 * tiles whose start would skip fewer walk from the root); 0 the default (2). */
void vx__compact_gpu_start_min(vx_compact_gpu* cg, uint32_t pushes);
/* Internal (benchmarks, tests): the start tables' entries whose cube's cells all hold one value. */
uint64_t vx__compact_gpu_uniform_entries(const vx_compact_gpu* cg);
/* The attribute words (with the start tables) are split over up to this many
 * storage buffers where they exceed one buffer's range (the render scene's,
 * vx_render_scene_desc.max_buffer_range or the device's maxStorageBufferRange);
 * the geometry must fit one. Internal: the parts in use (1: one buffer; 0:
 * paged). A layout in parts is traced by trace_compact.comp only (the passes'
 * kernels bind one attribute buffer and refuse it). */
#define VX_COMPACT_ATTR_PARTS 8
uint32_t vx__compact_gpu_attr_parts(const vx_compact_gpu* cg);
/* Internal (render_scene.c, the sun's depth map's node list): the whole
 * layout's geometry read back into *out (geom, slot and brick counts, the
 * dictionary flag, each model's root and depth; no attributes), freed with
 * vx_compact_free; VX_ERR_UNSUPPORTED for a paged layout. */
vx_result vx__compact_gpu_geometry(vx_compact_gpu* cg, vx_compact_scene* out, vx_error* err);

/* The paged layout on the GPU: the top of *p and a pool of pool_bytes for
 * its pages (one buffer; at least the largest page). It takes *p (zeroed).
 * No page is resident at first. Each frame (vx_compact_gpu_frame) first
 * loads the pages the previous frame requested, as many as the pool holds
 * (evicting pages no ray entered in the previous frame, the least recently
 * entered first; never one the previous frame entered), then traces: a ray
 * that enters a page not resident hits its cube (coarse: the page's mean
 * colour, VX_RENDER_HIT_COARSE in the hit) and requests it; then it reads
 * the requests back. A still camera thus converges in a few frames to the
 * image of the whole layout when the pages it sees fit in the pool. */
vx_result vx_compact_gpu_create_paged(vx_render_scene* rs, const vx_svo_scene* s, vx_compact_paged* p,
                                      uint64_t pool_bytes, vx_compact_gpu** out, vx_error* err);
/* The same, for a layout of the file source (vx_compact_page_build_reader:
 * no images in p, its reader borrowed for the object's lifetime): the
 * images are cut from the file as frames need them, through a host cache of
 * host_budget bytes (vx_compact_page_cache; 0: none). */
vx_result vx_compact_gpu_create_paged_ex(vx_render_scene* rs, const vx_svo_scene* s, vx_compact_paged* p,
                                         uint64_t pool_bytes, uint64_t host_budget, vx_compact_gpu** out, vx_error* err);
typedef vx_render_page_stats vx_compact_page_stats; /* render/render.h */
/* Zeroes for an unpaged object. */
void vx_compact_gpu_page_stats(const vx_compact_gpu* cg, vx_compact_page_stats* out);
/* Where page k is resident: its pool slot P (its blocks from P + 2), or -1. */
int64_t vx_compact_gpu_page_slot(const vx_compact_gpu* cg, uint32_t page);
/* Evicts page k now (tests: a page loaded again lands elsewhere). */
vx_result vx_compact_gpu_page_evict(vx_compact_gpu* cg, uint32_t page, vx_error* err);
/* The paged layout the object holds (NULL unpaged). */
const vx_compact_paged* vx_compact_gpu_paged(const vx_compact_gpu* cg);

#ifdef __cplusplus
}
#endif
#endif
