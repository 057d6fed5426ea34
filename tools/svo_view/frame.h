/* tools/svo_view/frame.h - one frame of the viewer (frame.c). */
#ifndef VX_SVO_VIEW_FRAME_H
#define VX_SVO_VIEW_FRAME_H

#include "tools/svo_view/app.h"

/* Renders, draws the overlay and panels, takes a pending pick, screenshot or
 * grab, and presents: on the GPU path possibly leaving the frame in flight
 * (render/display.h). */
vx_result sv_frame(app* a, vx_error* err);
/* The frames a batch of the GPU path still holds submitted and presented. */
vx_result sv_batch_drain(app* a, vx_error* err);

#endif
