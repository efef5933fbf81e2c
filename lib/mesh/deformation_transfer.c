/* Deformation transfer by a Poisson solve: per target triangle the gradients of its hat
 * functions, g_k = grad phi_k; the right-hand side of vertex v_k is area_t (T_t - I) g_k for
 * every triangle t around it; the matrix is the target's cotangent stiffness plus the anchors.
 * One factorization (CHOLMOD), all shapes and coordinates as right-hand sides. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "linalg/linalg.h"
#include "mesh/deformation_transfer.h"
#include "mesh/laplacian.h"
#include "sparse/csr.h"

#define ANCHOR_WEIGHT 1e4 /* against cotangent weights of order 1 */
#define FREE_WEIGHT 1e-9  /* keeps the matrix definite when nothing is anchored */

struct fr_dtransfer {
    int nv, nt;
    const int32_t *tris;
    double *rest_inv; /* 9 per triangle: V_rest^-1 of the source (row-major); 0 = degenerate */
    uint8_t *ok;      /* per triangle: the source triangle is not degenerate */
    double *grad;     /* 9 per triangle: area * g_0, g_1, g_2 of the target */
    uint8_t *anchored;
    float *source_rest;
    fr_cholesky *ch;
};

void fr_triangle_frame(const double a[3], const double b[3], const double c[3], double V[9]) {
    double e1[3], e2[3], n[3];
    for (int k = 0; k < 3; k++) e1[k] = b[k] - a[k], e2[k] = c[k] - a[k];
    n[0] = e1[1] * e2[2] - e1[2] * e2[1];
    n[1] = e1[2] * e2[0] - e1[0] * e2[2];
    n[2] = e1[0] * e2[1] - e1[1] * e2[0];
    double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    double s = len > 0 ? 1.0 / sqrt(len) : 0.0;
    for (int k = 0; k < 3; k++) {
        V[3 * k] = e1[k];
        V[3 * k + 1] = e2[k];
        V[3 * k + 2] = n[k] * s;
    }
}

/* Inverse of a 3x3 (row-major); returns 0 when singular. */
static int inverse3(const double m[9], double inv[9]) {
    double det = fr_det3(m);
    if (!(fabs(det) > 1e-300)) return 0;
    inv[0] = (m[4] * m[8] - m[5] * m[7]) / det;
    inv[1] = (m[2] * m[7] - m[1] * m[8]) / det;
    inv[2] = (m[1] * m[5] - m[2] * m[4]) / det;
    inv[3] = (m[5] * m[6] - m[3] * m[8]) / det;
    inv[4] = (m[0] * m[8] - m[2] * m[6]) / det;
    inv[5] = (m[2] * m[3] - m[0] * m[5]) / det;
    inv[6] = (m[3] * m[7] - m[4] * m[6]) / det;
    inv[7] = (m[1] * m[6] - m[0] * m[7]) / det;
    inv[8] = (m[0] * m[4] - m[1] * m[3]) / det;
    return 1;
}

static void mul3(const double a[9], const double b[9], double c[9]) {
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) c[3 * i + j] = a[3 * i] * b[j] + a[3 * i + 1] * b[3 + j] + a[3 * i + 2] * b[6 + j];
}

int fr_deformation_gradient(const double rest[3][3], const double def[3][3], double T[9]) {
    double V0[9], V1[9], inv[9];
    fr_triangle_frame(rest[0], rest[1], rest[2], V0);
    fr_triangle_frame(def[0], def[1], def[2], V1);
    if (!inverse3(V0, inv)) {
        for (int k = 0; k < 9; k++) T[k] = k % 4 == 0;
        return 0;
    }
    mul3(V1, inv, T);
    return 1;
}

/* The gradients of the hat functions of a triangle, times its area: g = E (E^T E)^-1 for the
 * edges E = [e1 e2]; g_0 = -(g_1 + g_2). Returns the area (0 for a degenerate triangle). */
static double hat_gradients(const double p[3][3], double g[9]) {
    double e1[3], e2[3];
    for (int k = 0; k < 3; k++) e1[k] = p[1][k] - p[0][k], e2[k] = p[2][k] - p[0][k];
    double a = e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2], b = e1[0] * e2[0] + e1[1] * e2[1] + e1[2] * e2[2];
    double c = e2[0] * e2[0] + e2[1] * e2[1] + e2[2] * e2[2], det = a * c - b * b;
    if (!(det > 1e-30)) {
        memset(g, 0, sizeof(double) * 9);
        return 0;
    }
    double area = 0.5 * sqrt(det);
    /* (E^T E)^-1 = [c -b; -b a] / det; g_1 = (c e1 - b e2) / det, g_2 = (a e2 - b e1) / det. */
    for (int k = 0; k < 3; k++) {
        double g1 = (c * e1[k] - b * e2[k]) / det, g2 = (a * e2[k] - b * e1[k]) / det;
        g[3 + k] = area * g1;
        g[6 + k] = area * g2;
        g[k] = -area * (g1 + g2);
    }
    return area;
}

static void corners(const float *xyz, const int32_t *v, double p[3][3]) {
    for (int c = 0; c < 3; c++)
        for (int k = 0; k < 3; k++) p[c][k] = xyz[3 * (size_t)v[c] + k];
}

frig_status fr_dtransfer_create(frig_ctx *ctx, int nv, const int32_t *tris, int nt, const float *source_rest,
                                const float *target_rest, const uint8_t *anchored, fr_dtransfer **out) {
    *out = NULL;
    fr_dtransfer *dt = calloc(1, sizeof *dt);
    if (!dt) return fr_nomem(ctx, "a deformation transfer");
    dt->nv = nv, dt->nt = nt, dt->tris = tris;
    dt->rest_inv = malloc(sizeof(double) * 9 * ((size_t)nt + 1));
    dt->ok = calloc((size_t)nt + 1, 1);
    dt->grad = malloc(sizeof(double) * 9 * ((size_t)nt + 1));
    dt->anchored = calloc((size_t)nv + 1, 1);
    dt->source_rest = malloc(sizeof(float) * 3 * ((size_t)nv + 1));
    frig_status s = dt->rest_inv && dt->ok && dt->grad && dt->anchored && dt->source_rest
                        ? FRIG_OK
                        : fr_nomem(ctx, "a deformation transfer");
    if (!s) {
        memcpy(dt->source_rest, source_rest, sizeof(float) * 3 * (size_t)nv);
        if (anchored) memcpy(dt->anchored, anchored, (size_t)nv);
        for (int t = 0; t < nt; t++) {
            double p[3][3], V[9];
            corners(source_rest, tris + 3 * (size_t)t, p);
            fr_triangle_frame(p[0], p[1], p[2], V);
            dt->ok[t] = (uint8_t)inverse3(V, dt->rest_inv + 9 * (size_t)t);
            corners(target_rest, tris + 3 * (size_t)t, p);
            hat_gradients(p, dt->grad + 9 * (size_t)t);
        }
    }
    fr_csr L;
    memset(&L, 0, sizeof L);
    fr_triplets lower;
    memset(&lower, 0, sizeof lower);
    if (!s) s = fr_cotan_laplacian(ctx, nv, target_rest, tris, nt, &L, NULL);
    if (!s) {
        for (int v = 0; v < nv; v++) {
            long d = fr_csr_find(&L, v, v);
            L.x[d] += dt->anchored[v] ? ANCHOR_WEIGHT : FREE_WEIGHT;
        }
        s = fr_triplets_init(ctx, &lower, nv, nv, (size_t)L.start[nv]);
    }
    if (!s) s = fr_csr_lower_triplets(ctx, &L, &lower);
    if (!s) s = fr_cholesky_create(ctx, &lower, &dt->ch);
    fr_csr_free(&L);
    fr_triplets_free(&lower);
    if (s) {
        fr_dtransfer_free(dt);
        return s;
    }
    *out = dt;
    return FRIG_OK;
}

void fr_dtransfer_free(fr_dtransfer *dt) {
    if (!dt) return;
    free(dt->rest_inv);
    free(dt->ok);
    free(dt->grad);
    free(dt->anchored);
    free(dt->source_rest);
    fr_cholesky_free(dt->ch);
    free(dt);
}

frig_status fr_dtransfer_apply(frig_ctx *ctx, fr_dtransfer *dt, int nshapes, const float *source_deltas,
                               const float *anchor_deltas, float *out) {
    int nv = dt->nv, any_anchor = 0;
    for (int v = 0; v < nv; v++) any_anchor |= dt->anchored[v];
    size_t n3 = 3 * (size_t)nv;
    double *rhs = calloc(n3 * (size_t)nshapes + 1, sizeof(double));
    if (!rhs) return fr_nomem(ctx, "a deformation transfer");
    for (int j = 0; j < nshapes; j++) {
        const float *d = source_deltas + n3 * (size_t)j;
        const float *a = (anchor_deltas ? anchor_deltas : source_deltas) + n3 * (size_t)j;
        double *b = rhs + n3 * (size_t)j; /* columns x, y, z of shape j: b[k * nv + v] */
        for (int t = 0; t < dt->nt; t++) {
            if (!dt->ok[t]) continue;
            const int32_t *v = dt->tris + 3 * (size_t)t;
            double def[3][3], V1[9], T[9];
            for (int c = 0; c < 3; c++)
                for (int k = 0; k < 3; k++)
                    def[c][k] = (double)dt->source_rest[3 * (size_t)v[c] + k] + d[3 * (size_t)v[c] + k];
            fr_triangle_frame(def[0], def[1], def[2], V1);
            mul3(V1, dt->rest_inv + 9 * (size_t)t, T);
            for (int k = 0; k < 3; k++) T[4 * k] -= 1.0;
            const double *g = dt->grad + 9 * (size_t)t;
            for (int c = 0; c < 3; c++)
                for (int r = 0; r < 3; r++)
                    b[(size_t)r * nv + v[c]] += T[3 * r] * g[3 * c] + T[3 * r + 1] * g[3 * c + 1] + T[3 * r + 2] * g[3 * c + 2];
        }
        for (int v = 0; v < nv; v++)
            if (dt->anchored[v])
                for (int r = 0; r < 3; r++) b[(size_t)r * nv + v] += ANCHOR_WEIGHT * a[3 * (size_t)v + r];
    }
    frig_status s = fr_cholesky_solve(ctx, dt->ch, 3 * nshapes, rhs, rhs);
    for (int j = 0; j < nshapes && !s; j++) {
        const double *b = rhs + n3 * (size_t)j;
        double shift[3] = {0, 0, 0};
        if (!any_anchor) {
            /* Without anchors only the gradients are fixed: give the result the source's mean. */
            const float *d = source_deltas + n3 * (size_t)j;
            for (int v = 0; v < nv; v++)
                for (int r = 0; r < 3; r++) shift[r] += (d[3 * (size_t)v + r] - b[(size_t)r * nv + v]) / nv;
        }
        for (int v = 0; v < nv; v++)
            for (int r = 0; r < 3; r++) out[n3 * (size_t)j + 3 * (size_t)v + r] = (float)(b[(size_t)r * nv + v] + shift[r]);
    }
    free(rhs);
    return s;
}
