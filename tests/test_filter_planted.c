/* Planted-failure experiment for the filter stage (section 4.2, Algorithm 1): take good landmark
 * detections (dlib's own 68-point model, ../shared/tools/dlib_ref.cpp) on real photos of one
 * person, corrupt a known share of them (jaw contour drifted, eyes shifted, another person's face
 * pasted in, an occluding patch painted over the eyes or mouth), run failure detection on shapes
 * only, textures only and both, and measure precision and recall of the dropped set.
 *
 *   test_filter_planted          the test: 60 frames of one video, 20% planted, 5 seeds, asserts floors
 *   test_filter_planted --full   the benchmark table: every photo set, rates 10-30%, 5 seeds, and
 *                                the runtime for 100 photos (bench/filter_planted.sh runs it)
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <cjson/cJSON.h>

#include "core/context.h"
#include "core/rng.h"
#include "filter/contact_sheet.h"
#include "filter/face_warp.h"
#include "filter/failure_detection.h"
#include "filter/robust_pca.h"
#include "image/image.h"
#include "testing.h"

#define LM 136
#define MAX_PHOTOS 128

enum { JAW, EYES, PASTE, OCCLUDE, KINDS };
static const char *kind_names[KINDS] = {"jaw drift", "eyes shifted", "other face", "occluded"};

/* A good detection: the face region cropped from the photo (gray) and its landmarks in the crop. */
typedef struct face {
    frig_image *img;
    double lm[LM];
} face;

typedef struct face_set {
    const char *name;
    int count;
    face faces[MAX_PHOTOS];
} face_set;

static double now(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return t.tv_sec + 1e-9 * t.tv_nsec;
}

static double iod(const double *lm) { return hypot(lm[90] - lm[72], lm[91] - lm[73]); }

/* ---- good detections from dlib ------------------------------------------------------------ */

static int cmp_str(const void *a, const void *b) { return strcmp(*(char *const *)a, *(char *const *)b); }

/* Up to 'want' photos of the folder, evenly spread over its sorted JPEG/PNG files. */
static int list_photos(const char *dir, int want, char **out) {
    char cmd[4600];
    snprintf(cmd, sizeof cmd, "ls '%s' | grep -i -E '\\.(jpg|jpeg|png)$' | sort", dir);
    FILE *p = popen(cmd, "r");
    if (!p) return 0;
    char *all[1024], line[1024];
    int n = 0;
    while (n < 1024 && fgets(line, sizeof line, p)) {
        line[strcspn(line, "\n")] = 0;
        all[n] = malloc(strlen(dir) + strlen(line) + 2);
        sprintf(all[n++], "%s/%s", dir, line);
    }
    pclose(p);
    qsort(all, (size_t)n, sizeof *all, cmp_str);
    int k = 0;
    for (int i = 0; i < want && i < n; i++) out[k++] = strdup(all[(long)i * n / (want < n ? want : n)]);
    for (int i = 0; i < n; i++) free(all[i]);
    return k;
}

/* Run dlib_ref on the photos (or read its cached output) and keep, per photo, the landmarks of the
 * largest face. Writes landmarks (LM per photo) and found[i] = 1 when a face was found. */
static int dlib_landmarks(const char *tool, const char *cache, int n, char **paths, double *lm, int *found) {
    char *cmd = malloc(8192 + (size_t)n * 1100);
    FILE *p = NULL;
    int cached = cache && test_file_exists(cache);
    if (cached) {
        p = fopen(cache, "r");
    } else {
        int len = sprintf(cmd, "'%s' /usr/share/dlib/shape_predictor_68_face_landmarks.dat", tool);
        for (int i = 0; i < n; i++) len += sprintf(cmd + len, " '%s'", paths[i]);
        sprintf(cmd + len, " 2>/dev/null%s%s%s", cache ? " | tee '" : "", cache ? cache : "", cache ? "'" : "");
        p = cache ? popen(cmd, "r") : test_ref_open(cmd); /* a bench run's cache, or the suite's */
    }
    free(cmd);
    if (!p) return 0;
    double *area = calloc((size_t)n, sizeof(double));
    memset(found, 0, sizeof(int) * n);
    char *line = malloc(1 << 16);
    while (fgets(line, 1 << 16, p)) {
        cJSON *j = cJSON_Parse(line);
        cJSON *img = cJSON_GetObjectItem(j, "image"), *box = cJSON_GetObjectItem(j, "box"),
              *pts = cJSON_GetObjectItem(j, "landmarks");
        int i = 0;
        while (img && i < n && strcmp(paths[i], img->valuestring) != 0) i++;
        if (i < n && cJSON_GetArraySize(box) == 4 && cJSON_GetArraySize(pts) == 68) {
            double a = (cJSON_GetArrayItem(box, 2)->valuedouble - cJSON_GetArrayItem(box, 0)->valuedouble) *
                       (cJSON_GetArrayItem(box, 3)->valuedouble - cJSON_GetArrayItem(box, 1)->valuedouble);
            if (!found[i] || a > area[i]) {
                found[i] = 1;
                area[i] = a;
                for (int k = 0; k < 68; k++) {
                    cJSON *q = cJSON_GetArrayItem(pts, k);
                    lm[(size_t)i * LM + 2 * k] = cJSON_GetArrayItem(q, 0)->valuedouble;
                    lm[(size_t)i * LM + 2 * k + 1] = cJSON_GetArrayItem(q, 1)->valuedouble;
                }
            }
        }
        cJSON_Delete(j);
    }
    free(line);
    free(area);
    if (cached)
        fclose(p);
    else if (cache)
        pclose(p);
    else
        test_ref_close(p);
    return 1;
}

/* The face region (landmark box grown by its size on each side, within the photo) as a gray crop. */
static frig_image *crop_face(const frig_image *img, double *lm) {
    double x0 = 1e9, y0 = 1e9, x1 = -1e9, y1 = -1e9;
    for (int k = 0; k < 68; k++) {
        x0 = fmin(x0, lm[2 * k]), x1 = fmax(x1, lm[2 * k]);
        y0 = fmin(y0, lm[2 * k + 1]), y1 = fmax(y1, lm[2 * k + 1]);
    }
    double s = fmax(x1 - x0, y1 - y0);
    int cx0 = (int)fmax(0, floor(x0 - s)), cy0 = (int)fmax(0, floor(y0 - s));
    int cx1 = (int)fmin(img->width, ceil(x1 + s)), cy1 = (int)fmin(img->height, ceil(y1 + s));
    frig_image *c = fr_image_new(cx1 - cx0, cy1 - cy0, 1);
    if (!c) return NULL;
    for (int y = 0; y < c->height; y++)
        memcpy(c->pixels + (size_t)y * c->stride, img->pixels + (size_t)(y + cy0) * img->stride + cx0,
               (size_t)c->width);
    for (int k = 0; k < 68; k++) lm[2 * k] -= cx0, lm[2 * k + 1] -= cy0;
    return c;
}

/* Good detections of up to 'want' photos of a set under ../shared/photos. */
static int load_set(frig_ctx *ctx, const char *tool, const char *name, int want, const char *cache, face_set *set) {
    char dir[4096], *paths[MAX_PHOTOS];
    snprintf(dir, sizeof dir, "%s", test_shared_path("photos"));
    snprintf(dir + strlen(dir), sizeof dir - strlen(dir), "/%s", name);
    set->name = name;
    set->count = 0;
    int n = list_photos(dir, want < MAX_PHOTOS ? want : MAX_PHOTOS, paths);
    double *lm = malloc(sizeof(double) * LM * (size_t)(n > 0 ? n : 1));
    int found[MAX_PHOTOS];
    int ok = n > 0 && dlib_landmarks(tool, cache, n, paths, lm, found);
    for (int i = 0; ok && i < n; i++) {
        frig_image *img = NULL;
        if (!found[i] || frig_image_load(ctx, paths[i], FRIG_LOAD_GRAY | FRIG_LOAD_IGNORE_ORIENTATION, &img))
            continue;
        face *f = &set->faces[set->count];
        memcpy(f->lm, lm + (size_t)i * LM, sizeof f->lm);
        f->img = crop_face(img, f->lm);
        frig_image_free(img);
        if (f->img) set->count++;
    }
    for (int i = 0; i < n; i++) free(paths[i]);
    free(lm);
    return set->count;
}

static void free_set(face_set *set) {
    for (int i = 0; i < set->count; i++) frig_image_free(set->faces[i].img);
    set->count = 0;
}

/* ---- corruption ------------------------------------------------------------------------------ */

static int cmp_double(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double uniform(fr_rng *r, double lo, double hi) { return lo + (hi - lo) * fr_rng_uniform(r); }

/* The jaw contour of one side slides off the jaw line (outwards onto the background or inwards
 * onto the cheek), by up to 0.25-0.5 inter-ocular distances at the ear end. */
static void corrupt_jaw(fr_rng *r, double *lm) {
    double cx = 0, cy = 0, d = iod(lm), amp = uniform(r, 0.25, 0.5) * d * (fr_rng_uniform(r) < 0.5 ? -1 : 1);
    for (int k = 0; k < 68; k++) cx += lm[2 * k] / 68, cy += lm[2 * k + 1] / 68;
    int left = fr_rng_uniform(r) < 0.5;
    for (int j = left ? 0 : 9; j <= (left ? 7 : 16); j++) {
        double t = abs(j - 8) / 8.0, ux = lm[2 * j] - cx, uy = lm[2 * j + 1] - cy, u = hypot(ux, uy);
        lm[2 * j] += amp * t * ux / u;
        lm[2 * j + 1] += amp * t * uy / u;
    }
}

/* Both eyes' six points moved up (onto the brows) or down (onto the cheeks) by 0.12-0.25 IOD. */
static void corrupt_eyes(fr_rng *r, double *lm) {
    double d = iod(lm), dy = uniform(r, 0.12, 0.25) * d * (fr_rng_uniform(r) < 0.5 ? -1 : 1);
    double dx = uniform(r, -0.1, 0.1) * d;
    /* along the face's own axes */
    double ax = (lm[90] - lm[72]) / d, ay = (lm[91] - lm[73]) / d;
    for (int k = 36; k < 48; k++) {
        lm[2 * k] += dx * ax - dy * ay;
        lm[2 * k + 1] += dx * ay + dy * ax;
    }
}

/* A flat or noisy patch painted over the eyes or the mouth (landmarks unchanged). */
static frig_image *corrupt_occlude(fr_rng *r, const face *f) {
    frig_image *c = fr_image_new(f->img->width, f->img->height, 1);
    memcpy(c->pixels, f->img->pixels, c->stride * (size_t)c->height);
    int eyes = fr_rng_uniform(r) < 0.5, first = eyes ? 36 : 48, last = eyes ? 47 : 67;
    double x0 = 1e9, y0 = 1e9, x1 = -1e9, y1 = -1e9, pad = 0.15 * iod(f->lm);
    for (int k = first; k <= last; k++) {
        x0 = fmin(x0, f->lm[2 * k]), x1 = fmax(x1, f->lm[2 * k]);
        y0 = fmin(y0, f->lm[2 * k + 1]), y1 = fmax(y1, f->lm[2 * k + 1]);
    }
    int flat = fr_rng_uniform(r) < 0.5, level = (int)fr_rng_below(r, 256);
    for (int y = (int)fmax(0, y0 - pad); y <= (int)fmin(c->height - 1, y1 + pad); y++)
        for (int x = (int)fmax(0, x0 - pad); x <= (int)fmin(c->width - 1, x1 + pad); x++)
            c->pixels[(size_t)y * c->stride + x] = (uint8_t)(flat ? (uint64_t)level : fr_rng_below(r, 256));
    return c;
}

/* ---- one trial --------------------------------------------------------------------------------- */

enum { SHAPE_ONLY, TEXTURE_ONLY, BOTH, CONFIGS };
static const char *config_names[CONFIGS] = {"shape only", "texture only", "both"};

typedef struct tally {
    long tp, fp, fn, runs, rounds;
    long kind_tp[KINDS], kind_n[KINDS];
    double auc; /* summed over runs: ROC area of the first round's errors (planted vs good) */
} tally;

typedef struct trial_data {
    int n, texels;
    double *textures, *shapes;
    int planted[MAX_PHOTOS]; /* -1 or the kind */
} trial_data;

/* Build the data matrices of a set with a share 'rate' of its photos corrupted (kinds in turn,
 * from a random start), donors giving the pasted faces. */
static int make_trial(frig_ctx *ctx, const fr_face_warp *warp, const face_set *set, const face_set *donors,
                      uint64_t seed, double rate, trial_data *t) {
    fr_rng r;
    fr_rng_seed(&r, seed);
    int n = set->count, P = fr_face_warp_texels(warp), order[MAX_PHOTOS];
    t->n = n;
    t->texels = P;
    t->textures = malloc(sizeof(double) * (size_t)P * n);
    t->shapes = malloc(sizeof(double) * LM * (size_t)n);
    double *lms = malloc(sizeof(double) * LM * (size_t)n);
    for (int i = 0; i < n; i++) order[i] = i, t->planted[i] = -1;
    for (int i = n - 1; i > 0; i--) {
        int j = (int)fr_rng_below(&r, (uint64_t)i + 1), s = order[i];
        order[i] = order[j];
        order[j] = s;
    }
    int planted = (int)lround(rate * n), kind0 = (int)fr_rng_below(&r, KINDS);
    for (int j = 0; j < planted; j++) t->planted[order[j]] = (kind0 + j) % KINDS;
    int ok = 1;
    for (int i = 0; i < n && ok; i++) {
        const face *f = &set->faces[i];
        double *lm = lms + (size_t)i * LM;
        memcpy(lm, f->lm, sizeof f->lm);
        const frig_image *img = f->img;
        frig_image *own = NULL;
        switch (t->planted[i]) {
        case JAW: corrupt_jaw(&r, lm); break;
        case EYES: corrupt_eyes(&r, lm); break;
        case PASTE: {
            const face *d = &donors->faces[fr_rng_below(&r, (uint64_t)donors->count)];
            memcpy(lm, d->lm, sizeof d->lm);
            img = d->img;
            break;
        }
        case OCCLUDE: img = own = corrupt_occlude(&r, f); break;
        default: break;
        }
        ok = fr_face_texture(ctx, warp, img, lm, t->textures + (size_t)i * P, NULL) == FRIG_OK;
        frig_image_free(own);
    }
    ok = ok && fr_filter_align_shapes(ctx, n, lms, t->shapes, NULL) == FRIG_OK;
    free(lms);
    return ok;
}

static void free_trial(trial_data *t) {
    free(t->textures);
    free(t->shapes);
}

static int run_config(frig_ctx *ctx, const trial_data *t, int config, const fr_filter_options *opt, tally *out,
                      fr_filter_result *res) {
    int rounds = 0;
    frig_status st = fr_failure_detection(ctx, t->n, t->texels, config == SHAPE_ONLY ? NULL : t->textures,
                                          config == TEXTURE_ONLY ? NULL : t->shapes, opt, res, &rounds, NULL);
    if (st != FRIG_OK) {
        fprintf(stderr, "failure detection: %s\n", frig_ctx_errmsg(ctx));
        return 0;
    }
    out->runs++;
    out->rounds += rounds;
    /* How well the first round's errors alone separate planted from good photos. */
    fr_filter_options first = *opt;
    first.max_rounds = 1;
    first.omega = 1e6;
    fr_filter_result r1[MAX_PHOTOS];
    if (fr_failure_detection(ctx, t->n, t->texels, config == SHAPE_ONLY ? NULL : t->textures,
                             config == TEXTURE_ONLY ? NULL : t->shapes, &first, r1, NULL, NULL) != FRIG_OK)
        return 0;
    long pairs = 0, above = 0;
    for (int i = 0; i < t->n; i++)
        for (int j = 0; j < t->n; j++)
            if (t->planted[i] >= 0 && t->planted[j] < 0) {
                pairs += 2;
                above += r1[i].error > r1[j].error ? 2 : r1[i].error == r1[j].error;
            }
    out->auc += pairs ? (double)above / pairs : 1.0;
    for (int i = 0; i < t->n; i++) {
        int dropped = res[i].round_dropped > 0, k = t->planted[i];
        out->tp += dropped && k >= 0;
        out->fp += dropped && k < 0;
        out->fn += !dropped && k >= 0;
        if (k >= 0) out->kind_n[k]++, out->kind_tp[k] += dropped;
    }
    return 1;
}

static double precision(const tally *t) { return t->tp + t->fp ? (double)t->tp / (t->tp + t->fp) : 1.0; }
static double recall(const tally *t) { return t->tp + t->fn ? (double)t->tp / (t->tp + t->fn) : 1.0; }

/* Seeds 1..seeds at the given rate; tallies per configuration. */
static int run_trials(frig_ctx *ctx, const fr_face_warp *warp, const face_set *set, const face_set *donors,
                      double rate, int seeds, const fr_filter_options *opt, tally tallies[CONFIGS]) {
    memset(tallies, 0, sizeof(tally) * CONFIGS);
    fr_filter_result res[MAX_PHOTOS];
    for (int s = 1; s <= seeds; s++) {
        trial_data t;
        if (!make_trial(ctx, warp, set, donors, (uint64_t)s * 7919 + (uint64_t)(rate * 1000), rate, &t)) {
            free_trial(&t);
            return 0;
        }
        for (int c = 0; c < CONFIGS; c++)
            if (!run_config(ctx, &t, c, opt, &tallies[c], res)) {
                free_trial(&t);
                return 0;
            }
        free_trial(&t);
    }
    return 1;
}

static void print_tallies(const char *set, double rate, int seeds, const tally tallies[CONFIGS]) {
    for (int c = 0; c < CONFIGS; c++) {
        const tally *t = &tallies[c];
        printf("%-34s %3.0f%% %d seeds  %-12s  precision %.3f  recall %.3f  (tp %ld fp %ld fn %ld, rounds %.1f)",
               set, 100 * rate, seeds, config_names[c], precision(t), recall(t), t->tp, t->fp, t->fn,
               t->runs ? (double)t->rounds / t->runs : 0.0);
        printf("  AUC %.3f  recall by kind:", t->runs ? t->auc / t->runs : 0.0);
        for (int k = 0; k < KINDS; k++)
            printf(" %s %.2f", kind_names[k], t->kind_n[k] ? (double)t->kind_tp[k] / t->kind_n[k] : NAN);
        printf("\n");
    }
}

/* ---- the test ---------------------------------------------------------------------------------- */

static const char *dlib_tool(void) {
    const char *tool = getenv("FRIG_DLIB_REF");
    if (tool && *tool && test_file_exists(tool)) return tool;
    static char path[4096];
    snprintf(path, sizeof path, "%s/tools/dlib_ref", FRIG_BINARY_DIR);
    return test_file_exists(path) ? path : NULL;
}

/* A window of 'photos' consecutive faces of the set from its share 'at' (a small album): the faces
 * are the set's own (not copied). */
static void set_window(const face_set *set, int photos, double at, face_set *out) {
    int n = photos < set->count ? photos : set->count, first = (int)(at * set->count);
    if (first + n > set->count) first = set->count - n;
    out->name = set->name;
    out->count = n;
    for (int i = 0; i < n; i++) out->faces[i] = set->faces[first + i];
}

/* Small albums: windows of 10 consecutive frames (one planted failure in each), judged with the
 * default filter and with the peeling rounds of Algorithm 1 as printed (filter.peel_min_faces 3). */
static void small_windows(frig_ctx *ctx, const fr_face_warp *warp, const face_set *set, const face_set *donors,
                          int peel_min, tally out[CONFIGS]) {
    fr_filter_options opt;
    fr_filter_options_from_ctx(ctx, &opt);
    opt.peel_min = peel_min;
    memset(out, 0, sizeof(tally) * CONFIGS);
    for (int w = 0; w < 6; w++) {
        face_set window;
        set_window(set, 10, w / 6.0, &window);
        tally t[CONFIGS];
        CHECK(run_trials(ctx, warp, &window, donors, 0.1, 5, &opt, t));
        for (int c = 0; c < CONFIGS; c++) out[c].tp += t[c].tp, out[c].fp += t[c].fp, out[c].fn += t[c].fn;
    }
    printf("10-frame windows, filter.peel_min_faces %d: both tp %ld fp %ld fn %ld\n", peel_min, (long)out[BOTH].tp,
           (long)out[BOTH].fp, (long)out[BOTH].fn);
}

static int test_mode(frig_ctx *ctx, const char *tool) {
    face_set *set = calloc(1, sizeof *set), *donors = calloc(1, sizeof *donors);
    if (load_set(ctx, tool, "video_sadtalker_WDA_KatieHill_000", 60, NULL, set) < 55 ||
        load_set(ctx, tool, "lfw_colin_powell", 12, NULL, donors) < 8) {
        fprintf(stderr, "too few faces found: %d and %d\n", set->count, donors->count);
        test_failures++;
    } else {
        fr_face_warp *warp = NULL;
        CHECK(fr_face_warp_create(ctx, fr_param_int(ctx, FRIG_PARAM_FILTER_TEXTURE_SIZE), &warp) == FRIG_OK);
        fr_filter_options opt;
        fr_filter_options_from_ctx(ctx, &opt);
        tally clean[CONFIGS], planted[CONFIGS];
        CHECK(run_trials(ctx, warp, set, donors, 0.0, 1, &opt, clean));
        print_tallies(set->name, 0.0, 1, clean);
        CHECK(run_trials(ctx, warp, set, donors, 0.2, 5, &opt, planted));
        print_tallies(set->name, 0.2, 5, planted);
        /* Floors from the measured figures with margin (60 frames, 12 planted per seed, 5 seeds;
         * measured at filter.omega 4: both P 0.93 R 0.83, texture only P 1.00 R 0.67, shape only
         * P 0.71 R 0.77, 2 of 60 clean frames dropped; at 3, the default until 2026-12-07: both P
         * 0.77 R 0.93, texture only P 0.98 R 0.92, 5 clean frames dropped). Shapes alone cannot see
         * occlusions (a quarter of the planted failures), and their heavy-tailed errors drop good
         * frames. The looser limit misses occlusions that 3 caught (docs/filter.md). */
        CHECK(recall(&planted[BOTH]) >= 0.75);
        CHECK(precision(&planted[BOTH]) >= 0.8);
        CHECK(recall(&planted[TEXTURE_ONLY]) >= 0.6);
        CHECK(precision(&planted[TEXTURE_ONLY]) >= 0.85);
        CHECK(recall(&planted[SHAPE_ONLY]) >= 0.6);
        CHECK(planted[SHAPE_ONLY].kind_tp[JAW] == planted[SHAPE_ONLY].kind_n[JAW]);
        CHECK(planted[SHAPE_ONLY].kind_tp[EYES] == planted[SHAPE_ONLY].kind_n[EYES]);
        CHECK(clean[BOTH].fp <= 5);
        CHECK(clean[TEXTURE_ONLY].fp <= 4);
        tally peeled[CONFIGS], small[CONFIGS];
        small_windows(ctx, warp, set, donors, 3, peeled);
        small_windows(ctx, warp, set, donors, fr_param_int(ctx, FRIG_PARAM_FILTER_PEEL_MIN_FACES), small);
        /* Measured (30 windows, 30 planted) at filter.omega 4: peeling rounds tp 27 fp 39, the default tp
         * 27 fp 13 (at 3: tp 28 fp 55 and tp 27 fp 19). */
        CHECK(recall(&small[BOTH]) >= 0.8);
        CHECK(small[BOTH].fp <= 25);
        CHECK(peeled[BOTH].fp >= 2 * small[BOTH].fp);
        fr_face_warp_free(warp);
    }
    free_set(set);
    free_set(donors);
    free(set);
    free(donors);
    return test_result("test_filter_planted");
}

/* ---- the benchmark ------------------------------------------------------------------------------ */

static const char *all_sets[] = {"video_sadtalker_WDA_KatieHill_000", "video_liveportrait_d6", "lfw_george_w_bush",
                                 "lfw_colin_powell", "lfw_tony_blair", "bing_mel_gibson", "bing_will_smith"};
#define N_SETS (int)(sizeof all_sets / sizeof all_sets[0])

static void bench_runtime(frig_ctx *ctx, const face_set *set) {
    fr_face_warp *warp = NULL;
    fr_face_warp_create(ctx, fr_param_int(ctx, FRIG_PARAM_FILTER_TEXTURE_SIZE), &warp);
    int n = set->count, P = fr_face_warp_texels(warp);
    double *tex = malloc(sizeof(double) * (size_t)P * n), *lms = malloc(sizeof(double) * LM * n),
           *shapes = malloc(sizeof(double) * LM * n);
    fr_filter_result *res = malloc(sizeof *res * n);
    /* Each stage 5 times; the median time (the machine is shared). */
    double tw[5], tp[5], ta[5];
    fr_filter_options opt;
    fr_filter_options_from_ctx(ctx, &opt);
    int rounds = 0;
    for (int rep = 0; rep < 5; rep++) {
        double t0 = now();
        for (int i = 0; i < n; i++)
            fr_face_texture(ctx, warp, set->faces[i].img, set->faces[i].lm, tex + (size_t)i * P, NULL);
        double t1 = now();
        for (int i = 0; i < n; i++) memcpy(lms + (size_t)i * LM, set->faces[i].lm, sizeof(double) * LM);
        fr_filter_align_shapes(ctx, n, lms, shapes, NULL);
        double t2 = now();
        fr_failure_detection(ctx, n, P, tex, shapes, &opt, res, &rounds, NULL);
        double t3 = now();
        tw[rep] = t1 - t0, tp[rep] = t2 - t1, ta[rep] = t3 - t2;
    }
    qsort(tw, 5, sizeof(double), cmp_double);
    qsort(tp, 5, sizeof(double), cmp_double);
    qsort(ta, 5, sizeof(double), cmp_double);
    printf("\nruntime, %d photos of %s (texture %dx%d, %d texels; decoding not counted; median of 5):\n", n,
           set->name, fr_face_warp_size(warp), fr_face_warp_size(warp), P);
    printf("  warp + normalize %.1f ms, Procrustes %.2f ms, Algorithm 1 (%d rounds) %.1f ms, total %.1f ms\n",
           1e3 * tw[2], 1e3 * tp[2], rounds, 1e3 * ta[2], 1e3 * (tw[2] + tp[2] + ta[2]));
    /* How much the robust PCA tolerance moves the first round's errors. */
    fr_filter_options first = opt;
    first.max_rounds = 1;
    first.omega = 1e6;
    fr_filter_result *ref = malloc(sizeof *ref * n);
    first.rpca.tol = 1e-9;
    fr_failure_detection(ctx, n, P, tex, shapes, &first, ref, NULL, NULL);
    for (double tol = 1e-4; tol >= 1e-8; tol /= 10) {
        first.rpca.tol = tol;
        double a = now();
        fr_failure_detection(ctx, n, P, tex, shapes, &first, res, NULL, NULL);
        double b = now(), d = 0, spread = 0;
        for (int i = 0; i < n; i++) d = fmax(d, fabs(res[i].error - ref[i].error)), spread += ref[i].error / n;
        printf("  one round with robust PCA tolerance %.0e: %.1f ms, errors within %.1e of tolerance 1e-9 "
               "(mean error %.3f)\n",
               tol, 1e3 * (b - a), d, spread);
    }
    free(ref);
    /* Robust PCA of the texture matrix: singular value thresholding by Gram matrix vs thin SVD. */
    double *L = malloc(sizeof(double) * (size_t)P * n), *S = malloc(sizeof(double) * (size_t)P * n);
    int saved = fr_blas_serial_begin(); /* as inside the filter */
    for (int m = FR_SVT_SVD; m <= FR_SVT_GRAM; m++) {
        fr_rpca_options o = opt.rpca;
        o.svt = (fr_svt_method)m;
        fr_rpca_info info;
        double a = now();
        fr_robust_pca(ctx, P, n, tex, P, &o, L, S, &info);
        double b = now();
        printf("  robust PCA of the %d x %d texture matrix, SVT by %s: %.1f ms (%d iterations, rank %d, "
               "%.1f%% of S nonzero)\n",
               P, n, m == FR_SVT_SVD ? "LAPACK dgesdd" : "Gram + dsyevd", 1e3 * (b - a), info.iterations,
               info.rank, 100.0 * info.nonzeros / ((double)P * n));
    }
    fr_blas_serial_end(saved);
    free(L);
    free(S);
    free(tex);
    free(lms);
    free(shapes);
    free(res);
    fr_face_warp_free(warp);
}

static int bench_mode(frig_ctx *ctx, const char *tool, const char *sheet_dir, const char *only, int seeds,
                      int photos) {
    face_set *sets = calloc(N_SETS, sizeof *sets);
    for (int s = 0; s < N_SETS; s++) {
        /* the set itself, or the donor of a chosen set */
        if (only && !strstr(only, all_sets[s]) && !strstr(only, all_sets[(s + N_SETS - 2) % N_SETS])) continue;
        char cache[4096];
        snprintf(cache, sizeof cache, "%s/tools/lm_%s.jsonl", FRIG_BINARY_DIR, all_sets[s]);
        double t = now();
        load_set(ctx, tool, all_sets[s], 100, cache, &sets[s]);
        printf("%s: %d faces (%.1f s)\n", all_sets[s], sets[s].count, now() - t);
    }
    fr_face_warp *warp = NULL;
    fr_face_warp_create(ctx, fr_param_int(ctx, FRIG_PARAM_FILTER_TEXTURE_SIZE), &warp);
    fr_filter_options opt;
    fr_filter_options_from_ctx(ctx, &opt);
    if (getenv("FILTER_PLAIN")) opt.robust = 0; /* plain PCA instead of robust PCA, for comparison */
    static const double rates[] = {0.0, 0.1, 0.2, 0.3};
    tally total[4][CONFIGS];
    memset(total, 0, sizeof total);
    printf("\nplanted failures (%s, omega %g, %s, w_t %g, w_s %g, energy %g, texture %d):\n",
           opt.robust ? "robust PCA" : "plain PCA", opt.omega,
           opt.statistic == FR_FILTER_MEDIAN_MAD ? "median/MAD" : "mean/std", opt.w_texture, opt.w_shape,
           opt.pca_energy, fr_face_warp_size(warp));
    for (int s = 0; s < N_SETS; s++)
        for (int ri = 0; ri < 4; ri++) {
            if ((only && !strstr(only, all_sets[s])) || seeds < 1) continue;
            tally t[CONFIGS];
            for (int w = 0; w < (photos > 0 ? 4 : 1); w++) {
                face_set window;
                if (photos > 0) set_window(&sets[s], photos, 0.25 * w, &window);
                run_trials(ctx, warp, photos > 0 ? &window : &sets[s], &sets[(s + 2) % N_SETS], rates[ri],
                           ri == 0 ? 1 : seeds, &opt, t);
                print_tallies(sets[s].name, rates[ri], ri == 0 ? 1 : seeds, t);
                for (int c = 0; c < CONFIGS; c++) {
                    total[ri][c].tp += t[c].tp, total[ri][c].fp += t[c].fp, total[ri][c].fn += t[c].fn;
                    total[ri][c].runs += t[c].runs, total[ri][c].rounds += t[c].rounds, total[ri][c].auc += t[c].auc;
                    for (int k = 0; k < KINDS; k++)
                        total[ri][c].kind_tp[k] += t[c].kind_tp[k], total[ri][c].kind_n[k] += t[c].kind_n[k];
                }
            }
        }
    printf("\nall sets:\n");
    for (int ri = 0; ri < 4; ri++) print_tallies("all sets", rates[ri], ri == 0 ? 1 : seeds, total[ri]);
    if (sheet_dir && sets[0].count) {
        /* A contact sheet of one planted trial of the first set. */
        trial_data t;
        fr_filter_result res[MAX_PHOTOS];
        if (make_trial(ctx, warp, &sets[0], &sets[2], 1, 0.2, &t)) {
            int rounds;
            fr_failure_detection(ctx, t.n, t.texels, t.textures, t.shapes, &opt, res, &rounds, NULL);
            int dropped[MAX_PHOTOS];
            for (int i = 0; i < t.n; i++) dropped[i] = res[i].round_dropped;
            frig_image *sheet = NULL;
            char path[4200];
            snprintf(path, sizeof path, "%s/filter_contact_sheet.png", sheet_dir);
            if (fr_contact_sheet(ctx, warp, t.n, t.textures, dropped, NULL, 0.6, 10, &sheet) == FRIG_OK &&
                frig_image_save_png(ctx, sheet, path) == FRIG_OK)
                printf("\ncontact sheet: %s\n", path);
            frig_image_free(sheet);
        }
        free_trial(&t);
    }
    if (sets[0].count) bench_runtime(ctx, &sets[0]);
    for (int s = 0; s < N_SETS; s++) free_set(&sets[s]);
    free(sets);
    fr_face_warp_free(warp);
    return 0;
}

static void log_to_stderr(void *user, frig_log_level level, const char *message) {
    (void)user;
    (void)level;
    fprintf(stderr, "  %s\n", message);
}

int main(int argc, char **argv) {
    const char *tool = dlib_tool();
    if (!tool) return test_skip("dlib_ref was not built (needs libdlib-dev: scripts/install-deps.sh --test)");
    if (!test_file_exists("/usr/share/dlib/shape_predictor_68_face_landmarks.dat"))
        return test_skip("dlib's landmark model is missing (libdlib-data)");
    if (!test_file_exists(test_shared_path("photos/video_sadtalker_WDA_KatieHill_000")))
        return test_skip("../shared/photos is missing");
    frig_ctx *ctx = frig_ctx_create();
    if (getenv("FRIG_TEST_VERBOSE")) frig_ctx_set_log(ctx, log_to_stderr, NULL, FRIG_LOG_DEBUG);
    /* Arguments: --full, --sheet DIR, and parameters as name=value (filter.omega=3). */
    int full = 0, seeds = 5, photos = 0;
    const char *sheet = NULL, *only = NULL;
    for (int a = 1; a < argc; a++) {
        char name[128];
        double value;
        frig_param p;
        if (strcmp(argv[a], "--full") == 0)
            full = 1;
        else if (strcmp(argv[a], "--sheet") == 0 && a + 1 < argc)
            sheet = argv[++a];
        else if (strcmp(argv[a], "--sets") == 0 && a + 1 < argc)
            only = argv[++a];
        else if (strcmp(argv[a], "--seeds") == 0 && a + 1 < argc)
            seeds = atoi(argv[++a]);
        else if (strcmp(argv[a], "--photos") == 0 && a + 1 < argc)
            photos = atoi(argv[++a]);
        else if (sscanf(argv[a], "%127[^=]=%lf", name, &value) == 2 && frig_param_lookup(ctx, name, &p) == FRIG_OK &&
                 frig_ctx_set_param(ctx, p, value) == FRIG_OK)
            continue;
        else {
            fprintf(stderr, "usage: %s [--full] [--sheet DIR] [--sets A,B] [--seeds N] [--photos N] [name=value ...]: %s\n",
                    argv[0], frig_ctx_errmsg(ctx));
            frig_ctx_free(ctx);
            return 2;
        }
    }
    int rc = full ? bench_mode(ctx, tool, sheet, only, seeds, photos) : test_mode(ctx, tool);
    frig_ctx_free(ctx);
    return rc;
}
