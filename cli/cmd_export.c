/* frig export -w WORKSPACE -o OUT: the workspace's current rig, in the files users load. */
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "cli.h"

const char cmd_export_usage[] =
    "usage: frig export -w WORKSPACE -o OUT|NAME.glb [--model FILE] [--texture PNG | --no-texture]\n"
    "\n"
    "Write the workspace's current rig as OUT/rig.glb (glTF 2.0, metres, ARKit-named morph\n"
    "targets, painted eyes, ICT's eye overlays alpha-blended) and OUT/shapes/*.obj (neutral +\n"
    "one full shape per blendshape, ICT vertex order, frig.mtl and its textures); with -o\n"
    "NAME.glb, that file and NAME_shapes/ beside it. The current rig is\n"
    "WORKSPACE/rig/rig.frigrig, written by frig fit (the subject's model-space rig) and replaced\n"
    "by frig retarget (the personalized rig). Without it, the rig is made from the model and the\n"
    "identity in WORKSPACE/report.json. The face's base-colour texture is\n"
    "WORKSPACE/textures/albedo.png when it exists (the sfs stage writes it; ICT's face UV\n"
    "layout), or --texture PNG.\n"
    "Parameters: export.* (frig help params).\n";

int cmd_export(cli_env *env, int argc, char **argv) {
    const char *ws = NULL, *out = NULL, *model_path = NULL, *texture = NULL;
    int no_texture = 0;
    for (int i = 0; i < argc; i++) {
        if ((!strcmp(argv[i], "-w") || !strcmp(argv[i], "--workspace")) && i + 1 < argc) ws = argv[++i];
        else if (!strcmp(argv[i], "-o") && i + 1 < argc) out = argv[++i];
        else if (!strcmp(argv[i], "--model") && i + 1 < argc) model_path = argv[++i];
        else if (!strcmp(argv[i], "--texture") && i + 1 < argc) texture = argv[++i];
        else if (!strcmp(argv[i], "--no-texture")) no_texture = 1;
        else return cli_usage_error("export", "unexpected argument '%s' (see frig help export)", argv[i]);
    }
    if (!ws || !out) return cli_usage_error("export", "both -w WORKSPACE and -o OUT are needed");
    char albedo[4096];
    snprintf(albedo, sizeof albedo, "%s/textures/albedo.png", ws);
    if (!texture && !no_texture && access(albedo, F_OK) == 0) texture = albedo;
    if (no_texture) texture = NULL;
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
    int rc = cli_export_rig(env, "export", rig, out, texture);
    frig_rig_free(rig);
    return rc;
}
