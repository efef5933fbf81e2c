/* The gray image OpenCV's cascades see (cv2.imread(IMREAD_GRAYSCALE)), derived from the photo's
 * decoded RGB so the detect stage decodes each photo once: libpng's rgb_to_gray weights for
 * PNG sources (what OpenCV asks libpng for), cvtColor's BT.601 fixed point otherwise. */
#include "core/context.h"
#include "detect/detector.h"
#include "image/image.h"

/* libpng's png_do_rgb_to_gray (8-bit, no gamma) with OpenCV's weights: equal channels pass
 * unchanged, others (9797 r + 19234 g + 3737 b) >> 15. */
static uint8_t libpng_gray(const uint8_t *s) {
    if (s[0] == s[1] && s[1] == s[2]) return s[0];
    return (uint8_t)((s[0] * 9797u + s[1] * 19234u + s[2] * 3737u) >> 15);
}

frig_status fr_gray_like_opencv(frig_ctx *ctx, const frig_image *img, frig_image **out) {
    if (!img || !out) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "fr_gray_like_opencv: NULL argument");
    if (img->format != FRIG_FORMAT_PNG) return frig_image_to_gray(ctx, img, out);
    return fr_image_gray_map(ctx, img, libpng_gray, out);
}
