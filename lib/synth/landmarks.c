/* Landmark truth of a synthetic photo (the 2D input of the fit, paper eq. 4.5): the exact
 * projections of the 68 landmark vertices, their visibility, and "detector-like" positions in
 * which the jaw points 0-16 lie on the face's visible outline, as annotators and cascaded
 * regressors mark them (the contour correspondence problem of section 4.3). The rule:
 * docs/synth.md. Also the fast path that makes landmarks without an image. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "synth/synth.h"

#define VISIBLE_TOL 0.002     /* metres behind the visible surface still counted as on it */
#define SCAN_STEP 0.5         /* pixels */
#define LEAD 3.0              /* pixels from a jaw vertex's projection to the outline face's pixels */

static int outline_pixel(const frig_synth_subject *s, const fr_raster *r, int x, int y) {
    if (x < 0 || y < 0 || x >= r->width || y >= r->height) return 0;
    int32_t t = r->tri[(size_t)y * (size_t)r->width + (size_t)x];
    return t >= 0 && s->outline_tri[t];
}

/* Jaw point k: from the vertex's projection outward (the jaw line's outward normal in the
 * face plane, through the pose) to where the outline face's pixels end, when the projection
 * lies on them or within LEAD pixels of them: a hidden far-side point goes to the cheek's
 * silhouette, a near-side point of a turned face to the face's visible edge toward the ear,
 * a point on the jaw line of a frontal face stays (within a pixel or two). */
static void jaw_to_outline(const frig_synth_subject *s, const fr_synth_photo *p, const fr_raster *r, int k,
                           fr_synth_landmarks *lm) {
    double u = lm->exact[2 * k], v = lm->exact[2 * k + 1], d[3];
    if (!isfinite(u) || !isfinite(v)) return;
    fr_mat3_apply(p->R, s->jaw_normal[k], d);
    double len = sqrt(d[0] * d[0] + d[1] * d[1]);
    if (!(len > 1e-3)) return;
    double dx = d[0] / len, dy = d[1] / len, px = u, py = v;
    int on = 0; /* reached the outline face */
    for (double step = 0.0;; step += SCAN_STEP) {
        double x = u + step * dx, y = v + step * dy;
        int xi = (int)lround(x), yi = (int)lround(y);
        int inside = xi >= 0 && yi >= 0 && xi < r->width && yi < r->height;
        if (inside && outline_pixel(s, r, xi, yi)) {
            on = 1, px = x, py = y;
            continue;
        }
        if (!inside || (!on && step >= LEAD)) return; /* off the image, or not on the face */
        if (!on) continue;
        double ex = 0.5 * (px + x), ey = 0.5 * (py + y);
        if (hypot(ex - u, ey - v) > 0.5) {
            lm->detector[2 * k] = ex;
            lm->detector[2 * k + 1] = ey;
            lm->jaw_moved[k] = 1;
        }
        return;
    }
}

static void face_box(const frig_synth_subject *s, const fr_raster *r, double box[4]) {
    box[0] = box[1] = box[2] = box[3] = -1.0;
    int any = 0;
    for (int y = 0; y < r->height; y++)
        for (int x = 0; x < r->width; x++) {
            if (!outline_pixel(s, r, x, y)) continue;
            if (!any || x < box[0]) box[0] = x;
            if (!any || y < box[1]) box[1] = y;
            if (!any || x > box[2]) box[2] = x;
            if (!any || y > box[3]) box[3] = y;
            any = 1;
        }
}

static int in_image(const fr_synth_photo *p, double u, double v) {
    return u >= -0.5 && v >= -0.5 && u < p->width - 0.5 && v < p->height - 0.5;
}

frig_status fr_synth_landmarks_from_render(frig_ctx *ctx, const frig_synth_subject *s, fr_synth_photo *p,
                                           const fr_raster *r, const float *xyz_cam, fr_synth_landmarks *lm) {
    memset(lm, 0, sizeof *lm);
    uint8_t *vis = malloc((size_t)s->nv_render);
    if (!vis) return fr_nomem(ctx, "landmark visibility");
    fr_raster_visible_vertices(r, &p->cam, xyz_cam, s->nv_render, s->tris, VISIBLE_TOL, vis);
    for (int k = 0; k < FR_SYNTH_LANDMARKS; k++) {
        const float *x = xyz_cam + 3 * (size_t)s->landmarks[k];
        double xc[3] = {x[0], x[1], x[2]}, uv[2] = {NAN, NAN};
        fr_camera_project(&p->cam, xc, uv);
        lm->exact[2 * k] = uv[0];
        lm->exact[2 * k + 1] = uv[1];
        lm->visible[k] = vis[s->landmarks[k]];
    }
    free(vis);
    if (p->failure == FRIG_SYNTH_FAILURE_OCCLUDER) fr_synth_place_occluder(p, lm->exact);
    if (p->failure == FRIG_SYNTH_FAILURE_SUNGLASSES) fr_synth_place_sunglasses(p, lm->exact);
    memcpy(lm->detector, lm->exact, sizeof lm->exact);
    for (int k = 0; k < 17; k++) jaw_to_outline(s, p, r, k, lm);
    for (int k = 0; k < 17; k++)
        if (lm->jaw_moved[k]) lm->visible[k] = 1;
    for (int k = 0; k < FR_SYNTH_LANDMARKS; k++) {
        double u = lm->detector[2 * k], v = lm->detector[2 * k + 1];
        if (!in_image(p, u, v) || fr_synth_occluded(p, u, v)) lm->visible[k] = 0;
    }
    face_box(s, r, lm->face_box);
    return FRIG_OK;
}

void fr_synth_landmarks_none(fr_synth_landmarks *lm) {
    memset(lm, 0, sizeof *lm);
    for (int i = 0; i < 2 * FR_SYNTH_LANDMARKS; i++) lm->exact[i] = lm->detector[i] = NAN;
    for (int i = 0; i < 4; i++) lm->face_box[i] = -1.0;
}

frig_status fr_synth_landmarks_only(frig_ctx *ctx, const frig_synth_subject *s, const fr_synth_photo *p,
                               fr_synth_landmarks *lm) {
    if (p->failure == FRIG_SYNTH_FAILURE_NO_FACE) {
        fr_synth_landmarks_none(lm);
        return FRIG_OK;
    }
    fr_synth_photo q = *p;
    float *xyz = NULL;
    fr_raster *r = NULL;
    frig_status st = fr_synth_posed_vertices(ctx, s, p, &xyz);
    if (!st) st = fr_raster_create(ctx, p->width, p->height, &r);
    if (!st) st = fr_raster_render(ctx, r, &p->cam, xyz, s->nv_render, s->tris, s->nt, NULL);
    if (!st) st = fr_synth_landmarks_from_render(ctx, s, &q, r, xyz, lm);
    fr_raster_free(r);
    free(xyz);
    return st;
}
