/* The inference layers of lib/nn against direct definitions: convolutions (im2col + sgemm,
 * 1x1 sgemm, depthwise) against a naive loop with TensorFlow's SAME / VALID padding, the
 * folds of batch norm and scale layers, pooling, and the face networks' square input against
 * tf.image.resizeBilinear's rule written out by hand. No data files needed. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "nn/layers.h"
#include "testing.h"

static unsigned long long seed = 12345;
static float rnd(void) {
    seed = seed * 6364136223846793005ULL + 1442695040888963407ULL;
    return (float)((seed >> 40) / (double)(1ULL << 24)) * 2.0f - 1.0f;
}

/* A weights set of one filter and one bias tensor, built through the manifest parser. */
static fr_nn_weights *make_weights(frig_ctx *ctx, int kh, int kw, int cin, int cout, int depthwise, float **fw,
                                   float **fb) {
    int co = depthwise ? 1 : cout;
    size_t nw = (size_t)kh * kw * cin * co;
    char manifest[512];
    snprintf(manifest, sizeof manifest,
             "[{\"paths\": [\"x.bin\"], \"weights\": [{\"name\": \"f\", \"shape\": [%d, %d, %d, %d], \"dtype\": "
             "\"float32\"}, {\"name\": \"b\", \"shape\": [%d], \"dtype\": \"float32\"}]}]",
             kh, kw, cin, co, cout);
    size_t n = (nw + (size_t)cout) * 4;
    unsigned char *bin = malloc(n);
    *fw = malloc(nw * sizeof **fw);
    *fb = malloc((size_t)cout * sizeof **fb);
    for (size_t i = 0; i < nw; i++) (*fw)[i] = rnd(), memcpy(bin + 4 * i, &(*fw)[i], 4);
    for (int i = 0; i < cout; i++) (*fb)[i] = rnd(), memcpy(bin + 4 * (nw + (size_t)i), &(*fb)[i], 4);
    fr_nn_weights *w = NULL;
    CHECK(fr_nn_weights_parse(ctx, "test", manifest, strlen(manifest), bin, n, &w) == FRIG_OK);
    free(bin);
    return w;
}

/* The definition: out[y][x][o] = b[o] + sum in[y s + ky - pt][x s + kx - pl][i] w[ky][kx][i][o]. */
static void naive(const fr_nn_map *in, const float *w, const float *b, int kh, int kw, int cout, int s, int dw,
                  fr_nn_pad pad, fr_nn_act act, fr_nn_map *out) {
    int oh, ow, pt = 0, pl = 0;
    if (pad == FR_NN_SAME) {
        oh = (in->h + s - 1) / s, ow = (in->w + s - 1) / s;
        int th = (oh - 1) * s + kh - in->h, tw = (ow - 1) * s + kw - in->w;
        pt = th > 0 ? th / 2 : 0, pl = tw > 0 ? tw / 2 : 0;
    } else {
        oh = (in->h - kh) / s + 1, ow = (in->w - kw) / s + 1;
    }
    *out = fr_nn_map_new(oh, ow, cout);
    for (int y = 0; y < oh; y++)
        for (int x = 0; x < ow; x++)
            for (int o = 0; o < cout; o++) {
                double acc = b[o];
                for (int ky = 0; ky < kh; ky++)
                    for (int kx = 0; kx < kw; kx++) {
                        int iy = y * s + ky - pt, ix = x * s + kx - pl;
                        if (iy < 0 || ix < 0 || iy >= in->h || ix >= in->w) continue;
                        const float *v = in->d + ((size_t)iy * in->w + ix) * in->c;
                        if (dw) acc += (double)v[o] * w[((size_t)ky * kw + kx) * in->c + o];
                        else
                            for (int i = 0; i < in->c; i++) acc += (double)v[i] * w[(((size_t)ky * kw + kx) * in->c + i) * cout + o];
                    }
                if (act == FR_NN_RELU && acc < 0) acc = 0;
                if (act == FR_NN_RELU6) acc = acc < 0 ? 0 : acc > 6 ? 6 : acc;
                out->d[((size_t)y * ow + x) * cout + o] = (float)acc;
            }
}

static void check_conv(frig_ctx *ctx, int h, int w, int cin, int cout, int k, int s, int dw, fr_nn_pad pad, fr_nn_act act) {
    float *fw, *fb;
    fr_nn_weights *wts = make_weights(ctx, k, k, cin, cout, dw, &fw, &fb);
    fr_nn_conv conv;
    CHECK(fr_nn_conv_init(ctx, wts, "f", "b", k, k, cin, cout, dw, s, pad, act, &conv) == FRIG_OK);
    fr_nn_map in = fr_nn_map_new(h, w, cin), got, want;
    for (size_t i = 0; i < (size_t)h * w * cin; i++) in.d[i] = rnd();
    int oh, ow;
    fr_nn_conv_out_size(&conv, h, w, &oh, &ow);
    got = fr_nn_map_new(oh, ow, cout);
    CHECK(fr_nn_conv_run(&conv, &in, &got) == FRIG_OK);
    naive(&in, fw, fb, k, k, cout, s, dw, pad, act, &want);
    CHECK(got.h == want.h && got.w == want.w);
    double worst = 0;
    for (size_t i = 0; i < (size_t)want.h * want.w * cout; i++) worst = fmax(worst, fabs(got.d[i] - want.d[i]));
    if (worst > 1e-4) fprintf(stderr, "conv %dx%dx%d k%d s%d dw%d pad%d: worst %g\n", h, w, cin, k, s, dw, pad, worst);
    CHECK(worst <= 1e-4);
    fr_nn_map_free(&in), fr_nn_map_free(&got), fr_nn_map_free(&want);
    fr_nn_conv_free(&conv);
    fr_nn_weights_free(wts);
    free(fw), free(fb);
}

static void check_folds(frig_ctx *ctx) {
    float *fw, *fb;
    fr_nn_weights *wts = make_weights(ctx, 3, 3, 4, 5, 0, &fw, &fb);
    fr_nn_conv conv;
    CHECK(fr_nn_conv_init(ctx, wts, "f", "b", 3, 3, 4, 5, 0, 1, FR_NN_SAME, FR_NN_LINEAR, &conv) == FRIG_OK);
    fr_nn_map in = fr_nn_map_new(6, 7, 4), raw = fr_nn_map_new(6, 7, 5), folded = fr_nn_map_new(6, 7, 5);
    for (size_t i = 0; i < 6 * 7 * 4; i++) in.d[i] = rnd();
    CHECK(fr_nn_conv_run(&conv, &in, &raw) == FRIG_OK);
    float g[5], be[5], mu[5], var[5], s[5], t[5];
    for (int i = 0; i < 5; i++) g[i] = rnd() + 2, be[i] = rnd(), mu[i] = rnd(), var[i] = rnd() + 1.5f, s[i] = rnd(), t[i] = rnd();
    fr_nn_conv_fold_batch_norm(&conv, g, be, mu, var, 1e-3f);
    fr_nn_conv_fold_scale(&conv, s, t);
    CHECK(fr_nn_conv_run(&conv, &in, &folded) == FRIG_OK);
    double worst = 0;
    for (size_t p = 0; p < 6 * 7; p++)
        for (int o = 0; o < 5; o++) {
            double bn = (raw.d[p * 5 + o] - mu[o]) * g[o] / sqrt(var[o] + 1e-3) + be[o];
            worst = fmax(worst, fabs(folded.d[p * 5 + o] - (bn * s[o] + t[o])));
        }
    CHECK(worst < 1e-4);
    fr_nn_map_free(&in), fr_nn_map_free(&raw), fr_nn_map_free(&folded);
    fr_nn_conv_free(&conv);
    fr_nn_weights_free(wts);
    free(fw), free(fb);
}

static void check_pools(void) {
    fr_nn_map in = fr_nn_map_new(5, 5, 2);
    for (int i = 0; i < 50; i++) in.d[i] = (float)((i * 7) % 11);
    fr_nn_map mx = fr_nn_max_pool(&in, 3, 2), av = fr_nn_avg_pool(&in, 2, 2);
    CHECK(mx.h == 2 && mx.w == 2 && av.h == 2 && av.w == 2);
    for (int y = 0; y < 2; y++)
        for (int x = 0; x < 2; x++)
            for (int c = 0; c < 2; c++) {
                float m = -1, a = 0;
                for (int ky = 0; ky < 3; ky++)
                    for (int kx = 0; kx < 3; kx++) m = fmaxf(m, in.d[((y * 2 + ky) * 5 + x * 2 + kx) * 2 + c]);
                for (int ky = 0; ky < 2; ky++)
                    for (int kx = 0; kx < 2; kx++) a += in.d[((y * 2 + ky) * 5 + x * 2 + kx) * 2 + c] / 4;
                CHECK(mx.d[(y * 2 + x) * 2 + c] == m);
                CHECK_NEAR(av.d[(y * 2 + x) * 2 + c], a, 1e-5);
            }
    fr_nn_map_free(&in), fr_nn_map_free(&mx), fr_nn_map_free(&av);
}

/* A gray region 3 wide and 2 high padded to a 3 x 3 square with a zero row below (centred
 * padding is the same here: round(1 / 2) = 1 row after, none before), resized to 2 x 2:
 * source = dst * 1.5. */
static void check_square_input(void) {
    const uint8_t px[6] = {10, 20, 30, 40, 50, 60}; /* rows: 10 20 30 / 40 50 60 */
    float out[2 * 2 * 3];
    fr_nn_square_input(px, 3, 1, 0, 0, 3, 2, 0, 2, out);
    /* (0,0) -> 10; (0,1): x 1.5 -> 25; (1,0): y 1.5 between row 1 (40) and row 2 (zero pad) -> 20;
     * (1,1): between 50, 60 and zeros -> 27.5 */
    CHECK_NEAR(out[0], 10, 1e-6);
    CHECK_NEAR(out[3], 25, 1e-6);
    CHECK_NEAR(out[6], 20, 1e-6);
    CHECK_NEAR(out[9], 27.5, 1e-6);
    CHECK(out[1] == out[0] && out[2] == out[0]);
    /* centred: diff 1, round(0.5) = 1 appended, 0 before: the same as bottom padding here */
    float c[12];
    fr_nn_square_input(px, 3, 1, 0, 0, 3, 2, 1, 2, c);
    CHECK(memcmp(c, out, sizeof c) == 0);
    /* a 1 x 4 column padded centred to 4 x 4: diff 3, 2 after, 1 before */
    const uint8_t col[4] = {100, 100, 100, 100};
    float s[4 * 4 * 3];
    fr_nn_square_input(col, 1, 1, 0, 0, 1, 4, 1, 4, s);
    CHECK(s[(0 * 4 + 0) * 3] == 0 && s[(0 * 4 + 1) * 3] == 100 && s[(0 * 4 + 2) * 3] == 0);
}

int main(void) {
    frig_ctx *ctx = frig_ctx_create();
    int saved = fr_blas_serial_begin();
    check_conv(ctx, 9, 8, 3, 5, 3, 2, 0, FR_NN_SAME, FR_NN_RELU6);  /* the SSD's first layer, small */
    check_conv(ctx, 10, 10, 4, 6, 3, 1, 0, FR_NN_SAME, FR_NN_RELU);
    check_conv(ctx, 12, 11, 3, 4, 7, 2, 0, FR_NN_VALID, FR_NN_LINEAR); /* the recognition net's first */
    check_conv(ctx, 7, 7, 8, 16, 1, 1, 0, FR_NN_SAME, FR_NN_LINEAR);  /* pointwise: one sgemm */
    check_conv(ctx, 9, 9, 6, 6, 3, 2, 1, FR_NN_SAME, FR_NN_RELU6);    /* depthwise, stride 2 */
    check_conv(ctx, 8, 5, 5, 5, 3, 1, 1, FR_NN_SAME, FR_NN_LINEAR);
    check_conv(ctx, 8, 8, 4, 4, 3, 2, 0, FR_NN_VALID, FR_NN_RELU);
    check_folds(ctx);
    check_pools();
    check_square_input();
    fr_blas_serial_end(saved);
    frig_ctx_free(ctx);
    return test_result("test_nn_layers");
}
