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

/* cascade_dir: folder holding haarcascade_frontalface_alt2.xml and haarcascade_profileface.xml,
 * directly or in its haarcascades/ subfolder (NULL: /usr/share/opencv4);
 * landmark_model: dlib's .dat (NULL: /usr/share/dlib/shape_predictor_68_face_landmarks.dat).
 * A missing file fails with FRIG_ERR_NOT_FOUND and a sentence naming the Debian package.
 * Reads the search parameters of ctx at creation (detect.scale_factor, min_neighbors,
 * min_face, profile, max_side); frig_detect_photoset reads detect.user_landmarks and
 * detect.min_eye_distance from its own ctx. */
FRIG_API frig_status frig_detector_create(frig_ctx *ctx, const char *cascade_dir, const char *landmark_model,
                                          frig_detector **out);
/* The same with face-api's networks (frig/identity.h, docs/identity.md): face_models is the
 * folder holding ssd_mobilenetv1_model, face_landmark_68_model and face_recognition_model
 * (*-weights_manifest.json + *.bin); NULL: $FRIG_FACE_MODELS, else
 * /usr/local/share/frig/face-api/model. With detect.detector 0 (the default) the SSD detector
 * replaces the cascades when the networks are found there, and the cascades are used when
 * they are not (a folder given here must hold them); 2 requires them, 1 keeps the cascades.
 * With detect.descriptors 1 every face gets a 128-D descriptor when the networks are loaded.
 * frig_detector_create is this with face_models NULL. Damaged weights fail with
 * FRIG_ERR_CORRUPT / FRIG_ERR_TRUNCATED and a sentence naming the file. */
FRIG_API frig_status frig_detector_create_with(frig_ctx *ctx, const char *cascade_dir, const char *landmark_model,
                                               const char *face_models, frig_detector **out);
/* 1 when the detector runs face-api's SSD detector, 0 for the cascades; 1 in *descriptors when
 * it computes descriptors (may be NULL). */
FRIG_API int frig_detector_uses_ssd(const frig_detector *det, int *descriptors);
FRIG_API void frig_detector_free(frig_detector *det);

/* Every face in the image (an upright RGB photo; gray works too): boxes (x, y, w, h in the
 * image's pixels, calibrated to dlib's HOG box convention: dlib's rectangle is (x, y,
 * x + w - 1, y + h - 1)), scores (the cascade's neighbour count), sources
 * (frig_face_source) and 68 landmarks each (x0, y0, ... x67, y67: 136 doubles per face).
 * Arrays are caller-allocated for max_faces faces (4, 1, 1 and 136 values per face);
 * *count is the number found (may exceed max_faces: only the first max_faces are
 * written). Faces are sorted by decreasing box area. The frontal cascade runs on OpenCV's
 * gray of the image, the profile cascade (and on the mirrored image) only when it finds
 * nothing and detect.profile is 1; images longer than detect.max_side are searched on a
 * downscaled copy; landmarks use dlib's gray at full resolution. Safe to call concurrently
 * on one detector from several threads (each with its own ctx). */
FRIG_API frig_status frig_detect_faces(frig_ctx *ctx, const frig_detector *det, const frig_image *image,
                                       size_t max_faces, size_t *count, double *boxes, double *scores,
                                       int *sources, double *landmarks);

/* 68 landmarks for a given box (x, y, w, h in dlib's convention, as above), as dlib's predictor
 * gives them on dlib's gray of the image (unrounded). */
FRIG_API frig_status frig_detect_landmarks(frig_ctx *ctx, const frig_detector *det, const frig_image *image,
                                           const double box[4], double landmarks[136]);

/* Run detection on every photo of a set: read it once (upright RGB), find faces and their
 * landmarks, choose the subject (largest and most central usable face, see docs/detect.md),
 * set the status (ok / unreadable / no_face / face_too_small) with a reason. Photos with
 * user landmarks beside them (STEM.pts in iBUG format, or STEM.landmarks.json, STEM being
 * the photo's path without extension; parameter detect.user_landmarks) use those instead.
 * Parallel across photos (progress stage "detect"), deterministic whatever the thread count.
 * A bad photo only gets its status: the call fails only when out of memory or cancelled. */
FRIG_API frig_status frig_detect_photoset(frig_ctx *ctx, const frig_detector *det, frig_photoset *set);

/* run: detection in batches, for callers that save progress between them (frig run resumes
 * an interrupted detect at its first pending photo). frig_detect_photoset is
 * frig_detect_photoset_range over every photo, then frig_detect_mark_duplicates when
 * detect.duplicates is 1; a photo's result does not depend on the batches. */
FRIG_API frig_status frig_detect_photoset_range(frig_ctx *ctx, const frig_detector *det, frig_photoset *set,
                                                size_t first, size_t count);
/* Mark every usable photo whose file has the same bytes as an earlier usable photo of the set
 * FRIG_PHOTO_DUPLICATE, the reason naming the first copy. */
FRIG_API frig_status frig_detect_mark_duplicates(frig_ctx *ctx, frig_photoset *set);

/* One JPEG per photo in dir (created if needed), named NNN_STEM.jpg after the photo's index
 * in the set: the photo with every face's box (the subject's thick and green, other faces
 * yellow, user-supplied faces blue), the landmarks, and the status written in the corner;
 * unreadable photos get a gray card with their reason. Parallel, progress stage "overlays". */
FRIG_API frig_status frig_detect_write_overlays(frig_ctx *ctx, const frig_photoset *set, const char *dir);

#ifdef __cplusplus
}
#endif
#endif /* FRIG_DETECT_H */
