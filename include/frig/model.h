/* libfrig face model: the ICT-FaceKit linear morphable head model (identity PCA modes and
 * ARKit-style expression shapes on one topology), imported once into a binary model file.
 * Geometry is in metres. See docs/model-format.md for the file layout.
 */
#ifndef FRIG_MODEL_H
#define FRIG_MODEL_H

#include "frig/core.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct frig_model frig_model;

/* Read an ICT-FaceKit folder (generic_neutral_mesh.obj, identityNNN.obj, the expression
 * OBJs, vertex_indices.json); non-neutral files may hold only 'v' lines or repeat vt/f.
 * A missing file or one with a different vertex count fails with a sentence naming it. */
FRIG_API frig_status frig_model_import_ict(frig_ctx *ctx, const char *dir, frig_model **out);

/* The binary model file: validated on load (counts, indices, checksum), written atomically. */
FRIG_API frig_status frig_model_load(frig_ctx *ctx, const char *path, frig_model **out);
FRIG_API frig_status frig_model_save(frig_ctx *ctx, const frig_model *model, const char *path);
FRIG_API void frig_model_free(frig_model *model);

/* Where commands look for the model: $FRIG_MODEL, else $XDG_DATA_HOME/frig/ict.frigmodel,
 * else ~/.local/share/frig/ict.frigmodel. FRIG_ERR_INVALID_ARGUMENT if buf is too small. */
FRIG_API frig_status frig_model_default_path(frig_ctx *ctx, char *buf, size_t size);

/* ---- topology ---- */
FRIG_API int frig_model_vertex_count(const frig_model *model);
/* Triangulation used for computation (rendering, normals, glTF): 3 indices per triangle. */
FRIG_API int frig_model_triangle_count(const frig_model *model);
FRIG_API const int32_t *frig_model_triangles(const frig_model *model);
/* Polygons as the source mesh gives them (quads and triangles), for OBJ export: polygon p
 * has corners offsets[p] .. offsets[p+1]-1 in 'corners' (vertex indices) and 'corner_uvs'. */
FRIG_API int frig_model_polygon_count(const frig_model *model);
FRIG_API const int32_t *frig_model_polygon_offsets(const frig_model *model); /* count + 1 */
FRIG_API const int32_t *frig_model_polygon_corners(const frig_model *model);
FRIG_API const int32_t *frig_model_polygon_corner_uvs(const frig_model *model);
FRIG_API int frig_model_uv_count(const frig_model *model);
FRIG_API const float *frig_model_uvs(const frig_model *model); /* 2 per uv */
/* Triangle t's corner c (0..2) uses uv index triangle_uvs[3t + c]. */
FRIG_API const int32_t *frig_model_triangle_uvs(const frig_model *model);
/* Material of each polygon / triangle (index into the material names). */
FRIG_API int frig_model_material_count(const frig_model *model);
FRIG_API const char *frig_model_material_name(const frig_model *model, int material);
FRIG_API const int32_t *frig_model_polygon_materials(const frig_model *model);
FRIG_API const int32_t *frig_model_triangle_materials(const frig_model *model);

/* Named vertex ranges ("face", "narrow_face", "head_neck", "mouth_socket", "eye_socket_left",
 * "gums_tongue", "teeth", "eyeball_left", ...): vertices first .. first+count-1. */
FRIG_API int frig_model_region_count(const frig_model *model);
FRIG_API frig_status frig_model_region(const frig_model *model, int region, const char **name, int *first,
                                       int *count);
/* Region by name; -1 when absent. */
FRIG_API int frig_model_region_find(const frig_model *model, const char *name);

/* ---- shape spaces ---- */
FRIG_API const float *frig_model_neutral(const frig_model *model); /* 3 floats per vertex */
/* Identity modes: mode k's deltas (3 per vertex, one standard deviation) start at
 * identity_modes + 3 * vertex_count * k. Weights are in standard deviations (prior N(0, I)). */
FRIG_API int frig_model_identity_count(const frig_model *model);
FRIG_API const float *frig_model_identity_modes(const frig_model *model);
/* Expression shapes as deltas from the neutral, same layout; names as in ICT ("jawOpen",
 * "eyeBlink_L", ...). frig_model_expression_fitting() is 1 for the shapes the model's
 * vertex_indices.json lists for fitting. */
FRIG_API int frig_model_expression_count(const frig_model *model);
FRIG_API const char *frig_model_expression_name(const frig_model *model, int k);
FRIG_API int frig_model_expression_find(const frig_model *model, const char *name);
FRIG_API int frig_model_expression_fitting(const frig_model *model, int k);
FRIG_API const float *frig_model_expression_deltas(const frig_model *model);

/* ---- correspondences ---- */
/* The 68 landmark vertices, iBUG/Multi-PIE order. */
FRIG_API const int32_t *frig_model_landmarks(const frig_model *model);
/* Jawline contour candidates: side 0 = the subject's right (iBUG points 0-7), side 1 = left
 * (points 9-16); ordered from the ear toward the chin. */
FRIG_API int frig_model_contour(const frig_model *model, int side, const int32_t **vertices);
/* Vertices that move rigidly with the skull (for pose alignment). */
FRIG_API int frig_model_rigid_vertices(const frig_model *model, const int32_t **vertices);

/* Evaluate neutral + sum identity[k] * mode_k + sum expression[j] * delta_j into out
 * (3 floats per vertex). identity has identity_count values (or NULL = zeros), expression
 * has expression_count values (or NULL = zeros). */
FRIG_API frig_status frig_model_eval(frig_ctx *ctx, const frig_model *model, const double *identity,
                                     const double *expression, float *out);

#ifdef __cplusplus
}
#endif
#endif /* FRIG_MODEL_H */
