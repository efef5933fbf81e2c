/* Pieces several subcommands share: folders, writing a rig for users. */
#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

#include "cli.h"

int cli_make_dir(cli_env *env, const char *path) {
    char buf[4096];
    snprintf(buf, sizeof buf, "%s", path);
    for (char *c = buf + 1;; c++) {
        if (*c == '/' || *c == 0) {
            char keep = *c;
            *c = 0;
            if (mkdir(buf, 0755) != 0 && errno != EEXIST) {
                if (env->progress_shown) fputc('\n', stderr), env->progress_shown = 0;
                fprintf(stderr, "frig: cannot create folder %s: %s\n", buf, strerror(errno));
                return CLI_FAILED;
            }
            *c = keep;
            if (!keep) break;
        }
    }
    return CLI_OK;
}

int cli_export_rig(cli_env *env, const char *cmd, const frig_rig *rig, const char *out) {
    char path[4096];
    if ((size_t)snprintf(path, sizeof path, "%s/shapes", out) >= sizeof path)
        return cli_usage_error(cmd, "output path too long");
    if (frig_rig_save_obj(env->ctx, rig, path)) return cli_fail(env, cmd);
    snprintf(path, sizeof path, "%s/rig.glb", out);
    if (frig_rig_save_gltf(env->ctx, rig, path)) return cli_fail(env, cmd);
    printf("%s/rig.glb and %s/shapes/ (neutral.obj + %d shapes)\n", out, out, frig_rig_target_count(rig));
    printf("targets (%d):", frig_rig_target_count(rig));
    for (int i = 0; i < frig_rig_target_count(rig); i++) printf(" %s", frig_rig_target_name(rig, i));
    printf("\nARKit names not provided:");
    int missing = 0;
    for (int i = 0; i < frig_arkit_name_count(); i++)
        if (!frig_rig_provides_arkit(rig, frig_arkit_name(i))) printf(" %s", frig_arkit_name(i)), missing++;
    printf("%s\n", missing ? "" : " none");
    return CLI_OK;
}
