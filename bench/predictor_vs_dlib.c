/* Our shape predictor against dlib's on every face dlib_ref reported (bench/predictor_vs_dlib.sh
 * runs it): time per face in dlib_ref's own pattern (read the image, then one call), warm time
 * (the same face again), and the distance of our points to dlib's on identical boxes, with
 * dlib's gray and with our BT.601 gray, over all faces and per photo set.
 * Use: predictor_vs_dlib MODEL.dat DLIB_REF_OUTPUT.jsonl DLIB_US_PER_FACE */
#include <time.h>

#include "landmark_ref.h"

static double now(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

#define MAX_SETS 64

typedef struct set_stats {
    char name[128];
    long faces, identical;
    lm_stats rounded, bt601;
} set_stats;

/* The folder under photos/ (or the parent folder) that names the set. */
static set_stats *set_of(set_stats *sets, int *n, const char *path) {
    const char *p = strstr(path, "photos/");
    char name[128];
    if (p) {
        p += 7;
        const char *slash = strchr(p, '/');
        size_t len = slash ? (size_t)(slash - p) : strlen(p);
        if (len >= sizeof name) len = sizeof name - 1;
        memcpy(name, p, len);
        name[len] = 0;
    } else {
        snprintf(name, sizeof name, "other");
    }
    for (int i = 0; i < *n; i++)
        if (!strcmp(sets[i].name, name)) return &sets[i];
    if (*n == MAX_SETS) return &sets[MAX_SETS - 1];
    set_stats *s = &sets[(*n)++];
    memset(s, 0, sizeof *s);
    strcpy(s->name, name);
    return s;
}

int main(int argc, char **argv) {
    if (argc != 4) {
        fprintf(stderr, "usage: predictor_vs_dlib MODEL.dat DLIB_REF_OUTPUT.jsonl DLIB_US_PER_FACE\n");
        return 2;
    }
    double dlib_us = atof(argv[3]);
    frig_ctx *ctx = frig_ctx_create();
    fr_shape_predictor *sp;
    double t = now();
    if (fr_shape_predictor_load(ctx, argv[1], &sp)) {
        fprintf(stderr, "%s\n", frig_ctx_errmsg(ctx));
        return 1;
    }
    double load_s = now() - t;
    lm_face *faces;
    long n = lm_read_faces(argv[2], &faces);
    if (n <= 0) {
        fprintf(stderr, "%s: no faces\n", argv[2]);
        return 1;
    }
    set_stats sets[MAX_SETS];
    int nsets = 0;
    lm_stats all_rounded = {0}, all_raw = {0}, all_bt601 = {0};
    long identical = 0;
    double cold = 0, warm = 0;
    enum { REPEAT = 5 };
    lm_image im = {0};
    for (long k = 0; k < n; k++) {
        double pts[2 * LM_POINTS], pts_bt601[2 * LM_POINTS];
        lm_image_clear(&im); /* read the image for every face, as dlib_ref --boxes does */
        if (lm_image_get(ctx, &im, faces[k].image)) {
            fprintf(stderr, "%s\n", frig_ctx_errmsg(ctx));
            return 1;
        }
        t = now();
        frig_status st = lm_predict(sp, im.dlib_gray, faces[k].box, pts);
        cold += now() - t;
        double best = INFINITY;
        for (int r = 0; r < REPEAT && !st; r++) {
            t = now();
            st = lm_predict(sp, im.dlib_gray, faces[k].box, pts);
            double dt = now() - t;
            if (dt < best) best = dt;
        }
        warm += best;
        if (!st) st = lm_predict(sp, im.our_gray, faces[k].box, pts_bt601);
        if (st) {
            fprintf(stderr, "%s: predictor failed\n", faces[k].image);
            return 1;
        }
        set_stats *s = set_of(sets, &nsets, faces[k].image);
        double before = all_rounded.sum;
        lm_stats_add(&all_rounded, pts, faces[k].dlib, 1);
        lm_stats_add(&all_raw, pts, faces[k].dlib, 0);
        lm_stats_add(&all_bt601, pts_bt601, faces[k].dlib, 1);
        lm_stats_add(&s->rounded, pts, faces[k].dlib, 1);
        lm_stats_add(&s->bt601, pts_bt601, faces[k].dlib, 1);
        s->faces++;
        if (all_rounded.sum == before) {
            identical++;
            s->identical++;
        }
    }
    lm_image_clear(&im);
    double cold_us = 1e6 * cold / (double)n, warm_us = 1e6 * warm / (double)n;
    printf("model load: %.3f s\n", load_s);
    printf("faces: %ld (dlib's HOG boxes over all photos)\n", n);
    printf("time per face, single thread: dlib %.1f us, ours %.1f us (image read before each call, as dlib_ref "
           "does) -> dlib/ours = %.2fx; ours warm (same face again) %.1f us\n",
           dlib_us, cold_us, dlib_us / cold_us, warm_us);
    printf("identical boxes, dlib's (r+g+b)/3 gray: %ld of %ld faces identical; rounded points: mean %.4f px, max "
           "%.4f px; unrounded: mean %.4f px, max %.4f px\n",
           identical, n, lm_stats_mean(&all_rounded), all_rounded.max, lm_stats_mean(&all_raw), all_raw.max);
    printf("identical boxes, our BT.601 gray: rounded points: mean %.4f px, max %.4f px\n", lm_stats_mean(&all_bt601),
           all_bt601.max);
    printf("%-40s %6s %9s %22s %22s\n", "set", "faces", "identical", "dlib gray mean/max px", "BT.601 mean/max px");
    for (int i = 0; i < nsets; i++)
        printf("%-40s %6ld %9ld %10.4f %10.4f  %10.4f %10.4f\n", sets[i].name, sets[i].faces, sets[i].identical,
               lm_stats_mean(&sets[i].rounded), sets[i].rounded.max, lm_stats_mean(&sets[i].bt601),
               sets[i].bt601.max);
    free(faces);
    fr_shape_predictor_free(sp);
    frig_ctx_free(ctx);
    return 0;
}
