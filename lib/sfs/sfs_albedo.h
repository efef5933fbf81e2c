/* The subject's albedo in the model's UV space from all photos (paper Algorithm 5; sfs_albedo.c).
 * Internal. */
#ifndef FR_SFS_SFS_ALBEDO_H
#define FR_SFS_SFS_ALBEDO_H

#include "sfs/sfs.h"
#include "sfs/sfs_uv.h"

typedef struct fr_sfs_albedo {
    int size;      /* T */
    float *albedo; /* 3 per texel, linear RGB */
    float *weight; /* per texel: sum of the observations' weights, 0 where unseen */
} fr_sfs_albedo;

frig_status fr_sfs_albedo_init(frig_ctx *ctx, const fr_sfs_uv *uv, fr_sfs_albedo *a);
void fr_sfs_albedo_free(fr_sfs_albedo *a);

/* Every texel's albedo from the views with use[k] != 0: their images divided by their shading
 * (lighting v->sh on the rig's normals v->vn_cam), averaged with the view cosine times
 * v->photo_weight as weights and Tukey's biweight against cast shadows, highlights and
 * misregistered edges (eq. 5.14 and Algorithm 5's mean texture). Texels are independent
 * (parallel, deterministic). sigma: relative intensity error of one standard deviation.
 * texture: the subject's texture's stricter rules: a view whose colour would need an albedo
 * above 1 (linear) in a channel, whose shading is not positive, or whose albedo is greener or
 * bluer than red (more than 5%), does not count (0: every view counts, as the stage's own
 * lighting fits want). */
frig_status fr_sfs_albedo_solve(frig_ctx *ctx, const fr_sfs_mesh *m, const fr_sfs_uv *uv, const fr_sfs_view *views,
                                int nviews, const uint8_t *use, double sigma, int texture, fr_sfs_albedo *a);

/* The subject's texture's shading at normal n (camera frame) under lighting sh: the mean of the
 * three channels' shading, each channel's share of it held within 10% of its share in the light on
 * a surface facing the camera (the normal 0, 0, -1). Each channel's nine SH coefficients are fitted
 * mostly on normals that face the camera and extrapolate apart at grazing ones (a cheek's side on
 * Bing Will Smith: R 0.43, G 0.11, B 0.48, where the light facing the camera is in the proportions
 * 0.90 : 1.02 : 1.08); dividing by them painted the face's sides, the ears and the nostrils
 * yellow-green. frig synth's lights differ by up to 8% per channel between the direct and the
 * ambient light, which the 10% keeps. */
void fr_sfs_texture_shading(const double sh[3][FR_SH_COUNT], const float n[3], double S[3]);

/* The texture's albedo at view v's face pixels (v->albedo; 'fallback' where no photo saw the
 * texel) and the rig's normals as the view's normal prior (v->n_prior). */
void fr_sfs_albedo_apply(const fr_sfs_mesh *m, const fr_sfs_albedo *a, fr_sfs_view *v, const double fallback[3]);

#endif
