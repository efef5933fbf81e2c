/* The inside of the synthetic ground-truth harness (paper section 7.2): subjects, the
 * parameters of one photo, the landmark truth and the renderer's pieces. Internal; the fit
 * stage's tests use fr_synth_photo_draw + fr_synth_landmarks to make landmark sets quickly. */
#ifndef FR_SYNTH_SYNTH_H
#define FR_SYNTH_SYNTH_H

#include <stdint.h>

#include "core/rng.h"
#include "frig/synth.h"
#include "image/srgb.h"
#include "raster/camera.h"
#include "raster/raster.h"
#include "raster/sh_lighting.h"

#define FR_SYNTH_LANDMARKS 68
#define FR_SYNTH_MAX_ACTIVE 5 /* expression shapes active in one photo (4 + a paired jawOpen) */
#define FR_SYNTH_FAILURE_KINDS 6 /* occluder .. overexposed */

/* Vertex classes the renderer and the albedo painter use. */
enum {
    FR_SYNTH_SKIN = 0,    /* face, head and neck, mouth and eye sockets */
    FR_SYNTH_RIGID = 1,   /* eyeballs and teeth: move rigidly, never stretched */
    FR_SYNTH_GUMS = 2,    /* gums and tongue: follow the teeth */
    FR_SYNTH_OVERLAY = 3, /* eyelashes and the transparent eye overlays: follow the lids */
};

struct frig_synth_subject {
    uint64_t seed;
    frig_rig *rig; /* the true rig */
    int nv, shape_count, identity_count;
    /* rendered: the rig's nv vertices then the torso's (torso.c), moving with the head */
    int nv_render;
    float *torso_xyz; /* 3 per torso vertex, head frame */
    float *albedo;    /* linear RGB, 3 per rendered vertex */
    int32_t *tris;    /* the triangles drawn: nt_head of the head (eye overlays and lashes left
                       * out), then the torso's */
    int nt, nt_head;
    uint8_t *outline_tri; /* per drawn triangle: 1 = part of the face whose outline a detector marks */
    uint8_t *eye_tri;     /* per drawn triangle: 0, or 1 + eyeball (iris and pupil painted per pixel) */
    double eye_centre[2][3], eye_axis[2][3]; /* in the neutral's frame */
    double iris_radius, pupil_radius;        /* metres, across the gaze axis */
    double iris_albedo[3], sclera_albedo[3]; /* linear RGB */
    int32_t landmarks[FR_SYNTH_LANDMARKS];
    uint8_t *fitting;     /* per shape: 1 = one of the model's fitting expressions */
    double face_centre[3]; /* model point placed in the photo (between chin and forehead) */
    double face_height;    /* metres, chin to the top of the forehead */
    double jaw_normal[17][3]; /* outward normals of the jaw line (landmarks 0-16) in the face plane */
    /* truth */
    double *identity; /* identity_count */
    double identity_scale;
    double offset_rms_mm, offset_raw_rms_mm, offset_in_span; /* in_span: share of raw energy removed */
    int offset_bumps;
    double *shape_scale;     /* a_j per shape */
    double *shape_field_rel; /* RMS of s_j / RMS of d_j over the vertices d_j moves */
    double skin_srgb[3], hair_srgb[3], iris_srgb[3], cloth_srgb[3];
    int bald, beard;
    float *hair;      /* per head vertex: 0..1, how much hair, brow or beard covers the skin */
    uint8_t *skin;    /* per head vertex: 1 = skin (face, head and neck), 0 = eyes, teeth, mouth, lashes */
};

/* One photo's parameters, all drawn from its seed (fr_synth_photo_draw); callers may edit
 * the fields (pose, expression) before rendering or computing landmarks. */
typedef struct fr_synth_photo {
    uint64_t seed;
    int width, height;
    int failure; /* frig_synth_failure */
    double yaw, pitch, roll; /* degrees */
    double R[9], t[3];
    fr_camera cam;
    double focal_mm, face_frac;
    int n_active, active[FR_SYNTH_MAX_ACTIVE];
    double weight[FR_SYNTH_MAX_ACTIVE];
    /* lighting: irradiance E_c(n) = sum_k sh[c][k] Y_k(n), n in camera coordinates */
    double sh[3][9], light_dir[3], light_ratio, exposure;
    /* background: two-colour gradient along 'bg_angle', low-frequency blobs, clutter */
    double bg_colour[2][3], bg_angle;
    int bg_clutter;
    uint64_t bg_seed;
    /* occluder (failure OCCLUDER): 0 rectangle, 1 ellipse, 2 hand; over 0 the eyes, 1 the mouth */
    int occ_shape, occ_over;
    double occ_jitter[4];  /* drawn; the placement follows from the landmarks */
    double occ_centre[2], occ_axes[2], occ_angle, occ_colour[3]; /* pixels, radians, linear RGB */
    int jpeg_quality;
    double noise_sigma; /* sensor noise, 8-bit levels */
    uint64_t noise_seed;
    /* the key light's part of the lighting (drawn by fr_synth_photo_draw with the rest) */
    double sh_direct[3][9]; /* its share of sh: removed where the key light is shadowed */
    double direct_rgb[3];   /* its irradiance per channel (for highlights) */
    double gain;            /* the whole image times this: 1, or an exposure failure's factor */
    /* sunglasses (failure SUNGLASSES), placed from the landmarks like the occluder (sunglasses.c) */
    double sg_jitter[4];
    double sg_centre[2][2], sg_axes[2][2], sg_angle, sg_rim; /* pixels, radians */
    double sg_lens[3], sg_frame[3], sg_glare;              /* linear RGB, reflection strength */
    /* cast shadows and highlights (fr_synth_photo_effects, from their own stream) */
    int shadows;                    /* 1: the key light casts hard shadows */
    double spec_ks, spec_shininess; /* skin's Blinn-Phong highlight */
} fr_synth_photo;

/* The landmark truth of one photo. */
typedef struct fr_synth_landmarks {
    double exact[2 * FR_SYNTH_LANDMARKS];    /* projections of the landmark vertices */
    double detector[2 * FR_SYNTH_LANDMARKS]; /* jaw points moved onto the outline */
    uint8_t visible[FR_SYNTH_LANDMARKS];
    uint8_t jaw_moved[17];
    double face_box[4]; /* x0, y0, x1, y1 of the outline-face pixels (-1 when none) */
} fr_synth_landmarks;

/* ---- subject pieces (subject.c calls them in this order) ---- */
/* Personal displacement (offset_field.c): a smooth field of RMS offset_mm over the face
 * region, minus its projection onto the identity modes there, added to 'neutral' (3 per
 * vertex); fills the subject's offset_* figures (offset_rms_mm: what remains). */
frig_status fr_synth_offset(frig_ctx *ctx, const frig_model *model, frig_synth_subject *s, fr_rng *rng,
                            double offset_mm, float *neutral);
/* Per-expression changes (expression_perturb.c): deltas (3 nv per shape) changed in place. */
frig_status fr_synth_perturb_expressions(frig_ctx *ctx, const frig_model *model, frig_synth_subject *s, fr_rng *rng,
                                         const float *neutral, float *deltas);
/* Skin, lips, brows, eyes, teeth, hair (albedo.c) into s->albedo. */
frig_status fr_synth_paint_albedo(frig_ctx *ctx, const frig_model *model, frig_synth_subject *s, fr_rng *rng);
/* Shoulders under the neck (torso.c): vertices (head frame) and triangles, caller frees. */
frig_status fr_synth_torso(frig_ctx *ctx, frig_synth_subject *s, fr_rng *rng, float **xyz, int *nv, int32_t **tris,
                           int *nt);
/* Cosine-weighted share of directions from which each vertex is seen (occlusion.c). */
frig_status fr_synth_ambient_occlusion(frig_ctx *ctx, const float *xyz, int nv, const int32_t *tris, int nt,
                                       float *ao);
/* Vertex class (FR_SYNTH_*) of each vertex, from the model's regions; NULL when out of memory. */
uint8_t *fr_synth_vertex_classes(const frig_model *model);
/* A named vertex range (1 when present and not empty). */
int fr_synth_region(const frig_model *model, const char *name, int *first, int *count);
/* Centroid of a named region of xyz (3 per vertex); 0 (and c = 0) when absent. */
int fr_synth_region_centroid(const frig_model *model, const char *name, const float *xyz, double c[3]);

/* Smooth random fields (bumps.c): sums of Gaussian radial basis bumps v exp(-|x - c|^2 / 2r^2). */
typedef struct fr_bump {
    double c[3], r, v[3];
} fr_bump;
void fr_bumps_eval(const fr_bump *b, int n, const double x[3], double out[3]);
double fr_smoothstep(double e0, double e1, double x);

/* ---- photos ---- */
/* Draw a photo's parameters; failure is a frig_synth_failure (AUTO: from failure_rate). */
void fr_synth_photo_draw(const frig_synth_subject *s, uint64_t seed, int width, int height, int failure,
                         double max_yaw_deg, double failure_rate, fr_synth_photo *p);
/* Cast shadows (with probability shadow_rate) and specular highlights (strength x specular)
 * for a drawn photo, from a stream of their own (the photo's other parameters do not change). */
void fr_synth_photo_effects(fr_synth_photo *p, double shadow_rate, double specular);
/* The subject's one light (synth.one_light) in place of the photo's own: drawn from the subject's
 * seed, the same for all its photos. Before fr_synth_photo_effects. */
void fr_synth_photo_one_light(const frig_synth_subject *s, fr_synth_photo *p);

/* A shadow map of the key light: the scene's depth along the light's direction of travel,
 * orthographic (shadow.c). */
typedef struct fr_shadow_map {
    int size;
    double u[3], v[3], w[3]; /* light frame: w = direction of travel */
    double scale, ou, ov;    /* texel = scale * (X.u, X.v) + (ou, ov) */
    fr_raster *r;
} fr_shadow_map;
/* Render the triangles of camera-space vertices xyz as seen from a distant light in direction
 * light_dir (unit, toward the light) into a size x size map. */
frig_status fr_synth_shadow_map(frig_ctx *ctx, const float *xyz, int nv, const int32_t *tris, int nt,
                                const double light_dir[3], int size, fr_shadow_map *m);
void fr_synth_shadow_map_free(fr_shadow_map *m);
/* Share (0..1) of a 3x3 neighbourhood of map texels around camera-space point X that do not
 * hide X from the light (percentage-closer filtering). */
double fr_synth_shadow_visibility(const fr_shadow_map *m, const double X[3]);
/* The posed head in camera coordinates (3 per vertex; caller frees). */
frig_status fr_synth_posed_vertices(frig_ctx *ctx, const frig_synth_subject *s, const fr_synth_photo *p,
                                    float **xyz_cam);
/* Landmark truth from a render of the posed head at the photo's size (r, xyz_cam: the
 * posed vertices rendered with s->tris). An OCCLUDER photo's occluder is placed in p. */
frig_status fr_synth_landmarks_from_render(frig_ctx *ctx, const frig_synth_subject *s, fr_synth_photo *p,
                                           const fr_raster *r, const float *xyz_cam, fr_synth_landmarks *lm);
/* The fast path: landmarks only, no image (renders the photo-sized raster internally); all
 * NaN for a NO_FACE photo. */
frig_status fr_synth_landmarks_only(frig_ctx *ctx, const frig_synth_subject *s, const fr_synth_photo *p,
                                    fr_synth_landmarks *lm);
/* Place the occluder over the eyes or the mouth of the exact landmark projections (occluder.c). */
void fr_synth_place_occluder(fr_synth_photo *p, const double exact[2 * FR_SYNTH_LANDMARKS]);
/* Place the sunglasses over the eyes of the exact landmark projections (sunglasses.c). */
void fr_synth_place_sunglasses(fr_synth_photo *p, const double exact[2 * FR_SYNTH_LANDMARKS]);
/* Is image point (x, y) under the photo's occluder or sunglasses (0 for other photos)? */
int fr_synth_occluded(const fr_synth_photo *p, double x, double y);
/* The sunglasses' part at (x, y): 0 none, 1 lens, 2 frame (sunglasses.c). */
int fr_synth_sunglasses_at(const fr_synth_photo *p, double x, double y, double *lens_u, double *lens_v);
/* Draw the sunglasses over a linear RGB buffer rendered at 'scale' times the photo's size. */
void fr_synth_draw_sunglasses(const fr_synth_photo *p, int w, int h, double scale, float *rgb);


/* Background of a photo into a linear RGB buffer (w x h x 3) (background.c). */
void fr_synth_background(const fr_synth_photo *p, int w, int h, double scale, float *rgb);
/* Draw the occluder over a linear RGB buffer rendered at 'scale' times the photo's size. */
void fr_synth_draw_occluder(const fr_synth_photo *p, int w, int h, double scale, float *rgb);

/* A 64-bit seed for item 'index' of a stream (splitmix64 of both). */
uint64_t fr_seed_mix(uint64_t seed, uint64_t index);

/* All landmarks NaN, nothing visible (a photo without a face). */
void fr_synth_landmarks_none(fr_synth_landmarks *lm);

/* Albedo of eyeball e at a point of the neutral eyeball (sclera, iris with its dark rim, pupil). */
void fr_synth_eye_albedo(const frig_synth_subject *s, int e, const double rest[3], double rgb[3]);

/* The truth object behind frig_synth_truth. */
struct frig_synth_truth {
    fr_synth_photo photo;
    fr_synth_landmarks lm;
    int has_face;
    int shape_count;
    double *expression;       /* shape_count */
    const char **shape_names; /* point into names_blob */
    char *names_blob;
    int32_t landmark_vertices[FR_SYNTH_LANDMARKS];
    float *depth; /* width * height, 0 where empty */
    uint8_t *mask; /* width * height FRIG_SYNTH_PIXEL_* bits */
};
/* A one-line JSON array of n numbers (truth.c). */
struct fr_json;
void fr_synth_json_numbers(struct fr_json *j, const char *key, const double *v, int n);

/* A truth for subject s with the photo's parameters, expression weights filled, no depth yet. */
frig_status fr_synth_truth_new(frig_ctx *ctx, const frig_synth_subject *s, const fr_synth_photo *p,
                               frig_synth_truth **out);

/* Render a photo and fill its truth (render.c). */
frig_status fr_synth_render_photo(frig_ctx *ctx, const frig_synth_subject *s, const fr_synth_photo *p,
                                  frig_image **image, frig_synth_truth **truth);

#endif
