/* Z-buffered triangle rasterization for photo-consistency (paper section 4.4) and shape from
 * shading (section 5.1): homogeneous edge functions (Olano & Greer 1997) evaluated at pixel
 * centres in double precision, which give watertight coverage with the top-left rule,
 * perspective-correct barycentrics as ray-plane intersections and exact per-pixel near-plane
 * clipping without splitting triangles. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "core/floor_int.h"
#include "raster/raster.h"

/* Bounding boxes are widened by this many pixels so rounding in the projection never drops a
 * pixel the edge functions cover. */
#define BBOX_SLACK 1e-4
/* |det(P0, P1, P2)| below this fraction of |P0| |P1| |P2|: edge-on, skipped. */
#define EDGE_ON 1e-13
#define MIN_NEAR 1e-9

frig_status fr_raster_create(frig_ctx *ctx, int width, int height, fr_raster **out) {
    *out = NULL;
    if (width <= 0 || height <= 0 || (size_t)width > SIZE_MAX / 12 / (size_t)height)
        return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "a raster of %d x %d pixels cannot be made", width, height);
    size_t n = (size_t)width * (size_t)height;
    fr_raster *r = calloc(1, sizeof *r);
    if (!r) return fr_nomem(ctx, "the raster");
    r->width = width;
    r->height = height;
    r->depth = malloc(n * sizeof *r->depth);
    r->tri = malloc(n * sizeof *r->tri);
    r->bary = malloc(3 * n * sizeof *r->bary);
    if (!r->depth || !r->tri || !r->bary) {
        fr_raster_free(r);
        return fr_nomem(ctx, "the raster's buffers");
    }
    fr_raster_clear(r);
    *out = r;
    return FRIG_OK;
}

void fr_raster_free(fr_raster *r) {
    if (!r) return;
    free(r->depth);
    free(r->tri);
    free(r->bary);
    free(r);
}

void fr_raster_clear(fr_raster *r) {
    size_t n = (size_t)r->width * (size_t)r->height;
    for (size_t i = 0; i < n; i++) r->depth[i] = INFINITY;
    memset(r->tri, 0xff, n * sizeof *r->tri); /* -1 */
    memset(r->bary, 0, 3 * n * sizeof *r->bary);
}

static void cross3(const double a[3], const double b[3], double c[3]) {
    c[0] = a[1] * b[2] - a[2] * b[1];
    c[1] = a[2] * b[0] - a[0] * b[2];
    c[2] = a[0] * b[1] - a[1] * b[0];
}

static double dot3(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
static double min2(double a, double b) { return a < b ? a : b; }
static double max2(double a, double b) { return a > b ? a : b; }

/* Pixel range [lo, hi] covering [mn, mx] in an axis of n pixels; 0 when empty. */
static int pixel_range(double mn, double mx, int n, int *lo, int *hi) {
    double x = mn - BBOX_SLACK, y = mx + BBOX_SLACK;
    /* floor_int.h's cheaper ints where they fit: the same values as ceil and floor */
    double a = fabs(x) < FR_INT_RANGE ? fr_ceil_int(x) : ceil(x);
    double b = fabs(y) < FR_INT_RANGE ? fr_floor_int(y) : floor(y);
    if (a < 0.0) a = 0.0;
    if (b > n - 1) b = n - 1;
    if (!(a <= b)) return 0;
    *lo = (int)a;
    *hi = (int)b;
    return 1;
}

static void project_corner(const fr_camera *cam, const double x[3], double uv[2]) {
    uv[0] = cam->f * x[0] / x[2] + cam->cx;
    uv[1] = cam->f * x[1] / x[2] + cam->cy;
}

/* Image-space bounding box {umin, vmin, umax, vmax} of the part of the triangle with
 * z >= near (perspective): the corners in front and the edges' crossings of z = near. */
static int clipped_bbox(const fr_camera *cam, const double P[3][3], double near, double box[4]) {
    double pts[6][2];
    int n = 0;
    for (int i = 0; i < 3; i++) {
        const double *a = P[i], *b = P[(i + 1) % 3];
        if (a[2] >= near) project_corner(cam, a, pts[n++]);
        if ((a[2] < near) != (b[2] < near)) {
            double s = (near - a[2]) / (b[2] - a[2]);
            double x[3] = {a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1]), near};
            project_corner(cam, x, pts[n++]);
        }
    }
    if (n == 0) return 0;
    box[0] = box[2] = pts[0][0];
    box[1] = box[3] = pts[0][1];
    for (int i = 1; i < n; i++) {
        box[0] = min2(box[0], pts[i][0]), box[2] = max2(box[2], pts[i][0]);
        box[1] = min2(box[1], pts[i][1]), box[3] = max2(box[3], pts[i][1]);
    }
    return 1;
}

/* The pixel box of the corners' image positions uv when every corner is at z >= near (the box
 * tri_setup draws in then): 1, or 0 when it holds no pixel; -1 when a corner is nearer (or its z
 * not a number). */
static int corner_box(const float *const p[3], const double *const uv[3], double near, int width, int height,
                      fr_raster_tri *t) {
    for (int i = 0; i < 3; i++)
        if (!(p[i][2] >= near)) return -1;
    double box[4];
    box[0] = min2(uv[0][0], min2(uv[1][0], uv[2][0]));
    box[2] = max2(uv[0][0], max2(uv[1][0], uv[2][0]));
    box[1] = min2(uv[0][1], min2(uv[1][1], uv[2][1]));
    box[3] = max2(uv[0][1], max2(uv[1][1], uv[2][1]));
    return pixel_range(box[0], box[2], width, &t->x0, &t->x1) && pixel_range(box[1], box[3], height, &t->y0, &t->y1);
}

/* The set-up shared by fr_raster_tri_setup and the renderer; uv (may be NULL) holds the
 * corners' image positions when the caller has them (used only when all are at z >= near).
 * With uv the pixel box comes first and the first cross product (the facing) before the other
 * two: a triangle off the image or facing away costs least (the outcome is the same). */
static int tri_setup(const fr_camera *cam, const float *const p[3], const double *const uv[3],
                     const fr_raster_options *opt, int width, int height, fr_raster_tri *t) {
    double P[3][3];
    double near = opt ? opt->near : FR_RASTER_DEFAULT_NEAR;
    if (!(near > MIN_NEAR)) near = MIN_NEAR;
    /* with uv and every corner in front: the box tri_setup would end with (uv's), now */
    int boxed = !cam->weak && uv ? corner_box(p, uv, near, width, height, t) : -1;
    if (boxed == 0) return 0;
    for (int i = 0; i < 3; i++)
        for (int k = 0; k < 3; k++)
            if (!isfinite(p[i][k])) return 0;
    int cull = opt ? opt->cull_back : 0;
    t->weak = cam->weak;
    t->near = near;
    for (int i = 0; i < 3; i++) {
        if (cam->weak) {
            P[i][0] = cam->scale * p[i][0] + cam->cx;
            P[i][1] = cam->scale * p[i][1] + cam->cy;
            P[i][2] = 1.0;
        } else {
            for (int k = 0; k < 3; k++) P[i][k] = p[i][k];
        }
        t->z[i] = p[i][2];
    }
    t->zmin = min2(t->z[0], min2(t->z[1], t->z[2]));
    t->zmax = max2(t->z[0], max2(t->z[1], t->z[2]));
    if (!cam->weak && t->zmax < near) return 0;
    /* e_i is the edge opposite corner i: P_{i+1} x P_{i+2}; det = P0 . (P1 x P2) */
    double cr[3][3];
    cross3(P[1], P[2], cr[0]);
    double det = dot3(P[0], cr[0]);
    double bound2 = cam->weak ? 0.0 : EDGE_ON * EDGE_ON * dot3(P[0], P[0]) * dot3(P[1], P[1]) * dot3(P[2], P[2]);
    if (!(det * det > bound2) || det == 0.0) return 0;
    /* det < 0: counter-clockwise in the image = facing the camera */
    if (cull && det > 0.0) return 0;
    cross3(P[2], P[0], cr[1]);
    cross3(P[0], P[1], cr[2]);
    double sgn = det < 0.0 ? -1.0 : 1.0;
    for (int i = 0; i < 3; i++) {
        double c0 = sgn * cr[i][0], c1 = sgn * cr[i][1], c2 = sgn * cr[i][2];
        t->a[i] = c0;
        t->b[i] = c1;
        t->c[i] = cam->weak ? c2 : c2 * cam->f - c0 * cam->cx - c1 * cam->cy;
        t->tie[i] = (unsigned char)(c0 > 0.0 || (c0 == 0.0 && c1 > 0.0));
    }
    t->zk = cam->weak ? 0.0 : cam->f * fabs(det);
    if (boxed == 1) return 1;
    double box[4], q[3][2];
    if (cam->weak || t->zmin >= near) {
        for (int i = 0; i < 3; i++) {
            if (cam->weak)
                q[i][0] = P[i][0], q[i][1] = P[i][1];
            else if (uv)
                q[i][0] = uv[i][0], q[i][1] = uv[i][1];
            else
                project_corner(cam, P[i], q[i]);
        }
        box[0] = min2(q[0][0], min2(q[1][0], q[2][0]));
        box[2] = max2(q[0][0], max2(q[1][0], q[2][0]));
        box[1] = min2(q[0][1], min2(q[1][1], q[2][1]));
        box[3] = max2(q[0][1], max2(q[1][1], q[2][1]));
    } else if (!clipped_bbox(cam, P, near, box)) {
        return 0;
    }
    return pixel_range(box[0], box[2], width, &t->x0, &t->x1) &&
           pixel_range(box[1], box[3], height, &t->y0, &t->y1);
}

int fr_raster_tri_setup(const fr_camera *cam, const float p0[3], const float p1[3], const float p2[3],
                        const fr_raster_options *opt, int width, int height, fr_raster_tri *t) {
    const float *const p[3] = {p0, p1, p2};
    return tri_setup(cam, p, NULL, opt, width, height, t);
}

/* The coverage test at pixel column u of a row whose terms b_i v + c_i are in row[]. The
 * renderer and fr_raster_tri_sample share it, so tests see exactly what is drawn. */
static inline int sample_in_row(const fr_raster_tri *t, double u, const double row[3], double *z,
                                double bary[3]) {
    double e[3];
    for (int i = 0; i < 3; i++) {
        e[i] = t->a[i] * u + row[i];
        if (e[i] < 0.0 || (e[i] == 0.0 && !t->tie[i])) return 0;
    }
    double sum = e[0] + e[1] + e[2];
    if (!(sum > 0.0)) return 0;
    double inv = 1.0 / sum;
    for (int i = 0; i < 3; i++) bary[i] = e[i] * inv;
    if (t->weak) {
        *z = bary[0] * t->z[0] + bary[1] * t->z[1] + bary[2] * t->z[2];
        return 1;
    }
    double zz = t->zk * inv;
    if (!(zz >= t->near)) return 0;
    /* the intersection is a convex combination of the corners: keep rounding inside */
    *z = zz < t->zmin ? t->zmin : zz > t->zmax ? t->zmax : zz;
    return 1;
}

static void row_terms(const fr_raster_tri *t, int y, double row[3]) {
    for (int i = 0; i < 3; i++) row[i] = t->b[i] * (double)y + t->c[i];
}

int fr_raster_tri_sample(const fr_raster_tri *t, int x, int y, double *z, double bary[3]) {
    double row[3], zz, bb[3];
    row_terms(t, y, row);
    if (!sample_in_row(t, (double)x, row, &zz, bb)) return 0;
    if (z) *z = zz;
    if (bary)
        for (int i = 0; i < 3; i++) bary[i] = bb[i];
    return 1;
}

/* Columns of row 'row' that can be inside (a superset, 1 pixel of slack per side: the exact
 * test runs on each); lo > hi when none. */
static void row_span(const fr_raster_tri *t, const double row[3], int *lo, int *hi) {
    double a = *lo, b = *hi;
    for (int i = 0; i < 3; i++) {
        if (t->a[i] > 0.0)
            a = max2(a, ceil(-row[i] / t->a[i]) - 1.0);
        else if (t->a[i] < 0.0)
            b = min2(b, floor(-row[i] / t->a[i]) + 1.0);
        else if (row[i] < 0.0)
            b = a - 1.0;
    }
    if (!(a <= b)) {
        *hi = *lo - 1;
        return;
    }
    *lo = (int)a;
    *hi = (int)b;
}

static void draw_triangle(fr_raster *r, const fr_raster_tri *t, int32_t id) {
    for (int y = t->y0; y <= t->y1; y++) {
        double row[3];
        row_terms(t, y, row);
        int x0 = t->x0, x1 = t->x1;
        if (x1 - x0 > 6) row_span(t, row, &x0, &x1);
        size_t base = (size_t)y * (size_t)r->width;
        for (int x = x0; x <= x1; x++) {
            double z, b[3];
            if (!sample_in_row(t, (double)x, row, &z, b)) continue;
            size_t p = base + (size_t)x;
            float zf = (float)z;
            if (!(zf < r->depth[p])) continue;
            r->depth[p] = zf;
            r->tri[p] = id;
            r->bary[3 * p] = (float)b[0];
            r->bary[3 * p + 1] = (float)b[1];
            r->bary[3 * p + 2] = (float)b[2];
        }
    }
}

frig_status fr_raster_render(frig_ctx *ctx, fr_raster *r, const fr_camera *cam, const float *xyz, int nv,
                             const int32_t *tris, int nt, const fr_raster_options *opt) {
    for (int k = 0; k < nt; k++)
        for (int c = 0; c < 3; c++)
            if (tris[3 * (size_t)k + c] < 0 || tris[3 * (size_t)k + c] >= nv)
                return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT,
                                "triangle %d uses vertex %d, but the mesh has %d vertices", k,
                                (int)tris[3 * (size_t)k + c], nv);
    if (cam->weak ? !(cam->scale > 0.0) : !(cam->f > 0.0))
        return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "the camera's %s must be positive",
                        cam->weak ? "scale" : "focal length");
    /* each corner is shared by ~6 triangles: project the vertices once */
    double *uv = NULL;
    if (!cam->weak && nv > 0) {
        uv = malloc(2 * (size_t)nv * sizeof *uv);
        if (!uv) return fr_nomem(ctx, "the projected vertices");
        for (int i = 0; i < nv; i++) {
            double x[3] = {xyz[3 * (size_t)i], xyz[3 * (size_t)i + 1], xyz[3 * (size_t)i + 2]};
            if (x[2] > 0.0) project_corner(cam, x, uv + 2 * (size_t)i);
        }
    }
    fr_raster_clear(r);
    for (int k = 0; k < nt; k++) {
        if ((k & 0xffff) == 0xffff && fr_cancelled(ctx)) {
            free(uv);
            return fr_check_cancel(ctx, "rendering");
        }
        const int32_t *tr = tris + 3 * (size_t)k;
        const float *const p[3] = {xyz + 3 * (size_t)tr[0], xyz + 3 * (size_t)tr[1], xyz + 3 * (size_t)tr[2]};
        const double *const q[3] = {uv ? uv + 2 * (size_t)tr[0] : NULL, uv ? uv + 2 * (size_t)tr[1] : NULL,
                                    uv ? uv + 2 * (size_t)tr[2] : NULL};
        fr_raster_tri t;
        if (tri_setup(cam, p, uv ? q : NULL, opt, r->width, r->height, &t)) draw_triangle(r, &t, k);
    }
    free(uv);
    return FRIG_OK;
}

/* Interpolate at pixel index p (covered) into out. */
static void interpolate_at(const fr_raster *r, const int32_t *tris, size_t p, const float *attr, int dim,
                           float *out) {
    const int32_t *tr = tris + 3 * (size_t)r->tri[p];
    const float *b = r->bary + 3 * p;
    const float *a0 = attr + (size_t)tr[0] * (size_t)dim, *a1 = attr + (size_t)tr[1] * (size_t)dim,
                *a2 = attr + (size_t)tr[2] * (size_t)dim;
    for (int d = 0; d < dim; d++) out[d] = (float)((double)b[0] * a0[d] + (double)b[1] * a1[d] + (double)b[2] * a2[d]);
}

int fr_raster_interpolate(const fr_raster *r, const int32_t *tris, int x, int y, const float *attr, int dim,
                          float *out) {
    if (x < 0 || y < 0 || x >= r->width || y >= r->height) return 0;
    size_t p = (size_t)y * (size_t)r->width + (size_t)x;
    if (r->tri[p] < 0) return 0;
    interpolate_at(r, tris, p, attr, dim, out);
    return 1;
}

void fr_raster_attribute_map(const fr_raster *r, const int32_t *tris, const float *attr, int dim, float empty,
                             float *out) {
    size_t n = (size_t)r->width * (size_t)r->height;
    for (size_t p = 0; p < n; p++) {
        float *o = out + p * (size_t)dim;
        if (r->tri[p] >= 0)
            interpolate_at(r, tris, p, attr, dim, o);
        else
            for (int d = 0; d < dim; d++) o[d] = empty;
    }
}

void fr_raster_normal_map(const fr_raster *r, const int32_t *tris, const float *normals, float *out) {
    size_t n = (size_t)r->width * (size_t)r->height;
    for (size_t p = 0; p < n; p++) {
        float *o = out + 3 * p;
        o[0] = o[1] = o[2] = 0.0f;
        if (r->tri[p] < 0) continue;
        interpolate_at(r, tris, p, normals, 3, o);
        double len = sqrt((double)o[0] * o[0] + (double)o[1] * o[1] + (double)o[2] * o[2]);
        for (int d = 0; d < 3; d++) o[d] = len > 0.0 ? (float)(o[d] / len) : 0.0f;
    }
}

/* Triangle tr's cross product (area-weighted normal) added to its corners' sums. */
static void add_face_normal(const float *xyz, const int32_t *tr, float *normals) {
    const float *a = xyz + 3 * (size_t)tr[0], *b = xyz + 3 * (size_t)tr[1], *c = xyz + 3 * (size_t)tr[2];
    double e1[3] = {(double)b[0] - a[0], (double)b[1] - a[1], (double)b[2] - a[2]};
    double e2[3] = {(double)c[0] - a[0], (double)c[1] - a[1], (double)c[2] - a[2]};
    double n[3];
    cross3(e1, e2, n);
    for (int j = 0; j < 3; j++)
        for (int d = 0; d < 3; d++) normals[3 * (size_t)tr[j] + d] += (float)n[d];
}

static void normalize_sum(float *n) {
    double len = sqrt((double)n[0] * n[0] + (double)n[1] * n[1] + (double)n[2] * n[2]);
    for (int d = 0; d < 3; d++) n[d] = len > 0.0 ? (float)(n[d] / len) : 0.0f;
}

void fr_mesh_vertex_normals(const float *xyz, int nv, const int32_t *tris, int nt, float *normals) {
    for (size_t i = 0; i < 3 * (size_t)nv; i++) normals[i] = 0.0f;
    for (int k = 0; k < nt; k++) add_face_normal(xyz, tris + 3 * (size_t)k, normals);
    for (int i = 0; i < nv; i++) normalize_sum(normals + 3 * (size_t)i);
}

void fr_mesh_vertex_normals_at(const float *xyz, int nv, const int32_t *tris, const int32_t *list, int nlist,
                               const uint8_t *want, float *normals) {
    for (size_t i = 0; i < 3 * (size_t)nv; i++) normals[i] = 0.0f;
    for (int j = 0; j < nlist; j++) add_face_normal(xyz, tris + 3 * (size_t)list[j], normals);
    for (int i = 0; i < nv; i++)
        if (want[i]) normalize_sum(normals + 3 * (size_t)i);
        else normals[3 * (size_t)i] = normals[3 * (size_t)i + 1] = normals[3 * (size_t)i + 2] = 0.0f;
}

/* Camera z where the ray through image point (u, v) meets the plane of triangle tr; NAN when
 * the ray runs along the plane. */
static double plane_depth_at(const fr_camera *cam, const float *xyz, const int32_t *tr, double u, double v) {
    const float *a = xyz + 3 * (size_t)tr[0], *b = xyz + 3 * (size_t)tr[1], *c = xyz + 3 * (size_t)tr[2];
    double e1[3] = {(double)b[0] - a[0], (double)b[1] - a[1], (double)b[2] - a[2]};
    double e2[3] = {(double)c[0] - a[0], (double)c[1] - a[1], (double)c[2] - a[2]}, n[3];
    cross3(e1, e2, n);
    double na = n[0] * a[0] + n[1] * a[1] + n[2] * a[2];
    if (cam->weak) { /* the point ((u - cx) / s, (v - cy) / s, z) */
        if (n[2] == 0.0) return NAN;
        return (na - n[0] * (u - cam->cx) / cam->scale - n[1] * (v - cam->cy) / cam->scale) / n[2];
    }
    double d[3] = {(u - cam->cx) / cam->f, (v - cam->cy) / cam->f, 1.0};
    double nd = n[0] * d[0] + n[1] * d[1] + n[2] * d[2];
    return nd != 0.0 ? na / nd : NAN;
}

void fr_raster_visible_vertices(const fr_raster *r, const fr_camera *cam, const float *xyz, int nv,
                                const int32_t *tris, double tol, uint8_t *visible) {
    for (int i = 0; i < nv; i++) {
        const float *q = xyz + 3 * (size_t)i;
        double p[3] = {q[0], q[1], q[2]}, uv[2];
        visible[i] = 0;
        if (!fr_camera_project(cam, p, uv)) continue;
        if (!(uv[0] >= -0.5 && uv[0] < r->width - 0.5 && uv[1] >= -0.5 && uv[1] < r->height - 0.5)) continue;
        int x = (int)floor(uv[0] + 0.5), y = (int)floor(uv[1] + 0.5);
        if (x >= r->width || y >= r->height) continue;
        size_t px = (size_t)y * (size_t)r->width + (size_t)x;
        int32_t k = r->tri[px];
        if (k < 0) continue;
        const int32_t *tr = tris + 3 * (size_t)k;
        if (tr[0] == i || tr[1] == i || tr[2] == i) {
            visible[i] = 1;
            continue;
        }
        /* the surface seen at that pixel, extended to the vertex's exact image position */
        double zs = plane_depth_at(cam, xyz, tr, uv[0], uv[1]);
        if (!isfinite(zs)) zs = r->depth[px];
        visible[i] = (uint8_t)(p[2] <= zs + tol);
    }
}
