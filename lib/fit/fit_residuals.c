/* Every landmark's reprojection error of the stored fits (paper section 4.3, eq. 4.5): the
 * fitted identity, expression, pose and camera of each photo evaluated again with the fit's own
 * model, the jaw landmarks on the silhouette as the fit last placed them, for the report's
 * cumulative error curves. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "fit/fit_model.h"
#include "fit/photo_fit.h"
#include "frig/fit.h"
#include "workspace/photoset.h"

/* 0 when out of memory. */
static int one_photo(const fr_fit_model *fm, const frig_photoset *set, size_t i, double *err, double *eye) {
    const fr_photo *p = &set->photos[i];
    const fr_face *f = fr_photo_subject(p);
    for (int k = 0; k < FRIG_LANDMARK_COUNT; k++) err[k] = NAN;
    *eye = NAN;
    if (!p->fitted || !f) return 1;
    double *w = malloc(sizeof(double) * (size_t)fm->n_cols);
    if (!w) return 0;
    memcpy(w, set->identity, sizeof(double) * (size_t)fm->n_id);
    memcpy(w + fm->n_id, p->fit_expression, sizeof(double) * (size_t)fm->n_exp);
    fr_fit_photo ph;
    fr_fit_photo_init(fm, &ph, f->landmarks, p->width, p->height, p->fit_perspective, w);
    memcpy(ph.R, p->fit_rotation, sizeof ph.R);
    memcpy(ph.t, p->fit_translation, sizeof ph.t);
    ph.f = p->fit_focal;
    fr_fit_photo_update_contour(fm, &ph);
    for (int k = 0; k < FRIG_LANDMARK_COUNT; k++) {
        double X[3], uv[2];
        int slot = ph.corr[k];
        fr_fit_model_eval_slots(fm, w, &slot, 1, X);
        fr_fit_photo_project(&ph, X, 1, uv);
        err[k] = hypot(uv[0] - f->landmarks[2 * k], uv[1] - f->landmarks[2 * k + 1]);
    }
    *eye = fr_fit_eye_distance(f->landmarks);
    free(w);
    return 1;
}

frig_status frig_fit_landmark_errors(frig_ctx *ctx, const frig_model *model, const frig_photoset *set, double *errors,
                                     double *eye_distance) {
    if (!model || !set || !errors || !eye_distance)
        return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_fit_landmark_errors: NULL argument");
    if (set->n_identity <= 0 || !set->identity)
        return fr_error(ctx, FRIG_ERR_STATE, "the photo set has no fit yet (run frig fit)");
    fr_fit_model fm;
    memset(&fm, 0, sizeof fm);
    frig_status s = fr_fit_model_build(ctx, model, set->n_identity, &fm);
    if (!s && (fm.n_id != set->n_identity || fm.n_exp != set->n_expressions))
        s = fr_error(ctx, FRIG_ERR_STATE, "the fit used %d identity modes and %d expressions; this model gives %d and %d",
                     set->n_identity, set->n_expressions, fm.n_id, fm.n_exp);
    for (int k = 0; !s && k < fm.n_exp; k++)
        if (strcmp(frig_model_expression_name(model, fm.exp_index[k]), set->expression_names[k]) != 0)
            s = fr_error(ctx, FRIG_ERR_STATE, "the fit's expression %d is %s, this model's %s", k,
                         set->expression_names[k], frig_model_expression_name(model, fm.exp_index[k]));
    int ok = 1;
    if (!s) {
        int saved = fr_blas_serial_begin();
#pragma omp parallel for schedule(dynamic) num_threads(fr_threads(ctx)) reduction(& : ok)
        for (size_t i = 0; i < set->count; i++) ok &= one_photo(&fm, set, i, errors + FRIG_LANDMARK_COUNT * i, eye_distance + i);
        fr_blas_serial_end(saved);
        if (!ok) s = fr_nomem(ctx, "landmark errors");
    }
    fr_fit_model_free(&fm);
    return s;
}
