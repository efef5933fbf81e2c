/* A z-buffered triangle rasterizer: per pixel the nearest surface's camera depth, triangle id
 * and perspective-correct barycentrics, for photo-consistency (paper section 4.4: which model
 * vertices are visible and where they land), shape from shading (section 5.1: depth, normals,
 * barycentrics, triangle ids per pixel) and synthetic ground-truth renders.
 * Camera conventions: raster/camera.h and docs/camera.md. */
#ifndef FR_RASTER_RASTER_H
#define FR_RASTER_RASTER_H

#include <stdint.h>

#include "frig/frig.h"
#include "raster/camera.h"

/* The render target: row-major arrays of width * height pixels (bary: 3 per pixel). */
typedef struct fr_raster {
    int width, height;
    float *depth;    /* camera z of the nearest surface; +INFINITY where empty */
    int32_t *tri;    /* its triangle index; -1 where empty */
    float *bary;     /* weights of the triangle's corners 0, 1, 2 (sum 1); 0 where empty */
} fr_raster;

typedef struct fr_raster_options {
    double near;   /* perspective: surface nearer than this camera z (metres) is clipped */
    int cull_back; /* 1: skip triangles seen from behind (front = counter-clockwise in the
                    * image, i.e. the OBJ winding seen from outside) */
} fr_raster_options;

#define FR_RASTER_DEFAULT_NEAR 1e-3

frig_status fr_raster_create(frig_ctx *ctx, int width, int height, fr_raster **out);
void fr_raster_free(fr_raster *r);
/* Set every pixel empty. */
void fr_raster_clear(fr_raster *r);

/* Clear, then draw the triangles (3 vertex indices each) of a mesh whose vertices 'xyz' are
 * in CAMERA coordinates (3 floats each). opt may be NULL (near = 1 mm, no culling).
 * A pixel belongs to a triangle when its centre is strictly inside it or on an edge that is a
 * top or left edge (each pixel of a closed mesh is covered once); ties in depth keep the
 * lower triangle index. Triangles with a non-finite vertex are skipped. Deterministic.
 * FRIG_ERR_INVALID_ARGUMENT for an index outside 0..nv-1 (naming the triangle). */
frig_status fr_raster_render(frig_ctx *ctx, fr_raster *r, const fr_camera *cam, const float *xyz, int nv,
                             const int32_t *tris, int nt, const fr_raster_options *opt);

/* ---- one triangle (the renderer's own coverage rule, exposed for tests and 2D fills) ----
 * Edge functions e_i(u, v) = a_i u + (b_i v + c_i), positive inside. Perspective: e_i is
 * f (u - cx, v - cy, f) . (P_{i+1} x P_{i+2}), so the barycentrics of the ray-plane
 * intersection are e_i / sum e and its depth z = zk / sum e (homogeneous rasterization, no
 * 2D projection of the corners needed; pixels with z < near are clipped). Weak perspective:
 * the same with 2D homogeneous corners (u_i, v_i, 1), depth interpolated affinely. */
typedef struct fr_raster_tri {
    double a[3], b[3], c[3];
    unsigned char tie[3]; /* e_i == 0 counts as inside (top-left rule) */
    int weak;
    double zk;            /* perspective: z = zk / sum e */
    double z[3];          /* corner depths */
    double zmin, zmax;    /* their range (perspective depths are clamped to it) */
    double near;
    int x0, y0, x1, y1;   /* pixel bounding box, inclusive, clipped to the image */
} fr_raster_tri;

/* Set up triangle (p0, p1, p2) (camera coordinates) for a width x height image. Returns 0 when
 * nothing can be drawn (degenerate, edge-on, culled, entirely nearer than near, off-image). */
int fr_raster_tri_setup(const fr_camera *cam, const float p0[3], const float p1[3], const float p2[3],
                        const fr_raster_options *opt, int width, int height, fr_raster_tri *t);

/* Does pixel (x, y) belong to the triangle? Then z and bary (both may be NULL) are set. */
int fr_raster_tri_sample(const fr_raster_tri *t, int x, int y, double *z, double bary[3]);

/* ---- reading the result ---- */
/* Interpolate a per-vertex attribute (dim floats per vertex) at pixel (x, y) into out (dim
 * floats). Returns 0 (out untouched) when the pixel is empty or outside the image. */
int fr_raster_interpolate(const fr_raster *r, const int32_t *tris, int x, int y, const float *attr, int dim,
                          float *out);

/* The same for every pixel: out holds width * height * dim floats; empty pixels get 'empty'. */
void fr_raster_attribute_map(const fr_raster *r, const int32_t *tris, const float *attr, int dim, float empty,
                             float *out);

/* Per-pixel unit normals (3 floats per pixel) interpolated from per-vertex normals given in
 * the same (camera) frame as the render; (0, 0, 0) where empty. */
void fr_raster_normal_map(const fr_raster *r, const int32_t *tris, const float *normals, float *out);

/* Area-weighted vertex normals (sum of the adjacent faces' cross products, normalized),
 * outward for counter-clockwise (OBJ) winding; (0, 0, 0) for unused vertices. */
void fr_mesh_vertex_normals(const float *xyz, int nv, const int32_t *tris, int nt, float *normals);
/* The same at the vertices marked in want only (0, 0, 0 elsewhere), from the triangles listed (indices
 * into tris, ascending), which must hold every triangle that uses a wanted vertex: then each wanted
 * vertex sums the same terms in the same order as fr_mesh_vertex_normals, and gets the same floats. */
void fr_mesh_vertex_normals_at(const float *xyz, int nv, const int32_t *tris, const int32_t *list, int nlist,
                               const uint8_t *want, float *normals);

/* visible[i] = 1 when camera-space vertex i projects inside the image, the pixel nearest to
 * it is covered, and either the triangle drawn there uses vertex i or the vertex is at most
 * 'tol' metres behind that triangle's plane at the vertex's exact image position (so a
 * steep surface does not hide its own vertices); else 0. 'r' must hold the render of the same
 * mesh with the same camera. */
void fr_raster_visible_vertices(const fr_raster *r, const fr_camera *cam, const float *xyz, int nv,
                                const int32_t *tris, double tol, uint8_t *visible);

#endif
