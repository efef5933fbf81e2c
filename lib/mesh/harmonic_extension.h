/* Values given on some vertices of a triangle mesh carried smoothly over the rest: the harmonic
 * extension (the minimizer of the Dirichlet energy under the cotangent Laplacian, the given
 * vertices held). Used to carry the personalized face's change over the head (retarget's
 * whole_head.c) and the face texture's colour over the back of the head (rig/head_texture.c).
 * Internal. */
#ifndef FR_MESH_HARMONIC_EXTENSION_H
#define FR_MESH_HARMONIC_EXTENSION_H

#include <stdint.h>

#include "frig/core.h"

/* vals: 'fields' blocks of 3 nv floats (3 values per vertex in each). Every vertex with free[v]
 * set that one of the nt triangles 'tris' uses gets the values that solve L_uu x_u = -L_uk x_k
 * (L the cotangent Laplacian of xyz over those triangles, u the free vertices, k the others)
 * plus 'ridge' (I x_u - to) on the left, which keeps a piece no held vertex reaches well-posed
 * (to: 3 fields values toward which, NULL for 0). One factorization, 3 fields right-hand sides.
 * Other vertices keep their values. */
frig_status fr_harmonic_extend(frig_ctx *ctx, int nv, const float *xyz, const int32_t *tris, int nt,
                               const uint8_t *free_vertex, int fields, double ridge, const float *to, float *vals);

#endif
