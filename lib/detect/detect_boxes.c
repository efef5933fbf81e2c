/* Face boxes for the detect stage (paper section 4.2): OpenCV's frontal cascade (alt2), and
 * only where it finds nothing, the profile cascade on the photo and its mirror image (the
 * measured choice in docs/detect-cascades.md), on a copy no larger than detect.max_side;
 * overlapping boxes merged by non-maximum suppression, frontal first. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "detect/detector.h"
#include "image/image.h"

/* Box-average by an integer factor k, then OpenCV's exact bilinear resize to dw x dh: a
 * downscale that does not alias for large factors. Returns a new dw x dh buffer or NULL. */
static uint8_t *downscale(const frig_image *g, int dw, int dh) {
    int k = (int)floor(fmin((double)g->width / dw, (double)g->height / dh));
    if (k < 1) k = 1;
    int bw = g->width / k, bh = g->height / k;
    uint8_t *boxed = malloc((size_t)bw * (size_t)bh), *out = malloc((size_t)dw * (size_t)dh);
    if (!boxed || !out) {
        free(boxed);
        free(out);
        return NULL;
    }
    for (int y = 0; y < bh; y++)
        for (int x = 0; x < bw; x++) {
            unsigned sum = 0;
            for (int j = 0; j < k; j++) {
                const uint8_t *r = g->pixels + (size_t)(y * k + j) * g->stride + (size_t)x * (size_t)k;
                for (int i = 0; i < k; i++) sum += r[i];
            }
            boxed[(size_t)y * (size_t)bw + (size_t)x] = (uint8_t)((sum + (unsigned)(k * k) / 2) / (unsigned)(k * k));
        }
    int fail = fr_cascade_resize(boxed, bw, bh, (size_t)bw, out, dw, dh, (size_t)dw);
    free(boxed);
    if (fail) {
        free(out);
        return NULL;
    }
    return out;
}

static void mirror_rows(uint8_t *p, int w, int h) {
    for (int y = 0; y < h; y++) {
        uint8_t *row = p + (size_t)y * (size_t)w;
        for (int x = 0; x < w / 2; x++) {
            uint8_t t = row[x];
            row[x] = row[w - 1 - x];
            row[w - 1 - x] = t;
        }
    }
}

/* Append one cascade's boxes (in the w x h working image) scaled by up[0], up[1] to full pixels. */
static frig_status run_one(frig_ctx *ctx, const frig_detector *det, const fr_cascade *c, const uint8_t *px, int w,
                           int h, int mirrored, const double up[2], int source, fr_detected_face **faces,
                           size_t *count) {
    fr_cascade_box *b = NULL;
    size_t n = 0;
    frig_status st = fr_cascade_detect(ctx, c, px, w, h, (size_t)w, det->scale_factor, det->min_neighbors,
                                       det->min_face, det->min_face, 0, 0, &b, &n);
    if (st || n == 0) return st;
    fr_detected_face *v = realloc(*faces, (*count + n) * sizeof *v);
    if (!v) {
        free(b);
        return fr_nomem(ctx, "face boxes");
    }
    *faces = v;
    for (size_t i = 0; i < n; i++) {
        fr_detected_face *f = &v[(*count)++];
        memset(f, 0, sizeof *f);
        double x = mirrored ? (double)(w - b[i].x - b[i].w) : (double)b[i].x;
        f->box[0] = x * up[0];
        f->box[1] = b[i].y * up[1];
        f->box[2] = b[i].w * up[0];
        f->box[3] = b[i].h * up[1];
        f->score = b[i].neighbors;
        f->source = source;
    }
    free(b);
    return FRIG_OK;
}

/* fr_detect_cascade_boxes on a copy no larger than max_side. */
static frig_status cascade_boxes_at(frig_ctx *ctx, const frig_detector *det, const frig_image *gray, unsigned which,
                                    int max_side, fr_detected_face **faces, size_t *count) {
    *faces = NULL;
    *count = 0;
    if ((which & (FR_DETECT_RUN_PROFILE | FR_DETECT_RUN_PROFILE_MIRRORED)) && !det->profile)
        return fr_error(ctx, FRIG_ERR_STATE, "the detector was created with detect.profile = 0 (no profile cascade)");
    int w = gray->width, h = gray->height, side = w > h ? w : h;
    double up[2] = {1.0, 1.0};
    uint8_t *work = NULL;
    if (side > max_side) {
        double s = (double)max_side / side;
        int dw = (int)lround(w * s), dh = (int)lround(h * s);
        dw = dw < 1 ? 1 : dw;
        dh = dh < 1 ? 1 : dh;
        work = downscale(gray, dw, dh);
        if (!work) return fr_nomem(ctx, "a downscaled photo");
        up[0] = (double)w / dw;
        up[1] = (double)h / dh;
        w = dw;
        h = dh;
    } else if (gray->stride != (size_t)w || (which & FR_DETECT_RUN_PROFILE_MIRRORED)) {
        work = malloc((size_t)w * (size_t)h);
        if (!work) return fr_nomem(ctx, "a gray copy");
        for (int y = 0; y < h; y++) memcpy(work + (size_t)y * (size_t)w, gray->pixels + (size_t)y * gray->stride, (size_t)w);
    }
    const uint8_t *px = work ? work : gray->pixels;
    frig_status st = FRIG_OK;
    if (which & FR_DETECT_RUN_FRONTAL)
        st = run_one(ctx, det, det->frontal, px, w, h, 0, up, FRIG_FACE_FRONTAL, faces, count);
    if (!st && (which & FR_DETECT_RUN_PROFILE))
        st = run_one(ctx, det, det->profile, px, w, h, 0, up, FRIG_FACE_PROFILE, faces, count);
    if (!st && (which & FR_DETECT_RUN_PROFILE_MIRRORED)) {
        mirror_rows(work, w, h);
        st = run_one(ctx, det, det->profile, work, w, h, 1, up, FRIG_FACE_PROFILE_MIRRORED, faces, count);
    }
    free(work);
    if (st) {
        free(*faces);
        *faces = NULL;
        *count = 0;
    }
    return st;
}

frig_status fr_detect_cascade_boxes(frig_ctx *ctx, const frig_detector *det, const frig_image *gray, unsigned which,
                                    fr_detected_face **faces, size_t *count) {
    if (!det || !gray || gray->channels != 1 || !faces || !count)
        return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "fr_detect_cascade_boxes: bad argument");
    return cascade_boxes_at(ctx, det, gray, which, det->max_side, faces, count);
}

frig_status fr_detect_frontal(frig_ctx *ctx, const frig_detector *det, const frig_image *gray, fr_detected_face **faces,
                              size_t *count) {
    if (!det || !gray || gray->channels != 1 || !faces || !count)
        return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "fr_detect_frontal: bad argument");
    int side = gray->width > gray->height ? gray->width : gray->height;
    if (det->coarse_side > 0 && det->coarse_side < det->max_side && side > det->coarse_side) {
        frig_status st = cascade_boxes_at(ctx, det, gray, FR_DETECT_RUN_FRONTAL, det->coarse_side, faces, count);
        if (st || *count > 0) return st;
        free(*faces);
        *faces = NULL;
    }
    return cascade_boxes_at(ctx, det, gray, FR_DETECT_RUN_FRONTAL, det->max_side, faces, count);
}

double fr_box_iou(const double a[4], const double b[4]) {
    double x0 = fmax(a[0], b[0]), y0 = fmax(a[1], b[1]);
    double x1 = fmin(a[0] + a[2], b[0] + b[2]), y1 = fmin(a[1] + a[3], b[1] + b[3]);
    double inter = fmax(0.0, x1 - x0) * fmax(0.0, y1 - y0);
    double uni = a[2] * a[3] + b[2] * b[3] - inter;
    return uni > 0 ? inter / uni : 0.0;
}

static double overlap_of_smaller(const double a[4], const double b[4]) {
    double x0 = fmax(a[0], b[0]), y0 = fmax(a[1], b[1]);
    double x1 = fmin(a[0] + a[2], b[0] + b[2]), y1 = fmin(a[1] + a[3], b[1] + b[3]);
    double inter = fmax(0.0, x1 - x0) * fmax(0.0, y1 - y0);
    double small = fmin(a[2] * a[3], b[2] * b[3]);
    return small > 0 ? inter / small : 0.0;
}

/* Merge order: frontal before profile before mirrored profile, then more neighbours, then
 * larger, then top-left first (a total order, so the result does not depend on qsort). */
static int merge_order(const void *pa, const void *pb) {
    const fr_detected_face *a = pa, *b = pb;
    if (a->source != b->source) return a->source < b->source ? -1 : 1;
    if (a->score != b->score) return a->score > b->score ? -1 : 1;
    double aa = a->box[2] * a->box[3], ab = b->box[2] * b->box[3];
    if (aa != ab) return aa > ab ? -1 : 1;
    if (a->box[1] != b->box[1]) return a->box[1] < b->box[1] ? -1 : 1;
    if (a->box[0] != b->box[0]) return a->box[0] < b->box[0] ? -1 : 1;
    return 0;
}

size_t fr_detect_merge(fr_detected_face *faces, size_t count) {
    if (count < 2) return count;
    qsort(faces, count, sizeof *faces, merge_order);
    size_t kept = 0;
    for (size_t i = 0; i < count; i++) {
        int drop = 0;
        for (size_t j = 0; j < kept && !drop; j++)
            drop = fr_box_iou(faces[i].box, faces[j].box) >= 0.3 || overlap_of_smaller(faces[i].box, faces[j].box) >= 0.7;
        if (!drop) faces[kept++] = faces[i];
    }
    return kept;
}

frig_status fr_detect_boxes(frig_ctx *ctx, const frig_detector *det, const frig_image *gray, fr_detected_face **faces,
                            size_t *count) {
    frig_status st = fr_detect_frontal(ctx, det, gray, faces, count);
    if (st || *count > 0 || !det->profile_fallback) return st;
    free(*faces);
    *faces = NULL;
    st = fr_detect_cascade_boxes(ctx, det, gray, FR_DETECT_RUN_PROFILE | FR_DETECT_RUN_PROFILE_MIRRORED, faces, count);
    if (!st) *count = fr_detect_merge(*faces, *count);
    return st;
}
