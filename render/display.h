/* render/display.h - a frame of the pass pipeline turned into display bytes
 * on the GPU, for presenters that show it without reading it back.
 *
 * A frame rendered with vx_frame_desc.no_readback leaves its image on the
 * GPU. vx_display converts it there, in one dispatch, to 8-bit pixels (R, G,
 * B clamped to [0,1] and rounded as lrintf(v * 255), the bytes svo_render's
 * PNG and svo_view's host conversion give; alpha 255) in R,G,B,A or B,G,R,A
 * order, and lays an overlay over it: premultiplied 8-bit colour and
 * coverage in the same byte order, which the caller draws on the CPU into
 * the mapped buffer vx_display_overlay returns (zeroed: nothing over the
 * frame): out = P + F * (255 - A) / 255. The bytes land in a buffer of the
 * display's, which a presenter copies to its swapchain image in the same
 * submission (vx_display_record), or which vx_display_run reads back
 * (benchmarks, tests, screenshots of the displayed frame).
 *
 * Usage: vx_display_create(gpu) -> per frame: vx_frame_render(no_readback)
 *        [-> vx_display_overlay, draw] -> vx_display_record into the
 *        presenter's command buffer (or vx_display_run) -> vx_display_destroy.
 * Frames in flight (below) put the passes into the same command buffer.
 * The device must be the frame renderer's; Vulkan handles go as uint64_t /
 * void* so that this header needs no vulkan.h. */
#ifndef VX_RENDER_DISPLAY_H
#define VX_RENDER_DISPLAY_H

#include <stdbool.h>
#include <stdint.h>

#include "render/pipeline.h"
#include "render/render.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct vx_display vx_display;

/* What to convert: the last frame fr rendered (width x height: its size). */
typedef struct vx_display_desc {
    const vx_frame_renderer* fr;
    uint32_t width, height;
    bool bgra;    /* B,G,R,A byte order (the swapchain's), else R,G,B,A */
    bool overlay; /* lay the overlay (vx_display_overlay) over the frame */
} vx_display_desc;

vx_result vx_display_create(vx_gpu* gpu, vx_display** out, vx_error* err);
void vx_display_destroy(vx_display* d);
/* The overlay for a width x height frame: 4 bytes a pixel, rows top first,
 * host-mapped, zeroed by this call; valid until the next call or
 * vx_display_destroy. Frames recorded after the call lay it over their image
 * (until the next call: an overlay drawn once is kept); the first of them
 * copies it into device memory, which the frames read (8 MB of host memory
 * read by every 1920x1080 frame cost more than its trace). There are two:
 * the call returns the one no frame in flight copies from (waiting for one
 * that still does), so the CPU draws while the GPU shows the last one. NULL
 * on failure (err says why). */
uint8_t* vx_display_overlay(vx_display* d, uint32_t width, uint32_t height, vx_error* err);
/* Records the conversion into `cmd` (a VkCommandBuffer in the recording
 * state, on the frame renderer's queue): a barrier after the frame's writes,
 * the dispatch, and a barrier before transfer reads. *out_buffer (a
 * VkBuffer) then holds width * height * 4 bytes at offset 0, for a
 * vkCmdCopyBufferToImage after this; valid until the next call. */
vx_result vx_display_record(vx_display* d, void* cmd, const vx_display_desc* desc, uint64_t* out_buffer, vx_error* err);
/* The same in a submission of its own, waited for; with `bytes` (width *
 * height * 4) the result is read back there. *seconds: the submission's
 * wall time, NULL allowed. */
vx_result vx_display_run(vx_display* d, const vx_display_desc* desc, uint8_t* bytes, double* seconds, vx_error* err);

/* Frames in flight: the passes, the conversion and the copy to the shown
 * image in one command buffer and one submission per frame, with up to
 * VX_DISPLAY_FRAMES frames submitted and not waited for. Per frame:
 *   vx_display_frame_begin(d, &slot, &cmd)   waits for the frame submitted
 *       VX_DISPLAY_FRAMES frames before (only that one), begins its command
 *       buffer (cmd, a VkCommandBuffer) with a start timestamp
 *   vx_frame_record(fr, desc, cmd, slot, ...)    the passes (pipeline.h)
 *   vx_display_record(d, cmd, ...)               the conversion and overlay
 *   vx_display_copy_to_image(cmd, buffer, ...)   into the swapchain image
 *   vx_display_frame_submit(d, acquired, rendered)  one vkQueueSubmit with
 *       the slot's fence, waiting at the copy (transfer stage) for
 *       `wait_semaphore` (a swapchain's acquire; 0: none) and signalling
 *       `signal_semaphore` (for vkQueuePresentKHR; 0: none)
 * A frame whose recording failed is dropped with vx_display_frame_cancel
 * (which also tells a renderer whose passes vx_display_record_frame recorded
 * there; after vx_frame_record call vx_frame_record_cancel too).
 * The slot (0 .. VX_DISPLAY_FRAMES - 1) is also vx_frame_record's: after
 * vx_display_frame_begin returns it, its last frame has run, and
 * vx_frame_record_result(fr, slot) gives that frame's pass times.
 * vx_display_wait waits for every frame in flight (before reading a result
 * back, or changing what the frames read from the host). */
#define VX_DISPLAY_FRAMES 3
/* How frames reach the queue: `frames` in flight (0: VX_DISPLAY_FRAMES; at
 * most VX_DISPLAY_SLOTS; slots are then 0 .. frames - 1), submitted `batch`
 * at a time (0 or 1: each frame at its own vkQueueSubmit; more: the frames
 * are held until that many are recorded and go in one vkQueueSubmit, the
 * last one's fence standing for all; vx_display_wait and a wait for a held
 * frame submit what is held), with one_submit_info the batch's command
 * buffers in one VkSubmitInfo where no frame has semaphores. Waits for the
 * frames in flight. Frames held for a batch are submitted before any other
 * work reaches the queue or waits for it (vx_gpu.held_submit), so an edit
 * after them does not show in them. With batches a presenter presents a
 * frame once its batch was submitted (vx_display_times.frames_submitted;
 * svo_view --batch): a queue submission costs an H200 about 0.01 ms
 * between frames (view_bench --submit). */
#define VX_DISPLAY_SLOTS 8
vx_result vx_display_set_queue(vx_display* d, uint32_t frames, uint32_t batch, bool one_submit_info, vx_error* err);
vx_result vx_display_frame_begin(vx_display* d, uint32_t* slot, void** cmd, vx_error* err);
vx_result vx_display_frame_submit(vx_display* d, uint64_t wait_semaphore, uint64_t signal_semaphore, vx_error* err);
void vx_display_frame_cancel(vx_display* d);
vx_result vx_display_wait(vx_display* d, vx_error* err);
/* Records the copy of a w x h buffer of display bytes (vx_display_record's
 * *out_buffer; 0: none, the image is cleared) into `image` (a VkImage of
 * iw x ih, 4-byte pixels, TRANSFER_DST usage; its contents are not kept),
 * clipped or padded with black, left in `final_layout` (a VkImageLayout:
 * PRESENT_SRC_KHR for a swapchain image). */
void vx_display_copy_to_image(void* cmd, uint64_t buffer, uint32_t w, uint32_t h, uint64_t image, uint32_t iw, uint32_t ih,
                              int final_layout);
/* The device's times of the last frame found done (by begin or wait), from
 * the timestamps at its command buffer's start and end: gpu_ms its length,
 * gpu_start_ms its start on the device's clock (the difference between two
 * frames' starts is their interval on the GPU). All 0 without timestamps. */
typedef struct vx_display_times {
    uint64_t frames_done;
    uint64_t frames_submitted; /* frames given to vkQueueSubmit (with batches: held ones not yet) */
    uint64_t submits;          /* the vkQueueSubmit calls that carried them (a batch of K frames: one) */
    uint64_t begins_waited; /* waits for a slot's frame that found it not yet done (the CPU ahead of the GPU) */
    double gpu_ms;
    double gpu_start_ms;
} vx_display_times;
void vx_display_frame_times(const vx_display* d, vx_display_times* out);
/* Whether frames begun from now on write those two timestamps (default on;
 * a viewer that does not read them turns them off: with their query reset
 * they cost a frame in flight a few microseconds on an H200). Frames without
 * them leave vx_display_frame_times as it was. */
void vx_display_set_timestamps(vx_display* d, bool on);

/* Off-screen images that stand in for a swapchain's where there is no
 * display (benchmarks, tests, a GPU machine without a window system):
 * w x h, B,G,R,A bytes, device-local, transfer destination and source and
 * colour attachment (a render pass may draw over the frame, as svo_view's
 * panels do); destroyed with the display. vx_display_image_view gives an
 * image's view (a VkImageView, 0: not one of these images). vx_display_image_read waits for the frames in
 * flight and reads one back (rows top first); the image must have been
 * copied to with final layout TRANSFER_SRC_OPTIMAL. */
#define VX_DISPLAY_IMAGES 16
vx_result vx_display_image_create(vx_display* d, uint32_t w, uint32_t h, uint64_t* image, vx_error* err);
vx_result vx_display_image_read(vx_display* d, uint64_t image, uint32_t w, uint32_t h, uint8_t* bytes, vx_error* err);
void vx_display_image_destroy(vx_display* d, uint64_t image);
uint64_t vx_display_image_view(const vx_display* d, uint64_t image);
/* Where the device can (shaderStorageImageWriteWithoutFormat, which
 * vx_gpu_create and vx_gpu_make_device enable where offered, and storage
 * images of the format: vx_display_can_store; vx_display_image_storage for
 * the off-screen images) the conversion writes the image itself:
 * vx_display_record_image records the conversion and overlay into `image`
 * (iw x ih, left in final_layout) through `view` (a VkImageView of it, 0:
 * the image is one of vx_display_image_create's), in place of
 * vx_display_record + vx_display_copy_to_image; the image needs STORAGE
 * usage (a swapchain's: when the surface offers it). The buffer-to-image
 * copy it saves cost 0.10 ms of a 1920x1080 frame on an H200, more than the
 * conversion (0.014 ms). Same bytes. */
bool vx_display_can_store(const vx_display* d, int format /* VkFormat */);
bool vx_display_image_storage(const vx_display* d);
vx_result vx_display_record_image(vx_display* d, void* cmd, const vx_display_desc* desc, uint64_t image, uint64_t view,
                                  uint32_t iw, uint32_t ih, int final_layout, vx_error* err);
/* The conversion fused into the frame: records the passes of `fd` (as
 * vx_frame_record, in the frame being recorded: vx_display_frame_begin's
 * command buffer and slot, renderer fr = desc->fr) with the frame's last pass
 * (tonemap, else aa, else the merged kernel or resolve: still its own timing
 * row) also writing the display bytes and the overlay into `image` as
 * vx_display_record_image would (same bytes; view, iw, ih, final_layout as
 * there), in place of vx_frame_record + vx_display_record_image: no pass
 * reads the frame again (the conversion read the 33 MB float image of a
 * 1920x1080 frame: 0.018 ms of a 0.12 ms frame on an H200). A frame of one
 * sample whose last pass is the merged kernel or resolve does not write its
 * float image either (nothing reads it: vx_display_record then has no frame
 * to convert); with more samples, aa or tonemap it is written as by
 * vx_frame_record. The image is written by the passes' compute stage: a
 * swapchain acquire the submission waits for (at the transfer stage, as
 * vx_display_frame_submit does) is ordered before the passes by an image
 * barrier at the start; final_layout COLOR_ATTACHMENT_OPTIMAL makes the
 * frame's writes visible to a render pass that loads the image next (the
 * panels drawn over it: tools/svo_view/ui.h ui_gpu_record). desc: width and
 * height the frame's (fd->base), the
 * byte order and the overlay. VX_ERR_UNSUPPORTED where the device cannot
 * store images without a format (then vx_frame_record and the copy). On
 * failure the frame is the caller's to cancel (vx_display_frame_cancel). */
vx_result vx_display_record_frame(vx_display* d, vx_frame_renderer* fr, const vx_frame_desc* fd,
                                  const vx_display_desc* desc, uint64_t image,
                                  uint64_t view, uint32_t iw, uint32_t ih, int final_layout, vx_frame_result* out,
                                  vx_error* err);

#ifdef __cplusplus
}
#endif
#endif
