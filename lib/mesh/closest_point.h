/* The point of a triangle nearest to a point (the correspondence of a cloud point on a mesh,
 * paper Algorithm 7), by the Voronoi regions of the triangle's corners, edges and face.
 * Internal. */
#ifndef FR_MESH_CLOSEST_POINT_H
#define FR_MESH_CLOSEST_POINT_H

/* Nearest point q of triangle (a, b, c) to p and its barycentric weights (q = w0 a + w1 b +
 * w2 c, each in [0, 1], summing to 1); returns |p - q|^2. A degenerate triangle gives the
 * nearest point of its longest edge. */
double fr_closest_point_triangle(const double p[3], const double a[3], const double b[3], const double c[3],
                                 double q[3], double bary[3]);

#endif
