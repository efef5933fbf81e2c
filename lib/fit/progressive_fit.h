/* Multi-photo fitting schemes on plain arrays (paper sections 4.3.3-4.4, Algorithm 2):
 * individual fits only, a naive joint fit of all photos at once, and the progressive
 * scheme with subset selection. Internal; frig_fit() wraps it for a photo set. */
#ifndef FR_FIT_PROGRESSIVE_FIT_H
#define FR_FIT_PROGRESSIVE_FIT_H

#include "fit/photo_fit.h"
#include "frig/image.h"

typedef enum fr_fit_scheme {
    FR_SCHEME_INDIVIDUAL = 0,  /* each photo its own identity (the paper's first step only) */
    FR_SCHEME_NAIVE_JOINT = 1, /* one identity fitted to all photos at once */
    FR_SCHEME_PROGRESSIVE = 2  /* Algorithm 2 */
} fr_fit_scheme;

typedef struct fr_fit_input {
    const double *landmarks;  /* 136 values */
    int width, height;
    /* For photo-consistency (section 4.4): a gray crop around the face and the map from
     * photo pixels to crop pixels, crop = (photo - origin) * scale. crop may be NULL. */
    const frig_image *crop;
    double crop_origin[2], crop_scale;
} fr_fit_input;

typedef struct fr_fit_result {
    double R[9], t[3], f;
    int perspective;
    double *w;        /* n_cols: the identity used for this photo, then its expression */
    double rms_px;
    int in_joint;     /* in the last joint subset */
    double score;     /* the last subset-selection score (eq. 4.11), lower is better */
} fr_fit_result;

typedef struct fr_fit_settings {
    int perspective;
    int rounds;                    /* progressive rounds (3) */
    double subset_first, subset_step; /* 0.4, 0.2 */
    double score_w_id, score_w_tex;   /* eq. 4.11: 1, 10 */
    fr_fit_weights start, end;     /* prior weights, decreasing */
    double joint_w_id;             /* identity prior weight in the joint fit (eq. 4.9 w3), per photo */
    double joint_prior;            /* the joint prior is this fraction of the subset's centroid */
    double contour_weight;         /* weight of the jaw landmarks 0-16 */
    int mean_size;                 /* 1: the joint identity keeps the mean face's size */
    int iterations;                /* LM iterations of an individual fit */
    int joint_sweeps;              /* alternations pose/expression <-> identity */
    int threads;
} fr_fit_settings;

/* The options of one photo fit under these settings: expression always, identity when
 * fit_identity (with the prior id_prior, NULL = the model mean), focal length with a
 * perspective camera, jaw correspondences re-picked every 5 iterations. */
void fr_fit_options_make(const fr_fit_settings *s, int fit_identity, const double *id_prior, fr_fit_weights start,
                         fr_fit_weights end, int iterations, fr_fit_options *opt);

/* Defaults from the paper and the context's fit.* parameters. */
void fr_fit_settings_from_ctx(const frig_ctx *ctx, fr_fit_settings *s);

/* Fit n photos. results[i].w must point to fm->n_cols doubles each. identity receives the
 * subject's identity (fm->n_id values; for FR_SCHEME_INDIVIDUAL the mean of the photos'). */
frig_status fr_fit_run(frig_ctx *ctx, const fr_fit_model *fm, const fr_fit_settings *s, fr_fit_scheme scheme, int n,
                       const fr_fit_input *in, fr_fit_result *results, double *identity);

#endif
