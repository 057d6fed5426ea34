/* tools/svo_view/panels.h - svo_view's Dear ImGui panels (panels.c over the
 * ui.h shim): an outliner (layers, models, instances, lights: visibility,
 * select), properties (an instance's cell position, quarter turns, mirrors,
 * duplicate/delete/hide, voxel brush and palette; a light's type, colour,
 * intensity, range, position; a material's type and parameters), a render
 * panel (mode, passes, GI method and its settings, exposure, vsync), statistics (per-pass GPU times of the last frames as
 * stacked bars, rays per second, memory) and, for an animation, playback
 * (play, pause, step, scrub, frames per second). Every action goes through
 * the same sv_* function as the key or script command that does it.
 *
 * Built without ImGui (CMake VX_WITH_IMGUI off or libimgui-dev absent),
 * panels_none.c stands in: sv_panels_create says so and the viewer keeps
 * its text overlay. */
#ifndef VX_SVO_VIEW_PANELS_H
#define VX_SVO_VIEW_PANELS_H

#include "tools/svo_view/app.h"
#include "tools/svo_view/font.h"

/* Whether this build has panels. */
bool sv_panels_built(void);
/* Sets a->ui; false (with a message) when not built or out of memory. */
bool sv_panels_create(app* a);
void sv_panels_destroy(app* a);
/* Builds this frame's panels (their actions run now) and draws them over cv
 * (with a->panels_gpu_now: only builds them, for sv_panels_gpu_record). */
void sv_panels_draw(app* a, vf_canvas* cv);
/* The panels drawn on the GPU (ui.h ui_gpu_init) on the window's device,
 * into images of the swapchain's format left for presentation; false with
 * the reason in why (not built: none). */
bool sv_panels_gpu_init(app* a, char* why, size_t why_size);
/* Records the last built panels over a frame in flight's image (ui.h
 * ui_gpu_record: view, w x h, in COLOR_ATTACHMENT_OPTIMAL layout). */
bool sv_panels_gpu_record(app* a, void* cmd, uint32_t slot, uint64_t view, uint32_t w, uint32_t h, char* why,
                          size_t why_size);

/* Input from the window, in frame pixels; the *_wants functions say whether
 * the panels took it (the viewer then ignores it). */
void sv_panels_mouse(app* a, double x, double y);
void sv_panels_button(app* a, int button, bool down);
void sv_panels_wheel(app* a, double dy);
void sv_panels_key(app* a, int key, bool down, int mods);
void sv_panels_char(app* a, unsigned int c);
/* The scripted click's target (ui.h ui_find): the next drawn panels note
 * where the widget labelled `label` is; false from sv_panels_found until
 * they did (or when this build has no panels). */
void sv_panels_find(app* a, const char* label);
bool sv_panels_found(const app* a, float rect[4]);
bool sv_panels_wants_mouse(const app* a);
bool sv_panels_wants_keyboard(const app* a);

#endif
