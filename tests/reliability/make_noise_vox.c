/* tests/reliability/make_noise_vox.c - writes a .vox scene that takes
 * vox2svo a noticeable time and gives a large .svo: MODELS models of
 * SIZE^3 cells, each cell set with probability 1/2 in a random palette
 * colour (xorshift, fixed seed: the same bytes every time), so neither
 * collapse nor the DAG can shrink it; one group places every model.
 * Usage: make_noise_vox OUT.vox [MODELS [SIZE [SEED]]] (default 2 160 1). */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static FILE* f;
static void u32(uint32_t v) {
    uint8_t b[4] = {(uint8_t)v, (uint8_t)(v >> 8), (uint8_t)(v >> 16), (uint8_t)(v >> 24)};
    fwrite(b, 1, 4, f);
}
static void chunk(const char* id, uint32_t content) {
    fwrite(id, 1, 4, f);
    u32(content);
    u32(0);
}
static void str(const char* s) {
    u32((uint32_t)strlen(s));
    fwrite(s, 1, strlen(s), f);
}

int main(int argc, char** argv) {
    if (argc < 2) {
        fprintf(stderr, "usage: make_noise_vox OUT.vox [MODELS [SIZE [SEED]]]\n");
        return 2;
    }
    uint32_t models = argc > 2 ? (uint32_t)atoi(argv[2]) : 2, size = argc > 3 ? (uint32_t)atoi(argv[3]) : 160;
    uint64_t s = argc > 4 ? strtoull(argv[4], NULL, 10) : 1;
    s = s * 0x9E3779B97F4A7C15ull + 1;
    if (models < 1 || models > 64 || size < 1 || size > 256) return 2;
    size_t cells = (size_t)size * size * size;
    uint8_t* xyzi = malloc(cells * 4);
    f = fopen(argv[1], "wb");
    if (!xyzi || !f) return 1;
    fwrite("VOX ", 1, 4, f);
    u32(200);
    long main_at = ftell(f);
    chunk("MAIN", 0);
    for (uint32_t m = 0; m < models; m++) {
        uint32_t n = 0;
        for (uint32_t z = 0; z < size; z++)
            for (uint32_t y = 0; y < size; y++)
                for (uint32_t x = 0; x < size; x++) {
                    s ^= s << 13, s ^= s >> 7, s ^= s << 17;
                    if (s & 1) continue;
                    uint8_t* v = xyzi + 4 * (size_t)n++;
                    v[0] = (uint8_t)x, v[1] = (uint8_t)y, v[2] = (uint8_t)z, v[3] = (uint8_t)(1 + (s >> 8) % 255);
                }
        chunk("SIZE", 12);
        u32(size), u32(size), u32(size);
        chunk("XYZI", 4 + 4 * n);
        u32(n);
        fwrite(xyzi, 4, n, f);
    }
    /* nTRN 0 -> nGRP 1 -> (nTRN 2+2m -> nSHP 3+2m) per model, side by side */
    chunk("nTRN", 28);
    u32(0), u32(0), u32(1), u32(UINT32_MAX), u32(UINT32_MAX), u32(1), u32(0);
    chunk("nGRP", 12 + 4 * models);
    u32(1), u32(0), u32(models);
    for (uint32_t m = 0; m < models; m++) u32(2 + 2 * m);
    for (uint32_t m = 0; m < models; m++) {
        char t[64];
        snprintf(t, sizeof t, "%u 0 0", m * (size + 2));
        chunk("nTRN", 24 + 4 + 6 + 4 + (uint32_t)strlen(t));
        u32(2 + 2 * m), u32(0), u32(3 + 2 * m), u32(UINT32_MAX), u32(UINT32_MAX), u32(1);
        u32(1), str("_t"), str(t);
        chunk("nSHP", 20);
        u32(3 + 2 * m), u32(0), u32(1), u32(m), u32(0);
    }
    chunk("RGBA", 1024);
    for (uint32_t i = 0; i < 256; i++) u32(0xFF000000u | (i * 2654435761u & 0xFFFFFFu));
    long end = ftell(f);
    fseek(f, main_at + 8, SEEK_SET);
    u32((uint32_t)(end - main_at - 12));
    free(xyzi);
    return fclose(f) == 0 ? 0 : 1;
}
