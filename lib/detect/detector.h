/* The detect stage's inside (paper section 4.2, first half): the detector handle (OpenCV's
 * frontal and profile cascades, dlib's 68-point predictor), and the steps frig_detect_faces
 * chains: the two gray images, boxes from the cascades, the box calibration to dlib's HOG
 * convention, the merge, subject choice and user-supplied landmarks. Internal. */
#ifndef FR_DETECT_DETECTOR_H
#define FR_DETECT_DETECTOR_H

#include "detect/cascade.h"
#include "detect/shape_predictor.h"
#include "frig/detect.h"
#include "frig/identity.h"
#include "nn/face_nets.h"

#define FR_DETECT_DEFAULT_CASCADE_DIR "/usr/share/opencv4"
#define FR_DETECT_DEFAULT_LANDMARK_MODEL "/usr/share/dlib/shape_predictor_68_face_landmarks.dat"
#define FR_DETECT_FRONTAL_FILE "haarcascade_frontalface_alt2.xml"
#define FR_DETECT_PROFILE_FILE "haarcascade_profileface.xml"

struct frig_detector {
    fr_cascade *frontal, *profile;
    fr_shape_predictor *sp;
    /* detect.* parameters, read at creation */
    double scale_factor;
    int min_neighbors, min_face, profile_fallback, max_side, coarse_side;
    /* face-api's networks (NULL when not installed and detect.detector is 0): the SSD detector
     * replaces the cascades when use_ssd; descriptors for every face when descriptors */
    fr_face_models *nets;
    int use_ssd, landmark_source, descriptors, ssd_fallback;
    double ssd_min_score, net_turn;
};

/* A face on its way through the stage: box x, y, w, h (upright pixels; after calibration in
 * dlib's convention: the dlib rectangle is (x, y, x + w - 1, y + h - 1)). */
typedef struct fr_detected_face {
    double box[4];
    double score;
    int source; /* frig_face_source */
    double landmarks[2 * FRIG_LANDMARK_COUNT];
    int has_descriptor;
    float descriptor[FRIG_DESCRIPTOR_SIZE];
} fr_detected_face;

/* The flags the stage decodes photos with: as jpeg-js does when the SSD detector runs (its
 * reference answers were made on jpeg-js's pixels), else the default decode. */
unsigned fr_detect_load_flags(const frig_detector *det);

/* ---- gray images (gray_like_opencv.c) ---- */
/* The gray image OpenCV's IMREAD_GRAYSCALE gives, computed from decoded RGB: for a PNG source
 * libpng's rgb_to_gray (9797, 19234, 3737)/32768 truncated, as OpenCV asks libpng for it (the
 * very bytes); otherwise cvtColor's BT.601 (4899, 9617, 1868)/16384 rounded, which is within a
 * grey level or so of libjpeg's own luma (see docs/detect.md). A gray image is copied. */
frig_status fr_gray_like_opencv(frig_ctx *ctx, const frig_image *rgb, frig_image **out);

/* ---- boxes (detect_boxes.c) ---- */
typedef enum fr_detect_cascades {
    FR_DETECT_RUN_FRONTAL = 1,
    FR_DETECT_RUN_PROFILE = 2,
    FR_DETECT_RUN_PROFILE_MIRRORED = 4
} fr_detect_cascades;

/* Raw cascade boxes (not calibrated) of the chosen cascades on an OpenCV-like gray image, in
 * its pixels: detection runs on a copy downscaled to det->max_side when the image is larger
 * and the boxes are scaled back. Each box's source is the cascade that found it, score its
 * neighbour count. *faces is a new array (free() it; NULL when none). No merging. */
frig_status fr_detect_cascade_boxes(frig_ctx *ctx, const frig_detector *det, const frig_image *gray, unsigned which,
                                    fr_detected_face **faces, size_t *count);

/* The frontal cascade as the stage runs it: on a copy no larger than det->coarse_side first
 * (when that is smaller than the photo and than det->max_side), then, only if that finds no
 * face, at det->max_side. Large photos of one person are searched at a third of the cost. */
frig_status fr_detect_frontal(frig_ctx *ctx, const frig_detector *det, const frig_image *gray, fr_detected_face **faces,
                              size_t *count);

/* The stage's boxes: fr_detect_frontal; when it finds nothing and detect.profile is 1, the
 * profile cascade on the photo and on its mirror image, merged by fr_detect_merge. */
frig_status fr_detect_boxes(frig_ctx *ctx, const frig_detector *det, const frig_image *gray, fr_detected_face **faces,
                            size_t *count);

/* Non-maximum suppression in place: faces are taken in order of source (frontal first), then
 * larger score, then larger area; a face whose box overlaps a kept one with IoU >= 0.3 (or
 * lies mostly inside it: intersection >= 0.7 of the smaller box) is dropped. Returns the
 * number kept, in the order kept. */
size_t fr_detect_merge(fr_detected_face *faces, size_t count);
double fr_box_iou(const double a[4], const double b[4]);

/* ---- calibration (box_calibration.c) ---- */
/* Per-axis map of a raw cascade box to dlib's HOG box of the same face:
 * (x + a w, y + b h, c w, d h). */
typedef struct fr_box_map {
    double a, b, c, d;
} fr_box_map;
/* The measured map for a source (FRIG_FACE_FRONTAL, _PROFILE, _PROFILE_MIRRORED); the
 * identity for others. */
fr_box_map fr_box_map_for(int source);
void fr_box_map_apply(const fr_box_map *m, const double raw[4], double out[4]);
/* dlib's HOG box (x, y, w, h) of a face from its 68 points (measured map, box_calibration.c):
 * the box for dlib's predictor from another model's points (face-api's landmark net). */
void fr_box_from_landmarks(const double *landmarks, double box[4]);
/* How far the face of 68 points is turned: the nose tip's place between the outline's sides
 * at its height, -1 .. 1 (0 frontal). */
double fr_landmarks_turn(const double *landmarks);
/* dlib rectangle (left, top, right, bottom) of an x, y, w, h box. */
void fr_box_to_ltrb(const double box[4], double ltrb[4]);

/* ---- landmarks and the whole image (detect_faces.c) ---- */
/* Every face of an upright RGB (or gray) image: boxes, calibration when 'calibrate', 68
 * landmarks each on dlib's gray at full resolution; sorted by decreasing box area (ties:
 * top-left first). *faces is a new array (free() it). */
frig_status fr_detect_image(frig_ctx *ctx, const frig_detector *det, const frig_image *image, int calibrate,
                            fr_detected_face **faces, size_t *count);
/* Landmarks for the faces' boxes (dlib convention), on dlib's gray image. */
frig_status fr_detect_landmarks_on(frig_ctx *ctx, const frig_detector *det, const frig_image *dlib_gray,
                                   fr_detected_face *faces, size_t count);

/* ---- face-api's networks (detect_ssd.c) ---- */
/* SSD faces of an upright RGB image: boxes (mapped to dlib's convention), scores, landmarks
 * (face-api's net, or dlib's predictor on dlib_gray when det->landmark_source is 1) and
 * descriptors. *faces is a new array (free() it). */
frig_status fr_detect_ssd(frig_ctx *ctx, const frig_detector *det, const frig_image *image, fr_detected_face **faces,
                          size_t *count);
/* Descriptors for faces that have landmarks but none yet (cascade or user faces): the face
 * chip aligned on their landmarks as the package aligns it. No-op without the networks. */
frig_status fr_detect_descriptors(frig_ctx *ctx, const frig_detector *det, const frig_image *image,
                                  fr_detected_face *faces, size_t count);

/* ---- subject (subject.c) ---- */
/* Outer eye corners' distance (points 36 and 45). */
double fr_face_eye_distance(const double *landmarks);
/* The subject among faces of a width x height photo: the usable face (eye distance >=
 * min_eye_distance) with the highest fr_subject_score; when none is usable, the best of all
 * and *too_small = 1. -1 when count is 0. */
long fr_choose_subject(const fr_detected_face *faces, size_t count, int width, int height, double min_eye_distance,
                       int *too_small);
/* sqrt(box area) * (1 - 0.5 * distance of the box centre from the photo centre / half its
 * diagonal): the largest face wins unless a smaller one is much more central. */
double fr_subject_score(const double box[4], int width, int height);

/* ---- user landmarks (user_landmarks.c) ---- */
/* Landmarks supplied beside a photo: STEM.pts (iBUG, 1-based) or STEM.landmarks.json, where
 * STEM is the photo's path without its extension. FRIG_OK with *count 0 when neither exists;
 * an unreadable or malformed file is FRIG_ERR_CORRUPT with a sentence. *file receives the
 * file used (new string) or NULL. */
frig_status fr_user_landmarks(frig_ctx *ctx, const char *photo_path, fr_detected_face **faces, size_t *count,
                              char **file);
/* One face from an iBUG .pts file, shifted to 0-based; landmarks untouched on failure. */
frig_status fr_read_pts(frig_ctx *ctx, const char *path, double *landmarks);
frig_status fr_read_landmarks_json(frig_ctx *ctx, const char *path, fr_detected_face **faces, size_t *count);

#endif
