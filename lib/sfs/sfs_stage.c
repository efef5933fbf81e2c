/* The sfs stage over a photo set (paper section 5.1, Algorithms 4-5): runs the computation
 * (sfs_run.c), then per photo the region selection (eq. 5.15), the check that the photo's
 * colours agree with the subject's albedo, the pose refinement against the recovered depth, the
 * cloud in the rig's head frame and the picture; records statuses and results in the set. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/clock.h"
#include "core/context.h"
#include "core/select.h"
#include "frig/sfs.h"
#include "image/image.h"
#include "image/pull_push.h"
#include "image/srgb.h"
#include "io/file.h"
#include "raster/rotation.h"
#include "sfs/sfs_photo.h"
#include "sfs/sfs_run.h"
#include "workspace/photoset.h"

#define SEEN_SHARE 0.3 /* of the median seen texel's view weight (docs/sfs.md) */
#define SHADOW_SHARE 0.6 /* off the narrow face: texels darker than this times the skin are not seen */
#define BRIGHT_QUANTILE 0.8 /* texels seen less than the median: at most this quantile of the others' brightness */

typedef struct finish_job {
    fr_sfs_run *r;
    const frig_photoset *set;
    const char *overlay_dir;
    float **xyz, **nrm, **conf; /* per view: the cloud, then its margin */
    int *count, *margin;
} finish_job;

/* The view's pixels kept as 'which' (1 the cloud, 2 its margin) as points in the head frame,
 * R^T (X_c - t) and R^T n_c at the refined pose; returns how many. */
static int cloud_points(const fr_sfs_view *v, int which, float *xyz, float *nrm, float *conf) {
    const double *R = v->R_refined, *t = v->t_refined;
    size_t n = (size_t)v->w * v->h;
    int c = 0;
    for (size_t i = 0; i < n; i++) {
        if (v->kept[i] != which) continue;
        int x = (int)(i % v->w), y = (int)(i / v->w);
        double X[3] = {v->z[i] * (x - v->cam.cx) / v->cam.f - t[0], v->z[i] * (y - v->cam.cy) / v->cam.f - t[1],
                       v->z[i] - t[2]};
        const float *nc = v->normal + 3 * i;
        for (int q = 0; q < 3; q++) {
            xyz[3 * c + q] = (float)(R[q] * X[0] + R[3 + q] * X[1] + R[6 + q] * X[2]);
            nrm[3 * c + q] = (float)(R[q] * nc[0] + R[3 + q] * nc[1] + R[6 + q] * nc[2]);
        }
        conf[c++] = v->confidence[i];
    }
    return c;
}

static frig_status finish_one(frig_ctx *ctx, size_t k, void *user) {
    finish_job *j = user;
    fr_sfs_run *r = j->r;
    fr_sfs_view *v = &r->views[k];
    const fr_sfs_settings *st = &r->st;
    char why[256];
    if (!r->ok[k] && (!v->rgb || r->status[k] != FRIG_OK)) return FRIG_OK; /* not read or drawn: no picture */
    int judged_before = !r->ok[k];
    v->agreement = judged_before ? 0 : fr_sfs_photo_agreement(v);
    if (!judged_before && v->agreement < st->min_agreement) {
        snprintf(why, sizeof why, "its shading does not follow the subject's albedo (correlation %.2f < %.2f): no face, "
                 "someone else or an occluder", v->agreement, st->min_agreement);
        r->ok[k] = 0, r->reason[k] = strdup(why);
    }
    if (!judged_before) fr_sfs_select_region(v, st);
    memcpy(v->R_refined, v->R, sizeof v->R), memcpy(v->t_refined, v->t, sizeof v->t);
    frig_status s = FRIG_OK;
    if (r->ok[k] && st->pose && v->kept_pixels >= 50) s = fr_sfs_refine_pose(ctx, &r->mesh, v, v->R_refined, v->t_refined);
    if (s) return s;
    v->pose_change_deg = fr_rotation_angle_deg(v->R, v->R_refined);
    if (!judged_before && st->cloud_region) fr_sfs_region_narrow(v, st->cloud_region == 2);
    if (r->ok[k] && v->kept_pixels < st->min_points) {
        snprintf(why, sizeof why, "only %d points kept (sfs.min_points %d)", v->kept_pixels, st->min_points);
        r->ok[k] = 0, r->reason[k] = strdup(why);
    }
    if (r->ok[k]) {
        size_t total = (size_t)v->kept_pixels + (size_t)v->margin_pixels; /* 0 margin pixels unless sfs.cloud_region 2 */
        float *xyz = malloc(sizeof(float) * 3 * (total + 1));
        float *nrm = malloc(sizeof(float) * 3 * (total + 1));
        float *conf = malloc(sizeof(float) * (total + 1));
        if (!xyz || !nrm || !conf) {
            free(xyz), free(nrm), free(conf);
            return fr_nomem(ctx, "a point cloud");
        }
        int c = cloud_points(v, 1, xyz, nrm, conf); /* the cloud: every kept pixel without a region, else the face's */
        int m = cloud_points(v, 2, xyz + 3 * (size_t)c, nrm + 3 * (size_t)c, conf + c);
        j->xyz[k] = xyz, j->nrm[k] = nrm, j->conf[k] = conf, j->count[k] = c, j->margin[k] = m;
    }
    if (j->overlay_dir) {
        char name[1024], label[256];
        s = frig_clouds_file_name(ctx, j->set, r->photo[k], name, sizeof name);
        char *dot = strrchr(name, '.');
        if (dot) strcpy(dot, ".jpg");
        if (r->ok[k])
            snprintf(label, sizeof label, "kept %d of %d px, error %.3f, pose %+.1f deg", v->kept_pixels, v->face_pixels,
                     v->sfs_error, v->pose_change_deg);
        else
            snprintf(label, sizeof label, "sfs_failed: %.200s", r->reason[k] ? r->reason[k] : "");
        char *path = s ? NULL : fr_path_join(j->overlay_dir, name);
        if (!s && !path) s = fr_nomem(ctx, "a path");
        if (!s) s = fr_sfs_write_overlay(ctx, v, st, label, path);
        free(path);
    }
    return s;
}

/* The median of the positive values of v (0 when none is) into *med; -1 when memory ran out. */
static int median_positive(const float *v, size_t n, double *med) {
    float *p = malloc(sizeof(float) * (n + 1));
    if (!p) return -1;
    size_t m = 0;
    for (size_t i = 0; i < n; i++)
        if (v[i] > 0) p[m++] = v[i];
    *med = m ? fr_select_float(p, m, m / 2) : 0.0;
    free(p);
    return 0;
}

/* Texels that their views weigh less than a typical texel (the median seen one: only grazing
 * views saw them, where the lighting's shading is least sure and small) are brought down to the
 * BRIGHT_QUANTILE of the brightness (mean of r, g, b) of the texels seen at least that well, their
 * colour kept: dividing by the faint shading of a face's side painted a bright rim there
 * (docs/sfs.md, "The albedo texture's colours"). */
static int cap_faint_texels(fr_sfs_albedo *a, size_t n, double wmed) {
    float *lum = malloc(sizeof(float) * (n + 1));
    if (!lum) return -1;
    size_t m = 0;
    for (size_t t = 0; t < n; t++)
        if (a->weight[t] > 0 && a->weight[t] >= wmed)
            lum[m++] = (a->albedo[3 * t] + a->albedo[3 * t + 1] + a->albedo[3 * t + 2]) / 3;
    if (m) {
        double cap = fr_select_float(lum, m, (size_t)(BRIGHT_QUANTILE * (double)(m - 1)));
        for (size_t t = 0; t < n; t++) {
            float *c = a->albedo + 3 * t;
            double l = (c[0] + c[1] + c[2]) / 3.0;
            if (a->weight[t] > 0 && a->weight[t] < wmed && l > cap)
                for (int k = 0; k < 3; k++) c[k] = (float)(c[k] * cap / l);
        }
    }
    free(lum);
    return 0;
}

/* The skin's colour: per channel the median of the narrow face's texels seen at least as well as
 * the median texel ('fallback', the photos' mean skin colour, when there are none). */
static int skin_median(const fr_sfs_albedo *a, const uint8_t *core, size_t n, double wmed, const double fallback[3],
                       double skin[3]) {
    float *v = malloc(sizeof(float) * (n + 1));
    if (!v) return -1;
    for (int c = 0; c < 3; c++) {
        size_t m = 0;
        for (size_t t = 0; t < n; t++)
            if (core[t] && a->weight[t] > 0 && a->weight[t] >= wmed) v[m++] = a->albedo[3 * t + c];
        skin[c] = m ? fr_select_float(v, m, m / 2) : fallback[c];
    }
    free(v);
    return 0;
}

/* Texels off the narrow face (the neck, the ears, the scalp) darker than SHADOW_SHARE of the
 * narrow face's skin do not count as seen: the neck under the jaw is in the jaw's shadow in most
 * photos, which the lighting (no cast shadows) leaves in the albedo as grey and dark red blotches. */
static void drop_shadowed(const float *rgb, const uint8_t *core, size_t n, const double skin[3], uint8_t *known) {
    double level = (skin[0] + skin[1] + skin[2]) / 3;
    for (size_t t = 0; t < n; t++)
        if (known[t] && !core[t] && (rgb[3 * t] + rgb[3 * t + 1] + rgb[3 * t + 2]) / 3 < SHADOW_SHARE * level) known[t] = 0;
}

/* The subject's albedo as an sRGB texture of sfs.texture_size texels (Algorithm 5 once more, on
 * the final lighting and the shared shape's normals); texels no photo saw well, and shadowed ones
 * off the narrow face, are filled smoothly from the seen ones (pull-push, image/pull_push.h). */
frig_status fr_sfs_run_albedo(frig_ctx *ctx, fr_sfs_run *r, frig_image **out) {
    fr_sfs_uv uv;
    fr_sfs_albedo a;
    memset(&a, 0, sizeof a);
    frig_status s = fr_sfs_uv_init(ctx, &r->mesh, r->st.texture_size, &uv);
    if (!s) s = fr_sfs_albedo_init(ctx, &uv, &a);
    if (!s)
        s = fr_sfs_albedo_solve(ctx, &r->mesh, &uv, r->views, r->n, r->ok, fmax(r->st.sigma, 0.03), 1, &a);
    int T = uv.size;
    size_t n = (size_t)T * T;
    frig_image *img = s ? NULL : fr_image_new(T, T, 3);
    float *rgb = s ? NULL : malloc(sizeof(float) * 3 * n);
    uint8_t *known = s ? NULL : calloc(n, 1), *core = s ? NULL : calloc(n, 1);
    if (!s && (!img || !rgb || !known || !core)) s = fr_nomem(ctx, "the albedo texture");
    double skin[3];
    if (!s) {
        /* A texel counts as seen when its views weigh at least SEEN_SHARE of a typical seen
         * texel's (a texel only a grazing view or two showed is the outline's colour). */
        double wmed = 0;
        for (int k = 0; k < uv.count; k++) core[uv.texel[k]] = r->mesh.core[uv.tri[k]];
        if (median_positive(a.weight, n, &wmed) || cap_faint_texels(&a, n, wmed) ||
            skin_median(&a, core, n, wmed, r->mean_albedo, skin))
            s = fr_nomem(ctx, "the albedo texture");
        double wmin = SEEN_SHARE * wmed;
        for (size_t t = 0; t < n; t++) {
            for (int c = 0; c < 3; c++) rgb[3 * t + c] = a.albedo[3 * t + c];
            known[t] = a.weight[t] > 0 && a.weight[t] >= wmin;
        }
    }
    if (!s) {
        drop_shadowed(rgb, core, n, skin, known);
        /* texels no photo saw well: filled smoothly from the seen ones (the skin's colour when none was) */
        int filled = fr_pull_push(rgb, known, T, T);
        if (filled < 0) s = fr_nomem(ctx, "the albedo texture");
        for (size_t t = 0; filled == 0 && t < n; t++)
            for (int c = 0; c < 3; c++) rgb[3 * t + c] = (float)skin[c];
    }
    if (!s) {
        for (int y = 0; y < T; y++)
            for (int x = 0; x < T; x++)
                for (int c = 0; c < 3; c++)
                    img->pixels[(size_t)y * img->stride + 3 * (size_t)x + c] =
                        (uint8_t)floor(255.0 * fr_linear_to_srgb(rgb[3 * ((size_t)y * T + x) + c]) + 0.5);
        *out = img;
        img = NULL;
    }
    frig_image_free(img);
    free(rgb), free(known), free(core);
    fr_sfs_albedo_free(&a);
    fr_sfs_uv_free(&uv);
    return s;
}

frig_status frig_sfs(frig_ctx *ctx, const frig_rig *rig, frig_photoset *set, const char *overlay_dir,
                     frig_clouds **clouds, frig_image **albedo) {
    return frig_sfs_with_model(ctx, NULL, rig, set, overlay_dir, clouds, albedo);
}

frig_status frig_sfs_with_model(frig_ctx *ctx, const frig_model *model, const frig_rig *rig, frig_photoset *set,
                                const char *overlay_dir, frig_clouds **clouds, frig_image **albedo) {
    fr_sfs_settings st;
    fr_sfs_settings_from_ctx(ctx, &st);
    if (model && rig && frig_model_vertex_count(model) != frig_rig_vertex_count(rig))
        return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_sfs_with_model: the model has %d vertices, the rig %d",
                        frig_model_vertex_count(model), frig_rig_vertex_count(rig));
    if (model && set) fr_sfs_settings_identity(ctx, &st, model, set);
    return fr_sfs_stage(ctx, rig, set, &st, overlay_dir, clouds, albedo);
}

static frig_status stage(frig_ctx *ctx, const frig_rig *rig, frig_photoset *set, const fr_sfs_settings *st,
                         const char *overlay_dir, frig_clouds **clouds, frig_image **albedo, fr_sfs_run **keep);

/* The rig weights a photo's cloud was drawn at, by the fit's expression names, into the report
 * (NULL: the fit's, nothing recorded). */
static frig_status sfs_expression_to_report(frig_ctx *ctx, const frig_rig *rig, frig_photoset *set, size_t i,
                                            const double *rig_weights) {
    if (!rig_weights || set->n_expressions <= 0) return fr_photoset_set_sfs_expression(ctx, set, i, NULL);
    double *w = malloc(sizeof(double) * (size_t)set->n_expressions);
    if (!w) return fr_nomem(ctx, "a photo's sfs expression");
    for (int e = 0; e < set->n_expressions; e++) {
        int k = frig_rig_shape_find(rig, set->expression_names[e]);
        w[e] = k >= 0 ? rig_weights[k] : set->photos[i].fit_expression[e];
    }
    frig_status s = fr_photoset_set_sfs_expression(ctx, set, i, w);
    free(w);
    return s;
}

/* The identity the clouds were drawn at: the fit's with the shared solve's change in the model's
 * first modes (none when the shared solve did not move the identity). */
static frig_status sfs_identity_to_report(frig_ctx *ctx, const fr_sfs_run *run, frig_photoset *set) {
    int m = run->st.identity_count;
    if (!run->ident || m <= 0 || m > set->n_identity || !set->identity) return fr_photoset_set_sfs_identity(ctx, set, NULL);
    double *w = malloc(sizeof(double) * (size_t)set->n_identity);
    if (!w) return fr_nomem(ctx, "the sfs identity");
    memcpy(w, set->identity, sizeof(double) * (size_t)set->n_identity);
    for (int k = 0; k < m; k++) w[k] += run->ident[k];
    frig_status s = fr_photoset_set_sfs_identity(ctx, set, w);
    free(w);
    return s;
}

frig_status fr_sfs_stage(frig_ctx *ctx, const frig_rig *rig, frig_photoset *set, const fr_sfs_settings *st,
                         const char *overlay_dir, frig_clouds **clouds, frig_image **albedo) {
    return stage(ctx, rig, set, st, overlay_dir, clouds, albedo, NULL);
}

frig_status fr_sfs_stage_keep(frig_ctx *ctx, const frig_rig *rig, frig_photoset *set, const fr_sfs_settings *st,
                              frig_clouds **clouds, fr_sfs_run **keep) {
    *keep = NULL;
    return stage(ctx, rig, set, st, NULL, clouds, NULL, keep);
}

static frig_status stage(frig_ctx *ctx, const frig_rig *rig, frig_photoset *set, const fr_sfs_settings *st,
                         const char *overlay_dir, frig_clouds **clouds, frig_image **albedo, fr_sfs_run **keep) {
    if (clouds) *clouds = NULL;
    if (albedo) *albedo = NULL;
    if (!rig || !set) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_sfs: NULL rig or photo set");
    frig_status s = overlay_dir ? fr_make_dirs(ctx, overlay_dir) : FRIG_OK;
    if (s) return s;
    fr_sfs_run run;
    /* BLAS serial: the stage runs its photos in parallel itself, and CHOLMOD's supernodal BLAS
     * calls on the shared shape's and the depth's small fronts only spun OpenBLAS's threads
     * (the same bytes, 1-2 CPU s less on 32 photos) */
    int blas = fr_blas_serial_begin();
    s = fr_sfs_run_all(ctx, rig, set, st, &run);
    fr_blas_serial_end(blas);
    if (!s && run.n == 0)
        s = fr_error(ctx, FRIG_ERR_TOO_FEW, "no fitted photo with an ok status for shape from shading (run frig fit first)");
    finish_job job = {&run, set, overlay_dir, NULL, NULL, NULL, NULL, NULL};
    if (!s) {
        job.xyz = calloc((size_t)run.n + 1, sizeof(float *));
        job.nrm = calloc((size_t)run.n + 1, sizeof(float *));
        job.conf = calloc((size_t)run.n + 1, sizeof(float *));
        job.count = calloc((size_t)run.n + 1, sizeof(int));
        job.margin = calloc((size_t)run.n + 1, sizeof(int));
        if (!job.xyz || !job.nrm || !job.conf || !job.count || !job.margin) s = fr_nomem(ctx, "the clouds");
    }
    double cpu[3];
    cpu[0] = fr_cpu_seconds();
    if (!s) {
        int saved = fr_blas_serial_begin();
        s = fr_parallel_items(ctx, (size_t)run.n, "sfs.clouds", finish_one, &job);
        fr_blas_serial_end(saved);
    }
    cpu[1] = fr_cpu_seconds();
    frig_clouds *cl = NULL;
    if (!s && clouds) s = frig_clouds_create(ctx, set->count, &cl);
    /* results of an earlier run stay only with the photos judged now */
    for (size_t i = 0; i < set->count && !s; i++) set->photos[i].sfs_done = 0;
    int usable = 0;
    for (int k = 0; k < run.n && !s; k++) {
        fr_photo *p = &set->photos[run.photo[k]];
        const fr_sfs_view *v = &run.views[k];
        double sh[27];
        for (int c = 0; c < 3; c++) memcpy(sh + 9 * c, v->sh[c], sizeof(double) * 9);
        if (run.status[k] == FRIG_ERR_IO || run.status[k] == FRIG_ERR_CORRUPT || run.status[k] == FRIG_ERR_TRUNCATED ||
            run.status[k] == FRIG_ERR_NOT_FOUND || run.status[k] == FRIG_ERR_UNSUPPORTED) {
            p->sfs_done = 0;
            s = frig_photoset_set_status(ctx, set, run.photo[k], FRIG_PHOTO_UNREADABLE, run.reason[k]);
            continue;
        }
        if (run.status[k] == FRIG_ERR_NO_MEMORY || run.status[k] == FRIG_ERR_INTERNAL || run.status[k] == FRIG_ERR_CANCELLED) {
            s = fr_error(ctx, run.status[k], "%s", run.reason[k] ? run.reason[k] : "shape from shading failed");
            break;
        }
        fr_photoset_set_sfs(p, v->face_pixels, run.ok[k] ? v->kept_pixels : 0, v->sfs_error, sh, v->R_refined,
                            v->t_refined);
        p->sfs_margin = run.ok[k] && cl ? job.margin[k] : 0; /* the points written as its cloud's margin */
        s = sfs_expression_to_report(ctx, rig, set, run.photo[k], run.st.expression_steps > 0 ? v->weights : NULL);
        if (!s)
            s = frig_photoset_set_status(ctx, set, run.photo[k], run.ok[k] ? FRIG_PHOTO_OK : FRIG_PHOTO_SFS_FAILED,
                                         run.ok[k] ? NULL : run.reason[k]);
        if (!s && run.ok[k]) {
            usable++;
            if (cl) s = frig_clouds_set(ctx, cl, run.photo[k], (size_t)job.count[k], job.xyz[k], job.nrm[k], job.conf[k]);
            size_t c3 = 3 * (size_t)job.count[k];
            if (!s && cl && job.margin[k])
                s = frig_clouds_set_margin(ctx, cl, run.photo[k], (size_t)job.margin[k], job.xyz[k] + c3, job.nrm[k] + c3,
                                           job.conf[k] + job.count[k]);
        }
    }
    (void)usable;
    if (!s) fr_photoset_set_sfs_solve(set, run.light_why ? FRIG_SFS_SOLVE_LIGHT : FRIG_SFS_SOLVE_FULL, run.light_why, run.n,
                                      run.light_axis);
    if (!s) s = sfs_identity_to_report(ctx, &run, set);
    if (!s && albedo) s = fr_sfs_run_albedo(ctx, &run, albedo);
    cpu[2] = fr_cpu_seconds();
    fr_log(ctx, FRIG_LOG_DEBUG, "sfs (CPU s): regions, poses, clouds%s %.2f, albedo texture %.2f",
           overlay_dir ? " and pictures" : "", cpu[1] - cpu[0], cpu[2] - cpu[1]);
    for (int k = 0; job.xyz && k < run.n; k++) free(job.xyz[k]), free(job.nrm[k]), free(job.conf[k]);
    free(job.xyz), free(job.nrm), free(job.conf), free(job.count), free(job.margin);
    if (!s && keep && !(*keep = malloc(sizeof run))) s = fr_nomem(ctx, "the sfs computation");
    if (!s && keep) **keep = run; /* handed over whole */
    else fr_sfs_run_free(&run);
    if (s) {
        frig_clouds_free(cl);
        if (albedo) frig_image_free(*albedo), *albedo = NULL;
        return s;
    }
    if (clouds) *clouds = cl;
    return FRIG_OK;
}
