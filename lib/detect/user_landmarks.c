/* Bring-your-own landmarks (docs/detect.md): a user with a better landmark detector puts its
 * 68 iBUG points beside the photo, as STEM.pts (iBUG/300-W format, 1-based pixels) or
 * STEM.landmarks.json ({"landmarks": [[x, y] x 68]} or {"faces": [{"landmarks": ...}, ...]},
 * 0-based upright pixels), and the detect stage uses them instead of its own. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include <cJSON.h>

#include "core/context.h"
#include "detect/detector.h"
#include "io/file.h"

#define USER_FILE_MAX (16u << 20)

/* The landmarks' bounding box as the face box; the score is 1. */
static void user_face(fr_detected_face *f, const double *lm) {
    memset(f, 0, sizeof *f);
    memcpy(f->landmarks, lm, sizeof f->landmarks);
    double x0 = lm[0], x1 = lm[0], y0 = lm[1], y1 = lm[1];
    for (int i = 1; i < FRIG_LANDMARK_COUNT; i++) {
        x0 = fmin(x0, lm[2 * i]);
        x1 = fmax(x1, lm[2 * i]);
        y0 = fmin(y0, lm[2 * i + 1]);
        y1 = fmax(y1, lm[2 * i + 1]);
    }
    f->box[0] = x0;
    f->box[1] = y0;
    f->box[2] = x1 - x0;
    f->box[3] = y1 - y0;
    f->score = 1.0;
    f->source = FRIG_FACE_USER;
}

static int plausible(double v) { return isfinite(v) && fabs(v) < 1e7; }

frig_status fr_read_pts(frig_ctx *ctx, const char *path, double *lm) {
    unsigned char *data;
    size_t size;
    frig_status st = fr_read_file(ctx, path, USER_FILE_MAX, &data, &size);
    if (st) return st;
    /* A NUL-terminated copy for strtod. */
    char *text = malloc(size + 1);
    if (!text) {
        free(data);
        return fr_nomem(ctx, "a .pts file");
    }
    memcpy(text, data, size);
    text[size] = 0;
    free(data);
    const char *brace = strchr(text, '{');
    const char *np = strstr(text, "n_points");
    long declared = -1;
    if (np && (!brace || np < brace)) {
        const char *c = strchr(np, ':');
        if (c) declared = strtol(c + 1, NULL, 10);
    }
    int n = 0, bad_value = 0;
    double pts[2 * FRIG_LANDMARK_COUNT];
    const char *p = brace ? brace + 1 : NULL;
    while (p && n <= FRIG_LANDMARK_COUNT && !bad_value) {
        char *end;
        double x = strtod(p, &end);
        if (end == p) break;
        p = end;
        double y = strtod(p, &end);
        if (end == p) break;
        p = end;
        bad_value = !plausible(x) || !plausible(y);
        if (n < FRIG_LANDMARK_COUNT) {
            pts[2 * n] = x - 1.0; /* iBUG files are 1-based (Matlab) */
            pts[2 * n + 1] = y - 1.0;
        }
        n++;
    }
    while (p && (*p == ' ' || *p == '\t' || *p == '\r' || *p == '\n')) p++;
    int closed = p && *p == '}';
    free(text);
    if (!brace || !closed || bad_value || n != FRIG_LANDMARK_COUNT || (declared >= 0 && declared != FRIG_LANDMARK_COUNT))
        return fr_error(ctx, FRIG_ERR_CORRUPT,
                        "%s is not a 68-point iBUG .pts file (want 'n_points: 68' and { 68 lines of 'x y' })", path);
    memcpy(lm, pts, sizeof pts);
    return FRIG_OK;
}

static int json_points(const cJSON *arr, double *lm) {
    if (!cJSON_IsArray(arr) || cJSON_GetArraySize(arr) != FRIG_LANDMARK_COUNT) return 0;
    for (int i = 0; i < FRIG_LANDMARK_COUNT; i++) {
        const cJSON *pt = cJSON_GetArrayItem(arr, i);
        const cJSON *x = cJSON_GetArrayItem(pt, 0), *y = cJSON_GetArrayItem(pt, 1);
        if (!cJSON_IsArray(pt) || cJSON_GetArraySize(pt) != 2 || !cJSON_IsNumber(x) || !cJSON_IsNumber(y) ||
            !plausible(x->valuedouble) || !plausible(y->valuedouble))
            return 0;
        lm[2 * i] = x->valuedouble;
        lm[2 * i + 1] = y->valuedouble;
    }
    return 1;
}

frig_status fr_read_landmarks_json(frig_ctx *ctx, const char *path, fr_detected_face **faces, size_t *count) {
    *faces = NULL;
    *count = 0;
    unsigned char *data;
    size_t size;
    frig_status st = fr_read_file(ctx, path, USER_FILE_MAX, &data, &size);
    if (st) return st;
    cJSON *root = cJSON_ParseWithLength((const char *)data, size);
    free(data);
    const cJSON *single = cJSON_GetObjectItemCaseSensitive(root, "landmarks");
    const cJSON *list = cJSON_GetObjectItemCaseSensitive(root, "faces");
    int n = single ? 1 : cJSON_IsArray(list) ? cJSON_GetArraySize(list) : 0;
    fr_detected_face *v = n > 0 ? calloc((size_t)n, sizeof *v) : NULL;
    int ok = root && n > 0 && v;
    double lm[2 * FRIG_LANDMARK_COUNT];
    for (int i = 0; ok && i < n; i++) {
        const cJSON *arr = single ? single : cJSON_GetObjectItemCaseSensitive(cJSON_GetArrayItem(list, i), "landmarks");
        ok = json_points(arr, lm);
        if (ok) user_face(&v[i], lm);
    }
    cJSON_Delete(root);
    if (!ok) {
        free(v);
        if (n > 0 && !v) return fr_nomem(ctx, "user landmarks");
        return fr_error(ctx, FRIG_ERR_CORRUPT,
                        "%s is not a landmark file: want {\"landmarks\": [[x, y], ... 68 points]} or "
                        "{\"faces\": [{\"landmarks\": [...]}, ...]}",
                        path);
    }
    *faces = v;
    *count = (size_t)n;
    return FRIG_OK;
}

static int exists(const char *path) {
    struct stat st;
    return stat(path, &st) == 0;
}

/* STEM + suffix in a new string: the photo path without its extension (if any). */
static char *beside(const char *photo, const char *suffix) {
    const char *base = fr_path_base(photo), *dot = strrchr(base, '.');
    size_t stem = dot && dot != base ? (size_t)(dot - photo) : strlen(photo);
    char *s = malloc(stem + strlen(suffix) + 1);
    if (!s) return NULL;
    memcpy(s, photo, stem);
    strcpy(s + stem, suffix);
    return s;
}

frig_status fr_user_landmarks(frig_ctx *ctx, const char *photo, fr_detected_face **faces, size_t *count,
                              char **file) {
    *faces = NULL;
    *count = 0;
    *file = NULL;
    char *pts = beside(photo, ".pts"), *json = beside(photo, ".landmarks.json");
    frig_status st = FRIG_OK;
    if (!pts || !json) {
        st = fr_nomem(ctx, "a path");
    } else if (exists(json)) {
        st = fr_read_landmarks_json(ctx, json, faces, count);
        if (!st) *file = json, json = NULL;
    } else if (exists(pts)) {
        fr_detected_face *f = malloc(sizeof *f);
        double lm[2 * FRIG_LANDMARK_COUNT];
        if (!f) st = fr_nomem(ctx, "user landmarks");
        else st = fr_read_pts(ctx, pts, lm);
        if (!st) {
            user_face(f, lm);
            *faces = f;
            *count = 1;
            *file = pts, pts = NULL;
        } else {
            free(f);
        }
    }
    free(pts);
    free(json);
    return st;
}
