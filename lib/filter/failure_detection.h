/* Failure detection for facial landmarks (section 4.2, Algorithm 1): robust PCA shape and texture
 * models of the current inliers, PCA reconstruction of every inlier, error
 * e = w_t RMSE(texture) + w_s sum_j ||p_j - p'_j||^2, drop e > mu + omega sigma, repeat until
 * nothing is dropped. Works on arrays; the photo set wiring lives elsewhere. Internal.
 *
 * Units (so that the paper's w_t = 1, w_s = 0.1 weigh the two terms comparably):
 * - textures are normalized for gain and bias (zero mean, unit standard deviation over the face,
 *   fr_face_texture), so RMSE(texture) is a relative error: 0 = perfect, 1 = the model explains
 *   nothing of the face's contrast;
 * - shapes are similarity-aligned (fr_filter_align_shapes) to a mean whose inter-ocular distance
 *   (outer eye corners 36-45) is FR_FILTER_SHAPE_IOD, so ||p - p'|| is in tenths of the
 *   inter-ocular distance. */
#ifndef FR_FILTER_FAILURE_DETECTION_H
#define FR_FILTER_FAILURE_DETECTION_H

#include "filter/face_warp.h"
#include "filter/pca_model.h"
#include "filter/robust_pca.h"
#include "frig/frig.h"

#define FR_FILTER_SHAPE_DIM 136
#define FR_FILTER_SHAPE_IOD 10.0

/* The centre and spread of the errors in "drop e > mu + omega sigma". */
typedef enum fr_filter_statistic {
    FR_FILTER_MEAN_STD = 0,  /* mean and standard deviation (Algorithm 1 as printed) */
    FR_FILTER_MEDIAN_MAD = 1 /* median and 1.4826 x the median absolute deviation (robust to the outliers) */
} fr_filter_statistic;

typedef struct fr_filter_options {
    double omega;      /* drop e > mu + omega sigma (filter.omega) */
    double w_texture;  /* w_t (filter.w_texture) */
    double w_shape;    /* w_s (filter.w_shape) */
    double pca_energy; /* variance kept by both PCA models (filter.pca_energy) */
    int max_rounds;    /* filter.max_rounds */
    int robust;        /* 1: PCA of the low-rank part of robust PCA (the paper); 0: plain PCA */
    fr_filter_statistic statistic;
    int score_all;     /* filter.score_all */
    int mirror;        /* filter.mirror */
    int peel_min;      /* filter.peel_min_faces: rounds after the first need this many inliers */
    fr_rpca_options rpca;
} fr_filter_options;

/* The filter.* parameters of the context, robust PCA with its defaults. */
void fr_filter_options_from_ctx(const frig_ctx *ctx, fr_filter_options *opt);

typedef struct fr_filter_result {
    double error;         /* e = w_t texture_error + w_s shape_error */
    double texture_error; /* RMSE of the normalized texture against its reconstruction */
    double shape_error;   /* sum over the 68 points of the squared distance to the reconstruction */
    int round_dropped;    /* 0: kept; else the round (1, 2, ...) in which the photo was dropped */
} fr_filter_result;

/* The shape and texture models of a set's inliers. A model not used (its data NULL) has k = 0
 * and dim = 0. */
typedef struct fr_filter_model {
    fr_pca texture, shape;
    double w_texture, w_shape;
} fr_filter_model;

void fr_filter_model_free(fr_filter_model *model);

/* Similarity-align count shapes (68 landmarks each, 136 x count, in photo pixels) to their
 * generalized Procrustes mean, in the units described above. mean (136) may be NULL. */
frig_status fr_filter_align_shapes(frig_ctx *ctx, int count, const double *landmarks, double *aligned,
                                   double *mean);

/* Algorithm 1 on count photos. textures: texels x count (from fr_face_texture), or NULL to use the
 * shapes alone; shapes: 136 x count aligned by fr_filter_align_shapes, or NULL to use the textures
 * alone. Writes one result per photo (a kept photo's errors are those of the last round; a dropped
 * photo's those of the round that dropped it), the number of rounds run (may be NULL) and, when
 * model is not NULL, the models of the final inliers. FRIG_ERR_TOO_FEW for fewer than 3 photos. */
frig_status fr_failure_detection(frig_ctx *ctx, int count, int texels, const double *textures, const double *shapes,
                                 const fr_filter_options *opt, fr_filter_result *results, int *rounds,
                                 fr_filter_model *model);

/* Errors of count faces (textures texels x count and aligned shapes 136 x count, either NULL when
 * the model does not use it) under a trained model; round_dropped is set to 0. */
frig_status fr_filter_score(frig_ctx *ctx, const fr_filter_model *model, int count, const double *textures,
                            const double *shapes, fr_filter_result *results);

/* Re-choose the subject of a photo with several faces: the face most consistent with the model
 * (smallest e). landmarks: 136 x faces in the image's pixels. Each face's texture is made with
 * 'warp' (which must be the warp that made the model's textures) and its shape aligned to the
 * model's mean shape. scores (faces values, may be NULL) get every face's errors; a face whose
 * texture is flat gets an infinite error. *best is the chosen face, or -1 when every face is flat. */
frig_status fr_filter_choose_face(frig_ctx *ctx, const fr_filter_model *model, const fr_face_warp *warp,
                                  const frig_image *image, int faces, const double *landmarks, int *best,
                                  fr_filter_result *scores);

#endif
