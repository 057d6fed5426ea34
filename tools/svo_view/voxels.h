/* tools/svo_view/voxels.h - voxel editing inside a model, for svo_view.
 *
 * A brush (one cell, a box or a ball of cells around a centre cell) adds,
 * removes or paints cells of one model. The edit decodes the model's octree
 * to its cell list (Morton order), applies the brush there and builds the
 * octree again with the library's builder (collapse and DAG sharing as
 * vox2svo does), so the stored model is exactly what converting the edited
 * cells gives. The whole model is rebuilt, not only the touched subtrees:
 * the builder has no incremental entry point, and the rebuild of a model of
 * a few hundred thousand cells takes milliseconds (svo_view -v prints it).
 * Every instance of the model (in every frame) sees the edit, as in
 * MagicaVoxel, where a model is edited wherever it is placed.
 *
 * Cells: model cell coordinates; a cell added outside the model's box grows
 * it (size), below 0 the model's cells shift up by the overhang and every
 * instance of the model (every frame) moves back by M * shift, so nothing
 * moves in the world. At most 2^21 cells a side (VX_SVO_MAX_DEPTH).
 *
 * Attributes: an added cell gets the brush colour (a palette index for
 * palette models, RGBA8 for colour models; geometry-only models take no
 * colour) and the other channels (normal, material, density) of the
 * nearest face neighbour that is set, else of the model's first cell;
 * painting changes only the colour channel. Painting a geometry-only model
 * is refused.
 *
 * Undo: the edit is one ved step (ved_begin is called here), the old
 * octree parked in the snapshot (editor.h). */
#ifndef VX_SVO_VIEW_VOXELS_H
#define VX_SVO_VIEW_VOXELS_H

#include "tools/svo_view/editor.h"

typedef enum vvx_op { VVX_ADD = 0, VVX_REMOVE, VVX_PAINT, VVX_OP_COUNT } vvx_op;
typedef enum vvx_shape { VVX_VOXEL = 0, VVX_BOX, VVX_SPHERE, VVX_SHAPE_COUNT } vvx_shape;

/* Zero-initialised: one cell, palette index 1, opaque white. */
typedef struct vvx_brush {
    vvx_shape shape;
    uint32_t radius;  /* box: cells with |d|_inf <= radius; sphere: |d|_2 <= radius (at most 64) */
    uint8_t palette;  /* palette models; 0 == 1 */
    uint32_t rgba;    /* colour models; 0 == opaque white */
} vvx_brush;

#define VVX_MAX_RADIUS 64u

const char* vvx_op_name(vvx_op op);
const char* vvx_shape_name(vvx_shape s);
bool vvx_shape_parse(const char* s, vvx_shape* out);

/* Applies op with brush b centred on model cell c of scene model `model`.
 * *changed (may be NULL) = cells added, removed or recoloured; nothing is
 * recorded for undo when none changed. */
vx_result vvx_apply(ved* e, uint32_t model, vvx_op op, const vvx_brush* b, const int64_t c[3], uint64_t* changed,
                    vx_error* err);

#endif
