/* libfrig fit stage (paper sections 4.3-4.4, Algorithm 2): per photo a camera, head pose and
 * expression weights, and one identity for the subject, fitted to the 68 landmarks of the
 * photo set's usable photos with the progressive scheme (individual fits, subset selection
 * by identity fitness and photo-consistency, joint identity on the best 0.4 / 0.6 / 0.8,
 * final fits with the identity fixed). Results go into the photo set (frig_photoset_fit_*).
 */
#ifndef FRIG_FIT_H
#define FRIG_FIT_H

#include "frig/model.h"
#include "frig/photoset.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Fit every photo whose status is ok and whose subject face has landmarks. Reads the fit.*
 * parameters of ctx. Photos are read again (for photo-consistency) from their paths.
 * Photos whose final fit is unusable get the status fit_failed with a reason.
 * FRIG_ERR_TOO_FEW when no photo can be fitted. Parallel across photos, deterministic. */
FRIG_API frig_status frig_fit(frig_ctx *ctx, const frig_model *model, frig_photoset *set);

/* Draw the fitted mesh (shaded, half transparent) and the landmarks (detected: green,
 * re-projected: red) over each fitted photo; writes DIR/<photo name>.jpg. */
FRIG_API frig_status frig_fit_write_overlays(frig_ctx *ctx, const frig_model *model, const frig_photoset *set,
                                             const char *dir);

/* run: each landmark's reprojection error of the stored fits, for reports: errors gets 68
 * values per photo of the set (pixels; the jaw landmarks where the fit last put them on the
 * silhouette), eye_distance one per photo (pixels between the eye centres, the mean of
 * landmarks 36-41 and of 42-47); both NaN for photos without a fit. model must be the one the
 * set was fitted with (FRIG_ERR_STATE otherwise, or when the set has no fit). */
FRIG_API frig_status frig_fit_landmark_errors(frig_ctx *ctx, const frig_model *model, const frig_photoset *set,
                                              double *errors, double *eye_distance);

#ifdef __cplusplus
}
#endif
#endif /* FRIG_FIT_H */
