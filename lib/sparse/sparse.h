/* Sparse symmetric positive definite systems over CHOLMOD, in the shape every later stage
 * needs: build a matrix from triplets, analyze its pattern once, factorize (again whenever
 * the values change but not the pattern), and solve many right-hand sides at a time.
 * Least-squares problems min ||A x - b|| go through the normal equations A^T A.
 * Internal. */
#ifndef FR_SPARSE_SPARSE_H
#define FR_SPARSE_SPARSE_H

#include "frig/frig.h"

/* Coordinate-form matrix; duplicates are summed when the matrix is built. */
typedef struct fr_triplets {
    int rows, cols;
    size_t count, capacity;
    int *i, *j;
    double *x;
} fr_triplets;

frig_status fr_triplets_init(frig_ctx *ctx, fr_triplets *t, int rows, int cols, size_t capacity);
frig_status fr_triplets_add(frig_ctx *ctx, fr_triplets *t, int i, int j, double x);
void fr_triplets_clear(fr_triplets *t); /* keep storage, drop entries */
void fr_triplets_free(fr_triplets *t);

typedef struct fr_cholesky fr_cholesky;

/* Symmetric system: 'lower' holds entries with i >= j of an n x n SPD matrix. Analyzes and
 * factorizes. FRIG_ERR_NUMERIC when the matrix is not positive definite. */
frig_status fr_cholesky_create(frig_ctx *ctx, const fr_triplets *lower, fr_cholesky **out);

/* Least squares: A is m x n (m >= n); factors A^T A and keeps A for the right-hand sides. */
frig_status fr_cholesky_create_lsq(frig_ctx *ctx, const fr_triplets *A, fr_cholesky **out);

/* New values, same pattern (the same triplet positions in the same order): numeric
 * factorization only, the analysis is reused. */
frig_status fr_cholesky_refactor(frig_ctx *ctx, fr_cholesky *ch, const fr_triplets *same_pattern);

int fr_cholesky_size(const fr_cholesky *ch);

/* Solve M X = B, M the factored n x n matrix, B and X n x nrhs column-major (may alias). The
 * factorization keeps the solve's workspace for the next one, so one factorization is solved by one
 * thread at a time. */
frig_status fr_cholesky_solve(frig_ctx *ctx, fr_cholesky *ch, int nrhs, const double *B, double *X);

/* For a least-squares factorization: X = argmin ||A X - b||, b m x nrhs, X n x nrhs. */
frig_status fr_cholesky_solve_lsq(frig_ctx *ctx, fr_cholesky *ch, int nrhs, const double *b, double *X);

void fr_cholesky_free(fr_cholesky *ch);

/* A symmetric system from a square CSR matrix of which the entries with column <= row are used
 * (the test's reference for sparse/frontal.h, which took its one caller, the mesh's Laplacian
 * deformations). simplicial: a simplicial (column by column) factor
 * instead of CHOLMOD's choice, for small systems refactored many times (the supernodal one's
 * BLAS calls and workspace cost more than they save there: a 9,409-vertex mesh Laplacian with
 * 222,000 factor entries factors about 25% faster). */
struct fr_csr;
frig_status fr_cholesky_create_csr(frig_ctx *ctx, const struct fr_csr *lower, int simplicial, fr_cholesky **out);

#endif
