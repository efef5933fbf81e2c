/* The stages of frig run, one row each: name, what changes its result (parameter prefixes and
 * options such as input files' contents), what it reads and writes, how to run it. A new stage
 * (identity after detect; sfs and retarget after fit) is a row here and its run function;
 * the runner (cmd_run.c) does the rest: records, resuming, progress, time and memory. */
#include <dirent.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <frig/detect.h>
#include <frig/filter.h>
#include <frig/fit.h>
#include <frig/identity.h>
#include <frig/retarget.h>
#include <frig/sfs.h>

#include "run.h"

/* ---- options: files by content ---- */

static int add_file_hash(cJSON *opts, const char *key, const char *path) {
    run_hash h;
    run_hash_init(&h);
    char hex[17] = "missing";
    if (run_hash_file(&h, path) == 0) run_hex(h.h, hex);
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, "path", path);
    cJSON_AddStringToObject(o, "hash", hex);
    cJSON_AddItemToObject(opts, key, o);
    return CLI_OK;
}

/* ---- frames: videos sampled with ffmpeg ---- */

static int has_videos(run_ctx *r) {
    for (size_t i = 0; i < r->source_count; i++)
        if (r->sources[i].video) return 1;
    return 0;
}

static void video_meta(run_ctx *r, const run_source *s, char *buf, size_t size) {
    run_hash h;
    run_hash_init(&h);
    char hex[17] = "missing";
    if (run_hash_file(&h, s->path) == 0) run_hex(h.h, hex);
    snprintf(buf, size, "{\"video\": \"%s\", \"hash\": \"%s\", \"frames\": %d}\n", s->path, hex,
             (int)frig_ctx_get_param(r->env->ctx, FRIG_PARAM_RUN_VIDEO_FRAMES));
}

static int frames_options(run_ctx *r, cJSON *opts) {
    cJSON *v = cJSON_AddArrayToObject(opts, "videos");
    for (size_t i = 0; i < r->source_count; i++) {
        if (!r->sources[i].video) continue;
        char meta[5000];
        video_meta(r, &r->sources[i], meta, sizeof meta);
        cJSON_AddItemToArray(v, cJSON_CreateString(meta));
    }
    return CLI_OK;
}

static int frames_run(run_ctx *r) {
    char dir[4200];
    run_path(r, "frames", dir, sizeof dir);
    if (cli_make_dir(r->env, dir)) return CLI_FAILED;
    int n = (int)frig_ctx_get_param(r->env->ctx, FRIG_PARAM_RUN_VIDEO_FRAMES), videos = 0, kept = 0;
    for (size_t i = 0; i < r->source_count; i++) {
        run_source *s = &r->sources[i];
        if (!s->video) continue;
        videos++;
        /* a video already taken apart with these options: keep its frames (resume per video) */
        char meta[5000], have_path[4300];
        video_meta(r, s, meta, sizeof meta);
        snprintf(have_path, sizeof have_path, "%s/frames.json", s->frames);
        char *have = run_read_text(have_path, NULL);
        int same = have && strcmp(have, meta) == 0;
        free(have);
        if (same) {
            kept++;
            continue;
        }
        run_progress_stage(r, "sampling %d frames of %s", n, s->path);
        int rc = run_video_frames(r, s, n, meta);
        if (rc) return rc;
    }
    /* frames of videos no longer given */
    DIR *d = opendir(dir);
    for (struct dirent *e; d && (e = readdir(d)) != NULL;) {
        if (e->d_name[0] == '.') continue;
        int ours = 0;
        for (size_t i = 0; i < r->source_count; i++)
            ours |= r->sources[i].video && strcmp(r->sources[i].name, e->d_name) == 0;
        char stale[4500];
        if (!ours && snprintf(stale, sizeof stale, "%s/%s", dir, e->d_name) < (int)sizeof stale) run_remove_tree(stale);
    }
    if (d) closedir(d);
    run_summary(r, "%d video%s, %d frames each%s",
             videos, videos == 1 ? "" : "s", n, kept ? " (some kept from an earlier run)" : "");
    return CLI_OK;
}

/* ---- detect: faces and landmarks, in batches so a rerun resumes at the first photo left ---- */

/* Every photo the run takes, in order: named photos and the videos' frames. */
static int each_photo(run_ctx *r, int (*fn)(run_ctx *r, const char *path, void *user), void *user) {
    for (size_t i = 0; i < r->source_count; i++) {
        const run_source *s = &r->sources[i];
        if (!s->video) {
            int rc = fn(r, s->path, user);
            if (rc) return rc;
            continue;
        }
        char **files;
        size_t n;
        if (run_list_files(s->frames, &files, &n)) return cli_fail_msg("run", "cannot read %s", s->frames);
        int rc = CLI_OK;
        for (size_t k = 0; k < n; k++) {
            if (rc == CLI_OK && cli_is_photo_name(files[k])) rc = fn(r, files[k], user);
            free(files[k]);
        }
        free(files);
        if (rc) return rc;
    }
    return CLI_OK;
}

static int hash_photo(run_ctx *r, const char *path, void *user) {
    (void)r;
    cJSON *list = user;
    run_hash h;
    run_hash_init(&h);
    char hex[17] = "unreadable";
    if (run_hash_file(&h, path) == 0) run_hex(h.h, hex);
    cJSON *o = cJSON_CreateArray();
    cJSON_AddItemToArray(o, cJSON_CreateString(path));
    cJSON_AddItemToArray(o, cJSON_CreateString(hex));
    cJSON_AddItemToArray(list, o);
    return CLI_OK;
}

static int detect_options(run_ctx *r, cJSON *opts) {
    int rc = each_photo(r, hash_photo, cJSON_AddArrayToObject(opts, "photos"));
    if (rc) return rc;
    char path[4200];
    const char *dir = r->cascades ? r->cascades : "/usr/share/opencv4";
    snprintf(path, sizeof path, "%s/haarcascades/haarcascade_frontalface_alt2.xml", dir);
    struct stat st;
    if (stat(path, &st) != 0) snprintf(path, sizeof path, "%s/haarcascade_frontalface_alt2.xml", dir);
    add_file_hash(opts, "frontal_cascade", path);
    add_file_hash(opts, "landmark_model",
                  r->landmark_model ? r->landmark_model : "/usr/share/dlib/shape_predictor_68_face_landmarks.dat");
    /* face-api's networks, when they are used: their files by content */
    const char *models = r->face_models ? r->face_models : getenv("FRIG_FACE_MODELS");
    if (!models) models = "/usr/local/share/frig/face-api/model";
    char **files;
    size_t n;
    if (run_list_files(models, &files, &n) == 0) {
        cJSON *list = cJSON_AddObjectToObject(opts, "face_models");
        for (size_t i = 0; i < n; i++) {
            add_file_hash(list, strrchr(files[i], '/') + 1, files[i]);
            free(files[i]);
        }
        free(files);
    }
    return CLI_OK;
}

static int add_photo(run_ctx *r, const char *path, void *user) {
    return frig_photoset_add(r->env->ctx, user, path, NULL) ? cli_fail(r->env, "run") : CLI_OK;
}

static int fail_or_interrupted(run_ctx *r) {
    return frig_ctx_status(r->env->ctx) == FRIG_ERR_CANCELLED || r->interrupted ? RUN_INTERRUPTED
                                                                                : cli_fail(r->env, "run");
}

static int detect_run(run_ctx *r) {
    cli_env *env = r->env;
    char partial[4200], keyfile[4300];
    run_path(r, "stages/detect/partial", partial, sizeof partial);
    snprintf(keyfile, sizeof keyfile, "%s/key", partial);
    frig_photoset *set = NULL;
    /* an interrupted detect with these options: go on from its first pending photo */
    char *key = run_read_text(keyfile, NULL);
    int resume = key && strcmp(key, r->results[r->stage].key) == 0 && frig_photoset_load(env->ctx, partial, &set) == 0;
    free(key);
    if (!resume) {
        frig_photoset_free(set);
        set = NULL;
        run_remove_tree(partial);
        if (frig_photoset_create(env->ctx, &set)) return cli_fail(env, "run");
        int rc = each_photo(r, add_photo, set);
        if (rc) {
            frig_photoset_free(set);
            return rc;
        }
        if (cli_make_dir(env, partial) || run_write_atomic(keyfile, r->results[r->stage].key, 16)) {
            frig_photoset_free(set);
            return cli_fail_msg("run", "cannot write %s", keyfile);
        }
    }
    size_t n = frig_photoset_count(set), first = 0;
    while (first < n && frig_photoset_status(set, first) != FRIG_PHOTO_PENDING) first++;
    if (resume && first) run_progress_stage(r, "resuming at photo %zu of %zu", first + 1, n);
    frig_detector *det = NULL;
    if (first < n && frig_detector_create_with(env->ctx, r->cascades, r->landmark_model, r->face_models, &det)) {
        frig_photoset_free(set);
        return cli_fail(env, "run");
    }
    int threads = frig_ctx_threads(env->ctx) > 0 ? frig_ctx_threads(env->ctx) : 2;
    size_t batch = (size_t)(8 * threads);
    int rc = CLI_OK;
    for (size_t at = first; at < n && rc == CLI_OK; at += batch) {
        size_t count = at + batch <= n ? batch : n - at;
        run_progress_range(r, at, n);
        if (frig_detect_photoset_range(env->ctx, det, set, at, count)) rc = fail_or_interrupted(r);
        else if (frig_photoset_save(env->ctx, set, partial)) rc = cli_fail(env, "run");
    }
    run_progress_range(r, 0, 0);
    frig_detector_free(det);
    if (rc == CLI_OK && frig_ctx_get_param(env->ctx, FRIG_PARAM_DETECT_DUPLICATES) != 0 &&
        frig_detect_mark_duplicates(env->ctx, set))
        rc = fail_or_interrupted(r);
    if (rc == CLI_OK) rc = run_save_set(r, set);
    if (rc == CLI_OK) {
        char dir[4200];
        run_path(r, "overlays/detect", dir, sizeof dir);
        cli_clear_jpegs(dir);
        if (frig_detect_write_overlays(env->ctx, set, dir)) rc = fail_or_interrupted(r);
    }
    if (rc == CLI_OK) {
        run_remove_tree(partial);
        char dropped[512];
        run_dropped_sentence(set, dropped, sizeof dropped);
        size_t ok = 0;
        for (size_t i = 0; i < n; i++) ok += frig_photoset_status(set, i) == FRIG_PHOTO_OK;
        run_summary(r, "%zu photos, %zu with a usable face%s%s",
                 n, ok, dropped[0] ? "; " : "", dropped);
        rc = run_check_enough(r, set, 0);
    }
    frig_photoset_free(set);
    return rc;
}

/* ---- identity: who is in each photo (face descriptors; docs/identity.md) ---- */

static int identity_run(run_ctx *r) {
    frig_photoset *set = NULL;
    int rc = run_load_set(r, &set);
    if (rc) return rc;
    if (frig_identify_photoset(r->env->ctx, set)) {
        if (frig_ctx_status(r->env->ctx) == FRIG_ERR_TOO_FEW) { /* no dominant person: say so, stop */
            snprintf(r->stop, sizeof r->stop, "%s", frig_ctx_errmsg(r->env->ctx));
            rc = RUN_STOP;
        } else {
            rc = fail_or_interrupted(r);
        }
    }
    if (rc == CLI_OK || rc == RUN_STOP) {
        int save = run_save_set(r, set);
        if (save) rc = save;
    }
    if (rc == CLI_OK) {
        float id[FRIG_DESCRIPTOR_SIZE];
        size_t other = 0;
        for (size_t i = 0; i < frig_photoset_count(set); i++) other += frig_photoset_status(set, i) == FRIG_PHOTO_OTHER_PERSON;
        if (frig_photoset_identity_descriptor(set, id))
            run_summary(r, "%zu photo%s of other people set aside (identity.threshold %g)", other, other == 1 ? "" : "s",
                        frig_ctx_get_param(r->env->ctx, FRIG_PARAM_IDENTITY_THRESHOLD));
        else
            run_summary(r, "no face descriptors (face-api's networks not installed): subjects as detect chose");
        rc = run_check_enough(r, set, 0);
    }
    frig_photoset_free(set);
    return rc;
}

/* ---- filter ---- */

static int filter_run(run_ctx *r) {
    frig_photoset *set = NULL;
    int rc = run_load_set(r, &set);
    if (rc) return rc;
    char sheet[4200];
    run_path(r, "filter_contact_sheet.png", sheet, sizeof sheet);
    if (frig_filter(r->env->ctx, set, sheet)) rc = fail_or_interrupted(r);
    if (rc == CLI_OK) rc = run_save_set(r, set);
    if (rc == CLI_OK) {
        size_t checked = 0, dropped = 0;
        for (size_t i = 0; i < frig_photoset_count(set); i++) {
            int round;
            if (!frig_photoset_filter(set, i, NULL, NULL, NULL, &round)) continue;
            checked++;
            dropped += round > 0;
        }
        run_summary(r, "%zu photos checked, %zu dropped as outliers", checked, dropped);
        rc = run_check_enough(r, set, 0);
    }
    frig_photoset_free(set);
    return rc;
}

/* ---- fit ---- */

static int fit_options(run_ctx *r, cJSON *opts) {
    char path[4096];
    int rc = cli_model_path(r->env, "run", r->model_given, path, sizeof path);
    if (rc) return rc;
    return add_file_hash(opts, "model", path);
}

static int fit_run(run_ctx *r) {
    cli_env *env = r->env;
    int rc = run_load_model(r);
    frig_photoset *set = NULL;
    if (!rc) rc = run_load_set(r, &set);
    if (rc) return rc;
    frig_rig *rig = NULL;
    char path[4200];
    if (frig_fit(env->ctx, r->model, set)) rc = fail_or_interrupted(r);
    if (rc == CLI_OK) rc = run_save_set(r, set);
    const double *identity;
    if (rc == CLI_OK) {
        frig_photoset_identity(set, &identity);
        if (frig_rig_from_model(env->ctx, r->model, identity, &rig)) rc = fail_or_interrupted(r);
        else rc = run_save_rig(r, rig);
    }
    if (rc == CLI_OK) {
        run_path(r, "overlays/fit", path, sizeof path);
        cli_clear_jpegs(path);
        if (frig_fit_write_overlays(env->ctx, r->model, set, path)) rc = fail_or_interrupted(r);
    }
    if (rc == CLI_OK) {
        size_t fitted = 0, joint = 0;
        double sum = 0;
        for (size_t i = 0; i < frig_photoset_count(set); i++) {
            if (!frig_photoset_fitted(set, i) || frig_photoset_status(set, i) != FRIG_PHOTO_OK) continue;
            fitted++;
            joint += frig_photoset_fit_in_joint(set, i);
            sum += frig_photoset_fit_error(set, i);
        }
        run_summary(r, "%zu photos fitted (%zu in the joint identity), mean landmark error %.2f px", fitted, joint,
                 fitted ? sum / (double)fitted : 0.0);
        rc = run_check_enough(r, set, 1);
    }
    frig_rig_free(rig);
    frig_photoset_free(set);
    return rc;
}

/* ---- sfs: per-photo clouds from shading (section 5.1) ----
 * Its clouds and albedo stay in its own folder (OUT/stages/sfs/clouds/, albedo.png): the
 * retarget stage's outer loop recovers them again with each new rig and writes the final ones
 * to OUT/clouds/ and OUT/textures/albedo.png, so neither stage rewrites the other's files. */

/* Most fitted photos without a cloud: their shading does not read as a face's (animals,
 * cartoons, paintings, a set of strangers' photos each fitted alone) or they are too dark or
 * blown out to shape anything: stop, saying how many and why (the report lists each photo's fate). */
static int run_check_clouds(run_ctx *r, const frig_photoset *set, size_t with, size_t judged) {
    double need = frig_ctx_get_param(r->env->ctx, FRIG_PARAM_RUN_MIN_CLOUD_SHARE);
    if (!judged || (double)with >= need * (double)judged) return CLI_OK;
    char dropped[512];
    run_dropped_sentence(set, dropped, sizeof dropped);
    snprintf(r->stop, sizeof r->stop,
             "%zu of %zu fitted photos kept a point cloud, under run.min_cloud_share (%g): most photos' shading does not "
             "read as a face's (%s); add photos of the person, or --set run.min_cloud_share=0 for the fit's "
             "model-space rig",
             with, judged, need, dropped[0] ? dropped : "none dropped");
    return RUN_STOP;
}

static int sfs_run(run_ctx *r) {
    cli_env *env = r->env;
    frig_photoset *set = NULL;
    /* the model's identity modes in the shared solve (sfs.identity_modes) */
    int rc = frig_ctx_get_param(env->ctx, FRIG_PARAM_SFS_IDENTITY_MODES) > 0 ? run_load_model(r) : CLI_OK;
    if (!rc) rc = run_load_set(r, &set);
    if (rc) return rc;
    frig_rig *rig = NULL;
    frig_clouds *clouds = NULL;
    frig_image *albedo = NULL;
    char dir[4200], overlays[4200], path[4300];
    run_path(r, "stages/sfs", dir, sizeof dir);
    run_path(r, "overlays/sfs", overlays, sizeof overlays);
    cli_clear_jpegs(overlays);
    snprintf(path, sizeof path, "%s/albedo.png", dir);
    if (frig_rig_load(env->ctx, r->rig_from, &rig)) rc = cli_fail(env, "run");
    else if (frig_sfs_with_model(env->ctx, r->model, rig, set, overlays, &clouds, &albedo)) {
        if (frig_ctx_status(env->ctx) != FRIG_ERR_TOO_FEW) rc = fail_or_interrupted(r);
        else unlink(path); /* no photo's shading could be read: retarget keeps the fit's rig */
    }
    if (rc == CLI_OK && !clouds) {
        char stale[4300];
        snprintf(stale, sizeof stale, "%s/clouds", dir);
        run_remove_tree(stale);
    }
    if (rc == CLI_OK && clouds && frig_clouds_save(env->ctx, clouds, set, dir)) rc = fail_or_interrupted(r);
    if (rc == CLI_OK && albedo && frig_image_save_png(env->ctx, albedo, path)) rc = fail_or_interrupted(r);
    if (rc == CLI_OK) rc = run_save_set(r, set);
    if (rc == CLI_OK) {
        size_t with = 0, failed = 0, points = 0;
        for (size_t i = 0; i < frig_photoset_count(set); i++) {
            if (!frig_photoset_sfs_done(set, i)) continue;
            failed += frig_photoset_status(set, i) == FRIG_PHOTO_SFS_FAILED;
            with += frig_clouds_count(clouds, i) > 0;
            points += frig_clouds_count(clouds, i);
        }
        char words[160];
        if (clouds)
            run_summary(r, "%zu clouds (%zu points), %zu photo%s sfs_failed; %s", with, points, failed,
                        failed == 1 ? "" : "s", cli_sfs_solve_words(set, words, sizeof words));
        else
            run_summary(r, "no photo's shading could be read (%zu sfs_failed): the rig stays the fit's", failed);
        rc = run_check_clouds(r, set, with, with + failed);
    }
    frig_image_free(albedo);
    frig_clouds_free(clouds);
    frig_rig_free(rig);
    frig_photoset_free(set);
    return rc;
}

/* ---- retarget: the personalized rig, with the outer loop (sections 5.2-5.3) ---- */

/* OUT/textures/albedo.png: the last recovery's albedo, or the sfs stage's when the loop did
 * not recover the clouds again; none when sfs had none. */
static int write_texture(run_ctx *r, const frig_image *albedo) {
    char dir[4200], path[4300], from[4300];
    run_path(r, "textures", dir, sizeof dir);
    snprintf(path, sizeof path, "%s/albedo.png", dir);
    run_path(r, "stages/sfs/albedo.png", from, sizeof from);
    if (cli_make_dir(r->env, dir)) return CLI_FAILED;
    if (albedo) return frig_image_save_png(r->env->ctx, albedo, path) ? fail_or_interrupted(r) : CLI_OK;
    size_t size;
    char *bytes = run_read_text(from, &size);
    int rc = CLI_OK;
    if (!bytes) unlink(path);
    else if (run_write_atomic(path, bytes, size)) rc = cli_fail_msg("run", "cannot write %s: %s", path, strerror(errno));
    free(bytes);
    return rc;
}

/* The library's frig_retarget_recover_sfs, counting its calls for the log line. */
typedef struct recover_count {
    frig_image *albedo; /* the last recovery's albedo, NULL before the first */
    int calls;
} recover_count;

static frig_status recover_counted(void *user, frig_ctx *ctx, const frig_model *model, const frig_rig *rig,
                                   frig_photoset *set, frig_clouds **clouds) {
    recover_count *rec = user;
    rec->calls++;
    return frig_retarget_recover_sfs(&rec->albedo, ctx, model, rig, set, clouds);
}

static int retarget_run(run_ctx *r) {
    cli_env *env = r->env;
    int rc = run_load_model(r);
    frig_photoset *set = NULL;
    if (!rc) rc = run_load_set(r, &set);
    if (rc) return rc;
    frig_rig *rig = NULL, *before = NULL;
    frig_clouds *clouds = NULL;
    recover_count rec = {NULL, 0};
    char sfs_dir[4200], sheet[4200];
    run_path(r, "stages/sfs", sfs_dir, sizeof sfs_dir);
    size_t with = 0;
    if (frig_rig_load(env->ctx, r->rig_from, &rig) || frig_clouds_load(env->ctx, set, sfs_dir, &clouds) ||
        frig_rig_clone(env->ctx, rig, &before))
        rc = cli_fail(env, "run");
    for (size_t i = 0; rc == CLI_OK && i < frig_photoset_count(set); i++) with += frig_clouds_count(clouds, i) > 0;
    if (rc == CLI_OK && with && frig_retarget_refine(env->ctx, r->model, set, &clouds, rig, recover_counted, &rec))
        rc = fail_or_interrupted(r);
    if (rc == CLI_OK && frig_clouds_save(env->ctx, clouds, set, r->out)) rc = fail_or_interrupted(r);
    if (rc == CLI_OK) rc = write_texture(r, rec.albedo);
    if (rc == CLI_OK) rc = run_save_rig(r, rig);
    if (rc == CLI_OK) rc = run_save_set(r, set);
    int personalized = with && frig_photoset_retarget_rounds(set) > 0;
    if (rc == CLI_OK && !personalized) /* no sheet of a rig that is the fit's (nor one left from a run before) */
        remove(run_path(r, "overlays/retarget/rigs.png", sheet, sizeof sheet));
    if (rc == CLI_OK && personalized) {
        const frig_rig *rows[2] = {before, rig};
        const char *labels[2] = {"the fit's rig (the model's span)", "personalized"};
        run_path(r, "overlays/retarget", sheet, sizeof sheet);
        if (cli_make_dir(env, sheet)) rc = CLI_FAILED;
        run_path(r, "overlays/retarget/rigs.png", sheet, sizeof sheet);
        if (rc == CLI_OK && frig_retarget_write_sheet(env->ctx, r->model, rows, labels, 2, sheet)) rc = fail_or_interrupted(r);
    }
    if (rc == CLI_OK && !with) run_summary(r, "no point clouds: the rig is the fit's");
    else if (rc == CLI_OK && !personalized)
        run_summary(r, "%zu photo%s with a point cloud, under retarget.min_clouds (%g): the rig is the fit's", with,
                    with == 1 ? "" : "s", frig_ctx_get_param(env->ctx, FRIG_PARAM_RETARGET_MIN_CLOUDS));
    else if (rc == CLI_OK) {
        int rounds = frig_photoset_retarget_rounds(set), photos = 0; /* > 0: personalized */
        double change = 0, rms = 0;
        frig_photoset_retarget_round(set, rounds - 1, &change, &photos, &rms);
        run_summary(r, "%d round%s (clouds recovered %d times more), %d photos, last round moved the neutral %.3f mm, cloud RMS %.2f mm",
                    rounds, rounds == 1 ? "" : "s", rec.calls, photos, change, rms);
    }
    frig_image_free(rec.albedo);
    frig_clouds_free(clouds);
    frig_rig_free(before);
    frig_rig_free(rig);
    frig_photoset_free(set);
    return rc;
}

/* ---- export: rig.glb and the OBJ folder ---- */

static int export_options(run_ctx *r, cJSON *opts) {
    char path[4200];
    add_file_hash(opts, "rig", r->rig_from);
    run_path(r, "textures/albedo.png", path, sizeof path);
    struct stat st;
    if (stat(path, &st) == 0) add_file_hash(opts, "face_texture", path);
    cJSON_AddStringToObject(opts, "glb", r->rig.glb);
    cJSON_AddStringToObject(opts, "shapes", r->rig.shapes);
    return CLI_OK;
}

static int export_run(run_ctx *r) {
    cli_env *env = r->env;
    char path[4200];
    frig_rig *rig = NULL;
    if (frig_rig_load(env->ctx, r->rig_from, &rig)) return cli_fail(env, "run");
    run_path(r, "textures/albedo.png", path, sizeof path);
    struct stat st;
    int rc = CLI_OK, textured = stat(path, &st) == 0;
    if (textured && frig_rig_set_face_texture(env->ctx, rig, path)) rc = cli_fail(env, "run");
    if (rc == CLI_OK && cli_make_dir(env, r->rig.folder)) rc = CLI_FAILED;
    if (rc == CLI_OK && (frig_rig_save_obj(env->ctx, rig, r->rig.shapes) || frig_rig_save_gltf(env->ctx, rig, r->rig.glb)))
        rc = fail_or_interrupted(r);
    if (rc == CLI_OK)
        run_summary(r, "%s and %s/ (%d shapes)%s",
                 r->rig.glb, r->rig.shapes, frig_rig_target_count(rig), textured ? ", with the face texture" : "");
    frig_rig_free(rig);
    return rc;
}

/* ---- report ---- */

static int report_wanted(run_ctx *r) { return !r->no_report; }

static int report_run(run_ctx *r) { return run_write_report(r); }

/* ---- the table ---- */

const run_stage run_stages[] = {
    {"frames", "frames sampled from the videos with ffmpeg", "run.video_frames", "the video files", "frames",
     "frames", 0, 0, has_videos, frames_options, frames_run},
    {"detect", "faces and 68 landmarks per photo (section 4.2)", "detect. image. run.min_photos", "the photos, OpenCV's cascades, dlib's landmark model",
     "stages/detect/report.json overlays/detect", "stages/detect/report.json", 1, 0, NULL, detect_options, detect_run},
    {"identity", "who is in each photo: the set's dominant person, photos of others set aside", "identity. run.min_photos",
     "report.json (the faces' descriptors)", "stages/identity/report.json", "stages/identity/report.json", 1, 0, NULL, NULL,
     identity_run},
    {"filter", "failed detections dropped by robust PCA (Algorithm 1)", "filter. image.max_pixels run.min_photos", "report.json, the photos",
     "stages/filter/report.json filter_contact_sheet.png", "stages/filter/report.json", 1, 0, NULL, NULL, filter_run},
    {"fit", "camera, pose and expression per photo, one identity (sections 4.3-4.4)", "fit. image. run.min_photos",
     "report.json, the photos, the face model", "stages/fit/report.json stages/fit/rig.frigrig overlays/fit",
     "stages/fit/report.json stages/fit/rig.frigrig", 1, 1, NULL, fit_options, fit_run},
    {"sfs", "a point cloud per photo from its shading, the subject's albedo (section 5.1)", "sfs. image. run.min_cloud_share",
     "report.json, the photos, the fit's rig, the face model (sfs.identity_modes)",
     "stages/sfs/report.json stages/sfs/clouds stages/sfs/albedo.png overlays/sfs",
     "stages/sfs/report.json stages/sfs/clouds stages/sfs/albedo.png", 1, 0, NULL, fit_options, sfs_run},
    {"retarget", "the personalized rig from the clouds, refit and sfs again (sections 5.2-5.3)", "retarget. fit. sfs. image.",
     "report.json, the clouds, the fit's rig, the face model",
     "stages/retarget/report.json stages/retarget/rig.frigrig clouds textures overlays/retarget",
     "stages/retarget/report.json stages/retarget/rig.frigrig textures", 1, 1, NULL, fit_options, retarget_run},
    {"export", "the rig as glTF and OBJ files", "export.", "the rig (the last rig stage's), textures/albedo.png", "@glb @shapes", "@glb",
     0, 0, NULL, export_options, export_run},
    {"report", "report.html: photos, renders, error curves, times", "", "everything above", "report.html report",
     "report.html", 0, 0, report_wanted, NULL, report_run},
};
const int run_stage_count = (int)(sizeof run_stages / sizeof run_stages[0]);
