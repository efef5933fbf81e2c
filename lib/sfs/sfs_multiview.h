/* Shape from shading from all photos at once, in the model's UV space (beyond the paper's
 * per-photo section 5.1; sfs_multiview.c): one displacement of the rig's face along its normals,
 * shared by every photo of the subject, whose shading explains all the photos under their own
 * lights and poses. Internal. */
#ifndef FR_SFS_SFS_MULTIVIEW_H
#define FR_SFS_SFS_MULTIVIEW_H

#include "sfs/sfs.h"
#include "sfs/sfs_albedo.h"
#include "sfs/sfs_uv.h"

typedef struct fr_sfs_multiview_options {
    int outer;        /* rounds of (resample, albedo, displacement, lighting) */
    int iterations;   /* Gauss-Newton iterations per round */
    double sigma;     /* relative intensity error of one standard deviation */
    double w_smooth;  /* second differences of the displacement (per texel, mm) */
    double w_anchor;  /* displacement held to zero (per texel, mm) */
    double max_mm;    /* the displacement is clamped to +-this */
    int pose_steps;   /* per round, Levenberg-Marquardt steps of each photo's pose against the shared surface */
    int joint_albedo; /* 1: the texels' albedo solved with the displacement (eliminated per texel), not alternated */
    double w_stereo;  /* the photos' own gradients along each texel's projected path (0: shading only) */
    int pose_levels;  /* each photo's pose registered coarse to fine (sfs_pose_align.c) before the shared solve and
                       * after each round, with this many blur levels (0: off) */
    double pose_sigma_px; /* the finest level's blur, crop pixels for a 160-pixel face */
    int expression_steps;     /* each photo's expression weights refined after each round (sfs_expression.c; 0 off) */
    double expression_prior;  /* held to the weights the views start with (the fit's) */
    double expression_sparse; /* L1 on the weights */
    /* the model's identity modes solved with the displacement (id_count 0: off): id_count modes of 3 nv
     * floats (the mesh's vertices), the change c of the identity weights held by id_prior
     * |(1 - id_centre) id_start + c|^2 (id_start NULL: zeros; id_centre 1: the prior centred at the start);
     * the change is written to the mesh's ident (which must be allocated) and,
     * when id_change is given, its weights there (id_count) */
    const float *id_modes;
    int id_count;
    double id_prior;
    double id_centre;
    double id_hold;   /* with identity modes: w_anchor in the first half of the rounds (0: w_anchor throughout) */
    const double *id_start;
    double *id_change;
} fr_sfs_multiview_options;

void fr_sfs_multiview_options_default(fr_sfs_multiview_options *o);

/* disp: T x T metres along the rig's normals (0 off the face), filled; ps->albedo is used as the
 * start and updated; each used view's lighting is refitted on the displaced surface. */
frig_status fr_sfs_multiview(frig_ctx *ctx, const fr_sfs_mesh *m, const fr_sfs_uv *uv, fr_sfs_view *views, int nviews,
                             const uint8_t *use, const fr_sfs_multiview_options *o, fr_sfs_albedo *ps, float *disp);

/* Photo v's shading for head-frame normal N (per channel, clamped at 0) and, with G, its gradient by N
 * (3 per channel; 0 where clamped). */
void fr_sfs_shade_head(const fr_sfs_view *v, const double N[3], double S[3], double G[3][3]);

/* Tukey's biweight (c 4.685): the IRLS weight and the energy of a scaled residual u. */
double fr_sfs_tukey_w(double u);
double fr_sfs_tukey_rho(double u);

/* Per vertex of the rig: the displacement at its UV (metres; 0 for vertices off the face). */
frig_status fr_sfs_vertex_displacement(frig_ctx *ctx, const fr_sfs_mesh *m, const float *disp, int T, float *out);

#endif
