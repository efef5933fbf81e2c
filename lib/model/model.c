/* frig_model accessors, the default model path, and evaluation of the linear model
 * x = neutral + U_id w_id + U_exp w_exp as two BLAS matrix-vector products over the
 * contiguous 3N x K column-major mode matrices (paper section 3.2, eq. 3.1). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cblas.h>

#include "core/context.h"
#include "model/model.h"

frig_status frig_model_default_path(frig_ctx *ctx, char *buf, size_t size) {
    const char *env = getenv("FRIG_MODEL"), *xdg = getenv("XDG_DATA_HOME"), *home = getenv("HOME");
    int n;
    if (!buf || size == 0) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_model_default_path: no buffer");
    buf[0] = 0;
    if (env && *env) n = snprintf(buf, size, "%s", env);
    else if (xdg && *xdg) n = snprintf(buf, size, "%s/frig/ict.frigmodel", xdg);
    else if (home && *home) n = snprintf(buf, size, "%s/.local/share/frig/ict.frigmodel", home);
    else return fr_error(ctx, FRIG_ERR_NOT_FOUND, "no default model path: neither FRIG_MODEL, XDG_DATA_HOME nor HOME is set");
    if (n < 0 || (size_t)n >= size) {
        buf[0] = 0;
        return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "the default model path needs %d bytes, the buffer has %zu",
                        n + 1, size);
    }
    return FRIG_OK;
}

int frig_model_vertex_count(const frig_model *m) { return m ? m->topo.vertex_count : 0; }
int frig_model_triangle_count(const frig_model *m) { return m ? m->topo.triangle_count : 0; }
const int32_t *frig_model_triangles(const frig_model *m) { return m ? m->topo.triangles : NULL; }
int frig_model_polygon_count(const frig_model *m) { return m ? m->topo.polygon_count : 0; }
const int32_t *frig_model_polygon_offsets(const frig_model *m) { return m ? m->topo.poly_offsets : NULL; }
const int32_t *frig_model_polygon_corners(const frig_model *m) { return m ? m->topo.poly_corners : NULL; }
const int32_t *frig_model_polygon_corner_uvs(const frig_model *m) { return m ? m->topo.poly_uvs : NULL; }
int frig_model_uv_count(const frig_model *m) { return m ? m->topo.uv_count : 0; }
const float *frig_model_uvs(const frig_model *m) { return m ? m->topo.uvs : NULL; }
const int32_t *frig_model_triangle_uvs(const frig_model *m) { return m ? m->topo.triangle_uvs : NULL; }
int frig_model_material_count(const frig_model *m) { return m ? m->topo.material_count : 0; }
const int32_t *frig_model_polygon_materials(const frig_model *m) { return m ? m->topo.poly_materials : NULL; }
const int32_t *frig_model_triangle_materials(const frig_model *m) { return m ? m->topo.triangle_materials : NULL; }

const char *frig_model_material_name(const frig_model *m, int k) {
    return m && k >= 0 && k < m->topo.material_count ? m->topo.material_names[k] : NULL;
}

int frig_model_region_count(const frig_model *m) { return m ? m->topo.region_count : 0; }

frig_status frig_model_region(const frig_model *m, int r, const char **name, int *first, int *count) {
    if (!m || r < 0 || r >= m->topo.region_count) return FRIG_ERR_INVALID_ARGUMENT;
    if (name) *name = m->topo.region_names[r];
    if (first) *first = m->topo.regions[2 * r];
    if (count) *count = m->topo.regions[2 * r + 1];
    return FRIG_OK;
}

int frig_model_region_find(const frig_model *m, const char *name) {
    if (!m || !name) return -1;
    for (int r = 0; r < m->topo.region_count; r++)
        if (strcmp(m->topo.region_names[r], name) == 0) return r;
    return -1;
}

const float *frig_model_neutral(const frig_model *m) { return m ? m->neutral : NULL; }
int frig_model_identity_count(const frig_model *m) { return m ? m->identity_count : 0; }
const float *frig_model_identity_modes(const frig_model *m) { return m ? m->identity : NULL; }
int frig_model_expression_count(const frig_model *m) { return m ? m->expression_count : 0; }
const float *frig_model_expression_deltas(const frig_model *m) { return m ? m->expressions : NULL; }

const char *frig_model_expression_name(const frig_model *m, int k) {
    return m && k >= 0 && k < m->expression_count ? m->expression_names[k] : NULL;
}

int frig_model_expression_find(const frig_model *m, const char *name) {
    if (!m || !name) return -1;
    for (int k = 0; k < m->expression_count; k++)
        if (strcmp(m->expression_names[k], name) == 0) return k;
    return -1;
}

int frig_model_expression_fitting(const frig_model *m, int k) {
    return m && k >= 0 && k < m->expression_count ? m->expression_fitting[k] : 0;
}

const int32_t *frig_model_landmarks(const frig_model *m) { return m ? m->landmarks : NULL; }

int frig_model_contour(const frig_model *m, int side, const int32_t **vertices) {
    if (vertices) *vertices = NULL;
    if (!m || side < 0 || side > 1) return 0;
    if (vertices) *vertices = m->contour[side];
    return m->contour_count[side];
}

int frig_model_rigid_vertices(const frig_model *m, const int32_t **vertices) {
    if (vertices) *vertices = m ? m->rigid : NULL;
    return m ? m->rigid_count : 0;
}

frig_status fr_add_modes(frig_ctx *ctx, int n, int k, const float *modes, const double *weights, float *out,
                             const char *what) {
    if (!weights || k == 0) return FRIG_OK;
    float *w = malloc(sizeof *w * (size_t)k);
    if (!w) return fr_nomem(ctx, "model weights");
    for (int i = 0; i < k; i++) {
        if (!isfinite(weights[i])) {
            free(w);
            return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "%s weight %d is not a finite number", what, i);
        }
        w[i] = (float)weights[i];
    }
    /* Threaded OpenBLAS sgemv sums in an order that depends on its thread count; one
     * thread keeps the bytes fixed (80k x 100 takes about a millisecond). */
    int saved = fr_blas_serial_begin();
    cblas_sgemv(CblasColMajor, CblasNoTrans, n, k, 1.0f, modes, n, w, 1, 1.0f, out, 1);
    fr_blas_serial_end(saved);
    free(w);
    return FRIG_OK;
}

frig_status frig_model_eval(frig_ctx *ctx, const frig_model *m, const double *identity, const double *expression,
                            float *out) {
    if (!m || !out) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_model_eval: NULL model or output");
    int n = 3 * m->topo.vertex_count;
    memcpy(out, m->neutral, sizeof *out * (size_t)n);
    frig_status s = fr_add_modes(ctx, n, m->identity_count, m->identity, identity, out, "identity");
    if (!s) s = fr_add_modes(ctx, n, m->expression_count, m->expressions, expression, out, "expression");
    return s;
}
