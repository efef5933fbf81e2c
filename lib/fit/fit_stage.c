/* The fit stage over a photo set (paper sections 4.3-4.4, Algorithm 2): gathers the usable
 * photos, cuts a small gray face crop from each for photo-consistency, runs the progressive
 * fit and records poses, cameras, expression weights and the identity in the set. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "fit/outline_fit.h"
#include "fit/photo_consistency.h"
#include "fit/progressive_fit.h"
#include "frig/fit.h"
#include "image/image.h"
#include "workspace/photoset.h"

/* A fit whose RMS landmark error exceeds this share of the face's scale (the eye distance, or
 * half the landmarks' height where a turn makes that larger: fr_fit_face_scale) is unusable. */
#define FIT_FAILED_RMS_PER_FACE_SCALE 0.15
#define CROP_SIDE 160

typedef struct usable {
    size_t photo;
    double landmarks[2 * FR_LANDMARKS];
} usable;

static int collect_usable(const frig_photoset *set, usable *u) {
    int n = 0;
    for (size_t i = 0; i < set->count; i++) {
        const fr_photo *p = &set->photos[i];
        /* A photo a previous fit failed on is tried again (the options may have changed). */
        int again = p->status == FRIG_PHOTO_OK || p->status == FRIG_PHOTO_FIT_FAILED;
        const fr_face *f = again ? fr_photo_subject(p) : NULL;
        if (!f) continue;
        u[n].photo = i;
        memcpy(u[n].landmarks, f->landmarks, sizeof u[n].landmarks);
        n++;
    }
    return n;
}

/* The JPEG reduction (1, 2, 4, 8) that keeps the face at least CROP_SIDE pixels. */
static int reduction_for(const double *lm) {
    double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
    for (int k = 0; k < FR_LANDMARKS; k++) {
        x0 = fmin(x0, lm[2 * k]), x1 = fmax(x1, lm[2 * k]);
        y0 = fmin(y0, lm[2 * k + 1]), y1 = fmax(y1, lm[2 * k + 1]);
    }
    double face = fmax(x1 - x0, y1 - y0);
    int r = 1;
    while (r < 8 && face / (2 * r) >= CROP_SIDE) r *= 2;
    return r;
}

/* Read every usable photo once (in parallel) and keep only a small gray face crop. */
static void load_crops(frig_ctx *ctx, frig_photoset *set, const usable *u, int n, fr_fit_input *in,
                       frig_image **crops, char **errors) {
    atomic_size_t done;
    atomic_init(&done, 0);
    int saved = fr_blas_serial_begin();
#pragma omp parallel for schedule(dynamic) num_threads(fr_threads(ctx))
    for (int a = 0; a < n; a++) {
        if (fr_cancelled(ctx)) continue;
        const fr_photo *p = &set->photos[u[a].photo];
        frig_ctx *local = frig_ctx_create(); /* errors of one photo stay with it */
        frig_image *img = NULL;
        if (local) {
            frig_ctx_set_param(local, FRIG_PARAM_IMAGE_MAX_PIXELS, fr_param(ctx, FRIG_PARAM_IMAGE_MAX_PIXELS));
            /* Only a small face crop is kept: decode big JPEGs reduced (DCT scaling) when the
             * photo's upright size is known from detection. */
            int want = p->width > 0 && p->height > 0 ? reduction_for(u[a].landmarks) : 1, got = 1;
            double lm[2 * FR_LANDMARKS], origin[2] = {0, 0}, scale = 1;
            frig_status st = fr_image_load_reduced(local, p->path, FRIG_LOAD_DEFAULT, want, &img, &got);
            for (int k = 0; k < 2 * FR_LANDMARKS; k++) lm[k] = (u[a].landmarks[k] - 0.5 * (got - 1)) / got;
            if (!st) st = fr_face_crop(local, img, lm, CROP_SIDE, &crops[a], origin, &scale);
            if (st) errors[a] = strdup(frig_ctx_errmsg(local));
            /* crop = (reduced - origin) * scale = (full - ((got - 1) / 2 + got * origin)) * scale / got */
            in[a].crop_origin[0] = 0.5 * (got - 1) + got * origin[0];
            in[a].crop_origin[1] = 0.5 * (got - 1) + got * origin[1];
            in[a].crop_scale = scale / got;
            in[a].width = got > 1 ? p->width : img ? frig_image_width(img) : p->width;
            in[a].height = got > 1 ? p->height : img ? frig_image_height(img) : p->height;
        }
        in[a].crop = crops[a];
        frig_image_free(img);
        frig_ctx_free(local);
        fr_progress_tick(ctx, &done, "fit.read", (size_t)n);
    }
    fr_blas_serial_end(saved);
}

static frig_status record(frig_ctx *ctx, frig_photoset *set, const fr_fit_model *fm, const usable *u, int n,
                          const fr_fit_result *res, const double *identity) {
    const char **names = malloc(sizeof(char *) * (size_t)(fm->n_exp + 1));
    if (!names) return fr_nomem(ctx, "fit results");
    for (int k = 0; k < fm->n_exp; k++) names[k] = frig_model_expression_name(fm->model, fm->exp_index[k]);
    frig_status s = fr_photoset_set_fit_spaces(ctx, set, fm->n_id, fm->n_exp, names);
    free(names);
    if (s) return s;
    memcpy(set->identity, identity, sizeof(double) * (size_t)fm->n_id);
    for (int a = 0; a < n && !s; a++) {
        const fr_fit_result *r = &res[a];
        s = fr_photoset_set_fit(ctx, set, u[a].photo, r->R, r->t, r->f, r->perspective, r->w + fm->n_id, r->rms_px,
                                r->in_joint);
        double scale = fr_fit_face_scale(u[a].landmarks);
        if (!s && !(r->rms_px <= FIT_FAILED_RMS_PER_FACE_SCALE * scale)) {
            char why[160];
            snprintf(why, sizeof why, "landmark fit error %.1f px is over %.0f%% of the face's scale (%.1f px)",
                     r->rms_px, 100 * FIT_FAILED_RMS_PER_FACE_SCALE, scale);
            s = frig_photoset_set_status(ctx, set, u[a].photo, FRIG_PHOTO_FIT_FAILED, why);
        } else if (!s && set->photos[u[a].photo].status == FRIG_PHOTO_FIT_FAILED) {
            s = frig_photoset_set_status(ctx, set, u[a].photo, FRIG_PHOTO_OK, NULL);
        }
    }
    return s;
}

/* The identity and the poses refined from the photos' outlines (outline_fit.c). */
static frig_status refine_by_outlines(frig_ctx *ctx, const frig_photoset *set, const fr_fit_model *fm, const usable *u,
                                      int n, const fr_fit_input *in, fr_fit_result *res, double *identity) {
    fr_outline_options o = {fr_param_int(ctx, FRIG_PARAM_FIT_OUTLINE_ITERATIONS),
                            fr_param(ctx, FRIG_PARAM_FIT_OUTLINE_PRIOR), fr_param_int(ctx, FRIG_PARAM_FIT_MEAN_SIZE),
                            fr_threads(ctx), fr_param_int(ctx, FRIG_PARAM_FIT_OUTLINE_BAND)};
    if (o.iterations <= 0) return FRIG_OK;
    const char **paths = malloc(sizeof(char *) * ((size_t)n + 1));
    if (!paths) return fr_nomem(ctx, "the outline fit");
    for (int a = 0; a < n; a++) paths[a] = set->photos[u[a].photo].path;
    double moved[2];
    frig_status s = fr_fit_outline(ctx, fm, &o, n, paths, in, res, identity, moved);
    if (!s)
        fr_log(ctx, FRIG_LOG_INFO, "fit: the outlines %.2f -> %.2f px from the photos' edges (RMS, %d steps)",
               moved[0], moved[1], o.iterations);
    free(paths);
    return s;
}

frig_status frig_fit(frig_ctx *ctx, const frig_model *model, frig_photoset *set) {
    if (!model || !set) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_fit: NULL model or photo set");
    usable *u = malloc(sizeof(usable) * (set->count + 1));
    if (!u) return fr_nomem(ctx, "the fit");
    int n = collect_usable(set, u);
    if (n == 0) {
        free(u);
        return fr_error(ctx, FRIG_ERR_TOO_FEW, "no photo with an ok status and subject landmarks to fit "
                                               "(run frig detect and frig filter first)");
    }
    fr_fit_input *in = calloc((size_t)n, sizeof *in);
    frig_image **crops = calloc((size_t)n, sizeof *crops);
    char **errors = calloc((size_t)n, sizeof *errors);
    fr_fit_result *res = calloc((size_t)n, sizeof *res);
    fr_fit_model fm;
    memset(&fm, 0, sizeof fm);
    double *w = NULL, *identity = NULL;
    frig_status s = !in || !crops || !errors || !res ? fr_nomem(ctx, "the fit") : FRIG_OK;
    if (!s) s = fr_fit_model_build(ctx, model, fr_param_int(ctx, FRIG_PARAM_FIT_IDENTITY_MODES), &fm);
    if (!s) {
        w = calloc((size_t)n * fm.n_cols + 1, sizeof(double));
        identity = calloc((size_t)fm.n_id + 1, sizeof(double));
        if (!w || !identity) s = fr_nomem(ctx, "the fit");
    }
    if (!s) {
        for (int a = 0; a < n; a++) {
            in[a].landmarks = u[a].landmarks;
            res[a].w = w + (size_t)a * fm.n_cols;
        }
        load_crops(ctx, set, u, n, in, crops, errors);
        s = fr_check_cancel(ctx, "fit.read");
    }
    /* Photos that cannot be read again are reported and left out. */
    int kept = 0;
    for (int a = 0; a < n && !s; a++) {
        if (errors[a]) {
            s = frig_photoset_set_status(ctx, set, u[a].photo, FRIG_PHOTO_UNREADABLE, errors[a]);
            continue;
        }
        frig_image *crop = crops[a];
        crops[a] = NULL;
        u[kept] = u[a];
        in[kept] = in[a];
        in[kept].landmarks = u[kept].landmarks;
        crops[kept] = crop;
        res[kept].w = w + (size_t)kept * fm.n_cols;
        kept++;
    }
    if (!s && kept == 0) s = fr_error(ctx, FRIG_ERR_TOO_FEW, "none of the photos to fit could be read again");
    if (!s) {
        fr_fit_settings st;
        fr_fit_settings_from_ctx(ctx, &st);
        s = fr_fit_run(ctx, &fm, &st, FR_SCHEME_PROGRESSIVE, kept, in, res, identity);
    }
    if (!s) s = refine_by_outlines(ctx, set, &fm, u, kept, in, res, identity);
    if (!s) s = record(ctx, set, &fm, u, kept, res, identity);
    for (int a = 0; a < n && errors && crops; a++) {
        free(errors[a]);
        frig_image_free(crops[a]);
    }
    fr_fit_model_free(&fm);
    free(u), free(in), free(crops), free(errors), free(res), free(w), free(identity);
    return s;
}
