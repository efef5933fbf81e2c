/* libfrig detect stage (paper section 4.2, first half): face boxes from OpenCV's boosted
 * cascades (evaluated by our own code), then 68 landmarks per face from dlib's ensemble of
 * regression trees (evaluated by our own code). Data files come from Debian packages:
 * opencv-data (/usr/share/opencv4/haarcascades, lbpcascades) and libdlib-data
 * (/usr/share/dlib/shape_predictor_68_face_landmarks.dat).
 */
#ifndef FRIG_DETECT_H
#define FRIG_DETECT_H

#include "frig/image.h"
#include "frig/photoset.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct frig_detector frig_detector;

/* cascade_dir: folder holding the cascade XML files (NULL: /usr/share/opencv4);
 * landmark_model: dlib's .dat (NULL: /usr/share/dlib/shape_predictor_68_face_landmarks.dat).
 * A missing file fails with FRIG_ERR_NOT_FOUND and a sentence naming the Debian package.
 * Reads the detect.* parameters of ctx at creation. */
FRIG_API frig_status frig_detector_create(frig_ctx *ctx, const char *cascade_dir, const char *landmark_model,
                                          frig_detector **out);
FRIG_API void frig_detector_free(frig_detector *det);

/* Every face in the image: boxes (x, y, w, h; upright pixels, dlib's box convention after
 * calibration), scores, sources (frig_face_source) and 68 landmarks each. Arrays are
 * caller-allocated for max_faces faces; *count is the number found (may exceed max_faces:
 * only the first max_faces are written, largest first). Faces are sorted by decreasing
 * area. Safe to call concurrently on one detector from several threads. */
FRIG_API frig_status frig_detect_faces(frig_ctx *ctx, const frig_detector *det, const frig_image *image,
                                       size_t max_faces, size_t *count, double *boxes, double *scores,
                                       int *sources, double *landmarks);

/* 68 landmarks for a given box (x, y, w, h in dlib's convention), as dlib's predictor. */
FRIG_API frig_status frig_detect_landmarks(frig_ctx *ctx, const frig_detector *det, const frig_image *image,
                                           const double box[4], double landmarks[136]);

/* Run detection on every photo of a set: read it, find faces, landmarks, choose the subject
 * (largest and most central), set the status (ok / unreadable / no_face / face_too_small)
 * with a reason. Photos with user landmarks beside them (PHOTO.pts in iBUG format, or
 * PHOTO.landmarks.json) use those instead. Parallel across photos, deterministic. */
FRIG_API frig_status frig_detect_photoset(frig_ctx *ctx, const frig_detector *det, frig_photoset *set);

#ifdef __cplusplus
}
#endif
#endif /* FRIG_DETECT_H */
