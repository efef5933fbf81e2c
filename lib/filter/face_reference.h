/* The common face frame of the filter stage (section 4.2): a reference 68-point shape (iBUG /
 * Multi-PIE order) and a fixed triangulation of it, over which faces are warped piecewise-affinely
 * (as in active appearance models, Cootes, Edwards, Taylor 2001). Internal. */
#ifndef FR_FILTER_FACE_REFERENCE_H
#define FR_FILTER_FACE_REFERENCE_H

#define FR_FACE_POINTS 68

/* 136 values (x0, y0, x1, y1, ...), x right, y down: centred on its bounding box, whose larger
 * side is 1. */
const double *fr_face_reference_shape(void);

/* Triangles as vertex index triples with positive area in (x, y-down) coordinates; together they
 * cover the convex hull of the reference shape. */
const unsigned char (*fr_face_triangles(int *count))[3];

#endif
