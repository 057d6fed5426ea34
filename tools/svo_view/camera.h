/* tools/svo_view/camera.h - the viewer's camera (camera.c): an eye with yaw
 * and pitch (z up), or the tracer's own default framing (app.cam_default),
 * which the viewer keeps until the camera moves so that its first frame is
 * svo_render's image exactly. sv_frame_camera (app.h) frames the selection. */
#ifndef VX_SVO_VIEW_CAMERA_H
#define VX_SVO_VIEW_CAMERA_H

#include "tools/svo_view/app.h"

#define SV_PI 3.14159265358979323846

/* World box of instance i as the frame shown places it. */
void sv_world_box(const app* a, uint32_t i, double lo[3], double hi[3]);
/* The unit view direction of yaw and pitch. */
void sv_cam_fwd(const app* a, double f[3]);
/* Places the camera to frame a box from direction dir (towards the eye),
 * exactly as the tracer's default camera does for the scene bounds. */
void sv_frame_box(app* a, const double lo[3], const double hi[3], const double dir[3]);
/* The tracer's default framing of every frame's bounds (cam_default set). */
void sv_camera_default(app* a);
/* The render desc's camera: unset (the tracer's framing) while cam_default. */
vx_render_camera sv_camera_desc(const app* a);

#endif
