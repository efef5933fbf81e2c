/* Order statistics (core/select.c): the k-th smallest equals the sorted array's k-th entry, for
 * distinct values, many ties, sorted and reversed inputs. */
#include <stdlib.h>
#include <string.h>

#include "core/select.h"
#include "testing.h"

static int cmp_float(const void *a, const void *b) {
    float x = *(const float *)a, y = *(const float *)b;
    return (x > y) - (x < y);
}

int main(void) {
    enum { MAX_N = 300 };
    float v[MAX_N], sorted[MAX_N];
    unsigned seed = 7;
    int wrong = 0;
    for (int trial = 0; trial < 4000; trial++) {
        seed = seed * 1103515245u + 12345u;
        size_t n = 1 + (seed >> 8) % MAX_N;
        int kind = trial % 4;
        for (size_t i = 0; i < n; i++) {
            seed = seed * 1103515245u + 12345u;
            unsigned r = seed >> 8;
            v[i] = kind == 0 ? (float)(r % 5) : kind == 1 ? (float)r / 16777216.0f : kind == 2 ? (float)i : -(float)i;
        }
        memcpy(sorted, v, sizeof(float) * n);
        qsort(sorted, n, sizeof(float), cmp_float);
        size_t k = (seed >> 4) % n;
        if (fr_select_float(v, n, k) != sorted[k]) wrong++;
    }
    CHECK(wrong == 0);
    float one = 3.5f;
    CHECK(fr_select_float(&one, 1, 0) == 3.5f);
    return test_result("test_select");
}
