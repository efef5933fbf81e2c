/* Collisions a rig's shapes must not have (the whole head follows the personalized face):
 *  - an eyelid inside its eyeball: the signed distance of every skin vertex within LID_REACH
 *    of an eyeball's mesh to that mesh (its nearest point, signed by that triangle's outward
 *    normal; negative = inside);
 *  - teeth through the lips: seen from the front (model +z), the front-most face-region
 *    triangle over a tooth vertex must not be behind it; the depth by which a tooth vertex
 *    stands in front of the skin covering it (positive = through the lips). Where the mouth is
 *    open no skin covers the teeth and nothing is measured.
 * fr_rt_collisions measures the worst of both over the neutral and every full shape. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "mesh/triangle_tree.h"
#include "retarget/collisions.h"

#define LID_REACH 0.004  /* metres outside the eyeball that count as its lids */
#define CELL 0.002       /* metres: the grid over the mouth's skin */
#define MOUTH_REACH 0.03 /* metres around the teeth whose face triangles may cover them */

static int region(const frig_model *m, const char *name, int *first, int *count) {
    int r = frig_model_region_find(m, name);
    return r >= 0 && frig_model_region(m, r, NULL, first, count) == FRIG_OK && *count > 0;
}

/* The triangles of an eyeball (all corners in its region). */
static int eye_triangles(const frig_model *m, int eye, int32_t **out) {
    int first, count, nt = frig_model_triangle_count(m), n = 0;
    *out = NULL;
    if (!region(m, eye == 0 ? "eyeball_left" : "eyeball_right", &first, &count)) return 0;
    const int32_t *t = frig_model_triangles(m);
    int32_t *e = malloc(sizeof(int32_t) * 3 * ((size_t)nt + 1));
    if (!e) return -1;
    for (int i = 0; i < nt; i++) {
        int in = 1;
        for (int c = 0; c < 3; c++) in &= t[3 * i + c] >= first && t[3 * i + c] < first + count;
        if (in) memcpy(e + 3 * (size_t)n++, t + 3 * (size_t)i, sizeof(int32_t) * 3);
    }
    *out = e;
    return n;
}

struct fr_rt_lids {
    const frig_model *model;
    int nt[2];
    int32_t *tris[2];
    fr_tri_tree *tree[2];
    int *skin, n_skin; /* the skin vertices that may come near an eye */
};

frig_status fr_rt_lids_create(frig_ctx *ctx, const frig_model *m, fr_rt_lids **out) {
    *out = NULL;
    fr_rt_lids *l = calloc(1, sizeof *l);
    int nv = frig_model_vertex_count(m);
    if (!l || !(l->skin = malloc(sizeof(int) * ((size_t)nv + 1)))) {
        free(l);
        return fr_nomem(ctx, "the collision check");
    }
    l->model = m;
    const char *skin[4] = {"face", "eye_socket_left", "eye_socket_right", "head_neck"};
    for (int s = 0; s < 4; s++) {
        int f0, n0;
        if (!region(m, skin[s], &f0, &n0)) continue;
        for (int v = f0; v < f0 + n0 && v < nv; v++) l->skin[l->n_skin++] = v;
    }
    const float *x = frig_model_neutral(m);
    for (int e = 0; e < 2; e++) {
        l->nt[e] = eye_triangles(m, e, &l->tris[e]);
        frig_status s = l->nt[e] < 0 ? fr_nomem(ctx, "the collision check") : FRIG_OK;
        if (!s && l->nt[e] > 0) s = fr_tri_tree_build(ctx, x, l->tris[e], l->nt[e], &l->tree[e]);
        if (s) {
            fr_rt_lids_free(l);
            return s;
        }
    }
    *out = l;
    return FRIG_OK;
}

void fr_rt_lids_free(fr_rt_lids *l) {
    if (!l) return;
    for (int e = 0; e < 2; e++) fr_tri_tree_free(l->tree[e]), free(l->tris[e]);
    free(l->skin);
    free(l);
}

void fr_rt_lid_clearance(fr_rt_lids *l, const float *x, float *clearance, float *direction) {
    int nv = frig_model_vertex_count(l->model);
    for (int v = 0; v < nv; v++) clearance[v] = INFINITY;
    for (int e = 0; e < 2; e++) {
        fr_tri_tree *tree = l->tree[e];
        const int32_t *tris = l->tris[e];
        if (!tree) continue;
        fr_tri_tree_refit(tree, x);
        /* Only skin inside the eyeball's box grown by the reach can be near it. */
        float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
        for (int i = 0; i < 3 * l->nt[e]; i++)
            for (int k = 0; k < 3; k++)
                lo[k] = fminf(lo[k], x[3 * (size_t)tris[i] + k]), hi[k] = fmaxf(hi[k], x[3 * (size_t)tris[i] + k]);
        for (int a = 0; a < l->n_skin; a++) {
            int v = l->skin[a];
            const float *p = x + 3 * (size_t)v;
            if (p[0] < lo[0] - LID_REACH || p[0] > hi[0] + LID_REACH || p[1] < lo[1] - LID_REACH ||
                p[1] > hi[1] + LID_REACH || p[2] < lo[2] - LID_REACH || p[2] > hi[2] + LID_REACH)
                continue;
            double q[3] = {p[0], p[1], p[2]};
            fr_tri_hit hit;
            if (!fr_tri_tree_nearest(tree, q, LID_REACH, &hit)) continue;
            const int32_t *tv = tris + 3 * (size_t)hit.tri;
            double e1[3], e2[3], n[3], dot = 0;
            for (int k = 0; k < 3; k++) {
                e1[k] = x[3 * (size_t)tv[1] + k] - x[3 * (size_t)tv[0] + k];
                e2[k] = x[3 * (size_t)tv[2] + k] - x[3 * (size_t)tv[0] + k];
            }
            n[0] = e1[1] * e2[2] - e1[2] * e2[1], n[1] = e1[2] * e2[0] - e1[0] * e2[2], n[2] = e1[0] * e2[1] - e1[1] * e2[0];
            for (int k = 0; k < 3; k++) dot += n[k] * (q[k] - hit.point[k]);
            double d = sqrt(hit.dist2) * (dot < 0 ? -1 : 1);
            if (d < clearance[v]) {
                clearance[v] = (float)d;
                /* Outward: from the nearest point to the vertex (signed), or the normal on it. */
                double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]), dist = sqrt(hit.dist2);
                for (int k = 0; k < 3 && direction; k++)
                    direction[3 * (size_t)v + k] =
                        (float)(dist > 1e-9 ? (dot < 0 ? -1 : 1) * (q[k] - hit.point[k]) / dist : n[k] / len);
            }
        }
    }
}

/* The front-most z of the face triangles over (px, py), -inf when none covers it. */
static double front_z(const float *x, const int32_t *tris, const int *cell_start, const int *cell_tri, int gw, int gh,
                      double x0, double y0, double px, double py) {
    int cx = (int)floor((px - x0) / CELL), cy = (int)floor((py - y0) / CELL);
    if (cx < 0 || cy < 0 || cx >= gw || cy >= gh) return -INFINITY;
    double best = -INFINITY;
    int cell = cy * gw + cx;
    for (int k = cell_start[cell]; k < cell_start[cell + 1]; k++) {
        const int32_t *v = tris + 3 * (size_t)cell_tri[k];
        const float *a = x + 3 * (size_t)v[0], *b = x + 3 * (size_t)v[1], *c = x + 3 * (size_t)v[2];
        double d = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]);
        if (fabs(d) < 1e-14) continue;
        double u = ((px - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (py - a[1])) / d;
        double w = ((b[0] - a[0]) * (py - a[1]) - (px - a[0]) * (b[1] - a[1])) / d;
        if (u < 0 || w < 0 || u + w > 1) continue;
        double z = a[2] + u * (b[2] - a[2]) + w * (c[2] - a[2]);
        if (z > best) best = z;
    }
    return best;
}

double fr_rt_teeth_depth(frig_ctx *ctx, const frig_model *m, const float *x, frig_status *st) {
    int nv = frig_model_vertex_count(m);
    int tf, tn, ff, fn;
    *st = FRIG_OK;
    if (!region(m, "teeth", &tf, &tn) || !region(m, "face", &ff, &fn)) return -INFINITY;
    double ctr[3] = {0, 0, 0};
    for (int v = tf; v < tf + tn; v++)
        for (int k = 0; k < 3; k++) ctr[k] += x[3 * (size_t)v + k] / tn;
    /* The face triangles near the teeth, binned on a grid in (x, y). */
    int nt = frig_model_triangle_count(m);
    const int32_t *tris = frig_model_triangles(m);
    double x0 = ctr[0] - MOUTH_REACH, y0 = ctr[1] - MOUTH_REACH;
    int gw = (int)ceil(2 * MOUTH_REACH / CELL), gh = gw;
    int *cell_start = calloc((size_t)gw * gh + 1, sizeof(int)), *near = malloc(sizeof(int) * ((size_t)nt + 1));
    int n_near = 0, total = 0, *cell_tri = NULL;
    if (!cell_start || !near) {
        free(cell_start), free(near);
        *st = fr_nomem(ctx, "the collision check");
        return NAN;
    }
    int (*box)[4] = malloc(sizeof(int[4]) * ((size_t)nt + 1));
    if (!box) {
        free(cell_start), free(near);
        *st = fr_nomem(ctx, "the collision check");
        return NAN;
    }
    for (int t = 0; t < nt; t++) {
        const int32_t *v = tris + 3 * (size_t)t;
        if (v[0] >= ff + fn || v[1] >= ff + fn || v[2] >= ff + fn || v[0] < ff || v[1] < ff || v[2] < ff) continue;
        double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
        for (int c = 0; c < 3; c++)
            for (int k = 0; k < 2; k++) lo[k] = fmin(lo[k], x[3 * (size_t)v[c] + k]), hi[k] = fmax(hi[k], x[3 * (size_t)v[c] + k]);
        int bx0 = (int)floor((lo[0] - x0) / CELL), bx1 = (int)floor((hi[0] - x0) / CELL);
        int by0 = (int)floor((lo[1] - y0) / CELL), by1 = (int)floor((hi[1] - y0) / CELL);
        if (bx1 < 0 || by1 < 0 || bx0 >= gw || by0 >= gh) continue;
        bx0 = bx0 < 0 ? 0 : bx0, by0 = by0 < 0 ? 0 : by0, bx1 = bx1 >= gw ? gw - 1 : bx1, by1 = by1 >= gh ? gh - 1 : by1;
        box[n_near][0] = bx0, box[n_near][1] = bx1, box[n_near][2] = by0, box[n_near][3] = by1;
        near[n_near++] = t;
        for (int yy = by0; yy <= by1; yy++)
            for (int xx = bx0; xx <= bx1; xx++) cell_start[yy * gw + xx + 1]++, total++;
    }
    for (int c = 0; c < gw * gh; c++) cell_start[c + 1] += cell_start[c];
    cell_tri = malloc(sizeof(int) * ((size_t)total + 1));
    int *fill = malloc(sizeof(int) * ((size_t)gw * gh + 1));
    double worst = -INFINITY;
    if (cell_tri && fill) {
        memcpy(fill, cell_start, sizeof(int) * (size_t)gw * gh);
        for (int i = 0; i < n_near; i++)
            for (int yy = box[i][2]; yy <= box[i][3]; yy++)
                for (int xx = box[i][0]; xx <= box[i][1]; xx++) cell_tri[fill[yy * gw + xx]++] = near[i];
        for (int v = tf; v < tf + tn && v < nv; v++) {
            const float *p = x + 3 * (size_t)v;
            double z = front_z(x, tris, cell_start, cell_tri, gw, gh, x0, y0, p[0], p[1]);
            if (z > -INFINITY && p[2] - z > worst) worst = p[2] - z;
        }
    } else {
        *st = fr_nomem(ctx, "the collision check");
    }
    free(cell_start), free(near), free(cell_tri), free(fill), free(box);
    return worst;
}

frig_status fr_rt_collisions(frig_ctx *ctx, const frig_model *model, const float *neutral, const float *deltas,
                             int shapes, double *lid, double *teeth) {
    int nv = frig_model_vertex_count(model);
    size_t n3 = 3 * (size_t)nv;
    float *x = malloc(sizeof(float) * n3), *c = malloc(sizeof(float) * ((size_t)nv + 1));
    fr_rt_lids *lids = NULL;
    frig_status s = x && c ? fr_rt_lids_create(ctx, model, &lids) : fr_nomem(ctx, "the collision check");
    for (int f = 0; f <= shapes && !s; f++) {
        for (size_t q = 0; q < n3; q++) x[q] = neutral[q] + (f ? deltas[n3 * (f - 1) + q] : 0.0f);
        fr_rt_lid_clearance(lids, x, c, NULL);
        lid[f] = INFINITY;
        for (int v = 0; v < nv; v++) lid[f] = fmin(lid[f], c[v]);
        teeth[f] = fr_rt_teeth_depth(ctx, model, x, &s);
    }
    fr_rt_lids_free(lids);
    free(x), free(c);
    return s;
}
