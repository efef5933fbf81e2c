/* Rigid and similarity alignment of corresponding point sets (Kabsch, Umeyama). */
#include <math.h>

#include <lapacke.h>

#include "mesh/point_align.h"

int fr_point_align(const float *a, const float *b, int n, int with_scale, double R[9], double t[3], double *s) {
    if (n <= 0) return 0;
    double ma[3] = {0, 0, 0}, mb[3] = {0, 0, 0}, M[9] = {0}, var_b = 0;
    for (int v = 0; v < n; v++)
        for (int c = 0; c < 3; c++) ma[c] += a[3 * v + c] / n, mb[c] += b[3 * v + c] / n;
    /* M = sum (b - mb)(a - ma)^T, column-major */
    for (int v = 0; v < n; v++)
        for (int i = 0; i < 3; i++) {
            double bi = b[3 * v + i] - mb[i];
            var_b += bi * bi;
            for (int j = 0; j < 3; j++) M[i + 3 * j] += bi * (a[3 * v + j] - ma[j]);
        }
    double U[9], VT[9], sv[3], super[2];
    if (LAPACKE_dgesvd(LAPACK_COL_MAJOR, 'A', 'A', 3, 3, M, 3, sv, U, 3, VT, 3, super) != 0 || var_b <= 0) return 0;
    /* R = V D U^T maps b onto a; D = diag(1, 1, det(V U^T)) keeps it a rotation. */
    double d = 1;
    for (int pass = 0; pass < 2; pass++) {
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++) {
                double r = 0;
                for (int k = 0; k < 3; k++) r += VT[k + 3 * i] * (k == 2 ? d : 1) * U[j + 3 * k];
                R[3 * i + j] = r;
            }
        double det = R[0] * (R[4] * R[8] - R[5] * R[7]) - R[1] * (R[3] * R[8] - R[5] * R[6]) +
                     R[2] * (R[3] * R[7] - R[4] * R[6]);
        if (det > 0) break;
        d = -1;
    }
    *s = with_scale ? (sv[0] + sv[1] + d * sv[2]) / var_b : 1.0;
    for (int i = 0; i < 3; i++) t[i] = ma[i] - *s * (R[3 * i] * mb[0] + R[3 * i + 1] * mb[1] + R[3 * i + 2] * mb[2]);
    return 1;
}
