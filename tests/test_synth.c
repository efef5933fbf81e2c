/* Synthetic ground truth (lib/synth, docs/synth.md): the offset lies outside the identity
 * span, truth landmarks land on the rendered head at the truth depth, the detector-like jaw
 * rule, the failure share, decodable images, rig round trips, the fast landmark path, and
 * the same bytes whatever the thread count. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cJSON.h>
#include <frig/frig.h>
#include <frig/synth.h>

#include "linalg/linalg.h"
#include "model_fixture.h"
#include "synth/synth.h"
#include "testing.h"

#define SIDE 160 /* small photos keep the test fast */

static frig_ctx *ctx;
static frig_model *model;

static void small_photos(void) {
    CHECK(frig_ctx_set_param(ctx, FRIG_PARAM_SYNTH_IMAGE_SIZE, SIDE) == FRIG_OK);
    CHECK(frig_ctx_set_param(ctx, FRIG_PARAM_SYNTH_RIG_OBJ, 0) == FRIG_OK);
}

/* Over the face region, the least-squares projection of (true neutral - model(identity)) onto
 * the identity modes explains (almost) none of it; its RMS is the reported figure. */
static void test_offset_outside_span(const frig_synth_subject *s) {
    const frig_rig *rig = frig_synth_subject_rig(s);
    int nv = frig_model_vertex_count(model), K = frig_model_identity_count(model), first, count;
    CHECK(fr_synth_region(model, "face", &first, &count));
    const double *w;
    CHECK(frig_synth_subject_identity(s, &w) == K);
    float *mean = malloc(sizeof *mean * 3 * (size_t)nv);
    CHECK(frig_model_eval(ctx, model, w, NULL, mean) == FRIG_OK);
    int n = 3 * count;
    double *r = malloc(sizeof *r * (size_t)n), *G = calloc((size_t)K * K, sizeof *G), *b = calloc((size_t)K, sizeof *b);
    for (int i = 0; i < n; i++) r[i] = (double)frig_rig_neutral(rig)[3 * first + i] - mean[3 * first + i];
    const float *U = frig_model_identity_modes(model);
    for (int a = 0; a < K; a++) {
        const float *ua = U + 3 * (size_t)nv * a + 3 * first;
        for (int i = 0; i < n; i++) b[a] += ua[i] * r[i];
        for (int c = 0; c <= a; c++) {
            const float *uc = U + 3 * (size_t)nv * c + 3 * first;
            double g = 0.0;
            for (int i = 0; i < n; i++) g += (double)ua[i] * uc[i];
            G[a * K + c] = G[c * K + a] = g;
        }
    }
    double *x = malloc(sizeof *x * K);
    memcpy(x, b, sizeof *x * K);
    CHECK(fr_solve_spd(ctx, K, 1, G, K, x, K) == FRIG_OK);
    double energy = 0.0, explained = 0.0;
    for (int i = 0; i < n; i++) energy += r[i] * r[i];
    for (int a = 0; a < K; a++) explained += x[a] * b[a]; /* |P r|^2 = b^T G^-1 b */
    double rms_mm = 1e3 * sqrt(energy / count);
    printf("offset: out-of-span RMS %.3f mm (reported %.3f), identity modes explain %.2e of its energy\n", rms_mm,
           frig_synth_subject_offset_rms_mm(s), explained / energy);
    CHECK(explained / energy < 1e-3);
    CHECK_NEAR(rms_mm, frig_synth_subject_offset_rms_mm(s), 0.01 * rms_mm);
    CHECK(rms_mm > 0.5 && rms_mm < frig_ctx_get_param(ctx, FRIG_PARAM_SYNTH_OFFSET_MM));
    CHECK_NEAR(s->offset_raw_rms_mm, frig_ctx_get_param(ctx, FRIG_PARAM_SYNTH_OFFSET_MM), 1e-9);
    free(mean), free(r), free(G), free(b), free(x);
}

/* d_j' = (1 + a_j) d_j + s_j: rigid parts scaled exactly, the rest close to the template. */
static void test_expressions(const frig_synth_subject *s) {
    const frig_rig *rig = frig_synth_subject_rig(s);
    int nv = frig_model_vertex_count(model), eye0, neye, changed = 0;
    CHECK(fr_synth_region(model, "eyeball_left", &eye0, &neye));
    for (int j = 0; j < frig_rig_shape_count(rig); j++) {
        const float *d = frig_model_expression_deltas(model) + 3 * (size_t)nv * j, *e = frig_rig_shape_deltas(rig, j);
        double a = s->shape_scale[j], worst = 0.0, num = 0.0, den = 0.0;
        CHECK(fabs(a) <= 0.25);
        for (int i = 3 * eye0; i < 3 * (eye0 + neye); i++) worst = fmax(worst, fabs(e[i] - (1.0 + a) * d[i]));
        CHECK(worst < 1e-7);
        for (int i = 0; i < 3 * nv; i++) num += (e[i] - d[i]) * (e[i] - d[i]), den += (double)d[i] * d[i];
        double rel = sqrt(num / den);
        changed += rel > 0.01;
        CHECK(rel < 0.6);
    }
    CHECK(changed > frig_rig_shape_count(rig) / 2);
}

static void test_subject_determinism(const frig_synth_subject *s) {
    frig_synth_subject *same = NULL, *other = NULL;
    CHECK(frig_synth_subject_create(ctx, model, 1234, &same) == FRIG_OK);
    CHECK(frig_synth_subject_create(ctx, model, 1235, &other) == FRIG_OK);
    size_t n = 3 * (size_t)frig_model_vertex_count(model);
    const frig_rig *a = frig_synth_subject_rig(s), *b = frig_synth_subject_rig(same), *c = frig_synth_subject_rig(other);
    CHECK(memcmp(frig_rig_neutral(a), frig_rig_neutral(b), n * sizeof(float)) == 0);
    CHECK(memcmp(frig_rig_shape_deltas(a, 5), frig_rig_shape_deltas(b, 5), n * sizeof(float)) == 0);
    CHECK(memcmp(s->albedo, same->albedo, 3 * (size_t)s->nv_render * sizeof(float)) == 0);
    CHECK(memcmp(frig_rig_neutral(a), frig_rig_neutral(c), n * sizeof(float)) != 0);
    frig_synth_subject_free(same);
    frig_synth_subject_free(other);
}

static void test_rig_round_trip(const frig_synth_subject *s) {
    const char *dir = test_temp_dir("synth_rig");
    char path[8600];
    snprintf(path, sizeof path, "%s/rig.frigrig", dir);
    const frig_rig *rig = frig_synth_subject_rig(s);
    frig_rig *back = NULL;
    CHECK(frig_rig_save(ctx, rig, path) == FRIG_OK);
    CHECK(frig_rig_load(ctx, path, &back) == FRIG_OK);
    if (!back) return;
    size_t n = 3 * (size_t)frig_rig_vertex_count(rig);
    CHECK(frig_rig_shape_count(back) == frig_rig_shape_count(rig));
    CHECK(memcmp(frig_rig_neutral(back), frig_rig_neutral(rig), n * sizeof(float)) == 0);
    for (int k = 0; k < frig_rig_shape_count(rig); k++) {
        CHECK(strcmp(frig_rig_shape_name(back, k), frig_rig_shape_name(rig, k)) == 0);
        CHECK(memcmp(frig_rig_shape_deltas(back, k), frig_rig_shape_deltas(rig, k), n * sizeof(float)) == 0);
    }
    frig_rig_free(back);
}

/* Camera coordinates of vertex v of the rig posed as the truth says. */
static void posed_vertex(const frig_rig *rig, const frig_synth_truth *t, int v, double xc[3]) {
    const double *w = frig_synth_truth_expression(t);
    double x[3], R[9], tr[3];
    for (int i = 0; i < 3; i++) {
        x[i] = frig_rig_neutral(rig)[3 * v + i];
        for (int k = 0; k < frig_rig_shape_count(rig); k++) x[i] += w[k] * frig_rig_shape_deltas(rig, k)[3 * v + i];
    }
    frig_synth_truth_pose(t, R, tr);
    for (int i = 0; i < 3; i++) xc[i] = R[3 * i] * x[0] + R[3 * i + 1] * x[1] + R[3 * i + 2] * x[2] + tr[i];
}

/* The projections in the truth are those of the posed vertices; the nose tip lands on a
 * covered pixel whose truth depth is the vertex's (to the pixel grid's rounding). */
static void test_truth_matches_render(const frig_synth_subject *s) {
    const frig_rig *rig = frig_synth_subject_rig(s);
    const int32_t *lmv = frig_model_landmarks(model);
    int checked = 0;
    double worst_uv = 0.0, worst_z = 0.0;
    for (uint64_t seed = 100; seed < 112; seed++) {
        frig_image *img = NULL;
        frig_synth_truth *t = NULL;
        CHECK(frig_synth_render(ctx, s, seed, FRIG_SYNTH_FAILURE_NONE, &img, &t) == FRIG_OK);
        if (!t) continue;
        CHECK(frig_image_width(img) == SIDE && frig_image_height(img) == SIDE && frig_image_channels(img) == 3);
        const double *lm = frig_synth_truth_landmarks(t, 0);
        double f, cx, cy;
        frig_synth_truth_camera(t, &f, &cx, &cy);
        for (int k = 0; k < FR_SYNTH_LANDMARKS; k++) {
            double xc[3];
            posed_vertex(rig, t, lmv[k], xc);
            worst_uv = fmax(worst_uv, hypot(f * xc[0] / xc[2] + cx - lm[2 * k], f * xc[1] / xc[2] + cy - lm[2 * k + 1]));
        }
        int w, h;
        const float *depth = frig_synth_truth_depth(t, &w, &h);
        double xc[3];
        posed_vertex(rig, t, lmv[30], xc);
        int x = (int)lround(lm[60]), y = (int)lround(lm[61]);
        if (frig_synth_truth_visible(t)[30] && x >= 0 && y >= 0 && x < w && y < h) {
            float z = depth[y * w + x];
            CHECK(z > 0.0f);
            /* one pixel at this distance is f / z pixels per metre; the nose is steep */
            double tol = 0.002 + 2.0 * xc[2] / f;
            worst_z = fmax(worst_z, fabs(z - xc[2]) / tol);
            checked++;
        }
        frig_image_free(img);
        frig_synth_truth_free(t);
    }
    printf("truth vs render: %d nose tips checked, projections within %.2g px, depth within %.2f of tolerance\n",
           checked, worst_uv, worst_z);
    CHECK(checked >= 8);
    CHECK(worst_uv < 1e-3);
    CHECK(worst_z <= 1.0);
}

/* The fast path gives the render's landmark truth, byte for byte; the jaw rule leaves frontal
 * points near the vertices and puts a turned face's far side on a silhouette. */
static void test_landmarks(const frig_synth_subject *s) {
    for (int failure = 0; failure <= FR_SYNTH_FAILURE_KINDS; failure++) {
        if (failure == FRIG_SYNTH_FAILURE_NO_FACE) continue;
        fr_synth_photo p;
        fr_synth_photo_draw(s, 77 + failure, SIDE, SIDE, failure, 60, 0.1, &p);
        fr_synth_landmarks fast;
        frig_synth_truth *t = NULL;
        CHECK(fr_synth_landmarks_only(ctx, s, &p, &fast) == FRIG_OK);
        CHECK(fr_synth_render_photo(ctx, s, &p, NULL, &t) == FRIG_OK);
        if (!t) continue;
        CHECK(memcmp(&fast, &t->lm, sizeof fast) == 0);
        if (failure == FRIG_SYNTH_FAILURE_OCCLUDER || failure == FRIG_SYNTH_FAILURE_SUNGLASSES) {
            int hidden = 0;
            for (int k = 0; k < FR_SYNTH_LANDMARKS; k++)
                hidden += !t->lm.visible[k] && fr_synth_occluded(&t->photo, t->lm.detector[2 * k], t->lm.detector[2 * k + 1]);
            CHECK(hidden >= 4);
        }
        frig_synth_truth_free(t);
    }
    double frontal = 0.0;
    int far_moved = 0, near_moved = 0;
    for (int turn = 0; turn < 2; turn++) {
        fr_synth_photo p;
        fr_synth_photo_draw(s, 500, 256, 256, FRIG_SYNTH_FAILURE_NONE, 60, 0.0, &p);
        p.yaw = turn ? 45.0 : 0.0, p.pitch = p.roll = 0.0;
        fr_rotation_from_euler(p.yaw * M_PI / 180.0, 0.0, 0.0, p.R);
        fr_synth_landmarks lm;
        CHECK(fr_synth_landmarks_only(ctx, s, &p, &lm) == FRIG_OK);
        for (int k = 0; k < 17; k++) {
            double d = hypot(lm.detector[2 * k] - lm.exact[2 * k], lm.detector[2 * k + 1] - lm.exact[2 * k + 1]);
            if (!turn) frontal = fmax(frontal, d);
            else if (k > 8) far_moved += lm.jaw_moved[k]; /* yaw > 0 turns the subject's left side away */
            else if (k >= 4) near_moved += lm.jaw_moved[k]; /* the near jaw line below the cheek */
        }
    }
    printf("jaw rule: frontal points within %.2f px of their vertices; at 45 deg %d far-side points and %d of the "
           "near side's lower ones moved\n", frontal, far_moved, near_moved);
    CHECK(frontal < 3.0);
    CHECK(far_moved >= 4);
    CHECK(near_moved <= 1);
}

/* Luminance (0-255 scale, sRGB-encoded values) of pixel i. */
static double lum(const frig_image *img, size_t i) {
    const uint8_t *px = frig_image_pixels(img) + 3 * i;
    return 0.2126 * px[0] + 0.7152 * px[1] + 0.0722 * px[2];
}

/* Cast shadows darken exactly the pixels the class map calls shadow (and change little
 * elsewhere); highlights brighten the ones it calls highlight; the sunglasses cover the eyes;
 * the exposure failures darken or blow out the face; HEAD agrees with the depth map. */
static void test_effects(const frig_synth_subject *s) {
    const int side = 256;
    fr_synth_photo p;
    fr_synth_photo_draw(s, 4242, side, side, FRIG_SYNTH_FAILURE_NONE, 0, 0.0, &p);
    double d[3] = {0.75, -0.45, -0.5}, len = sqrt(0.75 * 0.75 + 0.45 * 0.45 + 0.25); /* from the side and above */
    for (int c = 0; c < 3; c++) {
        for (int i = 0; i < 3; i++) p.light_dir[i] = d[i] / len;
        p.direct_rgb[c] = 0.9;
        fr_sh_irradiance_coeffs(p.light_dir, 0.9, 0.25, p.sh[c]);
        fr_sh_irradiance_coeffs(p.light_dir, 0.9, 0.0, p.sh_direct[c]);
    }
    p.shadows = 0, p.spec_ks = 0.0, p.spec_shininess = 20.0;
    frig_image *plain = NULL, *shadowed = NULL, *shiny = NULL;
    frig_synth_truth *t0 = NULL, *t1 = NULL, *t2 = NULL;
    CHECK(fr_synth_render_photo(ctx, s, &p, &plain, &t0) == FRIG_OK);
    p.shadows = 1;
    CHECK(fr_synth_render_photo(ctx, s, &p, &shadowed, &t1) == FRIG_OK);
    p.shadows = 0, p.spec_ks = 0.3;
    CHECK(fr_synth_render_photo(ctx, s, &p, &shiny, &t2) == FRIG_OK);
    if (!plain || !shadowed || !shiny) goto done;
    size_t n = (size_t)side * side;
    int shadow = 0, darker = 0, other = 0, same = 0, high = 0, brighter = 0, head = 0, agree = 0;
    for (size_t i = 0; i < n; i++) {
        uint8_t m = t1->mask[i];
        int is_head = t0->depth[i] > 0.0f;
        head += is_head, agree += is_head == ((m & FRIG_SYNTH_PIXEL_HEAD) != 0);
        CHECK(!(t0->mask[i] & FRIG_SYNTH_PIXEL_SHADOW)); /* no shadows without them */
        if (m & FRIG_SYNTH_PIXEL_SHADOW) shadow++, darker += lum(shadowed, i) < 0.95 * lum(plain, i);
        else if (m & FRIG_SYNTH_PIXEL_HEAD) other++, same += fabs(lum(shadowed, i) - lum(plain, i)) <= 1.5 + 0.08 * lum(plain, i);
        if (t2->mask[i] & FRIG_SYNTH_PIXEL_HIGHLIGHT) high++, brighter += lum(shiny, i) > lum(plain, i) + 2.0;
    }
    printf("effects: %d cast-shadow pixels (%d darker by 5%%+), %d of %d other head pixels within 8%%; %d highlight "
           "pixels (%d brighter); HEAD agrees with the depth map on %d of %d+ pixels\n",
           shadow, darker, same, other, high, brighter, agree, head);
    CHECK(shadow >= 50 && darker >= 0.9 * shadow);
    CHECK(same >= 0.95 * other);
    CHECK(high >= 20 && brighter >= 0.9 * high);
    CHECK(agree >= (int)n - (int)(0.05 * head));
    frig_image_free(plain), frig_image_free(shadowed), frig_image_free(shiny);
    frig_synth_truth_free(t0), frig_synth_truth_free(t1), frig_synth_truth_free(t2);
    plain = shadowed = shiny = NULL;
    t0 = t1 = t2 = NULL;

    /* Exposure failures against the same photo well exposed; sunglasses over the eyes. */
    int kinds[3] = {FRIG_SYNTH_FAILURE_UNDEREXPOSED, FRIG_SYNTH_FAILURE_OVEREXPOSED, FRIG_SYNTH_FAILURE_SUNGLASSES};
    fr_synth_photo_draw(s, 99, side, side, FRIG_SYNTH_FAILURE_NONE, 20, 0.0, &p);
    CHECK(fr_synth_render_photo(ctx, s, &p, &plain, &t0) == FRIG_OK);
    for (int k = 0; k < 3 && plain; k++) {
        fr_synth_photo q;
        fr_synth_photo_draw(s, 99, side, side, kinds[k], 20, 0.0, &q);
        frig_image *img = NULL;
        frig_synth_truth *t = NULL;
        CHECK(fr_synth_render_photo(ctx, s, &q, &img, &t) == FRIG_OK);
        if (!img) continue;
        double face = 0.0, face0 = 0.0;
        int faces = 0, clipped = 0, eyes_hidden = 0;
        for (size_t i = 0; i < n; i++) {
            if (!(t->mask[i] & FRIG_SYNTH_PIXEL_SKIN)) continue;
            const uint8_t *px = frig_image_pixels(img) + 3 * i;
            faces++, face += lum(img, i), face0 += lum(plain, i);
            clipped += px[0] == 255 || px[1] == 255 || px[2] == 255;
        }
        for (int e = 36; e < 48; e++) {
            int x = (int)lround(t->lm.exact[2 * e]), y = (int)lround(t->lm.exact[2 * e + 1]);
            if (x >= 0 && y >= 0 && x < side && y < side)
                eyes_hidden += (t->mask[(size_t)y * side + (size_t)x] & FRIG_SYNTH_PIXEL_OCCLUDED) != 0;
        }
        printf("%s: skin luminance %.1f (well exposed %.1f), %d of %d skin pixels clipped, %d of 12 eye points "
               "under the glasses\n", frig_synth_failure_name(kinds[k]), face / faces, face0 / faces, clipped, faces,
               eyes_hidden);
        if (k == 0) CHECK(face < 0.35 * face0);
        if (k == 1) CHECK(clipped >= 0.5 * faces);
        if (k == 2) CHECK(eyes_hidden == 12);
        frig_image_free(img);
        frig_synth_truth_free(t);
    }
done:
    frig_image_free(plain), frig_image_free(shadowed), frig_image_free(shiny);
    frig_synth_truth_free(t0), frig_synth_truth_free(t1), frig_synth_truth_free(t2);
}

static double json_number(const cJSON *o, const char *key) {
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(o, key);
    return cJSON_IsNumber(v) ? v->valuedouble : NAN;
}

static cJSON *read_json(const char *dir, const char *rel) {
    char path[8600];
    snprintf(path, sizeof path, "%s/%s", dir, rel);
    size_t n;
    unsigned char *text = test_read_file(path, &n);
    cJSON *j = text ? cJSON_ParseWithLength((const char *)text, n) : NULL;
    free(text);
    CHECK(j != NULL);
    return j;
}

/* Every file of the data set, byte for byte. */
static int same_tree(const char *a, const char *b) {
    char cmd[8600];
    snprintf(cmd, sizeof cmd, "diff -r -q '%s' '%s' >/dev/null", a, b);
    return system(cmd) == 0;
}

/* Failure share, failure truths, decodable images of the right size, the rig file. */
static void check_dataset(const char *dir, int photos, double rate) {
    cJSON *index = read_json(dir, "index.json");
    const cJSON *subj = cJSON_GetArrayItem(cJSON_GetObjectItemCaseSensitive(index, "subjects"), 0);
    const cJSON *list = cJSON_GetObjectItemCaseSensitive(subj, "photos"), *ph;
    CHECK(cJSON_GetArraySize(list) == photos);
    int failures = 0, kinds[FR_SYNTH_FAILURE_KINDS + 1] = {0};
    cJSON_ArrayForEach(ph, list) {
        const char *kind = cJSON_GetObjectItemCaseSensitive(ph, "failure")->valuestring;
        int k = 0;
        while (k <= FR_SYNTH_FAILURE_KINDS && strcmp(frig_synth_failure_name(k), kind) != 0) k++;
        CHECK(k <= FR_SYNTH_FAILURE_KINDS);
        if (k > FR_SYNTH_FAILURE_KINDS) continue;
        kinds[k]++, failures += k != 0;
        cJSON *t = read_json(dir, cJSON_GetObjectItemCaseSensitive(ph, "truth")->valuestring);
        const cJSON *lm = cJSON_GetObjectItemCaseSensitive(t, "landmarks");
        CHECK((k == FRIG_SYNTH_FAILURE_NO_FACE) == (lm == NULL));
        if (k == FRIG_SYNTH_FAILURE_EXTREME_POSE)
            CHECK(fabs(json_number(cJSON_GetObjectItemCaseSensitive(t, "pose"), "yaw_deg")) >= 75.0);
        CHECK((k == FRIG_SYNTH_FAILURE_OCCLUDER) == cJSON_IsObject(cJSON_GetObjectItemCaseSensitive(t, "occluder")));
        CHECK((k == FRIG_SYNTH_FAILURE_SUNGLASSES) == cJSON_IsObject(cJSON_GetObjectItemCaseSensitive(t, "sunglasses")));
        const cJSON *mask = cJSON_GetObjectItemCaseSensitive(t, "mask");
        char mpath[8600];
        const char *tname = cJSON_GetObjectItemCaseSensitive(ph, "truth")->valuestring, *slash = strrchr(tname, '/');
        snprintf(mpath, sizeof mpath, "%s/%.*s/%s", dir, (int)(slash ? slash - tname : 0), tname,
                 cJSON_GetStringValue(cJSON_GetObjectItemCaseSensitive(mask, "file")));
        size_t msize = 0;
        unsigned char *mbytes = test_read_file(mpath, &msize);
        CHECK(mbytes && msize == (size_t)SIDE * SIDE);
        free(mbytes);
        char path[8600];
        snprintf(path, sizeof path, "%s/%s", dir, cJSON_GetObjectItemCaseSensitive(ph, "photo")->valuestring);
        frig_image *img = NULL;
        CHECK(frig_image_load(ctx, path, FRIG_LOAD_DEFAULT, &img) == FRIG_OK);
        CHECK(img && frig_image_width(img) == SIDE && frig_image_height(img) == SIDE);
        frig_image_free(img);
        cJSON_Delete(t);
    }
    printf("data set: %d photos, %d failures (%d occluder, %d extreme pose, %d no face, %d sunglasses, %d dark, %d "
           "blown out)\n", photos, failures, kinds[1], kinds[2], kinds[3], kinds[4], kinds[5], kinds[6]);
    CHECK(failures == (int)lround(rate * photos));
    for (int k = 1; k <= FR_SYNTH_FAILURE_KINDS; k++) CHECK(kinds[k] >= failures / FR_SYNTH_FAILURE_KINDS);
    char path[8600];
    snprintf(path, sizeof path, "%s/subject_00/rig/rig.frigrig", dir);
    frig_rig *rig = NULL;
    CHECK(frig_rig_load(ctx, path, &rig) == FRIG_OK);
    CHECK(rig && frig_rig_shape_count(rig) == frig_model_expression_count(model));
    frig_rig_free(rig);
    cJSON_Delete(index);
}

/* synth.one_light: two photos of a subject share its one light (direction, ambient, colour and
 * exposure in sh), nothing else of them changes; a photo has a light of its own otherwise. */
static void test_one_light(const frig_synth_subject *s) {
    fr_synth_photo a, b, a0;
    fr_synth_photo_draw(s, 11, 128, 128, FRIG_SYNTH_FAILURE_NONE, 60, 0.0, &a);
    fr_synth_photo_draw(s, 12, 128, 128, FRIG_SYNTH_FAILURE_NONE, 60, 0.0, &b);
    a0 = a;
    CHECK(memcmp(a.sh, b.sh, sizeof a.sh) != 0);
    fr_synth_photo_one_light(s, &a);
    fr_synth_photo_one_light(s, &b);
    CHECK(memcmp(a.sh, b.sh, sizeof a.sh) == 0 && memcmp(a.light_dir, b.light_dir, sizeof a.light_dir) == 0);
    CHECK(a.exposure == b.exposure && memcmp(a.sh_direct, b.sh_direct, sizeof a.sh_direct) == 0);
    CHECK(memcmp(a.sh, a0.sh, sizeof a.sh) != 0);
    CHECK(a.yaw == a0.yaw && a.pitch == a0.pitch && memcmp(a.R, a0.R, sizeof a.R) == 0 && a.seed == a0.seed);
}

static void test_dataset(void) {
    const int photos = 24;
    const double rate = 0.25;
    CHECK(frig_ctx_set_param(ctx, FRIG_PARAM_SYNTH_FAILURE_RATE, rate) == FRIG_OK);
    char one[4200], two[4200];
    snprintf(one, sizeof one, "%s", test_temp_dir("synth_t1"));
    snprintf(two, sizeof two, "%s", test_temp_dir("synth_t2"));
    CHECK(frig_ctx_set_threads(ctx, 1) == FRIG_OK);
    CHECK(frig_synth_dataset(ctx, model, one, 1, photos, 42) == FRIG_OK);
    CHECK(frig_ctx_set_threads(ctx, 2) == FRIG_OK);
    CHECK(frig_synth_dataset(ctx, model, two, 1, photos, 42) == FRIG_OK);
    CHECK(same_tree(one, two));
    check_dataset(one, photos, rate);
    CHECK(frig_ctx_set_param(ctx, FRIG_PARAM_SYNTH_FAILURE_RATE, 0.1) == FRIG_OK);
}

/* SH irradiance: exact toward the light, close to ambient + clamped cosine elsewhere. */
static void test_sh(void) {
    double d[3] = {0.3, -0.5, -0.81}, len = sqrt(0.09 + 0.25 + 0.6561), c[9], y[9], worst = 0.0;
    for (int i = 0; i < 3; i++) d[i] /= len;
    fr_sh_irradiance_coeffs(d, 0.7, 0.3, c);
    fr_sh_basis(d, y);
    double e = 0.0;
    for (int k = 0; k < 9; k++) e += c[k] * y[k];
    CHECK_NEAR(e, 1.0, 1e-12);
    fr_rng rng;
    fr_rng_seed(&rng, 9);
    for (int i = 0; i < 1000; i++) {
        double n[3] = {fr_rng_normal(&rng), fr_rng_normal(&rng), fr_rng_normal(&rng)};
        double l = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]), dot = 0.0;
        for (int k = 0; k < 3; k++) n[k] /= l, dot += n[k] * d[k];
        fr_sh_basis(n, y);
        e = 0.0;
        for (int k = 0; k < 9; k++) e += c[k] * y[k];
        worst = fmax(worst, fabs(e - (0.3 + 0.7 * fmax(0.0, dot))));
    }
    printf("SH irradiance: within %.3f of ambient + clamped cosine (direct 0.7)\n", worst);
    CHECK(worst < 0.1 * 0.7);
}

int main(void) {
    ctx = frig_ctx_create();
    test_sh();
    model = fixture_model(ctx);
    if (!model) {
        frig_ctx_free(ctx);
        return test_skip("the ICT-FaceKit model (../shared/ict-facekit) is not available");
    }
    small_photos();
    frig_synth_subject *s = NULL;
    CHECK(frig_synth_subject_create(ctx, model, 1234, &s) == FRIG_OK);
    if (s) {
        test_offset_outside_span(s);
        test_expressions(s);
        test_subject_determinism(s);
        test_rig_round_trip(s);
        test_truth_matches_render(s);
        test_landmarks(s);
        test_effects(s);
        test_one_light(s);
    }
    frig_synth_subject_free(s);
    test_dataset();
    frig_model_free(model);
    frig_ctx_free(ctx);
    return test_result("test_synth");
}
