/* Robust PCA by principal component pursuit (paper section 4.2, eq. 4.1; Candes, Li, Ma, Wright 2011):
 * X = L + S minimizing ||L||_* + lambda ||S||_1, solved by the inexact augmented Lagrange multiplier
 * method (Lin, Chen, Ma 2010, Algorithm 5). Matrices are column-major. Internal. */
#ifndef FR_FILTER_ROBUST_PCA_H
#define FR_FILTER_ROBUST_PCA_H

#include "frig/frig.h"

/* How singular value thresholding factors its m x n argument. */
typedef enum fr_svt_method {
    FR_SVT_AUTO = 0, /* the Gram matrix (measured faster at every size used here, equally accurate) */
    FR_SVT_SVD = 1,  /* thin SVD (LAPACK dgesdd) */
    FR_SVT_GRAM = 2  /* eigen-decomposition (dsyevd) of the small side's Gram matrix */
} fr_svt_method;

typedef struct fr_rpca_options {
    double lambda;  /* weight of ||S||_1; <= 0 means 1 / sqrt(max(m, n)) (the paper's choice) */
    double tol;     /* stop when ||X - L - S||_F / ||X||_F < tol (default 1e-7) */
    double rho;     /* growth of the penalty mu per iteration (default 1.5) */
    int max_iter;   /* at most this many iterations (default 500) */
    fr_svt_method svt;
} fr_rpca_options;

typedef struct fr_rpca_info {
    int iterations;  /* iterations run */
    int rank;        /* rank of L at the last iteration */
    double residual; /* ||X - L - S||_F / ||X||_F at the end */
    double lambda;   /* lambda used */
    long nonzeros;   /* nonzero entries of S */
} fr_rpca_info;

void fr_rpca_default_options(fr_rpca_options *opt);

/* Decompose X (m x n, leading dimension ldx) into L + S, both m x n with leading dimension m.
 * opt may be NULL (defaults); info may be NULL. An all-zero X gives L = S = 0. Not reaching
 * the tolerance within max_iter is not an error: info->residual says how far it got. */
frig_status fr_robust_pca(frig_ctx *ctx, int m, int n, const double *X, int ldx, const fr_rpca_options *opt,
                          double *L, double *S, fr_rpca_info *info);

/* Singular value thresholding: A = U diag(max(s - tau, 0)) V^T for M = U diag(s) V^T (m x n,
 * leading dimension m; M is not changed). Returns the rank of A in *rank. */
frig_status fr_svt(frig_ctx *ctx, int m, int n, const double *M, double tau, fr_svt_method method, double *A,
                   int *rank);

/* Largest singular value of M (m x n, leading dimension m). */
frig_status fr_spectral_norm(frig_ctx *ctx, int m, int n, const double *M, double *out);

#endif
