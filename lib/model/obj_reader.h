/* A fast Wavefront OBJ reader for the model importer: v, vt, f (v, v/vt, v/vt/vn, v//vn,
 * negative = relative indices), usemtl, mtllib; other statements are skipped. Numbers are
 * parsed by hand (no sscanf per token). Errors name the file and the line. Internal. */
#ifndef FR_MODEL_OBJ_READER_H
#define FR_MODEL_OBJ_READER_H

#include <stddef.h>
#include <stdint.h>

#include "frig/frig.h"

typedef struct fr_obj {
    int vertex_count;
    double *positions;          /* 3 per vertex, as written in the file */
    int uv_count;
    float *uvs;                 /* 2 per uv */
    int polygon_count, corner_count;
    int32_t *offsets;           /* polygon_count + 1 */
    int32_t *corners;           /* 0-based vertex indices */
    int32_t *corner_uvs;        /* 0-based uv indices, -1 when the corner has none */
    int32_t *materials;         /* per polygon; "default" is added for faces before any usemtl */
    int material_count;
    char **material_names;
    char *mtllib;               /* the first mtllib file name, or NULL */
} fr_obj;

/* Parse 'size' bytes of OBJ text. 'name' is used in messages, written to err (a sentence
 * naming the file and line) on failure. Statuses: CORRUPT, NO_MEMORY. */
frig_status fr_obj_parse(const char *text, size_t size, const char *name, fr_obj *out, char *err, size_t err_size);
void fr_obj_free(fr_obj *obj);

/* Parse a decimal number ("-1.5", "2e-08", "7") at *p (before end); advances *p. 0 on
 * failure. Exposed for the MTL reader and the tests. */
int fr_parse_double(const char **p, const char *end, double *out);

#endif
