/* Algorithm 1 (section 4.2) on synthetic data with known answers: low-rank textures and shapes with
 * planted outliers are found in the first rounds, errors are what the definitions say, results do
 * not depend on the BLAS thread count, a trained model scores new faces, and the subject of a
 * multi-face photo is re-chosen as the face the model knows, and with the mirror images in the
 * shape model (filter.mirror) a few faces turned the less common way are kept. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "core/rng.h"
#include "filter/face_reference.h"
#include "filter/face_warp.h"
#include "filter/failure_detection.h"
#include "image/image.h"
#include "testing.h"

enum { N = 60, P = 400, RANK = 5, BAD_TEX = 6, BAD_SHAPE = 6 };

/* Textures: mean + U c + noise, normalized; shapes: the reference (inter-ocular distance 10) plus
 * 4 smooth modes and noise. Photos 0..BAD_TEX-1 get another texture, the next BAD_SHAPE a jaw
 * pushed out by 1.5 units. */
static void make_data(uint64_t seed, double *tex, double *shapes) {
    fr_rng r;
    fr_rng_seed(&r, seed);
    double *U = malloc(sizeof(double) * P * (RANK + 1));
    for (int k = 0; k < P * (RANK + 1); k++) U[k] = fr_rng_normal(&r);
    const double *ref = fr_face_reference_shape();
    double s = FR_FILTER_SHAPE_IOD / hypot(ref[90] - ref[72], ref[91] - ref[73]);
    for (int i = 0; i < N; i++) {
        double *t = tex + (size_t)i * P;
        for (int p = 0; p < P; p++) t[p] = U[p]; /* the mean texture */
        double c[RANK];
        for (int k = 0; k < RANK; k++) c[k] = 0.5 * fr_rng_normal(&r);
        for (int p = 0; p < P; p++) {
            for (int k = 0; k < RANK; k++) t[p] += c[k] * U[p + (k + 1) * P];
            t[p] += 0.05 * fr_rng_normal(&r);
        }
        if (i < BAD_TEX)
            for (int p = 0; p < P; p++) t[p] = fr_rng_normal(&r);
        fr_texture_normalize(P, t);
        double *sh = shapes + (size_t)i * 136, a = fr_rng_normal(&r), b = fr_rng_normal(&r);
        for (int k = 0; k < 68; k++) {
            double u = ref[2 * k], v = ref[2 * k + 1];
            sh[2 * k] = s * (u + 0.2 * a * v * v) + 0.02 * fr_rng_normal(&r);
            sh[2 * k + 1] = s * (v + 0.2 * b * u * v) + 0.02 * fr_rng_normal(&r);
        }
        if (i >= BAD_TEX && i < BAD_TEX + BAD_SHAPE)
            for (int k = 0; k <= 8; k++) sh[2 * k] -= 1.5 * (8 - k) / 8.0;
    }
    free(U);
}

static void test_planted(frig_ctx *ctx) {
    double *tex = malloc(sizeof(double) * P * N), *shapes = malloc(sizeof(double) * 136 * N);
    make_data(1, tex, shapes);
    fr_filter_options opt;
    fr_filter_options_from_ctx(ctx, &opt);
    fr_filter_result res[N], again[N];
    int rounds = 0;
    fr_filter_model model;
    CHECK(fr_failure_detection(ctx, N, P, tex, shapes, &opt, res, &rounds, &model) == FRIG_OK);
    int found = 0, false_drops = 0, early = 1;
    for (int i = 0; i < N; i++) {
        int bad = i < BAD_TEX + BAD_SHAPE;
        found += bad && res[i].round_dropped > 0;
        false_drops += !bad && res[i].round_dropped > 0;
        if (bad) early &= res[i].round_dropped >= 1 && res[i].round_dropped <= 2;
        /* e = w_t texture + w_s shape */
        CHECK_NEAR(res[i].error, opt.w_texture * res[i].texture_error + opt.w_shape * res[i].shape_error, 1e-12);
    }
    printf("synthetic: %d rounds, %d of %d planted dropped, %d good dropped; texture error good %.3f bad %.3f, "
           "shape error good %.3f bad %.3f\n",
           rounds, found, BAD_TEX + BAD_SHAPE, false_drops, res[N - 1].texture_error, res[0].texture_error,
           res[N - 1].shape_error, res[BAD_TEX].shape_error);
    CHECK(found == BAD_TEX + BAD_SHAPE);
    CHECK(early);
    CHECK(false_drops <= 2);
    CHECK(rounds >= 2 && rounds <= opt.max_rounds);
    /* filter.score_all: the same planted photos, judged each round against all photos' spread;
     * the final model's errors are those recorded for every photo, dropped or not. */
    {
        fr_filter_options all = opt;
        all.score_all = 1;
        fr_filter_result r2[N], s2[N];
        fr_filter_model m2;
        int rounds2 = 0, found2 = 0, false2 = 0;
        CHECK(fr_failure_detection(ctx, N, P, tex, shapes, &all, r2, &rounds2, &m2) == FRIG_OK);
        for (int i = 0; i < N; i++) {
            int bad = i < BAD_TEX + BAD_SHAPE;
            found2 += bad && r2[i].round_dropped > 0;
            false2 += !bad && r2[i].round_dropped > 0;
        }
        printf("score_all: %d rounds, %d of %d planted dropped, %d good dropped\n", rounds2, found2,
               BAD_TEX + BAD_SHAPE, false2);
        CHECK(found2 == BAD_TEX + BAD_SHAPE);
        CHECK(false2 <= false_drops);
        CHECK(fr_filter_score(ctx, &m2, N, tex, shapes, s2) == FRIG_OK);
        for (int i = 0; i < N; i++) CHECK_NEAR(s2[i].error, r2[i].error, 1e-9);
        fr_filter_model_free(&m2);
    }
    /* The texture outliers have large texture errors, the shape outliers large shape errors. */
    for (int i = 0; i < BAD_TEX; i++) CHECK(res[i].texture_error > 3 * res[N - 1].texture_error);
    for (int i = BAD_TEX; i < BAD_TEX + BAD_SHAPE; i++) CHECK(res[i].shape_error > 3 * res[N - 1].shape_error);

    /* The model of the inliers scores the photos again like the last round did for the kept ones. */
    fr_filter_result scored[N];
    CHECK(fr_filter_score(ctx, &model, N, tex, shapes, scored) == FRIG_OK);
    for (int i = BAD_TEX + BAD_SHAPE; i < N; i++)
        if (!res[i].round_dropped) CHECK_NEAR(scored[i].error, res[i].error, 1e-9);
    CHECK(model.texture.k >= 1 && model.texture.k <= RANK + 2);
    fr_filter_model_free(&model);

    /* Deterministic: the same bytes again, whatever the context's thread count. (OpenBLAS's own
     * thread count is another matter: its threaded dgemm does not give the same bits.) */
    CHECK(frig_ctx_set_threads(ctx, 1) == FRIG_OK);
    CHECK(fr_failure_detection(ctx, N, P, tex, shapes, &opt, again, NULL, NULL) == FRIG_OK);
    CHECK(frig_ctx_set_threads(ctx, 0) == FRIG_OK);
    int same = 1;
    for (int i = 0; i < N; i++)
        same &= res[i].error == again[i].error && res[i].texture_error == again[i].texture_error &&
                res[i].shape_error == again[i].shape_error && res[i].round_dropped == again[i].round_dropped;
    CHECK(same);

    /* Shapes alone miss the texture outliers; textures alone miss the shape outliers. */
    CHECK(fr_failure_detection(ctx, N, P, NULL, shapes, &opt, again, NULL, NULL) == FRIG_OK);
    int tex_found = 0, shape_found = 0;
    for (int i = 0; i < BAD_TEX; i++) tex_found += again[i].round_dropped > 0;
    for (int i = BAD_TEX; i < BAD_TEX + BAD_SHAPE; i++) shape_found += again[i].round_dropped > 0;
    CHECK(shape_found == BAD_SHAPE);
    CHECK(tex_found <= 1);
    CHECK(again[0].texture_error == 0);
    CHECK(fr_failure_detection(ctx, N, P, tex, NULL, &opt, again, NULL, NULL) == FRIG_OK);
    tex_found = shape_found = 0;
    for (int i = 0; i < BAD_TEX; i++) tex_found += again[i].round_dropped > 0;
    for (int i = BAD_TEX; i < BAD_TEX + BAD_SHAPE; i++) shape_found += again[i].round_dropped > 0;
    CHECK(tex_found == BAD_TEX);
    CHECK(shape_found <= 1);

    /* Arguments. */
    CHECK(fr_failure_detection(ctx, 2, P, tex, shapes, &opt, again, NULL, NULL) == FRIG_ERR_TOO_FEW);
    CHECK(fr_failure_detection(ctx, N, P, NULL, NULL, &opt, again, NULL, NULL) == FRIG_ERR_INVALID_ARGUMENT);
    opt.omega = 0;
    CHECK(fr_failure_detection(ctx, N, P, tex, shapes, &opt, again, NULL, NULL) == FRIG_ERR_INVALID_ARGUMENT);
    free(tex);
    free(shapes);
}

/* A photo with two faces: the model trained on one of them picks it again. */
static void test_choose_face(frig_ctx *ctx) {
    fr_rng r;
    fr_rng_seed(&r, 3);
    frig_image *img = fr_image_new(240, 160, 1);
    /* smooth random content: a sum of a few random blobs */
    double bx[12], by[12], bw[12];
    for (int b = 0; b < 12; b++) bx[b] = 240 * fr_rng_uniform(&r), by[b] = 160 * fr_rng_uniform(&r), bw[b] = 80 * fr_rng_uniform(&r) - 40;
    for (int y = 0; y < 160; y++)
        for (int x = 0; x < 240; x++) {
            double v = 128;
            for (int b = 0; b < 12; b++) v += bw[b] * exp(-((x - bx[b]) * (x - bx[b]) + (y - by[b]) * (y - by[b])) / 400.0);
            img->pixels[(size_t)y * img->stride + x] = (uint8_t)fmin(255, fmax(0, v));
        }
    fr_face_warp *warp = NULL;
    CHECK(fr_face_warp_create(ctx, 32, &warp) == FRIG_OK);
    int texels = fr_face_warp_texels(warp);
    const double *ref = fr_face_reference_shape();
    enum { M = 30 };
    double lm[M * 136], faces[3 * 136];
    double *tex = malloc(sizeof(double) * texels * M), *shapes = malloc(sizeof(double) * 136 * M);
    /* face A near (60, 80), 90 pixels wide, jittered per "photo" */
    for (int i = 0; i < M; i++)
        for (int k = 0; k < 68; k++) {
            lm[i * 136 + 2 * k] = 60 + 90 * ref[2 * k] + 0.8 * fr_rng_normal(&r);
            lm[i * 136 + 2 * k + 1] = 80 + 90 * ref[2 * k + 1] + 0.8 * fr_rng_normal(&r);
        }
    for (int i = 0; i < M; i++) CHECK(fr_face_texture(ctx, warp, img, lm + i * 136, tex + (size_t)i * texels, NULL) == FRIG_OK);
    CHECK(fr_filter_align_shapes(ctx, M, lm, shapes, NULL) == FRIG_OK);
    fr_filter_options opt;
    fr_filter_options_from_ctx(ctx, &opt);
    fr_filter_result res[M];
    fr_filter_model model;
    CHECK(fr_failure_detection(ctx, M, texels, tex, shapes, &opt, res, NULL, &model) == FRIG_OK);
    /* candidates: face B elsewhere, face A, a face on a flat corner (made flat below) */
    for (int k = 0; k < 68; k++) {
        faces[2 * k] = 170 + 80 * ref[2 * k], faces[2 * k + 1] = 75 + 80 * ref[2 * k + 1];
        faces[136 + 2 * k] = 60.5 + 90 * ref[2 * k], faces[136 + 2 * k + 1] = 79.5 + 90 * ref[2 * k + 1];
        faces[272 + 2 * k] = 20 + 20 * ref[2 * k], faces[272 + 2 * k + 1] = 140 + 20 * ref[2 * k + 1];
    }
    for (int y = 125; y < 160; y++) memset(img->pixels + (size_t)y * img->stride, 90, 45);
    int best = -2;
    fr_filter_result scores[3];
    CHECK(fr_filter_choose_face(ctx, &model, warp, img, 3, faces, &best, scores) == FRIG_OK);
    printf("choose face: errors %.3f (other), %.3f (subject), %g (flat); chose %d\n", scores[0].error,
           scores[1].error, scores[2].error, best);
    CHECK(best == 1);
    CHECK(scores[0].error > 2 * scores[1].error);
    CHECK(isinf(scores[2].error));
    fr_filter_model_free(&model);
    fr_face_warp_free(warp);
    frig_image_free(img);
    free(tex);
    free(shapes);
}

/* filter.mirror: a set turned mostly one way. The shapes are a face with depth (cheeks back, nose
 * forward) turned by yaw: 48 photos 15-45 degrees one way, 6 good photos 15-45 degrees the other
 * way, 6 with the eyes, the nose or the mouth placed off. Without the mirror images the few photos
 * turned the other way look like failures; with them they stay and the misplaced features still
 * go. (Six failures that share one pattern, the same feature moved the same way, are not all found
 * with the mirror images: doubled, robust PCA can take them for part of the low-rank set;
 * docs/filter.md.) */
static void test_mirror(frig_ctx *ctx) {
    enum { M = 60, OTHER = 6, MISPLACED = 6 };
    const double *ref = fr_face_reference_shape();
    double *lm = malloc(sizeof(double) * 136 * M), *shapes = malloc(sizeof(double) * 136 * M);
    fr_rng r;
    fr_rng_seed(&r, 11);
    for (int i = 0; i < M; i++) {
        double yaw = (15 + 30 * fr_rng_uniform(&r)) * M_PI / 180 * (i < OTHER ? -1 : 1);
        for (int k = 0; k < 68; k++) {
            double u = ref[2 * k], v = ref[2 * k + 1], z = 0.4 * (1 - 4 * u * u);
            if (k >= 27 && k <= 35) z += 0.25 * (k <= 30 ? (k - 26) / 4.0 : 0.6); /* the nose */
            lm[i * 136 + 2 * k] = 100 + 90 * (u * cos(yaw) + z * sin(yaw)) + 1.5 * fr_rng_normal(&r);
            lm[i * 136 + 2 * k + 1] = 100 + 90 * v + 1.5 * fr_rng_normal(&r);
        }
        if (i >= M - MISPLACED) { /* the eyes, the nose or the mouth placed 10-20 pixels off, one way */
            static const int first[3] = {36, 27, 48}, last[3] = {47, 35, 67};
            double a = 2 * M_PI * fr_rng_uniform(&r), d = 10 + 10 * fr_rng_uniform(&r);
            for (int k = first[i % 3]; k <= last[i % 3]; k++)
                lm[i * 136 + 2 * k] += d * cos(a), lm[i * 136 + 2 * k + 1] += d * sin(a);
        }
    }
    CHECK(fr_filter_align_shapes(ctx, M, lm, shapes, NULL) == FRIG_OK);
    int dropped_other[2] = {0, 0}, dropped_misplaced[2] = {0, 0}, dropped_good[2] = {0, 0};
    for (int mirror = 0; mirror < 2; mirror++) {
        fr_filter_options opt;
        fr_filter_options_from_ctx(ctx, &opt);
        opt.mirror = mirror;
        fr_filter_result res[M];
        CHECK(fr_failure_detection(ctx, M, 0, NULL, shapes, &opt, res, NULL, NULL) == FRIG_OK);
        for (int i = 0; i < M; i++) {
            int d = res[i].round_dropped > 0;
            if (i < OTHER) dropped_other[mirror] += d;
            else if (i >= M - MISPLACED) dropped_misplaced[mirror] += d;
            else dropped_good[mirror] += d;
        }
    }
    printf("mirror: dropped without -> with the mirror images: turned the other way %d -> %d of %d, features misplaced "
           "%d -> %d of %d, the rest %d -> %d\n",
           dropped_other[0], dropped_other[1], OTHER, dropped_misplaced[0], dropped_misplaced[1], MISPLACED, dropped_good[0],
           dropped_good[1]);
    /* measured: 6 -> 0, 6 -> 6, 2 -> 0 */
    CHECK(dropped_other[0] >= 4 && dropped_other[1] <= 1);
    CHECK(dropped_misplaced[0] == MISPLACED && dropped_misplaced[1] == MISPLACED);
    CHECK(dropped_good[1] <= dropped_good[0]);
    free(lm), free(shapes);
}

int main(void) {
    frig_ctx *ctx = frig_ctx_create();
    test_planted(ctx);
    test_choose_face(ctx);
    test_mirror(ctx);
    frig_ctx_free(ctx);
    return test_result("test_failure_detection");
}
