/* A supernodal multifrontal Cholesky factorization for a symmetric positive definite system of
 * fixed pattern refactored many times with new values (the mesh's Laplacian deformations):
 * the ordering (CHOLMOD's AMD), the supernodes, their row patterns, every value's place in its
 * front and every child's place in its parent's front are found once (fr_frontal_create); a
 * factorization is then dense work on each front and extend-adds, without BLAS calls. Several
 * factors (one per thread) share one analysis. Internal. */
#ifndef FR_SPARSE_FRONTAL_H
#define FR_SPARSE_FRONTAL_H

#include "frig/frig.h"
#include "sparse/csr.h"

typedef struct fr_frontal fr_frontal;        /* the analysis */
typedef struct fr_frontal_factor fr_frontal_factor;

/* The pattern of the entries with column <= row of 'lower' (square CSR); a factorization takes
 * one value per such entry, in their CSR order. */
frig_status fr_frontal_create(frig_ctx *ctx, const fr_csr *lower, fr_frontal **out);
void fr_frontal_free(fr_frontal *an);
/* Factor entries (factor nonzeros) and floating-point operations of one factorization. */
void fr_frontal_stats(const fr_frontal *an, double *entries, double *flops);

frig_status fr_frontal_factor_create(frig_ctx *ctx, const fr_frontal *an, fr_frontal_factor **out);
void fr_frontal_factor_free(fr_frontal_factor *f);
/* Factor with these values; FRIG_ERR_NUMERIC when the matrix is not positive definite. */
frig_status fr_frontal_factorize(frig_ctx *ctx, fr_frontal_factor *f, const double *values);
/* X = A^-1 B for nrhs columns of n values (B and X may be the same). */
frig_status fr_frontal_solve(frig_ctx *ctx, fr_frontal_factor *f, int nrhs, const double *B, double *X);

#endif
