/* Progressive reconstruction (paper section 4.3.4, Algorithm 2): individual fits, ranking by
 * identity fitness and photo-consistency (section 4.4, eq. 4.10-4.11), a joint identity fit
 * (eq. 4.9) on the best 0.4, 0.6, 0.8 of the photos, repeated with the joint identity as the
 * next round's prior; finally every photo fitted with the identity fixed. The joint fit
 * alternates per-photo pose/expression fits with Gauss-Newton steps on the shared identity,
 * as the author's implementation does. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cblas.h>
#include <omp.h>

#include "core/context.h"
#include "model/face_size.h"
#include "fit/photo_consistency.h"
#include "fit/progressive_fit.h"
#include "linalg/linalg.h"

void fr_fit_settings_from_ctx(const frig_ctx *ctx, fr_fit_settings *s) {
    memset(s, 0, sizeof *s);
    s->perspective = fr_param_int(ctx, FRIG_PARAM_FIT_PERSPECTIVE);
    s->rounds = fr_param_int(ctx, FRIG_PARAM_FIT_ROUNDS);
    s->subset_first = fr_param(ctx, FRIG_PARAM_FIT_SUBSET_FIRST);
    s->subset_step = fr_param(ctx, FRIG_PARAM_FIT_SUBSET_STEP);
    s->score_w_id = fr_param(ctx, FRIG_PARAM_FIT_SCORE_W_ID);
    s->score_w_tex = fr_param(ctx, FRIG_PARAM_FIT_SCORE_W_TEX);
    s->start.id = fr_param(ctx, FRIG_PARAM_FIT_W_ID);
    s->start.exp = fr_param(ctx, FRIG_PARAM_FIT_W_EXP);
    s->start.sparse = fr_param(ctx, FRIG_PARAM_FIT_W_SPARSE);
    s->start.focal = fr_param(ctx, FRIG_PARAM_FIT_W_FOCAL);
    /* "Their values decrease gradually in the optimization process": to a half. */
    s->end.id = s->start.id / 2;
    s->end.exp = s->start.exp / 2;
    s->end.sparse = s->start.sparse / 2;
    s->end.focal = s->start.focal;
    s->joint_w_id = s->start.id;
    s->joint_prior = fr_param(ctx, FRIG_PARAM_FIT_JOINT_PRIOR);
    s->contour_weight = fr_param(ctx, FRIG_PARAM_FIT_CONTOUR_WEIGHT);
    s->mean_size = fr_param_int(ctx, FRIG_PARAM_FIT_MEAN_SIZE);
    s->iterations = fr_param_int(ctx, FRIG_PARAM_FIT_ITERATIONS);
    s->joint_sweeps = 4;
    s->threads = fr_threads(ctx);
}

typedef struct run {
    frig_ctx *ctx;
    const fr_fit_model *fm;
    const fr_fit_settings *s;
    int n;
    const fr_fit_input *in;
    fr_fit_photo *ph;
    double *w;           /* n x n_cols working weights */
    atomic_size_t done;
} run;

static fr_fit_weights avoid_zero(fr_fit_weights w) {
    /* pow() in the schedule needs positive weights. */
    if (w.id <= 0) w.id = 1e-12;
    if (w.exp <= 0) w.exp = 1e-12;
    if (w.sparse <= 0) w.sparse = 1e-12;
    return w;
}

void fr_fit_options_make(const fr_fit_settings *s, int fit_identity, const double *id_prior, fr_fit_weights start,
                         fr_fit_weights end, int iterations, fr_fit_options *opt) {
    memset(opt, 0, sizeof *opt);
    opt->fit_identity = fit_identity;
    opt->fit_expression = 1;
    opt->fit_focal = s->perspective;
    opt->id_prior = id_prior;
    opt->start = avoid_zero(start);
    opt->end = avoid_zero(end);
    opt->iterations = iterations;
    opt->contour_every = 5;
}

/* Individual fits of the photos in 'which' (all when NULL), each starting from id_init with
 * prior id_prior; fit_identity 0 keeps the identity fixed at id_init. */
static frig_status fit_photos(run *r, const int *which, int count, const double *id_init, const double *id_prior,
                              int fit_identity, int iterations, fr_fit_weights start, fr_fit_weights end,
                              int reinit, const char *stage) {
    const fr_fit_model *fm = r->fm;
    fr_fit_options opt;
    fr_fit_options_make(r->s, fit_identity, id_prior, start, end, iterations, &opt);
    atomic_store(&r->done, 0);
    int err = 0;
    int saved = fr_blas_serial_begin();
#pragma omp parallel for schedule(dynamic) num_threads(r->s->threads)
    for (int a = 0; a < count; a++) {
        if (err || fr_cancelled(r->ctx)) continue;
        int i = which ? which[a] : a;
        fr_fit_photo *p = &r->ph[i];
        if (id_init) memcpy(p->w, id_init, sizeof(double) * (size_t)fm->n_id);
        if (reinit) {
            memset(p->w + fm->n_id, 0, sizeof(double) * (size_t)fm->n_exp);
            fr_fit_photo_init(fm, p, r->in[i].landmarks, r->in[i].width, r->in[i].height, r->s->perspective, p->w);
            fr_fit_photo_set_contour_weight(p, r->s->contour_weight);
        }
        if (fr_fit_photo_run(r->ctx, fm, p, &opt) != FRIG_OK) err = 1;
        fr_progress_tick(r->ctx, &r->done, stage, (size_t)count);
    }
    fr_blas_serial_end(saved);
    if (err) return fr_nomem(r->ctx, "photo fits");
    return fr_check_cancel(r->ctx, stage);
}

/* One Gauss-Newton step on the shared identity, poses and expressions fixed (eq. 4.9):
 * H = sum_k J_k^T J_k + w3 I, g = sum_k J_k^T r_k + w3 (w - prior). Per-photo products in
 * parallel, summed in photo order (deterministic). */
static frig_status identity_step(run *r, const int *which, int count, double *identity, const double *prior,
                                 double w3) {
    const fr_fit_model *fm = r->fm;
    int ni = fm->n_id, nr = 2 * FR_LANDMARKS;
    if (ni == 0) return FRIG_OK;
    double *HH = malloc(sizeof(double) * (size_t)count * ((size_t)ni * ni + ni));
    double *J = malloc(sizeof(double) * (size_t)r->s->threads * ((size_t)nr * ni + nr));
    double *H = malloc(sizeof(double) * ((size_t)ni * ni + ni));
    if (!HH || !J || !H) {
        free(HH), free(J), free(H);
        return fr_nomem(r->ctx, "the joint identity fit");
    }
    int saved = fr_blas_serial_begin();
#pragma omp parallel for schedule(static) num_threads(r->s->threads)
    for (int a = 0; a < count; a++) {
        int tid = omp_get_thread_num();
        double *Jt = J + (size_t)tid * ((size_t)nr * ni + nr), *rt = Jt + (size_t)nr * ni;
        fr_fit_photo *p = &r->ph[which[a]];
        memcpy(p->w, identity, sizeof(double) * (size_t)ni);
        fr_fit_photo_identity_jacobian(fm, p, Jt, rt);
        double *Ha = HH + (size_t)a * ((size_t)ni * ni + ni), *ga = Ha + (size_t)ni * ni;
        cblas_dsyrk(CblasColMajor, CblasLower, CblasTrans, ni, nr, 1.0, Jt, nr, 0.0, Ha, ni);
        cblas_dgemv(CblasColMajor, CblasTrans, nr, ni, 1.0, Jt, nr, rt, 1, 0.0, ga, 1);
    }
    fr_blas_serial_end(saved);
    double *g = H + (size_t)ni * ni;
    memset(H, 0, sizeof(double) * ((size_t)ni * ni + ni));
    for (int a = 0; a < count; a++) {
        const double *Ha = HH + (size_t)a * ((size_t)ni * ni + ni);
        for (size_t e = 0; e < (size_t)ni * ni + ni; e++) H[e] += Ha[e];
    }
    for (int i = 0; i < ni; i++) {
        H[i + (size_t)ni * i] += w3;
        g[i] += w3 * (identity[i] - (prior ? prior[i] : 0));
    }
    /* identity -= step; with the size held, g . (identity - step) = 0 */
    frig_status st = r->s->mean_size && fm->size_gradient
                         ? fr_solve_size_held(r->ctx, ni, H, g, fm->size_gradient,
                                              fr_face_size_change(fm->size_gradient, identity, ni))
                         : fr_solve_spd(r->ctx, ni, 1, H, ni, g, ni);
    if (!st)
        for (int i = 0; i < ni; i++) identity[i] -= g[i];
    free(HH), free(J), free(H);
    return st;
}

/* Joint reconstruction on a subset (eq. 4.9): alternate pose/expression fits (identity
 * fixed) with identity steps. */
static frig_status joint_fit(run *r, const int *which, int count, double *identity, const double *prior,
                             const char *stage) {
    const fr_fit_settings *s = r->s;
    frig_status st = FRIG_OK;
    for (int sweep = 0; sweep < s->joint_sweeps && !st; sweep++) {
        st = fit_photos(r, which, count, identity, NULL, 0, s->iterations / 3 + 1, s->end, s->end, 0, stage);
        /* The identity prior grows with the subset, as in the author's implementation
         * (weight x |K|): otherwise the shared identity absorbs what all photos' landmarks
         * have in common but the model cannot explain (measured on synthetic subjects:
         * 3.90 mm with a fixed weight, 2.75 mm scaled). */
        double w3 = s->joint_w_id * count;
        for (int gn = 0; gn < 2 && !st; gn++) st = identity_step(r, which, count, identity, prior, w3);
    }
    return st;
}

/* Identity fitness (eq. 4.10): F = (w_i - mean)^T Sigma (w_i - mean), Sigma the covariance of
 * the current identity estimates. */
static void identity_fitness(const run *r, double *F) {
    int n = r->n, ni = r->fm->n_id, nc = r->fm->n_cols;
    double *mean = calloc((size_t)ni + 1, sizeof(double));
    double *D = malloc(sizeof(double) * (size_t)n * (ni + 1));
    double *SD = malloc(sizeof(double) * (size_t)n * (ni + 1));
    if (!mean || !D || !SD || ni == 0 || n < 2) {
        for (int i = 0; i < n; i++) F[i] = 0;
        free(mean), free(D), free(SD);
        return;
    }
    for (int i = 0; i < n; i++)
        for (int k = 0; k < ni; k++) mean[k] += r->w[(size_t)i * nc + k] / n;
    for (int i = 0; i < n; i++)
        for (int k = 0; k < ni; k++) D[(size_t)i * ni + k] = r->w[(size_t)i * nc + k] - mean[k];
    /* Sigma = D^T D / (n - 1); F_i = d_i^T Sigma d_i = |D d_i|^2 / (n - 1). */
    cblas_dgemm(CblasRowMajor, CblasNoTrans, CblasTrans, n, n, ni, 1.0, D, ni, D, ni, 0.0, SD, n);
    for (int i = 0; i < n; i++) {
        double f = 0;
        for (int j = 0; j < n; j++) f += SD[(size_t)j * n + i] * SD[(size_t)j * n + i];
        F[i] = f / (n - 1);
    }
    free(mean), free(D), free(SD);
}

/* Rank by score (eq. 4.11), ties by index, and keep the best k in photo order. */
static void select_subset(int n, const double *score, int k, int *which) {
    for (int i = 0; i < n; i++) which[i] = i;
    for (int i = 1; i < n; i++) /* insertion sort: stable, deterministic, n is small */
        for (int j = i; j > 0 && score[which[j]] < score[which[j - 1]]; j--) {
            int t = which[j];
            which[j] = which[j - 1];
            which[j - 1] = t;
        }
    for (int i = 1; i < k; i++)
        for (int j = i; j > 0 && which[j] < which[j - 1]; j--) {
            int t = which[j];
            which[j] = which[j - 1];
            which[j - 1] = t;
        }
}

static void mean_identity(const run *r, const int *which, int count, double *out) {
    int ni = r->fm->n_id, nc = r->fm->n_cols;
    memset(out, 0, sizeof(double) * (size_t)ni);
    for (int a = 0; a < count; a++)
        for (int k = 0; k < ni; k++) out[k] += r->w[(size_t)(which ? which[a] : a) * nc + k] / count;
}

static void collect(const run *r, fr_fit_result *res, const int *in_joint, const double *score) {
    int nc = r->fm->n_cols;
    for (int i = 0; i < r->n; i++) {
        const fr_fit_photo *p = &r->ph[i];
        memcpy(res[i].R, p->R, sizeof p->R);
        memcpy(res[i].t, p->t, sizeof p->t);
        res[i].f = p->f;
        res[i].perspective = p->perspective;
        memcpy(res[i].w, r->w + (size_t)i * nc, sizeof(double) * (size_t)nc);
        res[i].rms_px = p->rms_px;
        res[i].in_joint = in_joint ? in_joint[i] : 0;
        res[i].score = score ? score[i] : 0;
    }
}

static frig_status progressive(run *r, fr_fit_result *res, double *identity) {
    const fr_fit_settings *s = r->s;
    const fr_fit_model *fm = r->fm;
    int n = r->n, ni = fm->n_id;
    double *score = calloc((size_t)n, sizeof(double) * 3);
    int *which = malloc(sizeof(int) * (size_t)n), *in_joint = calloc((size_t)n, sizeof(int));
    double *prior = calloc((size_t)ni + 1, sizeof(double));
    if (!score || !which || !in_joint || !prior) {
        free(score), free(which), free(in_joint), free(prior);
        return fr_nomem(r->ctx, "the progressive fit");
    }
    double *f_id = score + n, *f_tex = f_id + n;
    memset(identity, 0, sizeof(double) * (size_t)ni);
    frig_status st = FRIG_OK;
    char stage[64];
    for (int round = 0; round < s->rounds && !st; round++) {
        /* Individual fits from the current identity (the mean face at first); its value is
         * also the prior of later rounds (section 4.3.2). */
        snprintf(stage, sizeof stage, "fit.individual.%d", round + 1);
        /* Later rounds start from the previous round's poses and expressions (warm). */
        st = fit_photos(r, NULL, n, identity, round ? identity : NULL, 1, round ? s->iterations / 2 + 1 : s->iterations,
                        s->start, s->end, round == 0, stage);
        if (st) break;
        identity_fitness(r, f_id);
        st = fr_photo_consistency(r->ctx, fm, n, r->in, r->ph, s->threads, f_tex);
        if (st) break;
        for (int i = 0; i < n; i++) score[i] = s->score_w_id * f_id[i] + s->score_w_tex * f_tex[i];
        double frac = s->subset_first + s->subset_step * round;
        int k = (int)lround(frac * n);
        k = k < 1 ? 1 : k > n ? n : k;
        select_subset(n, score, k, which);
        memset(in_joint, 0, sizeof(int) * (size_t)n);
        for (int a = 0; a < k; a++) in_joint[which[a]] = 1;
        /* Joint fit from the subset's centroid, which is also its prior (section 4.3.3). */
        mean_identity(r, which, k, identity);
        /* The joint prior (section 4.3.3: the subset's centroid; fit.joint_prior scales it
         * toward the model mean, which the author's code uses). */
        for (int q = 0; q < ni; q++) prior[q] = s->joint_prior * identity[q];
        snprintf(stage, sizeof stage, "fit.joint.%d", round + 1);
        st = joint_fit(r, which, k, identity, prior, stage);
        fr_log(r->ctx, FRIG_LOG_INFO, "fit round %d: joint identity on %d of %d photos", round + 1, k, n);
    }
    /* Final fits of every photo with the identity fixed (Algorithm 2, lines 10-12). */
    if (!st) st = fit_photos(r, NULL, n, identity, NULL, 0, s->iterations, s->end, s->end, 0, "fit.final");
    if (!st) collect(r, res, in_joint, score);
    free(score), free(which), free(in_joint), free(prior);
    return st;
}

static frig_status naive_joint(run *r, fr_fit_result *res, double *identity) {
    const fr_fit_settings *s = r->s;
    int n = r->n;
    memset(identity, 0, sizeof(double) * (size_t)r->fm->n_id);
    /* Poses and expressions of the mean face, then the joint alternation on all photos. */
    frig_status st = fit_photos(r, NULL, n, identity, NULL, 0, s->iterations, s->start, s->end, 1, "fit.naive");
    int *all = malloc(sizeof(int) * (size_t)n);
    if (!all) return fr_nomem(r->ctx, "the naive fit");
    for (int i = 0; i < n; i++) all[i] = i;
    if (!st) st = joint_fit(r, all, n, identity, NULL, "fit.naive.joint");
    if (!st) st = fit_photos(r, NULL, n, identity, NULL, 0, s->iterations, s->end, s->end, 0, "fit.final");
    if (!st) {
        int *in = malloc(sizeof(int) * (size_t)n);
        for (int i = 0; in && i < n; i++) in[i] = 1;
        collect(r, res, in, NULL);
        free(in);
    }
    free(all);
    return st;
}

static frig_status individual_only(run *r, fr_fit_result *res, double *identity) {
    const fr_fit_settings *s = r->s;
    memset(identity, 0, sizeof(double) * (size_t)r->fm->n_id);
    frig_status st = fit_photos(r, NULL, r->n, identity, NULL, 1, s->iterations, s->start, s->end, 1, "fit.individual");
    if (st) return st;
    mean_identity(r, NULL, r->n, identity);
    collect(r, res, NULL, NULL);
    return FRIG_OK;
}

frig_status fr_fit_run(frig_ctx *ctx, const fr_fit_model *fm, const fr_fit_settings *s, fr_fit_scheme scheme, int n,
                       const fr_fit_input *in, fr_fit_result *results, double *identity) {
    if (n < 1) return fr_error(ctx, FRIG_ERR_TOO_FEW, "no photo to fit");
    run r = {ctx, fm, s, n, in, NULL, NULL, 0};
    r.ph = calloc((size_t)n, sizeof *r.ph);
    r.w = calloc((size_t)n * (size_t)fm->n_cols, sizeof(double));
    if (!r.ph || !r.w) {
        free(r.ph), free(r.w);
        return fr_nomem(ctx, "photo fits");
    }
    for (int i = 0; i < n; i++) {
        r.ph[i].w = r.w + (size_t)i * fm->n_cols;
        fr_fit_photo_init(fm, &r.ph[i], in[i].landmarks, in[i].width, in[i].height, s->perspective, r.ph[i].w);
        fr_fit_photo_set_contour_weight(&r.ph[i], s->contour_weight);
    }
    /* The fit's linear algebra is small: OpenBLAS threads would only spin (docs/api.md). */
    int saved = fr_blas_serial_begin();
    frig_status st = scheme == FR_SCHEME_INDIVIDUAL  ? individual_only(&r, results, identity)
                     : scheme == FR_SCHEME_NAIVE_JOINT ? naive_joint(&r, results, identity)
                                                       : progressive(&r, results, identity);
    fr_blas_serial_end(saved);
    free(r.ph);
    free(r.w);
    return st;
}
