/* Shoulders and clothing under the ICT head's cut-off neck, so synthetic photos show a person
 * rather than a floating head (the face detectors of paper section 4.2 were trained on such
 * photos). Rendered only: not part of the rig, the depth truth or the landmarks. A stack of
 * superellipse rings in the head's frame (metres), widening from the neck's base to the
 * shoulders, closed on top; posed by fr_synth_posed_vertices (half the head's turn). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "synth/synth.h"

#define RINGS 28
#define SEGMENTS 64
#define TOP_Y (-0.120)    /* the cap, around the neck above its flared base */
#define BOTTOM_Y (-0.900) /* far below any frame */
#define CENTRE_Z (-0.025)
#define EXPONENT 2.6      /* superellipse |x/a|^p + |z/c|^p = 1: a rounded box */

static double ring_y(int j) {
    double t = (double)j / (RINGS - 1);
    return TOP_Y + (BOTTOM_Y - TOP_Y) * t * t; /* rings crowd near the shoulders */
}

static void ring_radii(double y, const double shoulders[2], double *a, double *c) {
    double d = TOP_Y - y;
    *a = 0.105 + (shoulders[0] - 0.105) * (1.0 - exp(-d / 0.045));
    *c = 0.085 + (shoulders[1] - 0.085) * (1.0 - exp(-d / 0.06));
}

static double spow(double v, double e) { return v < 0.0 ? -pow(-v, e) : pow(v, e); }

frig_status fr_synth_torso(frig_ctx *ctx, frig_synth_subject *s, fr_rng *rng, float **xyz, int *nv, int32_t **tris,
                           int *nt) {
    int n_v = RINGS * SEGMENTS + 1, n_t = 2 * SEGMENTS * (RINGS - 1) + SEGMENTS;
    float *x = malloc(sizeof *x * 3 * (size_t)n_v);
    int32_t *t = malloc(sizeof *t * 3 * (size_t)n_t);
    if (!x || !t) {
        free(x), free(t);
        return fr_nomem(ctx, "the synthetic torso");
    }
    double shoulders[2] = {0.17 + 0.03 * fr_rng_uniform(rng), 0.095 + 0.02 * fr_rng_uniform(rng)};
    for (int j = 0; j < RINGS; j++) {
        double y = ring_y(j), a, c;
        ring_radii(y, shoulders, &a, &c);
        for (int i = 0; i < SEGMENTS; i++) {
            double th = 6.283185307179586 * i / SEGMENTS;
            float *p = x + 3 * (size_t)(j * SEGMENTS + i);
            p[0] = (float)(a * spow(cos(th), 2.0 / EXPONENT));
            p[1] = (float)y;
            p[2] = (float)(CENTRE_Z + c * spow(sin(th), 2.0 / EXPONENT));
        }
    }
    float *apex = x + 3 * (size_t)(RINGS * SEGMENTS);
    apex[0] = 0.0f, apex[1] = (float)(TOP_Y + 0.01), apex[2] = (float)CENTRE_Z;
    int k = 0;
    for (int j = 0; j + 1 < RINGS; j++)
        for (int i = 0; i < SEGMENTS; i++) {
            int32_t a = j * SEGMENTS + i, b = j * SEGMENTS + (i + 1) % SEGMENTS, c = a + SEGMENTS, d = b + SEGMENTS;
            /* outward, counter-clockwise seen from outside (theta runs from +x toward +z) */
            int32_t q[6] = {a, b, c, b, d, c};
            memcpy(t + 3 * (size_t)k, q, sizeof q);
            k += 2;
        }
    for (int i = 0; i < SEGMENTS; i++, k++) {
        int32_t q[3] = {RINGS * SEGMENTS, (i + 1) % SEGMENTS, i};
        memcpy(t + 3 * (size_t)k, q, sizeof q);
    }
    for (int c = 0; c < 3; c++) s->cloth_srgb[c] = 30.0 + 190.0 * fr_rng_uniform(rng);
    *xyz = x, *nv = n_v, *tris = t, *nt = n_t;
    return FRIG_OK;
}
