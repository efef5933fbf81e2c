/* Which parts of the ICT head move how in a synthetic subject (paper section 7.2's ground
 * truth must stay a plausible head): skin deforms smoothly, eyeballs and teeth move rigidly,
 * gums follow the teeth, eyelashes and the transparent eye overlays follow the lids. */
#include <stdlib.h>
#include <string.h>

#include "synth/synth.h"

int fr_synth_region(const frig_model *model, const char *name, int *first, int *count) {
    int r = frig_model_region_find(model, name);
    if (r < 0) return 0;
    return frig_model_region(model, r, NULL, first, count) == FRIG_OK && *count > 0;
}

static void mark(const frig_model *model, const char *name, uint8_t cls, uint8_t *out) {
    int first, count;
    if (!fr_synth_region(model, name, &first, &count)) return;
    memset(out + first, cls, (size_t)count);
}

uint8_t *fr_synth_vertex_classes(const frig_model *model) {
    int nv = frig_model_vertex_count(model);
    uint8_t *c = calloc((size_t)nv, 1); /* FR_SYNTH_SKIN = 0 */
    if (!c) return NULL;
    static const char *const rigid[] = {"eyeball_left", "eyeball_right", "teeth"};
    static const char *const overlay[] = {"lacrimal_fluid_left", "lacrimal_fluid_right", "eye_blend_left",
                                          "eye_blend_right",     "eye_occlusion_left",   "eye_occlusion_right",
                                          "eyelashes_left",      "eyelashes_right"};
    for (size_t i = 0; i < sizeof rigid / sizeof rigid[0]; i++) mark(model, rigid[i], FR_SYNTH_RIGID, c);
    mark(model, "gums_tongue", FR_SYNTH_GUMS, c);
    for (size_t i = 0; i < sizeof overlay / sizeof overlay[0]; i++) mark(model, overlay[i], FR_SYNTH_OVERLAY, c);
    return c;
}

/* Centroid of a region of xyz (3 per vertex); 0 when the region is absent. */
int fr_synth_region_centroid(const frig_model *model, const char *name, const float *xyz, double c[3]) {
    int first, count;
    c[0] = c[1] = c[2] = 0.0;
    if (!fr_synth_region(model, name, &first, &count)) return 0;
    for (int i = first; i < first + count; i++)
        for (int d = 0; d < 3; d++) c[d] += xyz[3 * (size_t)i + d];
    for (int d = 0; d < 3; d++) c[d] /= count;
    return 1;
}
