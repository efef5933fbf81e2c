/* Synthetic data sets (paper section 7.2: subjects with known blendshapes, photographed in
 * many poses and expressions): the public one-photo call, and whole folders of subjects,
 * photos, truth files and an index, rendered in parallel with bytes independent of the
 * thread count (each photo has its own seed and its own files). Layout: docs/synth.md. */
#include <math.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "image/image.h"
#include "io/file.h"
#include "io/json_writer.h"
#include "synth/synth.h"

#define STAGE "synth"
#define MAX_SUBJECTS 10000
#define MAX_PHOTOS 100000
enum { STREAM_FAILURES = 0xfa11, STREAM_PHOTOS = 0x9407 };

static void draw_params(frig_ctx *ctx, const frig_synth_subject *s, uint64_t seed, int failure, fr_synth_photo *p) {
    int side = fr_param_int(ctx, FRIG_PARAM_SYNTH_IMAGE_SIZE);
    fr_synth_photo_draw(s, seed, side, side, failure, fr_param(ctx, FRIG_PARAM_SYNTH_MAX_YAW),
                        fr_param(ctx, FRIG_PARAM_SYNTH_FAILURE_RATE), p);
    if (fr_param_int(ctx, FRIG_PARAM_SYNTH_ONE_LIGHT)) fr_synth_photo_one_light(s, p);
    fr_synth_photo_effects(p, fr_param(ctx, FRIG_PARAM_SYNTH_SHADOWS), fr_param(ctx, FRIG_PARAM_SYNTH_SPECULAR));
}

frig_status frig_synth_render(frig_ctx *ctx, const frig_synth_subject *subject, uint64_t photo_seed, int failure,
                              frig_image **image, frig_synth_truth **truth) {
    if (image) *image = NULL;
    if (truth) *truth = NULL;
    if (!subject) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_synth_render: no subject");
    if (failure < FRIG_SYNTH_FAILURE_AUTO || failure > FR_SYNTH_FAILURE_KINDS)
        return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_synth_render: %d is not a failure kind", failure);
    fr_synth_photo p;
    draw_params(ctx, subject, photo_seed, failure, &p);
    return fr_synth_render_photo(ctx, subject, &p, image, truth);
}

/* Exactly round(rate * n) failures at seeded places, their kinds in turn. */
static void failure_plan(uint64_t seed, double rate, int n, int *kind) {
    fr_rng rng;
    fr_rng_seed(&rng, seed);
    int *order = malloc(sizeof *order * (size_t)(n > 0 ? n : 1));
    for (int i = 0; i < n; i++) kind[i] = FRIG_SYNTH_FAILURE_NONE;
    int nf = (int)lround(rate * n), first = (int)fr_rng_below(&rng, FR_SYNTH_FAILURE_KINDS);
    if (!order) { /* still deterministic: the first photos */
        for (int j = 0; j < nf; j++) kind[j] = 1 + (first + j) % FR_SYNTH_FAILURE_KINDS;
        return;
    }
    for (int i = 0; i < n; i++) order[i] = i;
    for (int j = 0; j < nf; j++) {
        int r = j + (int)fr_rng_below(&rng, (uint64_t)(n - j)), tmp = order[j];
        order[j] = order[r], order[r] = tmp;
        kind[order[j]] = 1 + (first + j) % FR_SYNTH_FAILURE_KINDS;
    }
    free(order);
}

typedef struct subject_job {
    const char *dir;
    const frig_synth_subject *s;
    fr_synth_photo *params; /* per photo */
    int photos;
} subject_job;

static frig_status one_photo(frig_ctx *ctx, const subject_job *job, int i) {
    char name[96], base[24];
    snprintf(base, sizeof base, "photo_%03d", i);
    frig_image *img = NULL;
    frig_synth_truth *t = NULL;
    unsigned char *jpg = NULL;
    size_t size = 0;
    char *photo = NULL, *json = NULL, *depth = NULL;
    frig_status st = fr_synth_render_photo(ctx, job->s, &job->params[i], &img, &t);
    if (!st) st = fr_jpeg_encode(ctx, img, t->photo.jpeg_quality, 0, &jpg, &size);
    snprintf(name, sizeof name, "photos/%s.jpg", base);
    if (!st && !(photo = fr_path_join(job->dir, name))) st = fr_nomem(ctx, "a file name");
    if (!st) st = fr_write_file_atomic(ctx, photo, jpg, size);
    snprintf(name, sizeof name, "truth/%s.json", base);
    if (!st && !(json = fr_path_join(job->dir, name))) st = fr_nomem(ctx, "a file name");
    snprintf(name, sizeof name, "truth/%s.depth.f32", base);
    if (!st && !(depth = fr_path_join(job->dir, name))) st = fr_nomem(ctx, "a file name");
    snprintf(name, sizeof name, "../photos/%s.jpg", base);
    if (!st) st = frig_synth_truth_save(ctx, t, name, json, depth);
    free(jpg), free(photo), free(json), free(depth);
    frig_image_free(img);
    frig_synth_truth_free(t);
    return st;
}

static frig_status render_photos(frig_ctx *ctx, const subject_job *job, atomic_size_t *done, size_t total) {
    frig_status *st = calloc((size_t)job->photos + 1, sizeof *st);
    if (!st) return fr_nomem(ctx, "the photo statuses");
#pragma omp parallel for schedule(dynamic) num_threads(fr_threads(ctx))
    for (int i = 0; i < job->photos; i++) {
        if (fr_cancelled(ctx)) {
            st[i] = FRIG_ERR_CANCELLED;
            continue;
        }
        st[i] = one_photo(ctx, job, i);
        fr_progress_tick(ctx, done, STAGE, total);
    }
    frig_status s = FRIG_OK;
    for (int i = 0; i < job->photos && !s; i++) s = st[i];
    free(st);
    if (s == FRIG_ERR_CANCELLED) return fr_check_cancel(ctx, "rendering synthetic photos");
    return s;
}

static void index_subject(fr_json *j, const char *name, const frig_synth_subject *s, const fr_synth_photo *p,
                          int photos) {
    char seed[24], file[128];
    snprintf(seed, sizeof seed, "%016llx", (unsigned long long)s->seed);
    fr_json_object(j, NULL);
    fr_json_string(j, "name", name);
    fr_json_string(j, "seed", seed);
    snprintf(file, sizeof file, "%s/subject.json", name);
    fr_json_string(j, "truth", file);
    snprintf(file, sizeof file, "%s/rig/rig.frigrig", name);
    fr_json_string(j, "rig", file);
    fr_json_number(j, "offset_rms_mm", s->offset_rms_mm);
    fr_json_array(j, "photos", 0);
    for (int i = 0; i < photos; i++) {
        fr_json_object(j, NULL);
        snprintf(file, sizeof file, "%s/photos/photo_%03d.jpg", name, i);
        fr_json_string(j, "photo", file);
        snprintf(file, sizeof file, "%s/truth/photo_%03d.json", name, i);
        fr_json_string(j, "truth", file);
        fr_json_string(j, "failure", frig_synth_failure_name(p[i].failure));
        fr_json_number(j, "yaw_deg", p[i].yaw);
        fr_json_end(j);
    }
    fr_json_end(j);
    fr_json_end(j);
}

static void index_head(frig_ctx *ctx, fr_json *j, uint64_t seed, int subjects, int photos) {
    char buf[24];
    snprintf(buf, sizeof buf, "%016llx", (unsigned long long)seed);
    fr_json_object(j, NULL);
    fr_json_string(j, "format", "frig-synth-index 1");
    fr_json_string(j, "seed", buf);
    fr_json_int(j, "subjects_count", subjects);
    fr_json_int(j, "photos_per_subject", photos);
    fr_json_object(j, "params");
    static const frig_param params[] = {FRIG_PARAM_SYNTH_IMAGE_SIZE, FRIG_PARAM_SYNTH_MAX_YAW,
                                        FRIG_PARAM_SYNTH_OFFSET_MM, FRIG_PARAM_SYNTH_FAILURE_RATE,
                                        FRIG_PARAM_SYNTH_ONE_LIGHT};
    for (size_t k = 0; k < sizeof params / sizeof params[0]; k++)
        fr_json_number(j, frig_param_name(params[k]), fr_param(ctx, params[k]));
    fr_json_end(j);
    fr_json_array(j, "subjects", 0);
}

/* Subject k: its rig and truth, then its photos in parallel, then its index entry. */
static frig_status one_subject(frig_ctx *ctx, const frig_model *model, const char *out_dir, uint64_t seed, int k,
                               int photos, fr_json *index, atomic_size_t *done, size_t total) {
    char name[32];
    snprintf(name, sizeof name, "subject_%02d", k);
    frig_synth_subject *s = NULL;
    subject_job job = {0};
    char *dir = fr_path_join(out_dir, name), *pdir = dir ? fr_path_join(dir, "photos") : NULL,
         *tdir = dir ? fr_path_join(dir, "truth") : NULL;
    int *kind = malloc(sizeof *kind * (size_t)(photos + 1));
    job.params = malloc(sizeof *job.params * (size_t)(photos + 1));
    frig_status st = dir && pdir && tdir && kind && job.params ? FRIG_OK : fr_nomem(ctx, "a synthetic subject's files");
    uint64_t sseed = fr_seed_mix(seed, (uint64_t)k);
    if (!st) st = frig_synth_subject_create(ctx, model, sseed, &s);
    if (!st) st = fr_make_dirs(ctx, pdir);
    if (!st) st = fr_make_dirs(ctx, tdir);
    if (!st) st = frig_synth_subject_save(ctx, s, dir);
    if (!st) {
        failure_plan(fr_seed_mix(sseed, STREAM_FAILURES), fr_param(ctx, FRIG_PARAM_SYNTH_FAILURE_RATE), photos, kind);
        uint64_t pseed = fr_seed_mix(sseed, STREAM_PHOTOS);
        for (int i = 0; i < photos; i++) draw_params(ctx, s, fr_seed_mix(pseed, (uint64_t)i), kind[i], &job.params[i]);
        job.dir = dir, job.s = s, job.photos = photos;
        st = render_photos(ctx, &job, done, total);
    }
    if (!st) index_subject(index, name, s, job.params, photos);
    frig_synth_subject_free(s);
    free(dir), free(pdir), free(tdir), free(kind), free(job.params);
    return st;
}

frig_status frig_synth_dataset(frig_ctx *ctx, const frig_model *model, const char *out_dir, int subjects,
                               int photos, uint64_t seed) {
    if (!model || !out_dir) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_synth_dataset: no model or folder");
    if (subjects < 1 || subjects > MAX_SUBJECTS || photos < 0 || photos > MAX_PHOTOS)
        return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT,
                        "frig_synth_dataset: %d subjects and %d photos each (at most %d and %d)", subjects, photos,
                        MAX_SUBJECTS, MAX_PHOTOS);
    char *index_path = fr_path_join(out_dir, "index.json");
    if (!index_path) return fr_nomem(ctx, "a file name");
    fr_atomic_file af;
    frig_status st = fr_make_dirs(ctx, out_dir);
    if (!st) st = fr_atomic_open(ctx, index_path, &af);
    free(index_path);
    if (st) return st;
    fr_json j;
    fr_json_begin(&j, af.fp);
    index_head(ctx, &j, seed, subjects, photos);
    size_t total = (size_t)subjects * (size_t)photos;
    atomic_size_t done = 0;
    fr_progress(ctx, STAGE, 0, total);
    for (int k = 0; k < subjects && !st; k++) st = one_subject(ctx, model, out_dir, seed, k, photos, &j, &done, total);
    if (st) {
        fr_atomic_abort(&af);
        return st;
    }
    fr_json_end(&j);
    fr_json_end(&j);
    fr_json_finish(&j);
    return fr_atomic_commit(ctx, &af);
}
