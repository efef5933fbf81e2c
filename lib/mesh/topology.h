/* A mesh's fixed structure as the model and rig files store it: polygons (as the source
 * gives them) with UVs and materials, the triangulation used for computation, material
 * names and colours, named vertex ranges. The arrays are borrowed from a file image. Internal. */
#ifndef FR_MESH_TOPOLOGY_H
#define FR_MESH_TOPOLOGY_H

#include <stdint.h>

#include "io/container.h"

#define FR_TOPOLOGY_META 7      /* int32 values in the "topo_meta" section */
#define FR_TOPOLOGY_SECTIONS 13 /* sections fr_topology_sections adds */

typedef struct fr_topology {
    int vertex_count, polygon_count, corner_count, triangle_count, uv_count, material_count, region_count;
    const int32_t *poly_offsets;  /* polygon_count + 1 */
    const int32_t *poly_corners;  /* corner_count vertex indices */
    const int32_t *poly_uvs;      /* corner_count uv indices */
    const int32_t *poly_materials;
    const int32_t *triangles;     /* 3 per triangle */
    const int32_t *triangle_uvs;  /* 3 per triangle */
    const int32_t *triangle_materials;
    const int32_t *regions;       /* first, count per region */
    const float *uvs;             /* 2 per uv */
    const float *material_kd;     /* diffuse colour, 3 per material */
    const char *material_blob, *region_blob; /* names, NUL-separated */
    size_t material_blob_size, region_blob_size;
    const char **material_names, **region_names; /* arrays owned by the topology once bound */
} fr_topology;

/* Fill s[0 .. FR_TOPOLOGY_SECTIONS-1] with the topology's sections; meta is caller storage. */
void fr_topology_sections(const fr_topology *t, int32_t meta[FR_TOPOLOGY_META], fr_section *s);
/* Take the topology sections out of a parsed container and check every count and index. */
frig_status fr_topology_bind(frig_ctx *ctx, const fr_container *c, fr_topology *t);
/* Free what bind allocated (the name arrays). */
void fr_topology_release(fr_topology *t);

/* The named vertex range (vertices first .. first + count - 1); 0 when absent or empty. */
int fr_topology_region(const fr_topology *t, const char *name, int *first, int *count);
/* The material's index by name; -1 when absent. */
int fr_topology_material(const fr_topology *t, const char *name);
/* Whether triangle i is drawn opaque in a photo: every material but ICT's transparent eye
 * overlays (lacrimal fluid, eye blend, eye occlusion) and the lashes, which a photo shows through
 * or as strands (the synthetic renderer leaves them out too). */
int fr_topology_opaque(const fr_topology *t, int i);
/* Whether triangle i is the face's skin (ICT's M_Face material: face, neck, ears, scalp). */
int fr_topology_face_skin(const fr_topology *t, int i);

/* Fan-triangulate polygons: triangle count = sum (corners - 2). Outputs are allocated. */
frig_status fr_triangulate(frig_ctx *ctx, int polygon_count, const int32_t *offsets, const int32_t *corners,
                           const int32_t *corner_uvs, const int32_t *materials, int *triangle_count,
                           int32_t **triangles, int32_t **triangle_uvs, int32_t **triangle_materials);

/* Area-weighted vertex normals (sum of the unnormalized face normals of the triangles
 * around each vertex, then normalized; (0, 0, 1) for a vertex no triangle touches). */
frig_status fr_vertex_normals(frig_ctx *ctx, int vertex_count, const float *positions, int triangle_count,
                              const int32_t *triangles, float *normals);

#endif
