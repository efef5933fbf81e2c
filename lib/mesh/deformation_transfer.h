/* Deformation transfer (Sumner & Popovic 2004): the deformation of a source mesh from its
 * rest shape to an expression, given per triangle as a deformation gradient T (3 x 3, with
 * the fourth vertex along the normal: T = [e1' e2' n'] [e1 e2 n]^-1), moved onto another rest
 * shape of the same topology. The target's displacement u minimizes
 *     sum_t area_t |grad_t u - (T_t - I)|^2 + anchor sum_{v anchored} |u_v - a_v|^2
 * (grad_t: the gradient of the piecewise-linear displacement over the target's triangle t),
 * whose normal equations are the target's cotangent Laplacian: factored once, solved for every
 * shape and coordinate at once. This is the retargeting term D(B_0, B_0^t, B_j^t) of the
 * paper's eq. 5.16. Internal. */
#ifndef FR_MESH_DEFORMATION_TRANSFER_H
#define FR_MESH_DEFORMATION_TRANSFER_H

#include <stdint.h>

#include "frig/frig.h"

/* Sumner's frame of triangle (a, b, c): columns b - a, c - a, n / sqrt|n| with n = (b - a) x
 * (c - a); row-major 3 x 3. */
void fr_triangle_frame(const double a[3], const double b[3], const double c[3], double V[9]);

/* Deformation gradient T = V_def V_rest^-1 of one triangle (row-major). Returns 0 for a
 * degenerate rest triangle (T = I then). */
int fr_deformation_gradient(const double rest[3][3], const double def[3][3], double T[9]);

typedef struct fr_dtransfer fr_dtransfer;

/* Transfer from source_rest onto target_rest (3 floats per vertex each; copied), over the
 * triangles (borrowed). anchored (nv flags, may be NULL = none) marks vertices held at the
 * displacement given to fr_dtransfer_apply; with no anchor the mean displacement is fixed to
 * the source's. */
frig_status fr_dtransfer_create(frig_ctx *ctx, int nv, const int32_t *tris, int nt, const float *source_rest,
                                const float *target_rest, const uint8_t *anchored, fr_dtransfer **out);
void fr_dtransfer_free(fr_dtransfer *dt);

/* For each of nshapes source deformations (source_rest + source_deltas[k], 3 nv floats per
 * shape) the target's displacement out[k] (3 nv floats per shape); anchored vertices are held
 * at anchor_deltas[k] (NULL: at the source's own deltas). */
frig_status fr_dtransfer_apply(frig_ctx *ctx, fr_dtransfer *dt, int nshapes, const float *source_deltas,
                               const float *anchor_deltas, float *out);

#endif
