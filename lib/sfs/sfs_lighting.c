/* Lighting for shape from shading (paper eq. 5.3-5.5, Algorithm 4 line 11): nine spherical
 * harmonics coefficients per colour channel by least squares, I_c = a_c sum_k l_ck Y_k(n), on
 * the current normals and albedo, made robust to what the model does not explain (cast shadows,
 * highlights, occluders) by iteratively reweighted least squares with Tukey's biweight on the
 * relative residual. The basis is the renderer's (raster/sh_lighting.c).
 * The normals a face shows cover less than a hemisphere, where the constant, z and 3z^2 - 1
 * terms are nearly collinear: a free fit of a frontal face finds a large negative ambient
 * balanced by large first- and second-order terms that explain its pixels and nothing else.
 * So each round first finds the ambient + directional light (the clamped cosine's SH,
 * fr_sh_irradiance_coeffs, non-negative strengths per channel, one direction searched on a
 * sphere of directions and refined) that best explains the pixels, and then fits all nine
 * terms held to it by a ridge of PRIOR_W times the mean diagonal. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "core/select.h"
#include "core/v2d.h"
#include "linalg/linalg.h"
#include "linalg/weighted_rows.h"
#include "sfs/sfs.h"

#define IRLS_ROUNDS 4
#define TUKEY_C 4.685
#define PRIOR_W 0.05
#define DIRECTIONS 400 /* the coarse sphere of light directions */
#define REFINE 3       /* rounds of the local search around the best */

/* The shading for SH basis y (clamped at 0). */
static void shading_at(const double sh[3][FR_SH_COUNT], const double y[FR_SH_COUNT], double S[3]) {
    for (int c = 0; c < 3; c++) {
        double e = 0;
        for (int k = 0; k < FR_SH_COUNT; k++) e += sh[c][k] * y[k];
        S[c] = e > 0 ? e : 0;
    }
}

void fr_sfs_shading(const double sh[3][FR_SH_COUNT], const float n[3], double S[3]) {
    double nd[3] = {n[0], n[1], n[2]}, y[FR_SH_COUNT];
    fr_sh_basis(nd, y);
    shading_at(sh, y, S);
}

enum { NL = FR_SH_COUNT * (FR_SH_COUNT + 1) / 2, /* y y^T's lower triangle, packed */
       NB = FR_SH_COUNT + NL };                   /* a pixel's basis y, then y y^T */

/* Pixel i's SH basis y and the packed y y^T into out (NB). */
static void basis_products(const float *normals, int i, double *out) {
    double nd[3] = {normals[3 * i], normals[3 * i + 1], normals[3 * i + 2]}, *y = out, *yy = out + FR_SH_COUNT;
    fr_sh_basis(nd, y);
    for (int k = 0, h = 0; k < FR_SH_COUNT; k++)
        for (int l = 0; l <= k; l++, h++) yy[h] = y[k] * y[l];
}

/* The basis and its products (basis_products) of every pixel the moments can weigh (in the mask,
 * a positive weight), computed once for the fit's rounds, which reweigh the same pixels: slot[i]
 * its place in the returned array (NB per pixel), -1 for the others. NULL when out of memory (the
 * rounds compute them then). */
static double *basis_cache(int n, const uint8_t *mask, const float *normals, const float *wt, int *slot) {
    int m = 0;
    for (int i = 0; i < n; i++) slot[i] = (!mask || mask[i]) && (!wt || wt[i] > 0) ? m++ : -1;
    double *c = malloc(sizeof(double) * NB * ((size_t)m + 1));
    if (!c) return NULL;
    for (int i = 0; i < n; i++)
        if (slot[i] >= 0) basis_products(normals, i, c + NB * (size_t)slot[i]);
    return c;
}

/* Per channel the weighted moments M = sum w a^2 Y Y^T and b = sum w a I Y. The lower triangle is
 * summed packed (45 running sums per channel, each over the pixels in order), a chunk of pixels
 * at a time (their products y y^T and weights gathered, then each run of sums over the chunk in
 * registers: fr_add_weighted_rows), then unpacked. cache (may be NULL) and slot: basis_cache's. */
static void moments(int n, const uint8_t *mask, const float *I, const float *albedo, const float *normals,
                    const float *wt, const float *robust, const double *cache, const int *slot,
                    double M[3][FR_SH_COUNT * FR_SH_COUNT], double b[3][FR_SH_COUNT]) {
    enum { CHUNK = 32 };
    double L[3][NL], B[3][FR_SH_COUNT];
    double yb[CHUNK][NB], wa2[3][CHUNK], wai[3][CHUNK]; /* the chunk */
    const double *yy_rows[CHUNK], *ys_rows[CHUNK];
    memset(L, 0, sizeof L), memset(B, 0, sizeof B);
    int m = 0;
    for (int i = 0; i <= n; i++) {
        if (m == CHUNK || (i == n && m)) {
            for (int c = 0; c < 3; c++) {
                fr_add_weighted_rows(wai[c], ys_rows, m, FR_SH_COUNT, B[c]);
                fr_add_weighted_rows(wa2[c], yy_rows, m, NL, L[c]);
            }
            m = 0;
        }
        if (i == n) break;
        if (mask && !mask[i]) continue;
        double w = (wt ? wt[i] : 1.0) * (robust ? robust[i] : 1.0);
        if (!(w > 0)) continue;
        const double *y = yb[m];
        if (cache && slot[i] >= 0) y = cache + NB * (size_t)slot[i];
        else basis_products(normals, i, yb[m]);
        ys_rows[m] = y, yy_rows[m] = y + FR_SH_COUNT;
        for (int c = 0; c < 3; c++) {
            double a = albedo[3 * i + c];
            wa2[c][m] = w * a * a, wai[c][m] = w * a * I[3 * i + c];
        }
        m++;
    }
    for (int c = 0; c < 3; c++)
        for (int k = 0, h = 0; k < FR_SH_COUNT; k++) {
            b[c][k] = B[c][k];
            for (int l = 0; l <= k; l++, h++) M[c][k * FR_SH_COUNT + l] = M[c][l * FR_SH_COUNT + k] = L[c][h];
        }
}

static double quad(const double *M, const double *u, const double *v) {
    double s = 0;
    for (int k = 0; k < FR_SH_COUNT; k++)
        for (int l = 0; l < FR_SH_COUNT; l++) s += u[k] * M[k * FR_SH_COUNT + l] * v[l];
    return s;
}

static double dot9(const double *u, const double *v) {
    double s = 0;
    for (int k = 0; k < FR_SH_COUNT; k++) s += u[k] * v[k];
    return s;
}

static const double U[FR_SH_COUNT] = {1.0 / 0.282094791773878, 0, 0, 0, 0, 0, 0, 0, 0};

/* What directional_fit needs of the moments whatever the direction: per channel u^T M u and
 * b^T u of the ambient U; and whether M is finite (then u^T M v sums only U's row: the other
 * terms are zeros, which leave the sum as it is). */
typedef struct moments_u {
    double a11[3], g1[3];
    int finite;
    v2d M01[FR_SH_COUNT * FR_SH_COUNT]; /* channels 0 and 1's M side by side (quad01) */
} moments_u;

static void moments_ambient(const double M[3][FR_SH_COUNT * FR_SH_COUNT], const double b[3][FR_SH_COUNT],
                            moments_u *mu) {
    mu->finite = 1;
    for (int c = 0; c < 3; c++) {
        mu->a11[c] = quad(M[c], U, U), mu->g1[c] = dot9(b[c], U);
        for (int k = 0; k < FR_SH_COUNT * FR_SH_COUNT; k++) mu->finite &= isfinite(M[c][k]) != 0;
    }
    for (int k = 0; k < FR_SH_COUNT * FR_SH_COUNT; k++) mu->M01[k] = (v2d){M[0][k], M[1][k]};
}

/* quad for channels 0 and 1 at once (M01: their M side by side), u0 v0 and u1 v1 their vectors:
 * each lane's sum quad's, term by term. */
static v2d quad01(const v2d *M01, const double *u0, const double *u1, const double *v0, const double *v1) {
    v2d s = {0, 0};
    for (int k = 0; k < FR_SH_COUNT; k++) {
        v2d uk = {u0[k], u1[k]};
        for (int l = 0; l < FR_SH_COUNT; l++) {
            v2d vl = {v0[l], v1[l]};
            s = s + uk * M01[k * FR_SH_COUNT + l] * vl;
        }
    }
    return s;
}

/* u^T M v for u = U (quad's sum, its zero terms left out when M is finite). */
static double quad_u(const double *M, const double *v, int finite) {
    if (!finite) return quad(M, U, v);
    double s = 0;
    for (int l = 0; l < FR_SH_COUNT; l++) s += U[0] * M[l] * v[l];
    return s;
}

/* For light direction d: per channel the non-negative ambient and direct strengths that
 * minimize x^T M x - 2 b^T x with x = amb U + dir K(d); the summed energy, the coefficients. */
static double directional_fit(const double M[3][FR_SH_COUNT * FR_SH_COUNT], const double b[3][FR_SH_COUNT],
                              const moments_u *mu, const double d[3], double sh[3][FR_SH_COUNT]) {
    double K[FR_SH_COUNT], e = 0;
    fr_sh_irradiance_coeffs(d, 1.0, 0.0, K);
    v2d kk = quad01(mu->M01, K, K, K, K); /* channels 0 and 1's K^T M K */
    double a22s[3] = {kk[0], kk[1], quad(M[2], K, K)};
    for (int c = 0; c < 3; c++) {
        double a11 = mu->a11[c], a12 = quad_u(M[c], K, mu->finite), a22 = a22s[c];
        double g1 = mu->g1[c], g2 = dot9(b[c], K), amb = 0, dir = 0;
        double det = a11 * a22 - a12 * a12;
        if (det > 1e-300) amb = (a22 * g1 - a12 * g2) / det, dir = (a11 * g2 - a12 * g1) / det;
        if (!(amb >= 0 && dir >= 0)) {
            /* on the boundary: one of the two alone, the better of the two */
            double amb1 = a11 > 0 ? fmax(0, g1 / a11) : 0, dir2 = a22 > 0 ? fmax(0, g2 / a22) : 0;
            double e1 = a11 * amb1 * amb1 - 2 * g1 * amb1, e2 = a22 * dir2 * dir2 - 2 * g2 * dir2;
            if (e1 <= e2) amb = amb1, dir = 0;
            else amb = 0, dir = dir2;
        }
        for (int k = 0; k < FR_SH_COUNT; k++) sh[c][k] = amb * U[k] + dir * K[k];
    }
    v2d ss = quad01(mu->M01, sh[0], sh[1], sh[0], sh[1]); /* channels 0 and 1's sh^T M sh */
    double q[3] = {ss[0], ss[1], quad(M[2], sh[2], sh[2])};
    for (int c = 0; c < 3; c++) e += q[c] - 2 * dot9(b[c], sh[c]);
    return e;
}

/* The ambient + directional light that explains the moments best (a sphere of directions, then
 * finer and finer caps around the best). */
static void best_directional(const double M[3][FR_SH_COUNT * FR_SH_COUNT], const double b[3][FR_SH_COUNT],
                             double sh[3][FR_SH_COUNT]) {
    double best = INFINITY, bd[3] = {0, 0, -1}, tmp[3][FR_SH_COUNT];
    moments_u mu;
    moments_ambient(M, b, &mu);
    for (int i = 0; i < DIRECTIONS; i++) {
        /* a Fibonacci sphere */
        double z = 1 - (2.0 * i + 1) / DIRECTIONS, r = sqrt(fmax(0, 1 - z * z)), phi = 2.399963229728653 * i;
        double d[3] = {r * cos(phi), r * sin(phi), z};
        double e = directional_fit(M, b, &mu, d, tmp);
        if (e < best) best = e, memcpy(bd, d, sizeof bd);
    }
    double step = 0.15;
    for (int round = 0; round < REFINE; round++, step *= 0.35) {
        double centre[3] = {bd[0], bd[1], bd[2]};
        for (int a = -3; a <= 3; a++)
            for (int c = -3; c <= 3; c++) {
                double d[3] = {centre[0] + a * step / 3 * (fabs(centre[0]) < 0.9), centre[1] + c * step / 3,
                               centre[2] + a * step / 3 * (fabs(centre[0]) >= 0.9)};
                double l = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
                for (int k = 0; k < 3; k++) d[k] /= l;
                double e = directional_fit(M, b, &mu, d, tmp);
                if (e < best) best = e, memcpy(bd, d, sizeof bd);
            }
    }
    directional_fit(M, b, &mu, bd, sh);
}

/* All nine terms per channel, held to the prior by the ridge. */
static frig_status full_fit(frig_ctx *ctx, const double M[3][FR_SH_COUNT * FR_SH_COUNT], const double b[3][FR_SH_COUNT],
                            const double prior[3][FR_SH_COUNT], double sh[3][FR_SH_COUNT]) {
    for (int c = 0; c < 3; c++) {
        double A[FR_SH_COUNT * FR_SH_COUNT], x[FR_SH_COUNT], tr = 0;
        memcpy(A, M[c], sizeof A);
        for (int k = 0; k < FR_SH_COUNT; k++) tr += A[k * FR_SH_COUNT + k];
        double ridge = PRIOR_W * tr / FR_SH_COUNT + 1e-300;
        for (int k = 0; k < FR_SH_COUNT; k++) A[k * FR_SH_COUNT + k] += ridge, x[k] = b[c][k] + ridge * prior[c][k];
        frig_status s = fr_solve_spd(ctx, FR_SH_COUNT, 1, A, FR_SH_COUNT, x, FR_SH_COUNT);
        if (s) return s;
        memcpy(sh[c], x, sizeof x);
    }
    return FRIG_OK;
}

/* Relative residual |I - a S| / |a S| (RMS over the channels) at pixel i; y its SH basis (NULL:
 * computed here). */
static double residual(const double sh[3][FR_SH_COUNT], const float *I, const float *albedo, const float *normals,
                       int i, const double *y) {
    double S[3], num = 0, den = 0;
    if (y) shading_at(sh, y, S);
    else fr_sfs_shading(sh, normals + 3 * (size_t)i, S);
    for (int c = 0; c < 3; c++) {
        double m = albedo[3 * i + c] * S[c], d = I[3 * i + c] - m;
        num += d * d, den += m * m;
    }
    return sqrt(num / fmax(den, 1e-12));
}

frig_status fr_sfs_fit_lighting(frig_ctx *ctx, int n, const uint8_t *mask, const float *I, const float *albedo,
                                const float *normals, const float *weights, double sh[3][FR_SH_COUNT]) {
    float *robust = malloc(sizeof(float) * (size_t)(n + 1)), *r = malloc(sizeof(float) * (size_t)(n + 1));
    double *res = malloc(sizeof(double) * (size_t)(n + 1)); /* each pixel's residual, for its weight */
    double (*M)[FR_SH_COUNT * FR_SH_COUNT] = malloc(sizeof(double) * 3 * FR_SH_COUNT * FR_SH_COUNT);
    int *slot = malloc(sizeof(int) * (size_t)(n + 1));
    double b[3][FR_SH_COUNT], prior[3][FR_SH_COUNT];
    if (!robust || !r || !res || !M || !slot) {
        free(robust), free(r), free(res), free(M), free(slot);
        return fr_nomem(ctx, "the lighting fit");
    }
    for (int i = 0; i < n; i++) robust[i] = 1.0f;
    double *cache = basis_cache(n, mask, normals, weights, slot);
    frig_status s = FRIG_OK;
    for (int round = 0; round < IRLS_ROUNDS && !s; round++) {
        moments(n, mask, I, albedo, normals, weights, robust, cache, slot, M, b);
        best_directional((const double (*)[FR_SH_COUNT * FR_SH_COUNT])M, (const double (*)[FR_SH_COUNT])b, prior);
        s = full_fit(ctx, (const double (*)[FR_SH_COUNT * FR_SH_COUNT])M, (const double (*)[FR_SH_COUNT])b,
                     (const double (*)[FR_SH_COUNT])prior, sh);
        if (s || round == IRLS_ROUNDS - 1) break;
        int m = 0;
        for (int i = 0; i < n; i++) {
            if (mask && !mask[i]) continue;
            res[i] = residual(sh, I, albedo, normals, i, cache && slot[i] >= 0 ? cache + NB * (size_t)slot[i] : NULL);
            r[m++] = (float)res[i];
        }
        if (m < 10) break;
        /* residuals are >= 0: their median as the spread */
        double scale = fmax(1.4826 * fr_select_float(r, (size_t)m, (size_t)m / 2), 0.005);
        for (int i = 0; i < n; i++) {
            if (mask && !mask[i]) continue;
            double u = res[i] / (TUKEY_C * scale);
            robust[i] = u < 1 ? (float)((1 - u * u) * (1 - u * u)) : 0.0f;
        }
    }
    free(robust), free(r), free(res), free(M), free(slot), free(cache);
    return s;
}
