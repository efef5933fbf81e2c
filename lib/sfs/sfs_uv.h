/* The model's UV space for shape from shading (paper Algorithm 5: per-photo albedos averaged
 * in the model's texture space; and the shape shared by all photos, sfs_multiview.c): which
 * face triangle and barycentrics each texel of a T x T texture lies on, and where a texel
 * appears in a photo's crop. Texel (x, y) is at uv = ((x + 0.5) / T, 1 - (y + 0.5) / T)
 * (docs/workspace.md: rows from the top, OBJ's v up). Internal. */
#ifndef FR_SFS_SFS_UV_H
#define FR_SFS_SFS_UV_H

#include <math.h>
#include <stddef.h>

#include "image/bilinear.h"
#include "sfs/sfs.h"

typedef struct fr_sfs_uv {
    int size;       /* T */
    int count;      /* texels on the face */
    int32_t *texel; /* y * T + x of each */
    int32_t *tri;   /* drawn triangle (a face triangle) of each */
    float *bary;    /* 3 per texel */
    int32_t *index; /* T * T: texel number, -1 off the face */
} fr_sfs_uv;

frig_status fr_sfs_uv_init(frig_ctx *ctx, const fr_sfs_mesh *m, int size, fr_sfs_uv *uv);
void fr_sfs_uv_free(fr_sfs_uv *uv);

/* Where texel k shows in view v: crop coordinates (u, v), and whether it is seen there (in
 * front of the camera, inside the crop, not hidden: the crop's nearest pixel shows its
 * triangle or a surface at most 'tol' metres in front of it). Returns 1 when seen. */
int fr_sfs_uv_locate(const fr_sfs_uv *uv, const fr_sfs_mesh *m, const fr_sfs_view *v, int k, double tol,
                     double xy[2], double *depth);

/* The UV coordinate at a crop pixel of view v (the rendered face triangle's corner UVs
 * interpolated); 0 when the pixel shows no face triangle. */
int fr_sfs_uv_at_pixel(const fr_sfs_mesh *m, const fr_sfs_view *v, size_t pixel, double uv[2]);

/* The image's central-difference gradient at crop point xy (bilinear samples one pixel either
 * side), per channel: gx along x, gy along y. */
void fr_sfs_image_gradient(const float *img, int w, int h, const double xy[2], double gx[3], double gy[3]);

/* Bilinear sample of a T x T texture with 'dim' floats per texel at uv (texel-centre
 * convention above); texels with weight[t] <= 0 (may be NULL) are left out and the others
 * renormalized. Returns 0 when no texel around uv has weight. */
int fr_sfs_texture_sample(const float *tex, const float *weight, int size, int dim, const double uv[2], float *out);

#endif
