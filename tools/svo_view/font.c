/* tools/svo_view/font.c - a tiny 5x7 bitmap font for the overlay, drawn on
 * the CPU into the RGBA8 frame before it is copied to the swapchain (no
 * extra pipeline; the overlay costs a few microseconds per line). */
#include "tools/svo_view/font.h"

#include <ctype.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>

typedef struct glyph {
    char c;
    uint8_t rows[7]; /* bit 4 is the leftmost column */
} glyph;

static const glyph glyphs[] = {
    {'0', {0x0E, 0x11, 0x13, 0x15, 0x19, 0x11, 0x0E}}, {'1', {0x04, 0x0C, 0x04, 0x04, 0x04, 0x04, 0x0E}},
    {'2', {0x0E, 0x11, 0x01, 0x02, 0x04, 0x08, 0x1F}}, {'3', {0x1F, 0x02, 0x04, 0x02, 0x01, 0x11, 0x0E}},
    {'4', {0x02, 0x06, 0x0A, 0x12, 0x1F, 0x02, 0x02}}, {'5', {0x1F, 0x10, 0x1E, 0x01, 0x01, 0x11, 0x0E}},
    {'6', {0x06, 0x08, 0x10, 0x1E, 0x11, 0x11, 0x0E}}, {'7', {0x1F, 0x01, 0x02, 0x04, 0x08, 0x08, 0x08}},
    {'8', {0x0E, 0x11, 0x11, 0x0E, 0x11, 0x11, 0x0E}}, {'9', {0x0E, 0x11, 0x11, 0x0F, 0x01, 0x02, 0x0C}},
    {'A', {0x0E, 0x11, 0x11, 0x1F, 0x11, 0x11, 0x11}}, {'B', {0x1E, 0x11, 0x11, 0x1E, 0x11, 0x11, 0x1E}},
    {'C', {0x0E, 0x11, 0x10, 0x10, 0x10, 0x11, 0x0E}}, {'D', {0x1C, 0x12, 0x11, 0x11, 0x11, 0x12, 0x1C}},
    {'E', {0x1F, 0x10, 0x10, 0x1E, 0x10, 0x10, 0x1F}}, {'F', {0x1F, 0x10, 0x10, 0x1E, 0x10, 0x10, 0x10}},
    {'G', {0x0E, 0x11, 0x10, 0x17, 0x11, 0x11, 0x0F}}, {'H', {0x11, 0x11, 0x11, 0x1F, 0x11, 0x11, 0x11}},
    {'I', {0x0E, 0x04, 0x04, 0x04, 0x04, 0x04, 0x0E}}, {'J', {0x07, 0x02, 0x02, 0x02, 0x02, 0x12, 0x0C}},
    {'K', {0x11, 0x12, 0x14, 0x18, 0x14, 0x12, 0x11}}, {'L', {0x10, 0x10, 0x10, 0x10, 0x10, 0x10, 0x1F}},
    {'M', {0x11, 0x1B, 0x15, 0x15, 0x11, 0x11, 0x11}}, {'N', {0x11, 0x11, 0x19, 0x15, 0x13, 0x11, 0x11}},
    {'O', {0x0E, 0x11, 0x11, 0x11, 0x11, 0x11, 0x0E}}, {'P', {0x1E, 0x11, 0x11, 0x1E, 0x10, 0x10, 0x10}},
    {'Q', {0x0E, 0x11, 0x11, 0x11, 0x15, 0x12, 0x0D}}, {'R', {0x1E, 0x11, 0x11, 0x1E, 0x14, 0x12, 0x11}},
    {'S', {0x0F, 0x10, 0x10, 0x0E, 0x01, 0x01, 0x1E}}, {'T', {0x1F, 0x04, 0x04, 0x04, 0x04, 0x04, 0x04}},
    {'U', {0x11, 0x11, 0x11, 0x11, 0x11, 0x11, 0x0E}}, {'V', {0x11, 0x11, 0x11, 0x11, 0x11, 0x0A, 0x04}},
    {'W', {0x11, 0x11, 0x11, 0x15, 0x15, 0x15, 0x0A}}, {'X', {0x11, 0x11, 0x0A, 0x04, 0x0A, 0x11, 0x11}},
    {'Y', {0x11, 0x11, 0x11, 0x0A, 0x04, 0x04, 0x04}}, {'Z', {0x1F, 0x01, 0x02, 0x04, 0x08, 0x10, 0x1F}},
    {'.', {0x00, 0x00, 0x00, 0x00, 0x00, 0x0C, 0x0C}}, {',', {0x00, 0x00, 0x00, 0x00, 0x0C, 0x04, 0x08}},
    {':', {0x00, 0x0C, 0x0C, 0x00, 0x0C, 0x0C, 0x00}}, {';', {0x00, 0x0C, 0x0C, 0x00, 0x0C, 0x04, 0x08}},
    {'/', {0x00, 0x01, 0x02, 0x04, 0x08, 0x10, 0x00}}, {'%', {0x18, 0x19, 0x02, 0x04, 0x08, 0x13, 0x03}},
    {'(', {0x02, 0x04, 0x08, 0x08, 0x08, 0x04, 0x02}}, {')', {0x08, 0x04, 0x02, 0x02, 0x02, 0x04, 0x08}},
    {'[', {0x0E, 0x08, 0x08, 0x08, 0x08, 0x08, 0x0E}}, {']', {0x0E, 0x02, 0x02, 0x02, 0x02, 0x02, 0x0E}},
    {'-', {0x00, 0x00, 0x00, 0x1F, 0x00, 0x00, 0x00}}, {'+', {0x00, 0x04, 0x04, 0x1F, 0x04, 0x04, 0x00}},
    {'=', {0x00, 0x00, 0x1F, 0x00, 0x1F, 0x00, 0x00}}, {'_', {0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x1F}},
    {'\'', {0x04, 0x04, 0x08, 0x00, 0x00, 0x00, 0x00}}, {'"', {0x0A, 0x0A, 0x00, 0x00, 0x00, 0x00, 0x00}},
    {'!', {0x04, 0x04, 0x04, 0x04, 0x04, 0x00, 0x04}}, {'?', {0x0E, 0x11, 0x01, 0x02, 0x04, 0x00, 0x04}},
    {'<', {0x02, 0x04, 0x08, 0x10, 0x08, 0x04, 0x02}}, {'>', {0x08, 0x04, 0x02, 0x01, 0x02, 0x04, 0x08}},
    {'#', {0x0A, 0x0A, 0x1F, 0x0A, 0x1F, 0x0A, 0x0A}}, {'*', {0x00, 0x04, 0x15, 0x0E, 0x15, 0x04, 0x00}},
    {'@', {0x0E, 0x11, 0x17, 0x15, 0x17, 0x10, 0x0F}}, {'x', {0x00, 0x00, 0x11, 0x0A, 0x04, 0x0A, 0x11}},
};

static const uint8_t* find_glyph(char c) {
    if (c != 'x') c = (char)toupper((unsigned char)c);
    for (size_t i = 0; i < sizeof glyphs / sizeof glyphs[0]; i++)
        if (glyphs[i].c == c) return glyphs[i].rows;
    return NULL;
}

void vf_fill_rect(vf_canvas* cv, int x0, int y0, int w, int h, uint32_t rgba, int alpha) {
    for (int y = y0 < 0 ? 0 : y0; y < y0 + h && y < (int)cv->height; y++)
        for (int x = x0 < 0 ? 0 : x0; x < x0 + w && x < (int)cv->width; x++) {
            uint8_t* p = cv->pixels + 4 * ((size_t)y * cv->width + (size_t)x);
            for (int k = 0; k < 3; k++) {
                int src = (int)((rgba >> (8 * k)) & 0xFFu);
                int ch = cv->bgra && k != 1 ? 2 - k : k;
                p[ch] = (uint8_t)((src * alpha + p[ch] * (255 - alpha)) / 255);
            }
            p[3] = (uint8_t)((255 * alpha + p[3] * (255 - alpha)) / 255); /* coverage (an overlay: header) */
        }
}

int vf_text(vf_canvas* cv, int x, int y, int scale, uint32_t rgba, const char* s) {
    if (scale < 1) scale = 1;
    int x0 = x;
    for (; *s; s++) {
        if (*s == '\n') {
            y += 9 * scale;
            x = x0;
            continue;
        }
        const uint8_t* g = find_glyph(*s);
        for (int r = 0; g && r < 7; r++)
            for (int c = 0; c < 5; c++)
                if (g[r] & (0x10 >> c)) vf_fill_rect(cv, x + c * scale, y + r * scale, scale, scale, rgba, 255);
        x += 6 * scale;
    }
    return x;
}

void vf_line(vf_canvas* cv, double x0, double y0, double x1, double y1, uint32_t rgba, int thickness) {
    double dx = x1 - x0, dy = y1 - y0;
    double len = dx * dx + dy * dy;
    int steps = (int)(len > 0 ? sqrt(len) : 0) + 1;
    if (steps > 100000) steps = 100000; /* a projected corner far off screen */
    for (int i = 0; i <= steps; i++) {
        double t = (double)i / steps;
        int x = (int)(x0 + dx * t), y = (int)(y0 + dy * t);
        vf_fill_rect(cv, x - thickness / 2, y - thickness / 2, thickness, thickness, rgba, 255);
    }
}

/* Twice the signed area of (a, b, p): the edge function of a triangle. */
static float edge(const vf_vertex* a, const vf_vertex* b, float px, float py) {
    return (b->x - a->x) * (py - a->y) - (b->y - a->y) * (px - a->x);
}

static void triangle(vf_canvas* cv, const vf_vertex* v0, const vf_vertex* v1, const vf_vertex* v2, const float clip[4],
                     const vf_texture* tex) {
    float area = edge(v0, v1, v2->x, v2->y);
    if (!(fabsf(area) > 1e-12f)) return; /* degenerate (or NaN) */
    float x0 = fminf(v0->x, fminf(v1->x, v2->x)), x1 = fmaxf(v0->x, fmaxf(v1->x, v2->x));
    float y0 = fminf(v0->y, fminf(v1->y, v2->y)), y1 = fmaxf(v0->y, fmaxf(v1->y, v2->y));
    x0 = fmaxf(x0, fmaxf(clip[0], 0)), y0 = fmaxf(y0, fmaxf(clip[1], 0));
    x1 = fminf(x1, fminf(clip[2], (float)cv->width)), y1 = fminf(y1, fminf(clip[3], (float)cv->height));
    if (!(x0 < x1 && y0 < y1)) return;
    /* pixel centres px + 0.5 in [x0, x1) */
    int ix0 = (int)ceilf(x0 - 0.5f), ix1 = (int)ceilf(x1 - 0.5f), iy0 = (int)ceilf(y0 - 0.5f), iy1 = (int)ceilf(y1 - 0.5f);
    float inv = 1.0f / area;
    /* a rectangle of one colour and one texel (most of ImGui's fills) skips the interpolation */
    bool flat = v0->rgba == v1->rgba && v1->rgba == v2->rgba && v0->u == v1->u && v1->u == v2->u && v0->v == v1->v &&
                v1->v == v2->v;
    int r = cv->bgra ? 2 : 0, b = cv->bgra ? 0 : 2;
    /* A flat triangle of some size (ImGui's window and widget backgrounds)
     * blends every pixel with one colour and alpha: the blend of each
     * possible byte is tabulated once (the same lrintf of the same float
     * expression, so the same bytes) instead of evaluated per pixel. */
    uint8_t lut[4][256];
    bool use_lut = false;
    if (flat && (float)(ix1 - ix0) * (float)(iy1 - iy0) >= 256.0f) {
        float c[4], alpha;
        for (int k = 0; k < 4; k++) c[k] = (float)((v0->rgba >> (8 * k)) & 0xFF);
        alpha = c[3] / 255.0f;
        if (tex && tex->alpha) {
            long tx = lrintf(v0->u * (float)tex->width - 0.5f), ty = lrintf(v0->v * (float)tex->height - 0.5f);
            tx = tx < 0 ? 0 : (tx >= (long)tex->width ? (long)tex->width - 1 : tx);
            ty = ty < 0 ? 0 : (ty >= (long)tex->height ? (long)tex->height - 1 : ty);
            alpha *= tex->alpha[(size_t)ty * tex->width + (size_t)tx] / 255.0f;
        }
        if (!(alpha > 0)) return;
        for (int d = 0; d < 256; d++) {
            for (int k = 0; k < 3; k++) lut[k][d] = (uint8_t)lrintf((float)d + (c[k] - (float)d) * alpha);
            lut[3][d] = (uint8_t)lrintf((float)d + (255 - (float)d) * alpha);
        }
        use_lut = true;
    }
    /* Samples sit a hair off the pixel centre, in a direction no edge of ImGui's
     * (integer corners, 45-degree diagonals) runs along: a centre on the
     * shared diagonal of a quad's two triangles then falls in exactly one of
     * them, and a translucent fill is not blended twice there. */
    for (int y = iy0; y < iy1; y++) {
        float py = (float)y + 0.5f + 1.0f / 2048;
        for (int x = ix0; x < ix1; x++) {
            float px = (float)x + 0.5f + 1.0f / 1024;
            float w0 = edge(v1, v2, px, py) * inv, w1 = edge(v2, v0, px, py) * inv, w2 = 1.0f - w0 - w1;
            if (w0 < 0 || w1 < 0 || w2 < 0) continue;
            if (use_lut) {
                uint8_t* d = cv->pixels + 4 * ((size_t)y * cv->width + (size_t)x);
                d[r] = lut[0][d[r]], d[1] = lut[1][d[1]], d[b] = lut[2][d[b]], d[3] = lut[3][d[3]];
                continue;
            }
            float c[4], u, v;
            if (flat) {
                for (int k = 0; k < 4; k++) c[k] = (float)((v0->rgba >> (8 * k)) & 0xFF);
                u = v0->u, v = v0->v;
            } else {
                for (int k = 0; k < 4; k++)
                    c[k] = w0 * (float)((v0->rgba >> (8 * k)) & 0xFF) + w1 * (float)((v1->rgba >> (8 * k)) & 0xFF) +
                           w2 * (float)((v2->rgba >> (8 * k)) & 0xFF);
                u = w0 * v0->u + w1 * v1->u + w2 * v2->u, v = w0 * v0->v + w1 * v1->v + w2 * v2->v;
            }
            float alpha = c[3] / 255.0f;
            if (tex && tex->alpha) {
                long tx = lrintf(u * (float)tex->width - 0.5f), ty = lrintf(v * (float)tex->height - 0.5f);
                tx = tx < 0 ? 0 : (tx >= (long)tex->width ? (long)tex->width - 1 : tx);
                ty = ty < 0 ? 0 : (ty >= (long)tex->height ? (long)tex->height - 1 : ty);
                alpha *= tex->alpha[(size_t)ty * tex->width + (size_t)tx] / 255.0f;
            }
            if (!(alpha > 0)) continue;
            uint8_t* d = cv->pixels + 4 * ((size_t)y * cv->width + (size_t)x);
            d[r] = (uint8_t)lrintf(d[r] + (c[0] - d[r]) * alpha);
            d[1] = (uint8_t)lrintf(d[1] + (c[1] - d[1]) * alpha);
            d[b] = (uint8_t)lrintf(d[b] + (c[2] - d[b]) * alpha);
            d[3] = (uint8_t)lrintf(d[3] + (255 - d[3]) * alpha);
        }
    }
}

void vf_triangles(vf_canvas* cv, const vf_vertex* vtx, const uint16_t* idx, uint32_t index_count, const float clip[4],
                  const vf_texture* tex) {
    for (uint32_t i = 0; i + 2 < index_count; i += 3) triangle(cv, &vtx[idx[i]], &vtx[idx[i + 1]], &vtx[idx[i + 2]], clip, tex);
}
