/* A visual check of the renderer and the drawing used for fitted-mesh overlays (paper
 * sections 4.4 and 5.1): a sphere through a torus's tube rendered with per-pixel Lambert shading, its
 * depth map, and an overlay on a synthetic "photo" with visible vertices, a box, antialiased
 * lines and the whole font. Writes shaded.png, depth.png, overlay.png, font.png into the folder given.
 * Build and run: bench/raster_run.sh. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "image/image.h"
#include "raster/draw.h"
#include "raster/shapes.h"

/* Sphere and torus as one mesh in camera coordinates, the torus tipped toward the camera and
 * the sphere through its tube (the z-buffer draws the intersection curve). */
static fr_shape scene(frig_ctx *ctx, int *sphere_tris) {
    const double sc[3] = {0.09, 0.03, 0.0}, tc[3] = {0.0, 0.0, 0.0};
    fr_shape s, t, all;
    if (fr_shape_sphere(ctx, sc, 0.05, 96, 48, &s) || fr_shape_torus(ctx, tc, 0.11, 0.03, 128, 48, &t)) exit(1);
    all.nv = s.nv + t.nv;
    all.nt = s.nt + t.nt;
    all.xyz = malloc(sizeof(float) * 3 * all.nv);
    all.tris = malloc(sizeof(int32_t) * 3 * all.nt);
    double R[9], tr[3] = {0.0, 0.0, 0.55};
    fr_rotation_from_euler(0.0, 0.0, 0.0, R); /* model (y up) to camera (y down) */
    fr_transform_points(R, tr, s.xyz, s.nv, all.xyz);
    double Rt[9];
    fr_rotation_from_euler(0.3, 0.9, 0.2, Rt);
    fr_transform_points(Rt, tr, t.xyz, t.nv, all.xyz + 3 * s.nv);
    memcpy(all.tris, s.tris, sizeof(int32_t) * 3 * s.nt);
    for (int i = 0; i < 3 * t.nt; i++) all.tris[3 * s.nt + i] = t.tris[i] + s.nv;
    *sphere_tris = s.nt;
    fr_shape_free(&s);
    fr_shape_free(&t);
    return all;
}

static void save(frig_ctx *ctx, const frig_image *img, const char *dir, const char *name) {
    char path[4096];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    if (frig_image_save_png(ctx, img, path)) {
        fprintf(stderr, "%s\n", frig_ctx_errmsg(ctx));
        exit(1);
    }
    printf("wrote %s\n", path);
}

int main(int argc, char **argv) {
    const char *dir = argc > 1 ? argv[1] : ".";
    const int w = 512, h = 512;
    frig_ctx *ctx = frig_ctx_create();
    int nsphere;
    fr_shape m = scene(ctx, &nsphere);
    fr_camera cam = fr_camera_perspective(900.0, w, h);
    fr_raster *r;
    fr_raster_options opt = {FR_RASTER_DEFAULT_NEAR, 1};
    if (fr_raster_create(ctx, w, h, &r) || fr_raster_render(ctx, r, &cam, m.xyz, m.nv, m.tris, m.nt, &opt)) return 1;
    float *normals = malloc(sizeof(float) * 3 * m.nv), *nmap = malloc(sizeof(float) * 3 * w * h);
    fr_mesh_vertex_normals(m.xyz, m.nv, m.tris, m.nt, normals);
    fr_raster_normal_map(r, m.tris, normals, nmap);

    /* 1. per-pixel Lambert shading, light from the upper left of the camera */
    frig_image *shaded = fr_image_new(w, h, 3), *depth = fr_image_new(w, h, 1);
    const double L[3] = {-0.4 / 1.17, -0.5 / 1.17, -0.9 / 1.17};
    double zmin = INFINITY, zmax = -INFINITY;
    for (int i = 0; i < w * h; i++)
        if (r->tri[i] >= 0) zmin = fmin(zmin, r->depth[i]), zmax = fmax(zmax, r->depth[i]);
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            int i = y * w + x;
            uint8_t *p = shaded->pixels + (size_t)y * shaded->stride + 3 * (size_t)x;
            if (r->tri[i] < 0) {
                p[0] = p[1] = p[2] = 30;
                continue;
            }
            const float *n = nmap + 3 * i;
            double lam = fmax(0.0, n[0] * L[0] + n[1] * L[1] + n[2] * L[2]), s = 0.15 + 0.85 * lam;
            const double *col = r->tri[i] < nsphere ? (const double[3]){90, 150, 255} : (const double[3]){255, 160, 60};
            for (int c = 0; c < 3; c++) p[c] = (uint8_t)fmin(255.0, s * col[c] + 0.5);
            depth->pixels[(size_t)y * depth->stride + x] = (uint8_t)(255.0 - 200.0 * (r->depth[i] - zmin) / (zmax - zmin));
        }
    save(ctx, shaded, dir, "shaded.png");
    save(ctx, depth, dir, "depth.png");

    /* 2. overlay on a synthetic photo, with visible vertices, a box, lines and text */
    frig_image *photo = fr_image_new(w, h, 3);
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            uint8_t *p = photo->pixels + (size_t)y * photo->stride + 3 * (size_t)x;
            int check = ((x / 32) + (y / 32)) & 1;
            p[0] = (uint8_t)(60 + x / 4 + 20 * check), p[1] = (uint8_t)(70 + y / 5 + 20 * check), p[2] = 90;
        }
    const uint8_t skin[3] = {235, 200, 170}, green[3] = {40, 255, 80}, red[3] = {255, 50, 50},
                  yellow[3] = {255, 230, 0}, white[3] = {255, 255, 255};
    fr_overlay_mesh(ctx, photo, r, m.tris, normals, skin, 0.6);
    uint8_t *vis = malloc((size_t)m.nv);
    fr_raster_visible_vertices(r, &cam, m.xyz, m.nv, m.tris, 1e-3, vis);
    int x0 = w, y0 = h, x1 = 0, y1 = 0;
    for (int i = 0; i < m.nv; i += 37) {
        double p[3] = {m.xyz[3 * i], m.xyz[3 * i + 1], m.xyz[3 * i + 2]}, uv[2];
        if (!fr_camera_project(&cam, p, uv)) continue;
        fr_draw_disc(photo, uv[0], uv[1], vis[i] ? 1.8 : 0.9, vis[i] ? green : red, 1); /* hidden: small, red */
        x0 = (int)fmin(x0, uv[0]), y0 = (int)fmin(y0, uv[1]), x1 = (int)fmax(x1, uv[0]), y1 = (int)fmax(y1, uv[1]);
    }
    fr_draw_rect(photo, x0 - 4, y0 - 4, x1 + 4, y1 + 4, 2, yellow);
    for (int k = 0; k < 12; k++) {
        double a = 2 * M_PI * k / 12;
        fr_draw_line(photo, 440 + 12 * cos(a), 70 + 12 * sin(a), 440 + 60 * cos(a), 70 + 60 * sin(a), 1.0 + k / 4.0,
                     white, k % 2);
    }
    fr_draw_text(photo, 8, h - 60, "kept", 2, green);
    fr_draw_text(photo, 70, h - 60, "r2 e=3.1", 2, yellow);
    char sheet[200];
    int n = 0;
    for (int c = 32; c < 127; c++) {
        sheet[n++] = (char)c;
        if ((c - 31) % 32 == 0) sheet[n++] = '\n';
    }
    sheet[n] = 0;
    fr_draw_text(photo, 8, 8, sheet, 2, white);
    fr_draw_text(photo, -5, h - 10, "clipped at the border", 3, red);
    save(ctx, photo, dir, "overlay.png");
    frig_image *font = fr_image_new(6 * 32 * 4 + 16, 9 * 3 * 4 + 16, 3);
    fr_draw_text(font, 8, 8, sheet, 4, white);
    save(ctx, font, dir, "font.png");
    frig_image_free(font);

    free(vis);
    free(normals);
    free(nmap);
    frig_image_free(shaded);
    frig_image_free(depth);
    frig_image_free(photo);
    fr_raster_free(r);
    fr_shape_free(&m);
    frig_ctx_free(ctx);
    return 0;
}
