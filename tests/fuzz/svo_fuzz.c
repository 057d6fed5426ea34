/* tests/fuzz/svo_fuzz.c - libFuzzer target for the .svo reader:
 * probe -> read (checksums on, on the caller's thread; then off so mutations
 * reach the structure checks, on two threads so a chunked model's chunks
 * (FORMAT.md 3.6) inflate in parallel) -> validate -> decode with a work cap
 * -> the last animation frame's bounds -> free. A model the read accepts
 * must pass the full validation: the reader does not walk the models it
 * rebuilds from the structural form (vx__svo_check_rebuilt), it relies on
 * the reconstruction's own checks; a failure here aborts (a finding). */
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

#include "svo/svo.h"

static bool capped(void* user, uint32_t x, uint32_t y, uint32_t z, uint32_t attr) {
    (void)x, (void)y, (void)z, (void)attr;
    return --*(long*)user > 0;
}

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    vx_error err;
    vx_svo_file_info info;
    (void)vx_svo_probe(data, size, &info, &err);
    for (int skip = 0; skip < 2; skip++) {
        vx_svo_scene s;
        vx_svo_read_desc d = {.skip_checksums = skip != 0, .threads = skip ? 2u : 1u};
        if (vx_svo_read(&d, data, size, &s, &err) != VX_OK) continue;
        for (uint32_t i = 0; i < s.model_count; i++) {
            long budget = 1 << 16; /* a valid DAG may stand for 2^63 cells */
            if (vx_svo_validate_model(&s.models[i], &err) != VX_OK) abort();
            vx_svo_decode_model(&s.models[i], capped, &budget, &err);
            if (s.models[i].attr_count) (void)vx_svo_attr_color(&s, &s.models[i], s.models[i].root_attr);
        }
        vx_svo_scene_update_bounds(&s);
        vx_svo_scene last; /* an animation's last frame through the view */
        if (vx_svo_scene_frame(&s, vx_svo_scene_frames(&s) - 1, &last)) vx_svo_scene_update_bounds(&last);
        vx_svo_scene_free(&s);
        break;
    }
    return 0;
}
