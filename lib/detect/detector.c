/* The detector handle (paper section 4.2): OpenCV's frontal (alt2) and profile cascades from
 * Debian's opencv-data and dlib's 68-point predictor from libdlib-data, and face-api's networks
 * (SSD detector, landmark and recognition nets) where installed, loaded once and only read
 * afterwards, so one detector serves many threads. A missing file names its package. */
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "core/context.h"
#include "detect/detector.h"
#include "io/file.h"

static int is_file(const char *path) {
    struct stat st;
    return stat(path, &st) == 0 && S_ISREG(st.st_mode);
}

/* DIR/haarcascades/NAME, else DIR/NAME: a new string, or NULL with the error set. */
static char *cascade_path(frig_ctx *ctx, const char *dir, const char *name, frig_status *st) {
    char *sub = fr_path_join(dir, "haarcascades");
    char *p = sub ? fr_path_join(sub, name) : NULL;
    free(sub);
    if (p && !is_file(p)) {
        free(p);
        p = fr_path_join(dir, name);
        if (p && !is_file(p)) {
            *st = fr_error(ctx, FRIG_ERR_NOT_FOUND,
                           "the face cascade %s is not in %s/haarcascades nor in %s "
                           "(install Debian's opencv-data package: apt-get install opencv-data)",
                           name, dir, dir);
            free(p);
            return NULL;
        }
    }
    if (!p) *st = fr_nomem(ctx, "a cascade path");
    return p;
}

static frig_status load_cascade(frig_ctx *ctx, const char *dir, const char *name, fr_cascade **out) {
    frig_status st = FRIG_OK;
    char *path = cascade_path(ctx, dir, name, &st);
    if (!path) return st;
    st = fr_cascade_load(ctx, path, out);
    free(path);
    return st;
}

void frig_detector_free(frig_detector *det) {
    if (!det) return;
    fr_cascade_free(det->frontal);
    fr_cascade_free(det->profile);
    fr_shape_predictor_free(det->sp);
    fr_face_models_free(det->nets);
    free(det);
}

/* face-api's networks as detect.detector and detect.descriptors ask: NULL and no error when
 * they are optional and not installed. */
static frig_status load_nets(frig_ctx *ctx, const char *face_models, frig_detector *det) {
    int mode = fr_param_int(ctx, FRIG_PARAM_DETECT_DETECTOR);
    det->descriptors = fr_param_int(ctx, FRIG_PARAM_DETECT_DESCRIPTORS);
    det->landmark_source = fr_param_int(ctx, FRIG_PARAM_DETECT_LANDMARKS);
    det->net_turn = fr_param(ctx, FRIG_PARAM_DETECT_NET_TURN);
    det->ssd_min_score = fr_param(ctx, FRIG_PARAM_DETECT_SSD_MIN_SCORE);
    det->ssd_fallback = fr_param_int(ctx, FRIG_PARAM_DETECT_SSD_FALLBACK);
    if (mode == 1 && !det->descriptors) return FRIG_OK;
    frig_status st = fr_face_models_load(ctx, face_models, &det->nets);
    if (st == FRIG_ERR_NOT_FOUND && mode != 2 && !face_models) {
        fr_log(ctx, FRIG_LOG_INFO, "%s; detecting with the cascades, without descriptors", frig_ctx_errmsg(ctx));
        frig_ctx_clear_error(ctx);
        return FRIG_OK;
    }
    if (st) return st;
    det->use_ssd = mode != 1;
    return FRIG_OK;
}

frig_status frig_detector_create(frig_ctx *ctx, const char *cascade_dir, const char *landmark_model,
                                 frig_detector **out) {
    return frig_detector_create_with(ctx, cascade_dir, landmark_model, NULL, out);
}

frig_status frig_detector_create_with(frig_ctx *ctx, const char *cascade_dir, const char *landmark_model,
                                      const char *face_models, frig_detector **out) {
    if (!out) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_detector_create: NULL output");
    *out = NULL;
    const char *dir = cascade_dir ? cascade_dir : FR_DETECT_DEFAULT_CASCADE_DIR;
    const char *model = landmark_model ? landmark_model : FR_DETECT_DEFAULT_LANDMARK_MODEL;
    if (!is_file(model))
        return fr_error(ctx, FRIG_ERR_NOT_FOUND,
                        "the landmark model %s does not exist (install Debian's libdlib-data package: "
                        "apt-get install libdlib-data)",
                        model);
    frig_detector *det = calloc(1, sizeof *det);
    if (!det) return fr_nomem(ctx, "a detector");
    det->scale_factor = fr_param(ctx, FRIG_PARAM_DETECT_SCALE_FACTOR);
    det->min_neighbors = fr_param_int(ctx, FRIG_PARAM_DETECT_MIN_NEIGHBORS);
    det->min_face = fr_param_int(ctx, FRIG_PARAM_DETECT_MIN_FACE);
    det->profile_fallback = fr_param_int(ctx, FRIG_PARAM_DETECT_PROFILE);
    det->max_side = fr_param_int(ctx, FRIG_PARAM_DETECT_MAX_SIDE);
    det->coarse_side = fr_param_int(ctx, FRIG_PARAM_DETECT_COARSE_SIDE);
    frig_status st = load_cascade(ctx, dir, FR_DETECT_FRONTAL_FILE, &det->frontal);
    if (!st && det->profile_fallback) st = load_cascade(ctx, dir, FR_DETECT_PROFILE_FILE, &det->profile);
    if (!st) st = fr_shape_predictor_load(ctx, model, &det->sp);
    if (!st) st = load_nets(ctx, face_models, det);
    if (!st && fr_shape_predictor_num_parts(det->sp) != FRIG_LANDMARK_COUNT)
        st = fr_error(ctx, FRIG_ERR_UNSUPPORTED, "%s predicts %d landmarks; the detect stage needs dlib's 68-point model",
                      model, fr_shape_predictor_num_parts(det->sp));
    if (st) {
        frig_detector_free(det);
        return st;
    }
    *out = det;
    return FRIG_OK;
}

int frig_detector_uses_ssd(const frig_detector *det, int *descriptors) {
    if (descriptors) *descriptors = det && det->nets && det->descriptors;
    return det && det->use_ssd;
}
