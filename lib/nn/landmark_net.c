/* The 68-point landmark net of @vladmandic/face-api (face_landmark_68_model), as the package's
 * FaceLandmark68Net runs it on a detection: the box clipped to the image and floored, the crop
 * padded to a centred square and resized to 112 x 112, (RGB - mean) / 255; four dense blocks
 * (a stride-2 convolution, then three separable convolutions whose inputs are the ReLU of the
 * sum of all earlier outputs of the block), 7x7 average pooling, a fully connected layer to
 * 136 values; the points undo the padding and scale, and are shifted by the detection's
 * corner (unrounded, as extendWithFaceLandmarks does). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "nn/face_nets.h"
#include "nn/layers.h"

#define LM_INPUT 112
#define LM_FEATURES 256

static const float mean_rgb[3] = {122.782f, 117.001f, 104.298f};
static const int block_channels[4][2] = {{3, 32}, {32, 64}, {64, 128}, {128, 256}};

/* One separable convolution: depthwise (no bias) then pointwise with the bias. */
typedef struct separable {
    fr_nn_conv dw, pw;
} separable;

struct fr_landmark_net {
    fr_nn_conv first;         /* dense0/conv0: a regular 3x3 stride-2 convolution */
    separable down[3];        /* dense1..3/conv0: separable, stride 2 */
    separable conv[4][3];     /* denseI/conv1..3 */
    float *fc_w, *fc_b;       /* [256 x 136], [136] */
};

static void separable_free(separable *s) {
    fr_nn_conv_free(&s->dw);
    fr_nn_conv_free(&s->pw);
}

void fr_landmark_net_free(fr_landmark_net *net) {
    if (!net) return;
    fr_nn_conv_free(&net->first);
    for (int i = 0; i < 3; i++) separable_free(&net->down[i]);
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 3; j++) separable_free(&net->conv[i][j]);
    free(net->fc_w);
    free(net->fc_b);
    free(net);
}

static frig_status load_separable(frig_ctx *ctx, const fr_nn_weights *w, int block, int conv, int cin, int cout,
                                  int stride, separable *s) {
    char d[96], p[96], b[96];
    snprintf(d, sizeof d, "dense%d/conv%d/depthwise_filter", block, conv);
    snprintf(p, sizeof p, "dense%d/conv%d/pointwise_filter", block, conv);
    snprintf(b, sizeof b, "dense%d/conv%d/bias", block, conv);
    frig_status st = fr_nn_conv_init(ctx, w, d, NULL, 3, 3, cin, cin, 1, stride, FR_NN_SAME, FR_NN_LINEAR, &s->dw);
    if (!st) st = fr_nn_conv_init(ctx, w, p, b, 1, 1, cin, cout, 0, 1, FR_NN_SAME, FR_NN_LINEAR, &s->pw);
    return st;
}

static frig_status load_all(frig_ctx *ctx, const fr_nn_weights *w, fr_landmark_net *net) {
    frig_status st = fr_nn_conv_init(ctx, w, "dense0/conv0/filters", "dense0/conv0/bias", 3, 3, 3, 32, 0, 2, FR_NN_SAME,
                                     FR_NN_LINEAR, &net->first);
    for (int i = 1; i < 4 && !st; i++)
        st = load_separable(ctx, w, i, 0, block_channels[i][0], block_channels[i][1], 2, &net->down[i - 1]);
    for (int i = 0; i < 4 && !st; i++)
        for (int j = 0; j < 3 && !st; j++)
            st = load_separable(ctx, w, i, j + 1, block_channels[i][1], block_channels[i][1], 1, &net->conv[i][j]);
    if (st) return st;
    int ws[2] = {LM_FEATURES, 136}, bs = 136;
    const float *fw = fr_nn_weights_get(ctx, w, "fc/weights", 2, ws);
    const float *fb = fw ? fr_nn_weights_get(ctx, w, "fc/bias", 1, &bs) : NULL;
    if (!fb) return FRIG_ERR_CORRUPT;
    net->fc_w = malloc(sizeof(float) * LM_FEATURES * 136);
    net->fc_b = malloc(sizeof(float) * 136);
    if (!net->fc_w || !net->fc_b) return fr_nomem(ctx, "the landmark net");
    memcpy(net->fc_w, fw, sizeof(float) * LM_FEATURES * 136);
    memcpy(net->fc_b, fb, sizeof(float) * 136);
    return FRIG_OK;
}

frig_status fr_landmark_net_from(frig_ctx *ctx, const fr_nn_weights *w, fr_landmark_net **out) {
    *out = NULL;
    fr_landmark_net *net = calloc(1, sizeof *net);
    frig_status st = net ? load_all(ctx, w, net) : fr_nomem(ctx, "the landmark net");
    if (st) {
        fr_landmark_net_free(net);
        return st;
    }
    *out = net;
    return FRIG_OK;
}

static fr_nn_map apply_separable(const separable *s, const fr_nn_map *in) {
    fr_nn_map t = fr_nn_apply(&s->dw, in);
    if (!t.d) return t;
    fr_nn_map y = fr_nn_apply(&s->pw, &t);
    fr_nn_map_free(&t);
    return y;
}

/* denseBlock4: out1 = relu(conv0(x)); out2 = sep1(out1); out3 = sep2(relu(out1 + out2));
 * out4 = sep3(relu(out1 + out2 + out3)); result relu(out1 + out2 + out3 + out4). */
static fr_nn_map dense_block(const fr_landmark_net *net, int i, const fr_nn_map *x) {
    fr_nn_map o[4];
    memset(o, 0, sizeof o);
    o[0] = i == 0 ? fr_nn_apply(&net->first, x) : apply_separable(&net->down[i - 1], x);
    fr_nn_map sum = {0, 0, 0, NULL};
    int ok = o[0].d != NULL;
    if (ok) fr_nn_relu(&o[0]);
    if (ok) {
        sum = fr_nn_map_new(o[0].h, o[0].w, o[0].c);
        ok = sum.d != NULL;
    }
    if (ok) memcpy(sum.d, o[0].d, sizeof(float) * (size_t)sum.h * (size_t)sum.w * (size_t)sum.c);
    for (int k = 1; k < 4 && ok; k++) {
        /* the input of conv k: out1 alone, then relu of the running sum */
        fr_nn_map in = sum;
        if (k > 1) fr_nn_relu(&in);
        o[k] = apply_separable(&net->conv[i][k - 1], k == 1 ? &o[0] : &in);
        ok = o[k].d != NULL;
        if (ok && k == 1) {
            /* running sum = out1 + out2 (tfjs adds out1 + out2 before its ReLU) */
            memcpy(sum.d, o[0].d, sizeof(float) * (size_t)sum.h * (size_t)sum.w * (size_t)sum.c);
            fr_nn_add(&sum, &o[1], 0);
        } else if (ok) {
            /* out1 + (out2 + out3 [+ out4]) as tfjs groups it */
            fr_nn_map rest = fr_nn_map_new(sum.h, sum.w, sum.c);
            ok = rest.d != NULL;
            if (ok) {
                memcpy(rest.d, o[1].d, sizeof(float) * (size_t)sum.h * (size_t)sum.w * (size_t)sum.c);
                if (k == 2) fr_nn_add(&rest, &o[2], 0);
                else {
                    fr_nn_map tail = fr_nn_map_new(sum.h, sum.w, sum.c);
                    ok = tail.d != NULL;
                    if (ok) {
                        memcpy(tail.d, o[2].d, sizeof(float) * (size_t)sum.h * (size_t)sum.w * (size_t)sum.c);
                        fr_nn_add(&tail, &o[3], 0);
                        fr_nn_add(&rest, &tail, 0);
                    }
                    fr_nn_map_free(&tail);
                }
                memcpy(sum.d, o[0].d, sizeof(float) * (size_t)sum.h * (size_t)sum.w * (size_t)sum.c);
                fr_nn_add(&sum, &rest, 0);
            }
            fr_nn_map_free(&rest);
        }
    }
    for (int k = 0; k < 4; k++) fr_nn_map_free(&o[k]);
    if (!ok) fr_nn_map_free(&sum);
    else fr_nn_relu(&sum);
    return sum;
}

/* tfjs Box.clipAtImageBorders(...).floor() of a box (x, y, w, h). */
static void clip_floor(const double box[4], int width, int height, int out[4]) {
    double x = fmax(box[0], 0.0), y = fmax(box[1], 0.0);
    double w = fmin(box[0] + box[2] - x, width - x), h = fmin(box[1] + box[3] - y, height - y);
    out[0] = (int)floor(x);
    out[1] = (int)floor(y);
    out[2] = (int)floor(w);
    out[3] = (int)floor(h);
}

frig_status fr_landmark_net_run(frig_ctx *ctx, const fr_landmark_net *net, const fr_nn_image *img,
                                const double box[4], double landmarks[136], int crop[4]) {
    int c[4];
    clip_floor(box, img->width, img->height, c);
    if (c[2] <= 0 || c[3] <= 0 || c[0] >= img->width || c[1] >= img->height)
        return fr_error(ctx, FRIG_ERR_NO_FACE, "landmark net: the box (%g, %g, %g, %g) has no pixels in the image",
                        box[0], box[1], box[2], box[3]);
    if (c[0] + c[2] > img->width) c[2] = img->width - c[0];
    if (c[1] + c[3] > img->height) c[3] = img->height - c[1];
    if (crop) memcpy(crop, c, sizeof c);
    fr_nn_map x = fr_nn_map_new(LM_INPUT, LM_INPUT, 3);
    if (!x.d) return fr_nomem(ctx, "the landmark net's input");
    fr_nn_square_input(img->pixels + (size_t)c[1] * img->stride + (size_t)c[0] * (size_t)img->channels, img->stride,
                       img->channels, 0, 0, c[2], c[3], 1, LM_INPUT, x.d);
    for (size_t p = 0; p < (size_t)LM_INPUT * LM_INPUT; p++)
        for (int k = 0; k < 3; k++) x.d[3 * p + (size_t)k] = (x.d[3 * p + (size_t)k] - mean_rgb[k]) / 255.0f;
    for (int i = 0; i < 4 && x.d; i++) {
        fr_nn_map y = dense_block(net, i, &x);
        fr_nn_map_free(&x);
        x = y;
    }
    if (!x.d) return fr_nomem(ctx, "the landmark net's maps");
    fr_nn_map pooled = fr_nn_avg_pool(&x, 7, 2);
    fr_nn_map_free(&x);
    if (!pooled.d) return fr_nomem(ctx, "the landmark net's maps");
    if (pooled.h * pooled.w * pooled.c != LM_FEATURES) {
        fr_nn_map_free(&pooled);
        return fr_error(ctx, FRIG_ERR_INTERNAL, "landmark net: %d features, expected %d", pooled.h * pooled.w * pooled.c,
                        LM_FEATURES);
    }
    float out[136];
    fr_nn_dense(pooled.d, LM_FEATURES, net->fc_w, net->fc_b, 136, out);
    fr_nn_map_free(&pooled);
    /* postProcess: the crop scaled so that its longer side is 112, centred padding removed. */
    double s = (double)LM_INPUT / (c[2] > c[3] ? c[2] : c[3]);
    double sw = c[2] * s, sh = c[3] * s;
    double px = sw < sh ? fabs(sw - sh) / 2 : 0, py = sh < sw ? fabs(sw - sh) / 2 : 0;
    for (int k = 0; k < 68; k++) {
        float rx = (float)(((float)(out[2 * k] * (float)LM_INPUT) - (float)px) / (float)sw);
        float ry = (float)(((float)(out[2 * k + 1] * (float)LM_INPUT) - (float)py) / (float)sh);
        landmarks[2 * k] = (double)rx * c[2] + box[0];
        landmarks[2 * k + 1] = (double)ry * c[3] + box[1];
    }
    return FRIG_OK;
}
