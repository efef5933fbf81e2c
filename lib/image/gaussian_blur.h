/* Gaussian blur of a float image with any number of channels (separable, the border repeated),
 * for coarse-to-fine image alignment (the sfs stage's photometric pose). Internal. */
#ifndef FR_IMAGE_GAUSSIAN_BLUR_H
#define FR_IMAGE_GAUSSIAN_BLUR_H

#include "frig/frig.h"

/* out (w x h x ch floats, may not alias in) = in convolved with a normalized Gaussian of
 * standard deviation sigma pixels (kernel radius ceil(3 sigma)); sigma <= 0 copies. */
frig_status fr_gaussian_blur(frig_ctx *ctx, const float *in, int w, int h, int ch, double sigma, float *out);

#endif
