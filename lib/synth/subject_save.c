/* A synthetic subject's truth on disk (paper section 7.2: the true blendshapes E_B is measured
 * against): subject.json (identity, offset figures, per-expression changes, colours) and the
 * true rig through the rig writers, so the same readers load truth and results. */
#include <stdio.h>
#include <stdlib.h>

#include "core/context.h"
#include "io/file.h"
#include "io/json_writer.h"
#include "rig/rig.h"
#include "synth/synth.h"

static void write_subject(fr_json *j, const frig_synth_subject *s) {
    char seed[24];
    snprintf(seed, sizeof seed, "%016llx", (unsigned long long)s->seed);
    fr_json_object(j, NULL);
    fr_json_string(j, "format", "frig-synth-subject 1");
    fr_json_string(j, "seed", seed);
    fr_json_string(j, "rig", "rig/rig.frigrig");
    fr_json_number(j, "identity_scale", s->identity_scale);
    fr_synth_json_numbers(j, "identity", s->identity, s->identity_count);
    fr_json_object(j, "offset");
    fr_json_number(j, "out_of_span_rms_mm", s->offset_rms_mm);
    fr_json_number(j, "raw_rms_mm", s->offset_raw_rms_mm);
    fr_json_number(j, "in_span_share_removed", s->offset_in_span);
    fr_json_int(j, "bumps", s->offset_bumps);
    fr_json_string(j, "region", "face");
    fr_json_end(j);
    fr_json_array(j, "expressions", 0);
    for (int k = 0; k < s->shape_count; k++) {
        fr_json_object(j, NULL);
        fr_json_string(j, "name", frig_rig_shape_name(s->rig, k));
        fr_json_bool(j, "fitting", s->fitting[k]);
        fr_json_number(j, "scale", s->shape_scale[k]);
        fr_json_number(j, "field_rel_rms", s->shape_field_rel[k]);
        fr_json_end(j);
    }
    fr_json_end(j);
    fr_json_object(j, "colours_srgb");
    fr_synth_json_numbers(j, "skin", s->skin_srgb, 3);
    fr_synth_json_numbers(j, "hair", s->hair_srgb, 3);
    fr_synth_json_numbers(j, "iris", s->iris_srgb, 3);
    fr_json_bool(j, "bald", s->bald);
    fr_json_end(j);
    fr_json_end(j);
    fr_json_finish(j);
}

frig_status frig_synth_subject_save(frig_ctx *ctx, const frig_synth_subject *s, const char *dir) {
    if (!s || !dir) return fr_error(ctx, FRIG_ERR_INVALID_ARGUMENT, "frig_synth_subject_save: no subject or folder");
    char *rig_dir = fr_path_join(dir, "rig"), *json = fr_path_join(dir, "subject.json");
    char *rig_file = rig_dir ? fr_path_join(rig_dir, "rig.frigrig") : NULL;
    char *glb = rig_dir ? fr_path_join(rig_dir, "rig.glb") : NULL;
    char *shapes = rig_dir ? fr_path_join(rig_dir, "shapes") : NULL;
    frig_status st = rig_dir && json && rig_file && glb && shapes ? FRIG_OK : fr_nomem(ctx, "file names");
    if (!st) st = fr_make_dirs(ctx, rig_dir);
    if (!st) st = frig_rig_save(ctx, s->rig, rig_file);
    if (!st) st = frig_rig_save_gltf(ctx, s->rig, glb);
    if (!st && fr_param_int(ctx, FRIG_PARAM_SYNTH_RIG_OBJ)) st = frig_rig_save_obj(ctx, s->rig, shapes);
    fr_atomic_file af;
    if (!st) st = fr_atomic_open(ctx, json, &af);
    if (!st) {
        fr_json j;
        fr_json_begin(&j, af.fp);
        write_subject(&j, s);
        st = fr_atomic_commit(ctx, &af);
    }
    free(rig_dir), free(json), free(rig_file), free(glb), free(shapes);
    return st;
}
