/* dlib's 68-point shape predictor in C (lib/detect/shape_predictor*): the reader refuses
 * every damaged model (hand-made defects, every truncation and byte flip of a small model
 * written here, truncations and byte flips of the real .dat) without crashing; and on dlib's
 * own HOG boxes over a subset of every photo set, our points equal dlib's (dlib_ref, built on
 * the fly), with the normalized mean error against the iBUG ground truth reported. */
#include <dirent.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "detect/dlib_deserialize.h"
#include "detect/shape_predictor.h"
#include "io/file.h"
#include "landmark_ref.h"
#include "testing.h"

#define MODEL "/usr/share/dlib/shape_predictor_68_face_landmarks.dat"

static frig_ctx *ctx;

/* ---- a small writer of dlib's format, for models with chosen defects ---------------- */
typedef struct wbuf {
    unsigned char *p;
    size_t n, cap;
} wbuf;

static void put_byte(wbuf *b, unsigned v) {
    if (b->n == b->cap) {
        b->cap = b->cap ? 2 * b->cap : 256;
        b->p = realloc(b->p, b->cap);
        if (!b->p) abort();
    }
    b->p[b->n++] = (unsigned char)v;
}

static void put_magnitude(wbuf *b, uint64_t v, unsigned sign) {
    unsigned char bytes[8];
    unsigned n = 0;
    do {
        bytes[n++] = (unsigned char)(v & 0xFF);
        v >>= 8;
    } while (v);
    put_byte(b, n | sign);
    for (unsigned i = 0; i < n; i++) put_byte(b, bytes[i]);
}

static void put_uint(wbuf *b, uint64_t v) { put_magnitude(b, v, 0); }
static void put_int(wbuf *b, int64_t v) { put_magnitude(b, v < 0 ? (uint64_t)(-v) : (uint64_t)v, v < 0 ? 0x80 : 0); }

/* mantissa * 2^exponent with a 24-bit mantissa, low zero bytes dropped (as dlib writes it). */
static void put_float(wbuf *b, float f) {
    int e;
    double frac = frexp(f, &e);
    int64_t m = (int64_t)(frac * (double)(1 << 24));
    int64_t x = e - 24;
    for (int i = 0; i < 8 && (m & 0xFF) == 0; i++) {
        m >>= 8;
        x += 8;
    }
    put_int(b, m);
    put_int(b, x);
}

static void put_nan(wbuf *b) {
    put_int(b, 0);
    put_int(b, 32002);
}

static void put_column(wbuf *b, const float *v, size_t n) {
    put_int(b, -(int64_t)n);
    put_int(b, -1);
    for (size_t i = 0; i < n; i++) put_float(b, v[i]);
}

enum defect {
    OK_MODEL,
    BAD_VERSION,
    ODD_SHAPE,
    LEAF_COUNT,
    LEAF_SIZE,
    SPLIT_INDEX,
    ANCHOR_INDEX,
    DELTA_COUNT,
    LIST_COUNT,
    NAN_VALUE,
    DEFECTS
};

#define SYN_PARTS 3
#define SYN_CASCADES 2
#define SYN_TREES 2
#define SYN_FEATURES 5

/* A 3-point model: 2 cascades of 2 depth-2 trees over 5 feature pixels each. */
static wbuf synthetic_model(enum defect defect) {
    wbuf b = {0};
    const float shape[2 * SYN_PARTS] = {0.3f, 0.4f, 0.7f, 0.4f, 0.5f, 0.8f};
    put_int(&b, defect == BAD_VERSION ? 2 : 1);
    put_column(&b, shape, defect == ODD_SHAPE ? 5 : 6);
    put_uint(&b, SYN_CASCADES);
    for (int c = 0; c < SYN_CASCADES; c++) {
        put_uint(&b, SYN_TREES);
        for (int t = 0; t < SYN_TREES; t++) {
            put_uint(&b, 3);
            for (int s = 0; s < 3; s++) {
                put_uint(&b, defect == SPLIT_INDEX && c == 1 && t == 1 && s == 2 ? SYN_FEATURES : (unsigned)(s + t));
                put_uint(&b, (unsigned)(4 - s - c));
                put_float(&b, (float)(s - 1) * 7.5f);
            }
            int leaves = defect == LEAF_COUNT && c == 1 ? 3 : 4;
            put_uint(&b, (uint64_t)leaves);
            for (int l = 0; l < leaves; l++) {
                float v[2 * SYN_PARTS];
                for (int k = 0; k < 2 * SYN_PARTS; k++) v[k] = 0.01f * (float)((l + 1) * (k - 2) + c - t);
                if (defect == NAN_VALUE && c == 1 && l == 3) {
                    put_int(&b, -6);
                    put_int(&b, -1);
                    for (int k = 0; k < 6; k++) k == 4 ? put_nan(&b) : put_float(&b, v[k]);
                } else {
                    put_column(&b, v, defect == LEAF_SIZE && t == 1 ? 4 : 6);
                }
            }
        }
    }
    put_uint(&b, defect == LIST_COUNT ? SYN_CASCADES + 1 : SYN_CASCADES);
    for (int c = 0; c < SYN_CASCADES; c++) {
        put_uint(&b, SYN_FEATURES);
        for (int i = 0; i < SYN_FEATURES; i++) put_uint(&b, defect == ANCHOR_INDEX && i == 4 ? SYN_PARTS : (unsigned)(i % 3));
    }
    put_uint(&b, SYN_CASCADES);
    for (int c = 0; c < SYN_CASCADES; c++) {
        int n = defect == DELTA_COUNT && c == 1 ? SYN_FEATURES - 1 : SYN_FEATURES;
        put_uint(&b, (uint64_t)n);
        for (int i = 0; i < n; i++) {
            put_float(&b, 0.05f * (float)(i - 2));
            put_float(&b, -0.04f * (float)(i - c));
        }
    }
    return b;
}

/* A gray test image: a smooth pattern with an edge, so the trees take varied branches. */
static uint8_t *test_image(int w, int h) {
    uint8_t *g = malloc((size_t)w * (size_t)h);
    if (!g) abort();
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) g[(size_t)y * (size_t)w + (size_t)x] = (uint8_t)((x * 7 + y * 3 + (x > y ? 90 : 0)) & 0xFF);
    return g;
}

/* Parse 'data' and check the status is one of the allowed ones; when the model loads, run it
 * once (ASan watches the reads). Returns the status. */
static frig_status parse_and_run(const char *name, const unsigned char *data, size_t size) {
    fr_shape_predictor *sp = NULL;
    frig_ctx_clear_error(ctx);
    frig_status st = fr_shape_predictor_parse(ctx, name, data, size, &sp);
    CHECK(st == FRIG_OK || st == FRIG_ERR_CORRUPT || st == FRIG_ERR_TRUNCATED);
    if (st) {
        CHECK(sp == NULL);
        if (!strstr(frig_ctx_errmsg(ctx), name)) {
            fprintf(stderr, "message does not name the file: %s\n", frig_ctx_errmsg(ctx));
            test_failures++;
        }
        return st;
    }
    uint8_t *img = test_image(64, 48);
    const double box[4] = {10, 8, 50, 44};
    double out[2 * FR_SP_MAX_PARTS];
    CHECK(fr_shape_predictor_run(sp, img, 64, 48, 64, box, out) == FRIG_OK);
    free(img);
    fr_shape_predictor_free(sp);
    return st;
}

static void test_synthetic(void) {
    wbuf good = synthetic_model(OK_MODEL);
    fr_shape_predictor *sp = NULL;
    CHECK(fr_shape_predictor_parse(ctx, "synthetic.dat", good.p, good.n, &sp) == FRIG_OK);
    if (sp) {
        CHECK(sp->parts == SYN_PARTS && sp->cascades == SYN_CASCADES);
        CHECK(sp->tree_begin[SYN_CASCADES] == SYN_CASCADES * SYN_TREES);
        CHECK(sp->feature_begin[SYN_CASCADES] == SYN_CASCADES * SYN_FEATURES);
        CHECK_NEAR(sp->delta[2], -0.05f, 0);
        CHECK_NEAR(sp->initial_shape[5], 0.8f, 0);
        /* Bad arguments are refused, not crashed on. */
        uint8_t px[4] = {0};
        double box[4] = {0, 0, 1, 1}, out[2 * SYN_PARTS];
        CHECK(fr_shape_predictor_run(sp, NULL, 2, 2, 2, box, out) == FRIG_ERR_INVALID_ARGUMENT);
        CHECK(fr_shape_predictor_run(sp, px, 2, 2, 1, box, out) == FRIG_ERR_INVALID_ARGUMENT);
        box[2] = NAN;
        CHECK(fr_shape_predictor_run(sp, px, 2, 2, 2, box, out) == FRIG_ERR_INVALID_ARGUMENT);
        fr_shape_predictor_free(sp);
    }
    /* Each defect is named as corruption. */
    for (int d = BAD_VERSION; d < DEFECTS; d++) {
        wbuf bad = synthetic_model((enum defect)d);
        sp = NULL;
        frig_status st = fr_shape_predictor_parse(ctx, "defect.dat", bad.p, bad.n, &sp);
        if (st != FRIG_ERR_CORRUPT) {
            fprintf(stderr, "defect %d: status %d (%s)\n", d, st, frig_ctx_errmsg(ctx));
            test_failures++;
        }
        CHECK(sp == NULL);
        free(bad.p);
    }
    /* A compressed download is recognized as such. */
    const unsigned char bz[] = "BZh91AY&SY";
    CHECK(fr_shape_predictor_parse(ctx, "packed.dat", bz, sizeof bz - 1, &sp) == FRIG_ERR_CORRUPT);
    CHECK(strstr(frig_ctx_errmsg(ctx), "bzip2") != NULL);
    /* Every strict prefix is a truncation. */
    size_t bad_prefix = 0;
    for (size_t n = 0; n < good.n; n++)
        if (parse_and_run("prefix.dat", good.p, n) != FRIG_ERR_TRUNCATED) bad_prefix++;
    CHECK(bad_prefix == 0);
    /* Every byte flipped three ways: a status, never a crash. */
    unsigned char *m = malloc(good.n);
    if (!m) abort();
    size_t loaded = 0, refused = 0;
    const unsigned flips[3] = {0x01, 0x80, 0xFF};
    for (size_t i = 0; i < good.n; i++)
        for (int f = 0; f < 3; f++) {
            memcpy(m, good.p, good.n);
            m[i] ^= (unsigned char)flips[f];
            if (parse_and_run("flipped.dat", m, good.n) == FRIG_OK) loaded++;
            else refused++;
        }
    printf("synthetic model: %zu bytes, %zu prefixes truncated, flips: %zu loaded, %zu refused\n", good.n, good.n,
           loaded, refused);
    CHECK(refused > 0);
    free(m);
    free(good.p);
}

/* ---- the real model ----------------------------------------------------------------- */
static uint64_t splitmix(uint64_t *s) {
    uint64_t z = (*s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

static void test_real_structure(const fr_shape_predictor *sp) {
    CHECK(sp->parts == 68);
    CHECK(sp->cascades == 15);
    for (int c = 0; c < sp->cascades; c++) {
        CHECK(sp->tree_begin[c + 1] - sp->tree_begin[c] == 500);
        CHECK(sp->feature_begin[c + 1] - sp->feature_begin[c] == 500);
    }
    size_t trees = sp->tree_begin[sp->cascades];
    CHECK(sp->split_begin[trees] == 15 * trees); /* depth 4: 15 splits, 16 leaves */
}

static void test_real_mutations(const unsigned char *data, size_t size) {
    unsigned char *m = malloc(size);
    if (!m) abort();
    memcpy(m, data, size);
    const size_t cuts[] = {0, 1, 2, 5, 40, 1000, 1 << 20, size / 3, size / 2, size - 200000, size - 8, size - 1};
    size_t ncut = sizeof cuts / sizeof cuts[0], bad = 0;
    for (size_t i = 0; i < ncut; i++)
        if (parse_and_run("truncated.dat", data, cuts[i]) != FRIG_ERR_TRUNCATED) bad++;
    CHECK(bad == 0);
    /* Byte flips: the header and first tree, the anchor and delta lists at the end, and
     * anywhere (a seeded generator: the same positions every run). */
    uint64_t seed = 20140623;
    size_t loaded = 0, refused = 0;
    for (int k = 0; k < 24; k++) {
        size_t pos = k < 8 ? (size_t)(splitmix(&seed) % 64)
                           : k < 14 ? size - 1 - (size_t)(splitmix(&seed) % 120000) : (size_t)(splitmix(&seed) % size);
        m[pos] ^= (unsigned char)(1 + splitmix(&seed) % 255);
        if (parse_and_run("flipped.dat", m, size) == FRIG_OK) loaded++;
        else refused++;
        m[pos] = data[pos];
    }
    printf("real model: %zu truncations refused as truncated, 24 flips: %zu loaded, %zu refused\n", ncut, loaded,
           refused);
    free(m);
}

/* fr_dlib_read_floats (a tight loop) against fr_dlib_read_float one at a time: the same values
 * bit for bit, the same end position, the same status and message, on floats dlib writes,
 * odd but valid encodings (8-byte mantissas, 2-byte exponents, subnormal and huge results)
 * and defects (bad control bytes, an infinite exponent, a float overflowing, cut short). */
static void test_float_runs(void) {
    uint64_t seed = 77;
    for (int trial = 0; trial < 400; trial++) {
        wbuf b = {0};
        int n = 1 + (int)(splitmix(&seed) % 12);
        for (int i = 0; i < n; i++) {
            uint64_t kind = splitmix(&seed) % 10, r = splitmix(&seed);
            if (kind < 5) {
                put_float(&b, (float)((double)(int64_t)r / 9.2e18 * pow(2.0, (double)(int)(r % 60) - 30)));
            } else if (kind == 5) { /* a wide mantissa, a 2-byte exponent */
                put_int(&b, (int64_t)(r >> 1) * ((r & 1) ? -1 : 1));
                put_int(&b, -(int64_t)(70 + r % 200));
            } else if (kind == 6) { /* subnormal, overflowing or at the exponent limits */
                put_int(&b, (int64_t)(1 + r % 1000));
                static const int64_t ex[] = {-160, -149, 100, 127, 32767, -32768, 32000, 31999};
                put_int(&b, ex[r % 8]);
            } else if (kind == 7) { /* a bad control byte for the mantissa or the exponent */
                put_byte(&b, (r & 1) ? 0x10u | 1u : 0x09u);
                put_byte(&b, 1);
                put_int(&b, 0);
            } else if (kind == 8) {
                put_nan(&b);
            } else { /* INT64_MIN and 2^63 as mantissas */
                put_magnitude(&b, (uint64_t)1 << 63, (r & 1) ? 0x80 : 0);
                put_int(&b, 0);
            }
        }
        size_t cut = splitmix(&seed) % 3 ? b.n : (size_t)(splitmix(&seed) % (b.n + 1));
        float one[16] = {0}, run[16] = {0};
        frig_ctx *c1 = frig_ctx_create(), *c2 = frig_ctx_create();
        fr_dlib_reader r1, r2;
        fr_dlib_reader_init(&r1, c1, "f", b.p, cut);
        fr_dlib_reader_init(&r2, c2, "f", b.p, cut);
        for (int i = 0; i < n && !r1.status; i++) fr_dlib_read_float(&r1, "a value", &one[i]);
        fr_dlib_read_floats(&r2, "a value", (size_t)n, run);
        int same = r1.status == r2.status && r1.pos == r2.pos && !strcmp(frig_ctx_errmsg(c1), frig_ctx_errmsg(c2));
        for (int i = 0; i < n; i++) same &= memcmp(&one[i], &run[i], sizeof(float)) == 0;
        if (!same) printf("float run %d: status %d / %d, pos %zu / %zu\n", trial, r1.status, r2.status, r1.pos, r2.pos);
        CHECK(same);
        frig_ctx_free(c1), frig_ctx_free(c2);
        free(b.p);
    }
}

/* ---- against dlib ------------------------------------------------------------------- */
static int is_image(const char *name) {
    const char *dot = strrchr(name, '.');
    return dot && (!strcasecmp(dot, ".jpg") || !strcasecmp(dot, ".jpeg") || !strcasecmp(dot, ".png"));
}

static int by_name(const void *a, const void *b) { return strcmp(*(char *const *)a, *(char *const *)b); }

/* Names in 'dir' (sorted) that pass 'keep'; the caller frees each and the array. */
static size_t list_dir(const char *dir, int (*keep)(const char *), char ***out) {
    *out = NULL;
    DIR *d = opendir(dir);
    if (!d) return 0;
    size_t n = 0, cap = 0;
    char **v = NULL;
    struct dirent *e;
    while ((e = readdir(d))) {
        if (e->d_name[0] == '.' || !keep(e->d_name)) continue;
        if (n == cap) {
            cap = cap ? 2 * cap : 64;
            v = realloc(v, cap * sizeof *v);
            if (!v) abort();
        }
        v[n++] = strdup(e->d_name);
    }
    closedir(d);
    if (n) qsort(v, n, sizeof *v, by_name);
    *out = v;
    return n;
}

/* "a/b" into buf; aborts the test when it does not fit. */
static void join(char *buf, size_t size, const char *a, const char *b) {
    int r = snprintf(buf, size, "%s/%s", a, b);
    if (r < 0 || (size_t)r >= size) abort();
}

static int is_set(const char *name) { return strchr(name, '.') == NULL; }

static void free_list(char **v, size_t n) {
    for (size_t i = 0; i < n; i++) free(v[i]);
    free(v);
}

static void append(char **s, size_t *len, const char *piece) {
    size_t k = strlen(piece);
    char *t = realloc(*s, *len + k + 1);
    if (!t) abort();
    memcpy(t + *len, piece, k + 1);
    *s = t;
    *len += k;
}

/* Photos from every set: all of a small set (<= 20 images), 4 evenly spread from the others. */
static char *subset_arguments(const char *photos, int *count) {
    char **sets, *args = NULL;
    size_t len = 0, nsets = list_dir(photos, is_set, &sets);
    *count = 0;
    append(&args, &len, "");
    for (size_t s = 0; s < nsets; s++) {
        char dir[4096], **imgs;
        join(dir, sizeof dir, photos, sets[s]);
        size_t n = list_dir(dir, is_image, &imgs), take = n <= 20 ? n : 4;
        for (size_t k = 0; k < take; k++) {
            char piece[8300];
            snprintf(piece, sizeof piece, " '%s/%s'", dir, imgs[k * n / take]);
            append(&args, &len, piece);
            (*count)++;
        }
        free_list(imgs, n);
    }
    free_list(sets, nsets);
    return args;
}

/* NME of dlib's boxes + our predictor against the .pts ground truth of the GT sets. */
static void ground_truth_nme(const fr_shape_predictor *sp, const lm_face *faces, long n, const char *photos) {
    const char *sets[] = {"landmarks_300w_lfpw", "landmarks_300w_mmpose_tests", "outliers"};
    double sum_ours = 0, sum_dlib = 0, sum_bt601 = 0, worst_gap = 0;
    int scored = 0, missed = 0;
    lm_image im = {0};
    for (size_t s = 0; s < sizeof sets / sizeof sets[0]; s++) {
        char dir[4096], **imgs;
        join(dir, sizeof dir, photos, sets[s]);
        size_t ni = list_dir(dir, is_image, &imgs);
        for (size_t i = 0; i < ni; i++) {
            char path[8300], pts_path[8300];
            join(path, sizeof path, dir, imgs[i]);
            snprintf(pts_path, sizeof pts_path, "%s", path);
            strcpy(strrchr(pts_path, '.'), ".pts");
            double truth[2 * LM_POINTS], ours[2 * LM_POINTS], ours_bt601[2 * LM_POINTS];
            if (!lm_read_pts(pts_path, truth)) continue;
            long k = lm_match_truth(faces, n, path, truth);
            if (k < 0) {
                printf("  NME %-45s dlib's HOG finds no face here\n", imgs[i]);
                missed++;
                continue;
            }
            if (lm_image_get(ctx, &im, path) || lm_predict(sp, im.dlib_gray, faces[k].box, ours) ||
                lm_predict(sp, im.our_gray, faces[k].box, ours_bt601)) {
                fprintf(stderr, "%s: %s\n", path, frig_ctx_errmsg(ctx));
                test_failures++;
                continue;
            }
            double e_ours = lm_nme(ours, truth), e_dlib = lm_nme(faces[k].dlib, truth);
            double e_bt601 = lm_nme(ours_bt601, truth);
            printf("  NME %-45s ours %.4f  dlib %.4f  ours on BT.601 gray %.4f\n", imgs[i], e_ours, e_dlib, e_bt601);
            sum_bt601 += e_bt601;
            sum_ours += e_ours;
            sum_dlib += e_dlib;
            if (fabs(e_ours - e_dlib) > worst_gap) worst_gap = fabs(e_ours - e_dlib);
            scored++;
        }
        free_list(imgs, ni);
    }
    lm_image_clear(&im);
    printf("ground truth: %d faces scored, %d not detected; mean NME (inter-ocular, outer corners) ours %.4f, dlib's "
           "integer points %.4f, ours on BT.601 gray %.4f\n",
           scored, missed, scored ? sum_ours / scored : 0, scored ? sum_dlib / scored : 0,
           scored ? sum_bt601 / scored : 0);
    CHECK(scored >= 12);
    /* dlib's points are ours rounded: the errors can differ by rounding only (< 0.5 px / IOD). */
    CHECK(worst_gap < 0.01);
    /* The ERT model's published 300-W error is about 0.06 of the inter-ocular distance. */
    CHECK(scored && sum_ours / scored < 0.08);
    /* Fed our BT.601 gray, the predictor is as accurate. */
    CHECK(scored && fabs(sum_bt601 - sum_ours) / scored < 0.005);
}

static int test_against_dlib(const fr_shape_predictor *sp) {
    char why[1024], bin[4096], out[4096];
    const char *env = getenv("FRIG_DLIB_REF");
    if (env && *env) snprintf(bin, sizeof bin, "%s", env);
    else snprintf(bin, sizeof bin, "%s/tools/dlib_ref", FRIG_BINARY_DIR);
    if (lm_build_dlib_ref(test_shared_path("tools/dlib_ref.cpp"), bin, why, sizeof why)) {
        fprintf(stderr, "cannot compare with dlib: %s\n", why);
        return 1;
    }
    char photos[4096];
    snprintf(photos, sizeof photos, "%s", test_shared_path("photos"));
    int count;
    char *args = subset_arguments(photos, &count);
    const char *tmp = test_temp_dir("shape_predictor");
    snprintf(out, sizeof out, "%s/dlib.jsonl", tmp);
    size_t cmd_len = strlen(args) + 3 * 4096 + 64;
    char *cmd = malloc(cmd_len);
    if (!cmd) abort();
    snprintf(cmd, cmd_len, "'%s' '%s'%s 2>/dev/null", bin, MODEL, args);
    int rc = test_ref_to_file(cmd, out);
    free(cmd);
    free(args);
    CHECK(rc == 0);
    lm_face *faces;
    long n = lm_read_faces(out, &faces);
    printf("dlib_ref on %d photos from every set: %ld faces\n", count, n);
    CHECK(count >= 40 && n >= 40);

    lm_stats rounded = {0}, raw = {0}, our_gray = {0};
    long exact = 0;
    lm_image im = {0};
    for (long k = 0; k < n; k++) {
        double pts[2 * LM_POINTS], pts_ours[2 * LM_POINTS];
        if (lm_image_get(ctx, &im, faces[k].image) || lm_predict(sp, im.dlib_gray, faces[k].box, pts) ||
            lm_predict(sp, im.our_gray, faces[k].box, pts_ours)) {
            fprintf(stderr, "%s: %s\n", faces[k].image, frig_ctx_errmsg(ctx));
            test_failures++;
            continue;
        }
        double before = rounded.sum;
        lm_stats_add(&rounded, pts, faces[k].dlib, 1);
        lm_stats_add(&raw, pts, faces[k].dlib, 0);
        lm_stats_add(&our_gray, pts_ours, faces[k].dlib, 1);
        if (rounded.sum == before) exact++;
    }
    lm_image_clear(&im);
    printf("identical boxes, dlib's gray: %ld of %ld faces identical; rounded points mean %.4f px max %.4f px; "
           "unrounded mean %.4f px max %.4f px\n",
           exact, n, lm_stats_mean(&rounded), rounded.max, lm_stats_mean(&raw), raw.max);
    printf("identical boxes, our BT.601 gray: rounded points mean %.4f px max %.4f px from dlib's\n",
           lm_stats_mean(&our_gray), our_gray.max);
    CHECK(lm_stats_mean(&rounded) < 0.05);
    CHECK(rounded.max <= 1.0);
    CHECK(raw.max <= M_SQRT1_2 + 1.0);
    /* The model was trained on dlib's gray: other gray weights move the points by about a
     * pixel on average (the ensemble's sensitivity), not their accuracy (see the NME below). */
    CHECK(lm_stats_mean(&our_gray) < 2.0);
    ground_truth_nme(sp, faces, n, photos);
    free(faces);
    return 0;
}

int main(void) {
    ctx = frig_ctx_create();
    test_synthetic();
    test_float_runs();
    if (!test_file_exists(MODEL)) {
        frig_ctx_free(ctx);
        if (test_failures) return test_result("test_shape_predictor");
        return test_skip(MODEL " is missing (Debian package libdlib-data)");
    }
    unsigned char *data;
    size_t size;
    fr_shape_predictor *sp = NULL;
    CHECK(fr_read_file(ctx, MODEL, (size_t)1 << 31, &data, &size) == FRIG_OK);
    CHECK(fr_shape_predictor_parse(ctx, MODEL, data, size, &sp) == FRIG_OK);
    int skipped = 0;
    if (sp) {
        test_real_structure(sp);
        test_real_mutations(data, size);
        skipped = test_against_dlib(sp);
    }
    free(data);
    fr_shape_predictor_free(sp);
    frig_ctx_free(ctx);
    if (skipped && !test_failures) return test_skip("dlib_ref could not be built: no comparison with dlib");
    return test_result("test_shape_predictor");
}
