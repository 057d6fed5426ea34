/* tools/svo_view/batch.h - how many frames in flight go to the GPU in one
 * vkQueueSubmit when the user did not say (`--batch auto`, the default).
 *
 * Why: on a fast GPU a frame is so short (eph_monu1 at 1920x1080 on an
 * H200: 0.08 ms) that the queue's idle time between submissions (about
 * 0.013 ms) is a tenth of it; frames submitted 4 at a time bring svo_view
 * within 3-4% of svo_render's trace (docs/PERFORMANCE.md, section 6). A
 * batch of K shows a frame up to K - 1 frames after it was recorded, so K
 * is chosen from the measured frame time to keep that added latency under
 * SV_BATCH_LATENCY_MS: long frames (lavapipe, big views) stay one a
 * submission, and vsync (the display paces the frames) always gets 1.
 *
 * sv_batch is plain data: the tool feeds it the GPU times of its timed
 * frames and asks which batch it wants; it changes its answer at most
 * once every SV_BATCH_HOLD frames, so a noisy frame does not make the
 * viewer drain and re-queue its frames again and again. view_bench runs
 * the same policy to measure the default. */
#ifndef VX_SVO_VIEW_BATCH_H
#define VX_SVO_VIEW_BATCH_H

#include <stdbool.h>
#include <stdint.h>

#define SV_BATCH_LATENCY_MS 1.0 /* the most a batch may delay a frame: far under a 240 Hz refresh (4.2 ms) */
#define SV_BATCH_HOLD 64        /* frames between two changes of the batch */
#define SV_BATCH_SAMPLES 8      /* the median of the last timed frames decides */
#define SV_BATCH_TIMED_EVERY 8  /* at least one frame in 8 is timed (the statistics panel's pass times) ... */
#define SV_BATCH_TIMED_MS 4.0   /* ... and at most one per 4 ms of frames: timestamps cost an H200 about 0.004 ms a
                                 * frame, 5% of a 0.08 ms frame when every frame has them, 0.6% at one in 8 */

typedef struct sv_batch {
    uint32_t max;                    /* the largest batch (the frames in flight allow 2 x max) */
    double latency_ms;               /* the most a batch may delay a frame (0: SV_BATCH_LATENCY_MS) */
    uint32_t cur;                    /* the batch in use (1 until frames were measured) */
    double ms[SV_BATCH_SAMPLES];     /* the last timed frames' GPU times */
    uint32_t n;                      /* samples taken (the ring's fill is min(n, SV_BATCH_SAMPLES)) */
    uint64_t frames, changed_at;     /* frames counted; the frame of the last change */
    uint64_t timed_at;               /* the frame sv_batch_timed last said yes to */
    bool timed_any;
} sv_batch;

/* A policy that may batch up to max frames (at least 1), delaying a frame
 * by at most latency_ms (0: SV_BATCH_LATENCY_MS). */
sv_batch sv_batch_make(uint32_t max, double latency_ms);
/* The batch for one frame of frame_ms of GPU time: 1 + floor(latency_ms /
 * frame_ms), in 1..max (latency_ms 0: SV_BATCH_LATENCY_MS); 1 for vsync or
 * a frame not measured (<= 0 or NaN). */
uint32_t sv_batch_for(double frame_ms, double latency_ms, bool vsync, uint32_t max);
/* A frame was recorded; frame_ms > 0: its GPU time was measured. */
void sv_batch_frame(sv_batch* b, double frame_ms);
/* The batch the next frame should use: b->cur, or a new one when the
 * median of the samples (at least 2) asks for another and SV_BATCH_HOLD frames have
 * passed since the last change (vsync: 1 at once). The caller applies it
 * (drains the held frames, vx_display_set_queue) and sets b->cur through
 * sv_batch_set. */
uint32_t sv_batch_want(const sv_batch* b, bool vsync);
void sv_batch_set(sv_batch* b, uint32_t batch);
/* Whether the frame about to be recorded (the one sv_batch_frame counts
 * next) writes its timestamps: one frame in SV_BATCH_TIMED_EVERY, fewer
 * for short frames (one per SV_BATCH_TIMED_MS of the last measured frame
 * time). Call once per frame. */
bool sv_batch_timed(sv_batch* b);

#endif
