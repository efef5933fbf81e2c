/* An eyeball's centre and gaze axis from its vertices: the centroid, and the direction from it
 * through the mean of the most forward 5% (the cornea's bulge). */
#include <math.h>

#include "mesh/eye_frame.h"

int fr_eye_frame(const fr_topology *t, const float *xyz, const char *eyeball_region, double c[3], double a[3]) {
    int first, count;
    c[0] = c[1] = c[2] = 0.0;
    a[0] = a[1] = 0.0, a[2] = 1.0;
    if (!fr_topology_region(t, eyeball_region, &first, &count) || first < 0 || first + count > t->vertex_count)
        return 0;
    for (int i = first; i < first + count; i++)
        for (int d = 0; d < 3; d++) c[d] += xyz[3 * (size_t)i + d];
    for (int d = 0; d < 3; d++) c[d] /= count;
    double zmax = -INFINITY, zmin = INFINITY;
    for (int v = first; v < first + count; v++) {
        zmax = fmax(zmax, xyz[3 * (size_t)v + 2]);
        zmin = fmin(zmin, xyz[3 * (size_t)v + 2]);
    }
    double cut = zmax - 0.05 * (zmax - zmin), f[3] = {0, 0, 0};
    int n = 0;
    for (int v = first; v < first + count; v++)
        if (xyz[3 * (size_t)v + 2] >= cut) {
            for (int d = 0; d < 3; d++) f[d] += xyz[3 * (size_t)v + d];
            n++;
        }
    double len = 0.0;
    for (int d = 0; d < 3; d++) a[d] = f[d] / n - c[d], len += a[d] * a[d];
    for (int d = 0; d < 3; d++) a[d] /= sqrt(len);
    return 1;
}
