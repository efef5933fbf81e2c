/* A photo's head pose registered to the subject's shared surface and albedo by coarse-to-fine
 * direct image alignment (sfs_pose_align.c; beyond the paper, whose poses are the landmark
 * fit's). Internal. */
#ifndef FR_SFS_SFS_POSE_ALIGN_H
#define FR_SFS_SFS_POSE_ALIGN_H

#include "sfs/sfs.h"

typedef struct fr_sfs_pose_align_options {
    int levels;       /* pyramid levels; level l blurs by sigma_px 2^l (coarsest first); 0: off */
    double sigma_px;  /* the finest level's blur, crop pixels for a face 160 pixels long (scaled with the face) */
    int steps;        /* Levenberg-Marquardt steps per level */
    double scale;     /* residual scale, relative intensity (Huber's threshold is 1.345 of it) */
    double max_deg;   /* a pose that turned further than this from the start is rejected (the start kept) */
    double w_photo;   /* weight of the photometric term */
    double w_contour; /* weight of the occluding contour's term (all its residuals against all the photometric ones) */
    int redraw;       /* 1: v drawn again at the new pose; 0: only v->R, v->t set (the caller draws it before it is read) */
} fr_sfs_pose_align_options;

/* levels 3, sigma_px 2, steps 5, scale 0.05, max_deg 25, w_photo 1, w_contour 1, redraw 1 */
void fr_sfs_pose_align_options_default(fr_sfs_pose_align_options *o);

/* Register view v (its photo v->I, its lighting v->sh) to the rig at v->weights plus the
 * per-vertex displacement vdisp (may be NULL) with the albedo texture tex (T x T, 3 floats per
 * texel; texels with tex_w <= 0 unknown): per level, the prediction albedo x shading is drawn at
 * the current pose, blurred (normalized inside the face) like the photo, and the pose moved so
 * that the blurred photo at each face point's new projection matches it (robust Huber
 * residuals; 6 x 6 Levenberg-Marquardt). v->R, v->t get the new pose and v is drawn again at it (o->redraw).
 * *turn_deg (may be NULL): the rotation between the start and the result. */
frig_status fr_sfs_pose_align(frig_ctx *ctx, const fr_sfs_mesh *m, fr_sfs_view *v, const float *vdisp, const float *tex,
                              const float *tex_w, int T, const fr_sfs_pose_align_options *o, double *turn_deg);

#endif
