/* The small layers of the face networks: maps, max and average pooling (VALID), the global
 * mean, residual adds, ReLU and fully connected layers. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cblas.h>

#include "nn/layers.h"

fr_nn_map fr_nn_map_new(int h, int w, int c) {
    fr_nn_map m = {h, w, c, NULL};
    size_t n = (size_t)(h > 0 ? h : 0) * (size_t)(w > 0 ? w : 0) * (size_t)(c > 0 ? c : 0);
    m.d = malloc((n ? n : 1) * sizeof *m.d);
    return m;
}

void fr_nn_map_free(fr_nn_map *m) {
    if (!m) return;
    free(m->d);
    m->d = NULL;
}

static fr_nn_map pool(const fr_nn_map *in, int k, int s, int average) {
    int oh = in->h >= k ? (in->h - k) / s + 1 : 0, ow = in->w >= k ? (in->w - k) / s + 1 : 0;
    fr_nn_map out = fr_nn_map_new(oh, ow, in->c);
    if (!out.d) return out;
    int C = in->c;
    float inv = 1.0f / (float)(k * k);
    for (int oy = 0; oy < oh; oy++)
        for (int ox = 0; ox < ow; ox++) {
            float *o = out.d + ((size_t)oy * (size_t)ow + (size_t)ox) * (size_t)C;
            for (int ky = 0; ky < k; ky++)
                for (int kx = 0; kx < k; kx++) {
                    const float *x = in->d + ((size_t)(oy * s + ky) * (size_t)in->w + (size_t)(ox * s + kx)) * (size_t)C;
                    if (ky == 0 && kx == 0) memcpy(o, x, (size_t)C * sizeof *o);
                    else if (average)
                        for (int c = 0; c < C; c++) o[c] += x[c];
                    else
                        for (int c = 0; c < C; c++) o[c] = x[c] > o[c] ? x[c] : o[c];
                }
            if (average)
                for (int c = 0; c < C; c++) o[c] *= inv;
        }
    return out;
}

fr_nn_map fr_nn_max_pool(const fr_nn_map *in, int k, int s) { return pool(in, k, s, 0); }
fr_nn_map fr_nn_avg_pool(const fr_nn_map *in, int k, int s) { return pool(in, k, s, 1); }

void fr_nn_global_mean(const fr_nn_map *in, float *out) {
    size_t n = (size_t)in->h * (size_t)in->w;
    for (int c = 0; c < in->c; c++) {
        double sum = 0;
        for (size_t p = 0; p < n; p++) sum += in->d[p * (size_t)in->c + (size_t)c];
        out[c] = n ? (float)(sum / (double)n) : 0.0f;
    }
}

void fr_nn_relu(fr_nn_map *a) {
    size_t n = (size_t)a->h * (size_t)a->w * (size_t)a->c;
    for (size_t i = 0; i < n; i++) a->d[i] = a->d[i] > 0 ? a->d[i] : 0;
}

void fr_nn_add(fr_nn_map *a, const fr_nn_map *b, int relu) {
    size_t n = (size_t)a->h * (size_t)a->w * (size_t)a->c;
    for (size_t i = 0; i < n; i++) a->d[i] += b->d[i];
    if (relu) fr_nn_relu(a);
}

void fr_nn_dense(const float *x, int m, const float *W, const float *b, int n, float *y) {
    if (b) memcpy(y, b, (size_t)n * sizeof *y);
    else memset(y, 0, (size_t)n * sizeof *y);
    cblas_sgemv(CblasRowMajor, CblasTrans, m, n, 1.0f, W, n, x, 1, 1.0f, y, 1);
}
