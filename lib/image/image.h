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

/* Decoders: 'name' is used in messages. The result is in stored orientation with
 * 'orientation' set from EXIF (1 when absent). */
frig_status fr_jpeg_decode(frig_ctx *ctx, const char *name, const unsigned char *data, size_t size, unsigned flags,
                           frig_image **out);
frig_status fr_png_decode(frig_ctx *ctx, const char *name, const unsigned char *data, size_t size, unsigned flags,
                          frig_image **out);

/* Encoders to memory (caller frees *data). exif_orientation 0 writes no EXIF block. */
frig_status fr_jpeg_encode(frig_ctx *ctx, const frig_image *img, int quality, int exif_orientation,
                           unsigned char **data, size_t *size);
frig_status fr_png_encode(frig_ctx *ctx, const frig_image *img, unsigned char **data, size_t *size);

/* EXIF orientation (1-8) from a TIFF-structured EXIF block (starting at "II*\0" or "MM\0*");
 * 0 when absent or unreadable. */
int fr_exif_orientation(const unsigned char *tiff, size_t size);

/* A new image with the orientation transform applied (orientation 1: a copy). */
frig_image *fr_image_orient(const frig_image *img, int orientation);

#endif
