/* 8-bit gray exactly as dlib's load_image gives it to array2d<unsigned char> (dlib/pixel.h:
 * an RGB pixel becomes the truncated mean (r + g + b) / 3, not BT.601 luma), so that
 * side-by-side checks against dlib see the same pixels. Internal. */
#ifndef FR_DETECT_GRAY_LIKE_DLIB_H
#define FR_DETECT_GRAY_LIKE_DLIB_H

#include "frig/image.h"

/* A new one-channel image; a gray image is copied unchanged. */
frig_status fr_gray_like_dlib(frig_ctx *ctx, const frig_image *image, frig_image **out);

#endif
