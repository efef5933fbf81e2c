/* TensorFlow.js weights (model.json's weightsManifest, saved as NAME-weights_manifest.json
 * beside binary shards), as @vladmandic/face-api ships its networks. The manifest is an array
 * of groups {"paths": [shard files], "weights": [{"name", "shape", "dtype",
 * "quantization": {"dtype", "scale", "min"}}]}; a group's weights lie one after the other in
 * the concatenation of its shards. Decoded to float32 here, every value checked. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cJSON.h>

#include "core/context.h"
#include "io/file.h"
#include "nn/weights.h"

#define MANIFEST_MAX (16u << 20)
#define SHARD_MAX (512u << 20)
#define DIM_MAX (1 << 28)
#define NAME_MAX_LEN 256

typedef enum value_kind { KIND_FLOAT32, KIND_INT32 } value_kind;

typedef struct spec {
    const char *name; /* points into the cJSON tree */
    int rank, shape[FR_NN_MAX_RANK];
    size_t count, bytes;
    value_kind kind;
    int qbytes; /* 0: stored as 4-byte values; 1: uint8; 2: uint16 quantized */
    double scale, min;
} spec;

typedef struct manifest {
    cJSON *root;
    spec *specs;
    size_t n_specs;
    size_t n_groups;
    size_t *group_bytes; /* per group: the bytes its shards must hold */
} manifest;

static void manifest_free(manifest *m) {
    cJSON_Delete(m->root);
    free(m->specs);
    free(m->group_bytes);
    memset(m, 0, sizeof *m);
}

static frig_status corrupt(frig_ctx *ctx, const char *label, const char *what, size_t index, const char *name) {
    if (name)
        return fr_error(ctx, FRIG_ERR_CORRUPT, "%s: weight %zu (%s) of the manifest %s", label, index, name, what);
    return fr_error(ctx, FRIG_ERR_CORRUPT, "%s: the weights manifest %s", label, what);
}

static frig_status parse_quantization(frig_ctx *ctx, const char *label, size_t i, const cJSON *q, spec *s) {
    const cJSON *qd = cJSON_GetObjectItemCaseSensitive(q, "dtype");
    const cJSON *scale = cJSON_GetObjectItemCaseSensitive(q, "scale");
    const cJSON *min = cJSON_GetObjectItemCaseSensitive(q, "min");
    if (!cJSON_IsString(qd)) return corrupt(ctx, label, "has a quantization without a dtype", i, s->name);
    if (strcmp(qd->valuestring, "uint8") == 0) s->qbytes = 1;
    else if (strcmp(qd->valuestring, "uint16") == 0) s->qbytes = 2;
    else
        return fr_error(ctx, FRIG_ERR_UNSUPPORTED, "%s: weight %s is quantized as %.40s (only uint8 and uint16 are read)",
                        label, s->name, qd->valuestring);
    if (!cJSON_IsNumber(scale) || !cJSON_IsNumber(min) || !isfinite(scale->valuedouble) ||
        !isfinite(min->valuedouble))
        return corrupt(ctx, label, "has a quantization without a finite scale and min", i, s->name);
    s->scale = scale->valuedouble;
    s->min = min->valuedouble;
    return FRIG_OK;
}

static frig_status parse_spec(frig_ctx *ctx, const char *label, size_t i, const cJSON *jw, spec *s) {
    const cJSON *name = cJSON_GetObjectItemCaseSensitive(jw, "name");
    const cJSON *shape = cJSON_GetObjectItemCaseSensitive(jw, "shape");
    const cJSON *dtype = cJSON_GetObjectItemCaseSensitive(jw, "dtype");
    const cJSON *q = cJSON_GetObjectItemCaseSensitive(jw, "quantization");
    if (!cJSON_IsObject(jw)) return corrupt(ctx, label, "is not an object", i, NULL);
    if (!cJSON_IsString(name) || !name->valuestring[0] || strlen(name->valuestring) >= NAME_MAX_LEN)
        return corrupt(ctx, label, "has no name (or one over 255 bytes)", i, "?");
    s->name = name->valuestring;
    if (!cJSON_IsArray(shape)) return corrupt(ctx, label, "has no shape array", i, s->name);
    int rank = cJSON_GetArraySize(shape);
    if (rank > FR_NN_MAX_RANK)
        return fr_error(ctx, FRIG_ERR_UNSUPPORTED, "%s: weight %s has %d dimensions (at most %d are read)", label,
                        s->name, rank, FR_NN_MAX_RANK);
    s->rank = rank;
    s->count = 1;
    int k = 0;
    for (const cJSON *d = shape->child; d; d = d->next, k++) {
        if (!cJSON_IsNumber(d) || d->valuedouble < 0 || d->valuedouble > DIM_MAX ||
            d->valuedouble != floor(d->valuedouble))
            return corrupt(ctx, label, "has a dimension that is not a whole number in [0, 2^28]", i, s->name);
        s->shape[k] = (int)d->valuedouble;
        if (s->shape[k] && s->count > (SIZE_MAX / 8) / (size_t)s->shape[k])
            return corrupt(ctx, label, "has a shape too large to hold", i, s->name);
        s->count *= (size_t)s->shape[k];
    }
    if (!cJSON_IsString(dtype)) return corrupt(ctx, label, "has no dtype", i, s->name);
    if (strcmp(dtype->valuestring, "float32") == 0) s->kind = KIND_FLOAT32;
    else if (strcmp(dtype->valuestring, "int32") == 0) s->kind = KIND_INT32;
    else
        return fr_error(ctx, FRIG_ERR_UNSUPPORTED, "%s: weight %s has dtype %.40s (only float32 and int32 are read)",
                        label, s->name, dtype->valuestring);
    if (q) {
        if (!cJSON_IsObject(q)) return corrupt(ctx, label, "has a quantization that is not an object", i, s->name);
        frig_status st = parse_quantization(ctx, label, i, q, s);
        if (st) return st;
    }
    s->bytes = s->count * (size_t)(s->qbytes ? s->qbytes : 4);
    return FRIG_OK;
}

static int same_name_before(const spec *specs, size_t n, const char *name) {
    for (size_t i = 0; i < n; i++)
        if (strcmp(specs[i].name, name) == 0) return 1;
    return 0;
}

/* The manifest's structure and every weight's spec; group byte counts. */
static frig_status parse_manifest(frig_ctx *ctx, const char *label, const char *text, size_t size, manifest *m) {
    memset(m, 0, sizeof *m);
    m->root = cJSON_ParseWithLength(text, size);
    if (!m->root) return fr_error(ctx, FRIG_ERR_CORRUPT, "%s: the weights manifest is not valid JSON", label);
    if (!cJSON_IsArray(m->root) || cJSON_GetArraySize(m->root) < 1) {
        manifest_free(m);
        return corrupt(ctx, label, "is not a non-empty array of weight groups", 0, NULL);
    }
    size_t total = 0;
    for (const cJSON *g = m->root->child; g; g = g->next) {
        const cJSON *w = cJSON_GetObjectItemCaseSensitive(g, "weights");
        const cJSON *p = cJSON_GetObjectItemCaseSensitive(g, "paths");
        if (!cJSON_IsObject(g) || !cJSON_IsArray(w) || !cJSON_IsArray(p)) {
            manifest_free(m);
            return corrupt(ctx, label, "has a group without \"paths\" and \"weights\" arrays", 0, NULL);
        }
        total += (size_t)cJSON_GetArraySize(w);
        m->n_groups++;
    }
    m->specs = calloc(total ? total : 1, sizeof *m->specs);
    m->group_bytes = calloc(m->n_groups, sizeof *m->group_bytes);
    if (!m->specs || !m->group_bytes) {
        manifest_free(m);
        return fr_nomem(ctx, "the weights manifest");
    }
    size_t gi = 0;
    for (const cJSON *g = m->root->child; g; g = g->next, gi++) {
        for (const cJSON *jw = cJSON_GetObjectItemCaseSensitive(g, "weights")->child; jw; jw = jw->next) {
            spec *s = &m->specs[m->n_specs];
            frig_status st = parse_spec(ctx, label, m->n_specs, jw, s);
            if (!st && same_name_before(m->specs, m->n_specs, s->name))
                st = corrupt(ctx, label, "repeats an earlier weight's name", m->n_specs, s->name);
            if (!st && m->group_bytes[gi] > SIZE_MAX / 2 - s->bytes)
                st = corrupt(ctx, label, "makes the group too large", m->n_specs, s->name);
            if (st) {
                manifest_free(m);
                return st;
            }
            m->group_bytes[gi] += s->bytes;
            m->n_specs++;
        }
    }
    return FRIG_OK;
}

static float read_f32(const unsigned char *b) {
    uint32_t u = (uint32_t)b[0] | (uint32_t)b[1] << 8 | (uint32_t)b[2] << 16 | (uint32_t)b[3] << 24;
    float f;
    memcpy(&f, &u, sizeof f);
    return f;
}

static int32_t read_i32(const unsigned char *b) {
    uint32_t u = (uint32_t)b[0] | (uint32_t)b[1] << 8 | (uint32_t)b[2] << 16 | (uint32_t)b[3] << 24;
    return (int32_t)u;
}

/* One tensor's values from its bytes; FRIG_ERR_CORRUPT on a non-finite value. */
static frig_status decode(frig_ctx *ctx, const char *label, const spec *s, const unsigned char *b, float *out) {
    for (size_t i = 0; i < s->count; i++) {
        double v;
        if (s->qbytes == 1) v = b[i] * s->scale + s->min;
        else if (s->qbytes == 2) v = (b[2 * i] | b[2 * i + 1] << 8) * s->scale + s->min;
        else if (s->kind == KIND_FLOAT32) v = read_f32(b + 4 * i);
        else v = read_i32(b + 4 * i);
        if (s->qbytes && s->kind == KIND_INT32) v = round(v);
        out[i] = (float)v;
        if (!isfinite(out[i]))
            return fr_error(ctx, FRIG_ERR_CORRUPT, "%s: weight %s holds a value that is not a finite number", label,
                            s->name);
    }
    return FRIG_OK;
}

void fr_nn_weights_free(fr_nn_weights *w) {
    if (!w) return;
    for (size_t i = 0; i < w->count; i++) {
        free(w->tensors[i].name);
        free(w->tensors[i].data);
    }
    free(w->tensors);
    free(w->label);
    free(w);
}

static frig_status build(frig_ctx *ctx, const char *label, const manifest *m, const unsigned char *bin, size_t size,
                         fr_nn_weights **out) {
    size_t need = 0;
    for (size_t g = 0; g < m->n_groups; g++) need += m->group_bytes[g];
    if (size < need)
        return fr_error(ctx, FRIG_ERR_TRUNCATED, "%s: the weight shards hold %zu bytes, the manifest lists %zu", label,
                        size, need);
    if (size > need)
        return fr_error(ctx, FRIG_ERR_CORRUPT, "%s: the weight shards hold %zu bytes, %zu more than the manifest lists",
                        label, size, size - need);
    fr_nn_weights *w = calloc(1, sizeof *w);
    if (w) w->tensors = calloc(m->n_specs ? m->n_specs : 1, sizeof *w->tensors);
    if (w) w->label = strdup(label);
    if (!w || !w->tensors || !w->label) {
        fr_nn_weights_free(w);
        return fr_nomem(ctx, "network weights");
    }
    size_t off = 0;
    for (size_t i = 0; i < m->n_specs; i++) {
        const spec *s = &m->specs[i];
        fr_nn_tensor *t = &w->tensors[w->count++];
        t->name = strdup(s->name);
        t->data = malloc((s->count ? s->count : 1) * sizeof *t->data);
        if (!t->name || !t->data) {
            fr_nn_weights_free(w);
            return fr_nomem(ctx, "network weights");
        }
        t->rank = s->rank;
        memcpy(t->shape, s->shape, sizeof t->shape);
        t->count = s->count;
        frig_status st = decode(ctx, label, s, bin + off, t->data);
        if (st) {
            fr_nn_weights_free(w);
            return st;
        }
        off += s->bytes;
    }
    *out = w;
    return FRIG_OK;
}

frig_status fr_nn_weights_parse(frig_ctx *ctx, const char *label, const char *text, size_t text_size,
                                const unsigned char *bin, size_t bin_size, fr_nn_weights **out) {
    if (!label || !text || !out || (!bin && bin_size))
        return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "fr_nn_weights_parse: NULL argument");
    *out = NULL;
    manifest m;
    frig_status st = parse_manifest(ctx, label, text, text_size, &m);
    if (st) return st;
    st = build(ctx, label, &m, bin, bin_size, out);
    manifest_free(&m);
    return st;
}

/* A shard's path must be a plain file name beside the manifest. */
static int plain_name(const char *s) {
    return s[0] && strcmp(s, ".") != 0 && strcmp(s, "..") != 0 && !strchr(s, '/') && strlen(s) < NAME_MAX_LEN;
}

/* Every group's shards, concatenated in manifest order, each group's size checked. */
static frig_status read_shards(frig_ctx *ctx, const char *label, const char *dir, const manifest *m,
                               unsigned char **bin, size_t *size) {
    unsigned char *all = NULL;
    size_t n = 0, gi = 0;
    frig_status st = FRIG_OK;
    for (const cJSON *g = m->root->child; g && !st; g = g->next, gi++) {
        size_t group = 0;
        for (const cJSON *p = cJSON_GetObjectItemCaseSensitive(g, "paths")->child; p && !st; p = p->next) {
            if (!cJSON_IsString(p) || !plain_name(p->valuestring)) {
                st = corrupt(ctx, label, "names a shard that is not a plain file name", 0, NULL);
                break;
            }
            char *path = fr_path_join(dir, p->valuestring);
            unsigned char *data = NULL;
            size_t len = 0;
            st = path ? fr_read_file(ctx, path, SHARD_MAX, &data, &len) : fr_nomem(ctx, "a shard path");
            if (!st && len > SIZE_MAX / 2 - n) st = fr_error(ctx, FRIG_ERR_TOO_LARGE, "%s: the shards are too large", label);
            unsigned char *grown = st ? NULL : realloc(all, n + len + 1);
            if (!st && !grown) st = fr_nomem(ctx, "weight shards");
            if (!st) {
                all = grown;
                if (len) memcpy(all + n, data, len);
                n += len;
                group += len;
            }
            free(data);
            free(path);
        }
        if (!st && group != m->group_bytes[gi])
            st = fr_error(ctx, group < m->group_bytes[gi] ? FRIG_ERR_TRUNCATED : FRIG_ERR_CORRUPT,
                          "%s: weight group %zu's shards in %s hold %zu bytes, the manifest lists %zu", label, gi + 1,
                          dir, group, m->group_bytes[gi]);
    }
    if (st) {
        free(all);
        return st;
    }
    *bin = all;
    *size = n;
    return FRIG_OK;
}

frig_status fr_nn_weights_load(frig_ctx *ctx, const char *dir, const char *model, fr_nn_weights **out) {
    if (!dir || !model || !out) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "fr_nn_weights_load: NULL argument");
    *out = NULL;
    size_t len = strlen(model) + sizeof "-weights_manifest.json";
    char *file = malloc(len);
    if (!file) return fr_nomem(ctx, "a manifest path");
    snprintf(file, len, "%s-weights_manifest.json", model);
    char *path = fr_path_join(dir, file);
    free(file);
    unsigned char *text = NULL;
    size_t text_size = 0;
    frig_status st = path ? fr_read_file(ctx, path, MANIFEST_MAX, &text, &text_size) : fr_nomem(ctx, "a manifest path");
    free(path);
    if (st) return st;
    manifest m;
    st = parse_manifest(ctx, model, (const char *)text, text_size, &m);
    free(text);
    if (st) return st;
    unsigned char *bin = NULL;
    size_t bin_size = 0;
    st = read_shards(ctx, model, dir, &m, &bin, &bin_size);
    if (!st) st = build(ctx, model, &m, bin, bin_size, out);
    free(bin);
    manifest_free(&m);
    return st;
}

static void shape_text(char *buf, size_t size, int rank, const int *shape) {
    size_t n = (size_t)snprintf(buf, size, "[");
    for (int k = 0; k < rank && n < size; k++) n += (size_t)snprintf(buf + n, size - n, k ? ", %d" : "%d", shape[k]);
    if (n < size) snprintf(buf + n, size - n, "]");
}

const float *fr_nn_weights_get(frig_ctx *ctx, const fr_nn_weights *w, const char *name, int rank, const int *shape) {
    for (size_t i = 0; i < w->count; i++) {
        const fr_nn_tensor *t = &w->tensors[i];
        if (strcmp(t->name, name) != 0) continue;
        int same = t->rank == rank;
        for (int k = 0; same && k < rank; k++) same = t->shape[k] == shape[k];
        if (same) return t->data;
        char have[96], want[96];
        shape_text(have, sizeof have, t->rank, t->shape);
        shape_text(want, sizeof want, rank, shape);
        fr_error(ctx, FRIG_ERR_CORRUPT, "%s: tensor %s has shape %s, the network needs %s", w->label, name, have, want);
        return NULL;
    }
    fr_error(ctx, FRIG_ERR_CORRUPT, "%s: the weights have no tensor %s", w->label, name);
    return NULL;
}
