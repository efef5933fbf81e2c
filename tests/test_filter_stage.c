/* The filter stage over a photo set: in a photo holding two people, where the other person's
 * face is the larger (so detection picks it as the subject), the filter's models must switch
 * the subject to the face consistent with the rest of the set; and the results must not
 * depend on the thread count. */
#include <stdlib.h>
#include <string.h>

#include "frig/frig.h"
#include "testing.h"

/* Scale src by s (nearest) into dst at (x0, y0). */
static void paste(frig_image *dst, const frig_image *src, double s, int x0, int y0) {
    int W = frig_image_width(dst), H = frig_image_height(dst);
    uint8_t *d = frig_image_pixels_mutable(dst);
    const uint8_t *p = frig_image_pixels(src);
    int sw = frig_image_width(src), sh = frig_image_height(src);
    for (int y = 0; y < (int)(sh * s); y++)
        for (int x = 0; x < (int)(sw * s); x++) {
            int X = x0 + x, Y = y0 + y, sx = (int)(x / s), sy = (int)(y / s);
            if (X < 0 || Y < 0 || X >= W || Y >= H || sx >= sw || sy >= sh) continue;
            memcpy(d + (size_t)Y * frig_image_stride(dst) + 3 * (size_t)X,
                   p + (size_t)sy * frig_image_stride(src) + 3 * (size_t)sx, 3);
        }
}

static frig_photoset *run(frig_ctx *ctx, const frig_detector *det, const char *dir, const char *composite,
                          int threads, size_t *composite_index) {
    frig_photoset *set = NULL;
    frig_photoset_create(ctx, &set);
    for (int i = 0; i < 20; i++) {
        char path[4096];
        snprintf(path, sizeof path, "%s/frame_%04d.jpg", dir, 1 + 5 * i);
        frig_photoset_add(ctx, set, path, NULL);
    }
    frig_photoset_add(ctx, set, composite, composite_index);
    frig_ctx_set_threads(ctx, threads);
    CHECK(frig_detect_photoset(ctx, det, set) == FRIG_OK);
    CHECK(frig_filter(ctx, set, NULL) == FRIG_OK);
    return set;
}

int main(void) {
    const char *video = test_shared_path("photos/video_sadtalker_WDA_KatieHill_000");
    char probe[4200];
    snprintf(probe, sizeof probe, "%s/frame_0001.jpg", video);
    if (!test_file_exists(probe) || !test_file_exists("/usr/share/dlib/shape_predictor_68_face_landmarks.dat"))
        return test_skip("shared photos or dlib's landmark model (libdlib-data) missing");
    char dir[4096];
    snprintf(dir, sizeof dir, "%s", video);
    frig_ctx *ctx = frig_ctx_create();
    frig_detector *det = NULL;
    if (frig_detector_create(ctx, NULL, NULL, &det)) return test_skip(frig_ctx_errmsg(ctx));

    /* The composite: another person's face, larger, at the left; the set's person at the right. */
    frig_image *katie = NULL, *other = NULL, *canvas = NULL;
    char path[4200];
    snprintf(path, sizeof path, "%s/frame_0042.jpg", dir);
    CHECK(frig_image_load(ctx, path, 0, &katie) == FRIG_OK);
    CHECK(frig_image_load(ctx, test_shared_path("photos/lfw_george_w_bush/George_W_Bush_0001.jpg"), 0, &other) ==
          FRIG_OK);
    if (!katie || !other) return test_result("test_filter_stage");
    CHECK(frig_image_create(ctx, 960, 450, 3, &canvas) == FRIG_OK);
    paste(canvas, other, 3.0, 255, 0);     /* 150 px -> 450 px, centred: a face of about 180 px */
    paste(canvas, katie, 0.5, 705, 60);    /* 512 px -> 256 px, at the right: a face of about 95 px */
    const char *tmp = test_temp_dir("filter_stage");
    char composite[4200];
    snprintf(composite, sizeof composite, "%s/two_people.jpg", tmp);
    CHECK(frig_image_save_jpeg(ctx, canvas, composite) == FRIG_OK);

    size_t ci = 0;
    frig_photoset *a = run(ctx, det, dir, composite, 1, &ci);
    CHECK(frig_photoset_face_count(a, ci) == 2);
    long subject = frig_photoset_subject(a, ci);
    double box[4] = {0, 0, 0, 0};
    if (subject >= 0) frig_photoset_face_box(a, ci, (size_t)subject, box);
    printf("composite: %zu faces, subject %ld at x = %.0f (%s), status %s, reason: %s\n", frig_photoset_face_count(a, ci),
           subject, box[0], box[0] > 705 ? "the set's person" : "the other person",
           frig_photo_status_name(frig_photoset_status(a, ci)), frig_photoset_reason(a, ci));
    CHECK(subject >= 0 && box[0] > 705);
    CHECK(frig_photoset_status(a, ci) == FRIG_PHOTO_OK);
    CHECK(strstr(frig_photoset_reason(a, ci), "subject changed") != NULL);

    /* Two threads: the same report, byte for byte. */
    frig_photoset *b = run(ctx, det, dir, composite, 2, &ci);
    char wa[4200], wb[4200], cmd[9000];
    snprintf(wa, sizeof wa, "%s/a", tmp);
    snprintf(wb, sizeof wb, "%s/b", tmp);
    CHECK(frig_photoset_save(ctx, a, wa) == FRIG_OK && frig_photoset_save(ctx, b, wb) == FRIG_OK);
    snprintf(cmd, sizeof cmd, "cmp -s '%s/report.json' '%s/report.json'", wa, wb);
    CHECK(system(cmd) == 0);

    frig_photoset_free(a);
    frig_photoset_free(b);
    frig_image_free(katie);
    frig_image_free(other);
    frig_image_free(canvas);
    frig_detector_free(det);
    frig_ctx_free(ctx);
    return test_result("test_filter_stage");
}
