/* Normals and depth from shading (paper eq. 5.6-5.13, Algorithm 4 lines 12-13 and 17-18),
 * solved in the depth: the unknown is the log-depth g = f ln z of every face pixel (f the
 * crop's focal length in pixels, so g is in pixels), the normal of pixel i comes from the
 * central differences P = (g(x+1) - g(x-1)) / 2, Q = (g(y+1) - g(y-1)) / 2 (one-sided at the
 * face's edge) through the perspective camera,
 *     n ~ (P, Q, -(1 + rx P + ry Q)) + K_i,   (rx, ry) = ((x - cx) / f, (y - cy) / f),
 * (eq. 5.2 and 5.9-5.10 for a pinhole instead of an orthographic camera), so every normal
 * field the solver produces is integrable (eq. 5.8's E_int is zero by construction, as in the
 * author's own code, which optimizes depth directly). K_i makes the normal at the reference depth
 * the reference's own (the rig drawn with its interpolated normals and the shared shape: the
 * shading the shared solve explained), so the correction starts where the shared solve left off;
 * differences centred on the pixel compare each normal with its own pixel (forward differences
 * put it half a pixel off, sfs_texel_normal.h). Minimized by Gauss-Newton with
 * Levenberg-Marquardt damping:
 *     sum_i rho(|a_i S(n_i) - I_i| / (sigma Ibar_i))                      (eq. 5.7)
 *   + w_normal sum |second differences of (g - g_ref)|^2                  (eq. 5.8's E_normal)
 *   + w_anchor sum (g - g_ref)^2                                           (eq. 5.13)
 * with rho Tukey's biweight (shadows, highlights, occluders weigh nothing), g_ref the fitted
 * depth. The sparse normal equations keep one pattern for all iterations: CHOLMOD analyzes it
 * once and refactors. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "sfs/sfs.h"
#include "sfs/sfs_depth.h"
#include "sparse/sparse.h"

#define JUMP_PX 6.0     /* neighbours whose fitted log-depth differs more (slope > 80 degrees) are not linked */
#define TUKEY_C 4.685
#define INTENSITY_FLOOR 0.03

typedef struct problem {
    int w, h, n;        /* crop size, unknowns */
    int *idx;           /* pixel -> unknown, -1 */
    int *pix;           /* unknown -> pixel */
    uint8_t *right, *down; /* edge to the right / below links two unknowns */
    float *K;           /* 3 per pixel: the normal's constant (0 without a reference normal) */
    uint8_t *data;      /* pixel has a data term */
    double *g, *g_ref, *g_try, *delta, *rhs;
    double *robust;     /* per pixel */
    size_t *damped;     /* unknown -> its diagonal triplet holding w_anchor + mu */
    const float *I, *albedo, *prior;
    double sh[3][FR_SH_COUNT];
    double f, cx, cy, sigma, w_normal, w_anchor, w_prior;
} problem;

static void problem_free(problem *p) {
    free(p->idx), free(p->pix), free(p->right), free(p->down), free(p->data), free(p->K);
    free(p->g), free(p->g_ref), free(p->g_try), free(p->delta), free(p->rhs), free(p->robust), free(p->damped);
}

/* The ends of pixel i's differences: left or i, right or i, up or i, down or i (linked pixels);
 * 0 when a direction has neither neighbour (no normal). */
static int ends(const problem *p, size_t i, size_t e[4]) {
    int x = (int)(i % p->w), y = (int)(i / p->w);
    e[0] = x > 0 && p->right[i - 1] ? i - 1 : i;
    e[1] = p->right[i] ? i + 1 : i;
    e[2] = y > 0 && p->down[i - p->w] ? i - p->w : i;
    e[3] = p->down[i] ? i + p->w : i;
    return e[0] != e[1] && e[2] != e[3];
}

/* The stencil of pixel i's normal: its unknowns [i, left, right, up, down] (-1 where the
 * difference is one-sided there: that end is i), and d P, d Q by each. */
static void stencil(const problem *p, size_t i, const size_t e[4], int u[5], double dP[5], double dQ[5]) {
    double sx = e[1] - e[0] == 2 ? 0.5 : 1.0, sy = e[3] - e[2] == 2 * (size_t)p->w ? 0.5 : 1.0;
    u[0] = p->idx[i];
    for (int k = 0; k < 4; k++) u[1 + k] = e[k] != i ? p->idx[e[k]] : -1;
    for (int k = 0; k < 5; k++) dP[k] = dQ[k] = 0;
    dP[e[0] != i ? 1 : 0] -= sx, dP[e[1] != i ? 2 : 0] += sx;
    dQ[e[2] != i ? 3 : 0] -= sy, dQ[e[3] != i ? 4 : 0] += sy;
}

/* The unnormalized normal m of pixel i (with its constant K) from g and its ends. */
static void normal_m(const problem *p, const double *g, size_t i, const size_t e[4], double m[3]) {
    int x = (int)(i % p->w), y = (int)(i / p->w);
    double rx = (x - p->cx) / p->f, ry = (y - p->cy) / p->f;
    double P = (g[p->idx[e[1]]] - g[p->idx[e[0]]]) / (double)(e[1] - e[0]);
    double Q = (g[p->idx[e[3]]] - g[p->idx[e[2]]]) / (double)((e[3] - e[2]) / (size_t)p->w);
    m[0] = P, m[1] = Q, m[2] = -(1.0 + rx * P + ry * Q);
    for (int k = 0; k < 3; k++) m[k] += p->K[3 * i + k];
}

/* Normal of pixel i from g, and optionally d n / d P, d n / d Q (each 3). */
static void normal_of(const problem *p, const double *g, int i, double n[3], double dnP[3], double dnQ[3]) {
    size_t e[4];
    ends(p, (size_t)i, e);
    int x = i % p->w, y = i / p->w;
    double rx = (x - p->cx) / p->f, ry = (y - p->cy) / p->f, m[3];
    normal_m(p, g, (size_t)i, e, m);
    double len = sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
    for (int k = 0; k < 3; k++) n[k] = m[k] / len;
    if (!dnP) return;
    /* dn/dm = (I - n n^T) / |m|; dm/dP = (1, 0, -rx), dm/dQ = (0, 1, -ry) */
    double mP[3] = {1, 0, -rx}, mQ[3] = {0, 1, -ry};
    double nP = n[0] * mP[0] + n[2] * mP[2], nQ = n[1] * mQ[1] + n[2] * mQ[2];
    for (int k = 0; k < 3; k++) {
        dnP[k] = (mP[k] - n[k] * nP) / len;
        dnQ[k] = (mQ[k] - n[k] * nQ) / len;
    }
}

static double intensity_scale(const problem *p, int i) {
    double m = (p->I[3 * i] + p->I[3 * i + 1] + p->I[3 * i + 2]) / 3.0;
    return p->sigma * (m > INTENSITY_FLOOR ? m : INTENSITY_FLOOR);
}

/* Residuals (3, in sigmas) of data pixel i and their derivatives by P and Q. */
static void data_residual(const problem *p, const double *g, int i, double r[3], double dP[3], double dQ[3]) {
    double n[3], nP[3], nQ[3], y[FR_SH_COUNT], dy[3 * FR_SH_COUNT];
    normal_of(p, g, i, n, dP ? nP : NULL, dP ? nQ : NULL);
    if (dP) fr_sh_basis_gradient(n, y, dy);
    else fr_sh_basis(n, y);
    double inv = 1.0 / intensity_scale(p, i);
    for (int c = 0; c < 3; c++) {
        double S = 0, G[3] = {0, 0, 0};
        for (int k = 0; k < FR_SH_COUNT; k++) {
            S += p->sh[c][k] * y[k];
            if (dP)
                for (int j = 0; j < 3; j++) G[j] += p->sh[c][k] * dy[3 * k + j];
        }
        double a = p->albedo[3 * i + c];
        int lit = S > 0;
        r[c] = (a * (lit ? S : 0) - p->I[3 * i + c]) * inv;
        if (dP) {
            dP[c] = lit ? a * inv * (G[0] * nP[0] + G[1] * nP[1] + G[2] * nP[2]) : 0;
            dQ[c] = lit ? a * inv * (G[0] * nQ[0] + G[1] * nQ[1] + G[2] * nQ[2]) : 0;
        }
    }
}

/* The normal prior applies where the normal is defined and a prior is given. */
static int has_prior(const problem *p, size_t i) {
    size_t e[4];
    if (!(p->w_prior > 0) || !ends(p, i, e)) return 0;
    const float *q = p->prior + 3 * i;
    return q[0] != 0 || q[1] != 0 || q[2] != 0;
}

static double tukey_rho(double u) {
    double c2 = TUKEY_C * TUKEY_C;
    if (fabs(u) >= TUKEY_C) return c2 / 6.0;
    double t = 1 - (u / TUKEY_C) * (u / TUKEY_C);
    return c2 / 6.0 * (1 - t * t * t);
}

/* Second differences of (g - g_ref) through pixel i: horizontal (dir 0) and vertical (1);
 * returns 0 when the three pixels are not linked. */
static int curvature(const problem *p, int i, int dir, int nb[3]) {
    int step = dir ? p->w : 1;
    const uint8_t *link = dir ? p->down : p->right;
    int x = i % p->w, y = i / p->w;
    if ((dir ? y : x) < 1) return 0;
    if (!link[i - step] || !link[i]) return 0;
    nb[0] = p->idx[i - step], nb[1] = p->idx[i], nb[2] = p->idx[i + step];
    return 1;
}

static double energy(const problem *p, const double *g) {
    double e = 0;
    size_t np = (size_t)p->w * p->h;
    for (size_t i = 0; i < np; i++) {
        if (p->data[i]) {
            double r[3];
            data_residual(p, g, (int)i, r, NULL, NULL);
            for (int c = 0; c < 3; c++) e += tukey_rho(r[c]);
        }
        if (has_prior(p, i)) {
            double n[3];
            normal_of(p, g, (int)i, n, NULL, NULL);
            for (int k = 0; k < 3; k++) e += p->w_prior * (n[k] - p->prior[3 * i + k]) * (n[k] - p->prior[3 * i + k]);
        }
    }
    for (int u = 0; u < p->n; u++) {
        int i = p->pix[u], nb[3];
        double d = g[u] - p->g_ref[u];
        e += p->w_anchor * d * d;
        for (int dir = 0; dir < 2; dir++)
            if (curvature(p, i, dir, nb)) {
                double c = (g[nb[0]] - p->g_ref[nb[0]]) - 2 * (g[nb[1]] - p->g_ref[nb[1]]) + (g[nb[2]] - p->g_ref[nb[2]]);
                e += p->w_normal * c * c;
            }
    }
    return e;
}

static frig_status add(frig_ctx *ctx, fr_triplets *t, int a, int b, double v) {
    return a >= b ? fr_triplets_add(ctx, t, a, b, v) : fr_triplets_add(ctx, t, b, a, v);
}

/* A pixel's 5 x 5 block (upper triangle, row by row) over its stencil u, times w. */
static frig_status add_stencil(frig_ctx *ctx, fr_triplets *t, const int u[5], double w, const double H[15]) {
    frig_status s = FRIG_OK;
    for (int a = 0, h = 0; a < 5 && !s; a++)
        for (int b = a; b < 5 && !s; b++, h++)
            if (u[a] >= 0 && u[b] >= 0) s = add(ctx, t, u[a], u[b], w * H[h]);
    return s;
}

/* Normal equations at g (robust weights fixed from the residuals at g), damped by mu. The
 * triplets come in the same order every time, so the pattern never changes; set_damping
 * changes mu alone (the same triplets as assembling again with the new mu). */
static frig_status assemble(frig_ctx *ctx, problem *p, double mu, fr_triplets *t) {
    fr_triplets_clear(t);
    memset(p->rhs, 0, sizeof(double) * (size_t)p->n);
    frig_status s = FRIG_OK;
    size_t np = (size_t)p->w * p->h;
    for (size_t i = 0; i < np && !s; i++) {
        if (!has_prior(p, i)) continue;
        double n[3], nP[3], nQ[3], sP[5], sQ[5], H[15] = {0};
        size_t e[4];
        int u[5];
        ends(p, i, e);
        stencil(p, i, e, u, sP, sQ);
        normal_of(p, p->g, (int)i, n, nP, nQ);
        for (int k = 0; k < 3; k++) {
            double r = n[k] - p->prior[3 * i + k], j[5];
            for (int a = 0; a < 5; a++) j[a] = nP[k] * sP[a] + nQ[k] * sQ[a];
            for (int a = 0, h = 0; a < 5; a++)
                for (int b = a; b < 5; b++, h++) H[h] += j[a] * j[b];
            for (int a = 0; a < 5; a++)
                if (u[a] >= 0) p->rhs[u[a]] -= p->w_prior * j[a] * r;
        }
        s = add_stencil(ctx, t, u, p->w_prior, H);
    }
    for (size_t i = 0; i < np && !s; i++) {
        if (!p->data[i]) continue;
        double r[3], dP[3], dQ[3], sP[5], sQ[5], H[15] = {0};
        size_t e[4];
        int u[5];
        ends(p, i, e);
        stencil(p, i, e, u, sP, sQ);
        data_residual(p, p->g, (int)i, r, dP, dQ);
        for (int c = 0; c < 3; c++) {
            double uu = r[c] / TUKEY_C, wgt = fabs(uu) < 1 ? (1 - uu * uu) * (1 - uu * uu) : 0, j[5];
            for (int a = 0; a < 5; a++) j[a] = dP[c] * sP[a] + dQ[c] * sQ[a];
            for (int a = 0, h = 0; a < 5; a++)
                for (int b = a; b < 5; b++, h++) H[h] += wgt * j[a] * j[b];
            for (int a = 0; a < 5; a++)
                if (u[a] >= 0) p->rhs[u[a]] -= wgt * j[a] * r[c];
        }
        s = add_stencil(ctx, t, u, 1.0, H);
    }
    for (int u = 0; u < p->n && !s; u++) {
        int i = p->pix[u], nb[3];
        double d = p->g[u] - p->g_ref[u];
        p->rhs[u] -= p->w_anchor * d;
        p->damped[u] = t->count;
        s = add(ctx, t, u, u, p->w_anchor + mu);
        for (int dir = 0; dir < 2 && !s; dir++) {
            if (!curvature(p, i, dir, nb)) continue;
            static const double k[3] = {1, -2, 1};
            double c = 0;
            for (int q = 0; q < 3; q++) c += k[q] * (p->g[nb[q]] - p->g_ref[nb[q]]);
            for (int a = 0; a < 3 && !s; a++) {
                p->rhs[nb[a]] -= p->w_normal * k[a] * c;
                for (int b = 0; b <= a && !s; b++) s = add(ctx, t, nb[a], nb[b], p->w_normal * k[a] * k[b]);
            }
        }
    }
    return s;
}

static void set_damping(problem *p, double mu, fr_triplets *t) {
    for (int u = 0; u < p->n; u++) t->x[p->damped[u]] = p->w_anchor + mu;
}

static frig_status setup(frig_ctx *ctx, const fr_sfs_view *v, const uint8_t *data_mask, const fr_sfs_depth_options *o,
                         problem *p) {
    memset(p, 0, sizeof *p);
    p->w = v->w, p->h = v->h;
    size_t np = (size_t)p->w * p->h;
    p->idx = malloc(sizeof(int) * np);
    p->pix = malloc(sizeof(int) * np);
    p->right = calloc(np, 1), p->down = calloc(np, 1), p->data = calloc(np, 1);
    p->g = malloc(sizeof(double) * np), p->g_ref = malloc(sizeof(double) * np);
    p->g_try = malloc(sizeof(double) * np), p->delta = malloc(sizeof(double) * np);
    p->rhs = malloc(sizeof(double) * np), p->robust = malloc(sizeof(double) * np);
    p->damped = malloc(sizeof(size_t) * np), p->K = calloc(3 * np, sizeof(float));
    if (!p->idx || !p->pix || !p->right || !p->down || !p->data || !p->g || !p->g_ref || !p->g_try || !p->delta ||
        !p->rhs || !p->robust || !p->damped || !p->K)
        return fr_nomem(ctx, "the depth solver");
    p->I = v->I, p->albedo = v->albedo;
    memcpy(p->sh, v->sh, sizeof p->sh);
    p->f = v->cam.f, p->cx = v->cam.cx, p->cy = v->cam.cy;
    p->sigma = o->sigma, p->w_normal = o->w_normal, p->w_anchor = o->w_anchor, p->w_prior = o->w_prior;
    p->prior = v->n_prior;
    for (size_t i = 0; i < np; i++) {
        p->idx[i] = -1;
        if (!v->face[i] || !(v->z_ref[i] > 0)) continue;
        p->pix[p->n] = (int)i;
        p->g_ref[p->n] = p->f * log(v->z_ref[i]);
        p->g[p->n] = v->z[i] > 0 ? p->f * log(v->z[i]) : p->g_ref[p->n];
        p->idx[i] = p->n++;
    }
    for (size_t i = 0; i < np; i++) {
        int x = (int)(i % p->w), y = (int)(i / p->w), u = p->idx[i];
        if (u < 0) continue;
        if (x + 1 < p->w && p->idx[i + 1] >= 0 && fabs(p->g_ref[p->idx[i + 1]] - p->g_ref[u]) < JUMP_PX) p->right[i] = 1;
        if (y + 1 < p->h && p->idx[i + p->w] >= 0 && fabs(p->g_ref[p->idx[i + p->w]] - p->g_ref[u]) < JUMP_PX)
            p->down[i] = 1;
    }
    /* K: at the reference depth, the reference's normal (where the view has one) */
    for (size_t i = 0; i < np; i++) {
        size_t e[4];
        const float *nr = v->n_ref ? v->n_ref + 3 * i : NULL;
        if (p->idx[i] < 0 || !ends(p, i, e) || !nr || !(nr[0] != 0 || nr[1] != 0 || nr[2] != 0)) continue;
        double m[3];
        normal_m(p, p->g_ref, i, e, m); /* K is 0 here */
        double l = sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]), ln = sqrt(nr[0] * nr[0] + nr[1] * nr[1] + nr[2] * nr[2]);
        if (!(l > 0) || !(ln > 0) || nr[0] * m[0] + nr[1] * m[1] + nr[2] * m[2] <= 0) continue;
        for (int k = 0; k < 3; k++) p->K[3 * i + k] = (float)(l * nr[k] / ln - m[k]);
    }
    for (size_t i = 0; i < np; i++) {
        size_t e[4];
        p->data[i] = data_mask[i] && p->idx[i] >= 0 && ends(p, i, e);
    }
    return FRIG_OK;
}

void fr_sfs_depth_options_default(fr_sfs_depth_options *o) {
    o->sigma = 0.02;
    o->w_normal = 1.0;
    o->w_anchor = 1e-3;
    o->iterations = 5;
    o->w_prior = 0;
}

frig_status fr_sfs_solve_depth(frig_ctx *ctx, fr_sfs_view *v, const uint8_t *data_mask, const fr_sfs_depth_options *o,
                               fr_sfs_depth_stats *stats) {
    problem p;
    frig_status s = setup(ctx, v, data_mask, o, &p);
    fr_triplets t;
    memset(&t, 0, sizeof t);
    fr_cholesky *ch = NULL;
    fr_sfs_depth_stats st;
    memset(&st, 0, sizeof st);
    if (!s && p.n < 10) s = fr_error(ctx, FRIG_ERR_NO_FACE, "only %d face pixels to solve for", p.n);
    if (!s) s = fr_triplets_init(ctx, &t, p.n, p.n, (size_t)p.n * 24);
    if (!s) {
        double e = energy(&p, p.g), mu = 0;
        st.energy_start = e;
        for (int it = 0; it < o->iterations && !s; it++) {
            /* g moved (or this is the start): the equations at g; between tries only the damping changes */
            s = assemble(ctx, &p, 0.0, &t);
            if (it == 0 && !s) {
                double tr = 0;
                for (size_t k = 0; k < t.count; k++)
                    if (t.i[k] == t.j[k]) tr += t.x[k];
                mu = 1e-4 * tr / p.n;
            }
            for (int tries = 0; tries < 6 && !s; tries++) {
                set_damping(&p, mu, &t);
                if (!s) s = ch ? fr_cholesky_refactor(ctx, ch, &t) : fr_cholesky_create(ctx, &t, &ch);
                if (!s) s = fr_cholesky_solve(ctx, ch, 1, p.rhs, p.delta);
                if (s) break;
                st.factorizations++;
                for (int u = 0; u < p.n; u++) p.g_try[u] = p.g[u] + p.delta[u];
                double e2 = energy(&p, p.g_try);
                if (e2 < e) {
                    memcpy(p.g, p.g_try, sizeof(double) * (size_t)p.n);
                    e = e2;
                    mu *= 0.3;
                    break;
                }
                mu = mu * 4 + 1e-9;
            }
        }
        st.energy_end = e;
    }
    if (!s) {
        size_t np = (size_t)p.w * p.h;
        st.unknowns = p.n;
        for (size_t i = 0; i < np; i++) {
            v->z[i] = 0.0f;
            v->normal[3 * i] = v->normal[3 * i + 1] = v->normal[3 * i + 2] = 0.0f;
            v->err[i] = -1.0f;
            int u = p.idx[i];
            if (u < 0) continue;
            v->z[i] = (float)exp(p.g[u] / p.f);
            size_t e[4];
            if (!ends(&p, i, e)) continue;
            double n[3];
            normal_of(&p, p.g, (int)i, n, NULL, NULL);
            for (int k = 0; k < 3; k++) v->normal[3 * i + k] = (float)n[k];
            double r[3];
            data_residual(&p, p.g, (int)i, r, NULL, NULL);
            double rel = sqrt((r[0] * r[0] + r[1] * r[1] + r[2] * r[2]) / 3.0) * p.sigma;
            v->err[i] = (float)rel;
            if (p.data[i]) st.data_pixels++;
        }
    }
    if (stats) *stats = st;
    fr_cholesky_free(ch);
    fr_triplets_free(&t);
    problem_free(&p);
    return s;
}
