/* Whole-file reads and atomic writes (write a temporary file beside the target, flush it,
 * rename it over the target): a failure never leaves a half file where a good one was. */
#ifndef FR_IO_FILE_H
#define FR_IO_FILE_H

#include <stdio.h>

#include "frig/frig.h"

/* Read a whole file. Statuses: NOT_FOUND, IO, TOO_LARGE (over max_size), NO_MEMORY. */
frig_status fr_read_file(frig_ctx *ctx, const char *path, size_t max_size, unsigned char **data, size_t *size);

/* Open a regular file for reading and give its size: the checks fr_read_file makes, for
 * readers of another kind (file_map.c). The caller closes *fd. */
frig_status fr_open_regular(frig_ctx *ctx, const char *path, size_t max_size, int *fd, size_t *size);

/* Write 'size' bytes to 'path' atomically. */
frig_status fr_write_file_atomic(frig_ctx *ctx, const char *path, const void *data, size_t size);

/* Streaming form: open a temporary file, write to its FILE*, then commit (rename) or abort. */
typedef struct fr_atomic_file {
    FILE *fp;
    char *final_path;
    char *temp_path;
} fr_atomic_file;

frig_status fr_atomic_open(frig_ctx *ctx, const char *path, fr_atomic_file *af);
/* Flushes, checks for write errors, renames. Frees af's strings in every case. */
frig_status fr_atomic_commit(frig_ctx *ctx, fr_atomic_file *af);
void fr_atomic_abort(fr_atomic_file *af);

/* mkdir -p; FRIG_ERR_IO with a message on failure. */
frig_status fr_make_dirs(frig_ctx *ctx, const char *path);

/* "dir/name" in a new string (NULL when out of memory). */
char *fr_path_join(const char *dir, const char *name);
/* Last path component (points into 'path'). */
const char *fr_path_base(const char *path);

#endif
