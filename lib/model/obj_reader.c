/* Wavefront OBJ reading for ICT-FaceKit (Wavefront Technologies, "Object Files (.obj)",
 * Advanced Visualizer manual, appendix B1): a single pass over the text with a hand-written
 * number parser, since the importer reads ~160 files of ~27k lines. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "model/obj_reader.h"

static const double pow10_table[23] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,  1e9,  1e10, 1e11,
                                       1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};

/* m * 10^e, exact powers of ten where they exist (correctly rounded for the short decimals
 * of OBJ files). */
static double scale10(double m, int e) {
    while (e > 22) m *= 1e22, e -= 22;
    while (e < -22) m /= 1e22, e += 22;
    return e >= 0 ? m * pow10_table[e] : m / pow10_table[-e];
}

int fr_parse_double(const char **p, const char *end, double *out) {
    const char *s = *p;
    int neg = 0;
    if (s < end && (*s == '-' || *s == '+')) neg = *s++ == '-';
    uint64_t mant = 0;
    int digits = 0, exp10 = 0, any = 0;
    for (; s < end && *s >= '0' && *s <= '9'; s++, any = 1) {
        if (digits < 19) {
            if (mant || *s != '0') digits++;
            mant = mant * 10 + (uint64_t)(*s - '0');
        } else {
            exp10++;
        }
    }
    if (s < end && *s == '.') {
        for (s++; s < end && *s >= '0' && *s <= '9'; s++, any = 1) {
            if (digits < 19) {
                if (mant || *s != '0') digits++;
                mant = mant * 10 + (uint64_t)(*s - '0');
                exp10--;
            }
        }
    }
    if (!any) return 0;
    if (s < end && (*s == 'e' || *s == 'E')) {
        const char *q = s + 1;
        int eneg = 0, e = 0, edig = 0;
        if (q < end && (*q == '-' || *q == '+')) eneg = *q++ == '-';
        for (; q < end && *q >= '0' && *q <= '9'; q++, edig++)
            if (e < 10000) e = e * 10 + (*q - '0');
        if (!edig) return 0;
        exp10 += eneg ? -e : e;
        s = q;
    }
    if (exp10 < -400 || exp10 > 400) return 0;
    double v = scale10((double)mant, exp10);
    if (!isfinite(v)) return 0;
    *out = neg ? -v : v;
    *p = s;
    return 1;
}

static int parse_int(const char **p, const char *end, long *out) {
    const char *s = *p;
    int neg = 0;
    if (s < end && (*s == '-' || *s == '+')) neg = *s++ == '-';
    long v = 0;
    const char *start = s;
    for (; s < end && *s >= '0' && *s <= '9'; s++)
        if (v < 1000000000L) v = v * 10 + (*s - '0');
    if (s == start) return 0;
    *out = neg ? -v : v;
    *p = s;
    return 1;
}

static int is_space(char c) { return c == ' ' || c == '\t' || c == '\r'; }
static int at_token_end(const char *s, const char *end) { return s >= end || is_space(*s) || *s == '\n'; }

typedef struct reader {
    const char *name;
    long line;
    char *err;
    size_t err_size;
    fr_obj *obj;
    int cap_v, cap_vt, cap_poly, cap_corner, cap_mat;
    int current_material;
} reader;

static frig_status fail(reader *r, frig_status s, const char *fmt, ...) {
    va_list ap;
    va_start(ap, fmt);
    int n = snprintf(r->err, r->err_size, "%s line %ld: ", r->name, r->line);
    if (n > 0 && (size_t)n < r->err_size) vsnprintf(r->err + n, r->err_size - (size_t)n, fmt, ap);
    va_end(ap);
    return s;
}

/* Grow *arr (elements of 'size' bytes) to hold at least 'need' elements. */
static int grow(void **arr, int *cap, int need, size_t size) {
    if (need <= *cap) return 1;
    int ncap = *cap ? *cap : 1024;
    while (ncap < need) {
        if (ncap > (1 << 29)) return 0;
        ncap *= 2;
    }
    void *n = realloc(*arr, (size_t)ncap * size);
    if (!n) return 0;
    *arr = n;
    *cap = ncap;
    return 1;
}

/* A token's text for messages. */
static const char *token(const char *s, const char *end, char *buf, size_t size) {
    size_t n = 0;
    while (s + n < end && !at_token_end(s + n, end) && n + 1 < size) n++;
    memcpy(buf, s, n);
    buf[n] = 0;
    return buf;
}

static const char *skip_spaces(const char *s, const char *end) {
    while (s < end && is_space(*s)) s++;
    return s;
}

static frig_status read_numbers(reader *r, const char **p, const char *end, int n, double *out) {
    for (int i = 0; i < n; i++) {
        const char *s = skip_spaces(*p, end);
        if (s >= end || *s == '\n') return fail(r, FRIG_ERR_CORRUPT, "expected %d numbers, found %d", n, i);
        if (!fr_parse_double(&s, end, &out[i]) || !at_token_end(s, end)) {
            char buf[40];
            return fail(r, FRIG_ERR_CORRUPT, "malformed number '%s'", token(skip_spaces(*p, end), end, buf, sizeof buf));
        }
        *p = s;
    }
    return FRIG_OK;
}

static frig_status read_vertex(reader *r, const char **p, const char *end) {
    fr_obj *o = r->obj;
    if (!grow((void **)&o->positions, &r->cap_v, o->vertex_count + 1, 3 * sizeof(double)))
        return fail(r, FRIG_ERR_NO_MEMORY, "out of memory");
    frig_status s = read_numbers(r, p, end, 3, o->positions + 3 * o->vertex_count);
    if (!s) o->vertex_count++;
    return s;
}

static frig_status read_uv(reader *r, const char **p, const char *end) {
    fr_obj *o = r->obj;
    double uv[2];
    frig_status s = read_numbers(r, p, end, 2, uv);
    if (s) return s;
    if (!grow((void **)&o->uvs, &r->cap_vt, o->uv_count + 1, 2 * sizeof(float)))
        return fail(r, FRIG_ERR_NO_MEMORY, "out of memory");
    o->uvs[2 * o->uv_count] = (float)uv[0];
    o->uvs[2 * o->uv_count + 1] = (float)uv[1];
    o->uv_count++;
    return FRIG_OK;
}

static frig_status add_material(reader *r, const char *name, size_t len) {
    fr_obj *o = r->obj;
    for (int i = 0; i < o->material_count; i++)
        if (strlen(o->material_names[i]) == len && memcmp(o->material_names[i], name, len) == 0) {
            r->current_material = i;
            return FRIG_OK;
        }
    if (!grow((void **)&o->material_names, &r->cap_mat, o->material_count + 1, sizeof(char *)))
        return fail(r, FRIG_ERR_NO_MEMORY, "out of memory");
    char *s = malloc(len + 1);
    if (!s) return fail(r, FRIG_ERR_NO_MEMORY, "out of memory");
    memcpy(s, name, len);
    s[len] = 0;
    o->material_names[o->material_count] = s;
    r->current_material = o->material_count++;
    return FRIG_OK;
}

/* Resolve a 1-based or negative (relative) OBJ index against 'count' items read so far. */
static int resolve(long idx, int count) {
    if (idx > 0 && idx <= count) return (int)(idx - 1);
    if (idx < 0 && -idx <= count) return (int)(count + idx);
    return -1;
}

static frig_status read_corner(reader *r, const char **p, const char *end, int32_t *v, int32_t *vt) {
    const char *s = *p;
    long iv, ivt = 0, ivn;
    char buf[40];
    if (!parse_int(&s, end, &iv)) return fail(r, FRIG_ERR_CORRUPT, "malformed face corner '%s'", token(*p, end, buf, sizeof buf));
    if (s < end && *s == '/') {
        s++;
        if (s < end && *s != '/' && !parse_int(&s, end, &ivt))
            return fail(r, FRIG_ERR_CORRUPT, "malformed face corner '%s'", token(*p, end, buf, sizeof buf));
        if (s < end && *s == '/') {
            s++;
            if (!parse_int(&s, end, &ivn))
                return fail(r, FRIG_ERR_CORRUPT, "malformed face corner '%s'", token(*p, end, buf, sizeof buf));
        }
    }
    if (!at_token_end(s, end)) return fail(r, FRIG_ERR_CORRUPT, "malformed face corner '%s'", token(*p, end, buf, sizeof buf));
    *v = resolve(iv, r->obj->vertex_count);
    *vt = ivt ? resolve(ivt, r->obj->uv_count) : -1;
    if (*v < 0 || (ivt && *vt < 0))
        return fail(r, FRIG_ERR_CORRUPT, "face corner '%s' refers to a vertex or uv not defined before it",
                    token(*p, end, buf, sizeof buf));
    *p = s;
    return FRIG_OK;
}

static frig_status read_face(reader *r, const char **p, const char *end) {
    fr_obj *o = r->obj;
    if (r->current_material < 0) {
        frig_status s = add_material(r, "default", 7);
        if (s) return s;
    }
    int n = 0;
    for (;;) {
        const char *s = skip_spaces(*p, end);
        *p = s;
        if (s >= end || *s == '\n') break;
        int cap = r->cap_corner;
        if (!grow((void **)&o->corners, &cap, o->corner_count + n + 1, sizeof(int32_t)) ||
            !grow((void **)&o->corner_uvs, &r->cap_corner, o->corner_count + n + 1, sizeof(int32_t)))
            return fail(r, FRIG_ERR_NO_MEMORY, "out of memory");
        frig_status st = read_corner(r, p, end, &o->corners[o->corner_count + n], &o->corner_uvs[o->corner_count + n]);
        if (st) return st;
        n++;
    }
    if (n < 3) return fail(r, FRIG_ERR_CORRUPT, "a face with %d corners", n);
    int cap_off = r->cap_poly;
    if (!grow((void **)&o->offsets, &cap_off, o->polygon_count + 2, sizeof(int32_t)) ||
        !grow((void **)&o->materials, &r->cap_poly, o->polygon_count + 2, sizeof(int32_t)))
        return fail(r, FRIG_ERR_NO_MEMORY, "out of memory");
    o->corner_count += n;
    o->materials[o->polygon_count] = r->current_material;
    o->offsets[++o->polygon_count] = o->corner_count;
    return FRIG_OK;
}

/* The rest of the line as a name (trimmed). */
static frig_status read_name(reader *r, const char **p, const char *end, const char **name, size_t *len) {
    const char *s = skip_spaces(*p, end), *e = s;
    while (e < end && *e != '\n') e++;
    while (e > s && is_space(e[-1])) e--;
    if (e == s) return fail(r, FRIG_ERR_CORRUPT, "a statement without its name");
    *name = s;
    *len = (size_t)(e - s);
    *p = e;
    return FRIG_OK;
}

static frig_status read_statement(reader *r, const char **p, const char *end) {
    const char *s = *p;
    const char *name;
    size_t len;
    frig_status st;
    if (s + 1 < end && s[0] == 'v' && is_space(s[1])) {
        *p = s + 1;
        return read_vertex(r, p, end);
    }
    if (s + 2 < end && s[0] == 'v' && s[1] == 't' && is_space(s[2])) {
        *p = s + 2;
        return read_uv(r, p, end);
    }
    if (s + 1 < end && s[0] == 'f' && is_space(s[1])) {
        *p = s + 1;
        return read_face(r, p, end);
    }
    if (end - s > 7 && memcmp(s, "usemtl", 6) == 0 && is_space(s[6])) {
        *p = s + 6;
        if ((st = read_name(r, p, end, &name, &len))) return st;
        return add_material(r, name, len);
    }
    if (end - s > 7 && memcmp(s, "mtllib", 6) == 0 && is_space(s[6])) {
        *p = s + 6;
        if ((st = read_name(r, p, end, &name, &len))) return st;
        if (!r->obj->mtllib) {
            r->obj->mtllib = malloc(len + 1);
            if (!r->obj->mtllib) return fail(r, FRIG_ERR_NO_MEMORY, "out of memory");
            memcpy(r->obj->mtllib, name, len);
            r->obj->mtllib[len] = 0;
        }
        return FRIG_OK;
    }
    return FRIG_OK; /* comments, vn, o, g, s, l, ...: skipped */
}

frig_status fr_obj_parse(const char *text, size_t size, const char *name, fr_obj *out, char *err, size_t err_size) {
    memset(out, 0, sizeof *out);
    reader r = {.name = name, .err = err, .err_size = err_size, .obj = out, .current_material = -1};
    out->offsets = malloc(sizeof(int32_t));
    if (!out->offsets) return fail(&r, FRIG_ERR_NO_MEMORY, "out of memory");
    out->offsets[0] = 0;
    r.cap_poly = 0;
    const char *p = text, *end = text + size;
    frig_status s = FRIG_OK;
    /* offsets has its own capacity bookkeeping in read_face: start it at one element. */
    while (p < end && !s) {
        r.line++;
        p = skip_spaces(p, end);
        s = read_statement(&r, &p, end);
        while (p < end && *p != '\n') p++;
        if (p < end) p++;
    }
    if (s) fr_obj_free(out);
    return s;
}

void fr_obj_free(fr_obj *obj) {
    free(obj->positions);
    free(obj->uvs);
    free(obj->offsets);
    free(obj->corners);
    free(obj->corner_uvs);
    free(obj->materials);
    for (int i = 0; i < obj->material_count; i++) free(obj->material_names[i]);
    free(obj->material_names);
    free(obj->mtllib);
    memset(obj, 0, sizeof *obj);
}
