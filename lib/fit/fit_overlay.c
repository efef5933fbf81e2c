/* Pictures of the fit for people who would rather look than read (paper section 4.3,
 * Figures 4.4-4.6): each photo with its fitted face mesh shaded over it, the detected
 * landmarks (green), the re-projected model landmarks (red) and the error. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "fit/landmark_vertices.h"
#include "frig/fit.h"
#include "image/image.h"
#include "io/file.h"
#include "raster/draw.h"
#include "raster/raster.h"
#include "workspace/photoset.h"

/* The narrow face region's triangles (forehead to chin, between the ears): what the
 * landmarks constrain, without the neck and scalp that would hide the photo. */
static int face_triangles(const frig_model *m, int32_t **out) {
    int face_first = 0, face_count = frig_model_vertex_count(m);
    int r = frig_model_region_find(m, "narrow_face");
    if (r >= 0) frig_model_region(m, r, NULL, &face_first, &face_count);
    int nt = frig_model_triangle_count(m), n = 0;
    const int32_t *t = frig_model_triangles(m);
    int32_t *f = malloc(sizeof(int32_t) * 3 * (size_t)(nt + 1));
    if (!f) return -1;
    for (int i = 0; i < nt; i++) {
        int in = 1;
        for (int c = 0; c < 3; c++)
            if (t[3 * i + c] < face_first || t[3 * i + c] >= face_first + face_count) in = 0;
        if (in) memcpy(f + 3 * (size_t)n++, t + 3 * i, sizeof(int32_t) * 3);
    }
    *out = f;
    return n;
}

/* Model weights (all expressions of the model) from the set's fitted expressions. */
static void model_expression(const frig_model *m, const frig_photoset *set, const double *fitted, double *all) {
    memset(all, 0, sizeof(double) * (size_t)frig_model_expression_count(m));
    for (int k = 0; k < set->n_expressions; k++) {
        int j = frig_model_expression_find(m, set->expression_names[k]);
        if (j >= 0) all[j] = fitted[k];
    }
}

static frig_status draw_one(frig_ctx *ctx, const frig_model *m, const frig_photoset *set, size_t i,
                            const int32_t *tris, int nt, const char *dir) {
    const fr_photo *p = &set->photos[i];
    frig_image *img = NULL;
    frig_status s = frig_image_load(ctx, p->path, FRIG_LOAD_DEFAULT, &img);
    if (s) return s;
    int nv = frig_model_vertex_count(m);
    float *xyz = malloc(sizeof(float) * 3 * (size_t)nv * 3);
    double *exp_all = malloc(sizeof(double) * (size_t)(frig_model_expression_count(m) + 1));
    fr_raster *r = NULL;
    if (!xyz || !exp_all) s = fr_nomem(ctx, "an overlay");
    double id_all[1024] = {0};
    int nid = frig_model_identity_count(m);
    for (int k = 0; k < set->n_identity && k < nid && k < 1024; k++) id_all[k] = set->identity[k];
    if (!s) {
        model_expression(m, set, p->fit_expression, exp_all);
        s = frig_model_eval(ctx, m, id_all, exp_all, xyz);
    }
    if (!s) s = fr_raster_create(ctx, img->width, img->height, &r);
    if (!s) {
        float *xc = xyz + 3 * (size_t)nv, *nrm = xc + 3 * (size_t)nv;
        fr_transform_points(p->fit_rotation, p->fit_translation, xyz, nv, xc);
        fr_camera cam = p->fit_perspective ? fr_camera_perspective(p->fit_focal, img->width, img->height)
                                           : fr_camera_weak(p->fit_focal, img->width, img->height);
        fr_raster_options ro = {FR_RASTER_DEFAULT_NEAR, 1};
        s = fr_raster_render(ctx, r, &cam, xc, nv, tris, nt, &ro);
        if (!s) {
            fr_mesh_vertex_normals(xc, nv, tris, nt, nrm);
            const uint8_t skin[3] = {235, 205, 180};
            s = fr_overlay_mesh(ctx, img, r, tris, nrm, skin, 0.55);
        }
        double size = fmax(img->width, img->height);
        double rad = fmax(1.0, size / 300.0);
        const fr_face *f = fr_photo_subject(p);
        const uint8_t green[3] = {40, 220, 60}, red[3] = {240, 40, 40}, white[3] = {255, 255, 255};
        if (!s && f)
            for (int k = 0; k < FRIG_LANDMARK_COUNT; k++)
                fr_draw_disc(img, f->landmarks[2 * k], f->landmarks[2 * k + 1], rad, green, 1);
        int32_t lm[FRIG_LANDMARK_COUNT];
        fr_fit_landmark_vertices(ctx, m, lm);
        for (int k = 0; !s && k < FRIG_LANDMARK_COUNT; k++) {
            double uv[2];
            fr_project_points(&cam, p->fit_rotation, p->fit_translation, xyz + 3 * (size_t)lm[k], 1, uv, NULL);
            fr_draw_disc(img, uv[0], uv[1], rad * 0.8, red, 1);
        }
        char label[96];
        snprintf(label, sizeof label, "%.1f px RMS%s", p->fit_error_px, p->fit_in_joint ? ", joint subset" : "");
        /* Readable on a 250 px LFW crop and on a 1600 px photo alike. */
        int side = img->width > img->height ? img->width : img->height;
        int scale = (int)fmax(1.0, round(side / 320.0)), tw, th;
        fr_text_size(label, scale, &tw, &th);
        static const uint8_t black[3] = {0, 0, 0};
        if (!s) fr_fill_rect(img, 0, 0, 4 + tw + 2 * scale, 4 + th + 2 * scale, black, 0.6);
        if (!s) fr_draw_text(img, 4, 4, label, scale, white);
    }
    if (!s) {
        const char *base = fr_path_base(p->path);
        char name[512];
        snprintf(name, sizeof name, "%s", base);
        char *dot = strrchr(name, '.');
        if (dot) *dot = 0;
        char *out = fr_path_join(dir, name);
        char *path = out ? malloc(strlen(out) + 8) : NULL;
        if (!path) s = fr_nomem(ctx, "a path");
        else {
            sprintf(path, "%s.jpg", out);
            s = frig_image_save_jpeg(ctx, img, path);
        }
        free(out);
        free(path);
    }
    fr_raster_free(r);
    free(xyz);
    free(exp_all);
    frig_image_free(img);
    return s;
}

frig_status frig_fit_write_overlays(frig_ctx *ctx, const frig_model *model, const frig_photoset *set,
                                    const char *dir) {
    if (!model || !set || !dir) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_fit_write_overlays: NULL");
    frig_status s = fr_make_dirs(ctx, dir);
    if (s) return s;
    int32_t *tris = NULL;
    int nt = face_triangles(model, &tris);
    if (nt < 0) return fr_nomem(ctx, "overlay triangles");
    atomic_size_t done;
    atomic_init(&done, 0);
    int failed = 0;
    size_t n = set->count;
    int saved = fr_blas_serial_begin();
#pragma omp parallel for schedule(dynamic) num_threads(fr_threads(ctx))
    for (size_t i = 0; i < n; i++) {
        if (failed || fr_cancelled(ctx) || !set->photos[i].fitted) continue;
        frig_ctx *local = frig_ctx_create();
        if (!local || draw_one(local, model, set, i, tris, nt, dir)) {
            /* A photo that cannot be drawn stops the run with its message. */
            fr_error(ctx, local ? frig_ctx_status(local) : FRIG_ERR_NO_MEMORY, "%s",
                     local ? frig_ctx_errmsg(local) : "out of memory");
            failed = 1;
        }
        frig_ctx_free(local);
        fr_progress_tick(ctx, &done, "fit.overlays", n);
    }
    fr_blas_serial_end(saved);
    free(tris);
    if (failed) return frig_ctx_status(ctx);
    return fr_check_cancel(ctx, "fit.overlays");
}
