/* What ICT-FaceKit's README states about its topology, hard-coded: the vertex and polygon
 * ranges of each part of the head and the jawline contour candidates. Internal. */
#ifndef FR_MODEL_ICT_LAYOUT_H
#define FR_MODEL_ICT_LAYOUT_H

#include <stdint.h>

#include "frig/frig.h"
#include "model/obj_reader.h"

#define FR_ICT_VERTEX_COUNT 26719
#define FR_ICT_POLYGON_COUNT 26384

typedef struct fr_ict_region {
    const char *name;
    int first_vertex, last_vertex;   /* inclusive, as in the README */
    int first_polygon, last_polygon; /* inclusive */
    int partition;                   /* 1: one of the 17 parts that tile the whole mesh */
} fr_ict_region;

int fr_ict_region_count(void);
const fr_ict_region *fr_ict_region_at(int i);

/* Check the table against the neutral mesh: the vertex and polygon counts, the parts tile
 * the mesh in order, and each part's polygons use all of the part's vertices and none
 * after it. 'file' names the mesh in messages. */
frig_status fr_ict_check_layout(frig_ctx *ctx, const char *file, const fr_obj *neutral);

/* Jawline contour candidates (the README's "extended jawline" lists), ordered from the ear
 * toward the chin: side 0 = the subject's right (iBUG 0-7 side), 1 = left (iBUG 9-16). */
int fr_ict_contour(int side, const int32_t **vertices);

#endif
