/* The personal displacement of a synthetic subject (paper section 7.2: ground truth must lie
 * outside the fitted model's span): a smooth field of Gaussian bumps on the face, faded out
 * toward the back of the head, scaled to synth.offset_mm RMS over the face region, with its
 * least-squares projection onto the identity modes there removed (what remains is the part no
 * identity can explain). Eyeballs, teeth and gums move rigidly; the lids move with the eyeballs. */
#include <cblas.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "linalg/linalg.h"
#include "model/model.h"
#include "synth/synth.h"

#define FADE_NEAR 0.005 /* metres from the narrow face where the field starts to fade */
#define FADE_FAR 0.035  /* ... and where it is gone */
#define EYE_CALM_IN 0.016  /* within this distance of an eyeball's centre the field is the eyeball's */
#define EYE_CALM_OUT 0.030 /* beyond this it is the bumps' own */
#define MOUTH_CALM_IN 0.006  /* skin this close to the teeth or gums moves with them */
#define MOUTH_CALM_OUT 0.018
#define MOUTH_STRIDE 6       /* teeth and gum vertices sampled for that distance */
#define FADE_STRIDE 3      /* narrow-face vertices sampled for the fade distance */

typedef struct offset_work {
    const frig_model *m;
    int nv, face0, nface, narrow0, nnarrow;
    const float *neutral;
    uint8_t *cls;
    float *normals;
    double eye[2][3], eye_shift[2][3], mouth_shift[3];
    int eye_first[2], eye_count[2];
    fr_bump *bumps;
    int nb;
    double *d; /* 3 nv: the raw field */
} offset_work;

static double dist2(const float *a, const double b[3]) {
    double dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
    return dx * dx + dy * dy + dz * dz;
}

/* 1 on the narrow face, fading to 0 at FADE_FAR from it. */
static double fade_at(const offset_work *w, int v) {
    if (v >= w->narrow0 && v < w->narrow0 + w->nnarrow) return 1.0;
    const float *x = w->neutral + 3 * (size_t)v;
    double p[3] = {x[0], x[1], x[2]}, best = INFINITY;
    for (int i = w->narrow0; i < w->narrow0 + w->nnarrow; i += FADE_STRIDE) {
        double q = dist2(w->neutral + 3 * (size_t)i, p);
        if (q < best) best = q;
    }
    return 1.0 - fr_smoothstep(FADE_NEAR, FADE_FAR, sqrt(best));
}

static void draw_bumps(offset_work *w, fr_rng *rng) {
    for (int k = 0; k < w->nb; k++) {
        fr_bump *b = &w->bumps[k];
        int v = w->narrow0 + (int)fr_rng_below(rng, (uint64_t)w->nnarrow);
        const float *x = w->neutral + 3 * (size_t)v, *n = w->normals + 3 * (size_t)v;
        double dir[3], len = 0.0;
        for (int d = 0; d < 3; d++) {
            b->c[d] = x[d];
            dir[d] = n[d] + 0.4 * fr_rng_normal(rng);
            len += dir[d] * dir[d];
        }
        len = sqrt(len);
        b->r = 0.015 + 0.025 * fr_rng_uniform(rng);
        double a = fr_rng_normal(rng);
        for (int d = 0; d < 3; d++) b->v[d] = len > 0.0 ? a * dir[d] / len : 0.0;
    }
}

/* Which eyeball vertex v belongs to (0, 1) or -1. */
static int eyeball_of(const offset_work *w, int v) {
    for (int e = 0; e < 2; e++)
        if (v >= w->eye_first[e] && v < w->eye_first[e] + w->eye_count[e]) return e;
    return -1;
}

/* Distance from vertex v to the nearest (sampled) teeth or gum vertex. */
static double mouth_dist(const offset_work *w, int v) {
    const float *x = w->neutral + 3 * (size_t)v;
    double p[3] = {x[0], x[1], x[2]}, best = INFINITY;
    for (int i = 0; i < w->nv; i += MOUTH_STRIDE)
        if (w->cls[i] == FR_SYNTH_GUMS || (w->cls[i] == FR_SYNTH_RIGID && eyeball_of(w, i) < 0)) {
            double q = dist2(w->neutral + 3 * (size_t)i, p);
            if (q < best) best = q;
        }
    return sqrt(best);
}

/* Teeth and gums move rigidly by the bumps' mean over the teeth. */
static void mouth_shift(offset_work *w) {
    int first, count;
    double t[3] = {0, 0, 0};
    if (fr_synth_region(w->m, "teeth", &first, &count))
        for (int v = first; v < first + count; v++) {
            const float *x = w->neutral + 3 * (size_t)v;
            double p[3] = {x[0], x[1], x[2]}, f[3];
            fr_bumps_eval(w->bumps, w->nb, p, f);
            for (int d = 0; d < 3; d++) t[d] += f[d] / count;
        }
    memcpy(w->mouth_shift, t, sizeof t);
}

/* The raw field: bumps on skin and overlays, eyeballs and teeth shifted rigidly, and the skin
 * around them blended to their shifts so lids stay on the eyeballs and lips over the teeth. */
static void raw_field(offset_work *w) {
    for (int e = 0; e < 2; e++) fr_bumps_eval(w->bumps, w->nb, w->eye[e], w->eye_shift[e]);
    mouth_shift(w);
    for (int v = 0; v < w->nv; v++) {
        double *o = w->d + 3 * (size_t)v;
        int e = eyeball_of(w, v);
        if (e >= 0) {
            memcpy(o, w->eye_shift[e], sizeof w->eye_shift[e]);
            continue;
        }
        if (w->cls[v] == FR_SYNTH_RIGID || w->cls[v] == FR_SYNTH_GUMS) {
            memcpy(o, w->mouth_shift, sizeof w->mouth_shift);
            continue;
        }
        const float *x = w->neutral + 3 * (size_t)v;
        double p[3] = {x[0], x[1], x[2]}, f[3];
        fr_bumps_eval(w->bumps, w->nb, p, f);
        double fade = fade_at(w, v);
        for (int d = 0; d < 3; d++) o[d] = fade * f[d];
        int near = dist2(x, w->eye[0]) <= dist2(x, w->eye[1]) ? 0 : 1;
        double calm = fr_smoothstep(EYE_CALM_IN, EYE_CALM_OUT, sqrt(dist2(x, w->eye[near])));
        for (int d = 0; d < 3; d++) o[d] = w->eye_shift[near][d] + calm * (o[d] - w->eye_shift[near][d]);
        calm = fr_smoothstep(MOUTH_CALM_IN, MOUTH_CALM_OUT, mouth_dist(w, v));
        for (int d = 0; d < 3; d++) o[d] = w->mouth_shift[d] + calm * (o[d] - w->mouth_shift[d]);
    }
}

/* c = argmin || d_face - U_face c || by the normal equations (double, serial BLAS). */
static frig_status project(frig_ctx *ctx, const offset_work *w, double *c) {
    int K = w->m->identity_count, rows = 3 * w->nface;
    size_t n3 = 3 * (size_t)w->nv;
    double *A = malloc(sizeof *A * (size_t)rows * (size_t)K), *G = malloc(sizeof *G * (size_t)K * (size_t)K);
    if (!A || !G) {
        free(A), free(G);
        return fr_nomem(ctx, "the offset's projection");
    }
    for (int k = 0; k < K; k++)
        for (int i = 0; i < rows; i++)
            A[(size_t)k * (size_t)rows + (size_t)i] = w->m->identity[n3 * (size_t)k + 3 * (size_t)w->face0 + (size_t)i];
    int saved = fr_blas_serial_begin();
    cblas_dsyrk(CblasColMajor, CblasLower, CblasTrans, K, rows, 1.0, A, rows, 0.0, G, K);
    cblas_dgemv(CblasColMajor, CblasTrans, rows, K, 1.0, A, rows, w->d + 3 * (size_t)w->face0, 1, 0.0, c, 1);
    frig_status s = fr_solve_spd(ctx, K, 1, G, K, c, K);
    fr_blas_serial_end(saved);
    free(A), free(G);
    return s;
}

static double face_rms(const offset_work *w, const double *x) {
    double e = 0.0;
    for (size_t i = 3 * (size_t)w->face0; i < 3 * (size_t)(w->face0 + w->nface); i++) e += x[i] * x[i];
    return sqrt(e / w->nface);
}

static frig_status setup(frig_ctx *ctx, offset_work *w, const frig_model *m, const float *neutral) {
    w->m = m;
    w->nv = m->topo.vertex_count;
    w->neutral = neutral;
    if (!fr_synth_region(m, "face", &w->face0, &w->nface))
        return fr_error(ctx, FRIG_ERR_UNSUPPORTED, "the model has no 'face' region for the synthetic offset");
    if (!fr_synth_region(m, "narrow_face", &w->narrow0, &w->nnarrow)) w->narrow0 = w->face0, w->nnarrow = w->nface;
    static const char *const eyes[2] = {"eyeball_left", "eyeball_right"};
    for (int e = 0; e < 2; e++) {
        if (!fr_synth_region(m, eyes[e], &w->eye_first[e], &w->eye_count[e]))
            return fr_error(ctx, FRIG_ERR_UNSUPPORTED, "the model has no '%s' region", eyes[e]);
        fr_synth_region_centroid(m, eyes[e], neutral, w->eye[e]);
    }
    w->cls = fr_synth_vertex_classes(m);
    w->normals = malloc(sizeof *w->normals * 3 * (size_t)w->nv);
    w->d = malloc(sizeof *w->d * 3 * (size_t)w->nv);
    w->bumps = malloc(sizeof *w->bumps * 32);
    if (!w->cls || !w->normals || !w->d || !w->bumps) return fr_nomem(ctx, "the synthetic offset");
    fr_mesh_vertex_normals(neutral, w->nv, m->topo.triangles, m->topo.triangle_count, w->normals);
    return FRIG_OK;
}

frig_status fr_synth_offset(frig_ctx *ctx, const frig_model *model, frig_synth_subject *s, fr_rng *rng,
                            double offset_mm, float *neutral) {
    offset_work w = {0};
    double *c = NULL;
    frig_status st = setup(ctx, &w, model, neutral);
    w.nb = 12 + (int)fr_rng_below(rng, 19);
    if (!st) {
        draw_bumps(&w, rng);
        raw_field(&w);
        c = malloc(sizeof *c * (size_t)(model->identity_count > 0 ? model->identity_count : 1));
        if (!c) st = fr_nomem(ctx, "the offset's projection");
    }
    if (!st && model->identity_count > 0) st = project(ctx, &w, c);
    if (!st) {
        double raw = face_rms(&w, w.d);
        size_t n3 = 3 * (size_t)w.nv;
        for (int k = 0; k < model->identity_count; k++)
            for (size_t i = 0; i < n3; i++) w.d[i] -= c[k] * model->identity[n3 * (size_t)k + i];
        double out = face_rms(&w, w.d);
        double scale = raw > 0.0 ? offset_mm * 1e-3 / raw : 0.0;
        for (size_t i = 0; i < n3; i++) neutral[i] = (float)(neutral[i] + scale * w.d[i]);
        s->offset_bumps = w.nb;
        s->offset_rms_mm = out * scale * 1e3;
        s->offset_raw_rms_mm = raw * scale * 1e3;
        s->offset_in_span = raw > 0.0 ? 1.0 - (out * out) / (raw * raw) : 0.0;
    }
    free(c), free(w.cls), free(w.normals), free(w.d), free(w.bumps);
    return st;
}
