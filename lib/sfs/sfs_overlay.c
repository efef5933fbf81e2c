/* One picture per photo for people who would rather look than read (paper Figure 5.4): the face
 * crop with the skin mask (non-skin face pixels tinted red), the synthesized image a S(n) of the
 * recovered albedo, lighting and normals, the SfS error (jet, E_max at the top of the scale),
 * and the kept region (green) with the photo's figures. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "image/image.h"
#include "image/srgb.h"
#include "raster/draw.h"
#include "sfs/sfs.h"

static void jet(double t, uint8_t rgb[3]) {
    t = t < 0 ? 0 : t > 1 ? 1 : t;
    double r = fmin(fmax(1.5 - fabs(4 * t - 3), 0), 1), g = fmin(fmax(1.5 - fabs(4 * t - 2), 0), 1),
           b = fmin(fmax(1.5 - fabs(4 * t - 1), 0), 1);
    rgb[0] = (uint8_t)(255 * r), rgb[1] = (uint8_t)(255 * g), rgb[2] = (uint8_t)(255 * b);
}

static void blend(uint8_t *p, const uint8_t c[3], double a) {
    for (int k = 0; k < 3; k++) p[k] = (uint8_t)floor(p[k] + a * (c[k] - p[k]) + 0.5);
}

frig_status fr_sfs_write_overlay(frig_ctx *ctx, const fr_sfs_view *v, const fr_sfs_settings *st, const char *label,
                                 const char *path) {
    /* panels at least 240 pixels tall, whole-pixel zoom */
    int zoom = v->h < 240 ? (240 + v->h - 1) / v->h : 1;
    int pw = v->w * zoom, ph = v->h * zoom, bar = 14 * (zoom > 2 ? 2 : 1);
    frig_image *img = fr_image_new(4 * pw, ph + bar, 3);
    if (!img) return fr_nomem(ctx, "an sfs overlay");
    static const uint8_t red[3] = {230, 40, 40}, green[3] = {40, 220, 60}, white[3] = {255, 255, 255},
                         yellow[3] = {230, 210, 40};
    for (int y = 0; y < v->h; y++)
        for (int x = 0; x < v->w; x++) {
            size_t i = (size_t)y * v->w + x;
            uint8_t panel[4][3];
            memcpy(panel[0], v->rgb + 3 * i, 3);
            if (v->face[i] && !v->skin[i]) blend(panel[0], red, 0.55);
            double S[3];
            int has = v->normal[3 * i] != 0 || v->normal[3 * i + 1] != 0 || v->normal[3 * i + 2] != 0;
            fr_sfs_shading(v->sh, has ? v->normal + 3 * i : v->n_ref + 3 * i, S);
            for (int c = 0; c < 3; c++)
                panel[1][c] = v->face[i] ? (uint8_t)floor(255 * fr_linear_to_srgb(v->albedo[3 * i + c] * S[c]) + 0.5) : 0;
            if (v->skin[i] && v->err[i] >= 0) jet(v->err[i] / (st->e_max > 0 ? st->e_max : 1), panel[2]);
            else memset(panel[2], 0, 3);
            memcpy(panel[3], v->rgb + 3 * i, 3);
            if (v->kept[i]) blend(panel[3], v->kept[i] == 2 ? yellow : green, 0.5); /* the cloud, its margin */
            for (int q = 0; q < 4; q++)
                for (int dy = 0; dy < zoom; dy++)
                    for (int dx = 0; dx < zoom; dx++)
                        memcpy(img->pixels + (size_t)(y * zoom + dy) * img->stride + 3 * ((size_t)q * pw + x * zoom + dx),
                               panel[q], 3);
        }
    int scale = bar > 14 ? 2 : 1;
    fr_draw_text(img, 3, ph + 3, label, scale, white);
    frig_status s = frig_image_save_jpeg(ctx, img, path);
    frig_image_free(img);
    return s;
}
