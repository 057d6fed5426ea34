/* tools/svo_view/font.h - overlay drawing into an 8-bit frame on the CPU. */
#ifndef VX_SVO_VIEW_FONT_H
#define VX_SVO_VIEW_FONT_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Drawing blends over the pixels by each primitive's alpha and accumulates
 * the coverage in byte 3: over a frame (byte 3 = 255) that stays 255; over a
 * zeroed canvas the result is an overlay of premultiplied colour and
 * coverage (render/display.h lays it over the frame on the GPU). */
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

/* Textured, coloured triangles (what Dear ImGui draws: tools/svo_view/ui.h)
 * rasterized on the CPU: the pixel centres inside each triangle and inside
 * clip = {x0, y0, x1, y1} get colour * texel blended over the frame by its
 * alpha. Colours interpolate across the triangle; the texture is an alpha
 * map sampled at the nearest texel (the font atlas: white with coverage in
 * alpha). The layout is Dear ImGui's ImDrawVert (the shim checks it). */
typedef struct vf_vertex {
    float x, y, u, v;
    uint32_t rgba; /* R in bits 0..7 */
} vf_vertex;
typedef struct vf_texture {
    const uint8_t* alpha; /* width * height bytes */
    uint32_t width, height;
} vf_texture;
void vf_triangles(vf_canvas* cv, const vf_vertex* vtx, const uint16_t* idx, uint32_t index_count, const float clip[4],
                  const vf_texture* tex);

#ifdef __cplusplus
}
#endif
#endif
