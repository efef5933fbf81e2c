/* Bounding-box tree over triangles: nodes in one array in depth-first order (a node's
 * children come after it, so a reverse sweep refits the boxes bottom-up), leaves of at most
 * LEAF_SIZE triangles, split at the median centroid along the widest axis of the centroids.
 * Nearest-point queries descend the nearer child first and prune boxes farther than the best
 * distance found. Each leaf's triangles keep their corners' boxes side by side (tbox, in the
 * leaves' order, set at every build and refit), so the test that skips a triangle reads six
 * floats in a row instead of its three corners. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "mesh/closest_point.h"
#include "mesh/triangle_tree.h"

#define LEAF_SIZE 4
#define MAX_DEPTH 64

typedef struct node {
    float lo[3], hi[3];
    int first, count; /* leaf: triangles order[first .. first+count-1]; inner: count = 0 */
    int left, right;  /* inner: child nodes */
} node;

struct fr_tri_tree {
    const float *xyz;
    const int32_t *tris;
    int nt;
    int *order; /* triangle indices, grouped by leaf */
    float *tbox; /* per entry of order: its triangle's corner box, lo[3] then hi[3] */
    node *nodes;
    int n_nodes;
    float *centroid; /* 3 per triangle, build only */
};

static void tri_box(const fr_tri_tree *t, int tri, float lo[3], float hi[3]) {
    for (int k = 0; k < 3; k++) lo[k] = INFINITY, hi[k] = -INFINITY;
    for (int c = 0; c < 3; c++) {
        const float *p = t->xyz + 3 * (size_t)t->tris[3 * (size_t)tri + c];
        for (int k = 0; k < 3; k++) {
            if (p[k] < lo[k]) lo[k] = p[k];
            if (p[k] > hi[k]) hi[k] = p[k];
        }
    }
}

static void leaf_box(const fr_tri_tree *t, node *nd) {
    for (int k = 0; k < 3; k++) nd->lo[k] = INFINITY, nd->hi[k] = -INFINITY;
    for (int i = nd->first; i < nd->first + nd->count; i++) {
        float *lo = t->tbox + 6 * (size_t)i, *hi = lo + 3;
        tri_box(t, t->order[i], lo, hi);
        for (int k = 0; k < 3; k++) {
            if (lo[k] < nd->lo[k]) nd->lo[k] = lo[k];
            if (hi[k] > nd->hi[k]) nd->hi[k] = hi[k];
        }
    }
}

/* Partial sort of order[first .. first+count-1] so that the element at 'mid' has the median
 * centroid along axis (quickselect; ties broken by triangle index, so the result is the
 * same on every run). */
static int centroid_less(const fr_tri_tree *t, int a, int b, int axis) {
    float ca = t->centroid[3 * (size_t)a + axis], cb = t->centroid[3 * (size_t)b + axis];
    return ca < cb || (ca == cb && a < b);
}

static void select_median(fr_tri_tree *t, int lo, int hi, int mid, int axis) {
    int *o = t->order;
    while (hi > lo) {
        int pivot = o[(lo + hi) / 2], i = lo, j = hi;
        while (i <= j) {
            while (centroid_less(t, o[i], pivot, axis)) i++;
            while (centroid_less(t, pivot, o[j], axis)) j--;
            if (i <= j) {
                int tmp = o[i];
                o[i] = o[j];
                o[j] = tmp;
                i++, j--;
            }
        }
        if (mid <= j) hi = j;
        else if (mid >= i) lo = i;
        else return;
    }
}

static int build_node(fr_tri_tree *t, int first, int count, int depth) {
    int id = t->n_nodes++;
    node *nd = &t->nodes[id];
    nd->first = first;
    nd->count = count;
    nd->left = nd->right = -1;
    if (count <= LEAF_SIZE || depth >= MAX_DEPTH) {
        leaf_box(t, nd);
        return id;
    }
    float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int i = first; i < first + count; i++)
        for (int k = 0; k < 3; k++) {
            float c = t->centroid[3 * (size_t)t->order[i] + k];
            if (c < lo[k]) lo[k] = c;
            if (c > hi[k]) hi[k] = c;
        }
    int axis = 0;
    for (int k = 1; k < 3; k++)
        if (hi[k] - lo[k] > hi[axis] - lo[axis]) axis = k;
    int half = count / 2;
    select_median(t, first, first + count - 1, first + half, axis);
    int left = build_node(t, first, half, depth + 1);
    int right = build_node(t, first + half, count - half, depth + 1);
    nd = &t->nodes[id]; /* (the array does not move: it was allocated whole) */
    nd->count = 0;
    nd->left = left;
    nd->right = right;
    for (int k = 0; k < 3; k++) {
        nd->lo[k] = fminf(t->nodes[left].lo[k], t->nodes[right].lo[k]);
        nd->hi[k] = fmaxf(t->nodes[left].hi[k], t->nodes[right].hi[k]);
    }
    return id;
}

frig_status fr_tri_tree_build(frig_ctx *ctx, const float *xyz, const int32_t *tris, int nt, fr_tri_tree **out) {
    *out = NULL;
    fr_tri_tree *t = calloc(1, sizeof *t);
    if (!t) return fr_nomem(ctx, "a triangle tree");
    t->xyz = xyz;
    t->tris = tris;
    t->nt = nt;
    t->order = malloc(sizeof(int) * ((size_t)nt + 1));
    t->tbox = malloc(sizeof(float) * 6 * ((size_t)nt + 1));
    t->nodes = malloc(sizeof(node) * (2 * (size_t)nt + 1));
    t->centroid = malloc(sizeof(float) * 3 * ((size_t)nt + 1));
    if (!t->order || !t->tbox || !t->nodes || !t->centroid) {
        fr_tri_tree_free(t);
        return fr_nomem(ctx, "a triangle tree");
    }
    for (int i = 0; i < nt; i++) {
        t->order[i] = i;
        for (int k = 0; k < 3; k++) {
            double s = 0;
            for (int c = 0; c < 3; c++) s += xyz[3 * (size_t)tris[3 * (size_t)i + c] + k];
            t->centroid[3 * (size_t)i + k] = (float)(s / 3);
        }
    }
    if (nt > 0) build_node(t, 0, nt, 0);
    free(t->centroid);
    t->centroid = NULL;
    *out = t;
    return FRIG_OK;
}

frig_status fr_tri_tree_copy(frig_ctx *ctx, const fr_tri_tree *src, fr_tri_tree **out) {
    *out = NULL;
    fr_tri_tree *t = calloc(1, sizeof *t);
    if (!t) return fr_nomem(ctx, "a triangle tree");
    *t = *src;
    t->centroid = NULL;
    t->order = malloc(sizeof(int) * ((size_t)src->nt + 1));
    t->tbox = malloc(sizeof(float) * 6 * ((size_t)src->nt + 1));
    t->nodes = malloc(sizeof(node) * ((size_t)src->n_nodes + 1));
    if (!t->order || !t->tbox || !t->nodes) {
        fr_tri_tree_free(t);
        return fr_nomem(ctx, "a triangle tree");
    }
    memcpy(t->order, src->order, sizeof(int) * (size_t)src->nt);
    memcpy(t->tbox, src->tbox, sizeof(float) * 6 * (size_t)src->nt);
    memcpy(t->nodes, src->nodes, sizeof(node) * (size_t)src->n_nodes);
    *out = t;
    return FRIG_OK;
}

void fr_tri_tree_free(fr_tri_tree *t) {
    if (!t) return;
    free(t->order);
    free(t->tbox);
    free(t->nodes);
    free(t->centroid);
    free(t);
}

void fr_tri_tree_refit(fr_tri_tree *t, const float *xyz) {
    t->xyz = xyz;
    for (int id = t->n_nodes - 1; id >= 0; id--) {
        node *nd = &t->nodes[id];
        if (nd->count > 0 || nd->left < 0) {
            leaf_box(t, nd);
            continue;
        }
        for (int k = 0; k < 3; k++) {
            nd->lo[k] = fminf(t->nodes[nd->left].lo[k], t->nodes[nd->right].lo[k]);
            nd->hi[k] = fmaxf(t->nodes[nd->left].hi[k], t->nodes[nd->right].hi[k]);
        }
    }
}

static double box_dist2(const node *nd, const double p[3]) {
    double d2 = 0;
    for (int k = 0; k < 3; k++) {
        double d = p[k] < nd->lo[k] ? nd->lo[k] - p[k] : p[k] > nd->hi[k] ? p[k] - nd->hi[k] : 0;
        d2 += d * d;
    }
    return d2;
}

/* Squared distance from p to the box of triangle tri's corners: a lower bound of its distance. */
static double corner_box_dist2(const float *a, const float *b, const float *c, const double p[3]) {
    double d2 = 0;
    for (int k = 0; k < 3; k++) {
        float lo = fminf(a[k], fminf(b[k], c[k])), hi = fmaxf(a[k], fmaxf(b[k], c[k]));
        double d = p[k] < lo ? lo - p[k] : p[k] > hi ? p[k] - hi : 0;
        d2 += d * d;
    }
    return d2;
}

/* Squared distance from p to a box (lo[3], hi[3]): corner_box_dist2 of the box's corners. */
static double stored_box_dist2(const float *box, const double p[3]) {
    double d2 = 0;
    for (int k = 0; k < 3; k++) {
        float lo = box[k], hi = box[3 + k];
        double d = p[k] < lo ? lo - p[k] : p[k] > hi ? p[k] - hi : 0;
        d2 += d * d;
    }
    return d2;
}

/* The exact distance from p to triangle tri into hit when it beats hit's (ties to the lower
 * index). */
static void exact_triangle(const fr_tri_tree *t, const double p[3], int tri, fr_tri_hit *hit) {
    const int32_t *v = t->tris + 3 * (size_t)tri;
    const float *fa = t->xyz + 3 * (size_t)v[0], *fb = t->xyz + 3 * (size_t)v[1], *fc = t->xyz + 3 * (size_t)v[2];
    double a[3], b[3], c[3], q[3], w[3];
    for (int k = 0; k < 3; k++) a[k] = fa[k], b[k] = fb[k], c[k] = fc[k];
    double d2 = fr_closest_point_triangle(p, a, b, c, q, w);
    if (d2 < hit->dist2 || (d2 == hit->dist2 && (hit->tri < 0 || tri < hit->tri))) {
        hit->dist2 = d2;
        hit->tri = tri;
        for (int k = 0; k < 3; k++) hit->point[k] = q[k], hit->bary[k] = w[k];
    }
}

/* A triangle whose corners' box is clearly farther than the best so far cannot win (the margin
 * covers rounding), so the exact test is skipped: the same answer. */
static int cannot_win(double box_d2, const fr_tri_hit *hit) { return box_d2 > hit->dist2 * (1 + 1e-9) + 1e-24; }

static void try_triangle(const fr_tri_tree *t, const double p[3], int tri, fr_tri_hit *hit) {
    const int32_t *v = t->tris + 3 * (size_t)tri;
    const float *fa = t->xyz + 3 * (size_t)v[0], *fb = t->xyz + 3 * (size_t)v[1], *fc = t->xyz + 3 * (size_t)v[2];
    if (!cannot_win(corner_box_dist2(fa, fb, fc, p), hit)) exact_triangle(t, p, tri, hit);
}

/* The same for entry i of the leaves' order, from its stored box. */
static void try_entry(const fr_tri_tree *t, const double p[3], int i, fr_tri_hit *hit) {
    if (!cannot_win(stored_box_dist2(t->tbox + 6 * (size_t)i, p), hit)) exact_triangle(t, p, t->order[i], hit);
}

int fr_tri_tree_nearest(const fr_tri_tree *t, const double p[3], double max_dist, fr_tri_hit *hit) {
    return fr_tri_tree_nearest_hint(t, p, max_dist, -1, hit);
}

int fr_tri_tree_nearest_hint(const fr_tri_tree *t, const double p[3], double max_dist, int hint, fr_tri_hit *hit) {
    hit->tri = -1;
    hit->dist2 = max_dist * max_dist;
    if (t->n_nodes == 0) return 0;
    if (hint >= 0 && hint < t->nt) try_triangle(t, p, hint, hit);
    /* Each stacked node with its box's distance, measured once when its parent was opened. */
    int stack[2 * MAX_DEPTH + 4], top = 0;
    double dist[2 * MAX_DEPTH + 4];
    stack[top] = 0, dist[top++] = box_dist2(&t->nodes[0], p);
    while (top > 0) {
        top--;
        if (dist[top] > hit->dist2) continue;
        const node *nd = &t->nodes[stack[top]];
        if (nd->count > 0 || nd->left < 0) {
            for (int i = nd->first; i < nd->first + nd->count; i++) try_entry(t, p, i, hit);
            continue;
        }
        /* Push the farther child first, so the nearer is searched first; a child already
         * farther than the best so far is not pushed. */
        double dl = box_dist2(&t->nodes[nd->left], p), dr = box_dist2(&t->nodes[nd->right], p);
        int near = dl <= dr ? nd->left : nd->right, far = dl <= dr ? nd->right : nd->left;
        double dn = dl <= dr ? dl : dr, df = dl <= dr ? dr : dl;
        if (df <= hit->dist2) stack[top] = far, dist[top++] = df;
        if (dn <= hit->dist2) stack[top] = near, dist[top++] = dn;
    }
    return hit->tri >= 0;
}
