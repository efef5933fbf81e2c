/* Smooth random vector fields on the head as sums of Gaussian radial basis bumps: the
 * personal offsets and per-subject expression changes of the synthetic ground truth (paper
 * section 7.2 needs truth outside the model's span). */
#include <math.h>

#include "synth/synth.h"

/* Bumps are cut off where they fall below exp(-8) of their peak. */
#define CUTOFF_SIGMAS 4.0

void fr_bumps_eval(const fr_bump *b, int n, const double x[3], double out[3]) {
    out[0] = out[1] = out[2] = 0.0;
    for (int k = 0; k < n; k++) {
        double dx = x[0] - b[k].c[0], dy = x[1] - b[k].c[1], dz = x[2] - b[k].c[2];
        double q = (dx * dx + dy * dy + dz * dz) / (b[k].r * b[k].r);
        if (q > CUTOFF_SIGMAS * CUTOFF_SIGMAS) continue;
        double g = exp(-0.5 * q);
        for (int d = 0; d < 3; d++) out[d] += g * b[k].v[d];
    }
}

double fr_smoothstep(double e0, double e1, double x) {
    double t = (x - e0) / (e1 - e0);
    t = t < 0.0 ? 0.0 : t > 1.0 ? 1.0 : t;
    return t * t * (3.0 - 2.0 * t);
}
