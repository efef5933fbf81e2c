/* One photo's steps of shape from shading (paper Algorithm 4 for photo k): the skin region, its
 * highlights taken out (sfs_highlights.c, beyond the paper), the first lighting on the fitted normals
 * with a uniform albedo (the mean skin colour, section 5.1.2); lighting again on the current albedo
 * and normals (line 11); depth and normals (lines 12-13, 17-18). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "core/select.h"
#include "core/sort.h"
#include "sfs/sfs.h"
#include "sfs/sfs_depth.h"
#include "sfs/sfs_photo.h"
#include "sfs/sfs_highlights.h"

frig_status fr_sfs_photo_prepare(frig_ctx *ctx, fr_sfs_view *v, const fr_sfs_settings *st) {
    size_t n = (size_t)v->w * v->h;
    fr_skin_options so;
    fr_skin_options_default(&so);
    /* superpixels of about 1/16 of the face's size */
    so.slic_step = (int)fmax(4.0, round(fmax(v->w, v->h) / 16.0));
    frig_status s = fr_skin_detect(ctx, v->rgb, v->w, v->h, 3 * (size_t)v->w, v->face, v->core, &so, v->skin,
                                   &v->skin_stats);
    if (s) return s;
    s = fr_sfs_take_out_highlights(ctx, v, st->highlights, &v->highlight_pixels);
    if (s) return s;
    v->face_pixels = v->skin_stats.region;
    for (size_t i = 0; i < n; i++)
        for (int c = 0; c < 3; c++) v->albedo[3 * i + c] = (float)v->skin_stats.mean_linear[c];
    if (v->skin_stats.skin < 10) return FRIG_OK;
    return fr_sfs_fit_lighting(ctx, (int)n, v->skin, v->I, v->albedo, v->n_ref, NULL, v->sh);
}

static int is_set(const float *n) { return n[0] != 0 || n[1] != 0 || n[2] != 0; }

frig_status fr_sfs_photo_relight(frig_ctx *ctx, fr_sfs_view *v) {
    size_t n = (size_t)v->w * v->h;
    float *nrm = malloc(sizeof(float) * 3 * n);
    if (!nrm) return fr_nomem(ctx, "the lighting fit");
    for (size_t i = 0; i < n; i++) {
        const float *src = is_set(v->normal + 3 * i) ? v->normal + 3 * i
                           : is_set(v->n_prior + 3 * i) ? v->n_prior + 3 * i
                                                         : v->n_ref + 3 * i;
        memcpy(nrm + 3 * i, src, sizeof(float) * 3);
    }
    frig_status s = fr_sfs_fit_lighting(ctx, (int)n, v->skin, v->I, v->albedo, nrm, NULL, v->sh);
    free(nrm);
    return s;
}

frig_status fr_sfs_photo_depth(frig_ctx *ctx, fr_sfs_view *v, const fr_sfs_settings *st) {
    size_t n = (size_t)v->w * v->h;
    fr_sfs_depth_options o;
    fr_sfs_depth_options_default(&o);
    o.sigma = st->sigma;
    o.w_normal = st->w_normal;
    o.w_anchor = st->w_anchor;
    o.w_prior = st->w_prior;
    o.iterations = st->iterations;
    fr_sfs_depth_stats ds;
    frig_status s = fr_sfs_solve_depth(ctx, v, v->skin, &o, &ds);
    if (s) return s;
    v->data_pixels = ds.data_pixels;
    /* the median relative shading error over the skin pixels */
    float *e = malloc(sizeof(float) * (n + 1));
    if (!e) return fr_nomem(ctx, "the shading error");
    int m = 0;
    for (size_t i = 0; i < n; i++)
        if (v->skin[i] && v->err[i] >= 0) e[m++] = v->err[i];
    v->sfs_error = m ? fr_select_float(e, (size_t)m, (size_t)m / 2) : NAN;
    free(e);
    return FRIG_OK;
}

/* Rank correlation (Spearman) over the skin pixels between the photo's luminance and what the
 * subject's albedo and the photo's lighting and normals predict: a face of someone else, an
 * occluder or a background the detector took for a face do not follow the subject's albedo.
 * Ranks, because a few pixels with a wild normal (depth edges) must not decide it. */
typedef struct ranked {
    double v;
    int i;
} ranked;

static int cmp_ranked(const void *a, const void *b) {
    const ranked *x = a, *y = b;
    return x->v < y->v ? -1 : x->v > y->v ? 1 : x->i - y->i;
}

/* p (in index order) by value, then index: qsort's order with cmp_ranked, by the linear-time
 * radix sort when no value is NaN (cmp_ranked's order is then total, so both give it). */
static void sort_ranked(ranked *p, int m) {
    fr_sort_item *k = malloc(sizeof *k * (size_t)(m + 1));
    int ok = k != NULL;
    for (int j = 0; ok && j < m; j++) {
        if (isnan(p[j].v)) ok = 0;
        else k[j].key = fr_sort_key_double(p[j].v), k[j].index = j;
    }
    if (ok && !fr_sort_stable(k, (size_t)m)) {
        ranked *sorted = malloc(sizeof *sorted * (size_t)(m + 1));
        if (sorted) {
            for (int j = 0; j < m; j++) sorted[j] = p[k[j].index];
            memcpy(p, sorted, sizeof *p * (size_t)m);
            free(sorted), free(k);
            return;
        }
    }
    free(k);
    qsort(p, (size_t)m, sizeof *p, cmp_ranked);
}

double fr_sfs_photo_agreement(const fr_sfs_view *v) {
    size_t n = (size_t)v->w * v->h;
    int m = 0;
    for (size_t i = 0; i < n; i++) m += v->skin[i];
    if (m < 10) return 0;
    ranked *pa = malloc(sizeof(ranked) * (size_t)m), *pb = malloc(sizeof(ranked) * (size_t)m);
    double *ra = malloc(sizeof(double) * (size_t)m);
    if (!pa || !pb || !ra) {
        free(pa), free(pb), free(ra);
        return 0;
    }
    static const double lum[3] = {0.2126, 0.7152, 0.0722};
    int k = 0;
    for (size_t i = 0; i < n; i++) {
        if (!v->skin[i]) continue;
        const float *nn = v->normal + 3 * i;
        int has = nn[0] != 0 || nn[1] != 0 || nn[2] != 0;
        double S[3], a = 0, b = 0;
        fr_sfs_shading(v->sh, has ? nn : v->n_ref + 3 * i, S);
        for (int c = 0; c < 3; c++) a += lum[c] * v->I[3 * i + c], b += lum[c] * v->albedo[3 * i + c] * S[c];
        pa[k].v = a, pa[k].i = k, pb[k].v = b, pb[k].i = k;
        k++;
    }
    sort_ranked(pa, m);
    sort_ranked(pb, m);
    for (int r = 0; r < m; r++) ra[pa[r].i] = r;
    double d2 = 0;
    for (int r = 0; r < m; r++) {
        double d = ra[pb[r].i] - r;
        d2 += d * d;
    }
    free(pa), free(pb), free(ra);
    return 1.0 - 6.0 * d2 / ((double)m * ((double)m * m - 1.0));
}
