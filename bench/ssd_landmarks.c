/* Landmarks on face-api's SSD boxes (docs/detect.md, "Turned faces"): which box dlib's
 * predictor gets decides whether a turned face's points follow the face or collapse toward a
 * frontal layout.
 *   ssd_landmarks fit DLIB_HOG.jsonl
 *     the map from a face's 68 points to dlib's HOG box of it (lib/detect/box_calibration.c,
 *     fr_box_from_landmarks), fitted on dlib's own boxes and points, for a few choices of the
 *     points' scale: the constants and the mean IoU with dlib's box.
 *   ssd_landmarks eval PHOTO|SYNTH_SUBJECT_DIR...
 *     every photo with ground truth (iBUG .pts beside it, or a frig synth subject's truth: its
 *     detector-like landmarks), the SSD face at the truth, and its landmarks by: dlib on the
 *     mapped SSD box; face-api's net; dlib on the box from the net's points; that box refined
 *     once from dlib's points; the stage's answer (fr_detect_ssd with the context's detect.*
 *     parameters: dlib on the net-placed box, the net's points on faces turned more than
 *     detect.net_turn). NME (over the outer
 *     eye corners) mean and median per group: real photos, synthetic |yaw| < 30, >= 30. */
#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "detect/detector.h"
#include "landmark_ref.h"
#include "synth_truth.h"

#define VARIANTS 5
static const char *variant_name[VARIANTS] = {"dlib on mapped SSD box", "face-api net", "dlib on box from net points",
                                             "  + refined once from dlib", "the stage (detect.landmarks 1)"};

/* ---- fit ---- */
/* Scale choices: 0 sqrt of the points' bounding box area, 1 the box's height, 2 RMS distance of
 * the inner points (17-67) from their centroid, 3 the larger side of the bounding box. */
static double scale_of(const double *lm, int kind, double *mx, double *my) {
    double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY, sx = 0, sy = 0;
    for (int k = 0; k < 68; k++) {
        double x = lm[2 * k], y = lm[2 * k + 1];
        x0 = fmin(x0, x), x1 = fmax(x1, x), y0 = fmin(y0, y), y1 = fmax(y1, y);
    }
    for (int k = 17; k < 68; k++) sx += lm[2 * k] / 51, sy += lm[2 * k + 1] / 51;
    *mx = sx, *my = sy;
    if (kind == 0) return sqrt((x1 - x0) * (y1 - y0));
    if (kind == 1) return y1 - y0;
    if (kind == 3) return fmax(x1 - x0, y1 - y0);
    double r = 0;
    for (int k = 17; k < 68; k++) r += pow(lm[2 * k] - sx, 2) + pow(lm[2 * k + 1] - sy, 2);
    return sqrt(r / 51);
}

static int fit(const lm_face *ref, long n) {
    for (int kind = 0; kind < 4; kind++) {
        double sa = 0, sb = 0, sc = 0, sd = 0, ss = 0;
        for (long i = 0; i < n; i++) {
            double mx, my, s = scale_of(ref[i].dlib, kind, &mx, &my), W = ref[i].box[2] - ref[i].box[0] + 1,
                            H = ref[i].box[3] - ref[i].box[1] + 1;
            sa += s * (ref[i].box[0] - mx), sb += s * (ref[i].box[1] - my), sc += s * W, sd += s * H, ss += s * s;
        }
        double m[4] = {sa / ss, sb / ss, sc / ss, sd / ss}, iou = 0;
        for (long i = 0; i < n; i++) {
            double mx, my, s = scale_of(ref[i].dlib, kind, &mx, &my);
            double b[4] = {mx + m[0] * s, my + m[1] * s, m[2] * s, m[3] * s};
            double r[4] = {ref[i].box[0], ref[i].box[1], ref[i].box[2] - ref[i].box[0] + 1, ref[i].box[3] - ref[i].box[1] + 1};
            iou += fr_box_iou(b, r);
        }
        printf("scale %d over %ld faces: {%.4f, %.4f, %.4f, %.4f}, mean IoU with dlib's box %.3f\n", kind, n, m[0], m[1],
               m[2], m[3], iou / n);
    }
    return 0;
}

/* ---- eval ---- */
static int strcmp_ptr(const char **a, const char **b) { return strcmp(*a, *b); }

typedef struct group {
    double *v[VARIANTS];
    int n, cap;
} group;

static void group_add(group *g, const double *e) {
    if (g->n == g->cap) {
        g->cap = g->cap ? 2 * g->cap : 64;
        for (int k = 0; k < VARIANTS; k++) g->v[k] = realloc(g->v[k], sizeof(double) * (size_t)g->cap);
    }
    for (int k = 0; k < VARIANTS; k++) g->v[k][g->n] = e[k];
    g->n++;
}

static int cmp(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static void group_print(const char *name, group *g) {
    printf("%s: %d faces\n", name, g->n);
    for (int k = 0; k < VARIANTS && g->n; k++) {
        double s = 0;
        for (int i = 0; i < g->n; i++) s += g->v[k][i];
        qsort(g->v[k], (size_t)g->n, sizeof(double), cmp);
        printf("  %-34s NME mean %.4f median %.4f p90 %.4f\n", variant_name[k], s / g->n, g->v[k][g->n / 2],
               g->v[k][(int)(0.9 * (g->n - 1))]);
    }
}

static void box_from(const double *lm, double box[4]) { fr_box_from_landmarks(lm, box); }

/* The variants' landmarks for one SSD box (raw, the SSD's convention). */
static int variants(frig_ctx *ctx, const frig_detector *det, const fr_nn_image *in, const frig_image *dgray,
                    const double raw[4], double out[VARIANTS][136]) {
    fr_detected_face f;
    memset(&f, 0, sizeof f);
    fr_box_map m = fr_box_map_for(FRIG_FACE_SSD);
    fr_box_map_apply(&m, raw, f.box);
    if (fr_detect_landmarks_on(ctx, det, dgray, &f, 1)) return 1;
    memcpy(out[0], f.landmarks, sizeof f.landmarks);
    if (fr_landmark_net_run(ctx, det->nets->landmarks, in, raw, out[1], NULL)) return 1;
    box_from(out[1], f.box);
    if (fr_detect_landmarks_on(ctx, det, dgray, &f, 1)) return 1;
    memcpy(out[2], f.landmarks, sizeof f.landmarks);
    box_from(out[2], f.box);
    if (fr_detect_landmarks_on(ctx, det, dgray, &f, 1)) return 1;
    memcpy(out[3], f.landmarks, sizeof f.landmarks);
    return 0;
}

static int eval_photo(frig_ctx *ctx, const frig_detector *det, const char *photo, const double *truth, group *g,
                      const char *label) {
    frig_image *rgb = NULL, *dgray = NULL;
    if (frig_image_load(ctx, photo, FR_LOAD_LIKE_JPEG_JS, &rgb)) return 0;
    fr_nn_image in = {rgb->pixels, rgb->stride, rgb->width, rgb->height, rgb->channels};
    fr_ssd_face *b = NULL;
    size_t n = 0;
    int rc = fr_ssd_detect(ctx, det->nets->ssd, &in, det->ssd_min_score, 100, &b, &n) || fr_gray_like_dlib(ctx, rgb, &dgray);
    if (!rc && n) {
        fr_detected_face *v = calloc(n, sizeof *v);
        fr_box_map m = fr_box_map_for(FRIG_FACE_SSD);
        for (size_t i = 0; i < n; i++) fr_box_map_apply(&m, b[i].box, v[i].box);
        long k = lm_face_at_truth(v, n, truth);
        double lm[VARIANTS][136], e[VARIANTS];
        fr_detected_face *sf = NULL;
        size_t sn = 0;
        long sk = -1;
        if (k >= 0 && !(rc = fr_detect_ssd(ctx, det, rgb, &sf, &sn))) sk = lm_face_at_truth(sf, sn, truth);
        if (sk >= 0) memcpy(lm[4], sf[sk].landmarks, sizeof lm[4]);
        free(sf);
        if (sk >= 0 && !(rc = variants(ctx, det, &in, dgray, b[k].box, lm))) {
            for (int j = 0; j < VARIANTS; j++) e[j] = lm_nme(lm[j], truth);
            group_add(g, e);
            if (getenv("SSD_LANDMARKS_PHOTOS"))
                printf("  %-60s %s %.4f %.4f %.4f %.4f %.4f turn %.3f\n", photo, label, e[0], e[1], e[2], e[3], e[4],
                       fr_landmarks_turn(lm[1]));
        }
        free(v);
    }
    free(b);
    frig_image_free(rgb);
    frig_image_free(dgray);
    return rc;
}

static int eval(frig_ctx *ctx, const frig_detector *det, char **args, int n) {
    group real = {{0}, 0, 0}, frontal = {{0}, 0, 0}, turned = {{0}, 0, 0};
    for (int a = 0; a < n; a++) {
        char photos[4200];
        snprintf(photos, sizeof photos, "%s/photos", args[a]);
        DIR *d = opendir(photos);
        if (!d) {
            double truth[136];
            if (lm_truth_pts(args[a], truth) && eval_photo(ctx, det, args[a], truth, &real, "real")) return 1;
            continue;
        }
        char **names = NULL;
        int m = 0;
        for (struct dirent *e; (e = readdir(d));)
            if (strstr(e->d_name, ".jpg")) names = realloc(names, sizeof *names * (size_t)(m + 1)), names[m++] = strdup(e->d_name);
        closedir(d);
        qsort(names, (size_t)m, sizeof *names, (int (*)(const void *, const void *))strcmp_ptr);
        for (int i = 0; i < m; i++) {
            char path[8400];
            snprintf(path, sizeof path, "%s/%s", photos, names[i]);
            synth_photo_truth t;
            if (synth_truth_read(path, 0, &t) && t.has_landmarks && !strcmp(t.failure, "none")) {
                group *g = fabs(t.yaw_deg) < 30 ? &frontal : &turned;
                char label[64];
                snprintf(label, sizeof label, "yaw %6.1f", t.yaw_deg);
                if (eval_photo(ctx, det, path, t.landmarks, g, label)) return 1;
            }
            free(names[i]);
        }
        free(names);
    }
    group_print("real photos with .pts", &real);
    group_print("synthetic, |yaw| < 30", &frontal);
    group_print("synthetic, |yaw| >= 30", &turned);
    return 0;
}

int main(int argc, char **argv) {
    if (argc < 3) {
        fprintf(stderr, "usage: ssd_landmarks fit DLIB_HOG.jsonl | eval PHOTO|SYNTH_SUBJECT_DIR...\n");
        return 2;
    }
    frig_ctx *ctx = frig_ctx_create();
    if (!strcmp(argv[1], "fit")) {
        lm_face *ref = NULL;
        long nref = lm_read_faces(argv[2], &ref);
        if (nref <= 0) {
            fprintf(stderr, "cannot read %s\n", argv[2]);
            return 1;
        }
        int rc = fit(ref, nref);
        free(ref);
        frig_ctx_free(ctx);
        return rc;
    }
    frig_detector *det = NULL;
    frig_ctx_set_param(ctx, FRIG_PARAM_DETECT_DETECTOR, 2);
    frig_ctx_set_param(ctx, FRIG_PARAM_DETECT_DESCRIPTORS, 0);
    if (frig_detector_create(ctx, NULL, NULL, &det)) {
        fprintf(stderr, "%s\n", frig_ctx_errmsg(ctx));
        return 1;
    }
    int rc = eval(ctx, det, argv + 2, argc - 2);
    if (rc) fprintf(stderr, "failed: %s\n", frig_ctx_errmsg(ctx));
    frig_detector_free(det);
    frig_ctx_free(ctx);
    return rc;
}
