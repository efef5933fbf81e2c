/* Integral images for the cascade (Viola-Jones' summed-area table; Lienhart's 45-degree rotated
 * table for tilted Haar features), laid out as OpenCV's cv::integral with CV_32S outputs: one extra
 * zero row and column, entries modulo 2^32 (window differences stay exact). */
#include <string.h>

#include "detect/cascade.h"

void fr_cascade_integral(const uint8_t *img, int w, int h, size_t stride, uint32_t *sum, uint32_t *sqsum,
                         size_t istride) {
    memset(sum, 0, sizeof(uint32_t) * (size_t)(w + 1));
    if (sqsum) memset(sqsum, 0, sizeof(uint32_t) * (size_t)(w + 1));
    for (int y = 0; y < h; y++) {
        const uint8_t *s = img + (size_t)y * stride;
        const uint32_t *up = sum + (size_t)y * istride;
        uint32_t *row = sum + (size_t)(y + 1) * istride;
        uint32_t acc = 0;
        row[0] = 0;
        if (sqsum) {
            const uint32_t *squp = sqsum + (size_t)y * istride;
            uint32_t *sqrow = sqsum + (size_t)(y + 1) * istride, sqacc = 0;
            sqrow[0] = 0;
            for (int x = 0; x < w; x++) {
                uint32_t v = s[x];
                acc += v;
                sqacc += v * v;
                row[x + 1] = up[x + 1] + acc;
                sqrow[x + 1] = squp[x + 1] + sqacc;
            }
        } else {
            for (int x = 0; x < w; x++) {
                acc += s[x];
                row[x + 1] = up[x + 1] + acc;
            }
        }
    }
}

/* The rotated table at column X of row Y sums the pixels (x, y) with y < Y and |x - X + 1| <= Y - y - 1,
 * a triangle opening upwards. Its recurrence T(Y, X) = T(Y-1, X-1) + T(Y-1, X+1) - T(Y-2, X)
 * + I(Y-1, X-1) + I(Y-2, X-1) reaches h columns beyond each side, so three padded rows are kept. */
size_t fr_cascade_tilted_scratch(int w, int h) {
    return 3 * ((size_t)w + 2 * (size_t)h + 4);
}

void fr_cascade_integral_tilted(const uint8_t *img, int w, int h, size_t stride, uint32_t *tilted, size_t istride,
                                uint32_t *scratch) {
    size_t pad = (size_t)h + 1, pw = (size_t)w + 2 * (size_t)h + 4;
    uint32_t *r[3] = {scratch, scratch + pw, scratch + 2 * pw}; /* rows Y-2, Y-1, Y */
    memset(scratch, 0, sizeof(uint32_t) * 3 * pw);
    memset(tilted, 0, sizeof(uint32_t) * (size_t)(w + 1));
    for (int Y = 1; Y <= h; Y++) {
        uint32_t *cur = r[2], *prev = r[1], *prev2 = r[0];
        const uint8_t *i1 = img + (size_t)(Y - 1) * stride;
        const uint8_t *i2 = Y >= 2 ? img + (size_t)(Y - 2) * stride : NULL;
        cur[0] = cur[pw - 1] = 0;
        for (size_t i = 1; i + 1 < pw; i++) {
            long X = (long)i - (long)pad; /* image column of this padded entry */
            uint32_t v = prev[i - 1] + prev[i + 1] - prev2[i];
            if (X >= 1 && X <= w) {
                v += i1[X - 1];
                if (i2) v += i2[X - 1];
            }
            cur[i] = v;
        }
        uint32_t *out = tilted + (size_t)Y * istride;
        memcpy(out, cur + pad, sizeof(uint32_t) * (size_t)(w + 1));
        r[0] = prev;
        r[1] = cur;
        r[2] = prev2;
    }
}
