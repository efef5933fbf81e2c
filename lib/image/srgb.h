/* sRGB <-> linear light (IEC 61966-2-1), values in [0, 1]. Internal. */
#ifndef FR_IMAGE_SRGB_H
#define FR_IMAGE_SRGB_H

double fr_srgb_to_linear(double c);
/* Clamped to [0, 1]. */
double fr_linear_to_srgb(double c);

/* The 256 linear values of 8-bit sRGB codes. */
void fr_srgb_decode_table(float table[256]);

#endif
