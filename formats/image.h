/* formats/image.h - image files through OpenImageIO (PNG for 8-bit outputs,
 * EXR for float outputs), behind a small C interface. .pfm (float, 1 or 3
 * channels), .ppm and .pgm (8 bits) are written and read by voxkit's own
 * code in every build; a build without OpenImageIO (VX_WITH_OIIO off)
 * handles only those three and names the file for any other.
 *
 * Pixels are row-major, row 0 at the top, channels interleaved. The format
 * follows the file name's extension (.png, .exr, also .tif, .jpg, ...).
 * Writing goes through a temporary file in the same folder that is renamed
 * over the path only when complete, so a failure leaves no partial image.
 */
#ifndef VX_IMAGE_H
#define VX_IMAGE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "svo/core.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum vx_image_type {
    VX_IMAGE_U8 = 0, /* uint8_t per channel */
    VX_IMAGE_F32     /* float per channel */
} vx_image_type;

typedef struct vx_image_desc {
    uint32_t width, height;
    uint32_t channels;   /* 1..4 */
    vx_image_type type;
    const void* pixels;  /* width * height * channels values, borrowed */
} vx_image_desc;

vx_result vx_image_write(const char* path, const vx_image_desc* img, vx_error* err);

/* Reads an image converted to the requested type; *out_pixels is freed with
 * vx_free(NULL, ...). Images larger than max_dim (0 == 16384) per side are
 * refused. */
vx_result vx_image_read(const char* path, vx_image_type type, uint32_t max_dim, uint32_t* width, uint32_t* height,
                        uint32_t* channels, void** out_pixels, vx_error* err);

#ifdef __cplusplus
}
#endif
#endif /* VX_IMAGE_H */
