/* A whole file mapped read-only into memory instead of copied: for large files parsed once
 * (dlib's 100 MB landmark model), the pages come straight from the page cache, with no copy
 * and no fresh memory to fault in. Internal. */
#ifndef FR_IO_FILE_MAP_H
#define FR_IO_FILE_MAP_H

#include <stddef.h>

#include "frig/frig.h"

typedef struct fr_file_map {
    const unsigned char *data; /* NULL for an empty file */
    size_t size;
} fr_file_map;

/* Statuses as fr_read_file's: NOT_FOUND, IO, TOO_LARGE (over max_size). */
frig_status fr_file_map_open(frig_ctx *ctx, const char *path, size_t max_size, fr_file_map *map);
void fr_file_map_close(fr_file_map *map);

#endif
