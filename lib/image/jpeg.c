/* JPEG decoding and encoding over libjpeg-turbo, with an error manager that turns every
 * libjpeg error into a status (libjpeg's default handler would call exit()). */
#include <setjmp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <jerror.h>
#include <jpeglib.h>

#include "core/context.h"
#include "image/image.h"

typedef struct jpeg_guard {
    struct jpeg_error_mgr pub;
    jmp_buf jump;
    int hit_eof;     /* the data ended early (libjpeg inserted a fake end marker) */
    int corrupt;     /* the entropy-coded data was damaged */
    char msg[JMSG_LENGTH_MAX];
} jpeg_guard;

static void guard_error_exit(j_common_ptr c) {
    jpeg_guard *g = (jpeg_guard *)c->err;
    (*c->err->format_message)(c, g->msg);
    longjmp(g->jump, 1);
}

static void guard_emit_message(j_common_ptr c, int level) {
    if (level >= 0) return; /* trace messages */
    jpeg_guard *g = (jpeg_guard *)c->err;
    int code = c->err->msg_code;
    if (code == JWRN_JPEG_EOF) {
        g->hit_eof = 1;
    } else if (code == JWRN_HUFF_BAD_CODE || code == JWRN_MUST_RESYNC || code == JWRN_HIT_MARKER) {
        if (!g->corrupt) (*c->err->format_message)(c, g->msg);
        g->corrupt = 1;
    }
    c->err->num_warnings++;
}

static void cmyk_row_to_rgb(const uint8_t *cmyk, uint8_t *rgb, int width, int inverted) {
    for (int x = 0; x < width; x++, cmyk += 4, rgb += 3) {
        unsigned c = cmyk[0], m = cmyk[1], y = cmyk[2], k = cmyk[3];
        if (!inverted) { c = 255 - c; m = 255 - m; y = 255 - y; k = 255 - k; }
        /* Adobe writes inverted CMYK: stored c = 255 - cyan, so red = c * k / 255. */
        rgb[0] = (uint8_t)((c * k + 127) / 255);
        rgb[1] = (uint8_t)((m * k + 127) / 255);
        rgb[2] = (uint8_t)((y * k + 127) / 255);
    }
}

static uint8_t clamp_truncate(double v) { return v < 0 ? 0 : v > 255 ? 255 : (uint8_t)v; }

/* jpeg-js's colour conversion, in place: R = Y + 1.402 (Cr - 128), G = Y - 0.3441363 (Cb - 128)
 * - 0.71413636 (Cr - 128), B = Y + 1.772 (Cb - 128), clamped and truncated as a Uint8Array
 * store does. */
static void ycbcr_row_like_jpeg_js(uint8_t *p, int width) {
    for (int x = 0; x < width; x++, p += 3) {
        double y = p[0], cb = p[1] - 128.0, cr = p[2] - 128.0;
        p[0] = clamp_truncate(y + 1.402 * cr);
        p[1] = clamp_truncate(y - 0.3441363 * cb - 0.71413636 * cr);
        p[2] = clamp_truncate(y + 1.772 * cb);
    }
}

static int exif_from_markers(struct jpeg_decompress_struct *cinfo) {
    for (jpeg_saved_marker_ptr m = cinfo->marker_list; m; m = m->next)
        if (m->marker == JPEG_APP0 + 1 && m->data_length > 6 && memcmp(m->data, "Exif\0\0", 6) == 0) {
            int o = fr_exif_orientation(m->data + 6, m->data_length - 6);
            if (o) return o;
        }
    return 1;
}

frig_status fr_jpeg_decode(frig_ctx *ctx, const char *name, const unsigned char *data, size_t size, unsigned flags,
                           int reduce, frig_image **out) {
    struct jpeg_decompress_struct cinfo;
    jpeg_guard guard;
    frig_image *volatile img = NULL;
    uint8_t *volatile rowbuf = NULL;
    memset(&guard, 0, sizeof guard);
    cinfo.err = jpeg_std_error(&guard.pub);
    guard.pub.error_exit = guard_error_exit;
    guard.pub.emit_message = guard_emit_message;
    *out = NULL;

    if (setjmp(guard.jump)) {
        jpeg_destroy_decompress(&cinfo);
        frig_image_free(img);
        free(rowbuf);
        if (guard.hit_eof)
            return fr_error(ctx, FRIG_ERR_TRUNCATED, "%s: JPEG data ends too early (%s)", name, guard.msg);
        return fr_error(ctx, FRIG_ERR_CORRUPT, "%s: corrupt JPEG (%s)", name, guard.msg);
    }
    jpeg_create_decompress(&cinfo);
    jpeg_mem_src(&cinfo, data, (unsigned long)size);
    jpeg_save_markers(&cinfo, JPEG_APP0 + 1, 0xFFFF);
    jpeg_read_header(&cinfo, TRUE);
    int orientation = exif_from_markers(&cinfo); /* before finish: markers live in the image pool */

    double max_px = fr_param(ctx, FRIG_PARAM_IMAGE_MAX_PIXELS);
    if ((double)cinfo.image_width * (double)cinfo.image_height > max_px) {
        frig_status s = fr_error(ctx, FRIG_ERR_TOO_LARGE, "%s: %ux%u pixels is over image.max_pixels = %.0f", name,
                                 cinfo.image_width, cinfo.image_height, max_px);
        jpeg_destroy_decompress(&cinfo);
        return s;
    }
    int gray = (flags & FRIG_LOAD_GRAY) != 0;
    int cmyk = cinfo.jpeg_color_space == JCS_CMYK || cinfo.jpeg_color_space == JCS_YCCK;
    int source_channels = cinfo.num_components;
    if (cmyk) cinfo.out_color_space = JCS_CMYK;
    else cinfo.out_color_space = gray ? JCS_GRAYSCALE : JCS_RGB;
    /* jpeg-js (what @vladmandic/face-api's references decode with): chroma repeated, not
     * interpolated, and its own floating-point YCbCr -> RGB, truncated. */
    int like_js = (flags & FR_LOAD_LIKE_JPEG_JS) && !gray && !cmyk && cinfo.jpeg_color_space == JCS_YCbCr;
    if (like_js) {
        cinfo.out_color_space = JCS_YCbCr;
        cinfo.do_fancy_upsampling = FALSE;
    }
    if (reduce > 1) {
        cinfo.scale_num = 1;
        cinfo.scale_denom = (unsigned)reduce;
    }
    jpeg_start_decompress(&cinfo);

    int w = (int)cinfo.output_width, h = (int)cinfo.output_height;
    int channels = gray ? 1 : 3;
    img = fr_image_new(w, h, channels);
    if (cmyk) rowbuf = malloc((size_t)w * 4 + (size_t)w * 3);
    if (!img || (cmyk && !rowbuf)) {
        jpeg_destroy_decompress(&cinfo);
        frig_image_free(img);
        free(rowbuf);
        return fr_nomem(ctx, name);
    }
    while (cinfo.output_scanline < cinfo.output_height) {
        uint8_t *dst = img->pixels + (size_t)cinfo.output_scanline * img->stride;
        JSAMPROW row = cmyk ? (JSAMPROW)rowbuf : dst;
        jpeg_read_scanlines(&cinfo, &row, 1);
        if (like_js) ycbcr_row_like_jpeg_js(dst, w);
        if (cmyk) {
            uint8_t *rgb = rowbuf + (size_t)w * 4;
            cmyk_row_to_rgb(rowbuf, gray ? rgb : dst, w, cinfo.saw_Adobe_marker);
            if (gray)
                for (int x = 0; x < w; x++)
                    dst[x] = (uint8_t)((rgb[3 * x] * 4899u + rgb[3 * x + 1] * 9617u + rgb[3 * x + 2] * 1868u + 8192u) >>
                                       14);
        }
    }
    jpeg_finish_decompress(&cinfo);
    jpeg_destroy_decompress(&cinfo);
    free(rowbuf);
    rowbuf = NULL;

    if (guard.hit_eof) {
        frig_image_free(img);
        return fr_error(ctx, FRIG_ERR_TRUNCATED, "%s: JPEG data ends before the image does (file cut short?)", name);
    }
    if (guard.corrupt) {
        frig_image_free(img);
        return fr_error(ctx, FRIG_ERR_CORRUPT, "%s: damaged JPEG data (%s)", name, guard.msg);
    }
    img->format = FRIG_FORMAT_JPEG;
    img->source_channels = source_channels;
    img->source_bit_depth = 8;
    img->orientation = orientation;
    img->cmyk = cmyk;
    *out = img;
    return FRIG_OK;
}

/* A minimal big-endian TIFF block with one IFD0 entry: Orientation. */
static void exif_block(uint8_t out[32], int orientation) {
    static const uint8_t head[] = {'E', 'x', 'i', 'f', 0, 0, 'M', 'M', 0, 42, 0, 0, 0, 8, 0, 1,
                                   0x01, 0x12, 0, 3, 0, 0, 0, 1};
    memset(out, 0, 32);
    memcpy(out, head, sizeof head);
    out[24] = 0;
    out[25] = (uint8_t)orientation;
    /* bytes 26..31: value padding and a zero next-IFD offset */
}

frig_status fr_jpeg_encode(frig_ctx *ctx, const frig_image *img, int quality, int exif_orientation,
                           unsigned char **data, size_t *size) {
    struct jpeg_compress_struct cinfo;
    jpeg_guard guard;
    unsigned char *volatile buf = NULL;
    unsigned long len = 0;
    memset(&guard, 0, sizeof guard);
    cinfo.err = jpeg_std_error(&guard.pub);
    guard.pub.error_exit = guard_error_exit;
    guard.pub.emit_message = guard_emit_message;
    *data = NULL;
    *size = 0;
    if (setjmp(guard.jump)) {
        jpeg_destroy_compress(&cinfo);
        free(buf);
        return fr_error(ctx, FRIG_ERR_INTERNAL, "JPEG encoder failed (%s)", guard.msg);
    }
    jpeg_create_compress(&cinfo);
    unsigned char *b = NULL;
    jpeg_mem_dest(&cinfo, &b, &len);
    cinfo.image_width = (JDIMENSION)img->width;
    cinfo.image_height = (JDIMENSION)img->height;
    cinfo.input_components = img->channels;
    cinfo.in_color_space = img->channels == 1 ? JCS_GRAYSCALE : JCS_RGB;
    jpeg_set_defaults(&cinfo);
    jpeg_set_quality(&cinfo, quality, TRUE);
    jpeg_start_compress(&cinfo, TRUE);
    if (exif_orientation) {
        uint8_t ex[32];
        exif_block(ex, exif_orientation);
        jpeg_write_marker(&cinfo, JPEG_APP0 + 1, ex, sizeof ex);
    }
    while (cinfo.next_scanline < cinfo.image_height) {
        JSAMPROW row = (JSAMPROW)(img->pixels + (size_t)cinfo.next_scanline * img->stride);
        jpeg_write_scanlines(&cinfo, &row, 1);
    }
    jpeg_finish_compress(&cinfo);
    buf = b;
    jpeg_destroy_compress(&cinfo);
    *data = buf;
    *size = len;
    return FRIG_OK;
}
