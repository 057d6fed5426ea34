/* tools/svo_view/present.h - a GLFW window with a Vulkan swapchain that
 * shows 8-bit frames, on a device the tracer adopts (vx_gpu_desc.external).
 *
 * Three paths. Host: the tracer writes float pixels to a buffer of its own
 * and reads them back (vx_render_frame); the viewer converts them to 8 bits
 * on the CPU (the same conversion svo_render uses for PNG, so a screenshot
 * equals svo_render's image), draws the overlay there, and vp_present copies
 * the bytes into the swapchain image with one vkCmdCopyBufferToImage. GPU
 * (vp_present_display): the pass pipeline's image stays on the GPU and is
 * converted, overlaid and copied to the swapchain image in the present's
 * submission, waited for. Frames in flight (vp_acquire, below): the passes
 * too go into that submission, and the viewer does not wait for it. One
 * queue does compute, transfer and present.
 *
 * Usage: vp_create -> vx_gpu_create(&(vx_gpu_desc){.external = ...vp_external}) ->
 *        loop { vp_frame_size; render; vp_present } -> vx_gpu_destroy -> vp_destroy.
 */
#ifndef VX_SVO_VIEW_PRESENT_H
#define VX_SVO_VIEW_PRESENT_H

#include <stdbool.h>
#include <stdint.h>

#include "render/display.h"
#include "render/render.h"

typedef struct vp vp;
struct GLFWwindow;

typedef struct vp_desc {
    uint32_t width, height; /* window size in screen coordinates, 0 == 1280 x 800 */
    const char* title;
    const char* device;     /* as vx_gpu_desc.device */
    bool validate;          /* VK_LAYER_KHRONOS_validation, errors counted (below) and logged */
    uint32_t* validation_errors; /* with validate: incremented per validation error; must outlive vp_destroy
                                    (teardown is validated too) */
    const vx_logger* logger;     /* with validate: the messages ("gpu.validation") */
    bool vsync;             /* FIFO presentation (default off: mailbox/immediate when available) */
    bool hidden;            /* do not show the window (still presents) */
    uint32_t batch;         /* frames in flight submitted this many at a time (svo_view --batch; 0, 1: each alone):
                               the swapchain gets that many more images, acquired ahead of their present */
} vp_desc;

vx_result vp_create(const vp_desc* desc, vp** out, vx_error* err);
void vp_destroy(vp* p);
struct GLFWwindow* vp_window(vp* p);
/* Fills the external part of a vx_gpu_desc with the window's device. */
void vp_external(vp* p, vx_gpu_desc* gd);
/* Current swapchain size (the framebuffer size in pixels: HiDPI aware). */
void vp_frame_size(vp* p, uint32_t* w, uint32_t* h);
bool vp_frame_bgra(const vp* p); /* the swapchain wants B,G,R,A bytes */
bool vp_storage(const vp* p);    /* the swapchain images are storage images (vp_image.view) */
bool vp_colour(const vp* p);     /* ... and colour attachments (vp_image.view; the panels drawn on the GPU) */
int vp_format(const vp* p);      /* the swapchain images' VkFormat */
/* Changes vsync; takes effect by recreating the swapchain. */
void vp_set_vsync(vp* p, bool vsync);
bool vp_vsync(const vp* p);
/* Copies a w x h frame of 4-byte pixels (rows top first) to the next
 * swapchain image (clipped or padded with black when the sizes differ) and
 * presents it. Recreates the swapchain when the window was resized. */
vx_result vp_present(vp* p, const uint8_t* pixels, uint32_t w, uint32_t h, vx_error* err);
/* The GPU path: the frame renderer's last image (rendered with no_readback)
 * goes to the next swapchain image in one submission: vx_display's
 * conversion and overlay (render/display.h), a buffer-to-image copy, the
 * present. No pixel passes through host memory, except with `grab` (w * h *
 * 4 bytes): the displayed bytes are also copied back there. */
vx_result vp_present_display(vp* p, vx_display* disp, const vx_display_desc* desc, uint8_t* grab, vx_error* err);

/* Frames in flight (render/display.h): the viewer records the passes, the
 * conversion and the copy into one command buffer per frame and does not
 * wait for it. vp_acquire takes the next swapchain image for the frame
 * recorded in `slot` (vx_display_frame_begin's), signalling the slot's
 * semaphore (out->acquired, for vx_display_frame_submit to wait on; the
 * submission signals out->rendered); out->image is 0 when there is no image
 * (minimised, or the swapchain is made again next frame): the frame is then
 * cancelled. vp_present_acquired queues the present of that image after the
 * submission. */
typedef struct vp_image {
    uint64_t image; /* VkImage, 0: none */
    uint32_t width, height;
    uint64_t acquired, rendered; /* VkSemaphore */
    int layout;                  /* VkImageLayout the image is presented in */
    uint64_t view; /* VkImageView, a storage view (vx_display_record_image writes the image), 0: copy into it */
} vp_image;
vx_result vp_acquire(vp* p, uint32_t slot, vp_image* out, vx_error* err);
vx_result vp_present_acquired(vp* p, vx_error* err);
/* With batches (vp_desc.batch > 1, render/display.h vx_display_set_queue)
 * a frame's submission may come after its vp_present_acquired: that call
 * then queues the present of frame number `frame` (the count of frames
 * submitted before it, vx_display_times.frames_submitted's numbering), and
 * vp_present_submitted presents the queued frames numbered below
 * `submitted` (the display's frames_submitted), in order. vp_stale says
 * the next vp_acquire makes the swapchain again: the caller then has the
 * display submit what it holds (vx_display_wait) and presents it first. */
void vp_set_frame_number(vp* p, uint64_t frame);
vx_result vp_present_submitted(vp* p, uint64_t submitted, vx_error* err);
/* What became of the frames in flight's presents (vp_present_acquired and
 * vp_present_submitted): presents made, those whose frame number was not
 * above the one before (0 when every frame went to the screen in the order
 * it was recorded), and presents still queued. */
typedef struct vp_present_counts {
    uint64_t presented, out_of_order;
    uint32_t queued;
} vp_present_counts;
void vp_get_present_counts(const vp* p, vp_present_counts* out);
bool vp_stale(vp* p);

#endif
