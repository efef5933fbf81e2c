/* The bilinear downscale behind OpenCV's cascade pyramid: cv::resize(INTER_LINEAR_EXACT) on 8-bit
 * gray as OpenCV 4.6 computes it, bit for bit. Source offsets (x + 0.5) * scale - 0.5 in double, taps
 * in 8-bit fixed point (rounded to nearest even), rows in 8.8 fixed point, the vertical blend in
 * 16.16 rounded half up; outside the source the edge row or column alone. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "detect/cascade.h"

#define ONE 256 /* 1.0 in the taps' 8-bit fixed point */

/* Offsets and taps of one axis; [*lo, *hi) is the range that blends two source samples, below it
 * the first sample is copied, from it on the last. */
static void axis_taps(int n_src, int n_dst, int *ofs, uint16_t *taps, int *lo, int *hi) {
    double scale = 1. / ((double)n_dst / n_src);
    *lo = 0;
    *hi = n_dst;
    for (int d = 0; d < n_dst; d++) {
        double f = scale * ((double)d + 0.5) - 0.5;
        int i = (int)floor(f);
        ofs[d] = 0;
        taps[2 * d] = ONE;
        taps[2 * d + 1] = 0;
        if (i >= 0 && n_src > 1) {
            if (i < n_src - 1) {
                uint16_t t1 = (uint16_t)lrint((f - i) * ONE);
                ofs[d] = i;
                taps[2 * d + 1] = t1;
                taps[2 * d] = (uint16_t)(t1 < ONE ? ONE - t1 : 0);
            } else {
                ofs[d] = n_src - 1;
                if (d < *hi) *hi = d;
            }
        } else if (d + 1 > *lo) {
            *lo = d + 1;
        }
    }
}

/* One source row resampled horizontally, in 8.8 fixed point. */
static void hline(const uint8_t *s, uint16_t *row, int dw, const int *ofs, const uint16_t *taps, int lo, int hi) {
    int i = 0;
    for (; i < lo && i < dw; i++) row[i] = (uint16_t)(s[0] * ONE);
    for (; i < hi; i++) row[i] = (uint16_t)(taps[2 * i] * s[ofs[i]] + taps[2 * i + 1] * s[ofs[i] + 1]);
    for (; i < dw; i++) row[i] = (uint16_t)(s[ofs[dw - 1]] * ONE);
}

static void vset(const uint16_t *row, uint8_t *d, int dw) {
    for (int x = 0; x < dw; x++) d[x] = (uint8_t)((row[x] + ONE / 2) >> 8);
}

static void vblend(const uint16_t *r0, const uint16_t *r1, uint16_t t0, uint16_t t1, uint8_t *d, int dw) {
    for (int x = 0; x < dw; x++) {
        uint32_t v = ((uint32_t)r0[x] * t0 + (uint32_t)r1[x] * t1 + (1u << 15)) >> 16;
        d[x] = (uint8_t)(v > 255 ? 255 : v);
    }
}

int fr_cascade_resize(const uint8_t *src, int sw, int sh, size_t sstride, uint8_t *dst, int dw, int dh,
                      size_t dstride) {
    if (dw == sw && dh == sh) {
        for (int y = 0; y < sh; y++) memcpy(dst + (size_t)y * dstride, src + (size_t)y * sstride, (size_t)sw);
        return 0;
    }
    int *xofs = malloc(sizeof(int) * ((size_t)dw + (size_t)dh));
    uint16_t *taps = malloc(sizeof(uint16_t) * 2 * ((size_t)dw + (size_t)dh));
    uint16_t *rows = malloc(sizeof(uint16_t) * 2 * (size_t)dw);
    if (!xofs || !taps || !rows) {
        free(xofs);
        free(taps);
        free(rows);
        return -1;
    }
    int *yofs = xofs + dw, xlo, xhi, ylo, yhi;
    uint16_t *ytaps = taps + 2 * (size_t)dw;
    axis_taps(sw, dw, xofs, taps, &xlo, &xhi);
    axis_taps(sh, dh, yofs, ytaps, &ylo, &yhi);
    uint16_t *ra = rows, *rb = rows + dw; /* hold source rows have_a and have_a + 1 */
    int have_a = -2;
    for (int dy = 0; dy < dh; dy++) {
        uint8_t *d = dst + (size_t)dy * dstride;
        if (dy < ylo || dy >= yhi) {
            const uint8_t *s = src + (size_t)(dy < ylo ? 0 : sh - 1) * sstride;
            hline(s, ra, dw, xofs, taps, xlo, xhi);
            have_a = -2;
            vset(ra, d, dw);
            continue;
        }
        int iy = yofs[dy];
        if (iy == have_a + 1) { /* slide down one source row */
            uint16_t *t = ra;
            ra = rb;
            rb = t;
            hline(src + (size_t)(iy + 1) * sstride, rb, dw, xofs, taps, xlo, xhi);
        } else if (iy != have_a) {
            hline(src + (size_t)iy * sstride, ra, dw, xofs, taps, xlo, xhi);
            hline(src + (size_t)(iy + 1) * sstride, rb, dw, xofs, taps, xlo, xhi);
        }
        have_a = iy;
        vblend(ra, rb, ytaps[2 * dy], ytaps[2 * dy + 1], d, dw);
    }
    free(xofs);
    free(taps);
    free(rows);
    return 0;
}
