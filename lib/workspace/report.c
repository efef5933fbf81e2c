/* WORKSPACE/report.json: the photo set on disk, one entry per photo with its fate
 * (docs/workspace.md). Written atomically; read back with every value validated. */
#include <stdlib.h>
#include <string.h>

#include <cJSON.h>

#include "core/context.h"
#include "io/file.h"
#include "io/json_writer.h"
#include "workspace/photoset.h"
#include "workspace/sfs_report.h"

#define REPORT_NAME "report.json"
#define REPORT_VERSION 1

static const char *const source_names[] = {"frontal", "profile", "profile_mirrored", "user", "ssd"};

static void write_face(fr_json *j, const fr_face *f) {
    fr_json_object(j, NULL);
    fr_json_array(j, "box", 1);
    for (int k = 0; k < 4; k++) fr_json_number(j, NULL, f->box[k]);
    fr_json_end(j);
    fr_json_number(j, "score", f->score);
    fr_json_string(j, "source", source_names[f->source]);
    if (f->has_landmarks) {
        fr_json_array(j, "landmarks", 1);
        for (int k = 0; k < FRIG_LANDMARK_COUNT; k++) {
            fr_json_array(j, NULL, 1);
            fr_json_number(j, NULL, f->landmarks[2 * k]);
            fr_json_number(j, NULL, f->landmarks[2 * k + 1]);
            fr_json_end(j);
        }
        fr_json_end(j);
    }
    fr_report_write_face_identity(j, f);
    fr_json_end(j);
}

static void write_numbers(fr_json *j, const char *key, const double *v, int n) {
    fr_json_array(j, key, 1);
    for (int k = 0; k < n; k++) fr_json_number(j, NULL, v[k]);
    fr_json_end(j);
}

static void write_fit(fr_json *j, const frig_photoset *set, const fr_photo *p) {
    fr_json_object(j, "fit");
    write_numbers(j, "rotation", p->fit_rotation, 9);
    write_numbers(j, "translation", p->fit_translation, 3);
    fr_json_string(j, "camera", p->fit_perspective ? "perspective" : "weak_perspective");
    fr_json_number(j, p->fit_perspective ? "focal_px" : "scale_px_per_m", p->fit_focal);
    fr_json_number(j, "reprojection_error_px", p->fit_error_px);
    fr_json_bool(j, "joint", p->fit_in_joint);
    /* Expression weights by name; exact zeros (inactive shapes) are left out. */
    fr_json_object(j, "expression");
    for (int k = 0; k < set->n_expressions; k++)
        if (p->fit_expression[k] != 0) fr_json_number(j, set->expression_names[k], p->fit_expression[k]);
    fr_json_end(j);
    fr_json_end(j);
}

static void write_photo(fr_json *j, const frig_photoset *set, const fr_photo *p) {
    fr_json_object(j, NULL);
    fr_json_string(j, "file", p->path);
    fr_json_string(j, "status", frig_photo_status_name(p->status));
    if (p->reason && *p->reason) fr_json_string(j, "reason", p->reason);
    fr_json_int(j, "width", p->width);
    fr_json_int(j, "height", p->height);
    fr_json_int(j, "subject", p->subject);
    fr_json_array(j, "faces", 0);
    for (size_t f = 0; f < p->face_count; f++) write_face(j, &p->faces[f]);
    fr_json_end(j);
    if (p->filtered) {
        fr_json_object(j, "filter");
        fr_json_number(j, "error", p->filter_error);
        fr_json_number(j, "texture_error", p->filter_texture_error);
        fr_json_number(j, "shape_error", p->filter_shape_error);
        fr_json_int(j, "round_dropped", p->filter_round);
        fr_json_end(j);
    }
    if (p->fitted) write_fit(j, set, p);
    fr_retarget_report_write_photo(j, p);
    if (p->sfs_done) fr_report_write_sfs(j, set, p);
    fr_json_end(j);
}

frig_status frig_photoset_save(frig_ctx *ctx, const frig_photoset *set, const char *workspace) {
    if (!set || !workspace) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_photoset_save: NULL argument");
    frig_status s = fr_make_dirs(ctx, workspace);
    if (s) return s;
    char *path = fr_path_join(workspace, REPORT_NAME);
    if (!path) return fr_nomem(ctx, "a path");
    fr_atomic_file af;
    s = fr_atomic_open(ctx, path, &af);
    free(path);
    if (s) return s;
    size_t counts[FR_PHOTO_STATUS_LIMIT] = {0};
    for (size_t i = 0; i < set->count; i++) counts[set->photos[i].status]++;
    fr_json j;
    fr_json_begin(&j, af.fp);
    fr_json_object(&j, NULL);
    fr_json_string(&j, "format", "frig-report");
    fr_json_int(&j, "version", REPORT_VERSION);
    fr_json_string(&j, "frig", FRIG_VERSION_STRING);
    fr_json_object(&j, "summary");
    fr_json_int(&j, "photos", (long long)set->count);
    for (int k = 0; k < FR_PHOTO_STATUS_LIMIT; k++)
        if (counts[k] && frig_photo_status_name((frig_photo_status)k)) fr_json_int(&j, frig_photo_status_name((frig_photo_status)k), (long long)counts[k]);
    fr_json_end(&j);
    if (set->n_identity || set->n_expressions) {
        fr_json_object(&j, "fit");
        write_numbers(&j, "identity", set->identity, set->n_identity);
        fr_json_array(&j, "expressions", 1);
        for (int k = 0; k < set->n_expressions; k++) fr_json_string(&j, NULL, set->expression_names[k]);
        fr_json_end(&j);
        fr_json_end(&j);
    }
    fr_report_write_set_sfs(&j, set);
    fr_retarget_report_write_set(&j, set);
    fr_report_write_set_identity(&j, set);
    fr_json_array(&j, "photos", 0);
    for (size_t i = 0; i < set->count; i++) write_photo(&j, set, &set->photos[i]);
    fr_json_end(&j);
    fr_json_end(&j);
    fr_json_finish(&j);
    return fr_atomic_commit(ctx, &af);
}

/* ---- reading ---- */

typedef struct reader {
    frig_ctx *ctx;
    const char *file;
    size_t photo;
} reader;

static frig_status bad(reader *r, const char *what) {
    return fr_error(r->ctx, FRIG_ERR_CORRUPT, "%s: photo %zu: %s", r->file, r->photo, what);
}

int fr_report_read_numbers(const cJSON *a, double *out, int n) {
    if (!cJSON_IsArray(a) || cJSON_GetArraySize(a) != n) return 0;
    int k = 0;
    for (const cJSON *e = a->child; e; e = e->next, k++) {
        if (!cJSON_IsNumber(e)) return 0;
        out[k] = e->valuedouble;
    }
    return 1;
}

static int lookup_name(const char *s, const char *const *names, int n) {
    for (int k = 0; s && k < n; k++)
        if (strcmp(s, names[k]) == 0) return k;
    return -1;
}

static frig_status read_face(reader *r, frig_photoset *set, const cJSON *jf) {
    double box[4], lm[2 * FRIG_LANDMARK_COUNT];
    if (!fr_report_read_numbers(cJSON_GetObjectItemCaseSensitive(jf, "box"), box, 4)) return bad(r, "a face box is not 4 numbers");
    const cJSON *score = cJSON_GetObjectItemCaseSensitive(jf, "score");
    int source = lookup_name(cJSON_GetStringValue(cJSON_GetObjectItemCaseSensitive(jf, "source")), source_names, 5);
    if (source < 0) return bad(r, "a face has an unknown source");
    const cJSON *jl = cJSON_GetObjectItemCaseSensitive(jf, "landmarks");
    int has = 0;
    if (jl && !cJSON_IsNull(jl)) {
        if (!cJSON_IsArray(jl) || cJSON_GetArraySize(jl) != FRIG_LANDMARK_COUNT)
            return bad(r, "landmarks are not 68 points");
        int k = 0;
        for (const cJSON *e = jl->child; e; e = e->next, k++)
            if (!fr_report_read_numbers(e, lm + 2 * k, 2)) return bad(r, "a landmark is not an [x, y] pair");
        has = 1;
    }
    size_t face = 0;
    frig_status s = frig_photoset_add_face(r->ctx, set, r->photo, box, cJSON_IsNumber(score) ? score->valuedouble : 0,
                                           (frig_face_source)source, has ? lm : NULL, &face);
    char why[256];
    if (!s && fr_report_read_face_identity(&set->photos[r->photo].faces[face], jf, why, sizeof why)) return bad(r, why);
    if (!s) return FRIG_OK;
    snprintf(why, sizeof why, "%s", frig_ctx_errmsg(r->ctx));
    return bad(r, why);
}

static frig_status read_fit(reader *r, frig_photoset *set, size_t idx, const cJSON *fit) {
    double R[9], t[3];
    if (!fr_report_read_numbers(cJSON_GetObjectItemCaseSensitive(fit, "rotation"), R, 9) ||
        !fr_report_read_numbers(cJSON_GetObjectItemCaseSensitive(fit, "translation"), t, 3))
        return bad(r, "\"fit\" lacks rotation or translation");
    const char *cam = cJSON_GetStringValue(cJSON_GetObjectItemCaseSensitive(fit, "camera"));
    int perspective = cam && strcmp(cam, "perspective") == 0;
    if (!perspective && !(cam && strcmp(cam, "weak_perspective") == 0)) return bad(r, "unknown \"camera\"");
    const cJSON *f = cJSON_GetObjectItemCaseSensitive(fit, perspective ? "focal_px" : "scale_px_per_m");
    const cJSON *e = cJSON_GetObjectItemCaseSensitive(fit, "reprojection_error_px");
    if (!cJSON_IsNumber(f) || !cJSON_IsNumber(e)) return bad(r, "\"fit\" lacks its camera value or error");
    double *w = calloc((size_t)set->n_expressions + 1, sizeof(double));
    if (!w) return fr_nomem(r->ctx, "fit results");
    const cJSON *je = cJSON_GetObjectItemCaseSensitive(fit, "expression");
    for (const cJSON *x = cJSON_IsObject(je) ? je->child : NULL; x; x = x->next) {
        int k = 0;
        while (k < set->n_expressions && strcmp(set->expression_names[k], x->string)) k++;
        if (k == set->n_expressions || !cJSON_IsNumber(x) || x->valuedouble < 0 || x->valuedouble > 1) {
            free(w);
            return bad(r, "an expression weight names no fitted expression or is outside [0, 1]");
        }
        w[k] = x->valuedouble;
    }
    frig_status s = fr_photoset_set_fit(r->ctx, set, idx, R, t, f->valuedouble, perspective, w, e->valuedouble,
                                        cJSON_IsTrue(cJSON_GetObjectItemCaseSensitive(fit, "joint")));
    free(w);
    return s;
}

static frig_status read_fit_spaces(frig_ctx *ctx, const char *path, frig_photoset *set, const cJSON *root) {
    const cJSON *fit = cJSON_GetObjectItemCaseSensitive(root, "fit");
    if (!fit) return FRIG_OK;
    const cJSON *id = cJSON_GetObjectItemCaseSensitive(fit, "identity");
    const cJSON *names = cJSON_GetObjectItemCaseSensitive(fit, "expressions");
    if (!cJSON_IsArray(id) || !cJSON_IsArray(names) || cJSON_GetArraySize(id) > 10000 ||
        cJSON_GetArraySize(names) > 10000)
        return fr_error(ctx, FRIG_ERR_CORRUPT, "%s: \"fit\" needs identity and expressions arrays", path);
    int n_id = cJSON_GetArraySize(id), n_exp = cJSON_GetArraySize(names);
    const char **nm = calloc((size_t)n_exp + 1, sizeof(char *));
    if (!nm) return fr_nomem(ctx, "fit results");
    int k = 0;
    for (const cJSON *x = names->child; x; x = x->next, k++)
        if (!(nm[k] = cJSON_GetStringValue(x))) {
            free(nm);
            return fr_error(ctx, FRIG_ERR_CORRUPT, "%s: an expression name is not a string", path);
        }
    frig_status s = fr_photoset_set_fit_spaces(ctx, set, n_id, n_exp, nm);
    free(nm);
    if (s) return s;
    if (!fr_report_read_numbers(id, set->identity, n_id))
        return fr_error(ctx, FRIG_ERR_CORRUPT, "%s: identity weights are not numbers", path);
    return FRIG_OK;
}

static frig_status read_photo(reader *r, frig_photoset *set, const cJSON *jp) {
    const char *file = cJSON_GetStringValue(cJSON_GetObjectItemCaseSensitive(jp, "file"));
    if (!file) return bad(r, "no \"file\"");
    const char *sname = cJSON_GetStringValue(cJSON_GetObjectItemCaseSensitive(jp, "status"));
    int status = -1;
    for (int k = 0; sname && k < FR_PHOTO_STATUS_LIMIT && status < 0; k++)
        if (frig_photo_status_name((frig_photo_status)k) && !strcmp(sname, frig_photo_status_name((frig_photo_status)k)))
            status = k;
    if (status < 0) return bad(r, "unknown \"status\"");
    size_t idx;
    frig_status s = frig_photoset_add(r->ctx, set, file, &idx);
    if (s) return s;
    const char *reason = cJSON_GetStringValue(cJSON_GetObjectItemCaseSensitive(jp, "reason"));
    if ((s = frig_photoset_set_status(r->ctx, set, idx, (frig_photo_status)status, reason))) return s;
    const cJSON *w = cJSON_GetObjectItemCaseSensitive(jp, "width"), *h = cJSON_GetObjectItemCaseSensitive(jp, "height");
    if (cJSON_IsNumber(w) && cJSON_IsNumber(h)) {
        if (w->valuedouble < 0 || h->valuedouble < 0 || w->valuedouble > 1e6 || h->valuedouble > 1e6)
            return bad(r, "impossible width or height");
        frig_photoset_set_size(r->ctx, set, idx, w->valueint, h->valueint);
    }
    const cJSON *faces = cJSON_GetObjectItemCaseSensitive(jp, "faces");
    if (faces && !cJSON_IsArray(faces)) return bad(r, "\"faces\" is not an array");
    for (const cJSON *jf = faces ? faces->child : NULL; jf; jf = jf->next)
        if ((s = read_face(r, set, jf))) return s;
    const cJSON *subj = cJSON_GetObjectItemCaseSensitive(jp, "subject");
    if (cJSON_IsNumber(subj) && frig_photoset_set_subject(r->ctx, set, idx, (long)subj->valuedouble))
        return bad(r, "\"subject\" is not one of its faces");
    const cJSON *flt = cJSON_GetObjectItemCaseSensitive(jp, "filter");
    if (cJSON_IsObject(flt)) {
        const cJSON *e = cJSON_GetObjectItemCaseSensitive(flt, "error");
        const cJSON *te = cJSON_GetObjectItemCaseSensitive(flt, "texture_error");
        const cJSON *se = cJSON_GetObjectItemCaseSensitive(flt, "shape_error");
        const cJSON *rd = cJSON_GetObjectItemCaseSensitive(flt, "round_dropped");
        if (!cJSON_IsNumber(e) || !cJSON_IsNumber(rd)) return bad(r, "\"filter\" lacks error or round_dropped");
        frig_photoset_set_filter(r->ctx, set, idx, e->valuedouble, cJSON_IsNumber(te) ? te->valuedouble : 0,
                                 cJSON_IsNumber(se) ? se->valuedouble : 0, rd->valueint);
    }
    const cJSON *fit = cJSON_GetObjectItemCaseSensitive(jp, "fit");
    if (cJSON_IsObject(fit) && (s = read_fit(r, set, idx, fit))) return s;
    const cJSON *sfs = cJSON_GetObjectItemCaseSensitive(jp, "sfs");
    if (cJSON_IsObject(sfs) && !fr_report_read_sfs(r->ctx, sfs, set, idx)) return bad(r, "\"sfs\" is malformed");
    return fr_retarget_report_read_photo(r->ctx, set, idx, jp);
}

static int is_report(const cJSON *root) {
    const char *f = cJSON_GetStringValue(cJSON_GetObjectItemCaseSensitive(root, "format"));
    return f && strcmp(f, "frig-report") == 0;
}

frig_status frig_photoset_load(frig_ctx *ctx, const char *workspace, frig_photoset **out) {
    if (!out || !workspace) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_photoset_load: NULL argument");
    *out = NULL;
    char *path = fr_path_join(workspace, REPORT_NAME);
    if (!path) return fr_nomem(ctx, "a path");
    unsigned char *data = NULL;
    size_t size = 0;
    frig_status s = fr_read_file(ctx, path, (size_t)1 << 30, &data, &size);
    if (s == FRIG_ERR_NOT_FOUND)
        fr_error(ctx, s, "%s has no %s yet (run frig detect first)", workspace, REPORT_NAME);
    if (s) {
        free(path);
        return s;
    }
    cJSON *root = cJSON_ParseWithLength((const char *)data, size);
    free(data);
    frig_photoset *set = NULL;
    reader r = {ctx, path, 0};
    if (!root) {
        s = fr_error(ctx, FRIG_ERR_CORRUPT, "%s: not valid JSON", path);
    } else if (!cJSON_IsObject(root) ||
               !is_report(root)) {
        s = fr_error(ctx, FRIG_ERR_CORRUPT, "%s: not a frig report", path);
    } else if (!cJSON_IsNumber(cJSON_GetObjectItemCaseSensitive(root, "version")) ||
               cJSON_GetObjectItemCaseSensitive(root, "version")->valueint > REPORT_VERSION) {
        s = fr_error(ctx, FRIG_ERR_UNSUPPORTED, "%s: report version is newer than this libfrig understands", path);
    } else if (!(s = frig_photoset_create(ctx, &set))) {
        const cJSON *photos = cJSON_GetObjectItemCaseSensitive(root, "photos");
        if (!cJSON_IsArray(photos)) s = fr_error(ctx, FRIG_ERR_CORRUPT, "%s: no \"photos\" array", path);
        if (!s) s = read_fit_spaces(ctx, path, set, root);
        for (const cJSON *jp = cJSON_IsArray(photos) ? photos->child : NULL; jp && !s; jp = jp->next, r.photo++)
            s = read_photo(&r, set, jp);
        if (!s) s = fr_report_read_set_sfs(ctx, set, root);
        if (!s) s = fr_retarget_report_read_set(ctx, set, root);
        char why[256];
        if (!s && fr_report_read_set_identity(set, root, why, sizeof why))
            s = fr_error(ctx, FRIG_ERR_CORRUPT, "%s: %s", path, why);
    }
    cJSON_Delete(root);
    free(path);
    if (s) {
        frig_photoset_free(set);
        return s;
    }
    *out = set;
    return FRIG_OK;
}
