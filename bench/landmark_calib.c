/* Where the landmark detector's 68 points lie on the face, as model vertices: for every
 * inner landmark (17-67: brows, nose, eyes, mouth; the jaw 0-16 follows the outline), the
 * vertex near the model's own landmark vertex whose projection lies nearest, on average, to
 * what the pipeline detected, over the near-frontal, unoccluded photos of frig synth subjects
 * (each photo's true rig, expression, pose and camera). The table the fit stage uses instead
 * of ICT-FaceKit's landmark vertices (lib/fit/landmark_vertices.c, docs/fit.md "The landmarks'
 * vertices") was made by this program.
 * Usage: landmark_calib MODEL WORKSPACE... [--max-yaw DEG] [--radius MM] [--current] [--table]
 *   WORKSPACE: a synth subject's photos after frig detect (and filter); the truth is found
 *   beside the photos. --current scores the fit stage's table instead of the model's.
 *   Prints per landmark the mean distance (% of the eye distance) at the reference vertex and
 *   at the best one, and how far apart the two are on the mean face (mm). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fit/landmark_vertices.h"
#include "frig/frig.h"
#include "model/model.h"
#include "raster/camera.h"
#include "rig/rig.h"
#include "synth_truth.h"

#define NL 68
#define FIRST_INNER 17

typedef struct candidates {
    int n[NL];
    int *v[NL];
    double *sum[NL]; /* summed distance (eye distances) per candidate */
} candidates;

/* The vertices within radius (m) of each reference landmark vertex on the mean face, among
 * the first nf vertices (the face region). */
static int candidates_make(const float *mean, int nf, const int32_t *ref, double radius, candidates *c) {
    memset(c, 0, sizeof *c);
    for (int k = FIRST_INNER; k < NL; k++) {
        const float *p = mean + 3 * (size_t)ref[k];
        c->v[k] = malloc(sizeof(int) * (size_t)nf);
        c->sum[k] = calloc((size_t)nf, sizeof(double));
        if (!c->v[k] || !c->sum[k]) return 0;
        for (int v = 0; v < nf; v++) {
            double d2 = 0;
            for (int a = 0; a < 3; a++) d2 += (mean[3 * v + a] - p[a]) * (mean[3 * v + a] - p[a]);
            if (d2 <= radius * radius) c->v[k][c->n[k]++] = v;
        }
    }
    return 1;
}

static double eye_distance(const double *lm) {
    double l[2] = {0, 0}, r[2] = {0, 0};
    for (int k = 36; k < 42; k++) l[0] += lm[2 * k] / 6, l[1] += lm[2 * k + 1] / 6;
    for (int k = 42; k < 48; k++) r[0] += lm[2 * k] / 6, r[1] += lm[2 * k + 1] / 6;
    return hypot(l[0] - r[0], l[1] - r[1]);
}

/* One photo: the true posed mesh projected, every candidate's distance to the detected point. */
static int add_photo(frig_ctx *ctx, const frig_rig *truth, const synth_photo_truth *tr, const double *det,
                     candidates *c, float *posed, double *w) {
    int ns = frig_rig_shape_count(truth), nv = frig_rig_vertex_count(truth);
    memset(w, 0, sizeof(double) * (size_t)ns);
    for (int q = 0; q < tr->n_expr; q++) {
        int j = frig_rig_shape_find(truth, tr->names[q]);
        if (j >= 0) w[j] = tr->weights[q];
    }
    if (frig_rig_eval(ctx, truth, w, posed)) return 0;
    fr_camera cam = fr_camera_perspective(tr->f, tr->width, tr->height);
    cam.cx = tr->cx, cam.cy = tr->cy;
    double eye = eye_distance(det);
    if (!(eye > 1)) return 0;
    for (int k = FIRST_INNER; k < NL; k++)
        for (int i = 0; i < c->n[k]; i++) {
            int v = c->v[k][i];
            double uv[2];
            if (v >= nv) continue;
            fr_project_points(&cam, tr->R, tr->t, posed + 3 * (size_t)v, 1, uv, NULL);
            c->sum[k][i] += hypot(uv[0] - det[2 * k], uv[1] - det[2 * k + 1]) / eye;
        }
    return 1;
}

int main(int argc, char **argv) {
    double max_yaw = 25, radius_mm = 10;
    int table = 0, current = 0, nws = 0;
    const char *model_path = NULL, *ws[256];
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--max-yaw") && i + 1 < argc) max_yaw = atof(argv[++i]);
        else if (!strcmp(argv[i], "--radius") && i + 1 < argc) radius_mm = atof(argv[++i]);
        else if (!strcmp(argv[i], "--table")) table = 1;
        else if (!strcmp(argv[i], "--current")) current = 1;
        else if (!model_path) model_path = argv[i];
        else if (nws < 256) ws[nws++] = argv[i];
    }
    if (!model_path || nws == 0) {
        fprintf(stderr, "usage: landmark_calib MODEL WORKSPACE... [--max-yaw DEG] [--radius MM] [--current] [--table]\n");
        return 2;
    }
    frig_ctx *ctx = frig_ctx_create();
    frig_model *model = NULL;
    if (!ctx || frig_model_load(ctx, model_path, &model)) {
        fprintf(stderr, "%s\n", ctx ? frig_ctx_errmsg(ctx) : "no context");
        return 1;
    }
    int nf = 9409, face = frig_model_region_find(model, "face");
    if (face >= 0) frig_model_region(model, face, NULL, NULL, &nf);
    int32_t ref[NL];
    if (current) fr_fit_landmark_vertices(ctx, model, ref);
    else memcpy(ref, frig_model_landmarks(model), sizeof ref);
    candidates c;
    if (!candidates_make(model->neutral, nf, ref, 1e-3 * radius_mm, &c)) return 1;
    int photos = 0;
    for (int a = 0; a < nws; a++) {
        frig_photoset *set = NULL;
        frig_rig *truth = NULL;
        if (frig_photoset_load(ctx, ws[a], &set) || frig_photoset_count(set) == 0) {
            fprintf(stderr, "%s: %s\n", ws[a], frig_ctx_errmsg(ctx));
            return 1;
        }
        const char *photo = frig_photoset_path(set, 0), *slash = strrchr(photo, '/');
        char path[4200];
        snprintf(path, sizeof path, "%.*s/../rig/rig.frigrig", (int)(slash - photo), photo);
        if (frig_rig_load(ctx, path, &truth)) {
            fprintf(stderr, "%s: %s\n", path, frig_ctx_errmsg(ctx));
            return 1;
        }
        int nv = frig_rig_vertex_count(truth);
        float *posed = malloc(sizeof(float) * 3 * (size_t)nv);
        double *w = calloc((size_t)frig_rig_shape_count(truth) + 1, sizeof(double)), det[2 * NL];
        for (size_t i = 0; i < frig_photoset_count(set); i++) {
            synth_photo_truth tr;
            long sub = frig_photoset_subject(set, i);
            if (frig_photoset_status(set, i) != FRIG_PHOTO_OK || sub < 0 ||
                !synth_truth_read(frig_photoset_path(set, i), 0, &tr) || strcmp(tr.failure, "none") != 0 ||
                fabs(tr.yaw_deg) > max_yaw || frig_photoset_face_landmarks(set, i, (size_t)sub, det))
                continue;
            photos += add_photo(ctx, truth, &tr, det, &c, posed, w);
        }
        free(posed), free(w);
        frig_rig_free(truth);
        frig_photoset_free(set);
    }
    printf("%d photos (|yaw| <= %.0f deg, no failure), candidates within %.1f mm\n", photos, max_yaw, radius_mm);
    printf("landmark  reference vertex  mean %%eye  ->  best vertex  mean %%eye  moved mm\n");
    int best[NL];
    double before = 0, after = 0;
    for (int k = 0; k < NL; k++) best[k] = ref[k];
    for (int k = FIRST_INNER; k < NL; k++) {
        int bi = -1, ri = -1;
        for (int i = 0; i < c.n[k]; i++) {
            if (c.v[k][i] == ref[k]) ri = i;
            if (bi < 0 || c.sum[k][i] < c.sum[k][bi]) bi = i;
        }
        if (bi < 0 || ri < 0 || photos == 0) continue;
        best[k] = c.v[k][bi];
        const float *p = model->neutral + 3 * (size_t)ref[k], *q = model->neutral + 3 * (size_t)best[k];
        double moved = 1e3 * sqrt((p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) + (p[2] - q[2]) * (p[2] - q[2]));
        printf("%8d  %16d  %9.2f  ->  %11d  %9.2f  %8.2f\n", k, ref[k], 100 * c.sum[k][ri] / photos, best[k],
               100 * c.sum[k][bi] / photos, moved);
        before += c.sum[k][ri] / photos, after += c.sum[k][bi] / photos;
    }
    printf("mean over the inner landmarks: %.2f -> %.2f %% of the eye distance\n", 100 * before / (NL - FIRST_INNER),
           100 * after / (NL - FIRST_INNER));
    if (table) {
        printf("table:");
        for (int k = 0; k < NL; k++) printf("%s%d", k ? ", " : " ", best[k]);
        printf("\n");
    }
    for (int k = FIRST_INNER; k < NL; k++) free(c.v[k]), free(c.sum[k]);
    frig_model_free(model);
    frig_ctx_free(ctx);
    return 0;
}
