/* Face boxes against OpenCV: our cascade evaluator and OpenCV 4.6's detectMultiScale (Debian's
 * python3-opencv, run through shared/tools/opencv_ref.py) on photos of every set, box by box, for
 * the frontal cascades and the profile cascade; raw windows in OpenCV's order; neighbour counts and
 * level weights (detectMultiScale2/3); the pyramid resize bit for bit on random images. Without
 * OpenCV it still checks the integral images, resize and grouping against their definitions. */
#include <dirent.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <cjson/cJSON.h>

#include "core/context.h"
#include "detect/cascade.h"
#include "frig/image.h"
#include "testing.h"

#define PY "/usr/bin/python3"
#define CASCADES "/usr/share/opencv4/"
#define MAX_PHOTOS 128
#define MAX_BOXES 256

static frig_ctx *ctx;

static double now(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static uint64_t rng_state = 0x2545f4914f6cdd1dull;
static uint32_t rnd(void) {
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return (uint32_t)(rng_state >> 32);
}

/* ---- the parts, against their definitions ---- */

static void check_integral(void) {
    enum { W = 13, H = 11, S = 16 };
    uint8_t img[W * H];
    for (int i = 0; i < W * H; i++) img[i] = (uint8_t)rnd();
    uint32_t sum[(H + 1) * S], sq[(H + 1) * S], tilt[(H + 1) * S];
    uint32_t *scratch = malloc(sizeof(uint32_t) * fr_cascade_tilted_scratch(W, H));
    fr_cascade_integral(img, W, H, W, sum, sq, S);
    fr_cascade_integral_tilted(img, W, H, W, tilt, S, scratch);
    int bad = 0;
    for (int Y = 0; Y <= H; Y++)
        for (int X = 0; X <= W; X++) {
            uint32_t s = 0, q = 0, t = 0;
            for (int y = 0; y < H; y++)
                for (int x = 0; x < W; x++) {
                    uint32_t v = img[y * W + x];
                    if (y < Y && x < X) s += v, q += v * v;
                    if (y < Y && abs(x - X + 1) <= Y - y - 1) t += v;
                }
            bad += sum[Y * S + X] != s || sq[Y * S + X] != q || tilt[Y * S + X] != t;
        }
    CHECK(bad == 0);
    free(scratch);
}

static void check_resize_definition(void) {
    enum { W = 37, H = 23 };
    uint8_t img[W * H], out[W * H];
    for (int i = 0; i < W * H; i++) img[i] = (uint8_t)rnd();
    CHECK(fr_cascade_resize(img, W, H, W, out, W, H, W) == 0 && memcmp(img, out, sizeof img) == 0);
    /* an exact halving is the rounded mean of each 2x2 block */
    int bad = 0;
    CHECK(fr_cascade_resize(img, 36, 22, W, out, 18, 11, 18) == 0);
    for (int y = 0; y < 11; y++)
        for (int x = 0; x < 18; x++) {
            const uint8_t *p = img + 2 * y * W + 2 * x;
            bad += out[y * 18 + x] != (p[0] + p[1] + p[W] + p[W + 1] + 2) >> 2;
        }
    CHECK(bad == 0);
    memset(img, 77, sizeof img);
    CHECK(fr_cascade_resize(img, W, H, W, out, 20, 13, 20) == 0);
    bad = 0;
    for (int i = 0; i < 20 * 13; i++) bad += out[i] != 77;
    CHECK(bad == 0);
}

static void check_grouping(void) {
    fr_cascade_box b[8] = {0};
    for (int i = 0; i < 5; i++) b[i] = (fr_cascade_box){100 + i, 50, 40, 40, 1, 10.0 + i};
    b[5] = (fr_cascade_box){300, 300, 40, 40, 1, 3.0};                 /* alone */
    b[6] = (fr_cascade_box){110, 60, 20, 20, 1, 1.0};                  /* inside the group, weaker */
    b[7] = (fr_cascade_box){111, 61, 20, 20, 1, 1.0};
    fr_cascade_box g[8];
    memcpy(g, b, sizeof b);
    CHECK(fr_cascade_group(g, 8, 0, 0.2) == 8 && g[5].neighbors == 1);
    memcpy(g, b, sizeof b);
    long n = fr_cascade_group(g, 8, 1, 0.2);
    /* the 5-box group (mean x 102) survives, the lone box does not, the 2-box group inside it is dropped */
    CHECK(n == 1 && g[0].x == 102 && g[0].y == 50 && g[0].w == 40 && g[0].neighbors == 5 && g[0].weight == 14.0);
}

/* ---- OpenCV's answers ---- */

typedef struct answer {
    int n;
    int box[MAX_BOXES][4];
    int neighbors[MAX_BOXES];
    double weight[MAX_BOXES];
} answer;

static int have_opencv(void) {
    return test_file_exists(PY) && test_file_exists(test_shared_path("tools/opencv_ref.py")) &&
           test_file_exists(CASCADES "haarcascades/haarcascade_frontalface_alt2.xml") &&
           system(PY " -c 'import cv2' >/dev/null 2>&1") == 0;
}

/* Photos of every set: 'per_set' spread over each folder (0: all); under the sanitizers (10x slower)
 * every third of them. */
static int list_photos(char paths[][512], int max) {
    static const struct {
        const char *dir;
        int per_set;
    } sets[] = {{"lfw_george_w_bush", 6},  {"lfw_colin_powell", 6},
                {"lfw_tony_blair", 6},      {"video_sadtalker_WDA_KatieHill_000", 4},
                {"video_liveportrait_d6", 4}, {"landmarks_300w_lfpw", 0},
                {"landmarks_300w_mmpose_tests", 0}, {"landmarks_dlib_examples_faces_predicted", 0},
                {"outliers", 8},            {"bing_mel_gibson", 2},
                {"bing_will_smith", 2}};
    int n = 0;
    for (size_t s = 0; s < sizeof sets / sizeof *sets; s++) {
        char dir[512];
        snprintf(dir, sizeof dir, "%s", test_shared_path("photos"));
        snprintf(dir + strlen(dir), sizeof dir - strlen(dir), "/%s", sets[s].dir);
        DIR *d = opendir(dir);
        if (!d) continue;
        char names[256][128];
        int k = 0;
        struct dirent *e;
        while ((e = readdir(d)) && k < 256) {
            const char *dot = strrchr(e->d_name, '.');
            if (dot && (!strcmp(dot, ".jpg") || !strcmp(dot, ".png")) && strlen(e->d_name) < 128)
                strcpy(names[k++], e->d_name);
        }
        closedir(d);
        qsort(names, (size_t)k, sizeof names[0], (int (*)(const void *, const void *))strcmp);
        int take = sets[s].per_set ? sets[s].per_set : k;
        for (int i = 0; i < take && i < k && n < max; i++)
            snprintf(paths[n++], 512, "%s/%s", dir, names[(size_t)i * (size_t)k / (size_t)take]);
    }
    return n;
}

static int find_image(char paths[][512], int n, const char *name) {
    for (int i = 0; i < n; i++)
        if (!strcmp(paths[i], name)) return i;
    return -1;
}

static void read_int_array(const cJSON *arr, int *out, int max) {
    int i = 0;
    const cJSON *v;
    cJSON_ArrayForEach(v, arr) if (i < max) out[i++] = v->valueint;
}

/* Start a reference command over the photos (it runs while we compute ours); its answers come
 * from the reference cache when 'answers' (test_ref_open), not when it writes files of its own. */
static FILE *start_reference(const char *cmd_head, char paths[][512], int n, int answers) {
    size_t len = strlen(cmd_head) + 16;
    for (int i = 0; i < n; i++) len += strlen(paths[i]) + 3;
    char *cmd = malloc(len);
    strcpy(cmd, cmd_head);
    for (int i = 0; i < n; i++) strcat(strcat(strcat(cmd, " '"), paths[i]), "'");
    FILE *p = answers ? test_ref_open(cmd) : popen(cmd, "r");
    free(cmd);
    return p;
}

/* Its answers: one JSON object per line with "image" and "boxes" (maybe "neighbors", "weights").
 * Returns the number of images answered. */
static int finish_reference(FILE *p, char paths[][512], int n, answer *ans) {
    static char line[1 << 16];
    int got = 0;
    for (int i = 0; i < n; i++) ans[i].n = -1;
    while (p && fgets(line, sizeof line, p)) {
        cJSON *j = cJSON_Parse(line);
        const cJSON *img = cJSON_GetObjectItem(j, "image"), *boxes = cJSON_GetObjectItem(j, "boxes");
        int i = img && cJSON_IsString(img) ? find_image(paths, n, img->valuestring) : -1;
        if (i >= 0 && boxes) {
            answer *a = &ans[i];
            a->n = 0;
            const cJSON *b, *v;
            cJSON_ArrayForEach(b, boxes) if (a->n < MAX_BOXES) read_int_array(b, a->box[a->n++], 4);
            read_int_array(cJSON_GetObjectItem(j, "neighbors"), a->neighbors, MAX_BOXES);
            int k = 0;
            cJSON_ArrayForEach(v, cJSON_GetObjectItem(j, "weights")) if (k < MAX_BOXES) a->weight[k++] = v->valuedouble;
            got++;
        }
        cJSON_Delete(j);
    }
    if (p) test_ref_close(p);
    return got;
}

static frig_status run_ours(const fr_cascade *c, const char *path, double scale, int neighbors, int min_size,
                            answer *a) {
    frig_image *img = NULL;
    frig_status s = frig_image_load(ctx, path, FRIG_LOAD_GRAY | FRIG_LOAD_IGNORE_ORIENTATION, &img);
    if (s) return s;
    fr_cascade_box *b = NULL;
    size_t n = 0;
    s = fr_cascade_detect(ctx, c, frig_image_pixels(img), frig_image_width(img), frig_image_height(img),
                          frig_image_stride(img), scale, neighbors, min_size, min_size, 0, 0, &b, &n);
    a->n = 0;
    for (size_t i = 0; i < n && i < MAX_BOXES; i++, a->n++) {
        a->box[i][0] = b[i].x, a->box[i][1] = b[i].y, a->box[i][2] = b[i].w, a->box[i][3] = b[i].h;
        a->neighbors[i] = b[i].neighbors;
        a->weight[i] = b[i].weight;
    }
    free(b);
    frig_image_free(img);
    return s;
}

static double iou(const int *a, const int *b) {
    int x0 = a[0] > b[0] ? a[0] : b[0], y0 = a[1] > b[1] ? a[1] : b[1];
    int x1 = a[0] + a[2] < b[0] + b[2] ? a[0] + a[2] : b[0] + b[2];
    int y1 = a[1] + a[3] < b[1] + b[3] ? a[1] + a[3] : b[1] + b[3];
    double in = x1 > x0 && y1 > y0 ? (double)(x1 - x0) * (y1 - y0) : 0;
    return in / ((double)a[2] * a[3] + (double)b[2] * b[3] - in);
}

/* Share of a's boxes that b has (IoU >= 0.9), summed over images. */
static void matched(const answer *a, const answer *b, int n, int *hits, int *total) {
    for (int i = 0; i < n; i++)
        for (int k = 0; k < a[i].n; k++) {
            int found = 0;
            for (int m = 0; m < b[i].n && !found; m++) found = iou(a[i].box[k], b[i].box[m]) >= 0.9;
            *hits += found;
            (*total)++;
        }
}

static int same_list(const answer *a, const answer *b) {
    return a->n == b->n && (a->n == 0 || memcmp(a->box, b->box, sizeof(int) * 4 * (size_t)a->n) == 0);
}

/* Box agreement over the photos for one cascade and setting; returns 0 when the reference failed. */
static int compare_cascade(const char *cascade, double scale, int neighbors, int min_size, char paths[][512],
                           int n) {
    char head[1024];
    snprintf(head, sizeof head, PY " '%s' --cascade '%s%s' --scale %g --neighbors %d --min-size %d 2>/dev/null",
             test_shared_path("tools/opencv_ref.py"), CASCADES, cascade, scale, neighbors, min_size);
    answer *ref = calloc((size_t)n, sizeof *ref), *ours = calloc((size_t)n, sizeof *ours);
    FILE *job = start_reference(head, paths, n, 1);
    fr_cascade *c = NULL;
    char cpath[512];
    snprintf(cpath, sizeof cpath, CASCADES "%s", cascade);
    CHECK(fr_cascade_load(ctx, cpath, &c) == FRIG_OK);
    int exact = 0, hr = 0, tr = 0, ho = 0, to = 0;
    double t0 = now();
    for (int i = 0; i < n && c; i++) CHECK(run_ours(c, paths[i], scale, neighbors, min_size, &ours[i]) == FRIG_OK);
    double t1 = now();
    int answered = finish_reference(job, paths, n, ref);
    printf("  (ours %.1f s, then waited %.1f s for OpenCV)\n", t1 - t0, now() - t1);
    for (int i = 0; i < n && c; i++) {
        if (ref[i].n < 0) continue;
        exact += same_list(&ref[i], &ours[i]);
        if (!same_list(&ref[i], &ours[i])) fprintf(stderr, "  differs: %s\n", paths[i]);
    }
    matched(ref, ours, n, &hr, &tr);
    matched(ours, ref, n, &ho, &to);
    printf("%-48s scale %.2f nb %d min %3d: %d photos, identical lists %d; OpenCV boxes %d, ours have %d; "
           "ours %d, OpenCV has %d\n",
           cascade, scale, neighbors, min_size, answered, exact, tr, hr, to, ho);
    CHECK(answered == n);
    CHECK(hr >= 0.98 * tr && ho >= 0.98 * to);
    CHECK(exact >= 0.95 * n);
    fr_cascade_free(c);
    free(ref);
    free(ours);
    return answered == n;
}

/* Raw windows (no grouping) in OpenCV's order, on a few photos. */
static void compare_raw(char paths[][512], int n) {
    answer *ref = calloc((size_t)n, sizeof *ref), *ours = calloc((size_t)n, sizeof *ours);
    char head[1024];
    snprintf(head, sizeof head, PY " '%s' --neighbors 0 --min-size 30 2>/dev/null",
             test_shared_path("tools/opencv_ref.py"));
    FILE *job = start_reference(head, paths, n, 1);
    fr_cascade *c = NULL;
    CHECK(fr_cascade_load(ctx, CASCADES "haarcascades/haarcascade_frontalface_alt2.xml", &c) == FRIG_OK);
    for (int i = 0; i < n && c; i++) run_ours(c, paths[i], 1.1, 0, 30, &ours[i]);
    finish_reference(job, paths, n, ref);
    int same = 0;
    for (int i = 0; i < n && c; i++) {
        same += ref[i].n < MAX_BOXES && ours[i].n < MAX_BOXES && same_list(&ref[i], &ours[i]);
    }
    printf("raw windows (min_neighbors 0): identical ordered lists on %d of %d photos\n", same, n);
    CHECK(same == n);
    fr_cascade_free(c);
    free(ref);
    free(ours);
}

/* detectMultiScale2's neighbour counts and detectMultiScale3's level weights. */
static const char *SCORES_PY =
    "import cv2, json, sys\n"
    "cv2.setNumThreads(1)\n"
    "cc = cv2.CascadeClassifier(sys.argv[1])\n"
    "for p in sys.argv[2:]:\n"
    "    g = cv2.imread(p, cv2.IMREAD_IGNORE_ORIENTATION | cv2.IMREAD_GRAYSCALE)\n"
    "    b, n = cc.detectMultiScale2(g, 1.1, 3, 0, (30, 30))\n"
    "    b3, lv, w = cc.detectMultiScale3(g, 1.1, 3, 0, (30, 30), outputRejectLevels=True)\n"
    "    ok = [list(map(int, x)) for x in b] == [list(map(int, x)) for x in b3]\n"
    "    print(json.dumps({'image': p, 'boxes': [list(map(int, x)) for x in b] if ok else [],\n"
    "                      'neighbors': [int(x) for x in n], 'weights': [float(x) for x in w]}))\n";

static void compare_scores(char paths[][512], int n) {
    const char *dir = test_temp_dir("cascade_scores");
    char script[600], head[1200];
    snprintf(script, sizeof script, "%s/scores.py", dir);
    FILE *fp = fopen(script, "w");
    if (!fp) return;
    fputs(SCORES_PY, fp);
    fclose(fp);
    snprintf(head, sizeof head, PY " '%s' " CASCADES "haarcascades/haarcascade_frontalface_alt2.xml 2>/dev/null",
             script);
    answer *ref = calloc((size_t)n, sizeof *ref), *ours = calloc((size_t)n, sizeof *ours);
    FILE *job = start_reference(head, paths, n, 1);
    fr_cascade *c = NULL;
    CHECK(fr_cascade_load(ctx, CASCADES "haarcascades/haarcascade_frontalface_alt2.xml", &c) == FRIG_OK);
    for (int i = 0; i < n && c; i++) run_ours(c, paths[i], 1.1, 3, 30, &ours[i]);
    finish_reference(job, paths, n, ref);
    int boxes = 0, bad = 0;
    for (int i = 0; i < n && c; i++) {
        if (!same_list(&ref[i], &ours[i])) {
            bad++;
            continue;
        }
        for (int k = 0; k < ours[i].n; k++, boxes++)
            bad += ours[i].neighbors[k] != ref[i].neighbors[k] || fabs(ours[i].weight[k] - ref[i].weight[k]) > 1e-6;
    }
    printf("neighbour counts and level weights: %d boxes, %d disagreements\n", boxes, bad);
    CHECK(bad == 0 && boxes > 0);
    fr_cascade_free(c);
    free(ref);
    free(ours);
}

/* The pyramid resize against cv2.resize(INTER_LINEAR_EXACT), on random images and sizes. */
static const char *RESIZE_PY =
    "import cv2, sys\n"
    "d = sys.argv[1]\n"
    "for line in open(d + '/cases.txt'):\n"
    "    i, dw, dh = map(int, line.split())\n"
    "    g = cv2.imread('%s/in%d.png' % (d, i), cv2.IMREAD_GRAYSCALE)\n"
    "    open('%s/out%d.raw' % (d, i), 'wb').write(cv2.resize(g, (dw, dh), interpolation=cv2.INTER_LINEAR_EXACT)"
    ".tobytes())\n";

static void compare_resize(void) {
    enum { CASES = 60 };
    const char *dir = test_temp_dir("cascade_resize");
    char path[600];
    int sw[CASES], sh[CASES], dw[CASES], dh[CASES];
    snprintf(path, sizeof path, "%s/cases.txt", dir);
    FILE *cases = fopen(path, "w");
    if (!cases) return;
    for (int i = 0; i < CASES; i++) {
        sw[i] = 2 + (int)(rnd() % (i < 40 ? 120 : 900));
        sh[i] = 2 + (int)(rnd() % 120);
        double f = pow(1.1, 1 + rnd() % 24);
        dw[i] = (int)lrint(sw[i] / f), dh[i] = (int)lrint(sh[i] / f);
        if (dw[i] < 1) dw[i] = 1;
        if (dh[i] < 1) dh[i] = 1;
        frig_image *img = NULL;
        frig_image_create(ctx, sw[i], sh[i], 1, &img);
        uint8_t *px = frig_image_pixels_mutable(img);
        for (int y = 0; y < sh[i]; y++)
            for (int x = 0; x < sw[i]; x++) px[(size_t)y * frig_image_stride(img) + x] = (uint8_t)(rnd() >> 8);
        snprintf(path, sizeof path, "%s/in%d.png", dir, i);
        CHECK(frig_image_save_png(ctx, img, path) == FRIG_OK);
        frig_image_free(img);
        fprintf(cases, "%d %d %d\n", i, dw[i], dh[i]);
    }
    fclose(cases);
    char script[600];
    snprintf(script, sizeof script, "%s/resize.py", dir);
    FILE *fp = fopen(script, "w");
    if (!fp) return;
    fputs(RESIZE_PY, fp);
    fclose(fp);
    char cmd[1400];
    snprintf(cmd, sizeof cmd, PY " '%s' '%s'", script, dir);
    CHECK(system(cmd) == 0);
    int same = 0;
    for (int i = 0; i < CASES; i++) {
        frig_image *img = NULL;
        snprintf(path, sizeof path, "%s/in%d.png", dir, i);
        if (frig_image_load(ctx, path, FRIG_LOAD_GRAY, &img)) continue;
        size_t n = (size_t)dw[i] * (size_t)dh[i];
        uint8_t *ours = malloc(n), *ref = malloc(n);
        snprintf(path, sizeof path, "%s/out%d.raw", dir, i);
        FILE *rf = fopen(path, "rb");
        if (rf && fread(ref, 1, n, rf) == n &&
            fr_cascade_resize(frig_image_pixels(img), sw[i], sh[i], frig_image_stride(img), ours, dw[i], dh[i],
                              (size_t)dw[i]) == 0)
            same += memcmp(ours, ref, n) == 0;
        if (rf) fclose(rf);
        free(ours);
        free(ref);
        frig_image_free(img);
    }
    printf("resize: %d of %d random cases identical to cv2.resize(INTER_LINEAR_EXACT)\n", same, CASES);
    CHECK(same == CASES);
}

/* Our gray photo (FRIG_LOAD_GRAY | FRIG_LOAD_IGNORE_ORIENTATION) is cv2's IMREAD_GRAYSCALE image:
 * libjpeg's luma for JPEG, libpng's 0.299/0.587 conversion for PNG. */
static const char *GRAY_PY =
    "import cv2, struct, sys\n"
    "for i, p in enumerate(sys.argv[2:]):\n"
    "    g = cv2.imread(p, cv2.IMREAD_IGNORE_ORIENTATION | cv2.IMREAD_GRAYSCALE)\n"
    "    open('%s/gray%d.raw' % (sys.argv[1], i), 'wb').write(struct.pack('<ii', g.shape[1], g.shape[0]) + g.tobytes())\n";

static void compare_gray(char paths[][512], int n) {
    const char *dir = test_temp_dir("cascade_gray");
    char script[600], head[1400], path[700];
    snprintf(script, sizeof script, "%s/gray.py", dir);
    FILE *fp = fopen(script, "w");
    if (!fp) return;
    fputs(GRAY_PY, fp);
    fclose(fp);
    snprintf(head, sizeof head, PY " '%s' '%s'", script, dir);
    FILE *job = start_reference(head, paths, n, 0);
    if (job) pclose(job);
    int same = 0, pngs = 0;
    for (int i = 0; i < n; i++) {
        frig_image *img = NULL;
        snprintf(path, sizeof path, "%s/gray%d.raw", dir, i);
        FILE *rf = fopen(path, "rb");
        int32_t wh[2] = {0, 0};
        if (!rf || fread(wh, sizeof(int32_t), 2, rf) != 2 ||
            frig_image_load(ctx, paths[i], FRIG_LOAD_GRAY | FRIG_LOAD_IGNORE_ORIENTATION, &img)) {
            if (rf) fclose(rf);
            continue;
        }
        int ok = wh[0] == frig_image_width(img) && wh[1] == frig_image_height(img);
        uint8_t *row = malloc((size_t)wh[0] + 1);
        for (int y = 0; ok && y < wh[1]; y++)
            ok = fread(row, 1, (size_t)wh[0], rf) == (size_t)wh[0] &&
                 memcmp(row, frig_image_pixels(img) + (size_t)y * frig_image_stride(img), (size_t)wh[0]) == 0;
        same += ok;
        pngs += strstr(paths[i], ".png") != NULL;
        free(row);
        fclose(rf);
        frig_image_free(img);
    }
    printf("gray images: %d of %d photos (%d PNG) identical to cv2's IMREAD_GRAYSCALE\n", same, n, pngs);
    CHECK(same == n && pngs > 0);
}

/* Two threads on one cascade give the serial answers. */
static void check_threads(char paths[][512], int n) {
    fr_cascade *c = NULL;
    if (fr_cascade_load(ctx, CASCADES "haarcascades/haarcascade_frontalface_alt2.xml", &c)) return;
    answer *serial = calloc((size_t)n, sizeof *serial);
    for (int i = 0; i < n; i++) run_ours(c, paths[i], 1.1, 3, 30, &serial[i]);
    int bad = 0;
#pragma omp parallel num_threads(2) reduction(+ : bad)
    {
        frig_ctx *tctx = frig_ctx_create();
#pragma omp for schedule(dynamic, 1)
        for (int i = 0; i < n; i++) {
            frig_image *img = NULL;
            fr_cascade_box *b = NULL;
            size_t nb = 0;
            if (frig_image_load(tctx, paths[i], FRIG_LOAD_GRAY | FRIG_LOAD_IGNORE_ORIENTATION, &img) ||
                fr_cascade_detect(tctx, c, frig_image_pixels(img), frig_image_width(img), frig_image_height(img),
                                  frig_image_stride(img), 1.1, 3, 30, 30, 0, 0, &b, &nb))
                bad++;
            else if ((int)nb != serial[i].n)
                bad++;
            else
                for (size_t k = 0; k < nb; k++)
                    bad += b[k].x != serial[i].box[k][0] || b[k].y != serial[i].box[k][1] ||
                           b[k].w != serial[i].box[k][2] || b[k].weight != serial[i].weight[k];
            free(b);
            frig_image_free(img);
        }
        frig_ctx_free(tctx);
    }
    CHECK(bad == 0);
    fr_cascade_free(c);
    free(serial);
}

int main(void) {
    ctx = frig_ctx_create();
    check_integral();
    check_resize_definition();
    check_grouping();
    static char paths[MAX_PHOTOS][512];
    int n = list_photos(paths, MAX_PHOTOS);
    int enough = n >= 60;
#if defined(__SANITIZE_ADDRESS__)
    for (int i = 0; i < n; i += 3) memmove(paths[i / 3], paths[i], 512);
    n = (n + 2) / 3;
#endif
    if (!have_opencv() || !enough) {
        frig_ctx_free(ctx);
        if (test_failures) return test_result("test_cascade");
        return test_skip("needs Debian's python3-opencv and opencv-data and ../shared/photos (install-deps --test)");
    }
    printf("%d photos from every set\n", n);
    compare_resize();
    compare_gray(paths, n);
    /* the default frontal cascade on every photo, each other one on a third of them (which still
     * spans every set) */
    static char third[3][MAX_PHOTOS][512], some[12][512];
    int nt[3] = {0, 0, 0};
    for (int i = 0; i < n; i++) memcpy(third[i % 3][nt[i % 3]++], paths[i], 512);
    for (int i = 0; i < 12; i++) memcpy(some[i], paths[(size_t)i * (size_t)n / 12], 512);
    compare_cascade("haarcascades/haarcascade_frontalface_alt2.xml", 1.1, 3, 30, paths, n);
    compare_cascade("haarcascades/haarcascade_profileface.xml", 1.1, 3, 30, third[0], nt[0]);
    compare_cascade("lbpcascades/lbpcascade_frontalface.xml", 1.1, 3, 30, third[1], nt[1]);
    compare_cascade("haarcascades/haarcascade_frontalface_default.xml", 1.2, 5, 50, third[2], nt[2]);
    compare_raw(paths, 4);
    compare_scores(some, 12);
    check_threads(some, 12);
    frig_ctx_free(ctx);
    return test_result("test_cascade");
}
