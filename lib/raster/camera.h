/* The camera every stage uses (paper eq. 4.4: p = pi(c) R v + T, and the rendering of
 * sections 4.4 and 5.1). Model coordinates are metres (ICT: x to the subject's left, y up,
 * z toward the viewer); a pose maps them to camera coordinates X_c = R X + t, OpenCV-style
 * (x right, y down, z forward); a frontal face has R = diag(1, -1, -1), t = (0, 0, d > 0).
 *   perspective:        u = f x / z + cx,      v = f y / z + cy
 *   weak perspective:   u = scale x + cx,      v = scale y + cy   (z only orders depth)
 * Pixel centres are at integer coordinates, (0, 0) = centre of the top-left pixel.
 * The full statement with examples: docs/camera.md. */
#ifndef FR_RASTER_CAMERA_H
#define FR_RASTER_CAMERA_H

#include "raster/rotation.h"

typedef struct fr_camera {
    double f;      /* focal length in pixels (perspective) */
    double cx, cy; /* principal point in pixels (both models) */
    int weak;      /* 0: perspective, 1: weak perspective (scaled orthographic) */
    double scale;  /* weak perspective: pixels per metre of camera x, y */
} fr_camera;

/* A perspective camera whose principal point is the image centre ((w - 1) / 2, (h - 1) / 2). */
fr_camera fr_camera_perspective(double f, int width, int height);
/* A weak-perspective camera centred on the image. */
fr_camera fr_camera_weak(double scale, int width, int height);

/* Project one camera-space point. Returns 0 (and leaves uv untouched) when a perspective
 * point has z <= 0; weak perspective always projects. */
int fr_camera_project(const fr_camera *cam, const double xc[3], double uv[2]);

/* J = d(u, v) / d(x_c), 2x3 row-major. For perspective z must be nonzero. */
void fr_camera_project_jacobian(const fr_camera *cam, const double xc[3], double J[6]);

/* X_c = R X + t for n points (float xyz triples), into xc (3n floats; may not alias x). */
void fr_transform_points(const double R[9], const double t[3], const float *x, int n, float *xc);

/* Project n model points through a pose and a camera: uv gets 2n doubles, depth (may be
 * NULL) n camera z values. Perspective points with z <= 0 get uv = NaN. */
void fr_project_points(const fr_camera *cam, const double R[9], const double t[3], const float *x, int n,
                       double *uv, double *depth);

#endif
