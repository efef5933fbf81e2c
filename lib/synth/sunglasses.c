/* Dark glasses over both eyes, an intended failure of the synthetic data (shape from shading,
 * paper section 5.1.2, must find too little skin around the eyes, and its region selection must
 * not trust the lenses): two rounded lenses sized from each eye's projected corners (so a
 * turned face's far lens is narrower), a rim, a bridge and the temples toward the ears, drawn
 * in 2D over the photo like the occluder. Coordinates are photo pixels. */
#include <math.h>

#include "synth/synth.h"

static void eye_centre(const double *lm, int first, double c[2]) {
    c[0] = c[1] = 0.0;
    for (int k = first; k < first + 6; k++) c[0] += lm[2 * k] / 6.0, c[1] += lm[2 * k + 1] / 6.0;
}

void fr_synth_place_sunglasses(fr_synth_photo *p, const double exact[2 * FR_SYNTH_LANDMARKS]) {
    double c[2][2];
    eye_centre(exact, 36, c[0]);
    eye_centre(exact, 42, c[1]);
    p->sg_angle = atan2(c[1][1] - c[0][1], c[1][0] - c[0][0]);
    /* the nose bridge's length sets the lens height whatever the yaw */
    double bridge = hypot(exact[2 * 30] - exact[2 * 27], exact[2 * 30 + 1] - exact[2 * 27 + 1]);
    const double *j = p->sg_jitter;
    double height = bridge * (0.62 + 0.08 * j[0]);
    double cs = cos(p->sg_angle), sn = sin(p->sg_angle);
    for (int e = 0; e < 2; e++) {
        int a = e ? 42 : 36, b = e ? 45 : 39;
        double width = hypot(exact[2 * b] - exact[2 * a], exact[2 * b + 1] - exact[2 * a + 1]);
        p->sg_axes[e][0] = fmax(0.95 * width, 0.25 * height) * (1.0 + 0.08 * j[1]);
        p->sg_axes[e][1] = height;
        double down = height * (0.12 + 0.1 * j[2]); /* lenses sit a little below the eyes' centres */
        p->sg_centre[e][0] = c[e][0] - sn * down;
        p->sg_centre[e][1] = c[e][1] + cs * down;
    }
    p->sg_rim = 0.09 * height;
}

/* Rotate (x, y) into the glasses' frame about lens e's centre. */
static void local(const fr_synth_photo *p, int e, double x, double y, double *u, double *v) {
    double c = cos(p->sg_angle), s = sin(p->sg_angle), dx = x - p->sg_centre[e][0], dy = y - p->sg_centre[e][1];
    *u = c * dx + s * dy;
    *v = -s * dx + c * dy;
}

/* Superellipse |u/a|^3 + |v/b|^3 of a lens (1 on its edge). */
static double lens_level(const fr_synth_photo *p, int e, double u, double v) {
    double a = p->sg_axes[e][0], b = p->sg_axes[e][1];
    double su = fabs(u / a), sv = fabs(v / b);
    return su * su * su + sv * sv * sv;
}

static double seg_dist(double x, double y, double ax, double ay, double bx, double by) {
    double ux = bx - ax, uy = by - ay, L = ux * ux + uy * uy;
    double t = L > 0.0 ? ((x - ax) * ux + (y - ay) * uy) / L : 0.0;
    t = t < 0.0 ? 0.0 : t > 1.0 ? 1.0 : t;
    return hypot(x - ax - t * ux, y - ay - t * uy);
}

int fr_synth_sunglasses_at(const fr_synth_photo *p, double x, double y, double *lens_u, double *lens_v) {
    if (p->failure != FRIG_SYNTH_FAILURE_SUNGLASSES) return 0;
    int part = 0;
    for (int e = 0; e < 2; e++) {
        double u, v;
        local(p, e, x, y, &u, &v);
        double rim = p->sg_rim / p->sg_axes[e][1];
        double level = lens_level(p, e, u, v);
        if (level <= 1.0) {
            if (lens_u) *lens_u = u / p->sg_axes[e][0];
            if (lens_v) *lens_v = v / p->sg_axes[e][1];
            return 1;
        }
        if (level <= pow(1.0 + rim, 3.0)) part = 2;
        /* the temple: from the lens's outer edge, away from the other lens */
        double out = e ? 1.0 : -1.0, a = p->sg_axes[e][0];
        if (seg_dist(u, v, out * a, -0.45 * p->sg_axes[e][1], out * 2.3 * a, -0.35 * p->sg_axes[e][1]) <= 0.6 * p->sg_rim)
            part = 2;
    }
    /* the bridge between the two lenses' inner upper edges */
    double u0, v0, u1, v1;
    local(p, 0, x, y, &u0, &v0);
    local(p, 1, x, y, &u1, &v1);
    double cs = cos(p->sg_angle), sn = sin(p->sg_angle);
    double ax = p->sg_centre[0][0] + cs * 0.9 * p->sg_axes[0][0] + sn * 0.5 * p->sg_axes[0][1];
    double ay = p->sg_centre[0][1] + sn * 0.9 * p->sg_axes[0][0] - cs * 0.5 * p->sg_axes[0][1];
    double bx = p->sg_centre[1][0] - cs * 0.9 * p->sg_axes[1][0] + sn * 0.5 * p->sg_axes[1][1];
    double by = p->sg_centre[1][1] - sn * 0.9 * p->sg_axes[1][0] - cs * 0.5 * p->sg_axes[1][1];
    if (seg_dist(x, y, ax, ay, bx, by) <= 0.7 * p->sg_rim) part = 2;
    return part;
}

void fr_synth_draw_sunglasses(const fr_synth_photo *p, int w, int h, double scale, float *rgb) {
    if (p->failure != FRIG_SYNTH_FAILURE_SUNGLASSES) return;
    for (int y = 0; y < h; y++) {
        double py = (y + 0.5) / scale - 0.5;
        for (int x = 0; x < w; x++) {
            double px = (x + 0.5) / scale - 0.5, lu = 0.0, lv = 0.0;
            int part = fr_synth_sunglasses_at(p, px, py, &lu, &lv);
            if (!part) continue;
            float *o = rgb + 3 * ((size_t)y * (size_t)w + (size_t)x);
            if (part == 2) {
                for (int c = 0; c < 3; c++) o[c] = (float)p->sg_frame[c];
                continue;
            }
            /* darker at the top, the sky reflected in a soft diagonal band */
            double grad = 0.75 + 0.25 * (lv + 1.0) * 0.5;
            double band = exp(-pow((lu + lv + 0.3) / 0.35, 2.0)) * p->sg_glare;
            for (int c = 0; c < 3; c++) o[c] = (float)(p->sg_lens[c] * grad + band);
        }
    }
}
