/* The face recognition net of @vladmandic/face-api (face_recognition_model: a port of dlib's
 * ResNet-29 metric network), as the package's computeFaceDescriptor runs it: the face chip of
 * FaceLandmarks.align (dlib alignment: eye and mouth centres), padded to a centred square and
 * resized to 150 x 150, (RGB - mean) / 255; a 7x7 stride-2 convolution and 3x3 max pooling;
 * residual blocks of two 3x3 convolutions (each followed by a per-channel scale layer, folded
 * here) at 32, 64, 128 and 256 channels, the first of each width striding by two with an
 * average-pooled, zero-padded shortcut; the spatial mean; a 256 x 128 matrix. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "nn/face_nets.h"
#include "nn/layers.h"

#define RN_INPUT 150
#define RN_BLOCKS 13

static const float mean_rgb[3] = {122.782f, 117.001f, 104.298f};

/* The residual blocks in order: name, channels in, channels out, down-sampling. */
static const struct {
    const char *name;
    int cin, cout, down;
} blocks[RN_BLOCKS] = {
    {"conv32_1", 32, 32, 0},      {"conv32_2", 32, 32, 0},     {"conv32_3", 32, 32, 0},
    {"conv64_down", 32, 64, 1},   {"conv64_1", 64, 64, 0},     {"conv64_2", 64, 64, 0},
    {"conv64_3", 64, 64, 0},      {"conv128_down", 64, 128, 1}, {"conv128_1", 128, 128, 0},
    {"conv128_2", 128, 128, 0},   {"conv256_down", 128, 256, 1}, {"conv256_1", 256, 256, 0},
    {"conv256_2", 256, 256, 0},
};
/* ... and conv256_down_out (256 -> 256, down-sampling) last. */

struct fr_recognition_net {
    fr_nn_conv first;
    fr_nn_conv conv1[RN_BLOCKS + 1], conv2[RN_BLOCKS + 1];
    float *fc; /* [256 x 128] */
};

void fr_recognition_net_free(fr_recognition_net *net) {
    if (!net) return;
    fr_nn_conv_free(&net->first);
    for (int i = 0; i <= RN_BLOCKS; i++) fr_nn_conv_free(&net->conv1[i]), fr_nn_conv_free(&net->conv2[i]);
    free(net->fc);
    free(net);
}

/* PREFIX/conv/filters + PREFIX/conv/bias, then the scale layer PREFIX/scale/{weights,biases}. */
static frig_status load_conv(frig_ctx *ctx, const fr_nn_weights *w, const char *prefix, int k, int cin, int cout,
                             int stride, fr_nn_pad pad, fr_nn_act act, fr_nn_conv *conv) {
    char f[96], b[96], s[96], t[96];
    snprintf(f, sizeof f, "%s/conv/filters", prefix);
    snprintf(b, sizeof b, "%s/conv/bias", prefix);
    snprintf(s, sizeof s, "%s/scale/weights", prefix);
    snprintf(t, sizeof t, "%s/scale/biases", prefix);
    frig_status st = fr_nn_conv_init(ctx, w, f, b, k, k, cin, cout, 0, stride, pad, act, conv);
    if (st) return st;
    const float *sw = fr_nn_weights_get(ctx, w, s, 1, &cout);
    const float *sb = sw ? fr_nn_weights_get(ctx, w, t, 1, &cout) : NULL;
    if (!sb) return FRIG_ERR_CORRUPT;
    fr_nn_conv_fold_scale(conv, sw, sb);
    return FRIG_OK;
}

static frig_status load_all(frig_ctx *ctx, const fr_nn_weights *w, fr_recognition_net *net) {
    frig_status st = load_conv(ctx, w, "conv32_down", 7, 3, 32, 2, FR_NN_VALID, FR_NN_RELU, &net->first);
    for (int i = 0; i <= RN_BLOCKS && !st; i++) {
        const char *name = i < RN_BLOCKS ? blocks[i].name : "conv256_down_out";
        int cin = i < RN_BLOCKS ? blocks[i].cin : 256, cout = i < RN_BLOCKS ? blocks[i].cout : 256;
        int down = i < RN_BLOCKS ? blocks[i].down : 1;
        char p[96];
        snprintf(p, sizeof p, "%s/conv1", name);
        st = load_conv(ctx, w, p, 3, cin, cout, down ? 2 : 1, down ? FR_NN_VALID : FR_NN_SAME, FR_NN_RELU,
                       &net->conv1[i]);
        snprintf(p, sizeof p, "%s/conv2", name);
        if (!st) st = load_conv(ctx, w, p, 3, cout, cout, 1, FR_NN_SAME, FR_NN_LINEAR, &net->conv2[i]);
    }
    if (st) return st;
    int fs[2] = {256, FR_FACE_DESCRIPTOR_SIZE};
    const float *fc = fr_nn_weights_get(ctx, w, "fc", 2, fs);
    if (!fc) return FRIG_ERR_CORRUPT;
    net->fc = malloc(sizeof(float) * 256 * FR_FACE_DESCRIPTOR_SIZE);
    if (!net->fc) return fr_nomem(ctx, "the recognition net");
    memcpy(net->fc, fc, sizeof(float) * 256 * FR_FACE_DESCRIPTOR_SIZE);
    return FRIG_OK;
}

frig_status fr_recognition_net_from(frig_ctx *ctx, const fr_nn_weights *w, fr_recognition_net **out) {
    *out = NULL;
    fr_recognition_net *net = calloc(1, sizeof *net);
    frig_status st = net ? load_all(ctx, w, net) : fr_nomem(ctx, "the recognition net");
    if (st) {
        fr_recognition_net_free(net);
        return st;
    }
    *out = net;
    return FRIG_OK;
}

/* residual: relu(conv2(conv1(x)) + x); residualDown: the shortcut is x average-pooled 2x2,
 * its channels padded with zeros, and the main path padded with a zero row and column when
 * it came out smaller (as the package's residualDown). */
static fr_nn_map residual(const fr_recognition_net *net, int i, const fr_nn_map *x) {
    int down = i < RN_BLOCKS ? blocks[i].down : 1;
    fr_nn_map a = fr_nn_apply(&net->conv1[i], x), out = {0, 0, 0, NULL};
    if (!a.d) return a;
    fr_nn_map b = fr_nn_apply(&net->conv2[i], &a);
    fr_nn_map_free(&a);
    if (!b.d) return b;
    if (!down) {
        fr_nn_add(&b, x, 1);
        return b;
    }
    fr_nn_map pooled = fr_nn_avg_pool(x, 2, 2);
    if (pooled.d) out = fr_nn_map_new(pooled.h, pooled.w, b.c);
    if (out.d) {
        memset(out.d, 0, sizeof(float) * (size_t)out.h * (size_t)out.w * (size_t)out.c);
        for (int yy = 0; yy < b.h && yy < out.h; yy++)
            for (int xx = 0; xx < b.w && xx < out.w; xx++)
                memcpy(out.d + ((size_t)yy * (size_t)out.w + (size_t)xx) * (size_t)out.c,
                       b.d + ((size_t)yy * (size_t)b.w + (size_t)xx) * (size_t)b.c, sizeof(float) * (size_t)b.c);
        for (size_t p = 0; p < (size_t)out.h * (size_t)out.w; p++)
            for (int c = 0; c < pooled.c; c++) out.d[p * (size_t)out.c + (size_t)c] += pooled.d[p * (size_t)pooled.c + (size_t)c];
        fr_nn_relu(&out);
    }
    fr_nn_map_free(&pooled);
    fr_nn_map_free(&b);
    return out;
}

void fr_face_chip_box(const double lm[136], int ref_w, int ref_h, int width, int height, int chip[4]) {
    /* centres of the left eye (36-41), the right eye (42-47) and the mouth (48-67) */
    double c[3][2] = {{0, 0}, {0, 0}, {0, 0}};
    const int from[3] = {36, 42, 48}, to[3] = {42, 48, 68};
    for (int k = 0; k < 3; k++) {
        for (int i = from[k]; i < to[k]; i++) c[k][0] += lm[2 * i], c[k][1] += lm[2 * i + 1];
        c[k][0] /= to[k] - from[k];
        c[k][1] /= to[k] - from[k];
    }
    double d = (hypot(c[2][0] - c[0][0], c[2][1] - c[0][1]) + hypot(c[2][0] - c[1][0], c[2][1] - c[1][1])) / 2;
    double size = floor(d / 0.45);
    double rx = (c[0][0] + c[1][0] + c[2][0]) / 3, ry = (c[0][1] + c[1][1] + c[2][1]) / 3;
    double x = floor(fmax(0.0, rx - 0.5 * size)), y = floor(fmax(0.0, ry - 0.43 * size));
    double w = fmin(size, ref_w + x), h = fmin(size, ref_h + y);
    /* extractFaceTensors: clipAtImageBorders, then floor */
    double cw = fmin(x + w - x, width - x), ch = fmin(y + h - y, height - y);
    chip[0] = (int)x;
    chip[1] = (int)y;
    chip[2] = cw > 0 ? (int)floor(cw) : 0;
    chip[3] = ch > 0 ? (int)floor(ch) : 0;
}

frig_status fr_recognition_net_run(frig_ctx *ctx, const fr_recognition_net *net, const fr_nn_image *img,
                                   const double landmarks[136], int ref_w, int ref_h,
                                   float descriptor[FR_FACE_DESCRIPTOR_SIZE]) {
    int c[4];
    fr_face_chip_box(landmarks, ref_w, ref_h, img->width, img->height, c);
    memset(descriptor, 0, sizeof(float) * FR_FACE_DESCRIPTOR_SIZE);
    if (c[2] <= 0 || c[3] <= 0 || c[0] >= img->width || c[1] >= img->height) return FRIG_OK;
    fr_nn_map x = fr_nn_map_new(RN_INPUT, RN_INPUT, 3);
    if (!x.d) return fr_nomem(ctx, "the recognition net's input");
    fr_nn_square_input(img->pixels + (size_t)c[1] * img->stride + (size_t)c[0] * (size_t)img->channels, img->stride,
                       img->channels, 0, 0, c[2], c[3], 1, RN_INPUT, x.d);
    for (size_t p = 0; p < (size_t)RN_INPUT * RN_INPUT; p++)
        for (int k = 0; k < 3; k++) x.d[3 * p + (size_t)k] = (x.d[3 * p + (size_t)k] - mean_rgb[k]) / 255.0f;
    fr_nn_map y = fr_nn_apply(&net->first, &x);
    fr_nn_map_free(&x);
    if (y.d) {
        x = fr_nn_max_pool(&y, 3, 2);
        fr_nn_map_free(&y);
    }
    for (int i = 0; i <= RN_BLOCKS && x.d; i++) {
        y = residual(net, i, &x);
        fr_nn_map_free(&x);
        x = y;
    }
    if (!x.d) return fr_nomem(ctx, "the recognition net's maps");
    float mean[256];
    fr_nn_global_mean(&x, mean);
    fr_nn_map_free(&x);
    fr_nn_dense(mean, 256, net->fc, NULL, FR_FACE_DESCRIPTOR_SIZE, descriptor);
    return FRIG_OK;
}

double fr_descriptor_distance(const float *a, const float *b) {
    double s = 0;
    for (int i = 0; i < FR_FACE_DESCRIPTOR_SIZE; i++) s += ((double)a[i] - b[i]) * ((double)a[i] - b[i]);
    return sqrt(s);
}
