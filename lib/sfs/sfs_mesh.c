/* The rig as shape from shading draws it (paper section 5.1: "rasterize the current fit"):
 * the opaque triangles (the transparent eye overlays and the lashes are left out, as the
 * synthetic renderer leaves them out), which of them are the face material whose skin the
 * stage reads, and the rig evaluated at a photo's weights. */
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "model/mode_sums.h"
#include "raster/raster.h"
#include "rig/rig.h"
#include "sfs/sfs.h"

frig_status fr_sfs_mesh_init(frig_ctx *ctx, const frig_rig *rig, fr_sfs_mesh *m) {
    memset(m, 0, sizeof *m);
    const fr_topology *t = &rig->topo;
    m->rig = rig;
    m->nv = t->vertex_count;
    m->shapes = rig->shape_count;
    m->uvs = t->uvs;
    m->tris = malloc(sizeof(int32_t) * 3 * (size_t)(t->triangle_count + 1));
    m->tri_uv = malloc(sizeof(int32_t) * 3 * (size_t)(t->triangle_count + 1));
    m->face = malloc((size_t)t->triangle_count + 1);
    m->core = malloc((size_t)t->triangle_count + 1);
    m->face_vertex = calloc((size_t)m->nv + 1, 1);
    if (!m->tris || !m->tri_uv || !m->face || !m->core || !m->face_vertex) {
        fr_sfs_mesh_free(m);
        return fr_nomem(ctx, "the rig's triangles");
    }
    /* the narrow face: a named vertex range (all of the face when the rig has none) */
    int narrow_first = 0, narrow_count = m->nv;
    if (!fr_topology_region(t, "narrow_face", &narrow_first, &narrow_count)) narrow_first = 0, narrow_count = m->nv;
    for (int i = 0; i < t->triangle_count; i++) {
        if (!fr_topology_opaque(t, i)) continue;
        memcpy(m->tris + 3 * (size_t)m->nt, t->triangles + 3 * (size_t)i, sizeof(int32_t) * 3);
        memcpy(m->tri_uv + 3 * (size_t)m->nt, t->triangle_uvs + 3 * (size_t)i, sizeof(int32_t) * 3);
        m->face[m->nt] = (uint8_t)fr_topology_face_skin(t, i);
        m->core[m->nt] = m->face[m->nt];
        for (int c = 0; c < 3; c++) {
            int vtx = t->triangles[3 * (size_t)i + c];
            if (vtx < narrow_first || vtx >= narrow_first + narrow_count) m->core[m->nt] = 0;
        }
        if (m->face[m->nt])
            for (int c = 0; c < 3; c++) m->face_vertex[t->triangles[3 * (size_t)i + c]] = 1;
        m->nt++;
    }
    m->near_face = malloc(sizeof(int32_t) * (size_t)(m->nt + 1));
    if (!m->near_face) {
        fr_sfs_mesh_free(m);
        return fr_nomem(ctx, "the rig's triangles");
    }
    for (int i = 0; i < m->nt; i++) {
        const int32_t *tr = m->tris + 3 * (size_t)i;
        if (m->face_vertex[tr[0]] || m->face_vertex[tr[1]] || m->face_vertex[tr[2]]) m->near_face[m->n_near_face++] = i;
    }
    int faces = 0;
    for (int i = 0; i < m->nt; i++) faces += m->face[i];
    if (!faces) {
        fr_sfs_mesh_free(m);
        return fr_error(ctx, FRIG_ERR_UNSUPPORTED, "the rig has no M_Face triangles for shape from shading");
    }
    return FRIG_OK;
}

void fr_sfs_mesh_free(fr_sfs_mesh *m) {
    free(m->tris), free(m->tri_uv), free(m->face), free(m->core), free(m->face_vertex), free(m->near_face);
    free(m->ident);
    memset(m, 0, sizeof *m);
}

void fr_sfs_mesh_normals(const fr_sfs_mesh *m, const float *xyz, float *normals) {
    fr_mesh_vertex_normals_at(xyz, m->nv, m->tris, m->near_face, m->n_near_face, m->face_vertex, normals);
}

void fr_sfs_mesh_eval(const fr_sfs_mesh *m, const double *weights, float *xyz) {
    const frig_rig *r = m->rig;
    size_t n3 = 3 * (size_t)m->nv;
    int active[256], na = 0;
    for (int k = 0; k < m->shapes && na < 256; k++)
        if (weights && weights[k] != 0.0) active[na++] = k;
    fr_mode_sum(n3, r->neutral, r->deltas, n3, na, active, weights, m->ident, xyz);
}
