/* Robust PCA (principal component pursuit, inexact ALM): recovers planted low-rank matrices from
 * sparse gross corruption (the experiment of Lin, Chen, Ma 2010, section 5), leaves a pure
 * low-rank matrix alone, and the Gram-matrix SVT agrees with LAPACK's SVD. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "core/rng.h"
#include "filter/robust_pca.h"
#include "testing.h"

static double fro_diff(size_t count, const double *a, const double *b) {
    double s = 0;
    for (size_t i = 0; i < count; i++) s += (a[i] - b[i]) * (a[i] - b[i]);
    return sqrt(s);
}

static double fro(size_t count, const double *a) {
    double s = 0;
    for (size_t i = 0; i < count; i++) s += a[i] * a[i];
    return sqrt(s);
}

/* L0 = U V^T with U (m x r), V (n x r) standard normal / sqrt(m), S0 with a share 'rate' of entries
 * uniform in [-500, 500] (as in Lin et al.), X = L0 + S0. */
static void plant(uint64_t seed, int m, int n, int r, double rate, double *L0, double *S0, double *X) {
    fr_rng rng;
    fr_rng_seed(&rng, seed);
    double *U = malloc(sizeof(double) * (size_t)(m + n) * r), *V = U + (size_t)m * r;
    for (size_t i = 0; i < (size_t)(m + n) * r; i++) U[i] = fr_rng_normal(&rng) / sqrt((double)m);
    for (int j = 0; j < n; j++)
        for (int i = 0; i < m; i++) {
            double s = 0;
            for (int k = 0; k < r; k++) s += U[i + (size_t)k * m] * V[j + (size_t)k * n];
            L0[i + (size_t)j * m] = s;
        }
    free(U);
    memset(S0, 0, sizeof(double) * (size_t)m * n);
    size_t count = (size_t)(rate * m * n), placed = 0;
    while (placed < count) {
        size_t at = (size_t)fr_rng_below(&rng, (uint64_t)m * n);
        if (S0[at] != 0) continue;
        S0[at] = 1000 * fr_rng_uniform(&rng) - 500;
        placed++;
    }
    for (size_t i = 0; i < (size_t)m * n; i++) X[i] = L0[i] + S0[i];
}

/* Recovery of planted problems over several seeds, ranks and corruption rates. */
static void test_recovery(frig_ctx *ctx) {
    const int m = 200, n = 100;
    size_t mn = (size_t)m * n;
    double *buf = malloc(sizeof(double) * mn * 5);
    double *L0 = buf, *S0 = L0 + mn, *X = S0 + mn, *L = X + mn, *S = L + mn;
    static const struct {
        int rank;
        double rate;
    } cases[] = {{3, 0.05}, {5, 0.05}, {3, 0.10}, {5, 0.10}};
    double worst_l = 0, worst_s = 0;
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++)
        for (uint64_t seed = 1; seed <= 3; seed++) {
            plant(seed * 100 + c, m, n, cases[c].rank, cases[c].rate, L0, S0, X);
            fr_rpca_info info;
            fr_rpca_options o;
            fr_rpca_default_options(&o);
            o.tol = 1e-10; /* relative to ||X||, which S dominates (||S0|| ~ 1000 ||L0||) */
            CHECK(fr_robust_pca(ctx, m, n, X, m, &o, L, S, &info) == FRIG_OK);
            double el = fro_diff(mn, L, L0) / fro(mn, L0), es = fro_diff(mn, S, S0) / fro(mn, S0);
            /* The support of S: every planted entry found, few false entries. */
            long missed = 0, extra = 0;
            for (size_t i = 0; i < mn; i++) {
                missed += S0[i] != 0 && fabs(S[i]) < 1e-6;
                extra += S0[i] == 0 && fabs(S[i]) > 1e-6;
            }
            printf("rank %d, %2.0f%% corrupt, seed %d: ||L-L0||/||L0|| = %.2e, ||S-S0||/||S0|| = %.2e, "
                   "rank(L) %d, %d iterations, support missed %ld extra %ld\n",
                   cases[c].rank, 100 * cases[c].rate, (int)seed, el, es, info.rank, info.iterations, missed,
                   extra);
            CHECK(el < 5e-6);
            CHECK(es < 1e-9);
            CHECK(info.rank == cases[c].rank);
            CHECK(info.residual < 1e-10);
            CHECK(missed == 0);
            CHECK(extra == 0);
            CHECK_NEAR(info.lambda, 1 / sqrt(200.0), 1e-15);
            worst_l = fmax(worst_l, el);
            worst_s = fmax(worst_s, es);
        }
    printf("worst relative errors at tol 1e-10: L %.2e, S %.2e\n", worst_l, worst_s);

    /* A tighter tolerance buys accuracy in proportion. */
    plant(3, m, n, 5, 0.10, L0, S0, X);
    fr_rpca_options o;
    fr_rpca_default_options(&o);
    o.tol = 1e-12;
    CHECK(fr_robust_pca(ctx, m, n, X, m, &o, L, S, NULL) == FRIG_OK);
    double el = fro_diff(mn, L, L0) / fro(mn, L0);
    printf("rank 5, 10%% corrupt, tol 1e-12: ||L-L0||/||L0|| = %.2e\n", el);
    CHECK(el < 1e-7);
    /* The same with LAPACK's SVD inside the thresholding: the same answer. */
    o.svt = FR_SVT_SVD;
    double *L2 = malloc(sizeof(double) * mn);
    CHECK(fr_robust_pca(ctx, m, n, X, m, &o, L2, S, NULL) == FRIG_OK);
    double d = fro_diff(mn, L2, L) / fro(mn, L0);
    printf("SVT by SVD instead of the Gram matrix: ||L_svd - L_gram||/||L0|| = %.2e\n", d);
    CHECK(d < 1e-8);
    free(L2);
    o.svt = FR_SVT_AUTO;

    /* The transposed problem (m < n) takes the other Gram side and gives the transposed answer. */
    plant(77, m, n, 4, 0.08, L0, S0, X);
    double *XT = malloc(sizeof(double) * mn * 3), *LT = XT + mn, *ST = LT + mn;
    for (int j = 0; j < n; j++)
        for (int i = 0; i < m; i++) XT[j + (size_t)i * n] = X[i + (size_t)j * m];
    CHECK(fr_robust_pca(ctx, n, m, XT, n, &o, LT, ST, NULL) == FRIG_OK);
    double e = 0;
    for (int j = 0; j < n; j++)
        for (int i = 0; i < m; i++) e = fmax(e, fabs(LT[j + (size_t)i * n] - L0[i + (size_t)j * m]));
    printf("transposed: max |L - L0| = %.2e\n", e);
    CHECK(e < 1e-8);
    free(XT);
    free(buf);
}

/* A pure low-rank matrix: S stays (nearly) empty and L is X. */
static void test_pure_low_rank(frig_ctx *ctx) {
    const int m = 150, n = 60;
    size_t mn = (size_t)m * n;
    double *buf = malloc(sizeof(double) * mn * 5);
    double *L0 = buf, *S0 = L0 + mn, *X = S0 + mn, *L = X + mn, *S = L + mn;
    plant(9, m, n, 4, 0.0, L0, S0, X);
    fr_rpca_info info;
    CHECK(fr_robust_pca(ctx, m, n, X, m, NULL, L, S, &info) == FRIG_OK);
    double es = fro(mn, S) / fro(mn, X), el = fro_diff(mn, L, X) / fro(mn, X);
    printf("pure low rank: ||S||/||X|| = %.2e, ||L-X||/||X|| = %.2e, nonzeros of S %ld, rank %d\n", es, el,
           info.nonzeros, info.rank);
    CHECK(es < 1e-7);
    CHECK(el < 1e-7);
    CHECK(info.rank == 4);

    /* Zero in, zero out (no division by zero). */
    memset(X, 0, sizeof(double) * mn);
    CHECK(fr_robust_pca(ctx, m, n, X, m, NULL, L, S, &info) == FRIG_OK);
    CHECK(fro(mn, L) == 0 && fro(mn, S) == 0);
    free(buf);
}

/* SVT by the Gram matrix equals SVT by LAPACK's SVD, on both orientations; the thresholded
 * singular values are those of the input minus tau (checked through the Frobenius norm). */
static void test_svt(frig_ctx *ctx) {
    const int m = 90, n = 30;
    fr_rng rng;
    fr_rng_seed(&rng, 5);
    double *M = malloc(sizeof(double) * m * n * 4), *A1 = M + m * n, *A2 = A1 + m * n, *MT = A2 + m * n;
    for (int i = 0; i < m * n; i++) M[i] = fr_rng_normal(&rng);
    for (int j = 0; j < n; j++)
        for (int i = 0; i < m; i++) MT[j + i * n] = M[i + j * m];
    int r1, r2;
    double tau = 8.0;
    CHECK(fr_svt(ctx, m, n, M, tau, FR_SVT_SVD, A1, &r1) == FRIG_OK);
    CHECK(fr_svt(ctx, m, n, M, tau, FR_SVT_GRAM, A2, &r2) == FRIG_OK);
    CHECK(r1 == r2 && r1 > 0 && r1 < n);
    double d = fro_diff((size_t)m * n, A1, A2) / fro((size_t)m * n, A1);
    printf("SVT: rank %d of %d, Gram vs SVD relative difference %.2e\n", r1, n, d);
    CHECK(d < 1e-12);
    CHECK(fr_svt(ctx, n, m, MT, tau, FR_SVT_GRAM, A2, &r2) == FRIG_OK);
    double e = 0;
    for (int j = 0; j < n; j++)
        for (int i = 0; i < m; i++) e = fmax(e, fabs(A2[j + i * n] - A1[i + j * m]));
    CHECK(r2 == r1);
    CHECK(e < 1e-12);
    /* A threshold above the spectral norm gives zero. */
    double s_max;
    CHECK(fr_spectral_norm(ctx, m, n, M, &s_max) == FRIG_OK);
    CHECK(fr_svt(ctx, m, n, M, s_max * 1.0001, FR_SVT_AUTO, A1, &r1) == FRIG_OK);
    CHECK(r1 == 0 && fro((size_t)m * n, A1) == 0);
    CHECK(fr_svt(ctx, m, n, M, s_max * 0.999, FR_SVT_AUTO, A1, &r1) == FRIG_OK);
    CHECK(r1 == 1);
    free(M);
}

static void test_arguments(frig_ctx *ctx) {
    double x[4] = {1, 2, 3, 4}, l[4], s[4];
    fr_rpca_options o;
    fr_rpca_default_options(&o);
    o.rho = 1.0;
    CHECK(fr_robust_pca(ctx, 2, 2, x, 2, &o, l, s, NULL) == FRIG_ERR_INVALID_ARGUMENT);
    CHECK(strstr(frig_ctx_errmsg(ctx), "rho") != NULL);
    CHECK(fr_robust_pca(ctx, 2, 2, x, 1, NULL, l, s, NULL) == FRIG_ERR_INVALID_ARGUMENT);
}

int main(void) {
    frig_ctx *ctx = frig_ctx_create();
    test_svt(ctx);
    test_recovery(ctx);
    test_pure_low_rank(ctx);
    test_arguments(ctx);
    frig_ctx_free(ctx);
    return test_result("test_robust_pca");
}
