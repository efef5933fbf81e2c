/* Photo-consistency of fits (paper section 4.4): the face texture inside the polygon of the
 * re-projected landmark vertices, explained by a low-rank texture model of all photos
 * (robust PCA, as in failure detection); F_tex is each photo's reconstruction RMSE. Internal. */
#ifndef FR_FIT_PHOTO_CONSISTENCY_H
#define FR_FIT_PHOTO_CONSISTENCY_H

#include "fit/progressive_fit.h"

/* F_tex for n photos (0 for photos without a crop). */
frig_status fr_photo_consistency(frig_ctx *ctx, const fr_fit_model *fm, int n, const fr_fit_input *in,
                                 const fr_fit_photo *ph, int threads, double *f_tex);

/* A gray crop around a face for photo-consistency: the landmarks' box grown by half its size,
 * scaled so that the face is about 'side' pixels. */
frig_status fr_face_crop(frig_ctx *ctx, const frig_image *photo, const double *landmarks, int side,
                         frig_image **crop, double origin[2], double *scale);

#endif
