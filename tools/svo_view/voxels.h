/* tools/svo_view/voxels.h - voxel editing inside a model, for svo_view.
 *
 * A brush (one cell, a box or a ball of cells around a centre cell) adds,
 * removes or paints cells of one model through the model's vx_svo_editor
 * (svo/edit.h, kept per model in the ved): only the paths to the written
 * cells are made again, appended after the model's words and re-minimized
 * (collapse, shared blocks), so the GPU scene takes only the appended words
 * (vx_render_scene_update_model with ved.last). The saved file holds the
 * compacted model (vvx_file_scene), exactly what converting the edited
 * cells gives. A brush reaching below cell 0 shifts every key: that edit
 * decodes the model's cells, applies the brush and builds the octree again
 * (the builder, as vox2svo). Every instance of the model (in every frame)
 * sees the edit, as in
 * MagicaVoxel, where a model is edited wherever it is placed.
 *
 * Cells: model cell coordinates; a cell added outside the model's box grows
 * it (size), below 0 the model's cells shift up by the overhang and every
 * instance of the model (every frame) moves back by M * shift, so nothing
 * moves in the world. At most 2^21 cells a side (VX_SVO_MAX_DEPTH).
 *
 * The face brush (MagicaVoxel's and Goxel's extrude) starts at a set cell
 * and one of its faces that is exposed (the cell beyond it is empty): the
 * region is the cells of that plane connected to it by in-plane neighbours
 * whose same face is exposed, within the radius. add extrudes the region
 * one layer (each new cell copies the cell under it, colour included),
 * remove takes the region away (the face pushed in one layer), paint
 * recolours it. An extrusion below cell 0 is refused (grow the model with
 * another brush first).
 *
 * Attributes: an added cell gets the brush colour (a palette index for
 * palette models, RGBA8 for colour models; geometry-only models take no
 * colour) and the other channels (normal, material, density) of the
 * nearest face neighbour that is set, else of the model's first cell;
 * painting changes only the colour channel. Painting a geometry-only model
 * is refused.
 *
 * Undo: the edit is one ved step (ved_begin is called here) that keeps the
 * model's old header (the editor only appends), or for a rebuild parks the
 * old octree (editor.h). */
#ifndef VX_SVO_VIEW_VOXELS_H
#define VX_SVO_VIEW_VOXELS_H

#include "tools/svo_view/editor.h"

typedef enum vvx_op { VVX_ADD = 0, VVX_REMOVE, VVX_PAINT, VVX_OP_COUNT } vvx_op;
typedef enum vvx_shape { VVX_VOXEL = 0, VVX_BOX, VVX_SPHERE, VVX_FACE, VVX_SHAPE_COUNT } vvx_shape;

/* Zero-initialised: one cell, palette index 1, opaque white. */
typedef struct vvx_brush {
    vvx_shape shape;
    uint32_t radius;  /* box: cells with |d|_inf <= radius; sphere: |d|_2 <= radius; face: the
                       * region's cells within |d|_inf <= radius in its plane, 0 == 64 (at most 64) */
    uint8_t face;     /* face: the hit face, 0..5 = -x, +x, -y, +y, -z, +z (model axes) */
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

/* The scene as a file holds it: ved's scene with every model an
 * incremental edit changed compacted (vx_svo_model_compact: the builder's
 * model of its cells; a file holds no superseded words). *out shares the
 * scene's other arrays; free it with vvx_file_scene_free. */
vx_result vvx_file_scene(const ved* e, vx_svo_scene* out, vx_error* err);
void vvx_file_scene_free(const ved* e, vx_svo_scene* out);

#endif
