/* A photo's shape-from-shading results (paper section 5.1) in report.json:
 *   "sfs": {"pixels": 9800, "kept": 7400, "error": 0.031,
 *           "lighting": [[9 R], [9 G], [9 B]], "rotation": [9], "translation": [3]}
 * (docs/sfs.md, docs/workspace.md), and the photo set's accessors for them. */
#include <math.h>
#include <string.h>

#include "core/context.h"
#include "workspace/sfs_report.h"

void fr_photoset_set_sfs(fr_photo *p, int pixels, int kept, double error, const double lighting[27], const double R[9],
                         const double t[3]) {
    p->sfs_done = 1;
    p->sfs_pixels = pixels, p->sfs_kept = kept, p->sfs_error = error;
    memcpy(p->sfs_lighting, lighting, sizeof p->sfs_lighting);
    memcpy(p->sfs_rotation, R, sizeof p->sfs_rotation);
    memcpy(p->sfs_translation, t, sizeof p->sfs_translation);
}

static void numbers(fr_json *j, const char *key, const double *v, int n) {
    fr_json_array(j, key, 1);
    for (int k = 0; k < n; k++) fr_json_number(j, NULL, v[k]);
    fr_json_end(j);
}

void fr_report_write_sfs(fr_json *j, const fr_photo *p) {
    fr_json_object(j, "sfs");
    fr_json_int(j, "pixels", p->sfs_pixels);
    fr_json_int(j, "kept", p->sfs_kept);
    fr_json_number(j, "error", p->sfs_error);
    fr_json_array(j, "lighting", 0);
    for (int c = 0; c < 3; c++) numbers(j, NULL, p->sfs_lighting + 9 * c, 9);
    fr_json_end(j);
    numbers(j, "rotation", p->sfs_rotation, 9);
    numbers(j, "translation", p->sfs_translation, 3);
    fr_json_end(j);
}

int fr_report_read_sfs(const cJSON *sfs, fr_photo *p) {
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
    return 1;
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
