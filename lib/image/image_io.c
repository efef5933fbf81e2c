/* Loading by content (JPEG or PNG signature), orientation, and atomic saving. */
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "image/image.h"
#include "io/file.h"

/* The largest file we read: a JPEG of image.max_pixels can hardly exceed 3 bytes a pixel. */
static size_t max_file_size(const frig_ctx *ctx) {
    double px = fr_param(ctx, FRIG_PARAM_IMAGE_MAX_PIXELS);
    double bytes = px * 8.0 + (1 << 20);
    return bytes > (double)(SIZE_MAX / 2) ? SIZE_MAX / 2 : (size_t)bytes;
}

static frig_status decode(frig_ctx *ctx, const char *name, const unsigned char *data, size_t size, unsigned flags,
                          int *reduce, frig_image **out) {
    static const unsigned char png_sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    if (size == 0) return fr_error(ctx, FRIG_ERR_TRUNCATED, "%s: empty (0 bytes)", name);
    frig_image *img = NULL;
    frig_status s;
    if (size >= 2 && data[0] == 0xFF && data[1] == 0xD8) {
        s = fr_jpeg_decode(ctx, name, data, size, flags, *reduce, &img);
    } else if (size >= 8 && memcmp(data, png_sig, 8) == 0) {
        s = fr_png_decode(ctx, name, data, size, flags, &img);
        *reduce = 1;
    } else if (size < 8 && (data[0] == 0xFF || data[0] == 0x89)) {
        return fr_error(ctx, FRIG_ERR_TRUNCATED, "%s: only %zu bytes, too short for an image", name, size);
    } else {
        return fr_error(ctx, FRIG_ERR_UNSUPPORTED, "%s: not a JPEG or PNG file", name);
    }
    if (s) return s;
    if (!(flags & FRIG_LOAD_IGNORE_ORIENTATION) && img->orientation != 1) {
        frig_image *up = fr_image_orient(img, img->orientation);
        frig_image_free(img);
        if (!up) return fr_nomem(ctx, name);
        img = up;
    }
    *out = img;
    return FRIG_OK;
}

frig_status frig_image_load(frig_ctx *ctx, const char *path, unsigned flags, frig_image **out) {
    if (!out) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_image_load: no output pointer");
    *out = NULL;
    if (!path) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_image_load: no path");
    unsigned char *data;
    size_t size;
    frig_status s = fr_read_file(ctx, path, max_file_size(ctx), &data, &size);
    if (s) return s;
    int reduce = 1;
    s = decode(ctx, path, data, size, flags, &reduce, out);
    free(data);
    return s;
}

frig_status fr_image_load_reduced(frig_ctx *ctx, const char *path, unsigned flags, int reduce, frig_image **out,
                                  int *reduced) {
    *out = NULL;
    *reduced = 1;
    if (reduce != 1 && reduce != 2 && reduce != 4 && reduce != 8)
        return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "image reduction %d is not 1, 2, 4 or 8", reduce);
    unsigned char *data;
    size_t size;
    frig_status s = fr_read_file(ctx, path, max_file_size(ctx), &data, &size);
    if (s) return s;
    *reduced = reduce;
    s = decode(ctx, path, data, size, flags, reduced, out);
    free(data);
    return s;
}

frig_status frig_image_load_memory(frig_ctx *ctx, const void *data, size_t size, unsigned flags, frig_image **out) {
    if (!out) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_image_load_memory: no output pointer");
    *out = NULL;
    if (!data && size) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_image_load_memory: no data");
    int reduce = 1;
    return decode(ctx, "image in memory", data, size, flags, &reduce, out);
}

frig_status frig_image_save_png(frig_ctx *ctx, const frig_image *img, const char *path) {
    if (!img || !path) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_image_save_png: NULL argument");
    unsigned char *data;
    size_t size;
    frig_status s = fr_png_encode(ctx, img, &data, &size);
    if (s) return s;
    s = fr_write_file_atomic(ctx, path, data, size);
    free(data);
    return s;
}

frig_status frig_image_save_jpeg(frig_ctx *ctx, const frig_image *img, const char *path) {
    if (!img || !path) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_image_save_jpeg: NULL argument");
    unsigned char *data;
    size_t size;
    frig_status s = fr_jpeg_encode(ctx, img, fr_param_int(ctx, FRIG_PARAM_IMAGE_JPEG_QUALITY), 0, &data, &size);
    if (s) return s;
    s = fr_write_file_atomic(ctx, path, data, size);
    free(data);
    return s;
}
