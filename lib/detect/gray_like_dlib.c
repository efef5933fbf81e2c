/* dlib's RGB to gray conversion (assign_pixel from rgb_pixel to unsigned char in dlib/pixel.h):
 * the plain mean of the three channels, rounded down. Used to feed the landmark predictor the
 * very pixels dlib sees when its answers are the reference. */
#include "core/context.h"
#include "detect/gray_like_dlib.h"
#include "image/image.h"

static uint8_t mean_of_three(const uint8_t *s) { return (uint8_t)(((unsigned)s[0] + s[1] + s[2]) / 3u); }

frig_status fr_gray_like_dlib(frig_ctx *ctx, const frig_image *img, frig_image **out) {
    return fr_image_gray_map(ctx, img, mean_of_three, out);
}
