/* frig identify -w WORKSPACE: the identity step again on a detected workspace (frig detect
 * runs it already): the subject's identity from the set's face descriptors, the subject face
 * of each photo, other_person for photos without it. docs/identity.md. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "cli.h"

const char cmd_identify_usage[] =
    "usage: frig identify -w WORKSPACE\n"
    "\n"
    "Find the subject's identity among the faces' descriptors (written by frig detect when\n"
    "face-api's networks are installed): the face with the most photos holding a face within\n"
    "identity.cluster_radius, then the medoid of that cluster. In each photo the subject becomes\n"
    "the face nearest that identity; a photo whose nearest face is farther than\n"
    "identity.threshold gets the status other_person, with the distance in the reason. Photos\n"
    "with status ok or other_person are judged (a rerun with another threshold reconsiders\n"
    "other_person photos). A set in which two people appear about equally often stops with a\n"
    "sentence saying so, changing nothing. frig detect runs this step itself.\n"
    "Parameters: identity.* (frig help params).\n";

int cli_identify(cli_env *env, const char *cmd, frig_photoset *set) {
    if (frig_identify_photoset(env->ctx, set)) return cli_fail(env, cmd);
    float id[FRIG_DESCRIPTOR_SIZE];
    if (!frig_photoset_identity_descriptor(set, id)) {
        cli_note(env, "identity: no face descriptors (face-api's networks were not used); subjects as detect chose");
        return CLI_OK;
    }
    size_t n = frig_photoset_count(set), other = 0, judged = 0;
    for (size_t i = 0; i < n; i++) {
        frig_photo_status s = frig_photoset_status(set, i);
        other += s == FRIG_PHOTO_OTHER_PERSON;
        long subj = frig_photoset_subject(set, i);
        judged += (s == FRIG_PHOTO_OK || s == FRIG_PHOTO_OTHER_PERSON) && subj >= 0 &&
                  !isnan(frig_photoset_face_identity_distance(set, i, (size_t)subj));
    }
    if (!env->quiet)
        printf("identity: %zu photos judged, %zu of other people (identity.threshold %g)\n", judged, other,
               frig_ctx_get_param(env->ctx, FRIG_PARAM_IDENTITY_THRESHOLD));
    return CLI_OK;
}

int cmd_identify(cli_env *env, int argc, char **argv) {
    const char *ws = NULL;
    for (int i = 0; i < argc; i++) {
        if ((!strcmp(argv[i], "-w") || !strcmp(argv[i], "--workspace")) && i + 1 < argc) ws = argv[++i];
        else return cli_usage_error("identify", "unexpected argument '%s' (see frig help identify)", argv[i]);
    }
    if (!ws) return cli_usage_error("identify", "no workspace given (-w DIR)");
    frig_photoset *set = NULL;
    if (frig_photoset_load(env->ctx, ws, &set)) return cli_fail(env, "identify");
    int rc = cli_identify(env, "identify", set);
    if (rc == CLI_OK && frig_photoset_save(env->ctx, set, ws)) rc = cli_fail(env, "identify");
    frig_photoset_free(set);
    return rc;
}
