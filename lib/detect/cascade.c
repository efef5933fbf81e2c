/* Multi-scale detection with a boosted cascade (Viola-Jones; paper section 4.2), reproducing OpenCV
 * 4.6's CascadeClassifierImpl::detectMultiScale: scales factor^k as floats, the image resized to
 * each, windows of the trained size every 2 px (1 px from scale 2 on; a window rejected by the first
 * stage skips the next), Haar sums normalized by the window's standard deviation, then grouping. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "detect/cascade.h"

#define GROUP_EPS 0.2

/* Haar feature with offsets into the integral buffer (tilted rects point past the sum table). */
typedef struct haar_opt {
    int ofs[3][4];
    float weight[3];
} haar_opt;

typedef struct haar_stump {
    haar_opt f;
    float threshold, left, right;
} haar_stump;

/* A tree node with its feature's offsets inlined (same index as the cascade's node). */
typedef struct haar_node {
    haar_opt f;
    float threshold;
    int left, right;
} haar_node;

typedef struct lbp_opt {
    int ofs[16]; /* the 4x4 grid of block corners */
} lbp_opt;

typedef struct lbp_stump {
    lbp_opt f;
    int32_t subset[FR_CASCADE_SUBSET_WORDS];
    float left, right;
} lbp_stump;

/* Everything one detect call precomputes for its integral stride. */
typedef struct evaluator {
    const fr_cascade *c;
    int norm[4];
    double norm_area;
    haar_opt *haar;      /* per feature */
    haar_stump *hstumps; /* per weak classifier, stage order (stumps) */
    haar_node *hnodes;   /* per tree node (trees) */
    lbp_opt *lbp;
    lbp_stump *lstumps;
} evaluator;

static void sum_offsets(int o[4], int x, int y, int w, int h, int step) {
    o[0] = x + step * y;
    o[1] = x + w + step * y;
    o[2] = x + step * (y + h);
    o[3] = x + w + step * (y + h);
}

static void tilted_offsets(int o[4], int x, int y, int w, int h, int step, int tofs) {
    o[0] = tofs + x + step * y;
    o[1] = tofs + x - h + step * (y + h);
    o[2] = tofs + x + w + step * (y + w);
    o[3] = tofs + x + w - h + step * (y + w + h);
}

static void haar_setup(haar_opt *o, const fr_cascade_haar *f, int step, int tofs) {
    memset(o, 0, sizeof *o);
    for (int r = 0; r < f->nrects; r++) {
        const fr_cascade_rect *q = &f->rect[r];
        if (f->tilted) tilted_offsets(o->ofs[r], q->x, q->y, q->w, q->h, step, tofs);
        else sum_offsets(o->ofs[r], q->x, q->y, q->w, q->h, step);
        o->weight[r] = q->weight;
    }
}

static void lbp_setup(lbp_opt *o, const fr_cascade_lbp *f, int step) {
    for (int r = 0; r < 4; r++)
        for (int k = 0; k < 4; k++) o->ofs[r * 4 + k] = (f->y + r * f->h) * step + f->x + k * f->w;
}

static void evaluator_free(evaluator *e) {
    free(e->haar);
    free(e->hstumps);
    free(e->hnodes);
    free(e->lbp);
    free(e->lstumps);
}

static int evaluator_init(evaluator *e, const fr_cascade *c, int step, int tofs) {
    memset(e, 0, sizeof *e);
    e->c = c;
    sum_offsets(e->norm, 1, 1, c->win_w - 2, c->win_h - 2, step);
    e->norm_area = (double)(c->win_w - 2) * (c->win_h - 2);
    int stumps = c->max_nodes_per_tree == 1;
    if (c->type == FR_CASCADE_HAAR) {
        e->haar = malloc(sizeof *e->haar * (size_t)c->nfeatures);
        if (!e->haar) return -1;
        for (int i = 0; i < c->nfeatures; i++) haar_setup(&e->haar[i], &c->haar[i], step, tofs);
        if (stumps) {
            e->hstumps = malloc(sizeof *e->hstumps * (size_t)c->ntrees);
            if (!e->hstumps) return -1;
            for (int t = 0; t < c->ntrees; t++) {
                const fr_cascade_node *n = &c->nodes[c->trees[t].first_node];
                const float *leaf = &c->leaves[c->trees[t].first_leaf];
                haar_stump *s = &e->hstumps[t];
                s->f = e->haar[n->feature];
                s->threshold = n->threshold;
                s->left = leaf[-n->left];
                s->right = leaf[-n->right];
            }
        } else {
            e->hnodes = malloc(sizeof *e->hnodes * (size_t)c->nnodes);
            if (!e->hnodes) return -1;
            for (int i = 0; i < c->nnodes; i++) {
                e->hnodes[i].f = e->haar[c->nodes[i].feature];
                e->hnodes[i].threshold = c->nodes[i].threshold;
                e->hnodes[i].left = c->nodes[i].left;
                e->hnodes[i].right = c->nodes[i].right;
            }
        }
    } else {
        e->lbp = malloc(sizeof *e->lbp * (size_t)c->nfeatures);
        if (!e->lbp) return -1;
        for (int i = 0; i < c->nfeatures; i++) lbp_setup(&e->lbp[i], &c->lbp[i], step);
        if (stumps) {
            e->lstumps = malloc(sizeof *e->lstumps * (size_t)c->ntrees);
            if (!e->lstumps) return -1;
            for (int t = 0; t < c->ntrees; t++) {
                int ni = c->trees[t].first_node;
                const fr_cascade_node *n = &c->nodes[ni];
                const float *leaf = &c->leaves[c->trees[t].first_leaf];
                lbp_stump *s = &e->lstumps[t];
                s->f = e->lbp[n->feature];
                memcpy(s->subset, &c->subsets[(size_t)ni * FR_CASCADE_SUBSET_WORDS], sizeof s->subset);
                s->left = leaf[-n->left];
                s->right = leaf[-n->right];
            }
        }
    }
    return 0;
}

/* ---- feature values: OpenCV's float arithmetic, in its order ---- */

static inline int32_t box_sum(const uint32_t *p, const int o[4]) {
    return (int32_t)(p[o[0]] - p[o[1]] - p[o[2]] + p[o[3]]);
}

static inline float haar_value(const haar_opt *f, const uint32_t *p) {
    float v = f->weight[0] * (float)box_sum(p, f->ofs[0]) + f->weight[1] * (float)box_sum(p, f->ofs[1]);
    if (f->weight[2] != 0.0f) v += f->weight[2] * (float)box_sum(p, f->ofs[2]);
    return v;
}

static inline int lbp_code(const lbp_opt *f, const uint32_t *p) {
    const int *o = f->ofs;
    int32_t c = (int32_t)(p[o[5]] - p[o[6]] - p[o[9]] + p[o[10]]);
#define LBP_BIT(a, b, d, e, bit) ((int32_t)(p[o[a]] - p[o[b]] - p[o[d]] + p[o[e]]) >= c ? (bit) : 0)
    return LBP_BIT(0, 1, 4, 5, 128) | LBP_BIT(1, 2, 5, 6, 64) | LBP_BIT(2, 3, 6, 7, 32) | LBP_BIT(6, 7, 10, 11, 16) |
           LBP_BIT(10, 11, 14, 15, 8) | LBP_BIT(9, 10, 13, 14, 4) | LBP_BIT(8, 9, 12, 13, 2) | LBP_BIT(4, 5, 8, 9, 1);
#undef LBP_BIT
}

static inline int in_subset(const int32_t *subset, int code) {
    return ((uint32_t)subset[code >> 5] >> (code & 31)) & 1u;
}

/* ---- one stage's sum, for each kind of weak classifier ---- */

static double haar_stumps_sum(const evaluator *e, const fr_cascade_stage *st, const uint32_t *p, float inv_sd) {
    const haar_stump *s = e->hstumps + st->first_tree;
    double sum = 0;
    for (int i = 0; i < st->ntrees; i++, s++) {
        float v = haar_value(&s->f, p) * inv_sd;
        sum += v < s->threshold ? s->left : s->right;
    }
    return sum;
}

static double haar_trees_sum(const evaluator *e, const fr_cascade_stage *st, const uint32_t *p, float inv_sd) {
    const fr_cascade *c = e->c;
    double sum = 0;
    for (int t = st->first_tree; t < st->first_tree + st->ntrees; t++) {
        const fr_cascade_tree *tr = &c->trees[t];
        const haar_node *root = &e->hnodes[tr->first_node];
        int idx = 0;
        do {
            const haar_node *n = &root[idx];
            float v = haar_value(&n->f, p) * inv_sd;
            idx = v < n->threshold ? n->left : n->right;
        } while (idx > 0);
        sum += c->leaves[tr->first_leaf - idx];
    }
    return sum;
}

static double lbp_stumps_sum(const evaluator *e, const fr_cascade_stage *st, const uint32_t *p) {
    const lbp_stump *s = e->lstumps + st->first_tree;
    double sum = 0;
    for (int i = 0; i < st->ntrees; i++, s++) sum += in_subset(s->subset, lbp_code(&s->f, p)) ? s->left : s->right;
    return sum;
}

static double lbp_trees_sum(const evaluator *e, const fr_cascade_stage *st, const uint32_t *p) {
    const fr_cascade *c = e->c;
    double sum = 0;
    for (int t = st->first_tree; t < st->first_tree + st->ntrees; t++) {
        const fr_cascade_tree *tr = &c->trees[t];
        int idx = 0;
        do {
            int ni = tr->first_node + idx;
            const fr_cascade_node *n = &c->nodes[ni];
            int code = lbp_code(&e->lbp[n->feature], p);
            idx = in_subset(&c->subsets[(size_t)ni * FR_CASCADE_SUBSET_WORDS], code) ? n->left : n->right;
        } while (idx > 0);
        sum += c->leaves[tr->first_leaf - idx];
    }
    return sum;
}

/* OpenCV's variance normalization of a Haar window: 1 / (area * standard deviation) over the window
 * less its one-pixel border; 0 (window skipped) when the deviation is under 10 grey levels. */
static float haar_norm(const evaluator *e, const uint32_t *p, const uint32_t *q) {
    int32_t valsum = box_sum(p, e->norm);
    uint32_t valsq = q[e->norm[0]] - q[e->norm[1]] - q[e->norm[2]] + q[e->norm[3]];
    double nf = e->norm_area * valsq - (double)valsum * valsum;
    if (!(nf > 0.)) return 0.f;
    float inv_sd = (float)(1. / sqrt(nf));
    return e->norm_area * inv_sd < 1e-1 ? inv_sd : 0.f;
}

/* One window: 1 accepted, -k rejected by stage k (0 = the first), -1 also for a flat Haar window.
 * 'weight' is the last stage sum computed. */
static int run_window(const evaluator *e, const uint32_t *p, const uint32_t *q, double *weight) {
    const fr_cascade *c = e->c;
    float inv_sd = 0.f;
    if (c->type == FR_CASCADE_HAAR && (inv_sd = haar_norm(e, p, q)) == 0.f) return -1;
    double sum = 0;
    for (int si = 0; si < c->nstages; si++) {
        const fr_cascade_stage *st = &c->stages[si];
        if (c->type == FR_CASCADE_HAAR)
            sum = e->hstumps ? haar_stumps_sum(e, st, p, inv_sd) : haar_trees_sum(e, st, p, inv_sd);
        else
            sum = e->lstumps ? lbp_stumps_sum(e, st, p) : lbp_trees_sum(e, st, p);
        if (sum < st->threshold) {
            *weight = sum;
            return -si;
        }
    }
    *weight = sum;
    return 1;
}

/* ---- the scan ---- */

typedef struct box_list {
    fr_cascade_box *v;
    size_t n, cap;
} box_list;

static int push_box(box_list *l, int x, int y, int w, int h, double weight) {
    if (l->n == l->cap) {
        size_t cap = l->cap ? 2 * l->cap : 256;
        fr_cascade_box *v = realloc(l->v, cap * sizeof *v);
        if (!v) return -1;
        l->v = v;
        l->cap = cap;
    }
    fr_cascade_box *b = &l->v[l->n++];
    b->x = x, b->y = y, b->w = w, b->h = h, b->neighbors = 1, b->weight = weight;
    return 0;
}

/* Windows of one pyramid level: rows below ylimit, columns below xlimit, every 'step' pixels. */
static int scan_level(const evaluator *e, const uint32_t *sum, const uint32_t *sqsum, int istride, int xlimit,
                      int ylimit, int step, float scale, box_list *out) {
    int ww = (int)lrintf((float)e->c->win_w * scale), wh = (int)lrintf((float)e->c->win_h * scale);
    for (int y = 0; y < ylimit; y += step) {
        const uint32_t *prow = sum + (size_t)y * istride, *qrow = sqsum ? sqsum + (size_t)y * istride : NULL;
        for (int x = 0; x < xlimit; x += step) {
            double weight;
            int r = run_window(e, prow + x, qrow ? qrow + x : NULL, &weight);
            if (r > 0 && push_box(out, (int)lrintf((float)x * scale), (int)lrintf((float)y * scale), ww, wh, weight))
                return -1;
            if (r == 0) x += step;
        }
    }
    return 0;
}

/* The scale factors OpenCV tries: window sizes rounded from the double factor, kept as floats. */
static size_t list_scales(const fr_cascade *c, int w, int h, double scale_factor, int min_w, int min_h, int max_w,
                          int max_h, float *scales, size_t cap) {
    size_t n = 0;
    for (double f = 1; n < cap; f *= scale_factor) {
        int ww = (int)lrint(c->win_w * f), wh = (int)lrint(c->win_h * f);
        if (ww > max_w || wh > max_h || ww > w || wh > h) break;
        if (ww < min_w || wh < min_h) continue;
        scales[n++] = (float)f;
    }
    return n;
}

typedef struct scratch {
    float *scales;
    uint8_t *level;
    uint32_t *ints, *sqsum, *tilt_scratch;
} scratch;

static void scratch_free(scratch *s) {
    free(s->scales);
    free(s->level);
    free(s->ints);
    free(s->sqsum);
    free(s->tilt_scratch);
}

static void clip_boxes(fr_cascade_box *b, size_t *n, int w, int h) {
    size_t k = 0;
    for (size_t i = 0; i < *n; i++) {
        int x0 = b[i].x > 0 ? b[i].x : 0, y0 = b[i].y > 0 ? b[i].y : 0;
        int x1 = b[i].x + b[i].w < w ? b[i].x + b[i].w : w, y1 = b[i].y + b[i].h < h ? b[i].y + b[i].h : h;
        if (x1 <= x0 || y1 <= y0) continue;
        b[k] = b[i];
        b[k].x = x0, b[k].y = y0, b[k].w = x1 - x0, b[k].h = y1 - y0;
        k++;
    }
    *n = k;
}

/* Levels' sizes and the y range OpenCV's stripes cover (stripe count from the first level's width). */
typedef struct level_geom {
    int sw, sh, xlimit, ylimit, step;
} level_geom;

static level_geom level_of(const fr_cascade *c, int w, int h, float scale, int nstripes) {
    level_geom g;
    g.sw = (int)lrintf((float)w / scale);
    g.sh = (int)lrintf((float)h / scale);
    g.step = scale >= 2.f ? 1 : 2;
    g.xlimit = g.sw + 1 - c->win_w > 0 ? g.sw + 1 - c->win_w : 0;
    int hw = g.sh + 1 - c->win_h > 0 ? g.sh + 1 - c->win_h : 0;
    if (nstripes <= 0) {
        g.ylimit = 0;
        return g;
    }
    int stripe = (hw / g.step + nstripes - 1) / nstripes;
    stripe = (stripe > 1 ? stripe : 1) * g.step;
    long cover = (long)nstripes * stripe;
    g.ylimit = cover < hw ? (int)cover : hw;
    return g;
}

static frig_status detect_levels(frig_ctx *ctx, const fr_cascade *c, const uint8_t *gray, int w, int h,
                                 size_t stride, const float *scales, size_t nscales, scratch *s, box_list *raw) {
    level_geom g0 = level_of(c, w, h, scales[0], 1);
    int nstripes = (int)ceil(g0.xlimit / 32.);
    int istride = g0.sw + 1;
    size_t plane = (size_t)istride * (size_t)(g0.sh + 1);
    if (plane * (c->has_tilted ? 2 : 1) > (size_t)0x7fffffff)
        return fr_error(ctx, FRIG_ERR_TOO_LARGE, "face detection: a %dx%d image is too large for the cascade", w, h);
    s->level = malloc((size_t)g0.sw * (size_t)g0.sh);
    s->ints = malloc(sizeof(uint32_t) * plane * (c->has_tilted ? 2 : 1));
    if (c->type == FR_CASCADE_HAAR) s->sqsum = malloc(sizeof(uint32_t) * plane);
    if (c->has_tilted) s->tilt_scratch = malloc(sizeof(uint32_t) * fr_cascade_tilted_scratch(g0.sw, g0.sh));
    if (!s->level || !s->ints || (c->type == FR_CASCADE_HAAR && !s->sqsum) || (c->has_tilted && !s->tilt_scratch))
        return fr_nomem(ctx, "face detection buffers");
    evaluator e;
    if (evaluator_init(&e, c, istride, (int)plane)) {
        evaluator_free(&e);
        return fr_nomem(ctx, "face detection features");
    }
    frig_status st = FRIG_OK;
    for (size_t i = 0; i < nscales && !st; i++) {
        st = fr_check_cancel(ctx, "face detection");
        if (st) break;
        level_geom g = level_of(c, w, h, scales[i], nstripes);
        if (g.sw <= 0 || g.sh <= 0) continue;
        if (fr_cascade_resize(gray, w, h, stride, s->level, g.sw, g.sh, (size_t)g.sw)) {
            st = fr_nomem(ctx, "a pyramid level");
            break;
        }
        fr_cascade_integral(s->level, g.sw, g.sh, (size_t)g.sw, s->ints, s->sqsum, (size_t)istride);
        if (c->has_tilted)
            fr_cascade_integral_tilted(s->level, g.sw, g.sh, (size_t)g.sw, s->ints + plane, (size_t)istride,
                                       s->tilt_scratch);
        if (scan_level(&e, s->ints, s->sqsum, istride, g.xlimit, g.ylimit, g.step, scales[i], raw))
            st = fr_nomem(ctx, "face candidates");
    }
    evaluator_free(&e);
    return st;
}

frig_status fr_cascade_detect(frig_ctx *ctx, const fr_cascade *c, const uint8_t *gray, int w, int h,
                              size_t stride, double scale_factor, int min_neighbors, int min_w, int min_h,
                              int max_w, int max_h, fr_cascade_box **boxes, size_t *count) {
    if (!boxes || !count) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "fr_cascade_detect: NULL output");
    *boxes = NULL;
    *count = 0;
    if (!c || !gray || w <= 0 || h <= 0 || stride < (size_t)w)
        return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "fr_cascade_detect: bad image (%dx%d, stride %zu)", w, h,
                        stride);
    if (!(scale_factor > 1.0001) || !isfinite(scale_factor))
        return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "face detection: scale factor %g should be over 1.0001",
                        scale_factor);
    if (max_w <= 0 || max_h <= 0) max_w = w, max_h = h;
    scratch s = {0};
    box_list raw = {0};
    size_t cap = 1 + (size_t)(log((double)(w > h ? w : h) + 1.) / log(scale_factor)) + 2;
    s.scales = malloc(sizeof(float) * cap);
    if (!s.scales) return fr_nomem(ctx, "face detection scales");
    size_t nscales = list_scales(c, w, h, scale_factor, min_w, min_h, max_w, max_h, s.scales, cap);
    frig_status st = nscales ? detect_levels(ctx, c, gray, w, h, stride, s.scales, nscales, &s, &raw) : FRIG_OK;
    scratch_free(&s);
    if (!st) {
        long n = fr_cascade_group(raw.v, raw.n, min_neighbors, GROUP_EPS);
        if (n < 0) st = fr_nomem(ctx, "face grouping");
        else raw.n = (size_t)n;
    }
    if (st) {
        free(raw.v);
        return st;
    }
    clip_boxes(raw.v, &raw.n, w, h);
    if (raw.n == 0) {
        free(raw.v);
        raw.v = NULL;
    }
    *boxes = raw.v;
    *count = raw.n;
    return FRIG_OK;
}
