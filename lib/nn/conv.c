/* Convolutions for the face networks: regular ones as im2col + sgemm (BLAS-3; a 1x1 stride-1
 * convolution is a single sgemm on the map itself), depthwise ones as direct loops over the
 * channels, with TensorFlow's SAME / VALID padding and the bias and activation fused. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cblas.h>

#include "core/context.h"
#include "nn/layers.h"

/* im2col rows per block: about 4 MB of floats, so the buffer stays small for large maps. */
#define IM2COL_FLOATS (1u << 20)

frig_status fr_nn_conv_init(frig_ctx *ctx, const fr_nn_weights *wts, const char *filters, const char *bias, int kh,
                            int kw, int cin, int cout, int depthwise, int stride, fr_nn_pad pad, fr_nn_act act,
                            fr_nn_conv *conv) {
    memset(conv, 0, sizeof *conv);
    int fshape[4] = {kh, kw, cin, depthwise ? 1 : cout};
    const float *f = fr_nn_weights_get(ctx, wts, filters, 4, fshape);
    if (!f) return FRIG_ERR_CORRUPT;
    const float *b = NULL;
    if (bias && !(b = fr_nn_weights_get(ctx, wts, bias, 1, &cout))) return FRIG_ERR_CORRUPT;
    size_t nw = (size_t)kh * (size_t)kw * (size_t)cin * (size_t)(depthwise ? 1 : cout);
    conv->w = malloc(nw * sizeof *conv->w);
    conv->b = calloc((size_t)cout, sizeof *conv->b);
    if (!conv->w || !conv->b) {
        fr_nn_conv_free(conv);
        return fr_nomem(ctx, "convolution weights");
    }
    memcpy(conv->w, f, nw * sizeof *conv->w);
    if (b) memcpy(conv->b, b, (size_t)cout * sizeof *conv->b);
    conv->kh = kh;
    conv->kw = kw;
    conv->cin = cin;
    conv->cout = cout;
    conv->depthwise = depthwise;
    conv->stride = stride;
    conv->pad = pad;
    conv->act = act;
    return FRIG_OK;
}

void fr_nn_conv_free(fr_nn_conv *conv) {
    if (!conv) return;
    free(conv->w);
    free(conv->b);
    conv->w = conv->b = NULL;
}

/* Multiply output channel co's filter weights by g[co] (HWIO: co is the fastest index). */
static void scale_filters(fr_nn_conv *conv, const float *g) {
    size_t taps = (size_t)conv->kh * (size_t)conv->kw * (size_t)(conv->depthwise ? 1 : conv->cin);
    for (size_t t = 0; t < taps; t++)
        for (int co = 0; co < conv->cout; co++) conv->w[t * (size_t)conv->cout + (size_t)co] *= g[co];
}

void fr_nn_conv_fold_batch_norm(fr_nn_conv *conv, const float *gamma, const float *beta, const float *mean,
                                const float *var, float eps) {
    float *g = malloc((size_t)conv->cout * sizeof *g);
    if (!g) return;
    for (int co = 0; co < conv->cout; co++) {
        g[co] = (float)(gamma[co] / sqrt((double)var[co] + (double)eps));
        conv->b[co] = (conv->b[co] - mean[co]) * g[co] + beta[co];
    }
    scale_filters(conv, g);
    free(g);
}

void fr_nn_conv_fold_scale(fr_nn_conv *conv, const float *s, const float *t) {
    for (int co = 0; co < conv->cout; co++) conv->b[co] = conv->b[co] * s[co] + t[co];
    scale_filters(conv, s);
}

static void out_dim(int in, int k, int s, fr_nn_pad pad, int *out, int *before) {
    if (pad == FR_NN_SAME) {
        *out = (in + s - 1) / s;
        int total = (*out - 1) * s + k - in;
        *before = total > 0 ? total / 2 : 0;
    } else {
        *out = in >= k ? (in - k) / s + 1 : 0;
        *before = 0;
    }
}

void fr_nn_conv_out_size(const fr_nn_conv *conv, int h, int w, int *oh, int *ow) {
    int b;
    out_dim(h, conv->kh, conv->stride, conv->pad, oh, &b);
    out_dim(w, conv->kw, conv->stride, conv->pad, ow, &b);
}

static void activate(float *v, size_t n, fr_nn_act act) {
    if (act == FR_NN_RELU)
        for (size_t i = 0; i < n; i++) v[i] = v[i] > 0 ? v[i] : 0;
    else if (act == FR_NN_RELU6)
        for (size_t i = 0; i < n; i++) v[i] = v[i] > 0 ? (v[i] < 6 ? v[i] : 6) : 0;
}

/* Output rows [p0, p1) of the im2col matrix: for each output pixel, its kh x kw x cin patch. A
 * patch row's taps inside the map are one run of the input row (channels fastest in both), so
 * each is one copy; the taps outside are zeros. */
static void im2col(const fr_nn_conv *cv, const fr_nn_map *in, int ow, int pt, int pl, int p0, int p1, float *col) {
    size_t K = (size_t)cv->kh * (size_t)cv->kw * (size_t)cv->cin, cin = (size_t)cv->cin;
    for (int p = p0; p < p1; p++) {
        int oy = p / ow, ox = p % ow;
        float *row = col + (size_t)(p - p0) * K;
        int x0 = ox * cv->stride - pl; /* the input column of tap kx = 0 */
        int k0 = x0 < 0 ? -x0 : 0, k1 = in->w - x0 < cv->kw ? in->w - x0 : cv->kw; /* taps [k0, k1) inside */
        if (k0 > cv->kw) k0 = cv->kw;
        if (k1 < k0) k1 = k0;
        for (int ky = 0; ky < cv->kh; ky++) {
            int iy = oy * cv->stride - pt + ky;
            float *dst = row + (size_t)ky * (size_t)cv->kw * cin;
            if (iy < 0 || iy >= in->h) {
                memset(dst, 0, (size_t)cv->kw * cin * sizeof *dst);
                continue;
            }
            if (k0 > 0) memset(dst, 0, (size_t)k0 * cin * sizeof *dst);
            if (k1 > k0)
                memcpy(dst + (size_t)k0 * cin, in->d + ((size_t)iy * (size_t)in->w + (size_t)(x0 + k0)) * cin,
                       (size_t)(k1 - k0) * cin * sizeof *dst);
            if (k1 < cv->kw) memset(dst + (size_t)k1 * cin, 0, (size_t)(cv->kw - k1) * cin * sizeof *dst);
        }
    }
}

static frig_status conv_regular(const fr_nn_conv *cv, const fr_nn_map *in, fr_nn_map *out, int pt, int pl) {
    int P = out->h * out->w, N = cv->cout;
    int K = cv->kh * cv->kw * cv->cin;
    for (int p = 0; p < P; p++) memcpy(out->d + (size_t)p * (size_t)N, cv->b, (size_t)N * sizeof *cv->b);
    if (cv->kh == 1 && cv->kw == 1 && cv->stride == 1) {
        cblas_sgemm(CblasRowMajor, CblasNoTrans, CblasNoTrans, P, N, K, 1.0f, in->d, K, cv->w, N, 1.0f, out->d, N);
    } else {
        int rows = (int)(IM2COL_FLOATS / (size_t)K);
        if (rows < 1) rows = 1;
        if (rows > P) rows = P;
        float *col = malloc((size_t)rows * (size_t)K * sizeof *col);
        if (!col) return FRIG_ERR_NO_MEMORY;
        for (int p0 = 0; p0 < P; p0 += rows) {
            int p1 = p0 + rows < P ? p0 + rows : P;
            im2col(cv, in, out->w, pt, pl, p0, p1, col);
            cblas_sgemm(CblasRowMajor, CblasNoTrans, CblasNoTrans, p1 - p0, N, K, 1.0f, col, K, cv->w, N, 1.0f,
                        out->d + (size_t)p0 * (size_t)N, N);
        }
        free(col);
    }
    activate(out->d, (size_t)P * (size_t)N, cv->act);
    return FRIG_OK;
}

static void conv_depthwise(const fr_nn_conv *cv, const fr_nn_map *in, fr_nn_map *out, int pt, int pl) {
    int C = cv->cin;
    for (int oy = 0; oy < out->h; oy++)
        for (int ox = 0; ox < out->w; ox++) {
            float *acc = out->d + ((size_t)oy * (size_t)out->w + (size_t)ox) * (size_t)C;
            memcpy(acc, cv->b, (size_t)C * sizeof *acc);
            for (int ky = 0; ky < cv->kh; ky++) {
                int iy = oy * cv->stride - pt + ky;
                if (iy < 0 || iy >= in->h) continue;
                for (int kx = 0; kx < cv->kw; kx++) {
                    int ix = ox * cv->stride - pl + kx;
                    if (ix < 0 || ix >= in->w) continue;
                    const float *x = in->d + ((size_t)iy * (size_t)in->w + (size_t)ix) * (size_t)C;
                    const float *w = cv->w + ((size_t)ky * (size_t)cv->kw + (size_t)kx) * (size_t)C;
                    for (int c = 0; c < C; c++) acc[c] += x[c] * w[c];
                }
            }
            activate(acc, (size_t)C, cv->act);
        }
}

fr_nn_map fr_nn_apply(const fr_nn_conv *conv, const fr_nn_map *in) {
    int oh, ow;
    fr_nn_conv_out_size(conv, in->h, in->w, &oh, &ow);
    fr_nn_map y = fr_nn_map_new(oh, ow, conv->cout);
    if (y.d && fr_nn_conv_run(conv, in, &y)) fr_nn_map_free(&y);
    return y;
}

frig_status fr_nn_conv_run(const fr_nn_conv *cv, const fr_nn_map *in, fr_nn_map *out) {
    int pt, pl;
    out_dim(in->h, cv->kh, cv->stride, cv->pad, &out->h, &pt);
    out_dim(in->w, cv->kw, cv->stride, cv->pad, &out->w, &pl);
    out->c = cv->cout;
    if (out->h <= 0 || out->w <= 0) return FRIG_OK;
    if (cv->depthwise) {
        conv_depthwise(cv, in, out, pt, pl);
        return FRIG_OK;
    }
    return conv_regular(cv, in, out, pt, pl);
}
