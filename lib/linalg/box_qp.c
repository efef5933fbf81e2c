/* Bound-constrained convex QP by a primal active-set method (Nocedal & Wright, ch. 16.5),
 * each step a Cholesky solve of the free block. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <lapacke.h>

#include "core/context.h"
#include "linalg/box_qp.h"

enum { FREE = 0, AT_LO = 1, AT_HI = 2 };

/* Solve for the free block: H_FF y_F = -(g_F + H_F,W x_W). */
static int solve_free(int n, const double *H, const double *g, const double *x, const int *state, int *idx,
                      double *Hf, double *rhs, double *y) {
    int nf = 0;
    for (int i = 0; i < n; i++)
        if (state[i] == FREE) idx[nf++] = i;
    for (int a = 0; a < nf; a++) {
        int i = idx[a];
        double r = -g[i];
        for (int j = 0; j < n; j++)
            if (state[j] != FREE) r -= H[i + (size_t)n * j] * x[j];
        rhs[a] = r;
        for (int b = 0; b <= a; b++) Hf[a + (size_t)nf * b] = H[i + (size_t)n * idx[b]];
    }
    if (nf > 0) {
        if (LAPACKE_dposv(LAPACK_COL_MAJOR, 'L', nf, 1, Hf, nf, rhs, nf) != 0) return -1;
    }
    memcpy(y, x, sizeof(double) * (size_t)n);
    for (int a = 0; a < nf; a++) y[idx[a]] = rhs[a];
    return nf;
}

frig_status fr_box_qp(frig_ctx *ctx, int n, const double *H, const double *g, const double *lo, const double *hi,
                      double *x) {
    double *Hf = malloc(sizeof(double) * ((size_t)n * n + 3 * (size_t)n + 1));
    int *state = calloc((size_t)n + 1, sizeof(int)), *idx = malloc(sizeof(int) * ((size_t)n + 1));
    if (!Hf || !state || !idx) {
        free(Hf);
        free(state);
        free(idx);
        return fr_nomem(ctx, "a bounded QP");
    }
    double *rhs = Hf + (size_t)n * n, *y = rhs + n, *grad = y + n;
    for (int i = 0; i < n; i++) {
        if (x[i] <= lo[i]) x[i] = lo[i], state[i] = AT_LO;
        else if (x[i] >= hi[i]) x[i] = hi[i], state[i] = AT_HI;
    }
    frig_status s = FRIG_OK;
    for (int iter = 0; iter < 10 * n + 10; iter++) {
        if (solve_free(n, H, g, x, state, idx, Hf, rhs, y) < 0) {
            s = fr_error(ctx, FRIG_ERR_NUMERIC, "bounded QP: reduced Hessian not positive definite");
            break;
        }
        /* Longest feasible step from x toward y. */
        double alpha = 1;
        int block = -1, block_state = FREE;
        for (int i = 0; i < n; i++) {
            if (state[i] != FREE) continue;
            double d = y[i] - x[i];
            if (d < 0 && y[i] < lo[i]) {
                double a = (lo[i] - x[i]) / d;
                if (a < alpha) alpha = a, block = i, block_state = AT_LO;
            } else if (d > 0 && y[i] > hi[i]) {
                double a = (hi[i] - x[i]) / d;
                if (a < alpha) alpha = a, block = i, block_state = AT_HI;
            }
        }
        for (int i = 0; i < n; i++)
            if (state[i] == FREE) x[i] += alpha * (y[i] - x[i]);
        if (block >= 0) {
            x[block] = block_state == AT_LO ? lo[block] : hi[block];
            state[block] = block_state;
            continue;
        }
        /* At the free block's minimizer: release the bound whose multiplier has the wrong
         * sign the most, or stop. */
        for (int i = 0; i < n; i++) {
            double gi = g[i];
            for (int j = 0; j < n; j++) gi += H[i + (size_t)n * j] * x[j];
            grad[i] = gi;
        }
        int worst = -1;
        double worst_v = 1e-12;
        for (int i = 0; i < n; i++) {
            double v = state[i] == AT_LO ? -grad[i] : state[i] == AT_HI ? grad[i] : 0;
            if (v > worst_v) worst_v = v, worst = i;
        }
        if (worst < 0) break;
        state[worst] = FREE;
    }
    free(Hf);
    free(state);
    free(idx);
    return s;
}
