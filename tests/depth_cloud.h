/* Point clouds from a rendered depth map (frig synth's truth), for the retarget stage's tests
 * and bench/truth_clouds: the face pixels of a rig rendered at a pose, unprojected, with normals
 * from the neighbouring pixels, moved into the head frame. */
#ifndef FRIG_TESTS_DEPTH_CLOUD_H
#define FRIG_TESTS_DEPTH_CLOUD_H

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "frig/frig.h"
#include "raster/raster.h"
#include "rig/rig.h"

#define DEPTH_CLOUD_FACE 9409     /* ICT's face region, 0 .. 9408 */
#define DEPTH_CLOUD_EDGE 0.02     /* metres of depth between a pixel's neighbours: an occluding edge */

/* Pixels whose nearest surface is a face-region triangle of rig(weights) at pose (R, t) seen by
 * cam (W x H); NULL on failure. */
static inline unsigned char *depth_cloud_face_mask(frig_ctx *ctx, const frig_rig *rig, const double *weights,
                                                   const double R[9], const double t[3], const fr_camera *cam, int W,
                                                   int H) {
    int nv = frig_rig_vertex_count(rig), nt = rig->topo.triangle_count;
    float *x = malloc(sizeof(float) * 3 * nv), *xc = malloc(sizeof(float) * 3 * nv);
    unsigned char *mask = calloc((size_t)W * H, 1);
    fr_raster *r = NULL;
    fr_raster_options opt = {FR_RASTER_DEFAULT_NEAR, 1};
    int ok = x && xc && mask && !frig_rig_eval(ctx, rig, weights, x) && !fr_raster_create(ctx, W, H, &r);
    if (ok) {
        fr_transform_points(R, t, x, nv, xc);
        ok = !fr_raster_render(ctx, r, cam, xc, nv, rig->topo.triangles, nt, &opt);
    }
    for (int p = 0; ok && p < W * H; p++) {
        int tri = r->tri[p];
        if (tri < 0) continue;
        const int32_t *v = rig->topo.triangles + 3 * (size_t)tri;
        mask[p] = v[0] < DEPTH_CLOUD_FACE && v[1] < DEPTH_CLOUD_FACE && v[2] < DEPTH_CLOUD_FACE;
    }
    fr_raster_free(r);
    free(x), free(xc);
    if (!ok) {
        free(mask);
        return NULL;
    }
    return mask;
}

/* The cloud of the masked pixels of a W x H depth map (camera z, 0 where empty): each pixel's
 * point is put on the ray of camera (f, cx, cy) at depth z0 + relief (depth - depth0) (z0 =
 * depth0 and relief = 1: the depth map's own camera), normals from its four neighbours, then
 * moved into the head frame by the pose (R, t: head -> camera). Every stride-th pixel. Points
 * and normals (3 floats each) are allocated; returns the count (-1 on failure). */
static inline long depth_cloud_points(const float *depth, int W, int H, const unsigned char *mask, double f, double cx,
                                      double cy, double depth0, double z0, double relief, const double R[9],
                                      const double t[3], int stride, float **xyz, float **nrm) {
    float *P = calloc((size_t)W * H * 3, sizeof(float));
    size_t cap = (size_t)W * H / ((size_t)stride * stride) + 1, n = 0;
    *xyz = malloc(sizeof(float) * 3 * cap);
    *nrm = malloc(sizeof(float) * 3 * cap);
    if (!P || !*xyz || !*nrm) {
        free(P), free(*xyz), free(*nrm);
        *xyz = *nrm = NULL;
        return -1;
    }
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            float z = depth[(size_t)y * W + x];
            if (!(z > 0)) continue;
            double zz = z0 + relief * (z - depth0);
            float *p = P + 3 * ((size_t)y * W + x);
            p[0] = (float)((x - cx) * zz / f), p[1] = (float)((y - cy) * zz / f), p[2] = (float)zz;
        }
    for (int y = 1; y + 1 < H; y += stride)
        for (int x = 1; x + 1 < W; x += stride) {
            size_t q = (size_t)y * W + x;
            if (!mask[q]) continue;
            const float *c = P + 3 * q, *l = P + 3 * (q - 1), *r = P + 3 * (q + 1), *u = P + 3 * (q - W),
                        *d = P + 3 * (q + W);
            if (!(c[2] > 0 && l[2] > 0 && r[2] > 0 && u[2] > 0 && d[2] > 0)) continue;
            if (fabs(r[2] - l[2]) > DEPTH_CLOUD_EDGE || fabs(d[2] - u[2]) > DEPTH_CLOUD_EDGE) continue;
            double a[3] = {r[0] - l[0], r[1] - l[1], r[2] - l[2]}, b[3] = {d[0] - u[0], d[1] - u[1], d[2] - u[2]};
            double nc[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
            double len = sqrt(nc[0] * nc[0] + nc[1] * nc[1] + nc[2] * nc[2]);
            if (!(len > 0)) continue;
            if (nc[0] * c[0] + nc[1] * c[1] + nc[2] * c[2] > 0) len = -len; /* toward the camera */
            for (int k = 0; k < 3; k++) {
                double xv = 0, nv = 0;
                for (int j = 0; j < 3; j++) xv += R[3 * j + k] * (c[j] - t[j]), nv += R[3 * j + k] * nc[j] / len;
                (*xyz)[3 * n + k] = (float)xv;
                (*nrm)[3 * n + k] = (float)nv;
            }
            n++;
        }
    free(P);
    return (long)n;
}

#endif
