/* The retarget stage's inside (paper sections 5.2-5.3): the face mesh it optimizes, each
 * photo's cloud, weights and corresponded mesh M'_i, and the steps of Algorithm 6 on plain
 * arrays (correspondence, neutral, blendshapes, weights), then the whole head. Internal. */
#ifndef FR_RETARGET_RETARGET_H
#define FR_RETARGET_RETARGET_H

#include <stdint.h>

#include "frig/frig.h"
#include "mesh/laplacian_deform.h"
#include "mesh/triangle_tree.h"

typedef struct fr_rt_settings {
    int inner_iterations;    /* Algorithm 6's loop */
    int alternations;        /* blendshapes <-> weights (section 5.2.3) per inner iteration */
    int rigid_iterations;    /* rigid ICP before the deformation (Algorithm 7) */
    int deform_iterations;   /* correspondence + Laplacian deformation rounds */
    double w_data, w_transfer, w_prev_neutral, w_prev_shapes; /* eq. 5.16-5.17 */
    double max_distance;     /* metres: farther correspondences are rejected */
    double cos_max_angle;    /* normals further apart are rejected */
    double min_confidence;
    double spacing;          /* metres: the cloud is thinned to one point per cube this wide */
    double smooth;           /* metres: the Laplacian deformation's smoothing length */
    int smooth_order;        /* 1: membrane (squared gradient), 2: bending (squared Laplacian) */
    double tangential;       /* share of the tangential residual a correspondence pulls by */
    double weights_prior;    /* ridge on the weights' change, per mm^2 of observed residual */
    double weights_sparse;   /* L1 on the weights (they are >= 0), per mm^2 of observed residual */
    int identity_iterations; /* the identity from the clouds before Algorithm 6 (0: off) */
    double landmark_sigma;   /* metres: the lifted landmarks' noise in the identity fit (0: not used) */
    int cloud_scale;         /* 1: the clouds' alignment may also scale them */
    double max_correction;   /* radians: a cloud that needs a larger turn to fit is not used */
    double max_rms;          /* metres: a cloud whose points stay farther (RMS) is not used */
    int transfer_gradients;  /* E_t's target: 1 deformation transfer, 0 the template's deltas */
    int anchor_frame;        /* 1: the rig is moved back rigidly to its frame after the pass */
    double identity_prior;   /* weight of the identity's prior N(c, I) against the clouds (1: matches at 1 mm) */
    double prior_centre;     /* c: this share of the identity the pass starts from (0: the mean face) */
    double identity_spread;  /* variance of a cloud's own identity about the shared one (0: none) */
    double margin_weight;    /* weight of the margin's points (those from n_core on) */
    int mean_size;           /* 1: the identity step keeps the mean face's size (fit.mean_size) */
    double weights_ridge;    /* the identity fit's ridge on each photo's weights, per match (squared 1 mm residuals) */
    int threads;
} fr_rt_settings;

/* The face part of the rig the optimization works on: vertices 0 .. nv-1, the triangles all
 * of whose corners are among them, and its rim. */
typedef struct fr_rt_mesh {
    int nv, nt;
    int32_t *tris;
    uint8_t *rim;
    fr_tri_tree *tree; /* its spatial index, shaped on the positions given to fr_rt_mesh_make; copies
                        * of it are refitted to each reconstruction */
    float *shape;      /* those positions (the tree's own until refitted) */
} fr_rt_mesh;

typedef struct fr_rt_photo {
    size_t index;                 /* in the photo set */
    const float *xyz, *nrm, *conf; /* the cloud (borrowed), head frame */
    size_t n_points;
    size_t n_core;                /* the points before this are the cloud's, the rest its margin's */
    int *pick;                    /* the thinned cloud: indices into it */
    int n_pick;
    int *hint;                    /* per picked point: the triangle it matched last (-1: none) */
    double *w;                    /* the fitting shapes' weights */
    float *M;                     /* M'_i: 3 nv */
    float *cover;                 /* nv: how much of each vertex's area the cloud covers, [0, 1] */
    double R[9], t[3], scale;     /* the cloud's correction x -> scale R x + t, applied before
                                   * matching (start: the identity; each alignment continues from
                                   * the last). The scale is there because a cloud has the size its
                                   * photo's fitted focal length and distance give it. */
    /* the photo's landmarks (17-67) lifted onto its cloud: head-frame points of the cloud under
     * each landmark, before the rigid correction (fr_rt_lift_landmarks) */
    double lm3d[3 * 68];
    uint8_t lm_ok[68];
    int rejected;                 /* the cloud does not fit the photo's reconstruction: no data */
    /* figures of the last correspondence */
    int inliers;
    double rms_mm;                /* RMS distance of the inlier points to M'_i */
    double rigid_deg, rigid_mm;   /* size of the rigid correction (and its scale, above) */
} fr_rt_photo;

/* Borrow photo's cloud and its margin from clouds into p (xyz, nrm, conf, n_core, n_points). */
void fr_rt_photo_borrow_cloud(fr_rt_photo *p, const frig_clouds *clouds, size_t photo);

/* xyz: positions (3 per vertex, at least nv vertices) the spatial index is shaped on. */
frig_status fr_rt_mesh_make(frig_ctx *ctx, int nv, const int32_t *tris, int nt, const float *xyz, fr_rt_mesh *m);
void fr_rt_mesh_free(fr_rt_mesh *m);

/* out = base + sum_a w[a] deltas_a over n floats, in double, shape a's deltas at deltas + stride * a
 * (stride * shape[a] when shape is not NULL), the shapes of weight 0 skipped; summed per value in
 * the shapes' order, in blocks so that each shape's deltas are read in a row. */
void fr_rt_blend(size_t n, const float *base, int K, const double *w, const float *deltas, size_t stride,
                 const int *shape, float *out);

/* Thin the photo's cloud (p->pick): one point per spacing-wide cube, points below the
 * confidence bound or not finite left out. */
frig_status fr_rt_thin_cloud(frig_ctx *ctx, const fr_rt_settings *s, fr_rt_photo *p);

/* A cloud point matched to the nearest point of the current mesh. */
typedef struct fr_rt_match {
    int tri;        /* face-mesh triangle */
    double bary[3];
    double q[3];    /* the matched mesh point */
    double n[3];    /* the triangle's unit normal */
    double p[3];    /* the cloud point, rigidly corrected */
    double w;       /* its confidence (times retarget.margin_weight for a margin point) */
    double row;     /* its rows' scale in the identity fit: 1, or sqrt(retarget.margin_weight) */
} fr_rt_match;

/* Match the photo's thinned cloud (after its rigid correction) to the mesh cur (3 nf floats,
 * indexed by tree): nearer than max_dist, not on the rim, normals within the angle bound.
 * Returns the number of matches written to out (room for p->n_pick). */
int fr_rt_match_cloud(const fr_rt_settings *s, const fr_rt_mesh *m, const fr_tri_tree *tree, const float *cur,
                      const fr_rt_photo *p, double max_dist, fr_rt_match *out);
/* One point-to-plane ICP step: the photo's correction (a rotation, translation and, when
 * with_scale, scale) moves the cloud onto the mesh. */
void fr_rt_rigid_step(const fr_rt_match *mt, int n, int with_scale, fr_rt_photo *p);
/* The angle (radians) of the photo's alignment's rotation. */
double fr_rt_correction_angle(const fr_rt_photo *p);

/* Unit normal of triangle v (3 vertex indices) of positions x. */
void fr_rt_tri_normal(const float *x, const int32_t *v, double n[3]);

/* Lift a photo's detected landmarks (136 values, pixels) onto its cloud: the mean of the cloud
 * points that the pose (R, t: head -> camera) and the pinhole (f, cx, cy) put within radius
 * pixels of each inner landmark (17-67), when they lie on one surface (depths within 5 mm). */
void fr_rt_lift_landmarks(fr_rt_photo *p, const double R[9], const double t[3], double f, double cx, double cy,
                          const double *landmarks, double radius);

/* Algorithm 7 for one photo: rest (3 nv floats, B (x) w_i on the face) is aligned rigidly to
 * the cloud, then deformed toward it; p->M, p->cover and the figures are set. sv: a solver of
 * the face mesh's Laplacian system (one per thread), whose rest shape (the neutral's
 * operators) is set; mass: that system's vertex areas; tree: a copy of the mesh's index (one
 * per thread; refitted here). */
frig_status fr_rt_correspond(frig_ctx *ctx, const fr_rt_settings *s, const fr_rt_mesh *m, fr_lap_solver *sv,
                             const double *mass, fr_tri_tree *tree, const float *rest, fr_rt_photo *p);

/* Per-vertex least squares shared by the neutral and blendshape steps: for every vertex v,
 *     (sum_i c_iv a_i a_i^T + diag(reg)) X_v = sum_i c_iv a_i (y_iv - sub_v)^T + prior_v
 * with a_i the m coefficients of photo i (column i of A, m x n column-major), c_iv =
 * cover[i][v], y_i = targets[i] (3 nv floats), sub (3 nv floats, may be NULL), prior (nv x m
 * x 3, X_v's layout: m rows, 3 columns, column-major per vertex; may be NULL) and X (the same
 * layout). Parallel over vertex blocks; deterministic. */
frig_status fr_rt_vertex_solve(frig_ctx *ctx, int threads, int nv, int n, int m, const double *A,
                               const float *const *cover, const float *const *targets, const float *sub,
                               const double *reg, const double *prior, double *X);

/* Section 5.2.3 (b): each photo's weights (k values in [0, 1]) minimizing
 *     sum_v c_iv |M'_iv - N_v - D_v w|^2 + ridge |w - w_prev|^2
 * D: the k fitting shapes' deltas on the face (shape j at 3 nv j, floats). Parallel over photos. */
frig_status fr_rt_fit_weights(frig_ctx *ctx, const fr_rt_settings *s, int nv, int k, const float *neutral,
                              const float *D, int n, fr_rt_photo *photos);

/* Move the whole rig (neutral and shapes) by the rigid transform that best maps its first nf
 * neutral vertices onto before (3 nf floats): the frame stays the model's (frame_anchor.c). */
void fr_rt_anchor_frame(frig_rig *rig, int nf, const float *before);

/* Settings from the context's retarget.* parameters. */
void fr_rt_settings_from_ctx(const frig_ctx *ctx, fr_rt_settings *s);

/* One retarget pass (Algorithm 6) on rig's face (vertices 0 .. nf-1): K fitting shapes,
 * fit_shape[a] = the rig shape of weight a; n photos with clouds and weights (updated).
 * The rig is replaced in place, the rest of the head following the face. */
frig_status fr_rt_run(frig_ctx *ctx, const fr_rt_settings *s, const frig_model *model, frig_rig *rig, int nf,
                      int K, const int *fit_shape, int n, fr_rt_photo *photos, double *identity, int n_id);

/* The identity from the clouds (identity_fit.c): iterations of point-to-plane ICP of every
 * photo's reconstruction N + D w_i to its cloud, each photo's weights (in [0, 1]) and rigid
 * correction, then one Gauss-Newton step of the shared identity (n_id model modes, prior
 * N(0, I); identity holds the current weights and is updated): rig's neutral moves by the
 * modes over the whole head. */
frig_status fr_rt_fit_identity(frig_ctx *ctx, const fr_rt_settings *s, const frig_model *model, frig_rig *rig,
                               const fr_rt_mesh *m, int K, const int *fit_shape, int n, fr_rt_photo *photos,
                               double *identity, int n_id, int iterations);

/* The whole head (section 5.2's blendshapes are of the face): with the face vertices of rig
 * already replaced, the other vertices follow the change of the neutral and of every shape
 * from old_neutral / old_deltas (the rig before, all vertices): skin connected to the face by
 * a harmonic extension over the mesh, eyeballs, teeth and gums rigidly with the skin around
 * them, lashes and eye overlays with the nearest skin; then in no shape is a lid deeper in its
 * eyeball, or are the teeth further in front of the lips, than in the reference rig
 * (ref_neutral / ref_deltas: the rig the pass started from). */
frig_status fr_rt_whole_head(frig_ctx *ctx, const frig_model *model, int nf, const float *old_neutral,
                             const float *old_deltas, const float *ref_neutral, const float *ref_deltas, frig_rig *rig);

/* The outer loop's last recovery kept its sfs computation (recover_sfs.c, while
 * ctx->rt_defer_albedo): draw its albedo texture into the recovery's frig_image ** and free it
 * (nothing when none is kept); or only free it. */
frig_status fr_rt_pending_albedo_finish(frig_ctx *ctx);

/* frig_retarget in an outer round after the first (refine.c), with the loop's own iteration
 * counts (retarget.loop_*); the context's parameters as they were afterwards. */
frig_status fr_rt_retarget_later_round(frig_ctx *ctx, const frig_model *model, frig_photoset *set,
                                       const frig_clouds *clouds, frig_rig *rig);
void fr_rt_pending_albedo_drop(frig_ctx *ctx);

#endif
