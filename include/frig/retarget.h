/* libfrig retarget stage (paper sections 5.2-5.3, Algorithms 3, 6 and 7, eq. 5.16-5.17; Li,
 * Weise & Pauly 2010; Sumner & Popovic 2004): the personalized rig, beyond the model's span,
 * from per-photo point clouds. Per photo the current reconstruction B (x) w_i is aligned and
 * deformed to the photo's cloud (correspondence, M'_i); the neutral is solved from all M'_i
 * (eq. 5.16, w_d = 1, w_t = 0.5, w_m = 0.01, keeping only B_0); then, with the neutral fixed,
 * the blendshapes (data, deformation transfer of the template's expressions onto the neutral,
 * previous blendshapes: w_d = 1, w_t = 0.5, w_m = 0.25) and each photo's weights (bounded
 * least squares in [0, 1]) alternate. The rest of the head (neck, ears, eyes, teeth, gums,
 * mouth socket) follows the face: eyeballs and teeth rigidly, skin by a smooth deformation.
 * The outer loop (section 5.3, Algorithm 3) refits every photo with the new rig, recovers the
 * clouds again and retargets again.
 * Parameters: retarget.* (and fit.* for the refit); see docs/retarget.md.
 */
#ifndef FRIG_RETARGET_H
#define FRIG_RETARGET_H

#include "frig/clouds.h"
#include "frig/model.h"
#include "frig/photoset.h"
#include "frig/rig.h"

#ifdef __cplusplus
extern "C" {
#endif

/* One pass of Algorithm 6 on the fitted photos of set that have a cloud: rig (the current rig:
 * the fit stage's model-space rig, or an earlier personalized one) is replaced in place by the
 * personalized rig; each photo's retarget weights and correspondence figures are recorded in
 * set (frig_photoset_retarget_*). model supplies the template expressions and the regions.
 * FRIG_ERR_TOO_FEW when no photo has both a fit and a cloud. Parallel, deterministic. */
FRIG_API frig_status frig_retarget(frig_ctx *ctx, const frig_model *model, frig_photoset *set,
                                   const frig_clouds *clouds, frig_rig *rig);

/* Refit every fitted photo's camera, pose and expression on a rig (section 5.3: the
 * per-image reconstruction with the generated blendshapes instead of the model): the
 * progressive fit's per-photo step with the rig's neutral and shapes, identity fixed.
 * Photos whose refit is unusable get fit_failed, as in frig_fit; sfs_failed photos are refitted
 * too (the sfs stage judges them again) and keep their status. */
FRIG_API frig_status frig_fit_rig(frig_ctx *ctx, const frig_model *model, const frig_rig *rig, frig_photoset *set);

/* Recovering the clouds with the current rig (the sfs stage in the outer loop). *clouds may be
 * replaced (the old handle freed by the callee) or updated in place. */
typedef frig_status (*frig_clouds_fn)(void *user, frig_ctx *ctx, const frig_model *model, const frig_rig *rig,
                                      frig_photoset *set, frig_clouds **clouds);

/* A frig_clouds_fn that recovers the clouds with the current rig by the sfs stage: frig_sfs on
 * the set (sfs.* parameters of ctx, no pictures), the new clouds replacing *clouds. user is
 * NULL or a frig_image ** that receives the albedo of the last recovery (the image it held is
 * freed; the caller frees the last). Photos sfs marks sfs_failed give no cloud that round.
 * Called by frig_retarget_refine, it draws the albedo texture only for the loop's last recovery,
 * when the loop ends (the same image; *user is set then).
 * Usage: frig_retarget_refine(ctx, model, set, &clouds, rig, frig_retarget_recover_sfs, &albedo). */
FRIG_API frig_status frig_retarget_recover_sfs(void *user, frig_ctx *ctx, const frig_model *model,
                                               const frig_rig *rig, frig_photoset *set, frig_clouds **clouds);

/* The outer loop (Algorithm 3): retarget.iterations rounds of [refit (frig_fit_rig), recover
 * the clouds (recover; NULL keeps the clouds as given, and then at most
 * retarget.fixed_cloud_rounds rounds run), frig_retarget], the first round starting from the
 * fit and clouds as they are. Stops early when the rig's neutral moved less
 * than retarget.stop_mm (mean over the face, mm) in a round. Per-round figures (change,
 * residuals) are recorded in set's report (frig_photoset_save writes them); each round's time
 * goes to the log. With fewer than retarget.min_clouds photos with a cloud (default 2) no round
 * runs: the rig is left as it is (frig_photoset_retarget_rounds says 0). */
FRIG_API frig_status frig_retarget_refine(frig_ctx *ctx, const frig_model *model, frig_photoset *set,
                                          frig_clouds **clouds, frig_rig *rig, frig_clouds_fn recover, void *user);

/* A picture of rigs for a person to look at: one row per rig (labels may be NULL), the neutral
 * from the front and turned, then jawOpen, smile, blink, brows up and pucker, shaded; framed on
 * the first rig's face. Written as PNG (atomically). */
FRIG_API frig_status frig_retarget_write_sheet(frig_ctx *ctx, const frig_model *model, const frig_rig *const *rigs,
                                               const char *const *labels, int count, const char *path);

/* ---- results in the photo set ---- */
/* 1 when the photo took part in the last retarget pass. */
FRIG_API int frig_photoset_retargeted(const frig_photoset *set, size_t photo);
/* The photo's retarget figures: cloud points matched, their RMS distance to the corresponded
 * mesh (mm), the rigid correction of the cloud (degrees, mm). Any output may be NULL. */
FRIG_API frig_status frig_photoset_retarget_figures(const frig_photoset *set, size_t photo, int *inliers,
                                                    double *rms_mm, double *rigid_deg, double *rigid_mm);
/* Rounds of the outer loop recorded so far, and one round's figures: the mean change of the
 * neutral over the face (mm), photos used, their mean cloud RMS (mm). */
FRIG_API int frig_photoset_retarget_rounds(const frig_photoset *set);
FRIG_API frig_status frig_photoset_retarget_round(const frig_photoset *set, int round, double *change_mm,
                                                  int *photos, double *rms_mm);

#ifdef __cplusplus
}
#endif
#endif /* FRIG_RETARGET_H */
