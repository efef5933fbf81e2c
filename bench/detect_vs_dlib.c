/* The detect stage against dlib's own pipeline (HOG detector upsampled once + its 68-point
 * predictor, from ../shared/tools/dlib_ref.cpp), single thread, photos read as stored (as the
 * references read them) with the product path's grays derived from the decoded RGB.
 *   detect_vs_dlib calibrate DLIB_HOG.jsonl PHOTO...
 *     every cascade (frontal, profile, mirrored profile) on every photo; raw boxes matched to
 *     dlib's boxes (IoU >= 0.3, greedy by IoU); least-squares box map per cascade, printed as
 *     the rows of lib/detect/box_calibration.c.
 *   detect_vs_dlib e2e DLIB_HOG.jsonl [--opencv-seconds S] [--dlib-us U] [--gray-check] PHOTO...
 *     the stage's boxes (frontal; profile + mirror where it finds nothing), landmarks from
 *     calibrated and raw boxes; distance to dlib's points on the faces both find, NME on the
 *     iBUG ground truth (STEM.pts, not dlib's predicted example faces), detection rate per
 *     set, speed (detector s/MP, predictor us/face) and ratios to the given reference times.
 *   detect_vs_dlib ssd DLIB_HOG.jsonl PHOTO...
 *     face-api's SSD detector (photos decoded as jpeg-js does): its raw boxes fitted to dlib's
 *     boxes (the SSD row of box_calibration.c); photos with a face per set against the cascade
 *     path and dlib; NME on the ground-truth faces of face-api's landmark net and of dlib's
 *     predictor on the mapped SSD box (and of dlib's own pipeline); times. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "detect/detector.h"
#include "landmark_ref.h"

static double now(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* dlib's faces of one image, boxes as x, y, w, h (w = right - left + 1). */
typedef struct ref_faces {
    long first, n;
} ref_faces;

static ref_faces ref_of(const lm_face *all, long n, const char *image) {
    ref_faces r = {0, 0};
    for (long k = 0; k < n; k++)
        if (strcmp(all[k].image, image) == 0) {
            if (!r.n) r.first = k;
            r.n++;
        }
    return r;
}

static void ref_box(const lm_face *f, double box[4]) {
    box[0] = f->box[0];
    box[1] = f->box[1];
    box[2] = f->box[2] - f->box[0] + 1;
    box[3] = f->box[3] - f->box[1] + 1;
}

/* Greedy one-to-one matching by IoU >= 0.3: match[i] = index into dlib's faces or -1. */
static void match_boxes(const double *ours, size_t n, const lm_face *ref, ref_faces r, long *match) {
    int used[256] = {0};
    for (size_t i = 0; i < n; i++) match[i] = -1;
    for (;;) {
        double best = 0.3;
        long bi = -1, bj = -1;
        for (size_t i = 0; i < n; i++) {
            if (match[i] >= 0) continue;
            for (long j = 0; j < r.n && j < 256; j++) {
                double rb[4];
                ref_box(&ref[r.first + j], rb);
                double iou = fr_box_iou(ours + 4 * i, rb);
                if (!used[j] && iou >= best) best = iou, bi = (long)i, bj = j;
            }
        }
        if (bi < 0) return;
        match[bi] = r.first + bj;
        used[bj] = 1;
    }
}

static const char *set_of(const char *path, char *buf, size_t size) {
    const char *end = strrchr(path, '/');
    const char *start = end;
    while (start && start > path && start[-1] != '/') start--;
    if (!end || !start) return "?";
    snprintf(buf, size, "%.*s", (int)(end - start), start);
    return buf;
}

static frig_image *load_rgb(frig_ctx *ctx, const char *path) {
    frig_image *img = NULL;
    if (frig_image_load(ctx, path, FRIG_LOAD_IGNORE_ORIENTATION, &img)) return NULL;
    return img;
}

/* ---- calibrate ---- */
typedef struct fit {
    double sww, swx, sww2, shh, shy, shh2; /* sums for a, c (x axis) and b, d (y axis) */
    double iou_raw, iou_cal;
    size_t n;
    double *pairs; /* raw box, dlib box: 8 per pair */
    size_t cap;
} fit;

/* One matched pair: our raw box b, dlib's box rb. Nonzero when out of memory. */
static int fit_add(fit *q, const double *b, const double *rb) {
    q->sww += b[2] * b[2];
    q->swx += b[2] * (rb[0] - b[0]);
    q->sww2 += b[2] * rb[2];
    q->shh += b[3] * b[3];
    q->shy += b[3] * (rb[1] - b[1]);
    q->shh2 += b[3] * rb[3];
    if (q->n == q->cap) {
        q->cap = q->cap ? 2 * q->cap : 256;
        q->pairs = realloc(q->pairs, q->cap * 8 * sizeof *q->pairs);
        if (!q->pairs) return 1;
    }
    memcpy(q->pairs + 8 * q->n, b, 4 * sizeof *b);
    memcpy(q->pairs + 8 * q->n + 4, rb, 4 * sizeof *rb);
    q->n++;
    return 0;
}

static int calibrate(frig_ctx *ctx, const frig_detector *det, const lm_face *ref, long nref, char **photos, int np) {
    fit f[3];
    memset(f, 0, sizeof f);
    for (int p = 0; p < np; p++) {
        frig_image *rgb = load_rgb(ctx, photos[p]), *gray = NULL;
        if (!rgb) continue;
        fr_detected_face *v = NULL;
        size_t n = 0;
        if (!fr_gray_like_opencv(ctx, rgb, &gray))
            fr_detect_cascade_boxes(ctx, det, gray, FR_DETECT_RUN_FRONTAL | FR_DETECT_RUN_PROFILE |
                                                        FR_DETECT_RUN_PROFILE_MIRRORED, &v, &n);
        ref_faces r = ref_of(ref, nref, photos[p]);
        for (int s = 0; s < 3; s++) {
            double boxes[4 * 64];
            size_t m = 0;
            for (size_t i = 0; i < n && m < 64; i++)
                if (v[i].source == s) memcpy(boxes + 4 * m++, v[i].box, sizeof v[i].box);
            long match[64];
            match_boxes(boxes, m, ref, r, match);
            for (size_t i = 0; i < m; i++) {
                if (match[i] < 0) continue;
                double rb[4];
                ref_box(&ref[match[i]], rb);
                if (fit_add(&f[s], boxes + 4 * i, rb)) return 1;
            }
        }
        free(v);
        frig_image_free(gray);
        frig_image_free(rgb);
    }
    static const char *names[3] = {"frontal (alt2)", "profile", "profile on the mirrored photo"};
    printf("box calibration over %d photos (dlib HOG boxes matched with IoU >= 0.3):\n", np);
    for (int s = 0; s < 3; s++) {
        fit *q = &f[s];
        if (!q->n) {
            printf("  %-30s no matched faces\n", names[s]);
            continue;
        }
        fr_box_map m = {q->swx / q->sww, q->shy / q->shh, q->sww2 / q->sww, q->shh2 / q->shh};
        double ex = 0, ey = 0, ew = 0, eh = 0;
        for (size_t i = 0; i < q->n; i++) {
            double *b = q->pairs + 8 * i, *rb = b + 4, c[4];
            fr_box_map_apply(&m, b, c);
            q->iou_raw += fr_box_iou(b, rb);
            q->iou_cal += fr_box_iou(c, rb);
            ex += fabs(c[0] - rb[0]) / b[2];
            ey += fabs(c[1] - rb[1]) / b[3];
            ew += fabs(c[2] - rb[2]) / b[2];
            eh += fabs(c[3] - rb[3]) / b[3];
        }
        double n = (double)q->n;
        printf("  %-30s %4zu faces: a %+.4f  b %+.4f  c %.4f  d %.4f; mean IoU with dlib's box %.3f raw -> %.3f "
               "calibrated; mean |residual| / side: x %.3f y %.3f w %.3f h %.3f\n",
               names[s], q->n, m.a, m.b, m.c, m.d, q->iou_raw / n, q->iou_cal / n, ex / n, ey / n, ew / n, eh / n);
        printf("    C row: {%.4f, %.4f, %.4f, %.4f},\n", m.a, m.b, m.c, m.d);
        free(q->pairs);
    }
    return 0;
}

/* ---- end to end ---- */
#define MAX_SETS 32
typedef struct set_stats {
    char name[128];
    int photos, ours_found, dlib_found, fallback_found, either_found;
    size_t ours_faces, dlib_faces;
} set_stats;

/* The statistics of the photo's set (its folder; a new entry the first time), with the photo
 * and dlib's faces r in it counted. */
static set_stats *set_for(set_stats *sets, int *nsets, const char *photo, ref_faces r) {
    char sb[128];
    const char *sname = set_of(photo, sb, sizeof sb);
    int si = 0;
    while (si < *nsets && strcmp(sets[si].name, sname) != 0) si++;
    if (si == *nsets && *nsets < MAX_SETS) {
        memset(&sets[*nsets], 0, sizeof sets[*nsets]);
        snprintf(sets[*nsets].name, sizeof sets[*nsets].name, "%s", sname);
        (*nsets)++;
    }
    set_stats *ss = &sets[si < MAX_SETS ? si : MAX_SETS - 1];
    ss->photos++;
    ss->dlib_found += r.n > 0;
    ss->dlib_faces += (size_t)r.n;
    return ss;
}

typedef struct dist_stats {
    lm_stats px;
    double worst_nme;
    char worst[1024];
    double nme_sum; /* mean point distance over dlib's outer-eye-corner distance */
    size_t faces;
} dist_stats;

static void dist_add(dist_stats *d, const double *ours, const double *dlib, const char *image) {
    lm_stats one = {0, 0, 0};
    lm_stats_add(&one, ours, dlib, 1);
    lm_stats_add(&d->px, ours, dlib, 1);
    double iod = hypot(dlib[72] - dlib[90], dlib[73] - dlib[91]);
    d->nme_sum += lm_stats_mean(&one) / iod;
    d->faces++;
    if (lm_stats_mean(&one) / iod > d->worst_nme) {
        d->worst_nme = lm_stats_mean(&one) / iod;
        snprintf(d->worst, sizeof d->worst, "%s (%.1f px mean, %.3f of the eye distance)", image, lm_stats_mean(&one),
                 d->worst_nme);
    }
}

typedef struct e2e_opts {
    double opencv_seconds, dlib_us;
    int gray_check;
} e2e_opts;

static int end_to_end(frig_ctx *ctx, const frig_detector *det, const lm_face *ref, long nref, char **photos, int np,
                      e2e_opts o) {
    set_stats sets[MAX_SETS];
    int nsets = 0;
    dist_stats cal, raw;
    memset(&cal, 0, sizeof cal);
    memset(&raw, 0, sizeof raw);
    double mp = 0, t_frontal = 0, t_fallback = 0, t_sp = 0, t_gray = 0;
    size_t sp_faces = 0, gray_differ = 0, gray_photos = 0, gray_boxes_ref = 0, gray_boxes_ours = 0, gray_hit_ref = 0,
           gray_hit_ours = 0;
    double nme_cal = 0, nme_raw = 0, nme_dlib = 0, nme_both_cal = 0, nme_both_raw = 0, nme_both_dlib = 0;
    int gt = 0, gt_ours = 0, gt_dlib = 0, gt_both = 0;
    printf("ground truth faces (NME = mean point distance / outer eye corners distance):\n");
    for (int p = 0; p < np; p++) {
        ref_faces r = ref_of(ref, nref, photos[p]);
        set_stats *ss = set_for(sets, &nsets, photos[p], r);
        frig_image *rgb = load_rgb(ctx, photos[p]), *gray = NULL, *dgray = NULL;
        if (!rgb) continue;
        mp += rgb->width * (double)rgb->height / 1e6;
        fr_detected_face *v = NULL;
        size_t n = 0;
        if (fr_gray_like_opencv(ctx, rgb, &gray) || fr_gray_like_dlib(ctx, rgb, &dgray)) return 1;
        double t0 = now();
        if (fr_detect_frontal(ctx, det, gray, &v, &n)) return 1; /* as the stage: coarse, then fine */
        t_frontal += now() - t0;
        int fell_back = 0;
        if (n == 0 && det->profile_fallback) {
            t0 = now();
            if (fr_detect_cascade_boxes(ctx, det, gray, FR_DETECT_RUN_PROFILE | FR_DETECT_RUN_PROFILE_MIRRORED, &v, &n))
                return 1;
            n = fr_detect_merge(v, n);
            t_fallback += now() - t0;
            fell_back = n > 0;
        }
        if (o.gray_check) {
            frig_image *cvg = NULL;
            fr_detected_face *w = NULL;
            size_t m = 0;
            t0 = now();
            if (!frig_image_load(ctx, photos[p], FRIG_LOAD_GRAY | FRIG_LOAD_IGNORE_ORIENTATION, &cvg) &&
                !fr_detect_frontal(ctx, det, cvg, &w, &m)) {
                size_t k = 0;
                for (size_t i = 0; i < n && v[i].source == FRIG_FACE_FRONTAL; i++) k++;
                int same = m == k;
                for (size_t i = 0; same && i < m; i++) same = memcmp(w[i].box, v[i].box, sizeof w[i].box) == 0;
                gray_differ += !same;
                gray_photos++;
                gray_boxes_ref += m;
                gray_boxes_ours += k;
                for (size_t i = 0; i < m; i++) {
                    int hit = 0;
                    for (size_t j = 0; j < k; j++) hit |= fr_box_iou(w[i].box, v[j].box) >= 0.9;
                    gray_hit_ref += (size_t)hit;
                }
                for (size_t j = 0; j < k; j++) {
                    int hit = 0;
                    for (size_t i = 0; i < m; i++) hit |= fr_box_iou(w[i].box, v[j].box) >= 0.9;
                    gray_hit_ours += (size_t)hit;
                }
            }
            t_gray += now() - t0;
            free(w);
            frig_image_free(cvg);
        }
        ss->ours_found += n > 0;
        ss->fallback_found += fell_back;
        ss->ours_faces += n;
        fr_detected_face *u = n ? malloc(n * sizeof *u) : NULL;
        if (n && !u) return 1;
        if (n) memcpy(u, v, n * sizeof *u);
        for (size_t i = 0; i < n; i++) {
            fr_box_map m = fr_box_map_for(v[i].source);
            fr_box_map_apply(&m, u[i].box, v[i].box);
        }
        t0 = now();
        if (fr_detect_landmarks_on(ctx, det, dgray, v, n)) return 1;
        t_sp += now() - t0;
        sp_faces += n;
        if (fr_detect_landmarks_on(ctx, det, dgray, u, n)) return 1;
        double boxes[4 * 64];
        size_t nb = n < 64 ? n : 64;
        for (size_t i = 0; i < nb; i++) memcpy(boxes + 4 * i, v[i].box, sizeof v[i].box);
        long match[64];
        match_boxes(boxes, nb, ref, r, match);
        for (size_t i = 0; i < nb; i++) {
            if (match[i] < 0) continue;
            dist_add(&cal, v[i].landmarks, ref[match[i]].dlib, photos[p]);
            dist_add(&raw, u[i].landmarks, ref[match[i]].dlib, photos[p]);
        }
        double truth[2 * LM_POINTS];
        if (lm_truth_pts(photos[p], truth)) {
            gt++;
            long k = lm_face_at_truth(v, n, truth), d = lm_match_truth(ref, nref, photos[p], truth);
            double e_cal = k >= 0 ? lm_nme(v[k].landmarks, truth) : NAN;
            double e_raw = k >= 0 ? lm_nme(u[k].landmarks, truth) : NAN;
            double e_dlib = d >= 0 ? lm_nme(ref[d].dlib, truth) : NAN;
            printf("  %-70s ours calibrated %.4f  ours raw box %.4f  dlib %.4f%s\n", photos[p], e_cal, e_raw, e_dlib,
                   k >= 0 && v[k].source != FRIG_FACE_FRONTAL ? "  (profile cascade)" : "");
            if (k >= 0) gt_ours++, nme_cal += e_cal, nme_raw += e_raw;
            if (d >= 0) gt_dlib++, nme_dlib += e_dlib;
            if (k >= 0 && d >= 0) gt_both++, nme_both_cal += e_cal, nme_both_raw += e_raw, nme_both_dlib += e_dlib;
        }
        free(u);
        free(v);
        frig_image_free(gray);
        frig_image_free(dgray);
        frig_image_free(rgb);
    }
    printf("NME on %d ground-truth faces: ours finds %d, mean %.4f (raw cascade box: %.4f); dlib finds %d, mean "
           "%.4f; on the %d both find: ours %.4f (raw cascade box: %.4f), dlib %.4f\n",
           gt, gt_ours, nme_cal / gt_ours, nme_raw / gt_ours, gt_dlib, nme_dlib / gt_dlib, gt_both,
           nme_both_cal / gt_both, nme_both_raw / gt_both, nme_both_dlib / gt_both);
    printf("\nend to end vs dlib's pipeline (HOG box + predictor) on the %zu faces both find "
           "(boxes matched IoU >= 0.3; our points rounded as dlib rounds):\n",
           cal.faces);
    printf("  calibrated boxes:   mean %.3f px, max %.2f px; mean per face / dlib's outer-eye distance %.4f\n",
           lm_stats_mean(&cal.px), cal.px.max, cal.nme_sum / (double)cal.faces);
    printf("  raw cascade boxes:  mean %.3f px, max %.2f px; mean per face / dlib's outer-eye distance %.4f\n",
           lm_stats_mean(&raw.px), raw.px.max, raw.nme_sum / (double)raw.faces);
    printf("  worst face (calibrated): %s\n", cal.worst);
    printf("\ndetection rate per set (photos with at least one face):\n");
    printf("  %-40s %6s %16s %9s %16s\n", "set", "photos", "ours", "(profile)", "dlib HOG");
    int tp = 0, to = 0, td = 0;
    for (int s = 0; s < nsets; s++) {
        set_stats *q = &sets[s];
        printf("  %-40s %6d %5d (%5.1f%%) %9d %5d (%5.1f%%)   faces: ours %zu, dlib %zu\n", q->name, q->photos,
               q->ours_found, 100.0 * q->ours_found / q->photos, q->fallback_found, q->dlib_found,
               100.0 * q->dlib_found / q->photos, q->ours_faces, q->dlib_faces);
        tp += q->photos, to += q->ours_found, td += q->dlib_found;
    }
    printf("  %-40s %6d %5d (%5.1f%%) %9s %5d (%5.1f%%)\n", "all", tp, to, 100.0 * to / tp, "", td, 100.0 * td / tp);
    printf("\nspeed, single thread, %.1f megapixels:\n", mp);
    printf("  our detector: frontal cascade %.3f s/MP; with the profile fallback %.3f s/MP (+%.1f%%)\n",
           t_frontal / mp, (t_frontal + t_fallback) / mp, 100.0 * t_fallback / t_frontal);
    if (o.opencv_seconds > 0)
        printf("  OpenCV detectMultiScale (same cascade and parameters) %.3f s/MP: ours/OpenCV = %.2f (frontal), "
               "%.2f (with fallback)\n",
               o.opencv_seconds / mp, t_frontal / o.opencv_seconds, (t_frontal + t_fallback) / o.opencv_seconds);
    printf("  our predictor: %.1f us per face (%zu faces)\n", 1e6 * t_sp / (double)sp_faces, sp_faces);
    if (o.dlib_us > 0)
        printf("  dlib's predictor %.1f us per face: dlib/ours = %.2fx\n", o.dlib_us, o.dlib_us / (1e6 * t_sp / sp_faces));
    if (o.gray_check)
        printf("\ngray check: frontal boxes from the gray derived from RGB differ from those on cv2's IMREAD_GRAYSCALE "
               "gray on %zu of %zu photos; of the %zu boxes on cv2's gray %zu are found (IoU >= 0.9), of our %zu "
               "boxes %zu are on cv2's gray (%.1f s)\n",
               gray_differ, gray_photos, gray_boxes_ref, gray_hit_ref, gray_boxes_ours, gray_hit_ours, t_gray);
    return 0;
}

/* ---- face-api's SSD detector ---- */
typedef struct nme_sum {
    double sum;
    int n;
} nme_sum;

static int ssd_eval(frig_ctx *ctx, const frig_detector *det, const lm_face *ref, long nref, char **photos, int np) {
    fit q;
    memset(&q, 0, sizeof q);
    set_stats sets[MAX_SETS];
    int nsets = 0;
    nme_sum net = {0, 0}, dl = {0, 0}, dlib_own = {0, 0}, net_both = {0, 0}, dl_both = {0, 0}, own_both = {0, 0};
    double t_ssd = 0, t_net = 0, t_desc = 0, t_cascade = 0, mp = 0;
    size_t faces = 0;
    printf("ground truth faces: NME of face-api's net / dlib's predictor on the mapped SSD box / dlib's pipeline\n");
    for (int p = 0; p < np; p++) {
        ref_faces r = ref_of(ref, nref, photos[p]);
        set_stats *ss = set_for(sets, &nsets, photos[p], r);
        frig_image *rgb = NULL, *plain = NULL, *gray = NULL, *dgray = NULL;
        if (frig_image_load(ctx, photos[p], FRIG_LOAD_IGNORE_ORIENTATION | FR_LOAD_LIKE_JPEG_JS, &rgb)) continue;
        mp += rgb->width * (double)rgb->height / 1e6;
        fr_nn_image in = {rgb->pixels, rgb->stride, rgb->width, rgb->height, rgb->channels};
        fr_ssd_face *b = NULL;
        size_t n = 0;
        double t0 = now();
        if (fr_ssd_detect(ctx, det->nets->ssd, &in, det->ssd_min_score, 100, &b, &n)) return 1;
        t_ssd += now() - t0;
        ss->ours_found += n > 0;
        ss->ours_faces += n;
        /* the cascade path on the default decode, for the per-set count */
        fr_detected_face *cv = NULL;
        size_t cn = 0;
        if (!frig_image_load(ctx, photos[p], FRIG_LOAD_IGNORE_ORIENTATION, &plain) && !fr_gray_like_opencv(ctx, plain, &gray)) {
            t0 = now();
            if (fr_detect_boxes(ctx, det, gray, &cv, &cn)) return 1;
            t_cascade += now() - t0;
        }
        ss->fallback_found += cn > 0;
        ss->either_found += n > 0 || cn > 0;
        /* calibration pairs */
        double raw[4 * 64];
        size_t m = n < 64 ? n : 64;
        for (size_t i = 0; i < m; i++) memcpy(raw + 4 * i, b[i].box, sizeof b[i].box);
        long match[64];
        match_boxes(raw, m, ref, r, match);
        for (size_t i = 0; i < m; i++) {
            if (match[i] < 0) continue;
            double rb[4];
            ref_box(&ref[match[i]], rb);
            if (fit_add(&q, raw + 4 * i, rb)) return 1;
        }
        /* landmarks and descriptors of every face; NME where ground truth exists */
        fr_detected_face *v = calloc(n ? n : 1, sizeof *v);
        if (fr_gray_like_dlib(ctx, rgb, &dgray)) return 1;
        for (size_t i = 0; i < n; i++) {
            int crop[4];
            fr_box_map map = fr_box_map_for(FRIG_FACE_SSD);
            fr_box_map_apply(&map, b[i].box, v[i].box);
            t0 = now();
            if (fr_landmark_net_run(ctx, det->nets->landmarks, &in, b[i].box, v[i].landmarks, crop)) return 1;
            t_net += now() - t0;
            t0 = now();
            if (fr_recognition_net_run(ctx, det->nets->recognition, &in, v[i].landmarks, crop[2], crop[3], v[i].descriptor))
                return 1;
            t_desc += now() - t0;
            faces++;
        }
        double truth[2 * LM_POINTS];
        if (lm_truth_pts(photos[p], truth)) {
            long k = lm_face_at_truth(v, n, truth);
            long d = lm_match_truth(ref, nref, photos[p], truth);
            double e_net = -1, e_dl = -1, e_own = d >= 0 ? lm_nme(ref[d].dlib, truth) : -1;
            if (k >= 0) {
                fr_detected_face f = v[k];
                e_net = lm_nme(f.landmarks, truth);
                if (fr_detect_landmarks_on(ctx, det, dgray, &f, 1)) return 1;
                e_dl = lm_nme(f.landmarks, truth);
                net.sum += e_net, net.n++;
                dl.sum += e_dl, dl.n++;
            }
            if (e_own >= 0) dlib_own.sum += e_own, dlib_own.n++;
            if (k >= 0 && e_own >= 0) {
                net_both.sum += e_net, net_both.n++;
                dl_both.sum += e_dl, dl_both.n++;
                own_both.sum += e_own, own_both.n++;
            }
            printf("  %-72s net %.4f  dlib on SSD box %.4f  dlib pipeline %.4f\n", photos[p], e_net, e_dl, e_own);
        }
        free(v);
        free(b);
        free(cv);
        frig_image_free(rgb);
        frig_image_free(plain);
        frig_image_free(gray);
        frig_image_free(dgray);
    }
    printf("NME: face-api's net %.4f (%d faces), dlib's predictor on the mapped SSD box %.4f (%d), dlib's pipeline %.4f "
           "(%d); on the %d faces both pipelines find: net %.4f, dlib on SSD box %.4f, dlib's pipeline %.4f\n",
           net.n ? net.sum / net.n : 0, net.n, dl.n ? dl.sum / dl.n : 0, dl.n, dlib_own.n ? dlib_own.sum / dlib_own.n : 0,
           dlib_own.n, own_both.n, net_both.n ? net_both.sum / net_both.n : 0, dl_both.n ? dl_both.sum / dl_both.n : 0,
           own_both.n ? own_both.sum / own_both.n : 0);
    printf("\nphotos with a face: set, photos, SSD, SSD + cascade fallback, cascade path, dlib\n");
    int tot[5] = {0, 0, 0, 0, 0};
    for (int k = 0; k < nsets; k++) {
        printf("  %-42s %4d %4d %4d %4d %4d\n", sets[k].name, sets[k].photos, sets[k].ours_found, sets[k].either_found,
               sets[k].fallback_found, sets[k].dlib_found);
        tot[0] += sets[k].photos, tot[1] += sets[k].ours_found, tot[2] += sets[k].either_found,
            tot[3] += sets[k].fallback_found, tot[4] += sets[k].dlib_found;
    }
    printf("  %-42s %4d %4d %4d %4d %4d\n", "all", tot[0], tot[1], tot[2], tot[3], tot[4]);
    if (q.n) {
        fr_box_map mm = {q.swx / q.sww, q.shy / q.shh, q.sww2 / q.sww, q.shh2 / q.shh};
        double iou_raw = 0, iou_cal = 0;
        for (size_t i = 0; i < q.n; i++) {
            double *x = q.pairs + 8 * i, *rb = x + 4, c[4];
            fr_box_map_apply(&mm, x, c);
            iou_raw += fr_box_iou(x, rb);
            iou_cal += fr_box_iou(c, rb);
        }
        printf("\nSSD box -> dlib box over %zu faces: a %+.4f b %+.4f c %.4f d %.4f; mean IoU %.3f raw -> %.3f\n", q.n,
               mm.a, mm.b, mm.c, mm.d, iou_raw / q.n, iou_cal / q.n);
        printf("    C row: {%.4f, %.4f, %.4f, %.4f},\n", mm.a, mm.b, mm.c, mm.d);
        free(q.pairs);
    }
    printf("\ntimes (one thread, %.1f MP): SSD %.3f s/photo, landmark net %.2f ms/face, descriptor %.2f ms/face; "
           "cascade path %.3f s/photo (SSD / cascade %.2f)\n",
           mp, t_ssd / np, 1e3 * t_net / (faces ? faces : 1), 1e3 * t_desc / (faces ? faces : 1), t_cascade / np,
           t_cascade > 0 ? t_ssd / t_cascade : 0);
    return 0;
}

int main(int argc, char **argv) {
    if (argc < 4) {
        fprintf(stderr, "usage: detect_vs_dlib calibrate|e2e|ssd DLIB_HOG.jsonl [options] PHOTO...\n");
        return 2;
    }
    frig_ctx *ctx = frig_ctx_create();
    frig_detector *det = NULL;
    /* calibrate and e2e measure the cascade path; ssd loads face-api's networks too */
    if (ctx) frig_ctx_set_param(ctx, FRIG_PARAM_DETECT_DETECTOR, strcmp(argv[1], "ssd") == 0 ? 2 : 1);
    if (ctx) frig_ctx_set_param(ctx, FRIG_PARAM_DETECT_DESCRIPTORS, 0);
    if (!ctx || frig_detector_create(ctx, NULL, NULL, &det)) {
        fprintf(stderr, "%s\n", ctx ? frig_ctx_errmsg(ctx) : "out of memory");
        return 1;
    }
    lm_face *ref = NULL;
    long nref = lm_read_faces(argv[2], &ref);
    if (nref < 0) {
        fprintf(stderr, "cannot read %s\n", argv[2]);
        return 1;
    }
    e2e_opts o = {0, 0, 0};
    int i = 3;
    for (; i < argc && strncmp(argv[i], "--", 2) == 0; i++) {
        if (!strcmp(argv[i], "--gray-check")) o.gray_check = 1;
        else if (!strcmp(argv[i], "--opencv-seconds") && i + 1 < argc) o.opencv_seconds = atof(argv[++i]);
        else if (!strcmp(argv[i], "--dlib-us") && i + 1 < argc) o.dlib_us = atof(argv[++i]);
        else {
            fprintf(stderr, "unknown option %s\n", argv[i]);
            return 2;
        }
    }
    int rc = !strcmp(argv[1], "calibrate") ? calibrate(ctx, det, ref, nref, argv + i, argc - i)
             : !strcmp(argv[1], "ssd")     ? ssd_eval(ctx, det, ref, nref, argv + i, argc - i)
                                           : end_to_end(ctx, det, ref, nref, argv + i, argc - i, o);
    if (rc) fprintf(stderr, "failed: %s\n", frig_ctx_errmsg(ctx));
    free(ref);
    frig_detector_free(det);
    frig_ctx_free(ctx);
    return rc;
}
