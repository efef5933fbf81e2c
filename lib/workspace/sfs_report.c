/* A photo's shape-from-shading results (paper section 5.1) in report.json:
 *   "sfs": {"pixels": 9800, "kept": 7400, "margin": 600 (the cloud's margin's points, when it has one),
 *           "error": 0.031,
 *           "lighting": [[9 R], [9 G], [9 B]], "rotation": [9], "translation": [3],
 *           "expression": {"jawOpen": 0.31, ...}: the weights the cloud was drawn at, by the fit's names, the
 *           non-zero ones; only when sfs refined them}
 * and the set's (the shared solve of the stage's last run):
 *   "sfs": {"shared_solve": "full" or "light", "why": "" / "few_photos" / "many_photos" / "one_light_axis",
 *           "photos": 27 (judged), "light_axis": 0.571 (the lights' concentration along one axis),
 *           "identity": [the fit's identity weights with the shared solve's change: what the clouds were
 *           drawn at; only when the shared solve moved the identity and retarget has not used it yet]}
 * (docs/sfs.md, docs/workspace.md), and the photo set's accessors for them. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "workspace/sfs_report.h"

void fr_photoset_set_sfs(fr_photo *p, int pixels, int kept, double error, const double lighting[27], const double R[9],
                         const double t[3]) {
    p->sfs_done = 1;
    p->sfs_pixels = pixels, p->sfs_kept = kept, p->sfs_margin = 0, p->sfs_error = error;
    memcpy(p->sfs_lighting, lighting, sizeof p->sfs_lighting);
    memcpy(p->sfs_rotation, R, sizeof p->sfs_rotation);
    memcpy(p->sfs_translation, t, sizeof p->sfs_translation);
}

/* *slot becomes a copy of the n weights (NULL, or n <= 0: none). */
static frig_status keep_weights(frig_ctx *ctx, double **slot, const double *weights, int n, const char *what) {
    if (!weights || n <= 0) {
        free(*slot);
        *slot = NULL;
        return FRIG_OK;
    }
    if (!*slot && !(*slot = malloc(sizeof(double) * (size_t)n))) return fr_nomem(ctx, what);
    memcpy(*slot, weights, sizeof(double) * (size_t)n);
    return FRIG_OK;
}

frig_status fr_photoset_set_sfs_expression(frig_ctx *ctx, frig_photoset *set, size_t i, const double *weights) {
    return keep_weights(ctx, &set->photos[i].sfs_expression, weights, set->n_expressions, "a photo's sfs expression");
}

static void numbers(fr_json *j, const char *key, const double *v, int n) {
    fr_json_array(j, key, 1);
    for (int k = 0; k < n; k++) fr_json_number(j, NULL, v[k]);
    fr_json_end(j);
}

void fr_report_write_sfs(fr_json *j, const frig_photoset *set, const fr_photo *p) {
    fr_json_object(j, "sfs");
    fr_json_int(j, "pixels", p->sfs_pixels);
    fr_json_int(j, "kept", p->sfs_kept);
    if (p->sfs_margin > 0) fr_json_int(j, "margin", p->sfs_margin);
    fr_json_number(j, "error", p->sfs_error);
    fr_json_array(j, "lighting", 0);
    for (int c = 0; c < 3; c++) numbers(j, NULL, p->sfs_lighting + 9 * c, 9);
    fr_json_end(j);
    numbers(j, "rotation", p->sfs_rotation, 9);
    numbers(j, "translation", p->sfs_translation, 3);
    if (p->sfs_expression && set->n_expressions > 0) {
        /* as the fit's block writes its weights: by name, the non-zero ones */
        fr_json_object(j, "expression");
        for (int k = 0; k < set->n_expressions; k++)
            if (p->sfs_expression[k] != 0) fr_json_number(j, set->expression_names[k], p->sfs_expression[k]);
        fr_json_end(j);
    }
    fr_json_end(j);
}

int fr_report_read_sfs(frig_ctx *ctx, const cJSON *sfs, frig_photoset *set, size_t i) {
    fr_photo *p = &set->photos[i];
    const cJSON *px = cJSON_GetObjectItemCaseSensitive(sfs, "pixels");
    const cJSON *kept = cJSON_GetObjectItemCaseSensitive(sfs, "kept");
    const cJSON *err = cJSON_GetObjectItemCaseSensitive(sfs, "error");
    const cJSON *light = cJSON_GetObjectItemCaseSensitive(sfs, "lighting");
    double sh[27], R[9], t[3];
    if (!cJSON_IsNumber(px) || !cJSON_IsNumber(kept) || px->valuedouble < 0 || kept->valuedouble < 0 ||
        px->valuedouble > 1e9 || kept->valuedouble > px->valuedouble || !cJSON_IsArray(light) ||
        cJSON_GetArraySize(light) != 3)
        return 0;
    int c = 0;
    for (const cJSON *e = light->child; e; e = e->next, c++)
        if (!fr_report_read_numbers(e, sh + 9 * c, 9)) return 0;
    if (!fr_report_read_numbers(cJSON_GetObjectItemCaseSensitive(sfs, "rotation"), R, 9) ||
        !fr_report_read_numbers(cJSON_GetObjectItemCaseSensitive(sfs, "translation"), t, 3))
        return 0;
    /* a missing error (null: no skin pixel was left) reads back as NaN */
    fr_photoset_set_sfs(p, px->valueint, kept->valueint, cJSON_IsNumber(err) ? err->valuedouble : NAN, sh, R, t);
    const cJSON *margin = cJSON_GetObjectItemCaseSensitive(sfs, "margin"); /* absent: none (older reports too) */
    if (margin && (!cJSON_IsNumber(margin) || margin->valuedouble < 0 || margin->valuedouble > px->valuedouble)) return 0;
    if (margin) p->sfs_margin = margin->valueint;
    /* the refined expression (absent: the fit's; older reports have none) */
    const cJSON *ex = cJSON_GetObjectItemCaseSensitive(sfs, "expression");
    double *w = ex && set->n_expressions > 0 ? calloc((size_t)set->n_expressions, sizeof(double)) : NULL;
    int ok = !ex || (w && cJSON_IsObject(ex));
    for (const cJSON *x = ok && ex ? ex->child : NULL; x && ok; x = x->next) {
        int k = 0;
        while (k < set->n_expressions && strcmp(set->expression_names[k], x->string)) k++;
        if (k == set->n_expressions || !cJSON_IsNumber(x) || x->valuedouble < 0 || x->valuedouble > 1) ok = 0;
        else w[k] = x->valuedouble;
    }
    if (ok && fr_photoset_set_sfs_expression(ctx, set, i, ex ? w : NULL)) ok = 0;
    free(w);
    return ok;
}

static const fr_photo *sfs_photo(const frig_photoset *set, size_t i) {
    return set && i < set->count && set->photos[i].sfs_done ? &set->photos[i] : NULL;
}

int frig_photoset_sfs_done(const frig_photoset *set, size_t i) { return sfs_photo(set, i) != NULL; }

frig_status frig_photoset_sfs_stats(const frig_photoset *set, size_t i, size_t *pixels, size_t *kept, double *error) {
    const fr_photo *p = sfs_photo(set, i);
    if (!p) return FRIG_ERR_STATE;
    if (pixels) *pixels = (size_t)p->sfs_pixels;
    if (kept) *kept = (size_t)p->sfs_kept;
    if (error) *error = p->sfs_error;
    return FRIG_OK;
}

frig_status frig_photoset_sfs_lighting(const frig_photoset *set, size_t i, double sh[27]) {
    const fr_photo *p = sfs_photo(set, i);
    if (!p || !sh) return FRIG_ERR_STATE;
    memcpy(sh, p->sfs_lighting, sizeof p->sfs_lighting);
    return FRIG_OK;
}

frig_status frig_photoset_sfs_pose(const frig_photoset *set, size_t i, double R[9], double t[3]) {
    const fr_photo *p = sfs_photo(set, i);
    if (!p) return FRIG_ERR_STATE;
    if (R) memcpy(R, p->sfs_rotation, sizeof p->sfs_rotation);
    if (t) memcpy(t, p->sfs_translation, sizeof p->sfs_translation);
    return FRIG_OK;
}

frig_status fr_photoset_set_sfs_identity(frig_ctx *ctx, frig_photoset *set, const double *identity) {
    return keep_weights(ctx, &set->sfs_identity, identity, set->n_identity, "the sfs identity");
}

static const char *const why_names[] = {"", "few_photos", "many_photos", "one_light_axis", "outer_loop"};
static const char *const solve_names[] = {"", "full", "light"};

void fr_photoset_set_sfs_solve(frig_photoset *set, int solve, int why, int photos, double light_axis) {
    set->sfs_solve = solve >= FRIG_SFS_SOLVE_FULL && solve <= FRIG_SFS_SOLVE_LIGHT ? solve : FRIG_SFS_SOLVE_NONE;
    set->sfs_why = set->sfs_solve == FRIG_SFS_SOLVE_LIGHT && why > 0 && why <= FR_SFS_WHY_OUTER_LOOP ? why : 0;
    set->sfs_photos = set->sfs_solve ? photos : 0;
    set->sfs_light_axis = set->sfs_solve && isfinite(light_axis) ? light_axis : 0;
}

void fr_report_write_set_sfs(fr_json *j, const frig_photoset *set) {
    if (!set->sfs_solve) return;
    fr_json_object(j, "sfs");
    fr_json_string(j, "shared_solve", solve_names[set->sfs_solve]);
    fr_json_string(j, "why", why_names[set->sfs_why]);
    fr_json_int(j, "photos", set->sfs_photos);
    fr_json_number(j, "light_axis", set->sfs_light_axis);
    if (set->sfs_identity) numbers(j, "identity", set->sfs_identity, set->n_identity);
    fr_json_end(j);
}

static int name_index(const char *name, const char *const *names, int n) {
    for (int k = 0; name && k < n; k++)
        if (!strcmp(name, names[k])) return k;
    return -1;
}

frig_status fr_report_read_set_sfs(frig_ctx *ctx, frig_photoset *set, const cJSON *root) {
    const cJSON *b = cJSON_GetObjectItemCaseSensitive(root, "sfs");
    if (!b) return FRIG_OK;
    const cJSON *photos = cJSON_GetObjectItemCaseSensitive(b, "photos");
    const cJSON *axis = cJSON_GetObjectItemCaseSensitive(b, "light_axis");
    int solve = name_index(cJSON_GetStringValue(cJSON_GetObjectItemCaseSensitive(b, "shared_solve")), solve_names, 3);
    int why = name_index(cJSON_GetStringValue(cJSON_GetObjectItemCaseSensitive(b, "why")), why_names, 5);
    if (!cJSON_IsObject(b) || solve < FRIG_SFS_SOLVE_FULL || why < 0 || (why > 0 && solve != FRIG_SFS_SOLVE_LIGHT) ||
        !cJSON_IsNumber(photos) || !(photos->valuedouble >= 0 && photos->valuedouble <= 1e9) || !cJSON_IsNumber(axis) ||
        !(axis->valuedouble >= 0 && axis->valuedouble <= 1.5))
        return fr_error(ctx, FRIG_ERR_CORRUPT, "report.json: a malformed \"sfs\" block (the shared solve)");
    fr_photoset_set_sfs_solve(set, solve, why, photos->valueint, axis->valuedouble);
    const cJSON *id = cJSON_GetObjectItemCaseSensitive(b, "identity");
    if (!id) return FRIG_OK;
    double *w = malloc(sizeof(double) * (size_t)(set->n_identity > 0 ? set->n_identity : 1));
    if (!w) return fr_nomem(ctx, "the sfs identity");
    frig_status s = FRIG_OK;
    if (set->n_identity <= 0 || !fr_report_read_numbers(id, w, set->n_identity))
        s = fr_error(ctx, FRIG_ERR_CORRUPT, "report.json: the \"sfs\" block's identity is not %d numbers (the fit's)",
                     set->n_identity);
    if (!s) s = fr_photoset_set_sfs_identity(ctx, set, w);
    free(w);
    return s;
}

frig_sfs_solve frig_photoset_sfs_solve(const frig_photoset *set, int *photos, double *light_axis, const char **why) {
    int solve = set ? set->sfs_solve : FRIG_SFS_SOLVE_NONE;
    if (photos) *photos = solve ? set->sfs_photos : 0;
    if (light_axis) *light_axis = solve ? set->sfs_light_axis : 0;
    if (why) *why = solve ? why_names[set->sfs_why] : "";
    return (frig_sfs_solve)solve;
}
