/* The subject's identity and every photo's pose refined from the photos' outlines
 * (outline_fit.c; beyond the paper). Internal. */
#ifndef FR_FIT_OUTLINE_FIT_H
#define FR_FIT_OUTLINE_FIT_H

#include "fit/fit_model.h"
#include "fit/progressive_fit.h"

typedef struct fr_outline_options {
    int iterations;  /* Gauss-Newton steps (0: off) */
    double prior;    /* weight of the identity's prior N(0, I) against one outline residual of a pixel */
    int mean_size;   /* 1: the steps keep the face's size */
    int threads;
    int band;        /* 1: outline pixels from the brows' height to a little below the chin only; 0: the whole
                      * face region */
} fr_outline_options;

/* Refine identity (fm->n_id values, shared) and each photo's pose res[a].R, res[a].t (the
 * expressions, cameras and the photos' identity columns res[a].w[0 .. n_id) are set to the new
 * identity too) from the occluding contours of the n photos paths[a] (width x height pixels as
 * fitted). Photos that cannot be read or show no outline are left as they are. *moved (may be
 * NULL): the outline's RMS distance to the photos' edges before and after, pixels of a
 * 160-pixel face. */
frig_status fr_fit_outline(frig_ctx *ctx, const fr_fit_model *fm, const fr_outline_options *o, int n,
                           const char *const *paths, const fr_fit_input *in, fr_fit_result *res, double *identity,
                           double moved[2]);

#endif
