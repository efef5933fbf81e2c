/* The rigid or similarity transform that best maps one point set onto another in the
 * least-squares sense (Kabsch 1976; Umeyama 1991: the rotation from the SVD of the
 * cross-covariance with the reflection removed, the scale from its singular values). Used by
 * the shape errors (section 7.2, E_B) and to keep a personalized rig in the model's frame.
 * Internal. */
#ifndef FR_MESH_POINT_ALIGN_H
#define FR_MESH_POINT_ALIGN_H

/* R (row-major), t and scale s minimizing sum_v |s R b_v + t - a_v|^2 over the first n points
 * (3 floats each); with_scale 0 keeps s = 1. Returns 0 when the points are degenerate. */
int fr_point_align(const float *a, const float *b, int n, int with_scale, double R[9], double t[3], double *s);

#endif
