/* Dense linear algebra: thin, checked wrappers over LAPACKE (matrices column-major,
 * explicit leading dimensions). Internal. */
#ifndef FR_LINALG_LINALG_H
#define FR_LINALG_LINALG_H

#include "frig/frig.h"

/* Least squares min ||A X - B|| for m >= n, full column rank (QR, dgels). A (m x n) is
 * overwritten; on return the first n rows of B (m x nrhs) hold X. */
frig_status fr_lstsq(frig_ctx *ctx, int m, int n, int nrhs, double *A, int lda, double *B, int ldb);

/* Solve A X = B for symmetric positive definite A (n x n, overwritten by its Cholesky
 * factor); X overwrites B (n x nrhs). FRIG_ERR_NUMERIC when A is not positive definite. */
frig_status fr_solve_spd(frig_ctx *ctx, int n, int nrhs, double *A, int lda, double *B, int ldb);

/* Solve A X = B for a general square A (LU with pivoting); both overwritten. */
frig_status fr_solve_general(frig_ctx *ctx, int n, int nrhs, double *A, int lda, double *B, int ldb);

/* Thin SVD A = U diag(S) VT of A (m x n, overwritten), k = min(m, n): U is m x k (ldu = m),
 * VT is k x n (ldvt = k), S has k values in decreasing order. U or VT may be NULL. */
frig_status fr_svd(frig_ctx *ctx, int m, int n, double *A, int lda, double *S, double *U, double *VT);

/* Eigen-decomposition of symmetric A (n x n): eigenvalues ascending in w, eigenvectors in
 * the columns of A. */
frig_status fr_sym_eig(frig_ctx *ctx, int n, double *A, int lda, double *w);

/* Solve the 3x3 / small dense problem helpers used in geometry. */
double fr_det3(const double m[9]);

#endif
