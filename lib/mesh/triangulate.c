/* Fan triangulation of the source polygons (quads and triangles in ICT-FaceKit): polygon
 * (c0, c1, ..., cn-1) gives (c0, c1, c2), (c0, c2, c3), ...; the split OBJ importers use. */
#include <stdlib.h>

#include "core/context.h"
#include "mesh/topology.h"

frig_status fr_triangulate(frig_ctx *ctx, int polygon_count, const int32_t *offsets, const int32_t *corners,
                           const int32_t *corner_uvs, const int32_t *materials, int *triangle_count,
                           int32_t **triangles, int32_t **triangle_uvs, int32_t **triangle_materials) {
    int64_t n = 0;
    for (int p = 0; p < polygon_count; p++) n += offsets[p + 1] - offsets[p] - 2;
    *triangles = malloc(sizeof(int32_t) * 3 * (size_t)(n > 0 ? n : 1));
    *triangle_uvs = malloc(sizeof(int32_t) * 3 * (size_t)(n > 0 ? n : 1));
    *triangle_materials = malloc(sizeof(int32_t) * (size_t)(n > 0 ? n : 1));
    if (!*triangles || !*triangle_uvs || !*triangle_materials) {
        free(*triangles), free(*triangle_uvs), free(*triangle_materials);
        *triangles = *triangle_uvs = *triangle_materials = NULL;
        return fr_nomem(ctx, "the triangulation");
    }
    int64_t t = 0;
    for (int p = 0; p < polygon_count; p++) {
        int32_t a = offsets[p];
        for (int32_t k = a + 1; k + 1 < offsets[p + 1]; k++, t++) {
            int32_t c[3] = {a, k, k + 1};
            for (int j = 0; j < 3; j++) {
                (*triangles)[3 * t + j] = corners[c[j]];
                (*triangle_uvs)[3 * t + j] = corner_uvs[c[j]];
            }
            (*triangle_materials)[t] = materials[p];
        }
    }
    *triangle_count = (int)n;
    return FRIG_OK;
}
