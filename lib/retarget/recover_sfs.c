/* Recovering the clouds in the outer loop (paper section 5.3, Algorithm 3 line 6): the sfs
 * stage run again with the current (personalized) rig at each photo's refitted pose, as a
 * frig_clouds_fn for frig_retarget_refine. No pictures: the loop's clouds are working data. */
#include <stdlib.h>

#include "core/context.h"
#include "frig/retarget.h"
#include "frig/sfs.h"

frig_status frig_retarget_recover_sfs(void *user, frig_ctx *ctx, const frig_model *model, const frig_rig *rig,
                                      frig_photoset *set, frig_clouds **clouds) {
    (void)model;
    if (!rig || !set || !clouds) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_retarget_recover_sfs: NULL argument");
    frig_image **albedo = user, *a = NULL;
    frig_clouds *c = NULL;
    frig_status s = frig_sfs(ctx, rig, set, NULL, &c, albedo ? &a : NULL);
    if (s) return s;
    frig_clouds_free(*clouds);
    *clouds = c;
    if (albedo) {
        frig_image_free(*albedo);
        *albedo = a;
    }
    return FRIG_OK;
}
