/* tests/fuzz/probes_fuzz.c - libFuzzer target for the .probes reader:
 * read (small limits so mutated sizes stay cheap) -> write back -> re-read
 * must succeed and give the same bytes -> free. */
#include <stdlib.h>
#include <string.h>

#include "probes/probes.h"

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    vx_error err;
    vx_probe_set ps;
    vx_probe_read_desc d = {.max_res = 64, .max_probes = 64};
    if (vx_probe_read(&d, data, size, &ps, &err) != VX_OK) return 0;
    uint8_t* out = NULL;
    size_t n = 0;
    if (vx_probe_write(&ps, NULL, &out, &n, &err) == VX_OK) {
        vx_probe_set back;
        /* what the reader accepted, the writer reproduces readably */
        if (vx_probe_read(&d, out, n, &back, &err) != VX_OK) abort();
        uint8_t* again = NULL;
        size_t n2 = 0;
        if (vx_probe_write(&back, NULL, &again, &n2, &err) != VX_OK || n2 != n || memcmp(out, again, n)) abort();
        free(again);
        vx_probe_set_free(&back);
    }
    free(out);
    vx_probe_set_free(&ps);
    return 0;
}
