/* The image handle: allocation, accessors, orientation, gray conversion. */
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "image/image.h"

frig_image *fr_image_new(int width, int height, int channels) {
    if (width <= 0 || height <= 0 || (channels != 1 && channels != 3)) return NULL;
    size_t stride = (size_t)width * (size_t)channels;
    if ((size_t)height > SIZE_MAX / stride) return NULL;
    frig_image *img = calloc(1, sizeof *img);
    if (!img) return NULL;
    img->pixels = calloc((size_t)height, stride);
    if (!img->pixels) {
        free(img);
        return NULL;
    }
    img->width = width;
    img->height = height;
    img->channels = channels;
    img->stride = stride;
    img->source_channels = channels;
    img->source_bit_depth = 8;
    img->orientation = 1;
    return img;
}

frig_status frig_image_create(frig_ctx *ctx, int width, int height, int channels, frig_image **out) {
    if (!out) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_image_create: no output pointer");
    *out = NULL;
    if (width <= 0 || height <= 0 || (channels != 1 && channels != 3))
        return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_image_create: %dx%d with %d channels is not valid",
                        width, height, channels);
    double px = (double)width * (double)height;
    if (px > fr_param(ctx, FRIG_PARAM_IMAGE_MAX_PIXELS))
        return fr_error(ctx, FRIG_ERR_TOO_LARGE, "frig_image_create: %dx%d is over image.max_pixels = %.0f", width,
                        height, fr_param(ctx, FRIG_PARAM_IMAGE_MAX_PIXELS));
    *out = fr_image_new(width, height, channels);
    return *out ? FRIG_OK : fr_nomem(ctx, "an image");
}

frig_status frig_image_clone(frig_ctx *ctx, const frig_image *src, frig_image **out) {
    if (!src || !out) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_image_clone: NULL argument");
    frig_image *img = fr_image_new(src->width, src->height, src->channels);
    if (!img) return fr_nomem(ctx, "an image copy");
    for (int y = 0; y < src->height; y++)
        memcpy(img->pixels + (size_t)y * img->stride, src->pixels + (size_t)y * src->stride, img->stride);
    fr_image_copy_info(img, src);
    *out = img;
    return FRIG_OK;
}

void frig_image_free(frig_image *img) {
    if (!img) return;
    free(img->pixels);
    free(img);
}

int frig_image_width(const frig_image *img) { return img ? img->width : 0; }
int frig_image_height(const frig_image *img) { return img ? img->height : 0; }
int frig_image_channels(const frig_image *img) { return img ? img->channels : 0; }
size_t frig_image_stride(const frig_image *img) { return img ? img->stride : 0; }
const uint8_t *frig_image_pixels(const frig_image *img) { return img ? img->pixels : NULL; }
uint8_t *frig_image_pixels_mutable(frig_image *img) { return img ? img->pixels : NULL; }
frig_image_format frig_image_source_format(const frig_image *img) { return img ? img->format : FRIG_FORMAT_UNKNOWN; }
int frig_image_source_channels(const frig_image *img) { return img ? img->source_channels : 0; }
int frig_image_source_bit_depth(const frig_image *img) { return img ? img->source_bit_depth : 0; }
int frig_image_orientation(const frig_image *img) { return img ? img->orientation : 0; }
int frig_image_source_cmyk(const frig_image *img) { return img ? img->cmyk : 0; }

/* Upright pixel (x, y) comes from stored pixel (sx, sy); see the EXIF specification's
 * orientation table (1 upright, 2 mirrored, 3 rotated 180, 4 flipped, 5 transposed,
 * 6 rotated 90 clockwise to view, 7 transversed, 8 rotated 90 counter-clockwise to view). */
static void stored_coords(int orientation, int w, int h, int x, int y, int *sx, int *sy) {
    switch (orientation) {
    case 2: *sx = w - 1 - x; *sy = y; break;
    case 3: *sx = w - 1 - x; *sy = h - 1 - y; break;
    case 4: *sx = x; *sy = h - 1 - y; break;
    case 5: *sx = y; *sy = x; break;
    case 6: *sx = y; *sy = h - 1 - x; break;
    case 7: *sx = w - 1 - y; *sy = h - 1 - x; break;
    case 8: *sx = w - 1 - y; *sy = x; break;
    default: *sx = x; *sy = y; break;
    }
}

frig_image *fr_image_orient(const frig_image *img, int orientation) {
    int swap = orientation >= 5 && orientation <= 8;
    int W = swap ? img->height : img->width, H = swap ? img->width : img->height;
    frig_image *out = fr_image_new(W, H, img->channels);
    if (!out) return NULL;
    int c = img->channels;
    for (int y = 0; y < H; y++) {
        uint8_t *row = out->pixels + (size_t)y * out->stride;
        for (int x = 0; x < W; x++) {
            int sx, sy;
            stored_coords(orientation, img->width, img->height, x, y, &sx, &sy);
            memcpy(row + (size_t)x * c, img->pixels + (size_t)sy * img->stride + (size_t)sx * c, (size_t)c);
        }
    }
    fr_image_copy_info(out, img);
    return out;
}

void fr_image_copy_info(frig_image *dst, const frig_image *src) {
    dst->format = src->format;
    dst->source_channels = src->source_channels;
    dst->source_bit_depth = src->source_bit_depth;
    dst->orientation = src->orientation;
    dst->cmyk = src->cmyk;
}

frig_status fr_image_gray_map(frig_ctx *ctx, const frig_image *img, uint8_t (*to_gray)(const uint8_t *rgb),
                              frig_image **out) {
    if (!img || !out) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "gray conversion: NULL argument");
    *out = NULL;
    if (img->channels == 1) return frig_image_clone(ctx, img, out);
    frig_image *g = fr_image_new(img->width, img->height, 1);
    if (!g) return fr_nomem(ctx, "a gray image");
    for (int y = 0; y < img->height; y++) {
        const uint8_t *s = img->pixels + (size_t)y * img->stride;
        uint8_t *d = g->pixels + (size_t)y * g->stride;
        for (int x = 0; x < img->width; x++, s += 3) d[x] = to_gray(s);
    }
    fr_image_copy_info(g, img);
    *out = g;
    return FRIG_OK;
}

/* BT.601 in 14-bit fixed point, rounded (the same integers as OpenCV's RGB2GRAY). */
static uint8_t bt601(const uint8_t *s) { return (uint8_t)((s[0] * 4899u + s[1] * 9617u + s[2] * 1868u + 8192u) >> 14); }

frig_status frig_image_to_gray(frig_ctx *ctx, const frig_image *img, frig_image **out) {
    if (!img || !out) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_image_to_gray: NULL argument");
    return fr_image_gray_map(ctx, img, bt601, out);
}
