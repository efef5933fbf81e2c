/* Reading binary little-endian PLY point clouds (Turk, "The PLY Polygon File Format", 1994),
 * the layout frig_save_ply writes: a vertex element first, scalar properties; x y z and,
 * when present, nx ny nz and confidence are taken, other properties skipped. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "io/file.h"
#include "io/ply_reader.h"

#define PLY_MAX_FILE ((size_t)1 << 32)
#define PLY_MAX_PROPS 64

typedef struct ply_prop {
    char name[32];
    int size;  /* bytes */
    int kind;  /* 0 signed int, 1 unsigned int, 2 float */
    int slot;  /* 0..6 = x y z nx ny nz confidence, -1 = skipped */
} ply_prop;

static const char *const wanted[7] = {"x", "y", "z", "nx", "ny", "nz", "confidence"};

static int prop_type(const char *t, int *size, int *kind) {
    static const struct { const char *name; int size, kind; } types[] = {
        {"char", 1, 0},  {"int8", 1, 0},   {"uchar", 1, 1},  {"uint8", 1, 1},  {"short", 2, 0},
        {"int16", 2, 0}, {"ushort", 2, 1}, {"uint16", 2, 1}, {"int", 4, 0},    {"int32", 4, 0},
        {"uint", 4, 1},  {"uint32", 4, 1}, {"float", 4, 2},  {"float32", 4, 2}, {"double", 8, 2},
        {"float64", 8, 2}};
    for (size_t i = 0; i < sizeof types / sizeof types[0]; i++)
        if (!strcmp(t, types[i].name)) return *size = types[i].size, *kind = types[i].kind, 1;
    return 0;
}

static double read_value(const unsigned char *p, const ply_prop *pr) {
    uint64_t u = 0;
    for (int b = pr->size - 1; b >= 0; b--) u = (u << 8) | p[b];
    if (pr->kind == 2) {
        if (pr->size == 4) {
            uint32_t w = (uint32_t)u;
            float f;
            memcpy(&f, &w, 4);
            return f;
        }
        double d;
        memcpy(&d, &u, 8);
        return d;
    }
    if (pr->kind == 1) return (double)u;
    int shift = 64 - 8 * pr->size;
    return (double)((int64_t)(u << shift) >> shift);
}

/* The next header line (without its newline) into line; 0 at the end of the data. */
static int next_line(const unsigned char *data, size_t size, size_t *pos, char *line, size_t cap) {
    size_t n = 0;
    while (*pos < size && data[*pos] != '\n') {
        if (n + 1 < cap) line[n++] = (char)data[*pos];
        (*pos)++;
    }
    if (*pos >= size) return 0;
    (*pos)++;
    if (n && line[n - 1] == '\r') n--;
    line[n] = 0;
    return 1;
}

static frig_status parse_header(frig_ctx *ctx, const char *path, const unsigned char *data, size_t size,
                                size_t *pos, size_t *count, ply_prop *props, int *nprops) {
    char line[256];
    if (!next_line(data, size, pos, line, sizeof line) || strcmp(line, "ply") != 0)
        return fr_error(ctx, FRIG_ERR_CORRUPT, "%s: not a PLY file", path);
    int format_ok = 0, in_vertex = 0, seen_vertex = 0;
    *nprops = 0;
    for (;;) {
        if (!next_line(data, size, pos, line, sizeof line))
            return fr_error(ctx, FRIG_ERR_TRUNCATED, "%s: the PLY header has no end_header", path);
        char a[64] = "", b[64] = "", c[64] = "";
        int nw = sscanf(line, "%63s %63s %63s", a, b, c);
        if (nw <= 0 || !strcmp(a, "comment") || !strcmp(a, "obj_info")) continue;
        if (!strcmp(a, "end_header")) break;
        if (!strcmp(a, "format")) {
            if (strcmp(b, "binary_little_endian") != 0)
                return fr_error(ctx, FRIG_ERR_UNSUPPORTED, "%s: PLY format '%s' (only binary_little_endian is read)",
                                path, b);
            format_ok = 1;
        } else if (!strcmp(a, "element")) {
            if (seen_vertex) {
                in_vertex = 0; /* later elements are after the vertices: ignored */
                continue;
            }
            if (strcmp(b, "vertex") != 0)
                return fr_error(ctx, FRIG_ERR_UNSUPPORTED, "%s: the first PLY element is '%s', not vertex", path, b);
            char *end = NULL;
            unsigned long long n = strtoull(c, &end, 10);
            if (nw < 3 || !end || *end || c[0] == '-')
                return fr_error(ctx, FRIG_ERR_CORRUPT, "%s: bad vertex count '%s'", path, c);
            *count = (size_t)n;
            in_vertex = seen_vertex = 1;
        } else if (!strcmp(a, "property")) {
            if (!in_vertex) continue;
            if (!strcmp(b, "list"))
                return fr_error(ctx, FRIG_ERR_UNSUPPORTED, "%s: list property in the vertex element", path);
            if (*nprops >= PLY_MAX_PROPS)
                return fr_error(ctx, FRIG_ERR_UNSUPPORTED, "%s: more than %d vertex properties", path, PLY_MAX_PROPS);
            ply_prop *pr = &props[(*nprops)++];
            if (nw < 3 || !prop_type(b, &pr->size, &pr->kind))
                return fr_error(ctx, FRIG_ERR_CORRUPT, "%s: bad property line '%s'", path, line);
            snprintf(pr->name, sizeof pr->name, "%s", c);
            pr->slot = -1;
            for (int k = 0; k < 7; k++)
                if (!strcmp(c, wanted[k])) pr->slot = k;
        } else {
            return fr_error(ctx, FRIG_ERR_CORRUPT, "%s: unexpected PLY header line '%s'", path, line);
        }
    }
    if (!format_ok) return fr_error(ctx, FRIG_ERR_CORRUPT, "%s: the PLY header has no format line", path);
    if (!seen_vertex) return fr_error(ctx, FRIG_ERR_CORRUPT, "%s: the PLY file has no vertex element", path);
    return FRIG_OK;
}

frig_status fr_ply_read(frig_ctx *ctx, const char *path, fr_ply_cloud *out) {
    memset(out, 0, sizeof *out);
    unsigned char *data = NULL;
    size_t size = 0, pos = 0, count = 0;
    frig_status s = fr_read_file(ctx, path, PLY_MAX_FILE, &data, &size);
    if (s) return s;
    ply_prop props[PLY_MAX_PROPS];
    int nprops = 0, have[7] = {0};
    s = parse_header(ctx, path, data, size, &pos, &count, props, &nprops);
    size_t stride = 0;
    for (int k = 0; k < nprops && !s; k++) {
        stride += (size_t)props[k].size;
        if (props[k].slot >= 0) {
            if (have[props[k].slot]) s = fr_error(ctx, FRIG_ERR_CORRUPT, "%s: property %s twice", path, props[k].name);
            have[props[k].slot] = 1;
        }
    }
    if (!s && !(have[0] && have[1] && have[2]))
        s = fr_error(ctx, FRIG_ERR_CORRUPT, "%s: the vertices have no x, y and z", path);
    int normals = have[3] && have[4] && have[5];
    if (!s && (have[3] || have[4] || have[5]) && !normals)
        s = fr_error(ctx, FRIG_ERR_CORRUPT, "%s: the vertices have only some of nx, ny, nz", path);
    if (!s && count > (size - pos) / (stride ? stride : 1))
        s = fr_error(ctx, FRIG_ERR_TRUNCATED, "%s: %zu vertices announced, data for %zu", path, count,
                     (size - pos) / stride);
    if (!s) {
        out->count = count;
        out->xyz = malloc(sizeof(float) * (3 * count + 1));
        out->normals = calloc(3 * count + 1, sizeof(float));
        out->confidence = malloc(sizeof(float) * (count + 1));
        if (!out->xyz || !out->normals || !out->confidence) s = fr_nomem(ctx, path);
    }
    for (size_t i = 0; i < count && !s; i++) {
        const unsigned char *p = data + pos + i * stride;
        float v[7] = {0, 0, 0, 0, 0, 0, 1};
        for (int k = 0; k < nprops; k++) {
            if (props[k].slot >= 0) v[props[k].slot] = (float)read_value(p, &props[k]);
            p += props[k].size;
        }
        if (!isfinite(v[0]) || !isfinite(v[1]) || !isfinite(v[2])) {
            s = fr_error(ctx, FRIG_ERR_CORRUPT, "%s: vertex %zu is not finite", path, i);
            break;
        }
        memcpy(out->xyz + 3 * i, v, sizeof(float) * 3);
        memcpy(out->normals + 3 * i, v + 3, sizeof(float) * 3);
        out->confidence[i] = v[6];
    }
    free(data);
    if (s) fr_ply_cloud_free(out);
    return s;
}

void fr_ply_cloud_free(fr_ply_cloud *c) {
    free(c->xyz), free(c->normals), free(c->confidence);
    memset(c, 0, sizeof *c);
}
