/* Byte-identical photos of a set (see duplicates.h): a 64-bit FNV-1a hash and the size of
 * each usable photo's file find candidates; a full comparison of the bytes confirms them. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "detect/duplicates.h"
#include "io/file.h"
#include "workspace/photoset.h"

/* Photos are read again here; anything the image loader accepted is under this size. */
#define MAX_FILE_BYTES ((size_t)1 << 31)

static uint64_t fnv1a(const unsigned char *b, size_t n) {
    uint64_t h = 1469598103934665603ULL;
    for (size_t i = 0; i < n; i++) h = (h ^ b[i]) * 1099511628211ULL;
    return h;
}

typedef struct file_key {
    uint64_t hash;
    size_t size;
    int ok; /* the file could be read */
} file_key;

static int same_bytes(frig_ctx *ctx, const char *a, const char *b) {
    unsigned char *x = NULL, *y = NULL;
    size_t nx = 0, ny = 0;
    int same = fr_read_file(ctx, a, MAX_FILE_BYTES, &x, &nx) == FRIG_OK &&
               fr_read_file(ctx, b, MAX_FILE_BYTES, &y, &ny) == FRIG_OK && nx == ny && memcmp(x, y, nx) == 0;
    free(x);
    free(y);
    frig_ctx_clear_error(ctx);
    return same;
}

frig_status fr_mark_duplicates(frig_ctx *ctx, frig_photoset *set) {
    size_t n = set->count;
    file_key *key = calloc(n ? n : 1, sizeof *key);
    if (!key) return fr_error(ctx, FRIG_ERR_NO_MEMORY, "out of memory comparing photos");
    for (size_t i = 0; i < n; i++) {
        if (set->photos[i].status != FRIG_PHOTO_OK) continue;
        unsigned char *b = NULL;
        size_t size = 0;
        if (fr_read_file(ctx, set->photos[i].path, MAX_FILE_BYTES, &b, &size) == FRIG_OK) {
            key[i].hash = fnv1a(b, size);
            key[i].size = size;
            key[i].ok = 1;
        }
        free(b);
        frig_ctx_clear_error(ctx);
    }
    frig_status st = FRIG_OK;
    for (size_t i = 0; i < n && !st; i++) {
        if (!key[i].ok) continue;
        for (size_t j = 0; j < i; j++) {
            if (!key[j].ok || key[j].hash != key[i].hash || key[j].size != key[i].size) continue;
            if (!same_bytes(ctx, set->photos[j].path, set->photos[i].path)) continue;
            char reason[4200];
            snprintf(reason, sizeof reason, "the same bytes as %s", set->photos[j].path);
            st = frig_photoset_set_status(ctx, set, i, FRIG_PHOTO_DUPLICATE, reason);
            key[i].ok = 0; /* the first copy stays the reference */
            break;
        }
    }
    free(key);
    return st;
}
