/* CRC-32 with the reflected polynomial 0xEDB88320 (ISO 3309 / ITU-T V.42, as in zlib and
 * PNG), slice-by-8: eight table look-ups consume eight bytes per step (Kounavis & Berry,
 * "A systematic approach to building high performance software-based CRC generators", 2005). */
#include <string.h>

#include "io/crc32.h"

void fr_crc32_init(fr_crc32 *c) {
    for (uint32_t i = 0; i < 256; i++) {
        uint32_t r = i;
        for (int k = 0; k < 8; k++) r = (r >> 1) ^ (0xEDB88320u & (0u - (r & 1u)));
        c->table[0][i] = r;
    }
    for (int t = 1; t < 8; t++)
        for (int i = 0; i < 256; i++) {
            uint32_t prev = c->table[t - 1][i];
            c->table[t][i] = (prev >> 8) ^ c->table[0][prev & 0xFF];
        }
    c->crc = 0xFFFFFFFFu;
}

void fr_crc32_update(fr_crc32 *c, const void *data, size_t size) {
    const unsigned char *p = data;
    uint32_t crc = c->crc;
    while (size >= 8) {
        /* Assemble little-endian words byte by byte: independent of host order and alignment. */
        uint32_t lo = crc ^ ((uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24);
        uint32_t hi = (uint32_t)p[4] | (uint32_t)p[5] << 8 | (uint32_t)p[6] << 16 | (uint32_t)p[7] << 24;
        crc = c->table[7][lo & 0xFF] ^ c->table[6][(lo >> 8) & 0xFF] ^ c->table[5][(lo >> 16) & 0xFF] ^
              c->table[4][lo >> 24] ^ c->table[3][hi & 0xFF] ^ c->table[2][(hi >> 8) & 0xFF] ^
              c->table[1][(hi >> 16) & 0xFF] ^ c->table[0][hi >> 24];
        p += 8;
        size -= 8;
    }
    while (size--) crc = (crc >> 8) ^ c->table[0][(crc ^ *p++) & 0xFF];
    c->crc = crc;
}

uint32_t fr_crc32_final(const fr_crc32 *c) { return c->crc ^ 0xFFFFFFFFu; }

uint32_t fr_crc32_of(const void *data, size_t size) {
    fr_crc32 c;
    fr_crc32_init(&c);
    fr_crc32_update(&c, data, size);
    return fr_crc32_final(&c);
}
