/* Algorithm 1 of section 4.2 (failure detection for facial feature points): each round builds the
 * texture and shape models from the low-rank part L of robust PCA (eq. 4.1) of the current inliers,
 * reconstructs every inlier by projection on the PCA basis, and drops the photos whose error
 * e = w_t RMSE(I, I') + w_s sum ||p - p'||^2 exceeds mu + omega sigma; it stops when none is dropped. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "filter/face_reference.h"
#include "filter/failure_detection.h"
#include "filter/procrustes.h"

void fr_filter_options_from_ctx(const frig_ctx *ctx, fr_filter_options *o) {
    o->omega = fr_param(ctx, FRIG_PARAM_FILTER_OMEGA);
    o->w_texture = fr_param(ctx, FRIG_PARAM_FILTER_W_TEXTURE);
    o->w_shape = fr_param(ctx, FRIG_PARAM_FILTER_W_SHAPE);
    o->pca_energy = fr_param(ctx, FRIG_PARAM_FILTER_PCA_ENERGY);
    o->max_rounds = fr_param_int(ctx, FRIG_PARAM_FILTER_MAX_ROUNDS);
    o->robust = 1;
    o->score_all = fr_param_int(ctx, FRIG_PARAM_FILTER_SCORE_ALL);
    o->mirror = fr_param_int(ctx, FRIG_PARAM_FILTER_MIRROR);
    o->statistic = fr_param_int(ctx, FRIG_PARAM_FILTER_ROBUST_STATS) ? FR_FILTER_MEDIAN_MAD : FR_FILTER_MEAN_STD;
    o->peel_min = fr_param_int(ctx, FRIG_PARAM_FILTER_PEEL_MIN_FACES);
    fr_rpca_default_options(&o->rpca);
    /* The errors move by less than the tolerance (measured: 8e-6 at 1e-5, against errors of 0.3 and
     * thresholds that differ at the 1e-2 level); 1e-7 would cost 45% more time for nothing. */
    o->rpca.tol = 1e-5;
}

void fr_filter_model_free(fr_filter_model *m) {
    if (!m) return;
    fr_pca_free(&m->texture);
    fr_pca_free(&m->shape);
}

/* The reference shape at the filter's scale (outer eye corners FR_FILTER_SHAPE_IOD apart): the
 * frame the shapes are aligned to. */
static void filter_gauge(double gauge[FR_FILTER_SHAPE_DIM]) {
    const double *ref = fr_face_reference_shape();
    double iod = hypot(ref[2 * 45] - ref[2 * 36], ref[2 * 45 + 1] - ref[2 * 36 + 1]);
    for (int k = 0; k < FR_FILTER_SHAPE_DIM; k++) gauge[k] = ref[k] * (FR_FILTER_SHAPE_IOD / iod);
}

frig_status fr_filter_align_shapes(frig_ctx *ctx, int count, const double *landmarks, double *aligned,
                                   double *mean) {
    double gauge[FR_FILTER_SHAPE_DIM], own_mean[FR_FILTER_SHAPE_DIM];
    filter_gauge(gauge);
    return fr_procrustes_align(ctx, FR_FACE_POINTS, count, landmarks, gauge, aligned, mean ? mean : own_mean, NULL);
}

/* The k-th smallest of x[0..n-1] (Hoare's selection; x is reordered). */
static double select_kth(double *x, int n, int k) {
    int lo = 0, hi = n - 1;
    while (lo < hi) {
        double pivot = x[lo + (hi - lo) / 2];
        int i = lo, j = hi;
        while (i <= j) {
            while (x[i] < pivot) i++;
            while (x[j] > pivot) j--;
            if (i <= j) {
                double t = x[i];
                x[i++] = x[j];
                x[j--] = t;
            }
        }
        if (k <= j)
            hi = j;
        else if (k >= i)
            lo = i;
        else
            break;
    }
    return x[k];
}

/* Median of x[0..n-1] (n >= 1; x is reordered). */
static double median(double *x, int n) {
    double hi = select_kth(x, n, n / 2);
    if (n % 2) return hi;
    double lo = x[0]; /* after selection, x[0..n/2-1] are <= hi: the largest of them */
    for (int i = 1; i < n / 2; i++) lo = fmax(lo, x[i]);
    return 0.5 * (lo + hi);
}

/* The PCA model of the samples X (dim x n): PCA of L + median, where L is the low-rank part of the
 * robust PCA of X minus its per-row median (centring first leaves robust PCA only the variation to
 * explain; the median is not pulled by the outliers). With opt->robust = 0, plain PCA of X. */
static frig_status build_model(frig_ctx *ctx, int dim, int n, const double *X, const fr_filter_options *opt,
                               fr_pca *out, int *rank) {
    size_t dn = (size_t)dim * n;
    *rank = 0;
    if (!opt->robust) return fr_pca_fit(ctx, dim, n, X, opt->pca_energy, out);
    double *buf = calloc(3 * dn + dim + n, sizeof(double));
    if (!buf) return fr_nomem(ctx, "robust PCA of the filter's data");
    double *C = buf, *L = C + dn, *S = L + dn, *med = S + dn, *row = med + dim;
    for (int i = 0; i < dim; i++) {
        for (int j = 0; j < n; j++) row[j] = X[i + (size_t)j * dim];
        med[i] = median(row, n);
    }
    for (int j = 0; j < n; j++)
        for (int i = 0; i < dim; i++) C[i + (size_t)j * dim] = X[i + (size_t)j * dim] - med[i];
    fr_rpca_info info;
    frig_status st = fr_robust_pca(ctx, dim, n, C, dim, &opt->rpca, L, S, &info);
    if (st == FRIG_OK) {
        *rank = info.rank;
        for (int j = 0; j < n; j++)
            for (int i = 0; i < dim; i++) L[i + (size_t)j * dim] += med[i];
        st = fr_pca_fit(ctx, dim, n, L, opt->pca_energy, out);
    }
    free(buf);
    return st;
}

/* Copy the columns listed in idx of X (dim x ...) into Y (dim x n). */
static void gather(int dim, int n, const int *idx, const double *X, double *Y) {
    for (int j = 0; j < n; j++) memcpy(Y + (size_t)j * dim, X + (size_t)idx[j] * dim, sizeof(double) * dim);
}

/* iBUG's 68 points under a left-right mirror: point i of the mirror image is point mirror_of[i]. */
static const unsigned char mirror_of[FR_FACE_POINTS] = {
    16, 15, 14, 13, 12, 11, 10, 9,  8,  7,  6,  5,  4,  3,  2,  1,  0,  /* jaw */
    26, 25, 24, 23, 22, 21, 20, 19, 18, 17,                             /* brows */
    27, 28, 29, 30, 35, 34, 33, 32, 31,                                 /* nose */
    45, 44, 43, 42, 47, 46, 39, 38, 37, 36, 41, 40,                     /* eyes */
    54, 53, 52, 51, 50, 49, 48, 59, 58, 57, 56, 55,                     /* outer lips */
    64, 63, 62, 61, 60, 67, 66, 65,                                     /* inner lips */
};

/* The mirror image of an aligned shape (x negated, left and right points swapped), aligned again
 * to the gauge (filter_gauge). */
static void mirror_shape(const double *p, const double *gauge, double *out) {
    double T[4];
    for (int i = 0; i < FR_FACE_POINTS; i++) out[2 * i] = -p[2 * mirror_of[i]], out[2 * i + 1] = p[2 * mirror_of[i] + 1];
    fr_similarity_fit(FR_FACE_POINTS, out, gauge, T);
    fr_similarity_apply(FR_FACE_POINTS, T, out, out);
}

/* Build the models of the photos listed in idx. With opt->mirror the shape model learns from the n
 * shapes and their n mirror images (a face turned 40 degrees one way is nearly the mirror image of
 * one turned 40 degrees the other way, so a set with few photos turned one way no longer finds them
 * unlike the rest); the photos are still scored one by one against it. */
static frig_status build_models(frig_ctx *ctx, int n, const int *idx, int texels, const double *textures,
                                const double *shapes, const fr_filter_options *opt, fr_filter_model *model,
                                int ranks[2]) {
    memset(model, 0, sizeof *model);
    model->w_texture = opt->w_texture;
    model->w_shape = opt->w_shape;
    ranks[0] = ranks[1] = 0;
    int dim = textures && texels > FR_FILTER_SHAPE_DIM ? texels : FR_FILTER_SHAPE_DIM;
    size_t shape_columns = (size_t)(opt->mirror ? 2 : 1) * n;
    double *Y = calloc((size_t)dim * n > FR_FILTER_SHAPE_DIM * shape_columns ? (size_t)dim * n
                                                                            : FR_FILTER_SHAPE_DIM * shape_columns,
                       sizeof(double));
    if (!Y) return fr_nomem(ctx, "the filter's data matrix");
    frig_status st = FRIG_OK;
    if (textures) {
        gather(texels, n, idx, textures, Y);
        st = build_model(ctx, texels, n, Y, opt, &model->texture, &ranks[0]);
    }
    if (st == FRIG_OK && shapes) {
        gather(FR_FILTER_SHAPE_DIM, n, idx, shapes, Y);
        double gauge[FR_FILTER_SHAPE_DIM];
        filter_gauge(gauge);
        for (int j = 0; opt->mirror && j < n; j++)
            mirror_shape(Y + (size_t)j * FR_FILTER_SHAPE_DIM, gauge, Y + (size_t)(n + j) * FR_FILTER_SHAPE_DIM);
        st = build_model(ctx, FR_FILTER_SHAPE_DIM, (int)shape_columns, Y, opt, &model->shape, &ranks[1]);
    }
    free(Y);
    if (st != FRIG_OK) fr_filter_model_free(model);
    return st;
}

/* Errors of the n listed photos under the model. */
static frig_status score_listed(frig_ctx *ctx, const fr_filter_model *model, int n, const int *idx, int texels,
                                const double *textures, const double *shapes, fr_filter_result *res) {
    int dim = textures && texels > FR_FILTER_SHAPE_DIM ? texels : FR_FILTER_SHAPE_DIM;
    double *Y = calloc((size_t)dim * n + n, sizeof(double));
    if (!Y) return fr_nomem(ctx, "the filter's reconstructions");
    double *r2 = Y + (size_t)dim * n;
    frig_status st = FRIG_OK;
    for (int j = 0; j < n; j++) res[j].texture_error = res[j].shape_error = 0;
    if (textures && model->texture.dim == texels) {
        gather(texels, n, idx, textures, Y);
        st = fr_pca_reconstruct(ctx, &model->texture, n, Y, r2, NULL);
        for (int j = 0; j < n && st == FRIG_OK; j++) res[j].texture_error = sqrt(r2[j] / texels);
    }
    if (st == FRIG_OK && shapes && model->shape.dim == FR_FILTER_SHAPE_DIM) {
        gather(FR_FILTER_SHAPE_DIM, n, idx, shapes, Y);
        st = fr_pca_reconstruct(ctx, &model->shape, n, Y, r2, NULL);
        for (int j = 0; j < n && st == FRIG_OK; j++) res[j].shape_error = r2[j];
    }
    for (int j = 0; j < n; j++) {
        res[j].error = model->w_texture * res[j].texture_error + model->w_shape * res[j].shape_error;
        res[j].round_dropped = 0;
    }
    free(Y);
    return st;
}

frig_status fr_filter_score(frig_ctx *ctx, const fr_filter_model *model, int count, const double *textures,
                            const double *shapes, fr_filter_result *results) {
    int *idx = malloc(sizeof(int) * (size_t)(count > 0 ? count : 1));
    if (!idx) return fr_nomem(ctx, "face indices");
    for (int i = 0; i < count; i++) idx[i] = i;
    frig_status st = score_listed(ctx, model, count, idx, model->texture.dim, textures, shapes, results);
    free(idx);
    return st;
}

/* Centre and spread of the n errors. */
static void error_statistics(int n, const fr_filter_result *res, fr_filter_statistic statistic, double *mu,
                             double *sigma) {
    double *e = malloc(sizeof(double) * (size_t)n);
    if (statistic == FR_FILTER_MEDIAN_MAD && e) {
        for (int j = 0; j < n; j++) e[j] = res[j].error;
        double med = median(e, n);
        for (int j = 0; j < n; j++) e[j] = fabs(res[j].error - med);
        *mu = med;
        *sigma = 1.4826 * median(e, n);
    } else {
        double m = 0, v = 0;
        for (int j = 0; j < n; j++) m += res[j].error;
        m /= n;
        for (int j = 0; j < n; j++) v += (res[j].error - m) * (res[j].error - m);
        *mu = m;
        *sigma = sqrt(v / n);
    }
    free(e);
}

static void log_round(frig_ctx *ctx, int round, int n, const fr_filter_result *res, double mu, double sigma,
                      int dropped) {
    double mt = 0, ms = 0;
    for (int j = 0; j < n; j++) mt += res[j].texture_error / n, ms += res[j].shape_error / n;
    fr_log(ctx, FRIG_LOG_INFO,
           "filter round %d: %d faces scored, mean errors %.4g (texture) %.4g (shape), e centre %.4g spread %.4g, "
           "above the limit %d",
           round, n, mt, ms, mu, sigma, dropped);
}

/* Algorithm 1 as printed: the model scores the current inliers (idx[0..*n-1]), and those above
 * the limit of their own errors leave. Returns whether any left. */
static int judge_inliers(frig_ctx *ctx, const fr_filter_model *m, int texels, const double *textures,
                         const double *shapes, const fr_filter_options *opt, int round, int *idx, int *n,
                         fr_filter_result *res, fr_filter_result *results, frig_status *st) {
    if ((*st = score_listed(ctx, m, *n, idx, texels, textures, shapes, res)) != FRIG_OK) return 0;
    double mu, sigma;
    error_statistics(*n, res, opt->statistic, &mu, &sigma);
    double limit = mu + opt->omega * sigma;
    int kept = 0;
    for (int j = 0; j < *n; j++) {
        results[idx[j]] = res[j];
        if (res[j].error > limit)
            results[idx[j]].round_dropped = round;
        else
            idx[kept++] = idx[j];
    }
    log_round(ctx, round, *n, res, mu, sigma, *n - kept);
    int changed = kept != *n;
    *n = kept;
    return changed;
}

/* filter.score_all: the model of the current inliers scores all count photos; centre and spread
 * are those of all the errors, so the sample behind the limit does not shrink round after round,
 * and a photo the refined model explains comes back. Returns whether the inlier set changed. */
static int judge_all(frig_ctx *ctx, const fr_filter_model *m, int count, int texels, const double *textures,
                     const double *shapes, const fr_filter_options *opt, int round, int *idx, int *n,
                     fr_filter_result *res, fr_filter_result *results, frig_status *st) {
    int *all = malloc(sizeof(int) * (size_t)count);
    if (!all) {
        *st = fr_nomem(ctx, "failure detection");
        return 0;
    }
    for (int i = 0; i < count; i++) all[i] = i;
    *st = score_listed(ctx, m, count, all, texels, textures, shapes, res);
    free(all);
    if (*st != FRIG_OK) return 0;
    double mu, sigma;
    error_statistics(count, res, opt->statistic, &mu, &sigma);
    double limit = mu + opt->omega * sigma;
    int kept = 0, changed = 0;
    for (int i = 0; i < count; i++) {
        int dropped_before = results[i].round_dropped;
        results[i] = res[i];
        int out = res[i].error > limit;
        results[i].round_dropped = out ? (dropped_before ? dropped_before : round) : 0;
        changed |= out != (dropped_before != 0);
        if (!out) idx[kept++] = i;
    }
    log_round(ctx, round, count, res, mu, sigma, count - kept);
    *n = kept;
    return changed;
}

frig_status fr_failure_detection(frig_ctx *ctx, int count, int texels, const double *textures, const double *shapes,
                                 const fr_filter_options *opt, fr_filter_result *results, int *rounds,
                                 fr_filter_model *model) {
    if (rounds) *rounds = 0;
    if (model) memset(model, 0, sizeof *model);
    if (count < 3)
        return fr_error(ctx, FRIG_ERR_TOO_FEW, "failure detection needs at least 3 faces, not %d", count);
    if (!textures && !shapes) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "failure detection: no data");
    if (textures && texels < 1) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "textures of %d texels", texels);
    if (!(opt->omega > 0) || opt->max_rounds < 1 || !(opt->pca_energy > 0 && opt->pca_energy <= 1))
        return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "failure detection: omega %g, max_rounds %d, energy %g",
                        opt->omega, opt->max_rounds, opt->pca_energy);
    int *idx = malloc(sizeof(int) * (size_t)count);
    fr_filter_result *res = malloc(sizeof *res * (size_t)count);
    if (!idx || !res) {
        free(idx);
        free(res);
        return fr_nomem(ctx, "failure detection");
    }
    /* One BLAS thread: on these thin matrices (one side is the photo count) it is as fast as two
     * idle cores and much faster on busy ones (measured), and threaded OpenBLAS gemm/dsyevd do not
     * give the same bits for different thread counts; serial makes the result independent of them. */
    int blas_threads = fr_blas_serial_begin();
    for (int i = 0; i < count; i++) {
        idx[i] = i;
        memset(&results[i], 0, sizeof results[i]);
    }
    int n = count, round = 0;
    frig_status st = FRIG_OK;
    fr_filter_model m;
    memset(&m, 0, sizeof m);
    int settled = 0; /* the last round changed nothing: m is the model of the final inliers */
    /* Later rounds judge the inliers by a model of fewer photos. Below a dozen that model explains
     * too little of a set's ordinary variety (1-3 components), and its rounds dropped 4-36 good
     * photos for each failure they found (docs/filter.md, "Small sets"). Every round needs 3. */
    int later_min = opt->peel_min > 3 ? opt->peel_min : 3;
    while (round < opt->max_rounds && n >= (round == 0 ? 3 : later_min)) {
        round++;
        int ranks[2];
        if ((st = build_models(ctx, n, idx, texels, textures, shapes, opt, &m, ranks)) != FRIG_OK) break;
        int changed = opt->score_all ? judge_all(ctx, &m, count, texels, textures, shapes, opt, round, idx, &n, res,
                                                 results, &st)
                                     : judge_inliers(ctx, &m, texels, textures, shapes, opt, round, idx, &n, res,
                                                     results, &st);
        if (st != FRIG_OK) break;
        fr_log(ctx, FRIG_LOG_INFO, "filter round %d: robust PCA ranks %d (texture) %d (shape), PCA components %d "
               "(texture) %d (shape); %d inliers", round, ranks[0], ranks[1], m.texture.k, m.shape.k, n);
        fr_progress(ctx, "filter", (size_t)round, (size_t)opt->max_rounds);
        if (!changed) {
            settled = 1;
            break;
        }
        fr_filter_model_free(&m);
        if ((st = fr_check_cancel(ctx, "failure detection")) != FRIG_OK) break;
    }
    if (st == FRIG_OK && model) {
        int ranks[2];
        if (settled) {
            *model = m;
            memset(&m, 0, sizeof m);
        } else {
            st = build_models(ctx, n, idx, texels, textures, shapes, opt, model, ranks);
        }
    }
    fr_filter_model_free(&m);
    fr_blas_serial_end(blas_threads);
    if (st == FRIG_OK && rounds) *rounds = round;
    free(idx);
    free(res);
    return st;
}

frig_status fr_filter_choose_face(frig_ctx *ctx, const fr_filter_model *model, const fr_face_warp *warp,
                                  const frig_image *image, int faces, const double *landmarks, int *best,
                                  fr_filter_result *scores) {
    *best = -1;
    int texels = model->texture.dim;
    if (texels > 0 && (!warp || fr_face_warp_texels(warp) != texels))
        return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "choose face: the warp does not match the texture model");
    double *tex = malloc(sizeof(double) * ((size_t)(texels > 0 ? texels : 1) + FR_FILTER_SHAPE_DIM));
    if (!tex) return fr_nomem(ctx, "a face texture");
    double *shape = tex + (texels > 0 ? texels : 1), best_e = INFINITY;
    frig_status st = FRIG_OK;
    for (int f = 0; f < faces && st == FRIG_OK; f++) {
        const double *lm = landmarks + (size_t)f * FR_FILTER_SHAPE_DIM;
        fr_filter_result r = {INFINITY, INFINITY, INFINITY, 0};
        int usable = 1;
        if (texels > 0) {
            st = fr_face_warp_sample(ctx, warp, image, lm, tex, NULL);
            usable = st == FRIG_OK && fr_texture_normalize(texels, tex);
        }
        if (st == FRIG_OK && usable && model->shape.dim == FR_FILTER_SHAPE_DIM) {
            double T[4];
            fr_similarity_fit(FR_FACE_POINTS, lm, model->shape.mean, T);
            fr_similarity_apply(FR_FACE_POINTS, T, lm, shape);
        }
        if (st == FRIG_OK && usable)
            st = fr_filter_score(ctx, model, 1, texels > 0 ? tex : NULL,
                                 model->shape.dim == FR_FILTER_SHAPE_DIM ? shape : NULL, &r);
        if (scores) scores[f] = r;
        if (st == FRIG_OK && usable && r.error < best_e) {
            best_e = r.error;
            *best = f;
        }
    }
    free(tex);
    return st;
}
