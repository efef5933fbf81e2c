/* Binary little-endian PLY point clouds (Turk, "The PLY Polygon File Format", 1994):
 * x y z, optionally nx ny nz and a per-point confidence, all float. */
#include <stdio.h>

#include "core/context.h"
#include "io/buffer.h"
#include "io/file.h"
#include "frig/rig.h"

frig_status frig_save_ply(frig_ctx *ctx, const char *path, size_t count, const float *xyz, const float *normals,
                          const float *confidence) {
    if (!path || (count && !xyz)) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_save_ply: no path or points");
    fr_buffer b = {0};
    fr_buffer_printf(&b, "ply\nformat binary_little_endian 1.0\ncomment libfrig %s\nelement vertex %zu\n"
                         "property float x\nproperty float y\nproperty float z\n",
                     frig_version_string(), count);
    if (normals) fr_buffer_printf(&b, "property float nx\nproperty float ny\nproperty float nz\n");
    if (confidence) fr_buffer_printf(&b, "property float confidence\n");
    fr_buffer_printf(&b, "end_header\n");
    for (size_t i = 0; i < count; i++) {
        for (int d = 0; d < 3; d++) fr_buffer_f32(&b, xyz[3 * i + d]);
        if (normals)
            for (int d = 0; d < 3; d++) fr_buffer_f32(&b, normals[3 * i + d]);
        if (confidence) fr_buffer_f32(&b, confidence[i]);
    }
    frig_status s = b.failed ? fr_nomem(ctx, path) : fr_write_file_atomic(ctx, path, b.data, b.size);
    fr_buffer_free(&b);
    return s;
}
