/* Rig against true rig, over the face region (vertices 0 .. nf-1), the figures of the
 * retarget issue's table (docs/retarget.md):
 *   neutral_mm      mean per-vertex distance of the neutrals after the similarity transform
 *                   that best aligns them (section 7.2's E_B for one shape);
 *   neutral_raw_mm  the same without alignment (what a per-vertex scorer in the rig's frame sees);
 *   eb_mm           E_B: the aligned mean distance of every full shape (neutral + delta), averaged
 *                   over the shapes;
 *   delta_mm        the delta error over moving vertices: the mean |d - d_true| over every
 *                   (shape, face vertex) whose true delta moves it by more than MOVING_MM (as
 *                   bench/rig_error.c measures it);
 *   head_raw_mm, head_delta_mm: neutral_raw_mm and delta_mm over every vertex of the head (the
 *                   exported OBJ files' vertices) instead of the face region.
 * Shapes are matched by name; a shape the truth lacks is skipped. */
#ifndef BENCH_RIG_SCORE_H
#define BENCH_RIG_SCORE_H

#include <math.h>
#include <stdlib.h>

#include "eval/shape_error.h"
#include "frig/frig.h"

#define MOVING_MM 0.1

typedef struct rig_score {
    double neutral_mm, neutral_raw_mm, eb_mm, delta_mm;
    double head_raw_mm, head_delta_mm; /* the same, raw, over every vertex of the head */
    int shapes;
} rig_score;

static inline double raw_mean_distance(const float *a, const float *b, int n) {
    double s = 0;
    for (int v = 0; v < n; v++) {
        double d = 0;
        for (int k = 0; k < 3; k++) d += (a[3 * v + k] - b[3 * v + k]) * (a[3 * v + k] - b[3 * v + k]);
        s += sqrt(d);
    }
    return s / n;
}

/* neutral and deltas of ours given as arrays (deltas: shape by name through names[]). */
static inline rig_score rig_score_arrays(const frig_rig *truth, const float *neutral, int nshape, const char *const *names,
                                  const float *const *deltas, int nf) {
    rig_score r = {0, 0, 0, 0, 0, 0, 0};
    int nv = frig_rig_vertex_count(truth);
    double pooled = 0, hpooled = 0;
    long n_pooled = 0, n_hpooled = 0;
    const float *tn = frig_rig_neutral(truth);
    r.neutral_mm = 1e3 * fr_aligned_mean_distance(tn, neutral, nf);
    r.neutral_raw_mm = 1e3 * raw_mean_distance(tn, neutral, nf);
    r.head_raw_mm = 1e3 * raw_mean_distance(tn, neutral, nv);
    float *a = malloc(sizeof(float) * 3 * nf), *b = malloc(sizeof(float) * 3 * nf);
    for (int j = 0; j < nshape; j++) {
        int t = frig_rig_shape_find(truth, names[j]);
        if (t < 0) continue;
        const float *td = frig_rig_shape_deltas(truth, t), *od = deltas[j];
        double err = 0, herr = 0;
        int moving = 0, hmoving = 0;
        for (int v = nf; v < nv; v++) {
            double m = 0, e = 0;
            for (int k = 0; k < 3; k++) {
                m += td[3 * v + k] * td[3 * v + k];
                e += (td[3 * v + k] - od[3 * v + k]) * (td[3 * v + k] - od[3 * v + k]);
            }
            if (sqrt(m) > 1e-3 * MOVING_MM) herr += sqrt(e), hmoving++;
        }
        for (int v = 0; v < nf; v++) {
            double m = 0, e = 0;
            for (int k = 0; k < 3; k++) {
                m += td[3 * v + k] * td[3 * v + k];
                e += (td[3 * v + k] - od[3 * v + k]) * (td[3 * v + k] - od[3 * v + k]);
                a[3 * v + k] = tn[3 * v + k] + td[3 * v + k];
                b[3 * v + k] = neutral[3 * v + k] + od[3 * v + k];
            }
            if (sqrt(m) > 1e-3 * MOVING_MM) err += sqrt(e), moving++;
        }
        r.eb_mm += 1e3 * fr_aligned_mean_distance(a, b, nf);
        pooled += err, n_pooled += moving;
        hpooled += err + herr, n_hpooled += moving + hmoving;
        r.shapes++;
    }
    if (r.shapes) r.eb_mm /= r.shapes;
    r.delta_mm = n_pooled ? 1e3 * pooled / n_pooled : NAN;
    r.head_delta_mm = n_hpooled ? 1e3 * hpooled / n_hpooled : NAN;
    free(a), free(b);
    return r;
}

static inline rig_score rig_score_rig(const frig_rig *truth, const frig_rig *rig, int nf) {
    int n = frig_rig_shape_count(rig);
    const char **names = malloc(sizeof(char *) * (n + 1));
    const float **d = malloc(sizeof(float *) * (n + 1));
    for (int j = 0; j < n; j++) names[j] = frig_rig_shape_name(rig, j), d[j] = frig_rig_shape_deltas(rig, j);
    rig_score r = rig_score_arrays(truth, frig_rig_neutral(rig), n, names, d, nf);
    free(names), free(d);
    return r;
}

#endif
