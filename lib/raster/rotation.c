/* 3D rotations for head poses (paper section 4.3, eq. 4.4): Rodrigues' formula
 * R = I + a K + b K^2 (K = [omega]x, a = sin t / t, b = (1 - cos t) / t^2), its inverse, the
 * exact derivative of R(omega) v (differentiating that formula term by term), Euler angles
 * and rotation distances. Conventions: docs/camera.md. */
#include <math.h>

#include "raster/rotation.h"

/* Below this angle the coefficients use their Taylor series (exact to double rounding). */
#define SERIES_ANGLE 1e-2

void fr_mat3_mul(const double A[9], const double B[9], double AB[9]) {
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            AB[3 * i + j] = A[3 * i] * B[j] + A[3 * i + 1] * B[3 + j] + A[3 * i + 2] * B[6 + j];
}

void fr_mat3_transpose(const double A[9], double At[9]) {
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) At[3 * j + i] = A[3 * i + j];
}

static void cross3(const double a[3], const double b[3], double c[3]) {
    c[0] = a[1] * b[2] - a[2] * b[1];
    c[1] = a[2] * b[0] - a[0] * b[2];
    c[2] = a[0] * b[1] - a[1] * b[0];
}

/* The Rodrigues coefficients a(t), b(t) and their scaled derivatives a'(t)/t, b'(t)/t. */
static void rodrigues_coefficients(double t, double *a, double *b, double *da, double *db) {
    double t2 = t * t;
    if (t < SERIES_ANGLE) {
        *a = 1.0 - t2 / 6.0 + t2 * t2 / 120.0;
        *b = 0.5 - t2 / 24.0 + t2 * t2 / 720.0;
        *da = -1.0 / 3.0 + t2 / 30.0 - t2 * t2 / 840.0;
        *db = -1.0 / 12.0 + t2 / 180.0 - t2 * t2 / 6720.0;
        return;
    }
    double s = sin(t), c = cos(t);
    *a = s / t;
    *b = (1.0 - c) / t2;
    *da = (t * c - s) / (t2 * t);
    *db = (t * s - 2.0 * (1.0 - c)) / (t2 * t2);
}

void fr_rotation_from_axis_angle(const double omega[3], double R[9]) {
    double t = sqrt(omega[0] * omega[0] + omega[1] * omega[1] + omega[2] * omega[2]);
    double a, b, da, db;
    rodrigues_coefficients(t, &a, &b, &da, &db);
    double x = omega[0], y = omega[1], z = omega[2];
    /* K^2 = omega omega^T - t^2 I */
    R[0] = 1.0 + b * (x * x - t * t);
    R[1] = -a * z + b * x * y;
    R[2] = a * y + b * x * z;
    R[3] = a * z + b * x * y;
    R[4] = 1.0 + b * (y * y - t * t);
    R[5] = -a * x + b * y * z;
    R[6] = -a * y + b * x * z;
    R[7] = a * x + b * y * z;
    R[8] = 1.0 + b * (z * z - t * t);
}

void fr_rotation_to_axis_angle(const double R[9], double omega[3]) {
    double v[3] = {R[7] - R[5], R[2] - R[6], R[3] - R[1]}; /* 2 sin(t) n */
    double c = 0.5 * (R[0] + R[4] + R[8] - 1.0);
    double s = 0.5 * sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (c > 1.0) c = 1.0;
    if (c < -1.0) c = -1.0;
    double t = atan2(s, c);
    if (c > 0.0) { /* t < 90 degrees: the skew part is well conditioned */
        double k = s > 0.0 ? t / s : 1.0;
        for (int i = 0; i < 3; i++) omega[i] = 0.5 * k * v[i];
        return;
    }
    /* t >= 90 degrees: the symmetric part (R + R^T) / 2 - c I = (1 - c) n n^T gives the axis. */
    int j = 0;
    for (int i = 1; i < 3; i++)
        if (R[4 * i] > R[4 * j]) j = i;
    double col[3];
    for (int i = 0; i < 3; i++) col[i] = 0.5 * (R[3 * i + j] + R[3 * j + i]) - (i == j ? c : 0.0);
    double norm = sqrt(col[0] * col[0] + col[1] * col[1] + col[2] * col[2]);
    double sign = (col[0] * v[0] + col[1] * v[1] + col[2] * v[2]) < 0.0 ? -1.0 : 1.0;
    for (int i = 0; i < 3; i++) omega[i] = norm > 0.0 ? sign * t * col[i] / norm : 0.0;
}

void fr_rotation_apply_jacobian(const double omega[3], const double v[3], double rv[3], double J[9]) {
    double t = sqrt(omega[0] * omega[0] + omega[1] * omega[1] + omega[2] * omega[2]);
    double a, b, da, db;
    rodrigues_coefficients(t, &a, &b, &da, &db);
    double wxv[3], wwxv[3];
    cross3(omega, v, wxv);
    cross3(omega, wxv, wwxv);
    double wv = omega[0] * v[0] + omega[1] * v[1] + omega[2] * v[2];
    if (rv)
        for (int i = 0; i < 3; i++) rv[i] = v[i] + a * wxv[i] + b * wwxv[i];
    /* d(w x v)/dw = -[v]x ;  d(w x (w x v))/dw = (w.v) I + w v^T - 2 v w^T ;
     * d a/dw = (a'/t) w^T ;  d b/dw = (b'/t) w^T */
    double vx[9] = {0, -v[2], v[1], v[2], 0, -v[0], -v[1], v[0], 0};
    for (int i = 0; i < 3; i++)
        for (int k = 0; k < 3; k++) {
            double d2 = (i == k ? wv : 0.0) + omega[i] * v[k] - 2.0 * v[i] * omega[k];
            J[3 * i + k] = -a * vx[3 * i + k] + b * d2 + da * wxv[i] * omega[k] + db * wwxv[i] * omega[k];
        }
}

static void rot_x(double t, double R[9]) {
    double c = cos(t), s = sin(t);
    double m[9] = {1, 0, 0, 0, c, -s, 0, s, c};
    for (int i = 0; i < 9; i++) R[i] = m[i];
}

static void rot_y(double t, double R[9]) {
    double c = cos(t), s = sin(t);
    double m[9] = {c, 0, s, 0, 1, 0, -s, 0, c};
    for (int i = 0; i < 9; i++) R[i] = m[i];
}

static void rot_z(double t, double R[9]) {
    double c = cos(t), s = sin(t);
    double m[9] = {c, -s, 0, s, c, 0, 0, 0, 1};
    for (int i = 0; i < 9; i++) R[i] = m[i];
}

void fr_rotation_from_euler(double yaw, double pitch, double roll, double R[9]) {
    double ry[9], rx[9], rz[9], yx[9], m[9];
    rot_y(yaw, ry);
    rot_x(pitch, rx);
    rot_z(roll, rz);
    fr_mat3_mul(ry, rx, yx);
    fr_mat3_mul(yx, rz, m);
    /* F = diag(1, -1, -1): negate rows 1 and 2 */
    for (int j = 0; j < 3; j++) {
        R[j] = m[j];
        R[3 + j] = -m[3 + j];
        R[6 + j] = -m[6 + j];
    }
}

void fr_rotation_to_euler(const double R[9], double *yaw, double *pitch, double *roll) {
    /* M = F R = Ry Rx Rz = [ . . sa cb ; cb sc  cb cc  -sb ; . . ca cb ] */
    double m[9];
    for (int j = 0; j < 3; j++) {
        m[j] = R[j];
        m[3 + j] = -R[3 + j];
        m[6 + j] = -R[6 + j];
    }
    double sb = -m[5];
    double cb = sqrt(m[3] * m[3] + m[4] * m[4]);
    *pitch = atan2(sb, cb);
    if (cb > 1e-12) {
        *yaw = atan2(m[2], m[8]);
        *roll = atan2(m[3], m[4]);
    } else { /* gimbal lock: M row 0 = [cos(a -+ c), sin(a -+ c) * (+-1), 0] with c = 0 */
        *roll = 0.0;
        *yaw = atan2(sb > 0.0 ? m[1] : -m[1], m[0]);
    }
}

double fr_rotation_angle_deg(const double A[9], const double B[9]) {
    double At[9], M[9];
    fr_mat3_transpose(A, At);
    fr_mat3_mul(At, B, M);
    double v[3] = {M[7] - M[5], M[2] - M[6], M[3] - M[1]};
    double s = 0.5 * sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    double c = 0.5 * (M[0] + M[4] + M[8] - 1.0);
    return atan2(s, c) * (180.0 / M_PI);
}
