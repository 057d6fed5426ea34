/* tests/fuzz/vox_fuzz.c - libFuzzer target for the .vox reader and writer:
 * read -> validate -> write -> read again. Whatever the reader accepts must
 * validate, write, and read back to the same counts; anything else is a bug
 * and traps so the fuzzer keeps the input. */
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

#include "formats/vox.h"

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    vx_vox_read_desc desc = {.keep_hidden = true};
    vx_vox_scene s;
    vx_error err;
    if (vx_vox_read(&desc, data, size, &s, &err) != VX_OK) return 0;
    if (vx_vox_validate(&s, &err) != VX_OK) __builtin_trap();
    uint8_t* out = NULL;
    size_t out_size = 0;
    if (vx_vox_write(&s, NULL, &out, &out_size, &err) != VX_OK) __builtin_trap();
    vx_vox_scene s2;
    if (vx_vox_read(&desc, out, out_size, &s2, &err) != VX_OK) __builtin_trap();
    if (s2.model_count != s.model_count || s2.instance_count != s.instance_count ||
        s2.material_count != s.material_count || s2.layer_count != s.layer_count)
        __builtin_trap();
    vx_vox_scene_free(&s2);
    vx_free(NULL, out);
    vx_vox_scene_free(&s);
    return 0;
}
