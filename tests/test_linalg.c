/* Dense linear algebra: least squares against a closed form, SPD and general solves,
 * SVD and eigen-decomposition against known factors. */
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "linalg/linalg.h"
#include "testing.h"

/* Straight-line fit y = a + b x: closed form b = cov(x,y)/var(x), a = mean(y) - b mean(x). */
static void test_line_fit(frig_ctx *ctx) {
    enum { M = 50 };
    double A[M * 2], y[M], x[M];
    srand(3);
    double sx = 0, sy = 0;
    for (int i = 0; i < M; i++) {
        x[i] = i * 0.37 - 4;
        y[i] = 1.5 - 0.75 * x[i] + ((rand() % 1000) / 1000.0 - 0.5) * 0.2;
        A[i] = 1;
        A[M + i] = x[i];
        sx += x[i];
        sy += y[i];
    }
    double mx = sx / M, my = sy / M, cxy = 0, vx = 0;
    for (int i = 0; i < M; i++) cxy += (x[i] - mx) * (y[i] - my), vx += (x[i] - mx) * (x[i] - mx);
    double b = cxy / vx, a = my - b * mx;
    CHECK(fr_lstsq(ctx, M, 2, 1, A, M, y, M) == FRIG_OK);
    CHECK_NEAR(y[0], a, 1e-12);
    CHECK_NEAR(y[1], b, 1e-12);
}

static void test_solves(frig_ctx *ctx) {
    /* SPD: A = B^T B + I with known x. */
    enum { N = 6 };
    double B[N * N], A[N * N], x[N], rhs[N];
    srand(5);
    for (int i = 0; i < N * N; i++) B[i] = (rand() % 2001 - 1000) / 1000.0;
    for (int i = 0; i < N; i++)
        for (int j = 0; j < N; j++) {
            double s = i == j;
            for (int k = 0; k < N; k++) s += B[k + i * N] * B[k + j * N];
            A[i + j * N] = s;
        }
    for (int i = 0; i < N; i++) x[i] = i - 2.5;
    for (int i = 0; i < N; i++) {
        rhs[i] = 0;
        for (int j = 0; j < N; j++) rhs[i] += A[i + j * N] * x[j];
    }
    double A2[N * N], r2[N];
    memcpy(A2, A, sizeof A);
    memcpy(r2, rhs, sizeof rhs);
    CHECK(fr_solve_spd(ctx, N, 1, A, N, rhs, N) == FRIG_OK);
    for (int i = 0; i < N; i++) CHECK_NEAR(rhs[i], x[i], 1e-10);
    CHECK(fr_solve_general(ctx, N, 1, A2, N, r2, N) == FRIG_OK);
    for (int i = 0; i < N; i++) CHECK_NEAR(r2[i], x[i], 1e-10);

    /* Not positive definite: a status, not a crash. */
    double bad[4] = {1, 2, 2, 1}, r[2] = {1, 1};
    CHECK(fr_solve_spd(ctx, 2, 1, bad, 2, r, 2) == FRIG_ERR_NUMERIC);
    CHECK(strstr(frig_ctx_errmsg(ctx), "positive definite") != NULL);
    double sing[4] = {1, 2, 2, 4};
    CHECK(fr_solve_general(ctx, 2, 1, sing, 2, r, 2) == FRIG_ERR_NUMERIC);
}

static void test_svd_eig(frig_ctx *ctx) {
    /* A = U diag(3, 1) V^T with rotations U (3x2 orthonormal) and V. */
    double c = cos(0.3), s = sin(0.3);
    double U[6] = {c, s, 0, -s, c, 0}; /* columns (c,s,0), (-s,c,0) */
    double V[4] = {cos(1.1), sin(1.1), -sin(1.1), cos(1.1)};
    double sv[2] = {3, 1}, A[6];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 2; j++) A[i + 3 * j] = U[i] * sv[0] * V[j] + U[i + 3] * sv[1] * V[j + 2];
    double S[2], Uo[6], VT[4];
    CHECK(fr_svd(ctx, 3, 2, A, 3, S, Uo, VT) == FRIG_OK);
    CHECK_NEAR(S[0], 3, 1e-12);
    CHECK_NEAR(S[1], 1, 1e-12);
    CHECK_NEAR(fabs(Uo[0] * U[0] + Uo[1] * U[1] + Uo[2] * U[2]), 1, 1e-12);

    double E[9] = {2, 1, 0, 1, 2, 0, 0, 0, 5}, w[3];
    CHECK(fr_sym_eig(ctx, 3, E, 3, w) == FRIG_OK);
    CHECK_NEAR(w[0], 1, 1e-12);
    CHECK_NEAR(w[1], 3, 1e-12);
    CHECK_NEAR(w[2], 5, 1e-12);
    double R[9] = {0, 1, 0, -1, 0, 0, 0, 0, 1};
    CHECK_NEAR(fr_det3(R), 1, 1e-15);
}

int main(void) {
    frig_ctx *ctx = frig_ctx_create();
    test_line_fit(ctx);
    test_solves(ctx);
    test_svd_eig(ctx);
    frig_ctx_free(ctx);
    return test_result("test_linalg");
}
