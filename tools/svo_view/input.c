/* tools/svo_view/input.c - keys, mouse, scroll, dropped files and the
 * camera's flight from held keys (input.h). */
#include <GLFW/glfw3.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "tools/svo_view/app.h"
#include "tools/svo_view/camera.h"
#include "tools/svo_view/input.h"
#include "tools/svo_view/panels.h"

/* ---- input ---------------------------------------------------------------------------- */

static int axis_key(int key) { return key == GLFW_KEY_X ? 0 : key == GLFW_KEY_Y ? 1 : key == GLFW_KEY_Z ? 2 : -1; }

static void grab_end(app* a, bool keep) {
    if (!keep) {
        ved_undo(&a->ed, NULL); /* back to the snapshot taken at G */
        sv_update_instances(a);
    }
    a->op = 0;
}

static void key_cb(GLFWwindow* win, int key, int sc, int action, int mods) {
    (void)sc;
    app* a = glfwGetWindowUserPointer(win);
    a->ui_dirty = true;
    sv_panels_key(a, key, action != GLFW_RELEASE, mods);
    if (action == GLFW_RELEASE || sv_panels_wants_keyboard(a)) return;
    bool ctrl = mods & GLFW_MOD_CONTROL, shift = mods & GLFW_MOD_SHIFT, alt = mods & GLFW_MOD_ALT;
    if (a->op) {
        int ax = axis_key(key);
        if (a->op == 'l' && key >= GLFW_KEY_0 && key <= GLFW_KEY_9) {
            a->op = 0;
            sv_layer(a, (uint32_t)(key - GLFW_KEY_0), -1);
            return;
        }
        if (a->op == 'g') {
            if (ax >= 0 && a->op_axis < 0) {
                a->op_axis = ax;
                a->grab_px = 0;
                return;
            }
            if (a->op_axis >= 0 && (key == GLFW_KEY_RIGHT || key == GLFW_KEY_UP || key == GLFW_KEY_LEFT ||
                                    key == GLFW_KEY_DOWN || key == GLFW_KEY_PAGE_UP || key == GLFW_KEY_PAGE_DOWN)) {
                int32_t n = (key == GLFW_KEY_RIGHT || key == GLFW_KEY_UP || key == GLFW_KEY_PAGE_UP) ? 1 : -1;
                if (shift) n *= 10;
                sv_edit_move(a, a->op_axis, n);
                a->grab_moved += n;
                sv_update_instances(a);
                return;
            }
            if (key == GLFW_KEY_ENTER || key == GLFW_KEY_KP_ENTER) return grab_end(a, true);
            if (key == GLFW_KEY_ESCAPE) return grab_end(a, false);
            return;
        }
        if (ax >= 0 && a->op == 'r') sv_rotate(a, ax, shift ? -1 : 1);
        else if (ax >= 0 && a->op == 'm') sv_mirror(a, ax);
        a->op = 0;
        return;
    }
    if (ctrl) {
        if (key == GLFW_KEY_Z) sv_undo(a, shift);
        else if (key == GLFW_KEY_Y) sv_undo(a, true);
        else if (key == GLFW_KEY_S) {
            char path[1024];
            if (a->o.save) snprintf(path, sizeof path, "%s", a->o.save);
            else {
                const char* dot = strrchr(a->o.in, '.');
                int n = dot ? (int)(dot - a->o.in) : (int)strlen(a->o.in);
                snprintf(path, sizeof path, "%.*s.edited.svo", n, a->o.in);
            }
            sv_save(a, path);
        } else if (key == GLFW_KEY_E) {
            sv_export_default(a);
        } else if (key == GLFW_KEY_Q) a->quit = true;
        return;
    }
    if (key >= GLFW_KEY_1 && key <= GLFW_KEY_6) a->mode = (vx_render_mode)(key - GLFW_KEY_1), a->gi = false;
    else if (key == GLFW_KEY_7) sv_set_probe_mode(a, VX_PROBE_RENDER_GI);
    else if (key == GLFW_KEY_8) sv_set_probe_mode(a, VX_PROBE_RENDER_LIGHTFIELD);
    else if (key == GLFW_KEY_9) {
        static const char* const presets[] = {VX_PASS_LIST_DEFAULT, "gbuffer,direct,ao", "gbuffer,direct,ao,aa,tonemap",
                                              "gbuffer,dof,direct,ao,aa,tonemap", "gbuffer,direct,gi=cones,aa,tonemap",
                                              "gbuffer,direct,gi=photons,aa,tonemap"};
        char cur[160];
        vx_pass_list_format(&a->passes, cur, sizeof cur);
        size_t k = 0, n = sizeof presets / sizeof presets[0];
        while (k < n && strcmp(cur, presets[k])) k++;
        sv_set_passes(a, presets[(k + 1) % n]);
        a->mode = VX_RENDER_COLOR, a->gi = false;
    }
    else if (key == GLFW_KEY_V) vp_set_vsync(a->p, !vp_vsync(a->p));
    else if (key == GLFW_KEY_TAB && a->ui) a->panels = !a->panels;
    else if (key == GLFW_KEY_TAB) a->overlay = !a->overlay;
    else if (key == GLFW_KEY_SPACE) sv_play(a, !a->playing);
    else if (key == GLFW_KEY_COMMA || key == GLFW_KEY_PERIOD) {
        uint32_t nf = vx_svo_scene_frames(&a->scene);
        sv_set_frame(a, (a->anim_frame + (key == GLFW_KEY_PERIOD ? 1 : nf - 1)) % nf);
    } else if (key == GLFW_KEY_B) {
        a->voxel_mode = !a->voxel_mode;
        sv_message(a, false, "voxel mode %s (click: add, Shift: remove, Alt: paint; brush %s %u)",
                   a->voxel_mode ? "on" : "off", vvx_shape_name(a->brush.shape), a->brush.radius);
    }
    else if (key == GLFW_KEY_F) sv_frame_camera(a);
    else if (key == GLFW_KEY_O) {
        a->orbit = !a->orbit;
        if (a->orbit) {
            double f[3];
            sv_cam_fwd(a, f);
            if (a->sel != NO_SEL) {
                double lo[3], hi[3];
                sv_world_box(a, a->sel, lo, hi);
                for (int k = 0; k < 3; k++) a->orbit_center[k] = 0.5 * (lo[k] + hi[k]);
            }
            double v[3] = {a->orbit_center[0] - a->eye[0], a->orbit_center[1] - a->eye[1], a->orbit_center[2] - a->eye[2]};
            a->orbit_dist = fmax(1e-3, sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]));
            a->yaw = atan2(v[1], v[0]);
            a->pitch = asin(fmax(-1, fmin(1, v[2] / a->orbit_dist)));
        }
    } else if (key == GLFW_KEY_P) {
        snprintf(a->shot_buf, sizeof a->shot_buf, "svo_view_%03u.png", a->shot_counter++);
        a->shot = a->shot_buf;
    } else if (key == GLFW_KEY_G && a->sel != NO_SEL) {
        if (sv_edit_begin(a, true)) a->op = 'g', a->op_axis = -1, a->grab_moved = 0;
    } else if ((key == GLFW_KEY_R || key == GLFW_KEY_M) && a->sel != NO_SEL) a->op = key == GLFW_KEY_R ? 'r' : 'm';
    else if (key == GLFW_KEY_L) a->op = 'l';
    else if (key == GLFW_KEY_D && shift) sv_duplicate(a);
    else if (key == GLFW_KEY_DELETE || key == GLFW_KEY_BACKSPACE) sv_delete(a);
    else if (key == GLFW_KEY_H) sv_hide(a, !alt);
    else if (key == GLFW_KEY_ESCAPE) a->sel = NO_SEL;
}

static void mouse_cb(GLFWwindow* win, int button, int action, int mods) {
    ((app*)glfwGetWindowUserPointer(win))->ui_dirty = true;
    app* a = glfwGetWindowUserPointer(win);
    sv_panels_button(a, button, action == GLFW_PRESS);
    if (sv_panels_wants_mouse(a) && action == GLFW_PRESS) return;
    if (button == GLFW_MOUSE_BUTTON_RIGHT) a->rmb = action == GLFW_PRESS;
    if (button != GLFW_MOUSE_BUTTON_LEFT) return;
    a->lmb = action == GLFW_PRESS;
    if (action != GLFW_PRESS) return;
    if (a->op == 'g') return grab_end(a, true); /* a click confirms a move */
    /* the cursor is in screen coordinates; the frame in framebuffer pixels */
    int ww, wh;
    glfwGetWindowSize(win, &ww, &wh);
    uint32_t fw, fh;
    if (a->o.width) fw = a->o.width, fh = a->o.height;
    else vp_frame_size(a->p, &fw, &fh);
    if (ww <= 0 || wh <= 0) return;
    a->pick_x = a->mouse_x * fw / ww;
    a->pick_y = a->mouse_y * fh / wh;
    a->pick_pending = true;
    a->pick_op = !a->voxel_mode ? -1 : (mods & GLFW_MOD_SHIFT) ? VVX_REMOVE : (mods & GLFW_MOD_ALT) ? VVX_PAINT : VVX_ADD;
}

static void cursor_cb(GLFWwindow* win, double x, double y) {
    ((app*)glfwGetWindowUserPointer(win))->ui_dirty = true;
    app* a = glfwGetWindowUserPointer(win);
    {
        /* the panels work in frame pixels, the cursor comes in screen coordinates */
        int ww, wh;
        uint32_t fw, fh;
        glfwGetWindowSize(win, &ww, &wh);
        if (a->o.width) fw = a->o.width, fh = a->o.height;
        else vp_frame_size(a->p, &fw, &fh);
        if (ww > 0 && wh > 0) sv_panels_mouse(a, x * fw / ww, y * fh / wh);
    }
    double dx = x - a->mouse_x, dy = y - a->mouse_y;
    a->mouse_x = x, a->mouse_y = y;
    if (a->rmb) {
        a->cam_default = false;
        a->yaw -= dx * 0.004;
        a->pitch = fmax(-1.55, fmin(1.55, a->pitch - dy * 0.004));
        if (a->orbit) {
            double f[3];
            sv_cam_fwd(a, f);
            for (int k = 0; k < 3; k++) a->eye[k] = a->orbit_center[k] - f[k] * a->orbit_dist;
        }
    }
    if (a->op == 'g' && a->op_axis >= 0 && a->sel != NO_SEL) {
        /* whole voxels: about 8 pixels of horizontal motion per cell */
        a->grab_px += dx;
        int32_t n = (int32_t)(a->grab_px / 8);
        if (n) {
            a->grab_px -= n * 8;
            sv_edit_move(a, a->op_axis, n);
            a->grab_moved += n;
            sv_update_instances(a);
        }
    }
}

static void char_cb(GLFWwindow* win, unsigned int c) {
    ((app*)glfwGetWindowUserPointer(win))->ui_dirty = true;
    sv_panels_char(glfwGetWindowUserPointer(win), c);
}

static void scroll_cb(GLFWwindow* win, double dx, double dy) {
    ((app*)glfwGetWindowUserPointer(win))->ui_dirty = true;
    (void)dx;
    app* a = glfwGetWindowUserPointer(win);
    sv_panels_wheel(a, dy);
    if (sv_panels_wants_mouse(a)) return;
    if (a->orbit) {
        a->orbit_dist *= pow(0.9, dy);
        double f[3];
        sv_cam_fwd(a, f);
        for (int k = 0; k < 3; k++) a->eye[k] = a->orbit_center[k] - f[k] * a->orbit_dist;
        a->cam_default = false;
    } else {
        a->speed *= pow(1.2, dy);
    }
}

static void drop_cb(GLFWwindow* win, int n, const char** paths) {
    ((app*)glfwGetWindowUserPointer(win))->ui_dirty = true;
    app* a = glfwGetWindowUserPointer(win);
    for (int i = 0; i < n; i++) sv_add(a, paths[i]);
}

void sv_fly(app* a, double dt) {
    GLFWwindow* w = vp_window(a->p);
    double f[3], r[3];
    sv_cam_fwd(a, f);
    r[0] = sin(a->yaw), r[1] = -cos(a->yaw), r[2] = 0;
    double m[3] = {0, 0, 0}, s = a->speed * dt;
    if (glfwGetKey(w, GLFW_KEY_W) == GLFW_PRESS)
        for (int k = 0; k < 3; k++) m[k] += f[k];
    if (glfwGetKey(w, GLFW_KEY_S) == GLFW_PRESS)
        for (int k = 0; k < 3; k++) m[k] -= f[k];
    if (glfwGetKey(w, GLFW_KEY_D) == GLFW_PRESS && !(glfwGetKey(w, GLFW_KEY_LEFT_SHIFT) == GLFW_PRESS))
        for (int k = 0; k < 3; k++) m[k] += r[k];
    if (glfwGetKey(w, GLFW_KEY_A) == GLFW_PRESS)
        for (int k = 0; k < 3; k++) m[k] -= r[k];
    if (glfwGetKey(w, GLFW_KEY_E) == GLFW_PRESS) m[2] += 1;
    if (glfwGetKey(w, GLFW_KEY_Q) == GLFW_PRESS) m[2] -= 1;
    if (m[0] == 0 && m[1] == 0 && m[2] == 0) return;
    if (glfwGetKey(w, GLFW_KEY_LEFT_CONTROL) == GLFW_PRESS) return;
    a->cam_default = false;
    for (int k = 0; k < 3; k++) a->eye[k] += m[k] * s, a->orbit_center[k] += m[k] * s;
}

void sv_input_attach(app* a, GLFWwindow* w) {
    glfwSetWindowUserPointer(w, a);
    glfwSetKeyCallback(w, key_cb);
    glfwSetMouseButtonCallback(w, mouse_cb);
    glfwSetCursorPosCallback(w, cursor_cb);
    glfwSetScrollCallback(w, scroll_cb);
    glfwSetDropCallback(w, drop_cb);
    glfwSetCharCallback(w, char_cb);
    glfwGetCursorPos(w, &a->mouse_x, &a->mouse_y);
}
