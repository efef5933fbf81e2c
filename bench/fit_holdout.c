/* Held-out landmark error of the fitted identity, on a workspace after detect and filter:
 * a measure of identity quality that needs no 3D truth, so it works on real photos. The
 * usable photos are split in two (even and odd positions); the identity is fitted on the
 * first half by each scheme, then every photo of the second half is fitted with that
 * identity fixed (pose, camera and expression free) and its landmark RMS is reported. An
 * identity that explains photos it has not seen is closer to the person; one that absorbed
 * the first half's detector errors is not. The mean face (no identity fit) is the baseline.
 * With --truth RIG (a frig synth subject's rig/rig.frigrig) it also prints each identity's
 * neutral-shape error (mm, face region, similarity-aligned), to see whether the held-out
 * error ranks identities as the truth does.
 * Usage: fit_holdout MODEL WORKSPACE [--truth RIG] [--threads T] [--set NAME=VALUE]... */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench_param.h"
#include "core/context.h"
#include "eval/shape_error.h"
#include "fit/photo_consistency.h"
#include "fit/progressive_fit.h"
#include "frig/frig.h"

typedef struct photos {
    int n;
    double *lmk;
    fr_fit_input *in;
    frig_image **crops;
} photos;

static int load_half(frig_ctx *ctx, const frig_photoset *set, int parity, photos *h) {
    size_t count = frig_photoset_count(set);
    h->lmk = calloc(count * 136, sizeof(double));
    h->in = calloc(count, sizeof *h->in);
    h->crops = calloc(count, sizeof *h->crops);
    h->n = 0;
    int usable = 0;
    for (size_t p = 0; p < count; p++) {
        long sub = frig_photoset_subject(set, p);
        if (frig_photoset_status(set, p) != FRIG_PHOTO_OK || sub < 0) continue;
        if (usable++ % 2 != parity) continue;
        double *dst = h->lmk + 136 * (size_t)h->n;
        frig_image *img = NULL;
        if (frig_photoset_face_landmarks(set, p, (size_t)sub, dst) ||
            frig_image_load(ctx, frig_photoset_path(set, p), 0, &img))
            continue;
        fr_fit_input *in = &h->in[h->n];
        in->landmarks = dst;
        in->width = frig_image_width(img);
        in->height = frig_image_height(img);
        if (fr_face_crop(ctx, img, dst, 160, &h->crops[h->n], in->crop_origin, &in->crop_scale)) h->crops[h->n] = NULL;
        in->crop = h->crops[h->n];
        frig_image_free(img);
        h->n++;
    }
    return h->n;
}

static void free_half(photos *h) {
    for (int i = 0; i < h->n; i++) frig_image_free(h->crops[i]);
    free(h->lmk), free(h->in), free(h->crops);
}

/* Landmark RMS (px) of each held-out photo fitted with the identity fixed. */
static void heldout_rms(frig_ctx *ctx, const fr_fit_model *fm, const fr_fit_settings *s, const photos *h,
                        const double *identity, double *rms) {
    fr_fit_options opt; /* as the final fits of Algorithm 2 */
    fr_fit_options_make(s, 0, NULL, s->end, s->end, s->iterations, &opt);
    double *w = calloc((size_t)fm->n_cols, sizeof(double));
    for (int i = 0; i < h->n; i++) {
        memcpy(w, identity, sizeof(double) * (size_t)fm->n_id);
        memset(w + fm->n_id, 0, sizeof(double) * (size_t)fm->n_exp);
        fr_fit_photo p;
        fr_fit_photo_init(fm, &p, h->in[i].landmarks, h->in[i].width, h->in[i].height, s->perspective, w);
        fr_fit_photo_set_contour_weight(&p, s->contour_weight);
        fr_fit_photo_run(ctx, fm, &p, &opt);
        /* In % of the eye distance (between the eye centres, as bench/pipeline_sets.sh), so that
         * photos of every size count alike. */
        rms[i] = 100 * p.rms_px / fmax(fr_fit_eye_distance(h->in[i].landmarks), 1);
    }
    free(w);
}

static int cmp_double(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static const frig_rig *truth_rig;
static const frig_model *the_model;
static const double *the_identity;

static void report(const char *name, const double *rms, int n) {
    double *sorted = malloc(sizeof(double) * (size_t)n), sum = 0;
    memcpy(sorted, rms, sizeof(double) * (size_t)n);
    qsort(sorted, (size_t)n, sizeof(double), cmp_double);
    for (int i = 0; i < n; i++) sum += rms[i];
    printf("  %-40s held-out RMS, %% of eye distance: mean %6.3f  median %6.3f", name, sum / n, sorted[n / 2]);
    if (truth_rig) {
        int nv = frig_model_vertex_count(the_model), nface = 9409;
        int fr = frig_model_region_find(the_model, "face");
        if (fr >= 0) frig_model_region(the_model, fr, NULL, NULL, &nface);
        float *est = malloc(sizeof(float) * 3 * (size_t)nv);
        frig_model_eval(NULL, the_model, the_identity, NULL, est);
        printf("   neutral %.2f mm", fr_aligned_mean_distance(frig_rig_neutral(truth_rig), est, nface) * 1000);
        free(est);
    }
    printf("\n");
    free(sorted);
}

int main(int argc, char **argv) {
    if (argc < 3) {
        fprintf(stderr, "usage: fit_holdout MODEL WORKSPACE [--threads T] [--set NAME=VALUE]...\n");
        return 2;
    }
    frig_ctx *ctx = frig_ctx_create();
    frig_ctx_set_threads(ctx, 2);
    for (int i = 3; i < argc; i++) {
        if (!strcmp(argv[i], "--truth") && i + 1 < argc) {
            frig_rig *rig = NULL;
            if (frig_rig_load(ctx, argv[++i], &rig)) {
                fprintf(stderr, "%s\n", frig_ctx_errmsg(ctx));
                return 1;
            }
            truth_rig = rig;
        } else if (!strcmp(argv[i], "--threads") && i + 1 < argc) {
            frig_ctx_set_threads(ctx, atoi(argv[++i]));
        } else if (!strcmp(argv[i], "--set") && i + 1 < argc) {
            if (bench_set_param(ctx, argv[++i])) return 2;
        } else {
            fprintf(stderr, "unknown option %s\n", argv[i]);
            return 2;
        }
    }
    frig_model *model = NULL;
    frig_photoset *set = NULL;
    if (frig_model_load(ctx, argv[1], &model) || frig_photoset_load(ctx, argv[2], &set)) {
        fprintf(stderr, "%s\n", frig_ctx_errmsg(ctx));
        return 1;
    }
    fr_fit_model fm;
    if (fr_fit_model_build(ctx, model, fr_param_int(ctx, FRIG_PARAM_FIT_IDENTITY_MODES), &fm)) return 1;
    fr_fit_settings st;
    fr_fit_settings_from_ctx(ctx, &st);
    photos train, test;
    load_half(ctx, set, 0, &train);
    load_half(ctx, set, 1, &test);
    printf("%s: identity from %d photos, landmark error of %d others fitted with it fixed\n", argv[2], train.n, test.n);
    if (train.n < 4 || test.n < 1) return 1;
    double *identity = calloc((size_t)fm.n_id, sizeof(double)), *rms = calloc((size_t)test.n, sizeof(double));
    double *W = calloc((size_t)train.n * fm.n_cols, sizeof(double));
    fr_fit_result *res = calloc((size_t)train.n, sizeof *res);
    for (int i = 0; i < train.n; i++) res[i].w = W + (size_t)i * fm.n_cols;
    the_model = model, the_identity = identity;
    heldout_rms(ctx, &fm, &st, &test, identity, rms);
    report("mean face (no identity fit)", rms, test.n);
    static const double priors[] = {0, 0.5, 1};
    for (int scheme = 0; scheme < 3; scheme++) {
        for (int k = 0; k < 3; k++) {
            if (scheme != FR_SCHEME_PROGRESSIVE && k > 0) break;
            st.joint_prior = priors[k];
            if (fr_fit_run(ctx, &fm, &st, (fr_fit_scheme)scheme, train.n, train.in, res, identity)) {
                fprintf(stderr, "%s\n", frig_ctx_errmsg(ctx));
                return 1;
            }
            heldout_rms(ctx, &fm, &st, &test, identity, rms);
            char name[80];
            static const char *names[] = {"individual fits (mean identity)", "naive joint fit", "progressive"};
            if (scheme == FR_SCHEME_PROGRESSIVE)
                snprintf(name, sizeof name, "%s, joint_prior %.1f", names[scheme], priors[k]);
            else
                snprintf(name, sizeof name, "%s", names[scheme]);
            report(name, rms, test.n);
        }
    }
    free(identity), free(rms), free(W), free(res);
    free_half(&train), free_half(&test);
    fr_fit_model_free(&fm);
    frig_photoset_free(set);
    frig_rig_free((frig_rig *)truth_rig);
    frig_model_free(model);
    frig_ctx_free(ctx);
    return 0;
}
