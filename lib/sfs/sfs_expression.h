/* A photo's expression weights refined against its own pixels inside the shared solve
 * (sfs_expression.c; beyond the paper, whose per-photo expressions are the landmark fit's).
 * Internal. */
#ifndef FR_SFS_SFS_EXPRESSION_H
#define FR_SFS_SFS_EXPRESSION_H

#include "sfs/sfs.h"
#include "sfs/sfs_texel_normal.h"

/* The texel grid of the shared solve, and each rig shape's delta at its texels. */
typedef struct fr_sfs_expression_grid {
    int nt;                  /* texels */
    fr_sfs_texel_grid grid;  /* neighbour texel numbers, -1 */
    const signed char *sign; /* orientation of the grid's cross product against the normal */
    int shapes;              /* the rig's shapes */
    int active;              /* shapes refined (those that move the face) */
    const int *shape;        /* their rig shape numbers */
    const float *dX;         /* nt x active x 3: shape shape[j]'s delta at texel t, head frame, metres */
    const int *offset;       /* nt + 1: texel t's shapes are list[offset[t] .. offset[t + 1]) */
    const int *list;         /* active shapes (ascending) that move t or a neighbour of its stencil */
} fr_sfs_expression_grid;

/* What the shared solve knows of one photo at its current weights. */
typedef struct fr_sfs_expression_photo {
    const float *X, *n;  /* 3 per texel: the rig's texel points and unit normals at the view's weights (head frame) */
    const float *K;      /* 3 per texel: the normal's constant (sfs_texel_normal.h) */
    const float *I;      /* 3 per texel: the photo sampled there (the residuals' scale) */
    const float *w;      /* per texel: weight, 0 = not seen */
    const double *D;     /* per texel: the shared displacement along n, mm */
    const float *albedo; /* 3 per texel */
} fr_sfs_expression_photo;

typedef struct fr_sfs_expression_options {
    int steps;     /* Gauss-Newton steps (Levenberg-Marquardt, bounded to [0, 1]) */
    double sigma;  /* relative intensity error of one standard deviation (Tukey) */
    double prior;  /* sum (w - w0)^2 weighs this against the mean robust energy per seen texel */
    double sparse; /* sum w weighs this */
    int image;     /* 1: the photo sampled at each texel's moved projection (its gradients: the multi-view term) */
} fr_sfs_expression_options;

/* Refine v->weights (the rig's shapes; the grid's active ones move) from the photo's shading and
 * pixels: the surface at texel t is X(t) + sum_j (w_j - v->weights_j) dX_j(t) + D(t) n(t), its normal
 * from the grid's central secants (sfs_texel_normal.h), the residual a S(R N) - I(project(R P + t)) per channel.
 * w0: the prior's weights (the rig's shapes). *energy_change (may be NULL): the energy's relative
 * decrease. Returns the number of accepted steps (ctx: the bounded QP's errors). */
int fr_sfs_expression_refine(frig_ctx *ctx, const fr_sfs_expression_grid *g, const fr_sfs_expression_photo *p,
                             fr_sfs_view *v, const double *w0, const fr_sfs_expression_options *o,
                             double *energy_change);

#endif
