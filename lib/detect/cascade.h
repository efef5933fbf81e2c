/* OpenCV's boosted cascades (Viola-Jones; paper section 4.2, face boxes): Haar and LBP features,
 * stump and tree weak classifiers, read from opencv_traincascade's XML and evaluated so that the
 * boxes equal cv::CascadeClassifier::detectMultiScale's (OpenCV 4.6, Debian) for the same
 * parameters: the same pyramid (fixed-point bilinear resize), scan, stage sums and grouping. Internal. */
#ifndef FR_DETECT_CASCADE_H
#define FR_DETECT_CASCADE_H

#include <stddef.h>
#include <stdint.h>

#include "frig/frig.h"

/* ---- the model, as the reader (cascade_xml.c) builds it and the evaluator reads it ---- */

typedef enum fr_cascade_type { FR_CASCADE_HAAR = 0, FR_CASCADE_LBP = 1 } fr_cascade_type;

typedef struct fr_cascade_stage {
    int first_tree, ntrees;
    float threshold; /* the file's value minus 1e-5f, as OpenCV stores it */
} fr_cascade_stage;

typedef struct fr_cascade_tree {
    int first_node, nnodes, first_leaf; /* nnodes internal nodes, nnodes + 1 leaves */
} fr_cascade_tree;

/* left/right: > 0 is an internal node of the same tree, <= 0 the leaf number -value. */
typedef struct fr_cascade_node {
    int feature;
    float threshold; /* Haar only; LBP nodes use their 256-bit category subset */
    int left, right;
} fr_cascade_node;

typedef struct fr_cascade_rect {
    int x, y, w, h;
    float weight;
} fr_cascade_rect;

typedef struct fr_cascade_haar {
    int tilted, nrects; /* nrects 1..3; unused rects have weight 0 */
    fr_cascade_rect rect[3];
} fr_cascade_haar;

typedef struct fr_cascade_lbp {
    int x, y, w, h; /* top-left 3x3 block grid of w x h blocks */
} fr_cascade_lbp;

#define FR_CASCADE_SUBSET_WORDS 8 /* 256 LBP codes / 32 bits */

typedef struct fr_cascade {
    fr_cascade_type type;
    int win_w, win_h;
    int has_tilted;         /* a Haar feature uses the 45-degree integral */
    int max_nodes_per_tree; /* 1: every weak classifier is a stump */
    int nstages, ntrees, nnodes, nleaves, nfeatures;
    fr_cascade_stage *stages;
    fr_cascade_tree *trees;
    fr_cascade_node *nodes;
    float *leaves;
    int32_t *subsets; /* LBP: FR_CASCADE_SUBSET_WORDS per node */
    fr_cascade_haar *haar;
    fr_cascade_lbp *lbp;
} fr_cascade;

/* Read a cascade XML file. A malformed, truncated or inconsistent file gives FRIG_ERR_CORRUPT with
 * a sentence naming it; the old "opencv-haar-classifier" layout and HOG give FRIG_ERR_UNSUPPORTED. */
frig_status fr_cascade_load(frig_ctx *ctx, const char *path, fr_cascade **out);
/* The same from memory; 'name' is used in messages. */
frig_status fr_cascade_parse(frig_ctx *ctx, const char *name, const char *text, size_t size, fr_cascade **out);
void fr_cascade_free(fr_cascade *cascade);

/* ---- detection ---- */

typedef struct fr_cascade_box {
    int x, y, w, h;  /* pixels of the input image, clipped to it */
    int neighbors;   /* raw windows merged into the box (OpenCV's numDetections; 1 when not grouped) */
    double weight;   /* the largest last-stage sum among them (OpenCV's levelWeights for such boxes) */
} fr_cascade_box;

/* All objects in an 8-bit gray image, as detectMultiScale(image, scale_factor, min_neighbors, 0,
 * (min_w, min_h), (max_w, max_h)): max 0 means the image size; min_neighbors <= 0 returns the raw
 * windows ungrouped. *boxes is a new array (free() it; NULL when *count is 0). Thread-safe: the
 * cascade is only read, scratch memory is per call. Checks ctx's cancel flag between scales. */
frig_status fr_cascade_detect(frig_ctx *ctx, const fr_cascade *cascade, const uint8_t *gray, int w, int h,
                              size_t stride, double scale_factor, int min_neighbors, int min_w, int min_h,
                              int max_w, int max_h, fr_cascade_box **boxes, size_t *count);

/* ---- pieces, exposed for the tests ---- */

/* cv::resize(src, dst, Size(dw, dh), 0, 0, INTER_LINEAR) for 8-bit gray, bit for bit (OpenCV 4.6's
 * 11-bit fixed-point coefficients and its vector rounding). Returns 0, or -1 when out of memory. */
int fr_cascade_resize(const uint8_t *src, int sw, int sh, size_t sstride, uint8_t *dst, int dw, int dh,
                      size_t dstride);

/* Integral images of (w+1) x (h+1) entries, row stride 'istride' (>= w+1), modulo 2^32 as OpenCV's
 * CV_32S ones: sum, sum of squares (sqsum may be NULL), and the 45-degree "tilted" sum (tilted may
 * be NULL; needs scratch of fr_cascade_tilted_scratch(w, h) entries). */
void fr_cascade_integral(const uint8_t *img, int w, int h, size_t stride, uint32_t *sum, uint32_t *sqsum,
                         size_t istride);
size_t fr_cascade_tilted_scratch(int w, int h);
void fr_cascade_integral_tilted(const uint8_t *img, int w, int h, size_t stride, uint32_t *tilted, size_t istride,
                                uint32_t *scratch);

/* OpenCV's groupRectangles(rects, min_neighbors, eps) on raw windows (neighbors and weight of each
 * input are ignored; 1 and the window's weight are assumed). Writes at most n boxes back into 'boxes'
 * in OpenCV's order and returns their number, or -1 when out of memory. */
long fr_cascade_group(fr_cascade_box *boxes, size_t n, int min_neighbors, double eps);

#endif
