/* A photo's pose registered to the shared surface and albedo, coarse to fine (beyond the paper:
 * its poses are the landmark fit's, which on turned faces are several degrees off; docs/sfs.md,
 * "The blocker is the pose"). Two terms, one 6 x 6 Levenberg-Marquardt per level:
 * - photometric (direct image alignment with depth, Lucas-Kanade on a textured surface): the
 *   prediction a(uv) S(n) (the subject's albedo at the pixel's UV, the photo's own SH lighting on
 *   the drawn normal) is drawn at the current pose; the photo is sampled at every face pixel's
 *   projection through the moved pose (R', t') = (exp([w]) R, t + dt); both are blurred by the
 *   same Gaussian inside the face only (normalized convolution, so the unknown background does
 *   not enter), and compared with Huber's residual (hair, beards, occluders do not pull);
 * - the occluding contour (the cheek, jaw and head outline against the background, seen edge-on
 *   in the drawn rig): each contour point paired with the strongest edge of the blurred photo
 *   along its outward direction, point-to-line distances in pixels (ICP: pairs found again at
 *   every step).
 * A blur of sigma pixels widens the basin to a misregistration of about that many pixels (8 at a
 * 160-pixel face: a turn of about 8 degrees about the head's centre); each level's pose starts
 * the next, finer one. The coarse levels run on the crop reduced by about sigma / 2 (area
 * averages), so every level costs about the same. */
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "core/sort.h"
#include "image/gaussian_blur.h"
#include "linalg/linalg.h"
#include "raster/rotation.h"
#include "raster/sh_lighting.h"
#include "sfs/sfs_pose_align.h"
#include "sfs/sfs_uv.h"

#define HUBER_K 1.345
#define NB 4               /* the prediction's lighting: constant and linear SH terms per channel */
#define NCH (3 * NB)       /* basis channels: albedo_c x Y_k(n) */
#define LIGHT_RIDGE 1e-3   /* the lighting fit's ridge, relative to the mean diagonal */
#define MIN_MASK 0.6       /* template cells need this much face in their blurred neighbourhood */
#define MIN_TEMPLATE 50    /* fewer template cells: the level is skipped */
#define FACE_REF_PX 160.0  /* sigma_px is for a face this long in the crop */
#define CONTOUR_OFFSET 0.5 /* the drawn contour pixel lies this far inside the outline (pixels) */
#define EDGE_ON_COS 0.4    /* contour pixels are seen at more than 66 degrees */

void fr_sfs_pose_align_options_default(fr_sfs_pose_align_options *o) {
    o->levels = 3;
    o->sigma_px = 2.0;
    o->steps = 5;
    o->scale = 0.05;
    o->max_deg = 25.0;
    o->w_photo = 1.0;
    o->w_contour = 1.0;
    o->redraw = 1;
}

static double huber_rho(double u) {
    double a = fabs(u);
    return a <= HUBER_K ? 0.5 * u * u : HUBER_K * (a - 0.5 * HUBER_K);
}

static double huber_w(double u) {
    double a = fabs(u);
    return a <= HUBER_K ? 1.0 : HUBER_K / a;
}

/* One level's problem. */
typedef struct level {
    const fr_sfs_view *v;
    /* the photometric term, on the crop reduced by d */
    int w, h, d;
    fr_camera cam;   /* the reduced grid's camera */
    float *I, *Ib;   /* the reduced photo and its blur (3 per cell) */
    float *Mc, *Mb;  /* the share of face pixels per cell and its blur */
    float *PM, *PMb; /* the prediction's basis (NCH per cell) times that share, and its blur */
    int nf;          /* cells with face */
    int32_t *fpix;   /* their index */
    double *fq;      /* 3 per face cell: the mean X - t of its face pixels at the drawn pose */
    int nt;          /* template cells (mostly face, mostly surrounded by face) */
    int tbox[4];     /* their bounding box (x0, y0, x1, y1: half-open) */
    int32_t *tpix, *tface;
    double *tB;     /* NCH per template cell: the blurred basis */
    double *tP;     /* 3 per template cell: the blurred prediction */
    float *Iw, *Wb; /* the photo warped onto the face cells (times their share) and its blur */
    int warped;     /* 1: Iw and Wb hold the warp at the pose (wA, wt): a step's equations come at
                     * the pose its accepted try was warped at */
    double wA[9], wt[3];
    double sigma_r, sc, w_photo;
    /* the occluding contour, at the crop's resolution (its edges read on the reduced grid) */
    double sigma;
    int nc;
    double *cq;       /* 3 per contour point: X - t at the drawn pose */
    double *cnu;      /* 2 per: its outward direction in the crop */
    double *cy;       /* 2 per: the photo's edge it is paired with */
    double *cw;       /* per: 1, or 0 when no edge was found */
    double w_contour; /* weight of one contour residual */
    double csc;       /* contour residual scale, pixels */
    double pc[3];     /* the rotation's centre at the current pose: the face's mean point (camera frame) */
    int restricted;   /* 1: only the turn about the viewing axis and the translation (coarse levels) */
} level;

static void level_free(level *L) {
    free(L->I), free(L->Ib), free(L->Mc), free(L->Mb), free(L->PM), free(L->PMb), free(L->fpix), free(L->fq);
    free(L->tpix), free(L->tface), free(L->tB), free(L->tP), free(L->Iw), free(L->Wb), free(L->cq), free(L->cnu);
    free(L->cy), free(L->cw);
}

static frig_status level_alloc(frig_ctx *ctx, const fr_sfs_view *v, level *L) {
    size_t n = (size_t)v->w * v->h + 1;
    L->I = malloc(sizeof(float) * 3 * n), L->Ib = malloc(sizeof(float) * 3 * n);
    L->Mc = malloc(sizeof(float) * n), L->Mb = malloc(sizeof(float) * n);
    L->PM = malloc(sizeof(float) * NCH * n), L->PMb = malloc(sizeof(float) * NCH * n);
    L->tB = malloc(sizeof(double) * NCH * n);
    L->fpix = malloc(sizeof(int32_t) * n), L->fq = malloc(sizeof(double) * 3 * n);
    L->tpix = malloc(sizeof(int32_t) * n), L->tface = malloc(sizeof(int32_t) * n),
    L->tP = malloc(sizeof(double) * 3 * n);
    L->Iw = malloc(sizeof(float) * 3 * n), L->Wb = malloc(sizeof(float) * 3 * n);
    L->cq = malloc(sizeof(double) * 3 * n), L->cnu = malloc(sizeof(double) * 2 * n);
    L->cy = malloc(sizeof(double) * 2 * n), L->cw = calloc(n, sizeof(double));
    if (!L->I || !L->Ib || !L->Mc || !L->Mb || !L->PM || !L->PMb || !L->fpix || !L->fq || !L->tpix || !L->tface ||
        !L->tP || !L->tB || !L->Iw || !L->Wb || !L->cq || !L->cnu || !L->cy || !L->cw)
        return fr_nomem(ctx, "the pose alignment");
    return FRIG_OK;
}

/* The prediction's basis at the view's narrow-face pixels (mask M): the albedo a_c(uv) times the
 * constant and linear SH terms of the drawn normal, NCH per pixel (the lighting is fitted to the
 * photo at each level); returns the face's longer side in pixels. */
static double predict(const fr_sfs_mesh *m, const fr_sfs_view *v, const float *tex, const float *tex_w, int T, float *P,
                      uint8_t *M) {
    int x0 = v->w, y0 = v->h, x1 = -1, y1 = -1;
    for (int y = 0; y < v->h; y++)
        for (int x = 0; x < v->w; x++) {
            size_t i = (size_t)y * v->w + x;
            double uv[2], y9[FR_SH_COUNT], n[3] = {v->n_ref[3 * i], v->n_ref[3 * i + 1], v->n_ref[3 * i + 2]};
            float a[3];
            M[i] = 0;
            memset(P + NCH * i, 0, sizeof(float) * NCH);
            if (!v->core[i] || !fr_sfs_uv_at_pixel(m, v, i, uv) || !fr_sfs_texture_sample(tex, tex_w, T, 3, uv, a))
                continue;
            fr_sh_basis(n, y9);
            for (int c = 0; c < 3; c++)
                for (int k = 0; k < NB; k++)
                    P[NCH * i + NB * c + k] = (float)(a[c] * y9[k]);
            M[i] = 1;
            x0 = x < x0 ? x : x0, x1 = x > x1 ? x : x1, y0 = y < y0 ? y : y0, y1 = y > y1 ? y : y1;
        }
    return x1 < 0 ? 0 : fmax(x1 - x0 + 1, y1 - y0 + 1);
}

/* The drawn point at pixel i (camera frame), and its interpolated vertex normal. */
static void drawn_point(const fr_sfs_mesh *m, const fr_sfs_view *v, size_t i, double X[3], double nn[3]) {
    const int32_t *tri = m->tris + 3 * (size_t)v->tri[i];
    const float *b = v->bary + 3 * i;
    X[0] = X[1] = X[2] = 0;
    if (nn) nn[0] = nn[1] = nn[2] = 0;
    for (int c = 0; c < 3; c++)
        for (int d = 0; d < 3; d++) {
            X[d] += b[c] * v->xyz_cam[3 * (size_t)tri[c] + d];
            if (nn) nn[d] += b[c] * v->vn_cam[3 * (size_t)tri[c] + d];
        }
}

/* The bounding box (x0, y0, x1, y1: half-open) of n cells of a grid w wide. */
static void cell_box(const int32_t *cells, int n, int w, int box[4]) {
    box[0] = box[1] = n ? INT32_MAX : 0, box[2] = box[3] = 0;
    for (int j = 0; j < n; j++) {
        int x = cells[j] % w, y = cells[j] / w;
        box[0] = x < box[0] ? x : box[0], box[1] = y < box[1] ? y : box[1];
        box[2] = x + 1 > box[2] ? x + 1 : box[2], box[3] = y + 1 > box[3] ? y + 1 : box[3];
    }
}

/* The reduced grid of the level (factor L->d): photo, face share, prediction, the face cells'
 * points; then the blurs and the template. */
static frig_status build_grid(frig_ctx *ctx, const fr_sfs_mesh *m, const fr_sfs_view *v, const float *P,
                              const uint8_t *M, level *L) {
    int d = L->d, w = (v->w + d - 1) / d, h = (v->h + d - 1) / d;
    L->w = w, L->h = h, L->warped = 0;
    L->cam = v->cam;
    L->cam.f /= d, L->cam.scale /= d;
    L->cam.cx = (v->cam.cx - 0.5 * (d - 1)) / d, L->cam.cy = (v->cam.cy - 0.5 * (d - 1)) / d;
    L->nf = 0;
    for (int cy = 0; cy < h; cy++)
        for (int cx = 0; cx < w; cx++) {
            size_t c = (size_t)cy * w + cx;
            double I[3] = {0, 0, 0}, PMs[NCH] = {0}, X[3] = {0, 0, 0};
            int np = 0, nm = 0;
            for (int y = cy * d; y < cy * d + d && y < v->h; y++)
                for (int x = cx * d; x < cx * d + d && x < v->w; x++) {
                    size_t i = (size_t)y * v->w + x;
                    for (int k = 0; k < 3; k++)
                        I[k] += v->I[3 * i + k];
                    np++;
                    if (!M[i]) continue;
                    double Xi[3];
                    drawn_point(m, v, i, Xi, NULL);
                    for (int k = 0; k < NCH; k++)
                        PMs[k] += P[NCH * i + k];
                    for (int k = 0; k < 3; k++)
                        X[k] += Xi[k];
                    nm++;
                }
            for (int k = 0; k < 3; k++)
                L->I[3 * c + k] = (float)(I[k] / np);
            for (int k = 0; k < NCH; k++)
                L->PM[NCH * c + k] = (float)(PMs[k] / np);
            L->Mc[c] = (float)nm / np;
            if (!nm) continue;
            L->fpix[L->nf] = (int32_t)c;
            for (int k = 0; k < 3; k++)
                L->fq[3 * (size_t)L->nf + k] = X[k] / nm - v->t[k];
            L->nf++;
        }
    /* the blurred face share is read at face cells only, the blurred prediction and (in
     * photo_terms) the blurred warped photo at template cells only: blurred in their boxes */
    int fb[4], *tb = L->tbox;
    cell_box(L->fpix, L->nf, w, fb);
    frig_status s = fr_gaussian_blur_window(ctx, L->Mc, w, h, 1, L->sigma_r, fb[0], fb[1], fb[2], fb[3], L->Mb);
    if (!s) s = fr_gaussian_blur(ctx, L->I, w, h, 3, L->sigma_r, L->Ib);
    if (s) return s;
    L->nt = 0;
    for (int f = 0; f < L->nf; f++) {
        size_t c = (size_t)L->fpix[f];
        if (!(L->Mc[c] > 0.5f) || !(L->Mb[c] > MIN_MASK)) continue;
        L->tpix[L->nt] = (int32_t)c, L->tface[L->nt] = f;
        L->nt++;
    }
    cell_box(L->tpix, L->nt, w, tb);
    s = fr_gaussian_blur_window(ctx, L->PM, w, h, NCH, L->sigma_r, tb[0], tb[1], tb[2], tb[3], L->PMb);
    if (s)
        return s;
    for (int j = 0; j < L->nt; j++) {
        size_t c = (size_t)L->tpix[j];
        for (int k = 0; k < NCH; k++)
            L->tB[NCH * (size_t)j + k] = L->PMb[NCH * c + k] / L->Mb[c];
    }
    return FRIG_OK;
}

/* The occluding contour of the head as drawn now: pixels of a face-material triangle with a
 * background neighbour (no triangle), away from the crop's border, whose surface is seen nearly
 * edge-on (so the neck's cut is not one), with the outward direction from those neighbours. */
static void build_contour(const fr_sfs_mesh *m, const fr_sfs_view *v, level *L) {
    L->nc = 0;
    for (int y = 2; y < v->h - 2; y++)
        for (int x = 2; x < v->w - 2; x++) {
            size_t i = (size_t)y * v->w + x;
            int32_t tr = v->tri[i];
            if (tr < 0 || !m->face[tr]) continue;
            double nu[2] = {0, 0};
            int bg = 0;
            for (int dy = -1; dy <= 1; dy++)
                for (int dx = -1; dx <= 1; dx++)
                    if (v->tri[i + (ptrdiff_t)dy * v->w + dx] < 0) nu[0] += dx, nu[1] += dy, bg++;
            double l = sqrt(nu[0] * nu[0] + nu[1] * nu[1]);
            if (!bg || !(l > 0)) continue;
            double X[3], nn[3];
            drawn_point(m, v, i, X, nn);
            double xl = sqrt(X[0] * X[0] + X[1] * X[1] + X[2] * X[2]),
                   nl = sqrt(nn[0] * nn[0] + nn[1] * nn[1] + nn[2] * nn[2]);
            if (!(xl > 0) || !(nl > 0) || fabs(nn[0] * X[0] + nn[1] * X[1] + nn[2] * X[2]) / (xl * nl) > EDGE_ON_COS)
                continue;
            for (int d = 0; d < 3; d++)
                L->cq[3 * (size_t)L->nc + d] = X[d] - v->t[d];
            L->cnu[2 * (size_t)L->nc] = nu[0] / l, L->cnu[2 * (size_t)L->nc + 1] = nu[1] / l;
            L->nc++;
        }
}

/* The photo's edge strength across direction nu at xy: the blurred photo's derivative along nu,
 * summed over the channels in absolute value (on the reduced grid). */
static double edge_strength(const level *L, const double xy[2], const double nu[2]) {
    /* crop pixel x is reduced cell (x - (d - 1) / 2) / d; the difference spans one cell */
    double o = 0.5 * (L->d - 1), c[2] = {(xy[0] - o) / L->d, (xy[1] - o) / L->d};
    double a[3], b[3], xa[2] = {c[0] + nu[0], c[1] + nu[1]}, xb[2] = {c[0] - nu[0], c[1] - nu[1]};
    fr_bilinear3(L->Ib, L->w, L->h, xa, a), fr_bilinear3(L->Ib, L->w, L->h, xb, b);
    return fabs(a[0] - b[0]) + fabs(a[1] - b[1]) + fabs(a[2] - b[2]);
}

/* Each contour point at the pose (A, tc) paired with the strongest edge of the blurred photo
 * along its outward direction, within a window of the blur's size (nearer edges preferred);
 * points whose best edge is weak (below a quarter of the median best) get no weight. */
static double preference(double sd, double win) {
    return exp(-0.5 * sd * sd / (win * win));
}

static void contour_targets(level *L, const double A[9], const double tc[3], double *scratch) {
    double win = 2 * L->sigma + 3, step = 0.5;
    int m = 0, ns = 0;
    /* the preference of each offset along the search, the same for every point (NULL: each time) */
    for (double sd = -win; sd <= win + 1e-9; sd += step)
        ns++;
    double *pref = malloc(sizeof(double) * ((size_t)ns + 1));
    if (pref) {
        int i = 0;
        for (double sd = -win; sd <= win + 1e-9; sd += step)
            pref[i++] = preference(sd, win);
    }
    for (int j = 0; j < L->nc; j++) {
        double q[3], X[3], xy[2];
        const double *nu = L->cnu + 2 * (size_t)j;
        fr_mat3_apply(A, L->cq + 3 * (size_t)j, q);
        for (int c = 0; c < 3; c++)
            X[c] = q[c] + tc[c];
        L->cw[j] = 0;
        if (!fr_camera_project(&L->v->cam, X, xy)) continue;
        double best = -1, best_s = 0, best_e = 0;
        int i = 0;
        for (double sd = -win; sd <= win + 1e-9; sd += step, i++) {
            double p[2] = {xy[0] + sd * nu[0], xy[1] + sd * nu[1]};
            if (p[0] < 1 || p[1] < 1 || p[0] > L->v->w - 2 || p[1] > L->v->h - 2) continue;
            double e = edge_strength(L, p, nu), score = e * (pref ? pref[i] : preference(sd, win));
            if (score > best) best = score, best_s = sd, best_e = e;
        }
        if (best < 0) continue;
        L->cy[2 * j] = xy[0] + best_s * nu[0], L->cy[2 * j + 1] = xy[1] + best_s * nu[1];
        L->cw[j] = best_e;
        scratch[m++] = best_e;
    }
    free(pref);
    if (!m) return;
    qsort(scratch, (size_t)m, sizeof *scratch, fr_cmp_double);
    double med = scratch[m / 2];
    for (int j = 0; j < L->nc; j++)
        L->cw[j] = med > 0 && L->cw[j] > 0.25 * med ? 1.0 : 0.0;
}

/* H's entries k >= p only: the upper triangle of the row-major H is the lower one of the column-major
 * matrix that fr_solve_spd factors, the only one it reads (the rest stays 0). */
static void accumulate(const double jr[6], double w, double r, double *H, double *g) {
    for (int p = 0; p < 6; p++) {
        g[p] += w * jr[p] * r;
        for (int k = p; k < 6; k++)
            H[6 * p + k] += w * jr[p] * jr[k];
    }
}

/* The contour's energy at the pose mapping q to A q + tc (with H, g when H is given). */
static double contour_terms(const level *L, const double A[9], const double tc[3], double *H, double *g) {
    double e = 0;
    for (int j = 0; j < L->nc; j++) {
        if (!(L->cw[j] > 0)) continue;
        double q[3], X[3], xy[2], J[6];
        const double *nu = L->cnu + 2 * (size_t)j;
        fr_mat3_apply(A, L->cq + 3 * (size_t)j, q);
        for (int c = 0; c < 3; c++)
            X[c] = q[c] + tc[c];
        if (!fr_camera_project(&L->v->cam, X, xy)) continue;
        double r = (nu[0] * (xy[0] - L->cy[2 * j]) + nu[1] * (xy[1] - L->cy[2 * j + 1]) + CONTOUR_OFFSET) / L->csc;
        double wc = L->w_contour * L->cw[j];
        e += wc * huber_rho(r);
        if (!H) continue;
        fr_camera_project_jacobian(&L->v->cam, X, J);
        double u[3], jr[6];
        for (int d = 0; d < 3; d++)
            u[d] = (J[d] * nu[0] + J[3 + d] * nu[1]) / L->csc, q[d] = X[d] - L->pc[d];
        /* dr/dw = q x u (q = X - pc), dr/dt = u */
        for (int d = 0; d < 3; d++) {
            int d1 = (d + 1) % 3, d2 = (d + 2) % 3;
            jr[d] = q[d1] * u[d2] - q[d2] * u[d1];
            jr[3 + d] = u[d];
        }
        accumulate(jr, wc * huber_w(r), r, H, g);
    }
    return e;
}

/* The reduced photo sampled at every face cell's new projection at the pose mapping q to A q + tc
 * (times the cell's face share, 0 elsewhere) into Iw, and its blur inside the template's box into
 * Wb; nothing to do when they hold that pose's already. */
static frig_status warp(frig_ctx *ctx, level *L, const double A[9], const double tc[3]) {
    if (L->warped && !memcmp(A, L->wA, sizeof L->wA) && !memcmp(tc, L->wt, sizeof L->wt)) return FRIG_OK;
    L->warped = 0;
    memset(L->Iw, 0, sizeof(float) * 3 * (size_t)L->w * L->h);
    for (int f = 0; f < L->nf; f++) {
        double q[3], X[3], xy[2], I[3];
        size_t c0 = (size_t)L->fpix[f];
        fr_mat3_apply(A, L->fq + 3 * (size_t)f, q);
        for (int c = 0; c < 3; c++)
            X[c] = q[c] + tc[c];
        if (!fr_camera_project(&L->cam, X, xy)) continue;
        fr_bilinear3(L->I, L->w, L->h, xy, I);
        for (int c = 0; c < 3; c++)
            L->Iw[3 * c0 + c] = (float)(L->Mc[c0] * I[c]);
    }
    frig_status s = fr_gaussian_blur_window(ctx, L->Iw, L->w, L->h, 3, L->sigma_r, L->tbox[0], L->tbox[1], L->tbox[2],
                                            L->tbox[3], L->Wb);
    if (s) return s;
    memcpy(L->wA, A, sizeof L->wA), memcpy(L->wt, tc, sizeof L->wt);
    L->warped = 1;
    return FRIG_OK;
}

/* The photometric energy at that pose: the warped photo, blurred inside the face like the
 * prediction, against it; with H, g when H is given (the warp's derivative through the blurred
 * photo's gradient). */
static frig_status photo_terms(frig_ctx *ctx, level *L, const double A[9], const double tc[3], double *H, double *g,
                               double *energy) {
    *energy = 0;
    if (!(L->w_photo > 0)) return FRIG_OK;
    frig_status s = warp(ctx, L, A, tc);
    if (s) return s;
    double e = 0;
    for (int j = 0; j < L->nt; j++) {
        size_t i = (size_t)L->tpix[j];
        double r[3];
        for (int c = 0; c < 3; c++)
            r[c] = (L->tP[3 * (size_t)j + c] - L->Wb[3 * i + c] / L->Mb[i]) / L->sc;
        for (int c = 0; c < 3; c++)
            e += L->w_photo * huber_rho(r[c]);
        if (!H) continue;
        double q[3], X[3], xy[2], J[6];
        fr_mat3_apply(A, L->fq + 3 * (size_t)L->tface[j], q);
        for (int c = 0; c < 3; c++)
            X[c] = q[c] + tc[c];
        if (!fr_camera_project(&L->cam, X, xy)) continue;
        fr_camera_project_jacobian(&L->cam, X, J);
        for (int d = 0; d < 3; d++)
            q[d] = X[d] - L->pc[d];
        double gx[3], gy[3];
        fr_sfs_image_gradient(L->Ib, L->w, L->h, xy, gx, gy);
        for (int c = 0; c < 3; c++) {
            double u[3], jr[6];
            for (int d = 0; d < 3; d++)
                u[d] = J[d] * gx[c] + J[3 + d] * gy[c];
            /* about the centre: dI/dw = q x u (q = X - pc), dI/dt = u; r = (P - I) / sc */
            for (int d = 0; d < 3; d++) {
                int d1 = (d + 1) % 3, d2 = (d + 2) % 3;
                jr[d] = -(q[d1] * u[d2] - q[d2] * u[d1]) / L->sc;
                jr[3 + d] = -u[d] / L->sc;
            }
            accumulate(jr, L->w_photo * huber_w(r[c]), r[c], H, g);
        }
    }
    *energy = e;
    return FRIG_OK;
}

static frig_status align_terms(frig_ctx *ctx, level *L, const double A[9], const double tc[3], double *H, double *g,
                               double *energy) {
    if (H) memset(H, 0, 36 * sizeof *H), memset(g, 0, 6 * sizeof *g);
    frig_status s = photo_terms(ctx, L, A, tc, H, g, energy);
    if (!s) *energy += contour_terms(L, A, tc, H, g);
    return s;
}

/* Levenberg-Marquardt steps on (A, tc), the contour paired again before each; returns the steps
 * taken (-1 on an error). */
static int align_lm(frig_ctx *ctx, level *L, int steps, double A[9], double tc[3], double *scratch) {
    double H[36], g[6], mu = 1e-3, e;
    int taken = 0;
    /* the turn's centre: the face's mean point at the current pose (decouples turn and shift) */
    double mq[3] = {0, 0, 0};
    for (int f = 0; f < L->nf; f++)
        for (int c = 0; c < 3; c++)
            mq[c] += L->fq[3 * (size_t)f + c] / L->nf;
    for (int it = 0; it < steps; it++) {
        fr_mat3_apply(A, mq, L->pc);
        for (int c = 0; c < 3; c++)
            L->pc[c] += tc[c];
        contour_targets(L, A, tc, scratch);
        if (align_terms(ctx, L, A, tc, H, g, &e)) return -1;
        if (L->restricted) /* no turn about the camera's x and y axes: out of the image plane */
            for (int a = 0; a < 2; a++) {
                for (int k = 0; k < 6; k++)
                    H[6 * a + k] = H[6 * k + a] = 0;
                H[7 * a] = 1, g[a] = 0;
            }
        int done = 0;
        for (int tries = 0; tries < 6 && !done; tries++) {
            double M[36], b[6];
            memcpy(M, H, sizeof M);
            for (int i = 0; i < 6; i++)
                M[7 * i] += mu * (H[7 * i] > 0 ? H[7 * i] : 1), b[i] = -g[i];
            if (fr_solve_spd(ctx, 6, 1, M, 6, b, 6)) {
                frig_ctx_clear_error(ctx);
                mu *= 10;
                continue;
            }
            double dR[9], A2[9], t2[3], e2;
            fr_rotation_from_axis_angle(b, dR);
            fr_mat3_mul(dR, A, A2);
            double rel[3] = {tc[0] - L->pc[0], tc[1] - L->pc[1], tc[2] - L->pc[2]}, rr[3];
            fr_mat3_apply(dR, rel, rr);
            for (int c = 0; c < 3; c++)
                t2[c] = rr[c] + L->pc[c] + b[3 + c];
            if (align_terms(ctx, L, A2, t2, NULL, NULL, &e2)) return -1;
            if (e2 < e) {
                memcpy(A, A2, sizeof A2), memcpy(tc, t2, sizeof t2);
                mu *= 0.3, done = 1, taken++;
            } else
                mu *= 10;
        }
        if (!done) break;
    }
    return taken;
}

/* The prediction's lighting (constant and linear SH terms per channel) fitted to the blurred photo
 * at the pose (A, tc) by least squares with a small ridge, and the template's prediction from
 * it: the photo's own lighting estimate is the least reliable part of the prediction where the
 * poses are wrong. *mean: the prediction's mean over the template. */
static frig_status fit_lighting(frig_ctx *ctx, level *L, const double A[9], const double tc[3], double *mean) {
    double ed;
    L->sc = 1;
    *mean = 0;
    frig_status s = photo_terms(ctx, L, A, tc, NULL, NULL, &ed);
    for (int c = 0; c < 3 && !s; c++) {
        double N[NB * NB] = {0}, r[NB] = {0}, tr = 0;
        for (int j = 0; j < L->nt; j++) {
            const double *B = L->tB + NCH * (size_t)j + NB * c;
            double Ij = L->Wb[3 * (size_t)L->tpix[j] + c] / L->Mb[L->tpix[j]];
            for (int k = 0; k < NB; k++) {
                r[k] += B[k] * Ij;
                for (int q = 0; q < NB; q++)
                    N[NB * k + q] += B[k] * B[q];
            }
        }
        for (int k = 0; k < NB; k++)
            tr += N[NB * k + k];
        for (int k = 0; k < NB; k++)
            N[NB * k + k] += LIGHT_RIDGE * tr / NB + 1e-12;
        s = fr_solve_spd(ctx, NB, 1, N, NB, r, NB);
        for (int j = 0; j < L->nt && !s; j++) {
            const double *B = L->tB + NCH * (size_t)j + NB * c;
            double pj = 0;
            for (int k = 0; k < NB; k++)
                pj += r[k] * B[k];
            L->tP[3 * (size_t)j + c] = pj, *mean += pj / 3 / L->nt;
        }
    }
    return s;
}

frig_status fr_sfs_pose_align(frig_ctx *ctx, const fr_sfs_mesh *m, fr_sfs_view *v, const float *vdisp, const float *tex,
                              const float *tex_w, int T, const fr_sfs_pose_align_options *o, double *turn_deg) {
    size_t n = (size_t)v->w * v->h;
    level L;
    memset(&L, 0, sizeof L);
    L.v = v, L.w_photo = o->w_photo;
    float *P = malloc(sizeof(float) * NCH * (n + 1));
    uint8_t *M = malloc(n + 1);
    double *scratch = malloc(sizeof(double) * (n + 1));
    double R0[9], t0[3];
    memcpy(R0, v->R, sizeof R0), memcpy(t0, v->t, sizeof t0);
    if (turn_deg) *turn_deg = 0;
    frig_status s = !P || !M || !scratch ? fr_nomem(ctx, "the pose alignment") : level_alloc(ctx, v, &L);
    /* drawn once: every level moves the same face points from the drawn pose (R0, t0) */
    if (!s) s = fr_sfs_view_render(ctx, m, v, R0, t0, vdisp);
    double face = s ? 0 : predict(m, v, tex, tex_w, T, P, M);
    double A[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}, I3[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}, tc[3];
    memcpy(tc, t0, sizeof tc);
    for (int lv = o->levels - 1; lv >= 0 && !s && face > 0; lv--) {
        L.sigma = o->sigma_px * ldexp(1.0, lv) * fmax(face / FACE_REF_PX, 0.25);
        L.d = L.sigma >= 4 ? (int)(L.sigma / 2) : 1;
        L.sigma_r = L.sigma / L.d;
        L.restricted = lv >= 2;
        s = build_grid(ctx, m, v, P, M, &L);
        if (s) break;
        if (lv == o->levels - 1) build_contour(m, v, &L);
        if (L.nt < MIN_TEMPLATE) continue;
        double mean = 0;
        s = fit_lighting(ctx, &L, A, tc, &mean);
        if (s == FRIG_ERR_NUMERIC) { /* no lighting explains the photo here: the level is skipped */
            frig_ctx_clear_error(ctx);
            s = FRIG_OK;
            continue;
        }
        if (s) break;
        L.sc = o->scale * fmax(mean, 0.03);
        /* the contour's residuals in pixels (scale: half the blur), all of them together weighing
         * o->w_contour times the photometric term's */
        L.csc = fmax(1.0, 0.5 * L.sigma);
        L.w_contour = L.nc ? o->w_contour * 3.0 * L.nt / L.nc * (o->w_photo > 0 ? o->w_photo : 1) : 0;
        double A0[9];
        memcpy(A0, A, sizeof A0);
        int taken = align_lm(ctx, &L, o->steps, A, tc, scratch);
        if (taken < 0) {
            s = frig_ctx_status(ctx) ? frig_ctx_status(ctx) : fr_nomem(ctx, "the pose alignment");
            break;
        }
        fr_log(ctx, FRIG_LOG_DEBUG,
               "sfs: pose registration of photo %zu, level %d (blur %.2f px, reduced %d): %d cells, %d contour "
               "points, %d steps, turn %.2f deg",
               v->photo, lv, L.sigma, L.d, L.nt, L.nc, taken, fr_rotation_angle_deg(A, A0));
    }
    if (!s) {
        double R[9], turn = fr_rotation_angle_deg(A, I3);
        if (!(turn <= o->max_deg)) memcpy(A, I3, sizeof A), memcpy(tc, t0, sizeof tc), turn = 0;
        if (turn_deg) *turn_deg = turn;
        fr_mat3_mul(A, R0, R);
        if (o->redraw) s = fr_sfs_view_render(ctx, m, v, R, tc, vdisp);
        else memcpy(v->R, R, sizeof v->R), memcpy(v->t, tc, sizeof v->t);
    }
    free(P), free(M), free(scratch);
    level_free(&L);
    return s;
}
