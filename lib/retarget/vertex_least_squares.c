/* The per-vertex least squares of the neutral and blendshape steps (paper eq. 5.16-5.17 in
 * vertex positions): every vertex has its own small system, all of the same size, whose
 * matrices are sum_i c_iv a_i a_i^T. For a block of vertices they come from one BLAS-3
 * product of the photos' packed outer products with the block's coverage, the right-hand
 * sides from another; each system is then solved by Cholesky (LAPACK). */
#include <stdlib.h>
#include <string.h>

#include <cblas.h>
#include <lapacke.h>
#include <omp.h>

#include "core/context.h"
#include "retarget/retarget.h"

#define BLOCK 64 /* vertices per BLAS-3 block */

frig_status fr_rt_vertex_solve(frig_ctx *ctx, int threads, int nv, int n, int m, const double *A,
                               const float *const *cover, const float *const *targets, const float *sub,
                               const double *reg, const double *prior, double *X) {
    int P = m * (m + 1) / 2;
    double *Z = malloc(sizeof(double) * (size_t)P * ((size_t)n + 1));
    size_t per_thread = (size_t)n * BLOCK + (size_t)P * BLOCK + (size_t)n * 3 * BLOCK + (size_t)m * 3 * BLOCK +
                        (size_t)m * m + (size_t)m * 3;
    double *work = malloc(sizeof(double) * per_thread * (size_t)threads);
    if (!Z || !work) {
        free(Z), free(work);
        return fr_nomem(ctx, "the per-vertex systems");
    }
    /* Z[(a, b), i] = a_i[a] a_i[b] for a >= b, packed column by column (LAPACK's 'L' order). */
    for (int i = 0; i < n; i++) {
        const double *a = A + (size_t)m * i;
        double *z = Z + (size_t)P * i;
        int q = 0;
        for (int c = 0; c < m; c++)
            for (int r = c; r < m; r++) z[q++] = a[r] * a[c];
    }
    int n_blocks = (nv + BLOCK - 1) / BLOCK, failed = 0;
    int saved = fr_blas_serial_begin();
#pragma omp parallel for schedule(dynamic) num_threads(threads)
    for (int blk = 0; blk < n_blocks; blk++) {
        double *C = work + per_thread * (size_t)omp_get_thread_num();
        double *H = C + (size_t)n * BLOCK, *W = H + (size_t)P * BLOCK, *B = W + (size_t)n * 3 * BLOCK;
        double *S = B + (size_t)m * 3 * BLOCK, *rhs = S + (size_t)m * m;
        int v0 = blk * BLOCK, nb = nv - v0 < BLOCK ? nv - v0 : BLOCK;
        /* C (n x nb): coverage; W (n x 3nb): coverage times target. */
        for (int j = 0; j < nb; j++)
            for (int i = 0; i < n; i++) {
                int v = v0 + j;
                double c = cover[i][v];
                C[(size_t)j * n + i] = c;
                for (int k = 0; k < 3; k++) {
                    double y = targets[i][3 * (size_t)v + k] - (sub ? sub[3 * (size_t)v + k] : 0.0f);
                    W[(size_t)(3 * j + k) * n + i] = c * y;
                }
            }
        cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, P, nb, n, 1.0, Z, P, C, n, 0.0, H, P);
        cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, m, 3 * nb, n, 1.0, A, m, W, n, 0.0, B, m);
        for (int j = 0; j < nb; j++) {
            int v = v0 + j, q = 0;
            const double *h = H + (size_t)P * j;
            for (int c = 0; c < m; c++)
                for (int r = c; r < m; r++) {
                    S[(size_t)c * m + r] = h[q];
                    S[(size_t)r * m + c] = h[q++];
                }
            for (int a = 0; a < m; a++) S[(size_t)a * m + a] += reg[a];
            /* rhs (m x 3): columns x, y, z */
            for (int k = 0; k < 3; k++)
                for (int a = 0; a < m; a++)
                    rhs[(size_t)k * m + a] = B[(size_t)(3 * j + k) * m + a] +
                                             (prior ? prior[(size_t)v * m * 3 + (size_t)k * m + a] : 0.0);
            if (LAPACKE_dposv(LAPACK_COL_MAJOR, 'L', m, 3, S, m, rhs, m) != 0) {
                failed = 1;
                continue;
            }
            memcpy(X + (size_t)v * m * 3, rhs, sizeof(double) * (size_t)m * 3);
        }
    }
    fr_blas_serial_end(saved);
    free(Z), free(work);
    if (failed) return fr_error(ctx, FRIG_ERR_NUMERIC, "a per-vertex blendshape system is not positive definite");
    return FRIG_OK;
}
