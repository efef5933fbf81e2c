/* Iterative blendshape refinement (paper section 5.3, Algorithm 3): rounds of
 *     refit every photo on the current rig (frig_fit_rig) -> recover the clouds (the sfs stage,
 *     through a callback) -> retarget (frig_retarget),
 * the first round taking the fit and the clouds as they are. The paper runs three rounds; the
 * loop stops sooner when a round moves the neutral by less than retarget.stop_mm on average
 * over the face: the rig has stopped changing. frig_retarget_recover_sfs's albedo texture is
 * drawn once, from the last recovery, when the loop ends (recover_sfs.c). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/clock.h"
#include "core/context.h"
#include "frig/retarget.h"
#include "model/model.h"
#include "retarget/retarget.h"
#include "rig/rig.h"
#include "workspace/photoset.h"

frig_status fr_rt_retarget_later_round(frig_ctx *ctx, const frig_model *model, frig_photoset *set,
                                       const frig_clouds *clouds, frig_rig *rig) {
    int id_loop = fr_param_int(ctx, FRIG_PARAM_RETARGET_LOOP_IDENTITY_ITERATIONS);
    int deform_loop = fr_param_int(ctx, FRIG_PARAM_RETARGET_LOOP_DEFORM_ITERATIONS);
    double id = fr_param(ctx, FRIG_PARAM_RETARGET_IDENTITY_ITERATIONS);
    double deform = fr_param(ctx, FRIG_PARAM_RETARGET_DEFORM_ITERATIONS);
    frig_status s = FRIG_OK;
    if (id_loop >= 0) s = frig_ctx_set_param(ctx, FRIG_PARAM_RETARGET_IDENTITY_ITERATIONS, id_loop);
    if (!s && deform_loop > 0) s = frig_ctx_set_param(ctx, FRIG_PARAM_RETARGET_DEFORM_ITERATIONS, deform_loop);
    if (!s) s = frig_retarget(ctx, model, set, clouds, rig);
    frig_ctx_set_param(ctx, FRIG_PARAM_RETARGET_IDENTITY_ITERATIONS, id);
    frig_ctx_set_param(ctx, FRIG_PARAM_RETARGET_DEFORM_ITERATIONS, deform);
    return s;
}

frig_status frig_retarget_refine(frig_ctx *ctx, const frig_model *model, frig_photoset *set, frig_clouds **clouds,
                                 frig_rig *rig, frig_clouds_fn recover, void *user) {
    if (!model || !set || !clouds || !*clouds || !rig)
        return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_retarget_refine: NULL argument");
    int rounds = fr_param_int(ctx, FRIG_PARAM_RETARGET_ITERATIONS);
    /* Without a way to recover the clouds, later rounds would fit the same clouds' noise again. */
    int fixed = fr_param_int(ctx, FRIG_PARAM_RETARGET_FIXED_CLOUD_ROUNDS);
    if (!recover && rounds > fixed) rounds = fixed;
    double stop = fr_param(ctx, FRIG_PARAM_RETARGET_STOP_MM);
    int fr = frig_model_region_find(model, "face"), first = 0, nf = 0;
    if (fr < 0 || frig_model_region(model, fr, NULL, &first, &nf) || first != 0)
        return fr_error(ctx, FRIG_ERR_UNSUPPORTED, "the model has no face region starting at vertex 0");
    set->rt_rounds = 0; /* this run's rounds only */
    size_t with = 0;
    for (size_t i = 0; i < set->count; i++) with += frig_clouds_count(*clouds, i) > 0;
    /* too few to beat the fit (one cloud: docs/retarget.md): the rig stays; none is frig_retarget's error */
    if (with > 0 && (double)with < fr_param(ctx, FRIG_PARAM_RETARGET_MIN_CLOUDS)) return FRIG_OK;
    float *before = malloc(sizeof(float) * 3 * (size_t)nf);
    if (!before) return fr_nomem(ctx, "the outer loop");
    frig_status s = FRIG_OK;
    int defer = ctx->rt_defer_albedo;
    fr_rt_pending_albedo_drop(ctx);
    ctx->rt_defer_albedo = 1;
    for (int r = 0; r < rounds && !s; r++) {
        fr_stopwatch t0 = fr_stopwatch_start();
        double part[3] = {0, 0, 0}, c0 = fr_cpu_seconds(); /* CPU s: refit, recovery, retarget */
        if (r > 0) {
            s = frig_fit_rig(ctx, model, rig, set);
            part[0] = fr_cpu_seconds() - c0;
            if (!s && recover) s = recover(user, ctx, model, rig, set, clouds);
            part[1] = fr_cpu_seconds() - c0 - part[0];
        }
        memcpy(before, frig_rig_neutral(rig), sizeof(float) * 3 * (size_t)nf);
        if (!s) s = r > 0 ? fr_rt_retarget_later_round(ctx, model, set, *clouds, rig) : frig_retarget(ctx, model, set, *clouds, rig);
        double wall = 0, cpu = 0;
        fr_stopwatch_read(&t0, &wall, &cpu);
        part[2] = cpu - part[0] - part[1];
        if (s) break;
        const float *after = frig_rig_neutral(rig);
        double change = 0, rms = 0;
        for (int v = 0; v < nf; v++) {
            double d = 0;
            for (int k = 0; k < 3; k++) d += (after[3 * v + k] - before[3 * v + k]) * (after[3 * v + k] - before[3 * v + k]);
            change += sqrt(d) / nf;
        }
        fr_retarget_round q = {1e3 * change, 0, 0};
        for (size_t i = 0; i < set->count; i++)
            if (set->photos[i].retargeted && isfinite(set->photos[i].rt_rms_mm)) q.photos++, rms += set->photos[i].rt_rms_mm;
        q.rms_mm = q.photos ? rms / q.photos : NAN;
        s = fr_photoset_add_retarget_round(ctx, set, &q);
        fr_log(ctx, FRIG_LOG_INFO, "retarget round %d: %.1f s, neutral moved %.3f mm, %d photos, cloud RMS %.2f mm",
               r + 1, wall, q.change_mm, q.photos, q.rms_mm);
        fr_log(ctx, FRIG_LOG_DEBUG, "retarget round %d: %.1f CPU s (refit %.1f, clouds %.1f, retarget %.1f)", r + 1, cpu,
               part[0], part[1], part[2]);
        if (q.change_mm < stop) break;
    }
    if (!s) s = fr_rt_pending_albedo_finish(ctx);
    fr_rt_pending_albedo_drop(ctx);
    ctx->rt_defer_albedo = defer;
    free(before);
    return s;
}
