/* Photos that repeat an earlier photo of the set byte for byte (scraped collections often
 * hold two or three copies of one picture). Internal. */
#ifndef FR_DETECT_DUPLICATES_H
#define FR_DETECT_DUPLICATES_H

#include "frig/photoset.h"

/* Mark every usable photo whose file has the same bytes as an earlier usable photo of the
 * set FRIG_PHOTO_DUPLICATE, the reason naming the first copy. Copies would otherwise count
 * two or three times in the filter's statistics (an outlier in triplicate looks like a
 * consistent mode to robust PCA) and in the fit's joint identity. */
frig_status fr_mark_duplicates(frig_ctx *ctx, frig_photoset *set);

#endif
