/* CRC-32 (IEEE 802.3, reflected polynomial 0xEDB88320, the one zlib and PNG use), computed
 * slice-by-8. Used to checksum the model and rig files. Internal. */
#ifndef FR_IO_CRC32_H
#define FR_IO_CRC32_H

#include <stddef.h>
#include <stdint.h>

/* The tables live in the state (no global mutable data): 8 KiB, built by fr_crc32_init. */
typedef struct fr_crc32 {
    uint32_t table[8][256];
    uint32_t crc;
} fr_crc32;

void fr_crc32_init(fr_crc32 *c);
void fr_crc32_update(fr_crc32 *c, const void *data, size_t size);
uint32_t fr_crc32_final(const fr_crc32 *c);
/* One-shot convenience (builds the tables each call). */
uint32_t fr_crc32_of(const void *data, size_t size);

#endif
