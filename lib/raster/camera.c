/* Perspective and weak-perspective projection (paper eq. 4.4, the projection pi(c) of the
 * landmark reprojection term 4.5) and the pose transform X_c = R X + t, with the projection's
 * Jacobian for Gauss-Newton. Conventions: docs/camera.md. */
#include <math.h>
#include <stddef.h>

#include "raster/camera.h"

fr_camera fr_camera_perspective(double f, int width, int height) {
    fr_camera c = {f, 0.5 * (width - 1), 0.5 * (height - 1), 0, 0.0};
    return c;
}

fr_camera fr_camera_weak(double scale, int width, int height) {
    fr_camera c = {0.0, 0.5 * (width - 1), 0.5 * (height - 1), 1, scale};
    return c;
}

int fr_camera_project(const fr_camera *cam, const double xc[3], double uv[2]) {
    if (cam->weak) {
        uv[0] = cam->scale * xc[0] + cam->cx;
        uv[1] = cam->scale * xc[1] + cam->cy;
        return 1;
    }
    if (!(xc[2] > 0.0)) return 0;
    uv[0] = cam->f * xc[0] / xc[2] + cam->cx;
    uv[1] = cam->f * xc[1] / xc[2] + cam->cy;
    return 1;
}

void fr_camera_project_jacobian(const fr_camera *cam, const double xc[3], double J[6]) {
    if (cam->weak) {
        J[0] = cam->scale, J[1] = 0.0, J[2] = 0.0;
        J[3] = 0.0, J[4] = cam->scale, J[5] = 0.0;
        return;
    }
    double iz = 1.0 / xc[2];
    J[0] = cam->f * iz, J[1] = 0.0, J[2] = -cam->f * xc[0] * iz * iz;
    J[3] = 0.0, J[4] = cam->f * iz, J[5] = -cam->f * xc[1] * iz * iz;
}

static void transform_one(const double R[9], const double t[3], const float *x, double xc[3]) {
    for (int r = 0; r < 3; r++) xc[r] = R[3 * r] * x[0] + R[3 * r + 1] * x[1] + R[3 * r + 2] * x[2] + t[r];
}

void fr_transform_points(const double R[9], const double t[3], const float *x, int n, float *xc) {
    for (int i = 0; i < n; i++) {
        double p[3];
        transform_one(R, t, x + 3 * (size_t)i, p);
        for (int r = 0; r < 3; r++) xc[3 * (size_t)i + r] = (float)p[r];
    }
}

void fr_project_points(const fr_camera *cam, const double R[9], const double t[3], const float *x, int n,
                       double *uv, double *depth) {
    for (int i = 0; i < n; i++) {
        double p[3];
        transform_one(R, t, x + 3 * (size_t)i, p);
        if (!fr_camera_project(cam, p, uv + 2 * (size_t)i)) uv[2 * (size_t)i] = uv[2 * (size_t)i + 1] = NAN;
        if (depth) depth[i] = p[2];
    }
}
