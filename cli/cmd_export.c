/* frig export -w WORKSPACE -o OUT: the workspace's current rig, in the files users load. */
#include <stdio.h>
#include <string.h>

#include "cli.h"

const char cmd_export_usage[] =
    "usage: frig export -w WORKSPACE -o OUT [--model FILE]\n"
    "\n"
    "Write the workspace's current rig as OUT/rig.glb (glTF 2.0, metres, ARKit-named morph\n"
    "targets) and OUT/shapes/*.obj (neutral + one full shape per blendshape, ICT vertex order).\n"
    "The current rig is WORKSPACE/rig/rig.frigrig, written by frig fit (the subject's\n"
    "model-space rig) and replaced by later stages. Without it, the rig is made from the model\n"
    "and the identity in WORKSPACE/report.json.\n";

int cmd_export(cli_env *env, int argc, char **argv) {
    const char *ws = NULL, *out = NULL, *model_path = NULL;
    for (int i = 0; i < argc; i++) {
        if ((!strcmp(argv[i], "-w") || !strcmp(argv[i], "--workspace")) && i + 1 < argc) ws = argv[++i];
        else if (!strcmp(argv[i], "-o") && i + 1 < argc) out = argv[++i];
        else if (!strcmp(argv[i], "--model") && i + 1 < argc) model_path = argv[++i];
        else return cli_usage_error("export", "unexpected argument '%s' (see frig help export)", argv[i]);
    }
    if (!ws || !out) return cli_usage_error("export", "both -w WORKSPACE and -o OUT are needed");
    char path[4096];
    snprintf(path, sizeof path, "%s/rig/rig.frigrig", ws);
    frig_rig *rig = NULL;
    frig_status s = frig_rig_load(env->ctx, path, &rig);
    if (s == FRIG_ERR_NOT_FOUND) {
        frig_model *model = NULL;
        frig_photoset *set = NULL;
        int rc = cli_load_model(env, "export", model_path, &model);
        if (rc) return rc;
        const double *identity = NULL;
        if (frig_photoset_load(env->ctx, ws, &set)) rc = cli_fail(env, "export");
        else if (frig_photoset_identity(set, &identity) == 0)
            rc = cli_usage_error("export", "%s has no fitted identity yet (run frig fit first)", ws);
        else if (frig_rig_from_model(env->ctx, model, identity, &rig)) rc = cli_fail(env, "export");
        frig_photoset_free(set);
        frig_model_free(model);
        if (rc) return rc;
    } else if (s) {
        return cli_fail(env, "export");
    }
    int rc = cli_export_rig(env, "export", rig, out);
    frig_rig_free(rig);
    return rc;
}
