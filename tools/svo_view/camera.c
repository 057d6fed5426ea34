/* tools/svo_view/camera.c - the viewer's camera: the tracer's default
 * framing, framing a box or the selection, the tracer's camera from the
 * viewer's eye, yaw and pitch (camera.h). */
#include <math.h>

#include "tools/svo_view/app.h"
#include "tools/svo_view/camera.h"

/* World box of instance i as the frame shown places it. */
void sv_world_box(const app* a, uint32_t i, double lo[3], double hi[3]) {
    vx_svo_instance_world_box(&a->scene, vx_svo_scene_frame_instances(&a->scene, a->anim_frame) + i, lo, hi);
}

void sv_cam_fwd(const app* a, double f[3]) {
    f[0] = cos(a->pitch) * cos(a->yaw);
    f[1] = cos(a->pitch) * sin(a->yaw);
    f[2] = sin(a->pitch);
}

/* Places the camera to frame a box from direction `dir` (towards the eye),
 * exactly as the tracer's default camera does for the scene bounds. */
void sv_frame_box(app* a, const double lo[3], const double hi[3], const double dir_in[3]) {
    double c[3], rad = 0, dir[3] = {dir_in[0], dir_in[1], dir_in[2]};
    double l = sqrt(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);
    for (int k = 0; k < 3; k++) dir[k] /= l;
    for (int k = 0; k < 3; k++) c[k] = 0.5 * (lo[k] + hi[k]), rad += (hi[k] - lo[k]) * (hi[k] - lo[k]);
    rad = 0.5 * sqrt(rad);
    if (!(rad > 0)) rad = 1;
    double dist = rad / sin(0.5 * a->o.fov * SV_PI / 180.0) * 1.05;
    for (int k = 0; k < 3; k++) a->eye[k] = c[k] + dir[k] * dist, a->orbit_center[k] = c[k];
    a->orbit_dist = dist;
    a->yaw = atan2(-dir[1], -dir[0]);
    a->pitch = asin(-dir[2]);
    a->speed = rad > 0 ? rad * 0.5 : 1;
}

void sv_camera_default(app* a) {
    double lo[3], hi[3], dir[3] = {0.45, -1.0, 0.65};
    vx_svo_scene_world_bounds(&a->scene, lo, hi); /* the tracer's default framing: every frame */
    sv_frame_box(a, lo, hi, dir);
    a->cam_default = true;
}

vx_render_camera sv_camera_desc(const app* a) {
    vx_render_camera c = {.fov = a->o.fov};
    if (a->cam_default) return c; /* the tracer's own framing: svo_render's image exactly */
    double f[3];
    sv_cam_fwd(a, f);
    c.set = true;
    for (int k = 0; k < 3; k++) c.eye[k] = a->eye[k], c.target[k] = a->eye[k] + f[k];
    return c;
}

void sv_frame_camera(app* a) {
    double lo[3], hi[3], f[3];
    if (a->sel != NO_SEL) sv_world_box(a, a->sel, lo, hi);
    else vx_svo_scene_world_bounds(&a->scene, lo, hi);
    sv_cam_fwd(a, f);
    double dir[3] = {-f[0], -f[1], -f[2]};
    sv_frame_box(a, lo, hi, dir);
    a->cam_default = false;
}
