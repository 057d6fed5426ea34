/* tools/svo_view/font.h - overlay drawing into an 8-bit frame on the CPU. */
#ifndef VX_SVO_VIEW_FONT_H
#define VX_SVO_VIEW_FONT_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

typedef struct vf_canvas {
    uint8_t* pixels; /* 4 bytes per pixel, rows top first */
    uint32_t width, height;
    bool bgra;       /* byte order B,G,R,A (else R,G,B,A) */
} vf_canvas;

/* rgba: R in bits 0..7; alpha 0..255 blends over the frame. */
void vf_fill_rect(vf_canvas* cv, int x, int y, int w, int h, uint32_t rgba, int alpha);
/* Draws text (5x7 glyphs on a 6x9 cell times scale); returns the end x. */
int vf_text(vf_canvas* cv, int x, int y, int scale, uint32_t rgba, const char* s);
void vf_line(vf_canvas* cv, double x0, double y0, double x1, double y1, uint32_t rgba, int thickness);

#endif
