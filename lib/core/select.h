/* Order statistics without a full sort: the k-th smallest of an array (quickselect), the
 * median that robust fits take on every round. Internal. */
#ifndef FR_CORE_SELECT_H
#define FR_CORE_SELECT_H

#include <stddef.h>

/* The value sorted v[k] would hold (0 <= k < n; no NaNs); v is reordered. Average O(n). */
float fr_select_float(float *v, size_t n, size_t k);

#endif
