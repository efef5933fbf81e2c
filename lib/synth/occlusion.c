/* Ambient occlusion of a synthetic subject's head, baked into its albedo: the lighting of
 * paper section 5.1 (eq. 5.2, SH irradiance of the normal) has no shadows, so without it eye
 * sockets, nostrils and the mouth's corners come out as bright as the cheeks and face
 * detectors miss the faces. Per vertex, the cosine-weighted share of directions from which it
 * can be seen, each direction tested with an orthographic depth render of the head. */
#include <math.h>
#include <stdlib.h>

#include "core/context.h"
#include "synth/synth.h"

#define DIRECTIONS 64
#define SIDE 256          /* depth render, pixels */
#define EXTENT 0.5        /* metres across the render */
#define TOLERANCE 0.003   /* metres behind the visible surface still counted as seen */

/* Row-major rotation whose third row (the camera's forward axis) is -d. */
static void look_along(const double d[3], double R[9]) {
    double z[3] = {-d[0], -d[1], -d[2]}, up[3] = {0, 1, 0};
    if (fabs(z[1]) > 0.9) up[0] = 1, up[1] = 0;
    double x[3] = {up[1] * z[2] - up[2] * z[1], up[2] * z[0] - up[0] * z[2], up[0] * z[1] - up[1] * z[0]};
    double n = sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
    for (int i = 0; i < 3; i++) x[i] /= n;
    double y[3] = {z[1] * x[2] - z[2] * x[1], z[2] * x[0] - z[0] * x[2], z[0] * x[1] - z[1] * x[0]};
    for (int i = 0; i < 3; i++) R[i] = x[i], R[3 + i] = y[i], R[6 + i] = z[i];
}

/* Direction k of a Fibonacci sphere. */
static void direction(int k, double d[3]) {
    double y = 1.0 - 2.0 * (k + 0.5) / DIRECTIONS, r = sqrt(1.0 - y * y), phi = 2.399963229728653 * k;
    d[0] = r * cos(phi), d[1] = y, d[2] = r * sin(phi);
}

frig_status fr_synth_ambient_occlusion(frig_ctx *ctx, const float *xyz, int nv, const int32_t *tris, int nt,
                                       float *ao) {
    float *normals = malloc(sizeof *normals * 3 * (size_t)nv), *xc = malloc(sizeof *xc * 3 * (size_t)nv);
    double *seen = calloc((size_t)nv, sizeof *seen), *total = calloc((size_t)nv, sizeof *total);
    uint8_t *vis = malloc((size_t)nv);
    fr_raster *r = NULL;
    frig_status st = normals && xc && seen && total && vis ? FRIG_OK : fr_nomem(ctx, "ambient occlusion");
    if (!st) st = fr_raster_create(ctx, SIDE, SIDE, &r);
    double c[3] = {0, 0, 0};
    for (int v = 0; v < nv; v++)
        for (int i = 0; i < 3; i++) c[i] += xyz[3 * (size_t)v + i] / nv;
    if (!st) fr_mesh_vertex_normals(xyz, nv, tris, nt, normals);
    fr_camera cam = fr_camera_weak(SIDE / EXTENT, SIDE, SIDE);
    for (int k = 0; k < DIRECTIONS && !st; k++) {
        double d[3], R[9], t[3], rc[3];
        direction(k, d);
        look_along(d, R);
        fr_mat3_apply(R, c, rc);
        for (int i = 0; i < 3; i++) t[i] = -rc[i] + (i == 2 ? 1.0 : 0.0);
        fr_transform_points(R, t, xyz, nv, xc);
        st = fr_raster_render(ctx, r, &cam, xc, nv, tris, nt, NULL);
        if (st) break;
        fr_raster_visible_vertices(r, &cam, xc, nv, tris, TOLERANCE, vis);
        for (int v = 0; v < nv; v++) {
            const float *n = normals + 3 * (size_t)v;
            double w = n[0] * d[0] + n[1] * d[1] + n[2] * d[2];
            if (w <= 0.0) continue;
            total[v] += w;
            if (vis[v]) seen[v] += w;
        }
    }
    for (int v = 0; !st && v < nv; v++) ao[v] = total[v] > 0.0 ? (float)(seen[v] / total[v]) : 1.0f;
    fr_raster_free(r);
    free(normals), free(xc), free(seen), free(total), free(vis);
    return st;
}
