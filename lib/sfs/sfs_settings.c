/* The sfs.* parameters of a context as the stage's settings (docs/sfs.md). */
#include "core/context.h"
#include "model/model.h"
#include "sfs/sfs.h"
#include "workspace/photoset.h"

/* sfs.texture_size, where 0 asks for the power of two at or above twice the face's crop size
 * (the texture holds no more than the crops it is drawn from: docs/sfs.md, "The albedo texture's
 * size"), at least 64. */
static int texture_side(int asked, double face_px) {
    if (asked > 0) return asked < 64 ? 64 : asked;
    int side = 64;
    while (side < 2 * face_px && side < 8192) side *= 2;
    return side;
}

void fr_sfs_settings_from_ctx(const frig_ctx *ctx, fr_sfs_settings *s) {
    s->face_px = fr_param(ctx, FRIG_PARAM_SFS_FACE_PX);
    s->rounds = fr_param_int(ctx, FRIG_PARAM_SFS_ROUNDS);
    s->iterations = fr_param_int(ctx, FRIG_PARAM_SFS_ITERATIONS);
    s->w_normal = fr_param(ctx, FRIG_PARAM_SFS_W_NORMAL);
    s->w_anchor = fr_param(ctx, FRIG_PARAM_SFS_W_ANCHOR);
    s->w_prior = fr_param(ctx, FRIG_PARAM_SFS_W_PRIOR);
    s->sigma = fr_param(ctx, FRIG_PARAM_SFS_SIGMA);
    s->e_max = fr_param(ctx, FRIG_PARAM_SFS_E_MAX);
    s->d_max_mm = fr_param(ctx, FRIG_PARAM_SFS_D_MAX);
    s->min_skin = fr_param(ctx, FRIG_PARAM_SFS_MIN_SKIN);
    s->max_clipped = fr_param(ctx, FRIG_PARAM_SFS_MAX_CLIPPED);
    s->min_luma = fr_param(ctx, FRIG_PARAM_SFS_MIN_LUMA);
    s->min_agreement = fr_param(ctx, FRIG_PARAM_SFS_MIN_AGREEMENT);
    s->min_points = fr_param_int(ctx, FRIG_PARAM_SFS_MIN_POINTS);
    s->texture_size = texture_side(fr_param_int(ctx, FRIG_PARAM_SFS_TEXTURE_SIZE), s->face_px);
    s->shape_size = fr_param_int(ctx, FRIG_PARAM_SFS_SHAPE_SIZE);
    s->pose = fr_param_int(ctx, FRIG_PARAM_SFS_POSE);
    s->transfer = fr_param_int(ctx, FRIG_PARAM_SFS_TRANSFER);
    s->w_stereo = fr_param(ctx, FRIG_PARAM_SFS_STEREO);
    s->pose_steps = fr_param_int(ctx, FRIG_PARAM_SFS_JOINT_POSE);
    s->joint_albedo = fr_param_int(ctx, FRIG_PARAM_SFS_JOINT_ALBEDO);
    s->shape_iterations = fr_param_int(ctx, FRIG_PARAM_SFS_SHAPE_ITERATIONS);
    s->shape_sigma = fr_param(ctx, FRIG_PARAM_SFS_SHAPE_SIGMA);
    s->pose_levels = fr_param_int(ctx, FRIG_PARAM_SFS_POSE_LEVELS);
    s->pose_sigma_px = fr_param(ctx, FRIG_PARAM_SFS_POSE_SIGMA);
    s->joint_min_photos = fr_param_int(ctx, FRIG_PARAM_SFS_JOINT_MIN_PHOTOS);
    s->joint_max_photos = fr_param_int(ctx, FRIG_PARAM_SFS_JOINT_MAX_PHOTOS);
    s->joint_light = fr_param(ctx, FRIG_PARAM_SFS_JOINT_LIGHT);
    s->light = 0; /* the outer loop's recoveries ask for the light solve (retarget.sfs_light) */
    s->expression_steps = fr_param_int(ctx, FRIG_PARAM_SFS_EXPRESSION_STEPS);
    s->expression_prior = fr_param(ctx, FRIG_PARAM_SFS_EXPRESSION_PRIOR);
    s->expression_sparse = fr_param(ctx, FRIG_PARAM_SFS_EXPRESSION_SPARSE);
    s->cloud_region = fr_param_int(ctx, FRIG_PARAM_SFS_CLOUD_REGION);
    s->shape_use = NULL;
    s->identity_modes = NULL, s->identity_count = 0, s->identity_start = NULL;
    s->identity_prior = fr_param(ctx, FRIG_PARAM_SFS_IDENTITY_PRIOR);
    s->identity_centre = fr_param(ctx, FRIG_PARAM_SFS_IDENTITY_PRIOR_CENTRE);
    s->displacement_hold = fr_param(ctx, FRIG_PARAM_SFS_DISPLACEMENT_HOLD);
    s->highlights = fr_param(ctx, FRIG_PARAM_SFS_HIGHLIGHTS);
}

void fr_sfs_settings_identity(const frig_ctx *ctx, fr_sfs_settings *s, const frig_model *model, const frig_photoset *set) {
    int n = fr_param_int(ctx, FRIG_PARAM_SFS_IDENTITY_MODES);
    if (!model || n <= 0) return;
    if (n > model->identity_count) n = model->identity_count;
    if (set->n_identity > 0 && n > set->n_identity) n = set->n_identity;
    s->identity_modes = model->identity;
    s->identity_count = n;
    s->identity_start = set->n_identity > 0 ? set->identity : NULL;
}

void fr_sfs_light_shared_solve(fr_sfs_settings *s) {
    s->w_stereo = 0;
    s->joint_albedo = 0;
    s->pose_levels = 0;
    s->expression_steps = 0;
    if (s->rounds > 3) s->rounds = 3;
    s->shape_iterations = 4; /* the full solve takes fewer (sfs.shape_iterations 2): it has the identity and the registration between rounds */
    s->shape_sigma = 0.03;
    s->pose_steps = 0;
    s->identity_count = 0; /* without the multi-view term the identity takes the shading's errors (docs/sfs.md) */
}
