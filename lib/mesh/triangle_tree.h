/* A spatial index over a mesh's triangles (a bounding-box tree split at the median of the
 * triangles' centroids along the widest axis, k-d style) answering "which point of the mesh is
 * nearest to p" in logarithmic time: the point-to-triangle correspondences of the paper's
 * Algorithm 7. The tree keeps the vertex positions it is given (borrowed); after the vertices
 * move, fr_tri_tree_refit updates the boxes without rebuilding. Queries are read-only and may
 * run from many threads at once. Internal. */
#ifndef FR_MESH_TRIANGLE_TREE_H
#define FR_MESH_TRIANGLE_TREE_H

#include <stdint.h>

#include "frig/frig.h"

typedef struct fr_tri_tree fr_tri_tree;

typedef struct fr_tri_hit {
    int tri;         /* index into the triangle list given to build; -1 when none */
    double bary[3];  /* of the triangle's corners 0, 1, 2 */
    double point[3];
    double dist2;    /* squared distance */
} fr_tri_hit;

/* Index nt triangles (3 vertex indices each) over positions xyz (3 floats per vertex; borrowed,
 * must outlive the tree). */
frig_status fr_tri_tree_build(frig_ctx *ctx, const float *xyz, const int32_t *tris, int nt, fr_tri_tree **out);
void fr_tri_tree_free(fr_tri_tree *tree);

/* An independent copy (its own boxes) over the same triangles and positions, e.g. one per
 * thread, each refitted to its own positions. */
frig_status fr_tri_tree_copy(frig_ctx *ctx, const fr_tri_tree *tree, fr_tri_tree **out);

/* New positions (same vertices, same triangles): the boxes are recomputed bottom-up. */
void fr_tri_tree_refit(fr_tri_tree *tree, const float *xyz);

/* The nearest point of any triangle to p within max_dist (metres; use INFINITY for no limit).
 * Returns 1 and fills hit, or 0 (hit->tri = -1) when nothing is that near. Ties go to the
 * lower triangle index, so the answer does not depend on the tree's shape. */
int fr_tri_tree_nearest(const fr_tri_tree *tree, const double p[3], double max_dist, fr_tri_hit *hit);

/* The same, starting the search with triangle 'hint' (e.g. the point's previous match; -1 for
 * none) as the best so far: the same answer, found faster when the hint is near. */
int fr_tri_tree_nearest_hint(const fr_tri_tree *tree, const double p[3], double max_dist, int hint, fr_tri_hit *hit);

#endif
