/* Least-significant-digit radix sort of (key, index) pairs: one counting pass gives the eight
 * byte histograms, then each byte that differs between keys is a stable scatter into the other
 * buffer. */
#include <stdlib.h>
#include <string.h>

#include "core/sort.h"

int fr_sort_stable(fr_sort_item *a, size_t n) {
    if (n < 2) return 0;
    fr_sort_item *tmp = malloc(sizeof *tmp * n);
    if (!tmp) return -1;
    size_t (*count)[256] = calloc(8, sizeof *count);
    if (!count) {
        free(tmp);
        return -1;
    }
    for (size_t i = 0; i < n; i++)
        for (int d = 0; d < 8; d++) count[d][(a[i].key >> (8 * d)) & 0xff]++;
    fr_sort_item *src = a, *dst = tmp;
    for (int d = 0; d < 8; d++) {
        size_t *c = count[d];
        if (c[(src[0].key >> (8 * d)) & 0xff] == n) continue; /* every key has this byte */
        size_t start = 0;
        for (int b = 0; b < 256; b++) {
            size_t k = c[b];
            c[b] = start;
            start += k;
        }
        for (size_t i = 0; i < n; i++) dst[c[(src[i].key >> (8 * d)) & 0xff]++] = src[i];
        fr_sort_item *t = src;
        src = dst, dst = t;
    }
    if (src != a) memcpy(a, src, sizeof *a * n);
    free(tmp);
    free(count);
    return 0;
}

uint64_t fr_sort_key_double(double v) {
    if (v == 0) v = 0.0; /* -0 as +0 */
    uint64_t bits;
    memcpy(&bits, &v, sizeof bits);
    return bits >> 63 ? ~bits : bits | (UINT64_C(1) << 63);
}

int fr_cmp_double(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}
