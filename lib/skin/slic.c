/* SLIC superpixels (Achanta et al. 2012): seeds on a grid of step S moved to the lowest
 * gradient of their 3 x 3 neighbourhood, then k-means where each centre only competes for the
 * pixels of its 2S x 2S window, distance d_lab^2 + (m / S)^2 d_xy^2; finally pieces not
 * connected to their segment's largest part are merged into a neighbour. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "image/srgb.h"
#include "skin/slic.h"

static double lab_f(double t) { return t > 0.008856451679 ? cbrt(t) : 7.787037037 * t + 16.0 / 116.0; }

void fr_srgb8_to_lab(const uint8_t rgb[3], float lab[3]) {
    double r = fr_srgb_to_linear(rgb[0] / 255.0), g = fr_srgb_to_linear(rgb[1] / 255.0),
           b = fr_srgb_to_linear(rgb[2] / 255.0);
    double X = (0.4124564 * r + 0.3575761 * g + 0.1804375 * b) / 0.95047;
    double Y = 0.2126729 * r + 0.7151522 * g + 0.0721750 * b;
    double Z = (0.0193339 * r + 0.1191920 * g + 0.9503041 * b) / 1.08883;
    double fx = lab_f(X), fy = lab_f(Y), fz = lab_f(Z);
    lab[0] = (float)(116.0 * fy - 16.0);
    lab[1] = (float)(500.0 * (fx - fy));
    lab[2] = (float)(200.0 * (fy - fz));
}

typedef struct centre {
    double l, a, b, x, y;
} centre;

static double gradient_at(const float *lab, int w, int h, int x, int y) {
    if (x < 1 || y < 1 || x >= w - 1 || y >= h - 1) return INFINITY;
    double g = 0;
    for (int c = 0; c < 3; c++) {
        double dx = lab[3 * ((size_t)y * w + x + 1) + c] - lab[3 * ((size_t)y * w + x - 1) + c];
        double dy = lab[3 * ((size_t)(y + 1) * w + x) + c] - lab[3 * ((size_t)(y - 1) * w + x) + c];
        g += dx * dx + dy * dy;
    }
    return g;
}

/* Label connected pieces in scan order; a piece smaller than 'min_size' joins the piece met
 * just before it (its left or upper neighbour). 'list' holds width * height ints. */
static int enforce_connectivity(const int32_t *labels, int w, int h, int min_size, int32_t *out, int *list) {
    size_t n = (size_t)w * h;
    for (size_t i = 0; i < n; i++) out[i] = -1;
    static const int dx[4] = {-1, 0, 1, 0}, dy[4] = {0, -1, 0, 1};
    int next = 0;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            size_t i = (size_t)y * w + x;
            if (out[i] >= 0) continue;
            int adjacent = -1;
            for (int d = 0; d < 2; d++) {
                int xx = x + dx[d], yy = y + dy[d];
                if (xx >= 0 && yy >= 0 && out[(size_t)yy * w + xx] >= 0) adjacent = out[(size_t)yy * w + xx];
            }
            int size = 0;
            list[size++] = (int)i;
            out[i] = next;
            for (int head = 0; head < size; head++) {
                int p = list[head], px = p % w, py = p / w;
                for (int d = 0; d < 4; d++) {
                    int xx = px + dx[d], yy = py + dy[d];
                    if (xx < 0 || yy < 0 || xx >= w || yy >= h) continue;
                    size_t q = (size_t)yy * w + xx;
                    if (out[q] < 0 && labels[q] == labels[i]) out[q] = next, list[size++] = (int)q;
                }
            }
            if (size < min_size && adjacent >= 0) {
                for (int k = 0; k < size; k++) out[list[k]] = adjacent;
            } else {
                next++;
            }
        }
    return next;
}

frig_status fr_slic(frig_ctx *ctx, const float *lab, int w, int h, int step, double m, int iterations,
                    int32_t *labels, int *count) {
    *count = 0;
    if (step < 2) step = 2;
    int gx = (w + step - 1) / step, gy = (h + step - 1) / step, k = gx * gy;
    size_t n = (size_t)w * h;
    centre *c = malloc(sizeof *c * (size_t)k);
    double *dist = malloc(sizeof *dist * n);
    double *acc = malloc(sizeof *acc * 6 * (size_t)k);
    int32_t *tmp = malloc(sizeof *tmp * n);
    int *stack = malloc(sizeof *stack * (n + 1));
    if (!c || !dist || !acc || !tmp || !stack) {
        free(c), free(dist), free(acc), free(tmp), free(stack);
        return fr_nomem(ctx, "superpixels");
    }
    for (int j = 0; j < gy; j++)
        for (int i = 0; i < gx; i++) {
            int x = i * step + step / 2, y = j * step + step / 2;
            if (x >= w) x = w - 1;
            if (y >= h) y = h - 1;
            int bx = x, by = y;
            double bg = gradient_at(lab, w, h, x, y);
            for (int dy = -1; dy <= 1; dy++)
                for (int dx = -1; dx <= 1; dx++) {
                    double g = gradient_at(lab, w, h, x + dx, y + dy);
                    if (g < bg) bg = g, bx = x + dx, by = y + dy;
                }
            const float *p = lab + 3 * ((size_t)by * w + bx);
            c[j * gx + i] = (centre){p[0], p[1], p[2], bx, by};
        }
    double inv_s2 = (m / step) * (m / step);
    for (int it = 0; it < iterations; it++) {
        for (size_t i = 0; i < n; i++) dist[i] = INFINITY, labels[i] = 0;
        for (int q = 0; q < k; q++) {
            int x0 = (int)floor(c[q].x - step), x1 = (int)ceil(c[q].x + step);
            int y0 = (int)floor(c[q].y - step), y1 = (int)ceil(c[q].y + step);
            if (x0 < 0) x0 = 0;
            if (y0 < 0) y0 = 0;
            if (x1 > w - 1) x1 = w - 1;
            if (y1 > h - 1) y1 = h - 1;
            for (int y = y0; y <= y1; y++)
                for (int x = x0; x <= x1; x++) {
                    size_t i = (size_t)y * w + x;
                    const float *p = lab + 3 * i;
                    double dl = p[0] - c[q].l, da = p[1] - c[q].a, db = p[2] - c[q].b;
                    double ddx = x - c[q].x, ddy = y - c[q].y;
                    double d = dl * dl + da * da + db * db + inv_s2 * (ddx * ddx + ddy * ddy);
                    if (d < dist[i]) dist[i] = d, labels[i] = q; /* ties: the lower centre index */
                }
        }
        memset(acc, 0, sizeof *acc * 6 * (size_t)k);
        for (int y = 0; y < h; y++)
            for (int x = 0; x < w; x++) {
                size_t i = (size_t)y * w + x;
                double *a = acc + 6 * (size_t)labels[i];
                const float *p = lab + 3 * i;
                a[0] += p[0], a[1] += p[1], a[2] += p[2], a[3] += x, a[4] += y, a[5] += 1;
            }
        for (int q = 0; q < k; q++) {
            const double *a = acc + 6 * (size_t)q;
            if (a[5] > 0) c[q] = (centre){a[0] / a[5], a[1] / a[5], a[2] / a[5], a[3] / a[5], a[4] / a[5]};
        }
    }
    int min_size = step * step / 4;
    *count = enforce_connectivity(labels, w, h, min_size, tmp, stack);
    memcpy(labels, tmp, sizeof *labels * n);
    free(c), free(dist), free(acc), free(tmp), free(stack);
    return FRIG_OK;
}
