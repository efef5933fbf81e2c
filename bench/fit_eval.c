/* The fit stage on synthetic ground truth (issue 6's table): for each synthetic subject,
 * photos rendered by frig synth; landmarks = the truth's detector-like landmarks with noise
 * and a share of corrupted photos (or our detector's, with --detected); the three schemes
 * (individual fits only, naive joint fit, progressive Algorithm 2) measured against the
 * truth: neutral-shape error over the face region after similarity alignment (mm), head
 * rotation error (deg), expression error (weights, and the face geometry they make, mm),
 * landmark reprojection error (px).
 * Usage: fit_eval MODEL [--subjects S] [--photos N] [--noise PCT] [--corrupt FRACTION]
 *                       [--seed K] [--threads T] [--schemes 012] [--weak] [--detected] */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bench_param.h"
#include "core/context.h"
#include "eval/shape_error.h"
#include "fit/photo_consistency.h"
#include "fit/progressive_fit.h"
#include "frig/detect.h"
#include "frig/filter.h"
#include "frig/frig.h"
#include "frig/synth.h"
#include "raster/rotation.h"

typedef struct rng {
    unsigned long long s;
} rng;
static double uniform(rng *r) {
    r->s += 0x9E3779B97F4A7C15ULL;
    unsigned long long z = r->s;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return (double)((z ^ (z >> 31)) >> 11) / 9007199254740992.0;
}
static double gauss(rng *r) {
    double u = uniform(r) + 1e-300, v = uniform(r);
    return sqrt(-2 * log(u)) * cos(2 * M_PI * v);
}


typedef struct row {
    double neutral_mm, rot_deg, exp_w, exp_mm, reproj_px;
    int count;
} row;

static const char *scheme_name[] = {"individual fits only", "naive joint fit", "progressive (Algorithm 2)"};

/* Detected minus true landmarks on near-frontal photos (|yaw| < 15 deg), in % of the eye
 * distance: a systematic offset here is a landmark-embedding mismatch, not detector noise. */
static double bias_sum[136], bias_err[68];
static int bias_count;

static void landmark_bias_add(const double *truth, const double *det, const double R[9]) {
    double yaw, pitch, roll;
    fr_rotation_to_euler(R, &yaw, &pitch, &roll);
    if (fabs(yaw) * 57.3 > 15) return;
    double eye = fr_fit_eye_distance(truth);
    for (int k = 0; k < 68; k++) {
        double dx = (det[2 * k] - truth[2 * k]) / eye, dy = (det[2 * k + 1] - truth[2 * k + 1]) / eye;
        bias_sum[2 * k] += dx, bias_sum[2 * k + 1] += dy;
        bias_err[k] += hypot(dx, dy);
    }
    bias_count++;
}

static void landmark_bias_print(void) {
    if (!bias_count || !getenv("FIT_EVAL_LANDMARK_BIAS")) return;
    printf("landmark bias on %d near-frontal photos, %% of eye distance (mean dx, dy; mean |d|):\n", bias_count);
    for (int k = 0; k < 68; k++)
        printf("  %2d %6.1f %6.1f %6.1f\n", k, 100 * bias_sum[2 * k] / bias_count, 100 * bias_sum[2 * k + 1] / bias_count,
               100 * bias_err[k] / bias_count);
}

int main(int argc, char **argv) {
    if (argc < 2) {
        fprintf(stderr, "usage: fit_eval MODEL [options]\n");
        return 2;
    }
    int subjects = 3, photos = 30, threads = 0, weak = 0, detected = 0, exact = 0;
    double noise = 2.0, corrupt = 0.15;
    unsigned long long seed = 1;
    const char *schemes = "012";
    frig_ctx *ctx = frig_ctx_create();
    for (int i = 2; i < argc; i++) {
        if (!strcmp(argv[i], "--subjects") && i + 1 < argc) subjects = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--photos") && i + 1 < argc) photos = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--noise") && i + 1 < argc) noise = atof(argv[++i]);
        else if (!strcmp(argv[i], "--corrupt") && i + 1 < argc) corrupt = atof(argv[++i]);
        else if (!strcmp(argv[i], "--seed") && i + 1 < argc) seed = strtoull(argv[++i], NULL, 10);
        else if (!strcmp(argv[i], "--threads") && i + 1 < argc) threads = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--schemes") && i + 1 < argc) schemes = argv[++i];
        else if (!strcmp(argv[i], "--weak")) weak = 1;
        else if (!strcmp(argv[i], "--detected")) detected = 1;
        else if (!strcmp(argv[i], "--exact")) exact = 1;
        else if (!strcmp(argv[i], "--set") && i + 1 < argc) {
            if (bench_set_param(ctx, argv[++i])) return 2;
        } else {
            fprintf(stderr, "unknown option %s\n", argv[i]);
            return 2;
        }
    }
    frig_ctx_set_threads(ctx, threads);
    frig_ctx_set_param(ctx, FRIG_PARAM_SYNTH_FAILURE_RATE, 0);
    frig_model *model = NULL;
    if (frig_model_load(ctx, argv[1], &model)) {
        fprintf(stderr, "%s\n", frig_ctx_errmsg(ctx));
        return 1;
    }
    char tmpdir[] = "/tmp/fit_eval_XXXXXX";
    if (detected && !mkdtemp(tmpdir)) return 1;
    frig_detector *det = NULL;
    if (detected && frig_detector_create(ctx, NULL, NULL, &det)) {
        fprintf(stderr, "%s\n", frig_ctx_errmsg(ctx));
        return 1;
    }
    fr_fit_model fm;
    if (fr_fit_model_build(ctx, model, fr_param_int(ctx, FRIG_PARAM_FIT_IDENTITY_MODES), &fm)) return 1;
    fr_fit_settings st;
    fr_fit_settings_from_ctx(ctx, &st);
    if (weak) st.perspective = 0;
    int nv = frig_model_vertex_count(model), nface = 9409;
    int fr = frig_model_region_find(model, "face");
    if (fr >= 0) frig_model_region(model, fr, NULL, NULL, &nface);
    row rows[3] = {{0}};
    double seconds[3] = {0};
    rng r = {seed * 7919 + 17};
    printf("fit on synthetic ground truth: %d subjects x %d photos, landmarks %s, noise %.1f%% of eye distance, "
           "%.0f%% corrupted, %s camera\n",
           subjects, photos, detected ? "from our detect and filter stages (noise and corruption options unused)" : "truth (detector-like)", noise, corrupt * 100,
           st.perspective ? "perspective" : "weak-perspective");
    printf("%-8s %-26s %10s %9s %9s %9s %9s\n", "subject", "scheme", "neutral mm", "rot deg", "exp |w|", "exp mm",
           "reproj px");
    for (int s = 0; s < subjects; s++) {
        frig_synth_subject *subj = NULL;
        if (frig_synth_subject_create(ctx, model, seed * 1000 + (unsigned)s, &subj)) return 1;
        const frig_rig *truth_rig = frig_synth_subject_rig(subj);
        int nshape = frig_rig_shape_count(truth_rig);
        fr_fit_input *in = calloc((size_t)photos, sizeof *in);
        double *lmk = calloc((size_t)photos * 136, sizeof(double));
        double (*Rt)[9] = calloc((size_t)photos, sizeof *Rt);
        double *wt = calloc((size_t)photos * nshape, sizeof(double));
        frig_image **crops = calloc((size_t)photos, sizeof *crops);
        double (*Rt_all)[9] = calloc((size_t)photos, sizeof *Rt_all), t_unused[3];
        double *wt_all = calloc((size_t)photos * nshape, sizeof(double));
        double *lmk_truth = calloc((size_t)photos * 136, sizeof(double));
        int n = 0;
        for (int p = 0; p < photos; p++) {
            frig_image *img = NULL;
            frig_synth_truth *tr = NULL;
            if (frig_synth_render(ctx, subj, seed * 100000 + (unsigned)(s * 1000 + p), FRIG_SYNTH_FAILURE_NONE, &img,
                                  &tr))
                return 1;
            const double *q = frig_synth_truth_landmarks(tr, !exact);
            double *dst = lmk + 136 * (size_t)n;
            int ok = q != NULL;
            if (ok && detected) {
                /* Saved as a JPEG for the detect and filter stages, below. */
                char path[4200];
                snprintf(path, sizeof path, "%s/photo_%03d.jpg", tmpdir, p);
                frig_ctx_set_param(ctx, FRIG_PARAM_IMAGE_JPEG_QUALITY, frig_synth_truth_jpeg_quality(tr));
                ok = frig_image_save_jpeg(ctx, img, path) == FRIG_OK;
                frig_synth_truth_pose(tr, Rt_all[p], t_unused);
                memcpy(lmk_truth + 136 * (size_t)p, q, sizeof(double) * 136);
                memcpy(wt_all + (size_t)p * nshape, frig_synth_truth_expression(tr), sizeof(double) * (size_t)nshape);
                frig_image_free(img);
                frig_synth_truth_free(tr);
                continue;
            } else if (ok) {
                double sigma = noise / 100 * fr_fit_eye_distance(q);
                for (int k = 0; k < 136; k++) dst[k] = q[k] + sigma * gauss(&r);
                if (uniform(&r) < corrupt) {
                    /* A failed detection: one region (jaw, eyes or mouth) drifts by up to 15% of the face. */
                    int region = (int)(uniform(&r) * 3);
                    int a = region == 0 ? 0 : region == 1 ? 36 : 48, b = region == 0 ? 17 : region == 1 ? 48 : 68;
                    double dx = (uniform(&r) - 0.5) * 0.3 * (q[32] - q[0]), dy = (uniform(&r) - 0.5) * 0.3 * (q[32] - q[0]);
                    for (int k = a; k < b; k++) dst[2 * k] += dx, dst[2 * k + 1] += dy;
                }
            }
            if (ok) {
                double t[3];
                frig_synth_truth_pose(tr, Rt[n], t);
                memcpy(wt + (size_t)n * nshape, frig_synth_truth_expression(tr), sizeof(double) * (size_t)nshape);
                in[n].landmarks = dst;
                in[n].width = frig_image_width(img);
                in[n].height = frig_image_height(img);
                if (fr_face_crop(ctx, img, dst, 160, &crops[n], in[n].crop_origin, &in[n].crop_scale)) crops[n] = NULL;
                in[n].crop = crops[n];
                n++;
            }
            frig_image_free(img);
            frig_synth_truth_free(tr);
        }
        if (detected) {
            /* The pipeline's own landmarks: detect, then filter (Algorithm 1), on the saved photos. */
            frig_photoset *set = NULL;
            frig_photoset_create(ctx, &set);
            for (int p = 0; p < photos; p++) {
                char path[4200];
                snprintf(path, sizeof path, "%s/photo_%03d.jpg", tmpdir, p);
                frig_photoset_add(ctx, set, path, NULL);
            }
            if (frig_detect_photoset(ctx, det, set) || frig_filter(ctx, set, NULL)) {
                fprintf(stderr, "%s\n", frig_ctx_errmsg(ctx));
                return 1;
            }
            int dropped = 0, undetected = 0;
            for (int p = 0; p < photos; p++) {
                frig_photo_status ps = frig_photoset_status(set, (size_t)p);
                long sub = frig_photoset_subject(set, (size_t)p);
                dropped += ps == FRIG_PHOTO_OUTLIER;
                undetected += ps != FRIG_PHOTO_OK && ps != FRIG_PHOTO_OUTLIER;
                double *dst = lmk + 136 * (size_t)n;
                if (ps != FRIG_PHOTO_OK || sub < 0 || frig_photoset_face_landmarks(set, (size_t)p, (size_t)sub, dst)) continue;
                frig_image *img = NULL;
                if (frig_image_load(ctx, frig_photoset_path(set, (size_t)p), 0, &img)) continue;
                memcpy(Rt[n], Rt_all[p], sizeof Rt[n]);
                landmark_bias_add(lmk_truth + 136 * (size_t)p, dst, Rt_all[p]);
                memcpy(wt + (size_t)n * nshape, wt_all + (size_t)p * nshape, sizeof(double) * (size_t)nshape);
                in[n].landmarks = dst;
                in[n].width = frig_image_width(img);
                in[n].height = frig_image_height(img);
                if (fr_face_crop(ctx, img, dst, 160, &crops[n], in[n].crop_origin, &in[n].crop_scale)) crops[n] = NULL;
                in[n].crop = crops[n];
                frig_image_free(img);
                n++;
            }
            printf("%-8d %d photos: %d without a usable face, %d dropped by the filter, %d fitted\n", s, photos,
                   undetected, dropped, n);
            frig_photoset_free(set);
        }
        float *truth_neutral = malloc(sizeof(float) * 3 * (size_t)nv), *est = malloc(sizeof(float) * 3 * (size_t)nv);
        float *truth_exp = malloc(sizeof(float) * 3 * (size_t)nv), *est_exp = malloc(sizeof(float) * 3 * (size_t)nv);
        memcpy(truth_neutral, frig_rig_neutral(truth_rig), sizeof(float) * 3 * (size_t)nv);
        fr_fit_result *res = calloc((size_t)n, sizeof *res);
        double *W = calloc((size_t)n * fm.n_cols, sizeof(double)), identity[1024];
        for (int i = 0; i < n; i++) res[i].w = W + (size_t)i * fm.n_cols;
        for (const char *c = schemes; *c; c++) {
            int sc = *c - '0';
            struct timespec a, b;
            clock_gettime(CLOCK_MONOTONIC, &a);
            if (fr_fit_run(ctx, &fm, &st, (fr_fit_scheme)sc, n, in, res, identity)) {
                fprintf(stderr, "%s\n", frig_ctx_errmsg(ctx));
                return 1;
            }
            clock_gettime(CLOCK_MONOTONIC, &b);
            seconds[sc] += (double)(b.tv_sec - a.tv_sec) + 1e-9 * (double)(b.tv_nsec - a.tv_nsec);
            row o = {0};
            double *exp_all = calloc((size_t)frig_model_expression_count(model) + 1, sizeof(double));
            for (int i = 0; i < n; i++) {
                /* Neutral: this photo's identity (its own for individual fits). */
                frig_model_eval(ctx, model, res[i].w, NULL, est);
                o.neutral_mm += fr_aligned_mean_distance(truth_neutral, est, nface) * 1000;
                o.rot_deg += fr_rotation_angle_deg(Rt[i], res[i].R);
                if (getenv("FIT_EVAL_VERBOSE")) {
                    double ya, pa, ra, yb, pb, rb;
                    fr_rotation_to_euler(Rt[i], &ya, &pa, &ra);
                    fr_rotation_to_euler(res[i].R, &yb, &pb, &rb);
                    printf("   photo %d: truth ypr %.0f %.0f %.0f, fit %.0f %.0f %.0f, rms %.1f px\n", i, ya * 57.3,
                           pa * 57.3, ra * 57.3, yb * 57.3, pb * 57.3, rb * 57.3, res[i].rms_px);
                }
                o.reproj_px += res[i].rms_px;
                /* Expressions: weights by name, and the face displacement they make. */
                memset(exp_all, 0, sizeof(double) * (size_t)frig_model_expression_count(model));
                for (int k = 0; k < fm.n_exp; k++) exp_all[fm.exp_index[k]] = res[i].w[fm.n_id + k];
                double werr = 0;
                int nw = 0;
                for (int k = 0; k < fm.n_exp; k++) {
                    const char *name = frig_model_expression_name(model, fm.exp_index[k]);
                    int j = frig_rig_shape_find(truth_rig, name);
                    double tw = j >= 0 ? wt[(size_t)i * nshape + j] : 0;
                    werr += fabs(res[i].w[fm.n_id + k] - tw);
                    nw++;
                }
                o.exp_w += werr / nw;
                frig_model_eval(ctx, model, NULL, exp_all, est_exp);
                frig_rig_eval(ctx, truth_rig, wt + (size_t)i * nshape, truth_exp);
                double em = 0;
                for (int v = 0; v < nface; v++) {
                    double d = 0;
                    for (int e = 0; e < 3; e++) {
                        double de = (double)est_exp[3 * v + e] - frig_model_neutral(model)[3 * v + e];
                        double dt = (double)truth_exp[3 * v + e] - truth_neutral[3 * v + e];
                        d += (de - dt) * (de - dt);
                    }
                    em += sqrt(d);
                }
                o.exp_mm += em / nface * 1000;
                o.count++;
            }
            free(exp_all);
            printf("%-8d %-26s %10.2f %9.2f %9.3f %9.2f %9.2f\n", s, scheme_name[sc], o.neutral_mm / n, o.rot_deg / n,
                   o.exp_w / n, o.exp_mm / n, o.reproj_px / n);
            rows[sc].neutral_mm += o.neutral_mm / n;
            rows[sc].rot_deg += o.rot_deg / n;
            rows[sc].exp_w += o.exp_w / n;
            rows[sc].exp_mm += o.exp_mm / n;
            rows[sc].reproj_px += o.reproj_px / n;
            rows[sc].count++;
        }
        /* The mean face, for scale. */
        frig_model_eval(ctx, model, NULL, NULL, est);
        printf("%-8d %-26s %10.2f   (offset outside the span: %.2f mm RMS)\n", s, "mean face (no fit)",
               fr_aligned_mean_distance(truth_neutral, est, nface) * 1000, frig_synth_subject_offset_rms_mm(subj));
        for (int i = 0; i < n; i++) frig_image_free(crops[i]);
        free(crops), free(in), free(lmk), free(Rt), free(wt), free(res), free(W), free(Rt_all), free(wt_all), free(lmk_truth);
        free(truth_neutral), free(est), free(truth_exp), free(est_exp);
        frig_synth_subject_free(subj);
    }
    if (detected) landmark_bias_print();
    printf("\naverage over %d subjects:\n", subjects);
    for (const char *c = schemes; *c; c++) {
        int sc = *c - '0';
        row *o = &rows[sc];
        printf("%-8s %-26s %10.2f %9.2f %9.3f %9.2f %9.2f   %.2f s per subject\n", "all", scheme_name[sc],
               o->neutral_mm / o->count, o->rot_deg / o->count, o->exp_w / o->count, o->exp_mm / o->count,
               o->reproj_px / o->count, seconds[sc] / o->count);
    }
    fr_fit_model_free(&fm);
    frig_detector_free(det);
    frig_model_free(model);
    frig_ctx_free(ctx);
    return 0;
}
