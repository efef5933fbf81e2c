/* Faces in one photo (paper section 4.2, first half): from the upright RGB photo, OpenCV's gray
 * for the cascades and dlib's gray for the landmark predictor; cascade boxes calibrated to
 * dlib's HOG box convention (box_calibration.c), then dlib's 68 points at full resolution. */
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "detect/detector.h"
#include "detect/gray_like_dlib.h"
#include "image/image.h"

frig_status fr_detect_landmarks_on(frig_ctx *ctx, const frig_detector *det, const frig_image *g,
                                   fr_detected_face *faces, size_t count) {
    for (size_t i = 0; i < count; i++) {
        double ltrb[4];
        fr_box_to_ltrb(faces[i].box, ltrb);
        frig_status st = fr_shape_predictor_run(det->sp, g->pixels, g->width, g->height, g->stride, ltrb,
                                                faces[i].landmarks);
        if (st) return fr_error(ctx, st, "landmarks: bad face box (%g, %g, %g, %g)", faces[i].box[0], faces[i].box[1],
                                faces[i].box[2], faces[i].box[3]);
    }
    return FRIG_OK;
}

/* Decreasing area; ties top-left first (a total order on distinct boxes). */
static int by_area(const void *pa, const void *pb) {
    const fr_detected_face *a = pa, *b = pb;
    double aa = a->box[2] * a->box[3], ab = b->box[2] * b->box[3];
    if (aa != ab) return aa > ab ? -1 : 1;
    if (a->box[1] != b->box[1]) return a->box[1] < b->box[1] ? -1 : 1;
    if (a->box[0] != b->box[0]) return a->box[0] < b->box[0] ? -1 : 1;
    return a->source - b->source;
}

frig_status fr_detect_image(frig_ctx *ctx, const frig_detector *det, const frig_image *image, int calibrate,
                            fr_detected_face **faces, size_t *count) {
    if (!det || !image || !faces || !count)
        return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "face detection: NULL argument");
    *faces = NULL;
    *count = 0;
    frig_image *cv_gray = NULL, *dlib_gray = NULL;
    fr_detected_face *v = NULL;
    size_t n = 0;
    if (det->use_ssd) {
        frig_status st = fr_detect_ssd(ctx, det, image, &v, &n);
        if (!st && n > 0) qsort(v, n, sizeof *v, by_area);
        if (st || n > 0 || !det->ssd_fallback) {
            if (st) free(v);
            *faces = st ? NULL : v;
            *count = st ? 0 : n;
            return st;
        }
        free(v); /* nothing found: the cascades search, as without the networks */
        v = NULL;
    }
    frig_status st = fr_gray_like_opencv(ctx, image, &cv_gray);
    if (!st) st = fr_detect_boxes(ctx, det, cv_gray, &v, &n);
    frig_image_free(cv_gray);
    if (!st && n > 0) {
        for (size_t i = 0; calibrate && i < n; i++) {
            fr_box_map m = fr_box_map_for(v[i].source);
            double raw[4];
            memcpy(raw, v[i].box, sizeof raw);
            fr_box_map_apply(&m, raw, v[i].box);
        }
        st = fr_gray_like_dlib(ctx, image, &dlib_gray);
        if (!st) st = fr_detect_landmarks_on(ctx, det, dlib_gray, v, n);
        frig_image_free(dlib_gray);
        if (!st) st = fr_detect_descriptors(ctx, det, image, v, n);
        qsort(v, n, sizeof *v, by_area);
    }
    if (st) {
        free(v);
        return st;
    }
    *faces = v;
    *count = n;
    return FRIG_OK;
}

frig_status frig_detect_faces(frig_ctx *ctx, const frig_detector *det, const frig_image *image, size_t max_faces,
                              size_t *count, double *boxes, double *scores, int *sources, double *landmarks) {
    if (!count) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_detect_faces: NULL count");
    *count = 0;
    if (max_faces > 0 && (!boxes || !scores || !sources || !landmarks))
        return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_detect_faces: NULL output array for %zu faces", max_faces);
    fr_detected_face *v;
    size_t n;
    frig_status st = fr_detect_image(ctx, det, image, 1, &v, &n);
    if (st) return st;
    for (size_t i = 0; i < n && i < max_faces; i++) {
        memcpy(boxes + 4 * i, v[i].box, sizeof v[i].box);
        scores[i] = v[i].score;
        sources[i] = v[i].source;
        memcpy(landmarks + 2 * FRIG_LANDMARK_COUNT * i, v[i].landmarks, sizeof v[i].landmarks);
    }
    free(v);
    *count = n;
    return FRIG_OK;
}

frig_status frig_detect_landmarks(frig_ctx *ctx, const frig_detector *det, const frig_image *image,
                                  const double box[4], double landmarks[136]) {
    if (!det || !image || !box || !landmarks)
        return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_detect_landmarks: NULL argument");
    frig_image *g;
    frig_status st = fr_gray_like_dlib(ctx, image, &g);
    if (st) return st;
    fr_detected_face f;
    memset(&f, 0, sizeof f);
    memcpy(f.box, box, sizeof f.box);
    st = fr_detect_landmarks_on(ctx, det, g, &f, 1);
    frig_image_free(g);
    if (!st) memcpy(landmarks, f.landmarks, sizeof f.landmarks);
    return st;
}
