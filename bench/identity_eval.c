/* The identity step on sets built from ../shared/photos, with known answers: one person's photos
 * (a folder) with photos of other people planted (a share of the set), and composites of one of
 * the person's photos beside a photo of a stranger scaled up (the stranger's face larger, so
 * the old largest-face rule picks the stranger). Detection and descriptors run once (face-api's
 * SSD, two threads); the identity step then runs for each threshold. Prints, per threshold,
 * precision and recall of other_person over the planted photos, the share of the person's own
 * photos kept, and the composites whose subject is the person's face. The strangers of the
 * composites come from the first OTHER_DIR (photos framed like the person's: LFW crops).
 *   identity_eval [--threads N] [--planted SHARE] [--composites N] [--set NAME=VALUE] SUBJECT_DIR OTHER_DIR...
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <dirent.h>

#include "bench_param.h"
#include "core/context.h"
#include "frig/frig.h"
#include "image/image.h"
#include "workspace/photoset.h"

#define MAX_PHOTOS 4096

static double now(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return t.tv_sec + 1e-9 * t.tv_nsec;
}

static int by_name(const void *a, const void *b) { return strcmp(*(char *const *)a, *(char *const *)b); }

/* The folder's .jpg / .png files, sorted: a new array of new strings. */
static int list_dir(const char *dir, char **out, int max) {
    DIR *d = opendir(dir);
    int n = 0;
    for (struct dirent *e; d && (e = readdir(d)) && n < max;) {
        const char *dot = strrchr(e->d_name, '.');
        if (e->d_name[0] == '.' || !dot || (strcmp(dot, ".jpg") && strcmp(dot, ".png"))) continue;
        size_t len = strlen(dir) + strlen(e->d_name) + 2;
        out[n] = malloc(len);
        snprintf(out[n++], len, "%s/%s", dir, e->d_name);
    }
    if (d) closedir(d);
    qsort(out, (size_t)n, sizeof *out, by_name);
    return n;
}

/* A composite: the person's photo at 1x on the left, the stranger's at 2x beside it. */
static int composite(frig_ctx *ctx, const char *mine, const char *other, const char *out) {
    frig_image *a = NULL, *b = NULL, *c = NULL;
    int ok = !frig_image_load(ctx, mine, 0, &a) && !frig_image_load(ctx, other, 0, &b);
    int w = 0, h = 0;
    if (ok) {
        /* the stranger at twice the person's face scale: twice the person's photo size */
        double s = 2.0 * a->width / b->width;
        w = a->width + (int)(b->width * s) + 20;
        h = (int)fmax(a->height, b->height * s) + 20;
        ok = !frig_image_create(ctx, w, h, 3, &c);
        if (ok) {
            memset(c->pixels, 110, c->stride * (size_t)h);
            for (int y = 0; y < a->height; y++)
                memcpy(c->pixels + (size_t)(y + 10) * c->stride + 30, a->pixels + (size_t)y * a->stride,
                       (size_t)a->width * 3);
            int bw = (int)(b->width * s), bh = (int)(b->height * s);
            for (int y = 0; y < bh; y++)
                for (int x = 0; x < bw; x++) {
                    int sx = (int)(x / s), sy = (int)(y / s);
                    if (a->width + 10 + x >= w || y + 10 >= h) continue;
                    memcpy(c->pixels + (size_t)(y + 10) * c->stride + (size_t)(a->width + 10 + x) * 3,
                           b->pixels + (size_t)sy * b->stride + (size_t)sx * 3, 3);
                }
            ok = !frig_image_save_jpeg(ctx, c, out);
        }
    }
    frig_image_free(a), frig_image_free(b), frig_image_free(c);
    return ok;
}

int main(int argc, char **argv) {
    int threads = 2, n_comp = 8;
    double share = 0.1;
    int i = 1;
    frig_ctx *ctx = frig_ctx_create();
    for (; i + 1 < argc && argv[i][0] == '-'; i += 2) {
        if (!strcmp(argv[i], "--threads")) threads = atoi(argv[i + 1]);
        else if (!strcmp(argv[i], "--set") && bench_set_param(ctx, argv[i + 1])) return 2;
        else if (!strcmp(argv[i], "--planted")) share = atof(argv[i + 1]);
        else if (!strcmp(argv[i], "--composites")) n_comp = atoi(argv[i + 1]);
    }
    if (argc - i < 2) {
        fprintf(stderr, "usage: identity_eval [--threads N] [--planted SHARE] [--composites N] SUBJECT_DIR OTHER_DIR...\n");
        return 2;
    }
    static char *mine[MAX_PHOTOS], *others[MAX_PHOTOS];
    int n_mine = list_dir(argv[i], mine, MAX_PHOTOS), n_others = 0, n_first = 0;
    for (int k = i + 1; k < argc; k++) {
        n_others += list_dir(argv[k], others + n_others, MAX_PHOTOS - n_others);
        if (k == i + 1) n_first = n_others; /* composites take their strangers from the first folder */
    }
    /* planted: share of the final set, others taken evenly from the list */
    int n_plant = (int)lround(share * n_mine / (1 - share));
    if (n_plant > n_others) n_plant = n_others;
    frig_ctx_set_threads(ctx, threads);
    frig_detector *det = NULL;
    frig_ctx_set_param(ctx, FRIG_PARAM_DETECT_DETECTOR, 2);
    if (frig_detector_create(ctx, NULL, NULL, &det)) {
        fprintf(stderr, "%s\n", frig_ctx_errmsg(ctx));
        return 1;
    }
    char tmp[] = "/tmp/frig_identity_eval_XXXXXX";
    if (!mkdtemp(tmp)) return 1;
    frig_photoset *set = NULL;
    frig_photoset_create(ctx, &set);
    static int kind[MAX_PHOTOS]; /* 0 own, 1 planted, 2 composite */
    int n = 0;
    for (int k = 0; k < n_mine; k++) kind[n] = 0, frig_photoset_add(ctx, set, mine[k], NULL), n++;
    for (int k = 0; k < n_plant; k++)
        kind[n] = 1, frig_photoset_add(ctx, set, others[(size_t)k * (size_t)n_others / (size_t)n_plant], NULL), n++;
    for (int k = 0; k < n_comp && n_mine && n_first; k++) {
        char path[4200];
        snprintf(path, sizeof path, "%s/composite_%02d.jpg", tmp, k);
        if (!composite(ctx, mine[(k * 7 + 3) % n_mine], others[(k * 13 + 5) % n_first], path)) continue;
        kind[n] = 2, frig_photoset_add(ctx, set, path, NULL), n++;
    }
    double t0 = now();
    if (frig_detect_photoset(ctx, det, set)) {
        fprintf(stderr, "%s\n", frig_ctx_errmsg(ctx));
        return 1;
    }
    double t_detect = now() - t0;
    const char *dump = getenv("FRIG_EVAL_DUMP"); /* kind, photo, face, eye distance, 128 numbers per line */
    FILE *df = dump ? fopen(dump, "w") : NULL;
    for (int k = 0; df && k < n; k++)
        for (size_t f = 0; f < frig_photoset_face_count(set, (size_t)k); f++) {
            float d[FRIG_DESCRIPTOR_SIZE];
            double lm[136], b[4];
            if (frig_photoset_face_descriptor(set, (size_t)k, f, d) || frig_photoset_face_landmarks(set, (size_t)k, f, lm))
                continue;
            frig_photoset_face_box(set, (size_t)k, f, b);
            int w, h;
            frig_photoset_size(set, (size_t)k, &w, &h);
            fprintf(df, "%d %d %zu %.2f %d", kind[k], k, f, hypot(lm[72] - lm[90], lm[73] - lm[91]),
                    kind[k] == 2 ? b[0] + 0.5 * b[2] < w / 3.0 : -1);
            for (int j = 0; j < FRIG_DESCRIPTOR_SIZE; j++) fprintf(df, " %.7g", d[j]);
            fprintf(df, "\n");
        }
    if (df) fclose(df);
    /* the answer for composites: the person's face is the one left of the strip's divide */
    printf("set: %d of the person's photos (%s), %d planted, %d composites; detection + descriptors %.2f s "
           "(%d threads)\n",
           n_mine, argv[i], n_plant, n - n_mine - n_plant, t_detect, threads);
    printf("%9s %9s %9s %9s %9s %12s\n", "threshold", "precision", "recall", "own_kept", "own_usable", "composites");
    static const double thresholds[] = {0.4, 0.45, 0.5, 0.55, 0.6, 0.65, 0.7};
    for (size_t t = 0; t < sizeof thresholds / sizeof thresholds[0]; t++) {
        frig_ctx_set_param(ctx, FRIG_PARAM_IDENTITY_THRESHOLD, thresholds[t]);
        if (frig_identify_photoset(ctx, set)) {
            printf("%9.2f %s\n", thresholds[t], frig_ctx_errmsg(ctx));
            continue;
        }
        int tp = 0, fp = 0, fn = 0, own_ok = 0, own_usable = 0, comp_ok = 0, comp = 0;
        for (int k = 0; k < n; k++) {
            frig_photo_status s = frig_photoset_status(set, (size_t)k);
            int other = s == FRIG_PHOTO_OTHER_PERSON;
            int usable = s == FRIG_PHOTO_OK || other;
            if (kind[k] == 1) tp += other, fn += s == FRIG_PHOTO_OK;
            if (kind[k] == 0) fp += other, own_ok += s == FRIG_PHOTO_OK, own_usable += usable;
            if (kind[k] == 2) {
                comp++;
                long subj = frig_photoset_subject(set, (size_t)k);
                double box[4] = {1e9, 0, 0, 0};
                int w, h;
                frig_photoset_size(set, (size_t)k, &w, &h);
                if (subj >= 0) frig_photoset_face_box(set, (size_t)k, (size_t)subj, box);
                /* the person's photo occupies x in [30, 30 + its width): left of the stranger's */
                comp_ok += s == FRIG_PHOTO_OK && box[0] + 0.5 * box[2] < w / 3.0;
            }
        }
        if (getenv("FRIG_EVAL_VERBOSE") && thresholds[t] == 0.6)
            for (int k = 0; k < n; k++) {
                if (kind[k] == 0 && frig_photoset_status(set, (size_t)k) == FRIG_PHOTO_OK) continue;
                if (kind[k] == 1 && frig_photoset_status(set, (size_t)k) == FRIG_PHOTO_OTHER_PERSON) continue;
                printf("  %s %s: %s, %zu faces:", kind[k] == 2 ? "composite" : kind[k] ? "planted" : "own",
                       frig_photoset_path(set, (size_t)k), frig_photo_status_name(frig_photoset_status(set, (size_t)k)),
                       frig_photoset_face_count(set, (size_t)k));
                for (size_t f = 0; f < frig_photoset_face_count(set, (size_t)k); f++) {
                    double b[4];
                    frig_photoset_face_box(set, (size_t)k, f, b);
                    printf(" [x %.0f w %.0f %s d %.3f]", b[0], b[2],
                           frig_photoset_face_source(set, (size_t)k, f) == FRIG_FACE_SSD ? "ssd" : "cascade",
                           frig_photoset_face_identity_distance(set, (size_t)k, f));
                }
                printf("%s\n", frig_photoset_subject(set, (size_t)k) >= 0 ? "" : " (no subject)");
            }
        printf("%9.2f %9.3f %9.3f %5d/%-3d %9d %8d/%d\n", thresholds[t], tp + fp ? (double)tp / (tp + fp) : 1.0,
               tp + fn ? (double)tp / (tp + fn) : 1.0, own_ok, n_mine, own_usable, comp_ok, comp);
    }
    char cmd[4300];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmp);
    if (system(cmd) != 0) fprintf(stderr, "could not remove %s\n", tmp);
    frig_photoset_free(set);
    frig_detector_free(det);
    frig_ctx_free(ctx);
    for (int k = 0; k < n_mine; k++) free(mine[k]);
    for (int k = 0; k < n_others; k++) free(others[k]);
    return 0;
}
