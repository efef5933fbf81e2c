/* The sfs stage (paper section 5.1; lib/sfs, lib/skin, docs/sfs.md): the SH basis gradient,
 * the skin detector (a shirt below the face and a patch on it are not skin), SLIC segments,
 * the lighting fit, the depth solver on a problem its own model made, and the whole stage on a
 * small synthetic subject: cloud error against the true surface below floors measured on
 * synthetic subjects, an over-exposed photo sfs_failed, results in report.json read back,
 * the shared solve it took recorded (and each reason read back),
 * the same clouds whatever the thread count, the albedo texture drawn later from the kept
 * computation (the outer loop's) the same bytes; the shared shape's joint pose (with the photos'
 * own gradients) brings fits turned by 4 degrees toward the truth, and the coarse-to-fine pose
 * registration brings photos turned by 9 degrees back within a few degrees; each photo's expression
 * refined against its pixels (sfs_expression.c) takes fits with a wrong jaw, smile or brow nearer the
 * truth's expression; the model's identity modes solved with the shared shape take a rig started at
 * the mean face toward the subject's identity. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <frig/frig.h>

#include "core/rng.h"
#include "eval/albedo_error.h"
#include "eval/cloud_error.h"
#include "eval/shape_error.h"
#include "linalg/linalg.h"
#include "model_fixture.h"
#include "raster/rotation.h"
#include "raster/sh_lighting.h"
#include "rig/rig.h"
#include "sfs/sfs.h"
#include "sfs/sfs_albedo.h"
#include "sfs/sfs_depth.h"
#include "sfs/sfs_highlights.h"
#include "sfs/sfs_run.h"
#include "skin/skin.h"
#include "skin/slic.h"
#include "testing.h"
#include "workspace/photoset.h"

static frig_ctx *ctx;

/* The narrow face's vertex count (the rig's "narrow_face" range, from vertex 0: ICT-FaceKit's 0..6705);
 * the whole rig when it names none. */
static int narrow_face_count(const frig_rig *rig) {
    int first = 0, count = 0;
    return fr_topology_region(&rig->topo, "narrow_face", &first, &count) && first == 0 ? count : rig->topo.vertex_count;
}

static void test_sh_gradient(void) {
    double n[3] = {0.3, -0.5, -0.81}, y[9], dy[27], h = 1e-6;
    fr_sh_basis_gradient(n, y, dy);
    double worst = 0;
    for (int i = 0; i < 3; i++) {
        double m[3] = {n[0], n[1], n[2]}, y2[9];
        m[i] += h;
        fr_sh_basis(m, y2);
        for (int k = 0; k < 9; k++) worst = fmax(worst, fabs((y2[k] - y[k]) / h - dy[3 * k + i]));
    }
    printf("SH gradient: largest difference to finite differences %.2e\n", worst);
    CHECK(worst < 1e-5);
}

/* A 120 x 120 image: a skin-coloured face region (with noise and shading), a red shirt in its
 * lower part (outside the core where the colour model is learnt) and a blue patch on it. */
static void test_skin(void) {
    int w = 120, h = 120;
    uint8_t *rgb = malloc(3 * (size_t)w * h), *region = calloc((size_t)w * h, 1), *core = calloc((size_t)w * h, 1);
    uint8_t *skin = malloc((size_t)w * h);
    fr_rng rng;
    fr_rng_seed(&rng, 5);
    int shirt = 0, patch = 0, face = 0;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            size_t i = (size_t)y * w + x;
            double dx = (x - 60) / 45.0, dy = (y - 55) / 55.0, shade = 0.75 + 0.25 * (1 - dx);
            int in = dx * dx + dy * dy < 1;
            region[i] = (uint8_t)in;
            core[i] = in && y < 85;
            uint8_t c[3] = {(uint8_t)(205 * shade), (uint8_t)(165 * shade), (uint8_t)(140 * shade)};
            if (in && y >= 90) c[0] = 200, c[1] = 30, c[2] = 40, shirt++;
            else if (in && x > 70 && x < 85 && y > 35 && y < 50) c[0] = 40, c[1] = 60, c[2] = 200, patch++;
            else if (in) face++;
            for (int k = 0; k < 3; k++) {
                double v = c[k] + 2.0 * fr_rng_normal(&rng);
                rgb[3 * i + k] = (uint8_t)(v < 0 ? 0 : v > 255 ? 255 : v);
            }
        }
    fr_skin_stats st;
    CHECK(fr_skin_detect(ctx, rgb, w, h, 3 * (size_t)w, region, core, NULL, skin, &st) == FRIG_OK);
    int shirt_skin = 0, patch_skin = 0, face_skin = 0;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            size_t i = (size_t)y * w + x;
            if (!region[i]) continue;
            if (y >= 90) shirt_skin += skin[i];
            else if (x > 70 && x < 85 && y > 35 && y < 50) patch_skin += skin[i];
            else face_skin += skin[i];
        }
    printf("skin: face %d/%d, shirt %d/%d, patch %d/%d pixels called skin; %d segments, median luma %.0f\n", face_skin,
           face, shirt_skin, shirt, patch_skin, patch, st.segments, st.median_luma);
    CHECK(face_skin > 0.9 * face);
    CHECK(shirt_skin < 0.02 * shirt);
    CHECK(patch_skin < 0.02 * patch);
    free(rgb), free(region), free(core), free(skin);
}

/* Two colours side by side: no superpixel takes both. */
static void test_slic(void) {
    int w = 64, h = 48, count = 0;
    float *lab = malloc(sizeof(float) * 3 * (size_t)w * h);
    int32_t *labels = malloc(sizeof(int32_t) * (size_t)w * h);
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            uint8_t c[3] = {x < 29 ? 200 : 30, x < 29 ? 60 : 90, x < 29 ? 40 : 210};
            fr_srgb8_to_lab(c, lab + 3 * ((size_t)y * w + x));
        }
    CHECK(fr_slic(ctx, lab, w, h, 8, 10.0, 10, labels, &count) == FRIG_OK);
    int mixed = 0;
    int32_t *side = malloc(sizeof(int32_t) * (size_t)(count + 1));
    for (int k = 0; k <= count; k++) side[k] = -1;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            int l = labels[y * w + x], s = x < 29;
            CHECK(l >= 0 && l < count);
            if (side[l] < 0) side[l] = s;
            else if (side[l] != s) mixed++;
        }
    printf("slic: %d segments on 64 x 48, %d pixels in a segment of the other colour\n", count, mixed);
    CHECK(mixed == 0);
    CHECK(count >= 30 && count <= 60);
    free(lab), free(labels), free(side);
}

/* The lights' concentration on the face (fr_sfs_light_concentration): one light in camera axes on a
 * head that does not turn gives 1, whatever the light's strength and colour; heads turned by +-a
 * about the vertical axis under a frontal light give cos(a)^2 (the mean of d d^T is
 * diag(sin^2 a, 0, cos^2 a)); a light that turns with the head gives 1 again, and so does half of
 * those lights flipped to the opposite side (one axis); lights along the three axes give 1/3;
 * views not ok, or unlit, do not count; fewer than two give 0. */
static double concentration(const fr_sfs_view *v, const uint8_t *ok, int n) {
    double c = -1;
    CHECK(fr_sfs_light_concentration(ctx, v, ok, n, &c) == FRIG_OK);
    return c;
}

static void test_light_concentration(void) {
    enum { N = 6 };
    fr_sfs_view v[N];
    uint8_t ok[N];
    memset(v, 0, sizeof v);
    const double front[3] = {0, 0, -1}; /* toward the camera */
    for (int k = 0; k < N; k++) {
        fr_rotation_from_euler(0, 0, 0, v[k].R);
        for (int c = 0; c < 3; c++) fr_sh_irradiance_coeffs(front, 1.0 + 0.3 * k + 0.1 * c, 0.4, v[k].sh[c]);
        ok[k] = 1;
    }
    CHECK(fabs(concentration(v, ok, N) - 1.0) < 1e-12);
    const double a = 0.5; /* radians */
    for (int k = 0; k < N; k++) fr_rotation_from_euler(k % 2 ? a : -a, 0, 0, v[k].R);
    double turned = concentration(v, ok, N);
    for (int k = 0; k < N; k++) { /* the light turned with each head: one direction on the face */
        double d[3];
        for (int i = 0; i < 3; i++) d[i] = v[k].R[3 * i + 2] * -1.0; /* R (0, 0, -1) */
        for (int c = 0; c < 3; c++) fr_sh_irradiance_coeffs(d, 1.0, 0.4, v[k].sh[c]);
    }
    double following = concentration(v, ok, N);
    for (int k = 0; k < N; k += 2) /* the opposite light on every other view */
        for (int c = 0; c < 3; c++)
            for (int i = 1; i < 4; i++) v[k].sh[c][i] = -v[k].sh[c][i];
    double flipped = concentration(v, ok, N);
    for (int k = 0; k < N; k++) { /* head still, lights along x, y, z in turn */
        double d[3] = {k % 3 == 0, k % 3 == 1, k % 3 == 2};
        fr_rotation_from_euler(0, 0, 0, v[k].R);
        for (int c = 0; c < 3; c++) fr_sh_irradiance_coeffs(d, 1.0, 0.4, v[k].sh[c]);
    }
    double spread = concentration(v, ok, N);
    /* turned heads under lights from six directions: against LAPACK's eigenvalues of the same mean */
    double T[9] = {0}, w[3];
    for (int k = 0; k < N; k++) {
        double d[3] = {0.3 * k - 0.7, 1.0 - 0.2 * k, -1.5 + 0.1 * k * k}, l = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        fr_rotation_from_euler(0.2 * k - 0.5, 0.1 * k, 0.05 * k, v[k].R);
        for (int c = 0; c < 3; c++) fr_sh_irradiance_coeffs(d, 1.0 + c, 0.4, v[k].sh[c]);
        double h[3];
        for (int i = 0; i < 3; i++) h[i] = (v[k].R[i] * d[0] + v[k].R[3 + i] * d[1] + v[k].R[6 + i] * d[2]) / l;
        for (int i = 0; i < 9; i++) T[i] += h[i / 3] * h[i % 3] / N;
    }
    double general = concentration(v, ok, N);
    CHECK(fr_sym_eig(ctx, 3, T, 3, w) == FRIG_OK);
    printf("light concentration, six lights on turned heads: %.12f, LAPACK %.12f\n", general, w[2]);
    CHECK(fabs(general - w[2]) < 1e-9);
    memset(v[0].sh, 0, sizeof v[0].sh); /* unlit */
    ok[1] = 0;
    for (int k = 2; k < N; k++) ok[k] = 0;
    double one = concentration(v, ok, N);
    printf("light concentration: turned +-%.2f rad %.6f (cos^2 %.6f), the light turning with the head %.6f, half of "
           "them flipped %.6f, three axes %.6f, one lit view %.1f\n", a, turned, cos(a) * cos(a), following, flipped,
           spread, one);
    CHECK(fabs(turned - cos(a) * cos(a)) < 1e-9);
    CHECK(fabs(following - 1.0) < 1e-9);
    CHECK(fabs(flipped - 1.0) < 1e-9);
    CHECK(fabs(spread - 1.0 / 3) < 1e-9);
    CHECK(one == 0.0);
}

/* The texture's shading (fr_sfs_texture_shading): where the channels' lighting agrees in colour
 * within 10% it is the lighting's own; where one channel's SH extrapolates apart at a grazing normal
 * (the green's quadratic terms here) each channel's share is held within 10% of the light's colour
 * facing the camera, as shares of the lighting's own level there (the channels' mean). */
static void test_texture_shading(void) {
    const double d[3] = {0.3, -0.4, -0.87};
    const float front[3] = {0, 0, -1}, side[3] = {-0.85f, 0.40f, -0.34f};
    double sh[3][FR_SH_COUNT], S[3], T[3], F[3];
    const double tint_direct[3] = {1.05, 1.0, 0.95}, tint_ambient[3] = {0.95, 1.0, 1.05};
    for (int c = 0; c < 3; c++) fr_sh_irradiance_coeffs(d, 0.6 * tint_direct[c], 0.4 * tint_ambient[c], sh[c]);
    double worst_same = 0;
    const float *normals[2] = {front, side};
    for (int k = 0; k < 2; k++) {
        fr_sfs_shading(sh, normals[k], S);
        fr_sfs_texture_shading(sh, normals[k], T);
        for (int c = 0; c < 3; c++) worst_same = fmax(worst_same, fabs(T[c] - S[c]));
    }
    printf("texture shading, a light tinted 5%%: largest change %.2e\n", worst_same);
    CHECK(worst_same < 1e-12);
    sh[1][8] -= 0.8 * sh[1][0]; /* x^2 - y^2: nothing at the frontal normal */
    fr_sfs_shading(sh, front, F);
    fr_sfs_shading(sh, side, S);
    fr_sfs_texture_shading(sh, side, T);
    double fl = (F[0] + F[1] + F[2]) / 3, sl = (S[0] + S[1] + S[2]) / 3, tl = (T[0] + T[1] + T[2]) / 3;
    double own_worst = 0, kept_worst = 0;
    for (int c = 0; c < 3; c++) {
        double front_share = F[c] / fl;
        own_worst = fmax(own_worst, fabs(S[c] / sl / front_share - 1));
        kept_worst = fmax(kept_worst, fabs(T[c] / sl / front_share - 1));
    }
    printf("texture shading, green apart at a grazing normal: share off the frontal light's %.3f -> %.3f, level %.4f -> %.4f\n",
           own_worst, kept_worst, sl, tl);
    CHECK(own_worst > 0.3);
    CHECK(kept_worst < 0.1 + 1e-9);
    CHECK(fabs(tl - sl) < 0.1 * sl);
}

/* Highlights taken out of skin pixels (sfs_highlights.c): a 64 x 64 patch of skin of one chroma
 * (linear shares 0.55 : 0.30 : 0.15) with its tone blotched by 3% and its shading a ramp, a disc of
 * white highlight on it (a lobe of up to 30% of the pixel), a redder band (lips); the highlight must go,
 * the rest stay. The same skin made grey (a black-and-white photo) must stay as it is, and so must a
 * highlight in a warm lamp's colour (not white: skin plus white does not explain it). */
static void highlight_patch(fr_sfs_view *v, int grey, int orange, float *diffuse, uint8_t *lobe) {
    fr_rng rng;
    fr_rng_seed(&rng, 7);
    const double skin[3] = {0.55, 0.30, 0.15}, lips[3] = {0.70, 0.22, 0.08};
    const double white[3] = {1.0 / 3, 1.0 / 3, 1.0 / 3}, lamp[3] = {0.55, 0.33, 0.12}; /* a warm lamp's highlight */
    for (int y = 0; y < v->h; y++)
        for (int x = 0; x < v->w; x++) {
            size_t i = (size_t)y * v->w + x;
            double shade = 0.3 + 0.6 * x / (v->w - 1.0), tone = 1 + 0.03 * (2 * fr_rng_uniform(&rng) - 1);
            const double *ch = y >= 52 ? lips : skin;
            double r2 = (x - 20.0) * (x - 20.0) + (y - 24.0) * (y - 24.0), spec = 0.3 * shade * exp(-r2 / 18.0);
            lobe[i] = spec > 0.01;
            for (int c = 0; c < 3; c++) {
                double body = shade * tone * (grey ? 1.0 / 3 : ch[c]) * (1 + 0.01 * (2 * fr_rng_uniform(&rng) - 1));
                diffuse[3 * i + c] = (float)body;
                v->I[3 * i + c] = (float)(body + spec * (orange ? lamp[c] : white[c]));
            }
            v->skin[i] = 1;
        }
}

static void test_highlights(void) {
    fr_sfs_view v;
    memset(&v, 0, sizeof v);
    v.w = v.h = 64;
    size_t n = 64 * 64;
    v.I = malloc(sizeof(float) * 3 * n), v.skin = malloc(n);
    float *diffuse = malloc(sizeof(float) * 3 * n);
    uint8_t *lobe = malloc(n);
    highlight_patch(&v, 0, 0, diffuse, lobe);
    double d[3], before = 0, after = 0, off = 0;
    CHECK(fr_sfs_skin_chroma(&v, d) == 1);
    CHECK_NEAR(d[0] / (d[0] + d[1] + d[2]), 0.55, 0.01);
    int changed = -1, in_lobe = 0, changed_outside = 0;
    float *raw = malloc(sizeof(float) * 3 * n);
    memcpy(raw, v.I, sizeof(float) * 3 * n);
    CHECK(fr_sfs_take_out_highlights(ctx, &v, 2.0, &changed) == FRIG_OK);
    for (size_t i = 0; i < n; i++) {
        double eb = 0, ea = 0, moved = 0;
        for (int c = 0; c < 3; c++) {
            eb += fabs(raw[3 * i + c] - diffuse[3 * i + c]), ea += fabs(v.I[3 * i + c] - diffuse[3 * i + c]);
            moved += fabs(v.I[3 * i + c] - raw[3 * i + c]);
        }
        double strong = eb > 0.05 * (diffuse[3 * i] + diffuse[3 * i + 1] + diffuse[3 * i + 2]);
        if (strong) in_lobe++, before += eb, after += ea;
        else if (!lobe[i]) off += moved, changed_outside += moved > 0;
    }
    printf("highlights: %d pixels changed; the %d pixels with a highlight over 5%%: colour error %.4f -> %.4f; "
           "%d pixels without one changed (by %.4f in all)\n", changed, in_lobe, before / in_lobe, after / in_lobe,
           changed_outside, off);
    CHECK(in_lobe > 20);
    CHECK(after < 0.25 * before);
    CHECK(changed_outside <= (int)(0.03 * n));
    CHECK(changed >= in_lobe);
    /* grey skin: no chroma to tell a highlight by */
    highlight_patch(&v, 1, 0, diffuse, lobe);
    memcpy(raw, v.I, sizeof(float) * 3 * n);
    CHECK(fr_sfs_take_out_highlights(ctx, &v, 2.0, &changed) == FRIG_OK);
    CHECK(changed == 0);
    CHECK(memcmp(raw, v.I, sizeof(float) * 3 * n) == 0);
    /* off */
    highlight_patch(&v, 0, 0, diffuse, lobe);
    memcpy(raw, v.I, sizeof(float) * 3 * n);
    CHECK(fr_sfs_take_out_highlights(ctx, &v, 0.0, &changed) == FRIG_OK);
    CHECK(changed == 0 && memcmp(raw, v.I, sizeof(float) * 3 * n) == 0);
    /* a warm lamp's highlight: left as it is */
    highlight_patch(&v, 0, 1, diffuse, lobe);
    memcpy(raw, v.I, sizeof(float) * 3 * n);
    CHECK(fr_sfs_take_out_highlights(ctx, &v, 2.0, &changed) == FRIG_OK);
    int lamp_changed = 0;
    for (size_t i = 0; i < n; i++)
        if (lobe[i] && memcmp(raw + 3 * i, v.I + 3 * i, sizeof(float) * 3)) lamp_changed++;
    printf("highlights: a warm lamp's highlight: %d of its pixels changed, %d in all\n", lamp_changed, changed);
    CHECK(lamp_changed <= 5);
    free(v.I), free(v.skin), free(diffuse), free(lobe), free(raw);
}

/* Known lighting from normals and albedo, 10% of the pixels replaced by outliers. */
static void test_lighting(void) {
    int n = 4000;
    float *I = malloc(sizeof(float) * 3 * n), *a = malloc(sizeof(float) * 3 * n), *nr = malloc(sizeof(float) * 3 * n);
    double truth[3][9], sh[3][9], d[3] = {0.3, -0.6, -0.74};
    double l = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    for (int k = 0; k < 3; k++) d[k] /= l;
    for (int c = 0; c < 3; c++) fr_sh_irradiance_coeffs(d, 0.8 + 0.05 * c, 0.3, truth[c]);
    fr_rng rng;
    fr_rng_seed(&rng, 9);
    for (int i = 0; i < n; i++) {
        double v[3] = {fr_rng_normal(&rng), fr_rng_normal(&rng), -fabs(fr_rng_normal(&rng)) - 0.3};
        double len = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        for (int k = 0; k < 3; k++) nr[3 * i + k] = (float)(v[k] / len);
        double S[3];
        fr_sfs_shading(truth, nr + 3 * i, S);
        for (int c = 0; c < 3; c++) {
            a[3 * i + c] = (float)(0.4 + 0.2 * fr_rng_uniform(&rng));
            I[3 * i + c] = (float)(a[3 * i + c] * S[c] * (1 + 0.01 * fr_rng_normal(&rng)));
            if (i % 10 == 3) I[3 * i + c] *= 0.2f; /* cast shadows */
        }
    }
    CHECK(fr_sfs_fit_lighting(ctx, n, NULL, I, a, nr, NULL, sh) == FRIG_OK);
    double worst = 0;
    for (int c = 0; c < 3; c++)
        for (int k = 0; k < 9; k++) worst = fmax(worst, fabs(sh[c][k] - truth[c][k]));
    printf("lighting: largest coefficient error %.4f (coefficients up to %.2f)\n", worst, truth[0][0]);
    CHECK(worst < 0.02);
    free(I), free(a), free(nr);
}

/* A head-sized sphere cap seen by a pinhole camera, its image made by the solver's own model;
 * starting from the cap plus a 3 mm bump the solver must explain the image and come back part of
 * the way (the depth offset the anchor keeps is removed before comparing). One image under one
 * light does not determine a surface (the classic shape-from-shading ambiguity): measured, 35% of
 * the bump's depth error remains where the shading is explained to 0.1%. */
static void test_depth_solver(void) {
    fr_sfs_view v;
    memset(&v, 0, sizeof v);
    v.w = v.h = 90;
    size_t n = (size_t)v.w * v.h;
    v.cam = fr_camera_perspective(600.0, v.w, v.h);
    float *truth = malloc(sizeof(float) * n);
    v.I = malloc(sizeof(float) * 3 * n), v.albedo = malloc(sizeof(float) * 3 * n), v.z_ref = malloc(sizeof(float) * n);
    v.z = calloc(n, sizeof(float)), v.normal = calloc(3 * n, sizeof(float)), v.err = malloc(sizeof(float) * n);
    v.face = calloc(n, 1), v.skin = calloc(n, 1), v.n_prior = calloc(3 * n, sizeof(float));
    double d[3] = {-0.4, -0.5, -0.77}, l = sqrt(0.16 + 0.25 + 0.77 * 0.77);
    for (int k = 0; k < 3; k++) d[k] /= l;
    for (int c = 0; c < 3; c++) fr_sh_irradiance_coeffs(d, 0.9, 0.35, v.sh[c]);
    const double Z = 0.6, R = 0.09; /* sphere centre depth and radius, metres */
    for (int y = 0; y < v.h; y++)
        for (int x = 0; x < v.w; x++) {
            size_t i = (size_t)y * v.w + x;
            double rx = (x - v.cam.cx) / v.cam.f, ry = (y - v.cam.cy) / v.cam.f;
            /* ray t (rx, ry, 1) meets the sphere |X - (0, 0, Z)| = R */
            double A = rx * rx + ry * ry + 1, B = -2 * Z, C = Z * Z - R * R, disc = B * B - 4 * A * C;
            if (disc <= 0) continue;
            double t = (-B - sqrt(disc)) / (2 * A);
            truth[i] = (float)t;
            double bump = 0.003 * exp(-((x - 50.0) * (x - 50.0) + (y - 40.0) * (y - 40.0)) / (2 * 12.0 * 12.0));
            v.z_ref[i] = (float)(t + bump);
            v.face[i] = v.skin[i] = (rx * rx + ry * ry) < 0.06 * 0.06;
        }
    /* the image from the finite-difference normals of the true depth */
    for (int y = 0; y + 1 < v.h; y++)
        for (int x = 0; x + 1 < v.w; x++) {
            size_t i = (size_t)y * v.w + x;
            if (!v.face[i]) continue;
            double f = v.cam.f, P = f * log(truth[i + 1] / truth[i]), Q = f * log(truth[i + v.w] / truth[i]);
            double rx = (x - v.cam.cx) / f, ry = (y - v.cam.cy) / f, m[3] = {P, Q, -(1 + rx * P + ry * Q)};
            double len = sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]), S[3];
            float nf[3] = {(float)(m[0] / len), (float)(m[1] / len), (float)(m[2] / len)};
            fr_sfs_shading(v.sh, nf, S);
            for (int c = 0; c < 3; c++) v.albedo[3 * i + c] = 0.5f, v.I[3 * i + c] = (float)(0.5 * S[c]);
        }
    fr_sfs_depth_options o;
    fr_sfs_depth_options_default(&o);
    o.iterations = 10;
    o.w_anchor = 1e-3;
    o.w_normal = 0.1;
    fr_sfs_depth_stats ds;
    CHECK(fr_sfs_solve_depth(ctx, &v, v.skin, &o, &ds) == FRIG_OK);
    double e[2] = {0, 0}, mean[2] = {0, 0};
    int cnt = 0;
    for (size_t i = 0; i < n; i++)
        if (v.skin[i] && v.err[i] >= 0) mean[0] += v.z_ref[i] - truth[i], mean[1] += v.z[i] - truth[i], cnt++;
    mean[0] /= cnt, mean[1] /= cnt;
    for (size_t i = 0; i < n; i++)
        if (v.skin[i] && v.err[i] >= 0)
            e[0] += fabs(v.z_ref[i] - truth[i] - mean[0]), e[1] += fabs(v.z[i] - truth[i] - mean[1]);
    e[0] /= cnt, e[1] /= cnt;
    double *res = malloc(sizeof(double) * n), rm, rmed, r90;
    int nres = 0;
    for (size_t i = 0; i < n; i++)
        if (v.skin[i] && v.err[i] >= 0) res[nres++] = v.err[i];
    fr_error_stats(res, nres, &rm, &rmed, &r90);
    free(res);
    printf("depth solver: median relative shading residual %.5f (energy %.4g -> %.4g)\n", rmed, ds.energy_start, ds.energy_end);
    CHECK(rmed < 0.002);
    CHECK(ds.energy_end < 0.1 * ds.energy_start);
    printf("depth solver: %d unknowns, %d factorizations; depth error (offset removed) %.3f mm at the start, %.3f mm solved\n",
           ds.unknowns, ds.factorizations, 1e3 * e[0], 1e3 * e[1]);
    CHECK(ds.unknowns > 1000);
    CHECK(e[1] < 0.8 * e[0]);
    free(truth), free(v.I), free(v.albedo), free(v.z_ref), free(v.z), free(v.normal), free(v.err), free(v.face);
    free(v.skin), free(v.n_prior);
}

/* ---- the whole stage on a small synthetic subject ---- */

typedef struct scene {
    frig_rig *truth_rig, *rig;
    frig_photoset *set;
    frig_synth_truth *truth[16];
    int photos;
    int shared; /* the truths belong to the rendered scene (scene_in's copies) */
} scene;

/* Photos of subject 'seed' written to dir, a photo set with the true poses, cameras and
 * expressions as the fit, and the model-space rig at the subject's true identity (what a
 * perfect landmark fit could give: the personal offset outside the model's span remains). */
static int make_scene(frig_model *model, const char *dir, scene *sc) {
    memset(sc, 0, sizeof *sc);
    frig_synth_subject *subj = NULL;
    if (frig_synth_subject_create(ctx, model, 7100, &subj)) return 0;
    const double *id;
    frig_synth_subject_identity(subj, &id);
    if (frig_rig_from_model(ctx, model, id, &sc->rig) || frig_rig_clone(ctx, frig_synth_subject_rig(subj), &sc->truth_rig) ||
        frig_photoset_create(ctx, &sc->set))
        return 0;
    int ne = 0;
    const char *names[128];
    for (int k = 0; k < frig_model_expression_count(model) && ne < 128; k++)
        if (frig_model_expression_fitting(model, k)) names[ne++] = frig_model_expression_name(model, k);
    if (fr_photoset_set_fit_spaces(ctx, sc->set, frig_model_identity_count(model), ne, names)) return 0;
    static const int failure[] = {0, 0, 0, 0, 0, 0, 0, FRIG_SYNTH_FAILURE_OVEREXPOSED};
    sc->photos = 8;
    for (int p = 0; p < sc->photos; p++) {
        frig_image *img = NULL;
        if (frig_synth_render(ctx, subj, 9000 + (uint64_t)p, failure[p], &img, &sc->truth[p])) return 0;
        char path[4096];
        snprintf(path, sizeof path, "%s/photo_%03d.jpg", dir, p);
        size_t idx;
        if (frig_image_save_jpeg(ctx, img, path) || frig_photoset_add(ctx, sc->set, path, &idx)) return 0;
        frig_photoset_set_size(ctx, sc->set, idx, frig_image_width(img), frig_image_height(img));
        frig_photoset_set_status(ctx, sc->set, idx, FRIG_PHOTO_OK, NULL);
        frig_image_free(img);
        double R[9], t[3], f, w[128];
        frig_synth_truth_pose(sc->truth[p], R, t);
        frig_synth_truth_camera(sc->truth[p], &f, NULL, NULL);
        const double *tw = frig_synth_truth_expression(sc->truth[p]);
        for (int e = 0; e < ne; e++) {
            int k = frig_rig_shape_find(sc->truth_rig, names[e]);
            w[e] = k >= 0 ? tw[k] : 0;
        }
        if (fr_photoset_set_fit(ctx, sc->set, idx, R, t, f, 1, w, 1.0, 1)) return 0;
    }
    frig_synth_subject_free(subj);
    return 1;
}

static void free_scene(scene *sc) {
    for (int p = 0; p < sc->photos && !sc->shared; p++) frig_synth_truth_free(sc->truth[p]);
    frig_rig_free(sc->truth_rig), frig_rig_free(sc->rig), frig_photoset_free(sc->set);
}

/* Mean distance (mm) of photo p's cloud to the true surface after a similarity alignment. */
static double cloud_error(const scene *sc, const frig_clouds *cl, int p) {
    size_t n = frig_clouds_count(cl, (size_t)p);
    if (!n) return NAN;
    fr_sfs_mesh m;
    if (fr_sfs_mesh_init(ctx, sc->truth_rig, &m)) return NAN;
    float *xyz = malloc(sizeof(float) * 3 * (size_t)m.nv);
    int32_t *ft = malloc(sizeof(int32_t) * 3 * (size_t)m.nt);
    int nf = 0;
    for (int t = 0; t < m.nt; t++)
        if (m.face[t]) memcpy(ft + 3 * nf++, m.tris + 3 * t, sizeof(int32_t) * 3);
    fr_sfs_mesh_eval(&m, frig_synth_truth_expression(sc->truth[p]), xyz);
    fr_tri_tree *ix = NULL;
    fr_tri_tree_build(ctx, xyz, ft, nf, &ix);
    double *pts = malloc(sizeof(double) * 3 * n), *d = malloc(sizeof(double) * n), s, R[9], t[3], mean, med, p90;
    const float *c = frig_clouds_xyz(cl, (size_t)p);
    for (size_t k = 0; k < 3 * n; k++) pts[k] = c[k];
    fr_cloud_align(ctx, ix, pts, (int)n, 10, 0.01, d, &s, R, t);
    int fin = 0;
    for (size_t k = 0; k < n; k++)
        if (isfinite(d[k])) d[fin++] = d[k];
    fr_error_stats(d, fin, &mean, &med, &p90);
    fr_tri_tree_free(ix);
    free(pts), free(d), free(xyz), free(ft);
    fr_sfs_mesh_free(&m);
    return 1e3 * mean;
}

/* The scene is rendered once (photos in sfs_scene/, the photo set saved there) and each test
 * takes a copy of it: the rigs cloned, the photo set loaded afresh (each test changes its fits),
 * the truths shared. */
static scene rendered;
static const char *rendered_dir; /* NULL until rendered, then rendered_path */
static char rendered_path[4096];

/* 1 rendered, 0 failed, -1 without the model */
static int render_once(void) {
    if (rendered_dir) return 1;
    frig_model *model = fixture_model(ctx);
    if (!model) return -1;
    frig_ctx_set_param(ctx, FRIG_PARAM_SYNTH_IMAGE_SIZE, 256);
    frig_ctx_set_param(ctx, FRIG_PARAM_SYNTH_RIG_OBJ, 0);
    /* the scene's figures below were measured with the face at 160 pixels in the crop (the default
     * until 2026-12-06; at 128 the lights' axis reads 0.967, over sfs.joint_light, and the stage
     * takes the light solve, so the full solve's checks would not run) */
    frig_ctx_set_param(ctx, FRIG_PARAM_SFS_FACE_PX, 160);
    const char *dir = test_temp_dir("sfs_scene");
    int ok = make_scene(model, dir, &rendered) && frig_photoset_save(ctx, rendered.set, dir) == FRIG_OK;
    CHECK(ok);
    frig_model_free(model);
    if (ok) snprintf(rendered_path, sizeof rendered_path, "%s", dir), rendered_dir = rendered_path;
    return ok;
}

/* A copy of the scene, outputs in a temporary folder 'name'; 0 (skipped) without the model. */
static int scene_in(const char *name, scene *sc, const char **dir) {
    memset(sc, 0, sizeof *sc);
    int r = render_once();
    if (r < 0) test_skip("the ICT model is not available");
    if (r <= 0) return 0;
    *dir = test_temp_dir(name);
    *sc = rendered;
    sc->shared = 1, sc->rig = NULL, sc->truth_rig = NULL, sc->set = NULL;
    int ok = frig_rig_clone(ctx, rendered.rig, &sc->rig) == FRIG_OK &&
             frig_rig_clone(ctx, rendered.truth_rig, &sc->truth_rig) == FRIG_OK &&
             frig_photoset_load(ctx, rendered_dir, &sc->set) == FRIG_OK;
    CHECK(ok);
    return ok;
}

/* The outer loop's deferred texture (fr_sfs_stage_keep, then fr_sfs_run_albedo, as
 * frig_retarget_refine draws it): the same bytes as frig_sfs's albedo. */
static void check_kept_albedo(const scene *sc, const frig_image *albedo) {
    fr_sfs_settings st;
    fr_sfs_settings_from_ctx(ctx, &st);
    frig_clouds *cl = NULL;
    fr_sfs_run *run = NULL;
    frig_image *later = NULL;
    CHECK(fr_sfs_stage_keep(ctx, sc->rig, sc->set, &st, &cl, &run) == FRIG_OK && run && cl);
    if (run) CHECK(fr_sfs_run_albedo(ctx, run, &later) == FRIG_OK);
    int same = albedo && later && frig_image_width(later) == frig_image_width(albedo) &&
               frig_image_height(later) == frig_image_height(albedo) &&
               frig_image_stride(later) == frig_image_stride(albedo);
    if (same)
        same = !memcmp(frig_image_pixels(later), frig_image_pixels(albedo),
                       frig_image_stride(albedo) * (size_t)frig_image_height(albedo));
    printf("kept computation's albedo: %s\n", same ? "the same bytes" : "DIFFERENT");
    CHECK(same);
    if (run) fr_sfs_run_free(run);
    free(run);
    frig_image_free(later);
    frig_clouds_free(cl);
}

/* The albedo texture against the subject's painted albedo (lib/eval/albedo_error.h): views whose
 * colour needs an albedo above 1 or is no skin's, and texels only a grazing view or two showed,
 * do not colour it; the shading's colour stays the light's, faintly seen texels are no
 * brighter than most well seen ones, and the unseen ones are filled smoothly (pull-push). */
static void check_albedo_error(const frig_image *albedo) {
    frig_model *model = fixture_model(ctx);
    frig_synth_subject *subj = NULL;
    fr_albedo_error e;
    int ok = model && albedo && frig_synth_subject_create(ctx, model, 7100, &subj) == FRIG_OK &&
             fr_albedo_error_of(ctx, subj, albedo, &e) == FRIG_OK;
    CHECK(ok);
    if (ok) {
        printf("albedo texture: %d face skin vertices, error mean %.3f p90 %.3f, %.2f%% over %.1f\n", e.vertices, e.mean,
               e.p90, 100.0 * e.gross, FR_ALBEDO_GROSS);
        /* measured 0.386 and 28.1% on the shared shape's 96 grid (sfs.shape_size, the default
         * since 2026-12-07), 0.352 and 25.0% on the 128 grid before (0.371 and 28% with the unseen
         * texels grown 8 texels out, then one colour; 0.468 and 48% with the lighting's own colour
         * at every normal and no cap on the faintly seen texels' brightness as well; 0.584 and 59%
         * with every view and every seen texel counted as well) */
        CHECK(e.vertices > 5000);
        CHECK(e.mean < 0.40 && e.gross < 0.30);
    }
    frig_synth_subject_free(subj);
    frig_model_free(model);
}

static void test_stage(void) {
    const char *dir;
    scene sc;
    if (!scene_in("sfs_stage", &sc, &dir)) return;
    frig_clouds *cl = NULL, *cl1 = NULL;
    frig_image *albedo = NULL;
    char overlays[4200];
    snprintf(overlays, sizeof overlays, "%s/overlays", dir);
    frig_ctx_set_threads(ctx, 2);
    CHECK(frig_sfs(ctx, sc.rig, sc.set, overlays, &cl, &albedo) == FRIG_OK);
    if (!cl) {
        fprintf(stderr, "frig_sfs: %s\n", frig_ctx_errmsg(ctx));
        free_scene(&sc);
        return;
    }
    /* sfs.texture_size 0: the power of two at or above twice sfs.face_px (this scene's 160: 512) */
    int side = 64;
    while (side < 2 * frig_ctx_get_param(ctx, FRIG_PARAM_SFS_FACE_PX)) side *= 2;
    CHECK(frig_ctx_get_param(ctx, FRIG_PARAM_SFS_TEXTURE_SIZE) == 0 && side == 512);
    CHECK(albedo && frig_image_width(albedo) == side && frig_image_height(albedo) == side);
    double sum = 0;
    int clouds = 0;
    for (int p = 0; p < sc.photos; p++) {
        size_t px = 0, kept = 0;
        double err = NAN;
        frig_photoset_sfs_stats(sc.set, (size_t)p, &px, &kept, &err);
        double e = cloud_error(&sc, cl, p);
        printf("photo %d: %s, %zu of %zu pixels kept, shading error %.3f, cloud %.3f mm%s%s\n", p,
               frig_photo_status_name(frig_photoset_status(sc.set, (size_t)p)), kept, px, err, e,
               *frig_photoset_reason(sc.set, (size_t)p) ? ": " : "", frig_photoset_reason(sc.set, (size_t)p));
        if (p < 7) {
            CHECK(frig_photoset_status(sc.set, (size_t)p) == FRIG_PHOTO_OK);
            CHECK(kept >= 500 && kept == frig_clouds_count(cl, (size_t)p));
            if (isfinite(e)) sum += e, clouds++;
        }
    }
    /* the over-exposed photo is judged, not used */
    CHECK(frig_photoset_status(sc.set, 7) == FRIG_PHOTO_SFS_FAILED);
    CHECK(strstr(frig_photoset_reason(sc.set, 7), "over-exposed") != NULL);
    CHECK(frig_clouds_count(cl, 7) == 0);
    double mean = clouds ? sum / clouds : NAN;
    /* measured 0.88 mm (0.74-1.12 per photo) on this subject with the true poses, cameras and
     * expressions as the fit; the floor guards against regressions */
    printf("stage: %d clouds, mean error %.3f mm\n", clouds, mean);
    CHECK(clouds == 7);
    CHECK(mean < 1.1);
    char pic[4400];
    snprintf(pic, sizeof pic, "%s/photo_000.jpg", overlays);
    CHECK(test_file_exists(pic));
    /* the head frame: points near the rig's face, normals unit length */
    const float *x0 = frig_clouds_xyz(cl, 0), *n0 = frig_clouds_normals(cl, 0);
    CHECK(x0 && fabs(x0[2]) < 0.2 && fabs(sqrt(n0[0] * n0[0] + n0[1] * n0[1] + n0[2] * n0[2]) - 1) < 1e-3);
    /* the shared solve: eight photos judged (over sfs.joint_min_photos), lights from five directions */
    int judged = 0;
    double axis = 0;
    const char *why = NULL;
    frig_sfs_solve solve = frig_photoset_sfs_solve(sc.set, &judged, &axis, &why);
    printf("shared solve %d (%s), %d photos judged, lights' axis %.3f\n", (int)solve, why, judged, axis);
    CHECK(solve == FRIG_SFS_SOLVE_FULL && judged == 8 && !strcmp(why, ""));
    CHECK(axis > 1.0 / 3 && axis < frig_ctx_get_param(ctx, FRIG_PARAM_SFS_JOINT_LIGHT));
    /* report.json keeps the results */
    CHECK(frig_photoset_save(ctx, sc.set, dir) == FRIG_OK);
    frig_photoset *back = NULL;
    CHECK(frig_photoset_load(ctx, dir, &back) == FRIG_OK);
    if (back) {
        double a[27], b[27], Ra[9], Rb[9];
        CHECK(frig_photoset_sfs_lighting(sc.set, 0, a) == FRIG_OK && frig_photoset_sfs_lighting(back, 0, b) == FRIG_OK);
        CHECK(memcmp(a, b, sizeof a) == 0);
        CHECK(frig_photoset_sfs_pose(sc.set, 0, Ra, NULL) == FRIG_OK && frig_photoset_sfs_pose(back, 0, Rb, NULL) == FRIG_OK);
        CHECK(memcmp(Ra, Rb, sizeof Ra) == 0);
        CHECK(frig_photoset_status(back, 7) == FRIG_PHOTO_SFS_FAILED);
        int judged_back = 0;
        double axis_back = 0;
        CHECK(frig_photoset_sfs_solve(back, &judged_back, &axis_back, NULL) == FRIG_SFS_SOLVE_FULL && judged_back == 8 &&
              fabs(axis_back - axis) < 1e-9);
        frig_photoset_free(back);
    }
    /* one thread: the same clouds, byte for byte (the rerun judges the sfs_failed photo again) */
    frig_ctx_set_threads(ctx, 1);
    CHECK(frig_sfs(ctx, sc.rig, sc.set, NULL, &cl1, NULL) == FRIG_OK);
    int same = cl1 != NULL;
    for (int p = 0; cl1 && p < sc.photos; p++) {
        size_t n = frig_clouds_count(cl, (size_t)p);
        same &= n == frig_clouds_count(cl1, (size_t)p);
        if (same && n)
            same &= !memcmp(frig_clouds_xyz(cl, (size_t)p), frig_clouds_xyz(cl1, (size_t)p), sizeof(float) * 3 * n) &&
                    !memcmp(frig_clouds_confidence(cl, (size_t)p), frig_clouds_confidence(cl1, (size_t)p),
                            sizeof(float) * n);
    }
    printf("1 and 2 threads: %s clouds\n", same ? "the same" : "DIFFERENT");
    CHECK(same);
    check_kept_albedo(&sc, albedo);
    check_albedo_error(albedo);
    frig_clouds_free(cl), frig_clouds_free(cl1), frig_image_free(albedo);
    free_scene(&sc);
}

/* Poses turned by 4 degrees (about y and x, zero mean: a turn common to all photos is free): the
 * shared solve's pose steps (with the multi-view term and the joint albedo, residual scale 0.1)
 * against the shared surface and albedo bring them back toward the truth. */
/* The set's record of the shared solve: each reason read back from report.json as written, none on
 * a set the stage has not seen, and a malformed block refused. */
static void test_solve_report(void) {
    const char *dir = test_temp_dir("sfs_solve_report");
    frig_photoset *set = NULL, *back = NULL;
    CHECK(frig_photoset_create(ctx, &set) == FRIG_OK);
    if (!set || !dir) return;
    const char *why = "x";
    int photos = -1;
    CHECK(frig_photoset_sfs_solve(set, &photos, NULL, &why) == FRIG_SFS_SOLVE_NONE && photos == 0 && !strcmp(why, ""));
    const char *names[] = {"", "few_photos", "many_photos", "one_light_axis", "outer_loop"};
    for (int w = 0; w < 5; w++) {
        fr_photoset_set_sfs_solve(set, w ? FRIG_SFS_SOLVE_LIGHT : FRIG_SFS_SOLVE_FULL, w, 10 + w, 0.25 * w);
        CHECK(frig_photoset_save(ctx, set, dir) == FRIG_OK && frig_photoset_load(ctx, dir, &back) == FRIG_OK);
        double axis = -1;
        frig_sfs_solve solve = back ? frig_photoset_sfs_solve(back, &photos, &axis, &why) : FRIG_SFS_SOLVE_NONE;
        CHECK(solve == (w ? FRIG_SFS_SOLVE_LIGHT : FRIG_SFS_SOLVE_FULL) && photos == 10 + w && axis == 0.25 * w &&
              !strcmp(why, names[w]));
        frig_photoset_free(back), back = NULL;
    }
    /* a block naming no solve is refused, with a sentence */
    char path[4200];
    snprintf(path, sizeof path, "%s/report.json", dir);
    size_t size = 0;
    unsigned char *text = test_read_file(path, &size);
    char *at = text ? strstr((char *)text, "\"light\"") : NULL;
    CHECK(at != NULL);
    if (at) {
        memcpy(at, "\"heavy\"", 7);
        FILE *f = fopen(path, "wb");
        CHECK(f && fwrite(text, 1, size, f) == size);
        if (f) fclose(f);
        CHECK(frig_photoset_load(ctx, dir, &back) == FRIG_ERR_CORRUPT && strstr(frig_ctx_errmsg(ctx), "\"sfs\""));
        frig_photoset_free(back), back = NULL;
    }
    free(text);
    /* the identity the clouds were drawn at: read back to the bit; one weight short is refused; a new
     * fit drops it */
    const char *names1[] = {"jawOpen"};
    double id[3] = {0.125, -1.0 / 3.0, 2e-7};
    CHECK(fr_photoset_set_fit_spaces(ctx, set, 3, 1, names1) == FRIG_OK);
    CHECK(fr_photoset_set_sfs_identity(ctx, set, id) == FRIG_OK);
    CHECK(frig_photoset_save(ctx, set, dir) == FRIG_OK && frig_photoset_load(ctx, dir, &back) == FRIG_OK);
    CHECK(back && back->sfs_identity && memcmp(back->sfs_identity, id, sizeof id) == 0);
    frig_photoset_free(back), back = NULL;
    text = test_read_file(path, &size);
    at = text ? strstr((char *)text, "2e-07") : NULL;
    CHECK(at != NULL);
    if (at) {
        char *comma = at;
        while (comma > (char *)text && *comma != ',') comma--;
        memset(comma, ' ', (size_t)(at + 5 - comma)); /* ", 2e-07" gone: two weights for three */
        FILE *f = fopen(path, "wb");
        CHECK(f && fwrite(text, 1, size, f) == size);
        if (f) fclose(f);
        CHECK(frig_photoset_load(ctx, dir, &back) == FRIG_ERR_CORRUPT && strstr(frig_ctx_errmsg(ctx), "identity"));
        frig_photoset_free(back);
    }
    free(text);
    CHECK(fr_photoset_set_fit_spaces(ctx, set, 3, 1, names1) == FRIG_OK && set->sfs_identity == NULL);
    frig_photoset_free(set);
}

static void test_joint_pose(void) {
    const char *dir;
    scene sc;
    if (!scene_in("sfs_joint_pose", &sc, &dir)) return;
    double Rt[8][9];
    for (int p = 0; p < sc.photos; p++) {
        fr_photo *ph = &sc.set->photos[p];
        double w[3] = {0, 0, 0}, dR[9], R[9];
        w[p % 2 ? 0 : 1] = (p % 4 < 2 ? 4.0 : -4.0) * M_PI / 180; /* zero mean: a common turn is the gauge */
        memcpy(Rt[p], ph->fit_rotation, sizeof Rt[p]);
        fr_rotation_from_axis_angle(w, dR);
        fr_mat3_mul(dR, ph->fit_rotation, R);
        memcpy(ph->fit_rotation, R, sizeof R);
    }
    fr_sfs_settings st;
    fr_sfs_settings_from_ctx(ctx, &st);
    st.w_stereo = 1, st.pose_steps = 6, st.joint_albedo = 1, st.shape_sigma = 0.1;
    st.rounds = 3, st.shape_iterations = 4, st.pose_levels = 0, st.joint_min_photos = 0; /* as measured */
    st.shape_size = 128; /* as measured (the default is 96 since 2026-12-07: 3.75 deg there) */
    st.joint_light = 1; /* the scene's one light: the full solve all the same */
    st.expression_steps = 3; /* as measured (the default is 2 since 2026-12-05: 3.62 deg there) */
    st.highlights = 0; /* as measured (sfs.highlights 2, the default since 2026-12-07: 3.93 deg on this scene) */
    fr_sfs_run run;
    CHECK(fr_sfs_run_all(ctx, sc.rig, sc.set, &st, &run) == FRIG_OK);
    double before = 0, after = 0;
    int n = 0;
    for (int k = 0; k < run.n; k++) {
        if (!run.ok[k]) continue;
        size_t p = run.photo[k];
        before += fr_rotation_angle_deg(sc.set->photos[p].fit_rotation, Rt[p]);
        after += fr_rotation_angle_deg(run.views[k].R, Rt[p]);
        n++;
    }
    before /= n ? n : 1, after /= n ? n : 1;
    printf("joint pose: rotation error %.2f -> %.2f deg over %d photos\n", before, after, n);
    CHECK(n == 7);
    /* measured 4.00 -> 3.47 deg with 6 steps per round: the pose steps move the poses toward the
     * truth, slowly (docs/sfs.md). 2.82 before the lighting left out the texels of absurd albedo
     * (up to 290 times the mean here, sfs_multiview.c), which had set it in part */
    CHECK(after < 0.9 * before);
    fr_sfs_run_free(&run);
    free_scene(&sc);
}

/* Two photos' poses turned by 9 degrees about the head's origin (one about y, one about x), beyond
 * the shading pose steps' basin, the others true: the coarse-to-fine registration
 * (sfs_pose_align.c: blurred photometric and occluding-contour terms against the shape and albedo
 * the photos share) brings the two back near the truth and leaves the others near it. */
static void test_pose_align(void) {
    const char *dir;
    scene sc;
    if (!scene_in("sfs_pose_align", &sc, &dir)) return;
    double Rt[8][9], turn = 9.0;
    for (int p = 0; p < sc.photos; p++) {
        fr_photo *ph = &sc.set->photos[p];
        double w[3] = {0, 0, 0}, dR[9], R[9];
        memcpy(Rt[p], ph->fit_rotation, sizeof Rt[p]);
        if (p > 1) continue;
        w[p ? 0 : 1] = turn * M_PI / 180;
        fr_rotation_from_axis_angle(w, dR);
        fr_mat3_mul(dR, ph->fit_rotation, R);
        memcpy(ph->fit_rotation, R, sizeof R);
    }
    fr_sfs_settings st;
    fr_sfs_settings_from_ctx(ctx, &st);
    fr_sfs_light_shared_solve(&st); /* the shared solve it was measured with; J drifts on 7 photos */
    st.pose_levels = 3, st.joint_min_photos = 0, st.pose_steps = 0, st.joint_light = 1;
    fr_sfs_run run;
    CHECK(fr_sfs_run_all(ctx, sc.rig, sc.set, &st, &run) == FRIG_OK);
    double turned = 0, others = 0, turned_mean = 0;
    int n = 0;
    for (int k = 0; k < run.n; k++) {
        if (!run.ok[k]) continue;
        size_t p = run.photo[k];
        double a = fr_rotation_angle_deg(run.views[k].R, Rt[p]);
        printf("photo %zu: rotation error %.2f -> %.2f deg\n", p, fr_rotation_angle_deg(sc.set->photos[p].fit_rotation, Rt[p]), a);
        if (p < 2) turned = a > turned ? a : turned, turned_mean += a / 2;
        else others = a > others ? a : others;
        n++;
    }
    printf("pose registration: the turned photos' mean %.2f, worst %.2f deg (from %.1f), the others' worst %.2f deg (from 0)\n",
           turned_mean, turned, turn, others);
    CHECK(n == 7);
    /* measured: the turned 9 -> 5.03 and 2.67 deg, the others 0 -> 1.9-4.6 (the shared albedo and
     * shape are built from the turned photos too; docs/sfs.md); without the registration the
     * turned photos stay at 9 */
    CHECK(turned_mean < 4.5);
    CHECK(turned < 6.5);
    CHECK(others < 5.5);
    fr_sfs_run_free(&run);
    free_scene(&sc);
}

/* How far (mm, mean over the rig's narrow face) the rig at weights w (the rig's shapes) lies from
 * the rig at photo p's true expression. */
static double expression_error_mm(const scene *sc, int p, const double *w) {
    const frig_rig *rig = sc->rig;
    const double *tw = frig_synth_truth_expression(sc->truth[p]);
    int nv = rig->topo.vertex_count, nf = narrow_face_count(rig);
    size_t n3 = 3 * (size_t)nv;
    double *dw = calloc((size_t)rig->shape_count + 1, sizeof(double)), sum = 0;
    for (int j = 0; j < rig->shape_count; j++) {
        int k = frig_rig_shape_find(sc->truth_rig, frig_rig_shape_name(rig, j));
        dw[j] = w[j] - (k >= 0 ? tw[k] : 0);
    }
    for (int q = 0; q < nf; q++) {
        double a[3] = {0, 0, 0};
        for (int j = 0; j < rig->shape_count; j++)
            if (dw[j] != 0)
                for (int c = 0; c < 3; c++) a[c] += dw[j] * rig->deltas[n3 * j + 3 * (size_t)q + c];
        sum += sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
    }
    free(dw);
    return 1e3 * sum / nf;
}

/* The fit's expressions wrong on every photo (the jaw opened by 0.3, both smiles or both inner
 * brows raised by 0.4, in turn), pose and camera true: the expression step (sfs.expression_steps,
 * in the full shared solve) takes each photo's expression nearer the truth's. */
static void test_expression(void) {
    const char *dir;
    scene sc;
    if (!scene_in("sfs_expression", &sc, &dir)) return;
    static const char *const wrong[3][2] = {{"jawOpen", NULL}, {"mouthSmile_L", "mouthSmile_R"}, {"browInnerUp_L", "browInnerUp_R"}};
    static const double by[3] = {0.3, 0.4, 0.4};
    for (int p = 0; p < sc.photos; p++)
        for (int e = 0; e < sc.set->n_expressions; e++)
            for (int q = 0; q < 2; q++) {
                const char *name = wrong[p % 3][q];
                if (!name || strcmp(sc.set->expression_names[e], name)) continue;
                double *w = &sc.set->photos[p].fit_expression[e];
                *w = fmin(1.0, *w + by[p % 3]);
            }
    fr_sfs_settings st;
    fr_sfs_settings_from_ctx(ctx, &st);
    st.joint_min_photos = 0, st.pose_levels = 0, st.rounds = 3, st.shape_iterations = 4; /* J without the registration */
    st.joint_light = 1;
    st.pose_steps = 0;
    st.expression_steps = 3, st.expression_prior = 0.3, st.expression_sparse = 0.3; /* as measured (the default steps 2 since 2026-12-05) */
    st.highlights = 0; /* as measured (with sfs.highlights 2, the default since 2026-12-07: 1.164 -> 1.159 mm on this scene) */
    double before = 0, after = 0, smile_before = 0, smile_after = 0;
    int n = 0;
    fr_sfs_run run;
    CHECK(fr_sfs_run_all(ctx, sc.rig, sc.set, &st, &run) == FRIG_OK);
    double *w = calloc((size_t)sc.rig->shape_count + 1, sizeof(double));
    for (int k = 0; k < run.n; k++) {
        if (!run.ok[k]) continue;
        size_t p = run.photo[k];
        memset(w, 0, sizeof(double) * (size_t)sc.rig->shape_count);
        for (int e = 0; e < sc.set->n_expressions; e++) {
            int j = frig_rig_shape_find(sc.rig, sc.set->expression_names[e]);
            if (j >= 0) w[j] = sc.set->photos[p].fit_expression[e];
        }
        double a = expression_error_mm(&sc, (int)p, w), b = expression_error_mm(&sc, (int)p, run.views[k].weights);
        printf("photo %zu: expression error %.3f -> %.3f mm\n", p, a, b);
        before += a / 7, after += b / 7, n++;
        if (p % 3 == 1) smile_before += a, smile_after += b;
    }
    printf("expression step: the rig at the weights from the truth's expression, mean %.3f -> %.3f mm over %d photos\n",
           before, after, n);
    CHECK(n == 7);
    /* measured 1.164 -> 1.087 mm: the smiles 2.71 -> 1.61 (photos 1, 4), the jaws 4.97 -> 4.60 (0, 3,
     * 6: 0 and 3 better, 6 worse), the brows 0.47 -> 1.40 (the sparsity takes true weights down too; the
     * prior holds toward the fit's wrong ones; docs/sfs.md); 1.053, the smiles 1.28, when the lighting
     * was set in part by texels of absurd albedo */
    CHECK(after < 0.95 * before);
    CHECK(smile_after < 0.6 * smile_before);
    /* the stage at another thread count: the same weights in the report (by the fit's names), and
     * report.json keeps them */
    int threads = frig_ctx_threads(ctx), same = 1;
    frig_ctx_set_threads(ctx, threads == 1 ? 2 : 1);
    frig_clouds *cl = NULL;
    CHECK(fr_sfs_stage(ctx, sc.rig, sc.set, &st, NULL, &cl, NULL) == FRIG_OK);
    frig_ctx_set_threads(ctx, threads);
    frig_photoset *back = NULL;
    CHECK(frig_photoset_save(ctx, sc.set, dir) == FRIG_OK && frig_photoset_load(ctx, dir, &back) == FRIG_OK);
    for (int k = 0; k < run.n; k++) {
        if (!run.ok[k]) continue;
        const fr_photo *ph = &sc.set->photos[run.photo[k]];
        CHECK(ph->sfs_expression != NULL);
        if (!ph->sfs_expression) continue;
        for (int e = 0; e < sc.set->n_expressions; e++) {
            int j = frig_rig_shape_find(sc.rig, sc.set->expression_names[e]);
            if (j >= 0 && ph->sfs_expression[e] != run.views[k].weights[j]) same = 0;
        }
        const fr_photo *pb = back ? &back->photos[run.photo[k]] : NULL;
        if (!pb || !pb->sfs_expression ||
            memcmp(pb->sfs_expression, ph->sfs_expression, sizeof(double) * (size_t)sc.set->n_expressions))
            same = 0;
    }
    CHECK(same);
    frig_photoset_free(back);
    frig_clouds_free(cl);
    free(w);
    fr_sfs_run_free(&run);
    free_scene(&sc);
}

/* The model's identity modes solved with the shared shape (sfs.identity_modes, sfs_multiview.c):
 * the rig starts at the mean face (identity 0) with the photos' true poses and expressions; the
 * identity change the solve finds takes the narrow face's neutral toward the subject's (the
 * personal offset outside the model's span stays). One run with the displacement held by 'hold' in
 * the first rounds (sfs.displacement_hold; < 0: the default): the narrow face's neutral against the
 * truth, mm, and the change's norm in 'change'. */
static double identity_run(const scene *sc, const frig_rig *mean, const frig_model *model, double hold,
                           double *change) {
    fr_sfs_settings st;
    fr_sfs_settings_from_ctx(ctx, &st);
    fr_sfs_settings_identity(ctx, &st, model, sc->set); /* sfs.identity_modes: 100 by default */
    st.joint_min_photos = 0, st.pose_levels = 0, st.expression_steps = 0, st.pose_steps = 0; /* the true poses, expressions */
    st.joint_light = 1;
    /* seven photos of 256 pixels: the prior must be stronger than the default's (measured with the prior at
     * the mean face: 3.260 -> 3.728 mm at 1, 3.203 at 100, 2.823 at 1000; docs/sfs.md; at the fit's identity,
     * sfs.identity_prior_centre 1, 2.859 at 1000) */
    st.identity_prior = 1000;
    if (hold >= 0) st.displacement_hold = hold;
    CHECK(st.identity_count == 100);
    fr_sfs_run run;
    CHECK(fr_sfs_run_all(ctx, mean, sc->set, &st, &run) == FRIG_OK && run.mesh.ident && run.ident);
    int nv = frig_rig_vertex_count(mean), nf = narrow_face_count(mean);
    float *x = malloc(sizeof(float) * 3 * (size_t)nv);
    double c2 = 0;
    for (size_t q = 0; q < 3 * (size_t)nv; q++) x[q] = frig_rig_neutral(mean)[q] + (run.mesh.ident ? run.mesh.ident[q] : 0);
    for (int k = 0; k < st.identity_count && run.ident; k++) c2 += run.ident[k] * run.ident[k];
    *change = sqrt(c2);
    double after = 1e3 * fr_aligned_mean_distance(frig_rig_neutral(sc->truth_rig), x, nf);
    free(x);
    fr_sfs_run_free(&run);
    return after;
}

/* Held, the modes take more of the shape (docs/sfs.md, "The identity first"). */
static void test_identity(void) {
    const char *dir;
    scene sc;
    if (!scene_in("sfs_identity", &sc, &dir)) return;
    frig_model *model = fixture_model(ctx);
    frig_rig *mean = NULL;
    double *zero = calloc((size_t)frig_model_identity_count(model) + 1, sizeof(double));
    CHECK(frig_rig_from_model(ctx, model, zero, &mean) == FRIG_OK);
    double free_change, held_change;
    double free_after = identity_run(&sc, mean, model, 0, &free_change);
    double after = identity_run(&sc, mean, model, -1, &held_change); /* the default hold */
    int nf = narrow_face_count(mean);
    double before = 1e3 * fr_aligned_mean_distance(frig_rig_neutral(sc.truth_rig), frig_rig_neutral(mean), nf);
    double best = 1e3 * fr_aligned_mean_distance(frig_rig_neutral(sc.truth_rig), frig_rig_neutral(sc.rig), nf);
    printf("identity modes: narrow face's neutral %.3f mm (mean face) -> %.3f mm (|change| %.2f; the displacement "
           "never held: %.3f mm, |change| %.2f); the true identity's %.3f mm\n",
           before, after, held_change, free_after, free_change, best);
    /* measured on the 96 grid (sfs.shape_size, the default since 2026-12-07) 2.908 (|change| 0.73) held by the
     * default 100, 2.922 (0.70) not held; on the 128 grid 2.849 (1.03), 2.840 (1.04) by 5, 2.853 (1.01) */
    CHECK(after < 0.92 * before);
    CHECK(held_change > free_change);
    free(zero);
    frig_rig_free(mean);
    frig_model_free(model);
    free_scene(&sc);
}

int main(void) {
    ctx = frig_ctx_create();
    test_sh_gradient();
    test_skin();
    test_slic();
    test_lighting();
    test_texture_shading();
    test_highlights();
    test_light_concentration();
    test_depth_solver();
    test_solve_report();
    test_stage();
    test_joint_pose();
    test_pose_align();
    test_expression();
    test_identity();
    if (rendered_dir) free_scene(&rendered);
    frig_ctx_free(ctx);
    return test_result("test_sfs");
}
