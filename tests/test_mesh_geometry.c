/* The geometry parts of the retarget stage (lib/mesh): nearest point of a triangle against
 * dense sampling; the triangle tree against brute force; the cotangent Laplacian against
 * known Dirichlet energies; Laplacian deformation reproducing a smooth field from scattered
 * point constraints (and the same result from a cloned solver); deformation transfer
 * reproducing the source on the source and R d on a rotated, scaled target. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "mesh/closest_point.h"
#include "mesh/deformation_transfer.h"
#include "mesh/laplacian.h"
#include "mesh/laplacian_deform.h"
#include "mesh/triangle_tree.h"
#include "testing.h"

static unsigned long long rng_state = 12345;
static double urand(void) {
    rng_state = rng_state * 6364136223846793005ULL + 1442695040888963407ULL;
    return (double)(rng_state >> 11) / 9007199254740992.0;
}

/* An n x n grid of vertices on [0, 1]^2 (z = 0), two triangles per cell, counter-clockwise. */
static void grid_mesh(int n, float **xyz, int32_t **tris, int *nv, int *nt) {
    *nv = n * n;
    *nt = 2 * (n - 1) * (n - 1);
    *xyz = malloc(sizeof(float) * 3 * (size_t)*nv);
    *tris = malloc(sizeof(int32_t) * 3 * (size_t)*nt);
    for (int y = 0; y < n; y++)
        for (int x = 0; x < n; x++) {
            float *p = *xyz + 3 * (y * n + x);
            p[0] = (float)x / (n - 1), p[1] = (float)y / (n - 1), p[2] = 0;
        }
    int t = 0;
    for (int y = 0; y + 1 < n; y++)
        for (int x = 0; x + 1 < n; x++) {
            int a = y * n + x, b = a + 1, c = a + n, d = c + 1;
            int32_t *f = *tris + 6 * t++;
            f[0] = a, f[1] = b, f[2] = d, f[3] = a, f[4] = d, f[5] = c;
        }
}

/* A closed UV sphere of radius r. */
static void sphere_mesh(int rings, int segs, double r, float **xyz, int32_t **tris, int *nv, int *nt) {
    *nv = 2 + (rings - 1) * segs;
    *nt = 2 * segs * (rings - 1);
    *xyz = malloc(sizeof(float) * 3 * (size_t)*nv);
    *tris = malloc(sizeof(int32_t) * 3 * (size_t)*nt);
    float *p = *xyz;
    p[0] = 0, p[1] = 0, p[2] = (float)r;
    for (int i = 1; i < rings; i++)
        for (int j = 0; j < segs; j++) {
            double th = M_PI * i / rings, ph = 2 * M_PI * j / segs;
            float *q = p + 3 * (1 + (i - 1) * segs + j);
            q[0] = (float)(r * sin(th) * cos(ph)), q[1] = (float)(r * sin(th) * sin(ph)), q[2] = (float)(r * cos(th));
        }
    int south = *nv - 1;
    p[3 * south] = 0, p[3 * south + 1] = 0, p[3 * south + 2] = (float)-r;
    int t = 0;
    for (int j = 0; j < segs; j++) {
        int32_t *f = *tris + 3 * t++;
        f[0] = 0, f[1] = 1 + j, f[2] = 1 + (j + 1) % segs;
    }
    for (int i = 1; i + 1 < rings; i++)
        for (int j = 0; j < segs; j++) {
            int a = 1 + (i - 1) * segs + j, b = 1 + (i - 1) * segs + (j + 1) % segs, c = a + segs, d = b + segs;
            int32_t *f = *tris + 3 * t++;
            f[0] = a, f[1] = c, f[2] = d;
            f = *tris + 3 * t++;
            f[0] = a, f[1] = d, f[2] = b;
        }
    for (int j = 0; j < segs; j++) {
        int a = 1 + (rings - 2) * segs + j, b = 1 + (rings - 2) * segs + (j + 1) % segs;
        int32_t *f = *tris + 3 * t++;
        f[0] = a, f[1] = south, f[2] = b;
    }
}

static void test_closest_point(void) {
    double worst = 0;
    for (int trial = 0; trial < 300; trial++) {
        double a[3], b[3], c[3], p[3], q[3], w[3];
        for (int k = 0; k < 3; k++) {
            a[k] = urand(), b[k] = urand(), c[k] = urand();
            p[k] = 2 * urand() - 0.5;
        }
        if (trial % 50 == 0)
            for (int k = 0; k < 3; k++) c[k] = 0.5 * (a[k] + b[k]); /* degenerate */
        double d2 = fr_closest_point_triangle(p, a, b, c, q, w);
        /* The answer is on the triangle, its weights are barycentric, and no sample is nearer. */
        double rec = 0;
        for (int k = 0; k < 3; k++) rec += fabs(w[0] * a[k] + w[1] * b[k] + w[2] * c[k] - q[k]);
        CHECK(rec < 1e-12);
        CHECK(w[0] >= -1e-12 && w[1] >= -1e-12 && w[2] >= -1e-12 && fabs(w[0] + w[1] + w[2] - 1) < 1e-12);
        double best = INFINITY;
        int n = 120;
        for (int i = 0; i <= n; i++)
            for (int j = 0; i + j <= n; j++) {
                double u = (double)i / n, v = (double)j / n, e = 0;
                for (int k = 0; k < 3; k++) {
                    double x = (1 - u - v) * a[k] + u * b[k] + v * c[k] - p[k];
                    e += x * x;
                }
                if (e < best) best = e;
            }
        CHECK(d2 <= best + 1e-12);
        if (sqrt(best) - sqrt(d2) > worst) worst = sqrt(best) - sqrt(d2);
    }
    printf("closest point: 300 triangles, sampling is never nearer; largest gain over sampling %.2e\n", worst);
}

static void test_tree(frig_ctx *ctx) {
    float *xyz;
    int32_t *tris;
    int nv, nt;
    sphere_mesh(40, 60, 0.1, &xyz, &tris, &nv, &nt);
    fr_tri_tree *tree = NULL;
    CHECK(fr_tri_tree_build(ctx, xyz, tris, nt, &tree) == FRIG_OK);
    int mismatches = 0, limited = 0;
    for (int pass = 0; pass < 2; pass++) {
        if (pass == 1) {
            /* Move the vertices (an ellipsoid) and refit. */
            for (int v = 0; v < nv; v++) xyz[3 * v] *= 1.3f, xyz[3 * v + 2] *= 0.8f;
            fr_tri_tree_refit(tree, xyz);
        }
        for (int q = 0; q < 500; q++) {
            double p[3] = {0.3 * urand() - 0.15, 0.3 * urand() - 0.15, 0.3 * urand() - 0.15};
            fr_tri_hit hit;
            int found = fr_tri_tree_nearest(tree, p, INFINITY, &hit);
            double best = INFINITY;
            int best_t = -1;
            for (int t = 0; t < nt; t++) {
                double a[3], b[3], c[3], qq[3], w[3];
                for (int k = 0; k < 3; k++) {
                    a[k] = xyz[3 * tris[3 * t] + k], b[k] = xyz[3 * tris[3 * t + 1] + k], c[k] = xyz[3 * tris[3 * t + 2] + k];
                }
                double d2 = fr_closest_point_triangle(p, a, b, c, qq, w);
                if (d2 < best) best = d2, best_t = t;
            }
            if (!found || hit.dist2 != best || hit.tri != best_t) mismatches++;
            /* A limit below the distance finds nothing, one above finds the same. */
            fr_tri_hit h2;
            if (fr_tri_tree_nearest(tree, p, 0.5 * sqrt(best), &h2)) limited++;
            if (!fr_tri_tree_nearest(tree, p, 1.01 * sqrt(best) + 1e-9, &h2) || h2.tri != best_t) mismatches++;
        }
    }
    printf("triangle tree: %d triangles, 1000 queries (before and after a refit): %d differ from brute force\n", nt,
           mismatches);
    CHECK(mismatches == 0);
    CHECK(limited == 0);
    fr_tri_tree_free(tree);
    free(xyz), free(tris);
}

static void test_laplacian(frig_ctx *ctx) {
    float *xyz;
    int32_t *tris;
    int nv, nt, n = 41;
    grid_mesh(n, &xyz, &tris, &nv, &nt);
    /* Shear the grid so that the triangles are not all right-angled. */
    for (int v = 0; v < nv; v++) xyz[3 * v] += 0.3f * xyz[3 * v + 1];
    fr_csr L;
    double *mass = malloc(sizeof(double) * nv);
    CHECK(fr_cotan_laplacian(ctx, nv, xyz, tris, nt, &L, mass) == FRIG_OK);
    double area = 0;
    for (int v = 0; v < nv; v++) area += mass[v];
    CHECK_NEAR(area, 1.0, 1e-7); /* a sheared unit square keeps its area (float corners) */
    /* L 1 = 0 everywhere; L (a x + b y) = 0 at interior vertices; u^T L u = integral |grad u|^2. */
    double *u = malloc(sizeof(double) * nv), *Lu = malloc(sizeof(double) * nv);
    double worst_const = 0, worst_lin = 0;
    for (int v = 0; v < nv; v++) u[v] = 1;
    fr_csr_mul(&L, u, Lu);
    for (int v = 0; v < nv; v++) worst_const = fmax(worst_const, fabs(Lu[v]));
    for (int v = 0; v < nv; v++) u[v] = 2 * xyz[3 * v] - 3 * xyz[3 * v + 1];
    fr_csr_mul(&L, u, Lu);
    double energy = 0;
    for (int v = 0; v < nv; v++) {
        int x = v % n, y = v / n;
        if (x > 0 && y > 0 && x < n - 1 && y < n - 1) worst_lin = fmax(worst_lin, fabs(Lu[v]));
        energy += u[v] * Lu[v];
    }
    printf("cotangent Laplacian: |L 1| <= %.1e, interior |L linear| <= %.1e, Dirichlet energy %.9f (exact 13)\n",
           worst_const, worst_lin, energy);
    CHECK(worst_const < 1e-12);
    CHECK(worst_lin < 1e-5);
    CHECK_NEAR(energy, 13.0, 1e-5); /* |grad(2x - 3y)|^2 = 13 over unit area */
    uint8_t *rim = malloc(nv);
    CHECK(fr_mesh_boundary(ctx, nv, tris, nt, rim) == FRIG_OK);
    int rims = 0;
    for (int v = 0; v < nv; v++) rims += rim[v];
    CHECK(rims == 4 * (n - 1));
    fr_csr_free(&L);
    free(mass), free(u), free(Lu), free(rim), free(xyz), free(tris);
}

/* A smooth field on the unit square. */
static void bump(double x, double y, double d[3]) {
    d[0] = 0.01 * sin(M_PI * x) * y;
    d[1] = -0.005 * x * x;
    d[2] = 0.02 * exp(-((x - 0.5) * (x - 0.5) + (y - 0.4) * (y - 0.4)) / 0.08);
}

static void test_laplacian_deform(frig_ctx *ctx) {
    float *xyz;
    int32_t *tris;
    int nv, nt, n = 41;
    grid_mesh(n, &xyz, &tris, &nv, &nt);
    fr_lap_system *sys = NULL;
    fr_lap_solver *sv = NULL, *sv2 = NULL;
    CHECK(fr_lap_system_create(ctx, nv, tris, nt, xyz, 2, &sys) == FRIG_OK);
    CHECK(fr_lap_solver_create(ctx, sys, &sv) == FRIG_OK);
    CHECK(fr_lap_solver_create(ctx, sys, &sv2) == FRIG_OK);
    if (!sv || !sv2) return;
    CHECK(fr_lap_system_set_rest(ctx, sys, xyz) == FRIG_OK);
    /* 400 random points inside random triangles, each told to move by the field. */
    int nc = 400;
    fr_lap_constraint *c = malloc(sizeof *c * nc);
    for (int i = 0; i < nc; i++) {
        int t = (int)(urand() * nt);
        double b1 = urand(), b2 = urand();
        if (b1 + b2 > 1) b1 = 1 - b1, b2 = 1 - b2;
        double b[3] = {1 - b1 - b2, b1, b2}, x = 0, y = 0;
        for (int k = 0; k < 3; k++) {
            c[i].v[k] = tris[3 * t + k];
            c[i].b[k] = b[k];
            x += b[k] * xyz[3 * tris[3 * t + k]];
            y += b[k] * xyz[3 * tris[3 * t + k] + 1];
        }
        bump(x, y, c[i].r);
        c[i].w = 1.0 / nc;
    }
    double *u = malloc(sizeof(double) * 3 * nv), *u2 = malloc(sizeof(double) * 3 * nv);
    CHECK(fr_lap_solve(ctx, sv, 1e-7, 1e-9, c, nc, u) == FRIG_OK);
    /* The same system through another solver (its own copy of the analysis), after a different
     * solve: identical numbers. */
    CHECK(fr_lap_solve(ctx, sv2, 1e-3, 1e-9, c, nc / 2, u2) == FRIG_OK);
    CHECK(fr_lap_solve(ctx, sv2, 1e-7, 1e-9, c, nc, u2) == FRIG_OK);
    CHECK(memcmp(u, u2, sizeof(double) * 3 * nv) == 0);
    double err = 0, amp = 0;
    for (int v = 0; v < nv; v++) {
        double d[3];
        bump(xyz[3 * v], xyz[3 * v + 1], d);
        double e = 0, a = 0;
        for (int k = 0; k < 3; k++) e += (u[3 * v + k] - d[k]) * (u[3 * v + k] - d[k]), a += d[k] * d[k];
        err += sqrt(e) / nv;
        amp += sqrt(a) / nv;
    }
    printf("Laplacian deformation: a smooth field from 400 points, mean error %.2e m (field mean %.2e m)\n", err, amp);
    CHECK(err < 0.01 * amp);
    /* A stiffer deformation follows the points less closely. */
    CHECK(fr_lap_solve(ctx, sv, 1e-2, 1e-9, c, nc, u2) == FRIG_OK);
    double res_soft = 0, res_stiff = 0;
    for (int i = 0; i < nc; i++)
        for (int k = 0; k < 3; k++) {
            double a = -c[i].r[k], b = -c[i].r[k];
            for (int q = 0; q < 3; q++) a += c[i].b[q] * u[3 * c[i].v[q] + k], b += c[i].b[q] * u2[3 * c[i].v[q] + k];
            res_soft += a * a, res_stiff += b * b;
        }
    CHECK(res_stiff > 10 * res_soft);
    fr_lap_solver_free(sv);
    fr_lap_solver_free(sv2);
    fr_lap_system_free(sys);
    free(c), free(u), free(u2), free(xyz), free(tris);
}

static void test_deformation_transfer(frig_ctx *ctx) {
    float *src;
    int32_t *tris;
    int nv, nt, n = 31;
    grid_mesh(n, &src, &tris, &nv, &nt);
    /* A curved source (a paraboloid cap) and two deformations of it. */
    for (int v = 0; v < nv; v++) {
        double x = src[3 * v] - 0.5, y = src[3 * v + 1] - 0.5;
        src[3 * v + 2] = (float)(-0.4 * (x * x + y * y));
    }
    int ns = 2;
    float *delta = malloc(sizeof(float) * 3 * nv * ns), *out = malloc(sizeof(float) * 3 * nv * ns);
    for (int v = 0; v < nv; v++) {
        double d[3];
        bump(src[3 * v], src[3 * v + 1], d);
        for (int k = 0; k < 3; k++) delta[3 * v + k] = (float)d[k], delta[3 * nv + 3 * v + k] = (float)(-2 * d[(k + 1) % 3]);
    }
    uint8_t *rim = malloc(nv);
    fr_mesh_boundary(ctx, nv, tris, nt, rim);
    /* Onto the source itself: the source's deltas. */
    fr_dtransfer *dt = NULL;
    CHECK(fr_dtransfer_create(ctx, nv, tris, nt, src, src, rim, &dt) == FRIG_OK);
    CHECK(fr_dtransfer_apply(ctx, dt, ns, delta, NULL, out) == FRIG_OK);
    double e_same = 0, amp = 0;
    for (int i = 0; i < 3 * nv * ns; i++) e_same = fmax(e_same, fabs(out[i] - delta[i])), amp = fmax(amp, fabs(delta[i]));
    fr_dtransfer_free(dt);
    /* Onto a scaled, moved copy (anchors held at s d): s d everywhere. (Not a rotated one:
     * deformation gradients act in world coordinates, so transfer does not rotate with the
     * target.) */
    double s = 1.7;
    float *tgt = malloc(sizeof(float) * 3 * nv), *want = malloc(sizeof(float) * 3 * nv * ns);
    for (int v = 0; v < nv; v++)
        for (int i = 0; i < 3; i++) {
            tgt[3 * v + i] = (float)(s * src[3 * v + i] + 0.1 * (i + 1));
            for (int j = 0; j < ns; j++) want[3 * nv * j + 3 * v + i] = (float)(s * delta[3 * nv * j + 3 * v + i]);
        }
    CHECK(fr_dtransfer_create(ctx, nv, tris, nt, src, tgt, rim, &dt) == FRIG_OK);
    CHECK(fr_dtransfer_apply(ctx, dt, ns, delta, want, out) == FRIG_OK);
    double e_rot = 0;
    for (int i = 0; i < 3 * nv * ns; i++) e_rot = fmax(e_rot, fabs(out[i] - want[i]));
    fr_dtransfer_free(dt);
    /* Without anchors the shape of the displacement is still that, up to its mean. */
    CHECK(fr_dtransfer_create(ctx, nv, tris, nt, src, tgt, NULL, &dt) == FRIG_OK);
    CHECK(fr_dtransfer_apply(ctx, dt, ns, delta, want, out) == FRIG_OK);
    double e_free = 0;
    for (int j = 0; j < ns; j++) {
        double mo[3] = {0, 0, 0}, mw[3] = {0, 0, 0};
        for (int v = 0; v < nv; v++)
            for (int k = 0; k < 3; k++) mo[k] += out[3 * nv * j + 3 * v + k] / nv, mw[k] += want[3 * nv * j + 3 * v + k] / nv;
        for (int v = 0; v < nv; v++)
            for (int k = 0; k < 3; k++)
                e_free = fmax(e_free, fabs(out[3 * nv * j + 3 * v + k] - mo[k] - want[3 * nv * j + 3 * v + k] + mw[k]));
    }
    fr_dtransfer_free(dt);
    printf("deformation transfer: onto itself max error %.2e m, onto s (source) + t %.2e m, unanchored %.2e m "
           "(deltas up to %.3f m)\n", e_same, e_rot, e_free, amp);
    /* The source's own gradients integrate exactly: float rounding only. */
    CHECK(e_same < 1e-4 * amp);
    CHECK(e_rot < 1e-4 * s * amp);
    CHECK(e_free < 1e-4 * s * amp);
    free(delta), free(out), free(rim), free(src), free(tgt), free(want), free(tris);
}

int main(void) {
    frig_ctx *ctx = frig_ctx_create();
    test_closest_point();
    test_tree(ctx);
    test_laplacian(ctx);
    test_laplacian_deform(ctx);
    test_deformation_transfer(ctx);
    frig_ctx_free(ctx);
    return test_result("test_mesh_geometry");
}
