/* The sfs stage on synthetic ground truth, photo by photo (paper section 5.1 measured as
 * section 7.2 measures point clouds, E_P): for a workspace made from one frig synth subject's
 * photos (detect -> filter -> fit), the stage's computation in memory, then per photo the
 * cloud's error against the true posed surface after a similarity alignment (mean, median, p90
 * mm over the kept points), next to the same for the shared-shape reference and for the fitted
 * mesh over the same pixels; the rotation error of the fit and of the refined pose; with the
 * truth's class maps, the share of bad pixels (cast shadow, highlight, occluder, hair) that the
 * skin mask and region selection remove and of good skin they keep; the neutral of the rig with
 * the shared displacement against the true neutral; the stage's time; and the expression weights
 * the clouds were drawn at against the truth's (mean |w - w_true| per weight, and the rig moved
 * by the weights' errors, mm over the narrow face), the fit's and the stage's
 * (sfs.expression_steps).
 * --stereo W adds the photos' own gradients to the shared shape (the multi-view term, gain W),
 * --joint-pose N N steps of each photo's pose against the shared shape per round, --joint-albedo
 * the texels' albedo solved with the shared shape, --shape-iterations N and --shape-sigma S its
 * Gauss-Newton iterations per round and residual scale, --shape-oracle DEG the shared shape
 * from the photos whose fit is within DEG of the truth's rotation only; --pose-noise DEG (with
 * --truth-pose) turns each photo's true rotation by DEG about an axis of its own (docs/sfs.md).
 * --truth-pose replaces the fit's pose and camera by the truth's (--truth-weights the
 * expression weights too; --truth-expression the weights alone, with the fit's pose and camera): where
 * the error lives.
 * --in-span MODEL starts from the model at the subject's true identity (only the out-of-span offset
 * to recover), --truth-neutral from the true neutral, --truth-rig from the whole true rig: with
 * --truth-weights, what the shared shape adds to a rig that needs nothing (docs/sfs.md);
 * --dump-neutral PATH writes the rig's neutral with the shared displacement as OBJ vertices;
 * --dump-errors PATH the narrow face's true neutral vertices (x y z), their normals' z and their
 * distances (m) to the true face before and after the shared displacement, a line each;
 * "per-photo mean error in the head frame, not aligned" is the clouds' error as retarget sees
 * them (with --truth-pose, where the head frames agree); "neutral as a surface" the neutral's
 * distance to the true face (not vertex to vertex: what a displacement along the normals can
 * fix), by height band and by facing;
 * --identity MODEL solves the first --identity-modes N (default sfs.identity_modes) identity modes of MODEL with the
 * shared displacement, their weights held by --identity-prior W (default sfs.identity_prior) times
 * |(1 - sfs.identity_prior_centre) fit's + change|^2;
 * the neutral's measures are then of the rig with the identity change and the displacement;
 * --write-fits saves the workspace's report with the truth's poses (--truth-pose) and weights
 * (--truth-weights) in place of the fit's and runs nothing else (then frig sfs on it).
 * Usage: sfs_eval SUBJECT_DIR WORKSPACE [--set NAME=VALUE]... [--threads T] [--truth-pose]
 *                 [--truth-weights] [--truth-expression] [--quiet] [--stereo W] [--joint-pose N] [--joint-albedo]
 *                 [--shape-iterations N] [--shape-sigma S] [--shape-oracle DEG] [--pose-noise DEG]
 *                 [--in-span MODEL | --truth-neutral | --truth-rig] [--dump-neutral PATH] [--dump-errors PATH]
 *                 [--write-fits] */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bench_param.h"
#include "core/context.h"
#include "eval/cloud_error.h"
#include "eval/shape_error.h"
#include "frig/frig.h"
#include "raster/raster.h"
#include "raster/rotation.h"
#include "rig/rig.h"
#include "sfs/sfs.h"
#include "sfs/sfs_run.h"
#include "sfs_truth.h"
#include "workspace/photoset.h"
#include "mesh/point_align.h"
#include "model/model.h"

static double now(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

/* Head-frame points of the pixels in 'sel' from depth z through the view's camera and (R, t). */
static int points(const fr_sfs_view *v, const float *z, const uint8_t *sel, const double R[9], const double t[3],
                  double *out) {
    int n = 0;
    for (int y = 0; y < v->h; y++)
        for (int x = 0; x < v->w; x++) {
            size_t i = (size_t)y * v->w + x;
            if (!sel[i] || !(z[i] > 0)) continue;
            double c[3] = {z[i] * (x - v->cam.cx) / v->cam.f - t[0], z[i] * (y - v->cam.cy) / v->cam.f - t[1], z[i] - t[2]};
            for (int k = 0; k < 3; k++) out[3 * n + k] = R[k] * c[0] + R[3 + k] * c[1] + R[6 + k] * c[2];
            n++;
        }
    return n;
}

/* The points' distances to the surface after 'iterations' rounds of a similarity alignment (0:
 * as they are): st mean, median, p90 mm; each point's distance (metres, INFINITY unmatched) into
 * out when given. */
static void aligned_it(frig_ctx *ctx, const fr_tri_tree *ix, const double *p, int n, int iterations, double st[3],
                       double *out) {
    double *d = malloc(sizeof(double) * (size_t)(n + 1)), s, R[9], t[3];
    fr_cloud_align(ctx, ix, p, n, iterations, 0.01, d, &s, R, t);
    if (out) memcpy(out, d, sizeof(double) * (size_t)n);
    int m = 0;
    for (int i = 0; i < n; i++)
        if (isfinite(d[i])) d[m++] = d[i];
    fr_error_stats(d, m, &st[0], &st[1], &st[2]);
    for (int k = 0; k < 3; k++) st[k] *= 1000;
    free(d);
}

/* After a similarity alignment (st: mean, median, p90 mm). */
static void aligned(frig_ctx *ctx, const fr_tri_tree *ix, const double *p, int n, double st[3]) {
    aligned_it(ctx, ix, p, n, 10, st, NULL);
}


/* b's error against a (n vertices) after the similarity alignment, split along a's vertex
 * normals: the mean |normal part| and |tangential part| (features in the wrong place), mm. */
static void split_error(const float *a, const float *an, const float *b, int n, double *normal, double *tangential) {
    double R[9], t[3], scale, sn = 0, stg = 0;
    *normal = *tangential = NAN;
    if (n <= 0 || !fr_point_align(a, b, n, 1, R, t, &scale)) return;
    for (int v = 0; v < n; v++) {
        double e[3], en = 0, et = 0;
        for (int i = 0; i < 3; i++) {
            double x = t[i];
            for (int j = 0; j < 3; j++) x += scale * R[3 * i + j] * b[3 * v + j];
            e[i] = x - a[3 * v + i];
            en += e[i] * an[3 * v + i];
        }
        for (int i = 0; i < 3; i++) et += (e[i] - en * an[3 * v + i]) * (e[i] - en * an[3 * v + i]);
        sn += fabs(en), stg += sqrt(et);
    }
    *normal = 1e3 * sn / n, *tangential = 1e3 * stg / n;
}

static void set_truth_fits(const frig_rig *truth_rig, frig_photoset *set, int pose, int weights, double noise_deg) {
    for (size_t i = 0; i < set->count; i++) {
        fr_photo *p = &set->photos[i];
        bench_truth tr;
        memset(&tr, 0, sizeof tr);
        if (p->fitted && bench_truth_load(p->path, truth_rig, &tr) && tr.has_face) {
            for (int e = 0; e < set->n_expressions && weights; e++) {
                int k = frig_rig_shape_find(truth_rig, set->expression_names[e]);
                p->fit_expression[e] = k >= 0 ? tr.weights[k] : 0;
            }
            if (!pose) {
                bench_truth_free(&tr);
                continue;
            }
            memcpy(p->fit_rotation, tr.R, sizeof tr.R);
            if (noise_deg > 0) {
                /* a turn of noise_deg about an axis drawn per photo (the same axes on every run) */
                double a[3], l = 0, dR[9];
                for (int q = 0; q < 3; q++) a[q] = sin(12.9898 * (double)(i + 1) * (q + 1) + 78.233 * q), l += a[q] * a[q];
                for (int q = 0; q < 3; q++) a[q] *= noise_deg * M_PI / 180 / sqrt(l);
                fr_rotation_from_axis_angle(a, dR);
                fr_mat3_mul(dR, tr.R, p->fit_rotation);
            }
            memcpy(p->fit_translation, tr.t, sizeof tr.t);
            p->fit_focal = tr.f;
        }
        bench_truth_free(&tr);
    }
}

/* The rotation error of the poses R (9 per photo) against the truth's after the head-frame turn
 * common to all of them (a gauge for the shared solve): per photo into err, stats into st (mean,
 * median, p90); returns the common turn in degrees. */
static double common_turn_error(const double *R, const double *Rtrue, int rows, double *err, double st[3]) {
    double wm[3] = {0, 0, 0}, Qm[9];
    for (int k = 0; k < rows; k++) {
        double Rt[9], Q[9], w[3];
        fr_mat3_transpose(Rtrue + 9 * k, Rt);
        fr_mat3_mul(Rt, R + 9 * k, Q);
        fr_rotation_to_axis_angle(Q, w);
        for (int q = 0; q < 3; q++) wm[q] += w[q] / rows;
    }
    fr_rotation_from_axis_angle(wm, Qm);
    for (int k = 0; k < rows; k++) {
        double RQ[9];
        fr_mat3_mul(Rtrue + 9 * k, Qm, RQ);
        err[k] = fr_rotation_angle_deg(R + 9 * k, RQ);
    }
    fr_error_stats(err, rows, &st[0], &st[1], &st[2]);
    return 57.29578 * sqrt(wm[0] * wm[0] + wm[1] * wm[1] + wm[2] * wm[2]);
}

/* --in-span MODEL: the rig's neutral becomes the model at the subject's true identity (the
 * truth projected on the model's span), so that only the out-of-span offset is left to recover. */
static int set_in_span(frig_ctx *ctx, const char *model_path, const char *subject_dir, frig_rig *rig) {
    frig_model *model = NULL;
    if (frig_model_load(ctx, model_path, &model)) return 1;
    char path[4096];
    snprintf(path, sizeof path, "%s/subject.json", subject_dir);
    char *text = bench_read_all(path, NULL);
    cJSON *root = text ? cJSON_Parse(text) : NULL;
    free(text);
    const cJSON *a = root ? cJSON_GetObjectItemCaseSensitive(root, "identity") : NULL;
    int n = frig_model_identity_count(model), nv = frig_model_vertex_count(model);
    double *w = calloc((size_t)n + 1, sizeof(double));
    float *x = malloc(sizeof(float) * 3 * (size_t)nv);
    int ok = cJSON_IsArray(a) && w && x && nv == frig_rig_vertex_count(rig);
    for (int k = 0; ok && k < n && k < cJSON_GetArraySize(a); k++) w[k] = cJSON_GetArrayItem(a, k)->valuedouble;
    ok = ok && !frig_model_eval(ctx, model, w, NULL, x) && !frig_rig_set_neutral(ctx, rig, x);
    if (!ok) fprintf(stderr, "--in-span: no identity in %s or the model does not fit the rig\n", path);
    cJSON_Delete(root);
    free(w), free(x);
    frig_model_free(model);
    return !ok;
}

/* --dump-neutral PATH: vertices as OBJ v lines (metres), for outside tools. */
static void write_vertices(const char *path, const float *x, int nv) {
    FILE *f = fopen(path, "w");
    if (!f) return;
    for (int q = 0; q < nv; q++) fprintf(f, "v %.7f %.7f %.7f\n", x[3 * q], x[3 * q + 1], x[3 * q + 2]);
    fclose(f);
}

/* How far the weights' errors dw (one per rig shape, scaled by 'scale') move the rig: the mean over the
 * narrow face (its first 6706 vertices) of |sum_j scale dw_j d_j|, mm. */
static double rig_motion_mm(const frig_rig *rig, const double *dw, double scale) {
    int nfv = 6706 < rig->topo.vertex_count ? 6706 : rig->topo.vertex_count;
    size_t n3 = 3 * (size_t)rig->topo.vertex_count;
    double sum = 0;
    for (int q = 0; q < nfv; q++) {
        double a[3] = {0, 0, 0};
        for (int j = 0; j < rig->shape_count; j++)
            for (int c = 0; c < 3; c++) a[c] += scale * dw[j] * rig->deltas[n3 * j + 3 * (size_t)q + c];
        sum += sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
    }
    return 1e3 * sum / nfv;
}

static void log_stderr(void *user, frig_log_level level, const char *msg) {
    (void)user, (void)level;
    fprintf(stderr, "%s\n", msg);
}

int main(int argc, char **argv) {
    if (argc < 3) {
        fprintf(stderr, "usage: sfs_eval SUBJECT_DIR WORKSPACE [--set NAME=VALUE]... [--threads T] [--truth-pose] "
                        "[--truth-weights] [--truth-expression] [--quiet] [--stereo W] [--joint-pose N] [--joint-albedo] "
                        "[--shape-iterations N] [--shape-sigma S] [--shape-oracle DEG] "
                        "[--pose-noise DEG] [--pose-levels N] [--pose-sigma PX] [--in-span MODEL | --truth-neutral | "
                        "--truth-rig] [--dump-neutral PATH] [--dump-errors PATH] [--write-fits] [--verbose]\n");
        return 2;
    }
    frig_ctx *ctx = frig_ctx_create();
    /* the shared shape's options: -1 keeps the sfs.* parameter's value (--set) */
    int truth_pose = 0, truth_weights = 0, quiet = 0, pose_steps = -1, joint_albedo = -1, shape_iterations = -1;
    double w_stereo = -1, shape_sigma = -1, oracle_deg = 0, pose_noise = 0, pose_sigma = -1;
    int pose_levels = -1;
    const char *in_span_model = NULL, *dump_neutral = NULL, *dump_errors = NULL;
    int truth_neutral = 0, write_fits = 0, id_modes = -1; /* -1: sfs.identity_modes */
    const char *id_model = NULL;
    double id_prior = -1; /* -1: sfs.identity_prior */
    for (int i = 3; i < argc; i++) {
        if (!strcmp(argv[i], "--set") && i + 1 < argc) {
            if (bench_set_param(ctx, argv[++i])) return 2;
        } else if (!strcmp(argv[i], "--threads") && i + 1 < argc) frig_ctx_set_threads(ctx, atoi(argv[++i]));
        else if (!strcmp(argv[i], "--truth-pose")) truth_pose = 1;
        else if (!strcmp(argv[i], "--truth-weights")) truth_pose = truth_weights = 1;
        else if (!strcmp(argv[i], "--truth-expression")) truth_weights = 1;
        else if (!strcmp(argv[i], "--quiet")) quiet = 1;
        else if (!strcmp(argv[i], "--verbose")) frig_ctx_set_log(ctx, log_stderr, NULL, FRIG_LOG_DEBUG);
        else if (!strcmp(argv[i], "--stereo") && i + 1 < argc) w_stereo = atof(argv[++i]);
        else if (!strcmp(argv[i], "--joint-pose") && i + 1 < argc) pose_steps = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--joint-albedo")) joint_albedo = 1;
        else if (!strcmp(argv[i], "--shape-oracle") && i + 1 < argc) oracle_deg = atof(argv[++i]);
        else if (!strcmp(argv[i], "--pose-noise") && i + 1 < argc) pose_noise = atof(argv[++i]);
        else if (!strcmp(argv[i], "--shape-iterations") && i + 1 < argc) shape_iterations = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--shape-sigma") && i + 1 < argc) shape_sigma = atof(argv[++i]);
        else if (!strcmp(argv[i], "--pose-levels") && i + 1 < argc) pose_levels = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--pose-sigma") && i + 1 < argc) pose_sigma = atof(argv[++i]);
        else if (!strcmp(argv[i], "--in-span") && i + 1 < argc) in_span_model = argv[++i];
        else if (!strcmp(argv[i], "--dump-neutral") && i + 1 < argc) dump_neutral = argv[++i];
        else if (!strcmp(argv[i], "--dump-errors") && i + 1 < argc) dump_errors = argv[++i];
        else if (!strcmp(argv[i], "--truth-neutral")) truth_neutral = 1;
        else if (!strcmp(argv[i], "--truth-rig")) truth_neutral = 2;
        else if (!strcmp(argv[i], "--write-fits")) write_fits = 1;
        else if (!strcmp(argv[i], "--identity") && i + 1 < argc) id_model = argv[++i];
        else if (!strcmp(argv[i], "--identity-modes") && i + 1 < argc) id_modes = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--identity-prior") && i + 1 < argc) id_prior = atof(argv[++i]);
        else {
            fprintf(stderr, "unknown argument %s\n", argv[i]);
            return 2;
        }
    }
    char path[4096];
    frig_rig *rig = NULL, *truth_rig = NULL;
    frig_photoset *set = NULL;
    snprintf(path, sizeof path, "%s/rig/rig.frigrig", truth_neutral == 2 ? argv[1] : argv[2]);
    if (frig_rig_load(ctx, path, &rig)) goto fail;
    snprintf(path, sizeof path, "%s/rig/rig.frigrig", argv[1]);
    if (frig_rig_load(ctx, path, &truth_rig)) goto fail;
    if (frig_photoset_load(ctx, argv[2], &set)) goto fail;
    if (truth_pose || truth_weights) set_truth_fits(truth_rig, set, truth_pose, truth_weights, pose_noise);
    if (write_fits) { /* the workspace's fits replaced (--truth-pose, --truth-weights), nothing else run */
        frig_status ws = frig_photoset_save(ctx, set, argv[2]);
        frig_photoset_free(set), frig_rig_free(rig), frig_rig_free(truth_rig), frig_ctx_free(ctx);
        return ws ? 1 : 0;
    }
    if (in_span_model && set_in_span(ctx, in_span_model, argv[1], rig)) goto fail;
    if (truth_neutral == 1 && frig_rig_set_neutral(ctx, rig, frig_rig_neutral(truth_rig))) goto fail;
    fr_sfs_settings st;
    fr_sfs_settings_from_ctx(ctx, &st);
    if (w_stereo >= 0) st.w_stereo = w_stereo;
    if (pose_steps >= 0) st.pose_steps = pose_steps;
    if (joint_albedo >= 0) st.joint_albedo = joint_albedo;
    if (pose_levels >= 0) st.pose_levels = pose_levels;
    if (pose_sigma > 0) st.pose_sigma_px = pose_sigma;
    if (shape_iterations > 0) st.shape_iterations = shape_iterations;
    if (shape_sigma > 0) st.shape_sigma = shape_sigma;
    frig_model *idm = NULL;
    double *id_start = NULL;
    if (id_model) {
        if (frig_model_load(ctx, id_model, &idm)) goto fail;
        if (idm->topo.vertex_count != frig_rig_vertex_count(rig)) {
            fprintf(stderr, "--identity: the model does not fit the rig\n");
            return 1;
        }
        st.identity_modes = idm->identity;
        if (id_modes < 0) id_modes = (int)frig_ctx_get_param(ctx, FRIG_PARAM_SFS_IDENTITY_MODES);
        st.identity_count = id_modes < idm->identity_count ? id_modes : idm->identity_count;
        if (id_prior >= 0) st.identity_prior = id_prior;
        id_start = calloc((size_t)st.identity_count + 1, sizeof(double));
        for (int k = 0; k < st.identity_count && k < set->n_identity && set->identity; k++) id_start[k] = set->identity[k];
        st.identity_start = id_start;
        printf("identity: %d modes, prior %g centred at %g times the fit's identity (%d weights in the workspace)\n",
               st.identity_count, st.identity_prior, st.identity_centre, set->n_identity);
    }
    uint8_t *oracle = NULL;
    if (oracle_deg > 0) {
        /* the shared shape from the photos whose fit is within oracle_deg of the truth's rotation */
        oracle = calloc(set->count + 1, 1);
        int used = 0;
        for (size_t i = 0; i < set->count; i++) {
            bench_truth tr;
            memset(&tr, 0, sizeof tr);
            if (set->photos[i].fitted && bench_truth_load(set->photos[i].path, truth_rig, &tr) && tr.has_face)
                used += oracle[i] = fr_rotation_angle_deg(set->photos[i].fit_rotation, tr.R) < oracle_deg;
            bench_truth_free(&tr);
        }
        printf("the shared shape from %d photos (fit rotation error < %.1f deg)\n", used, oracle_deg);
        st.shape_use = oracle;
    }
    double t0 = now();
    fr_sfs_run run;
    if (fr_sfs_run_all(ctx, rig, set, &st, &run)) goto fail;
    double t1 = now();
    printf("sfs computation over %d photos: %.2f s (%d threads)\n", run.n, t1 - t0, fr_threads(ctx));
    if (run.vdisp) {
        /* the rig's neutral with the shared displacement against the true neutral, narrow face, aligned */
        int nv = run.mesh.nv, nf = 6706 < nv ? 6706 : nv;
        float *a = malloc(sizeof(float) * 3 * (size_t)nv), *nr = malloc(sizeof(float) * 3 * (size_t)nv);
        memcpy(a, frig_rig_neutral(rig), sizeof(float) * 3 * (size_t)nv);
        double before = fr_aligned_mean_distance(frig_rig_neutral(truth_rig), a, nf);
        if (run.mesh.ident) {
            /* the rig's neutral with the identity change the shared solve found */
            for (size_t q = 0; q < 3 * (size_t)nv; q++) a[q] += run.mesh.ident[q];
            double b2 = 0, bt = 0;
            for (int k = 0; k < run.st.identity_count; k++) b2 += run.ident[k] * run.ident[k];
            for (int k = 0; k < run.st.identity_count; k++) bt += (id_start[k] + run.ident[k]) * (id_start[k] + run.ident[k]);
            printf("identity change: |change| %.3f (|fit + change| %.3f), neutral with it alone %.3f mm\n", sqrt(b2), sqrt(bt),
                   1e3 * fr_aligned_mean_distance(frig_rig_neutral(truth_rig), a, nf));
            printf("identity change weights:");
            for (int k = 0; k < run.st.identity_count; k++) printf(" %.4f", run.ident[k]);
            printf("\n");
        }
        fr_mesh_vertex_normals(a, nv, run.mesh.tris, run.mesh.nt, nr);
        double rms = 0;
        for (int q = 0; q < nv; q++) {
            for (int c = 0; c < 3; c++) a[3 * q + c] += run.vdisp[q] * nr[3 * q + c];
            if (q < nf) rms += (double)run.vdisp[q] * run.vdisp[q];
        }
        printf("neutral (narrow face, aligned): rig %.3f mm, with the shared displacement %.3f mm (displacement RMS %.3f mm)\n",
               1e3 * before, 1e3 * fr_aligned_mean_distance(frig_rig_neutral(truth_rig), a, nf), 1e3 * sqrt(rms / nf));
        float *tn = malloc(sizeof(float) * 3 * (size_t)nv);
        fr_mesh_vertex_normals(frig_rig_neutral(truth_rig), nv, run.mesh.tris, run.mesh.nt, tn);
        double n0, t0s, n1, t1s;
        split_error(frig_rig_neutral(truth_rig), tn, frig_rig_neutral(rig), nf, &n0, &t0s);
        if (run.mesh.ident) {
            float *ai = malloc(sizeof(float) * 3 * (size_t)nv);
            for (size_t q = 0; q < 3 * (size_t)nv; q++) ai[q] = frig_rig_neutral(rig)[q] + run.mesh.ident[q];
            double ni, ti;
            split_error(frig_rig_neutral(truth_rig), tn, ai, nf, &ni, &ti);
            printf("neutral error along the true normals / tangential with the identity change alone: %.3f / %.3f mm\n", ni, ti);
            free(ai);
        }
        split_error(frig_rig_neutral(truth_rig), tn, a, nf, &n1, &t1s);
        printf("neutral error along the true normals / tangential (mean |part|): rig %.3f / %.3f mm, with the shared "
               "displacement %.3f / %.3f mm\n", n0, t0s, n1, t1s);
        free(tn);
        {   /* as surfaces: the narrow face's vertices to the true neutral's face, after a similarity alignment */
            int32_t *ft = malloc(sizeof(int32_t) * 3 * (size_t)run.mesh.nt);
            int nft0 = 0;
            for (int t = 0; t < run.mesh.nt; t++)
                if (run.mesh.face[t]) memcpy(ft + 3 * nft0++, run.mesh.tris + 3 * t, sizeof(int32_t) * 3);
            fr_tri_tree *tix = NULL;
            fr_tri_tree_build(ctx, frig_rig_neutral(truth_rig), ft, nft0, &tix);
            double *pa = malloc(sizeof(double) * 3 * (size_t)nf), *pb = malloc(sizeof(double) * 3 * (size_t)nf);
            for (int q = 0; q < 3 * nf; q++) pa[q] = frig_rig_neutral(rig)[q], pb[q] = a[q];
            double sa[3], sb[3];
            double *da = malloc(sizeof(double) * (size_t)nf), *db = malloc(sizeof(double) * (size_t)nf);
            aligned_it(ctx, tix, pa, nf, 10, sa, da), aligned_it(ctx, tix, pb, nf, 10, sb, db);
            {   /* by region: height bands (chin .. forehead) x centre / side, and by facing */
                const float *T = frig_rig_neutral(truth_rig);
                float *tn2 = malloc(sizeof(float) * 3 * (size_t)nv);
                fr_mesh_vertex_normals(T, nv, run.mesh.tris, run.mesh.nt, tn2);
                double ymin = 1e9, ymax = -1e9;
                for (int q = 0; q < nf; q++) ymin = fmin(ymin, T[3 * q + 1]), ymax = fmax(ymax, T[3 * q + 1]);
                double sa2[5][2][2] = {{{0}}}, cnt[5][2] = {{0}};
                double fa[3] = {0}, fb[3] = {0}, fc[3] = {0};
                for (int q = 0; q < nf; q++) {
                    if (!isfinite(da[q]) || !isfinite(db[q])) continue;
                    int hb = (int)(5 * (T[3 * q + 1] - ymin) / (ymax - ymin + 1e-9));
                    int side = fabs(T[3 * q]) > 0.035;
                    sa2[hb][side][0] += da[q], sa2[hb][side][1] += db[q], cnt[hb][side]++;
                    int fz = tn2[3 * q + 2] > 0.8 ? 0 : tn2[3 * q + 2] > 0.4 ? 1 : 2;
                    fa[fz] += da[q], fb[fz] += db[q], fc[fz]++;
                }
                printf("  by height band (chin..top) centre | side, fit -> with D (mm):");
                for (int hb = 0; hb < 5; hb++)
                    printf(" [%d] %.2f->%.2f | %.2f->%.2f", hb, 1e3 * sa2[hb][0][0] / fmax(cnt[hb][0], 1),
                           1e3 * sa2[hb][0][1] / fmax(cnt[hb][0], 1), 1e3 * sa2[hb][1][0] / fmax(cnt[hb][1], 1),
                           1e3 * sa2[hb][1][1] / fmax(cnt[hb][1], 1));
                printf("\n  by facing (n_z > 0.8, 0.4-0.8, < 0.4): ");
                for (int fz = 0; fz < 3; fz++)
                    printf(" %.2f->%.2f (%.0f%%)", 1e3 * fa[fz] / fmax(fc[fz], 1), 1e3 * fb[fz] / fmax(fc[fz], 1), 100 * fc[fz] / nf);
                printf("\n");
                if (dump_errors) {
                    FILE *fo = fopen(dump_errors, "w");
                    for (int q = 0; fo && q < nf; q++)
                        fprintf(fo, "%g %g %g %g %g %g\n", T[3 * q], T[3 * q + 1], T[3 * q + 2], tn2[3 * q + 2], da[q], db[q]);
                    if (fo) fclose(fo);
                }
                free(tn2);
            }
            free(da), free(db);
            printf("neutral as a surface (narrow face's vertices to the true face, aligned; mean / median / p90): rig "
                   "%.3f / %.3f / %.3f mm, with the shared displacement %.3f / %.3f / %.3f mm\n",
                   sa[0], sa[1], sa[2], sb[0], sb[1], sb[2]);
            free(pa), free(pb), free(ft);
            fr_tri_tree_free(tix);
        }
        if (dump_neutral) write_vertices(dump_neutral, a, nv);
        free(a), free(nr);
    }
    fr_sfs_mesh tm;
    if (fr_sfs_mesh_init(ctx, truth_rig, &tm)) goto fail;
    float *txyz = malloc(sizeof(float) * 3 * (size_t)tm.nv);
    int32_t *ftris = malloc(sizeof(int32_t) * 3 * (size_t)tm.nt);
    int nft = 0;
    for (int t = 0; t < tm.nt; t++)
        if (tm.face[t]) memcpy(ftris + 3 * nft++, tm.tris + 3 * t, sizeof(int32_t) * 3);
    if (!quiet)
        printf("%-14s %6s %6s %6s %5s | %-20s | %-20s | %-20s\n", "photo", "yaw", "rot", "rot'", "kept", "cloud mean/med/p90",
               "reference", "fit (same pixels)");
    double rawc = 0, rawf = 0;
    double *mc = malloc(sizeof(double) * (size_t)(run.n + 1)), *mr = malloc(sizeof(double) * (size_t)(run.n + 1));
    double *mf = malloc(sizeof(double) * (size_t)(run.n + 1)), *rb = malloc(sizeof(double) * (size_t)(run.n + 1));
    double *ra = malloc(sizeof(double) * (size_t)(run.n + 1)), *rj = malloc(sizeof(double) * (size_t)(run.n + 1));
    double *qw = malloc(sizeof(double) * 3 * (size_t)(run.n + 1)), *Rtrue = malloc(sizeof(double) * 9 * (size_t)(run.n + 1));
    double *Rfit = malloc(sizeof(double) * 9 * (size_t)(run.n + 1)), *Rjs = malloc(sizeof(double) * 9 * (size_t)(run.n + 1));
    long bad = 0, good = 0, bad_skin = 0, bad_kept = 0, good_skin = 0, good_kept = 0;
    int rows = 0, wcount = 0;
    double wfit_err = 0, wref_err = 0, wsurf_fit = 0, wsurf_ref = 0;
    double *bias_f = calloc((size_t)rig->shape_count + 1, sizeof(double));
    double *bias_r = calloc((size_t)rig->shape_count + 1, sizeof(double));
    int nbias = 0;
    for (int k = 0; k < run.n; k++) {
        const fr_photo *p = &set->photos[run.photo[k]];
        fr_sfs_view *v = &run.views[k];
        const char *base = strrchr(p->path, '/');
        base = base ? base + 1 : p->path;
        bench_truth tr;
        int truth = bench_truth_load(p->path, truth_rig, &tr);
        if (!run.ok[k]) {
            if (!quiet) printf("%-14s (%s) sfs_failed: %s\n", base, truth ? tr.failure : "?", run.reason[k]);
            bench_truth_free(&tr);
            continue;
        }
        if (!truth || !tr.has_face) {
            if (!quiet) printf("%-14s (%s) no face in the truth, not scored\n", base, truth ? tr.failure : "?");
            bench_truth_free(&tr);
            continue;
        }
        /* the expression weights against the truth's, by name: the fit's and the stage's (refined) */
        double *dwf = calloc((size_t)rig->shape_count + 1, sizeof(double));
        double *dwr = calloc((size_t)rig->shape_count + 1, sizeof(double));
        for (int e = 0; e < set->n_expressions; e++) {
            int ks = frig_rig_shape_find(rig, set->expression_names[e]);
            int kt = frig_rig_shape_find(truth_rig, set->expression_names[e]);
            double wt = kt >= 0 ? tr.weights[kt] : 0;
            wfit_err += fabs(p->fit_expression[e] - wt), wref_err += fabs((ks >= 0 ? v->weights[ks] : 0) - wt);
            wcount++;
            if (ks >= 0) dwf[ks] = p->fit_expression[e] - wt, dwr[ks] = v->weights[ks] - wt;
        }
        /* and as a surface: the rig moved by the weights' errors, mean over the narrow face, mm */
        wsurf_fit += rig_motion_mm(rig, dwf, 1), wsurf_ref += rig_motion_mm(rig, dwr, 1);
        for (int j = 0; j < rig->shape_count; j++) bias_f[j] += dwf[j], bias_r[j] += dwr[j];
        nbias++;
        free(dwf), free(dwr);
        fr_sfs_select_region(v, &st);
        double R2[9], t2[3];
        memcpy(R2, v->R, sizeof R2), memcpy(t2, v->t, sizeof t2);
        if (st.pose && v->kept_pixels >= 50) fr_sfs_refine_pose(ctx, &run.mesh, v, R2, t2);
        if (st.cloud_region) fr_sfs_region_narrow(v, 0); /* the cloud only: the scores are of the clouds */
        size_t npx = (size_t)v->w * v->h;
        if (tr.mask)
            for (size_t q = 0; q < npx; q++) {
                if (!v->face[q]) continue;
                int x = (int)(q % v->w), y = (int)(q / v->w);
                int px = (int)floor(v->x0 + (x + 0.5) / v->s), py = (int)floor(v->y0 + (y + 0.5) / v->s);
                if (px < 0 || py < 0 || px >= tr.width || py >= tr.height) continue;
                int m = tr.mask[(size_t)py * tr.width + px];
                int b = (m & (4 | 8 | 16 | 32)) != 0, g = (m & 1) && (m & 2) && !b;
                bad += b, good += g;
                bad_skin += b && !v->skin[q], bad_kept += b && !v->kept[q];
                good_skin += g && v->skin[q], good_kept += g && v->kept[q];
            }
        uint8_t *sel = malloc(npx);
        for (size_t q = 0; q < npx; q++) sel[q] = v->kept[q] && v->z_fit[q] > 0 && v->z_ref[q] > 0;
        double *pc = malloc(sizeof(double) * 3 * npx), *pr = malloc(sizeof(double) * 3 * npx);
        double *pf = malloc(sizeof(double) * 3 * npx);
        int nc = points(v, v->z, sel, R2, t2, pc), nr = points(v, v->z_ref, sel, v->R, v->t, pr);
        int nf = points(v, v->z_fit, sel, v->R_fit, v->t_fit, pf);
        fr_sfs_mesh_eval(&tm, tr.weights, txyz);
        fr_tri_tree *ix = NULL;
        fr_tri_tree_build(ctx, txyz, ftris, nft, &ix);
        double c[3], r[3], f[3];
        aligned(ctx, ix, pc, nc, c), aligned(ctx, ix, pr, nr, r), aligned(ctx, ix, pf, nf, f);
        double c0[3], f0[3];
        aligned_it(ctx, ix, pc, nc, 0, c0, NULL), aligned_it(ctx, ix, pf, nf, 0, f0, NULL);
        rawc += c0[0], rawf += f0[0];
        double yaw, pitch, roll;
        fr_rotation_to_euler(tr.R, &yaw, &pitch, &roll);
        rb[rows] = fr_rotation_angle_deg(p->fit_rotation, tr.R), ra[rows] = fr_rotation_angle_deg(R2, tr.R);
        rj[rows] = fr_rotation_angle_deg(v->R, tr.R);
        {
            double Rt[9], Q[9], w[3];
            fr_mat3_transpose(tr.R, Rt);
            fr_mat3_mul(Rt, p->fit_rotation, Q);
            fr_rotation_to_axis_angle(Q, w);
            memcpy(qw + 3 * rows, w, sizeof w), memcpy(Rtrue + 9 * rows, tr.R, sizeof tr.R);
            memcpy(Rfit + 9 * rows, p->fit_rotation, sizeof tr.R);
            memcpy(Rjs + 9 * rows, v->R, sizeof tr.R);
        }
        if (!quiet)
            printf("%-14s %6.1f %6.2f %6.2f %5d | %6.2f %6.2f %6.2f | %6.2f %6.2f %6.2f | %6.2f %6.2f %6.2f\n", base,
                   yaw * 57.29578, rb[rows], ra[rows], nc, c[0], c[1], c[2], r[0], r[1], r[2], f[0], f[1], f[2]);
        fflush(stdout);
        mc[rows] = c[0], mr[rows] = r[0], mf[rows] = f[0];
        rows++;
        fr_tri_tree_free(ix);
        free(sel), free(pc), free(pr), free(pf);
        bench_truth_free(&tr);
    }
    printf("per-photo mean error in the head frame, not aligned (meaningful with --truth-pose): cloud %.3f mm, fit %.3f mm\n",
           rawc / (rows ? rows : 1), rawf / (rows ? rows : 1));
    double a[3], b[3], d[3], e[3], g[3];
    fr_error_stats(mc, rows, &a[0], &a[1], &a[2]);
    fr_error_stats(mr, rows, &b[0], &b[1], &b[2]);
    fr_error_stats(mf, rows, &d[0], &d[1], &d[2]);
    fr_error_stats(rb, rows, &e[0], &e[1], &e[2]);
    fr_error_stats(ra, rows, &g[0], &g[1], &g[2]);
    printf("%d photos scored; per-photo mean error, mean (median) over photos: cloud %.3f (%.3f) mm, reference %.3f (%.3f), "
           "fit %.3f (%.3f); cloud / fit %.3f\n",
           rows, a[0], a[1], b[0], b[1], d[0], d[1], d[0] > 0 ? a[0] / d[0] : NAN);
    printf("expression weights against the truth's, mean |w - w_true| per weight: fit %.4f, the stage's %.4f "
           "(%d weights)\n",
           wfit_err / (wcount ? wcount : 1), wref_err / (wcount ? wcount : 1), wcount);
    printf("the rig moved by the weights' errors, mean over the narrow face and the photos: fit %.3f mm, the stage's "
           "%.3f mm\n",
           wsurf_fit / (rows ? rows : 1), wsurf_ref / (rows ? rows : 1));
    { /* the part of the weights' errors that every photo shares (their mean): an identity error */
        double inv = 1.0 / (nbias ? nbias : 1);
        printf("the rig moved by the weights' mean error over the photos (shared by all), mean over the narrow face: "
               "fit %.3f mm, the stage's %.3f mm; largest mean errors (stage):",
               rig_motion_mm(rig, bias_f, inv), rig_motion_mm(rig, bias_r, inv));
        for (int pass = 0; pass < 6; pass++) {
            int best = -1;
            for (int j = 0; j < rig->shape_count; j++)
                if (best < 0 || fabs(bias_r[j]) > fabs(bias_r[best])) best = j;
            if (best < 0) break;
            printf(" %s %+.3f", frig_rig_shape_name(rig, best), bias_r[best] * inv);
            bias_r[best] = 0;
        }
        printf("\n");
        free(bias_f), free(bias_r);
    }
    double h[3], cm[3], turn = common_turn_error(Rfit, Rtrue, rows, qw, cm);
    printf("the fit's rotation error after its common turn (%.2f deg): mean %.2f (median %.2f) deg\n", turn, cm[0], cm[1]);
    turn = common_turn_error(Rjs, Rtrue, rows, qw, cm);
    printf("the shared solve's rotation error after its common turn (%.2f deg): mean %.2f (median %.2f) deg\n", turn,
           cm[0], cm[1]);
    fr_error_stats(rj, rows, &h[0], &h[1], &h[2]);
    printf("rotation error: fit mean %.2f (median %.2f) deg, the shared solve's %.2f (%.2f), refined by ICP %.2f (%.2f) deg\n",
           e[0], e[1], h[0], h[1], g[0], g[1]);
    if (bad + good)
        printf("region selection: bad pixels (shadow, highlight, occluder, hair) removed %.1f%% by the skin mask, %.1f%% "
               "with eq. 5.15 (of %ld); good skin kept %.1f%% by the skin mask, %.1f%% with eq. 5.15 (of %ld)\n",
               100.0 * bad_skin / (bad ? bad : 1), 100.0 * bad_kept / (bad ? bad : 1), bad,
               100.0 * good_skin / (good ? good : 1), 100.0 * good_kept / (good ? good : 1), good);
    free(oracle), free(id_start);
    frig_model_free(idm);
    free(mc), free(mr), free(mf), free(rb), free(ra), free(rj), free(qw), free(Rtrue), free(Rfit), free(Rjs), free(txyz), free(ftris);
    fr_sfs_mesh_free(&tm);
    fr_sfs_run_free(&run);
    frig_photoset_free(set), frig_rig_free(rig), frig_rig_free(truth_rig), frig_ctx_free(ctx);
    return 0;
fail:
    fprintf(stderr, "%s\n", frig_ctx_errmsg(ctx));
    return 1;
}
