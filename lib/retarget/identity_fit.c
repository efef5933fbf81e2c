/* The identity from the clouds (beyond the paper: its chapter 4 fits the identity to 68
 * landmarks only; here the same linear model is fitted to every photo's dense cloud before the
 * correspondences). Point-to-plane ICP over all photos at once: per photo the cloud is aligned
 * rigidly and matched to the current reconstruction N + D w_i, the photo's expression weights
 * are solved (bounded, in [0, 1]), then one Gauss-Newton step moves the shared identity, N <-
 * N + U delta (U the model's identity modes, over the whole head, so everything the modes move
 * follows), with the model's prior N(c, I) on the identity weights, weighed retarget.identity_prior
 * times, c the identity the fit starts from times retarget.identity_prior_centre (1 by default: the
 * identity the sfs stage drew the clouds at, so that where the clouds cannot say, such as the features'
 * places along the surface, the identity stays where the landmarks and the pixels put it rather than
 * sliding to the mean face's; measured: docs/retarget.md): the matches are weighed as if each
 * were an independent 1 mm measurement, but a cloud's errors (sfs's, the pose's) are smooth and
 * shared by its neighbouring points, so thousands of matches per photo outweigh the prior far more
 * than they should (measured: docs/retarget.md).
 * So each cloud may show an identity of its own, N(0, retarget.identity_spread I) about the shared
 * one (a random effect, eliminated per photo: cap_by_spread): a photo's say on the shared identity
 * is then capped however many matches it has, and the clouds' own errors average out instead of
 * adding up (measured on nine frig synth subjects: docs/retarget.md).
 * Each photo's weights are solved with the identity (eliminated by their Schur complement) under a
 * ridge of retarget.identity_weights_ridge per match: nearly free weights keep whatever shape of
 * the clouds a blendshape can make (a chin longer than the model's read as jawOpen in every photo)
 * away from the shared identity (docs/retarget.md, "The weights' ridge in the identity fit").
 * Why: a point-to-surface deformation (Algorithm 7) can only move the surface along its normal;
 * where the fit from landmarks put the nose or the eyes a few millimetres off, the cloud cannot
 * say so, but the model's identity modes tie those positions to the surface's shape. Measured:
 * docs/retarget.md. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <cblas.h>
#include <omp.h>

#include "core/context.h"
#include "linalg/box_qp.h"
#include "linalg/linalg.h"
#include "model/face_size.h"
#include "model/model.h"
#include "retarget/retarget.h"
#include "rig/rig.h"

#define ROWS_MAX 3000     /* matches used per photo and iteration */
#define LD (ROWS_MAX + 3 * 68) /* rows of a photo's Jacobian: the matches, then its landmarks */
#define SIGMA 1e-3        /* metres: the noise a match is weighed against */
#define RIGID_STEPS 1

/* One photo's part of the joint normal equations of [identity step delta, weights e]:
 *     | A  B | | delta |   | u |
 *     | B' C | |   e   | = | v |,   A = Ji'Ji, B = Ji'Je, C = Je'Je + ridge, u = Ji'b, v = Je'b,
 * b = r + Je e0 (the residual as if the weights were 0). */
typedef struct per_photo {
    double *A, *B, *C, *u, *v;
    int rows, surface;
} per_photo;

/* The basis vertex by vertex: row (3 v + c) holds coordinate c of vertex v of the identity
 * modes, then of the fitting shapes (cols values), so a row of the Jacobian reads three
 * contiguous rows. */
static float *vertex_major_basis(const frig_model *model, const frig_rig *rig, int nf, int n_id, int K,
                                 const int *fit_shape) {
    int cols = n_id + K;
    size_t nv3 = 3 * (size_t)rig->topo.vertex_count;
    float *B = malloc(sizeof(float) * 3 * (size_t)nf * cols);
    if (!B) return NULL;
    for (int k = 0; k < cols; k++) {
        const float *col = k < n_id ? model->identity + nv3 * k : rig->deltas + nv3 * fit_shape[k - n_id];
        for (size_t q = 0; q < 3 * (size_t)nf; q++) B[q * cols + k] = col[q];
    }
    return B;
}

/* The landmark rows: the model's landmark vertex against the photo's lifted landmark (3D, after
 * the cloud's rigid correction), three rows each, from row 'first'. */
static int landmark_rows(const fr_rt_settings *s, const frig_model *model, const float *B, int nf, int n_id,
                         int K, const fr_rt_photo *p, const float *cur, int first, double *J, double *r) {
    if (!(s->landmark_sigma > 0)) return 0;
    int rows = first, cols = n_id + K;
    for (int l = 0; l < 68; l++) {
        int v = model->landmarks[l];
        if (!p->lm_ok[l] || v >= nf) continue;
        for (int c = 0; c < 3; c++) {
            double target = p->t[c];
            for (int d = 0; d < 3; d++) target += p->scale * p->R[3 * c + d] * p->lm3d[3 * l + d];
            r[rows] = (target - cur[3 * (size_t)v + c]) / s->landmark_sigma;
            const float *b = B + (3 * (size_t)v + c) * cols;
            for (int k = 0; k < cols; k++) J[(size_t)k * LD + rows] = b[k] / s->landmark_sigma;
            rows++;
        }
    }
    return rows - first;
}

/* Rows of one photo: J (rows x (n_id + K), column-major, ld = LD) and r; *surface gets the
 * number of match rows (the landmarks' follow). */
static int photo_rows(const fr_rt_settings *s, const frig_model *model, const float *B, const fr_rt_mesh *m,
                      int n_id, int K, fr_rt_photo *p, const float *cur, fr_tri_tree *tree, fr_rt_match *mt,
                      double max_dist, double *J, double *r, int *surface) {
    *surface = 0;
    for (int st = 0; st < (s->rigid_iterations > 0 ? RIGID_STEPS : 0); st++) {
        int n = fr_rt_match_cloud(s, m, tree, cur, p, max_dist, mt);
        if (n < 50) return 0;
        fr_rt_rigid_step(mt, n, s->cloud_scale, p);
    }
    int n = fr_rt_match_cloud(s, m, tree, cur, p, max_dist, mt);
    if (n < 50) return 0;
    int step = (n + ROWS_MAX - 1) / ROWS_MAX, rows = 0, cols = n_id + K;
    for (int c = 0; c < n && rows < ROWS_MAX; c += step, rows++) {
        const fr_rt_match *q = &mt[c];
        const int32_t *v = m->tris + 3 * (size_t)q->tri;
        double res = 0;
        for (int d = 0; d < 3; d++) res += q->n[d] * (q->p[d] - q->q[d]);
        r[rows] = q->row * res / SIGMA;
        double coef[9];
        const float *b[9];
        for (int j = 0; j < 3; j++)
            for (int d = 0; d < 3; d++) {
                coef[3 * j + d] = q->row * q->bary[j] * q->n[d] / SIGMA;
                b[3 * j + d] = B + (3 * (size_t)v[j] + d) * cols;
            }
        for (int k = 0; k < cols; k++) {
            double a = 0;
            for (int e = 0; e < 9; e++) a += coef[e] * b[e][k];
            J[(size_t)k * LD + rows] = a;
        }
    }
    *surface = rows;
    return rows + landmark_rows(s, model, B, m->nv, n_id, K, p, cur, rows, J, r);
}

static void symmetrize(double *M, int n) {
    for (int a = 0; a < n; a++)
        for (int b = a + 1; b < n; b++) M[(size_t)b * n + a] = M[(size_t)a * n + b];
}

/* A cloud's own identity c ~ N(0, spread I) about the shared one (its errors are smooth and
 * common to its points, not independent per match): eliminating c from the photo's reduced system
 * S_i (delta + c) = g_i leaves S_i' = S_i (I + spread S_i)^-1 and g_i' = (I + spread S_i)^-1 g_i,
 * in place. Work: n (2 n + 1) doubles. */
static frig_status cap_by_spread(frig_ctx *ctx, int n, double spread, double *Si, double *gi, double *work) {
    double *M = work, *X = M + (size_t)n * n;
    for (size_t e = 0; e < (size_t)n * n; e++) M[e] = spread * Si[e];
    for (int a = 0; a < n; a++) M[(size_t)a * n + a] += 1.0;
    memcpy(X, Si, sizeof(double) * (size_t)n * n);
    memcpy(X + (size_t)n * n, gi, sizeof(double) * n);
    if (fr_solve_spd(ctx, n, n + 1, M, n, X, n)) return ctx->status;
    memcpy(Si, X, sizeof(double) * (size_t)n * n);
    symmetrize(Si, n); /* (rounding) */
    memcpy(gi, X + (size_t)n * n, sizeof(double) * n);
    return FRIG_OK;
}

/* The identity step photo i's weights see: the shared step delta, plus its cloud's own part
 * c = spread (g_i' - S_i' delta) when the clouds have a spread. */
static void photo_step(double spread, int n, const per_photo *q, const double *delta, double *d) {
    memcpy(d, delta, sizeof(double) * n);
    if (!(spread > 0)) return;
    for (int a = 0; a < n; a++) {
        double r = q->u[a];
        for (int b = 0; b < n; b++) r -= q->A[(size_t)b * n + a] * delta[b];
        d[a] += spread * r;
    }
}

frig_status fr_rt_fit_identity(frig_ctx *ctx, const fr_rt_settings *s, const frig_model *model, frig_rig *rig,
                               const fr_rt_mesh *m, int K, const int *fit_shape, int n, fr_rt_photo *photos,
                               double *identity, int n_id, int iterations) {
    if (n_id <= 0 || iterations <= 0 || n == 0) return FRIG_OK;
    int nf = m->nv, nv = rig->topo.vertex_count, cols = n_id + K, threads = s->threads;
    size_t nf3 = 3 * (size_t)nf, nv3 = 3 * (size_t)nv;
    size_t per_thread = nf3 + (size_t)LD * cols + LD + (size_t)K * (n_id + 1) + (size_t)K * K + 3 * (size_t)K;
    size_t per_photo_size = (size_t)n_id * n_id + (size_t)n_id * K + (size_t)K * K + n_id + K;
    double *work = malloc(sizeof(double) * per_thread * (size_t)threads);
    float *cur = malloc(sizeof(float) * nf3 * (size_t)threads);
    fr_rt_match **mt = calloc((size_t)threads, sizeof *mt);
    fr_tri_tree **trees = calloc((size_t)threads, sizeof *trees);
    per_photo *pp = calloc((size_t)n, sizeof *pp);
    double *store = malloc(sizeof(double) * per_photo_size * (size_t)n);
    double *S = malloc(sizeof(double) * (size_t)n_id * (n_id + 1)), *g = S ? S + (size_t)n_id * n_id : NULL;
    float *B = vertex_major_basis(model, rig, nf, n_id, K, fit_shape);
    double *size_grad = s->mean_size ? malloc(sizeof(double) * (size_t)n_id) : NULL;
    frig_status st = work && cur && mt && pp && store && S && B && (size_grad || !s->mean_size)
                         ? FRIG_OK
                         : fr_nomem(ctx, "the identity fit");
    if (!st && size_grad) st = fr_face_size_gradient(ctx, model, n_id, size_grad);
    double *centre = calloc((size_t)n_id, sizeof(double)); /* the prior's centre */
    if (!centre && !st) st = fr_nomem(ctx, "the identity fit");
    for (int a = 0; a < n_id && centre; a++) centre[a] = s->prior_centre * identity[a];
    int most = 0;
    for (int i = 0; i < n; i++) most = photos[i].n_pick > most ? photos[i].n_pick : most;
    if (!trees && !st) st = fr_nomem(ctx, "the identity fit");
    for (int t = 0; t < threads && !st; t++) {
        if (!(mt[t] = malloc(sizeof(fr_rt_match) * ((size_t)most + 1)))) st = fr_nomem(ctx, "the identity fit");
        if (!st) st = fr_tri_tree_copy(ctx, m->tree, &trees[t]);
    }
    for (int i = 0; i < n && !st; i++) {
        pp[i].A = store + per_photo_size * (size_t)i;
        pp[i].B = pp[i].A + (size_t)n_id * n_id;
        pp[i].C = pp[i].B + (size_t)n_id * K;
        pp[i].u = pp[i].C + (size_t)K * K;
        pp[i].v = pp[i].u + n_id;
    }
    for (int it = 0; it < iterations && !st; it++) {
        /* Wider matches first: the landmark fit can be a centimetre off. */
        double max_dist = s->max_distance * (it == 0 ? 2.0 : 1.0);
        int failed = 0;
        int saved = fr_blas_serial_begin();
        /* Pass 1: each photo's rows and its blocks of the joint system. */
#pragma omp parallel for schedule(dynamic) num_threads(threads)
        for (int i = 0; i < n; i++) {
            if (failed) continue;
            int tid = omp_get_thread_num();
            double *J = work + per_thread * (size_t)tid, *r = J + (size_t)LD * cols;
            float *x = cur + nf3 * (size_t)tid;
            fr_rt_photo *p = &photos[i];
            per_photo *q = &pp[i];
            q->rows = 0;
            fr_rt_blend(nf3, rig->neutral, K, p->w, rig->deltas, nv3, fit_shape, x);
            fr_tri_tree *tree = trees[tid];
            fr_tri_tree_refit(tree, x);
            int surface = 0;
            int rows = p->rejected ? 0 : photo_rows(s, model, B, m, n_id, K, p, x, tree, mt[tid], max_dist, J, r, &surface);
            /* A cloud that needs too large a turn to fit shows something else (a wrong pose). */
            if (rows && fr_rt_correction_angle(p) > s->max_correction) p->rejected = 1, rows = 0;
            if (rows == 0) continue;
            double *Je = J + (size_t)n_id * LD;
            cblas_dgemv(CblasColMajor, CblasNoTrans, rows, K, 1.0, Je, LD, p->w, 1, 1.0, r, 1); /* b */
            cblas_dsyrk(CblasColMajor, CblasLower, CblasTrans, n_id, rows, 1.0, J, LD, 0.0, q->A, n_id);
            cblas_dgemm(CblasColMajor, CblasTrans, CblasNoTrans, n_id, K, rows, 1.0, J, LD, Je, LD, 0.0,
                        q->B, n_id);
            cblas_dsyrk(CblasColMajor, CblasLower, CblasTrans, K, rows, 1.0, Je, LD, 0.0, q->C, K);
            cblas_dgemv(CblasColMajor, CblasTrans, rows, n_id, 1.0, J, LD, r, 1, 0.0, q->u, 1);
            cblas_dgemv(CblasColMajor, CblasTrans, rows, K, 1.0, Je, LD, r, 1, 0.0, q->v, 1);
            symmetrize(q->A, n_id);
            symmetrize(q->C, K);
            for (int a = 0; a < K; a++) q->C[(size_t)a * K + a] += s->weights_ridge * surface;
            q->rows = rows;
            q->surface = surface;
        }
        if (failed) {
            fr_blas_serial_end(saved);
            st = fr_error(ctx, FRIG_ERR_NUMERIC, "the identity fit to the clouds failed");
            break;
        }
        /* The identity step: the Schur complement of the weights, S delta = g, summed in photo order:
         * S = sum (A - B C^-1 B') + I, g = sum (u - B C^-1 v) - identity. */
        memset(S, 0, sizeof(double) * (size_t)n_id * (n_id + 1));
        int used = 0;
        for (int i = 0; i < n && !st; i++) {
            per_photo *q = &pp[i];
            if (!q->rows) continue;
            double *J = work, *Cf = J + (size_t)K * (n_id + 1);
            /* W = C^-1 [B' v]: K x (n_id + 1). */
            memcpy(Cf, q->C, sizeof(double) * (size_t)K * K);
            for (int a = 0; a < n_id; a++)
                for (int b = 0; b < K; b++) J[(size_t)a * K + b] = q->B[(size_t)b * n_id + a];
            memcpy(J + (size_t)n_id * K, q->v, sizeof(double) * K); /* last column: v */
            if (fr_solve_spd(ctx, K, n_id + 1, Cf, K, J, K)) {
                st = ctx->status;
                break;
            }
            if (s->identity_spread > 0) {
                /* S_i = A - B W_B, g_i = u - B W_v in place of A and u, then capped by the cloud's spread */
                cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, n_id, n_id, K, -1.0, q->B, n_id, J, K, 1.0,
                            q->A, n_id);
                cblas_dgemv(CblasColMajor, CblasNoTrans, n_id, K, -1.0, q->B, n_id, J + (size_t)n_id * K, 1, 1.0, q->u,
                            1);
                symmetrize(q->A, n_id);
                if ((st = cap_by_spread(ctx, n_id, s->identity_spread, q->A, q->u, Cf))) break;
            } else {
                /* S += A - B W_B, g += u - B W_v */
                cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, n_id, n_id, K, -1.0, q->B, n_id, J, K, 1.0, S,
                            n_id);
                cblas_dgemv(CblasColMajor, CblasNoTrans, n_id, K, -1.0, q->B, n_id, J + (size_t)n_id * K, 1, 1.0, g, 1);
            }
            for (size_t e = 0; e < (size_t)n_id * n_id; e++) S[e] += q->A[e];
            for (int a = 0; a < n_id; a++) g[a] += q->u[a];
            used++;
        }
        if (st || !used) {
            fr_blas_serial_end(saved);
            break;
        }
        symmetrize(S, n_id); /* (rounding) */
        for (int a = 0; a < n_id; a++) {
            S[(size_t)a * n_id + a] += s->identity_prior;
            g[a] -= s->identity_prior * (identity[a] - centre[a]);
        }
        /* identity += step; with the size held (model/face_size.h), g . (identity + step) = 0 */
        st = size_grad ? fr_solve_size_held(ctx, n_id, S, g, size_grad, -fr_face_size_change(size_grad, identity, n_id))
                       : fr_solve_spd(ctx, n_id, 1, S, n_id, g, n_id);
        if (st) {
            fr_blas_serial_end(saved);
            break;
        }
        /* Pass 2: each photo's weights with the new identity, in [0, 1]: C e = v - B' delta. */
#pragma omp parallel for schedule(dynamic) num_threads(threads)
        for (int i = 0; i < n; i++) {
            per_photo *q = &pp[i];
            if (!q->rows || failed) continue;
            double *ge = work + per_thread * (size_t)omp_get_thread_num(), *lo = ge + K, *hi = lo + K, *d = hi + K;
            photo_step(s->identity_spread, n_id, q, g, d);
            cblas_dgemv(CblasColMajor, CblasTrans, n_id, K, 1.0, q->B, n_id, d, 1, 0.0, ge, 1);
            double l1 = s->weights_sparse * q->surface; /* rows are residuals in units of SIGMA = 1 mm */
            for (int a = 0; a < K; a++) ge[a] += l1 - q->v[a], lo[a] = 0, hi[a] = 1;
            if (fr_box_qp(NULL, K, q->C, ge, lo, hi, photos[i].w)) failed = 1;
        }
        fr_blas_serial_end(saved);
        if (failed) {
            st = fr_error(ctx, FRIG_ERR_NUMERIC, "the expression weights of the identity fit failed");
            break;
        }
        for (int a = 0; a < n_id; a++) identity[a] += g[a];
        for (size_t q = 0; q < nv3; q++) {
            double v = rig->neutral[q];
            for (int a = 0; a < n_id; a++) v += g[a] * model->identity[nv3 * a + q];
            rig->neutral[q] = (float)v;
        }
        fr_log(ctx, FRIG_LOG_DEBUG, "identity from the clouds, step %d: %d photos", it + 1, used);
    }
    for (int t = 0; mt && t < threads; t++) free(mt[t]);
    for (int t = 0; trees && t < threads; t++) fr_tri_tree_free(trees[t]);
    free(trees);
    free(work), free(cur), free(mt), free(pp), free(store), free(S), free(B), free(size_grad), free(centre);
    return st;
}
