/* Float32 NHWC inference layers (internal), batch of one: convolutions by im2col + sgemm
 * (OpenBLAS), depthwise convolutions, batch norm and scale layers folded into the
 * convolution at load, ReLU / ReLU6, max and average pooling, residual adds, fully
 * connected layers, and the square input TensorFlow.js's face networks are fed (zero
 * padding, TF's bilinear resize). TensorFlow's padding rules: SAME pads
 * max((ceil(in / s) - 1) s + k - in, 0) in all, the smaller half before; VALID none.
 * Single-threaded per call (callers parallelize across photos): the same bytes whatever the
 * thread count, as long as BLAS runs serially (fr_blas_serial_begin). */
#ifndef FR_NN_LAYERS_H
#define FR_NN_LAYERS_H

#include <stddef.h>
#include <stdint.h>

#include "nn/weights.h"

/* An activation map: h x w x c floats, channels fastest. */
typedef struct fr_nn_map {
    int h, w, c;
    float *d;
} fr_nn_map;

typedef enum fr_nn_pad { FR_NN_SAME = 0, FR_NN_VALID = 1 } fr_nn_pad;
typedef enum fr_nn_act { FR_NN_LINEAR = 0, FR_NN_RELU = 1, FR_NN_RELU6 = 2 } fr_nn_act;

typedef struct fr_nn_conv {
    int kh, kw, cin, cout, stride;
    int depthwise; /* one kh x kw filter per channel (cout == cin) */
    fr_nn_pad pad;
    fr_nn_act act;
    float *w; /* regular: [kh][kw][cin][cout] (TensorFlow's HWIO); depthwise: [kh][kw][cin] */
    float *b; /* [cout] */
} fr_nn_conv;

/* A convolution from the tensors 'filters' (shape [kh, kw, cin, cout], or [kh, kw, cin, 1]
 * when depthwise) and 'bias' ([cout]; NULL: zeros), copied so that folding may change them.
 * Shapes are checked (FRIG_ERR_CORRUPT with the tensor's name). */
frig_status fr_nn_conv_init(frig_ctx *ctx, const fr_nn_weights *wts, const char *filters, const char *bias, int kh,
                            int kw, int cin, int cout, int depthwise, int stride, fr_nn_pad pad, fr_nn_act act,
                            fr_nn_conv *conv);
void fr_nn_conv_free(fr_nn_conv *conv);
/* Batch norm after the convolution, folded in: y = (x - mean) gamma / sqrt(var + eps) + beta. */
void fr_nn_conv_fold_batch_norm(fr_nn_conv *conv, const float *gamma, const float *beta, const float *mean,
                                const float *var, float eps);
/* A per-channel scale layer after the convolution, folded in: y = x s + t. */
void fr_nn_conv_fold_scale(fr_nn_conv *conv, const float *s, const float *t);

/* Output size for an input of h x w. */
void fr_nn_conv_out_size(const fr_nn_conv *conv, int h, int w, int *oh, int *ow);
/* out = act(conv(in) + b); out->d must hold oh * ow * cout floats (sizes are set). Returns
 * FRIG_ERR_NO_MEMORY when the im2col buffer cannot be had. */
frig_status fr_nn_conv_run(const fr_nn_conv *conv, const fr_nn_map *in, fr_nn_map *out);

/* A new map: conv applied to in (NULL data when out of memory). */
fr_nn_map fr_nn_apply(const fr_nn_conv *conv, const fr_nn_map *in);

/* A map of h x w x c floats (uninitialized); NULL data when out of memory. */
fr_nn_map fr_nn_map_new(int h, int w, int c);
void fr_nn_map_free(fr_nn_map *m);

/* Pooling windows k x k with stride s, VALID padding (out = (in - k) / s + 1). */
fr_nn_map fr_nn_max_pool(const fr_nn_map *in, int k, int s);
fr_nn_map fr_nn_avg_pool(const fr_nn_map *in, int k, int s);
/* The mean over all positions: c values. */
void fr_nn_global_mean(const fr_nn_map *in, float *out);
/* a += b elementwise (same shape), then ReLU when relu. */
void fr_nn_add(fr_nn_map *a, const fr_nn_map *b, int relu);
void fr_nn_relu(fr_nn_map *a);
/* y[n] = x[m] W[m x n] (+ b[n] when b): a fully connected layer, W row-major as tfjs stores it. */
void fr_nn_dense(const float *x, int m, const float *W, const float *b, int n, float *y);

/* The square a TensorFlow.js face network is fed: the region (x, y, w, h) of an 8-bit image
 * (1 or 3 channels; gray is repeated), padded with zeros to a square of side max(w, h) (at the
 * bottom or right; or centred: round(d / 2) after and the rest before, as tfjs's padToSquare),
 * resized to size x size by tf.image.resizeBilinear (align_corners and half_pixel_centers
 * false: source = dst * side / size, floor and ceil neighbours), as RGB values in 0..255.
 * The region must lie inside the image. out: size * size * 3 floats. */
void fr_nn_square_input(const uint8_t *pixels, size_t stride, int channels, int x, int y, int w, int h, int centred,
                        int size, float *out);

#endif
