/* Eyelids inside eyeballs and teeth through lips, measured on a rig's shapes (collisions.c).
 * Internal; the whole-head step and the tests use it. */
#ifndef FR_RETARGET_COLLISIONS_H
#define FR_RETARGET_COLLISIONS_H

#include "frig/frig.h"

/* For the neutral (index 0) and each of the shapes (1 .. shapes: neutral + deltas[k - 1], 3 per
 * vertex of the model's topology): lid[k] = the smallest signed distance of any lid vertex to
 * its eyeball's mesh (metres; negative = inside), teeth[k] = the largest depth by which a tooth
 * vertex stands in front of the face skin over it (metres; positive = through the lips;
 * -inf when the skin covers no tooth). */
frig_status fr_rt_collisions(frig_ctx *ctx, const frig_model *model, const float *neutral, const float *deltas,
                             int shapes, double *lid, double *teeth);

/* The eyeballs' meshes and the skin near them, indexed once for many shapes. */
typedef struct fr_rt_lids fr_rt_lids;
frig_status fr_rt_lids_create(frig_ctx *ctx, const frig_model *model, fr_rt_lids **out);
void fr_rt_lids_free(fr_rt_lids *lids);
/* Per vertex of positions x: its signed distance to the nearer eyeball's mesh (metres;
 * negative = inside) for the skin vertices within 4 mm of an eyeball, +inf for the others;
 * direction (3 per vertex, may be NULL): the unit vector along which that distance grows.
 * Not for several threads on one lids. */
void fr_rt_lid_clearance(fr_rt_lids *lids, const float *x, float *clearance, float *direction);

/* Teeth through the lips for one set of positions (see fr_rt_collisions). */
double fr_rt_teeth_depth(frig_ctx *ctx, const frig_model *model, const float *x, frig_status *status);

#endif
