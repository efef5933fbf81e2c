/* floor and ceil of a double as an int: the same int as (int)floor(x) and (int)ceil(x), by one
 * truncation and a compare where x fits an int (the build targets plain SSE2, whose floor and ceil
 * are a dozen instructions each; the samplers and the rasterizer take millions). Internal. */
#ifndef FR_CORE_FLOOR_INT_H
#define FR_CORE_FLOOR_INT_H

#include <math.h>

#define FR_INT_RANGE 2147483647.0 /* |x| below this: its truncation and that +- 1 fit an int */

static inline int fr_floor_int(double x) {
    if (fabs(x) < FR_INT_RANGE) {
        int i = (int)x;
        return (double)i > x ? i - 1 : i;
    }
    return (int)floor(x);
}

static inline int fr_ceil_int(double x) {
    if (fabs(x) < FR_INT_RANGE) {
        int i = (int)x;
        return (double)i < x ? i + 1 : i;
    }
    return (int)ceil(x);
}

#endif
