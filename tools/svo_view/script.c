/* tools/svo_view/script.c - svo_view's script (--script FILE): the file read
 * into lines, one command run at a time (script.h; docs/VIEWER.md lists the
 * commands). */
#include <GLFW/glfw3.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tools/common/tool.h"
#include "tools/svo_view/app.h"
#include "tools/svo_view/camera.h"
#include "tools/svo_view/panels.h"
#include "tools/svo_view/script.h"

/* ---- scripts ---------------------------------------------------------------------------- */

static int parse_axis(const char* s) {
    if (!s || s[1]) return -1;
    return s[0] == 'x' || s[0] == 'X' ? 0 : s[0] == 'y' || s[0] == 'Y' ? 1 : s[0] == 'z' || s[0] == 'Z' ? 2 : -1;
}

static bool parse_doubles(char** tok, int n, double* v) {
    for (int i = 0; i < n; i++)
        if (!tok[i] || !vx_tool_parse_double(tok[i], &v[i]) || !isfinite(v[i])) return false;
    return true;
}

/* Runs one script line; false (with a message) on a malformed command. */
bool sv_script_command(app* a, char* line, uint32_t lineno) {
    a->ui_dirty = true; /* the panels may show what the command changed */
    char* tok[8] = {0};
    int nt = 0;
    for (char* t = strtok(line, " \t\r"); t && nt < 8; t = strtok(NULL, " \t\r")) tok[nt++] = t;
    if (!nt || tok[0][0] == '#') return true;
    const char* c = tok[0];
    double v[6];
#define BAD()                                                                                           \
    do {                                                                                                \
        fprintf(stderr, "%s: %s:%u: bad command '%s'\n", vx_tool_name, a->o.script, lineno, c);          \
        return false;                                                                                   \
    } while (0)
    if (!strcmp(c, "quit")) a->quit = true;
    else if (!strcmp(c, "camera") && nt == 2 && !strcmp(tok[1], "default")) sv_camera_default(a);
    else if (!strcmp(c, "camera")) {
        if (nt != 7 || !parse_doubles(tok + 1, 6, v)) BAD();
        double d[3] = {v[0] - v[3], v[1] - v[4], v[2] - v[5]};
        double l = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        if (!(l > 0)) BAD();
        memcpy(a->eye, v, sizeof a->eye);
        a->yaw = atan2(-d[1], -d[0]);
        a->pitch = asin(-d[2] / l);
        memcpy(a->orbit_center, v + 3, sizeof a->orbit_center);
        a->orbit_dist = l;
        a->cam_default = false;
    } else if (!strcmp(c, "fly")) {
        if (nt != 4 || !parse_doubles(tok + 1, 3, v)) BAD();
        double f[3], r[3] = {sin(a->yaw), -cos(a->yaw), 0};
        sv_cam_fwd(a, f);
        for (int k = 0; k < 3; k++) a->eye[k] += v[0] * f[k] + v[1] * r[k] + (k == 2 ? v[2] : 0);
        a->cam_default = false;
    } else if (!strcmp(c, "look")) {
        if (nt != 3 || !parse_doubles(tok + 1, 2, v)) BAD();
        a->yaw += v[0] * SV_PI / 180, a->pitch = fmax(-1.55, fmin(1.55, a->pitch + v[1] * SV_PI / 180));
        a->cam_default = false;
    } else if (!strcmp(c, "orbit")) {
        if (nt != 2) BAD();
        a->orbit = !strcmp(tok[1], "on");
    } else if (!strcmp(c, "mode")) {
        if (nt == 2 && !strcmp(tok[1], "gi")) sv_set_probe_mode(a, VX_PROBE_RENDER_GI);
        else if (nt == 2 && !strcmp(tok[1], "lightfield")) sv_set_probe_mode(a, VX_PROBE_RENDER_LIGHTFIELD);
        else if (nt != 2 || !vx_render_mode_parse(tok[1], &a->mode)) BAD();
        else a->gi = false;
    } else if (!strcmp(c, "passes") && nt <= 2) {
        if (!sv_set_passes(a, nt == 2 ? tok[1] : "")) return false;
    } else if (!strcmp(c, "probes") && nt >= 2 && !strcmp(tok[1], "bake")) {
        uint32_t res, spp, g[3] = {0, 0, 0};
        if ((nt != 4 && nt != 7) || !vx_tool_parse_u32(tok[2], &res) || !vx_tool_parse_u32(tok[3], &spp) ||
            (nt == 7 && (!vx_tool_parse_u32(tok[4], &g[0]) || !vx_tool_parse_u32(tok[5], &g[1]) ||
                         !vx_tool_parse_u32(tok[6], &g[2]))))
            BAD();
        sv_probe_bake(a, res, spp, g);
        if (!a->bake.active) return false; /* refused: the message says why */
    } else if (!strcmp(c, "probes") && nt == 3 && !strcmp(tok[1], "grid")) {
        if (strcmp(tok[2], "on") && strcmp(tok[2], "off")) BAD();
        a->probe_grid = !strcmp(tok[2], "on");
    } else if (!strcmp(c, "probes") && nt == 3 && !strcmp(tok[1], "show")) {
        uint32_t n;
        const vx_probe_set* ps = sv_probe_shown(a);
        if (!vx_tool_parse_u32(tok[2], &n)) BAD();
        if (!ps || n >= ps->probe_count) {
            fprintf(stderr, "%s: %s:%u: no probe %u (%u probes)\n", vx_tool_name, a->o.script, lineno, n,
                    ps ? ps->probe_count : 0);
            return false;
        }
        a->probe_sel = n;
    } else if (!strcmp(c, "probes") && nt == 3 && !strcmp(tok[1], "save")) {
        if (!sv_probe_save(a, tok[2])) return false;
    } else if (!strcmp(c, "probes") && nt == 2 && !strcmp(tok[1], "cancel")) {
        sv_probe_bake_cancel(a, "asked");
    } else if (!strcmp(c, "probes") && nt == 2) {
        sv_probes(a, tok[1]);
    } else if (!strcmp(c, "select")) {
        uint32_t n;
        if (nt == 2 && !strcmp(tok[1], "none")) a->sel = NO_SEL;
        else if (nt == 2 && vx_tool_parse_u32(tok[1], &n)) {
            if (n >= a->scene.instance_count) {
                fprintf(stderr, "%s: %s:%u: no instance %u (the scene has %u)\n", vx_tool_name, a->o.script, lineno, n,
                        a->scene.instance_count);
                return false;
            }
            a->sel = n;
        } else BAD();
    } else if (!strcmp(c, "pick")) {
        if (nt != 3 || !parse_doubles(tok + 1, 2, v)) BAD();
        a->pick_x = v[0], a->pick_y = v[1], a->pick_pending = true, a->pick_op = -1;
    } else if (!strcmp(c, "frame")) sv_frame_camera(a);
    else if (!strcmp(c, "move")) {
        if (nt != 4 || !parse_doubles(tok + 1, 3, v)) BAD();
        int32_t d[3];
        for (int k = 0; k < 3; k++) {
            if (v[k] != floor(v[k]) || fabs(v[k]) > 1e9) BAD();
            d[k] = (int32_t)v[k];
        }
        if (!sv_edit_begin(a, true)) return false;
        ved_move(&a->scene, a->sel, d);
        sv_edit_end(a, "move");
    } else if (!strcmp(c, "rotate") || !strcmp(c, "mirror")) {
        int ax = parse_axis(tok[1]);
        double turns = 1;
        if (ax < 0 || nt > 3 || (nt == 3 && (!parse_doubles(tok + 2, 1, &turns) || turns != floor(turns)))) BAD();
        if (a->sel == NO_SEL) {
            sv_message(a, true, "%s:%u: nothing selected", a->o.script, lineno);
            return false;
        }
        if (c[0] == 'r') sv_rotate(a, ax, (int)fmod(turns, 4));
        else sv_mirror(a, ax);
    } else if (!strcmp(c, "duplicate") || !strcmp(c, "delete") || !strcmp(c, "hide")) {
        if (a->sel == NO_SEL) {
            sv_message(a, true, "%s:%u: nothing selected", a->o.script, lineno);
            return false;
        }
        if (c[1] == 'u') sv_duplicate(a);
        else if (c[0] == 'd') sv_delete(a);
        else sv_hide(a, true);
    } else if (!strcmp(c, "show")) sv_hide(a, false);
    else if (!strcmp(c, "layer")) {
        uint32_t l;
        if (nt != 3 || !vx_tool_parse_u32(tok[1], &l) || (strcmp(tok[2], "hide") && strcmp(tok[2], "show"))) BAD();
        if (!sv_layer(a, l, !strcmp(tok[2], "hide"))) return false;
    } else if (!strcmp(c, "add") && nt == 2) sv_add(a, tok[1]); /* a file that does not read: a message, the run goes on */
    else if (!strcmp(c, "open") && nt == 2) sv_open(a, tok[1]);
    else if (!strcmp(c, "undo")) sv_undo(a, false);
    else if (!strcmp(c, "redo")) sv_undo(a, true);
    else if (!strcmp(c, "save") && nt == 2) {
        if (!sv_save(a, tok[1])) return false; /* a headless run must not end 0 without its file */
    } else if (!strcmp(c, "export") && (nt == 2 || (nt == 3 && !strcmp(tok[2], "quantize")))) {
        if (!sv_export(a, tok[1], nt == 3)) return false;
    }
    else if (!strcmp(c, "screenshot") && nt == 2) {
        snprintf(a->shot_buf, sizeof a->shot_buf, "%s", tok[1]);
        a->shot = a->shot_buf;
    } else if (!strcmp(c, "wait") && nt == 2) {
        if (!vx_tool_parse_u32(tok[1], &a->wait)) BAD();
    } else if (!strcmp(c, "anim")) {
        uint32_t nf = vx_svo_scene_frames(&a->scene), n;
        if (nt == 3 && !strcmp(tok[1], "frame") && vx_tool_parse_u32(tok[2], &n)) {
            if (n >= nf) {
                fprintf(stderr, "%s: %s:%u: no frame %u (the scene has %u)\n", vx_tool_name, a->o.script, lineno, n, nf);
                return false;
            }
            sv_set_frame(a, n);
        } else if ((nt == 2 || nt == 3) && !strcmp(tok[1], "step")) {
            double k = 1;
            if (nt == 3 && (!parse_doubles(tok + 2, 1, &k) || k != floor(k) || fabs(k) > 1e9)) BAD();
            int64_t f = ((int64_t)a->anim_frame + (int64_t)k) % (int64_t)nf;
            sv_set_frame(a, (uint32_t)(f < 0 ? f + nf : f));
        } else if (nt == 2 && !strcmp(tok[1], "play")) sv_play(a, true);
        else if (nt == 2 && !strcmp(tok[1], "pause")) sv_play(a, false);
        else if (nt == 3 && !strcmp(tok[1], "fps") && parse_doubles(tok + 2, 1, v) && v[0] > 0 && v[0] <= 1000)
            sv_set_fps(a, v[0]);
        else if (nt == 3 && !strcmp(tok[1], "tick") && parse_doubles(tok + 2, 1, v) && v[0] >= 0) sv_play_step(a, v[0]);
        else BAD();
        if (!strcmp(tok[1], "frame") || !strcmp(tok[1], "step") || !strcmp(tok[1], "tick"))
            printf("%s: frame %u of %u\n", vx_tool_name, a->anim_frame, nf);
    } else if (!strcmp(c, "exposure")) {
        if (nt != 2 || !parse_doubles(tok + 1, 1, v) || fabs(v[0]) > 64) BAD();
        a->exposure = v[0];
    } else if (!strcmp(c, "rename") || !strcmp(c, "setlayer") || !strcmp(c, "setmodel")) {
        uint32_t n;
        if (nt != 2) BAD();
        if (a->sel == NO_SEL) {
            sv_message(a, true, "%s:%u: nothing selected", a->o.script, lineno);
            return false;
        }
        if (c[0] == 'r') sv_rename(a, tok[1]);
        else if (!strcmp(c, "setlayer") && !strcmp(tok[1], "none")) {
            if (!sv_set_layer(a, UINT32_MAX)) return false;
        } else if (!vx_tool_parse_u32(tok[1], &n)) BAD();
        else if (!(c[3] == 'l' ? sv_set_layer(a, n) : sv_set_model(a, n))) return false;
    } else if (!strcmp(c, "vsync")) { /* the render panel's checkbox, key V */
        if (nt != 2 || (strcmp(tok[1], "on") && strcmp(tok[1], "off"))) BAD();
        vp_set_vsync(a->p, !strcmp(tok[1], "on"));
    } else if (!strcmp(c, "overlay")) {
        if (nt != 2 || (strcmp(tok[1], "on") && strcmp(tok[1], "off"))) BAD();
        a->overlay = !strcmp(tok[1], "on");
    } else if (!strcmp(c, "panels")) {
        if (nt != 2 || (strcmp(tok[1], "on") && strcmp(tok[1], "off"))) BAD();
        a->panels = !strcmp(tok[1], "on");
        if (a->panels && !a->ui) sv_message(a, true, "no panels: %s", sv_panels_built() ? "none made" : "built without Dear ImGui");
    } else if (!strcmp(c, "grab") && nt == 2) {
        snprintf(a->grab_buf, sizeof a->grab_buf, "%s", tok[1]);
        a->grab = a->grab_buf;
    } else if (!strcmp(c, "click")) {
        if (nt != 3 || !parse_doubles(tok + 1, 2, v)) BAD();
        a->click_x = v[0], a->click_y = v[1], a->click_state = 2;
    } else if (!strcmp(c, "ui")) { /* input through the panels' widgets, as a user's mouse and keys give it */
        if (nt < 3 || !a->ui) BAD();
        char text[128] = "";
        for (int k = 2; k < nt; k++) /* the rest of the line, single-spaced: a widget's label or the text to type */
            snprintf(text + strlen(text), sizeof text - strlen(text), "%s%s", k > 2 ? " " : "", tok[k]);
        if (!strcmp(tok[1], "click") || !strcmp(tok[1], "ctrl-click")) {
            snprintf(a->ui_label, sizeof a->ui_label, "%s", text);
            sv_panels_find(a, a->ui_label);
            a->ui_finding = 4; /* frames to wait for the panels to draw it */
            a->ui_ctrl = !strcmp(tok[1], "ctrl-click");
        } else if (!strcmp(tok[1], "type")) {
            for (const char* t = text; *t; t++) sv_panels_char(a, (unsigned char)*t);
        } else if (!strcmp(tok[1], "key") && nt == 3) {
            static const struct { const char* name; int key; } keys[] = {
                {"enter", GLFW_KEY_ENTER}, {"escape", GLFW_KEY_ESCAPE}, {"tab", GLFW_KEY_TAB}, {"backspace", GLFW_KEY_BACKSPACE}};
            for (size_t k = 0; k < sizeof keys / sizeof keys[0]; k++)
                if (!strcmp(tok[2], keys[k].name)) a->ui_key_up = keys[k].key;
            if (!a->ui_key_up) BAD();
            sv_panels_key(a, a->ui_key_up, true, 0); /* released after a frame */
        } else BAD();
    } else if (!strcmp(c, "voxel") || !strcmp(c, "vclick")) {
        vvx_op op = VVX_OP_COUNT;
        for (int k = 0; k < VVX_OP_COUNT && nt >= 2; k++)
            if (!strcmp(tok[1], vvx_op_name((vvx_op)k))) op = (vvx_op)k;
        bool cells = c[0] == 'v' && c[1] == 'o';
        static const char* const faces[6] = {"-x", "+x", "-y", "+y", "-z", "+z"};
        int face = -1;
        for (int k = 0; k < 6 && cells && nt == 6; k++)
            if (!strcmp(tok[5], faces[k])) face = k;
        if (op == VVX_OP_COUNT || (nt != (cells ? 5 : 4) && !(face >= 0 && nt == 6)) ||
            !parse_doubles(tok + 2, cells ? 3 : 2, v))
            BAD();
        if (face >= 0) a->brush.face = (uint8_t)face;
        if (cells) {
            int64_t p[3];
            for (int k = 0; k < 3; k++) {
                if (v[k] != floor(v[k]) || fabs(v[k]) > 1e8) BAD();
                p[k] = (int64_t)v[k];
            }
            if (!sv_voxels(a, op, p)) return false;
        } else {
            a->pick_x = v[0], a->pick_y = v[1], a->pick_pending = true, a->pick_op = (int)op;
        }
    } else if (!strcmp(c, "brush")) {
        vvx_shape sh;
        if (nt < 2 || nt > 3 || !vvx_shape_parse(tok[1], &sh) || (nt == 3 && !parse_doubles(tok + 2, 1, v)) ||
            (nt == 3 && (v[0] != floor(v[0]) || v[0] < 0 || v[0] > VVX_MAX_RADIUS)))
            BAD();
        a->brush.shape = sh;
        if (nt == 3) a->brush.radius = (uint32_t)v[0];
    } else if (!strcmp(c, "color")) {
        uint32_t idx;
        unsigned rgb;
        char extra;
        if (nt == 2 && tok[1][0] == '#' && strlen(tok[1]) == 7 && sscanf(tok[1] + 1, "%6x%c", &rgb, &extra) == 1) {
            if (!sv_brush_rgba(a, 0xFF000000u | ((rgb >> 16) & 0xFF) | (rgb & 0xFF00) | ((rgb & 0xFF) << 16))) return false;
        } else if (nt == 2 && vx_tool_parse_u32(tok[1], &idx) && idx >= 1 && idx <= 255) {
            if (!sv_brush_palette(a, idx)) return false;
        } else BAD();
    } else if (!strcmp(c, "light")) {
        uint32_t l;
        if (nt < 4 || !vx_tool_parse_u32(tok[1], &l)) BAD();
        if (l >= a->scene.light_count) {
            fprintf(stderr, "%s: %s:%u: no light %u (the scene has %u)\n", vx_tool_name, a->o.script, lineno, l,
                    a->scene.light_count);
            return false;
        }
        vx_light t = a->scene.lights[l];
        const char* f = tok[2];
        if (!strcmp(f, "color") && nt == 6 && parse_doubles(tok + 3, 3, v)) memcpy(t.color, v, sizeof t.color);
        else if (!strcmp(f, "position") && nt == 6 && parse_doubles(tok + 3, 3, v)) memcpy(t.position, v, sizeof t.position);
        else if (!strcmp(f, "intensity") && nt == 4 && parse_doubles(tok + 3, 1, v)) t.intensity = v[0];
        else if (!strcmp(f, "range") && nt == 4 && parse_doubles(tok + 3, 1, v)) t.range = v[0];
        else BAD();
        vx_error lerr = {0};
        if (vx_light_validate(&t, l, &lerr)) {
            fprintf(stderr, "%s: %s:%u: %s\n", vx_tool_name, a->o.script, lineno, lerr.msg);
            return false;
        }
        if (!sv_set_light(a, l, &t, false)) return false; /* an undo step of its own */
    } else if (!strcmp(c, "sky")) { /* svo_render --sky's text: an undo step of its own; alone: prints the sky */
        if (nt == 1) {
            char t[VX_SKY_SPEC_MAX];
            sv_sky_text(a, t, sizeof t);
            printf("%s: sky %s\n", vx_tool_name, t);
        } else {
            char spec[VX_SKY_SPEC_MAX + 64] = "";
            for (int k = 1; k < nt; k++) /* the rest of the line, single-spaced (a map's path may hold spaces) */
                snprintf(spec + strlen(spec), sizeof spec - strlen(spec), "%s%s", k > 1 ? " " : "", tok[k]);
            if (!sv_set_sky_text(a, spec)) return false;
        }
    } else if (!strcmp(c, "material")) {
        uint32_t id;
        if (nt != 4 || !vx_tool_parse_u32(tok[1], &id) || id > 65535) BAD();
        if (!sv_set_material(a, id, tok[2], tok[3], false)) return false; /* an undo step of its own */
    } else if (!strcmp(c, "gi")) {
        if (nt != 3) BAD();
        if (!sv_set_gi_option(a, tok[1], tok[2])) return false;
    } else if (!strcmp(c, "stats") && nt == 1) {
        vx_render_scene_stats st;
        vx_render_scene_get_stats(a->rs, &st);
        uint64_t w, rec;
        sv_uploads(a, &w, &rec);
        printf("%s: stats: render scenes made %u, node words uploaded %llu, records uploaded %llu; this scene: "
               "%llu words, %u model updates, %u instance table rebuilds (%u in place)\n",
               vx_tool_name, a->scenes_made, (unsigned long long)w, (unsigned long long)rec,
               (unsigned long long)st.node_words_uploaded, st.model_updates, st.instance_rebuilds,
               st.instance_updates_in_place);
    } else if (!strcmp(c, "echo")) {
        for (int i = 1; i < nt; i++) printf("%s%s", tok[i], i + 1 < nt ? " " : "\n");
    } else BAD();
#undef BAD
    return true;
}

int sv_script_load(app* a) {
    uint8_t* data = NULL;
    size_t size = 0;
    vx_error err = {0};
    if (vx_file_read(a->o.script, NULL, 1u << 20, &data, &size, &err)) return vx_tool_error(a->o.script, &err);
    uint32_t n = 1;
    for (size_t i = 0; i < size; i++) n += data[i] == '\n';
    a->lines = calloc(n, sizeof *a->lines);
    char* text = malloc(size + 1);
    if (!a->lines || !text) {
        free(text);
        vx_free(NULL, data);
        return vx_tool_errorf("out of memory");
    }
    memcpy(text, data, size);
    text[size] = 0;
    vx_free(NULL, data);
    /* the lines point into one block, owned through lines[0] */
    char* s = text;
    for (uint32_t i = 0; i < n; i++) {
        a->lines[i] = s;
        char* nl = strchr(s, '\n');
        if (nl) *nl = 0, s = nl + 1;
        else s += strlen(s);
    }
    a->line_count = n;
    return 0;
}
