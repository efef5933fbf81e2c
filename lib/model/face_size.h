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
frig_status fr_face_size_gradient(frig_ctx *ctx, const frig_model *model, int n_id, double *g);

/* g . w: the face's relative size change for identity weights w (first order). */
double fr_face_size_change(const double *g, const double *w, int n_id);

/* Solve H x = b subject to g . x = t (a Lagrange multiplier on one Cholesky factor): the
 * identity step with the face's size held, t chosen so the new identity has g . w = 0 (for
 * w_new = w - x, t = g . w). H (n x n, SPD) is overwritten by its factor, b by x. */
frig_status fr_solve_size_held(frig_ctx *ctx, int n, double *H, double *b, const double *g, double t);

#endif
