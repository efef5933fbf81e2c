/* dlib's RGB to gray conversion (assign_pixel from rgb_pixel to unsigned char in dlib/pixel.h):
 * the plain mean of the three channels, rounded down. Used to feed the landmark predictor the
 * very pixels dlib sees when its answers are the reference. */
#include "core/context.h"
#include "detect/gray_like_dlib.h"
#include "image/image.h"

frig_status fr_gray_like_dlib(frig_ctx *ctx, const frig_image *img, frig_image **out) {
    if (!img || !out) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "fr_gray_like_dlib: NULL argument");
    *out = NULL;
    if (img->channels == 1) return frig_image_clone(ctx, img, out);
    frig_image *g = fr_image_new(img->width, img->height, 1);
    if (!g) return fr_nomem(ctx, "a gray image");
    for (int y = 0; y < img->height; y++) {
        const uint8_t *s = img->pixels + (size_t)y * img->stride;
        uint8_t *d = g->pixels + (size_t)y * g->stride;
        for (int x = 0; x < img->width; x++, s += 3) d[x] = (uint8_t)(((unsigned)s[0] + s[1] + s[2]) / 3u);
    }
    g->format = img->format;
    g->source_channels = img->source_channels;
    g->source_bit_depth = img->source_bit_depth;
    g->orientation = img->orientation;
    g->cmyk = img->cmyk;
    *out = g;
    return FRIG_OK;
}
