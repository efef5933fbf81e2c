/* Area-averaged crops in linear light: a window of a photo resampled to fewer pixels with each
 * output pixel the exact average of the source area it covers (sRGB decoded first, so the
 * average is of light, not of codes). For shape from shading (paper section 5.1), whose data
 * term is linear in light. Internal. */
#ifndef FR_IMAGE_AREA_CROP_H
#define FR_IMAGE_AREA_CROP_H

#include <stdint.h>

#include "frig/frig.h"

/* Output pixel (i, j) averages the source area [ox + i step, ox + (i + 1) step) x
 * [oy + j step, oy + (j + 1) step) in source edge coordinates (source pixel k spans [k, k + 1)),
 * step >= 1 (reduce only). Source pixels beyond the image repeat the border. Fills linear (3
 * floats per pixel, RGB in [0, 1]; a gray source gives three equal values), srgb (3 bytes per
 * pixel: the average re-encoded; may be NULL) and inside (1 where the output pixel's centre lies
 * in the source; may be NULL). */
frig_status fr_area_crop(frig_ctx *ctx, const frig_image *src, double ox, double oy, double step, int width,
                         int height, float *linear, uint8_t *srgb, uint8_t *inside);

#endif
