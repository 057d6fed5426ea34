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
 * host-mapped, zeroed by this call; valid until the next call with another
 * size or vx_display_destroy. NULL on failure (err says why). */
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

#ifdef __cplusplus
}
#endif
#endif
