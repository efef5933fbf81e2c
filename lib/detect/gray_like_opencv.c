/* The gray image OpenCV's cascades see (cv2.imread(IMREAD_GRAYSCALE)), derived from the photo's
 * decoded RGB so the detect stage decodes each photo once: libpng's rgb_to_gray weights for
 * PNG sources (what OpenCV asks libpng for), cvtColor's BT.601 fixed point otherwise. */
#include "core/context.h"
#include "detect/detector.h"
#include "image/image.h"

frig_status fr_gray_like_opencv(frig_ctx *ctx, const frig_image *img, frig_image **out) {
    if (!img || !out) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "fr_gray_like_opencv: NULL argument");
    *out = NULL;
    if (img->channels == 1) return frig_image_clone(ctx, img, out);
    if (img->format != FRIG_FORMAT_PNG) return frig_image_to_gray(ctx, img, out);
    frig_image *g = fr_image_new(img->width, img->height, 1);
    if (!g) return fr_nomem(ctx, "a gray image");
    for (int y = 0; y < img->height; y++) {
        const uint8_t *s = img->pixels + (size_t)y * img->stride;
        uint8_t *d = g->pixels + (size_t)y * g->stride;
        /* libpng (png_do_rgb_to_gray, 8-bit, no gamma): equal channels pass unchanged. */
        for (int x = 0; x < img->width; x++, s += 3)
            d[x] = (uint8_t)((s[0] == s[1] && s[1] == s[2]) ? s[0] : (s[0] * 9797u + s[1] * 19234u + s[2] * 3737u) >> 15);
    }
    g->format = img->format;
    g->source_channels = img->source_channels;
    g->source_bit_depth = img->source_bit_depth;
    g->orientation = img->orientation;
    g->cmyk = img->cmyk;
    *out = g;
    return FRIG_OK;
}
