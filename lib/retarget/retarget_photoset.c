/* The retarget stage over a photo set (paper section 5.2): the fitted photos that have a
 * cloud, their weights in the rig's shapes, one pass of Algorithm 6 (retarget_stage.c), and
 * what it found recorded in the set: each photo's refined weights (section 5.2.3 (b)) and its
 * correspondence figures. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "core/sort.h"
#include "frig/retarget.h"
#include "model/model.h"
#include "retarget/retarget.h"
#include "rig/rig.h"
#include "workspace/photoset.h"

#define LANDMARK_RADIUS_PX 1.5 /* cloud points this near a landmark (pixels) stand for it */

/* The face region the stage personalizes: vertices 0 .. nf-1. */
static frig_status face_count(frig_ctx *ctx, const frig_model *model, int *nf) {
    int r = frig_model_region_find(model, "face"), first = 0, count = 0;
    if (r < 0 || frig_model_region(model, r, NULL, &first, &count) || first != 0 || count < 3)
        return fr_error(ctx, FRIG_ERR_UNSUPPORTED, "the model has no face region starting at vertex 0");
    *nf = count;
    return FRIG_OK;
}

static void free_photos(fr_rt_photo *p, int n) {
    for (int i = 0; p && i < n; i++) free(p[i].pick), free(p[i].hint), free(p[i].w), free(p[i].M), free(p[i].cover);
    free(p);
}

void fr_rt_photo_borrow_cloud(fr_rt_photo *p, const frig_clouds *clouds, size_t photo) {
    p->xyz = frig_clouds_xyz(clouds, photo);
    p->nrm = frig_clouds_normals(clouds, photo);
    p->conf = frig_clouds_confidence(clouds, photo);
    p->n_core = frig_clouds_count(clouds, photo);
    p->n_points = p->n_core + frig_clouds_margin_count(clouds, photo); /* the margin too */
}

/* The identity the sfs stage drew the clouds at (the fit's with its shared solve's change): the
 * rig's neutral moves by the modes' offset over the whole head and the set's identity becomes it,
 * so the pass starts from the surface the clouds were made from (docs/retarget.md, "Starting from
 * the identity sfs found"). */
static void start_from_sfs_identity(const frig_model *model, frig_photoset *set, frig_rig *rig, int n_id) {
    size_t n3 = 3 * (size_t)model->topo.vertex_count;
    float *neutral = rig->neutral;
    for (int k = 0; k < n_id; k++) {
        double d = set->sfs_identity[k] - set->identity[k];
        if (d == 0) continue;
        const float *mode = model->identity + n3 * (size_t)k;
        for (size_t i = 0; i < n3; i++) neutral[i] = (float)(neutral[i] + d * mode[i]);
        set->identity[k] = set->sfs_identity[k];
    }
}

/* A weight (nearly) every photo shows is the person's neutral, not an expression: the fit explains
 * a chin longer than the model's identity makes it by jawOpen in every photo, the sfs stage's
 * expression step, refining the weights against the pixels, keeps it, and the neutral fused under
 * those weights keeps the chin short. Each fitted shape's low quantile q of the weights the clouds
 * were drawn at (retarget.recenter) moves from every photo's weight into the rig's neutral, over
 * the whole head, before the pass. Only when every photo's weights are the sfs stage's (read from
 * its pixels): the landmark fit's alone (the light shared solve, a video) can share a bias the
 * pixels do not show (docs/retarget.md, "Weights every photo shares"). */
static frig_status recenter_weights(frig_ctx *ctx, double quantile, frig_rig *rig, int K, const int *fit_shape,
                                    fr_rt_photo *ph, int n) {
    if (!(quantile > 0) || n < 2) return FRIG_OK;
    double *v = malloc(sizeof(double) * (size_t)n);
    if (!v) return fr_nomem(ctx, "the weights' quantiles");
    size_t n3 = 3 * (size_t)rig->topo.vertex_count;
    for (int a = 0; a < K; a++) {
        for (int i = 0; i < n; i++) v[i] = ph[i].w[a];
        qsort(v, (size_t)n, sizeof(double), fr_cmp_double);
        double x = quantile * (n - 1);
        int lo = (int)floor(x);
        double q = lo + 1 < n ? v[lo] + (x - lo) * (v[lo + 1] - v[lo]) : v[lo];
        if (!(q > 0)) continue;
        const float *d = rig->deltas + n3 * (size_t)fit_shape[a];
        for (size_t c = 0; c < n3; c++) rig->neutral[c] = (float)(rig->neutral[c] + q * d[c]);
        for (int i = 0; i < n; i++) ph[i].w[a] = ph[i].w[a] > q ? ph[i].w[a] - q : 0;
        fr_log(ctx, FRIG_LOG_DEBUG, "retarget: %.3f of %s moved from every photo's weight into the neutral", q,
               rig->shape_names[fit_shape[a]]);
    }
    free(v);
    return FRIG_OK;
}

frig_status frig_retarget(frig_ctx *ctx, const frig_model *model, frig_photoset *set, const frig_clouds *clouds,
                          frig_rig *rig) {
    if (!model || !set || !clouds || !rig) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_retarget: NULL argument");
    if (rig->topo.vertex_count != model->topo.vertex_count)
        return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_retarget: the rig has %d vertices, the model %d",
                        rig->topo.vertex_count, model->topo.vertex_count);
    if (frig_clouds_photo_count(clouds) != set->count)
        return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_retarget: %zu clouds for %zu photos",
                        frig_clouds_photo_count(clouds), set->count);
    int nf = 0;
    frig_status s = face_count(ctx, model, &nf);
    if (s) return s;
    /* The fit's expressions as rig shapes (names the rig lacks are left out). */
    int K = 0, *fit_shape = malloc(sizeof(int) * ((size_t)set->n_expressions + 1));
    int *slot = malloc(sizeof(int) * ((size_t)set->n_expressions + 1));
    fr_rt_photo *ph = calloc(set->count + 1, sizeof *ph);
    if (!fit_shape || !slot || !ph) {
        free(fit_shape), free(slot), free(ph);
        return fr_nomem(ctx, "the retarget stage");
    }
    for (int k = 0; k < set->n_expressions; k++) {
        int j = frig_rig_shape_find(rig, set->expression_names[k]);
        slot[k] = j >= 0 ? K : -1;
        if (j >= 0) fit_shape[K++] = j;
    }
    int n = 0;
    for (size_t i = 0; i < set->count && !s; i++) {
        const fr_photo *p = &set->photos[i];
        if (p->status != FRIG_PHOTO_OK || !p->fitted || frig_clouds_count(clouds, i) == 0) continue;
        fr_rt_photo *q = &ph[n++];
        q->index = i;
        fr_rt_photo_borrow_cloud(q, clouds, i);
        for (int k = 0; k < 9; k++) q->R[k] = k % 4 == 0;
        q->scale = 1;
        const fr_face *face = fr_photo_subject(p);
        if (face && p->fit_perspective)
            fr_rt_lift_landmarks(q, p->fit_rotation, p->fit_translation, p->fit_focal, 0.5 * (p->width - 1),
                                 0.5 * (p->height - 1), face->landmarks, LANDMARK_RADIUS_PX);
        q->w = calloc((size_t)K + 1, sizeof(double));
        q->M = malloc(sizeof(float) * 3 * (size_t)nf);
        q->cover = malloc(sizeof(float) * (size_t)nf);
        if (!q->w || !q->M || !q->cover) s = fr_nomem(ctx, "the retarget stage");
        /* the expression the cloud was drawn at (sfs refines the fit's against the pixels) */
        const double *w = p->sfs_expression ? p->sfs_expression : p->fit_expression;
        for (int k = 0; k < set->n_expressions && !s; k++)
            if (slot[k] >= 0) q->w[slot[k]] = w[k];
    }
    if (!s && n == 0)
        s = fr_error(ctx, FRIG_ERR_TOO_FEW, "no photo has both a fit and a point cloud (run frig fit, then the "
                                            "sfs stage)");
    if (!s) {
        fr_rt_settings st;
        fr_rt_settings_from_ctx(ctx, &st);
        int n_id = set->n_identity < frig_model_identity_count(model) ? set->n_identity : frig_model_identity_count(model);
        if (set->sfs_identity && fr_param_int(ctx, FRIG_PARAM_RETARGET_SFS_IDENTITY))
            start_from_sfs_identity(model, set, rig, n_id);
        int from_pixels = 0;
        for (int a = 0; a < n; a++) from_pixels += set->photos[ph[a].index].sfs_expression != NULL;
        if (from_pixels == n) {
            s = recenter_weights(ctx, fr_param(ctx, FRIG_PARAM_RETARGET_RECENTER), rig, K, fit_shape, ph, n);
            /* the records now hold the weights on the moved neutral: another pass moves nothing again */
            for (int a = 0; a < n && !s; a++)
                for (int k = 0; k < set->n_expressions; k++)
                    if (slot[k] >= 0) set->photos[ph[a].index].sfs_expression[k] = ph[a].w[slot[k]];
        }
        if (!s) s = fr_rt_run(ctx, &st, model, rig, nf, K, fit_shape, n, ph, set->identity, n_id);
        /* used (or declined): the rig now is what the next clouds are drawn from */
        if (!s) s = fr_photoset_set_sfs_identity(ctx, set, NULL);
    }
    if (!s) {
        for (size_t i = 0; i < set->count; i++) set->photos[i].retargeted = 0;
        for (int a = 0; a < n; a++) {
            fr_photo *p = &set->photos[ph[a].index];
            p->retargeted = 1;
            p->rt_inliers = ph[a].inliers;
            p->rt_rms_mm = ph[a].rms_mm;
            p->rt_rigid_deg = ph[a].rigid_deg;
            p->rt_rigid_mm = ph[a].rigid_mm;
            for (int k = 0; k < set->n_expressions; k++)
                if (slot[k] >= 0) p->fit_expression[k] = ph[a].w[slot[k]];
        }
    }
    free_photos(ph, n);
    free(fit_shape), free(slot);
    return s;
}
