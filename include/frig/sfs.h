/* libfrig sfs stage (paper section 5.1, Algorithms 4-5, eq. 5.1-5.15): per usable photo a dense
 * point cloud of the face from its shading, in the rig's head frame, for the retarget stage;
 * and the subject's albedo in the model's UV space. docs/sfs.md describes the method (the
 * paper's per-photo shape from shading, helped by a shape shared by all photos), its
 * parameters (sfs.*) and its measured accuracy.
 *
 * EXPERIMENTAL: this part of the API may change while FRIG_VERSION_MAJOR is 0.
 */
#ifndef FRIG_SFS_H
#define FRIG_SFS_H

#include "frig/clouds.h"
#include "frig/image.h"
#include "frig/model.h"
#include "frig/photoset.h"
#include "frig/rig.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Recover a cloud for every photo whose status is ok (or sfs_failed from an earlier run) and
 * that has a fit, with the rig drawn at the photo's fit (camera, pose, expression weights,
 * mapped to the rig's shapes by name). Reads the sfs.* parameters of ctx.
 * - clouds: a new handle with one slot per photo of the set (NULL: not wanted);
 * - albedo: a new sfs.texture_size square sRGB image, the subject's albedo in the model's
 *   face UV layout (rows from the top; texel (x, y) at uv = ((x + 0.5) / W, 1 - (y + 0.5) / H)),
 *   NULL when not wanted;
 * - overlay_dir: one picture per photo, DIR/<photo file stem>.jpg (NULL: none).
 * In the set: per photo the pixels kept, the shading error, the lighting and the refined pose
 * (frig_photoset_sfs_*); photos whose face cannot be read (too little skin, over- or
 * under-exposed, colours unlike the subject's, too few points kept) get the status sfs_failed
 * with the reason, photos that cannot be read again unreadable, and the stage goes on.
 * FRIG_ERR_TOO_FEW when no photo can be used. Parallel across photos, deterministic. */
FRIG_API frig_status frig_sfs(frig_ctx *ctx, const frig_rig *rig, frig_photoset *set, const char *overlay_dir,
                              frig_clouds **clouds, frig_image **albedo);

/* frig_sfs with the morphable model the rig was fitted with (NULL: frig_sfs): with
 * sfs.identity_modes > 0 its first identity modes are solved with the shape all photos share,
 * from the set's fitted identity (frig_photoset_identity), so that the face may move along its
 * surface as well as across it; the clouds carry the change (docs/sfs.md). */
FRIG_API frig_status frig_sfs_with_model(frig_ctx *ctx, const frig_model *model, const frig_rig *rig,
                                         frig_photoset *set, const char *overlay_dir, frig_clouds **clouds,
                                         frig_image **albedo);

#ifdef __cplusplus
}
#endif
#endif /* FRIG_SFS_H */
