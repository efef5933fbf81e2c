/* 3D rotations for head poses (paper section 4.3, eq. 4.4: the rotation R of each photo's
 * pose): Rodrigues axis-angle <-> matrix with the exact derivative of R(omega) v for
 * Gauss-Newton, yaw/pitch/roll <-> matrix, and the angle between two rotations.
 * Matrices are row-major double[9] (R[3 * row + col]). Conventions: docs/camera.md. */
#ifndef FR_RASTER_ROTATION_H
#define FR_RASTER_ROTATION_H

/* R = exp([omega]x): rotation by |omega| radians about omega / |omega| (right hand). */
void fr_rotation_from_axis_angle(const double omega[3], double R[9]);

/* The inverse: omega with |omega| in [0, pi]. At exactly pi the sign of the axis is arbitrary.
 * R must be a rotation (orthonormal, det +1) up to rounding. */
void fr_rotation_to_axis_angle(const double R[9], double omega[3]);

/* J = d(R(omega) v) / d(omega), 3x3 row-major (J[3 * i + k] = d(Rv)_i / d omega_k); exact
 * for every omega (series near 0). Also returns R(omega) v in rv when rv is not NULL. */
void fr_rotation_apply_jacobian(const double omega[3], const double v[3], double rv[3], double J[9]);

/* Head pose angles in radians -> rotation from model to camera coordinates:
 *   R = F * Ry(yaw) * Rx(pitch) * Rz(roll),  F = diag(1, -1, -1)
 * with Rx, Ry, Rz the right-handed rotations about the MODEL's axes (x to the subject's
 * left, y up, z toward the viewer). All zero = a frontal face. Positive yaw turns the nose
 * toward the subject's left (image right); positive pitch tips the nose down; positive roll
 * raises the subject's left ear (counter-clockwise in the image). */
void fr_rotation_from_euler(double yaw, double pitch, double roll, double R[9]);

/* The inverse, pitch in [-pi/2, pi/2], yaw and roll in (-pi, pi]. At pitch = +-pi/2
 * (gimbal lock) roll is reported as 0 and yaw carries the whole turn. */
void fr_rotation_to_euler(const double R[9], double *yaw, double *pitch, double *roll);

/* The angle in degrees (0..180) of the rotation taking A to B (of A^T B). */
double fr_rotation_angle_deg(const double A[9], const double B[9]);

/* Small helpers. */
void fr_mat3_mul(const double A[9], const double B[9], double AB[9]);
void fr_mat3_transpose(const double A[9], double At[9]);

/* Av = A v. Inline: the shape-from-shading loops call it per texel and pixel. */
static inline void fr_mat3_apply(const double A[9], const double v[3], double Av[3]) {
    for (int i = 0; i < 3; i++) Av[i] = A[3 * i] * v[0] + A[3 * i + 1] * v[1] + A[3 * i + 2] * v[2];
}

#endif
