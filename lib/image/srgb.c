/* sRGB transfer functions (IEC 61966-2-1): synthetic photos and the rig's renders are lit and
 * shaded in linear light, then encoded, as a camera does; textures are painted in sRGB. */
#include <math.h>

#include "image/srgb.h"

double fr_srgb_to_linear(double c) { return c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4); }

double fr_linear_to_srgb(double c) {
    if (c <= 0.0) return 0.0;
    if (c >= 1.0) return 1.0;
    return c <= 0.0031308 ? 12.92 * c : 1.055 * pow(c, 1.0 / 2.4) - 0.055;
}

void fr_srgb_decode_table(float table[256]) {
    for (int i = 0; i < 256; i++) table[i] = (float)fr_srgb_to_linear(i / 255.0);
}
