/* A picture of two rigs side by side (the retarget stage's result next to the rig it started
 * from, for a person to look at): rows = rigs, columns = the neutral seen from the front and
 * turned, then a few expressions (the paper's Figures 5.5, 5.7, 5.8 show blendshapes this way),
 * each Lambert-shaded by the rasterizer. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "frig/retarget.h"
#include "image/image.h"
#include "model/model.h"
#include "raster/draw.h"
#include "raster/raster.h"
#include "raster/rotation.h"
#include "rig/rig.h"

#define CELL 280
#define LABEL 18
#define FACE_REGION_END 9409

typedef struct column {
    const char *title;
    const char *shapes[2];
    double yaw_deg;
} column;

static const column COLUMNS[] = {
    {"neutral", {NULL, NULL}, 0},          {"neutral 35 deg", {NULL, NULL}, 35},
    {"jawOpen", {"jawOpen", NULL}, 0},     {"smile", {"mouthSmile_L", "mouthSmile_R"}, 0},
    {"blink", {"eyeBlink_L", "eyeBlink_R"}, 0}, {"brows up", {"browInnerUp_L", "browInnerUp_R"}, 0},
    {"pucker", {"mouthPucker", NULL}, 20},
};
#define N_COLUMNS (int)(sizeof COLUMNS / sizeof COLUMNS[0])

/* The triangles worth drawing: all but the transparent eye overlays and the lashes. */
static int32_t *drawn_triangles(const frig_model *m, int *count) {
    int nt = frig_model_triangle_count(m), n = 0;
    const int32_t *t = frig_model_triangles(m);
    int skip_first = frig_model_vertex_count(m), r = frig_model_region_find(m, "lacrimal_fluid_left");
    if (r >= 0) frig_model_region(m, r, NULL, &skip_first, NULL);
    int32_t *out = malloc(sizeof(int32_t) * 3 * ((size_t)nt + 1));
    if (!out) return NULL;
    for (int i = 0; i < nt; i++) {
        if (t[3 * i] >= skip_first || t[3 * i + 1] >= skip_first || t[3 * i + 2] >= skip_first) continue;
        memcpy(out + 3 * (size_t)n++, t + 3 * (size_t)i, sizeof(int32_t) * 3);
    }
    *count = n;
    return out;
}

static frig_status draw_cell(frig_ctx *ctx, const frig_rig *rig, const column *c, const int32_t *tris, int nt,
                             const double centre[3], double scale, fr_raster *r, frig_image *cell) {
    int nv = frig_rig_vertex_count(rig), S = frig_rig_shape_count(rig);
    double *w = calloc((size_t)S + 1, sizeof(double));
    float *x = malloc(sizeof(float) * 3 * (size_t)nv), *xc = malloc(sizeof(float) * 3 * (size_t)nv);
    float *n = malloc(sizeof(float) * 3 * (size_t)nv);
    frig_status s = w && x && xc && n ? FRIG_OK : fr_nomem(ctx, "the rig picture");
    for (int k = 0; k < 2 && !s; k++) {
        int j = c->shapes[k] ? frig_rig_shape_find(rig, c->shapes[k]) : -1;
        if (j >= 0) w[j] = 1;
    }
    if (!s) s = frig_rig_eval(ctx, rig, w, x);
    if (!s) {
        /* Weak perspective from the front (or turned): the same framing for every rig. */
        double R[9], t[3];
        fr_rotation_from_euler(c->yaw_deg * M_PI / 180, 0, 0, R);
        for (int i = 0; i < 3; i++) t[i] = -(R[3 * i] * centre[0] + R[3 * i + 1] * centre[1] + R[3 * i + 2] * centre[2]);
        t[2] += 1.0;
        fr_transform_points(R, t, x, nv, xc);
        fr_mesh_vertex_normals(xc, nv, tris, nt, n);
        fr_camera cam = fr_camera_weak(scale, CELL, CELL);
        fr_raster_options opt = {FR_RASTER_DEFAULT_NEAR, 1};
        s = fr_raster_render(ctx, r, &cam, xc, nv, tris, nt, &opt);
        const uint8_t skin[3] = {214, 190, 170};
        if (!s) s = fr_overlay_mesh(ctx, cell, r, tris, n, skin, 1.0);
    }
    free(w), free(x), free(xc), free(n);
    return s;
}

static void paste(frig_image *dst, const frig_image *src, int x0, int y0) {
    for (int y = 0; y < src->height; y++)
        memcpy(dst->pixels + (size_t)(y0 + y) * dst->stride + (size_t)x0 * 3, src->pixels + (size_t)y * src->stride,
               (size_t)src->width * 3);
}

frig_status frig_retarget_write_sheet(frig_ctx *ctx, const frig_model *model, const frig_rig *const *rigs,
                                      const char *const *labels, int count, const char *path) {
    if (!model || !rigs || count < 1 || !path)
        return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_retarget_write_sheet: no rig or no path");
    for (int i = 0; i < count; i++)
        if (!rigs[i] || frig_rig_vertex_count(rigs[i]) != frig_model_vertex_count(model))
            return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_retarget_write_sheet: rig %d is not of the model", i);
    int nt = 0;
    int32_t *tris = drawn_triangles(model, &nt);
    frig_image *sheet = NULL, *cell = NULL;
    fr_raster *r = NULL;
    frig_status s = tris ? FRIG_OK : fr_nomem(ctx, "the rig picture");
    if (!s) s = frig_image_create(ctx, N_COLUMNS * CELL, count * (CELL + LABEL) + LABEL, 3, &sheet);
    if (!s) s = frig_image_create(ctx, CELL, CELL, 3, &cell);
    if (!s) s = fr_raster_create(ctx, CELL, CELL, &r);
    /* Framing: the first rig's face region, centred, 1.25 times its height in the cell. */
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY}, centre[3];
    const float *n0 = s ? NULL : frig_rig_neutral(rigs[0]);
    for (int v = 0; !s && v < FACE_REGION_END && v < frig_rig_vertex_count(rigs[0]); v++)
        for (int k = 0; k < 3; k++) lo[k] = fmin(lo[k], n0[3 * v + k]), hi[k] = fmax(hi[k], n0[3 * v + k]);
    for (int k = 0; k < 3; k++) centre[k] = 0.5 * (lo[k] + hi[k]);
    double scale = s ? 1 : CELL / (1.25 * (hi[1] - lo[1]));
    const uint8_t white[3] = {235, 235, 235}, grey[3] = {70, 70, 78};
    if (!s) {
        memset(sheet->pixels, 40, (size_t)sheet->stride * sheet->height);
        for (int c = 0; c < N_COLUMNS; c++) fr_draw_text(sheet, c * CELL + 6, 4, COLUMNS[c].title, 2, white);
    }
    for (int i = 0; i < count && !s; i++)
        for (int c = 0; c < N_COLUMNS && !s; c++) {
            memset(cell->pixels, grey[0], (size_t)cell->stride * cell->height);
            s = draw_cell(ctx, rigs[i], &COLUMNS[c], tris, nt, centre, scale, r, cell);
            if (!s) paste(sheet, cell, c * CELL, LABEL + i * (CELL + LABEL) + LABEL);
            if (!s && c == 0 && labels && labels[i])
                fr_draw_text(sheet, 6, LABEL + i * (CELL + LABEL) + 2, labels[i], 2, white);
        }
    if (!s) s = frig_image_save_png(ctx, sheet, path);
    fr_raster_free(r);
    frig_image_free(cell);
    frig_image_free(sheet);
    free(tris);
    return s;
}
