/* Separable Gaussian blur, the border repeated (gaussian_blur.h): rows into a scratch image
 * (each row padded with its border values, so the inner loop has no bounds), then columns (whole
 * rows at a time, accumulated in double). The result does not depend on the thread count. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "image/gaussian_blur.h"

static int clampi(int v, int lo, int hi) {
    return v < lo ? lo : v > hi ? hi : v;
}

frig_status fr_gaussian_blur(frig_ctx *ctx, const float *in, int w, int h, int ch, double sigma, float *out) {
    size_t n = (size_t)w * h * ch, row = (size_t)w * ch;
    if (!(sigma > 0)) {
        memcpy(out, in, sizeof(float) * n);
        return FRIG_OK;
    }
    int r = (int)ceil(3 * sigma);
    double *k = malloc(sizeof(double) * (size_t)(2 * r + 1));
    float *tmp = malloc(sizeof(float) * (n + 1)), *pad = malloc(sizeof(float) * ((size_t)(w + 2 * r) * ch + 1));
    double *acc = malloc(sizeof(double) * (row + 1));
    if (!k || !tmp || !pad || !acc) {
        free(k), free(tmp), free(pad), free(acc);
        return fr_nomem(ctx, "a blurred image");
    }
    double sum = 0;
    for (int i = -r; i <= r; i++)
        sum += k[i + r] = exp(-0.5 * i * i / (sigma * sigma));
    for (int i = 0; i <= 2 * r; i++)
        k[i] /= sum;
    for (int y = 0; y < h; y++) {
        const float *src = in + (size_t)y * row;
        for (int x = -r; x < w + r; x++)
            memcpy(pad + (size_t)(x + r) * ch, src + (size_t)clampi(x, 0, w - 1) * ch, sizeof(float) * (size_t)ch);
        float *dst = tmp + (size_t)y * row;
        for (int x = 0; x < w; x++)
            for (int c = 0; c < ch; c++) {
                const float *p = pad + (size_t)x * ch + c;
                double a = 0;
                for (int i = 0; i <= 2 * r; i++)
                    a += k[i] * p[(size_t)i * ch];
                dst[(size_t)x * ch + c] = (float)a;
            }
    }
    for (int y = 0; y < h; y++) {
        memset(acc, 0, sizeof(double) * row);
        for (int i = -r; i <= r; i++) {
            const float *src = tmp + (size_t)clampi(y + i, 0, h - 1) * row;
            double kk = k[i + r];
            for (size_t q = 0; q < row; q++)
                acc[q] += kk * src[q];
        }
        for (size_t q = 0; q < row; q++)
            out[(size_t)y * row + q] = (float)acc[q];
    }
    free(k), free(tmp), free(pad), free(acc);
    return FRIG_OK;
}
