/* Convex quadratic programs with bounds: minimize 1/2 x^T H x + g^T x subject to
 * lo <= x <= hi (entries may be -inf / +inf), H symmetric positive definite. Used for the
 * expression weights in [0, 1] (fit, eq. 4.8) and later the blendshape weights (retarget).
 * Internal. */
#ifndef FR_LINALG_BOX_QP_H
#define FR_LINALG_BOX_QP_H

#include "frig/frig.h"

/* H is n x n column-major (not modified); x holds a start on entry (clamped into the box)
 * and the solution on return. Primal active-set method: exact in finitely many steps.
 * FRIG_ERR_NUMERIC if a reduced system is not positive definite. */
frig_status fr_box_qp(frig_ctx *ctx, int n, const double *H, const double *g, const double *lo, const double *hi,
                      double *x);

#endif
