/* Point-cloud error against a true surface (section 7.2, E_P): iterative closest points with a
 * similarity per round (Besl and McKay 1992; Umeyama 1991), the nearest points from the mesh's
 * triangle tree, the transform from the point-set alignment the shape errors use. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "core/sort.h"
#include "eval/cloud_error.h"
#include "mesh/point_align.h"

#define FINAL_REACH 0.05 /* metres: farther points count as lost */

static void apply(double s, const double R[9], const double t[3], const double *p, double *out) {
    for (int i = 0; i < 3; i++) out[i] = t[i] + s * (R[3 * i] * p[0] + R[3 * i + 1] * p[1] + R[3 * i + 2] * p[2]);
}

frig_status fr_cloud_align(frig_ctx *ctx, const fr_tri_tree *tree, const double *pts, int n, int iterations,
                           double reject, double *dist, double *scale, double R[9], double t[3]) {
    float *near = malloc(sizeof(float) * 3 * (size_t)(n + 1)), *from = malloc(sizeof(float) * 3 * (size_t)(n + 1));
    int *hint = malloc(sizeof(int) * (size_t)(n + 1));
    if (!near || !from || !hint) {
        free(near), free(from), free(hint);
        return fr_nomem(ctx, "the cloud alignment");
    }
    for (int i = 0; i < n; i++) hint[i] = -1;
    double s = 1, Rt[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}, tt[3] = {0, 0, 0};
    for (int it = 0; it <= iterations; it++) {
        int m = 0;
        double reach = it == iterations ? FINAL_REACH : it < 2 ? 10 * reject : reject;
        for (int i = 0; i < n; i++) {
            double cur[3];
            apply(s, Rt, tt, pts + 3 * (size_t)i, cur);
            fr_tri_hit hit;
            dist[i] = INFINITY;
            if (!fr_tri_tree_nearest_hint(tree, cur, reach, hint[i], &hit)) continue;
            hint[i] = hit.tri;
            dist[i] = sqrt(hit.dist2);
            for (int k = 0; k < 3; k++) near[3 * m + k] = (float)hit.point[k], from[3 * m + k] = (float)pts[3 * (size_t)i + k];
            m++;
        }
        if (it == iterations) break;
        double s2, R2[9], t2[3];
        if (!fr_point_align(near, from, m, 1, R2, t2, &s2)) break;
        s = s2, memcpy(Rt, R2, sizeof Rt), memcpy(tt, t2, sizeof tt);
    }
    *scale = s, memcpy(R, Rt, sizeof Rt), memcpy(t, tt, sizeof tt);
    free(near), free(from), free(hint);
    return FRIG_OK;
}

void fr_error_stats(const double *v, int n, double *mean, double *median, double *p90) {
    *mean = *median = *p90 = NAN;
    if (n <= 0) return;
    double *c = malloc(sizeof(double) * (size_t)n);
    if (!c) return;
    double sum = 0;
    for (int i = 0; i < n; i++) sum += c[i] = v[i];
    qsort(c, (size_t)n, sizeof *c, fr_cmp_double);
    *mean = sum / n;
    *median = c[n / 2];
    *p90 = c[(int)(0.9 * (n - 1))];
    free(c);
}
