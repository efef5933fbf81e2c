/* Sums and layouts over mode sets, in blocks that stay in cache (see mode_sums.h). */
#include <string.h>

#include "model/mode_sums.h"

enum { SUM_BLOCK = 1024, VERTEX_BLOCK = 256 };

void fr_mode_sum(size_t n, const float *base, const float *modes, size_t stride, int count, const int *which,
                 const double *w, const float *add, float *out) {
    double v[SUM_BLOCK];
    for (size_t i0 = 0; i0 < n; i0 += SUM_BLOCK) {
        size_t len = n - i0 < SUM_BLOCK ? n - i0 : SUM_BLOCK;
        for (size_t i = 0; i < len; i++) v[i] = base ? base[i0 + i] : 0.0;
        for (int a = 0; a < count; a++) {
            int j = which ? which[a] : a;
            const float *d = modes + stride * (size_t)j + i0;
            for (size_t i = 0; i < len; i++) v[i] += w[j] * d[i];
        }
        for (size_t i = 0; i < len; i++) out[i0 + i] = (float)(add ? v[i] + add[i0 + i] : v[i]);
    }
}

void fr_modes_by_vertex(const float *modes, size_t nv, int k, float *out) {
    size_t nv3 = 3 * nv;
    for (size_t v0 = 0; v0 < nv; v0 += VERTEX_BLOCK)
        for (int j = 0; j < k; j++)
            for (size_t v = v0; v < nv && v < v0 + VERTEX_BLOCK; v++)
                memcpy(out + 3 * (v * (size_t)k + (size_t)j), modes + nv3 * (size_t)j + 3 * v, 3 * sizeof(float));
}
