/* Robust PCA by principal component pursuit, inexact augmented Lagrange multipliers (paper section
 * 4.2, eq. 4.1; Lin, Chen, Ma 2010, Algorithm 5): alternate soft thresholding of S and singular value
 * thresholding of L while the penalty mu grows geometrically, until ||X - L - S||_F / ||X||_F < tol. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <cblas.h>
#include <lapacke.h>

#include "core/context.h"
#include "filter/robust_pca.h"
#include "linalg/linalg.h"

void fr_rpca_default_options(fr_rpca_options *opt) {
    opt->lambda = 0;
    opt->tol = 1e-7;
    opt->rho = 1.5;
    opt->max_iter = 500;
    opt->svt = FR_SVT_AUTO;
}

/* Eigenvalues (ascending, in w) and, when vectors is nonzero, eigenvectors (columns of G) of the
 * k x k symmetric matrix G whose lower triangle is set. */
static frig_status sym_eig(frig_ctx *ctx, int k, double *G, double *w, int vectors) {
    lapack_int info = LAPACKE_dsyevd(LAPACK_COL_MAJOR, vectors ? 'V' : 'N', 'L', k, G, k, w);
    if (info > 0) return fr_error(ctx, FRIG_ERR_NUMERIC, "robust PCA: eigen-decomposition of order %d failed", k);
    if (info < 0) return fr_error(ctx, FRIG_ERR_INTERNAL, "robust PCA: dsyevd argument %d invalid", -info);
    return FRIG_OK;
}

/* Lower triangle of the Gram matrix of the small side: M^T M (n x n) when n <= m, else M M^T. */
static void gram_small_side(int m, int n, const double *M, double *G) {
    if (n <= m)
        cblas_dsyrk(CblasColMajor, CblasLower, CblasTrans, n, m, 1.0, M, m, 0.0, G, n);
    else
        cblas_dsyrk(CblasColMajor, CblasLower, CblasNoTrans, m, n, 1.0, M, m, 0.0, G, m);
}

frig_status fr_spectral_norm(frig_ctx *ctx, int m, int n, const double *M, double *out) {
    *out = 0;
    int k = m < n ? m : n;
    if (k < 1) return FRIG_OK;
    double *G = malloc(sizeof(double) * ((size_t)k * k + k));
    if (!G) return fr_nomem(ctx, "a Gram matrix");
    gram_small_side(m, n, M, G);
    frig_status st = sym_eig(ctx, k, G, G + (size_t)k * k, 0);
    if (st == FRIG_OK) *out = sqrt(fmax(G[(size_t)k * k + k - 1], 0.0));
    free(G);
    return st;
}

/* SVT through the Gram matrix of the small side: with V the eigenvectors of M^T M (eigenvalues
 * s^2), A = M V diag(max(s - tau, 0) / s) V^T; likewise with U from M M^T when m < n. */
static frig_status svt_gram(frig_ctx *ctx, int m, int n, const double *M, double tau, double *A, int *rank) {
    int k = m < n ? m : n;
    size_t other = (size_t)(m < n ? n : m);
    double *G = malloc(sizeof(double) * ((size_t)k * k + k + other * k));
    if (!G) return fr_nomem(ctx, "singular value thresholding workspace");
    double *w = G + (size_t)k * k, *B = w + k;
    gram_small_side(m, n, M, G);
    frig_status st = sym_eig(ctx, k, G, w, 1);
    if (st != FRIG_OK) {
        free(G);
        return st;
    }
    int r = 0; /* eigenvalues ascend: the kept ones are the last r */
    while (r < k && sqrt(fmax(w[k - 1 - r], 0.0)) > tau) r++;
    *rank = r;
    if (r == 0) {
        memset(A, 0, sizeof(double) * (size_t)m * n);
        free(G);
        return FRIG_OK;
    }
    const double *Q = G + (size_t)(k - r) * k; /* k x r, leading dimension k */
    if (n <= m) {
        cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, m, r, n, 1.0, M, m, Q, k, 0.0, B, m);
        for (int j = 0; j < r; j++) {
            double s = sqrt(w[k - r + j]);
            cblas_dscal(m, (s - tau) / s, B + (size_t)j * m, 1);
        }
        cblas_dgemm(CblasColMajor, CblasNoTrans, CblasTrans, m, n, r, 1.0, B, m, Q, k, 0.0, A, m);
    } else {
        cblas_dgemm(CblasColMajor, CblasTrans, CblasNoTrans, r, n, m, 1.0, Q, k, M, m, 0.0, B, r);
        for (int j = 0; j < r; j++) {
            double s = sqrt(w[k - r + j]);
            cblas_dscal(n, (s - tau) / s, B + j, r);
        }
        cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, m, n, r, 1.0, Q, k, B, r, 0.0, A, m);
    }
    free(G);
    return FRIG_OK;
}

/* SVT through LAPACK's thin SVD: A = U_r diag(s - tau) V_r^T. */
static frig_status svt_svd(frig_ctx *ctx, int m, int n, const double *M, double tau, double *A, int *rank) {
    int k = m < n ? m : n;
    size_t mn = (size_t)m * n;
    double *W = malloc(sizeof(double) * (mn + k + (size_t)m * k + (size_t)k * n));
    if (!W) return fr_nomem(ctx, "singular value thresholding workspace");
    double *s = W + mn, *U = s + k, *VT = U + (size_t)m * k;
    memcpy(W, M, sizeof(double) * mn);
    frig_status st = fr_svd(ctx, m, n, W, m, s, U, VT);
    if (st != FRIG_OK) {
        free(W);
        return st;
    }
    int r = 0;
    while (r < k && s[r] > tau) r++;
    *rank = r;
    for (int j = 0; j < r; j++) cblas_dscal(m, s[j] - tau, U + (size_t)j * m, 1);
    if (r == 0)
        memset(A, 0, sizeof(double) * mn);
    else
        cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, m, n, r, 1.0, U, m, VT, k, 0.0, A, m);
    free(W);
    return FRIG_OK;
}

frig_status fr_svt(frig_ctx *ctx, int m, int n, const double *M, double tau, fr_svt_method method, double *A,
                   int *rank) {
    *rank = 0;
    if (m < 1 || n < 1) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "SVT of a %d x %d matrix", m, n);
    /* Squaring the singular values costs accuracy only below sqrt(eps) of the largest, where
     * robust PCA's thresholds never reach at its tolerances (test_robust_pca checks both ways). */
    if (method == FR_SVT_AUTO) method = FR_SVT_GRAM;
    return method == FR_SVT_GRAM ? svt_gram(ctx, m, n, M, tau, A, rank) : svt_svd(ctx, m, n, M, tau, A, rank);
}

static double max_abs(size_t count, const double *x) {
    double v = 0;
    for (size_t i = 0; i < count; i++) v = fmax(v, fabs(x[i]));
    return v;
}

frig_status fr_robust_pca(frig_ctx *ctx, int m, int n, const double *X, int ldx, const fr_rpca_options *opt,
                          double *L, double *S, fr_rpca_info *info) {
    fr_rpca_options o;
    if (opt)
        o = *opt;
    else
        fr_rpca_default_options(&o);
    if (info) memset(info, 0, sizeof *info);
    if (m < 1 || n < 1 || ldx < m || !X || !L || !S)
        return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "robust PCA of a %d x %d matrix (ldx %d)", m, n, ldx);
    if (!(o.tol > 0) || !(o.rho > 1) || o.max_iter < 1)
        return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "robust PCA: tol %g, rho %g, max_iter %d are not valid",
                        o.tol, o.rho, o.max_iter);
    const double lambda = o.lambda > 0 ? o.lambda : 1.0 / sqrt((double)(m > n ? m : n));
    if (info) info->lambda = lambda;
    size_t mn = (size_t)m * n;
    memset(L, 0, sizeof(double) * mn);
    memset(S, 0, sizeof(double) * mn);

    double *D = malloc(sizeof(double) * mn * 3); /* X packed, the multiplier Y, a temporary */
    if (!D) return fr_nomem(ctx, "robust PCA workspace");
    double *Y = D + mn, *T = Y + mn;
    for (int j = 0; j < n; j++) memcpy(D + (size_t)j * m, X + (size_t)j * ldx, sizeof(double) * m);

    double norm_fro = cblas_dnrm2((int)mn, D, 1), norm_two = 0;
    frig_status st = norm_fro > 0 ? fr_spectral_norm(ctx, m, n, D, &norm_two) : FRIG_OK;
    if (st != FRIG_OK || !(norm_fro > 0) || !(norm_two > 0)) {
        free(D);
        return st;
    }
    /* Y0 = X / J(X), J = max(||X||_2, ||X||_inf / lambda): a dual-feasible start. */
    double dual = fmax(norm_two, max_abs(mn, D) / lambda);
    for (size_t i = 0; i < mn; i++) Y[i] = D[i] / dual;
    double mu = 1.25 / norm_two, mu_bar = mu * 1e7, residual = 1;
    int iter = 0, rank = 0;
    while (iter < o.max_iter && residual >= o.tol) {
        if ((st = fr_check_cancel(ctx, "robust PCA")) != FRIG_OK) break;
        double inv_mu = 1.0 / mu, shrink = lambda * inv_mu;
        /* S = shrink_{lambda/mu}(X - L + Y/mu) */
        for (size_t i = 0; i < mn; i++) {
            double t = D[i] - L[i] + inv_mu * Y[i];
            S[i] = t > shrink ? t - shrink : t < -shrink ? t + shrink : 0.0;
        }
        /* L = SVT_{1/mu}(X - S + Y/mu) */
        for (size_t i = 0; i < mn; i++) T[i] = D[i] - S[i] + inv_mu * Y[i];
        if ((st = fr_svt(ctx, m, n, T, inv_mu, o.svt, L, &rank)) != FRIG_OK) break;
        /* Y += mu (X - L - S) */
        double z2 = 0;
        for (size_t i = 0; i < mn; i++) {
            double z = D[i] - L[i] - S[i];
            z2 += z * z;
            Y[i] += mu * z;
        }
        residual = sqrt(z2) / norm_fro;
        mu = fmin(mu * o.rho, mu_bar);
        iter++;
    }
    free(D);
    if (st != FRIG_OK) return st;
    if (info) {
        info->iterations = iter;
        info->rank = rank;
        info->residual = residual;
        for (size_t i = 0; i < mn; i++) info->nonzeros += S[i] != 0;
    }
    return FRIG_OK;
}
