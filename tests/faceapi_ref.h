/* The reference answers of @vladmandic/face-api run by TensorFlow.js itself
 * (../shared/tools/faceapi_ref.cjs, stored in tests/data/faceapi_ref.jsonl: one JSON line per
 * photo of ../shared/photos, never the photos), and our C networks' answers on the same photo,
 * matched face to face. Shared by tests/test_face_nets.c and bench/faceapi_vs_ref.c. */
#ifndef FRIG_TESTS_FACEAPI_REF_H
#define FRIG_TESTS_FACEAPI_REF_H

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cJSON.h>

#include "image/image.h"
#include "nn/face_nets.h"

#define REF_MAX_FACES 64

typedef struct ref_face {
    double score, box[4], landmarks[136];
    float descriptor[FR_FACE_DESCRIPTOR_SIZE];
} ref_face;

typedef struct ref_image {
    char image[512];
    int width, height;
    double ms;
    int n;
    ref_face faces[REF_MAX_FACES];
} ref_image;

/* One line of the reference file; 0 when it is not one. */
static int ref_parse_line(const char *line, ref_image *r) {
    cJSON *j = cJSON_Parse(line);
    if (!j) return 0;
    memset(r, 0, sizeof *r);
    const cJSON *im = cJSON_GetObjectItem(j, "image"), *faces = cJSON_GetObjectItem(j, "faces");
    int ok = cJSON_IsString(im) && cJSON_IsArray(faces);
    if (ok) {
        snprintf(r->image, sizeof r->image, "%s", im->valuestring);
        r->width = cJSON_GetObjectItem(j, "width")->valueint;
        r->height = cJSON_GetObjectItem(j, "height")->valueint;
        r->ms = cJSON_GetObjectItem(j, "ms")->valuedouble;
        for (const cJSON *f = faces->child; f && r->n < REF_MAX_FACES; f = f->next) {
            ref_face *rf = &r->faces[r->n++];
            rf->score = cJSON_GetObjectItem(f, "score")->valuedouble;
            const cJSON *b = cJSON_GetObjectItem(f, "box")->child;
            for (int k = 0; k < 4 && b; k++, b = b->next) rf->box[k] = b->valuedouble;
            const cJSON *l = cJSON_GetObjectItem(f, "landmarks")->child;
            for (int k = 0; k < 68 && l; k++, l = l->next) {
                rf->landmarks[2 * k] = l->child->valuedouble;
                rf->landmarks[2 * k + 1] = l->child->next->valuedouble;
            }
            const cJSON *d = cJSON_GetObjectItem(f, "descriptor")->child;
            for (int k = 0; k < FR_FACE_DESCRIPTOR_SIZE && d; k++, d = d->next) rf->descriptor[k] = (float)d->valuedouble;
        }
    }
    cJSON_Delete(j);
    return ok;
}

static double ref_iou(const double a[4], const double b[4]) {
    double x0 = fmax(a[0], b[0]), y0 = fmax(a[1], b[1]);
    double x1 = fmin(a[0] + a[2], b[0] + b[2]), y1 = fmin(a[1] + a[3], b[1] + b[3]);
    double inter = fmax(0.0, x1 - x0) * fmax(0.0, y1 - y0);
    double u = a[2] * a[3] + b[2] * b[3] - inter;
    return u > 0 ? inter / u : 0.0;
}

/* Our answers for a photo: every SSD face with its landmarks and descriptor. */
static int ours_run(frig_ctx *ctx, const fr_face_models *m, const frig_image *img, ref_face *out, int max) {
    fr_nn_image in = {img->pixels, img->stride, img->width, img->height, img->channels};
    fr_ssd_face *v = NULL;
    size_t n = 0;
    if (fr_ssd_detect(ctx, m->ssd, &in, 0.5, 100, &v, &n)) return -1;
    int k = 0;
    for (size_t i = 0; i < n && k < max; i++, k++) {
        out[k].score = v[i].score;
        memcpy(out[k].box, v[i].box, sizeof out[k].box);
        int crop[4];
        if (fr_landmark_net_run(ctx, m->landmarks, &in, v[i].box, out[k].landmarks, crop) ||
            fr_recognition_net_run(ctx, m->recognition, &in, out[k].landmarks, crop[2], crop[3], out[k].descriptor)) {
            free(v);
            return -1;
        }
    }
    free(v);
    return k;
}

/* Match each reference face to our face of the highest IoU (and back): match[i] is our index
 * for reference face i, or -1; back[j] likewise. */
typedef struct ref_match {
    int n_ref, n_ours;
    int match[REF_MAX_FACES], back[REF_MAX_FACES];
    double iou[REF_MAX_FACES];
} ref_match;

static void ref_match_faces(const ref_image *r, const ref_face *ours, int n, ref_match *m) {
    m->n_ref = r->n;
    m->n_ours = n;
    for (int i = 0; i < r->n; i++) {
        m->match[i] = -1;
        m->iou[i] = 0;
        for (int j = 0; j < n; j++) {
            double u = ref_iou(r->faces[i].box, ours[j].box);
            if (u > m->iou[i]) m->iou[i] = u, m->match[i] = j;
        }
    }
    for (int j = 0; j < n; j++) {
        m->back[j] = -1;
        double best = 0;
        for (int i = 0; i < r->n; i++) {
            double u = ref_iou(r->faces[i].box, ours[j].box);
            if (u > best) best = u, m->back[j] = i;
        }
    }
}

/* Mean distance of two 68-point sets, pixels. */
static double ref_landmark_distance(const double *a, const double *b) {
    double s = 0;
    for (int k = 0; k < 68; k++) s += hypot(a[2 * k] - b[2 * k], a[2 * k + 1] - b[2 * k + 1]);
    return s / 68;
}

#endif
