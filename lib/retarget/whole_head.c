/* The whole head follows the personalized face (the paper personalizes the face region; an
 * exported rig must be a whole head): every field that changed on the face (the neutral and
 * each blendshape's delta) is carried to the rest of the head.
 *  - skin connected to the face (head and neck, ears, mouth and eye sockets): the harmonic
 *    extension of the face's change over the mesh (cotangent Laplacian of the old neutral,
 *    the face as the boundary), smooth and equal to the face's change where they meet;
 *  - eyeballs: rigidly, by the mean change of the skin within EYE_SKIN of their centre (the
 *    lids and socket they sit in); teeth and gums: rigidly by the mean change of the skin
 *    around them (lips and mouth socket); their own deltas (eye turns, the jaw) stay;
 *  - lashes and the eye overlays: with the nearest skin (a Gaussian average of its change);
 *  - finally no lid vertex stays inside its eyeball in any shape: one that would is moved
 *    out along the eyeball's radius to where the old rig had it (never nearer than the old
 *    clearance, and at least on the surface). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <omp.h>

#include "core/context.h"
#include "mesh/harmonic_extension.h"
#include "model/model.h"
#include "retarget/collisions.h"
#include "retarget/retarget.h"
#include "rig/rig.h"

#define EYE_SKIN 0.02     /* metres around an eyeball's centre whose skin carries it */
#define TEETH_SKIN 0.005  /* metres beyond the teeth's radius whose skin carries them */
#define OVERLAY_SIGMA 0.003
#define OVERLAY_REACH 0.01
#define LID_PASSES 4
#define LID_PUSH_MIN 1e-7 /* metres: a shortfall below this is the float clearance's rounding */

enum { PART_FACE = 0, PART_SKIN = 1, PART_EYE_L = 2, PART_EYE_R = 3, PART_TEETH = 4, PART_OVERLAY = 5, PART_OTHER = 6 };

typedef struct head {
    int nv, S, F;         /* vertices, shapes, fields (S + 1) */
    uint8_t *part;
    float *change;        /* F fields x 3 nv: field 0 the neutral, field 1 + j shape j's delta */
} head;

static void mark_region(const frig_model *m, const char *name, uint8_t part, uint8_t *parts) {
    int r = frig_model_region_find(m, name), first, count;
    if (r < 0 || frig_model_region(m, r, NULL, &first, &count)) return;
    for (int v = first; v < first + count; v++) parts[v] = part;
}

static frig_status classify(frig_ctx *ctx, const frig_model *m, int nf, head *h) {
    h->part = malloc((size_t)h->nv);
    if (!h->part) return fr_nomem(ctx, "the whole head");
    memset(h->part, PART_OTHER, (size_t)h->nv);
    const char *skin[] = {"head_neck", "mouth_socket", "eye_socket_left", "eye_socket_right"};
    for (int k = 0; k < 4; k++) mark_region(m, skin[k], PART_SKIN, h->part);
    mark_region(m, "eyeball_left", PART_EYE_L, h->part);
    mark_region(m, "eyeball_right", PART_EYE_R, h->part);
    mark_region(m, "teeth", PART_TEETH, h->part);
    mark_region(m, "gums_tongue", PART_TEETH, h->part);
    const char *overlay[] = {"lacrimal_fluid_left", "lacrimal_fluid_right", "eye_blend_left", "eye_blend_right",
                             "eye_occlusion_left", "eye_occlusion_right", "eyelashes_left", "eyelashes_right"};
    for (int k = 0; k < 8; k++) mark_region(m, overlay[k], PART_OVERLAY, h->part);
    for (int v = 0; v < nf && v < h->nv; v++) h->part[v] = PART_FACE;
    return FRIG_OK;
}

/* Harmonic extension over the skin: L_uu x_u = -L_uf x_f for every field and coordinate. */
static frig_status extend_skin(frig_ctx *ctx, const frig_rig *rig, const float *old_neutral, head *h) {
    int nv = h->nv, nt = rig->topo.triangle_count;
    const int32_t *tri = rig->topo.triangles;
    int32_t *st = malloc(sizeof(int32_t) * 3 * ((size_t)nt + 1));
    uint8_t *skin = malloc((size_t)nv + 1);
    if (!st || !skin) {
        free(st), free(skin);
        return fr_nomem(ctx, "the whole head");
    }
    int ns = 0;
    for (int t = 0; t < nt; t++) {
        int ok = 1;
        for (int c = 0; c < 3; c++) ok &= h->part[tri[3 * t + c]] <= PART_SKIN;
        if (ok) memcpy(st + 3 * (size_t)ns++, tri + 3 * (size_t)t, sizeof(int32_t) * 3);
    }
    /* skin vertices that some skin triangle uses are unknowns; the face holds its change */
    for (int v = 0; v < nv; v++) skin[v] = h->part[v] == PART_SKIN;
    frig_status s = fr_harmonic_extend(ctx, nv, old_neutral, st, ns, skin, h->F, 1e-9, NULL, h->change);
    free(st), free(skin);
    return s;
}

static void centroid(const head *h, const float *x, uint8_t part, double c[3], double *radius) {
    double n = 0;
    c[0] = c[1] = c[2] = 0;
    for (int v = 0; v < h->nv; v++)
        if (h->part[v] == part) {
            for (int k = 0; k < 3; k++) c[k] += x[3 * (size_t)v + k];
            n++;
        }
    for (int k = 0; k < 3 && n > 0; k++) c[k] /= n;
    *radius = 0;
    for (int v = 0; v < h->nv; v++)
        if (h->part[v] == part) {
            double d = 0;
            for (int k = 0; k < 3; k++) d += (x[3 * (size_t)v + k] - c[k]) * (x[3 * (size_t)v + k] - c[k]);
            *radius = fmax(*radius, sqrt(d));
        }
}

static double dist3(const float *x, const double c[3]) {
    double d = 0;
    for (int k = 0; k < 3; k++) d += (x[k] - c[k]) * (x[k] - c[k]);
    return sqrt(d);
}

/* A rigid part moves with the mean neutral change of the skin within reach of its centre; its
 * deltas do not change. */
static void move_rigid(head *h, const float *old_neutral, uint8_t part, double reach_beyond_radius, double reach) {
    double c[3], radius, t[3] = {0, 0, 0}, n = 0;
    centroid(h, old_neutral, part, c, &radius);
    double r = reach > 0 ? reach : radius + reach_beyond_radius;
    for (int v = 0; v < h->nv; v++)
        if (h->part[v] <= PART_SKIN && dist3(old_neutral + 3 * (size_t)v, c) < r) {
            for (int k = 0; k < 3; k++) t[k] += h->change[3 * (size_t)v + k];
            n++;
        }
    for (int k = 0; k < 3 && n > 0; k++) t[k] /= n;
    for (int v = 0; v < h->nv; v++)
        if (h->part[v] == part)
            for (int k = 0; k < 3; k++) {
                h->change[3 * (size_t)v + k] = (float)t[k];
                for (int f = 1; f < h->F; f++) h->change[(size_t)f * 3 * h->nv + 3 * (size_t)v + k] = 0;
            }
}

/* Overlays take a Gaussian average of the change of the skin near them. */
static frig_status move_overlays(frig_ctx *ctx, head *h, const float *old_neutral) {
    int *near = malloc(sizeof(int) * ((size_t)h->nv + 1)), nn = 0;
    if (!near) return fr_nomem(ctx, "the whole head");
    /* Candidate skin: within reach of any overlay vertex's bounding box. */
    float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int v = 0; v < h->nv; v++)
        if (h->part[v] == PART_OVERLAY)
            for (int k = 0; k < 3; k++) lo[k] = fminf(lo[k], old_neutral[3 * (size_t)v + k]), hi[k] = fmaxf(hi[k], old_neutral[3 * (size_t)v + k]);
    for (int v = 0; v < h->nv; v++) {
        if (h->part[v] > PART_SKIN) continue;
        int in = 1;
        for (int k = 0; k < 3; k++) in &= old_neutral[3 * (size_t)v + k] > lo[k] - OVERLAY_REACH && old_neutral[3 * (size_t)v + k] < hi[k] + OVERLAY_REACH;
        if (in) near[nn++] = v;
    }
    for (int v = 0; v < h->nv; v++) {
        if (h->part[v] != PART_OVERLAY) continue;
        const float *x = old_neutral + 3 * (size_t)v;
        double wsum = 0;
        double *acc = calloc(3 * (size_t)h->F, sizeof(double));
        if (!acc) {
            free(near);
            return fr_nomem(ctx, "the whole head");
        }
        for (int a = 0; a < nn; a++) {
            const float *y = old_neutral + 3 * (size_t)near[a];
            double d2 = 0;
            for (int k = 0; k < 3; k++) d2 += (x[k] - y[k]) * (x[k] - y[k]);
            if (d2 > OVERLAY_REACH * OVERLAY_REACH) continue;
            double w = exp(-d2 / (2 * OVERLAY_SIGMA * OVERLAY_SIGMA));
            wsum += w;
            for (int f = 0; f < h->F; f++)
                for (int k = 0; k < 3; k++) acc[3 * f + k] += w * h->change[(size_t)f * 3 * h->nv + 3 * (size_t)near[a] + k];
        }
        for (int f = 0; f < h->F; f++)
            for (int k = 0; k < 3; k++) h->change[(size_t)f * 3 * h->nv + 3 * (size_t)v + k] = wsum > 0 ? (float)(acc[3 * f + k] / wsum) : 0;
        free(acc);
    }
    free(near);
    return FRIG_OK;
}

/* No lid vertex inside its eyeball: in the neutral and in every shape, a skin vertex near an
 * eyeball keeps at least the clearance from its mesh that the old rig gave it (at most 0: the
 * surface), moved out along the vertex's offset from its eyeball's centre. Here one shape (f = 0:
 * the neutral), with its own lids index and scratch. Returns whether it moved a vertex. */
static int lids_out_shape(fr_rt_lids *lids, const head *h, const float *old_clearance, int f, float *xn, float *cn,
                          float *dir, frig_rig *rig) {
    int nv = h->nv;
    size_t n3 = 3 * (size_t)nv;
    const float *co = old_clearance + (size_t)f * nv;
    for (size_t q = 0; q < n3; q++) xn[q] = rig->neutral[q] + (f ? rig->deltas[n3 * (f - 1) + q] : 0.0f);
    fr_rt_lid_clearance(lids, xn, cn, dir);
    int moved = 0;
    for (int v = 0; v < nv; v++) {
        if (h->part[v] > PART_SKIN || !isfinite(cn[v])) continue;
        double want = fmin(isfinite(co[v]) ? co[v] : 0.0, 0.0);
        if (cn[v] >= want) continue;
        /* Out by the missing clearance, away from the eyeball's nearest point. */
        double push = want - cn[v];
        float *target = f == 0 ? rig->neutral + 3 * (size_t)v : rig->deltas + n3 * (f - 1) + 3 * (size_t)v;
        if (push < LID_PUSH_MIN) continue;
        for (int k = 0; k < 3; k++) target[k] += (float)(push * dir[3 * (size_t)v + k]);
        moved = 1;
    }
    return moved;
}

/* Per thread: a lids index (its trees are refitted per shape) and the scratch of one shape. */
typedef struct lids_work {
    fr_rt_lids *lids;
    float *x, *c, *dir;
} lids_work;

static void lids_work_free(lids_work *w, int threads) {
    for (int t = 0; w && t < threads; t++) fr_rt_lids_free(w[t].lids), free(w[t].x), free(w[t].c), free(w[t].dir);
    free(w);
}

static lids_work *lids_work_new(frig_ctx *ctx, const frig_model *model, int nv, int threads, frig_status *s) {
    lids_work *w = calloc((size_t)threads, sizeof *w);
    *s = w ? FRIG_OK : fr_nomem(ctx, "the whole head");
    for (int t = 0; t < threads && !*s; t++) {
        *s = fr_rt_lids_create(ctx, model, &w[t].lids);
        w[t].x = malloc(sizeof(float) * 3 * (size_t)nv), w[t].c = malloc(sizeof(float) * (size_t)nv);
        w[t].dir = malloc(sizeof(float) * 3 * (size_t)nv);
        if (!*s && (!w[t].x || !w[t].c || !w[t].dir)) *s = fr_nomem(ctx, "the whole head");
    }
    if (*s) lids_work_free(w, threads), w = NULL;
    return w;
}

/* The neutral first (every shape sits on it), then the shapes, each on its own thread's index:
 * a shape writes only its own deltas, so the result does not depend on the threads. A shape
 * that moved nothing in the last pass, on a neutral this pass left alone, would find what it
 * found then: it is skipped (moved[f], per shape, says what the last pass did; all 1 at first). */
static void keep_lids_out(lids_work *w, int threads, const head *h, const float *old_clearance, uint8_t *moved,
                          frig_rig *rig) {
    int neutral = moved[0] ? lids_out_shape(w[0].lids, h, old_clearance, 0, w[0].x, w[0].c, w[0].dir, rig) : 0;
    moved[0] = (uint8_t)neutral;
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
    for (int f = 1; f < h->F; f++) {
        lids_work *m = &w[omp_get_thread_num()];
        if (moved[f] || neutral) moved[f] = (uint8_t)lids_out_shape(m->lids, h, old_clearance, f, m->x, m->c, m->dir, rig);
    }
}

/* The old rig's lid clearances, per shape (F x nv). */
static float *old_clearances(frig_ctx *ctx, lids_work *w, int threads, const head *h, const float *old_neutral,
                             const float *old_deltas, frig_status *s) {
    size_t n3 = 3 * (size_t)h->nv;
    float *c = malloc(sizeof(float) * (size_t)h->F * h->nv);
    *s = c ? FRIG_OK : fr_nomem(ctx, "the whole head");
    if (*s) return NULL;
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
    for (int f = 0; f < h->F; f++) {
        float *x = w[omp_get_thread_num()].x;
        for (size_t q = 0; q < n3; q++) x[q] = old_neutral[q] + (f ? old_deltas[n3 * (f - 1) + q] : 0.0f);
        fr_rt_lid_clearance(w[omp_get_thread_num()].lids, x, c + (size_t)f * h->nv, NULL);
    }
    return c;
}

/* The teeth stay behind the lips: where the personalized lips came nearer than the old rig's
 * in front of the teeth, the teeth and gums move back (model -z) by the difference, in the
 * neutral (so in every shape) and then shape by shape for what still stands out. */
static void shift_teeth(const head *h, float *x, double dz) {
    for (int v = 0; v < h->nv; v++)
        if (h->part[v] == PART_TEETH) x[3 * (size_t)v + 2] -= (float)dz;
}

static frig_status keep_teeth_in(frig_ctx *ctx, const frig_model *model, const head *h, const float *old_neutral,
                                 const float *old_deltas, frig_rig *rig) {
    size_t n3 = 3 * (size_t)h->nv;
    float *xo = malloc(sizeof(float) * n3), *xn = malloc(sizeof(float) * n3);
    if (!xo || !xn) {
        free(xo), free(xn);
        return fr_nomem(ctx, "the whole head");
    }
    frig_status s = FRIG_OK;
    for (int f = 0; f < h->F && !s; f++) {
        for (size_t q = 0; q < n3; q++) {
            xo[q] = old_neutral[q] + (f ? old_deltas[n3 * (f - 1) + q] : 0.0f);
            xn[q] = rig->neutral[q] + (f ? rig->deltas[n3 * (f - 1) + q] : 0.0f);
        }
        double d_old = fr_rt_teeth_depth(ctx, model, xo, &s);
        double d_new = s ? 0 : fr_rt_teeth_depth(ctx, model, xn, &s);
        if (s || !isfinite(d_new)) continue;
        /* The neutral keeps the old gap; a shape may at most reach the old rig's depth (or the skin). */
        double allowed = f == 0 ? (isfinite(d_old) ? d_old : d_new) : fmax(isfinite(d_old) ? d_old : 0.0, 0.0);
        if (d_new <= allowed) continue;
        shift_teeth(h, f == 0 ? rig->neutral : rig->deltas + n3 * (f - 1), d_new - allowed);
    }
    free(xo), free(xn);
    return s;
}

frig_status fr_rt_whole_head(frig_ctx *ctx, const frig_model *model, int nf, const float *old_neutral,
                             const float *old_deltas, const float *ref_neutral, const float *ref_deltas, frig_rig *rig) {
    head h;
    memset(&h, 0, sizeof h);
    h.nv = rig->topo.vertex_count;
    h.S = rig->shape_count;
    h.F = h.S + 1;
    size_t n3 = 3 * (size_t)h.nv;
    h.change = calloc(n3 * (size_t)h.F, sizeof(float));
    frig_status s = h.change ? classify(ctx, model, nf, &h) : fr_nomem(ctx, "the whole head");
    if (!s) {
        /* Field by field (each a contiguous 3 nv block: a loop over the fields inside would
         * stride 3 nv floats per step). */
        for (size_t q = 0; q < 3 * (size_t)nf; q++) h.change[q] = rig->neutral[q] - old_neutral[q];
        for (int j = 0; j < h.S; j++)
            for (size_t q = 0; q < 3 * (size_t)nf; q++)
                h.change[n3 * (j + 1) + q] = rig->deltas[n3 * j + q] - old_deltas[n3 * j + q];
        s = extend_skin(ctx, rig, old_neutral, &h);
    }
    if (!s) {
        move_rigid(&h, old_neutral, PART_EYE_L, 0, EYE_SKIN);
        move_rigid(&h, old_neutral, PART_EYE_R, 0, EYE_SKIN);
        move_rigid(&h, old_neutral, PART_TEETH, TEETH_SKIN, 0);
        s = move_overlays(ctx, &h, old_neutral);
    }
    if (!s) {
        for (size_t q = 3 * (size_t)nf; q < n3; q++) rig->neutral[q] = old_neutral[q] + h.change[q];
        for (int j = 0; j < h.S; j++)
            for (size_t q = 3 * (size_t)nf; q < n3; q++)
                rig->deltas[n3 * j + q] = old_deltas[n3 * j + q] + h.change[n3 * (j + 1) + q];
        /* A push can bring a vertex nearer another part of the eyeball (the cornea's rim): a few
         * passes. */
        int threads = fr_threads(ctx);
        lids_work *w = lids_work_new(ctx, model, h.nv, threads, &s);
        float *old_c = s ? NULL : old_clearances(ctx, w, threads, &h, ref_neutral, ref_deltas, &s);
        uint8_t *moved = s ? NULL : malloc((size_t)h.F);
        if (!s && !moved) s = fr_nomem(ctx, "the whole head");
        if (moved) memset(moved, 1, (size_t)h.F);
        for (int pass = 0; pass < LID_PASSES && !s; pass++) keep_lids_out(w, threads, &h, old_c, moved, rig);
        free(moved);
        free(old_c);
        lids_work_free(w, threads);
        if (!s) s = keep_teeth_in(ctx, model, &h, ref_neutral, ref_deltas, rig);
    }
    free(h.part);
    free(h.change);
    return s;
}
