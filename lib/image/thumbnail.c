/* Thumbnails for pages people look at (frig run's report): a photo or overlay decoded at a
 * reduced size where the codec can (JPEG's DCT scaling), then box-filtered to fit the wanted
 * side exactly, written as a JPEG. */
#include <math.h>
#include <stdlib.h>

#include "core/context.h"
#include "image/image.h"

/* Area-average w x h from src (each output pixel the mean of the source area it covers). */
static frig_image *shrink(const frig_image *src, int w, int h) {
    frig_image *dst = fr_image_new(w, h, src->channels);
    if (!dst) return NULL;
    double sx = (double)src->width / w, sy = (double)src->height / h;
    int c = src->channels;
    for (int y = 0; y < h; y++) {
        double y0 = y * sy, y1 = y0 + sy;
        for (int x = 0; x < w; x++) {
            double x0 = x * sx, x1 = x0 + sx, sum[3] = {0, 0, 0}, area = 0;
            for (int yy = (int)y0; yy < (int)ceil(y1) && yy < src->height; yy++) {
                double wy = fmin(y1, yy + 1) - fmax(y0, yy);
                for (int xx = (int)x0; xx < (int)ceil(x1) && xx < src->width; xx++) {
                    double wgt = wy * (fmin(x1, xx + 1) - fmax(x0, xx));
                    const uint8_t *p = src->pixels + (size_t)yy * src->stride + (size_t)xx * (size_t)c;
                    for (int k = 0; k < c; k++) sum[k] += wgt * p[k];
                    area += wgt;
                }
            }
            uint8_t *q = dst->pixels + (size_t)y * dst->stride + (size_t)x * (size_t)c;
            for (int k = 0; k < c; k++) q[k] = (uint8_t)floor(sum[k] / area + 0.5);
        }
    }
    return dst;
}

frig_status frig_image_save_thumbnail(frig_ctx *ctx, const char *src, int max_side, const char *dst) {
    if (!src || !dst) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_image_save_thumbnail: NULL path");
    if (max_side < 8 || max_side > 8192)
        return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "a thumbnail of %d pixels (8 to 8192)", max_side);
    /* Decode 8x smaller first (cheap); if that is too small, again at the largest reduction
     * that keeps max_side. */
    frig_image *img = NULL;
    int reduced = 1;
    frig_status s = fr_image_load_reduced(ctx, src, 0, 8, &img, &reduced);
    if (!s && reduced > 1) {
        int side = (img->width > img->height ? img->width : img->height) * reduced, r = 8;
        while (r > 1 && side / r < max_side) r /= 2;
        if (r != reduced) {
            frig_image_free(img);
            img = NULL;
            s = fr_image_load_reduced(ctx, src, 0, r, &img, &reduced);
        }
    }
    if (s) return s;
    int side = img->width > img->height ? img->width : img->height;
    frig_image *small = img;
    if (side > max_side) {
        int w = (int)fmax(1.0, floor((double)img->width * max_side / side + 0.5));
        int h = (int)fmax(1.0, floor((double)img->height * max_side / side + 0.5));
        small = shrink(img, w, h);
        if (!small) s = fr_nomem(ctx, "a thumbnail");
    }
    if (!s) s = frig_image_save_jpeg(ctx, small, dst);
    if (small != img) frig_image_free(small);
    frig_image_free(img);
    return s;
}
