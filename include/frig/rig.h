/* libfrig rig: a neutral head plus named blendshapes (as deltas) on the model's topology,
 * and the writers engines and DCC tools read: glTF 2.0 binary, OBJ per shape, PLY clouds.
 * A rig is made from a model and identity weights (the "model-space rig": neutral(identity)
 * plus the template's expression deltas) and is later replaced by the retarget stage.
 */
#ifndef FRIG_RIG_H
#define FRIG_RIG_H

#include "frig/image.h"
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
 * ARKit-named blendshape (mesh.extras.targetNames); one primitive per material (face, back of
 * the head, mouth, teeth, sclera, iris, lashes and ICT's eye overlays) so users can hide or
 * re-material them. In every primitive the ICT vertices it uses come first, in ICT's order,
 * and the copies made at UV seams after them; primitive.extras.ictVertexIndex gives each
 * vertex's ICT index (ictVertexCount: how many come first). Sclera and iris get base-colour
 * textures libfrig paints (export.texture_size), ICT's translucent eye overlays (tear film,
 * eye blend, eye occlusion) are alpha-blended (export.eye_overlays 0 leaves them out), and the
 * face primitive uses the face texture when one is set (frig_rig_set_face_texture). */
FRIG_API frig_status frig_rig_save_gltf(frig_ctx *ctx, const frig_rig *rig, const char *path);
/* OBJ: DIR/neutral.obj, DIR/<shape>.obj per blendshape (full shape, ICT vertex order, ARKit
 * names), DIR/frig.mtl (colours, transparency, map_Kd / map_d) and the textures beside them
 * (frig_*.png). The folder is created if needed. */
FRIG_API frig_status frig_rig_save_obj(frig_ctx *ctx, const frig_rig *rig, const char *dir);

/* The face's base-colour texture for the writers and the renderer: a PNG in ICT's face UV
 * layout (sRGB, rows from the top; texel (x, y) of a W x H image lies at
 * uv = ((x + 0.5) / W, 1 - (y + 0.5) / H)), e.g. the albedo the sfs stage writes to
 * WORKSPACE/textures/albedo.png. The file is checked and its bytes kept in the rig (glTF
 * embeds them unchanged; OBJ export copies them to DIR/frig_face.png); the rig file written
 * by frig_rig_save does not hold them. NULL removes the texture. */
FRIG_API frig_status frig_rig_set_face_texture(frig_ctx *ctx, frig_rig *rig, const char *png_path);
FRIG_API int frig_rig_has_face_texture(const frig_rig *rig);

/* ---- pictures of a rig (EXPERIMENTAL: may change while FRIG_VERSION_MAJOR is 0) ----
 * Rendered by libfrig's own rasterizer with the look the writers export (painted eyes,
 * blended overlays, the face texture or a clay colour): three lights, 3x supersampled. */
enum {
    FRIG_FRAME_FACE = 0, /* the face fills the picture */
    FRIG_FRAME_HEAD = 1  /* the whole head */
};
/* weights: frig_rig_shape_count values, or NULL for the neutral. yaw turns the head to its
 * left (the viewer's right), pitch tips the nose down, in degrees. An RGB image. */
FRIG_API frig_status frig_rig_render(frig_ctx *ctx, const frig_rig *rig, const double *weights, double yaw_deg,
                                     double pitch_deg, int framing, int width, int height, frig_image **out);
/* A PNG contact sheet: the neutral, then every exported blendshape at weight 1 in the
 * exporters' order (frig_rig_target_name), each a cell x cell picture of the face with its
 * name under it, 'columns' to a row; mouthClose with jawOpen (it closes an open jaw's lips, as
 * in ARKit). Parallel over the pictures. */
FRIG_API frig_status frig_rig_save_contact_sheet(frig_ctx *ctx, const frig_rig *rig, int cell, int columns,
                                                 const char *path);

/* Binary little-endian PLY point cloud; normals and confidence may be NULL. */
FRIG_API frig_status frig_save_ply(frig_ctx *ctx, const char *path, size_t count, const float *xyz,
                                   const float *normals, const float *confidence);

#ifdef __cplusplus
}
#endif
#endif /* FRIG_RIG_H */
