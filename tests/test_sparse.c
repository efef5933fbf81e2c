/* Sparse Cholesky: the 2D Poisson problem against its known solution (second-order
 * convergence), refactorization with new values, many right-hand sides, least squares
 * against the dense solution, and a non-SPD matrix giving a status; the multifrontal factor
 * (sparse/frontal.h) against CHOLMOD's on a grid with diagonals, refactored, and an indefinite
 * matrix giving a status. */
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "linalg/linalg.h"
#include "sparse/csr.h"
#include "sparse/frontal.h"
#include "sparse/sparse.h"
#include "testing.h"

/* -Laplace(u) = f on (0,1)^2, u = 0 on the boundary, u = sin(pi x) sin(pi y),
 * f = 2 pi^2 u; n x n interior grid, 5-point stencil. Returns the max error. */
static double poisson_error(frig_ctx *ctx, int n, double scale, fr_cholesky **keep) {
    double h = 1.0 / (n + 1);
    fr_triplets t;
    fr_triplets_init(ctx, &t, n * n, n * n, (size_t)n * n * 3);
    for (int y = 0; y < n; y++)
        for (int x = 0; x < n; x++) {
            int k = y * n + x;
            fr_triplets_add(ctx, &t, k, k, scale * 4 / (h * h));
            if (x > 0) fr_triplets_add(ctx, &t, k, k - 1, -scale / (h * h));
            if (y > 0) fr_triplets_add(ctx, &t, k, k - n, -scale / (h * h));
        }
    fr_cholesky *ch = *keep;
    frig_status s = ch ? fr_cholesky_refactor(ctx, ch, &t) : fr_cholesky_create(ctx, &t, &ch);
    fr_triplets_free(&t);
    CHECK(s == FRIG_OK);
    if (s) return 1e9;
    double *b = malloc(sizeof(double) * (size_t)n * n * 2);
    for (int y = 0; y < n; y++)
        for (int x = 0; x < n; x++) {
            double u = sin(M_PI * (x + 1) * h) * sin(M_PI * (y + 1) * h);
            b[y * n + x] = scale * 2 * M_PI * M_PI * u;
            b[n * n + y * n + x] = 2 * scale * 2 * M_PI * M_PI * u; /* second right-hand side: 2u */
        }
    CHECK(fr_cholesky_solve(ctx, ch, 2, b, b) == FRIG_OK);
    double err = 0;
    for (int y = 0; y < n; y++)
        for (int x = 0; x < n; x++) {
            double u = sin(M_PI * (x + 1) * h) * sin(M_PI * (y + 1) * h);
            double e1 = fabs(b[y * n + x] - u), e2 = fabs(b[n * n + y * n + x] - 2 * u);
            if (e1 > err) err = e1;
            if (e2 / 2 > err) err = e2 / 2;
        }
    free(b);
    *keep = ch;
    return err;
}

static void test_poisson(frig_ctx *ctx) {
    fr_cholesky *a = NULL, *b = NULL;
    double e1 = poisson_error(ctx, 31, 1.0, &a);
    double e2 = poisson_error(ctx, 63, 1.0, &b);
    printf("Poisson max error: n=31 %.3e, n=63 %.3e, ratio %.2f (second order: ~4)\n", e1, e2, e1 / e2);
    CHECK(e1 < 1.2e-3);
    CHECK(e2 < 3e-4);
    CHECK(e1 / e2 > 3.5 && e1 / e2 < 4.5);
    /* Same pattern, values scaled by 3 (and the right side too): the analysis is reused. */
    double e3 = poisson_error(ctx, 31, 3.0, &a);
    CHECK_NEAR(e3, e1, 1e-9);
    fr_cholesky_free(a);
    fr_cholesky_free(b);
}

static void test_lsq(frig_ctx *ctx) {
    /* Sparse overdetermined problem; compare with the dense QR solution. */
    enum { M = 40, N = 12 };
    double dense[M * N];
    memset(dense, 0, sizeof dense);
    fr_triplets t;
    fr_triplets_init(ctx, &t, M, N, 64);
    srand(11);
    for (int i = 0; i < M; i++) {
        int c1 = i % N, c2 = (i * 7 + 3) % N;
        double v1 = 1 + (rand() % 100) / 50.0, v2 = (rand() % 100) / 100.0 - 0.5;
        fr_triplets_add(ctx, &t, i, c1, v1);
        fr_triplets_add(ctx, &t, i, c2, v2);
        dense[i + M * c1] += v1;
        dense[i + M * c2] += v2;
    }
    double b[M], bd[M], x[N];
    for (int i = 0; i < M; i++) b[i] = bd[i] = sin(i * 0.7) * 3;
    fr_cholesky *ch = NULL;
    CHECK(fr_cholesky_create_lsq(ctx, &t, &ch) == FRIG_OK);
    CHECK(ch && fr_cholesky_solve_lsq(ctx, ch, 1, b, x) == FRIG_OK);
    CHECK(fr_lstsq(ctx, M, N, 1, dense, M, bd, M) == FRIG_OK);
    for (int k = 0; k < N; k++) CHECK_NEAR(x[k], bd[k], 1e-9);
    fr_cholesky_free(ch);
    fr_triplets_free(&t);

    /* Indefinite: a status, not a crash. */
    fr_triplets s;
    fr_triplets_init(ctx, &s, 2, 2, 4);
    fr_triplets_add(ctx, &s, 0, 0, 1);
    fr_triplets_add(ctx, &s, 1, 0, 3);
    fr_triplets_add(ctx, &s, 1, 1, 1);
    fr_cholesky *bad = NULL;
    CHECK(fr_cholesky_create(ctx, &s, &bad) == FRIG_ERR_NUMERIC && bad == NULL);
    fr_triplets_free(&s);
}

/* A 1D chain with repeated entries (several triplets per position, some above the diagonal):
 * refactored with new values it solves bit for bit as a fresh factorization of those values
 * (the refactorization writes the values through its own map, summing repeats in triplet order
 * as CHOLMOD does); other positions still refactor through CHOLMOD. */
static void chain_triplets(frig_ctx *ctx, fr_triplets *t, int n, double scale, int swap) {
    fr_triplets_init(ctx, t, n, n, 16);
    for (int rep = 0; rep < 3; rep++)
        for (int k = 0; k < n; k++) {
            double v = scale * (1.0 + 0.37 * sin(k * 1.3 + rep)) / 3.0;
            fr_triplets_add(ctx, t, k, k, 4 * v + 0.1 * rep);
            if (k + 1 < n) {
                if ((k + rep + swap) % 2)
                    fr_triplets_add(ctx, t, k + 1, k, -v);
                else
                    fr_triplets_add(ctx, t, k, k + 1, -v);
            }
        }
}

static void test_refactor_map(frig_ctx *ctx) {
    enum { N = 200 };
    fr_triplets t1, t2, t3;
    chain_triplets(ctx, &t1, N, 1.0, 0);
    chain_triplets(ctx, &t2, N, 1.7, 0);
    chain_triplets(ctx, &t3, N, 2.3, 1); /* other triplet positions, the same matrix pattern */
    fr_cholesky *a = NULL, *b = NULL, *c = NULL;
    double rhs[N], x[N], y[N], z[N], w[N];
    for (int k = 0; k < N; k++)
        rhs[k] = cos(0.1 * k);
    CHECK(fr_cholesky_create(ctx, &t1, &a) == FRIG_OK);
    CHECK(a && fr_cholesky_refactor(ctx, a, &t2) == FRIG_OK);
    CHECK(a && fr_cholesky_solve(ctx, a, 1, rhs, x) == FRIG_OK);
    CHECK(fr_cholesky_create(ctx, &t2, &b) == FRIG_OK);
    CHECK(b && fr_cholesky_solve(ctx, b, 1, rhs, y) == FRIG_OK);
    CHECK(memcmp(x, y, sizeof x) == 0);
    CHECK(a && fr_cholesky_refactor(ctx, a, &t3) == FRIG_OK);
    CHECK(a && fr_cholesky_solve(ctx, a, 1, rhs, z) == FRIG_OK);
    CHECK(fr_cholesky_create(ctx, &t3, &c) == FRIG_OK);
    CHECK(c && fr_cholesky_solve(ctx, c, 1, rhs, w) == FRIG_OK);
    CHECK(memcmp(z, w, sizeof z) == 0);
    CHECK(a && fr_cholesky_refactor(ctx, a, &t2) == FRIG_OK); /* back to the first positions */
    CHECK(a && fr_cholesky_solve(ctx, a, 1, rhs, z) == FRIG_OK);
    CHECK(memcmp(z, y, sizeof z) == 0);
    double d = 0;
    for (int k = 0; k < N; k++)
        d = fmax(d, fabs(x[k] - w[k]));
    printf("refactor map: bit-identical to fresh factorizations; solutions of the two scales differ by %.3g\n", d);
    CHECK(d > 1e-3);
    fr_cholesky_free(a), fr_cholesky_free(b), fr_cholesky_free(c);
    fr_triplets_free(&t1), fr_triplets_free(&t2), fr_triplets_free(&t3);
}

/* An n x n grid with its diagonals (9-point pattern), values from 'scale'; diagonally dominant
 * when shift > 0, indefinite when shift is very negative. */
static void grid9(frig_ctx *ctx, int n, double scale, double shift, fr_csr *A) {
    fr_triplets t;
    fr_triplets_init(ctx, &t, n * n, n * n, (size_t)n * n * 9);
    for (int y = 0; y < n; y++)
        for (int x = 0; x < n; x++) {
            int k = y * n + x;
            double sum = 0;
            for (int dy = -1; dy <= 1; dy++)
                for (int dx = -1; dx <= 1; dx++) {
                    int xx = x + dx, yy = y + dy;
                    if ((!dx && !dy) || xx < 0 || yy < 0 || xx >= n || yy >= n) continue;
                    int j = yy * n + xx;
                    double v = -scale * (1 + 0.3 * sin(0.7 * (k < j ? k : j) + 1.1 * (k < j ? j : k)));
                    fr_triplets_add(ctx, &t, k, j, v);
                    sum += fabs(v);
                }
            fr_triplets_add(ctx, &t, k, k, sum + shift);
        }
    fr_csr_from_triplets(ctx, &t, A);
    fr_triplets_free(&t);
}

/* The values of A's entries with column <= row, in CSR order. */
static double *lower_values(const fr_csr *A) {
    double *v = malloc(sizeof(double) * ((size_t)A->start[A->rows] + 1));
    size_t q = 0;
    for (int r = 0; r < A->rows; r++)
        for (int k = A->start[r]; k < A->start[r + 1]; k++)
            if (A->col[k] <= r) v[q++] = A->x[k];
    return v;
}

static void test_frontal(frig_ctx *ctx) {
    enum { G = 37, N = G * G };
    fr_csr A, B, C;
    grid9(ctx, G, 1.0, 0.05, &A);
    grid9(ctx, G, 2.5, 1e-3, &B);
    grid9(ctx, G, 1.0, -50, &C);
    fr_frontal *an = NULL;
    fr_frontal_factor *f = NULL;
    CHECK(fr_frontal_create(ctx, &A, &an) == FRIG_OK);
    CHECK(an && fr_frontal_factor_create(ctx, an, &f) == FRIG_OK);
    double *b = malloc(sizeof(double) * 2 * N), *x = malloc(sizeof(double) * 2 * N), *y = malloc(sizeof(double) * 2 * N);
    for (int k = 0; k < 2 * N; k++) b[k] = cos(0.37 * k) + (k >= N);
    double worst = 0;
    const fr_csr *mats[2] = {&A, &B};
    for (int m = 0; m < 2 && f; m++) { /* factor A, then refactor with B's values */
        double *v = lower_values(mats[m]);
        fr_cholesky *ch = NULL;
        CHECK(fr_frontal_factorize(ctx, f, v) == FRIG_OK);
        CHECK(fr_frontal_solve(ctx, f, 2, b, x) == FRIG_OK);
        CHECK(fr_cholesky_create_csr(ctx, mats[m], 1, &ch) == FRIG_OK);
        CHECK(ch && fr_cholesky_solve(ctx, ch, 2, b, y) == FRIG_OK);
        double scale = 0;
        for (int k = 0; k < 2 * N; k++) scale = fmax(scale, fabs(y[k]));
        for (int k = 0; k < 2 * N; k++) worst = fmax(worst, fabs(x[k] - y[k]) / scale);
        memcpy(x, b, sizeof(double) * N); /* the same arrays in and out */
        CHECK(fr_frontal_solve(ctx, f, 1, x, x) == FRIG_OK);
        for (int k = 0; k < N; k++) worst = fmax(worst, fabs(x[k] - y[k]) / scale);
        fr_cholesky_free(ch);
        free(v);
    }
    double entries = 0, flops = 0;
    if (an) fr_frontal_stats(an, &entries, &flops);
    printf("multifrontal: %.0f factor entries, %.3g flops; largest difference from CHOLMOD %.3g (relative)\n", entries,
           flops, worst);
    CHECK(worst < 1e-10);
    double *v = lower_values(&C);
    CHECK(f && fr_frontal_factorize(ctx, f, v) == FRIG_ERR_NUMERIC);
    free(v), free(b), free(x), free(y);
    fr_frontal_factor_free(f);
    fr_frontal_free(an);
    fr_csr_free(&A), fr_csr_free(&B), fr_csr_free(&C);
}

int main(void) {
    frig_ctx *ctx = frig_ctx_create();
    test_poisson(ctx);
    test_lsq(ctx);
    test_refactor_map(ctx);
    test_frontal(ctx);
    frig_ctx_free(ctx);
    return test_result("test_sparse");
}
