/* Example: every face in a photo with libfrig's detect stage (OpenCV's cascades and dlib's
 * 68-point landmarks, from Debian's opencv-data and libdlib-data), printed one per line.
 * Build against an installed libfrig:
 *   cc detect_faces.c $(pkg-config --cflags --libs frig) -o detect_faces
 */
#include <stdio.h>

#include <frig/detect.h>

#define MAX_FACES 32

int main(int argc, char **argv) {
    if (argc != 2) {
        fprintf(stderr, "usage: %s PHOTO\n", argv[0]);
        return 2;
    }
    static double boxes[4 * MAX_FACES], scores[MAX_FACES], landmarks[136 * MAX_FACES];
    static int sources[MAX_FACES];
    static const char *const source_names[] = {"frontal", "profile", "profile_mirrored", "user", "ssd"};
    frig_ctx *ctx = frig_ctx_create();
    frig_detector *det = NULL;
    frig_image *photo = NULL;
    size_t n = 0;
    int rc = 1;
    if (frig_detector_create(ctx, NULL, NULL, &det) != FRIG_OK) goto done;
    if (frig_image_load(ctx, argv[1], FRIG_LOAD_DEFAULT, &photo) != FRIG_OK) goto done;
    if (frig_detect_faces(ctx, det, photo, MAX_FACES, &n, boxes, scores, sources, landmarks) != FRIG_OK) goto done;
    printf("%s: %zu face%s\n", argv[1], n, n == 1 ? "" : "s");
    for (size_t i = 0; i < n && i < MAX_FACES; i++) {
        const double *b = boxes + 4 * i, *lm = landmarks + 136 * i;
        printf("  box %.1f %.1f %.1f %.1f, %s, score %g, nose tip (point 30) at %.1f %.1f\n", b[0], b[1], b[2], b[3],
               source_names[sources[i] >= 0 && sources[i] <= 4 ? sources[i] : 0], scores[i], lm[60], lm[61]);
    }
    rc = 0;
done:
    if (rc) fprintf(stderr, "error: %s\n", frig_ctx_errmsg(ctx));
    frig_image_free(photo);
    frig_detector_free(det);
    frig_ctx_free(ctx);
    return rc;
}
