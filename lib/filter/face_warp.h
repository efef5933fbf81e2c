/* The texture data vector of the filter stage (section 4.2): a face warped piecewise-affinely over
 * the fixed 68-point triangulation (filter/face_reference.h) into an S x S frame, sampled in gray,
 * and normalized for gain and bias. The fit stage reuses it with re-projected model landmarks for
 * photo-consistency. Internal. */
#ifndef FR_FILTER_FACE_WARP_H
#define FR_FILTER_FACE_WARP_H

#include "frig/frig.h"

/* A warp plan for one frame size: which frame pixels lie inside the face and in which triangle.
 * Immutable once made: share it between threads. */
typedef struct fr_face_warp fr_face_warp;

/* size: side S of the frame in pixels (16..1024; the parameter filter.texture_size). */
frig_status fr_face_warp_create(frig_ctx *ctx, int size, fr_face_warp **out);
void fr_face_warp_free(fr_face_warp *warp);

int fr_face_warp_size(const fr_face_warp *warp);
/* P, the number of texels: frame pixels whose centre lies inside the convex hull of the reference
 * shape placed in the frame. */
int fr_face_warp_texels(const fr_face_warp *warp);
/* Position y * S + x of each texel in the frame (P values, increasing). */
const int *fr_face_warp_texel_index(const fr_face_warp *warp);
/* The reference shape in frame pixels (136 values): the reference of face_reference.h with its
 * bounding box scaled to 0.95 (S - 1) and centred in the frame. */
const double *fr_face_warp_frame_shape(const fr_face_warp *warp);

/* Sample the face whose 68 landmarks (136 values, pixels of 'image', centre of the top-left pixel
 * at (0, 0)) are given: P gray values in 0..255 (RGB is converted with BT.601 weights), bilinear,
 * averaged over n x n sub-texel samples when the face is n times larger than the frame (n <= 8).
 * Samples outside the image take the nearest border pixel; *outside (may be NULL) gets the share
 * of texels whose centre fell outside. FRIG_ERR_INVALID_ARGUMENT for non-finite landmarks. */
frig_status fr_face_warp_sample(frig_ctx *ctx, const fr_face_warp *warp, const frig_image *image,
                                const double *landmarks, double *texture, double *outside);

/* Gain and bias normalization in place: zero mean and unit (population) standard deviation.
 * Returns 0, leaving all zeros, when the values are flat (standard deviation below 1e-6). */
int fr_texture_normalize(int count, double *texture);

/* fr_face_warp_sample then fr_texture_normalize: the filter's texture vector (P values).
 * FRIG_ERR_NO_FACE when the sampled face is flat. */
frig_status fr_face_texture(frig_ctx *ctx, const fr_face_warp *warp, const frig_image *image,
                            const double *landmarks, double *texture, double *outside);

#endif
