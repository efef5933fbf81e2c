/* frig sfs -w WORKSPACE: per-photo point clouds from shading (paper section 5.1). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <frig/frig.h>

#include "cli.h"

const char cmd_sfs_usage[] =
    "usage: frig sfs -w WORKSPACE [--no-overlays]\n"
    "\n"
    "Recover the face's shape from the shading of every fitted photo of the workspace (after\n"
    "frig fit): the skin region, the subject's albedo and each photo's lighting, a shape shared\n"
    "by all photos, then each photo's own depth, kept where the shading is explained (eq. 5.15).\n"
    "Writes WORKSPACE/clouds/<photo>.ply (binary PLY, metres, the rig's head frame, with normals\n"
    "and confidence), WORKSPACE/textures/albedo.png (the subject's albedo in the model's UV\n"
    "layout), WORKSPACE/overlays/sfs/<photo>.jpg (skin, synthesized shading, error, kept region)\n"
    "and updates WORKSPACE/report.json (pixels kept, shading error, lighting, refined pose;\n"
    "photos whose face cannot be read become sfs_failed with the reason). Reads the current rig\n"
    "WORKSPACE/rig/rig.frigrig.\n"
    "\n"
    "  -w, --workspace DIR   the workspace folder\n"
    "  --no-overlays         skip the pictures\n"
    "  --model FILE          the model file, read when sfs.identity_modes > 0 (default: $FRIG_MODEL or the user\n"
    "                        data folder)\n"
    "Parameters: sfs.* (frig help params; docs/sfs.md).\n";

int cmd_sfs(cli_env *env, int argc, char **argv) {
    const char *ws = NULL, *model_path = NULL;
    int overlays = 1;
    for (int i = 0; i < argc; i++) {
        if ((!strcmp(argv[i], "-w") || !strcmp(argv[i], "--workspace")) && i + 1 < argc) ws = argv[++i];
        else if (!strcmp(argv[i], "--no-overlays")) overlays = 0;
        else if (!strcmp(argv[i], "--model") && i + 1 < argc) model_path = argv[++i];
        else return cli_usage_error("sfs", "unexpected argument '%s' (see frig help sfs)", argv[i]);
    }
    if (!ws) return cli_usage_error("sfs", "no workspace given (-w DIR)");
    frig_photoset *set = NULL;
    frig_rig *rig = NULL;
    frig_clouds *clouds = NULL;
    frig_image *albedo = NULL;
    frig_model *model = NULL;
    int rc = CLI_OK;
    char path[4096], dir[4096];
    snprintf(path, sizeof path, "%s/rig/rig.frigrig", ws);
    snprintf(dir, sizeof dir, "%s/overlays/sfs", ws);
    if (frig_photoset_load(env->ctx, ws, &set) || frig_rig_load(env->ctx, path, &rig)) {
        rc = cli_fail(env, "sfs");
        goto done;
    }
    /* the model's identity modes in the shared solve (sfs.identity_modes; 0: no model read) */
    if (frig_ctx_get_param(env->ctx, FRIG_PARAM_SFS_IDENTITY_MODES) > 0 &&
        (rc = cli_load_model(env, "sfs", model_path, &model)) != CLI_OK)
        goto done;
    if (frig_sfs_with_model(env->ctx, model, rig, set, overlays ? dir : NULL, &clouds, &albedo) ||
        frig_clouds_save(env->ctx, clouds, set, ws)) {
        rc = cli_fail(env, "sfs");
        goto done;
    }
    snprintf(dir, sizeof dir, "%s/textures", ws);
    snprintf(path, sizeof path, "%s/textures/albedo.png", ws);
    if (cli_make_dir(env, dir) || frig_image_save_png(env->ctx, albedo, path) || frig_photoset_save(env->ctx, set, ws)) {
        rc = rc ? rc : cli_fail(env, "sfs");
        goto done;
    }
    size_t n = frig_photoset_count(set), with = 0, failed = 0, points = 0;
    for (size_t i = 0; i < n; i++) {
        if (!frig_photoset_sfs_done(set, i)) continue;
        if (frig_photoset_status(set, i) == FRIG_PHOTO_SFS_FAILED) failed++;
        size_t c = frig_clouds_count(clouds, i);
        with += c > 0;
        points += c;
    }
    char words[160];
    cli_note(env, "sfs: %zu cloud%s (%zu points in all), %zu photo%s sfs_failed, %s; albedo in %s", with,
             with == 1 ? "" : "s", points, failed, failed == 1 ? "" : "s", cli_sfs_solve_words(set, words, sizeof words),
             path);
done:
    frig_image_free(albedo);
    frig_clouds_free(clouds);
    frig_rig_free(rig);
    frig_photoset_free(set);
    frig_model_free(model);
    return rc;
}
