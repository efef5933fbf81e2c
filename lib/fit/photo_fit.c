/* One photo's fit (paper section 4.3.2, eq. 4.4-4.8): Levenberg-Marquardt on the landmark
 * reprojection error (eq. 4.5) with the identity and expression priors (eq. 4.6) and the
 * L1 sparsity of the expression weights in [0, 1] (eq. 4.7); each step a bound-constrained
 * QP. The prior weights start at w1 = 10, w2 = 5, w3 = 10 and decrease (section 4.3.2).
 * The jaw landmarks' vertices are re-picked on the silhouette as the pose changes. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <cblas.h>

#include "core/context.h"
#include "fit/photo_fit.h"
#include "linalg/box_qp.h"
#include "raster/camera.h"

#define POSE_PARAMS 7 /* rotation (3), translation (3), log focal (1) */
#define MIN_DEPTH 1e-4

static void orthonormalize(double R[9]) {
    /* Gram-Schmidt on rows 0 and 1, row 2 = row0 x row1. */
    double *r0 = R, *r1 = R + 3, *r2 = R + 6;
    double n0 = sqrt(r0[0] * r0[0] + r0[1] * r0[1] + r0[2] * r0[2]);
    for (int i = 0; i < 3; i++) r0[i] /= n0;
    double d = r0[0] * r1[0] + r0[1] * r1[1] + r0[2] * r1[2];
    for (int i = 0; i < 3; i++) r1[i] -= d * r0[i];
    double n1 = sqrt(r1[0] * r1[0] + r1[1] * r1[1] + r1[2] * r1[2]);
    for (int i = 0; i < 3; i++) r1[i] /= n1;
    r2[0] = r0[1] * r1[2] - r0[2] * r1[1];
    r2[1] = r0[2] * r1[0] - r0[0] * r1[2];
    r2[2] = r0[0] * r1[1] - r0[1] * r1[0];
}

/* ---- projection ---- */

static void to_camera(const fr_fit_photo *p, const double X[3], double Xr[3], double Xc[3]) {
    for (int i = 0; i < 3; i++) {
        Xr[i] = p->R[3 * i] * X[0] + p->R[3 * i + 1] * X[1] + p->R[3 * i + 2] * X[2];
        Xc[i] = Xr[i] + p->t[i];
    }
}

static fr_camera camera_of(const fr_fit_photo *p) {
    return p->perspective ? fr_camera_perspective(p->f, p->width, p->height) : fr_camera_weak(p->f, p->width, p->height);
}

/* uv and the 2x3 derivative of uv with respect to camera coordinates; points nearer than
 * MIN_DEPTH are projected as if at MIN_DEPTH (and reported with 0). */
static int project_one(const fr_fit_photo *p, const double Xc[3], double uv[2], double P[6]) {
    fr_camera cam = camera_of(p);
    double x[3] = {Xc[0], Xc[1], Xc[2] < MIN_DEPTH ? MIN_DEPTH : Xc[2]};
    fr_camera_project(&cam, x, uv);
    if (P) fr_camera_project_jacobian(&cam, x, P);
    return !p->perspective || Xc[2] >= MIN_DEPTH;
}

void fr_fit_photo_project(const fr_fit_photo *p, const double *X, int n, double *uv) {
    for (int k = 0; k < n; k++) {
        double Xr[3], Xc[3];
        to_camera(p, X + 3 * k, Xr, Xc);
        project_one(p, Xc, uv + 2 * k, NULL);
    }
}

/* ---- set-up ---- */

double fr_fit_eye_distance(const double *q) {
    double l[2] = {0, 0}, r[2] = {0, 0};
    for (int k = 36; k < 42; k++) l[0] += q[2 * k] / 6, l[1] += q[2 * k + 1] / 6;
    for (int k = 42; k < 48; k++) r[0] += q[2 * k] / 6, r[1] += q[2 * k + 1] / 6;
    return hypot(l[0] - r[0], l[1] - r[1]);
}

/* The residual unit: 2% of the eye distance, about one standard deviation of a good
 * landmark detector's error, so that the prior weights (eq. 4.8) weigh priors against
 * noise-normalized data. The eye distance is kept from collapsing on profile views by the
 * face height. (The author's code normalizes by the eye distance / 100.) */
double fr_fit_face_scale(const double *q) {
    double ymin = 1e300, ymax = -1e300;
    for (int k = 0; k < FR_LANDMARKS; k++) {
        if (q[2 * k + 1] < ymin) ymin = q[2 * k + 1];
        if (q[2 * k + 1] > ymax) ymax = q[2 * k + 1];
    }
    return fmax(fr_fit_eye_distance(q), 0.5 * (ymax - ymin));
}

static double residual_unit(const double *q) { return fmax(fr_fit_face_scale(q), 1.0) / 50.0; }

void fr_fit_photo_init_pose(const fr_fit_model *fm, fr_fit_photo *p) {
    /* Affine camera [u v]^T = A [X 1]^T by least squares over the inner landmarks (17..67),
     * then the nearest rotation and a scale. */
    double X[3 * FR_LANDMARKS];
    int slots[FR_LANDMARKS];
    for (int k = 0; k < FR_LANDMARKS; k++) slots[k] = fm->landmark_slot[k];
    fr_fit_model_eval_slots(fm, p->w, slots, FR_LANDMARKS, X);
    double M[16] = {0}, bu[4] = {0}, bv[4] = {0};
    for (int k = 17; k < FR_LANDMARKS; k++) {
        double a[4] = {X[3 * k], X[3 * k + 1], X[3 * k + 2], 1};
        for (int i = 0; i < 4; i++) {
            for (int j = 0; j < 4; j++) M[4 * i + j] += a[i] * a[j];
            bu[i] += a[i] * p->q[2 * k];
            bv[i] += a[i] * p->q[2 * k + 1];
        }
    }
    /* Solve the 4x4 normal equations by Gaussian elimination (tiny, well conditioned). */
    double A[4][9];
    for (int i = 0; i < 4; i++) {
        for (int j = 0; j < 4; j++) A[i][j] = M[4 * i + j] + (i == j && i < 3 ? 1e-12 : 0);
        A[i][4] = bu[i];
        A[i][5] = bv[i];
    }
    for (int c = 0; c < 4; c++) {
        int piv = c;
        for (int r = c + 1; r < 4; r++)
            if (fabs(A[r][c]) > fabs(A[piv][c])) piv = r;
        for (int j = 0; j < 6; j++) {
            double tmp = A[c][j];
            A[c][j] = A[piv][j];
            A[piv][j] = tmp;
        }
        if (fabs(A[c][c]) < 1e-300) A[c][c] = 1e-300;
        for (int r = 0; r < 4; r++) {
            if (r == c) continue;
            double m = A[r][c] / A[c][c];
            for (int j = 0; j < 6; j++) A[r][j] -= m * A[c][j];
        }
    }
    double au[4], av[4];
    for (int i = 0; i < 4; i++) au[i] = A[i][4] / A[i][i], av[i] = A[i][5] / A[i][i];
    double R[9] = {au[0], au[1], au[2], av[0], av[1], av[2], 0, 0, 0};
    double s = 0.5 * (sqrt(au[0] * au[0] + au[1] * au[1] + au[2] * au[2]) +
                      sqrt(av[0] * av[0] + av[1] * av[1] + av[2] * av[2]));
    orthonormalize(R);
    memcpy(p->R, R, sizeof R);
    double cx = 0.5 * (p->width - 1), cy = 0.5 * (p->height - 1);
    if (s <= 0) s = 1;
    if (p->perspective) {
        p->f = p->f0;
        p->t[2] = p->f / s;
        /* The landmarks' centroid sits at depth t_z + (R X)_z; refine t for it. */
        double mz = 0;
        for (int k = 17; k < FR_LANDMARKS; k++)
            mz += (R[6] * X[3 * k] + R[7] * X[3 * k + 1] + R[8] * X[3 * k + 2]) / (FR_LANDMARKS - 17);
        p->t[2] -= mz;
        double z = p->t[2] + mz;
        p->t[0] = (au[3] - cx) * z / p->f;
        p->t[1] = (av[3] - cy) * z / p->f;
    } else {
        p->f = s;
        p->t[0] = (au[3] - cx) / s;
        p->t[1] = (av[3] - cy) / s;
        p->t[2] = 0;
    }
}

void fr_fit_photo_init(const fr_fit_model *fm, fr_fit_photo *p, const double *landmarks, int width, int height,
                       int perspective, double *w) {
    memset(p, 0, sizeof *p);
    memcpy(p->q, landmarks, sizeof p->q);
    for (int k = 0; k < FR_LANDMARKS; k++) {
        p->weight[k] = 1;
        p->corr[k] = fm->landmark_slot[k];
    }
    p->width = width;
    p->height = height;
    p->unit = residual_unit(p->q);
    p->perspective = perspective;
    /* A 50 mm lens on a 36 mm film width: f = 1.4 x the longer image side. */
    p->f0 = 1.4 * (width > height ? width : height);
    p->w = w;
    fr_fit_photo_init_pose(fm, p);
}

void fr_fit_photo_set_contour_weight(fr_fit_photo *p, double w) {
    for (int k = 0; k < FR_CONTOUR_LANDMARKS; k++) p->weight[k] = w;
}

/* ---- residuals and Jacobian ---- */

typedef struct problem {
    const fr_fit_model *fm;
    fr_fit_photo *p;
    const fr_fit_options *opt;
    fr_fit_weights wt;
    int n_params;      /* active parameters */
    int *param;        /* active parameter -> full index (0..6 pose, 7.. weights) */
    int n_res;         /* 2 per landmark */
} problem;

/* Landmark residuals r (n_res) and, when J is not NULL, the Jacobian for the active
 * parameters (n_res x n_params, column-major). */
static void landmark_terms(const problem *pb, double *r, double *J, double *scratch) {
    const fr_fit_model *fm = pb->fm;
    const fr_fit_photo *p = pb->p;
    int nc = fm->n_cols;
    double *PRB = scratch; /* 2 x n_cols per landmark */
    for (int k = 0; k < FR_LANDMARKS; k++) {
        double X[3], Xr[3], Xc[3], uv[2], P[6];
        int slot = p->corr[k];
        fr_fit_model_eval_slots(fm, p->w, &slot, 1, X);
        to_camera(p, X, Xr, Xc);
        project_one(p, Xc, uv, P);
        double s = sqrt(p->weight[k]) / p->unit;
        r[2 * k] = s * (uv[0] - p->q[2 * k]);
        r[2 * k + 1] = s * (uv[1] - p->q[2 * k + 1]);
        if (!J) continue;
        double cx = 0.5 * (p->width - 1), cy = 0.5 * (p->height - 1);
        /* d Xc / d omega = -[Xr]_x */
        double dW[9] = {0, Xr[2], -Xr[1], -Xr[2], 0, Xr[0], Xr[1], -Xr[0], 0};
        double full[2][POSE_PARAMS];
        for (int a = 0; a < 2; a++) {
            for (int j = 0; j < 3; j++)
                full[a][j] = P[3 * a] * dW[j] + P[3 * a + 1] * dW[3 + j] + P[3 * a + 2] * dW[6 + j];
            for (int j = 0; j < 3; j++) full[a][3 + j] = P[3 * a + j];
            full[a][6] = a == 0 ? uv[0] - cx : uv[1] - cy;
        }
        /* (P R) B_slot: 2 x n_cols */
        double PR[6];
        for (int a = 0; a < 2; a++)
            for (int j = 0; j < 3; j++)
                PR[3 * a + j] = P[3 * a] * p->R[j] + P[3 * a + 1] * p->R[3 + j] + P[3 * a + 2] * p->R[6 + j];
        /* (P R) times the slot's 3 basis rows (contiguous): too small for a BLAS call. */
        const double *B0 = fr_fit_model_row(fm, slot, 0), *B1 = B0 + nc, *B2 = B1 + nc;
        for (int c = 0; c < nc; c++) {
            PRB[c] = PR[0] * B0[c] + PR[1] * B1[c] + PR[2] * B2[c];
            PRB[nc + c] = PR[3] * B0[c] + PR[4] * B1[c] + PR[5] * B2[c];
        }
        for (int c = 0; c < pb->n_params; c++) {
            int full_i = pb->param[c];
            double j0 = full_i < POSE_PARAMS ? full[0][full_i] : PRB[full_i - POSE_PARAMS];
            double j1 = full_i < POSE_PARAMS ? full[1][full_i] : PRB[nc + full_i - POSE_PARAMS];
            J[2 * k + (size_t)pb->n_res * c] = s * j0;
            J[2 * k + 1 + (size_t)pb->n_res * c] = s * j1;
        }
    }
}

static double prior_cost(const problem *pb) {
    const fr_fit_model *fm = pb->fm;
    const fr_fit_photo *p = pb->p;
    double c = 0;
    if (pb->opt->fit_identity)
        for (int i = 0; i < fm->n_id; i++) {
            double d = p->w[i] - (pb->opt->id_prior ? pb->opt->id_prior[i] : 0);
            c += pb->wt.id * d * d;
        }
    for (int i = 0; i < fm->n_exp; i++) {
        double e = p->w[fm->n_id + i];
        c += pb->wt.exp * e * e + pb->wt.sparse * e;
    }
    if (p->perspective && pb->opt->fit_focal) {
        double lf = log(p->f / p->f0);
        c += pb->wt.focal * lf * lf;
    }
    return c;
}

static double total_cost(const problem *pb, double *r, double *scratch) {
    landmark_terms(pb, r, NULL, scratch);
    double c = 0;
    for (int i = 0; i < pb->n_res; i++) c += r[i] * r[i];
    return c + prior_cost(pb);
}

/* ---- contour ---- */

/* Cosine between a slot's normal and the viewing ray (negative: facing the camera). */
static double facing(const fr_fit_photo *p, const double *X, const double *N, int s) {
    double Xr[3], Xc[3], n[3];
    to_camera(p, X + 3 * s, Xr, Xc);
    for (int c = 0; c < 3; c++) n[c] = p->R[3 * c] * N[3 * s] + p->R[3 * c + 1] * N[3 * s + 1] + p->R[3 * c + 2] * N[3 * s + 2];
    double view[3] = {p->perspective ? Xc[0] : 0, p->perspective ? Xc[1] : 0, p->perspective ? Xc[2] : 1};
    double nn = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]), vn = sqrt(view[0] * view[0] + view[1] * view[1] + view[2] * view[2]);
    return nn > 0 && vn > 0 ? (n[0] * view[0] + n[1] * view[1] + n[2] * view[2]) / (nn * vn) : 1;
}

/* Normals at the scale of the cheek and jaw: a few rounds of averaging over neighbours,
 * so that small folds (eyelids, the nasolabial fold) do not count as turning away. */
#define NORMAL_SMOOTHING_ROUNDS 3
static void smooth_normals(const fr_fit_model *fm, double *N) {
    int ns = fm->n_slots;
    double *T = malloc(sizeof(double) * 3 * (size_t)ns);
    if (!T) return;
    for (int round = 0; round < NORMAL_SMOOTHING_ROUNDS; round++) {
        for (int s = 0; s < ns; s++) { /* unit normals first, so each neighbour counts once */
            double *n = N + 3 * s, len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
            if (len > 0) n[0] /= len, n[1] /= len, n[2] /= len;
        }
        for (int s = 0; s < ns; s++) {
            double acc[3] = {N[3 * s], N[3 * s + 1], N[3 * s + 2]};
            for (int i = fm->adj_start[s]; i < fm->adj_start[s + 1]; i++) {
                const double *m = N + 3 * fm->adj[i];
                acc[0] += m[0], acc[1] += m[1], acc[2] += m[2];
            }
            memcpy(T + 3 * s, acc, sizeof acc);
        }
        memcpy(N, T, sizeof(double) * 3 * (size_t)ns);
    }
    free(T);
}

/* The jaw landmarks follow the face's outline (section 4.3, "the jawline landmarks of a
 * turned face lie on the silhouette"): on the side facing the camera the outline is the jaw
 * line itself (the landmark's own vertex); on the side turned away the cheek hides it and
 * the outline is the occluding contour. So, walking each row outward from the face centre,
 * if some vertex inside the jaw line faces away from the camera, the landmark moves to the
 * outermost front-facing vertex inside the first one that does; otherwise it stays. */
void fr_fit_photo_update_contour(const fr_fit_model *fm, fr_fit_photo *p) {
    int ns = fm->n_slots;
    double *X = malloc(sizeof(double) * 3 * (size_t)ns * 2);
    if (!X) return; /* keep the old correspondences */
    double *N = X + 3 * (size_t)ns;
    fr_fit_model_eval_all(fm, p->w, X);
    memset(N, 0, sizeof(double) * 3 * (size_t)ns);
    for (int t = 0; t < fm->n_tris; t++) {
        const int *v = fm->tris + 3 * t;
        double e1[3], e2[3];
        for (int c = 0; c < 3; c++) {
            e1[c] = X[3 * v[1] + c] - X[3 * v[0] + c];
            e2[c] = X[3 * v[2] + c] - X[3 * v[0] + c];
        }
        double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
        for (int a = 0; a < 3; a++)
            for (int c = 0; c < 3; c++) N[3 * v[a] + c] += n[c];
    }
    smooth_normals(fm, N);
    double *face = malloc(sizeof(double) * (size_t)ns);
    if (!face) {
        free(X);
        return;
    }
    for (int sl = 0; sl < ns; sl++) face[sl] = facing(p, X, N, sl);
    for (int k = 0; k < FR_CONTOUR_LANDMARKS; k++) {
        if (k == 8) continue;
        /* Only vertices clearly inside the jaw line (by a tenth of its radius) count, so that
         * the face's own border near the ears does not. */
        double jaw_r = 0.9 * fm->jaw_radius[k];
        int hidden = 0;
        for (int i = fm->row_start[k]; i < fm->row_start[k + 1] && !hidden; i++)
            if (fm->row_radius[i] < jaw_r && face[fm->row_slots[i]] > 0) hidden = 1;
        p->corr[k] = fm->landmark_slot[k];
        if (!hidden) continue;
        /* The landmark slides along the occluding contour: the nearest (in the image) front-
         * facing vertex with a back-facing neighbour, in its own row or the two on each side. */
        int first = k < 8 ? 0 : 9, last = k < 8 ? 7 : 16;
        int lo = k - 2 < first ? first : k - 2, hi = k + 2 > last ? last : k + 2;
        double best = INFINITY;
        for (int r = lo; r <= hi; r++)
            for (int i = fm->row_start[r]; i < fm->row_start[r + 1]; i++) {
                int sl = fm->row_slots[i];
                if (fm->row_radius[i] >= 0.9 * fm->jaw_radius[r] || face[sl] > 0) continue;
                int on_contour = 0;
                for (int j = fm->adj_start[sl]; j < fm->adj_start[sl + 1] && !on_contour; j++)
                    if (face[fm->adj[j]] > 0) on_contour = 1;
                if (!on_contour) continue;
                double Xr[3], Xc[3], uv[2];
                to_camera(p, X + 3 * sl, Xr, Xc);
                project_one(p, Xc, uv, NULL);
                double d = hypot(uv[0] - p->q[2 * k], uv[1] - p->q[2 * k + 1]);
                if (d < best) best = d, p->corr[k] = sl;
            }
    }
    free(face);
    free(X);
}

/* ---- the solver ---- */

static void weights_at(const fr_fit_options *opt, int it, int n, fr_fit_weights *w) {
    double a = n > 1 ? (double)it / (n - 1) : 1;
    w->id = opt->start.id * pow(opt->end.id / opt->start.id, a);
    w->exp = opt->start.exp * pow(opt->end.exp / opt->start.exp, a);
    w->sparse = opt->start.sparse * pow(opt->end.sparse / opt->start.sparse, a);
    w->focal = opt->start.focal;
}

static void apply_step(const problem *pb, fr_fit_photo *p, const double *d) {
    double dw[3] = {0, 0, 0};
    for (int c = 0; c < pb->n_params; c++) {
        int f = pb->param[c];
        if (f < 3) dw[f] = d[c];
        else if (f < 6) p->t[f - 3] += d[c];
        else if (f == 6) p->f *= exp(d[c]);
        else p->w[f - POSE_PARAMS] += d[c];
    }
    double dR[9], M[9];
    fr_rotation_from_axis_angle(dw, dR);
    fr_mat3_mul(dR, p->R, M);
    memcpy(p->R, M, sizeof M);
    orthonormalize(p->R);
    /* Expression weights stay exactly inside [0, 1]. */
    const fr_fit_model *fm = pb->fm;
    for (int i = 0; i < fm->n_exp; i++) {
        double *e = &p->w[fm->n_id + i];
        *e = *e < 0 ? 0 : *e > 1 ? 1 : *e;
    }
}

frig_status fr_fit_photo_run(frig_ctx *ctx, const fr_fit_model *fm, fr_fit_photo *p, const fr_fit_options *opt) {
    problem pb = {fm, p, opt, opt->start, 0, NULL, 2 * FR_LANDMARKS};
    int nfull = POSE_PARAMS + fm->n_cols;
    pb.param = malloc(sizeof(int) * (size_t)nfull);
    int np_max = nfull;
    double *J = malloc(sizeof(double) * (size_t)pb.n_res * np_max);
    double *H = malloc(sizeof(double) * (size_t)np_max * np_max * 2);
    double *buf = malloc(sizeof(double) * ((size_t)np_max * 6 + (size_t)pb.n_res * 2 + 2 * (size_t)fm->n_cols));
    double *saved_w = malloc(sizeof(double) * (size_t)fm->n_cols);
    if (!pb.param || !J || !H || !buf || !saved_w) {
        free(pb.param), free(J), free(H), free(buf), free(saved_w);
        return fr_nomem(ctx, "a photo fit");
    }
    for (int i = 0; i < POSE_PARAMS; i++) {
        if (i == 5 && !p->perspective) continue; /* depth does not matter to weak perspective */
        if (i == 6 && !opt->fit_focal) continue;
        pb.param[pb.n_params++] = i;
    }
    for (int i = 0; i < fm->n_cols; i++) {
        if (i < fm->n_id ? !opt->fit_identity : !opt->fit_expression) continue;
        pb.param[pb.n_params++] = POSE_PARAMS + i;
    }
    int n = pb.n_params;
    double *Hd = H + (size_t)n * n, *g = buf, *d = g + n, *lo = d + n, *hi = lo + n, *diag = hi + n;
    double *r = diag + n, *r2 = r + pb.n_res, *scratch = r2 + pb.n_res;
    double lambda = 1e-3;
    fr_fit_photo_update_contour(fm, p);
    int iters = opt->iterations > 0 ? opt->iterations : 1;
    int contour_every = opt->contour_every > 0 ? opt->contour_every : 5;
    for (int it = 0; it < iters; it++) {
        weights_at(opt, it, iters, &pb.wt);
        if (it > 0 && it % contour_every == 0) fr_fit_photo_update_contour(fm, p);
        double cost = total_cost(&pb, r, scratch);
        landmark_terms(&pb, r, J, scratch);
        /* H = J^T J + prior Hessian; g = J^T r + prior gradient */
        cblas_dsyrk(CblasColMajor, CblasLower, CblasTrans, n, pb.n_res, 1.0, J, pb.n_res, 0.0, H, n);
        cblas_dgemv(CblasColMajor, CblasTrans, pb.n_res, n, 1.0, J, pb.n_res, r, 1, 0.0, g, 1);
        for (int c = 0; c < n; c++) {
            int f = pb.param[c];
            lo[c] = -INFINITY;
            hi[c] = INFINITY;
            if (f == 6) {
                H[c + (size_t)n * c] += pb.wt.focal;
                g[c] += pb.wt.focal * log(p->f / p->f0);
            } else if (f >= POSE_PARAMS) {
                int wi = f - POSE_PARAMS;
                if (wi < fm->n_id) {
                    double mu = opt->id_prior ? opt->id_prior[wi] : 0;
                    H[c + (size_t)n * c] += pb.wt.id;
                    g[c] += pb.wt.id * (p->w[wi] - mu);
                } else {
                    H[c + (size_t)n * c] += pb.wt.exp;
                    g[c] += pb.wt.exp * p->w[wi] + 0.5 * pb.wt.sparse;
                    lo[c] = -p->w[wi];
                    hi[c] = 1 - p->w[wi];
                }
            }
            diag[c] = H[c + (size_t)n * c];
        }
        for (int c = 0; c < n; c++)
            for (int e = c + 1; e < n; e++) H[c + (size_t)n * e] = H[e + (size_t)n * c];
        /* Levenberg-Marquardt: try steps with growing damping until the cost drops. */
        int accepted = 0;
        for (int tries = 0; tries < 8 && !accepted; tries++) {
            memcpy(Hd, H, sizeof(double) * (size_t)n * n);
            for (int c = 0; c < n; c++) Hd[c + (size_t)n * c] += lambda * (diag[c] + 1e-9);
            memset(d, 0, sizeof(double) * (size_t)n);
            if (fr_box_qp(ctx, n, Hd, g, lo, hi, d) != FRIG_OK) {
                lambda *= 10;
                continue;
            }
            fr_fit_photo saved = *p;
            memcpy(saved_w, p->w, sizeof(double) * (size_t)fm->n_cols);
            apply_step(&pb, p, d);
            double new_cost = total_cost(&pb, r2, scratch);
            if (new_cost < cost) {
                accepted = 1;
                lambda = fmax(lambda / 3, 1e-7);
            } else {
                double *w = p->w;
                *p = saved;
                p->w = w;
                memcpy(p->w, saved_w, sizeof(double) * (size_t)fm->n_cols);
                lambda *= 5;
            }
        }
        p->iterations = it + 1;
        if (!accepted && it >= iters / 2) break;
    }
    p->cost = total_cost(&pb, r, scratch);
    p->rms_px = fr_fit_photo_rms(fm, p);
    frig_ctx_clear_error(ctx); /* a refused step is not an error of the call */
    free(pb.param), free(J), free(H), free(buf), free(saved_w);
    return FRIG_OK;
}

double fr_fit_photo_rms(const fr_fit_model *fm, const fr_fit_photo *p) {
    double s = 0, wsum = 0;
    for (int k = 0; k < FR_LANDMARKS; k++) {
        if (p->weight[k] <= 0) continue;
        double X[3], uv[2];
        int slot = p->corr[k];
        fr_fit_model_eval_slots(fm, p->w, &slot, 1, X);
        fr_fit_photo_project(p, X, 1, uv);
        double dx = uv[0] - p->q[2 * k], dy = uv[1] - p->q[2 * k + 1];
        s += p->weight[k] * (dx * dx + dy * dy);
        wsum += p->weight[k];
    }
    return wsum > 0 ? sqrt(s / wsum) : 0;
}

void fr_fit_photo_identity_jacobian(const fr_fit_model *fm, const fr_fit_photo *p, double *J, double *r) {
    fr_fit_options opt = {0};
    opt.fit_identity = 1;
    problem pb = {fm, (fr_fit_photo *)p, &opt, opt.start, 0, NULL, 2 * FR_LANDMARKS};
    int *param = malloc(sizeof(int) * (size_t)(fm->n_id > 0 ? fm->n_id : 1));
    double *scratch = malloc(sizeof(double) * 2 * (size_t)fm->n_cols);
    if (!param || !scratch) {
        free(param);
        free(scratch);
        memset(J, 0, sizeof(double) * 2 * FR_LANDMARKS * (size_t)fm->n_id);
        memset(r, 0, sizeof(double) * 2 * FR_LANDMARKS);
        return;
    }
    for (int i = 0; i < fm->n_id; i++) param[i] = POSE_PARAMS + i;
    pb.param = param;
    pb.n_params = fm->n_id;
    landmark_terms(&pb, r, J, scratch);
    free(param);
    free(scratch);
}
