/* A photo's specular highlights taken out of its skin pixels (sfs_highlights.c). Internal. */
#ifndef FR_SFS_SFS_HIGHLIGHTS_H
#define FR_SFS_SFS_HIGHLIGHTS_H

#include "sfs/sfs.h"

/* The skin's chroma in v: the per-channel median of the chromaticities I_c / (I_r + I_g + I_b) of the
 * skin pixels (v->skin), as a unit vector. 1, or 0 when fewer than 50 skin pixels have a colour to
 * read; -1 on no memory. */
int fr_sfs_skin_chroma(const fr_sfs_view *v, double d[3]);

/* Every skin pixel of v->I split into k d + s (1, 1, 1), d the skin's chroma; where the white share
 * 3 s / (I_r + I_g + I_b) lies more than nsig robust standard deviations (1.4826 MAD) above the photo's
 * median share over its skin, s is taken out of each channel. Nothing when nsig <= 0, when the skin's
 * chroma cannot be read or is within 3 degrees of grey. *changed: the pixels changed. */
frig_status fr_sfs_take_out_highlights(frig_ctx *ctx, fr_sfs_view *v, double nsig, int *changed);

#endif
