/* PNG decoding and encoding over libpng, errors turned into statuses (setjmp). */
#include <setjmp.h>
#include <stdlib.h>
#include <string.h>

#include <png.h>

#include "core/context.h"
#include "image/image.h"

typedef struct png_reader {
    const unsigned char *data;
    size_t size, pos;
    int hit_end;
    char msg[256];
} png_reader;

static void read_fn(png_structp png, png_bytep out, png_size_t n) {
    png_reader *r = png_get_io_ptr(png);
    if (n > r->size - r->pos) {
        r->hit_end = 1;
        png_error(png, "file ends too early");
    }
    memcpy(out, r->data + r->pos, n);
    r->pos += n;
}

static void error_fn(png_structp png, png_const_charp msg) {
    png_reader *r = png_get_error_ptr(png);
    if (r) snprintf(r->msg, sizeof r->msg, "%s", msg);
    png_longjmp(png, 1);
}

static void warning_fn(png_structp png, png_const_charp msg) {
    (void)png;
    (void)msg;
}

frig_status fr_png_decode(frig_ctx *ctx, const char *name, const unsigned char *data, size_t size, unsigned flags,
                          frig_image **out) {
    png_reader r = {data, size, 0, 0, ""};
    frig_image *volatile img = NULL;
    png_bytep *volatile rows = NULL;
    png_infop info = NULL;
    *out = NULL;
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &r, error_fn, warning_fn);
    if (!png) return fr_nomem(ctx, "a PNG decoder");
    info = png_create_info_struct(png);
    if (!info) {
        png_destroy_read_struct(&png, NULL, NULL);
        return fr_nomem(ctx, "a PNG decoder");
    }
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_read_struct(&png, &info, NULL);
        frig_image_free(img);
        free(rows);
        if (r.hit_end) return fr_error(ctx, FRIG_ERR_TRUNCATED, "%s: PNG data ends too early", name);
        return fr_error(ctx, FRIG_ERR_CORRUPT, "%s: corrupt PNG (%s)", name, r.msg);
    }
    png_set_read_fn(png, &r, read_fn);
    /* We check the pixel count ourselves; lift libpng's own (lower) width/height caps. */
    png_set_user_limits(png, 0x7fffffff, 0x7fffffff);
    png_read_info(png, info);

    png_uint_32 w = png_get_image_width(png, info), h = png_get_image_height(png, info);
    double max_px = fr_param(ctx, FRIG_PARAM_IMAGE_MAX_PIXELS);
    if ((double)w * (double)h > max_px) {
        png_destroy_read_struct(&png, &info, NULL);
        return fr_error(ctx, FRIG_ERR_TOO_LARGE, "%s: %ux%u pixels is over image.max_pixels = %.0f", name,
                        (unsigned)w, (unsigned)h, max_px);
    }
    int color = png_get_color_type(png, info);
    int depth = png_get_bit_depth(png, info);
    int source_channels = png_get_channels(png, info);
    int gray = (flags & FRIG_LOAD_GRAY) != 0;

    if (color == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(png);
    if (color == PNG_COLOR_TYPE_GRAY && depth < 8) png_set_expand_gray_1_2_4_to_8(png);
    if (depth == 16) png_set_scale_16(png);
    png_set_strip_alpha(png);
    int is_gray = color == PNG_COLOR_TYPE_GRAY || color == PNG_COLOR_TYPE_GRAY_ALPHA;
    /* OpenCV's IMREAD_GRAYSCALE asks libpng for weights 0.299/0.587 (libpng truncates them to
     * 9797/19234/3737 out of 32768 and truncates each sum): the same call gives the same bytes. */
    if (gray && !is_gray) png_set_rgb_to_gray_fixed(png, 1, 29900, 58700);
    if (!gray && is_gray) png_set_gray_to_rgb(png);
    png_set_interlace_handling(png);
    png_read_update_info(png, info);
    int channels = gray ? 1 : 3;
    if ((int)png_get_channels(png, info) != channels || png_get_bit_depth(png, info) != 8) {
        png_destroy_read_struct(&png, &info, NULL);
        return fr_error(ctx, FRIG_ERR_UNSUPPORTED, "%s: PNG layout (color type %d, depth %d) not handled", name,
                        color, depth);
    }
    img = fr_image_new((int)w, (int)h, channels);
    rows = malloc(sizeof(png_bytep) * h);
    if (!img || !rows) {
        png_destroy_read_struct(&png, &info, NULL);
        frig_image_free(img);
        free(rows);
        return fr_nomem(ctx, name);
    }
    for (png_uint_32 y = 0; y < h; y++) rows[y] = img->pixels + (size_t)y * img->stride;
    png_read_image(png, rows);
    png_read_end(png, info);

    int orientation = 1;
    png_bytep exif = NULL;
    png_uint_32 exif_len = 0;
    if (png_get_eXIf_1(png, info, &exif_len, &exif) && exif) {
        int o = fr_exif_orientation(exif, exif_len);
        if (o) orientation = o;
    }
    png_destroy_read_struct(&png, &info, NULL);
    free(rows);
    img->format = FRIG_FORMAT_PNG;
    img->source_channels = source_channels;
    img->source_bit_depth = depth;
    img->orientation = orientation;
    *out = img;
    return FRIG_OK;
}

typedef struct png_writer {
    unsigned char *data;
    size_t size, cap;
    int failed;
} png_writer;

static void write_fn(png_structp png, png_bytep in, png_size_t n) {
    png_writer *w = png_get_io_ptr(png);
    if (w->size + n > w->cap) {
        size_t cap = w->cap ? w->cap : 65536;
        while (cap < w->size + n) cap *= 2;
        unsigned char *d = realloc(w->data, cap);
        if (!d) {
            w->failed = 1;
            png_error(png, "out of memory");
        }
        w->data = d;
        w->cap = cap;
    }
    memcpy(w->data + w->size, in, n);
    w->size += n;
}

static void flush_fn(png_structp png) { (void)png; }

frig_status fr_png_encode_pixels(frig_ctx *ctx, int width, int height, int channels, size_t stride,
                                 const uint8_t *pixels, unsigned char **data, size_t *size) {
    static const int types[5] = {0, PNG_COLOR_TYPE_GRAY, PNG_COLOR_TYPE_GRAY_ALPHA, PNG_COLOR_TYPE_RGB,
                                 PNG_COLOR_TYPE_RGB_ALPHA};
    png_writer w = {NULL, 0, 0, 0};
    *data = NULL;
    *size = 0;
    if (width <= 0 || height <= 0 || channels < 1 || channels > 4)
        return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "a PNG of %d x %d pixels with %d channels", width, height,
                        channels);
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, NULL, error_fn, warning_fn);
    if (!png) return fr_nomem(ctx, "a PNG encoder");
    png_infop info = png_create_info_struct(png);
    if (!info || setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        free(w.data);
        return w.failed ? fr_nomem(ctx, "PNG data") : fr_error(ctx, FRIG_ERR_INTERNAL, "PNG encoder failed");
    }
    png_set_write_fn(png, &w, write_fn, flush_fn);
    png_set_IHDR(png, info, (png_uint_32)width, (png_uint_32)height, 8, types[channels], PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_set_compression_level(png, 6);
    png_write_info(png, info);
    for (int y = 0; y < height; y++) png_write_row(png, pixels + (size_t)y * stride);
    png_write_end(png, info);
    png_destroy_write_struct(&png, &info);
    *data = w.data;
    *size = w.size;
    return FRIG_OK;
}

frig_status fr_png_encode(frig_ctx *ctx, const frig_image *img, unsigned char **data, size_t *size) {
    return fr_png_encode_pixels(ctx, img->width, img->height, img->channels, img->stride, img->pixels, data, size);
}
