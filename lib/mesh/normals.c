/* Area-weighted vertex normals: each triangle adds its cross product (twice its area times
 * its unit normal) to its three corners; sums are normalized. Accumulated in double, in
 * triangle order, so the result does not depend on threads. */
#include <math.h>
#include <stdlib.h>

#include "core/context.h"
#include "mesh/topology.h"

frig_status fr_vertex_normals(frig_ctx *ctx, int vertex_count, const float *positions, int triangle_count,
                              const int32_t *triangles, float *normals) {
    double *acc = calloc((size_t)vertex_count * 3 + 1, sizeof *acc);
    if (!acc) return fr_nomem(ctx, "normals");
    for (int t = 0; t < triangle_count; t++) {
        const int32_t *v = triangles + 3 * t;
        const float *a = positions + 3 * v[0], *b = positions + 3 * v[1], *c = positions + 3 * v[2];
        double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        double e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
        for (int j = 0; j < 3; j++)
            for (int d = 0; d < 3; d++) acc[3 * v[j] + d] += n[d];
    }
    for (int i = 0; i < vertex_count; i++) {
        double *n = acc + 3 * i;
        double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        if (!(len > 0)) n[0] = 0, n[1] = 0, n[2] = 1, len = 1;
        for (int d = 0; d < 3; d++) normals[3 * i + d] = (float)(n[d] / len);
    }
    free(acc);
    return FRIG_OK;
}
