/* Pull-push filling of an image's unknown pixels (Gortler et al. 1996, section 3.4): the known
 * pixels averaged into a pyramid of half-size levels, each level's pixel weighing min(1, the sum of
 * its children's weights); then, from the coarsest level down, a pixel that weighs less than 1
 * takes the rest of its colour from the coarser level's colour, sampled bilinearly at its centre.
 * Smooth where a ring-by-ring growth of the known pixels leaves streaks. */
#include "image/pull_push.h"

#include <stdlib.h>

#include "image/bilinear.h"

typedef struct level {
    int w, h;
    float *rgb, *wt;
} level;

/* Level from its finer one: each pixel the weighted mean of its (up to) 2 x 2 children. */
static void pull(const level *f, level *c) {
    for (int y = 0; y < c->h; y++)
        for (int x = 0; x < c->w; x++) {
            double acc[3] = {0, 0, 0}, ws = 0;
            for (int dy = 0; dy < 2; dy++)
                for (int dx = 0; dx < 2; dx++) {
                    int fx = 2 * x + dx, fy = 2 * y + dy;
                    if (fx >= f->w || fy >= f->h) continue;
                    size_t i = (size_t)fy * f->w + fx;
                    double wi = f->wt[i];
                    if (!(wi > 0)) continue;
                    for (int k = 0; k < 3; k++) acc[k] += wi * f->rgb[3 * i + k];
                    ws += wi;
                }
            size_t o = (size_t)y * c->w + x;
            for (int k = 0; k < 3; k++) c->rgb[3 * o + k] = ws > 0 ? (float)(acc[k] / ws) : 0.0f;
            c->wt[o] = (float)(ws < 1 ? ws : 1);
        }
}

/* Level's pixels that weigh less than 1 completed from the (complete) coarser level. */
static void push(level *f, const level *c) {
    for (int y = 0; y < f->h; y++)
        for (int x = 0; x < f->w; x++) {
            size_t i = (size_t)y * f->w + x;
            double wi = f->wt[i];
            if (wi >= 1) continue;
            double xy[2] = {0.5 * (x + 0.5) - 0.5, 0.5 * (y + 0.5) - 0.5}, up[3];
            fr_bilinear3(c->rgb, c->w, c->h, xy, up);
            for (int k = 0; k < 3; k++) f->rgb[3 * i + k] = (float)(wi * f->rgb[3 * i + k] + (1 - wi) * up[k]);
            f->wt[i] = 1;
        }
}

int fr_pull_push(float *img, const uint8_t *known, int w, int h) {
    if (w <= 0 || h <= 0) return 0;
    int n = 1;
    for (int a = w, b = h; a > 1 || b > 1; a = (a + 1) / 2, b = (b + 1) / 2) n++;
    level *L = calloc((size_t)n, sizeof *L);
    int ok = L != NULL;
    for (int l = 0, a = w, b = h; ok && l < n; l++, a = (a + 1) / 2, b = (b + 1) / 2) {
        L[l].w = a, L[l].h = b;
        L[l].rgb = l ? malloc(sizeof(float) * 3 * (size_t)a * b) : img; /* the finest level is the image */
        L[l].wt = malloc(sizeof(float) * (size_t)a * b);
        ok = L[l].rgb && L[l].wt;
    }
    int result = ok ? 1 : -1;
    if (ok) {
        size_t np = (size_t)w * h;
        for (size_t i = 0; i < np; i++) L[0].wt[i] = known[i] ? 1.0f : 0.0f;
        for (int l = 1; l < n; l++) pull(&L[l - 1], &L[l]);
        if (!(L[n - 1].wt[0] > 0)) result = 0;
        else {
            L[n - 1].wt[0] = 1;
            for (int l = n - 2; l >= 0; l--) push(&L[l], &L[l + 1]);
        }
    }
    for (int l = 0; L && l < n; l++) {
        if (l) free(L[l].rgb);
        free(L[l].wt);
    }
    free(L);
    return result;
}
