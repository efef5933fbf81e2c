/* The photo set's inside (internal): plain arrays of photos and faces. Stages read and
 * write these directly; the public accessors in include/frig/photoset.h wrap them. */
#ifndef FR_WORKSPACE_PHOTOSET_H
#define FR_WORKSPACE_PHOTOSET_H

#include "frig/identity.h"
#include "frig/photoset.h"

/* One past the largest photo status number (names may have gaps: frig_photo_status_name). */
#define FR_PHOTO_STATUS_LIMIT 16

typedef struct fr_face {
    double box[4]; /* x, y, w, h */
    double score;
    int source;
    int has_landmarks;
    double landmarks[2 * FRIG_LANDMARK_COUNT];
    /* identity (lib/identity, descriptors from lib/detect): face-api's 128-D descriptor, and
     * its distance to the set's identity (NaN until the identity step judged the photo) */
    int has_descriptor;
    float descriptor[FRIG_DESCRIPTOR_SIZE];
    double identity_distance;
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
    /* retarget (section 5.2): the last pass's correspondence figures; the pass also refines
     * fit_expression (section 5.2.3 (b)) */
    int retargeted;
    int rt_inliers;
    double rt_rms_mm, rt_rigid_deg, rt_rigid_mm;
    /* sfs (section 5.1): what the cloud was made of, the lighting, the refined pose */
    int sfs_done;
    int sfs_pixels, sfs_kept, sfs_margin; /* face pixels, the cloud's points, its margin's */
    double sfs_error;
    double sfs_lighting[27]; /* 9 per channel */
    double sfs_rotation[9], sfs_translation[3];
    double *sfs_expression; /* the expression its cloud was drawn at (n_expressions; NULL: the fit's) */
} fr_photo;

/* retarget (section 5.3): one round of the outer loop. */
typedef struct fr_retarget_round {
    double change_mm, rms_mm;
    int photos;
} fr_retarget_round;

struct frig_photoset {
    fr_photo *photos;
    size_t count, capacity;
    /* fit: the subject's identity and the names of the fitted expressions */
    int n_identity;
    double *identity;
    int n_expressions;
    char **expression_names;
    /* sfs: the shared solve of its last run (report.json "sfs"; frig_photoset_sfs_solve) */
    int sfs_solve, sfs_photos; /* frig_sfs_solve; photos judged */
    int sfs_why;               /* fr_sfs_why */
    double sfs_light_axis;
    /* sfs: the identity its clouds were drawn at (n_identity weights: the fit's with the change the
     * shared solve found in the model's first modes; NULL: the fit's). Retarget starts from it and
     * drops it; a new fit drops it too. */
    double *sfs_identity;
    /* retarget: the outer loop's rounds (report.json "retarget") */
    int rt_rounds;
    fr_retarget_round *rt_round;
    /* identity (lib/identity): the subject's descriptor (the medoid of the dominant cluster),
     * the threshold used, the photos in the cluster, and where the medoid came from */
    int has_subject_id;
    float subject_id[FRIG_DESCRIPTOR_SIZE];
    double subject_id_threshold;
    size_t subject_id_photos;
    long subject_id_photo, subject_id_face;
};

/* retarget's part of report.json (lib/workspace/retarget_report.c). */
struct fr_json;
void fr_retarget_report_write_photo(struct fr_json *j, const fr_photo *p);
void fr_retarget_report_write_set(struct fr_json *j, const frig_photoset *set);
struct cJSON;
frig_status fr_retarget_report_read_photo(frig_ctx *ctx, frig_photoset *set, size_t photo, const struct cJSON *jp);
frig_status fr_retarget_report_read_set(frig_ctx *ctx, frig_photoset *set, const struct cJSON *root);
/* Append a round (the outer loop). */
frig_status fr_photoset_add_retarget_round(frig_ctx *ctx, frig_photoset *set, const fr_retarget_round *r);

/* Set the fit's shape spaces (drops earlier fit results if the sizes change). */
frig_status fr_photoset_set_fit_spaces(frig_ctx *ctx, frig_photoset *set, int n_identity, int n_expressions,
                                       const char *const *expression_names);
/* Record one photo's fit (expression: set->n_expressions values). */
frig_status fr_photoset_set_fit(frig_ctx *ctx, frig_photoset *set, size_t photo, const double R[9], const double t[3],
                                double focal, int perspective, const double *expression, double error_px,
                                int in_joint);

/* Identity fields in report.json (identity_report.c): a face's "descriptor" and
 * "identity_distance", the set's "identity" block. */
struct fr_json;
void fr_report_write_face_identity(struct fr_json *j, const fr_face *f);
void fr_report_write_set_identity(struct fr_json *j, const frig_photoset *set);
/* 0 on success, else a sentence in why (size bytes). */
int fr_report_read_face_identity(fr_face *f, const void *json_face, char *why, size_t size);
int fr_report_read_set_identity(frig_photoset *set, const void *json_root, char *why, size_t size);
/* Record one photo's shape-from-shading results (sfs_report.c). */
void fr_photoset_set_sfs(fr_photo *p, int pixels, int kept, double error, const double lighting[27], const double R[9],
                         const double t[3]);
/* Record the identity the clouds were drawn at (NULL: the fit's; n must be set->n_identity). */
frig_status fr_photoset_set_sfs_identity(frig_ctx *ctx, frig_photoset *set, const double *identity);
/* Why the sfs stage took the light shared solve (frig_photoset_sfs_solve's why). */
typedef enum fr_sfs_why { FR_SFS_WHY_NONE = 0, FR_SFS_WHY_FEW_PHOTOS, FR_SFS_WHY_MANY_PHOTOS, FR_SFS_WHY_ONE_LIGHT_AXIS, FR_SFS_WHY_OUTER_LOOP } fr_sfs_why;
/* Record the stage's shared solve (solve: frig_sfs_solve). */
void fr_photoset_set_sfs_solve(frig_photoset *set, int solve, int why, int photos, double light_axis);
/* The expression weights (set->n_expressions) sfs drew photo i's cloud at; NULL: the fit's. */
frig_status fr_photoset_set_sfs_expression(frig_ctx *ctx, frig_photoset *set, size_t i, const double *weights);

/* The subject face, or NULL when the photo has none (or it has no landmarks). */
const fr_face *fr_photo_subject(const fr_photo *photo);

#endif
