/* Recovering the clouds in the outer loop (paper section 5.3, Algorithm 3 line 6): the sfs
 * stage run again with the current (personalized) rig at each photo's refitted pose, as a
 * frig_clouds_fn for frig_retarget_refine. No pictures: the loop's clouds are working data.
 * Each photo's depth takes retarget.sfs_iterations Gauss-Newton iterations instead of the
 * stage's sfs.iterations: the rig it starts from has the previous round's clouds in it
 * (measured in docs/retarget.md, "Time per outer iteration": a third of the depth's time, the
 * synthetic subject's neutral no worse). */
#include <stdlib.h>

#include "core/context.h"
#include "frig/retarget.h"
#include "frig/sfs.h"
#include "sfs/sfs_run.h"

frig_status frig_retarget_recover_sfs(void *user, frig_ctx *ctx, const frig_model *model, const frig_rig *rig,
                                      frig_photoset *set, frig_clouds **clouds) {
    (void)model;
    if (!rig || !set || !clouds) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_retarget_recover_sfs: NULL argument");
    frig_image **albedo = user, *a = NULL;
    frig_clouds *c = NULL;
    fr_sfs_settings st;
    fr_sfs_settings_from_ctx(ctx, &st);
    int iterations = fr_param_int(ctx, FRIG_PARAM_RETARGET_SFS_ITERATIONS);
    if (iterations > 0) st.iterations = iterations;
    frig_status s = fr_sfs_stage(ctx, rig, set, &st, NULL, &c, albedo ? &a : NULL);
    if (s) return s;
    frig_clouds_free(*clouds);
    *clouds = c;
    if (albedo) {
        frig_image_free(*albedo);
        *albedo = a;
    }
    return FRIG_OK;
}
