/* Shared by tests/test_shape_predictor.c and bench/predictor_vs_dlib.c: build and run dlib's
 * reference tool (../shared/tools/dlib_ref.cpp), read its JSON lines, run our predictor on
 * the same boxes, and score point distances and the normalized mean error against iBUG .pts
 * ground truth. Header-only (static functions) so the bench can include it too. */
#ifndef FRIG_TESTS_LANDMARK_REF_H
#define FRIG_TESTS_LANDMARK_REF_H

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include <cjson/cJSON.h>

#include "detect/detector.h"
#include "detect/gray_like_dlib.h"
#include "detect/shape_predictor.h"
#include "frig/frig.h"
#include "frig/image.h"
#include "image/image.h"

#define LM_POINTS 68

/* One face as dlib_ref reported it: the image, the box, dlib's (integer) points. */
typedef struct lm_face {
    char image[1024];
    double box[4];
    double score;
    double dlib[2 * LM_POINTS];
} lm_face;

/* Build dlib_ref into 'bin' unless it is there and newer than its source. 0 on success; else
 * 'why' says what is missing (libdlib-dev, g++) or what failed. */
static inline int lm_build_dlib_ref(const char *src, const char *bin, char *why, size_t why_size) {
    struct stat s_src, s_bin;
    if (stat(src, &s_src) != 0) {
        snprintf(why, why_size, "%.900s is missing", src);
        return 1;
    }
    if (stat(bin, &s_bin) == 0 && s_bin.st_mtime >= s_src.st_mtime) return 0;
    if (stat("/usr/include/dlib/image_processing/shape_predictor.h", &s_bin) != 0 ||
        system("pkg-config --exists dlib-1 && command -v g++ >/dev/null") != 0) {
        snprintf(why, why_size, "libdlib-dev (dlib's headers, pkg-config dlib-1) or g++ is not installed: "
                                "scripts/install-deps.sh --test installs them");
        return 1;
    }
    char cmd[6 * 4096];
    snprintf(cmd, sizeof cmd,
             "mkdir -p \"$(dirname '%s')\" && g++ -O2 -DDLIB_JPEG_SUPPORT -DDLIB_PNG_SUPPORT '%s' -o '%s.tmp' "
             "$(pkg-config --cflags --libs dlib-1) && mv '%s.tmp' '%s'",
             bin, src, bin, bin, bin);
    if (system(cmd) != 0) {
        snprintf(why, why_size, "building %.400s from %.400s failed", bin, src);
        return 1;
    }
    return 0;
}

static inline int lm_json_numbers(const cJSON *arr, double *out, int n) {
    if (!cJSON_IsArray(arr) || cJSON_GetArraySize(arr) != n) return 0;
    for (int i = 0; i < n; i++) {
        const cJSON *v = cJSON_GetArrayItem(arr, i);
        if (!cJSON_IsNumber(v)) return 0;
        out[i] = v->valuedouble;
    }
    return 1;
}

/* Parse one dlib_ref output line. 1 on success. */
static inline int lm_parse_line(const char *line, lm_face *f) {
    cJSON *j = cJSON_Parse(line);
    if (!j) return 0;
    const cJSON *img = cJSON_GetObjectItem(j, "image"), *score = cJSON_GetObjectItem(j, "score");
    const cJSON *pts = cJSON_GetObjectItem(j, "landmarks");
    int ok = cJSON_IsString(img) && strlen(img->valuestring) < sizeof f->image &&
             lm_json_numbers(cJSON_GetObjectItem(j, "box"), f->box, 4) && cJSON_IsArray(pts) &&
             cJSON_GetArraySize(pts) == LM_POINTS;
    for (int i = 0; ok && i < LM_POINTS; i++) ok = lm_json_numbers(cJSON_GetArrayItem(pts, i), f->dlib + 2 * i, 2);
    if (ok) {
        strcpy(f->image, img->valuestring);
        f->score = cJSON_IsNumber(score) ? score->valuedouble : 0.0;
    }
    cJSON_Delete(j);
    return ok;
}

/* Read every face of a dlib_ref output file. Returns the count, -1 when unreadable. */
static inline long lm_read_faces(const char *path, lm_face **faces) {
    *faces = NULL;
    FILE *fp = fopen(path, "r");
    if (!fp) return -1;
    size_t n = 0, cap = 0, line_cap = 0;
    char *line = NULL;
    lm_face *v = NULL;
    while (getline(&line, &line_cap, fp) > 0) {
        if (n == cap) {
            cap = cap ? 2 * cap : 64;
            lm_face *nv = realloc(v, cap * sizeof *v);
            if (!nv) break;
            v = nv;
        }
        if (lm_parse_line(line, &v[n])) n++;
    }
    free(line);
    fclose(fp);
    *faces = v;
    return (long)n;
}

/* Distances between two point sets. */
typedef struct lm_stats {
    double sum, max;
    size_t points;
} lm_stats;

static inline void lm_stats_add(lm_stats *s, const double *a, const double *b, int round_a) {
    for (int i = 0; i < LM_POINTS; i++) {
        double ax = a[2 * i], ay = a[2 * i + 1];
        if (round_a) {
            ax = floor(ax + 0.5);
            ay = floor(ay + 0.5);
        }
        double d = hypot(ax - b[2 * i], ay - b[2 * i + 1]);
        s->sum += d;
        if (d > s->max) s->max = d;
        s->points++;
    }
}

static inline double lm_stats_mean(const lm_stats *s) { return s->points ? s->sum / (double)s->points : 0.0; }

/* The two gray images of a photo: dlib's (r+g+b)/3 and ours (BT.601), read as stored (dlib_ref
 * ignores EXIF orientation). Kept across faces of the same image. */
typedef struct lm_image {
    char path[4096];
    frig_image *dlib_gray, *our_gray;
} lm_image;

static inline void lm_image_clear(lm_image *im) {
    frig_image_free(im->dlib_gray);
    frig_image_free(im->our_gray);
    memset(im, 0, sizeof *im);
}

static inline frig_status lm_image_get(frig_ctx *ctx, lm_image *im, const char *path) {
    if (im->dlib_gray && strcmp(im->path, path) == 0) return FRIG_OK;
    lm_image_clear(im);
    frig_image *rgb;
    frig_status st = frig_image_load(ctx, path, FRIG_LOAD_IGNORE_ORIENTATION, &rgb);
    if (st) return st;
    st = fr_gray_like_dlib(ctx, rgb, &im->dlib_gray);
    if (!st) st = frig_image_to_gray(ctx, rgb, &im->our_gray);
    frig_image_free(rgb);
    if (st) {
        lm_image_clear(im);
        return st;
    }
    if (strlen(path) >= sizeof im->path) {
        lm_image_clear(im);
        return FRIG_ERR_INVALID_ARGUMENT;
    }
    strcpy(im->path, path);
    return FRIG_OK;
}

static inline frig_status lm_predict(const fr_shape_predictor *sp, const frig_image *gray, const double box[4], double *out) {
    return fr_shape_predictor_run(sp, gray->pixels, gray->width, gray->height, gray->stride, box, out);
}

/* An iBUG .pts file (68 points, 1-based): the points shifted to 0-based. 1 on success. */
static inline int lm_read_pts(const char *path, double *pts) {
    FILE *fp = fopen(path, "r");
    if (!fp) return 0;
    char line[256];
    int n = 0, in_block = 0;
    while (fgets(line, sizeof line, fp) && n < LM_POINTS) {
        if (!in_block) {
            in_block = line[0] == '{';
            continue;
        }
        double x, y;
        if (sscanf(line, "%lf %lf", &x, &y) == 2) {
            pts[2 * n] = x - 1.0;
            pts[2 * n + 1] = y - 1.0;
            n++;
        }
    }
    fclose(fp);
    return n == LM_POINTS;
}

/* Normalized mean error: mean point distance over the outer eye corners' distance (36, 45). */
static inline double lm_nme(const double *pts, const double *truth) {
    double sum = 0;
    for (int i = 0; i < LM_POINTS; i++) sum += hypot(pts[2 * i] - truth[2 * i], pts[2 * i + 1] - truth[2 * i + 1]);
    double iod = hypot(truth[72] - truth[90], truth[73] - truth[91]);
    return sum / LM_POINTS / iod;
}

/* The ground truth beside a photo: STEM.pts (not for dlib's predicted example faces, which
 * are no ground truth). 1 when read. */
static inline int lm_truth_pts(const char *photo, double *truth) {
    if (strstr(photo, "landmarks_dlib_examples")) return 0;
    char pts[4096];
    const char *dot = strrchr(photo, '.');
    if (!dot || (size_t)(dot - photo) + 5 > sizeof pts) return 0;
    snprintf(pts, sizeof pts, "%.*s.pts", (int)(dot - photo), photo);
    return lm_read_pts(pts, truth);
}

/* Our face (box x, y, w, h) holding the truth's centroid, nearest centre; -1 when none. */
static inline long lm_face_at_truth(const fr_detected_face *v, size_t n, const double *truth) {
    double cx = 0, cy = 0;
    for (int i = 0; i < LM_POINTS; i++) cx += truth[2 * i] / LM_POINTS, cy += truth[2 * i + 1] / LM_POINTS;
    long best = -1;
    double bd = INFINITY;
    for (size_t k = 0; k < n; k++) {
        const double *b = v[k].box;
        if (cx < b[0] || cx > b[0] + b[2] || cy < b[1] || cy > b[1] + b[3]) continue;
        double d = hypot(cx - b[0] - 0.5 * b[2], cy - b[1] - 0.5 * b[3]);
        if (d < bd) bd = d, best = (long)k;
    }
    return best;
}

/* The face of 'faces' (those of image 'path') whose box holds the ground truth's centroid
 * and is closest to it; -1 when dlib found none there. */
static inline long lm_match_truth(const lm_face *faces, long n, const char *path, const double *truth) {
    double cx = 0, cy = 0;
    for (int i = 0; i < LM_POINTS; i++) {
        cx += truth[2 * i] / LM_POINTS;
        cy += truth[2 * i + 1] / LM_POINTS;
    }
    long best = -1;
    double best_d = INFINITY;
    for (long k = 0; k < n; k++) {
        const double *b = faces[k].box;
        if (strcmp(faces[k].image, path) != 0 || cx < b[0] || cx > b[2] || cy < b[1] || cy > b[3]) continue;
        double d = hypot(cx - 0.5 * (b[0] + b[2]), cy - 0.5 * (b[1] + b[3]));
        if (d < best_d) {
            best_d = d;
            best = k;
        }
    }
    return best;
}

#endif
