/* Errors of reconstructed shapes against ground truth (paper section 7.2: the blendshape
 * error E_B and the point error E_P are distances between a reconstruction and the truth,
 * per vertex). Internal; used by the tests and benchmarks of every stage. */
#ifndef FR_EVAL_SHAPE_ERROR_H
#define FR_EVAL_SHAPE_ERROR_H

/* Mean distance between a and b (3 floats per vertex) over their first n vertices, after the
 * similarity transform (rotation, translation, uniform scale) of b that best fits a in the
 * least-squares sense (Umeyama 1991). In the units of the coordinates. */
double fr_aligned_mean_distance(const float *a, const float *b, int n);

#endif
