/* Procedural meshes with analytic surfaces (sphere, torus, plane grid) for checking rendering
 * (paper sections 4.4 and 5.1) and geometry against exact answers, independent of the face
 * model. Triangles wind counter-clockwise seen from outside. */
#include <math.h>
#include <stdlib.h>

#include "core/context.h"
#include "raster/shapes.h"

void fr_shape_free(fr_shape *s) {
    if (!s) return;
    free(s->xyz);
    free(s->tris);
    s->xyz = NULL;
    s->tris = NULL;
    s->nv = s->nt = 0;
}

static frig_status shape_alloc(frig_ctx *ctx, long nv, long nt, fr_shape *s) {
    s->xyz = NULL;
    s->tris = NULL;
    s->nv = s->nt = 0;
    if (nv <= 0 || nt <= 0 || nv > INT32_MAX / 3 || nt > INT32_MAX / 3)
        return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "a mesh of %ld vertices and %ld triangles cannot be made",
                        nv, nt);
    s->xyz = malloc(3 * (size_t)nv * sizeof *s->xyz);
    s->tris = malloc(3 * (size_t)nt * sizeof *s->tris);
    if (!s->xyz || !s->tris) {
        fr_shape_free(s);
        return fr_nomem(ctx, "a procedural mesh");
    }
    s->nv = (int)nv;
    s->nt = (int)nt;
    return FRIG_OK;
}

static void put_vertex(fr_shape *s, int i, const double c[3], double x, double y, double z) {
    s->xyz[3 * (size_t)i] = (float)(c[0] + x);
    s->xyz[3 * (size_t)i + 1] = (float)(c[1] + y);
    s->xyz[3 * (size_t)i + 2] = (float)(c[2] + z);
}

static void put_tri(fr_shape *s, int k, int a, int b, int c) {
    s->tris[3 * (size_t)k] = a;
    s->tris[3 * (size_t)k + 1] = b;
    s->tris[3 * (size_t)k + 2] = c;
}

/* Quad a-b-c-d (counter-clockwise from outside) as triangles k and k + 1. */
static void put_quad(fr_shape *s, int k, int a, int b, int c, int d) {
    put_tri(s, k, a, b, c);
    put_tri(s, k + 1, a, c, d);
}

frig_status fr_shape_sphere(frig_ctx *ctx, const double centre[3], double radius, int nlon, int nlat,
                            fr_shape *out) {
    if (nlon < 3 || nlat < 2 || !(radius > 0.0))
        return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "a sphere needs radius > 0, >= 3 segments and >= 2 bands "
                        "(got %g, %d, %d)", radius, nlon, nlat);
    long rings = nlat - 1;
    frig_status st = shape_alloc(ctx, 2 + rings * nlon, 2L * nlon * rings, out);
    if (st) return st;
    /* vertex 0 = north pole (+y), 1 = south pole, then ring i (from the north), segment j */
    put_vertex(out, 0, centre, 0.0, radius, 0.0);
    put_vertex(out, 1, centre, 0.0, -radius, 0.0);
    for (int i = 0; i < rings; i++) {
        double th = M_PI * (i + 1) / nlat;
        for (int j = 0; j < nlon; j++) {
            double ph = 2.0 * M_PI * j / nlon;
            put_vertex(out, 2 + i * nlon + j, centre, radius * sin(th) * sin(ph), radius * cos(th),
                       radius * sin(th) * cos(ph));
        }
    }
    int k = 0;
    for (int j = 0; j < nlon; j++) {
        int j1 = (j + 1) % nlon;
        put_tri(out, k++, 0, 2 + j, 2 + j1);
        put_tri(out, k++, 1, 2 + (int)(rings - 1) * nlon + j1, 2 + (int)(rings - 1) * nlon + j);
    }
    for (int i = 0; i + 1 < rings; i++)
        for (int j = 0; j < nlon; j++) {
            int j1 = (j + 1) % nlon, a = 2 + i * nlon, b = a + nlon;
            put_quad(out, k, a + j, b + j, b + j1, a + j1);
            k += 2;
        }
    return FRIG_OK;
}

frig_status fr_shape_torus(frig_ctx *ctx, const double centre[3], double R, double r, int nu, int nv,
                           fr_shape *out) {
    if (nu < 3 || nv < 3 || !(r > 0.0) || !(R > r))
        return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "a torus needs R > r > 0 and >= 3 segments each way "
                        "(got %g, %g, %d, %d)", R, r, nu, nv);
    frig_status st = shape_alloc(ctx, (long)nu * nv, 2L * nu * nv, out);
    if (st) return st;
    for (int i = 0; i < nu; i++) {
        double u = 2.0 * M_PI * i / nu;
        for (int j = 0; j < nv; j++) {
            double v = 2.0 * M_PI * j / nv, w = R + r * cos(v);
            put_vertex(out, i * nv + j, centre, w * sin(u), r * sin(v), w * cos(u));
        }
    }
    int k = 0;
    for (int i = 0; i < nu; i++)
        for (int j = 0; j < nv; j++) {
            int i1 = (i + 1) % nu, j1 = (j + 1) % nv;
            put_quad(out, k, i * nv + j, i1 * nv + j, i1 * nv + j1, i * nv + j1);
            k += 2;
        }
    return FRIG_OK;
}

frig_status fr_shape_grid(frig_ctx *ctx, int nx, int ny, fr_shape *out) {
    if (nx < 1 || ny < 1)
        return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "a grid needs at least 1 x 1 cells (got %d x %d)", nx, ny);
    frig_status st = shape_alloc(ctx, (long)(nx + 1) * (ny + 1), 2L * nx * ny, out);
    if (st) return st;
    const double origin[3] = {0.0, 0.0, 0.0};
    for (int j = 0; j <= ny; j++)
        for (int i = 0; i <= nx; i++) put_vertex(out, i + (nx + 1) * j, origin, (double)i / nx, (double)j / ny, 0.0);
    int k = 0;
    for (int j = 0; j < ny; j++)
        for (int i = 0; i < nx; i++) {
            int a = i + (nx + 1) * j;
            put_quad(out, k, a, a + 1, a + 1 + (nx + 1), a + (nx + 1));
            k += 2;
        }
    return FRIG_OK;
}
