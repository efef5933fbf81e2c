/* Growable byte buffer with little-endian appends (see buffer.h). */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io/buffer.h"

void fr_buffer_free(fr_buffer *b) {
    free(b->data);
    memset(b, 0, sizeof *b);
}

void fr_buffer_reserve(fr_buffer *b, size_t n) {
    if (b->failed || n <= b->capacity) return;
    unsigned char *d = realloc(b->data, n);
    if (!d) {
        b->failed = 1;
        return;
    }
    b->data = d;
    b->capacity = n;
}

unsigned char *fr_buffer_extend(fr_buffer *b, size_t n) {
    if (b->failed) return NULL;
    if (b->size + n > b->capacity) {
        size_t cap = b->capacity ? b->capacity : 4096;
        while (cap < b->size + n) {
            if (cap > SIZE_MAX / 4) {
                b->failed = 1;
                return NULL;
            }
            cap *= 2;
        }
        unsigned char *d = realloc(b->data, cap);
        if (!d) {
            b->failed = 1;
            return NULL;
        }
        b->data = d;
        b->capacity = cap;
    }
    unsigned char *p = b->data + b->size;
    b->size += n;
    return p;
}

void fr_buffer_append(fr_buffer *b, const void *data, size_t n) {
    unsigned char *p = fr_buffer_extend(b, n);
    if (p && n) memcpy(p, data, n);
}

void fr_buffer_printf(fr_buffer *b, const char *fmt, ...) {
    char small[256];
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(small, sizeof small, fmt, ap);
    va_end(ap);
    if (n < 0) {
        b->failed = 1;
        return;
    }
    if ((size_t)n < sizeof small) {
        fr_buffer_append(b, small, (size_t)n);
        return;
    }
    unsigned char *p = fr_buffer_extend(b, (size_t)n + 1);
    if (!p) return;
    va_start(ap, fmt);
    vsnprintf((char *)p, (size_t)n + 1, fmt, ap);
    va_end(ap);
    b->size--; /* drop the NUL */
}

void fr_buffer_align(fr_buffer *b, size_t align, unsigned char byte) {
    while (!b->failed && b->size % align) fr_buffer_append(b, &byte, 1);
}

void fr_buffer_u16(fr_buffer *b, uint16_t v) {
    unsigned char p[2] = {(unsigned char)v, (unsigned char)(v >> 8)};
    fr_buffer_append(b, p, 2);
}

void fr_buffer_u32(fr_buffer *b, uint32_t v) {
    unsigned char p[4] = {(unsigned char)v, (unsigned char)(v >> 8), (unsigned char)(v >> 16), (unsigned char)(v >> 24)};
    fr_buffer_append(b, p, 4);
}

void fr_buffer_f32(fr_buffer *b, float v) {
    uint32_t u;
    memcpy(&u, &v, 4);
    fr_buffer_u32(b, u);
}
