/* One photo's shape-from-shading steps (sfs_photo.c). Internal. */
#ifndef FR_SFS_SFS_PHOTO_H
#define FR_SFS_SFS_PHOTO_H

#include "sfs/sfs.h"

/* Skin region, uniform albedo (mean skin colour), first lighting on the fitted normals. */
frig_status fr_sfs_photo_prepare(frig_ctx *ctx, fr_sfs_view *v, const fr_sfs_settings *st);
/* Lighting on the current albedo and normals (recovered, else the prior, else the fit's). */
frig_status fr_sfs_photo_relight(frig_ctx *ctx, fr_sfs_view *v);
/* Depth and normals from the lighting, albedo and normal prior. */
frig_status fr_sfs_photo_depth(frig_ctx *ctx, fr_sfs_view *v, const fr_sfs_settings *st);

/* Rank correlation over the skin pixels between the photo's luminance and the prediction of its
 * albedo, lighting and normals (1: the subject's albedo explains the photo). */
double fr_sfs_photo_agreement(const fr_sfs_view *v);

#endif
