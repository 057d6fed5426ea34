/* tests/fuzz/pnm_fuzz.c - libFuzzer target for voxkit's own image reader
 * (formats/image_pnm.c: .pfm, .ppm, .pgm; what svo_render reads for
 * --sky map:FILE.pfm). The input goes to a file under each of the three
 * names (the reader takes a path; the extension picks the format), is read
 * with a small size cap as both pixel types, and what was read is written
 * and read back to the same pixels. */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "formats/image.h"

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

static void one(const char* path, const uint8_t* data, size_t size) {
    FILE* f = fopen(path, "wb");
    if (!f) return;
    if (size && fwrite(data, 1, size, f) != size) abort();
    fclose(f);
    for (int t = 0; t < 2; t++) {
        uint32_t w, h, c;
        void* px = NULL;
        vx_error err;
        vx_image_type type = t ? VX_IMAGE_U8 : VX_IMAGE_F32;
        if (vx_image_read(path, type, 64, &w, &h, &c, &px, &err) != VX_OK) {
            if (px) abort(); /* a failed read returns no pixels */
            continue;
        }
        if (!px || !w || !h || w > 64 || h > 64 || (c != 1 && c != 3)) abort();
        /* what was read writes as the same format and reads back the same */
        char out[96];
        bool f32 = type == VX_IMAGE_F32;
        snprintf(out, sizeof out, "%s.back%s", path, f32 ? ".pfm" : c == 1 ? ".pgm" : ".ppm");
        if (vx_image_write(out, &(vx_image_desc){w, h, c, type, px}, &err) != VX_OK) abort();
        uint32_t w2, h2, c2;
        void* back = NULL;
        if (vx_image_read(out, type, 64, &w2, &h2, &c2, &back, &err) != VX_OK) abort();
        size_t bytes = (size_t)w * h * c * (f32 ? 4 : 1);
        if (w2 != w || h2 != h || c2 != c || memcmp(back, px, bytes)) abort();
        remove(out);
        vx_free(NULL, back);
        vx_free(NULL, px);
    }
    remove(path);
}

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    char path[64];
    static const char* ext[3] = {"pfm", "ppm", "pgm"};
    for (int e = 0; e < 3; e++) {
        snprintf(path, sizeof path, "/tmp/vx_pnm_fuzz.%d.%s", (int)getpid(), ext[e]);
        one(path, data, size);
    }
    return 0;
}
