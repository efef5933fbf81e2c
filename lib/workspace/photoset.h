/* The photo set's inside (internal): plain arrays of photos and faces. Stages read and
 * write these directly; the public accessors in include/frig/photoset.h wrap them. */
#ifndef FR_WORKSPACE_PHOTOSET_H
#define FR_WORKSPACE_PHOTOSET_H

#include "frig/photoset.h"

typedef struct fr_face {
    double box[4]; /* x, y, w, h */
    double score;
    int source;
    int has_landmarks;
    double landmarks[2 * FRIG_LANDMARK_COUNT];
} fr_face;

typedef struct fr_photo {
    char *path;
    frig_photo_status status;
    char *reason;
    int width, height;
    fr_face *faces;
    size_t face_count, face_capacity;
    long subject;
    /* filter */
    int filtered;
    double filter_error, filter_texture_error, filter_shape_error;
    int filter_round;
} fr_photo;

struct frig_photoset {
    fr_photo *photos;
    size_t count, capacity;
};

/* The subject face, or NULL when the photo has none (or it has no landmarks). */
const fr_face *fr_photo_subject(const fr_photo *photo);

#endif
