/* The shape-from-shading stage's inside (paper section 5.1, Algorithms 4-5): the rig as the
 * stage draws it, one photo's view (its face crop and the rig rendered into it), the subject's
 * albedo in the model's UV space, and the per-photo solvers. Internal. */
#ifndef FR_SFS_SFS_H
#define FR_SFS_SFS_H

#include <stdint.h>

#include "frig/frig.h"
#include "raster/camera.h"
#include "raster/sh_lighting.h"
#include "skin/skin.h"

/* ---- settings (the sfs.* parameters) ---- */
typedef struct fr_sfs_settings {
    double face_px;       /* the face's longer side in the crop is at most this many pixels */
    int rounds;           /* albedo rounds (Algorithm 4's outer loop) after the first estimate */
    int iterations;       /* Gauss-Newton iterations of the depth per round */
    double w_normal;      /* the normals' change kept smooth (curvature of the depth correction) */
    double w_anchor;      /* eq. 5.13: depth held to the fitted depth */
    double w_prior;       /* normals held to those of the shape shared by all photos */
    double sigma;         /* data residual scale: relative intensity error of one standard deviation */
    double e_max;         /* eq. 5.15: largest SfS error kept, relative intensity */
    double d_max_mm;      /* eq. 5.15: largest deviation from the fitted depth kept, mm */
    double min_skin;      /* sfs_failed below this share of skin in the face region */
    double max_clipped;   /* sfs_failed above this share of clipped face pixels */
    double min_luma;      /* sfs_failed when the face's median 8-bit luma is below this */
    double min_agreement; /* sfs_failed when the photo's albedo correlates less with the subject's */
    int min_points;       /* sfs_failed with fewer points kept */
    int cloud_region;     /* 2: the cloud from the narrow face, the neck, ears and scalp its margin; 1: those dropped; 0: all in the cloud */
    int texture_size;     /* side of the UV albedo texture written out */
    int shape_size;       /* side of the UV grid of the shared shape */
    int pose;             /* 1: refine the pose against the recovered depth (ICP) */
    int transfer;         /* Reinhard transfer of the albedo to each photo: 0 off, 1 means, 2 means and spreads */
    /* the shared shape's terms (sfs.stereo, sfs.joint_pose, sfs.joint_albedo, sfs.shape_iterations,
     * sfs.shape_sigma, sfs.pose_levels, sfs.pose_sigma; docs/sfs.md) */
    double w_stereo;      /* each photo's own image gradient along a texel's projected path (0: shading only) */
    int pose_steps;       /* per round, Levenberg-Marquardt steps of each photo's pose against the shared shape */
    int joint_albedo;     /* 1: the texels' albedo solved with the shared displacement, not alternated with it */
    int shape_iterations; /* Gauss-Newton iterations of the shared shape per round (0: its default, 4) */
    double shape_sigma;   /* the shared shape's residual scale (0: its default, 0.03) */
    int pose_levels;      /* each photo's pose registered coarse to fine with this many blur levels (0: off) */
    int joint_min_photos; /* fewer photos than this: the light shared solve (fr_sfs_light_shared_solve) */
    int joint_max_photos; /* more photos than this (0: no limit): the light shared solve too, for time */
    int light;            /* 1: the light shared solve whatever the photos (the outer loop's recoveries: why "outer_loop") */
    double joint_light;   /* the lights' concentration on the face above this: the light shared solve too */
    double pose_sigma_px; /* the finest blur level, crop pixels for a 160-pixel face (0: its default, 2) */
    /* each photo's expression refined after each round (sfs.expression_*; sfs_expression.c) */
    int expression_steps;     /* Gauss-Newton steps per round (0: the fit's weights) */
    double expression_prior;  /* held to the fit's weights */
    double expression_sparse; /* L1 */
    const uint8_t *shape_use; /* per photo of the set: used by the shared shape (NULL: every usable photo) */
    /* the model's identity modes solved with the shared shape (NULL / 0: off; set by the caller, not a
     * parameter): identity_count modes of 3 nv floats each (standard deviations), the weights' prior
     * identity_prior |(1 - identity_centre) identity_start + change|^2 in the shared solve's energy units
     * (identity_start: the fitted identity's first identity_count weights, NULL for zeros) */
    const float *identity_modes;
    int identity_count;
    double identity_prior;
    double identity_centre;
    double displacement_hold; /* the shared displacement's anchor in the first half of the rounds (identity modes) */
    double highlights;        /* skin pixels this many robust deviations whiter than the skin lose their white part (sfs_highlights.c; 0: off) */
    const double *identity_start;
} fr_sfs_settings;

void fr_sfs_settings_from_ctx(const frig_ctx *ctx, fr_sfs_settings *s);
/* With sfs.identity_modes > 0: the model's first identity modes (at most the model's and the set's
 * fitted identity's counts) solved with the shared shape from the set's fitted identity. The
 * settings borrow the model's and the set's arrays. Nothing without a model. */
void fr_sfs_settings_identity(const frig_ctx *ctx, fr_sfs_settings *s, const frig_model *model, const frig_photoset *set);
/* The shared solve as it was before the registration and J became the default (2026-12-02): the
 * albedo alternated with the displacement, no multi-view term, no pose registration, at most 3
 * rounds of 4 iterations, residual scale 0.03; for sets of fewer than joint_min_photos photos or
 * more than joint_max_photos. */
void fr_sfs_light_shared_solve(fr_sfs_settings *s);

/* ---- the rig as the stage draws it ---- */
typedef struct fr_sfs_mesh {
    const frig_rig *rig;
    int nv, shapes;
    int nt;           /* triangles drawn (opaque materials) */
    int32_t *tris;    /* 3 vertex indices per drawn triangle */
    int32_t *tri_uv;  /* 3 uv indices per drawn triangle */
    uint8_t *face;    /* per drawn triangle: 1 = the face material (skin the stage reads) */
    uint8_t *core;    /* per drawn triangle: a face triangle of the narrow face (no neck, ears, scalp) */
    const float *uvs; /* 2 per uv index */
    uint8_t *face_vertex; /* per vertex: used by a face triangle */
    int32_t *near_face;   /* the drawn triangles that use a face vertex, ascending (the only ones whose
                           * normals the stage reads: fr_sfs_mesh_normals) */
    int n_near_face;
    float *ident;     /* NULL, or per vertex an identity change (3 nv, metres) added to the rig wherever it is
                       * evaluated (the shared solve's identity modes; owned, freed with the mesh) */
} fr_sfs_mesh;

frig_status fr_sfs_mesh_init(frig_ctx *ctx, const frig_rig *rig, fr_sfs_mesh *m);
void fr_sfs_mesh_free(fr_sfs_mesh *m);
/* The rig at weights (one per rig shape; only non-zero weights are summed, in double, so the
 * result does not depend on BLAS), plus m->ident when there is one, 3 floats per vertex. */
void fr_sfs_mesh_eval(const fr_sfs_mesh *m, const double *weights, float *xyz);
/* Vertex normals of the posed rig xyz (fr_mesh_vertex_normals) at the face vertices, which are all the
 * stage reads (face triangles' corners): the same floats there, (0, 0, 0) elsewhere, for about a third
 * of the work. */
void fr_sfs_mesh_normals(const fr_sfs_mesh *m, const float *xyz, float *normals);

/* ---- one photo's view ---- */
typedef struct fr_sfs_view {
    size_t photo;
    int w, h;            /* crop size */
    double x0, y0, s;    /* crop pixel (i, j)'s centre is photo point (x0 + (i + 0.5) / s - 0.5, ...) */
    fr_camera cam;       /* the crop's camera */
    double R[9], t[3];   /* the pose (head -> camera) the view was rendered with */
    double R_fit[9], t_fit[3]; /* the fit's pose (z_fit's) */
    double *weights;     /* rig weights (m->shapes) */
    float *xyz_cam;      /* posed vertices, camera frame (3 nv) */
    float *vn_cam;       /* their unit normals, camera frame (3 nv) */
    float *I;            /* linear RGB, 3 per pixel */
    uint8_t *rgb;        /* the crop in 8-bit sRGB */
    uint8_t *inside;     /* pixel centre inside the photo */
    /* the rig rendered */
    float *zbuf;         /* camera depth of whatever the rig shows at each pixel, 0 where nothing */
    float *z_ref;        /* camera depth of the reference (the fit, later the displaced rig), 0 where not face */
    float *z_fit;        /* camera depth of the fit itself (the first render), 0 where not face */
    float *n_ref;        /* interpolated unit normals, camera frame (3 per pixel) */
    int32_t *tri;        /* drawn triangle, -1 where none */
    float *bary;         /* 3 per pixel */
    uint8_t *face;       /* pixel shows a face triangle, seen from the front, inside the photo */
    uint8_t *core;       /* of those, a narrow-face triangle (where the skin colour model is learnt) */
    uint8_t *skin;       /* skin (fr_skin_detect over 'face') */
    fr_skin_stats skin_stats;
    float *n_prior;      /* reference normals for the depth (camera frame), 0 where none */
    /* the solution */
    double sh[3][FR_SH_COUNT]; /* lighting per channel */
    float *albedo;       /* current albedo, linear RGB (3 per pixel) */
    float *z;            /* recovered depth (camera z, metres), 0 where none */
    float *normal;       /* recovered normals, camera frame (3 per pixel) */
    float *err;          /* SfS error per pixel (relative), -1 where none */
    uint8_t *kept;       /* region selection (eq. 5.15): 1 the cloud's, 2 its margin's (fr_sfs_region_narrow) */
    float *confidence;
    int face_pixels, data_pixels, kept_pixels, margin_pixels;
    int highlight_pixels; /* skin pixels whose white part was taken out (sfs_highlights.c) */
    double sfs_error;    /* median relative shading error over the skin pixels */
    double agreement;    /* correlation of the photo's albedo with the subject's */
    double photo_weight; /* weight of the photo's observations in the shared albedo and shape (from agreement) */
    double R_refined[9], t_refined[3];
    double pose_change_deg;
    /* what the rig's buffers above were drawn with (fr_sfs_view_render; drawn 0: unknown): the pose,
     * the weights, the displacement and the mesh's identity change (copies; NULL when none) */
    int drawn;
    double drawn_R[9], drawn_t[3];
    double *drawn_weights;
    float *drawn_disp, *drawn_ident;
    /* the rig at those weights with that displacement and identity change, head frame (3 nv; valid
     * while shaped, which drawn implies): a drawing that changes only the pose (the registration's
     * and the pose steps') starts from it instead of evaluating the rig and its normals again */
    int shaped;
    float *drawn_xyz;
} fr_sfs_view;

/* Read photo p of the set, crop it around the face and render the rig at the photo's fit into
 * the crop. 'fit_weights' are the set's fitted expression weights (names in the set). */
frig_status fr_sfs_view_build(frig_ctx *ctx, const fr_sfs_mesh *m, const fr_sfs_settings *st, const char *path,
                              int photo_width, int photo_height, const double R[9], const double t[3], double focal,
                              const double *weights, fr_sfs_view *v);
void fr_sfs_view_free(fr_sfs_view *v);

/* Render the rig at (R, t) into the view's crop: z_ref, n_ref, tri, bary, face (and xyz_cam,
 * vn_cam, zbuf). disp (may be NULL): per vertex, a displacement in metres along the vertex
 * normal of the rig at the view's weights (the subject's shape from all photos). */
frig_status fr_sfs_view_render(frig_ctx *ctx, const fr_sfs_mesh *m, fr_sfs_view *v, const double R[9],
                               const double t[3], const float *disp);

/* For the view's next drawing with disp (fr_sfs_view_render): the rig at the view's weights and
 * the mesh's identity change now, xyz (head frame), with its normals nrm (fr_sfs_mesh_normals),
 * displaced and kept, so that the drawing need not evaluate them again (the same floats). Without
 * memory, nothing is kept. */
void fr_sfs_view_keep_rig(const fr_sfs_mesh *m, fr_sfs_view *v, const float *disp, const float *xyz, const float *nrm);

/* ---- region selection (eq. 5.15; sfs_region.c) and the pose (sfs_pose.c) ---- */
/* v->kept and v->confidence from v->err, v->z, v->z_ref (st->e_max, st->d_max_mm). */
void fr_sfs_select_region(fr_sfs_view *v, const fr_sfs_settings *st);
/* The kept pixels narrowed to the narrow face (sfs.cloud_region): the neck, ears and scalp
 * become the margin (kept 2, not counted in kept_pixels), or are dropped when margin is 0. */
void fr_sfs_region_narrow(fr_sfs_view *v, int margin);
/* The pose (head -> camera) that best fits the rig at the view's weights to its kept points. */
frig_status fr_sfs_refine_pose(frig_ctx *ctx, const fr_sfs_mesh *m, fr_sfs_view *v, double R[9], double t[3]);

/* The photo's picture: skin mask, synthesized shading, error map, kept region (sfs_overlay.c). */
frig_status fr_sfs_write_overlay(frig_ctx *ctx, const fr_sfs_view *v, const fr_sfs_settings *st, const char *label,
                                 const char *path);

/* ---- lighting (eq. 5.3-5.5) ---- */
/* Least-squares SH lighting per channel: I_c = a_c sum_k l_ck Y_k(n) over the pixels with
 * weight > 0 (weights NULL: mask), normals 3 per pixel. Returns the residual RMS (relative). */
frig_status fr_sfs_fit_lighting(frig_ctx *ctx, int n, const uint8_t *mask, const float *I, const float *albedo,
                                const float *normals, const float *weights, double sh[3][FR_SH_COUNT]);
/* Shading S_c(n) = sum_k l_ck Y_k(n) clamped at 0. */
void fr_sfs_shading(const double sh[3][FR_SH_COUNT], const float n[3], double S[3]);

#endif
