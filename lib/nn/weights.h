/* Trained network weights in TensorFlow.js's format (internal): a JSON manifest
 * NAME-weights_manifest.json listing groups of weights (name, shape, dtype, optional
 * quantization {dtype, scale, min}) and, per group, the binary shards holding them in order.
 * Every tensor is decoded to float32 at load (uint8 / uint16 quantized values are
 * q * scale + min, as tfjs's decodeWeights computes them). Nothing is trusted: the manifest's
 * structure, each shape, the byte count of every group against its shards, and at lookup each
 * tensor's shape against what the network expects. A damaged file is a status and a sentence. */
#ifndef FR_NN_WEIGHTS_H
#define FR_NN_WEIGHTS_H

#include <stddef.h>

#include "frig/core.h"

#define FR_NN_MAX_RANK 4

typedef struct fr_nn_tensor {
    char *name;
    int rank;
    int shape[FR_NN_MAX_RANK];
    size_t count; /* product of the shape (1 for a scalar) */
    float *data;
} fr_nn_tensor;

typedef struct fr_nn_weights {
    char *label; /* the model's name, in messages */
    size_t count;
    fr_nn_tensor *tensors;
} fr_nn_weights;

/* DIR/MODEL-weights_manifest.json and its shards (plain file names beside it). Statuses:
 * NOT_FOUND (no manifest or shard: the sentence names the file), CORRUPT, TRUNCATED,
 * UNSUPPORTED (a dtype or quantization we do not decode), NO_MEMORY. */
frig_status fr_nn_weights_load(frig_ctx *ctx, const char *dir, const char *model, fr_nn_weights **out);

/* The same from memory: the manifest's text and the concatenation of every group's shards in
 * manifest order (what the loader reads). */
frig_status fr_nn_weights_parse(frig_ctx *ctx, const char *label, const char *manifest, size_t manifest_size,
                                const unsigned char *bin, size_t bin_size, fr_nn_weights **out);

void fr_nn_weights_free(fr_nn_weights *w);

/* The tensor 'name' with exactly 'rank' dimensions 'shape'; NULL with FRIG_ERR_CORRUPT and a
 * sentence ("MODEL: tensor NAME is missing" / "has shape [..], expected [..]") otherwise. */
const float *fr_nn_weights_get(frig_ctx *ctx, const fr_nn_weights *w, const char *name, int rank, const int *shape);

#endif
