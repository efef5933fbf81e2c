/* Piecewise-affine face warping (section 4.2; the shape-free texture of active appearance models,
 * Cootes, Edwards, Taylor 2001): each frame pixel inside the reference triangulation is mapped by
 * its triangle's affine map to the photo and sampled bilinearly; then gain and bias are removed. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "filter/face_reference.h"
#include "filter/face_warp.h"
#include "filter/procrustes.h"
#include "image/image.h"

struct fr_face_warp {
    int size, texels, triangles;
    int *index;          /* texel -> y * size + x */
    unsigned char *tri;  /* texel -> triangle */
    double (*bary)[9];   /* per triangle: inverse of [u_a u_b u_c; 1 1 1], row-major */
    double frame[2 * FR_FACE_POINTS];
};

/* Inverse of the 3 x 3 matrix [ax bx cx; ay by cy; 1 1 1] (row-major): it maps (x, y, 1) to the
 * barycentric coordinates of (x, y) in triangle a b c. Returns 0 for a degenerate triangle. */
static int barycentric_inverse(const double *a, const double *b, const double *c, double inv[9]) {
    double det = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]);
    if (fabs(det) < 1e-12) return 0;
    inv[0] = (b[1] - c[1]) / det, inv[1] = (c[0] - b[0]) / det, inv[2] = (b[0] * c[1] - c[0] * b[1]) / det;
    inv[3] = (c[1] - a[1]) / det, inv[4] = (a[0] - c[0]) / det, inv[5] = (c[0] * a[1] - a[0] * c[1]) / det;
    inv[6] = (a[1] - b[1]) / det, inv[7] = (b[0] - a[0]) / det, inv[8] = (a[0] * b[1] - b[0] * a[1]) / det;
    return 1;
}

/* The triangle holding frame point (x, y), or -1. Ties on shared edges go to the first. */
static int find_triangle(const fr_face_warp *w, double x, double y) {
    for (int t = 0; t < w->triangles; t++) {
        const double *m = w->bary[t];
        double l0 = m[0] * x + m[1] * y + m[2], l1 = m[3] * x + m[4] * y + m[5], l2 = m[6] * x + m[7] * y + m[8];
        if (l0 >= -1e-9 && l1 >= -1e-9 && l2 >= -1e-9) return t;
    }
    return -1;
}

frig_status fr_face_warp_create(frig_ctx *ctx, int size, fr_face_warp **out) {
    *out = NULL;
    if (size < 16 || size > 1024)
        return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "face texture size %d is outside [16, 1024]", size);
    int ntri;
    const unsigned char(*tris)[3] = fr_face_triangles(&ntri);
    fr_face_warp *w = calloc(1, sizeof *w);
    if (!w) return fr_nomem(ctx, "a face warp");
    w->size = size;
    w->triangles = ntri;
    w->bary = malloc(sizeof *w->bary * (size_t)ntri);
    w->index = malloc(sizeof(int) * (size_t)size * size);
    w->tri = malloc((size_t)size * size);
    if (!w->bary || !w->index || !w->tri) {
        fr_face_warp_free(w);
        return fr_nomem(ctx, "a face warp");
    }
    const double *ref = fr_face_reference_shape();
    double centre = 0.5 * (size - 1), scale = 0.95 * (size - 1);
    for (int k = 0; k < 2 * FR_FACE_POINTS; k++) w->frame[k] = centre + scale * ref[k];
    for (int t = 0; t < ntri; t++)
        if (!barycentric_inverse(w->frame + 2 * tris[t][0], w->frame + 2 * tris[t][1], w->frame + 2 * tris[t][2],
                                 w->bary[t])) {
            fr_face_warp_free(w);
            return fr_error(ctx, FRIG_ERR_INTERNAL, "reference triangle %d is degenerate at size %d", t, size);
        }
    for (int y = 0; y < size; y++)
        for (int x = 0; x < size; x++) {
            int t = find_triangle(w, x, y);
            if (t < 0) continue;
            w->index[w->texels] = y * size + x;
            w->tri[w->texels++] = (unsigned char)t;
        }
    *out = w;
    return FRIG_OK;
}

void fr_face_warp_free(fr_face_warp *w) {
    if (!w) return;
    free(w->bary);
    free(w->index);
    free(w->tri);
    free(w);
}

int fr_face_warp_size(const fr_face_warp *w) { return w->size; }
int fr_face_warp_texels(const fr_face_warp *w) { return w->texels; }
const int *fr_face_warp_texel_index(const fr_face_warp *w) { return w->index; }
const double *fr_face_warp_frame_shape(const fr_face_warp *w) { return w->frame; }

/* Gray value at a pixel (BT.601 for RGB). */
static inline double gray_at(const frig_image *img, int x, int y) {
    const uint8_t *p = img->pixels + (size_t)y * img->stride + (size_t)x * img->channels;
    return img->channels == 1 ? p[0] : 0.299 * p[0] + 0.587 * p[1] + 0.114 * p[2];
}

/* Bilinear gray value at (x, y), clamped to the image. */
static double bilinear(const frig_image *img, double x, double y) {
    x = fmin(fmax(x, 0.0), img->width - 1.0);
    y = fmin(fmax(y, 0.0), img->height - 1.0);
    int x0 = (int)x, y0 = (int)y;
    int x1 = x0 + 1 < img->width ? x0 + 1 : x0, y1 = y0 + 1 < img->height ? y0 + 1 : y0;
    double fx = x - x0, fy = y - y0;
    double top = (1 - fx) * gray_at(img, x0, y0) + fx * gray_at(img, x1, y0);
    double bottom = (1 - fx) * gray_at(img, x0, y1) + fx * gray_at(img, x1, y1);
    return (1 - fy) * top + fy * bottom;
}

/* How many times larger the face is in the photo than in the frame: the scale of the similarity
 * that best maps the frame shape onto the landmarks. */
static double face_scale(const fr_face_warp *w, const double *lm) {
    double T[4];
    fr_similarity_fit(FR_FACE_POINTS, w->frame, lm, T);
    return hypot(T[0], T[1]);
}

frig_status fr_face_warp_sample(frig_ctx *ctx, const fr_face_warp *w, const frig_image *img,
                                const double *landmarks, double *texture, double *outside) {
    if (outside) *outside = 0;
    if (!w || !img || !landmarks || !texture)
        return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "face warp: NULL argument");
    for (int k = 0; k < 2 * FR_FACE_POINTS; k++)
        if (!isfinite(landmarks[k]))
            return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "face warp: landmark %d is not a finite number", k / 2);
    int ntri;
    const unsigned char(*tris)[3] = fr_face_triangles(&ntri);
    /* Affine map of each triangle, frame -> photo: A = [q_a q_b q_c] * bary (2 x 3, row-major). */
    double(*A)[6] = malloc(sizeof *A * (size_t)ntri);
    if (!A) return fr_nomem(ctx, "face warp maps");
    for (int t = 0; t < ntri; t++)
        for (int r = 0; r < 2; r++)
            for (int c = 0; c < 3; c++) {
                const double *m = w->bary[t];
                A[t][3 * r + c] = landmarks[2 * tris[t][0] + r] * m[c] + landmarks[2 * tris[t][1] + r] * m[3 + c] +
                                  landmarks[2 * tris[t][2] + r] * m[6 + c];
            }
    double ratio = face_scale(w, landmarks);
    int n = ratio > 1 ? (int)ceil(ratio - 1e-9) : 1;
    if (n > 8) n = 8;
    long out_count = 0;
    for (int k = 0; k < w->texels; k++) {
        const double *a = A[w->tri[k]];
        double fx = w->index[k] % w->size, fy = w->index[k] / w->size;
        double cx = a[0] * fx + a[1] * fy + a[2], cy = a[3] * fx + a[4] * fy + a[5];
        out_count += cx < -0.5 || cy < -0.5 || cx > img->width - 0.5 || cy > img->height - 0.5;
        double sum = 0;
        for (int j = 0; j < n; j++)
            for (int i = 0; i < n; i++) {
                double sx = fx + (i + 0.5) / n - 0.5, sy = fy + (j + 0.5) / n - 0.5;
                sum += bilinear(img, a[0] * sx + a[1] * sy + a[2], a[3] * sx + a[4] * sy + a[5]);
            }
        texture[k] = sum / (n * n);
    }
    free(A);
    if (outside) *outside = w->texels ? (double)out_count / w->texels : 0;
    return FRIG_OK;
}

int fr_texture_normalize(int count, double *t) {
    double mean = 0, var = 0;
    for (int k = 0; k < count; k++) mean += t[k];
    mean /= count > 0 ? count : 1;
    for (int k = 0; k < count; k++) var += (t[k] - mean) * (t[k] - mean);
    double sd = count > 0 ? sqrt(var / count) : 0;
    if (!(sd >= 1e-6)) {
        memset(t, 0, sizeof(double) * (size_t)(count > 0 ? count : 0));
        return 0;
    }
    for (int k = 0; k < count; k++) t[k] = (t[k] - mean) / sd;
    return 1;
}

frig_status fr_face_texture(frig_ctx *ctx, const fr_face_warp *w, const frig_image *img, const double *landmarks,
                            double *texture, double *outside) {
    frig_status st = fr_face_warp_sample(ctx, w, img, landmarks, texture, outside);
    if (st != FRIG_OK) return st;
    if (!fr_texture_normalize(w->texels, texture))
        return fr_error(ctx, FRIG_ERR_NO_FACE, "the face under the landmarks is flat (no texture to compare)");
    return FRIG_OK;
}
