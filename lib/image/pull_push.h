/* Filling an RGB image's unknown pixels smoothly from its known ones (pull-push: Gortler,
 * Grzeszczuk, Szeliski and Cohen, "The Lumigraph", SIGGRAPH 1996, section 3.4). Internal. */
#ifndef FR_IMAGE_PULL_PUSH_H
#define FR_IMAGE_PULL_PUSH_H

#include <stdint.h>

/* img: w x h pixels of 3 floats; known: w x h flags. Every unknown pixel takes a colour
 * interpolated from the known ones around it, near ones most (a pyramid of half-size averages of
 * the known pixels, pulled up, then pushed down with bilinear upsampling into the gaps); known
 * pixels keep theirs. Returns 1 when done, 0 when no pixel is known (img unchanged) and -1 when
 * memory ran out (img unchanged). Serial: the same bytes every time. */
int fr_pull_push(float *img, const uint8_t *known, int w, int h);

#endif
