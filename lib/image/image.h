/* The image handle's inside and the codec entry points (internal). */
#ifndef FR_IMAGE_IMAGE_H
#define FR_IMAGE_IMAGE_H

#include "frig/image.h"

struct frig_image {
    int width, height, channels;
    size_t stride;
    uint8_t *pixels;
    frig_image_format format;
    int source_channels, source_bit_depth, orientation, cmyk;
};

/* Allocate an image (zeroed); NULL when out of memory or sizes overflow. */
frig_image *fr_image_new(int width, int height, int channels);

/* Internal load flag: decode a JPEG as the npm decoder jpeg-js does (chroma repeated, its own
 * floating-point YCbCr -> RGB), the decoder @vladmandic/face-api's reference answers use, so
 * that its networks see the reference's pixels (to a grey level on about one sample in ten: the
 * IDCTs differ). PNG and gray or CMYK JPEGs decode as usual. */
#define FR_LOAD_LIKE_JPEG_JS (1u << 16)

/* Decoders: 'name' is used in messages. The result is in stored orientation with
 * 'orientation' set from EXIF (1 when absent). */
frig_status fr_jpeg_decode(frig_ctx *ctx, const char *name, const unsigned char *data, size_t size, unsigned flags,
                           int reduce, frig_image **out);

/* Load an image reduced by 'reduce' (1, 2, 4 or 8) where the codec can do it cheaply (JPEG:
 * libjpeg's DCT scaling; PNG is decoded whole). *reduced tells the factor applied: pixel i of
 * the result is centred on pixel i * r + (r - 1) / 2 of the full upright image. */
frig_status fr_image_load_reduced(frig_ctx *ctx, const char *path, unsigned flags, int reduce, frig_image **out,
                                  int *reduced);
frig_status fr_png_decode(frig_ctx *ctx, const char *name, const unsigned char *data, size_t size, unsigned flags,
                          frig_image **out);

/* Encoders to memory (caller frees *data). exif_orientation 0 writes no EXIF block. */
frig_status fr_jpeg_encode(frig_ctx *ctx, const frig_image *img, int quality, int exif_orientation,
                           unsigned char **data, size_t *size);
frig_status fr_png_encode(frig_ctx *ctx, const frig_image *img, unsigned char **data, size_t *size);
/* 8-bit rows of 1 (gray), 2 (gray + alpha), 3 (RGB) or 4 (RGBA) channels, 'stride' bytes apart
 * (textures with alpha, which frig_image does not hold). */
frig_status fr_png_encode_pixels(frig_ctx *ctx, int width, int height, int channels, size_t stride,
                                 const uint8_t *pixels, unsigned char **data, size_t *size);

/* EXIF orientation (1-8) from a TIFF-structured EXIF block (starting at "II*\0" or "MM\0*");
 * 0 when absent or unreadable. */
int fr_exif_orientation(const unsigned char *tiff, size_t size);

/* Copy what the file held (format, source channels and bit depth, orientation, CMYK). */
void fr_image_copy_info(frig_image *dst, const frig_image *src);

/* A one-channel copy of an RGB image made pixel by pixel by 'to_gray' (given the pixel's
 * three samples); a gray image is cloned. */
frig_status fr_image_gray_map(frig_ctx *ctx, const frig_image *img, uint8_t (*to_gray)(const uint8_t *rgb),
                              frig_image **out);

/* A new image with the orientation transform applied (orientation 1: a copy). */
frig_image *fr_image_orient(const frig_image *img, int orientation);

#endif
