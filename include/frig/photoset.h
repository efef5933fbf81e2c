/* libfrig photo set: the in-memory form of a workspace folder. It holds the photos, every
 * face found in each with its box and 68 landmarks, which face is the subject, each photo's
 * status and the reason for it, and what later stages add (filter errors, fits).
 * On disk it is WORKSPACE/report.json (see docs/workspace.md).
 */
#ifndef FRIG_PHOTOSET_H
#define FRIG_PHOTOSET_H

#include "frig/core.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct frig_photoset frig_photoset;

/* A photo's fate. */
typedef enum frig_photo_status {
    FRIG_PHOTO_PENDING = 0,    /* not processed yet */
    FRIG_PHOTO_OK = 1,         /* usable so far */
    FRIG_PHOTO_UNREADABLE = 2, /* the file could not be decoded (reason says why) */
    FRIG_PHOTO_NO_FACE = 3,    /* no face found */
    FRIG_PHOTO_FACE_TOO_SMALL = 4, /* faces found, but the subject is too small to use */
    FRIG_PHOTO_OUTLIER = 5,    /* dropped by the filter stage (robust PCA, Algorithm 1) */
    FRIG_PHOTO_FIT_FAILED = 6, /* the model fit did not converge to anything usable */
    FRIG_PHOTO_DUPLICATE = 7,  /* the same bytes as an earlier photo of the set (reason names it) */
    FRIG_PHOTO_OTHER_PERSON = 8, /* no face in it is the subject's: its nearest face's descriptor is
                                    farther than identity.threshold from the set's identity (frig/identity.h) */
    FRIG_PHOTO_SFS_FAILED = 9    /* shape from shading could not read the face: too little skin, over- or
                                  * under-exposed, colours unlike the subject's (reason says which) */
} frig_photo_status;

/* "ok", "no_face", ... (the report's spelling); NULL for an unknown value. */
FRIG_API const char *frig_photo_status_name(frig_photo_status status);

/* Where a face's box or landmarks came from. */
typedef enum frig_face_source {
    FRIG_FACE_FRONTAL = 0,          /* frontal cascade */
    FRIG_FACE_PROFILE = 1,          /* profile cascade (face turned to its left) */
    FRIG_FACE_PROFILE_MIRRORED = 2, /* profile cascade on the mirrored photo */
    FRIG_FACE_USER = 3,             /* landmarks supplied by the user (.pts / .json) */
    FRIG_FACE_SSD = 4               /* face-api's SSD MobileNet v1 detector (frig/identity.h) */
} frig_face_source;

#define FRIG_LANDMARK_COUNT 68

FRIG_API frig_status frig_photoset_create(frig_ctx *ctx, frig_photoset **out);
FRIG_API void frig_photoset_free(frig_photoset *set);

/* Read / write WORKSPACE/report.json (written atomically). load fails with
 * FRIG_ERR_NOT_FOUND when the workspace has no report yet. */
FRIG_API frig_status frig_photoset_load(frig_ctx *ctx, const char *workspace, frig_photoset **out);
FRIG_API frig_status frig_photoset_save(frig_ctx *ctx, const frig_photoset *set, const char *workspace);

/* ---- photos ---- */
FRIG_API size_t frig_photoset_count(const frig_photoset *set);
/* Add a photo by path (not read now); returns its index. */
FRIG_API frig_status frig_photoset_add(frig_ctx *ctx, frig_photoset *set, const char *path, size_t *index);
FRIG_API const char *frig_photoset_path(const frig_photoset *set, size_t photo);
FRIG_API frig_photo_status frig_photoset_status(const frig_photoset *set, size_t photo);
/* The sentence explaining the status ("" when none). */
FRIG_API const char *frig_photoset_reason(const frig_photoset *set, size_t photo);
FRIG_API frig_status frig_photoset_set_status(frig_ctx *ctx, frig_photoset *set, size_t photo,
                                              frig_photo_status status, const char *reason);
/* Upright size of the photo (0 until read). */
FRIG_API void frig_photoset_size(const frig_photoset *set, size_t photo, int *width, int *height);
FRIG_API frig_status frig_photoset_set_size(frig_ctx *ctx, frig_photoset *set, size_t photo, int width,
                                            int height);

/* ---- faces ---- */
FRIG_API size_t frig_photoset_face_count(const frig_photoset *set, size_t photo);
/* box: x, y, width, height (upright pixels); landmarks: 68 (x, y) pairs, or NULL when the
 * face has none yet. Returns the face's index. */
FRIG_API frig_status frig_photoset_add_face(frig_ctx *ctx, frig_photoset *set, size_t photo, const double box[4],
                                            double score, frig_face_source source, const double *landmarks,
                                            size_t *face);
FRIG_API frig_status frig_photoset_clear_faces(frig_ctx *ctx, frig_photoset *set, size_t photo);
FRIG_API frig_status frig_photoset_face_box(const frig_photoset *set, size_t photo, size_t face, double box[4]);
FRIG_API double frig_photoset_face_score(const frig_photoset *set, size_t photo, size_t face);
FRIG_API frig_face_source frig_photoset_face_source(const frig_photoset *set, size_t photo, size_t face);
/* Copies 136 values (x0, y0, x1, y1, ...); FRIG_ERR_STATE when the face has no landmarks. */
FRIG_API frig_status frig_photoset_face_landmarks(const frig_photoset *set, size_t photo, size_t face,
                                                  double *landmarks);
FRIG_API frig_status frig_photoset_set_face_landmarks(frig_ctx *ctx, frig_photoset *set, size_t photo,
                                                      size_t face, const double *landmarks);
/* The subject's face in this photo, or -1 when none is chosen. */
FRIG_API long frig_photoset_subject(const frig_photoset *set, size_t photo);
FRIG_API frig_status frig_photoset_set_subject(frig_ctx *ctx, frig_photoset *set, size_t photo, long face);

/* ---- filter results (section 4.2, Algorithm 1) ---- */
/* e = w_t * texture_error + w_s * shape_error for the subject face, and the round in which
 * the photo was dropped (0 = kept). */
FRIG_API frig_status frig_photoset_set_filter(frig_ctx *ctx, frig_photoset *set, size_t photo, double error,
                                              double texture_error, double shape_error, int round_dropped);
FRIG_API int frig_photoset_filter(const frig_photoset *set, size_t photo, double *error, double *texture_error,
                                  double *shape_error, int *round_dropped); /* 0 when not filtered */

/* ---- fit results (sections 4.3-4.4, Algorithm 2) ---- */
/* 1 when the photo has a model fit. */
FRIG_API int frig_photoset_fitted(const frig_photoset *set, size_t photo);
/* rotation: row-major 3x3 mapping model to camera coordinates (x right, y down, z forward,
 * docs/camera.md); translation in metres; focal in pixels (perspective) or the scale in
 * pixels per metre (weak perspective, perspective = 0). Any output may be NULL. */
FRIG_API frig_status frig_photoset_fit_pose(const frig_photoset *set, size_t photo, double rotation[9],
                                            double translation[3], double *focal, int *perspective);
/* The fitted expressions (names as in the model) and one photo's weights in [0, 1]. */
FRIG_API int frig_photoset_fit_expression_count(const frig_photoset *set);
FRIG_API const char *frig_photoset_fit_expression_name(const frig_photoset *set, int k);
FRIG_API frig_status frig_photoset_fit_expression(const frig_photoset *set, size_t photo, double *weights);
/* RMS landmark reprojection error of the final fit, pixels (NaN when not fitted). */
FRIG_API double frig_photoset_fit_error(const frig_photoset *set, size_t photo);
/* 1 when the photo was in the last joint identity fit (the consistent subset, section 4.4). */
FRIG_API int frig_photoset_fit_in_joint(const frig_photoset *set, size_t photo);
/* The subject's identity weights (standard deviations of the model's identity modes). */
FRIG_API int frig_photoset_identity(const frig_photoset *set, const double **weights);

/* ---- shape-from-shading results (section 5.1; frig_sfs) ---- */
/* 1 when the photo has shape-from-shading results (its cloud may still be empty when the photo
 * is sfs_failed). */
FRIG_API int frig_photoset_sfs_done(const frig_photoset *set, size_t photo);
/* Face pixels of the crop, pixels kept in the cloud (eq. 5.15), and the median relative shading
 * error |I - a S(n)| / |a S(n)| over the skin pixels. Any output may be NULL. */
FRIG_API frig_status frig_photoset_sfs_stats(const frig_photoset *set, size_t photo, size_t *pixels, size_t *kept,
                                             double *error);
/* The lighting: 9 second-order SH coefficients per channel (R, G, B), irradiance
 * E_c(n) = sum_k sh[9 c + k] Y_k(n) with n in camera coordinates (docs/sfs.md). */
FRIG_API frig_status frig_photoset_sfs_lighting(const frig_photoset *set, size_t photo, double sh[27]);
/* The head pose refined against the recovered depth (model -> camera, as frig_photoset_fit_pose);
 * the fit's pose is kept as it was. The cloud is in the head frame of this pose. */
FRIG_API frig_status frig_photoset_sfs_pose(const frig_photoset *set, size_t photo, double rotation[9],
                                            double translation[3]);

/* Which solve the shape all photos share came from (docs/sfs.md, "J and the registration as the
 * default"): the full solve (the views' agreement, the model's identity modes, each photo's
 * registration and expression) or the light one (the shading's normals alone), which the stage
 * takes when fewer photos than sfs.joint_min_photos or more than sfs.joint_max_photos are judged,
 * or when the photos' lights fall on the face along one axis (sfs.joint_light). Of the stage's
 * last run on the set. */
typedef enum frig_sfs_solve {
    FRIG_SFS_SOLVE_NONE = 0,  /* the sfs stage has not run on the set */
    FRIG_SFS_SOLVE_FULL = 1,
    FRIG_SFS_SOLVE_LIGHT = 2
} frig_sfs_solve;
/* The solve; photos: the photos it judged; light_axis: the lights' concentration along one axis
 * (1: one axis, 1/3: spread evenly; the value sfs.joint_light is held against); why: for the light
 * solve "few_photos", "many_photos", "one_light_axis" or "outer_loop" (the clouds are the outer
 * loop's last recovery: retarget.sfs_light), else "" (a static string). Any output may be NULL;
 * with FRIG_SFS_SOLVE_NONE they are 0, 0 and "". */
FRIG_API frig_sfs_solve frig_photoset_sfs_solve(const frig_photoset *set, int *photos, double *light_axis,
                                                const char **why);

#ifdef __cplusplus
}
#endif
#endif /* FRIG_PHOTOSET_H */
