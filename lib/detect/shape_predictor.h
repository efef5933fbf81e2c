/* dlib's face landmark shape predictor (an ensemble of regression trees, Kazemi & Sullivan,
 * "One Millisecond Face Alignment with an Ensemble of Regression Trees", CVPR 2014), read from
 * dlib's .dat files (e.g. Debian's shape_predictor_68_face_landmarks.dat) and evaluated in C
 * so that, for the same gray image and box, the points are dlib's. Internal. */
#ifndef FR_DETECT_SHAPE_PREDICTOR_H
#define FR_DETECT_SHAPE_PREDICTOR_H

#include <stddef.h>
#include <stdint.h>

#include "frig/frig.h"

/* Limits the reader enforces (dlib's 68-point model: 68 parts, 15 cascades of 500 trees of
 * depth 4 over 500 feature pixels each). They size the per-call scratch on the stack. */
#define FR_SP_MAX_PARTS 256
#define FR_SP_MAX_CASCADES 64
#define FR_SP_MAX_FEATURES 4096       /* feature pixels per cascade */
#define FR_SP_MAX_TREES 8192          /* trees per cascade */
#define FR_SP_MAX_TREE_DEPTH 16

/* One split node: go left when pixel[idx1] - pixel[idx2] > thresh. */
typedef struct fr_sp_split {
    uint16_t idx1, idx2;
    float thresh;
} fr_sp_split;

/* The model, flattened into arrays. Tree t has its splits at splits[split_begin[t] ..
 * split_begin[t+1]) (a full binary tree in breadth-first order) and split count + 1 leaves,
 * which start at leaf (split_begin[t] + t); a leaf is 2*parts floats in 'leaves'. */
typedef struct fr_shape_predictor {
    int parts;                 /* landmarks; a shape is 2*parts floats x0 y0 x1 y1 ... */
    int cascades;
    float *initial_shape;      /* [2*parts], in box-normalized coordinates (box = unit square) */
    /* The similarity fit from the initial shape depends only on it: its centroid and the
     * centred coordinates (double) and their sum of squares. */
    double initial_mean[2];
    double *initial_centred;   /* [2*parts] */
    double initial_sumsq;
    size_t *tree_begin;        /* [cascades+1]: trees of cascade c are tree_begin[c] .. [c+1] */
    size_t *feature_begin;     /* [cascades+1]: feature pixels of cascade c */
    size_t *split_begin;       /* [trees+1] */
    fr_sp_split *splits;
    float *leaves;             /* [(splits + trees) * 2*parts] */
    uint32_t *anchor;          /* [features]: the landmark each feature pixel is attached to */
    float *delta;              /* [2*features]: offset from that landmark, normalized coordinates */
} fr_shape_predictor;

/* Read a dlib shape predictor file. Statuses: NOT_FOUND, IO, CORRUPT (with the byte offset and
 * what was being read), TRUNCATED, NO_MEMORY. */
frig_status fr_shape_predictor_load(frig_ctx *ctx, const char *path, fr_shape_predictor **out);
/* The same from a buffer holding the file; 'name' is used in messages. */
frig_status fr_shape_predictor_parse(frig_ctx *ctx, const char *name, const unsigned char *data, size_t size,
                                     fr_shape_predictor **out);
void fr_shape_predictor_free(fr_shape_predictor *sp);

int fr_shape_predictor_num_parts(const fr_shape_predictor *sp);

/* The landmarks for one face: 'gray' is w x h 8-bit pixels, rows 'stride' bytes apart;
 * box_ltrb is a dlib rectangle (left, top, right, bottom, inclusive pixel coordinates, usually
 * whole numbers). out receives 2*parts doubles x0 y0 x1 y1 ... (136 for the 68-point model)
 * in pixel coordinates (centre of the top-left pixel at 0,0), not rounded: dlib returns
 * floor(v + 0.5) of these. Thread-safe (the model is only read; scratch is on the stack), no
 * allocation. FRIG_ERR_INVALID_ARGUMENT for NULL pointers, an empty image or a non-finite box. */
frig_status fr_shape_predictor_run(const fr_shape_predictor *sp, const uint8_t *gray, int w, int h, size_t stride,
                                   const double box_ltrb[4], double *out);

#endif
