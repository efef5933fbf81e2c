/* Procedural meshes (sphere, torus, grid) with known analytic surfaces, for checking the
 * renderer of paper sections 4.4 and 5.1 and the later stages' geometry without the face
 * model. Triangles wind counter-clockwise seen from outside (as OBJ files do). */
#ifndef FR_RASTER_SHAPES_H
#define FR_RASTER_SHAPES_H

#include <stdint.h>

#include "frig/frig.h"

/* A mesh owned by the caller: free with fr_shape_free. */
typedef struct fr_shape {
    float *xyz;     /* 3 per vertex */
    int32_t *tris;  /* 3 per triangle */
    int nv, nt;
} fr_shape;

/* UV sphere about the y axis: nlat >= 2 bands, nlon >= 3 segments; 2 poles plus
 * (nlat - 1) nlon vertices, 2 nlon (nlat - 1) triangles, all vertices on the sphere. */
frig_status fr_shape_sphere(frig_ctx *ctx, const double centre[3], double radius, int nlon, int nlat,
                            fr_shape *out);
/* Torus about the y axis (ring radius R, tube radius r): nu x nv vertices, 2 nu nv triangles. */
frig_status fr_shape_torus(frig_ctx *ctx, const double centre[3], double R, double r, int nu, int nv,
                           fr_shape *out);
/* The unit square [0, 1]^2 in the plane z = 0 as nx x ny quads (2 triangles each, facing +z);
 * vertex (i, j) is i + (nx + 1) j at (i / nx, j / ny, 0). */
frig_status fr_shape_grid(frig_ctx *ctx, int nx, int ny, fr_shape *out);

void fr_shape_free(fr_shape *s);

#endif
