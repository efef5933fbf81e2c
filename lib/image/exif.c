/* EXIF orientation tag (0x0112) from IFD0 of a TIFF-structured block, bounds-checked. */
#include <stdint.h>

#include "image/image.h"

static unsigned rd16(const unsigned char *p, int little) {
    return little ? (unsigned)(p[0] | p[1] << 8) : (unsigned)(p[0] << 8 | p[1]);
}

static uint32_t rd32(const unsigned char *p, int little) {
    return little ? (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24
                  : (uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 | (uint32_t)p[3];
}

int fr_exif_orientation(const unsigned char *t, size_t size) {
    if (size < 8) return 0;
    int little;
    if (t[0] == 'I' && t[1] == 'I') little = 1;
    else if (t[0] == 'M' && t[1] == 'M') little = 0;
    else return 0;
    if (rd16(t + 2, little) != 42) return 0;
    uint32_t ifd = rd32(t + 4, little);
    if (ifd > size - 2) return 0;
    unsigned n = rd16(t + ifd, little);
    for (unsigned i = 0; i < n; i++) {
        size_t e = (size_t)ifd + 2 + 12 * (size_t)i;
        if (e + 12 > size) return 0;
        if (rd16(t + e, little) != 0x0112) continue;
        unsigned type = rd16(t + e + 2, little);
        if (type != 3) return 0; /* SHORT */
        unsigned v = rd16(t + e + 8, little);
        return v >= 1 && v <= 8 ? (int)v : 0;
    }
    return 0;
}
