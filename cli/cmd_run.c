/* frig run PHOTOS_OR_FOLDERS_OR_VIDEOS... -o OUT: every stage that exists, in order
 * (run_stages.c), in one workspace folder, resumable. Each stage's key is a hash of its
 * parameters and options (input files' contents included) and of the digest of what the
 * stage before it wrote; its record OUT/stages/NAME/stage.json holds the key, the digest of
 * its outputs and their sizes and times. A stage whose key matches its record and whose
 * outputs are as recorded is not run again; an interrupted stage has no record (it is removed
 * when the stage starts and written when it ends), so a rerun does it again, and detect goes
 * on from its last batch. Every file is written atomically, so a kill or a full disk leaves
 * old files or new ones, never half ones, and the outputs of a resumed run are the bytes of
 * an uninterrupted one. */
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <math.h>
#include <signal.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include "run.h"

const char cmd_run_usage[] =
    "usage: frig run PHOTO|FOLDER|VIDEO... -o OUT|NAME.glb [--model FILE] [--cascades DIR]\n"
    "                [--landmark-model FILE] [--face-models DIR] [--no-report]\n"
    "\n"
    "The whole pipeline: frames from videos, detect, identity, filter, fit, sfs, retarget (with the\n"
    "outer loop: refit, sfs, retarget, retarget.iterations rounds), export, and a report page\n"
    "(docs/run.md). Writes OUT/rig.glb (the personalized rig, textured with OUT/textures/albedo.png),\n"
    "OUT/shapes/*.obj, OUT/clouds/*.ply, OUT/report.html (open it first), OUT/report.json\n"
    "(every photo's fate) and the workspace the stage commands read (frig\n"
    "export -w OUT ...). With -o NAME.glb the rig is NAME.glb and NAME_shapes/, the rest\n"
    "NAME_run/. A folder stands for its photos (or, with none, its videos: .mp4 .mov .mkv .webm,\n"
    "each sampled to run.video_frames evenly spread frames with ffmpeg). Inputs are only read.\n"
    "\n"
    "Run it again after an interruption (Ctrl-C, a kill, a full disk) and it resumes: finished\n"
    "stages are kept and detect goes on from its last batch, giving the same bytes as a run that\n"
    "was never stopped. Run it again with other options (--set NAME=VALUE) and only the stages\n"
    "they change run again. At least run.min_photos usable photos are needed (default 5), and\n"
    "point clouds from at least run.min_cloud_share of the fitted ones (default 0.5).\n"
    "\n"
    "  -o OUT               the run's folder (created; a rerun reuses it)\n"
    "  --model FILE         the face model (default: $FRIG_MODEL or the user data folder)\n"
    "  --cascades DIR, --landmark-model FILE, --face-models DIR   detector data (frig help detect)\n"
    "  --no-report          skip report.html\n"
    "Parameters: run.*, detect.*, identity.*, filter.*, fit.*, sfs.*, retarget.*, export.* (frig help\n"
    "params).\n";

static run_ctx *signalled;

static void on_signal(int sig) {
    (void)sig;
    if (!signalled) return;
    signalled->interrupted = 1;
    frig_ctx_cancel(signalled->env->ctx);
    if (signalled->child_pid > 0) kill((pid_t)signalled->child_pid, SIGTERM);
}

const char *run_path(const run_ctx *r, const char *rel, char *buf, size_t size) {
    if ((size_t)snprintf(buf, size, "%s/%s", r->out, rel) >= size) buf[0] = 0; /* too long: names nothing */
    return buf;
}

int run_load_model(run_ctx *r) {
    if (r->model) return CLI_OK;
    return cli_load_model(r->env, "run", r->model_given, &r->model);
}

int run_load_set(run_ctx *r, frig_photoset **set) {
    *set = NULL;
    if (!r->from[0]) return cli_fail_msg("run", "stage %s has no report to start from", run_stages[r->stage].name);
    return frig_photoset_load(r->env->ctx, r->from, set) ? cli_fail(r->env, "run") : CLI_OK;
}

int run_save_set(run_ctx *r, const frig_photoset *set) {
    char rel[256], dir[4400];
    snprintf(rel, sizeof rel, "stages/%s", run_stages[r->stage].name);
    run_path(r, rel, dir, sizeof dir);
    if (frig_photoset_save(r->env->ctx, set, dir) || frig_photoset_save(r->env->ctx, set, r->out))
        return cli_fail(r->env, "run");
    return CLI_OK;
}

int run_save_rig(run_ctx *r, const frig_rig *rig) {
    char rel[256], path[4400];
    snprintf(rel, sizeof rel, "stages/%s/rig.frigrig", run_stages[r->stage].name);
    if (frig_rig_save(r->env->ctx, rig, run_path(r, rel, path, sizeof path))) return cli_fail(r->env, "run");
    if (cli_make_dir(r->env, run_path(r, "rig", path, sizeof path)) ||
        frig_rig_save(r->env->ctx, rig, run_path(r, "rig/rig.frigrig", path, sizeof path)))
        return cli_fail(r->env, "run");
    return CLI_OK;
}

void run_summary(run_ctx *r, const char *fmt, ...) {
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(r->results[r->stage].summary, sizeof r->results[r->stage].summary, fmt, ap);
    va_end(ap);
}

void run_dropped_sentence(const frig_photoset *set, char *buf, size_t size) {
    size_t counts[32] = {0};
    for (size_t i = 0; i < frig_photoset_count(set); i++) {
        unsigned s = (unsigned)frig_photoset_status(set, i);
        if (s < 32) counts[s]++;
    }
    buf[0] = 0;
    size_t len = 0;
    for (unsigned s = 0; s < 32; s++) {
        const char *name = frig_photo_status_name((frig_photo_status)s);
        if (!counts[s] || s == FRIG_PHOTO_OK || !name) continue;
        len += (size_t)snprintf(buf + len, len < size ? size - len : 0, "%s%zu %s", len ? ", " : "", counts[s], name);
        if (len >= size) break;
    }
}

int run_check_enough(run_ctx *r, const frig_photoset *set, int fitted) {
    size_t n = frig_photoset_count(set), usable = 0;
    for (size_t i = 0; i < n; i++)
        usable += frig_photoset_status(set, i) == FRIG_PHOTO_OK && (!fitted || frig_photoset_fitted(set, i));
    int need = (int)frig_ctx_get_param(r->env->ctx, FRIG_PARAM_RUN_MIN_PHOTOS);
    if ((int)usable >= need) return CLI_OK;
    char dropped[512];
    run_dropped_sentence(set, dropped, sizeof dropped);
    snprintf(r->stop, sizeof r->stop,
             "%zu of %zu photos %s usable after %s, and a rig needs at least %d (run.min_photos): %s%s",
             usable, n, usable == 1 ? "is" : "are", run_stages[r->stage].name, need, dropped[0] ? dropped : "none dropped",
             fitted ? "" : "; add photos of the person, or see the report for each photo's reason");
    return RUN_STOP;
}

/* ---- keys, records ---- */

/* 1 when the parameter's name starts with one of the space-separated prefixes (a prefix not
 * ending in '.' must match the whole name). */
static int param_matches(const char *name, const char *prefixes) {
    for (const char *p = prefixes; *p;) {
        while (*p == ' ') p++;
        size_t n = strcspn(p, " ");
        if (n && strncmp(name, p, n) == 0 && (p[n - 1] == '.' || name[n] == 0)) return 1;
        p += n;
    }
    return 0;
}

static cJSON *stage_options(run_ctx *r, int i, int *rc) {
    const run_stage *st = &run_stages[i];
    cJSON *opts = cJSON_CreateObject();
    cJSON *params = cJSON_AddObjectToObject(opts, "parameters");
    for (size_t k = 0; k < frig_param_count(); k++) {
        frig_param p = frig_param_at(k);
        if (param_matches(frig_param_name(p), st->params))
            cJSON_AddNumberToObject(params, frig_param_name(p), frig_ctx_get_param(r->env->ctx, p));
    }
    *rc = st->options ? st->options(r, opts) : CLI_OK;
    return opts;
}

/* The files an output names: itself, or a folder's files (in name order). */
static const char *resolve(const run_ctx *r, const char *token, char *buf, size_t size) {
    if (strcmp(token, "@glb") == 0) return snprintf(buf, size, "%s", r->rig.glb), buf;
    if (strcmp(token, "@shapes") == 0) return snprintf(buf, size, "%s", r->rig.shapes), buf;
    return run_path(r, token, buf, size);
}

typedef int (*file_fn)(const char *path, void *user);

static int each_output_file(const run_ctx *r, const char *list, file_fn fn, void *user) {
    for (const char *p = list; *p;) {
        while (*p == ' ') p++;
        size_t n = strcspn(p, " ");
        if (!n) break;
        char token[256], path[4200];
        snprintf(token, sizeof token, "%.*s", (int)n, p);
        p += n;
        resolve(r, token, path, sizeof path);
        struct stat st;
        if (stat(path, &st) != 0) continue; /* not written (e.g. no overlays to draw) */
        if (!S_ISDIR(st.st_mode)) {
            if (fn(path, user)) return -1;
            continue;
        }
        char **files;
        size_t count;
        if (run_list_files(path, &files, &count)) return -1;
        int bad = 0;
        for (size_t k = 0; k < count; k++) {
            if (!bad && fn(files[k], user)) bad = 1;
            free(files[k]);
        }
        free(files);
        if (bad) return -1;
    }
    return 0;
}

static int hash_one(const char *path, void *user) {
    run_hash_str(user, strrchr(path, '/') ? strrchr(path, '/') + 1 : path);
    return run_hash_file(user, path);
}

static int record_one(const char *path, void *user) {
    struct stat st;
    if (stat(path, &st) != 0) return -1;
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, "path", path);
    /* as text: cJSON prints numbers to 15 digits when they compare equal within an epsilon,
     * which a nanosecond time is not */
    char size[32], mtime[48];
    snprintf(size, sizeof size, "%lld", (long long)st.st_size);
    snprintf(mtime, sizeof mtime, "%lld.%09ld", (long long)st.st_mtim.tv_sec, (long)st.st_mtim.tv_nsec);
    cJSON_AddStringToObject(o, "size", size);
    cJSON_AddStringToObject(o, "mtime", mtime);
    cJSON_AddItemToArray(user, o);
    return 0;
}

static char *record_path(const run_ctx *r, int i, char *buf, size_t size) {
    snprintf(buf, size, "%s/stages/%s/stage.json", r->out, run_stages[i].name);
    return buf;
}

static void copy_string(const cJSON *o, const char *key, char *dst, size_t size) {
    const char *s = cJSON_GetStringValue(cJSON_GetObjectItemCaseSensitive(o, key));
    snprintf(dst, size, "%s", s ? s : "");
}

/* Do the outputs still match what the record says? (--verbose says which does not) */
static int outputs_unchanged(const run_ctx *r, int i, const cJSON *rec) {
    cJSON *now = cJSON_CreateArray();
    int same = each_output_file(r, run_stages[i].outputs, record_one, now) == 0;
    const cJSON *was = cJSON_GetObjectItemCaseSensitive(rec, "outputs");
    if (same && cJSON_GetArraySize(was) != cJSON_GetArraySize(now)) same = 0;
    for (int k = 0; same && k < cJSON_GetArraySize(now); k++) {
        const cJSON *a = cJSON_GetArrayItem(now, k), *b = cJSON_GetArrayItem(was, k);
        const char *pa = cJSON_GetStringValue(cJSON_GetObjectItemCaseSensitive(a, "path"));
        const char *pb = cJSON_GetStringValue(cJSON_GetObjectItemCaseSensitive(b, "path"));
        char sa[64], sb[64], ma[64], mb[64];
        copy_string(a, "size", sa, sizeof sa), copy_string(b, "size", sb, sizeof sb);
        copy_string(a, "mtime", ma, sizeof ma), copy_string(b, "mtime", mb, sizeof mb);
        same = pa && pb && strcmp(pa, pb) == 0 && strcmp(sa, sb) == 0 && strcmp(ma, mb) == 0 && sa[0] && ma[0];
        if (!same && r->env->verbose) cli_note(r->env, "frig run: %s: %s changed since the stage ran", run_stages[i].name, pa ? pa : "?");
    }
    if (!same && r->env->verbose && cJSON_GetArraySize(was) != cJSON_GetArraySize(now))
        cli_note(r->env, "frig run: %s: %d output files now, %d when the stage ran", run_stages[i].name,
                 cJSON_GetArraySize(now), cJSON_GetArraySize(was));
    cJSON_Delete(now);
    return same;
}

/* Load the stage's record when it is valid for 'key': 1 (results filled), else 0. */
static int up_to_date(run_ctx *r, int i, const char *key) {
    char path[4200];
    char *text = run_read_text(record_path(r, i, path, sizeof path), NULL);
    cJSON *rec = text ? cJSON_Parse(text) : NULL;
    free(text);
    char was[64];
    copy_string(rec, "key", was, sizeof was);
    if (rec && strcmp(was, key) != 0 && r->env->verbose)
        cli_note(r->env, "frig run: %s: its options or input changed since it ran", run_stages[i].name);
    int ok = rec && strcmp(was, key) == 0 && outputs_unchanged(r, i, rec);
    if (ok) {
        run_result *res = &r->results[i];
        copy_string(rec, "digest", res->digest, sizeof res->digest);
        copy_string(rec, "summary", res->summary, sizeof res->summary);
        res->seconds = cJSON_GetNumberValue(cJSON_GetObjectItemCaseSensitive(rec, "seconds"));
        res->cpu_seconds = cJSON_GetNumberValue(cJSON_GetObjectItemCaseSensitive(rec, "cpu_seconds"));
        if (!isfinite(res->cpu_seconds)) res->cpu_seconds = 0; /* a record from before it was kept */
        res->peak_rss_mb = cJSON_GetNumberValue(cJSON_GetObjectItemCaseSensitive(rec, "peak_rss_mb"));
        const char *stop = cJSON_GetStringValue(cJSON_GetObjectItemCaseSensitive(rec, "stop"));
        res->stopped = stop != NULL;
        if (stop) snprintf(r->stop, sizeof r->stop, "%s", stop);
    }
    cJSON_Delete(rec);
    return ok;
}

static int write_record(run_ctx *r, int i, cJSON *opts) {
    run_result *res = &r->results[i];
    run_hash h;
    run_hash_init(&h);
    if (each_output_file(r, run_stages[i].digest, hash_one, &h)) return cli_fail_msg("run", "cannot read %s's outputs", run_stages[i].name);
    run_hex(h.h, res->digest);
    cJSON *rec = cJSON_CreateObject(), *outs = cJSON_CreateArray();
    cJSON_AddStringToObject(rec, "format", "frig-run-stage");
    cJSON_AddNumberToObject(rec, "version", 1);
    cJSON_AddStringToObject(rec, "stage", run_stages[i].name);
    cJSON_AddStringToObject(rec, "frig", frig_version_string());
    cJSON_AddStringToObject(rec, "build", r->build);
    cJSON_AddStringToObject(rec, "key", res->key);
    cJSON_AddStringToObject(rec, "digest", res->digest);
    cJSON_AddStringToObject(rec, "summary", res->summary);
    if (res->stopped) cJSON_AddStringToObject(rec, "stop", r->stop); /* a kept stage stops the run again */
    cJSON_AddNumberToObject(rec, "seconds", res->seconds);
    cJSON_AddNumberToObject(rec, "cpu_seconds", res->cpu_seconds);
    cJSON_AddNumberToObject(rec, "peak_rss_mb", res->peak_rss_mb);
    cJSON_AddNumberToObject(rec, "threads", frig_ctx_threads(r->env->ctx));
    cJSON_AddItemReferenceToObject(rec, "options", opts);
    int bad = each_output_file(r, run_stages[i].outputs, record_one, outs);
    cJSON_AddItemToObject(rec, "outputs", outs);
    char *text = bad ? NULL : cJSON_Print(rec);
    cJSON_Delete(rec);
    char path[4200];
    record_path(r, i, path, sizeof path);
    int rc = text && run_write_atomic(path, text, strlen(text)) == 0 ? CLI_OK
                                                                      : cli_fail_msg("run", "cannot write %s: %s", path, strerror(errno));
    free(text);
    return rc;
}

/* ---- the command ---- */

static void sanitize(const char *path, char *name, size_t size) {
    const char *base = strrchr(path, '/') ? strrchr(path, '/') + 1 : path;
    const char *dot = strrchr(base, '.');
    size_t n = dot && dot != base ? (size_t)(dot - base) : strlen(base), k = 0;
    for (size_t i = 0; i < n && k + 1 < size; i++) {
        char c = base[i];
        name[k++] = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '-' || c == '_' ? c : '_';
    }
    name[k] = 0;
    if (!k) snprintf(name, size, "video");
}

static int make_sources(run_ctx *r, const cli_inputs *in) {
    r->sources = calloc(in->count + 1, sizeof *r->sources);
    if (!r->sources) return cli_fail_msg("run", "out of memory");
    for (size_t i = 0; i < in->count; i++) {
        run_source *s = &r->sources[r->source_count++];
        s->path = in->items[i].path;
        s->video = in->items[i].video;
        if (!s->video) continue;
        char base[200];
        sanitize(s->path, base, sizeof base);
        snprintf(s->name, sizeof s->name, "%s", base);
        for (int k = 2;; k++) { /* two videos with one name: name_2, name_3, ... */
            int taken = 0;
            for (size_t j = 0; j + 1 < r->source_count; j++) taken |= r->sources[j].video && !strcmp(r->sources[j].name, s->name);
            if (!taken) break;
            snprintf(s->name, sizeof s->name, "%s_%d", base, k);
        }
        if ((size_t)snprintf(s->frames, sizeof s->frames, "%s/frames/%s", r->out, s->name) >= sizeof s->frames)
            return cli_usage_error("run", "output path too long");
    }
    return CLI_OK;
}

/* The run's folders: OUT (or NAME_run beside NAME.glb) and where the rig goes. */
static int layout(run_ctx *r, const char *given) {
    /* absolute, so the records do not depend on where the command is run from */
    char out[4096], cwd[PATH_MAX];
    int len = given[0] != '/' && getcwd(cwd, sizeof cwd) ? snprintf(out, sizeof out, "%s/%s", cwd, given)
                                                          : snprintf(out, sizeof out, "%s", given);
    if (len < 0 || (size_t)len >= sizeof out) return cli_usage_error("run", "output path too long");
    int rc = cli_rig_paths_of("run", out, &r->rig);
    if (rc) return rc;
    size_t n = strlen(out);
    if (n > 4 && strcmp(r->rig.glb, out) == 0) snprintf(r->out, sizeof r->out, "%.*s_run", (int)(strrchr(out, '.') - out), out);
    else snprintf(r->out, sizeof r->out, "%s", out);
    while (strlen(r->out) > 1 && r->out[strlen(r->out) - 1] == '/') r->out[strlen(r->out) - 1] = 0;
    return CLI_OK;
}

static void clean_temps(run_ctx *r) {
    static const char *const dirs[] = {"", "rig", "overlays/detect", "overlays/fit", "overlays/sfs", "overlays/retarget",
                                       "report", "report/thumbs", "textures", "clouds", "clouds/margin", "stages/sfs/clouds",
                                       "stages/sfs/clouds/margin", "stages/detect/partial"};
    char path[4200];
    for (size_t i = 0; i < sizeof dirs / sizeof dirs[0]; i++) run_remove_temps(run_path(r, dirs[i], path, sizeof path));
    for (int i = 0; i < run_stage_count; i++) {
        char rel[256];
        snprintf(rel, sizeof rel, "stages/%s", run_stages[i].name);
        run_remove_temps(run_path(r, rel, path, sizeof path));
    }
    run_remove_temps(r->rig.folder);
    run_remove_temps(r->rig.shapes);
}

static int run_stage_at(run_ctx *r, int i, const char *prev_digest, const char *all_keys) {
    const run_stage *st = &run_stages[i];
    run_result *res = &r->results[i];
    r->stage = i;
    int rc;
    cJSON *opts = stage_options(r, i, &rc);
    if (rc) {
        cJSON_Delete(opts);
        return rc;
    }
    char *text = cJSON_PrintUnformatted(opts);
    run_hash h;
    run_hash_init(&h);
    run_hash_str(&h, st->name);
    run_hash_str(&h, r->build);
    run_hash_str(&h, text ? text : "");
    run_hash_str(&h, prev_digest);
    if (!st->digest[0] || strcmp(st->name, "report") == 0) run_hash_str(&h, all_keys);
    free(text);
    run_hex(h.h, res->key);
    if (up_to_date(r, i, res->key)) {
        res->done = 1;
        if (!r->env->quiet) run_progress_stage(r, "up to date: %s", res->summary);
        cJSON_Delete(opts);
        return res->stopped ? RUN_STOP : CLI_OK;
    }
    char path[4200], dir[4200];
    if ((size_t)snprintf(dir, sizeof dir, "%s/stages/%s", r->out, st->name) >= sizeof dir) {
        cJSON_Delete(opts);
        return cli_usage_error("run", "output path too long");
    }
    unlink(record_path(r, i, path, sizeof path)); /* no record while the stage runs */
    if (cli_make_dir(r->env, dir)) {
        cJSON_Delete(opts);
        return CLI_FAILED;
    }
    if (!r->env->quiet) run_progress_stage(r, "%s", st->what);
    run_peak_reset();
    double t = run_now(), cpu = run_cpu_now();
    res->summary[0] = 0;
    rc = st->run(r);
    res->seconds = run_now() - t;
    res->cpu_seconds = run_cpu_now() - cpu;
    res->peak_rss_mb = run_peak_mb();
    run_progress_done(r);
    res->stopped = rc == RUN_STOP;
    if (rc == CLI_OK || rc == RUN_STOP) {
        int wr = write_record(r, i, opts);
        if (wr) rc = wr;
        res->done = res->ran = 1;
        if (!r->env->quiet)
            fprintf(stderr, "frig run: [%d/%d] %-8s %s (%.1f s, %.1f s CPU, %.0f MB)\n", i + 1, run_stage_count, st->name,
                    res->summary, res->seconds, res->cpu_seconds, res->peak_rss_mb);
    }
    cJSON_Delete(opts);
    return rc;
}

int cmd_run(cli_env *env, int argc, char **argv) {
    run_ctx *r = calloc(1, sizeof *r);
    if (!r) return cli_fail_msg("run", "out of memory");
    r->env = env;
    r->t0 = run_now();
    run_build_hash(r->build); /* what it cannot read it leaves out: then only the version tells builds apart */
    const char *out = NULL;
    cli_inputs inputs = {0};
    int rc = CLI_OK;
    for (int i = 0; i < argc && rc == CLI_OK; i++) {
        const char *a = argv[i];
        int has_value = i + 1 < argc;
        if (strcmp(a, "-o") == 0 && has_value) out = argv[++i];
        else if (strcmp(a, "--model") == 0 && has_value) r->model_given = argv[++i];
        else if (strcmp(a, "--cascades") == 0 && has_value) r->cascades = argv[++i];
        else if (strcmp(a, "--landmark-model") == 0 && has_value) r->landmark_model = argv[++i];
        else if (strcmp(a, "--face-models") == 0 && has_value) r->face_models = argv[++i];
        else if (strcmp(a, "--no-report") == 0) r->no_report = 1;
        else if (a[0] == '-' && a[1]) rc = cli_usage_error("run", "unknown or incomplete option '%s' (see frig help run)", a);
        else rc = cli_inputs_add("run", &inputs, a, 1);
    }
    if (rc == CLI_OK && !out) rc = cli_usage_error("run", "no output given (-o FOLDER or -o NAME.glb)");
    if (rc == CLI_OK && inputs.count == 0) rc = cli_usage_error("run", "no photos or videos given");
    if (rc == CLI_OK) rc = layout(r, out);
    if (rc == CLI_OK) rc = make_sources(r, &inputs);
    int videos = 0;
    for (size_t i = 0; rc == CLI_OK && i < r->source_count; i++) videos += r->sources[i].video;
    if (rc == CLI_OK && videos && !run_have_ffmpeg())
        rc = cli_fail_msg("run", "%s is a video, and frig reads videos with ffmpeg, which is not installed "
                                 "(Debian: apt-get install ffmpeg); or extract frames yourself and give their folder",
                          videos == 1 ? "one input" : "some input");
    char stages[4200];
    if (rc == CLI_OK && cli_make_dir(env, run_path(r, "stages", stages, sizeof stages))) rc = CLI_FAILED;
    /* one run at a time in a folder: a second one would race the first's files */
    int lock = -1;
    if (rc == CLI_OK) {
        char path[4200];
        lock = open(run_path(r, "stages/lock", path, sizeof path), O_RDWR | O_CREAT, 0644);
        if (lock < 0) rc = cli_fail_msg("run", "cannot create %s: %s", path, strerror(errno));
        else if (flock(lock, LOCK_EX | LOCK_NB) != 0)
            rc = cli_fail_msg("run", "another frig run is working in %s; wait for it to finish", r->out);
    }
    if (rc == CLI_OK) {
        clean_temps(r);
        run_progress_install(r);
        signalled = r;
        struct sigaction sa;
        memset(&sa, 0, sizeof sa);
        sa.sa_handler = on_signal;
        sigaction(SIGINT, &sa, NULL);
        sigaction(SIGTERM, &sa, NULL);
        sigaction(SIGHUP, &sa, NULL);
        char prev_digest[17] = "", all_keys[16 * 17 + 1] = "";
        int stopped = 0;
        for (int i = 0; i < run_stage_count && rc == CLI_OK; i++) {
            const run_stage *st = &run_stages[i];
            if (st->wanted && !st->wanted(r)) continue;
            if (stopped && strcmp(st->name, "report") != 0) continue;
            rc = run_stage_at(r, i, prev_digest, all_keys);
            if (rc == RUN_STOP) stopped = 1, rc = CLI_OK;
            if (rc) break;
            snprintf(prev_digest, sizeof prev_digest, "%s", r->results[i].digest);
            strncat(all_keys, r->results[i].key, sizeof all_keys - strlen(all_keys) - 1);
            char rel[256];
            snprintf(rel, sizeof rel, "stages/%s", st->name);
            if (st->report) run_path(r, rel, r->from, sizeof r->from);
            if (st->rig) snprintf(r->rig_from, sizeof r->rig_from, "%s/stages/%s/rig.frigrig", r->out, st->name);
        }
        signal(SIGINT, SIG_DFL);
        signal(SIGTERM, SIG_DFL);
        signal(SIGHUP, SIG_DFL);
        signalled = NULL;
        run_progress_done(r);
        char report[4200];
        run_path(r, "report.html", report, sizeof report);
        if (r->interrupted || rc == RUN_INTERRUPTED) {
            fprintf(stderr, "frig run: interrupted during %s; run the same command again to resume\n",
                    run_stages[r->stage].name);
            rc = RUN_INTERRUPTED;
        } else if (rc == CLI_OK && stopped) {
            fprintf(stderr, "frig run: stopped: %s\n", r->stop);
            if (!r->no_report) fprintf(stderr, "report: %s\n", report);
            rc = CLI_FAILED;
        } else if (rc == CLI_OK) {
            printf("rig: %s and %s/\n", r->rig.glb, r->rig.shapes);
            if (!r->no_report) printf("report: %s\n", report);
            if (!env->quiet) fprintf(stderr, "frig run: done in %.1f s\n", run_now() - r->t0);
        }
    }
    if (lock >= 0) close(lock); /* releases the lock */
    frig_model_free(r->model);
    free(r->sources);
    cli_inputs_free(&inputs);
    free(r);
    return rc;
}
