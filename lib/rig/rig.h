/* The inside of frig_rig: like the model, one file image with the arrays pointing into it
 * (the shapes may be changed in place through the setters). Internal. */
#ifndef FR_RIG_RIG_H
#define FR_RIG_RIG_H

#include "frig/rig.h"
#include "io/container.h"
#include "mesh/topology.h"

#define FR_RIG_MAGIC "FRIGRIG"
#define FR_RIG_VERSION 1

struct frig_rig {
    unsigned char *image;
    size_t image_size;
    fr_topology topo;
    int shape_count;
    float *neutral, *deltas; /* 3 per vertex; deltas: shape k at 3 * vertex_count * k */
    const char **shape_names;
    const char *name_blob;
    size_t name_blob_size;
    /* run: the face's base-colour texture (PNG bytes as given; not in the rig file) */
    unsigned char *face_png;
    size_t face_png_size;
};

/* Pack a rig from its parts and bind the image (the one way a rig comes to be). */
frig_status fr_rig_build(frig_ctx *ctx, const fr_topology *topo, int shape_count, const float *neutral,
                         const float *deltas, const char *name_blob, size_t name_blob_size, frig_rig **out);
/* Validate an image (taken over: freed on failure too) and make a rig of it. */
frig_status fr_rig_from_image(frig_ctx *ctx, const char *what, unsigned char *image, size_t size, frig_rig **out);
frig_status fr_rig_pack(frig_ctx *ctx, const frig_rig *rig, unsigned char **image, size_t *size);

/* The shapes as exporters write them: grouped by ARKit name (ARKit's order first, then the
 * shapes ARKit lacks in rig order), deltas of a group summed. */
typedef struct fr_export_shapes {
    int count;
    const char **names; /* borrowed from the ARKit table or the rig */
    float *deltas;      /* 3 * vertex_count per shape */
} fr_export_shapes;

frig_status fr_export_shapes_make(frig_ctx *ctx, const frig_rig *rig, fr_export_shapes *out);
void fr_export_shapes_free(fr_export_shapes *s);

#endif
