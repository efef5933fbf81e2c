/* Separable Gaussian blur, the border repeated (gaussian_blur.h): rows into a scratch image
 * (each row padded with its border values, so the inner loop has no bounds; the taps outer and
 * the row inner, so the loop runs over contiguous values), then columns (whole rows at a time,
 * accumulated in double). Every output value sums its taps in the same order whatever window is
 * asked for, so a window's values are the whole image's, bit for bit. The result does not
 * depend on the thread count. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "image/gaussian_blur.h"

static int clampi(int v, int lo, int hi) {
    return v < lo ? lo : v > hi ? hi : v;
}

frig_status fr_gaussian_blur_window(frig_ctx *ctx, const float *in, int w, int h, int ch, double sigma, int x0, int y0,
                                    int x1, int y1, float *out) {
    x0 = clampi(x0, 0, w), x1 = clampi(x1, x0, w), y0 = clampi(y0, 0, h), y1 = clampi(y1, y0, h);
    if (x0 >= x1 || y0 >= y1)
        return FRIG_OK;
    size_t row = (size_t)w * ch, wrow = (size_t)(x1 - x0) * ch;
    if (!(sigma > 0)) {
        for (int y = y0; y < y1; y++)
            memcpy(out + (size_t)y * row + (size_t)x0 * ch, in + (size_t)y * row + (size_t)x0 * ch,
                   sizeof(float) * wrow);
        return FRIG_OK;
    }
    int r = (int)ceil(3 * sigma);
    /* the rows the columns read: the window's, r more on each side (within the image) */
    int ya = y0 - r < 0 ? 0 : y0 - r, yb = y1 + r > h ? h : y1 + r;
    double *k = malloc(sizeof(double) * (size_t)(2 * r + 1));
    float *tmp = malloc(sizeof(float) * (wrow * (size_t)(yb - ya) + 1));
    float *pad = malloc(sizeof(float) * ((size_t)(x1 - x0 + 2 * r) * ch + 1));
    double *acc = malloc(sizeof(double) * (wrow + 1));
    if (!k || !tmp || !pad || !acc) {
        free(k), free(tmp), free(pad), free(acc);
        return fr_nomem(ctx, "a blurred image");
    }
    double sum = 0;
    for (int i = -r; i <= r; i++)
        sum += k[i + r] = exp(-0.5 * i * i / (sigma * sigma));
    for (int i = 0; i <= 2 * r; i++)
        k[i] /= sum;
    for (int y = ya; y < yb; y++) {
        const float *src = in + (size_t)y * row;
        for (int x = x0 - r; x < x1 + r; x++)
            memcpy(pad + (size_t)(x - x0 + r) * ch, src + (size_t)clampi(x, 0, w - 1) * ch, sizeof(float) * (size_t)ch);
        memset(acc, 0, sizeof(double) * wrow);
        for (int i = 0; i <= 2 * r; i++) {
            const float *p = pad + (size_t)i * ch;
            double kk = k[i];
            for (size_t q = 0; q < wrow; q++)
                acc[q] += kk * p[q];
        }
        float *dst = tmp + (size_t)(y - ya) * wrow;
        for (size_t q = 0; q < wrow; q++)
            dst[q] = (float)acc[q];
    }
    for (int y = y0; y < y1; y++) {
        memset(acc, 0, sizeof(double) * wrow);
        for (int i = -r; i <= r; i++) {
            const float *src = tmp + (size_t)(clampi(y + i, 0, h - 1) - ya) * wrow;
            double kk = k[i + r];
            for (size_t q = 0; q < wrow; q++)
                acc[q] += kk * src[q];
        }
        float *dst = out + (size_t)y * row + (size_t)x0 * ch;
        for (size_t q = 0; q < wrow; q++)
            dst[q] = (float)acc[q];
    }
    free(k), free(tmp), free(pad), free(acc);
    return FRIG_OK;
}

frig_status fr_gaussian_blur(frig_ctx *ctx, const float *in, int w, int h, int ch, double sigma, float *out) {
    return fr_gaussian_blur_window(ctx, in, w, h, ch, sigma, 0, 0, w, h, out);
}
