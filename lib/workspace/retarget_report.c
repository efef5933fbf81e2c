/* The retarget stage's part of the photo set and of report.json: per photo the last pass's
 * correspondence figures ("retarget": inliers, rms_mm, rigid_deg, rigid_mm), per set the
 * outer loop's rounds ("retarget": {"rounds": [{change_mm, photos, rms_mm}]}; no times: the report
 * is the same bytes on every run). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <cjson/cJSON.h>

#include "core/context.h"
#include "frig/retarget.h"
#include "io/json_writer.h"
#include "workspace/photoset.h"

void fr_retarget_report_write_photo(fr_json *j, const fr_photo *p) {
    if (!p->retargeted) return;
    fr_json_object(j, "retarget");
    fr_json_int(j, "inliers", p->rt_inliers);
    fr_json_number(j, "rms_mm", p->rt_rms_mm);
    fr_json_number(j, "rigid_deg", p->rt_rigid_deg);
    fr_json_number(j, "rigid_mm", p->rt_rigid_mm);
    fr_json_end(j);
}

void fr_retarget_report_write_set(fr_json *j, const frig_photoset *set) {
    if (set->rt_rounds == 0) return;
    fr_json_object(j, "retarget");
    fr_json_array(j, "rounds", 0);
    for (int r = 0; r < set->rt_rounds; r++) {
        const fr_retarget_round *q = &set->rt_round[r];
        fr_json_object(j, NULL);
        fr_json_number(j, "change_mm", q->change_mm);
        fr_json_int(j, "photos", q->photos);
        fr_json_number(j, "rms_mm", q->rms_mm);
        fr_json_end(j);
    }
    fr_json_end(j);
    fr_json_end(j);
}

static int number(const cJSON *o, const char *key, double *v) {
    const cJSON *x = cJSON_GetObjectItemCaseSensitive(o, key);
    if (cJSON_IsNull(x)) {
        *v = NAN;
        return 1;
    }
    if (!cJSON_IsNumber(x)) return 0;
    *v = x->valuedouble;
    return 1;
}

frig_status fr_retarget_report_read_photo(frig_ctx *ctx, frig_photoset *set, size_t photo, const cJSON *jp) {
    const cJSON *rt = cJSON_GetObjectItemCaseSensitive(jp, "retarget");
    if (!rt) return FRIG_OK;
    fr_photo *p = &set->photos[photo];
    double inl;
    if (!cJSON_IsObject(rt) || !number(rt, "inliers", &inl) || !number(rt, "rms_mm", &p->rt_rms_mm) ||
        !number(rt, "rigid_deg", &p->rt_rigid_deg) || !number(rt, "rigid_mm", &p->rt_rigid_mm) || !(inl >= 0))
        return fr_error(ctx, FRIG_ERR_CORRUPT, "report.json: photo %zu: a malformed \"retarget\" entry", photo);
    p->rt_inliers = (int)inl;
    p->retargeted = 1;
    return FRIG_OK;
}

frig_status fr_photoset_add_retarget_round(frig_ctx *ctx, frig_photoset *set, const fr_retarget_round *r) {
    fr_retarget_round *n = realloc(set->rt_round, sizeof *n * ((size_t)set->rt_rounds + 1));
    if (!n) return fr_nomem(ctx, "the retarget rounds");
    set->rt_round = n;
    set->rt_round[set->rt_rounds++] = *r;
    return FRIG_OK;
}

frig_status fr_retarget_report_read_set(frig_ctx *ctx, frig_photoset *set, const cJSON *root) {
    const cJSON *rt = cJSON_GetObjectItemCaseSensitive(root, "retarget");
    if (!rt) return FRIG_OK;
    const cJSON *rounds = cJSON_GetObjectItemCaseSensitive(rt, "rounds");
    if (!cJSON_IsObject(rt) || !cJSON_IsArray(rounds))
        return fr_error(ctx, FRIG_ERR_CORRUPT, "report.json: \"retarget\" has no \"rounds\" array");
    for (const cJSON *q = rounds->child; q; q = q->next) {
        fr_retarget_round r;
        double photos;
        if (!number(q, "change_mm", &r.change_mm) ||
            !number(q, "photos", &photos) || !number(q, "rms_mm", &r.rms_mm))
            return fr_error(ctx, FRIG_ERR_CORRUPT, "report.json: a malformed retarget round");
        r.photos = (int)photos;
        frig_status s = fr_photoset_add_retarget_round(ctx, set, &r);
        if (s) return s;
    }
    return FRIG_OK;
}

int frig_photoset_retargeted(const frig_photoset *set, size_t photo) {
    return set && photo < set->count && set->photos[photo].retargeted;
}

frig_status frig_photoset_retarget_figures(const frig_photoset *set, size_t photo, int *inliers, double *rms_mm,
                                           double *rigid_deg, double *rigid_mm) {
    if (!frig_photoset_retargeted(set, photo)) return FRIG_ERR_STATE;
    const fr_photo *p = &set->photos[photo];
    if (inliers) *inliers = p->rt_inliers;
    if (rms_mm) *rms_mm = p->rt_rms_mm;
    if (rigid_deg) *rigid_deg = p->rt_rigid_deg;
    if (rigid_mm) *rigid_mm = p->rt_rigid_mm;
    return FRIG_OK;
}

int frig_photoset_retarget_rounds(const frig_photoset *set) { return set ? set->rt_rounds : 0; }

frig_status frig_photoset_retarget_round(const frig_photoset *set, int round, double *change_mm, int *photos,
                                         double *rms_mm) {
    if (!set || round < 0 || round >= set->rt_rounds) return FRIG_ERR_INVALID_ARGUMENT;
    const fr_retarget_round *r = &set->rt_round[round];
    if (change_mm) *change_mm = r->change_mm;
    if (photos) *photos = r->photos;
    if (rms_mm) *rms_mm = r->rms_mm;
    return FRIG_OK;
}
