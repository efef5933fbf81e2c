/* SSD MobileNet v1 face detector (ssd_mobilenetv1_model of @vladmandic/face-api), as the
 * package's SsdMobilenetv1.locateFaces runs it: the photo padded to a square (bottom / right)
 * and resized to 512 x 512, x / 127.5 - 1; MobileNet v1 (a 3x3 stride-2 convolution, then 13
 * depthwise + pointwise pairs, batch norm folded, ReLU6); eight more pointwise / 3x3 layers;
 * six box predictors (on the 32x32 map of layer 11, the 16x16 output and the 8, 4, 2, 1
 * maps: 3 + 5 x 6 anchors per position, 5118 in all); boxes decoded against the anchors stored
 * in the weights (Output/extra_dim; scales 10, 10, 5, 5), scores the sigmoid of class 1;
 * non-maximum suppression as the package's (IoU > 0.5 suppresses), boxes clipped to [0, 1]
 * and scaled back to the photo as the package does. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "nn/face_nets.h"
#include "nn/layers.h"

#define SSD_INPUT 512
#define SSD_ANCHORS 5118
#define BN_EPS 0.0010000000474974513f

struct fr_ssd {
    fr_nn_conv conv0;
    fr_nn_conv dw[13], pw[13];
    fr_nn_conv pred[8];
    fr_nn_conv box[6], cls[6];
    float *anchors; /* SSD_ANCHORS x 4: the anchors as the package decodes them */
};

static const int dw_channels[13] = {32, 64, 128, 128, 256, 256, 512, 512, 512, 512, 512, 512, 1024};
static const int pw_channels[13] = {64, 128, 128, 256, 256, 512, 512, 512, 512, 512, 512, 1024, 1024};
/* Prediction/Conv2d_i_pointwise: kernel, input and output channels, stride. */
static const int pred_layers[8][4] = {{1, 1024, 256, 1}, {3, 256, 512, 2}, {1, 512, 128, 1}, {3, 128, 256, 2},
                                      {1, 256, 128, 1},  {3, 128, 256, 2}, {1, 256, 64, 1},  {3, 64, 128, 2}};
/* Box predictor i: input channels and anchors per position. */
static const int predictor_in[6] = {512, 1024, 512, 256, 256, 128};
static const int predictor_anchors[6] = {3, 6, 6, 6, 6, 6};

void fr_ssd_free(fr_ssd *net) {
    if (!net) return;
    fr_nn_conv_free(&net->conv0);
    for (int i = 0; i < 13; i++) fr_nn_conv_free(&net->dw[i]), fr_nn_conv_free(&net->pw[i]);
    for (int i = 0; i < 8; i++) fr_nn_conv_free(&net->pred[i]);
    for (int i = 0; i < 6; i++) fr_nn_conv_free(&net->box[i]), fr_nn_conv_free(&net->cls[i]);
    free(net->anchors);
    free(net);
}

static frig_status load_depthwise(frig_ctx *ctx, const fr_nn_weights *w, int i, fr_nn_conv *dw) {
    char p[128], f[160], g[160], b[160], m[160], v[160];
    snprintf(p, sizeof p, "MobilenetV1/Conv2d_%d_depthwise", i + 1);
    snprintf(f, sizeof f, "%s/depthwise_weights", p);
    int stride = (i + 1 == 2 || i + 1 == 4 || i + 1 == 6 || i + 1 == 12) ? 2 : 1;
    int c = dw_channels[i];
    frig_status st = fr_nn_conv_init(ctx, w, f, NULL, 3, 3, c, c, 1, stride, FR_NN_SAME, FR_NN_RELU6, dw);
    if (st) return st;
    snprintf(g, sizeof g, "%s/BatchNorm/gamma", p);
    snprintf(b, sizeof b, "%s/BatchNorm/beta", p);
    snprintf(m, sizeof m, "%s/BatchNorm/moving_mean", p);
    snprintf(v, sizeof v, "%s/BatchNorm/moving_variance", p);
    const float *gamma = fr_nn_weights_get(ctx, w, g, 1, &c), *beta = gamma ? fr_nn_weights_get(ctx, w, b, 1, &c) : NULL;
    const float *mean = beta ? fr_nn_weights_get(ctx, w, m, 1, &c) : NULL;
    const float *var = mean ? fr_nn_weights_get(ctx, w, v, 1, &c) : NULL;
    if (!var) return FRIG_ERR_CORRUPT;
    for (int k = 0; k < c; k++)
        if (!(var[k] >= 0)) return fr_error(ctx, FRIG_ERR_CORRUPT, "%s: %s has a negative variance", FR_SSD_MODEL, v);
    fr_nn_conv_fold_batch_norm(dw, gamma, beta, mean, var, BN_EPS);
    return FRIG_OK;
}

static frig_status load_pointwise(frig_ctx *ctx, const fr_nn_weights *w, const char *prefix, int i, int k, int cin,
                                  int cout, int stride, fr_nn_conv *conv) {
    char f[160], b[160];
    snprintf(f, sizeof f, "%s/Conv2d_%d_pointwise/weights", prefix, i);
    snprintf(b, sizeof b, "%s/Conv2d_%d_pointwise/convolution_bn_offset", prefix, i);
    return fr_nn_conv_init(ctx, w, f, b, k, k, cin, cout, 0, stride, FR_NN_SAME, FR_NN_RELU6, conv);
}

static frig_status load_predictor(frig_ctx *ctx, const fr_nn_weights *w, int i, fr_ssd *net) {
    char f[160], b[160];
    int cin = predictor_in[i], a = predictor_anchors[i];
    snprintf(f, sizeof f, "Prediction/BoxPredictor_%d/BoxEncodingPredictor/weights", i);
    snprintf(b, sizeof b, "Prediction/BoxPredictor_%d/BoxEncodingPredictor/biases", i);
    frig_status st = fr_nn_conv_init(ctx, w, f, b, 1, 1, cin, 4 * a, 0, 1, FR_NN_SAME, FR_NN_LINEAR, &net->box[i]);
    if (st) return st;
    snprintf(f, sizeof f, "Prediction/BoxPredictor_%d/ClassPredictor/weights", i);
    snprintf(b, sizeof b, "Prediction/BoxPredictor_%d/ClassPredictor/biases", i);
    return fr_nn_conv_init(ctx, w, f, b, 1, 1, cin, 3 * a, 0, 1, FR_NN_SAME, FR_NN_LINEAR, &net->cls[i]);
}

static frig_status load_all(frig_ctx *ctx, const fr_nn_weights *w, fr_ssd *net) {
    frig_status st = fr_nn_conv_init(ctx, w, "MobilenetV1/Conv2d_0_pointwise/weights",
                                     "MobilenetV1/Conv2d_0_pointwise/convolution_bn_offset", 3, 3, 3, 32, 0, 2,
                                     FR_NN_SAME, FR_NN_RELU6, &net->conv0);
    for (int i = 0; i < 13 && !st; i++) {
        st = load_depthwise(ctx, w, i, &net->dw[i]);
        if (!st) st = load_pointwise(ctx, w, "MobilenetV1", i + 1, 1, dw_channels[i], pw_channels[i], 1, &net->pw[i]);
    }
    for (int i = 0; i < 8 && !st; i++)
        st = load_pointwise(ctx, w, "Prediction", i, pred_layers[i][0], pred_layers[i][1], pred_layers[i][2],
                            pred_layers[i][3], &net->pred[i]);
    for (int i = 0; i < 6 && !st; i++) st = load_predictor(ctx, w, i, net);
    if (st) return st;
    int shape[3] = {1, SSD_ANCHORS, 4};
    const float *a = fr_nn_weights_get(ctx, w, "Output/extra_dim", 3, shape);
    if (!a) return FRIG_ERR_CORRUPT;
    net->anchors = malloc(sizeof(float) * 4 * SSD_ANCHORS);
    if (!net->anchors) return fr_nomem(ctx, "SSD anchors");
    memcpy(net->anchors, a, sizeof(float) * 4 * SSD_ANCHORS);
    return FRIG_OK;
}

frig_status fr_ssd_from(frig_ctx *ctx, const fr_nn_weights *w, fr_ssd **out) {
    *out = NULL;
    fr_ssd *net = calloc(1, sizeof *net);
    frig_status st = net ? load_all(ctx, w, net) : fr_nomem(ctx, "the SSD detector");
    if (st) {
        fr_ssd_free(net);
        return st;
    }
    *out = net;
    return FRIG_OK;
}

/* The layers' maps in two buffers used in turn, each as large as the largest map: one
 * allocation per forward pass instead of one per layer (fresh pages every layer cost more than
 * the thinner layers' arithmetic, most of all under AddressSanitizer). */
typedef struct pingpong {
    float *buf[2];
    int next; /* the buffer the next layer writes */
} pingpong;

static void grow(size_t *cap, int h, int w, int c) {
    size_t n = (size_t)h * (size_t)w * (size_t)c;
    if (n > *cap) *cap = n;
}

/* The largest map (floats) the backbone and the prediction layers write for an input h x w. */
static size_t largest_map(const fr_ssd *net, int h, int w) {
    size_t cap = 1;
    fr_nn_conv_out_size(&net->conv0, h, w, &h, &w);
    grow(&cap, h, w, net->conv0.cout);
    for (int i = 0; i < 13; i++) {
        fr_nn_conv_out_size(&net->dw[i], h, w, &h, &w);
        grow(&cap, h, w, net->dw[i].cout);
        fr_nn_conv_out_size(&net->pw[i], h, w, &h, &w);
        grow(&cap, h, w, net->pw[i].cout);
    }
    for (int i = 0; i < 8; i++) {
        fr_nn_conv_out_size(&net->pred[i], h, w, &h, &w);
        grow(&cap, h, w, net->pred[i].cout);
    }
    return cap;
}

/* Run conv on *x into the buffer not holding it; *x becomes the result. */
static frig_status step(const fr_nn_conv *conv, pingpong *pp, fr_nn_map *x) {
    fr_nn_map y = {0, 0, 0, pp->buf[pp->next]};
    frig_status st = fr_nn_conv_run(conv, x, &y);
    if (st) return st;
    pp->next ^= 1;
    *x = y;
    return FRIG_OK;
}

/* A copy of x in a map of its own. */
static frig_status keep_copy(const fr_nn_map *x, fr_nn_map *out) {
    *out = fr_nn_map_new(x->h, x->w, x->c);
    if (!out->d) return FRIG_ERR_NO_MEMORY;
    memcpy(out->d, x->d, sizeof(float) * (size_t)x->h * (size_t)x->w * (size_t)x->c);
    return FRIG_OK;
}

/* The box predictors' raw outputs, concatenated as the package does: 5118 x 4 encodings and
 * 5118 scores (sigmoid of class 1). */
static frig_status predict(const fr_ssd *net, const fr_nn_map *maps[6], float *enc, float *score) {
    size_t at = 0;
    for (int i = 0; i < 6; i++) {
        const fr_nn_map *m = maps[i];
        fr_nn_map b = fr_nn_map_new(m->h, m->w, net->box[i].cout), c = fr_nn_map_new(m->h, m->w, net->cls[i].cout);
        frig_status st = (!b.d || !c.d) ? FRIG_ERR_NO_MEMORY : fr_nn_conv_run(&net->box[i], m, &b);
        if (!st) st = fr_nn_conv_run(&net->cls[i], m, &c);
        if (!st) {
            size_t n = (size_t)m->h * (size_t)m->w * (size_t)predictor_anchors[i];
            memcpy(enc + 4 * at, b.d, 4 * n * sizeof *enc);
            for (size_t k = 0; k < n; k++) score[at + k] = (float)(1.0 / (1.0 + exp(-(double)c.d[3 * k + 1])));
            at += n;
        }
        fr_nn_map_free(&b);
        fr_nn_map_free(&c);
        if (st) return st;
    }
    return at == SSD_ANCHORS ? FRIG_OK : FRIG_ERR_INTERNAL;
}

/* The network on a 512 x 512 x 3 input already scaled to [-1, 1] (left as it is). */
static frig_status forward(const fr_ssd *net, const fr_nn_map *in, float *enc, float *score) {
    fr_nn_map conv11 = {0, 0, 0, NULL}, c1 = conv11, c3 = conv11, c5 = conv11, last = conv11;
    size_t cap = largest_map(net, in->h, in->w);
    pingpong pp = {{malloc(sizeof(float) * cap), malloc(sizeof(float) * cap)}, 0};
    frig_status st = !pp.buf[0] || !pp.buf[1] ? FRIG_ERR_NO_MEMORY : FRIG_OK;
    fr_nn_map x = *in;
    if (!st) st = step(&net->conv0, &pp, &x);
    for (int i = 0; i < 13 && !st; i++) {
        st = step(&net->dw[i], &pp, &x);
        if (!st) st = step(&net->pw[i], &pp, &x);
        if (!st && i + 1 == 11) st = keep_copy(&x, &conv11);
    }
    /* x is now the 16 x 16 x 1024 output, kept; the prediction layers run on from it. */
    if (!st) st = keep_copy(&x, &last);
    fr_nn_map *keep[8] = {NULL, &c1, NULL, &c3, NULL, &c5, NULL, NULL};
    for (int i = 0; i < 8 && !st; i++) {
        st = step(&net->pred[i], &pp, &x);
        if (!st && keep[i]) st = keep_copy(&x, keep[i]);
    }
    if (!st) {
        const fr_nn_map *maps[6] = {&conv11, &last, &c1, &c3, &c5, &x};
        st = predict(net, maps, enc, score);
    }
    fr_nn_map_free(&conv11);
    fr_nn_map_free(&c1);
    fr_nn_map_free(&c3);
    fr_nn_map_free(&c5);
    fr_nn_map_free(&last);
    free(pp.buf[0]);
    free(pp.buf[1]);
    return st;
}

/* Decoded boxes (ymin, xmin, ymax, xmax) in the padded square's [0, 1] frame, in float32
 * steps as tfjs computes them. */
static void decode_boxes(const float *anchors, const float *enc, float *boxes) {
    for (int i = 0; i < SSD_ANCHORS; i++) {
        const float *a = anchors + 4 * i, *t = enc + 4 * i;
        float sy = a[2] - a[0], sx = a[3] - a[1];
        float cy = a[0] + sy / 2, cx = a[1] + sx / 2;
        float hy = (float)exp((double)(t[2] / 5)) * sy / 2, hx = (float)exp((double)(t[3] / 5)) * sx / 2;
        float my = t[0] / 10 * sy + cy, mx = t[1] / 10 * sx + cx;
        float *b = boxes + 4 * i;
        b[0] = my - hy;
        b[1] = mx - hx;
        b[2] = my + hy;
        b[3] = mx + hx;
    }
}

static double box_iou(const float *a, const float *b) {
    double ay0 = fmin(a[0], a[2]), ax0 = fmin(a[1], a[3]), ay1 = fmax(a[0], a[2]), ax1 = fmax(a[1], a[3]);
    double by0 = fmin(b[0], b[2]), bx0 = fmin(b[1], b[3]), by1 = fmax(b[0], b[2]), bx1 = fmax(b[1], b[3]);
    double aa = (ay1 - ay0) * (ax1 - ax0), ab = (by1 - by0) * (bx1 - bx0);
    if (aa <= 0 || ab <= 0) return 0.0;
    double inter = fmax(fmin(ay1, by1) - fmax(ay0, by0), 0.0) * fmax(fmin(ax1, bx1) - fmax(ax0, bx0), 0.0);
    return inter / (aa + ab - inter);
}

typedef struct candidate {
    float score;
    int index;
} candidate;

/* Higher score first; ties in index order (the package's sort is stable). */
static int by_score(const void *pa, const void *pb) {
    const candidate *a = pa, *b = pb;
    if (a->score != b->score) return a->score > b->score ? -1 : 1;
    return a->index - b->index;
}

/* The package's non-maximum suppression; returns the number selected into sel. */
static int suppress(const float *boxes, const float *score, double min_score, int max_out, int *sel) {
    candidate *c = malloc(sizeof *c * SSD_ANCHORS);
    if (!c) return -1;
    int n = 0, kept = 0;
    for (int i = 0; i < SSD_ANCHORS; i++)
        if (score[i] > min_score) c[n].score = score[i], c[n].index = i, n++;
    qsort(c, (size_t)n, sizeof *c, by_score);
    for (int i = 0; i < n && kept < max_out; i++) {
        int drop = 0;
        for (int j = kept - 1; j >= 0 && !drop; j--) drop = box_iou(boxes + 4 * c[i].index, boxes + 4 * sel[j]) > 0.5;
        if (!drop) sel[kept++] = c[i].index;
    }
    free(c);
    return kept;
}

frig_status fr_ssd_detect(frig_ctx *ctx, const fr_ssd *net, const fr_nn_image *img, double min_score, int max_results,
                          fr_ssd_face **faces, size_t *count) {
    *faces = NULL;
    *count = 0;
    if (img->width < 1 || img->height < 1) return FRIG_OK;
    fr_nn_map x = fr_nn_map_new(SSD_INPUT, SSD_INPUT, 3);
    float *enc = malloc(sizeof(float) * 4 * SSD_ANCHORS), *score = malloc(sizeof(float) * SSD_ANCHORS);
    float *boxes = malloc(sizeof(float) * 4 * SSD_ANCHORS);
    int *sel = malloc(sizeof(int) * (size_t)(max_results > 0 ? max_results : 1));
    frig_status st = (!x.d || !enc || !score || !boxes || !sel) ? FRIG_ERR_NO_MEMORY : FRIG_OK;
    if (!st) {
        fr_nn_square_input(img->pixels, img->stride, img->channels, 0, 0, img->width, img->height, 0, SSD_INPUT, x.d);
        for (size_t i = 0; i < (size_t)SSD_INPUT * SSD_INPUT * 3; i++) x.d[i] = x.d[i] / 127.5f - 1.0f;
        st = forward(net, &x, enc, score);
    }
    int kept = 0;
    if (!st) {
        decode_boxes(net->anchors, enc, boxes);
        kept = suppress(boxes, score, min_score, max_results, sel);
        if (kept < 0) st = FRIG_ERR_NO_MEMORY;
    }
    fr_ssd_face *v = NULL;
    if (!st && kept > 0 && !(v = malloc(sizeof *v * (size_t)kept))) st = FRIG_ERR_NO_MEMORY;
    if (!st && kept > 0) {
        /* locateFaces: relative box clipped to [0, 1] and scaled by input / reshaped size,
         * then FaceDetection scales it by the photo's size. */
        int side = img->width > img->height ? img->width : img->height;
        double scale = (double)SSD_INPUT / side;
        double pad_x = SSD_INPUT / floor(img->width * scale + 0.5), pad_y = SSD_INPUT / floor(img->height * scale + 0.5);
        for (int k = 0; k < kept; k++) {
            const float *b = boxes + 4 * sel[k];
            double top = fmax(0.0, b[0]) * pad_y, bottom = fmin(1.0, b[2]) * pad_y;
            double left = fmax(0.0, b[1]) * pad_x, right = fmin(1.0, b[3]) * pad_x;
            v[k].score = score[sel[k]];
            v[k].box[0] = left * img->width;
            v[k].box[1] = top * img->height;
            v[k].box[2] = (right - left) * img->width;
            v[k].box[3] = (bottom - top) * img->height;
        }
    }
    fr_nn_map_free(&x);
    free(enc);
    free(score);
    free(boxes);
    free(sel);
    if (st) {
        free(v);
        return st == FRIG_ERR_NO_MEMORY ? fr_nomem(ctx, "the SSD detector's maps") : fr_error(ctx, st, "SSD detector");
    }
    *faces = v;
    *count = (size_t)kept;
    return FRIG_OK;
}
