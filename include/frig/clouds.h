/* libfrig point clouds: per photo of a photo set, the dense face geometry the sfs stage
 * recovers from the photo's shading (paper section 5.1) and the retarget stage fits the rig to
 * (section 5.2). Points are in the rig's head frame (metres, ICT axes: x to the subject's left,
 * y up, z out of the face; the frame of the exported rig.glb and shapes/neutral.obj), with unit
 * normals in the same frame and a confidence in [0, 1].
 *
 * On disk: WORKSPACE/clouds/<photo file stem>.ply, binary little-endian PLY with float
 * x y z nx ny nz confidence (docs/workspace.md). A stem shared by two photos of the set gets
 * _2, _3, ... in photo order (frig_clouds_file_name).
 *
 * A photo's cloud may have a margin: points beyond the narrow face (neck, ears, scalp), read at
 * grazing angles and less accurate, which the retarget stage still uses for the shape they
 * cover. They are kept apart (WORKSPACE/clouds/margin/<same name>.ply) so that the cloud itself
 * holds only the face's own points.
 */
#ifndef FRIG_CLOUDS_H
#define FRIG_CLOUDS_H

#include "frig/photoset.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct frig_clouds frig_clouds;

/* An empty cloud for each of photo_count photos. */
FRIG_API frig_status frig_clouds_create(frig_ctx *ctx, size_t photo_count, frig_clouds **out);
FRIG_API void frig_clouds_free(frig_clouds *clouds);
FRIG_API size_t frig_clouds_photo_count(const frig_clouds *clouds);

/* Replace photo's cloud with a copy of count points: xyz and normals 3 floats per point,
 * confidence one (all three required when count > 0); count 0 removes the cloud. */
FRIG_API frig_status frig_clouds_set(frig_ctx *ctx, frig_clouds *clouds, size_t photo, size_t count,
                                     const float *xyz, const float *normals, const float *confidence);
/* Replace the margin of photo's cloud (which must have points) with a copy of count points,
 * laid out as for frig_clouds_set (they may be read from this cloud's own arrays); count 0
 * removes it. frig_clouds_set removes the margin. */
FRIG_API frig_status frig_clouds_set_margin(frig_ctx *ctx, frig_clouds *clouds, size_t photo, size_t count,
                                            const float *xyz, const float *normals, const float *confidence);
/* Points of photo's cloud (0 when it has none or photo is out of range), and of its margin. */
FRIG_API size_t frig_clouds_count(const frig_clouds *clouds, size_t photo);
FRIG_API size_t frig_clouds_margin_count(const frig_clouds *clouds, size_t photo);
/* Borrowed arrays, valid until the cloud is set again or freed; NULL when it has no points.
 * They hold frig_clouds_count points of the cloud, then frig_clouds_margin_count of its margin. */
FRIG_API const float *frig_clouds_xyz(const frig_clouds *clouds, size_t photo);
FRIG_API const float *frig_clouds_normals(const frig_clouds *clouds, size_t photo);
FRIG_API const float *frig_clouds_confidence(const frig_clouds *clouds, size_t photo);

/* The file name of photo's cloud ("photo_007.ply"): the photo's file name without its
 * extension, with _2, _3, ... when an earlier photo of the set has the same name (or took it).
 * FRIG_ERR_INVALID_ARGUMENT when buf is too small or photo is out of range. */
FRIG_API frig_status frig_clouds_file_name(frig_ctx *ctx, const frig_photoset *set, size_t photo, char *buf,
                                           size_t size);

/* Write WORKSPACE/clouds/NAME.ply for every photo with a cloud, and clouds/margin/NAME.ply for
 * every cloud with a margin (each atomically), and remove the .ply files in both that belong to
 * no cloud or margin of this set (a photo that lost its cloud on a rerun must not keep an old
 * one). clouds must have one slot per photo of set. */
FRIG_API frig_status frig_clouds_save(frig_ctx *ctx, const frig_clouds *clouds, const frig_photoset *set,
                                      const char *workspace);
/* Read the clouds of set's photos from WORKSPACE/clouds/ (a photo without a file has no
 * cloud) and their margins from clouds/margin/ (none without a file). A malformed file fails
 * with a sentence naming it. */
FRIG_API frig_status frig_clouds_load(frig_ctx *ctx, const frig_photoset *set, const char *workspace,
                                      frig_clouds **out);

/* Read one PLY file of this layout (binary little-endian, a vertex element first with float or
 * double x y z and optionally nx ny nz and confidence; other properties are skipped). Missing
 * normals come back as zeros, a missing confidence as ones. */
FRIG_API frig_status frig_clouds_load_ply(frig_ctx *ctx, frig_clouds *clouds, size_t photo, const char *path);

#ifdef __cplusplus
}
#endif
#endif /* FRIG_CLOUDS_H */
