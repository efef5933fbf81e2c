/* Shape from shading from all photos at once in UV space (beyond the paper's per-photo
 * section 5.1; the integrable form of photometric stereo, cf. Woodham 1980 and multi-view
 * photometric stereo): the unknown is one displacement D(t) per face texel t along the rig's
 * normal, shared by all photos, so photo k sees the surface
 *     P_k(t) = X_k(t) + D(t) n_k(t)
 * (X_k, n_k: the rig at photo k's expression, head frame), whose normal N_k(t) comes from the
 * texel grid's central secants, centred on t and equal to n_k(t) at D = 0 (sfs_texel_normal.h).
 * Minimized by
 * Gauss-Newton with Levenberg-Marquardt damping:
 *     sum_k sum_t sum_c rho((a_c(t) S_kc(R_k N_k(t)) - I_kc(t)) / (sigma Ibar))
 *   + w_smooth sum |second differences of D|^2 + w_anchor sum D^2,
 * alternating with the albedo a(t) (closed form per texel) and each photo's lighting S_k (least
 * squares, eq. 5.3-5.5). One photo constrains a normal only along its light; photos under other
 * lights and head turns constrain the rest, and the shared displacement is integrable by
 * construction. The normal equations have the texel grid's small stencil (CHOLMOD, one analysis).
 * Options, off by default (docs/sfs.md has the measurements): the multi-view term (the photo's own
 * gradient along each texel's projected path, I(D) = I + dI/dD (D - D_sampled), so the photos
 * must agree on where the surface is as well as on its shading); the joint albedo (each texel's
 * albedo eliminated from the Gauss-Newton step by its Schur complement, which has the same
 * stencil, and recovered by back-substitution, instead of alternated with D); and each photo's
 * pose refined against the shared surface and albedo after each round (6 x 6 Levenberg-Marquardt,
 * the views drawn again at their new poses); and each photo's pose registered coarse to fine
 * (sfs_pose_align.c: blurred photometric and occluding-contour terms, a wider basin), the whole
 * pyramid before the first round and after it.
 * With a model (o->id_count > 0: sfs.identity_modes, 100 by default through frig_sfs_with_model; docs/sfs.md,
 * "The identity's modes in the shared solve") the model's first identity modes are unknowns too: the
 * surface is P_k(t) = X_k(t) + U(t) (beta - beta_s) + D(t) n_k(t), U the modes at the texel, the same
 * change in every expression, held by id_prior |(1 - c) fit's weights + beta|^2 (c =
 * sfs.identity_prior_centre, 1 by default: the prior centred at the fit's identity, whose landmarks and
 * outlines placed the features along the surface, where shading and stereo cannot see; docs/sfs.md).
 * In the first half of the rounds D is held by id_hold (sfs.displacement_hold, 100) instead of w_anchor
 * (0.05): D can make any smooth change of the surface along its normals nearly for free, the modes only
 * against their prior, so a free D took the in-span shape too and left the identity near the fit's
 * (docs/sfs.md, "The identity first"); held, the modes take it, and the later rounds leave D the rest.
 * Each texel's terms are also kept by its stencil points' head-frame positions (15 x 15, the albedo
 * eliminated from them too), so that the identity's M x M block is sum_t U^T A_t U and its coupling to D
 * sparse x dense; the step solves the damped D block for the coupling's M columns and the rhs, then the
 * identity's Schur complement. After each round the change is baked into the rig (the mesh's ident: every
 * view, the registration, the reference and the depth draw it), the photos' texel geometry and views
 * drawn again, beta_s = beta. */
#include <cblas.h>
#undef I /* complex.h's, through cblas.h: the views' images are I here */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/clock.h"
#include "core/context.h"
#include "core/floor_int.h"
#include "core/v2d.h"
#include "linalg/linalg.h"
#include "linalg/weighted_rows.h"
#include "model/mode_sums.h"
#include "raster/raster.h"
#include "raster/rotation.h"
#include "rig/rig.h"
#include "sfs/sfs_expression.h"
#include "sfs/sfs_multiview.h"
#include "sfs/sfs_pose_align.h"
#include "sfs/sfs_texel_normal.h"
#include "sparse/sparse.h"

#define TUKEY_C 4.685
#define INTENSITY_FLOOR 0.03
#define ALBEDO_RATIO 4.0 /* texels whose albedo is above this many times the first albedo's mean do not set the lighting */
#define VISIBLE_TOL 0.004
#define MIN_COS 0.25
#define MM 1e-3

enum { CPU_REGISTRATION, CPU_SAMPLING, CPU_SHAPE, CPU_LIGHTING, CPU_EXPRESSIONS, CPU_PARTS }; /* the log's parts */

void fr_sfs_multiview_options_default(fr_sfs_multiview_options *o) {
    o->outer = 3;
    o->iterations = 4;
    o->sigma = 0.03;
    o->w_smooth = 30.0;
    o->w_anchor = 0.05;
    o->max_mm = 12.0;
    o->w_stereo = 0.0;
    o->pose_steps = 0;
    o->joint_albedo = 0;
    o->pose_levels = 0;
    o->pose_sigma_px = 2.0;
    o->expression_steps = 0;
    o->expression_prior = 0.3;
    o->expression_sparse = 0.3;
    o->id_modes = NULL, o->id_count = 0, o->id_prior = 1.0, o->id_centre = 0, o->id_hold = 0, o->id_start = NULL;
    o->id_change = NULL;
}

/* One photo's view of the texels: the rig's texel points and normals at its expression, and
 * what the photo shows there. */
typedef struct photo_texels {
    float *X, *n;   /* 3 per texel, head frame */
    float *K;       /* 3 per texel: the normal's constant (sfs_texel_normal.h) */
    float *I;       /* 3 per texel */
    float *dI;      /* 3 per texel: d I / d D (per mm) through the projection (the multi-view term) */
    float *w;       /* per texel: 0 = not seen, else the view cosine */
    float *gP;      /* with identity modes, 9 per texel: d I_c / d P_q (per metre, head frame) through the projection */
} photo_texels;

/* Every texel's data terms over its stencil [t, left, right, up, down]: H (15 per texel: the upper
 * triangle, row by row), g (5), and for the joint albedo Haa (3), HaD (15: 3 x the stencil's 5) and
 * ga (3). */
#define HN (FR_SFS_STENCIL * (FR_SFS_STENCIL + 1) / 2)
#define NP (3 * FR_SFS_STENCIL)
#define NZ 9               /* the identity's derivative gathered per texel (ident_rows) */
#define HZ (NZ * (NZ + 1) / 2)
typedef struct texel_eqs {
    double *H, *g, *Haa, *HaD, *ga;
    /* with identity modes, by z (9, ident_rows: the stencil points' head-frame positions, per
     * metre, are E z): Z (the upper triangle of the Gauss-Newton matrix), Bz (5 x 9: D by z), gz (9),
     * Hz (3 x 9: albedo by z); after the albedo's elimination when it is joint */
    double *Z, *Bz, *gz, *Hz;
} texel_eqs;

typedef struct mv {
    const fr_sfs_mesh *m;
    const fr_sfs_uv *uv;
    fr_sfs_view *views;
    int nviews;
    const uint8_t *use;
    const fr_sfs_multiview_options *o;
    int nt;             /* texels */
    int *left, *right, *up, *down; /* neighbour texel numbers, -1 */
    fr_sfs_texel_grid grid;
    signed char *sign;  /* orientation of the grid's cross product against the normal */
    photo_texels *pt;
    double *D;          /* per texel, mm */
    double *D_s;        /* per texel: the displacement the photos were sampled at */
    double *D_try, *delta, *rhs;
    float *albedo;      /* 3 per texel */
    float *albedo_try;  /* 3 per texel */
    double albedo_cap[3]; /* per channel: texels above it do not set the lighting (albedo_cap()) */
    texel_eqs eq[2];    /* the texels' equations at D (eq[cur]) and at the tried step */
    int cur;
    size_t *damped;     /* per texel: its diagonal triplet holding w_anchor + mu */
    const fr_sfs_albedo *ps; /* the first albedo (its observation weights tell the well-seen texels) */
    fr_sfs_expression_grid eg; /* the expression step's shapes at the texels (o->expression_steps > 0) */
    int *eshape, *eoffset, *elist;
    float *edX;
    double *w0;         /* per view: the weights it started with (the expression step's prior) */
    double *e_texel;         /* per texel: its 3 energy terms (evaluate()) */
    int threads;
    /* identity modes (o->id_count > 0) */
    int M;              /* the model's modes solved for */
    double *U;          /* per texel 3 x M (row by row): the modes at the texel, metres */
    double *beta, *beta_s, *beta_try, *dbeta; /* the identity change (its weights): now, baked into the rig, tried, step */
    double *Xb;         /* 3 per texel: U (beta - beta_s) at the point evaluated (evaluate()) */
    double *dXb;        /* 3 per texel: U dbeta */
    double *C;          /* nt x (M + 1), column-major: D by identity (assemble()), then the rhs */
    double *Y;          /* nt x (M + 1): the damped D block's solutions */
    double *Hbb, *gb, *S; /* M x M, M, M x M */
    double dmean;       /* the D block's mean diagonal at the first assembly (the identity's damping scale) */
    double cpu_id[4];   /* CPU s: evaluations, the identity's assembly, the solves, the bakes (the log) */
    double w_anchor;    /* the round's anchor of D: o->id_hold in the first half of the rounds, else o->w_anchor */
} mv;

static void interp(const float *attr, const int32_t *tri, const float *b, double out[3]) {
    out[0] = out[1] = out[2] = 0;
    for (int c = 0; c < 3; c++)
        for (int q = 0; q < 3; q++) out[q] += b[c] * attr[3 * (size_t)tri[c] + q];
}

/* The photo's texel points and normals at its expression (head frame); with vd (may be NULL), the
 * rig kept for the view's next drawing with that displacement (fr_sfs_view_keep_rig). */
static frig_status photo_geometry(frig_ctx *ctx, mv *s, int k, const float *vd) {
    const fr_sfs_mesh *m = s->m;
    fr_sfs_view *v = &s->views[k];
    photo_texels *p = &s->pt[k];
    float *xyz = malloc(sizeof(float) * 3 * (size_t)m->nv), *nrm = malloc(sizeof(float) * 3 * (size_t)m->nv);
    if (!xyz || !nrm) {
        free(xyz), free(nrm);
        return fr_nomem(ctx, "the multi-view solve");
    }
    fr_sfs_mesh_eval(m, v->weights, xyz);
    fr_sfs_mesh_normals(m, xyz, nrm); /* the texels lie on face triangles */
    for (int t = 0; t < s->nt; t++) {
        const int32_t *tri = m->tris + 3 * (size_t)s->uv->tri[t];
        const float *b = s->uv->bary + 3 * (size_t)t;
        double X[3], n[3];
        interp(xyz, tri, b, X);
        interp(nrm, tri, b, n);
        double l = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        for (int q = 0; q < 3; q++) p->X[3 * t + q] = (float)X[q], p->n[3 * t + q] = (float)(l > 0 ? n[q] / l : 0);
    }
    if (vd) fr_sfs_view_keep_rig(m, v, vd, xyz, nrm);
    free(xyz), free(nrm);
    return FRIG_OK;
}

/* Photo k's normal constants (its texel points and normals, the grid's orientation). */
static void photo_base(mv *s, int k) {
    photo_texels *p = &s->pt[k];
    for (int t = 0; t < s->nt; t++) fr_sfs_normal_base(&s->grid, p->X, p->n, s->sign[t], t, p->K + 3 * (size_t)t);
}

/* What photo k shows at each texel's displaced point (visibility from the rig's render). */
static void photo_sample(mv *s, int k) {
    const fr_sfs_view *v = &s->views[k];
    photo_texels *p = &s->pt[k];
    for (int t = 0; t < s->nt; t++) {
        p->w[t] = 0;
        double P[3], X[3], xy[2];
        for (int q = 0; q < 3; q++) P[q] = p->X[3 * t + q] + s->D[t] * MM * p->n[3 * t + q];
        fr_mat3_apply(v->R, P, X);
        for (int q = 0; q < 3; q++) X[q] += v->t[q];
        if (!fr_camera_project(&v->cam, X, xy)) continue;
        int px = fr_floor_int(xy[0] + 0.5), py = fr_floor_int(xy[1] + 0.5);
        if (px < 0 || py < 0 || px >= v->w || py >= v->h) continue;
        size_t i = (size_t)py * v->w + px;
        if (!v->skin[i] || !v->face[i] || !(v->zbuf[i] > 0) || X[2] > v->zbuf[i] + VISIBLE_TOL) continue;
        double nc[3], nh[3] = {p->n[3 * t], p->n[3 * t + 1], p->n[3 * t + 2]};
        fr_mat3_apply(v->R, nh, nc);
        double ray[3] = {X[0], X[1], X[2]}, rl = sqrt(X[0] * X[0] + X[1] * X[1] + X[2] * X[2]);
        double cosv = -(nc[0] * ray[0] + nc[1] * ray[1] + nc[2] * ray[2]) / rl;
        if (cosv < MIN_COS) continue;
        double smp[3];
        fr_bilinear3(v->I, v->w, v->h, xy, smp);
        for (int c = 0; c < 3; c++) p->I[3 * (size_t)t + c] = (float)smp[c], p->dI[3 * (size_t)t + c] = 0;
        if (s->o->w_stereo > 0) {
            /* the image's gradient along the texel's projected path as D changes */
            double J[6], gx[3], gy[3];
            fr_camera_project_jacobian(&v->cam, X, J);
            fr_sfs_image_gradient(v->I, v->w, v->h, xy, gx, gy);
            double du = MM * (J[0] * nc[0] + J[1] * nc[1] + J[2] * nc[2]);
            double dv = MM * (J[3] * nc[0] + J[4] * nc[1] + J[5] * nc[2]);
            for (int c = 0; c < 3; c++) p->dI[3 * (size_t)t + c] = (float)(s->o->w_stereo * (gx[c] * du + gy[c] * dv));
            if (p->gP) /* by head-frame position: the projection's Jacobian through R */
                for (int q = 0; q < 3; q++) {
                    double ju = J[0] * v->R[q] + J[1] * v->R[3 + q] + J[2] * v->R[6 + q];
                    double jv = J[3] * v->R[q] + J[4] * v->R[3 + q] + J[5] * v->R[6 + q];
                    for (int c = 0; c < 3; c++) p->gP[9 * (size_t)t + 3 * c + q] = (float)(s->o->w_stereo * (gx[c] * ju + gy[c] * jv));
                }
        }
        p->w[t] = (float)(cosv * v->photo_weight);
    }
}

/* The displaced surface's unit normal at texel t in photo k (head frame; sfs_texel_normal.h),
 * and its derivatives by D over t's stencil [t, left, right, up, down] (each 3, per mm; a missing
 * neighbour's part is t's). Returns 0 when t has no normal. */
static int texel_normal_at(const mv *s, const double *D, const double *Xb, int k, int t, double N[3],
                           double dN[FR_SFS_STENCIL][3], double sec[7]) {
    int e[4];
    if (!fr_sfs_secant_ends(&s->grid, t, e)) return 0;
    const photo_texels *p = &s->pt[k];
    double P[4][3], ex[3], ey[3], c[3];
    for (int a = 0; a < 4; a++)
        for (int q = 0; q < 3; q++)
            P[a][q] = p->X[3 * (size_t)e[a] + q] + D[e[a]] * MM * p->n[3 * (size_t)e[a] + q] + (Xb ? Xb[3 * (size_t)e[a] + q] : 0);
    for (int q = 0; q < 3; q++) ex[q] = P[1][q] - P[0][q], ey[q] = P[3][q] - P[2][q];
    fr_sfs_cross(ex, ey, c);
    double sg = s->sign[t];
    const float *K = p->K + 3 * (size_t)t;
    for (int q = 0; q < 3; q++) c[q] = sg * c[q] + K[q];
    double l = sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
    if (!(l > 0)) return 0;
    for (int q = 0; q < 3; q++) N[q] = c[q] / l;
    if (sec) {
        for (int q = 0; q < 3; q++) sec[q] = ex[q], sec[3 + q] = ey[q];
        sec[6] = l;
    }
    if (!dN) return 1;
    /* dc/dD at the ends: s (d ex x ey + ex x d ey); d ex = -n_left, n_right; d ey = -n_up, n_down (per mm) */
    double dc[FR_SFS_STENCIL][3];
    memset(dc, 0, sizeof dc);
    for (int a = 0; a < 4; a++) {
        const float *na = p->n + 3 * (size_t)e[a];
        double f = a % 2 ? MM : -MM, v[3] = {f * na[0], f * na[1], f * na[2]}, x[3];
        if (a < 2) fr_sfs_cross(v, ey, x);
        else fr_sfs_cross(ex, v, x);
        int slot = fr_sfs_end_slot(&s->grid, t, a);
        for (int q = 0; q < 3; q++) dc[slot][q] += sg * x[q];
    }
    for (int j = 0; j < FR_SFS_STENCIL; j++) {
        double proj = dc[j][0] * N[0] + dc[j][1] * N[1] + dc[j][2] * N[2];
        for (int q = 0; q < 3; q++) dN[j][q] = (dc[j][q] - proj * N[q]) / l;
    }
    return 1;
}

static int texel_normal(const mv *s, const double *D, int k, int t, double N[3], double dN[FR_SFS_STENCIL][3]) {
    return texel_normal_at(s, D, NULL, k, t, N, dN, NULL);
}

double fr_sfs_tukey_w(double u) {
    u /= TUKEY_C;
    return fabs(u) < 1 ? (1 - u * u) * (1 - u * u) : 0;
}

double fr_sfs_tukey_rho(double u) {
    double c2 = TUKEY_C * TUKEY_C;
    if (fabs(u) >= TUKEY_C) return c2 / 6.0;
    double q = 1 - (u / TUKEY_C) * (u / TUKEY_C);
    return c2 / 6.0 * (1 - q * q * q);
}

/* Shading of photo v for head-frame normal N, and its gradient by N (per channel, 3). */
void fr_sfs_shade_head(const fr_sfs_view *v, const double N[3], double S[3], double G[3][3]) {
    double nc[3], y[FR_SH_COUNT], dy[3 * FR_SH_COUNT], e[3], g[3][3];
    fr_mat3_apply(v->R, N, nc);
    if (G) fr_sh_basis_gradient(nc, y, dy);
    else fr_sh_basis(nc, y);
    /* channels 0 and 1 side by side in the lanes of a pair, channel 2 alone: each channel's sums
     * over k as one channel's loop would take them */
    v2d e01 = {0, 0}, g01[3] = {{0, 0}, {0, 0}, {0, 0}};
    double e2 = 0, g2[3] = {0, 0, 0};
    for (int k = 0; k < FR_SH_COUNT; k++) {
        v2d s01 = {v->sh[0][k], v->sh[1][k]}, yk = {y[k], y[k]};
        double s2 = v->sh[2][k];
        e01 = e01 + s01 * yk, e2 += s2 * y[k];
        if (G)
            for (int q = 0; q < 3; q++) {
                v2d d = {dy[3 * k + q], dy[3 * k + q]};
                g01[q] = g01[q] + s01 * d, g2[q] += s2 * dy[3 * k + q];
            }
    }
    e[0] = e01[0], e[1] = e01[1], e[2] = e2;
    for (int q = 0; q < 3; q++) g[0][q] = g01[q][0], g[1][q] = g01[q][1], g[2][q] = g2[q];
    for (int c = 0; c < 3; c++) {
        S[c] = e[c] > 0 ? e[c] : 0;
        if (G)
            for (int q = 0; q < 3; q++) /* d/dN of S(R N) = R^T g */
                G[c][q] = e[c] > 0 ? v->R[q] * g[c][0] + v->R[3 + q] * g[c][1] + v->R[6 + q] * g[c][2] : 0;
    }
}

/* What photo k shows at texel t for displacement D(t), linearized about the sampled one. */
static void observed(const mv *s, const photo_texels *p, const double *D, int t, double I[3]) {
    double dd = D[t] - s->D_s[t];
    for (int c = 0; c < 3; c++) I[c] = p->I[3 * (size_t)t + c] + p->dI[3 * (size_t)t + c] * dd;
}

/* The same with the identity change's offset Xb at the texels (NULL: none). */
static void observed_at(const mv *s, const photo_texels *p, const double *D, const double *Xb, int t, double I[3]) {
    observed(s, p, D, t, I);
    if (!Xb || !p->gP) return;
    const double *x = Xb + 3 * (size_t)t;
    const float *gp = p->gP + 9 * (size_t)t;
    for (int c = 0; c < 3; c++) I[c] += gp[3 * c] * x[0] + gp[3 * c + 1] * x[1] + gp[3 * c + 2] * x[2];
}

static double obs_scale(const mv *s, const float *I) {
    double m = (I[0] + I[1] + I[2]) / 3.0;
    return s->o->sigma * (m > INTENSITY_FLOOR ? m : INTENSITY_FLOOR);
}

static int curv(const mv *s, int t, int dir, int nb[3]) {
    /* t is the middle: its left/up neighbour links to it and it links right/down */
    const int *link = dir ? s->down : s->right;
    int next = link[t];
    if (next < 0) return 0;
    /* the previous texel: the one whose link is t (found through the texel grid) */
    int T = s->uv->size, tx = s->uv->texel[t] % T, ty = s->uv->texel[t] / T;
    int px = dir ? tx : tx - 1, py = dir ? ty - 1 : ty;
    if (px < 0 || py < 0) return 0;
    int prev = s->uv->index[py * T + px];
    if (prev < 0 || link[prev] != t) return 0;
    nb[0] = prev, nb[1] = t, nb[2] = next;
    return 1;
}

/* The identity's derivative by the stencil points' positions (15: 5 points x 3) is E z with z
 * (9) = the derivative by the horizontal secant's end (+ right, - left), by the vertical one's
 * (+ down, - up), and by the centre (the stereo term), E fixed per texel (its rows hold at most
 * three of +-1): texel t's rows of E, as columns and coefficients. */
static void ident_rows(const mv *s, int t, int nnz[NP], int col[NP][3], double cf[NP][3]) {
    int slot[4];
    for (int a = 0; a < 4; a++) slot[a] = fr_sfs_end_slot(&s->grid, t, a);
    for (int r = 0; r < NP; r++) {
        int pt = r / 3, q = r % 3, n = 0;
        double cx = (pt == slot[1]) - (pt == slot[0]), cy = (pt == slot[3]) - (pt == slot[2]);
        if (cx != 0) col[r][n] = q, cf[r][n++] = cx;
        if (cy != 0) col[r][n] = 3 + q, cf[r][n++] = cy;
        if (pt == 0) col[r][n] = 6 + q, cf[r][n++] = 1.0;
        nnz[r] = n;
    }
}

/* E^T x for x given at the texels (3 per texel): z's change when the stencil's points of t move by
 * x (u: t's stencil). */
static void ident_z(const mv *s, int t, const int u[FR_SFS_STENCIL], const double *x, double z[NZ]) {
    int nnz[NP], col[NP][3];
    double cf[NP][3];
    ident_rows(s, t, nnz, col, cf);
    memset(z, 0, NZ * sizeof *z);
    for (int r = 0; r < NP; r++) {
        if (!nnz[r] || u[r / 3] < 0) continue;
        double v = x[3 * (size_t)u[r / 3] + r % 3];
        for (int k = 0; k < nnz[r]; k++) z[col[r][k]] += cf[r][k] * v;
    }
}

/* y[i] += a x[i], i < n: two entries at a time (the same operations per entry). */
static inline void axpy_run(double *y, double a, const double *x, int n) {
    v2d aa = {a, a};
    int i = 0;
    for (; i + 2 <= n; i += 2) {
        v2d yv, xv;
        memcpy(&yv, y + i, sizeof yv), memcpy(&xv, x + i, sizeof xv);
        yv = yv + aa * xv;
        memcpy(y + i, &yv, sizeof yv);
    }
    if (i < n) y[i] += a * x[i];
}

/* y[i] += a0 x0[i], then a1 x1[i], then a2 x2[i] (three axpy_run passes in one), i < n. */
static inline void axpy3_run(double *y, double a0, double a1, double a2, const double *x0, const double *x1,
                             const double *x2, int n) {
    v2d b0 = {a0, a0}, b1 = {a1, a1}, b2 = {a2, a2};
    int i = 0;
    for (; i + 2 <= n; i += 2) {
        v2d yv, v0, v1, v2;
        memcpy(&yv, y + i, sizeof yv), memcpy(&v0, x0 + i, sizeof v0), memcpy(&v1, x1 + i, sizeof v1);
        memcpy(&v2, x2 + i, sizeof v2);
        yv = yv + b0 * v0, yv = yv + b1 * v1, yv = yv + b2 * v2;
        memcpy(y + i, &yv, sizeof yv);
    }
    if (i < n) y[i] = y[i] + a0 * x0[i] + a1 * x1[i] + a2 * x2[i];
}

/* Per texel at displacement D and albedo: the 6 Hessian entries and 3 gradient entries of its
 * data terms (all photos); with the joint albedo, the texel's albedo eliminated (its Schur
 * complement has the same stencil) and its terms kept for the back-substitution; and the data
 * energy (its robust terms summed photo by photo, channel by channel). */
static double texel_normal_equations(const mv *s, const double *D, const double *Xb, const float *albedo, int t,
                                     const texel_eqs *eqs) {
    enum { NS = FR_SFS_STENCIL };
    double *H = eqs->H + HN * (size_t)t, *g = eqs->g + NS * (size_t)t, e = 0;
    memset(H, 0, HN * sizeof *H), memset(g, 0, NS * sizeof *g);
    double *Haa = eqs->Haa + 3 * (size_t)t, *HaD = eqs->HaD + 3 * NS * (size_t)t, *ga = eqs->ga + 3 * (size_t)t;
    memset(Haa, 0, 3 * sizeof *Haa), memset(HaD, 0, 3 * NS * sizeof *HaD), memset(ga, 0, 3 * sizeof *ga);
    int id = s->M > 0;
    double *Z = NULL, *Bz = NULL, *gz = NULL, *Hz = NULL; /* the identity's terms by z (ident_rows) */
    if (id) {
        Z = eqs->Z + HZ * (size_t)t, Bz = eqs->Bz + NS * NZ * (size_t)t, gz = eqs->gz + NZ * (size_t)t;
        Hz = eqs->Hz + 3 * NZ * (size_t)t;
        memset(Z, 0, HZ * sizeof *Z), memset(Bz, 0, NS * NZ * sizeof *Bz), memset(gz, 0, NZ * sizeof *gz);
        memset(Hz, 0, 3 * NZ * sizeof *Hz);
    }
    double N[3], dN[NS][3], S[3], G[3][3], sec[7];
    for (int k = 0; k < s->nviews; k++) {
        const photo_texels *p = &s->pt[k];
        if (!s->use[k] || !(p->w[t] > 0) || !texel_normal_at(s, D, Xb, k, t, N, dN, sec)) continue;
        fr_sfs_shade_head(&s->views[k], N, S, G);
        double I[3];
        observed_at(s, p, D, Xb, t, I);
        double sc = obs_scale(s, p->I + 3 * (size_t)t);
        double j[3][NS], wj[3][NS], z[3][NZ], wz[3][NZ]; /* per channel: derivatives, and times the weight */
        for (int c = 0; c < 3; c++) {
            double a = albedo[3 * t + c], r = (a * S[c] - I[c]) / sc, w = p->w[t] * fr_sfs_tukey_w(r);
            e += p->w[t] * fr_sfs_tukey_rho(r);
            double *jc = j[c];
            for (int q = 0; q < NS; q++) jc[q] = a / sc * (G[c][0] * dN[q][0] + G[c][1] * dN[q][1] + G[c][2] * dN[q][2]);
            jc[0] -= p->dI[3 * (size_t)t + c] / sc;
            for (int q = 0; q < NS; q++) wj[c][q] = w * jc[q];
            for (int q = 0; q < NS; q++) g[q] += w * jc[q] * r;
            double ja = S[c] / sc;
            Haa[c] += w * ja * ja, ga[c] += w * ja * r;
            axpy_run(HaD + NS * c, w * ja, jc, NS);
            if (!id) continue;
            /* by the stencil points' positions: N = c / |c|, c = s (ex x ey) + K, ex = P(right) - P(left),
             * ey = P(down) - P(up); d r / d c = a / sc (G - (G.N) N) / |c| =: gn, so d r / d P(right) =
             * s ey x gn (minus that at the left), d r / d P(down) = s gn x ex (minus that at the top);
             * and the stereo term at the centre: z = (ey x gn, gn x ex, -dI/dP / sc) */
            double *zc = z[c], gn[3], f = a / sc * s->sign[t] / sec[6];
            double gN = G[c][0] * N[0] + G[c][1] * N[1] + G[c][2] * N[2];
            for (int q = 0; q < 3; q++) gn[q] = f * (G[c][q] - gN * N[q]);
            fr_sfs_cross(sec + 3, gn, zc);
            fr_sfs_cross(gn, sec, zc + 3);
            for (int q = 0; q < 3; q++) zc[6 + q] = p->gP ? -p->gP[9 * (size_t)t + 3 * c + q] / sc : 0.0;
            for (int q = 0; q < NZ; q++) {
                double wq = wz[c][q] = w * zc[q];
                gz[q] += wq * r;
                Hz[NZ * c + q] += wq * ja;
            }
        }
        /* H, Z and Bz (shared by the channels): each entry takes the three channels' terms in turn */
        for (int q = 0, h = 0; q < NS; h += NS - q, q++)
            axpy3_run(H + h, wj[0][q], wj[1][q], wj[2][q], j[0] + q, j[1] + q, j[2] + q, NS - q);
        if (!id) continue;
        for (int q = 0, h = 0; q < NZ; h += NZ - q, q++)
            axpy3_run(Z + h, wz[0][q], wz[1][q], wz[2][q], z[0] + q, z[1] + q, z[2] + q, NZ - q);
        for (int q = 0; q < NS; q++) axpy3_run(Bz + NZ * q, wj[0][q], wj[1][q], wj[2][q], z[0], z[1], z[2], NZ);
    }
    if (!s->o->joint_albedo)
        return e;
    for (int c = 0; c < 3; c++) {
        if (!(Haa[c] > 0)) continue;
        Haa[c] *= 1 + 1e-6;
        const double *h = HaD + NS * c, inv = 1.0 / Haa[c];
        for (int q = 0, k = 0; q < NS; q++)
            for (int b = q; b < NS; b++, k++) H[k] -= h[q] * h[b] * inv;
        for (int q = 0; q < NS; q++) g[q] -= h[q] * ga[c] * inv;
        if (!id) continue;
        const double *hz = Hz + NZ * c;
        for (int q = 0, k = 0; q < NZ; q++)
            for (int b = q; b < NZ; b++, k++) Z[k] -= hz[q] * hz[b] * inv;
        for (int q = 0; q < NS; q++)
            for (int b = 0; b < NZ; b++) Bz[NZ * q + b] -= h[q] * hz[b] * inv;
        for (int q = 0; q < NZ; q++) gz[q] -= hz[q] * ga[c] * inv;
    }
    return e;
}

/* The energy at (D, albedo) and, into q, every texel's equations there (one pass: an accepted
 * step's equations are the next step's): each texel's terms in parallel (3 per texel: data +
 * anchor, the two curvatures, 0 where a texel has none), summed in texel order (the same value
 * whatever the thread count). */
/* U_t (b - base) per texel into out (3 per texel; base NULL: zeros). */
static void ident_offsets(const mv *s, const double *b, const double *base, double *out) {
    int M = s->M;
#pragma omp parallel for schedule(static) num_threads(s->threads)
    for (int t = 0; t < s->nt; t++) {
        const double *u = s->U + 3 * (size_t)M * t;
        for (int q = 0; q < 3; q++) {
            double x = 0;
            for (int m = 0; m < M; m++) x += u[M * q + m] * (base ? b[m] - base[m] : b[m]);
            out[3 * (size_t)t + q] = x;
        }
    }
}

/* Where the identity prior's centre leaves the start, in mode m: the prior holds start + change at
 * id_centre times the start, that is (1 - id_centre) start + change at 0. */
static double prior_offset(const fr_sfs_multiview_options *o, int m) {
    return o->id_start ? (1.0 - o->id_centre) * o->id_start[m] : 0;
}

/* The identity prior's energy at change b. */
static double ident_prior(const mv *s, const double *b) {
    double e = 0;
    for (int m = 0; m < s->M; m++) {
        double x = prior_offset(s->o, m) + b[m];
        e += x * x;
    }
    return s->o->id_prior * e;
}

static double evaluate_at(const mv *s, const double *D, const double *beta, const float *albedo, const texel_eqs *q) {
    double *et = s->e_texel, *Xb = NULL;
    if (s->M > 0 && beta) {
        ident_offsets(s, beta, s->beta_s, s->Xb);
        Xb = s->Xb;
    }
#pragma omp parallel for schedule(dynamic, 64) num_threads(s->threads)
    for (int t = 0; t < s->nt; t++) {
        et[3 * (size_t)t] = texel_normal_equations(s, D, Xb, albedo, t, q) + s->w_anchor * D[t] * D[t];
        int nb[3];
        for (int dir = 0; dir < 2; dir++) {
            et[3 * (size_t)t + 1 + dir] = 0;
            if (curv(s, t, dir, nb)) {
                double c = D[nb[0]] - 2 * D[nb[1]] + D[nb[2]];
                et[3 * (size_t)t + 1 + dir] = s->o->w_smooth * c * c;
            }
        }
    }
    double e = 0;
    for (size_t k = 0; k < 3 * (size_t)s->nt; k++)
        e += et[k];
    if (s->M > 0 && beta) e += ident_prior(s, beta);
    return e;
}

static double evaluate(const mv *s, const double *D, const float *albedo, const texel_eqs *q) {
    return evaluate_at(s, D, s->M > 0 ? s->beta : NULL, albedo, q);
}

/* The albedo step that goes with the displacement step (back-substitution). */
static void albedo_step(mv *s, const double *dD) {
    for (int t = 0; t < s->nt; t++) {
        int u[FR_SFS_STENCIL];
        double dz[NZ]; /* the identity's step at the stencil's points, by z (the same for the channels) */
        fr_sfs_stencil(&s->grid, t, u);
        if (s->M > 0) ident_z(s, t, u, s->dXb, dz);
        for (int c = 0; c < 3; c++) {
            const texel_eqs *q = &s->eq[s->cur];
            double v = s->albedo[3 * t + c], Haa = q->Haa[3 * (size_t)t + c];
            if (Haa > 0) {
                const double *h = q->HaD + 3 * FR_SFS_STENCIL * (size_t)t + FR_SFS_STENCIL * c;
                double x = q->ga[3 * (size_t)t + c];
                for (int a = 0; a < FR_SFS_STENCIL; a++)
                    if (u[a] >= 0) x += h[a] * dD[u[a]];
                if (s->M > 0) { /* and the identity's step */
                    const double *hz = q->Hz + 3 * NZ * (size_t)t + NZ * c;
                    for (int k = 0; k < NZ; k++) x += hz[k] * dz[k];
                }
                v -= x / Haa;
            }
            s->albedo_try[3 * t + c] = (float)(v > 0 ? v : 0);
        }
    }
}

static frig_status add(frig_ctx *ctx, fr_triplets *t, int a, int b, double v) {
    return a >= b ? fr_triplets_add(ctx, t, a, b, v) : fr_triplets_add(ctx, t, b, a, v);
}

/* The system at D from the texels' equations there (eq[cur], evaluate()) and the priors. */
static frig_status assemble(frig_ctx *ctx, mv *s, double mu, fr_triplets *tr) {
    const texel_eqs *eq = &s->eq[s->cur];
    fr_triplets_clear(tr);
    memset(s->rhs, 0, sizeof(double) * (size_t)s->nt);
    frig_status st = FRIG_OK;
    for (int t = 0; t < s->nt && !st; t++) {
        const double *H = eq->H + HN * (size_t)t;
        int u[FR_SFS_STENCIL], e[4];
        fr_sfs_stencil(&s->grid, t, u);
        if (fr_sfs_secant_ends(&s->grid, t, e)) {
            for (int a = 0; a < FR_SFS_STENCIL; a++)
                if (u[a] >= 0) s->rhs[u[a]] -= eq->g[FR_SFS_STENCIL * (size_t)t + a];
            for (int a = 0, h = 0; a < FR_SFS_STENCIL && !st; a++)
                for (int b = a; b < FR_SFS_STENCIL && !st; b++, h++)
                    if (u[a] >= 0 && u[b] >= 0) st = add(ctx, tr, u[a], u[b], H[h]);
        }
        s->damped[t] = tr->count;
        if (!st) st = add(ctx, tr, t, t, s->w_anchor + mu);
        s->rhs[t] -= s->w_anchor * s->D[t];
        int nb[3];
        for (int dir = 0; dir < 2 && !st; dir++) {
            if (!curv(s, t, dir, nb)) continue;
            static const double k3[3] = {1, -2, 1};
            double c = s->D[nb[0]] - 2 * s->D[nb[1]] + s->D[nb[2]];
            for (int a = 0; a < 3 && !st; a++) {
                s->rhs[nb[a]] -= s->o->w_smooth * k3[a] * c;
                for (int b = 0; b <= a && !st; b++) st = add(ctx, tr, nb[a], nb[b], s->o->w_smooth * k3[a] * k3[b]);
            }
        }
    }
    return st;
}

/* out[m] += sum over i < n of coef[i] rows[M i + m] (the terms of coef[i] == 0 left out), m < M,
 * the terms added in order of i (fr_add_weighted_rows). */
static void combine_rows(const double *coef, const double *rows, int n, int M, double *out) {
    double cf[NZ];
    const double *rp[NZ];
    int k = 0;
    for (int i = 0; i < n; i++)
        if (coef[i] != 0) cf[k] = coef[i], rp[k++] = rows + (size_t)M * i;
    fr_add_weighted_rows(cf, rp, k, M, out);
}

/* A root R of a texel's identity block Z (NZ x NZ, symmetric, positive semi-definite: weighted
 * outer products less the albedo's Schur complement): Z = R^T R with R = sqrt(D) L^T from
 * Z = L D L^T, pivots under a relative 1e-12 (rounding) taken as zero, so V^T Z V = (R V)^T (R V)
 * and the texels' blocks add up by one symmetric rank-k product. R row by row into out. */
static void z_root(const double *Z, double *out) {
    double L[NZ * NZ], d[NZ], top = 0;
    for (int i = 0; i < NZ; i++) top = fmax(top, Z[NZ * i + i]);
    memset(L, 0, sizeof L);
    for (int j = 0; j < NZ; j++) {
        double dj = Z[NZ * j + j];
        for (int k = 0; k < j; k++) dj -= L[NZ * j + k] * L[NZ * j + k] * d[k];
        d[j] = dj > 1e-12 * top ? dj : 0.0;
        L[NZ * j + j] = 1.0;
        for (int i = j + 1; i < NZ; i++) {
            double x = Z[NZ * i + j];
            for (int k = 0; k < j; k++) x -= L[NZ * i + k] * L[NZ * j + k] * d[k];
            L[NZ * i + j] = d[j] > 0 ? x / d[j] : 0.0;
        }
    }
    for (int j = 0; j < NZ; j++) { /* row j of R: sqrt(d_j) times column j of L */
        double r = sqrt(d[j]);
        for (int i = 0; i < NZ; i++) out[NZ * j + i] = r * L[NZ * i + j];
    }
}

/* The identity's equations at the current point from the texels' (eq[cur]): C = H_Db (nt x M),
 * Hbb = sum_t V^T Z V with V = E^T U over each texel's stencil points (9 x M: U's rows at the
 * points combined as z combines them, ident_rows), gb, with the prior's terms (energy
 * id_prior |start + beta|^2). Texel order, one thread: the same sums whatever the thread count. */
static void assemble_ident(mv *s) {
    enum { NS = FR_SFS_STENCIL, CHUNK = 256 };
    const texel_eqs *eq = &s->eq[s->cur];
    int M = s->M;
    size_t nt = (size_t)s->nt;
    double *Cr = s->Y; /* C row by row first (each texel's M together), then into C's columns */
    memset(Cr, 0, sizeof(double) * nt * (size_t)M);
    memset(s->Hbb, 0, sizeof(double) * (size_t)M * M), memset(s->gb, 0, sizeof(double) * (size_t)M);
    /* a chunk of texels' V (9 rows per texel) and R V (z_root) */
    double *Vr = malloc(sizeof(double) * NZ * CHUNK * (size_t)M), *Wr = malloc(sizeof(double) * NZ * CHUNK * (size_t)M);
    if (!Vr || !Wr) { /* no identity step this time */
        free(Vr), free(Wr);
        for (int m = 0; m < M; m++) s->Hbb[(size_t)M * m + m] = 1e30;
        return;
    }
    int rows = 0; /* texels in the chunk */
    for (int t = 0; t <= s->nt; t++) {
        if (rows == CHUNK || (t == s->nt && rows)) { /* Hbb += (R V)^T (R V) over the chunk */
            cblas_dsyrk(CblasRowMajor, CblasUpper, CblasTrans, M, NZ * rows, 1.0, Wr, M, 1.0, s->Hbb, M);
            rows = 0;
        }
        if (t == s->nt) break;
        int u[NS], e[4], nnz[NP], col[NP][3];
        double cf[NP][3];
        fr_sfs_stencil(&s->grid, t, u);
        if (!fr_sfs_secant_ends(&s->grid, t, e)) continue;
        ident_rows(s, t, nnz, col, cf);
        const double *Z = eq->Z + HZ * (size_t)t, *Bz = eq->Bz + NS * NZ * (size_t)t, *gz = eq->gz + NZ * (size_t)t;
        double *vr = Vr + (size_t)NZ * M * rows, *wr = Wr + (size_t)NZ * M * rows, Zf[NZ * NZ];
        for (int q = 0, h = 0; q < NZ; q++)
            for (int b = q; b < NZ; b++, h++) Zf[NZ * q + b] = Zf[NZ * b + q] = Z[h];
        memset(vr, 0, sizeof(double) * NZ * (size_t)M);
        for (int r = 0; r < NP; r++) {
            if (!nnz[r] || u[r / 3] < 0) continue;
            const double *x = s->U + 3 * (size_t)M * u[r / 3] + (size_t)M * (r % 3);
            for (int k = 0; k < nnz[r]; k++) {
                double *v = vr + (size_t)M * col[r][k], c = cf[r][k];
                for (int m = 0; m < M; m++) v[m] += c * x[m];
            }
        }
        double R[NZ * NZ];
        z_root(Zf, R);
        for (int i = 0; i < NZ; i++) {
            double *w = wr + (size_t)M * i;
            memset(w, 0, sizeof(double) * (size_t)M);
            combine_rows(R + NZ * i, vr, NZ, M, w);
            const double *x = vr + (size_t)M * i;
            for (int m = 0; m < M; m++) s->gb[m] += x[m] * gz[i];
        }
        rows++;
        /* C's rows at the stencil: Bz (5 x 9) V */
        for (int a = 0; a < NS; a++) {
            if (u[a] < 0) continue;
            combine_rows(Bz + NZ * a, vr, NZ, M, Cr + (size_t)M * u[a]);
        }
    }
    for (size_t t = 0; t < nt; t++)
        for (int m = 0; m < M; m++) s->C[nt * m + t] = Cr[(size_t)M * t + m];
    for (int m = 0; m < M; m++) /* the upper triangle dsyrk filled, mirrored */
        for (int m2 = 0; m2 < m; m2++) s->Hbb[(size_t)M * m + m2] = s->Hbb[(size_t)M * m2 + m];
    for (int m = 0; m < M; m++) {
        s->Hbb[(size_t)M * m + m] += 2 * s->o->id_prior;
        s->gb[m] += 2 * s->o->id_prior * (prior_offset(s->o, m) + s->beta[m]);
    }
    free(Vr), free(Wr);
}

/* The joint step with the identity: the damped D block K (factored in ch) solved for C's columns
 * and the rhs, the identity's Schur complement Hbb + damping - C^T K^-1 C solved for dbeta, and
 * the displacement's step back-substituted (into s->delta). */
static frig_status solve_ident(frig_ctx *ctx, mv *s, fr_cholesky *ch, double mu) {
    int M = s->M;
    size_t nt = (size_t)s->nt;
    memcpy(s->C + nt * (size_t)M, s->rhs, sizeof(double) * nt);
    frig_status st = fr_cholesky_solve(ctx, ch, M + 1, s->C, s->Y);
    if (st) return st;
    const double *y = s->Y + nt * (size_t)M;
    double lam = mu / (s->dmean > 0 ? s->dmean : 1);
    /* dbeta's rhs -gb - C^T y, and S = Hbb - C^T K^-1 C (C and Y column-major, nt x M): its upper
     * triangle (row-major, as S is read) by one product, mirrored */
    for (int m = 0; m < M; m++) s->dbeta[m] = -s->gb[m];
    cblas_dgemv(CblasColMajor, CblasTrans, (int)nt, M, -1.0, s->C, (int)nt, y, 1, 1.0, s->dbeta, 1);
    memcpy(s->S, s->Hbb, sizeof(double) * (size_t)M * M);
    cblas_dgemm(CblasColMajor, CblasTrans, CblasNoTrans, M, M, (int)nt, -1.0, s->Y, (int)nt, s->C, (int)nt, 1.0,
                s->S, M);
    for (int m = 0; m < M; m++) {
        for (int m2 = m + 1; m2 < M; m2++) s->S[(size_t)M * m2 + m] = s->S[(size_t)M * m + m2];
        s->S[(size_t)M * m + m] += lam * s->Hbb[(size_t)M * m + m];
    }
    st = fr_solve_spd(ctx, M, 1, s->S, M, s->dbeta, M); /* S symmetric: its row-major layout is LAPACK's */
    if (st == FRIG_ERR_NUMERIC) { /* not positive definite at this damping: no identity step this try */
        frig_ctx_clear_error(ctx);
        st = FRIG_OK;
        memset(s->dbeta, 0, sizeof(double) * (size_t)M);
    }
    if (st) return st;
    memcpy(s->delta, y, sizeof(double) * nt); /* delta = y - Y dbeta */
    cblas_dgemv(CblasColMajor, CblasNoTrans, (int)nt, M, -1.0, s->Y, (int)nt, s->dbeta, 1, 1.0, s->delta, 1);
    return FRIG_OK;
}

/* The identity change baked into the rig: the mesh's per-vertex change from beta, every used
 * photo's texel geometry and normal constants again, each view drawn again (with the
 * displacement) for the visibility of the next sampling unless the round's pose step draws it
 * (redraw 0); beta_s = beta. */
static frig_status ident_bake(frig_ctx *ctx, mv *s, int redraw) {
    const fr_sfs_mesh *m = s->m;
    size_t n3 = 3 * (size_t)m->nv;
    fr_mode_sum(n3, NULL, s->o->id_modes, n3, s->M, NULL, s->beta, NULL, m->ident);
    memcpy(s->beta_s, s->beta, sizeof(double) * (size_t)s->M);
    int T = s->uv->size;
    float *disp = calloc((size_t)T * T, sizeof(float)), *vd = malloc(sizeof(float) * ((size_t)m->nv + 1));
    frig_status st = !disp || !vd ? fr_nomem(ctx, "the identity change") : FRIG_OK;
    for (int t = 0; t < s->nt && !st; t++) disp[s->uv->texel[t]] = (float)(s->D[t] * MM);
    if (!st) st = fr_sfs_vertex_displacement(ctx, m, disp, T, vd);
    int failed = 0;
#pragma omp parallel for schedule(dynamic, 1) num_threads(s->threads)
    for (int k = 0; k < s->nviews; k++) {
        if (!s->use[k] || st) continue;
        frig_ctx child;
        fr_ctx_init_child(&child, ctx);
        double R[9], t[3];
        memcpy(R, s->views[k].R, sizeof R), memcpy(t, s->views[k].t, sizeof t);
        if (photo_geometry(&child, s, k, redraw ? vd : NULL) ||
            (redraw && fr_sfs_view_render(&child, m, &s->views[k], R, t, vd)))
            failed = 1;
        else photo_base(s, k);
    }
    if (failed && !st) st = fr_nomem(ctx, "the identity change");
    free(disp), free(vd);
    double rms = 0, b2 = 0;
    int nf = 0;
    for (int v = 0; v < m->nv; v++)
        if (m->face_vertex[v]) {
            for (int q = 0; q < 3; q++) rms += (double)m->ident[3 * (size_t)v + q] * m->ident[3 * (size_t)v + q];
            nf++;
        }
    for (int k = 0; k < s->M; k++) b2 += s->beta[k] * s->beta[k];
    fr_log(ctx, FRIG_LOG_DEBUG, "sfs: identity change |dbeta| %.3f, RMS %.3f mm over the face's vertices, prior %.1f",
           sqrt(b2), 1e3 * sqrt(rms / (nf ? nf : 1)), ident_prior(s, s->beta));
    return st;
}

/* The damping alone changed: the triplets assemble() would give at the same D with this mu. */
static void set_damping(mv *s, double mu, fr_triplets *tr) {
    for (int t = 0; t < s->nt; t++) tr->x[s->damped[t]] = s->w_anchor + mu;
}

/* Photo k's observation of texel t for the albedo: the shading S of its normal at D (the rig's
 * where it has none), what it shows there I, its scale sc and weight pw; 0 when k does not see t. */
static int albedo_obs(const mv *s, int k, int t, double S[3], double I[3], double *sc, double *pw) {
    const photo_texels *p = &s->pt[k];
    if (!s->use[k] || !(p->w[t] > 0)) return 0;
    double N[3];
    if (!texel_normal(s, s->D, k, t, N, NULL))
        for (int q = 0; q < 3; q++) N[q] = p->n[3 * t + q];
    fr_sfs_shade_head(&s->views[k], N, S, NULL);
    observed(s, p, s->D, t, I);
    *sc = obs_scale(s, p->I + 3 * (size_t)t);
    *pw = p->w[t];
    return 1;
}

/* One observation's terms of texel t's albedo (pass 1: Tukey-weighted at the albedo now). */
static void albedo_terms(const mv *s, int t, int pass, const double S[3], const double I[3], double sc, double pw,
                         double num[3], double den[3]) {
    for (int c = 0; c < 3; c++) {
        double w = pw / (sc * sc);
        if (pass) w *= fr_sfs_tukey_w((s->albedo[3 * t + c] * S[c] - I[c]) / sc);
        num[c] += w * S[c] * I[c], den[c] += w * S[c] * S[c];
    }
}

/* Albedo of each texel given the displacement: a_c = sum w S I / sum w S^2 (robust). The photos'
 * observations are found once for both passes (each thread's ob: 8 per photo; without it, again). */
static void update_albedo(mv *s, int threads) {
#pragma omp parallel num_threads(threads)
    {
        double *ob = malloc(sizeof(double) * 8 * ((size_t)s->nviews + 1));
#pragma omp for schedule(dynamic, 64)
        for (int t = 0; t < s->nt; t++) {
            int n = 0; /* observations kept in ob */
            for (int pass = 0; pass < 2; pass++) {
                double num[3] = {0, 0, 0}, den[3] = {0, 0, 0}, S[3], I[3], sc, pw;
                if (pass && ob)
                    for (int j = 0; j < n; j++) {
                        const double *o = ob + 8 * (size_t)j;
                        albedo_terms(s, t, pass, o, o + 3, o[6], o[7], num, den);
                    }
                else
                    for (int k = 0; k < s->nviews; k++) {
                        if (!albedo_obs(s, k, t, S, I, &sc, &pw)) continue;
                        albedo_terms(s, t, pass, S, I, sc, pw, num, den);
                        if (!ob) continue;
                        double *o = ob + 8 * (size_t)n++;
                        memcpy(o, S, sizeof S), memcpy(o + 3, I, sizeof I), o[6] = sc, o[7] = pw;
                    }
                for (int c = 0; c < 3; c++)
                    if (den[c] > 0) s->albedo[3 * t + c] = (float)(num[c] / den[c]);
            }
        }
        free(ob);
    }
}

/* Per channel ALBEDO_RATIO times the mean of the first albedo (Algorithm 5's) over the texels. */
static void albedo_cap(const mv *s, double cap[3]) {
    cap[0] = cap[1] = cap[2] = 0;
    for (int t = 0; t < s->nt; t++)
        for (int c = 0; c < 3; c++) cap[c] += s->ps->albedo[3 * (size_t)s->uv->texel[t] + c];
    for (int c = 0; c < 3; c++) cap[c] = ALBEDO_RATIO * fmax(cap[c] / (s->nt ? s->nt : 1), INTENSITY_FLOOR);
}

/* Whether texel t's albedo is under the cap in every channel. */
static int albedo_plausible(const mv *s, int t, const double cap[3]) {
    return s->albedo[3 * t] <= cap[0] && s->albedo[3 * t + 1] <= cap[1] && s->albedo[3 * t + 2] <= cap[2];
}

/* Photo k's lighting refitted on the displaced surface and the texel albedo. Texels whose albedo
 * is far above the first albedo's mean are left out: where every photo shades a texel nearly
 * black (S -> 0 at the edge of a light) the albedo update's I / S grows without bound, and the
 * lighting refitted on such texels shrank a whole channel round after round (five LFW photos:
 * blue albedo 1e8, the lighting's 1e-7, no point kept). The albedo itself is left free: it also
 * takes the highlights a photo or two show, and capping it moved the poses (tests/test_sfs.c). */
static void update_lighting(mv *s, int k, frig_ctx *ctx) {
    const photo_texels *p = &s->pt[k];
    const double *cap = s->albedo_cap;
    int n = 0;
    for (int t = 0; t < s->nt; t++) n += p->w[t] > 0 && albedo_plausible(s, t, cap);
    if (n < 50) return;
    float *I = malloc(sizeof(float) * 3 * (size_t)n), *a = malloc(sizeof(float) * 3 * (size_t)n);
    float *nc = malloc(sizeof(float) * 3 * (size_t)n), *w = malloc(sizeof(float) * (size_t)n);
    if (I && a && nc && w) {
        int j = 0;
        for (int t = 0; t < s->nt; t++) {
            if (!(p->w[t] > 0) || !albedo_plausible(s, t, cap)) continue;
            double N[3], c[3];
            if (!texel_normal(s, s->D, k, t, N, NULL))
                for (int q = 0; q < 3; q++) N[q] = p->n[3 * t + q];
            fr_mat3_apply(s->views[k].R, N, c);
            for (int q = 0; q < 3; q++)
                I[3 * j + q] = p->I[3 * t + q], a[3 * j + q] = s->albedo[3 * t + q], nc[3 * j + q] = (float)c[q];
            w[j++] = p->w[t];
        }
        fr_sfs_fit_lighting(ctx, n, NULL, I, a, nc, w, s->views[k].sh);
    }
    free(I), free(a), free(nc), free(w);
}

/* A texel's part of the pose term that does not depend on the pose: its unit normal and displaced
 * point (head frame); ok 0 when it has no weight or normal. */
typedef struct pose_texel {
    double N[3], P[3];
    int ok;
} pose_texel;

/* The pose steps read every POSE_STRIDE-th texel: six unknowns need far fewer than a face's
 * thousands, and at 2 the clouds of four frig synth subjects were as good as with all of them
 * while the steps cost half (docs/sfs.md, "Eight rounds of one iteration"). */
#define POSE_STRIDE 2

/* Photo k's pose_texel for each texel into pt: update_pose's every evaluation reads them (the
 * same floats as computing them in each); texels between the strides are not read. */
static void pose_texels(const mv *s, int k, pose_texel *pt) {
    const photo_texels *p = &s->pt[k];
    for (int t = 0; t < s->nt; t += POSE_STRIDE) {
        pose_texel *x = &pt[t];
        x->ok = p->w[t] > 0 && texel_normal(s, s->D, k, t, x->N, NULL);
        if (!x->ok) continue;
        for (int c = 0; c < 3; c++) x->P[c] = p->X[3 * t + c] + s->D[t] * MM * p->n[3 * t + c];
    }
}

/* Photo k's pose term at (R, tv): the robust energy of its texels (every POSE_STRIDE-th) against
 * the shared surface and albedo, sampling the photo at each texel's projection; with H (6 x 6,
 * row-major) and g (6) when H is given, for the perturbation R' = exp([w]) R, t' = t + dt (w about
 * the head's origin in camera axes). */
static double pose_terms(const mv *s, int k, const pose_texel *pt, const double R[9], const double tv[3], double *H,
                         double *g) {
    const fr_sfs_view *v = &s->views[k];
    const photo_texels *p = &s->pt[k];
    if (H) memset(H, 0, 36 * sizeof *H), memset(g, 0, 6 * sizeof *g);
    double e = 0;
    for (int t = 0; t < s->nt; t += POSE_STRIDE) {
        double q[3], Xc[3], xy[2];
        if (!pt[t].ok) continue;
        const double *N = pt[t].N, *P = pt[t].P;
        fr_mat3_apply(R, P, q);
        for (int c = 0; c < 3; c++) Xc[c] = q[c] + tv[c];
        if (!fr_camera_project(&v->cam, Xc, xy)) continue;
        if (xy[0] < 1 || xy[1] < 1 || xy[0] > v->w - 2 || xy[1] > v->h - 2) continue;
        double I[3], S[3], nc[3], y[FR_SH_COUNT], dy[3 * FR_SH_COUNT];
        fr_bilinear3(v->I, v->w, v->h, xy, I);
        fr_mat3_apply(R, N, nc);
        if (H) fr_sh_basis_gradient(nc, y, dy);
        else fr_sh_basis(nc, y); /* the same y */
        double sc = s->o->sigma * fmax((I[0] + I[1] + I[2]) / 3.0, INTENSITY_FLOOR);
        double gx[3], gy[3], J[6];
        if (H) {
            fr_sfs_image_gradient(v->I, v->w, v->h, xy, gx, gy);
            fr_camera_project_jacobian(&v->cam, Xc, J);
        }
        for (int c = 0; c < 3; c++) {
            double sh = 0, gc[3] = {0, 0, 0};
            for (int j = 0; j < FR_SH_COUNT; j++) {
                sh += v->sh[c][j] * y[j];
                if (H)
                    for (int d = 0; d < 3; d++) gc[d] += v->sh[c][j] * dy[3 * j + d];
            }
            S[c] = sh > 0 ? sh : 0;
            double a = s->albedo[3 * t + c], r = (a * S[c] - I[c]) / sc;
            e += p->w[t] * fr_sfs_tukey_rho(r);
            if (!H) continue;
            double u[3], jr[6], w = p->w[t] * fr_sfs_tukey_w(r);
            if (!(w > 0)) continue;
            for (int d = 0; d < 3; d++) u[d] = J[d] * gx[c] + J[3 + d] * gy[c];
            if (!(sh > 0)) gc[0] = gc[1] = gc[2] = 0;
            /* d(a S)/dw = a (nc x gc), dI/dw = q x u, dI/dt = u */
            for (int d = 0; d < 3; d++) {
                int d1 = (d + 1) % 3, d2 = (d + 2) % 3;
                jr[d] = (a * (nc[d1] * gc[d2] - nc[d2] * gc[d1]) - (q[d1] * u[d2] - q[d2] * u[d1])) / sc;
                jr[3 + d] = -u[d] / sc;
            }
            for (int i = 0; i < 6; i++) { /* H's lower triangle: all update_pose's Cholesky reads */
                g[i] += w * jr[i] * r;
                for (int j = 0; j <= i; j++) H[6 * i + j] += w * jr[i] * jr[j];
            }
        }
    }
    return e;
}

/* A few Levenberg-Marquardt steps of photo k's pose against the shared surface and albedo; 0 when
 * out of memory (the pose unchanged). */
static int update_pose(mv *s, int k, int steps) {
    fr_sfs_view *v = &s->views[k];
    double R[9], tv[3], H[36], g[6], mu = 1e-3;
    pose_texel *pt = malloc(sizeof(pose_texel) * ((size_t)s->nt + 1));
    if (!pt) return 0;
    pose_texels(s, k, pt);
    memcpy(R, v->R, sizeof R), memcpy(tv, v->t, sizeof tv);
    double e = pose_terms(s, k, pt, R, tv, NULL, NULL);
    for (int it = 0; it < steps; it++) {
        pose_terms(s, k, pt, R, tv, H, g);
        int done = 0;
        for (int tries = 0; tries < 6 && !done; tries++) {
            double A[36], b[6];
            memcpy(A, H, sizeof A);
            for (int i = 0; i < 6; i++) A[7 * i] += mu * (H[7 * i] > 0 ? H[7 * i] : 1), b[i] = -g[i];
            /* Cholesky of the 6 x 6 */
            int ok = 1;
            for (int i = 0; i < 6 && ok; i++) {
                for (int j = 0; j <= i; j++) {
                    double x = A[6 * i + j];
                    for (int q = 0; q < j; q++) x -= A[6 * i + q] * A[6 * j + q];
                    if (i == j) {
                        if (!(x > 0)) ok = 0;
                        else A[6 * i + i] = sqrt(x);
                    } else A[6 * i + j] = x / A[6 * j + j];
                }
            }
            if (!ok) {
                mu *= 10;
                continue;
            }
            for (int i = 0; i < 6; i++) {
                for (int q = 0; q < i; q++) b[i] -= A[6 * i + q] * b[q];
                b[i] /= A[6 * i + i];
            }
            for (int i = 5; i >= 0; i--) {
                for (int q = i + 1; q < 6; q++) b[i] -= A[6 * q + i] * b[q];
                b[i] /= A[6 * i + i];
            }
            double dR[9], R2[9], t2[3];
            fr_rotation_from_axis_angle(b, dR);
            fr_mat3_mul(dR, R, R2);
            for (int c = 0; c < 3; c++) t2[c] = tv[c] + b[3 + c];
            double e2 = pose_terms(s, k, pt, R2, t2, NULL, NULL);
            if (e2 < e) {
                memcpy(R, R2, sizeof R), memcpy(tv, t2, sizeof tv);
                e = e2, mu *= 0.3, done = 1;
            } else mu *= 10;
        }
        if (!done) break;
    }
    memcpy(v->R, R, sizeof R), memcpy(v->t, tv, sizeof tv);
    free(pt);
    return 1;
}

static int cmp_float(const void *x, const void *y) {
    float a = *(const float *)x, b = *(const float *)y;
    return (a > b) - (a < b);
}

static void mv_free(mv *s) {
    for (int k = 0; s->pt && k < s->nviews; k++) free(s->pt[k].X), free(s->pt[k].n), free(s->pt[k].I), free(s->pt[k].w), free(s->pt[k].dI);
    for (int k = 0; s->pt && k < s->nviews; k++) free(s->pt[k].K), free(s->pt[k].gP);
    free(s->pt), free(s->left), free(s->right), free(s->up), free(s->down), free(s->sign), free(s->D), free(s->D_s), free(s->D_try), free(s->delta), free(s->rhs);
    for (int b = 0; b < 2; b++)
        free(s->eq[b].H), free(s->eq[b].g), free(s->eq[b].Haa), free(s->eq[b].HaD), free(s->eq[b].ga), free(s->eq[b].Z),
            free(s->eq[b].Bz), free(s->eq[b].gz), free(s->eq[b].Hz);
    free(s->U), free(s->beta), free(s->beta_s), free(s->beta_try), free(s->dbeta), free(s->Xb), free(s->dXb), free(s->C), free(s->Y);
    free(s->Hbb), free(s->gb), free(s->S);
    free(s->albedo), free(s->albedo_try), free(s->damped), free(s->e_texel);
    free(s->eshape), free(s->eoffset), free(s->elist), free(s->edX), free(s->w0);
}

/* The expression step's grid: each rig shape's delta at the texels, the shapes that move the face
 * by more than 0.1 mm somewhere; and every view's starting weights. */
static frig_status expression_init(frig_ctx *ctx, mv *s) {
    const fr_sfs_mesh *m = s->m;
    const frig_rig *rig = m->rig;
    size_t n3 = 3 * (size_t)m->nv, nt = (size_t)s->nt;
    s->eshape = malloc(sizeof(int) * ((size_t)m->shapes + 1));
    s->edX = malloc(sizeof(float) * 3 * nt * ((size_t)m->shapes + 1));
    s->w0 = malloc(sizeof(double) * ((size_t)m->shapes * s->nviews + 1));
    if (!s->eshape || !s->edX || !s->w0) return fr_nomem(ctx, "the expression step");
    for (int k = 0; k < s->nviews; k++)
        memcpy(s->w0 + (size_t)m->shapes * k, s->views[k].weights, sizeof(double) * m->shapes);
    int na = 0;
    for (int j = 0; j < m->shapes; j++) {
        float *d = s->edX + 3 * nt * (size_t)na, big = 0;
        const float *delta = rig->deltas + n3 * (size_t)j;
        for (size_t t = 0; t < nt; t++) {
            const int32_t *tri = m->tris + 3 * (size_t)s->uv->tri[t];
            const float *b = s->uv->bary + 3 * t;
            for (int q = 0; q < 3; q++) {
                double x = 0;
                for (int c = 0; c < 3; c++) x += b[c] * delta[3 * (size_t)tri[c] + q];
                d[3 * t + q] = (float)x, big = fabsf((float)x) > big ? fabsf((float)x) : big;
            }
        }
        if (big > 1e-4f) s->eshape[na++] = j;
    }
    /* per texel, the shapes that move it or its grid neighbours by more than a micrometre (most
     * shapes are local; the rest count as still there) */
    s->eoffset = malloc(sizeof(int) * (nt + 1));
    if (!s->eoffset) return fr_nomem(ctx, "the expression step");
    size_t count = 0;
    for (int pass = 0; pass < 2; pass++) {
        count = 0;
        for (size_t t = 0; t < nt; t++) {
            s->eoffset[t] = (int)count;
            int u[FR_SFS_STENCIL];
            fr_sfs_stencil(&s->grid, (int)t, u);
            for (int j = 0; j < na; j++) {
                int moves = 0;
                for (int c = 0; c < FR_SFS_STENCIL && !moves; c++) {
                    const float *d = u[c] >= 0 ? s->edX + 3 * (nt * (size_t)j + (size_t)u[c]) : NULL;
                    moves = d && fabsf(d[0]) + fabsf(d[1]) + fabsf(d[2]) > 1e-6f;
                }
                if (moves && pass) s->elist[count] = j;
                count += moves;
            }
        }
        s->eoffset[nt] = (int)count;
        if (!pass && !(s->elist = malloc(sizeof(int) * (count + 1)))) return fr_nomem(ctx, "the expression step");
    }
    /* texel-major for the step (each texel's shapes side by side: one stream through memory) */
    float *tm = malloc(sizeof(float) * 3 * nt * ((size_t)na + 1));
    if (!tm) return fr_nomem(ctx, "the expression step");
    for (int j = 0; j < na; j++)
        for (size_t t = 0; t < nt; t++)
            memcpy(tm + 3 * (t * (size_t)na + (size_t)j), s->edX + 3 * (nt * (size_t)j + t), 3 * sizeof(float));
    free(s->edX);
    s->edX = tm;
    fr_log(ctx, FRIG_LOG_DEBUG, "sfs: expression step: %d shapes, %.1f per texel", na, (double)count / (nt ? nt : 1));
    s->eg = (fr_sfs_expression_grid){s->nt, s->grid, s->sign, m->shapes, na, s->eshape, s->edX, s->eoffset, s->elist};
    return FRIG_OK;
}

/* Every photo's expression weights refined against its pixels with the shared surface, albedo
 * and its lighting held (sfs_expression.c); its texel geometry and its view drawn again at them. */
static frig_status expression_step(frig_ctx *ctx, mv *s, int threads, int redraw) {
    int T = s->uv->size;
    size_t TT = (size_t)T * T;
    float *disp = calloc(TT, sizeof(float)), *vd = malloc(sizeof(float) * ((size_t)s->m->nv + 1));
    frig_status st = !disp || !vd ? fr_nomem(ctx, "the expression step") : FRIG_OK;
    for (int t = 0; t < s->nt && !st; t++) disp[s->uv->texel[t]] = (float)(s->D[t] * MM);
    if (!st) st = fr_sfs_vertex_displacement(ctx, s->m, disp, T, vd);
    fr_sfs_expression_options eo = {s->o->expression_steps, s->o->sigma, s->o->expression_prior,
                                    s->o->expression_sparse, s->o->w_stereo > 0};
    int failed = 0;
    double moved = 0, gain = 0;
    int photos = 0;
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads) reduction(+ : moved, gain, photos)
    for (int k = 0; k < s->nviews; k++) {
        if (!s->use[k] || st) continue;
        frig_ctx child;
        fr_ctx_init_child(&child, ctx);
        fr_sfs_view *v = &s->views[k];
        const photo_texels *p = &s->pt[k];
        fr_sfs_expression_photo ep = {p->X, p->n, p->K, p->I, p->w, s->D, s->albedo};
        double before[256], change = 0;
        int na = s->eg.active < 256 ? s->eg.active : 256;
        for (int j = 0; j < na; j++) before[j] = v->weights[s->eshape[j]];
        fr_sfs_expression_refine(&child, &s->eg, &ep, v, s->w0 + (size_t)s->m->shapes * k, &eo, &change);
        double d = 0;
        for (int j = 0; j < na; j++) d += fabs(v->weights[s->eshape[j]] - before[j]);
        moved += d, gain += change, photos++;
        double R[9], t[3];
        memcpy(R, v->R, sizeof R), memcpy(t, v->t, sizeof t);
        /* without redraw the pose step that follows draws the view again itself */
        /* the drawing that follows (here or in the pose step) is with vd at these weights */
        if (photo_geometry(&child, s, k, vd) || (redraw && fr_sfs_view_render(&child, s->m, v, R, t, vd)))
            failed = 1;
        else
            photo_base(s, k);
    }
    if (failed && !st) st = fr_nomem(ctx, "the expression step");
    fr_log(ctx, FRIG_LOG_DEBUG,
           "sfs: expression step: %d photos, weights moved by %.4f (sum |dw|) and the energy by %.2f%% on average", photos,
           photos ? moved / photos : 0, photos ? 100 * gain / photos : 0);
    free(disp), free(vd);
    return st;
}

/* The albedo the registration draws (T x T, with a weight per texel): the texels' albedo where
 * photos saw it well, an observation weight above a fifth of the median's and a plausible value
 * (texels seen rarely or at grazing angles carry wild colours). */
static void registration_texture(const mv *s, float *tex, float *tex_w) {
    double wmed = 0;
    float *ws = malloc(sizeof(float) * ((size_t)s->nt + 1));
    if (ws) {
        int n = 0;
        for (int t = 0; t < s->nt; t++)
            if (s->ps->weight[s->uv->texel[t]] > 0) ws[n++] = s->ps->weight[s->uv->texel[t]];
        qsort(ws, (size_t)n, sizeof *ws, cmp_float);
        wmed = n ? ws[n / 2] : 0;
        free(ws);
    }
    for (int t = 0; t < s->nt; t++) {
        size_t q = (size_t)s->uv->texel[t];
        int sane = 1;
        for (int c = 0; c < 3; c++) {
            float a = s->albedo[3 * t + c];
            tex[3 * q + c] = a, sane &= a > 0.005f && a < 1.5f;
        }
        tex_w[q] = sane && s->ps->weight[q] > 0.2 * wmed;
    }
}

/* Every photo's pose against the shared surface: registered coarse to fine (o->pose_levels), then
 * 'steps' Levenberg-Marquardt steps of the shading term; each view drawn again at its pose (the
 * visibility that the next sampling reads). */
static frig_status joint_pose(frig_ctx *ctx, mv *s, int threads, int steps, int levels) {
    int T = s->uv->size;
    size_t TT = (size_t)T * T;
    float *disp = calloc(TT, sizeof(float)), *vd = malloc(sizeof(float) * ((size_t)s->m->nv + 1));
    /* the registration's albedo: only for a round that registers */
    float *tex = levels > 0 ? calloc(3 * TT, sizeof(float)) : NULL;
    float *tex_w = levels > 0 ? calloc(TT, sizeof(float)) : NULL;
    frig_status st = !disp || !vd || (levels > 0 && (!tex || !tex_w)) ? fr_nomem(ctx, "the joint pose") : FRIG_OK;
    for (int t = 0; t < s->nt && !st; t++) disp[s->uv->texel[t]] = (float)(s->D[t] * MM);
    if (tex && tex_w && !st) registration_texture(s, tex, tex_w);
    if (!st) st = fr_sfs_vertex_displacement(ctx, s->m, disp, T, vd);
    fr_sfs_pose_align_options ao;
    fr_sfs_pose_align_options_default(&ao);
    ao.levels = levels, ao.sigma_px = s->o->pose_sigma_px;
    ao.redraw = steps <= 0; /* with pose steps the view is drawn after them */
    int failed = 0;
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
    for (int k = 0; k < s->nviews; k++) {
        if (!s->use[k] || st) continue;
        frig_ctx child;
        fr_ctx_init_child(&child, ctx);
        if (ao.levels > 0 && fr_sfs_pose_align(&child, s->m, &s->views[k], vd, tex, tex_w, T, &ao, NULL)) failed = 1;
        if (steps <= 0) continue;
        if (!update_pose(s, k, steps)) failed = 1;
        double R[9], t[3];
        memcpy(R, s->views[k].R, sizeof R), memcpy(t, s->views[k].t, sizeof t);
        if (fr_sfs_view_render(&child, s->m, &s->views[k], R, t, vd)) failed = 1;
    }
    if (failed && !st) st = fr_nomem(ctx, "the joint pose");
    free(disp), free(vd), free(tex), free(tex_w);
    return st;
}

frig_status fr_sfs_multiview(frig_ctx *ctx, const fr_sfs_mesh *m, const fr_sfs_uv *uv, fr_sfs_view *views, int nviews,
                             const uint8_t *use, const fr_sfs_multiview_options *o, fr_sfs_albedo *ps, float *disp) {
    mv s;
    memset(&s, 0, sizeof s);
    s.ps = ps, s.m = m, s.uv = uv, s.views = views, s.nviews = nviews, s.use = use, s.o = o, s.nt = uv->count;
    s.w_anchor = o->w_anchor;
    albedo_cap(&s, s.albedo_cap);
    int T = uv->size, threads = fr_threads(ctx);
    size_t nt = (size_t)s.nt + 1;
    s.pt = calloc((size_t)nviews + 1, sizeof *s.pt);
    s.left = malloc(sizeof(int) * nt), s.right = malloc(sizeof(int) * nt), s.up = malloc(sizeof(int) * nt);
    s.down = malloc(sizeof(int) * nt), s.sign = malloc(nt);
    s.grid = (fr_sfs_texel_grid){s.left, s.right, s.up, s.down};
    s.D = calloc(nt, sizeof(double)), s.D_s = calloc(nt, sizeof(double)), s.D_try = malloc(sizeof(double) * nt), s.delta = malloc(sizeof(double) * 3 * nt);
    s.rhs = malloc(sizeof(double) * nt), s.albedo = malloc(sizeof(float) * 3 * nt);
    s.albedo_try = malloc(sizeof(float) * 3 * nt);
    int eq_ok = 1;
    for (int b = 0; b < 2; b++) {
        texel_eqs *q = &s.eq[b];
        q->H = malloc(sizeof(double) * HN * nt), q->g = malloc(sizeof(double) * FR_SFS_STENCIL * nt);
        q->Haa = malloc(sizeof(double) * 3 * nt), q->HaD = malloc(sizeof(double) * 3 * FR_SFS_STENCIL * nt);
        q->ga = malloc(sizeof(double) * 3 * nt);
        eq_ok &= q->H && q->g && q->Haa && q->HaD && q->ga;
    }
    if (o->id_count > 0 && o->id_modes && m->ident) {
        int M = s.M = o->id_count;
        for (int b = 0; b < 2; b++) {
            texel_eqs *q = &s.eq[b];
            q->Z = malloc(sizeof(double) * HZ * nt), q->Bz = malloc(sizeof(double) * FR_SFS_STENCIL * NZ * nt);
            q->gz = malloc(sizeof(double) * NZ * nt), q->Hz = malloc(sizeof(double) * 3 * NZ * nt);
            eq_ok &= q->Z && q->Bz && q->gz && q->Hz;
        }
        s.U = malloc(sizeof(double) * 3 * (size_t)M * nt);
        s.beta = calloc((size_t)M, sizeof(double)), s.beta_s = calloc((size_t)M, sizeof(double));
        s.beta_try = calloc((size_t)M, sizeof(double)), s.dbeta = calloc((size_t)M, sizeof(double));
        s.Xb = calloc(3 * nt, sizeof(double)), s.dXb = calloc(3 * nt, sizeof(double));
        s.C = malloc(sizeof(double) * nt * (size_t)(M + 1)), s.Y = malloc(sizeof(double) * nt * (size_t)(M + 1));
        s.Hbb = malloc(sizeof(double) * (size_t)M * M), s.gb = malloc(sizeof(double) * (size_t)M);
        s.S = malloc(sizeof(double) * (size_t)M * M);
        eq_ok &= s.U && s.beta && s.beta_s && s.beta_try && s.dbeta && s.Xb && s.dXb && s.C && s.Y && s.Hbb && s.gb && s.S;
        /* the modes at the texels, interpolated as the rig's points are; the rig starts with no change */
        size_t n3 = 3 * (size_t)m->nv;
        memset(m->ident, 0, sizeof(float) * n3);
        for (int t = 0; t < s.nt && eq_ok; t++) {
            const int32_t *tri = m->tris + 3 * (size_t)uv->tri[t];
            const float *b = uv->bary + 3 * (size_t)t;
            for (int k = 0; k < M; k++) {
                double x[3];
                interp(o->id_modes + n3 * (size_t)k, tri, b, x);
                for (int q = 0; q < 3; q++) s.U[3 * (size_t)M * t + (size_t)M * q + k] = x[q];
            }
        }
    }
    s.damped = malloc(sizeof(size_t) * nt), s.e_texel = malloc(sizeof(double) * 3 * nt), s.threads = threads;
    frig_status st = !s.pt || !s.left || !s.right || !s.up || !s.down || !s.sign || !s.D || !s.D_s || !s.D_try || !s.delta || !s.rhs ||
                             !eq_ok || !s.albedo || !s.albedo_try || !s.damped || !s.e_texel
                         ? fr_nomem(ctx, "the multi-view solve")
                         : FRIG_OK;
    for (int k = 0; k < nviews && !st; k++) {
        photo_texels *p = &s.pt[k];
        if (!use[k]) continue;
        p->X = malloc(sizeof(float) * 3 * nt), p->n = malloc(sizeof(float) * 3 * nt);
        p->I = malloc(sizeof(float) * 3 * nt), p->w = calloc(nt, sizeof(float));
        p->dI = calloc(3 * nt, sizeof(float)), p->K = calloc(3 * nt, sizeof(float));
        if (s.M > 0) p->gP = calloc(9 * nt, sizeof(float));
        if (!p->X || !p->n || !p->I || !p->w || !p->dI || !p->K || (s.M > 0 && !p->gP)) st = fr_nomem(ctx, "the multi-view solve");
    }
    for (int t = 0; t < s.nt && !st; t++) {
        int x = uv->texel[t] % T, y = uv->texel[t] / T;
        s.left[t] = x > 0 ? uv->index[y * T + x - 1] : -1;
        s.right[t] = x + 1 < T ? uv->index[y * T + x + 1] : -1;
        s.up[t] = y > 0 ? uv->index[(y - 1) * T + x] : -1;
        s.down[t] = y + 1 < T ? uv->index[(y + 1) * T + x] : -1;
        for (int q = 0; q < 3; q++) s.albedo[3 * t + q] = ps->albedo[3 * (size_t)uv->texel[t] + q];
    }
    int failed = 0;
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
    for (int k = 0; k < nviews; k++)
        if (use[k] && !st && photo_geometry(ctx, &s, k, NULL)) failed = 1;
    if (failed && !st) st = fr_nomem(ctx, "the multi-view solve");
    /* the grid's orientation against the rig's neutral normals (the first used photo's) */
    int k0 = 0;
    while (k0 < nviews && !use[k0]) k0++;
    for (int t = 0; t < s.nt && !st; t++)
        s.sign[t] = k0 < nviews ? fr_sfs_grid_sign(&s.grid, s.pt[k0].X, s.pt[k0].n, t) : 1;
    for (int k = 0; k < nviews && !st; k++)
        if (use[k]) photo_base(&s, k);
    fr_triplets tr;
    memset(&tr, 0, sizeof tr);
    fr_cholesky *ch = NULL;
    if (!st) st = fr_triplets_init(ctx, &tr, s.nt, s.nt, (size_t)s.nt * 32);
    if (!st && o->expression_steps > 0) st = expression_init(ctx, &s);
    /* the photos registered to the rig and the first albedo before the first round */
    double cpu[CPU_PARTS] = {0}, c0 = fr_cpu_seconds(), c1; /* the log's CPU seconds by part */
    if (o->pose_levels > 0 && !st && k0 < nviews) st = joint_pose(ctx, &s, threads, 0, o->pose_levels);
    c1 = fr_cpu_seconds(), cpu[CPU_REGISTRATION] += c1 - c0, c0 = c1;
    for (int outer = 0; outer < o->outer && !st && k0 < nviews; outer++) {
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
        for (int k = 0; k < nviews; k++)
            if (use[k]) photo_sample(&s, k);
        /* the identity first: D held in the first half of the rounds, so that the modes make what they can
         * of the shape (their prior is against the fit's identity, D's anchor nearly free), then D the rest */
        s.w_anchor = s.M > 0 && o->id_hold > 0 && outer < o->outer / 2 ? o->id_hold : o->w_anchor;
        memcpy(s.D_s, s.D, sizeof(double) * (size_t)s.nt);
        update_albedo(&s, threads);
        s.cur = 0;
        c1 = fr_cpu_seconds(), cpu[CPU_SAMPLING] += c1 - c0, c0 = c1;
        double e = evaluate(&s, s.D, s.albedo, &s.eq[0]), mu = -1;
        fr_log(ctx, FRIG_LOG_DEBUG, "sfs: shared shape round %d starts at energy %.6g", outer + 1, e);
        int assembled = 0; /* tr and rhs hold the equations at the current D (albedo, lighting) */
        for (int it = 0; it < o->iterations && !st; it++) {
            for (int tries = 0; tries < 5 && !st; tries++) {
                if (!assembled) {
                    st = assemble(ctx, &s, 0.0, &tr);
                    double ca = fr_cpu_seconds();
                    if (s.M > 0 && !st) assemble_ident(&s);
                    s.cpu_id[1] += fr_cpu_seconds() - ca;
                    assembled = 1;
                }
                if (mu < 0 && !st) {
                    double trace = 0;
                    for (size_t q = 0; q < tr.count; q++)
                        if (tr.i[q] == tr.j[q]) trace += tr.x[q];
                    mu = 1e-3 * trace / s.nt;
                    if (!(s.dmean > 0)) s.dmean = trace / s.nt;
                }
                if (!st) set_damping(&s, mu, &tr);
                double cs = fr_cpu_seconds();
                if (!st) st = ch ? fr_cholesky_refactor(ctx, ch, &tr) : fr_cholesky_create(ctx, &tr, &ch);
                if (!st) st = s.M > 0 ? solve_ident(ctx, &s, ch, mu) : fr_cholesky_solve(ctx, ch, 1, s.rhs, s.delta);
                s.cpu_id[2] += fr_cpu_seconds() - cs;
                if (st) break;
                for (int t = 0; t < s.nt; t++) {
                    double d = s.D[t] + s.delta[t];
                    s.D_try[t] = d > o->max_mm ? o->max_mm : d < -o->max_mm ? -o->max_mm : d;
                }
                if (s.M > 0) {
                    for (int k = 0; k < s.M; k++) s.beta_try[k] = s.beta[k] + s.dbeta[k];
                    ident_offsets(&s, s.dbeta, NULL, s.dXb);
                }
                if (o->joint_albedo) albedo_step(&s, s.delta);
                double ce = fr_cpu_seconds();
                double e2 = evaluate_at(&s, s.D_try, s.M > 0 ? s.beta_try : NULL, o->joint_albedo ? s.albedo_try : s.albedo,
                                        &s.eq[1 - s.cur]);
                s.cpu_id[0] += fr_cpu_seconds() - ce;
                if (e2 < e) {
                    s.cur = 1 - s.cur; /* the tried step's equations are those at the new D */
                    memcpy(s.D, s.D_try, sizeof(double) * (size_t)s.nt);
                    if (s.M > 0) memcpy(s.beta, s.beta_try, sizeof(double) * (size_t)s.M);
                    if (o->joint_albedo) memcpy(s.albedo, s.albedo_try, sizeof(float) * 3 * (size_t)s.nt);
                    assembled = 0;
                    e = e2;
                    mu *= 0.3;
                    break;
                }
                mu *= 5;
            }
        }
        double rms = 0;
        for (int t = 0; t < s.nt; t++) rms += s.D[t] * s.D[t];
        fr_log(ctx, FRIG_LOG_DEBUG, "sfs: shared shape round %d: energy %.6g, displacement RMS %.3f mm", outer + 1, e,
               sqrt(rms / (s.nt ? s.nt : 1)));
        /* the round's pose step (below) draws every view again before the next sampling reads it,
         * so the bake and the expression step need not (nothing between reads the drawing) */
        int levels = o->pose_levels <= 0 || outer > 0 ? 0 : o->pose_levels;
        int pose_follows = o->pose_steps > 0 || levels > 0;
        double cb = fr_cpu_seconds();
        if (s.M > 0 && !st) st = ident_bake(ctx, &s, !pose_follows);
        s.cpu_id[3] += fr_cpu_seconds() - cb;
        c1 = fr_cpu_seconds(), cpu[CPU_SHAPE] += c1 - c0, c0 = c1;
        update_albedo(&s, threads);
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
        for (int k = 0; k < nviews; k++) {
            if (!use[k]) continue;
            frig_ctx child;
            fr_ctx_init_child(&child, ctx);
            update_lighting(&s, k, &child);
        }
        /* each photo's expression against its pixels, then the registration: the whole pyramid
         * after the first round only; the later rounds leave the poses to the pose steps (measured:
         * the same clouds and neutral within noise, docs/sfs.md "The fourth pass" and "The twelfth
         * pass") */
        c1 = fr_cpu_seconds(), cpu[CPU_LIGHTING] += c1 - c0, c0 = c1;
        if (o->expression_steps > 0 && !st) st = expression_step(ctx, &s, threads, !pose_follows);
        c1 = fr_cpu_seconds(), cpu[CPU_EXPRESSIONS] += c1 - c0, c0 = c1;
        if (pose_follows && !st) st = joint_pose(ctx, &s, threads, o->pose_steps, levels);
        c1 = fr_cpu_seconds(), cpu[CPU_REGISTRATION] += c1 - c0, c0 = c1;
    }
    fr_log(ctx, FRIG_LOG_DEBUG, "sfs: shared shape (CPU s): registration %.2f, sampling and albedo %.2f, shape %.2f, "
           "albedo and lighting %.2f, expressions %.2f", cpu[CPU_REGISTRATION], cpu[CPU_SAMPLING], cpu[CPU_SHAPE],
           cpu[CPU_LIGHTING], cpu[CPU_EXPRESSIONS]);
    fr_log(ctx, FRIG_LOG_DEBUG, "sfs: shared shape (CPU s): tried steps' evaluations %.2f, identity assembly %.2f, "
           "factor and solves %.2f, identity bakes %.2f", s.cpu_id[0], s.cpu_id[1], s.cpu_id[2], s.cpu_id[3]);
    if (!st) {
        memset(disp, 0, sizeof(float) * (size_t)T * T);
        for (int t = 0; t < s.nt; t++) {
            size_t q = (size_t)uv->texel[t];
            disp[q] = (float)(s.D[t] * MM);
            for (int c = 0; c < 3; c++) ps->albedo[3 * q + c] = s.albedo[3 * t + c];
        }
        if (s.M > 0 && o->id_change) memcpy(o->id_change, s.beta, sizeof(double) * (size_t)s.M);
    }
    fr_cholesky_free(ch);
    fr_triplets_free(&tr);
    mv_free(&s);
    return st;
}

frig_status fr_sfs_vertex_displacement(frig_ctx *ctx, const fr_sfs_mesh *m, const float *disp, int T, float *out) {
    uint8_t *done = calloc((size_t)m->nv + 1, 1);
    if (!done) return fr_nomem(ctx, "the displacement");
    memset(out, 0, sizeof(float) * (size_t)m->nv);
    for (int t = 0; t < m->nt; t++) {
        if (!m->face[t]) continue;
        for (int c = 0; c < 3; c++) {
            int v = m->tris[3 * (size_t)t + c];
            if (done[v]) continue;
            const float *u = m->uvs + 2 * (size_t)m->tri_uv[3 * (size_t)t + c];
            double uv[2] = {u[0], u[1]};
            float d;
            /* texels with a displacement only (0 marks off-face texels too: a true zero is harmless) */
            if (fr_sfs_texture_sample(disp, NULL, T, 1, uv, &d)) out[v] = d;
            done[v] = 1;
        }
    }
    free(done);
    return FRIG_OK;
}
