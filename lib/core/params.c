/* The table of enumerated parameters: names, defaults, bounds. Adding an option means
 * adding a row here and a value to enum frig_param; nothing else changes. */
#include <math.h>
#include <string.h>

#include "core/context.h"
#include "core/params.h"

typedef struct param_row {
    frig_param id;
    const char *name;
    double def, lo, hi;
    int integer;
    const char *help;
} param_row;

static const param_row rows[] = {
    {FRIG_PARAM_IMAGE_MAX_PIXELS, "image.max_pixels", 1e8, 1, 1e10, 1,
     "refuse images with more pixels than this, before decoding"},
    {FRIG_PARAM_IMAGE_JPEG_QUALITY, "image.jpeg_quality", 92, 1, 100, 1, "quality of the JPEGs libfrig writes"},

    {FRIG_PARAM_DETECT_SCALE_FACTOR, "detect.scale_factor", 1.1, 1.01, 2.0, 0,
     "step between scales of the face detector's pyramid"},
    {FRIG_PARAM_DETECT_MIN_NEIGHBORS, "detect.min_neighbors", 3, 0, 100, 1,
     "overlapping raw detections needed to keep a face"},
    {FRIG_PARAM_DETECT_MIN_FACE, "detect.min_face", 30, 10, 100000, 1, "smallest face side searched, in pixels"},
    {FRIG_PARAM_DETECT_PROFILE, "detect.profile", 1, 0, 1, 1,
     "1: where the frontal cascade finds no face, run the profile cascade on the photo and its mirror image"},
    {FRIG_PARAM_DETECT_MAX_SIDE, "detect.max_side", 1024, 64, 100000, 1,
     "detect faces on a copy whose longer side is at most this (landmarks use full resolution)"},
    {FRIG_PARAM_DETECT_USER_LANDMARKS, "detect.user_landmarks", 1, 0, 1, 1,
     "1: landmarks in PHOTO.pts or PHOTO.landmarks.json beside a photo replace detection"},
    {FRIG_PARAM_DETECT_MIN_EYE_DISTANCE, "detect.min_eye_distance", 15, 0, 10000, 0,
     "a subject whose outer eye corners are closer than this (pixels) makes the photo face_too_small"},
    {FRIG_PARAM_DETECT_COARSE_SIDE, "detect.coarse_side", 640, 0, 100000, 1,
     "the frontal cascade first searches a copy whose longer side is at most this, and detect.max_side only when "
     "it finds nothing (0: off)"},
    {FRIG_PARAM_DETECT_DUPLICATES, "detect.duplicates", 1, 0, 1, 1,
     "1: a photo whose file has the same bytes as an earlier one is marked duplicate (scraped sets repeat photos)"},

    /* detect with face-api's networks (identity) */
    {FRIG_PARAM_DETECT_DETECTOR, "detect.detector", 0, 0, 2, 1,
     "0: face-api's SSD detector where its weights are installed, else the cascades; 1: the cascades; 2: the SSD "
     "detector (an error when its weights are missing)"},
    {FRIG_PARAM_DETECT_SSD_MIN_SCORE, "detect.ssd_min_score", 0.2, 0.01, 0.99, 0,
     "faces the SSD detector scores above this are kept (the package's default is 0.5; 0.2 finds the small faces of "
     "group photos, and the identity step sets aside what is not the subject)"},
    {FRIG_PARAM_DETECT_LANDMARKS, "detect.landmarks", 1, 1, 3, 1,
     "landmarks on SSD faces: 1 dlib's predictor on its box convention placed by face-api's 68-point net's points, 2 "
     "that net's points, 3 dlib's predictor on the SSD box mapped to dlib's convention (turned faces collapse to a "
     "frontal layout: docs/detect.md)"},
    {FRIG_PARAM_DETECT_NET_TURN, "detect.net_turn", 0.8, 0, 2, 0,
     "with detect.landmarks 1, a face whose nose tip lies this far toward the outline (0 midway, 1 on it: about 40 "
     "degrees of yaw) keeps face-api's net's points, which follow a turned face better than dlib's; above 1: never"},
    {FRIG_PARAM_DETECT_SSD_FALLBACK, "detect.ssd_fallback", 1, 0, 1, 1,
     "1: where the SSD detector finds no face, the cascades search the photo (small faces of web thumbnails; the "
     "identity step marks what is not the subject)"},
    {FRIG_PARAM_DETECT_DESCRIPTORS, "detect.descriptors", 1, 0, 1, 1,
     "1: a 128-D face descriptor for every face found, when face-api's networks are installed (the identity step needs "
     "them)"},

    {FRIG_PARAM_FILTER_OMEGA, "filter.omega", 4.0, 0.1, 100, 0,
     "drop photos with error > mu + omega * sigma (see filter.robust_stats; 4 since 2026-12-07, 3 dropped "
     "expressive and turned photos of the subject: docs/filter.md)"},
    {FRIG_PARAM_FILTER_W_TEXTURE, "filter.w_texture", 1.0, 0, 1e6, 0, "weight of the texture error (w_t)"},
    {FRIG_PARAM_FILTER_W_SHAPE, "filter.w_shape", 0.1, 0, 1e6, 0, "weight of the shape error (w_s)"},
    {FRIG_PARAM_FILTER_MAX_ROUNDS, "filter.max_rounds", 10, 1, 1000, 1, "most rounds of outlier removal"},
    {FRIG_PARAM_FILTER_TEXTURE_SIZE, "filter.texture_size", 64, 16, 512, 1, "side of the warped face texture"},
    {FRIG_PARAM_FILTER_PCA_ENERGY, "filter.pca_energy", 0.98, 0.5, 1.0, 0,
     "share of variance kept by the shape and texture PCA models"},
    {FRIG_PARAM_FILTER_SCORE_ALL, "filter.score_all", 0, 0, 1, 1,
     "1: each round's model of the inliers scores every photo, centre and spread over all of them, so a small set "
     "is not peeled round after round and a dropped photo can return; 0: Algorithm 1 as printed"},
    {FRIG_PARAM_FILTER_MIRROR, "filter.mirror", 1, 0, 1, 1,
     "1: the shape model is built from the inliers and their mirror images (a face turned left looks like one "
     "turned right, mirrored), so the few photos turned the less common way are not dropped for their pose; 0: "
     "the inliers alone, as in the paper"},
    {FRIG_PARAM_FILTER_ROBUST_STATS, "filter.robust_stats", 1, 0, 1, 1,
     "1: mu and sigma are the median and 1.4826 x MAD of the errors; 0: their mean and standard deviation"},
    {FRIG_PARAM_FILTER_PEEL_MIN_FACES, "filter.peel_min_faces", 12, 3, 100000, 1,
     "rounds after the first run only while at least this many photos are inliers: a model rebuilt from fewer "
     "explains too little, and its later rounds drop mostly good photos (3: Algorithm 1 as printed)"},

    {FRIG_PARAM_FIT_W_EXP, "fit.w_exp", 10, 0, 1e6, 0, "weight of the expression prior (eq. 4.8 w2)"},
    {FRIG_PARAM_FIT_W_SPARSE, "fit.w_sparse", 100, 0, 1e6, 0, "weight of the L1 expression sparsity (eq. 4.8 w3)"},
    {FRIG_PARAM_FIT_W_ID, "fit.w_id", 20, 0, 1e6, 0, "weight of the identity prior (eq. 4.8 w1)"},
    {FRIG_PARAM_FIT_ROUNDS, "fit.rounds", 3, 1, 20, 1, "rounds of progressive reconstruction"},
    {FRIG_PARAM_FIT_SUBSET_FIRST, "fit.subset_first", 0.4, 0.01, 1, 0, "fraction of photos in the first joint fit"},
    {FRIG_PARAM_FIT_SUBSET_STEP, "fit.subset_step", 0.2, 0, 1, 0, "fraction added in each later round"},
    {FRIG_PARAM_FIT_SCORE_W_ID, "fit.score_w_id", 1.0, 0, 1e6, 0, "weight of identity fitness in the ranking"},
    {FRIG_PARAM_FIT_SCORE_W_TEX, "fit.score_w_tex", 10.0, 0, 1e6, 0,
     "weight of photo-consistency in the ranking"},
    {FRIG_PARAM_FIT_IDENTITY_MODES, "fit.identity_modes", 100, 0, 1000, 1, "identity modes fitted"},
    {FRIG_PARAM_FIT_ITERATIONS, "fit.iterations", 20, 1, 1000, 1, "Levenberg-Marquardt iterations per photo fit"},
    {FRIG_PARAM_FIT_PERSPECTIVE, "fit.perspective", 1, 0, 1, 1,
     "1: perspective camera with fitted focal length; 0: weak perspective"},
    {FRIG_PARAM_FIT_CONTOUR_WEIGHT, "fit.contour_weight", 0.25, 0, 1, 0,
     "weight of the jaw landmarks 0-16 (a detector's jaw points err twice as much as the others)"},
    {FRIG_PARAM_FIT_JOINT_PRIOR, "fit.joint_prior", 0, 0, 1, 0,
     "joint identity prior: this fraction of the selected photos' mean identity (1: the paper; 0: the model mean)"},
    {FRIG_PARAM_FIT_MEAN_SIZE, "fit.mean_size", 0, 0, 1, 1,
     "0: the size is the identity's (the model ties a head's size to its shape, which the outlines of the lower "
     "face fix: follows synthetic subjects' true size); 1: the identity keeps the mean face's size, in the fit's "
     "joint identity and retarget's identity from the clouds (docs/fit.md \"The head's size\")"},
    {FRIG_PARAM_FIT_OUTLINE_ITERATIONS, "fit.outline_iterations", 16, 0, 50, 1,
     "Gauss-Newton steps of the identity and every photo's pose from the photos' outlines (where the head is "
     "seen edge-on against the background) after the landmark fit; 0: off"},
    {FRIG_PARAM_FIT_OUTLINE_PRIOR, "fit.outline_prior", 30, 0.01, 1e6, 0,
     "weight of the identity's prior N(0, I) in the outline steps, against one outline pixel's error of a pixel"},
    {FRIG_PARAM_FIT_W_FOCAL, "fit.w_focal", 10, 0, 1e9, 0,
     "weight of the focal length's prior log(f / f0)^2 (f0: 1.4 times the photo's longer side, a 50 mm lens)"},
    {FRIG_PARAM_FIT_LANDMARK_VERTICES, "fit.landmark_vertices", 0, 0, 1, 1,
     "1: with ICT-FaceKit's model, the nostrils' wings and the mouth (iBUG 31-35, 48-67) are matched to the vertices "
     "where the landmark detector puts them (measured on synthetic photos, docs/fit.md); 0: to the model's own"},
    {FRIG_PARAM_FIT_OUTLINE_BAND, "fit.outline_band", 1, 0, 1, 1,
     "1: the outline steps read the face's outline from the brows' height to a little below the chin (in photos "
     "hair covers the forehead and temples, and its edges made the faces small); 0: the whole face region's "
     "outline, forehead and scalp too (renders without hair)"},

    {FRIG_PARAM_SYNTH_MAX_YAW, "synth.max_yaw", 60, 0, 90, 0, "largest head yaw of synthetic photos, degrees"},
    {FRIG_PARAM_SYNTH_OFFSET_MM, "synth.offset_mm", 4, 0, 50, 0,
     "RMS over the face of a synthetic subject's personal displacement before its in-span part is removed, mm"},
    {FRIG_PARAM_SYNTH_FAILURE_RATE, "synth.failure_rate", 0.1, 0, 1, 0,
     "share of synthetic photos that are intended failures"},
    {FRIG_PARAM_SYNTH_IMAGE_SIZE, "synth.image_size", 512, 64, 8192, 1, "side of synthetic photos, pixels"},
    {FRIG_PARAM_SYNTH_RIG_OBJ, "synth.rig_obj", 1, 0, 1, 1,
     "1: write each synthetic subject's true rig as OBJ files too (about 150 MB a subject)"},
    {FRIG_PARAM_SYNTH_SHADOWS, "synth.shadows", 0.5, 0, 1, 0,
     "share of synthetic photos whose key light casts hard shadows (nose, brows, jaw on the neck)"},
    {FRIG_PARAM_SYNTH_SPECULAR, "synth.specular", 1, 0, 10, 0,
     "strength of synthetic skin's specular highlights relative to the default (0: matte skin)"},
    {FRIG_PARAM_SYNTH_ONE_LIGHT, "synth.one_light", 0, 0, 1, 1,
     "1: every photo of a subject under the same light (direction, ambient, colour and exposure), as the frames of "
     "a video under one lamp; 0: a light of its own per photo"},


    /* sfs (docs/sfs.md) */
    {FRIG_PARAM_SFS_FACE_PX, "sfs.face_px", 128, 16, 4096, 1,
     "shape from shading works on a crop whose face (longer side) is at most this many pixels"},
    {FRIG_PARAM_SFS_ROUNDS, "sfs.rounds", 8, 0, 20, 1,
     "rounds of the shape shared by all photos (albedo, displacement, lighting; Algorithm 4's outer loop); 0: none"},
    {FRIG_PARAM_SFS_ITERATIONS, "sfs.iterations", 1, 1, 100, 1, "Gauss-Newton iterations of each photo's depth"},
    {FRIG_PARAM_SFS_W_NORMAL, "sfs.w_normal", 1, 0, 1e9, 0,
     "weight keeping the change of the normals smooth (second differences of the depth correction)"},
    {FRIG_PARAM_SFS_W_ANCHOR, "sfs.w_anchor", 1000, 0, 1e9, 0,
     "eq. 5.13: weight holding each photo's depth to its reference (the rig with the shared shape; per pixel, depth "
     "in pixels)"},
    {FRIG_PARAM_SFS_SIGMA, "sfs.sigma", 0.02, 1e-4, 1, 0,
     "relative intensity error of one standard deviation in the data term"},
    {FRIG_PARAM_SFS_E_MAX, "sfs.e_max", 0.07, 0, 10, 0,
     "eq. 5.15 E_max: pixels with a larger relative shading error are left out of the cloud"},
    {FRIG_PARAM_SFS_D_MAX, "sfs.d_max", 5, 0, 1000, 0,
     "eq. 5.15 d_max: pixels whose depth moved more than this many mm from the reference are left out"},
    {FRIG_PARAM_SFS_MIN_SKIN, "sfs.min_skin", 0.3, 0, 1, 0,
     "a photo whose face region is less skin than this share is sfs_failed"},
    {FRIG_PARAM_SFS_MAX_CLIPPED, "sfs.max_clipped", 0.3, 0, 1, 0,
     "a photo with more clipped (over-exposed) face pixels than this share is sfs_failed"},
    {FRIG_PARAM_SFS_MIN_LUMA, "sfs.min_luma", 60, 0, 255, 0,
     "a photo whose face's median 8-bit luma is below this is under-exposed (no shading to read): sfs_failed"},
    {FRIG_PARAM_SFS_MIN_AGREEMENT, "sfs.min_agreement", 0.1, -1, 1, 0,
     "a photo whose luminance rank-correlates less than this with what the subject's albedo and its lighting "
     "predict is sfs_failed"},
    {FRIG_PARAM_SFS_MIN_POINTS, "sfs.min_points", 500, 0, 1e9, 1, "a photo with fewer cloud points is sfs_failed"},
    {FRIG_PARAM_SFS_TEXTURE_SIZE, "sfs.texture_size", 0, 0, 8192, 1,
     "side of the subject's albedo texture in the model's UV space (textures/albedo.png); 0: the power of two at "
     "or above twice sfs.face_px (256 at the default 128), as fine as the photos' crops it is drawn from; at least 64"},
    {FRIG_PARAM_SFS_POSE, "sfs.pose", 0, 0, 1, 1,
     "1: refine each photo's head pose against its recovered depth by ICP after the shared solve's registration "
     "(0: the registration's pose; measured on 17 synth subjects, ICP made the rotations and the clouds worse)"},
    {FRIG_PARAM_SFS_TRANSFER, "sfs.transfer", 0, 0, 2, 1,
     "Reinhard colour transfer of the subject's albedo to each photo: 0 off (best measured on synthetic subjects), "
     "1 the l-alpha-beta means, 2 means and spreads"},
    {FRIG_PARAM_SFS_W_PRIOR, "sfs.w_prior", 10, 0, 1e9, 0,
     "weight holding each photo's normals to those of the shape recovered from all photos"},
    {FRIG_PARAM_SFS_SHAPE_SIZE, "sfs.shape_size", 96, 16, 2048, 1,
     "side of the UV grid on which the shape shared by all photos is solved (texels of the model's face layout)"},
    {FRIG_PARAM_SFS_POSE_LEVELS, "sfs.pose_levels", 1, 0, 6, 1,
     "each photo's pose registered to the shared shape and albedo, coarse to fine, with this many blur levels "
     "(photometric and occluding-contour terms; 0: the fit's poses)"},
    {FRIG_PARAM_SFS_POSE_SIGMA, "sfs.pose_sigma", 2, 0.5, 32, 0,
     "the pose registration's finest blur, pixels for a face 160 pixels long (each coarser level doubles it)"},
    {FRIG_PARAM_SFS_STEREO, "sfs.stereo", 1, 0, 100, 0,
     "weight of the shared shape's multi-view term (each photo's own image gradient along a texel's path; 0 off)"},
    {FRIG_PARAM_SFS_JOINT_ALBEDO, "sfs.joint_albedo", 1, 0, 1, 1,
     "1: the shared shape's texel albedo solved with the displacement (Schur complement), 0: alternated"},
    {FRIG_PARAM_SFS_SHAPE_ITERATIONS, "sfs.shape_iterations", 1, 1, 100, 1,
     "Gauss-Newton iterations of the shared shape per round (the light solve takes 4)"},
    {FRIG_PARAM_SFS_SHAPE_SIGMA, "sfs.shape_sigma", 0.1, 1e-3, 1, 0,
     "the shared shape's residual scale, relative intensity of one standard deviation"},
    {FRIG_PARAM_SFS_JOINT_POSE, "sfs.joint_pose", 4, 0, 50, 1,
     "Levenberg-Marquardt steps of each photo's pose against the shared shape's shading after each round (0 off)"},
    {FRIG_PARAM_SFS_JOINT_MIN_PHOTOS, "sfs.joint_min_photos", 4, 0, 1e6, 1,
     "with fewer photos to judge than this, the shared shape is solved the light way (albedo alternated, no multi-view "
     "term, no pose registration, at most 3 rounds of 4 iterations each); the full solve was better down to 4 photos "
     "judged on frig synth subjects (docs/sfs.md); 0: never"},
    {FRIG_PARAM_SFS_JOINT_MAX_PHOTOS, "sfs.joint_max_photos", 120, 0, 1e6, 1,
     "with more photos to judge than this, the light shared solve too, for time: the full one's cost grows with the "
     "photos (a 100-photo frig synth subject: 33 CPU s against 18 for the stage, frig run 42 s on 2 cores); 0: no limit"},
    {FRIG_PARAM_SFS_EXPRESSION_STEPS, "sfs.expression_steps", 1, 0, 50, 1,
     "Gauss-Newton steps of each photo's expression weights against its own shading and image gradients after each "
     "round of the full shared solve (the rig at the weights plus the shared displacement; the light solve keeps the fit's; "
     "0: the fit's weights everywhere)"},
    {FRIG_PARAM_SFS_EXPRESSION_PRIOR, "sfs.expression_prior", 0.3, 0, 1e6, 0,
     "weight of the refined expression weights' prior toward the fit's (per squared weight, against the mean robust "
     "shading energy per texel)"},
    {FRIG_PARAM_SFS_EXPRESSION_SPARSE, "sfs.expression_sparse", 0.3, 0, 1e6, 0,
     "weight of the L1 sparsity of the refined expression weights (against the mean robust shading energy per texel)"},
    {FRIG_PARAM_SFS_CLOUD_REGION, "sfs.cloud_region", 2, 0, 2, 1,
     "the pixels a cloud may keep: 1 the narrow face (no neck, ears or scalp: their points were 1.5-2.3 mm off, twice "
     "the rest, and pulled every cloud's alignment), 2 the same with the rest written as the cloud's margin "
     "(clouds/margin/, read by retarget), 0 the whole face region the skin model judges"},
    {FRIG_PARAM_SFS_IDENTITY_MODES, "sfs.identity_modes", 100, 0, 1000, 1,
     "the model's first N identity modes solved with the shared shape from the fit's identity, so that the face may "
     "move along its surface as well as across it (frig_sfs_with_model; frig sfs --model; 0 off)"},
    {FRIG_PARAM_SFS_IDENTITY_PRIOR, "sfs.identity_prior", 30, 0, 1e9, 0,
     "weight of the identity weights' prior |w - c|^2 (standard deviations; c set by sfs.identity_prior_centre) "
     "against the shared solve's robust energy"},
    {FRIG_PARAM_SFS_IDENTITY_PRIOR_CENTRE, "sfs.identity_prior_centre", 1, 0, 1, 0,
     "the shared solve's identity prior is centred at this share of the fit's identity: 1 the fit's (its landmarks "
     "and outlines placed the face's features along the surface, which shading and stereo cannot see), 0 the "
     "mean face"},
    {FRIG_PARAM_SFS_DISPLACEMENT_HOLD, "sfs.displacement_hold", 100, 0, 1e6, 0,
     "with the identity's modes (sfs.identity_modes), weight holding the shared displacement to zero (per texel, "
     "mm^2) in the first half of the shared solve's rounds, so that the modes make the shape first and the "
     "displacement only what they cannot in the later rounds (0.05 there); 0: 0.05 in every round"},
    {FRIG_PARAM_SFS_HIGHLIGHTS, "sfs.highlights", 2, 0, 100, 0,
     "specular highlights taken out of each photo's skin pixels before the stage reads them: a pixel whose white "
     "share (the dichromatic model: the skin's chroma plus white) lies more than this many robust standard "
     "deviations above the photo's median share loses its white part; 0: the pixels as they are"},
    {FRIG_PARAM_SFS_JOINT_LIGHT, "sfs.joint_light", 0.95, 0, 1, 0,
     "when the photos' lights, turned into the head's frame, are closer to one axis than this (the largest "
     "eigenvalue of the mean outer product of their directions; 1 = one axis, as frames of a video under one "
     "lamp without turns), the light shared solve runs: the full one takes the face's colours for its shape there"},

    /* identity */
    {FRIG_PARAM_IDENTITY_THRESHOLD, "identity.threshold", 0.5, 0.05, 2, 0,
     "a photo whose face nearest the subject's identity is farther than this (descriptor distance) is other_person"},
    {FRIG_PARAM_IDENTITY_CLUSTER_RADIUS, "identity.cluster_radius", 0.5, 0.05, 2, 0,
     "faces closer than this count as the same person when the dominant identity is sought"},
    {FRIG_PARAM_IDENTITY_PROTOTYPE, "identity.prototype", 1, 0, 1, 1,
     "the subject's identity: 0 the medoid of the dominant cluster, 1 the mean of that cluster's members (one face "
     "per photo within identity.cluster_radius of the medoid: strangers are not in it)"},
    {FRIG_PARAM_IDENTITY_MIN_DOMINANCE, "identity.min_dominance", 1.5, 1, 100, 0,
     "the subject's cluster must hold at least this many times the photos of the next person's, else the set has "
     "no dominant identity and the step stops"},

    /* run (frig run, docs/run.md) */
    {FRIG_PARAM_RUN_VIDEO_FRAMES, "run.video_frames", 100, 1, 100000, 1,
     "frames frig run samples from each video file, evenly spread over it (ffmpeg)"},
    {FRIG_PARAM_RUN_MIN_PHOTOS, "run.min_photos", 5, 1, 100000, 1,
     "frig run stops when fewer photos than this are usable (the paper's smallest set had 5)"},
    {FRIG_PARAM_RUN_MIN_CLOUD_SHARE, "run.min_cloud_share", 0.5, 0, 1, 0,
     "frig run stops after sfs when a smaller share of the fitted photos kept a point cloud (their shading does not "
     "read as a face's: not a set of one person's photos); 0: never"},

    /* export (glTF and OBJ writers) */
    {FRIG_PARAM_EXPORT_EYE_OVERLAYS, "export.eye_overlays", 1, 0, 1, 1,
     "1: export ICT's translucent eye overlays (tear film, eye blend, eye occlusion) alpha-blended; 0: leave them out"},
    {FRIG_PARAM_EXPORT_TEXTURE_SIZE, "export.texture_size", 512, 0, 4096, 1,
     "side in pixels of the sclera, iris and eye-overlay textures libfrig paints; 0: flat colours"},

    /* retarget (sections 5.2-5.3) */
    {FRIG_PARAM_RETARGET_ITERATIONS, "retarget.iterations", 1, 1, 20, 1,
     "rounds of the outer loop (section 5.3): refit every photo on the rig, recover the clouds, retarget "
     "(the paper runs 3; 1 measured best with today's clouds: docs/retarget.md)"},
    {FRIG_PARAM_RETARGET_INNER_ITERATIONS, "retarget.inner_iterations", 1, 1, 20, 1,
     "rounds of Algorithm 6 per retarget: correspondences, neutral, blendshapes and weights"},
    {FRIG_PARAM_RETARGET_ALTERNATIONS, "retarget.alternations", 2, 1, 20, 1,
     "alternations of blendshapes and weights (section 5.2.3) per round"},
    {FRIG_PARAM_RETARGET_W_DATA, "retarget.w_data", 1, 1e-6, 1e6, 0, "eq. 5.16 w_d: the corresponded meshes"},
    {FRIG_PARAM_RETARGET_W_TRANSFER, "retarget.w_transfer", 0.5, 0, 1e6, 0,
     "eq. 5.16 w_t: the template's expressions transferred onto the neutral"},
    {FRIG_PARAM_RETARGET_W_PREV_NEUTRAL, "retarget.w_prev_neutral", 0.01, 1e-9, 1e6, 0,
     "eq. 5.16 w_m in the neutral step: the previous neutral"},
    {FRIG_PARAM_RETARGET_W_PREV_SHAPES, "retarget.w_prev_shapes", 0.25, 0, 1e6, 0,
     "eq. 5.16 w_m in the blendshape step: the previous blendshapes"},
    {FRIG_PARAM_RETARGET_MAX_DISTANCE_MM, "retarget.max_distance_mm", 10, 0.1, 1000, 0,
     "correspondences farther than this (mm) are rejected"},
    {FRIG_PARAM_RETARGET_MAX_NORMAL_ANGLE, "retarget.max_normal_angle", 60, 1, 180, 0,
     "correspondences whose normals differ more (degrees) are rejected"},
    {FRIG_PARAM_RETARGET_MIN_CONFIDENCE, "retarget.min_confidence", 0.5, 0, 1, 0,
     "cloud points of lower confidence are not used"},
    {FRIG_PARAM_RETARGET_SPACING_MM, "retarget.spacing_mm", 4, 0.1, 100, 0,
     "clouds are thinned to one point per cube this wide (mm)"},
    {FRIG_PARAM_RETARGET_SMOOTH_MM, "retarget.smooth_mm", 20, 0.1, 1000, 0,
     "smoothing length of the Laplacian deformation toward a cloud (mm)"},
    {FRIG_PARAM_RETARGET_TANGENTIAL, "retarget.tangential", 0.25, 0, 1, 0,
     "share of a correspondence's offset along the surface it pulls by (0: point-to-plane, 1: point-to-point)"},
    {FRIG_PARAM_RETARGET_WEIGHTS_PRIOR, "retarget.weights_prior", 0.1, 0, 1e6, 0,
     "ridge on the change of a photo's weights, per observed vertex and mm^2"},
    {FRIG_PARAM_RETARGET_STOP_MM, "retarget.stop_mm", 0.05, 0, 100, 0,
     "the outer loop stops when a round moves the neutral less than this (mean over the face, mm)"},
    {FRIG_PARAM_RETARGET_RIGID_ITERATIONS, "retarget.rigid_iterations", 2, 0, 100, 1,
     "rigid alignment steps of each cloud before the deformation"},
    {FRIG_PARAM_RETARGET_DEFORM_ITERATIONS, "retarget.deform_iterations", 4, 1, 100, 1,
     "rounds of correspondence and Laplacian deformation per cloud"},
    {FRIG_PARAM_RETARGET_IDENTITY_ITERATIONS, "retarget.identity_iterations", 5, 0, 100, 1,
     "steps of the model's identity fitted to all clouds before the correspondences (beyond the paper; 0: off)"},
    {FRIG_PARAM_RETARGET_LANDMARK_MM, "retarget.landmark_mm", 0, 0, 1000, 0,
     "the identity fit also pulls the model's landmark vertices to the photos' landmarks lifted onto the clouds, "
     "with this noise (mm; 0: not used)"},
    {FRIG_PARAM_RETARGET_SMOOTH_ORDER, "retarget.smooth_order", 1, 1, 2, 1,
     "smoothness of the deformation toward a cloud: 1 the membrane (squared gradient), 2 the bending energy "
     "(squared Laplacian, nine times the factorization work)"},
    {FRIG_PARAM_RETARGET_WEIGHTS_SPARSE, "retarget.weights_sparse", 0.2, 0, 1e6, 0,
     "L1 sparsity of each photo's expression weights, per observed vertex and mm^2"},
    {FRIG_PARAM_RETARGET_CLOUD_SCALE, "retarget.cloud_scale", 1, 0, 1, 1,
     "1: aligning a cloud to its reconstruction may also scale it (a cloud has the size its photo's fitted "
     "focal length and distance give it); 0: rotation and translation only"},
    {FRIG_PARAM_RETARGET_TRANSFER, "retarget.transfer", 0, 0, 1, 1,
     "the retargeting term's target for each blendshape: 1 the template's expression moved onto the neutral by "
     "deformation transfer (the paper), 0 the template's deltas vertex by vertex"},
    {FRIG_PARAM_RETARGET_ANCHOR_FRAME, "retarget.anchor_frame", 1, 0, 2, 1,
     "1: after each pass the rig is moved back rigidly to the frame it had (the clouds' alignments leave the frame "
     "free); 2: to the frame of the model at the identity the clouds gave; 0: the clouds' frame (for clouds in a "
     "known true frame)"},
    {FRIG_PARAM_RETARGET_MAX_CORRECTION_DEG, "retarget.max_correction_deg", 15, 0, 180, 0,
     "a cloud that must be turned more than this (degrees) to fit its photo's reconstruction is not used: it "
     "shows another surface (a wrong pose, a failed sfs)"},
    {FRIG_PARAM_RETARGET_MAX_RMS_MM, "retarget.max_rms_mm", 1.5, 0, 1000, 0,
     "a cloud whose matched points stay farther than this (RMS, mm) from the deformed mesh is not used"},
    {FRIG_PARAM_RETARGET_FIXED_CLOUD_ROUNDS, "retarget.fixed_cloud_rounds", 1, 1, 20, 1,
     "outer rounds at most when the clouds cannot be recovered with the new rig (no sfs stage in the loop): later "
     "rounds only refit the poses, and with the same clouds they fit the clouds' noise again"},
    {FRIG_PARAM_RETARGET_IDENTITY_PRIOR, "retarget.identity_prior", 60, 0.01, 1e6, 0,
     "weight of the prior on the identity fitted to the clouds (the model's N(c, I), c set by "
     "retarget.identity_prior_centre), against matches weighed at 1 mm each (s^2 weighs them at s mm)"},
    {FRIG_PARAM_RETARGET_IDENTITY_PRIOR_CENTRE, "retarget.identity_prior_centre", 1, 0, 1, 0,
     "the identity fit's prior is centred at this share of the identity the pass starts from: 1 the identity the sfs "
     "stage drew the clouds at (which the fit's landmarks and the photos' pixels placed), so that the clouds move "
     "it only where their surfaces show it wrong; 0 the mean face"},
    {FRIG_PARAM_RETARGET_MARGIN_WEIGHT, "retarget.margin_weight", 1, 0, 1, 0,
     "weight of each cloud's margin points (neck, ears, scalp: sfs.cloud_region 2) in the matches, against the "
     "cloud's own points (0: the margin unused)"},
    {FRIG_PARAM_RETARGET_MIN_CLOUDS, "retarget.min_clouds", 2, 1, 1000000, 1,
     "with fewer photos with a point cloud, frig_retarget_refine leaves the rig as it is (measured: one cloud makes "
     "the neutral worse than the fit's, docs/retarget.md)"},
    {FRIG_PARAM_RETARGET_SFS_IDENTITY, "retarget.sfs_identity", 1, 0, 1, 1,
     "1: the pass starts from the identity the sfs stage drew the clouds at (the fit's with the change its shared "
     "solve found; the rig's neutral moved by the modes' offset); 0: from the rig as it is"},
    {FRIG_PARAM_RETARGET_IDENTITY_WEIGHTS_RIDGE, "retarget.identity_weights_ridge", 0.5, 0, 1e6, 0,
     "in the identity fit to the clouds, the cost of a photo's expression weight of 1 per match, in units of a match's "
     "squared 1 mm residual: how much each photo's weights may explain its cloud before the shared identity does (a "
     "shape every photo shows, such as a longer chin read as jawOpen, is then the identity's)"},
    {FRIG_PARAM_RETARGET_RECENTER, "retarget.recenter", 0.1, 0, 0.5, 0,
     "each fitted expression's weight that this share of the photos exceeds (a low quantile over the photos) is "
     "moved into the neutral before the pass: a weight every photo shows is the person's face, not an expression "
     "(0: none)"},
    {FRIG_PARAM_RETARGET_IDENTITY_SPREAD, "retarget.identity_spread", 0.03, 0, 100, 0,
     "variance (in the model's identity units) of the identity each cloud shows about the shared one: a cloud's "
     "errors are smooth and shared by its points, so each photo's say on the shared identity is capped (0: "
     "every match counts as independent)"},
    {FRIG_PARAM_RETARGET_SFS_ITERATIONS, "retarget.sfs_iterations", 0, 0, 100, 1,
     "Gauss-Newton iterations of each photo's depth when the outer loop recovers the clouds with the new rig "
     "(0: the sfs stage's own sfs.iterations)"},
    {FRIG_PARAM_RETARGET_SFS_LIGHT, "retarget.sfs_light", 1, 0, 1, 1,
     "1: the outer loop recovers the clouds with sfs's light shared solve (no registration, identity modes or "
     "expression steps; measured: the rounds after the first come out the same as with the full solve, in 40% of its "
     "time); 0: the solve the sfs stage would take"},
    {FRIG_PARAM_RETARGET_SFS_SHAPE_ITERATIONS, "retarget.sfs_shape_iterations", 0, 0, 100, 1,
     "Gauss-Newton iterations per round of the shape shared by all photos when the outer loop recovers the clouds "
     "(0: the sfs stage's own, sfs.shape_iterations); fewer are faster (2: 0.7 CPU s less per recovery of 91 photos) but measured worse "
     "on a frig synth subject (neutral after round 3 4.479 mm against 4.389: docs/retarget.md)"},
    {FRIG_PARAM_RETARGET_LOOP_IDENTITY_ITERATIONS, "retarget.loop_identity_iterations", -1, -1, 100, 1,
     "iterations of the identity from the clouds in the outer rounds after the first (-1: retarget.identity_iterations); "
     "1 saves 1.2 CPU s per round on 91 photos but measured worse (neutral after round 3 4.484 mm against 4.389)"},
    {FRIG_PARAM_RETARGET_LOOP_DEFORM_ITERATIONS, "retarget.loop_deform_iterations", 0, 0, 100, 1,
     "correspondence + deformation rounds per photo in the outer rounds after the first (0: "
     "retarget.deform_iterations); 3 saves 0.9 CPU s per round on 91 photos but measured worse (neutral after "
     "round 3 4.447 mm against 4.389)"},
};

#define N_ROWS (sizeof rows / sizeof rows[0])
_Static_assert(N_ROWS <= FR_PARAM_MAX, "raise FR_PARAM_MAX");

static int row_of(frig_param p) {
    for (size_t i = 0; i < N_ROWS; i++)
        if (rows[i].id == p) return (int)i;
    return -1;
}

void fr_params_init(double *values) {
    for (size_t i = 0; i < N_ROWS; i++) values[i] = rows[i].def;
}

size_t frig_param_count(void) { return N_ROWS; }
frig_param frig_param_at(size_t index) { return index < N_ROWS ? rows[index].id : (frig_param)-1; }

const char *frig_param_name(frig_param p) {
    int r = row_of(p);
    return r < 0 ? NULL : rows[r].name;
}

const char *frig_param_help(frig_param p) {
    int r = row_of(p);
    return r < 0 ? NULL : rows[r].help;
}

double frig_param_default(frig_param p) {
    int r = row_of(p);
    return r < 0 ? NAN : rows[r].def;
}

frig_status frig_param_lookup(frig_ctx *ctx, const char *name, frig_param *out) {
    if (!name || !out) return ctx ? fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "no parameter name given")
                                  : FRIG_ERR_INVALID_ARGUMENT;
    for (size_t i = 0; i < N_ROWS; i++)
        if (strcmp(rows[i].name, name) == 0) {
            *out = rows[i].id;
            return FRIG_OK;
        }
    return ctx ? fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "unknown parameter '%s' (frig help params lists them)",
                          name)
               : FRIG_ERR_INVALID_ARGUMENT;
}

frig_status frig_ctx_set_param(frig_ctx *ctx, frig_param p, double value) {
    if (!ctx) return FRIG_ERR_INVALID_ARGUMENT;
    int r = row_of(p);
    if (r < 0) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "unknown parameter number %d", (int)p);
    const param_row *row = &rows[r];
    if (!(value >= row->lo && value <= row->hi))
        return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "parameter %s = %g is outside [%g, %g]", row->name, value,
                        row->lo, row->hi);
    if (row->integer && value != floor(value))
        return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "parameter %s must be a whole number, not %g", row->name,
                        value);
    ctx->params[r] = value;
    return FRIG_OK;
}

double frig_ctx_get_param(const frig_ctx *ctx, frig_param p) {
    int r = row_of(p);
    if (r < 0) return NAN;
    return ctx ? ctx->params[r] : rows[r].def;
}

double fr_param(const frig_ctx *ctx, frig_param p) { return frig_ctx_get_param(ctx, p); }
int fr_param_int(const frig_ctx *ctx, frig_param p) { return (int)lround(frig_ctx_get_param(ctx, p)); }
