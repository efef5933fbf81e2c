/* A weighted sum of rows added to an accumulator (weighted_rows.h): the shared kernel of the
 * lighting fit's moments and the shared solve's identity assembly. */
#include <string.h>

#include "core/v2d.h"
#include "linalg/weighted_rows.h"

void fr_add_weighted_rows(const double *w, const double *const *rows, int n, int width, double *acc) {
    int h = 0;
    for (; h + 8 <= width; h += 8) {
        v2d a0, a1, a2, a3;
        memcpy(&a0, acc + h, sizeof a0), memcpy(&a1, acc + h + 2, sizeof a1);
        memcpy(&a2, acc + h + 4, sizeof a2), memcpy(&a3, acc + h + 6, sizeof a3);
        for (int i = 0; i < n; i++) {
            const double *x = rows[i] + h;
            v2d c = {w[i], w[i]}, x0, x1, x2, x3;
            memcpy(&x0, x, sizeof x0), memcpy(&x1, x + 2, sizeof x1), memcpy(&x2, x + 4, sizeof x2);
            memcpy(&x3, x + 6, sizeof x3);
            a0 = a0 + c * x0, a1 = a1 + c * x1, a2 = a2 + c * x2, a3 = a3 + c * x3;
        }
        memcpy(acc + h, &a0, sizeof a0), memcpy(acc + h + 2, &a1, sizeof a1);
        memcpy(acc + h + 4, &a2, sizeof a2), memcpy(acc + h + 6, &a3, sizeof a3);
    }
    for (; h < width; h++) {
        double a = acc[h];
        for (int i = 0; i < n; i++) a += w[i] * rows[i][h];
        acc[h] = a;
    }
}
