/* A weighted sum of rows added to an accumulator, a few columns at a time in registers
 * (weighted_rows.c). Internal. */
#ifndef FR_LINALG_WEIGHTED_ROWS_H
#define FR_LINALG_WEIGHTED_ROWS_H

/* acc[h] += w[i] rows[i][h] for i < n, the terms added in order of i, h < width: eight sums at a
 * time held in registers over the rows. Every sum the same operations in the same order as the
 * plain loop (no contraction), so the result is that loop's, bit for bit. */
void fr_add_weighted_rows(const double *w, const double *const *rows, int n, int width, double *acc);

#endif
