/* The head (and the torso under it) of a synthetic photo in camera coordinates: the true
 * rig's neutral plus the photo's few active blendshapes (a sparse sum, no BLAS, so parallel photos stay
 * deterministic), moved by the pose X_c = R X + t (paper eq. 4.4; docs/camera.md). */
#include <stdlib.h>

#include "core/context.h"
#include "rig/rig.h"
#include "synth/synth.h"

frig_status fr_synth_posed_vertices(frig_ctx *ctx, const frig_synth_subject *s, const fr_synth_photo *p,
                                    float **xyz_cam) {
    *xyz_cam = NULL;
    size_t n3 = 3 * (size_t)s->nv;
    float *x = malloc(sizeof *x * n3), *xc = malloc(sizeof *xc * 3 * (size_t)s->nv_render);
    if (!x || !xc) {
        free(x), free(xc);
        return fr_nomem(ctx, "the posed head");
    }
    const float *neutral = frig_rig_neutral(s->rig), *d[FR_SYNTH_MAX_ACTIVE];
    for (int a = 0; a < p->n_active; a++) d[a] = frig_rig_shape_deltas(s->rig, p->active[a]);
    for (size_t i = 0; i < n3; i++) {
        double v = neutral[i];
        for (int a = 0; a < p->n_active; a++) v += p->weight[a] * d[a][i];
        x[i] = (float)v;
    }
    fr_transform_points(p->R, p->t, x, s->nv, xc);
    /* the torso turns half as far as the head, about the neck's base */
    static const double DEG = 3.14159265358979323846 / 360.0; /* half a degree, in radians */
    static const double base[3] = {0.0, -0.13, -0.02};
    double Rt[9], tt[3], a[3], b[3];
    fr_rotation_from_euler(p->yaw * DEG, p->pitch * DEG, p->roll * DEG, Rt);
    fr_mat3_apply(p->R, base, a);
    fr_mat3_apply(Rt, base, b);
    for (int i = 0; i < 3; i++) tt[i] = a[i] + p->t[i] - b[i];
    fr_transform_points(Rt, tt, s->torso_xyz, s->nv_render - s->nv, xc + n3);
    free(x);
    *xyz_cam = xc;
    return FRIG_OK;
}
