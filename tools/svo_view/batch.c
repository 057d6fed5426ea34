/* tools/svo_view/batch.c - the default batch of frames a submission (batch.h). */
#include "batch.h"

#include <string.h>

sv_batch sv_batch_make(uint32_t max, double latency_ms) {
    sv_batch b;
    memset(&b, 0, sizeof b);
    b.max = max ? max : 1;
    b.latency_ms = latency_ms > 0 ? latency_ms : SV_BATCH_LATENCY_MS;
    b.cur = 1;
    return b;
}

uint32_t sv_batch_for(double frame_ms, double latency_ms, bool vsync, uint32_t max) {
    if (vsync || !(frame_ms > 0) || max <= 1) return 1; /* NaN counts as unmeasured */
    double k = 1.0 + (latency_ms > 0 ? latency_ms : SV_BATCH_LATENCY_MS) / frame_ms;
    return k >= (double)max ? max : (uint32_t)k;
}

void sv_batch_frame(sv_batch* b, double frame_ms) {
    b->frames++;
    if (frame_ms > 0) b->ms[b->n++ % SV_BATCH_SAMPLES] = frame_ms;
}

static double median_of(const double* v, uint32_t n) {
    double s[SV_BATCH_SAMPLES];
    memcpy(s, v, n * sizeof *s);
    for (uint32_t i = 1; i < n; i++) /* insertion sort: at most 8 values */
        for (uint32_t j = i; j > 0 && s[j - 1] > s[j]; j--) {
            double t = s[j];
            s[j] = s[j - 1], s[j - 1] = t;
        }
    return n % 2 ? s[n / 2] : 0.5 * (s[n / 2 - 1] + s[n / 2]);
}

uint32_t sv_batch_want(const sv_batch* b, bool vsync) {
    if (vsync) return 1; /* the display paces the frames: a batch would only add latency */
    uint32_t n = b->n < SV_BATCH_SAMPLES ? b->n : SV_BATCH_SAMPLES;
    if (n < 2 || b->frames - b->changed_at < SV_BATCH_HOLD) return b->cur;
    return sv_batch_for(median_of(b->ms, n), b->latency_ms, false, b->max);
}

void sv_batch_set(sv_batch* b, uint32_t batch) {
    if (batch == b->cur) return;
    b->cur = batch;
    b->changed_at = b->frames;
}

bool sv_batch_timed(sv_batch* b) {
    uint64_t every = SV_BATCH_TIMED_EVERY;
    if (b->n) { /* the last measured frame */
        double last = b->ms[(b->n - 1) % SV_BATCH_SAMPLES];
        double k = SV_BATCH_TIMED_MS / last;
        if (k > (double)every) every = k > 1e6 ? 1000000 : (uint64_t)k;
    }
    if (b->timed_any && b->frames - b->timed_at < every) return false;
    b->timed_any = true;
    b->timed_at = b->frames;
    return true;
}
