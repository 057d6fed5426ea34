/* formats/image_pnm.h - private to formats/image*: PFM/PPM/PGM by voxkit's
 * own code (image_pnm.c), used by both image back ends. */
#ifndef VX_IMAGE_PNM_H
#define VX_IMAGE_PNM_H

#include "formats/image.h"

/* Arguments of a write: NULLs, sides 1..65536, 1..4 channels (every back end's rule) */
vx_result vx__image_desc_check(const char* path, const vx_image_desc* img, vx_error* err);
/* 'f' .pfm, 'g' .pgm, 'p' .ppm (either case), 0 any other name */
char vx__image_pnm_kind(const char* path);
vx_result vx__image_pnm_write(const char* path, const vx_image_desc* img, vx_error* err);
vx_result vx__image_pnm_read(const char* path, vx_image_type type, uint32_t max_dim, uint32_t* width,
                             uint32_t* height, uint32_t* channels, void** out_pixels, vx_error* err);

#endif /* VX_IMAGE_PNM_H */
