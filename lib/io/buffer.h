/* A growable byte buffer for writers that build a file in memory (glTF, OBJ, PLY) before
 * one atomic write. Appends never fail loudly: the first failed allocation sets 'failed'
 * and later appends do nothing; check it once at the end. Internal. */
#ifndef FR_IO_BUFFER_H
#define FR_IO_BUFFER_H

#include <stddef.h>
#include <stdint.h>

typedef struct fr_buffer {
    unsigned char *data;
    size_t size, capacity;
    int failed;
} fr_buffer;

void fr_buffer_free(fr_buffer *b);
/* Make the capacity at least n bytes at once (a size known ahead: no growing copies). */
void fr_buffer_reserve(fr_buffer *b, size_t n);
/* Make room for n more bytes; returns a pointer to them (NULL once failed). Size grows by n. */
unsigned char *fr_buffer_extend(fr_buffer *b, size_t n);
void fr_buffer_append(fr_buffer *b, const void *data, size_t n);
void fr_buffer_printf(fr_buffer *b, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
/* Pad with 'byte' up to a multiple of 'align'. */
void fr_buffer_align(fr_buffer *b, size_t align, unsigned char byte);
/* Little-endian values, independent of the host's byte order. */
void fr_buffer_u16(fr_buffer *b, uint16_t v);
void fr_buffer_u32(fr_buffer *b, uint32_t v);
void fr_buffer_f32(fr_buffer *b, float v);

#endif
