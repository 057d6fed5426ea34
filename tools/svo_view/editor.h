/* tools/svo_view/editor.h - scene edits for svo_view, with undo and redo.
 *
 * The editor works on a vx_svo_scene in place: instances are moved, rotated,
 * mirrored, duplicated and deleted; layers and instances hidden or shown;
 * models from another file added. Every edit keeps transforms exact: the
 * linear part stays a signed permutation times the original and
 * translations move by whole cells, so the scene still exports to .vox.
 *
 * Rotation and mirroring pivot on the centre p = (lo + hi) / 2 of the
 * instance's grid-space box [lo, hi] (its model box [0,size]^3 mapped by
 * the transform): a point x goes to R (x - p) + p, so the cell with centre
 * w + 1/2 goes to the cell with centre R (w + 1/2 - p) + p. Mirroring is
 * always cell-exact and its own inverse. A quarter turn in the plane of
 * axes a < b is cell-exact when p_a + p_b is whole (the footprint's sides
 * have equal parity: then four turns are the identity); otherwise p_a is
 * lowered by 1/2 first (a turn then also shifts the box by half a cell).
 *
 * Animations (vx_svo_scene frames): record i of every frame animates
 * instance i, so an edit of instance i applies to its record in every frame:
 * a move, turn or mirror is one map applied to the whole track (the pivot is
 * taken in the frame the user looks at, `frame` below, so that frame turns
 * in place and the others keep their motion relative to it); hide and show
 * set every frame's flag (a per-frame visibility key is lost on show);
 * duplicate and delete add or remove record i in every frame; an added file
 * is placed, still, in every frame. Frame 0 is always s->instances.
 *
 * Undo: ved_begin() snapshots the instances (every frame), the layer
 * flags, the lights and the sky before an edit; ved_undo()/ved_redo() swap
 * snapshots. A material edit (ved_begin_materials) also copies the
 * materials (their dictionaries are small, but other steps need none). A voxel edit
 * (voxels.h) also keeps the model's previous header (svo/edit.h: the
 * editor only appends, so restoring the header is the undo), or, for an
 * edit that rebuilt the model, parks its previous octree. Models
 * are only ever appended (ved_add_scene), so snapshots stay valid; undoing an
 * add leaves the new models unreferenced.
 */
#ifndef VX_SVO_VIEW_EDITOR_H
#define VX_SVO_VIEW_EDITOR_H

#include <stdbool.h>
#include <stdint.h>

#include "svo/edit.h"
#include "svo/svo.h"

/* What an incremental edit left in a model's arrays: the words / records
 * undo and redo steps may still reference (an editor made later must not
 * overwrite them: vx_svo_editor_desc.words_in_use; 0: none past the
 * model's), and the header the arrays had before their first such edit
 * (while the model has it again, its words are the untouched original). */
typedef struct ved_arrays {
    uint32_t words_in_use, records_in_use;
    bool edited;
    vx_svo_model_header pristine;
} ved_arrays;

typedef struct ved_snapshot {
    vx_svo_instance* inst;
    uint32_t inst_count;
    vx_svo_instance* frame_inst; /* (frame_count - 1) * inst_count records, NULL for a still scene */
    uint32_t frame_count;
    uint32_t* layer_flags;
    uint32_t layer_count;
    vx_light* lights; /* the scene's lights (few: copied whole at every step) */
    uint32_t light_count;
    vx_sky sky;
    /* a material edit (ved_begin_materials): the scene's materials as they were, dictionaries copied */
    bool has_materials;
    vx_svo_material* materials;
    uint32_t material_count;
    bool has_model;        /* a voxel edit: `model` is models[model_index] as it was */
    uint32_t model_index;
    vx_svo_model model;
    ved_arrays model_arrays;  /* has_model: the parked arrays' state */
    bool has_header;          /* a voxel edit by the editor: `header` is models[model_index]'s as it was */
    vx_svo_model_header header;
} ved_snapshot;

/* Per model: its incremental editor (made at its first voxel edit, NULL
 * when none) and the state of its arrays. */
typedef struct ved_voxels {
    vx_svo_editor* ed;
    const vx_svo_model* models; /* s->models when ed was made (ved_add_scene moves the array) */
    ved_arrays arrays;
} ved_voxels;

/* What the last voxel edit did (voxels.c), for the render scene's update:
 * incremental, the model's words and records from these on are new
 * (vx_render_scene_update_model); else the model was built again. */
typedef struct ved_voxel_step {
    bool incremental;
    uint32_t model, words_from, records_from;
} ved_voxel_step;

/* Undo history bounds (ved.undo_limit / ved.undo_bytes, 0: these): the
 * oldest steps are dropped when there are more steps than the limit, or when
 * the snapshots together hold more bytes than the byte bound (the newest
 * step is always kept). A step holds a copy of every frame's instance
 * records, the layer flags and the lights (about 200 bytes an instance a
 * frame), and a voxel edit that rebuilt its model the old model's arrays;
 * an incremental voxel step holds only a header (its appended words stay in
 * the model's arrays until the scene is saved and reopened). */
#define VED_UNDO_STEPS_DEFAULT 1024u
#define VED_UNDO_BYTES_DEFAULT (256ull << 20)

typedef struct ved {
    vx_svo_scene* s; /* borrowed */
    ved_snapshot *undo, *redo; /* oldest first; cap entries each */
    uint32_t undo_count, redo_count, cap;
    uint32_t undo_limit; /* steps kept (0: VED_UNDO_STEPS_DEFAULT) */
    uint64_t undo_bytes; /* bytes the snapshots may hold (0: VED_UNDO_BYTES_DEFAULT) */
    uint32_t dropped;    /* steps dropped by the bounds since ved_init */
    uint64_t serial;     /* counts ved_begin, ved_undo and ved_redo calls (the step count may stand still at the bound) */
    ved_voxels* vox; /* per model, vox_count of them (voxels.c) */
    uint32_t vox_count;
    ved_voxel_step last;
    bool vox_rebuild; /* tests: every brush edit but the face brush's decodes and builds the model again (the reference) */
    /* palette entries (bit i: entry i, 1..255) no model's cell used when the
     * scene was opened (or models added: ved_palette_scan) and the brush has
     * not taken since: ved_palette_take may give them a new colour */
    uint32_t pal_unused[8];
} ved;

void ved_init(ved* e, vx_svo_scene* s);
void ved_free(ved* e);
/* Entries the scene's models use (every model, every record) leave
 * e->pal_unused (ved_init calls it; call it again after models are added). */
void ved_palette_scan(ved* e);
/* The palette entry a brush of colour rgba paints with (palette scenes): the
 * entry of that colour, else the first empty one, else the first that no
 * cell used when the scene was opened (a .vox's palette has all 255 entries
 * set, most of them unused) and no brush took since, which gets the colour
 * (never one a cell in the undo history may use). 0: the palette is full.
 * The entry returned is the brush's from then on (ved_palette_keep). */
uint32_t ved_palette_take(ved* e, uint32_t rgba);
/* Entry i (1..255) is a brush's: never given another colour. */
void ved_palette_keep(ved* e, uint32_t i);
/* Bytes the snapshot holds (what the history's byte bound counts). */
uint64_t ved_snapshot_bytes(const ved_snapshot* sn);
/* Snapshot before an edit (drops the redo list, then the oldest steps past
 * the bounds above). */
vx_result ved_begin(ved* e, vx_error* err);
/* ved_begin, and the step also holds the materials (before a material edit). */
vx_result ved_begin_materials(ved* e, vx_error* err);
/* false when there is nothing to undo / redo. */
bool ved_undo(ved* e, vx_error* err);
bool ved_redo(ved* e, vx_error* err);

/* Record i of frame f (frame 0: s->instances[i]); f < vx_svo_scene_frames(s). */
vx_svo_instance* ved_record(vx_svo_scene* s, uint32_t f, uint32_t i);
/* Grid-space box of instance i's model box in frame f. */
void ved_instance_box(const vx_svo_scene* s, uint32_t f, uint32_t i, double lo[3], double hi[3]);
/* The pivot of a rotation about / mirror along axis for instance i in frame f (see above). */
void ved_pivot(const vx_svo_scene* s, uint32_t f, uint32_t i, int axis, bool rotate, double p[3]);

/* Every frame's record of instance i moves by d cells. */
void ved_move(vx_svo_scene* s, uint32_t i, const int32_t d[3]);
/* quarter turns counter-clockwise (right-handed) about axis 0/1/2; negative
 * turns clockwise; the pivot is instance i's in frame f, every frame turns */
void ved_rotate(vx_svo_scene* s, uint32_t f, uint32_t i, int axis, int quarter_turns);
void ved_mirror(vx_svo_scene* s, uint32_t f, uint32_t i, int axis);
/* Sets or clears instance i's hidden flag in every frame. */
void ved_hide(vx_svo_scene* s, uint32_t i, bool hide);
/* Instance i's name (cut to 63 bytes), layer (UINT32_MAX: none) or model, in every frame. */
void ved_rename(vx_svo_scene* s, uint32_t i, const char* name);
void ved_set_layer(vx_svo_scene* s, uint32_t i, uint32_t layer);
void ved_set_model(vx_svo_scene* s, uint32_t i, uint32_t model);
/* Appends a copy of instance i (same model, same place, in every frame); *out = its index. */
vx_result ved_duplicate(vx_svo_scene* s, uint32_t i, uint32_t* out, vx_error* err);
void ved_delete(vx_svo_scene* s, uint32_t i);
/* Moves other's models and instances into s (other is emptied and may then
 * be freed), offset by d cells; palette-coloured models whose palette
 * differs from s's are rebuilt with RGBA8 attributes. *first = index of the
 * first added instance. Both scenes must use the default allocator. */
vx_result ved_add_scene(vx_svo_scene* s, vx_svo_scene* other, const int32_t d[3], uint32_t* first, vx_error* err);

/* Material `id`'s dictionary (docs/FORMAT.md 2.3, 4.1: MagicaVoxel keys such
 * as "_type" "_rough" "_ri" "_emit") gets key = value (value NULL: the key
 * removed); the first material of that id is edited, a new one (an empty
 * dictionary) appended when the scene has none. The other pairs keep their
 * order; a new key goes last. Keys and values are non-empty (values may be
 * empty only by removal) and at most 63 bytes. VX_ERR_INVALID_ARG, VX_ERR_NOMEM;
 * the scene is unchanged on failure. */
vx_result ved_material_set(vx_svo_scene* s, uint32_t id, const char* key, const char* value, vx_error* err);

/* The 3x3 rotation of a quarter turn about an axis, row-major integers. */
void ved_quarter_turn(int axis, int quarter_turns, int32_t r[9]);

#endif
