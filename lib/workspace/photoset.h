/* The photo set's inside (internal): plain arrays of photos and faces. Stages read and
 * write these directly; the public accessors in include/frig/photoset.h wrap them. */
#ifndef FR_WORKSPACE_PHOTOSET_H
#define FR_WORKSPACE_PHOTOSET_H

#include "frig/photoset.h"

typedef struct fr_face {
    double box[4]; /* x, y, w, h */
    double score;
    int source;
    int has_landmarks;
    double landmarks[2 * FRIG_LANDMARK_COUNT];
} fr_face;

typedef struct fr_photo {
    char *path;
    frig_photo_status status;
    char *reason;
    int width, height;
    fr_face *faces;
    size_t face_count, face_capacity;
    long subject;
    /* filter */
    int filtered;
    double filter_error, filter_texture_error, filter_shape_error;
    int filter_round;
    /* fit (section 4.3): pose, camera, expression weights (set->n_expressions) */
    int fitted;
    double fit_rotation[9]; /* row-major, model -> camera */
    double fit_translation[3];
    double fit_focal;
    int fit_perspective;
    double *fit_expression;
    double fit_error_px;
    int fit_in_joint;
} fr_photo;

struct frig_photoset {
    fr_photo *photos;
    size_t count, capacity;
    /* fit: the subject's identity and the names of the fitted expressions */
    int n_identity;
    double *identity;
    int n_expressions;
    char **expression_names;
};

/* Set the fit's shape spaces (drops earlier fit results if the sizes change). */
frig_status fr_photoset_set_fit_spaces(frig_ctx *ctx, frig_photoset *set, int n_identity, int n_expressions,
                                       const char *const *expression_names);
/* Record one photo's fit (expression: set->n_expressions values). */
frig_status fr_photoset_set_fit(frig_ctx *ctx, frig_photoset *set, size_t photo, const double R[9], const double t[3],
                                double focal, int perspective, const double *expression, double error_px,
                                int in_joint);

/* The subject face, or NULL when the photo has none (or it has no landmarks). */
const fr_face *fr_photo_subject(const fr_photo *photo);

#endif
