/* Skin albedo of a synthetic subject (the reflectance the shape-from-shading stage of paper
 * section 5.1 estimates; here it only has to make renders that face detectors and landmark
 * predictors accept): per-vertex linear RGB painted on the mean face from the 68 landmarks
 * (skin tone, lips, brows, lid lines, eye shadow, nostrils, blush, hair) plus smooth noise.
 * The iris and pupil are painted per pixel by the renderer (fr_synth_eye_albedo). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "model/model.h"
#include "synth/synth.h"

#define BEARD_SHARE 0.3 /* subjects with a beard */

typedef struct painter {
    const frig_model *m;
    const float *x;   /* mean-face positions (metres) */
    const int32_t *lm;
    uint8_t *cls;
    int face0, nface, head0, nhead;
    double skin[3], lip[3], brow[3], hair[3];
    double hairline, brow_density;
    int bald;
    double beard; /* density, 0 = clean-shaven */
} painter;

static void lin3(const double srgb[3], double out[3]) {
    for (int i = 0; i < 3; i++) out[i] = fr_srgb_to_linear(srgb[i] / 255.0);
}

static void mix3(double *c, const double t[3], double a) {
    for (int i = 0; i < 3; i++) c[i] += a * (t[i] - c[i]);
}

static const float *P(const painter *p, int landmark) { return p->x + 3 * (size_t)p->lm[landmark]; }

/* 2D (x, y) distance from q to segment a-b, and the parameter along it. */
static double seg_dist(const double q[2], const float *a, const float *b, double *t) {
    double ux = b[0] - a[0], uy = b[1] - a[1], wx = q[0] - a[0], wy = q[1] - a[1];
    double L = ux * ux + uy * uy, s = L > 0.0 ? (wx * ux + wy * uy) / L : 0.0;
    s = s < 0.0 ? 0.0 : s > 1.0 ? 1.0 : s;
    if (t) *t = s;
    double dx = wx - s * ux, dy = wy - s * uy;
    return sqrt(dx * dx + dy * dy);
}

/* Distance to the polyline through landmarks first..last (closed: back to first), and where
 * along it (0 at first, 1 at last). */
static double poly_dist(const painter *p, const double q[2], int first, int last, int closed, double *where) {
    double best = INFINITY, bw = 0.0;
    int n = last - first;
    for (int k = first; k < last + (closed ? 1 : 0); k++) {
        int k2 = k == last ? first : k + 1;
        double t, d = seg_dist(q, P(p, k), P(p, k2), &t);
        if (d < best) best = d, bw = n > 0 ? ((k - first) + t) / n : 0.0;
    }
    if (where) *where = bw;
    return best;
}

/* Even-odd point in the polygon of landmarks first..last (x, y). */
static int inside(const painter *p, const double q[2], int first, int last) {
    int in = 0;
    for (int i = first, j = last; i <= last; j = i++) {
        const float *a = P(p, i), *b = P(p, j);
        if ((a[1] > q[1]) != (b[1] > q[1]) && q[0] < (b[0] - a[0]) * (q[1] - a[1]) / (b[1] - a[1]) + a[0]) in = !in;
    }
    return in;
}

static void paint_lips(const painter *p, const float *x, double *c) {
    double q[2] = {x[0], x[1]};
    if (x[2] < P(p, 48)[2] - 0.012) return;
    double d = poly_dist(p, q, 48, 59, 1, NULL);
    /* the colour edge lies on the landmarks' contour */
    double a = inside(p, q, 48, 59) ? 0.5 + 0.5 * fr_smoothstep(0.0, 0.0012, d) : 0.5 - 0.5 * fr_smoothstep(0.0, 0.0008, d);
    if (a > 0.0) mix3(c, p->lip, a);
}

/* Returns how much brow covers the point. */
static double paint_brows(const painter *p, const float *x, double *c) {
    double most = 0.0;
    for (int side = 0; side < 2; side++) {
        int first = side ? 22 : 17, last = side ? 26 : 21;
        if (x[2] < P(p, first)[2] - 0.015) continue;
        double q[2] = {x[0], x[1] + 0.0012}, w; /* the brow lies just below the landmarks' line */
        double d = poly_dist(p, q, first, last, 0, &w);
        double inner = side ? 1.0 - w : w; /* 1 at the brow's inner end */
        double hw = 0.0022 + 0.0016 * inner;
        double a = 1.0 - fr_smoothstep(hw - 0.0008, hw + 0.0008, d);
        if (a > 0.0) mix3(c, p->brow, a * p->brow_density);
        most = fmax(most, a * p->brow_density);
    }
    return most;
}

static void paint_eye_surround(const painter *p, const float *x, double *c) {
    for (int side = 0; side < 2; side++) {
        int first = side ? 42 : 36, last = side ? 47 : 41;
        if (x[2] < P(p, first)[2] - 0.015) continue;
        double q[2] = {x[0], x[1]};
        double d = poly_dist(p, q, first, last, 1, NULL);
        double upper = poly_dist(p, q, first, first + 3, 0, NULL); /* corners and the upper lid */
        int in = inside(p, q, first, last);
        double shade = 1.0 - 0.22 * (1.0 - fr_smoothstep(0.0, 0.009, d)); /* socket shadow */
        double line = in ? 0.55
                         : fmin(1.0 - 0.65 * (1.0 - fr_smoothstep(0.0004, 0.0015, upper)),  /* upper lash line */
                                1.0 - 0.3 * (1.0 - fr_smoothstep(0.0002, 0.0008, d))); /* lower lid rim */
        for (int i = 0; i < 3; i++) c[i] *= shade * line;
    }
}

static void paint_nostrils(const painter *p, const float *x, const float *n, double *c) {
    const float *a = P(p, 31), *b = P(p, 35), *m = P(p, 33);
    for (int side = 0; side < 2; side++) {
        const float *e = side ? b : a;
        double cx = 0.5 * (e[0] + m[0]), cy = m[1] + 0.0025;
        double u = (x[0] - cx) / 0.0042, v = (x[1] - cy) / 0.0028;
        if (x[2] < m[2] - 0.02 || n[1] > -0.15) continue;
        double a2 = 1.0 - fr_smoothstep(0.6, 1.0, sqrt(u * u + v * v));
        for (int i = 0; i < 3; i++) c[i] *= 1.0 - 0.8 * a2;
    }
}

/* Height of the hairline over depth z (model metres): the forehead at the front, above the
 * ears at the sides, the nape at the back. */
static double hairline_at(const painter *p, double z) {
    if (z >= 0.06) return p->hairline;
    if (z >= 0.0) return 0.05 + (p->hairline - 0.05) * z / 0.06;
    double t = fmin(1.0, -z / 0.07);
    return 0.05 + (-0.03 - 0.05) * t;
}

/* Returns how much hair covers the point. */
static double paint_hair(const painter *p, const float *x, int in_face, double *c) {
    if (p->bald) return 0.0;
    int ear = in_face && fabs(x[0]) > 0.068 && x[1] < 0.06 && x[2] < 0.04; /* the ears are face vertices */
    if (ear) return 0.0;
    double a = fr_smoothstep(-0.004, 0.006, x[1] - hairline_at(p, x[2]));
    if (a > 0.0) mix3(c, p->hair, a);
    return a;
}

/* Signed side of q relative to the line a -> b in (x, y) (positive to its left). */
static double side_of(const double q[2], const float *a, const float *b) {
    return (b[0] - a[0]) * (q[1] - a[1]) - (b[1] - a[1]) * (q[0] - a[0]);
}

/* A beard: the jaw and chin below the lines from the ears' level of the jaw (landmarks 2, 14)
 * to the mouth corners, under the chin, and a moustache between the nose and the upper lip;
 * never on the lips. Returns how much beard covers the point. */
static double paint_beard(const painter *p, const float *x, double *c) {
    if (p->beard <= 0.0 || x[2] < P(p, 8)[2] - 0.07) return 0.0;
    double q[2] = {x[0], x[1]};
    if (inside(p, q, 48, 59) || poly_dist(p, q, 48, 59, 1, NULL) < 0.0015) return 0.0;
    int right = x[0] < 0.0;
    const float *ear = P(p, right ? 2 : 14), *corner = P(p, right ? 48 : 54);
    double s = side_of(q, ear, corner) * (right ? -1.0 : 1.0) / 0.05;
    double jaw = fr_smoothstep(-0.002, 0.003, s) * (1.0 - fr_smoothstep(0.075, 0.085, fabs(x[0])));
    double below = P(p, 8)[1] - x[1]; /* under the chin, onto the neck */
    double chin = 1.0 - fr_smoothstep(0.03, 0.045, below);
    double a = jaw * chin;
    double top = P(p, 33)[1] - 0.003, bottom = fmax(P(p, 50)[1], P(p, 52)[1]) + 0.001;
    if (x[1] < top && x[1] > bottom && fabs(x[0]) < fabs(P(p, 48)[0]) + 0.004 && x[2] > P(p, 33)[2] - 0.02)
        a = fmax(a, fr_smoothstep(0.0, 0.002, fmin(top - x[1], x[1] - bottom)));
    a *= p->beard;
    if (a > 0.0) mix3(c, p->hair, a);
    return a;
}

/* Paints vertex v; returns how much hair, brow or beard covers it. */
static double skin_vertex(const painter *p, int v, const float *normals, fr_rng *rng, const fr_bump *blot, int nblot,
                          double *c) {
    const float *x = p->x + 3 * (size_t)v;
    memcpy(c, p->skin, sizeof p->skin);
    double q[3] = {x[0], x[1], x[2]}, f[3];
    fr_bumps_eval(blot, nblot, q, f); /* smooth tone variation and cheek blush */
    for (int i = 0; i < 3; i++) c[i] *= 1.0 + f[i];
    int in_face = v >= p->face0 && v < p->face0 + p->nface;
    double hair = 0.0;
    if (in_face) {
        paint_lips(p, x, c);
        paint_eye_surround(p, x, c);
        paint_nostrils(p, x, normals + 3 * (size_t)v, c);
        hair = paint_brows(p, x, c);
    }
    hair = fmax(hair, paint_beard(p, x, c));
    hair = fmax(hair, paint_hair(p, x, in_face, c));
    double grain = 1.0 + 0.03 * (fr_rng_uniform(rng) - 0.5);
    for (int i = 0; i < 3; i++) c[i] *= grain;
    return hair;
}

static void pick_colours(painter *p, frig_synth_subject *s, fr_rng *rng) {
    static const double light[3] = {236, 198, 172}, dark[3] = {112, 74, 54};
    static const double hairs[][3] = {{28, 22, 20}, {58, 40, 28}, {98, 68, 44}, {172, 140, 96}, {140, 138, 134},
                                      {120, 58, 34}};
    static const double irises[][3] = {{86, 54, 30}, {48, 30, 20}, {72, 100, 138}, {82, 104, 70}, {112, 86, 52}};
    double t = fr_rng_uniform(rng);
    for (int i = 0; i < 3; i++)
        s->skin_srgb[i] = (1.0 - t) * light[i] + t * dark[i] + 6.0 * (fr_rng_uniform(rng) - 0.5);
    int h = (int)fr_rng_below(rng, 6), e = (int)fr_rng_below(rng, 5);
    memcpy(s->hair_srgb, hairs[h], sizeof s->hair_srgb);
    memcpy(s->iris_srgb, irises[e], sizeof s->iris_srgb);
    s->bald = fr_rng_uniform(rng) < 0.1;
    lin3(s->skin_srgb, p->skin);
    lin3(s->hair_srgb, p->hair);
    double lip_srgb[3] = {s->skin_srgb[0] * 0.82, s->skin_srgb[1] * 0.52, s->skin_srgb[2] * 0.55};
    lin3(lip_srgb, p->lip);
    double brow_srgb[3];
    for (int i = 0; i < 3; i++) brow_srgb[i] = fmin(s->hair_srgb[i], s->skin_srgb[i]) * 0.45;
    lin3(brow_srgb, p->brow);
    p->brow_density = 0.75 + 0.2 * fr_rng_uniform(rng);
    p->hairline = 0.088 + 0.014 * fr_rng_uniform(rng);
    p->bald = s->bald;
}

/* Smooth tone variation (a few percent) and a blush on each cheek. */
static int draw_blots(const painter *p, fr_rng *rng, fr_bump *b, int max) {
    int n = 0;
    for (; n < max - 2; n++) {
        int v = p->face0 + (int)fr_rng_below(rng, (uint64_t)p->nface);
        for (int d = 0; d < 3; d++) b[n].c[d] = p->x[3 * (size_t)v + d];
        b[n].r = 0.02 + 0.02 * fr_rng_uniform(rng);
        double l = 0.07 * (fr_rng_uniform(rng) - 0.5), hue = 0.03 * (fr_rng_uniform(rng) - 0.5);
        b[n].v[0] = l + hue, b[n].v[1] = l, b[n].v[2] = l - hue;
    }
    for (int side = 0; side < 2; side++, n++) {
        const float *e = P(p, side ? 46 : 41), *j = P(p, side ? 13 : 3);
        for (int d = 0; d < 3; d++) b[n].c[d] = 0.45 * e[d] + 0.55 * j[d];
        b[n].c[2] += 0.01;
        b[n].r = 0.018;
        double a = 0.06 + 0.06 * fr_rng_uniform(rng);
        b[n].v[0] = a, b[n].v[1] = -0.5 * a, b[n].v[2] = -0.4 * a;
    }
    return n;
}

static void fixed_colours(const painter *p, const frig_synth_subject *s, int v, double *c) {
    static const double teeth[3] = {226, 216, 190}, gums[3] = {168, 72, 78}, mouth[3] = {92, 34, 40},
                        sclera[3] = {226, 218, 212};
    int first, count;
    if (fr_synth_region(p->m, "teeth", &first, &count) && v >= first && v < first + count) lin3(teeth, c);
    else if (p->cls[v] == FR_SYNTH_GUMS) lin3(gums, c);
    else if (p->cls[v] == FR_SYNTH_OVERLAY) {
        for (int i = 0; i < 3; i++) c[i] = fr_srgb_to_linear(fmin(s->hair_srgb[i], 60.0) / 255.0);
    } else if (p->cls[v] == FR_SYNTH_RIGID) lin3(sclera, c);
    else lin3(mouth, c);
}

frig_status fr_synth_paint_albedo(frig_ctx *ctx, const frig_model *model, frig_synth_subject *s, fr_rng *rng) {
    painter p = {0};
    p.m = model;
    p.x = model->neutral;
    p.lm = model->landmarks;
    int nv = model->topo.vertex_count;
    if (!fr_synth_region(model, "face", &p.face0, &p.nface) || !fr_synth_region(model, "head_neck", &p.head0, &p.nhead))
        return fr_error(ctx, FRIG_ERR_UNSUPPORTED, "the model lacks the 'face' or 'head_neck' region");
    p.cls = fr_synth_vertex_classes(model);
    float *normals = malloc(sizeof *normals * 3 * (size_t)nv);
    if (!p.cls || !normals) {
        free(p.cls), free(normals);
        return fr_nomem(ctx, "the synthetic albedo");
    }
    fr_mesh_vertex_normals(model->neutral, nv, model->topo.triangles, model->topo.triangle_count, normals);
    pick_colours(&p, s, rng);
    fr_bump blot[14];
    int nblot = draw_blots(&p, rng, blot, 14);
    /* The beard from a stream of its own: the other colours stay what they were. */
    fr_rng beard;
    fr_rng_seed(&beard, fr_seed_mix(s->seed, 0xbea4dULL));
    s->beard = fr_rng_uniform(&beard) < BEARD_SHARE;
    p.beard = s->beard ? 0.55 + 0.4 * fr_rng_uniform(&beard) : 0.0;
    for (int v = 0; v < nv; v++) {
        double c[3];
        int skin = (v >= p.face0 && v < p.face0 + p.nface) || (v >= p.head0 && v < p.head0 + p.nhead);
        if (skin) s->hair[v] = (float)skin_vertex(&p, v, normals, rng, blot, nblot, c);
        else fixed_colours(&p, s, v, c);
        s->skin[v] = (uint8_t)(skin && p.cls[v] == FR_SYNTH_SKIN);
        for (int i = 0; i < 3; i++) s->albedo[3 * (size_t)v + i] = (float)fmin(1.0, fmax(0.0, c[i]));
    }
    free(p.cls), free(normals);
    return FRIG_OK;
}
