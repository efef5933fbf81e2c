/* 2D similarity (Procrustes) alignment of landmark shapes, and the generalized Procrustes mean
 * (Gower 1975; the shape normalization of active shape models), used by the filter stage's shape
 * model (section 4.2). Shapes are n points interleaved (x0, y0, x1, y1, ...). Internal. */
#ifndef FR_FILTER_PROCRUSTES_H
#define FR_FILTER_PROCRUSTES_H

#include "frig/frig.h"

/* The similarity q ~ [a -b; b a] p + (tx, ty) minimizing sum ||.||^2 over the n points (a rotation,
 * a uniform scale and a translation; no reflection): T = {a, b, tx, ty}. A degenerate p (all points
 * equal) gives the translation alone. */
void fr_similarity_fit(int n, const double *p, const double *q, double T[4]);
void fr_similarity_apply(int n, const double T[4], const double *p, double *out);
/* The inverse similarity. */
void fr_similarity_invert(const double T[4], double inv[4]);

/* Generalized Procrustes analysis of count shapes of n points (shape i at shapes + 2 n i): each
 * shape is similarity-aligned to the mean, the mean recomputed and re-aligned to 'gauge' (which
 * fixes position, size and orientation; n points), until the mean moves less than 1e-12 of its
 * size (at most 100 rounds). Writes the aligned shapes (2 n x count) and the mean (2 n); iterations
 * may be NULL. */
frig_status fr_procrustes_align(frig_ctx *ctx, int n, int count, const double *shapes, const double *gauge,
                                double *aligned, double *mean, int *iterations);

#endif
