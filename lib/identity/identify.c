/* The identity step (after detect, before filter): who the subject is. The dissertation
 * (section 4.2) assumes every photo shows one person; web collections do not (other people
 * under the same name, co-stars, crowds). Each face has a 128-D descriptor from face-api's
 * recognition net (lib/detect); the subject's identity is the dominant cluster of them over
 * the set: the face with the most photos holding a face within identity.cluster_radius (the
 * mode), then the medoid of each such photo's nearest face (robust: a mean over all faces would
 * drift toward strangers), refined once; the identity is the mean of that cluster's members
 * (strangers are outside it; measured a cleaner prototype than the medoid itself, whose own
 * noise every distance would carry; identity.prototype 0 keeps the medoid). In every photo the
 * subject is the usable face nearest that identity (not the largest); a photo whose nearest
 * face is farther than identity.threshold is other_person. Sequential and in index order: the same result whatever the thread count. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "workspace/photoset.h"

/* One candidate face: a usable face with a descriptor in a photo the step judges. */
typedef struct cand {
    size_t photo, face;
    const float *d;
} cand;

typedef struct cands {
    cand *v;
    size_t n;
    size_t *first; /* per judged photo k: its faces are v[first[k] .. first[k + 1]) */
    size_t *photo; /* judged photo k's index in the set */
    size_t photos;
} cands;

static double eye_distance(const double *lm) { return hypot(lm[72] - lm[90], lm[73] - lm[91]); }

static int judged(const fr_photo *p) { return p->status == FRIG_PHOTO_OK || p->status == FRIG_PHOTO_OTHER_PERSON; }

static frig_status collect(frig_ctx *ctx, const frig_photoset *set, double min_eye, cands *c) {
    memset(c, 0, sizeof *c);
    size_t faces = 0;
    for (size_t i = 0; i < set->count; i++)
        if (judged(&set->photos[i])) faces += set->photos[i].face_count;
    c->v = malloc((faces ? faces : 1) * sizeof *c->v);
    c->first = malloc((set->count + 1) * sizeof *c->first);
    c->photo = malloc((set->count + 1) * sizeof *c->photo);
    if (!c->v || !c->first || !c->photo) return fr_nomem(ctx, "the identity step");
    for (size_t i = 0; i < set->count; i++) {
        const fr_photo *p = &set->photos[i];
        if (!judged(p)) continue;
        size_t start = c->n;
        for (size_t f = 0; f < p->face_count; f++) {
            const fr_face *fc = &p->faces[f];
            if (!fc->has_descriptor || !fc->has_landmarks || eye_distance(fc->landmarks) < min_eye) continue;
            c->v[c->n++] = (cand){i, f, fc->descriptor};
        }
        if (c->n == start) continue; /* no descriptor: the photo is left alone */
        c->first[c->photos] = start;
        c->photo[c->photos++] = i;
    }
    c->first[c->photos] = c->n;
    return FRIG_OK;
}

static void cands_free(cands *c) {
    free(c->v);
    free(c->first);
    free(c->photo);
}

static double dist(const float *a, const float *b) { return frig_descriptor_distance(a, b); }

/* The face of judged photo k nearest d: its candidate index; *best its distance. */
static size_t nearest_in(const cands *c, size_t k, const float *d, double *best) {
    size_t arg = c->first[k];
    *best = INFINITY;
    for (size_t j = c->first[k]; j < c->first[k + 1]; j++) {
        double e = dist(c->v[j].d, d);
        if (e < *best) *best = e, arg = j;
    }
    return arg;
}

/* Among candidates with allowed[j] (NULL: all), the mode: the face with the most other photos
 * holding an allowed face within r (ties: the smaller sum of those distances, then the lower
 * index). Returns its index, or (size_t)-1 when none is allowed; *support its photo count. */
static size_t mode(const cands *c, const unsigned char *allowed, double r, size_t *support) {
    size_t arg = (size_t)-1, best_n = 0;
    double best_sum = INFINITY;
    size_t k_of = 0;
    for (size_t j = 0; j < c->n; j++) {
        while (c->first[k_of + 1] <= j) k_of++;
        if (allowed && !allowed[j]) continue;
        size_t n = 1; /* its own photo */
        double sum = 0;
        for (size_t k = 0; k < c->photos; k++) {
            if (k == k_of) continue;
            double best = INFINITY;
            for (size_t g = c->first[k]; g < c->first[k + 1]; g++)
                if (!allowed || allowed[g]) best = fmin(best, dist(c->v[j].d, c->v[g].d));
            if (best <= r) n++, sum += best;
        }
        if (arg == (size_t)-1 || n > best_n || (n == best_n && sum < best_sum)) arg = j, best_n = n, best_sum = sum;
    }
    *support = arg == (size_t)-1 ? 0 : best_n;
    return arg;
}

/* The cluster around d: per photo its nearest face when within r (member list, count); then
 * the member with the least summed distance to the others (ties: lower index). */
static size_t medoid_around(const cands *c, const float *d, double r, size_t *members, size_t *count) {
    size_t n = 0;
    for (size_t k = 0; k < c->photos; k++) {
        double e;
        size_t j = nearest_in(c, k, d, &e);
        if (e <= r) members[n++] = j;
    }
    *count = n;
    size_t arg = n ? members[0] : (size_t)-1;
    double best = INFINITY;
    for (size_t a = 0; a < n; a++) {
        double s = 0;
        for (size_t b = 0; b < n; b++) s += dist(c->v[members[a]].d, c->v[members[b]].d);
        if (s < best) best = s, arg = members[a];
    }
    return arg;
}

/* The subject in each judged photo and its status. */
static frig_status apply(frig_ctx *ctx, frig_photoset *set, const cands *c, const float *id, double threshold) {
    for (size_t k = 0; k < c->photos; k++) {
        size_t i = c->photo[k];
        fr_photo *p = &set->photos[i];
        for (size_t f = 0; f < p->face_count; f++)
            p->faces[f].identity_distance = p->faces[f].has_descriptor ? dist(p->faces[f].descriptor, id) : NAN;
        double e;
        size_t j = nearest_in(c, k, id, &e);
        frig_status st = frig_photoset_set_subject(ctx, set, i, (long)c->v[j].face);
        if (st) return st;
        if (e > threshold) {
            char reason[200];
            snprintf(reason, sizeof reason,
                     "the face nearest the subject's identity is %.3f from it, over identity.threshold = %g "
                     "(%zu face%s compared)",
                     e, threshold, c->first[k + 1] - c->first[k], c->first[k + 1] - c->first[k] == 1 ? "" : "s");
            st = frig_photoset_set_status(ctx, set, i, FRIG_PHOTO_OTHER_PERSON, reason);
        } else if (p->status == FRIG_PHOTO_OTHER_PERSON) {
            st = frig_photoset_set_status(ctx, set, i, FRIG_PHOTO_OK, NULL);
        }
        if (st) return st;
    }
    return FRIG_OK;
}

/* The identity: the medoid of the dominant cluster (and in 'mean', when not NULL, the mean of
 * its members), or a sentence when there is none. */
static frig_status find_identity(frig_ctx *ctx, const cands *c, double r, double dominance, size_t *medoid,
                                 size_t *size, float *mean) {
    size_t *members = malloc((c->photos ? c->photos : 1) * sizeof *members);
    unsigned char *other = calloc(c->n ? c->n : 1, 1);
    if (!members || !other) {
        free(members);
        free(other);
        return fr_nomem(ctx, "the identity step");
    }
    size_t support;
    size_t seed = mode(c, NULL, r, &support);
    size_t m = medoid_around(c, c->v[seed].d, r, members, size);
    m = medoid_around(c, c->v[m].d, r, members, size);
    if (mean) {
        double acc[FRIG_DESCRIPTOR_SIZE] = {0};
        for (size_t a = 0; a < *size; a++)
            for (int k = 0; k < FRIG_DESCRIPTOR_SIZE; k++) acc[k] += c->v[members[a]].d[k];
        for (int k = 0; k < FRIG_DESCRIPTOR_SIZE; k++) mean[k] = (float)(acc[k] / (double)(*size ? *size : 1));
    }
    /* The next person: the mode among faces outside the subject's radius. */
    for (size_t j = 0; j < c->n; j++) other[j] = dist(c->v[j].d, c->v[m].d) > r;
    size_t second = 0;
    size_t s2 = mode(c, other, r, &second);
    frig_status st = FRIG_OK;
    if (c->photos > 1 && *size < 2)
        st = fr_error(ctx, FRIG_ERR_TOO_FEW,
                      "no dominant identity: no person's face appears in two of the %zu photos (faces count as one "
                      "person within identity.cluster_radius = %g)",
                      c->photos, r);
    else if (s2 != (size_t)-1 && (double)*size < dominance * (double)second)
        st = fr_error(ctx, FRIG_ERR_TOO_FEW,
                      "no dominant identity: one person appears in %zu photos and another in %zu of the %zu photos "
                      "(identity.min_dominance = %g); remove the other person's photos, or lower identity.min_dominance",
                      *size, second, c->photos, dominance);
    free(members);
    free(other);
    *medoid = m;
    return st;
}

frig_status frig_identify_photoset(frig_ctx *ctx, frig_photoset *set) {
    if (!set) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_identify_photoset: NULL photo set");
    double threshold = fr_param(ctx, FRIG_PARAM_IDENTITY_THRESHOLD);
    double r = fr_param(ctx, FRIG_PARAM_IDENTITY_CLUSTER_RADIUS);
    double dominance = fr_param(ctx, FRIG_PARAM_IDENTITY_MIN_DOMINANCE);
    cands c;
    frig_status st = collect(ctx, set, fr_param(ctx, FRIG_PARAM_DETECT_MIN_EYE_DISTANCE), &c);
    if (!st && c.photos == 0) {
        fr_log(ctx, FRIG_LOG_INFO, "identity: no photo has face descriptors; subjects left as detect chose them");
        cands_free(&c);
        return FRIG_OK;
    }
    size_t m = 0, size = 0;
    float mean[FRIG_DESCRIPTOR_SIZE];
    int use_mean = fr_param_int(ctx, FRIG_PARAM_IDENTITY_PROTOTYPE) == 1;
    if (!st) st = find_identity(ctx, &c, r, dominance, &m, &size, use_mean ? mean : NULL);
    if (!st) {
        memcpy(set->subject_id, use_mean ? mean : c.v[m].d, sizeof set->subject_id);
        set->has_subject_id = 1;
        set->subject_id_threshold = threshold;
        set->subject_id_photos = size;
        set->subject_id_photo = (long)c.v[m].photo;
        set->subject_id_face = (long)c.v[m].face;
        fr_log(ctx, FRIG_LOG_INFO, "identity: %zu of %zu photos in the subject's cluster (medoid: photo %zu face %zu)",
               size, c.photos, c.v[m].photo, c.v[m].face);
        st = apply(ctx, set, &c, set->subject_id, threshold);
    }
    cands_free(&c);
    return st;
}
