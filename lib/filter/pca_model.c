/* PCA through the Gram matrix of the smaller side (section 4.2's shape and texture models): with
 * few samples of long vectors, the count x count matrix Xc^T Xc has the same nonzero spectrum as
 * the covariance, and its eigenvectors v give the principal directions Xc v / sqrt(lambda). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <cblas.h>
#include <lapacke.h>

#include "core/context.h"
#include "filter/pca_model.h"

void fr_pca_free(fr_pca *p) {
    if (!p) return;
    free(p->mean);
    free(p->basis);
    free(p->variance);
    memset(p, 0, sizeof *p);
}

/* Number of leading eigenvalues (descending in w) reaching 'energy' of their sum; eigenvalues
 * below 1e-12 of the largest are never kept. */
static int components_for(int count, const double *w, double energy, double *total) {
    double sum = 0;
    for (int i = 0; i < count; i++) sum += fmax(w[i], 0.0);
    *total = sum;
    if (!(sum > 0)) return 0;
    double acc = 0;
    int k = 0;
    while (k < count && w[k] > 1e-12 * w[0] && acc < energy * sum * (1 - 1e-12)) acc += w[k++];
    return k;
}

frig_status fr_pca_fit(frig_ctx *ctx, int dim, int count, const double *X, double energy, fr_pca *out) {
    memset(out, 0, sizeof *out);
    if (dim < 1 || count < 1 || !(energy > 0 && energy <= 1))
        return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "PCA of %d samples of length %d keeping %g", count, dim,
                        energy);
    int small = count < dim ? count : dim;
    size_t dn = (size_t)dim * count;
    double *Xc = malloc(sizeof(double) * (dn + (size_t)small * small + small));
    out->mean = calloc((size_t)dim, sizeof(double));
    if (!Xc || !out->mean) {
        free(Xc);
        fr_pca_free(out);
        return fr_nomem(ctx, "a PCA model");
    }
    double *G = Xc + dn, *w = G + (size_t)small * small;
    out->dim = dim;
    for (int j = 0; j < count; j++)
        for (int i = 0; i < dim; i++) out->mean[i] += X[i + (size_t)j * dim];
    for (int i = 0; i < dim; i++) out->mean[i] /= count;
    for (int j = 0; j < count; j++)
        for (int i = 0; i < dim; i++) Xc[i + (size_t)j * dim] = X[i + (size_t)j * dim] - out->mean[i];
    if (count <= dim)
        cblas_dsyrk(CblasColMajor, CblasLower, CblasTrans, count, dim, 1.0, Xc, dim, 0.0, G, count);
    else
        cblas_dsyrk(CblasColMajor, CblasLower, CblasNoTrans, dim, count, 1.0, Xc, dim, 0.0, G, dim);
    lapack_int info = LAPACKE_dsyevd(LAPACK_COL_MAJOR, 'V', 'L', small, G, small, w);
    if (info != 0) {
        free(Xc);
        fr_pca_free(out);
        return fr_error(ctx, FRIG_ERR_NUMERIC, "PCA: eigen-decomposition of order %d failed (%d)", small,
                        (int)info);
    }
    /* Descending order: reverse the eigenvalues and the eigenvector columns. */
    for (int i = 0; i < small / 2; i++) {
        double t = w[i];
        w[i] = w[small - 1 - i];
        w[small - 1 - i] = t;
        cblas_dswap(small, G + (size_t)i * small, 1, G + (size_t)(small - 1 - i) * small, 1);
    }
    int k = components_for(small, w, energy, &out->total);
    out->total /= count;
    out->k = k;
    out->basis = malloc(sizeof(double) * (size_t)dim * (k > 0 ? k : 1));
    out->variance = malloc(sizeof(double) * (size_t)(k > 0 ? k : 1));
    if (!out->basis || !out->variance) {
        free(Xc);
        fr_pca_free(out);
        return fr_nomem(ctx, "a PCA basis");
    }
    for (int j = 0; j < k; j++) out->variance[j] = w[j] / count;
    if (k > 0) {
        if (count <= dim) {
            cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, dim, k, count, 1.0, Xc, dim, G, count, 0.0,
                        out->basis, dim);
            for (int j = 0; j < k; j++) cblas_dscal(dim, 1.0 / sqrt(w[j]), out->basis + (size_t)j * dim, 1);
        } else {
            memcpy(out->basis, G, sizeof(double) * (size_t)dim * k);
        }
    }
    free(Xc);
    return FRIG_OK;
}

frig_status fr_pca_reconstruct(frig_ctx *ctx, const fr_pca *p, int count, const double *X, double *residual2,
                               double *R) {
    if (count < 1 || p->dim < 1) return FRIG_OK;
    size_t dn = (size_t)p->dim * count;
    double *D = malloc(sizeof(double) * (dn + (size_t)(p->k > 0 ? p->k : 1) * count));
    if (!D) return fr_nomem(ctx, "PCA reconstruction");
    double *C = D + dn;
    for (int j = 0; j < count; j++)
        for (int i = 0; i < p->dim; i++) D[i + (size_t)j * p->dim] = X[i + (size_t)j * p->dim] - p->mean[i];
    if (p->k > 0) {
        /* C = B^T D, D -= B C: D becomes the residual. */
        cblas_dgemm(CblasColMajor, CblasTrans, CblasNoTrans, p->k, count, p->dim, 1.0, p->basis, p->dim, D, p->dim,
                    0.0, C, p->k);
        cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, p->dim, count, p->k, -1.0, p->basis, p->dim, C, p->k,
                    1.0, D, p->dim);
    }
    for (int j = 0; j < count; j++) {
        const double *d = D + (size_t)j * p->dim;
        double s = 0;
        for (int i = 0; i < p->dim; i++) s += d[i] * d[i];
        residual2[j] = s;
        if (R)
            for (int i = 0; i < p->dim; i++) R[i + (size_t)j * p->dim] = X[i + (size_t)j * p->dim] - d[i];
    }
    free(D);
    return FRIG_OK;
}
