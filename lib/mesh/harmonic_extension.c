/* The harmonic extension of values held on some vertices over the rest of a triangle mesh
 * (harmonic_extension.h): the cotangent Laplacian restricted to the free vertices, factored once
 * (sparse Cholesky), solved for every field's three coordinates at once. */
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "mesh/harmonic_extension.h"
#include "mesh/laplacian.h"
#include "sparse/csr.h"
#include "sparse/sparse.h"

frig_status fr_harmonic_extend(frig_ctx *ctx, int nv, const float *xyz, const int32_t *tris, int nt,
                               const uint8_t *free_vertex, int fields, double ridge, const float *to, float *vals) {
    int *idx = malloc(sizeof(int) * ((size_t)nv + 1)), nu = 0;
    if (!idx) return fr_nomem(ctx, "a harmonic extension");
    for (int v = 0; v < nv; v++) idx[v] = -1;
    for (int t = 0; t < nt; t++)
        for (int c = 0; c < 3; c++) {
            int v = tris[3 * t + c];
            if (free_vertex[v] && idx[v] < 0) idx[v] = nu++;
        }
    fr_csr L;
    memset(&L, 0, sizeof L);
    fr_triplets tr;
    memset(&tr, 0, sizeof tr);
    fr_cholesky *ch = NULL;
    double *B = NULL;
    int cols = 3 * fields;
    frig_status s = nu ? fr_cotan_laplacian(ctx, nv, xyz, tris, nt, &L, NULL) : FRIG_OK;
    if (!s && nu) s = fr_triplets_init(ctx, &tr, nu, nu, (size_t)L.start[nv]);
    if (!s && nu && !(B = calloc((size_t)nu * cols, sizeof(double)))) s = fr_nomem(ctx, "a harmonic extension");
    for (int v = 0; v < nv && !s && nu; v++) {
        if (idx[v] < 0) continue;
        for (int j = 0; to && j < cols; j++) B[(size_t)j * nu + idx[v]] = ridge * to[j];
        for (int k = L.start[v]; k < L.start[v + 1] && !s; k++) {
            int w = L.col[k];
            if (idx[w] >= 0) {
                if (idx[w] <= idx[v]) s = fr_triplets_add(ctx, &tr, idx[v], idx[w], L.x[k] + (w == v ? ridge : 0));
            } else {
                for (int f = 0; f < fields; f++)
                    for (int c = 0; c < 3; c++)
                        B[(size_t)(3 * f + c) * nu + idx[v]] -= L.x[k] * vals[(size_t)f * 3 * nv + 3 * (size_t)w + c];
            }
        }
    }
    if (!s && nu) s = fr_cholesky_create(ctx, &tr, &ch);
    if (!s && nu) s = fr_cholesky_solve(ctx, ch, cols, B, B);
    for (int v = 0; v < nv && !s && nu; v++)
        if (idx[v] >= 0)
            for (int f = 0; f < fields; f++)
                for (int c = 0; c < 3; c++)
                    vals[(size_t)f * 3 * nv + 3 * (size_t)v + c] = (float)B[(size_t)(3 * f + c) * nu + idx[v]];
    fr_cholesky_free(ch);
    fr_triplets_free(&tr);
    fr_csr_free(&L);
    free(B), free(idx);
    return s;
}
