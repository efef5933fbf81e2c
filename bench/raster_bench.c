/* Rendering speed for photo-consistency (paper section 4.4) and shape from shading (5.1):
 * a ~50k-triangle sphere (the ICT head has ~52k triangles once its quads are split) filling
 * about as much of the frame as a face does, at 512x512 and 1600x1200, with and without
 * back-face culling, plus the per-pixel normal map and vertex visibility that follow a render.
 * Build and run: bench/raster_run.sh (after building build/). */
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "raster/raster.h"
#include "raster/shapes.h"

static double now(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static void run(frig_ctx *ctx, const fr_shape *s, const float *normals, int w, int h, double fill) {
    fr_raster *r;
    if (fr_raster_create(ctx, w, h, &r)) exit(1);
    /* the sphere (radius 0.1 m at 0.5 m) spans 'fill' of the image height */
    fr_camera cam = fr_camera_perspective(fill * h * 0.5 / 0.2, w, h);
    float *nmap = malloc(sizeof(float) * 3 * (size_t)w * h);
    uint8_t *vis = malloc((size_t)s->nv);
    for (int cull = 0; cull < 2; cull++) {
        fr_raster_options opt = {FR_RASTER_DEFAULT_NEAR, cull};
        int reps = w * h > 1000000 ? 20 : 50;
        fr_raster_render(ctx, r, &cam, s->xyz, s->nv, s->tris, s->nt, &opt); /* warm up */
        double t0 = now();
        for (int i = 0; i < reps; i++) fr_raster_render(ctx, r, &cam, s->xyz, s->nv, s->tris, s->nt, &opt);
        double t_render = (now() - t0) / reps;
        long covered = 0;
        for (long i = 0; i < (long)w * h; i++) covered += r->tri[i] >= 0;
        printf("%4dx%-4d  %6d tris  cull=%d  covered %7ld px  render %7.2f ms", w, h, s->nt, cull, covered,
               1e3 * t_render);
        if (cull) {
            t0 = now();
            for (int i = 0; i < reps; i++) fr_raster_normal_map(r, s->tris, normals, nmap);
            double t_nmap = (now() - t0) / reps;
            t0 = now();
            for (int i = 0; i < reps; i++) fr_raster_visible_vertices(r, &cam, s->xyz, s->nv, s->tris, 1e-3, vis);
            double t_vis = (now() - t0) / reps;
            printf("  normal map %6.2f ms  visibility %5.2f ms", 1e3 * t_nmap, 1e3 * t_vis);
        }
        printf("\n");
    }
    free(nmap);
    free(vis);
    fr_raster_free(r);
}

int main(void) {
    frig_ctx *ctx = frig_ctx_create();
    const double centre[3] = {0.0, 0.0, 0.5};
    fr_shape s;
    if (!ctx || fr_shape_sphere(ctx, centre, 0.1, 224, 112, &s)) return 1;
    float *normals = malloc(sizeof(float) * 3 * s.nv);
    fr_mesh_vertex_normals(s.xyz, s.nv, s.tris, s.nt, normals);
    printf("sphere filling 60%% of the image height (a close face crop):\n");
    run(ctx, &s, normals, 512, 512, 0.6);
    run(ctx, &s, normals, 1600, 1200, 0.6);
    printf("sphere filling 25%% (a face in a wider photo):\n");
    run(ctx, &s, normals, 1600, 1200, 0.25);
    free(normals);
    fr_shape_free(&s);
    frig_ctx_free(ctx);
    return 0;
}
