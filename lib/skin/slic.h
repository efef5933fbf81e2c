/* SLIC superpixels (Achanta et al. 2012, "SLIC superpixels compared to state-of-the-art
 * superpixel methods"; the paper's reference [64]): k-means in (CIELAB, x, y) restricted to
 * 2S x 2S windows, then connectivity enforced. Used by the skin detector of section 5.1.2 to
 * drop whole outlier segments. Deterministic. Internal. */
#ifndef FR_SKIN_SLIC_H
#define FR_SKIN_SLIC_H

#include <stdint.h>

#include "frig/frig.h"

/* CIELAB (D65) of an 8-bit sRGB pixel. */
void fr_srgb8_to_lab(const uint8_t rgb[3], float lab[3]);

/* Segment a width x height Lab image (3 floats per pixel) into superpixels of about step x
 * step pixels; compactness m weighs space against colour (10 is SLIC's usual value).
 * labels gets width * height values in 0 .. *count - 1, segments connected. */
frig_status fr_slic(frig_ctx *ctx, const float *lab, int width, int height, int step, double compactness,
                    int iterations, int32_t *labels, int *count);

#endif
