/* Laplacian deformation toward point constraints: the normal equations
 *     (smooth Q + tikhonov M + sum_c w_c b_c b_c^T) u = sum_c w_c b_c r_c^T
 * in one fixed sparse pattern (that of Q, which holds every pair of vertices sharing a
 * triangle), so each solve is a numeric refactorization of an analysis made once; the values
 * go to the factor in the pattern's order, without conversion. The factor is multifrontal
 * (sparse/frontal.h, dense loops over small fronts): refactored for every solve (the
 * constraints change), a face-sized system (9,409 vertices) factors and solves in about 60% of
 * CHOLMOD's simplicial time, which was itself faster than its supernodal one at this size. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "mesh/laplacian.h"
#include "mesh/laplacian_deform.h"
#include "sparse/frontal.h"

struct fr_lap_system {
    int nv, nt, order;
    const int32_t *tris;
    fr_csr Q;           /* of the current rest shape */
    double *mass;
    long *lower;        /* per CSR entry: its index among the entries with col <= row, or -1 */
    long *diag;         /* per vertex: the index of its diagonal among those */
    size_t n_lower;
    fr_frontal *an;     /* the pattern's analysis */
};

struct fr_lap_solver {
    const fr_lap_system *sys;
    double *values;     /* the lower entries' values */
    fr_frontal_factor *ch;
    double *rhs;        /* nv x 3, column-major */
};

static frig_status operators(frig_ctx *ctx, int nv, const int32_t *tris, int nt, const float *xyz, int order,
                             fr_csr *Q, double *mass) {
    if (order == 1) return fr_cotan_laplacian(ctx, nv, xyz, tris, nt, Q, mass);
    fr_csr L;
    frig_status s = fr_cotan_laplacian(ctx, nv, xyz, tris, nt, &L, mass);
    if (s) return s;
    s = fr_bilaplacian(ctx, &L, mass, Q);
    fr_csr_free(&L);
    return s;
}

frig_status fr_lap_system_create(frig_ctx *ctx, int nv, const int32_t *tris, int nt, const float *xyz, int order,
                                 fr_lap_system **out) {
    *out = NULL;
    fr_lap_system *sys = calloc(1, sizeof *sys);
    if (!sys) return fr_nomem(ctx, "a Laplacian deformation");
    sys->nv = nv, sys->nt = nt, sys->tris = tris, sys->order = order == 1 ? 1 : 2;
    sys->mass = malloc(sizeof(double) * ((size_t)nv + 1));
    sys->diag = malloc(sizeof(long) * ((size_t)nv + 1));
    frig_status s = sys->mass && sys->diag ? FRIG_OK : fr_nomem(ctx, "a Laplacian deformation");
    if (!s) s = operators(ctx, nv, tris, nt, xyz, sys->order, &sys->Q, sys->mass);
    if (!s) {
        size_t nnz = (size_t)sys->Q.start[nv];
        sys->lower = malloc(sizeof(long) * (nnz + 1));
        if (!sys->lower) s = fr_nomem(ctx, "a Laplacian deformation");
        for (int r = 0; r < nv && !s; r++)
            for (int k = sys->Q.start[r]; k < sys->Q.start[r + 1]; k++) {
                sys->lower[k] = sys->Q.col[k] <= r ? (long)sys->n_lower++ : -1;
                if (sys->Q.col[k] == r) sys->diag[r] = sys->lower[k];
            }
    }
    if (!s) s = fr_frontal_create(ctx, &sys->Q, &sys->an);
    if (s) {
        fr_lap_system_free(sys);
        return s;
    }
    *out = sys;
    return FRIG_OK;
}

void fr_lap_system_free(fr_lap_system *sys) {
    if (!sys) return;
    fr_csr_free(&sys->Q);
    fr_frontal_free(sys->an);
    free(sys->mass), free(sys->lower), free(sys->diag);
    free(sys);
}

frig_status fr_lap_system_set_rest(frig_ctx *ctx, fr_lap_system *sys, const float *xyz) {
    fr_csr Q;
    frig_status s = operators(ctx, sys->nv, sys->tris, sys->nt, xyz, sys->order, &Q, sys->mass);
    if (s) return s;
    int nnz = sys->Q.start[sys->nv];
    if (Q.start[sys->nv] != nnz || memcmp(Q.col, sys->Q.col, sizeof(int) * (size_t)nnz) != 0)
        s = fr_error(ctx, FRIG_ERR_INTERNAL, "Laplacian deformation: the rest shape's pattern changed");
    else
        memcpy(sys->Q.x, Q.x, sizeof(double) * (size_t)nnz);
    fr_csr_free(&Q);
    return s;
}

const double *fr_lap_system_mass(const fr_lap_system *sys) { return sys->mass; }

frig_status fr_lap_solver_create(frig_ctx *ctx, const fr_lap_system *sys, fr_lap_solver **out) {
    *out = NULL;
    fr_lap_solver *sv = calloc(1, sizeof *sv);
    if (!sv) return fr_nomem(ctx, "a Laplacian solver");
    sv->sys = sys;
    sv->values = malloc(sizeof(double) * (sys->n_lower + 1));
    sv->rhs = malloc(sizeof(double) * 3 * ((size_t)sys->nv + 1));
    frig_status s = sv->values && sv->rhs ? FRIG_OK : fr_nomem(ctx, "a Laplacian solver");
    if (!s) s = fr_frontal_factor_create(ctx, sys->an, &sv->ch);
    if (s) {
        fr_lap_solver_free(sv);
        return s;
    }
    *out = sv;
    return FRIG_OK;
}

void fr_lap_solver_free(fr_lap_solver *sv) {
    if (!sv) return;
    fr_frontal_factor_free(sv->ch);
    free(sv->values);
    free(sv->rhs);
    free(sv);
}

/* The lower entry of (i, j) (either order), or -1 when the pattern lacks it. */
static long lower_slot(const fr_lap_system *sys, int i, int j) {
    long k = i >= j ? fr_csr_find(&sys->Q, i, j) : fr_csr_find(&sys->Q, j, i);
    return k < 0 ? -1 : sys->lower[k];
}

frig_status fr_lap_solve(frig_ctx *ctx, fr_lap_solver *sv, double smooth, double tikhonov,
                         const fr_lap_constraint *c, int nc, double *u) {
    const fr_lap_system *sys = sv->sys;
    int nv = sys->nv;
    for (int r = 0; r < nv; r++)
        for (int k = sys->Q.start[r]; k < sys->Q.start[r + 1]; k++)
            if (sys->lower[k] >= 0) sv->values[sys->lower[k]] = smooth * sys->Q.x[k];
    /* A vertex of no triangle: keep the matrix definite. */
    for (int v = 0; v < nv; v++) sv->values[sys->diag[v]] += tikhonov * (sys->mass[v] > 0 ? sys->mass[v] : 1.0);
    memset(sv->rhs, 0, sizeof(double) * 3 * (size_t)nv);
    for (int i = 0; i < nc; i++) {
        const fr_lap_constraint *ci = &c[i];
        if (!(ci->w > 0)) continue;
        for (int a = 0; a < 3; a++) {
            if (ci->b[a] == 0) continue;
            for (int b = a; b < 3; b++) {
                if (ci->b[b] == 0) continue;
                long slot = ci->v[a] == ci->v[b] ? sys->diag[ci->v[a]] : lower_slot(sys, ci->v[a], ci->v[b]);
                if (slot < 0)
                    return fr_error(ctx, FRIG_ERR_INTERNAL, "constraint on vertices %d and %d that share no triangle",
                                    ci->v[a], ci->v[b]);
                /* One lower entry stands for (a, b) and (b, a); a repeated vertex takes both. */
                double twice = a != b && ci->v[a] == ci->v[b] ? 2.0 : 1.0;
                sv->values[slot] += twice * ci->w * ci->b[a] * ci->b[b];
            }
            for (int k = 0; k < 3; k++) sv->rhs[(size_t)k * nv + ci->v[a]] += ci->w * ci->b[a] * ci->r[k];
        }
    }
    frig_status s = fr_frontal_factorize(ctx, sv->ch, sv->values);
    if (!s) s = fr_frontal_solve(ctx, sv->ch, 3, sv->rhs, sv->rhs);
    if (s) return s;
    for (int v = 0; v < nv; v++)
        for (int k = 0; k < 3; k++) u[3 * (size_t)v + k] = sv->rhs[(size_t)k * nv + v];
    return FRIG_OK;
}
