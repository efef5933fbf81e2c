/* The detect stage over a photo set (paper section 4.2, first half): each photo read once as
 * upright RGB, its faces found (or taken from the user's landmark files), the subject chosen
 * and the photo's status set. Parallel across photos, each photo in its own slot, so the
 * result is the same whatever the thread count; one bad photo never stops the run. */
#include <stdio.h>
#include <stdlib.h>

#include "core/context.h"
#include "detect/detector.h"
#include "detect/duplicates.h"
#include "image/image.h"
#include "workspace/photoset.h"

/* Store faces and the subject; the status follows from them. */
static frig_status store_faces(frig_ctx *ctx, frig_photoset *set, size_t i, const fr_detected_face *v, size_t n,
                               double min_eye) {
    fr_photo *p = &set->photos[i];
    frig_status st = frig_photoset_clear_faces(ctx, set, i);
    for (size_t k = 0; k < n && !st; k++) {
        size_t face = 0;
        st = frig_photoset_add_face(ctx, set, i, v[k].box, v[k].score, (frig_face_source)v[k].source, v[k].landmarks,
                                    &face);
        if (!st && v[k].has_descriptor) st = frig_photoset_set_face_descriptor(ctx, set, i, face, v[k].descriptor);
    }
    if (st) return st;
    int too_small = 0;
    long subject = fr_choose_subject(v, n, p->width, p->height, min_eye, &too_small);
    st = frig_photoset_set_subject(ctx, set, i, subject);
    if (st) return st;
    if (n == 0) return frig_photoset_set_status(ctx, set, i, FRIG_PHOTO_NO_FACE, "no face found");
    if (too_small) {
        char reason[160];
        snprintf(reason, sizeof reason,
                 "the largest face's eyes are %.1f px apart, under detect.min_eye_distance = %g px",
                 fr_face_eye_distance(v[subject].landmarks), min_eye);
        return frig_photoset_set_status(ctx, set, i, FRIG_PHOTO_FACE_TOO_SMALL, reason);
    }
    return frig_photoset_set_status(ctx, set, i, FRIG_PHOTO_OK, NULL);
}

/* One photo; a status other than OK is a failure of the run (out of memory, cancelled),
 * not of the photo, and 'child' holds its sentence. */
static frig_status detect_photo(frig_ctx *child, const frig_detector *det, frig_photoset *set, size_t i) {
    fr_photo *p = &set->photos[i];
    frig_photoset_clear_faces(child, set, i);
    frig_image *img = NULL;
    frig_status st = frig_image_load(child, p->path, fr_detect_load_flags(det), &img);
    if (st == FRIG_ERR_NO_MEMORY) return st;
    if (st) return frig_photoset_set_status(child, set, i, FRIG_PHOTO_UNREADABLE, frig_ctx_errmsg(child));
    p->width = img->width;
    p->height = img->height;
    fr_detected_face *v = NULL;
    size_t n = 0;
    char *user_file = NULL;
    if (fr_param_int(child, FRIG_PARAM_DETECT_USER_LANDMARKS)) {
        st = fr_user_landmarks(child, p->path, &v, &n, &user_file);
        if (st && st != FRIG_ERR_NO_MEMORY) {
            frig_image_free(img);
            return frig_photoset_set_status(child, set, i, FRIG_PHOTO_UNREADABLE, frig_ctx_errmsg(child));
        }
    }
    if (!st && !user_file) st = fr_detect_image(child, det, img, 1, &v, &n);
    else if (!st) st = fr_detect_descriptors(child, det, img, v, n);
    frig_image_free(img);
    if (!st) {
        st = store_faces(child, set, i, v, n, fr_param(child, FRIG_PARAM_DETECT_MIN_EYE_DISTANCE));
        if (!st && user_file && p->status == FRIG_PHOTO_OK) {
            char reason[4200];
            snprintf(reason, sizeof reason, "landmarks from %s", user_file);
            st = frig_photoset_set_status(child, set, i, FRIG_PHOTO_OK, reason);
        }
    }
    free(v);
    free(user_file);
    return st;
}

typedef struct photo_job {
    const frig_detector *det;
    frig_photoset *set;
    size_t first;
} photo_job;

/* The loop's item: a failure of the run gets the photo's path in front of its sentence. */
static frig_status photo_item(frig_ctx *child, size_t i, void *user) {
    const photo_job *job = user;
    frig_photoset *set = job->set;
    i += job->first;
    frig_status st = detect_photo(child, job->det, set, i);
    if (st) {
        char msg[FR_ERRMSG_SIZE];
        snprintf(msg, sizeof msg, "%s", frig_ctx_errmsg(child));
        frig_ctx_clear_error(child);
        fr_error(child, st, "%s: %s", set->photos[i].path, msg);
    }
    return st;
}

frig_status frig_detect_photoset_range(frig_ctx *ctx, const frig_detector *det, frig_photoset *set, size_t first,
                                       size_t count) {
    if (!det || !set) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_detect_photoset_range: NULL argument");
    if (first > set->count || count > set->count - first)
        return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "photos %zu to %zu of a set of %zu", first, first + count,
                        set->count);
    photo_job job = {det, set, first};
    int saved = fr_blas_serial_begin();
    frig_status st = fr_parallel_items(ctx, count, "detect", photo_item, &job);
    fr_blas_serial_end(saved);
    return st;
}

frig_status frig_detect_mark_duplicates(frig_ctx *ctx, frig_photoset *set) {
    if (!set) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_detect_mark_duplicates: no photo set");
    return fr_mark_duplicates(ctx, set);
}

frig_status frig_detect_photoset(frig_ctx *ctx, const frig_detector *det, frig_photoset *set) {
    if (!det || !set) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_detect_photoset: NULL argument");
    frig_status st = frig_detect_photoset_range(ctx, det, set, 0, set->count);
    if (!st && fr_param_int(ctx, FRIG_PARAM_DETECT_DUPLICATES)) st = fr_mark_duplicates(ctx, set);
    return st;
}
