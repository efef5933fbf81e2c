/* The head's size (docs/fit.md, "The head's size"): a head s times larger and s
 * times farther away makes the same picture, so the photos show the face's
 * proportions, not its scale, but the model ties the two (its modes scale a face
 * only together with a change of shape). With fit.mean_size 1 (the default) the
 * size is held at the model's mean, as a linear constraint on the identity step;
 * with 0 the identity's own size is kept (on seventeen frig synth subjects the free
 * sizes follow the truth's, correlation 0.8, but on two real videos they come out
 * 15-20% small). */
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "linalg/linalg.h"
#include "model/face_size.h"

frig_status fr_face_size_gradient(frig_ctx *ctx, const frig_model *model, int n_id, double *g) {
    int first = 0, count = frig_model_vertex_count(model);
    int face = frig_model_region_find(model, "face");
    if (face >= 0 && frig_model_region(model, face, NULL, &first, &count))
        return fr_error(ctx, FRIG_ERR_CORRUPT, "the model's face region cannot be read");
    const float *mean = frig_model_neutral(model) + 3 * (size_t)first;
    const float *modes = frig_model_identity_modes(model);
    size_t n3 = 3 * (size_t)frig_model_vertex_count(model);
    double c[3] = {0, 0, 0}, norm = 0;
    for (int v = 0; v < count; v++)
        for (int k = 0; k < 3; k++)
            c[k] += mean[3 * (size_t)v + k] / count;
    for (int v = 0; v < count; v++)
        for (int k = 0; k < 3; k++)
            norm += (mean[3 * (size_t)v + k] - c[k]) * (mean[3 * (size_t)v + k] - c[k]);
    if (!(norm > 0))
        return fr_error(ctx, FRIG_ERR_CORRUPT, "the model's face region has no extent");
    /* d(RMS)/RMS = sum (m - c) . dm / sum |m - c|^2; the centroid's own change
     * drops out. */
    for (int i = 0; i < n_id; i++) {
        const float *u = modes + n3 * (size_t)i + 3 * (size_t)first;
        double d = 0;
        for (int v = 0; v < count; v++)
            for (int k = 0; k < 3; k++)
                d += (mean[3 * (size_t)v + k] - c[k]) * u[3 * (size_t)v + k];
        g[i] = d / norm;
    }
    return FRIG_OK;
}

double fr_face_size_change(const double *g, const double *w, int n_id) {
    double d = 0;
    for (int i = 0; i < n_id; i++)
        d += g[i] * w[i];
    return d;
}

frig_status fr_solve_size_held(frig_ctx *ctx, int n, double *H, double *b, const double *g, double t) {
    /* Two right-hand sides: y = H^-1 b, z = H^-1 g; x = y + mu z with g . x = t. */
    double *B = malloc(sizeof(double) * 2 * (size_t)n);
    if (!B)
        return fr_nomem(ctx, "the identity step");
    memcpy(B, b, sizeof(double) * (size_t)n);
    memcpy(B + n, g, sizeof(double) * (size_t)n);
    frig_status s = fr_solve_spd(ctx, n, 2, H, n, B, n);
    if (!s) {
        double gy = 0, gz = 0;
        for (int i = 0; i < n; i++)
            gy += g[i] * B[i], gz += g[i] * B[n + i];
        double mu = gz > 0 ? (t - gy) / gz : 0;
        for (int i = 0; i < n; i++)
            b[i] = B[i] + mu * B[n + i];
    }
    free(B);
    return s;
}
