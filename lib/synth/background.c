/* Backgrounds of synthetic photos: a two-colour gradient with a few soft colour blobs, and
 * sometimes clutter (rectangles and ellipses of random colours) for the face detector to
 * reject. Linear RGB, drawn at 'scale' times the photo's size; coordinates are photo pixels. */
#include <math.h>

#include "synth/synth.h"

#define BLOBS 6

typedef struct blob {
    double x, y, r, m[3];
} blob;

static double uniform(fr_rng *r, double lo, double hi) { return lo + (hi - lo) * fr_rng_uniform(r); }

static void gradient(const fr_synth_photo *p, int w, int h, double scale, const blob *b, float *rgb) {
    double c = cos(p->bg_angle), s = sin(p->bg_angle);
    double W = p->width, H = p->height, span = fabs(c) * W + fabs(s) * H, lo = fmin(0.0, c * W) + fmin(0.0, s * H);
    for (int y = 0; y < h; y++) {
        double py = (y + 0.5) / scale - 0.5;
        for (int x = 0; x < w; x++) {
            double px = (x + 0.5) / scale - 0.5, t = (c * px + s * py - lo) / span, m[3] = {1, 1, 1};
            for (int k = 0; k < BLOBS; k++) {
                double dx = px - b[k].x, dy = py - b[k].y, g = exp(-(dx * dx + dy * dy) / (2.0 * b[k].r * b[k].r));
                for (int i = 0; i < 3; i++) m[i] *= 1.0 + g * b[k].m[i];
            }
            float *o = rgb + 3 * ((size_t)y * (size_t)w + (size_t)x);
            for (int i = 0; i < 3; i++) o[i] = (float)(m[i] * ((1.0 - t) * p->bg_colour[0][i] + t * p->bg_colour[1][i]));
        }
    }
}

/* One clutter shape: axis-aligned rectangle or ellipse, flat colour. */
static void clutter_shape(fr_rng *r, const fr_synth_photo *p, int w, int h, double scale, float *rgb) {
    double side = p->width > p->height ? p->width : p->height;
    double cx = uniform(r, 0, p->width), cy = uniform(r, 0, p->height);
    double ax = side * uniform(r, 0.02, 0.2), ay = side * uniform(r, 0.02, 0.2);
    int ellipse = fr_rng_uniform(r) < 0.5;
    double col[3], grey = uniform(r, 0.1, 0.9), sat = uniform(r, 0.1, 0.7);
    for (int i = 0; i < 3; i++) col[i] = fr_srgb_to_linear(grey + sat * (uniform(r, 0.05, 0.95) - grey));
    int x0 = (int)floor((cx - ax + 0.5) * scale), x1 = (int)ceil((cx + ax + 0.5) * scale);
    int y0 = (int)floor((cy - ay + 0.5) * scale), y1 = (int)ceil((cy + ay + 0.5) * scale);
    for (int y = y0 < 0 ? 0 : y0; y < h && y <= y1; y++) {
        double v = ((y + 0.5) / scale - 0.5 - cy) / ay;
        for (int x = x0 < 0 ? 0 : x0; x < w && x <= x1; x++) {
            double u = ((x + 0.5) / scale - 0.5 - cx) / ax;
            if (ellipse ? u * u + v * v > 1.0 : fabs(u) > 1.0 || fabs(v) > 1.0) continue;
            float *o = rgb + 3 * ((size_t)y * (size_t)w + (size_t)x);
            for (int i = 0; i < 3; i++) o[i] = (float)(col[i] * (0.85 + 0.15 * v));
        }
    }
}

void fr_synth_background(const fr_synth_photo *p, int w, int h, double scale, float *rgb) {
    fr_rng r;
    fr_rng_seed(&r, p->bg_seed);
    double side = p->width > p->height ? p->width : p->height;
    blob b[BLOBS];
    for (int k = 0; k < BLOBS; k++) {
        b[k].x = uniform(&r, 0, p->width), b[k].y = uniform(&r, 0, p->height);
        b[k].r = side * uniform(&r, 0.08, 0.35);
        for (int i = 0; i < 3; i++) b[k].m[i] = uniform(&r, -0.3, 0.3);
    }
    gradient(p, w, h, scale, b, rgb);
    if (!p->bg_clutter) return;
    int n = 8 + (int)fr_rng_below(&r, 20);
    for (int k = 0; k < n; k++) clutter_shape(&r, p, w, h, scale, rgb);
}
