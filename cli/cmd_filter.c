/* frig filter -w WORKSPACE: robust-PCA failure detection (paper section 4.2, Algorithm 1). */
#include <stdio.h>
#include <string.h>

#include "cli.h"

const char cmd_filter_usage[] =
    "usage: frig filter -w WORKSPACE\n"
    "\n"
    "Drop the photos whose detected face the rest of the set cannot explain (Algorithm 1:\n"
    "robust PCA shape and texture models, error e = w_t RMSE(texture) + w_s sum |p - p'|^2,\n"
    "drop e > mu + omega sigma, repeat until none is dropped). In photos with several faces the\n"
    "subject becomes the face most consistent with the others. Updates WORKSPACE/report.json\n"
    "(status outlier with the error and the round) and writes\n"
    "WORKSPACE/filter_contact_sheet.png (the warped faces, dropped ones framed in red).\n"
    "Parameters: filter.* (frig help params).\n";

int cmd_filter(cli_env *env, int argc, char **argv) {
    const char *ws = NULL;
    for (int i = 0; i < argc; i++) {
        if ((!strcmp(argv[i], "-w") || !strcmp(argv[i], "--workspace")) && i + 1 < argc) ws = argv[++i];
        else return cli_usage_error("filter", "unexpected argument '%s' (see frig help filter)", argv[i]);
    }
    if (!ws) return cli_usage_error("filter", "no workspace given (-w DIR)");
    frig_photoset *set = NULL;
    char sheet[4096];
    snprintf(sheet, sizeof sheet, "%s/filter_contact_sheet.png", ws);
    if (frig_photoset_load(env->ctx, ws, &set) || frig_filter(env->ctx, set, sheet) ||
        frig_photoset_save(env->ctx, set, ws)) {
        frig_photoset_free(set);
        return cli_fail(env, "filter");
    }
    size_t n = frig_photoset_count(set), filtered = 0, dropped = 0, usable = 0;
    for (size_t i = 0; i < n; i++) {
        int round;
        usable += frig_photoset_status(set, i) == FRIG_PHOTO_OK;
        if (!frig_photoset_filter(set, i, NULL, NULL, NULL, &round)) continue;
        filtered++;
        dropped += round > 0;
    }
    if (filtered)
        cli_note(env, "filter: %zu photos checked, %zu dropped as outliers, %zu kept", filtered, dropped,
                 filtered - dropped);
    else
        cli_note(env, "filter: %zu usable photo%s kept unchecked (too few to tell outliers)", usable,
                 usable == 1 ? "" : "s");
    frig_photoset_free(set);
    return CLI_OK;
}
