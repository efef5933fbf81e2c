/* Images: the bad-image corpus (each file must give its documented status, no crash, no
 * leak), every EXIF orientation, CMYK/YCCK, gray, progressive, 16-bit, palette, alpha and
 * interlaced files, and atomic saves. The corpus is made here, by the test itself. */
#include <dirent.h>
#include <math.h>
#include <setjmp.h>
#include <stdlib.h>
#include <string.h>
#include <stdio.h>
#include <sys/stat.h>

#include <jpeglib.h>
#include <png.h>
#include <zlib.h>

#include "frig/frig.h"
#include "image/gaussian_blur.h"
#include "image/image.h"
#include "image/pull_push.h"
#include "testing.h"

static frig_ctx *ctx;
static const char *dir;

static const char *path_of(const char *name) {
    static char buf[4096];
    snprintf(buf, sizeof buf, "%s/%s", dir, name);
    return buf;
}

static void write_bytes(const char *name, const void *data, size_t n) {
    FILE *fp = fopen(path_of(name), "wb");
    if (!fp) abort();
    if (n) fwrite(data, 1, n, fp);
    fclose(fp);
}

/* A test pattern whose every pixel is distinct enough to tell orientations apart. */
static frig_image *pattern(int w, int h) {
    frig_image *img = fr_image_new(w, h, 3);
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            uint8_t *p = img->pixels + (size_t)y * img->stride + 3 * (size_t)x;
            p[0] = (uint8_t)(x * 255 / (w - 1));
            p[1] = (uint8_t)(y * 255 / (h - 1));
            p[2] = (uint8_t)(40 + (x * 160) / (w - 1));
        }
    return img;
}

static void save_jpeg_bytes(const char *name, const frig_image *img, int quality, int orientation,
                            unsigned char **data, size_t *size) {
    if (fr_jpeg_encode(ctx, img, quality, orientation, data, size)) abort();
    write_bytes(name, *data, *size);
}

/* ---- a libpng writer for the unusual layouts ---- */
typedef struct png_spec {
    int width, height, color_type, bit_depth, interlace;
    const png_color *palette;
    int palette_size;
    const unsigned char *exif;
    int exif_size;
} png_spec;

static void write_png_file(const char *name, const png_spec *s, png_bytep *rows) {
    FILE *fp = fopen(path_of(name), "wb");
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    png_infop info = png_create_info_struct(png);
    if (setjmp(png_jmpbuf(png))) abort();
    png_init_io(png, fp);
    png_set_IHDR(png, info, (png_uint_32)s->width, (png_uint_32)s->height, s->bit_depth, s->color_type,
                 s->interlace ? PNG_INTERLACE_ADAM7 : PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
                 PNG_FILTER_TYPE_DEFAULT);
    if (s->palette) png_set_PLTE(png, info, s->palette, s->palette_size);
    if (s->exif) png_set_eXIf_1(png, info, (png_uint_32)s->exif_size, (png_bytep)s->exif);
    png_write_info(png, info);
    png_write_image(png, rows);
    png_write_end(png, info);
    png_destroy_write_struct(&png, &info);
    fclose(fp);
}

/* ---- CMYK / YCCK JPEG (Adobe convention: inverted values) ---- */
static void write_cmyk_jpeg(const char *name, int w, int h, const uint8_t rgb[3], J_COLOR_SPACE jpeg_space) {
    struct jpeg_compress_struct c;
    struct jpeg_error_mgr e;
    c.err = jpeg_std_error(&e);
    jpeg_create_compress(&c);
    FILE *fp = fopen(path_of(name), "wb");
    jpeg_stdio_dest(&c, fp);
    c.image_width = (JDIMENSION)w;
    c.image_height = (JDIMENSION)h;
    c.input_components = 4;
    c.in_color_space = JCS_CMYK;
    jpeg_set_defaults(&c);
    jpeg_set_colorspace(&c, jpeg_space);
    jpeg_set_quality(&c, 95, TRUE);
    jpeg_start_compress(&c, TRUE);
    unsigned k = rgb[0] > rgb[1] ? rgb[0] : rgb[1];
    if (rgb[2] > k) k = rgb[2];
    uint8_t px[4] = {(uint8_t)(k ? rgb[0] * 255 / k : 0), (uint8_t)(k ? rgb[1] * 255 / k : 0),
                     (uint8_t)(k ? rgb[2] * 255 / k : 0), (uint8_t)k};
    uint8_t *row = malloc((size_t)w * 4);
    for (int x = 0; x < w; x++) memcpy(row + 4 * x, px, 4);
    while (c.next_scanline < c.image_height) jpeg_write_scanlines(&c, &row, 1);
    jpeg_finish_compress(&c);
    jpeg_destroy_compress(&c);
    fclose(fp);
    free(row);
}

static void write_progressive_jpeg(const char *name, const frig_image *img) {
    struct jpeg_compress_struct c;
    struct jpeg_error_mgr e;
    c.err = jpeg_std_error(&e);
    jpeg_create_compress(&c);
    FILE *fp = fopen(path_of(name), "wb");
    jpeg_stdio_dest(&c, fp);
    c.image_width = (JDIMENSION)img->width;
    c.image_height = (JDIMENSION)img->height;
    c.input_components = 3;
    c.in_color_space = JCS_RGB;
    jpeg_set_defaults(&c);
    jpeg_simple_progression(&c);
    jpeg_set_quality(&c, 95, TRUE);
    jpeg_start_compress(&c, TRUE);
    while (c.next_scanline < c.image_height) {
        JSAMPROW row = img->pixels + (size_t)c.next_scanline * img->stride;
        jpeg_write_scanlines(&c, &row, 1);
    }
    jpeg_finish_compress(&c);
    jpeg_destroy_compress(&c);
    fclose(fp);
}

/* Load 'name', print the status for the record, and check it is the documented one. */
static frig_image *expect(const char *name, frig_status want) {
    frig_image *img = NULL;
    frig_status s = frig_image_load(ctx, path_of(name), 0, &img);
    printf("  %-30s -> %-22s %s\n", name, s ? frig_strerror(s) : "ok", s ? frig_ctx_errmsg(ctx) : "");
    if (s != want) {
        fprintf(stderr, "%s: got status %d (%s), expected %d (%s)\n", name, s, frig_strerror(s), want,
                frig_strerror(want));
        test_failures++;
    }
    if (s) {
        CHECK(img == NULL);
        CHECK(strlen(frig_ctx_errmsg(ctx)) > 0);
        CHECK(strstr(frig_ctx_errmsg(ctx), name) != NULL || want == FRIG_ERR_NOT_FOUND);
    }
    return img;
}

static int pixel_close(const frig_image *img, int x, int y, const uint8_t *want, int tol) {
    const uint8_t *p = img->pixels + (size_t)y * img->stride + (size_t)x * img->channels;
    for (int c = 0; c < img->channels; c++)
        if (abs(p[c] - want[c]) > tol) return 0;
    return 1;
}

static void test_bad_files(void) {
    printf("bad-image corpus:\n");
    frig_image *src = pattern(64, 48);
    unsigned char *jpg;
    size_t jn;
    save_jpeg_bytes("good.jpg", src, 90, 0, &jpg, &jn);

    write_bytes("empty.jpg", "", 0);
    expect("empty.jpg", FRIG_ERR_TRUNCATED);

    write_bytes("truncated_half.jpg", jpg, jn / 2);
    expect("truncated_half.jpg", FRIG_ERR_TRUNCATED);
    write_bytes("truncated_header.jpg", jpg, 100);
    expect("truncated_header.jpg", FRIG_ERR_TRUNCATED);
    write_bytes("truncated_2bytes.jpg", jpg, 2);
    expect("truncated_2bytes.jpg", FRIG_ERR_TRUNCATED);

    /* A good header followed by damaged entropy-coded data. */
    unsigned char *dam = malloc(jn);
    memcpy(dam, jpg, jn);
    srand(7);
    for (size_t i = jn / 2; i < jn - 2; i++) dam[i] = (unsigned char)(rand() & 0xff);
    write_bytes("damaged_scan.jpg", dam, jn);
    expect("damaged_scan.jpg", FRIG_ERR_CORRUPT);

    /* JPEG signature then random bytes. */
    unsigned char rnd[4096];
    for (size_t i = 0; i < sizeof rnd; i++) rnd[i] = (unsigned char)(rand() & 0xff);
    rnd[0] = 0xFF;
    rnd[1] = 0xD8;
    write_bytes("random_after_soi.jpg", rnd, sizeof rnd);
    expect("random_after_soi.jpg", FRIG_ERR_CORRUPT);

    static const unsigned char sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    memcpy(rnd, sig, 8);
    write_bytes("random_after_sig.png", rnd, sizeof rnd);
    expect("random_after_sig.png", FRIG_ERR_CORRUPT);

    rnd[0] = 'G';
    write_bytes("random.jpg", rnd, sizeof rnd);
    expect("random.jpg", FRIG_ERR_UNSUPPORTED);
    write_bytes("text.png", "hello, this is not an image\n", 28);
    expect("text.png", FRIG_ERR_UNSUPPORTED);

    /* A PNG cut short. */
    unsigned char *png;
    size_t pn;
    if (fr_png_encode(ctx, src, &png, &pn)) abort();
    write_bytes("truncated.png", png, pn / 2);
    expect("truncated.png", FRIG_ERR_TRUNCATED);
    write_bytes("truncated_ihdr.png", png, 20);
    expect("truncated_ihdr.png", FRIG_ERR_TRUNCATED);
    /* A PNG whose data CRC is wrong. */
    png[pn - 20] ^= 0x55;
    write_bytes("bad_crc.png", png, pn);
    expect("bad_crc.png", FRIG_ERR_CORRUPT);
    free(png);

    /* Headers claiming enormous images: refused before allocating. */
    {
        png_bytep rows1[1];
        uint8_t row[3 * 4] = {0};
        rows1[0] = row;
        png_spec s = {4, 1, PNG_COLOR_TYPE_RGB, 8, 0, NULL, 0, NULL, 0};
        write_png_file("huge_src.png", &s, rows1);
        unsigned char *h;
        size_t hn;
        char p[4096];
        snprintf(p, sizeof p, "%s", path_of("huge_src.png"));
        FILE *fp = fopen(p, "rb");
        fseek(fp, 0, SEEK_END);
        hn = (size_t)ftell(fp);
        rewind(fp);
        h = malloc(hn);
        if (fread(h, 1, hn, fp) != hn) abort();
        fclose(fp);
        /* IHDR width/height at bytes 16..23; then recompute the chunk CRC (bytes 29..32). */
        uint32_t W = 100000, H = 100000;
        unsigned char *ihdr = h + 16;
        ihdr[0] = (unsigned char)(W >> 24); ihdr[1] = (unsigned char)(W >> 16); ihdr[2] = (unsigned char)(W >> 8);
        ihdr[3] = (unsigned char)W;
        ihdr[4] = (unsigned char)(H >> 24); ihdr[5] = (unsigned char)(H >> 16); ihdr[6] = (unsigned char)(H >> 8);
        ihdr[7] = (unsigned char)H;
        uint32_t crc = (uint32_t)crc32(0, h + 12, 17);
        h[29] = (unsigned char)(crc >> 24); h[30] = (unsigned char)(crc >> 16); h[31] = (unsigned char)(crc >> 8);
        h[32] = (unsigned char)crc;
        write_bytes("huge_100000x100000.png", h, hn);
        expect("huge_100000x100000.png", FRIG_ERR_TOO_LARGE);
        free(h);
    }
    {
        /* SOF0 of our JPEG: find FF C0 and overwrite height/width with 65000. */
        unsigned char *h = malloc(jn);
        memcpy(h, jpg, jn);
        for (size_t i = 2; i + 9 < jn; i++)
            if (h[i] == 0xFF && h[i + 1] == 0xC0) {
                h[i + 5] = 0xFD; h[i + 6] = 0xE8; /* 65000 */
                h[i + 7] = 0xFD; h[i + 8] = 0xE8;
                break;
            }
        write_bytes("huge_65000x65000.jpg", h, jn);
        expect("huge_65000x65000.jpg", FRIG_ERR_TOO_LARGE);
        free(h);
    }
    /* A normal image over a lowered limit. */
    frig_ctx_set_param(ctx, FRIG_PARAM_IMAGE_MAX_PIXELS, 1000);
    expect("good.jpg", FRIG_ERR_TOO_LARGE);
    frig_ctx_set_param(ctx, FRIG_PARAM_IMAGE_MAX_PIXELS, 1e8);

    expect("does_not_exist.jpg", FRIG_ERR_NOT_FOUND);
    mkdir(path_of("a_folder.jpg"), 0755);
    expect("a_folder.jpg", FRIG_ERR_IO);

    frig_image *good = expect("good.jpg", FRIG_OK);
    CHECK(good && good->width == 64 && good->height == 48);
    frig_image_free(good);

    /* Loading from memory gives the same statuses. */
    frig_image *m = NULL;
    CHECK(frig_image_load_memory(ctx, jpg, jn / 2, 0, &m) == FRIG_ERR_TRUNCATED && !m);
    CHECK(frig_image_load_memory(ctx, jpg, jn, 0, &m) == FRIG_OK && m);
    frig_image_free(m);

    free(dam);
    free(jpg);
    frig_image_free(src);
}

static void test_orientations(void) {
    printf("EXIF orientations:\n");
    frig_image *src = pattern(40, 24); /* stored 40 wide, 24 high */
    for (int o = 1; o <= 8; o++) {
        char name[64];
        snprintf(name, sizeof name, "orientation_%d.jpg", o);
        unsigned char *d;
        size_t n;
        save_jpeg_bytes(name, src, 98, o, &d, &n);
        free(d);
        frig_image *img = expect(name, FRIG_OK);
        if (!img) continue;
        CHECK(frig_image_orientation(img) == o);
        int swap = o >= 5;
        CHECK(img->width == (swap ? 24 : 40) && img->height == (swap ? 40 : 24));
        /* The upright image must equal our own transform of the stored pattern. */
        frig_image *want = fr_image_orient(src, o);
        int bad = 0;
        for (int y = 0; y < img->height; y++)
            for (int x = 0; x < img->width; x++)
                if (!pixel_close(img, x, y, want->pixels + (size_t)y * want->stride + 3 * (size_t)x, 12)) bad++;
        if (bad) fprintf(stderr, "orientation %d: %d pixels differ\n", o, bad);
        CHECK(bad == 0);
        /* Spot checks against the EXIF table itself, independent of fr_image_orient:
         * stored top-left (red 0, green 0) must land where the standard puts it. */
        int tlx = 0, tly = 0, W = img->width, H = img->height;
        switch (o) {
        case 1: tlx = 0; tly = 0; break;
        case 2: tlx = W - 1; tly = 0; break;
        case 3: tlx = W - 1; tly = H - 1; break;
        case 4: tlx = 0; tly = H - 1; break;
        case 5: tlx = 0; tly = 0; break;
        case 6: tlx = W - 1; tly = 0; break;
        case 7: tlx = W - 1; tly = H - 1; break;
        case 8: tlx = 0; tly = H - 1; break;
        }
        const uint8_t black_ish[3] = {0, 0, 40};
        CHECK(pixel_close(img, tlx, tly, black_ish, 12));
        frig_image_free(want);
        frig_image *raw = NULL;
        CHECK(frig_image_load(ctx, path_of(name), FRIG_LOAD_IGNORE_ORIENTATION, &raw) == FRIG_OK);
        CHECK(raw && raw->width == 40 && raw->height == 24 && frig_image_orientation(raw) == o);
        frig_image_free(raw);
        frig_image_free(img);
    }
    /* PNG with an eXIf chunk (orientation 6). */
    {
        static const unsigned char ex[] = {'M', 'M', 0, 42, 0, 0, 0, 8, 0, 1, 0x01, 0x12, 0, 3, 0, 0, 0, 1, 0, 6, 0, 0,
                                           0, 0, 0, 0};
        png_bytep rows[24];
        for (int y = 0; y < 24; y++) rows[y] = src->pixels + (size_t)y * src->stride;
        png_spec s = {40, 24, PNG_COLOR_TYPE_RGB, 8, 0, NULL, 0, ex, (int)sizeof ex};
        write_png_file("orientation_6.png", &s, rows);
        frig_image *img = expect("orientation_6.png", FRIG_OK);
        CHECK(img && img->width == 24 && img->height == 40 && frig_image_orientation(img) == 6);
        frig_image *want = fr_image_orient(src, 6);
        CHECK(img && memcmp(img->pixels, want->pixels, (size_t)24 * 40 * 3) == 0);
        frig_image_free(want);
        frig_image_free(img);
    }
    frig_image_free(src);
}

static void test_layouts(void) {
    printf("accepted layouts:\n");
    const uint8_t orange[3] = {230, 120, 30};
    write_cmyk_jpeg("cmyk.jpg", 32, 16, orange, JCS_CMYK);
    frig_image *img = expect("cmyk.jpg", FRIG_OK);
    CHECK(img && frig_image_source_cmyk(img) && frig_image_source_channels(img) == 4);
    CHECK(img && pixel_close(img, 16, 8, orange, 6));
    frig_image_free(img);
    write_cmyk_jpeg("ycck.jpg", 32, 16, orange, JCS_YCCK);
    img = expect("ycck.jpg", FRIG_OK);
    CHECK(img && frig_image_source_cmyk(img) && pixel_close(img, 16, 8, orange, 6));
    frig_image_free(img);

    frig_image *src = pattern(64, 48);
    frig_image *g = NULL;
    CHECK(frig_image_to_gray(ctx, src, &g) == FRIG_OK);
    unsigned char *d;
    size_t n;
    save_jpeg_bytes("gray.jpg", g, 95, 0, &d, &n);
    free(d);
    img = expect("gray.jpg", FRIG_OK);
    CHECK(img && frig_image_source_channels(img) == 1 && img->channels == 3);
    CHECK(img && abs(img->pixels[3 * 10] - g->pixels[10]) <= 3 && img->pixels[30] == img->pixels[31]);
    frig_image_free(img);
    frig_image *gl = NULL;
    CHECK(frig_image_load(ctx, path_of("gray.jpg"), FRIG_LOAD_GRAY, &gl) == FRIG_OK && gl && gl->channels == 1);
    frig_image_free(gl);

    write_progressive_jpeg("progressive.jpg", src);
    img = expect("progressive.jpg", FRIG_OK);
    CHECK(img && pixel_close(img, 5, 5, src->pixels + 5 * src->stride + 15, 10));
    frig_image_free(img);

    /* 16-bit RGB PNG: 0xABCD scales to 0xAB or 0xAC (libpng rounds: 43981 * 255 / 65535 = 171.1). */
    {
        uint8_t row[2][4 * 6];
        for (int y = 0; y < 2; y++)
            for (int x = 0; x < 4; x++) {
                uint16_t v[3] = {0xABCD, 0x0000, 0xFFFF};
                for (int c = 0; c < 3; c++) {
                    row[y][x * 6 + 2 * c] = (uint8_t)(v[c] >> 8);
                    row[y][x * 6 + 2 * c + 1] = (uint8_t)v[c];
                }
            }
        png_bytep rows[2] = {row[0], row[1]};
        png_spec s = {4, 2, PNG_COLOR_TYPE_RGB, 16, 0, NULL, 0, NULL, 0};
        write_png_file("rgb16.png", &s, rows);
        img = expect("rgb16.png", FRIG_OK);
        CHECK(img && frig_image_source_bit_depth(img) == 16);
        CHECK(img && img->pixels[0] == 171 && img->pixels[1] == 0 && img->pixels[2] == 255);
        frig_image_free(img);
    }
    /* 16-bit gray with alpha. */
    {
        uint8_t row[4 * 4];
        for (int x = 0; x < 4; x++) row[4 * x] = 0x80, row[4 * x + 1] = 0x00, row[4 * x + 2] = 0x12, row[4 * x + 3] = 0;
        png_bytep rows[1] = {row};
        png_spec s = {4, 1, PNG_COLOR_TYPE_GRAY_ALPHA, 16, 0, NULL, 0, NULL, 0};
        write_png_file("gray_alpha16.png", &s, rows);
        img = expect("gray_alpha16.png", FRIG_OK);
        CHECK(img && frig_image_source_channels(img) == 2 && img->pixels[0] == 128 && img->pixels[2] == 128);
        frig_image_free(img);
    }
    /* Palette, 4-bit. */
    {
        png_color pal[3] = {{255, 0, 0}, {0, 255, 0}, {0, 0, 255}};
        uint8_t row[2] = {0x01, 0x20}; /* pixels 0,1,2,0 */
        png_bytep rows[1] = {row};
        png_spec s = {4, 1, PNG_COLOR_TYPE_PALETTE, 4, 0, pal, 3, NULL, 0};
        write_png_file("palette4.png", &s, rows);
        img = expect("palette4.png", FRIG_OK);
        const uint8_t green[3] = {0, 255, 0}, blue[3] = {0, 0, 255};
        CHECK(img && pixel_close(img, 1, 0, green, 0) && pixel_close(img, 2, 0, blue, 0));
        frig_image_free(img);
    }
    /* RGBA: alpha dropped. 1-bit gray. Interlaced. */
    {
        uint8_t row[4 * 4];
        for (int x = 0; x < 4; x++) row[4 * x] = 10, row[4 * x + 1] = 20, row[4 * x + 2] = 30, row[4 * x + 3] = 7;
        png_bytep rows[1] = {row};
        png_spec s = {4, 1, PNG_COLOR_TYPE_RGBA, 8, 0, NULL, 0, NULL, 0};
        write_png_file("rgba.png", &s, rows);
        img = expect("rgba.png", FRIG_OK);
        const uint8_t want[3] = {10, 20, 30};
        CHECK(img && pixel_close(img, 3, 0, want, 0));
        frig_image_free(img);

        uint8_t bits[1] = {0xA0}; /* 1,0,1,0 */
        png_bytep brows[1] = {bits};
        png_spec b = {4, 1, PNG_COLOR_TYPE_GRAY, 1, 0, NULL, 0, NULL, 0};
        write_png_file("gray1.png", &b, brows);
        img = expect("gray1.png", FRIG_OK);
        CHECK(img && img->pixels[0] == 255 && img->pixels[3] == 0 && frig_image_source_bit_depth(img) == 1);
        frig_image_free(img);

        png_bytep prow[48];
        for (int y = 0; y < 48; y++) prow[y] = src->pixels + (size_t)y * src->stride;
        png_spec il = {64, 48, PNG_COLOR_TYPE_RGB, 8, 1, NULL, 0, NULL, 0};
        write_png_file("interlaced.png", &il, prow);
        img = expect("interlaced.png", FRIG_OK);
        CHECK(img && memcmp(img->pixels, src->pixels, (size_t)64 * 48 * 3) == 0);
        frig_image_free(img);
    }
    frig_image_free(g);
    frig_image_free(src);
}

static int count_entries(const char *path) {
    DIR *d = opendir(path);
    int n = 0;
    if (!d) return -1;
    for (struct dirent *e; (e = readdir(d));)
        if (strcmp(e->d_name, ".") && strcmp(e->d_name, "..")) n++;
    closedir(d);
    return n;
}

static void test_saves(void) {
    const char *sub = test_temp_dir("image_saves");
    char p[4096];
    frig_image *src = pattern(50, 30);
    snprintf(p, sizeof p, "%s/out.png", sub);
    CHECK(frig_image_save_png(ctx, src, p) == FRIG_OK);
    frig_image *back = NULL;
    CHECK(frig_image_load(ctx, p, 0, &back) == FRIG_OK);
    CHECK(back && memcmp(back->pixels, src->pixels, (size_t)50 * 30 * 3) == 0);
    frig_image_free(back);
    snprintf(p, sizeof p, "%s/out.jpg", sub);
    CHECK(frig_image_save_jpeg(ctx, src, p) == FRIG_OK);
    CHECK(frig_image_load(ctx, p, 0, &back) == FRIG_OK);
    CHECK(back && pixel_close(back, 25, 15, src->pixels + 15 * src->stride + 75, 8));
    frig_image_free(back);
    CHECK(count_entries(sub) == 2); /* no temporary files left behind */

    /* A save that cannot complete (the target is a folder) fails, keeps what was there,
     * and leaves no temporary file. */
    snprintf(p, sizeof p, "%s/taken", sub);
    mkdir(p, 0755);
    CHECK(frig_image_save_png(ctx, src, p) == FRIG_ERR_IO);
    CHECK(count_entries(sub) == 3);
    snprintf(p, sizeof p, "%s/no/such/folder/x.png", sub);
    CHECK(frig_image_save_png(ctx, src, p) == FRIG_ERR_IO);
    frig_image_free(src);
}

/* Pull-push filling (image/pull_push.h): on a smooth colour ramp with a disc and a band unknown
 * the filled pixels land near the ramp (the fill is smooth and follows its neighbours), the
 * known pixels keep their colours to the bit; nothing known leaves the image as it was. */
static void test_pull_push(void) {
    enum { W = 96, H = 80 };
    float *img = malloc(sizeof(float) * 3 * W * H), *truth = malloc(sizeof(float) * 3 * W * H);
    uint8_t *known = malloc(W * H);
    CHECK(img && truth && known);
    if (!img || !truth || !known) {
        free(img), free(truth), free(known);
        return;
    }
    int unknown = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            size_t i = (size_t)y * W + x;
            truth[3 * i] = 0.2f + 0.6f * x / (W - 1), truth[3 * i + 1] = 0.1f + 0.5f * y / (H - 1);
            truth[3 * i + 2] = 0.3f + 0.2f * (x + y) / (W + H - 2);
            int hole = (x - 40) * (x - 40) + (y - 30) * (y - 30) < 15 * 15 || (y >= 60 && y < 66);
            known[i] = (uint8_t)!hole;
            unknown += hole;
            for (int c = 0; c < 3; c++) img[3 * i + c] = hole ? 9.0f : truth[3 * i + c];
        }
    CHECK(fr_pull_push(img, known, W, H) == 1);
    double worst = 0, mean = 0;
    int kept = 1;
    for (size_t i = 0; i < (size_t)W * H; i++)
        for (int c = 0; c < 3; c++) {
            if (known[i]) kept &= img[3 * i + c] == truth[3 * i + c];
            else {
                double e = fabs(img[3 * i + c] - truth[3 * i + c]);
                worst = fmax(worst, e), mean += e / (3.0 * unknown);
            }
        }
    printf("pull-push: %d unknown pixels of %d, error mean %.4f worst %.4f; known ones kept: %s\n", unknown, W * H, mean,
           worst, kept ? "yes" : "NO");
    CHECK(kept);
    CHECK(mean < 0.01 && worst < 0.05);
    memset(known, 0, W * H);
    float before = img[0];
    CHECK(fr_pull_push(img, known, W, H) == 0 && img[0] == before);
    free(img), free(truth), free(known);
}

/* The Gaussian blur (lib/image/gaussian_blur.c): an impulse becomes the sampled, normalized
 * Gaussian (its sum 1, its centre and its spread the kernel's), a constant stays constant at the
 * borders, channels do not mix. */
static void test_gaussian_blur(void) {
    enum { W = 41, H = 37 };
    float *in = calloc(2 * W * H, sizeof(float)), *out = malloc(sizeof(float) * 2 * W * H);
    if (!in || !out) {
        free(in), free(out);
        CHECK(0);
        return;
    }
    double sigma = 2.5, k0 = 0, ksum = 0, kvar = 0; /* the kernel: radius ceil(3 sigma) = 8 */
    for (int i = -8; i <= 8; i++) ksum += exp(-0.5 * i * i / (sigma * sigma)), kvar += i * i * exp(-0.5 * i * i / (sigma * sigma));
    k0 = 1 / ksum, kvar /= ksum;
    in[2 * (18 * W + 20)] = 1;                                   /* channel 0: an impulse */
    for (int i = 0; i < W * H; i++) in[2 * i + 1] = 0.25f;       /* channel 1: constant */
    CHECK(fr_gaussian_blur(ctx, in, W, H, 2, sigma, out) == FRIG_OK);
    double sum = 0, var = 0, cmax = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            double v = out[2 * (y * W + x)];
            sum += v, var += v * ((x - 20) * (x - 20) + (y - 18) * (y - 18)) / 2.0;
            cmax = fmax(cmax, fabs(out[2 * (y * W + x) + 1] - 0.25));
        }
    printf("gaussian blur: sum %.6f, centre %.6f (kernel %.6f), variance %.4f (the truncated kernel's %.4f), constant off "
           "by %.2g\n", sum, out[2 * (18 * W + 20)], k0 * k0, var, kvar, cmax);
    CHECK(fabs(sum - 1) < 1e-5);
    CHECK(fabs(out[2 * (18 * W + 20)] - k0 * k0) < 1e-6);
    CHECK(fabs(var - kvar) < 1e-4 && kvar > 0.98 * sigma * sigma);
    CHECK(cmax < 1e-6);
    /* a window is the whole image's blur there, bit for bit, and leaves the rest alone */
    float *win = malloc(sizeof(float) * 2 * W * H);
    if (win) {
        srand(5);
        for (int i = 0; i < 2 * W * H; i++)
            in[i] = (float)(rand() % 1000) / 997.0f;
        CHECK(fr_gaussian_blur(ctx, in, W, H, 2, 1.4, out) == FRIG_OK);
        static const int boxes[3][4] = {{0, 0, W, H}, {3, 30, 40, 37}, {10, 5, 22, 19}};
        int same = 1, untouched = 1;
        for (int b = 0; b < 3; b++) {
            for (int i = 0; i < 2 * W * H; i++)
                win[i] = -7.0f;
            const int *q = boxes[b];
            CHECK(fr_gaussian_blur_window(ctx, in, W, H, 2, 1.4, q[0], q[1], q[2], q[3], win) == FRIG_OK);
            for (int y = 0; y < H; y++)
                for (int x = 0; x < W; x++)
                    for (int c = 0; c < 2; c++) {
                        size_t i = 2 * ((size_t)y * W + x) + c;
                        int inside = x >= q[0] && x < q[2] && y >= q[1] && y < q[3];
                        if (inside)
                            same &= memcmp(&win[i], &out[i], sizeof(float)) == 0;
                        else
                            untouched &= win[i] == -7.0f;
                    }
        }
        printf("gaussian blur window: %s, outside %s\n", same ? "bit-identical" : "DIFFERENT",
               untouched ? "untouched" : "WRITTEN");
        CHECK(same && untouched);
    }
    free(win);
    free(in), free(out);
}

int main(void) {
    ctx = frig_ctx_create();
    test_gaussian_blur();
    test_pull_push();
    dir = test_temp_dir("image_corpus");
    test_bad_files();
    test_orientations();
    test_layouts();
    test_saves();
    frig_ctx_free(ctx);
    return test_result("test_image");
}
