/* Hard cast shadows of a synthetic photo's key light (what paper section 5.1.3's region
 * selection must find: "hard shadows ... will make the algorithm fail"): a shadow map, the
 * scene's depth along the light's direction of travel rendered orthographically by libfrig's
 * rasterizer, and percentage-closer filtering of a 3x3 texel neighbourhood. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "synth/synth.h"

#define BIAS_METRES 0.0015 /* depth behind the nearest surface still lit (acne on smooth skin) */
#define BIAS_TEXELS 1.5    /* plus this many texels' worth, for slopes */

static void cross(const double a[3], const double b[3], double c[3]) {
    c[0] = a[1] * b[2] - a[2] * b[1], c[1] = a[2] * b[0] - a[0] * b[2], c[2] = a[0] * b[1] - a[1] * b[0];
}

static void normalize(double v[3]) {
    double n = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    for (int i = 0; i < 3; i++) v[i] /= n;
}

static double dot(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

frig_status fr_synth_shadow_map(frig_ctx *ctx, const float *xyz, int nv, const int32_t *tris, int nt,
                                const double light_dir[3], int size, fr_shadow_map *m) {
    memset(m, 0, sizeof *m);
    m->size = size;
    for (int i = 0; i < 3; i++) m->w[i] = -light_dir[i];
    normalize(m->w);
    double up[3] = {0, 1, 0};
    if (fabs(m->w[1]) > 0.9) up[0] = 1, up[1] = 0;
    cross(up, m->w, m->u);
    normalize(m->u);
    cross(m->w, m->u, m->v);
    float *lx = malloc(sizeof *lx * 3 * (size_t)(nv > 0 ? nv : 1));
    if (!lx) return fr_nomem(ctx, "the shadow map");
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (int k = 0; k < nv; k++) {
        double X[3] = {xyz[3 * (size_t)k], xyz[3 * (size_t)k + 1], xyz[3 * (size_t)k + 2]};
        double a = dot(X, m->u), b = dot(X, m->v);
        lx[3 * (size_t)k] = (float)a, lx[3 * (size_t)k + 1] = (float)b, lx[3 * (size_t)k + 2] = (float)dot(X, m->w);
        lo[0] = fmin(lo[0], a), hi[0] = fmax(hi[0], a), lo[1] = fmin(lo[1], b), hi[1] = fmax(hi[1], b);
    }
    double extent = fmax(fmax(hi[0] - lo[0], hi[1] - lo[1]), 1e-6);
    m->scale = (size - 4) / extent;
    m->ou = 2.0 - m->scale * lo[0];
    m->ov = 2.0 - m->scale * lo[1];
    fr_camera cam = fr_camera_weak(m->scale, size, size);
    cam.cx = m->ou, cam.cy = m->ov;
    frig_status st = fr_raster_create(ctx, size, size, &m->r);
    if (!st) st = fr_raster_render(ctx, m->r, &cam, lx, nv, tris, nt, NULL);
    free(lx);
    if (st) fr_synth_shadow_map_free(m);
    return st;
}

void fr_synth_shadow_map_free(fr_shadow_map *m) {
    fr_raster_free(m->r);
    m->r = NULL;
}

double fr_synth_shadow_visibility(const fr_shadow_map *m, const double X[3]) {
    double tx = m->scale * dot(X, m->u) + m->ou, ty = m->scale * dot(X, m->v) + m->ov, d = dot(X, m->w);
    double bias = BIAS_METRES + BIAS_TEXELS / m->scale;
    int x0 = (int)lround(tx), y0 = (int)lround(ty), lit = 0;
    for (int j = -1; j <= 1; j++)
        for (int i = -1; i <= 1; i++) {
            int x = x0 + i, y = y0 + j;
            if (x < 0 || y < 0 || x >= m->size || y >= m->size) {
                lit++;
                continue;
            }
            float z = m->r->depth[(size_t)y * (size_t)m->size + (size_t)x];
            if (!(z < d - bias)) lit++;
        }
    return lit / 9.0;
}
