/* Sums and layouts over mode sets: k blocks of 3 nv floats (the model's identity modes and
 * expressions, a rig's blendshape deltas), read block by block in cache-sized pieces rather than
 * one vertex's k values at a time, which strides 3 nv floats per step. Internal. */
#ifndef FR_MODEL_MODE_SUMS_H
#define FR_MODEL_MODE_SUMS_H

#include <stddef.h>

/* out[i] = (float)(base[i] + sum_a w_a modes_a[i] + add[i]) for i < n, summed in double in that
 * order. Term a is mode j = which[a] (which NULL: j = a), at modes + j stride, weighed w[j].
 * base and add may be NULL (0). */
void fr_mode_sum(size_t n, const float *base, const float *modes, size_t stride, int count, const int *which,
                 const double *w, const float *add, float *out);

/* The k modes (k blocks of 3 nv floats) vertex by vertex: out[(v k + j) 3 + d] = modes[j 3 nv +
 * 3 v + d], so that one vertex's k modes are one contiguous read (out: 3 nv k floats). */
void fr_modes_by_vertex(const float *modes, size_t nv, int k, float *out);

#endif
