/* Skin region detection (paper section 5.1.2): which pixels of a face region show skin, for
 * shape from shading (albedo and normals only from skin) and later fine-scale detail. YCbCr
 * chroma, a Gaussian mixture on (Cb, Cr) grown over rounds with more components and outliers
 * removed each round, then SLIC superpixels whose pixels are mostly not skin dropped whole
 * (hair, beard, hands, glasses, microphones). Pixels too dark or clipped carry no shading and
 * are never skin. Internal. */
#ifndef FR_SKIN_SKIN_H
#define FR_SKIN_SKIN_H

#include <stdint.h>

#include "frig/frig.h"
#include "skin/gmm.h"

typedef struct fr_skin_options {
    int rounds;              /* mixture rounds: 1, 2, ... components (3) */
    double chi2;             /* outlier: squared Mahalanobis distance above this to every component (9.21: 99%) */
    int em_iterations;       /* EM iterations per round (10) */
    int slic_step;           /* superpixel side in pixels; 0: no superpixels */
    double slic_compactness; /* SLIC's m (10) */
    double segment_skin;     /* a segment with a smaller share of skin pixels is dropped whole (0.5) */
    int dark;                /* 8-bit: brightest channel below this: too dark to read (12) */
    int clipped;             /* 8-bit: any channel at or above this: clipped (250) */
} fr_skin_options;

void fr_skin_options_default(fr_skin_options *o);

typedef struct fr_skin_stats {
    int region;       /* pixels of the region */
    int dark, clipped; /* of those, too dark / clipped */
    int chroma_skin;  /* skin by the colour model alone */
    int skin;         /* skin after the superpixels */
    int segments;     /* superpixels in the image */
    double mean_linear[3]; /* mean linear RGB of the skin pixels */
    double median_luma;    /* median 8-bit luma (BT.601 Y) of the region's pixels */
    fr_gmm2 gmm;      /* the final chroma model */
} fr_skin_stats;

/* (Y, Cb, Cr), ITU-R BT.601 full range (JPEG's), of an 8-bit RGB pixel. */
void fr_rgb_to_ycbcr(const uint8_t rgb[3], double ycc[3]);

/* Classify the pixels of a width x height 8-bit sRGB image (3 bytes per pixel, rows 'stride'
 * bytes apart) inside 'region' (1 per pixel; NULL: everywhere): skin[i] = 1 for skin, else 0.
 * The colour model is learnt from the pixels of 'core' (a part of the region where skin is
 * likely, e.g. the inner face without neck and ears, so that a collar or a shirt that fills
 * part of the region does not become a skin colour; NULL: the whole region). o may be NULL
 * (defaults); stats may be NULL. */
frig_status fr_skin_detect(frig_ctx *ctx, const uint8_t *rgb, int width, int height, size_t stride,
                           const uint8_t *region, const uint8_t *core, const fr_skin_options *o, uint8_t *skin,
                           fr_skin_stats *stats);

#endif
