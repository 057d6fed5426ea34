/* svo/edit.h - incremental edits of one model's octree (an editor's brush).
 *
 * vx_svo_build_model makes a model from all its cells; an editor that changes
 * a few hundred cells of a model of millions should not. A vx_svo_editor
 * changes cells of a built model in place, touching only the subtrees that
 * hold them:
 *
 *  - Copy-on-write, append-only. No existing word or attribute record is
 *    ever modified: the nodes on the paths from the root to the written
 *    cells are made again and appended after the model's words (children
 *    precede parents, so every pointer still goes backwards), with their
 *    attribute records appended to the record arrays, and a new root
 *    descriptor goes last. Subtrees the writes do not touch, shared ones
 *    (the DAG) included, are referenced where they are. So the model before
 *    an edit is a prefix of the model after it: undo is restoring the old
 *    header (root, root_attr, node_count, attr_count, size, depth,
 *    voxel_count; vx_svo_model_header), and a renderer keeps the old words
 *    and uploads only the new ones (render/render.h,
 *    vx_render_scene_update_model).
 *  - Re-minimized. A made-again node whose eight children are full leaves
 *    with one attribute tuple collapses into a leaf (upwards, as the
 *    builder's step 1), coarse attribute records follow the builder's rule
 *    (svo.h), and a node whose block equals one already stored (same
 *    masks, same child blocks, same records) points at that block instead
 *    of storing a copy (the builder's step 2), found through an index of
 *    the model's blocks made when the editor is created.
 *  - What it does not do: the word layout differs from the builder's (the
 *    superseded path copies stay as unreferenced words). The cells, their
 *    attributes and the coarse records equal a from-scratch build of the
 *    same cells (tests/svo/test_svo_edit.c); vx_svo_model_compact gives
 *    the builder's exact words. A file may not hold unreferenced words:
 *    save the compacted model (its file has the same bytes as converting
 *    the cells).
 *
 * Growth: a write past the model's size grows it (depth too: the old root
 * becomes octant 0 of a new one). Cells below 0 do not exist: moving a
 * model's origin changes every key, which is a rebuild (the caller's).
 *
 * Usage:
 *   vx_svo_editor* e; vx_svo_editor_create(&(vx_svo_editor_desc){.alloc = a}, &model, &e, &err);
 *   vx_svo_cell c; bool set = vx_svo_editor_get(e, x, y, z, &c);
 *   vx_svo_cell_write w[] = {{.x = 1, .y = 2, .z = 3, .set = true, .value = c}};
 *   vx_svo_edit_stats st; vx_svo_editor_apply(e, w, 1, &st, &err);   // model changed in place
 *   ... upload words [st.words_from, model.node_count) ...
 *   vx_svo_editor_destroy(e);   // the model stays valid and owned by its owner
 */
#ifndef VX_SVO_EDIT_H
#define VX_SVO_EDIT_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "svo/svo.h"

#ifdef __cplusplus
extern "C" {
#endif

/* One cell's attribute values; channels the model lacks are ignored (and
 * read back as 0). */
typedef struct vx_svo_cell {
    uint8_t palette; /* VX_ATTR_PALETTE */
    uint32_t rgba;   /* VX_ATTR_RGBA8 */
    uint32_t normal; /* VX_ATTR_NORMAL */
    uint16_t material;
    float density;
} vx_svo_cell;

/* Sets (set true, with value) or clears cell (x, y, z). */
typedef struct vx_svo_cell_write {
    uint32_t x, y, z;
    bool set;
    vx_svo_cell value;
} vx_svo_cell_write;

typedef struct vx_svo_editor_desc {
    const vx_allocator* alloc; /* the model's arrays come from it (they are grown with vx_grow); the
                                  editor keeps the pointer: it must outlive the editor */
    bool no_dag;               /* never point at an existing equal block (no index is made) */
    /* Words and records of the model's arrays that must not be overwritten
     * although past node_count / attr_count: a caller that undid edits by
     * restoring an older header and may restore a newer one again gives the
     * largest counts it may restore (0: node_count, attr_count). */
    uint32_t words_in_use, records_in_use;
    vx_svo_testing testing; /* test hooks: far_limit only (svo/core.h); leave zeroed */
} vx_svo_editor_desc;

typedef struct vx_svo_editor vx_svo_editor;

/* The fields of a model that an edit changes (its arrays aside). */
typedef struct vx_svo_model_header {
    uint32_t size[3], depth, root, root_attr, node_count, attr_count;
    uint64_t voxel_count;
} vx_svo_model_header;
vx_svo_model_header vx_svo_model_header_get(const vx_svo_model* m);
void vx_svo_model_header_set(vx_svo_model* m, const vx_svo_model_header* h);

/* What one vx_svo_editor_apply did. */
typedef struct vx_svo_edit_stats {
    uint32_t words_from, records_from; /* new words are [words_from, node_count), records likewise */
    uint32_t words_added, records_added;
    uint64_t cells_added, cells_removed, cells_changed; /* changed: set before and after, other values */
    uint32_t blocks_made, blocks_shared;                /* blocks appended / found in the index */
} vx_svo_edit_stats;

/* m (validated here) is edited in place for the editor's lifetime; the
 * caller keeps owning it and must not change its header or arrays meanwhile,
 * except by restoring a header an earlier apply left (undo, redo). */
vx_result vx_svo_editor_create(const vx_svo_editor_desc* desc, vx_svo_model* m, vx_svo_editor** out, vx_error* err);
void vx_svo_editor_destroy(vx_svo_editor* e);
/* Whether cell (x, y, z) is set (outside the model: false), and its values. */
bool vx_svo_editor_get(const vx_svo_editor* e, uint32_t x, uint32_t y, uint32_t z, vx_svo_cell* out);
/* Reads the box of cells [lo, hi] (inclusive on each axis) at once, for a
 * brush that reads its cells and their neighbours (one walk of the subtrees
 * the box meets instead of a descent per cell): set[i] (and out[i] when out
 * is not NULL) for the cell lo + (x, y, z) at i = (z * dy + y) * dx + x,
 * d = hi - lo + 1; cells outside the model read as not set. */
vx_result vx_svo_editor_get_box(const vx_svo_editor* e, const uint32_t lo[3], const uint32_t hi[3], bool* set,
                                vx_svo_cell* out, vx_error* err);
/* Applies n writes (in any order; for a cell written twice the last wins).
 * A coordinate of 2^21 or more is VX_ERR_LIMIT; on any failure the model is
 * as before. stats may be NULL. */
vx_result vx_svo_editor_apply(vx_svo_editor* e, const vx_svo_cell_write* w, size_t n, vx_svo_edit_stats* stats,
                              vx_error* err);

/* vx_svo_validate_model for an edited model: words no descriptor reaches
 * (the superseded copies) are allowed, which vx_svo_validate_model and the
 * file writer refuse (a file holds none: save vx_svo_model_compact's
 * model). Everything reachable is checked as strictly. */
vx_result vx_svo_validate_edited_model(const vx_svo_model* m, vx_error* err);

/* The builder's model of m's cells (what vx_svo_build_model(desc, ...) gives
 * for them: the words without the superseded copies), into *out (free with
 * vx_svo_model_free(desc->alloc, out)). desc: NULL or zero-initialised for
 * the defaults; its alloc serves every block (the cells' scratch and *out),
 * its other fields (no_collapse, no_dag, max_depth, progress,
 * testing.far_limit) reach the build as vx_svo_build_model reads them. */
vx_result vx_svo_model_compact(const vx_svo_build_desc* desc, const vx_svo_model* m, vx_svo_model* out,
                               vx_error* err);

#ifdef __cplusplus
}
#endif
#endif /* VX_SVO_EDIT_H */
