/* libfrig images: JPEG and PNG in, 8-bit RGB (or gray) out, EXIF orientation applied,
 * atomic saves. Pixel coordinates everywhere in libfrig are those of the upright photo.
 */
#ifndef FRIG_IMAGE_H
#define FRIG_IMAGE_H

#include "frig/core.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct frig_image frig_image;

/* Flags for frig_image_load*(). */
enum {
    FRIG_LOAD_DEFAULT = 0,
    /* Decode to one gray channel (for JPEG: the decoder's own luma, as OpenCV's
     * IMREAD_GRAYSCALE does) instead of RGB. */
    FRIG_LOAD_GRAY = 1u << 0,
    /* Keep pixels as stored: do not apply the EXIF orientation tag. */
    FRIG_LOAD_IGNORE_ORIENTATION = 1u << 1
};

typedef enum frig_image_format {
    FRIG_FORMAT_UNKNOWN = 0,
    FRIG_FORMAT_JPEG = 1,
    FRIG_FORMAT_PNG = 2
} frig_image_format;

/* Load a JPEG or PNG (recognized by content, not name). Grayscale, CMYK/YCCK and progressive
 * JPEGs, 1-16 bit, palette and alpha PNGs are accepted: 16-bit samples are scaled to 8 bits,
 * palettes expanded, alpha dropped, CMYK converted to RGB. Images with more pixels than the
 * parameter image.max_pixels are refused (FRIG_ERR_TOO_LARGE) before any pixel is allocated.
 * Statuses: FRIG_ERR_NOT_FOUND, FRIG_ERR_IO, FRIG_ERR_CORRUPT, FRIG_ERR_TRUNCATED,
 * FRIG_ERR_UNSUPPORTED, FRIG_ERR_TOO_LARGE, FRIG_ERR_NO_MEMORY. */
FRIG_API frig_status frig_image_load(frig_ctx *ctx, const char *path, unsigned flags, frig_image **out);
FRIG_API frig_status frig_image_load_memory(frig_ctx *ctx, const void *data, size_t size, unsigned flags,
                                            frig_image **out);

/* A new image with every sample zero; channels is 1 (gray) or 3 (RGB). */
FRIG_API frig_status frig_image_create(frig_ctx *ctx, int width, int height, int channels, frig_image **out);
FRIG_API frig_status frig_image_clone(frig_ctx *ctx, const frig_image *image, frig_image **out);
FRIG_API void frig_image_free(frig_image *image);

FRIG_API int frig_image_width(const frig_image *image);
FRIG_API int frig_image_height(const frig_image *image);
FRIG_API int frig_image_channels(const frig_image *image);
/* Bytes from one row to the next (at least width * channels). */
FRIG_API size_t frig_image_stride(const frig_image *image);
/* Row-major samples, RGB interleaved. */
FRIG_API const uint8_t *frig_image_pixels(const frig_image *image);
FRIG_API uint8_t *frig_image_pixels_mutable(frig_image *image);

/* What the file held, before conversion (for images made in memory: what they are). */
FRIG_API frig_image_format frig_image_source_format(const frig_image *image);
FRIG_API int frig_image_source_channels(const frig_image *image);   /* 1 gray, 2 gray+alpha, 3, 4 */
FRIG_API int frig_image_source_bit_depth(const frig_image *image);  /* 1, 2, 4, 8 or 16 */
/* The EXIF orientation tag found (1-8; 1 when absent); applied unless IGNORE_ORIENTATION. */
FRIG_API int frig_image_orientation(const frig_image *image);
/* 1 if the file was a CMYK or YCCK JPEG. */
FRIG_API int frig_image_source_cmyk(const frig_image *image);

/* Gray copy (ITU-R BT.601 weights, rounded) of an RGB image; a gray image is copied. */
FRIG_API frig_status frig_image_to_gray(frig_ctx *ctx, const frig_image *image, frig_image **out);

/* Save atomically: the data is written to a temporary file in the same folder, flushed,
 * then renamed over 'path', so a failure never leaves a half file where a good one was.
 * The JPEG quality is the parameter image.jpeg_quality. */
FRIG_API frig_status frig_image_save_png(frig_ctx *ctx, const frig_image *image, const char *path);
FRIG_API frig_status frig_image_save_jpeg(frig_ctx *ctx, const frig_image *image, const char *path);

/* A thumbnail of an image file: decoded at a reduced size where the codec can (JPEG), then
 * area-averaged to fit max_side (8 to 8192) on its longer side (never enlarged), saved
 * atomically as a JPEG (image.jpeg_quality). */
FRIG_API frig_status frig_image_save_thumbnail(frig_ctx *ctx, const char *src, int max_side, const char *dst);

#ifdef __cplusplus
}
#endif
#endif /* FRIG_IMAGE_H */
