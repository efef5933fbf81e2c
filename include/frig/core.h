/* libfrig core: versions, statuses, the context handle that every call takes, and the
 * enumerated parameters through which every stage is configured. Include <frig/frig.h>
 * for the whole API.
 * The conventions are written down in docs/api.md.
 *
 * Copyright (c) 2026 the libfrig authors. MIT licence (see LICENSE).
 */
#ifndef FRIG_CORE_H
#define FRIG_CORE_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* ======================================================================================
 * STABLE API
 * ====================================================================================== */

#define FRIG_VERSION_MAJOR 0
#define FRIG_VERSION_MINOR 1
#define FRIG_VERSION_PATCH 0
#define FRIG_VERSION_NUMBER (FRIG_VERSION_MAJOR * 10000 + FRIG_VERSION_MINOR * 100 + FRIG_VERSION_PATCH)
#define FRIG_VERSION_STRING "0.1.0"

#if defined(FRIG_BUILDING_LIBRARY)
#define FRIG_API __attribute__((visibility("default")))
#else
#define FRIG_API
#endif

/* Version of the library actually linked (compare with FRIG_VERSION_NUMBER). */
FRIG_API unsigned frig_version_number(void);
FRIG_API const char *frig_version_string(void);

/* Every call that can fail returns one of these; the context keeps a sentence saying
 * what failed (which file, which photo, which value): frig_ctx_errmsg(). */
typedef enum frig_status {
    FRIG_OK = 0,
    FRIG_ERR_INVALID_ARGUMENT = 1, /* a NULL handle, an out-of-range value, a bad option */
    FRIG_ERR_NO_MEMORY = 2,        /* an allocation failed */
    FRIG_ERR_IO = 3,               /* a file could not be opened, read or written */
    FRIG_ERR_NOT_FOUND = 4,        /* a required file (model, data) does not exist */
    FRIG_ERR_CORRUPT = 5,          /* data is malformed: a broken JPEG, a bad model file */
    FRIG_ERR_TRUNCATED = 6,        /* data ends before it should */
    FRIG_ERR_UNSUPPORTED = 7,      /* valid data in a form we do not handle */
    FRIG_ERR_TOO_LARGE = 8,        /* over a configured limit (e.g. image.max_pixels) */
    FRIG_ERR_NUMERIC = 9,          /* a factorization or solve failed (singular, not SPD) */
    FRIG_ERR_CANCELLED = 10,       /* frig_ctx_cancel() was called */
    FRIG_ERR_NO_FACE = 11,         /* no usable face where one was needed */
    FRIG_ERR_TOO_FEW = 12,         /* too few usable photos for the stage */
    FRIG_ERR_STATE = 13,           /* a stage was called before the stage it needs */
    FRIG_ERR_INTERNAL = 14         /* a bug: please report it with the message */
} frig_status;

/* A short fixed description of a status ("corrupt data"). Never NULL. */
FRIG_API const char *frig_strerror(frig_status status);

/* ---- the context ------------------------------------------------------------------
 * A frig_ctx carries settings (threads, parameters), callbacks (log, progress), a cancel
 * flag and the last error. Use one context per thread of the caller; the library itself
 * runs parallel loops inside a call. */
typedef struct frig_ctx frig_ctx;

typedef enum frig_log_level {
    FRIG_LOG_ERROR = 0,
    FRIG_LOG_WARNING = 1,
    FRIG_LOG_INFO = 2,
    FRIG_LOG_DEBUG = 3
} frig_log_level;

/* Called with one line of text (no trailing newline). Calls are serialized by the library. */
typedef void (*frig_log_fn)(void *user, frig_log_level level, const char *message);
/* Called as a long loop advances: stage name ("detect", "fit.individual", ...), items done,
 * items in all. Calls are serialized by the library and come in increasing 'done' order. */
typedef void (*frig_progress_fn)(void *user, const char *stage, size_t done, size_t total);

/* Returns NULL only when out of memory. */
FRIG_API frig_ctx *frig_ctx_create(void);
FRIG_API void frig_ctx_free(frig_ctx *ctx);

/* The last error sentence set on this context ("" if none). Valid until the next call. */
FRIG_API const char *frig_ctx_errmsg(const frig_ctx *ctx);
/* The status of the last failed call on this context (FRIG_OK if none). */
FRIG_API frig_status frig_ctx_status(const frig_ctx *ctx);
FRIG_API void frig_ctx_clear_error(frig_ctx *ctx);

/* Worker threads for parallel loops; 0 (the default) means one per available core.
 * Results are identical whatever this number is. */
FRIG_API frig_status frig_ctx_set_threads(frig_ctx *ctx, int threads);
FRIG_API int frig_ctx_threads(const frig_ctx *ctx);

/* Messages at or below max_level go to fn (default: none are delivered). */
FRIG_API void frig_ctx_set_log(frig_ctx *ctx, frig_log_fn fn, void *user, frig_log_level max_level);
FRIG_API void frig_ctx_set_progress(frig_ctx *ctx, frig_progress_fn fn, void *user);

/* Ask running calls on this context to stop; they return FRIG_ERR_CANCELLED soon after.
 * Safe to call from another thread or a signal handler. */
FRIG_API void frig_ctx_cancel(frig_ctx *ctx);
/* Clear a previous cancel so the context can be used again. */
FRIG_API void frig_ctx_reset_cancel(frig_ctx *ctx);

/* ---- parameters ----------------------------------------------------------------------
 * Every stage option is an enumerated parameter with a name, a default, and bounds.
 * New parameters are appended; numbers never change meaning. All values are doubles
 * (integers and booleans included). */
typedef enum frig_param {
    /* images */
    FRIG_PARAM_IMAGE_MAX_PIXELS = 100,      /* refuse images with more pixels (default 1e8) */
    FRIG_PARAM_IMAGE_JPEG_QUALITY = 101,    /* quality of JPEGs we write (default 92) */

    /* detect (section 4.2) */
    FRIG_PARAM_DETECT_SCALE_FACTOR = 200,   /* cascade pyramid step (default 1.1) */
    FRIG_PARAM_DETECT_MIN_NEIGHBORS = 201,  /* cascade grouping threshold (default 3) */
    FRIG_PARAM_DETECT_MIN_FACE = 202,       /* smallest face, pixels (default 30) */
    FRIG_PARAM_DETECT_PROFILE = 203,        /* profile cascade where the frontal finds nothing (default 1) */
    FRIG_PARAM_DETECT_MAX_SIDE = 204,       /* detect on a copy downscaled to this side (default 1024) */
    FRIG_PARAM_DETECT_USER_LANDMARKS = 205, /* use PHOTO.pts / PHOTO.landmarks.json when present (default 1) */
    FRIG_PARAM_DETECT_MIN_EYE_DISTANCE = 206, /* smaller subject faces are face_too_small, pixels (default 15) */
    FRIG_PARAM_DETECT_DUPLICATES = 207,     /* 1: a photo with an earlier photo's bytes is a duplicate (default 1) */
    FRIG_PARAM_DETECT_COARSE_SIDE = 208,    /* frontal search first on a copy this large; 0: off (default 640) */
    /* detect with face-api's networks (frig/identity.h) */
    FRIG_PARAM_DETECT_DETECTOR = 209,       /* 0: SSD where its weights are installed, else cascades; 1: cascades; 2: SSD */
    FRIG_PARAM_DETECT_SSD_MIN_SCORE = 210,  /* SSD faces scored above this are kept (default 0.2; the package's 0.5) */
    FRIG_PARAM_DETECT_LANDMARKS = 211,      /* landmarks on SSD faces: 1 dlib's predictor on the box from the net's points (default), 2 face-api's net, 3 dlib on the mapped SSD box */
    FRIG_PARAM_DETECT_DESCRIPTORS = 212,    /* 1: a 128-D descriptor for every face when the networks are there */
    FRIG_PARAM_DETECT_SSD_FALLBACK = 213,   /* 1: where the SSD finds no face, the cascades search (default 1) */
    FRIG_PARAM_DETECT_NET_TURN = 214,       /* with detect.landmarks 1, faces turned more than this keep the net's points (default 0.8; >1 never) */


    /* filter (section 4.2, Algorithm 1) */
    FRIG_PARAM_FILTER_OMEGA = 300,          /* drop e > mu + omega * sigma (default 4) */
    FRIG_PARAM_FILTER_W_TEXTURE = 301,      /* w_t (default 1.0) */
    FRIG_PARAM_FILTER_W_SHAPE = 302,        /* w_s (default 0.1) */
    FRIG_PARAM_FILTER_MAX_ROUNDS = 303,     /* at most this many rounds (default 10) */
    FRIG_PARAM_FILTER_TEXTURE_SIZE = 304,   /* side of the warped texture (default 64) */
    FRIG_PARAM_FILTER_PCA_ENERGY = 305,     /* variance kept by the PCA models (default 0.98) */
    FRIG_PARAM_FILTER_ROBUST_STATS = 306,   /* 1: mu, sigma = median, 1.4826 MAD; 0: mean, std (default 1) */
    FRIG_PARAM_FILTER_SCORE_ALL = 307,      /* 1: each round judges every photo against all photos' spread (default 0) */
    FRIG_PARAM_FILTER_MIRROR = 308,         /* 1: the shape model also learns the inliers' mirror images (default 1) */
    FRIG_PARAM_FILTER_PEEL_MIN_FACES = 309, /* rounds after the first only with at least this many inliers (default 12) */

    /* fit (sections 4.3-4.4, Algorithm 2) */
    FRIG_PARAM_FIT_W_EXP = 400,             /* expression prior (default 10) */
    FRIG_PARAM_FIT_W_SPARSE = 401,          /* L1 expression sparsity (default 100) */
    FRIG_PARAM_FIT_W_ID = 402,              /* identity prior (default 20) */
    FRIG_PARAM_FIT_ROUNDS = 403,            /* progressive rounds (default 3) */
    FRIG_PARAM_FIT_SUBSET_FIRST = 404,      /* fraction in the first joint fit (default 0.4) */
    FRIG_PARAM_FIT_SUBSET_STEP = 405,       /* added per round (default 0.2: 0.4, 0.6, 0.8) */
    FRIG_PARAM_FIT_SCORE_W_ID = 406,        /* eq. 4.11 w1 (default 1.0) */
    FRIG_PARAM_FIT_SCORE_W_TEX = 407,       /* eq. 4.11 w2 (default 10.0) */
    FRIG_PARAM_FIT_IDENTITY_MODES = 408,    /* identity modes used (default 100) */
    FRIG_PARAM_FIT_ITERATIONS = 409,        /* Levenberg-Marquardt iterations per fit (default 20) */
    FRIG_PARAM_FIT_PERSPECTIVE = 410,       /* 1: perspective camera, 0: weak perspective (default 1) */
    FRIG_PARAM_FIT_CONTOUR_WEIGHT = 411,    /* weight of the jaw landmarks 0-16 (default 0.25) */
    FRIG_PARAM_FIT_JOINT_PRIOR = 412,       /* joint identity prior = this x the subset centroid (default 0: the model mean) */
    FRIG_PARAM_FIT_MEAN_SIZE = 450,         /* 1: fit's and retarget's identity keep the mean face's size (default 0: the identity's own; docs/fit.md) */
    FRIG_PARAM_FIT_OUTLINE_ITERATIONS = 451, /* steps of identity and poses from the photos' outlines (default 16; 0: off) */
    FRIG_PARAM_FIT_OUTLINE_PRIOR = 452,      /* the identity's prior against an outline pixel's error (default 30) */
    FRIG_PARAM_FIT_W_FOCAL = 453,            /* prior log(f / f0)^2 of the focal length (default 10) */
    FRIG_PARAM_FIT_LANDMARK_VERTICES = 454,  /* 1: ICT's nostrils and mouth at the vertices where the detector puts them (default 0: the model's own) */
    FRIG_PARAM_FIT_OUTLINE_BAND = 455,       /* 1: the outline steps read the lower face's outline only, brows to below the chin (default 1; 0: the whole face region) */

    /* synthetic ground truth */
    FRIG_PARAM_SYNTH_MAX_YAW = 500,         /* degrees (default 60) */
    FRIG_PARAM_SYNTH_OFFSET_MM = 501,       /* personal displacement amplitude, mm (default 4) */
    FRIG_PARAM_SYNTH_FAILURE_RATE = 502,    /* share of intended failures (default 0.1) */
    FRIG_PARAM_SYNTH_IMAGE_SIZE = 503,      /* photo side in pixels (default 512) */
    FRIG_PARAM_SYNTH_RIG_OBJ = 504,         /* 1: also write each true rig as OBJ files (default 1) */
    FRIG_PARAM_SYNTH_SHADOWS = 505,         /* share of photos whose key light casts hard shadows (default 0.5) */
    FRIG_PARAM_SYNTH_SPECULAR = 506,        /* strength of the skin's specular highlights, 0 = none (default 1) */
    FRIG_PARAM_SYNTH_ONE_LIGHT = 507,       /* 1: all photos of a subject under one light, as a video's (default 0) */

    /* sfs (section 5.1, Algorithms 4-5; docs/sfs.md) */
    FRIG_PARAM_SFS_FACE_PX = 600,           /* the face's longer side in the crop at most, pixels (default 160) */
    FRIG_PARAM_SFS_ROUNDS = 601,            /* rounds of the shape shared by all photos (default 8) */
    FRIG_PARAM_SFS_ITERATIONS = 602,        /* Gauss-Newton iterations of each photo's depth (default 1) */
    FRIG_PARAM_SFS_W_NORMAL = 604,          /* smoothness of the normals' change (default 1) */
    FRIG_PARAM_SFS_W_ANCHOR = 605,          /* eq. 5.13: depth held to the reference depth (default 1000) */
    FRIG_PARAM_SFS_SIGMA = 606,             /* data residual scale, relative intensity (default 0.02) */
    FRIG_PARAM_SFS_E_MAX = 607,             /* eq. 5.15 E_max, relative intensity error (default 0.07) */
    FRIG_PARAM_SFS_D_MAX = 608,             /* eq. 5.15 d_max, mm from the reference depth (default 5) */
    FRIG_PARAM_SFS_MIN_SKIN = 609,          /* sfs_failed below this share of skin in the face (default 0.3) */
    FRIG_PARAM_SFS_MAX_CLIPPED = 610,       /* sfs_failed above this share of clipped face pixels (default 0.3) */
    FRIG_PARAM_SFS_MIN_LUMA = 611,          /* sfs_failed when the face's median 8-bit luma is below this (default 60) */
    FRIG_PARAM_SFS_MIN_AGREEMENT = 612,     /* sfs_failed below this albedo correlation with the subject's (default 0.1) */
    FRIG_PARAM_SFS_MIN_POINTS = 613,        /* sfs_failed with fewer cloud points (default 500) */
    FRIG_PARAM_SFS_TEXTURE_SIZE = 614,      /* side of the UV albedo texture (default 512) */
    FRIG_PARAM_SFS_POSE = 615,              /* 1: refine each photo's pose against its depth by ICP (default 0) */
    FRIG_PARAM_SFS_TRANSFER = 616,          /* Reinhard colour transfer of the albedo to each photo: 0 off, 1 means, 2 means and spreads (default 0) */
    FRIG_PARAM_SFS_W_PRIOR = 617,           /* normals held to the multi-view shape's normals (default 10) */
    FRIG_PARAM_SFS_SHAPE_SIZE = 618,        /* side of the UV grid of the shape shared by all photos (default 96) */
    FRIG_PARAM_SFS_POSE_LEVELS = 619,       /* each photo's pose registered to the shared shape coarse to fine, levels (default 1; 0 off) */
    FRIG_PARAM_SFS_POSE_SIGMA = 620,        /* the registration's finest blur, pixels at a 160-pixel face (default 2) */
    FRIG_PARAM_SFS_STEREO = 621,            /* the shared shape's multi-view term, the photos' own gradients (default 1; 0 off) */
    FRIG_PARAM_SFS_JOINT_ALBEDO = 622,      /* 1: the shared shape's albedo solved with the displacement (default 1) */
    FRIG_PARAM_SFS_SHAPE_ITERATIONS = 623,  /* Gauss-Newton iterations of the shared shape per round (default 1) */
    FRIG_PARAM_SFS_SHAPE_SIGMA = 624,       /* the shared shape's residual scale, relative intensity (default 0.1) */
    FRIG_PARAM_SFS_JOINT_POSE = 625,        /* shading pose steps per photo after each shared-shape round (default 4) */
    FRIG_PARAM_SFS_JOINT_MIN_PHOTOS = 626,  /* fewer photos: the light shared solve, no registration (default 4; docs/sfs.md) */
    FRIG_PARAM_SFS_JOINT_MAX_PHOTOS = 627,  /* more photos: the light shared solve too, for time (default 120; 0: no limit) */
    FRIG_PARAM_SFS_EXPRESSION_STEPS = 628,  /* each photo's expression steps per full shared round (default 1; 0 off) */
    FRIG_PARAM_SFS_EXPRESSION_PRIOR = 629,  /* refined expression weights held to the fit's (default 0.3) */
    FRIG_PARAM_SFS_EXPRESSION_SPARSE = 630, /* L1 on the refined expression weights (default 0.3) */
    FRIG_PARAM_SFS_CLOUD_REGION = 631,      /* the clouds' pixels: 2 the narrow face, the rest of the face region in
                                               the cloud's margin (default); 1 the narrow face only; 0 all in the cloud */
    FRIG_PARAM_SFS_IDENTITY_MODES = 632,    /* the model's first N identity modes solved with the shared shape, with
                                               frig_sfs_with_model (default 100; 0 off) */
    FRIG_PARAM_SFS_IDENTITY_PRIOR = 633,    /* weight of their prior N(c, I) in the shared solve's energy (default 30) */
    FRIG_PARAM_SFS_JOINT_LIGHT = 634,       /* the photos' lights closer to one axis on the face than this: the
                                             * light shared solve (default 0.95; 1: never; docs/sfs.md) */
    FRIG_PARAM_SFS_IDENTITY_PRIOR_CENTRE = 635, /* c: this share of the fit's identity (default 1; 0: the mean face) */
    FRIG_PARAM_SFS_DISPLACEMENT_HOLD = 636, /* with identity modes, the shared displacement held to zero by this in
                                             * the first half of the rounds, so that the modes take the shape first
                                             * (default 100; 0: the shared solve's anchor, 0.05, throughout) */
    FRIG_PARAM_SFS_HIGHLIGHTS = 637,        /* skin pixels whiter than the photo's skin by more than this many robust
                                             * deviations lose their white part, the highlight (default 2; 0: off) */

    /* identity (frig/identity.h) */
    FRIG_PARAM_IDENTITY_THRESHOLD = 800,    /* a photo whose nearest face is farther is other_person (default 0.5) */
    FRIG_PARAM_IDENTITY_CLUSTER_RADIUS = 801, /* faces this close count as one person when finding the identity */
    FRIG_PARAM_IDENTITY_MIN_DOMINANCE = 802, /* the subject's cluster must hold this many times the photos of the next */
    FRIG_PARAM_IDENTITY_PROTOTYPE = 803,    /* the identity: 0 the cluster's medoid, 1 the mean of its members (default 1) */

    /* frig run: the whole pipeline (docs/run.md) */
    FRIG_PARAM_RUN_VIDEO_FRAMES = 900,      /* frames sampled from each video, evenly spread (default 100) */
    FRIG_PARAM_RUN_MIN_PHOTOS = 901,        /* fewer usable photos stop the run (default 5) */
    FRIG_PARAM_RUN_MIN_CLOUD_SHARE = 902,   /* a smaller share of fitted photos with a point cloud stops the run (0.5) */

    /* export: glTF and OBJ files of a rig */
    FRIG_PARAM_EXPORT_EYE_OVERLAYS = 950,   /* 1: ICT's translucent eye overlays alpha-blended; 0: left out (default 1) */
    FRIG_PARAM_EXPORT_TEXTURE_SIZE = 951,   /* side of the painted eye textures; 0: flat colours (default 512) */

    /* retarget (sections 5.2-5.3, Algorithms 3, 6, 7) */
    FRIG_PARAM_RETARGET_ITERATIONS = 700,        /* outer rounds: refit, clouds, retarget (default 1; the paper runs 3) */
    FRIG_PARAM_RETARGET_INNER_ITERATIONS = 701,  /* Algorithm 6: correspondence, neutral, shapes (default 1) */
    FRIG_PARAM_RETARGET_ALTERNATIONS = 702,      /* blendshapes <-> weights per inner iteration (default 2) */
    FRIG_PARAM_RETARGET_W_DATA = 703,            /* eq. 5.16 w_d (default 1) */
    FRIG_PARAM_RETARGET_W_TRANSFER = 704,        /* eq. 5.16 w_t (default 0.5) */
    FRIG_PARAM_RETARGET_W_PREV_NEUTRAL = 705,    /* eq. 5.16 w_m in the neutral step (default 0.01) */
    FRIG_PARAM_RETARGET_W_PREV_SHAPES = 706,     /* eq. 5.16 w_m in the blendshape step (default 0.25) */
    FRIG_PARAM_RETARGET_MAX_DISTANCE_MM = 707,   /* farther correspondences are rejected (default 10) */
    FRIG_PARAM_RETARGET_MAX_NORMAL_ANGLE = 708,  /* degrees (default 60) */
    FRIG_PARAM_RETARGET_MIN_CONFIDENCE = 709,    /* cloud points below are ignored (default 0.5) */
    FRIG_PARAM_RETARGET_SPACING_MM = 710,        /* clouds thinned to one point per cube this wide (default 4) */
    FRIG_PARAM_RETARGET_SMOOTH_MM = 711,         /* smoothing length of the Laplacian deformation (default 20) */
    FRIG_PARAM_RETARGET_TANGENTIAL = 712,        /* share of a match's tangential offset it pulls by (default 0.25) */
    FRIG_PARAM_RETARGET_WEIGHTS_PRIOR = 713,     /* ridge on the weights' change (default 0.1) */
    FRIG_PARAM_RETARGET_STOP_MM = 714,           /* the outer loop stops when the neutral moves less (default 0.05) */
    FRIG_PARAM_RETARGET_RIGID_ITERATIONS = 715,  /* rigid ICP steps before the deformation (default 2) */
    FRIG_PARAM_RETARGET_DEFORM_ITERATIONS = 716, /* correspondence + deformation rounds (default 4) */
    FRIG_PARAM_RETARGET_IDENTITY_ITERATIONS = 717, /* identity from the clouds first; 0: off (default 5) */
    FRIG_PARAM_RETARGET_LANDMARK_MM = 718,       /* noise of the landmarks lifted onto the clouds; 0: unused (default 0) */
    FRIG_PARAM_RETARGET_SMOOTH_ORDER = 719,      /* 1: membrane, 2: bending energy of the deformation (default 1) */
    FRIG_PARAM_RETARGET_WEIGHTS_SPARSE = 720,    /* L1 on each photo's weights (default 0.2) */
    FRIG_PARAM_RETARGET_CLOUD_SCALE = 721,       /* 1: a cloud's alignment may scale it (default 1) */
    FRIG_PARAM_RETARGET_TRANSFER = 722,          /* E_t: 1 deformation transfer, 0 template deltas (default 0) */
    FRIG_PARAM_RETARGET_ANCHOR_FRAME = 723,      /* 1: each pass keeps the rig in the frame it had (default 1) */
    FRIG_PARAM_RETARGET_MAX_CORRECTION_DEG = 724, /* a cloud needing a larger turn is not used (default 15) */
    FRIG_PARAM_RETARGET_MAX_RMS_MM = 725,        /* a cloud the mesh cannot follow closer is not used (default 1.5) */
    FRIG_PARAM_RETARGET_FIXED_CLOUD_ROUNDS = 726, /* rounds at most when the clouds cannot be recovered (default 1) */
    FRIG_PARAM_RETARGET_IDENTITY_PRIOR = 727,    /* weight of the identity's prior in the identity from the clouds (default 60) */
    FRIG_PARAM_RETARGET_SFS_ITERATIONS = 728,    /* each photo's depth iterations when the loop recovers the clouds (default 2) */
    FRIG_PARAM_RETARGET_SFS_SHAPE_ITERATIONS = 729, /* the shared shape's iterations per round in the loop's recovery (0: sfs's) */
    FRIG_PARAM_RETARGET_LOOP_IDENTITY_ITERATIONS = 730, /* retarget.identity_iterations in the outer rounds after the first */
    FRIG_PARAM_RETARGET_LOOP_DEFORM_ITERATIONS = 731,   /* retarget.deform_iterations in the outer rounds after the first */
    FRIG_PARAM_RETARGET_IDENTITY_SPREAD = 732, /* variance of each cloud's own identity about the shared one (default 0.03) */
    FRIG_PARAM_RETARGET_MARGIN_WEIGHT = 733, /* weight of a cloud's margin points against its own (default 1) */
    FRIG_PARAM_RETARGET_MIN_CLOUDS = 734,    /* with fewer photos with a cloud the rig is left as it is (default 2) */
    FRIG_PARAM_RETARGET_SFS_IDENTITY = 735,  /* 1: start from the identity the clouds were drawn at (sfs's); 0: the rig's (default 1) */
    FRIG_PARAM_RETARGET_RECENTER = 736,      /* quantile of each shape's weights over the photos moved into the neutral (default 0.1; 0: none) */
    FRIG_PARAM_RETARGET_IDENTITY_WEIGHTS_RIDGE = 737, /* the identity fit's ridge on each photo's expression weights, per match (default 0.5) */
    FRIG_PARAM_RETARGET_IDENTITY_PRIOR_CENTRE = 738, /* the identity's prior centred at this share of the pass's start (default 1; 0: the mean face) */
    FRIG_PARAM_RETARGET_SFS_LIGHT = 739 /* 1: the outer loop recovers the clouds with sfs's light shared solve (default 1) */
} frig_param;

FRIG_API frig_status frig_ctx_set_param(frig_ctx *ctx, frig_param param, double value);
/* Returns the parameter's current value, or NaN for an unknown parameter. */
FRIG_API double frig_ctx_get_param(const frig_ctx *ctx, frig_param param);

/* Introspection, for command lines and bindings: parameters by index 0..count-1. */
FRIG_API size_t frig_param_count(void);
FRIG_API frig_param frig_param_at(size_t index);
/* "detect.scale_factor"; NULL for an unknown parameter. */
FRIG_API const char *frig_param_name(frig_param param);
FRIG_API const char *frig_param_help(frig_param param);
FRIG_API double frig_param_default(frig_param param);
/* Find a parameter by its name; FRIG_ERR_INVALID_ARGUMENT (with a message) if unknown. */
FRIG_API frig_status frig_param_lookup(frig_ctx *ctx, const char *name, frig_param *out);

#ifdef __cplusplus
}
#endif

#endif /* FRIG_CORE_H */
