/* Compressed sparse rows: the form in which the mesh operators (Laplacians, their products)
 * are built, multiplied and handed to the Cholesky factorization with a fixed pattern, so
 * that a system whose values change every iteration is analyzed once and refactored.
 * Internal. */
#ifndef FR_SPARSE_CSR_H
#define FR_SPARSE_CSR_H

#include "sparse/sparse.h"

typedef struct fr_csr {
    int rows, cols;
    int *start; /* rows + 1 */
    int *col;   /* start[rows] column indices, increasing within a row */
    double *x;
} fr_csr;

/* From triplets: duplicates summed, columns sorted. */
frig_status fr_csr_from_triplets(frig_ctx *ctx, const fr_triplets *t, fr_csr *out);
frig_status fr_csr_copy(frig_ctx *ctx, const fr_csr *a, fr_csr *out);
void fr_csr_free(fr_csr *a);

/* y = A x (x: cols values, y: rows values; may not alias). */
void fr_csr_mul(const fr_csr *a, const double *x, double *y);

/* C = A diag(d) B (d may be NULL: the identity); A is m x k, B k x n. */
frig_status fr_csr_product(frig_ctx *ctx, const fr_csr *a, const double *d, const fr_csr *b, fr_csr *out);

/* The position of entry (i, j) in x/col, or -1 when it is not in the pattern. */
long fr_csr_find(const fr_csr *a, int i, int j);

/* The entries with i >= j of a square matrix as triplets in row order (the Cholesky input,
 * the same positions in the same order whenever the pattern is the same). t must have been
 * initialized with a square size; it is cleared first. */
frig_status fr_csr_lower_triplets(frig_ctx *ctx, const fr_csr *a, fr_triplets *t);

#endif
