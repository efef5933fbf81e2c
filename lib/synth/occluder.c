/* Intended failures of the synthetic data (the filter stage of paper section 4.2 must drop
 * them): an opaque rectangle or ellipse over the eyes or the mouth, or a hand (a palm and
 * four fingers in the subject's skin tone) over them. Coordinates are photo pixels. */
#include <math.h>

#include "synth/synth.h"

static void mean_point(const double *lm, int first, int last, double c[2]) {
    c[0] = c[1] = 0.0;
    for (int k = first; k <= last; k++) c[0] += lm[2 * k], c[1] += lm[2 * k + 1];
    c[0] /= last - first + 1, c[1] /= last - first + 1;
}

void fr_synth_place_occluder(fr_synth_photo *p, const double exact[2 * FR_SYNTH_LANDMARKS]) {
    double dx = exact[2 * 45] - exact[2 * 36], dy = exact[2 * 45 + 1] - exact[2 * 36 + 1];
    double span = sqrt(dx * dx + dy * dy), roll = atan2(dy, dx);
    /* a turned face's eye corners come close together: keep the shape face-sized */
    double ex = exact[2 * 8] - exact[2 * 27], ey = exact[2 * 8 + 1] - exact[2 * 27 + 1];
    double height = sqrt(ex * ex + ey * ey);
    if (span < 0.6 * height) span = 0.6 * height;
    const double *j = p->occ_jitter;
    if (p->occ_over == 0) mean_point(exact, 36, 47, p->occ_centre);
    else mean_point(exact, 48, 67, p->occ_centre);
    p->occ_centre[0] += 0.08 * span * j[0];
    p->occ_centre[1] += 0.08 * span * j[1];
    double grow = p->occ_shape == 2 ? 1.1 : 1.0;
    p->occ_axes[0] = grow * span * (p->occ_over == 0 ? 0.78 : 0.62) * (1.0 + 0.15 * j[2]);
    p->occ_axes[1] = grow * span * (p->occ_over == 0 ? 0.30 : 0.36) * (1.0 + 0.2 * j[3]);
    p->occ_angle = roll + 0.15 * j[0];
}

/* Distance from (x, y) to the segment a-b. */
static double seg_dist(double x, double y, double ax, double ay, double bx, double by) {
    double ux = bx - ax, uy = by - ay, L = ux * ux + uy * uy;
    double t = L > 0.0 ? ((x - ax) * ux + (y - ay) * uy) / L : 0.0;
    t = t < 0.0 ? 0.0 : t > 1.0 ? 1.0 : t;
    double ddx = x - ax - t * ux, ddy = y - ay - t * uy;
    return sqrt(ddx * ddx + ddy * ddy);
}

int fr_synth_occluded(const fr_synth_photo *p, double x, double y) {
    if (p->failure == FRIG_SYNTH_FAILURE_SUNGLASSES) return fr_synth_sunglasses_at(p, x, y, NULL, NULL) != 0;
    if (p->failure != FRIG_SYNTH_FAILURE_OCCLUDER) return 0;
    double c = cos(p->occ_angle), s = sin(p->occ_angle);
    double u = c * (x - p->occ_centre[0]) + s * (y - p->occ_centre[1]);
    double v = -s * (x - p->occ_centre[0]) + c * (y - p->occ_centre[1]);
    double a = p->occ_axes[0], b = p->occ_axes[1];
    if (p->occ_shape == 0) return fabs(u) <= a && fabs(v) <= b;
    double e = (u / a) * (u / a) + (v / b) * (v / b);
    if (p->occ_shape == 1) return e <= 1.0;
    /* hand: the palm is the ellipse's lower half-size, fingers rise from its upper edge */
    double pu = u / (0.55 * a), pv = (v - 0.35 * b) / (0.9 * b);
    if (pu * pu + pv * pv <= 1.0) return 1;
    double r = 0.11 * a;
    for (int k = 0; k < 4; k++) {
        double fx = (-0.42 + 0.28 * k) * a, len = (k == 0 || k == 3 ? 1.45 : 1.8) * b;
        if (seg_dist(u, v, fx, 0.1 * b, fx + 0.06 * a * (k - 1.5), -len) <= r) return 1;
    }
    return 0;
}

void fr_synth_draw_occluder(const fr_synth_photo *p, int w, int h, double scale, float *rgb) {
    if (p->failure != FRIG_SYNTH_FAILURE_OCCLUDER) return;
    for (int y = 0; y < h; y++) {
        double py = (y + 0.5) / scale - 0.5;
        for (int x = 0; x < w; x++) {
            double px = (x + 0.5) / scale - 0.5;
            if (!fr_synth_occluded(p, px, py)) continue;
            /* a soft top-down shading keeps it from looking like a hole */
            double shade = 0.8 + 0.2 * (1.0 - (py - p->occ_centre[1] + p->occ_axes[1]) / (2.0 * p->occ_axes[1] + 1e-9));
            shade = shade < 0.6 ? 0.6 : shade > 1.0 ? 1.0 : shade;
            for (int c = 0; c < 3; c++) rgb[3 * ((size_t)y * (size_t)w + (size_t)x) + c] = (float)(p->occ_colour[c] * shade);
        }
    }
}
