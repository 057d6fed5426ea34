/* formats/image_pnm.c - the portable float map (.pfm: "Pf" one channel,
 * "PF" three, little-endian, rows bottom to top) and the portable pixmaps
 * (.pgm "P5" one channel, .ppm "P6" three, 8 bits), written and read by
 * voxkit itself in every build (Debian's OpenImageIO has no PFM writer), and
 * the whole of formats/image.h where VX_WITH_OIIO is off, so that svo_render
 * and svo_bake run on machines without OpenImageIO (the GPU machines: their
 * output is compared with cmp, which these formats allow: the same pixels
 * give the same bytes). Channel counts these formats do not hold are errors
 * naming the file: nothing is converted silently. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "formats/image.h"
#include "formats/image_pnm.h"

char vx__image_pnm_kind(const char* path) {
    const char* dot = strrchr(path, '.');
    const char* slash = strrchr(path, '/');
    if (!dot || (slash && dot < slash)) return 0;
    if (!strcmp(dot, ".pfm") || !strcmp(dot, ".PFM")) return 'f';
    if (!strcmp(dot, ".pgm") || !strcmp(dot, ".PGM")) return 'g';
    if (!strcmp(dot, ".ppm") || !strcmp(dot, ".PPM")) return 'p';
    return 0;
}

vx_result vx__image_desc_check(const char* path, const vx_image_desc* img, vx_error* err) {
    if (!path || !img || !img->pixels) return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    if (img->width == 0 || img->height == 0 || img->width > 65536 || img->height > 65536 || img->channels < 1 ||
        img->channels > 4)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "%s: bad image shape %ux%ux%u", path, img->width,
                       img->height, img->channels);
    return VX_OK;
}

vx_result vx__image_pnm_write(const char* path, const vx_image_desc* img, vx_error* err) {
    vx_result bad = vx__image_desc_check(path, img, err);
    if (bad) return bad;
    char kind = vx__image_pnm_kind(path);
    if (!kind) return vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET, "%s: not a .pfm, .ppm or .pgm name", path);
    bool f32 = img->type == VX_IMAGE_F32;
    if ((kind == 'f') != f32)
        return vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET, "%s: %s pixels need a %s file", path,
                       f32 ? "float" : "8-bit", f32 ? ".pfm" : ".ppm or .pgm");
    uint32_t want = kind == 'g' ? 1 : kind == 'p' ? 3 : (img->channels == 1 ? 1 : 3);
    if (img->channels != want)
        return vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET, "%s: %u channels do not fit this format (it holds %s)",
                       path, img->channels, kind == 'f' ? "1 or 3" : kind == 'g' ? "1" : "3");
    char head[64];
    int hn = kind == 'f' ? snprintf(head, sizeof head, "P%c\n%u %u\n-1.0\n", want == 1 ? 'f' : 'F', img->width,
                                    img->height)
                         : snprintf(head, sizeof head, "P%c\n%u %u\n255\n", kind == 'g' ? '5' : '6', img->width,
                                    img->height);
    size_t row = (size_t)img->width * want * (f32 ? 4 : 1); /* at most 65536 * 3 * 4 */
    vx_atomic_file af;
    vx_result r = vx_atomic_open(&af, path, NULL, err);
    if (r != VX_OK) return r;
    bool ok = vx_atomic_write(&af, head, (size_t)hn);
    for (uint32_t y = 0; ok && y < img->height; y++) {
        /* PFM stores the bottom row first; the float bytes are written as the
         * machine holds them, which the "-1.0" scale declares little-endian
         * (every platform voxkit builds on) */
        uint32_t src = kind == 'f' ? img->height - 1 - y : y;
        ok = vx_atomic_write(&af, (const uint8_t*)img->pixels + (size_t)src * row, row);
    }
    if (!ok) {
        vx_atomic_abort(&af);
        return vx_fail(err, VX_ERR_IO, VX_NO_OFFSET, "%s: write failed", path);
    }
    return vx_atomic_commit(&af, err);
}

/* One header token (PNM: whitespace separated, '#' comments to the line's
 * end); false at the end or on a token longer than the buffer. */
static bool token(const uint8_t* d, size_t n, size_t* at, char* out, size_t cap) {
    size_t i = *at;
    for (;;) {
        while (i < n && (d[i] == ' ' || d[i] == '\t' || d[i] == '\n' || d[i] == '\r')) i++;
        if (i < n && d[i] == '#') {
            while (i < n && d[i] != '\n') i++;
            continue;
        }
        break;
    }
    size_t k = 0;
    while (i < n && !(d[i] == ' ' || d[i] == '\t' || d[i] == '\n' || d[i] == '\r')) {
        if (k + 1 >= cap) return false;
        out[k++] = (char)d[i++];
    }
    out[k] = 0;
    if (!k || i >= n) return false;
    *at = i + 1; /* exactly one whitespace byte ends the header's last token */
    return true;
}

static bool parse_u32(const char* s, uint32_t* v) {
    char* end;
    unsigned long x = strtoul(s, &end, 10);
    if (*s < '0' || *s > '9' || *end || x > 0xFFFFFFFFul) return false;
    *v = (uint32_t)x;
    return true;
}

vx_result vx__image_pnm_read(const char* path, vx_image_type type, uint32_t max_dim, uint32_t* width,
                             uint32_t* height, uint32_t* channels, void** out_pixels, vx_error* err) {
    if (!path || !width || !height || !channels || !out_pixels)
        return vx_fail(err, VX_ERR_INVALID_ARG, VX_NO_OFFSET, "NULL argument");
    *out_pixels = NULL;
    if (!max_dim) max_dim = 16384;
    if (!vx__image_pnm_kind(path))
        return vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET, "%s: not a .pfm, .ppm or .pgm name", path);
    uint8_t* d = NULL;
    size_t n = 0;
    /* the largest file the limits allow: 3 float channels of max_dim^2 plus a header */
    uint64_t cap = (uint64_t)max_dim * max_dim * 12 + 256;
    vx_result r = vx_file_read(path, NULL, cap, &d, &n, err);
    if (r != VX_OK) return r;
    char magic[8], ws[16], hs[16], ms[32];
    size_t at = 0;
    uint32_t w = 0, h = 0, maxv = 0, ch = 0;
    bool pf = false;
    if (!token(d, n, &at, magic, sizeof magic) || !token(d, n, &at, ws, sizeof ws) ||
        !token(d, n, &at, hs, sizeof hs) || !token(d, n, &at, ms, sizeof ms) || !parse_u32(ws, &w) ||
        !parse_u32(hs, &h)) {
        r = vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "%s: not a PFM/PPM/PGM header", path);
        goto out;
    }
    if (!strcmp(magic, "Pf") || !strcmp(magic, "PF")) {
        pf = true;
        ch = magic[1] == 'f' ? 1 : 3;
        char* end;
        double scale = strtod(ms, &end);
        if (*end || !(scale < 0)) { /* big-endian (positive) maps are not read */
            r = vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET, "%s: PFM scale %s: only little-endian maps are read",
                        path, ms);
            goto out;
        }
    } else if (!strcmp(magic, "P5") || !strcmp(magic, "P6")) {
        ch = magic[1] == '5' ? 1 : 3;
        if (!parse_u32(ms, &maxv) || maxv != 255) {
            r = vx_fail(err, VX_ERR_UNSUPPORTED, VX_NO_OFFSET, "%s: only 8-bit pixmaps (maximum 255) are read", path);
            goto out;
        }
    } else {
        r = vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "%s: unknown magic '%s'", path, magic);
        goto out;
    }
    if (!w || !h || w > max_dim || h > max_dim) {
        r = vx_fail(err, VX_ERR_LIMIT, VX_NO_OFFSET, "%s: image %ux%u outside the limits (1..%u a side)", path, w, h,
                    max_dim);
        goto out;
    }
    size_t count = (size_t)w * h * ch, in_size = count * (pf ? 4 : 1);
    if (n - at != in_size) {
        r = vx_fail(err, VX_ERR_BAD_FORMAT, VX_NO_OFFSET, "%s: %zu bytes of pixels, %ux%ux%u need %zu", path, n - at, w,
                    h, ch, in_size);
        goto out;
    }
    void* px = vx_calloc(NULL, count, type == VX_IMAGE_F32 ? 4 : 1);
    if (!px) {
        r = vx_fail(err, VX_ERR_NOMEM, VX_NO_OFFSET, "%s: out of memory", path);
        goto out;
    }
    for (size_t i = 0; i < count; i++) {
        size_t y = i / ((size_t)w * ch), rest = i % ((size_t)w * ch);
        size_t src = pf ? (h - 1 - y) * (size_t)w * ch + rest : i; /* PFM: bottom row first */
        float v;
        if (pf)
            memcpy(&v, d + at + 4 * src, 4);
        else
            v = d[at + src] / 255.0f;
        if (type == VX_IMAGE_F32)
            ((float*)px)[i] = v;
        else
            ((uint8_t*)px)[i] = pf ? (uint8_t)(v != v || v <= 0 ? 0 : v >= 1 ? 255 : (int)(v * 255.0f + 0.5f))
                                   : d[at + src];
    }
    *width = w, *height = h, *channels = ch, *out_pixels = px;
out:
    vx_free(NULL, d);
    return r;
}
