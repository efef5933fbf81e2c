/* Area-averaged crops in linear light (for shape from shading, paper section 5.1): separable
 * box weights with fractional coverage at the borders of each output pixel, computed once per
 * axis; the sRGB codes are decoded through a table before averaging. */
#include <math.h>
#include <stdlib.h>

#include "core/context.h"
#include "image/area_crop.h"
#include "image/image.h"
#include "image/srgb.h"

typedef struct taps {
    int *first, *count; /* per output index: first source index (clamped later) and tap count */
    double *w;          /* count weights per output index, at stride 'max' */
    int max;
} taps;

static int make_taps(double o, double step, int n, taps *t) {
    t->max = (int)ceil(step) + 2;
    t->first = malloc(sizeof(int) * (size_t)n);
    t->count = malloc(sizeof(int) * (size_t)n);
    t->w = malloc(sizeof(double) * (size_t)n * (size_t)t->max);
    if (!t->first || !t->count || !t->w) return 0;
    for (int i = 0; i < n; i++) {
        double a = o + i * step, b = a + step;
        int k0 = (int)floor(a), c = 0;
        t->first[i] = k0;
        for (int k = k0; k < b && c < t->max; k++, c++) {
            double lo = a > k ? a : k, hi = b < k + 1 ? b : k + 1;
            t->w[(size_t)i * t->max + c] = (hi - lo) / step;
        }
        t->count[i] = c;
    }
    return 1;
}

static void free_taps(taps *t) { free(t->first), free(t->count), free(t->w); }

frig_status fr_area_crop(frig_ctx *ctx, const frig_image *src, double ox, double oy, double step, int width,
                         int height, float *linear, uint8_t *srgb, uint8_t *inside) {
    if (!(step >= 1.0) || width <= 0 || height <= 0)
        return fr_error(ctx, FRIG_ERR_INTERNAL, "area crop with step %g and size %d x %d", step, width, height);
    taps tx = {0}, ty = {0};
    float lut[256];
    fr_srgb_decode_table(lut);
    int W = src->width, H = src->height, C = src->channels;
    float *row = malloc(sizeof(float) * 3 * (size_t)width);
    if (!row || !make_taps(ox, step, width, &tx) || !make_taps(oy, step, height, &ty)) {
        free(row), free_taps(&tx), free_taps(&ty);
        return fr_nomem(ctx, "a face crop");
    }
    for (int j = 0; j < height; j++) {
        float *out = linear + 3 * (size_t)j * width;
        for (size_t q = 0; q < 3 * (size_t)width; q++) out[q] = 0.0f;
        for (int b = 0; b < ty.count[j]; b++) {
            int sy = ty.first[j] + b;
            sy = sy < 0 ? 0 : sy >= H ? H - 1 : sy;
            const uint8_t *s = src->pixels + (size_t)sy * src->stride;
            double wy = ty.w[(size_t)j * ty.max + b];
            for (int i = 0; i < width; i++) {
                double acc[3] = {0, 0, 0};
                for (int a = 0; a < tx.count[i]; a++) {
                    int sx = tx.first[i] + a;
                    sx = sx < 0 ? 0 : sx >= W ? W - 1 : sx;
                    double wx = tx.w[(size_t)i * tx.max + a];
                    const uint8_t *p = s + (size_t)sx * C;
                    if (C >= 3) {
                        acc[0] += wx * lut[p[0]], acc[1] += wx * lut[p[1]], acc[2] += wx * lut[p[2]];
                    } else {
                        double v = wx * lut[p[0]];
                        acc[0] += v, acc[1] += v, acc[2] += v;
                    }
                }
                for (int c = 0; c < 3; c++) row[3 * i + c] = (float)(wy * acc[c]);
            }
            for (size_t q = 0; q < 3 * (size_t)width; q++) out[q] += row[q];
        }
        for (int i = 0; i < width; i++) {
            if (srgb)
                for (int c = 0; c < 3; c++)
                    srgb[3 * ((size_t)j * width + i) + c] = (uint8_t)floor(255.0 * fr_linear_to_srgb(out[3 * i + c]) + 0.5);
            if (inside) {
                double cx = ox + (i + 0.5) * step, cy = oy + (j + 0.5) * step;
                inside[(size_t)j * width + i] = cx >= 0 && cy >= 0 && cx <= W && cy <= H;
            }
        }
    }
    free(row), free_taps(&tx), free_taps(&ty);
    return FRIG_OK;
}
