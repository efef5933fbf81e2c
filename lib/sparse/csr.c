/* Compressed sparse rows: built from triplets (counting sort by row, then by column within a
 * row, duplicates summed), products by Gustavson's row-by-row method with a dense marker. */
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "sparse/csr.h"

static frig_status csr_alloc(frig_ctx *ctx, int rows, int cols, size_t nnz, fr_csr *a) {
    memset(a, 0, sizeof *a);
    a->rows = rows;
    a->cols = cols;
    a->start = calloc((size_t)rows + 1, sizeof(int));
    a->col = malloc(sizeof(int) * (nnz + 1));
    a->x = malloc(sizeof(double) * (nnz + 1));
    if (!a->start || !a->col || !a->x) {
        fr_csr_free(a);
        return fr_nomem(ctx, "a sparse matrix");
    }
    return FRIG_OK;
}

void fr_csr_free(fr_csr *a) {
    free(a->start);
    free(a->col);
    free(a->x);
    memset(a, 0, sizeof *a);
}

frig_status fr_csr_from_triplets(frig_ctx *ctx, const fr_triplets *t, fr_csr *out) {
    /* Bucket by column first, then stably by row: rows come out with increasing columns. */
    size_t n = t->count;
    int *by_col = malloc(sizeof(int) * (n + 1)), *cstart = calloc((size_t)t->cols + 1, sizeof(int));
    int *rstart = calloc((size_t)t->rows + 1, sizeof(int)), *order = malloc(sizeof(int) * (n + 1));
    frig_status s = by_col && cstart && rstart && order ? FRIG_OK : fr_nomem(ctx, "a sparse matrix");
    if (!s) {
        for (size_t k = 0; k < n; k++) cstart[t->j[k] + 1]++;
        for (int c = 0; c < t->cols; c++) cstart[c + 1] += cstart[c];
        for (size_t k = 0; k < n; k++) by_col[cstart[t->j[k]]++] = (int)k;
        for (size_t k = 0; k < n; k++) rstart[t->i[k] + 1]++;
        for (int r = 0; r < t->rows; r++) rstart[r + 1] += rstart[r];
        for (size_t q = 0; q < n; q++) {
            int k = by_col[q];
            order[rstart[t->i[k]]++] = k;
        }
        /* rstart[r] is now the end of row r; row r began at the previous row's end. */
        s = csr_alloc(ctx, t->rows, t->cols, n, out);
    }
    if (!s) {
        size_t nnz = 0, q = 0;
        for (int r = 0; r < t->rows; r++) {
            out->start[r] = (int)nnz;
            int last = -1;
            for (; q < (size_t)rstart[r]; q++) {
                int k = order[q];
                if (t->j[k] == last) {
                    out->x[nnz - 1] += t->x[k];
                } else {
                    out->col[nnz] = last = t->j[k];
                    out->x[nnz++] = t->x[k];
                }
            }
        }
        out->start[t->rows] = (int)nnz;
    }
    free(by_col), free(cstart), free(rstart), free(order);
    return s;
}

frig_status fr_csr_copy(frig_ctx *ctx, const fr_csr *a, fr_csr *out) {
    size_t nnz = (size_t)a->start[a->rows];
    frig_status s = csr_alloc(ctx, a->rows, a->cols, nnz, out);
    if (s) return s;
    memcpy(out->start, a->start, sizeof(int) * ((size_t)a->rows + 1));
    memcpy(out->col, a->col, sizeof(int) * nnz);
    memcpy(out->x, a->x, sizeof(double) * nnz);
    return FRIG_OK;
}

void fr_csr_mul(const fr_csr *a, const double *x, double *y) {
    for (int r = 0; r < a->rows; r++) {
        double s = 0;
        for (int k = a->start[r]; k < a->start[r + 1]; k++) s += a->x[k] * x[a->col[k]];
        y[r] = s;
    }
}

frig_status fr_csr_product(frig_ctx *ctx, const fr_csr *a, const double *d, const fr_csr *b, fr_csr *out) {
    memset(out, 0, sizeof *out);
    if (a->cols != b->rows) return fr_error(ctx, FRIG_ERR_INTERNAL, "sparse product of %dx%d and %dx%d", a->rows,
                                            a->cols, b->rows, b->cols);
    int *mark = malloc(sizeof(int) * ((size_t)b->cols + 1)), *list = malloc(sizeof(int) * ((size_t)b->cols + 1));
    double *acc = calloc((size_t)b->cols + 1, sizeof(double));
    if (!mark || !list || !acc) {
        free(mark), free(list), free(acc);
        return fr_nomem(ctx, "a sparse product");
    }
    for (int c = 0; c < b->cols; c++) mark[c] = -1;
    /* Pass 1: the pattern's size. */
    size_t nnz = 0;
    for (int r = 0; r < a->rows; r++)
        for (int p = a->start[r]; p < a->start[r + 1]; p++) {
            int k = a->col[p];
            for (int q = b->start[k]; q < b->start[k + 1]; q++)
                if (mark[b->col[q]] != r) mark[b->col[q]] = r, nnz++;
        }
    frig_status s = csr_alloc(ctx, a->rows, b->cols, nnz, out);
    if (s) {
        free(mark), free(list), free(acc);
        return s;
    }
    for (int c = 0; c < b->cols; c++) mark[c] = -1;
    nnz = 0;
    for (int r = 0; r < a->rows; r++) {
        int n = 0;
        for (int p = a->start[r]; p < a->start[r + 1]; p++) {
            int k = a->col[p];
            double v = a->x[p] * (d ? d[k] : 1.0);
            for (int q = b->start[k]; q < b->start[k + 1]; q++) {
                int c = b->col[q];
                if (mark[c] != r) mark[c] = r, list[n++] = c, acc[c] = 0;
                acc[c] += v * b->x[q];
            }
        }
        /* Sort the row's columns (insertion sort: rows are short). */
        for (int i = 1; i < n; i++)
            for (int j = i; j > 0 && list[j] < list[j - 1]; j--) {
                int tmp = list[j];
                list[j] = list[j - 1];
                list[j - 1] = tmp;
            }
        out->start[r] = (int)nnz;
        for (int i = 0; i < n; i++) {
            out->col[nnz] = list[i];
            out->x[nnz++] = acc[list[i]];
        }
    }
    out->start[a->rows] = (int)nnz;
    free(mark), free(list), free(acc);
    return FRIG_OK;
}

long fr_csr_find(const fr_csr *a, int i, int j) {
    int lo = a->start[i], hi = a->start[i + 1] - 1;
    while (lo <= hi) {
        int mid = (lo + hi) / 2;
        if (a->col[mid] == j) return mid;
        if (a->col[mid] < j) lo = mid + 1;
        else hi = mid - 1;
    }
    return -1;
}

frig_status fr_csr_lower_triplets(frig_ctx *ctx, const fr_csr *a, fr_triplets *t) {
    fr_triplets_clear(t);
    for (int r = 0; r < a->rows; r++)
        for (int k = a->start[r]; k < a->start[r + 1] && a->col[k] <= r; k++) {
            frig_status s = fr_triplets_add(ctx, t, r, a->col[k], a->x[k]);
            if (s) return s;
        }
    return FRIG_OK;
}
