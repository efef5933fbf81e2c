/* 2D drawing on images for the pictures a person checks by eye (landmarks, boxes, fitted
 * meshes of paper sections 4.2-4.4): plain and antialiased lines (capsule coverage with a box
 * filter), discs, boxes and blended triangles that reuse the rasterizer's coverage rule. */
#include <math.h>

#include "image/image.h"
#include "raster/draw.h"

static uint8_t blend_channel(uint8_t in, double colour, double alpha) {
    double v = in + alpha * (colour - in);
    return (uint8_t)(v <= 0.0 ? 0 : v >= 255.0 ? 255 : floor(v + 0.5));
}

void fr_draw_blend_pixel(frig_image *img, int x, int y, const uint8_t rgb[3], double alpha) {
    if (x < 0 || y < 0 || x >= img->width || y >= img->height || !(alpha > 0.0)) return;
    if (alpha > 1.0) alpha = 1.0;
    uint8_t *p = img->pixels + (size_t)y * img->stride + (size_t)x * (size_t)img->channels;
    if (img->channels >= 3) {
        for (int c = 0; c < 3; c++) p[c] = blend_channel(p[c], rgb[c], alpha);
    } else {
        double luma = (299.0 * rgb[0] + 587.0 * rgb[1] + 114.0 * rgb[2]) / 1000.0;
        p[0] = blend_channel(p[0], floor(luma + 0.5), alpha);
    }
}

static double clamp01(double v) { return v < 0.0 ? 0.0 : v > 1.0 ? 1.0 : v; }

/* Liang-Barsky: clip the segment to [lo, hi] x [lo2, hi2]; 0 when nothing is left. */
static int clip_segment(double *x0, double *y0, double *x1, double *y1, double xmin, double ymin, double xmax,
                        double ymax) {
    double dx = *x1 - *x0, dy = *y1 - *y0, t0 = 0.0, t1 = 1.0;
    double p[4] = {-dx, dx, -dy, dy};
    double q[4] = {*x0 - xmin, xmax - *x0, *y0 - ymin, ymax - *y0};
    for (int i = 0; i < 4; i++) {
        if (p[i] == 0.0) {
            if (q[i] < 0.0) return 0;
            continue;
        }
        double r = q[i] / p[i];
        if (p[i] < 0.0) {
            if (r > t1) return 0;
            if (r > t0) t0 = r;
        } else {
            if (r < t0) return 0;
            if (r < t1) t1 = r;
        }
    }
    double ax = *x0 + t0 * dx, ay = *y0 + t0 * dy;
    *x1 = *x0 + t1 * dx, *y1 = *y0 + t1 * dy;
    *x0 = ax, *y0 = ay;
    return 1;
}

static double round_half_up(double v) { return floor(v + 0.5); }

/* One pixel per step along the major axis. */
static void thin_line(frig_image *img, double x0, double y0, double x1, double y1, const uint8_t rgb[3]) {
    double dx = x1 - x0, dy = y1 - y0;
    int major_x = fabs(dx) >= fabs(dy);
    double m0 = major_x ? x0 : y0, m1 = major_x ? x1 : y1, k0 = major_x ? y0 : x0;
    double slope = (m1 != m0) ? (major_x ? dy : dx) / (m1 - m0) : 0.0;
    int a = (int)round_half_up(fmin(m0, m1)), b = (int)round_half_up(fmax(m0, m1));
    for (int m = a; m <= b; m++) {
        int k = (int)round_half_up(k0 + ((double)m - m0) * slope);
        if (major_x)
            fr_draw_blend_pixel(img, m, k, rgb, 1.0);
        else
            fr_draw_blend_pixel(img, k, m, rgb, 1.0);
    }
}

static double segment_distance(double px, double py, double x0, double y0, double dx, double dy, double len2) {
    double s = len2 > 0.0 ? clamp01(((px - x0) * dx + (py - y0) * dy) / len2) : 0.0;
    double ex = px - (x0 + s * dx), ey = py - (y0 + s * dy);
    return sqrt(ex * ex + ey * ey);
}

/* Capsule of radius r around the segment; walks the major axis and, per step, only the band
 * of the minor axis the capsule can reach. */
static void capsule(frig_image *img, double x0, double y0, double x1, double y1, double r, const uint8_t rgb[3],
                    int antialias) {
    double dx = x1 - x0, dy = y1 - y0, len2 = dx * dx + dy * dy, reach = r + 1.0;
    int major_x = fabs(dx) >= fabs(dy);
    double m0 = major_x ? x0 : y0, dm = major_x ? dx : dy, k0 = major_x ? y0 : x0, dk = major_x ? dy : dx;
    int nm = major_x ? img->width : img->height, nk = major_x ? img->height : img->width;
    double mlo = fmax(0.0, ceil(fmin(m0, m0 + dm) - reach)), mhi = fmin(nm - 1.0, floor(fmax(m0, m0 + dm) + reach));
    for (double mm = mlo; mm <= mhi; mm += 1.0) {
        double ta = 0.0, tb = 1.0;
        if (dm != 0.0) {
            ta = clamp01((mm - reach - m0) / dm);
            tb = clamp01((mm + reach - m0) / dm);
        }
        double ka = k0 + ta * dk, kb = k0 + tb * dk;
        double klo = fmax(0.0, ceil(fmin(ka, kb) - reach)), khi = fmin(nk - 1.0, floor(fmax(ka, kb) + reach));
        for (double kk = klo; kk <= khi; kk += 1.0) {
            double px = major_x ? mm : kk, py = major_x ? kk : mm;
            double d = segment_distance(px, py, x0, y0, dx, dy, len2);
            double cover = antialias ? clamp01(r + 0.5 - d) : (d <= r ? 1.0 : 0.0);
            if (cover > 0.0) fr_draw_blend_pixel(img, (int)px, (int)py, rgb, cover);
        }
    }
}

void fr_draw_line(frig_image *img, double x0, double y0, double x1, double y1, double thickness,
                  const uint8_t rgb[3], int antialias) {
    if (!isfinite(x0) || !isfinite(y0) || !isfinite(x1) || !isfinite(y1) || !(thickness > 0.0)) return;
    double r = 0.5 * thickness, m = r + 2.0;
    if (!clip_segment(&x0, &y0, &x1, &y1, -m, -m, img->width - 1 + m, img->height - 1 + m)) return;
    if (!antialias && thickness <= 1.0)
        thin_line(img, x0, y0, x1, y1, rgb);
    else
        capsule(img, x0, y0, x1, y1, r, rgb, antialias);
}

void fr_draw_disc(frig_image *img, double cx, double cy, double radius, const uint8_t rgb[3], int antialias) {
    if (!isfinite(cx) || !isfinite(cy) || !(radius > 0.0) || !isfinite(radius)) return;
    capsule(img, cx, cy, cx, cy, radius, rgb, antialias);
}

static void order(int *a, int *b) {
    if (*a > *b) {
        int t = *a;
        *a = *b;
        *b = t;
    }
}

/* Intersect [x0, x1] x [y0, y1] with the image; 0 when empty. */
static int clip_box(const frig_image *img, int *x0, int *y0, int *x1, int *y1) {
    order(x0, x1);
    order(y0, y1);
    if (*x0 < 0) *x0 = 0;
    if (*y0 < 0) *y0 = 0;
    if (*x1 > img->width - 1) *x1 = img->width - 1;
    if (*y1 > img->height - 1) *y1 = img->height - 1;
    return *x0 <= *x1 && *y0 <= *y1;
}

void fr_draw_rect(frig_image *img, int x0, int y0, int x1, int y1, int thickness, const uint8_t rgb[3]) {
    if (thickness < 1) return;
    order(&x0, &x1);
    order(&y0, &y1);
    int bx0 = x0, by0 = y0, bx1 = x1, by1 = y1;
    if (!clip_box(img, &bx0, &by0, &bx1, &by1)) return;
    for (int y = by0; y <= by1; y++)
        for (int x = bx0; x <= bx1; x++)
            if ((long)x - x0 < thickness || (long)x1 - x < thickness || (long)y - y0 < thickness ||
                (long)y1 - y < thickness)
                fr_draw_blend_pixel(img, x, y, rgb, 1.0);
}

void fr_fill_rect(frig_image *img, int x0, int y0, int x1, int y1, const uint8_t rgb[3], double alpha) {
    if (!clip_box(img, &x0, &y0, &x1, &y1)) return;
    for (int y = y0; y <= y1; y++)
        for (int x = x0; x <= x1; x++) fr_draw_blend_pixel(img, x, y, rgb, alpha);
}

void fr_fill_triangle(frig_image *img, const double p0[2], const double p1[2], const double p2[2],
                      const uint8_t rgb[3], double alpha) {
    /* pixel coordinates are a weak-perspective camera of scale 1 at the origin */
    fr_camera cam = {0.0, 0.0, 0.0, 1, 1.0};
    float a[3] = {(float)p0[0], (float)p0[1], 0.0f}, b[3] = {(float)p1[0], (float)p1[1], 0.0f},
          c[3] = {(float)p2[0], (float)p2[1], 0.0f};
    fr_raster_tri t;
    if (!fr_raster_tri_setup(&cam, a, b, c, NULL, img->width, img->height, &t)) return;
    for (int y = t.y0; y <= t.y1; y++)
        for (int x = t.x0; x <= t.x1; x++)
            if (fr_raster_tri_sample(&t, x, y, NULL, NULL)) fr_draw_blend_pixel(img, x, y, rgb, alpha);
}
