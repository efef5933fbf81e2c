/* The native rig file: the model file's container (docs/model-format.md) with the
 * topology sections plus the rig's neutral, shape deltas and shape names. */
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "io/file.h"
#include "rig/rig.h"

#define RIG_SECTIONS (FR_TOPOLOGY_SECTIONS + 4)
#define MAX_RIG_FILE ((size_t)1 << 34)

static frig_status pack(frig_ctx *ctx, const fr_topology *topo, int shape_count, const float *neutral,
                        const float *deltas, const char *name_blob, size_t name_blob_size, unsigned char **image,
                        size_t *size) {
    int32_t topo_meta[FR_TOPOLOGY_META], meta[1] = {shape_count};
    fr_section s[RIG_SECTIONS];
    fr_topology_sections(topo, topo_meta, s);
    uint64_t n3 = 3 * (uint64_t)topo->vertex_count;
    int i = FR_TOPOLOGY_SECTIONS;
    s[i++] = (fr_section){"rig_meta", FR_SEC_I32, 1, meta};
    s[i++] = (fr_section){"neutral", FR_SEC_F32, n3, neutral};
    s[i++] = (fr_section){"shape_deltas", FR_SEC_F32, n3 * (uint64_t)shape_count, deltas};
    s[i++] = (fr_section){"shape_names", FR_SEC_BYTES, name_blob_size, name_blob};
    return fr_container_pack(ctx, FR_RIG_MAGIC, FR_RIG_VERSION, s, i, image, size);
}

frig_status fr_rig_pack(frig_ctx *ctx, const frig_rig *r, unsigned char **image, size_t *size) {
    return pack(ctx, &r->topo, r->shape_count, r->neutral, r->deltas, r->name_blob, r->name_blob_size, image, size);
}

frig_status fr_rig_build(frig_ctx *ctx, const fr_topology *topo, int shape_count, const float *neutral,
                         const float *deltas, const char *name_blob, size_t name_blob_size, frig_rig **out) {
    unsigned char *image;
    size_t size;
    *out = NULL;
    frig_status s = pack(ctx, topo, shape_count, neutral, deltas, name_blob, name_blob_size, &image, &size);
    if (s) return s;
    return fr_rig_from_image(ctx, "the new rig", image, size, out);
}

static frig_status bind(frig_ctx *ctx, const fr_container *c, frig_rig *r) {
    void *p;
    frig_status s;
    if ((s = fr_topology_bind(ctx, c, &r->topo)) || (s = fr_container_take(ctx, c, "rig_meta", FR_SEC_I32, 1, &p)))
        return s;
    int n = *(const int32_t *)p;
    if (n < 0 || n > (1 << 20)) return fr_error(ctx, FRIG_ERR_CORRUPT, "%s: %d shapes", c->what, n);
    r->shape_count = n;
    uint64_t n3 = 3 * (uint64_t)r->topo.vertex_count;
    if ((s = fr_container_take(ctx, c, "neutral", FR_SEC_F32, n3, &p))) return s;
    r->neutral = p;
    if ((s = fr_container_take(ctx, c, "shape_deltas", FR_SEC_F32, n3 * (uint64_t)n, &p))) return s;
    r->deltas = p;
    if ((s = fr_names_parse(ctx, c, "shape_names", n, &r->shape_names, &r->name_blob, &r->name_blob_size))) return s;
    for (int k = 0; k < n; k++)
        for (int j = 0; j < k; j++)
            if (strcmp(r->shape_names[j], r->shape_names[k]) == 0)
                return fr_error(ctx, FRIG_ERR_CORRUPT, "%s: shape '%s' appears twice", c->what, r->shape_names[k]);
    if (!fr_all_finite(r->neutral, n3) || !fr_all_finite(r->deltas, n3 * (uint64_t)n))
        return fr_error(ctx, FRIG_ERR_CORRUPT, "%s: the shapes hold numbers that are not finite", c->what);
    return FRIG_OK;
}

frig_status fr_rig_from_image(frig_ctx *ctx, const char *what, unsigned char *image, size_t size, frig_rig **out) {
    *out = NULL;
    frig_rig *r = calloc(1, sizeof *r);
    fr_container *c = malloc(sizeof *c);
    if (!r || !c) {
        free(r), free(c), free(image);
        return fr_nomem(ctx, "a rig");
    }
    r->image = image;
    r->image_size = size;
    frig_status s = fr_container_parse(ctx, what, FR_RIG_MAGIC, FR_RIG_VERSION, image, size, c);
    if (!s) s = bind(ctx, c, r);
    free(c);
    if (s) {
        frig_rig_free(r);
        return s;
    }
    *out = r;
    return FRIG_OK;
}

frig_status frig_rig_load(frig_ctx *ctx, const char *path, frig_rig **out) {
    if (!out) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_rig_load: out is NULL");
    *out = NULL;
    if (!path) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_rig_load: path is NULL");
    unsigned char *data;
    size_t size;
    frig_status s = fr_read_file(ctx, path, MAX_RIG_FILE, &data, &size);
    if (s) return s;
    return fr_rig_from_image(ctx, path, data, size, out);
}

frig_status frig_rig_save(frig_ctx *ctx, const frig_rig *rig, const char *path) {
    if (!rig || !path) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_rig_save: NULL rig or path");
    unsigned char *image;
    size_t size;
    frig_status s = fr_rig_pack(ctx, rig, &image, &size);
    if (s) return s;
    s = fr_write_file_atomic(ctx, path, image, size);
    free(image);
    return s;
}

void frig_rig_free(frig_rig *r) {
    if (!r) return;
    fr_topology_release(&r->topo);
    free((void *)r->shape_names);
    free(r->face_png);
    free(r->image);
    free(r);
}
