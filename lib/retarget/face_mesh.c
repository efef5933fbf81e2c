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
