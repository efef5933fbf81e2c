/* The errors of a reconstructed rig against a synthetic subject's true rig (paper section 7.2,
 * bench/rig_score.h): the neutral's mean vertex distance after a similarity alignment, E_B (the
 * same for every blendshape, neutral + delta, each aligned on its own, averaged over the shapes)
 * and the delta error (mean distance between the estimated and true deltas, no alignment, over
 * the vertices the true shape moves by more than 0.1 mm). Over the face region (ICT vertices
 * 0-9408), in mm.
 * Printed for the rig given and, as baselines, the model-space rig of the fitted identity (what
 * the fit alone gives; the same as the rig until retarget lands) and the model's mean face.
 *
 *   rig_error RUN_DIR TRUE_RIG MODEL
 *
 * RUN_DIR is a frig run folder (its rig/rig.frigrig and report.json). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "frig/frig.h"
#include "rig_score.h"

#define FACE_VERTICES 9409

int main(int argc, char **argv) {
    if (argc != 4) {
        fprintf(stderr, "usage: rig_error RUN_DIR TRUE_RIG MODEL\n");
        return 2;
    }
    frig_ctx *ctx = frig_ctx_create();
    char path[4200];
    snprintf(path, sizeof path, "%s/rig/rig.frigrig", argv[1]);
    frig_rig *est = NULL, *truth = NULL, *model_rig = NULL, *mean = NULL;
    frig_model *model = NULL;
    frig_photoset *set = NULL;
    const double *identity = NULL;
    if (frig_rig_load(ctx, path, &est) || frig_rig_load(ctx, argv[2], &truth) || frig_model_load(ctx, argv[3], &model) ||
        frig_photoset_load(ctx, argv[1], &set) || !frig_photoset_identity(set, &identity) ||
        frig_rig_from_model(ctx, model, identity, &model_rig) || frig_rig_from_model(ctx, model, NULL, &mean)) {
        fprintf(stderr, "rig_error: %s\n", frig_ctx_errmsg(ctx));
        return 1;
    }
    const struct {
        const char *name;
        const frig_rig *rig;
    } rows[] = {{"the run's rig", est}, {"model-space rig (fit)", model_rig}, {"mean face", mean}};
    printf("%-24s %12s %10s %10s %7s\n", "rig vs truth (face)", "neutral mm", "E_B mm", "delta mm", "shapes");
    for (int i = 0; i < 3; i++) {
        rig_score e = rig_score_rig(truth, rows[i].rig, FACE_VERTICES);
        printf("%-24s %12.3f %10.3f %10.3f %7d\n", rows[i].name, e.neutral_mm, e.eb_mm, e.delta_mm, e.shapes);
    }
    frig_rig_free(est), frig_rig_free(truth), frig_rig_free(model_rig), frig_rig_free(mean);
    frig_photoset_free(set);
    frig_model_free(model);
    frig_ctx_free(ctx);
    return 0;
}
