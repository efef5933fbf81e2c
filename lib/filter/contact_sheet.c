/* The filter stage's contact sheet: each face's shape-free texture in an S x S cell with a 3-pixel
 * frame (red when dropped, gray when kept) and, for dropped faces, the round number in a 3 x 5
 * pixel digit font scaled by 2. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "core/context.h"
#include "raster/draw.h"
#include "filter/contact_sheet.h"
#include "image/image.h"

#define FRAME 3
#define GAP 2
#define DIGIT_SCALE 2

/* 3 x 5 digits, one row of 3 bits per entry, top row first, most significant bit = left column. */
static const unsigned char digits[10][5] = {
    {7, 5, 5, 5, 7}, {2, 6, 2, 2, 7}, {7, 1, 7, 4, 7}, {7, 1, 7, 1, 7}, {5, 5, 7, 1, 1},
    {7, 4, 7, 1, 7}, {7, 4, 7, 5, 7}, {7, 1, 1, 1, 1}, {7, 5, 7, 5, 7}, {7, 5, 7, 1, 7},
};

static void put(frig_image *img, int x, int y, const uint8_t rgb[3]) {
    if (x < 0 || y < 0 || x >= img->width || y >= img->height) return;
    memcpy(img->pixels + (size_t)y * img->stride + 3 * (size_t)x, rgb, 3);
}

static void fill(frig_image *img, int x0, int y0, int w, int h, const uint8_t rgb[3]) {
    for (int y = y0; y < y0 + h; y++)
        for (int x = x0; x < x0 + w; x++) put(img, x, y, rgb);
}

/* Draw a non-negative number at (x, y) in white on a red box. */
static void draw_number(frig_image *img, int x, int y, int value) {
    char text[16];
    int len = snprintf(text, sizeof text, "%d", value);
    static const uint8_t red[3] = {220, 0, 0}, white[3] = {255, 255, 255};
    int step = 4 * DIGIT_SCALE;
    fill(img, x, y, len * step + DIGIT_SCALE, 7 * DIGIT_SCALE, red);
    for (int c = 0; c < len; c++) {
        const unsigned char *g = digits[text[c] - '0'];
        for (int row = 0; row < 5; row++)
            for (int col = 0; col < 3; col++)
                if (g[row] >> (2 - col) & 1)
                    fill(img, x + DIGIT_SCALE + c * step + col * DIGIT_SCALE, y + DIGIT_SCALE + row * DIGIT_SCALE,
                         DIGIT_SCALE, DIGIT_SCALE, white);
    }
}

/* The identity distance at the bottom-left of a cell, on a dark strip. */
static void draw_distance(frig_image *img, int x, int y, double d, double threshold) {
    static const uint8_t yellow[3] = {255, 220, 60}, red[3] = {255, 90, 90}, dark[3] = {0, 0, 0};
    char text[16];
    snprintf(text, sizeof text, "%.2f", d);
    int w, h;
    fr_text_size(text, 1, &w, &h);
    fill(img, x, y - h - 2, w + 2, h + 2, dark);
    fr_draw_text(img, x + 1, y - h - 1, text, 1, d > threshold ? red : yellow);
}

frig_status fr_contact_sheet(frig_ctx *ctx, const fr_face_warp *warp, int count, const double *textures,
                             const int *round_dropped, const double *distances, double threshold, int columns,
                             frig_image **out) {
    *out = NULL;
    if (!warp || count < 1 || columns < 1 || !textures || !round_dropped)
        return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "contact sheet of %d faces in %d columns", count, columns);
    int S = fr_face_warp_size(warp), P = fr_face_warp_texels(warp), cell = S + 2 * FRAME + GAP;
    int cols = count < columns ? count : columns, rows = (count + columns - 1) / columns;
    frig_status st = frig_image_create(ctx, cols * cell + GAP, rows * cell + GAP, 3, out);
    if (st != FRIG_OK) return st;
    frig_image *img = *out;
    memset(img->pixels, 255, img->stride * (size_t)img->height);
    const int *index = fr_face_warp_texel_index(warp);
    static const uint8_t red[3] = {220, 0, 0}, gray[3] = {170, 170, 170}, back[3] = {40, 40, 40};
    for (int i = 0; i < count; i++) {
        int x0 = GAP + (i % columns) * cell, y0 = GAP + (i / columns) * cell;
        fill(img, x0, y0, S + 2 * FRAME, S + 2 * FRAME, round_dropped[i] > 0 ? red : gray);
        fill(img, x0 + FRAME, y0 + FRAME, S, S, back);
        const double *t = textures + (size_t)i * P;
        for (int k = 0; k < P; k++) {
            double v = 128 + 40 * t[k];
            uint8_t g = (uint8_t)(v < 0 ? 0 : v > 255 ? 255 : lround(v));
            uint8_t rgb[3] = {g, g, g};
            put(img, x0 + FRAME + index[k] % S, y0 + FRAME + index[k] / S, rgb);
        }
        if (round_dropped[i] > 0) draw_number(img, x0 + FRAME, y0 + FRAME, round_dropped[i]);
        if (distances && !isnan(distances[i])) draw_distance(img, x0 + FRAME, y0 + FRAME + S, distances[i], threshold);
    }
    return FRIG_OK;
}
