/* tools/svo_view/panels.c - svo_view's panels (see panels.h), C over ui.h. */
#include "tools/svo_view/panels.h"

#include <GLFW/glfw3.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <vulkan/vulkan.h> /* the swapchain's layout for the panels drawn on the GPU */

#include "tools/svo_view/camera.h" /* SV_PI */
#include "tools/svo_view/ui.h"

static const char* const light_types[VX_LIGHT_TYPE_COUNT] = {"directional", "point", "spot", "sphere", "rect"};
static const char* const gi_methods[] = {"none", "probes", "lightfield", "pathtrace", "cones", "photons"};
#define GI_METHODS ((int)(sizeof gi_methods / sizeof gi_methods[0]))
/* pass colours of the statistics bars, by timing row */
static const uint32_t bar_colours[] = {0x4FA3F2u, 0x5CD65Cu, 0x3FC8F0u, 0xE0709Au, 0x4A7CE8u, 0xC0C040u, 0xA070E0u, 0x80B0B0u};

bool sv_panels_built(void) { return true; }

bool sv_panels_create(app* a) {
    a->ui = ui_create();
    if (!a->ui) sv_message(a, true, "panels: out of memory");
    return a->ui != NULL;
}

void sv_panels_destroy(app* a) {
    ui_destroy(a->ui);
    a->ui = NULL;
}

bool sv_panels_gpu_init(app* a, char* why, size_t why_size) {
    if (!a->ui || !a->p) return false;
    vx_gpu_desc gd = {0};
    vp_external(a->p, &gd);
    ui_gpu_desc ud = {.instance = (void*)gd.external.instance, .phys = (void*)gd.external.physical_device,
                      .device = (void*)gd.external.device, .queue = (void*)gd.external.queue,
                      .queue_family = gd.external.queue_family, .format = vp_format(a->p),
                      .final_layout = VK_IMAGE_LAYOUT_PRESENT_SRC_KHR, .frames = VX_DISPLAY_SLOTS};
    return ui_gpu_init(a->ui, &ud, why, why_size);
}

bool sv_panels_gpu_record(app* a, void* cmd, uint32_t slot, uint64_t view, uint32_t w, uint32_t h, char* why,
                          size_t why_size) {
    return ui_gpu_record(a->ui, cmd, slot, view, w, h, why, why_size);
}

void sv_panels_mouse(app* a, double x, double y) {
    if (a->ui) ui_mouse(a->ui, x, y);
}
void sv_panels_button(app* a, int button, bool down) {
    if (a->ui) ui_mouse_button(a->ui, button, down);
}
void sv_panels_find(app* a, const char* label) {
    if (a->ui) ui_find(a->ui, label);
}
bool sv_panels_found(const app* a, float rect[4]) { return a->ui && ui_found(a->ui, rect); }
void sv_panels_wheel(app* a, double dy) {
    if (a->ui) ui_wheel(a->ui, dy);
}
void sv_panels_key(app* a, int key, bool down, int mods) {
    if (a->ui)
        ui_key(a->ui, key, down, mods & GLFW_MOD_CONTROL, mods & GLFW_MOD_SHIFT, mods & GLFW_MOD_ALT);
}
void sv_panels_char(app* a, unsigned int c) {
    if (a->ui) ui_char(a->ui, c);
}
bool sv_panels_wants_mouse(const app* a) { return a->ui && a->panels && ui_wants_mouse(a->ui); }
bool sv_panels_wants_keyboard(const app* a) { return a->ui && a->panels && ui_wants_keyboard(a->ui); }

/* ---- outliner --------------------------------------------------------------------------- */

static void outliner(app* a) {
    vx_svo_scene* s = &a->scene;
    const vx_svo_instance* fr = vx_svo_scene_frame_instances(s, a->anim_frame);
    char label[160];
    if (s->layer_count && ui_collapsing("Layers", true)) {
        for (uint32_t l = 0; l < s->layer_count; l++) {
            bool shown = !(s->layers[l].flags & VX_SVO_LAYER_HIDDEN);
            snprintf(label, sizeof label, "%u %s##layer%u", l, s->layers[l].name, l);
            if (ui_checkbox(label, &shown)) sv_layer(a, l, !shown);
        }
    }
    if (ui_collapsing("Instances", true)) {
        /* a long list shows its first rows; the rest are picked in the view or by script */
        uint32_t n = s->instance_count < 2000 ? s->instance_count : 2000;
        for (uint32_t i = 0; i < n; i++) {
            ui_push_id((int)i);
            bool shown = !(fr[i].flags & VX_SVO_INSTANCE_HIDDEN);
            if (ui_checkbox("##shown", &shown)) sv_hide_instance(a, i, !shown);
            ui_same_line();
            snprintf(label, sizeof label, "%u %s (model %u)", i, fr[i].name[0] ? fr[i].name : "-", fr[i].model);
            if (ui_selectable(label, a->sel == i)) sv_select(a, a->sel == i ? NO_SEL : i);
            ui_pop_id();
        }
        if (n < s->instance_count) ui_text("... %u more", s->instance_count - n);
    }
    if (ui_collapsing("Models", false)) {
        for (uint32_t m = 0; m < s->model_count; m++) {
            const vx_svo_model* md = &s->models[m];
            uint32_t uses = 0;
            for (uint32_t i = 0; i < s->instance_count; i++) uses += fr[i].model == m;
            ui_text("%u: %ux%ux%u, %llu voxels, %u instance%s", m, md->size[0], md->size[1], md->size[2],
                    (unsigned long long)md->voxel_count, uses, uses == 1 ? "" : "s");
        }
    }
    if (ui_collapsing("Lights", true)) {
        if (!s->light_count) ui_text("(none in the file)");
        for (uint32_t l = 0; l < s->light_count; l++) {
            snprintf(label, sizeof label, "light %u: %s##light%u", l,
                     (unsigned)s->lights[l].type < VX_LIGHT_TYPE_COUNT ? light_types[s->lights[l].type] : "?", l);
            if (ui_selectable(label, a->sel_light == l)) a->sel_light = a->sel_light == l ? NO_SEL : l;
        }
    }
    /* a .vox palette holds 255 colours: an RGBA8 scene with more is refused unless quantized */
    if (ui_collapsing("Export", false)) {
        ui_checkbox("quantize colours (over 255)", &a->export_quantize);
        if (ui_button("export .vox (Ctrl+E)")) sv_export_default(a);
        if (ui_button("export .glb")) sv_export_as(a, "glb");
        if (ui_button("export .vdb")) sv_export_as(a, "vdb");
    }
}

/* ---- properties ------------------------------------------------------------------------- */

static void brush_panel(app* a) {
    vx_svo_scene* s = &a->scene;
    ui_checkbox("voxel mode (B)", &a->voxel_mode);
    ui_text("click: add  Shift: remove  Alt: paint");
    static const char* const shapes[VVX_SHAPE_COUNT] = {"voxel", "box", "sphere", "face"};
    int shape = (int)a->brush.shape, radius = (int)a->brush.radius;
    if (ui_combo("brush", &shape, shapes, VVX_SHAPE_COUNT)) a->brush.shape = (vvx_shape)shape;
    if (a->brush.shape != VVX_VOXEL && ui_slider_int("radius", &radius, 0, 16)) a->brush.radius = (uint32_t)radius;
    if (s->has_palette) {
        ui_text("palette: %u", a->brush.palette ? a->brush.palette : 1);
        for (int i = 1; i < 256; i++) {
            char id[24]; /* "##pal" and any int: -O1 builds warn of truncation at 16 */
            snprintf(id, sizeof id, "##pal%d", i);
            if ((i - 1) % 16) ui_same_line();
            uint8_t cur = a->brush.palette ? a->brush.palette : 1;
            /* empty entries (a .svo keeps the used ones) show black; the colour below fills one */
            if (ui_swatch(id, s->palette[i], cur == i, 12) && s->palette[i]) sv_brush_palette(a, (uint32_t)i);
        }
    }
    /* a colour is taken on the button, not while dragging (each new colour
     * fills an empty palette entry) */
    ui_color3("##pick", a->pick_rgb);
    ui_same_line();
    if (ui_button("use colour")) {
        uint32_t v = 0xFF000000u;
        for (int k = 0; k < 3; k++) {
            double x = a->pick_rgb[k] < 0 ? 0 : a->pick_rgb[k] > 1 ? 1 : a->pick_rgb[k];
            v |= (uint32_t)(x * 255 + 0.5) << (8 * k);
        }
        sv_brush_rgba(a, v);
    }
    uint32_t c = a->brush.rgba ? a->brush.rgba : 0xFFFFFFFFu;
    ui_text("brush colour #%02X%02X%02X", c & 0xFF, (c >> 8) & 0xFF, (c >> 16) & 0xFF);
    if (ui_button("undo")) sv_undo(a, false);
    ui_same_line();
    if (ui_button("redo")) sv_undo(a, true);
}

static void instance_props(app* a) {
    const vx_svo_instance* in = vx_svo_scene_frame_instances(&a->scene, a->anim_frame) + a->sel;
    ui_text("instance %u", a->sel);
    /* the field edits a copy; Enter renames (an undo step) */
    if (a->name_for != a->sel) snprintf(a->name_buf, sizeof a->name_buf, "%s", in->name), a->name_for = a->sel;
    if (ui_input_text("name (Enter)", a->name_buf, sizeof a->name_buf)) sv_rename(a, a->name_buf);
    /* model and layer: combos over the scene's (at most 64 named here; scripts reach any) */
    enum { MAXN = 64 };
    char names[MAXN + 1][80]; /* "N " and a 63-byte name */
    const char* items[MAXN + 1];
    int nm = a->scene.model_count < MAXN ? (int)a->scene.model_count : MAXN, cur = (int)in->model;
    for (int m = 0; m < nm; m++) {
        const vx_svo_model* md = &a->scene.models[m];
        snprintf(names[m], sizeof names[m], "%d: %ux%ux%u", m, md->size[0], md->size[1], md->size[2]);
        items[m] = names[m];
    }
    if (cur < nm && ui_combo("model", &cur, items, nm)) sv_set_model(a, (uint32_t)cur);
    int nl = a->scene.layer_count < MAXN ? (int)a->scene.layer_count : MAXN;
    cur = in->layer < (uint32_t)nl ? (int)in->layer + 1 : 0;
    snprintf(names[0], sizeof names[0], "none");
    items[0] = names[0];
    for (int l = 0; l < nl; l++) {
        snprintf(names[l + 1], sizeof names[l + 1], "%d %s", l, a->scene.layers[l].name);
        items[l + 1] = names[l + 1];
    }
    if (ui_combo("layer", &cur, items, nl + 1)) sv_set_layer(a, cur ? (uint32_t)cur - 1 : UINT32_MAX);
    int32_t t[3] = {(int32_t)in->xform[3], (int32_t)in->xform[7], (int32_t)in->xform[11]};
    int32_t t0[3] = {t[0], t[1], t[2]};
    if (ui_input_int3("position (cells, Enter)", t)) {
        int32_t d[3] = {t[0] - t0[0], t[1] - t0[1], t[2] - t0[2]};
        if (d[0] || d[1] || d[2]) sv_move(a, d);
    }
    ui_text("linear part: %g %g %g | %g %g %g | %g %g %g", in->xform[0], in->xform[1], in->xform[2], in->xform[4],
            in->xform[5], in->xform[6], in->xform[8], in->xform[9], in->xform[10]);
    static const char* const rot[3][2] = {{"turn X+", "turn X-"}, {"turn Y+", "turn Y-"}, {"turn Z+", "turn Z-"}};
    static const char* const mir[3] = {"mirror X", "mirror Y", "mirror Z"};
    for (int k = 0; k < 3; k++) {
        if (ui_button(rot[k][0])) sv_rotate(a, k, 1);
        ui_same_line();
        if (ui_button(rot[k][1])) sv_rotate(a, k, -1);
        ui_same_line();
        if (ui_button(mir[k])) sv_mirror(a, k);
    }
    if (ui_button("duplicate")) sv_duplicate(a);
    ui_same_line();
    if (ui_button("delete")) sv_delete(a);
    ui_same_line();
    if (ui_button("hide")) sv_hide(a, true);
    ui_same_line();
    if (ui_button("frame")) sv_frame_camera(a);
}

static void light_props(app* a) {
    vx_light* l = &a->scene.lights[a->sel_light];
    vx_light before = *l;
    ui_text("light %u", a->sel_light);
    int type = (int)l->type;
    if (ui_combo("type", &type, light_types, VX_LIGHT_TYPE_COUNT)) l->type = (vx_light_type)type;
    ui_color3("colour", l->color);
    ui_drag_double("intensity", &l->intensity, 0.05, 0, 1e9);
    if (l->type == VX_LIGHT_POINT || l->type == VX_LIGHT_SPOT) ui_drag_double("range (0: none)", &l->range, 0.1, 0, 1e9);
    if (l->type != VX_LIGHT_DIRECTIONAL) ui_drag_double3("position", l->position, 0.1);
    if (l->type == VX_LIGHT_POINT || l->type == VX_LIGHT_SPOT || l->type == VX_LIGHT_SPHERE)
        ui_drag_double("radius", &l->radius, 0.01, 0, 1e9);
    /* the edit goes through the editor's undo (a drag is one step); one that
     * breaks the light's rules (vx_light_validate) is taken back */
    if (memcmp(&before, l, sizeof before)) {
        vx_light t = *l;
        *l = before;
        sv_set_light(a, a->sel_light, &t, true);
    }
}

/* The scene's sky (svo/svo.h vx_sky): its type, colours or map, and its
 * text as svo_render --sky takes it (the script's `sky SPEC`); every edit
 * through sv_set_sky, so undo restores it (a colour drag is one step). */
static void sky_props(app* a) {
    static const char* const types[VX_SKY_TYPE_COUNT] = {"default (the renderer's)", "constant", "gradient",
                                                         "environment map"};
    const vx_sky* cur = &a->scene.sky;
    if (a->sky_text_for != a->light_serial + 1) { /* the sky may have changed (an edit, undo, open): the fields again */
        a->sky_text_for = a->light_serial + 1;   /* + 1: 0 is "never filled" */
        sv_sky_text(a, a->sky_text, sizeof a->sky_text);
        const char* m = !strncmp(a->sky_text, "map:", 4) ? a->sky_text + 4 : "";
        size_t l = strcspn(m, ":");
        snprintf(a->sky_map_text, sizeof a->sky_map_text, "%.*s", (int)l, m);
    }
    vx_sky k = *cur;
    int type = (unsigned)k.type < VX_SKY_TYPE_COUNT ? (int)k.type : 0;
    if (ui_combo("sky type", &type, types, VX_SKY_TYPE_COUNT) && type != (int)k.type) {
        /* a type of its own colours: the zenith kept as the colour, a pale sky where there is none */
        double c[3] = {k.color[0], k.color[1], k.color[2]};
        if (k.type != VX_SKY_CONSTANT && k.type != VX_SKY_GRADIENT) c[0] = 0.5, c[1] = 0.6, c[2] = 0.8;
        vx_sky n = {.type = (vx_sky_type)type};
        if (type == VX_SKY_CONSTANT || type == VX_SKY_GRADIENT) memcpy(n.color, c, sizeof c);
        if (type == VX_SKY_GRADIENT) {
            n.horizon[0] = n.horizon[1] = 0.9, n.horizon[2] = 1.0;
            n.ground[0] = n.ground[1] = n.ground[2] = 0.2;
        }
        if (type == VX_SKY_ENVMAP) {
            if (!a->sky_map_text[0]) sv_message(a, false, "sky: type the map's file and press Enter");
            else { /* the file last shown, from the current folder */
                char t[VX_SKY_SPEC_MAX + 8];
                snprintf(t, sizeof t, "map:%s", a->sky_map_text);
                sv_set_sky_text(a, t);
            }
        } else {
            sv_set_sky(a, &n, false);
        }
        return;
    }
    if (k.type == VX_SKY_CONSTANT) ui_color3("sky colour", k.color);
    if (k.type == VX_SKY_GRADIENT) {
        ui_color3("zenith", k.color);
        ui_color3("horizon", k.horizon);
        ui_color3("ground", k.ground);
    }
    if (k.type == VX_SKY_ENVMAP) {
        double deg = k.rotation * 180 / SV_PI;
        ui_drag_double("map intensity", &k.intensity, 0.05, 0, 1e9);
        if (ui_drag_double("map rotation (deg)", &deg, 1, -360, 360)) k.rotation = deg * SV_PI / 180;
    }
    /* colours and the map's numbers: one step a drag; a change the sky's rules refuse is taken back */
    if (memcmp(&k, cur, sizeof k)) sv_set_sky(a, &k, true);
    if (ui_input_text("map file", a->sky_map_text, sizeof a->sky_map_text) && a->sky_map_text[0]) {
        /* from the current folder, with the map's intensity and rotation as they are */
        char t[2 * VX_SKY_SPEC_MAX], num[VX_SKY_SPEC_MAX] = "";
        vx_sky m = *cur;
        memset(m.path, 0, sizeof m.path);
        m.path[0] = 'x'; /* the text's numbers after "map:x" (vx_sky_format: they read back exactly) */
        if (cur->type == VX_SKY_ENVMAP && !vx_sky_format(&m, num, sizeof num, NULL)) memmove(num, num + 5, strlen(num + 5) + 1);
        else num[0] = 0;
        snprintf(t, sizeof t, "map:%s%s", a->sky_map_text, num);
        sv_set_sky_text(a, t);
    }
    if (ui_input_text("sky (svo_render --sky)", a->sky_text, sizeof a->sky_text)) sv_set_sky_text(a, a->sky_text);
}

/* The material of a palette index or material id (docs/FORMAT.md 4.1): its
 * type and parameters as the scene's dictionary has them, each edit through
 * sv_set_material (the script command `material ID FIELD VALUE`). */
static void material_props(app* a) {
    int id = (int)(a->mat_sel < 256 ? a->mat_sel : 255);
    if (ui_slider_int("id (palette index / material)", &id, 0, 255)) a->mat_sel = (uint32_t)id;
    if (a->scene.has_palette && ui_button("the brush's palette entry")) a->mat_sel = a->brush.palette ? a->brush.palette : 1;
    const vx_svo_material* m = NULL;
    for (uint32_t i = 0; i < a->scene.material_count && !m; i++)
        if (a->scene.materials[i].id == a->mat_sel) m = &a->scene.materials[i];
    vx_material r = vx_svo_material_resolve(m); /* defaults where the dictionary has no key */
    static const char* const types[4] = {"diffuse", "metal", "glass", "emit"};
    const char* t = vx_svo_material_get(m, "_type");
    int type = 0;
    for (int k = 1; k < 4; k++)
        if (t && t[0] == '_' && !strcmp(t + 1, types[k])) type = k;
    ui_text("material %u: %s%s", a->mat_sel, m ? "" : "(none in the file: diffuse) ", r.emission > 0 ? "emissive" : "");
    char v[64];
    if (ui_combo("type", &type, types, 4)) sv_set_material(a, a->mat_sel, "type", types[type], false);
    /* each drag is one undo step (merged) */
    static const struct {
        const char* label;
        const char* field;
        double speed, lo, hi;
    } f[] = {{"roughness", "rough", 0.01, 0, 1}, {"metalness", "metal", 0.01, 0, 1}, {"specular", "spec", 0.01, 0, 1},
             {"IOR", "ior", 0.01, 1, 4},          {"transmission", "trans", 0.01, 0, 1},
             {"emission (_emit)", "emit", 0.01, 0, 1e6}, {"flux (2^flux)", "flux", 0.05, 0, 16}};
    double emit = 0, flux = 0;
    const char* e = vx_svo_material_get(m, "_emit");
    const char* x = vx_svo_material_get(m, "_flux");
    if (e) emit = strtod(e, NULL);
    if (x) flux = strtod(x, NULL);
    double val[7] = {r.roughness, r.metalness, r.specular, r.ior, r.transmission, emit, flux};
    for (int k = 0; k < 7; k++) {
        if (k == 1 && type != 1) continue; /* metalness: metal */
        if ((k == 3 || k == 4) && type != 2) continue; /* IOR, transmission: glass */
        double d = val[k];
        if (ui_drag_double(f[k].label, &d, f[k].speed, f[k].lo, f[k].hi) && d != val[k]) {
            snprintf(v, sizeof v, "%.4g", d);
            sv_set_material(a, a->mat_sel, f[k].field, v, true);
        }
    }
    /* the emission's own colour (_emit_color, glTF's emissive colour) or the voxel's (MagicaVoxel's) */
    bool own = r.emission_color[0] > 0 || r.emission_color[1] > 0 || r.emission_color[2] > 0;
    if (ui_checkbox("own emission colour (_emit_color)", &own)) sv_set_material(a, a->mat_sel, "emit_color", own ? "1,1,1" : "none", false);
    double ec[3] = {r.emission_color[0], r.emission_color[1], r.emission_color[2]};
    if (own && ui_color3("emission colour", ec)) {
        snprintf(v, sizeof v, "%.4g,%.4g,%.4g", ec[0], ec[1], ec[2]);
        sv_set_material(a, a->mat_sel, "emit_color", v, true);
    }
    if (own)
        ui_text("emission: its own colour (%.3g %.3g %.3g) x %g", r.emission_color[0], r.emission_color[1],
                r.emission_color[2], r.emission);
    else
        ui_text("emission: colour x %g", r.emission);
}

/* ---- render and statistics -------------------------------------------------------------- */

/* The gi method's settings as svo_render has them (settings.h; the script
 * command `gi OPTION VALUE`); shown for the method in the pass list. */
static void gi_settings(app* a) {
    const sv_gi_settings* g = &a->gis;
    bool has = vx_pass_list_has(&a->passes, VX_PASS_GI);
    const char* m = has ? a->passes.gi : "none";
    char v[32];
    int i;
    double d;
    bool b;
#define SET(name, ...) (snprintf(v, sizeof v, __VA_ARGS__), sv_set_gi_option(a, name, v))
    ui_text("method: %s", m);
    i = (int)(g->spp ? g->spp : 0);
    if (ui_slider_int("samples (0: default)", &i, 0, 64) && i > 0) SET("spp", "%d", i);
    i = (int)g->seed;
    if (ui_slider_int("seed", &i, 0, 1000)) SET("seed", "%d", i);
    if (vx_pass_list_has(&a->passes, VX_PASS_AO)) {
        i = (int)(g->ao_rays ? g->ao_rays : 4);
        if (ui_slider_int("ao rays", &i, 1, 64)) SET("ao-rays", "%d", i);
    }
    if (!strcmp(m, "pathtrace")) {
        i = (int)(g->bounces ? g->bounces : 2);
        if (ui_slider_int("bounces", &i, 1, 16)) SET("bounces", "%d", i);
    } else if (!strcmp(m, "photons")) {
        vx_photon_desc D = vx_photon_desc_defaults();
        i = (int)(g->photon.photons ? g->photon.photons : D.photons);
        if (ui_slider_int("photons a pass", &i, 1000, 4000000)) SET("photons", "%d", i);
        i = (int)g->photon.final_gather;
        if (ui_slider_int("final gather rays", &i, 0, 64)) SET("final-gather", "%d", i);
        d = g->photon.radius;
        ui_text("radius: %s", d > 0 ? "" : "0 = scene diagonal / 100");
        if (ui_drag_double("radius (world)", &d, 0.01, 0, 1e6) && d > 0) SET("radius", "%.6g", d);
    } else if (!strcmp(m, "cones")) {
        vx_cone_desc D = vx_cone_desc_defaults();
        i = (int)(g->cone.res ? g->cone.res : D.res);
        if (ui_slider_int("volume res", &i, 2, VX_CONE_RES_MAX)) SET("cone-res", "%d", i);
        i = (int)(g->cone.cones ? g->cone.cones : D.cones);
        if (ui_slider_int("cones", &i, 1, VX_CONE_CONES_MAX)) SET("cones", "%d", i);
        d = g->cone.aperture > 0 ? g->cone.aperture : 0;
        if (ui_drag_double("aperture (deg, 0: auto)", &d, 0.1, 0, 88.9) && d > 0) SET("cone-aperture", "%.6g", d);
        i = (int)(g->cone.bounces ? g->cone.bounces : D.bounces);
        if (ui_slider_int("volume bounces", &i, 1, 4)) SET("cone-bounces", "%d", i);
        b = g->cone.isotropic;
        if (ui_checkbox("isotropic", &b)) SET("cone-isotropic", "%s", b ? "on" : "off");
        b = g->cone.half_res;
        if (ui_checkbox("half resolution", &b)) SET("cone-half", "%s", b ? "on" : "off");
        b = g->cone.shadows;
        if (ui_checkbox("cone shadows (no direct pass)", &b)) SET("cone-shadows", "%s", b ? "on" : "off");
        if (g->cone.shadows) {
            d = g->cone.sun_angle > 0 ? g->cone.sun_angle : D.sun_angle;
            if (ui_drag_double("sun angle (deg)", &d, 0.05, 0.01, 29.9)) SET("cone-sun-angle", "%.6g", d);
        }
        b = g->cone.no_specular;
        if (ui_checkbox("no specular cones", &b)) SET("cone-no-specular", "%s", b ? "on" : "off");
        b = g->cone.output == VX_CONE_OUTPUT_AO;
        if (ui_checkbox("AO as the gi image", &b)) SET("cone-ao", "%s", b ? "on" : "off");
    } else if (has) {
        ui_text("(the probes' own settings: svo_bake's; see the Probes panel)");
    }
#undef SET
    char line[320];
    sv_gi_options_format(g, line, sizeof line);
    ui_text("svo_render:%s", line[0] ? line : " (defaults)");
}


static void render_panel(app* a) {
    static const char* const modes[VX_RENDER_MODE_NUM] = {"color", "albedo", "normal", "depth", "instance", "iterations"};
    int mode = a->gi ? -1 : (int)a->mode;
    if (a->gi) ui_text("mode %s (probes)", sv_mode_name(a));
    if (ui_combo("mode", &mode, modes, VX_RENDER_MODE_NUM) && mode >= 0) a->mode = (vx_render_mode)mode, a->gi = false;
    ui_text("passes (colour mode):");
    bool on[VX_PASS_KIND_COUNT];
    for (int k = 0; k < VX_PASS_KIND_COUNT; k++) on[k] = vx_pass_list_has(&a->passes, (vx_pass_kind)k);
    int gi = 0;
    for (int m = 1; m < GI_METHODS; m++)
        if (on[VX_PASS_GI] && !strcmp(a->passes.gi, gi_methods[m])) gi = m;
    bool changed = false;
    for (int k = 0; k < VX_PASS_KIND_COUNT; k++) {
        if (k == VX_PASS_GI) continue; /* the GI combo below */
        if (k % 3) ui_same_line();
        changed |= ui_checkbox(vx_pass_name((vx_pass_kind)k), &on[k]);
    }
    changed |= ui_combo("GI method", &gi, gi_methods, GI_METHODS);
    if (changed) {
        /* the list in the only order passes may take (render/pipeline.h) */
        char list[200] = "";
        size_t at = 0;
        for (int k = 0; k < VX_PASS_KIND_COUNT && at < sizeof list; k++) {
            if (k == VX_PASS_GI ? gi == 0 : !on[k]) continue;
            at += (size_t)snprintf(list + at, sizeof list - at, "%s%s%s%s", at ? "," : "", vx_pass_name((vx_pass_kind)k),
                                   k == VX_PASS_GI ? "=" : "", k == VX_PASS_GI ? gi_methods[gi] : "");
        }
        if (sv_set_passes(a, list)) a->mode = VX_RENDER_COLOR, a->gi = false;
    }
    ui_drag_double("exposure (stops, tonemap)", &a->exposure, 0.05, -16, 16);
    bool vs = vp_vsync(a->p);
    if (ui_checkbox("vsync", &vs)) vp_set_vsync(a->p, vs);
    if (ui_collapsing("GI settings", false)) gi_settings(a);
}

static void stats_panel(app* a) {
    double med = 0;
    uint32_t n = a->frame_n < 64 ? a->frame_n : 64;
    for (uint32_t i = 0; i < n; i++) med += a->frame_ms[i];
    med = n ? med / n : 0;
    ui_text("%s%s", vx_gpu_device_name(a->gpu), vx_gpu_is_cpu(a->gpu) ? " (software)" : "");
    ui_text("frame %.2f ms (%.1f FPS), trace %.2f ms GPU", med, med > 0 ? 1000 / med : 0.0, a->trace_ms);
    ui_text("%.2f Mrays/s, last scene update %.2f ms", a->rays_per_s * 1e-6, a->update_ms);
    ui_text("present: %s", a->frame_in_flight ? "GPU, frames in flight (passes, conversion, copy: one submission)"
                           : a->frame_on_gpu ? "GPU (display conversion + copy to the swapchain)" : a->disp ?
            "host readback (this frame: not the colour passes, or a pick or screenshot)" : a->present_note);
    uint64_t bytes = 0, voxels = 0;
    for (uint32_t m = 0; m < a->scene.model_count; m++) {
        const vx_svo_model* md = &a->scene.models[m];
        size_t rec = ((md->attrs & VX_ATTR_PALETTE) ? 1 : 0) + ((md->attrs & VX_ATTR_RGBA8) ? 4 : 0) +
                     ((md->attrs & VX_ATTR_NORMAL) ? 4 : 0) + ((md->attrs & VX_ATTR_MATERIAL) ? 2 : 0) +
                     ((md->attrs & VX_ATTR_DENSITY) ? 4 : 0);
        bytes += (uint64_t)md->node_count * 4 + (uint64_t)md->attr_count * rec;
        voxels += md->voxel_count;
    }
    ui_text("models: %.2f MB octrees (%llu voxels), frame %.2f MB", bytes / 1048576.0, (unsigned long long)voxels,
            (double)a->px8_cap / 1048576.0);
    uint64_t words, records;
    sv_uploads(a, &words, &records);
    ui_text("GPU scene made %u times; uploaded %.2f MB of node words, %.2f MB of colours", a->scenes_made,
            words * 4 / 1048576.0, records * 4 / 1048576.0);
    if (!a->hist_n || a->gi || a->mode != VX_RENDER_COLOR) {
        ui_text("(per-pass times: the colour mode's passes)");
        return;
    }
    float top = 0;
    for (uint32_t f = 0; f < a->hist_n; f++) {
        float sum = 0;
        for (uint32_t l = 0; l < a->hist_layers; l++) sum += a->hist[f][l];
        top = sum > top ? sum : top;
    }
    ui_text("GPU ms per pass, last %u frames (top %.2f ms):", a->hist_n, top);
    int nc = (int)(sizeof bar_colours / sizeof bar_colours[0]);
    ui_stacked_bars(&a->hist[0][0], (int)a->hist_n, (int)a->hist_layers, VX_PASS_KIND_COUNT + 1, bar_colours, nc, top, 60);
    for (uint32_t l = 0; l < a->hist_layers; l++) {
        char t[96];
        snprintf(t, sizeof t, "%s %.2f ms", a->hist_names[l], a->hist[a->hist_n - 1][l]);
        ui_legend(bar_colours[l % (uint32_t)nc], t);
    }
}

/* One probe map as display texels, at most 64 a side (every k-th texel):
 * kind 0 radiance (x / (1 + x), then a square root), 1 distance (near
 * bright; misses dark blue), 2 normal (n / 2 + 1/2; black where the ray
 * missed), 3 irradiance (as radiance, divided by pi). */
static int probe_map_texels(const vx_probe_set* ps, uint32_t p, int kind, uint32_t* out, int* side) {
    uint32_t n = kind == 3 ? VX_PROBE_IRR_RES + 2 : ps->res + 2, k = (n + 63) / 64, m = n / k;
    size_t q = p - ps->first, nn = (size_t)n * n;
    uint32_t dmax = 1;
    if (kind == 1)
        for (size_t i = 0; i < nn; i++) {
            uint16_t c = ps->distance[q * nn + i];
            if (c != VX_PROBE_DIST_MISS && c > dmax) dmax = c;
        }
    for (uint32_t y = 0; y < m; y++)
        for (uint32_t x = 0; x < m; x++) {
            size_t t = (size_t)(y * k) * n + x * k;
            float c[3] = {0, 0, 0};
            if (kind == 0 || kind == 3) {
                const uint16_t* h = kind == 0 ? ps->radiance + (q * nn + t) * 3 : ps->irradiance + (q * nn + t) * 3;
                for (int j = 0; j < 3; j++) {
                    float v = vx_probe_half_to_float(h[j]) / (kind == 3 ? 3.14159265f : 1.0f);
                    v = v > 0 ? v / (1 + v) : 0;
                    c[j] = sqrtf(v);
                }
            } else if (kind == 1) {
                uint16_t d = ps->distance[q * nn + t];
                if (d == VX_PROBE_DIST_MISS) c[2] = 0.35f;
                else c[0] = c[1] = c[2] = 1.0f - 0.85f * (float)d / (float)dmax;
            } else {
                if (ps->distance[q * nn + t] != VX_PROBE_DIST_MISS) {
                    double d[3];
                    vx_probe_oct_unpack16(ps->normal[q * nn + t], d);
                    for (int j = 0; j < 3; j++) c[j] = (float)(0.5 * d[j] + 0.5);
                }
            }
            uint32_t v = 0;
            for (int j = 0; j < 3; j++) {
                float f = c[j] < 0 ? 0 : c[j] > 1 ? 1 : c[j];
                v |= (uint32_t)lrintf(f * 255) << (8 * j);
            }
            out[y * m + x] = v;
        }
    *side = (int)m;
    return (int)m;
}

static void probe_maps(app* a);

static void probe_panel(app* a) {
    const vx_probe_set* ps = sv_probe_shown(a);
    if (!ps) ui_text("no probes: bake them here, or load a .probes file");
    else
        ui_text("%u probes, %ux%ux%u, res %u, %u spp; %s", ps->probe_count, ps->grid[0], ps->grid[1], ps->grid[2],
                ps->res, ps->spp, a->bake.active ? "baking" : a->probes_path);
    ui_checkbox("show grid", &a->probe_grid);
    if (a->bake.active) {
        char t[96];
        snprintf(t, sizeof t, "%u / %u probes, %.1f s", a->bake.ps.count, a->bake.ps.probe_count,
                 vx_time_now() - a->bake.t0);
        ui_progress(a->bake.ps.probe_count ? (float)a->bake.ps.count / (float)a->bake.ps.probe_count : 0, t);
        if (ui_button("cancel")) sv_probe_bake_cancel(a, "asked");
    }
    probe_maps(a);
    if (!a->bake.active && ui_collapsing("Bake", !ps)) {
        static const char* const res_items[4] = {"16", "32", "64", "128"};
        ui_combo("res", &a->bake_res_i, res_items, 4);
        ui_slider_int("spp", &a->bake_spp, 1, 64);
        ui_slider_int("per axis (0: spacing)", &a->bake_grid, 0, 16);
        if (ui_button("bake (GPU, in steps)")) {
            uint32_t g = (uint32_t)(a->bake_grid > 0 ? a->bake_grid : 0), grid[3] = {g, g, g};
            sv_probe_bake(a, 16u << (a->bake_res_i & 3), (uint32_t)(a->bake_spp > 0 ? a->bake_spp : 1), grid);
        }
    }
}

/* The selected probe: where it is, and its maps as images. */
static void probe_maps(app* a) {
    const vx_probe_set* ps = sv_probe_shown(a);
    if (!ps || !ps->probe_count) return;
    ui_separator();
    int sel = (int)(a->probe_sel < ps->probe_count ? a->probe_sel : 0);
    if (ui_slider_int("probe", &sel, 0, (int)ps->probe_count - 1)) a->probe_sel = (uint32_t)sel;
    const vx_probe* pr = &ps->probes[sel];
    static const char* const states[3] = {"at its grid point", "moved out of a voxel", "disabled"};
    ui_text("at %.1f %.1f %.1f, %s", pr->pos[0], pr->pos[1], pr->pos[2], states[pr->state < 3 ? pr->state : 2]);
    if ((uint32_t)sel < ps->first || (uint32_t)sel >= ps->first + ps->count) {
        ui_text("(not baked yet)");
        return;
    }
    uint32_t texels[64 * 64]; /* 16 KB on the stack: at most 64 a side */
    static const char* const names[4] = {"radiance", "distance", "normal", "irradiance"};
    for (int kind = 0; kind < 4; kind++) {
        int side;
        probe_map_texels(ps, (uint32_t)sel, kind, texels, &side);
        float scale = side > 0 ? (float)(int)(72 / side > 0 ? 72 / side : 1) : 1;
        if (kind & 1) ui_same_line();
        ui_image_rgba(texels, side, side, scale);
    }
    ui_text("%s, %s | %s, %s", names[0], names[1], names[2], names[3]);
}

static void anim_panel(app* a) {
    uint32_t nf = vx_svo_scene_frames(&a->scene);
    ui_text("frame %u of %u (0..%u)", a->anim_frame, nf, nf - 1);
    if (ui_button("|<")) sv_set_frame(a, 0);
    ui_same_line();
    if (ui_button("<")) sv_set_frame(a, (a->anim_frame + nf - 1) % nf);
    ui_same_line();
    if (ui_button(a->playing ? "pause" : "play")) sv_play(a, !a->playing);
    ui_same_line();
    if (ui_button(">")) sv_set_frame(a, (a->anim_frame + 1) % nf);
    ui_same_line();
    if (ui_button(">|")) sv_set_frame(a, nf - 1);
    int f = (int)a->anim_frame;
    if (ui_slider_int("scrub", &f, 0, (int)nf - 1)) sv_set_frame(a, (uint32_t)f);
    double fps = a->fps;
    if (ui_drag_double("frames/s", &fps, 0.1, 0.1, 240)) sv_set_fps(a, fps);
    ui_text("file rate %g, frame switch %.2f ms (no upload)", a->scene.frame_rate, a->switch_ms);
}

void sv_panels_draw(app* a, vf_canvas* cv) {
    if (!a->ui) return;
    double now = glfwGetTime(), dt = a->ui_time > 0 ? now - a->ui_time : 1.0 / 60;
    a->ui_time = now;
    ui_frame_begin(a->ui, cv->width, cv->height, dt);
    float W = (float)cv->width, H = (float)cv->height, lw = 300, rw = 330;
    if (ui_window_begin("Outliner", 0, 0, lw, H * 0.45f)) outliner(a);
    ui_window_end();
    if (ui_window_begin("Properties", 0, H * 0.45f, lw, H * 0.55f)) {
        if (a->sel != NO_SEL && a->sel < a->scene.instance_count) instance_props(a);
        else ui_text("select an instance (click, or the outliner)");
        if (a->sel_light != NO_SEL && a->sel_light < a->scene.light_count) {
            ui_separator();
            light_props(a);
        }
        ui_separator();
        if (ui_collapsing("Voxel editing", a->voxel_mode)) brush_panel(a);
        if (ui_collapsing("Material", false)) material_props(a);
        if (ui_collapsing("Sky", false)) sky_props(a);
    }
    ui_window_end();
    if (ui_window_begin("Render", W - rw, 0, rw, H * 0.3f)) render_panel(a);
    ui_window_end();
    if (ui_window_begin("Statistics", W - rw, H * 0.3f, rw, H * 0.3f)) stats_panel(a);
    ui_window_end();
    bool anim = vx_svo_scene_frames(&a->scene) > 1;
    if (anim) {
        if (ui_window_begin("Animation", W - rw, H * 0.6f, rw, H * 0.15f)) anim_panel(a);
        ui_window_end();
    }
    if (ui_window_begin("Probes", W - rw, H * (anim ? 0.75f : 0.6f), rw, H * (anim ? 0.25f : 0.4f))) probe_panel(a);
    ui_window_end();
    ui_frame_end(a->ui, a->panels_gpu_now ? NULL : cv); /* on the GPU: the draw lists kept for ui_gpu_record */
}
