/* Discrete Laplace-Beltrami operators of a triangle mesh: the cotangent stiffness matrix and
 * the lumped mass (Pinkall & Polthier 1993; Meyer et al. 2003), the building blocks of the
 * Laplacian deformation (paper section 5.2.1, Sorkine et al. 2004) and of the Poisson solve of
 * deformation transfer (Sumner & Popovic 2004). Internal. */
#ifndef FR_MESH_LAPLACIAN_H
#define FR_MESH_LAPLACIAN_H

#include <stdint.h>

#include "sparse/csr.h"

/* Stiffness L (nv x nv, symmetric, positive semidefinite): L_ij = -(cot a_ij + cot b_ij) / 2
 * for an edge ij opposite the angles a_ij and b_ij, L_ii = -sum_j L_ij; u^T L u is the
 * Dirichlet energy of the piecewise-linear function u. Every vertex gets a diagonal entry (0
 * for a vertex no triangle uses). mass (nv values, may be NULL): a third of the area of the
 * triangles around each vertex. Triangles of zero area are skipped. */
frig_status fr_cotan_laplacian(frig_ctx *ctx, int nv, const float *xyz, const int32_t *tris, int nt, fr_csr *L,
                               double *mass);

/* boundary[v] = 1 when vertex v lies on an edge that only one triangle uses (a hole's or the
 * mesh's rim), else 0. */
frig_status fr_mesh_boundary(frig_ctx *ctx, int nv, const int32_t *tris, int nt, uint8_t *boundary);

/* The bending operator Q = L M^-1 L (u^T Q u is the integral of (Laplacian u)^2, the energy a
 * smooth Laplacian deformation minimizes); a vertex of zero mass contributes nothing. */
frig_status fr_bilaplacian(frig_ctx *ctx, const fr_csr *L, const double *mass, fr_csr *Q);

#endif
