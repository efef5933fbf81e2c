/* Gaussian blur of a float image with any number of channels (separable, the border repeated),
 * for coarse-to-fine image alignment (the sfs stage's photometric pose). Internal. */
#ifndef FR_IMAGE_GAUSSIAN_BLUR_H
#define FR_IMAGE_GAUSSIAN_BLUR_H

#include "frig/frig.h"

/* out (w x h x ch floats, may not alias in) = in convolved with a normalized Gaussian of
 * standard deviation sigma pixels (kernel radius ceil(3 sigma)); sigma <= 0 copies. */
frig_status fr_gaussian_blur(frig_ctx *ctx, const float *in, int w, int h, int ch, double sigma, float *out);

/* The same blur written only inside the window x0 <= x < x1, y0 <= y < y1 of out (the rest of
 * out untouched): the values there are fr_gaussian_blur's, bit for bit, at the cost of the
 * window (plus the kernel's radius of rows). */
frig_status fr_gaussian_blur_window(frig_ctx *ctx, const float *in, int w, int h, int ch, double sigma, int x0, int y0,
                                    int x1, int y1, float *out);

#endif
