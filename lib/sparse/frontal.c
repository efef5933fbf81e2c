/* Supernodal multifrontal Cholesky (Duff & Reid 1983; Liu 1992, "The multifrontal method for
 * sparse matrix solution"): the matrix is permuted by CHOLMOD's AMD ordering and the elimination
 * tree's postorder, columns with the same pattern below them are grouped into supernodes, and
 * each supernode's front (its rows by its rows) gathers the matrix's values and its children's
 * update matrices, factors its columns densely and passes its own update matrix up (a stack, in
 * postorder). Everything that depends on the pattern only is found once; a factorization reads
 * the values, adds, and does dense loops (no BLAS: the fronts of a face mesh are small). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <cholmod.h>

#include "core/context.h"
#include "sparse/frontal.h"

struct fr_frontal {
    int n, ns;
    int *perm;       /* new index -> input index */
    int *sfirst;     /* ns + 1: first column of each supernode (its columns are contiguous) */
    int *rstart;     /* ns + 1: each supernode's rows in rows[] */
    int *rows;       /* its columns first, then the rows below them, ascending */
    int *rel;        /* like rows: for a row below the columns, its place in the parent's rows */
    int *cstart;     /* ns + 1: each supernode's children in child[] */
    int *child;
    size_t *lstart;  /* ns + 1: each supernode's block (rows x columns, column-major) in the factor */
    size_t *ustart;  /* ns: its update matrix's place in the stack */
    size_t *astart;  /* ns + 1: its values in asrc / adst */
    size_t *asrc, *adst;
    size_t nvalues, stack_size, front_size;
    double lnz, flops;
};

struct fr_frontal_factor {
    const fr_frontal *an;
    double *Lx, *front, *stack, *x;
    int nrhs_room;
};

/* ---- analysis ---- */

typedef struct pattern {
    int n;
    int *rp, *ri; /* rows: for row i the columns j < i (new order) */
    int *cp, *ci; /* columns: for column j the rows i > j */
} pattern;

static void pattern_free(pattern *p) { free(p->rp), free(p->ri), free(p->cp), free(p->ci); }

/* The strictly lower pattern of the input's entries er/ec (input indices) in the order iperm. */
static int pattern_make(int n, size_t ne, const int *er, const int *ec, const int *iperm, pattern *p) {
    memset(p, 0, sizeof *p);
    p->n = n;
    p->rp = calloc((size_t)n + 1, sizeof(int)), p->cp = calloc((size_t)n + 1, sizeof(int));
    p->ri = malloc(sizeof(int) * (ne + 1)), p->ci = malloc(sizeof(int) * (ne + 1));
    int *fill = malloc(sizeof(int) * ((size_t)n + 1)), *fill2 = malloc(sizeof(int) * ((size_t)n + 1));
    int ok = p->rp && p->cp && p->ri && p->ci && fill && fill2;
    for (size_t e = 0; e < ne && ok; e++) {
        int a = iperm[er[e]], b = iperm[ec[e]];
        if (a == b) continue;
        p->rp[(a > b ? a : b) + 1]++, p->cp[(a < b ? a : b) + 1]++;
    }
    for (int k = 0; k < n && ok; k++) p->rp[k + 1] += p->rp[k], p->cp[k + 1] += p->cp[k];
    if (ok) memcpy(fill, p->rp, sizeof(int) * (size_t)n), memcpy(fill2, p->cp, sizeof(int) * (size_t)n);
    for (size_t e = 0; e < ne && ok; e++) {
        int a = iperm[er[e]], b = iperm[ec[e]];
        if (a == b) continue;
        int i = a > b ? a : b, j = a < b ? a : b;
        p->ri[fill[i]++] = j;
        p->ci[fill2[j]++] = i;
    }
    free(fill), free(fill2);
    if (!ok) pattern_free(p);
    return ok;
}

/* Elimination tree (Liu's algorithm with path compression). */
static void etree(const pattern *p, int *parent, int *anc) {
    for (int k = 0; k < p->n; k++) {
        parent[k] = anc[k] = -1;
        for (int q = p->rp[k]; q < p->rp[k + 1]; q++)
            for (int r = p->ri[q]; r != -1 && r < k;) {
                int next = anc[r];
                anc[r] = k;
                if (next == -1) parent[r] = k;
                r = next;
            }
    }
}

/* post[k]: the node visited k-th by a depth-first postorder (children in increasing order). */
static int postorder(int n, const int *parent, int *post) {
    int *head = malloc(sizeof(int) * ((size_t)n + 1)), *next = malloc(sizeof(int) * ((size_t)n + 1));
    int *stack = malloc(sizeof(int) * ((size_t)n + 1));
    if (!head || !next || !stack) {
        free(head), free(next), free(stack);
        return 0;
    }
    for (int k = 0; k < n; k++) head[k] = -1;
    for (int k = n - 1; k >= 0; k--)
        if (parent[k] >= 0) next[k] = head[parent[k]], head[parent[k]] = k;
    int done = 0;
    for (int root = 0; root < n; root++) {
        if (parent[root] >= 0) continue;
        int top = 0;
        stack[top++] = root;
        while (top > 0) {
            int v = stack[top - 1];
            if (head[v] >= 0) {
                int c = head[v];
                head[v] = next[c];
                stack[top++] = c;
            } else {
                top--;
                post[done++] = v;
            }
        }
    }
    free(head), free(next), free(stack);
    return done == n;
}

/* The ordering: CHOLMOD's fill-reducing one for this pattern (upper storage, pattern only). */
static int ordering(int n, size_t ne, const int *er, const int *ec, int *perm) {
    if (n <= 0) return 0;
    cholmod_common cc;
    cholmod_start(&cc);
    cc.print = 0, cc.error_handler = NULL, cc.supernodal = CHOLMOD_SIMPLICIAL;
    cholmod_sparse *A = cholmod_allocate_sparse((size_t)n, (size_t)n, ne, 1, 1, 1, CHOLMOD_PATTERN, &cc);
    int ok = A != NULL;
    if (ok) {
        int *p = A->p, *i = A->i;
        for (int c = 0; c <= n; c++) p[c] = 0;
        for (size_t e = 0; e < ne; e++) p[(er[e] > ec[e] ? er[e] : ec[e]) + 1]++;
        for (int c = 0; c < n; c++) p[c + 1] += p[c];
        int *fill = malloc(sizeof(int) * ((size_t)n + 1));
        ok = fill != NULL;
        if (ok) memcpy(fill, p, sizeof(int) * (size_t)n);
        for (size_t e = 0; e < ne && ok; e++) {
            int c = er[e] > ec[e] ? er[e] : ec[e];
            i[fill[c]++] = er[e] < ec[e] ? er[e] : ec[e];
        }
        free(fill);
        A->sorted = 0;
    }
    cholmod_factor *L = ok ? cholmod_analyze(A, &cc) : NULL;
    ok = L && L->Perm;
    if (ok) memcpy(perm, L->Perm, sizeof(int) * (size_t)n);
    cholmod_free_factor(&L, &cc);
    cholmod_free_sparse(&A, &cc);
    cholmod_finish(&cc);
    return ok;
}

static int int_cmp(const void *a, const void *b) {
    int x = *(const int *)a, y = *(const int *)b;
    return (x > y) - (x < y);
}

/* Supernodes, their rows, children and relative indices from the postordered pattern. */
static int supernodes(fr_frontal *an, const pattern *p, const int *parent, int *work) {
    int n = an->n, *count = work, *mark = work + n, *super = work + 2 * n, *pos = work + 3 * n;
    /* column counts from the row subtrees */
    for (int k = 0; k < n; k++) count[k] = 1, mark[k] = -1;
    for (int k = 0; k < n; k++) {
        mark[k] = k;
        for (int q = p->rp[k]; q < p->rp[k + 1]; q++)
            for (int r = p->ri[q]; mark[r] != k; r = parent[r]) mark[r] = k, count[r]++;
    }
    an->sfirst = malloc(sizeof(int) * ((size_t)n + 1));
    if (!an->sfirst) return 0;
    int ns = 0;
    for (int j = 0; j < n; j++) {
        if (!(j > 0 && parent[j - 1] == j && count[j - 1] == count[j] + 1)) an->sfirst[ns++] = j;
        super[j] = ns - 1;
    }
    an->sfirst[ns] = n;
    an->ns = ns;
    size_t total = 0;
    for (int s = 0; s < ns; s++) total += (size_t)count[an->sfirst[s]];
    an->rstart = malloc(sizeof(int) * ((size_t)ns + 1));
    an->rows = malloc(sizeof(int) * (total + 1));
    an->rel = malloc(sizeof(int) * (total + 1));
    an->cstart = calloc((size_t)ns + 2, sizeof(int));
    an->child = malloc(sizeof(int) * ((size_t)ns + 1));
    int *sparent = malloc(sizeof(int) * ((size_t)ns + 1));
    if (!an->rstart || !an->rows || !an->rel || !an->cstart || !an->child || !sparent) {
        free(sparent);
        return 0;
    }
    for (int s = 0; s < ns; s++) {
        int last = an->sfirst[s + 1] - 1;
        sparent[s] = parent[last] >= 0 ? super[parent[last]] : -1;
        if (sparent[s] >= 0) an->cstart[sparent[s] + 2]++;
    }
    for (int s = 0; s < ns; s++) an->cstart[s + 2] += an->cstart[s + 1];
    for (int s = 0; s < ns; s++)
        if (sparent[s] >= 0) an->child[an->cstart[sparent[s] + 1]++] = s;
    for (int k = 0; k < n; k++) mark[k] = -1;
    int ok = 1;
    an->rstart[0] = 0;
    for (int s = 0; s < ns && ok; s++) {
        int f = an->sfirst[s], l = an->sfirst[s + 1] - 1, m = 0, *rows = an->rows + an->rstart[s];
        for (int c = f; c <= l; c++) rows[m++] = c, mark[c] = s;
        for (int c = f; c <= l; c++)
            for (int q = p->cp[c]; q < p->cp[c + 1]; q++)
                if (mark[p->ci[q]] != s) mark[p->ci[q]] = s, rows[m++] = p->ci[q];
        for (int q = an->cstart[s]; q < an->cstart[s + 1]; q++) {
            int k = an->child[q], w = an->sfirst[k + 1] - an->sfirst[k];
            for (int i = an->rstart[k] + w; i < an->rstart[k + 1]; i++)
                if (mark[an->rows[i]] != s) mark[an->rows[i]] = s, rows[m++] = an->rows[i];
        }
        qsort(rows + (l - f + 1), (size_t)(m - (l - f + 1)), sizeof(int), int_cmp);
        ok = m == count[f];
        an->rstart[s + 1] = an->rstart[s] + m;
    }
    /* each child's rows below its columns, placed among its parent's rows */
    for (int s = 0; s < ns && ok; s++) {
        for (int i = an->rstart[s]; i < an->rstart[s + 1]; i++) pos[an->rows[i]] = i - an->rstart[s];
        for (int q = an->cstart[s]; q < an->cstart[s + 1]; q++) {
            int k = an->child[q], w = an->sfirst[k + 1] - an->sfirst[k];
            for (int i = an->rstart[k] + w; i < an->rstart[k + 1]; i++) an->rel[i] = pos[an->rows[i]];
        }
    }
    free(sparent);
    return ok;
}

/* Where each value goes in its supernode's front; the factor's and the stack's layout. */
static int layout(fr_frontal *an, size_t ne, const int *er, const int *ec, int *work) {
    int n = an->n, ns = an->ns, *iperm = work, *super = work + n, *pos = work + 2 * n;
    for (int k = 0; k < n; k++) iperm[an->perm[k]] = k;
    for (int s = 0; s < ns; s++)
        for (int c = an->sfirst[s]; c < an->sfirst[s + 1]; c++) super[c] = s;
    an->astart = calloc((size_t)ns + 2, sizeof(size_t));
    an->asrc = malloc(sizeof(size_t) * (ne + 1)), an->adst = malloc(sizeof(size_t) * (ne + 1));
    an->lstart = malloc(sizeof(size_t) * ((size_t)ns + 1)), an->ustart = malloc(sizeof(size_t) * ((size_t)ns + 1));
    if (!an->astart || !an->asrc || !an->adst || !an->lstart || !an->ustart) return 0;
    for (size_t e = 0; e < ne; e++) {
        int a = iperm[er[e]], b = iperm[ec[e]];
        an->astart[super[a < b ? a : b] + 2]++;
    }
    for (int s = 0; s < ns; s++) an->astart[s + 2] += an->astart[s + 1];
    for (size_t e = 0; e < ne; e++) {
        int a = iperm[er[e]], b = iperm[ec[e]];
        an->asrc[an->astart[super[a < b ? a : b] + 1]++] = e;
    }
    size_t top = 0, lz = 0;
    an->lnz = an->flops = 0;
    for (int s = 0; s < ns; s++) {
        int f = an->sfirst[s], w = an->sfirst[s + 1] - f, m = an->rstart[s + 1] - an->rstart[s], u = m - w;
        for (int i = 0; i < m; i++) pos[an->rows[an->rstart[s] + i]] = i;
        for (size_t q = an->astart[s]; q < an->astart[s + 1]; q++) {
            size_t e = an->asrc[q];
            int a = iperm[er[e]], b = iperm[ec[e]], i = a > b ? a : b, j = a < b ? a : b;
            an->adst[q] = (size_t)pos[i] + (size_t)(j - f) * m;
        }
        if ((size_t)m * m > an->front_size) an->front_size = (size_t)m * m;
        /* the children's updates are the top of the stack (postorder); this one replaces them */
        for (int q = an->cstart[s + 1] - 1; q >= an->cstart[s]; q--) {
            int k = an->child[q], uk = (an->rstart[k + 1] - an->rstart[k]) - (an->sfirst[k + 1] - an->sfirst[k]);
            if (an->ustart[k] + (size_t)uk * uk != top) return 0;
            top = an->ustart[k];
        }
        an->ustart[s] = top;
        top += (size_t)u * u;
        if (top > an->stack_size) an->stack_size = top;
        an->lstart[s] = lz;
        lz += (size_t)m * w;
        for (int k = 0; k < w; k++) {
            double below = m - k - 1;
            an->lnz += below + 1;
            an->flops += below * (below + 3) + 1; /* the column's scaling and its rank-1 update */
        }
    }
    an->lstart[ns] = lz;
    return 1;
}

frig_status fr_frontal_create(frig_ctx *ctx, const fr_csr *lower, fr_frontal **out) {
    *out = NULL;
    int n = lower->rows;
    size_t ne = 0;
    for (int r = 0; r < n; r++)
        for (int k = lower->start[r]; k < lower->start[r + 1]; k++) ne += lower->col[k] <= r;
    fr_frontal *an = calloc(1, sizeof *an);
    int *er = malloc(sizeof(int) * (ne + 1)), *ec = malloc(sizeof(int) * (ne + 1));
    int *amd = malloc(sizeof(int) * ((size_t)n + 1)), *iperm = malloc(sizeof(int) * ((size_t)n + 1));
    int *parent = malloc(sizeof(int) * ((size_t)n + 1)), *work = malloc(sizeof(int) * (4 * (size_t)n + 1));
    int ok = an && er && ec && amd && iperm && parent && work;
    if (ok) {
        an->n = n, an->nvalues = ne;
        an->perm = malloc(sizeof(int) * ((size_t)n + 1));
        ok = an->perm != NULL;
    }
    size_t e = 0;
    for (int r = 0; r < n && ok; r++)
        for (int k = lower->start[r]; k < lower->start[r + 1]; k++)
            if (lower->col[k] <= r) er[e] = r, ec[e++] = lower->col[k];
    pattern p;
    memset(&p, 0, sizeof p);
    int analyzed = ok && ordering(n, ne, er, ec, amd);
    if (analyzed) {
        /* AMD's order, then the postorder of its elimination tree */
        for (int k = 0; k < n; k++) iperm[amd[k]] = k;
        analyzed = pattern_make(n, ne, er, ec, iperm, &p);
        if (analyzed) etree(&p, parent, work);
        pattern_free(&p);
        analyzed = analyzed && postorder(n, parent, work);
        for (int k = 0; k < n && analyzed; k++) an->perm[k] = amd[work[k]];
        for (int k = 0; k < n && analyzed; k++) iperm[an->perm[k]] = k;
        analyzed = analyzed && pattern_make(n, ne, er, ec, iperm, &p);
        if (analyzed) etree(&p, parent, work);
        analyzed = analyzed && supernodes(an, &p, parent, work) && layout(an, ne, er, ec, work);
        pattern_free(&p);
    }
    free(er), free(ec), free(amd), free(iperm), free(parent), free(work);
    if (!analyzed) {
        fr_frontal_free(an);
        return ok ? fr_error(ctx, FRIG_ERR_INTERNAL, "the multifrontal analysis of a %d x %d system failed", n, n)
                  : fr_nomem(ctx, "a multifrontal analysis");
    }
    *out = an;
    return FRIG_OK;
}

void fr_frontal_free(fr_frontal *an) {
    if (!an) return;
    free(an->perm), free(an->sfirst), free(an->rstart), free(an->rows), free(an->rel), free(an->cstart);
    free(an->child), free(an->lstart), free(an->ustart), free(an->astart), free(an->asrc), free(an->adst);
    free(an);
}

void fr_frontal_stats(const fr_frontal *an, double *entries, double *flops) {
    *entries = an->lnz;
    *flops = an->flops;
}

/* ---- factorization ---- */

frig_status fr_frontal_factor_create(frig_ctx *ctx, const fr_frontal *an, fr_frontal_factor **out) {
    *out = NULL;
    fr_frontal_factor *f = calloc(1, sizeof *f);
    if (!f) return fr_nomem(ctx, "a multifrontal factor");
    f->an = an;
    f->Lx = malloc(sizeof(double) * (an->lstart[an->ns] + 1));
    f->front = malloc(sizeof(double) * (an->front_size + 1));
    f->stack = malloc(sizeof(double) * (an->stack_size + 1));
    if (!f->Lx || !f->front || !f->stack) {
        fr_frontal_factor_free(f);
        return fr_nomem(ctx, "a multifrontal factor");
    }
    *out = f;
    return FRIG_OK;
}

void fr_frontal_factor_free(fr_frontal_factor *f) {
    if (!f) return;
    free(f->Lx), free(f->front), free(f->stack), free(f->x);
    free(f);
}

/* The children's update matrices added into front F (m rows) of supernode s. */
static void extend_add(const fr_frontal *an, const double *stack, int s, int m, double *F) {
    for (int q = an->cstart[s]; q < an->cstart[s + 1]; q++) {
        int k = an->child[q], wk = an->sfirst[k + 1] - an->sfirst[k];
        int uk = an->rstart[k + 1] - an->rstart[k] - wk;
        const int *rel = an->rel + an->rstart[k] + wk;
        const double *U = stack + an->ustart[k];
        for (int jj = 0; jj < uk; jj++) {
            double *Fc = F + (size_t)rel[jj] * m;
            const double *Uc = U + (size_t)jj * uk;
            for (int ii = jj; ii < uk; ii++) Fc[rel[ii]] += Uc[ii];
        }
    }
}

/* y[i] -= sum_k c_k[i] c_k[0] for i < len, c_k = cols + ld k (k < nk): four columns at a time. */
static void subtract_products(double *y, int len, const double *cols, size_t ld, int nk) {
    int k = 0;
    for (; k + 4 <= nk; k += 4) {
        const double *c0 = cols + ld * k, *c1 = c0 + ld, *c2 = c1 + ld, *c3 = c2 + ld;
        double l0 = c0[0], l1 = c1[0], l2 = c2[0], l3 = c3[0];
        if (l0 == 0 && l1 == 0 && l2 == 0 && l3 == 0) continue;
        for (int i = 0; i < len; i++) y[i] -= c0[i] * l0 + c1[i] * l1 + c2[i] * l2 + c3[i] * l3;
    }
    for (; k < nk; k++) {
        const double *c = cols + ld * k;
        double l = c[0];
        if (l == 0) continue;
        for (int i = 0; i < len; i++) y[i] -= c[i] * l;
    }
}

/* Dense Cholesky of the front's first w columns (m rows, column-major), column by column from
 * the ones before it: L11 and L21 in place. */
static int factor_columns(double *F, int m, int w) {
    for (int j = 0; j < w; j++) {
        double *cj = F + (size_t)j * m;
        subtract_products(cj + j, m - j, F + j, (size_t)m, j);
        double d = cj[j];
        if (!(d > 0)) return 0;
        double l = sqrt(d), inv = 1.0 / l;
        cj[j] = l;
        for (int i = j + 1; i < m; i++) cj[i] *= inv;
    }
    return 1;
}

/* U = F22 - L21 L21^T (u x u, lower part) from the factored front. */
static void update_matrix(const double *F, int m, int w, double *U) {
    int u = m - w;
    for (int jj = 0; jj < u; jj++) {
        double *Uc = U + (size_t)jj * u;
        memcpy(Uc + jj, F + (size_t)(w + jj) * m + w + jj, sizeof(double) * (size_t)(u - jj));
        subtract_products(Uc + jj, u - jj, F + w + jj, (size_t)m, w);
    }
}

frig_status fr_frontal_factorize(frig_ctx *ctx, fr_frontal_factor *f, const double *values) {
    const fr_frontal *an = f->an;
    double *F = f->front;
    for (int s = 0; s < an->ns; s++) {
        int w = an->sfirst[s + 1] - an->sfirst[s], m = an->rstart[s + 1] - an->rstart[s];
        memset(F, 0, sizeof(double) * (size_t)m * m); /* (one call: cheaper than the lower part column by column) */
        for (size_t q = an->astart[s]; q < an->astart[s + 1]; q++) F[an->adst[q]] += values[an->asrc[q]];
        extend_add(an, f->stack, s, m, F);
        if (!factor_columns(F, m, w))
            return fr_error(ctx, FRIG_ERR_NUMERIC, "sparse system of order %d is not positive definite (column %d)",
                            an->n, an->sfirst[s]);
        memcpy(f->Lx + an->lstart[s], F, sizeof(double) * (size_t)m * w);
        update_matrix(F, m, w, f->stack + an->ustart[s]);
    }
    return FRIG_OK;
}

/* L y = b, then L^T x = y, on nrhs interleaved columns (x[nrhs k + c]): one pass over the factor. */
static inline __attribute__((always_inline)) void solve_interleaved(const fr_frontal_factor *f, int nrhs, double *x) {
    const fr_frontal *an = f->an;
    size_t r = (size_t)nrhs;
    for (int s = 0; s < an->ns; s++) {
        int fc = an->sfirst[s], w = an->sfirst[s + 1] - fc, m = an->rstart[s + 1] - an->rstart[s];
        const int *rows = an->rows + an->rstart[s];
        const double *L = f->Lx + an->lstart[s];
        for (int k = 0; k < w; k++) {
            const double *ck = L + (size_t)k * m;
            double *xk = x + r * (size_t)(fc + k);
            for (size_t c = 0; c < r; c++) xk[c] /= ck[k];
            for (int i = k + 1; i < m; i++) {
                double *xi = x + r * (size_t)rows[i], l = ck[i];
                for (size_t c = 0; c < r; c++) xi[c] -= l * xk[c];
            }
        }
    }
    for (int s = an->ns - 1; s >= 0; s--) {
        int fc = an->sfirst[s], w = an->sfirst[s + 1] - fc, m = an->rstart[s + 1] - an->rstart[s];
        const int *rows = an->rows + an->rstart[s];
        const double *L = f->Lx + an->lstart[s];
        for (int k = w - 1; k >= 0; k--) {
            const double *ck = L + (size_t)k * m;
            double *xk = x + r * (size_t)(fc + k);
            for (int i = k + 1; i < m; i++) {
                const double *xi = x + r * (size_t)rows[i];
                double l = ck[i];
                for (size_t c = 0; c < r; c++) xk[c] -= l * xi[c];
            }
            for (size_t c = 0; c < r; c++) xk[c] /= ck[k];
        }
    }
}

frig_status fr_frontal_solve(frig_ctx *ctx, fr_frontal_factor *f, int nrhs, const double *B, double *X) {
    const fr_frontal *an = f->an;
    size_t n = (size_t)an->n, r = (size_t)nrhs;
    if (nrhs > f->nrhs_room) {
        free(f->x);
        f->x = malloc(sizeof(double) * (n * r + 1));
        f->nrhs_room = f->x ? nrhs : 0;
        if (!f->x) return fr_nomem(ctx, "a multifrontal solve");
    }
    for (size_t c = 0; c < r; c++)
        for (size_t k = 0; k < n; k++) f->x[r * k + c] = B[n * c + (size_t)an->perm[k]];
    if (nrhs == 3)
        solve_interleaved(f, 3, f->x); /* (the deformations' x, y and z: the loops over them unrolled) */
    else
        solve_interleaved(f, nrhs, f->x);
    for (size_t c = 0; c < r; c++)
        for (size_t k = 0; k < n; k++) X[n * c + (size_t)an->perm[k]] = f->x[r * k + c];
    return FRIG_OK;
}
