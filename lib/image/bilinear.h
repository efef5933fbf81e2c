/* Bilinear sampling of float RGB images (3 floats per pixel, pixel centres at integer
 * coordinates). Internal. */
#ifndef FR_IMAGE_BILINEAR_H
#define FR_IMAGE_BILINEAR_H

#include <math.h>
#include <stddef.h>

#include "core/floor_int.h"

static inline int fr_clamp_index(int v, int n) { return v < 0 ? 0 : v >= n ? n - 1 : v; }

/* Bilinear sample of a w x h RGB image at xy, the border repeated; the four corners summed in the
 * order (x0, y0), (x1, y0), (x0, y1), (x1, y1). Inline: the shape-from-shading and outline
 * loops call it per texel and pixel. */
static inline void fr_bilinear3(const float *img, int w, int h, const double xy[2], double out[3]) {
    int x0 = fr_floor_int(xy[0]), y0 = fr_floor_int(xy[1]);
    double fx = xy[0] - x0, fy = xy[1] - y0;
    int xa = fr_clamp_index(x0, w), xb = fr_clamp_index(x0 + 1, w);
    size_t ra = (size_t)fr_clamp_index(y0, h) * w, rb = (size_t)fr_clamp_index(y0 + 1, h) * w;
    const float *p00 = img + 3 * (ra + xa), *p10 = img + 3 * (ra + xb), *p01 = img + 3 * (rb + xa),
                *p11 = img + 3 * (rb + xb);
    double w00 = (1 - fx) * (1 - fy), w10 = fx * (1 - fy), w01 = (1 - fx) * fy, w11 = fx * fy;
    for (int c = 0; c < 3; c++) {
        double a = 0;
        a += w00 * p00[c];
        a += w10 * p10[c];
        a += w01 * p01[c];
        a += w11 * p11[c];
        out[c] = a;
    }
}

#endif
