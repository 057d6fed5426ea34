/* tools/svo_info/cells.h - what the exports (--to-glb, --to-vdb) share: a
 * model's cells decoded into arrays, and sRGB bytes as linear values. */
#ifndef VX_SVO_INFO_CELLS_H
#define VX_SVO_INFO_CELLS_H

#include <stddef.h>
#include <stdint.h>

#include "svo/svo.h"

typedef struct svo_cells {
    uint32_t* xyz;  /* 3 per cell, model cells */
    uint32_t* rgba; /* RGBA8 per cell (vx_svo_attr_rgba) */
    uint32_t* attr; /* attribute record per cell */
    size_t n;
    const vx_allocator* alloc; /* of the arrays */
} svo_cells;

/* Decodes model m of s (in Morton order) with allocator a (NULL: malloc);
 * free with svo_cells_free. */
vx_result svo_cells_decode(const vx_allocator* a, const vx_svo_scene* s, uint32_t m, svo_cells* out, vx_error* err);
void svo_cells_free(svo_cells* c);

/* The sRGB transfer function's inverse for each byte value. */
void svo_srgb_to_linear(double lin[256]);

#endif
