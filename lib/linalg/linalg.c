/* Dense linear algebra over LAPACKE, with statuses instead of info codes. */
#include <stdlib.h>

#include <lapacke.h>

#include "core/context.h"
#include "linalg/linalg.h"

frig_status fr_lstsq(frig_ctx *ctx, int m, int n, int nrhs, double *A, int lda, double *B, int ldb) {
    if (m < n || n < 1 || nrhs < 1)
        return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "least squares of %d x %d needs m >= n >= 1", m, n);
    lapack_int info = LAPACKE_dgels(LAPACK_COL_MAJOR, 'N', m, n, nrhs, A, lda, B, ldb);
    if (info > 0) return fr_error(ctx, FRIG_ERR_NUMERIC, "least squares: matrix is rank deficient (column %d)", info);
    if (info < 0) return fr_error(ctx, FRIG_ERR_INTERNAL, "least squares: LAPACK argument %d invalid", -info);
    return FRIG_OK;
}

frig_status fr_solve_spd(frig_ctx *ctx, int n, int nrhs, double *A, int lda, double *B, int ldb) {
    lapack_int info = LAPACKE_dposv(LAPACK_COL_MAJOR, 'L', n, nrhs, A, lda, B, ldb);
    if (info > 0)
        return fr_error(ctx, FRIG_ERR_NUMERIC, "Cholesky: matrix not positive definite (minor %d of %d)", info, n);
    if (info < 0) return fr_error(ctx, FRIG_ERR_INTERNAL, "Cholesky: LAPACK argument %d invalid", -info);
    return FRIG_OK;
}

frig_status fr_solve_general(frig_ctx *ctx, int n, int nrhs, double *A, int lda, double *B, int ldb) {
    lapack_int *piv = malloc(sizeof(lapack_int) * (size_t)(n > 0 ? n : 1));
    if (!piv) return fr_nomem(ctx, "pivots");
    lapack_int info = LAPACKE_dgesv(LAPACK_COL_MAJOR, n, nrhs, A, lda, piv, B, ldb);
    free(piv);
    if (info > 0) return fr_error(ctx, FRIG_ERR_NUMERIC, "LU: matrix is singular (pivot %d of %d)", info, n);
    if (info < 0) return fr_error(ctx, FRIG_ERR_INTERNAL, "LU: LAPACK argument %d invalid", -info);
    return FRIG_OK;
}

frig_status fr_svd(frig_ctx *ctx, int m, int n, double *A, int lda, double *S, double *U, double *VT) {
    int k = m < n ? m : n;
    double *u = U, *vt = VT;
    double *tmpu = NULL, *tmpvt = NULL;
    if (!u) u = tmpu = malloc(sizeof(double) * (size_t)m * (size_t)k);
    if (!vt) vt = tmpvt = malloc(sizeof(double) * (size_t)k * (size_t)n);
    if (!u || !vt) {
        free(tmpu);
        free(tmpvt);
        return fr_nomem(ctx, "SVD workspace");
    }
    lapack_int info = LAPACKE_dgesdd(LAPACK_COL_MAJOR, 'S', m, n, A, lda, S, u, m, vt, k);
    free(tmpu);
    free(tmpvt);
    if (info > 0) return fr_error(ctx, FRIG_ERR_NUMERIC, "SVD of %d x %d did not converge", m, n);
    if (info < 0) return fr_error(ctx, FRIG_ERR_INTERNAL, "SVD: LAPACK argument %d invalid", -info);
    return FRIG_OK;
}

frig_status fr_sym_eig(frig_ctx *ctx, int n, double *A, int lda, double *w) {
    lapack_int info = LAPACKE_dsyevd(LAPACK_COL_MAJOR, 'V', 'L', n, A, lda, w);
    if (info > 0) return fr_error(ctx, FRIG_ERR_NUMERIC, "symmetric eigenproblem of order %d did not converge", n);
    if (info < 0) return fr_error(ctx, FRIG_ERR_INTERNAL, "eigen: LAPACK argument %d invalid", -info);
    return FRIG_OK;
}

double fr_det3(const double m[9]) {
    return m[0] * (m[4] * m[8] - m[5] * m[7]) - m[3] * (m[1] * m[8] - m[2] * m[7]) + m[6] * (m[1] * m[5] - m[2] * m[4]);
}
