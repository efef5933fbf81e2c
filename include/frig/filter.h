/* libfrig filter stage (paper section 4.2, Algorithm 1): robust-PCA failure detection of the
 * landmark results. Shape (similarity-aligned landmarks) and texture (the face warped to a
 * common frame, gain and bias normalized) models are built from the low-rank part of robust
 * PCA; photos whose face the models cannot reconstruct are dropped, round after round, until
 * none is. The same models re-choose the subject in photos with several faces.
 */
#ifndef FRIG_FILTER_H
#define FRIG_FILTER_H

#include "frig/photoset.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Filter the photos whose status is ok and whose subject has landmarks: dropped photos get the
 * status outlier with the round and the errors (frig_photoset_filter); every filtered photo
 * gets its errors. Photos are read again from their paths (one that can no longer be read
 * becomes unreadable). contact_sheet (may be NULL): a PNG of the warped faces, dropped ones
 * framed in red with their round. Fewer than 3 usable photos: nothing is dropped (a warning
 * is logged). Reads the filter.* parameters. Parallel across photos, deterministic. */
FRIG_API frig_status frig_filter(frig_ctx *ctx, frig_photoset *set, const char *contact_sheet);

#ifdef __cplusplus
}
#endif
#endif /* FRIG_FILTER_H */
