/* tools/svo_view/ui.h - the C face of Dear ImGui for svo_view's panels.
 *
 * A thin shim (ui.cpp, the only C++ of the viewer): one context, input fed
 * by the viewer's GLFW callbacks in frame pixels, the widgets the panels use
 * as C functions, and the frame's draw lists rasterized on the CPU into the
 * 8-bit frame (font.h vf_triangles) before it goes to the swapchain. The
 * CPU path keeps the viewer's one presentation path (the tracer's image is
 * read back on every device, lavapipe under Xvfb included), and a grab of
 * the displayed frame holds the panels. Where the frame goes to the
 * swapchain image on the GPU, Debian's libimgui.a's Vulkan backend draws the
 * same draw lists there instead (ui_gpu_init below). Its GLFW backend is not
 * used: it reads the cursor itself where scripts inject it.
 *
 * Widgets work between ui_frame_begin and ui_frame_end as ImGui's do (ids
 * from labels, "##" hides the rest of a label); they return true when the
 * user changed the value or pressed the button.
 *
 * Built only with ImGui (CMake VX_WITH_IMGUI); without it svo_view has no
 * panels (panels.h says so at run time). */
#ifndef VX_SVO_VIEW_UI_H
#define VX_SVO_VIEW_UI_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "tools/svo_view/font.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct ui ui;

/* NULL when out of memory. */
ui* ui_create(void);
void ui_destroy(ui* u);

/* Input in frame pixels (the canvas the panels are drawn on). */
void ui_mouse(ui* u, double x, double y);
void ui_mouse_button(ui* u, int button, bool down); /* 0 left, 1 right, 2 middle */
void ui_wheel(ui* u, double dy);
void ui_key(ui* u, int glfw_key, bool down, bool ctrl, bool shift, bool alt);
void ui_char(ui* u, unsigned int codepoint);
/* Scripted input (svo_view's `ui click LABEL`): the next frame notes the
 * rectangle (x0, y0, x1, y1, frame pixels) of the first widget drawn with
 * this label (as passed to the widget, "##" suffixes included; the items of
 * an open combo by their text); ui_found gives it once drawn. */
void ui_find(ui* u, const char* label);
bool ui_found(const ui* u, float rect[4]);
/* Whether the panels took the mouse / keyboard in the last frame (the
 * viewer then neither picks nor handles its keys). */
bool ui_wants_mouse(const ui* u);
bool ui_wants_keyboard(const ui* u);

void ui_frame_begin(ui* u, uint32_t width, uint32_t height, double dt_seconds);
/* Ends the frame and draws it over cv (NULL: not on the CPU; the frame's
 * draw lists are kept for ui_gpu_record until the next ui_frame_begin). */
void ui_frame_end(ui* u, vf_canvas* cv);
/* Draws the kept draw lists over cv on the CPU (what ui_frame_end does). */
void ui_draw_cpu(ui* u, vf_canvas* cv);

/* ---- the panels drawn on the GPU ----
 * Dear ImGui's own Vulkan backend (imgui_impl_vulkan, in Debian's
 * libimgui.a) draws the kept draw lists into the shown image in the frame's
 * command buffer, after the tracer's last pass wrote the scene there
 * (render/display.h vx_display_record_frame with final layout
 * COLOR_ATTACHMENT_OPTIMAL): a render pass that loads the image, the
 * panels' triangles blended over it, the image left in final_layout. No
 * panel pixel passes through host memory and the scene pixels outside the
 * panels stay the tracer's bytes. Vulkan handles go as void* / uint64_t so
 * this header needs no vulkan.h. */
typedef struct ui_gpu_desc {
    void* instance; /* VkInstance */
    void* phys;     /* VkPhysicalDevice */
    void* device;   /* VkDevice */
    void* queue;    /* VkQueue, of queue_family (the font upload's submission) */
    uint32_t queue_family;
    int format;       /* VkFormat of the images drawn into (0: B8G8R8A8_UNORM) */
    int final_layout; /* VkImageLayout the images are left in (0: PRESENT_SRC_KHR) */
    uint32_t frames;  /* frames in flight that record panels (>= 2; 0: 3) */
} ui_gpu_desc;
/* Makes the backend's pipeline, font texture (uploaded in a submission of
 * its own, waited for) and render pass; false with the reason in why. */
bool ui_gpu_init(ui* u, const ui_gpu_desc* desc, char* why, size_t why_size);
/* Records the kept draw lists into cmd (a VkCommandBuffer being recorded)
 * over `view` (a VkImageView of a w x h image in COLOR_ATTACHMENT_OPTIMAL
 * layout, its writes before this made visible to colour attachment reads).
 * `slot` (< desc.frames) names the frame in flight: its framebuffer from
 * the last call with that slot is destroyed here (that frame has ended: the
 * caller waited for it). False when nothing could be recorded (why). */
bool ui_gpu_record(ui* u, void* cmd, uint32_t slot, uint64_t view, uint32_t w, uint32_t h, char* why, size_t why_size);
/* Whether ui_gpu_init succeeded (and ui_gpu_shutdown was not called). */
bool ui_gpu_ready(const ui* u);
/* Frees the GPU objects (after waiting for the device); ui_destroy does it too,
 * but the device may be gone by then: call this before destroying it. */
void ui_gpu_shutdown(ui* u);

/* ---- widgets ---- */
/* A window placed at (x, y) with size (w, h) the first time it appears;
 * false when collapsed (still call ui_window_end). */
bool ui_window_begin(const char* title, float x, float y, float w, float h);
void ui_window_end(void);
bool ui_collapsing(const char* label, bool default_open);
bool ui_tree_begin(const char* label, bool default_open); /* true: call ui_tree_end */
void ui_tree_end(void);
void ui_text(const char* fmt, ...) __attribute__((format(printf, 1, 2)));
void ui_separator(void);
void ui_same_line(void);
void ui_push_id(int id);
void ui_pop_id(void);
bool ui_button(const char* label);
bool ui_checkbox(const char* label, bool* v);
bool ui_selectable(const char* label, bool selected);
bool ui_combo(const char* label, int* current, const char* const* items, int count);
/* A text field over buf (size bytes), reported when Enter is pressed. */
bool ui_input_text(const char* label, char* buf, size_t size);
/* Three integers, reported when Enter is pressed in a field. */
bool ui_input_int3(const char* label, int32_t v[3]);
bool ui_drag_double(const char* label, double* v, double speed, double min, double max);
bool ui_drag_double3(const char* label, double v[3], double speed);
bool ui_slider_int(const char* label, int* v, int min, int max);
bool ui_color3(const char* label, double rgb[3]);
/* A colour swatch (RGBA8, R low); a frame around it when selected. */
bool ui_swatch(const char* id, uint32_t rgba, bool selected, float size);
/* Bars of the last `count` frames, oldest first, each a stack of `layers`
 * values (values[frame * stride + layer]) in colours[layer % colour_count],
 * scaled so `top` fills `height` pixels. */
void ui_stacked_bars(const float* values, int count, int layers, int stride, const uint32_t* colours, int colour_count,
                     float top, float height);
/* A small coloured square in the text line (a legend). */
void ui_legend(uint32_t rgba, const char* label);
/* An image drawn as rectangles, one per texel (runs of one colour merged):
 * w x h RGBA8 texels (R in bits 0..7), each `scale` pixels; small maps only. */
void ui_image_rgba(const uint32_t* texels, int w, int h, float scale);
/* A progress bar of `fraction` in [0,1] with a label over it. */
void ui_progress(float fraction, const char* label);

#ifdef __cplusplus
}
#endif
#endif
