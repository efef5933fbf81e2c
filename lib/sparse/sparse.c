/* Sparse Cholesky over CHOLMOD: analyze once, factorize when values change, solve many
 * right-hand sides. Each factorization owns its cholmod_common (no shared state). */
#include <stdlib.h>
#include <string.h>

#include <cholmod.h>
#include <omp.h>

#include "core/context.h"
#include "sparse/csr.h"
#include "sparse/sparse.h"

struct fr_cholesky {
    cholmod_common cc;
    cholmod_sparse *M;  /* the factored symmetric matrix (lower storage) */
    cholmod_sparse *A;  /* least squares only: the m x n design matrix */
    cholmod_factor *L;
    cholmod_dense *X, *Y, *E; /* fr_cholesky_solve's solution and cholmod_solve2's workspace, kept */
    int n;
    /* fr_cholesky_create's triplets (positions, in order) and where each lands in M->x, so
     * that a refactorization with the same triplets writes M's values directly, summing
     * duplicates in triplet order as cholmod_triplet_to_sparse does (the same bits) */
    size_t tcount;
    int *ti, *tj;
    size_t *slot;
    unsigned char *first; /* 1: the first triplet of its slot (assigned; later ones added) */
};

frig_status fr_triplets_init(frig_ctx *ctx, fr_triplets *t, int rows, int cols, size_t capacity) {
    memset(t, 0, sizeof *t);
    t->rows = rows;
    t->cols = cols;
    if (capacity < 16) capacity = 16;
    t->i = malloc(sizeof(int) * capacity);
    t->j = malloc(sizeof(int) * capacity);
    t->x = malloc(sizeof(double) * capacity);
    if (!t->i || !t->j || !t->x) {
        fr_triplets_free(t);
        return fr_nomem(ctx, "sparse triplets");
    }
    t->capacity = capacity;
    return FRIG_OK;
}

frig_status fr_triplets_add(frig_ctx *ctx, fr_triplets *t, int i, int j, double x) {
    if (i < 0 || j < 0 || i >= t->rows || j >= t->cols)
        return fr_error(ctx, FRIG_ERR_INTERNAL, "sparse entry (%d, %d) outside %d x %d", i, j, t->rows, t->cols);
    if (t->count == t->capacity) {
        size_t cap = t->capacity * 2;
        int *ni = realloc(t->i, sizeof(int) * cap);
        if (ni) t->i = ni;
        int *nj = realloc(t->j, sizeof(int) * cap);
        if (nj) t->j = nj;
        double *nx = realloc(t->x, sizeof(double) * cap);
        if (nx) t->x = nx;
        if (!ni || !nj || !nx) return fr_nomem(ctx, "sparse triplets");
        t->capacity = cap;
    }
    t->i[t->count] = i;
    t->j[t->count] = j;
    t->x[t->count] = x;
    t->count++;
    return FRIG_OK;
}

void fr_triplets_clear(fr_triplets *t) { t->count = 0; }

void fr_triplets_free(fr_triplets *t) {
    free(t->i);
    free(t->j);
    free(t->x);
    memset(t, 0, sizeof *t);
}

/* Triplets -> compressed column, duplicates summed. stype -1: symmetric, lower stored. */
static cholmod_sparse *to_sparse(const fr_triplets *t, int stype, cholmod_common *cc) {
    cholmod_triplet *T = cholmod_allocate_triplet((size_t)t->rows, (size_t)t->cols, t->count, stype, CHOLMOD_REAL, cc);
    if (!T) return NULL;
    memcpy(T->i, t->i, sizeof(int) * t->count);
    memcpy(T->j, t->j, sizeof(int) * t->count);
    memcpy(T->x, t->x, sizeof(double) * t->count);
    T->nnz = t->count;
    cholmod_sparse *S = cholmod_triplet_to_sparse(T, t->count, cc);
    cholmod_free_triplet(&T, cc);
    return S;
}

static fr_cholesky *cholesky_new(void) {
    fr_cholesky *ch = calloc(1, sizeof *ch);
    if (!ch) return NULL;
    cholmod_start(&ch->cc);
    ch->cc.print = 0;
    ch->cc.error_handler = NULL;
    ch->cc.final_ll = 1; /* LL^T: an indefinite matrix is reported, not silently LDL^T-factored */
    /* supernodes amalgamated more than CHOLMOD's default (4, 16, 48 columns): each supernode's
     * copies run in an OpenMP region of their own (a futex call each, even serially); fewer of
     * them cost less than the explicit zeros they add. The same factors bit for bit (sfs clouds
     * compared), docs/sfs.md "The fourth pass". */
    ch->cc.nrelax[0] = 16, ch->cc.nrelax[1] = 64, ch->cc.nrelax[2] = 192;
    /* Supernodal with BLAS-3 for big systems; CHOLMOD chooses. Keep it deterministic:
     * CHOLMOD's ordering (AMD/METIS) depends only on the pattern. */
    return ch;
}

/* Numeric factorization of ch->M into ch->L, with the status as a sentence. CHOLMOD's own
 * OpenMP loops (copies into the supernodes, 4 threads compiled in) run serially: called from a
 * team of one they started 3 fresh threads per factorization (95k thread starts in an sfs stage
 * at --threads 1), and their results do not depend on the thread count (BLAS does the work). */
static frig_status factor_numeric(frig_ctx *ctx, fr_cholesky *ch) {
    int levels = omp_get_max_active_levels();
    omp_set_max_active_levels(omp_get_active_level());
    cholmod_factorize(ch->M, ch->L, &ch->cc);
    omp_set_max_active_levels(levels);
    if (ch->cc.status == CHOLMOD_NOT_POSDEF)
        return fr_error(ctx, FRIG_ERR_NUMERIC, "sparse system of order %d is not positive definite (column %d)",
                        ch->n, (int)ch->L->minor);
    if (ch->cc.status < CHOLMOD_OK)
        return fr_error(ctx, FRIG_ERR_NUMERIC, "sparse factorization failed (CHOLMOD status %d)", ch->cc.status);
    return FRIG_OK;
}

/* The triplet -> value map of a lower (stype -1) M built from t; left empty (the CHOLMOD path
 * then) when memory is short or M is not sorted and packed. Entries above the diagonal count as
 * their transposes, as cholmod_triplet_to_sparse stores them. */
static void build_slot_map(fr_cholesky *ch, const fr_triplets *t) {
    cholmod_sparse *M = ch->M;
    if (!M->sorted || !M->packed || t->count == 0)
        return;
    const int *Mp = M->p, *Mi = M->i;
    size_t nnz = (size_t)Mp[M->ncol];
    ch->ti = malloc(sizeof(int) * t->count), ch->tj = malloc(sizeof(int) * t->count);
    ch->slot = malloc(sizeof(size_t) * t->count), ch->first = malloc(t->count);
    unsigned char *seen = calloc(nnz + 1, 1);
    int ok = ch->ti && ch->tj && ch->slot && ch->first && seen;
    for (size_t k = 0; k < t->count && ok; k++) {
        int r = t->i[k] > t->j[k] ? t->i[k] : t->j[k], c = t->i[k] > t->j[k] ? t->j[k] : t->i[k];
        int lo = Mp[c], hi = Mp[c + 1] - 1;
        while (lo < hi) { /* the first row index >= r in column c */
            int mid = lo + (hi - lo) / 2;
            if (Mi[mid] < r)
                lo = mid + 1;
            else
                hi = mid;
        }
        if (lo > hi || Mi[lo] != r)
            ok = 0;
        else
            ch->slot[k] = (size_t)lo, ch->first[k] = !seen[lo], seen[lo] = 1;
    }
    free(seen);
    if (ok) {
        memcpy(ch->ti, t->i, sizeof(int) * t->count), memcpy(ch->tj, t->j, sizeof(int) * t->count);
        ch->tcount = t->count;
        return;
    }
    free(ch->ti), free(ch->tj), free(ch->slot), free(ch->first);
    ch->ti = ch->tj = NULL, ch->slot = NULL, ch->first = NULL;
}

static int same_triplets(const fr_cholesky *ch, const fr_triplets *t) {
    return ch->tcount && t->count == ch->tcount && !memcmp(t->i, ch->ti, sizeof(int) * t->count) &&
           !memcmp(t->j, ch->tj, sizeof(int) * t->count);
}

static frig_status analyze_and_factor(frig_ctx *ctx, fr_cholesky *ch) {
    ch->L = cholmod_analyze(ch->M, &ch->cc);
    if (!ch->L) return fr_error(ctx, FRIG_ERR_NO_MEMORY, "sparse analysis of a %d x %d system failed", ch->n, ch->n);
    return factor_numeric(ctx, ch);
}

frig_status fr_cholesky_create(frig_ctx *ctx, const fr_triplets *lower, fr_cholesky **out) {
    *out = NULL;
    if (lower->rows != lower->cols)
        return fr_error(ctx, FRIG_ERR_INTERNAL, "Cholesky of a non-square %d x %d matrix", lower->rows, lower->cols);
    fr_cholesky *ch = cholesky_new();
    if (!ch) return fr_nomem(ctx, "a sparse factorization");
    ch->n = lower->rows;
    ch->M = to_sparse(lower, -1, &ch->cc);
    if (!ch->M) {
        fr_cholesky_free(ch);
        return fr_nomem(ctx, "a sparse matrix");
    }
    build_slot_map(ch, lower);
    frig_status s = analyze_and_factor(ctx, ch);
    if (s) {
        fr_cholesky_free(ch);
        return s;
    }
    *out = ch;
    return FRIG_OK;
}

/* M = lower triangle of A^T A. */
static cholmod_sparse *normal_matrix(cholmod_sparse *A, cholmod_common *cc) {
    cholmod_sparse *At = cholmod_transpose(A, 1, cc);
    if (!At) return NULL;
    cholmod_sparse *AtA = cholmod_aat(At, NULL, 0, 1, cc); /* At * At^T = A^T A, unsymmetric storage */
    cholmod_free_sparse(&At, cc);
    if (!AtA) return NULL;
    cholmod_sparse *M = cholmod_copy(AtA, -1, 1, cc);
    cholmod_free_sparse(&AtA, cc);
    return M;
}

frig_status fr_cholesky_create_lsq(frig_ctx *ctx, const fr_triplets *A, fr_cholesky **out) {
    *out = NULL;
    if (A->rows < A->cols)
        return fr_error(ctx, FRIG_ERR_INTERNAL, "least squares with fewer rows (%d) than unknowns (%d)", A->rows,
                        A->cols);
    fr_cholesky *ch = cholesky_new();
    if (!ch) return fr_nomem(ctx, "a sparse factorization");
    ch->n = A->cols;
    ch->A = to_sparse(A, 0, &ch->cc);
    ch->M = ch->A ? normal_matrix(ch->A, &ch->cc) : NULL;
    if (!ch->M) {
        fr_cholesky_free(ch);
        return fr_nomem(ctx, "a sparse matrix");
    }
    frig_status s = analyze_and_factor(ctx, ch);
    if (s) {
        fr_cholesky_free(ch);
        return s;
    }
    *out = ch;
    return FRIG_OK;
}

frig_status fr_cholesky_refactor(frig_ctx *ctx, fr_cholesky *ch, const fr_triplets *t) {
    cholmod_sparse *M;
    if (ch->A) {
        cholmod_sparse *A = to_sparse(t, 0, &ch->cc);
        if (!A) return fr_nomem(ctx, "a sparse matrix");
        M = normal_matrix(A, &ch->cc);
        cholmod_free_sparse(&ch->A, &ch->cc);
        ch->A = A;
    } else if (same_triplets(ch, t)) {
        double *x = ch->M->x;
        for (size_t k = 0; k < t->count; k++) {
            if (ch->first[k])
                x[ch->slot[k]] = t->x[k];
            else
                x[ch->slot[k]] += t->x[k];
        }
        return factor_numeric(ctx, ch);
    } else {
        ch->tcount = 0; /* other triplets: the map is for the first ones only */
        M = to_sparse(t, -1, &ch->cc);
    }
    if (!M) return fr_nomem(ctx, "a sparse matrix");
    if (M->nrow != ch->M->nrow || M->nzmax != ch->M->nzmax) {
        cholmod_free_sparse(&M, &ch->cc);
        return fr_error(ctx, FRIG_ERR_INTERNAL, "sparse refactorization with a different pattern");
    }
    cholmod_free_sparse(&ch->M, &ch->cc);
    ch->M = M;
    return factor_numeric(ctx, ch);
}

int fr_cholesky_size(const fr_cholesky *ch) { return ch ? ch->n : 0; }

frig_status fr_cholesky_solve(frig_ctx *ctx, fr_cholesky *ch, int nrhs, const double *B, double *X) {
    /* B read in place (CHOLMOD does not write it); the solution and the workspace kept for the
     * next solve of as many columns or fewer (cholmod_solve2), so repeated solves allocate nothing */
    cholmod_dense b = {.nrow = (size_t)ch->n, .ncol = (size_t)nrhs, .nzmax = (size_t)ch->n * (size_t)nrhs,
                       .d = (size_t)ch->n, .x = (void *)B, .xtype = CHOLMOD_REAL, .dtype = CHOLMOD_DOUBLE};
    if (!cholmod_solve2(CHOLMOD_A, ch->L, &b, NULL, &ch->X, NULL, &ch->Y, &ch->E, &ch->cc))
        return ch->cc.status == CHOLMOD_OUT_OF_MEMORY
                   ? fr_nomem(ctx, "a sparse solve")
                   : fr_error(ctx, FRIG_ERR_NUMERIC, "sparse solve failed (CHOLMOD status %d)", ch->cc.status);
    memcpy(X, ch->X->x, sizeof(double) * (size_t)ch->n * (size_t)nrhs);
    return FRIG_OK;
}

frig_status fr_cholesky_solve_lsq(frig_ctx *ctx, fr_cholesky *ch, int nrhs, const double *b, double *X) {
    if (!ch->A) return fr_error(ctx, FRIG_ERR_INTERNAL, "least-squares solve on a plain factorization");
    size_t m = ch->A->nrow;
    cholmod_dense *bd = cholmod_allocate_dense(m, (size_t)nrhs, m, CHOLMOD_REAL, &ch->cc);
    cholmod_dense *rhs = cholmod_zeros((size_t)ch->n, (size_t)nrhs, CHOLMOD_REAL, &ch->cc);
    if (!bd || !rhs) {
        cholmod_free_dense(&bd, &ch->cc);
        cholmod_free_dense(&rhs, &ch->cc);
        return fr_nomem(ctx, "a right-hand side");
    }
    memcpy(bd->x, b, sizeof(double) * m * (size_t)nrhs);
    double one[2] = {1, 0}, zero[2] = {0, 0};
    cholmod_sdmult(ch->A, 1, one, zero, bd, rhs, &ch->cc); /* rhs = A^T b */
    cholmod_free_dense(&bd, &ch->cc);
    cholmod_dense *x = cholmod_solve(CHOLMOD_A, ch->L, rhs, &ch->cc);
    cholmod_free_dense(&rhs, &ch->cc);
    if (!x) return fr_error(ctx, FRIG_ERR_NUMERIC, "sparse solve failed (CHOLMOD status %d)", ch->cc.status);
    memcpy(X, x->x, sizeof(double) * (size_t)ch->n * (size_t)nrhs);
    cholmod_free_dense(&x, &ch->cc);
    return FRIG_OK;
}

frig_status fr_cholesky_create_csr(frig_ctx *ctx, const fr_csr *lower, int simplicial, fr_cholesky **out) {
    *out = NULL;
    int n = lower->rows;
    size_t nnz = 0;
    for (int r = 0; r < n; r++)
        for (int k = lower->start[r]; k < lower->start[r + 1] && lower->col[k] <= r; k++) nnz++;
    fr_cholesky *ch = cholesky_new();
    if (!ch) return fr_nomem(ctx, "a sparse factorization");
    if (simplicial) ch->cc.supernodal = CHOLMOD_SIMPLICIAL;
    ch->n = n;
    /* Row r of the lower triangle, read as column r of the upper: CHOLMOD's stype = 1. */
    ch->M = cholmod_allocate_sparse((size_t)n, (size_t)n, nnz, 1, 1, 1, CHOLMOD_REAL, &ch->cc);
    if (!ch->M) {
        fr_cholesky_free(ch);
        return fr_nomem(ctx, "a sparse matrix");
    }
    int *cp = ch->M->p, *ri = ch->M->i;
    double *x = ch->M->x;
    size_t q = 0;
    for (int r = 0; r < n; r++) {
        cp[r] = (int)q;
        for (int k = lower->start[r]; k < lower->start[r + 1] && lower->col[k] <= r; k++) {
            ri[q] = lower->col[k];
            x[q++] = lower->x[k];
        }
    }
    cp[n] = (int)q;
    frig_status s = analyze_and_factor(ctx, ch);
    if (s) {
        fr_cholesky_free(ch);
        return s;
    }
    *out = ch;
    return FRIG_OK;
}

void fr_cholesky_free(fr_cholesky *ch) {
    if (!ch) return;
    cholmod_free_factor(&ch->L, &ch->cc);
    cholmod_free_sparse(&ch->M, &ch->cc);
    cholmod_free_sparse(&ch->A, &ch->cc);
    cholmod_free_dense(&ch->X, &ch->cc), cholmod_free_dense(&ch->Y, &ch->cc), cholmod_free_dense(&ch->E, &ch->cc);
    cholmod_finish(&ch->cc);
    free(ch->ti), free(ch->tj), free(ch->slot), free(ch->first);
    free(ch);
}
