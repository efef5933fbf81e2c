/* The head pose refined against the recovered depth (beyond the paper: the landmark fit's
 * rotation is several degrees off on turned faces): point-to-plane ICP (Chen and Medioni 1992)
 * of the rig at the photo's expression to the photo's kept cloud points, with projective data
 * association (each point is paired with the rig surface the crop shows at its pixel, the rig
 * drawn again at every round), Huber weights, and a small ridge on the update. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "linalg/linalg.h"
#include "raster/raster.h"
#include "raster/rotation.h"
#include "sfs/sfs.h"

#define ICP_ROUNDS 6
#define HUBER_M 0.002 /* metres */

frig_status fr_sfs_refine_pose(frig_ctx *ctx, const fr_sfs_mesh *m, fr_sfs_view *v, double R[9], double t[3]) {
    memcpy(R, v->R, sizeof v->R);
    memcpy(t, v->t, sizeof v->t);
    size_t n = (size_t)v->w * v->h;
    float *xyz = malloc(sizeof(float) * 3 * (size_t)m->nv), *xc = malloc(sizeof(float) * 3 * (size_t)m->nv);
    float *nrm = malloc(sizeof(float) * 3 * (size_t)m->nv);
    fr_raster *r = NULL;
    frig_status s = !xyz || !xc || !nrm ? fr_nomem(ctx, "the pose refinement") : FRIG_OK;
    if (!s) s = fr_raster_create(ctx, v->w, v->h, &r);
    if (!s) fr_sfs_mesh_eval(m, v->weights, xyz);
    fr_raster_options ro = {FR_RASTER_DEFAULT_NEAR, 1};
    for (int round = 0; round < ICP_ROUNDS && !s; round++) {
        fr_transform_points(R, t, xyz, m->nv, xc);
        s = fr_raster_render(ctx, r, &v->cam, xc, m->nv, m->tris, m->nt, &ro);
        if (s) break;
        fr_sfs_mesh_normals(m, xc, nrm); /* read at face triangles only */
        double A[36] = {0}, b[6] = {0}, W = 0;
        for (size_t i = 0; i < n; i++) {
            if (!v->kept[i] || r->tri[i] < 0 || !m->face[r->tri[i]]) continue;
            int x = (int)(i % v->w), y = (int)(i / v->w);
            double X[3] = {v->z[i] * (x - v->cam.cx) / v->cam.f, v->z[i] * (y - v->cam.cy) / v->cam.f, v->z[i]};
            double Y[3] = {r->depth[i] * (x - v->cam.cx) / v->cam.f, r->depth[i] * (y - v->cam.cy) / v->cam.f, r->depth[i]};
            float nn[3];
            if (!fr_raster_interpolate(r, m->tris, x, y, nrm, 3, nn)) continue;
            double mm[3] = {nn[0], nn[1], nn[2]}, l = sqrt(mm[0] * mm[0] + mm[1] * mm[1] + mm[2] * mm[2]);
            if (!(l > 0)) continue;
            for (int k = 0; k < 3; k++) mm[k] /= l;
            double res = (Y[0] - X[0]) * mm[0] + (Y[1] - X[1]) * mm[1] + (Y[2] - X[2]) * mm[2];
            double w = v->confidence[i] * (fabs(res) < HUBER_M ? 1.0 : HUBER_M / fabs(res));
            double J[6] = {Y[1] * mm[2] - Y[2] * mm[1], Y[2] * mm[0] - Y[0] * mm[2], Y[0] * mm[1] - Y[1] * mm[0],
                           mm[0], mm[1], mm[2]};
            for (int p = 0; p < 6; p++) {
                b[p] -= w * J[p] * res;
                for (int q = 0; q < 6; q++) A[6 * p + q] += w * J[p] * J[q];
            }
            W += w;
        }
        if (W < 50) break;
        double tr = 0;
        for (int p = 0; p < 6; p++) tr += A[7 * p];
        for (int p = 0; p < 6; p++) A[7 * p] += 1e-6 * tr;
        if (fr_solve_spd(ctx, 6, 1, A, 6, b, 6)) break; /* degenerate: keep the pose */
        double dR[9], Rn[9], tn[3];
        fr_rotation_from_axis_angle(b, dR);
        fr_mat3_mul(dR, R, Rn);
        fr_mat3_apply(dR, t, tn);
        memcpy(R, Rn, sizeof Rn);
        for (int k = 0; k < 3; k++) t[k] = tn[k] + b[3 + k];
        if (sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]) < 1e-5 && sqrt(b[3] * b[3] + b[4] * b[4] + b[5] * b[5]) < 1e-6)
            break;
    }
    fr_raster_free(r);
    free(xyz), free(xc), free(nrm);
    return s;
}
