/* tools/svo_view/app.h - svo_view's state and the actions its keys, script
 * commands and panels share (scene.c, probes.c, camera.c and frame.c
 * implement them; panels.c draws the panels with them). The viewer's rooms:
 * options.c (the command line), scene.c (actions on the scene), probes.c,
 * camera.c, frame.c (a frame: render, overlay, present), input.c (keys and
 * mouse), script.c (--script), main.c (set-up, the loop, teardown). */
#ifndef VX_SVO_VIEW_APP_H
#define VX_SVO_VIEW_APP_H

#include <stdbool.h>
#include <stdint.h>

#include "cones/cones.h"
#include "photons/photons.h"
#include "probes/probes.h"
#include "render/pipeline.h"
#include "render/render.h"
#include "tools/common/conv.h"
#include "tools/svo_view/batch.h"
#include "tools/svo_view/editor.h"
#include "tools/svo_view/options.h"
#include "tools/svo_view/present.h"
#include "tools/svo_view/settings.h"
#include "tools/svo_view/voxels.h"

#define NO_SEL UINT32_MAX
#define SV_HISTORY 120     /* frames the statistics panel keeps */
#define SV_FPS_DEFAULT 24.0 /* an animation whose file has no frame rate */

typedef struct app {
    options o;
    vx_budget budget; /* --max-memory: scenes the viewer loads come from it */
    vp* p;
    vx_gpu* gpu;
    vx_render_scene* rs;
    uint32_t rs_models; /* the model count rs was made with */
    vx_svo_scene scene;
    ved ed;
    /* camera: eye + yaw/pitch (z up); default: svo_render's framing */
    bool cam_default;
    double eye[3], yaw, pitch, speed;
    bool orbit;
    double orbit_center[3], orbit_dist;
    vx_render_mode mode;
    bool gi; /* a probe mode (gi, lightfield): replaces `mode` while probes are loaded */
    vx_probe_render_mode pmode;
    bool overlay;
    /* light field probes (mode gi); nothing of them is touched while none are loaded */
    vx_probe_set probes;
    vx_probe_gpu* probes_gpu; /* their maps on the GPU for rs (made at the first probe frame) */
    /* the colour mode's pass pipeline over rs, its gi method (made at the first frame that needs it) */
    vx_frame_renderer* fr;
    vx_pass_list passes;
    vx_probe_gi* pgi;
    vx_cone_gi* cgi; /* gi=cones: its volume, built at the first frame after a change */
    vx_photon_gi* phgi; /* gi=photons: made at the first frame after a change (its photons every frame) */
    vx_gi_method gm;
    sv_gi_settings gis;     /* the gi methods' settings (render panel, script `gi OPTION VALUE`: svo_render's options) */
    vx_pass_list passes_run; /* the list a frame runs when it differs from `passes` (cone shadows: no direct pass) */
    vx_pass_timing timings[VX_PASS_KIND_COUNT + 1];
    uint32_t timing_count;
    double passes_ms;
    bool have_probes;
    char probes_path[1024];
    /* the probe panel: grid display, the probe whose maps are shown, and a
     * bake run in steps between frames (the UI stays live): vx_probe_place,
     * then vx_probe_bake_more_gpu over as many probes as fit about 40 ms */
    bool probe_grid;
    uint32_t probe_sel;
    int bake_res_i, bake_spp, bake_grid; /* the panel's settings: res 16 << i, spp, probes per axis (0: spacing) */
    struct sv_bake {
        bool active;
        vx_probe_bake_desc desc;
        vx_probe_set ps; /* placed, baked up to ps.count */
        uint32_t step;   /* probes the next step bakes */
        double t0, ms;   /* start (wall), time spent baking */
    } bake;
    uint32_t validation_errors;
    uint32_t sel;
    /* pending editor operation: 'g' grab, 'r' rotate, 'm' mirror, 'l' layer */
    char op;
    int op_axis;
    int32_t grab_moved;
    double grab_px;
    bool pick_pending;
    int pick_op; /* -1: a click selects; else the vvx_op a click in voxel mode applies */
    double pick_x, pick_y;
    char msg[256];
    double msg_until;
    bool msg_error;
    double frame_ms[64];
    /* statistics panel: the per-pass GPU times of the last SV_HISTORY frames */
    float hist[SV_HISTORY][VX_PASS_KIND_COUNT + 1];
    const char* hist_names[VX_PASS_KIND_COUNT + 1];
    uint32_t hist_layers, hist_n;
    double exposure; /* the tonemap pass's stops (render panel, script `exposure`) */
    /* animation: the frame shown, playback (play/pause/step/scrub/fps) */
    uint32_t anim_frame;
    bool playing;
    double fps, play_clock;
    double switch_ms; /* the last frame switch (vx_render_scene_set_frame) */
    /* voxel editing: a click adds (Shift: removes, Alt: paints) with the brush */
    bool voxel_mode;
    vvx_brush brush;
    double pick_rgb[3]; /* the panel's colour picker, taken by its button */
    /* .vox export (Ctrl+E, the Export panel): more than 255 colours mapped to
     * a 255-entry palette (the panel's checkbox; a script's `export FILE quantize`) */
    bool export_quantize;
    /* panels (NULL without ImGui or when off) */
    struct ui* ui;
    bool panels;
    double ui_time; /* glfwGetTime() of the last panel frame */
    /* the panels drawn on the GPU over the shown image (ui.h ui_gpu_init made: frames in flight into a swapchain
     * of storage and colour-attachment images); panels_gpu_now: this frame's are (the CPU draws none) */
    bool panels_gpu, panels_gpu_now;
    uint32_t sel_light;
    uint32_t light_step_for; /* the light whose panel edit made the undo step of ed.serial light_step */
    uint64_t light_step;
    uint32_t light_serial, gi_light_serial; /* lights changed (edit, undo, open); what the gi method was made with */
    char scene_file[1024]; /* the file the scene came from (a map sky's path is relative to it) */
    uint64_t sky_step;     /* the undo step (ed.serial) of the last merged sky edit in the panel */
    char sky_text[VX_SKY_SPEC_MAX]; /* the properties panel's sky field (sv_sky_text) ... */
    char sky_map_text[VX_SKY_PATH_MAX + 1]; /* ... and its map file field, from the current folder */
    uint32_t sky_text_for;                  /* 1 + the light_serial these show (made again when it moves on) */
    char sky_file[1280];   /* the environment map sky_rgb was read from ("" none) */
    float* sky_rgb;
    vx_sky_texels sky_map;
    uint32_t mat_sel;                /* the material the properties panel edits (palette index or material id) */
    uint32_t mat_step_for;           /* as light_step_for, for a material's panel edits */
    uint64_t mat_step;
    char name_buf[64]; /* the properties panel's name field, for instance name_for */
    uint32_t name_for;
    int click_state; /* a scripted click: 2 press, 1 release */
    double click_x, click_y;
    int ui_finding;     /* `ui click LABEL`: frames left for the panels to draw the widget */
    bool ui_ctrl;       /* ... with Ctrl held (ctrl-click) */
    int ui_key_up;      /* `ui key K`: the key to release next frame */
    char ui_label[128];
    const char* grab; /* save the displayed frame (panels included) */
    char grab_buf[1024];
    uint32_t frame_n;
    uint64_t frames_recorded; /* frames given to vx_display_frame_submit (numbers the presents of batches) */
    sv_batch batch;           /* frames a submission: --batch K (max = cur = K) or auto (batch.h; max 4) */
    double trace_ms, rays_per_s, update_ms;
    double panels_ms; /* drawing the panels into the frame or overlay (CPU), the last frame */
    /* presentation: vx_display set: the colour passes' frames go to the
     * swapchain on the GPU (vp_present_display); else, and for other modes,
     * picks and screenshots, the host readback path (vp_present) */
    vx_display* disp;
    bool frame_on_gpu; /* the last frame took the GPU path */
    bool frame_in_flight; /* ... and was not waited for (frames in flight, render/display.h) */
    /* the GPU path's overlay is kept between frames while nothing it shows changed */
    bool ui_dirty, ov_valid, ov_cam_default;
    double ov_time, ov_cam[5];
    uint32_t ov_w, ov_h;
    char present_note[1024];
    /* GPU scene uploads: render scenes made (sv_rebuild), and the node words
     * and records of the scenes before the current one (its own: vx_render_scene_get_stats) */
    uint32_t scenes_made;
    uint64_t words_before, records_before;
    bool quit;
    int status;
    /* script */
    char** lines;
    uint32_t line_count, line_pos, wait;
    /* frame */
    uint8_t* px8;
    size_t px8_cap;
    vx_render_image img;
    const char* shot;
    char shot_buf[1024];
    uint32_t shot_counter;
    double mouse_x, mouse_y;
    bool rmb, lmb;
} app;

/* ---- between the viewer's own files (scene.c, probes.c) ------------------------------- */

/* Reads a scene file with the command line's converter options. */
vx_result sv_load_scene(const options* o, const char* path, vx_svo_scene* out, vx_error* err);
/* Reads a complete probe set; the current one stays on failure. */
vx_result sv_load_probes(app* a, const char* path, vx_error* err);
/* A step of a running bake, between frames (nothing when none runs). */
void sv_probe_bake_step(app* a);
/* The gi methods (probes, cones, photons) destroyed: made again at the next frame that needs one. */
void sv_drop_gi(app* a);
/* The loaded probe set (where there is one) freed, with what was made for it or borrows it: the probes' and
 * the photons' gi methods (the cones' stays) and the probe modes' GPU maps. */
void sv_drop_probes(app* a);
/* The pipeline's objects bound to rs (and its gi method bound to the probes) destroyed. */
void sv_drop_passes(app* a);
/* After an edit of instances only: the render scene's instance tables again (scene.c). */
void sv_update_instances(app* a);
/* The selection moved n cells along axis (an undo step of its own). */
void sv_edit_move(app* a, int axis, int32_t n);
/* The animation's clock advanced by dt seconds while playing. */
void sv_play_step(app* a, double dt);

/* ---- the actions ------------------------------------------------------------------------ */

void sv_message(app* a, bool error, const char* fmt, ...) __attribute__((format(printf, 3, 4)));
const char* sv_mode_name(const app* a);
/* Recreates the render scene from a->scene (after a model edit), at the frame shown. */
void sv_rebuild(app* a);
/* Node words and colour records uploaded since the viewer started (every render scene made). */
void sv_uploads(const app* a, uint64_t* words, uint64_t* records);
/* An edit: sv_edit_begin snapshots for undo (false: nothing selected when
 * needs_sel, or out of memory, with a message); sv_edit_end updates the
 * render scene (instances only, unless models were added). */
bool sv_edit_begin(app* a, bool needs_sel);
void sv_edit_end(app* a, const char* what);
/* Open, add, save, export: false with a message naming the file once (a
 * script's failed save or export ends it with status 1; a file that does
 * not open or add leaves the scene as it was and the script goes on). */
bool sv_open(app* a, const char* path);
bool sv_add(app* a, const char* path);
bool sv_save(app* a, const char* path);
/* By the path's extension: .glb and .vdb through the library's exports
 * (convert/export.h: what svo_info --to-glb / --to-vdb write from the saved
 * scene), anything else .vox. quantize (.vox): more than 255 colours are
 * mapped to a 255-entry palette (vx_conv_vox_export_desc), the message a
 * warning giving the count and the colour error; without it such a scene is
 * refused, the message naming the script's and the panel's option. */
bool sv_export(app* a, const char* path, bool quantize);
/* Ctrl+E and the Export panel's button: FILE.edited.vox beside the file
 * opened, quantized as the panel's checkbox says; sv_export_as the same
 * with the extension ext ("glb", "vdb": the panel's other buttons). */
bool sv_export_default(app* a);
bool sv_export_as(app* a, const char* ext);
void sv_probes(app* a, const char* path);
/* Starts baking probes over the scene as shown (res, spp, grid probes per
 * axis, 0 0 0: the default spacing) on the GPU, in steps between frames; the
 * set replaces the loaded probes when done. An edit, open or rebuild cancels it. */
void sv_probe_bake(app* a, uint32_t res, uint32_t spp, const uint32_t grid[3]);
void sv_probe_bake_cancel(app* a, const char* why);
bool sv_probe_save(app* a, const char* path);
/* The probe set the panel shows: the bake in progress (its placed grid), else the loaded one; NULL: none. */
const vx_probe_set* sv_probe_shown(const app* a);
void sv_frame_camera(app* a);
void sv_select(app* a, uint32_t instance); /* NO_SEL: none */
void sv_move(app* a, const int32_t d[3]);
void sv_rotate(app* a, int axis, int turns);
void sv_mirror(app* a, int axis);
void sv_duplicate(app* a);
void sv_delete(app* a);
void sv_hide(app* a, bool hide); /* hide the selection, or show every instance */
void sv_hide_instance(app* a, uint32_t i, bool hide);
/* The selection's name, layer (UINT32_MAX: none) and model (false with a
 * message: no such layer or model, nothing selected). */
void sv_rename(app* a, const char* name);
bool sv_set_layer(app* a, uint32_t layer);
bool sv_set_model(app* a, uint32_t model);
bool sv_layer(app* a, uint32_t l, int hide /* -1 toggles; false with a message: no layer l */);
void sv_undo(app* a, bool redo);
/* Light l becomes *t (false with a message when vx_light_validate refuses
 * it; the light is then unchanged). An undo step: its own, or with merge
 * the step of the previous edit when that was also a merged edit of light l
 * and nothing was edited or undone since (a drag in the panel is one step). */
bool sv_set_light(app* a, uint32_t l, const vx_light* t, bool merge);
/* The scene's sky becomes *k (stored form: a map's relative path from the
 * scene file's folder); false with a message when vx_sky_validate refuses
 * it. An undo step, merged as sv_set_light's; the gi methods are made again
 * (they take the sky), the passes use it from the next frame. */
bool sv_set_sky(app* a, const vx_sky* k, bool merge);
/* The sky from svo_render --sky's text (svo.h vx_sky_parse; "default"
 * resets it), a map's path given from the current folder and stored from
 * the scene file's, as vox2svo --sky stores it (the script's `sky SPEC`,
 * the panel's text field): sv_set_sky, its own step. False with a message. */
bool sv_set_sky_text(app* a, const char* spec);
/* The sky as that text, a map's path from the current folder (what
 * sv_set_sky_text takes back); "" with a message when it has none. */
void sv_sky_text(app* a, char* out, size_t n);
/* Material id's field (settings.h sv_material_field: type, rough, metal,
 * spec, trans, ior, emit, flux) set from value text: an undo step, merged
 * as sv_set_light's; the gi methods are made again. False with a message. */
bool sv_set_material(app* a, uint32_t id, const char* field, const char* value, bool merge);
/* A gi setting (settings.h sv_gi_option, svo_render's option names); the gi
 * method is made again at the next frame. False with a message. */
bool sv_set_gi_option(app* a, const char* name, const char* value);
bool sv_set_passes(app* a, const char* list);
void sv_set_probe_mode(app* a, vx_probe_render_mode m);
/* Animation: shows frame f (no model upload), play/pause, frames per second. */
void sv_set_frame(app* a, uint32_t f);
void sv_play(app* a, bool play);
void sv_set_fps(app* a, double fps);
/* The brush colour: a palette entry (false with a message when the file has
 * it empty), or an RGBA8 colour (palette models: the entry of that colour,
 * else an empty one, else one no cell used when the scene was opened:
 * ved_palette_take; false with a message when none is left). */
bool sv_brush_palette(app* a, uint32_t index);
bool sv_brush_rgba(app* a, uint32_t rgba);
/* Voxel edit with the brush at model cell c of the selected instance's model. */
bool sv_voxels(app* a, vvx_op op, const int64_t c[3]);

#endif
