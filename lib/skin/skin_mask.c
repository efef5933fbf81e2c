/* Skin region detection (paper section 5.1.2, Figure 5.2): the face region's pixels in
 * YCbCr; a mixture of Gaussians on (Cb, Cr) fitted by EM to the current skin pixels, with one
 * more component each round (a robust single Gaussian first), and pixels far from every
 * component removed as outliers; then SLIC superpixels (reference [64]) whose region pixels
 * are mostly not skin are dropped whole, which removes hair, beards, hands, glasses or
 * microphones that share the skin's chroma in places. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "image/srgb.h"
#include "skin/skin.h"
#include "skin/slic.h"

#define MIN_WEIGHT 0.03   /* components lighter than this do not vouch for a pixel */
#define CHROMA_FLOOR 0.25 /* least chroma variance (8-bit units squared) */

void fr_skin_options_default(fr_skin_options *o) {
    o->rounds = 3;
    o->chi2 = 9.21;
    o->em_iterations = 10;
    o->slic_step = 10;
    o->slic_compactness = 10.0;
    o->segment_skin = 0.5;
    o->dark = 12;
    o->clipped = 250;
}

void fr_rgb_to_ycbcr(const uint8_t rgb[3], double ycc[3]) {
    double r = rgb[0], g = rgb[1], b = rgb[2];
    ycc[0] = 0.299 * r + 0.587 * g + 0.114 * b;
    ycc[1] = 128.0 - 0.168736 * r - 0.331264 * g + 0.5 * b;
    ycc[2] = 128.0 + 0.5 * r - 0.418688 * g - 0.081312 * b;
}

static int near_some_component(const fr_gmm2 *g, double x, double y, double chi2) {
    for (int j = 0; j < g->k; j++)
        if (g->w[j] >= MIN_WEIGHT && fr_gmm2_mahalanobis2(g, j, x, y) <= chi2) return 1;
    return 0;
}

/* The component to split next: the widest (largest weight x covariance determinant). */
static int widest(const fr_gmm2 *g) {
    int best = 0;
    double bv = -1;
    for (int j = 0; j < g->k; j++) {
        double v = g->w[j] * sqrt(fmax(0.0, g->cov[j][0] * g->cov[j][2] - g->cov[j][1] * g->cov[j][1]));
        if (v > bv) bv = v, best = j;
    }
    return best;
}

/* Drop every superpixel whose region pixels are mostly not skin. */
static frig_status drop_segments(frig_ctx *ctx, const uint8_t *rgb, int w, int h, size_t stride,
                                 const uint8_t *region, const fr_skin_options *o, uint8_t *skin, int *segments) {
    size_t n = (size_t)w * h;
    float *lab = malloc(sizeof *lab * 3 * n);
    int32_t *labels = malloc(sizeof *labels * n);
    if (!lab || !labels) {
        free(lab), free(labels);
        return fr_nomem(ctx, "the skin superpixels");
    }
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) fr_srgb8_to_lab(rgb + (size_t)y * stride + 3 * (size_t)x, lab + 3 * ((size_t)y * w + x));
    int count = 0;
    frig_status s = fr_slic(ctx, lab, w, h, o->slic_step, o->slic_compactness, 10, labels, &count);
    int *tally = s ? NULL : calloc(2 * (size_t)count + 2, sizeof *tally);
    if (!s && !tally) s = fr_nomem(ctx, "the skin superpixels");
    if (!s) {
        for (size_t i = 0; i < n; i++)
            if (!region || region[i]) tally[2 * labels[i]]++, tally[2 * labels[i] + 1] += skin[i];
        for (size_t i = 0; i < n; i++)
            if (skin[i] && tally[2 * labels[i] + 1] < o->segment_skin * tally[2 * labels[i]]) skin[i] = 0;
        *segments = count;
    }
    free(tally), free(lab), free(labels);
    return s;
}

frig_status fr_skin_detect(frig_ctx *ctx, const uint8_t *rgb, int w, int h, size_t stride, const uint8_t *region,
                           const uint8_t *core, const fr_skin_options *opt, uint8_t *skin, fr_skin_stats *stats) {
    fr_skin_options o;
    if (opt) o = *opt;
    else fr_skin_options_default(&o);
    fr_skin_stats st;
    memset(&st, 0, sizeof st);
    size_t n = (size_t)w * h;
    double *cbcr = malloc(sizeof *cbcr * 2 * (n + 1));
    uint8_t *fit = calloc(n + 1, 1); /* the pixels the model is learnt from */
    if (!cbcr || !fit) {
        free(cbcr), free(fit);
        return fr_nomem(ctx, "the skin detector");
    }
    memset(skin, 0, n);
    long hist[256] = {0};
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            size_t i = (size_t)y * w + x;
            const uint8_t *p = rgb + (size_t)y * stride + 3 * (size_t)x;
            double ycc[3];
            fr_rgb_to_ycbcr(p, ycc);
            cbcr[2 * i] = ycc[1], cbcr[2 * i + 1] = ycc[2];
            if (region && !region[i]) continue;
            st.region++;
            hist[(int)floor(fmin(255.0, fmax(0.0, ycc[0])) + 0.5) & 255]++;
            int mx = p[0] > p[1] ? p[0] : p[1];
            if (p[2] > mx) mx = p[2];
            if (mx < o.dark) st.dark++;
            else if (p[0] >= o.clipped || p[1] >= o.clipped || p[2] >= o.clipped) st.clipped++;
            else skin[i] = 1;
        }
    for (long acc = 0, lv = 0; lv < 256; lv++)
        if ((acc += hist[lv]) * 2 >= st.region) {
            st.median_luma = (double)lv;
            break;
        }
    int core_count = 0;
    for (size_t i = 0; i < n; i++) core_count += fit[i] = skin[i] && (!core || core[i]);
    if (core_count < 20)
        for (size_t i = 0; i < n; i++) fit[i] = skin[i];
    for (int r = 0; r < o.rounds; r++) {
        if (r == 0) {
            if (!fr_gmm2_robust_init(cbcr, fit, (int)n, &st.gmm)) break;
        } else {
            fr_gmm2_split(&st.gmm, widest(&st.gmm));
        }
        fr_gmm2_em(&st.gmm, cbcr, fit, (int)n, o.em_iterations, CHROMA_FLOOR);
        for (size_t i = 0; i < n; i++)
            if (skin[i] && !near_some_component(&st.gmm, cbcr[2 * i], cbcr[2 * i + 1], o.chi2)) skin[i] = fit[i] = 0;
    }
    free(cbcr), free(fit);
    for (size_t i = 0; i < n; i++) st.chroma_skin += skin[i];
    frig_status s = FRIG_OK;
    if (o.slic_step > 0 && st.chroma_skin > 0) s = drop_segments(ctx, rgb, w, h, stride, region, &o, skin, &st.segments);
    if (s) return s;
    double sum[3] = {0, 0, 0};
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            size_t i = (size_t)y * w + x;
            if (!skin[i]) continue;
            st.skin++;
            const uint8_t *p = rgb + (size_t)y * stride + 3 * (size_t)x;
            for (int c = 0; c < 3; c++) sum[c] += fr_srgb_to_linear(p[c] / 255.0);
        }
    for (int c = 0; c < 3; c++) st.mean_linear[c] = st.skin ? sum[c] / st.skin : 0.0;
    if (stats) *stats = st;
    return FRIG_OK;
}
