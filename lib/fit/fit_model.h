/* The part of the face model the fit stage works with (paper section 4.3): the landmark
 * vertices, the jawline contour candidates and the cheek/jaw vertices whose silhouette the
 * jaw landmarks follow, with their rows of the identity and expression bases, in double
 * precision. Built once per model, shared read-only by every photo's fit. Internal. */
#ifndef FR_FIT_FIT_MODEL_H
#define FR_FIT_FIT_MODEL_H

#include <stdint.h>

#include "frig/model.h"
#include "frig/rig.h"

#define FR_LANDMARKS 68
#define FR_CONTOUR_LANDMARKS 17 /* iBUG 0..16: the jawline */

typedef struct fr_fit_model {
    const frig_model *model;
    const frig_rig *rig; /* NULL: the model's bases; else the rig's neutral and shapes, no identity */
    int n_id;         /* identity modes fitted */
    int n_exp;        /* expression shapes fitted */
    int *exp_index;   /* model expression index of each fitted expression */
    int n_cols;       /* n_id + n_exp */

    /* Vertex slots: every vertex the fit evaluates. */
    int n_slots;
    int *slot_vertex; /* model vertex of each slot */
    double *mean;     /* 3 per slot: the neutral */
    double *basis;    /* (3 n_slots) x n_cols, row-major: identity modes, then expressions */

    int32_t landmark_vertex[FR_LANDMARKS]; /* the model vertex of each iBUG landmark (fit/landmark_vertices.h) */
    int landmark_slot[FR_LANDMARKS];   /* default slot of each iBUG landmark */
    /* Silhouette rows: jaw landmark k (iBUG 0..16, not the chin 8) may move to a vertex of
     * row k, the jawline and cheek vertices whose angle around the face centre (model x-y
     * plane, neutral shape) is nearest to its default vertex's: row_slots[row_start[k] ..
     * row_start[k + 1] - 1]. */
    int row_start[FR_CONTOUR_LANDMARKS + 1];
    int *row_slots;
    double *row_radius; /* per row slot: distance from the face centre in the x-y plane (neutral) */
    double jaw_radius[FR_CONTOUR_LANDMARKS]; /* the same for each landmark's default vertex */
    /* Triangles over the slots (for silhouette normals): 3 slots each; and each slot's
     * neighbours along triangle edges (adj[adj_start[s] .. adj_start[s + 1] - 1]). */
    int n_tris;
    int *tris;
    int *adj_start, *adj;
    /* Model-space x of the face centre line and the sign of x on side 0. */
    double side0_sign;
    /* n_id values: the face size's relative change per identity mode (fit/face_size.h); NULL
     * when n_id is 0. */
    double *size_gradient;
} fr_fit_model;

frig_status fr_fit_model_build(frig_ctx *ctx, const frig_model *model, int n_id, fr_fit_model *out);
/* The same vertex slots and silhouette rows on a rig of the model's topology (section 5.3: the
 * per-image reconstruction with the generated blendshapes): the mean is the rig's neutral, the
 * basis the rig's shapes named as the model's fitting expressions (a shape the rig lacks gives
 * a zero column), n_id = 0. */
frig_status fr_fit_model_build_rig(frig_ctx *ctx, const frig_model *model, const frig_rig *rig, fr_fit_model *out);
void fr_fit_model_free(fr_fit_model *fm);

/* Positions of the given slots for weights w (n_cols values): out[3k..3k+2]. */
void fr_fit_model_eval_slots(const fr_fit_model *fm, const double *w, const int *slots, int n, double *out);
/* Positions of every slot. */
void fr_fit_model_eval_all(const fr_fit_model *fm, const double *w, double *out);

/* Row of the basis for coordinate c (0..2) of slot s: n_cols values. */
static inline const double *fr_fit_model_row(const fr_fit_model *fm, int s, int c) {
    return fm->basis + (3 * (size_t)s + (size_t)c) * (size_t)fm->n_cols;
}

#endif
