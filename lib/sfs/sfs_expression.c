/* A photo's expression weights refined against its own pixels inside the shared solve (beyond
 * the paper: its section 5.1 draws each photo's surface at the landmark fit's expression, eq.
 * 4.8, and section 5.2.3 (b) refines the weights only against the clouds). The shared solve sees
 * photo k's surface as the rig at k's weights plus the shared displacement,
 *     P_k(t) = X(w_k, t) + D(t) n_k(t),   X(w, t) = X_0(t) + sum_j w_j dX_j(t),
 * so a wrong weight puts a wrong mouth, cheek or brow into every cloud of k. With the shared
 * displacement, albedo and k's lighting held, the weights minimize
 *     1/W sum_t w_t sum_c rho((a_c(t) S_kc(R_k N_k(t)) - I_kc(proj(R_k P_k(t) + t_k))) / (sigma Ibar))
 *   + prior sum_j (w_j - w0_j)^2 + sparse sum_j w_j,   0 <= w_j <= 1,
 * N_k from the texel grid's central secants of P_k (as the shared solve's normals:
 * sfs_texel_normal.h, its constant K held), the
 * photo sampled at the moved point (its gradients: the multi-view term), rho Tukey's, W the
 * seen texels' weight (the sums run over every third texel: TEXEL_STRIDE below): Gauss-Newton
 * with Levenberg-Marquardt damping, each step a bounded
 * quadratic program (linalg/box_qp.c) over the shapes that move the face. The normal n_k of
 * the displacement is held at its start (second order). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "core/v2d.h"
#include "linalg/box_qp.h"
#include "raster/raster.h"
#include "sfs/sfs_expression.h"
#include "sfs/sfs_multiview.h"
#include "sfs/sfs_texel_normal.h"
#include "sfs/sfs_uv.h"

#define INTENSITY_FLOOR 0.03
#define MM 1e-3
/* The step reads every third texel in the grid's order (a diagonal lattice over the face): some
 * 2,700 texels of three channels for about 55 weights. Measured on seventeen frig synth subjects
 * against every texel (docs/sfs.md, "The fourth pass"): the same held-out error and neutral
 * within noise, the step 2.4 times faster. */
#define TEXEL_STRIDE 3

#define cross fr_sfs_cross

/* The points of texel t and of its secants' ends (left or t, right or t, up or t, down or t) at
 * weight change dw (active shapes; those of t's list L, nl of them, the only ones that move them),
 * each summed in the list's order: P[0] the texel's, P[1 + e] the ends'. */
static void points(const fr_sfs_expression_grid *g, const fr_sfs_expression_photo *p, const double *dw, const int u[5],
                   const int *L, int nl, double P[5][3]) {
    for (int c = 0; c < 5; c++)
        for (int q = 0; q < 3; q++)
            P[c][q] = p->X[3 * (size_t)u[c] + q] + p->D[u[c]] * MM * p->n[3 * (size_t)u[c] + q];
    for (int a = 0; a < nl; a++) {
        int j = L[a];
        if (dw[j] == 0)
            continue;
        for (int c = 0; c < 5; c++) {
            const float *d = g->dX + 3 * ((size_t)u[c] * g->active + (size_t)j);
            for (int q = 0; q < 3; q++)
                P[c][q] += dw[j] * d[q];
        }
    }
}

typedef struct scratch {
    double *dN; /* 3 per active shape */
    double *dP; /* 2 per active shape: the texel point's image motion (u, v: J R dP), the same for the channels */
    double *jr; /* 3 x active: each channel's residual derivative by each active shape */
} scratch;

/* One texel's Gauss-Newton terms into H (column-major, upper part) and gr: per channel ch with
 * live[ch], weight w[ch], residual res[ch] and derivatives sc->jr[ch * na + a]. The three
 * channels are added to each entry in turn (channel order, as one channel's pass after the
 * other would), one load and store of the entry for them all. */
static void accumulate(const scratch *sc, int na, const int *L, int nl, const double w[3], const int live[3],
                       const double res[3], double *H, double *gr) {
    for (int a = 0; a < nl; a++) {
        double wj[3];
        const double *jr[3];
        int k = 0;
        for (int ch = 0; ch < 3; ch++) {
            if (!live[ch])
                continue;
            const double *j = sc->jr + (size_t)ch * na;
            double v = w[ch] * j[a];
            if (v == 0)
                continue;
            gr[L[a]] += v * res[ch];
            wj[k] = v, jr[k++] = j;
        }
        double *col = H + (size_t)na * L[a];
        if (k == 3) {
            /* two entries at a time (the same operations per entry, in pairs of lanes) */
            v2d w0 = {wj[0], wj[0]}, w1 = {wj[1], wj[1]}, w2 = {wj[2], wj[2]};
            int b = a;
            for (; b + 1 < nl; b += 2) {
                double *h0 = col + L[b], *h1 = col + L[b + 1];
                v2d h = {*h0, *h1}, j0, j1, j2;
                memcpy(&j0, jr[0] + b, sizeof j0), memcpy(&j1, jr[1] + b, sizeof j1), memcpy(&j2, jr[2] + b, sizeof j2);
                h = h + w0 * j0 + w1 * j1 + w2 * j2;
                *h0 = h[0], *h1 = h[1];
            }
            for (; b < nl; b++)
                col[L[b]] = col[L[b]] + wj[0] * jr[0][b] + wj[1] * jr[1][b] + wj[2] * jr[2][b];
        } else if (k == 2)
            for (int b = a; b < nl; b++)
                col[L[b]] = col[L[b]] + wj[0] * jr[0][b] + wj[1] * jr[1][b];
        else if (k == 1)
            for (int b = a; b < nl; b++)
                col[L[b]] += wj[0] * jr[0][b];
    }
}

/* The data energy (normalized by W) at weight change dw; with H (active x active, column-major)
 * and gr (active) its Gauss-Newton normal equations. *W: the seen texels' weight (computed when
 * W <= 0 on entry). */
static double data_terms(const fr_sfs_expression_grid *g, const fr_sfs_expression_photo *p, const fr_sfs_view *v,
                         const fr_sfs_expression_options *o, const double *dw, double *H, double *gr, scratch *sc,
                         double *W) {
    int na = g->active, count_w = !(*W > 0);
    double e = 0, wsum = 0;
    if (H)
        memset(H, 0, sizeof(double) * (size_t)na * na), memset(gr, 0, sizeof(double) * (size_t)na);
    for (int t = 0; t < g->nt; t += TEXEL_STRIDE) {
        int e4[4];
        if (!(p->w[t] > 0) || !fr_sfs_secant_ends(&g->grid, t, e4))
            continue;
        double P[5][3], ex[3], ey[3], c[3];
        const int *L = g->list + g->offset[t], u[5] = {t, e4[0], e4[1], e4[2], e4[3]};
        int nl = g->offset[t + 1] - g->offset[t];
        points(g, p, dw, u, L, nl, P);
        const double *P0 = P[0];
        for (int q = 0; q < 3; q++)
            ex[q] = P[2][q] - P[1][q], ey[q] = P[4][q] - P[3][q];
        cross(ex, ey, c);
        double sg = g->sign[t], N[3];
        const float *K = p->K + 3 * (size_t)t;
        for (int q = 0; q < 3; q++)
            c[q] = sg * c[q] + K[q];
        double l = sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
        if (!(l > 0))
            continue;
        for (int q = 0; q < 3; q++)
            N[q] = c[q] / l;
        double S[3], G[3][3], I[3], gx[3] = {0, 0, 0}, gy[3] = {0, 0, 0}, Jp[6] = {0, 0, 0, 0, 0, 0};
        fr_sfs_shade_head(v, N, S, H ? G : NULL);
        const float *I0 = p->I + 3 * (size_t)t;
        if (o->image) {
            double Xc[3], xy[2];
            fr_mat3_apply(v->R, P0, Xc);
            for (int q = 0; q < 3; q++)
                Xc[q] += v->t[q];
            if (!fr_camera_project(&v->cam, Xc, xy))
                continue;
            if (xy[0] < 1 || xy[1] < 1 || xy[0] > v->w - 2 || xy[1] > v->h - 2)
                continue;
            fr_bilinear3(v->I, v->w, v->h, xy, I);
            if (H) {
                fr_sfs_image_gradient(v->I, v->w, v->h, xy, gx, gy);
                double J[6];
                fr_camera_project_jacobian(&v->cam, Xc, J);
                /* d(u, v)/dP (head frame) = J R */
                for (int row = 0; row < 2; row++)
                    for (int q = 0; q < 3; q++)
                        Jp[3 * row + q] =
                            J[3 * row] * v->R[q] + J[3 * row + 1] * v->R[3 + q] + J[3 * row + 2] * v->R[6 + q];
            }
        } else
            for (int q = 0; q < 3; q++)
                I[q] = I0[q];
        double mean = (I0[0] + I0[1] + I0[2]) / 3.0,
               scale = o->sigma * (mean > INTENSITY_FLOOR ? mean : INTENSITY_FLOOR);
        wsum += p->w[t];
        if (H) {
            /* the normal's and the point's derivatives by each active weight */
            for (int a = 0; a < nl; a++) {
                int j = L[a];
                const float *d0 = g->dX + 3 * ((size_t)t * na + (size_t)j);
                const float *dl = g->dX + 3 * ((size_t)e4[0] * na + (size_t)j);
                const float *dr = g->dX + 3 * ((size_t)e4[1] * na + (size_t)j);
                const float *du = g->dX + 3 * ((size_t)e4[2] * na + (size_t)j);
                const float *dd = g->dX + 3 * ((size_t)e4[3] * na + (size_t)j);
                double dex[3], dey[3], c1[3], c2[3], dc[3];
                for (int q = 0; q < 3; q++)
                    dex[q] = dr[q] - dl[q], dey[q] = dd[q] - du[q];
                sc->dP[2 * a] = Jp[0] * d0[0] + Jp[1] * d0[1] + Jp[2] * d0[2];
                sc->dP[2 * a + 1] = Jp[3] * d0[0] + Jp[4] * d0[1] + Jp[5] * d0[2];
                cross(dex, ey, c1), cross(ex, dey, c2);
                for (int q = 0; q < 3; q++)
                    dc[q] = sg * (c1[q] + c2[q]);
                double proj = dc[0] * N[0] + dc[1] * N[1] + dc[2] * N[2];
                for (int q = 0; q < 3; q++)
                    sc->dN[3 * a + q] = (dc[q] - proj * N[q]) / l;
            }
        }
        double res[3], w[3];
        int live[3];
        for (int ch = 0; ch < 3; ch++) {
            double alb = p->albedo[3 * t + ch];
            res[ch] = (alb * S[ch] - I[ch]) / scale;
            e += p->w[t] * fr_sfs_tukey_rho(res[ch]);
            if (!H)
                continue;
            w[ch] = p->w[t] * fr_sfs_tukey_w(res[ch]);
            live[ch] = w[ch] > 0;
            if (!live[ch])
                continue;
            double *jr = sc->jr + (size_t)ch * na;
            for (int a = 0; a < nl; a++) {
                const double *dn = sc->dN + 3 * a, *duv = sc->dP + 2 * a;
                double js = alb * (G[ch][0] * dn[0] + G[ch][1] * dn[1] + G[ch][2] * dn[2]);
                jr[a] = (js - (gx[ch] * duv[0] + gy[ch] * duv[1])) / scale;
            }
        }
        if (H)
            accumulate(sc, na, L, nl, w, live, res, H, gr);
    }
    if (count_w)
        *W = wsum;
    double inv = *W > 0 ? 1.0 / *W : 0;
    if (H) {
        for (int j = 0; j < na; j++) {
            gr[j] *= inv;
            for (int i = j; i < na; i++)
                H[(size_t)na * j + i] *= inv, H[(size_t)na * i + j] = H[(size_t)na * j + i];
        }
    }
    return e * inv;
}

/* The prior's and sparsity's energy at the active weights x (absolute). */
static double prior_terms(const fr_sfs_expression_grid *g, const fr_sfs_expression_options *o, const double *x,
                          const double *w0) {
    double e = 0;
    for (int j = 0; j < g->active; j++) {
        double d = x[j] - w0[g->shape[j]];
        e += o->prior * d * d + o->sparse * x[j];
    }
    return e;
}

int fr_sfs_expression_refine(frig_ctx *ctx, const fr_sfs_expression_grid *g, const fr_sfs_expression_photo *p,
                             fr_sfs_view *v, const double *w0, const fr_sfs_expression_options *o,
                             double *energy_change) {
    int na = g->active, accepted = 0;
    if (energy_change)
        *energy_change = 0;
    if (na <= 0 || o->steps <= 0)
        return 0;
    size_t nn = (size_t)na * na;
    double *buf = malloc(sizeof(double) * (2 * nn + 16 * (size_t)na + 1));
    if (!buf)
        return 0;
    double *H = buf, *A = H + nn, *gr = A + nn, *b = gr + na, *x = b + na, *dw = x + na, *lo = dw + na, *hi = lo + na;
    scratch sc = {hi + na, hi + 4 * (size_t)na, hi + 7 * (size_t)na};
    double *dx = hi + 10 * (size_t)na;
    for (int j = 0; j < na; j++)
        x[j] = v->weights[g->shape[j]], dw[j] = 0;
    double W = 0;
    double e = data_terms(g, p, v, o, dw, NULL, NULL, &sc, &W) + prior_terms(g, o, x, w0), e0 = e, mu = -1;
    for (int it = 0; it < o->steps && W > 0; it++) {
        for (int j = 0; j < na; j++)
            dw[j] = x[j] - v->weights[g->shape[j]];
        data_terms(g, p, v, o, dw, H, gr, &sc, &W);
        for (int j = 0; j < na; j++) {
            H[(size_t)na * j + j] += 2 * o->prior;
            gr[j] += 2 * o->prior * (x[j] - w0[g->shape[j]]) + o->sparse;
        }
        if (mu < 0) {
            double tr = 0;
            for (int j = 0; j < na; j++)
                tr += H[(size_t)na * j + j];
            mu = 1e-3 * tr / na;
        }
        int done = 0;
        for (int tries = 0; tries < 6 && !done; tries++) {
            memcpy(A, H, sizeof(double) * nn);
            for (int j = 0; j < na; j++) {
                A[(size_t)na * j + j] += mu + 1e-12;
                lo[j] = -x[j], hi[j] = 1 - x[j], dx[j] = 0;
            }
            if (fr_box_qp(ctx, na, A, gr, lo, hi, dx)) {
                mu *= 10;
                continue;
            }
            for (int j = 0; j < na; j++) {
                double y = x[j] + dx[j];
                b[j] = y < 0 ? 0 : y > 1 ? 1 : y;
                dw[j] = b[j] - v->weights[g->shape[j]];
            }
            double e2 = data_terms(g, p, v, o, dw, NULL, NULL, &sc, &W) + prior_terms(g, o, b, w0);
            if (e2 < e) {
                memcpy(x, b, sizeof(double) * (size_t)na);
                e = e2, mu *= 0.3, done = 1, accepted++;
            } else
                mu *= 10;
        }
        if (!done)
            break;
    }
    for (int j = 0; j < na; j++)
        v->weights[g->shape[j]] = x[j];
    if (energy_change)
        *energy_change = e0 > 0 ? (e0 - e) / e0 : 0;
    free(buf);
    return accepted;
}
