/* The inside of frig_model: one file image (the model file's bytes, also what an import
 * packs) with every array pointing into it. Internal. */
#ifndef FR_MODEL_MODEL_H
#define FR_MODEL_MODEL_H

#include "frig/model.h"
#include "io/container.h"
#include "mesh/topology.h"

#define FR_MODEL_MAGIC "FRIGMDL"
#define FR_MODEL_VERSION 1
#define FR_MODEL_META 6 /* int32 values in "model_meta" */
#define FR_LANDMARK_COUNT 68

struct frig_model {
    unsigned char *image; /* owns everything below */
    size_t image_size;
    fr_topology topo;
    int identity_count, expression_count, landmark_count, contour_count[2], rigid_count;
    const float *neutral, *identity, *expressions;
    const char **expression_names; /* array owned here, strings in the image */
    const char *expression_blob;
    size_t expression_blob_size;
    const int32_t *expression_fitting, *landmarks, *contour[2], *rigid;
};

/* What a model is made of, before packing (arrays borrowed). */
typedef struct fr_model_parts {
    fr_topology topo;
    int identity_count, expression_count, landmark_count, contour_count[2], rigid_count;
    const float *neutral, *identity, *expressions;
    const char *expression_blob;
    size_t expression_blob_size;
    const int32_t *expression_fitting, *landmarks, *contour[2], *rigid;
} fr_model_parts;

/* Pack parts into a file image and bind it: the one way a model comes to be. */
frig_status fr_model_build(frig_ctx *ctx, const fr_model_parts *parts, frig_model **out);
/* Validate an image (taken over: freed on failure too) and make a model of it. */
frig_status fr_model_from_image(frig_ctx *ctx, const char *what, unsigned char *image, size_t size, frig_model **out);
/* The model's file image keeping only the first identity_count identity modes and
 * expression_count expressions (the whole model with the model's own counts). */
frig_status fr_model_pack(frig_ctx *ctx, const frig_model *m, int identity_count, int expression_count,
                          unsigned char **image, size_t *size);
/* The parts of an existing model (pointers into it). */
void fr_model_parts_of(const frig_model *m, fr_model_parts *parts);

/* out += modes (n x k column-major floats) * weights (k doubles, NULL = none) through one
 * BLAS sgemv; 'what' names the weights in messages. */
frig_status fr_add_modes(frig_ctx *ctx, int n, int k, const float *modes, const double *weights, float *out,
                         const char *what);

#endif
