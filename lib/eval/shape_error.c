/* Shape error after similarity alignment (section 7.2, E_B): the mean distance once b is
 * mapped onto a by the best similarity transform (lib/mesh/point_align.c). */
#include <math.h>

#include "eval/shape_error.h"
#include "mesh/point_align.h"

double fr_aligned_mean_distance(const float *a, const float *b, int n) {
    if (n <= 0) return 0;
    double R[9], t[3], scale, sum = 0;
    if (!fr_point_align(a, b, n, 1, R, t, &scale)) return NAN;
    for (int v = 0; v < n; v++) {
        double e = 0;
        for (int i = 0; i < 3; i++) {
            double x = t[i];
            for (int j = 0; j < 3; j++) x += scale * R[3 * i + j] * b[3 * v + j];
            e += (x - a[3 * v + i]) * (x - a[3 * v + i]);
        }
        sum += sqrt(e);
    }
    return sum / n;
}
