/* 2D drawing (lib/raster/draw.c, font.c, overlay.c): exact pixel sets of plain lines, boxes
 * and discs, coverage sums of antialiased shapes against their areas, blended triangles that
 * share an edge (each pixel blended once), font glyphs against their pictures and set-pixel
 * counts, clipping far outside the image (ASan watches the writes), gray images, and the mesh
 * overlay's Lambert shade. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "image/image.h"
#include "raster/draw.h"
#include "raster/shapes.h"
#include "testing.h"

static const uint8_t WHITE[3] = {255, 255, 255};

static uint8_t px(const frig_image *img, int x, int y, int c) {
    return img->pixels[(size_t)y * img->stride + (size_t)x * img->channels + c];
}

static long count_set(const frig_image *img) {
    long n = 0;
    for (int y = 0; y < img->height; y++)
        for (int x = 0; x < img->width; x++) n += px(img, x, y, 0) != 0;
    return n;
}

static double coverage_sum(const frig_image *img) {
    double s = 0;
    for (int y = 0; y < img->height; y++)
        for (int x = 0; x < img->width; x++) s += px(img, x, y, 0) / 255.0;
    return s;
}

static void clear(frig_image *img) { memset(img->pixels, 0, img->stride * (size_t)img->height); }

static void test_lines(void) {
    frig_image *img = fr_image_new(40, 30, 3);
    /* plain horizontal: exactly (2..10, 5) */
    fr_draw_line(img, 2, 5, 10, 5, 1.0, WHITE, 0);
    int bad = 0;
    for (int y = 0; y < 30; y++)
        for (int x = 0; x < 40; x++) bad += (px(img, x, y, 0) == 255) != (y == 5 && x >= 2 && x <= 10);
    CHECK(bad == 0);
    CHECK(count_set(img) == 9);
    /* plain 45 degrees: the diagonal pixels only (8-connected) */
    clear(img);
    fr_draw_line(img, 3, 4, 15, 16, 1.0, WHITE, 0);
    bad = 0;
    for (int i = 3; i <= 15; i++) bad += px(img, i, i + 1, 0) != 255;
    CHECK(bad == 0 && count_set(img) == 13);
    /* steep plain line: one pixel per row */
    clear(img);
    fr_draw_line(img, 10.2, 2, 14.7, 25, 1.0, WHITE, 0);
    for (int y = 0; y < 30; y++) {
        int n = 0;
        for (int x = 0; x < 40; x++) n += px(img, x, y, 0) != 0;
        CHECK(n == (y >= 2 && y <= 25));
    }
    /* plain thickness 3: pixel centres within 1.5 of the segment: 3 rows of 11 (caps add 1 a side) */
    clear(img);
    fr_draw_line(img, 2, 5, 10, 5, 3.0, WHITE, 0);
    CHECK(count_set(img) == 33);
    CHECK(px(img, 1, 4, 0) == 255 && px(img, 0, 5, 0) == 0 && px(img, 5, 3, 0) == 0);
    /* antialiased: the coverage sums to the capsule's area (2 r L + pi r^2) */
    frig_image *big = fr_image_new(200, 150, 3);
    const double L = hypot(150.0 - 20.3, 120.0 - 10.7);
    for (int k = 0; k < 3; k++) {
        double thick = 1.0 + k * 1.5;
        clear(big);
        fr_draw_line(big, 20.3, 10.7, 150.0, 120.0, thick, WHITE, 1);
        double area = thick * L + M_PI * thick * thick / 4;
        double sum = coverage_sum(big);
        printf("antialiased line, thickness %.1f: coverage %.1f vs area %.1f (%.2f%%)\n", thick, sum, area,
               100 * (sum - area) / area);
        CHECK(fabs(sum - area) < 0.01 * area);
    }
    /* antialiased horizontal on a pixel row stays crisp; half way between rows splits evenly */
    clear(img);
    fr_draw_line(img, 2, 5, 10, 5, 1.0, WHITE, 1);
    CHECK(px(img, 6, 5, 0) == 255 && px(img, 6, 4, 0) == 0 && px(img, 6, 6, 0) == 0);
    clear(img);
    fr_draw_line(img, 2, 5.5, 10, 5.5, 1.0, WHITE, 1);
    CHECK(px(img, 6, 5, 0) == 128 && px(img, 6, 6, 0) == 128);
    frig_image_free(big);
    frig_image_free(img);
}

static void test_discs_and_boxes(void) {
    frig_image *img = fr_image_new(40, 30, 3);
    /* plain disc: the lattice points within the radius (Gauss circle count) */
    const double r = 5.3;
    fr_draw_disc(img, 20, 15, r, WHITE, 0);
    long want = 0;
    for (int j = -6; j <= 6; j++)
        for (int i = -6; i <= 6; i++) want += i * i + j * j <= r * r;
    CHECK(count_set(img) == want);
    clear(img);
    fr_draw_disc(img, 19.37, 14.81, r, WHITE, 1);
    double sum = coverage_sum(img), area = M_PI * r * r;
    printf("antialiased disc r = %.1f: coverage %.2f vs area %.2f (%.2f%%); plain disc %ld pixels\n", r, sum, area,
           100 * (sum - area) / area, want);
    CHECK(fabs(sum - area) < 0.01 * area);
    /* box outline, 2 pixels thick, inward: 10 x 8 minus the 6 x 4 inside */
    clear(img);
    fr_draw_rect(img, 12, 9, 3, 2, 2, WHITE);
    CHECK(count_set(img) == 10 * 8 - 6 * 4);
    CHECK(px(img, 3, 2, 0) == 255 && px(img, 4, 3, 0) == 255 && px(img, 5, 4, 0) == 0);
    /* blended box */
    memset(img->pixels, 100, img->stride * (size_t)img->height);
    const uint8_t c200[3] = {200, 200, 200};
    fr_fill_rect(img, 1, 1, 4, 4, c200, 0.5);
    CHECK(px(img, 1, 1, 0) == 150 && px(img, 4, 4, 2) == 150 && px(img, 5, 4, 0) == 100);
    frig_image_free(img);
}

static void test_triangles(void) {
    frig_image *img = fr_image_new(20, 14, 3);
    /* the rectangle [2, 10] x [3, 8] as two blended triangles: 40 pixels blended once each */
    double a[2] = {2, 3}, b[2] = {10, 3}, c[2] = {10, 8}, d[2] = {2, 8};
    fr_fill_triangle(img, a, b, c, WHITE, 0.5);
    fr_fill_triangle(img, a, c, d, WHITE, 0.5);
    long once = 0, other = 0;
    for (int y = 0; y < 14; y++)
        for (int x = 0; x < 20; x++) {
            int v = px(img, x, y, 1);
            int inside = x >= 2 && x <= 9 && y >= 3 && y <= 7;
            once += inside && v == 128;
            other += inside ? v != 128 : v != 0;
        }
    CHECK(once == 40);
    CHECK(other == 0);
    frig_image_free(img);
}

static void test_text(void) {
    frig_image *img = fr_image_new(60, 30, 3);
    static const char *one[7] = {"..#..", ".##..", "..#..", "..#..", "..#..", "..#..", ".###."};
    long n = fr_draw_text(img, 1, 2, "1", 1, WHITE);
    int bad = 0, expect = 0;
    for (int y = 0; y < 30; y++)
        for (int x = 0; x < 60; x++) {
            int in = x >= 1 && x < 6 && y >= 2 && y < 9 && one[y - 2][x - 1] == '#';
            expect += in;
            bad += (px(img, x, y, 0) == 255) != in;
        }
    CHECK(bad == 0 && n == expect && expect == 10);
    /* "kept": k 12 + e 14 + p 12 + t 11 font pixels (counted from the glyph pictures) */
    clear(img);
    CHECK(fr_draw_text(img, 0, 0, "kept", 1, WHITE) == 49);
    CHECK(count_set(img) == 49);
    clear(img);
    CHECK(fr_draw_text(img, 2, 3, "kept", 2, WHITE) == 4 * 49);
    CHECK(count_set(img) == 4 * 49);
    int w, h;
    fr_text_size("kept", 2, &w, &h);
    CHECK(w == 2 * (4 * 6 - 1) && h == 14);
    fr_text_size("ab\ncde", 1, &w, &h);
    CHECK(w == 17 && h == 16);
    /* unknown characters draw as '?' */
    clear(img);
    long q = fr_draw_text(img, 0, 0, "?", 1, WHITE);
    clear(img);
    CHECK(fr_draw_text(img, 0, 0, "\x01", 1, WHITE) == q && q > 0);
    /* clipped text counts only what lands in the image */
    clear(img);
    long part = fr_draw_text(img, 57, 25, "r2 e=3.1", 1, WHITE);
    CHECK(part == count_set(img) && part > 0 && part < 20);
    frig_image_free(img);
}

static void test_clipping(void) {
    /* shapes reaching far outside a 7 x 5 image: under ASan any write outside the pixel block
     * fails the test; inside, every pixel ends up set */
    frig_image *img = fr_image_new(7, 5, 3);
    const double far = 1e9;
    fr_draw_line(img, -far, -far, far, far, 3.0, WHITE, 1);
    fr_draw_line(img, -far, 2, far, 2, 1.0, WHITE, 0);
    fr_draw_line(img, 3, -50, 3, 50, 5.0, WHITE, 0);
    fr_draw_line(img, -10, -10, -3, -3, 2.0, WHITE, 1);
    fr_draw_line(img, NAN, 0, 3, 3, 1.0, WHITE, 1);
    fr_draw_line(img, 0, 0, INFINITY, 3, 1.0, WHITE, 0);
    fr_draw_disc(img, 6.5, 4.5, 40.0, WHITE, 1);
    fr_draw_disc(img, -1e12, 3, 2.0, WHITE, 0);
    fr_draw_rect(img, -5, -5, 100, 100, 3, WHITE);
    fr_fill_rect(img, -1000000, -3, 1000000, 1, WHITE, 0.3);
    double a[2] = {-1e6, -1e6}, b[2] = {1e6, 0}, c[2] = {3, 1e6};
    fr_fill_triangle(img, a, b, c, WHITE, 0.7);
    fr_draw_text(img, -3, -4, "Hello", 3, WHITE);
    fr_draw_text(img, 2000000000, 5, "x", 1000, WHITE);
    fr_draw_blend_pixel(img, -1, 0, WHITE, 1.0);
    fr_draw_blend_pixel(img, 7, 0, WHITE, 1.0);
    CHECK(count_set(img) == 35); /* the disc of radius 40 covers everything */
    /* gray images get the colour's luma */
    frig_image *g = fr_image_new(8, 8, 1);
    const uint8_t red[3] = {255, 0, 0};
    fr_draw_disc(g, 3, 3, 1.0, red, 0);
    CHECK(px(g, 3, 3, 0) == 76); /* 0.299 * 255 */
    frig_image_free(g);
    frig_image_free(img);
}

static void test_overlay(void) {
    frig_ctx *ctx = frig_ctx_create();
    const int w = 96, h = 80;
    const double centre[3] = {0, 0, 0.5};
    fr_shape s;
    CHECK(fr_shape_sphere(ctx, centre, 0.1, 48, 24, &s) == FRIG_OK);
    fr_camera cam = fr_camera_perspective(150.0, w, h);
    fr_raster *r;
    CHECK(fr_raster_create(ctx, w, h, &r) == FRIG_OK);
    CHECK(fr_raster_render(ctx, r, &cam, s.xyz, s.nv, s.tris, s.nt, NULL) == FRIG_OK);
    float *normals = malloc(sizeof(float) * 3 * s.nv);
    fr_mesh_vertex_normals(s.xyz, s.nv, s.tris, s.nt, normals);
    frig_image *img = fr_image_new(w, h, 3);
    memset(img->pixels, 40, img->stride * (size_t)h);
    const uint8_t grey[3] = {200, 200, 200};
    CHECK(fr_overlay_mesh(ctx, img, r, s.tris, normals, grey, 1.0) == FRIG_OK);
    /* the sphere's centre faces the camera: n = (0, 0, -1), n . l = 1 / sqrt(1.09) */
    double shade = 0.25 + 0.75 / sqrt(1.09);
    int cx = (w - 1) / 2, cy = (h - 1) / 2;
    CHECK(abs(px(img, cx, cy, 0) - (int)floor(200 * shade + 0.5)) <= 1);
    CHECK(px(img, 0, 0, 0) == 40);
    /* the lit side (top, facing the light from above) is brighter than the bottom rim */
    CHECK(px(img, cx, cy - 20, 1) > px(img, cx, cy + 20, 1));
    /* half blend */
    memset(img->pixels, 40, img->stride * (size_t)h);
    CHECK(fr_overlay_mesh(ctx, img, r, s.tris, normals, grey, 0.5) == FRIG_OK);
    CHECK(abs(px(img, cx, cy, 2) - (int)floor(40 + 0.5 * (floor(200 * shade + 0.5) - 40) + 0.5)) <= 1);
    frig_image *small = fr_image_new(w - 1, h, 3);
    CHECK(fr_overlay_mesh(ctx, small, r, s.tris, normals, grey, 0.5) == FRIG_ERR_INVALID_ARGUMENT);
    frig_image_free(small);
    frig_image_free(img);
    free(normals);
    fr_raster_free(r);
    fr_shape_free(&s);
    frig_ctx_free(ctx);
}

int main(void) {
    test_lines();
    test_discs_and_boxes();
    test_triangles();
    test_text();
    test_clipping();
    test_overlay();
    return test_result("test_draw");
}
