/* The model/rig container: header, section table, 16-byte aligned little-endian sections
 * and a CRC-32 over the whole file (the CRC field counted as zero). The format is
 * written down in docs/model-format.md; every count and offset is checked before use. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "io/container.h"
#include "io/crc32.h"

#define CRC_OFFSET 40

static int host_is_big_endian(void) {
    const uint16_t one = 1;
    unsigned char b;
    memcpy(&b, &one, 1);
    return b == 0;
}

static void put_u32(unsigned char *p, uint32_t v) {
    for (int i = 0; i < 4; i++) p[i] = (unsigned char)(v >> (8 * i));
}
static void put_u64(unsigned char *p, uint64_t v) {
    for (int i = 0; i < 8; i++) p[i] = (unsigned char)(v >> (8 * i));
}
static uint32_t get_u32(const unsigned char *p) {
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}
static uint64_t get_u64(const unsigned char *p) {
    return (uint64_t)get_u32(p) | (uint64_t)get_u32(p + 4) << 32;
}

static size_t element_size(fr_section_type t) { return t == FR_SEC_BYTES ? 1 : 4; }
static uint64_t align16(uint64_t x) { return (x + 15) & ~(uint64_t)15; }

/* Reverse each 4-byte word (host <-> little-endian on a big-endian host). */
static void swap_words(unsigned char *p, uint64_t words) {
    for (uint64_t i = 0; i < words; i++, p += 4) {
        unsigned char a = p[0], b = p[1];
        p[0] = p[3], p[1] = p[2], p[2] = b, p[3] = a;
    }
}

static uint32_t file_crc(const unsigned char *buf, size_t size) {
    static const unsigned char zero[4] = {0, 0, 0, 0};
    fr_crc32 c;
    fr_crc32_init(&c);
    fr_crc32_update(&c, buf, CRC_OFFSET);
    fr_crc32_update(&c, zero, 4);
    fr_crc32_update(&c, buf + CRC_OFFSET + 4, size - CRC_OFFSET - 4);
    return fr_crc32_final(&c);
}

frig_status fr_container_pack(frig_ctx *ctx, const char magic[8], uint32_t version, const fr_section *sections,
                              int count, unsigned char **out, size_t *size) {
    *out = NULL;
    *size = 0;
    if (count < 0 || count > FR_CONTAINER_MAX_SECTIONS)
        return fr_error(ctx, FRIG_ERR_INTERNAL, "container with %d sections (at most %d)", count,
                        FR_CONTAINER_MAX_SECTIONS);
    uint64_t pos = align16(FR_CONTAINER_HEADER + (uint64_t)count * FR_CONTAINER_ENTRY);
    uint64_t offsets[FR_CONTAINER_MAX_SECTIONS];
    for (int i = 0; i < count; i++) {
        if (strlen(sections[i].tag) >= FR_CONTAINER_TAG)
            return fr_error(ctx, FRIG_ERR_INTERNAL, "section tag '%s' is too long", sections[i].tag);
        offsets[i] = pos;
        pos = align16(pos + sections[i].count * element_size(sections[i].type));
    }
    uint64_t total = count ? offsets[count - 1] + sections[count - 1].count * element_size(sections[count - 1].type)
                           : (uint64_t)FR_CONTAINER_HEADER;
    if (total > (uint64_t)SIZE_MAX / 2) return fr_error(ctx, FRIG_ERR_TOO_LARGE, "container of %llu bytes", (unsigned long long)total);
    unsigned char *buf = calloc((size_t)total, 1);
    if (!buf) return fr_nomem(ctx, "a model or rig file image");
    memcpy(buf, magic, 8);
    put_u32(buf + 8, version);
    put_u32(buf + 12, FR_CONTAINER_HEADER);
    put_u32(buf + 16, (uint32_t)count);
    put_u32(buf + 20, FR_CONTAINER_ENTRY);
    put_u64(buf + 24, total);
    put_u64(buf + 32, FR_CONTAINER_HEADER);
    int swap = host_is_big_endian();
    for (int i = 0; i < count; i++) {
        unsigned char *e = buf + FR_CONTAINER_HEADER + (size_t)i * FR_CONTAINER_ENTRY;
        memcpy(e, sections[i].tag, strlen(sections[i].tag));
        put_u32(e + 16, (uint32_t)sections[i].type);
        put_u64(e + 24, offsets[i]);
        put_u64(e + 32, sections[i].count);
        size_t bytes = (size_t)(sections[i].count * element_size(sections[i].type));
        if (bytes) memcpy(buf + offsets[i], sections[i].data, bytes);
        if (swap && sections[i].type != FR_SEC_BYTES) swap_words(buf + offsets[i], sections[i].count);
    }
    put_u32(buf + CRC_OFFSET, file_crc(buf, (size_t)total));
    *out = buf;
    *size = (size_t)total;
    return FRIG_OK;
}

static frig_status check_header(frig_ctx *ctx, const char *what, const char magic[8], uint32_t version,
                                const unsigned char *buf, size_t size, uint32_t *count) {
    if (size < FR_CONTAINER_HEADER)
        return fr_error(ctx, size >= 8 && memcmp(buf, magic, 8) == 0 ? FRIG_ERR_TRUNCATED : FRIG_ERR_CORRUPT,
                        "%s: %zu bytes, too short for a libfrig %.7s file", what, size, magic);
    if (memcmp(buf, magic, 8) != 0)
        return fr_error(ctx, FRIG_ERR_CORRUPT, "%s: not a libfrig %.7s file (wrong magic bytes)", what, magic);
    uint32_t v = get_u32(buf + 8);
    if (v != version)
        return fr_error(ctx, v > version ? FRIG_ERR_UNSUPPORTED : FRIG_ERR_CORRUPT,
                        "%s: format version %u, this libfrig reads version %u", what, v, version);
    uint64_t file_size = get_u64(buf + 24);
    if (file_size > size)
        return fr_error(ctx, FRIG_ERR_TRUNCATED, "%s: file ends at byte %zu of %llu (truncated)", what, size,
                        (unsigned long long)file_size);
    if (file_size < size)
        return fr_error(ctx, FRIG_ERR_CORRUPT, "%s: %zu bytes where the header says %llu", what, size,
                        (unsigned long long)file_size);
    uint32_t crc = file_crc(buf, size), stored = get_u32(buf + CRC_OFFSET);
    if (crc != stored)
        return fr_error(ctx, FRIG_ERR_CORRUPT, "%s: checksum mismatch (stored %08x, computed %08x): the file is damaged",
                        what, stored, crc);
    *count = get_u32(buf + 16);
    if (get_u32(buf + 12) != FR_CONTAINER_HEADER || get_u32(buf + 20) != FR_CONTAINER_ENTRY ||
        get_u64(buf + 32) != FR_CONTAINER_HEADER || *count > FR_CONTAINER_MAX_SECTIONS)
        return fr_error(ctx, FRIG_ERR_CORRUPT, "%s: bad header (header size, entry size, table offset or %u sections)",
                        what, *count);
    return FRIG_OK;
}

frig_status fr_container_parse(frig_ctx *ctx, const char *what, const char magic[8], uint32_t version,
                               unsigned char *buf, size_t size, fr_container *out) {
    memset(out, 0, sizeof *out);
    out->what = what;
    uint32_t count = 0;
    frig_status s = check_header(ctx, what, magic, version, buf, size, &count);
    if (s) return s;
    uint64_t prev_end = FR_CONTAINER_HEADER + (uint64_t)count * FR_CONTAINER_ENTRY;
    if (prev_end > size) return fr_error(ctx, FRIG_ERR_CORRUPT, "%s: section table runs past the end", what);
    int swap = host_is_big_endian();
    for (uint32_t i = 0; i < count; i++) {
        const unsigned char *e = buf + FR_CONTAINER_HEADER + (size_t)i * FR_CONTAINER_ENTRY;
        fr_parsed_section *p = &out->sec[i];
        if (memchr(e, 0, FR_CONTAINER_TAG) == NULL || e[0] == 0)
            return fr_error(ctx, FRIG_ERR_CORRUPT, "%s: section %u has no valid tag", what, i);
        memcpy(p->tag, e, FR_CONTAINER_TAG);
        uint32_t type = get_u32(e + 16);
        uint64_t off = get_u64(e + 24), n = get_u64(e + 32);
        if (type < FR_SEC_BYTES || type > FR_SEC_F32)
            return fr_error(ctx, FRIG_ERR_CORRUPT, "%s: section '%s' has unknown type %u", what, p->tag, type);
        for (uint32_t j = 0; j < i; j++)
            if (strcmp(out->sec[j].tag, p->tag) == 0)
                return fr_error(ctx, FRIG_ERR_CORRUPT, "%s: section '%s' appears twice", what, p->tag);
        p->type = (fr_section_type)type;
        size_t es = element_size(p->type);
        /* Offsets increase, are aligned, and every section lies inside the file. */
        if (off % 16 != 0 || off < prev_end || off > size || n > (size - off) / es)
            return fr_error(ctx, FRIG_ERR_CORRUPT, "%s: section '%s' (offset %llu, %llu values) is misplaced", what,
                            p->tag, (unsigned long long)off, (unsigned long long)n);
        p->count = n;
        p->data = buf + off;
        prev_end = off + n * es;
        if (swap && p->type != FR_SEC_BYTES) swap_words(buf + off, n);
    }
    out->count = (int)count;
    return FRIG_OK;
}

frig_status fr_container_take(frig_ctx *ctx, const fr_container *c, const char *tag, fr_section_type type,
                              uint64_t count, void **data) {
    *data = NULL;
    for (int i = 0; i < c->count; i++) {
        const fr_parsed_section *p = &c->sec[i];
        if (strcmp(p->tag, tag) != 0) continue;
        if (p->type != type)
            return fr_error(ctx, FRIG_ERR_CORRUPT, "%s: section '%s' has type %d, expected %d", c->what, tag, p->type,
                            type);
        if (p->count != count)
            return fr_error(ctx, FRIG_ERR_CORRUPT, "%s: section '%s' holds %llu values where %llu were expected",
                            c->what, tag, (unsigned long long)p->count, (unsigned long long)count);
        *data = p->data;
        return FRIG_OK;
    }
    return fr_error(ctx, FRIG_ERR_CORRUPT, "%s: section '%s' is missing", c->what, tag);
}

frig_status fr_container_take_all(frig_ctx *ctx, const fr_container *c, const fr_section_want *want, int count) {
    for (int i = 0; i < count; i++) {
        void *p;
        frig_status s = fr_container_take(ctx, c, want[i].tag, want[i].type, want[i].count, &p);
        if (s) return s;
        *want[i].dst = p;
    }
    return FRIG_OK;
}

int fr_name_is_safe(const char *name) {
    size_t n = strlen(name);
    if (n < 1 || n > 63 || name[0] == '.') return 0;
    for (size_t i = 0; i < n; i++) {
        char ch = name[i];
        int ok = (ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z') || (ch >= '0' && ch <= '9') || ch == '_' ||
                 ch == '-' || ch == '.';
        if (!ok) return 0;
    }
    return 1;
}

frig_status fr_names_pack(frig_ctx *ctx, const char *const *names, int count, char **blob, size_t *size) {
    size_t total = 0;
    for (int i = 0; i < count; i++) total += strlen(names[i]) + 1;
    *blob = malloc(total ? total : 1);
    *size = total;
    if (!*blob) return fr_nomem(ctx, "names");
    size_t pos = 0;
    for (int i = 0; i < count; i++) {
        size_t n = strlen(names[i]) + 1;
        memcpy(*blob + pos, names[i], n);
        pos += n;
    }
    return FRIG_OK;
}

frig_status fr_names_parse(frig_ctx *ctx, const fr_container *c, const char *tag, int count, const char ***names,
                           const char **blob, size_t *blob_size) {
    *names = NULL;
    const fr_parsed_section *p = NULL;
    for (int i = 0; i < c->count; i++)
        if (strcmp(c->sec[i].tag, tag) == 0) p = &c->sec[i];
    if (!p || p->type != FR_SEC_BYTES)
        return fr_error(ctx, FRIG_ERR_CORRUPT, "%s: name section '%s' is missing", c->what, tag);
    const char *s = p->data, *end = s + p->count;
    const char **list = malloc(sizeof *list * (size_t)(count > 0 ? count : 1));
    if (!list) return fr_nomem(ctx, "a name list");
    for (int i = 0; i < count; i++) {
        const char *nul = s < end ? memchr(s, 0, (size_t)(end - s)) : NULL;
        if (!nul || !fr_name_is_safe(s)) {
            free(list);
            return fr_error(ctx, FRIG_ERR_CORRUPT, "%s: name %d of %d in '%s' is %s", c->what, i + 1, count, tag,
                            nul ? "not a plain name" : "missing or not terminated");
        }
        list[i] = s;
        s = nul + 1;
    }
    if (s != end) {
        free(list);
        return fr_error(ctx, FRIG_ERR_CORRUPT, "%s: '%s' holds more than %d names", c->what, tag, count);
    }
    *names = list;
    *blob = p->data;
    *blob_size = (size_t)p->count;
    return FRIG_OK;
}

int fr_all_finite(const float *v, uint64_t count) {
    int ok = 1;
    for (uint64_t i = 0; i < count; i++) ok &= isfinite(v[i]) != 0;
    return ok;
}
