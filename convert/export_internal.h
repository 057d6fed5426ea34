/* convert/export_internal.h - what the exports (export_glb.c, export_vdb.c)
 * share: a model's cells decoded into arrays, and sRGB bytes as linear
 * values. Private to convert/export*.c. */
#ifndef VX_CONV_EXPORT_INTERNAL_H
#define VX_CONV_EXPORT_INTERNAL_H

#include <stddef.h>
#include <stdint.h>

#include "svo/svo.h"

typedef struct vx__export_cells {
    uint32_t* xyz;  /* 3 per cell, model cells */
    uint32_t* rgba; /* RGBA8 per cell (vx_svo_attr_rgba) */
    uint32_t* attr; /* attribute record per cell */
    size_t n;
    const vx_allocator* alloc; /* of the arrays */
} vx__export_cells;

/* Decodes model m of s (in Morton order) with allocator a (NULL: malloc);
 * free with vx__export_cells_free. */
vx_result vx__export_cells_decode(const vx_allocator* a, const vx_svo_scene* s, uint32_t m, vx__export_cells* out,
                                  vx_error* err);
void vx__export_cells_free(vx__export_cells* c);

/* The sRGB transfer function's inverse for each byte value. */
void vx__export_srgb_to_linear(double lin[256]);

#endif
