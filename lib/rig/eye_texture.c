/* Base-colour textures libfrig paints for the rig's eyes, so that an imported rig has eyes
 * that look like eyes instead of flat grey shells: ICT's sclera mesh is the eyeball's outer
 * shell and covers the iris with its cornea, so the sclera texture is transparent over the
 * cornea (alpha mask); the iris mesh (the inner shell) gets an iris with radial fibres, a dark
 * limbal ring and a pupil (ICT's PupilDilate moves the pupil's vertices, so the painted pupil
 * widens with it); the eye occlusion and eye blend overlays get an alpha that fades from their
 * border. Each texel is painted from the rig's neutral at the surface point the texel's UV
 * lands on (the material's triangles rasterized in UV space), so any UV layout works. */
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "core/rng.h"
#include "image/image.h"
#include "image/srgb.h"
#include "mesh/eye_frame.h"
#include "raster/raster.h"
#include "rig/look.h"


void fr_texture_free(fr_texture *t) {
    if (!t) return;
    free(t->pixels);
    free(t->png);
    memset(t, 0, sizeof *t);
}

/* The four texels around (u, v) (clamped: the UV islands have gutters) and their bilinear weights. */
static void bilinear(const fr_texture *t, double u, double v, const uint8_t *p[4], double w[4]) {
    double x = (u - floor(u)) * t->width - 0.5, y = (1.0 - (v - floor(v))) * t->height - 0.5;
    int x0 = (int)floor(x), y0 = (int)floor(y);
    double fx = x - x0, fy = y - y0;
    for (int j = 0; j < 2; j++)
        for (int i = 0; i < 2; i++) {
            int xi = x0 + i, yj = y0 + j;
            xi = xi < 0 ? 0 : xi >= t->width ? t->width - 1 : xi;
            yj = yj < 0 ? 0 : yj >= t->height ? t->height - 1 : yj;
            w[2 * j + i] = (i ? fx : 1.0 - fx) * (j ? fy : 1.0 - fy);
            p[2 * j + i] = t->pixels + ((size_t)yj * (size_t)t->width + (size_t)xi) * (size_t)t->channels;
        }
}

void fr_texture_sample(const fr_texture *t, double u, double v, double rgba[4]) {
    const uint8_t *p[4];
    double w[4];
    bilinear(t, u, v, p, w);
    rgba[0] = rgba[1] = rgba[2] = 0.0, rgba[3] = 0.0;
    for (int k = 0; k < 4; k++) {
        for (int c = 0; c < 3; c++) rgba[c] += w[k] * p[k][c] / 255.0;
        rgba[3] += w[k] * (t->channels == 4 ? p[k][3] / 255.0 : 1.0);
    }
}

void fr_texture_sample_linear(const fr_texture *t, const float decode[256], double u, double v, double rgba[4]) {
    const uint8_t *p[4];
    double w[4];
    bilinear(t, u, v, p, w);
    rgba[0] = rgba[1] = rgba[2] = 0.0, rgba[3] = 0.0;
    for (int k = 0; k < 4; k++) {
        for (int c = 0; c < 3; c++) rgba[c] += w[k] * decode[p[k][c]];
        rgba[3] += w[k] * (t->channels == 4 ? p[k][3] / 255.0 : 1.0);
    }
}

/* ---- the painters: colour (sRGB, 0..1) and alpha of a surface point ---- */

/* Radial streaks: a sum of 48 angular harmonics with fixed random phases (seeded per eye),
 * twisting a little with the radius, tabulated over (angle, radius) and read bilinearly. */
#define STREAK_ANGLES 1024
#define STREAK_RADII 16
#define STREAK_MAX_RHO 3.5

typedef struct streaks {
    float table[STREAK_RADII][STREAK_ANGLES];
} streaks;

static void streaks_init(streaks *s, uint64_t seed) {
    double phase[48], amp[48], norm = 0.0;
    int freq[48];
    fr_rng rng;
    fr_rng_seed(&rng, seed);
    for (int k = 0; k < 48; k++) {
        freq[k] = 6 + (int)fr_rng_below(&rng, 90);
        phase[k] = 2.0 * M_PI * fr_rng_uniform(&rng);
        amp[k] = 0.3 + 0.7 * fr_rng_uniform(&rng);
        norm += amp[k];
    }
    for (int j = 0; j < STREAK_RADII; j++)
        for (int i = 0; i < STREAK_ANGLES; i++) {
            double angle = 2.0 * M_PI * i / STREAK_ANGLES, rho = STREAK_MAX_RHO * j / (STREAK_RADII - 1), v = 0.0;
            for (int k = 0; k < 48; k++) v += amp[k] * cos(freq[k] * angle + phase[k] + 1.5 * rho * (k % 3 - 1));
            s->table[j][i] = (float)(2.2 * v / norm);
        }
}

/* An eye's fibres depend on the eye alone: made once per process (each table 64 KB), not for every
 * texture of every export and picture. */
static const streaks *eye_fibres(int eye) {
    static streaks tables[2];
    static int ready[2];
    const streaks *out;
#pragma omp critical(frig_eye_fibres)
    {
        if (!ready[eye]) streaks_init(&tables[eye], 0x1415926535ull + (uint64_t)eye), ready[eye] = 1;
        out = &tables[eye];
    }
    return out;
}

/* About [-1, 1]: fibres along the radius (angle in radians, any value; rho in iris radii). */
static double streak(const streaks *s, double angle, double rho) {
    double a = angle / (2.0 * M_PI);
    a = (a - floor(a)) * STREAK_ANGLES;
    double r = fmin(fmax(rho, 0.0), STREAK_MAX_RHO) / STREAK_MAX_RHO * (STREAK_RADII - 1);
    int i0 = (int)a % STREAK_ANGLES, i1 = (i0 + 1) % STREAK_ANGLES, j0 = (int)r, j1 = j0 + 1 < STREAK_RADII ? j0 + 1 : j0;
    double fa = a - floor(a), fr = r - j0;
    double lo = s->table[j0][i0] + fa * (s->table[j0][i1] - s->table[j0][i0]);
    double hi = s->table[j1][i0] + fa * (s->table[j1][i1] - s->table[j1][i0]);
    return lo + fr * (hi - lo);
}

static double smooth(double e0, double e1, double x) {
    double t = (x - e0) / (e1 - e0);
    t = t < 0.0 ? 0.0 : t > 1.0 ? 1.0 : t;
    return t * t * (3.0 - 2.0 * t);
}

static void mix3(double *c, const double *a, const double *b, double t) {
    for (int i = 0; i < 3; i++) c[i] = a[i] + (b[i] - a[i]) * t;
}

/* Eye geometry of one eyeball: frame, iris radius (the flat front of ICT's iris shell),
 * pupil radius, and two orthonormal directions across the gaze axis. */
typedef struct eye_geom {
    double c[3], a[3], u[3], w[3];
    double iris_r, pupil_r;
    const streaks *fibres;
} eye_geom;

/* Position relative to the eye: along the axis, distance from it, angle around it. */
static void eye_coords(const eye_geom *g, const float *p, double *along, double *rr, double *angle) {
    double d[3] = {p[0] - g->c[0], p[1] - g->c[1], p[2] - g->c[2]};
    *along = d[0] * g->a[0] + d[1] * g->a[1] + d[2] * g->a[2];
    double x = d[0] * g->u[0] + d[1] * g->u[1] + d[2] * g->u[2];
    double y = d[0] * g->w[0] + d[1] * g->w[1] + d[2] * g->w[2];
    *rr = sqrt(x * x + y * y);
    *angle = atan2(y, x);
}

static void iris_colour(const eye_geom *g, const float *p, double rgba[4]) {
    static const double pupil[3] = {0.02, 0.02, 0.025}, amber[3] = {0.62, 0.44, 0.22}, brown[3] = {0.36, 0.25, 0.15},
                        rim[3] = {0.10, 0.08, 0.07};
    double along, rr, angle;
    eye_coords(g, p, &along, &rr, &angle);
    double rho = rr / g->iris_r, rp = g->pupil_r / g->iris_r;
    rgba[3] = 1.0;
    if (along <= 0.0 || rho >= 1.06) {
        /* the inside of the eye: seen only through the pupil's opening (ICT's pupil is a
         * funnel into the eyeball), dark as a pupil */
        memcpy(rgba, pupil, sizeof pupil);
        return;
    }
    double f = streak(g->fibres, angle, rho), c[3];
    /* the collarette: lighter amber near the pupil, brown toward the rim */
    mix3(c, amber, brown, smooth(rp + 0.05, 0.75, rho));
    double light = 1.0 + 0.22 * f * smooth(rp, rp + 0.1, rho);
    /* crypts: darker lacunae in the middle band */
    double crypt = 0.5 + 0.5 * streak(g->fibres, 2.0 * angle + 1.0, 3.0 * rho);
    light *= 1.0 - 0.25 * smooth(0.75, 1.0, crypt) * smooth(0.4, 0.5, rho) * (1.0 - smooth(0.8, 0.9, rho));
    for (int i = 0; i < 3; i++) c[i] *= light;
    mix3(c, c, rim, smooth(0.80, 0.97, rho));          /* limbal ring */
    mix3(c, c, pupil, 1.0 - smooth(rp - 0.01, rp + 0.03, rho)); /* pupil, a soft edge */
    for (int i = 0; i < 3; i++) rgba[i] = c[i] < 0.0 ? 0.0 : c[i] > 1.0 ? 1.0 : c[i];
}

static void sclera_colour(const eye_geom *g, const float *p, double rgba[4]) {
    static const double white[3] = {0.93, 0.905, 0.88}, pink[3] = {0.86, 0.68, 0.64}, limbus[3] = {0.70, 0.72, 0.75},
                        vein[3] = {0.70, 0.26, 0.22};
    double along, rr, angle;
    eye_coords(g, p, &along, &rr, &angle);
    double rho = rr / g->iris_r, c[3];
    /* toward the back (where lids and corners cover it) warmer and pinker */
    double back = 1.0 - smooth(-0.2 * g->iris_r, 0.9 * g->iris_r, along);
    mix3(c, white, pink, 0.7 * back);
    if (along > 0.0) mix3(c, c, limbus, 0.5 * (1.0 - smooth(1.0, 1.35, rho))); /* the shadowed ring by the cornea */
    /* a few thin veins reaching in from the corners */
    double v = streak(g->fibres, 0.5 * angle + 2.0, 0.0);
    double vein_w = smooth(0.93, 1.0, 0.5 + 0.5 * v) * smooth(1.5, 2.6, rho) * (0.3 + 0.7 * back);
    mix3(c, c, vein, 0.55 * vein_w);
    memcpy(rgba, c, sizeof c);
    /* the cornea: see-through over the iris */
    rgba[3] = along > 0.0 && rho < 1.0 ? 0.0 : 1.0;
}

static frig_status eye_geometry(const frig_rig *rig, int material, int eye, eye_geom *g) {
    static const char *const regions[2] = {"eyeball_left", "eyeball_right"};
    const fr_topology *t = &rig->topo;
    if (!fr_eye_frame(t, rig->neutral, regions[eye], g->c, g->a)) return FRIG_ERR_STATE;
    /* u, w: across the axis */
    double ref[3] = {0.0, 1.0, 0.0};
    double dot = ref[0] * g->a[0] + ref[1] * g->a[1] + ref[2] * g->a[2], len = 0.0;
    for (int i = 0; i < 3; i++) g->w[i] = ref[i] - dot * g->a[i], len += g->w[i] * g->w[i];
    for (int i = 0; i < 3; i++) g->w[i] /= sqrt(len);
    g->u[0] = g->w[1] * g->a[2] - g->w[2] * g->a[1];
    g->u[1] = g->w[2] * g->a[0] - g->w[0] * g->a[2];
    g->u[2] = g->w[0] * g->a[1] - g->w[1] * g->a[0];
    /* the iris: the flat front of the iris shell (vertices at least 92% as far forward as its
     * foremost), its radius 2% past their widest */
    int iris = -1;
    for (int m = 0; m < t->material_count; m++) {
        int e;
        if (fr_material_kind_of(t->material_names[m], &e) == FR_MAT_IRIS && e == eye) iris = m;
    }
    if (iris < 0) iris = material;
    double max_along = -INFINITY, max_r = 0.0;
    for (int pass = 0; pass < 2; pass++)
        for (int i = 0; i < t->triangle_count; i++) {
            if (t->triangle_materials[i] != iris) continue;
            for (int c = 0; c < 3; c++) {
                double along, rr, angle;
                eye_coords(g, rig->neutral + 3 * (size_t)t->triangles[3 * i + c], &along, &rr, &angle);
                if (pass == 0) max_along = fmax(max_along, along);
                else if (along >= 0.92 * max_along) max_r = fmax(max_r, rr);
            }
        }
    if (!(max_r > 0.0)) return FRIG_ERR_STATE;
    g->iris_r = 1.02 * max_r;
    g->pupil_r = 0.3 * g->iris_r;
    g->fibres = eye_fibres(eye);
    return FRIG_OK;
}

static int32_t find_root(int32_t *parent, int32_t v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
}

/* The connected pieces of a material's triangles: parent[] (union-find over nv vertices) and
 * the list of the material's vertices. */
typedef struct pieces {
    int32_t *parent, *list, *edges;
    int nm, ne;
} pieces;

static void pieces_free(pieces *p) {
    free(p->parent), free(p->list), free(p->edges);
    memset(p, 0, sizeof *p);
}

static frig_status pieces_make(frig_ctx *ctx, const fr_topology *t, int material, pieces *p, float *out) {
    int nv = t->vertex_count, ne = 0;
    memset(p, 0, sizeof *p);
    for (int i = 0; i < t->triangle_count; i++) ne += 3 * (t->triangle_materials[i] == material);
    p->parent = malloc(sizeof(int32_t) * (size_t)nv);
    p->edges = malloc(sizeof(int32_t) * 2 * (size_t)(ne + 1));
    p->list = malloc(sizeof(int32_t) * (size_t)(ne + 1));
    if (!p->parent || !p->edges || !p->list) {
        pieces_free(p);
        return fr_nomem(ctx, "an overlay's alpha");
    }
    for (int v = 0; v < nv; v++) p->parent[v] = v, out[v] = -1.0f;
    for (int i = 0; i < t->triangle_count; i++) {
        if (t->triangle_materials[i] != material) continue;
        for (int c = 0; c < 3; c++) {
            int32_t a = t->triangles[3 * i + c], b = t->triangles[3 * i + (c + 1) % 3];
            p->edges[2 * p->ne] = a < b ? a : b, p->edges[2 * p->ne + 1] = a < b ? b : a, p->ne++;
            int32_t ra = find_root(p->parent, a), rb = find_root(p->parent, b);
            if (ra != rb) p->parent[ra > rb ? ra : rb] = ra < rb ? ra : rb;
            if (out[a] < 0.0f) out[a] = 0.0f, p->list[p->nm++] = a;
        }
    }
    return FRIG_OK;
}

/* Divide each value by the largest in its piece. */
static frig_status per_piece_normalize(frig_ctx *ctx, const fr_topology *t, pieces *p, float *out) {
    float *top = calloc((size_t)t->vertex_count, sizeof *top);
    if (!top) return fr_nomem(ctx, "an overlay's alpha");
    for (int i = 0; i < p->nm; i++) {
        int32_t r = find_root(p->parent, p->list[i]);
        if (out[p->list[i]] > top[r]) top[r] = out[p->list[i]];
    }
    for (int i = 0; i < p->nm; i++) {
        float m = top[find_root(p->parent, p->list[i])];
        out[p->list[i]] = m > 0.0f ? out[p->list[i]] / m : 0.0f;
    }
    free(top);
    return FRIG_OK;
}

static double dist2(const float *a, const float *b) {
    double s = 0.0;
    for (int k = 0; k < 3; k++) {
        double d = (double)a[k] - b[k];
        s += d * d;
    }
    return s;
}

/* Per vertex of the material's triangles (-1 elsewhere), divided by the largest in its piece:
 * the distance to the material's own border (edges used by one triangle; ICT's quads split in
 * two share their diagonal, used twice), or with 'to_skin' the distance to the nearest vertex
 * of material 'skin' (a lash card's root is where it meets the lid). */
static frig_status piece_distance(frig_ctx *ctx, const fr_topology *t, const float *xyz, int material, int skin,
                                  float *out) {
    pieces p;
    frig_status s = pieces_make(ctx, t, material, &p, out);
    if (s) return s;
    uint8_t *target = calloc((size_t)t->vertex_count, 1);
    if (!target) {
        pieces_free(&p);
        return fr_nomem(ctx, "an overlay's alpha");
    }
    int32_t *near = NULL;
    int nn = 0;
    if (skin >= 0) {
        /* the skin within 1 cm of the material's bounding box */
        double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
        for (int i = 0; i < p.nm; i++)
            for (int k = 0; k < 3; k++) {
                double x = xyz[3 * (size_t)p.list[i] + k];
                lo[k] = fmin(lo[k], x - 0.01), hi[k] = fmax(hi[k], x + 0.01);
            }
        for (int i = 0; i < t->triangle_count; i++)
            if (t->triangle_materials[i] == skin)
                for (int c = 0; c < 3; c++) {
                    int32_t v = t->triangles[3 * i + c];
                    const float *q = xyz + 3 * (size_t)v;
                    if (q[0] >= lo[0] && q[0] <= hi[0] && q[1] >= lo[1] && q[1] <= hi[1] && q[2] >= lo[2] && q[2] <= hi[2])
                        target[v] = 1;
                }
        near = malloc(sizeof(int32_t) * (size_t)t->vertex_count);
        if (!near) {
            free(target);
            pieces_free(&p);
            return fr_nomem(ctx, "an overlay's alpha");
        }
        for (int v = 0; v < t->vertex_count; v++)
            if (target[v]) near[nn++] = v;
    } else {
        for (int i = 0; i < p.ne; i++) {
            int once = 1;
            for (int j = 0; j < p.ne && once; j++)
                if (j != i && p.edges[2 * j] == p.edges[2 * i] && p.edges[2 * j + 1] == p.edges[2 * i + 1]) once = 0;
            if (once) target[p.edges[2 * i]] = target[p.edges[2 * i + 1]] = 1;
        }
    }
    for (int i = 0; i < p.nm; i++) {
        int32_t v = p.list[i], root = find_root(p.parent, v);
        double best = INFINITY;
        if (skin >= 0) {
            for (int j = 0; j < nn; j++) best = fmin(best, dist2(xyz + 3 * (size_t)near[j], xyz + 3 * (size_t)v));
        } else {
            for (int j = 0; j < p.nm; j++) {
                int32_t u = p.list[j];
                if (target[u] && find_root(p.parent, u) == root)
                    best = fmin(best, dist2(xyz + 3 * (size_t)u, xyz + 3 * (size_t)v));
            }
        }
        out[v] = isfinite(best) ? (float)sqrt(best) : 0.0f;
    }
    s = per_piece_normalize(ctx, t, &p, out);
    free(near);
    free(target);
    pieces_free(&p);
    return s;
}

/* Lash strands across a card: columns of texels x (along the lid), running from the root
 * (t = 0) toward the tip, each with its own length, offset and curl, thinner toward the tip. */
static void lash_colour(double x, double t, int lower, int size, double rgba[4]) {
    /* lower lashes: shorter, sparser, lighter */
    double scale = size / 512.0, spacing = (lower ? 7.0 : 4.5) * scale, keep = 1.0, reach = lower ? 0.5 : 1.0;
    rgba[0] = 0.045, rgba[1] = 0.032, rgba[2] = 0.026;
    long k0 = (long)floor(x / spacing);
    for (long k = k0 - 2; k <= k0 + 2; k++) {
        fr_rng rng;
        fr_rng_seed(&rng, 0x1a5e5ull * 31u + (uint64_t)(k + 100000));
        double jitter = (fr_rng_uniform(&rng) - 0.5) * 0.7 * spacing;
        double len = reach * (0.55 + 0.45 * fr_rng_uniform(&rng));
        double curl = (fr_rng_uniform(&rng) - 0.5) * 3.0 * scale;
        if (t > len) continue;
        double u = t / len, centre = (k + 0.5) * spacing + jitter + curl * 3.0 * u * u;
        double half = fmax(0.25, 0.9 - 0.6 * u) * scale;
        double cover = half + 0.5 - fabs(x - centre);
        cover = cover < 0.0 ? 0.0 : cover > 1.0 ? 1.0 : cover;
        keep *= 1.0 - (lower ? 0.7 : 0.95) * cover;
    }
    rgba[3] = 1.0 - keep;
    if (!lower && t < 0.06) rgba[3] = fmax(rgba[3], 0.7 * (1.0 - t / 0.06)); /* the dense line at the lid */
}

static void occlusion_colour(double t, double rgba[4]) {
    rgba[0] = 0.09, rgba[1] = 0.06, rgba[2] = 0.05;
    rgba[3] = 0.6 * (1.0 - smooth(0.0, 0.55, t));
}

static void blend_colour(double t, double rgba[4]) {
    rgba[0] = 0.78, rgba[1] = 0.55, rgba[2] = 0.52;
    rgba[3] = 0.75 * smooth(0.0, 0.6, t);
}

static const char *texture_file(fr_material_kind kind, int eye) {
    switch (kind) {
    case FR_MAT_SCLERA: return eye ? "frig_sclera_right.png" : "frig_sclera_left.png";
    case FR_MAT_IRIS: return eye ? "frig_iris_right.png" : "frig_iris_left.png";
    case FR_MAT_EYE_OCCLUSION: return "frig_eye_occlusion.png";
    case FR_MAT_EYE_BLEND: return "frig_eye_blend.png";
    case FR_MAT_LASHES: return "frig_lashes.png";
    default: return "frig_texture.png";
    }
}

frig_status fr_eye_texture_paint(frig_ctx *ctx, const frig_rig *rig, int material, fr_material_kind kind, int eye,
                                 int size, fr_texture *out) {
    memset(out, 0, sizeof *out);
    const fr_topology *t = &rig->topo;
    int nv = t->vertex_count, per_vertex = kind == FR_MAT_SCLERA || kind == FR_MAT_IRIS;
    eye_geom g;
    if (per_vertex && eye_geometry(rig, material, eye, &g))
        return fr_error(ctx, FRIG_ERR_STATE, "the rig has no eyeball regions to paint material %s by",
                        t->material_names[material]);
    size_t n = (size_t)size * (size_t)size;
    int dim = per_vertex ? 3 : 2;
    /* overlays and lashes: (normalized distance, below its eye's centre) per vertex */
    float *attr = per_vertex ? NULL : malloc(sizeof(float) * 3 * (size_t)nv);
    float *baked = malloc(sizeof(float) * (size_t)dim * n);
    uint8_t *covered = malloc(n);
    out->pixels = malloc(4 * n);
    frig_status s = !baked || !covered || !out->pixels || (!per_vertex && !attr) ? fr_nomem(ctx, "an eye texture")
                                                                                  : FRIG_OK;
    int skin = -1;
    for (int m = 0; kind == FR_MAT_LASHES && m < t->material_count; m++)
        if (fr_material_kind_of(t->material_names[m], NULL) == FR_MAT_FACE) skin = m;
    if (!s && !per_vertex) s = piece_distance(ctx, t, rig->neutral, material, skin, attr + 2 * (size_t)nv);
    if (!s && !per_vertex) {
        double c[2][3], a[3];
        int have = fr_eye_frame(t, rig->neutral, "eyeball_left", c[0], a) &&
                   fr_eye_frame(t, rig->neutral, "eyeball_right", c[1], a);
        for (int v = 0; v < nv; v++) {
            const float *p = rig->neutral + 3 * (size_t)v;
            int e = have && dist2(p, (float[3]){(float)c[1][0], (float)c[1][1], (float)c[1][2]}) <
                                dist2(p, (float[3]){(float)c[0][0], (float)c[0][1], (float)c[0][2]});
            attr[2 * (size_t)v] = attr[2 * (size_t)nv + (size_t)v];
            attr[2 * (size_t)v + 1] = have && p[1] < c[e][1] ? 1.0f : 0.0f;
        }
    }
    if (!s) s = fr_texture_bake(ctx, t, material, per_vertex ? rig->neutral : attr, dim, size, baked, covered);
    int alpha = 0;
    for (size_t px = 0; !s && px < n; px++) {
        double rgba[4] = {0.5, 0.5, 0.5, 0.0};
        if (covered[px]) {
            float *b = baked + px * (size_t)dim;
            if (kind == FR_MAT_IRIS) iris_colour(&g, b, rgba);
            else if (kind == FR_MAT_SCLERA) sclera_colour(&g, b, rgba);
            else if (kind == FR_MAT_EYE_OCCLUSION) occlusion_colour(b[0], rgba);
            else if (kind == FR_MAT_LASHES) lash_colour((double)(px % (size_t)size), b[0], b[1] > 0.5f, size, rgba);
            else blend_colour(b[0], rgba);
        }
        for (int c = 0; c < 4; c++) out->pixels[4 * px + (size_t)c] = (uint8_t)floor(255.0 * rgba[c] + 0.5);
        alpha |= out->pixels[4 * px + 3] != 255;
    }
    if (!s) {
        out->width = out->height = size;
        out->channels = alpha ? 4 : 3;
        if (!alpha) /* opaque: keep RGB only (byte by byte, forward: each read lies at or after its write) */
            for (size_t px = 0; px < n; px++)
                for (int c = 0; c < 3; c++) out->pixels[3 * px + (size_t)c] = out->pixels[4 * px + (size_t)c];
        snprintf(out->file, sizeof out->file, "%s", texture_file(kind, eye));
        s = fr_png_encode_pixels(ctx, size, size, out->channels, (size_t)size * (size_t)out->channels, out->pixels,
                                 &out->png, &out->png_size);
    }
    free(attr);
    free(baked);
    free(covered);
    if (s) fr_texture_free(out);
    return s;
}
