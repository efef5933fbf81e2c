/* frig retarget -w WORKSPACE: the personalized rig from the photos' point clouds, with the
 * outer refit loop (paper sections 5.2-5.3, Algorithms 3, 6, 7). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <frig/frig.h>

#include "cli.h"

const char cmd_retarget_usage[] =
    "usage: frig retarget -w WORKSPACE [--model FILE] [--iterations N] [--fixed-clouds]\n"
    "\n"
    "Personalize the workspace's rig beyond the model's span from the photos' point clouds\n"
    "(WORKSPACE/clouds/, written by the sfs stage): per photo the current reconstruction is\n"
    "deformed onto its cloud, the neutral is solved from all of them, then the blendshapes and\n"
    "each photo's expression weights in turn; the rest of the head (neck, ears, eyes, teeth,\n"
    "gums, mouth) follows the face. Then the outer loop: every photo is fitted again on the new\n"
    "rig and the stage runs again, retarget.iterations rounds in all (default 1; the paper runs 3), stopping\n"
    "early when a round moves the neutral by less than retarget.stop_mm on average. Each later\n"
    "round recovers the clouds with the new rig (the sfs stage, sfs.* parameters) and writes\n"
    "them to WORKSPACE/clouds/ and the albedo to WORKSPACE/textures/albedo.png. With\n"
    "--fixed-clouds the clouds stay as they are and at most retarget.fixed_cloud_rounds rounds\n"
    "run (more would fit the same clouds' noise again).\n"
    "Reads WORKSPACE/rig/rig.frigrig (frig fit's model-space rig, or an earlier personalized\n"
    "one) and replaces it; updates WORKSPACE/report.json (each photo's weights and\n"
    "correspondence figures, each round's figures) and draws the rig before and after in\n"
    "WORKSPACE/overlays/retarget/rigs.png. frig export writes the result.\n"
    "\n"
    "  -w, --workspace DIR   the workspace folder\n"
    "  --model FILE          the model file (default: $FRIG_MODEL or the user data folder)\n"
    "  --iterations N        outer rounds (sets retarget.iterations and fixed_cloud_rounds)\n"
    "  --fixed-clouds        keep WORKSPACE/clouds/ (do not run the sfs stage again)\n"
    "Parameters: retarget.*, fit.*, sfs.* (frig help params).\n";

int cmd_retarget(cli_env *env, int argc, char **argv) {
    const char *ws = NULL, *model_path = NULL;
    int fixed_clouds = 0;
    for (int i = 0; i < argc; i++) {
        if ((!strcmp(argv[i], "-w") || !strcmp(argv[i], "--workspace")) && i + 1 < argc) ws = argv[++i];
        else if (!strcmp(argv[i], "--model") && i + 1 < argc) model_path = argv[++i];
        else if (!strcmp(argv[i], "--iterations") && i + 1 < argc) {
            char *end;
            double v = strtod(argv[++i], &end);
            if (*end || frig_ctx_set_param(env->ctx, FRIG_PARAM_RETARGET_ITERATIONS, v) ||
                frig_ctx_set_param(env->ctx, FRIG_PARAM_RETARGET_FIXED_CLOUD_ROUNDS, v))
                return cli_usage_error("retarget", "--iterations wants a whole number from 1 to 20, not '%s'", argv[i]);
        } else if (!strcmp(argv[i], "--fixed-clouds"))
            fixed_clouds = 1;
        else
            return cli_usage_error("retarget", "unexpected argument '%s' (see frig help retarget)", argv[i]);
    }
    if (!ws) return cli_usage_error("retarget", "no workspace given (-w DIR)");
    frig_model *model = NULL;
    frig_photoset *set = NULL;
    frig_rig *rig = NULL, *before = NULL;
    frig_clouds *clouds = NULL;
    frig_image *albedo = NULL;
    char path[4096];
    snprintf(path, sizeof path, "%s/rig/rig.frigrig", ws);
    int rc = cli_load_model(env, "retarget", model_path, &model);
    if (rc) return rc;
    if (frig_photoset_load(env->ctx, ws, &set)) {
        rc = cli_fail(env, "retarget");
        goto done;
    }
    if (frig_rig_load(env->ctx, path, &rig)) {
        if (frig_ctx_status(env->ctx) == FRIG_ERR_NOT_FOUND)
            rc = cli_usage_error("retarget", "%s has no rig yet (run frig fit first)", ws);
        else
            rc = cli_fail(env, "retarget");
        goto done;
    }
    if (frig_clouds_load(env->ctx, set, ws, &clouds)) {
        rc = cli_fail(env, "retarget");
        goto done;
    }
    size_t with_cloud = 0;
    for (size_t i = 0; i < frig_photoset_count(set); i++) with_cloud += frig_clouds_count(clouds, i) > 0;
    if (with_cloud == 0) {
        rc = cli_usage_error("retarget", "%s/clouds has no point cloud of any photo (run the sfs stage first)", ws);
        goto done;
    }
    /* The outer loop recovers the clouds with each new rig by the sfs stage (public API:
     * frig_retarget_recover_sfs calls frig_sfs), keeping the last albedo. */
    if (frig_rig_clone(env->ctx, rig, &before) ||
        frig_retarget_refine(env->ctx, model, set, &clouds, rig, fixed_clouds ? NULL : frig_retarget_recover_sfs,
                             &albedo) ||
        frig_rig_save(env->ctx, rig, path)) {
        rc = cli_fail(env, "retarget");
        goto done;
    }
    if (albedo) { /* the clouds and albedo of the last recovery go with the rig they came from */
        char dir[4096];
        snprintf(dir, sizeof dir, "%s/textures", ws);
        snprintf(path, sizeof path, "%s/textures/albedo.png", ws);
        if ((rc = cli_make_dir(env, dir))) goto done;
        if (frig_clouds_save(env->ctx, clouds, set, ws) || frig_image_save_png(env->ctx, albedo, path)) {
            rc = cli_fail(env, "retarget");
            goto done;
        }
        snprintf(path, sizeof path, "%s/rig/rig.frigrig", ws);
    }
    if (frig_photoset_save(env->ctx, set, ws)) {
        rc = cli_fail(env, "retarget");
        goto done;
    }
    /* The picture: the rig before and after. */
    char sheet[4096];
    snprintf(sheet, sizeof sheet, "%s/overlays/retarget", ws);
    const frig_rig *rows[2] = {before, rig};
    const char *labels[2] = {"before (the rig retarget started from)", "personalized"};
    if ((rc = cli_make_dir(env, sheet))) goto done;
    snprintf(sheet, sizeof sheet, "%s/overlays/retarget/rigs.png", ws);
    if (frig_retarget_write_sheet(env->ctx, model, rows, labels, 2, sheet)) {
        rc = cli_fail(env, "retarget");
        goto done;
    }
    for (int r = 0; r < frig_photoset_retarget_rounds(set); r++) {
        double change, rms;
        int photos;
        frig_photoset_retarget_round(set, r, &change, &photos, &rms);
        cli_note(env, "round %d: %d photo%s, neutral moved %.3f mm, cloud RMS %.2f mm", r + 1, photos,
                 photos == 1 ? "" : "s", change, rms);
    }
    if (frig_photoset_retarget_rounds(set) == 0)
        cli_note(env, "too few photos with a point cloud (under retarget.min_clouds, %g): the rig is left as it was",
                 frig_ctx_get_param(env->ctx, FRIG_PARAM_RETARGET_MIN_CLOUDS));
    else
        cli_note(env, "wrote the personalized rig to %s (frig export -w %s -o OUT writes rig.glb and OBJ files)", path, ws);
done:
    frig_image_free(albedo);
    frig_clouds_free(clouds);
    frig_rig_free(before);
    frig_rig_free(rig);
    frig_photoset_free(set);
    frig_model_free(model);
    return rc;
}
