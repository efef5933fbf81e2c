/* Cotangent Laplacian and lumped mass: each triangle adds, for each of its corners, half the
 * cotangent of that corner's angle to the opposite edge's weight, and a third of its area to
 * each corner's mass. Accumulated in triangle order (deterministic). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "mesh/laplacian.h"

frig_status fr_cotan_laplacian(frig_ctx *ctx, int nv, const float *xyz, const int32_t *tris, int nt, fr_csr *L,
                               double *mass) {
    fr_triplets t;
    frig_status s = fr_triplets_init(ctx, &t, nv, nv, 12 * (size_t)nt + (size_t)nv);
    if (s) return s;
    if (mass) memset(mass, 0, sizeof(double) * (size_t)nv);
    for (int v = 0; v < nv && !s; v++) s = fr_triplets_add(ctx, &t, v, v, 0.0);
    for (int f = 0; f < nt && !s; f++) {
        const int32_t *v = tris + 3 * (size_t)f;
        double p[3][3];
        for (int c = 0; c < 3; c++)
            for (int k = 0; k < 3; k++) p[c][k] = xyz[3 * (size_t)v[c] + k];
        double e1[3], e2[3], n[3];
        for (int k = 0; k < 3; k++) e1[k] = p[1][k] - p[0][k], e2[k] = p[2][k] - p[0][k];
        n[0] = e1[1] * e2[2] - e1[2] * e2[1];
        n[1] = e1[2] * e2[0] - e1[0] * e2[2];
        n[2] = e1[0] * e2[1] - e1[1] * e2[0];
        double twice_area = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        if (!(twice_area > 1e-20)) continue;
        if (mass)
            for (int c = 0; c < 3; c++) mass[v[c]] += twice_area / 6;
        for (int c = 0; c < 3; c++) {
            /* The angle at corner c, between the edges to the other two corners. */
            int a = (c + 1) % 3, b = (c + 2) % 3;
            double u[3], w[3];
            for (int k = 0; k < 3; k++) u[k] = p[a][k] - p[c][k], w[k] = p[b][k] - p[c][k];
            double cot = (u[0] * w[0] + u[1] * w[1] + u[2] * w[2]) / twice_area;
            double wgt = 0.5 * cot;
            s = fr_triplets_add(ctx, &t, v[a], v[b], -wgt);
            if (!s) s = fr_triplets_add(ctx, &t, v[b], v[a], -wgt);
            if (!s) s = fr_triplets_add(ctx, &t, v[a], v[a], wgt);
            if (!s) s = fr_triplets_add(ctx, &t, v[b], v[b], wgt);
            if (s) break;
        }
    }
    if (!s) s = fr_csr_from_triplets(ctx, &t, L);
    fr_triplets_free(&t);
    return s;
}

typedef struct edge {
    int a, b;
} edge;

static int edge_cmp(const void *x, const void *y) {
    const edge *e = x, *f = y;
    if (e->a != f->a) return e->a < f->a ? -1 : 1;
    return e->b < f->b ? -1 : e->b > f->b;
}

frig_status fr_mesh_boundary(frig_ctx *ctx, int nv, const int32_t *tris, int nt, uint8_t *boundary) {
    edge *e = malloc(sizeof(edge) * (3 * (size_t)nt + 1));
    if (!e) return fr_nomem(ctx, "mesh edges");
    for (int f = 0; f < nt; f++)
        for (int c = 0; c < 3; c++) {
            int a = tris[3 * (size_t)f + c], b = tris[3 * (size_t)f + (c + 1) % 3];
            e[3 * (size_t)f + c].a = a < b ? a : b;
            e[3 * (size_t)f + c].b = a < b ? b : a;
        }
    size_t ne = 3 * (size_t)nt;
    qsort(e, ne, sizeof(edge), edge_cmp);
    memset(boundary, 0, (size_t)nv);
    for (size_t i = 0; i < ne;) {
        size_t j = i + 1;
        while (j < ne && e[j].a == e[i].a && e[j].b == e[i].b) j++;
        if (j - i == 1) boundary[e[i].a] = boundary[e[i].b] = 1;
        i = j;
    }
    free(e);
    return FRIG_OK;
}

frig_status fr_bilaplacian(frig_ctx *ctx, const fr_csr *L, const double *mass, fr_csr *Q) {
    double *inv = malloc(sizeof(double) * ((size_t)L->rows + 1));
    if (!inv) return fr_nomem(ctx, "the bending operator");
    for (int v = 0; v < L->rows; v++) inv[v] = mass[v] > 0 ? 1.0 / mass[v] : 0.0;
    frig_status s = fr_csr_product(ctx, L, inv, L, Q);
    free(inv);
    return s;
}
