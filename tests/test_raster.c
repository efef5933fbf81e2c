/* The rasterizer (lib/raster/raster.c) against analytic answers: covered pixel sets of single
 * triangles and rectangles (top-left rule), every pixel covered exactly once by meshes that
 * share edges (perspective and integer-exact weak grids), depth and perspective-correct
 * barycentrics against ray-plane intersection, near-plane clipping of a triangle with a corner
 * behind the camera against ray-triangle intersection, a sphere's depth and normals against
 * the analytic sphere, vertex visibility, culling, ids and argument checks; the renderer against
 * drawing triangle by triangle, and the normals at chosen vertices against the whole mesh's. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "raster/raster.h"
#include "raster/shapes.h"
#include "testing.h"

static frig_ctx *ctx;

static uint64_t rng = 0x2545f4914f6cdd1dull;
static double uniform(double lo, double hi) {
    rng ^= rng >> 12, rng ^= rng << 25, rng ^= rng >> 27;
    return lo + (hi - lo) * (double)((rng * 2685821657736338717ull) >> 11) / 9007199254740992.0;
}

static fr_camera pixel_camera(void) { /* weak perspective, scale 1: camera x, y are pixels */
    fr_camera c = {0.0, 0.0, 0.0, 1, 1.0};
    return c;
}

/* How many triangles of the mesh claim each pixel (by the renderer's own per-triangle rule). */
static int *coverage_counts(const fr_camera *cam, const float *xyz, const int32_t *tris, int nt, int w, int h,
                            const fr_raster_options *opt) {
    int *count = calloc((size_t)w * h, sizeof *count);
    for (int k = 0; k < nt; k++) {
        fr_raster_tri t;
        const int32_t *tr = tris + 3 * k;
        if (!fr_raster_tri_setup(cam, xyz + 3 * tr[0], xyz + 3 * tr[1], xyz + 3 * tr[2], opt, w, h, &t)) continue;
        for (int y = t.y0; y <= t.y1; y++)
            for (int x = t.x0; x <= t.x1; x++) count[y * w + x] += fr_raster_tri_sample(&t, x, y, NULL, NULL);
    }
    return count;
}

static void test_analytic_counts(void) {
    const int w = 20, h = 14;
    fr_camera cam = pixel_camera();
    /* the rectangle [2, 10] x [3, 8] (corners on pixel centres), both diagonals: top and left
     * edges are in, bottom and right out, so x = 2..9, y = 3..7 */
    const float quad[12] = {2, 3, 0, 10, 3, 0, 10, 8, 0, 2, 8, 0};
    const int32_t diag[2][6] = {{0, 1, 2, 0, 2, 3}, {0, 1, 3, 1, 2, 3}};
    for (int d = 0; d < 2; d++) {
        int *count = coverage_counts(&cam, quad, diag[d], 2, w, h, NULL);
        int bad = 0;
        for (int y = 0; y < h; y++)
            for (int x = 0; x < w; x++) bad += count[y * w + x] != (x >= 2 && x <= 9 && y >= 3 && y <= 7);
        CHECK(bad == 0);
        free(count);
    }
    /* right triangle (3,2) (12,2) (3,8): top and left legs in, hypotenuse (a right edge) out:
     * pixels (3 + i, 2 + j), i, j >= 0, 6 i + 9 j < 54 */
    const float t1[9] = {3, 2, 0, 12, 2, 0, 3, 8, 0};
    /* its mirror (12,8) (3,8) (12,2): bottom and right legs out, hypotenuse (a left edge) in */
    const float t2[9] = {12, 8, 0, 3, 8, 0, 12, 2, 0};
    const int32_t one[3] = {0, 1, 2};
    int *c1 = coverage_counts(&cam, t1, one, 1, w, h, NULL), *c2 = coverage_counts(&cam, t2, one, 1, w, h, NULL);
    int bad = 0, n1 = 0, n2 = 0;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            int i = x - 3, j = y - 2;
            int in1 = i >= 0 && j >= 0 && 6 * i + 9 * j < 54;
            int in2 = x < 12 && y < 8 && 6 * i + 9 * (y - 8) >= 0 && i >= 0 && j >= 0;
            bad += c1[y * w + x] != in1 || c2[y * w + x] != in2;
            n1 += in1, n2 += in2;
        }
    printf("single triangles: %d and %d pixels as counted analytically, %d mismatches\n", n1, n2, bad);
    CHECK(bad == 0);
    /* Pick: area 27, 18 boundary points, so 19 inside and 37 in the closed triangle; the first
     * loses the 4 points on its hypotenuse, the second the 16 on its bottom and right legs */
    CHECK(n1 == 37 - 4 && n2 == 37 - 16);
    free(c1);
    free(c2);

    /* random triangles with float corners against an independent long-double inside test */
    long mismatches = 0, covered = 0;
    for (int rep = 0; rep < 300; rep++) {
        float p[9];
        for (int i = 0; i < 3; i++) p[3 * i] = (float)uniform(-4, w + 4), p[3 * i + 1] = (float)uniform(-4, h + 4),
                                    p[3 * i + 2] = 0.0f;
        int *c = coverage_counts(&cam, p, one, 1, w, h, NULL);
        long double ax = p[0], ay = p[1], bx = p[3], by = p[4], cx = p[6], cy = p[7];
        long double area = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
        for (int y = 0; y < h; y++)
            for (int x = 0; x < w; x++) {
                long double e0 = (cx - bx) * (y - by) - (cy - by) * (x - bx);
                long double e1 = (ax - cx) * (y - cy) - (ay - cy) * (x - cx);
                long double e2 = (bx - ax) * (y - ay) - (by - ay) * (x - ax);
                int in = area != 0 && (area > 0 ? (e0 > 0 && e1 > 0 && e2 > 0) : (e0 < 0 && e1 < 0 && e2 < 0));
                mismatches += in != c[y * w + x];
                covered += in;
            }
        free(c);
    }
    printf("300 random triangles: %ld pixels inside, %ld disagreements with a long-double test\n", covered,
           mismatches);
    CHECK(covered > 1000);
    CHECK(mismatches == 0);
}

/* A grid of nx x ny cells over the whole image, corners jittered, random diagonals. */
static void jittered_grid(int nx, int ny, int integer_weak, float *xyz, int32_t *tris) {
    for (int j = 0; j <= ny; j++)
        for (int i = 0; i <= nx; i++) {
            float *p = xyz + 3 * (i + (nx + 1) * j);
            if (integer_weak) { /* pixel-centre corners every 4 px from -6, jitter +-1 px */
                int inner = i > 0 && i < nx && j > 0 && j < ny;
                p[0] = (float)(-6 + 4 * i + (inner ? (int)uniform(-1.99, 1.99) : 0));
                p[1] = (float)(-6 + 4 * j + (inner ? (int)uniform(-1.99, 1.99) : 0));
                p[2] = (float)uniform(0.5, 1.0);
            } else { /* a wavy sheet 0.5..0.8 m away, wider than the view */
                double gx = (double)i / nx, gy = (double)j / ny;
                double jx = (i > 0 && i < nx) ? uniform(-0.2, 0.2) / nx : 0.0;
                double jy = (j > 0 && j < ny) ? uniform(-0.2, 0.2) / ny : 0.0;
                p[0] = (float)(-0.35 + 0.7 * (gx + jx));
                p[1] = (float)(-0.3 + 0.6 * (gy + jy));
                p[2] = (float)(0.5 + 0.2 * gx + 0.1 * gy + 0.005 * sin(20 * gx) * cos(17 * gy));
            }
        }
    int k = 0;
    for (int j = 0; j < ny; j++)
        for (int i = 0; i < nx; i++) {
            int a = i + (nx + 1) * j, b = a + 1, c = b + nx + 1, d = a + nx + 1;
            int32_t *t = tris + 6 * k++;
            if (uniform(0, 1) < 0.5) {
                int32_t q[6] = {a, b, c, a, c, d};
                memcpy(t, q, sizeof q);
            } else {
                int32_t q[6] = {a, b, d, b, c, d};
                memcpy(t, q, sizeof q);
            }
        }
}

static void test_watertight(void) {
    const int w = 160, h = 120;
    for (int mode = 0; mode < 2; mode++) {
        int nx = mode ? 43 : 40, ny = mode ? 33 : 30;
        float *xyz = malloc(sizeof(float) * 3 * (nx + 1) * (ny + 1));
        int32_t *tris = malloc(sizeof(int32_t) * 6 * nx * ny);
        jittered_grid(nx, ny, mode, xyz, tris);
        fr_camera cam = mode ? pixel_camera() : fr_camera_perspective(300.0, w, h);
        int *count = coverage_counts(&cam, xyz, tris, 2 * nx * ny, w, h, NULL);
        int zero = 0, multi = 0;
        for (int i = 0; i < w * h; i++) zero += count[i] == 0, multi += count[i] > 1;
        printf("%s grid, %d triangles sharing edges: %d pixels uncovered, %d covered more than once\n",
               mode ? "weak integer" : "perspective", 2 * nx * ny, zero, multi);
        CHECK(zero == 0);
        CHECK(multi == 0);
        /* the renderer agrees: every pixel drawn, by the triangle that claims it */
        fr_raster *r;
        CHECK(fr_raster_create(ctx, w, h, &r) == FRIG_OK);
        CHECK(fr_raster_render(ctx, r, &cam, xyz, (nx + 1) * (ny + 1), tris, 2 * nx * ny, NULL) == FRIG_OK);
        int empty = 0;
        for (int i = 0; i < w * h; i++) empty += r->tri[i] < 0;
        CHECK(empty == 0);
        fr_raster_free(r);
        free(count);
        free(xyz);
        free(tris);
    }
}

/* Barycentrics of X in triangle P by Cramer's rule on X = sum b_i P_i (long double). */
static void solve_bary(const double P[3][3], const long double X[3], long double b[3]) {
    long double m[3][3];
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++) m[r][c] = P[c][r];
    long double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                      m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                      m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    for (int k = 0; k < 3; k++) {
        long double a[3][3];
        memcpy(a, m, sizeof a);
        for (int r = 0; r < 3; r++) a[r][k] = X[r];
        b[k] = (a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
                a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0])) / det;
    }
}

static void test_plane_interpolation(void) {
    const int w = 256, h = 192;
    fr_camera cam = fr_camera_perspective(280.0, w, h);
    const float xyz[9] = {-0.4f, -0.3f, 0.45f, 0.5f, -0.1f, 1.2f, -0.05f, 0.45f, 0.7f};
    const int32_t tri[3] = {0, 1, 2};
    double P[3][3];
    for (int i = 0; i < 3; i++)
        for (int k = 0; k < 3; k++) P[i][k] = xyz[3 * i + k];
    fr_raster *r;
    CHECK(fr_raster_create(ctx, w, h, &r) == FRIG_OK);
    CHECK(fr_raster_render(ctx, r, &cam, xyz, 3, tri, 1, NULL) == FRIG_OK);
    double n[3], e1[3], e2[3];
    for (int k = 0; k < 3; k++) e1[k] = P[1][k] - P[0][k], e2[k] = P[2][k] - P[0][k];
    n[0] = e1[1] * e2[2] - e1[2] * e2[1], n[1] = e1[2] * e2[0] - e1[0] * e2[2], n[2] = e1[0] * e2[1] - e1[1] * e2[0];
    double nP0 = n[0] * P[0][0] + n[1] * P[0][1] + n[2] * P[0][2];
    double zerr = 0, berr = 0, xerr = 0, affine_err = 0;
    long covered = 0;
    /* screen-space (affine) interpolation of position, to show what perspective correction buys */
    double uvs[3][2];
    for (int i = 0; i < 3; i++) fr_camera_project(&cam, P[i], uvs[i]);
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            size_t p = (size_t)y * w + x;
            if (r->tri[p] < 0) continue;
            covered++;
            long double d[3] = {(x - cam.cx) / cam.f, (y - cam.cy) / cam.f, 1.0L};
            long double t = nP0 / (n[0] * d[0] + n[1] * d[1] + n[2] * d[2]);
            long double X[3] = {t * d[0], t * d[1], t};
            long double b[3];
            solve_bary(P, X, b);
            zerr = fmax(zerr, fabs((double)(r->depth[p] - t)) / (double)t);
            for (int k = 0; k < 3; k++) berr = fmax(berr, fabs((double)(r->bary[3 * p + k] - b[k])));
            float Xi[3];
            CHECK(fr_raster_interpolate(r, tri, x, y, xyz, 3, Xi));
            for (int k = 0; k < 3; k++) xerr = fmax(xerr, fabs((double)(Xi[k] - X[k])));
            double den = (uvs[1][0] - uvs[0][0]) * (uvs[2][1] - uvs[0][1]) - (uvs[1][1] - uvs[0][1]) * (uvs[2][0] - uvs[0][0]);
            double s1 = ((x - uvs[0][0]) * (uvs[2][1] - uvs[0][1]) - (y - uvs[0][1]) * (uvs[2][0] - uvs[0][0])) / den;
            double s2 = ((uvs[1][0] - uvs[0][0]) * (y - uvs[0][1]) - (uvs[1][1] - uvs[0][1]) * (x - uvs[0][0])) / den;
            for (int k = 0; k < 3; k++)
                affine_err = fmax(affine_err, fabs((1 - s1 - s2) * P[0][k] + s1 * P[1][k] + s2 * P[2][k] - (double)X[k]));
        }
    printf("tilted plane, %ld pixels: depth relative error %.2e, barycentric error %.2e, interpolated "
           "position error %.2e m (affine screen-space interpolation would be off by %.3f m)\n",
           covered, zerr, berr, xerr, affine_err);
    /* the whole-image attribute map agrees with the per-pixel accessor, 'empty' elsewhere */
    float *map = malloc(sizeof(float) * 3 * w * h);
    fr_raster_attribute_map(r, tri, xyz, 3, -7.0f, map);
    long map_bad = 0;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            float one[3] = {-7.0f, -7.0f, -7.0f};
            fr_raster_interpolate(r, tri, x, y, xyz, 3, one);
            map_bad += memcmp(one, map + 3 * (y * w + x), sizeof one) != 0;
        }
    CHECK(map_bad == 0);
    free(map);
    CHECK(covered > 5000);
    CHECK(zerr < 1e-7);  /* float storage */
    CHECK(berr < 5e-7);
    CHECK(xerr < 5e-7);
    CHECK(affine_err > 0.01);

    /* weak perspective: depth and barycentrics are affine in the image */
    fr_camera weak = fr_camera_weak(150.0, w, h);
    CHECK(fr_raster_render(ctx, r, &weak, xyz, 3, tri, 1, NULL) == FRIG_OK);
    double werr = 0;
    covered = 0;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            size_t p = (size_t)y * w + x;
            if (r->tri[p] < 0) continue;
            covered++;
            double X = (x - weak.cx) / weak.scale, Y = (y - weak.cy) / weak.scale;
            double z = (nP0 - n[0] * X - n[1] * Y) / n[2];
            werr = fmax(werr, fabs(r->depth[p] - z));
        }
    printf("weak perspective plane, %ld pixels: depth error %.2e m\n", covered, werr);
    CHECK(covered > 5000);
    CHECK(werr < 1e-6);
    fr_raster_free(r);
}

static void test_near_clipping(void) {
    const int w = 200, h = 150;
    fr_camera cam = fr_camera_perspective(150.0, w, h);
    fr_raster_options opt = {0.05, 0};
    /* one corner behind the camera, the plane crossing z = near inside the view */
    const float xyz[9] = {-0.05f, -0.02f, -0.3f, 0.4f, -0.3f, 1.2f, 0.05f, 0.5f, 1.0f};
    const int32_t tri[3] = {0, 1, 2};
    fr_raster *r;
    CHECK(fr_raster_create(ctx, w, h, &r) == FRIG_OK);
    CHECK(fr_raster_render(ctx, r, &cam, xyz, 3, tri, 1, &opt) == FRIG_OK);
    long mism = 0, covered = 0, clipped = 0;
    double zerr = 0;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            /* Moller-Trumbore along d = ((x - cx) / f, (y - cy) / f, 1) in long double */
            long double d[3] = {(x - cam.cx) / cam.f, (y - cam.cy) / cam.f, 1.0L}, p0[3], e1[3], e2[3];
            for (int k = 0; k < 3; k++) p0[k] = xyz[k], e1[k] = xyz[3 + k] - p0[k], e2[k] = xyz[6 + k] - p0[k];
            long double pv[3] = {d[1] * e2[2] - d[2] * e2[1], d[2] * e2[0] - d[0] * e2[2], d[0] * e2[1] - d[1] * e2[0]};
            long double det = e1[0] * pv[0] + e1[1] * pv[1] + e1[2] * pv[2];
            long double tv[3] = {-p0[0], -p0[1], -p0[2]};
            long double u = (tv[0] * pv[0] + tv[1] * pv[1] + tv[2] * pv[2]) / det;
            long double qv[3] = {tv[1] * e1[2] - tv[2] * e1[1], tv[2] * e1[0] - tv[0] * e1[2], tv[0] * e1[1] - tv[1] * e1[0]};
            long double v = (d[0] * qv[0] + d[1] * qv[1] + d[2] * qv[2]) / det;
            long double t = (e2[0] * qv[0] + e2[1] * qv[1] + e2[2] * qv[2]) / det;
            int hit = u > 0 && v > 0 && u + v < 1 && t > 0;
            int want = hit && t >= opt.near;
            clipped += hit && !want;
            int got = r->tri[y * w + x] >= 0;
            mism += want != got;
            if (want && got) {
                covered++;
                zerr = fmax(zerr, fabs((double)(r->depth[y * w + x] - t)) / (double)t);
            }
        }
    printf("triangle with a corner behind the camera: %ld pixels drawn, %ld clipped by the near plane, "
           "%ld disagreements with ray-triangle intersection, depth relative error %.2e\n",
           covered, clipped, mism, zerr);
    CHECK(covered > 1000 && clipped > 1000);
    CHECK(mism == 0);
    CHECK(zerr < 1e-7);
    fr_raster_free(r);
}

static double angle_deg(const double *a, const float *b) {
    double la = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
    double lb = sqrt((double)b[0] * b[0] + (double)b[1] * b[1] + (double)b[2] * b[2]);
    double c = (a[0] * b[0] + a[1] * b[1] + a[2] * b[2]) / (la * lb);
    return acos(c > 1 ? 1 : c < -1 ? -1 : c) * 180.0 / M_PI;
}

static void test_sphere(void) {
    const int w = 512, h = 512, nlon = 256, nlat = 128;
    const double c[3] = {0.01, -0.02, 0.5}, rad = 0.1;
    fr_camera cam = fr_camera_perspective(600.0, w, h);
    fr_shape s;
    CHECK(fr_shape_sphere(ctx, c, rad, nlon, nlat, &s) == FRIG_OK);
    fr_raster *r;
    CHECK(fr_raster_create(ctx, w, h, &r) == FRIG_OK);
    fr_raster_options opt = {FR_RASTER_DEFAULT_NEAR, 1};
    CHECK(fr_raster_render(ctx, r, &cam, s.xyz, s.nv, s.tris, s.nt, &opt) == FRIG_OK);
    float *normals = malloc(sizeof(float) * 3 * s.nv), *nmap = malloc(sizeof(float) * 3 * w * h);
    fr_mesh_vertex_normals(s.xyz, s.nv, s.tris, s.nt, normals);
    fr_raster_normal_map(r, s.tris, normals, nmap);
    double vn_err = 0;
    for (int i = 0; i < s.nv; i++) {
        double radial[3] = {s.xyz[3 * i] - c[0], s.xyz[3 * i + 1] - c[1], s.xyz[3 * i + 2] - c[2]};
        vn_err = fmax(vn_err, angle_deg(radial, normals + 3 * i));
    }
    /* the inscribed mesh lies within delta of the sphere, radially (half a band by half a
     * segment from the nearest corner); along a ray meeting the surface at incidence a the
     * depth error is at most delta / cos(a) */
    double delta = rad * (1.0 - cos(M_PI / (2 * nlat)) * cos(M_PI / nlon));
    double err_all = 0, err_front = 0, sum = 0, nerr = 0, nerr_front = 0;
    long covered = 0, covered_miss = 0, hit_uncovered = 0;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            size_t p = (size_t)y * w + x;
            double d[3] = {(x - cam.cx) / cam.f, (y - cam.cy) / cam.f, 1.0};
            double dd = d[0] * d[0] + d[1] * d[1] + d[2] * d[2], dc = d[0] * c[0] + d[1] * c[1] + d[2] * c[2];
            double cc = c[0] * c[0] + c[1] * c[1] + c[2] * c[2];
            double disc = dc * dc - dd * (cc - rad * rad);
            int hit = disc >= 0;
            if (r->tri[p] < 0) {
                hit_uncovered += hit;
                continue;
            }
            covered++;
            if (!hit) {
                covered_miss++;
                continue;
            }
            double t = (dc - sqrt(disc)) / dd; /* z of the nearer intersection (d_z = 1) */
            double X[3] = {t * d[0], t * d[1], t * d[2]}, nrm[3] = {X[0] - c[0], X[1] - c[1], X[2] - c[2]};
            double cosinc = -(nrm[0] * d[0] + nrm[1] * d[1] + nrm[2] * d[2]) / (rad * sqrt(dd));
            double e = fabs(r->depth[p] - t);
            err_all = fmax(err_all, e);
            sum += e;
            double ne = angle_deg(nrm, nmap + 3 * p);
            nerr = fmax(nerr, ne);
            if (cosinc > 0.5) err_front = fmax(err_front, e), nerr_front = fmax(nerr_front, ne);
        }
    printf("sphere r = %.2f m at %.2f m, %d triangles, %dx%d: %ld pixels; depth error max %.3g mm (%.3g mm where "
           "the surface faces the camera within 60 deg; bound from the tessellation %.3g mm), mean %.3g mm\n",
           rad, c[2], s.nt, w, h, covered, 1e3 * err_all, 1e3 * err_front, 1e3 * 2 * delta, 1e3 * sum / covered);
    printf("  covered but off the sphere: %ld, on the sphere but not covered: %ld (silhouette ring); vertex "
           "normal error max %.3f deg, pixel normal error max %.3f deg (%.3f deg within 60 deg)\n",
           covered_miss, hit_uncovered, vn_err, nerr, nerr_front);
    CHECK(covered > 20000);
    CHECK(covered_miss == 0);
    CHECK(hit_uncovered < 2 * M_PI * 600 * rad / c[2] * 1.5); /* under 1.5 x the perimeter in pixels */
    CHECK(err_front <= 2 * delta + 1e-6);
    CHECK(err_all <= sqrt(2 * rad * 2 * delta)); /* a ray grazing the rim: the chord's depth */
    CHECK(vn_err < 0.25 * 180.0 / nlat); /* a quarter of the band angle */
    CHECK(nerr_front < 1.0);

    /* visibility: vertices facing the camera (normal . view > 0.2) are visible, facing away
     * (< -0.2) are not */
    uint8_t *vis = malloc((size_t)s.nv);
    fr_raster_visible_vertices(r, &cam, s.xyz, s.nv, s.tris, 1e-3, vis);
    long front = 0, front_bad = 0, back = 0, back_bad = 0;
    for (int i = 0; i < s.nv; i++) {
        const float *v = s.xyz + 3 * i;
        double nrm[3] = {(v[0] - c[0]) / rad, (v[1] - c[1]) / rad, (v[2] - c[2]) / rad};
        double len = sqrt((double)v[0] * v[0] + (double)v[1] * v[1] + (double)v[2] * v[2]);
        double facing = -(nrm[0] * v[0] + nrm[1] * v[1] + nrm[2] * v[2]) / len;
        if (facing > 0.2) front++, front_bad += !vis[i];
        if (facing < -0.2) back++, back_bad += vis[i];
    }
    printf("  visibility: %ld front vertices, %ld marked hidden; %ld back vertices, %ld marked visible\n", front,
           front_bad, back, back_bad);
    CHECK(front > 5000 && back > 5000);
    CHECK(front_bad == 0 && back_bad == 0);
    free(vis);
    free(normals);
    free(nmap);
    fr_raster_free(r);
    fr_shape_free(&s);
}

static void test_occlusion_and_rules(void) {
    const int w = 64, h = 48;
    fr_camera cam = fr_camera_perspective(60.0, w, h);
    fr_raster *r;
    CHECK(fr_raster_create(ctx, w, h, &r) == FRIG_OK);
    /* a wall at z = 1 (grid) and a square card at z = 0.5 in front of its middle */
    fr_shape g;
    CHECK(fr_shape_grid(ctx, 20, 20, &g) == FRIG_OK);
    int nv = g.nv + 4, nt = g.nt + 2;
    float *xyz = malloc(sizeof(float) * 3 * nv);
    int32_t *tris = malloc(sizeof(int32_t) * 3 * nt);
    for (int i = 0; i < g.nv; i++) {
        xyz[3 * i] = 2.0f * g.xyz[3 * i] - 1.0f;
        xyz[3 * i + 1] = 2.0f * g.xyz[3 * i + 1] - 1.0f;
        xyz[3 * i + 2] = 1.0f;
    }
    memcpy(tris, g.tris, sizeof(int32_t) * 3 * g.nt);
    const float card[12] = {-0.1f, -0.1f, 0.5f, 0.1f, -0.1f, 0.5f, 0.1f, 0.1f, 0.5f, -0.1f, 0.1f, 0.5f};
    memcpy(xyz + 3 * g.nv, card, sizeof card);
    int b = g.nv;
    int32_t ct[6] = {b, b + 2, b + 1, b, b + 3, b + 2}; /* counter-clockwise in the image: facing us */
    memcpy(tris + 3 * g.nt, ct, sizeof ct);
    CHECK(fr_raster_render(ctx, r, &cam, xyz, nv, tris, nt, NULL) == FRIG_OK);
    uint8_t *vis = malloc((size_t)nv);
    fr_raster_visible_vertices(r, &cam, xyz, nv, tris, 1e-3, vis);
    int bad = 0, hidden = 0;
    for (int i = 0; i < g.nv; i++) {
        double x = xyz[3 * i], y = xyz[3 * i + 1];
        int behind = fabs(x) < 0.18 && fabs(y) < 0.18, outside = fabs(x) > 0.22 || fabs(y) > 0.22;
        double u = cam.f * x + cam.cx, v = cam.f * y + cam.cy;
        int in_image = u > -0.5 && u < w - 0.5 && v > -0.5 && v < h - 0.5;
        if (behind) hidden++, bad += vis[i];
        if (outside && in_image) bad += !vis[i];
        if (!in_image) bad += vis[i];
    }
    printf("occlusion: %d wall vertices behind the card; %d visibility errors\n", hidden, bad);
    CHECK(hidden >= 4);
    CHECK(bad == 0);
    for (int i = g.nv; i < nv; i++) CHECK(vis[i]);
    /* culling: the wall faces +z (away from the camera), so culling leaves only the card */
    fr_raster_options cull = {FR_RASTER_DEFAULT_NEAR, 1};
    CHECK(fr_raster_render(ctx, r, &cam, xyz, nv, tris, nt, &cull) == FRIG_OK);
    int drawn_wall = 0, drawn_card = 0;
    for (int i = 0; i < w * h; i++) drawn_wall += r->tri[i] >= 0 && r->tri[i] < g.nt, drawn_card += r->tri[i] >= g.nt;
    CHECK(drawn_wall == 0);
    CHECK(drawn_card == 24 * 24); /* 0.2 m at 0.5 m, f = 60: u and v span 24 px between pixel centres */
    /* equal depth: the lower triangle index wins */
    int32_t twice[6] = {b, b + 2, b + 1, b, b + 2, b + 1};
    CHECK(fr_raster_render(ctx, r, &cam, xyz, nv, twice, 2, NULL) == FRIG_OK);
    int first = 0, second = 0;
    for (int i = 0; i < w * h; i++) first += r->tri[i] == 0, second += r->tri[i] == 1;
    CHECK(first > 0 && second == 0);
    /* a bad index is refused with a sentence */
    int32_t badtri[3] = {0, 1, nv};
    CHECK(fr_raster_render(ctx, r, &cam, xyz, nv, badtri, 1, NULL) == FRIG_ERR_INVALID_ARGUMENT);
    CHECK(strstr(frig_ctx_errmsg(ctx), "triangle 0") != NULL);
    /* a non-finite corner skips the triangle, nothing else */
    xyz[3 * (b + 1)] = NAN; /* only in triangle 0 */
    CHECK(fr_raster_render(ctx, r, &cam, xyz, nv, ct, 2, NULL) == FRIG_OK);
    int n0 = 0, n1 = 0;
    for (int i = 0; i < w * h; i++) n0 += r->tri[i] == 0, n1 += r->tri[i] == 1;
    CHECK(n0 == 0 && n1 > 0);
    free(vis);
    free(xyz);
    free(tris);
    fr_shape_free(&g);
    fr_raster_free(r);
}

/* The renderer (vertices projected once, rows clipped to the edges' spans) draws the same pixels as
 * every triangle set up alone by fr_raster_tri_setup and sampled by fr_raster_tri_sample in order
 * (depth, ids and barycentrics bit for bit), on random triangles of every size and facing, partly
 * off the raster, behind the near plane, edge-on and degenerate, culling on and off. */
static void test_render_per_triangle(void) {
    const int w = 96, h = 80, nt = 3000, nv = 3 * nt;
    fr_camera cam = fr_camera_perspective(120.0, w, h);
    float *xyz = malloc(sizeof(float) * 3 * nv);
    int32_t *tris = malloc(sizeof(int32_t) * 3 * nt);
    for (int k = 0; k < nt; k++) {
        double c[3] = {uniform(-0.6, 0.6), uniform(-0.5, 0.5), uniform(0.3, 1.5)}, size = pow(10.0, uniform(-4, -0.5));
        int kind = k % 10;
        for (int i = 0; i < 3; i++) {
            float *q = xyz + 3 * (3 * k + i);
            for (int d = 0; d < 3; d++) q[d] = (float)(c[d] + size * uniform(-1, 1));
            if (kind == 7 && i == 2) q[2] = -0.1f;                                  /* a corner behind the camera */
            if (kind == 8) q[0] = (float)c[0], q[1] = (float)(c[1] + 0.01 * i);     /* edge-on: a vertical segment */
            if (kind == 9 && i == 2) memcpy(q, xyz + 3 * (3 * k), sizeof(float) * 3); /* two corners at one point */
        }
        for (int i = 0; i < 3; i++) tris[3 * k + i] = 3 * k + i;
    }
    fr_raster *r;
    CHECK(fr_raster_create(ctx, w, h, &r) == FRIG_OK);
    float *depth = malloc(sizeof(float) * w * h), *bary = malloc(sizeof(float) * 3 * w * h);
    int32_t *id = malloc(sizeof(int32_t) * w * h);
    for (int cull = 0; cull <= 1; cull++) {
        fr_raster_options opt = {FR_RASTER_DEFAULT_NEAR, cull};
        CHECK(fr_raster_render(ctx, r, &cam, xyz, nv, tris, nt, &opt) == FRIG_OK);
        for (int i = 0; i < w * h; i++) depth[i] = INFINITY, id[i] = -1;
        memset(bary, 0, sizeof(float) * 3 * w * h);
        int set_up = 0;
        for (int k = 0; k < nt; k++) {
            const int32_t *tr = tris + 3 * k;
            fr_raster_tri t;
            if (!fr_raster_tri_setup(&cam, xyz + 3 * tr[0], xyz + 3 * tr[1], xyz + 3 * tr[2], &opt, w, h, &t)) continue;
            set_up++;
            for (int y = t.y0; y <= t.y1; y++)
                for (int x = t.x0; x <= t.x1; x++) {
                    double z, b[3];
                    if (!fr_raster_tri_sample(&t, x, y, &z, b) || !((float)z < depth[y * w + x])) continue;
                    depth[y * w + x] = (float)z, id[y * w + x] = k;
                    for (int c = 0; c < 3; c++) bary[3 * (y * w + x) + c] = (float)b[c];
                }
        }
        int differ = 0, covered = 0;
        for (int i = 0; i < w * h; i++) {
            differ += memcmp(&depth[i], &r->depth[i], sizeof(float)) != 0 || id[i] != r->tri[i] ||
                      memcmp(bary + 3 * i, r->bary + 3 * i, 3 * sizeof(float)) != 0;
            covered += id[i] >= 0;
        }
        printf("triangle by triangle (cull %d): %d of %d set up, %d pixels covered, %d differ\n", cull, set_up, nt,
               covered, differ);
        CHECK(covered > w * h / 2);
        CHECK(differ == 0);
    }
    /* the normals at chosen vertices from the triangles that use them: the whole mesh's floats there */
    fr_shape s;
    const double c[3] = {0.0, 0.0, 0.5};
    CHECK(fr_shape_sphere(ctx, c, 0.1, 64, 32, &s) == FRIG_OK);
    uint8_t *want = calloc((size_t)s.nv, 1);
    int32_t *list = malloc(sizeof(int32_t) * s.nt);
    float *all = malloc(sizeof(float) * 3 * s.nv), *some = malloc(sizeof(float) * 3 * s.nv);
    for (int i = 0; i < s.nv; i++) want[i] = uniform(0, 1) < 0.3;
    int nl = 0;
    for (int k = 0; k < s.nt; k++)
        if (want[s.tris[3 * k]] || want[s.tris[3 * k + 1]] || want[s.tris[3 * k + 2]]) list[nl++] = k;
    fr_mesh_vertex_normals(s.xyz, s.nv, s.tris, s.nt, all);
    fr_mesh_vertex_normals_at(s.xyz, s.nv, s.tris, list, nl, want, some);
    int bad = 0, wanted = 0;
    for (int i = 0; i < s.nv; i++) {
        wanted += want[i];
        if (want[i]) bad += memcmp(all + 3 * i, some + 3 * i, 3 * sizeof(float)) != 0;
        else bad += some[3 * i] != 0 || some[3 * i + 1] != 0 || some[3 * i + 2] != 0;
    }
    printf("normals at %d of %d vertices from %d of %d triangles: %d differ\n", wanted, s.nv, nl, s.nt, bad);
    CHECK(wanted > 0 && nl < s.nt && bad == 0);
    free(want), free(list), free(all), free(some);
    fr_shape_free(&s);
    free(depth), free(bary), free(id), free(xyz), free(tris);
    fr_raster_free(r);
}

int main(void) {
    ctx = frig_ctx_create();
    if (!ctx) return 1;
    test_analytic_counts();
    test_watertight();
    test_plane_interpolation();
    test_near_clipping();
    test_sphere();
    test_occlusion_and_rules();
    test_render_per_triangle();
    frig_ctx_free(ctx);
    return test_result("test_raster");
}
