/* Baking a per-vertex attribute into a material's UV tile: the material's triangles rasterized
 * in UV space, the attribute interpolated at each texel's centre, and the texels no triangle
 * covers given the value of the nearest covered one (gutters for bilinear and mip filtering).
 * Used by the painted eye textures (eye_texture.c) and the back of the head's (head_texture.c). */
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "raster/raster.h"
#include "rig/look.h"

/* Every uncovered texel takes the value of its nearest covered one (a two-pass chamfer
 * propagation of the nearest covered texel's coordinates, 8 neighbours). */
static frig_status fill_uncovered(frig_ctx *ctx, int size, int dim, float *out, uint8_t *covered) {
    size_t n = (size_t)size * (size_t)size;
    int32_t *nx = malloc(sizeof(int32_t) * 2 * n), *ny = nx ? nx + n : NULL;
    if (!nx) return fr_nomem(ctx, "a texture bake");
    int any = 0;
    for (size_t px = 0; px < n; px++) {
        nx[px] = covered[px] ? (int32_t)(px % (size_t)size) : -1;
        ny[px] = covered[px] ? (int32_t)(px / (size_t)size) : -1;
        any |= covered[px];
    }
    static const int fwd[4][2] = {{-1, 0}, {-1, -1}, {0, -1}, {1, -1}}, bwd[4][2] = {{1, 0}, {1, 1}, {0, 1}, {-1, 1}};
    for (int pass = 0; any && pass < 2; pass++) {
        const int(*nb)[2] = pass ? bwd : fwd;
        for (int yy = 0; yy < size; yy++) {
            int y = pass ? size - 1 - yy : yy;
            for (int xx = 0; xx < size; xx++) {
                int x = pass ? size - 1 - xx : xx;
                size_t px = (size_t)y * (size_t)size + (size_t)x;
                long bd = nx[px] >= 0 ? (long)(nx[px] - x) * (nx[px] - x) + (long)(ny[px] - y) * (ny[px] - y) : LONG_MAX;
                for (int k = 0; k < 4; k++) {
                    int qx = x + nb[k][0], qy = y + nb[k][1];
                    if (qx < 0 || qy < 0 || qx >= size || qy >= size) continue;
                    size_t q = (size_t)qy * (size_t)size + (size_t)qx;
                    if (nx[q] < 0) continue;
                    long d = (long)(nx[q] - x) * (nx[q] - x) + (long)(ny[q] - y) * (ny[q] - y);
                    if (d < bd) bd = d, nx[px] = nx[q], ny[px] = ny[q];
                }
            }
        }
    }
    for (size_t px = 0; any && px < n; px++)
        if (!covered[px]) {
            size_t src = (size_t)ny[px] * (size_t)size + (size_t)nx[px];
            memcpy(out + px * (size_t)dim, out + src * (size_t)dim, sizeof(float) * (size_t)dim);
            covered[px] = 2;
        }
    free(nx);
    return FRIG_OK;
}

/* out (size * size * dim floats) gets the attribute (dim floats per rig vertex) interpolated at
 * each texel centre covered by the material's triangles; covered[] marks those texels (1), and
 * every other texel gets the value of the nearest covered one (covered[] 2): gutters for
 * bilinear and mip filtering, and a value for triangles whose UVs collapse to a point (ICT's
 * pupil: rasterized they cover no texel, sampled they read the texel at that point). */
frig_status fr_texture_bake(frig_ctx *ctx, const fr_topology *t, int material, const float *attr, int dim, int size,
                        float *out, uint8_t *covered) {
    int nt = 0;
    for (int i = 0; i < t->triangle_count; i++) nt += t->triangle_materials[i] == material;
    float *xyz = malloc(sizeof(float) * 9 * (size_t)(nt + 1));
    float *cattr = malloc(sizeof(float) * 3 * (size_t)dim * (size_t)(nt + 1));
    int32_t *tris = malloc(sizeof(int32_t) * 3 * (size_t)(nt + 1));
    fr_raster *r = NULL;
    frig_status s = !xyz || !cattr || !tris ? fr_nomem(ctx, "a texture bake") : fr_raster_create(ctx, size, size, &r);
    int k = 0;
    for (int i = 0; !s && i < t->triangle_count; i++) {
        if (t->triangle_materials[i] != material) continue;
        double tile = INFINITY;
        for (int c = 0; c < 3; c++) tile = fmin(tile, floor(t->uvs[2 * t->triangle_uvs[3 * i + c]]));
        for (int c = 0; c < 3; c++) {
            const float *uv = t->uvs + 2 * t->triangle_uvs[3 * i + c];
            float *p = xyz + 3 * (size_t)(3 * k + c);
            p[0] = (float)((uv[0] - tile) * size - 0.5);
            p[1] = (float)((1.0 - uv[1]) * size - 0.5);
            p[2] = 1.0f;
            memcpy(cattr + (size_t)dim * (size_t)(3 * k + c), attr + (size_t)dim * (size_t)t->triangles[3 * i + c],
                   sizeof(float) * (size_t)dim);
            tris[3 * k + c] = 3 * k + c;
        }
        k++;
    }
    fr_camera cam = {0};
    cam.weak = 1, cam.scale = 1.0;
    if (!s) s = fr_raster_render(ctx, r, &cam, xyz, 3 * nt, tris, nt, NULL);
    size_t n = (size_t)size * (size_t)size;
    for (size_t px = 0; !s && px < n; px++) {
        covered[px] = fr_raster_interpolate(r, tris, (int)(px % (size_t)size), (int)(px / (size_t)size), cattr, dim,
                                            out + px * (size_t)dim);
        if (!covered[px]) memset(out + px * (size_t)dim, 0, sizeof(float) * (size_t)dim);
    }
    if (!s) s = fill_uncovered(ctx, size, dim, out, covered);
    fr_raster_free(r);
    free(xyz);
    free(cattr);
    free(tris);
    return s;
}
