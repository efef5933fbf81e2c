/* The radix sort of (key, index) pairs (core/sort.c): the order qsort gives with "key, then
 * index", for 64-bit keys with many ties, keys sharing their high bytes, doubles (negative,
 * -0 and +0, tiny and huge) through fr_sort_key_double, and the empty and one-item cases. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/rng.h"
#include "core/sort.h"
#include "testing.h"

static int cmp_item(const void *a, const void *b) {
    const fr_sort_item *x = a, *y = b;
    if (x->key != y->key) return x->key < y->key ? -1 : 1;
    return (x->index > y->index) - (x->index < y->index);
}

static int cmp_double_index(const void *a, const void *b) {
    const double *x = a, *y = b; /* value, index */
    if (x[0] < y[0]) return -1;
    if (x[0] > y[0]) return 1;
    return (x[1] > y[1]) - (x[1] < y[1]);
}

/* n pairs in index order with keys of one kind: many ties, shared high bytes, spread out. */
static void random_keys(fr_rng *rng, int kind, fr_sort_item *a, size_t n) {
    for (size_t i = 0; i < n; i++) {
        uint64_t r = fr_rng_next(rng) >> 11;
        a[i].key = kind == 0 ? r % 7 : kind == 1 ? (UINT64_C(0xabcd) << 48) | (r & 0xffffff) : r * 2654435761u;
        a[i].index = (int)i;
    }
}

int main(void) {
    enum { MAX_N = 2000 };
    static fr_sort_item a[MAX_N], b[MAX_N];
    static double d[2 * MAX_N];
    static const double special[] = {0.0, -0.0, 1e-310, -1e-310, 1e300, -1e300, 0.5, -0.5};
    fr_rng rng;
    fr_rng_seed(&rng, 11);
    int wrong = 0, wrong_double = 0;
    for (int trial = 0; trial < 600; trial++) {
        size_t n = 1 + (size_t)fr_rng_below(&rng, MAX_N);
        random_keys(&rng, trial % 3, a, n);
        memcpy(b, a, sizeof a[0] * n);
        qsort(b, n, sizeof b[0], cmp_item);
        CHECK(fr_sort_stable(a, n) == 0);
        for (size_t i = 0; i < n; i++) wrong += a[i].key != b[i].key || a[i].index != b[i].index;
        /* doubles: the values' order, ties (and -0 = +0) by index */
        for (size_t i = 0; i < n; i++) {
            double v = trial % 2 ? special[fr_rng_below(&rng, 8)] : (fr_rng_uniform(&rng) - 0.5) * 1e3;
            d[2 * i] = v, d[2 * i + 1] = (double)i;
            a[i].key = fr_sort_key_double(v), a[i].index = (int)i;
        }
        qsort(d, n, 2 * sizeof(double), cmp_double_index);
        CHECK(fr_sort_stable(a, n) == 0);
        for (size_t i = 0; i < n; i++) wrong_double += a[i].index != (int)d[2 * i + 1];
    }
    CHECK(wrong == 0);
    CHECK(wrong_double == 0);
    CHECK(fr_sort_stable(a, 0) == 0 && fr_sort_stable(a, 1) == 0);
    CHECK(fr_sort_key_double(-0.0) == fr_sort_key_double(0.0));
    CHECK(fr_sort_key_double(-1.0) < fr_sort_key_double(-0.5) && fr_sort_key_double(0.5) < fr_sort_key_double(INFINITY));
    return test_result("test_sort");
}
