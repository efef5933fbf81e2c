/* frig_rig: a neutral head plus named blendshape deltas on the model's topology. The
 * model-space rig is neutral(identity) plus the template's expression deltas (the B^m of
 * the paper's section 5.2, the starting point of the retarget stage). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "model/model.h"
#include "rig/rig.h"

frig_status frig_rig_from_model(frig_ctx *ctx, const frig_model *model, const double *identity, frig_rig **out) {
    if (!out) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_rig_from_model: out is NULL");
    *out = NULL;
    if (!model) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_rig_from_model: no model");
    float *neutral = malloc(sizeof *neutral * 3 * (size_t)model->topo.vertex_count);
    if (!neutral) return fr_nomem(ctx, "the rig's neutral");
    frig_status s = frig_model_eval(ctx, model, identity, NULL, neutral);
    if (!s)
        s = fr_rig_build(ctx, &model->topo, model->expression_count, neutral, model->expressions,
                         model->expression_blob, model->expression_blob_size, out);
    free(neutral);
    return s;
}

frig_status frig_rig_clone(frig_ctx *ctx, const frig_rig *rig, frig_rig **out) {
    if (!out) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_rig_clone: out is NULL");
    *out = NULL;
    if (!rig) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_rig_clone: no rig");
    frig_status s = fr_rig_build(ctx, &rig->topo, rig->shape_count, rig->neutral, rig->deltas, rig->name_blob,
                                 rig->name_blob_size, out);
    if (!s && rig->face_png) {
        (*out)->face_png = malloc(rig->face_png_size);
        if (!(*out)->face_png) {
            frig_rig_free(*out);
            *out = NULL;
            return fr_nomem(ctx, "the rig's face texture");
        }
        memcpy((*out)->face_png, rig->face_png, rig->face_png_size);
        (*out)->face_png_size = rig->face_png_size;
    }
    return s;
}

int frig_rig_vertex_count(const frig_rig *r) { return r ? r->topo.vertex_count : 0; }
int frig_rig_shape_count(const frig_rig *r) { return r ? r->shape_count : 0; }
const char *frig_rig_shape_name(const frig_rig *r, int k) {
    return r && k >= 0 && k < r->shape_count ? r->shape_names[k] : NULL;
}

int frig_rig_shape_find(const frig_rig *r, const char *name) {
    if (!r || !name) return -1;
    for (int k = 0; k < r->shape_count; k++)
        if (strcmp(r->shape_names[k], name) == 0) return k;
    return -1;
}

const float *frig_rig_neutral(const frig_rig *r) { return r ? r->neutral : NULL; }
const float *frig_rig_shape_deltas(const frig_rig *r, int k) {
    return r && k >= 0 && k < r->shape_count ? r->deltas + 3 * (size_t)r->topo.vertex_count * (size_t)k : NULL;
}

static frig_status copy_finite(frig_ctx *ctx, float *dst, const float *src, size_t n, const char *what) {
    if (!src) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "%s: no values given", what);
    for (size_t i = 0; i < n; i++)
        if (!isfinite(src[i]))
            return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "%s: value %zu is not a finite number", what, i);
    memcpy(dst, src, n * sizeof *dst);
    return FRIG_OK;
}

frig_status frig_rig_set_neutral(frig_ctx *ctx, frig_rig *r, const float *positions) {
    if (!r) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_rig_set_neutral: no rig");
    return copy_finite(ctx, r->neutral, positions, 3 * (size_t)r->topo.vertex_count, "the rig's new neutral");
}

frig_status frig_rig_set_shape_deltas(frig_ctx *ctx, frig_rig *r, int k, const float *deltas) {
    if (!r || k < 0 || k >= r->shape_count)
        return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_rig_set_shape_deltas: no rig or shape %d out of range", k);
    size_t n3 = 3 * (size_t)r->topo.vertex_count;
    return copy_finite(ctx, r->deltas + n3 * (size_t)k, deltas, n3, r->shape_names[k]);
}

frig_status frig_rig_eval(frig_ctx *ctx, const frig_rig *r, const double *weights, float *out) {
    if (!r || !out) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_rig_eval: NULL rig or output");
    int n = 3 * r->topo.vertex_count;
    memcpy(out, r->neutral, sizeof *out * (size_t)n);
    return fr_add_modes(ctx, n, r->shape_count, r->deltas, weights, out, "blendshape");
}
