/* dlib's binary serialization format, read from memory (format described in dlib/serialize.h
 * and dlib/float_details.h): an integer is a control byte (bit 7: negative, low 4 bits: how
 * many little-endian magnitude bytes follow) then its bytes; a float is two such integers,
 * mantissa then exponent, worth mantissa * 2^exponent; a std::vector is its count then its
 * elements; a matrix is rows and columns (both negated by newer writers) then row-major values. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>

#include "core/context.h"
#include "detect/dlib_deserialize.h"

/* float_details' exponent values that stand for +inf, -inf and NaN (and above: NaN). */
#define FR_DLIB_EXPONENT_SPECIAL 32000

void fr_dlib_reader_init(fr_dlib_reader *r, frig_ctx *ctx, const char *name, const unsigned char *data,
                         size_t size) {
    r->ctx = ctx;
    r->name = name;
    r->data = data;
    r->size = size;
    r->pos = 0;
    r->status = FRIG_OK;
}

static frig_status truncated(fr_dlib_reader *r, const char *what) {
    r->status = fr_error(r->ctx, FRIG_ERR_TRUNCATED, "%s: the file ends at byte %zu while reading %s (truncated dlib model)",
                         r->name, r->size, what);
    return r->status;
}

frig_status fr_dlib_corrupt(fr_dlib_reader *r, const char *fmt, ...) {
    char why[512];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(why, sizeof why, fmt, ap);
    va_end(ap);
    r->status = fr_error(r->ctx, FRIG_ERR_CORRUPT, "%s: corrupt dlib model near byte %zu: %s", r->name, r->pos, why);
    return r->status;
}

/* The control byte and 'n' magnitude bytes; n is checked by the caller's rule. */
static frig_status read_control(fr_dlib_reader *r, const char *what, unsigned *control) {
    if (r->status) return r->status;
    if (r->pos >= r->size) return truncated(r, what);
    *control = r->data[r->pos++];
    return FRIG_OK;
}

static frig_status read_magnitude(fr_dlib_reader *r, const char *what, unsigned n, uint64_t *out) {
    if (r->size - r->pos < n) return truncated(r, what);
    uint64_t v = 0;
    for (unsigned i = n; i-- > 0;) v = (v << 8) | r->data[r->pos + i];
    r->pos += n;
    *out = v;
    return FRIG_OK;
}

frig_status fr_dlib_read_uint(fr_dlib_reader *r, const char *what, uint64_t *out) {
    unsigned control = 0;
    *out = 0;
    if (read_control(r, what, &control)) return r->status;
    /* Bits 4-6 are reserved and ignored; a set sign bit makes the size invalid. */
    unsigned n = control & 0x8Fu;
    if (n == 0 || n > 8) return fr_dlib_corrupt(r, "%s: bad unsigned integer control byte 0x%02x", what, control);
    return read_magnitude(r, what, n, out);
}

frig_status fr_dlib_read_int(fr_dlib_reader *r, const char *what, int bytes, int64_t *out) {
    unsigned control = 0;
    *out = 0;
    if (read_control(r, what, &control)) return r->status;
    unsigned n = control & 0x0Fu;
    if (n == 0 || n > (unsigned)bytes)
        return fr_dlib_corrupt(r, "%s: bad integer control byte 0x%02x for a %d-byte integer", what, control, bytes);
    uint64_t mag = 0;
    if (read_magnitude(r, what, n, &mag)) return r->status;
    uint64_t limit = (uint64_t)1 << (8 * bytes - 1); /* |INT_MIN| of the type */
    int negative = (control & 0x80u) != 0;
    if (mag > limit || (!negative && mag == limit))
        return fr_dlib_corrupt(r, "%s: integer out of range for %d bytes", what, bytes);
    *out = negative ? (mag == limit ? INT64_MIN : -(int64_t)mag) : (int64_t)mag;
    return FRIG_OK;
}

frig_status fr_dlib_read_float(fr_dlib_reader *r, const char *what, float *out) {
    *out = 0.0f;
    if (r->status) return r->status;
    if (r->pos >= r->size) return truncated(r, what);
    /* Bits 4-6 of a control byte are always clear; set ones mean dlib's ancient text format. */
    if (r->data[r->pos] & 0x70u)
        return fr_dlib_corrupt(r, "%s: not a binary float (dlib's old text float format is not read)", what);
    int64_t mantissa, exponent;
    if (fr_dlib_read_int(r, what, 8, &mantissa) || fr_dlib_read_int(r, what, 2, &exponent)) return r->status;
    if (exponent >= FR_DLIB_EXPONENT_SPECIAL) return fr_dlib_corrupt(r, "%s: infinite or NaN value", what);
    float v = ldexpf((float)mantissa, (int)exponent);
    if (!isfinite(v)) return fr_dlib_corrupt(r, "%s: value out of float range", what);
    *out = v;
    return FRIG_OK;
}

/* One float's bytes at d[0..left), decoded as fr_dlib_read_float decodes them when they are
 * well formed; 0 (and nothing stored) for anything else, which the careful reader then
 * reports in its own words. */
static size_t float_fast(const unsigned char *d, size_t left, float *out) {
    if (left < 4) return 0;
    unsigned c = d[0], n = c & 0x0Fu;
    if ((c & 0x70u) || n == 0 || n > 8 || left < 3 + n) return 0;
    uint64_t m = 0;
    for (unsigned i = n; i > 0; i--) m = (m << 8) | d[i];
    if (m >= (uint64_t)1 << 63) return 0; /* INT64_MIN and beyond: the careful path */
    unsigned c2 = d[1 + n], n2 = c2 & 0x0Fu;
    if (n2 == 0 || n2 > 2 || left < 2 + n + n2) return 0;
    unsigned e = d[2 + n];
    if (n2 == 2) e |= (unsigned)d[3 + n] << 8;
    if (e >= 32768u) return 0;
    int exponent = (c2 & 0x80u) ? -(int)e : (int)e;
    if (exponent >= FR_DLIB_EXPONENT_SPECIAL) return 0;
    int64_t mantissa = (c & 0x80u) ? -(int64_t)m : (int64_t)m;
    float v = ldexpf((float)mantissa, exponent);
    if (!isfinite(v)) return 0;
    *out = v;
    return 2 + n + n2;
}

frig_status fr_dlib_read_floats(fr_dlib_reader *r, const char *what, size_t count, float *out) {
    for (size_t i = 0; i < count; i++) {
        if (r->status) return r->status;
        size_t used = r->pos < r->size ? float_fast(r->data + r->pos, r->size - r->pos, &out[i]) : 0;
        if (used) r->pos += used;
        else if (fr_dlib_read_float(r, what, &out[i])) return r->status;
    }
    return r->status;
}

frig_status fr_dlib_read_count(fr_dlib_reader *r, const char *what, size_t min_item_bytes, uint64_t max,
                               size_t *out) {
    uint64_t n;
    *out = 0;
    if (fr_dlib_read_uint(r, what, &n)) return r->status;
    if (n > max) return fr_dlib_corrupt(r, "%s: %llu elements (at most %llu allowed)", what, (unsigned long long)n,
                                        (unsigned long long)max);
    if (min_item_bytes && n > (r->size - r->pos) / min_item_bytes) {
        /* The bytes left cannot hold that many elements: the file was cut (or the count is
         * damaged; either way the file ends before what it announces). */
        r->status = fr_error(r->ctx, FRIG_ERR_TRUNCATED,
                             "%s: %s announces %llu elements at byte %zu but the file ends %zu bytes later", r->name,
                             what, (unsigned long long)n, r->pos, r->size - r->pos);
        return r->status;
    }
    *out = (size_t)n;
    return FRIG_OK;
}

frig_status fr_dlib_read_column_header(fr_dlib_reader *r, const char *what, uint64_t max_rows, size_t *rows) {
    int64_t nr, nc;
    *rows = 0;
    if (fr_dlib_read_int(r, what, 8, &nr) || fr_dlib_read_int(r, what, 8, &nc)) return r->status;
    if (nr < 0 || nc < 0) { /* the newer format stores both negated */
        if (nr == INT64_MIN || nc == INT64_MIN) return fr_dlib_corrupt(r, "%s: bad matrix size", what);
        nr = -nr;
        nc = -nc;
    }
    if (nc != 1 || nr < 0)
        return fr_dlib_corrupt(r, "%s: a %lld x %lld matrix where a column vector was expected", what, (long long)nr,
                               (long long)nc);
    if ((uint64_t)nr > max_rows)
        return fr_dlib_corrupt(r, "%s: %lld rows (at most %llu allowed)", what, (long long)nr,
                               (unsigned long long)max_rows);
    *rows = (size_t)nr;
    return FRIG_OK;
}
