/* The model vertices the fit stage matches the 68 detected landmarks to (docs/fit.md, "The
 * landmarks' vertices"). */
#ifndef FR_FIT_LANDMARK_VERTICES_H
#define FR_FIT_LANDMARK_VERTICES_H

#include <stdint.h>

#include "frig/core.h"
#include "frig/model.h"

/* The 68 vertices: for ICT-FaceKit's model with fit.landmark_vertices = 1 the nostrils' wings
 * (31-35) and the mouth (48-67) at the vertices where the landmark detector puts them; else
 * (another model, or 0, the default) the model's own landmark vertices. */
void fr_fit_landmark_vertices(const frig_ctx *ctx, const frig_model *model, int32_t out[68]);

#endif
