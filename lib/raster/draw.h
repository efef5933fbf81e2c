/* 2D drawing on frig_image for the pictures a person checks by eye: detected landmarks and
 * boxes, fitted-mesh overlays on photos (paper sections 4.3-4.4, Figures 4.x), labels such as
 * "kept" or "r2 e=3.1". Coordinates are pixels with (0, 0) the centre of the top-left pixel;
 * every call clips to the image (nothing is written outside it). Colours are RGB; on a gray
 * image their BT.601 luma is drawn. alpha in [0, 1] blends: out = in + alpha (colour - in). */
#ifndef FR_RASTER_DRAW_H
#define FR_RASTER_DRAW_H

#include <stdint.h>

#include "frig/image.h"
#include "raster/raster.h"

/* Blend one pixel (no-op outside the image). */
void fr_draw_blend_pixel(frig_image *img, int x, int y, const uint8_t rgb[3], double alpha);

/* A segment of the given thickness (pixels). Plain (antialias 0): thickness <= 1 draws one
 * pixel per step along the major axis (the pixel nearest the line), thicker lines every pixel
 * centre within thickness / 2 of the segment. Antialiased: each pixel blended by the covered
 * fraction of a capsule of radius thickness / 2 (a 1-pixel box filter). */
void fr_draw_line(frig_image *img, double x0, double y0, double x1, double y1, double thickness,
                  const uint8_t rgb[3], int antialias);

/* A filled disc (landmarks, points): plain = pixel centres within radius; antialiased =
 * blended by coverage. */
void fr_draw_disc(frig_image *img, double cx, double cy, double radius, const uint8_t rgb[3], int antialias);

/* Box outline: the pixels x0..x1, y0..y1 (inclusive) minus the interior shrunk by
 * 'thickness' pixels (the outline grows inward). */
void fr_draw_rect(frig_image *img, int x0, int y0, int x1, int y1, int thickness, const uint8_t rgb[3]);
/* Filled box, blended. */
void fr_fill_rect(frig_image *img, int x0, int y0, int x1, int y1, const uint8_t rgb[3], double alpha);

/* Filled triangle, blended; the pixels are those the rasterizer gives (top-left rule), so
 * triangles sharing an edge blend each pixel once. */
void fr_fill_triangle(frig_image *img, const double p0[2], const double p1[2], const double p2[2],
                      const uint8_t rgb[3], double alpha);

/* ---- text: a built-in 5x7 bitmap font (printable ASCII) ---- */
/* Draw 'text' with its top-left corner at (x, y), each font pixel a scale x scale block;
 * glyphs advance 6 * scale, '\n' starts a new line 9 * scale lower; other characters
 * outside ' '..'~' draw as '?'. Returns the number of pixels set (inside the image). */
long fr_draw_text(frig_image *img, int x, int y, const char *text, int scale, const uint8_t rgb[3]);
/* Size in pixels of the box fr_draw_text would fill. */
void fr_text_size(const char *text, int scale, int *width, int *height);
/* 1 when font pixel (col 0..4, row 0..6) of character ch is set. */
int fr_font_pixel(char ch, int col, int row);

/* ---- mesh overlay ---- */
/* Blend a Lambert-shaded mesh over the photo wherever the raster is covered: shade =
 * 0.25 + 0.75 max(0, n . l) with n the interpolated unit normal (camera frame, 3 floats per
 * vertex, outward) and l a light from the camera, slightly above: (0, -0.3, -1) normalized;
 * pixel = in + alpha (shade * rgb - in). The raster must have the image's size. */
frig_status fr_overlay_mesh(frig_ctx *ctx, frig_image *img, const fr_raster *r, const int32_t *tris,
                            const float *normals, const uint8_t rgb[3], double alpha);

#endif
