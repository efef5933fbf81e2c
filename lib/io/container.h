/* The container shared by the model and rig files: a 64-byte header (magic, version, file
 * size, CRC-32), a table of named, typed sections, then the sections, 16-byte aligned, all
 * little-endian. Parsing validates the header, the table and the checksum before anyone
 * reads a section. Layout: docs/model-format.md. Internal. */
#ifndef FR_IO_CONTAINER_H
#define FR_IO_CONTAINER_H

#include <stdint.h>

#include "frig/frig.h"

#define FR_CONTAINER_HEADER 64
#define FR_CONTAINER_ENTRY 40
#define FR_CONTAINER_TAG 16
#define FR_CONTAINER_MAX_SECTIONS 64

typedef enum fr_section_type { FR_SEC_BYTES = 1, FR_SEC_I32 = 2, FR_SEC_F32 = 3 } fr_section_type;

/* A section to write: 'count' elements of 'type' (1 or 4 bytes each) at 'data'. */
typedef struct fr_section {
    const char *tag; /* at most 15 characters */
    fr_section_type type;
    uint64_t count;
    const void *data;
} fr_section;

/* A parsed section: data points into the parsed buffer, already in host byte order. */
typedef struct fr_parsed_section {
    char tag[FR_CONTAINER_TAG];
    fr_section_type type;
    uint64_t count;
    void *data;
} fr_parsed_section;

typedef struct fr_container {
    const char *what; /* the file name, for messages */
    int count;
    fr_parsed_section sec[FR_CONTAINER_MAX_SECTIONS];
} fr_container;

/* Serialize sections into a new buffer (caller frees). */
frig_status fr_container_pack(frig_ctx *ctx, const char magic[8], uint32_t version, const fr_section *sections,
                              int count, unsigned char **out, size_t *size);

/* Check buf (size bytes, malloc-aligned, modified in place on big-endian hosts) and fill
 * 'out' with pointers into it. 'what' names the file in messages and must outlive 'out'. */
frig_status fr_container_parse(frig_ctx *ctx, const char *what, const char magic[8], uint32_t version,
                               unsigned char *buf, size_t size, fr_container *out);

/* The section 'tag' with exactly 'count' elements of 'type', or a CORRUPT status naming
 * the file and the section. */
frig_status fr_container_take(frig_ctx *ctx, const fr_container *c, const char *tag, fr_section_type type,
                              uint64_t count, void **data);

/* Several sections at once: each wanted tag with its type and exact count, stored in *dst. */
typedef struct fr_section_want {
    const char *tag;
    fr_section_type type;
    uint64_t count;
    const void **dst;
} fr_section_want;
frig_status fr_container_take_all(frig_ctx *ctx, const fr_container *c, const fr_section_want *want, int count);

/* Name lists are stored as one BYTES section of NUL-terminated names, back to back. */
frig_status fr_names_pack(frig_ctx *ctx, const char *const *names, int count, char **blob, size_t *size);
/* Split a names section into exactly 'count' names (pointers into blob, array allocated
 * here). Every name must be 1..63 characters of [A-Za-z0-9_.-], not starting with '.'
 * (names become file names on export). */
frig_status fr_names_parse(frig_ctx *ctx, const fr_container *c, const char *tag, int count, const char ***names,
                           const char **blob, size_t *blob_size);
/* 1 when 'name' is a safe name in the sense above. */
int fr_name_is_safe(const char *name);

/* 1 when every value is finite. */
int fr_all_finite(const float *v, uint64_t count);

#endif
