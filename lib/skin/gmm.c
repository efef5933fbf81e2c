/* Two-dimensional Gaussian mixtures by expectation-maximization (Dempster, Laird and Rubin
 * 1977), for the skin chroma model of paper section 5.1.2: a robust single Gaussian first,
 * then components added by splitting along principal axes, each round refitted by EM. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/sort.h"
#include "skin/gmm.h"

#define TWO_PI 6.283185307179586

static double median_of(double *v, int n) {
    qsort(v, (size_t)n, sizeof *v, fr_cmp_double);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

int fr_gmm2_robust_init(const double *xy, const unsigned char *use, int n, fr_gmm2 *g) {
    double *v = malloc(sizeof(double) * (size_t)(n + 1));
    if (!v) return 0;
    double med[2], mad[2];
    int m = 0;
    for (int a = 0; a < 2; a++) {
        m = 0;
        for (int i = 0; i < n; i++)
            if (!use || use[i]) v[m++] = xy[2 * i + a];
        if (m < 3) {
            free(v);
            return 0;
        }
        med[a] = median_of(v, m);
        for (int i = 0; i < m; i++) v[i] = fabs(v[i] - med[a]);
        mad[a] = 1.4826 * median_of(v, m);
        if (mad[a] < 0.5) mad[a] = 0.5;
    }
    free(v);
    double sxx = 0, sxy = 0, syy = 0, sw = 0;
    for (int i = 0; i < n; i++) {
        if (use && !use[i]) continue;
        double dx = xy[2 * i] - med[0], dy = xy[2 * i + 1] - med[1];
        if (fabs(dx) > 3 * mad[0] || fabs(dy) > 3 * mad[1]) continue;
        sxx += dx * dx, sxy += dx * dy, syy += dy * dy, sw += 1;
    }
    double rho = sw > 2 && sxx > 0 && syy > 0 ? sxy / sqrt(sxx * syy) : 0.0;
    if (rho > 0.95) rho = 0.95;
    if (rho < -0.95) rho = -0.95;
    g->k = 1;
    g->w[0] = 1.0;
    g->mu[0][0] = med[0], g->mu[0][1] = med[1];
    g->cov[0][0] = mad[0] * mad[0], g->cov[0][1] = rho * mad[0] * mad[1], g->cov[0][2] = mad[1] * mad[1];
    return m;
}

void fr_gmm2_split(fr_gmm2 *g, int j) {
    if (g->k >= FR_GMM_MAX || j < 0 || j >= g->k) return;
    double a = g->cov[j][0], b = g->cov[j][1], c = g->cov[j][2];
    double tr = 0.5 * (a + c), det = a * c - b * b, disc = sqrt(fmax(0.0, tr * tr - det));
    double l1 = tr + disc; /* larger eigenvalue */
    double ex = b, ey = l1 - a;
    if (fabs(ex) + fabs(ey) < 1e-12) ex = 1, ey = 0;
    if (a < c && fabs(b) < 1e-12) ex = 0, ey = 1;
    double len = sqrt(ex * ex + ey * ey), s = sqrt(fmax(l1, 1e-12));
    ex /= len, ey /= len;
    int k = g->k++;
    g->w[j] *= 0.5;
    g->w[k] = g->w[j];
    memcpy(g->cov[k], g->cov[j], sizeof g->cov[j]);
    g->mu[k][0] = g->mu[j][0] - s * ex, g->mu[k][1] = g->mu[j][1] - s * ey;
    g->mu[j][0] += s * ex, g->mu[j][1] += s * ey;
    /* each half is narrower along the split axis */
    for (int q = 0; q < 2; q++) {
        int i = q ? k : j;
        double shrink = 0.75 * l1;
        g->cov[i][0] -= shrink * ex * ex, g->cov[i][1] -= shrink * ex * ey, g->cov[i][2] -= shrink * ey * ey;
    }
}

double fr_gmm2_mahalanobis2(const fr_gmm2 *g, int j, double x, double y) {
    double a = g->cov[j][0], b = g->cov[j][1], c = g->cov[j][2], det = a * c - b * b;
    double dx = x - g->mu[j][0], dy = y - g->mu[j][1];
    return (c * dx * dx - 2 * b * dx * dy + a * dy * dy) / det;
}

static double component_density(const fr_gmm2 *g, int j, double x, double y) {
    double det = g->cov[j][0] * g->cov[j][2] - g->cov[j][1] * g->cov[j][1];
    return exp(-0.5 * fr_gmm2_mahalanobis2(g, j, x, y)) / (TWO_PI * sqrt(det));
}

double fr_gmm2_density(const fr_gmm2 *g, double x, double y) {
    double p = 0;
    for (int j = 0; j < g->k; j++) p += g->w[j] * component_density(g, j, x, y);
    return p;
}

/* Keep the covariance positive definite with at least 'floor' variance along any axis. */
static void regularize(double cov[3], double floor) {
    double a = cov[0], b = cov[1], c = cov[2];
    double tr = 0.5 * (a + c), disc = sqrt(fmax(0.0, tr * tr - (a * c - b * b)));
    double l2 = tr - disc;
    if (l2 < floor) cov[0] += floor - l2, cov[2] += floor - l2;
}

void fr_gmm2_em(fr_gmm2 *g, const double *xy, const unsigned char *use, int n, int iterations, double floor) {
    for (int it = 0; it < iterations; it++) {
        double sw[FR_GMM_MAX] = {0}, sx[FR_GMM_MAX][2] = {{0}}, sc[FR_GMM_MAX][3] = {{0}};
        for (int i = 0; i < n; i++) {
            if (use && !use[i]) continue;
            double x = xy[2 * i], y = xy[2 * i + 1], r[FR_GMM_MAX], tot = 0;
            for (int j = 0; j < g->k; j++) tot += r[j] = g->w[j] * component_density(g, j, x, y);
            if (!(tot > 1e-300)) {
                /* far from everything: give it to the nearest component */
                int best = 0;
                double bd = INFINITY;
                for (int j = 0; j < g->k; j++) {
                    double d = fr_gmm2_mahalanobis2(g, j, x, y);
                    if (d < bd) bd = d, best = j;
                }
                for (int j = 0; j < g->k; j++) r[j] = j == best;
                tot = 1;
            }
            for (int j = 0; j < g->k; j++) {
                double q = r[j] / tot;
                sw[j] += q, sx[j][0] += q * x, sx[j][1] += q * y;
                sc[j][0] += q * x * x, sc[j][1] += q * x * y, sc[j][2] += q * y * y;
            }
        }
        double total = 0;
        for (int j = 0; j < g->k; j++) total += sw[j];
        if (!(total > 0)) return;
        for (int j = 0; j < g->k; j++) {
            if (sw[j] < 1e-9 * total + 1e-12) continue; /* an empty component keeps its place */
            double mx = sx[j][0] / sw[j], my = sx[j][1] / sw[j];
            g->w[j] = sw[j] / total;
            g->mu[j][0] = mx, g->mu[j][1] = my;
            g->cov[j][0] = sc[j][0] / sw[j] - mx * mx;
            g->cov[j][1] = sc[j][1] / sw[j] - mx * my;
            g->cov[j][2] = sc[j][2] / sw[j] - my * my;
            regularize(g->cov[j], floor);
        }
        double ws = 0;
        for (int j = 0; j < g->k; j++) ws += g->w[j];
        for (int j = 0; j < g->k; j++) g->w[j] /= ws;
    }
}
