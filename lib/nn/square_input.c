/* The input of TensorFlow.js's face networks as @vladmandic/face-api builds it
 * (NetInput.toBatchTensor): the image region padded with zeros to a square (padToSquare),
 * then tf.image.resizeBilinear with align_corners = half_pixel_centers = false (tfjs's CPU
 * kernel: source = dst * in / out, the floor and ceil neighbours, interpolated along x, then
 * y). The padded square is never built: samples outside the region read zero. */
#include <math.h>

#include "nn/layers.h"

/* Sample c of the padded square at (sx, sy): zero outside the region. */
static float sample(const uint8_t *px, size_t stride, int channels, int x, int y, int w, int h, int ox, int oy,
                    int sx, int sy, int c) {
    int ix = sx - ox, iy = sy - oy;
    if (ix < 0 || iy < 0 || ix >= w || iy >= h) return 0.0f;
    const uint8_t *p = px + (size_t)(y + iy) * stride + (size_t)(x + ix) * (size_t)channels;
    return (float)p[channels == 1 ? 0 : c];
}

/* tf.image.resizeBilinear's source of output index i: floor and ceil neighbours (clamped to
 * the side) and the fraction between them. */
static void source_of(double ratio, int i, int side, int *i0, int *i1, double *frac) {
    double f = ratio * i;
    *i0 = (int)floor(f);
    if (*i0 < 0) *i0 = 0;
    *frac = f - *i0;
    *i1 = (int)ceil(f);
    if (*i1 > side - 1) *i1 = side - 1;
}

void fr_nn_square_input(const uint8_t *px, size_t stride, int channels, int x, int y, int w, int h, int centred,
                        int size, float *out) {
    int side = w > h ? w : h, diff = w > h ? w - h : h - w;
    /* padToSquare: round(diff / 2) appended (JS Math.round of a half rounds up), the rest before. */
    int before = centred ? diff - (int)floor(diff * 0.5 + 0.5) : 0;
    int ox = w < h ? before : 0, oy = h < w ? before : 0;
    double ratio = (double)side / size;
    for (int r = 0; r < size; r++) {
        int y0, y1;
        double wy;
        source_of(ratio, r, side, &y0, &y1, &wy);
        for (int col = 0; col < size; col++) {
            int x0, x1;
            double wx;
            source_of(ratio, col, side, &x0, &x1, &wx);
            float *o = out + ((size_t)r * (size_t)size + (size_t)col) * 3;
            for (int c = 0; c < 3; c++) {
                double tl = sample(px, stride, channels, x, y, w, h, ox, oy, x0, y0, c);
                double tr = sample(px, stride, channels, x, y, w, h, ox, oy, x1, y0, c);
                double bl = sample(px, stride, channels, x, y, w, h, ox, oy, x0, y1, c);
                double br = sample(px, stride, channels, x, y, w, h, ox, oy, x1, y1, c);
                double top = tl + (tr - tl) * wx, bottom = bl + (br - bl) * wx;
                o[c] = (float)(top + (bottom - top) * wy);
            }
        }
    }
}
