/* The retarget stage on a synthetic subject's workspace (the table): the workspace has
 * been through detect, filter and fit, and has clouds (from the sfs stage, or from the true
 * depth: bench/truth_clouds). Prints, against the subject's true rig, the neutral error, E_B
 * and the moving-vertex delta error (bench/rig_score.h) of: the generic template, the fit's
 * model-space rig, the best in-span rig (the true identity with the template's deltas), and
 * the rig after each outer round (refit on the rig, with --sfs the clouds recovered by the sfs
 * stage with the new rig, retarget; else the clouds stay), with each
 * round's time, the expression-weight error against the truth and the correspondence figures.
 * Usage: retarget_eval MODEL WORKSPACE [--rounds N] [--threads T] [--set NAME=VALUE]...
 *                      [--sfs] [--where] [--cloud-error] [--oracle | --oracle-vertices N] [--save RIG] [--quiet] */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bench_param.h"
#include "core/context.h"
#include "frig/frig.h"
#include "mesh/laplacian_deform.h"
#include "mesh/point_align.h"
#include "mesh/topology.h"
#include "retarget/collisions.h"
#include "retarget/retarget.h"
#include "rig/rig.h"
#include "workspace/photoset.h"
#include "rig_score.h"
#include "synth_truth.h"

static double now(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static void log_line(void *user, frig_log_level level, const char *msg) {
    (void)user, (void)level;
    fprintf(stderr, "  [%s]\n", msg);
}

static void row(const char *name, rig_score s, const char *extra) {
    printf("%-28s %8.3f %8.3f %8.3f %8.3f | %8.3f %8.3f  %s\n", name, s.neutral_mm, s.neutral_raw_mm, s.eb_mm,
           s.delta_mm, s.head_raw_mm, s.head_delta_mm, extra ? extra : "");
    fflush(stdout);
}

/* Mean |w - w_true| over the fitted photos and the fitting shapes. */
static double weight_error(const frig_photoset *set) {
    int ne = frig_photoset_fit_expression_count(set), n = 0;
    double *w = malloc(sizeof(double) * (ne + 1)), err = 0;
    for (size_t i = 0; i < frig_photoset_count(set); i++) {
        if (frig_photoset_status(set, i) != FRIG_PHOTO_OK || !frig_photoset_fitted(set, i)) continue;
        synth_photo_truth tr;
        if (!synth_truth_read(frig_photoset_path(set, i), 0, &tr)) continue;
        frig_photoset_fit_expression(set, i, w);
        for (int k = 0; k < ne; k++) {
            double t = 0;
            for (int q = 0; q < tr.n_expr; q++)
                if (!strcmp(tr.names[q], frig_photoset_fit_expression_name(set, k))) t = tr.weights[q];
            err += fabs(w[k] - t);
        }
        n++;
    }
    free(w);
    return n ? err / (n * (double)ne) : NAN;
}

static int read_identity(const char *subject_json, double *w, int n) {
    char *text = synth_read_text(subject_json);
    cJSON *root = text ? cJSON_Parse(text) : NULL;
    free(text);
    const cJSON *a = root ? cJSON_GetObjectItemCaseSensitive(root, "identity") : NULL;
    int ok = cJSON_IsArray(a) && cJSON_GetArraySize(a) <= n;
    for (int k = 0; ok && k < n; k++) w[k] = k < cJSON_GetArraySize(a) ? cJSON_GetArrayItem(a, k)->valuedouble : 0;
    cJSON_Delete(root);
    return ok;
}

/* Mean distance over the vertices with cover > 0.5 (raw, in the rig's frame). */
static double covered_distance(const float *a, const float *b, const float *cover, int nf) {
    double s = 0;
    int n = 0;
    for (int v = 0; v < nf; v++) {
        if (cover && cover[v] <= 0.5) continue;
        double d = 0;
        for (int k = 0; k < 3; k++) d += (a[3 * v + k] - b[3 * v + k]) * (a[3 * v + k] - b[3 * v + k]);
        s += sqrt(d), n++;
    }
    return n ? 1e3 * s / n : NAN;
}

/* Algorithm 7 alone on every photo: the reconstruction before and M'_i after, against the
 * photo's true shape (true neutral and deltas with the true weights), over the vertices the
 * cloud covers; raw (rig frame) and after similarity alignment. */
static void correspondence_report(frig_ctx *ctx, const frig_model *model, const frig_photoset *set,
                                  const frig_clouds *clouds, const frig_rig *rig, const frig_rig *truth, int nf) {
    fr_rt_settings s;
    fr_rt_settings_from_ctx(ctx, &s);
    fr_rt_mesh m;
    fr_lap_system *sys = NULL;
    fr_lap_solver *sv = NULL;
    if (fr_rt_mesh_make(ctx, nf, rig->topo.triangles, rig->topo.triangle_count, rig->neutral, &m) ||
        fr_lap_system_create(ctx, nf, m.tris, m.nt, rig->neutral, s.smooth_order, &sys) || fr_lap_solver_create(ctx, sys, &sv)) {
        fprintf(stderr, "%s\n", frig_ctx_errmsg(ctx));
        return;
    }
    int nv = frig_rig_vertex_count(rig), ns = frig_rig_shape_count(rig), nt = frig_rig_shape_count(truth);
    float *rest = malloc(sizeof(float) * 3 * nv), *tru = malloc(sizeof(float) * 3 * nv);
    double *w = calloc(ns + 1, sizeof(double)), *wt = calloc(nt + 1, sizeof(double));
    int ne = frig_photoset_fit_expression_count(set);
    double *we = calloc(ne + 1, sizeof(double));
    fr_rt_photo p;
    memset(&p, 0, sizeof p);
    for (int k = 0; k < 9; k++) p.R[k] = k % 4 == 0;
    p.M = malloc(sizeof(float) * 3 * nf);
    p.cover = malloc(sizeof(float) * nf);
    double sum[4] = {0, 0, 0, 0};
    int count = 0;
    printf("correspondence (Algorithm 7) per photo, mm over covered vertices: before raw/aligned -> after raw/aligned\n");
    int saved = fr_blas_serial_begin();
    for (size_t i = 0; i < frig_photoset_count(set); i++) {
        if (frig_photoset_status(set, i) != FRIG_PHOTO_OK || !frig_photoset_fitted(set, i) ||
            frig_clouds_count(clouds, i) == 0)
            continue;
        synth_photo_truth tr;
        if (!synth_truth_read(frig_photoset_path(set, i), 0, &tr)) continue;
        frig_photoset_fit_expression(set, i, we);
        memset(w, 0, sizeof(double) * ns);
        for (int k = 0; k < ne; k++) {
            int j = frig_rig_shape_find(rig, frig_photoset_fit_expression_name(set, k));
            if (j >= 0) w[j] = we[k];
        }
        memset(wt, 0, sizeof(double) * nt);
        for (int q = 0; q < tr.n_expr; q++) {
            int j = frig_rig_shape_find(truth, tr.names[q]);
            if (j >= 0) wt[j] = tr.weights[q];
        }
        frig_rig_eval(ctx, rig, w, rest);
        frig_rig_eval(ctx, truth, wt, tru);
        fr_rt_photo_borrow_cloud(&p, clouds, i);
        fr_rt_thin_cloud(ctx, &s, &p);
        for (int k = 0; k < 9; k++) p.R[k] = k % 4 == 0;
        p.t[0] = p.t[1] = p.t[2] = 0;
        p.scale = 1;
        if (fr_rt_correspond(ctx, &s, &m, sv, fr_lap_system_mass(sys), m.tree, rest, &p)) {
            fprintf(stderr, "%s\n", frig_ctx_errmsg(ctx));
            break;
        }
        double b_raw = covered_distance(rest, tru, p.cover, nf), a_raw = covered_distance(p.M, tru, p.cover, nf);
        double b_al = 1e3 * fr_aligned_mean_distance(tru, rest, nf), a_al = 1e3 * fr_aligned_mean_distance(tru, p.M, nf);
        printf("  photo %3zu: %5d points, %5d matched, rms %.2f, rigid %.2f deg %.2f mm: %.2f / %.2f -> %.2f / %.2f\n", i,
               p.n_pick, p.inliers, p.rms_mm, p.rigid_deg, p.rigid_mm, b_raw, b_al, a_raw, a_al);
        sum[0] += b_raw, sum[1] += b_al, sum[2] += a_raw, sum[3] += a_al, count++;
    }
    fr_blas_serial_end(saved);
    if (count)
        printf("  mean of %d photos: %.2f / %.2f -> %.2f / %.2f\n", count, sum[0] / count, sum[1] / count,
               sum[2] / count, sum[3] / count);
    free(rest), free(tru), free(w), free(wt), free(we), free(p.M), free(p.cover), free(p.pick), free(p.hint);
    fr_lap_solver_free(sv);
    fr_lap_system_free(sys);
    fr_rt_mesh_free(&m);
}

/* E_P of the clouds themselves: each cloud aligned (rotation, translation, scale) to the photo's
 * true shape (true neutral and deltas, true weights) and its RMS distance to it, over the points
 * within 10 mm. */
static void cloud_error_report(frig_ctx *ctx, const frig_photoset *set, const frig_clouds *clouds,
                               const frig_rig *truth, int nf) {
    fr_rt_settings s;
    fr_rt_settings_from_ctx(ctx, &s);
    s.rigid_iterations = 20;
    s.deform_iterations = 1;
    s.max_correction = M_PI, s.max_rms = 1; /* the cloud's frame is the fit's: measure, do not reject */
    s.smooth = 10.0; /* metres: no deformation to speak of */
    s.cloud_scale = 1;
    fr_rt_mesh m;
    fr_lap_system *sys = NULL;
    fr_lap_solver *sv = NULL;
    if (fr_rt_mesh_make(ctx, nf, truth->topo.triangles, truth->topo.triangle_count, truth->neutral, &m) ||
        fr_lap_system_create(ctx, nf, m.tris, m.nt, truth->neutral, 1, &sys) || fr_lap_solver_create(ctx, sys, &sv))
        return;
    int nv = frig_rig_vertex_count(truth), nt = frig_rig_shape_count(truth), count = 0;
    float *tru = malloc(sizeof(float) * 3 * nv);
    double *wt = calloc(nt + 1, sizeof(double)), sum = 0, sum_scale = 0;
    fr_rt_photo p;
    memset(&p, 0, sizeof p);
    p.M = malloc(sizeof(float) * 3 * nf);
    p.cover = malloc(sizeof(float) * nf);
    int saved = fr_blas_serial_begin();
    for (size_t i = 0; i < frig_photoset_count(set); i++) {
        if (!frig_clouds_count(clouds, i) || !frig_photoset_fitted(set, i)) continue;
        synth_photo_truth tr;
        if (!synth_truth_read(frig_photoset_path(set, i), 0, &tr)) continue;
        memset(wt, 0, sizeof(double) * nt);
        for (int q = 0; q < tr.n_expr; q++) {
            int j = frig_rig_shape_find(truth, tr.names[q]);
            if (j >= 0) wt[j] = tr.weights[q];
        }
        frig_rig_eval(ctx, truth, wt, tru);
        fr_rt_photo_borrow_cloud(&p, clouds, i);
        p.n_points = p.n_core; /* the cloud alone: its own error */
        fr_rt_thin_cloud(ctx, &s, &p);
        for (int k = 0; k < 9; k++) p.R[k] = k % 4 == 0;
        p.t[0] = p.t[1] = p.t[2] = 0;
        p.scale = 1;
        if (fr_rt_correspond(ctx, &s, &m, sv, fr_lap_system_mass(sys), m.tree, tru, &p) || !isfinite(p.rms_mm)) continue;
        sum += p.rms_mm, sum_scale += p.scale, count++;
    }
    fr_blas_serial_end(saved);
    if (count)
        printf("clouds against the true surface (aligned, points within 10 mm): RMS %.2f mm over %d photos, mean "
               "scale %.4f\n", sum / count, count, sum_scale / count);
    free(tru), free(wt), free(p.M), free(p.cover), free(p.pick), free(p.hint);
    fr_lap_solver_free(sv);
    fr_lap_system_free(sys);
    fr_rt_mesh_free(&m);
}

/* --where: where a neutral's error is, against the truth over the face: the similarity that
 * aligns it (its scale and shift: the raw frame's share), then of the aligned error the parts
 * along the true normal and along the surface, the smooth part (the error field averaged over
 * 30 rounds of mesh neighbours, ~ a few cm) and the rest, and the mean by height band. */
static void where_report(frig_ctx *ctx, const char *name, const frig_rig *truth, const float *neutral, int nf) {
    const float *tn = frig_rig_neutral(truth);
    double R[9], tt[3], sc;
    if (!fr_point_align(tn, neutral, nf, 1, R, tt, &sc)) return;
    int nv = frig_rig_vertex_count(truth), ntri = truth->topo.triangle_count;
    const int32_t *tri = truth->topo.triangles;
    float *nrm = malloc(sizeof(float) * 3 * nv);
    double *e = malloc(sizeof(double) * 3 * nf), *lo = malloc(sizeof(double) * 3 * nf), *acc = malloc(sizeof(double) * 4 * nf);
    fr_vertex_normals(ctx, nv, tn, ntri, tri, nrm);
    double dn = 0, dt = 0, all = 0, rot = 0;
    for (int v = 0; v < nf; v++) {
        double dot = 0;
        for (int k = 0; k < 3; k++) {
            double x = tt[k];
            for (int j = 0; j < 3; j++) x += sc * R[3 * k + j] * neutral[3 * v + j];
            e[3 * v + k] = lo[3 * v + k] = x - tn[3 * v + k];
            dot += e[3 * v + k] * nrm[3 * v + k];
        }
        double m = sqrt(e[3 * v] * e[3 * v] + e[3 * v + 1] * e[3 * v + 1] + e[3 * v + 2] * e[3 * v + 2]);
        all += m, dn += fabs(dot), dt += sqrt(fmax(m * m - dot * dot, 0));
    }
    rot = acos(fmax(-1, fmin(1, (R[0] + R[4] + R[8] - 1) / 2))) * 180 / M_PI;
    for (int it = 0; it < 30; it++) {
        memset(acc, 0, sizeof(double) * 4 * nf);
        for (int f = 0; f < ntri; f++) {
            const int32_t *q = tri + 3 * f;
            if (q[0] >= nf || q[1] >= nf || q[2] >= nf) continue;
            for (int a = 0; a < 3; a++)
                for (int b = 0; b < 3; b++) {
                    if (a == b) continue;
                    for (int k = 0; k < 3; k++) acc[4 * q[a] + k] += lo[3 * q[b] + k];
                    acc[4 * q[a] + 3] += 1;
                }
        }
        for (int v = 0; v < nf; v++)
            if (acc[4 * v + 3] > 0)
                for (int k = 0; k < 3; k++) lo[3 * v + k] = 0.5 * lo[3 * v + k] + 0.5 * acc[4 * v + k] / acc[4 * v + 3];
    }
    double low = 0, high = 0, band[4] = {0, 0, 0, 0}, ymin = 1e9, ymax = -1e9;
    int nb[4] = {0, 0, 0, 0};
    for (int v = 0; v < nf; v++) ymin = fmin(ymin, tn[3 * v + 1]), ymax = fmax(ymax, tn[3 * v + 1]);
    for (int v = 0; v < nf; v++) {
        double l = 0, h = 0, m = 0;
        for (int k = 0; k < 3; k++) {
            l += lo[3 * v + k] * lo[3 * v + k];
            h += (e[3 * v + k] - lo[3 * v + k]) * (e[3 * v + k] - lo[3 * v + k]);
            m += e[3 * v + k] * e[3 * v + k];
        }
        low += sqrt(l), high += sqrt(h);
        int b = (int)(4 * (tn[3 * v + 1] - ymin) / (ymax - ymin + 1e-9));
        band[b] += sqrt(m), nb[b]++;
    }
    printf("where %-22s scale %.4f shift %.2f mm turn %.2f deg | aligned %.3f: normal %.3f tangential %.3f | smooth %.3f "
           "rest %.3f | by height (chin..top) %.2f %.2f %.2f %.2f (shares %.2f %.2f %.2f %.2f)\n",
           name, sc, 1e3 * sqrt(tt[0] * tt[0] + tt[1] * tt[1] + tt[2] * tt[2]), rot, 1e3 * all / nf, 1e3 * dn / nf,
           1e3 * dt / nf, 1e3 * low / nf, 1e3 * high / nf, 1e3 * band[0] / nb[0], 1e3 * band[1] / nb[1],
           1e3 * band[2] / nb[2], 1e3 * band[3] / nb[3], (double)nb[0] / nf, (double)nb[1] / nf, (double)nb[2] / nf,
           (double)nb[3] / nf);
    free(nrm), free(e), free(lo), free(acc);
}

/* A copy of the set's fitted identity; returns its length. */
static int copy_identity(const frig_photoset *set, double **out) {
    const double *id0;
    int nid = frig_photoset_identity(set, &id0);
    *out = malloc(sizeof(double) * (nid + 1));
    memcpy(*out, id0, sizeof(double) * nid);
    return nid;
}

/* The identity from the clouds alone (identity_fit.c), scored after each number of steps. */
static void identity_report(frig_ctx *ctx, const frig_model *model, frig_photoset *set, const frig_clouds *clouds,
                            frig_rig *rig0, const frig_rig *truth, int nf, int steps, const double *wtrue) {
    fr_rt_settings s;
    fr_rt_settings_from_ctx(ctx, &s);
    fr_rt_mesh m;
    fr_rt_mesh_make(ctx, nf, rig0->topo.triangles, rig0->topo.triangle_count, rig0->neutral, &m);
    int ne = frig_photoset_fit_expression_count(set), K = 0, *fit_shape = malloc(sizeof(int) * (ne + 1));
    int *slot = malloc(sizeof(int) * (ne + 1));
    for (int k = 0; k < ne; k++) {
        int j = frig_rig_shape_find(rig0, frig_photoset_fit_expression_name(set, k));
        slot[k] = j >= 0 ? K : -1;
        if (j >= 0) fit_shape[K++] = j;
    }
    fr_rt_photo *ph = calloc(frig_photoset_count(set), sizeof *ph);
    int n = 0;
    double *we = calloc(ne + 1, sizeof(double));
    for (size_t i = 0; i < frig_photoset_count(set); i++) {
        if (frig_photoset_status(set, i) != FRIG_PHOTO_OK || !frig_photoset_fitted(set, i) || !frig_clouds_count(clouds, i))
            continue;
        fr_rt_photo *p = &ph[n++];
        p->index = i;
        fr_rt_photo_borrow_cloud(p, clouds, i);
        for (int k = 0; k < 9; k++) p->R[k] = k % 4 == 0;
        p->scale = 1;
        p->w = calloc(K + 1, sizeof(double));
        double R[9], t[3], f, lm[136];
        int W, H, persp;
        frig_photoset_fit_pose(set, i, R, t, &f, &persp);
        frig_photoset_size(set, i, &W, &H);
        if (!frig_photoset_face_landmarks(set, i, (size_t)frig_photoset_subject(set, i), lm) && persp)
            fr_rt_lift_landmarks(p, R, t, f, 0.5 * (W - 1), 0.5 * (H - 1), lm, 1.5);
        frig_photoset_fit_expression(set, i, we);
        for (int k = 0; k < ne; k++)
            if (slot[k] >= 0) p->w[slot[k]] = we[k];
        fr_rt_thin_cloud(ctx, &s, p);
    }
    double *id = NULL;
    int nid = copy_identity(set, &id);
    frig_rig *rig = NULL;
    frig_rig_clone(ctx, rig0, &rig);
    printf("identity from the clouds: steps, neutral, raw, |w - w_true| of the photos\n");
    for (int it = 0; it <= steps; it++) {
        if (it > 0 && fr_rt_fit_identity(ctx, &s, model, rig, &m, K, fit_shape, n, ph, id, nid, 1))
            fprintf(stderr, "%s\n", frig_ctx_errmsg(ctx));
        double err = 0;
        int cnt = 0;
        for (int a = 0; a < n; a++) {
            synth_photo_truth tr;
            if (!synth_truth_read(frig_photoset_path(set, ph[a].index), 0, &tr)) continue;
            for (int k = 0; k < ne; k++) {
                if (slot[k] < 0) continue;
                double t = 0;
                for (int q = 0; q < tr.n_expr; q++)
                    if (!strcmp(tr.names[q], frig_photoset_fit_expression_name(set, k))) t = tr.weights[q];
                err += fabs(ph[a].w[slot[k]] - t), cnt++;
            }
        }
        rig_score sc = rig_score_rig(truth, rig, nf);
        /* The in-span part: model(identity) against model(true identity); and our neutral's
         * error split along the true surface's normal and across it. */
        double in_span = NAN, nrm = 0, tan = 0;
        if (wtrue) {
            float *a = malloc(sizeof(float) * 3 * frig_model_vertex_count(model)), *b = malloc(sizeof(float) * 3 * frig_model_vertex_count(model));
            frig_model_eval(ctx, model, id, NULL, a);
            frig_model_eval(ctx, model, wtrue, NULL, b);
            in_span = 1e3 * fr_aligned_mean_distance(b, a, nf);
            free(a), free(b);
        }
        const float *tn = frig_rig_neutral(truth), *on = frig_rig_neutral(rig);
        float *tnorm = malloc(sizeof(float) * 3 * frig_rig_vertex_count(truth));
        fr_vertex_normals(NULL, frig_rig_vertex_count(truth), tn, truth->topo.triangle_count, truth->topo.triangles, tnorm);
        for (int v = 0; v < nf; v++) {
            double d[3], dn = 0;
            for (int k = 0; k < 3; k++) d[k] = on[3 * v + k] - tn[3 * v + k], dn += d[k] * tnorm[3 * v + k];
            double t2 = 0;
            for (int k = 0; k < 3; k++) t2 += (d[k] - dn * tnorm[3 * v + k]) * (d[k] - dn * tnorm[3 * v + k]);
            nrm += fabs(dn) / nf, tan += sqrt(t2) / nf;
        }
        free(tnorm);
        printf("  %d: %.3f %.3f  weights %.4f  in-span %.3f  raw normal %.3f tangential %.3f\n", it, sc.neutral_mm,
               sc.neutral_raw_mm, err / cnt, in_span, 1e3 * nrm, 1e3 * tan);
    }
    /* Keep the result for what follows (the correspondence report, the rounds). */
    frig_rig_set_neutral(ctx, rig0, frig_rig_neutral(rig));
    for (int a = 0; a < n; a++) {
        double R[9], t[3], f;
        int persp;
        frig_photoset_fit_pose(set, ph[a].index, R, t, &f, &persp);
        frig_photoset_fit_expression(set, ph[a].index, we);
        for (int k = 0; k < ne; k++)
            if (slot[k] >= 0) we[k] = ph[a].w[slot[k]];
        fr_photoset_set_fit(ctx, set, ph[a].index, R, t, f, persp, we, frig_photoset_fit_error(set, ph[a].index), 0);
    }
    for (int a = 0; a < n; a++) free(ph[a].w), free(ph[a].pick), free(ph[a].hint);
    free(ph), free(we), free(id), free(fit_shape), free(slot);
    frig_rig_free(rig);
    fr_rt_mesh_free(&m);
}

/* Oracle: the identity fit to the true neutral itself (every face vertex a cloud point with its
 * normal, or the first oracle_vertices of them: 6706 is the narrow face the sfs clouds keep), one
 * "photo" with no expression; tells what the surface alone says about the identity. */
static void oracle_report(frig_ctx *ctx, const frig_model *model, const frig_photoset *set, const frig_rig *rig0,
                          const frig_rig *truth, int nf, const double *wtrue, int oracle_vertices) {
    fr_rt_settings s;
    fr_rt_settings_from_ctx(ctx, &s);
    s.landmark_sigma = 0;
    fr_rt_mesh m;
    fr_rt_mesh_make(ctx, nf, rig0->topo.triangles, rig0->topo.triangle_count, rig0->neutral, &m);
    int nv = frig_rig_vertex_count(truth);
    float *nrm = malloc(sizeof(float) * 3 * nv), *conf = malloc(sizeof(float) * nv);
    fr_vertex_normals(NULL, nv, frig_rig_neutral(truth), truth->topo.triangle_count, truth->topo.triangles, nrm);
    for (int v = 0; v < nv; v++) conf[v] = 1;
    fr_rt_photo p;
    memset(&p, 0, sizeof p);
    p.xyz = frig_rig_neutral(truth), p.nrm = nrm, p.conf = conf, p.n_points = p.n_core = nf;
    for (int k = 0; k < 9; k++) p.R[k] = k % 4 == 0;
    p.scale = 1;
    p.pick = malloc(sizeof(int) * nf);
    p.hint = malloc(sizeof(int) * nf);
    int lim = oracle_vertices > 0 && oracle_vertices < nf ? oracle_vertices : nf;
    for (int v = 0; v < lim; v++) if (!m.rim[v]) p.hint[p.n_pick] = -1, p.pick[p.n_pick++] = v;
    int K = 1, fit_shape[1] = {0};
    p.w = calloc(2, sizeof(double));
    double *id = NULL;
    int nid = copy_identity(set, &id);
    frig_rig *rig = NULL;
    frig_rig_clone(ctx, rig0, &rig);
    float *a = malloc(sizeof(float) * 3 * nv), *b = malloc(sizeof(float) * 3 * nv);
    frig_model_eval(ctx, model, wtrue, NULL, b);
    printf("oracle: identity fitted to the true neutral surface (all face vertices, point-to-plane)\n");
    for (int it = 0; it <= 12; it++) {
        if (it && fr_rt_fit_identity(ctx, &s, model, rig, &m, K, fit_shape, 1, &p, id, nid, 1)) fprintf(stderr, "%s\n", frig_ctx_errmsg(ctx));
        frig_model_eval(ctx, model, id, NULL, a);
        rig_score sc = rig_score_rig(truth, rig, nf);
        printf("  %d: neutral %.3f raw %.3f in-span %.3f\n", it, sc.neutral_mm, sc.neutral_raw_mm, 1e3 * fr_aligned_mean_distance(b, a, nf));
    }
    free(a), free(b), free(nrm), free(conf), free(p.pick), free(p.hint), free(p.w), free(id);
    frig_rig_free(rig);
    fr_rt_mesh_free(&m);
}

/* Worst lid clearance and teeth depth over the shapes, and the worst change from the template's
 * same shape (mm). */
static void collision_row(frig_ctx *ctx, const frig_model *model, const char *name, const frig_rig *rig,
                          const double *lid_t, const double *teeth_t) {
    int S = frig_rig_shape_count(rig);
    double *lid = malloc(sizeof(double) * (S + 1)), *teeth = malloc(sizeof(double) * (S + 1));
    if (fr_rt_collisions(ctx, model, frig_rig_neutral(rig), frig_rig_shape_deltas(rig, 0), S, lid, teeth)) return;
    double lmin = INFINITY, tmax = -INFINITY, dl = INFINITY, dt = -INFINITY;
    for (int k = 0; k <= S; k++) {
        lmin = fmin(lmin, lid[k]), tmax = fmax(tmax, teeth[k]);
        if (lid_t) dl = fmin(dl, lid[k] - fmin(lid_t[k], 0)), dt = fmax(dt, teeth[k] - fmax(teeth_t[k], 0));
    }
    printf("collisions %-18s lid clearance min %.2f mm, teeth in front of the lips max %.2f mm", name, 1e3 * lmin, 1e3 * tmax);
    if (lid_t) printf(" (beyond the template's: lid %.2f, teeth %.2f)", 1e3 * dl, 1e3 * dt);
    printf("\n");
    free(lid), free(teeth);
}

int main(int argc, char **argv) {
    if (argc < 3) {
        fprintf(stderr, "usage: retarget_eval MODEL WORKSPACE [--rounds N] [--threads T] [--set NAME=VALUE] "
                        "[--sfs] [--save RIG] [--quiet]\n");
        return 2;
    }
    frig_ctx *ctx = frig_ctx_create();
    int rounds = 3, threads = 0, quiet = 0, corr = 0, id_steps = 0, limit = 0, sfs = 0, where = 0, oracle_vertices = 0;
    const char *save = NULL, *sheet = NULL, *ws = argv[2];
    for (int i = 3; i < argc; i++) {
        if (!strcmp(argv[i], "--rounds") && i + 1 < argc) rounds = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--threads") && i + 1 < argc) threads = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--save") && i + 1 < argc) save = argv[++i];
        else if (!strcmp(argv[i], "--sheet") && i + 1 < argc) sheet = argv[++i];
        else if (!strcmp(argv[i], "--quiet")) quiet = 1;
        else if (!strcmp(argv[i], "--sfs")) sfs = 1;
        else if (!strcmp(argv[i], "--where")) where = 1;
        else if (!strcmp(argv[i], "--correspondence")) corr = 1;
        else if (!strcmp(argv[i], "--oracle")) corr = 2;
        else if (!strcmp(argv[i], "--oracle-vertices") && i + 1 < argc) corr = 2, oracle_vertices = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--cloud-error")) corr = 3;
        else if (!strcmp(argv[i], "--identity") && i + 1 < argc) id_steps = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--limit") && i + 1 < argc) limit = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--set") && i + 1 < argc) {
            if (bench_set_param(ctx, argv[++i])) return 2;
        } else {
            fprintf(stderr, "unknown option %s\n", argv[i]);
            return 2;
        }
    }
    frig_ctx_set_threads(ctx, threads);
    frig_model *model = NULL;
    frig_photoset *set = NULL;
    frig_rig *rig = NULL, *truth = NULL, *tmp = NULL;
    frig_clouds *clouds = NULL;
    char path[4200];
    snprintf(path, sizeof path, "%s/rig/rig.frigrig", ws);
    if (frig_model_load(ctx, argv[1], &model) || frig_photoset_load(ctx, ws, &set) || frig_rig_load(ctx, path, &rig) ||
        frig_clouds_load(ctx, set, ws, &clouds)) {
        fprintf(stderr, "%s\n", frig_ctx_errmsg(ctx));
        return 1;
    }
    /* --limit N: only the first N usable photos take part. */
    for (size_t i = 0, used = 0; limit > 0 && i < frig_photoset_count(set); i++)
        if (frig_photoset_status(set, i) == FRIG_PHOTO_OK && frig_photoset_fitted(set, i) && ++used > (size_t)limit)
            frig_photoset_set_status(ctx, set, i, FRIG_PHOTO_OUTLIER, "left out (--limit)");
    /* The truth beside the photos: subject_SS/rig/rig.frigrig and subject_SS/subject.json. */
    const char *photo = frig_photoset_path(set, 0), *slash = strrchr(photo, '/');
    if (!slash || slash - photo < 7) return 1;
    int base = (int)(slash - 6 - photo);
    snprintf(path, sizeof path, "%.*srig/rig.frigrig", base, photo);
    if (frig_rig_load(ctx, path, &truth)) {
        fprintf(stderr, "%s\n", frig_ctx_errmsg(ctx));
        return 1;
    }
    int nf = 9409, face = frig_model_region_find(model, "face");
    if (face >= 0) frig_model_region(model, face, NULL, NULL, &nf);
    printf("%s: %zu photos; against %s (face region, %d vertices)\n", ws, frig_photoset_count(set), path, nf);
    printf("%-28s %8s %8s %8s %8s | %8s %8s   (mm; face region | whole head)\n", "rig", "neutral", "raw", "E_B",
           "delta", "head raw", "delta");
    /* Template, model-space, best in-span. */
    frig_rig_from_model(ctx, model, NULL, &tmp);
    row("generic template", rig_score_rig(truth, tmp, nf), NULL);
    if (where) where_report(ctx, "template", truth, frig_rig_neutral(tmp), nf);
    frig_rig_free(tmp);
    char extra[256];
    snprintf(extra, sizeof extra, "weights |w - w_true| %.4f", weight_error(set));
    row("fit (model-space rig)", rig_score_rig(truth, rig, nf), extra);
    if (where) where_report(ctx, "fit", truth, frig_rig_neutral(rig), nf);
    frig_rig *fit_rig = NULL;
    frig_rig_clone(ctx, rig, &fit_rig);
    int nid = frig_model_identity_count(model);
    double *wtrue = calloc(nid + 1, sizeof(double));
    snprintf(path, sizeof path, "%.*ssubject.json", base, photo);
    if (read_identity(path, wtrue, nid) && !frig_rig_from_model(ctx, model, wtrue, &tmp)) {
        row("best in-span (true identity)", rig_score_rig(truth, tmp, nf), NULL);
        if (where) where_report(ctx, "best in-span", truth, frig_rig_neutral(tmp), nf);
        frig_rig_free(tmp);
    } else {
        free(wtrue);
        wtrue = NULL;
    }
    if (!quiet) frig_ctx_set_log(ctx, log_line, NULL, getenv("RETARGET_EVAL_DEBUG") ? FRIG_LOG_DEBUG : FRIG_LOG_ERROR);
    if (corr == 2 && wtrue) oracle_report(ctx, model, set, rig, truth, nf, wtrue, oracle_vertices);
    if (corr == 3) cloud_error_report(ctx, set, clouds, truth, nf);
    if (id_steps) identity_report(ctx, model, set, clouds, rig, truth, nf, id_steps, wtrue);
    if (corr == 1) correspondence_report(ctx, model, set, clouds, rig, truth, nf);
    for (int r = 0; r < rounds; r++) {
        double t0 = now(), t_fit = 0, t_sfs = 0;
        if (r > 0) {
            if (frig_fit_rig(ctx, model, rig, set)) {
                fprintf(stderr, "%s\n", frig_ctx_errmsg(ctx));
                return 1;
            }
            t_fit = now() - t0;
            if (sfs && frig_retarget_recover_sfs(NULL, ctx, model, rig, set, &clouds)) {
                fprintf(stderr, "%s\n", frig_ctx_errmsg(ctx));
                return 1;
            }
            t_sfs = now() - t0 - t_fit;
            if (sfs && corr == 3) cloud_error_report(ctx, set, clouds, truth, nf);
        }
        double t1 = now();
        /* as frig_retarget_refine: the loop's own iteration counts after the first round */
        if (r > 0 ? fr_rt_retarget_later_round(ctx, model, set, clouds, rig) : frig_retarget(ctx, model, set, clouds, rig)) {
            fprintf(stderr, "%s\n", frig_ctx_errmsg(ctx));
            return 1;
        }
        double t_rt = now() - t1;
        int n = 0;
        double rms = 0, rdeg = 0, rmm = 0;
        for (size_t i = 0; i < frig_photoset_count(set); i++) {
            int inl;
            double a, b, c;
            if (frig_photoset_retarget_figures(set, i, &inl, &a, &b, &c) || !isfinite(a)) continue;
            n++, rms += a, rdeg += b, rmm += c;
        }
        snprintf(extra, sizeof extra, "%d photos, fit %.2f s + sfs %.2f s + retarget %.2f s; |w - w_true| %.4f; "
                                      "cloud RMS %.2f mm, rigid %.2f deg %.2f mm",
                 n, t_fit, t_sfs, t_rt, weight_error(set), rms / n, rdeg / n, rmm / n);
        char name[64];
        snprintf(name, sizeof name, "retarget round %d", r + 1);
        row(name, rig_score_rig(truth, rig, nf), extra);
        if (where) where_report(ctx, name + 9, truth, frig_rig_neutral(rig), nf);
    }
    if (rounds > 0) {
        frig_rig *tpl = NULL;
        frig_rig_from_model(ctx, model, NULL, &tpl);
        int S = frig_rig_shape_count(tpl);
        double *lid = malloc(sizeof(double) * (S + 1)), *teeth = malloc(sizeof(double) * (S + 1));
        fr_rt_collisions(ctx, model, frig_rig_neutral(tpl), frig_rig_shape_deltas(tpl, 0), S, lid, teeth);
        collision_row(ctx, model, "template", tpl, NULL, NULL);
        collision_row(ctx, model, "truth", truth, lid, teeth);
        collision_row(ctx, model, "fit (model-space)", fit_rig, lid, teeth);
        collision_row(ctx, model, "retargeted", rig, lid, teeth);
        free(lid), free(teeth);
        frig_rig_free(tpl);
    }
    if (save && frig_rig_save(ctx, rig, save)) fprintf(stderr, "%s\n", frig_ctx_errmsg(ctx));
    if (sheet) {
        const frig_rig *rows[3] = {fit_rig, rig, truth};
        const char *labels[3] = {"fit (model-space)", "retargeted", "truth"};
        if (frig_retarget_write_sheet(ctx, model, rows, labels, 3, sheet)) fprintf(stderr, "%s\n", frig_ctx_errmsg(ctx));
    }
    frig_clouds_free(clouds);
    frig_rig_free(fit_rig);
    frig_rig_free(rig);
    frig_rig_free(truth);
    frig_photoset_free(set);
    frig_model_free(model);
    frig_ctx_free(ctx);
    return 0;
}
