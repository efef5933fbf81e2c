/* Sorting (key, index) pairs in linear time: a stable radix sort on 64-bit keys, so pairs given
 * in ascending index order come out ordered by key, then index; the order qsort gives with a
 * "key, then index" comparison, found without its comparison calls (the cloud thinning of
 * every retarget pass, the rank correlation of every sfs lighting pass). Internal. */
#ifndef FR_CORE_SORT_H
#define FR_CORE_SORT_H

#include <stddef.h>
#include <stdint.h>

typedef struct fr_sort_item {
    uint64_t key;
    int index;
} fr_sort_item;

/* Stable sort of a by key (8 passes of 8 bits at most; a pass whose byte every key shares is
 * skipped). Returns 0, or -1 when its buffer cannot be allocated (a is then unchanged). */
int fr_sort_stable(fr_sort_item *a, size_t n);

/* A key whose unsigned order is v's order for every double but NaN; -0 and +0 get one key
 * (they compare equal). */
uint64_t fr_sort_key_double(double v);

/* qsort's comparison of two doubles, ascending (no NaNs). */
int fr_cmp_double(const void *a, const void *b);

#endif
