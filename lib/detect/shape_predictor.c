/* Evaluating dlib's ensemble of regression trees (Kazemi & Sullivan 2014, section 2; the
 * arithmetic of dlib's shape_predictor::operator(), reproduced operation for operation so the
 * points agree bit for bit): start from the mean shape in the box; per cascade level, fit the
 * similarity from the mean shape to the current one, read each feature pixel at its anchor
 * landmark plus the transformed delta (nearest pixel, 0 outside the image), walk every tree on
 * pixel differences, and add the reached leaves' shape increments in tree order. */
#include <math.h>
#include <string.h>

#include "detect/shape_predictor.h"

/* The 2x2 part of the least-squares similarity (Umeyama 1991) taking the initial shape to
 * 'shape', rounded to float as dlib does. For a 2-D similarity, scale times rotation is the
 * conformal part of the cross-covariance over the source spread:
 * [[a+d, b-c], [c-b, a+d]] / sum|from - mean|^2, with cov = [[a, b], [c, d]]. */
static void fit_similarity(const fr_shape_predictor *sp, const float *shape, float m[4]) {
    int n = sp->parts;
    if (n == 1) { /* dlib uses the identity for a single landmark */
        m[0] = m[3] = 1.0f;
        m[1] = m[2] = 0.0f;
        return;
    }
    double mx = 0, my = 0;
    for (int i = 0; i < n; i++) {
        mx += shape[2 * i];
        my += shape[2 * i + 1];
    }
    mx /= n;
    my /= n;
    double a = 0, b = 0, c = 0, d = 0;
    const double *from = sp->initial_centred;
    for (int i = 0; i < n; i++) {
        double tx = shape[2 * i] - mx, ty = shape[2 * i + 1] - my;
        a += tx * from[2 * i];
        b += tx * from[2 * i + 1];
        c += ty * from[2 * i];
        d += ty * from[2 * i + 1];
    }
    double s = sp->initial_sumsq;
    m[0] = (float)((a + d) / s);
    m[1] = (float)((b - c) / s);
    m[2] = (float)((c - b) / s);
    m[3] = m[0];
}

/* The gray value at the nearest pixel (dlib rounds with floor(v + 0.5)), 0 outside. */
static float pixel_at(const uint8_t *gray, int w, int h, size_t stride, double x, double y) {
    double fx = floor(x + 0.5), fy = floor(y + 0.5);
    if (!(fx >= 0 && fx <= w - 1 && fy >= 0 && fy <= h - 1)) return 0.0f; /* NaN lands here too */
    return (float)gray[(size_t)fy * stride + (size_t)fx];
}

/* Feature pixels of cascade c for the current shape, into feat[]. */
static void sample_features(const fr_shape_predictor *sp, int c, const float *shape, const float m[4],
                            const uint8_t *gray, int w, int h, size_t stride, const double box[4], float *feat) {
    size_t begin = sp->feature_begin[c], n = sp->feature_begin[c + 1] - begin;
    const uint32_t *anchor = sp->anchor + begin;
    const float *delta = sp->delta + 2 * begin;
    double bw = box[2] - box[0], bh = box[3] - box[1];
    for (size_t i = 0; i < n; i++) {
        float dx = delta[2 * i], dy = delta[2 * i + 1];
        /* in float, as dlib computes tform * delta + location */
        float px = m[0] * dx + m[1] * dy + shape[2 * anchor[i]];
        float py = m[2] * dx + m[3] * dy + shape[2 * anchor[i] + 1];
        feat[i] = pixel_at(gray, w, h, stride, bw * (double)px + box[0], bh * (double)py + box[1]);
    }
}

/* Walk one tree: left (2i+1) when the pixel difference exceeds the threshold. */
static size_t walk_tree(const fr_sp_split *split, size_t n_splits, const float *feat) {
    size_t i = 0;
    while (i < n_splits) {
        const fr_sp_split *s = &split[i];
        i = feat[s->idx1] - feat[s->idx2] > s->thresh ? 2 * i + 1 : 2 * i + 2;
    }
    return i - n_splits;
}

/* Add the leaves reached by cascade c's trees to the shape, in tree order. The leaves are
 * found first so their memory (a few MB per face, spread over the model) can be prefetched. */
static void apply_cascade(const fr_shape_predictor *sp, int c, const float *feat, float *shape) {
    enum { AHEAD = 4 };
    size_t t0 = sp->tree_begin[c], nt = sp->tree_begin[c + 1] - t0;
    size_t coords = 2 * (size_t)sp->parts;
    uint32_t leaf[FR_SP_MAX_TREES];
    for (size_t k = 0; k < nt; k++) {
        size_t t = t0 + k, sb = sp->split_begin[t];
        leaf[k] = (uint32_t)(sb + t + walk_tree(sp->splits + sb, sp->split_begin[t + 1] - sb, feat));
    }
    for (size_t k = 0; k < nt; k++) {
        if (k + AHEAD < nt) {
            const char *next = (const char *)(sp->leaves + (size_t)leaf[k + AHEAD] * coords);
            for (size_t off = 0; off < coords * sizeof(float); off += 64) __builtin_prefetch(next + off);
        }
        const float *v = sp->leaves + (size_t)leaf[k] * coords;
        for (size_t j = 0; j < coords; j++) shape[j] += v[j];
    }
}

frig_status fr_shape_predictor_run(const fr_shape_predictor *sp, const uint8_t *gray, int w, int h, size_t stride,
                                   const double box_ltrb[4], double *out) {
    if (!sp || !gray || !box_ltrb || !out || w <= 0 || h <= 0 || stride < (size_t)w) return FRIG_ERR_INVALID_ARGUMENT;
    for (int k = 0; k < 4; k++)
        if (!isfinite(box_ltrb[k])) return FRIG_ERR_INVALID_ARGUMENT;
    size_t coords = 2 * (size_t)sp->parts;
    float shape[2 * FR_SP_MAX_PARTS];
    float feat[FR_SP_MAX_FEATURES];
    memcpy(shape, sp->initial_shape, coords * sizeof *shape);
    for (int c = 0; c < sp->cascades; c++) {
        float m[4];
        fit_similarity(sp, shape, m);
        sample_features(sp, c, shape, m, gray, w, h, stride, box_ltrb, feat);
        apply_cascade(sp, c, feat, shape);
    }
    /* From the unit square back to the box: (0,0) -> top-left corner, (1,1) -> bottom-right. */
    double bw = box_ltrb[2] - box_ltrb[0], bh = box_ltrb[3] - box_ltrb[1];
    for (int i = 0; i < sp->parts; i++) {
        out[2 * i] = bw * (double)shape[2 * i] + box_ltrb[0];
        out[2 * i + 1] = bh * (double)shape[2 * i + 1] + box_ltrb[1];
    }
    return FRIG_OK;
}
