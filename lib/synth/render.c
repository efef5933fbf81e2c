/* Rendering a synthetic photo with libfrig's own z-buffer rasterizer: the image-formation
 * model the shape-from-shading stage inverts (paper section 5.1, eq. 5.1-5.2: Lambertian
 * albedo times second-order SH irradiance of the normal) and what it must survive (section
 * 5.1.3: hard cast shadows of the key light, specular highlights), in linear light at twice the
 * size, box-filtered down, sensor noise added, gamma-encoded to sRGB. The photo-sized render
 * gives the depth map and landmark truth; the big one the per-pixel class map. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "image/image.h"
#include "rig/rig.h"
#include "synth/synth.h"

#define SUPERSAMPLE 2

void fr_synth_eye_albedo(const frig_synth_subject *s, int e, const double rest[3], double rgb[3]) {
    const double *c = s->eye_centre[e], *a = s->eye_axis[e];
    double d[3] = {rest[0] - c[0], rest[1] - c[1], rest[2] - c[2]};
    double along = d[0] * a[0] + d[1] * a[1] + d[2] * a[2], r2 = 0.0;
    for (int i = 0; i < 3; i++) {
        double q = d[i] - along * a[i];
        r2 += q * q;
    }
    double r = sqrt(r2) / s->iris_radius, pupil = s->pupil_radius / s->iris_radius;
    memcpy(rgb, s->sclera_albedo, 3 * sizeof *rgb);
    if (along <= 0.0 || r >= 1.0) return;
    double rim = fr_smoothstep(0.75, 1.0, r), ray = 0.85 + 0.15 * cos(37.0 * atan2(d[1], d[0]));
    for (int i = 0; i < 3; i++) rgb[i] = s->iris_albedo[i] * ray * (1.0 - 0.6 * rim);
    if (r < pupil) rgb[0] = rgb[1] = rgb[2] = 0.01;
}

/* Camera for the supersampled render: pixel (x, y) of the photo covers samples 2x..2x+1. */
static fr_camera supersampled(const fr_camera *c) {
    fr_camera s = *c;
    s.f *= SUPERSAMPLE;
    s.cx = SUPERSAMPLE * c->cx + 0.5 * (SUPERSAMPLE - 1);
    s.cy = SUPERSAMPLE * c->cy + 0.5 * (SUPERSAMPLE - 1);
    return s;
}

static void interpolate(const float *attr, const int32_t *tr, const float *b, double out[3]) {
    for (int i = 0; i < 3; i++)
        out[i] = b[0] * attr[3 * (size_t)tr[0] + i] + b[1] * attr[3 * (size_t)tr[1] + i] + b[2] * attr[3 * (size_t)tr[2] + i];
}

#define SHADOW_MAP_SIDE 1024
#define EYE_KS 0.5          /* the cornea's highlight (a catchlight) */
#define EYE_SHININESS 400.0
#define SHADOW_MIN_SHARE 0.15   /* a sample counts as cast shadow when the shadow takes this share of its light */
#define HIGHLIGHT_MIN_SHARE 0.1 /* a sample counts as highlight when the specular part is this share of it */

static double luminance(const double c[3]) { return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]; }

/* The triangle corner with the largest weight. */
static int32_t main_corner(const int32_t *tr, const float *b) {
    return b[0] >= b[1] && b[0] >= b[2] ? tr[0] : b[1] >= b[2] ? tr[1] : tr[2];
}

typedef struct shading {
    const frig_synth_subject *s;
    const fr_synth_photo *p;
    const fr_camera *cam;
    const fr_raster *r;
    const float *xyz, *normals;
    const fr_shadow_map *shadow; /* NULL: no cast shadows */
} shading;

/* One covered sample: Lambert with SH irradiance, the key light's part removed where it is
 * shadowed, plus a Blinn-Phong highlight; the sample's FRIG_SYNTH_PIXEL_* bits. */
static uint8_t shade_sample(const shading *sh, int x, int y, float *out) {
    const frig_synth_subject *s = sh->s;
    const fr_synth_photo *p = sh->p;
    size_t px = (size_t)y * (size_t)sh->r->width + (size_t)x;
    int32_t t = sh->r->tri[px];
    const int32_t *tr = s->tris + 3 * (size_t)t;
    const float *b = sh->r->bary + 3 * px;
    double n[3], alb[3], Y[9], X[3];
    interpolate(sh->normals, tr, b, n);
    double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (!(len > 0.0)) return 0;
    /* seen from behind (lashes, the inside of the lips): light the side we see */
    const fr_camera *cam = sh->cam;
    double ray[3] = {(x - cam->cx) / cam->f, (y - cam->cy) / cam->f, 1.0};
    if (n[0] * ray[0] + n[1] * ray[1] + n[2] * ray[2] > 0.0) len = -len;
    for (int i = 0; i < 3; i++) n[i] /= len;
    int head = t < s->nt_head, v = main_corner(tr, b);
    if (s->eye_tri[t]) {
        double rest[3];
        interpolate(frig_rig_neutral(s->rig), tr, b, rest);
        fr_synth_eye_albedo(s, s->eye_tri[t] - 1, rest, alb);
    } else {
        interpolate(s->albedo, tr, b, alb);
    }
    interpolate(sh->xyz, tr, b, X);
    double vis = sh->shadow ? fr_synth_shadow_visibility(sh->shadow, X) : 1.0;
    fr_sh_basis(n, Y);
    double diffuse[3], direct[3], spec[3] = {0, 0, 0};
    for (int c = 0; c < 3; c++) {
        double e = 0.0, d = 0.0;
        for (int k = 0; k < 9; k++) e += p->sh[c][k] * Y[k], d += p->sh_direct[c][k] * Y[k];
        direct[c] = d > 0.0 ? d : 0.0;
        e -= (1.0 - vis) * direct[c];
        diffuse[c] = alb[c] * (e > 0.0 ? e : 0.0);
    }
    /* highlight: skin (less where hair covers it) and the corneas */
    int skin = head && v < s->nv && s->skin[v];
    double hair = head && v < s->nv ? s->hair[v] : 0.0;
    double ks = s->eye_tri[t] ? EYE_KS : skin ? p->spec_ks * (1.0 - hair) : 0.0;
    double shin = s->eye_tri[t] ? EYE_SHININESS : p->spec_shininess;
    const double *l = p->light_dir;
    double nl = n[0] * l[0] + n[1] * l[1] + n[2] * l[2];
    if (ks > 0.0 && vis > 0.0 && nl > 0.0) {
        double rl = sqrt(ray[0] * ray[0] + ray[1] * ray[1] + ray[2] * ray[2]);
        double h[3] = {l[0] - ray[0] / rl, l[1] - ray[1] / rl, l[2] - ray[2] / rl};
        double hl = sqrt(h[0] * h[0] + h[1] * h[1] + h[2] * h[2]);
        double nh = (n[0] * h[0] + n[1] * h[1] + n[2] * h[2]) / hl;
        double lobe = nh > 0.0 ? ks * vis * pow(nh, shin) : 0.0;
        for (int c = 0; c < 3; c++) spec[c] = lobe * p->direct_rgb[c];
    }
    for (int c = 0; c < 3; c++) out[c] = (float)(diffuse[c] + spec[c]);
    if (!head) return 0;
    uint8_t bits = FRIG_SYNTH_PIXEL_HEAD;
    if (skin && hair < 0.5) bits |= FRIG_SYNTH_PIXEL_SKIN;
    if (hair >= 0.5) bits |= FRIG_SYNTH_PIXEL_HAIR;
    double total[3];
    for (int c = 0; c < 3; c++) total[c] = diffuse[c] + spec[c];
    double irr[3];
    for (int c = 0; c < 3; c++) {
        double e = 0.0;
        for (int k = 0; k < 9; k++) e += p->sh[c][k] * Y[k];
        irr[c] = e > 0.0 ? e : 0.0;
    }
    double lost = (1.0 - vis) * luminance(direct);
    if (lost > 0.0 && lost >= SHADOW_MIN_SHARE * luminance(irr)) bits |= FRIG_SYNTH_PIXEL_SHADOW;
    if (luminance(spec) >= HIGHLIGHT_MIN_SHARE * luminance(total) && luminance(spec) > 0.0)
        bits |= FRIG_SYNTH_PIXEL_HIGHLIGHT;
    return bits;
}

static void shade(const shading *sh, float *rgb, uint8_t *bits) {
    for (int y = 0; y < sh->r->height; y++)
        for (int x = 0; x < sh->r->width; x++) {
            size_t px = (size_t)y * (size_t)sh->r->width + (size_t)x;
            if (sh->r->tri[px] >= 0) bits[px] = shade_sample(sh, x, y, rgb + 3 * px);
        }
}

/* A photo pixel has a bit when at least half its samples have it. */
static void pixel_classes(const fr_synth_photo *p, const uint8_t *samples, uint8_t *mask) {
    int W2 = SUPERSAMPLE * p->width;
    for (int y = 0; y < p->height; y++)
        for (int x = 0; x < p->width; x++) {
            int count[8] = {0};
            for (int j = 0; j < SUPERSAMPLE; j++)
                for (int i = 0; i < SUPERSAMPLE; i++) {
                    uint8_t b = samples[(size_t)(SUPERSAMPLE * y + j) * (size_t)W2 + (size_t)(SUPERSAMPLE * x + i)];
                    for (int k = 0; k < 8; k++) count[k] += (b >> k) & 1;
                }
            uint8_t m = 0;
            for (int k = 0; k < 8; k++)
                if (2 * count[k] >= SUPERSAMPLE * SUPERSAMPLE) m |= (uint8_t)(1u << k);
            mask[(size_t)y * (size_t)p->width + (size_t)x] = m;
        }
}

/* Box-filter the supersampled linear image, add sensor noise, encode to 8-bit sRGB. */
static void develop(const fr_synth_photo *p, const float *big, frig_image *img) {
    fr_rng rng;
    fr_rng_seed(&rng, p->noise_seed);
    int W = p->width, W2 = SUPERSAMPLE * W;
    double norm = 1.0 / (SUPERSAMPLE * SUPERSAMPLE);
    for (int y = 0; y < p->height; y++) {
        uint8_t *row = img->pixels + (size_t)y * img->stride;
        for (int x = 0; x < W; x++)
            for (int c = 0; c < 3; c++) {
                double sum = 0.0;
                for (int j = 0; j < SUPERSAMPLE; j++)
                    for (int i = 0; i < SUPERSAMPLE; i++)
                        sum += big[3 * ((size_t)(SUPERSAMPLE * y + j) * (size_t)W2 + (size_t)(SUPERSAMPLE * x + i)) + c];
                double v = 255.0 * fr_linear_to_srgb(sum * norm * p->gain) + p->noise_sigma * fr_rng_normal(&rng);
                v = floor(v + 0.5);
                row[3 * x + c] = (uint8_t)(v < 0.0 ? 0.0 : v > 255.0 ? 255.0 : v);
            }
    }
}

/* The head: landmark truth and depth from the photo-sized render, colour and the class map
 * from the big one (with the key light's shadow map when the photo has cast shadows). */
static frig_status render_head(frig_ctx *ctx, const frig_synth_subject *s, fr_synth_photo *p, frig_synth_truth *t,
                               float *big) {
    float *xyz = NULL, *normals = NULL;
    uint8_t *bits = NULL;
    fr_raster *r1 = NULL, *r2 = NULL;
    fr_shadow_map map = {0};
    fr_camera cam2 = supersampled(&p->cam);
    frig_status st = fr_synth_posed_vertices(ctx, s, p, &xyz);
    if (!st) st = fr_raster_create(ctx, p->width, p->height, &r1);
    if (!st) st = fr_raster_render(ctx, r1, &p->cam, xyz, s->nv_render, s->tris, s->nt, NULL);
    if (!st) st = fr_synth_landmarks_from_render(ctx, s, p, r1, xyz, &t->lm);
    if (!st) {
        size_t n = (size_t)p->width * (size_t)p->height;
        for (size_t i = 0; i < n; i++) t->depth[i] = r1->tri[i] >= 0 && r1->tri[i] < s->nt_head ? r1->depth[i] : 0.0f;
        fr_raster_free(r1);
        r1 = NULL;
        st = fr_raster_create(ctx, SUPERSAMPLE * p->width, SUPERSAMPLE * p->height, &r2);
    }
    if (!st) st = fr_raster_render(ctx, r2, &cam2, xyz, s->nv_render, s->tris, s->nt, NULL);
    if (!st && p->shadows) st = fr_synth_shadow_map(ctx, xyz, s->nv_render, s->tris, s->nt, p->light_dir, SHADOW_MAP_SIDE, &map);
    if (!st) {
        normals = malloc(sizeof *normals * 3 * (size_t)s->nv_render);
        bits = calloc((size_t)r2->width * (size_t)r2->height, 1);
        if (!normals || !bits) st = fr_nomem(ctx, "the photo's normals");
    }
    if (!st) {
        fr_mesh_vertex_normals(xyz, s->nv_render, s->tris, s->nt, normals);
        shading sh = {s, p, &cam2, r2, xyz, normals, p->shadows ? &map : NULL};
        shade(&sh, big, bits);
        pixel_classes(p, bits, t->mask);
    }
    fr_synth_shadow_map_free(&map);
    fr_raster_free(r1), fr_raster_free(r2);
    free(xyz), free(normals), free(bits);
    return st;
}

/* Pixels under the occluder or the sunglasses. */
static void mark_occluded(const fr_synth_photo *p, uint8_t *mask) {
    if (p->failure != FRIG_SYNTH_FAILURE_OCCLUDER && p->failure != FRIG_SYNTH_FAILURE_SUNGLASSES) return;
    for (int y = 0; y < p->height; y++)
        for (int x = 0; x < p->width; x++)
            if (fr_synth_occluded(p, x, y)) mask[(size_t)y * (size_t)p->width + (size_t)x] |= FRIG_SYNTH_PIXEL_OCCLUDED;
}

frig_status fr_synth_render_photo(frig_ctx *ctx, const frig_synth_subject *s, const fr_synth_photo *photo,
                                  frig_image **image, frig_synth_truth **truth) {
    if (image) *image = NULL;
    if (truth) *truth = NULL;
    fr_synth_photo p = *photo;
    int W2 = SUPERSAMPLE * p.width, H2 = SUPERSAMPLE * p.height;
    frig_synth_truth *t = NULL;
    frig_status st = fr_synth_truth_new(ctx, s, &p, &t);
    if (st) return st;
    float *big = malloc(sizeof *big * 3 * (size_t)W2 * (size_t)H2);
    frig_image *img = fr_image_new(p.width, p.height, 3);
    if (!big || !img) st = fr_nomem(ctx, "the synthetic photo");
    if (!st) {
        fr_synth_background(&p, W2, H2, SUPERSAMPLE, big);
        if (p.failure == FRIG_SYNTH_FAILURE_NO_FACE) fr_synth_landmarks_none(&t->lm);
        else st = render_head(ctx, s, &p, t, big);
    }
    if (!st) {
        fr_synth_draw_occluder(&p, W2, H2, SUPERSAMPLE, big);
        fr_synth_draw_sunglasses(&p, W2, H2, SUPERSAMPLE, big);
        mark_occluded(&p, t->mask);
        develop(&p, big, img);
        t->photo = p;
        t->has_face = p.failure != FRIG_SYNTH_FAILURE_NO_FACE;
    }
    free(big);
    if (st || !image) frig_image_free(img);
    else *image = img;
    if (st || !truth) frig_synth_truth_free(t);
    else *truth = t;
    return st;
}
