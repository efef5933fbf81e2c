/* libfrig synthetic ground truth: subjects whose true rig lies outside the face model's span
 * (the model's identity plus a smooth personal offset, and perturbed expressions), and photos
 * of them rendered by libfrig's own rasterizer with the truth every stage is measured against
 * (paper section 7.2: blendshape error E_B, point-cloud error E_P). Formats: docs/synth.md.
 *
 * EXPERIMENTAL: this part of the API may change while FRIG_VERSION_MAJOR is 0.
 */
#ifndef FRIG_SYNTH_H
#define FRIG_SYNTH_H

#include "frig/image.h"
#include "frig/rig.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct frig_synth_subject frig_synth_subject;
typedef struct frig_synth_truth frig_synth_truth;

/* What an intended failure photo is. */
typedef enum frig_synth_failure {
    FRIG_SYNTH_FAILURE_AUTO = -1,     /* (as an argument) draw it from synth.failure_rate */
    FRIG_SYNTH_FAILURE_NONE = 0,      /* a usable photo */
    FRIG_SYNTH_FAILURE_OCCLUDER = 1,  /* an opaque shape or a hand over the eyes or the mouth */
    FRIG_SYNTH_FAILURE_EXTREME_POSE = 2, /* yaw 75-90 degrees */
    FRIG_SYNTH_FAILURE_NO_FACE = 3,   /* background only */
    FRIG_SYNTH_FAILURE_SUNGLASSES = 4, /* dark glasses over both eyes */
    FRIG_SYNTH_FAILURE_UNDEREXPOSED = 5, /* the whole photo 8-30x too dark */
    FRIG_SYNTH_FAILURE_OVEREXPOSED = 6 /* the whole photo 4-10x too bright: the face blown out */
} frig_synth_failure;

/* "none", "occluder", "extreme_pose", "no_face", "sunglasses", "underexposed", "overexposed";
 * NULL for other values. */
FRIG_API const char *frig_synth_failure_name(int failure);

/* ---- subjects ----
 * A subject from a seed: identity weights ~ N(0, s^2 I), s in [0.8, 1], plus a smooth personal
 * displacement (synth.offset_mm RMS over the face region) whose projection onto the identity
 * modes is removed, plus per-expression changes d_j' = (1 + a_j) d_j + s_j, and a painted
 * skin albedo. The same seed and model give the same subject, byte for byte. The
 * subject copies what it needs; the model may be freed afterwards. */
FRIG_API frig_status frig_synth_subject_create(frig_ctx *ctx, const frig_model *model, uint64_t seed,
                                               frig_synth_subject **out);
FRIG_API void frig_synth_subject_free(frig_synth_subject *subject);

/* The subject's true rig: neutral + the model's expressions as this subject makes them. */
FRIG_API const frig_rig *frig_synth_subject_rig(const frig_synth_subject *subject);
/* The identity weights (count returned; *weights borrowed). neutral = model(weights) + offset
 * with the offset orthogonal to the identity modes over the face region, so these weights are
 * also the best an identity fit over the face region can do. */
FRIG_API int frig_synth_subject_identity(const frig_synth_subject *subject, const double **weights);
/* RMS over the face region, in mm, of the personal offset that is outside the identity span. */
FRIG_API double frig_synth_subject_offset_rms_mm(const frig_synth_subject *subject);
/* The subject's truth (DIR/subject.json) and true rig (DIR/rig/rig.frigrig, DIR/rig/rig.glb,
 * and unless synth.rig_obj is 0 DIR/rig/shapes/ *.obj). The folder is created if needed. */
FRIG_API frig_status frig_synth_subject_save(frig_ctx *ctx, const frig_synth_subject *subject, const char *dir);

/* ---- photos ----
 * Render one photo of a subject from a photo seed: pose, camera, expression mix, lighting,
 * background, noise and (failure != NONE) the intended failure are all drawn from the seed.
 * failure: one of frig_synth_failure (AUTO: a failure with probability synth.failure_rate,
 * its kind drawn too). The image is synth.image_size square, 8-bit sRGB, as it is before the
 * JPEG compression whose quality the truth names. Either output may be NULL when not wanted. */
FRIG_API frig_status frig_synth_render(frig_ctx *ctx, const frig_synth_subject *subject, uint64_t photo_seed,
                                       int failure, frig_image **image, frig_synth_truth **truth);
FRIG_API void frig_synth_truth_free(frig_synth_truth *truth);

FRIG_API frig_synth_failure frig_synth_truth_failure(const frig_synth_truth *truth);
/* 68 landmarks (x, y pixel pairs, iBUG order): detector_like 0 = the landmark vertices' exact
 * projections, 1 = the same with the jaw points 0-16 on the face's visible outline (the rule is
 * in docs/synth.md). NULL for a photo without a face. */
FRIG_API const double *frig_synth_truth_landmarks(const frig_synth_truth *truth, int detector_like);
/* 68 flags: 1 = the landmark can be seen (inside the image, not hidden by the head or an occluder). */
FRIG_API const uint8_t *frig_synth_truth_visible(const frig_synth_truth *truth);
/* Model-to-camera pose X_c = R X + t (R row-major, metres) and the perspective camera
 * (docs/camera.md). Zeros for a photo without a face. */
FRIG_API void frig_synth_truth_pose(const frig_synth_truth *truth, double R[9], double t[3]);
FRIG_API void frig_synth_truth_camera(const frig_synth_truth *truth, double *f, double *cx, double *cy);
/* Expression weights, one per rig shape (frig_rig_shape_count). */
FRIG_API const double *frig_synth_truth_expression(const frig_synth_truth *truth);
/* Camera z (metres) of the rendered head at each pixel centre, row-major, 0 where no surface. */
FRIG_API const float *frig_synth_truth_depth(const frig_synth_truth *truth, int *width, int *height);

/* What each pixel shows, as bits (a pixel has a bit when most of its 2x2 render samples have it).
 * The pixels shape from shading may trust are HEAD & SKIN with none of SHADOW, HIGHLIGHT,
 * OCCLUDED, HAIR. */
enum {
    FRIG_SYNTH_PIXEL_HEAD = 1,      /* the head's surface (as in the depth map) */
    FRIG_SYNTH_PIXEL_SKIN = 2,      /* ... and it is skin (not eyes, teeth, mouth, lashes) */
    FRIG_SYNTH_PIXEL_SHADOW = 4,    /* a cast shadow of the key light takes >= 15% of its light */
    FRIG_SYNTH_PIXEL_HIGHLIGHT = 8, /* specular reflection is >= 10% of its value */
    FRIG_SYNTH_PIXEL_OCCLUDED = 16, /* an occluder, a hand or sunglasses in front */
    FRIG_SYNTH_PIXEL_HAIR = 32      /* hair, brows or beard painted on the skin */
};
/* The class map (width x height bytes of FRIG_SYNTH_PIXEL_* bits, row-major); NULL without a truth. */
FRIG_API const uint8_t *frig_synth_truth_mask(const frig_synth_truth *truth, int *width, int *height);
FRIG_API int frig_synth_truth_jpeg_quality(const frig_synth_truth *truth);
/* Write the truth as JSON and the depth map as raw float32 little-endian (docs/synth.md);
 * 'photo' is the file name the JSON refers to; depth_path may be NULL (then no depth file).
 * With a depth file the class map is written beside it as raw bytes: NAME.depth.f32 ->
 * NAME.mask.u8 (any other depth name: the depth name + ".mask.u8"). */
FRIG_API frig_status frig_synth_truth_save(frig_ctx *ctx, const frig_synth_truth *truth, const char *photo,
                                           const char *json_path, const char *depth_path);

/* ---- datasets ----
 * out_dir/index.json, and per subject s: out_dir/subject_SS/{subject.json, rig/,
 * photos/photo_PPP.jpg, truth/photo_PPP.json, truth/photo_PPP.depth.f32}. Exactly
 * round(synth.failure_rate * photos) photos of each subject are intended failures (their
 * kinds in turn). Photos are rendered in parallel; the bytes do not depend on the thread count.
 * Progress is reported as stage "synth". */
FRIG_API frig_status frig_synth_dataset(frig_ctx *ctx, const frig_model *model, const char *out_dir, int subjects,
                                        int photos, uint64_t seed);

#ifdef __cplusplus
}
#endif
#endif /* FRIG_SYNTH_H */
