/* Recovering the clouds in the outer loop (paper section 5.3, Algorithm 3 line 6): the sfs
 * stage run again with the current (personalized) rig at each photo's refitted pose, as a
 * frig_clouds_fn for frig_retarget_refine. No pictures: the loop's clouds are working data.
 * Each photo's depth takes retarget.sfs_iterations Gauss-Newton iterations when that is set
 * (0, the default: the stage's own sfs.iterations, 1; docs/retarget.md, "Time per outer
 * iteration"). With retarget.sfs_light (the default) the recovery takes sfs's light shared solve
 * (no registration, identity modes or expression steps): the rounds after the first come out the
 * same as with the full solve in 40% of its time (docs/retarget.md, "The loop's recovery"); the
 * set's record of the solve then says so (report.json's "sfs" block: "light", "outer_loop").
 * Inside frig_retarget_refine the albedo texture (the export's; 2-3 CPU s at 512 texels, a
 * quarter of that at the 256 of sfs.texture_size 0) is not drawn in every recovery: the recovery
 * keeps its computation and the loop draws the last one's texture when it ends
 * (fr_rt_pending_albedo_finish), the same bytes as before. */
#include <stdlib.h>

#include "core/clock.h"
#include "core/context.h"
#include "frig/retarget.h"
#include "frig/sfs.h"
#include "retarget/retarget.h"
#include "sfs/sfs_run.h"

/* A recovery's computation waiting for its albedo texture, and where the texture goes. */
typedef struct pending_albedo {
    fr_sfs_run *run;
    frig_image **albedo;
} pending_albedo;

static void pending_free(void *p) {
    pending_albedo *q = p;
    if (!q) return;
    if (q->run) fr_sfs_run_free(q->run);
    free(q->run);
    free(q);
}

void fr_rt_pending_albedo_drop(frig_ctx *ctx) {
    pending_free(ctx->rt_pending);
    ctx->rt_pending = NULL;
    ctx->rt_pending_free = NULL;
}

frig_status fr_rt_pending_albedo_finish(frig_ctx *ctx) {
    pending_albedo *q = ctx->rt_pending;
    if (!q) return FRIG_OK;
    fr_stopwatch t = fr_stopwatch_start();
    frig_image *a = NULL;
    frig_status s = fr_sfs_run_albedo(ctx, q->run, &a);
    if (!s) {
        frig_image_free(*q->albedo);
        *q->albedo = a;
        double wall = 0, cpu = 0;
        fr_stopwatch_read(&t, &wall, &cpu);
        fr_log(ctx, FRIG_LOG_DEBUG, "retarget: the last recovery's albedo texture %.2f s (%.2f CPU s)", wall, cpu);
    }
    fr_rt_pending_albedo_drop(ctx);
    return s;
}

frig_status frig_retarget_recover_sfs(void *user, frig_ctx *ctx, const frig_model *model, const frig_rig *rig,
                                      frig_photoset *set, frig_clouds **clouds) {
    if (!rig || !set || !clouds) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_retarget_recover_sfs: NULL argument");
    frig_image **albedo = user, *a = NULL;
    frig_clouds *c = NULL;
    fr_sfs_settings st;
    fr_sfs_settings_from_ctx(ctx, &st);
    fr_sfs_settings_identity(ctx, &st, model, set);
    int iterations = fr_param_int(ctx, FRIG_PARAM_RETARGET_SFS_ITERATIONS);
    if (iterations > 0) st.iterations = iterations;
    int shape_iterations = fr_param_int(ctx, FRIG_PARAM_RETARGET_SFS_SHAPE_ITERATIONS);
    if (shape_iterations > 0) st.shape_iterations = shape_iterations; /* 0: sfs.shape_iterations */
    st.light = fr_param_int(ctx, FRIG_PARAM_RETARGET_SFS_LIGHT);
    if (albedo && ctx->rt_defer_albedo) {
        /* the texture when the loop ends, from the last recovery's computation; the previous
         * round's is dropped first, so that only one is ever held */
        fr_rt_pending_albedo_drop(ctx);
        pending_albedo *q = calloc(1, sizeof *q);
        if (!q) return fr_nomem(ctx, "the outer loop's albedo");
        frig_status s = fr_sfs_stage_keep(ctx, rig, set, &st, &c, &q->run);
        if (s) {
            free(q);
            return s;
        }
        q->albedo = albedo;
        ctx->rt_pending = q;
        ctx->rt_pending_free = pending_free;
        frig_clouds_free(*clouds);
        *clouds = c;
        return FRIG_OK;
    }
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
