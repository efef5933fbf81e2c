/* The filter stage's face frame: the reference triangulation covers the hull of the 68 points
 * exactly once; the piecewise-affine warp reproduces a linear intensity ramp exactly under any
 * affine placement of the face (bilinear sampling and box supersampling are exact on linear
 * functions); gain/bias normalization; Procrustes alignment recovers known similarities; the
 * contact sheet frames dropped faces in red. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "core/rng.h"
#include "filter/contact_sheet.h"
#include "filter/face_reference.h"
#include "filter/face_warp.h"
#include "filter/failure_detection.h"
#include "filter/procrustes.h"
#include "image/image.h"
#include "testing.h"

static double cross(const double *o, const double *a, const double *b) {
    return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
}

static int cmp_xy(const void *a, const void *b) {
    const double *p = a, *q = b;
    return p[0] != q[0] ? (p[0] > q[0]) - (p[0] < q[0]) : (p[1] > q[1]) - (p[1] < q[1]);
}

/* Convex hull (monotone chain), counter-clockwise in (x, y-down) terms of cross > 0; returns h. */
static int hull(const double *pts, int n, double *out) {
    double *p = malloc(sizeof(double) * 2 * n);
    memcpy(p, pts, sizeof(double) * 2 * n);
    qsort(p, (size_t)n, sizeof(double) * 2, cmp_xy);
    int k = 0;
    for (int i = 0; i < n; i++) {
        while (k >= 2 && cross(out + 2 * (k - 2), out + 2 * (k - 1), p + 2 * i) <= 0) k--;
        memcpy(out + 2 * k++, p + 2 * i, sizeof(double) * 2);
    }
    for (int i = n - 2, lo = k + 1; i >= 0; i--) {
        while (k >= lo && cross(out + 2 * (k - 2), out + 2 * (k - 1), p + 2 * i) <= 0) k--;
        memcpy(out + 2 * k++, p + 2 * i, sizeof(double) * 2);
    }
    free(p);
    return k - 1;
}

static int inside_hull(const double *h, int count, double x, double y) {
    double q[2] = {x, y};
    for (int i = 0; i < count; i++)
        if (cross(h + 2 * i, h + 2 * ((i + 1) % count), q) < -1e-9) return 0;
    return 1;
}

static void test_triangulation(frig_ctx *ctx) {
    int nt;
    const unsigned char(*t)[3] = fr_face_triangles(&nt);
    const double *ref = fr_face_reference_shape();
    double h[2 * 70], area = 0, hull_area = 0;
    int nh = hull(ref, 68, h);
    for (int i = 0; i < nh; i++) hull_area += 0.5 * cross(h, h + 2 * i, h + 2 * ((i + 1) % nh));
    int ok = 1, edges[68][68];
    memset(edges, 0, sizeof edges);
    for (int i = 0; i < nt; i++) {
        double a = 0.5 * cross(ref + 2 * t[i][0], ref + 2 * t[i][1], ref + 2 * t[i][2]);
        ok &= a > 0;
        area += a;
        for (int e = 0; e < 3; e++) {
            int u = t[i][e], v = t[i][(e + 1) % 3];
            edges[u < v ? u : v][u < v ? v : u]++;
        }
    }
    int boundary = 0, over = 0;
    for (int u = 0; u < 68; u++)
        for (int v = 0; v < 68; v++) boundary += edges[u][v] == 1, over += edges[u][v] > 2;
    printf("triangulation: %d triangles, hull of %d points, area %.6f vs hull %.6f, %d boundary edges\n", nt, nh,
           area, hull_area, boundary);
    CHECK(ok);
    CHECK(over == 0);
    CHECK(nt == 2 * 68 - nh - 2); /* every point used, the hull filled */
    CHECK(boundary == nh);
    CHECK_NEAR(area, hull_area, 1e-12);
    /* The reference is centred in a unit box. */
    double x0 = 1, x1 = -1, y0 = 1, y1 = -1;
    for (int k = 0; k < 68; k++)
        x0 = fmin(x0, ref[2 * k]), x1 = fmax(x1, ref[2 * k]), y0 = fmin(y0, ref[2 * k + 1]), y1 = fmax(y1, ref[2 * k + 1]);
    CHECK_NEAR(fmax(x1 - x0, y1 - y0), 1.0, 1e-6);
    CHECK_NEAR(x0 + x1, 0, 1e-6);
    CHECK_NEAR(y0 + y1, 0, 1e-6);

    /* The plan's texels are the frame pixels inside the hull. */
    fr_face_warp *w = NULL;
    CHECK(fr_face_warp_create(ctx, 64, &w) == FRIG_OK);
    const double *fs = fr_face_warp_frame_shape(w);
    nh = hull(fs, 68, h);
    int expect = 0, mismatch = 0, P = fr_face_warp_texels(w);
    const int *idx = fr_face_warp_texel_index(w);
    for (int y = 0, k = 0; y < 64; y++)
        for (int x = 0; x < 64; x++) {
            int in = inside_hull(h, nh, x, y), listed = k < P && idx[k] == y * 64 + x;
            expect += in;
            mismatch += in != listed;
            k += listed;
        }
    printf("64 x 64 frame: %d texels (%d pixels inside the hull, %d disagree)\n", P, expect, mismatch);
    CHECK(mismatch == 0);
    CHECK(P == expect);
    fr_face_warp_free(w);
    CHECK(fr_face_warp_create(ctx, 8, &w) == FRIG_ERR_INVALID_ARGUMENT);
    CHECK(w == NULL);
}

/* An image whose gray value is x (axis 0) or y (axis 1) at pixel (x, y), the same in RGB. */
static frig_image *ramp(int size, int channels, int axis) {
    frig_image *img = fr_image_new(size, size, channels);
    for (int y = 0; y < size; y++)
        for (int x = 0; x < size; x++)
            for (int c = 0; c < channels; c++)
                img->pixels[(size_t)y * img->stride + (size_t)x * channels + c] = (uint8_t)(axis ? y : x);
    return img;
}

static void test_warp_exact(frig_ctx *ctx) {
    fr_face_warp *w = NULL;
    CHECK(fr_face_warp_create(ctx, 48, &w) == FRIG_OK);
    int P = fr_face_warp_texels(w), S = fr_face_warp_size(w);
    const double *fs = fr_face_warp_frame_shape(w);
    const int *idx = fr_face_warp_texel_index(w);
    double *tex = malloc(sizeof(double) * P), lm[136];
    /* Affine placements: shrunk (no supersampling), enlarged 2.6x (3 x 3 samples), rotated and sheared. */
    static const double maps[][6] = {
        {0.8, 0.0, 0.0, 0.8, 20, 15}, {2.6, 0.3, -0.4, 2.2, 5, 30}, {0.9, -0.45, 0.45, 0.9, 40, 10}};
    for (int m = 0; m < 3; m++)
        for (int c = 0; c < 4; c++) {
            int channels = c < 2 ? 1 : 3, axis = c % 2;
            frig_image *img = ramp(256, channels, axis);
            const double *a = maps[m];
            for (int k = 0; k < 68; k++) {
                lm[2 * k] = a[0] * fs[2 * k] + a[1] * fs[2 * k + 1] + a[4];
                lm[2 * k + 1] = a[2] * fs[2 * k] + a[3] * fs[2 * k + 1] + a[5];
            }
            double outside = -1, err = 0;
            CHECK(fr_face_warp_sample(ctx, w, img, lm, tex, &outside) == FRIG_OK);
            for (int k = 0; k < P; k++) {
                double fx = idx[k] % S, fy = idx[k] / S;
                double x = a[0] * fx + a[1] * fy + a[4], y = a[2] * fx + a[3] * fy + a[5];
                err = fmax(err, fabs(tex[k] - (axis ? y : x)));
            }
            printf("warp %d, %d channel(s), ramp along %c: max error %.2e, outside %.3f\n", m, channels,
                   axis ? 'y' : 'x', err, outside);
            CHECK(err < 1e-9);
            CHECK(outside == 0);
            frig_image_free(img);
        }
    /* Half the face off the left edge: about half the texels outside, border values clamped. */
    frig_image *img = ramp(100, 1, 1);
    for (int k = 0; k < 68; k++) lm[2 * k] = fs[2 * k] - S / 2.0, lm[2 * k + 1] = fs[2 * k + 1] + 10;
    double outside;
    CHECK(fr_face_warp_sample(ctx, w, img, lm, tex, &outside) == FRIG_OK);
    printf("face half outside: %.3f of texels outside\n", outside);
    CHECK(outside > 0.35 && outside < 0.65);
    for (int k = 0; k < P; k++) {
        double x = idx[k] % S - S / 2.0, y = idx[k] / S + 10;
        if (x < 0) CHECK_NEAR(tex[k], y, 1e-9);
    }
    /* Normalization: zero mean, unit deviation; a flat face is refused. */
    CHECK(fr_face_texture(ctx, w, img, lm, tex, NULL) == FRIG_OK);
    double mean = 0, var = 0;
    for (int k = 0; k < P; k++) mean += tex[k] / P;
    for (int k = 0; k < P; k++) var += (tex[k] - mean) * (tex[k] - mean) / P;
    CHECK_NEAR(mean, 0, 1e-12);
    CHECK_NEAR(var, 1, 1e-12);
    memset(img->pixels, 77, img->stride * (size_t)img->height);
    CHECK(fr_face_texture(ctx, w, img, lm, tex, NULL) == FRIG_ERR_NO_FACE);
    lm[7] = NAN;
    CHECK(fr_face_warp_sample(ctx, w, img, lm, tex, NULL) == FRIG_ERR_INVALID_ARGUMENT);
    CHECK(strstr(frig_ctx_errmsg(ctx), "landmark 3") != NULL);
    frig_image_free(img);
    free(tex);
    fr_face_warp_free(w);
}

static void test_procrustes(frig_ctx *ctx) {
    const double *ref = fr_face_reference_shape();
    enum { N = 12 };
    double shapes[N * 136], aligned[N * 136], mean[136];
    fr_rng r;
    fr_rng_seed(&r, 11);
    /* Exact similarities of one shape: the fit recovers them, and they all align onto one mean. */
    for (int s = 0; s < N; s++) {
        double ang = fr_rng_uniform(&r) * 2 - 1, sc = 50 + 200 * fr_rng_uniform(&r);
        double T[4] = {sc * cos(ang), sc * sin(ang), 500 * fr_rng_uniform(&r), 500 * fr_rng_uniform(&r)}, F[4];
        fr_similarity_apply(68, T, ref, shapes + 136 * s);
        fr_similarity_fit(68, ref, shapes + 136 * s, F);
        for (int k = 0; k < 4; k++) CHECK_NEAR(F[k], T[k], 1e-9 * sc * 10);
        double inv[4], back[136];
        fr_similarity_invert(T, inv);
        fr_similarity_apply(68, inv, shapes + 136 * s, back);
        for (int k = 0; k < 136; k++) CHECK_NEAR(back[k], ref[k], 1e-12);
    }
    CHECK(fr_filter_align_shapes(ctx, N, shapes, aligned, mean) == FRIG_OK);
    double spread = 0, iod = hypot(mean[90] - mean[72], mean[91] - mean[73]);
    for (int s = 0; s < N; s++)
        for (int k = 0; k < 136; k++) spread = fmax(spread, fabs(aligned[136 * s + k] - mean[k]));
    /* The mean is the reference in shape units: inter-ocular distance FR_FILTER_SHAPE_IOD. */
    double scale = FR_FILTER_SHAPE_IOD / hypot(ref[90] - ref[72], ref[91] - ref[73]), off = 0;
    for (int k = 0; k < 136; k++) off = fmax(off, fabs(mean[k] - scale * ref[k]));
    printf("Procrustes of exact similarities: spread %.2e, inter-ocular %.6f, off the gauge %.2e\n", spread, iod, off);
    CHECK(spread < 1e-9);
    CHECK_NEAR(iod, FR_FILTER_SHAPE_IOD, 1e-9);
    CHECK(off < 1e-9);
    /* With noise the mean is the average of the aligned shapes, aligned to the gauge. */
    for (int k = 0; k < N * 136; k++) shapes[k] += 2 * fr_rng_normal(&r);
    int iters = 0;
    CHECK(fr_procrustes_align(ctx, 68, N, shapes, ref, aligned, mean, &iters) == FRIG_OK);
    double avg[136] = {0}, T[4], avg_aligned[136], dev = 0;
    for (int s = 0; s < N; s++)
        for (int k = 0; k < 136; k++) avg[k] += aligned[136 * s + k] / N;
    fr_similarity_fit(68, avg, ref, T);
    fr_similarity_apply(68, T, avg, avg_aligned);
    for (int k = 0; k < 136; k++) dev = fmax(dev, fabs(avg_aligned[k] - mean[k]));
    printf("Procrustes with noise: %d iterations, mean vs aligned average %.2e\n", iters, dev);
    CHECK(dev < 1e-9);
    CHECK(iters < 100);
}

static void test_contact_sheet(frig_ctx *ctx) {
    fr_face_warp *w = NULL;
    CHECK(fr_face_warp_create(ctx, 32, &w) == FRIG_OK);
    int P = fr_face_warp_texels(w);
    double *tex = calloc((size_t)P * 5, sizeof(double));
    for (int k = 0; k < P; k++) tex[k] = 2.0; /* face 0: bright */
    int rounds[5] = {0, 3, 0, 0, 12};
    frig_image *img = NULL;
    double dist[5] = {0.31, NAN, NAN, 0.72, NAN}; /* identity distances: yellow under 0.5, red over */
    CHECK(fr_contact_sheet(ctx, w, 5, tex, rounds, dist, 0.5, 3, &img) == FRIG_OK);
    /* cells of 32 + 2 * 3 + 2 = 40 pixels, plus a 2-pixel margin: 3 x 40 + 2 by 2 x 40 + 2 */
    CHECK(img && frig_image_width(img) == 122 && frig_image_height(img) == 82);
    const uint8_t *px = frig_image_pixels(img);
    size_t stride = frig_image_stride(img);
#define PX(x, y, c) px[(size_t)(y) * stride + 3 * (size_t)(x) + (c)]
    CHECK(PX(2, 2, 0) == 170 && PX(2, 2, 1) == 170);         /* kept: gray frame */
    CHECK(PX(42, 2, 0) == 220 && PX(42, 2, 1) == 0);          /* dropped: red frame */
    CHECK(PX(2 + 3 + 16, 2 + 3 + 16, 0) == 208);              /* bright face: 128 + 40 * 2 */
    CHECK(PX(42 + 3 + 16, 2 + 3 + 16, 0) == 128);             /* flat face */
    /* the round number: red box with white strokes in the corner of the dropped cell */
    int white = 0;
    for (int y = 5; y < 5 + 14; y++)
        for (int x = 45; x < 45 + 18; x++) white += PX(x, y, 0) == 255 && PX(x, y, 1) == 255;
    CHECK(white > 10);
    /* the distances: yellow text at the bottom of cell 0, red at the bottom of cell 3 (row 2) */
    int yellow = 0, red = 0, none = 0;
    for (int y = 2 + 3 + 32 - 9; y < 2 + 3 + 32; y++)
        for (int x = 5; x < 5 + 26; x++) {
            yellow += PX(x, y, 0) == 255 && PX(x, y, 1) == 220 && PX(x, y, 2) == 60;
            red += PX(x, y + 40, 0) == 255 && PX(x, y + 40, 1) == 90;
            none += PX(x + 80, y, 0) == 255 && PX(x + 80, y, 1) == 220; /* cell 2: no distance */
        }
    CHECK(yellow > 10 && red > 10 && none == 0);
#undef PX
    frig_image_free(img);
    CHECK(fr_contact_sheet(ctx, w, 0, tex, rounds, NULL, 0.6, 3, &img) == FRIG_ERR_INVALID_ARGUMENT);
    free(tex);
    fr_face_warp_free(w);
}

int main(void) {
    frig_ctx *ctx = frig_ctx_create();
    test_triangulation(ctx);
    test_warp_exact(ctx);
    test_procrustes(ctx);
    test_contact_sheet(ctx);
    frig_ctx_free(ctx);
    return test_result("test_face_warp");
}
