/* libfrig identity: who is in the photo. Face descriptors (128 numbers per face, from the face
 * recognition network of the npm package @vladmandic/face-api, a port of dlib's ResNet; the
 * same person is usually closer than 0.6), computed by the detect stage for every face when
 * the networks are installed, and the identity step that follows detect: the subject's
 * identity is the dominant cluster of descriptors over the set (its medoid), the subject face
 * of each photo is the face nearest that identity, and a photo whose nearest face is farther
 * than identity.threshold gets the status other_person. docs/identity.md.
 *
 * The networks are read from a folder holding face-api's model files (*-weights_manifest.json
 * and *.bin): the path given to frig_detector_create_with, else $FRIG_FACE_MODELS, else
 * /usr/local/share/frig/face-api/model (where scripts/install-deps.sh puts them).
 */
#ifndef FRIG_IDENTITY_H
#define FRIG_IDENTITY_H

#include "frig/photoset.h"

#ifdef __cplusplus
extern "C" {
#endif

#define FRIG_DESCRIPTOR_SIZE 128

/* A face's descriptor (128 floats); FRIG_ERR_STATE when the face has none (the networks were
 * not installed, or the face came from the user's landmark file). */
FRIG_API frig_status frig_photoset_face_descriptor(const frig_photoset *set, size_t photo, size_t face,
                                                   float descriptor[FRIG_DESCRIPTOR_SIZE]);
FRIG_API frig_status frig_photoset_set_face_descriptor(frig_ctx *ctx, frig_photoset *set, size_t photo, size_t face,
                                                       const float descriptor[FRIG_DESCRIPTOR_SIZE]);
/* The face's distance to the set's identity, NaN until frig_identify_photoset judged it. */
FRIG_API double frig_photoset_face_identity_distance(const frig_photoset *set, size_t photo, size_t face);
/* The set's identity descriptor; 0 (and nothing written) until frig_identify_photoset ran. */
FRIG_API int frig_photoset_identity_descriptor(const frig_photoset *set, float descriptor[FRIG_DESCRIPTOR_SIZE]);

/* Euclidean distance of two descriptors. */
FRIG_API double frig_descriptor_distance(const float a[FRIG_DESCRIPTOR_SIZE], const float b[FRIG_DESCRIPTOR_SIZE]);

/* The identity step, after frig_detect_photoset: over the photos with status ok or
 * other_person (a rerun judges other_person photos again) whose faces have descriptors, find
 * the dominant identity (the face with the most photos holding a face within
 * identity.cluster_radius, then the medoid of those photos' nearest faces), make each photo's
 * subject its face nearest that identity (usable faces only: eyes at least
 * detect.min_eye_distance apart), and mark photos whose nearest face is farther than
 * identity.threshold other_person, with the distance in the reason. Photos without
 * descriptors are left alone. A set with no dominant identity (the second person's cluster has
 * at least identity.min_dominance of the first's photos... see docs/identity.md) fails with
 * FRIG_ERR_TOO_FEW and a sentence saying so, changing nothing. */
FRIG_API frig_status frig_identify_photoset(frig_ctx *ctx, frig_photoset *set);

#ifdef __cplusplus
}
#endif
#endif /* FRIG_IDENTITY_H */
