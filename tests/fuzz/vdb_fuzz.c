/* tests/fuzz/vdb_fuzz.c - .vdb bytes -> OpenVDB shim -> svo scene -> validate.
 * Both cell rules run (fog/surface by grid class, then solid); a cell cap
 * keeps a mutated tile table from turning one input into minutes of work. */
#include <stddef.h>
#include <stdint.h>

#include "convert/volume.h"

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    for (int solid = 0; solid < 2; solid++) {
        vx_conv_vdb_desc d = {0};
        d.solid = solid != 0;
        d.density = true;
        d.color_grid = solid ? "Cd" : NULL; /* absent in most inputs: exercises the error path */
        d.max_cells = 1u << 20;
        vx_svo_scene s;
        vx_error err;
        if (vx_conv_vdb_memory(&d, data, size, &s, NULL, &err) == VX_OK) {
            (void)vx_svo_validate_scene(&s, NULL);
            vx_svo_scene_free(&s);
        }
    }
    return 0;
}
