/* Similarity Procrustes in 2D by complex least squares: with centred points as complex numbers,
 * the best q ~ z p has z = <p, q> / <p, p> (no reflection). Generalized Procrustes alternates
 * aligning every shape to the mean and re-estimating the mean (Gower 1975). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "filter/procrustes.h"

static void centroid(int n, const double *p, double c[2]) {
    c[0] = c[1] = 0;
    for (int i = 0; i < n; i++) c[0] += p[2 * i], c[1] += p[2 * i + 1];
    c[0] /= n;
    c[1] /= n;
}

void fr_similarity_fit(int n, const double *p, const double *q, double T[4]) {
    double cp[2], cq[2];
    centroid(n, p, cp);
    centroid(n, q, cq);
    double pp = 0, re = 0, im = 0;
    for (int i = 0; i < n; i++) {
        double px = p[2 * i] - cp[0], py = p[2 * i + 1] - cp[1];
        double qx = q[2 * i] - cq[0], qy = q[2 * i + 1] - cq[1];
        pp += px * px + py * py;
        re += px * qx + py * qy; /* conj(p) q */
        im += px * qy - py * qx;
    }
    double a = pp > 0 ? re / pp : 1, b = pp > 0 ? im / pp : 0;
    T[0] = a;
    T[1] = b;
    T[2] = cq[0] - (a * cp[0] - b * cp[1]);
    T[3] = cq[1] - (b * cp[0] + a * cp[1]);
}

void fr_similarity_apply(int n, const double T[4], const double *p, double *out) {
    for (int i = 0; i < n; i++) {
        double x = p[2 * i], y = p[2 * i + 1];
        out[2 * i] = T[0] * x - T[1] * y + T[2];
        out[2 * i + 1] = T[1] * x + T[0] * y + T[3];
    }
}

void fr_similarity_invert(const double T[4], double inv[4]) {
    double d = T[0] * T[0] + T[1] * T[1];
    double a = d > 0 ? T[0] / d : 1, b = d > 0 ? -T[1] / d : 0;
    inv[0] = a;
    inv[1] = b;
    inv[2] = -(a * T[2] - b * T[3]);
    inv[3] = -(b * T[2] + a * T[3]);
}

static void align_to(int n, const double *p, const double *target, double *out) {
    double T[4];
    fr_similarity_fit(n, p, target, T);
    fr_similarity_apply(n, T, p, out);
}

frig_status fr_procrustes_align(frig_ctx *ctx, int n, int count, const double *shapes, const double *gauge,
                                double *aligned, double *mean, int *iterations) {
    if (iterations) *iterations = 0;
    if (n < 2 || count < 1)
        return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "Procrustes of %d shapes of %d points", count, n);
    size_t len = 2 * (size_t)n;
    double *next = malloc(sizeof(double) * len);
    if (!next) return fr_nomem(ctx, "a mean shape");
    double size = 0, gc[2];
    centroid(n, gauge, gc);
    for (int i = 0; i < n; i++) size += pow(gauge[2 * i] - gc[0], 2) + pow(gauge[2 * i + 1] - gc[1], 2);
    size = sqrt(size);
    memcpy(mean, gauge, sizeof(double) * len);
    int iter = 0;
    while (iter < 100) {
        iter++;
        for (int s = 0; s < count; s++) align_to(n, shapes + len * s, mean, aligned + len * s);
        memset(next, 0, sizeof(double) * len);
        for (int s = 0; s < count; s++)
            for (size_t k = 0; k < len; k++) next[k] += aligned[len * s + k];
        for (size_t k = 0; k < len; k++) next[k] /= count;
        align_to(n, next, gauge, next);
        double moved = 0;
        for (size_t k = 0; k < len; k++) moved += (next[k] - mean[k]) * (next[k] - mean[k]);
        memcpy(mean, next, sizeof(double) * len);
        if (sqrt(moved) <= 1e-12 * size) {
            for (int s = 0; s < count; s++) align_to(n, shapes + len * s, mean, aligned + len * s);
            break;
        }
    }
    free(next);
    if (iterations) *iterations = iter;
    return FRIG_OK;
}
