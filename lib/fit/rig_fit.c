/* Per-image reconstruction with the generated blendshapes (paper section 5.3, Algorithm 3
 * line 5): every fitted photo's camera, pose and expression fitted again to its landmarks,
 * with the rig's neutral and shapes in place of the model (no identity), starting from the
 * photo's current pose and weights. The per-photo fit is the fit stage's (photo_fit.c: eq.
 * 4.3-4.8 with the final, halved prior weights). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "fit/progressive_fit.h"
#include "frig/retarget.h"
#include "workspace/photoset.h"

#define FIT_FAILED_RMS_PER_FACE_SCALE 0.15 /* as frig_fit */

typedef struct refit {
    const fr_fit_model *fm;
    const fr_fit_settings *st;
    frig_photoset *set;
    const size_t *photo;
    int *exp_of_weight; /* per fit-model expression: its index in the set's expressions (-1: none) */
    fr_fit_photo *ph;
    double *w;
} refit;

static frig_status refit_one(frig_ctx *child, size_t a, void *user) {
    refit *r = user;
    const fr_fit_model *fm = r->fm;
    fr_photo *p = &r->set->photos[r->photo[a]];
    const fr_face *face = fr_photo_subject(p);
    fr_fit_photo *ph = &r->ph[a];
    double *w = r->w + a * (size_t)fm->n_cols;
    for (int k = 0; k < fm->n_exp; k++) w[k] = r->exp_of_weight[k] >= 0 ? p->fit_expression[r->exp_of_weight[k]] : 0;
    fr_fit_photo_init(fm, ph, face->landmarks, p->width, p->height, p->fit_perspective, w);
    fr_fit_photo_set_contour_weight(ph, r->st->contour_weight);
    /* Warm start: the photo's current pose and camera. */
    memcpy(ph->R, p->fit_rotation, sizeof ph->R);
    memcpy(ph->t, p->fit_translation, sizeof ph->t);
    ph->f = p->fit_focal;
    fr_fit_photo_update_contour(fm, ph);
    fr_fit_options opt;
    fr_fit_options_make(r->st, 0, NULL, r->st->end, r->st->end, r->st->iterations, &opt);
    return fr_fit_photo_run(child, fm, ph, &opt);
}

frig_status frig_fit_rig(frig_ctx *ctx, const frig_model *model, const frig_rig *rig, frig_photoset *set) {
    if (!model || !rig || !set) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_fit_rig: NULL argument");
    size_t n = 0, *photo = malloc(sizeof(size_t) * (set->count + 1));
    if (!photo) return fr_nomem(ctx, "the refit");
    for (size_t i = 0; i < set->count; i++) {
        const fr_photo *p = &set->photos[i];
        /* sfs_failed photos too: the sfs stage judges them again with the new fit */
        if ((p->status == FRIG_PHOTO_OK || p->status == FRIG_PHOTO_FIT_FAILED || p->status == FRIG_PHOTO_SFS_FAILED) &&
            p->fitted && fr_photo_subject(p))
            photo[n++] = i;
    }
    if (n == 0) {
        free(photo);
        return fr_error(ctx, FRIG_ERR_TOO_FEW, "no fitted photo to refit on the rig (run frig fit first)");
    }
    fr_fit_model fm;
    frig_status s = fr_fit_model_build_rig(ctx, model, rig, &fm);
    if (s) {
        free(photo);
        return s;
    }
    fr_fit_settings st;
    fr_fit_settings_from_ctx(ctx, &st);
    refit r = {&fm, &st, set, photo, NULL, NULL, NULL};
    r.exp_of_weight = malloc(sizeof(int) * ((size_t)fm.n_exp + 1));
    r.ph = calloc(n, sizeof *r.ph);
    r.w = calloc(n * (size_t)fm.n_cols + 1, sizeof(double));
    if (!r.exp_of_weight || !r.ph || !r.w) s = fr_nomem(ctx, "the refit");
    for (int k = 0; k < fm.n_exp && !s; k++) {
        const char *name = frig_model_expression_name(model, fm.exp_index[k]);
        r.exp_of_weight[k] = -1;
        for (int e = 0; e < set->n_expressions; e++)
            if (!strcmp(set->expression_names[e], name)) r.exp_of_weight[k] = e;
    }
    if (!s) {
        int saved = fr_blas_serial_begin();
        s = fr_parallel_items(ctx, n, "fit.rig", refit_one, &r);
        fr_blas_serial_end(saved);
    }
    for (size_t a = 0; a < n && !s; a++) {
        fr_photo *p = &set->photos[photo[a]];
        const fr_fit_photo *ph = &r.ph[a];
        double *w = r.w + a * (size_t)fm.n_cols, *expr = malloc(sizeof(double) * ((size_t)set->n_expressions + 1));
        if (!expr) {
            s = fr_nomem(ctx, "the refit");
            break;
        }
        memcpy(expr, p->fit_expression, sizeof(double) * (size_t)set->n_expressions);
        for (int k = 0; k < fm.n_exp; k++)
            if (r.exp_of_weight[k] >= 0) expr[r.exp_of_weight[k]] = w[k];
        s = fr_photoset_set_fit(ctx, set, photo[a], ph->R, ph->t, ph->f, ph->perspective, expr, ph->rms_px,
                                p->fit_in_joint);
        free(expr);
        double scale = fr_fit_face_scale(fr_photo_subject(p)->landmarks);
        if (!s && !(ph->rms_px <= FIT_FAILED_RMS_PER_FACE_SCALE * scale)) {
            char why[160];
            snprintf(why, sizeof why, "landmark fit error on the rig %.1f px is over %.0f%% of the face's scale (%.1f px)",
                     ph->rms_px, 100 * FIT_FAILED_RMS_PER_FACE_SCALE, scale);
            s = frig_photoset_set_status(ctx, set, photo[a], FRIG_PHOTO_FIT_FAILED, why);
        } else if (!s && p->status == FRIG_PHOTO_FIT_FAILED) {
            s = frig_photoset_set_status(ctx, set, photo[a], FRIG_PHOTO_OK, NULL);
        }
    }
    fr_fit_model_free(&fm);
    free(r.exp_of_weight), free(r.ph), free(r.w), free(photo);
    return s;
}
