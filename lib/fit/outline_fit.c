/* The subject's identity and every photo's pose refined from the photos' outlines (beyond the
 * paper: its sections 4.3-4.4 fit the identity to 68 landmarks per photo, whose jaw points are
 * the only outline they see). Measured on frig synth subjects, even the truth's own landmarks
 * leave the fitted neutral 2.7-3.5 mm from the truth (docs/fit.md, "The outlines"): 68 points do
 * not fix the model's 100 identity modes. Where a photo sees the head edge-on (cheeks, jaw, chin,
 * neck, forehead of a turned face) its outline against the background is a dense measurement of
 * the shape, and photos turned every way put it on different parts of the head.
 *
 * Each step draws the model at the current identity, each photo's expression and pose into a crop
 * of the photo (area-averaged in linear light, the face's longer side about 160 pixels, blurred by
 * a pixel), pairs every outline pixel (a face-skin triangle next to a pixel with no triangle, seen
 * at more than 66 degrees, between the brows' height and a little below the chin: band_init) with
 * the photo's strongest edge along its outward direction (within 4 pixels, nearer ones
 * preferred; kept only where the photo 3 pixels inside the edge looks like the face's skin:
 * skin_inside), and takes one Gauss-Newton step of
 *     sum_photos sum_pairs huber(nu . (p(X) - e)) + prior |w|^2
 * in the identity w (the model's modes, shared; the face's size held when fit.mean_size is set)
 * and each photo's rotation and translation (6 values, eliminated per photo by their Schur
 * complement; p the crop's projection, X the outline point, nu its outward direction, e the
 * edge; Huber at a pixel, pairs more than 3 pixels apart left out), plus each photo's inner
 * landmarks (iBUG 17-67: brows, eyes, nose, mouth) at 3 crop pixels' weight, which keep the pose
 * from sliding along the outline (without them the rotation's median error on turned photos grew
 * from 6.6 to 10 degrees and the mouth left the photo's). The band leaves out the forehead,
 * scalp and lower neck, whose outline in real photos is mostly hair and collars: with them the
 * free size of two real talking-head videos came out 0.84 and 0.81 times the mean face's, the
 * model's outline paired with the hair over the temples (docs/fit.md). The skin test stops the
 * outline creeping inward over strands of hair on the cheeks and ears, one edge per step (the
 * same videos' sizes fell from 0.95 after 4 steps to 0.85 after 32 without it). The photos'
 * per-photo work runs in parallel; the sums are made in photo order (the same result for any
 * thread count). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <omp.h>

#include "core/context.h"
#include "core/sort.h"
#include "fit/outline_fit.h"
#include "image/area_crop.h"
#include "image/bilinear.h"
#include "image/gaussian_blur.h"
#include "image/image.h"
#include "linalg/linalg.h"
#include "mesh/topology.h"
#include "model/face_size.h"
#include "model/mode_sums.h"
#include "model/model.h"
#include "raster/raster.h"
#include "raster/rotation.h"

#define FACE_PX 160.0     /* the crop's face, longer side */
#define MARGIN_SHARE 0.08 /* the crop's margin around the face */
#define BLUR_PX 1.0       /* the photo's blur before its edges are read */
#define EDGE_ON_COS 0.4   /* outline pixels are seen at more than 66 degrees */
#define WINDOW_PX 4.0     /* the edge is searched this far either side */
#define HUBER_PX 1.0
#define MAX_PX 3.0        /* pairs farther apart are left out */
#define OUTLINE_OFFSET 0.5 /* the outline pixel's centre lies about this far inside the outline */
#define LANDMARK_PX 3.0    /* the inner landmarks' error (crop pixels of a 160-pixel face): they keep the
                            * eyes, nose and mouth where the landmark fit put them */
#define FIRST_INNER 17     /* iBUG 0-16 are the jaw: the outline's */
#define BELOW_CHIN 0.3     /* the outline's band reaches this share of the brow-to-chin height below the
                            * chin (band_init) */
#define SKIN_INSET_PX 3.0  /* an edge is the face's when the photo this far inside it looks like the face's */
#define SKIN_LUMA 8.0      /* skin: within this factor of the face's median luminance */
#define SKIN_CHROMA 0.05   /* and this near its median chromaticity (r, g of r + g + b) */

typedef struct view {
    int ok, w, h;
    fr_camera cam;   /* the crop's */
    double x0, y0, s; /* crop = (photo - origin + 0.5) s - 0.5, origin (x0, y0) */
    float *I;        /* blurred linear RGB, 3 per pixel */
    uint8_t *inside; /* pixel centre inside the photo */
} view;

/* One photo's part of a step: over [identity (n), pose (6)], A (n x n), B (n x 6), C (6 x 6), g
 * (n), u (6), the turn's centre, and the pairs' count and squared residuals. */
typedef struct part {
    double *A, *B, C[36], *g, u[6], centre[3];
    double rss, lss; /* squared outline and landmark residuals, pixels^2 */
    int pairs, landmarks;
} part;

typedef struct mesh {
    int nt;
    int32_t *tris;   /* opaque triangles */
    uint8_t *skin;   /* per drawn triangle: face skin */
    uint8_t *band;   /* per drawn triangle: face skin within the outline's band (band_init) */
    int32_t *vertex; /* face-skin vertices, for the crop box */
    int nface;
} mesh;

static void mesh_free(mesh *m) { free(m->tris), free(m->skin), free(m->band), free(m->vertex); }

/* Which vertices may give outline pixels: all (band 0), or those from the brows' height (the
 * mean of landmarks 17-26 on the model's neutral) down to BELOW_CHIN of the brow-to-chin height
 * below the chin (landmark 8), the model's y axis up. */
static uint8_t *band_init(const fr_fit_model *fm, int band) {
    const frig_model *model = fm->model;
    int nv = model->topo.vertex_count;
    uint8_t *in = malloc((size_t)nv + 1);
    if (!in) return NULL;
    if (!band) return memset(in, 1, (size_t)nv + 1);
    double brows = 0, chin = model->neutral[3 * (size_t)fm->landmark_vertex[8] + 1];
    for (int k = 17; k < 27; k++) brows += model->neutral[3 * (size_t)fm->landmark_vertex[k] + 1] / 10;
    double low = chin - BELOW_CHIN * (brows - chin);
    for (int i = 0; i < nv; i++) {
        double y = model->neutral[3 * (size_t)i + 1];
        in[i] = y <= brows && y >= low;
    }
    return in;
}

static frig_status mesh_init(frig_ctx *ctx, const fr_fit_model *fm, int band, mesh *m) {
    const fr_topology *t = &fm->model->topo;
    memset(m, 0, sizeof *m);
    m->tris = malloc(sizeof(int32_t) * 3 * ((size_t)t->triangle_count + 1));
    m->skin = malloc((size_t)t->triangle_count + 1);
    m->band = malloc((size_t)t->triangle_count + 1);
    uint8_t *seen = calloc((size_t)t->vertex_count + 1, 1), *in = band_init(fm, band);
    m->vertex = malloc(sizeof(int32_t) * ((size_t)t->vertex_count + 1));
    if (!m->tris || !m->skin || !m->band || !seen || !in || !m->vertex) {
        free(seen), free(in);
        return fr_nomem(ctx, "the outline fit");
    }
    for (int i = 0; i < t->triangle_count; i++) {
        if (!fr_topology_opaque(t, i)) continue;
        const int32_t *t3 = t->triangles + 3 * (size_t)i;
        memcpy(m->tris + 3 * (size_t)m->nt, t3, sizeof(int32_t) * 3);
        m->skin[m->nt] = (uint8_t)fr_topology_face_skin(t, i);
        m->band[m->nt] = (uint8_t)(m->skin[m->nt] && in[t3[0]] && in[t3[1]] && in[t3[2]]);
        for (int c = 0; m->skin[m->nt] && c < 3; c++)
            if (!seen[t3[c]]) seen[t3[c]] = 1, m->vertex[m->nface++] = t3[c];
        m->nt++;
    }
    free(seen), free(in);
    return FRIG_OK;
}

/* The model at identity w (n of the model's modes) and photo a's fitted expression, head frame. */
static frig_status pose_model(frig_ctx *ctx, const fr_fit_model *fm, const double *w, const fr_fit_result *r,
                              double *id_full, double *ex_full, float *xyz) {
    const frig_model *model = fm->model;
    memset(id_full, 0, sizeof(double) * (size_t)model->identity_count);
    memset(ex_full, 0, sizeof(double) * (size_t)model->expression_count);
    memcpy(id_full, w, sizeof(double) * (size_t)fm->n_id);
    for (int k = 0; k < fm->n_exp; k++) ex_full[fm->exp_index[k]] = r->w[fm->n_id + k];
    return frig_model_eval(ctx, model, id_full, ex_full, xyz);
}

static fr_camera full_camera(const fr_fit_result *r, int W, int H) {
    return r->perspective ? fr_camera_perspective(r->f, W, H) : fr_camera_weak(r->f, W, H);
}

/* Photo a's crop around the face as fitted, read and blurred. */
static frig_status view_build(frig_ctx *ctx, const mesh *m, const char *path, int W, int H, const fr_fit_result *r,
                              const float *xyz, view *v) {
    memset(v, 0, sizeof *v);
    fr_camera full = full_camera(r, W, H);
    double box[4] = {INFINITY, INFINITY, -INFINITY, -INFINITY};
    for (int k = 0; k < m->nface; k++) {
        const float *x = xyz + 3 * (size_t)m->vertex[k];
        double p[3], c[3] = {x[0], x[1], x[2]}, uv[2];
        fr_mat3_apply(r->R, c, p);
        for (int d = 0; d < 3; d++) p[d] += r->t[d];
        if (!fr_camera_project(&full, p, uv)) continue;
        box[0] = fmin(box[0], uv[0]), box[1] = fmin(box[1], uv[1]), box[2] = fmax(box[2], uv[0]), box[3] = fmax(box[3], uv[1]);
    }
    double size = fmax(box[2] - box[0], box[3] - box[1]);
    if (!(size > 8)) return FRIG_OK; /* no face to read: left out */
    double grow = MARGIN_SHARE * size, s = size > FACE_PX ? FACE_PX / size : 1.0;
    double x0 = fmax(-0.5, box[0] - grow), y0 = fmax(-0.5, box[1] - grow);
    double x1 = fmin(W - 0.5, box[2] + grow), y1 = fmin(H - 0.5, box[3] + grow);
    if (!(x1 - x0 > 8 && y1 - y0 > 8)) return FRIG_OK;
    x0 = floor(x0 + 0.5), y0 = floor(y0 + 0.5);
    v->x0 = x0, v->y0 = y0, v->s = s;
    v->w = (int)ceil((x1 + 0.5 - x0) * s), v->h = (int)ceil((y1 + 0.5 - y0) * s);
    v->cam = full;
    if (r->perspective) v->cam.f *= s;
    else v->cam.scale *= s;
    v->cam.cx = (full.cx - x0 + 0.5) * s - 0.5, v->cam.cy = (full.cy - y0 + 0.5) * s - 0.5;
    int reduce = 1;
    while (reduce < 8 && 2.0 * reduce * s <= 1.0) reduce *= 2;
    size_t np = (size_t)v->w * v->h;
    float *lin = malloc(sizeof(float) * 3 * np);
    v->I = malloc(sizeof(float) * 3 * np), v->inside = malloc(np);
    frig_image *img = NULL;
    int got = 1;
    frig_status st = lin && v->I && v->inside ? fr_image_load_reduced(ctx, path, FRIG_LOAD_DEFAULT, reduce, &img, &got)
                                               : fr_nomem(ctx, "the outline fit");
    if (!st) st = fr_area_crop(ctx, img, x0 / got, y0 / got, 1.0 / (s * got), v->w, v->h, lin, NULL, v->inside);
    if (!st) st = fr_gaussian_blur(ctx, lin, v->w, v->h, 3, BLUR_PX, v->I);
    frig_image_free(img);
    free(lin);
    v->ok = !st;
    return st;
}

static void view_free(view *v) { free(v->I), free(v->inside); }

/* The blurred photo's derivative across nu at xy, summed over the channels in absolute value. */
static double edge_strength(const view *v, const double xy[2], const double nu[2]) {
    double a[3], b[3], xa[2] = {xy[0] + nu[0], xy[1] + nu[1]}, xb[2] = {xy[0] - nu[0], xy[1] - nu[1]};
    fr_bilinear3(v->I, v->w, v->h, xa, a), fr_bilinear3(v->I, v->w, v->h, xb, b);
    return fabs(a[0] - b[0]) + fabs(a[1] - b[1]) + fabs(a[2] - b[2]);
}

/* Pixel i's outward direction when it is an outline pixel (its neighbours with no triangle all
 * inside the photo). */
static int outward(const view *v, const fr_raster *r, int x, int y, double nu[2]) {
    int bg = 0;
    nu[0] = nu[1] = 0;
    for (int dy = -1; dy <= 1; dy++)
        for (int dx = -1; dx <= 1; dx++) {
            size_t q = (size_t)(y + dy) * v->w + (size_t)(x + dx);
            if (r->tri[q] >= 0) continue;
            if (!v->inside[q]) return 0;
            nu[0] += dx, nu[1] += dy, bg++;
        }
    double l = sqrt(nu[0] * nu[0] + nu[1] * nu[1]);
    if (!bg || !(l > 0)) return 0;
    nu[0] /= l, nu[1] /= l;
    return 1;
}

/* The offset of the photo's strongest edge along nu from pixel (x, y) (nearer ones preferred);
 * 0 when none. */
static int edge_along(const view *v, int x, int y, const double nu[2], double *at) {
    double best = 0;
    int found = 0;
    for (double sd = -WINDOW_PX; sd <= WINDOW_PX + 1e-9; sd += 0.5) {
        double p[2] = {x + sd * nu[0], y + sd * nu[1]};
        if (p[0] < 1 || p[1] < 1 || p[0] > v->w - 2 || p[1] > v->h - 2) continue;
        double e = edge_strength(v, p, nu) * exp(-0.5 * sd * sd / (WINDOW_PX * WINDOW_PX));
        if (e > best) best = e, *at = sd, found = 1;
    }
    return found;
}

/* A colour's luminance and chromaticity (r and g over r + g + b) into out; 0 when it is black. */
static int skin_coords(double r, double g, double b, double out[3]) {
    double sum = r + g + b;
    if (!(sum > 1e-4)) return 0;
    out[0] = 0.2126 * r + 0.7152 * g + 0.0722 * b, out[1] = r / sum, out[2] = g / sum;
    return 1;
}

/* The face's skin in this view: the medians of luminance and chromaticity (r and g over r + g +
 * b) over the pixels the band's triangles cover. Returns 1, 0 without such pixels, -1 without
 * memory. */
static int skin_colour(const view *v, const fr_raster *r, const mesh *m, double ref[3]) {
    size_t n = (size_t)v->w * v->h, k = 0;
    double *a = malloc(sizeof(double) * 3 * (n + 1));
    if (!a) return -1;
    for (size_t i = 0; i < n; i++) {
        if (r->tri[i] < 0 || !m->band[r->tri[i]]) continue;
        const float *c = v->I + 3 * i;
        double q[3];
        if (!skin_coords(c[0], c[1], c[2], q)) continue;
        a[k] = q[0], a[n + k] = q[1], a[2 * n + k] = q[2];
        k++;
    }
    for (int d = 0; d < 3 && k > 0; d++) {
        qsort(a + d * n, k, sizeof(double), fr_cmp_double);
        ref[d] = a[d * n + k / 2];
    }
    free(a);
    return k > 0;
}

/* Whether the photo SKIN_INSET_PX inside the edge at (x, y) looks like the face's skin (ref): an
 * edge with hair on both sides (strands over a cheek) is not the face's outline. */
static int skin_inside(const view *v, const double ref[3], double x, double y, const double nu[2]) {
    double p[2] = {x - SKIN_INSET_PX * nu[0], y - SKIN_INSET_PX * nu[1]}, c[3], q[3];
    fr_bilinear3(v->I, v->w, v->h, p, c);
    if (!skin_coords(c[0], c[1], c[2], q) || !(q[0] > ref[0] / SKIN_LUMA && q[0] < ref[0] * SKIN_LUMA)) return 0;
    return hypot(q[1] - ref[1], q[2] - ref[2]) < SKIN_CHROMA;
}

/* One linearized residual (row: n identity values, then 6 pose values) added to the part with
 * weight wt. */
static void add_row(part *pa, int n, const double *row, double wt, double rr) {
    for (int a = 0; a < n; a++) {
        double ra = wt * row[a];
        if (ra == 0) continue;
        pa->g[a] -= ra * rr;
        for (int c = a; c < n; c++) pa->A[(size_t)a * n + c] += ra * row[c];
        for (int c = 0; c < 6; c++) pa->B[(size_t)a * 6 + c] += ra * row[n + c];
    }
    for (int a = 0; a < 6; a++) {
        pa->u[a] -= wt * row[n + a] * rr;
        for (int c = 0; c < 6; c++) pa->C[6 * a + c] += wt * row[n + a] * row[n + c];
    }
}

/* The row of a residual jn . X (jn: its derivative by the camera-frame point X, at model vertex
 * corners t3 with barycentrics b): identity modes through R, then the turn about the centre and
 * the shift. Ut: the n identity modes vertex by vertex (n x 3 floats per vertex), so that a
 * corner's modes are one contiguous read. */
static void fill_row(const float *Ut, int n, const double R[9], const int32_t *t3, const float *b,
                     const double jn[3], const double X[3], const double centre[3], double *row) {
    double jh[3];
    for (int d = 0; d < 3; d++) jh[d] = R[d] * jn[0] + R[3 + d] * jn[1] + R[6 + d] * jn[2];
    for (int k = 0; k < n; k++) row[k] = 0;
    for (int c = 0; c < 3; c++) {
        const float *u = Ut + 3 * (size_t)n * (size_t)t3[c];
        for (int k = 0; k < n; k++) row[k] += b[c] * (jh[0] * u[3 * k] + jh[1] * u[3 * k + 1] + jh[2] * u[3 * k + 2]);
    }
    double q[3] = {X[0] - centre[0], X[1] - centre[1], X[2] - centre[2]};
    row[n + 0] = q[1] * jn[2] - q[2] * jn[1];
    row[n + 1] = q[2] * jn[0] - q[0] * jn[2];
    row[n + 2] = q[0] * jn[1] - q[1] * jn[0];
    row[n + 3] = jn[0], row[n + 4] = jn[1], row[n + 5] = jn[2];
}

/* The inner landmarks' rows (iBUG 17-67 at the fit's landmark vertices), x and y each, in crop
 * pixels, weighed 1 / LANDMARK_PX^2 (Huber at LANDMARK_PX). */
static void landmark_rows(const fr_fit_model *fm, const float *Ut, int n, const view *v, const fr_fit_result *res,
                          const double *landmarks, const float *cam, const double centre[3], double *row, part *pa) {
    for (int l = FIRST_INNER; l < 68 && l < fm->model->landmark_count; l++) {
        int vtx = fm->landmark_vertex[l];
        double X[3] = {cam[3 * (size_t)vtx], cam[3 * (size_t)vtx + 1], cam[3 * (size_t)vtx + 2]}, uv[2], J[6];
        if (!fr_camera_project(&v->cam, X, uv)) continue;
        fr_camera_project_jacobian(&v->cam, X, J);
        int32_t t3[3] = {vtx, vtx, vtx};
        float b[3] = {1, 0, 0};
        for (int c = 0; c < 2; c++) {
            double target = (landmarks[2 * l + c] - (c ? v->y0 : v->x0) + 0.5) * v->s - 0.5;
            double rr = (uv[c] - target) / LANDMARK_PX, jn[3] = {J[3 * c] / LANDMARK_PX, J[3 * c + 1] / LANDMARK_PX,
                                                               J[3 * c + 2] / LANDMARK_PX};
            fill_row(Ut, n, res->R, t3, b, jn, X, centre, row);
            add_row(pa, n, row, fabs(rr) <= 1 ? 1.0 : 1.0 / fabs(rr), rr);
            pa->lss += rr * rr * LANDMARK_PX * LANDMARK_PX, pa->landmarks++;
        }
    }
}

/* Photo a's part of the step at identity w: its outline drawn, paired and linearized. xyz (3 nv)
 * and cam (3 nv) are scratch. */
static frig_status photo_part(frig_ctx *ctx, const fr_fit_model *fm, const float *Ut, const mesh *m, const view *v,
                              const fr_fit_result *res, const double *landmarks, const double *w, double *id_full,
                              double *ex_full, float *xyz, float *cam, float *nrm, double *row, part *pa) {
    const frig_model *model = fm->model;
    int n = fm->n_id, nv = model->topo.vertex_count;
    memset(pa->A, 0, sizeof(double) * (size_t)n * n), memset(pa->B, 0, sizeof(double) * (size_t)n * 6);
    memset(pa->g, 0, sizeof(double) * (size_t)n), memset(pa->C, 0, sizeof pa->C), memset(pa->u, 0, sizeof pa->u);
    pa->rss = pa->lss = 0, pa->pairs = pa->landmarks = 0;
    frig_status st = pose_model(ctx, fm, w, res, id_full, ex_full, xyz);
    fr_raster *r = NULL;
    if (!st) {
        fr_transform_points(res->R, res->t, xyz, nv, cam);
        fr_mesh_vertex_normals(cam, nv, m->tris, m->nt, nrm);
        st = fr_raster_create(ctx, v->w, v->h, &r);
    }
    fr_raster_options ro = {FR_RASTER_DEFAULT_NEAR, 1};
    if (!st) st = fr_raster_render(ctx, r, &v->cam, cam, nv, m->tris, m->nt, &ro);
    if (st) {
        fr_raster_free(r);
        return st;
    }
    /* the turn's centre: the drawn face's mean point (camera frame) */
    double centre[3] = {0, 0, 0};
    int nc = 0;
    for (size_t i = 0; i < (size_t)v->w * v->h; i++)
        if (r->tri[i] >= 0 && m->skin[r->tri[i]]) {
            const int32_t *t3 = m->tris + 3 * (size_t)r->tri[i];
            for (int c = 0; c < 3; c++)
                for (int d = 0; d < 3; d++) centre[d] += r->bary[3 * i + c] * cam[3 * (size_t)t3[c] + d];
            nc++;
        }
    for (int d = 0; d < 3 && nc; d++) centre[d] /= nc;
    memcpy(pa->centre, centre, sizeof centre);
    double skin[3];
    int has_skin = skin_colour(v, r, m, skin);
    if (has_skin < 0) {
        fr_raster_free(r);
        return fr_nomem(ctx, "the outline fit");
    }
    for (int y = 2; y < v->h - 2; y++)
        for (int x = 2; x < v->w - 2; x++) {
            size_t i = (size_t)y * v->w + x;
            int32_t tr = r->tri[i];
            double nu[2], X[3] = {0, 0, 0}, nc3[3] = {0, 0, 0}, at = 0;
            if (tr < 0 || !m->band[tr] || !v->inside[i] || !outward(v, r, x, y, nu)) continue;
            const int32_t *t3 = m->tris + 3 * (size_t)tr;
            const float *b = r->bary + 3 * i;
            for (int c = 0; c < 3; c++)
                for (int d = 0; d < 3; d++)
                    X[d] += b[c] * cam[3 * (size_t)t3[c] + d], nc3[d] += b[c] * nrm[3 * (size_t)t3[c] + d];
            double xl = sqrt(X[0] * X[0] + X[1] * X[1] + X[2] * X[2]);
            double nl = sqrt(nc3[0] * nc3[0] + nc3[1] * nc3[1] + nc3[2] * nc3[2]);
            if (!(xl > 0) || !(nl > 0) || fabs(nc3[0] * X[0] + nc3[1] * X[1] + nc3[2] * X[2]) / (xl * nl) > EDGE_ON_COS)
                continue;
            if (!edge_along(v, x, y, nu, &at) || !has_skin || !skin_inside(v, skin, x + at * nu[0], y + at * nu[1], nu))
                continue;
            double rr = OUTLINE_OFFSET - at; /* the drawn outline's distance outside the photo's edge */
            if (fabs(rr) > MAX_PX) continue;
            double wt = fabs(rr) <= HUBER_PX ? 1.0 : HUBER_PX / fabs(rr);
            /* d r / d X (camera) = nu . J; the pose: a turn om about the centre moves X by om x q */
            double J[6], jn[3];
            fr_camera_project_jacobian(&v->cam, X, J);
            for (int d = 0; d < 3; d++) jn[d] = nu[0] * J[d] + nu[1] * J[3 + d];
            fill_row(Ut, n, res->R, t3, b, jn, X, centre, row);
            add_row(pa, n, row, wt, rr);
            pa->rss += rr * rr, pa->pairs++;
        }
    if (landmarks && pa->pairs) landmark_rows(fm, Ut, n, v, res, landmarks, cam, centre, row, pa);
    for (int a = 0; a < n; a++)
        for (int c = 0; c < a; c++) pa->A[(size_t)a * n + c] = pa->A[(size_t)c * n + a];
    fr_raster_free(r);
    return FRIG_OK;
}

/* The photo's pose moved by its step (turn om about the centre, then shift dt). */
static void move_pose(fr_fit_result *r, const double step[6], const double centre[3]) {
    double dR[9], R2[9], rel[3], rr[3];
    fr_rotation_from_axis_angle(step, dR);
    fr_mat3_mul(dR, r->R, R2);
    for (int c = 0; c < 3; c++) rel[c] = r->t[c] - centre[c];
    fr_mat3_apply(dR, rel, rr);
    for (int c = 0; c < 3; c++) r->t[c] = rr[c] + centre[c] + step[3 + c];
    memcpy(r->R, R2, sizeof R2);
}

frig_status fr_fit_outline(frig_ctx *ctx, const fr_fit_model *fm, const fr_outline_options *o, int n,
                           const char *const *paths, const fr_fit_input *in, fr_fit_result *res, double *identity,
                           double moved[2]) {
    if (moved) moved[0] = moved[1] = 0;
    if (o->iterations <= 0 || n <= 0 || fm->n_id <= 0) return FRIG_OK;
    const frig_model *model = fm->model;
    int nid = fm->n_id, nv = model->topo.vertex_count, threads = o->threads > 0 ? o->threads : 1;
    size_t nv3 = 3 * (size_t)nv;
    mesh m;
    frig_status st = mesh_init(ctx, fm, o->band, &m);
    view *views = calloc((size_t)n, sizeof *views);
    part *parts = calloc((size_t)n, sizeof *parts);
    size_t scratch = 3 * nv3 + (size_t)model->identity_count + (size_t)model->expression_count + (size_t)nid + 6;
    float *fbuf = malloc(sizeof(float) * 3 * nv3 * (size_t)threads);
    double *dbuf = malloc(sizeof(double) * scratch * (size_t)threads);
    double *S = malloc(sizeof(double) * ((size_t)nid * nid + nid)), *X = malloc(sizeof(double) * 6 * ((size_t)nid + 1));
    double *store = malloc(sizeof(double) * ((size_t)nid * nid + (size_t)nid * 6 + nid) * (size_t)n);
    float *Ut = malloc(sizeof(float) * nv3 * (size_t)nid + 1); /* the identity modes vertex by vertex */
    if (Ut) fr_modes_by_vertex(model->identity, (size_t)nv, nid, Ut);
    if (!st && (!views || !parts || !fbuf || !dbuf || !S || !X || !store || !Ut)) st = fr_nomem(ctx, "the outline fit");
    for (int a = 0; a < n && !st; a++) {
        double *p = store + ((size_t)nid * nid + (size_t)nid * 6 + nid) * (size_t)a;
        parts[a].A = p, parts[a].B = p + (size_t)nid * nid, parts[a].g = parts[a].B + (size_t)nid * 6;
    }
    /* the crops, from the fit's poses */
    int failed = 0, saved = fr_blas_serial_begin();
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
    for (int a = 0; a < n; a++) {
        if (st || failed) continue;
        int tid = omp_get_thread_num();
        float *xyz = fbuf + 3 * nv3 * (size_t)tid;
        double *id_full = dbuf + scratch * (size_t)tid, *ex_full = id_full + model->identity_count;
        frig_ctx *local = frig_ctx_create(); /* a photo that cannot be read is left out */
        if (!local) {
            failed = 1;
            continue;
        }
        if (pose_model(local, fm, identity, &res[a], id_full, ex_full, xyz) ||
            view_build(local, &m, paths[a], in[a].width, in[a].height, &res[a], xyz, &views[a]))
            views[a].ok = 0;
        frig_ctx_free(local);
    }
    if (failed && !st) st = fr_nomem(ctx, "the outline fit");
    double *step = malloc(sizeof(double) * ((size_t)nid + 1));
    if (!step && !st) st = fr_nomem(ctx, "the outline fit");
    for (int it = 0; it <= o->iterations && !st; it++) {
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
        for (int a = 0; a < n; a++) {
            parts[a].pairs = 0;
            if (st || failed || !views[a].ok) continue;
            int tid = omp_get_thread_num();
            float *xyz = fbuf + 3 * nv3 * (size_t)tid, *cam = xyz + nv3, *nrm = cam + nv3;
            double *id_full = dbuf + scratch * (size_t)tid, *ex_full = id_full + model->identity_count;
            double *row = ex_full + model->expression_count;
            frig_ctx child;
            fr_ctx_init_child(&child, ctx);
            if (photo_part(&child, fm, Ut, &m, &views[a], &res[a], in[a].landmarks, identity, id_full, ex_full, xyz,
                           cam, nrm, row, &parts[a]))
                failed = 1;
        }
        if (failed) {
            st = fr_nomem(ctx, "the outline fit");
            break;
        }
        double rss = 0, lss = 0;
        long pairs = 0, lms = 0;
        for (int a = 0; a < n; a++) rss += parts[a].rss, pairs += parts[a].pairs, lss += parts[a].lss, lms += parts[a].landmarks;
        if (moved) moved[it == 0 ? 0 : 1] = pairs ? sqrt(rss / pairs) : 0;
        if (it == 0 || it == o->iterations)
            for (int a = 0; a < n; a++)
                fr_log(ctx, FRIG_LOG_DEBUG, "fit: outline step %d, photo %d: %d pairs, RMS %.2f px", it, a, parts[a].pairs,
                       parts[a].pairs ? sqrt(parts[a].rss / parts[a].pairs) : 0.0);
        fr_log(ctx, FRIG_LOG_DEBUG, "fit: outline step %d: %ld outline pixels paired, RMS %.2f px; inner landmarks RMS %.2f px",
               it, pairs, pairs ? sqrt(rss / pairs) : 0.0, lms ? sqrt(lss / lms) : 0.0);
        if (it == o->iterations || !pairs) break;
        /* The identity step: the poses eliminated photo by photo, summed in photo order. */
        memset(S, 0, sizeof(double) * ((size_t)nid * nid + nid));
        double *g = S + (size_t)nid * nid;
        for (int a = 0; a < n && !st; a++) {
            part *pa = &parts[a];
            if (!pa->pairs) continue;
            double C[36];
            memcpy(C, pa->C, sizeof C);
            for (int k = 0; k < 6; k++) C[7 * k] += 1e-6 * C[7 * k] + 1e-9;
            for (int x = 0; x < nid; x++)
                for (int y = 0; y < 6; y++) X[6 * x + y] = pa->B[(size_t)x * 6 + y];
            memcpy(X + 6 * (size_t)nid, pa->u, sizeof pa->u);
            if ((st = fr_solve_spd(ctx, 6, nid + 1, C, 6, X, 6))) break;
            for (int x = 0; x < nid; x++) {
                const double *bx = pa->B + (size_t)x * 6;
                for (int y = 0; y < nid; y++) {
                    const double *xy = X + 6 * (size_t)y;
                    S[(size_t)x * nid + y] += pa->A[(size_t)x * nid + y] -
                                              (bx[0] * xy[0] + bx[1] * xy[1] + bx[2] * xy[2] + bx[3] * xy[3] +
                                               bx[4] * xy[4] + bx[5] * xy[5]);
                }
                const double *xu = X + 6 * (size_t)nid;
                g[x] += pa->g[x] - (bx[0] * xu[0] + bx[1] * xu[1] + bx[2] * xu[2] + bx[3] * xu[3] + bx[4] * xu[4] +
                                    bx[5] * xu[5]);
            }
        }
        if (st) break;
        for (int x = 0; x < nid; x++) S[(size_t)x * nid + x] += o->prior, g[x] -= o->prior * identity[x];
        memcpy(step, g, sizeof(double) * (size_t)nid);
        st = o->mean_size && fm->size_gradient ? fr_solve_size_held(ctx, nid, S, step, fm->size_gradient, 0.0)
                                               : fr_solve_spd(ctx, nid, 1, S, nid, step, nid);
        if (st) break;
        /* each photo's pose: C dp = u - B' step */
        for (int a = 0; a < n; a++) {
            part *pa = &parts[a];
            if (!pa->pairs) continue;
            double C[36], b[6];
            memcpy(C, pa->C, sizeof C);
            for (int k = 0; k < 6; k++) C[7 * k] += 1e-6 * C[7 * k] + 1e-9;
            for (int y = 0; y < 6; y++) {
                b[y] = pa->u[y];
                for (int x = 0; x < nid; x++) b[y] -= pa->B[(size_t)x * 6 + y] * step[x];
            }
            if ((st = fr_solve_spd(ctx, 6, 1, C, 6, b, 6))) break;
            move_pose(&res[a], b, pa->centre);
        }
        for (int x = 0; x < nid && !st; x++) identity[x] += step[x];
    }
    fr_blas_serial_end(saved);
    /* every photo's identity columns are the shared identity */
    for (int a = 0; a < n && !st; a++) memcpy(res[a].w, identity, sizeof(double) * (size_t)nid);
    for (int a = 0; views && a < n; a++) view_free(&views[a]);
    free(views), free(parts), free(fbuf), free(dbuf), free(S), free(X), free(store), free(step), free(Ut);
    mesh_free(&m);
    return st;
}
