/* One photo's view for shape from shading (paper Algorithm 4, lines 1-3 and 7: "rasterize the
 * current fit"): the photo read, cropped around the face at full resolution with the face's
 * longer side capped at sfs.face_px pixels (area-averaged in linear light), and the rig drawn
 * at the photo's fit into the crop: camera depth, interpolated normals, triangle ids,
 * barycentrics, and which pixels show the face material from the front. Camera and frames:
 * docs/camera.md. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "image/area_crop.h"
#include "image/image.h"
#include "raster/raster.h"
#include "sfs/sfs.h"

#define MARGIN_PX 3        /* crop pixels around the face's box */
#define MARGIN_SHARE 0.04  /* and this share of its size */
#define GRAZING_COS 0.2    /* face pixels need |n . view| above this (78 degrees) */

void fr_sfs_view_free(fr_sfs_view *v) {
    free(v->weights), free(v->xyz_cam), free(v->vn_cam), free(v->zbuf), free(v->n_prior), free(v->I), free(v->rgb), free(v->inside);
    free(v->z_ref), free(v->z_fit), free(v->n_ref), free(v->tri), free(v->bary), free(v->face), free(v->core), free(v->skin);
    free(v->albedo), free(v->z), free(v->normal), free(v->err), free(v->kept), free(v->confidence);
    free(v->drawn_weights), free(v->drawn_disp), free(v->drawn_ident), free(v->drawn_xyz);
    memset(v, 0, sizeof *v);
}

static frig_status alloc_buffers(frig_ctx *ctx, fr_sfs_view *v) {
    size_t n = (size_t)v->w * v->h;
    v->I = malloc(sizeof(float) * 3 * n);
    v->rgb = malloc(3 * n);
    v->inside = malloc(n);
    v->z_ref = malloc(sizeof(float) * n);
    v->z_fit = malloc(sizeof(float) * n);
    v->zbuf = malloc(sizeof(float) * n);
    v->n_prior = calloc(3 * n, sizeof(float));
    v->n_ref = malloc(sizeof(float) * 3 * n);
    v->tri = malloc(sizeof(int32_t) * n);
    v->bary = malloc(sizeof(float) * 3 * n);
    v->face = malloc(n);
    v->core = malloc(n);
    v->skin = calloc(n, 1);
    v->albedo = calloc(3 * n, sizeof(float));
    v->z = calloc(n, sizeof(float));
    v->normal = calloc(3 * n, sizeof(float));
    v->err = malloc(sizeof(float) * n);
    v->kept = calloc(n, 1);
    v->confidence = calloc(n, sizeof(float));
    if (!v->I || !v->rgb || !v->z_fit || !v->zbuf || !v->n_prior || !v->inside || !v->z_ref || !v->n_ref || !v->tri || !v->bary || !v->face || !v->core || !v->skin ||
        !v->albedo || !v->z || !v->normal || !v->err || !v->kept || !v->confidence)
        return fr_nomem(ctx, "a photo's shape-from-shading buffers");
    for (size_t i = 0; i < n; i++) v->err[i] = -1.0f;
    return FRIG_OK;
}

/* n floats at a and b the same bytes (both NULL, or neither). */
static int same_floats(const float *a, const float *b, size_t n) {
    return !a == !b && (!a || !memcmp(a, b, sizeof(float) * n));
}

/* Whether the view's last drawing was of the rig with its weights, the mesh's identity change now
 * and disp (at whatever pose): then drawn_xyz holds that rig in the head frame. */
static int drawn_shape(const fr_sfs_mesh *m, const fr_sfs_view *v, const float *disp) {
    return v->shaped && !memcmp(v->drawn_weights, v->weights, sizeof(double) * (size_t)m->shapes) &&
           same_floats(v->drawn_disp, disp, (size_t)m->nv) && same_floats(v->drawn_ident, m->ident, 3 * (size_t)m->nv);
}

/* Whether the view's buffers hold the drawing of the rig at (R, t, disp) with its weights and the
 * mesh's identity change now. */
static int drawn_already(const fr_sfs_mesh *m, const fr_sfs_view *v, const double R[9], const double t[3],
                         const float *disp) {
    return v->drawn && !memcmp(v->drawn_R, R, sizeof v->drawn_R) && !memcmp(v->drawn_t, t, sizeof v->drawn_t) &&
           drawn_shape(m, v, disp);
}

/* Whether disp moves a vertex off the face (then the displacement follows the whole mesh's normals). */
static int off_face(const fr_sfs_mesh *m, const float *disp) {
    for (int i = 0; i < m->nv; i++)
        if (disp[i] != 0 && !m->face_vertex[i]) return 1;
    return 0;
}

/* xyz (3 nv) moved by disp along the normals nrm. */
static void displace(const fr_sfs_mesh *m, const float *disp, const float *nrm, float *xyz) {
    for (int i = 0; i < m->nv; i++)
        for (int k = 0; k < 3; k++) xyz[3 * (size_t)i + k] += disp[i] * nrm[3 * (size_t)i + k];
}

/* The rig at the view's weights, displaced by disp along its normals (head frame) into xyz; nrm
 * (3 nv) is scratch. */
static void posed_rig(const fr_sfs_mesh *m, const fr_sfs_view *v, const float *disp, float *xyz, float *nrm) {
    fr_sfs_mesh_eval(m, v->weights, xyz);
    if (!disp) return;
    /* the subject's displacement along the normals at this expression (the face's vertices
     * only, unless a caller moves others) */
    if (off_face(m, disp)) fr_mesh_vertex_normals(xyz, m->nv, m->tris, m->nt, nrm);
    else fr_sfs_mesh_normals(m, xyz, nrm);
    displace(m, disp, nrm, xyz);
}

/* A copy of n floats into *keep (allocated once; NULL when src is); 0 when out of memory. */
static int keep_floats(float **keep, const float *src, size_t n) {
    if (!src) {
        free(*keep), *keep = NULL;
        return 1;
    }
    if (!*keep && !(*keep = malloc(sizeof(float) * n))) return 0;
    memcpy(*keep, src, sizeof(float) * n);
    return 1;
}

/* The rig's inputs recorded (drawn_shape: drawn_xyz holds it); without memory, none (shaped 0). */
static void record_shape(const fr_sfs_mesh *m, fr_sfs_view *v, const float *disp) {
    v->drawn = v->shaped = 0;
    if (!v->drawn_weights && !(v->drawn_weights = malloc(sizeof(double) * ((size_t)m->shapes + 1)))) return;
    if (!keep_floats(&v->drawn_disp, disp, (size_t)m->nv) || !keep_floats(&v->drawn_ident, m->ident, 3 * (size_t)m->nv))
        return;
    memcpy(v->drawn_weights, v->weights, sizeof(double) * (size_t)m->shapes);
    v->shaped = 1;
}

/* The drawing's inputs recorded (drawn_already); without memory, none (drawn 0). */
static void record_drawing(const fr_sfs_mesh *m, fr_sfs_view *v, const double R[9], const double t[3],
                           const float *disp) {
    record_shape(m, v, disp);
    if (!v->shaped) return;
    memcpy(v->drawn_R, R, sizeof v->drawn_R), memcpy(v->drawn_t, t, sizeof v->drawn_t);
    v->drawn = 1;
}

void fr_sfs_view_keep_rig(const fr_sfs_mesh *m, fr_sfs_view *v, const float *disp, const float *xyz, const float *nrm) {
    if (disp && drawn_shape(m, v, disp)) return; /* kept already (and maybe drawn: the buffers stay valid) */
    v->drawn = v->shaped = 0;
    if (!disp || off_face(m, disp)) return; /* posed_rig's other normals: left to the drawing */
    if (!v->drawn_xyz && !(v->drawn_xyz = malloc(sizeof(float) * 3 * (size_t)m->nv))) return;
    memcpy(v->drawn_xyz, xyz, sizeof(float) * 3 * (size_t)m->nv);
    displace(m, disp, nrm, v->drawn_xyz);
    record_shape(m, v, disp);
}

frig_status fr_sfs_view_render(frig_ctx *ctx, const fr_sfs_mesh *m, fr_sfs_view *v, const double R[9],
                               const double t[3], const float *disp) {
    if (drawn_already(m, v, R, t, disp)) { /* the buffers hold this drawing: the pose is all that changes */
        memcpy(v->R, R, sizeof v->R), memcpy(v->t, t, sizeof v->t);
        return FRIG_OK;
    }
    /* only the pose changed since the last drawing: the rig as it was (the same floats) */
    int same_shape = drawn_shape(m, v, disp) && v->drawn_xyz;
    v->drawn = 0;
    if (!same_shape) v->shaped = 0;
    float *xyz = v->drawn_xyz, *nrm = v->vn_cam;
    if (!xyz) xyz = v->drawn_xyz = malloc(sizeof(float) * 3 * (size_t)m->nv);
    fr_raster *r = NULL;
    frig_status s = !xyz ? fr_nomem(ctx, "the posed rig") : FRIG_OK;
    if (!s) {
        if (!same_shape) posed_rig(m, v, disp, xyz, nrm);
        fr_transform_points(R, t, xyz, m->nv, v->xyz_cam);
        s = fr_raster_create(ctx, v->w, v->h, &r);
    }
    fr_raster_options ro = {FR_RASTER_DEFAULT_NEAR, 1};
    if (!s) s = fr_raster_render(ctx, r, &v->cam, v->xyz_cam, m->nv, m->tris, m->nt, &ro);
    if (!s) {
        memcpy(v->R, R, sizeof v->R);
        memcpy(v->t, t, sizeof v->t);
        fr_sfs_mesh_normals(m, v->xyz_cam, nrm); /* read at face triangles only */
        for (int y = 0; y < v->h; y++)
            for (int x = 0; x < v->w; x++) {
                size_t i = (size_t)y * v->w + x;
                int32_t tr = r->tri[i];
                v->tri[i] = tr;
                v->zbuf[i] = tr >= 0 ? r->depth[i] : 0.0f;
                memcpy(v->bary + 3 * i, r->bary + 3 * i, sizeof(float) * 3);
                v->face[i] = v->core[i] = 0;
                v->z_ref[i] = 0.0f;
                v->n_ref[3 * i] = v->n_ref[3 * i + 1] = v->n_ref[3 * i + 2] = 0.0f;
                if (tr < 0 || !m->face[tr] || !v->inside[i]) continue;
                float nn[3];
                if (!fr_raster_interpolate(r, m->tris, x, y, nrm, 3, nn)) continue;
                double len = sqrt((double)nn[0] * nn[0] + (double)nn[1] * nn[1] + (double)nn[2] * nn[2]);
                if (!(len > 0)) continue;
                double ray[3] = {(x - v->cam.cx) / v->cam.f, (y - v->cam.cy) / v->cam.f, 1.0};
                double rl = sqrt(ray[0] * ray[0] + ray[1] * ray[1] + 1.0);
                double c = (nn[0] * ray[0] + nn[1] * ray[1] + nn[2] * ray[2]) / (len * rl);
                for (int k = 0; k < 3; k++) v->n_ref[3 * i + k] = (float)(nn[k] / len);
                v->z_ref[i] = r->depth[i];
                v->face[i] = c < -GRAZING_COS;
                v->core[i] = v->face[i] && m->core[tr];
            }
    }
    if (!s) record_drawing(m, v, R, t, disp);
    fr_raster_free(r);
    return s;
}

/* The face's box in photo pixels: the projections of the face triangles' vertices. */
static int face_box(const fr_sfs_mesh *m, const fr_camera *cam, const float *xc, double box[4]) {
    box[0] = box[1] = INFINITY, box[2] = box[3] = -INFINITY;
    int n = 0;
    for (int i = 0; i < m->nv; i++) {
        if (!m->face_vertex[i]) continue;
        double p[3] = {xc[3 * i], xc[3 * i + 1], xc[3 * i + 2]}, uv[2];
        if (!fr_camera_project(cam, p, uv)) continue;
        box[0] = fmin(box[0], uv[0]), box[1] = fmin(box[1], uv[1]);
        box[2] = fmax(box[2], uv[0]), box[3] = fmax(box[3], uv[1]);
        n++;
    }
    return n;
}

frig_status fr_sfs_view_build(frig_ctx *ctx, const fr_sfs_mesh *m, const fr_sfs_settings *st, const char *path,
                              int W, int H, const double R[9], const double t[3], double focal,
                              const double *weights, fr_sfs_view *v) {
    memset(v, 0, sizeof *v);
    v->weights = malloc(sizeof(double) * (size_t)(m->shapes + 1));
    v->xyz_cam = malloc(sizeof(float) * 3 * (size_t)m->nv);
    v->vn_cam = malloc(sizeof(float) * 3 * (size_t)m->nv);
    if (!v->weights || !v->xyz_cam || !v->vn_cam) return fr_nomem(ctx, "a photo's view");
    memcpy(v->weights, weights, sizeof(double) * (size_t)m->shapes);
    float *xyz = malloc(sizeof(float) * 3 * (size_t)m->nv);
    if (!xyz) return fr_nomem(ctx, "a photo's view");
    fr_sfs_mesh_eval(m, v->weights, xyz);
    fr_transform_points(R, t, xyz, m->nv, v->xyz_cam);
    free(xyz);
    fr_camera full = fr_camera_perspective(focal, W, H);
    double box[4];
    if (face_box(m, &full, v->xyz_cam, box) < 3)
        return fr_error(ctx, FRIG_ERR_NO_FACE, "%s: the fitted face is behind the camera", path);
    /* the box, grown, clipped to the photo (what lies outside has no pixels) */
    double size = fmax(box[2] - box[0], box[3] - box[1]);
    double grow = MARGIN_SHARE * size;
    double bx0 = fmax(-0.5, box[0] - grow), by0 = fmax(-0.5, box[1] - grow);
    double bx1 = fmin(W - 0.5, box[2] + grow), by1 = fmin(H - 0.5, box[3] + grow);
    if (!(bx1 - bx0 > 4 && by1 - by0 > 4))
        return fr_error(ctx, FRIG_ERR_NO_FACE, "%s: the fitted face lies outside the photo", path);
    double s = size > st->face_px ? st->face_px / size : 1.0;
    int reduce = 1;
    while (reduce < 8 && 2.0 * reduce * s <= 1.0) reduce *= 2;
    v->s = s;
    v->x0 = floor(bx0 + 0.5) - MARGIN_PX / s; /* full-resolution edge coordinate of crop pixel 0 */
    v->y0 = floor(by0 + 0.5) - MARGIN_PX / s;
    v->w = (int)ceil((bx1 + 0.5 - v->x0) * s) + MARGIN_PX;
    v->h = (int)ceil((by1 + 0.5 - v->y0) * s) + MARGIN_PX;
    v->cam = fr_camera_perspective(focal * s, 1, 1);
    v->cam.cx = (full.cx - v->x0 + 0.5) * s - 0.5;
    v->cam.cy = (full.cy - v->y0 + 0.5) * s - 0.5;
    v->photo_weight = 1.0;
    frig_status e = alloc_buffers(ctx, v);
    if (e) return e;
    frig_image *img = NULL;
    int got = 1;
    e = fr_image_load_reduced(ctx, path, FRIG_LOAD_DEFAULT, reduce, &img, &got);
    if (e) return e;
    if (abs(img->width * got - W) >= got || abs(img->height * got - H) >= got) {
        int iw = img->width, ih = img->height;
        frig_image_free(img);
        return fr_error(ctx, FRIG_ERR_STATE, "%s is %d x %d now, the report says %d x %d (rerun frig detect)", path,
                        iw * got, ih * got, W, H);
    }
    e = fr_area_crop(ctx, img, v->x0 / got, v->y0 / got, 1.0 / (s * got), v->w, v->h, v->I, v->rgb, v->inside);
    frig_image_free(img);
    if (e) return e;
    e = fr_sfs_view_render(ctx, m, v, R, t, NULL);
    if (!e) memcpy(v->z_fit, v->z_ref, sizeof(float) * (size_t)v->w * v->h);
    memcpy(v->R_fit, R, sizeof v->R_fit), memcpy(v->t_fit, t, sizeof v->t_fit);
    return e;
}
