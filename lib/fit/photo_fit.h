/* One photo's model fit (paper section 4.3.2, eq. 4.3-4.8): camera, rotation, translation,
 * expression weights in [0, 1] with an L1 term, and (for individual fits) identity weights,
 * minimizing the landmark reprojection error with priors, by Levenberg-Marquardt with
 * analytic Jacobians. Jaw landmarks slide along the silhouette. Internal. */
#ifndef FR_FIT_PHOTO_FIT_H
#define FR_FIT_PHOTO_FIT_H

#include "fit/fit_model.h"

/* Camera: pinhole (u = f x/z + cx) or weak perspective (u = f x + cx, f in pixels per metre). */
typedef struct fr_fit_photo {
    /* input */
    double q[2 * FR_LANDMARKS];    /* detected landmarks, pixels */
    double weight[FR_LANDMARKS];   /* per-landmark weight (0: ignore) */
    int width, height;
    double unit;                   /* pixels per residual unit: eye distance / 100 */
    /* state */
    double R[9];                   /* row-major rotation, model -> camera */
    double t[3];
    double f;                      /* focal length (pixels) or weak-perspective scale */
    double f0;                     /* focal prior */
    int perspective;
    double *w;                     /* n_cols weights: identity, then expression */
    int corr[FR_LANDMARKS];        /* slot used for each landmark */
    /* results */
    double rms_px;                 /* RMS landmark reprojection error, pixels */
    double cost;
    int iterations;
} fr_fit_photo;

typedef struct fr_fit_weights {
    double id, exp, sparse;        /* eq. 4.8 w1, w2, w3 */
    double focal;                  /* prior on log(f / f0) */
} fr_fit_weights;

typedef struct fr_fit_options {
    int fit_identity, fit_expression, fit_focal;
    const double *id_prior;        /* n_id values (NULL: zeros) */
    fr_fit_weights start, end;     /* weights decrease from start to end over the iterations */
    int iterations;
    int contour_every;             /* re-pick the jaw correspondences every this many iterations */
} fr_fit_options;

/* Distance between the eye centres (means of landmarks 36-41 and 42-47), pixels. */
double fr_fit_eye_distance(const double *landmarks);
/* The face's scale in pixels: the eye distance, kept from collapsing on a turned face by half
 * the landmarks' height. */
double fr_fit_face_scale(const double *landmarks);

/* Set up a photo: landmarks (136 values), image size; w must hold n_cols values (owned by
 * the caller). Camera and pose are initialized from the landmarks (affine fit of the
 * current shape), correspondences to the default landmark vertices. */
void fr_fit_photo_init(const fr_fit_model *fm, fr_fit_photo *p, const double *landmarks, int width, int height,
                       int perspective, double *w);

/* Weight of the jaw landmarks (0-16) relative to the others. */
void fr_fit_photo_set_contour_weight(fr_fit_photo *p, double w);

/* Re-estimate the pose from the current shape (keeps w). */
void fr_fit_photo_init_pose(const fr_fit_model *fm, fr_fit_photo *p);

/* Run the fit. Never fails for numerical reasons (a failed step just stops early);
 * returns FRIG_ERR_NO_MEMORY only. */
frig_status fr_fit_photo_run(frig_ctx *ctx, const fr_fit_model *fm, fr_fit_photo *p, const fr_fit_options *opt);

/* Re-pick the jaw landmarks' vertices on the current fit's silhouette. */
void fr_fit_photo_update_contour(const fr_fit_model *fm, fr_fit_photo *p);

/* Project slot positions (3 per point, model space) with the photo's camera. */
void fr_fit_photo_project(const fr_fit_photo *p, const double *X, int n, double *uv);

/* Identity part of the landmark Jacobian for the joint fit: rows = 2 per landmark (weighted,
 * in residual units), cols = n_id; and the residuals. J: (2*68) x n_id column-major. */
void fr_fit_photo_identity_jacobian(const fr_fit_model *fm, const fr_fit_photo *p, double *J, double *r);

/* RMS landmark error in pixels of the current state (over weighted landmarks). */
double fr_fit_photo_rms(const fr_fit_model *fm, const fr_fit_photo *p);

#endif
