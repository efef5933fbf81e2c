/* The face-api model folder and its three networks. libfrig finds the folder as it finds
 * dlib's model: the caller's path, else $FRIG_FACE_MODELS, else the default that
 * scripts/install-deps.sh installs (/usr/local/share/frig/face-api/model, the model/ folder
 * of the npm package @vladmandic/face-api). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "core/context.h"
#include "nn/face_nets.h"

const char *fr_face_models_dir(const char *given) {
    if (given) return given;
    const char *env = getenv(FR_FACE_MODELS_ENV);
    return env && *env ? env : FR_FACE_MODELS_DEFAULT;
}

void fr_face_models_free(fr_face_models *m) {
    if (!m) return;
    fr_ssd_free(m->ssd);
    fr_landmark_net_free(m->landmarks);
    fr_recognition_net_free(m->recognition);
    free(m->dir);
    free(m);
}

frig_status fr_face_models_load(frig_ctx *ctx, const char *given, fr_face_models **out) {
    *out = NULL;
    const char *dir = fr_face_models_dir(given);
    struct stat st_dir;
    if (stat(dir, &st_dir) != 0 || !S_ISDIR(st_dir.st_mode))
        return fr_error(ctx, FRIG_ERR_NOT_FOUND,
                        "the face network folder %s does not exist (scripts/install-deps.sh installs the model/ folder "
                        "of the npm package @vladmandic/face-api there; or point %s or --face-models at one)",
                        dir, FR_FACE_MODELS_ENV);
    fr_face_models *m = calloc(1, sizeof *m);
    if (!m || !(m->dir = strdup(dir))) {
        free(m);
        return fr_nomem(ctx, "the face networks");
    }
    const char *names[3] = {FR_SSD_MODEL, FR_LANDMARK_MODEL, FR_RECOGNITION_MODEL};
    frig_status st = FRIG_OK;
    for (int k = 0; k < 3 && !st; k++) {
        fr_nn_weights *w = NULL;
        st = fr_nn_weights_load(ctx, dir, names[k], &w);
        if (!st && k == 0) st = fr_ssd_from(ctx, w, &m->ssd);
        if (!st && k == 1) st = fr_landmark_net_from(ctx, w, &m->landmarks);
        if (!st && k == 2) st = fr_recognition_net_from(ctx, w, &m->recognition);
        fr_nn_weights_free(w);
    }
    if (st) {
        fr_face_models_free(m);
        return st;
    }
    *out = m;
    return FRIG_OK;
}
