/* frig fit -w WORKSPACE: the progressive model fit (paper sections 4.3-4.4). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <frig/fit.h>
#include <frig/rig.h>

#include "cli.h"

const char cmd_fit_usage[] =
    "usage: frig fit -w WORKSPACE [--model FILE] [--no-overlays]\n"
    "\n"
    "Fit the face model to every usable photo of the workspace (after frig detect and frig\n"
    "filter): a camera, head pose and expression weights per photo and one identity for the\n"
    "subject, by the paper's progressive scheme (individual fits, subset selection, joint\n"
    "identity on the best 0.4 / 0.6 / 0.8, final fits). Updates WORKSPACE/report.json, writes\n"
    "the subject's model-space rig to WORKSPACE/rig/rig.frigrig and overlays of the fitted\n"
    "mesh to WORKSPACE/overlays/fit/.\n"
    "\n"
    "  -w, --workspace DIR   the workspace folder\n"
    "  --model FILE          the model file (default: $FRIG_MODEL or the user data folder)\n"
    "  --no-overlays         skip the overlay pictures\n"
    "Parameters: fit.* (frig help params).\n";

int cmd_fit(cli_env *env, int argc, char **argv) {
    const char *ws = NULL, *model_path = NULL;
    int overlays = 1;
    for (int i = 0; i < argc; i++) {
        if ((!strcmp(argv[i], "-w") || !strcmp(argv[i], "--workspace")) && i + 1 < argc) ws = argv[++i];
        else if (!strcmp(argv[i], "--model") && i + 1 < argc) model_path = argv[++i];
        else if (!strcmp(argv[i], "--no-overlays")) overlays = 0;
        else return cli_usage_error("fit", "unexpected argument '%s' (see frig help fit)", argv[i]);
    }
    if (!ws) return cli_usage_error("fit", "no workspace given (-w DIR)");
    frig_model *model = NULL;
    frig_photoset *set = NULL;
    frig_rig *rig = NULL;
    int rc = cli_load_model(env, "fit", model_path, &model);
    if (rc) return rc;
    if (frig_photoset_load(env->ctx, ws, &set) || frig_fit(env->ctx, model, set) ||
        frig_photoset_save(env->ctx, set, ws)) {
        rc = cli_fail(env, "fit");
        goto done;
    }
    const double *identity;
    frig_photoset_identity(set, &identity);
    char path[4096];
    snprintf(path, sizeof path, "%s/rig", ws);
    if (frig_rig_from_model(env->ctx, model, identity, &rig) || cli_make_dir(env, path) ||
        (snprintf(path, sizeof path, "%s/rig/rig.frigrig", ws), frig_rig_save(env->ctx, rig, path))) {
        rc = cli_fail(env, "fit");
        goto done;
    }
    if (overlays) {
        snprintf(path, sizeof path, "%s/overlays/fit", ws);
        if (frig_fit_write_overlays(env->ctx, model, set, path)) {
            rc = cli_fail(env, "fit");
            goto done;
        }
    }
    size_t n = frig_photoset_count(set), fitted = 0, joint = 0, failed = 0;
    double sum = 0;
    for (size_t i = 0; i < n; i++) {
        if (!frig_photoset_fitted(set, i)) continue;
        if (frig_photoset_status(set, i) == FRIG_PHOTO_FIT_FAILED) failed++;
        fitted++;
        joint += frig_photoset_fit_in_joint(set, i);
        sum += frig_photoset_fit_error(set, i);
    }
    cli_note(env, "fitted %zu photo%s (%zu in the final joint subset, %zu failed); mean landmark error %.2f px",
             fitted, fitted == 1 ? "" : "s", joint, failed, fitted ? sum / fitted : 0.0);
done:
    frig_rig_free(rig);
    frig_photoset_free(set);
    frig_model_free(model);
    return rc;
}
