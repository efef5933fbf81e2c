/* Laplacian surface deformation toward points (paper section 5.2.1, Algorithm 7's
 * DeformShapeWithPoints; Sorkine et al. 2004, Botsch & Sorkine 2008): the displacement u of a
 * rest mesh that minimizes
 *     sum_c w_c |sum_k b_ck u(v_ck) - r_c|^2  +  smooth u^T Q u  +  tikhonov u^T M u
 * with Q the bending operator L M^-1 L of the rest mesh (order 2: the integral of the
 * displacement's squared Laplacian, so the rest shape's Laplacian coordinates are kept) or the
 * membrane operator L (order 1: the integral of its squared gradient; a sparser system, about
 * a ninth of the factorization's work on the face mesh), M its lumped mass, and
 * point constraints c on the mesh (a point with barycentric weights b on up to three
 * vertices, to be moved by r_c). The x, y and z parts share one matrix: three right-hand
 * sides per solve.
 * The pattern of the system is the same for every rest shape of one topology: a system is
 * analyzed once (fr_lap_system, which also holds the rest shape's operators), and each solver
 * (one per thread) refactors it with new values. Internal. */
#ifndef FR_MESH_LAPLACIAN_DEFORM_H
#define FR_MESH_LAPLACIAN_DEFORM_H

#include <stdint.h>

#include "sparse/csr.h"

typedef struct fr_lap_system fr_lap_system;
typedef struct fr_lap_solver fr_lap_solver;

typedef struct fr_lap_constraint {
    int v[3];        /* vertices (repeat one with weight 0 for a vertex constraint) */
    double b[3];     /* their weights */
    double r[3];     /* wanted displacement of the point */
    double w;        /* weight */
} fr_lap_constraint;

/* The pattern and its analysis for a mesh of nv vertices and these triangles (borrowed; every
 * vertex should belong to a triangle). xyz: any rest shape of the mesh (for the analysis). */
frig_status fr_lap_system_create(frig_ctx *ctx, int nv, const int32_t *tris, int nt, const float *xyz, int order,
                                 fr_lap_system **out);
void fr_lap_system_free(fr_lap_system *sys);

/* Set the rest shape (3 floats per vertex) whose Q and M the solvers use (not while they
 * solve). The creation's shape is the first rest shape. */
frig_status fr_lap_system_set_rest(frig_ctx *ctx, fr_lap_system *sys, const float *xyz);
/* The rest shape's lumped mass per vertex (nv values). */
const double *fr_lap_system_mass(const fr_lap_system *sys);

/* One solver (not shared between threads). */
frig_status fr_lap_solver_create(frig_ctx *ctx, const fr_lap_system *sys, fr_lap_solver **out);
void fr_lap_solver_free(fr_lap_solver *sv);

/* Factor the system for these constraints and weights and solve: u gets 3 values per vertex
 * (x, y, z interleaved). */
frig_status fr_lap_solve(frig_ctx *ctx, fr_lap_solver *sv, double smooth, double tikhonov,
                         const fr_lap_constraint *c, int nc, double *u);

#endif
