/* The photo set handle: photos, faces, statuses, subject choice, stage results. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "workspace/photoset.h"

static const char *const status_names[] = {
    [FRIG_PHOTO_PENDING] = "pending",       [FRIG_PHOTO_OK] = "ok",
    [FRIG_PHOTO_UNREADABLE] = "unreadable", [FRIG_PHOTO_NO_FACE] = "no_face",
    [FRIG_PHOTO_FACE_TOO_SMALL] = "face_too_small", [FRIG_PHOTO_OUTLIER] = "outlier",
    [FRIG_PHOTO_FIT_FAILED] = "fit_failed", [FRIG_PHOTO_DUPLICATE] = "duplicate",
    [FRIG_PHOTO_OTHER_PERSON] = "other_person", [FRIG_PHOTO_SFS_FAILED] = "sfs_failed"};

const char *frig_photo_status_name(frig_photo_status s) {
    return (unsigned)s < sizeof status_names / sizeof status_names[0] ? status_names[s] : NULL;
}

frig_status frig_photoset_create(frig_ctx *ctx, frig_photoset **out) {
    if (!out) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_photoset_create: no output pointer");
    *out = calloc(1, sizeof **out);
    return *out ? FRIG_OK : fr_nomem(ctx, "a photo set");
}

void frig_photoset_free(frig_photoset *set) {
    if (!set) return;
    for (size_t i = 0; i < set->count; i++) {
        free(set->photos[i].path);
        free(set->photos[i].reason);
        free(set->photos[i].faces);
        free(set->photos[i].fit_expression);
        free(set->photos[i].sfs_expression);
    }
    for (int k = 0; k < set->n_expressions; k++) free(set->expression_names[k]);
    free(set->expression_names);
    free(set->identity);
    free(set->sfs_identity);
    free(set->rt_round);
    free(set->photos);
    free(set);
}

size_t frig_photoset_count(const frig_photoset *set) { return set ? set->count : 0; }

static fr_photo *photo_at(const frig_photoset *set, size_t i) {
    return set && i < set->count ? &set->photos[i] : NULL;
}

static frig_status bad_photo(frig_ctx *ctx, const frig_photoset *set, size_t i) {
    return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "photo index %zu is outside the set of %zu", i,
                    set ? set->count : 0);
}

frig_status frig_photoset_add(frig_ctx *ctx, frig_photoset *set, const char *path, size_t *index) {
    if (!set || !path) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_photoset_add: NULL argument");
    if (set->count == set->capacity) {
        size_t cap = set->capacity ? 2 * set->capacity : 64;
        fr_photo *p = realloc(set->photos, cap * sizeof *p);
        if (!p) return fr_nomem(ctx, "the photo list");
        set->photos = p;
        set->capacity = cap;
    }
    fr_photo *ph = &set->photos[set->count];
    memset(ph, 0, sizeof *ph);
    ph->path = strdup(path);
    if (!ph->path) return fr_nomem(ctx, "a photo path");
    ph->subject = -1;
    if (index) *index = set->count;
    set->count++;
    return FRIG_OK;
}

const char *frig_photoset_path(const frig_photoset *set, size_t i) {
    fr_photo *p = photo_at(set, i);
    return p ? p->path : NULL;
}

frig_photo_status frig_photoset_status(const frig_photoset *set, size_t i) {
    fr_photo *p = photo_at(set, i);
    return p ? p->status : FRIG_PHOTO_PENDING;
}

const char *frig_photoset_reason(const frig_photoset *set, size_t i) {
    fr_photo *p = photo_at(set, i);
    return p && p->reason ? p->reason : "";
}

frig_status frig_photoset_set_status(frig_ctx *ctx, frig_photoset *set, size_t i, frig_photo_status status,
                                     const char *reason) {
    fr_photo *p = photo_at(set, i);
    if (!p) return bad_photo(ctx, set, i);
    if (!frig_photo_status_name(status))
        return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "unknown photo status %d", (int)status);
    char *r = NULL;
    if (reason && *reason && !(r = strdup(reason))) return fr_nomem(ctx, "a reason");
    free(p->reason);
    p->reason = r;
    p->status = status;
    return FRIG_OK;
}

void frig_photoset_size(const frig_photoset *set, size_t i, int *w, int *h) {
    fr_photo *p = photo_at(set, i);
    if (w) *w = p ? p->width : 0;
    if (h) *h = p ? p->height : 0;
}

frig_status frig_photoset_set_size(frig_ctx *ctx, frig_photoset *set, size_t i, int w, int h) {
    fr_photo *p = photo_at(set, i);
    if (!p) return bad_photo(ctx, set, i);
    if (w < 0 || h < 0) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "negative photo size %dx%d", w, h);
    p->width = w;
    p->height = h;
    return FRIG_OK;
}

size_t frig_photoset_face_count(const frig_photoset *set, size_t i) {
    fr_photo *p = photo_at(set, i);
    return p ? p->face_count : 0;
}

static int finite_all(const double *v, size_t n) {
    for (size_t k = 0; k < n; k++)
        if (!(v[k] == v[k]) || v[k] > 1e12 || v[k] < -1e12) return 0;
    return 1;
}

frig_status frig_photoset_add_face(frig_ctx *ctx, frig_photoset *set, size_t i, const double box[4], double score,
                                   frig_face_source source, const double *landmarks, size_t *face) {
    fr_photo *p = photo_at(set, i);
    if (!p) return bad_photo(ctx, set, i);
    if (!box || !finite_all(box, 4) || box[2] < 0 || box[3] < 0)
        return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "%s: a face box must be 4 finite numbers, w and h >= 0",
                        p->path);
    if (landmarks && !finite_all(landmarks, 2 * FRIG_LANDMARK_COUNT))
        return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "%s: landmarks must be finite", p->path);
    if ((unsigned)source > FRIG_FACE_SSD)
        return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "unknown face source %d", (int)source);
    if (p->face_count == p->face_capacity) {
        size_t cap = p->face_capacity ? 2 * p->face_capacity : 4;
        fr_face *f = realloc(p->faces, cap * sizeof *f);
        if (!f) return fr_nomem(ctx, "a face list");
        p->faces = f;
        p->face_capacity = cap;
    }
    fr_face *f = &p->faces[p->face_count];
    memset(f, 0, sizeof *f);
    memcpy(f->box, box, sizeof f->box);
    f->score = score == score ? score : 0;
    f->source = (int)source;
    if (landmarks) {
        memcpy(f->landmarks, landmarks, sizeof f->landmarks);
        f->has_landmarks = 1;
    }
    f->identity_distance = NAN;
    if (face) *face = p->face_count;
    p->face_count++;
    return FRIG_OK;
}

frig_status frig_photoset_clear_faces(frig_ctx *ctx, frig_photoset *set, size_t i) {
    fr_photo *p = photo_at(set, i);
    if (!p) return bad_photo(ctx, set, i);
    p->face_count = 0;
    p->subject = -1;
    return FRIG_OK;
}

static const fr_face *face_at(const frig_photoset *set, size_t i, size_t f) {
    fr_photo *p = photo_at(set, i);
    return p && f < p->face_count ? &p->faces[f] : NULL;
}

frig_status frig_photoset_face_box(const frig_photoset *set, size_t i, size_t f, double box[4]) {
    const fr_face *fc = face_at(set, i, f);
    if (!fc) return FRIG_ERR_INVALID_ARGUMENT;
    memcpy(box, fc->box, sizeof fc->box);
    return FRIG_OK;
}

double frig_photoset_face_score(const frig_photoset *set, size_t i, size_t f) {
    const fr_face *fc = face_at(set, i, f);
    return fc ? fc->score : 0;
}

frig_face_source frig_photoset_face_source(const frig_photoset *set, size_t i, size_t f) {
    const fr_face *fc = face_at(set, i, f);
    return fc ? (frig_face_source)fc->source : FRIG_FACE_FRONTAL;
}

frig_status frig_photoset_face_landmarks(const frig_photoset *set, size_t i, size_t f, double *lm) {
    const fr_face *fc = face_at(set, i, f);
    if (!fc) return FRIG_ERR_INVALID_ARGUMENT;
    if (!fc->has_landmarks) return FRIG_ERR_STATE;
    memcpy(lm, fc->landmarks, sizeof fc->landmarks);
    return FRIG_OK;
}

frig_status frig_photoset_set_face_landmarks(frig_ctx *ctx, frig_photoset *set, size_t i, size_t f,
                                             const double *lm) {
    fr_photo *p = photo_at(set, i);
    if (!p) return bad_photo(ctx, set, i);
    if (f >= p->face_count)
        return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "%s: face %zu of %zu", p->path, f, p->face_count);
    if (!lm || !finite_all(lm, 2 * FRIG_LANDMARK_COUNT))
        return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "%s: landmarks must be 136 finite numbers", p->path);
    memcpy(p->faces[f].landmarks, lm, sizeof p->faces[f].landmarks);
    p->faces[f].has_landmarks = 1;
    return FRIG_OK;
}

long frig_photoset_subject(const frig_photoset *set, size_t i) {
    fr_photo *p = photo_at(set, i);
    return p ? p->subject : -1;
}

frig_status frig_photoset_set_subject(frig_ctx *ctx, frig_photoset *set, size_t i, long face) {
    fr_photo *p = photo_at(set, i);
    if (!p) return bad_photo(ctx, set, i);
    if (face < -1 || (face >= 0 && (size_t)face >= p->face_count))
        return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "%s: no face %ld (it has %zu)", p->path, face,
                        p->face_count);
    p->subject = face;
    return FRIG_OK;
}

const fr_face *fr_photo_subject(const fr_photo *p) {
    if (p->subject < 0 || (size_t)p->subject >= p->face_count) return NULL;
    const fr_face *f = &p->faces[p->subject];
    return f->has_landmarks ? f : NULL;
}

frig_status frig_photoset_set_filter(frig_ctx *ctx, frig_photoset *set, size_t i, double error, double texture_error,
                                     double shape_error, int round_dropped) {
    fr_photo *p = photo_at(set, i);
    if (!p) return bad_photo(ctx, set, i);
    p->filtered = 1;
    p->filter_error = error;
    p->filter_texture_error = texture_error;
    p->filter_shape_error = shape_error;
    p->filter_round = round_dropped;
    return FRIG_OK;
}

int frig_photoset_filter(const frig_photoset *set, size_t i, double *error, double *texture_error,
                         double *shape_error, int *round_dropped) {
    fr_photo *p = photo_at(set, i);
    if (!p || !p->filtered) return 0;
    if (error) *error = p->filter_error;
    if (texture_error) *texture_error = p->filter_texture_error;
    if (shape_error) *shape_error = p->filter_shape_error;
    if (round_dropped) *round_dropped = p->filter_round;
    return 1;
}

/* ---- fit results (section 4.3) ---- */

static void drop_fits(frig_photoset *set) {
    for (size_t i = 0; i < set->count; i++) {
        free(set->photos[i].fit_expression), free(set->photos[i].sfs_expression);
        set->photos[i].fit_expression = set->photos[i].sfs_expression = NULL;
        set->photos[i].fitted = 0;
    }
    for (int k = 0; k < set->n_expressions; k++) free(set->expression_names[k]);
    free(set->expression_names);
    free(set->identity), free(set->sfs_identity);
    set->expression_names = NULL;
    set->identity = set->sfs_identity = NULL;
    set->n_expressions = set->n_identity = 0;
}

frig_status fr_photoset_set_fit_spaces(frig_ctx *ctx, frig_photoset *set, int n_identity, int n_expressions,
                                       const char *const *names) {
    drop_fits(set);
    set->identity = calloc((size_t)(n_identity > 0 ? n_identity : 1), sizeof(double));
    set->expression_names = calloc((size_t)(n_expressions > 0 ? n_expressions : 1), sizeof(char *));
    if (!set->identity || !set->expression_names) {
        drop_fits(set);
        return fr_nomem(ctx, "fit results");
    }
    set->n_identity = n_identity;
    set->n_expressions = n_expressions;
    for (int k = 0; k < n_expressions; k++)
        if (!(set->expression_names[k] = strdup(names[k]))) {
            drop_fits(set);
            return fr_nomem(ctx, "fit results");
        }
    return FRIG_OK;
}

frig_status fr_photoset_set_fit(frig_ctx *ctx, frig_photoset *set, size_t i, const double R[9], const double t[3],
                                double focal, int perspective, const double *expression, double error_px,
                                int in_joint) {
    fr_photo *p = photo_at(set, i);
    if (!p) return bad_photo(ctx, set, i);
    if (!p->fit_expression && !(p->fit_expression = calloc((size_t)(set->n_expressions + 1), sizeof(double))))
        return fr_nomem(ctx, "fit results");
    memcpy(p->fit_rotation, R, sizeof p->fit_rotation);
    memcpy(p->fit_translation, t, sizeof p->fit_translation);
    p->fit_focal = focal;
    p->fit_perspective = perspective;
    memcpy(p->fit_expression, expression, sizeof(double) * (size_t)set->n_expressions);
    p->fit_error_px = error_px;
    p->fit_in_joint = in_joint;
    p->fitted = 1;
    return FRIG_OK;
}

int frig_photoset_fitted(const frig_photoset *set, size_t i) {
    fr_photo *p = photo_at(set, i);
    return p ? p->fitted : 0;
}

frig_status frig_photoset_fit_pose(const frig_photoset *set, size_t i, double rotation[9], double translation[3],
                                   double *focal, int *perspective) {
    fr_photo *p = photo_at(set, i);
    if (!p) return FRIG_ERR_INVALID_ARGUMENT;
    if (!p->fitted) return FRIG_ERR_STATE;
    if (rotation) memcpy(rotation, p->fit_rotation, sizeof p->fit_rotation);
    if (translation) memcpy(translation, p->fit_translation, sizeof p->fit_translation);
    if (focal) *focal = p->fit_focal;
    if (perspective) *perspective = p->fit_perspective;
    return FRIG_OK;
}

int frig_photoset_fit_expression_count(const frig_photoset *set) { return set ? set->n_expressions : 0; }

const char *frig_photoset_fit_expression_name(const frig_photoset *set, int k) {
    return set && k >= 0 && k < set->n_expressions ? set->expression_names[k] : NULL;
}

frig_status frig_photoset_fit_expression(const frig_photoset *set, size_t i, double *weights) {
    fr_photo *p = photo_at(set, i);
    if (!p) return FRIG_ERR_INVALID_ARGUMENT;
    if (!p->fitted) return FRIG_ERR_STATE;
    memcpy(weights, p->fit_expression, sizeof(double) * (size_t)set->n_expressions);
    return FRIG_OK;
}

double frig_photoset_fit_error(const frig_photoset *set, size_t i) {
    fr_photo *p = photo_at(set, i);
    return p && p->fitted ? p->fit_error_px : NAN;
}

int frig_photoset_fit_in_joint(const frig_photoset *set, size_t i) {
    fr_photo *p = photo_at(set, i);
    return p && p->fitted ? p->fit_in_joint : 0;
}

int frig_photoset_identity(const frig_photoset *set, const double **weights) {
    if (weights) *weights = set ? set->identity : NULL;
    return set ? set->n_identity : 0;
}
