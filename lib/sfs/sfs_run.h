/* The stage's whole computation over a photo set, kept in memory for the stage's outputs and
 * for the benchmarks (sfs_run.c). Internal. */
#ifndef FR_SFS_SFS_RUN_H
#define FR_SFS_SFS_RUN_H

#include "sfs/sfs.h"
#include "sfs/sfs_albedo.h"
#include "sfs/sfs_uv.h"

typedef struct fr_sfs_run {
    fr_sfs_settings st;
    fr_sfs_mesh mesh;
    fr_sfs_uv uv;
    fr_sfs_albedo ps;
    int n;              /* candidate photos (ok and fitted) */
    size_t *photo;      /* their indices in the set */
    fr_sfs_view *views;
    uint8_t *ok;        /* still usable */
    char **reason;      /* why not (NULL when usable) */
    frig_status *status; /* the photo's own failure (FRIG_OK for a judged failure) */
    double mean_albedo[3];
    float *vdisp;       /* per rig vertex: the multi-view displacement along its normal, metres (NULL: none) */
    double *ident;      /* with st.identity_count modes: the identity weights' change (mesh.ident its shape), else NULL */
    int light_why;      /* fr_sfs_why: why the light shared solve ran (FR_SFS_WHY_NONE: the full solve) */
    double light_axis;  /* the lights' concentration along one axis (fr_sfs_light_concentration) */
} fr_sfs_run;

frig_status fr_sfs_run_all(frig_ctx *ctx, const frig_rig *rig, const frig_photoset *set, const fr_sfs_settings *st,
                           fr_sfs_run *run);
void fr_sfs_run_free(fr_sfs_run *run);
/* How nearly the lights of the views marked ok fall on the face along one axis: their directions in
 * the head's frame (each view's first-order SH terms summed over the channels, turned by the inverse
 * of its rotation R) and the largest eigenvalue of the mean of d d^T, 1 = one axis (frames of a
 * video under one lamp, the head hardly turning), 1/3 = spread evenly; 0 with fewer than two lit
 * views (LAPACK's symmetric eigensolver; its failure is the status). The stage takes the light
 * shared solve above sfs.joint_light. */
frig_status fr_sfs_light_concentration(frig_ctx *ctx, const fr_sfs_view *views, const uint8_t *ok, int n,
                                       double *concentration);

/* frig_sfs with the settings given instead of the context's (the outer loop's recovery). */
frig_status fr_sfs_stage(frig_ctx *ctx, const frig_rig *rig, frig_photoset *set, const fr_sfs_settings *st,
                         const char *overlay_dir, frig_clouds **clouds, frig_image **albedo);
/* The same without the albedo texture and without pictures: the computation is handed over in
 * *keep (free it with fr_sfs_run_free, then free) for fr_sfs_run_albedo later (the outer loop
 * draws only its last recovery's texture). */
frig_status fr_sfs_stage_keep(frig_ctx *ctx, const frig_rig *rig, frig_photoset *set, const fr_sfs_settings *st,
                              frig_clouds **clouds, fr_sfs_run **keep);
/* The albedo texture of a computation (what fr_sfs_stage gives in *albedo), the same bytes. */
frig_status fr_sfs_run_albedo(frig_ctx *ctx, fr_sfs_run *run, frig_image **out);

#endif
