/* A synthetic subject's own blendshapes (paper section 7.2, E_B against true blendshapes):
 * each template delta d_j becomes d_j' = (1 + a_j) d_j + s_j with |a_j| <= 0.25 and s_j a
 * smooth field proportional to |d_j| (so it lives where d_j moves), small relative to d_j,
 * zero on the eyeballs, teeth and gums and calmed near the eyes so lids stay on the eyeballs. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "model/model.h"
#include "synth/synth.h"

#define SCALE_MAX 0.25      /* |a_j| */
#define CLOSING_MAX 0.05    /* closing shapes (blinks, mouthClose) and eye turns may not grow more than
                             * this: lids would cross, linear eyeball turns would push through lids */
#define FIELD_BUMPS 3
#define FIELD_AMPLITUDE 0.25 /* per bump, relative to |d_j| */
#define MOVING 0.02          /* a vertex moves when |d_j| > this share of the largest */
#define EYE_CALM_IN 0.014
#define EYE_CALM_OUT 0.024

static int is_limited(const char *name) {
    return strncmp(name, "eyeBlink", 8) == 0 || strncmp(name, "eyeLook", 7) == 0 || strcmp(name, "mouthClose") == 0;
}

static double norm3f(const float *v) { return sqrt((double)v[0] * v[0] + (double)v[1] * v[1] + (double)v[2] * v[2]); }

/* A vertex of class skin drawn with probability proportional to |d|. */
static int pick_weighted(const float *d, const uint8_t *cls, int nv, double total, fr_rng *rng) {
    double u = fr_rng_uniform(rng) * total, acc = 0.0;
    int last = 0;
    for (int v = 0; v < nv; v++) {
        if (cls[v] != FR_SYNTH_SKIN) continue;
        acc += norm3f(d + 3 * (size_t)v);
        last = v;
        if (acc > u) return v;
    }
    return last;
}

static void draw_field(const float *d, const float *neutral, const uint8_t *cls, int nv, fr_rng *rng, fr_bump *b) {
    double total = 0.0;
    for (int v = 0; v < nv; v++)
        if (cls[v] == FR_SYNTH_SKIN) total += norm3f(d + 3 * (size_t)v);
    for (int k = 0; k < FIELD_BUMPS; k++) {
        int v = pick_weighted(d, cls, nv, total, rng);
        double dir[3], len = 0.0;
        for (int i = 0; i < 3; i++) {
            b[k].c[i] = neutral[3 * (size_t)v + i];
            dir[i] = fr_rng_normal(rng);
            len += dir[i] * dir[i];
        }
        len = sqrt(len);
        b[k].r = 0.01 + 0.02 * fr_rng_uniform(rng);
        double a = FIELD_AMPLITUDE * (2.0 * fr_rng_uniform(rng) - 1.0);
        for (int i = 0; i < 3; i++) b[k].v[i] = len > 0.0 ? a * dir[i] / len : 0.0;
    }
}

/* Change one shape in place; returns RMS(s_j) / RMS(d_j) over the vertices d_j moves. */
static double perturb_one(float *d, const float *neutral, const uint8_t *cls, int nv, const double eye[2][3],
                          double a, const fr_bump *b) {
    double dmax = 0.0;
    for (int v = 0; v < nv; v++) dmax = fmax(dmax, norm3f(d + 3 * (size_t)v));
    double es = 0.0, ed = 0.0;
    for (int v = 0; v < nv; v++) {
        float *dv = d + 3 * (size_t)v;
        double m = norm3f(dv), f[3] = {0, 0, 0};
        if (cls[v] == FR_SYNTH_SKIN || cls[v] == FR_SYNTH_OVERLAY) {
            const float *x = neutral + 3 * (size_t)v;
            double p[3] = {x[0], x[1], x[2]}, calm = 1.0;
            fr_bumps_eval(b, FIELD_BUMPS, p, f);
            for (int e = 0; e < 2; e++) {
                double dx = p[0] - eye[e][0], dy = p[1] - eye[e][1], dz = p[2] - eye[e][2];
                calm = fmin(calm, fr_smoothstep(EYE_CALM_IN, EYE_CALM_OUT, sqrt(dx * dx + dy * dy + dz * dz)));
            }
            for (int i = 0; i < 3; i++) f[i] *= calm * m;
        }
        if (m > MOVING * dmax) {
            es += f[0] * f[0] + f[1] * f[1] + f[2] * f[2];
            ed += m * m;
        }
        for (int i = 0; i < 3; i++) dv[i] = (float)((1.0 + a) * dv[i] + f[i]);
    }
    return ed > 0.0 ? sqrt(es / ed) : 0.0;
}

frig_status fr_synth_perturb_expressions(frig_ctx *ctx, const frig_model *model, frig_synth_subject *s, fr_rng *rng,
                                         const float *neutral, float *deltas) {
    int nv = model->topo.vertex_count, ns = model->expression_count;
    uint8_t *cls = fr_synth_vertex_classes(model);
    if (!cls) return fr_nomem(ctx, "the expression changes");
    double eye[2][3];
    fr_synth_region_centroid(model, "eyeball_left", neutral, eye[0]);
    fr_synth_region_centroid(model, "eyeball_right", neutral, eye[1]);
    for (int j = 0; j < ns; j++) {
        double hi = is_limited(model->expression_names[j]) ? CLOSING_MAX : SCALE_MAX;
        double a = -SCALE_MAX + (hi + SCALE_MAX) * fr_rng_uniform(rng);
        fr_bump b[FIELD_BUMPS];
        float *d = deltas + 3 * (size_t)nv * (size_t)j;
        draw_field(d, neutral, cls, nv, rng, b);
        s->shape_scale[j] = a;
        s->shape_field_rel[j] = perturb_one(d, neutral, cls, nv, eye, a, b);
    }
    free(cls);
    return FRIG_OK;
}
