/* The identity step (frig_identify_photoset). On made-up descriptors: the dominant cluster's
 * medoid, the subject as the face nearest it (not the largest), other_person with the distance
 * in the reason, a rerun with a looser threshold giving photos back, a set of two people
 * equally often refused with a sentence and left unchanged. On real photos with face-api's
 * networks: LFW photos of one person with photos of another planted and a composite of the
 * subject beside a larger stranger, through frig_detect_photoset (SSD, descriptors) and the
 * identity step; the same report with 1 and 2 threads. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "image/image.h"
#include "io/file.h"
#include "testing.h"
#include "workspace/photoset.h"

static unsigned long long seed = 99;
static double gauss(void) {
    double u = 0;
    for (int k = 0; k < 12; k++) {
        seed = seed * 6364136223846793005ULL + 1442695040888963407ULL;
        u += (double)(seed >> 11) / 9007199254740992.0;
    }
    return u - 6;
}

/* A person: a centre; a face of them: the centre plus noise of about 0.4 in all. */
static void person(float *c) {
    for (int k = 0; k < FRIG_DESCRIPTOR_SIZE; k++) c[k] = (float)(gauss() * 0.06);
}
static void face_of(const float *c, float *d) {
    for (int k = 0; k < FRIG_DESCRIPTOR_SIZE; k++) d[k] = c[k] + (float)(gauss() * 0.025);
}

/* A face whose eyes are 40 px apart at (x, y), size s. */
static size_t add_face(frig_ctx *ctx, frig_photoset *set, size_t photo, double x, double y, double s, const float *d) {
    double box[4] = {x, y, s, s}, lm[136];
    for (int k = 0; k < 68; k++) lm[2 * k] = x + s * 0.5, lm[2 * k + 1] = y + s * 0.5;
    lm[72] = x + 0.2 * s, lm[73] = y + 0.4 * s, lm[90] = x + 0.2 * s + 40, lm[91] = y + 0.4 * s;
    size_t f = 0;
    CHECK(frig_photoset_add_face(ctx, set, photo, box, 0.9, FRIG_FACE_SSD, lm, &f) == FRIG_OK);
    CHECK(frig_photoset_set_face_descriptor(ctx, set, photo, f, d) == FRIG_OK);
    return f;
}

static void synthetic(frig_ctx *ctx) {
    float a[FRIG_DESCRIPTOR_SIZE], b[FRIG_DESCRIPTOR_SIZE], d[FRIG_DESCRIPTOR_SIZE];
    person(a);
    person(b);
    printf("between people %.3f\n", frig_descriptor_distance(a, b));
    frig_photoset *set = NULL;
    CHECK(frig_photoset_create(ctx, &set) == FRIG_OK);
    char name[32];
    /* 0-9: A alone; 10, 11: B alone; 12: A small beside a larger B; 13: duplicate (ignored) */
    for (int i = 0; i < 14; i++) {
        snprintf(name, sizeof name, "/p%02d.jpg", i);
        size_t idx;
        CHECK(frig_photoset_add(ctx, set, name, &idx) == FRIG_OK);
        frig_photoset_set_size(ctx, set, idx, 800, 600);
        if (i < 10 || i == 13) face_of(a, d), add_face(ctx, set, idx, 300, 200, 200, d);
        else if (i < 12) face_of(b, d), add_face(ctx, set, idx, 300, 200, 200, d);
        else {
            face_of(b, d);
            add_face(ctx, set, idx, 300, 150, 300, d);
            face_of(a, d);
            add_face(ctx, set, idx, 20, 20, 120, d);
            frig_photoset_set_subject(ctx, set, idx, 0); /* detect's choice: the larger face */
        }
        if (i < 12) frig_photoset_set_subject(ctx, set, idx, 0);
        frig_photoset_set_status(ctx, set, idx, i == 13 ? FRIG_PHOTO_DUPLICATE : FRIG_PHOTO_OK, NULL);
    }
    CHECK(frig_identify_photoset(ctx, set) == FRIG_OK);
    for (int i = 0; i < 10; i++) CHECK(frig_photoset_status(set, (size_t)i) == FRIG_PHOTO_OK);
    for (int i = 10; i < 12; i++) {
        CHECK(frig_photoset_status(set, (size_t)i) == FRIG_PHOTO_OTHER_PERSON);
        CHECK(strstr(frig_photoset_reason(set, (size_t)i), "identity.threshold") != NULL);
    }
    printf("other person's reason: %s\n", frig_photoset_reason(set, 10));
    CHECK(frig_photoset_status(set, 12) == FRIG_PHOTO_OK && frig_photoset_subject(set, 12) == 1);
    CHECK(frig_photoset_status(set, 13) == FRIG_PHOTO_DUPLICATE);
    CHECK(isnan(frig_photoset_face_identity_distance(set, 13, 0)));
    CHECK(frig_photoset_face_identity_distance(set, 12, 1) < 0.5 && frig_photoset_face_identity_distance(set, 12, 0) > 0.5);
    CHECK(set->subject_id_photos == 11); /* photos 0-9 and the composite */
    /* saved and read back: the same bytes */
    const char *ws = test_temp_dir("identity_synthetic");
    CHECK(frig_photoset_save(ctx, set, ws) == FRIG_OK);
    frig_photoset *back = NULL;
    CHECK(frig_photoset_load(ctx, ws, &back) == FRIG_OK);
    float id[FRIG_DESCRIPTOR_SIZE], id2[FRIG_DESCRIPTOR_SIZE];
    CHECK(frig_photoset_identity_descriptor(set, id) && frig_photoset_identity_descriptor(back, id2));
    CHECK(memcmp(id, id2, sizeof id) == 0);
    CHECK(frig_photoset_face_descriptor(back, 12, 1, d) == FRIG_OK && frig_photoset_face_descriptor(set, 12, 1, id2) == FRIG_OK);
    CHECK(memcmp(d, id2, sizeof d) == 0);
    CHECK(frig_photoset_status(back, 10) == FRIG_PHOTO_OTHER_PERSON);
    /* a rerun with a threshold over the distance between people gives B's photos back */
    frig_ctx_set_param(ctx, FRIG_PARAM_IDENTITY_THRESHOLD, 1.9);
    CHECK(frig_identify_photoset(ctx, back) == FRIG_OK);
    CHECK(frig_photoset_status(back, 10) == FRIG_PHOTO_OK && frig_photoset_status(back, 11) == FRIG_PHOTO_OK);
    frig_ctx_set_param(ctx, FRIG_PARAM_IDENTITY_THRESHOLD, 0.5);
    frig_photoset_free(back);
    frig_photoset_free(set);

    /* two people, five photos each: no dominant identity */
    CHECK(frig_photoset_create(ctx, &set) == FRIG_OK);
    for (int i = 0; i < 10; i++) {
        snprintf(name, sizeof name, "/q%02d.jpg", i);
        size_t idx;
        frig_photoset_add(ctx, set, name, &idx);
        face_of(i % 2 ? b : a, d);
        add_face(ctx, set, idx, 300, 200, 200, d);
        frig_photoset_set_subject(ctx, set, idx, 0);
        frig_photoset_set_status(ctx, set, idx, FRIG_PHOTO_OK, NULL);
    }
    CHECK(frig_identify_photoset(ctx, set) == FRIG_ERR_TOO_FEW);
    printf("two people: %s\n", frig_ctx_errmsg(ctx));
    CHECK(strstr(frig_ctx_errmsg(ctx), "no dominant identity") != NULL);
    for (int i = 0; i < 10; i++) CHECK(frig_photoset_status(set, (size_t)i) == FRIG_PHOTO_OK);
    CHECK(!frig_photoset_identity_descriptor(set, NULL));
    frig_photoset_free(set);
}

/* dst (w x h RGB) gets src pasted at (x, y), scaled by an integer factor k. */
static void paste(frig_image *dst, const frig_image *src, int x, int y, int k) {
    for (int j = 0; j < src->height * k && y + j < dst->height; j++)
        for (int i = 0; i < src->width * k && x + i < dst->width; i++)
            memcpy(dst->pixels + (size_t)(y + j) * dst->stride + (size_t)(x + i) * 3,
                   src->pixels + (size_t)(j / k) * src->stride + (size_t)(i / k) * 3, 3);
}

static void real(frig_ctx *ctx) {
    frig_detector *det = NULL;
    frig_ctx_set_param(ctx, FRIG_PARAM_DETECT_DETECTOR, 2);
    CHECK(frig_detector_create(ctx, NULL, NULL, &det) == FRIG_OK);
    if (!det) return;
    const char *dir = test_temp_dir("identity_real");
    /* the composite: Tony Blair at 1x beside Colin Powell at 2x (larger), on gray */
    frig_image *blair = NULL, *powell = NULL, *canvas = NULL;
    char path[4096];
    CHECK(frig_image_load(ctx, test_shared_path("photos/lfw_tony_blair/Tony_Blair_0074.jpg"), 0, &blair) == FRIG_OK);
    CHECK(frig_image_load(ctx, test_shared_path("photos/lfw_colin_powell/Colin_Powell_0081.jpg"), 0, &powell) == FRIG_OK);
    CHECK(frig_image_create(ctx, 480, 320, 3, &canvas) == FRIG_OK);
    if (!blair || !powell || !canvas) return;
    memset(canvas->pixels, 128, canvas->stride * (size_t)canvas->height);
    paste(canvas, blair, 10, 100, 1);
    paste(canvas, powell, 170, 10, 2);
    snprintf(path, sizeof path, "%s/composite.png", dir);
    CHECK(frig_image_save_png(ctx, canvas, path) == FRIG_OK);
    frig_photoset *set[2] = {NULL, NULL};
    for (int t = 0; t < 2; t++) {
        CHECK(frig_photoset_create(ctx, &set[t]) == FRIG_OK);
        static const char *const own[] = {"Tony_Blair_0001", "Tony_Blair_0025", "Tony_Blair_0049", "Tony_Blair_0098",
                                          "Tony_Blair_0123", "Tony_Blair_0049"};
        for (int i = 0; i < 5; i++) {
            char rel[256];
            snprintf(rel, sizeof rel, "photos/lfw_tony_blair/%s.jpg", own[i]);
            frig_photoset_add(ctx, set[t], test_shared_path(rel), NULL);
        }
        frig_photoset_add(ctx, set[t], test_shared_path("photos/lfw_colin_powell/Colin_Powell_0001.jpg"), NULL);
        frig_photoset_add(ctx, set[t], test_shared_path("photos/lfw_george_w_bush/George_W_Bush_0001.jpg"), NULL);
        frig_photoset_add(ctx, set[t], path, NULL);
        frig_ctx_set_threads(ctx, t + 1);
        CHECK(frig_detect_photoset(ctx, det, set[t]) == FRIG_OK);
        CHECK(frig_identify_photoset(ctx, set[t]) == FRIG_OK);
    }
    frig_photoset *s = set[0];
    for (size_t i = 0; i < frig_photoset_count(s); i++) {
        long subj = frig_photoset_subject(s, i);
        printf("%-40s %-13s subject %ld of %zu, distance %.3f  %s\n", fr_path_base(frig_photoset_path(s, i)),
               frig_photo_status_name(frig_photoset_status(s, i)), subj, frig_photoset_face_count(s, i),
               subj >= 0 ? frig_photoset_face_identity_distance(s, i, (size_t)subj) : NAN, frig_photoset_reason(s, i));
    }
    for (size_t i = 0; i < 5; i++)
        CHECK(frig_photoset_status(s, i) == FRIG_PHOTO_OK || frig_photoset_status(s, i) == FRIG_PHOTO_NO_FACE);
    CHECK(frig_photoset_status(s, 5) == FRIG_PHOTO_OTHER_PERSON && frig_photoset_status(s, 6) == FRIG_PHOTO_OTHER_PERSON);
    /* the composite: the subject is the smaller face on the left (Blair) */
    long subj = frig_photoset_subject(s, 7);
    double box[4] = {0, 0, 0, 0};
    CHECK(frig_photoset_status(s, 7) == FRIG_PHOTO_OK && subj >= 0);
    if (subj >= 0) frig_photoset_face_box(s, 7, (size_t)subj, box);
    CHECK(box[0] < 160 && box[2] < 150);
    /* one thread or two: the same report */
    const char *w1 = test_temp_dir("identity_t1");
    char w2[4096];
    snprintf(w2, sizeof w2, "%s", test_temp_dir("identity_t2"));
    CHECK(frig_photoset_save(ctx, set[0], w1) == FRIG_OK && frig_photoset_save(ctx, set[1], w2) == FRIG_OK);
    char p1[4200], p2[4200];
    snprintf(p1, sizeof p1, "%s/report.json", w1);
    snprintf(p2, sizeof p2, "%s/report.json", w2);
    size_t n1, n2;
    unsigned char *b1 = test_read_file(p1, &n1), *b2 = test_read_file(p2, &n2);
    CHECK(b1 && b2 && n1 == n2 && memcmp(b1, b2, n1) == 0);
    free(b1), free(b2);
    frig_photoset_free(set[0]), frig_photoset_free(set[1]);
    frig_image_free(blair), frig_image_free(powell), frig_image_free(canvas);
    frig_detector_free(det);
}

int main(void) {
    frig_ctx *ctx = frig_ctx_create();
    synthetic(ctx);
    int have = test_file_exists(test_shared_path("photos/lfw_tony_blair/Tony_Blair_0001.jpg"));
    frig_detector *probe = NULL;
    frig_ctx_set_param(ctx, FRIG_PARAM_DETECT_DETECTOR, 2);
    int nets = frig_detector_create(ctx, NULL, NULL, &probe) == FRIG_OK;
    frig_detector_free(probe);
    int rc = test_result("test_identity");
    if (!have || !nets) {
        frig_ctx_free(ctx);
        return rc ? rc : test_skip("no ../shared/photos or no face-api networks: the real-photo half did not run");
    }
    real(ctx);
    frig_ctx_free(ctx);
    return test_result("test_identity");
}
