/* The filter stage over a photo set (paper section 4.2, Algorithm 1): every usable photo's
 * subject face warped to the common frame and its landmarks aligned; robust-PCA failure
 * detection drops the photos whose face the set's shape and texture models cannot explain
 * (status "outlier", with the error and the round); in photos with several faces the model
 * then re-chooses the subject (the face most consistent with the rest), and if that changed
 * anything the detection runs again on the new subjects. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "filter/contact_sheet.h"
#include "filter/failure_detection.h"
#include "frig/filter.h"
#include "image/image.h"
#include "workspace/photoset.h"

typedef struct entry {
    size_t photo;
    frig_image *image;     /* kept only for photos with several faces */
    double *texture;       /* texels: the subject face's texture */
    double landmarks[FR_FILTER_SHAPE_DIM];
    char *error;           /* a photo that could not be read again */
} entry;

typedef struct stage {
    frig_ctx *ctx;
    frig_photoset *set;
    fr_face_warp *warp;
    int texels;
    int n;
    entry *e;
} stage;

/* JPEG reduction (1, 2, 4, 8) keeping the face at least twice the texture frame. */
static int reduction_for(const double *lm, int frame) {
    double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
    for (int k = 0; k < 68; k++) {
        x0 = fmin(x0, lm[2 * k]), x1 = fmax(x1, lm[2 * k]);
        y0 = fmin(y0, lm[2 * k + 1]), y1 = fmax(y1, lm[2 * k + 1]);
    }
    double face = fmax(x1 - x0, y1 - y0);
    int r = 1;
    while (r < 8 && face / (2 * r) >= 2 * frame) r *= 2;
    return r;
}

static void to_reduced(const double *full, int r, double *out) {
    for (int k = 0; k < FR_FILTER_SHAPE_DIM; k++) out[k] = (full[k] - 0.5 * (r - 1)) / r;
}

/* Read one photo (reduced), make its subject's texture; keep the image if it has several faces. */
static void read_one(stage *st, entry *e) {
    const fr_photo *p = &st->set->photos[e->photo];
    frig_ctx *local = frig_ctx_create();
    if (!local) {
        e->error = strdup("out of memory");
        return;
    }
    frig_ctx_set_param(local, FRIG_PARAM_IMAGE_MAX_PIXELS, fr_param(st->ctx, FRIG_PARAM_IMAGE_MAX_PIXELS));
    int multi = 0;
    for (size_t f = 0; f < p->face_count; f++) multi += p->faces[f].has_landmarks;
    int want = multi > 1 ? 1 : reduction_for(e->landmarks, fr_face_warp_size(st->warp)), got = 1;
    frig_image *img = NULL;
    double lm[FR_FILTER_SHAPE_DIM];
    frig_status s = fr_image_load_reduced(local, p->path, FRIG_LOAD_DEFAULT, want, &img, &got);
    to_reduced(e->landmarks, got, lm);
    if (!s) s = fr_face_texture(local, st->warp, img, lm, e->texture, NULL);
    if (s) e->error = strdup(frig_ctx_errmsg(local));
    if (!s && multi > 1) e->image = img;
    else frig_image_free(img);
    frig_ctx_free(local);
}

static frig_status read_all(stage *st) {
    atomic_size_t done;
    atomic_init(&done, 0);
    int saved = fr_blas_serial_begin();
#pragma omp parallel for schedule(dynamic) num_threads(fr_threads(st->ctx))
    for (int a = 0; a < st->n; a++) {
        if (fr_cancelled(st->ctx)) continue;
        read_one(st, &st->e[a]);
        fr_progress_tick(st->ctx, &done, "filter.read", (size_t)st->n);
    }
    fr_blas_serial_end(saved);
    return fr_check_cancel(st->ctx, "filter.read");
}

/* Photos that can no longer be read are marked and left out of the statistics. */
static frig_status drop_unreadable(stage *st) {
    int kept = 0;
    for (int a = 0; a < st->n; a++) {
        entry *e = &st->e[a];
        if (e->error) {
            frig_status s = frig_photoset_set_status(st->ctx, st->set, e->photo, FRIG_PHOTO_UNREADABLE, e->error);
            free(e->error);
            free(e->texture);
            frig_image_free(e->image);
            if (s) return s;
            continue;
        }
        st->e[kept++] = *e;
    }
    st->n = kept;
    return FRIG_OK;
}

static frig_status detect_failures(stage *st, const fr_filter_options *opt, fr_filter_result *res, int *rounds,
                                   fr_filter_model *model) {
    int n = st->n, P = st->texels;
    double *tex = malloc(sizeof(double) * (size_t)P * n), *lm = malloc(sizeof(double) * 136 * (size_t)n);
    double *aligned = malloc(sizeof(double) * 136 * (size_t)n);
    frig_status s = !tex || !lm || !aligned ? fr_nomem(st->ctx, "the filter's data") : FRIG_OK;
    for (int a = 0; !s && a < n; a++) {
        memcpy(tex + (size_t)P * a, st->e[a].texture, sizeof(double) * (size_t)P);
        memcpy(lm + 136 * (size_t)a, st->e[a].landmarks, sizeof(double) * 136);
    }
    if (!s) s = fr_filter_align_shapes(st->ctx, n, lm, aligned, NULL);
    if (!s) s = fr_failure_detection(st->ctx, n, P, tex, aligned, opt, res, rounds, model);
    free(tex), free(lm), free(aligned);
    return s;
}

/* Re-choose the subject of multi-face photos; returns how many changed. */
static int rechoose_subjects(stage *st, const fr_filter_model *model) {
    int changed = 0;
    for (int a = 0; a < st->n; a++) {
        entry *e = &st->e[a];
        if (!e->image) continue;
        fr_photo *p = &st->set->photos[e->photo];
        /* a subject the identity step chose (by face descriptors) stays */
        if (p->subject >= 0 && !isnan(p->faces[p->subject].identity_distance)) continue;
        int nf = 0;
        size_t index[64];
        double lm[136 * 64];
        for (size_t f = 0; f < p->face_count && nf < 64; f++)
            if (p->faces[f].has_landmarks) {
                memcpy(lm + 136 * (size_t)nf, p->faces[f].landmarks, sizeof(double) * 136);
                index[nf++] = f;
            }
        int best = -1;
        if (fr_filter_choose_face(st->ctx, model, st->warp, e->image, nf, lm, &best, NULL) || best < 0) continue;
        if ((long)index[best] == p->subject) continue;
        frig_ctx_clear_error(st->ctx);
        char why[160];
        snprintf(why, sizeof why, "subject changed from face %ld to face %zu (more consistent with the other photos)",
                 p->subject, index[best]);
        p->subject = (long)index[best];
        memcpy(e->landmarks, p->faces[p->subject].landmarks, sizeof e->landmarks);
        if (fr_face_texture(st->ctx, st->warp, e->image, e->landmarks, e->texture, NULL) == FRIG_OK) {
            frig_photoset_set_status(st->ctx, st->set, e->photo, FRIG_PHOTO_OK, why);
            changed++;
        }
    }
    return changed;
}

static frig_status record(stage *st, const fr_filter_result *res, const fr_filter_options *opt) {
    frig_status s = FRIG_OK;
    for (int a = 0; a < st->n && !s; a++) {
        const fr_filter_result *r = &res[a];
        s = frig_photoset_set_filter(st->ctx, st->set, st->e[a].photo, r->error, r->texture_error, r->shape_error,
                                     r->round_dropped);
        if (!s && r->round_dropped) {
            char why[200];
            snprintf(why, sizeof why,
                     "robust PCA outlier (Algorithm 1), dropped in round %d: error %.3f = %.1f x texture %.3f + %.2f x "
                     "shape %.2f",
                     r->round_dropped, r->error, opt->w_texture, r->texture_error, opt->w_shape, r->shape_error);
            s = frig_photoset_set_status(st->ctx, st->set, st->e[a].photo, FRIG_PHOTO_OUTLIER, why);
        } else if (!s && st->set->photos[st->e[a].photo].status != FRIG_PHOTO_OK) {
            s = frig_photoset_set_status(st->ctx, st->set, st->e[a].photo, FRIG_PHOTO_OK, NULL);
        }
    }
    return s;
}

static frig_status write_sheet(stage *st, const fr_filter_result *res, const char *path) {
    int n = st->n, P = st->texels;
    double *tex = malloc(sizeof(double) * (size_t)P * (n ? n : 1));
    int *round = malloc(sizeof(int) * (size_t)(n ? n : 1));
    double *dist = malloc(sizeof(double) * (size_t)(n ? n : 1));
    frig_image *sheet = NULL;
    frig_status s = !tex || !round || !dist ? fr_nomem(st->ctx, "the contact sheet") : FRIG_OK;
    for (int a = 0; !s && a < n; a++) {
        memcpy(tex + (size_t)P * a, st->e[a].texture, sizeof(double) * (size_t)P);
        round[a] = res[a].round_dropped;
        const fr_face *f = fr_photo_subject(&st->set->photos[st->e[a].photo]);
        dist[a] = f ? f->identity_distance : NAN; /* NaN when the identity step did not judge it */
    }
    int columns = (int)ceil(sqrt((double)n * 1.5));
    if (!s)
        s = fr_contact_sheet(st->ctx, st->warp, n, tex, round, dist, fr_param(st->ctx, FRIG_PARAM_IDENTITY_THRESHOLD),
                             columns < 1 ? 1 : columns, &sheet);
    if (!s) s = frig_image_save_png(st->ctx, sheet, path);
    frig_image_free(sheet);
    free(tex), free(round), free(dist);
    return s;
}

frig_status frig_filter(frig_ctx *ctx, frig_photoset *set, const char *contact_sheet) {
    if (!set) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_filter: no photo set");
    fr_filter_options opt;
    fr_filter_options_from_ctx(ctx, &opt);
    stage st = {ctx, set, NULL, 0, 0, calloc(set->count + 1, sizeof(entry))};
    fr_filter_result *res = calloc(set->count + 1, sizeof *res);
    fr_filter_model model;
    memset(&model, 0, sizeof model);
    frig_status s = !st.e || !res ? fr_nomem(ctx, "the filter") : FRIG_OK;
    if (!s) s = fr_face_warp_create(ctx, fr_param_int(ctx, FRIG_PARAM_FILTER_TEXTURE_SIZE), &st.warp);
    if (!s) st.texels = fr_face_warp_texels(st.warp);
    for (size_t i = 0; !s && i < set->count; i++) {
        /* Photos a previous run dropped are judged again, so that a rerun with other options
         * (or after frig fit) starts from what detect found. */
        frig_photo_status ps = set->photos[i].status;
        int usable = ps == FRIG_PHOTO_OK || ps == FRIG_PHOTO_OUTLIER || ps == FRIG_PHOTO_FIT_FAILED;
        const fr_face *f = usable ? fr_photo_subject(&set->photos[i]) : NULL;
        if (!f) continue;
        entry *e = &st.e[st.n++];
        e->photo = i;
        memcpy(e->landmarks, f->landmarks, sizeof e->landmarks);
        if (!(e->texture = malloc(sizeof(double) * (size_t)st.texels))) s = fr_nomem(ctx, "a face texture");
    }
    if (!s) s = read_all(&st);
    if (!s) s = drop_unreadable(&st);
    if (!s && st.n < 3) {
        fr_log(ctx, FRIG_LOG_WARNING, "filter: only %d usable photo%s, too few to tell outliers; all kept", st.n,
               st.n == 1 ? "" : "s");
    } else if (!s) {
        int rounds = 0;
        s = detect_failures(&st, &opt, res, &rounds, &model);
        if (!s && rechoose_subjects(&st, &model) > 0) {
            fr_filter_model_free(&model);
            s = detect_failures(&st, &opt, res, &rounds, &model);
        }
        if (!s) s = record(&st, res, &opt);
        if (!s && contact_sheet) s = write_sheet(&st, res, contact_sheet);
        fr_log(ctx, FRIG_LOG_INFO, "filter: %d photos, %d rounds", st.n, rounds);
    }
    for (int a = 0; st.e && a < st.n; a++) {
        free(st.e[a].texture);
        frig_image_free(st.e[a].image);
    }
    fr_filter_model_free(&model);
    fr_face_warp_free(st.warp);
    free(st.e);
    free(res);
    return s;
}
