/* The identity step's part of the photo set (lib/identity writes it, lib/detect fills the
 * descriptors): per face the 128-D descriptor and its distance to the set's identity; per set
 * the identity itself. Accessors, and their report.json form: a face's "descriptor" (floats
 * written with 9 significant digits, which read back to the same float) and
 * "identity_distance"; the set's "identity" block. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cJSON.h>

#include "core/context.h"
#include "io/json_writer.h"
#include "workspace/photoset.h"

static fr_face *face_of(const frig_photoset *set, size_t photo, size_t face) {
    if (!set || photo >= set->count || face >= set->photos[photo].face_count) return NULL;
    return &set->photos[photo].faces[face];
}

frig_status frig_photoset_face_descriptor(const frig_photoset *set, size_t photo, size_t face,
                                          float descriptor[FRIG_DESCRIPTOR_SIZE]) {
    const fr_face *f = face_of(set, photo, face);
    if (!f || !descriptor) return FRIG_ERR_INVALID_ARGUMENT;
    if (!f->has_descriptor) return FRIG_ERR_STATE;
    memcpy(descriptor, f->descriptor, sizeof f->descriptor);
    return FRIG_OK;
}

frig_status frig_photoset_set_face_descriptor(frig_ctx *ctx, frig_photoset *set, size_t photo, size_t face,
                                              const float descriptor[FRIG_DESCRIPTOR_SIZE]) {
    fr_face *f = face_of(set, photo, face);
    if (!f || !descriptor)
        return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_photoset_set_face_descriptor: no face %zu in photo %zu",
                        face, photo);
    for (int k = 0; k < FRIG_DESCRIPTOR_SIZE; k++)
        if (!isfinite(descriptor[k])) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "a descriptor must be finite");
    memcpy(f->descriptor, descriptor, sizeof f->descriptor);
    f->has_descriptor = 1;
    return FRIG_OK;
}

double frig_photoset_face_identity_distance(const frig_photoset *set, size_t photo, size_t face) {
    const fr_face *f = face_of(set, photo, face);
    return f ? f->identity_distance : NAN;
}

int frig_photoset_identity_descriptor(const frig_photoset *set, float descriptor[FRIG_DESCRIPTOR_SIZE]) {
    if (!set || !set->has_subject_id) return 0;
    if (descriptor) memcpy(descriptor, set->subject_id, sizeof set->subject_id);
    return 1;
}

double frig_descriptor_distance(const float a[FRIG_DESCRIPTOR_SIZE], const float b[FRIG_DESCRIPTOR_SIZE]) {
    double s = 0;
    for (int i = 0; i < FRIG_DESCRIPTOR_SIZE; i++) s += ((double)a[i] - b[i]) * ((double)a[i] - b[i]);
    return sqrt(s);
}

/* The double nearest the float's 9-digit decimal: its shortest form has at most 9 digits. */
static double float_as_short_double(float v) {
    char buf[32];
    snprintf(buf, sizeof buf, "%.9g", (double)v);
    return strtod(buf, NULL);
}

static void write_descriptor(fr_json *j, const char *key, const float *d) {
    fr_json_array(j, key, 1);
    for (int k = 0; k < FRIG_DESCRIPTOR_SIZE; k++) fr_json_number(j, NULL, float_as_short_double(d[k]));
    fr_json_end(j);
}

void fr_report_write_face_identity(fr_json *j, const fr_face *f) {
    if (f->has_descriptor) write_descriptor(j, "descriptor", f->descriptor);
    if (!isnan(f->identity_distance)) fr_json_number(j, "identity_distance", f->identity_distance);
}

void fr_report_write_set_identity(fr_json *j, const frig_photoset *set) {
    if (!set->has_subject_id) return;
    fr_json_object(j, "identity");
    fr_json_number(j, "threshold", set->subject_id_threshold);
    fr_json_int(j, "photos", (long long)set->subject_id_photos);
    fr_json_int(j, "medoid_photo", set->subject_id_photo);
    fr_json_int(j, "medoid_face", set->subject_id_face);
    write_descriptor(j, "descriptor", set->subject_id);
    fr_json_end(j);
}

static int read_descriptor(const cJSON *a, float *out) {
    if (!cJSON_IsArray(a) || cJSON_GetArraySize(a) != FRIG_DESCRIPTOR_SIZE) return 0;
    int k = 0;
    for (const cJSON *e = a->child; e; e = e->next, k++) {
        if (!cJSON_IsNumber(e) || !isfinite(e->valuedouble) || fabs(e->valuedouble) > 1e6) return 0;
        out[k] = (float)e->valuedouble;
    }
    return 1;
}

int fr_report_read_face_identity(fr_face *f, const void *json_face, char *why, size_t size) {
    const cJSON *jf = json_face;
    const cJSON *d = cJSON_GetObjectItemCaseSensitive(jf, "descriptor");
    const cJSON *dist = cJSON_GetObjectItemCaseSensitive(jf, "identity_distance");
    if (d) {
        if (!read_descriptor(d, f->descriptor)) {
            snprintf(why, size, "a face's \"descriptor\" is not %d finite numbers", FRIG_DESCRIPTOR_SIZE);
            return 1;
        }
        f->has_descriptor = 1;
    }
    if (dist) {
        if (!cJSON_IsNumber(dist) || !(dist->valuedouble >= 0)) {
            snprintf(why, size, "a face's \"identity_distance\" is not a number >= 0");
            return 1;
        }
        f->identity_distance = dist->valuedouble;
    }
    return 0;
}

int fr_report_read_set_identity(frig_photoset *set, const void *json_root, char *why, size_t size) {
    const cJSON *id = cJSON_GetObjectItemCaseSensitive((const cJSON *)json_root, "identity");
    if (!id) return 0;
    const cJSON *t = cJSON_GetObjectItemCaseSensitive(id, "threshold");
    const cJSON *n = cJSON_GetObjectItemCaseSensitive(id, "photos");
    const cJSON *mp = cJSON_GetObjectItemCaseSensitive(id, "medoid_photo");
    const cJSON *mf = cJSON_GetObjectItemCaseSensitive(id, "medoid_face");
    if (!cJSON_IsObject(id) || !cJSON_IsNumber(t) || !cJSON_IsNumber(n) || !cJSON_IsNumber(mp) || !cJSON_IsNumber(mf) ||
        !read_descriptor(cJSON_GetObjectItemCaseSensitive(id, "descriptor"), set->subject_id) || n->valuedouble < 0 ||
        mp->valuedouble < 0 || mp->valuedouble >= (double)set->count || mf->valuedouble < 0) {
        snprintf(why, size, "the \"identity\" block lacks its threshold, photos, medoid or a %d-number descriptor",
                 FRIG_DESCRIPTOR_SIZE);
        return 1;
    }
    set->subject_id_threshold = t->valuedouble;
    set->subject_id_photos = (size_t)n->valuedouble;
    set->subject_id_photo = (long)mp->valuedouble;
    set->subject_id_face = (long)mf->valuedouble;
    set->has_subject_id = 1;
    return 0;
}
