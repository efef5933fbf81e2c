/* Colour transfer between images (Reinhard, Ashikhmin, Gooch and Shirley 2001, "Color transfer
 * between images"; the paper's reference [65], section 5.1.2): the statistics of one set of
 * pixels moved onto another in the decorrelated l-alpha-beta space. Internal. */
#ifndef FR_IMAGE_COLOUR_TRANSFER_H
#define FR_IMAGE_COLOUR_TRANSFER_H

#include <stddef.h>
#include <stdint.h>

/* Change src (n linear RGB pixels, 3 floats each, changed in place where src_mask is set) so
 * that its l-alpha-beta mean (and, with match_spread, standard deviation) over the src_mask
 * pixels equals that of target over target_mask (masks may be NULL: all pixels). Pixels with a
 * non-positive channel are left alone. Returns the number of pixels changed. */
size_t fr_colour_transfer(float *src, const uint8_t *src_mask, const float *target, const uint8_t *target_mask,
                          size_t n, int match_spread);

#endif
