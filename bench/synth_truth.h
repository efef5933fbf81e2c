/* The benchmarks' reader of frig synth's per-photo truth (docs/synth.md): the photo's pose,
 * camera, expression and depth map, found from the photo's path
 * (.../subject_SS/photos/photo_PPP.jpg -> .../subject_SS/truth/photo_PPP.json). */
#ifndef BENCH_SYNTH_TRUTH_H
#define BENCH_SYNTH_TRUTH_H

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cjson/cJSON.h>

typedef struct synth_photo_truth {
    double R[9], t[3], f, cx, cy;
    int width, height;
    float *depth; /* width * height, 0 where no head */
    int n_expr;
    char names[64][64];
    double weights[64];
    double yaw_deg;
    char failure[32];             /* "none", "occluder", "extreme_pose", ... */
    int has_landmarks;            /* the photo shows the face's landmarks */
    double landmarks[136];        /* the truth's detector-like landmarks (jaw on the outline) */
} synth_photo_truth;

static inline char *synth_read_text(const char *path) {
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *s = malloc((size_t)n + 1);
    if (s && fread(s, 1, (size_t)n, f) != (size_t)n) {
        free(s);
        s = NULL;
    }
    if (s) s[n] = 0;
    fclose(f);
    return s;
}

/* The truth JSON path of a photo path; 0 when the path is not a synth photo's. */
static inline int synth_truth_path(const char *photo, const char *ext, char *out, size_t size) {
    const char *slash = strrchr(photo, '/');
    const char *dot = strrchr(photo, '.');
    if (!slash || !dot || dot < slash || slash - photo < 7 || strncmp(slash - 6, "photos", 6) != 0) return 0;
    snprintf(out, size, "%.*struth/%.*s%s", (int)(slash - 6 - photo), photo, (int)(dot - slash - 1), slash + 1, ext);
    return 1;
}

static inline int json_numbers(const cJSON *a, double *v, int n) {
    if (!cJSON_IsArray(a) || cJSON_GetArraySize(a) != n) return 0;
    for (int i = 0; i < n; i++) v[i] = cJSON_GetArrayItem(a, i)->valuedouble;
    return 1;
}

/* Read the truth of a photo; with_depth loads the depth map too. 0 on failure. */
static inline int synth_truth_read(const char *photo, int with_depth, synth_photo_truth *tr) {
    memset(tr, 0, sizeof *tr);
    char path[4200];
    if (!synth_truth_path(photo, ".json", path, sizeof path)) return 0;
    char *text = synth_read_text(path);
    cJSON *root = text ? cJSON_Parse(text) : NULL;
    free(text);
    if (!root) return 0;
    const cJSON *pose = cJSON_GetObjectItemCaseSensitive(root, "pose");
    const cJSON *cam = cJSON_GetObjectItemCaseSensitive(root, "camera");
    int ok = pose && cam && json_numbers(cJSON_GetObjectItemCaseSensitive(pose, "R"), tr->R, 9) &&
             json_numbers(cJSON_GetObjectItemCaseSensitive(pose, "t"), tr->t, 3);
    if (ok) {
        tr->f = cJSON_GetObjectItemCaseSensitive(cam, "f")->valuedouble;
        tr->cx = cJSON_GetObjectItemCaseSensitive(cam, "cx")->valuedouble;
        tr->cy = cJSON_GetObjectItemCaseSensitive(cam, "cy")->valuedouble;
        tr->width = cJSON_GetObjectItemCaseSensitive(root, "width")->valueint;
        tr->height = cJSON_GetObjectItemCaseSensitive(root, "height")->valueint;
        const cJSON *yaw = cJSON_GetObjectItemCaseSensitive(pose, "yaw_deg");
        tr->yaw_deg = cJSON_IsNumber(yaw) ? yaw->valuedouble : 0;
        const cJSON *fail = cJSON_GetObjectItemCaseSensitive(root, "failure");
        snprintf(tr->failure, sizeof tr->failure, "%s", cJSON_IsString(fail) ? fail->valuestring : "?");
        const cJSON *lm = cJSON_GetObjectItemCaseSensitive(root, "landmarks");
        const cJSON *det = lm ? cJSON_GetObjectItemCaseSensitive(lm, "detector_like") : NULL;
        if (cJSON_IsArray(det) && cJSON_GetArraySize(det) == 68) {
            tr->has_landmarks = 1;
            for (int k = 0; k < 68; k++)
                tr->has_landmarks &= json_numbers(cJSON_GetArrayItem(det, k), tr->landmarks + 2 * k, 2);
        }
        const cJSON *e = cJSON_GetObjectItemCaseSensitive(root, "expression"), *it;
        cJSON_ArrayForEach(it, e) {
            if (tr->n_expr >= 64) break;
            snprintf(tr->names[tr->n_expr], 64, "%s", it->string);
            tr->weights[tr->n_expr++] = it->valuedouble;
        }
    }
    cJSON_Delete(root);
    if (ok && with_depth) {
        synth_truth_path(photo, ".depth.f32", path, sizeof path);
        FILE *f = fopen(path, "rb");
        size_t n = (size_t)tr->width * tr->height;
        tr->depth = malloc(sizeof(float) * (n + 1));
        ok = f && tr->depth && fread(tr->depth, sizeof(float), n, f) == n;
        if (f) fclose(f);
    }
    return ok;
}

static inline void synth_truth_free(synth_photo_truth *tr) {
    free(tr->depth);
    tr->depth = NULL;
}

#endif
