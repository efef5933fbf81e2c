/* The k-th smallest value by quickselect (Hoare partition around the median of three; the
 * answer is a value, so it is the same whatever the partitioning order). */
#include "core/select.h"

static float median3(float a, float b, float c) {
    if (a > b) {
        float t = a;
        a = b, b = t;
    }
    return c < a ? a : c > b ? b : c;
}

float fr_select_float(float *v, size_t n, size_t k) {
    if (n == 0 || k >= n) return 0.0f;
    size_t lo = 0, hi = n - 1;
    while (hi > lo) {
        float pivot = median3(v[lo], v[lo + (hi - lo) / 2], v[hi]);
        size_t i = lo, j = hi;
        for (;;) {
            while (v[i] < pivot) i++;
            while (pivot < v[j]) j--;
            if (i >= j) break;
            float t = v[i];
            v[i] = v[j], v[j] = t;
            i++, j--;
        }
        /* now v[lo .. j] <= pivot <= v[j + 1 .. hi] */
        if (k <= j) hi = j;
        else lo = j + 1;
    }
    return v[k];
}
