/* Camera and rotations (docs/camera.md): Rodrigues against the matrix exponential series,
 * axis-angle and Euler round trips (near 0, near 180 degrees, at gimbal lock), the derivative
 * of R(omega) v against central differences, the meaning of yaw/pitch/roll signs, rotation
 * distances, and projection with its Jacobian. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>

#include "raster/camera.h"
#include "testing.h"

/* xorshift64*: an explicit seeded generator */
static uint64_t rng = 0x9e3779b97f4a7c15ull;
static double uniform(double lo, double hi) {
    rng ^= rng >> 12, rng ^= rng << 25, rng ^= rng >> 27;
    return lo + (hi - lo) * (double)((rng * 2685821657736338717ull) >> 11) / 9007199254740992.0;
}

static double max_abs_diff(const double *a, const double *b, int n) {
    double m = 0.0;
    for (int i = 0; i < n; i++) m = fmax(m, fabs(a[i] - b[i]));
    return m;
}

/* exp([w]x) by its power series, summed until the terms vanish: independent of Rodrigues. */
static void expm_series(const double w[3], double E[9]) {
    double K[9] = {0, -w[2], w[1], w[2], 0, -w[0], -w[1], w[0], 0}, T[9], N[9];
    for (int i = 0; i < 9; i++) E[i] = T[i] = (i % 4 == 0);
    for (int n = 1; n < 60; n++) {
        fr_mat3_mul(T, K, N);
        for (int i = 0; i < 9; i++) T[i] = N[i] / n, E[i] += T[i];
    }
}

static void random_omega(double angle, double w[3]) {
    double a[3], n;
    do {
        for (int i = 0; i < 3; i++) a[i] = uniform(-1, 1);
        n = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
    } while (n < 0.1 || n > 1.0);
    for (int i = 0; i < 3; i++) w[i] = a[i] / n * angle;
}

static void test_rodrigues(void) {
    const double angles[] = {0.0, 1e-12, 1e-7, 1e-4, 9.99e-3, 1e-2, 1.001e-2, 0.3, 1.0, 2.0, 3.0,
                             M_PI - 1e-4, M_PI - 1e-9, M_PI};
    double worst_exp = 0, worst_orth = 0, worst_rt = 0, worst_omega = 0;
    for (size_t a = 0; a < sizeof angles / sizeof *angles; a++)
        for (int rep = 0; rep < 20; rep++) {
            double w[3], R[9], E[9], Rt[9], RtR[9], w2[3], R2[9];
            random_omega(angles[a], w);
            fr_rotation_from_axis_angle(w, R);
            expm_series(w, E);
            worst_exp = fmax(worst_exp, max_abs_diff(R, E, 9));
            fr_mat3_transpose(R, Rt);
            fr_mat3_mul(Rt, R, RtR);
            double I[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
            worst_orth = fmax(worst_orth, max_abs_diff(RtR, I, 9));
            fr_rotation_to_axis_angle(R, w2);
            fr_rotation_from_axis_angle(w2, R2);
            worst_rt = fmax(worst_rt, max_abs_diff(R, R2, 9));
            if (angles[a] < M_PI - 1e-3) worst_omega = fmax(worst_omega, max_abs_diff(w, w2, 3));
        }
    printf("rodrigues: max |R - expm| %.2e, |R^T R - I| %.2e, matrix round trip %.2e, omega round trip %.2e\n",
           worst_exp, worst_orth, worst_rt, worst_omega);
    CHECK(worst_exp < 1e-14);
    CHECK(worst_orth < 1e-14);
    CHECK(worst_rt < 1e-12);
    CHECK(worst_omega < 1e-12);
    /* a known case: 90 degrees about z maps x to y */
    double w[3] = {0, 0, M_PI / 2}, R[9], v[3] = {1, 0, 0}, Rv[3];
    fr_rotation_from_axis_angle(w, R);
    fr_mat3_apply(R, v, Rv);
    CHECK_NEAR(Rv[0], 0.0, 1e-15);
    CHECK_NEAR(Rv[1], 1.0, 1e-15);
    CHECK_NEAR(Rv[2], 0.0, 1e-15);
    /* exactly 180 degrees: the axis comes back up to sign */
    double half[3] = {0, M_PI, 0}, Rh[9], wh[3];
    fr_rotation_from_axis_angle(half, Rh);
    fr_rotation_to_axis_angle(Rh, wh);
    CHECK_NEAR(fabs(wh[1]), M_PI, 1e-12);
    CHECK_NEAR(fabs(wh[0]) + fabs(wh[2]), 0.0, 1e-12);
}

static void test_jacobian(void) {
    const double angles[] = {0.0, 1e-9, 1e-3, 9.99e-3, 1.001e-2, 0.5, 2.0, 3.1};
    double worst = 0.0;
    for (size_t a = 0; a < sizeof angles / sizeof *angles; a++)
        for (int rep = 0; rep < 20; rep++) {
            double w[3], v[3], J[9], rv[3], R[9], Rv[3];
            random_omega(angles[a], w);
            for (int i = 0; i < 3; i++) v[i] = uniform(-1, 1);
            fr_rotation_apply_jacobian(w, v, rv, J);
            fr_rotation_from_axis_angle(w, R);
            fr_mat3_apply(R, v, Rv);
            worst = fmax(worst, max_abs_diff(rv, Rv, 3));
            const double h = 1e-6;
            for (int k = 0; k < 3; k++) {
                double wp[3] = {w[0], w[1], w[2]}, wm[3] = {w[0], w[1], w[2]}, Rp[9], Rm[9], vp[3], vm[3];
                wp[k] += h, wm[k] -= h;
                fr_rotation_from_axis_angle(wp, Rp);
                fr_rotation_from_axis_angle(wm, Rm);
                fr_mat3_apply(Rp, v, vp);
                fr_mat3_apply(Rm, v, vm);
                for (int i = 0; i < 3; i++) worst = fmax(worst, fabs((vp[i] - vm[i]) / (2 * h) - J[3 * i + k]));
            }
        }
    printf("d(R v)/d omega: max |analytic - central difference| %.2e\n", worst);
    CHECK(worst < 1e-8);
}

static void test_euler(void) {
    double worst = 0.0, worst_mat = 0.0;
    for (int rep = 0; rep < 500; rep++) {
        double yaw = uniform(-M_PI + 1e-6, M_PI), pitch = uniform(-M_PI / 2 + 1e-6, M_PI / 2 - 1e-6),
               roll = uniform(-M_PI + 1e-6, M_PI), R[9], y2, p2, r2, R2[9];
        fr_rotation_from_euler(yaw, pitch, roll, R);
        fr_rotation_to_euler(R, &y2, &p2, &r2);
        worst = fmax(worst, fmax(fabs(yaw - y2), fmax(fabs(pitch - p2), fabs(roll - r2))));
        fr_rotation_from_euler(y2, p2, r2, R2);
        worst_mat = fmax(worst_mat, max_abs_diff(R, R2, 9));
    }
    printf("euler round trip: max angle error %.2e rad\n", worst);
    CHECK(worst < 1e-9);
    CHECK(worst_mat < 1e-14);
    /* gimbal lock: the matrix survives even though the angles are not unique */
    for (int s = -1; s <= 1; s += 2) {
        double R[9], y2, p2, r2, R2[9];
        fr_rotation_from_euler(0.4, s * M_PI / 2, -0.7, R);
        fr_rotation_to_euler(R, &y2, &p2, &r2);
        fr_rotation_from_euler(y2, p2, r2, R2);
        CHECK(max_abs_diff(R, R2, 9) < 1e-12);
        CHECK_NEAR(p2, s * M_PI / 2, 1e-9);
        CHECK_NEAR(r2, 0.0, 0.0);
    }
    /* meaning of the signs, in pixels, for a face 0.5 m away */
    fr_camera cam = fr_camera_perspective(800.0, 640, 480);
    double t[3] = {0, 0, 0.5}, R[9], uv[2];
    const float nose[3] = {0, 0, 0.1f}, left_ear[3] = {0.08f, 0, 0}, top[3] = {0, 0.1f, 0};
    fr_rotation_from_euler(0, 0, 0, R);
    double F[9] = {1, 0, 0, 0, -1, 0, 0, 0, -1};
    CHECK(max_abs_diff(R, F, 9) == 0.0);
    fr_project_points(&cam, R, t, top, 1, uv, NULL);
    CHECK(uv[1] < cam.cy); /* model up is image up */
    fr_project_points(&cam, R, t, left_ear, 1, uv, NULL);
    CHECK(uv[0] > cam.cx); /* the subject's left is the image's right */
    fr_rotation_from_euler(0.3, 0, 0, R);
    fr_project_points(&cam, R, t, nose, 1, uv, NULL);
    CHECK(uv[0] > cam.cx + 10); /* positive yaw: nose toward image right */
    fr_rotation_from_euler(0, 0.3, 0, R);
    fr_project_points(&cam, R, t, nose, 1, uv, NULL);
    CHECK(uv[1] > cam.cy + 10); /* positive pitch: nose down */
    fr_rotation_from_euler(0, 0, 0.3, R);
    fr_project_points(&cam, R, t, left_ear, 1, uv, NULL);
    CHECK(uv[1] < cam.cy - 10); /* positive roll: the left ear rises */
}

static void test_angle(void) {
    double worst = 0.0;
    const double thetas[] = {1e-8, 1e-4, 0.5, 2.0, M_PI - 1e-6};
    for (size_t i = 0; i < sizeof thetas / sizeof *thetas; i++) {
        double w[3], A[9], D[9], B[9], d[3];
        random_omega(1.3, w);
        fr_rotation_from_axis_angle(w, A);
        random_omega(thetas[i], d);
        fr_rotation_from_axis_angle(d, D);
        fr_mat3_mul(A, D, B);
        double deg = fr_rotation_angle_deg(A, B), want = thetas[i] * 180.0 / M_PI;
        worst = fmax(worst, fabs(deg - want) / fmax(want, 1e-300));
        CHECK_NEAR(fr_rotation_angle_deg(B, A), want, 1e-9 * want + 1e-12);
    }
    printf("rotation angle: max relative error %.2e\n", worst);
    CHECK(worst < 1e-7);
}

static void test_projection(void) {
    fr_camera cam = fr_camera_perspective(1000.0, 1600, 1200);
    CHECK_NEAR(cam.cx, 799.5, 0);
    CHECK_NEAR(cam.cy, 599.5, 0);
    double xc[3] = {0.05, -0.02, 0.6}, uv[2], J[6];
    CHECK(fr_camera_project(&cam, xc, uv));
    CHECK_NEAR(uv[0], 1000.0 * 0.05 / 0.6 + 799.5, 1e-12);
    CHECK_NEAR(uv[1], 1000.0 * -0.02 / 0.6 + 599.5, 1e-12);
    double behind[3] = {0, 0, -1};
    CHECK(!fr_camera_project(&cam, behind, uv));
    fr_camera weak = fr_camera_weak(2000.0, 640, 480);
    double jw_worst = 0.0;
    for (int c = 0; c < 2; c++) {
        const fr_camera *k = c ? &weak : &cam;
        fr_camera_project_jacobian(k, xc, J);
        for (int j = 0; j < 3; j++) {
            double p[3] = {xc[0], xc[1], xc[2]}, m[3] = {xc[0], xc[1], xc[2]}, up[2], um[2];
            p[j] += 1e-7, m[j] -= 1e-7;
            fr_camera_project(k, p, up);
            fr_camera_project(k, m, um);
            for (int i = 0; i < 2; i++) jw_worst = fmax(jw_worst, fabs((up[i] - um[i]) / 2e-7 - J[3 * i + j]));
        }
    }
    printf("projection Jacobian: max |analytic - central difference| %.2e px/m\n", jw_worst);
    CHECK(jw_worst < 1e-3); /* entries are ~1e3..1e4 px/m */
    /* fr_project_points = transform then project; a point behind the camera gives NaN */
    double R[9], t[3] = {0.01, 0.02, 0.5}, uvs[4], depth[2];
    fr_rotation_from_euler(0.2, -0.1, 0.05, R);
    const float pts[6] = {0.03f, 0.04f, 0.05f, 0, 0, 2.0f};
    fr_project_points(&cam, R, t, pts, 2, uvs, depth);
    float xcf[6];
    fr_transform_points(R, t, pts, 2, xcf);
    double q[3] = {xcf[0], xcf[1], xcf[2]}, uv0[2];
    fr_camera_project(&cam, q, uv0);
    CHECK_NEAR(uvs[0], uv0[0], 1e-3);
    CHECK_NEAR(uvs[1], uv0[1], 1e-3);
    CHECK_NEAR(depth[0], xcf[2], 1e-6);
    CHECK(isnan(uvs[2]) && isnan(uvs[3]));
}

int main(void) {
    test_rodrigues();
    test_jacobian();
    test_euler();
    test_angle();
    test_projection();
    return test_result("test_raster_camera");
}
