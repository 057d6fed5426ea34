/* tests/fuzz/probes_fuzz.c - libFuzzer target for the .probes reader:
 * read (small limits so mutated sizes stay cheap) -> write back -> re-read
 * must succeed and give the same bytes -> free. Each input runs twice: as
 * given, then with every section's CRC-32 recomputed (the reader has no
 * switch to skip checksums; without the fix-up almost every mutation stops at
 * the CRC check and never reaches the GRID and DATA parsers). */
#include <stdlib.h>
#include <string.h>

#include "probes/probes.h"

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

static void one(const uint8_t* data, size_t size) {
    vx_error err;
    vx_probe_set ps;
    vx_probe_read_desc d = {.max_res = 64, .max_probes = 64};
    if (vx_probe_read(&d, data, size, &ps, &err) != VX_OK) return;
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
}

static uint32_t le32(const uint8_t* p) { return p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24; }

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    one(data, size);
    if (size < 16) return 0;
    uint8_t* c = (uint8_t*)malloc(size);
    if (!c) return 0;
    memcpy(c, data, size);
    bool changed = false;
    /* header: magic[8] version u32 sections u32; section: tag[4] crc u32 len u64 bytes */
    size_t at = 16;
    for (uint32_t s = 0, nsec = le32(c + 12); s < nsec && size - at >= 16; s++) {
        uint64_t len = le32(c + at + 8) | (uint64_t)le32(c + at + 12) << 32;
        if (len > size - at - 16) break;
        uint32_t crc = vx_crc32(0, c + at + 16, (size_t)len);
        if (crc != le32(c + at + 4)) {
            for (int k = 0; k < 4; k++) c[at + 4 + k] = (uint8_t)(crc >> (8 * k));
            changed = true;
        }
        at += 16 + (size_t)len;
    }
    if (changed) one(c, size);
    free(c);
    return 0;
}
