/* Photo-consistency of the individual fits (paper section 4.4, F_tex of eq. 4.11): the face
 * texture inside the polygon of the RE-PROJECTED landmark vertices (not the detected points),
 * warped to the filter stage's common frame; a texture model of all photos (robust PCA, then
 * PCA of the low-rank part, as in failure detection) explains the consistent ones, and F_tex
 * is each photo's reconstruction RMSE (on gain/bias-normalized textures). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "filter/face_warp.h"
#include "filter/pca_model.h"
#include "filter/robust_pca.h"
#include "fit/photo_consistency.h"
#include "image/image.h"

#define TEXTURE_SIZE 48
#define PCA_ENERGY 0.95

frig_status fr_face_crop(frig_ctx *ctx, const frig_image *photo, const double *lm, int side, frig_image **crop,
                         double origin[2], double *scale) {
    double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
    for (int k = 0; k < FR_LANDMARKS; k++) {
        x0 = fmin(x0, lm[2 * k]), x1 = fmax(x1, lm[2 * k]);
        y0 = fmin(y0, lm[2 * k + 1]), y1 = fmax(y1, lm[2 * k + 1]);
    }
    double size = fmax(x1 - x0, y1 - y0);
    if (!(size > 1)) return fr_error(ctx, FRIG_ERR_NO_FACE, "landmarks span no area");
    /* The box grown by half its size; the crop shows the face at about 'side' pixels. */
    double cx = 0.5 * (x0 + x1), cy = 0.5 * (y0 + y1), half = 0.75 * size;
    double s = side / size;
    if (s > 1) s = 1; /* never enlarge */
    int n = (int)ceil(2 * half * s) + 1;
    frig_image *g = fr_image_new(n, n, 1);
    if (!g) return fr_nomem(ctx, "a face crop");
    origin[0] = cx - half;
    origin[1] = cy - half;
    *scale = s;
    /* Area-averaged sampling: each crop pixel averages taps x taps source pixels, whose
     * (clamped) columns and rows are computed once. */
    int W = photo->width, H = photo->height, C = photo->channels;
    double step = 1 / s;
    int taps = (int)ceil(step);
    int *col = malloc(sizeof(int) * (size_t)n * taps * 2);
    if (!col) {
        frig_image_free(g);
        return fr_nomem(ctx, "a face crop");
    }
    int *row = col + (size_t)n * taps;
    for (int x = 0; x < n; x++)
        for (int i = 0; i < taps; i++) {
            int sx = (int)floor(origin[0] + (x + (i + 0.5) / taps - 0.5) * step + 0.5);
            int sy = (int)floor(origin[1] + (x + (i + 0.5) / taps - 0.5) * step + 0.5);
            col[x * taps + i] = (sx < 0 ? 0 : sx >= W ? W - 1 : sx) * C;
            row[x * taps + i] = sy < 0 ? 0 : sy >= H ? H - 1 : sy;
        }
    for (int y = 0; y < n; y++)
        for (int x = 0; x < n; x++) {
            double sum = 0;
            for (int j = 0; j < taps; j++) {
                const uint8_t *src = photo->pixels + (size_t)row[y * taps + j] * photo->stride;
                for (int i = 0; i < taps; i++) {
                    const uint8_t *q = src + col[x * taps + i];
                    sum += C == 1 ? q[0] : 0.299 * q[0] + 0.587 * q[1] + 0.114 * q[2];
                }
            }
            g->pixels[(size_t)y * g->stride + x] = (uint8_t)(sum / (taps * taps) + 0.5);
        }
    free(col);
    *crop = g;
    return FRIG_OK;
}

/* The fit's re-projected landmarks, mapped into the photo's crop. */
static void reprojected_in_crop(const fr_fit_model *fm, const fr_fit_photo *p, const fr_fit_input *in, double *out) {
    double X[3 * FR_LANDMARKS];
    fr_fit_model_eval_slots(fm, p->w, fm->landmark_slot, FR_LANDMARKS, X);
    fr_fit_photo_project(p, X, FR_LANDMARKS, out);
    for (int k = 0; k < FR_LANDMARKS; k++) {
        out[2 * k] = (out[2 * k] - in->crop_origin[0]) * in->crop_scale;
        out[2 * k + 1] = (out[2 * k + 1] - in->crop_origin[1]) * in->crop_scale;
    }
}

frig_status fr_photo_consistency(frig_ctx *ctx, const fr_fit_model *fm, int n, const fr_fit_input *in,
                                 const fr_fit_photo *ph, int threads, double *f_tex) {
    for (int i = 0; i < n; i++) f_tex[i] = 0;
    fr_face_warp *warp = NULL;
    frig_status s = fr_face_warp_create(ctx, TEXTURE_SIZE, &warp);
    if (s) return s;
    int P = fr_face_warp_texels(warp);
    int *col = malloc(sizeof(int) * (size_t)n);
    double *X = malloc(sizeof(double) * (size_t)P * n);
    if (!col || !X) {
        free(col), free(X);
        fr_face_warp_free(warp);
        return fr_nomem(ctx, "photo-consistency textures");
    }
    int *ok = calloc((size_t)n, sizeof(int));
    int saved = fr_blas_serial_begin();
#pragma omp parallel for schedule(dynamic) num_threads(threads)
    for (int i = 0; i < n; i++) {
        if (!in[i].crop || !ok) continue;
        double lm[2 * FR_LANDMARKS];
        reprojected_in_crop(fm, &ph[i], &in[i], lm);
        frig_ctx *local = frig_ctx_create();
        if (local && fr_face_texture(local, warp, in[i].crop, lm, X + (size_t)P * i, NULL) == FRIG_OK) ok[i] = 1;
        frig_ctx_free(local);
    }
    fr_blas_serial_end(saved);
    /* Pack the usable textures as columns, in photo order. */
    int m = 0;
    for (int i = 0; ok && i < n; i++)
        if (ok[i]) {
            if (m != i) memmove(X + (size_t)P * m, X + (size_t)P * i, sizeof(double) * (size_t)P);
            col[m++] = i;
        }
    if (!ok) s = fr_nomem(ctx, "photo-consistency textures");
    if (!s && m >= 3) {
        /* Low-rank part by robust PCA, PCA model of it, RMSE of each photo's reconstruction. */
        double *Lbuf = malloc(sizeof(double) * (size_t)P * m * 2);
        double *res2 = malloc(sizeof(double) * (size_t)m);
        fr_pca pca;
        memset(&pca, 0, sizeof pca);
        if (!Lbuf || !res2) s = fr_nomem(ctx, "photo-consistency textures");
        if (!s) s = fr_robust_pca(ctx, P, m, X, P, NULL, Lbuf, Lbuf + (size_t)P * m, NULL);
        if (!s) s = fr_pca_fit(ctx, P, m, Lbuf, PCA_ENERGY, &pca);
        if (!s) s = fr_pca_reconstruct(ctx, &pca, m, X, res2, NULL);
        for (int a = 0; !s && a < m; a++) f_tex[col[a]] = sqrt(res2[a] / P);
        fr_pca_free(&pca);
        free(Lbuf);
        free(res2);
    }
    free(ok);
    free(col);
    free(X);
    fr_face_warp_free(warp);
    return s;
}
