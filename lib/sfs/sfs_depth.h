/* Normals and depth from shading, solved in the log-depth (paper eq. 5.6-5.13; sfs_depth.c).
 * Internal. */
#ifndef FR_SFS_SFS_DEPTH_H
#define FR_SFS_SFS_DEPTH_H

#include "sfs/sfs.h"

typedef struct fr_sfs_depth_options {
    double sigma;    /* relative intensity error of one standard deviation */
    double w_normal; /* curvature of the depth correction (pixels) */
    double w_anchor; /* depth held to the fitted depth (pixels) */
    double w_prior;  /* normals held to the view's n_prior where it is set */
    int iterations;  /* Gauss-Newton iterations */
} fr_sfs_depth_options;

void fr_sfs_depth_options_default(fr_sfs_depth_options *o);

typedef struct fr_sfs_depth_stats {
    int unknowns, data_pixels, factorizations;
    double energy_start, energy_end;
} fr_sfs_depth_stats;

/* Solve for v->z (camera depth) and v->normal on the face pixels of v, with data terms on the
 * pixels of data_mask, from the view's lighting v->sh and albedo v->albedo; starts from v->z
 * where it is set (> 0), else from the fitted depth. Fills v->err (relative RMS residual). */
frig_status fr_sfs_solve_depth(frig_ctx *ctx, fr_sfs_view *v, const uint8_t *data_mask,
                               const fr_sfs_depth_options *o, fr_sfs_depth_stats *stats);

#endif
