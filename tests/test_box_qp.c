/* Bounded QP against brute force: for small random problems, every split of the variables
 * into free / at lower / at upper is tried, and the best KKT point must equal ours. */
#include <stdlib.h>
#include <string.h>

#include <lapacke.h>

#include "core/context.h"
#include "linalg/box_qp.h"
#include "testing.h"

static double objective(int n, const double *H, const double *g, const double *x) {
    double f = 0;
    for (int i = 0; i < n; i++) {
        f += g[i] * x[i];
        for (int j = 0; j < n; j++) f += 0.5 * x[i] * H[i + n * j] * x[j];
    }
    return f;
}

static unsigned long long rng = 88172645463325252ULL;
static double uniform(void) {
    rng ^= rng << 13;
    rng ^= rng >> 7;
    rng ^= rng << 17;
    return (double)(rng >> 11) / 9007199254740992.0;
}

/* Best objective over all assignments (free, lo, hi) whose free solve is feasible. */
static double brute_force(int n, const double *H, const double *g, const double *lo, const double *hi) {
    int combos = 1;
    for (int i = 0; i < n; i++) combos *= 3;
    double best = 1e300;
    for (int c = 0; c < combos; c++) {
        int st[8], code = c, nf = 0, idx[8];
        double x[8], A[64], b[8];
        for (int i = 0; i < n; i++) st[i] = code % 3, code /= 3;
        for (int i = 0; i < n; i++) {
            x[i] = st[i] == 1 ? lo[i] : st[i] == 2 ? hi[i] : 0;
            if (st[i] == 0) idx[nf++] = i;
        }
        if (nf) {
            for (int a = 0; a < nf; a++) {
                b[a] = -g[idx[a]];
                for (int j = 0; j < n; j++)
                    if (st[j]) b[a] -= H[idx[a] + n * j] * x[j];
                for (int bb = 0; bb < nf; bb++) A[a + nf * bb] = H[idx[a] + n * idx[bb]];
            }
            if (LAPACKE_dposv(LAPACK_COL_MAJOR, 'L', nf, 1, A, nf, b, nf)) continue;
            for (int a = 0; a < nf; a++) x[idx[a]] = b[a];
        }
        int ok = 1;
        for (int i = 0; i < n; i++)
            if (x[i] < lo[i] - 1e-12 || x[i] > hi[i] + 1e-12) ok = 0;
        if (ok) {
            double f = objective(n, H, g, x);
            if (f < best) best = f;
        }
    }
    return best;
}

int main(void) {
    frig_ctx *ctx = frig_ctx_create();
    double worst = 0;
    for (int trial = 0; trial < 300; trial++) {
        int n = 1 + trial % 6;
        double B[64], H[64], g[8], lo[8], hi[8], x[8];
        for (int i = 0; i < n * n; i++) B[i] = uniform() * 2 - 1;
        for (int i = 0; i < n; i++)
            for (int j = 0; j < n; j++) {
                double s = i == j ? 0.1 : 0;
                for (int k = 0; k < n; k++) s += B[k + n * i] * B[k + n * j];
                H[i + n * j] = s;
            }
        for (int i = 0; i < n; i++) {
            g[i] = (uniform() * 2 - 1) * 3;
            lo[i] = -uniform();
            hi[i] = uniform();
            if (trial % 5 == 0 && i == 0) lo[i] = -INFINITY, hi[i] = INFINITY; /* an unbounded variable */
            x[i] = 0;
        }
        CHECK(fr_box_qp(ctx, n, H, g, lo, hi, x) == FRIG_OK);
        for (int i = 0; i < n; i++) CHECK(x[i] >= lo[i] && x[i] <= hi[i]);
        double diff = objective(n, H, g, x) - brute_force(n, H, g, lo, hi);
        if (fabs(diff) > worst) worst = fabs(diff);
    }
    printf("bounded QP vs brute force over 300 problems: worst objective difference %.3g\n", worst);
    CHECK(worst < 1e-10);
    frig_ctx_free(ctx);
    return test_result("test_box_qp");
}
