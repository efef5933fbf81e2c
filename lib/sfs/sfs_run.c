/* Shape from shading over a photo set (paper Algorithm 4, with the albedo of Algorithm 5):
 * every usable photo's view (crop, render, skin, first lighting) in parallel; the subject's
 * albedo in UV space from all photos and each photo's lighting on it, the photos that this
 * albedo does not explain weighted down (three passes); the shape shared by all photos (a
 * displacement of the rig in UV space, sfs_multiview.c); each view drawn again with it; finally
 * each photo's own depth from its shading, held to the shared shape's normals and depth.
 * Photos are independent inside each step (OpenMP), texels too; results do not depend on the
 * thread count. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/clock.h"
#include "core/context.h"
#include "core/sort.h"
#include "image/colour_transfer.h"
#include "linalg/linalg.h"
#include "rig/rig.h"
#include "sfs/sfs_multiview.h"
#include "sfs/sfs_photo.h"
#include "sfs/sfs_run.h"
#include "workspace/photoset.h"

/* The first views' lighting (DC terms per channel) in the log: --verbose. */
static void log_lighting(frig_ctx *ctx, const fr_sfs_run *r, const char *when) {
    for (int k = 0; k < r->n && k < 3; k++)
        if (r->ok[k])
            fr_log(ctx, FRIG_LOG_DEBUG, "sfs: %s: photo %zu lighting DC %.3f %.3f %.3f, weight %.2f", when, r->photo[k],
                   r->views[k].sh[0][0], r->views[k].sh[1][0], r->views[k].sh[2][0], r->views[k].photo_weight);
}

void fr_sfs_run_free(fr_sfs_run *r) {
    for (int k = 0; k < r->n; k++) {
        fr_sfs_view_free(&r->views[k]);
        free(r->reason ? r->reason[k] : NULL);
    }
    free(r->views), free(r->photo), free(r->ok), free(r->reason), free(r->status);
    fr_sfs_albedo_free(&r->ps);
    free(r->vdisp), free(r->ident);
    fr_sfs_uv_free(&r->uv);
    fr_sfs_mesh_free(&r->mesh);
    memset(r, 0, sizeof *r);
}

static void fail_view(fr_sfs_run *r, int k, const char *why) {
    r->ok[k] = 0;
    if (!r->reason[k]) r->reason[k] = strdup(why);
}

typedef struct run_job {
    fr_sfs_run *r;
    const frig_photoset *set;
    int *shape_of; /* fit expression -> rig shape */
    int step;
    const float *vdisp; /* per vertex displacement from the multi-view solve */
} run_job;

/* Step 0: read, crop, render, skin, first lighting; then the photo's own checks. */
static frig_status prepare_one(frig_ctx *ctx, size_t k, void *user) {
    run_job *j = user;
    fr_sfs_run *r = j->r;
    const fr_photo *p = &j->set->photos[r->photo[k]];
    double *w = calloc((size_t)r->mesh.shapes + 1, sizeof(double));
    if (!w) return fr_nomem(ctx, "rig weights");
    for (int e = 0; e < j->set->n_expressions; e++)
        if (j->shape_of[e] >= 0) w[j->shape_of[e]] = p->fit_expression[e];
    fr_sfs_view *v = &r->views[k];
    frig_status s = fr_sfs_view_build(ctx, &r->mesh, &r->st, p->path, p->width, p->height, p->fit_rotation,
                                      p->fit_translation, p->fit_focal, w, v);
    v->photo = r->photo[k]; /* the set's index, for the logs */
    free(w);
    if (!s) s = fr_sfs_photo_prepare(ctx, v, &r->st);
    if (s) {
        r->status[k] = s;
        fail_view(r, (int)k, frig_ctx_errmsg(ctx));
        return FRIG_OK;
    }
    const fr_skin_stats *ss = &v->skin_stats;
    if (v->highlight_pixels > 0)
        fr_log(ctx, FRIG_LOG_DEBUG, "sfs: photo %zu: the highlights of %d skin pixels taken out", v->photo, v->highlight_pixels);
    char why[256];
    double region = ss->region > 0 ? ss->region : 1;
    if (ss->region < 100) {
        snprintf(why, sizeof why, "the fitted face covers only %d pixels of the crop", ss->region);
        fail_view(r, (int)k, why);
    } else if (ss->clipped > r->st.max_clipped * region) {
        snprintf(why, sizeof why, "over-exposed: %.0f%% of the face's pixels are clipped", 100.0 * ss->clipped / region);
        fail_view(r, (int)k, why);
    } else if (ss->median_luma < r->st.min_luma) {
        snprintf(why, sizeof why, "under-exposed: the face's median level is %.0f of 255 (sfs.min_luma %.0f), no shading "
                 "to read", ss->median_luma, r->st.min_luma);
        fail_view(r, (int)k, why);
    } else if (ss->skin < r->st.min_skin * region) {
        snprintf(why, sizeof why, "too little skin: %.0f%% of the face region (sunglasses, hands, hair?)",
                 100.0 * ss->skin / region);
        fail_view(r, (int)k, why);
    }
    return FRIG_OK;
}

/* The subject's albedo brought to the photo's colours (section 5.1.2: Reinhard colour transfer
 * of the projected albedo to the photo): its l-alpha-beta statistics over the skin made those of
 * the photo's own albedo I / S under the photo's current lighting. */
static frig_status transfer_colours(frig_ctx *ctx, fr_sfs_view *v, int spread) {
    size_t n = (size_t)v->w * v->h;
    float *own = malloc(sizeof(float) * 3 * n);
    if (!own) return fr_nomem(ctx, "the colour transfer");
    for (size_t i = 0; i < n; i++) {
        double S[3];
        fr_sfs_shading(v->sh, v->n_prior + 3 * i, S);
        for (int c = 0; c < 3; c++) own[3 * i + c] = S[c] > 1e-3 ? (float)(v->I[3 * i + c] / S[c]) : 0.0f;
    }
    fr_colour_transfer(v->albedo, v->skin, own, v->skin, n, spread);
    free(own);
    return FRIG_OK;
}

static frig_status apply_one(frig_ctx *ctx, size_t k, void *user) {
    run_job *j = user;
    fr_sfs_run *r = j->r;
    if (!r->ok[k]) return FRIG_OK;
    fr_sfs_view *v = &r->views[k];
    fr_sfs_albedo_apply(&r->mesh, &r->ps, v, r->mean_albedo);
    frig_status s = r->st.transfer ? transfer_colours(ctx, v, r->st.transfer == 2) : FRIG_OK;
    if (!s) s = fr_sfs_photo_relight(ctx, v);
    if (s) r->status[k] = s, fail_view(r, (int)k, frig_ctx_errmsg(ctx));
    return FRIG_OK;
}

/* The view drawn again with the subject's displacement: the better reference depth and normals. */
static frig_status displace_one(frig_ctx *ctx, size_t k, void *user) {
    run_job *j = user;
    fr_sfs_run *r = j->r;
    if (!r->ok[k]) return FRIG_OK;
    fr_sfs_view *v = &r->views[k];
    double R[9], t[3];
    memcpy(R, v->R, sizeof R), memcpy(t, v->t, sizeof t);
    frig_status s = fr_sfs_view_render(ctx, &r->mesh, v, R, t, j->vdisp);
    if (!s) {
        /* the shared albedo, and the displaced rig's normals as the prior */
        size_t n = (size_t)v->w * v->h;
        fr_sfs_albedo_apply(&r->mesh, &r->ps, v, r->mean_albedo);
        memcpy(v->n_prior, v->n_ref, sizeof(float) * 3 * n);
        for (size_t i = 0; i < n; i++)
            if (!v->face[i]) v->n_prior[3 * i] = v->n_prior[3 * i + 1] = v->n_prior[3 * i + 2] = 0;
    }
    if (s) r->status[k] = s, fail_view(r, (int)k, frig_ctx_errmsg(ctx));
    return FRIG_OK;
}

static frig_status depth_one(frig_ctx *ctx, size_t k, void *user) {
    run_job *j = user;
    fr_sfs_run *r = j->r;
    if (!r->ok[k]) return FRIG_OK;
    frig_status s = fr_sfs_photo_depth(ctx, &r->views[k], &r->st);
    if (s) r->status[k] = s, fail_view(r, (int)k, frig_ctx_errmsg(ctx));
    return FRIG_OK;
}

/* How close the photos' lights are to one axis on the face: each photo's light direction from its
 * first-order SH terms (y, z, x: raster/sh_lighting.c), turned into the head's frame by its rotation,
 * and the largest eigenvalue of the mean of d d^T (1: every light on one axis, 1/3 spread evenly).
 * An axis, not a direction: a light and its opposite shade along the same normal component, and
 * under one soft lamp the fitted first-order terms can flip sign from photo to photo. */
frig_status fr_sfs_light_concentration(frig_ctx *ctx, const fr_sfs_view *views, const uint8_t *ok, int n,
                                       double *concentration) {
    double T[9] = {0}, w[3];
    *concentration = 0;
    int m = 0;
    for (int k = 0; k < n; k++) {
        if (!ok[k]) continue;
        const fr_sfs_view *v = &views[k];
        double d[3] = {0, 0, 0}, h[3];
        for (int c = 0; c < 3; c++) d[0] += v->sh[c][3], d[1] += v->sh[c][1], d[2] += v->sh[c][2];
        double l = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        if (!(l > 0)) continue;
        for (int i = 0; i < 3; i++) h[i] = (v->R[i] * d[0] + v->R[3 + i] * d[1] + v->R[6 + i] * d[2]) / l;
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++) T[3 * i + j] += h[i] * h[j];
        m++;
    }
    if (m < 2) return FRIG_OK;
    for (int i = 0; i < 9; i++) T[i] /= m;
    frig_status s = fr_sym_eig(ctx, 3, T, 3, w);
    if (!s) *concentration = w[2];
    return s;
}

/* Photos the stage judges: fitted, ok or judged by an earlier sfs run (options may have changed). */
static int candidate(const fr_photo *p) {
    return p->fitted && (p->status == FRIG_PHOTO_OK || p->status == FRIG_PHOTO_SFS_FAILED) && p->width > 0 && p->height > 0;
}

frig_status fr_sfs_run_all(frig_ctx *ctx, const frig_rig *rig, const frig_photoset *set, const fr_sfs_settings *st,
                           fr_sfs_run *r) {
    memset(r, 0, sizeof *r);
    r->st = *st;
    frig_status s = fr_sfs_mesh_init(ctx, rig, &r->mesh);
    if (s) return s;
    size_t n = 0;
    for (size_t i = 0; i < set->count; i++) n += candidate(&set->photos[i]);
    /* A few photos' shared albedo and shape cannot register them, and many make the full solve
     * slow (docs/sfs.md): the light solve. */
    int few = n < (size_t)(st->joint_min_photos > 0 ? st->joint_min_photos : 0);
    int many = st->joint_max_photos > 0 && n > (size_t)st->joint_max_photos;
    int light = few || many || st->light;
    if (light) fr_sfs_light_shared_solve(&r->st);
    r->light_why = few    ? FR_SFS_WHY_FEW_PHOTOS
                   : many ? FR_SFS_WHY_MANY_PHOTOS
                   : light ? FR_SFS_WHY_OUTER_LOOP
                           : FR_SFS_WHY_NONE;
    st = &r->st;
    r->photo = malloc(sizeof(size_t) * (n + 1));
    r->views = calloc(n + 1, sizeof *r->views);
    r->ok = malloc(n + 1);
    r->reason = calloc(n + 1, sizeof(char *));
    r->status = calloc(n + 1, sizeof(frig_status));
    int *shape_of = malloc(sizeof(int) * (size_t)(set->n_expressions + 1));
    if (!r->photo || !r->views || !r->ok || !r->reason || !r->status || !shape_of) {
        free(shape_of);
        return fr_nomem(ctx, "the sfs stage");
    }
    for (size_t i = 0; i < set->count; i++)
        if (candidate(&set->photos[i])) r->photo[r->n++] = i;
    memset(r->ok, 1, n + 1);
    for (int e = 0; e < set->n_expressions; e++) shape_of[e] = frig_rig_shape_find(rig, set->expression_names[e]);
    run_job job = {r, set, shape_of, 0, NULL};
    int saved = fr_blas_serial_begin();
    double cpu[6]; /* CPU seconds at each step's end, for the log */
    cpu[0] = fr_cpu_seconds();
    s = fr_parallel_items(ctx, n, "sfs.prepare", prepare_one, &job);
    cpu[1] = fr_cpu_seconds();
    /* the mean skin colour of the usable photos: the albedo where no photo saw the texel */
    int used = 0;
    for (int k = 0; k < r->n; k++)
        if (r->ok[k]) {
            for (int c = 0; c < 3; c++) r->mean_albedo[c] += r->views[k].skin_stats.mean_linear[c];
            used++;
        }
    for (int c = 0; c < 3; c++) r->mean_albedo[c] /= used ? used : 1;
    log_lighting(ctx, r, "first lighting");
    if (!s) s = fr_sfs_uv_init(ctx, &r->mesh, st->shape_size, &r->uv);
    if (!s) s = fr_sfs_albedo_init(ctx, &r->uv, &r->ps);
    double albedo_sigma = fmax(st->sigma, 0.03);
    /* Algorithm 5: the albedo from all photos on the fitted normals, and each photo's lighting on it */
    for (int pass = 0; pass < 3 && !s && used; pass++) {
        s = fr_sfs_albedo_solve(ctx, &r->mesh, &r->uv, r->views, r->n, r->ok, albedo_sigma, 0, &r->ps);
        if (!s) s = fr_parallel_items(ctx, n, "sfs.lighting", apply_one, &job);
        /* photos the subject's albedo does not explain (a wrong fit, an occluder, no face) weigh less
         * in the next estimate: the weight is the squared correlation of prediction and photo */
        double *a = malloc(sizeof(double) * (size_t)(r->n + 1)), *sorted = malloc(sizeof(double) * (size_t)(r->n + 1));
        int m = 0;
        for (int k = 0; a && sorted && k < r->n; k++) {
            a[k] = r->ok[k] ? fr_sfs_photo_agreement(&r->views[k]) : 0;
            if (r->ok[k]) sorted[m++] = a[k];
        }
        if (a && sorted && m) {
            qsort(sorted, (size_t)m, sizeof *sorted, fr_cmp_double);
            double med = sorted[m / 2] > 0.05 ? sorted[m / 2] : 0.05;
            for (int k = 0; k < r->n; k++) {
                double q = a[k] > 0 ? a[k] / med : 0;
                r->views[k].photo_weight = q < 1 ? q * q : 1;
            }
        }
        free(a), free(sorted);
    }
    log_lighting(ctx, r, "on the shared albedo");
    /* Lights along one axis on the face (frames of a video under one lamp, the head hardly
     * turning) do not tell the face's colours from its shape, and the full solve then carves the
     * colours into the shape (docs/sfs.md, "One light for all photos"): the light solve. */
    double conc = 0;
    if (!s) s = fr_sfs_light_concentration(ctx, r->views, r->ok, r->n, &conc);
    r->light_axis = conc;
    if (!s && !light && used && st->joint_light < 1 && conc > st->joint_light) { /* 1: never (rounding can pass 1) */
        fr_log(ctx, FRIG_LOG_INFO, "sfs: the photos' lights fall on the face along one axis (concentration %.3f "
               "over sfs.joint_light %.3g): the light shared solve", conc, st->joint_light);
        fr_sfs_light_shared_solve(&r->st);
        r->light_why = FR_SFS_WHY_ONE_LIGHT_AXIS;
    } else if (!s)
        fr_log(ctx, FRIG_LOG_DEBUG, "sfs: the photos' lights on the face: concentration %.3f", conc);
    cpu[2] = fr_cpu_seconds();
    /* the subject's shape from all photos: a displacement of the rig in UV space */
    float *disp = NULL, *vdisp = NULL;
    if (!s && used && st->rounds > 0) {
        disp = calloc((size_t)st->shape_size * st->shape_size, sizeof(float));
        vdisp = calloc((size_t)r->mesh.nv + 1, sizeof(float));
        if (!disp || !vdisp) s = fr_nomem(ctx, "the multi-view solve");
        fr_sfs_multiview_options mo;
        fr_sfs_multiview_options_default(&mo);
        mo.w_stereo = st->w_stereo;
        mo.pose_steps = st->pose_steps;
        mo.joint_albedo = st->joint_albedo;
        if (st->shape_iterations > 0) mo.iterations = st->shape_iterations;
        if (st->shape_sigma > 0) mo.sigma = st->shape_sigma;
        mo.pose_levels = st->pose_levels;
        if (st->pose_sigma_px > 0) mo.pose_sigma_px = st->pose_sigma_px;
        mo.outer = st->rounds;
        mo.expression_steps = st->expression_steps;
        mo.expression_prior = st->expression_prior;
        mo.expression_sparse = st->expression_sparse;
        if (st->identity_count > 0 && st->identity_modes && !s) {
            /* the model's identity modes with the displacement: the change lives in the mesh (every view,
             * the reference and the depth drawn with it) and its weights in r->ident */
            r->mesh.ident = calloc(3 * (size_t)r->mesh.nv + 1, sizeof(float));
            r->ident = calloc((size_t)st->identity_count + 1, sizeof(double));
            if (!r->mesh.ident || !r->ident) s = fr_nomem(ctx, "the identity change");
            mo.id_modes = st->identity_modes, mo.id_count = st->identity_count, mo.id_prior = st->identity_prior;
            mo.id_centre = st->identity_centre, mo.id_hold = st->displacement_hold;
            mo.id_start = st->identity_start, mo.id_change = r->ident;
        }
        uint8_t *use = malloc((size_t)r->n + 1);
        if (!use && !s) s = fr_nomem(ctx, "the multi-view solve");
        for (int k = 0; use && k < r->n; k++) use[k] = r->ok[k] && (!st->shape_use || st->shape_use[r->photo[k]]);
        if (!s) s = fr_sfs_multiview(ctx, &r->mesh, &r->uv, r->views, r->n, use, &mo, &r->ps, disp);
        free(use);
        if (!s) s = fr_sfs_vertex_displacement(ctx, &r->mesh, disp, st->shape_size, vdisp);
        log_lighting(ctx, r, "with the shared shape");
        job.vdisp = vdisp;
        if (!s) s = fr_parallel_items(ctx, n, "sfs.reference", displace_one, &job);
    }
    free(disp);
    r->vdisp = vdisp;
    cpu[3] = fr_cpu_seconds();
    if (!s && used) s = fr_parallel_items(ctx, n, "sfs.depth", depth_one, &job);
    cpu[4] = fr_cpu_seconds();
    fr_log(ctx, FRIG_LOG_DEBUG, "sfs (CPU s): views %.2f, albedo and lighting %.2f, shared shape and reference %.2f, "
           "depth %.2f", cpu[1] - cpu[0], cpu[2] - cpu[1], cpu[3] - cpu[2], cpu[4] - cpu[3]);
    fr_blas_serial_end(saved);
    free(shape_of);
    return s;
}
