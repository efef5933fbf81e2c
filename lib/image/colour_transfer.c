/* Reinhard colour transfer (Reinhard et al. 2001; the paper's reference [65]): linear RGB to
 * LMS cone space, logarithm, the decorrelated l-alpha-beta axes; each axis of the source shifted
 * (and scaled) to the target's mean (and standard deviation); back by the inverse transforms. */
#include <math.h>

#include "image/colour_transfer.h"

static const double RGB2LMS[9] = {0.3811, 0.5783, 0.0402, 0.1967, 0.7244, 0.0782, 0.0241, 0.1288, 0.8444};
static const double LMS2RGB[9] = {4.4679, -3.5873, 0.1193, -1.2186, 2.3809, -0.1624, 0.0497, -0.2439, 1.2045};

static int to_lab(const float *rgb, double lab[3]) {
    double lms[3];
    for (int i = 0; i < 3; i++) {
        lms[i] = RGB2LMS[3 * i] * rgb[0] + RGB2LMS[3 * i + 1] * rgb[1] + RGB2LMS[3 * i + 2] * rgb[2];
        if (!(lms[i] > 1e-6)) return 0;
        lms[i] = log10(lms[i]);
    }
    lab[0] = (lms[0] + lms[1] + lms[2]) / sqrt(3.0);
    lab[1] = (lms[0] + lms[1] - 2 * lms[2]) / sqrt(6.0);
    lab[2] = (lms[0] - lms[1]) / sqrt(2.0);
    return 1;
}

static void from_lab(const double lab[3], float *rgb) {
    double a = lab[0] / sqrt(3.0), b = lab[1] / sqrt(6.0), c = lab[2] / sqrt(2.0), lms[3];
    lms[0] = pow(10.0, a + b + c);
    lms[1] = pow(10.0, a + b - c);
    lms[2] = pow(10.0, a - 2 * b);
    for (int i = 0; i < 3; i++)
        rgb[i] = (float)(LMS2RGB[3 * i] * lms[0] + LMS2RGB[3 * i + 1] * lms[1] + LMS2RGB[3 * i + 2] * lms[2]);
}

static int stats(const float *px, const uint8_t *mask, size_t n, double mean[3], double sd[3]) {
    double s[3] = {0, 0, 0}, s2[3] = {0, 0, 0}, lab[3];
    size_t m = 0;
    for (size_t i = 0; i < n; i++) {
        if ((mask && !mask[i]) || !to_lab(px + 3 * i, lab)) continue;
        for (int k = 0; k < 3; k++) s[k] += lab[k], s2[k] += lab[k] * lab[k];
        m++;
    }
    if (m < 2) return 0;
    for (int k = 0; k < 3; k++) {
        mean[k] = s[k] / m;
        sd[k] = sqrt(fmax(0.0, s2[k] / m - mean[k] * mean[k]));
    }
    return 1;
}

size_t fr_colour_transfer(float *src, const uint8_t *src_mask, const float *target, const uint8_t *target_mask,
                          size_t n, int match_spread) {
    double ms[3], ss[3], mt[3], st[3];
    if (!stats(src, src_mask, n, ms, ss) || !stats(target, target_mask, n, mt, st)) return 0;
    size_t changed = 0;
    double lab[3];
    for (size_t i = 0; i < n; i++) {
        if ((src_mask && !src_mask[i]) || !to_lab(src + 3 * i, lab)) continue;
        for (int k = 0; k < 3; k++) {
            double g = match_spread && ss[k] > 1e-9 ? st[k] / ss[k] : 1.0;
            lab[k] = mt[k] + g * (lab[k] - ms[k]);
        }
        from_lab(lab, src + 3 * i);
        changed++;
    }
    return changed;
}
