/* Point-cloud error against a true surface (paper section 7.2, E_P): the distance of each
 * point to the nearest point of a triangle mesh (lib/mesh/triangle_tree.c), after the
 * similarity transform (rotation, translation, uniform scale) of the cloud that best fits the
 * surface (iterative closest points, each round's transform lib/mesh/point_align.c's). Internal;
 * for tests and benchmarks. */
#ifndef FR_EVAL_CLOUD_ERROR_H
#define FR_EVAL_CLOUD_ERROR_H

#include <stdint.h>

#include "frig/frig.h"
#include "mesh/triangle_tree.h"

/* Align n points (3 doubles each) to the surface the tree indexes by similarity ICP (at most
 * 'iterations' rounds; points farther than 'reject' metres do not pull after the first two
 * rounds), then write each point's distance to the surface (dist, n values; INFINITY beyond
 * 5 cm) and the transform applied (p -> scale R p + t). */
frig_status fr_cloud_align(frig_ctx *ctx, const fr_tri_tree *tree, const double *pts, int n, int iterations,
                           double reject, double *dist, double *scale, double R[9], double t[3]);

/* Mean, median and 90th percentile of n values. */
void fr_error_stats(const double *v, int n, double *mean, double *median, double *p90);

#endif
