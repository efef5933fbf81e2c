/* libfrig rig: a neutral head plus named blendshapes (as deltas) on the model's topology,
 * and the writers engines and DCC tools read: glTF 2.0 binary, OBJ per shape, PLY clouds.
 * A rig is made from a model and identity weights (the "model-space rig": neutral(identity)
 * plus the template's expression deltas) and is later replaced by the retarget stage.
 */
#ifndef FRIG_RIG_H
#define FRIG_RIG_H

#include "frig/model.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct frig_rig frig_rig;

/* identity: frig_model_identity_count values, or NULL for the mean face. The rig copies what
 * it needs; the model may be freed afterwards. */
FRIG_API frig_status frig_rig_from_model(frig_ctx *ctx, const frig_model *model, const double *identity,
                                         frig_rig **out);
FRIG_API frig_status frig_rig_clone(frig_ctx *ctx, const frig_rig *rig, frig_rig **out);
FRIG_API void frig_rig_free(frig_rig *rig);

/* Native binary rig file (the workspace's current rig), validated on load, saved atomically. */
FRIG_API frig_status frig_rig_load(frig_ctx *ctx, const char *path, frig_rig **out);
FRIG_API frig_status frig_rig_save(frig_ctx *ctx, const frig_rig *rig, const char *path);

FRIG_API int frig_rig_vertex_count(const frig_rig *rig);
FRIG_API int frig_rig_shape_count(const frig_rig *rig);
/* The shape's own name (ICT spelling, e.g. "eyeBlink_L"). */
FRIG_API const char *frig_rig_shape_name(const frig_rig *rig, int k);
FRIG_API int frig_rig_shape_find(const frig_rig *rig, const char *name);
FRIG_API const float *frig_rig_neutral(const frig_rig *rig);            /* 3 per vertex, metres */
FRIG_API const float *frig_rig_shape_deltas(const frig_rig *rig, int k); /* 3 per vertex */
FRIG_API frig_status frig_rig_set_neutral(frig_ctx *ctx, frig_rig *rig, const float *positions);
FRIG_API frig_status frig_rig_set_shape_deltas(frig_ctx *ctx, frig_rig *rig, int k, const float *deltas);

/* neutral + sum weights[k] * deltas_k into out (3 per vertex); weights has shape_count values. */
FRIG_API frig_status frig_rig_eval(frig_ctx *ctx, const frig_rig *rig, const double *weights, float *out);

/* ARKit's name for a rig shape ("eyeBlink_L" -> "eyeBlinkLeft"; the split "browInnerUp_L/_R"
 * and "cheekPuff_L/_R" -> "browInnerUp", "cheekPuff"); shapes ARKit lacks keep their own
 * name. Returns a pointer into a static table or into the rig. */
FRIG_API const char *frig_rig_arkit_name(const frig_rig *rig, int k);
/* ARKit's 52 names, and which of them this rig cannot provide (e.g. "tongueOut"). */
FRIG_API int frig_arkit_name_count(void);
FRIG_API const char *frig_arkit_name(int i);
FRIG_API int frig_rig_provides_arkit(const frig_rig *rig, const char *arkit_name);
/* The blendshapes the exporters write, in their order: the ARKit names the rig provides in
 * ARKit's order (split halves summed into one), then the shapes ARKit lacks in rig order.
 * Index i in 0 .. frig_rig_target_count()-1. */
FRIG_API int frig_rig_target_count(const frig_rig *rig);
FRIG_API const char *frig_rig_target_name(const frig_rig *rig, int i);

/* glTF 2.0 binary (.glb): positions in metres, normals, UVs, indices; one morph target per
 * ARKit-named blendshape (mesh.extras.targetNames); separate primitives per material group
 * (face/head, eyes, teeth and mouth, lashes) so users can hide or re-material them. */
FRIG_API frig_status frig_rig_save_gltf(frig_ctx *ctx, const frig_rig *rig, const char *path);
/* OBJ: DIR/neutral.obj, DIR/<shape>.obj per blendshape (full shape, ICT vertex order, ARKit
 * names), DIR/frig.mtl. The folder is created if needed. */
FRIG_API frig_status frig_rig_save_obj(frig_ctx *ctx, const frig_rig *rig, const char *dir);

/* Binary little-endian PLY point cloud; normals and confidence may be NULL. */
FRIG_API frig_status frig_save_ply(frig_ctx *ctx, const char *path, size_t count, const float *xyz,
                                   const float *normals, const float *confidence);

#ifdef __cplusplus
}
#endif
#endif /* FRIG_RIG_H */
