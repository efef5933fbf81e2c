/* Faces from face-api's networks (npm @vladmandic/face-api, evaluated by lib/nn): the SSD
 * MobileNet v1 detector in place of the cascades, 68 landmarks from its landmark net (or from
 * dlib's predictor on the box mapped to dlib's convention), and a 128-D descriptor for every
 * face from its recognition net on the face chip aligned as the package aligns it (on the
 * landmark net's points). The identity step (lib/identity) uses the descriptors. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "detect/detector.h"
#include "detect/gray_like_dlib.h"
#include "image/image.h"

static fr_nn_image as_nn(const frig_image *img) {
    fr_nn_image v = {img->pixels, img->stride, img->width, img->height, img->channels};
    return v;
}

unsigned fr_detect_load_flags(const frig_detector *det) { return det && det->use_ssd ? FR_LOAD_LIKE_JPEG_JS : 0; }

frig_status fr_detect_ssd(frig_ctx *ctx, const frig_detector *det, const frig_image *image, fr_detected_face **faces,
                          size_t *count) {
    *faces = NULL;
    *count = 0;
    fr_nn_image in = as_nn(image);
    fr_ssd_face *boxes = NULL;
    size_t n = 0;
    frig_status st = fr_ssd_detect(ctx, det->nets->ssd, &in, det->ssd_min_score, 100, &boxes, &n);
    if (st || n == 0) return st;
    fr_detected_face *v = calloc(n, sizeof *v);
    if (!v) {
        free(boxes);
        return fr_nomem(ctx, "SSD faces");
    }
    frig_image *gray = NULL;
    if (det->landmark_source != 2) st = fr_gray_like_dlib(ctx, image, &gray);
    for (size_t i = 0; i < n && !st; i++) {
        fr_detected_face *f = &v[i];
        f->score = boxes[i].score;
        f->source = FRIG_FACE_SSD;
        fr_box_map m = fr_box_map_for(FRIG_FACE_SSD);
        fr_box_map_apply(&m, boxes[i].box, f->box);
        int crop[4];
        st = fr_landmark_net_run(ctx, det->nets->landmarks, &in, boxes[i].box, f->landmarks, crop);
        if (st == FRIG_ERR_NO_FACE) {
            /* a box with no pixels inside the photo: no face */
            frig_ctx_clear_error(ctx);
            st = FRIG_OK;
            f->score = -1;
            continue;
        }
        if (!st && det->descriptors) {
            st = fr_recognition_net_run(ctx, det->nets->recognition, &in, f->landmarks, crop[2], crop[3],
                                        f->descriptor);
            f->has_descriptor = !st;
        }
        /* dlib's predictor on the box its training used, placed by the net's points (1), or on
         * the SSD's box mapped to dlib's convention (3): on a face turned 30 degrees or more the
         * SSD's box covers the head and the predictor then draws a frontal face in it */
        int use_dlib = det->landmark_source == 3 || (det->landmark_source == 1 && fabs(fr_landmarks_turn(f->landmarks)) < det->net_turn);
        if (!st && det->landmark_source != 2) {
            double b[4];
            fr_box_from_landmarks(f->landmarks, b);
            if (det->landmark_source == 1 && b[2] >= 1 && b[3] >= 1 && isfinite(b[0]) && isfinite(b[1]))
                memcpy(f->box, b, sizeof b);
        }
        if (!st && use_dlib) st = fr_detect_landmarks_on(ctx, det, gray, f, 1);
    }
    frig_image_free(gray);
    free(boxes);
    size_t kept = 0;
    for (size_t i = 0; i < n; i++)
        if (v[i].score >= 0) v[kept++] = v[i];
    if (st || kept == 0) {
        free(v);
        return st;
    }
    *faces = v;
    *count = kept;
    return FRIG_OK;
}

frig_status fr_detect_descriptors(frig_ctx *ctx, const frig_detector *det, const frig_image *image,
                                  fr_detected_face *faces, size_t count) {
    if (!det || !det->nets || !det->descriptors) return FRIG_OK;
    fr_nn_image in = as_nn(image);
    for (size_t i = 0; i < count; i++) {
        if (faces[i].has_descriptor) continue;
        frig_status st = fr_recognition_net_run(ctx, det->nets->recognition, &in, faces[i].landmarks, image->width,
                                                image->height, faces[i].descriptor);
        if (st) return st;
        faces[i].has_descriptor = 1;
    }
    return FRIG_OK;
}
