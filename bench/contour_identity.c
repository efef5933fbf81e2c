/* What the photos' outlines say about the identity (a measurement, docs/retarget.md): the
 * subject's identity (the model's modes) refined from the occluding contours of all fitted photos
 * at once, each photo's pose with it (its 6 parameters eliminated per photo). Every photo's crop is
 * drawn at the current identity (the sfs stage's view), its outline pixels (face triangles next to
 * no triangle, seen nearly edge-on) are paired with the strongest edge of the photo, blurred by a
 * pixel, along their outward direction, and Gauss-Newton moves identity and poses so that the
 * outlines meet the edges (Huber at 1 pixel, pairs beyond --cmax pixels left out), with the
 * model's prior N(0, I) weighed --prior times against one pixel squared. Prints the neutral's
 * aligned error against the frig synth subject's truth (face region, narrow face) per iteration.
 * Usage: contour_identity MODEL SUBJECT_DIR WORKSPACE [--iterations N] [--prior P] [--cmax PX] [--core]
 *        [--threads T] [--set NAME=VALUE]... */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench_param.h"
#include "core/context.h"
#include "frig/frig.h"
#include "image/gaussian_blur.h"
#include "linalg/linalg.h"
#include "eval/shape_error.h"
#include "mesh/point_align.h"
#include "model/model.h"
#include "raster/rotation.h"
#include "rig/rig.h"
#include "sfs/sfs.h"
#include "sfs/sfs_uv.h"
#include "workspace/photoset.h"

#define EDGE_ON_COS 0.4

typedef struct obs {
    double r0, nu[2], X[3];
    int tri;
    float b[3];
} obs;

static double edge_strength(const float *Ib, int w, int h, const double xy[2], const double nu[2]) {
    double a[3], b[3], xa[2] = {xy[0] + nu[0], xy[1] + nu[1]}, xb[2] = {xy[0] - nu[0], xy[1] - nu[1]};
    fr_sfs_bilinear(Ib, w, h, xa, a), fr_sfs_bilinear(Ib, w, h, xb, b);
    return fabs(a[0] - b[0]) + fabs(a[1] - b[1]) + fabs(a[2] - b[2]);
}

static int outward(const fr_sfs_view *v, size_t i, double nu[2]) {
    int bg = 0;
    nu[0] = nu[1] = 0;
    for (int dy = -1; dy <= 1; dy++)
        for (int dx = -1; dx <= 1; dx++) {
            size_t q = (size_t)((ptrdiff_t)i + (ptrdiff_t)dy * v->w + dx);
            if (v->tri[q] >= 0) continue;
            if (!v->inside[q]) return 0;
            nu[0] += dx, nu[1] += dy, bg++;
        }
    double l = sqrt(nu[0] * nu[0] + nu[1] * nu[1]);
    if (!bg || !(l > 0)) return 0;
    nu[0] /= l, nu[1] /= l;
    return 1;
}

static int observe(const fr_sfs_mesh *m, const fr_sfs_view *v, const float *Ib, int core_only, obs *o) {
    int n = 0;
    for (int y = 2; y < v->h - 2; y++)
        for (int x = 2; x < v->w - 2; x++) {
            size_t i = (size_t)y * v->w + x;
            int32_t tr = v->tri[i];
            double nu[2];
            if (tr < 0 || !m->face[tr] || (core_only && !v->core[i]) || !v->inside[i] || !outward(v, i, nu)) continue;
            const int32_t *t3 = m->tris + 3 * (size_t)tr;
            const float *b = v->bary + 3 * i;
            double X[3] = {0, 0, 0}, nc[3] = {0, 0, 0};
            for (int c = 0; c < 3; c++)
                for (int d = 0; d < 3; d++)
                    X[d] += b[c] * v->xyz_cam[3 * (size_t)t3[c] + d], nc[d] += b[c] * v->vn_cam[3 * (size_t)t3[c] + d];
            double xl = sqrt(X[0] * X[0] + X[1] * X[1] + X[2] * X[2]), nl = sqrt(nc[0] * nc[0] + nc[1] * nc[1] + nc[2] * nc[2]);
            if (!(xl > 0) || !(nl > 0) || fabs(nc[0] * X[0] + nc[1] * X[1] + nc[2] * X[2]) / (xl * nl) > EDGE_ON_COS) continue;
            double best = -1, best_s = 0, win = 4;
            for (double sd = -win; sd <= win + 1e-9; sd += 0.5) {
                double p[2] = {x + sd * nu[0], y + sd * nu[1]};
                if (p[0] < 1 || p[1] < 1 || p[0] > v->w - 2 || p[1] > v->h - 2) continue;
                double e = edge_strength(Ib, v->w, v->h, p, nu) * exp(-0.5 * sd * sd / (win * win));
                if (e > best) best = e, best_s = sd;
            }
            if (!(best > 0)) continue;
            o[n].r0 = 0.5 - best_s, o[n].nu[0] = nu[0], o[n].nu[1] = nu[1], o[n].tri = tr;
            memcpy(o[n].X, X, sizeof X), memcpy(o[n].b, b, sizeof o[n].b);
            n++;
        }
    return n;
}

int main(int argc, char **argv) {
    if (argc < 4) {
        fprintf(stderr, "usage: contour_identity MODEL SUBJECT_DIR WORKSPACE [--iterations N] [--prior P] [--cmax PX] "
                        "[--core] [--threads T] [--set NAME=VALUE]...\n");
        return 2;
    }
    frig_ctx *ctx = frig_ctx_create();
    int iterations = 4, core_only = 0;
    double prior = 30, cmax = 3;
    for (int i = 4; i < argc; i++) {
        if (!strcmp(argv[i], "--iterations") && i + 1 < argc) iterations = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--prior") && i + 1 < argc) prior = atof(argv[++i]);
        else if (!strcmp(argv[i], "--cmax") && i + 1 < argc) cmax = atof(argv[++i]);
        else if (!strcmp(argv[i], "--core")) core_only = 1;
        else if (!strcmp(argv[i], "--threads") && i + 1 < argc) frig_ctx_set_threads(ctx, atoi(argv[++i]));
        else if (!strcmp(argv[i], "--set") && i + 1 < argc) {
            if (bench_set_param(ctx, argv[++i])) return 2;
        }
    }
    char path[4096];
    frig_model *model = NULL;
    frig_rig *rig = NULL, *truth = NULL;
    frig_photoset *set = NULL;
    if (frig_model_load(ctx, argv[1], &model)) goto fail;
    snprintf(path, sizeof path, "%s/rig/rig.frigrig", argv[2]);
    if (frig_rig_load(ctx, path, &truth)) goto fail;
    snprintf(path, sizeof path, "%s/rig/rig.frigrig", argv[3]);
    if (frig_rig_load(ctx, path, &rig)) goto fail;
    if (frig_photoset_load(ctx, argv[3], &set)) goto fail;
    int nid = frig_model_identity_count(model), nv = frig_model_vertex_count(model), nf = 9409;
    size_t nv3 = 3 * (size_t)nv;
    double *id = calloc((size_t)nid, sizeof(double));
    const double *id0;
    int nset = frig_photoset_identity(set, &id0);
    for (int k = 0; k < nid && k < nset; k++) id[k] = id0[k];
    float *xyz = malloc(sizeof(float) * nv3);
    frig_model_eval(ctx, model, id, NULL, xyz);
    frig_rig_set_neutral(ctx, rig, xyz);
    fr_sfs_mesh m;
    if (fr_sfs_mesh_init(ctx, rig, &m)) goto fail;
    fr_sfs_settings st;
    fr_sfs_settings_from_ctx(ctx, &st);
    int nviews = 0;
    fr_sfs_view *views = calloc(set->count, sizeof *views);
    float **blur = calloc(set->count, sizeof *blur);
    for (size_t i = 0; i < set->count; i++) {
        fr_photo *p = &set->photos[i];
        if (p->status != FRIG_PHOTO_OK || !p->fitted) continue;
        double *w = calloc((size_t)rig->shape_count + 1, sizeof(double));
        for (int e = 0; e < set->n_expressions; e++) {
            int j = frig_rig_shape_find(rig, set->expression_names[e]);
            if (j >= 0) w[j] = p->fit_expression[e];
        }
        fr_sfs_view *v = &views[nviews];
        if (fr_sfs_view_build(ctx, &m, &st, p->path, p->width, p->height, p->fit_rotation, p->fit_translation,
                              p->fit_focal, w, v)) {
            frig_ctx_clear_error(ctx);
            free(w);
            continue;
        }
        free(w);
        v->photo = i;
        blur[nviews] = malloc(sizeof(float) * 3 * (size_t)v->w * v->h);
        fr_gaussian_blur(ctx, v->I, v->w, v->h, 3, 1.0, blur[nviews]);
        nviews++;
    }
    printf("%d views\n", nviews);
    obs *o = malloc(sizeof(obs) * 200000);
    double *S = malloc(sizeof(double) * nid * (nid + 1)), *g = S + (size_t)nid * nid;
    double *Bv = malloc(sizeof(double) * nid * 6 * nviews), *Cv = malloc(sizeof(double) * 36 * nviews);
    double *vv = malloc(sizeof(double) * 6 * nviews), *a = malloc(sizeof(double) * (nid + 6));
    double *centre = malloc(sizeof(double) * 3 * (nviews + 1));
    for (int it = 0; it <= iterations; it++) {
        double e_al = 1e3 * fr_aligned_mean_distance(frig_rig_neutral(truth), xyz, nf);
        double e_nar = 1e3 * fr_aligned_mean_distance(frig_rig_neutral(truth), xyz, 6706);
        memset(S, 0, sizeof(double) * nid * (nid + 1));
        int total = 0;
        double rss = 0;
        for (int k = 0; k < nviews; k++) {
            fr_sfs_view *v = &views[k];
            double R[9], t[3];
            memcpy(R, v->R, sizeof R), memcpy(t, v->t, sizeof t);
            fr_sfs_view_render(ctx, &m, v, R, t, NULL);
            int n = observe(&m, v, blur[k], core_only, o);
            double *B = Bv + (size_t)nid * 6 * k, *C = Cv + 36 * k, *u = vv + 6 * k;
            memset(B, 0, sizeof(double) * nid * 6), memset(C, 0, sizeof(double) * 36), memset(u, 0, sizeof(double) * 6);
            double pc[3] = {0, 0, 0};
            for (int q = 0; q < n; q++)
                for (int d = 0; d < 3; d++) pc[d] += o[q].X[d] / n;
            for (int q = 0; q < n; q++) {
                double r = o[q].r0;
                if (fabs(r) > cmax) continue;
                double w = fabs(r) <= 1.0 ? 1.0 : 1.0 / fabs(r);
                double J[6];
                fr_camera_project_jacobian(&v->cam, o[q].X, J);
                double jn[3]; /* d(nu . uv) / dX (camera) */
                for (int d = 0; d < 3; d++) jn[d] = o[q].nu[0] * J[d] + o[q].nu[1] * J[3 + d];
                /* identity mode m moves the point by R u_m; the outline moves by jn . R u_m (sign: r = model - photo
                 * outward; a model point moving outward by s makes r grow... r0 = 0.5 - s_edge: outline outside
                 * the edge -> r0 > 0; moving outward increases the model outline: dr = + jn . dX) */
                const int32_t *t3 = m.tris + 3 * (size_t)o[q].tri;
                for (int mm = 0; mm < nid; mm++) {
                    double um[3] = {0, 0, 0}, cu[3];
                    for (int c = 0; c < 3; c++)
                        for (int d = 0; d < 3; d++) um[d] += o[q].b[c] * model->identity[nv3 * mm + 3 * (size_t)t3[c] + d];
                    fr_mat3_apply(v->R, um, cu);
                    a[mm] = jn[0] * cu[0] + jn[1] * cu[1] + jn[2] * cu[2];
                }
                double qd[3] = {o[q].X[0] - pc[0], o[q].X[1] - pc[1], o[q].X[2] - pc[2]};
                /* rotation w about pc: dX = w x q -> jn . (w x q) = w . (q x jn); translation: jn */
                a[nid + 0] = qd[1] * jn[2] - qd[2] * jn[1];
                a[nid + 1] = qd[2] * jn[0] - qd[0] * jn[2];
                a[nid + 2] = qd[0] * jn[1] - qd[1] * jn[0];
                a[nid + 3] = jn[0], a[nid + 4] = jn[1], a[nid + 5] = jn[2];
                for (int x = 0; x < nid; x++) {
                    g[x] -= w * a[x] * r;
                    for (int y = 0; y < nid; y++) S[(size_t)x * nid + y] += w * a[x] * a[y];
                    for (int y = 0; y < 6; y++) B[(size_t)x * 6 + y] += w * a[x] * a[nid + y];
                }
                for (int x = 0; x < 6; x++) {
                    u[x] -= w * a[nid + x] * r;
                    for (int y = 0; y < 6; y++) C[6 * x + y] += w * a[nid + x] * a[nid + y];
                }
                rss += r * r, total++;
            }
            for (int x = 0; x < 6; x++) C[7 * x] += 1e-3 + 1e-6 * C[7 * x];
            memcpy(centre + 3 * k, pc, sizeof pc);
        }
        printf("iteration %d: neutral aligned %.3f mm (narrow %.3f), %d contour pixels, rms %.2f px\n", it, e_al, e_nar,
               total, sqrt(rss / (total ? total : 1)));
        if (it == iterations) break;
        /* Schur: S -= B C^-1 B', g -= B C^-1 u */
        for (int k = 0; k < nviews; k++) {
            double *B = Bv + (size_t)nid * 6 * k, *C = Cv + 36 * k, *u = vv + 6 * k;
            double Ci[36], X[6 * 101];
            if (nid > 100) goto fail;
            memcpy(Ci, C, sizeof Ci);
            /* X = C^-1 [B' u] (6 x (nid + 1)) */
            for (int x = 0; x < nid; x++)
                for (int y = 0; y < 6; y++) X[6 * x + y] = B[(size_t)x * 6 + y];
            for (int y = 0; y < 6; y++) X[6 * nid + y] = u[y];
            if (fr_solve_spd(ctx, 6, nid + 1, Ci, 6, X, 6)) goto fail;
            for (int x = 0; x < nid; x++) {
                for (int y = 0; y < nid; y++) {
                    double s = 0;
                    for (int z = 0; z < 6; z++) s += B[(size_t)x * 6 + z] * X[6 * y + z];
                    S[(size_t)x * nid + y] -= s;
                }
                double s = 0;
                for (int z = 0; z < 6; z++) s += B[(size_t)x * 6 + z] * X[6 * nid + z];
                g[x] -= s;
            }
        }
        for (int x = 0; x < nid; x++) S[(size_t)x * nid + x] += prior, g[x] -= prior * id[x];
        double *Sc = malloc(sizeof(double) * nid * nid), *dx = malloc(sizeof(double) * nid);
        memcpy(Sc, S, sizeof(double) * nid * nid), memcpy(dx, g, sizeof(double) * nid);
        if (fr_solve_spd(ctx, nid, 1, Sc, nid, dx, nid)) goto fail;
        /* each view's pose step: C dp = u - B' dx */
        for (int k = 0; k < nviews; k++) {
            double *B = Bv + (size_t)nid * 6 * k, *C = Cv + 36 * k, *u = vv + 6 * k, Ci[36], b[6];
            memcpy(Ci, C, sizeof Ci);
            for (int y = 0; y < 6; y++) {
                b[y] = u[y];
                for (int x = 0; x < nid; x++) b[y] -= B[(size_t)x * 6 + y] * dx[x];
            }
            if (fr_solve_spd(ctx, 6, 1, Ci, 6, b, 6)) goto fail;
            fr_sfs_view *v = &views[k];
            double dR[9], R2[9], pc[3], rel[3], rr[3];
            memcpy(pc, centre + 3 * k, sizeof pc);
            fr_rotation_from_axis_angle(b, dR);
            fr_mat3_mul(dR, v->R, R2);
            for (int c = 0; c < 3; c++) rel[c] = v->t[c] - pc[c];
            fr_mat3_apply(dR, rel, rr);
            for (int c = 0; c < 3; c++) v->t[c] = rr[c] + pc[c] + b[3 + c];
            memcpy(v->R, R2, sizeof R2);
        }
        for (int x = 0; x < nid; x++) id[x] += dx[x];
        free(Sc), free(dx);
        frig_model_eval(ctx, model, id, NULL, xyz);
        frig_rig_set_neutral(ctx, rig, xyz);
    }
    for (int k = 0; k < nviews; k++) fr_sfs_view_free(&views[k]), free(blur[k]);
    free(views), free(blur), free(o), free(S), free(Bv), free(Cv), free(vv), free(a), free(centre), free(id), free(xyz);
    fr_sfs_mesh_free(&m);
    frig_photoset_free(set), frig_rig_free(rig), frig_rig_free(truth), frig_model_free(model), frig_ctx_free(ctx);
    return 0;
fail:
    fprintf(stderr, "%s\n", frig_ctx_errmsg(ctx));
    return 1;
}
