/* Reading dlib's binary serialization format from a memory buffer (the format of
 * dlib/serialize.h, read to understand it, not copied): variable-length integers, floats as
 * (mantissa, exponent) integer pairs, matrices and std::vector counts. Internal.
 * Every read checks the bytes left; a failure sets the context's error naming the file and
 * the byte offset, and later reads on the same reader fail at once. */
#ifndef FR_DETECT_DLIB_DESERIALIZE_H
#define FR_DETECT_DLIB_DESERIALIZE_H

#include <stddef.h>
#include <stdint.h>

#include "frig/frig.h"

typedef struct fr_dlib_reader {
    frig_ctx *ctx;
    const char *name; /* the file, for messages */
    const unsigned char *data;
    size_t size, pos;
    frig_status status; /* the first failure (FRIG_OK while all reads succeeded) */
} fr_dlib_reader;

void fr_dlib_reader_init(fr_dlib_reader *r, frig_ctx *ctx, const char *name, const unsigned char *data,
                         size_t size);

/* An unsigned integer (dlib's 'unsigned long': at most 8 value bytes). */
frig_status fr_dlib_read_uint(fr_dlib_reader *r, const char *what, uint64_t *out);
/* A signed integer of a C++ type 'bytes' wide (2 short, 4 int, 8 long/int64). */
frig_status fr_dlib_read_int(fr_dlib_reader *r, const char *what, int bytes, int64_t *out);
/* A float stored as mantissa * 2^exponent; refuses infinities and NaNs (CORRUPT). */
frig_status fr_dlib_read_float(fr_dlib_reader *r, const char *what, float *out);
/* 'count' floats in a row (a matrix's values): the same values and errors as as many
 * fr_dlib_read_float calls, decoded in one tight loop. */
frig_status fr_dlib_read_floats(fr_dlib_reader *r, const char *what, size_t count, float *out);
/* A std::vector's element count, refused when the bytes left cannot hold that many elements
 * of at least min_item_bytes each (TRUNCATED), or when it exceeds 'max' (CORRUPT). */
frig_status fr_dlib_read_count(fr_dlib_reader *r, const char *what, size_t min_item_bytes, uint64_t max,
                               size_t *out);
/* The header of a column vector (dlib::matrix<T,0,1>): rows and columns; columns must be 1. */
frig_status fr_dlib_read_column_header(fr_dlib_reader *r, const char *what, uint64_t max_rows, size_t *rows);

/* Fail the reader with CORRUPT and a sentence about the current offset (for checks of
 * values made by the caller). */
frig_status fr_dlib_corrupt(fr_dlib_reader *r, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

#endif
