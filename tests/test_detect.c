/* The detect stage (include/frig/detect.h): missing data files name their Debian package; the
 * merge and subject rules on made-up boxes; user landmark files; on real photos, boxes and
 * landmarks against dlib's own pipeline (dlib_ref, built on the fly) and NME on the iBUG
 * ground truth; no face on non-face photos; the profile fallback; detection on a downscaled
 * copy; identical results from concurrent calls; the photo set's statuses (unreadable, empty,
 * tiny face, user landmarks) identical whatever the thread count. */
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "detect/cascade.h"
#include "detect/detector.h"
#include "frig/detect.h"
#include "frig/photoset.h"
#include "image/image.h"
#include "io/file.h"
#include "landmark_ref.h"
#include "testing.h"

#define MAX_FACES 16

/* Tolerances, from the values this test prints (and bench/detect_end_to_end.sh over all photos:
 * mean distance to dlib's points 0.0165 of the eye distance, NME 0.030 where dlib finds the
 * face too), with room for other builds' rounding: */
#define TOL_IOU 0.70      /* our calibrated box vs dlib's HOG box of the same face, worst face (0.80) */
#define TOL_NME_MEAN 0.03 /* our points vs dlib's pipeline, / dlib's outer-eye distance, mean (0.013) */
#define TOL_NME_MAX 0.05  /* the same, worst face (0.021) */
#define TOL_GT_MEAN 0.04  /* NME on the iBUG ground truth, mean of 5 faces (0.032) */
#define TOL_GT_MAX 0.065  /* worst of them (0.052) */

static frig_ctx *ctx;
static frig_detector *det;

typedef struct found {
    size_t n;
    double boxes[4 * MAX_FACES], scores[MAX_FACES], lm[136 * MAX_FACES];
    int sources[MAX_FACES];
} found;

static frig_status detect(frig_ctx *c, const frig_detector *d, const frig_image *img, found *f) {
    memset(f, 0, sizeof *f);
    frig_status st = frig_detect_faces(c, d, img, MAX_FACES, &f->n, f->boxes, f->scores, f->sources, f->lm);
    if (f->n > MAX_FACES) f->n = MAX_FACES;
    return st;
}

static frig_image *load(const char *rel, unsigned flags) {
    frig_image *img = NULL;
    if (frig_image_load(ctx, test_shared_path(rel), flags, &img)) {
        fprintf(stderr, "%s: %s\n", rel, frig_ctx_errmsg(ctx));
        test_failures++;
    }
    return img;
}

/* ---- no data needed ---- */

static void test_missing_files(void) {
    frig_detector *d = NULL;
    CHECK(frig_detector_create(ctx, "/nonexistent-frig-dir", NULL, &d) == FRIG_ERR_NOT_FOUND && !d);
    CHECK(strstr(frig_ctx_errmsg(ctx), "opencv-data") != NULL);
    CHECK(strstr(frig_ctx_errmsg(ctx), FR_DETECT_FRONTAL_FILE) != NULL);
    CHECK(frig_detector_create(ctx, NULL, "/nonexistent-frig-dir/model.dat", &d) == FRIG_ERR_NOT_FOUND && !d);
    CHECK(strstr(frig_ctx_errmsg(ctx), "libdlib-data") != NULL);
    CHECK(strstr(frig_ctx_errmsg(ctx), "/nonexistent-frig-dir/model.dat") != NULL);
}

static fr_detected_face face(int source, double score, double x, double y, double w, double h) {
    fr_detected_face f;
    memset(&f, 0, sizeof f);
    f.source = source;
    f.score = score;
    f.box[0] = x, f.box[1] = y, f.box[2] = w, f.box[3] = h;
    return f;
}

static void test_merge_and_subject(void) {
    fr_detected_face v[5] = {
        face(FRIG_FACE_PROFILE, 9, 0, 0, 100, 100),           /* overlaps the frontal face: dropped */
        face(FRIG_FACE_PROFILE_MIRRORED, 9, 300, 0, 80, 80),  /* overlaps the profile face below: dropped */
        face(FRIG_FACE_FRONTAL, 3, 10, 10, 100, 100),
        face(FRIG_FACE_PROFILE, 2, 305, 5, 80, 80),
        face(FRIG_FACE_PROFILE_MIRRORED, 4, 150, 300, 20, 20), /* alone: kept */
    };
    size_t n = fr_detect_merge(v, 5);
    CHECK(n == 3);
    CHECK(v[0].source == FRIG_FACE_FRONTAL && v[0].box[0] == 10);
    CHECK(v[1].source == FRIG_FACE_PROFILE && v[1].box[0] == 305);
    CHECK(v[2].source == FRIG_FACE_PROFILE_MIRRORED && v[2].box[0] == 150);
    fr_detected_face nested[2] = {face(FRIG_FACE_FRONTAL, 5, 0, 0, 200, 200), face(FRIG_FACE_PROFILE, 5, 20, 20, 60, 60)};
    CHECK(fr_detect_merge(nested, 2) == 1); /* IoU 0.09 but inside the frontal box */
    CHECK_NEAR(fr_box_iou(v[0].box, v[0].box), 1.0, 1e-12);

    /* Subject: a large face in the corner against a slightly smaller central one. */
    fr_detected_face s[2] = {face(FRIG_FACE_FRONTAL, 3, 0, 0, 100, 100), face(FRIG_FACE_FRONTAL, 3, 150, 100, 90, 90)};
    CHECK_NEAR(fr_subject_score(s[0].box, 400, 300), 100 * (1 - 0.5 * hypot(150, 100) / 250), 1e-9);
    for (int k = 0; k < 2; k++) { /* eyes 30 px apart */
        s[k].landmarks[72] = s[k].box[0] + 20, s[k].landmarks[73] = s[k].box[1] + 30;
        s[k].landmarks[90] = s[k].box[0] + 50, s[k].landmarks[91] = s[k].box[1] + 30;
    }
    int small = -1;
    CHECK(fr_choose_subject(s, 2, 400, 300, 15, &small) == 1 && small == 0);
    CHECK(fr_choose_subject(s, 2, 400, 300, 31, &small) == 1 && small == 1); /* both too small: best, flagged */
    s[1].landmarks[90] = s[1].box[0] + 30; /* central face's eyes 10 px apart: the corner face wins */
    CHECK(fr_choose_subject(s, 2, 400, 300, 15, &small) == 0 && small == 0);
    CHECK(fr_choose_subject(s, 0, 400, 300, 15, &small) == -1 && small == 0);
}

static void write_text(const char *path, const char *text) {
    CHECK(fr_write_file_atomic(ctx, path, text, strlen(text)) == FRIG_OK);
}

static void pts_text(char *buf, size_t size, const double *lm, double shift) {
    size_t k = (size_t)snprintf(buf, size, "version: 1\nn_points:  68\n{\n");
    for (int i = 0; i < 68 && k < size; i++)
        k += (size_t)snprintf(buf + k, size - k, "%.3f %.3f\n", lm[2 * i] + shift, lm[2 * i + 1] + shift);
    if (k < size) snprintf(buf + k, size - k, "}\n");
}

static void json_text(char *buf, size_t size, const double *lm, int faces) {
    size_t k = (size_t)snprintf(buf, size, faces ? "{\"faces\": [{\"landmarks\": [" : "{\"landmarks\": [");
    for (int i = 0; i < 68 && k < size; i++)
        k += (size_t)snprintf(buf + k, size - k, "%s[%.3f, %.3f]", i ? ", " : "", lm[2 * i], lm[2 * i + 1]);
    if (k < size) snprintf(buf + k, size - k, faces ? "]}, {\"landmarks\": []}]}" : "]}");
}

static void test_user_files(void) {
    const char *dir = test_temp_dir("detect_user");
    char photo[4200], path[4300], text[8192];
    double lm[136];
    for (int i = 0; i < 68; i++) lm[2 * i] = 100 + 2 * i, lm[2 * i + 1] = 50 + (i % 17);
    fr_detected_face *v = NULL;
    size_t n = 0;
    char *file = NULL;
    snprintf(photo, sizeof photo, "%s/a.photo.jpg", dir);
    CHECK(fr_user_landmarks(ctx, photo, &v, &n, &file) == FRIG_OK && n == 0 && !file); /* none there */
    snprintf(path, sizeof path, "%s/a.photo.pts", dir);
    pts_text(text, sizeof text, lm, 1.0);
    write_text(path, text);
    CHECK(fr_user_landmarks(ctx, photo, &v, &n, &file) == FRIG_OK && n == 1 && file && strcmp(file, path) == 0);
    if (n == 1) {
        double worst = 0;
        for (int i = 0; i < 136; i++) worst = fmax(worst, fabs(v[0].landmarks[i] - lm[i]));
        CHECK(worst < 1e-9); /* 1-based -> 0-based */
        CHECK(v[0].source == FRIG_FACE_USER);
        CHECK_NEAR(v[0].box[0], 100, 1e-9);
        CHECK_NEAR(v[0].box[2], 134, 1e-9);
        CHECK_NEAR(v[0].box[3], 16, 1e-9);
    }
    free(v), free(file);
    /* JSON wins over .pts; the "faces" form with a second, empty face is refused. */
    snprintf(path, sizeof path, "%s/a.photo.landmarks.json", dir);
    json_text(text, sizeof text, lm, 1);
    write_text(path, text);
    CHECK(fr_user_landmarks(ctx, photo, &v, &n, &file) == FRIG_ERR_CORRUPT && n == 0 && !v && !file);
    CHECK(strstr(frig_ctx_errmsg(ctx), "a.photo.landmarks.json") != NULL);
    json_text(text, sizeof text, lm, 0);
    write_text(path, text);
    CHECK(fr_user_landmarks(ctx, photo, &v, &n, &file) == FRIG_OK && n == 1 && file);
    if (n == 1) CHECK_NEAR(v[0].landmarks[135], lm[135], 1e-9);
    free(v), free(file);
    /* Broken .pts files. */
    const char *bad[] = {"version: 1\nn_points: 68\n{\n1 2\n}\n", "version: 1\nn_points: 5\n{\n}\n", "nothing",
                         "version: 1\nn_points: 68\n{\n1 2 3\n"};
    snprintf(path, sizeof path, "%s/b.pts", dir);
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        write_text(path, bad[k]);
        CHECK(fr_read_pts(ctx, path, lm) == FRIG_ERR_CORRUPT);
    }
    pts_text(text, sizeof text, lm, 1.0);
    char *third = strstr(text, "{\n") + 2;
    third = strchr(strchr(third, '\n') + 1, '\n') + 1;
    memcpy(third, "nan", 3); /* the third point's x */
    write_text(path, text);
    CHECK(fr_read_pts(ctx, path, lm) == FRIG_ERR_CORRUPT);
    pts_text(text, sizeof text, lm, 1.0);
    strcat(text, "extra\n");
    write_text(path, text);
    CHECK(fr_read_pts(ctx, path, lm) == FRIG_OK);
    /* Every cut of a .pts (before its closing brace) and of a JSON file is refused. */
    char json[8192];
    json_text(json, sizeof json, lm, 0);
    size_t full[2] = {(size_t)(strrchr(text, '}') - text), strlen(json)}, refused[2] = {0, 0}, tried[2] = {0, 0};
    for (int kind = 0; kind < 2; kind++) {
        const char *src = kind ? json : text;
        for (size_t cut = 0; cut < full[kind]; cut += 3) {
            FILE *fp = fopen(path, "wb");
            if (!fp) break;
            fwrite(src, 1, cut, fp);
            fclose(fp);
            double pts[136];
            fr_detected_face *faces = NULL;
            size_t nf = 0;
            frig_status st = kind ? fr_read_landmarks_json(ctx, path, &faces, &nf) : fr_read_pts(ctx, path, pts);
            refused[kind] += st == FRIG_ERR_CORRUPT;
            tried[kind]++;
            free(faces);
        }
    }
    printf("cut user landmark files: .pts %zu of %zu refused, JSON %zu of %zu\n", refused[0], tried[0], refused[1],
           tried[1]);
    CHECK(refused[0] == tried[0] && refused[1] == tried[1]);
}

/* ---- real photos ---- */

/* A few photos of several sets on which dlib's HOG detector and our cascade both find faces. */
static const char *const ref_photos[] = {
    "photos/lfw_tony_blair/Tony_Blair_0001.jpg",        "photos/lfw_george_w_bush/George_W_Bush_0038.jpg",
    "photos/video_liveportrait_d6/frame_0001.jpg",       "photos/video_sadtalker_WDA_KatieHill_000/frame_0050.jpg",
    "photos/landmarks_300w_lfpw/lfpw_trainset_image_0002.png", "photos/landmarks_300w_mmpose_tests/indoor_029.png",
    "photos/landmarks_dlib_examples_faces_predicted/2008_002506.jpg",
};
#define N_REF (sizeof ref_photos / sizeof ref_photos[0])

static int test_against_dlib(void) {
    char why[1024], bin[4096], out[4200], cmd[16384];
    const char *env = getenv("FRIG_DLIB_REF");
    if (env && *env) snprintf(bin, sizeof bin, "%s", env);
    else snprintf(bin, sizeof bin, "%s/tools/dlib_ref", FRIG_BINARY_DIR);
    if (lm_build_dlib_ref(test_shared_path("tools/dlib_ref.cpp"), bin, why, sizeof why)) {
        fprintf(stderr, "cannot compare with dlib: %s\n", why);
        return 1;
    }
    snprintf(out, sizeof out, "%s/dlib.jsonl", test_temp_dir("detect_dlib"));
    size_t k = (size_t)snprintf(cmd, sizeof cmd, "'%s' '%s'", bin, FR_DETECT_DEFAULT_LANDMARK_MODEL);
    for (size_t i = 0; i < N_REF; i++) k += (size_t)snprintf(cmd + k, sizeof cmd - k, " '%s'", test_shared_path(ref_photos[i]));
    snprintf(cmd + k, sizeof cmd - k, " 2>/dev/null");
    CHECK(test_ref_to_file(cmd, out) == 0);
    lm_face *ref;
    long nref = lm_read_faces(out, &ref);
    CHECK(nref >= (long)N_REF);
    long matched = 0;
    double worst_nme = 0, sum_nme = 0, worst_iou = 1;
    for (size_t i = 0; i < N_REF; i++) {
        frig_image *img = load(ref_photos[i], FRIG_LOAD_IGNORE_ORIENTATION);
        found f;
        if (!img || detect(ctx, det, img, &f)) continue;
        for (long r = 0; r < nref; r++) {
            if (strcmp(ref[r].image, test_shared_path(ref_photos[i])) != 0) continue;
            double rb[4] = {ref[r].box[0], ref[r].box[1], ref[r].box[2] - ref[r].box[0] + 1,
                            ref[r].box[3] - ref[r].box[1] + 1};
            long best = -1;
            double best_iou = 0.3;
            for (size_t j = 0; j < f.n; j++)
                if (fr_box_iou(f.boxes + 4 * j, rb) >= best_iou) best_iou = fr_box_iou(f.boxes + 4 * j, rb), best = (long)j;
            if (best < 0) continue;
            matched++;
            double e = lm_nme(f.lm + 136 * best, ref[r].dlib);
            worst_nme = fmax(worst_nme, e);
            worst_iou = fmin(worst_iou, best_iou);
            sum_nme += e;
        }
        frig_image_free(img);
    }
    printf("vs dlib's pipeline: %ld of %ld dlib faces matched; box IoU >= %.3f; landmark distance / outer-eye "
           "distance mean %.4f, max %.4f\n",
           matched, nref, worst_iou, matched ? sum_nme / matched : 0.0, worst_nme);
    CHECK(matched >= nref - 1);
    CHECK(worst_iou >= TOL_IOU);
    CHECK(matched && sum_nme / matched <= TOL_NME_MEAN);
    CHECK(worst_nme <= TOL_NME_MAX);
    free(ref);
    return 0;
}

static const char *const gt_photos[] = {
    "photos/landmarks_300w_lfpw/lfpw_image_0010.png",   "photos/landmarks_300w_lfpw/lfpw_trainset_image_0001.png",
    "photos/landmarks_300w_mmpose_tests/indoor_020.png", "photos/landmarks_300w_mmpose_tests/AFW_134212_1_0.jpg",
    "photos/landmarks_300w_mmpose_tests/300vw_001_000006.jpg",
};

static void test_ground_truth(void) {
    double sum = 0, worst = 0;
    int scored = 0;
    for (size_t i = 0; i < sizeof gt_photos / sizeof gt_photos[0]; i++) {
        char pts[4096];
        snprintf(pts, sizeof pts, "%s", test_shared_path(gt_photos[i]));
        strcpy(strrchr(pts, '.'), ".pts");
        double truth[136];
        frig_image *img = load(gt_photos[i], 0);
        found f;
        CHECK(lm_read_pts(pts, truth));
        if (!img || detect(ctx, det, img, &f)) continue;
        CHECK(f.n >= 1);
        double best = INFINITY;
        for (size_t j = 0; j < f.n; j++) best = fmin(best, lm_nme(f.lm + 136 * j, truth));
        printf("  %s: %zu face(s), NME %.4f\n", gt_photos[i], f.n, best);
        if (f.n) sum += best, worst = fmax(worst, best), scored++;
        frig_image_free(img);
    }
    printf("NME on %d ground-truth faces: mean %.4f, max %.4f\n", scored, scored ? sum / scored : 0, worst);
    CHECK(scored == (int)(sizeof gt_photos / sizeof gt_photos[0]));
    CHECK(scored && sum / scored <= TOL_GT_MEAN);
    CHECK(worst <= TOL_GT_MAX);
}

static void test_no_face_and_profile(void) {
    const char *nonface[] = {"photos/outliers/nonface_rocket_skimage.jpg", "photos/outliers/nonface_coins_gray_skimage.png"};
    for (int i = 0; i < 2; i++) {
        frig_image *img = load(nonface[i], 0);
        found f;
        CHECK(img && detect(ctx, det, img, &f) == FRIG_OK && f.n == 0);
        frig_image_free(img);
    }
    /* The turned head: only the profile fallback finds it. */
    frig_image *img = load("photos/outliers/hardpose_aflw2000_image00475.jpg", 0);
    found f;
    CHECK(img && detect(ctx, det, img, &f) == FRIG_OK && f.n >= 1);
    CHECK(f.n >= 1 && f.sources[0] != FRIG_FACE_FRONTAL);
    frig_ctx *c = frig_ctx_create();
    frig_ctx_set_param(c, FRIG_PARAM_DETECT_DETECTOR, 1); /* the cascades (face-api's SSD: test_identity) */
    frig_detector *d = NULL;
    CHECK(frig_ctx_set_param(c, FRIG_PARAM_DETECT_PROFILE, 0) == FRIG_OK);
    CHECK(frig_detector_create(c, NULL, NULL, &d) == FRIG_OK);
    CHECK(d && detect(c, d, img, &f) == FRIG_OK && f.n == 0);
    frig_detector_free(d);
    frig_ctx_free(c);
    frig_image_free(img);
}

/* A detector with the given detect.max_side and detect.coarse_side. */
static frig_detector *detector_with(frig_ctx *c, int max_side, int coarse_side) {
    frig_detector *d = NULL;
    CHECK(frig_ctx_set_param(c, FRIG_PARAM_DETECT_MAX_SIDE, max_side) == FRIG_OK);
    CHECK(frig_ctx_set_param(c, FRIG_PARAM_DETECT_COARSE_SIDE, coarse_side) == FRIG_OK);
    CHECK(frig_detector_create(c, NULL, NULL, &d) == FRIG_OK);
    return d;
}

/* The 1280 x 1024 photo searched on a copy of longer side 640: the same face, box within a few
 * pixels, landmarks close (they are computed at full resolution either way). The stage's
 * coarse pass (detect.coarse_side 640) finds exactly what max_side 640 finds. */
static void test_max_side(void) {
    frig_image *img = load("photos/landmarks_300w_lfpw/lfpw_image_0010.png", 0);
    found full, small, coarse;
    frig_ctx *c = frig_ctx_create();
    frig_ctx_set_param(c, FRIG_PARAM_DETECT_DETECTOR, 1); /* the cascades (face-api's SSD: test_identity) */
    frig_detector *d_full = detector_with(c, 1024, 0), *d_small = detector_with(c, 640, 0);
    CHECK(d_full && img && detect(c, d_full, img, &full) == FRIG_OK && full.n >= 1);
    CHECK(d_small && img && detect(c, d_small, img, &small) == FRIG_OK && small.n >= 1);
    CHECK(img && detect(ctx, det, img, &coarse) == FRIG_OK && coarse.n == small.n);
    CHECK(memcmp(coarse.boxes, small.boxes, sizeof coarse.boxes) == 0);
    if (full.n >= 1 && small.n >= 1) {
        double iou = fr_box_iou(full.boxes, small.boxes), nme = lm_nme(small.lm, full.lm);
        printf("max_side 640 on a 1280x1024 photo: box IoU %.3f with max_side 1024, landmarks %.4f of the eye "
               "distance apart\n",
               iou, nme);
        CHECK(iou >= 0.8);
        CHECK(nme <= 0.05);
    }
    frig_detector_free(d_full);
    frig_detector_free(d_small);
    frig_ctx_free(c);
    frig_image_free(img);
}

/* A small face in a large photo (an LFW photo in the middle of a 2400 px gray canvas): too small
 * for the coarse pass at 640, found by the pass at detect.max_side, as without a coarse pass. */
static void test_coarse_miss(void) {
    frig_image *lfw = load("photos/lfw_tony_blair/Tony_Blair_0001.jpg", 0);
    frig_image *big = fr_image_new(2400, 2400, 3);
    CHECK(big != NULL);
    if (!lfw || !big) {
        frig_image_free(lfw);
        frig_image_free(big);
        return;
    }
    memset(big->pixels, 128, big->stride * (size_t)big->height);
    for (int y = 0; y < lfw->height; y++)
        memcpy(big->pixels + (size_t)(1100 + y) * big->stride + 1100 * 3, lfw->pixels + (size_t)y * lfw->stride,
               (size_t)lfw->width * 3);
    frig_ctx *c = frig_ctx_create();
    frig_ctx_set_param(c, FRIG_PARAM_DETECT_DETECTOR, 1); /* the cascades (face-api's SSD: test_identity) */
    frig_detector *d_640 = detector_with(c, 640, 0), *d_off = detector_with(c, 1024, 0);
    found at640, off, staged;
    CHECK(d_640 && detect(c, d_640, big, &at640) == FRIG_OK && at640.n == 0);
    CHECK(d_off && detect(c, d_off, big, &off) == FRIG_OK && off.n == 1);
    CHECK(detect(ctx, det, big, &staged) == FRIG_OK && staged.n == off.n);
    CHECK(memcmp(staged.boxes, off.boxes, sizeof staged.boxes) == 0 && memcmp(staged.lm, off.lm, sizeof staged.lm) == 0);
    printf("a 250 px face in a 2400 px photo: %zu faces at max_side 640, %zu at 1024, %zu with the coarse pass\n",
           at640.n, off.n, staged.n);
    frig_detector_free(d_640);
    frig_detector_free(d_off);
    frig_ctx_free(c);
    frig_image_free(lfw);
    frig_image_free(big);
}

/* Two threads, each with its own context, detecting on different photos at once. */
typedef struct job {
    const frig_image *img[3];
    found out[3];
    frig_status st;
} job;

static void *run_job(void *arg) {
    job *j = arg;
    frig_ctx *c = frig_ctx_create();
    frig_ctx_set_param(c, FRIG_PARAM_DETECT_DETECTOR, 1); /* the cascades (face-api's SSD: test_identity) */
    j->st = c ? FRIG_OK : FRIG_ERR_NO_MEMORY;
    for (int k = 0; k < 3 && !j->st; k++) j->st = detect(c, det, j->img[k], &j->out[k]);
    frig_ctx_free(c);
    return NULL;
}

static void test_threads(void) {
    const char *rel[6] = {ref_photos[0], ref_photos[2], ref_photos[6], ref_photos[1], ref_photos[3], ref_photos[5]};
    frig_image *img[6];
    found seq[6];
    for (int i = 0; i < 6; i++) {
        img[i] = load(rel[i], 0);
        if (!img[i]) return;
        CHECK(detect(ctx, det, img[i], &seq[i]) == FRIG_OK);
    }
    job jobs[2];
    pthread_t th[2];
    for (int t = 0; t < 2; t++) {
        memset(&jobs[t], 0, sizeof jobs[t]);
        for (int k = 0; k < 3; k++) jobs[t].img[k] = img[3 * t + k];
        CHECK(pthread_create(&th[t], NULL, run_job, &jobs[t]) == 0);
    }
    int same = 0;
    for (int t = 0; t < 2; t++) {
        pthread_join(th[t], NULL);
        CHECK(jobs[t].st == FRIG_OK);
        for (int k = 0; k < 3; k++) same += memcmp(&jobs[t].out[k], &seq[3 * t + k], sizeof(found)) == 0;
    }
    printf("concurrent detection on 2 threads: %d of 6 photos identical to sequential calls\n", same);
    CHECK(same == 6);
    for (int i = 0; i < 6; i++) frig_image_free(img[i]);
}

/* A photo set with a good photo, a non-face, a corrupt and an empty file, a tiny face (an LFW
 * photo shrunk so the face is about 29 px), and a photo with user landmarks; detected with 1
 * and with 2 threads: the statuses, and the same report bytes. */
static void test_photoset(void) {
    const char *dir = test_temp_dir("detect_set");
    char p[8][4300];
    snprintf(p[0], sizeof p[0], "%s", test_shared_path(ref_photos[0]));
    snprintf(p[1], sizeof p[1], "%s", test_shared_path("photos/outliers/nonface_rocket_skimage.jpg"));
    snprintf(p[2], sizeof p[2], "%s/corrupt.jpg", dir);
    snprintf(p[3], sizeof p[3], "%s/empty.jpg", dir);
    snprintf(p[4], sizeof p[4], "%s/tiny.png", dir);
    snprintf(p[5], sizeof p[5], "%s/user.jpg", dir);
    snprintf(p[6], sizeof p[6], "%s/missing.jpg", dir);
    size_t size;
    unsigned char *jpeg = test_read_file(test_shared_path(ref_photos[1]), &size);
    CHECK(jpeg && size > 1000);
    if (!jpeg) return;
    CHECK(fr_write_file_atomic(ctx, p[2], jpeg, size / 3) == FRIG_OK); /* cut short */
    CHECK(fr_write_file_atomic(ctx, p[3], "", 0) == FRIG_OK);
    CHECK(fr_write_file_atomic(ctx, p[5], jpeg, size) == FRIG_OK);
    free(jpeg);
    frig_image *lfw = load(ref_photos[0], 0), *tiny = NULL;
    CHECK(lfw && frig_image_create(ctx, 120, 120, 3, &tiny) == FRIG_OK);
    if (!lfw || !tiny) return;
    /* 150 -> 72 px (face ~60 -> ~29 px, eyes ~13 px apart), in a gray 120 x 120 frame, per channel. */
    uint8_t src[150 * 150], dst[72 * 72];
    memset(tiny->pixels, 128, tiny->stride * 120);
    for (int ch = 0; ch < 3; ch++) {
        for (int i = 0; i < 150 * 150; i++) src[i] = lfw->pixels[(size_t)(i / 150) * lfw->stride + (size_t)(i % 150) * 3 + (size_t)ch];
        CHECK(fr_cascade_resize(src, 150, 150, 150, dst, 72, 72, 72) == 0);
        for (int i = 0; i < 72 * 72; i++) tiny->pixels[(size_t)(20 + i / 72) * tiny->stride + (size_t)(20 + i % 72) * 3 + (size_t)ch] = dst[i];
    }
    CHECK(frig_image_save_png(ctx, tiny, p[4]) == FRIG_OK);
    frig_image_free(tiny);
    found f;
    CHECK(detect(ctx, det, lfw, &f) == FRIG_OK && f.n >= 1);
    char pts[8192], path[4400];
    double user_lm[136];
    memcpy(user_lm, f.lm, sizeof user_lm);
    for (int i = 0; i < 136; i++) user_lm[i] = round(user_lm[i] * 8) / 8 + 3; /* not ours: shifted 3 px */
    pts_text(pts, sizeof pts, user_lm, 1.0);
    snprintf(path, sizeof path, "%s/user.pts", dir);
    write_text(path, pts);
    frig_image_free(lfw);

    char report[2][4400];
    for (int t = 1; t <= 2; t++) {
        frig_photoset *set = NULL;
        CHECK(frig_photoset_create(ctx, &set) == FRIG_OK);
        for (int i = 0; i < 7; i++) CHECK(frig_photoset_add(ctx, set, p[i], NULL) == FRIG_OK);
        CHECK(frig_ctx_set_threads(ctx, t) == FRIG_OK);
        CHECK(frig_detect_photoset(ctx, det, set) == FRIG_OK);
        static const frig_photo_status want[7] = {FRIG_PHOTO_OK, FRIG_PHOTO_NO_FACE, FRIG_PHOTO_UNREADABLE,
                                                  FRIG_PHOTO_UNREADABLE, FRIG_PHOTO_FACE_TOO_SMALL, FRIG_PHOTO_OK,
                                                  FRIG_PHOTO_UNREADABLE};
        for (int i = 0; i < 7; i++) {
            if (t == 1)
                printf("  %-12s %-15s subject %ld, %zu face(s); %s\n", fr_path_base(p[i]),
                       frig_photo_status_name(frig_photoset_status(set, i)), frig_photoset_subject(set, i),
                       frig_photoset_face_count(set, i), frig_photoset_reason(set, i));
            CHECK(frig_photoset_status(set, i) == want[i]);
        }
        CHECK(strstr(frig_photoset_reason(set, 3), "empty.jpg") != NULL);
        CHECK(frig_photoset_subject(set, 0) == 0 && frig_photoset_subject(set, 1) == -1);
        CHECK(frig_photoset_face_count(set, 5) == 1 && frig_photoset_face_source(set, 5, 0) == FRIG_FACE_USER);
        double lm[136];
        if (frig_photoset_face_landmarks(set, 5, 0, lm) == FRIG_OK) CHECK_NEAR(lm[100], user_lm[100], 1e-9);
        int w, h;
        frig_photoset_size(set, 4, &w, &h);
        CHECK(w == 120 && h == 120);
        snprintf(report[t - 1], sizeof report[t - 1], "%s/t%d", dir, t);
        CHECK(frig_photoset_save(ctx, set, report[t - 1]) == FRIG_OK);
        if (t == 2) CHECK(frig_detect_write_overlays(ctx, set, report[1]) == FRIG_OK);
        frig_photoset_free(set);
    }
    CHECK(frig_ctx_set_threads(ctx, 0) == FRIG_OK);
    char a[4500], b[4500];
    snprintf(a, sizeof a, "%s/report.json", report[0]);
    snprintf(b, sizeof b, "%s/report.json", report[1]);
    size_t na, nb;
    unsigned char *ra = test_read_file(a, &na), *rb = test_read_file(b, &nb);
    CHECK(ra && rb && na == nb && memcmp(ra, rb, na) == 0);
    free(ra), free(rb);
    snprintf(a, sizeof a, "%s/4_tiny.jpg", report[1]);
    snprintf(b, sizeof b, "%s/2_corrupt.jpg", report[1]);
    CHECK(test_file_exists(a) && test_file_exists(b));
}

/* Progress arrives in order up to the photo count; a cancel from the callback stops the run. */
typedef struct ticks {
    size_t calls, last, total;
    int ordered, cancel_at;
    frig_ctx *ctx;
} ticks;

static void on_progress(void *user, const char *stage, size_t done, size_t total) {
    ticks *t = user;
    if (strcmp(stage, "detect") != 0) return;
    t->ordered &= t->calls == 0 || done >= t->last;
    t->calls++;
    t->last = done;
    t->total = total;
    if (t->cancel_at && done >= (size_t)t->cancel_at) frig_ctx_cancel(t->ctx);
}

static void test_progress_and_cancel(void) {
    frig_photoset *set = NULL;
    CHECK(frig_photoset_create(ctx, &set) == FRIG_OK);
    for (size_t i = 0; i < N_REF; i++) CHECK(frig_photoset_add(ctx, set, test_shared_path(ref_photos[i]), NULL) == FRIG_OK);
    for (int cancel = 0; cancel < 2; cancel++) {
        frig_ctx *c = frig_ctx_create();
        frig_ctx_set_param(c, FRIG_PARAM_DETECT_DETECTOR, 1); /* the cascades (face-api's SSD: test_identity) */
        ticks t = {0, 0, 0, 1, cancel ? 2 : 0, c};
        frig_ctx_set_progress(c, on_progress, &t);
        CHECK(frig_ctx_set_threads(c, 2) == FRIG_OK);
        frig_status st = frig_detect_photoset(c, det, set);
        if (!cancel) CHECK(st == FRIG_OK && t.ordered && t.last == N_REF && t.total == N_REF && t.calls == N_REF + 1);
        else CHECK(st == FRIG_ERR_CANCELLED && strstr(frig_ctx_errmsg(c), "cancel") && t.last < N_REF);
        frig_ctx_free(c);
    }
    frig_photoset_free(set);
}

/* A photo stored sideways with an EXIF orientation tag: boxes and landmarks come out in the
 * upright photo's pixels, as for the same photo stored upright (both re-encoded as JPEG). */
static void test_exif(void) {
    frig_image *orig = load("photos/landmarks_dlib_examples_faces_predicted/2008_002506.jpg", 0);
    if (!orig) return;
    frig_image *sideways = fr_image_orient(orig, 8); /* turned a quarter left; tag 6 turns it back */
    const char *dir = test_temp_dir("detect_exif");
    char path[2][4300];
    for (int k = 0; k < 2; k++) {
        unsigned char *data = NULL;
        size_t size = 0;
        snprintf(path[k], sizeof path[k], "%s/%s.jpg", dir, k ? "tagged" : "upright");
        CHECK(sideways && fr_jpeg_encode(ctx, k ? sideways : orig, 95, k ? 6 : 0, &data, &size) == FRIG_OK);
        CHECK(data && fr_write_file_atomic(ctx, path[k], data, size) == FRIG_OK);
        free(data);
    }
    frig_photoset *set = NULL;
    CHECK(frig_photoset_create(ctx, &set) == FRIG_OK);
    for (int k = 0; k < 2; k++) CHECK(frig_photoset_add(ctx, set, path[k], NULL) == FRIG_OK);
    CHECK(frig_detect_photoset(ctx, det, set) == FRIG_OK);
    int w[2], h[2];
    for (int k = 0; k < 2; k++) frig_photoset_size(set, (size_t)k, &w[k], &h[k]);
    CHECK(w[0] == orig->width && h[0] == orig->height && w[1] == w[0] && h[1] == h[0] && w[0] != h[0]);
    size_t n = frig_photoset_face_count(set, 0), close = 0;
    CHECK(n >= 3 && frig_photoset_face_count(set, 1) == n);
    for (size_t f = 0; f < n && frig_photoset_face_count(set, 1) == n; f++) {
        double a[4], b[4], la[136], lb[136];
        frig_photoset_face_box(set, 0, f, a);
        frig_photoset_face_box(set, 1, f, b);
        CHECK(frig_photoset_face_landmarks(set, 0, f, la) == FRIG_OK);
        CHECK(frig_photoset_face_landmarks(set, 1, f, lb) == FRIG_OK);
        close += fr_box_iou(a, b) >= 0.9 && lm_nme(lb, la) <= 0.05;
    }
    printf("EXIF orientation 6: %zu of %zu faces where the upright copy has them\n", close, n);
    CHECK(close == n);
    frig_photoset_free(set);
    frig_image_free(sideways);
    frig_image_free(orig);
}

int main(void) {
    ctx = frig_ctx_create();
    frig_ctx_set_param(ctx, FRIG_PARAM_DETECT_DETECTOR, 1); /* the cascades (face-api's SSD: test_identity) */
    test_missing_files();
    test_merge_and_subject();
    test_user_files();
    if (!test_file_exists(FR_DETECT_DEFAULT_LANDMARK_MODEL) ||
        !test_file_exists(FR_DETECT_DEFAULT_CASCADE_DIR "/haarcascades/" FR_DETECT_FRONTAL_FILE) ||
        !test_file_exists(test_shared_path("photos/outliers"))) {
        frig_ctx_free(ctx);
        if (test_failures) return test_result("test_detect");
        return test_skip("needs libdlib-data, opencv-data and ../shared/photos");
    }
    CHECK(frig_detector_create(ctx, NULL, NULL, &det) == FRIG_OK);
    int skipped = 0;
    if (det) {
        test_ground_truth();
        test_no_face_and_profile();
        test_max_side();
        test_coarse_miss();
        test_threads();
        test_photoset();
        test_exif();
        test_progress_and_cancel();
        skipped = test_against_dlib();
    }
    frig_detector_free(det);
    frig_ctx_free(ctx);
    if (skipped && !test_failures) return test_skip("dlib_ref could not be built: no comparison with dlib");
    return test_result("test_detect");
}
