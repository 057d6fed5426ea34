/* tools/svo_view/scene.c - the actions on the scene shown (app.h): loading,
 * messages, the render scene made again after edits, instance edits,
 * animation, voxel edits with the brush, lights, materials and gi settings. */
#include <GLFW/glfw3.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "convert/convert.h"
#include "convert/export.h"
#include "tools/common/tool.h"
#include "tools/svo_view/app.h"
#include "tools/svo_view/camera.h"

/* ---- loading ---------------------------------------------------------------------- */

vx_result sv_load_scene(const options* o, const char* path, vx_svo_scene* out, vx_error* err) {
    vx_logger log = vx_tool_logger(o->verbose);
    return vx_tool_conv_load(path, &o->conv, true, &log, (vx_progress){0}, out, NULL, err);
}

/* ---- application state ---------------------------------------------------------------- */



void sv_message(app* a, bool error, const char* fmt, ...) __attribute__((format(printf, 3, 4)));
void sv_message(app* a, bool error, const char* fmt, ...) {
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(a->msg, sizeof a->msg, fmt, ap);
    va_end(ap);
    a->msg_error = error;
    a->msg_until = glfwGetTime() + 6;
    fprintf(error ? stderr : stdout, "%s: %s\n", vx_tool_name, a->msg);
}

/* An error about a file: "path: message", the path once (the library's file
 * functions name it first themselves: vx_tool_names_file). */
static void file_error(app* a, const char* path, const char* msg) {
    if (vx_tool_names_file(path, msg)) sv_message(a, true, "%s", msg);
    else sv_message(a, true, "%s: %s", path, msg);
}

const char* sv_mode_name(const app* a) {
    return a->gi ? vx_probe_render_mode_name(a->pmode) : vx_render_mode_name(a->mode);
}

/* The gi methods made with the probe set: the probes' is made for it, the photons' borrows its sun and sky. */
static void drop_probe_gi(app* a) {
    vx_probe_gi_destroy(a->pgi);
    a->pgi = NULL;
    vx_photon_gi_destroy(a->phgi);
    a->phgi = NULL;
}

void sv_drop_gi(app* a) {
    drop_probe_gi(a);
    vx_cone_gi_destroy(a->cgi);
    a->cgi = NULL;
}

void sv_drop_probes(app* a) {
    drop_probe_gi(a); /* the cones' volume does not depend on the probes: it stays */
    vx_probe_gpu_destroy(a->probes_gpu);
    a->probes_gpu = NULL;
    if (a->have_probes) vx_probe_set_free(&a->probes);
    a->have_probes = false;
}

/* The pipeline's objects bound to rs (and its gi method bound to the probes). */
void sv_drop_passes(app* a) {
    sv_drop_gi(a);
    vx_frame_renderer_destroy(a->fr);
    a->fr = NULL;
}

void sv_rebuild(app* a) {
    double t0 = vx_time_now();
    sv_probe_bake_cancel(a, "the scene changed");
    a->name_for = NO_SEL; /* the panel's name field shows the name again */
    vx_probe_gpu_destroy(a->probes_gpu); /* bound to the old render scene */
    a->probes_gpu = NULL;
    sv_drop_passes(a);
    vx_render_scene_stats st;
    vx_render_scene_get_stats(a->rs, &st);
    a->words_before += st.node_words_uploaded, a->records_before += st.records_uploaded;
    vx_render_scene_destroy(a->rs);
    a->rs = NULL;
    a->scenes_made++;
    vx_error err = {0};
    uint32_t nf = vx_svo_scene_frames(&a->scene);
    if (a->anim_frame >= nf) a->anim_frame = nf - 1; /* an undo may have made the scene still */
    if (vx_render_scene_create(a->gpu, &a->scene, &a->rs, &err)) sv_message(a, true, "cannot draw the scene: %s", err.msg);
    else if (a->anim_frame && vx_render_scene_set_frame(a->rs, &a->scene, a->anim_frame, &err))
        sv_message(a, true, "frame %u: %s", a->anim_frame, err.msg);
    else if (vx_frame_renderer_create(a->rs, &a->scene, &a->fr, &err)) sv_message(a, true, "pass pipeline: %s", err.msg);
    a->rs_models = a->scene.model_count;
    a->update_ms = (vx_time_now() - t0) * 1e3;
}

void sv_uploads(const app* a, uint64_t* words, uint64_t* records) {
    vx_render_scene_stats st;
    vx_render_scene_get_stats(a->rs, &st);
    *words = a->words_before + st.node_words_uploaded;
    *records = a->records_before + st.records_uploaded;
}

/* After an edit of instances only (the models as rs has them): the instance
 * tables and the BVH are made again from the frame shown
 * (vx_render_scene_set_frame, which takes any instance count); the models'
 * node words stay on the GPU. The pass pipeline's and the probes' objects
 * hold scene facts (bounds, cell sizes, lights): the probes' and the gi
 * methods' are made again, which costs no GPU work until the next frame;
 * the frame renderer takes its facts again and keeps its buffers and frames
 * in flight. */
void sv_update_instances(app* a) {
    sv_probe_bake_cancel(a, "the scene changed");
    if (!a->rs || a->scene.model_count != a->rs_models) {
        sv_rebuild(a);
        return;
    }
    double t0 = vx_time_now();
    a->name_for = NO_SEL;
    vx_probe_gpu_destroy(a->probes_gpu);
    a->probes_gpu = NULL;
    /* the gi methods are made again; the frame renderer keeps its buffers (and
     * its frames in flight): only its scene facts change */
    vx_frame_renderer* fr = a->fr;
    a->fr = NULL;
    sv_drop_passes(a);
    a->fr = fr;
    uint32_t nf = vx_svo_scene_frames(&a->scene);
    if (a->anim_frame >= nf) a->anim_frame = nf - 1;
    vx_error err = {0};
    if (vx_render_scene_set_frame(a->rs, &a->scene, a->anim_frame, &err)) {
        sv_message(a, true, "instance update: %s", err.msg);
        sv_rebuild(a);
        return;
    }
    if (a->fr && vx_frame_renderer_update_scene(a->fr, &a->scene, &err)) {
        vx_frame_renderer_destroy(a->fr);
        a->fr = NULL;
    }
    if (!a->fr && vx_frame_renderer_create(a->rs, &a->scene, &a->fr, &err))
        sv_message(a, true, "pass pipeline: %s", err.msg);
    a->update_ms = (vx_time_now() - t0) * 1e3;
}

/* Starts an edit: the camera stops following the scene bounds, and the
 * state is saved for undo. */
bool sv_edit_begin(app* a, bool needs_sel) {
    if (needs_sel && a->sel == NO_SEL) {
        sv_message(a, true, "nothing selected");
        return false;
    }
    a->cam_default = false;
    vx_error err = {0};
    if (ved_begin(&a->ed, &err)) {
        sv_message(a, true, "%s", err.msg);
        return false;
    }
    return true;
}

void sv_edit_end(app* a, const char* what) {
    sv_update_instances(a); /* models changed: sv_rebuild */
    if (a->o.verbose) printf("%s: %s (scene update %.2f ms)\n", vx_tool_name, what, a->update_ms);
}

static void set_scene(app* a, vx_svo_scene* s) {
    ved_free(&a->ed);
    vx_svo_scene_free(&a->scene);
    a->scene = *s;
    ved_init(&a->ed, &a->scene);
    a->ed.undo_limit = a->o.undo_limit, a->ed.undo_bytes = a->o.undo_bytes;
    a->sel = NO_SEL;
    a->sel_light = NO_SEL;
    a->light_step_for = NO_SEL;
    a->mat_step_for = NO_SEL;
    a->light_serial++;
    a->op = 0;
    a->anim_frame = 0;
    a->playing = false;
    a->fps = a->o.fps > 0 ? a->o.fps : a->scene.frame_rate > 0 ? a->scene.frame_rate : SV_FPS_DEFAULT;
    sv_camera_default(a);
    sv_rebuild(a);
}

bool sv_open(app* a, const char* path) {
    vx_svo_scene s;
    vx_error err = {0};
    if (sv_load_scene(&a->o, path, &s, &err)) {
        file_error(a, path, err.msg);
        return false;
    }
    set_scene(a, &s);
    snprintf(a->scene_file, sizeof a->scene_file, "%s", path);
    /* probes describe the light of the scene they were baked in */
    bool had = a->have_probes;
    if (had) {
        sv_drop_probes(a);
        a->gi = false;
    }
    sv_message(a, false, "opened %s: %u models, %u instances%s", path, a->scene.model_count, a->scene.instance_count,
            had ? " (probes of the previous scene unloaded)" : "");
    return true;
}

bool sv_add(app* a, const char* path) {
    vx_svo_scene s;
    vx_error err = {0};
    if (sv_load_scene(&a->o, path, &s, &err)) {
        file_error(a, path, err.msg);
        return false;
    }
    /* next to the scene along +x, in grid cells */
    int32_t d[3] = {0, 0, 0};
    vx_svo_scene_update_bounds(&a->scene);
    vx_svo_scene_update_bounds(&s);
    if (a->scene.instance_count) {
        d[0] = (int32_t)(ceil(a->scene.bounds_max[0]) + 1 - floor(s.bounds_min[0]));
        d[1] = (int32_t)(floor(a->scene.bounds_min[1]) - floor(s.bounds_min[1]));
        d[2] = (int32_t)(floor(a->scene.bounds_min[2]) - floor(s.bounds_min[2]));
    }
    uint32_t first = 0, n = s.instance_count;
    if (!sv_edit_begin(a, false)) {
        vx_svo_scene_free(&s);
        return false;
    }
    bool ok = !ved_add_scene(&a->scene, &s, d, &first, &err);
    if (!ok) {
        file_error(a, path, err.msg);
        ved_undo(&a->ed, NULL);
    } else {
        ved_palette_scan(&a->ed); /* the added models' entries are in use */
        a->sel = n ? first : NO_SEL;
        sv_message(a, false, "added %s: %u instances", path, n);
    }
    vx_svo_scene_free(&s);
    sv_edit_end(a, "add");
    return ok;
}

/* The file holds the compacted models (vvx_file_scene). */
bool sv_save(app* a, const char* path) {
    vx_error err = {0};
    vx_svo_scene_update_bounds(&a->scene);
    vx_svo_scene fs;
    vx_result r = vvx_file_scene(&a->ed, &fs, &err);
    if (!r) {
        /* a map sky's relative path starts at the scene's file (app.h scene_file): the copy names the same image
         * from its own folder */
        r = vx_sky_rebase(&fs.sky, a->scene_file[0] ? a->scene_file : NULL, path, &err);
        if (!r) r = vx_svo_write_file(NULL, &fs, path, &err);
        vvx_file_scene_free(&a->ed, &fs);
    }
    if (r) file_error(a, path, err.msg);
    else sv_message(a, false, "saved %s", path);
    return !r;
}

/* .glb and .vdb: the library's exports (convert/export.h) of the scene as a
 * save would write it (svo_info --to-glb / --to-vdb of that file: the same
 * .glb bytes). */
static bool export_other(app* a, const char* path, bool glb) {
    vx_error err = {0};
    vx_svo_scene fs;
    vx_result r = vvx_file_scene(&a->ed, &fs, &err);
    if (!r) {
        /* a map sky's relative path starts at the scene's file (app.h scene_file) */
        vx_conv_export_desc xd = {.svo_path = a->scene_file[0] ? a->scene_file : NULL};
        r = glb ? vx_conv_svo_to_glb_file(&xd, &fs, path, NULL, &err) : vx_conv_svo_to_vdb_file(&xd, &fs, path, NULL, &err);
        vvx_file_scene_free(&a->ed, &fs);
    }
    if (r) file_error(a, path, err.msg);
    else sv_message(a, false, "exported %s", path);
    return !r;
}

bool sv_export(app* a, const char* path, bool quantize) {
    const char* kind = vx_tool_ext(path);
    if (!strcmp(kind, "glb") || !strcmp(kind, "vdb")) return export_other(a, path, !strcmp(kind, "glb"));
    vx_error err = {0};
    vx_vox_scene vs;
    vx_svo_scene fs;
    vx_conv_vox_export_stats st = {0};
    vx_result r = vvx_file_scene(&a->ed, &fs, &err);
    if (!r) {
        r = vx_conv_svo_to_vox_ex(&(vx_conv_vox_export_desc){.quantize = quantize}, &fs, &vs, &st, &err);
        vvx_file_scene_free(&a->ed, &fs);
    }
    if (!r) {
        r = vx_vox_write_file(NULL, &vs, path, &err);
        vx_vox_scene_free(&vs);
    }
    if (r == VX_ERR_UNSUPPORTED && st.colors > 255) /* the library names its desc field; the user needs the viewer's */
        snprintf(err.msg + strlen(err.msg), sizeof err.msg - strlen(err.msg), " (export FILE.vox quantize, the Export panel's "
                 "checkbox)");
    if (r) file_error(a, path, err.msg);
    else if (st.quantized) /* a warning, not an error: the file is written, its colours approximate */
        sv_message(a, false, "exported %s: warning: %u distinct colours quantized to a 255-entry palette: colour error (RGBA "
                   "distance, 0-255 a channel) max %.2f, mean %.2f", path, st.colors, st.max_error, st.mean_error);
    else sv_message(a, false, "exported %s", path);
    return !r;
}

bool sv_export_default(app* a) { return sv_export_as(a, "vox"); }

bool sv_export_as(app* a, const char* ext) {
    char path[1024];
    const char* dot = strrchr(a->o.in, '.');
    int n = dot ? (int)(dot - a->o.in) : (int)strlen(a->o.in);
    snprintf(path, sizeof path, "%.*s.edited.%s", n, a->o.in, ext);
    return sv_export(a, path, a->export_quantize);
}

void sv_edit_move(app* a, int axis, int32_t n) {
    int32_t d[3] = {0, 0, 0};
    d[axis] = n;
    ved_move(&a->scene, a->sel, d);
}

void sv_rotate(app* a, int axis, int turns) {
    if (!sv_edit_begin(a, true)) return;
    ved_rotate(&a->scene, a->anim_frame, a->sel, axis, turns);
    sv_edit_end(a, "rotate");
}

void sv_mirror(app* a, int axis) {
    if (!sv_edit_begin(a, true)) return;
    ved_mirror(&a->scene, a->anim_frame, a->sel, axis);
    sv_edit_end(a, "mirror");
}

void sv_duplicate(app* a) {
    if (!sv_edit_begin(a, true)) return;
    vx_error err = {0};
    uint32_t n;
    if (ved_duplicate(&a->scene, a->sel, &n, &err)) sv_message(a, true, "%s", err.msg);
    else a->sel = n;
    sv_edit_end(a, "duplicate");
}

void sv_delete(app* a) {
    if (!sv_edit_begin(a, true)) return;
    ved_delete(&a->scene, a->sel);
    a->sel = NO_SEL;
    sv_edit_end(a, "delete");
}

void sv_hide(app* a, bool hide) {
    if (!sv_edit_begin(a, hide)) return;
    if (hide) ved_hide(&a->scene, a->sel, true);
    else
        for (uint32_t i = 0; i < a->scene.instance_count; i++) ved_hide(&a->scene, i, false);
    sv_edit_end(a, hide ? "hide" : "show");
}

void sv_hide_instance(app* a, uint32_t i, bool hide) {
    if (i >= a->scene.instance_count || !sv_edit_begin(a, false)) return;
    ved_hide(&a->scene, i, hide);
    sv_edit_end(a, hide ? "hide" : "show");
}

void sv_rename(app* a, const char* name) {
    if (!sv_edit_begin(a, true)) return;
    ved_rename(&a->scene, a->sel, name);
    sv_edit_end(a, "rename");
}

bool sv_set_layer(app* a, uint32_t layer) {
    if (layer != UINT32_MAX && layer >= a->scene.layer_count) {
        sv_message(a, true, "no layer %u (the scene has %u)", layer, a->scene.layer_count);
        return false;
    }
    if (!sv_edit_begin(a, true)) return false;
    ved_set_layer(&a->scene, a->sel, layer);
    sv_edit_end(a, "layer");
    return true;
}

bool sv_set_model(app* a, uint32_t model) {
    if (model >= a->scene.model_count) {
        sv_message(a, true, "no model %u (the scene has %u)", model, a->scene.model_count);
        return false;
    }
    if (!sv_edit_begin(a, true)) return false;
    ved_set_model(&a->scene, a->sel, model);
    sv_edit_end(a, "model");
    return true;
}

void sv_select(app* a, uint32_t i) { a->sel = i < a->scene.instance_count ? i : NO_SEL; }

void sv_move(app* a, const int32_t d[3]) {
    if (!sv_edit_begin(a, true)) return;
    ved_move(&a->scene, a->sel, d);
    sv_edit_end(a, "move");
}

/* ---- animation ------------------------------------------------------------------------ */

void sv_set_frame(app* a, uint32_t f) {
    uint32_t nf = vx_svo_scene_frames(&a->scene);
    if (f >= nf) f = nf - 1;
    if (f == a->anim_frame) return;
    a->anim_frame = f;
    if (!a->rs) return;
    double t0 = vx_time_now();
    vx_error err = {0};
    /* the instance tables and the BVH only: the models stay on the GPU */
    if (vx_render_scene_set_frame(a->rs, &a->scene, f, &err)) sv_message(a, true, "frame %u: %s", f, err.msg);
    a->switch_ms = (vx_time_now() - t0) * 1e3;
}

void sv_play(app* a, bool play) {
    a->playing = play && vx_svo_scene_frames(&a->scene) > 1;
    a->play_clock = 0;
}

void sv_set_fps(app* a, double fps) {
    if (fps > 0 && fps <= 1000) a->fps = fps;
}

/* Advances playback by dt seconds of wall time (whole frames, wrapping). */
void sv_play_step(app* a, double dt) {
    uint32_t nf = vx_svo_scene_frames(&a->scene);
    if (!a->playing || nf < 2) return;
    a->play_clock += dt * a->fps;
    if (a->play_clock < 1) return;
    uint32_t steps = (uint32_t)fmin(a->play_clock, (double)nf);
    a->play_clock -= floor(a->play_clock);
    sv_set_frame(a, (a->anim_frame + steps) % nf);
}

/* ---- voxel editing ---------------------------------------------------------------------- */

bool sv_brush_palette(app* a, uint32_t i) {
    if (i < 1 || i > 255) return false;
    if (a->scene.has_palette && !a->scene.palette[i]) {
        /* a .svo stores the entries in use only (docs/FORMAT.md 2.2) */
        sv_message(a, true, "palette entry %u is empty in this file; give a colour (#RRGGBB) instead", i);
        return false;
    }
    a->brush.palette = (uint8_t)i;
    if (a->scene.has_palette) {
        a->brush.rgba = a->scene.palette[i];
        ved_palette_keep(&a->ed, i);
    }
    return true;
}

bool sv_brush_rgba(app* a, uint32_t rgba) {
    a->brush.rgba = rgba;
    if (!a->scene.has_palette) return true;
    /* palette models take the entry of that colour, an empty one, or one no cell used */
    uint32_t i = ved_palette_take(&a->ed, rgba);
    if (!i) {
        sv_message(a, true, "the palette is full: pick one of its colours");
        return false;
    }
    a->brush.palette = (uint8_t)i;
    return true;
}

/* After a voxel edit through the model's editor, or the undo or redo of
 * one: only the model's new words go to the GPU
 * (vx_render_scene_update_model); the gi methods' and the probes' objects,
 * which hold per-record tables, are made again at the next frame that needs
 * them, the pass pipeline's scene facts only when the model's size changed. */
static void update_model(app* a, uint32_t model, uint32_t words_from, uint32_t records_from, const uint32_t size[3]) {
    sv_probe_bake_cancel(a, "the scene changed");
    if (!a->rs || a->scene.model_count != a->rs_models) {
        sv_rebuild(a);
        return;
    }
    double t0 = vx_time_now();
    vx_error err = {0};
    if (vx_render_scene_update_model(a->rs, &a->scene, model, words_from, records_from, &err)) {
        sv_message(a, true, "model update: %s", err.msg);
        sv_rebuild(a);
        return;
    }
    a->update_ms = (vx_time_now() - t0) * 1e3;
    vx_probe_gpu_destroy(a->probes_gpu);
    a->probes_gpu = NULL;
    const uint32_t* ns = a->scene.models[model].size;
    if (ns[0] != size[0] || ns[1] != size[1] || ns[2] != size[2]) {
        /* a new size moves the bounds: the gi methods made again, the frame renderer's facts taken again */
        vx_frame_renderer* fr = a->fr;
        a->fr = NULL;
        sv_drop_passes(a);
        a->fr = fr;
        if (a->fr && vx_frame_renderer_update_scene(a->fr, &a->scene, &err)) {
            vx_frame_renderer_destroy(a->fr);
            a->fr = NULL;
        }
        if (!a->fr && vx_frame_renderer_create(a->rs, &a->scene, &a->fr, &err))
            sv_message(a, true, "pass pipeline: %s", err.msg);
    } else {
        sv_drop_gi(a);
        /* records appended: the pipeline's emission per record */
        if (records_from != UINT32_MAX && a->fr && vx_frame_renderer_update_scene(a->fr, &a->scene, &err))
            sv_message(a, true, "pass pipeline: %s", err.msg);
    }
}

bool sv_voxels(app* a, vvx_op op, const int64_t c[3]) {
    if (a->sel == NO_SEL) {
        sv_message(a, true, "voxel %s: nothing selected", vvx_op_name(op));
        return false;
    }
    uint32_t model = vx_svo_scene_frame_instances(&a->scene, a->anim_frame)[a->sel].model;
    uint32_t size[3];
    memcpy(size, a->scene.models[model].size, sizeof size);
    double t0 = vx_time_now();
    uint64_t n = 0;
    vx_error err = {0};
    if (vvx_apply(&a->ed, model, op, &a->brush, c, &n, &err)) {
        sv_message(a, true, "voxel %s: %s", vvx_op_name(op), err.msg);
        return false;
    }
    double t_model = (vx_time_now() - t0) * 1e3;
    a->cam_default = false;
    if (!n) return true;
    const ved_voxel_step* st = &a->ed.last;
    if (st->incremental) update_model(a, model, st->words_from, st->records_from, size);
    else sv_rebuild(a);
    if (a->o.verbose)
        printf("%s: voxel %s at %lld,%lld,%lld: %llu cells (model %s %.2f ms, scene update %.2f ms)\n", vx_tool_name,
               vvx_op_name(op), (long long)c[0], (long long)c[1], (long long)c[2], (unsigned long long)n,
               st->incremental ? "edit" : "decode + rebuild", t_model, a->update_ms);
    return true;
}

bool sv_layer(app* a, uint32_t l, int hide /* -1 toggles */) {
    if (l >= a->scene.layer_count) {
        sv_message(a, true, "no layer %u (the scene has %u)", l, a->scene.layer_count);
        return false;
    }
    if (!sv_edit_begin(a, false)) return false;
    uint32_t* f = &a->scene.layers[l].flags;
    bool h = hide < 0 ? !(*f & VX_SVO_LAYER_HIDDEN) : hide > 0;
    *f = h ? (*f | VX_SVO_LAYER_HIDDEN) : (*f & ~VX_SVO_LAYER_HIDDEN);
    sv_message(a, false, "layer %u '%s' %s", l, a->scene.layers[l].name, h ? "hidden" : "shown");
    sv_edit_end(a, "layer");
    return true;
}

void sv_undo(app* a, bool redo) {
    a->cam_default = false;
    bool ok = redo ? ved_redo(&a->ed, NULL) : ved_undo(&a->ed, NULL);
    if (!ok) {
        sv_message(a, false, "nothing to %s", redo ? "redo" : "undo");
        return;
    }
    if (a->sel != NO_SEL && a->sel >= a->scene.instance_count) a->sel = NO_SEL;
    if (a->sel_light != NO_SEL && a->sel_light >= a->scene.light_count) a->sel_light = NO_SEL;
    a->light_step_for = a->mat_step_for = NO_SEL; /* the next light or material edit is a step of its own */
    a->light_serial++;          /* the step may hold other lights */
    /* the step just swapped went to the other list: did it hold a model? */
    const ved_snapshot* sn = redo ? &a->ed.undo[a->ed.undo_count - 1] : &a->ed.redo[a->ed.redo_count - 1];
    if (sn->has_header) /* a header restored: the words are on the GPU (or uploaded if it never had them) */
        update_model(a, sn->model_index, UINT32_MAX, UINT32_MAX, sn->header.size);
    else if (sn->has_model) sv_rebuild(a);
    else sv_update_instances(a);
    if (a->o.verbose) printf("%s: %s (scene update %.2f ms)\n", vx_tool_name, redo ? "redo" : "undo", a->update_ms);
}

bool sv_set_light(app* a, uint32_t l, const vx_light* t, bool merge) {
    vx_error err = {0};
    if (l >= a->scene.light_count) {
        sv_message(a, true, "no light %u (the scene has %u)", l, a->scene.light_count);
        return false;
    }
    if (vx_light_validate(t, l, &err)) {
        sv_message(a, true, "%s", err.msg);
        return false;
    }
    if (!memcmp(t, &a->scene.lights[l], sizeof *t)) return true;
    bool same = merge && a->light_step_for == l && a->light_step == a->ed.serial && a->ed.undo_count > 0 &&
                a->ed.redo_count == 0;
    if (!same && !sv_edit_begin(a, false)) return false;
    a->scene.lights[l] = *t;
    a->light_serial++;
    a->light_step_for = merge ? l : NO_SEL, a->light_step = a->ed.serial;
    return true;
}

bool sv_set_sky(app* a, const vx_sky* k, bool merge) {
    vx_error err = {0};
    if (vx_sky_validate(k, &err)) {
        sv_message(a, true, "%s", err.msg);
        return false;
    }
    if (!memcmp(k, &a->scene.sky, sizeof *k)) return true;
    bool same = merge && a->sky_step == a->ed.serial && a->ed.undo_count > 0 && a->ed.redo_count == 0;
    if (!same && !sv_edit_begin(a, false)) return false; /* the snapshot holds the sky (editor.h) */
    a->scene.sky = *k;
    a->light_serial++; /* the gi methods are made with the sky (frame.c frame_desc) */
    a->sky_step = merge ? a->ed.serial : 0;
    return true;
}

bool sv_set_sky_text(app* a, const char* spec) {
    vx_sky k;
    vx_error err = {0};
    if (vx_sky_parse(spec, &k, &err)) {
        sv_message(a, true, "bad sky '%s': %s", spec, err.msg);
        return false;
    }
    /* from the current folder to the scene file's (a scene made here has none: the current folder) */
    if (vx_sky_rebase(&k, NULL, a->scene_file[0] ? a->scene_file : NULL, &err)) {
        sv_message(a, true, "sky '%s': %s", spec, err.msg);
        return false;
    }
    return sv_set_sky(a, &k, false);
}

void sv_sky_text(app* a, char* out, size_t n) {
    vx_sky k = a->scene.sky;
    vx_error err = {0};
    const char* file = a->scene_file[0] ? a->scene_file : NULL;
    if (vx_sky_rebase(&k, file, NULL, &err)) {
        /* the file's folder no longer resolves: its path joined as text still names the map from here */
        char joined[VX_SKY_PATH_MAX + 1];
        if (vx_sky_path(&a->scene.sky, file, joined, sizeof joined)) memcpy(k.path, joined, sizeof k.path);
    }
    if (vx_sky_format(&k, out, n, &err)) sv_message(a, true, "%s", err.msg);
}

/* After the materials changed (an edit; undo and redo go through
 * update_instances, which does the same): the gi methods read them when made
 * (metal and glass, emission) and the frame renderer's emission table. */
static void materials_changed(app* a) {
    sv_probe_bake_cancel(a, "the materials changed");
    vx_frame_renderer* fr = a->fr;
    a->fr = NULL;
    sv_drop_passes(a); /* the gi methods; the frame renderer keeps its buffers and frames in flight */
    a->fr = fr;
    vx_error err = {0};
    if (a->fr && vx_frame_renderer_update_scene(a->fr, &a->scene, &err)) {
        vx_frame_renderer_destroy(a->fr);
        a->fr = NULL;
    }
    if (!a->fr && a->rs && vx_frame_renderer_create(a->rs, &a->scene, &a->fr, &err))
        sv_message(a, true, "pass pipeline: %s", err.msg);
}

bool sv_set_material(app* a, uint32_t id, const char* field, const char* value, bool merge) {
    const char* keys[2];
    char values[2][SV_MATERIAL_VALUE], why[256];
    uint32_t n;
    if (!sv_material_field(field, value, keys, values, &n, why, sizeof why)) {
        sv_message(a, true, "material %u: %s", id, why);
        return false;
    }
    /* nothing to do when every pair is there already */
    const vx_svo_material* m = NULL;
    for (uint32_t i = 0; i < a->scene.material_count && !m; i++)
        if (a->scene.materials[i].id == id) m = &a->scene.materials[i];
    bool same = true;
    for (uint32_t k = 0; k < n; k++) {
        const char* v = vx_svo_material_get(m, keys[k]);
        same = same && v && !strcmp(v, values[k]);
    }
    if (same) return true;
    bool merged = merge && a->mat_step_for == id && a->mat_step == a->ed.serial && a->ed.undo_count > 0 &&
                  a->ed.redo_count == 0;
    vx_error err = {0};
    if (!merged) {
        if (ved_begin_materials(&a->ed, &err)) {
            sv_message(a, true, "%s", err.msg);
            return false;
        }
    }
    for (uint32_t k = 0; k < n; k++)
        if (ved_material_set(&a->scene, id, keys[k], values[k], &err)) {
            sv_message(a, true, "%s", err.msg); /* out of memory: the pairs set so far stay (an undo step) */
            break;
        }
    a->mat_step_for = merge ? id : NO_SEL, a->mat_step = a->ed.serial;
    materials_changed(a);
    if (a->o.verbose) printf("%s: material %u %s %s\n", vx_tool_name, id, field, value);
    return true;
}

bool sv_set_gi_option(app* a, const char* name, const char* value) {
    char why[320];
    if (!sv_gi_option(&a->gis, name, value, why, sizeof why)) {
        sv_message(a, true, "gi: %s", why);
        return false;
    }
    /* the gi methods are made with these at the next frame */
    vx_frame_renderer* fr = a->fr;
    a->fr = NULL;
    sv_drop_passes(a);
    a->fr = fr;
    a->timing_count = 0;
    return true;
}
