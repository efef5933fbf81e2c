/* The face's size as a linear function of the identity (docs/fit.md, "The
 * head's size"). Internal. */
#ifndef FR_MODEL_FACE_SIZE_H
#define FR_MODEL_FACE_SIZE_H

#include "frig/frig.h"

/* g[k] = the relative change of the face's size per unit of identity mode k
 * (first order), the size being the RMS distance of the "face" region's
 * vertices (all vertices when the model names no such region) from their
 * centroid on the model's mean: for identity weights w the face is (1 + g . w)
 * times the mean face's size. n_id values. */
frig_status fr_face_size_gradient(frig_ctx *ctx, const frig_model *model,
                                  int n_id, double *g);

/* Solve H x = b for the identity step with the face's size held: x minimizes
 * x^T H x / 2 - b^T x subject to g . (w - x) = 0, i.e. the new identity w - x
 * has the mean face's size (to first order). H (n x n, SPD, overwritten) and b
 * (overwritten by x). */
frig_status fr_solve_size_held(frig_ctx *ctx, int n, double *H, double *b,
                               const double *w, const double *g);

#endif
