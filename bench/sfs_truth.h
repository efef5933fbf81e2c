/* Reading a frig synth photo's truth for the shape-from-shading benchmarks (docs/synth.md):
 * pose, camera, expression weights by name, lighting, the depth map and (when the data set has
 * them) the per-pixel class map. */
#ifndef BENCH_SFS_TRUTH_H
#define BENCH_SFS_TRUTH_H

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cJSON.h>

#include "frig/frig.h"

typedef struct bench_truth {
    int has_face, width, height;
    char failure[32];
    double R[9], t[3], f, cx, cy;
    double sh[3][9];
    double *weights; /* per shape of the true rig */
    float *depth;    /* width x height, 0 = no head */
    unsigned char *mask; /* class map or NULL */
} bench_truth;

static void bench_truth_free(bench_truth *t) {
    free(t->weights), free(t->depth), free(t->mask);
    memset(t, 0, sizeof *t);
}

static char *bench_read_all(const char *path, size_t *size) {
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *d = malloc((size_t)n + 1);
    if (d && fread(d, 1, (size_t)n, f) != (size_t)n) free(d), d = NULL;
    fclose(f);
    if (d) d[n] = 0;
    if (size) *size = (size_t)n;
    return d;
}

static int bench_numbers(const cJSON *a, double *out, int n) {
    if (!cJSON_IsArray(a) || cJSON_GetArraySize(a) != n) return 0;
    int k = 0;
    for (const cJSON *e = a->child; e; e = e->next) out[k++] = e->valuedouble;
    return 1;
}

/* The truth of the photo at photo_path (".../photos/photo_PPP.jpg" -> ".../truth/photo_PPP.json"). */
static int bench_truth_load(const char *photo_path, const frig_rig *true_rig, bench_truth *t) {
    memset(t, 0, sizeof *t);
    char base[4096];
    snprintf(base, sizeof base, "%s", photo_path);
    char *slash = strrchr(base, '/');
    if (!slash) return 0;
    *slash = 0;
    char stem[512];
    snprintf(stem, sizeof stem, "%s", slash + 1);
    char *dot = strrchr(stem, '.');
    if (dot) *dot = 0;
    char *up = strrchr(base, '/');
    if (up) *up = 0;
    char path[8192];
    snprintf(path, sizeof path, "%s/truth/%s.json", base, stem);
    char *text = bench_read_all(path, NULL);
    if (!text) return 0;
    cJSON *j = cJSON_Parse(text);
    free(text);
    if (!j) return 0;
    t->width = cJSON_GetObjectItem(j, "width")->valueint;
    t->height = cJSON_GetObjectItem(j, "height")->valueint;
    snprintf(t->failure, sizeof t->failure, "%s", cJSON_GetStringValue(cJSON_GetObjectItem(j, "failure")));
    const cJSON *pose = cJSON_GetObjectItem(j, "pose");
    t->has_face = pose != NULL;
    if (pose) {
        bench_numbers(cJSON_GetObjectItem(pose, "R"), t->R, 9);
        bench_numbers(cJSON_GetObjectItem(pose, "t"), t->t, 3);
        const cJSON *cam = cJSON_GetObjectItem(j, "camera");
        t->f = cJSON_GetObjectItem(cam, "f")->valuedouble;
        t->cx = cJSON_GetObjectItem(cam, "cx")->valuedouble;
        t->cy = cJSON_GetObjectItem(cam, "cy")->valuedouble;
        const cJSON *light = cJSON_GetObjectItem(j, "lighting");
        const cJSON *sh = cJSON_GetObjectItem(light, "sh");
        int c = 0;
        for (const cJSON *e = sh ? sh->child : NULL; e && c < 3; e = e->next, c++) bench_numbers(e, t->sh[c], 9);
        int ns = frig_rig_shape_count(true_rig);
        t->weights = calloc((size_t)ns + 1, sizeof(double));
        const cJSON *ex = cJSON_GetObjectItem(j, "expression");
        for (const cJSON *e = ex ? ex->child : NULL; e; e = e->next) {
            int k = frig_rig_shape_find(true_rig, e->string);
            if (k >= 0) t->weights[k] = e->valuedouble;
        }
        size_t size = 0;
        snprintf(path, sizeof path, "%s/truth/%s.depth.f32", base, stem);
        t->depth = (float *)bench_read_all(path, &size);
        if (t->depth && size != sizeof(float) * (size_t)t->width * t->height) free(t->depth), t->depth = NULL;
        snprintf(path, sizeof path, "%s/truth/%s.mask.u8", base, stem);
        t->mask = (unsigned char *)bench_read_all(path, &size);
        if (t->mask && size != (size_t)t->width * t->height) free(t->mask), t->mask = NULL;
    }
    cJSON_Delete(j);
    return 1;
}

#endif
