/* Separable Gaussian blur, the border repeated (gaussian_blur.h): rows into a scratch image
 * (each row copied in double with its border values, so the inner loop has no bounds), then
 * columns. Each output value is its centre tap plus its symmetric pairs of taps (one product a
 * pair), in double, and the rows' sums are rounded to float before the columns read them; the values are
 * computed a few at a time with the taps inside (the running sums stay in registers), and every
 * value sums its taps in the same order whatever window is asked for, so a window's values are
 * the whole image's, bit for bit. The result does not depend on the thread count. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "core/v2d.h"
#include "image/gaussian_blur.h"

static int clampi(int v, int lo, int hi) {
    return v < lo ? lo : v > hi ? hi : v;
}

/* dst[q] = k[r] src[r][q] + sum over i < r of k[i] (src[i][q] + src[taps-1-i][q]), q < n: the kernel is
 * symmetric (k[i] and k[taps-1-i] are computed from the same i^2, so they are equal), so a pair of
 * taps takes one product; each sum starts at the centre tap and adds the pairs in the same order
 * for every q. */
static void convolve(const double *k, int taps, const double *const *src, size_t n, double *dst) {
    int r = taps / 2;
    size_t q = 0;
    for (; q + 8 <= n; q += 8) {
        v2d kc = {k[r], k[r]}, x0, x1, x2, x3, y0, y1, y2, y3;
        const double *c = src[r] + q;
        memcpy(&x0, c, sizeof x0), memcpy(&x1, c + 2, sizeof x1);
        memcpy(&x2, c + 4, sizeof x2), memcpy(&x3, c + 6, sizeof x3);
        v2d a0 = kc * x0, a1 = kc * x1, a2 = kc * x2, a3 = kc * x3;
        for (int i = 0; i < r; i++) {
            const double *p = src[i] + q, *m = src[taps - 1 - i] + q;
            v2d kk = {k[i], k[i]};
            memcpy(&x0, p, sizeof x0), memcpy(&x1, p + 2, sizeof x1);
            memcpy(&x2, p + 4, sizeof x2), memcpy(&x3, p + 6, sizeof x3);
            memcpy(&y0, m, sizeof y0), memcpy(&y1, m + 2, sizeof y1);
            memcpy(&y2, m + 4, sizeof y2), memcpy(&y3, m + 6, sizeof y3);
            a0 = a0 + kk * (x0 + y0), a1 = a1 + kk * (x1 + y1), a2 = a2 + kk * (x2 + y2), a3 = a3 + kk * (x3 + y3);
        }
        memcpy(dst + q, &a0, sizeof a0), memcpy(dst + q + 2, &a1, sizeof a1);
        memcpy(dst + q + 4, &a2, sizeof a2), memcpy(dst + q + 6, &a3, sizeof a3);
    }
    for (; q < n; q++) {
        double a = k[r] * src[r][q];
        for (int i = 0; i < r; i++) a += k[i] * (src[i][q] + src[taps - 1 - i][q]);
        dst[q] = a;
    }
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
    int r = (int)ceil(3 * sigma), taps = 2 * r + 1;
    /* the rows the columns read: the window's, r more on each side (within the image) */
    int ya = y0 - r < 0 ? 0 : y0 - r, yb = y1 + r > h ? h : y1 + r;
    double *k = malloc(sizeof(double) * (size_t)taps);
    double *tmp = malloc(sizeof(double) * (wrow * (size_t)(yb - ya) + 1)); /* the rows' sums, rounded to float */
    double *pad = malloc(sizeof(double) * ((size_t)(x1 - x0 + 2 * r) * ch + 1));
    double *acc = malloc(sizeof(double) * (wrow + 1));
    const double **src = malloc(sizeof(double *) * (size_t)taps);
    if (!k || !tmp || !pad || !acc || !src) {
        free(k), free(tmp), free(pad), free(acc), free(src);
        return fr_nomem(ctx, "a blurred image");
    }
    double sum = 0;
    for (int i = -r; i <= r; i++)
        sum += k[i + r] = exp(-0.5 * i * i / (sigma * sigma));
    for (int i = 0; i < taps; i++)
        k[i] /= sum;
    for (int i = 0; i < taps; i++)
        src[i] = pad + (size_t)i * ch;
    for (int y = ya; y < yb; y++) {
        const float *row_in = in + (size_t)y * row;
        for (int x = x0 - r; x < x1 + r; x++) {
            const float *p = row_in + (size_t)clampi(x, 0, w - 1) * ch;
            double *d = pad + (size_t)(x - x0 + r) * ch;
            for (int c = 0; c < ch; c++)
                d[c] = p[c];
        }
        double *dst = tmp + (size_t)(y - ya) * wrow;
        convolve(k, taps, src, wrow, acc);
        for (size_t q = 0; q < wrow; q++)
            dst[q] = (float)acc[q];
    }
    for (int y = y0; y < y1; y++) {
        for (int i = -r; i <= r; i++)
            src[i + r] = tmp + (size_t)(clampi(y + i, 0, h - 1) - ya) * wrow;
        convolve(k, taps, src, wrow, acc);
        float *dst = out + (size_t)y * row + (size_t)x0 * ch;
        for (size_t q = 0; q < wrow; q++)
            dst[q] = (float)acc[q];
    }
    free(k), free(tmp), free(pad), free(acc), free(src);
    return FRIG_OK;
}

frig_status fr_gaussian_blur(frig_ctx *ctx, const float *in, int w, int h, int ch, double sigma, float *out) {
    return fr_gaussian_blur_window(ctx, in, w, h, ch, sigma, 0, 0, w, h, out);
}
