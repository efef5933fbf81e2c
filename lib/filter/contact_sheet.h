/* A contact sheet of the filter stage's warped face textures (section 4.2, Algorithm 1's
 * outcome at a glance): a grid in photo order, dropped faces framed in red with the round that
 * dropped them. Internal. */
#ifndef FR_FILTER_CONTACT_SHEET_H
#define FR_FILTER_CONTACT_SHEET_H

#include "filter/face_warp.h"
#include "frig/frig.h"

/* count textures (texels x count, normalized as by fr_face_texture; shown as 128 + 40 t) made with
 * 'warp'; round_dropped (count values, 0 = kept) frames a face in red and writes its round number.
 * columns: faces per row (>= 1). distances (NULL, or count values, NaN for none): each face's
 * descriptor distance to the subject's identity, written at the bottom of its cell (red when
 * over 'threshold'). Returns a new RGB image (save it with frig_image_save_png). */
frig_status fr_contact_sheet(frig_ctx *ctx, const fr_face_warp *warp, int count, const double *textures,
                             const int *round_dropped, const double *distances, double threshold, int columns,
                             frig_image **out);

#endif
