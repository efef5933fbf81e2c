/* A photo's landmarks on its point cloud: the 2D detections become 3D points where the cloud
 * (the surface the photo shows) lies under them, in the head frame. The jaw points (0-16)
 * follow the outline, not vertices, and are left out. Used by the identity fit
 * (identity_fit.c) to tie the model's features to where the photos show them. */
#include <math.h>
#include <string.h>

#include "retarget/retarget.h"

#define FIRST_INNER 17
#define ONE_SURFACE 0.005 /* metres of depth spread beyond which the points straddle an edge */

void fr_rt_lift_landmarks(fr_rt_photo *p, const double R[9], const double t[3], double f, double cx, double cy,
                          const double *landmarks, double radius) {
    double sum[68][3], zmin[68], zmax[68];
    int count[68];
    memset(sum, 0, sizeof sum);
    memset(count, 0, sizeof count);
    for (int k = 0; k < 68; k++) zmin[k] = INFINITY, zmax[k] = -INFINITY, p->lm_ok[k] = 0;
    double r2 = radius * radius;
    for (size_t i = 0; i < p->n_points; i++) {
        const float *x = p->xyz + 3 * i;
        double xc[3];
        for (int r = 0; r < 3; r++) xc[r] = R[3 * r] * x[0] + R[3 * r + 1] * x[1] + R[3 * r + 2] * x[2] + t[r];
        if (!(xc[2] > 0)) continue;
        double u = f * xc[0] / xc[2] + cx, v = f * xc[1] / xc[2] + cy;
        for (int k = FIRST_INNER; k < 68; k++) {
            double du = u - landmarks[2 * k], dv = v - landmarks[2 * k + 1];
            if (du * du + dv * dv > r2) continue;
            for (int c = 0; c < 3; c++) sum[k][c] += x[c];
            count[k]++;
            zmin[k] = fmin(zmin[k], xc[2]);
            zmax[k] = fmax(zmax[k], xc[2]);
        }
    }
    for (int k = FIRST_INNER; k < 68; k++) {
        if (count[k] == 0 || zmax[k] - zmin[k] > ONE_SURFACE) continue;
        for (int c = 0; c < 3; c++) p->lm3d[3 * k + c] = sum[k][c] / count[k];
        p->lm_ok[k] = 1;
    }
}
