/* The model file the subcommands use: --model FILE, else the default path
 * (frig_model_default_path), with a hint on how to import one when it is missing. */
#include <stdio.h>

#include "cli.h"

int cli_model_path(cli_env *env, const char *cmd, const char *given, char *buf, size_t size) {
    if (given) {
        snprintf(buf, size, "%s", given);
        return CLI_OK;
    }
    if (frig_model_default_path(env->ctx, buf, size)) return cli_fail(env, cmd);
    return CLI_OK;
}

int cli_load_model(cli_env *env, const char *cmd, const char *given, frig_model **m) {
    char path[4096];
    int rc = cli_model_path(env, cmd, given, path, sizeof path);
    if (rc) return rc;
    if (frig_model_load(env->ctx, path, m)) {
        cli_fail(env, cmd);
        fprintf(stderr, "(import one with: frig model import-ict DIR -o %s)\n", path);
        return CLI_FAILED;
    }
    return CLI_OK;
}
