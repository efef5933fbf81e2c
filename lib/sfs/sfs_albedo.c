/* The subject's albedo in UV space (paper section 5.1.2 and Algorithm 5): each photo's
 * illumination factored out, a = I / I_lighting (eq. 5.14), and the per-photo albedos averaged
 * in the model's texture space ("ComputeMeanTexture"). Per texel the average is the weighted
 * least-squares albedo a_c = sum w S I / sum w S^2 over the photos that see the texel (S the
 * photo's shading there), the weights the view cosine times the photo's weight, reweighted once
 * by Tukey's biweight so that cast shadows, highlights and misregistered edges do not tint it.
 * For the texture a view whose colour would need an albedo above 1 (or whose shading is not
 * positive), or an albedo greener or bluer than red, does not count: on Bing Will Smith such
 * views painted the face's sides and the neck's top in saturated red, green, magenta and black
 * (docs/sfs.md, "The albedo texture's outline"). The texture's views are also divided by a shading
 * whose colour stays near the light's colour on a surface facing the camera
 * (fr_sfs_texture_shading), which took the yellow-green off the face's sides ("The albedo
 * texture's colours"). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "raster/rotation.h"
#include "sfs/sfs_albedo.h"

#define TUKEY_C 4.685
#define INTENSITY_FLOOR 0.03
#define VISIBLE_TOL 0.004 /* metres: a texel this close behind the drawn surface is seen */
#define MIN_COS 0.2
#define ALBEDO_MAX 1.0  /* linear: the texture's views need no more */
#define LIGHT_HUE_SPREAD 0.1 /* the texture's shading: each channel's share within 10% of the frontal light's */
#define SKIN_CHROMA 1.05 /* the texture's views: green and blue at most this times red */

void fr_sfs_albedo_free(fr_sfs_albedo *a) {
    free(a->albedo), free(a->weight);
    memset(a, 0, sizeof *a);
}

frig_status fr_sfs_albedo_init(frig_ctx *ctx, const fr_sfs_uv *uv, fr_sfs_albedo *a) {
    memset(a, 0, sizeof *a);
    size_t n = (size_t)uv->size * uv->size;
    a->size = uv->size;
    a->albedo = calloc(3 * n, sizeof(float));
    a->weight = calloc(n, sizeof(float));
    if (!a->albedo || !a->weight) {
        fr_sfs_albedo_free(a);
        return fr_nomem(ctx, "the UV albedo");
    }
    return FRIG_OK;
}

typedef struct obs {
    double I[3], S[3], w, scale;
} obs;

/* The texture's rule for a view: a colour the shading cannot explain (a grazing normal's tiny or
 * negative shading, the background or hair at the face's outline: an albedo above 1), or that is
 * no skin's (greener or bluer than red: melanin and haemoglobin absorb the shorter wavelengths
 * most), is not the face's. */
static int skin_colour(const obs *ob) {
    double a[3];
    for (int c = 0; c < 3; c++) {
        if (!(ob->S[c] > 0) || ob->I[c] > ALBEDO_MAX * ob->S[c]) return 0;
        a[c] = ob->I[c] / ob->S[c];
    }
    return a[1] <= SKIN_CHROMA * a[0] && a[2] <= SKIN_CHROMA * a[0];
}

void fr_sfs_texture_shading(const double sh[3][FR_SH_COUNT], const float n[3], double S[3]) {
    const float front[3] = {0, 0, -1};
    double F[3];
    fr_sfs_shading(sh, front, F);
    fr_sfs_shading(sh, n, S);
    double level = (S[0] + S[1] + S[2]) / 3, front_level = (F[0] + F[1] + F[2]) / 3;
    for (int c = 0; c < 3; c++) {
        double front_share = front_level > 0 && level > 0 ? F[c] / front_level : 0, share = level > 0 ? S[c] / level : 0;
        S[c] = level * fmin(fmax(share, front_share * (1 - LIGHT_HUE_SPREAD)), front_share * (1 + LIGHT_HUE_SPREAD));
    }
}

/* Texel k as each used view shows it: colour, shading, weight. */
static int gather(const fr_sfs_mesh *m, const fr_sfs_uv *uv, const fr_sfs_view *views, int nviews, const uint8_t *use,
                  int k, double sigma, int texture, obs *o) {
    int n = 0;
    const int32_t *tri = m->tris + 3 * (size_t)uv->tri[k];
    const float *b = uv->bary + 3 * (size_t)k;
    for (int j = 0; j < nviews; j++) {
        const fr_sfs_view *v = &views[j];
        if (!use[j] || !(v->photo_weight > 0)) continue;
        double xy[2];
        if (!fr_sfs_uv_locate(uv, m, v, k, VISIBLE_TOL, xy, NULL)) continue;
        size_t i = (size_t)floor(xy[1] + 0.5) * v->w + (size_t)floor(xy[0] + 0.5);
        if (!v->skin[i] || !v->face[i]) continue;
        float nc[3] = {0, 0, 0};
        for (int c = 0; c < 3; c++)
            for (int q = 0; q < 3; q++) nc[q] += b[c] * v->vn_cam[3 * (size_t)tri[c] + q];
        double l = sqrt((double)nc[0] * nc[0] + (double)nc[1] * nc[1] + (double)nc[2] * nc[2]);
        if (!(l > 0)) continue;
        for (int q = 0; q < 3; q++) nc[q] = (float)(nc[q] / l);
        double ray[3] = {(xy[0] - v->cam.cx) / v->cam.f, (xy[1] - v->cam.cy) / v->cam.f, 1.0};
        double cosv = -(nc[0] * ray[0] + nc[1] * ray[1] + nc[2] * ray[2]) / sqrt(ray[0] * ray[0] + ray[1] * ray[1] + 1);
        if (cosv < MIN_COS) continue;
        obs *ob = &o[n];
        fr_bilinear3(v->I, v->w, v->h, xy, ob->I);
        if (texture) fr_sfs_texture_shading(v->sh, nc, ob->S);
        else fr_sfs_shading(v->sh, nc, ob->S);
        if (texture && !skin_colour(ob)) continue;
        n++;
        double mean = (ob->I[0] + ob->I[1] + ob->I[2]) / 3;
        ob->scale = sigma * (mean > INTENSITY_FLOOR ? mean : INTENSITY_FLOOR);
        ob->w = cosv * v->photo_weight;
    }
    return n;
}

static double tukey_w(double u) {
    u /= TUKEY_C;
    return fabs(u) < 1 ? (1 - u * u) * (1 - u * u) : 0;
}

/* a_c = sum w S I / sum w S^2, then once more with Tukey weights of the residuals. */
static double texel_albedo(const obs *o, int n, double a[3]) {
    double wsum = 0;
    for (int pass = 0; pass < 2; pass++) {
        double num[3] = {0, 0, 0}, den[3] = {0, 0, 0};
        wsum = 0;
        for (int j = 0; j < n; j++)
            for (int c = 0; c < 3; c++) {
                double w = o[j].w / (o[j].scale * o[j].scale);
                if (pass) w *= tukey_w((a[c] * o[j].S[c] - o[j].I[c]) / o[j].scale);
                num[c] += w * o[j].S[c] * o[j].I[c], den[c] += w * o[j].S[c] * o[j].S[c];
                wsum += o[j].w * (w > 0) / 3.0;
            }
        for (int c = 0; c < 3; c++)
            if (den[c] > 0) a[c] = num[c] / den[c];
            else if (pass == 0) a[c] = 0;
    }
    return wsum;
}

frig_status fr_sfs_albedo_solve(frig_ctx *ctx, const fr_sfs_mesh *m, const fr_sfs_uv *uv, const fr_sfs_view *views,
                                int nviews, const uint8_t *use, double sigma, int texture, fr_sfs_albedo *out) {
    int failed = 0;
#pragma omp parallel num_threads(fr_threads(ctx))
    {
        obs *ob = malloc(sizeof(obs) * (size_t)(nviews + 1));
        if (!ob) {
#pragma omp atomic write
            failed = 1;
        }
#pragma omp for schedule(dynamic, 256)
        for (int k = 0; k < uv->count; k++) {
            if (!ob || fr_cancelled(ctx)) continue;
            size_t t = (size_t)uv->texel[k];
            int n = gather(m, uv, views, nviews, use, k, sigma, texture, ob);
            double a[3] = {0, 0, 0};
            out->weight[t] = n ? (float)texel_albedo(ob, n, a) : 0.0f;
            for (int c = 0; c < 3; c++) out->albedo[3 * t + c] = (float)(a[c] > 0 ? a[c] : 0);
        }
        free(ob);
    }
    if (failed) return fr_nomem(ctx, "the UV albedo");
    return fr_check_cancel(ctx, "sfs.albedo");
}

void fr_sfs_albedo_apply(const fr_sfs_mesh *m, const fr_sfs_albedo *a, fr_sfs_view *v, const double fallback[3]) {
    size_t n = (size_t)v->w * v->h;
    for (size_t i = 0; i < n; i++) {
        float *np = v->n_prior + 3 * i;
        np[0] = np[1] = np[2] = 0;
        double uv[2];
        if (!v->face[i] || !fr_sfs_uv_at_pixel(m, v, i, uv)) continue;
        float al[3];
        int seen = fr_sfs_texture_sample(a->albedo, a->weight, a->size, 3, uv, al);
        for (int q = 0; q < 3; q++) v->albedo[3 * i + q] = seen ? al[q] : (float)fallback[q];
        memcpy(np, v->n_ref + 3 * i, sizeof(float) * 3);
    }
}
