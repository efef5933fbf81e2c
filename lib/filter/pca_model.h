/* A PCA model (mean and orthonormal basis keeping a share of the variance) for the shape and
 * texture models of the filter stage (section 4.2, Algorithm 1: "PCAReconstruction"). Data are
 * column-major, one sample per column. Internal. */
#ifndef FR_FILTER_PCA_MODEL_H
#define FR_FILTER_PCA_MODEL_H

#include "frig/frig.h"

typedef struct fr_pca {
    int dim;          /* length of a sample */
    int k;            /* components kept */
    double *mean;     /* dim */
    double *basis;    /* dim x k, orthonormal columns, by decreasing variance */
    double *variance; /* k: variance (eigenvalue / count) of each component */
    double total;     /* total variance of the data */
} fr_pca;

/* Fit on count samples X (dim x count, leading dimension dim), keeping the fewest components whose
 * variance reaches 'energy' (0 < energy <= 1) of the total. The smaller side's Gram matrix is
 * eigen-decomposed (LAPACK dsyevd). Free with fr_pca_free. */
frig_status fr_pca_fit(frig_ctx *ctx, int dim, int count, const double *X, double energy, fr_pca *out);
void fr_pca_free(fr_pca *pca);

/* Reconstruct count samples X (dim x count): x' = mean + B B^T (x - mean). Writes the squared
 * residual ||x - x'||^2 of each sample to residual2 (count values) and, when R is not NULL, the
 * reconstructions to R (dim x count). */
frig_status fr_pca_reconstruct(frig_ctx *ctx, const fr_pca *pca, int count, const double *X, double *residual2,
                               double *R);

#endif
