/* Binary little-endian PLY point clouds, read back (the writer is frig_save_ply). Internal. */
#ifndef FR_IO_PLY_READER_H
#define FR_IO_PLY_READER_H

#include "frig/frig.h"

typedef struct fr_ply_cloud {
    size_t count;
    float *xyz;        /* 3 per point */
    float *normals;    /* 3 per point; zeros when the file has none */
    float *confidence; /* 1 per point; ones when the file has none */
} fr_ply_cloud;

/* The vertex element's x y z (required), nx ny nz and confidence (optional), any scalar type.
 * Statuses: NOT_FOUND, IO, CORRUPT, TRUNCATED, UNSUPPORTED (ascii or big-endian files, list
 * properties among the vertices), NO_MEMORY; out is empty on failure. */
frig_status fr_ply_read(frig_ctx *ctx, const char *path, fr_ply_cloud *out);
void fr_ply_cloud_free(fr_ply_cloud *c);

#endif
