/* An albedo texture (the sfs stage's textures/albedo.png layout, docs/workspace.md) against a
 * frig synth subject's painted albedo: at every skin vertex of the face region that no hair,
 * brow or beard covers, the texture's colour at the vertex's UV next to the true linear albedo
 * (ambient occlusion included, as rendered). The texture's scale per channel is free (lighting
 * and albedo trade it), fitted by least squares; a vertex's error is the colour distance in
 * linear RGB over the length of the mean true colour (0.10: a tenth of the skin's brightness).
 * Internal; for tests and benchmarks. */
#ifndef FR_EVAL_ALBEDO_ERROR_H
#define FR_EVAL_ALBEDO_ERROR_H

#include "frig/frig.h"
#include "frig/synth.h"

#define FR_ALBEDO_GROSS 0.5 /* a vertex this far off shows a colour that is not the skin's */

typedef struct fr_albedo_error {
    int vertices;
    double mean, p90, p99;
    double gross; /* share of the vertices over FR_ALBEDO_GROSS */
    double scale[3];
} fr_albedo_error;

/* texture: 3 channels, sRGB. */
frig_status fr_albedo_error_of(frig_ctx *ctx, const frig_synth_subject *subject, const frig_image *texture,
                               fr_albedo_error *out);

#endif
