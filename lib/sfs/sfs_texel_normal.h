/* The normal of the shared solve's displaced surface at a texel of the UV grid, centred on the
 * texel (sfs_multiview.c, sfs_expression.c). Internal.
 *
 * The surface photo k sees is P(t) = X(t) + D(t) n(t) (the rig's texel point and smooth normal at
 * k's expression, the shared displacement D). Its normal at texel t comes from the central secants
 *     ex = P(right) - P(left),  ey = P(down) - P(up)
 * (t itself where a neighbour is missing), plus a constant per texel and photo,
 *     c = s (ex x ey) + K,   K = |ex0 x ey0| n(t) - s (ex0 x ey0),   N = c / |c|,
 * with s the grid's orientation and ex0, ey0 the secants of X alone: at D = 0 the normal is the
 * rig's interpolated normal at t, the one the photos are shaded with (a renderer's), and D's
 * change moves it as the secants move. Forward differences (t, right, down) placed each normal
 * half a texel right and down of the point and the photo's pixel it is compared with: on a
 * curved face the solve then bent the surface to move the normals back (measured: from the true
 * rig with the true poses and weights, the shared displacement ended 0.95 mm from the truth on
 * frig synth photos without shadows or highlights; docs/sfs.md). */
#ifndef FR_SFS_SFS_TEXEL_NORMAL_H
#define FR_SFS_SFS_TEXEL_NORMAL_H

#include <math.h>

/* The stencil of a texel's normal: t, left, right, up, down (-1 where there is none). */
enum { FR_SFS_STENCIL = 5 };

/* The grid's neighbour links (texel numbers, -1 off the grid). */
typedef struct fr_sfs_texel_grid {
    const int *left, *right, *up, *down;
} fr_sfs_texel_grid;

/* The secants' ends at texel t: a and b along x (left or t, right or t), c and e along y; 0 when a
 * direction has neither neighbour (no normal). */
static inline int fr_sfs_secant_ends(const fr_sfs_texel_grid *g, int t, int ends[4]) {
    ends[0] = g->left[t] >= 0 ? g->left[t] : t;
    ends[1] = g->right[t] >= 0 ? g->right[t] : t;
    ends[2] = g->up[t] >= 0 ? g->up[t] : t;
    ends[3] = g->down[t] >= 0 ? g->down[t] : t;
    return ends[0] != ends[1] && ends[2] != ends[3];
}

/* The stencil's texel numbers [t, left, right, up, down] (-1 where missing: a missing neighbour's
 * part is t's). */
static inline void fr_sfs_stencil(const fr_sfs_texel_grid *g, int t, int u[FR_SFS_STENCIL]) {
    u[0] = t, u[1] = g->left[t], u[2] = g->right[t], u[3] = g->up[t], u[4] = g->down[t];
}

/* Slot in the stencil of secant end e (0..3: left, right, up, down) of texel t. */
static inline int fr_sfs_end_slot(const fr_sfs_texel_grid *g, int t, int e) {
    const int *link = e == 0 ? g->left : e == 1 ? g->right : e == 2 ? g->up : g->down;
    return link[t] >= 0 ? 1 + e : 0;
}

static inline void fr_sfs_cross(const double a[3], const double b[3], double c[3]) {
    c[0] = a[1] * b[2] - a[2] * b[1], c[1] = a[2] * b[0] - a[0] * b[2], c[2] = a[0] * b[1] - a[1] * b[0];
}

/* K of the header for texel t from the secants of X alone and the unit normal n (3 floats each per
 * texel); 0 where t has no normal. */
static inline void fr_sfs_normal_base(const fr_sfs_texel_grid *g, const float *X, const float *n, int sign, int t,
                                      float K[3]) {
    int e[4];
    K[0] = K[1] = K[2] = 0;
    if (!fr_sfs_secant_ends(g, t, e)) return;
    double ex[3], ey[3], c[3];
    for (int q = 0; q < 3; q++) {
        ex[q] = (double)X[3 * (size_t)e[1] + q] - X[3 * (size_t)e[0] + q];
        ey[q] = (double)X[3 * (size_t)e[3] + q] - X[3 * (size_t)e[2] + q];
    }
    fr_sfs_cross(ex, ey, c);
    double l = sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
    for (int q = 0; q < 3; q++) K[q] = (float)(l * n[3 * (size_t)t + q] - sign * c[q]);
}

/* The orientation of the grid at t against the unit normal n: +1 or -1 (+1 without a normal). */
static inline signed char fr_sfs_grid_sign(const fr_sfs_texel_grid *g, const float *X, const float *n, int t) {
    int e[4];
    if (!fr_sfs_secant_ends(g, t, e)) return 1;
    double ex[3], ey[3], c[3];
    for (int q = 0; q < 3; q++) {
        ex[q] = (double)X[3 * (size_t)e[1] + q] - X[3 * (size_t)e[0] + q];
        ey[q] = (double)X[3 * (size_t)e[3] + q] - X[3 * (size_t)e[2] + q];
    }
    fr_sfs_cross(ex, ey, c);
    return c[0] * n[3 * (size_t)t] + c[1] * n[3 * (size_t)t + 1] + c[2] * n[3 * (size_t)t + 2] < 0 ? -1 : 1;
}

#endif
