/* The face mesh the retarget stage optimizes (the paper's "medium resolution mesh", ICT's
 * face region): the rig's first nv vertices, the triangles among them, and their rim. */
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "mesh/laplacian.h"
#include "retarget/retarget.h"

frig_status fr_rt_mesh_make(frig_ctx *ctx, int nv, const int32_t *tris, int nt, const float *xyz, fr_rt_mesh *m) {
    m->nv = nv;
    m->nt = 0;
    m->tree = NULL;
    m->shape = malloc(sizeof(float) * 3 * ((size_t)nv + 1));
    m->tris = malloc(sizeof(int32_t) * 3 * ((size_t)nt + 1));
    m->rim = malloc((size_t)nv + 1);
    if (!m->tris || !m->rim || !m->shape) {
        fr_rt_mesh_free(m);
        return fr_nomem(ctx, "the face mesh");
    }
    for (int t = 0; t < nt; t++) {
        const int32_t *v = tris + 3 * (size_t)t;
        if (v[0] >= nv || v[1] >= nv || v[2] >= nv) continue;
        for (int c = 0; c < 3; c++) m->tris[3 * (size_t)m->nt + c] = v[c];
        m->nt++;
    }
    memcpy(m->shape, xyz, sizeof(float) * 3 * (size_t)nv);
    frig_status s = fr_mesh_boundary(ctx, nv, m->tris, m->nt, m->rim);
    if (!s) s = fr_tri_tree_build(ctx, m->shape, m->tris, m->nt, &m->tree);
    if (s) fr_rt_mesh_free(m);
    return s;
}

void fr_rt_mesh_free(fr_rt_mesh *m) {
    fr_tri_tree_free(m->tree);
    free(m->tris);
    free(m->rim);
    free(m->shape);
    m->tree = NULL;
    m->tris = NULL;
    m->rim = NULL;
    m->shape = NULL;
}

#define BLEND_BLOCK 512

void fr_rt_blend(size_t n, const float *base, int K, const double *w, const float *deltas, size_t stride,
                 const int *shape, float *out) {
    double acc[BLEND_BLOCK];
    for (size_t q0 = 0; q0 < n; q0 += BLEND_BLOCK) {
        size_t len = n - q0 < BLEND_BLOCK ? n - q0 : BLEND_BLOCK;
        for (size_t q = 0; q < len; q++) acc[q] = base[q0 + q];
        for (int a = 0; a < K; a++) {
            if (w[a] == 0) continue;
            const float *d = deltas + stride * (size_t)(shape ? shape[a] : a) + q0;
            double wa = w[a];
            for (size_t q = 0; q < len; q++) acc[q] += wa * d[q];
        }
        for (size_t q = 0; q < len; q++) out[q0 + q] = (float)acc[q];
    }
}
