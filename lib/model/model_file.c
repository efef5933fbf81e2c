/* The binary model file (docs/model-format.md): the container of lib/io/container.c with
 * the topology sections and the model's shape spaces and correspondences. Loading checks
 * every count and index, so a damaged or hostile file gives a status, never a crash. */
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "io/file.h"
#include "model/model.h"

#define MODEL_SECTIONS (FR_TOPOLOGY_SECTIONS + 10)
#define MAX_MODEL_FILE ((size_t)1 << 34)

static int model_sections(const fr_model_parts *p, int32_t topo_meta[FR_TOPOLOGY_META],
                          int32_t meta[FR_MODEL_META], fr_section *s) {
    fr_topology_sections(&p->topo, topo_meta, s);
    int i = FR_TOPOLOGY_SECTIONS;
    uint64_t n3 = 3 * (uint64_t)p->topo.vertex_count;
    meta[0] = p->identity_count, meta[1] = p->expression_count, meta[2] = p->landmark_count;
    meta[3] = p->contour_count[0], meta[4] = p->contour_count[1], meta[5] = p->rigid_count;
    s[i++] = (fr_section){"model_meta", FR_SEC_I32, FR_MODEL_META, meta};
    s[i++] = (fr_section){"neutral", FR_SEC_F32, n3, p->neutral};
    s[i++] = (fr_section){"identity", FR_SEC_F32, n3 * (uint64_t)p->identity_count, p->identity};
    s[i++] = (fr_section){"expressions", FR_SEC_F32, n3 * (uint64_t)p->expression_count, p->expressions};
    s[i++] = (fr_section){"expr_names", FR_SEC_BYTES, p->expression_blob_size, p->expression_blob};
    s[i++] = (fr_section){"expr_fitting", FR_SEC_I32, (uint64_t)p->expression_count, p->expression_fitting};
    s[i++] = (fr_section){"landmarks", FR_SEC_I32, (uint64_t)p->landmark_count, p->landmarks};
    s[i++] = (fr_section){"contour_right", FR_SEC_I32, (uint64_t)p->contour_count[0], p->contour[0]};
    s[i++] = (fr_section){"contour_left", FR_SEC_I32, (uint64_t)p->contour_count[1], p->contour[1]};
    s[i++] = (fr_section){"rigid", FR_SEC_I32, (uint64_t)p->rigid_count, p->rigid};
    return i;
}

void fr_model_parts_of(const frig_model *m, fr_model_parts *p) {
    memset(p, 0, sizeof *p);
    p->topo = m->topo;
    p->identity_count = m->identity_count, p->expression_count = m->expression_count;
    p->landmark_count = m->landmark_count, p->rigid_count = m->rigid_count;
    p->contour_count[0] = m->contour_count[0], p->contour_count[1] = m->contour_count[1];
    p->neutral = m->neutral, p->identity = m->identity, p->expressions = m->expressions;
    p->expression_blob = m->expression_blob, p->expression_blob_size = m->expression_blob_size;
    p->expression_fitting = m->expression_fitting, p->landmarks = m->landmarks;
    p->contour[0] = m->contour[0], p->contour[1] = m->contour[1], p->rigid = m->rigid;
}

static frig_status pack_parts(frig_ctx *ctx, const fr_model_parts *p, unsigned char **image, size_t *size) {
    int32_t topo_meta[FR_TOPOLOGY_META], meta[FR_MODEL_META];
    fr_section s[MODEL_SECTIONS];
    int n = model_sections(p, topo_meta, meta, s);
    return fr_container_pack(ctx, FR_MODEL_MAGIC, FR_MODEL_VERSION, s, n, image, size);
}

frig_status fr_model_pack(frig_ctx *ctx, const frig_model *m, int identity_count, int expression_count,
                          unsigned char **image, size_t *size) {
    fr_model_parts p;
    fr_model_parts_of(m, &p);
    if (identity_count < 0 || identity_count > m->identity_count || expression_count < 0 ||
        expression_count > m->expression_count)
        return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "cannot keep %d identity modes and %d expressions of %d and %d",
                        identity_count, expression_count, m->identity_count, m->expression_count);
    p.identity_count = identity_count;
    p.expression_count = expression_count;
    /* The names of the first expression_count expressions are a prefix of the blob. */
    size_t blob = 0;
    for (int k = 0; k < expression_count; k++) blob += strlen(m->expression_names[k]) + 1;
    p.expression_blob_size = blob;
    return pack_parts(ctx, &p, image, size);
}

frig_status fr_model_build(frig_ctx *ctx, const fr_model_parts *parts, frig_model **out) {
    unsigned char *image;
    size_t size;
    *out = NULL;
    frig_status s = pack_parts(ctx, parts, &image, &size);
    if (s) return s;
    return fr_model_from_image(ctx, "the imported model", image, size, out);
}

static frig_status check_list(frig_ctx *ctx, const fr_container *c, const char *tag, const int32_t *v, int n,
                              int limit) {
    for (int i = 0; i < n; i++)
        if (v[i] < 0 || v[i] >= limit)
            return fr_error(ctx, FRIG_ERR_CORRUPT, "%s: '%s' entry %d is vertex %d, outside the %d vertices", c->what,
                            tag, i, v[i], limit);
    return FRIG_OK;
}

static frig_status take_meta(frig_ctx *ctx, const fr_container *c, frig_model *m) {
    void *p;
    frig_status s = fr_container_take(ctx, c, "model_meta", FR_SEC_I32, FR_MODEL_META, &p);
    if (s) return s;
    const int32_t *meta = p;
    for (int i = 0; i < FR_MODEL_META; i++)
        if (meta[i] < 0 || meta[i] > (1 << 24))
            return fr_error(ctx, FRIG_ERR_CORRUPT, "%s: model count %d is %d", c->what, i, meta[i]);
    if (meta[2] != FR_LANDMARK_COUNT)
        return fr_error(ctx, FRIG_ERR_CORRUPT, "%s: %d landmarks where 68 are needed", c->what, meta[2]);
    m->identity_count = meta[0], m->expression_count = meta[1], m->landmark_count = meta[2];
    m->contour_count[0] = meta[3], m->contour_count[1] = meta[4], m->rigid_count = meta[5];
    return FRIG_OK;
}

static frig_status take_arrays(frig_ctx *ctx, const fr_container *c, frig_model *m) {
    uint64_t n3 = 3 * (uint64_t)m->topo.vertex_count;
    const fr_section_want want[] = {
        {"neutral", FR_SEC_F32, n3, (const void **)&m->neutral},
        {"identity", FR_SEC_F32, n3 * (uint64_t)m->identity_count, (const void **)&m->identity},
        {"expressions", FR_SEC_F32, n3 * (uint64_t)m->expression_count, (const void **)&m->expressions},
        {"expr_fitting", FR_SEC_I32, (uint64_t)m->expression_count, (const void **)&m->expression_fitting},
        {"landmarks", FR_SEC_I32, (uint64_t)m->landmark_count, (const void **)&m->landmarks},
        {"contour_right", FR_SEC_I32, (uint64_t)m->contour_count[0], (const void **)&m->contour[0]},
        {"contour_left", FR_SEC_I32, (uint64_t)m->contour_count[1], (const void **)&m->contour[1]},
        {"rigid", FR_SEC_I32, (uint64_t)m->rigid_count, (const void **)&m->rigid},
    };
    return fr_container_take_all(ctx, c, want, (int)(sizeof want / sizeof want[0]));
}

static frig_status check_model(frig_ctx *ctx, const fr_container *c, const frig_model *m) {
    int nv = m->topo.vertex_count;
    frig_status s;
    if ((s = check_list(ctx, c, "landmarks", m->landmarks, m->landmark_count, nv)) ||
        (s = check_list(ctx, c, "contour_right", m->contour[0], m->contour_count[0], nv)) ||
        (s = check_list(ctx, c, "contour_left", m->contour[1], m->contour_count[1], nv)) ||
        (s = check_list(ctx, c, "rigid", m->rigid, m->rigid_count, nv)))
        return s;
    for (int k = 0; k < m->expression_count; k++) {
        if (m->expression_fitting[k] != 0 && m->expression_fitting[k] != 1)
            return fr_error(ctx, FRIG_ERR_CORRUPT, "%s: fitting flag of '%s' is %d", c->what, m->expression_names[k],
                            m->expression_fitting[k]);
        for (int j = 0; j < k; j++)
            if (strcmp(m->expression_names[j], m->expression_names[k]) == 0)
                return fr_error(ctx, FRIG_ERR_CORRUPT, "%s: expression '%s' appears twice", c->what,
                                m->expression_names[k]);
    }
    uint64_t n3 = 3 * (uint64_t)nv;
    if (!fr_all_finite(m->neutral, n3) || !fr_all_finite(m->identity, n3 * (uint64_t)m->identity_count) ||
        !fr_all_finite(m->expressions, n3 * (uint64_t)m->expression_count))
        return fr_error(ctx, FRIG_ERR_CORRUPT, "%s: the shapes hold numbers that are not finite", c->what);
    return FRIG_OK;
}

frig_status fr_model_from_image(frig_ctx *ctx, const char *what, unsigned char *image, size_t size, frig_model **out) {
    *out = NULL;
    frig_model *m = calloc(1, sizeof *m);
    fr_container *c = malloc(sizeof *c);
    if (!m || !c) {
        free(m), free(c), free(image);
        return fr_nomem(ctx, "a model");
    }
    m->image = image;
    m->image_size = size;
    frig_status s;
    if (!(s = fr_container_parse(ctx, what, FR_MODEL_MAGIC, FR_MODEL_VERSION, image, size, c)) &&
        !(s = fr_topology_bind(ctx, c, &m->topo)) && !(s = take_meta(ctx, c, m)) && !(s = take_arrays(ctx, c, m)) &&
        !(s = fr_names_parse(ctx, c, "expr_names", m->expression_count, &m->expression_names, &m->expression_blob,
                             &m->expression_blob_size)))
        s = check_model(ctx, c, m);
    free(c);
    if (s) {
        frig_model_free(m);
        return s;
    }
    *out = m;
    return FRIG_OK;
}

frig_status frig_model_load(frig_ctx *ctx, const char *path, frig_model **out) {
    if (!out) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_model_load: out is NULL");
    *out = NULL;
    if (!path) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_model_load: path is NULL");
    unsigned char *data;
    size_t size;
    frig_status s = fr_read_file(ctx, path, MAX_MODEL_FILE, &data, &size);
    if (s) return s;
    return fr_model_from_image(ctx, path, data, size, out);
}

frig_status frig_model_save(frig_ctx *ctx, const frig_model *model, const char *path) {
    if (!model || !path) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_model_save: NULL model or path");
    unsigned char *image;
    size_t size;
    frig_status s = fr_model_pack(ctx, model, model->identity_count, model->expression_count, &image, &size);
    if (s) return s;
    s = fr_write_file_atomic(ctx, path, image, size);
    free(image);
    return s;
}

void frig_model_free(frig_model *m) {
    if (!m) return;
    fr_topology_release(&m->topo);
    free((void *)m->expression_names);
    free(m->image);
    free(m);
}
