/* The model's UV space (paper Algorithm 5, "ComputeMeanTexture"): the face triangles drawn in
 * texture space with the rasterizer (each texel gets one triangle and its barycentrics), and
 * the texel <-> photo correspondences through a view's render. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "core/floor_int.h"
#include "raster/raster.h"
#include "sfs/sfs_uv.h"

void fr_sfs_uv_free(fr_sfs_uv *uv) {
    free(uv->texel), free(uv->tri), free(uv->bary), free(uv->index);
    memset(uv, 0, sizeof *uv);
}

frig_status fr_sfs_uv_init(frig_ctx *ctx, const fr_sfs_mesh *m, int T, fr_sfs_uv *uv) {
    memset(uv, 0, sizeof *uv);
    uv->size = T;
    int nf = 0;
    for (int t = 0; t < m->nt; t++) nf += m->face[t];
    /* one unwelded vertex per corner, at its texel coordinates; the rasterizer's weak camera
     * with scale 1 puts (x, y) at pixel (x, y) */
    float *xyz = malloc(sizeof(float) * 9 * (size_t)nf);
    int32_t *tris = malloc(sizeof(int32_t) * 3 * (size_t)nf), *drawn = malloc(sizeof(int32_t) * (size_t)nf);
    fr_raster *r = NULL;
    frig_status s = !xyz || !tris || !drawn ? fr_nomem(ctx, "the UV raster") : FRIG_OK;
    int k = 0;
    for (int t = 0; t < m->nt && !s; t++) {
        if (!m->face[t]) continue;
        for (int c = 0; c < 3; c++) {
            const float *u = m->uvs + 2 * (size_t)m->tri_uv[3 * (size_t)t + c];
            xyz[9 * (size_t)k + 3 * c] = (float)(u[0] * T - 0.5);
            xyz[9 * (size_t)k + 3 * c + 1] = (float)((1.0 - u[1]) * T - 0.5);
            xyz[9 * (size_t)k + 3 * c + 2] = 1.0f;
            tris[3 * (size_t)k + c] = 3 * k + c;
        }
        drawn[k++] = t;
    }
    if (!s) s = fr_raster_create(ctx, T, T, &r);
    fr_camera cam = fr_camera_weak(1.0, 1, 1);
    cam.cx = cam.cy = 0.0;
    if (!s) s = fr_raster_render(ctx, r, &cam, xyz, 3 * nf, tris, nf, NULL);
    size_t n = (size_t)T * T;
    if (!s) {
        uv->index = malloc(sizeof(int32_t) * n);
        uv->texel = malloc(sizeof(int32_t) * n);
        uv->tri = malloc(sizeof(int32_t) * n);
        uv->bary = malloc(sizeof(float) * 3 * n);
        if (!uv->index || !uv->texel || !uv->tri || !uv->bary) s = fr_nomem(ctx, "the UV raster");
    }
    for (size_t i = 0; i < n && !s; i++) {
        uv->index[i] = -1;
        if (r->tri[i] < 0) continue;
        uv->index[i] = uv->count;
        uv->texel[uv->count] = (int32_t)i;
        uv->tri[uv->count] = drawn[r->tri[i]];
        memcpy(uv->bary + 3 * (size_t)uv->count, r->bary + 3 * i, sizeof(float) * 3);
        uv->count++;
    }
    fr_raster_free(r);
    free(xyz), free(tris), free(drawn);
    if (s) fr_sfs_uv_free(uv);
    return s;
}

int fr_sfs_uv_locate(const fr_sfs_uv *uv, const fr_sfs_mesh *m, const fr_sfs_view *v, int k, double tol,
                     double xy[2], double *depth) {
    int t = uv->tri[k];
    const float *b = uv->bary + 3 * (size_t)k;
    double X[3] = {0, 0, 0};
    for (int c = 0; c < 3; c++) {
        const float *p = v->xyz_cam + 3 * (size_t)m->tris[3 * (size_t)t + c];
        for (int j = 0; j < 3; j++) X[j] += b[c] * p[j];
    }
    if (!fr_camera_project(&v->cam, X, xy)) return 0;
    int px = fr_floor_int(xy[0] + 0.5), py = fr_floor_int(xy[1] + 0.5);
    if (px < 0 || py < 0 || px >= v->w || py >= v->h) return 0;
    size_t i = (size_t)py * v->w + px;
    if (depth) *depth = X[2];
    if (v->tri[i] == t) return 1;
    if (v->tri[i] < 0 || !(v->zbuf[i] > 0)) return 0;
    return X[2] <= v->zbuf[i] + tol;
}

int fr_sfs_uv_at_pixel(const fr_sfs_mesh *m, const fr_sfs_view *v, size_t i, double out[2]) {
    int t = v->tri[i];
    if (t < 0 || !m->face[t]) return 0;
    const float *b = v->bary + 3 * i;
    out[0] = out[1] = 0;
    for (int c = 0; c < 3; c++) {
        const float *u = m->uvs + 2 * (size_t)m->tri_uv[3 * (size_t)t + c];
        out[0] += b[c] * u[0], out[1] += b[c] * u[1];
    }
    return 1;
}

int fr_sfs_texture_sample(const float *tex, const float *weight, int T, int dim, const double uv[2], float *out) {
    double x = uv[0] * T - 0.5, y = (1.0 - uv[1]) * T - 0.5;
    int x0 = fr_floor_int(x), y0 = fr_floor_int(y);
    double fx = x - x0, fy = y - y0, acc[8] = {0}, wsum = 0;
    for (int j = 0; j < 2; j++)
        for (int i = 0; i < 2; i++) {
            int xx = x0 + i, yy = y0 + j;
            if (xx < 0 || yy < 0 || xx >= T || yy >= T) continue;
            size_t q = (size_t)yy * T + xx;
            if (weight && !(weight[q] > 0)) continue;
            double w = (i ? fx : 1 - fx) * (j ? fy : 1 - fy);
            if (!(w > 0)) continue;
            for (int d = 0; d < dim && d < 8; d++) acc[d] += w * tex[(size_t)dim * q + d];
            wsum += w;
        }
    if (!(wsum > 1e-9)) return 0;
    for (int d = 0; d < dim && d < 8; d++) out[d] = (float)(acc[d] / wsum);
    return 1;
}

void fr_sfs_image_gradient(const float *img, int w, int h, const double xy[2], double gx[3], double gy[3]) {
    double a[3], b[3], xa[2] = {xy[0] + 1, xy[1]}, xb[2] = {xy[0] - 1, xy[1]};
    fr_bilinear3(img, w, h, xa, a), fr_bilinear3(img, w, h, xb, b);
    for (int c = 0; c < 3; c++) gx[c] = 0.5 * (a[c] - b[c]);
    xa[0] = xb[0] = xy[0], xa[1] = xy[1] + 1, xb[1] = xy[1] - 1;
    fr_bilinear3(img, w, h, xa, a), fr_bilinear3(img, w, h, xb, b);
    for (int c = 0; c < 3; c++) gy[c] = 0.5 * (a[c] - b[c]);
}
