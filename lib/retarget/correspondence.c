/* Correspondence generation (paper section 5.2.1, Algorithm 7): the current reconstruction of
 * a photo, B (x) w_i on the face, is deformed to fit the photo's point cloud. First the cloud
 * is aligned rigidly (point-to-plane ICP), then correspondences and Laplacian deformation
 * alternate (Li et al. 2008's iterative closest point with a stiffness that decreases):
 * every cloud point is matched to the nearest point of the current mesh through the triangle
 * tree, matches too far, on the mesh's rim, with normals too different or of low confidence
 * are rejected, and the mesh is deformed so that each matched point moves onto the tangent
 * plane of its cloud point (plus a share of the tangential offset). The result M'_i has the
 * rig's topology. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "core/sort.h"
#include "linalg/linalg.h"
#include "mesh/triangle_tree.h"
#include "raster/rotation.h"
#include "retarget/retarget.h"

#define MIN_INLIERS 50          /* fewer matches: the photo gives no data */
#define STIFF_START 4.0         /* the first deformation is this much smoother */
#define TIKHONOV 1e-3           /* pull toward the rest shape (decay away from the cloud) */
#define RIGID_DISTANCE_FACTOR 2 /* the rigid alignment accepts matches this much farther */

/* ---- thinning ---- */

/* Points by grid cell, then index (the radix sort's fallback when its buffer cannot be had). */
static int keyed_cmp(const void *a, const void *b) {
    const fr_sort_item *x = a, *y = b;
    if (x->key != y->key) return x->key < y->key ? -1 : 1;
    return (x->index > y->index) - (x->index < y->index);
}

frig_status fr_rt_thin_cloud(frig_ctx *ctx, const fr_rt_settings *s, fr_rt_photo *p) {
    free(p->pick);
    free(p->hint);
    p->pick = p->hint = NULL;
    p->n_pick = 0;
    fr_sort_item *k = malloc(sizeof(fr_sort_item) * (p->n_points + 1));
    p->pick = malloc(sizeof(int) * (p->n_points + 1));
    p->hint = malloc(sizeof(int) * (p->n_points + 1));
    if (!k || !p->pick || !p->hint) {
        free(k);
        return fr_nomem(ctx, "a thinned cloud");
    }
    size_t n = 0;
    for (size_t i = 0; i < p->n_points; i++) {
        const float *x = p->xyz + 3 * i, *nm = p->nrm + 3 * i;
        if (!isfinite(x[0]) || !isfinite(x[1]) || !isfinite(x[2]) || !(p->conf[i] >= s->min_confidence)) continue;
        if (i >= p->n_core && !(s->margin_weight > 0)) continue; /* the margin unused */
        if (!(nm[0] * nm[0] + nm[1] * nm[1] + nm[2] * nm[2] > 0.25)) continue; /* no normal */
        uint64_t key = 0;
        for (int c = 0; c < 3; c++) {
            double q = floor(x[c] / s->spacing) + (double)(1 << 20);
            if (q < 0) q = 0;
            if (q > (double)((1 << 21) - 1)) q = (double)((1 << 21) - 1);
            key = (key << 21) | (uint64_t)q;
        }
        k[n].key = key;
        k[n++].index = (int)i;
    }
    if (fr_sort_stable(k, n)) qsort(k, n, sizeof *k, keyed_cmp); /* in index order: by cell, then index */
    for (size_t i = 0; i < n; i++)
        if (i == 0 || k[i].key != k[i - 1].key) p->hint[p->n_pick] = -1, p->pick[p->n_pick++] = k[i].index;
    free(k);
    return FRIG_OK;
}

/* ---- matching ---- */

void fr_rt_tri_normal(const float *x, const int32_t *v, double n[3]) {
    double e1[3], e2[3];
    for (int k = 0; k < 3; k++) {
        e1[k] = x[3 * (size_t)v[1] + k] - x[3 * (size_t)v[0] + k];
        e2[k] = x[3 * (size_t)v[2] + k] - x[3 * (size_t)v[0] + k];
    }
    n[0] = e1[1] * e2[2] - e1[2] * e2[1];
    n[1] = e1[2] * e2[0] - e1[0] * e2[2];
    n[2] = e1[0] * e2[1] - e1[1] * e2[0];
    double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    for (int k = 0; k < 3; k++) n[k] = len > 0 ? n[k] / len : 0;
}

/* A match on the rim (an edge or corner of the mesh's border) is where the cloud runs past
 * the mesh: not a correspondence. */
static int on_rim(const fr_rt_mesh *m, const int32_t *v, const double b[3]) {
    int inside = 0, rim_only = 1;
    for (int c = 0; c < 3; c++)
        if (b[c] > 1e-6) {
            inside++;
            if (!m->rim[v[c]]) rim_only = 0;
        }
    return inside <= 2 && rim_only;
}

int fr_rt_match_cloud(const fr_rt_settings *s, const fr_rt_mesh *m, const fr_tri_tree *tree, const float *cur,
                      const fr_rt_photo *p, double max_dist, fr_rt_match *out) {
    int n = 0;
    for (int a = 0; a < p->n_pick; a++) {
        int i = p->pick[a];
        double x[3], nc[3];
        for (int r = 0; r < 3; r++) {
            x[r] = p->t[r], nc[r] = 0;
            for (int c = 0; c < 3; c++) {
                x[r] += p->scale * p->R[3 * r + c] * p->xyz[3 * (size_t)i + c];
                nc[r] += p->R[3 * r + c] * p->nrm[3 * (size_t)i + c];
            }
        }
        fr_tri_hit hit;
        if (!fr_tri_tree_nearest_hint(tree, x, max_dist, p->hint[a], &hit)) continue;
        p->hint[a] = hit.tri;
        const int32_t *v = m->tris + 3 * (size_t)hit.tri;
        if (on_rim(m, v, hit.bary)) continue;
        fr_rt_match *mt = &out[n];
        fr_rt_tri_normal(cur, v, mt->n);
        double len = sqrt(nc[0] * nc[0] + nc[1] * nc[1] + nc[2] * nc[2]);
        if (!((nc[0] * mt->n[0] + nc[1] * mt->n[1] + nc[2] * mt->n[2]) >= s->cos_max_angle * len)) continue;
        mt->tri = hit.tri;
        for (int k = 0; k < 3; k++) mt->bary[k] = hit.bary[k], mt->q[k] = hit.point[k], mt->p[k] = x[k];
        int margin = (size_t)i >= p->n_core;
        mt->w = p->conf[i] * (margin ? s->margin_weight : 1.0);
        mt->row = margin ? sqrt(s->margin_weight) : 1.0;
        n++;
    }
    return n;
}

/* ---- rigid alignment: point-to-plane ICP, small-angle steps ---- */

void fr_rt_rigid_step(const fr_rt_match *mt, int n, int with_scale, fr_rt_photo *p) {
    /* x' = (1 + sigma) dR x + dt around the current points x: unknowns omega (3), dt (3), sigma. */
    enum { N = 7 };
    double H[N * N] = {0}, g[N] = {0};
    int m = with_scale ? 7 : 6;
    for (int i = 0; i < n; i++) {
        const double *x = mt[i].p, *nm = mt[i].n;
        double J[N] = {x[1] * nm[2] - x[2] * nm[1], x[2] * nm[0] - x[0] * nm[2], x[0] * nm[1] - x[1] * nm[0],
                       nm[0], nm[1], nm[2], x[0] * nm[0] + x[1] * nm[1] + x[2] * nm[2]};
        double r = (x[0] - mt[i].q[0]) * nm[0] + (x[1] - mt[i].q[1]) * nm[1] + (x[2] - mt[i].q[2]) * nm[2];
        for (int a = 0; a < m; a++) {
            g[a] -= mt[i].w * J[a] * r;
            for (int b = 0; b < m; b++) H[m * a + b] += mt[i].w * J[a] * J[b];
        }
    }
    /* A little damping keeps directions the surface does not constrain (sliding) still. */
    double tr = 0;
    for (int a = 0; a < m; a++) tr += H[(m + 1) * a];
    for (int a = 0; a < m; a++) H[(m + 1) * a] += 1e-6 * tr + 1e-12;
    if (fr_solve_spd(NULL, m, 1, H, m, g, m)) return;
    double dR[9], R[9], t[3], grow = with_scale ? 1 + g[6] : 1;
    fr_rotation_from_axis_angle(g, dR);
    for (int r = 0; r < 3; r++) {
        t[r] = g[3 + r];
        for (int c = 0; c < 3; c++) {
            R[3 * r + c] = dR[3 * r] * p->R[c] + dR[3 * r + 1] * p->R[3 + c] + dR[3 * r + 2] * p->R[6 + c];
            t[r] += grow * dR[3 * r + c] * p->t[c];
        }
    }
    memcpy(p->R, R, sizeof R);
    memcpy(p->t, t, sizeof t);
    p->scale *= grow;
}

double fr_rt_correction_angle(const fr_rt_photo *p) {
    double c = 0.5 * (p->R[0] + p->R[4] + p->R[8] - 1);
    return acos(c > 1 ? 1 : c < -1 ? -1 : c);
}

/* ---- the whole of Algorithm 7 ---- */

static void coverage(const fr_rt_mesh *m, const fr_rt_match *mt, int n, double area, const double *mass, float *cover) {
    for (int v = 0; v < m->nv; v++) cover[v] = 0;
    for (int i = 0; i < n; i++) {
        const int32_t *tv = m->tris + 3 * (size_t)mt[i].tri;
        for (int c = 0; c < 3; c++) cover[tv[c]] += (float)(mt[i].w * area * mt[i].bary[c]);
    }
    for (int v = 0; v < m->nv; v++) {
        double c = mass[v] > 0 ? cover[v] / mass[v] : 0;
        cover[v] = (float)(c > 1 ? 1 : c);
    }
}

frig_status fr_rt_correspond(frig_ctx *ctx, const fr_rt_settings *s, const fr_rt_mesh *m, fr_lap_solver *sv,
                             const double *mass, fr_tri_tree *tree, const float *rest, fr_rt_photo *p) {
    int nv = m->nv;
    size_t n3 = 3 * (size_t)nv;
    memcpy(p->M, rest, sizeof(float) * n3);
    memset(p->cover, 0, sizeof(float) * (size_t)nv);
    p->inliers = 0;
    p->rms_mm = NAN;
    p->rigid_deg = p->rigid_mm = 0;
    if (p->n_pick < MIN_INLIERS || p->rejected) return FRIG_OK;
    fr_rt_match *mt = malloc(sizeof(fr_rt_match) * ((size_t)p->n_pick + 1));
    fr_lap_constraint *con = malloc(sizeof(fr_lap_constraint) * ((size_t)p->n_pick + 1));
    double *u = malloc(sizeof(double) * n3);
    frig_status st = mt && con && u ? FRIG_OK : fr_nomem(ctx, "correspondences");
    fr_tri_tree_refit(tree, p->M);
    /* Rigid: the cloud onto the current reconstruction. */
    for (int it = 0; it < s->rigid_iterations && !st; it++) {
        int n = fr_rt_match_cloud(s, m, tree, p->M, p, RIGID_DISTANCE_FACTOR * s->max_distance, mt);
        if (n < MIN_INLIERS) break;
        fr_rt_rigid_step(mt, n, s->cloud_scale, p);
    }
    /* Non-rigid: matches and Laplacian deformation, the stiffness decreasing to s->smooth. */
    int n = 0;
    double area = s->spacing * s->spacing;
    for (int it = 0; it < s->deform_iterations && !st; it++) {
        fr_tri_tree_refit(tree, p->M);
        n = fr_rt_match_cloud(s, m, tree, p->M, p, s->max_distance, mt);
        if (n < MIN_INLIERS) break;
        for (int i = 0; i < n; i++) {
            const int32_t *tv = m->tris + 3 * (size_t)mt[i].tri;
            double d[3], dn = 0, rest_q[3] = {0, 0, 0};
            for (int k = 0; k < 3; k++) d[k] = mt[i].p[k] - mt[i].q[k], dn += d[k] * mt[i].n[k];
            for (int c = 0; c < 3; c++) {
                con[i].v[c] = tv[c];
                con[i].b[c] = mt[i].bary[c];
                for (int k = 0; k < 3; k++) rest_q[k] += mt[i].bary[c] * rest[3 * (size_t)tv[c] + k];
            }
            /* Target: the tangent plane of the cloud point, plus a share of the offset along it;
             * as a displacement of the rest shape's point with the same weights. */
            for (int k = 0; k < 3; k++) {
                double target = mt[i].q[k] + dn * mt[i].n[k] + s->tangential * (d[k] - dn * mt[i].n[k]);
                con[i].r[k] = target - rest_q[k];
            }
            con[i].w = mt[i].w * area;
        }
        double len = s->smooth * pow(STIFF_START, s->deform_iterations > 1
                                                      ? (double)(s->deform_iterations - 1 - it) / (s->deform_iterations - 1)
                                                      : 0.0);
        st = fr_lap_solve(ctx, sv, s->smooth_order == 1 ? len * len : len * len * len * len, TIKHONOV, con, n, u);
        for (size_t k = 0; k < n3 && !st; k++) p->M[k] = (float)(rest[k] + u[k]);
    }
    /* Figures and coverage from the last matches, with their points on the final mesh. */
    if (!st) {
        if (n >= MIN_INLIERS) {
            double ss = 0;
            for (int i = 0; i < n; i++) {
                const int32_t *tv = m->tris + 3 * (size_t)mt[i].tri;
                for (int k = 0; k < 3; k++) {
                    double q = 0;
                    for (int c = 0; c < 3; c++) q += mt[i].bary[c] * p->M[3 * (size_t)tv[c] + k];
                    ss += (mt[i].p[k] - q) * (mt[i].p[k] - q);
                }
            }
            p->inliers = n;
            p->rms_mm = 1e3 * sqrt(ss / n);
            coverage(m, mt, n, area, mass, p->cover);
            /* A cloud that needed too large a turn, or that the mesh could not follow, is some
             * other surface than the reconstruction's (a wrong pose, a failed sfs): no data. */
            if (fr_rt_correction_angle(p) > s->max_correction || 1e-3 * p->rms_mm > s->max_rms) {
                p->rejected = 1;
                memset(p->cover, 0, sizeof(float) * (size_t)nv);
                memcpy(p->M, rest, sizeof(float) * n3);
            }
        } else {
            memcpy(p->M, rest, sizeof(float) * n3);
        }
        double axis[3];
        fr_rotation_to_axis_angle(p->R, axis);
        p->rigid_deg = sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]) * 180 / M_PI;
        p->rigid_mm = 1e3 * sqrt(p->t[0] * p->t[0] + p->t[1] * p->t[1] + p->t[2] * p->t[2]);
    }
    free(mt), free(con), free(u);
    return st;
}
