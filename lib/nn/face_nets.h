/* The face networks of the npm package @vladmandic/face-api (MIT), evaluated by our own C as
 * the package runs them (internal): the SSD MobileNet v1 face detector, the 68-point landmark
 * net, and the face recognition net (a port of dlib's ResNet: a 128-D descriptor per aligned
 * face). Loaded once, then only read: any number of threads may run them at once. */
#ifndef FR_NN_FACE_NETS_H
#define FR_NN_FACE_NETS_H

#include <stddef.h>
#include <stdint.h>

#include "frig/core.h"
#include "nn/weights.h"

#define FR_FACE_DESCRIPTOR_SIZE 128
#define FR_FACE_MODELS_ENV "FRIG_FACE_MODELS"
#define FR_FACE_MODELS_DEFAULT "/usr/local/share/frig/face-api/model"
#define FR_SSD_MODEL "ssd_mobilenetv1_model"
#define FR_LANDMARK_MODEL "face_landmark_68_model"
#define FR_RECOGNITION_MODEL "face_recognition_model"

/* An 8-bit image the networks read (1 or 3 channels, rows 'stride' bytes apart). */
typedef struct fr_nn_image {
    const uint8_t *pixels;
    size_t stride;
    int width, height, channels;
} fr_nn_image;

/* ---- SSD MobileNet v1 (ssd_mobilenet.c) ---- */
typedef struct fr_ssd fr_ssd;
typedef struct fr_ssd_face {
    double score;
    double box[4]; /* x, y, w, h in image pixels, as the package's FaceDetection.box */
} fr_ssd_face;

/* Each network from its weights (fr_nn_weights_load; every tensor's name and shape checked). */
frig_status fr_ssd_from(frig_ctx *ctx, const fr_nn_weights *w, fr_ssd **out);
void fr_ssd_free(fr_ssd *net);
/* Faces with score > min_score after the package's non-maximum suppression (IoU 0.5), at most
 * max_results, best first. The image is padded to a square at the bottom or right and resized
 * to 512 x 512, values scaled to [-1, 1]. *faces is a new array (free() it). */
frig_status fr_ssd_detect(frig_ctx *ctx, const fr_ssd *net, const fr_nn_image *img, double min_score, int max_results,
                          fr_ssd_face **faces, size_t *count);

/* ---- 68-point landmark net (landmark_net.c) ---- */
typedef struct fr_landmark_net fr_landmark_net;
frig_status fr_landmark_net_from(frig_ctx *ctx, const fr_nn_weights *w, fr_landmark_net **out);
void fr_landmark_net_free(fr_landmark_net *net);
/* The 68 points (x0, y0, ...) for a detection box (x, y, w, h), as the package computes them:
 * the box clipped to the image and floored, that crop padded to a centred square and resized
 * to 112, the net, and the points shifted by the box's unrounded corner.
 * crop (may be NULL) receives the crop's x, y, w, h. FRIG_ERR_NO_FACE when it is empty. */
frig_status fr_landmark_net_run(frig_ctx *ctx, const fr_landmark_net *net, const fr_nn_image *img,
                                const double box[4], double landmarks[136], int crop[4]);

/* ---- face recognition net (recognition_net.c) ---- */
typedef struct fr_recognition_net fr_recognition_net;
frig_status fr_recognition_net_from(frig_ctx *ctx, const fr_nn_weights *w, fr_recognition_net **out);
void fr_recognition_net_free(fr_recognition_net *net);
/* The package's face chip for 68 landmarks (FaceLandmarks.align with useDlibAlignment): a
 * square of side floor(mean eye-to-mouth distance / 0.45) placed by the centre of the eye and
 * mouth centres, its sides capped at ref_w + x and ref_h + y (the package caps them by the
 * size of the crop the landmarks came from: pass the landmark net's crop size, or the image's),
 * clipped to the width x height image and floored: x, y, w, h in whole pixels (w, h may be 0). */
void fr_face_chip_box(const double landmarks[136], int ref_w, int ref_h, int width, int height, int chip[4]);
/* The 128-D descriptor of the face with these landmarks (the chip padded to a centred square,
 * resized to 150, the net). A chip of no pixels gives zeros, as the package. */
frig_status fr_recognition_net_run(frig_ctx *ctx, const fr_recognition_net *net, const fr_nn_image *img,
                                   const double landmarks[136], int ref_w, int ref_h,
                                   float descriptor[FR_FACE_DESCRIPTOR_SIZE]);

/* ---- the three together (face_models.c) ---- */
typedef struct fr_face_models {
    char *dir;
    fr_ssd *ssd;
    fr_landmark_net *landmarks;
    fr_recognition_net *recognition;
} fr_face_models;

/* The model folder: 'given' when not NULL, else $FRIG_FACE_MODELS when set and not empty, else
 * FR_FACE_MODELS_DEFAULT. Returns a pointer to one of these (not a copy). */
const char *fr_face_models_dir(const char *given);
/* Load the three networks from fr_face_models_dir(given). A missing folder or manifest is
 * FRIG_ERR_NOT_FOUND with a sentence saying how to install the weights. */
frig_status fr_face_models_load(frig_ctx *ctx, const char *given, fr_face_models **out);
void fr_face_models_free(fr_face_models *m);

/* Euclidean distance of two descriptors. */
double fr_descriptor_distance(const float *a, const float *b);

#endif
