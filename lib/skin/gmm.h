/* Gaussian mixtures in two dimensions fitted by expectation-maximization: the skin colour model
 * of the paper's section 5.1.2 (a mixture on the Cb, Cr chroma of the face's pixels, grown over
 * rounds with more components). Deterministic: no random initialization. Internal. */
#ifndef FR_SKIN_GMM_H
#define FR_SKIN_GMM_H

#define FR_GMM_MAX 8

typedef struct fr_gmm2 {
    int k;
    double w[FR_GMM_MAX];      /* mixing weights, sum 1 */
    double mu[FR_GMM_MAX][2];
    double cov[FR_GMM_MAX][3]; /* xx, xy, yy */
} fr_gmm2;

/* One robust Gaussian of n points (2 per point, 'use' selects them when not NULL): the median
 * and 1.4826 x MAD per axis, the correlation of the points within 3 of those scales. Returns
 * the points used (0: g is left unchanged). */
int fr_gmm2_robust_init(const double *xy, const unsigned char *use, int n, fr_gmm2 *g);

/* Split component j in two along its principal axis (one standard deviation each side), for
 * growing a mixture deterministically. No-op when k is already FR_GMM_MAX. */
void fr_gmm2_split(fr_gmm2 *g, int j);

/* EM iterations from g's current components over the selected points; 'floor' is the least
 * variance along any axis (keeps a component from collapsing on quantized chroma). */
void fr_gmm2_em(fr_gmm2 *g, const double *xy, const unsigned char *use, int n, int iterations, double floor);

/* Squared Mahalanobis distance from (x, y) to component j. */
double fr_gmm2_mahalanobis2(const fr_gmm2 *g, int j, double x, double y);
/* Mixture density at (x, y). */
double fr_gmm2_density(const fr_gmm2 *g, double x, double y);

#endif
